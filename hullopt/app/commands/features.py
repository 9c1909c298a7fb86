"""``hullopt features`` (contour lines and feature curves of a hull) and ``hullopt deform`` (a parent and a
design TOML → a deformed hull)."""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ...errors import HullError
from ...geometry import EXPORT_FORMATS
from ...hydro import hydrostatics
from ...models import (ApexMove, ContourEdit, Distribution, FeatureParams, check_design, extract_parent,
                       feature_model, load_parent, parent_names)
from .._app import app
from ..hulls import load_hull
from ..output import console, write_hull_file, write_json

_KEYS = {
    "apex_move": ({"segment", "x_fixed1", "x_moved", "x_fixed2", "d"}, {"profile"}),
    "distribution": ({"x_a", "x_b", "c"}, {"curves"}),
    "contour_edit": ({"line", "x_a", "x_b", "amplitude"}, {"shape"}),
}


def _items(cfg: dict, key: str, where: str) -> list[dict]:
    items = cfg.get(key, [])
    if not isinstance(items, list) or not all(isinstance(i, dict) for i in items):
        raise HullError(f"{where}: '{key}' must be a list of tables ([[{key}]])")
    need, opt = _KEYS[key]
    for k, it in enumerate(items):
        if missing := need - it.keys():
            raise HullError(f"{where}: [[{key}]] #{k + 1} misses {', '.join(sorted(missing))}")
        if unknown := it.keys() - need - opt:
            raise HullError(f"{where}: [[{key}]] #{k + 1} has unknown key {sorted(unknown)[0]!r}; expected "
                            f"{', '.join(sorted(need | opt))}")
    return items


def _number(v, what: str) -> float:
    if isinstance(v, bool) or not isinstance(v, int | float):
        raise HullError(f"{what} must be a number, got {v!r}")
    return float(v)


def read_design(path: Path, parent: str | None = None):
    """A design TOML → ``(model, params, parent name)``; :class:`HullError` naming the field on bad input."""
    try:
        cfg = tomllib.loads(path.read_text())
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise HullError(f"{path}: cannot read the design ({e})") from None
    if unknown := cfg.keys() - {"parent", *_KEYS}:
        raise HullError(f"{path}: unknown key {sorted(unknown)[0]!r}; expected parent, {', '.join(_KEYS)}")
    name = parent or cfg.get("parent")
    if not name:
        raise HullError(f"{path}: give the parent (a key 'parent = \"dtc\"' or the PARENT argument)")
    hull = load_parent(name.removeprefix("parent:"))
    moves, d = [], []
    for k, it in enumerate(_items(cfg, "apex_move", str(path))):
        w = f"{path}: [[apex_move]] #{k + 1}"
        if not isinstance(it["segment"], int):
            raise HullError(f"{w}: segment must be an integer")
        moves.append(ApexMove(it["segment"], *(_number(it[f], f"{w}: {f}") for f in ("x_fixed1", "x_moved", "x_fixed2")),
                              it.get("profile", "linear")))
        if not (isinstance(it["d"], list) and len(it["d"]) == 2):
            raise HullError(f"{w}: d must be two numbers [dy, dz] in m")
        d.append([_number(v, f"{w}: d") for v in it["d"]])
    dists, coef = [], []
    for k, it in enumerate(_items(cfg, "distribution", str(path))):
        w = f"{path}: [[distribution]] #{k + 1}"
        c = it["c"] if isinstance(it["c"], list) else [it["c"]]
        curves = it.get("curves", "all")
        dists.append(Distribution(_number(it["x_a"], f"{w}: x_a"), _number(it["x_b"], f"{w}: x_b"),
                                  curves if isinstance(curves, str) else tuple(curves), max(1, len(c))))
        coef.append([_number(v, f"{w}: c") for v in c])
    edits, amp = [], []
    for k, it in enumerate(_items(cfg, "contour_edit", str(path))):
        w = f"{path}: [[contour_edit]] #{k + 1}"
        edits.append(ContourEdit(str(it["line"]), _number(it["x_a"], f"{w}: x_a"), _number(it["x_b"], f"{w}: x_b"),
                                 it.get("shape", "bump")))
        amp.append(_number(it["amplitude"], f"{w}: amplitude"))
    model = feature_model(hull, moves, dists, edits)
    modes = max((len(c) for c in coef), default=0)
    dist = np.zeros((len(coef), modes))
    for g, c in enumerate(coef):
        dist[g, : len(c)] = c
    params = FeatureParams(np.array(d).reshape(len(d), 2), dist, np.array(amp))
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
    ax.legend(fontsize=7, loc="upper center")
    fig.savefig(path, dpi=120)
    plt.close(fig)


@app.command()
def features(
    hull: Annotated[str, typer.Argument(help=f"A parent (parent:NAME or NAME: {', '.join(parent_names())}; a "
                                             "parent .json) or any hull spec (offsets .csv, mesh, builtin:…)")],
    out: Annotated[Path, typer.Option(help="Folder for features.json, contours.json and features.png")] = Path("."),
    level: Annotated[int, typer.Option(help="Levels of auxiliary apexes (1 = the patent's frame)")] = 2,
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
                  f"{int(np.asarray(fh.real).sum())} real segments; wrote features.json, contours.json, features.png "
                  f"to {out}")


@app.command()
def deform(
    parent: Annotated[str, typer.Argument(help=f"Parent (parent:NAME or NAME: {', '.join(parent_names())}; "
                                               "or a parent .json)")],
    params: Annotated[Path, typer.Argument(help="Design TOML: [[apex_move]], [[distribution]], [[contour_edit]]")],
    out: Annotated[Path, typer.Option(help=f"Output mesh (.{', .'.join(EXPORT_FORMATS)})")] = Path("hull.stl"),
    draft: Annotated[float | None, typer.Option(help="Draft for the report [m] (default: the parent's)")] = None,
) -> None:
    """Deform a parent by apex-line moves (claim 5), distributions (claim 7) and contour edits; write a mesh."""
    if out.suffix.lower().lstrip(".") not in EXPORT_FORMATS:
        raise HullError(f"--out {out}: unknown mesh format {out.suffix!r}; expected .{', .'.join(EXPORT_FORMATS)}")
    if not params.is_file():
        raise HullError(f"{params}: no such design file")
    model, p, _ = read_design(params, parent)
    sec = check_design(model, p)
    t = draft if draft is not None else model.hull.design_draft
    if t is not None:
        before, after = hydrostatics(model.hull.sections(), t), hydrostatics(sec, t)
        for key, label in (("volume", "∇ [m³]"), ("cb", "Cb"), ("lcb_pct", "LCB [% Lpp fwd of midship]")):
            console.print(f"{label:28s} {float(getattr(before, key)):12.4f} → {float(getattr(after, key)):12.4f}",
                          markup=False)  # "[m³]" is no style tag
    written = write_hull_file(sec, out, t)
    console.print(f"wrote {out} ({written.summary()}; read back)", soft_wrap=True)
