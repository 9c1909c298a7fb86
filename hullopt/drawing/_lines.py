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

from .._types import Lengths, Waterlines
from ..errors import HullError
from ..geometry import Sections, atomic_write_bytes, sections_at
from ._save import save_figure

LINES_FORMATS = ("png", "svg", "pdf", "dxf")


@dataclass
class LinesPlan:
    """Polylines of the three views, each ``(kind, label, points (k, 2))``; ``kind`` is one of
    ``station``, ``waterline``, ``buttock``, ``outline``, ``dwl`` (the design waterline) or ``grid``.
    ``extent`` the hull's ``(x_min, x_max, half_breadth, z_min, z_max)`` [m]; ``lpp``, ``beam`` (moulded,
    2 × the largest half-breadth) and ``draft`` (the DWL, None when not given) [m] for the title block."""

    name: str
    sheer: list = field(default_factory=list)
    half_breadth: list = field(default_factory=list)
    body: list = field(default_factory=list)
    extent: tuple = ()
    lpp: float = float("nan")
    beam: float = float("nan")
    draft: float | None = None


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


def station_sections(sections: Sections, per_station: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The hull at the stations 0, 1/per_station, …, 10 (ten stations from the AP at 0 to the FP at 10), each
    half-section interpolated at its station (:func:`~hullopt.geometry.sections_at`), not the given section
    nearest it.

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    per_station : int
        Sections per station interval (2: the half stations).

    Returns
    -------
    tuple of numpy.ndarray
        ``stations (k,)`` (0 … 10), ``x (k,)`` [m from the AP] and ``yz (k, p, 2)`` [m], ``k = 10·per_station + 1``.
    """
    stations = np.arange(10 * per_station + 1) / per_station
    x = stations * float(sections.lpp) / 10.0
    return stations, x, sections_at(sections, x)


def lines_plan(sections: Sections, name: str = "", n_waterlines: int = 8, n_buttocks: int = 4,
               waterlines: Waterlines | None = None, buttocks: Lengths | None = None,
               draft: float | None = None) -> LinesPlan:
    """Cut the lines plan from ``sections``: stations 0…10, waterlines (default ``n_waterlines`` equally
    spaced from the keel to the lowest deck edge) and buttocks (default ``n_buttocks`` equally spaced
    inside the largest half-breadth); with ``draft`` [m above the baseline] the design waterline (DWL) in
    all three views.

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    name : str
        The hull's name for the title block.
    n_waterlines : int
        Number of default waterlines (when ``waterlines`` is None).
    n_buttocks : int
        Number of default buttocks (when ``buttocks`` is None).
    waterlines : (w,) array_like or None
        Waterline heights [m above the baseline]; None: the default.
    buttocks : (b,) array_like or None
        Buttock offsets [m from the centreline]; None: the default.
    draft : float or None
        Design draft [m above the baseline] for the DWL; None: no DWL.

    Returns
    -------
    LinesPlan
        The polylines of the sheer, half-breadth and body plans [m], with the extent and the particulars.
    """
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
    plan = LinesPlan(name=name, extent=(float(x.min()), float(x.max()), half, zmin, zmax), lpp=lpp,
                     beam=2.0 * half, draft=None if draft is None else float(draft))
    p0, p1 = yz[:, :-1], yz[:, 1:]

    # stations: the hull at the ten divisions of Lpp
    for k, xk, section in zip(*station_sections(sections)):
        label = f"{k:g}"
        sign = 1.0 if xk >= 0.5 * lpp else -1.0
        plan.body.append(("station", label, section * np.array([sign, 1.0])))
        for view, pts in (("sheer", [[xk, zmin], [xk, zmax]]), ("half_breadth", [[xk, 0.0], [xk, half]])):
            getattr(plan, view).append(("grid", label, np.array(pts)))

    for z in waterlines:
        hit, y = _crossings(p0, p1, 1, z)
        yw = np.where(hit.any(axis=1), np.max(np.where(hit, y, -np.inf), axis=1), np.nan)
        for run in _nan_runs(x, yw):
            plan.half_breadth.append(("waterline", f"{z:.3g}", run))
        plan.sheer.append(("grid", f"WL {z:.3g}", np.array([[x.min(), z], [x.max(), z]])))
        plan.body.append(("grid", f"WL {z:.3g}", np.array([[-half, z], [half, z]])))
    if draft is not None:
        hit, y = _crossings(p0, p1, 1, float(draft))
        yw = np.where(hit.any(axis=1), np.max(np.where(hit, y, -np.inf), axis=1), np.nan)
        for run in _nan_runs(x, yw):
            plan.half_breadth.append(("dwl", "DWL", run))
        plan.sheer.append(("dwl", "DWL", np.array([[x.min(), draft], [x.max(), draft]])))
        plan.body.append(("dwl", "DWL", np.array([[-half, draft], [half, draft]])))
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
    "dwl": dict(color="tab:purple", lw=1.4, ls="-."),
    "grid": dict(color="0.75", lw=0.5),
}

# standard drawing scales 1:N (N of one significant figure 1, 2, 2.5 or 5 times a power of ten)
_SCALES = np.array([m * 10.0**k for k in range(0, 6) for m in (1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 7.5)])


def _draw(ax, curves, title, xlabel, ylabel):
    for kind, _, pts in curves:
        ax.plot(pts[:, 0], pts[:, 1], **_STYLE[kind])
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title(title, fontsize=9, loc="left")
    ax.set_xlabel(xlabel, fontsize=8)
    ax.set_ylabel(ylabel, fontsize=8)
    ax.tick_params(labelsize=7)


def _label_grid(ax, curves, prefix, where, **kw):
    """Write the labels of the grid lines whose label starts with ``prefix`` (``"WL "``: waterlines, ``""``:
    stations) at their ``where`` end (``"end"``: the last point, ``"start"``: the first)."""
    for kind, label, pts in curves:
        if kind == "grid" and label.startswith(prefix) and (prefix or " " not in label):
            q = pts[-1] if where == "end" else pts[0]
            ax.annotate(label.removeprefix("WL ") if prefix else label, q, fontsize=6, color="0.35",
                        annotation_clip=False, **kw)


def _paper_scale(fig, ax) -> float:
    """N of the scale 1:N at which ``ax`` is drawn on the sheet (metres of hull per metre of paper along x)."""
    fig.canvas.draw()
    paper = ax.get_window_extent().width / fig.dpi * 0.0254
    lo, hi = ax.get_xlim()
    return (hi - lo) / paper


def _set_scale(fig, axes, spans) -> float:
    """Set the limits of ``axes`` (drawn at one scale, equal aspect) to the smallest standard scale 1:N at
    which each axes holds its ``spans`` ``(x_lo, x_hi, y_lo, y_hi)`` [m], centred on them; returns N."""
    fig.canvas.draw()
    boxes = [ax.get_window_extent() for ax in axes]
    inch = 0.0254 / fig.dpi  # metres of paper per pixel
    n = max(max((b[1] - b[0]) / (box.width * inch), (b[3] - b[2]) / (box.height * inch))
            for b, box in zip(spans, boxes))
    std = float(_SCALES[np.searchsorted(_SCALES, n * (1 - 1e-9))])
    for ax, box, b in zip(axes, boxes, spans):
        xc, yc = 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3])
        w = box.width / fig.dpi * 0.0254 * std  # metres of hull across the axes at 1:std
        h = box.height / fig.dpi * 0.0254 * std
        ax.set_xlim(xc - 0.5 * w, xc + 0.5 * w)
        ax.set_ylim(yc - 0.5 * h, yc + 0.5 * h)
    return std


def _label_stations(ax, curves):
    """Station numbers above the body plan's sections, those ending at one point named once (``3–7``, ``0, 10``)."""
    tops = [(label, pts[np.argmax(pts[:, 1])]) for kind, label, pts in curves if kind == "station"]
    tol = 0.03 * max(abs(float(p[0])) for _, p in tops) + 1e-12 if tops else 0.0
    groups = []
    for label, p in tops:
        near = [g for g in groups if np.hypot(*(p - g[1])) <= tol]
        if near:
            near[0][0].append(label)
        else:
            groups.append(([label], p))
    for labels, p in groups:
        nums = [int(v) for v in labels]
        run = nums == list(range(nums[0], nums[0] + len(nums)))
        text = labels[0] if len(labels) == 1 else f"{labels[0]}–{labels[-1]}" if run else ", ".join(labels)
        ax.annotate(text, p, xytext=(0, 3), textcoords="offset points", ha="center", fontsize=6,
                    color="tab:blue")


def plot_lines(plan: LinesPlan, path: str | os.PathLike) -> Path:
    """Draw the three views on one sheet (sheer plan above the half-breadth plan, body plan to the right)
    and save it as PNG, SVG or PDF (by the extension).

    Axes in metres (x from the AP, y to port, z above the baseline); station numbers 0 (AP) … 10 (FP) under
    the sheer and half-breadth plans and above the body plan's sections; waterline heights [m] at the right of
    the sheer and body plans; the DWL (when the plan has a draft) dash-dotted; a title block with the name,
    Lpp, B, T and the scales 1:N at which the plans and the body plan are drawn on this sheet (the sheet's
    size as saved: no cropping).

    Parameters
    ----------
    plan : LinesPlan
        The lines plan (:func:`lines_plan`).
    path : str or os.PathLike
        The figure file; its suffix picks the format (PNG, SVG, PDF).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    path = Path(path)
    x0, x1, half, z0, z1 = plan.extent
    length, height = x1 - x0, z1 - z0
    # the plans share one scale; the body plan is drawn larger (its own scale), as on a lines sheet
    fig_w, body_frac = 16.0, 0.25
    left_w = fig_w * (1.0 - body_frac)
    left_h = left_w * (height + half) / length
    body_h = fig_w * body_frac * height / (2 * half)
    fig_h = max(left_h * 1.25, body_h) + 2.6
    fig = plt.figure(figsize=(fig_w, fig_h))
    gs = fig.add_gridspec(2, 2, width_ratios=[1.0 - body_frac, body_frac], height_ratios=[height, half],
                          wspace=0.12, hspace=0.45, left=0.05, right=0.97, top=0.9, bottom=1.9 / fig_h)
    sheer, plan_ax, body = fig.add_subplot(gs[0, 0]), fig.add_subplot(gs[1, 0]), fig.add_subplot(gs[:, 1])
    _draw(sheer, plan.sheer, "Sheer plan (buttocks)", "x from AP [m]", "z above base [m]")
    _draw(plan_ax, plan.half_breadth, "Half-breadth plan (waterlines)", "x from AP [m]", "y [m]")
    _draw(body, plan.body, "Body plan (aft body ← | → fore body)", "y [m]", "z above base [m]")
    # station numbers under the sheer and half-breadth plans, above the body plan's sections
    _label_grid(sheer, plan.sheer, "", "start", xytext=(0, -9), textcoords="offset points", ha="center")
    _label_grid(plan_ax, plan.half_breadth, "", "start", xytext=(0, -9), textcoords="offset points",
                ha="center")
    _label_stations(body, plan.body)
    # waterline heights at the right of the sheer and body plans
    _label_grid(sheer, plan.sheer, "WL ", "end", xytext=(3, 0), textcoords="offset points", va="center")
    _label_grid(body, plan.body, "WL ", "end", xytext=(3, 0), textcoords="offset points", va="center")
    if plan.draft is not None:
        for ax, xl in ((sheer, x0), (body, -half)):
            ax.annotate(f"DWL {plan.draft:.3g} m", (xl, plan.draft), xytext=(2, 2), textcoords="offset points",
                        fontsize=7, color="tab:purple", ha="left", va="bottom")
    mx, mz = 0.03 * length, 0.12 * height  # room for the station and waterline labels
    n_plans = _set_scale(fig, (sheer, plan_ax), ((x0 - mx, x1 + mx, z0 - mz, z1 + 0.05 * height),
                                                      (x0 - mx, x1 + mx, -0.12 * half, 1.05 * half)))
    n_body = _set_scale(fig, (body,), ((-1.15 * half, 1.35 * half, z0 - 0.05 * height, z1 + mz),))
    fig.suptitle(f"Lines plan — {plan.name}" if plan.name else "Lines plan", fontsize=12, x=0.05, ha="left")
    kinds = ["station", "waterline", "buttock"] + (["dwl"] if plan.draft is not None else [])
    names = {"station": "stations", "waterline": "waterlines", "buttock": "buttocks", "dwl": "DWL"}
    fig.legend([Line2D([], [], **_STYLE[k]) for k in kinds], [names[k] for k in kinds], loc="lower left",
               bbox_to_anchor=(0.05, 0.02), fontsize=8, ncol=len(kinds), frameon=False)
    # the title block, bottom right
    t = "—" if plan.draft is None else f"{plan.draft:.3f} m"
    rows = [("Ship", plan.name or "—"), ("Lpp", f"{plan.lpp:.3f} m"), ("B (moulded)", f"{plan.beam:.3f} m"),
            ("T (DWL)", t), ("Scale, plans", f"1:{n_plans:g}"), ("Scale, body plan", f"1:{n_body:g}"),
            ("Sheet", f"{fig_w:g} × {fig_h:.1f} in"), ("Stations", "0 AP … 10 FP"), ("Units", "m")]
    text = "\n".join(f"{k:<17}{v}" for k, v in rows)
    fig.text(0.97, 0.02, text, ha="right", va="bottom", fontsize=7.5, family="monospace", multialignment="left",
             bbox=dict(boxstyle="square,pad=0.6", fc="white", ec="black", lw=1.0))
    return save_figure(fig, path, dpi=150)


def write_lines_dxf(plan: LinesPlan, path: str | os.PathLike) -> Path:
    """Write the three views to a DXF (model space, metres): sheer plan at the origin, half-breadth plan
    below it (y downward), body plan to the right; one layer per kind of line.

    Parameters
    ----------
    plan : LinesPlan
        The lines plan (:func:`lines_plan`).
    path : str or os.PathLike
        The DXF file to write.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    import io

    import ezdxf

    x0, x1, half, z0, z1 = plan.extent
    gap = 0.05 * (x1 - x0)
    doc = ezdxf.new("R2010")
    doc.units = ezdxf.units.M
    colors = {"station": 5, "waterline": 3, "buttock": 1, "outline": 7, "dwl": 6, "grid": 8}
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
    """Save the lines plan by the file's extension: .png, .svg, .pdf (matplotlib) or .dxf (ezdxf).

    Parameters
    ----------
    plan : LinesPlan
        The lines plan (:func:`lines_plan`).
    path : str or os.PathLike
        The file; its suffix picks the format (one of ``LINES_FORMATS``).

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    HullError
        For an unknown suffix.
    """
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in LINES_FORMATS:
        raise HullError(f"{path}: unknown drawing format {path.suffix!r}; expected one of .{', .'.join(LINES_FORMATS)}")
    return write_lines_dxf(plan, path) if fmt == "dxf" else plot_lines(plan, path)
