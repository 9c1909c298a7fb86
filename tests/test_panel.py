"""The Rankine-source panel method (hullopt.resistance._panel): Hess–Smith panel velocities against quadrature,
the sphere's potential flow and Havelock's submerged-sphere wave resistance (closed forms), the thin-ship limit
(Michell's integral), convergence with the panelling, and gradients against central differences."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import quad

from hullopt.constants import G, RHO_SEA
from hullopt.models import wigley
from hullopt.resistance import (LAMBDA_PANELS, Panels, double_body_flow, kelvin_spectrum, michell_wave_resistance,
                                panel_wave_resistance, source_velocity)
from hullopt.resistance._michell import lambda_nodes

from helpers import fd_grad


def _half_sphere(a, n_theta, n_phi, zc):
    """Port half of a sphere (radius a, centre (0, 0, zc)) as latitude–longitude quads about the x axis."""
    th, ph = np.meshgrid(np.linspace(0, np.pi, n_theta + 1), np.linspace(0, np.pi, n_phi + 1), indexing="ij")
    p = np.stack([a * np.cos(th), a * np.sin(th) * np.sin(ph), zc + a * np.sin(th) * np.cos(ph)], -1)
    return np.stack([p[:-1, :-1], p[:-1, 1:], p[1:, 1:], p[1:, :-1]], 2).reshape(-1, 4, 3)


def test_panel_velocity_matches_quadrature():
    """A flat quadrilateral's closed-form velocity equals a 600 × 600 midpoint sum of (p − q)/(4π|p − q|³),
    near the panel (above, below, beside it) and far away."""
    v = np.array([[0.0, 0.0, 0.0], [1.2, 0.1, 0.0], [1.0, 0.9, 0.0], [-0.1, 1.1, 0.0]])
    pts = np.array([[0.5, 0.5, 0.3], [2.0, 1.0, 0.5], [0.5, 0.5, -0.05], [3.0, 3.0, 0.0], [0.4, 0.6, 0.02]])
    got = np.asarray(source_velocity(jnp.asarray(pts), Panels(jnp.asarray(v[None]), jnp.array(0.0))))[:, 0]
    n = 600
    u = (np.arange(n) + 0.5) / n
    s, t = np.meshgrid(u, u, indexing="ij")
    q = ((1 - s) * (1 - t))[..., None] * v[0] + (s * (1 - t))[..., None] * v[1] + (s * t)[..., None] * v[2] \
        + ((1 - s) * t)[..., None] * v[3]
    ds = (1 - t)[..., None] * (v[1] - v[0]) + t[..., None] * (v[2] - v[3])
    dt = (1 - s)[..., None] * (v[3] - v[0]) + s[..., None] * (v[2] - v[1])
    da = np.linalg.norm(np.cross(ds, dt), axis=-1) / n**2
    for p, g in zip(pts, got):
        r = p - q
        want = (r / np.linalg.norm(r, axis=-1)[..., None] ** 3 * da[..., None]).sum((0, 1)) / (4 * np.pi)
        np.testing.assert_allclose(g, want, atol=2e-3 * np.abs(want).max())


def test_panel_velocity_shortcuts_equal_the_whole_kernel():
    """The shortcuts Dawson's system takes, against the kernel in full: a flat grid of panels at its own centroids
    (``flat``: no solid angle, normal part ½ on the diagonal only), and panels below a waterplane and their images
    above it seen from points on it (two images with the in-plane part doubled and no vertical one)."""
    x, y = np.meshgrid(np.linspace(0.0, 4.0, 6), np.linspace(0.0, 2.0, 4), indexing="ij")
    grid = np.stack([x, y, np.full_like(x, 1.5)], -1)
    quads = np.stack([grid[:-1, :-1], grid[1:, :-1], grid[1:, 1:], grid[:-1, 1:]], 2).reshape(-1, 4, 3)
    quads[..., :2] += 0.05 * np.sin(np.arange(quads[..., :2].size)).reshape(quads[..., :2].shape)  # not a lattice
    flat = Panels(jnp.asarray(quads), jnp.array(1.5))
    whole = source_velocity(flat.centre, flat, own=True)
    np.testing.assert_allclose(source_velocity(flat.centre, flat, own=True, flat=True), whole, rtol=0, atol=1e-15)
    np.testing.assert_allclose(np.diagonal(np.asarray(whole[..., 2])), 0.5)
    below = quads.copy()  # the same quads tilted down from the waterplane z = 1.5: a hull's side
    below[..., 2] = 1.5 - 0.3 * below[..., 1] - 0.1 * below[..., 0]
    above = below[:, ::-1].copy()  # the images above the waterplane, their winding turned
    above[..., 2] = 3.0 - above[..., 2]
    pts = jnp.asarray(grid.reshape(-1, 3) + np.array([0.13, 0.07, 0.0]))  # points on the waterplane
    four = source_velocity(pts, Panels(jnp.asarray(np.concatenate([below, above])), jnp.array(1.5)))
    four = np.asarray(four).reshape(len(pts), 2, -1, 3).sum(1)
    two = 2.0 * np.asarray(source_velocity(pts, Panels(jnp.asarray(below), jnp.array(1.5)))) * [1.0, 1.0, 0.0]
    np.testing.assert_allclose(two, four, rtol=0, atol=1e-14 * np.abs(four).max())
    assert np.abs(four[..., :2]).max() > 1e-3 and np.abs(four[..., 2]).max() < 1e-15


@pytest.fixture(scope="module")
def sphere():
    """A unit sphere 60 m deep (its images in the waterplane 120 m away), 16 × 8 quads on the port side."""
    pan = Panels(jnp.asarray(_half_sphere(1.0, 16, 8, -60.0)), jnp.array(0.0))
    return pan, *double_body_flow(pan)


def test_sphere_surface_velocity(sphere):
    """Potential flow past a sphere: |v| = (3/2)·U·sin θ on its surface (θ from the stream's axis)."""
    pan, _, vel = sphere
    r = np.asarray(pan.centre) - [0.0, 0.0, -60.0]
    sin = np.linalg.norm(r[:, 1:], axis=1) / np.linalg.norm(r, axis=1)
    np.testing.assert_allclose(np.linalg.norm(np.asarray(vel), axis=1), 1.5 * sin, atol=0.01)


def test_sphere_wave_resistance_is_havelocks(sphere):
    """The sphere's panel sources radiating at depth f: Havelock's (1932) R = 4πρg k₀³a⁶ ∫ e^{−2k₀f sec²θ}
    sec⁵θ dθ (a point doublet; the surface sources are one exactly in the wave spectrum, which is harmonic).
    Flat panels inscribed in the sphere overstate its dipole by 2.7 % at this panelling (1.9 % at 48 × 24):
    R within 6 %, where a wrong constant in the spectrum would be off by a factor."""
    pan, sigma, _ = sphere
    u, f = 3.0, 3.0
    k0 = G / u**2
    lam, w = lambda_nodes(256)
    s = kelvin_spectrum(Panels(pan.vertices, jnp.array(-60.0 + f)), sigma * u, k0, lam)
    r = RHO_SEA * G**2 / (np.pi * u**4) * float(jnp.sum(w * jnp.abs(s) ** 2))
    sec = lambda t: 1.0 / np.cos(t)  # noqa: E731
    want = 4 * np.pi * RHO_SEA * G * k0**3 * quad(lambda t: np.exp(-2 * k0 * f * sec(t) ** 2) * sec(t) ** 5,
                                                     0, np.pi / 2)[0]
    assert r == pytest.approx(want, rel=0.06)


FNS = np.array([0.25, 0.3, 0.35, 0.4])


@pytest.mark.slow
def test_thin_wigley_is_michells():
    """On a thin Wigley hull (B/L 0.02) the double-body sources are Michell's thin-ship ones: the panel R_w
    equals Michell's integral within 5 % at Fn 0.25–0.4 (at B/L 0.1 it is 1.25–1.55× Michell's: thickness)."""
    h = wigley(100, 2.0, 6.25, 10, n=61, m=33)
    u = jnp.asarray(FNS * np.sqrt(G * 100.0))
    rp = panel_wave_resistance(h, 6.25, u, stations=32, girth=8).r_wave
    rm = michell_wave_resistance(h, 6.25, u)
    np.testing.assert_allclose(np.asarray(rp) / np.asarray(rm), 1.0, atol=0.05)


@pytest.mark.slow
def test_panel_convergence_and_sinkage():
    """Wigley (L 100, B 10, T 6.25 m) at Fn 0.3: R_w changes < 1.5 % from 32 × 8 to 48 × 12 to 64 × 16 panels,
    monotonely; the double-body sinkage (down) converges likewise and the trim of the fore-aft symmetric hull is 0."""
    h = wigley(100, 10, 6.25, 10, n=61, m=33)
    u = 0.3 * np.sqrt(G * 100.0)
    res = [panel_wave_resistance(h, 6.25, u, stations=s, girth=g) for s, g in ((32, 8), (48, 12), (64, 16))]
    r = np.array([float(x.r_wave) for x in res])
    assert np.all(np.diff(r) > 0) and abs(r[2] / r[1] - 1) < abs(r[1] / r[0] - 1) < 0.015
    sink = np.array([float(x.sinkage) for x in res])
    assert np.all(sink > 0) and abs(sink[2] / sink[1] - 1) < abs(sink[1] / sink[0] - 1) < 0.025
    assert abs(float(res[-1].trim)) < 1e-9


@pytest.mark.parametrize("draft", [6.25, 6.1])
@pytest.mark.slow
def test_panel_gradient_matches_differences(draft):
    """dR_w/dT and dR_w/d(beam scale) by AD equal central differences — between the sections' points and at a
    draft on them (the builtin Wigley's design draft): there the wet girth has a kink, and AD gives the mean of
    the one-sided derivatives, as central differences do."""
    h = wigley(100, 10, 6.25, 10, n=41, m=33)
    u = 0.3 * np.sqrt(G * 100.0)

    def f(p):
        s = eqx_scale(h, p[1])
        return panel_wave_resistance(s, p[0], u, stations=24, girth=6).r_wave / 1e3

    p = np.array([draft, 1.0])
    ad = np.asarray(jax.grad(f)(jnp.asarray(p)))
    fd = fd_grad(f, p, h=1e-5)
    np.testing.assert_allclose(ad, fd, rtol=2e-4)


def eqx_scale(h, s):
    """The hull with every half-breadth times ``s``."""
    return type(h)(x=h.x, yz=h.yz * jnp.stack([s, jnp.ones_like(s)]), lpp=h.lpp)


@pytest.mark.slow
def test_vmap_over_designs_equals_each():
    """A batch of hulls through one vmapped program gives each hull's own value."""
    h = wigley(100, 10, 6.25, 10, n=41, m=33)
    u = 0.3 * np.sqrt(G * 100.0)
    scales = jnp.array([0.9, 1.0, 1.1])
    f = lambda s: panel_wave_resistance(eqx_scale(h, s), 6.25, u, stations=24, girth=6).r_wave  # noqa: E731
    np.testing.assert_allclose(np.asarray(jax.vmap(f)(scales)), [float(f(s)) for s in scales], rtol=1e-10)


@pytest.mark.slow
def test_wave_pattern_is_kelvins():
    """The far-field pattern of the Wigley at Fn 0.3: transverse waves on the centreline behind it at the
    wavelength 2πU²/g (within 2 %), calm ahead of the bow, and its waves inside the Kelvin wedge (19.47° from
    the bow): far outside it the elevation is < 15 % of inside."""
    from hullopt.resistance import wave_pattern

    h = wigley(100, 10, 6.25, 10, n=41, m=33)
    u = 0.3 * np.sqrt(G * 100.0)
    x = np.linspace(-400.0, 150.0, 1101)
    z = np.asarray(wave_pattern(h, 6.25, u, x, np.array([0.0]), stations=24, girth=6))[:, 0]
    behind = x < -100.0
    up = np.flatnonzero(np.diff(np.sign(z[behind])) > 0)  # up-crossings
    wavelength = np.mean(np.diff(x[behind][up]))
    assert wavelength == pytest.approx(2 * np.pi * u**2 / G, rel=0.02)
    assert np.all(z[x > 100.5] == 0.0)
    side = np.asarray(wave_pattern(h, 6.25, u, np.array([-100.0]), np.array([20.0, 150.0]), stations=24,
                                   girth=6))[0]
    assert abs(side[1]) < 0.15 * np.abs(z[behind]).max() and abs(side[0]) > 0.15 * np.abs(z[behind]).max()


def test_kelvin_spectrum_is_the_rectangles_integral():
    """The spectrum, computed in real arithmetic where it can be (the depth factor shared by both sides, the
    horizontal half-side's factor sin(y)/y), equals each panel rectangle's integral A·e^{a·c}·shc(a·h₁)·shc(a·h₂)
    summed over both sides in numpy's complex arithmetic; the second half-side is horizontal."""
    from hullopt.resistance._panel import _spectral_rectangles, hull_panels

    panels = hull_panels(wigley(100, 10, 6.25, 10, n=41, m=17), 6.25)
    sigma = jnp.asarray(np.random.default_rng(0).normal(size=panels.area.shape))
    k0, lam = 9.80665 / 8.0**2, jnp.linspace(1.0, 6.0, 40)
    got = np.asarray(kelvin_spectrum(panels, sigma, k0, lam))
    c, h1, h2 = (np.asarray(a) for a in _spectral_rectangles(panels))
    assert np.max(np.abs(h2[:, 2])) < 1e-12 * np.max(np.abs(h2))
    c = c - np.array([0.0, 0.0, 6.25])
    lam = np.asarray(lam)[:, None]
    q = np.asarray(sigma * panels.area * panels.real)

    def shc(z):
        return np.where(np.abs(z) < 1e-8, 1.0, np.sinh(z) / np.where(np.abs(z) < 1e-8, 1.0, z))

    want = 0.0
    for side in (1.0, -1.0):
        def dot(r):
            return k0 * lam**2 * r[:, 2] + 1j * k0 * lam * (r[:, 0] + side * np.sqrt(lam**2 - 1.0) * r[:, 1])

        want = want + (np.exp(dot(c)) * shc(dot(h1)) * shc(dot(h2))) @ q
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-12 * np.max(np.abs(want)))


def test_the_analyses_lambda_rule_against_a_fine_one():
    """``LAMBDA_PANELS`` (64, the default of objectives and rescoring) against 512 panels on the Wigley:
    measured 2.4e-5 at Fn 0.15, 7e-7 at Fn 0.2 (1.9e-4 at Fn 0.12)."""
    s = wigley(100.0, 10.0, 6.25, 10.0, n=101, m=33)
    u = jnp.asarray(np.array([0.15, 0.2]) * np.sqrt(G * 100.0))
    rule = jax.jit(lambda p: panel_wave_resistance(s, 6.25, u, lambda_panels=p).r_wave, static_argnums=0)
    err = np.abs(np.asarray(rule(LAMBDA_PANELS)) / np.asarray(rule(512)) - 1)
    assert np.all(err < [1e-4, 3e-6])
