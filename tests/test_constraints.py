"""Design runs that hold up: ``[constraints]`` parsed strictly, the augmented Lagrangian's inequalities against a
problem solved by hand (KKT), the section limits against offsets worked out by hand, and a small run whose
constraints hold, with the report's ``objectives`` and ``warnings`` and the parent's offsets in the folder."""

import tomllib
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.study import DEFAULT_LIMITS, FAIRNESS, RunConfig, parse_bound

CONFIGS = Path(__file__).resolve().parents[1] / "configs"


@pytest.mark.parametrize("text, expected", [
    ("<= parent", (1, 1.0, True, 0.0)),
    (">= 0.98 * parent", (-1, 0.98, True, 0.0)),
    ("<=1.2e5", (1, 1.2e5, False, 0.0)),
    (" >= -3 ", (-1, -3.0, False, 0.0)),
])
def test_bounds_parse(text, expected):
    assert parse_bound("x", text) == expected


@pytest.mark.parametrize("text", ["< parent", "parent", "<= 2 parents", "<= ", 5.0, "<= 1..2"])
def test_bad_bounds_name_the_constraint(text):
    with pytest.raises(ValueError, match=r"constraints\.calm_resistance = .*expected '<= parent'"):
        parse_bound("calm_resistance", text)


ONE_CONDITION = Path(__file__).resolve().parent / "data" / "rescore_wigley.toml"  # a single-condition minimise run


@pytest.mark.parametrize("value, expected", [
    (">= 0.98 * parent", ((-1, 0.98, True, 0.0),)),
    ([">= 0.95 * parent", "<= 1.05 * parent"], ((-1, 0.95, True, 0.0), (1, 1.05, True, 0.0))),
    (["<= 1.05 * parent", ">= parent - 0.5"], ((-1, 1.0, True, -0.5), (1, 1.05, True, 0.0))),  # lower first
    ([">= 19.0", "<= 21"], ((-1, 19.0, False, 0.0), (1, 21.0, False, 0.0))),
])
def test_two_sided_bounds_parse(value, expected):
    from hullopt.study import parse_bounds

    assert parse_bounds("bwl", value) == expected


@pytest.mark.parametrize("value, message", [
    ([">= 0.95 * parent"], r"constraints.bwl = \['>= 0.95 \* parent'\]: a two-sided bound is a list of two"),
    ([">= 0.9 * parent", "<= parent", "<= 2"], "constraints.bwl = .*: a two-sided bound is a list of two"),
    ([">= 0.95 * parent", 1.05], "constraints.bwl = .*: a two-sided bound is a list of two bound strings"),
    ([">= 0.95 * parent", ">= 19"], r"constraints.bwl = .*: both bounds are '>='; a two-sided bound takes one"),
    ([">= 0.95 * parent", "<= 1.05 * parents"], r"constraints.bwl\[1\] = '<= 1.05 \* parents': expected"),
    ([">= 21", "<= 19"], "constraints.bwl = .*: no value is both >= 21 and <= 19"),
])
def test_bad_two_sided_bounds_name_the_constraint(value, message):
    from hullopt.study import parse_bounds

    with pytest.raises(ValueError, match=message):
        parse_bounds("bwl", value)


def _raw(**constraints) -> dict:
    raw = tomllib.loads(ONE_CONDITION.read_text())
    raw["constraints"] = constraints
    return raw


@pytest.mark.parametrize("constraints, message", [
    ({"drag": "<= parent"}, "constraints.drag: unknown measure (expected one of k_aw"),
    ({"calm_resistance": "less than parent"}, "constraints.calm_resistance = 'less than parent': expected"),
    ({"max_half_breadth": -1.0}, "constraints.max_half_breadth = -1.0: expected a positive half-breadth"),
    ({"bulge": "sometimes"}, "constraints.bulge"),
    ({"tolerance": 0.5}, "constraints.tolerance"),
    ({"bwl": [">= 0.95 * parent", ">= 0.9 * parent"]}, "constraints.bwl = ['>= 0.95 * parent', '>= 0.9 * parent']: "
                                                        "both bounds are '>='"),
    ({"cb": [">= 0.5"]}, "constraints.cb = ['>= 0.5']: a two-sided bound is a list of two bound strings"),
])
def test_bad_constraints_fail_with_the_field(constraints, message):
    with pytest.raises(ValueError, match="1 validation error") as e:
        RunConfig.model_validate(_raw(**constraints))
    assert message in str(e.value)


@pytest.mark.parametrize("override, key, kind, owners", [
    ('objective.kind="k_aw"', "hs", "k_aw", "mean_added_resistance"),
    ('objective.kind="calm_resistance"', "hs", "calm_resistance", "mean_added_resistance"),
    ('objective.method="panel"', "method", "mean_added_resistance",
     "calm_resistance, calm_resistance_michell, calm_resistance_dawson, profile_resistance, profile_power"),
    ("objective.wind_speed=10", "wind_speed", "mean_added_resistance", "wind_added_resistance"),
])
def test_an_option_of_another_objective_kind_is_an_error_naming_the_kind(override, key, kind, owners):
    """One options model per objective kind: an option another kind owns is refused as a one-line config error
    naming the kind given and the kinds that take it (it used to validate and be silently ignored)."""
    from hullopt.errors import HullError
    from hullopt.study import load_config

    with pytest.raises(HullError, match=rf"rescore_wigley.toml: objective: {key}: kind = '{kind}' takes no "
                                        rf"'{key}' \(it is an option of {owners}\)"):
        load_config(ONE_CONDITION, [override])


def test_objective_constraints_take_the_objectives_options():
    cfg = RunConfig.model_validate(_raw(calm_resistance="<= parent", wetted_surface="<= 1.01 * parent"))
    own = {k: v for k, v in cfg.constraints.bounds().items() if k not in DEFAULT_LIMITS}
    assert own == {"calm_resistance": ((1, 1.0, True, 0.0),), "wetted_surface": ((1, 1.01, True, 0.0),)}
    assert cfg.constraint_options("calm_resistance").speed_kn == cfg.objective.speed_kn
    raw = _raw(mean_added_resistance="<= parent")
    raw["objective"] = {"kind": "calm_resistance", "speed_kn": 15.0}  # no sea state for the constraint
    with pytest.raises(ValueError, match="constraints.mean_added_resistance: .*hs"):
        RunConfig.model_validate(raw)
    raw = _raw(cwp=">= parent")
    raw.update(kind="fit", objective=None)
    with pytest.raises(ValueError, match="a fit holds targets only"):
        RunConfig.model_validate({k: v for k, v in raw.items() if v is not None})
    from hullopt.study import Fit, Minimise, Pareto, load_study

    assert Minimise.fairness == Pareto.fairness == FAIRNESS > 0 and Fit.fairness == 0  # on, but for fits
    fit = {"kind": "fit", "hull": {"parent": "wigley"}, "targets": {"cb": 0.45},
           "design": {"distribution": [{"x_a": 0.0, "x_b": 100.0}]}}
    assert load_study(RunConfig.model_validate(fit)).problem.design.fairness == 0
    fit["solver"] = {"fairness": 0.2}
    assert load_study(RunConfig.model_validate(fit)).problem.design.fairness == 0.2


def test_inequalities_meet_the_kkt_point_by_hand():
    """min (x − 2)² + (y − 1)² with x + y = 2.5, x ≤ 1.2, y ≥ 0: on the line the free minimum is (1.75, 0.75),
    beyond x ≤ 1.2, so x = 1.2, y = 1.3 and f = 0.8² + 0.3² = 0.73 (the multiplier of x ≤ 1.2 is 1.0 > 0)."""
    from hullopt.optimise import minimise_constrained

    def solve():
        return minimise_constrained(lambda p, a: (p[0] - 2.0) ** 2 + (p[1] - 1.0) ** 2,
                                    lambda p, a: jnp.array([p[0] + p[1] - 2.5]),
                                    jnp.zeros(2), -5.0 * jnp.ones(2), 5.0 * jnp.ones(2), tol=1e-6,
                                    inequalities=lambda p, a: jnp.array([p[0] - 1.2, -p[1]]),
                                    inequality_tol=1e-6, outer=6, max_steps=100)

    r = jax.jit(solve)()
    assert np.allclose(r.params, [1.2, 1.3], atol=2e-8) and bool(r.met)
    assert float(r.objective) == pytest.approx(0.73, abs=1e-7)


def test_section_limits_by_hand():
    """Two stations of three offsets at draft 2: a plain section (wider at the waterline) and one that bulges
    0.5 m beyond its 1 m waterline half-breadth at z = 1; the parent's own bulge is allowed, a new one is not."""
    from hullopt.geometry import Sections
    from hullopt.optimise import Limits

    plain = [[0.0, 0.0], [1.0, 1.0], [2.0, 2.0], [2.0, 3.0]]
    bulb = [[0.0, 0.0], [1.5, 1.0], [1.0, 2.0], [1.0, 3.0]]
    parent = Sections(jnp.array([0.0, 10.0]), jnp.array([plain, plain]), 10.0)
    design = Sections(jnp.array([0.0, 10.0]), jnp.array([plain, bulb]), 10.0)
    lim = Limits(max_half_breadth=np.asarray(np.nan)).at_parent(parent, 2.0)
    g = lim.groups(design, 2.0)
    assert float(lim.max_half_breadth) == 2.0 and float(lim.y_ref) == 2.0
    assert float(jnp.max(g["max_half_breadth"])) == 0.0  # the parent's half-breadth: on the bound
    assert float(jnp.max(g["bulge"])) == pytest.approx((1.5 - 1.0) / 2.0)  # 0.5 m of new bulge / y_ref
    allowed = Limits().at_parent(design, 2.0).groups(design, 2.0)["bulge"]  # the parent's bulge is allowed
    assert float(jnp.max(allowed)) <= 0.0


def _ribbed(a):
    """Eleven rectangular sections (depth 3 m, x 0…10 m) of half-breadth 1 + a·sin(πx/5) [m]: at draft 2 m
    the sectional area is A = 4(1 + a·w) m², so A'' (second differences, h = 1 m) is 4a·Δ²w."""
    from hullopt.geometry import Sections

    x = jnp.linspace(0.0, 10.0, 11)
    b = 1.0 + a * jnp.sin(jnp.pi * x / 5.0)
    yz = jnp.stack([jnp.stack([jnp.zeros_like(b), jnp.zeros_like(b)], -1), jnp.stack([b, jnp.zeros_like(b)], -1),
                    jnp.stack([b, jnp.full_like(b, 3.0)], -1)], axis=1)
    return Sections(x, yz, 10.0)


def test_roughness_constraints_are_parsed_and_reach_the_limits():
    from hullopt import fairing
    from hullopt.study import limits_from

    cfg = RunConfig.model_validate(_raw(sac_roughness="<= 2 * parent", section_roughness="<= 2 * parent",
                                        unfairness="<= 1.5 * parent"))
    assert cfg.constraints.bounds()["sac_roughness"] == ((1, 2.0, True, 0.0),)
    lim = limits_from(cfg)
    named = dict(zip(lim.names, lim.measures))
    assert {"sac_roughness", "section_roughness", "unfairness"} <= set(named)
    assert (named["sac_roughness"], named["section_roughness"]) == (fairing.sac_roughness, fairing.section_roughness)
    per_station = limits_from(RunConfig.model_validate(_raw(station_knuckles="<= 3 * parent")))
    k = per_station.names.index("station_knuckles")
    assert per_station.measures[k] == fairing.station_knuckles and float(per_station.values[k]) == 3.0
    shipped = RunConfig.model_validate(tomllib.loads((CONFIGS / "min_added_resistance.toml").read_text()))
    assert set(DEFAULT_LIMITS) | {"calm_resistance_dawson", "volume"} <= set(shipped.constraints.bounds())


def test_sac_roughness_by_hand_and_against_the_report():
    """Σ (A'')² Δx of the ribbed hull against the second differences of 4a·sin(πx/5) written out, and the
    report's numpy measure on the same hull."""
    from helpers import np_sac_roughness
    from hullopt.fairing import sac_roughness
    from hullopt.hydro import sectional_areas

    s = _ribbed(0.3)
    w = np.sin(np.pi * np.arange(11) / 5.0)
    by_hand = np.sum((4 * 0.3 * (w[2:] - 2 * w[1:-1] + w[:-2])) ** 2)
    assert float(sac_roughness(s, 2.0)) == pytest.approx(by_hand, rel=1e-12)
    assert float(sac_roughness(s, 2.0)) == pytest.approx(np_sac_roughness(s.x, sectional_areas(s, 2.0)), rel=1e-12)


def test_section_roughness_zero_on_arcs_positive_at_a_knuckle_and_as_the_report():
    """Circular-arc half-sections have equal turns over equal chords (Δκ = 0); a knuckle is rough; with
    centreline and repeated points the JAX measure equals the report's numpy one (which drops them), and its
    gradient is finite there."""
    from helpers import np_section_roughness
    from hullopt.fairing import section_roughness
    from hullopt.geometry import Sections

    t = np.linspace(-np.pi / 2, 0.0, 9)
    arc = np.stack([3.0 * np.cos(t), 3.0 + 3.0 * np.sin(t)], -1)
    arc[0, 0] = 0.0  # the keel on the centreline
    arcs = Sections(jnp.array([0.0, 5.0]), jnp.array([arc, arc]), 5.0)
    assert abs(float(jax.jit(section_roughness)(arcs))) < 1e-24
    knuckle = arc.copy()
    knuckle[5:, 0] = knuckle[5, 0]  # straight-sided above the fifth point
    odd = np.insert(knuckle, 3, knuckle[3], axis=0)[:-1]  # a repeated point, the same count of offsets
    odd = np.concatenate([[[0.0, 0.0]], odd[:-1]])  # and a second centreline point
    rough = Sections(jnp.array([0.0, 5.0]), jnp.array([knuckle, odd]), 5.0)
    value = float(jax.jit(section_roughness)(rough))
    assert value > 1e-3 and value == pytest.approx(np_section_roughness(rough.yz), rel=1e-12)
    g = jax.jit(jax.grad(lambda yz: section_roughness(Sections(rough.x, yz, 5.0))))(rough.yz)
    assert bool(jnp.all(jnp.isfinite(g)))


def test_section_measures_ignore_a_sub_millimetre_stub():
    """Feature points that coincide at the parent drift apart under a deformation; a stub of 0.5 mm turning
    any way is one point to the section measures (it multiplied the KCS's roughness 1e8-fold), not a knuckle."""
    from helpers import np_section_roughness
    from hullopt.fairing import MERGE, section_knuckle, section_roughness
    from hullopt.geometry import Sections

    t = np.linspace(-np.pi / 2, 0.0, 12)
    clean = np.stack([3.0 * np.cos(t) + 0.5, 3.0 + 3.0 * np.sin(t)], -1)
    clean[4:, 0] += 0.1 * (clean[4:, 1] - clean[4, 1])  # a mild knuckle: the measures are not zero
    stub = np.insert(clean, 7, clean[6] + 0.5 * MERGE * np.array([-0.6, 0.8]), axis=0)
    s_stub, s_clean = (Sections(jnp.zeros(1), jnp.asarray(p)[None], 5.0) for p in (stub, clean))
    for measure in (section_roughness, section_knuckle):
        assert float(measure(s_stub)) == pytest.approx(float(measure(s_clean)), rel=1e-2)
    assert np_section_roughness(stub[None]) == pytest.approx(np_section_roughness(clean[None]), rel=1e-2)
    assert float(section_roughness(s_clean)) > 1e-3


def test_section_knuckle_by_hand_and_its_gradient():
    """Σ θ⁴ of the turning angles, by hand: an arc of equal 11.25° turns gives 6·(π/16)⁴ (its keel point on the
    centreline left out, a repeated point too; finite gradient there), a section straight up to a 20° knuckle
    and then vertical (the optimiser's knuckle of issue 16) gives (20°)⁴; the gradient matches central
    differences."""
    from hullopt.fairing import section_knuckle
    from hullopt.geometry import Sections
    from tests.helpers import check_grad

    t = np.linspace(-np.pi / 2, 0.0, 9)
    arc = np.stack([3.0 * np.cos(t), 3.0 + 3.0 * np.sin(t)], -1)
    arc[0, 0] = 0.0
    arc = np.concatenate([[[0.0, 0.0]], arc, arc[-1:]])  # a second centreline point and a repeated one
    slope = np.deg2rad(20.0)  # the side 20° off the vertical, then vertical
    z = np.linspace(0.0, 6.0, 10)
    knuckle = np.concatenate([np.stack([z * np.tan(slope) + 0.1, z], -1), [[6.0 * np.tan(slope) + 0.1, 10.0]]])
    s = Sections(jnp.array([0.0, 5.0]), jnp.array([arc, knuckle]), 5.0)
    expected = 0.5 * (6 * (np.pi / 16) ** 4 + slope**4)  # the keel point is on the centreline: 6 turns kept
    assert float(jax.jit(section_knuckle)(s)) == pytest.approx(expected, rel=1e-10)
    grad = jax.jit(jax.grad(lambda yz: section_knuckle(Sections(s.x, yz, 5.0))))(s.yz)
    assert bool(jnp.all(jnp.isfinite(grad)))  # at the left-out points too
    one = jax.jit(lambda yz: section_knuckle(Sections(jnp.zeros(1), yz[None], 5.0)))
    check_grad(one, knuckle, rtol=1e-6)  # the knuckled section (no point left out)


def test_station_knuckles_hold_each_station_to_the_parents():
    """A parent with one sharp turn (70°, a skeg's) and a fair station; the design adds a 25° knuckle to the
    fair one. The mean over stations barely moves (under 2x, as on the KCS), the station bound sees it at
    that station only; stations flatter than the floor (one 5° turn) count as the floor."""
    from hullopt.fairing import KNUCKLE_FLOOR, section_knuckle, station_knuckles
    from hullopt.geometry import Sections
    from hullopt.optimise import Limits

    z = np.linspace(0.0, 6.0, 13)
    fair = np.stack([2.0 + 0.02 * z, z], -1)  # straight: no turn at all
    skeg = fair.copy()
    skeg[7:, 0] = skeg[6, 0] + (z[7:] - z[6]) * np.tan(np.deg2rad(70.0))  # one 70° turn at z = 3 m
    knuckled = fair.copy()
    knuckled[7:, 0] = knuckled[6, 0] + (z[7:] - z[6]) * np.tan(np.deg2rad(25.0))
    x = jnp.array([0.0, 5.0])
    parent, design = (Sections(x, jnp.array([skeg, s]), 6.0) for s in (fair, knuckled))
    assert float(section_knuckle(design)) < 2.0 * float(section_knuckle(parent))  # blind to it
    turn = np.deg2rad(70.0) - np.arctan(0.02)  # from the side's slope to 70° off the vertical
    np.testing.assert_allclose(station_knuckles(parent), [turn**4, KNUCKLE_FLOOR], rtol=1e-12)
    lim = Limits(names=("station_knuckles",), measures=(station_knuckles,), sense=np.array([1.0]),
                 values=np.array([2.0]), relative=(True,), max_half_breadth=None, bulge=False).at_parent(parent, 6.0)
    g = np.asarray(lim.groups(design, 6.0)["station_knuckles"])
    assert g[0] == pytest.approx(-0.5) and g[1] > 10.0  # the skeg as the parent's; the new knuckle, far over
    assert np.all(np.asarray(lim.groups(parent, 6.0)["station_knuckles"]) == pytest.approx(-0.5))


def test_sac_roughness_constraint_binds_in_the_solver():
    """min (a − 1)² with the SAC no rougher than twice the parent's (a₀ = 0.5): roughness ∝ a², so the
    bound is a² ≤ 2·0.25, the solution a = 1/√2 on it (the free minimum a = 1 is twice as rough again)."""
    from hullopt.fairing import sac_roughness
    from hullopt.optimise import Limits, minimise_constrained

    lim = Limits(names=("sac_roughness",), measures=(sac_roughness,), sense=np.ones(1), values=np.full(1, 2.0),
                 relative=(True,), max_half_breadth=None, bulge=False).at_parent(_ribbed(0.5), 2.0)

    def solve():
        return minimise_constrained(lambda p, a: (p[0] - 1.0) ** 2, lambda p, a: jnp.zeros(1), jnp.array([0.5]),
                                    jnp.zeros(1), 2.0 * jnp.ones(1), tol=1e-6,
                                    inequalities=lambda p, a: lim(_ribbed(p[0]), 2.0),
                                    inequality_tol=1e-6, outer=8, max_steps=100)

    r = jax.jit(solve)()
    assert bool(r.met) and float(r.params[0]) == pytest.approx(2**-0.5, abs=1e-6)
    assert float(lim.groups(_ribbed(r.params[0]), 2.0)["sac_roughness"]) == pytest.approx(0.0, abs=1e-6)


@pytest.mark.parametrize("curves, hinted", [("all", True), ("stations", False)])
def test_the_roughness_warning_names_a_distribution_that_blends_frames(curves, hinted):
    """The DTC's segments change in number between stations (its bulb, its stern): a distribution that re-reads
    frames there blends frames of different make-up into new shapes (the KCS fit of configs/fit_own_hull.toml
    had sections 26600x rougher); the roughness warning then says to move the frames instead."""
    from hullopt.study import load_study
    from hullopt.study._assess import blend_hint

    raw = {"kind": "fit", "hull": {"parent": "dtc"}, "targets": {"cb": 0.66},
           "design": {"distribution": [{"x_a": 150.0, "x_b": 340.0, "curves": curves}]}}
    cfg = RunConfig.model_validate(raw)
    hint = blend_hint(cfg, load_study(cfg).problem)
    assert ('curves = "stations"' in hint and "design.distribution[0]" in hint) == hinted
    assert bool(hint) == hinted


def test_waterline_angles_of_a_wigley_by_the_closed_form():
    """Half-angles of entrance and run at six heights up to the DWL: on a Wigley y = B/2 (1 − ξ²)(1 − ζ²) the
    chord from the end to the next station (ξ = 0.95) is atan(B/2 · 0.0975 · (1 − ζ²) / Δx), the same at both
    ends; a blunter bow raises the entrance only; the gradient is finite and matches differences."""
    from helpers import check_grad

    from hullopt.fairing import WATERLINE_FRACTIONS, entrance_angle, run_angle, waterline_angles
    from hullopt.geometry import Sections
    from hullopt.models import wigley

    s = wigley(100.0, 10.0, 6.25, 6.25, n=41, m=25)  # the heights k/6 · T lie on section points
    zeta = 1.0 - np.asarray(WATERLINE_FRACTIONS)
    expected = np.arctan(5.0 * 0.0975 * (1.0 - zeta**2) / 2.5)
    got = np.asarray(jax.jit(waterline_angles)(s, 6.25))
    np.testing.assert_allclose(got, [expected, expected], rtol=1e-12)
    assert float(entrance_angle(s, 6.25)) == pytest.approx(expected[-1], rel=1e-12)  # iE, at the DWL
    blunt = Sections(s.x, s.yz.at[-2, :, 0].multiply(1.5), s.lpp)
    assert float(entrance_angle(blunt, 6.25)) > float(entrance_angle(s, 6.25))
    assert float(run_angle(blunt, 6.25)) == pytest.approx(float(run_angle(s, 6.25)), rel=1e-12)
    check_grad(jax.jit(lambda a: entrance_angle(Sections(s.x, s.yz * jnp.array([1.0 + a[0], 1.0]), s.lpp), 6.25)),
               np.array([0.1]), rtol=1e-6)


def test_waterlines_of_two_wigleys_by_the_closed_form():
    """The overlay's waterlines: heights k/6 of the draft above the lower keel of the two hulls, each hull's
    half-breadths there y = B/2 (1 − ξ²)(1 − ζ²) (ζ = (z − its own Wigley draft)/T; wall-sided above that
    draft; 0 below its keel)."""
    from hullopt.fairing import WATERLINE_FRACTIONS, waterlines
    from hullopt.geometry import Sections
    from hullopt.models import wigley

    a = wigley(100.0, 10.0, 6.25, 10.0, n=41, m=201)
    b = wigley(100.0, 12.0, 6.25, 10.0, n=41, m=201)
    b = Sections(b.x, b.yz.at[..., 1].add(-1.0), b.lpp)  # 1 m lower: keel at z = −1 m, wall-sided above 5.25 m
    z, (ya, yb) = jax.jit(waterlines)([a, b], 6.25)
    np.testing.assert_allclose(z, -1.0 + 7.25 * np.asarray(WATERLINE_FRACTIONS), rtol=1e-14)
    xi = (2.0 * np.asarray(a.x) / 100.0 - 1.0)[:, None]
    z = np.asarray(z)

    def want(half, zeta):
        return half * (1.0 - xi**2) * np.where(zeta < -1.0, 0.0, 1.0 - np.minimum(zeta, 0.0) ** 2)

    np.testing.assert_allclose(ya, want(5.0, (z - 6.25) / 6.25), atol=1e-3)
    np.testing.assert_allclose(yb, want(6.0, (z - 5.25) / 6.25), atol=1e-3)
    # two more above the DWL, a third and two thirds of the way to the lower deck (b's, at 9 m): wall-sided there
    z2, (ya2, yb2) = jax.jit(waterlines, static_argnums=2)([a, b], 6.25, 2)
    np.testing.assert_allclose(z2, [*z, 6.25 + 2.75 / 3, 6.25 + 5.5 / 3], rtol=1e-14)
    np.testing.assert_allclose(ya2[:, 6:], np.broadcast_to(want(5.0, 0.0), (41, 2)), atol=1e-3)
    np.testing.assert_allclose(yb2[:, 6:], np.broadcast_to(want(6.0, 0.0), (41, 2)), atol=1e-3)


def test_sac_regions_add_up_and_place_a_shoulder():
    """Σ (A'')² Δx per region adds up to the whole curve's; a fuller fore shoulder shows in its region."""
    from hullopt.fairing import sac_regions, sac_roughness
    from hullopt.geometry import Sections
    from hullopt.models import wigley

    s = wigley(100.0, 10.0, 6.25, 10.0, n=41, m=21)
    r = np.asarray(sac_regions(s, 6.25))
    assert r.sum() == pytest.approx(float(sac_roughness(s, 6.25)), rel=1e-12)
    fuller = Sections(s.x, s.yz.at[26, :, 0].multiply(1.2), s.lpp)  # x = 65 m: the fore shoulder
    d = np.asarray(sac_regions(fuller, 6.25)) - r
    assert d[2] > 10 * max(abs(d[0]), abs(d[1]), abs(d[3]))


def test_local_shape_measures_are_constraints():
    from hullopt import fairing
    from hullopt.study import limits_from

    cfg = RunConfig.model_validate(_raw(waterline_angles="<= 1.1 * parent", sac_regions="<= 3 * parent"))
    lim = limits_from(cfg)
    named = {k: (m, float(v)) for k, m, v in zip(lim.names, lim.measures, lim.values)}
    assert named["waterline_angles"] == (fairing.waterline_angles, 1.1)
    assert named["sac_regions"] == (fairing.sac_regions, 3.0)


def test_a_two_sided_bound_holds_both_sides_in_the_limits_and_the_report():
    """``bwl = [">= 0.95 * parent", "<= 1.05 * parent"]``: two entries of one name in the limits, the measure
    measured once and its group both sides' g (the worse side is the one a report and its warnings show), both
    sides in the bound the report writes (its table too); a default limit may be given both sides."""
    from hullopt.geometry import Sections
    from hullopt.models import box
    from hullopt.report._html import limits_table
    from hullopt.study import limits_from

    cfg = RunConfig.model_validate(_raw(bwl=[">= 0.95 * parent", "<= 1.05 * parent"],
                                        kmt=[">= parent - 0.05", "<= parent + 1"]))
    written = cfg.constraints.written()
    assert written["bwl"] == ">= 0.95 * parent and <= 1.05 * parent"
    assert written["kmt"] == ">= parent - 0.05 and <= parent + 1"
    lim = limits_from(cfg)
    k = [i for i, n in enumerate(lim.names) if n == "bwl"]
    assert len(k) == 2 and lim.measures[k[0]] is lim.measures[k[1]]
    np.testing.assert_array_equal(np.asarray(lim.sense)[k], [-1.0, 1.0])
    np.testing.assert_array_equal(np.asarray(lim.values)[k], [0.95, 1.05])
    bwl = type(lim)(names=("bwl", "bwl"), measures=tuple(lim.measures[i] for i in k), sense=np.asarray(lim.sense)[k],
                    values=np.asarray(lim.values)[k], relative=(True, True), max_half_breadth=None, bulge=False)
    parent = box(100.0, 10.0, 8.0)
    bwl = bwl.at_parent(parent, 5.0)
    for scale, g in ((1.0, (-0.05 / 0.95, -0.05 / 1.05)), (1.1, (-0.15 / 0.95, 0.05 / 1.05)),
                     (0.9, (0.05 / 0.95, -0.15 / 1.05))):
        design = Sections(parent.x, parent.yz * jnp.array([scale, 1.0]), parent.lpp)
        np.testing.assert_allclose(bwl.groups(design, 5.0)["bwl"], g, rtol=1e-12)
    report = {"limits": {"bwl": {"parent": -0.0476, "design": 0.0, "bound": written["bwl"], "tolerance": 1e-3}}}
    assert ">= 0.95 * parent and <= 1.05 * parent" in limits_table(report).replace("&gt;", ">").replace("&lt;", "<")
