"""``hullopt rescore``: a run's designs and parent re-scored by every calm-water and added-resistance method, over
the profile and off it; the parent's values against the methods called directly, and a design that is worse by
every independent method warned of."""

import json

import jax
import numpy as np
import pytest

from hullopt.constants import KNOT

CONFIG = "tests/data/rescore_wigley.toml"  # one condition, the bow re-shaped by apex moves


@pytest.mark.slow
def test_rescore_a_run_folder(cli, tmp_path):
    from hullopt.models import save_features
    from hullopt.resistance import calm_water
    from hullopt.study import load_config, load_study, params_to_dict
    from hullopt.waves import mean_added_resistance

    cfg, raw = load_config(CONFIG)
    study = load_study(cfg)
    p0 = study.problem.p0
    fuller = type(p0)(np.asarray(p0.apex) + 0.5, np.asarray(p0.distribution), np.asarray(p0.contour))
    run = tmp_path / "run"
    run.mkdir()
    (run / "config.json").write_text(json.dumps(raw))
    save_features(study.problem.design.model.hull, run / "parent.json")
    (run / "report.json").write_text(json.dumps({"kind": "minimise", "met": True, "converged": True,
                                                 "params": params_to_dict(fuller), "warnings": ["kept"]}))
    code, out, err = cli("rescore", run, "--json")
    assert code == 0, err
    r = json.loads(out)
    m = r["methods"]
    assert set(m) == {"calm_holtrop", "calm_michell", "calm_panel", "waves_nmri", "waves_snnm", "waves_stawave2"}
    assert m["waves_nmri"]["own"] and not any(v["own"] for k, v in m.items() if k != "waves_nmri")
    assert r["conditions"]["sea_states"] == [[3.0, 9.0, 0.0]] and r["conditions"]["speeds_kn"] == [15.0]
    # the parent's nominal values are the methods' own, called directly
    s, t, u = study.problem.design.model(p0), 6.25, 15.0 * KNOT
    assert m["calm_holtrop"]["parent"] == pytest.approx(float(calm_water(s, t, u, "holtrop").total), rel=1e-9)
    snnm = jax.jit(lambda s: mean_added_resistance("snnm", s, t, u, 3.0, 9.0, 0.0).total)(s)
    assert m["waves_snnm"]["parent"] == pytest.approx(float(snnm), rel=1e-9)
    # a fuller bow: more resistance by every independent method in some condition (SNNM sees −0.4 % at the
    # nominal T_p but +0.9 % off it): no gain holds
    assert all(v["worst_pct"][0] > 0 and not v["holds"][0] for v in m.values() if not v["own"])
    assert m["waves_snnm"]["change_pct"][0] < 0 < m["waves_snnm"]["worst_pct"][0]
    assert r["verdict"] == [{"calm": False, "waves": False}]
    said = " ".join(err.split())
    # NMRI, the run's own, finds the fuller bow no better: no gain to confirm, but a loss the others see off the
    # profile
    assert "design 0: no independent method finds its added resistance in waves at or below the parent's" in said
    assert "design 0: no independent method finds its calm-water resistance at or below the parent's" in said
    report = json.loads((run / "report.json").read_text())
    assert report["rescored"]["methods"].keys() == m.keys() and "kept" in report["warnings"]
    assert len([w for w in report["warnings"] if w.startswith("design 0: ")]) == 2
    assert "re-scored by independent methods" in (run / "report.html").read_text()
    # the parent itself: its own method (NMRI) finds no gain, so there is none to confirm, only no loss to find
    # (STAWAVE-2, the particulars held, sees none): it holds, without a word
    same, doubts = study.rescore([p0])
    assert same["verdict"] == [{"calm": True, "waves": True}] and doubts == []
    # run again: the warnings are replaced, not doubled
    assert cli("rescore", run, "--json")[0] == 0
    again = json.loads((run / "report.json").read_text())["warnings"]
    assert len([w for w in again if w.startswith("design 0: ")]) == 2


def test_rescore_refuses_a_fit(cli, tmp_path):
    run = tmp_path / "fit"
    run.mkdir()
    raw = {"kind": "fit", "hull": {"parent": "wigley"}, "targets": {"cb": 0.45},
           "design": {"distribution": [{"x_a": 0.0, "x_b": 100.0}]}}
    (run / "config.json").write_text(json.dumps(raw))
    (run / "report.json").write_text(json.dumps({"kind": "fit", "params": {}}))
    code, _, err = cli("rescore", run)
    assert code == 2 and "nothing to re-score" in err, err


def test_an_objective_that_is_the_sum_is_confirmed_by_a_pair_of_methods():
    """An operating profile with sea states (calm water + R_AW): the gain is the sum's. Its own pair (michell +
    nmri) confirms nothing; a pair with an independent method does when the sum falls at the profile and
    nowhere rises off it (conditions: the profile, speed × 0.9 and 1.1, T_p −2 and +2 s)."""
    from hullopt.study._rescore import CONDITIONS, _total_holds

    assert len(CONDITIONS) == 5
    parent = np.full(5, 100.0)
    values = {"calm_michell": np.stack([parent, np.full(5, 90.0)]),  # calm water: the first three conditions
              "calm_holtrop": np.stack([parent, np.full(5, 100.5)]),
              "waves_nmri": np.stack([parent, np.full(5, 105.0)]),
              "waves_snnm": np.stack([parent, [100.0, 100.0, 100.0, 100.0, 109.0]])}
    methods = {k: {"kind": k.split("_")[0], "method": k.split("_")[1], "own": k in ("calm_michell", "waves_nmri")}
               for k in values}
    held, text = _total_holds(values, methods, 0)
    # michell + snnm: 190 against 200 at the profile, 199 at T_p + 2 s: held (holtrop + either: +2.75 %, +0.25 %)
    assert held and "michell + snnm -5.00 % (worst -0.50 %)" in text and "michell + nmri" not in text
    values["waves_snnm"][1, 4] = 111.0  # now 201 > 200 off the profile
    assert not _total_holds(values, methods, 0)[0]


def test_a_method_outside_its_validity_confirms_nothing():
    """On a full hull the Kelvin panel method (outside its validity) finding a design lower does not confirm the
    objective's (Michell's) gain when Dawson's and Holtrop's find it higher: the warning names both, and the
    excluded one as not counted."""
    from hullopt.study._rescore import _confirmed

    def method(name, change, own=False, invalid=None):
        return {"kind": "calm", "method": name, "own": own, "outside_validity": invalid, "change_pct": [change],
                "worst_pct": [change], "holds": [change <= 0.1]}

    methods = {m["method"]: m for m in (method("michell", -5.0, own=True, invalid="Cb 0.64"),
                                        method("panel", -3.6, invalid="Cb 0.64"), method("holtrop", 0.2),
                                        method("dawson", 0.9))}
    held, warning = _confirmed(methods, "calm", 0)
    assert not held and "dawson +0.90 %" in warning and "not counted, outside their validity on the parent: panel -3.60 %" in warning
    methods["panel"]["outside_validity"] = None
    assert _confirmed(methods, "calm", 0) == (True, None)


def test_conditions_at_one_speed_share_their_strip_theory():
    """The rescoring's conditions (the profile, ±10 % speed, ±2 s T_p), laid out condition-major, grouped by speed
    and heading: the T_p shifts at the profile's speeds fall in the profile's groups (one strip-theory solve for
    the three), the speed factors each in their own."""
    from hullopt.study._rescore import CONDITIONS, _groups

    assert [c[0] for c in CONDITIONS] == [1.0, 0.9, 1.1, 1.0, 1.0]
    assert _groups(np.array([10.0, 12.0]), np.zeros(2)) == ((0, 6, 8), (1, 7, 9), (2,), (3,), (4,), (5,))
    assert _groups(np.array([10.0, 10.0]), np.array([0.0, 0.5])) == ((0, 6, 8), (1, 7, 9), (2,), (3,), (4,), (5,))
    assert len(_groups(np.array([10.0, 10.0]), np.zeros(2))) == 3  # two sea states at one speed: one group a speed


def test_calm_water_is_rescored_once_a_speed(monkeypatch):
    """Two sea states at one speed: calm water's R_T is computed at that speed once a speed factor (the
    conditions of ±2 s T_p take the profile's), not once a point or a condition, in one call; the profile's
    value is R_T there (the weights sum to one speed's)."""
    from hullopt.optimise import point_groups
    from hullopt.resistance import calm_water
    from hullopt.study import load_config, load_study
    from hullopt.study import _rescore

    prob = load_study(load_config(CONFIG)[0]).problem
    speeds = np.array([15.0, 15.0]) * KNOT
    seen = []
    monkeypatch.setattr(_rescore, "calm_water", lambda s, t, u, m: seen.append(u.shape) or calm_water(s, t, u, m))
    stacked = jax.tree.map(lambda a: np.asarray(a)[None], prob.p0)
    args = (prob.design.model, prob.p0, stacked, 6.25, speeds, np.array([1.0, 3.0]), np.array([3.0, 2.0]),
            np.array([9.0, 8.0]), np.zeros(2))
    values = _rescore._program(*args, False, ("holtrop",), _rescore._groups(speeds, np.zeros(2)),
                               point_groups(speeds, np.zeros(2)))
    assert seen == [(3, 1)]  # the speed factors 1, 0.9, 1.1 × the one speed
    s = prob.design.model(prob.p0)
    direct = [float(calm_water(s, 6.25, f * 15.0 * KNOT).total) for f in (1.0, 0.9, 1.1, 1.0, 1.0)]
    np.testing.assert_allclose(values["calm_holtrop"], [direct, direct], rtol=1e-12)


def test_a_wave_method_blind_to_the_mechanism_confirms_nothing_and_the_note_says_who_sees_it():
    """A Bf sweep's NMRI gain (C_U) is not judged by SNNM or STAWAVE-2, which cannot see it: the warning names
    them as not counted, and the note gives each method's span and why."""
    from hullopt.study._rescore import BLIND, _confirmed, mechanism_note

    def method(name, changes, own=False):
        return {"kind": "waves", "method": name, "own": own, "change_pct": changes, "worst_pct": changes,
                "holds": [c <= 0.1 for c in changes]}

    methods = {m["method"]: m for m in (method("nmri", [-20.6, 12.0], own=True), method("snnm", [-1.7, -0.9]),
                                        method("stawave2", [0.7, 0.4]))}
    note = mechanism_note(methods)
    assert "NMRI -20.6 … +12.0 %" in note and "SNNM -1.7 … -0.9 %" in note and "C_U" in note
    assert BLIND["snnm"] in note and BLIND["stawave2"] in note
    assert _confirmed(methods, "waves", 0)[0]  # SNNM's −1.7 % holds it, while it is counted
    held, warning = _confirmed(methods, "waves", 1)  # NMRI finds no gain (+12 %): only a loss would be said
    assert held and warning is None
    methods["snnm"]["change_pct"][1] = methods["snnm"]["worst_pct"][1] = 0.9
    methods["snnm"]["holds"][1] = False
    held, warning = _confirmed(methods, "waves", 1)
    assert not held and "no independent method finds its added resistance in waves at or below" in warning
    for m in ("snnm", "stawave2"):
        methods[m]["blind"] = BLIND[m]
    # no method can judge it: no verdict and no warning of its own (the note says why, once a run)
    assert _confirmed(methods, "waves", 0) == (None, None)
