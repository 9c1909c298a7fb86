"""Waterline and bluntness Bf(α): closed forms (wedge, semicircle), the patent's integral by quadrature,
symmetry, scaling, the aft option and gradients."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import check_grad
from scipy.integrate import quad

from hullopt.geometry import Sections
from hullopt.models import wigley
from hullopt.waves import bluntness, entrance_lengths, waterline

BF = jax.jit(bluntness, static_argnames="aft")
D = 10.0


def wall_sided(x, y, lpp=None):
    """Wall-sided hull with waterline half-breadths ``y`` at stations ``x`` (sections keel–bilge–deck)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    yz = np.stack([np.stack([np.zeros_like(y), np.zeros_like(y)], -1), np.stack([y, np.zeros_like(y)], -1),
                   np.stack([y, np.full_like(y, D)], -1)], axis=1)
    return Sections(x=jnp.asarray(x), yz=jnp.asarray(yz), lpp=jnp.asarray(float(lpp or x[-1])))


def wedge_hull(half_angle, b=10.0, n_wedge=5, beyond=True):
    """Transom stern, parallel body to x = 50, a straight wedge bow to the stem, a dry station beyond."""
    xs = 50.0 + b / np.tan(half_angle)
    x = np.concatenate([[0.0, 25.0], np.linspace(50.0, xs, n_wedge), [xs + 5.0] if beyond else []])
    y = np.concatenate([[b, b], np.linspace(b, 0.0, n_wedge), [0.0] if beyond else []])
    return wall_sided(x, y, lpp=xs)


def semicircle_hull(n, r=10.0):
    """Parallel body and a semicircular entrance of radius r, vertices equally spaced in angle."""
    phi = np.linspace(0.0, np.pi / 2, n + 1)
    x = np.concatenate([[0.0], 60.0 + r * np.sin(phi)])
    y = np.concatenate([[r], r * np.cos(phi)])
    return wall_sided(x, y)


@pytest.mark.parametrize("deg", [5.0, 20.0, 45.0, 70.0])
def test_wedge_is_sin2_of_half_angle(deg):
    e = np.radians(deg)
    np.testing.assert_allclose(BF(wedge_hull(e), 5.0), np.sin(e) ** 2, rtol=1e-13)
    # the entrance ends exactly at the last station (no dry station beyond): same value
    np.testing.assert_allclose(BF(wedge_hull(e, beyond=False), 5.0), np.sin(e) ** 2, rtol=1e-13)


def test_box_bow_face_is_one():
    s = wall_sided([0.0, 100.0], [5.0, 5.0])
    np.testing.assert_allclose(BF(s, 5.0), 1.0, rtol=1e-14)


def test_semicircle_converges_to_two_thirds():
    errs = np.array([abs(float(BF(semicircle_hull(n), 5.0)) - 2.0 / 3.0) for n in (8, 16, 32, 64)])
    assert errs[-1] < 2e-4
    np.testing.assert_allclose(errs[:-1] / errs[1:], 4.0, rtol=0.05)  # second order in the angle step


def test_independent_of_breadth_scaling():
    # a semicircle of any radius: 2/3 in the limit, and the same polygon value for the same angles
    vals = [float(BF(semicircle_hull(32, r), 5.0)) for r in (5.0, 10.0, 20.0)]
    np.testing.assert_allclose(vals, vals[0], rtol=1e-13)
    # geometric similarity (x, y and z scaled alike) leaves Bf unchanged at every heading
    s = wigley(100.0, 12.0, 6.0, 9.0, n=41, m=5)
    big = Sections(x=3.0 * s.x, yz=3.0 * s.yz, lpp=3.0 * s.lpp)
    a = jnp.linspace(-np.pi, np.pi, 13)
    np.testing.assert_allclose(BF(big, 18.0, a), BF(s, 6.0, a), rtol=1e-12, atol=1e-15)
    # scaling the breadth alone changes the entrance angle as it must: wedge tan E → c tan E
    e = np.radians(10.0)
    np.testing.assert_allclose(BF(wedge_hull(np.arctan(2 * np.tan(e))), 5.0), np.sin(np.arctan(2 * np.tan(e))) ** 2)


def _patent_bf_wigley(length, beam, alpha, entrance_only=False):
    """Patent eq. 3 on the smooth Wigley waterline y = (B/2)(1 − (2ξ/L)²) by adaptive quadrature; with
    ``entrance_only`` over the lit entrance (x > L/2, β > 0) only."""

    def slope(x):
        return -(beam / 2) * 8 * (x - length / 2) / length**2

    def integrand(x, side):
        yp = slope(x)
        beta = np.arctan(-yp)  # waterline angle, positive in the entrance
        ang = alpha + beta if side == "I" else alpha - beta
        lit = np.sin(ang) > 0 if side == "I" else np.sin(beta - alpha) > 0
        lit = lit and (beta > 0 or not entrance_only)
        return np.sin(ang) ** 2 * np.sin(beta) * np.sqrt(1 + yp**2) * lit

    # split where the integrand has kinks: midship and the lit/shadow switches β = ∓α
    c = length**2 / (4 * beam)
    cuts = [length / 2 + c * np.tan(b) for b in (-alpha, alpha) if abs(b) < np.pi / 2]
    edges = sorted({0.0, length / 2, length, *[x for x in cuts if 0.0 < x < length]})
    tot = sum(quad(integrand, a, b, args=(side,), limit=200, epsabs=1e-14)[0]
              for side in ("I", "II") for a, b in zip(edges[:-1], edges[1:]))
    return tot / beam


@pytest.mark.parametrize("deg", [0.0, 3.0, 10.0, 30.0, 60.0, 90.0, 135.0])
def test_wigley_matches_patent_integral(deg):
    s = wigley(100.0, 10.0, 6.25, 10.0, n=401, m=3)
    a = np.radians(deg)
    for aft, entrance_only in (("include", False), ("exclude", True)):
        got = np.asarray(BF(s, 6.25, jnp.array([a, -a]), aft=aft))
        ref = _patent_bf_wigley(100.0, 10.0, a, entrance_only)
        np.testing.assert_allclose(got, ref, rtol=2e-4, atol=2e-6)  # polyline with 400 segments: O(h²)
        np.testing.assert_allclose(got[0], got[1], rtol=1e-14)  # ±α on a symmetric hull


@pytest.mark.slow
def test_head_seas_closed_form_and_aft_option():
    s = wigley(100.0, 10.0, 6.25, 10.0, n=201, m=3)
    # head seas: (2/B) ∫ |y'|³/(1 + y'²) dξ over the entrance
    ref = 2 / 10.0 * quad(lambda x: (0.004 * x) ** 3 / (1 + (0.004 * x) ** 2), 0, 50)[0]
    np.testing.assert_allclose(BF(s, 6.25, 0.0), ref, rtol=2e-4)
    np.testing.assert_allclose(BF(s, 6.25, 0.0, aft="exclude"), BF(s, 6.25, 0.0, aft="include"), rtol=1e-14)
    # beam seas: the lit aft body of the weather side counts against the bow when included;
    # fore-aft symmetric Wigley: the two cancel exactly, excluding (the default) leaves the entrance part
    a = np.radians(90.0)
    np.testing.assert_allclose(BF(s, 6.25, a, aft="include"), 0.0, atol=1e-14)
    assert float(BF(s, 6.25, a)) > 0.05
    np.testing.assert_allclose(BF(s, 6.25, a), BF(s, 6.25, a, aft="exclude"), rtol=0)
    # following seas: included, the run mirrors head seas on a fore-aft symmetric hull; by default no
    # part of the entrance is lit
    np.testing.assert_allclose(BF(s, 6.25, np.pi, aft="include"), -BF(s, 6.25, 0.0), rtol=1e-12)
    assert float(BF(s, 6.25, np.pi)) == 0.0
    with pytest.raises(ValueError, match="aft"):
        bluntness(s, 6.25, 0.0, aft="both")


def test_waterline_is_exact_at_the_draft():
    s = wigley(100.0, 10.0, 6.25, 10.0, n=21, m=41)
    t = 4.0
    wl = waterline(s, t)
    xi = 2 * (np.asarray(s.x) - 50) / 100
    zeta = (6.25 - t) / 6.25
    expect = 5 * (1 - xi**2)
    # the polyline section's crossing of z = t (41 points per section: within the chord error)
    np.testing.assert_allclose(wl.y, expect * (1 - zeta**2), rtol=2e-3)
    np.testing.assert_allclose(wl.slope, np.diff(wl.y) / np.diff(np.asarray(s.x)), rtol=1e-12)
    np.testing.assert_allclose(wl.beam, 2 * np.max(wl.y))
    np.testing.assert_allclose(np.sum(wl.dy), 0.0, atol=1e-12)  # closed polyline


def test_entrance_lengths_on_wedge():
    e = np.radians(20.0)
    wl = waterline(wedge_hull(e), 5.0)
    l95, _ = entrance_lengths(wl, 0.95)
    np.testing.assert_allclose(l95, 0.95 * 10.0 / np.tan(e), rtol=1e-12)
    l99, run = entrance_lengths(wl, 0.99)
    np.testing.assert_allclose(l99, 0.99 * 10.0 / np.tan(e), rtol=1e-12)
    np.testing.assert_allclose(run, 0.0, atol=1e-12)  # transom stern


@pytest.mark.slow
def test_gradients_match_finite_differences():
    s = wigley(100.0, 10.0, 6.25, 10.0, n=41, m=9)
    f_t = jax.jit(lambda t: bluntness(s, t, 0.2))
    check_grad(f_t, 5.3, rtol=1e-6)
    f_g = jax.jit(lambda c: bluntness(Sections(x=s.x, yz=s.yz * jnp.array([c, 1.0]), lpp=s.lpp), 5.0, 0.3))
    check_grad(f_g, 1.2, rtol=1e-6)
    # per-vertex gradients are finite everywhere
    g = jax.jit(jax.grad(lambda yz: bluntness(Sections(x=s.x, yz=yz, lpp=s.lpp), 5.0, 0.2)))(s.yz)
    assert np.all(np.isfinite(g))
    # at the stem of the wedge, where a station is exactly dry and segments have zero length
    w = wedge_hull(np.radians(30.0))
    g = jax.jit(jax.grad(lambda yz: bluntness(Sections(x=w.x, yz=yz, lpp=w.lpp), 5.0, 0.0)))(w.yz)
    assert np.all(np.isfinite(g))
