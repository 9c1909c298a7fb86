"""Shared test utilities: central finite differences to check gradients."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np


def fd_grad(f, x, h: float = 1e-6):
    """Central finite-difference gradient of the scalar ``f`` at the array ``x`` (relative step ``h``)."""
    x = np.asarray(x, dtype=np.float64)
    g = np.zeros_like(x)
    step = h * np.maximum(np.abs(x), 1.0)
    for i in np.ndindex(x.shape):
        e = np.zeros_like(x)
        e[i] = step[i]
        g[i] = (float(f(jnp.asarray(x + e))) - float(f(jnp.asarray(x - e)))) / (2 * step[i])
    return g


def check_grad(f, x, rtol: float = 1e-6, atol: float = 1e-9, h: float = 1e-6):
    """Assert ``jax.grad(f)(x)`` equals central differences; returns both for further checks."""
    ad = np.asarray(jax.grad(f)(jnp.asarray(x, dtype=jnp.float64)))
    fd = fd_grad(f, x, h)
    assert np.all(np.isfinite(ad)), "gradient has NaN/inf"
    np.testing.assert_allclose(ad, fd, rtol=rtol, atol=atol * max(1.0, np.abs(fd).max()))
    return ad, fd
