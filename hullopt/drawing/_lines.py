"""The lines plan as a yard reads it: the sheer plan (profile and buttocks), the half-breadth plan (waterlines
above the centreline, the developed diagonals below it) and the body plan (stations: aft body left, fore body
right; the diagonals straight), cut from the sections (static preprocessing, numpy).

The ordinates are :mod:`._grid`'s: stations 0 (AP) … N (FP) equally spaced over Lpp, waterlines at a round
spacing with the DWL among them, buttocks at a round spacing, diagonals across the bilge, the deck at side
smoothed. A waterline is the outermost crossing of each section with ``z = const``, a buttock the lowest crossing
with ``y = const``, a developed diagonal the distance along the diagonal from the centreline to its outermost
crossing; the profile is the keel (the sections' lowest points), the stem and stern (the waterlines' ends on a
fine grid of heights) and the deck at side. Each view is a list of polylines in its own 2-D coordinates [m],
which the sheet (:mod:`._sheet`) and the DXF (:mod:`._dxf`) draw:

* sheer plan ``(x, z)``, half-breadth plan ``(x, y)``, body plan ``(y, z)``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .._types import Lengths, Waterlines
from ..geometry import Sections, sections_at
from ._grid import (
    Diagonal,
    buttock_offsets,
    deck_at_side,
    diagonals,
    lowest_deck,
    station_x,
    waterline_heights,
    waterline_spacing,
)
from ._offsets import half_breadths

#: The kinds of line, one DXF layer each, in drawing order.
KINDS = ("grid", "station", "waterline", "buttock", "diagonal", "dwl", "outline")


@dataclass
class LinesPlan:
    """Polylines of the three views, each ``(kind, label, points (k, 2))`` [m]; ``kind`` one of :data:`KINDS`
    (``dwl``: the design waterline; ``grid``: the stations, waterlines, buttocks, baseline and centreline where
    they are straight). The particulars for the title block: ``lpp``, ``beam`` (moulded: 2 × the largest
    half-breadth), ``draft`` (the DWL; None: none drawn) [m], ``displacement`` [t] and ``cb`` at that draft
    (None: not given), ``stations`` (intervals over Lpp), ``spacing`` (between waterlines) [m], ``buttocks`` (their
    offsets [m]) and ``diagonals`` (:class:`~._grid.Diagonal`). ``extent``
    ``(x_min, x_max, half_breadth, z_min, z_max)`` [m] of the hull."""

    name: str
    sheer: list = field(default_factory=list)
    half_breadth: list = field(default_factory=list)
    body: list = field(default_factory=list)
    extent: tuple = ()
    lpp: float = float("nan")
    beam: float = float("nan")
    draft: float | None = None
    displacement: float | None = None
    cb: float | None = None
    stations: int = 20
    spacing: float = float("nan")
    buttocks: tuple = ()
    diagonals: tuple = ()


def view_bounds(curves: list) -> tuple[float, float, float, float]:
    """``(u_min, u_max, v_min, v_max)`` [m] of a view's polylines."""
    pts = np.concatenate([c[2] for c in curves])
    return float(pts[:, 0].min()), float(pts[:, 0].max()), float(pts[:, 1].min()), float(pts[:, 1].max())


def station_sections(sections: Sections, per_station: int = 1, stations: int = 10
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The hull at the stations 0, 1/per_station, …, ``stations`` (0 at the AP, ``stations`` at the FP), each
    half-section interpolated at its station (:func:`~hullopt.geometry.sections_at`), not the given section
    nearest it.

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    per_station : int
        Sections per station interval (2: the half stations).
    stations : int
        Station intervals over Lpp (10: the stations 0…10; 20 a yard's lines plan).

    Returns
    -------
    tuple of numpy.ndarray
        ``stations (k,)`` (0 … ``stations``), ``x (k,)`` [m from the AP] and ``yz (k, p, 2)`` [m],
        ``k = stations·per_station + 1``.
    """
    numbers = np.arange(stations * per_station + 1) / per_station
    x = numbers * float(sections.lpp) / stations
    return numbers, x, sections_at(sections, x)


def _crossings(p0: np.ndarray, p1: np.ndarray, axis: int, level: float) -> tuple[np.ndarray, np.ndarray]:
    """Edges ``p0 → p1`` ((..., 2) arrays) crossing ``coord[axis] = level``: mask and the other coordinate."""
    a, b = p0[..., axis], p1[..., axis]
    hit = ((a - level) * (b - level) < 0) | (a == level) | (b == level)
    den = np.where(hit, b - a, 1.0)
    t = np.where(hit, (level - a) / den, 0.0)
    other = p0[..., 1 - axis] + t * (p1[..., 1 - axis] - p0[..., 1 - axis])
    return hit, other


def _outermost(yz: np.ndarray, axis: int, level: float, lowest: bool = False) -> np.ndarray:
    """Per section ``(n, m, 2)``: the largest (``lowest``: the smallest) other coordinate where the polyline
    crosses ``coord[axis] = level``, NaN where it does not."""
    hit, other = _crossings(yz[:, :-1], yz[:, 1:], axis, level)
    pick = np.min(np.where(hit, other, np.inf), axis=1) if lowest else np.max(np.where(hit, other, -np.inf), axis=1)
    return np.where(hit.any(axis=1), pick, np.nan)


def _nan_runs(x: np.ndarray, v: np.ndarray) -> list[np.ndarray]:
    """Split a curve at NaNs into runs of at least 2 points, ``(k, 2)`` arrays of ``(x, v)``."""
    ok = np.append(np.isfinite(v), False)
    edges = np.flatnonzero(np.diff(np.concatenate([[False], ok])))
    return [np.column_stack([x[a:b], v[a:b]]) for a, b in zip(edges[::2], edges[1::2]) if b - a >= 2]


def _buttock_runs(x: np.ndarray, yz: np.ndarray, yb: float) -> list[np.ndarray]:
    """The buttock ``y = yb`` in profile, ``(k, 2)`` runs of ``(x, z)`` [m]: its lowest crossing of each section,
    split where it misses one, and each run carried on past its last section to where the buttock plane leaves
    the hull before the next (which is narrower than ``yb``): where the sections' widest half-breadth falls to
    ``yb``, at the height of their widest point there (the deck at side, a waterline), both interpolated — not
    stopped a station short of the stem, the stern or the deck."""
    z = _outermost(yz, 0, yb, lowest=True)
    y = yz[..., 0]
    wide = y.max(axis=1)
    top = yz[np.arange(len(x)), np.argmax(y, axis=1), 1]  # the height of each section's widest point
    ok = np.append(np.isfinite(z), False)
    edges = np.flatnonzero(np.diff(np.concatenate([[False], ok])))
    runs = []
    for a, b in zip(edges[::2], edges[1::2]):  # sections a … b − 1 cross the buttock
        ends = []
        for i, j in ((a, a - 1), (b - 1, b)):  # the run's aft end, then its forward end
            if 0 <= j < len(x) and wide[j] < yb <= wide[i]:
                t = (wide[i] - yb) / (wide[i] - wide[j])
                zt = top[i] + t * (top[j] - top[i]) if wide[j] > 0.0 else top[i]  # a stem's section: no widest point
                ends.append(np.array([[x[i] + t * (x[j] - x[i]), zt]]))
            else:
                ends.append(np.empty((0, 2)))
        run = np.concatenate([ends[0], np.column_stack([x[a:b], z[a:b]]), ends[1]])
        if len(run) >= 2:
            runs.append(run)
    return runs


def developed_diagonal(yz: np.ndarray, diagonal: Diagonal) -> np.ndarray:
    """Per section ``(n, m, 2)`` [m]: the distance [m] along ``diagonal`` from the centreline to its outermost
    crossing with the section (the developed diagonal), NaN where it misses the section."""
    u = np.array(diagonal.direction)
    normal = np.array([-u[1], u[0]])
    rel = yz - np.array([0.0, diagonal.z0])
    along_normal = np.stack([rel @ u, rel @ normal], axis=-1)  # (s along the diagonal, t across it)
    s = _outermost(along_normal, 1, 0.0)
    return np.where(s >= 0.0, s, np.nan)


def _end_contour(x: np.ndarray, y: np.ndarray, z: np.ndarray) -> np.ndarray:
    """The hull's end (stem or stern) in profile, ``(k, 2)`` points ``(x, z)`` [m], from the half-breadths
    ``y (n, l)`` [m] of sections ``x (n,)`` ordered from that end inward, at heights ``z (l,)``.

    At each height the end lies beyond the outermost section with breadth (more than 1 % of the largest, so that a
    spline surface's ripples are none): the waterline is carried on to the centreline by its last two offsets, at
    most to the next section with none at all (or the last section). Along the height the
    outermost section steps from one to the next; a section where the end advances starts there (its first height
    is a point of the contour), one where it recedes ends there (its last height), one between two further out
    (a notch, the neck of a bulb) gives its middle: the contour runs through these, not along the steps."""
    has = y > 1e-2 * max(float(y.max()), 1e-12)
    rows = np.flatnonzero(has.any(axis=0))
    if len(rows) < 2:
        return np.empty((0, 2))
    i = np.argmax(has[:, rows], axis=0)  # the outermost section with breadth at each height
    inner = np.minimum(i + 1, len(x) - 1)
    yi, yn = y[i, rows], y[inner, rows]
    reach = np.where(yn > yi, np.abs(x[inner] - x[i]) * yi / np.where(yn > yi, yn - yi, 1.0), 0.0)
    index = np.arange(len(x))[:, None]
    empty = np.maximum.accumulate(np.where(y[:, rows] <= 1e-9 * float(y.max()), index, 0), axis=0)
    room = np.abs(x[empty[np.maximum(i - 1, 0), np.arange(len(rows))]] - x[i])
    xe = x[i] + np.sign(x[0] - x[-1]) * np.minimum(reach, room)
    cut = np.flatnonzero(np.diff(i)) + 1
    keep = []
    for a, b in zip(np.r_[0, cut], np.r_[cut, len(rows)]):  # each run of heights with one outermost section
        before = i[a - 1] if a else len(x)
        after = i[b] if b < len(rows) else len(x)
        if before > i[a]:
            keep.append(a)
        if after > i[a] and b - 1 != a:
            keep.append(b - 1)
        if before < i[a] and after < i[a]:
            keep.append((a + b - 1) // 2)
    keep = np.unique(keep)
    return np.column_stack([xe[keep], z[rows][keep]]) if len(keep) else np.empty((0, 2))


def _keel(x: np.ndarray, yz: np.ndarray) -> list[np.ndarray]:
    """The keel in profile: where each section ``(n, m, 2)`` leaves the centreline (the end of its first run of
    points on it, so a stern that lifts shows), split where it jumps from one piece of the hull to another (an
    aperture: steeper than 2:1); ``(k, 2)`` polylines ``(x, z)`` [m]."""
    off = yz[..., 0] > 1e-2 * yz[..., 0].max(axis=1, keepdims=True)  # of the section's own breadth
    first = np.maximum(np.argmax(off, axis=1) - 1, 0)
    keel = np.where(off.any(axis=1), yz[np.arange(len(x)), first, 1], np.nan)
    out = []
    for run in _nan_runs(x, keel):
        steep = np.abs(np.diff(run[:, 1])) > 2.0 * np.diff(run[:, 0])
        out += [piece for piece in np.split(run, np.flatnonzero(steep) + 1) if len(piece) >= 2]
    return out


def _outline(sections: Sections, stations: int) -> tuple[list, list]:
    """The outline: in profile the keel, the stern and the stem (:func:`_end_contour` on 240 heights) and the deck
    at side (smoothed, :func:`~._grid.deck_at_side`); in plan the deck at side. Curves ``(kind, label, points)``
    of the sheer and half-breadth plans [m]."""
    x, yz = np.asarray(sections.x, float), np.asarray(sections.yz, float)
    deck_x, deck_y, deck_z = deck_at_side(sections, stations)
    keel = _keel(x, yz)
    levels = np.linspace(float(yz[..., 1].min()), float(deck_z.max()), 241)[1:]
    at_levels = half_breadths(sections, x, levels)
    sheer = []
    for label, order in (("stern", slice(None)), ("stem", slice(None, None, -1))):
        contour = _end_contour(x[order], at_levels[order], levels)
        if len(contour) >= 2:
            sheer.append(("outline", label, contour))
            foot = contour[0]  # its lowest point: the keel runs on to it where it lies beyond (a Wigley's corners)
            if keel and label == "stern" and foot[0] < keel[0][0, 0]:
                keel[0] = np.vstack([foot, keel[0]])
            elif keel and label == "stem" and foot[0] > keel[-1][-1, 0]:
                keel[-1] = np.vstack([keel[-1], foot])
    sheer += [("outline", "keel", run) for run in keel]
    sheer.append(("outline", "deck", np.column_stack([deck_x, deck_z])))
    return sheer, [("outline", "deck", np.column_stack([deck_x, deck_y]))]


def lines_plan(sections: Sections, name: str = "", draft: float | None = None, stations: int = 20,
               spacing: float | None = None, n_buttocks: int = 4, n_diagonals: int = 3,
               waterlines: Waterlines | None = None, buttocks: Lengths | None = None,
               displacement: float | None = None, cb: float | None = None) -> LinesPlan:
    """Cut the lines plan from ``sections``: stations 0 (AP) … ``stations`` (FP), waterlines every ``spacing``
    [m] (default: a round spacing from the draft, :func:`~._grid.waterline_spacing`) below the deck, the DWL at
    ``draft``, ``n_buttocks`` buttocks and ``n_diagonals`` diagonals (:mod:`._grid`).

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    name : str
        The hull's name for the title block.
    draft : float or None
        Design draft [m above the baseline] for the DWL; None: no DWL (the waterlines and diagonals then take
        half the depth for it).
    stations : int
        Station intervals over Lpp (20: stations 0…20).
    spacing : float or None
        Waterline spacing [m]; None: the round default.
    n_buttocks, n_diagonals : int
        At most this many buttocks (at a round spacing); this many diagonals.
    waterlines : (w,) array_like or None
        Waterline heights [m above the baseline] instead of the round ones.
    buttocks : (b,) array_like or None
        Buttock offsets [m from the centreline] instead of the round ones.
    displacement, cb : float or None
        Δ [t] and Cb at ``draft`` for the title block (the drawing does no hydrostatics).

    Returns
    -------
    LinesPlan
        The polylines of the sheer, half-breadth and body plans [m], with the extent and the particulars.
    """
    x = np.asarray(sections.x, float)
    yz = np.asarray(sections.yz, float)
    lpp = float(sections.lpp)
    half, zmin, zmax = float(yz[..., 0].max()), float(yz[..., 1].min()), float(yz[..., 1].max())
    t_ref = float(draft) if draft is not None else 0.5 * (zmax - max(zmin, 0.0))
    spacing = float(spacing) if spacing is not None else waterline_spacing(t_ref, zmax - max(zmin, 0.0))
    if waterlines is None:
        waterlines = waterline_heights(spacing, lowest_deck(sections, stations))
        waterlines = waterlines[waterlines > zmin + 0.05 * spacing]
    buttocks = buttock_offsets(half, n_buttocks) if buttocks is None else buttocks
    waterlines, buttocks = np.asarray(waterlines, float), np.asarray(buttocks, float)
    plan = LinesPlan(name=name, extent=(float(x.min()), float(x.max()), half, zmin, zmax), lpp=lpp, beam=2.0 * half,
                     draft=None if draft is None else float(draft), displacement=displacement, cb=cb,
                     stations=stations, spacing=spacing)
    diags = diagonals(t_ref, half, n_diagonals) if n_diagonals else []
    plan.buttocks, plan.diagonals = tuple(float(b) for b in buttocks), tuple(diags)
    developed = {d.name: developed_diagonal(yz, d) for d in diags}
    reach = max([float(np.nanmax(v)) for v in developed.values() if np.isfinite(v).any()] + [0.0])
    x0, x1, zlo = float(x.min()), float(x.max()), min(zmin, 0.0)

    # the grid: baseline, centreline, stations, waterlines and buttocks where they are straight
    plan.sheer.append(("grid", "BL", np.array([[x0, 0.0], [x1, 0.0]])))
    plan.half_breadth.append(("grid", "CL", np.array([[x0, 0.0], [x1, 0.0]])))
    plan.body.append(("grid", "BL", np.array([[-half, 0.0], [half, 0.0]])))
    plan.body.append(("grid", "CL", np.array([[0.0, zlo], [0.0, zmax]])))
    numbers, xs, cuts = station_sections(sections, stations=stations)
    for k, xk in zip(numbers, xs):
        plan.sheer.append(("grid", f"{k:g}", np.array([[xk, zlo], [xk, zmax]])))
        plan.half_breadth.append(("grid", f"{k:g}", np.array([[xk, -reach], [xk, half]])))
    for z in waterlines:
        plan.sheer.append(("grid", f"WL {z:g}", np.array([[x0, z], [x1, z]])))
        plan.body.append(("grid", f"WL {z:g}", np.array([[-half, z], [half, z]])))
    for yb in buttocks:
        plan.half_breadth.append(("grid", f"Butt {yb:g}", np.array([[x0, yb], [x1, yb]])))
        for s in (-1.0, 1.0):
            plan.body.append(("grid", f"Butt {yb:g}", np.array([[s * yb, zlo], [s * yb, zmax]])))

    # the lines: stations in the body plan (midship on both sides), waterlines, buttocks, diagonals, the DWL
    for k, section in zip(numbers, cuts):
        for sign in ((-1.0,) if k < stations / 2 else (1.0,) if k > stations / 2 else (-1.0, 1.0)):
            plan.body.append(("station", f"{k:g}", section * np.array([sign, 1.0])))
    for z in waterlines:
        for run in _nan_runs(x, _outermost(yz, 1, z)):
            plan.half_breadth.append(("waterline", f"WL {z:g}", run))
    for yb in buttocks:
        for run in _buttock_runs(x, yz, yb):
            plan.sheer.append(("buttock", f"Butt {yb:g}", run))
    for d in diags:
        end = d.end(half)
        for sign in (-1.0, 1.0):
            plan.body.append(("diagonal", f"Diag {d.name}", np.array([[0.0, d.z0], [sign * end[0], end[1]]])))
        for run in _nan_runs(x, developed[d.name]):
            plan.half_breadth.append(("diagonal", f"Diag {d.name}", run * np.array([1.0, -1.0])))
    if draft is not None:
        for run in _nan_runs(x, _outermost(yz, 1, float(draft))):
            plan.half_breadth.append(("dwl", "DWL", run))
        plan.sheer.append(("dwl", "DWL", np.array([[x0, draft], [x1, draft]])))
        plan.body.append(("dwl", "DWL", np.array([[-half, draft], [half, draft]])))

    sheer, plan_view = _outline(sections, stations)
    plan.sheer += sheer
    plan.half_breadth += plan_view
    return plan


@dataclass(frozen=True)
class Label:
    """A text of the lines plan: ``text`` at ``at`` ``(u, v)`` [m, in ``view``'s coordinates], aligned by
    ``ha``/``va`` (matplotlib's words) and moved by ``offset`` [text heights]; ``kind`` what it names
    (``station``, ``section`` — the body plan's station numbers —, ``perpendicular``, ``waterline``, ``dwl``,
    ``buttock``, ``diagonal``, ``base``), so that a sheet can thin the labels of lines close together on paper."""

    view: str
    kind: str
    text: str
    at: tuple[float, float]
    ha: str = "center"
    va: str = "center"
    offset: tuple[float, float] = (0.0, 0.0)


def _station_groups(curves: list) -> list[tuple[str, np.ndarray]]:
    """The body plan's station numbers, those whose sections end at one point (the parallel middle body, a
    transom) named once, ``3–7`` or ``0, 10``: ``(text, top point)``."""
    tops = [(label, pts[np.argmax(pts[:, 1])]) for kind, label, pts in curves if kind == "station"]
    if not tops:
        return []
    tol = 0.03 * max(abs(float(p[0])) for _, p in tops) + 1e-12
    groups: list[tuple[list[str], np.ndarray]] = []
    for label, p in tops:
        near = [g for g in groups if np.hypot(*(p - g[1])) <= tol]
        if near:
            near[0][0].append(label)
        else:
            groups.append(([label], p))
    out = []
    for labels, p in groups:
        nums = [int(float(v)) for v in labels]
        run = nums == list(range(nums[0], nums[0] + len(nums)))
        out.append((labels[0] if len(labels) == 1 else f"{labels[0]}–{labels[-1]}" if run else ", ".join(labels), p))
    return out


def _longest(curves: list, kind: str) -> dict[str, np.ndarray]:
    """The longest polyline of each label of ``kind``: ``{label: points}``."""
    out: dict[str, np.ndarray] = {}
    for k, label, pts in curves:
        if k == kind and len(pts) > len(out.get(label, ())):
            out[label] = pts
    return out


def _diagonal_labels(developed: dict[str, np.ndarray], candidates: np.ndarray, floor: float) -> list[Label]:
    """Each developed diagonal named on its line (the text breaks it) at the station of ``candidates`` [m] where it
    lies furthest from its neighbours on both sides (the other diagonals, the centreline at 0, the view's
    ``floor`` [m])."""
    at = {name: np.interp(candidates, p[:, 0], p[:, 1], left=np.nan, right=np.nan) for name, p in developed.items()}
    out = []
    for name, v in at.items():
        others = np.array([np.zeros_like(v), np.full_like(v, floor)] + [w for n, w in at.items() if n != name])
        gap = others - v
        above = np.min(np.where(gap > 0, gap, np.inf), axis=0)
        below = np.min(np.where(gap <= 0, -gap, np.inf), axis=0)
        j = int(np.argmax(np.where(np.isfinite(v), np.minimum(above, below), -np.inf)))
        out.append(Label("half_breadth", "diagonal", name, (float(candidates[j]), float(v[j]))))
    return out


def _section_labels(stations: list, levels: list[float], room: float) -> list[Label]:
    """Body-plan stations that share their deck edge (the parallel middle body), named where they cross one
    waterline, on each side the one of ``levels`` [m] where most of them lie ``room`` [m] clear of their
    neighbours."""
    out = []
    for side in (-1.0, 1.0):
        mine = [(label, pts * [side, 1.0]) for label, pts in stations if side * pts[-1, 0] >= 0]
        if not mine:
            continue
        sections = [pts for _, pts in mine]
        y = np.array([[_outermost(p[None], 1, z)[0] for p in sections] for z in levels])  # (levels, stations)

        def clear(row):
            order = np.sort(row[np.isfinite(row)])
            gaps = np.diff(np.r_[-np.inf, order, np.inf])
            return int(np.sum((gaps[:-1] >= room) & (gaps[1:] >= room)))

        j = int(np.argmax([clear(row) for row in y]))
        for (label, _), yk in zip(mine, y[j]):
            if np.isfinite(yk) and yk > 1e-9:
                out.append(Label("body", "section", label, (float(side * yk), levels[j]),
                                 "right" if side > 0 else "left", "bottom", (-0.2 * side, 0.15)))
    return out


def plan_labels(plan: LinesPlan) -> list[Label]:
    """The texts of the three views: station numbers (under the sheer and half-breadth plans, above the body
    plan's sections), AP and FP, the waterlines' heights (right of the sheer plan, left of the body plan), the DWL
    (``DWL T = … m``), the buttocks and diagonals by name, the baseline and centreline.

    Parameters
    ----------
    plan : LinesPlan
        The lines plan (:func:`lines_plan`).

    Returns
    -------
    list of Label
        Anchored in each view's coordinates [m].
    """
    out: list[Label] = []
    bounds = {v: view_bounds(getattr(plan, v)) for v in ("sheer", "half_breadth", "body")}
    x1 = bounds["sheer"][1]
    for view in ("sheer", "half_breadth"):
        bottom = bounds[view][2]
        for kind, label, pts in getattr(plan, view):
            if kind == "grid" and label[0].isdigit():
                out.append(Label(view, "station", label, (float(pts[0, 0]), bottom), "center", "top", (0.0, -0.3)))
    top = bounds["sheer"][3]
    out += [Label("sheer", "perpendicular", name, (x, top), "center", "bottom", (0.0, 0.3))
            for name, x in (("AP", 0.0), ("FP", plan.lpp))]
    for kind, label, pts in plan.sheer:
        if kind == "grid" and label.startswith("WL "):
            out.append(Label("sheer", "waterline", label, (x1, float(pts[0, 1])), "left", "center", (0.4, 0.0)))
        elif kind == "grid" and label == "BL":
            out.append(Label("sheer", "base", "BL", (x1, 0.0), "left", "center", (0.4, 0.35)))  # clear of "20"
    if plan.draft is not None:
        text = f"DWL T = {plan.draft:.2f} m"
        out.append(Label("sheer", "dwl", text, (0.5 * plan.lpp, plan.draft), "center", "bottom", (0.0, 0.2)))
        out.append(Label("body", "dwl", "DWL", (bounds["body"][1], plan.draft), "left", "center", (0.4, 0.0)))
    level = plan.draft if plan.draft is not None else 0.5 * (top + bounds["sheer"][2])
    for label, pts in _longest(plan.sheer, "buttock").items():  # where the buttock rises through the DWL forward
        up = np.flatnonzero((pts[:-1, 1] < level) & (pts[1:, 1] >= level))
        at = pts[-1] if not len(up) else pts[up[-1]] + (level - pts[up[-1], 1]) / (
            pts[up[-1] + 1, 1] - pts[up[-1], 1]) * (pts[up[-1] + 1] - pts[up[-1]])
        out.append(Label("sheer", "buttock", label, (float(at[0]), float(at[1])), "right", "bottom", (-0.3, 0.2)))
    for kind, label, pts in plan.half_breadth:
        if kind == "grid" and (label.startswith("Butt ") or label == "CL"):
            out.append(Label("half_breadth", "buttock" if label != "CL" else "base", label, (x1, float(pts[0, 1])),
                             "left", "center", (0.4, 0.0)))
    out += _diagonal_labels(_longest(plan.half_breadth, "diagonal"), station_x(plan.lpp, plan.stations)[2:-2],
                            bounds["half_breadth"][2])
    for text, p in _station_groups(plan.body):
        out.append(Label("body", "section", text, (float(p[0]), float(p[1])), "center", "bottom", (0.0, 0.3)))
    named = {t for t, _ in _station_groups(plan.body) if t.isdigit()}
    levels = [float(pts[0, 1]) for kind, label, pts in plan.body if kind == "grid" and label.startswith("WL ")]
    out += _section_labels([(label, pts) for kind, label, pts in plan.body if kind == "station" and label not in named],
                           levels or [level], 0.06 * bounds["body"][1])
    b0, _, v0, _ = bounds["body"]
    for kind, label, pts in plan.body:
        if kind == "grid" and label.startswith("WL "):
            out.append(Label("body", "waterline", label, (b0, float(pts[0, 1])), "right", "center", (-0.4, 0.0)))
        elif kind == "grid" and label.startswith("Butt ") and pts[0, 0] < 0:
            out.append(Label("body", "buttock", label.removeprefix("Butt "), (float(pts[0, 0]), v0), "center", "top",
                             (0.0, -0.3)))
        elif kind == "diagonal" and pts[-1, 0] > 0:
            out.append(Label("body", "diagonal", label.removeprefix("Diag "), tuple(map(float, pts[-1])), "left",
                             "center", (0.3, 0.0)))
    out.append(Label("body", "base", "CL", (0.0, v0), "center", "top", (0.0, -0.3)))
    return out


def thin_labels(labels: list[Label], plan: LinesPlan, scale: float, height: float) -> list[Label]:
    """The labels that do not overlap their neighbours when drawn ``scale`` units per metre with text ``height``
    units high (mm on a sheet, m in a DXF): the waterlines' heights every k-th waterline (k · spacing on paper at
    least 1.3 text heights; not the ¼ and ½ waterlines when k > 1), the station numbers every k-th station (3 text
    heights apart).

    Parameters
    ----------
    labels : list of Label
        The labels (:func:`plan_labels`), of one view (its ``scale``).
    plan : LinesPlan
        The plan (its waterline spacing and stations).
    scale : float
        Units of the drawing per metre of hull.
    height : float
        The text height in the drawing's units.

    Returns
    -------
    list of Label
        Those kept, in their order.
    """
    def every(step: float, room: float) -> float:  # the distance [m] between named lines: k steps, ≥ room apart
        return step * max(1, math.ceil(room / max(step * scale, 1e-12) - 1e-9))

    rules = {"waterline": every(plan.spacing, 1.3 * height), "station": every(plan.lpp / plan.stations, 3 * height)}

    def keep(lab: Label) -> bool:
        if lab.kind not in rules:
            return True
        value = float(lab.text.split()[-1]) * (plan.lpp / plan.stations if lab.kind == "station" else 1.0)
        return abs(value / rules[lab.kind] - round(value / rules[lab.kind])) < 1e-6

    return [lab for lab in labels if keep(lab)]


#: A label's text width per character [text heights] (DejaVu Sans digits 0.64 em, capitals up to 0.77) and the
#: gap kept between two labels' boxes [text heights]
CHAR_WIDTH, LABEL_GAP = 0.68, 0.25


def text_box(lab: Label, p: np.ndarray, height: float) -> np.ndarray:
    """The box a label's text takes at ``p``, by its alignment.

    Parameters
    ----------
    lab : Label
        The label (its text and alignment).
    p : numpy.ndarray, (2,)
        Where it is placed, in the drawing's units.
    height : float
        The text height in the drawing's units.

    Returns
    -------
    numpy.ndarray, (4,)
        ``(x0, y0, x1, y1)``, a character :data:`CHAR_WIDTH` text heights wide.
    """
    w = CHAR_WIDTH * height * len(lab.text)
    x0 = p[0] - {"left": 0.0, "center": 0.5, "right": 1.0}[lab.ha] * w
    y0 = p[1] - {"bottom": 0.0, "center": 0.5, "top": 1.0}[lab.va] * height
    return np.array([x0, y0, x0 + w, y0 + height])


def legible_labels(labels: list[Label], place: Callable[[Label], np.ndarray], height: float) -> list[tuple]:
    """The labels that do not collide, each with its place: every label but the body plan's station numbers
    and the buttocks' names, which are kept in order of rank (0, 5, 10 … first, then the even ones) where each
    clears the boxes of those kept before it by :data:`LABEL_GAP` — so no two read as one ("1310–11").

    Parameters
    ----------
    labels : list of Label
        The labels (thinned: :func:`thin_labels`).
    place : callable
        A label → where its anchor lies in the drawing, ``(2,)`` (its view's offset and scale, its ``offset``).
    height : float
        The text height in the drawing's units (mm on a sheet, m in a DXF).

    Returns
    -------
    list of tuple of (Label, numpy.ndarray)
        Those kept, with their places.
    """
    def rank(lab):
        if lab.kind not in ("section", "buttock"):
            return (0, 0, 0, 0.0)
        first = float(lab.text.replace("–", " ").replace(",", " ").split()[-1 if lab.kind == "buttock" else 0])
        return (1, first % 5 != 0, first % 2 != 0, first)

    gap = LABEL_GAP * height
    placed: list[tuple] = []
    boxes: list[np.ndarray] = []
    for lab in sorted(labels, key=rank):
        p = np.asarray(place(lab), float)
        box = text_box(lab, p, height)
        clear = all(box[2] + gap <= b[0] or b[2] + gap <= box[0] or box[3] + gap <= b[1] or b[3] + gap <= box[1]
                    for b in boxes)
        if clear or rank(lab)[0] == 0:
            placed.append((lab, p))
            boxes.append(box)
    return placed


def arrange(plan: LinesPlan, gap: float) -> dict[str, tuple[float, float]]:
    """Where each view goes on one drawing [m]: the sheer plan as it is, the half-breadth plan under it and the
    body plan under that, at the left, ``gap`` [m] apart: ``{view: (du, dv)}`` added to the view's coordinates."""
    s, h, b = (view_bounds(getattr(plan, v)) for v in ("sheer", "half_breadth", "body"))
    dv_half = s[2] - gap - h[3]
    return {"sheer": (0.0, 0.0), "half_breadth": (0.0, dv_half),
            "body": (s[0] - b[0], dv_half + h[2] - gap - b[3])}
