"""K0, K1 (Cephes series in JAX) and the draft factor α_T against scipy and the 80-digit reference table."""

import csv

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.special as sp

from conftest import DATA
from hullopt.waves import alpha_t, k0, k0e, k1, k1e

X = np.geomspace(1e-6, 700.0, 4001)


@pytest.mark.parametrize("ours,ref", [(k0, sp.k0), (k1, sp.k1), (k0e, sp.k0e), (k1e, sp.k1e)])
def test_k_against_scipy(ours, ref):
    got = np.asarray(jax.jit(ours)(X))
    np.testing.assert_allclose(got, ref(X), rtol=1e-13, atol=0)


def test_derivatives_match_recurrences():
    x = jnp.asarray(np.geomspace(1e-3, 300.0, 301))
    d = jax.jit(jax.vmap(jax.grad(k0e)))(x)
    np.testing.assert_allclose(d, sp.k0e(x) - sp.k1e(x), rtol=1e-12)
    d = jax.jit(jax.vmap(jax.grad(k1)))(x)
    np.testing.assert_allclose(d, -sp.k0(x) - sp.k1(x) / x, rtol=1e-12)
    # second derivative through the custom JVP: K0'' = K0 + K1/x
    d2 = jax.jit(jax.vmap(jax.grad(jax.grad(k0))))(x)
    np.testing.assert_allclose(d2, sp.k0(x) + sp.k1(x) / x, rtol=1e-11)


def _reference():
    with open(DATA / "alpha_T_bessel_reference.csv") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    head, body = rows[0], rows[1:]
    return {k: np.array([float(r[i]) for r in body]) for i, k in enumerate(head)}


def test_alpha_t_and_k1_against_reference_table():
    ref = _reference()
    x = ref["x"]
    # the table gives 13 significant digits
    np.testing.assert_allclose(np.asarray(jax.jit(k1)(x)), ref["K1"], rtol=2e-12)
    np.testing.assert_allclose(np.asarray(sp.i1(x)), ref["I1"], rtol=2e-12)  # the table itself is sound
    np.testing.assert_allclose(np.asarray(jax.jit(alpha_t)(x)), ref["alpha_T"], rtol=2e-12, atol=0)
    tail = ref["one_minus_alpha_T"] > 1e-6  # where 1 − α_T is still representable from α_T to 7 digits
    np.testing.assert_allclose(1.0 - np.asarray(alpha_t(x[tail])), ref["one_minus_alpha_T"][tail], rtol=1e-5)


def test_alpha_t_is_finite_with_asymptotes_and_gradients():
    x = jnp.asarray(np.concatenate([[0.0, 1e-300, 1e-8], np.geomspace(1e-3, 1e3, 200), [1e6]]))
    a = np.asarray(jax.jit(alpha_t)(x))
    assert np.all(np.isfinite(a)) and a[0] == 0.0 and a[-1] == 1.0
    small = np.asarray(x) < 1e-2
    np.testing.assert_allclose(a[small][1:], np.pi**2 * np.asarray(x)[small][1:] ** 4 / 4, rtol=1e-3)
    g = np.asarray(jax.jit(jax.vmap(jax.grad(alpha_t)))(x))
    assert np.all(np.isfinite(g)) and g[0] == 0.0
    # analytic derivative from scipy: α = r²/(1+r²), r = π I1/K1
    keep = slice(3, -1)
    xs = np.asarray(x)[keep]
    keep_small = xs < 50.0
    xs = xs[keep_small]
    r = np.pi * sp.i1(xs) / sp.k1(xs)
    dr = np.pi * ((sp.i0(xs) - sp.i1(xs) / xs) * sp.k1(xs) + sp.i1(xs) * (sp.k0(xs) + sp.k1(xs) / xs)) / sp.k1(xs) ** 2
    np.testing.assert_allclose(g[keep][keep_small], 2 * r * dr / (1 + r * r) ** 2, rtol=1e-9, atol=1e-300)
    # continuity across the branch switch at x = 2
    at = jax.jit(alpha_t)
    np.testing.assert_allclose(at(2.0), at(np.nextafter(2.0, 3.0)), rtol=1e-14)
