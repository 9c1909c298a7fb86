"""The geometry kernel: a hull as a stack of half-sections, and exact integrals over them.

Conventions (DESIGN.md §2): x forward from the aft perpendicular (AP), y to port (half-breadths ≥ 0),
z up from the baseline. Units are metres.

A half-section is a polyline in the (y, z) plane running from the keel (on the centreline, y = 0) around
the bilge to the deck edge. It is closed implicitly by the deck (a horizontal segment back to y = 0) and by
the centreline (y = 0) down to the keel. Disjoint parts (a bulb below the forefoot) are joined by segments on
the centreline, and a section that starts above the baseline simply repeats points on the centreline: such
segments add nothing to any integral here (they have y = 0), so every hull keeps a fixed (n, m) size.

Every integral of the part below a waterline z = T is a sum over polygon edges of a closed-form integral
restricted to z ≤ T (Green's theorem): the waterline itself and the centreline contribute nothing. This is
exact for the polyline and differentiable in the vertices and in T.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float

from .._types import Draft, Length, Lengths, Offsets, Stations
from ._safe import safe_div


class Sections(eqx.Module):
    """A hull as ``n`` stations of half-section polylines with ``m`` points each.

    Attributes
    ----------
    x : (n,) float
        Station positions [m], strictly increasing, from the AP, forward positive.
    yz : (n, m, 2) float
        Half-section polylines, ``yz[i, j] = (y, z)`` [m], from the keel (``y = 0``) to the deck edge.
    lpp : () float
        Length between perpendiculars [m]; the FP is at ``x = lpp``.
    """

    x: Stations  # numpy where a model is built without running JAX, JAX under transforms
    yz: Offsets
    lpp: Length

    @property
    def n(self) -> int:
        return self.yz.shape[-3]

    @property
    def m(self) -> int:
        return self.yz.shape[-2]

    @property
    def depth(self) -> Float[Array, ""]:
        """Highest point of the hull above the baseline [m]."""
        return jnp.max(self.yz[..., 1])

    @property
    def keel(self) -> Float[Array, ""]:
        """Lowest point of the hull [m] (below 0 for a sonar dome or a bulb under the baseline)."""
        return jnp.min(self.yz[..., 1])

    @property
    def max_half_breadth(self) -> Float[Array, ""]:
        return jnp.max(self.yz[..., 0])


def closed_half_polygon(yz: Float[ArrayLike, "... m 2"]) -> Float[Array, "... m+1 2"]:
    """Close half-sections: append the deck's centreline point ``(0, z_deck_edge)``.

    The closing edge from that point back to the keel runs down the centreline.

    Parameters
    ----------
    yz : array_like, (..., m, 2) float
        Half-section polylines ``(y, z)`` [m], keel to deck edge.

    Returns
    -------
    Array, (..., m+1, 2) float
        The same points followed by ``(0, z_deck_edge)`` [m].
    """
    deck_centre = jnp.stack([jnp.zeros_like(yz[..., -1, 1]), yz[..., -1, 1]], axis=-1)
    return jnp.concatenate([yz, deck_centre[..., None, :]], axis=-2)


class EdgeIntegrals(eqx.Module):
    """Per-edge line integrals over the part of each edge at or below the level (Green's theorem forms).

    ``area = ∮ y dz``, ``moment_z = ∮ y z dz``, ``moment_y = ∮ y²/2 dz``, and ``width``, the signed
    crossing of the level (+y going up, −y going down); summed over a closed polygon ordered
    counter-clockwise in (y, z) these give the area below the level, its first moments about z = 0 and
    y = 0, and the width of the region at the level.
    """

    area: Float[Array, "*edges"]
    moment_z: Float[Array, "*edges"]
    moment_y: Float[Array, "*edges"]
    width: Float[Array, "*edges"]


def clipped_edge_integrals(p0: Array, p1: Array, level: Array) -> EdgeIntegrals:
    """Closed-form integrals of edges ``p0 → p1`` (``(..., 2)`` arrays of (y, z)) clipped to ``z ≤ level``.

    Parameters
    ----------
    p0, p1 : Array, (..., 2) float
        Start and end points ``(y, z)`` [m] of each edge, broadcast together.
    level : Array, float
        The clipping height ``z`` [m], broadcast with the edges' shape ``(...)``.

    Returns
    -------
    EdgeIntegrals
        Per edge, shape ``(...)``: ``area`` [m²], ``moment_z`` and ``moment_y`` [m³], ``width`` [m] (signed).
    """
    y0, z0 = p0[..., 0], p0[..., 1]
    y1, z1 = p1[..., 0], p1[..., 1]
    dz = z1 - z0
    crosses = (z0 - level) * (z1 - level) < 0.0
    s = safe_div(level - z0, dz, crosses)  # crossing parameter along the edge
    yc = y0 + s * (y1 - y0)
    # Each end is either kept (below the level) or moved to the crossing point; an edge wholly above
    # collapses to a point and contributes nothing.
    below0, below1 = z0 <= level, z1 <= level
    a_y = jnp.where(below0, y0, yc)
    a_z = jnp.where(below0, z0, level)
    b_y = jnp.where(below1, y1, yc)
    b_z = jnp.where(below1, z1, level)
    both_above = ~below0 & ~below1
    a_y, b_y = jnp.where(both_above, 0.0, a_y), jnp.where(both_above, 0.0, b_y)
    a_z, b_z = jnp.where(both_above, level, a_z), jnp.where(both_above, level, b_z)
    h = b_z - a_z
    area = 0.5 * h * (a_y + b_y)
    moment_z = h / 6.0 * (2 * a_y * a_z + a_y * b_z + b_y * a_z + 2 * b_y * b_z)
    moment_y = h / 6.0 * (a_y**2 + a_y * b_y + b_y**2)
    # Width: an edge counts where lo < level ≤ hi (its upper end included, its lower end not), so a vertex
    # on the level is counted once and every width is its limit from below — at the deck-edge height the
    # waterline is the deck edge's breadth, as the deck closes the section.
    up_to = (jnp.minimum(z0, z1) < level) & (level <= jnp.maximum(z0, z1))
    sw = safe_div(level - z0, dz, up_to)
    width = jnp.where(up_to, jnp.sign(dz) * (y0 + sw * (y1 - y0)), 0.0)
    return EdgeIntegrals(area, moment_z, moment_y, width)


def level_widths(poly: Float[ArrayLike, "... k 2"], levels: Float[ArrayLike, " K"]) -> Float[Array, "... K"]:
    """Widths of closed polygons at many ``levels``: ``polygon_integrals(poly, z).width`` for each ``z``
    (the same crossing rule, equal to rounding), computed for many levels at once — the slope of each edge
    once, then per level a crossing test and one multiply-add, with the edges on the leading axis so that
    the sum over them is elementwise (which matters under ``vmap``).

    Parameters
    ----------
    poly : array_like, (..., k, 2) float
        Closed polygons ``(y, z)`` [m] (last point joins the first), e.g. from :func:`closed_half_polygon`.
    levels : array_like, (K,) float
        Heights ``z`` [m].

    Returns
    -------
    Array, (..., K) float
        The polygons' widths [m] at each level (a half-section's half-breadth).
    """
    p1 = jnp.roll(poly, -1, axis=-2)
    y0, z0, y1, z1 = (jnp.moveaxis(q, -1, 0)[..., None] for q in (poly[..., 0], poly[..., 1], p1[..., 0], p1[..., 1]))
    dz = z1 - z0
    moving = dz != 0
    sg = jnp.sign(dz)
    # per edge (before broadcasting to the levels): signed start, signed slope, z range, signed half ends
    a, b = sg * y0, sg * safe_div(y1 - y0, dz, moving)
    lo, hi = jnp.minimum(z0, z1), jnp.maximum(z0, z1)
    lv = jnp.asarray(levels)
    width = jnp.where((lo < lv) & (lv <= hi), a + (lv - z0) * b, 0.0)  # the crossing rule of clipped_edge_integrals
    return jnp.sum(width, axis=0)


def polygon_integrals(poly: Float[ArrayLike, "... k 2"], level: Lengths) -> EdgeIntegrals:
    """Sum of :func:`clipped_edge_integrals` over the edges of closed polygons (last point joins the first).

    Parameters
    ----------
    poly : array_like, (..., k, 2) float
        Closed polygons ``(y, z)`` [m], ordered counter-clockwise (last point joins the first).
    level : float or array_like, (...)
        Clipping height ``z`` [m], scalar or one per polygon.

    Returns
    -------
    EdgeIntegrals
        Sums over the edges, each ``(...)``: ``area`` [m²] below the level, ``moment_z`` and ``moment_y`` [m³],
        ``width`` [m] at the level.
    """
    p1 = jnp.roll(poly, -1, axis=-2)
    e = clipped_edge_integrals(poly, p1, jnp.asarray(level)[..., None])
    # one sum of the four stacked: XLA then clips each edge once, not once per sum (run and compile)
    sums = jnp.sum(jnp.stack([e.area, e.moment_z, e.moment_y, e.width], -1), axis=-2)
    return EdgeIntegrals(*jnp.moveaxis(sums, -1, 0))


def section_integrals(sections: Sections, draft: Draft) -> EdgeIntegrals:
    """Half-section integrals below the waterline ``z = draft`` at every station, each ``(n,)``.

    ``area`` [m²] (one side), ``moment_z`` = ∫ z dA [m³], ``moment_y`` = ∫ y dA [m³], ``width`` = the
    waterline half-breadth [m] (summed over every crossing, so bulbs and tumblehome come out right).

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    EdgeIntegrals
        ``area``, ``moment_z``, ``moment_y``, ``width``, each ``(n,)``, units as above.
    """
    return polygon_integrals(closed_half_polygon(sections.yz), draft)


def section_necks(sections: Sections, draft: Draft) -> Float[Array, " n"]:
    """Each station's neck under the waterline [m]: how much narrower its outline gets above a wider part of it
    below ``draft`` (max over its points of the running maximum half-breadth from the keel minus the
    half-breadth). 0 for a section that only widens from the keel up; a bulb's neck is its width less the
    section's at its waist. No gradient (a shape class, not a measure to optimise).

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m, keel to deck].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, (n,)
        The necks [m], ≥ 0.
    """
    yz = jax.lax.stop_gradient(sections.yz)
    y, z = yz[..., 0], yz[..., 1]
    narrowing = jnp.where(z < jnp.asarray(draft, dtype=y.dtype), jax.lax.cummax(y, axis=1) - y, 0.0)
    return jnp.max(narrowing, axis=1)
