"""Above-water geometry: the hull above the waterline (from :class:`~hullopt.geometry.Sections`) plus named
superstructure and deck-cargo parts, as lateral (side) and frontal projections.

Coordinates (DESIGN.md §2): x forward from the AP, y to port, z up. Parts are given with z from the baseline;
projections are returned with heights ``h = z − T`` above the waterline, so every wind variable is measured
from the waterline. Polygons are counter-clockwise ``(k, 2)`` arrays; shorter ones are padded by repeating
their last vertex (a zero-length edge adds nothing to any integral), so parts stack into fixed-size arrays.
"""

from __future__ import annotations

from collections.abc import Sequence

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import numpy.typing as npt
from jaxtyping import Array, Bool, Float

from .._types import Draft, Lengths, Polygon
from ..errors import HullError
from ..geometry import SAME_POINT, Sections, closed_half_polygon, level_widths

KINDS = ("superstructure", "cargo", "mast")
"""Part kinds: ``superstructure`` (bridge, deckhouse, funnel: A_SS, C_BR, H_BR), ``cargo`` (containers, hatch
covers, tanks, cranes: in A_OD only) and ``mast`` (masts, king posts: slender, left out of the outline length S
and counted in mast groups M)."""


class Parts(eqx.Module):
    """Named above-deck parts, each a convex polygon in the side view and one in the front view.

    Attributes
    ----------
    side : (p, ks, 2) float
        Lateral projections ``(x, z)`` [m]: x from the AP, z from the baseline; counter-clockwise.
    front : (p, kf, 2) float
        Frontal projections ``(y, z)`` [m]: y to port, z from the baseline; counter-clockwise.
    names, kinds, groups : tuple of str (static)
        Part names, kinds (see :data:`KINDS`) and mast-group labels (masts with one label count once in M).
    """

    side: Float[Array, "p ks 2"]
    front: Float[Array, "p kf 2"]
    names: tuple[str, ...] = eqx.field(static=True)
    kinds: tuple[str, ...] = eqx.field(static=True)
    groups: tuple[str, ...] = eqx.field(static=True)

    @property
    def p(self) -> int:
        return len(self.names)


def no_parts() -> Parts:
    """The bare hull: no parts.

    Returns
    -------
    Parts
        Parts with p = 0: ``side`` and ``front`` of shape (0, 4, 2), empty names.
    """
    return Parts(jnp.zeros((0, 4, 2)), jnp.zeros((0, 4, 2)), (), (), ())


def _check_meta(names, kinds, groups) -> tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
    names, kinds = tuple(names), tuple(kinds)
    groups = tuple(groups) if groups is not None else tuple(n if k == "mast" else "" for n, k in zip(names, kinds))
    if not (len(names) == len(kinds) == len(groups)):
        raise HullError(f"parts: {len(names)} names, {len(kinds)} kinds and {len(groups)} groups must match")
    for n, k in zip(names, kinds):
        if k not in KINDS:
            raise HullError(f"part {n!r}: unknown kind {k!r}; expected one of {', '.join(KINDS)}")
    if len(set(names)) != len(names) or "hull" in names:
        raise HullError("parts: names must be unique and not 'hull'")
    return names, kinds, groups


def box_parts(names: Sequence[str], kinds: Sequence[str], x_aft: Lengths, x_fore: Lengths, z_low: Lengths,
              z_top: Lengths, breadth: Lengths, y_centre: Lengths = 0.0, groups: Sequence[str] | None = None) -> Parts:
    """Rectangular parts (boxes), differentiable in their sizes: each argument is a scalar or ``(p,)`` [m].

    ``x_aft < x_fore`` from the AP, ``z_low < z_top`` from the baseline, full ``breadth`` centred on
    ``y_centre`` (to port). Mast groups default to one group per mast.

    Parameters
    ----------
    names : sequence of str
        p unique part names (not ``"hull"``).
    kinds : sequence of str
        Each part's kind, one of :data:`KINDS`.
    x_aft, x_fore : float or (p,) float
        Aft and forward ends [m from the AP].
    z_low, z_top : float or (p,) float
        Bottom and top [m above the baseline].
    breadth : float or (p,) float
        Full breadth [m].
    y_centre : float or (p,) float
        Centre of the breadth [m], to port positive.
    groups : sequence of str or None
        Mast-group labels; None: each mast its own group, "" for the other kinds.

    Returns
    -------
    Parts
        ``side`` and ``front`` rectangles of shape (p, 4, 2) [m].

    Raises
    ------
    HullError
        If the names, kinds and groups differ in number, a kind is unknown, or a name repeats or is ``"hull"``.
    """
    names, kinds, groups = _check_meta(names, kinds, groups)
    p = len(names)
    x0, x1, z0, z1, b, yc = (jnp.broadcast_to(jnp.asarray(v, dtype=float), (p,))
                             for v in (x_aft, x_fore, z_low, z_top, breadth, y_centre))

    def rect(u0, u1):
        return jnp.stack([jnp.stack([u0, z0], -1), jnp.stack([u1, z0], -1),
                          jnp.stack([u1, z1], -1), jnp.stack([u0, z1], -1)], axis=-2)

    return Parts(rect(x0, x1), rect(yc - b / 2, yc + b / 2), names, kinds, groups)


def _ccw_convex(poly: npt.ArrayLike, what: str) -> np.ndarray:
    poly = np.asarray(poly, dtype=float)
    if poly.ndim != 2 or poly.shape[1] != 2 or len(poly) < 3 or not np.all(np.isfinite(poly)):
        raise HullError(f"{what}: expected at least 3 finite [u, z] points")
    d = np.roll(poly, -1, axis=0) - poly
    area2 = np.sum(poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1])
    if abs(area2) <= 1e-12 * max(1.0, np.abs(poly).max()) ** 2:
        raise HullError(f"{what}: the polygon has no area")
    if area2 < 0:
        poly, d = poly[::-1], np.roll(poly[::-1], -1, axis=0) - poly[::-1]
    cross = d[:, 0] * np.roll(d[:, 1], -1) - d[:, 1] * np.roll(d[:, 0], -1)
    if np.any(cross < -SAME_POINT * np.abs(d).max() ** 2):
        raise HullError(f"{what}: the polygon must be convex (split a non-convex shape into convex parts)")
    return poly


def _pad(polys: list[np.ndarray]) -> np.ndarray:
    k = max(len(p) for p in polys)
    return np.stack([np.concatenate([p, np.repeat(p[-1:], k - len(p), axis=0)]) for p in polys])


def polygon_parts(names: Sequence[str], kinds: Sequence[str], sides: Sequence[Polygon], fronts: Sequence[Polygon],
                  groups: Sequence[str] | None = None) -> Parts:
    """Parts from convex polygons (static input, e.g. a config): ``sides[i]`` is a list of ``(x, z)`` [m]
    and ``fronts[i]`` a list of ``(y, z)`` [m] (z from the baseline); either orientation is accepted.

    Parameters
    ----------
    names : sequence of str
        p unique part names (not ``"hull"``).
    kinds : sequence of str
        Each part's kind, one of :data:`KINDS`.
    sides : sequence of (k_i, 2) array_like
        Side-view convex polygons ``(x, z)`` [m from the AP, m above the baseline], k_i ≥ 3.
    fronts : sequence of (k_i, 2) array_like
        Front-view convex polygons ``(y, z)`` [m to port, m above the baseline], k_i ≥ 3.
    groups : sequence of str or None
        Mast-group labels; None: each mast its own group, "" for the other kinds.

    Returns
    -------
    Parts
        Counter-clockwise polygons padded to shape (p, k, 2), k the largest k_i of each view.

    Raises
    ------
    HullError
        If the metadata disagree (see :func:`box_parts`) or a polygon is too short, not finite, flat or not convex.
    """
    names, kinds, groups = _check_meta(names, kinds, groups)
    if not names:
        return no_parts()
    side = [_ccw_convex(s, f"part {n!r} side") for n, s in zip(names, sides)]
    front = [_ccw_convex(f, f"part {n!r} front") for n, f in zip(names, fronts)]
    return Parts(jnp.asarray(_pad(side)), jnp.asarray(_pad(front)), names, kinds, groups)


def concat_parts(*parts: Parts) -> Parts:
    """Join several :class:`Parts` (their polygons are padded to one size).

    Parameters
    ----------
    *parts : Parts
        The sets to join, in order.

    Returns
    -------
    Parts
        All their parts (:func:`no_parts` if none), polygons padded to the largest vertex count of each view.

    Raises
    ------
    HullError
        If the joined names repeat.
    """
    parts = [p for p in parts if p.p]
    if not parts:
        return no_parts()

    def pad(a, k):
        return jnp.concatenate([a, jnp.repeat(a[:, -1:], k - a.shape[1], axis=1)], axis=1)

    ks, kf = max(p.side.shape[1] for p in parts), max(p.front.shape[1] for p in parts)
    names, kinds, groups = _check_meta(sum((p.names for p in parts), ()), sum((p.kinds for p in parts), ()),
                                       sum((p.groups for p in parts), ()))
    return Parts(jnp.concatenate([pad(p.side, ks) for p in parts]), jnp.concatenate([pad(p.front, kf) for p in parts]),
                 names, kinds, groups)


class Projections(eqx.Module):
    """Lateral and frontal projections above the waterline; heights ``h = z − T`` [m].

    ``hull_side`` (2n, 2) is the hull profile ``(x, h)`` above the waterline: along the waterline (or the
    underside of an overhang) forward, back along the deck line with its sheer; stations below water give
    zero-height vertices. ``hull_front`` (2K+2, 2) is ``(y, h)``, the envelope of the half-breadths of all
    stations at K+1 levels from the waterline to the highest deck (mirrored). ``part_side``/``part_front``
    are the parts' polygons with heights above the waterline. ``present`` (n,) marks the stations that
    bound some of the profile above water.
    """

    hull_side: Float[Array, "v 2"]
    hull_front: Float[Array, "w 2"]
    part_side: Float[Array, "p ks 2"]
    part_front: Float[Array, "p kf 2"]
    present: Bool[Array, " n"]
    draft: Float[Array, ""]
    parts: Parts


def _level_half_breadths(sections: Sections, levels) -> Array:
    """Envelope over stations of the half-breadth at each level (sum over the crossings of a station)."""
    return jnp.max(level_widths(closed_half_polygon(sections.yz), levels), axis=0)


def projections(sections: Sections, draft: Draft, parts: Parts, levels: int = 24) -> Projections:
    """Side and front projections of the hull above ``z = draft`` and of the parts (see :class:`Projections`).

    The profile at a station spans from ``max(T, lowest point)`` to ``max(T, highest point)`` of its
    half-section and is linear between stations. The frontal hull outline uses ``levels`` + 1 levels (the
    top one just under the highest deck edge); its area converges as ``levels`` grows (exact for wall sides).

    Parameters
    ----------
    sections : Sections
        The hull's n stations (x [m from the AP], z [m above the baseline]).
    draft : float or Array
        Draft T [m above the baseline] (scalar).
    parts : Parts
        The above-deck parts (p of them).
    levels : int
        Level intervals K of the frontal hull outline.

    Returns
    -------
    Projections
        ``hull_side`` (2n, 2), ``hull_front`` (2K + 2, 2), ``part_side``, ``part_front`` (p, k, 2) [m], heights
        above the waterline; ``present`` (n,) bool; ``draft`` [m].
    """
    t = jnp.asarray(draft, dtype=float)
    z = sections.yz[..., 1]
    bot = jnp.maximum(jnp.min(z, axis=1), t)
    top = jnp.maximum(jnp.max(z, axis=1), bot)
    side = jnp.concatenate([jnp.stack([sections.x, bot - t], -1), jnp.stack([sections.x, top - t], -1)[::-1]])
    above = top > bot
    present = above | jnp.roll(above, 1).at[0].set(False) | jnp.roll(above, -1).at[-1].set(False)
    deck = jnp.max(top)
    s = jnp.linspace(0.0, 1.0, levels + 1)
    hs = (deck - t) * s
    w = _level_half_breadths(sections, t + (deck - t) * jnp.clip(s, 1e-9, 1.0 - 1e-9))
    front = jnp.concatenate([jnp.stack([w, hs], -1), jnp.stack([-w, hs], -1)[::-1]])
    shift = jnp.array([0.0, 1.0]) * t
    return Projections(side, front, parts.side - shift, parts.front - shift, present, t, parts)


def check_parts(sections: Sections, draft: float, parts: Parts) -> None:
    """Static sanity checks (numpy): every part above the waterline, within the hull's length above water
    and within its breadth; :class:`HullError` naming the part otherwise.

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    draft : float
        Draft T [m above the baseline].
    parts : Parts
        The above-deck parts.

    Returns
    -------
    None

    Raises
    ------
    HullError
        If the hull is wholly under water, or a part lies below the waterline, beyond the hull's length above
        water or beyond its half-breadth.
    """
    pr = projections(sections, draft, parts)
    front = np.asarray(pr.hull_front)
    xs = np.asarray(sections.x)[np.asarray(pr.present)]
    if xs.size == 0:
        raise HullError(f"draft {draft:g} m: the hull is wholly under water")
    x_lo, x_hi = xs.min(), xs.max()
    half_b = np.abs(front[:, 0]).max()
    tol = 1e-6 * max(float(sections.lpp), 1.0)
    for i, name in enumerate(parts.names):
        ps, pf = np.asarray(pr.part_side[i]), np.asarray(pr.part_front[i])
        if ps[:, 1].min() < -tol or pf[:, 1].min() < -tol:
            raise HullError(f"part {name!r} reaches {-min(ps[:, 1].min(), pf[:, 1].min()):.3g} m below the "
                            f"waterline (T = {draft:g} m): parts must lie above water")
        if ps[:, 0].min() < x_lo - tol or ps[:, 0].max() > x_hi + tol:
            raise HullError(f"part {name!r} spans x = {ps[:, 0].min():g}…{ps[:, 0].max():g} m, outside the ship "
                            f"({x_lo:g}…{x_hi:g} m from the AP above water)")
        if np.abs(pf[:, 0]).max() > half_b + tol:
            raise HullError(f"part {name!r} reaches y = ±{np.abs(pf[:, 0]).max():g} m, outside the ship "
                            f"(half-breadth {half_b:g} m)")
