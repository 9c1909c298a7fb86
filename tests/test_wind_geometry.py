"""Wind variables from geometry: closed forms, unions, gradients against finite differences, checks, data."""


import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import check_grad

from hullopt.errors import HullError
from hullopt.models import box, wigley
from hullopt.wind import (box_parts, check_parts, no_parts, polygon_moments, polygon_parts, wind_coefficients,
                          wind_variables)

wv = eqx.filter_jit(wind_variables)
L, B, D, T = 200.0, 32.0, 20.0, 12.0


@pytest.fixture(scope="module")
def barge():
    return box(L, B, D, n=5)


def parts_for(height):
    """Deckhouse aft (superstructure), one container block (cargo) and a mast, on a deck at z = D."""
    return box_parts(["bridge", "stack", "mast"], ["superstructure", "cargo", "mast"],
                     [20.0, 60.0, 180.0], [35.0, 150.0, 181.0], D, [D + height, D + 12.0, D + 20.0],
                     [24.0, 30.0, 1.0])


def test_polygon_moments_closed_forms():
    # Rectangle [a, b] × [c, d]: M[p, q] = (b^(p+1) − a^(p+1))/(p+1) · (d^(q+1) − c^(q+1))/(q+1).
    a, b, c, d = -3.0, 5.0, 1.0, 4.0
    rect = jnp.array([[a, c], [b, c], [b, d], [a, d]])
    m = np.asarray(polygon_moments(rect))
    for p in range(4):
        for q in range(4 - p):
            want = (b ** (p + 1) - a ** (p + 1)) / (p + 1) * (d ** (q + 1) - c ** (q + 1)) / (q + 1)
            assert m[p, q] == pytest.approx(want, rel=1e-13)
    assert np.all(m[np.add.outer(range(4), range(4)) > 3] == 0)
    # Right triangle (0,0), (w,0), (0,h): area wh/2, centroid (w/3, h/3), ∬x² = w³h/12, ∬x y = w²h²/24,
    # ∬x³ = w⁴h/20; and the clockwise polygon gives the negatives.
    w, h = 6.0, 9.0
    tri = jnp.array([[0.0, 0.0], [w, 0.0], [0.0, h]])
    m = np.asarray(polygon_moments(tri))
    assert m[0, 0] == pytest.approx(w * h / 2)
    assert m[1, 0] / m[0, 0] == pytest.approx(w / 3) and m[0, 1] / m[0, 0] == pytest.approx(h / 3)
    assert m[2, 0] == pytest.approx(w**3 * h / 12) and m[1, 1] == pytest.approx(w**2 * h**2 / 24)
    assert m[3, 0] == pytest.approx(w**4 * h / 20) and m[0, 3] == pytest.approx(w * h**4 / 20)
    np.testing.assert_allclose(polygon_moments(tri[::-1]), -m, rtol=1e-13)


def test_barge_with_parts_by_hand(barge):
    v = wv(barge, jnp.asarray(T), parts_for(25.0))
    f = D - T  # freeboard 8
    # Side: hull 200×8 = 1600, bridge 15×25 = 375, stack 90×12 = 1080, mast 1×20 = 20.
    assert float(v.A_L) == pytest.approx(1600 + 375 + 1080 + 20, rel=1e-12)
    assert float(v.A_OD) == pytest.approx(375 + 1080 + 20, rel=1e-12)
    assert float(v.A_SS) == pytest.approx(375, rel=1e-12)
    assert float(v.L) == L and float(v.B) == B and float(v.H_BR) == pytest.approx(f + 25)
    xc = (1600 * 100 + 375 * 27.5 + 1080 * 105 + 20 * 180.5) / 3075
    hc = (1600 * 4 + 375 * (f + 12.5) + 1080 * (f + 6) + 20 * (f + 10)) / 3075
    assert float(v.C) == pytest.approx(xc - 100, rel=1e-12) and float(v.H_C) == pytest.approx(hc, rel=1e-12)
    assert float(v.C_BR) == pytest.approx(27.5 - 100) and float(v.C_bow) == pytest.approx(100 - (xc - 100))
    # Front: hull 32×8; then up to 12 m above deck the stack (30 wide) hides the bridge (24): union
    # 30×12, then the bridge alone 24×13. The mast (1 wide) is inside both.
    assert float(v.A_T) == pytest.approx(32 * 8 + 30 * 12 + 24 * 13, rel=1e-12)
    # Outline without waterline and mast: stern 8 + deck 20 + 25 up + 15 + 25 down + 25 + 12 up + 90 + 12 down
    # + 50 + bow 8.
    assert float(v.S) == pytest.approx(8 + 20 + 25 + 15 + 25 + 25 + 12 + 90 + 12 + 50 + 8, rel=1e-12)
    assert float(v.M) == 1.0
    assert v.part_names == ("hull", "bridge", "stack", "mast")
    np.testing.assert_allclose(v.part_area, [1600, 375, 1080, 20], rtol=1e-12)
    np.testing.assert_allclose(v.part_front_area, [32 * 8, 24 * 25, 30 * 12, 20], rtol=1e-12)
    np.testing.assert_allclose(v.part_perimeter, [416, 80, 204, 42], rtol=1e-12)


def test_overlaps_counted_once(barge):
    # Two boxes overlapping by 10 m in x (and the second also sitting 2 m into the hull): union areas.
    parts = box_parts(["a", "b"], ["cargo", "cargo"], [50.0, 70.0], [80.0, 120.0], [D, D - 2.0], [D + 10, D + 6],
                      [20.0, 20.0])
    v = wv(barge, jnp.asarray(T), parts)
    a_od = 30 * 10 + 50 * 8 - 10 * 6  # − the a∩b rectangle, b's 2 m inside the hull counts in A_OD
    assert float(v.A_OD) == pytest.approx(a_od, rel=1e-12)
    assert float(v.A_L) == pytest.approx(200 * 8 + 30 * 10 + 50 * 6 - 10 * 6, rel=1e-12)


def test_wigley_wall_sides_and_polygon_parts():
    # Above T the Wigley hull has vertical sides: profile L×(D−T), front B×(D−T), centroid at half height.
    hull = wigley(100.0, 10.0, 6.25, 10.0, n=21, m=11)
    v = wv(hull, jnp.asarray(6.25), no_parts())
    assert float(v.A_L) == pytest.approx(375.0, rel=1e-12) and float(v.A_T) == pytest.approx(37.5, rel=1e-9)
    assert float(v.H_C) == pytest.approx(1.875) and float(v.H_T) == pytest.approx(1.875, rel=1e-9)
    assert float(v.C) == pytest.approx(0.0, abs=1e-9) and float(v.B) == pytest.approx(10.0)
    # A triangular funnel (base 8, height 12) given clockwise: the same area and centroid as counter-clockwise.
    tri = polygon_parts(["funnel"], ["superstructure"], [[(30, 10), (34, 22), (38, 10)]],
                        [[(-2, 10), (2, 10), (2, 22), (-2, 22)]])
    v = wv(hull, jnp.asarray(6.25), tri)
    assert float(v.A_SS) == pytest.approx(48.0, rel=1e-12)
    assert float(v.part_h[1]) == pytest.approx(3.75 + 4.0) and float(v.C_BR) == pytest.approx(34.0 - 50.0)
    with pytest.raises(HullError, match="convex"):
        polygon_parts(["x"], ["cargo"], [[(0, 0), (4, 0), (2, 1), (4, 4), (0, 4)]], [[(0, 0), (1, 0), (1, 1)]])


@pytest.mark.slow
def test_gradients_draft_and_size():
    # Curved below 7 m: the front depends on the draft. (Drafts on a section vertex, 0.7 m apart, are kinks.)
    hull = wigley(120.0, 16.0, 7.0, 12.0, n=21, m=11)
    names = ["A_L", "H_C", "C", "A_T", "S", "C_BR"]

    @jax.jit
    def f(p):  # p = (draft, bridge height, bridge breadth) → the variables and C_X(0)·A_T
        parts = box_parts(["bridge", "stack"], ["superstructure", "cargo"], [10.0, 50.0], [25.0, 95.0], 12.0,
                          [12.0 + p[1], 20.0], [p[2], 14.0])
        v = wind_variables(hull, p[0], parts)
        return jnp.stack([*(getattr(v, n) for n in names), wind_coefficients(v, 0.0, "fujiwara1998").cx * v.A_T])

    p0 = np.array([6.45, 17.0, 12.0])
    ad = np.asarray(jax.jacfwd(f)(jnp.asarray(p0)))
    step = 1e-6 * np.abs(p0)
    fd = np.stack([(np.asarray(f(jnp.asarray(p0 + e))) - np.asarray(f(jnp.asarray(p0 - e)))) / (2 * e[i])
                   for i, e in enumerate(np.diag(step))], axis=1)
    assert np.all(np.isfinite(ad))
    np.testing.assert_allclose(ad, fd, rtol=1e-6, atol=1e-7 * np.abs(fd).max())
    assert ad[names.index("A_L"), 0] == pytest.approx(-120.0, rel=1e-9)  # wall sides above T: −L
    assert ad[-1, 1] < 0  # a taller bridge adds head-wind drag: C_X·A_T more negative


def test_sheer_profile_is_piecewise_linear():
    # A box with a deck rising linearly from 10 m aft to 14 m forward: profile above T = 6 is a trapezoid.
    x = jnp.linspace(0.0, 50.0, 6)
    deck = 10.0 + 4.0 * x / 50.0
    yz = jnp.stack([jnp.stack([jnp.zeros(6), jnp.zeros(6)], -1), jnp.stack([jnp.full(6, 4.0), jnp.zeros(6)], -1),
                    jnp.stack([jnp.full(6, 4.0), deck], -1)], axis=1)
    from hullopt.geometry import Sections

    v = wv(Sections(x=x, yz=yz, lpp=jnp.asarray(50.0)), jnp.asarray(6.0), no_parts())
    assert float(v.A_L) == pytest.approx(50 * 6.0, rel=1e-12)  # mean freeboard 6
    assert float(v.C) == pytest.approx(50 * (4 + 2 * 8) / (3 * (4 + 8)) - 25.0, rel=1e-12)  # trapezoid centroid
    assert float(v.S) == pytest.approx(4 + 8 + np.hypot(50, 4), rel=1e-12)


def test_parts_outside_the_ship(barge):
    ok = parts_for(25.0)
    check_parts(barge, T, ok)
    for parts, msg in [
        (box_parts(["crane"], ["cargo"], 190.0, 230.0, D, D + 5, 4.0), "outside the ship"),
        (box_parts(["tank"], ["cargo"], 50.0, 60.0, T - 3, D + 5, 4.0), "below the waterline"),
        (box_parts(["wing"], ["superstructure"], 50.0, 60.0, D, D + 5, 40.0), "outside the ship"),
    ]:
        with pytest.raises(HullError, match=msg):
            check_parts(barge, T, parts)
    with pytest.raises(HullError, match="unknown kind"):
        box_parts(["x"], ["bridge"], 0.0, 1.0, 0.0, 1.0, 1.0)
