"""Whether a hull read from a file looks like a ship in metres in hullopt's axes, and if not, the likely cause and
the fix (issue 62): a mesh written in millimetres reads as a 100 km ship, one exported y-up as a hull lying on its
side, a z-down one upside down. :func:`plausibility_warnings` measures the sections (numpy: no JAX operation, a
few milliseconds) and says, one line a finding, what looks wrong and what to give the hull spec;
:func:`~hullopt.models.load_hull` runs it on every hull it reads (meshes, IGES/STEP, half hulls, offset tables,
parents; not a builtin, whose spec states its dimensions) and issues each line as a
:class:`~hullopt.errors.HullWarning`.

The limits are wide on purpose, so that no real ship, tank model or small craft is flagged:

* **size**: Lpp 1–500 m (a towing-tank model of 2–10 m is legitimate and not flagged: it is read at model
  scale, which is right for a model, and ``?scale=λ`` gives the ship). Above 500 m the fixes offered are those
  of a file in millimetres (``?scale=0.001``), centimetres (``?scale=0.01``) or inches (``?scale=0.0254``), each
  where it brings Lpp into 1–500 m, with the Lpp it gives;
* **origin**: the AP at x = 0 with the hull's aft end at most a quarter of its length aft of it, or ahead of it;
  the baseline at z = 0 with the keel at most 30 % of the hull's height below it (the DTMB 5415's sonar dome
  reaches 19 % below its baseline) or above it; the fix is ``?shift=``; ``lpp=`` (a length in m after
  ``?scale=``) within 0.5–1.5 of the hull's length along x;
* **axes**: the hull longest along x; not taller than 3× its beam; not symmetric about z = 0 (a hull is about
  its centre plane: the file's y up); not holding more than 1.15× the volume in the lowest quarter of its height
  that it holds in the highest (upside down: the file's z down; upright, the examples and library parents hold
  0.23–0.9×, a box 1×); the fix is ``?axes=`` (our x, y, z from the file's);
* **proportions** (ships, generously: L/B 2–15, B/T 1–10, T/Lpp 0.02–0.08, D/T 1–3, ∇/Lpp³ 0.0005–0.03 at the
  design draft): warned only far outside, L/B outside 1.5–30, and where the design draft is known B/T outside
  0.5–15, T/Lpp outside 0.005–0.25, D/T above 10, ∇/Lpp³ outside 1e-4–0.06 (at the deck, with no draft:
  2e-4–0.12).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..geometry import Sections

#: The lengths between perpendiculars of ships and towing-tank models [m]; outside them a warning.
LPP_RANGE = (1.0, 500.0)
#: File units a mesh may have been written in: (name, metres per unit).
UNITS = (("millimetres", 0.001), ("centimetres", 0.01), ("inches", 0.0254))
#: Warned-outside ranges of the hull's proportions (each far wider than ships': see the module docstring).
L_OVER_B = (1.5, 30.0)
B_OVER_T = (0.5, 15.0)
T_OVER_LPP = (0.005, 0.25)
D_OVER_T_MAX = 10.0
VOLUME_OVER_LPP3 = (1e-4, 0.06)  # at the design draft
VOLUME_OVER_LPP3_DECK = (2e-4, 0.12)  # at the deck, when no draft is known
DEPTH_OVER_B_MAX = 3.0
AFT_OVERHANG = 0.25  # the hull's aft end at most this fraction of its length from the AP (either way)
KEEL_BELOW = 0.3  # the keel at most this fraction of the hull's height from the baseline (either way)
LPP_OVER_LENGTH = (0.5, 1.5)
LOWEST_OVER_HIGHEST_MAX = 1.15  # the volume in the lowest quarter of the height over that in the highest


def _close(pts: np.ndarray) -> np.ndarray:
    """A half-section (keel on y = 0 to its top edge) closed along the centreline: the points and, where its top
    edge is off the centreline, ``(0, z_top)``."""
    return pts if pts[-1, 0] == 0.0 else np.vstack([pts, [0.0, pts[-1, 1]]])


def _area(poly: np.ndarray) -> float:
    """The area [m²] of a closed polygon (k, 2) by the shoelace formula (either orientation)."""
    y, z = poly[:, 0], poly[:, 1]
    return 0.5 * abs(float(np.dot(y, np.roll(z, -1)) - np.dot(z, np.roll(y, -1))))


def _area_below(poly: np.ndarray, level: float) -> float:
    """The area [m²] of the part of a closed polygon (k, 2) with z ≤ ``level`` (the polygon clipped)."""
    a, b = poly, np.roll(poly, -1, axis=0)
    ina, inb = a[:, 1] <= level, b[:, 1] <= level
    cross = ina != inb
    t = np.where(cross, (level - a[:, 1]) / np.where(cross, b[:, 1] - a[:, 1], 1.0), 0.0)
    hit = a + t[:, None] * (b - a)
    pts = np.stack([a, hit], axis=1).reshape(-1, 2)
    keep = np.stack([ina, cross], axis=1).reshape(-1)
    clipped = pts[keep]
    return _area(clipped) if len(clipped) >= 3 else 0.0


def _fmt(v: float) -> str:
    """A length or ratio to 3 significant figures as a naval architect reads it (100000, 3.33, 0.0625)."""
    return f"{float(f'{v:.3g}'):g}"


def _kind(spec: str) -> str:
    """How a fix is worded for the hull spec ``spec``: ``"mesh"`` (a mesh or CAD file, whose spec takes
    ``scale``, ``axes`` and ``shift``), ``"table"`` (an offsets ``.csv``) or ``"other"`` (a parent ``.json``…)."""
    base = spec.partition("?")[0]
    if base.startswith(("builtin:", "parent:")) or base.lower().endswith(".json") or not Path(base).suffix:
        return "other"
    return "table" if base.lower().endswith(".csv") else "mesh"


_AXES_FIX = {"mesh": "give the file's axes in the hull spec (our x, y, z from the file's, with signs, e.g. {axes})",
             "table": "check the table's columns and rows", "other": "check the hull's axes"}


@dataclass(frozen=True)
class _Hull:
    """What the checks read of a hull's sections: its stations that cut it (x [m], yz [m]), Lpp, its length
    along x, beam, lowest and highest z [m] and the fix's wording (:func:`_kind`)."""

    x: np.ndarray
    yz: np.ndarray
    lpp: float
    length: float
    beam: float
    z_lo: float
    z_hi: float
    kind: str

    @property
    def height(self) -> float:
        return self.z_hi - self.z_lo

    def volume(self, level: float | None = None) -> float:
        """The volume [m³] below z = ``level`` (None: the whole hull), both sides."""
        polys = [_close(p) for p in self.yz]
        areas = [_area(p) if level is None else _area_below(p, level) for p in polys]
        return 2.0 * float(np.trapezoid(areas, self.x))


def _size(h: _Hull, consistent: bool) -> str | None:
    """Lpp outside :data:`LPP_RANGE`: the file's unit (or a dimensionless or scaled model)."""
    size, what = (h.lpp, f"Lpp {_fmt(h.lpp)} m") if consistent else (h.length, f"the hull's length {_fmt(h.length)} m")
    lo, hi = LPP_RANGE
    if size > hi:
        fits = [(unit, f) for unit, f in UNITS if lo <= size * f <= hi]
        names = [u for u, _ in fits]
        units = " or ".join([", ".join(names[:-1]), names[-1]]) if len(names) > 1 else "".join(names)
        gives = [f"{f:g} ({'Lpp ' if consistent else ''}{_fmt(size * f)} m)" for _, f in fits]
        fix = {"mesh": "read it with " + " or ".join(f"?scale={g}" for g in gives),
               "table": "write it in metres: ×" + " or ×".join(gives),
               "other": "give it in metres: ×" + " or ×".join(gives)}
        if not fits:
            units = "a unit other than metres"
            fix = {"mesh": "read it with ?scale= (metres per unit of the file)", "table": "write it in metres",
                   "other": "give it in metres"}
        file = {"mesh": "a mesh", "table": "a table", "other": "lengths"}[h.kind]
        return f"{what} is longer than any ship ({lo:g}–{hi:g} m): {file} in {units}? {fix[h.kind]}"
    if size < lo:
        fix = {"mesh": "read it at full scale with ?scale=λ (the ship's length over this one)",
               "table": "write it in metres at full scale", "other": "give it in metres at full scale"}
        return (f"{what} is shorter than any ship or towing-tank model ({lo:g}–{hi:g} m): a hull made "
                f"dimensionless, or a model in another unit? {fix[h.kind]}")
    return None


def _axes(h: _Hull) -> str | None:
    """The hull not lying along x with its deck up: longer across or up than along, symmetric about z = 0 (on its
    side), far taller than wide, or fuller in the lowest quarter of its height than in the highest (upside down)."""
    if h.length < max(h.beam, h.height):
        along, axes = ("across (y)", "?axes=y,x,z") if h.beam >= h.height else ("up (z)", "?axes=z,y,x")
        return (f"the hull is longer {along}, {_fmt(max(h.beam, h.height))} m, than along x, {_fmt(h.length)} m: read "
                f"in the wrong axes? {_AXES_FIX[h.kind].format(axes=axes)}")
    if h.z_lo < 0.0 < h.z_hi and abs(h.z_lo + h.z_hi) <= 0.02 * h.height:
        return (f"the hull is symmetric about z = 0 (z {_fmt(h.z_lo)} … {_fmt(h.z_hi)} m), as a hull is about its "
                f"centre plane: lying on its side (the file's y up)? {_AXES_FIX[h.kind].format(axes='?axes=x,-z,y')}")
    if h.height > DEPTH_OVER_B_MAX * h.beam:
        return (f"the hull is {_fmt(h.height / h.beam)}× as tall ({_fmt(h.height)} m) as wide ({_fmt(h.beam)} m): "
                f"read in the wrong axes? {_AXES_FIX[h.kind].format(axes='?axes=x,-z,y')}")
    quarter = 0.25 * h.height
    lowest, highest = h.volume(h.z_lo + quarter), h.volume() - h.volume(h.z_hi - quarter)
    if lowest > LOWEST_OVER_HIGHEST_MAX * highest:
        fix = {"mesh": "read it with ?axes=x,-y,-z", "table": "check the table's waterlines",
               "other": "check the hull's axes"}
        return (f"the hull holds {_fmt(lowest / highest)}× as much volume in the lowest quarter of its height as "
                "in the highest (a ship is narrower at its keel than at its deck): upside down (the file's z down)? "
                + fix[h.kind])
    return None


def _origin(h: _Hull, consistent: bool) -> list[str]:
    """The AP not at x = 0 or the baseline not at z = 0 (an origin amidships, at the waterline), and an Lpp
    that does not fit the hull's length."""
    dx = -float(h.x[0]) if abs(float(h.x[0])) > AFT_OVERHANG * h.length else 0.0
    dz = -h.z_lo if abs(h.z_lo) > KEEL_BELOW * h.height else 0.0
    out = []
    if dx or dz:
        where = " and ".join(w for w, d in ((f"its aft end at x = {_fmt(h.x[0])} m (the AP is at x = 0)", dx),
                                            (f"its keel at z = {_fmt(h.z_lo)} m (drafts are heights above z = 0, "
                                             "the baseline)", dz)) if d)
        puts = " and ".join(w for w, d in (("x = 0 at its aft end", dx), ("z = 0 at its keel", dz)) if d)
        fix = {"mesh": f"?shift={_fmt(dx)},0,{_fmt(dz)} puts {puts}",
               "table": "measure its x from the AP and its z from the baseline",
               "other": "its x is measured from the AP, its z from the baseline"}
        out.append(f"the hull's origin is not at the AP on the baseline: {where}; {fix[h.kind]}")
    elif not consistent and LPP_RANGE[0] <= h.length <= LPP_RANGE[1]:
        fix = {"mesh": f"lpp= is in metres after ?scale= (a model-scale file? ?scale={_fmt(h.lpp / h.length)})",
               "table": "check the table's lpp", "other": "check its Lpp"}
        out.append(f"Lpp {_fmt(h.lpp)} m does not fit the hull's length along x, {_fmt(h.length)} m: {fix[h.kind]}")
    return out


def _proportions(h: _Hull, draft: float | None) -> list[str]:
    """L/B, and at the design draft B/T, T/Lpp, D/T and ∇/Lpp³ (∇/Lpp³ at the deck without one), far outside
    ships' ranges."""
    fix = {"mesh": "check the hull spec's lpp= and ?axes=", "table": "check the table", "other": "check the hull"}
    checks = [("L/B", h.lpp / h.beam, L_OVER_B, "2–15", "")]
    if draft is not None and np.isfinite(draft) and draft > 0:
        at = f" at the design draft {_fmt(draft)} m"
        depth = h.z_hi - max(h.z_lo, 0.0)
        checks += [("B/T", h.beam / draft, B_OVER_T, "1–10", at),
                   ("T/Lpp", draft / h.lpp, T_OVER_LPP, "0.02–0.08", at),
                   ("D/T", depth / draft, (0.0, D_OVER_T_MAX), "1–3", at),
                   ("∇/Lpp³", h.volume(draft) / h.lpp**3, VOLUME_OVER_LPP3, "0.0005–0.03", at)]
        fix = {k: f"check the design draft; {v[0].lower()}{v[1:]}" for k, v in fix.items()}
    else:
        checks.append(("∇/Lpp³", h.volume() / h.lpp**3, VOLUME_OVER_LPP3_DECK, "0.001–0.06", " at the deck"))
    return [f"{label} {_fmt(value)}{at} is far outside ships' {ships}: {fix[h.kind]}"
            for label, value, (lo, hi), ships, at in checks if not lo <= value <= hi]


def plausibility_warnings(sections: Sections, draft: float | None = None, spec: str = "") -> list[str]:
    """What looks wrong with a hull read from a file, one line a finding, each naming the likely cause and the fix.

    Parameters
    ----------
    sections : Sections
        The hull as read (our axes, m).
    draft : float, optional
        Its design draft [m above the baseline] when known: B/T, T/Lpp, D/T and ∇/Lpp³ are then judged at it
        (∇/Lpp³ at the deck otherwise).
    spec : str
        The hull spec it was read from: its file's name starts each line, and its kind words the fix (a mesh or
        CAD file: ``?scale=``, ``?axes=``, ``?shift=``; an offsets ``.csv``: the table's own units; else plain).

    Returns
    -------
    list of str
        The findings, in the order size, axes, origin, proportions (the module docstring gives the checks and
        their limits; a hull in the wrong axes is not judged for its origin or proportions, nor one of the wrong
        size for its proportions); empty for a plausible hull.
    """
    yz = np.asarray(sections.yz, dtype=float)
    live = yz[..., 0].max(axis=1) > 0.0  # the stations that cut the hull (one beyond its ends is all zeros)
    if not live.any() or not np.isfinite(yz).all():
        return []
    x, yz = np.asarray(sections.x, dtype=float)[live], yz[live]
    h = _Hull(x, yz, float(np.asarray(sections.lpp)), float(x[-1] - x[0]), 2.0 * float(yz[..., 0].max()),
              float(yz[..., 1].min()), float(yz[..., 1].max()), _kind(spec))
    if not (h.length > 0 and h.beam > 0 and h.height > 0 and h.lpp > 0):
        return []
    consistent = LPP_OVER_LENGTH[0] <= h.lpp / h.length <= LPP_OVER_LENGTH[1]
    size, axes = _size(h, consistent), _axes(h)
    out = [w for w in (size, axes) if w is not None]
    if axes is None:
        out += _origin(h, consistent)
        if size is None:
            out += _proportions(h, draft)
    name = Path(spec.partition("?")[0]).name or "the hull"
    return [f"{name}: {w}" for w in out]
