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


def np_sac_roughness(x, a) -> float:
    """Reference (numpy, loops) for :func:`hullopt.fairing.sac_roughness`: Σ (A'')² Δx of a sectional-area curve
    ``a (n,)`` [m²] at stations ``x (n,)`` [m], second divided differences."""
    x, a = np.asarray(x, float), np.asarray(a, float)
    h0, h1 = np.diff(x)[:-1], np.diff(x)[1:]
    d2 = 2.0 * ((a[2:] - a[1:-1]) / h1 - (a[1:-1] - a[:-2]) / h0) / (h0 + h1)
    return float(np.sum(d2**2 * 0.5 * (h0 + h1)))


def np_section_roughness(yz, merge: float = 1e-3) -> float:
    """Reference (numpy, boolean indexing) for :func:`hullopt.fairing.section_roughness`: the mean over stations of
    Σ (Δκ)²/Δs of each half-section polyline, centreline points and segments under ``merge`` [m] dropped."""
    total = []
    for p in np.asarray(yz, float):
        p = p[p[:, 0] > 1e-9]
        d = np.diff(p, axis=0)
        ds = np.hypot(d[:, 0], d[:, 1])
        d, ds = d[ds > merge], ds[ds > merge]
        if len(ds) < 3:
            total.append(0.0)
            continue
        t = d / ds[:, None]
        turn = np.arctan2(t[:-1, 0] * t[1:, 1] - t[:-1, 1] * t[1:, 0], np.sum(t[:-1] * t[1:], 1))
        kappa = turn / (0.5 * (ds[:-1] + ds[1:]))
        total.append(float(np.sum(np.diff(kappa) ** 2 / ds[1:-1])))
    return float(np.mean(total))
