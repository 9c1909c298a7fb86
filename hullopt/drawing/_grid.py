"""The ordinates of a lines plan and of its offset table, as a yard sets them out: stations equally spaced over
Lpp (0 at the AP, N at the FP), waterlines at a round spacing chosen from the draft, buttocks at a round spacing
inside the half-breadth, diagonals across the bilge, and the deck at side, smoothed (a mesh's slices put mesh
wiggles in it). Numpy: static preprocessing for drawings and tables."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..geometry import Sections, pchip

#: Round steps [m]: these times a power of ten.
ROUND_STEPS = (1.0, 2.0, 2.5, 5.0)


def round_step(span: float, most: float) -> float:
    """The smallest round step ``s`` = {1, 2, 2.5, 5} × 10^k with ``span / s ≤ most``.

    Parameters
    ----------
    span : float
        The length to divide [m] (positive).
    most : float
        The most steps it may hold.

    Returns
    -------
    float
        The step [m].

    Examples
    --------
    >>> round_step(14.5, 10), round_step(6.25, 10), round_step(24.2, 5)
    (2.0, 1.0, 5.0)
    """
    raw = span / most
    k = math.floor(math.log10(raw))
    return next(m * 10.0**k for m in (*ROUND_STEPS, 10.0) if m * 10.0**k >= raw * (1 - 1e-12))


def station_x(lpp: float, stations: int = 20) -> np.ndarray:
    """The stations 0 (AP) … ``stations`` (FP), ``(stations + 1,)`` [m from the AP], Lpp/``stations`` apart."""
    return np.arange(stations + 1) * float(lpp) / stations


def waterline_spacing(draft: float, depth: float) -> float:
    """A round waterline spacing: at most 10 waterlines up to the draft and 20 up to the depth (so 5 to 10 below
    the DWL; the DTC at T = 14.5 m: 2 m, the Wigley at 6.25 m: 1 m).

    Parameters
    ----------
    draft : float
        The design draft [m above the baseline].
    depth : float
        The depth to the deck [m above the baseline].

    Returns
    -------
    float
        The spacing [m], {1, 2, 2.5, 5} × 10^k.
    """
    return max(round_step(draft, 10), round_step(depth, 20))


def waterline_heights(spacing: float, top: float, bottom: float = 0.0) -> np.ndarray:
    """The waterlines ``k · spacing`` [m above the baseline] from ``bottom`` (the baseline, or the multiple below a
    keel under it) to below ``top`` (the lowest deck at side: a waterline within 5 % of a spacing of it is the
    deck), with the ¼ and ½ waterlines over the baseline, where a section turns at the bilge (as a yard adds them:
    the DTC's table read back gives its ∇ to −0.16 % with them, −0.9 % without)."""
    lo = math.floor(min(bottom, 0.0) / spacing + 1e-9)
    hi = math.ceil((top - 0.05 * spacing) / spacing - 1e-9)
    z = np.union1d(spacing * np.arange(lo, hi), [0.25 * spacing, 0.5 * spacing])
    return z[z < top - 0.05 * spacing]


def buttock_offsets(half_breadth: float, most: int = 4) -> np.ndarray:
    """At most ``most`` buttocks at a round spacing [m from the centreline], inside 95 % of the half-breadth
    (one nearer the side is lost in it): the DTC (25.5 m) 5, 10, 15, 20; the Wigley (5 m) 1, 2, 3, 4."""
    inner = 0.95 * half_breadth
    s = round_step(inner, most + 1)
    return s * np.arange(1, math.ceil(inner / s - 1e-9))


@dataclass(frozen=True)
class Diagonal:
    """A diagonal plane, straight in the body plan: from ``(0, z0)`` on the centreline [m above the baseline]
    outward and down along the unit vector ``direction`` ``(dy, dz)``; ``name`` A, B, …"""

    name: str
    z0: float
    direction: tuple[float, float]

    def end(self, half_breadth: float) -> np.ndarray:
        """Where it leaves the body plan, ``(2,)`` [m]: at the baseline or at ``half_breadth``, whichever first."""
        dy, dz = self.direction
        t = min(half_breadth / dy, self.z0 / -dz) if dz < 0 else half_breadth / dy
        return np.array([t * dy, self.z0 + t * dz])


def diagonals(draft: float, half_breadth: float, n: int = 3) -> list[Diagonal]:
    """``n`` diagonals parallel to the bilge diagonal — the line from the DWL on the centreline to where the
    baseline meets the half-breadth, about normal to the turn of the bilge — through the centreline at
    ``T · (1 + (k − (n − 1)/2) / 2)``: one at T, three at T/2, T and 3T/2 [m above the baseline]."""
    direction = np.array([half_breadth, -draft]) / math.hypot(half_breadth, draft)
    return [Diagonal(chr(ord("A") + k), draft * (1 + (k - (n - 1) / 2) / 2), (float(direction[0]), float(direction[1])))
            for k in range(n)]


def deck_at_side(sections: Sections, stations: int = 20) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The deck at side, smoothed: each section's deck edge (its last point) filtered over about one station
    interval of sections — its height closed (a running maximum, then minimum: a mesh's slices cut the corner at
    the deck edge, so their wiggles are dips below it, which the closing fills, while a sheer rising to the ends, a
    step and a peak stay as they are), its half-breadth by a running median (which keeps a monotone run, the
    deck closing in at the ends, as it is) — then PCHIP through the stations and the sections beyond the
    perpendiculars (where the ends turn quickly).

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    stations : int
        Station intervals over Lpp.

    Returns
    -------
    tuple of numpy.ndarray
        ``x (k,)`` [m from the AP], the half-breadth ``y (k,)`` and height ``z (k,)`` [m] of the deck at side,
        from the aft end of the hull to the fore end.
    """
    from scipy.ndimage import grey_closing, median_filter

    x = np.asarray(sections.x, float)
    edge = np.asarray(sections.yz, float)[:, -1]
    lpp = float(sections.lpp)
    per_station = len(x) * lpp / stations / max(x[-1] - x[0], 1e-12)
    window = max(3, 2 * math.ceil(per_station / 2) + 1)
    smooth = np.column_stack([median_filter(edge[:, 0], size=window, mode="nearest"),
                              grey_closing(edge[:, 1], size=window, mode="nearest")])
    st = station_x(lpp, stations)
    knots = np.union1d(st[(st > x[0]) & (st < x[-1])], x[(x <= 0.0) | (x >= lpp)])
    knots = np.union1d(knots, x[[0, -1]])
    at = np.column_stack([np.interp(knots, x, smooth[:, 0]), np.interp(knots, x, smooth[:, 1])])
    fine = np.union1d(np.linspace(x[0], x[-1], 401), knots)
    y, z = pchip(knots, at, fine).T
    return fine, np.maximum(y, 0.0), z


def lowest_deck(sections: Sections, stations: int = 20) -> float:
    """The lowest deck at side [m above the baseline] where the deck is wider than 5 % of the largest
    half-breadth (not at a stem or a stern that closes to the centreline): the top of a table's waterlines."""
    _, y, z = deck_at_side(sections, stations)
    wide = y > 0.05 * float(np.max(np.asarray(sections.yz)[..., 0]))
    return float(np.min(z[wide])) if wide.any() else float(np.max(z))
