"""Integrals along the length: Simpson weights for stations at arbitrary (increasing) positions, and the
longitudinal integrals of a hull at a draft (∇, LCB, KB, the waterplane) that every analysis shares."""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from ._safe import safe_div
from ._sections import Sections, section_integrals


def simpson_weights(x: Float[Array, " n"]) -> Float[Array, " n"]:
    """Weights ``w`` with ``∫ f dx ≈ w @ f`` by composite Simpson's rule on uneven spacing.

    Exact for quadratics (so for the sectional-area curve of a Wigley hull). Pairs of intervals use
    the uneven three-point rule; with an odd number of intervals the last one is integrated with the
    parabola through the last three points (as ``scipy.integrate.simpson``). ``n`` must be ≥ 2; with
    ``n = 2`` this is the trapezoidal rule.
    """
    x = jnp.asarray(x)
    n = x.shape[0]
    if n < 2:
        raise ValueError(f"need at least 2 stations to integrate, got {n}")
    w = jnp.zeros(n, dtype=x.dtype)
    if n == 2:
        h = x[1] - x[0]
        return w + 0.5 * h
    n_simpson = n if n % 2 == 1 else n - 1  # points covered by pairs of intervals
    h = jnp.diff(x[:n_simpson])
    h0, h1 = h[0::2], h[1::2]
    hs = h0 + h1
    w = w.at[0 : n_simpson - 2 : 2].add(hs / 6.0 * (2.0 - h1 / h0))
    w = w.at[1 : n_simpson - 1 : 2].add(hs / 6.0 * hs**2 / (h0 * h1))
    w = w.at[2:n_simpson:2].add(hs / 6.0 * (2.0 - h0 / h1))
    if n_simpson < n:
        h0, h1 = x[-2] - x[-3], x[-1] - x[-2]
        w = w.at[-1].add((2 * h1**2 + 3 * h0 * h1) / (6 * (h0 + h1)))
        w = w.at[-2].add((h1**2 + 3 * h0 * h1) / (6 * h0))
        w = w.at[-3].add(-(h1**3) / (6 * h0 * (h0 + h1)))
    return w


def volume_lcb(x: Float[Array, " n"], area: Float[Array, " n"]) -> tuple[Array, Array]:
    """Volume ``∫A dx`` [m³] and its centroid ``∫xA dx / ∫A dx`` [m from the AP] of the sectional-area curve
    ``area`` at stations ``x`` (Simpson's rule, :func:`simpson_weights`): the rule of
    :func:`longitudinal_integrals`, for areas held while the stations move (a Lackenby shift)."""
    w = simpson_weights(x)
    volume = w @ area
    return volume, (w @ (x * area)) / volume


def _waterline_length(x: Array, bw: Array) -> Array:
    """From the first to the last station with a waterline, each extended to its dry neighbour (where
    the ruled surface between the two stations ends); exact when the stations include both ends."""
    wet = bw > 0.0
    n = x.shape[0]
    first = jnp.argmax(wet)
    last = n - 1 - jnp.argmax(wet[::-1])
    return jnp.where(jnp.any(wet), x[jnp.minimum(last + 1, n - 1)] - x[jnp.maximum(first - 1, 0)], 0.0)


class LongitudinalIntegrals(eqx.Module):
    """The hull's integrals along the length at one draft (both sides; x from the AP), exact per section
    and by Simpson's rule along x — the rules of :func:`hullopt.hydro.hydrostatics`.

    ``area (n,)`` full-section immersed areas [m²] (the sectional-area curve), ``moment_z (n,)`` their
    first moments about the baseline [m³], ``half_breadth (n,)`` waterline half-breadths [m]; ``volume``
    ∇ [m³], ``lcb`` [m], ``kb`` [m]; the waterplane: ``awp`` [m²], ``lcf`` [m], its transverse and
    longitudinal (about the LCF) second moments ``i_t``, ``i_l`` [m⁴], ``bwl`` = 2·max half-breadth and
    ``lwl`` (from the first to the last wet station, each extended to its dry neighbour) [m].
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


def longitudinal_integrals(sections: Sections, draft) -> LongitudinalIntegrals:
    """:class:`LongitudinalIntegrals` of ``sections`` at the waterline ``z = draft`` [m] (even keel): the
    kernel's :func:`section_integrals` at every station, :func:`simpson_weights` along x. Pure JAX:
    jit/vmap/grad in the geometry and the draft. ``lcb``, ``kb`` and ``lcf`` are 0 where the hull is dry."""
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
    return LongitudinalIntegrals(
        area=area, moment_z=moment_z, half_breadth=bw, volume=volume, lcb=lcb, kb=kb, awp=awp, lcf=lcf,
        i_t=(2.0 / 3.0) * (w @ bw**3), i_l=2.0 * (w @ (x**2 * bw)) - awp * lcf**2, bwl=2.0 * jnp.max(bw),
        lwl=_waterline_length(x, bw),
    )
