"""Michell's thin-ship wave resistance from the sections: against the Wigley hull's closed-form x and z
integrals (the λ integral by adaptive quadrature), convergence, speeds vmapped, gradients by differences."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import check_grad
from scipy.integrate import quad

from hullopt.errors import HullError
from hullopt.geometry import Sections
from hullopt.models import wigley
from hullopt.resistance import LAMBDA_PANELS, michell_wave_resistance

G, RHO = 9.80665, 1025.0
L, B, T = 100.0, 10.0, 6.25
FNS = np.array([0.2, 0.25, 0.3, 0.35, 0.4, 0.45])


def wigley_reference(fn):
    """R_w [N] of the Wigley hull Y = (B/2)(1 − ξ²)(1 − ζ²), ξ = 2x/L − 1, ζ = (T − z)/T, by Michell's
    integral with its x and z integrals in closed form:
    ∫ Y_x e^{ikx} dx = −2iB e^{ikL/2}(sin κ − κ cos κ)/κ², κ = kL/2, k = k₀λ, and
    ∫ (1 − ζ²) e^{−k₀λ²(T − z)} dz = T[(1 − e^{−a})/a − 2/a³ + e^{−a}(1/a + 2/a² + 2/a³)], a = k₀λ²T;
    the λ integral by adaptive quadrature in λ = cosh u (no singularity) to λ = 400 (tail < 1e-8)."""
    u = fn * np.sqrt(G * L)
    k0 = G / u**2

    def f(v):
        lam = np.cosh(v)
        kap = k0 * lam * L / 2
        x = 2 * B * (np.sin(kap) - kap * np.cos(kap)) / kap**2
        a = k0 * lam**2 * T
        z = T * ((1 - np.exp(-a)) / a - 2 / a**3 + np.exp(-a) * (1 / a + 2 / a**2 + 2 / a**3))
        return (x * z) ** 2 * lam**2

    edges = np.linspace(0.0, np.arccosh(400.0), 161)
    tot = sum(quad(f, a, b, limit=200, epsabs=0, epsrel=1e-10)[0] for a, b in zip(edges[:-1], edges[1:]))
    return 4 * RHO * G**2 / (np.pi * u**2) * tot


@pytest.fixture(scope="module")
def reference():
    return np.array([wigley_reference(f) for f in FNS])


def test_wigley_against_closed_forms(reference):
    """101 stations × 33 levels: within 7e-4 of the closed forms at Fn 0.2–0.45 (measured 3.3e-4 to 6.7e-4,
    below the exact value: the polyline sections and the ruled surface are slightly thinner); second order,
    the error falls about 4× from 41 × 17 (measured 1.1e-3 to 3.2e-3)."""
    speeds = jnp.asarray(FNS * np.sqrt(G * L))
    fine = np.asarray(jax.jit(michell_wave_resistance)(wigley(L, B, T, 10.0, n=101, m=33), T, speeds))
    np.testing.assert_allclose(fine, reference, rtol=1e-3)
    coarse = jax.jit(lambda s, u: michell_wave_resistance(s, T, u, n_levels=17))(
        wigley(L, B, T, 10.0, n=41, m=17), speeds)
    err_f, err_c = np.abs(fine / reference - 1), np.abs(np.asarray(coarse) / reference - 1)
    assert np.all(err_c < 5e-3) and np.all(err_c / err_f > 3.0)
    # the classic humps and hollows of the Wigley: a hump near Fn 0.3, a hollow near 0.35, rising beyond
    assert fine[2] > fine[3] < fine[4] < fine[5] and fine[1] < fine[2]


def test_low_froude_number_oscillation(reference):
    """At Fn 0.15 the bow and stern waves interfere with period 2π/(k₀L) = 0.14 in λ; the exact x integral
    and the default 256 panels hold the closed forms to the same 1e-3 (measured −1e-4)."""
    r = float(jax.jit(michell_wave_resistance)(wigley(L, B, T, 10.0, n=101, m=33), T, 0.15 * np.sqrt(G * L)))
    assert r == pytest.approx(wigley_reference(0.15), rel=1e-3)


def test_speeds_shape_zero_speed_and_bad_input():
    s = wigley(L, B, T, 10.0, n=21, m=9)
    f = jax.jit(lambda u: michell_wave_resistance(s, T, u, n_levels=9))
    r = np.asarray(f(jnp.array([[0.0, 5.0], [7.0, 9.0]])))
    assert r.shape == (2, 2) and r[0, 0] == 0.0 and np.all(r.ravel()[1:] > 0)
    np.testing.assert_allclose(r[1, 1], float(f(9.0)), rtol=1e-13)
    with pytest.raises(HullError, match="n_levels"):
        michell_wave_resistance(s, T, 5.0, n_levels=1)
    with pytest.raises(HullError, match="panels"):
        michell_wave_resistance(s, T, 5.0, panels=0)


def test_gradients_match_central_differences():
    """∂R_w/∂(breadth scale, draft scale, speed, one offset) against central differences (measured ≤ 7e-9)."""
    s0 = wigley(L, B, T, 10.0, n=41, m=17)

    def f(v):
        yz = s0.yz * jnp.array([v[0], 1.0])
        yz = yz.at[20, 8, 0].multiply(1.0 + v[3])
        return michell_wave_resistance(Sections(x=s0.x, yz=yz, lpp=s0.lpp), T * v[1], v[2], n_levels=17)

    check_grad(jax.jit(f), np.array([1.0, 0.95, 0.3 * np.sqrt(G * L), 0.1]), rtol=1e-7, h=1e-5)


def test_a_dip_below_a_flat_bottom_moves_r_w_continuously():
    """A flat-bottomed Wigley whose keel point at one station dips δ below the flat: R_W moves by O(δ),
    not by the jump of the lowest level's half-breadth between 0 and the flat's (which a probe 1e-9·T above
    the keel made, 1.5 % on the KCS between designs 1e-10 apart)."""
    n, m = 61, 25
    xi = np.linspace(-1.0, 1.0, n)
    b = 0.5 * B * (1.0 - xi**2)
    zeta = np.linspace(0.0, 1.0, m - 1)
    wall = np.stack([b[:, None] * (0.4 + 0.6 * (1.0 - (1.0 - zeta) ** 2)),
                     np.broadcast_to(1.5 * T * zeta, (n, m - 1))], -1)
    keel = np.zeros((n, 1, 2))  # the centreline point of the flat bottom, then its edge at 0.4 b
    yz = np.concatenate([keel, wall], axis=1)
    x = jnp.asarray((xi + 1.0) * L / 2)
    speed = 0.3 * np.sqrt(G * L)
    r = jax.jit(lambda yz: michell_wave_resistance(Sections(x, yz, T), T, speed))
    flat = float(r(jnp.asarray(yz)))
    for dip in (0.5e-9 * T, 2e-9 * T, 1e-6, 1e-3):
        dipped = yz.copy()
        dipped[n // 2, 0, 1] = -dip
        assert float(r(jnp.asarray(dipped))) == pytest.approx(flat, rel=max(dip / T, 1e-8))  # was off 1.1 %


def test_the_analyses_lambda_rule_against_a_fine_one():
    """``LAMBDA_PANELS`` (64, what objectives and rescoring use) against 1024 panels on the Wigley, the hull
    with the strongest bow–stern interference: measured 1.3e-5 at Fn 0.12, 8e-9 at 0.15, 6e-12 at 0.2."""
    s = wigley(L, B, T, 10.0, n=101, m=33)
    u = jnp.asarray(np.array([0.12, 0.15, 0.2]) * np.sqrt(G * L))
    rule = jax.jit(lambda p: michell_wave_resistance(s, T, u, panels=p), static_argnums=0)
    err = np.abs(np.asarray(rule(LAMBDA_PANELS)) / np.asarray(rule(1024)) - 1)
    assert np.all(err < [4e-5, 4e-8, 4e-11])
