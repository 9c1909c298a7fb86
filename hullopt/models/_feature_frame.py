"""Frame rebuilding (seed 000, claim 3 / §0017): each segment between adjacent inflection points is a cubic
spline through its auxiliary apexes and apex, with the tangent at the apex parallel to the segment's chord,
so the apex stays the apex.

Everything is in the segment's *chord frame*: for a segment from ``a`` to ``b`` (the chord ``c = b − a``) a
point is ``a + u·c + v·rot(c)`` with ``rot(c) = (−c_z, c_y)`` (the chord turned +90° in the (y, z) plane), so
``u ∈ [0, 1]`` runs along the chord and ``v`` is the signed distance from it, both in chord lengths. A segment
is then, besides its ends:

* the apex ``(β, η)``: ``u = β``, ``v = η``;
* on each half (inflection → apex) ``J`` auxiliary apexes as the two ratios of claim 6, which a moving apex
  keeps: ``ρ = u_C / u_B`` and ``σ = v_C / v_B`` on the first half (measured from the first inflection),
  ``ρ = (1 − u_C) / (1 − u_B)`` and ``σ = v_C / v_B`` on the second (from the second inflection), ordered
  from the inflection to the apex. ``J = 1`` is the patent's frame (one auxiliary apex per half); ``J = 3``
  (``level = 2``) adds the farthest points from the chords inflection–auxiliary apex and auxiliary
  apex–apex, the same rule one level down, for frames a single auxiliary apex cannot hold (long straight
  stretches between two bends).

Each half is a cubic spline on ``J + 2`` knots with zero curvature at the inflection point (it *is* an
inflection) and zero slope ``dv/du`` at the apex (the apex condition). A segment whose chord has zero length
(a degenerate segment, see :mod:`._feature_extract`) collapses to its end point with no special case: every
point is ``a + 0``.

Pure JAX, vectorised over stations and segments; differentiable in every input.
"""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float


def _half_spline(u: Array, v: Array, f: Array) -> tuple[Array, Array]:
    """Cubic spline through knots ``u (..., K)`` (``u[0] = 0``, increasing) with values ``v (..., K)``
    (``v[0] = 0``): natural at ``u[0]``, ``dv/du = 0`` at ``u[-1]``. Sampled at fractions ``f (q,)`` of each
    knot interval: returns ``(u, v)`` of shape ``(..., (K−1)·q)``, the last sample being the last knot."""
    k = u.shape[-1]
    h = jnp.diff(u, axis=-1)  # (..., K-1)
    d = jnp.diff(v, axis=-1) / h
    # Unknowns M_1..M_{K-1} (M_0 = 0): interior rows j = 1..K-2, then the clamped row. The system is
    # tridiagonal and strictly diagonally dominant, so it is solved by the Thomas algorithm (no pivoting),
    # unrolled over the K − 1 rows: elementwise, where a batched LU solve (jnp.linalg.solve) of many tiny
    # systems is slow, above all under vmap.
    rhs = jnp.concatenate([6.0 * (d[..., 1:] - d[..., :-1]), -6.0 * d[..., -1:]], -1)
    n_rows = k - 1
    sub = [None] + [h[..., j - 1] for j in range(2, k)]  # row r = j − 1 couples M_{j−1}
    diag = [2.0 * (h[..., j - 1] + h[..., j]) for j in range(1, k - 1)] + [2.0 * h[..., k - 2]]
    sup = [h[..., j] for j in range(1, k - 1)]  # M_{j+1} in rows 0 … K−3
    cp, dp = [], []
    for r in range(n_rows):
        if r == 0:
            den, num = diag[0], rhs[..., 0]
        else:
            den = diag[r] - sub[r] * cp[r - 1]
            num = rhs[..., r] - sub[r] * dp[r - 1]
        cp.append(sup[r] / den if r < n_rows - 1 else None)
        dp.append(num / den)
    sol = [None] * n_rows
    sol[-1] = dp[-1]
    for r in range(n_rows - 2, -1, -1):
        sol[r] = dp[r] - cp[r] * sol[r + 1]
    m = jnp.stack(sol, -1)
    m = jnp.concatenate([jnp.zeros_like(m[..., :1]), m], -1)  # (..., K)
    g = f
    hh = (h * h / 6.0)[..., None]
    mj, mk = m[..., :-1, None], m[..., 1:, None]
    vj, vk = v[..., :-1, None], v[..., 1:, None]
    vs = mj * hh * (1 - g) ** 3 + mk * hh * g**3 + (vj - mj * hh) * (1 - g) + (vk - mk * hh) * g
    us = u[..., :-1, None] + h[..., None] * g
    return us.reshape(us.shape[:-2] + (-1,)), vs.reshape(vs.shape[:-2] + (-1,))


def segment_points(
    a: Float[ArrayLike, "... 2"],
    b: Float[ArrayLike, "... 2"],
    apex: Float[ArrayLike, "... 2"],
    aux: Float[ArrayLike, "... 2 J 2"],
    q: int,
) -> Float[Array, "... P 2"]:
    """Points of the rebuilt segments from ``a`` to ``b`` (``a`` excluded, ``b`` included),
    ``P = 2·(J+1)·q`` each.

    ``apex = (β, η)`` and ``aux[half, j] = (ρ, σ)`` in the chord frame (module docstring); ``q`` samples per
    knot interval, equally spaced in ``u``.
    """
    beta, eta = apex[..., 0], apex[..., 1]
    f = jnp.arange(1, q + 1, dtype=a.dtype) / q
    zero = jnp.zeros_like(beta)[..., None]

    def half(rho, sig, width):
        u = jnp.concatenate([zero, rho * width[..., None], width[..., None]], -1)
        v = jnp.concatenate([zero, sig * eta[..., None], eta[..., None]], -1)
        return _half_spline(u, v, f)

    u_lo, v_lo = half(aux[..., 0, :, 0], aux[..., 0, :, 1], beta)  # inflection a → apex
    u_hi, v_hi = half(aux[..., 1, :, 0], aux[..., 1, :, 1], 1.0 - beta)  # inflection b → apex (mirrored)
    # The mirrored half runs from b to the apex: reverse it, drop the apex (already in the first half), end at b.
    u_hi = jnp.concatenate([u_hi[..., ::-1][..., 1:], jnp.zeros_like(u_hi[..., :1])], -1)
    v_hi = jnp.concatenate([v_hi[..., ::-1][..., 1:], jnp.zeros_like(v_hi[..., :1])], -1)
    u = jnp.concatenate([u_lo, 1.0 - u_hi], -1)
    v = jnp.concatenate([v_lo, v_hi], -1)
    c = b - a
    rc = jnp.stack([-c[..., 1], c[..., 0]], -1)
    return a[..., None, :] + u[..., None] * c[..., None, :] + v[..., None] * rc[..., None, :]


def rebuild_frames(
    keel: Float[ArrayLike, "n 2"],
    ends: Float[ArrayLike, "n S1 2"],
    apex: Float[ArrayLike, "n S 2"],
    aux: Float[ArrayLike, "n S 2 J 2"],
    deck: Float[ArrayLike, "n 2"],
    q: int,
) -> Float[Array, "n m 2"]:
    """Half-section polylines ``keel → flat of bottom → S segments → flat of side → deck edge``.

    ``ends[:, 0]`` is the end of the flat of bottom (the keel point where there is none), ``ends[:, S]``
    the start of the flat of side (the deck edge where there is none), the others the inflection points.
    ``m = 3 + 2·(J+1)·q·S`` points per station.

    Parameters
    ----------
    keel : array_like, (n, 2) float
        Keel points ``(y, z)`` [m] (on the centreline).
    ends : array_like, (n, S+1, 2) float
        Segment ends ``(y, z)`` [m].
    apex : array_like, (n, S, 2) float
        Apexes ``(β, η)`` in each segment's chord frame (chord lengths, dimensionless).
    aux : array_like, (n, S, 2, J, 2) float
        Auxiliary apexes' ratios ``(ρ, σ)`` per half (dimensionless).
    deck : array_like, (n, 2) float
        Deck edges ``(y, z)`` [m].
    q : int
        Samples per knot interval of each half's spline.

    Returns
    -------
    Array, (n, 3 + 2(J+1)qS, 2) float
        The half-section polylines ``(y, z)`` [m].
    """
    n = ends.shape[0]
    pts = segment_points(ends[:, :-1], ends[:, 1:], apex, aux, q)  # (n, S, P, 2)
    body = pts.reshape(n, -1, 2)
    return jnp.concatenate([keel[:, None], ends[:, :1], body, deck[:, None]], axis=1)


def apex_points(ends: ArrayLike, apex: ArrayLike) -> ArrayLike:
    """Absolute (y, z) of the apexes ``(n, S, 2)`` from the chord-frame ``(β, η)``."""
    a, b = ends[..., :-1, :], ends[..., 1:, :]
    c = b - a
    rc = c[..., ::-1] * np.array([-1.0, 1.0])  # c turned +90°; operators only, so numpy in gives numpy out
    return a + apex[..., :1] * c + apex[..., 1:] * rc


def aux_points(ends: ArrayLike, apex: ArrayLike, aux: ArrayLike) -> ArrayLike:
    """Absolute (y, z) of the auxiliary apexes ``(n, S, 2, J, 2)``."""
    a, b = ends[..., :-1, :], ends[..., 1:, :]
    c = b - a
    rc = jnp.stack([-c[..., 1], c[..., 0]], -1)
    beta, eta = apex[..., 0, None], apex[..., 1, None]
    u = jnp.stack([aux[..., 0, :, 0] * beta, 1.0 - aux[..., 1, :, 0] * (1.0 - beta)], -2)
    v = aux[..., 1] * eta[..., None]
    return a[..., None, None, :] + u[..., None] * c[..., None, None, :] + v[..., None] * rc[..., None, None, :]
