"""Shape measures of a hull's sections and sectional-area curve, as differentiable constraint measures
``measure(sections, draft) -> Array`` (the draft unused where a measure does not need one). Each is compared
with the parent's only (``"<= 2 * parent"``): the values are dimensional and their scale is the hull's own."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._types import Draft
from ..geometry import Sections, closed_half_polygon, level_widths, safe_norm, section_integrals
from ._unfairness import unfairness

MERGE = 1e-3
"""m: section offsets closer than this are one point in the section measures. Feature points that coincide at
the parent (a collapsed segment, the deck edge where there is no flat of side) drift apart by 1e-9 m under a
deformation, and a segment that short turns any way. No hull's offsets resolve a millimetre."""

CENTRELINE = 1e-9
"""m: offsets with a half-breadth at most this are on the centreline (left out of the section measures)."""

KNUCKLE_FLOOR = np.deg2rad(5.0) ** 4
"""rad⁴: a station's Σ θ⁴ counts at least this (one 5° turn) in :func:`station_knuckles`, so that a bound
relative to a parent's nearly straight station still allows it a gentle turn."""


def _sac_terms(sections: Sections, draft: Draft) -> Float[Array, " n2"]:
    """(A'')² Δx [m] at the inner stations of the sectional-area curve A(x) at ``draft`` (second divided
    differences; Δx the mean of the neighbouring spacings)."""
    x, a = sections.x, 2.0 * section_integrals(sections, draft).area
    h0, h1 = jnp.diff(x)[:-1], jnp.diff(x)[1:]
    d2 = 2.0 * ((a[2:] - a[1:-1]) / h1 - (a[1:-1] - a[:-2]) / h0) / (h0 + h1)
    return d2**2 * 0.5 * (h0 + h1)


def sac_roughness(sections: Sections, draft: Draft) -> Float[Array, ""]:
    """Σ (A'')² Δx [m] of the sectional-area curve A(x) at ``draft`` [m above the baseline] (second divided
    differences over the stations): a fuller or hollower shoulder raises it.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, scalar
        Σ (A'')² Δx [m].
    """
    return jnp.sum(_sac_terms(sections, draft))


def _compact(keep, *arrays):
    """The rows of ``arrays`` where ``keep``, moved to the front in order (the rest after them), and how
    many there are: a fixed-shape stand-in for ``array[keep]``."""
    order = jnp.argsort(~keep, stable=True)
    return (*(v[order] for v in arrays), jnp.sum(keep))


def _turns(p, at: bool = False):
    """Turning angles [rad] between neighbouring segments of a half-section polyline ``p (m, 2)`` [m] (keel to
    deck: a convex section turns positive, a hollow or a flare negative) and the segment lengths [m], its
    centreline points and segments under :data:`MERGE` left out, as fixed-shape arrays: ``(turn (m−2,),
    ds (m−1,), s)`` with the ``s`` kept segments first (the rest padded: turns 0, lengths 1 m), and with ``at``
    the heights of the turns' vertices ``z (m−2,)`` [m] (padded with +∞). Finite gradients: the left-out
    entries are replaced before any division or angle."""
    p, k = _compact(jax.lax.stop_gradient(p[:, 0] > CENTRELINE), p)
    d = jnp.diff(p, axis=0)
    ds = safe_norm(d)
    idx = jnp.arange(d.shape[0])
    d, ds, start, s = _compact(jax.lax.stop_gradient((idx < k - 1) & (ds > MERGE)), d, ds, p[:-1, 1])
    ok = idx < s
    ds = jnp.where(ok, ds, 1.0)
    t = jnp.where(ok[:, None], d / ds[:, None], jnp.array([1.0, 0.0]))
    cross = t[:-1, 0] * t[1:, 1] - t[:-1, 1] * t[1:, 0]
    turn = jnp.arctan2(cross, jnp.sum(t[:-1] * t[1:], 1))
    if not at:
        return turn, ds, s
    return turn, ds, s, jax.lax.stop_gradient(jnp.where(idx[1:] < s, start[1:], jnp.inf))


def section_roughness(sections: Sections, draft: Draft | None = None) -> Float[Array, ""]:
    """The sections' variation of curvature [m⁻³]: the mean over stations of Σ (Δκ)²/Δs of each half-section
    polyline (κ the turning angle over the mean neighbouring segment length). A wavy section raises it.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar, optional
        Waterline height [m above the baseline] (unused).

    Returns
    -------
    Array, scalar
        The mean over stations [m⁻³].
    """

    def one(p):
        turn, ds, s = _turns(p)
        kappa = turn / (0.5 * (ds[:-1] + ds[1:]))
        terms = jnp.diff(kappa) ** 2 / ds[1:-1]
        return jnp.sum(jnp.where(jnp.arange(terms.shape[0]) + 2 < s, terms, 0.0))

    return jnp.mean(jax.vmap(one)(sections.yz))


def _turns4(sections: Sections) -> Float[Array, " n"]:
    """Σ θ⁴ [rad⁴] of each station's turning angles (:func:`_turns`)."""

    def one(p):
        turn, _, s = _turns(p)
        return jnp.sum(jnp.where(jnp.arange(turn.shape[0]) + 1 < s, turn**4, 0.0))

    return jax.vmap(one)(sections.yz)


def section_knuckle(sections: Sections, draft: Draft | None = None) -> Float[Array, ""]:
    """The sections' knuckles [rad⁴]: the mean over stations of Σ θ⁴, θ the turning angle between neighbouring
    segments of each half-section polyline — a soft maximum of the sharpest turn, which
    :func:`section_roughness` misses where a knuckle sits beside a long segment. ``"<= 2 * parent"`` lets no
    turn grow by more than about 2^(1/4) ≈ 1.19× the parent's sharpest where that is one turn.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar, optional
        Waterline height [m above the baseline] (unused).

    Returns
    -------
    Array, scalar
        The mean over stations of Σ θ⁴ [rad⁴].
    """
    return jnp.mean(_turns4(sections))


def station_knuckles(sections: Sections, draft: Draft | None = None) -> Float[Array, " n"]:
    """Each station's knuckles ``(n,)`` [rad⁴]: Σ θ⁴ as :func:`section_knuckle`, floored at
    :data:`KNUCKLE_FLOOR`. As a constraint every station is held against the parent's same station: the mean
    over stations is ruled by a real hull's sharpest turns (on the KCS, 99 % of it is a 66° turn at the skeg
    and a 72° one at the forefoot), so that twice it allowed a new 60° knuckle anywhere else.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar, optional
        Waterline height [m above the baseline] (unused).

    Returns
    -------
    Array, (n,)
        Each station's Σ θ⁴ [rad⁴], at least :data:`KNUCKLE_FLOOR`.
    """
    return jnp.maximum(_turns4(sections), KNUCKLE_FLOOR)


DWL_BAND = 0.5
"""m: :func:`dwl_turns` holds the sections' turns within this height of the DWL (either side)."""

INFLECTION_FLOOR = np.deg2rad(2.0) ** 2
"""rad²: a station's reverse turning counts at least this (one 2° hollow) in :func:`section_inflections`, so that
a bound relative to a parent's convex station still allows the turns a deformation makes by a hair."""


def dwl_turns(sections: Sections, draft: Draft) -> Float[Array, ""]:
    """The sharpest turn of the sections near the waterline [rad⁴]: the largest over stations of Σ θ⁴ of the
    turns (:func:`section_knuckle`) whose vertex lies within :data:`DWL_BAND` of the DWL, at least
    :data:`KNUCKLE_FLOOR`. Held at most the parent's, no station turns sharper there than the parent's
    sharpest: a deformation makes no soft chine at the waterline, where the bow wave and the reflection of waves
    form and the station knuckles (ruled by a turn at the bilge or the keel) do not see it. Every other station
    may turn as sharply as that one.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, scalar
        The largest station's Σ θ⁴ [rad⁴] within the band, at least :data:`KNUCKLE_FLOOR`.
    """

    def one(p):
        turn, _, _, z = _turns(p, at=True)
        return jnp.sum(jnp.where(jnp.abs(z - draft) <= DWL_BAND, turn**4, 0.0))

    return jnp.maximum(jnp.max(jax.vmap(one)(sections.yz)), KNUCKLE_FLOOR)


def section_inflections(sections: Sections, draft: Draft) -> Float[Array, " n"]:
    """Each station's reverse turning below the waterline ``(n,)`` [rad²]: Σ max(0, −θ)² of the turns whose
    vertex lies under the DWL (a convex section turns one way only, :func:`_turns`; a hollow, an S or a bulb's
    neck turns back), floored at :data:`INFLECTION_FLOOR`. Held at most the parent's, station by station, a
    deformation makes no new inflection and the parent's (a bulb's neck) may stay.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, (n,)
        Each station's Σ max(0, −θ)² [rad²] under the DWL, at least :data:`INFLECTION_FLOOR`.
    """

    def one(p):
        turn, _, _, z = _turns(p, at=True)
        return jnp.sum(jnp.where(z < draft, jnp.maximum(-turn, 0.0) ** 2, 0.0))

    return jnp.maximum(jax.vmap(one)(sections.yz), INFLECTION_FLOOR)


WATERLINE_FRACTIONS = (1 / 6, 2 / 6, 3 / 6, 4 / 6, 5 / 6, 1.0)
"""The heights of :func:`waterline_angles`, as fractions of the draft above the keel (the last: the DWL)."""

WATERLINES_ABOVE = 2
"""How many waterlines above the DWL a design's overlay draws (:func:`waterlines` ``above``): a bow
attachment or any change "at least above the waterline vicinity" shows there."""

SAC_REGIONS = ((0.0, 0.25), (0.25, 0.5), (0.5, 0.75), (0.75, 1.0))
"""The regions of :func:`sac_regions` as fractions of the stations' span from aft: the run, the aft shoulder, the
fore shoulder and the entrance."""


ANGLE_FLOOR = np.deg2rad(1.0)
"""rad: :func:`waterline_angles` are at least this, so that a bound relative to the parent's is never one on
zero or a negative angle (a waterline that widens at its very end)."""


def _end_angles(x, y):
    """Half-angles [rad] of a waterline ``y (n,)`` [m] at stations ``x (n,)`` [m] at its aft and fore ends: the
    chord from where it leaves the centreline (or from the end station, a transom) to the next station."""
    n = x.shape[0]
    wet = jax.lax.stop_gradient(y > MERGE)
    idx = jnp.arange(n)
    first = jnp.min(jnp.where(wet, idx, n - 1))
    last = jnp.max(jnp.where(wet, idx, 0))
    a = jnp.clip(first - 1, 0, n - 2)
    f = jnp.clip(last + 1, 1, n - 1)
    run = jnp.arctan2(y[a + 1] - y[a], x[a + 1] - x[a])
    entrance = jnp.arctan2(y[f - 1] - y[f], x[f] - x[f - 1])
    return jnp.stack([entrance, run])


def waterlines(hulls: list[Sections], draft: Draft,
               above: int = 0) -> tuple[Float[Array, " h"], list[Float[Array, "n h"]]]:
    """The waterlines of hulls at the heights :data:`WATERLINE_FRACTIONS` of the draft above the lowest keel
    among them (one set of heights, so that a design and its parent compare line by line), then ``above`` more
    evenly spaced between the DWL and the lowest deck among them (where a bow change above the water shows).

    Parameters
    ----------
    hulls : list of Sections
        The hulls: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m] each.
    draft : float or Array, scalar
        Waterline height [m above the baseline].
    above : int, static
        How many waterlines above the DWL: at ``T + (D − T)·j/(above + 1)``, j = 1 … above, D the lowest
        hull's top (its deck at side).

    Returns
    -------
    z : Array, (h,)
        The heights [m above the baseline], h = 6 + ``above`` (the keel's and deck's taken as fixed: no
        gradient through them).
    y : list of Array, (n, h) each
        Each hull's half-breadths [m] at its stations and those heights.
    """
    keel = jax.lax.stop_gradient(jnp.min(jnp.stack([jnp.min(s.yz[..., 1]) for s in hulls])))
    z = keel + (draft - keel) * jnp.asarray(WATERLINE_FRACTIONS)
    if above:
        deck = jax.lax.stop_gradient(jnp.min(jnp.stack([jnp.max(s.yz[..., 1]) for s in hulls])))
        z = jnp.concatenate([z, draft + (deck - draft) * jnp.arange(1.0, above + 1.0) / (above + 1.0)])
    return z, [level_widths(closed_half_polygon(s.yz), z) for s in hulls]


def waterline_angles(sections: Sections, draft: Draft) -> Float[Array, "2 h"]:
    """Half-angles [rad] of entrance (row 0, at the fore end) and of the run (row 1, at the aft end) of the
    waterlines at the heights :data:`WATERLINE_FRACTIONS` of the draft above the keel; the entrance at the DWL
    (the last column) is the half-angle of entrance iE. Each is the chord from the waterline's end (where it
    leaves the centreline, or the end station where it does not) to the next station: a fuller or blunter end
    raises it; a run's angle beyond about 20° risks separation. Each at least :data:`ANGLE_FLOOR`.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, (2, h)
        Entrance and run half-angles [rad] at each height.
    """
    _, (y,) = waterlines([sections], draft)
    return jnp.maximum(jax.vmap(lambda col: _end_angles(sections.x, col), in_axes=1, out_axes=1)(y), ANGLE_FLOOR)


def entrance_angle(sections: Sections, draft: Draft) -> Float[Array, ""]:
    """The largest waterline half-angle of entrance [rad] over the heights of :func:`waterline_angles`.

    Parameters
    ----------
    sections : Sections
        The hull.
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, scalar
        The bluntest entrance [rad].
    """
    return jnp.max(waterline_angles(sections, draft)[0])


def run_angle(sections: Sections, draft: Draft) -> Float[Array, ""]:
    """The largest waterline half-angle of the run [rad] over the heights of :func:`waterline_angles`.

    Parameters
    ----------
    sections : Sections
        The hull.
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, scalar
        The steepest run [rad].
    """
    return jnp.max(waterline_angles(sections, draft)[1])


def sac_regions(sections: Sections, draft: Draft) -> Float[Array, " 4"]:
    """Σ (A'')² Δx [m] of the sectional-area curve per region of :data:`SAC_REGIONS` (run, aft shoulder, fore
    shoulder, entrance): a sharper shoulder or a hollow run shows in its own region, which
    :func:`sac_roughness` (one sum over the length, ruled by the sharpest feature anywhere) does not tell apart.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, (4,)
        The regions' Σ (A'')² Δx [m]; they add up to :func:`sac_roughness`.
    """
    terms, x = _sac_terms(sections, draft), sections.x
    t = jax.lax.stop_gradient((x[1:-1] - x[0]) / (x[-1] - x[0]))
    edges = [lo for lo, _ in SAC_REGIONS] + [SAC_REGIONS[-1][1]]
    return jnp.stack([jnp.sum(jnp.where((t >= lo) & ((t < hi) | (hi == edges[-1])), terms, 0.0))
                      for lo, hi in SAC_REGIONS])


def unfairness_measure(sections: Sections, draft: Draft | None = None) -> Float[Array, ""]:
    """:func:`~hullopt.fairing.unfairness` as a measure (the draft unused)."""
    return unfairness(sections)


SHAPE_MEASURES = {"unfairness": unfairness_measure, "sac_roughness": sac_roughness,
                  "section_roughness": section_roughness, "section_knuckle": section_knuckle,
                  "station_knuckles": station_knuckles, "waterline_angles": waterline_angles,
                  "entrance_angle": entrance_angle, "run_angle": run_angle, "sac_regions": sac_regions,
                  "dwl_turns": dwl_turns, "section_inflections": section_inflections}
"""The shape measures a design's ``[constraints]`` may name (``name = "<= 2 * parent"``), by name: each
``measure(sections, draft)``. ``station_knuckles``, ``section_inflections``, ``waterline_angles`` and
``sac_regions`` are one value per station, height or region, each held against the parent's same one
(constraints, not report values)."""

ARRAY_MEASURES = ("station_knuckles", "section_inflections", "waterline_angles", "sac_regions")
"""The :data:`SHAPE_MEASURES` with one value per station, height or region: constraints, each item against the
parent's same one, not values a report tables."""

SHAPE_UNITS = {"unfairness": "-", "sac_roughness": "m", "section_roughness": "m⁻³", "section_knuckle": "rad⁴",
         "station_knuckles": "rad⁴", "waterline_angles": "rad", "entrance_angle": "rad", "run_angle": "rad",
               "sac_regions": "m", "dwl_turns": "rad⁴", "section_inflections": "rad²"}
"""The units of :data:`SHAPE_MEASURES` (``"-"``: dimensionless)."""
