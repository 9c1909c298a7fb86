"""Quadrature weights along the length for stations at arbitrary (increasing) positions."""

from __future__ import annotations

import jax.numpy as jnp
from jaxtyping import Array, Float


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
