"""``hullopt features`` (contour lines and feature curves of a hull) and ``hullopt deform`` (a parent and a
design TOML → a deformed hull)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import equinox as eqx
import numpy as np
import typer

from ...errors import HullError
from ...geometry import EXPORT_FORMATS
from ...hydro import hydrostatics
from ...models import check_design, extract_parent, load_parent, parent_names
from ...report import write_json
from ...study import load_hull
from .._app import Strict, app
from ..output import console, write_hull_file, wrote


def read_design(path: Path, parent: str | None = None, draft: float | None = None):
    """A design TOML → ``(model, params, parent spec)``, validated by the run config's models
    (:func:`~hullopt.study.load_design`) and built as ``hullopt run`` builds its start point
    (:func:`~hullopt.study.design_params`); ``parent`` (the PARENT argument) before the TOML's ``parent``.
    :class:`HullError` naming the file and the field on bad input."""
    from ...study import design_params, load_design, run_parent

    cfg = load_design(path)
    name = parent or cfg.parent
    if not name:
        raise HullError(f"{path}: give the parent (a key 'parent = \"dtc\"' or the PARENT argument)")
    model, params, _ = design_params(cfg, run_parent(name, draft), where="", draft=draft)
    return model, params, name


def plot_features(hull, path: Path, title: str = "") -> None:
    """Body plan with the feature points (inflection ■, apex ▲, auxiliary apex ·) and the contour points."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    yz = np.asarray(hull.sections().yz)
    x = np.asarray(hull.x)
    mid = float(hull.lpp) / 2
    fig, ax = plt.subplots(figsize=(10, 7))
    for i in range(len(x)):
        sgn = 1.0 if x[i] >= mid else -1.0  # fore body right, after body left
        ax.plot(sgn * yz[i, :, 0], yz[i, :, 1], color="0.6", lw=0.6)
    ends, apex, aux = (np.asarray(a) for a in (hull.ends, hull.apex_points(), hull.aux_points()))
    real = np.asarray(hull.real)
    sg = np.where(x >= mid, 1.0, -1.0)
    for s in range(apex.shape[1]):
        r = real[:, s]
        ax.plot(sg[r] * apex[r, s, 0], apex[r, s, 1], "^", ms=3, label=f"apex line {s}" if r.any() else None)
        a = aux[r, s].reshape(-1, 2)
        ax.plot(np.repeat(sg[r], a.shape[0] // max(r.sum(), 1)) * a[:, 0], a[:, 1], ".", ms=1.5, color="0.3")
    inner = ends[:, 1:-1].reshape(len(x), -1, 2)
    ax.plot(np.repeat(sg, inner.shape[1]) * inner[..., 0].ravel(), inner[..., 1].ravel(), "s", ms=2.5, color="k",
            label="inflection points")
    ax.plot(sg * ends[:, 0, 0], ends[:, 0, 1], "|", color="tab:brown", label="flat of bottom")
    ax.plot(sg * ends[:, -1, 0], ends[:, -1, 1], "_", color="tab:purple", label="flat of side")
    ax.set_aspect("equal")
    ax.set_xlabel("y [m] (aft body left, fore body right)")
    ax.set_ylabel("z [m]")
    ax.set_title(title or f"Feature curves — {hull.name}")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)  # off the curves
    from ...drawing import save_figure

    save_figure(fig, path, dpi=120, bbox_inches="tight")


@app.command()
def features(
    hull: Annotated[str, typer.Argument(help=f"A parent (parent:NAME or NAME: {', '.join(parent_names())}; a "
                                             "parent .json) or any hull spec (offsets .csv, mesh, builtin:…)")],
    out: Annotated[Path, typer.Option(help="Folder for features.json, contours.json and features.png")] = Path("."),
    level: Annotated[int, typer.Option(help="Levels of auxiliary apexes (1 = the patent's frame)")] = 2,
    strict: Strict = False,
) -> None:
    """Extract contour lines and feature curves (inflection, apex, auxiliary-apex lines) and plot them."""
    if not 1 <= level <= 4:
        raise HullError(f"--level {level}: expected 1 to 4")
    name = hull.removeprefix("parent:")
    if name in parent_names() or name.endswith(".json"):
        fh = load_parent(name)
    else:
        loaded = load_hull(hull)
        fh = extract_parent(loaded.sections, loaded.name, loaded.design_draft, level=level)
    from ...models import save_features

    out.mkdir(parents=True, exist_ok=True)
    save_features(fh, out / "features.json")
    write_json(out / "contours.json", {k: v for k, v in fh.contour_lines().items()})
    plot_features(fh, out / "features.png")
    console.print(f"{fh.name}: {fh.x.shape[0]} stations, {fh.n_segments} segments per frame, "
                  f"{int(np.asarray(fh.real).sum())} real segments", soft_wrap=True)
    for name in ("features.json", "contours.json", "features.png"):
        wrote(out / name)


@app.command()
def deform(
    parent: Annotated[str, typer.Argument(help=f"Parent (parent:NAME or NAME: {', '.join(parent_names())}; "
                                               "a parent .json; or any hull spec a run config's parent takes)")],
    params: Annotated[Path, typer.Argument(help="Design TOML: [[apex_move]], [[distribution]], [[contour_edit]] "
                                                "(the fields and defaults of a run config's [design])")],
    out: Annotated[Path, typer.Option(help=f"Output mesh (.{', .'.join(EXPORT_FORMATS)})")] = Path("hull.stl"),
    draft: Annotated[float | None, typer.Option(help="Draft for the report [m] (default: the parent's)")] = None,
    strict: Strict = False,
) -> None:
    """Deform a parent by apex-line moves (claim 5), distributions (claim 7) and contour edits; write a mesh."""
    if out.suffix.lower().lstrip(".") not in EXPORT_FORMATS:
        raise HullError(f"--out {out}: unknown mesh format {out.suffix!r}; expected .{', .'.join(EXPORT_FORMATS)}")
    if not params.is_file():
        raise HullError(f"{params}: no such design file")
    model, p, _ = read_design(params, parent, draft)
    sec = check_design(model, p)
    t = draft if draft is not None else model.hull.design_draft
    if t is not None:
        hydro = eqx.filter_jit(hydrostatics)  # one program for both (a warm call loads it from the cache)
        before, after = hydro(model.hull.sections(), t), hydro(sec, t)
        for key, label in (("volume", "∇ [m³]"), ("cb", "Cb"), ("lcb_pct", "LCB [% Lpp fwd of midship]")):
            console.print(f"{label:28s} {float(getattr(before, key)):12.4f} → {float(getattr(after, key)):12.4f}",
                          markup=False)  # "[m³]" is no style tag
    written = write_hull_file(sec, out, t)
    wrote(out, f"{written.summary()}; read back")
