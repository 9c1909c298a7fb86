"""Compiled programs kept between runs, so that a warm ``hullopt run`` neither traces nor compiles.

JAX's persistent compilation cache saves the XLA compile, but every new process still traces and lowers the
Python program (seconds for a solve through the feature-hull model). :func:`cached_call` also keeps the
lowered program: a ``jax.export`` serialization (StableHLO) of the jitted function, keyed by what determines
it — the caller's key (the resolved config), the shapes of the array inputs, the source of this package and
the versions of jax, jaxlib, equinox, optimistix and lineax. Beside it the file keeps
the compiled executable (``jax.experimental.serialize_executable``): a later process loads that and calls it,
with no tracing, lowering or compiling at all (lowering the exported module alone took ~0.5–1 s of a warm
``hullopt hydro``); when the executable cannot be loaded, the exported program is called and its compile
comes from the compilation cache. Array inputs stay arguments (not constants), so the program file is small.

A command whose input is slow to read (a mesh, sliced) can :func:`prepare_call` its program from the shapes
it will have, on a background thread, and read the input meanwhile: a cold ``hullopt hydro`` of a mesh traces
and compiles while the file is parsed and sliced, and a sweep's last programs (assessment, rescoring, the
designs' measures) trace while its chunks' program compiles and compile while it runs (``cached_call(...,
ready=…)``).

A program that evaluates a hull once (the hydrostatic table, a run folder's design, the report's hulls) is
compiled ``quick``: with LLVM's optimisation off (:data:`QUICK`), which halves XLA's compile and adds
milliseconds to its run; a solver's loop, a GZ curve's equilibria or a panel method keep XLA's default. A fit's
solver is quick only in a process that compiles with XLA:CPU's classic emitters (``quick="classic"``: the CLI's
fit runs, :mod:`hullopt.app.cli`), whose code loses little without LLVM's optimisation.

Programs are kept only when the persistent compilation cache is on (the CLI turns it on), in a sibling folder
``programs-<cache folder name>``; a missing, stale or unreadable file is rebuilt, never trusted, and programs
unused for 30 days are deleted when a new one is written.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import logging
import os
import pickle
import re
import threading
import time
from collections.abc import Callable
from concurrent.futures import Future
from importlib import metadata
from pathlib import Path

import equinox as eqx
import jax

from ..geometry import atomic_write_bytes

_PACKAGE = Path(__file__).resolve().parents[1]
QUICK = {"xla_backend_optimization_level": 0}
"""XLA's compile options of a ``quick`` program on the CPU. Measured on 2 cores: the DTC's hydrostatic table
(201 stations, 20 drafts) compiles in 1.6 s instead of 2.8 s and runs in 0.12 s instead of 0.03 s. Not quick:
the demo fit with XLA:CPU's default emitters (its cold run 26 → 20–22 s, but every warm run's solve 0.3 s slower;
with the classic ones it is, see :func:`cached_call`), the GZ curve (its compile 1.1 s shorter, its run 1.0 s
longer; with the classic emitters 1.2–1.6 s shorter and 1.2–2.0 s longer), the KCS sweep's rescoring (47 s
slower). Results agree with the default's to round-off (1e-12)."""
_LIBRARIES = ("jax", "jaxlib", "equinox", "optimistix", "lineax")
# in XLA_FLAGS: the process compiles with XLA:CPU's classic emitters
CLASSIC_EMITTERS_SET = re.compile(r"--xla_cpu_use_fusion_emitters=(false|0)\b")


def programs_dir() -> Path | None:
    """Where programs are kept: beside the persistent compilation cache, or None when that is off."""
    cc = jax.config.jax_compilation_cache_dir
    return Path(cc).parent / f"programs-{Path(cc).name}" if cc else None


@functools.cache
def _code_digest() -> str:
    """Digest of this package's source and data and of the versions of the libraries it traces through."""
    h = hashlib.sha256()
    for path in sorted(p for p in _PACKAGE.rglob("*") if p.is_file() and "__pycache__" not in p.parts):
        h.update(str(path.relative_to(_PACKAGE)).encode())
        h.update(path.read_bytes())
    for lib in _LIBRARIES:
        h.update(f"{lib}={metadata.version(lib)}".encode())
    h.update(f"{jax.config.jax_enable_x64} {jax.config.jax_numpy_dtype_promotion}".encode())
    return h.hexdigest()


def _baked(in_tree, fixed) -> list[str]:
    """What of ``args`` a program has baked in, as text: the static fields of its modules (in the tree's
    structure, object addresses dropped) and its non-array leaves other than functions."""
    scalars = [repr(v) for v in jax.tree.leaves(fixed) if not callable(v)]
    return [re.sub(r" at 0x[0-9a-fA-F]+", "", str(in_tree)), *scalars]


def cached_call(name: str, fn: Callable, args: tuple, static: tuple, key: object, quick: bool | str = False,
                ready: Callable[[], None] | None = None):
    """``jax.jit(fn)(*args, *static)``, through a kept program when there is one (see the module docstring).

    Without a programs folder (:func:`programs_dir`: the persistent compilation cache off) this is a plain
    ``eqx.filter_jit`` call.

    Parameters
    ----------
    name : str
        The program's name, the prefix of its file (``<name>-<digest>.bin``).
    fn : Callable
        The function to jit, called as ``fn(*args, *static)``.
    args : tuple
        A pytree holding the array inputs; its non-array leaves are baked into the program, so they must be
        determined by ``key``.
    static : tuple
        Hashable Python values passed after ``args``.
    key : object
        Any JSON-serialisable value that, with the array shapes and what :func:`_baked` reads off ``args``,
        determines the program: what ``fn`` captures besides its arguments (e.g. the config's structure, its
        solver settings and the parent's digest), not the numbers that enter as arrays.
    quick : bool or "classic"
        Compile for a single short run (:data:`QUICK`, on the CPU): for a program that evaluates a hull once,
        not for a solver's loop (a warm run pays its slower code every time). ``"classic"``: quick where the
        process uses XLA:CPU's classic emitters (``XLA_FLAGS``), whose code runs nearly as fast without LLVM's
        optimisation (the demo fit: compile 10.8 → 6.1 s, run 0.06 → 0.13 s; with the default MLIR emitters
        its run is 0.37 s), so that the compile of a fit's solver, run once by a process, halves.
    ready : callable, optional
        Called once the program no longer needs Python (with kept programs only): once it is traced and
        lowered, before XLA compiles it, or once it is loaded. E.g. to start preparing the next programs
        (:func:`prepare_call`): they trace while this one compiles and compile while it runs, which release
        the GIL.

    Returns
    -------
    object
        What ``fn(*args, *static)`` returns (the same pytree structure), computed by the compiled program.
    """
    if programs_dir() is None:
        return eqx.filter_jit(fn)(*args, *static)
    path, leaves, in_tree, fixed, options = _locate(name, args, static, key, quick)
    pending = _PENDING.pop(path, None)
    program = pending.result() if pending is not None else None
    if program is None:  # not prepared, or preparing it failed: build it here, where an error is raised
        program = _program(path, fn, leaves, in_tree, fixed, static, options, ready)
    elif ready is not None:
        ready()
    compiled, skeleton = program
    return jax.tree.unflatten(jax.tree.structure(skeleton), compiled(*leaves))


def prepare_call(name: str, fn: Callable, args: tuple, static: tuple, key: object, quick: bool | str = False
                 ) -> None:
    """Start loading, or tracing and compiling, the program of a later :func:`cached_call` on a background
    thread, before its inputs are known: ``args`` may hold :class:`jax.ShapeDtypeStruct` leaves where the
    arrays will be (e.g. a mesh's sections while the file is read and sliced; XLA compiles without the GIL).

    The :func:`cached_call` with the same name, key, static values and shapes then waits for this program
    instead of building its own; a call with other shapes builds its own, and the prepared one is wasted work.
    Without a programs folder this does nothing.

    Parameters
    ----------
    name, fn, static, key, quick
        As :func:`cached_call`'s.
    args : tuple
        As :func:`cached_call`'s, with :class:`jax.ShapeDtypeStruct` leaves allowed in place of arrays.

    Returns
    -------
    None
        An error in building the program is raised by the call, not here.
    """
    if programs_dir() is None:
        return
    path, leaves, in_tree, fixed, options = _locate(name, args, static, key, quick)
    if path in _PENDING:
        return
    pending = _PENDING[path] = Future()

    def build():
        try:
            pending.set_result(_program(path, fn, leaves, in_tree, fixed, static, options))
        except BaseException:  # the call builds it again and raises there
            logging.getLogger(__name__).debug("preparing the program %s failed", name, exc_info=True)
            pending.set_result(None)

    threading.Thread(target=build, name=f"prepare-{name}", daemon=True).start()


_PENDING: dict[Path, Future] = {}  # programs being prepared (prepare_call), by their file


def discard_prepared() -> None:
    """Forget the programs :func:`prepare_call` started that no :func:`cached_call` took (a command that
    failed before its call): a long-lived process (the tests, a notebook) would otherwise hold them, their
    executables included. Those still building finish on their threads and are dropped.

    Returns
    -------
    None
    """
    _PENDING.clear()


def _is_input(x) -> bool:
    return eqx.is_array(x) or isinstance(x, jax.ShapeDtypeStruct)


def _locate(name: str, args: tuple, static: tuple, key: object, quick: bool | str) -> tuple:
    """The kept program's file for these inputs, ``args`` split as :func:`_program` takes them, and XLA's
    compile options."""
    dynamic, fixed = eqx.partition(args, _is_input)
    leaves, in_tree = jax.tree.flatten(dynamic)
    # the executable is built for these devices and XLA's flags
    devices = [jax.default_backend(), jax.device_count(), os.environ.get("XLA_FLAGS", "")]
    if quick == "classic":
        quick = CLASSIC_EMITTERS_SET.search(os.environ.get("XLA_FLAGS", "")) is not None
    options = QUICK if quick and jax.default_backend() == "cpu" else {}
    signature = [name, key, [repr(s) for s in static], [(x.shape, str(x.dtype)) for x in leaves], _code_digest(),
                 devices, _baked(in_tree, fixed), options]
    digest = hashlib.sha256(json.dumps(signature, default=str).encode()).hexdigest()[:32]
    return programs_dir() / f"{name}-{digest}.bin", leaves, in_tree, fixed, options


def _program(path: Path, fn: Callable, leaves: list, in_tree, fixed, static: tuple, options: dict,
             ready: Callable[[], None] | None = None) -> tuple:
    """``(compiled, skeleton)``: the kept program at ``path`` loaded, or ``fn`` exported, compiled with XLA's
    ``options`` and kept there (``leaves`` may be :class:`jax.ShapeDtypeStruct`); ``ready()`` called once it is
    loaded, or lowered and not yet compiled."""
    ready = ready or (lambda: None)
    try:
        kept = pickle.loads(path.read_bytes())
        program, skeleton = kept["program"], kept["outputs"]
    except Exception:  # absent, stale or unreadable: build it again
        exported, skeleton = _export(fn, leaves, in_tree, fixed, static)
        targets = sorted(set(re.findall(r"custom_call @(\w+)", exported.mlir_module())))
        lowered = jax.jit(exported.call).lower(*leaves)
        ready()
        # an executable calling out to anything but LAPACK (a host callback holds an address of this process)
        # is not kept; its compile goes through the compilation cache
        keep = all(t.startswith("lapack_") for t in targets)
        compiled, fresh = _compile_fresh(lowered, options) if keep else (lowered.compile(options), False)
        kept = {"program": exported.serialize(), "outputs": skeleton, "targets": targets,
                "executable": _serialize(compiled) if fresh else None}
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            atomic_write_bytes(path, pickle.dumps(kept))
            _prune(path.parent)
        except OSError:
            pass  # a read-only cache: run without keeping the program
        return compiled, skeleton
    with contextlib.suppress(OSError):
        path.touch()  # in use: keep it (see _prune)
    compiled = _deserialize(kept.get("executable"), kept.get("targets", []))
    if compiled is None:  # kept without an executable, or one this jaxlib cannot load: compile (cached)
        compiled = jax.jit(jax.export.deserialize(program).call).lower(*leaves).compile(options)
    ready()
    return compiled, skeleton


def _compile_fresh(lowered, options: dict) -> tuple:
    """``(lowered.compile(options), fresh)``: compiled here, not loaded from the persistent compilation cache, when
    ``fresh`` (XLA:CPU cannot serialize again an executable it loaded from there: the copy lacks its fused
    kernels). The cache is bypassed for this thread only (:func:`_bypassable`: a program prepared on a thread
    compiles beside the main thread's jitted calls, which keep the cache), through jax's private check, which
    the key's jax version pins; where that fails, an ordinary compile (not fresh)."""
    try:
        from jax._src import compilation_cache as cc

        with _BYPASS_LOCK:
            if not hasattr(cc.is_cache_used, "bypassed"):
                cc.is_cache_used = _bypassable(cc.is_cache_used)
    except Exception:
        return lowered.compile(options), False
    _BYPASS.on = True
    try:
        return lowered.compile(options), True
    finally:
        _BYPASS.on = False


_BYPASS = threading.local()  # ``on`` while this thread compiles a program it keeps (:func:`_compile_fresh`)
_BYPASS_LOCK = threading.Lock()


def _bypassable(is_cache_used: Callable) -> Callable:
    """jax's check whether the persistent compilation cache is used, answering no on a thread that bypasses it."""

    @functools.wraps(is_cache_used)
    def check(backend) -> bool:
        return False if getattr(_BYPASS, "on", False) else is_cache_used(backend)

    check.bypassed = True
    return check


def _serialize(compiled) -> tuple | None:
    """A compiled executable as bytes and its argument and result trees; None where the backend cannot
    serialize it."""
    from jax.experimental.serialize_executable import serialize

    try:
        return serialize(compiled)
    except Exception:  # the exported program is enough
        return None


def _deserialize(kept: tuple | None, targets: list[str]):
    """The executable kept by :func:`_serialize`, loaded; None when there is none or it does not load."""
    if kept is None:
        return None
    from jax.experimental.serialize_executable import deserialize_and_load

    try:
        if targets:  # LAPACK's kernels are bound when jax first lowers one; a loaded executable needs them bound
            from jax._src.lib import lapack

            lapack._lapack.initialize()
        # on the one device a jit runs on: by default the executable would expect a shard on every device
        # (with jax_num_cpu_devices = 2, every warm call failed)
        return deserialize_and_load(*kept, execution_devices=jax.devices()[:1])
    except Exception:
        return None


def _prune(folder: Path, days: float = 30.0) -> None:
    """Delete kept programs unused for ``days`` (older code versions and configs leave theirs behind)."""
    cutoff = time.time() - days * 86400.0
    for old in folder.glob("*.bin"):
        with contextlib.suppress(OSError):  # another process may have pruned it already
            if old.stat().st_mtime < cutoff:
                old.unlink()


def _export(fn, leaves, in_tree, fixed, static):
    """The ``jax.export`` of ``fn`` on flat array inputs, and the skeleton of its outputs (their pytree with
    the leaves numbered)."""
    out_tree = []

    def flat(*xs):
        out = fn(*eqx.combine(jax.tree.unflatten(in_tree, xs), fixed), *static)
        ys, tree = jax.tree.flatten(out)
        out_tree.append(tree)
        return ys

    checks = []
    for _ in range(2):
        try:
            exported = jax.export.export(jax.jit(flat), disabled_checks=checks)(*leaves)
            break
        except ValueError as e:
            # LAPACK kernels (QR, LU) have no cross-version guarantee; the key pins the jaxlib version
            targets = set(re.findall(r"custom_call @(\w+)", str(e)))
            if not targets or checks:
                raise
            checks = [jax.export.DisabledSafetyCheck.custom_call(t) for t in sorted(targets)]
    skeleton = jax.tree.unflatten(out_tree[-1], range(out_tree[-1].num_leaves))
    return exported, skeleton
