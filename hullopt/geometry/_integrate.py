"""Integrals along the length: Simpson weights for stations at arbitrary (increasing) positions, and the
longitudinal integrals of a hull at a draft (∇, LCB, KB, the waterplane) that every analysis shares."""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float

from .._types import Draft
from ._safe import safe_div, safe_sqrt
from ._sections import Sections, closed_half_polygon, polygon_integrals, section_integrals


def simpson_weights(x: Float[ArrayLike, " n"]) -> Float[Array, " n"]:
    """Weights ``w`` with ``∫ f dx ≈ w @ f`` by composite Simpson's rule on uneven spacing.

    Exact for quadratics (so for the sectional-area curve of a Wigley hull). Pairs of intervals use
    the uneven three-point rule; with an odd number of intervals the last one is integrated with the
    parabola through the last three points (as ``scipy.integrate.simpson``). ``n`` must be ≥ 2; with
    ``n = 2`` this is the trapezoidal rule.

    Parameters
    ----------
    x : array_like, (n,) float
        Strictly increasing positions [m] (any unit), ``n ≥ 2``.

    Returns
    -------
    Array, (n,) float
        Quadrature weights, in the unit of ``x``.
    """
    x = jnp.asarray(x)
    n = x.shape[0]
    if n < 2:
        raise ValueError(f"need at least 2 stations to integrate, got {n}")
    if n == 2:
        return jnp.full(2, 0.5 * (x[1] - x[0]))
    # interleaved, not scattered: a strided scatter-add is a loop in XLA:CPU, compiled and run (same sums)
    n_simpson = n if n % 2 == 1 else n - 1  # points covered by pairs of intervals
    h = jnp.diff(x[:n_simpson])
    h0, h1 = h[0::2], h[1::2]
    hs = h0 + h1
    zero = jnp.zeros(1, dtype=x.dtype)
    even = jnp.concatenate([hs / 6.0 * (2.0 - h1 / h0), zero]) + jnp.concatenate([zero, hs / 6.0 * (2.0 - h0 / h1)])
    odd = hs / 6.0 * hs**2 / (h0 * h1)
    w = jnp.concatenate([jnp.stack([even[:-1], odd], -1).reshape(-1), even[-1:]])
    if n_simpson < n:
        h0, h1 = x[-2] - x[-3], x[-1] - x[-2]
        tail = jnp.stack([-(h1**3) / (6 * h0 * (h0 + h1)), (h1**2 + 3 * h0 * h1) / (6 * h0),
                          (2 * h1**2 + 3 * h0 * h1) / (6 * (h0 + h1))])
        w = jnp.concatenate([w, zero]) + jnp.concatenate([jnp.zeros(n - 3, dtype=x.dtype), tail])
    return w


def simpson_weights_between(x: Float[ArrayLike, " n"], lo: Float[ArrayLike, ""],
                            hi: Float[ArrayLike, ""]) -> Float[Array, " n"]:
    """Weights ``w`` with ``∫_lo^hi f dx ≈ w @ f``: :func:`simpson_weights`'s rule restricted to ``[lo, hi]``.

    Each of that rule's pieces — a pair of intervals, or the last interval of an odd count, each with the
    parabola through its three stations (``n = 2``: the line through both) — is integrated exactly over its
    part inside ``[lo, hi]``, so the weights are the rule's own where the range covers the stations, and a
    range that starts or ends between stations takes its share of the piece's parabola there: exact for a
    quadratic ``f``, continuous and piecewise polynomial in ``lo``, ``hi`` and the stations (so a bound
    between stations moves smoothly as the stations move; ``∂/∂lo = −`` the piece's parabola at ``lo``).
    Outside the stations ``f`` is taken as 0; an empty range (``hi ≤ lo``) gives zeros.

    Parameters
    ----------
    x : array_like, (n,) float
        Strictly increasing positions [m] (any unit), ``n ≥ 2``.
    lo, hi : float or Array, scalar
        The range [m] (the unit of ``x``); ``-inf`` / ``inf`` for none.

    Returns
    -------
    Array, (n,) float
        Quadrature weights, in the unit of ``x``.
    """
    x = jnp.asarray(x)
    n = x.shape[0]
    if n < 2:
        raise ValueError(f"need at least 2 stations to integrate, got {n}")
    lo = jnp.asarray(lo, dtype=x.dtype)
    hi = jnp.maximum(jnp.asarray(hi, dtype=x.dtype), lo)

    def part(a, b):  # each piece's [a, b] ∩ [lo, hi], from a: (t0, t1) ≥ 0
        return jnp.clip(lo, a, b) - a, jnp.clip(hi, a, b) - a

    if n == 2:
        t0, t1 = part(x[0], x[1])
        h = x[1] - x[0]
        return jnp.stack([(t1 - t0) - (t1**2 - t0**2) / (2 * h), (t1**2 - t0**2) / (2 * h)])

    def quad(c1, c2, t0, t1):  # ∫_t0^t1 (t − c1)(t − c2) dt
        f = lambda t: t**3 / 3.0 - (c1 + c2) * t**2 / 2.0 + c1 * c2 * t  # noqa: E731
        return f(t1) - f(t0)

    def piece(x0, x1, x2, a, b):  # the Lagrange weights of the parabola through x0, x1, x2 over [a, b]
        h0, h1 = x1 - x0, x2 - x1
        hs = h0 + h1
        t0, t1 = part(a, b)
        t0, t1 = t0 + (a - x0), t1 + (a - x0)  # from x0
        return quad(h0, hs, t0, t1) / (h0 * hs), -quad(0.0, hs, t0, t1) / (h0 * h1), quad(0.0, h0, t0, t1) / (hs * h1)

    n_simpson = n if n % 2 == 1 else n - 1
    x0, x1, x2 = x[0:n_simpson - 2:2], x[1:n_simpson - 1:2], x[2:n_simpson:2]
    w0, w1, w2 = piece(x0, x1, x2, x0, x2)
    zero = jnp.zeros(1, dtype=x.dtype)
    even = jnp.concatenate([w0, zero]) + jnp.concatenate([zero, w2])
    w = jnp.concatenate([jnp.stack([even[:-1], w1], -1).reshape(-1), even[-1:]])
    if n_simpson < n:  # the last interval: the parabola through the last three stations
        tail = jnp.stack(piece(x[-3], x[-2], x[-1], x[-2], x[-1]))
        w = jnp.concatenate([w, zero]) + jnp.concatenate([jnp.zeros(n - 3, dtype=x.dtype), tail])
    return w


def region_volume(sections: Sections, draft: Draft, x_a: Float[ArrayLike, ""] = -jnp.inf,
                  x_b: Float[ArrayLike, ""] = jnp.inf, z_top: Float[ArrayLike, ""] = jnp.inf) -> Array:
    """The displaced volume [m³] of a region of the hull: forward of ``x_a``, aft of ``x_b`` and below
    ``z_top`` (and the waterline ``z = draft``), both sides — e.g. a sonar dome or a bulb's volume.

    ``∫_{x_a}^{x_b} A(x) dx`` with ``A`` each station's exact area below ``min(z_top, draft)``
    (:func:`section_integrals`) and the longitudinal rule of ∇ (:func:`simpson_weights`) restricted to the
    range (:func:`simpson_weights_between`: a range that starts between stations takes the share of the
    quadrature's parabola there, so the volume is continuous and smooth in ``x_a`` as the stations move).
    With no range and ``z_top ≥ draft`` it is the hull's ∇ of :func:`longitudinal_integrals`, to round-off.
    Pure JAX: jit/vmap/grad in the geometry, the draft and the region.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height [m above the baseline].
    x_a, x_b : float or Array, scalar
        The region's aft and forward ends [m from the AP]; default none (``-inf``, ``inf``).
    z_top : float or Array, scalar
        Its top [m above the baseline]; default none (the waterline).

    Returns
    -------
    Array, scalar
        The region's displaced volume [m³].
    """
    level = jnp.minimum(jnp.asarray(z_top, dtype=sections.yz.dtype), jnp.asarray(draft, dtype=sections.yz.dtype))
    area = 2.0 * section_integrals(sections, level).area
    return simpson_weights_between(sections.x, x_a, x_b) @ area


def volume_lcb(x: Float[ArrayLike, " n"], area: Float[ArrayLike, " n"]) -> tuple[Array, Array]:
    """Volume ``∫A dx`` [m³] and its centroid ``∫xA dx / ∫A dx`` [m from the AP] of the sectional-area curve
    ``area`` at stations ``x`` (Simpson's rule, :func:`simpson_weights`): the rule of
    :func:`longitudinal_integrals`, for areas held while the stations move (a Lackenby shift).

    Parameters
    ----------
    x : array_like, (n,) float
        Station positions [m from the AP], strictly increasing.
    area : array_like, (n,) float
        Full-section immersed areas [m²] at the stations.

    Returns
    -------
    volume : Array, scalar
        ``∫A dx`` [m³].
    lcb : Array, scalar
        ``∫xA dx / ∫A dx`` [m from the AP] (not guarded: NaN or inf where the volume is 0).
    """
    w = simpson_weights(x)
    volume = w @ area
    return volume, (w @ (x * area)) / volume


def _centre_waterline_distance(yz: Array, level: Array) -> Array:
    """Distance [m] from the point ``(0, level)`` to each section's surface edges ``(n,)``: the edges of the
    half-section polyline off the centre plane (all of them for a section wholly in the centre plane, a stem).
    """
    p0, p1 = yz[..., :-1, :], yz[..., 1:, :]
    knife = jnp.all(yz[..., 0] == 0.0, axis=-1, keepdims=True)
    surface = ~((p0[..., 0] == 0.0) & (p1[..., 0] == 0.0)) | knife
    e = p1 - p0
    w = jnp.stack([-p0[..., 0], level - p0[..., 1]], axis=-1)
    ee = jnp.sum(e * e, axis=-1)
    s = jnp.clip(safe_div(jnp.sum(w * e, axis=-1), ee, ee > 0.0), 0.0, 1.0)
    r = w - s[..., None] * e
    d2 = jnp.min(jnp.where(surface, jnp.sum(r * r, axis=-1), jnp.inf), axis=-1)
    return safe_sqrt(jnp.where(jnp.isfinite(d2), d2, 0.0))


def waterline_ends(x: ArrayLike, yz: ArrayLike, half_breadth: ArrayLike, level: ArrayLike) -> tuple[Array, Array]:
    """The aft and forward ends [m from the AP] of the waterline ``z = level``: where it meets the stern and
    stem profiles, between the last station with a waterline (``half_breadth > 0``) and its dry neighbour.

    Each station gets ``φ``, the distance from the centre plane's waterline point ``(0, level)`` to its
    surface, positive where the station has a waterline. Outside the hull ``φ`` grows about linearly with the
    distance from the end (the gap under a counter, above a bulb, below a raked stem), so the end is where
    the line through the first two dry stations reaches 0, kept between the wet and the dry station; where
    there is no second dry station, or ``φ`` does not grow, ``φ`` is interpolated across the wet and the dry
    station. A wet end station is the end (a transom; a box); a section wholly in the centre plane (a
    stem, the Wigley's) has ``φ = 0`` and is the end. Both ends are 0 where nothing is wet.
    """
    n = x.shape[0]
    wet = half_breadth > 0.0
    phi = jnp.where(wet, 1.0, -1.0) * _centre_waterline_distance(yz, level)
    first = jnp.argmax(wet)
    last = n - 1 - jnp.argmax(wet[::-1])

    def end(a, step):  # a: the last wet station; step: +1 forward, -1 aft
        b, c = a + step, a + 2 * step
        inside = (b >= 0) & (b <= n - 1)
        has_c = (c >= 0) & (c <= n - 1)
        b, c = jnp.clip(b, 0, n - 1), jnp.clip(c, 0, n - 1)
        xa, xb, xc = x[a], x[b], x[c]
        pa, pb, pc = phi[a], phi[b], phi[c]
        grows = has_c & (pc < pb)  # φ more negative further out
        outer = xb - pb * safe_div(xc - xb, pc - pb, grows)
        lo, hi = jnp.minimum(xa, xb), jnp.maximum(xa, xb)
        across = xa + (xb - xa) * safe_div(pa, pa - pb, pa - pb > 0.0)
        return jnp.where(inside, jnp.clip(jnp.where(grows, outer, across), lo, hi), xa)

    any_wet = jnp.any(wet)
    return jnp.where(any_wet, end(first, -1), 0.0), jnp.where(any_wet, end(last, 1), 0.0)


def transom_area(x: ArrayLike, yz: ArrayLike, level: ArrayLike, rake: float = 1.0) -> Array:
    """The immersed transom area A_T [m²] (Holtrop and Mennen's): the projection on the transverse plane of
    the hull's aft end face below the waterline ``z = level``: vertical, raked or curved.

    A vertical transom at the aftmost station is that station's immersed area (both sides). A raked or
    curved face (steeper than 45° by default) is cut by the stations aft of its lower edge: each of them
    starts at the face, so their bottoms (each section's lowest point) drop by more than ``rake`` × the
    station spacing going forward. The face's lower edge is where the line through the last two such bottoms
    before the run's end meets the bottom profile (the line through the next two bottoms after it), and A_T
    is the hull's section just forward of the face between that edge and the waterline: the largest of the
    three stations from the run's end (a lower edge curved in plan, as the DTMB 5415's, ends further
    forward off the centre plane than on it). Exact for a box with a raked or curved (circular-arc) transom
    (``B·T``) and for a vertical one; 0 where the aft end is dry or there is no steep face there. A rounded
    knuckle at the lower edge, finer than the station spacing, is taken as a sharp corner (on the DTMB 5415,
    +14 % at 201 stations, −3 % at 401, against the mesh's aft faces steeper than 45°).

    Parameters
    ----------
    x : array_like, (n,) float
        Station positions [m from the AP], increasing.
    yz : array_like, (n, m, 2) float
        Half-sections ``(y, z)`` [m], keel to deck.
    level : float or Array, scalar
        Waterline height [m above the baseline].
    rake : float
        The least slope ``dz/dx`` of the bottom profile that counts as the transom face (1: 45°).

    Returns
    -------
    Array, scalar
        A_T [m²], both sides.
    """
    x, yz = jnp.asarray(x), jnp.asarray(yz)
    level = jnp.asarray(level, dtype=yz.dtype)
    n = x.shape[0]
    poly = closed_half_polygon(yz)

    end = 2.0 * polygon_integrals(poly[0], level).area  # a vertical transom at the aftmost station
    if n < 2:
        return end
    bottom = jnp.min(yz[..., 1], axis=-1)  # (n,) each section's lowest point
    dx = jnp.diff(x)
    run = jnp.cumprod(bottom[:-1] - bottom[1:] > rake * dx)  # (n−1,) intervals on the face, from the aft end
    k = jnp.sum(run)  # the run's last station: the face's lower edge lies between it and the next
    take = lambda v, i: v[jnp.clip(i, 0, n - 1)]  # noqa: E731
    # the face through the run's last two stations before k, the bottom through the two after it (station k
    # itself may lie on either), and the face's lower edge where they meet, between stations k − 1 and k + 1
    f0, f1 = jnp.maximum(k - 2, 0), jnp.maximum(k - 1, 1)
    b0, b1 = jnp.minimum(k + 1, n - 2), jnp.minimum(k + 2, n - 1)
    xf0, xf1, xb0, xb1 = take(x, f0), take(x, f1), take(x, b0), take(x, b1)
    zf0, zf1, zb0, zb1 = take(bottom, f0), take(bottom, f1), take(bottom, b0), take(bottom, b1)
    s_face = safe_div(zf0 - zf1, xf1 - xf0, xf1 > xf0)  # the face's drop per metre forward (> rake)
    s_bottom = jnp.where(k + 2 <= n - 1, safe_div(zb0 - zb1, xb1 - xb0, xb1 > xb0), 0.0)  # the bottom's, small
    x_edge = xf1 + safe_div(zf1 - zb0 - s_bottom * (xb0 - xf1), s_face - s_bottom, s_face > s_bottom)
    x_edge = jnp.clip(x_edge, take(x, k - 1), take(x, k + 1))
    z_edge = zb0 + s_bottom * (xb0 - x_edge)  # on the bottom profile (exact where the bottom is straight)
    # the face's projection: the hull's section between the edge and the waterline just forward of the face,
    # the largest of the next stations' (a lower edge curved in plan ends further forward off the centre)
    near = jnp.clip(k + jnp.arange(3), 0, n - 1)
    wet, below_edge = (polygon_integrals(poly[near], z).area for z in (level, jnp.minimum(z_edge, level)))
    above = wet - below_edge
    face = 2.0 * jnp.max(above)
    return jnp.where((k >= 1) & (k + 1 <= n - 1), face, end)


class LongitudinalIntegrals(eqx.Module):
    """The hull's integrals along the length at one draft (both sides; x from the AP), exact per section
    and by Simpson's rule along x — the rules of :func:`hullopt.hydro.hydrostatics`.

    ``area (n,)`` full-section immersed areas [m²] (the sectional-area curve), ``moment_z (n,)`` their
    first moments about the baseline [m³], ``half_breadth (n,)`` waterline half-breadths [m]; ``volume``
    ∇ [m³], ``lcb`` [m], ``kb`` [m]; the waterplane: ``awp`` [m²], ``lcf`` [m], its transverse and
    longitudinal (about the LCF) second moments ``i_t``, ``i_l`` [m⁴], ``bwl`` = 2·max half-breadth; the
    waterline's ends ``x_aft``, ``x_fwd`` [m from the AP] where it meets the stern and stem profiles
    (:func:`waterline_ends`) and ``lwl`` = ``x_fwd − x_aft`` [m]; ``a_transom`` [m²], the immersed transom
    area (Holtrop's A_T, :func:`transom_area`): the transverse projection of the aft end face below the
    waterline, vertical (the aft end station's immersed area), raked or curved; 0 where there is none.
    """

    area: Float[Array, " n"]
    moment_z: Float[Array, " n"]
    half_breadth: Float[Array, " n"]
    volume: Float[Array, ""]
    lcb: Float[Array, ""]
    kb: Float[Array, ""]
    awp: Float[Array, ""]
    lcf: Float[Array, ""]
    i_t: Float[Array, ""]
    i_l: Float[Array, ""]
    bwl: Float[Array, ""]
    lwl: Float[Array, ""]
    x_aft: Float[Array, ""]
    x_fwd: Float[Array, ""]
    a_transom: Float[Array, ""]


def longitudinal_integrals(sections: Sections, draft: Draft) -> LongitudinalIntegrals:
    """:class:`LongitudinalIntegrals` of ``sections`` at the waterline ``z = draft`` [m] (even keel): the
    kernel's :func:`section_integrals` at every station, :func:`simpson_weights` along x. Pure JAX:
    jit/vmap/grad in the geometry and the draft. ``lcb``, ``kb`` and ``lcf`` are 0 where the hull is dry.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    LongitudinalIntegrals
        Per station ``area``, ``moment_z``, ``half_breadth`` ``(n,)``; scalars ``volume``, ``lcb``, ``kb``,
        ``awp``, ``lcf``, ``i_t``, ``i_l``, ``bwl``, ``lwl``, ``x_aft``, ``x_fwd``, ``a_transom`` (units as in
        :class:`LongitudinalIntegrals`).
    """
    t = jnp.asarray(draft, dtype=sections.yz.dtype)
    x = sections.x
    s = section_integrals(sections, t)
    w = simpson_weights(x)
    area = 2.0 * s.area
    moment_z = 2.0 * s.moment_z
    volume = w @ area
    lcb = safe_div(w @ (x * area), volume)
    kb = safe_div(w @ moment_z, volume)
    bw = s.width
    awp = 2.0 * (w @ bw)
    lcf = safe_div(2.0 * (w @ (x * bw)), awp)
    x_aft, x_fwd = waterline_ends(x, sections.yz, bw, t)
    return LongitudinalIntegrals(
        area=area, moment_z=moment_z, half_breadth=bw, volume=volume, lcb=lcb, kb=kb, awp=awp, lcf=lcf,
        i_t=(2.0 / 3.0) * (w @ bw**3), i_l=2.0 * (w @ (x**2 * bw)) - awp * lcf**2, bwl=2.0 * jnp.max(bw),
        lwl=x_fwd - x_aft, x_aft=x_aft, x_fwd=x_fwd, a_transom=transom_area(x, sections.yz, t),
    )
