"""The shipped L2-Sea benchmark config (configs/l2sea_5415.toml, issue [W4 2/6] item 5) poses the NATO AVT-331
problem as published: the DTMB 5415 model (Lpp 5.720 m, T 0.248 m, ∇ held), calm-water R_T by Dawson's
method at Fr 0.28, beam and draft each within ±5 %, ∇ held, the sonar dome's volume not below the parent's; and a
calm-water run's re-scoring, which has no added-resistance method, draws no fronts (it crashed the run)."""

from pathlib import Path

import numpy as np
import pytest

from hullopt.constants import KNOT, G

CONFIG = Path(__file__).resolve().parents[1] / "configs" / "l2sea_5415.toml"


def test_the_config_poses_the_benchmark():
    from hullopt.study import load_config

    cfg, _ = load_config(CONFIG)
    assert cfg.kind == "minimise"
    assert cfg.hull.draft == pytest.approx(0.248)
    assert cfg.objective.kind == "calm_resistance" and cfg.objective.method == "dawson"
    assert cfg.objective.speed_kn * KNOT / np.sqrt(G * 5.72) == pytest.approx(0.28, abs=5e-5)
    assert cfg.design.beam.bound == 0.05 and cfg.design.draft.bound == 0.05
    assert cfg.constraints.held()["volume"] == [">= parent", "<= parent"]  # ∇ held on the run's own parent
    dome = cfg.constraints.regions()["region_volume:sonar_dome"]
    assert dome.bound == ">= parent" and dome.z_top == 0.0
    held = cfg.constraints.held()
    assert {"sac_regions", "section_roughness", "waterline_angles", "kmt"} <= set(held)  # local limits on


def test_a_calm_water_rescoring_has_no_front_to_draw():
    from hullopt.app.run import has_fronts

    calm = {"calm_holtrop": {"kind": "calm"}, "calm_dawson": {"kind": "calm"}}
    assert not has_fronts({"methods": calm})
    assert has_fronts({"methods": calm | {"waves_nmri": {"kind": "waves"}}})
