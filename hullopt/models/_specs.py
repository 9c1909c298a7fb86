"""Hull specs: one string names a hull and how to read it (the library's reader of hulls; the CLI and configs
take the same strings, and add run folders: :func:`hullopt.study.load_hull`).

* ``builtin:wigley?L=100&B=10&T=6.25&D=10`` or ``builtin:box?L=100&B=20&D=10`` (``n``, ``m``: resolution);
* ``parent:dtc`` — a feature-curve parent: the library's (``dtc``, ``tanker``, ``wigley``, ``seed003``) or a
  parent ``.json`` written by ``hullopt features`` (``?q=``: points per segment);
* ``path/to/offsets.csv`` (``?n=121&m=81``: stations and points of the spline surface);
* ``path/to/hull.stl[.gz]`` or any mesh trimesh reads, with
  ``?scale=59.407&lpp=355&axes=x,y,z&shift=0,0,0&n=201&m=96&half=auto``: closed, open along its top (no deck),
  or a half hull open at the centre plane (``half=auto|yes|no``);
* ``path/to/hull.igs`` (``.iges``, ``.stp``, ``.step``: CAD surfaces, needs ``pip install 'hullopt[cad]'``), with
  the mesh parameters and ``tol``: the largest triangle edge of the tessellation [m, at the file's scale, in
  metres whatever the file's unit; default 1/200 of the model's largest extent].

Reading is static preprocessing (numpy, files); the :class:`~hullopt.geometry.Sections` it returns are what
the differentiable code takes.

Slicing a mesh takes seconds (reading the file, checking where it is open, cutting every station); given a
``cache`` folder, :func:`load_hull` keeps a mesh's sections there as ``<key digest>.npz``, keyed by the SHA-256
of the file's content (not its path), the spec's parameters (scale, axes, shift, lpp, n, m, tol, half), the
source of the modules that read and slice it and the versions of the libraries they read with (trimesh, numpy;
gmsh for CAD). A later call with the same file and spec reads them back (no trimesh, no slicing); a changed file,
spec or reading code misses. Files are written atomically and a missing, corrupt or foreign one is sliced again;
a read-only folder is only read; kept sections unused for 30 days are deleted when new ones are written.
The library keeps nothing unless asked; the CLI passes ``$HULLOPT_CACHE/sections``.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import io
import json
import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any
from urllib.parse import parse_qsl

import numpy as np

from ..errors import HullError, HullWarning
from ..geometry import Sections, atomic_write_bytes, read_stl_header
from ._builtins import BUILTINS
from ._cad import is_cad
from ._meshes import MeshTransform, read_mesh, slice_mesh
from ._offsets import offsets_to_sections, read_offsets
from ._plausibility import plausibility_warnings


@dataclass(frozen=True)
class LoadedHull:
    """A hull read from a spec: its sections, a display name, its design draft when known [m] and what looks
    implausible about it (:func:`~hullopt.models.plausibility_warnings`: one line a finding, with the fix)."""

    sections: Sections
    name: str
    design_draft: float | None = None
    warnings: tuple[str, ...] = ()

    def keel_and_depth(self) -> tuple[float, float]:
        """The lowest and highest points of the sections [m above the baseline] (numpy: no JAX op)."""
        z = np.asarray(self.sections.yz)[..., 1]
        return float(z.min()), float(z.max())

    def check_draft(self, draft: float, what: str = "--draft") -> float:
        """``draft`` [m above the baseline] as a float when it lies above the baseline (and the keel) and at most at
        the deck (there the waterplane is the deck edge's: the deck closes the sections; above it the hull is
        submerged); :class:`HullError` naming ``what`` (the option or field) otherwise."""
        keel, hi = self.keel_and_depth()
        lo = max(0.0, keel)
        if not (np.isfinite(draft) and lo < draft <= hi):
            where = "above the deck" if np.isfinite(draft) and draft > hi else "outside the hull"
            hint = ""
            if np.isfinite(draft) and draft > 5.0 * hi:  # a model-scale file read as a ship
                hint = (f"; the hull is only {hi:g} m deep: a model-scale file? give the spec its scale, "
                        "FILE?scale=S (S = ship length / model length)")
            raise HullError(f"{what} {draft:g} m is {where}: expected a draft in ({lo:g}, {hi:g}] m "
                            f"(keel or baseline to deck){hint}")
        return float(draft)


def split_spec(spec: str) -> tuple[str, dict[str, str]]:
    """Split a hull spec ``BASE?k=v&…`` into its base and its parameters.

    Parameters
    ----------
    spec : str
        The hull spec.

    Returns
    -------
    tuple of (str, dict of str to str)
        ``BASE`` and ``{k: v}`` (values as written).

    Raises
    ------
    HullError
        A parameter given twice.
    """
    base, _, query = spec.partition("?")
    pairs = parse_qsl(query, keep_blank_values=True, strict_parsing=False)
    params = {}
    for k, v in pairs:
        if k in params:
            raise HullError(f"hull {spec!r}: parameter {k} given twice")
        params[k] = v
    return base, params


def take_param(params: dict[str, str], key: str, spec: str, kind: Callable[[str], Any] = float, default: Any = None):
    """Take one parameter of a hull spec (removing it from ``params``).

    Parameters
    ----------
    params : dict of str to str
        The spec's remaining parameters (:func:`split_spec`); ``key`` is popped.
    key : str
        The parameter's name.
    spec : str
        The whole spec, for messages.
    kind : callable, optional
        Parses the value (``float``, ``int``, ``str``).
    default : optional
        The value when ``key`` is absent; None: the parameter is required.

    Returns
    -------
    object
        ``kind(value)``, or ``default``.

    Raises
    ------
    HullError
        ``key`` missing without a default, or a value ``kind`` does not parse.
    """
    if key not in params:
        if default is None:
            raise HullError(f"hull {spec!r}: missing parameter {key}")
        return default
    text = params.pop(key)
    try:
        return kind(text)
    except ValueError:
        raise HullError(f"hull {spec!r}: parameter {key}={text!r} is not a valid {kind.__name__}") from None


def check_params_used(params: dict[str, str], spec: str, allowed: list[str]) -> None:
    """Refuse the parameters of a hull spec that no reader took.

    Parameters
    ----------
    params : dict of str to str
        The parameters left after the reader took its own.
    spec : str
        The whole spec, for the message.
    allowed : list of str
        The reader's parameters, listed in the message.

    Returns
    -------
    None

    Raises
    ------
    HullError
        Naming the first parameter left over, when any is.
    """
    if params:
        raise HullError(
            f"hull {spec!r}: unknown parameter {sorted(params)[0]!r}; expected {', '.join(allowed)}"
        )


def load_hull(spec: str, cache: str | Path | None = None) -> LoadedHull:
    """Read the hull named by a hull spec.

    Parameters
    ----------
    spec : str
        ``builtin:NAME?…``, ``parent:NAME|FILE.json[?q=]``, an offsets ``.csv`` or a mesh or CAD file with its
        ``?scale=&lpp=&axes=&shift=&n=&m=&half=&tol=`` parameters (see the module docstring; lengths in m).
    cache : str or Path, optional
        A folder where the sections sliced from a mesh or CAD file are kept and read back, keyed by the file's
        content, the spec's parameters and the slicing code (see the module docstring); created if missing.
        ``None`` (default): nothing is kept. Other specs ignore it.

    Returns
    -------
    LoadedHull
        ``sections`` (:class:`~hullopt.geometry.Sections`), a display ``name``, the ``design_draft`` [m]
        when the spec knows one (builtins with ``T``, parents, meshes hullopt wrote), else None, and the
        ``warnings`` of a hull read from a file that looks implausible (a mesh in millimetres, in the wrong
        axes: :func:`~hullopt.models.plausibility_warnings`; a builtin states its dimensions and is not judged).

    Raises
    ------
    HullError
        On any problem with the spec or the file, naming the spec (a folder too: run folders are the CLI's,
        :func:`hullopt.study.load_hull`).

    Warns
    -----
    HullWarning
        Each of the hull's ``warnings`` (``warnings.simplefilter("error", HullWarning)`` refuses such a hull).
    """
    loaded = _read(spec, cache)
    if spec.startswith("builtin:"):
        return loaded
    found = tuple(plausibility_warnings(loaded.sections, loaded.design_draft, spec))
    for text in found:
        warnings.warn(text, HullWarning, stacklevel=2)
    return replace(loaded, warnings=found)


def _read(spec: str, cache: str | Path | None) -> LoadedHull:
    """:func:`load_hull` before its hull is judged."""
    base, params = split_spec(spec)
    if base.startswith("parent:"):
        return _parent(base.removeprefix("parent:"), params, spec)
    if base.startswith("builtin:"):
        return _builtin(base.removeprefix("builtin:"), params, spec)
    path = Path(base)
    if path.is_dir():
        raise HullError(f"hull {spec!r}: {base!r} is a folder; run folders are read by hullopt.study.load_hull")
    if not path.is_file():
        from ._features import parent_names

        hint = f"; the library parent is parent:{base}" if base in parent_names() else ""
        raise HullError(f"hull {spec!r}: no such file or run folder {base!r} (nor builtin:NAME, parent:NAME){hint}")
    if path.suffix.lower() == ".csv":
        return _offset_table(path, params, spec)
    return _mesh(path, params, spec, cache)


MESH_STATIONS, MESH_POINTS = 201, 96  # a mesh's slicing by default: stations, points a half-section


def mesh_sections_shape(spec: str) -> tuple[int, int] | None:
    """The shape of the sections :func:`load_hull` slices from the mesh or CAD file of ``spec``, known before
    the file is read.

    Parameters
    ----------
    spec : str
        A hull spec, as :func:`load_hull` takes it.

    Returns
    -------
    tuple of (int, int) or None
        ``(n, m)``: the stations and the points a half-section (the spec's ``n`` and ``m``, 201 and 96 by
        default); None for any other spec (quick to load) or one whose parameters do not read
        (:func:`load_hull` says why).
    """
    try:
        base, params = split_spec(spec)
        path = Path(base)
        if base.startswith(("parent:", "builtin:")) or path.suffix.lower() == ".csv" or not path.is_file():
            return None
        return take_param(params, "n", spec, int, MESH_STATIONS), take_param(params, "m", spec, int, MESH_POINTS)
    except HullError:
        return None


def _builtin(name: str, params: dict[str, str], spec: str) -> LoadedHull:
    """An analytic hull (:data:`~hullopt.models.BUILTINS`) from its dimensions [m]."""
    if name not in BUILTINS:
        raise HullError(f"hull {spec!r}: unknown builtin {name!r}; expected one of {', '.join(BUILTINS)}")
    fn, required = BUILTINS[name]
    args = {k: take_param(params, k, spec) for k in required}
    res = {k: take_param(params, k, spec, int) for k in ("n", "m") if k in params}
    check_params_used(params, spec, [*required, "n", "m"])
    return LoadedHull(fn(**args, **res), f"{name} " + " ".join(f"{k}={v:g}" for k, v in args.items()), args.get("T"))


def _offset_table(path: Path, params: dict[str, str], spec: str) -> LoadedHull:
    """The spline surface through an offset table (``n`` stations × ``m`` points)."""
    table = read_offsets(path)
    res = {k: take_param(params, key, spec, int, d) for k, key, d in (("n_stations", "n", 121), ("n_points", "m", 81))}
    check_params_used(params, spec, ["n", "m"])
    return LoadedHull(offsets_to_sections(table, **res), path.name)


def _mesh(path: Path, params: dict[str, str], spec: str, cache: str | Path | None = None) -> LoadedHull:
    """A mesh or CAD surface, brought into our axes and sliced (closed, open-topped or a half hull); kept in
    and read back from ``cache`` when given."""
    shift = take_param(params, "shift", spec, str, "0,0,0")
    try:
        shift_xyz = tuple(float(v) for v in shift.split(","))
        assert len(shift_xyz) == 3
    except (ValueError, AssertionError):
        raise HullError(f"hull {spec!r}: shift={shift!r} must be three numbers x,y,z") from None
    transform = MeshTransform(
        scale=take_param(params, "scale", spec, float, 1.0), axes=take_param(params, "axes", spec, str, "x,y,z"),
        shift=shift_xyz,
    )
    lpp = take_param(params, "lpp", spec, float, 0.0) or None
    n = take_param(params, "n", spec, int, MESH_STATIONS)
    m = take_param(params, "m", spec, int, MESH_POINTS)
    tol = take_param(params, "tol", spec, float, 0.0) or None  # IGES/STEP tessellation size [m, file's scale]
    if tol is not None and not is_cad(path):
        raise HullError(f"hull {spec!r}: tol applies to IGES/STEP surfaces, not to a {path.suffix} mesh")
    if tol is not None and not (np.isfinite(tol) and tol > 0):
        raise HullError(f"hull {spec!r}: tol must be a positive length in m (largest triangle edge of a CAD surface)")
    half = take_param(params, "half", spec, str, "auto")  # auto|yes|no: a half hull open at the centre plane
    check_params_used(params, spec, ["scale", "axes", "shift", "lpp", "n", "m", "tol", "half"])
    kept = None
    if cache is not None:
        kept = _KeptSections(Path(cache), path, {
            "scale": transform.scale, "axes": transform.axes, "shift": list(transform.shift), "lpp": lpp, "n": n,
            "m": m, "tol": tol, "half": half,
        })
        hit = kept.read()
        if hit is not None:
            return hit
    mesh = read_mesh(path, transform, half=half, tolerance=tol)
    # Lpp and draft of a hull hullopt wrote (in its own axes: used when the file is read as it was written)
    as_written = transform.axes.replace(" ", "") == "x,y,z" and transform.shift == (0.0, 0.0, 0.0)
    written = read_stl_header(str(mesh.metadata.get("header", ""))) if as_written else {}
    draft = written["draft"] * transform.scale if "draft" in written else None
    if lpp is None:  # no Lpp given: the one hullopt wrote in the file, else the FP at the forward end
        lpp = written["lpp"] * transform.scale if "lpp" in written else float(mesh.bounds[1, 0])
    if not (np.isfinite(lpp) and lpp > 0):
        raise HullError(f"hull {spec!r}: lpp must be positive")
    try:
        sections = slice_mesh(mesh, lpp, n, m)
    except HullError as e:
        raise HullError(f"{path}: {e}") from None
    loaded = LoadedHull(sections, path.name, draft)
    if kept is not None:
        kept.write(loaded)
    return loaded


_KEPT_DAYS = 30.0  # kept sections unused this long are deleted when new ones are written
_SLICING_CODE = ("_meshes.py", "_cad.py", "_specs.py")  # the modules that read and slice a mesh


@functools.cache
def _slicing_digest(cad: bool) -> str:
    """Digest of the source that reads and slices a mesh and of the library versions it reads with."""
    from importlib import metadata

    h = hashlib.sha256()
    here = Path(__file__).resolve().parent
    for name in _SLICING_CODE:
        h.update(name.encode())
        h.update((here / name).read_bytes())
    for lib in ("numpy", "trimesh", *(("gmsh",) if cad else ())):
        try:
            h.update(f"{lib}={metadata.version(lib)}".encode())
        except metadata.PackageNotFoundError:
            h.update(f"{lib}=none".encode())
    return h.hexdigest()


class _KeptSections:
    """The sections of one mesh file and spec in a cache folder (see the module docstring)."""

    def __init__(self, folder: Path, path: Path, spec_params: dict) -> None:
        self.folder, self.path = folder, path
        try:
            content = hashlib.sha256(path.read_bytes()).hexdigest()
        except OSError as e:
            raise HullError(f"{path}: cannot read the file ({e})") from None
        key = {"file": content, "spec": spec_params, "code": _slicing_digest(is_cad(path)), "format": 1}
        self.key = hashlib.sha256(json.dumps(key, sort_keys=True, default=repr).encode()).hexdigest()
        self.file = folder / f"{self.key[:32]}.npz"

    def read(self) -> LoadedHull | None:
        """The kept sections, or None when absent, unreadable or not this key's."""
        import jax.numpy as jnp

        try:
            with np.load(io.BytesIO(self.file.read_bytes()), allow_pickle=False) as z:
                meta = json.loads(str(z["meta"]))
                if meta.get("key") != self.key:
                    return None
                x, yz, lpp = (np.array(z[k], dtype=np.float64) for k in ("x", "yz", "lpp"))
        except (OSError, ValueError, KeyError, TypeError):
            return None
        if x.ndim != 1 or yz.shape != (len(x), yz.shape[1], 2) or lpp.shape != ():
            return None
        with contextlib.suppress(OSError):
            self.file.touch()  # in use: keep it (see _prune)
        draft = meta.get("design_draft")
        sections = Sections(x=jnp.asarray(x), yz=jnp.asarray(yz), lpp=jnp.asarray(lpp))
        return LoadedHull(sections, self.path.name, None if draft is None else float(draft))

    def write(self, hull: LoadedHull) -> None:
        """Keep ``hull``'s sections (atomically); a read-only folder keeps nothing."""
        s = hull.sections
        meta = {"key": self.key, "design_draft": hull.design_draft, "source": self.path.name}
        buf = io.BytesIO()
        np.savez(buf, x=np.asarray(s.x, np.float64), yz=np.asarray(s.yz, np.float64),
                 lpp=np.asarray(s.lpp, np.float64), meta=np.array(json.dumps(meta)))
        try:
            self.folder.mkdir(parents=True, exist_ok=True)
            atomic_write_bytes(self.file, buf.getvalue())
        except OSError:
            return
        cutoff = time.time() - _KEPT_DAYS * 86400.0
        for old in self.folder.glob("*.npz"):
            with contextlib.suppress(OSError):  # another process may have deleted it already
                if old.stat().st_mtime < cutoff:
                    old.unlink()


def _parent(name: str, params: dict[str, str], spec: str) -> LoadedHull:
    """A feature-curve parent (library name or parent .json) as a hull."""
    from ._features import load_parent

    q = take_param(params, "q", spec, int, 0) or None
    check_params_used(params, spec, ["q"])
    try:
        fh = load_parent(name)
    except HullError as e:
        raise HullError(f"hull {spec!r}: {e}") from None
    return LoadedHull(fh.sections(q), f"parent {fh.name}", fh.design_draft)
