"""Design runs that hold up: ``[constraints]`` parsed strictly, the augmented Lagrangian's inequalities against a
problem solved by hand (KKT), the section limits against offsets worked out by hand, and a small run whose
constraints hold, with the report's ``objectives`` and ``warnings`` and the parent's offsets in the folder."""

import json
import tomllib
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.app.config import FAIRNESS, RunConfig, SolverConfig, parse_bound

CONFIGS = Path(__file__).resolve().parents[1] / "configs"


@pytest.mark.parametrize("text, expected", [
    ("<= parent", (1, 1.0, True)),
    (">= 0.98 * parent", (-1, 0.98, True)),
    ("<=1.2e5", (1, 1.2e5, False)),
    (" >= -3 ", (-1, -3.0, False)),
])
def test_bounds_parse(text, expected):
    assert parse_bound("x", text) == expected


@pytest.mark.parametrize("text", ["< parent", "parent", "<= 2 parents", "<= ", 5.0, "<= 1..2"])
def test_bad_bounds_name_the_constraint(text):
    with pytest.raises(ValueError, match=r"constraints\.calm_resistance = .*expected '<= parent'"):
        parse_bound("calm_resistance", text)


def _raw(**constraints) -> dict:
    raw = tomllib.loads((CONFIGS / "min_added_resistance.toml").read_text())
    raw["constraints"] = constraints
    return raw


@pytest.mark.parametrize("constraints, message", [
    ({"drag": "<= parent"}, "constraints.drag: unknown measure; expected one of k_aw"),
    ({"calm_resistance": "less than parent"}, "constraints.calm_resistance = 'less than parent': expected"),
    ({"max_half_breadth": -1.0}, "constraints.max_half_breadth = -1.0: expected a positive half-breadth"),
    ({"bulge": "sometimes"}, "constraints.bulge"),
    ({"tolerance": 0.5}, "constraints.tolerance"),
])
def test_bad_constraints_fail_with_the_field(constraints, message):
    with pytest.raises(ValueError, match="1 validation error") as e:
        RunConfig.model_validate(_raw(**constraints))
    assert message in str(e.value)


def test_objective_constraints_take_the_objectives_options():
    cfg = RunConfig.model_validate(_raw(calm_resistance="<= parent", wetted_surface="<= 1.01 * parent"))
    assert cfg.constraints.bounds() == {"calm_resistance": (1, 1.0, True), "wetted_surface": (1, 1.01, True)}
    assert cfg.constraint_options("calm_resistance").speed_kn == cfg.objective.speed_kn
    raw = _raw(mean_added_resistance="<= parent")
    raw["objective"] = {"kind": "calm_resistance", "speed_kn": 15.0}  # no sea state for the constraint
    with pytest.raises(ValueError, match="constraints.mean_added_resistance: .*hs"):
        RunConfig.model_validate(raw)
    raw = _raw(cwp=">= parent")
    raw.update(kind="fit", objective=None)
    with pytest.raises(ValueError, match="a fit holds targets only"):
        RunConfig.model_validate({k: v for k, v in raw.items() if v is not None})
    solver = SolverConfig()  # fairness on by default, but for fits
    assert solver.fairness_for("minimise") == solver.fairness_for("pareto") == FAIRNESS > 0
    assert solver.fairness_for("fit") == 0 and SolverConfig(fairness=0.2).fairness_for("fit") == 0.2


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
