"""Hull specs on the command line and in configs: the library's specs (:func:`hullopt.models.load_hull`:
``builtin:``, ``parent:``, offsets ``.csv``, meshes and CAD with ``?scale=&lpp=&…``) and run folders:

* ``runs/NAME`` — a run folder: its design hull, rebuilt exactly from ``config.json`` and ``report.json``
  (``?design=K`` picks design K of a sweep).

A run folder needs the run code (configs, problems), so it is read here, on the app floor; every other spec is
delegated to :mod:`hullopt.models`. The sections sliced from a mesh or CAD file are kept in
``$HULLOPT_CACHE/sections`` (default ``~/.cache/hullopt/sections``), keyed by the file's content, the spec and
the slicing code, so the next command on the same hull skips reading and slicing it.
"""

from __future__ import annotations

import os
from pathlib import Path

from ..errors import HullError
from ..models import LoadedHull, check_params_used, split_spec, take_param
from ..models import load_hull as load_spec

__all__ = ["LoadedHull", "load_hull", "sections_cache"]


def sections_cache() -> Path:
    """Where the sections of mesh and CAD hulls are kept: ``$HULLOPT_CACHE/sections`` (default
    ``~/.cache/hullopt/sections``)."""
    return Path(os.environ.get("HULLOPT_CACHE", Path.home() / ".cache" / "hullopt")) / "sections"


def load_hull(spec: str) -> LoadedHull:
    """Read the hull named by ``spec``: a run folder here, any other spec by :func:`hullopt.models.load_hull`
    (a mesh's sections kept in :func:`sections_cache`); :class:`HullError` on any problem."""
    base, params = split_spec(spec)
    if not base.startswith(("parent:", "builtin:")) and Path(base).is_dir():
        return _run_folder(Path(base), params, spec)
    return load_spec(spec, cache=sections_cache())


def _run_folder(folder: Path, params: dict[str, str], spec: str) -> LoadedHull:
    """The design hull of a run folder: the run's model at its final parameters (a sweep: ``design=K``)."""
    import json

    from pydantic import ValidationError

    from ..models import read_features
    from .config import RunConfig
    from .run import build_problem, params_from_dict

    design = take_param(params, "design", spec, int, -1)
    check_params_used(params, spec, ["design"])
    try:
        raw = json.loads((folder / "config.json").read_text())
        report = json.loads((folder / "report.json").read_text())
    except (OSError, ValueError) as e:
        raise HullError(f"hull {spec!r}: {folder} is not a run folder with config.json and report.json "
                        f"({type(e).__name__}: {e})") from None
    try:
        cfg = RunConfig.model_validate(raw)
    except ValidationError as e:
        raise HullError(f"hull {spec!r}: {folder / 'config.json'} is not a valid run config ({e.errors()[0]['msg']})") from None
    if "designs" in report:
        designs = report["designs"]
        if not 0 <= design < len(designs):
            raise HullError(f"hull {spec!r}: a sweep's run folder needs ?design=K with K in 0…{len(designs) - 1}")
        values, label = designs[design]["params"], f" design {design}"
    else:
        if design != -1:
            raise HullError(f"hull {spec!r}: ?design applies to sweeps; {folder} is a {report.get('kind')!r} run")
        if "params" not in report:
            raise HullError(f"hull {spec!r}: {folder / 'report.json'} has no params (an unfinished shard?)")
        values, label = report["params"], ""
    kept = folder / "parent.json"  # the parent the run deformed (the config's may have changed since)
    prob = build_problem(cfg, read_features(kept) if kept.is_file() else None)
    sections = prob.design.model(params_from_dict(values, prob.p0))
    return LoadedHull(sections, f"{folder.name}{label}", float(prob.design.draft))
