"""Inflections of an offset table's lines (what fairing must not add) and the C² curvature surface of the
fairing plots: closed forms, scipy's tensor-product spline, gradients against central differences."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.interpolate import RectBivariateSpline

from conftest import REPO
from hullopt.app.commands.fair import _fields
from hullopt.fairing import (
    count_inflections,
    floors,
    hull_knots,
    inflection_counts,
    line_curvatures,
    mixed_curvature,
    sign_variation,
)
from hullopt.geometry import coons_surface, spline_curvatures
from hullopt.models import read_offsets

from helpers import check_grad


def test_spline_curvatures_of_a_cubic_are_exact():
    z = np.array([0.0, 0.5, 1.3, 2.0, 3.2, 4.0])
    y = 1 + 0.4 * z - 0.3 * z**2 + 0.05 * z**3  # not-a-knot reproduces a cubic
    d1, d2 = 0.4 - 0.6 * z + 0.15 * z**2, -0.6 + 0.3 * z
    np.testing.assert_allclose(spline_curvatures(jnp.asarray(z), jnp.asarray(y)), d2 / (1 + d1**2) ** 1.5,
                               rtol=1e-10, atol=1e-12)


def test_spline_twist_gives_scipys_c2_tensor_spline_through_the_same_lines():
    t = read_offsets(REPO / "hullopt/data/offsets/seed003_table1.csv")
    x, z, y = t.x, t.z, t.y
    c2, c1 = (coons_surface(jnp.asarray(x), jnp.asarray(z), jnp.asarray(y), twist=tw) for tw in ("spline", "zero"))
    ref = RectBivariateSpline(x, z, y, kx=3, ky=3, s=0)  # FITPACK's knots at s = 0: not-a-knot both ways
    rng = np.random.default_rng(0)
    xp, zp = rng.uniform(x[0], x[-1], 200), rng.uniform(z[0], z[-1], 200)
    for dx, dz in ((0, 0), (1, 0), (0, 1), (2, 0), (1, 1), (0, 2)):
        scale = float(np.abs(ref(xp, zp, dx, dz, grid=False)).max())
        np.testing.assert_allclose(c2(xp, zp, dx, dz), ref(xp, zp, dx, dz, grid=False), atol=1e-9 * scale)
    # the same frame lines and waterlines as the seed's zero-twist surface, but C² across patch edges
    zz, xx = np.linspace(z[0], z[-1], 41), np.linspace(x[0], x[-1], 61)
    np.testing.assert_allclose(c2(x[:, None], zz[None, :]), c1(x[:, None], zz[None, :]), atol=1e-12)
    np.testing.assert_allclose(c2(xx[:, None], z[None, :]), c1(xx[:, None], z[None, :]), atol=1e-12)
    u = jnp.array([0.3, 0.6])
    for s, c2_expected in ((c2, True), (c1, False)):
        jump = s.cells(u, jnp.array([0.0]), 0, 2)[:, 1:] - s.cells(u, jnp.array([1.0]), 0, 2)[:, :-1]
        assert (float(jnp.max(jnp.abs(jump))) < 1e-9) == c2_expected
    with pytest.raises(ValueError, match="twist"):
        coons_surface(jnp.asarray(x), jnp.asarray(z), jnp.asarray(y), twist="bent")


def test_curvature_maps_have_no_checkerboard_on_a_fair_hull():
    """The clean Wigley fore body: mean curvature varies smoothly on the plots' fine grid (the seed's
    zero-twist surface jumps at every patch edge: second differences 300× larger)."""
    ns, nw, L, B, T = 21, 9, 100.0, 10.0, 6.25
    x, z = np.linspace(0, L, ns), np.linspace(0, T, nw)
    y = (B / 2) * (1 - (2 * (x[:, None] - L / 2) / L) ** 2) * (1 - ((T - z[None, :]) / T) ** 2)
    xf, zf, yy, h, *_ = (np.asarray(a) for a in _fields(jnp.asarray(x), jnp.asarray(z), jnp.asarray(y)))
    fore = (xf[:, None] > 0.55 * L) & (yy > 0.05)
    inside = fore[1:-1] & fore[2:] & fore[:-2]
    d2 = np.abs(np.diff(h, 2, axis=0))[inside]
    assert d2.max() < 2e-3 * np.abs(h[fore]).max()


def line(values, z):
    """A frame-line curvature field ``(1, w)`` and its hull knots (every interior knot)."""
    k = jnp.asarray(values, dtype=jnp.float64)[None, :]
    m = np.ones(k.shape, bool)
    m[:, [0, -1]] = False
    return k, m, np.broadcast_to(np.gradient(z), k.shape)


@pytest.mark.parametrize(
    ("kappa", "count", "variation"),
    [
        ([0, -0.5, -0.3, -0.4, -0.2, 0], 0, 0.0),  # one-signed: a bilge turn
        ([0, -0.5, -0.3, 0.4, 0.2, 0], 1, 1.0),  # one clear S
        ([0, -0.5, 0.001, 0.003, 0.4, 0], 1, 1.0),  # the same S through knots in the dead band
        ([0, -0.5, 0.004, -0.4, 0.003, 0], 0, 1.5),  # straight in the band: no inflection, but the smooth
        # count adds ½ for each step into or out of the band (an upper bound that a constraint may use)
        ([0, -0.5, 0.4, -0.4, 0.4, 0], 3, 3.0),  # three
    ],
)
def test_counts_and_the_smooth_count_agree_on_clear_lines(kappa, count, variation):
    z = np.linspace(0.0, 5.0, len(kappa))
    k, m, w = line(kappa, z)
    floor = 0.01
    assert inflection_counts(np.asarray(k), m, 2 * floor, axis=1).tolist() == [count]
    assert float(sign_variation(k, m, floor, 1)[0]) == pytest.approx(variation, abs=0.1)
    assert (float(mixed_curvature(k, m, w, floor, 1)[0]) > 0) == (count > 0)


def test_smooth_counts_have_finite_gradients_matching_differences():
    z = np.linspace(0.0, 5.0, 7)
    k0, m, w = line([0, -0.5, -0.02, 0.07, 0.2, -0.09, 0], z)  # off the kinks at ±floor, ±2 floor
    for f in (lambda k: sign_variation(k[None, :], m, 0.05, 1)[0],
              lambda k: mixed_curvature(k[None, :], m, w, 0.05, 1)[0]):
        check_grad(f, np.asarray(k0[0]), rtol=1e-5, atol=1e-8)
        flat = jax.grad(f)(jnp.zeros(7))  # all inside the dead band: 0/0 avoided, no NaN
        assert np.all(np.isfinite(flat))


def test_table_inflections_of_the_wigley_and_of_a_bulge():
    """The Wigley's sections and waterlines are parabolas: no inflection. A local bulge on a section's
    straight part is at least two new ones; the judge sees them, on the given table's knots and dead bands."""
    L, B, T = 100.0, 10.0, 6.25
    x, z = np.linspace(0, L, 15), np.linspace(0, T, 9)
    y = (B / 2) * (1 - (2 * (x[:, None] - L / 2) / L) ** 2) * (1 - ((T - z[None, :]) / T) ** 2)
    frames, waterlines = count_inflections(x, z, y)
    assert not frames.any() and not waterlines.any()
    knots = hull_knots(y)
    assert knots[0][:, [0, -1]].sum() == 0 and knots[0][7, 2:-1].all()
    assert not knots[0][7, 1]  # its neighbour is the keel's zero half-breadth: the section begins there
    kf, kw = floors(*line_curvatures(x, z, y), *knots)
    assert kf > 0 and kw > 0 and kf > 10 * kw  # sections curve far more than waterlines
    bent = y.copy()
    bent[7, 4] += 0.1
    frames, _ = count_inflections(x, z, bent, y)
    assert frames[7] >= 2 and frames.sum() == frames[7]  # the spline rings either side of the bump
