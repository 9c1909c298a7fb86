"""Curvature of the hull surface and of its curves (seed 001 §2.2: Gaussian, mean, section "porcupines").

Sign convention: curvatures are positive where the hull is convex seen from outside (the bilge, a
sphere seen from outside), i.e. measured with the unit normal pointing into the hull.
"""

from __future__ import annotations

import jax.numpy as jnp
from jaxtyping import Array, Float

from .._types import Mask, Values, Vectors
from ..geometry import TINY_LENGTH, Sections, safe_div, safe_sqrt


def surface_curvatures(r_u: Vectors, r_v: Vectors, r_uu: Vectors, r_uv: Vectors, r_vv: Vectors) -> tuple[Array, Array]:
    """Gaussian ``K`` [1/m²] and mean ``H`` [1/m] curvature of a parametric surface ``r(u, v)``.

    Inputs are the first and second partial derivatives, shape ``(..., 3)``. With the fundamental forms
    ``E = r_u·r_u, F = r_u·r_v, G = r_v·r_v`` and ``L = r_uu·N, M = r_uv·N, N' = r_vv·N`` for the unit
    normal ``N = r_u × r_v / |r_u × r_v|``::

        K = (L N' − M²) / (E G − F²),    H = (E N' − 2 F M + G L) / (2 (E G − F²)).

    ``H > 0`` where the surface bends towards ``N`` (a sphere with ``N`` pointing inwards has
    ``H = 1/R``). The surface must be regular (``r_u × r_v ≠ 0``).

    Parameters
    ----------
    r_u, r_v : Array, (..., 3) float
        First partial derivatives of ``r`` [m per unit of the parameter].
    r_uu, r_uv, r_vv : Array, (..., 3) float
        Second partial derivatives of ``r``.

    Returns
    -------
    K : Array, (...)
        Gaussian curvature [1/m²].
    H : Array, (...)
        Mean curvature [1/m], positive bending towards ``N``.
    """
    n = jnp.cross(r_u, r_v)
    n = n / jnp.linalg.norm(n, axis=-1, keepdims=True)
    e, f, g = (jnp.sum(a * b, -1) for a, b in ((r_u, r_u), (r_u, r_v), (r_v, r_v)))
    ll, mm, nn = (jnp.sum(a * n, -1) for a in (r_uu, r_uv, r_vv))
    det = e * g - f**2
    return (ll * nn - mm**2) / det, (e * nn - 2 * f * mm + g * ll) / (2 * det)


def graph_curvatures(fx: Values, fz: Values, fxx: Values, fxz: Values, fzz: Values) -> tuple[Array, Array]:
    """Gaussian ``K`` [1/m²] and mean ``H`` [1/m] curvature of the hull side ``y = f(x, z)`` from the
    partial derivatives of ``f`` (any shapes, broadcast). With ``W² = 1 + fx² + fz²``::

        K = (fxx fzz − fxz²) / W⁴,
        H = −((1 + fz²) fxx − 2 fx fz fxz + (1 + fx²) fzz) / (2 W³),

    i.e. :func:`surface_curvatures` of ``r = (x, f, z)`` with ``(u, v) = (x, z)``, whose normal points
    into the hull: ``H > 0`` at a convex bilge.

    Parameters
    ----------
    fx, fz : array_like
        First partial derivatives of ``f`` (dimensionless), broadcast together.
    fxx, fxz, fzz : array_like
        Second partial derivatives of ``f`` [1/m].

    Returns
    -------
    K : Array
        Gaussian curvature [1/m²], in the broadcast shape.
    H : Array
        Mean curvature [1/m], positive at a convex bilge.
    """
    w2 = 1.0 + fx**2 + fz**2
    k = (fxx * fzz - fxz**2) / w2**2
    h = -((1.0 + fz**2) * fxx - 2.0 * fx * fz * fxz + (1.0 + fx**2) * fzz) / (2.0 * w2**1.5)
    return k, h


def curve_curvature(dy: Values, d2y: Values) -> Array:
    """Signed curvature [1/m] of a plane curve ``y(t)`` (a frame line ``y(z)`` or a waterline ``y(x)``)::

        κ = −y'' / (1 + y'²)^{3/2}    (positive where the hull is convex).

    Parameters
    ----------
    dy : array_like
        First derivative ``y'`` (dimensionless).
    d2y : array_like
        Second derivative ``y''`` [1/m], broadcast with ``dy``.

    Returns
    -------
    Array
        Signed curvature κ [1/m] in the broadcast shape, positive where the hull is convex.
    """
    return -d2y / (1.0 + dy**2) ** 1.5


def safe_unit(e, eps):
    """Unit vectors of the edges ``e (..., d)`` and a mask of the edges longer than ``eps`` (double where:
    degenerate edges give 0 with finite gradients)."""
    length2 = jnp.sum(e * e, -1)
    ok = length2 > eps**2
    length = safe_sqrt(length2, ok)
    return safe_div(e, length[..., None], ok[..., None]), length, ok


def polyline_curvature(points: Float[Array, "... k d"], eps: float = TINY_LENGTH, edge_ok: Mask | None = None):
    """Discrete curvature vectors at the interior vertices of polylines ``points (..., k, d)`` [m].

    ``κ_i = (t_i − t_{i−1}) / ((ℓ_{i−1} + ℓ_i)/2)`` with ``t`` the unit edge tangents and ``ℓ`` the edge
    lengths: the curvature vector (magnitude → 1/R, pointing to the centre) of a smooth curve sampled
    finely. Returns ``(kappa (..., k−2, d), ds (..., k−2), ok (..., k−2))``: ``ds`` the vertex's share of
    arc length [m]; ``ok`` false where an adjacent edge is shorter than ``eps`` (repeated points) or
    excluded by ``edge_ok (..., k−1)``; there ``kappa`` and ``ds`` are 0. Smooth (no norms of
    curvature), NaN-free gradients.

    Parameters
    ----------
    points : Array, (..., k, d) float
        Polyline vertices [m], ``k ≥ 3``.
    eps : float
        Shortest edge [m] that counts (:data:`~hullopt.geometry.TINY_LENGTH`, 1e-9 m, by default).
    edge_ok : Array, (..., k−1) bool, optional
        Edges to use; ``None``: all of them.

    Returns
    -------
    kappa : Array, (..., k−2, d) float
        Curvature vectors [1/m] at the interior vertices.
    ds : Array, (..., k−2) float
        Each interior vertex's share of arc length [m].
    ok : Array, (..., k−2) bool
        Where ``kappa`` is defined.
    """
    t, length, ok_e = safe_unit(jnp.diff(points, axis=-2), eps)
    if edge_ok is not None:
        ok_e = ok_e & edge_ok
    ds = 0.5 * (length[..., :-1] + length[..., 1:])
    ok = ok_e[..., :-1] & ok_e[..., 1:]
    kappa = safe_div(t[..., 1:, :] - t[..., :-1, :], ds[..., None], ok[..., None])
    return kappa, jnp.where(ok, ds, 0.0), ok


def section_curvature(sections: Sections, eps: float = TINY_LENGTH) -> Float[Array, "n m"]:
    """Signed curvature [1/m] of every half-section polyline at its points (0 at the two ends and next
    to repeated points): ``±|κ|`` of :func:`polyline_curvature` (exactly ``1/R`` on the chords of a
    circle), positive where the section turns left going from
    keel to deck (a convex bilge). The "porcupine" of seed 001 §2.2 draws ``κ`` along the section normal.

    Parameters
    ----------
    sections : Sections
        The hull: ``yz (n, m, 2)`` [m].
    eps : float
        Shortest edge [m] that counts (:data:`~hullopt.geometry.TINY_LENGTH`, 1e-9 m, by default).

    Returns
    -------
    Array, (n, m) float
        Signed curvature [1/m] at every point, positive at a convex bilge.
    """
    kappa, _, _ = polyline_curvature(sections.yz, eps)
    t, _, _ = safe_unit(jnp.diff(sections.yz, axis=-2), eps)
    # component along the left normal of the bisector t_{i−1} + t_i, to which κ is parallel: exactly ±|κ|
    b, _, ok = safe_unit(t[..., :-1, :] + t[..., 1:, :], eps)
    normal = jnp.stack([-b[..., 1], b[..., 0]], -1)
    signed = jnp.where(ok, jnp.sum(kappa * normal, -1), 0.0)
    pad = jnp.zeros(signed.shape[:-1] + (1,), signed.dtype)
    return jnp.concatenate([pad, signed, pad], -1)
