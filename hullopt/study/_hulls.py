"""The parent of a design run (``[hull] parent``): a library parent (``dtc``, ``parent:dtc``), a parent ``.json``,
or any hull spec :func:`~hullopt.study.load_hull` reads — a mesh ``hull.stl?scale=…&lpp=…``, an offsets
``.csv``, a ``builtin:…``, a run folder. A hull spec's contour lines and feature curves are extracted on first use
(:func:`~hullopt.models._feature_library.extract_faithful`: the cheapest level of auxiliary apexes whose rebuilt
hull holds ∇ to 0.05 % and LCB to 0.01 % Lpp) and kept in the cache folder::

    $HULLOPT_CACHE/parents/<key digest>.json        (default ~/.cache/hullopt/parents)

keyed by the SHA-256 of the file's content (not its path), the spec's parameters, the config's draft and the
extraction's settings and code (the sources that read, slice and extract a hull), so a later run reads them
back; a missing, corrupt or foreign file is extracted again and rewritten (atomically; a read-only cache is
only read); files unused for 30 days are deleted when a new one is written. A kept file is a parent ``.json``
(:func:`~hullopt.models.save_features`) with the key and the measured fidelity (``"fidelity"``) beside it.
"""

from __future__ import annotations

import contextlib
import functools
import hashlib
import json
import os
import time
import warnings
from pathlib import Path
from typing import TYPE_CHECKING
from urllib.parse import parse_qsl

from ..errors import FidelityWarning, HullError, HullWarning
from ..geometry import Sections, atomic_write_bytes
from ..models import (
    FAITHFUL,
    FeatureHull,
    LoadedHull,
    check_params_used,
    extract_faithful,
    load_parent,
    mesh_sections_shape,
    parent_names,
    read_features,
    split_spec,
    take_param,
)
from ..models import load_hull as load_spec

if TYPE_CHECKING:  # the configs and studies load where a study is made: reading a hull needs neither
    from ._config import RunConfig
    from ._study import Study

#: Bump to re-extract every kept parent (a change of what is stored, not of the code: that is in the key).
EXTRACTION_VERSION = 1
_PACKAGE = Path(__file__).resolve().parents[1]


def cache_folder(what: str = "parents") -> Path:
    """Where hullopt keeps ``what``: ``$HULLOPT_CACHE/<what>`` (default ``~/.cache/hullopt/<what>``).

    Parameters
    ----------
    what : str
        The kind of thing kept: ``"parents"`` (extracted parents) or ``"sections"`` (the sections sliced from
        mesh and CAD hulls).

    Returns
    -------
    pathlib.Path
        The folder (not created here).
    """
    return Path(os.environ.get("HULLOPT_CACHE", Path.home() / ".cache" / "hullopt")) / what


def load_hull(spec: str) -> LoadedHull:
    """Read the hull named by ``spec``.

    A run folder gives its design hull, rebuilt exactly from ``config.json`` and ``report.json`` (``?design=K``
    picks design K of a sweep); any other spec is read by :func:`hullopt.models.load_hull` (a mesh's sections
    kept in ``cache_folder("sections")``).

    Parameters
    ----------
    spec : str
        A hull spec: a run folder (optionally ``?design=K``), a library parent, a parent ``.json``, a mesh or
        offsets file with its parameters, a ``builtin:…``.

    Returns
    -------
    LoadedHull
        The hull's sections, its name and its design draft [m] (a run folder's: the run's draft).

    Raises
    ------
    HullError
        On any problem: an unknown spec, an unreadable file, a run folder whose files do not fit each other.
    """
    base, params = split_spec(spec)
    if not base.startswith(("parent:", "builtin:")) and Path(base).is_dir():
        return _run_folder(Path(base), params, spec)
    return load_spec(spec, cache=cache_folder("sections"))


def sections_like(spec: str) -> Sections | None:
    """The sections :func:`load_hull` will give for ``spec``, as shapes, where the spec alone tells them and
    loading is slow: for :func:`~hullopt.study.prepare_call`, to build a command's program while the file is
    read.

    Parameters
    ----------
    spec : str
        A hull spec.

    Returns
    -------
    Sections or None
        :class:`jax.ShapeDtypeStruct` leaves (float64): ``x (n,)``, ``yz (n, m, 2)``, ``lpp ()``, for a mesh or
        CAD file (read and sliced); None for any other spec.
    """
    shape = mesh_sections_shape(spec)
    if shape is None:
        return None
    import jax
    import numpy as np

    n, m = shape
    like = Sections(x=np.zeros(n), yz=np.zeros((n, m, 2)), lpp=np.float64(0.0))
    return jax.tree.map(lambda a: jax.ShapeDtypeStruct(np.shape(a), np.result_type(a)), like)


def read_run_config(folder: Path, what: str = "") -> RunConfig:
    """The validated ``config.json`` of a run folder.

    Parameters
    ----------
    folder : pathlib.Path
        The run folder.
    what : str
        A prefix for the error message, e.g. the hull spec.

    Returns
    -------
    RunConfig
        The run's config.

    Raises
    ------
    HullError
        When ``config.json`` is missing, not JSON or not a valid run config; the message names the file.
    """
    from pydantic import ValidationError

    path = folder / "config.json"
    try:
        raw = json.loads(path.read_text())
    except (OSError, ValueError) as e:
        raise HullError(f"{what}{folder} is not a run folder (config.json: {type(e).__name__}: {e})") from None
    try:
        from ._config import RunConfig

        return RunConfig.model_validate(raw)
    except ValidationError as e:
        err = e.errors()[0]
        raise HullError(f"{what}{path} is not a valid run config "
                        f"({'.'.join(map(str, err['loc'])) or 'config'}: {err['msg']})") from None


def load_study(cfg: RunConfig) -> Study:
    """The study of a config (:data:`~hullopt.study.STUDIES` by its ``kind``) on the parent it names.

    Parameters
    ----------
    cfg : RunConfig
        A validated run config; its ``[hull]`` parent and draft are read by :func:`run_parent`.

    Returns
    -------
    Study
        The study (:class:`Fit`, :class:`Minimise` or :class:`Pareto`), its problem built.

    Raises
    ------
    HullError
        A bad parent spec, a parent without a design draft when the config gives none, or a bad design.
    """
    from ._study import STUDIES

    return STUDIES[cfg.kind](cfg, run_parent(cfg.hull.parent, cfg.hull.draft))


def folder_study(folder: Path, cfg: RunConfig) -> Study:
    """The study of a run folder: its config on the parent the run deformed.

    That is the kept ``parent.json`` (the config's parent may have changed since), else the config's parent.

    Parameters
    ----------
    folder : pathlib.Path
        The run folder.
    cfg : RunConfig
        Its config (:func:`read_run_config`).

    Returns
    -------
    Study
        The study of ``cfg.kind`` on that parent.
    """
    kept = folder / "parent.json"
    parent = read_features(kept) if kept.is_file() else run_parent(cfg.hull.parent, cfg.hull.draft)
    from ._study import STUDIES

    return STUDIES[cfg.kind](cfg, parent)


def _run_folder(folder: Path, params: dict[str, str], spec: str) -> LoadedHull:
    """The design hull of a run folder: the run's model at its final parameters (a sweep: ``design=K``)."""
    design = take_param(params, "design", spec, int, -1)
    check_params_used(params, spec, ["design"])
    cfg = read_run_config(folder, f"hull {spec!r}: ")
    try:
        report = json.loads((folder / "report.json").read_text())
    except (OSError, ValueError) as e:
        raise HullError(f"hull {spec!r}: {folder} is not a run folder with config.json and report.json "
                        f"({type(e).__name__}: {e})") from None
    study = folder_study(folder, cfg)
    try:
        p, label = study.final_params(report, design)
    except ValueError as e:
        raise HullError(f"hull {spec!r}: {e}") from None
    import numpy as np

    from ._programs import cached_call

    # a kept program: evaluated op by op, the model took ~7 s of a cold `hullopt lines RUN` (160 small compiles)
    d = study.problem.design
    sections, draft = cached_call("design-hull", _evaluate, (d.model, p, np.asarray(d.draft)), (), key=study.key,
                                  quick=True)
    return LoadedHull(sections, f"{folder.name}{label}", float(draft))  # at the design's own draft


def _evaluate(model, params, draft) -> tuple:
    return model(params), draft * model.draft_factor(params)


def _library(spec: str) -> str | None:
    """The name :func:`~hullopt.models.load_parent` takes for a library parent or parent ``.json``, else None."""
    name = spec.removeprefix("parent:")
    if name != spec or name in parent_names() or name.lower().endswith(".json"):
        return name
    return None


@functools.cache
def _code_digest() -> str:
    """Digest of the code that turns a spec into feature curves (models, geometry, the spec parser)."""
    h = hashlib.sha256(f"extraction v{EXTRACTION_VERSION}".encode())
    files = [*sorted((_PACKAGE / "models").glob("*.py")), *sorted((_PACKAGE / "geometry").glob("*.py")),
             Path(__file__)]
    for path in files:
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()


def _content_digest(base: str) -> str | None:
    """SHA-256 of a spec's file (a run folder: of its config.json and report.json); None for a builtin."""
    path = Path(base)
    if path.is_file():
        return hashlib.sha256(path.read_bytes()).hexdigest()
    if path.is_dir():
        h = hashlib.sha256()
        for name in ("config.json", "report.json"):
            f = path / name
            h.update(f.read_bytes() if f.is_file() else b"")
        return h.hexdigest()
    return None


def parent_key(spec: str, draft: float | None = None) -> dict:
    """What determines the features extracted from the hull spec ``spec``: the file's content digest and
    kind (its suffixes), the spec's parameters (sorted), the config's draft [m] (the fidelity is checked there
    when the spec has no design draft), the extraction settings and the code digest.
    :class:`HullError` if ``spec`` names no file, run folder or builtin."""
    base, _, query = spec.partition("?")
    digest = _content_digest(base)
    if digest is None and not base.startswith("builtin:"):
        if Path(base).suffix:  # a file's name: say it is missing, not that the name is unknown
            where = "" if Path(base).is_absolute() else (" (a relative path is read from the config's folder, "
                                                         f"then from the working directory {Path.cwd()})")
            raise HullError(f"parent {spec!r}: no such file{where}")
        raise HullError(f"unknown parent {spec!r}; expected a library parent ({', '.join(parent_names())}), "
                        "a parent .json, or a hull spec: a mesh or offsets file (relative to the config's "
                        "folder), builtin:…, a run folder")
    kind = base if digest is None else ("run folder" if Path(base).is_dir() else "".join(Path(base).suffixes).lower())
    params = sorted(parse_qsl(query, keep_blank_values=True))
    return {"kind": kind, "content": digest, "params": params, "draft": None if draft is None else float(draft),
            "extraction": FAITHFUL, "code": _code_digest()}


def _key_digest(key: dict) -> str:
    return hashlib.sha256(json.dumps(key, sort_keys=True, default=list).encode()).hexdigest()


def parent_digest(spec: str, draft: float | None = None) -> str | None:
    """A digest of a run parent's content, for the compiled-program key.

    Parameters
    ----------
    spec : str
        The config's ``[hull] parent``.
    draft : float or None
        The config's draft [m] (part of a hull spec's feature key).

    Returns
    -------
    str or None
        A parent ``.json``'s SHA-256, a hull spec's feature key digest (:func:`parent_key`), None for a library
        parent (the package's code digest has it).

    Raises
    ------
    HullError
        When ``spec`` is no library parent or parent ``.json`` and names no file, run folder or builtin.
    """
    name = _library(spec)
    if name is not None:
        path = Path(name)
        return hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else None
    return _key_digest(parent_key(spec, draft))


def _read_kept(path: Path, key: dict) -> tuple[FeatureHull, list[str], dict] | None:
    """The kept parent at ``path`` and the warnings of the hull it was extracted from, if it is one for ``key``,
    else None (absent, corrupt or another key's)."""
    try:
        data = json.loads(path.read_text())
        if json.loads(json.dumps(key, default=list)) != data.get("key"):
            return None
        hull = read_features(path)
        found = [str(w) for w in data.get("warnings", [])]
        fidelity = dict(data.get("fidelity") or {})
    except (OSError, ValueError, AttributeError, TypeError, HullError):
        return None
    with contextlib.suppress(OSError):
        path.touch()  # in use: keep it (see _keep)
    return hull, found, fidelity


def extract_spec(spec: str, draft: float | None = None) -> tuple[FeatureHull, dict]:
    """Read the hull ``spec`` and extract its features faithfully (no cache), checked at its design draft:
    the spec's (a builtin's T), else ``draft`` [m]. Returns the hull and the
    extraction report of :func:`~hullopt.models._feature_library.extract_faithful` with the hull's plausibility
    ``warnings`` (:class:`~hullopt.models.LoadedHull`'s, issued as it was read). :class:`HullError` when
    neither the spec nor ``draft`` gives a design draft."""
    loaded = load_hull(spec)
    if draft is None and loaded.design_draft is None:
        raise HullError(_no_draft(spec))
    hull, report = extract_faithful(loaded.sections, loaded.name, loaded.design_draft or draft)
    return hull, {**report, "warnings": list(loaded.warnings)}


def fidelity_warning(spec: str, fidelity: dict) -> str | None:
    """The warning of a run's parent whose feature curves miss their source hull (``fidelity["met"]`` false,
    :func:`~hullopt.models._feature_library.extract_faithful`'s report), else None.

    Parameters
    ----------
    spec : str
        The hull spec the parent was extracted from.
    fidelity : dict
        The extraction's report: ``met``, ``volume_error``, ``lcb_error`` (the worst over its ``drafts``),
        their tolerances ``tol_volume``, ``tol_lcb`` and, where measured, ``wetted_surface_error``.

    Returns
    -------
    str or None
        One line naming the misses against their tolerances and what they mean for the run.
    """
    if fidelity.get("met", True):
        return None
    tv, tl = fidelity.get("tol_volume", 5e-4), fidelity.get("tol_lcb", 1e-4)
    parts = [f"∇ off by up to {100 * fidelity.get('volume_error', 0.0):.3f} % (tolerance {100 * tv:.3f} %)",
             f"LCB by up to {100 * fidelity.get('lcb_error', 0.0):.4f} % Lpp (tolerance {100 * tl:.4f} %)"]
    if "wetted_surface_error" in fidelity:
        parts.append(f"wetted surface {100 * fidelity['wetted_surface_error']:+.2f} % at the design draft")
    return (f"the parent's feature curves miss the hull read from {spec}: {', '.join(parts)}; the run's parent and "
            "its particulars are the feature model's, not the file's (hullopt hydro on the file gives the file's)")


def _no_draft(spec: str) -> str:
    return (f"hull.draft: the parent {spec!r} has no known design draft; give it in [hull] as draft = … [m] "
            "(the draft the targets are meant at)")


def run_parent(spec: str, draft: float | None = None) -> FeatureHull:
    """The feature-curve parent named by ``[hull] parent`` (see the module docstring).

    A hull spec's features come from the cache folder when kept there, else are extracted and kept; either way
    the hull's plausibility warnings are issued (:class:`~hullopt.errors.HullWarning`: kept with the features).

    Parameters
    ----------
    spec : str
        A library parent (``dtc``, ``parent:dtc``), a parent ``.json`` or a hull spec.
    draft : float or None
        The config's draft [m]; None: the parent's design draft.

    Returns
    -------
    FeatureHull
        The parent's feature curves.

    Raises
    ------
    HullError
        When ``draft`` is None and the parent has no design draft, or on a bad spec.
    """
    name = _library(spec)
    if name is not None:
        return load_parent(name)
    key = parent_key(spec, draft)
    path = cache_folder() / f"{_key_digest(key)[:32]}.json"
    kept = _read_kept(path, key)
    if kept is None:
        hull, report = extract_spec(spec, draft)  # load_hull issues the hull's warnings
        _keep(path, hull, key, spec, report)
        missed = fidelity_warning(spec, report)
    else:
        hull, found, fidelity = kept
        for text in found:
            warnings.warn(text, HullWarning, stacklevel=2)
        missed = fidelity_warning(spec, fidelity)
    if missed:
        warnings.warn(missed, FidelityWarning, stacklevel=2)
    if draft is None and hull.design_draft is None:
        raise HullError(_no_draft(spec))
    return hull


def _keep(path: Path, hull: FeatureHull, key: dict, spec: str, report: dict) -> None:
    fidelity = {k: v for k, v in report.items() if k != "warnings"}
    data = {"key": key, "source": spec, "warnings": report.get("warnings", []), "fidelity": fidelity,
            **hull.to_dict()}
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        atomic_write_bytes(path, (json.dumps(data, separators=(",", ":"), default=list) + "\n").encode())
    except OSError:
        return  # a read-only cache: extract again next time
    cutoff = time.time() - 30 * 86400.0  # kept parents unused for 30 days (older code, edited files) go
    for old in path.parent.glob("*.json"):
        with contextlib.suppress(OSError):
            if old.stat().st_mtime < cutoff:
                old.unlink()
