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
    longitudinal_integrals,
    natural_cubic_spline,
    polygon_integrals,
    safe_div,
    safe_norm,
    safe_sqrt,
    section_integrals,
    simpson_weights,
    spline_matrix,
    to_trimesh,
    volume_lcb,
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


@pytest.mark.parametrize("k", [2, 3, 4, 41])
def test_spline_matrix_is_scipys_natural_spline_inside_and_beyond_the_knots(k):
    """The numpy matrix form against scipy's natural spline of each unit vector, the end cubics continued."""
    knots = np.cumsum(np.random.default_rng(k).uniform(0.2, 2.0, k))
    at = np.linspace(knots[0] - 1.0, knots[-1] + 1.0, 97)
    ref = scipy.interpolate.CubicSpline(knots, np.eye(k), bc_type="natural")(at)
    np.testing.assert_allclose(spline_matrix(knots, at), ref, rtol=0, atol=1e-11 * max(1.0, np.abs(ref).max()))


@pytest.mark.slow
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

    def cut_area(x):  # area of trimesh's capped cut of the triangulated mesh at x (exact: its faces are planar)
        part = mesh.slice_plane([x, 0.0, 0.0], [-1.0, 0.0, 0.0], cap=True)
        on = np.all(np.abs(part.triangles[:, :, 0] - x) < 1e-9, axis=1)
        return float(part.area_faces[on].sum())

    # Station areas by hand (both sides; the bulb of station 1 is 1.5 m² a side): 19, 19, 0 m²; the triangles
    # move linearly between stations, so each interval's volume is the prismoidal formula with the mid cut.
    assert cut_area(4.0) == pytest.approx(19.0, abs=1e-5)
    prismoidal = 4.0 / 6.0 * (19.0 + 4.0 * cut_area(2.0) + 19.0) + 4.0 / 6.0 * (19.0 + 4.0 * cut_area(6.0) + 0.0)
    assert mesh.volume == pytest.approx(prismoidal, rel=1e-6)  # measured 1.5e-7 (the mesh's 1e-7 m wall)


def test_level_widths_equal_the_polygon_integrals_width_at_each_level():
    """The many-level width (wind front view) against the kernel's single-level crossing rule, on random
    closed polygons with vertices exactly on some of the levels (counted half, never lost or doubled)."""
    from hullopt.geometry import level_widths, polygon_integrals

    rng = np.random.default_rng(3)
    levels = jnp.linspace(0.0, 4.0, 9)
    z = rng.choice(np.asarray(levels), size=(5, 12))  # many vertices on a level
    z[:, ::3] += rng.uniform(-0.3, 0.3, (5, 4))
    poly = jnp.asarray(np.stack([rng.uniform(0.0, 3.0, (5, 12)), z], -1))
    # each side compiled once (jit): the same functions as op by op, ~3x faster to run here
    one_by_one = jax.jit(jax.vmap(lambda lv: polygon_integrals(poly, lv).width, out_axes=-1))(levels)
    np.testing.assert_allclose(jax.jit(level_widths)(poly, levels), one_by_one, rtol=1e-12, atol=1e-12)
    g_many = jax.jit(jax.grad(lambda p: jnp.sum(level_widths(p, levels) ** 2)))(poly)
    g_one = jax.jit(jax.grad(lambda p: jnp.sum(jax.vmap(lambda lv: polygon_integrals(p, lv).width)(levels) ** 2)))(
        poly)
    np.testing.assert_allclose(g_many, g_one, rtol=1e-10, atol=1e-12)


def test_atomic_writes_get_ordinary_permissions(tmp_path):
    import os

    from hullopt.geometry import atomic_write_bytes

    atomic_write_bytes(tmp_path / "a.bin", b"x")
    (tmp_path / "b.bin").write_bytes(b"x")
    assert (tmp_path / "a.bin").read_bytes() == b"x"
    assert os.stat(tmp_path / "a.bin").st_mode & 0o777 == os.stat(tmp_path / "b.bin").st_mode & 0o777
    assert not [p for p in tmp_path.iterdir() if p.suffix == ".tmp"]


def _box(L=100.0, B=20.0, D=10.0, n=11):
    yz = np.array([[0.0, 0.0], [B / 2, 0.0], [B / 2, D]])
    return Sections(x=jnp.linspace(0.0, L, n), yz=jnp.asarray(np.broadcast_to(yz, (n, 3, 2))), lpp=jnp.asarray(L))


# one compile of the integrals for the box tests below (op-by-op dispatch of the kernel took ~10 s a call)
_integrals = jax.jit(longitudinal_integrals)


def test_longitudinal_integrals_of_a_box_are_exact():
    L, B, T = 100.0, 20.0, 6.0
    li = _integrals(_box(L, B), T)
    np.testing.assert_allclose(np.asarray(li.area), B * T, rtol=1e-14)
    np.testing.assert_allclose(np.asarray(li.half_breadth), B / 2, rtol=1e-14)
    got = {k: float(getattr(li, k)) for k in ("volume", "lcb", "kb", "awp", "lcf", "i_t", "i_l", "bwl", "lwl")}
    want = {"volume": L * B * T, "lcb": L / 2, "kb": T / 2, "awp": L * B, "lcf": L / 2, "i_t": L * B**3 / 12,
            "i_l": B * L**3 / 12, "bwl": B, "lwl": L}
    assert got == pytest.approx(want, rel=1e-12)
    assert tuple(map(float, volume_lcb(_box(L, B).x, li.area))) == pytest.approx((L * B * T, L / 2), rel=1e-14)


def test_longitudinal_integrals_vmap_grad_and_dry():
    box = _box()
    drafts = jnp.asarray([2.0, 5.0, 8.0])
    vols = jax.jit(jax.vmap(lambda t: longitudinal_integrals(box, t).volume))(drafts)
    np.testing.assert_allclose(np.asarray(vols), 100.0 * 20.0 * np.asarray(drafts), rtol=1e-13)
    dv = jax.jit(jax.grad(lambda t: longitudinal_integrals(box, t).volume))(5.0)  # d∇/dT = Awp
    assert float(dv) == pytest.approx(2000.0, rel=1e-12)
    dry = _integrals(box, -1.0)  # below the keel: nothing immersed, no NaN
    assert float(dry.volume) == 0.0 and float(dry.lcb) == 0.0 and float(dry.kb) == 0.0
    g = jax.jit(jax.grad(lambda t: longitudinal_integrals(box, t).lcb + longitudinal_integrals(box, t).kb))(-1.0)
    assert np.isfinite(float(g))


def test_safe_div_and_sqrt_have_finite_gradients_where_guarded():
    den = jnp.asarray([0.0, 2.0])
    np.testing.assert_array_equal(np.asarray(safe_div(jnp.asarray([1.0, 1.0]), den)), [0.0, 0.5])
    np.testing.assert_array_equal(np.asarray(safe_div(1.0, den, den > 1.0, fill=-1.0)), [-1.0, 0.5])
    g = jax.grad(lambda d: jnp.sum(safe_div(3.0, d)))(den)
    np.testing.assert_array_equal(np.asarray(g), [0.0, -0.75])
    g = jax.grad(lambda v: jnp.sum(safe_sqrt(v)))(jnp.asarray([0.0, 4.0]))
    np.testing.assert_array_equal(np.asarray(g), [0.0, 0.25])
    g = jax.grad(lambda v: safe_norm(v))(jnp.zeros(3))
    np.testing.assert_array_equal(np.asarray(g), np.zeros(3))
    assert float(safe_norm(jnp.asarray([3.0, 4.0]))) == 5.0


def test_section_necks_by_hand():
    """A section that widens to 3 m at z 1, narrows to 1 m at z 2 and widens again: a neck of 2 m under a
    waterline above the waist, none under one below it; a Wigley (only widening from the keel) has none."""
    from hullopt.geometry import Sections, section_necks
    from hullopt.models import wigley

    bulb = jnp.array([[0.0, 0.0], [3.0, 1.0], [1.0, 2.0], [5.0, 4.0], [5.0, 8.0]])
    plain = jnp.array([[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [4.0, 4.0], [5.0, 8.0]])
    s = Sections(jnp.array([0.0, 10.0]), jnp.stack([plain, bulb]), jnp.asarray(10.0))
    np.testing.assert_allclose(section_necks(s, 6.0), [0.0, 2.0], atol=1e-15)
    np.testing.assert_allclose(section_necks(s, 1.5), [0.0, 0.0], atol=1e-15)
    w = jax.tree.map(jnp.asarray, wigley(100.0, 10.0, 6.25, 10.0, n=21, m=41))
    assert float(jnp.max(section_necks(w, 6.25))) < 1e-12
