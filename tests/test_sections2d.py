"""Sectional heave added mass and damping by Frank's close-fit method (hullopt/waves/_sections2d.py), against
closed forms and limits that do not come from hullopt: E1 against scipy, the infinite-frequency added mass
of a semicircle (ρπR²/2, the half of a circle's in unbounded fluid) and of rectangles (Blevins, "Formulas for
natural frequency and mode shape", Table 14-2, rectangles of sides 2a × 2b moving normal to 2a: the
double-body of a box of beam B = 2a and draft T = b), the low-frequency damping limit b33 → ρωB² (a source
of flux ωB... radiating ν B-amplitude waves, Ursell 1949's leading term), and energy conservation (damping
from the pressure equals the energy flux of the far-field waves)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.special

from hullopt.waves._sections2d import exp1, far_field_damping, heave_coefficients, section_panels

RHO, G = 1025.0, 9.80665
_coefficients = jax.jit(heave_coefficients, static_argnames=("n_gauss", "infinite"))
_far_damping = jax.jit(far_field_damping)


def _semicircle(r, n):
    a = np.linspace(0.0, 0.5 * np.pi, n + 1)
    return jnp.asarray(np.stack([r * np.sin(a), -r * np.cos(a)], axis=-1))


def _box(b, t, n):
    nb = n // 2
    y = np.r_[np.linspace(0.0, b / 2, nb + 1), np.full(n - nb, b / 2)]
    z = np.r_[np.full(nb + 1, -t), np.linspace(-t, 0.0, n - nb + 1)[1:]]
    return jnp.asarray(np.stack([y, z], axis=-1))


def test_exp1_matches_scipy_in_the_second_quadrant():
    rng = np.random.default_rng(0)
    r = 10 ** rng.uniform(-3, 2.5, 3000)
    th = rng.uniform(0.5 * np.pi, np.pi, 3000)
    z = r * np.exp(1j * th)
    ref = scipy.special.exp1(z)
    rel = np.abs(np.asarray(exp1(jnp.asarray(z))) - ref) / np.abs(ref)
    assert rel[r < 20].max() < 1e-11  # measured 1.4e-12
    assert rel.max() < 2e-10  # measured 4.3e-11 (|z| ≤ 300; the fraction near the cut, |z| > 25)


def test_infinite_frequency_added_mass_of_semicircle_and_boxes():
    a, _ = _coefficients(_semicircle(1.0, 40), 1.0, infinite=True)
    assert float(a) / (RHO * np.pi / 2) == pytest.approx(1.0, abs=0.012)  # measured +0.85 % (N = 40)
    for b_over_t, c in ((1.0, 1.70), (2.0, 1.51), (4.0, 1.36), (10.0, 1.21)):
        a, _ = _coefficients(_box(2.0, 2.0 / b_over_t, 40), 1.0, infinite=True)
        assert float(a) / (0.5 * c * RHO * np.pi) == pytest.approx(1.0, abs=0.01)  # measured ≤ 0.82 %


def test_semicircle_damping_low_frequency_limit_and_energy_flux():
    nodes = _semicircle(1.0, 40)
    om = np.sqrt(0.001 * G)
    _, b = _coefficients(nodes, om)
    assert float(b) / (RHO * om * 4.0) == pytest.approx(1.0, abs=0.01)  # measured 0.996 at νR = 0.001
    om = np.sqrt(np.array([0.1, 0.5, 1.0, 2.0]) * G)
    _, b = jax.vmap(_coefficients, (None, 0))(nodes, om)
    ratio = np.asarray(b) / np.asarray(jax.vmap(_far_damping, (None, 0))(nodes, om))
    np.testing.assert_allclose(ratio, 1.0, atol=0.01)  # measured ≤ 0.6 %


@pytest.mark.slow
def test_semicircle_coefficients_converge_with_panels():
    # The classical curve (Ursell 1949; Frank 1967 Fig. 3): added mass coefficient C = a33/(ρπR²/2) with its
    # minimum ≈ 0.6 near νR = 1 and → 1 as ω → ∞; converged to 1 % between 20 and 40 panels.
    om = np.sqrt(np.array([0.25, 1.0, 2.0]) * G)
    a20, b20 = jax.vmap(_coefficients, (None, 0))(_semicircle(1.0, 20), om)
    a40, b40 = jax.vmap(_coefficients, (None, 0))(_semicircle(1.0, 40), om)
    np.testing.assert_allclose(np.asarray(a20 / a40), 1.0, atol=0.02)
    np.testing.assert_allclose(np.asarray(b20 / b40), 1.0, atol=0.08)
    a, _ = _coefficients(_semicircle(1.0, 40), np.sqrt(G))
    assert 0.55 < float(a) / (RHO * np.pi / 2) < 0.65


def test_section_panels_follow_the_wigley_sections(wigley_small):
    nodes, wet = jax.jit(section_panels, static_argnums=2)(wigley_small, 6.25, 16)
    assert nodes.shape == (wigley_small.n, 17, 2)
    assert bool(jnp.all(nodes[..., 1] <= 1e-12)) and bool(jnp.all(nodes[..., 0] >= 0.0))
    assert not bool(wet[0]) and not bool(wet[-1]) and bool(jnp.all(wet[1:-1]))
    mid = wigley_small.n // 2
    assert float(nodes[mid, -1, 0]) == pytest.approx(5.0, rel=1e-9)  # waterline half-breadth B/2
    assert float(nodes[mid, 0, 1]) == pytest.approx(-6.25, rel=1e-9)  # keel at the draft


@pytest.mark.slow
def test_gradient_of_damping_in_the_section_shape():
    def b33(scale):
        _, b = heave_coefficients(_semicircle(1.0, 20) * jnp.asarray([scale, 1.0]), 2.0)
        return b

    vg = jax.jit(jax.value_and_grad(b33))  # one compile for the gradient and the differences
    _, g = vg(1.0)
    h = 1e-5
    fd = (vg(1.0 + h)[0] - vg(1.0 - h)[0]) / (2 * h)
    assert np.isfinite(float(g)) and float(g) == pytest.approx(float(fd), rel=1e-6)


@pytest.fixture(scope="module")
def wigley_small():
    from hullopt.models import wigley

    return wigley(100.0, 10.0, 6.25, 8.0, n=11, m=21)


def test_immersed_section_ends_on_the_waterline_crossing_and_has_the_mean_derivative_on_a_point():
    from hullopt.waves._sections2d import _resample_polyline

    yz = jnp.asarray([[0.0, 0.0], [1.0, 0.5], [2.0, 1.5], [3.0, 3.0], [4.0, 5.0]])  # flared above z = 1.5
    nodes = lambda t: _resample_polyline(yz, t, 6, 1e-3)[0]  # noqa: E731
    # between points the last node is the crossing (2 + 1/3, 0), not the start of the dry segment above (3, 0)
    np.testing.assert_allclose(nodes(2.0)[-1], [7.0 / 3.0, 0.0], atol=1e-12)
    # on a point (z = 1.5) the nodes' derivative is the mean of the one-sided ones, as central differences
    h = 1e-7
    up, down = (nodes(1.5 + h) - nodes(1.5)) / h, (nodes(1.5) - nodes(1.5 - h)) / h
    assert float(jnp.max(jnp.abs(up - down))) > 0.1  # a real kink
    np.testing.assert_allclose(jax.jacfwd(nodes)(1.5), 0.5 * (up + down), atol=1e-6)
