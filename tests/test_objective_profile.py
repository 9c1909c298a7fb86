"""The operating-profile objectives: the weighted mean of calm-water R_T plus the sea-state mean R_AW over
speeds and sea states (and its effective power), against the methods called one point at a time; the config's
[[profile]] tables; the gradient against central differences."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import check_grad

from hullopt.constants import KNOT
from hullopt.geometry import Sections
from hullopt.models import wigley
from hullopt.resistance import calm_water
from hullopt.waves import mean_added_resistance

PROFILE = """kind = "minimise"
[hull]
parent = "wigley"
draft = 6.25
[[design.apex_move]]
segment = -1
x_fixed1 = 50.0
x_moved = 85.0
x_fixed2 = 100.0
[targets]
cb = 0.4442
[objective]
kind = "{kind}"
{extra}
[[profile]]
speed_kn = 12
weight = 2
[[profile]]
speed_kn = 15
hs = 3
tp = 9
[[profile]]
speed_kn = 18
hs = 2
tp = 8
heading_deg = 30
"""


def _load(tmp_path, kind="profile_resistance", extra="", edit=lambda text: text):
    from hullopt.study import load_config

    path = tmp_path / "p.toml"
    path.write_text(edit(PROFILE.format(kind=kind, extra=extra)))
    return load_config(path)[0]


@pytest.mark.parametrize("kind", ["profile_resistance", "profile_power"])
@pytest.mark.slow
def test_profile_is_the_weighted_sum_of_the_methods_point_by_point(tmp_path, kind):
    hull = wigley(100.0, 10.0, 6.25, 10.0, n=41, m=11)
    objective = _load(tmp_path, kind).objective.build()
    value = float(jax.jit(objective.__call__)(hull, 6.25))
    points = [(12.0, 2.0, None), (15.0, 1.0, (3.0, 9.0, 0.0)), (18.0, 1.0, (2.0, 8.0, 30.0))]
    total = 0.0
    for kn, w, sea in points:
        u = kn * KNOT
        r = float(calm_water(hull, 6.25, u, "holtrop").total)
        if sea is not None:
            r += float(jax.jit(lambda s, u=u, sea=sea: mean_added_resistance(
                "nmri", s, 6.25, u, sea[0], sea[1], np.radians(sea[2])).total)(hull))
        total += w * r * (u if kind == "profile_power" else 1.0)
    assert value == pytest.approx(total / 4.0, rel=1e-9)
    assert objective.unit == ("W" if kind == "profile_power" else "N")


@pytest.mark.slow
def test_profile_added_resistance_is_the_weighted_mean_of_r_aw(tmp_path):
    """Σ w R_AW / Σ w over points that each have a sea state, no calm water; a point without one is refused."""
    hull = wigley(100.0, 10.0, 6.25, 10.0, n=41, m=11)
    text = PROFILE.format(kind="profile_added_resistance", extra="").split("[[profile]]")
    path = tmp_path / "a.toml"
    path.write_text("[[profile]]".join([text[0]] + text[2:]))  # the calm-water point left out
    from hullopt.study import load_config

    objective = load_config(path)[0].objective.build()
    value = float(jax.jit(objective.__call__)(hull, 6.25))
    r = [float(jax.jit(lambda s, u=u, sea=sea: mean_added_resistance("nmri", s, 6.25, u * KNOT, *sea).total)(hull))
         for u, sea in ((15.0, (3.0, 9.0, 0.0)), (18.0, (2.0, 8.0, np.radians(30.0))))]
    assert value == pytest.approx(0.5 * (r[0] + r[1]), rel=1e-9)
    from hullopt.errors import HullError

    with pytest.raises((HullError, ValueError), match=r"profile\[0\]: hs = 0; profile_added_resistance needs"):
        _load(tmp_path, "profile_added_resistance").objective.build()


def test_profile_tables_in_the_config(tmp_path):
    from hullopt.errors import HullError
    from hullopt.study import load_config

    cfg = _load(tmp_path)
    assert [p.speed_kn for p in cfg.objective.profile] == [12.0, 15.0, 18.0]
    assert [p.weight for p in cfg.objective.profile] == [2.0, 1.0, 1.0]
    assert _load(tmp_path, extra='method = "michell"').objective.build().method == "michell"
    with pytest.raises(HullError, match="speed_kn: kind = 'profile_resistance' takes no 'speed_kn'"):
        _load(tmp_path, extra="speed_kn = 15")
    calm = tmp_path / "calm.toml"
    calm.write_text(PROFILE.format(kind="profile_resistance", extra="").replace("hs = 3\n", "").replace(
        "hs = 2\n", ""))
    assert not load_config(calm)[0].objective.build().waves  # no sea state: calm water only
    none = tmp_path / "none.toml"
    none.write_text(PROFILE.format(kind="k_aw", extra="").replace('kind = "k_aw"\n', "").replace("[objective]\n",
                                                                                                  ""))
    with pytest.raises(HullError, match="an operating profile needs an \\[objective\\]"):
        load_config(none)


@pytest.mark.slow
def test_profile_gradient_matches_differences(tmp_path):
    """d/dα of the profile for the Wigley whose beam scales by 1 + α (a design parameter's path), calm water and
    the reflection part (the motion part's: the test below)."""
    hull = wigley(100.0, 10.0, 6.25, 10.0, n=31, m=10)
    objective = _load(tmp_path, extra="motion = false").objective.build()
    f = jax.jit(lambda a: objective(Sections(hull.x, hull.yz * jnp.array([1.0 + a[0], 1.0]), hull.lpp), 6.25))
    check_grad(f, np.array([0.05]), rtol=1e-6)


@pytest.mark.slow
def test_head_sea_motion_part_gradient_matches_differences():
    """In head seas the sea-state mean with NMRI's motion part: d/dα (the beam × (1 + α)) by reverse-mode AD
    equals central differences. It was 0.25 % off: the strips interpolated between stations as (1 − f)·a + f·b
    moved the Wigley's waterline vertex (at the draft) by an ulp, differently in each kernel of the compiled
    program, so the forward and backward passes took different sides of it."""
    hull = wigley(100.0, 10.0, 6.25, 10.0, n=31, m=10)
    f = jax.jit(lambda a: mean_added_resistance("nmri", Sections(hull.x, hull.yz * jnp.array([1.0 + a[0], 1.0]),
                                                                  hull.lpp), 6.25, 15 * KNOT, 3.0, 9.0, 0.0).total)
    check_grad(f, np.array([0.05]), rtol=1e-4)


def test_points_at_one_speed_and_heading_share_what_those_alone_give():
    """An operating profile's points grouped by speed and heading (first appearance first); ``vmap_grouped``
    keeps a group's shared values unbatched, so what depends on them alone (here a sine; in a profile the strip
    theory) is computed once a group, not once a point — and every point gets its own value back in order."""
    from hullopt.optimise import point_groups, vmap_grouped

    speed, heading, hs = [12.0, 15.0, 12.0, 15.0, 18.0], [0.0, 0.0, 0.0, 0.5, 0.0], [1.0, 2.0, 3.0, 4.0, 5.0]
    groups = point_groups(speed, heading)
    assert groups == ((0, 2), (1,), (3,), (4,))

    def fn(u, a, h):
        return jnp.sin(u) * jnp.cos(a) + h

    args = (jnp.asarray(speed), jnp.asarray(heading)), (jnp.asarray(hs),)
    np.testing.assert_array_equal(vmap_grouped(fn, groups, *args), fn(*args[0], *args[1]))
    sines = [e for e in jax.make_jaxpr(lambda *a: vmap_grouped(fn, groups, a[:2], a[2:]))(*args[0], *args[1]).eqns
             if e.primitive.name == "sin"]
    assert [e.outvars[0].aval.shape for e in sines] == [(4,)]  # once a group; (4, 2) would be once a slot


def _two_seas_a_speed(tmp_path, kind):
    """The profile of ``kind`` with two sea states at 18 kn (a group) and 15 kn alone, motion part off."""
    cfg = _load(tmp_path, kind, "motion = false", lambda text: text.replace(
        "speed_kn = 12\nweight = 2\n", "speed_kn = 18\nweight = 2\nhs = 4\ntp = 11\nheading_deg = 30\n"))
    grouped = cfg.objective.build()
    assert grouped.groups == ((0, 2), (1,))
    return grouped


def test_a_profile_with_two_sea_states_a_speed_equals_its_points_alone(tmp_path):
    """Two sea states at one speed (a group) and a speed alone: the grouped profile equals the same profile
    evaluated point by point (``groups=None``) to rounding, and sees each point's own sea state."""
    import dataclasses

    hull, grouped = wigley(100.0, 10.0, 6.25, 10.0, n=31, m=10), _two_seas_a_speed(tmp_path, "profile_added_resistance")
    alone = dataclasses.replace(grouped, groups=None)
    value, point_by_point = (float(jax.jit(o.__call__)(hull, 6.25)) for o in (grouped, alone))
    assert value == pytest.approx(point_by_point, rel=1e-13)
    swapped = dataclasses.replace(grouped, hs=np.asarray(grouped.hs)[[2, 1, 0]], tp=np.asarray(grouped.tp)[[2, 1, 0]],
                                  weights=np.asarray(grouped.weights)[[2, 1, 0]])
    assert float(jax.jit(swapped.__call__)(hull, 6.25)) == pytest.approx(value, rel=1e-13)


def test_a_profile_computes_calm_water_once_a_speed(tmp_path, monkeypatch):
    """A profile with calm water and two sea states at one speed: R_T is computed at each group's speed (two
    speeds, not three: the panel methods' cost is per speed) and the profile equals its points alone."""
    import dataclasses

    from hullopt.optimise import _objectives

    hull, grouped = wigley(100.0, 10.0, 6.25, 10.0, n=31, m=10), _two_seas_a_speed(tmp_path, "profile_resistance")
    speeds = []
    monkeypatch.setattr(_objectives, "calm_water", lambda s, t, u, m: speeds.append(u.shape) or calm_water(s, t, u, m))
    alone = dataclasses.replace(grouped, groups=None)
    value, point_by_point = (float(jax.jit(o.__call__)(hull, 6.25)) for o in (grouped, alone))
    assert speeds == [(2,), (3,)]
    assert value == pytest.approx(point_by_point, rel=1e-13)
    r_t = calm_water(hull, 6.25, np.array([18.0, 15.0]) * KNOT).total
    no_waves = dataclasses.replace(grouped, waves=False)
    assert float(no_waves(hull, 6.25)) == pytest.approx(float(r_t @ np.array([3.0, 1.0])) / 4.0, rel=1e-12)


def test_conditions_captions_say_where_an_objective_is_measured():
    """The Pareto plot's caption: the shipped configs' profiles, a speed list, one speed in one sea."""
    from conftest import REPO
    from hullopt.study import conditions_text
    from hullopt.study._config import load_config

    cfg, _ = load_config(REPO / "configs/pareto_bow.toml")
    assert conditions_text(cfg.objective) == "22, 24, 26 kn, weighted"
    assert conditions_text(cfg.sweep.measure) == "22, 24, 26 kn × (Hs 2.5 m/Tp 8 s, Hs 4 m/Tp 10 s), weighted"
    cfg, _ = load_config(REPO / "tests/data/pareto_wigley.toml")
    assert conditions_text(cfg.objective) == "15 kn" and conditions_text(cfg.sweep.measure) == "15 kn, Hs 3 m/Tp 9 s"
