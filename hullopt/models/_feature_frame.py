"""Frame rebuilding (seed 000, claim 3 / §0017): each segment between adjacent inflection points is a cubic
spline through its auxiliary apex, apex and auxiliary apex, with the tangent at the apex parallel to the
segment's chord, so the apex stays the apex.

Everything is in the segment's *chord frame*: for a segment from ``a`` to ``b`` (the chord ``c = b − a``) a
point is ``a + u·c + v·rot(c)`` with ``rot(c) = (−c_z, c_y)`` (the chord turned +90° in the (y, z) plane), so
``u ∈ [0, 1]`` runs along the chord and ``v`` is the signed distance from it, both in chord lengths. A segment
is then five numbers besides its ends:

* the apex ``(β, η)``: ``u = β``, ``v = η``;
* the auxiliary apexes as the two ratios of claim 6, which a moving apex keeps: ``ρ₁ = u_C1 / u_B`` and
  ``σ₁ = v_C1 / v_B`` (measured from the first inflection point), ``ρ₂ = (1 − u_C2) / (1 − u_B)`` and
  ``σ₂ = v_C2 / v_B`` (from the second).

Each half (inflection → auxiliary apex → apex) is a cubic spline on three knots with zero curvature at the
inflection point (it *is* an inflection) and zero slope ``dv/du`` at the apex (the apex condition). A segment
whose chord has zero length (a degenerate segment, see :mod:`._feature_extract`) collapses to its end point
with no special case: every point is ``a + 0``.

Pure JAX, vectorised over stations and segments; differentiable in every input.
"""

from __future__ import annotations

import jax.numpy as jnp
from jaxtyping import Array, Float


def _half_spline(u1, v1, u2, v2, f):
    """Cubic spline through ``(0, 0)``, ``(u1, v1)``, ``(u2, v2)``: natural at 0, ``dv/du = 0`` at ``u2``.

    Inputs ``(...)``; returns ``(u, v)`` of shape ``(..., 2q)`` sampled at the fractions ``f (q,)`` of each
    knot interval (the last sample is the apex itself).
    """
    h0, h1 = u1, u2 - u1
    d0, d1 = v1 / h0, (v2 - v1) / h1
    # Second derivatives at the knots: M0 = 0 (natural), continuity of v' at u1, v'(u2) = 0.
    m1 = 6.0 * (3.0 * d1 - 2.0 * d0) / (4.0 * h0 + 3.0 * h1)
    m2 = (-6.0 * d1 - h1 * m1) / (2.0 * h1)

    def piece(uj, vj, mj, vk, mk, h):
        g = f  # (q,)
        hh = (h * h / 6.0)[..., None]
        v = (mj[..., None] * hh * (1 - g) ** 3 + mk[..., None] * hh * g**3
             + (vj[..., None] - mj[..., None] * hh) * (1 - g) + (vk[..., None] - mk[..., None] * hh) * g)
        return uj[..., None] + h[..., None] * g, v

    zero = jnp.zeros_like(u1)
    ua, va = piece(zero, zero, zero, v1, m1, h0)
    ub, vb = piece(u1, v1, m1, v2, m2, h1)
    return jnp.concatenate([ua, ub], -1), jnp.concatenate([va, vb], -1)


def segment_points(
    a: Float[Array, "... 2"],
    b: Float[Array, "... 2"],
    apex: Float[Array, "... 2"],
    aux: Float[Array, "... 4"],
    q: int,
) -> Float[Array, "... 4q 2"]:
    """Points of the rebuilt segments from ``a`` to ``b`` (``a`` excluded, ``b`` included), ``4q`` each.

    ``apex = (β, η)`` and ``aux = (ρ₁, σ₁, ρ₂, σ₂)`` in the chord frame (module docstring); ``q`` samples per
    knot interval, equally spaced in ``u``.
    """
    beta, eta = apex[..., 0], apex[..., 1]
    rho1, sig1, rho2, sig2 = (aux[..., k] for k in range(4))
    f = jnp.arange(1, q + 1, dtype=a.dtype) / q
    # First half: inflection a (u = 0) → C1 → apex.
    u_lo, v_lo = _half_spline(rho1 * beta, sig1 * eta, beta, eta, f)
    # Second half, mirrored (u' = 1 − u): inflection b → C2 → apex, then reversed to run apex → b.
    w = 1.0 - beta
    u_hi, v_hi = _half_spline(rho2 * w, sig2 * eta, w, eta, f)
    # Mirrored samples run from b towards the apex: reverse, drop the apex (already in the first half) and
    # append b (u' = 0).
    u_hi = jnp.concatenate([u_hi[..., ::-1][..., 1:], jnp.zeros_like(u_hi[..., :1])], -1)
    v_hi = jnp.concatenate([v_hi[..., ::-1][..., 1:], jnp.zeros_like(v_hi[..., :1])], -1)
    u = jnp.concatenate([u_lo, 1.0 - u_hi], -1)
    v = jnp.concatenate([v_lo, v_hi], -1)
    c = b - a
    rc = jnp.stack([-c[..., 1], c[..., 0]], -1)
    return a[..., None, :] + u[..., None] * c[..., None, :] + v[..., None] * rc[..., None, :]


def rebuild_frames(
    keel: Float[Array, "n 2"],
    ends: Float[Array, "n S+1 2"],
    apex: Float[Array, "n S 2"],
    aux: Float[Array, "n S 4"],
    deck: Float[Array, "n 2"],
    q: int,
) -> Float[Array, "n m 2"]:
    """Half-section polylines ``keel → flat of bottom → S segments → flat of side → deck edge``.

    ``ends[:, 0]`` is the end of the flat of bottom (= the keel point where there is none), ``ends[:, S]``
    the start of the flat of side (= the deck edge where there is none), the others the inflection points.
    ``m = 3 + 4·q·S`` points per station.
    """
    n, s1 = ends.shape[0], ends.shape[1]
    pts = segment_points(ends[:, :-1], ends[:, 1:], apex, aux, q)  # (n, S, 4q, 2)
    body = pts.reshape(n, (s1 - 1) * 4 * q, 2)
    return jnp.concatenate([keel[:, None], ends[:, :1], body, deck[:, None]], axis=1)


def chord_coordinates(a, b, p):
    """``(u, v)`` of points ``p`` in the chord frame of ``a → b`` (numpy or JAX; the chord must not be
    degenerate)."""
    c = b - a
    rc = jnp.stack([-c[..., 1], c[..., 0]], -1)
    cc = jnp.sum(c * c, -1)
    d = p - a
    return jnp.sum(d * c, -1) / cc, jnp.sum(d * rc, -1) / cc
