"""hullopt.geometry.pchip: numpy PCHIP (the feature model's distributions, the mesh writer, the lines plan's deck
line) against scipy's PchipInterpolator, on random data with flat chords, sign changes and uneven knots."""

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator

from hullopt.geometry import pchip, pchip_slopes


@pytest.mark.parametrize("shape", [(), (4,), (5, 2)])
def test_pchip_is_scipys(shape):
    rng = np.random.default_rng(7)
    for _ in range(100):
        x = np.unique(rng.uniform(0.0, 100.0, rng.integers(2, 25)))
        if x.size < 2:
            continue
        y = rng.normal(size=(x.size, *shape))
        y[rng.uniform(size=y.shape) < 0.2] = 0.0  # flat chords
        y[:2] = y[:1]  # a flat start
        if shape:
            y[..., 0] = np.cumsum(np.abs(y[..., 0]), axis=0)  # a monotone column
        ref = PchipInterpolator(x, y, axis=0)
        np.testing.assert_allclose(pchip_slopes(x, y), ref.derivative()(x), rtol=1e-12, atol=1e-12)
        t = np.sort(np.r_[rng.uniform(x[0], x[-1], 50), x])
        np.testing.assert_allclose(pchip(x, y, t), ref(t), rtol=1e-12, atol=1e-12)


def test_hermite_traced_is_the_numpy_one_and_differentiates():
    """The feature model's traced Hermite evaluation (``xp=jax.numpy``) equals numpy's, and its derivative in
    ``t`` (the distributions' moved stations) matches central differences."""
    import jax
    import jax.numpy as jnp

    from hullopt.geometry import hermite

    rng = np.random.default_rng(3)
    x = np.sort(rng.uniform(0.0, 50.0, 12))
    y = rng.normal(size=(12, 3))
    d = pchip_slopes(x, y)
    t = rng.uniform(x[0], x[-1], 9)
    ours = hermite(jnp.asarray(x), jnp.asarray(y), jnp.asarray(d), jnp.asarray(t), jnp)
    np.testing.assert_allclose(ours, hermite(x, y, d, t), rtol=1e-13, atol=1e-13)
    g = jax.grad(lambda t: jnp.sum(hermite(jnp.asarray(x), jnp.asarray(y), jnp.asarray(d), t, jnp)))(jnp.asarray(t))
    h = 1e-6
    fd = (hermite(x, y, d, t + h).sum(axis=1) - hermite(x, y, d, t - h).sum(axis=1)) / (2 * h)
    np.testing.assert_allclose(g, fd, rtol=1e-6, atol=1e-6)
