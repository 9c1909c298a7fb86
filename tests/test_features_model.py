"""Feature-curve hull (seed 000): round trip, zero deformation, claims 5-7, gradients, bad input."""

import equinox as eqx
import jax
import jax.flatten_util
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import check_grad

from hullopt.errors import HullError
from hullopt.geometry import section_integrals
from hullopt.hydro import hydrostatics, volume_at
from hullopt.models import (ApexMove, ContourEdit, Distribution, check_design, feature_model, load_parent,
                            parent_names)
from hullopt.models._feature_frame import segment_points
from hullopt.models._feature_library import build_parent, recipe_sections


def _roundtrip(parent, rebuilt, draft):
    h0, h1 = hydrostatics(parent, draft), hydrostatics(rebuilt, draft)
    zs = np.linspace(0.03 * draft, 0.999 * float(parent.depth), 30)
    dev = max(np.abs(np.asarray(section_integrals(parent, z).width - section_integrals(rebuilt, z).width)).max()
              for z in zs)
    return float(h1.volume / h0.volume - 1), float(h1.lcb_pct - h0.lcb_pct), dev / float(2 * parent.max_half_breadth)


@pytest.mark.parametrize("name,draft", [("seed003", 4.0), ("wigley", 6.25)])
def test_roundtrip_small(name, draft):
    dv, dl, dev = _roundtrip(recipe_sections(name), load_parent(name).sections(), draft)
    assert abs(dv) < 2e-3 and abs(dl) < 0.1 and dev < 5e-3


def test_roundtrip_dtc_and_library_matches_reextraction(shared):
    parent = recipe_sections("dtc", shared)
    stored = load_parent("dtc")
    dv, dl, dev = _roundtrip(parent, stored.sections(), 14.5)
    assert abs(dv) < 2e-3 and abs(dl) < 0.1 and dev < 5e-3
    fresh = build_parent("dtc", shared)
    np.testing.assert_allclose(np.asarray(fresh.sections().yz), np.asarray(stored.sections().yz), atol=1e-9)


def test_library_names():
    assert {"dtc", "tanker", "wigley", "seed003"} <= set(parent_names())
    with pytest.raises(HullError, match="unknown parent"):
        load_parent("nope")


def test_segment_spline_keeps_apex_and_claim6_ratios():
    a, b = jnp.array([0.0, 0.0]), jnp.array([4.0, 3.0])
    apex = jnp.array([0.4, -0.2])
    aux = jnp.array([[[0.5, 0.75]], [[0.4, 0.6]]])
    pts = segment_points(a, b, apex, aux, 8)
    c, rc = b - a, jnp.array([-3.0, 4.0])
    u = (pts - a) @ c / 25.0
    v = (pts - a) @ rc / 25.0
    k = 2 * 8 - 1  # the apex is the last sample of the first half
    np.testing.assert_allclose([u[k], v[k]], apex, atol=1e-14)
    assert np.argmax(np.abs(v)) == k  # the apex stays the point farthest from the chord
    # Tangent parallel to the chord at the apex: one-sided slopes dv/du vanish as the step shrinks.
    fine = segment_points(a, b, apex, aux, 400)
    uf, vf = (fine - a) @ c / 25.0, (fine - a) @ rc / 25.0
    kk = 2 * 400 - 1
    assert abs((vf[kk] - vf[kk - 1]) / (uf[kk] - uf[kk - 1])) < 2e-3
    np.testing.assert_allclose(pts[-1], b, atol=1e-14)
    # Claim 6: a moved apex; the auxiliary apexes keep their ratios to it.
    apex2 = jnp.array([0.55, -0.3])
    p2 = segment_points(a, b, apex2, aux, 8)
    u2, v2 = (p2 - a) @ c / 25.0, (p2 - a) @ rc / 25.0
    i1 = 8 - 1  # first auxiliary apex
    np.testing.assert_allclose([u2[i1] / apex2[0], v2[i1] / apex2[1]], [0.5, 0.75], atol=1e-14)
    i2 = 2 * 8 + 8 - 1  # second half's auxiliary apex (mirrored)
    np.testing.assert_allclose([(1 - u2[i2]) / (1 - apex2[0]), v2[i2] / apex2[1]], [0.4, 0.6], atol=1e-14)


@pytest.fixture(scope="module")
def dtc_model():
    h = load_parent("dtc")
    moves = [ApexMove(-1, 200.0, 300.0, 350.0, "linear"), ApexMove(-1, 0.0, 40.0, 150.0, "smooth")]
    return feature_model(h, moves, [Distribution(180.0, 340.0, "all", 2)], [ContourEdit("fob_y", 150.0, 300.0)])


def test_zero_parameters_give_the_parent_exactly(dtc_model):
    yz = np.asarray(dtc_model(dtc_model.zeros()).yz)
    assert np.array_equal(yz, np.asarray(dtc_model.hull.sections().yz))  # bit for bit, eagerly
    jitted = np.asarray(eqx.filter_jit(dtc_model)(dtc_model.zeros()).yz)  # XLA may fuse: round-off only
    np.testing.assert_allclose(jitted, yz, rtol=0, atol=1e-12 * float(dtc_model.hull.lpp))


def test_claim5_ratios(dtc_model):
    h = dtc_model.hull
    x = np.asarray(h.x)
    p = eqx.tree_at(lambda t: t.apex, dtc_model.zeros(), jnp.array([[0.8, -0.5], [0.0, 0.0]]))
    before = np.asarray(h.apex_points())[:, -1]
    after = np.asarray(dtc_model.features(p).apex_points())[:, -1]
    move = after - before
    i1, k, i2 = (int(np.argmin(abs(x - v))) for v in (200.0, 300.0, 350.0))
    np.testing.assert_allclose(move[k], [0.8, -0.5], atol=1e-12)
    assert np.allclose(move[: i1 + 1], 0) and np.allclose(move[i2:], 0)
    e1, e2 = np.r_[x[i1], before[i1]], np.r_[x[i2], before[i2]]
    pts = np.column_stack([x, before])
    f = lambda i: np.linalg.norm(e1 + (pts[i] - e1) @ (e2 - e1) / np.sum((e2 - e1) ** 2) * (e2 - e1) - e2)  # noqa
    for i in range(k + 1, i2):  # between the moved apex and E2: ratio L2 / L1 of projected distances to E2
        np.testing.assert_allclose(move[i], move[k] * f(i) / f(k), rtol=1e-9, atol=1e-12)


def test_patent_worked_example_cb_held_lcb_forward():
    from hullopt.app.commands.features import read_design
    from pathlib import Path

    model, p, _ = read_design(Path(__file__).parents[1] / "configs" / "deform_example.toml")
    h0 = hydrostatics(model.hull.sections(), 14.5)
    h1 = hydrostatics(check_design(model, p), 14.5)
    assert abs(float(h1.cb - h0.cb)) < 1e-3
    assert 0.25 < float(h1.lcb_pct - h0.lcb_pct) < 0.35


def test_fair_for_moderate_moves(dtc_model):
    """No new curvature sign changes inside the moved segments (uppermost line, fore body)."""
    p = eqx.tree_at(lambda t: t.apex, dtc_model.zeros(), jnp.array([[0.5, -0.5], [-0.5, 0.5]]))
    base = None
    for params in (dtc_model.zeros(), p):
        f = dtc_model.features(params)
        from hullopt.models._feature_frame import segment_points as sp

        pts = np.asarray(sp(f.ends[:, -2], f.ends[:, -1], f.apex[:, -1], f.aux[:, -1], 6))
        d1 = np.diff(pts, axis=1)
        cross = d1[:, :-1, 0] * d1[:, 1:, 1] - d1[:, :-1, 1] * d1[:, 1:, 0]
        sig = np.where(np.abs(cross) > 1e-9 * np.abs(cross).max(), np.sign(cross), 0)
        changes = [np.sum(np.abs(np.diff(s[s != 0])) > 0) for s in sig]
        base = changes if base is None else base
    assert all(c <= b for c, b in zip(changes, base))


def test_gradients_volume_lcb(dtc_model):
    p0 = dtc_model.zeros()
    flat, unravel = jax.flatten_util.ravel_pytree(p0)
    x0 = np.asarray(flat) + 0.01

    @jax.jit
    def vol(v):
        return volume_at(dtc_model(unravel(v)), 14.5) / 1e5

    @jax.jit
    def lcb(v):
        return hydrostatics(dtc_model(unravel(v)), 14.5).lcb_pct

    check_grad(vol, x0, rtol=1e-5, atol=1e-7)
    check_grad(lcb, x0, rtol=1e-5, atol=1e-7)


def test_vmap_over_parameters(dtc_model):
    p = jax.tree.map(lambda a: jnp.stack([a, a + 0.01]), dtc_model.zeros())
    v = jax.jit(jax.vmap(lambda q: volume_at(dtc_model(q), 14.5)))(p)
    assert v.shape == (2,) and float(v[0]) != float(v[1])


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
    from pathlib import Path

    cfg = Path(__file__).parents[1] / "configs" / "deform_example.toml"
    assert main(["deform", "wigley", str(cfg), "--out", str(tmp_path / "h.stl")]) == 2  # lines absent on wigley
    assert main(["features", "wigley", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "features.png").is_file() and (tmp_path / "contours.json").is_file()
    bad = tmp_path / "bad.toml"
    bad.write_text('parent = "dtc"\n[[apex_move]]\nsegment = -1\nx_fixed1 = 0\nx_moved = 40\nx_fixed2 = 150\nd = [0.1, 0.1]\nwrong = 1\n')
    assert main(["deform", "dtc", str(bad), "--out", str(tmp_path / "h.stl")]) == 2
