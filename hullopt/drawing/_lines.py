"""The lines plan: body plan, half-breadth plan and sheer (profile) plan with stations, waterlines and
buttocks (seed 003 §3.1), to PNG/SVG (matplotlib, Agg) and DXF (ezdxf).

The curves are cut from the sections (static preprocessing, numpy): stations are the sections nearest to
the ten equal divisions of Lpp; a waterline is the outermost crossing of each section with ``z = const``; a
buttock is the lowest crossing of each section with ``y = const``. Each view is a list of polylines in its
own 2-D coordinates (m), which both back ends draw:

* sheer plan ``(x, z)``: buttocks, the profile (keel and deck line), station and waterline grid;
* half-breadth plan ``(x, y)``: waterlines, the deck line, station and buttock grid;
* body plan ``(y, z)``: forebody stations on the right (y > 0), afterbody on the left (y < 0).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import HullError
from ..geometry import Sections, atomic_write_bytes
from ._save import save_figure

LINES_FORMATS = ("png", "svg", "pdf", "dxf")


@dataclass
class LinesPlan:
    """Polylines of the three views, each ``(kind, label, points (k, 2))``; ``kind`` is one of
    ``station``, ``waterline``, ``buttock``, ``outline`` or ``grid``. ``extent`` the hull's
    ``(x_min, x_max, half_breadth, z_min, z_max)`` [m]."""

    name: str
    sheer: list = field(default_factory=list)
    half_breadth: list = field(default_factory=list)
    body: list = field(default_factory=list)
    extent: tuple = ()


def _crossings(p0: np.ndarray, p1: np.ndarray, axis: int, level: float) -> tuple[np.ndarray, np.ndarray]:
    """Edges ``p0 → p1`` ((..., 2) arrays) crossing ``coord[axis] = level``: mask and the other coordinate."""
    a, b = p0[..., axis], p1[..., axis]
    hit = ((a - level) * (b - level) < 0) | (a == level) | (b == level)
    den = np.where(hit, b - a, 1.0)
    t = np.where(hit, (level - a) / den, 0.0)
    other = p0[..., 1 - axis] + t * (p1[..., 1 - axis] - p0[..., 1 - axis])
    return hit, other


def _nan_runs(x: np.ndarray, v: np.ndarray) -> list[np.ndarray]:
    """Split a curve at NaNs into runs of at least 2 points."""
    ok = np.isfinite(v)
    runs, start = [], None
    for i, good in enumerate(np.append(ok, False)):
        if good and start is None:
            start = i
        elif not good and start is not None:
            if i - start >= 2:
                runs.append(np.column_stack([x[start:i], v[start:i]]))
            start = None
    return runs


def lines_plan(sections: Sections, name: str = "", n_waterlines: int = 8, n_buttocks: int = 4,
               waterlines=None, buttocks=None) -> LinesPlan:
    """Cut the lines plan from ``sections``: stations 0…10, waterlines (default ``n_waterlines`` equally
    spaced from the keel to the lowest deck edge) and buttocks (default ``n_buttocks`` equally spaced
    inside the largest half-breadth)."""
    x = np.asarray(sections.x, dtype=float)
    yz = np.asarray(sections.yz, dtype=float)
    lpp = float(sections.lpp)
    half, zmin, zmax = float(yz[..., 0].max()), float(yz[..., 1].min()), float(yz[..., 1].max())
    deck_z = yz[:, -1, 1]
    if waterlines is None:
        top = float(np.min(deck_z[yz[:, -1, 0] > 0.05 * half])) if np.any(yz[:, -1, 0] > 0.05 * half) else zmax
        waterlines = np.linspace(zmin, top, n_waterlines + 1)[1:]
    if buttocks is None:
        buttocks = np.linspace(0.0, half, n_buttocks + 2)[1:-1]
    waterlines, buttocks = np.asarray(waterlines, float), np.asarray(buttocks, float)
    plan = LinesPlan(name=name, extent=(float(x.min()), float(x.max()), half, zmin, zmax))
    p0, p1 = yz[:, :-1], yz[:, 1:]

    # stations: the sections nearest to the ten divisions of Lpp (and the ends of the hull)
    targets = np.arange(11) * lpp / 10.0
    idx = sorted({int(np.argmin(np.abs(x - t))) for t in targets})
    for i in idx:
        label = f"{x[i] / lpp * 10:.3g}"
        sign = 1.0 if x[i] >= 0.5 * lpp else -1.0
        plan.body.append(("station", label, yz[i] * np.array([sign, 1.0])))
        for view, pts in (("sheer", [[x[i], zmin], [x[i], zmax]]), ("half_breadth", [[x[i], 0.0], [x[i], half]])):
            getattr(plan, view).append(("grid", label, np.array(pts)))

    for z in waterlines:
        hit, y = _crossings(p0, p1, 1, z)
        yw = np.where(hit.any(axis=1), np.max(np.where(hit, y, -np.inf), axis=1), np.nan)
        for run in _nan_runs(x, yw):
            plan.half_breadth.append(("waterline", f"{z:.3g}", run))
        plan.sheer.append(("grid", f"WL {z:.3g}", np.array([[x.min(), z], [x.max(), z]])))
        plan.body.append(("grid", f"WL {z:.3g}", np.array([[-half, z], [half, z]])))
    for yb in buttocks:
        hit, z = _crossings(p0, p1, 0, yb)
        zb = np.where(hit.any(axis=1), np.min(np.where(hit, z, np.inf), axis=1), np.nan)
        for run in _nan_runs(x, zb):
            plan.sheer.append(("buttock", f"{yb:.3g}", run))
        plan.half_breadth.append(("grid", f"BL {yb:.3g}", np.array([[x.min(), yb], [x.max(), yb]])))
        for s in (-1.0, 1.0):
            plan.body.append(("grid", f"BL {yb:.3g}", np.array([[s * yb, zmin], [s * yb, zmax]])))

    # outlines: profile (lowest point and deck edge of each section) and the deck line in plan
    off = yz[..., 0] > 1e-2 * half  # the profile: lowest point off the centreline (so the stern shows)
    keel = np.where(off.any(axis=1), np.min(np.where(off, yz[..., 1], np.inf), axis=1), np.nan)
    for run in _nan_runs(x, keel):
        plan.sheer.append(("outline", "keel", run))
    plan.sheer.append(("outline", "deck", np.column_stack([x, deck_z])))
    plan.half_breadth.append(("outline", "deck", np.column_stack([x, yz[:, -1, 0]])))
    plan.body.append(("outline", "centreline", np.array([[0.0, zmin], [0.0, zmax]])))
    return plan


_STYLE = {
    "station": dict(color="tab:blue", lw=0.9),
    "waterline": dict(color="tab:green", lw=0.9),
    "buttock": dict(color="tab:red", lw=0.9),
    "outline": dict(color="black", lw=1.3),
    "grid": dict(color="0.75", lw=0.5),
}


def _draw(ax, curves, title):
    for kind, _, pts in curves:
        ax.plot(pts[:, 0], pts[:, 1], **_STYLE[kind])
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9, loc="left")
    ax.tick_params(labelsize=7)


def plot_lines(plan: LinesPlan, path: str | os.PathLike) -> Path:
    """Draw the three views on one sheet (sheer plan above the half-breadth plan, body plan to the right)
    and save it as PNG, SVG or PDF (by the extension)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path = Path(path)
    x0, x1, half, z0, z1 = plan.extent
    length, height = x1 - x0, z1 - z0
    # the plans share one scale; the body plan is drawn larger (its own scale), as on a lines sheet
    fig_w, body_frac = 16.0, 0.25
    left_w = fig_w * (1.0 - body_frac)
    left_h = left_w * (height + half) / length
    body_h = fig_w * body_frac * height / (2 * half)
    fig = plt.figure(figsize=(fig_w, max(left_h * 1.25, body_h) + 1.2))
    gs = fig.add_gridspec(2, 2, width_ratios=[1.0 - body_frac, body_frac], height_ratios=[height, half],
                          wspace=0.1, hspace=0.3)
    _draw(fig.add_subplot(gs[0, 0]), plan.sheer, "Sheer plan (buttocks)")
    _draw(fig.add_subplot(gs[1, 0]), plan.half_breadth, "Half-breadth plan (waterlines)")
    _draw(fig.add_subplot(gs[:, 1]), plan.body, "Body plan (aft | fore)")
    fig.suptitle(f"Lines plan — {plan.name}" if plan.name else "Lines plan", fontsize=11)
    from matplotlib.lines import Line2D

    fig.legend([Line2D([], [], **_STYLE[k]) for k in ("station", "waterline", "buttock")],
               ["stations", "waterlines", "buttocks"], loc="lower right", fontsize=8, ncol=3)
    return save_figure(fig, path, dpi=150)


def write_lines_dxf(plan: LinesPlan, path: str | os.PathLike) -> Path:
    """Write the three views to a DXF (model space, metres): sheer plan at the origin, half-breadth plan
    below it (y downward), body plan to the right; one layer per kind of line."""
    import io

    import ezdxf

    x0, x1, half, z0, z1 = plan.extent
    gap = 0.05 * (x1 - x0)
    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.M
    colors = {"station": 5, "waterline": 3, "buttock": 1, "outline": 7, "grid": 8}
    for kind, c in colors.items():
        doc.layers.add(kind.upper(), color=c)
    msp = doc.modelspace()
    placements = (
        (plan.sheer, lambda p: p),
        (plan.half_breadth, lambda p: np.column_stack([p[:, 0], z0 - gap - p[:, 1]])),
        (plan.body, lambda p: np.column_stack([p[:, 0] + x1 + gap + half, p[:, 1]])),
    )
    for curves, place in placements:
        for kind, _, pts in curves:
            msp.add_lwpolyline([tuple(map(float, q)) for q in place(pts)], dxfattribs={"layer": kind.upper()})
    buf = io.StringIO()
    doc.write(buf)
    atomic_write_bytes(path, buf.getvalue().encode())
    return Path(path)


def save_lines(plan: LinesPlan, path: str | os.PathLike) -> Path:
    """Save the lines plan by the file's extension: .png, .svg, .pdf (matplotlib) or .dxf (ezdxf)."""
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in LINES_FORMATS:
        raise HullError(f"{path}: unknown drawing format {path.suffix!r}; expected one of .{', .'.join(LINES_FORMATS)}")
    return write_lines_dxf(plan, path) if fmt == "dxf" else plot_lines(plan, path)
