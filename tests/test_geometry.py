"""The geometry kernel against independent computations: shapely polygons, scipy quadrature and splines."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.integrate
import scipy.interpolate
import shapely.geometry as sg
from helpers import check_grad

from hullopt.geometry import (
    Sections,
    natural_cubic_spline,
    polygon_integrals,
    section_integrals,
    simpson_weights,
    spline_matrix,
    to_trimesh,
    wetted_surface,
)


def _random_section(rng, m=12):
    """A half-section with a bulb-like lobe: keel on the centreline, wiggly outline, deck edge on top."""
    z = np.sort(rng.uniform(0, 10, m))
    z[0] = 0.0
    y = rng.uniform(0.5, 5, m)
    y[0] = 0.0
    return np.stack([y, z], 1)


@pytest.mark.parametrize("seed", range(5))
def test_clipped_area_and_moments_match_shapely(seed):
    rng = np.random.default_rng(seed)
    yz = _random_section(rng)
    level = rng.uniform(1, 9)
    closed = np.concatenate([yz, [[0.0, yz[-1, 1]]]])
    poly = sg.Polygon(closed).buffer(0)  # the outline may self-intersect: shapely's area is unsigned
    if not sg.Polygon(closed).is_valid:
        pytest.skip("random outline self-intersects")
    below = poly.intersection(sg.box(-1, -1, 100, level))
    res = polygon_integrals(jnp.asarray(closed), level)
    assert float(res.area) == pytest.approx(below.area, rel=1e-12)
    assert float(res.moment_z) / float(res.area) == pytest.approx(below.centroid.y, rel=1e-12)
    assert float(res.moment_y) / float(res.area) == pytest.approx(below.centroid.x, rel=1e-12)
    width = poly.intersection(sg.LineString([(-1, level), (100, level)])).length
    assert float(res.width) == pytest.approx(width, rel=1e-12)


def test_multi_part_section_bulb_and_hull():
    """A bulb below the hull, joined along the centreline: integrals add, the joint contributes nothing."""
    bulb = [[0, 0], [2, 0.5], [2, 2.5], [0, 3]]
    hull = [[0, 4], [3, 4], [5, 6], [5, 10]]
    yz = jnp.asarray(np.array(bulb + hull, float))
    closed = jnp.concatenate([yz, jnp.array([[0.0, 10.0]])])
    shp_bulb = sg.Polygon(bulb)
    shp_hull = sg.Polygon(hull + [[0, 10]])
    for level in (2.0, 3.5, 7.0):
        r = polygon_integrals(closed, level)
        box = sg.box(-1, -1, 100, level)
        expect = shp_bulb.intersection(box).area + shp_hull.intersection(box).area
        assert float(r.area) == pytest.approx(expect, rel=1e-12)
    assert float(polygon_integrals(closed, 2.0).width) == pytest.approx(2.0)
    assert float(polygon_integrals(closed, 3.5).width) == pytest.approx(0.0, abs=1e-15)


def test_width_is_derivative_of_area_including_at_vertices():
    yz = jnp.array([[0.0, 0.0], [2.0, 0.0], [3.0, 1.0], [3.5, 2.0], [3.5, 4.0]])
    closed = jnp.concatenate([yz, jnp.array([[0.0, 4.0]])])
    d_area = jax.jit(jax.grad(lambda t: polygon_integrals(closed, t).area))
    for level in (0.5, 1.0, 1.7, 2.0, 3.0):  # 1.0 and 2.0 are vertices
        dA = d_area(level)
        assert float(dA) == pytest.approx(float(polygon_integrals(closed, level).width), rel=1e-12)


def test_section_integrals_gradient_in_vertices():
    rng = np.random.default_rng(3)
    yz0 = _random_section(rng, 8)
    x = jnp.array([0.0, 1.0])

    def f(flat):
        yz = flat.reshape(1, 8, 2)
        s = Sections(x=x[:1], yz=yz, lpp=jnp.asarray(1.0))
        r = section_integrals(s, 5.0)
        return r.area[0] + 0.3 * r.moment_z[0] + 0.1 * r.moment_y[0] + r.width[0]

    check_grad(jax.jit(f), yz0.ravel())


@pytest.mark.parametrize("n", [2, 3, 4, 7, 10])
def test_simpson_weights_exact_for_quadratics_on_uneven_stations(n):
    rng = np.random.default_rng(n)
    x = np.sort(rng.uniform(0, 10, n))
    x += np.arange(n) * 0.5  # keep spacing ratios moderate
    w = np.asarray(simpson_weights(jnp.asarray(x)))
    f = lambda t: 1.0 + 2.0 * t - 0.3 * t**2  # noqa: E731
    exact = (lambda t: t + t**2 - 0.1 * t**3)(x[-1]) - (lambda t: t + t**2 - 0.1 * t**3)(x[0])
    if n == 2:
        assert w @ f(x) == pytest.approx(scipy.integrate.trapezoid(f(x), x), rel=1e-14)
    else:
        assert w @ f(x) == pytest.approx(exact, rel=1e-12)
        assert w @ np.sin(x) == pytest.approx(scipy.integrate.simpson(np.sin(x), x=x), rel=1e-10)


def test_natural_spline_matches_scipy_and_matrix_form():
    knots = np.array([0.0, 0.7, 1.5, 3.0, 3.2, 5.0])
    values = np.array([[0.0, 1.0], [1.0, 0.5], [0.5, 2.0], [2.0, 0.1], [1.9, 0.0], [0.3, 3.0]])
    at = np.linspace(-0.0, 5.0, 37)
    ref = scipy.interpolate.CubicSpline(knots, values, bc_type="natural")
    s = natural_cubic_spline(jnp.asarray(knots), jnp.asarray(values))
    np.testing.assert_allclose(s(jnp.asarray(at)), ref(at), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(s(jnp.asarray(at), 1), ref(at, 1), rtol=1e-10, atol=1e-10)
    np.testing.assert_allclose(s(jnp.asarray(at), 2), ref(at, 2), rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(spline_matrix(knots, at) @ values, ref(at), rtol=1e-12, atol=1e-12)


def test_wetted_surface_of_a_box_and_a_tilted_plate():
    L, B, D = 10.0, 4.0, 3.0
    yz = jnp.broadcast_to(jnp.array([[0.0, 0.0], [B / 2, 0.0], [B / 2, D]]), (3, 3, 2))
    box = Sections(x=jnp.array([0.0, 5.0, 10.0]), yz=yz, lpp=jnp.asarray(L))
    ws = jax.jit(wetted_surface)
    for t in (0.5, 1.7, 3.0):
        assert float(ws(box, t)) == pytest.approx(L * (B + 2 * t), rel=1e-13)
    # a V section: sides at 45°, wetted girth √2·T each side
    vee = Sections(x=jnp.array([0.0, 10.0]), yz=jnp.broadcast_to(jnp.array([[0.0, 0.0], [3.0, 3.0]]), (2, 2, 2)),
                   lpp=jnp.asarray(10.0))
    assert float(wetted_surface(vee, 2.0)) == pytest.approx(2 * 10 * 2 * np.sqrt(2), rel=1e-13)
    g = jax.grad(lambda t: wetted_surface(vee, t))(2.0)
    assert float(g) == pytest.approx(2 * 10 * np.sqrt(2), rel=1e-10)


def test_closed_mesh_is_watertight_with_bulb_joint_and_zero_width_stations():
    # station 0 has not started below z = 2 (centreline run), station 1 has a bulb joined to the hull
    s0 = [[0, 0], [0, 1], [0, 2], [1, 2.5], [2, 3], [3, 4], [3, 6]]
    s1 = [[0, 0], [1, 0.5], [1, 1.5], [0, 2], [0, 2.5], [2, 3], [3, 6]]
    s2 = [[0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 0], [0, 6]]
    sec = Sections(x=jnp.array([0.0, 4.0, 8.0]), yz=jnp.asarray(np.array([s0, s1, s2], float)), lpp=jnp.asarray(8.0))
    mesh = to_trimesh(sec)
    assert mesh.is_watertight and mesh.is_winding_consistent
    assert mesh.volume > 0


def test_level_widths_equal_the_polygon_integrals_width_at_each_level():
    """The many-level width (wind front view) against the kernel's single-level crossing rule, on random
    closed polygons with vertices exactly on some of the levels (counted half, never lost or doubled)."""
    from hullopt.geometry import level_widths, polygon_integrals

    rng = np.random.default_rng(3)
    levels = jnp.linspace(0.0, 4.0, 9)
    z = rng.choice(np.asarray(levels), size=(5, 12))  # many vertices on a level
    z[:, ::3] += rng.uniform(-0.3, 0.3, (5, 4))
    poly = jnp.asarray(np.stack([rng.uniform(0.0, 3.0, (5, 12)), z], -1))
    one_by_one = jax.vmap(lambda lv: polygon_integrals(poly, lv).width, out_axes=-1)(levels)
    np.testing.assert_allclose(level_widths(poly, levels), one_by_one, rtol=1e-12, atol=1e-12)
    g_many = jax.grad(lambda p: jnp.sum(level_widths(p, levels) ** 2))(poly)
    g_one = jax.grad(lambda p: jnp.sum(jax.vmap(lambda lv: polygon_integrals(p, lv).width)(levels) ** 2))(poly)
    np.testing.assert_allclose(g_many, g_one, rtol=1e-10, atol=1e-12)


def test_atomic_writes_get_ordinary_permissions(tmp_path):
    import os

    from hullopt.geometry import atomic_write_bytes

    atomic_write_bytes(tmp_path / "a.bin", b"x")
    (tmp_path / "b.bin").write_bytes(b"x")
    assert (tmp_path / "a.bin").read_bytes() == b"x"
    assert os.stat(tmp_path / "a.bin").st_mode & 0o777 == os.stat(tmp_path / "b.bin").st_mode & 0o777
    assert not [p for p in tmp_path.iterdir() if p.suffix == ".tmp"]
