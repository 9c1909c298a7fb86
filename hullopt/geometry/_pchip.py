"""Monotone piecewise-cubic (PCHIP, Fritsch–Carlson) interpolation in numpy, along axis 0: scipy's
``PchipInterpolator`` rule (tested equal) without importing scipy.interpolate, which costs a run's start half a
second. Used on the parent's data (the feature model's distributions, the mesh writer), never on traced values."""

from __future__ import annotations

from types import ModuleType

import numpy as np
from jaxtyping import ArrayLike


def pchip_slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The PCHIP slopes at the knots: zero where the chords on either side differ in sign or one is flat, else
    their weighted harmonic mean; at the ends the one-sided three-point slope, kept shape-preserving (Moler,
    *Numerical Computing with MATLAB*, pchiptx); with two knots the chord's slope.

    Parameters
    ----------
    x : numpy.ndarray, (n,)
        The knots, increasing, n ≥ 2 (any unit of length).
    y : numpy.ndarray, (n, ...)
        The values at the knots; trailing axes are independent curves.

    Returns
    -------
    numpy.ndarray, (n, ...)
        ``dy/dx`` at the knots (units of ``y`` per unit of ``x``).
    """
    y = np.asarray(y, float)
    h = np.diff(x).reshape((-1,) + (1,) * (y.ndim - 1))
    m = np.diff(y, axis=0) / h  # (n - 1, ...) the chords' slopes
    if len(x) == 2:
        return np.concatenate([m, m])
    w1, w2 = 2 * h[1:] + h[:-1], h[1:] + 2 * h[:-1]
    flat = (np.sign(m[1:]) != np.sign(m[:-1])) | (m[1:] == 0) | (m[:-1] == 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        inner = (w1 + w2) / (w1 / m[:-1] + w2 / m[1:])

    def end(h0, h1, m0, m1):
        e = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
        e = np.where(np.sign(e) != np.sign(m0), 0.0, e)
        return np.where((np.sign(m0) != np.sign(m1)) & (np.abs(e) > 3 * np.abs(m0)), 3 * m0, e)

    d = np.empty_like(y)
    d[1:-1] = np.where(flat, 0.0, inner)
    d[0], d[-1] = end(h[0], h[1], m[0], m[1]), end(h[-1], h[-2], m[-1], m[-2])
    return d


def pchip(x: np.ndarray, y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The PCHIP interpolant (monotone between monotone data, no overshoot), exact at the knots.

    Parameters
    ----------
    x : numpy.ndarray, (n,)
        The knots, increasing, n ≥ 2.
    y : numpy.ndarray, (n, ...)
        The values at the knots; trailing axes are independent curves.
    t : numpy.ndarray, (p,)
        Where to interpolate, within ``[x[0], x[-1]]`` (outside: the end pieces extended).

    Returns
    -------
    numpy.ndarray, (p, ...)
        The interpolated values.
    """
    y = np.asarray(y, float)
    return hermite(x, y, pchip_slopes(x, y), t)


def hermite(x: ArrayLike, y: ArrayLike, d: ArrayLike, t: ArrayLike, xp: ModuleType = np) -> ArrayLike:
    """Piecewise cubic Hermite interpolation with given slopes: numpy (``xp=np``) or traced (``xp=jax.numpy``,
    the feature model's distributions, whose slopes :func:`pchip_slopes` gave once).

    Parameters
    ----------
    x : array, (n,)
        The knots, increasing, n ≥ 2.
    y, d : array, (n, ...)
        The values and their slopes ``dy/dx`` at the knots.
    t : array, (p,)
        Where to interpolate (outside ``[x[0], x[-1]]``: the end pieces extended).
    xp : module
        ``numpy`` or ``jax.numpy``.

    Returns
    -------
    array, (p, ...)
        The interpolated values; exact at the knots.
    """
    i = xp.clip(xp.searchsorted(x, t, side="right") - 1, 0, x.shape[0] - 2)
    h = (x[i + 1] - x[i]).reshape((-1,) + (1,) * (y.ndim - 1))
    s = (xp.asarray(t) - x[i]).reshape(h.shape) / h
    return ((2 * s**3 - 3 * s**2 + 1) * y[i] + (s**3 - 2 * s**2 + s) * h * d[i]
            + (-2 * s**3 + 3 * s**2) * y[i + 1] + (s**3 - s**2) * h * d[i + 1])
