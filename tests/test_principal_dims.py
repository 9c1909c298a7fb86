"""Principal dimensions as design variables: the draft scale ``[design.draft]`` beside the beam scale (the NATO
AVT-331 L2-Sea benchmark's beam and draft within ±5 %, Lpp and ∇ held). The Wigley's hydrostatics under the draft
scale s against its closed forms (∇ = 4/9·L·B·T, KB = 5/8·T, Cb = 4/9; T and every height × (1 + s)), the
design evaluated at its own draft (:meth:`hullopt.optimise.Design.hull`), gradients against central differences,
a fit with ∇ held and beam and draft both free, and the config, report and run folder keeping the design's
draft."""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import check_grad

from hullopt.hydro import hydrostatics
from hullopt.models import FeatureParams, feature_model, load_parent
from hullopt.optimise import Design, make_targets, solve_fit

L, B, T = 100.0, 10.0, 6.25  # the library's Wigley


@pytest.fixture(scope="module")
def wigley():
    hull = load_parent("wigley")
    return hull, feature_model(hull, beam=True, draft_scale=True)


def _params(model, beam=0.0, draft=0.0) -> FeatureParams:
    p = model.zeros()
    return FeatureParams(p.apex, p.distribution, p.contour, p.bow, jnp.array([beam]), jnp.array([draft]))


def test_zero_parameters_give_the_parent_exactly(wigley):
    hull, model = wigley
    p = model.zeros()
    assert p.draft.shape == (1,) and p.beam.shape == (1,)
    np.testing.assert_array_equal(np.asarray(model(p).yz), np.asarray(hull.sections().yz))
    assert float(model.draft_factor(p)) == 1.0
    assert feature_model(hull).draft_factor(feature_model(hull).zeros()) == 1.0  # no draft scale: the parent's


@pytest.mark.parametrize("s", [-0.05, 0.03])
def test_draft_scale_against_the_wigleys_closed_forms(wigley, s):
    """Heights and draft × (1 + s) from the baseline: ∇ × (1 + s), T × (1 + s), KB × (1 + s) (5/8·T), Cb 4/9
    unchanged; breadths, Lpp and the keel on the baseline kept."""
    hull, model = wigley
    p = _params(model, draft=s)
    design = Design(model=model, draft=np.asarray(T), targets=make_targets({}))
    sec, t = design.hull(p)
    assert float(t) == pytest.approx(T * (1 + s), rel=1e-14)
    h0, h = hydrostatics(hull.sections(), T), hydrostatics(sec, t)
    # the rebuilt parent against the closed forms (its splines: to 1e-3), the scaled hull against the parent exactly
    assert float(h0.volume) == pytest.approx(4 / 9 * L * B * T, rel=2e-3)
    assert float(h0.kb) == pytest.approx(5 / 8 * T, rel=2e-3)
    assert float(h.volume) == pytest.approx(4 / 9 * L * B * T * (1 + s), rel=2e-3)
    assert float(h.volume / h0.volume) == pytest.approx(1 + s, rel=1e-12)
    assert float(h.draft) == pytest.approx(T * (1 + s), rel=1e-14)
    assert float(h.kb / h0.kb) == pytest.approx(1 + s, rel=1e-12)
    for k in ("cb", "cp", "cm", "cwp", "lcb_pct"):
        assert float(getattr(h, k)) == pytest.approx(float(getattr(h0, k)), rel=1e-10, abs=1e-12), k
    assert float(h.cb) == pytest.approx(4 / 9, rel=2e-3)
    assert float(h.bwl) == pytest.approx(float(h0.bwl), rel=1e-12)
    assert float(h.lwl) == pytest.approx(float(h0.lwl), rel=1e-12)
    yz0, yz = np.asarray(hull.sections().yz), np.asarray(sec.yz)
    np.testing.assert_allclose(yz[..., 0], yz0[..., 0], rtol=0, atol=0)
    np.testing.assert_allclose(yz[..., 1], (1 + s) * yz0[..., 1], rtol=1e-14)
    assert float(yz[..., 1].min()) == float(yz0[..., 1].min()) == 0.0  # the keel on the baseline


def test_beam_and_draft_scales_multiply(wigley):
    hull, model = wigley
    design = Design(model=model, draft=np.asarray(T), targets=make_targets({}))
    h0 = hydrostatics(hull.sections(), T)
    h = hydrostatics(*design.hull(_params(model, 0.04, -0.03)))
    assert float(h.volume / h0.volume) == pytest.approx(1.04 * 0.97, rel=1e-12)
    assert float(h.bwl / h0.bwl) == pytest.approx(1.04, rel=1e-12)
    assert float(h.cb) == pytest.approx(float(h0.cb), rel=1e-10)


def test_gradients_against_central_differences(wigley):
    _, model = wigley
    design = Design(model=model, draft=np.asarray(T), targets=make_targets({}))

    def f(v):
        h = hydrostatics(*design.hull(_params(model, v[0], v[1])))
        return h.volume / 1e3 + h.kb + h.kmt + h.wetted_surface / 1e3

    check_grad(jax.jit(f), np.array([0.02, -0.03]), rtol=1e-6)


def test_fit_holds_the_volume_with_beam_and_draft_free(wigley):
    """∇ held and KB raised 3 %: the draft scale takes KB (5/8·T(1 + s)), the beam gives the volume back,
    (1 + s_B)(1 + s_T) = 1; evaluated at the design's own draft (at the parent's, KB could not move so)."""
    hull, model = wigley
    h0 = hydrostatics(hull.sections(), T)
    targets = make_targets({"volume": float(h0.volume), "kb": 1.03 * float(h0.kb)})
    design = Design(model=model, draft=np.asarray(T), targets=targets, smoothness=0.0)
    p0 = model.zeros()
    half = _params(model, 0.05, 0.05)
    r = jax.jit(lambda p: solve_fit(design, p, jax.tree.map(lambda h: -h, half), half, max_steps=100))(p0)
    assert bool(r.met)
    s_b, s_t = float(r.params.beam[0]), float(r.params.draft[0])
    assert s_t == pytest.approx(0.03, abs=2e-5)
    assert (1 + s_b) * (1 + s_t) == pytest.approx(1.0, abs=1e-5)
    h = hydrostatics(*design.hull(r.params))
    assert float(h.draft) == pytest.approx(T * 1.03, rel=2e-5)
    assert float(h.volume) == pytest.approx(float(h0.volume), rel=5e-4)


def test_config_report_and_run_folder_keep_the_designs_draft(cli, tmp_path):
    """``[design.draft]`` through a fit run: the report's ``params`` has ``draft_s``, ``achieved.draft`` is the
    design's (T·(1 + s)), the run folder read back as a hull floats at it; a start outside the bound is refused."""
    cfg = tmp_path / "fit.toml"
    cfg.write_text(f"""kind = "fit"
[hull]
parent = "wigley"
draft = {T}
[design.beam]
bound = 0.05
[design.draft]
bound = 0.05
[targets]
volume = {4 / 9 * L * B * T * 1.0:.6f}
kb = {1.02 * 5 / 8 * T:.6f}
[tolerances]
kb = 2e-3
volume = 2e-3
""")
    out = tmp_path / "run"
    code, stdout, err = cli("run", str(cfg), "--out", str(out), "--json")
    assert code == 0, err
    report = json.loads(stdout)
    assert report["met"]
    s = report["params"]["draft_s"][0]
    assert abs(s) > 0.005 and abs(report["params"]["beam_s"][0]) > 0.005
    assert report["achieved"]["draft"] == pytest.approx(T * (1 + s), rel=1e-9)
    assert report["parent"]["draft"] == pytest.approx(T)
    code, stdout, err = cli("hydro", str(out), "--json")
    assert code == 0, err
    again = json.loads(stdout)
    assert again["draft"] == pytest.approx(T * (1 + s), rel=1e-9)
    assert again["volume"] == pytest.approx(report["achieved"]["volume"], rel=1e-9)
    bad = tmp_path / "bad.toml"
    bad.write_text(cfg.read_text().replace("[design.draft]\nbound = 0.05", "[design.draft]\ns = 0.06\nbound = 0.05"))
    code, _, err = cli("run", str(bad), "--out", str(tmp_path / "bad"))
    assert code != 0 and "draft s" in err
