"""The lines plan on a standard sheet at true size: ISO A3 (420 × 297 mm) or A1 (841 × 594 mm), landscape,
with ISO 5457's borders (20 mm at the left, 10 mm elsewhere), the sheer and half-breadth plans at one standard
scale 1:N — the largest at which they fit — the body plan at the same or a larger standard scale where the sheet
has room, each view's scale in its title, and a title block (ISO 7200's width, 180 mm) with the particulars, the
scales, the date and hullopt's version; saved as PNG (at ``dpi``), SVG (texts kept as text) or PDF, the page
exactly the sheet, so that a print at 100 % measures true to scale.

Layout: the sheer plan at the top, the half-breadth plan under it (stations one above the other), the body
plan at the bottom left, the notes that define the lines and the title block with the key of the lines and a
scale bar at the bottom right. Everything is placed in millimetres of paper: one axes spans the sheet, 1 data
unit = 1 mm.
"""

from __future__ import annotations

import datetime
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import HullError
from ._dxf import write_lines_dxf
from ._grid import round_step
from ._lines import LinesPlan, legible_labels, plan_labels, text_box, thin_labels, view_bounds
from ._save import save_figure

#: The formats of a lines plan.
LINES_FORMATS = ("png", "svg", "pdf", "dxf")
#: Sheet sizes, landscape, ``(width, height)`` [mm].
SHEETS = {"A3": (420.0, 297.0), "A1": (841.0, 594.0)}
#: Standard scales 1:N: ISO 5455's 1, 2, 5 series with the 1.5, 2.5, 3, 4 and 7.5 of ship drawings.
SCALES = tuple(sorted(m * 10.0**k for k in range(0, 6) for m in (1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 7.5)))
BORDER = (20.0, 10.0, 10.0, 10.0)  # left, right, bottom, top [mm] (ISO 5457)
GAP = 6.0  # between the views [mm]
BLOCK = (180.0, 52.0)  # title block with the key [mm]
VIEWS = ("sheer", "half_breadth", "body")
TITLES = {"sheer": "SHEER PLAN", "half_breadth": "HALF-BREADTH PLAN", "body": "BODY PLAN"}
# room around each view's lines for its labels and title: left, right, bottom, top [mm]
MARGINS = {"sheer": (2.0, 11.0, 4.5, 9.0), "half_breadth": (2.0, 11.0, 4.5, 5.5), "body": (9.0, 6.0, 4.5, 9.0)}
TEXT_PT = 7.0  # labels: 1.8 mm capitals (ISO 3098)
STYLE = {
    "grid": dict(color="0.72", lw=0.35),
    "station": dict(color="tab:blue", lw=0.6),
    "waterline": dict(color="tab:green", lw=0.6),
    "buttock": dict(color="tab:red", lw=0.6),
    "diagonal": dict(color="darkorange", lw=0.6),
    "dwl": dict(color="tab:purple", lw=1.0, ls=(0, (8, 2, 1.5, 2))),
    "outline": dict(color="black", lw=1.1),
}
KEY = (("station", "stations"), ("waterline", "waterlines"), ("dwl", "DWL"), ("buttock", "buttocks"),
       ("diagonal", "diagonals"), ("outline", "profile, deck at side"))
MM_PER_PT = 25.4 / 72.0


@dataclass(frozen=True)
class SheetLayout:
    """The views placed on a sheet: ``size`` ``(width, height)`` [mm]; the plans (sheer and half-breadth) at
    1:``scale``, the body plan at 1:``body_scale`` (the same, or larger where the sheet has room: a yard lofts the
    frames from it); each view's ``origins[view]`` [mm] (paper = origin + model [m] · 1000/N) and its
    ``boxes[view]`` ``(x, y, w, h)`` [mm] with the room for its labels; the title block ``block`` ``(x, y, w, h)``
    [mm]."""

    sheet: str
    size: tuple[float, float]
    scale: float
    body_scale: float
    origins: dict
    boxes: dict
    block: tuple[float, float, float, float]

    def factor(self, view: str) -> float:
        """Millimetres of paper per metre of hull in ``view``."""
        return 1000.0 / (self.body_scale if view == "body" else self.scale)

    def place(self, view: str, pts: np.ndarray) -> np.ndarray:
        """Points ``(k, 2)`` [m] of ``view`` on the paper [mm]."""
        return np.asarray(self.origins[view]) + np.asarray(pts, float) * self.factor(view)


def _box(bounds: tuple, view: str, scale: float) -> tuple[float, float]:
    """Width and height [mm] of ``view`` with its labels' room at 1:``scale``."""
    m = MARGINS[view]
    k = 1000.0 / scale
    return (bounds[1] - bounds[0]) * k + m[0] + m[1], (bounds[3] - bounds[2]) * k + m[2] + m[3]


def _fit(plan: LinesPlan, sheet: str, scale: float) -> SheetLayout | None:
    """The layout with the plans at 1:``scale`` — the body plan at the largest standard scale, not smaller than
    theirs, that fits left of the title block (or above it) — or None when the plans do not fit on ``sheet``."""
    w_sheet, h_sheet = SHEETS[sheet]
    left, right, bottom, top = BORDER
    width, height = w_sheet - left - right, h_sheet - bottom - top
    bounds = {v: view_bounds(getattr(plan, v)) for v in VIEWS}
    sheer, half = _box(bounds["sheer"], "sheer", scale), _box(bounds["half_breadth"], "half_breadth", scale)
    bw, bh = BLOCK
    room = height - sheer[1] - half[1] - 2 * GAP  # for the bottom row: the body plan and the title block
    if max(sheer[0], half[0], bw) > width:
        return None
    body_scale, beside = None, True
    for n in (n for n in SCALES if n <= scale):
        body = _box(bounds["body"], "body", n)
        if body[0] + GAP + bw <= width and max(body[1], bh) <= room:
            body_scale = n
            break
    if body_scale is None:  # the body plan above the title block, at the plans' scale
        body, body_scale, beside = _box(bounds["body"], "body", scale), scale, False
        if body[0] > width or body[1] + GAP + bh > room:
            return None
    row = max(body[1], bh) if beside else body[1] + GAP + bh
    slack = (room - row) / 3.0  # shared by the top and the two gaps
    x_left = left + 0.5 * (width - max(sheer[0], half[0]))
    boxes = {"sheer": (x_left, bottom + height - slack - sheer[1], *sheer)}
    boxes["half_breadth"] = (x_left, boxes["sheer"][1] - GAP - slack - half[1], *half)
    boxes["body"] = (left, bottom if beside else bottom + bh + GAP, *body)
    block = (w_sheet - right - bw, bottom, bw, bh)
    layout = SheetLayout(sheet, (w_sheet, h_sheet), scale, body_scale, {}, boxes, block)
    for v in VIEWS:
        k = layout.factor(v)
        layout.origins[v] = (boxes[v][0] + MARGINS[v][0] - bounds[v][0] * k,
                             boxes[v][1] + MARGINS[v][2] - bounds[v][2] * k)
    return layout


def layout_sheet(plan: LinesPlan, sheet: str = "A3") -> SheetLayout:
    """Place the views on ``sheet`` at the largest standard scale (the smallest N of :data:`SCALES`) at which they
    fit with their labels and the title block.

    Parameters
    ----------
    plan : LinesPlan
        The lines plan (:func:`~._lines.lines_plan`).
    sheet : str
        ``A3`` or ``A1`` (:data:`SHEETS`).

    Returns
    -------
    SheetLayout
        The scale and where each view, its labels and the title block go [mm].

    Raises
    ------
    HullError
        For an unknown sheet, or a hull that fits at none of the scales.
    """
    if sheet not in SHEETS:
        raise HullError(f"sheet {sheet!r}: expected one of {', '.join(SHEETS)}")
    for scale in SCALES:
        layout = _fit(plan, sheet, scale)
        if layout is not None:
            return layout
    raise HullError(f"the lines plan of {plan.name or 'this hull'} fits on {sheet} at none of the scales 1:1 … "
                    f"1:{SCALES[-1]:g}")


def package_version() -> str:
    """hullopt's version from the installed package's metadata ('unknown' when it is not installed)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("hullopt")
    except PackageNotFoundError:
        return "unknown"


def title_block(plan: LinesPlan, layout: SheetLayout | None = None, date: datetime.date | None = None
                ) -> list[tuple[str, str]]:
    """The title block's fields ``(name, value)``, first the title: the ship, Lpp, B, T, Δ and Cb at T, the
    scale, the sheet, the stations and waterlines, the date and the program (hullopt and its version).

    Parameters
    ----------
    plan : LinesPlan
        The lines plan with its particulars.
    layout : SheetLayout or None
        Its sheet and scale (:func:`layout_sheet`); None: a drawing at full scale (DXF), no sheet.
    date : datetime.date or None
        The drawing's date; None: today.

    Returns
    -------
    list of (str, str)
        ``[("Lines plan", name), ("Lpp", "355.000 m"), …]``; ``—`` where a particular is not known.
    """
    def m(v):
        return "—" if v is None else f"{v:.3f} m"

    n = plan.stations
    on_sheet = [("Scale", "1:1 (full scale)")]
    if layout is not None:
        body = "" if layout.body_scale == layout.scale else f"; body plan 1:{layout.body_scale:g}"
        w, h = layout.size
        on_sheet = [("Scale", f"1:{layout.scale:g}{body}"), ("Sheet", f"{layout.sheet} ({w:g} × {h:g} mm)")]
    delta = "—" if plan.displacement is None else f"{plan.displacement:,.0f} t (ρ = 1.025 t/m³)".replace(",", " ")
    return [
        ("Lines plan", plan.name or "—"),
        ("Lpp", m(plan.lpp)),
        ("B (moulded)", m(plan.beam)),
        ("T (DWL)", m(plan.draft)),
        ("Δ at T", delta),
        ("Cb at T", "—" if plan.cb is None else f"{plan.cb:.3f}"),
        *on_sheet,
        ("Stations", f"0 (AP) … {n} (FP), {plan.lpp / n:.3f} m apart"),
        ("Waterlines", f"every {plan.spacing:g} m; ¼ and ½ over the baseline"),
        ("Date", (date or datetime.date.today()).isoformat()),
        ("Drawn by", f"hullopt {package_version()}; dimensions in m"),
    ]


def _text_box(lab, p: np.ndarray) -> np.ndarray:
    """The box ``(x0, y0, x1, y1)`` [mm] a label's text takes at ``p`` [mm] (:func:`~._lines.text_box`)."""
    return text_box(lab, p, TEXT_PT * MM_PER_PT)


def _legible(plan: LinesPlan, layout: SheetLayout) -> list[tuple]:
    """The labels (:func:`~._lines.plan_labels`) that stay legible on the sheet, each with its place [mm]: the
    waterlines' and stations' every k-th where they lie closer than a label (:func:`~._lines.thin_labels`); then
    the body plan's station numbers (0, 5, 10 … first, then the even ones) and the buttocks' names, each where it
    clears the labels kept before it (:func:`~._lines.legible_labels`)."""
    text_mm = TEXT_PT * MM_PER_PT
    kept: list = []
    for view in VIEWS:
        f = layout.factor(view)
        mine = [lab for lab in plan_labels(plan) if lab.view == view]
        kept += thin_labels(mine, plan, f, text_mm)
    return legible_labels(kept, lambda lab: layout.place(lab.view, np.array([lab.at]))[0]
                          + np.asarray(lab.offset) * text_mm, text_mm)


def _draw_block(ax, plan: LinesPlan, layout: SheetLayout) -> None:
    """The title block at the bottom right: the key of the lines and a scale bar of the plans over the fields."""
    from matplotlib.patches import Rectangle

    x, y, w, h = layout.block
    fields = title_block(plan, layout)
    kw = dict(fontsize=6.0, color="0.3", va="center")
    ax.add_patch(Rectangle((x, y), w, h, fill=False, lw=1.4, ec="black"))
    key_h, title_h, row_h = 10.0, 9.0, 5.5
    y_key = y + h - key_h
    ax.plot([x, x + w], [y_key, y_key], color="black", lw=0.7)
    for i, (kind, name) in enumerate(KEY):  # the key: a sample of each line
        cx = x + 3.0 + (i % 3) * 34.0
        cy = y_key + key_h - 3.0 - (i // 3) * 4.0
        ax.plot([cx, cx + 8.0], [cy, cy], **STYLE[kind])
        ax.text(cx + 10.0, cy, name, **kw)
    bar_m = round_step(40.0 * layout.scale / 1000.0, 1)  # a scale bar of a round length, 20 to 55 mm
    bar_m /= 2.0 if bar_m * 1000.0 / layout.scale > 55.0 else 1.0
    bar = bar_m * 1000.0 / layout.scale
    bx, by = x + w - 5.0 - bar, y_key + 3.0
    for i in range(4):
        ax.add_patch(Rectangle((bx + i * bar / 4, by), bar / 4, 1.2, fc="black" if i % 2 == 0 else "white",
                               ec="black", lw=0.4))
    for frac in (0.0, 0.5, 1.0):
        ax.text(bx + frac * bar, by + 1.7, f"{frac * bar_m:g}" + (" m" if frac == 1.0 else ""), fontsize=5.5,
                ha="center", va="bottom")
    ax.text(bx - 2.0, by + 0.6, f"1:{layout.scale:g}", fontsize=5.5, ha="right", va="center")
    y_title = y_key - title_h
    ax.plot([x, x + w], [y_title, y_title], color="black", lw=0.7)
    (head, name), rest = fields[0], fields[1:]
    ax.text(x + 3.0, y_title + 0.5 * title_h, f"{head.upper()} — {name}", fontsize=12.0, fontweight="bold",
            va="center")
    half = len(rest) // 2 + len(rest) % 2
    for i, (field, value) in enumerate(rest):
        col, r = divmod(i, half)
        fx, fy = x + col * w / 2, y_title - (r + 0.5) * row_h
        ax.text(fx + 2.0, fy, field, **kw)
        ax.text(fx + 21.0, fy, value, fontsize=7.5, va="center")
        if r:
            ax.plot([fx, fx + w / 2], [fy + 0.5 * row_h] * 2, color="0.6", lw=0.3)
    ax.plot([x + w / 2] * 2, [y, y_title], color="black", lw=0.7)


def notes(plan: LinesPlan) -> list[str]:
    """The notes that define the plan's lines, so that a yard draws them again: stations, waterlines, buttocks,
    diagonals (where each meets the centreline and its angle), the body plan's sides."""
    out = [f"Stations 0 (AP) … {plan.stations} (FP), {plan.lpp / plan.stations:.3f} m apart; waterlines every "
           f"{plan.spacing:g} m above the baseline, with the ¼ and ½ waterlines."]
    if plan.buttocks:
        out.append("Buttocks " + ", ".join(f"{b:g}" for b in plan.buttocks) + " m from the centreline.")
    for d in plan.diagonals:
        angle = math.degrees(math.atan2(-d.direction[1], d.direction[0]))
        out.append(f"Diagonal {d.name}: through the centreline {d.z0:.3f} m above the baseline, {angle:.1f}° below "
                   "the horizontal, outward.")
    out.append("Body plan: aft body left, fore body right; diagonals developed below the centreline of the "
               "half-breadth plan.")
    return out


def _draw_notes(ax, plan: LinesPlan, layout: SheetLayout) -> None:
    """The notes (:func:`notes`) over the title block, where the sheet has room for them."""
    x, y, _, h = layout.block
    lines = notes(plan)
    line_h = 3.4
    top = y + h + 3.0 + line_h * (len(lines) + 1)
    body = layout.boxes["body"]
    half = layout.boxes["half_breadth"]
    if body[0] + body[2] > x - 2.0 or top > half[1] - 2.0:
        return
    ax.text(x, top, "NOTES", fontsize=7.5, fontweight="bold", va="top")
    for i, line in enumerate(lines):
        ax.text(x, top - line_h * (i + 1), f"{i + 1}. {line}", fontsize=6.0, va="top")


def plot_lines(plan: LinesPlan, path: str | os.PathLike, sheet: str = "A3", dpi: int = 200) -> Path:
    """Draw the lines plan on ``sheet`` at true size (:func:`layout_sheet`) and save it as PNG, SVG or PDF (by
    the extension): the page is the sheet, ``W × H`` mm (a PNG ``W/25.4 · dpi`` pixels wide).

    Lines: stations, waterlines, buttocks, diagonals (straight in the body plan, developed below the centreline
    of the half-breadth plan), the DWL dash-dotted, the profile and the deck at side heavy, the grid grey; labels:
    station numbers, AP and FP, waterline heights (every one, or every k-th where they lie closer than a label
    on paper), ``DWL T = … m``, buttocks and diagonals by name; the title block with the particulars and the
    scale, the key and a scale bar.

    Parameters
    ----------
    plan : LinesPlan
        The lines plan (:func:`~._lines.lines_plan`).
    path : str or os.PathLike
        The figure file; its suffix picks the format (PNG, SVG, PDF).
    sheet : str
        ``A3`` (default) or ``A1``.
    dpi : int
        Resolution of a PNG [dots per inch].

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    layout = layout_sheet(plan, sheet)
    w, h = layout.size
    with plt.rc_context({"svg.fonttype": "none", "pdf.fonttype": 42}):
        fig = plt.figure(figsize=(w / 25.4, h / 25.4))
        ax = fig.add_axes((0.0, 0.0, 1.0, 1.0))
        ax.set_xlim(0.0, w)
        ax.set_ylim(0.0, h)
        ax.set_axis_off()
        left, right, bottom, top = BORDER
        ax.add_patch(Rectangle((left, bottom), w - left - right, h - bottom - top, fill=False, lw=2.0, ec="black"))
        for view in VIEWS:
            curves = getattr(plan, view)
            for kind in STYLE:  # the grid under the lines, the outline on top
                for c_kind, _, pts in curves:
                    if c_kind == kind:
                        q = layout.place(view, pts)
                        ax.plot(q[:, 0], q[:, 1], solid_capstyle="butt", **STYLE[kind])
            bx, by, bw, bh = layout.boxes[view]
            scale = layout.body_scale if view == "body" else layout.scale
            ax.text(bx + bw / 2, by + bh - 0.5, f"{TITLES[view]}  1:{scale:g}", fontsize=9.0, fontweight="bold",
                    ha="center", va="top")
        for lab, p in _legible(plan, layout):
            box = dict(boxstyle="square,pad=0.1", fc="white", ec="none") if lab.kind in ("dwl", "buttock", "diagonal") \
                and lab.view != "body" else None
            color = STYLE["dwl"]["color"] if lab.kind == "dwl" else "0.15"
            ax.text(p[0], p[1], lab.text, fontsize=TEXT_PT, ha=lab.ha, va=lab.va, color=color, bbox=box)
        _draw_block(ax, plan, layout)
        _draw_notes(ax, plan, layout)
        return save_figure(fig, path, dpi=dpi)


def save_lines(plan: LinesPlan, path: str | os.PathLike, sheet: str = "A3", dpi: int = 200) -> Path:
    """Save the lines plan by the file's extension: .png, .svg, .pdf (on ``sheet`` at true size, :func:`plot_lines`)
    or .dxf (full scale in metres, :func:`~._dxf.write_lines_dxf`, with the title block's fields).

    Parameters
    ----------
    plan : LinesPlan
        The lines plan (:func:`~._lines.lines_plan`).
    path : str or os.PathLike
        The file; its suffix picks the format (one of ``LINES_FORMATS``).
    sheet : str
        ``A3`` or ``A1`` for a PNG, SVG or PDF.
    dpi : int
        Resolution of a PNG [dots per inch].

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    HullError
        For an unknown suffix or sheet.
    """
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in LINES_FORMATS:
        raise HullError(f"{path}: unknown drawing format {path.suffix!r}; expected one of .{', .'.join(LINES_FORMATS)}")
    if fmt == "dxf":
        return write_lines_dxf(plan, path, title_block(plan))
    return plot_lines(plan, path, sheet, dpi)
