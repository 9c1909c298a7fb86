"""Feature-curve hull (seed 000): round trip, zero deformation, claims 5-7, gradients, bad input.

Kept fast by compiling each function once: one jitted round-trip measure per parent, one jitted feature map,
and for the gradients one vmapped program that returns the sections, the measures and their directional
derivatives (``jax.jvp``), evaluated in a single batch for every finite-difference point and every
parameter direction. The DTC is sliced and re-extracted once per module.
"""

from pathlib import Path

import equinox as eqx
import jax
import jax.flatten_util
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.errors import HullError
from hullopt.geometry import longitudinal_integrals, section_integrals
from hullopt.hydro import hydrostatics, volume_at
from hullopt.models import (ApexMove, ContourEdit, Distribution, check_design, feature_hull, feature_model,
                            load_parent, parent_names)
from hullopt.models._feature_frame import segment_points
from hullopt.models._feature_library import RECIPES, extract_parent, recipe_sections
from hullopt.waves import bluntness

FIELDS = ("x", "keel", "deck", "ends", "apex", "aux", "real")
DTC_DRAFT = 14.5

_features = eqx.filter_jit(lambda model, params: model.features(params))
_segments = jax.jit(segment_points, static_argnums=4)


@eqx.filter_jit
def _roundtrip(parent, hull, draft, zs):
    """Relative volume error, LCB error [% Lpp] at ``draft`` and the largest half-breadth deviation at the
    waterlines ``zs`` [fraction of B] of the rebuilt ``hull`` against the ``parent`` sections."""
    rebuilt = hull.sections()

    def measure(s):
        li = longitudinal_integrals(s, draft)
        return li.volume, li.lcb, jax.vmap(lambda z: section_integrals(s, z).width)(zs)

    (v0, l0, w0), (v1, l1, w1) = measure(parent), measure(rebuilt)
    dev = jnp.max(jnp.abs(w1 - w0)) / (2.0 * parent.max_half_breadth)
    return v1 / v0 - 1.0, 100.0 * (l1 - l0) / parent.lpp, dev


#: (∇ relative, LCB [% Lpp], half-breadth [fraction of B]) allowed per library parent, about twice what each
#: measures: seed003 −0.008 %, +0.0026 % Lpp, 0.24 % B; wigley −0.099 % (level 2, kept as first extracted),
#: 0 (symmetric), 0.09 % B; dtc −0.003 %, −0.0011 % Lpp, 0.195 % B (the README's numbers).
ROUNDTRIP_TOL = {"seed003": (2e-4, 5e-3, 4e-3), "wigley": (1.5e-3, 1e-9, 2e-3), "dtc": (1e-4, 2e-3, 2.5e-3)}


def _check_roundtrip(name, parent, hull, draft):
    zs = jnp.linspace(0.03 * draft, 0.999 * float(parent.depth), 30)
    dv, dl, dev = (float(v) for v in _roundtrip(parent, hull, jnp.asarray(draft), zs))
    tv, tl, td = ROUNDTRIP_TOL[name]
    assert abs(dv) < tv and abs(dl) < tl and dev < td, (dv, dl, dev)


@pytest.mark.parametrize("name,draft", [("seed003", 4.0), ("wigley", 6.25)])
def test_roundtrip_small(name, draft):
    _check_roundtrip(name, recipe_sections(name), load_parent(name), draft)


@pytest.fixture(scope="module")
def dtc_sections(hulls):
    """The DTC sliced as its library recipe does (once)."""
    return recipe_sections("dtc", hulls)


def test_roundtrip_dtc(dtc_sections):
    _check_roundtrip("dtc", dtc_sections, load_parent("dtc"), DTC_DRAFT)


def test_library_file_matches_reextraction(dtc_sections):
    recipe = {k: v for k, v in RECIPES["dtc"].items() if k not in ("source", "design_draft")}
    fresh = extract_parent(dtc_sections, "dtc", DTC_DRAFT, **recipe)
    stored = load_parent("dtc")
    for k in FIELDS:
        np.testing.assert_allclose(np.asarray(getattr(fresh, k)), np.asarray(getattr(stored, k)), atol=1e-9, err_msg=k)


def test_library_names():
    assert {"dtc", "tanker", "wigley", "seed003"} <= set(parent_names())
    with pytest.raises(HullError, match="unknown parent"):
        load_parent("nope")


def test_segment_spline_keeps_apex_and_claim6_ratios():
    q = 400
    a, b = jnp.array([0.0, 0.0]), jnp.array([4.0, 3.0])
    apex = jnp.array([0.4, -0.2])
    aux = jnp.array([[[0.5, 0.75]], [[0.4, 0.6]]])
    c, rc = np.array([4.0, 3.0]), np.array([-3.0, 4.0])
    uv = lambda p: (np.asarray(p - a) @ c / 25.0, np.asarray(p - a) @ rc / 25.0)  # noqa: E731 - chord frame
    pts = _segments(a, b, apex, aux, q)
    u, v = uv(pts)
    k = 2 * q - 1  # the apex is the last sample of the first half
    np.testing.assert_allclose([u[k], v[k]], apex, atol=1e-14)
    assert np.argmax(np.abs(v)) == k  # the apex stays the point farthest from the chord
    # Tangent parallel to the chord at the apex: the one-sided slope dv/du vanishes as the step shrinks.
    assert abs((v[k] - v[k - 1]) / (u[k] - u[k - 1])) < 2e-3
    np.testing.assert_allclose(pts[-1], b, atol=1e-14)
    # Claim 6: a moved apex; the auxiliary apexes keep their ratios to it.
    apex2 = jnp.array([0.55, -0.3])
    u2, v2 = uv(_segments(a, b, apex2, aux, q))
    i1 = q - 1  # first auxiliary apex
    np.testing.assert_allclose([u2[i1] / apex2[0], v2[i1] / apex2[1]], [0.5, 0.75], atol=1e-14)
    i2 = 2 * q + q - 1  # second half's auxiliary apex (mirrored)
    np.testing.assert_allclose([(1 - u2[i2]) / (1 - apex2[0]), v2[i2] / apex2[1]], [0.4, 0.6], atol=1e-14)


@pytest.fixture(scope="module")
def dtc_model():
    """Two apex moves (claim 5: linear in the fore body, smooth in the run), a distribution of all curves
    (claim 7) and two contour edits: the flat of bottom and the deck side line in the fore body (the latter
    moves the upper segments' chord ends, so it changes the waterline and Bf)."""
    moves = [ApexMove(-1, 200.0, 300.0, 350.0, "linear"), ApexMove(-1, 0.0, 40.0, 150.0, "smooth")]
    edits = [ContourEdit("fob_y", 150.0, 300.0), ContourEdit("deck_y", 250.0, 345.0)]
    return feature_model(load_parent("dtc"), moves, [Distribution(180.0, 340.0, "all", 2)], edits)


@pytest.mark.slow
def test_zero_parameters_give_the_parent_exactly(dtc_model):
    zeros = dtc_model.zeros()
    f = _features(dtc_model, zeros)
    for k in FIELDS:  # the feature curves, bit for bit under jit
        assert np.array_equal(np.asarray(getattr(f, k)), np.asarray(getattr(dtc_model.hull, k))), k
    # The user's path (check_design: one compiled program): the sections bit for bit against the parent's compiled
    # alone, and against the parent's evaluated operation by operation to rounding (XLA fuses multiply-adds)
    yz = np.asarray(check_design(dtc_model, zeros).yz)
    assert np.array_equal(yz, np.asarray(eqx.filter_jit(lambda h: h.sections())(dtc_model.hull).yz))
    np.testing.assert_allclose(yz, np.asarray(dtc_model.hull.sections().yz), rtol=0,
                               atol=1e-14 * float(dtc_model.hull.lpp))


def test_claim5_ratios(dtc_model):
    h = dtc_model.hull
    x = np.asarray(h.x)
    p = eqx.tree_at(lambda t: t.apex, dtc_model.zeros(), jnp.array([[0.8, -0.5], [0.0, 0.0]]))
    before = np.asarray(h.apex_points())[:, -1]
    after = np.asarray(_features(dtc_model, p).apex_points())[:, -1]
    move = after - before
    i1, k, i2 = (int(np.argmin(abs(x - v))) for v in (200.0, 300.0, 350.0))
    np.testing.assert_allclose(move[k], [0.8, -0.5], atol=1e-12)
    assert np.allclose(move[: i1 + 1], 0) and np.allclose(move[i2:], 0)
    e1, e2 = np.r_[x[i1], before[i1]], np.r_[x[i2], before[i2]]
    pts = np.column_stack([x, before])
    f = lambda i: np.linalg.norm(e1 + (pts[i] - e1) @ (e2 - e1) / np.sum((e2 - e1) ** 2) * (e2 - e1) - e2)  # noqa
    assert i2 - k > 2
    for i in range(k + 1, i2):  # between the moved apex and E2: ratio L2 / L1 of projected distances to E2
        np.testing.assert_allclose(move[i], move[k] * f(i) / f(k), rtol=1e-9, atol=1e-12)


def test_patent_worked_example_cb_held_lcb_forward():
    from hullopt.app.commands.features import read_design

    model, p, _ = read_design(Path(__file__).parents[1] / "configs" / "deform_example.toml")
    hydro = jax.jit(hydrostatics)
    h0 = hydro(model.hull.sections(), DTC_DRAFT)
    h1 = hydro(check_design(model, p), DTC_DRAFT)
    assert abs(float(h1.cb - h0.cb)) < 1e-3
    assert 0.25 < float(h1.lcb_pct - h0.lcb_pct) < 0.35


def test_fair_for_moderate_moves(dtc_model):
    """No new curvature sign changes inside the moved segments (uppermost line, both moves)."""
    p = eqx.tree_at(lambda t: t.apex, dtc_model.zeros(), jnp.array([[0.5, -0.5], [-0.5, 0.5]]))
    changes = []
    for params in (dtc_model.zeros(), p):
        f = _features(dtc_model, params)
        pts = np.asarray(_segments(f.ends[:, -2], f.ends[:, -1], f.apex[:, -1], f.aux[:, -1], 6))
        d1 = np.diff(pts, axis=1)
        cross = d1[:, :-1, 0] * d1[:, 1:, 1] - d1[:, :-1, 1] * d1[:, 1:, 0]
        sig = np.where(np.abs(cross) > 1e-9 * np.abs(cross).max(), np.sign(cross), 0)
        changes.append(np.array([np.sum(np.abs(np.diff(s[s != 0])) > 0) for s in sig]))
    moved = np.asarray(dtc_model.move_w).max(0) > 0
    assert moved.sum() > 10
    assert np.all(changes[1] <= changes[0])


@pytest.fixture(scope="module")
def dtc_derivatives(dtc_model):
    """Volume/1e5 [m³], LCB [% Lpp] and head-sea Bf at T = 14.5 m of the DTC design at a point away from the
    parent, and their derivatives w.r.t. every parameter two ways: forward mode (``jax.jvp`` along each unit
    vector) and central finite differences — every row from one jitted program."""
    flat, unravel = jax.flatten_util.ravel_pytree(dtc_model.zeros())

    def measures(v):
        s = dtc_model(unravel(v))
        h = hydrostatics(s, DTC_DRAFT)
        return jnp.stack([h.volume / 1e5, h.lcb_pct, bluntness(s, DTC_DRAFT)])

    run = jax.jit(lambda v, d: jax.jvp(measures, (v,), (d,)))
    x0 = jnp.asarray(flat) + 0.01
    step = 1e-6 * jnp.maximum(jnp.abs(x0), 1.0)
    eye = jnp.eye(flat.size, dtype=flat.dtype)
    zero = jnp.zeros_like(x0)
    ad = np.stack([np.asarray(run(x0, e)[1]) for e in eye], 1)  # (3, n)
    fd = np.stack([(np.asarray(run(x0 + h * e, zero)[0]) - np.asarray(run(x0 - h * e, zero)[0])) / (2 * float(h))
                   for h, e in zip(step, eye)], 1)
    return ad, fd, np.asarray(run(x0, zero)[0])


@pytest.mark.slow
def test_vmap_over_parameters(dtc_model, dtc_sections):
    """The batch: design 0 (the parent) holds the sliced DTC's ∇ (round trip: −0.003 %), design 1 equals the
    same design evaluated on its own (not batched), and the two differ."""
    zeros = dtc_model.zeros()
    shifted = jax.tree.map(lambda a: a + 0.01, zeros)
    p = jax.tree.map(lambda a, b: jnp.stack([a, b]), zeros, shifted)
    v = jax.jit(jax.vmap(lambda q: volume_at(dtc_model(q), DTC_DRAFT)))(p)
    assert v.shape == (2,)
    vol = jax.jit(volume_at)  # compiled: the same integrals as op by op, a few times faster here
    assert float(v[0]) == pytest.approx(float(vol(dtc_sections, DTC_DRAFT)), rel=1e-4)
    assert float(v[1]) == pytest.approx(float(vol(check_design(dtc_model, shifted), DTC_DRAFT)), rel=1e-12)
    assert abs(float(v[1]) / float(v[0]) - 1.0) > 1e-4


def _assert_fd(ad, fd):
    assert np.all(np.isfinite(ad)), "gradient has NaN/inf"
    np.testing.assert_allclose(ad, fd, rtol=1e-5, atol=1e-7 * max(1.0, np.abs(fd).max()))


def test_gradients_volume_lcb(dtc_derivatives):
    ad, fd, _ = dtc_derivatives
    _assert_fd(ad[0], fd[0])
    _assert_fd(ad[1], fd[1])
    assert np.all(np.abs(ad[:2]).max(0) > 1e-4)  # every parameter moves volume or LCB: no vacuous column


def test_gradient_waterline_bluntness(dtc_derivatives, dtc_model):
    ad, fd, m = dtc_derivatives
    assert 0.0 < m[2] < 2.0 / 3.0  # a fine entrance: blunter only with a semicircular bow (2/3)
    _assert_fd(ad[2], fd[2])
    # The fore-body parameters act on the waterline (the run is not lit in head seas: exactly 0 there).
    flat, unravel = jax.flatten_util.ravel_pytree(dtc_model.zeros())
    g = unravel(jnp.asarray(ad[2]))
    assert np.all(np.abs(np.asarray(g.apex[0])) > 1e-4) and np.all(np.asarray(g.apex[1]) == 0)
    assert np.all(np.abs(np.asarray(g.distribution)) > 1e-4) and abs(float(g.contour[1])) > 1e-4  # deck_y


def test_a_named_curve_slides_with_the_inflection_curve_on_it():
    """Where a hull has no flat of side, its start is the deck edge (here at every station of a Wigley made
    so): sliding the deck slides it too, so the sections stay closed (sliding the deck alone opened a gap of
    ~1e-9 m per 1e-8 of amplitude there, and a segment that short turns any way: the KCS's section
    roughness grew 1e8-fold)."""
    f = load_parent("wigley").to_dict()
    f["ends"] = np.asarray(f["ends"])
    f["ends"][:, -1] = f["deck"]
    h = feature_hull(f)
    model = feature_model(h, distributions=[Distribution(10.0, 90.0, "deck", 2)])
    slid = model.features(eqx.tree_at(lambda t: t.distribution, model.zeros(), jnp.array([[0.2, -0.1]])))
    assert float(jnp.max(jnp.abs(slid.deck - h.deck))) > 1e-2  # the deck slid
    np.testing.assert_array_equal(np.asarray(slid.ends[:, -1]), np.asarray(slid.deck))


def test_a_whole_frame_distribution_keeps_coincident_feature_points_together():
    """The DTC's segments collapse (two inflection points coincide) at 176 pairs of neighbouring stations. A
    distribution of all curves re-reads the frames between the parent's stations; it interpolates the chain of
    offsets keel → segment ends → deck, so two points that coincide at both stations around a frame's source
    coincide in the frame too (interpolated one by one, their different slopes parted them by up to 0.15 m
    here: a stub segment that turns any way, which the knuckle and roughness measures read as knuckles)."""
    h = load_parent("dtc")
    xa, xb, c = 20.0, 340.0, np.array([0.25, -0.1])
    model = feature_model(h, distributions=[Distribution(xa, xb, "all", 2)])
    f = model.features(eqx.tree_at(lambda t: t.distribution, model.zeros(), jnp.asarray(c[None])))
    x, ends = np.asarray(h.x), np.asarray(h.ends)
    xi = np.clip((x - xa) / (xb - xa), 0.0, 1.0)
    warp = xa + (xb - xa) * (xi + c[0] * np.sin(np.pi * xi) / np.pi + c[1] * np.sin(2 * np.pi * xi) / (2 * np.pi))
    source = np.where((x > xa) & (x < xb), warp, x)
    i = np.clip(np.searchsorted(x, source, side="right") - 1, 0, len(x) - 2)
    same = np.all(ends[:, 1:] == ends[:, :-1], -1)  # (n, S) segment s collapsed at the parent's station
    both = same[i] & same[i + 1]
    assert both.sum() > 50 and np.any(np.abs(source - x) > 5.0)  # many such frames, moved metres
    gap = np.hypot(*np.moveaxis(np.asarray(f.ends[:, 1:] - f.ends[:, :-1]), -1, 0))
    assert gap[both].max() < 1e-12
    # one by one, the same interpolation parts them
    from scipy.interpolate import PchipInterpolator

    alone = PchipInterpolator(x, ends, axis=0)(source)
    assert np.hypot(*np.moveaxis(alone[:, 1:] - alone[:, :-1], -1, 0))[both].max() > 0.1


def test_a_group_uses_only_its_own_modes():
    """Two groups with 1 and 3 modes share a (2, 3) parameter array: the first group's two extra columns move
    nothing and count nothing in its monotonicity margin (they warped its frames and were bounded as its own)."""
    from hullopt.models import design_margins

    h = load_parent("dtc")
    model = feature_model(h, distributions=[Distribution(10.0, 150.0, "stations", 1),
                                            Distribution(180.0, 340.0, "stations", 3)])
    at = lambda c: eqx.tree_at(lambda t: t.distribution, model.zeros(), jnp.asarray(c, float))  # noqa: E731
    base = at([[0.2, 0.0, 0.0], [0.1, -0.1, 0.05]])
    extra = at([[0.2, 0.5, -0.4], [0.1, -0.1, 0.05]])
    np.testing.assert_array_equal(np.asarray(model(extra).x), np.asarray(model(base).x))
    np.testing.assert_allclose(np.asarray(design_margins(model, extra)["warp"]), [0.8, 0.75], atol=1e-15)
    assert not np.array_equal(np.asarray(model(base).x), np.asarray(h.x))  # the used modes do move it


@pytest.mark.slow
def test_a_station_shift_moves_the_frames_and_keeps_their_shapes():
    """``curves="stations"`` moves the frames themselves along the length (a Lackenby-like shift): each keeps
    the parent's shape, so the section measures are the parent's, while Cb, LCB and the waterline's entrance
    change. Volume checked against the closed mesh of the shifted hull (trimesh, a second method) and its
    gradient against central differences."""
    from hullopt.geometry import to_trimesh

    h = load_parent("dtc")
    xa, xb = 180.0, 340.0
    model = feature_model(h, distributions=[Distribution(xa, xb, "stations", 2)])
    at = lambda c: eqx.tree_at(lambda t: t.distribution, model.zeros(), jnp.asarray([c], float))  # noqa: E731
    s0, s1 = model(model.zeros()), model(at([0.2, -0.1]))
    np.testing.assert_array_equal(np.asarray(s1.yz), np.asarray(s0.yz))  # the frames keep their shapes
    x0, x1 = np.asarray(s0.x), np.asarray(s1.x)
    inside = (x0 > xa) & (x0 < xb)
    np.testing.assert_array_equal(x1[~inside], x0[~inside])
    xi = (x0[inside] - xa) / (xb - xa)
    shift = (xb - xa) * (0.2 * np.sin(np.pi * xi) / np.pi - 0.1 * np.sin(2 * np.pi * xi) / (2 * np.pi))
    np.testing.assert_allclose(x1[inside] - x0[inside], shift, atol=1e-12)
    assert np.all(np.diff(x1) > 0) and np.max(np.abs(x1 - x0)) > 5.0
    # frames moved forward in the fore body: fuller there, LCB forward
    h0, h1 = hydrostatics(s0, 11.0), hydrostatics(s1, 11.0)
    assert float(h1.cb) > float(h0.cb) + 0.005 and float(h1.lcb_pct) > float(h0.lcb_pct) + 0.3
    # the whole hull's volume (to the deck) against the closed mesh's: the change agrees to 1 %
    depth = float(jnp.max(s0.yz[..., 1]))
    dv = float(volume_at(s1, depth) - volume_at(s0, depth))
    dv_mesh = to_trimesh(s1).volume - to_trimesh(s0).volume
    assert abs(dv) > 500.0
    np.testing.assert_allclose(dv_mesh, dv, rtol=1e-2)
    grad = jax.grad(lambda c: volume_at(model(at([c, -0.1])), 11.0))(0.2)
    e = 1e-5
    fd = (volume_at(model(at([0.2 + e, -0.1])), 11.0) - volume_at(model(at([0.2 - e, -0.1])), 11.0)) / (2 * e)
    np.testing.assert_allclose(float(grad), float(fd), rtol=1e-6)


def test_bad_designs():
    h = load_parent("dtc")
    with pytest.raises(HullError, match="strictly between"):
        feature_model(h, [ApexMove(-1, 200.0, 100.0, 300.0)])
    with pytest.raises(HullError, match="outside the hull"):
        feature_model(h, [ApexMove(-1, -50.0, 100.0, 300.0)])
    with pytest.raises(HullError, match="not on apex line"):
        feature_model(h, [ApexMove(0, 100.0, 150.0, 200.0)])
    with pytest.raises(HullError, match="two groups"):
        feature_model(h, distributions=[Distribution(10.0, 100.0), Distribution(150.0, 200.0)])
    with pytest.raises(HullError, match="a group of its own"):
        feature_model(h, distributions=[Distribution(10.0, 100.0, ("stations", "keel"))])
    with pytest.raises(HullError, match="overlap"):
        feature_model(h, distributions=[Distribution(10.0, 100.0, "stations"), Distribution(90.0, 200.0, "stations")])
    with pytest.raises(HullError, match="line"):
        feature_model(h, edits=[ContourEdit("bow", 10.0, 20.0)])
    model = feature_model(h, [ApexMove(-1, 200.0, 300.0, 350.0)], [Distribution(180.0, 340.0, "all", 1)])
    big = eqx.tree_at(lambda t: t.apex, model.zeros(), jnp.array([[40.0, 0.0]]))
    with pytest.raises(HullError, match="outside its segment|crosses|folds"):
        check_design(model, big)
    warp = eqx.tree_at(lambda t: t.distribution, model.zeros(), jnp.array([[1.5]]))
    with pytest.raises(HullError, match="fold"):
        check_design(model, warp)


def test_cli_features_and_deform(tmp_path):
    from hullopt.app.cli import main

    cfg = Path(__file__).parents[1] / "configs" / "deform_example.toml"
    assert main(["deform", "wigley", str(cfg), "--out", str(tmp_path / "h.stl")]) == 2  # lines absent on wigley
    assert main(["features", "dtc", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "features.png").is_file() and (tmp_path / "contours.json").is_file()
    bad = tmp_path / "bad.toml"
    bad.write_text('parent = "dtc"\n[[apex_move]]\nsegment = -1\nx_fixed1 = 0\nx_moved = 40\nx_fixed2 = 150\nd = [0.1, 0.1]\nwrong = 1\n')
    assert main(["deform", "dtc", str(bad), "--out", str(tmp_path / "h.stl")]) == 2


_MOVE = 'segment = -1\nx_fixed1 = 0\nx_moved = 40\nx_fixed2 = 150\nd = [0.1, 0.1]\n'


@pytest.mark.parametrize("table, field", [
    ("[[apex_move]]\n" + _MOVE + "wrong = 1\n", "apex_move.0.wrong"),  # unknown key
    ("[[apex_move]]\n" + _MOVE.replace("d = [0.1, 0.1]", "d = [0.1]"), "apex_move.0.d"),
    ("[[apex_move]]\n" + _MOVE.replace("x_moved = 40", 'x_moved = "forty"'), "apex_move.0.x_moved"),
    ("[[contour_edit]]\nline = \"keel\"\nx_a = 0\nx_b = 10\n", "contour_edit.0.line"),
    ("colour = 1\n[[apex_move]]\n" + _MOVE, "colour"),
])
def test_deform_design_errors_name_the_file_and_the_field(cli, tmp_path, table, field):
    """`hullopt deform` validates its design TOML with the run config's models: one line, the file, the field."""
    bad = tmp_path / "bad.toml"
    bad.write_text('parent = "dtc"\n' + table)
    code, _, err = cli("deform", "dtc", bad, "--out", tmp_path / "h.stl")
    assert code == 2
    line = err.strip()
    assert "\n" not in line and line.startswith("error:") and str(bad) in line and field in line, line


def test_deform_and_run_build_the_same_hull_from_the_same_tables(tmp_path):
    """The same [[apex_move]]/[[distribution]]/[[contour_edit]] tables (defaults included: profile, modes)
    give the same start parameters, bounds and hull in `hullopt deform` and in a run config's [design]."""
    from hullopt.app.commands.features import read_design
    from hullopt.study import load_config, load_study

    tables = ("[[{p}apex_move]]\nsegment = -1\nx_fixed1 = 50.0\nx_moved = 80.0\nx_fixed2 = 100.0\nd = [0.4, -0.3]\n"
              "[[{p}distribution]]\nx_a = 0.0\nx_b = 100.0\nc = [0.06]\n")
    (tmp_path / "d.toml").write_text('parent = "wigley"\n' + tables.format(p=""))
    (tmp_path / "r.toml").write_text('kind = "fit"\n[hull]\nparent = "wigley"\n[targets]\ncb = 0.45\n'
                                     + tables.format(p="design."))
    model, p, name = read_design(tmp_path / "d.toml")
    cfg, _ = load_config(tmp_path / "r.toml")
    prob = load_study(cfg).problem
    from hullopt.study import load_design

    assert name == "wigley" and load_design(tmp_path / "d.toml").apex_move[0].profile == "smooth"  # one default
    for a, b in zip(jax.tree.leaves(p), jax.tree.leaves(prob.p0)):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    s1, s2 = model(p), prob.design.model(prob.p0)
    np.testing.assert_array_equal(np.asarray(s1.yz), np.asarray(s2.yz))
    np.testing.assert_array_equal(np.asarray(s1.x), np.asarray(s2.x))


def test_deform_design_parent_is_a_spec_relative_to_the_toml(tmp_path):
    """A design TOML's ``parent`` may be any run-config parent spec, a file resolved beside the TOML."""
    import shutil

    from hullopt.study import load_design
    from hullopt.models import save_features

    save_features(load_parent("wigley"), tmp_path / "w.json")
    (tmp_path / "sub").mkdir()
    shutil.move(tmp_path / "w.json", tmp_path / "sub" / "w.json")
    (tmp_path / "sub" / "d.toml").write_text('parent = "w.json"\n[[distribution]]\nx_a = 0.0\nx_b = 100.0\n')
    assert load_design(tmp_path / "sub" / "d.toml").parent == str(tmp_path / "sub" / "w.json")


def test_generate_hull_follows_its_sectional_area_curve():
    """A tanker-like hull from dimensions alone (320 × 58 × 30 m, T 20.8 m, bilge radius 3 m) against the
    formula it is built from: A(x) = a(x)·A_M with A_M = B·T − (4 − π)r²/2 and a = 1 on the parallel midbody
    (0.3–0.65 Lpp), 1 − ξ^2.2 / 1 − ξ^1.8 towards the FP / AP, so Cp = ∫a = 0.35 + 0.35·2.2/3.2 + 0.3·1.8/2.8.
    Measured: midbody A −0.006 % (the bilge's polyline), A(x) within 0.045 % of A_M, Cp −0.00016 (Simpson on
    41 stations across the midbody's kinks)."""
    from hullopt.hydro import sectional_areas
    from hullopt.models import generate_hull

    lpp, b, d, t, r = 320.0, 58.0, 30.0, 20.8, 3.0
    hull = generate_hull(lpp, b, d, t, bilge_radius=r, n=41)
    s = hull.sections()
    h = eqx.filter_jit(hydrostatics)(s, t)
    area = np.asarray(eqx.filter_jit(sectional_areas)(s, t))
    u = np.asarray(s.x) / lpp
    a = (1 - np.clip((u - 0.65) / 0.35, 0, 1) ** 2.2) * (1 - np.clip((0.3 - u) / 0.3, 0, 1) ** 1.8)
    am = b * t - (4 - np.pi) * r**2 / 2
    mid = (u >= 0.3) & (u <= 0.65)
    assert mid.sum() >= 10
    np.testing.assert_allclose(area[mid], am, rtol=2e-4)
    np.testing.assert_allclose(area, a * am, rtol=0, atol=1e-3 * am)
    assert float(h.cm) == pytest.approx(am / (b * t), abs=2e-4)
    assert float(h.cp) == pytest.approx(0.35 + 0.35 * 2.2 / 3.2 + 0.3 * 1.8 / 2.8, abs=5e-4)
    assert float(h.bwl) == pytest.approx(b, rel=1e-12) and float(h.lwl) == pytest.approx(lpp, rel=1e-12)
    with pytest.raises(HullError, match="bilge_radius"):
        generate_hull(lpp, b, d, t, bilge_radius=25.0)


def test_saved_parent_reads_back_exactly(tmp_path):
    """save_features → read_features: every array bit for bit (JSON floats round-trip by repr), the name,
    design draft and q kept, the rebuilt sections identical; the meta stays in the file; a file that is not a
    parent is refused with its path."""
    import json

    from hullopt.models import read_features, save_features

    for name in ("wigley", "dtc"):
        parent = load_parent(name)
        path = save_features(parent, tmp_path / f"{name}.json", source="a test", fidelity={"volume": 1e-5})
        back = read_features(path)
        for k in (*FIELDS, "lpp"):
            assert np.array_equal(np.asarray(getattr(back, k)), np.asarray(getattr(parent, k))), (name, k)
        assert (back.name, back.design_draft, back.q) == (parent.name, parent.design_draft, parent.q)
        assert np.array_equal(np.asarray(back.sections().yz), np.asarray(parent.sections().yz))
        raw = json.loads(path.read_text())
        assert raw["source"] == "a test" and raw["fidelity"] == {"volume": 1e-5}
    bad = tmp_path / "bad.json"
    bad.write_text('{"x": [0, 1]}')
    with pytest.raises(HullError, match="not a feature-curve parent file") as e:
        read_features(bad)
    assert str(bad) in str(e.value)

