"""Natural cubic splines (seed 003 §3.1), in JAX, differentiable in the values and the knots."""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float


class CubicSpline(eqx.Module):
    """Piecewise cubic ``s(t) = a + b·u + c·u² + d·u³``, ``u = t − knots[i]`` on interval ``i``.

    ``knots (k,)``; coefficients ``(k−1, ...)`` so several curves on the same knots are one spline
    (trailing axes of the values).
    """

    knots: Float[Array, " k"]
    a: Float[Array, "k-1 *curves"]
    b: Float[Array, "k-1 *curves"]
    c: Float[Array, "k-1 *curves"]
    d: Float[Array, "k-1 *curves"]

    def __call__(self, t, nu: int = 0):
        """Value (``nu = 0``) or ``nu``-th derivative at ``t`` (any shape); linear extrapolation is not
        applied: the end cubics continue beyond the knots."""
        t = jnp.asarray(t)
        i = jnp.clip(jnp.searchsorted(self.knots, t, side="right") - 1, 0, self.knots.shape[0] - 2)
        u = (t - self.knots[i]).reshape(t.shape + (1,) * (self.a.ndim - 1))
        a, b, c, d = self.a[i], self.b[i], self.c[i], self.d[i]
        if nu == 0:
            return a + u * (b + u * (c + u * d))
        if nu == 1:
            return b + u * (2 * c + 3 * u * d)
        if nu == 2:
            return 2 * c + 6 * u * d
        raise ValueError(f"derivative order nu must be 0, 1 or 2, got {nu}")


def natural_cubic_spline(knots: Float[Array, " k"], values: Float[Array, "k ..."]) -> CubicSpline:
    """The natural cubic spline (zero second derivative at both ends) through ``(knots, values)``.

    ``knots`` strictly increasing, ``k ≥ 2``. Solves the tridiagonal system for the second
    derivatives (a dense solve: k is a handful of stations or waterlines).

    Parameters
    ----------
    knots : Array, (k,) float
        Strictly increasing abscissae, ``k ≥ 2`` (any unit, e.g. m).
    values : Array, (k, ...) float
        Ordinates at the knots; trailing axes are several curves on the same knots.

    Returns
    -------
    CubicSpline
        The spline: ``knots (k,)``, coefficients ``a, b, c, d (k−1, ...)``; call it at ``t`` for values or
        derivatives.
    """
    knots = jnp.asarray(knots)
    y = jnp.asarray(values)
    k = knots.shape[0]
    if k < 2:
        raise ValueError(f"a spline needs at least 2 knots, got {k}")
    h = jnp.diff(knots)
    dy = jnp.diff(y, axis=0) / h.reshape((-1,) + (1,) * (y.ndim - 1))
    if k == 2:
        c = jnp.zeros((k,) + y.shape[1:], y.dtype)
    else:
        main = 2.0 * (h[:-1] + h[1:])
        mat = jnp.diag(main) + jnp.diag(h[1:-1], 1) + jnp.diag(h[1:-1], -1)
        rhs = 3.0 * (dy[1:] - dy[:-1])
        inner = jnp.linalg.solve(mat, rhs.reshape(k - 2, -1)).reshape(rhs.shape)
        zero = jnp.zeros((1,) + y.shape[1:], y.dtype)
        c = jnp.concatenate([zero, inner, zero], axis=0)
    hh = h.reshape((-1,) + (1,) * (y.ndim - 1))
    b = dy - hh * (2.0 * c[:-1] + c[1:]) / 3.0
    d = (c[1:] - c[:-1]) / (3.0 * hh)
    return CubicSpline(knots, y[:-1], b, c[:-1], d)


def spline_matrix(knots: Float[ArrayLike, ' k'], at: Float[ArrayLike, ' p']) -> np.ndarray:
    """Matrix ``W (len(at), len(knots))`` with ``s(at) = W @ values`` for the natural spline on ``knots``.

    A natural spline is linear in its values, so with fixed knots (static preprocessing, numpy) the
    interpolation on the hot path is one matrix product.

    Parameters
    ----------
    knots : array_like, (k,) float
        Strictly increasing knot positions, ``k ≥ 2`` (any unit).
    at : array_like, (p,) float
        Positions to interpolate at, same unit as ``knots``.

    Returns
    -------
    numpy.ndarray, (p, k) float64
        Weights ``W`` with ``s(at) = W @ values`` for values ``(k, ...)`` on ``knots``.
    """
    # numpy, as natural_cubic_spline: static preprocessing, and scipy.interpolate's import took ~0.4 s of a
    # command reading an offset table
    knots = np.asarray(knots, dtype=np.float64)
    at = np.asarray(at, dtype=np.float64)
    k = knots.shape[0]
    if k < 2:
        raise ValueError(f"a spline needs at least 2 knots, got {k}")
    h = np.diff(knots)[:, None]
    dy = np.diff(np.eye(k), axis=0) / h  # the spline of each unit vector of values: one column each
    c = np.zeros((k, k))
    if k > 2:
        mat = np.diag(2.0 * (h[:-1, 0] + h[1:, 0])) + np.diag(h[1:-1, 0], 1) + np.diag(h[1:-1, 0], -1)
        c[1:-1] = np.linalg.solve(mat, 3.0 * (dy[1:] - dy[:-1]))
    b = dy - h * (2.0 * c[:-1] + c[1:]) / 3.0
    d = (c[1:] - c[:-1]) / (3.0 * h)
    i = np.clip(np.searchsorted(knots, at, side="right") - 1, 0, k - 2)  # the end cubics continue beyond
    u = (at - knots[i])[:, None]
    return np.eye(k)[i] + u * (b[i] + u * (c[i] + u * d[i]))
