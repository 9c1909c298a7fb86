"""Entry point of the ``hullopt`` command: global JAX set-up, the commands, and one-line errors."""

from __future__ import annotations

import os
import re
import socket
import sys
import tomllib
import warnings
from pathlib import Path

# XLA logs a false alarm about CPU features each time it loads a cached executable; keep the terminal for
# the user (set TF_CPP_MIN_LOG_LEVEL yourself to see XLA's logs). It must be set before jax is imported.
os.environ.setdefault("TF_CPP_MIN_LOG_LEVEL", "3")

from ..errors import HullError, HullWarning  # noqa: E402

# XLA:CPU emits its fused kernels one of two ways, for a whole process. Its MLIR emitters (the default) vectorise
# better: the large vmapped programs of a sweep's chunks, of re-scoring and of the panel methods run 15-30 % faster.
# Its classic emitters compile a small program in about half the time and run it as fast (2 cores, 2026-11-29: the
# demo fit's compile 13.9 -> 6.9 s; the DTC's GZ curve 3.1-3.8 -> 1.9-2.9 s, its run 0.98 -> 0.69 s; results equal
# to 1e-14). A cold call is mostly compiling, so a process started for a command that builds only small programs
# uses the classic ones. Cold calls measured by pairs (MLIR -> classic): motions 14.3 -> 7.5 s, waves 9.3 -> 7.4 s,
# wind 11.1 -> 8.0 s, lines 8.1 -> 6.3 s, deform 22.4 -> 18.2 s, fair 35 -> 26 s; their warm calls unchanged. Not
# `resistance` (its warm call 2.7 -> 3.2 s with Holtrop and Michell, and the panel methods' solves are large), nor
# sweeps and minimisations (their large programs). With them a fit's solver also compiles without LLVM's
# optimisation (hullopt.study's quick="classic"): the demo's cold run 21-25 -> 17-18 s, its warm run unchanged.
# Kept programs are keyed by XLA_FLAGS (hullopt.study), so each kind has its own; the user's XLA_FLAGS decide
# where they name the option. jaxlib 0.11.1 removed the option, and XLA aborts a process whose XLA_FLAGS name an
# unknown one: it is set only where jaxlib is older (classic_emitters_available).
CLASSIC_EMITTERS = "--xla_cpu_use_fusion_emitters=false"
SMALL_PROGRAM_COMMANDS = frozenset({"hydro", "stability", "motions", "waves", "wind", "lines", "deform", "fair"})
SMALL_PROGRAM_RUNS = frozenset({"fit"})  # `hullopt run` of a config of these kinds


def classic_emitters_available(jaxlib_version: str | None = None) -> bool:
    """Whether XLA:CPU takes :data:`CLASSIC_EMITTERS`: jaxlib before 0.11.1 (``jaxlib_version``; None: the
    installed one, read from its metadata without importing it)."""
    if jaxlib_version is None:
        from importlib.metadata import PackageNotFoundError, version

        try:
            jaxlib_version = version("jaxlib")
        except PackageNotFoundError:
            return False
    release = []
    for part in jaxlib_version.split(".")[:3]:
        digits = re.match(r"\d+", part)
        if digits is None:
            break
        release.append(int(digits.group()))
    return bool(release) and tuple(release) < (0, 11, 1)


def xla_flags_for(argv: list[str], current: str, classic: bool | None = None) -> str:
    """``XLA_FLAGS`` for a process that runs the command ``argv``: ``current`` with :data:`CLASSIC_EMITTERS`
    appended where the command builds only small programs (:data:`SMALL_PROGRAM_COMMANDS`, or ``run`` of a config
    whose ``kind`` is in :data:`SMALL_PROGRAM_RUNS`), ``current`` does not choose the emitters itself and XLA has
    them (``classic``; None: :func:`classic_emitters_available`)."""
    words = [a for a in argv if not a.startswith("-")]
    command = words[0] if words else None
    small = command in SMALL_PROGRAM_COMMANDS
    if command == "run":  # the config's kind decides; an unreadable config is the run command's error to report
        config = next((a for a in words[1:] if a.endswith(".toml")), None)
        try:
            small = tomllib.loads(Path(config).read_text()).get("kind") in SMALL_PROGRAM_RUNS
        except (TypeError, OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
            small = False
    if not small or "xla_cpu_use_fusion_emitters" in current or not (
            classic_emitters_available() if classic is None else classic):
        return current
    return f"{current} {CLASSIC_EMITTERS}".strip()


def configure_jax() -> None:
    """float64 everywhere, and a per-host persistent compilation cache (warm starts skip compiling)."""
    import jax

    jax.config.update("jax_enable_x64", True)
    cache = Path(os.environ.get("HULLOPT_CACHE", Path.home() / ".cache" / "hullopt")) / f"jax-{socket.gethostname()}"
    try:
        cache.mkdir(parents=True, exist_ok=True)
        jax.config.update("jax_compilation_cache_dir", str(cache))
        jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
        jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)
    except OSError:
        pass  # a read-only home: run without the cache


def _warn_hull_warnings() -> None:
    """Within a ``warnings.catch_warnings()`` block: print each distinct :class:`HullWarning` as one ``warning: …``
    line on stderr (through ``output.warn``, as the commands' own warnings); other warnings as Python prints them."""
    from .output import warn

    warnings.simplefilter("default", HullWarning)
    shown = warnings.showwarning

    def show(message, category, filename, lineno, file=None, line=None) -> None:
        if issubclass(category, HullWarning):
            warn(str(message))
        else:
            shown(message, category, filename, lineno, file, line)

    warnings.showwarning = show


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; a user's mistake (:class:`HullError`, or a :class:`HullWarning` under ``--strict``) is one line
    on stderr and exit code 2; a hull that looks implausible is one ``warning: …`` line each finding."""
    configure_jax()
    from ._app import app
    from .commands import register

    register(sys.argv[1:] if argv is None else argv)
    with warnings.catch_warnings():  # the command's filters (--strict) end with it
        _warn_hull_warnings()
        try:
            app(args=argv)  # usage errors: the parser prints them and exits with code 2
        except SystemExit as e:
            return e.code if isinstance(e.code, int) else (0 if e.code is None else 1)
        except HullError as e:
            print(f"error: {e}", file=sys.stderr)
            return 2
        except HullWarning as e:
            print(f"error: {e} (refused by --strict)", file=sys.stderr)
            return 2
        finally:
            if "hullopt.study._programs" in sys.modules:  # what this command prepared and did not take (an error)
                from ..study import discard_prepared

                discard_prepared()
    return 0


if __name__ == "__main__":
    sys.exit(main())


def run() -> None:
    """Console-script entry point. Every output is written (atomically) and flushed when :func:`main` returns,
    so the process ends at once: the interpreter's teardown of JAX, XLA and the imported modules would add
    about half a second to every command. XLA's flags are chosen here, for the process, before jax starts its
    backend (:func:`xla_flags_for`)."""
    os.environ["XLA_FLAGS"] = xla_flags_for(sys.argv[1:], os.environ.get("XLA_FLAGS", ""))
    code = main()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
