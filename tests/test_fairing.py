"""Fairing geometry: the Coons surface, curvature, and the unfairness functionals (values, gradients)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import quad
from scipy.interpolate import CubicSpline as ScipySpline

from conftest import REPO
from hullopt.fairing import RESIDUALS, graph_curvatures, measure, section_curvature, surface_curvatures, unfairness
from hullopt.geometry import Sections, coons_surface, natural_cubic_spline, spline_slopes
from hullopt.models import offsets_to_sections, read_offsets, wigley

from helpers import check_grad

SEED003 = str(REPO / "hullopt/data/offsets/seed003_table1.csv")
ORDERS = ((1, 0), (0, 1), (2, 0), (1, 1), (0, 2))
surface = jax.jit(coons_surface, static_argnums=3)
value = jax.jit(lambda s, xq, zq: s(xq, zq))
derivs = jax.jit(lambda s, xq, zq: tuple(s(xq, zq, a, b) for a, b in ORDERS))


@pytest.fixture(scope="module")
def table():
    return read_offsets(SEED003)


def wigley_offsets(ns=9, nw=6, L=100.0, B=10.0, T=6.25):
    x, z = np.linspace(0, L, ns), np.linspace(0, T, nw)
    return x, z, (B / 2) * (1 - (2 * (x[:, None] - L / 2) / L) ** 2) * (1 - ((T - z[None, :]) / T) ** 2)


@pytest.mark.parametrize("end", ["not-a-knot", "natural"])
def test_spline_slopes_match_scipy(end):
    rng = np.random.default_rng(0)
    k = np.cumsum(rng.uniform(0.5, 2.0, 9))
    v = rng.normal(size=(9, 3))
    ours = spline_slopes(jnp.asarray(k), jnp.asarray(v), end)
    np.testing.assert_allclose(ours, ScipySpline(k, v, bc_type=end)(k, 1), rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("end", ["not-a-knot", "natural"])
def test_coons_patches_interpolate_their_boundary_curves(table, end):
    x, z, y = table.x, table.z, table.y
    s = surface(jnp.asarray(x), jnp.asarray(z), jnp.asarray(y), end)
    zz, xx = np.linspace(z[0], z[-1], 97), np.linspace(x[0], x[-1], 201)
    frames = ScipySpline(z, y.T, bc_type=end)(zz).T  # every station's frame line, (s, 97)
    wls = ScipySpline(x, y, bc_type=end)(xx)  # every waterline, (201, w)
    np.testing.assert_allclose(value(s, x[:, None], zz[None, :]), frames, atol=1e-12)
    np.testing.assert_allclose(value(s, xx[:, None], z[None, :]), wls, atol=1e-12)
    if end == "natural":  # the same as the kernel's splines
        np.testing.assert_allclose(value(s, x[3], zz), natural_cubic_spline(jnp.asarray(z), jnp.asarray(y[3]))(zz), atol=1e-12)


def test_coons_surface_is_c1_with_curvature_jumps_across_patch_edges(table):
    s = coons_surface(jnp.asarray(table.x), jnp.asarray(table.z), jnp.asarray(table.y))
    u = jnp.array([0.3, 0.6])
    below, above = s.cells(u, jnp.array([1.0]), 0, 1)[:, :-1], s.cells(u, jnp.array([0.0]), 0, 1)[:, 1:]
    np.testing.assert_allclose(below, above, atol=1e-10)  # cross slope continuous across waterline edges
    aft, fore = s.cells(jnp.array([1.0]), u, 1, 0)[:-1], s.cells(jnp.array([0.0]), u, 1, 0)[1:]
    np.testing.assert_allclose(aft, fore, atol=1e-10)
    jump = s.cells(u, jnp.array([0.0]), 0, 2)[:, 1:] - s.cells(u, jnp.array([1.0]), 0, 2)[:, :-1]
    assert float(jnp.max(jnp.abs(jump))) > 1e-2  # but only C¹: the seed's reason for edge-aware measures


def test_coons_reproduces_a_twist_free_bicubic():
    """f = a(x) + b(z) with cubic a, b has no twist: the zero-twist patches reproduce it exactly."""
    x, z = np.array([0.0, 1.0, 2.5, 3.0, 4.5, 6.0]), np.array([0.0, 0.7, 1.5, 2.0, 3.1])
    a = lambda t: 1 + 0.3 * t - 0.05 * t**2 + 0.01 * t**3  # noqa: E731
    b = lambda t: 0.5 * t - 0.2 * t**2 + 0.03 * t**3  # noqa: E731
    s = surface(jnp.asarray(x), jnp.asarray(z), jnp.asarray(a(x)[:, None] + b(z)[None, :]), "not-a-knot")
    xp, zp = np.random.default_rng(1).uniform(0, 6, 50), np.random.default_rng(2).uniform(0, 3.1, 50)
    np.testing.assert_allclose(value(s, xp, zp), a(xp) + b(zp), atol=1e-12)
    fx, fz, fxx, fxz, fzz = derivs(s, xp, zp)
    np.testing.assert_allclose(fzz, -0.4 + 0.18 * zp, atol=1e-10)
    np.testing.assert_allclose(fxz, 0.0, atol=1e-10)
    np.testing.assert_allclose(fx, 0.3 - 0.1 * xp + 0.03 * xp**2, atol=1e-10)


def test_curvature_of_cylinder_and_sphere_closed_forms():
    r, uv = 2.5, jnp.array([[0.3, 0.7], [1.1, -0.4], [2.0, 0.9]])
    u, v = uv[:, 0], uv[:, 1]
    zero = jnp.zeros_like(u)
    # cylinder (x = v, y = R sin u, z = −R cos u); r_v × r_u points inwards → ordering (v, u)
    ru = jnp.stack([zero, r * jnp.cos(u), r * jnp.sin(u)], -1)
    ruu = jnp.stack([zero, -r * jnp.sin(u), r * jnp.cos(u)], -1)
    rv = jnp.stack([zero + 1, zero, zero], -1)
    k, h = surface_curvatures(rv, ru, 0 * ruu, 0 * ruu, ruu)
    np.testing.assert_allclose(k, 0.0, atol=1e-14)
    np.testing.assert_allclose(h, 1 / (2 * r), rtol=1e-12)
    # sphere: r(θ, φ) with r_θ × r_φ pointing outwards
    t, p = u, v
    pos = lambda t, p: r * jnp.stack([jnp.sin(t) * jnp.cos(p), jnp.sin(t) * jnp.sin(p), jnp.cos(t)], -1)  # noqa: E731
    d = lambda f, i: jax.vmap(jax.jacfwd(f, argnums=i))(t, p)  # noqa: E731
    rt, rp = d(pos, 0), d(pos, 1)
    rtt = jax.vmap(jax.jacfwd(jax.jacfwd(pos, 0), 0))(t, p)
    rtp = jax.vmap(jax.jacfwd(jax.jacfwd(pos, 0), 1))(t, p)
    rpp = jax.vmap(jax.jacfwd(jax.jacfwd(pos, 1), 1))(t, p)
    k, h = surface_curvatures(rt, rp, rtt, rtp, rpp)
    np.testing.assert_allclose(k, 1 / r**2, rtol=1e-12)
    np.testing.assert_allclose(h, -1 / r, rtol=1e-12)  # outward normal: bends away
    k2, h2 = surface_curvatures(rp, rt, rpp, rtp, rtt)  # swapped: inward normal
    np.testing.assert_allclose(h2, 1 / r, rtol=1e-12)


def test_graph_curvatures_equal_the_parametric_formula():
    d = np.random.default_rng(3).normal(size=(5, 20))
    fx, fz, fxx, fxz, fzz = map(jnp.asarray, d)
    one, zero = jnp.ones_like(fx), jnp.zeros_like(fx)
    rx, rz = jnp.stack([one, fx, zero], -1), jnp.stack([zero, fz, one], -1)
    sec = lambda a: jnp.stack([zero, a, zero], -1)  # noqa: E731
    np.testing.assert_allclose(graph_curvatures(fx, fz, fxx, fxz, fzz),
                               surface_curvatures(rx, rz, sec(fxx), sec(fxz), sec(fzz)), rtol=1e-12)


@pytest.mark.slow
def test_coons_curvature_of_cylinder_and_sphere_offsets():
    r = 10.0
    x, z = np.linspace(0.0, 20.0, 11), np.linspace(2.0, 18.0, 33)
    cyl = np.sqrt(r**2 - (z - r) ** 2)[None, :] + 0 * x[:, None]  # cylinder along x, axis at z = R
    s = surface(jnp.asarray(x), jnp.asarray(z), jnp.asarray(cyl), "not-a-knot")
    xp, zp = np.linspace(4, 16, 7)[:, None], np.linspace(6, 14, 9)[None, :]
    k, h = graph_curvatures(*derivs(s, xp, zp))
    np.testing.assert_allclose(k, 0.0, atol=1e-14)
    np.testing.assert_allclose(h, 1 / (2 * r), rtol=2e-3)
    # a sphere cap y = √(R² − (x − 10)² − (z − 10)²), around its pole (zero twist is exact there)
    x, z = np.linspace(4.0, 16.0, 25), np.linspace(4.0, 16.0, 25)
    sph = np.sqrt(r**2 - (x[:, None] - 10) ** 2 - (z[None, :] - 10) ** 2)
    s = surface(jnp.asarray(x), jnp.asarray(z), jnp.asarray(sph), "not-a-knot")
    xp, zp = np.linspace(8, 12, 5)[:, None], np.linspace(8, 12, 5)[None, :]
    k, h = graph_curvatures(*derivs(s, xp, zp))
    np.testing.assert_allclose(k, 1 / r**2, rtol=1e-2)
    np.testing.assert_allclose(h, 1 / r, rtol=5e-3)


def test_section_curvature_of_a_circle_is_exact():
    r, th = 3.0, np.linspace(0, np.pi, 25)
    yz = np.stack([r * np.sin(th), r - r * np.cos(th)], -1)
    s = Sections(x=jnp.array([0.0, 1.0]), yz=jnp.asarray(np.stack([yz, yz])), lpp=jnp.asarray(1.0))
    kappa = section_curvature(s)
    np.testing.assert_allclose(kappa[:, 1:-1], 1 / r, rtol=1e-12)  # chords of a circle: exactly 1/R
    np.testing.assert_allclose(kappa[:, [0, -1]], 0.0)
    flipped = Sections(x=s.x, yz=s.yz.at[..., 0].multiply(-1), lpp=s.lpp)  # turning right: concave
    np.testing.assert_allclose(section_curvature(flipped)[:, 1:-1], -1 / r, rtol=1e-12)


def test_lines_measure_against_quadrature():
    """Offsets a(x) + c·z: straight frames (κ = 0), every waterline the cubic a(x) shifted; the measure is
    L³·(w waterlines)·∫ (dκ/ds)² ds, integrated here by scipy.quad on the closed form."""
    x, z = np.linspace(0.0, 10.0, 7), np.linspace(0.0, 2.0, 4)
    a0, a1, a2, a3 = 2.0, 0.4, -0.09, 0.004
    y = (a0 + a1 * x + a2 * x**2 + a3 * x**3)[:, None] + 0.3 * z[None, :]
    d1 = lambda t: a1 + 2 * a2 * t + 3 * a3 * t**2  # noqa: E731
    d2 = lambda t: 2 * a2 + 6 * a3 * t  # noqa: E731
    dk = lambda t: -6 * a3 / (1 + d1(t) ** 2) ** 1.5 + 3 * d1(t) * d2(t) ** 2 / (1 + d1(t) ** 2) ** 2.5  # noqa: E731
    one = quad(lambda t: dk(t) ** 2 / np.sqrt(1 + d1(t) ** 2), 0, 10, epsabs=1e-14, epsrel=1e-12)[0]
    lines = jax.jit(lambda yy: measure(coons_surface(jnp.asarray(x), jnp.asarray(z), yy), "lines"))  # one compile
    assert float(lines(jnp.asarray(y))) == pytest.approx(10.0**3 * 4 * one, rel=1e-4)  # 3-point Gauss


@pytest.mark.slow
def test_knots_and_jumps_vanish_on_a_twist_free_bicubic_and_see_one_bad_offset():
    x, z, y = wigley_offsets()
    y2 = np.sin(x / 40)[:, None] * 0 + (1 + 0.02 * x - 1e-4 * x**2)[:, None] + (0.3 * z - 0.01 * z**3)[None, :]
    # each measure of the surface through the offsets compiled once (jit) for the three tables below
    of = jax.jit(lambda yy, name: measure(coons_surface(jnp.asarray(x), jnp.asarray(z), yy), name), static_argnums=1)
    for name in ("knots", "jumps"):
        assert float(of(jnp.asarray(y2), name)) < 1e-16
    bad = y2.copy()
    bad[4, 3] += 0.01
    for name in RESIDUALS:
        assert float(of(jnp.asarray(bad), name)) > float(of(jnp.asarray(y2), name)) + 1e-3
    # a parabolic (Wigley) hull is fair for "knots": every line is one cubic
    assert float(of(jnp.asarray(y), "knots")) < 1e-12


@pytest.mark.parametrize("name", list(RESIDUALS))
@pytest.mark.slow
def test_measure_gradients_match_finite_differences(name):
    x, z, y = wigley_offsets(7, 5)
    y = y + np.where(y > 0, 0.03 * np.random.default_rng(4).normal(size=y.shape), 0.0)
    f = jax.jit(lambda yy: measure(coons_surface(jnp.asarray(x), jnp.asarray(z), yy), name, y > 0))
    check_grad(f, y, rtol=1e-5, atol=1e-7)


@pytest.fixture(scope="module")
def seed003_sections(table):
    return offsets_to_sections(table, 21, 15)


@pytest.mark.slow
def test_unfairness_of_sections(seed003_sections):
    r, th = 3.0, np.linspace(0, np.pi / 2, 9)
    yz = np.stack([r * np.sin(th), r - r * np.cos(th)], -1)
    cyl = Sections(x=jnp.linspace(0, 10, 5), yz=jnp.asarray(np.broadcast_to(yz, (5, 9, 2))), lpp=jnp.asarray(10.0))
    f = jax.jit(unfairness)
    assert float(f(cyl)) < 1e-20  # constant curvature around, straight along
    w = wigley(100, 10, 6.25, 6.25, n=11, m=9)
    smooth = float(f(w))
    bumped = Sections(w.x, w.yz.at[3, 4, 0].add(0.05), w.lpp)  # a 5 cm dent in one section
    assert float(f(bumped)) > 2 * smooth
    assert float(f(seed003_sections)) > smooth  # the hand-drawn table is rougher than the Wigley
    batch = jax.jit(jax.vmap(lambda yz: unfairness(Sections(w.x, yz, w.lpp))))(jnp.stack([w.yz, bumped.yz]))
    np.testing.assert_allclose(batch, [smooth, float(f(bumped))], rtol=1e-12)


@pytest.mark.slow
def test_unfairness_gradient_matches_finite_differences():
    s = wigley(100, 10, 6.25, 8.0, n=5, m=6)  # with the vertical side above T and the keel point at y = 0
    yz0 = np.asarray(s.yz) + 0.01 * np.random.default_rng(5).normal(size=s.yz.shape) * (np.asarray(s.yz) > 0)
    f = jax.jit(lambda yz: unfairness(Sections(s.x, yz, s.lpp)))
    check_grad(f, yz0, rtol=1e-5, atol=1e-7)
