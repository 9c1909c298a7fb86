"""Design problems and solvers: auto-fit to targets (vmapped over several target pairs, near and far,
feasible and not), constrained minimisation, gradients of the full objective, Pareto filtering, jaxopt."""

import dataclasses
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.constants import KNOT
from hullopt.hydro import hydrostatics
from hullopt.models import ApexMove, ContourEdit, Distribution, feature_model, load_parent
from hullopt.optimise import (
    OBJECTIVES,
    CalmResistance,
    DawsonCalmResistance,
    Design,
    KAw,
    MeanAddedResistance,
    MichellCalmResistance,
    Objective,
    WindAddedResistance,
    fit,
    fit_traced,
    make_targets,
    minimise_constrained,
    minimise_lbfgsb,
    non_dominated,
    solve_fit,
    with_objective_scale,
)


@pytest.fixture(scope="module")
def wigley_design():
    h = load_parent("wigley")
    model = feature_model(
        h,
        [ApexMove(-1, 50.0, 80.0, 100.0, "smooth"), ApexMove(-1, 0.0, 20.0, 50.0, "smooth")],
        [Distribution(0.0, 100.0, "all", 2)],
        [ContourEdit("deck_y", 55.0, 100.0, "bump")],
    )
    p0 = model.zeros()
    half = type(p0)(jnp.full((2, 2), 1.5), jnp.full((1, 2), 0.4), jnp.full((1,), 1.0))
    lower = jax.tree.map(lambda a: -a, half)
    parent = eqx.filter_jit(lambda p: hydrostatics(model(p), 6.25))(p0)  # compiled: op by op took ~15 s
    return model, p0, lower, half, parent


def test_make_targets_rejects_bad_input():
    with pytest.raises(ValueError, match="unknown target 'cbb'"):
        make_targets({"cbb": 0.5})
    with pytest.raises(ValueError, match="cb = 1.3 is outside the physical range"):
        make_targets({"cb": 1.3})
    with pytest.raises(ValueError, match="gm target needs kg"):
        make_targets({"gm": 1.0})


@pytest.mark.slow
def test_fit_many_target_pairs_in_one_vmap(wigley_design):
    """Near, far (Cb +8 %, LCB 1.5 % Lpp — beyond the ±3–5 % of a Lackenby/Maxsurf transformation) and
    infeasible targets, one vmapped solve: each member reports its own status."""
    model, p0, lo, hi, parent = wigley_design
    cb0 = float(parent.cb)
    cases = np.array([[cb0 * 1.08, -1.5], [cb0 * 0.94, 1.0], [cb0 * 1.02, 0.5], [0.75, 0.0]])
    base = Design(model=model, draft=jnp.asarray(6.25), targets=make_targets({"cb": cb0, "lcb_pct": 0.0}),
                  param_scale=hi)

    @eqx.filter_jit
    def solve(values):
        d = eqx.tree_at(lambda x: x.targets.values, base, values)
        r = solve_fit(d, p0, lo, hi, max_steps=80)
        h = hydrostatics(d.model(r.params), d.draft)
        return r.met, h.cb, h.lcb_pct

    met, cb, lcb = jax.vmap(solve)(jnp.asarray(cases))
    met, cb, lcb = np.asarray(met), np.asarray(cb), np.asarray(lcb)
    assert met[:3].all() and not met[3]  # Cb 0.75 on a Wigley's length, breadth and draft: out of reach
    np.testing.assert_allclose(cb[:3], cases[:3, 0], atol=1e-4)
    np.testing.assert_allclose(lcb[:3], cases[:3, 1], atol=0.01)
    assert cb[3] < 0.7  # the closest design found, reported as not met


@pytest.mark.slow
def test_traced_fit_records_its_history_and_agrees_with_the_optimistix_solve(wigley_design):
    model, p0, lo, hi, parent = wigley_design
    d = Design(model=model, draft=jnp.asarray(6.25), param_scale=hi,
               targets=make_targets({"volume": float(parent.volume) * 1.05, "lcb_pct": -1.0}))
    traced, plain = eqx.filter_jit(lambda: (solve_fit(d, p0, lo, hi, traced=True), solve_fit(d, p0, lo, hi)))()
    h = eqx.filter_jit(lambda p: hydrostatics(model(p), 6.25))(traced.params)
    assert bool(traced.met) and bool(traced.solver_ok)
    assert float(h.volume) == pytest.approx(float(parent.volume) * 1.05, rel=5e-4)
    assert float(h.lcb_pct) == pytest.approx(-1.0, abs=0.01)
    costs = np.asarray(traced.history)
    n = int(traced.steps)
    assert np.isfinite(costs[: n + 1]).all() and np.isnan(costs[n + 1:]).all()
    assert costs[n] < 1e-3 * costs[0] and np.all(np.diff(costs[: n + 1]) <= 1e-12 * costs[0])  # LM never climbs
    assert costs[n] == pytest.approx(float(traced.objective), rel=1e-9)
    # the costs and residuals are the solver's own (its linearisation's values, not a second evaluation of the
    # model): the same as evaluated afresh, at the start and at the solution
    r0, r = eqx.filter_jit(lambda a, b: (d.residuals(a), d.residuals(b)))(p0, traced.params)
    assert costs[0] == pytest.approx(float(r0 @ r0), rel=1e-12)
    np.testing.assert_allclose(np.asarray(traced.residuals), np.asarray(r), rtol=1e-10, atol=1e-12)
    with pytest.raises(ValueError, match="max_steps=0"):
        solve_fit(d, p0, lo, hi, traced=True, max_steps=0)
    # the same solution as optimistix's own loop (which polishes longer: same targets, close parameters)
    np.testing.assert_allclose(np.asarray(traced.residuals[:2]), np.asarray(plain.residuals[:2]), atol=1e-3)


def _count(jaxpr, primitive: str) -> int:
    """How many times ``primitive`` appears in ``jaxpr`` and the jaxprs inside it (loops, conds, calls)."""
    n = 0
    for e in jaxpr.eqns:
        n += e.primitive.name == primitive
        for v in e.params.values():
            for inner in v if isinstance(v, (list, tuple)) else [v]:
                inner = getattr(inner, "jaxpr", None)
                if inner is not None:
                    n += _count(inner if hasattr(inner, "eqns") else inner.jaxpr, primitive)
    return n


def test_the_traced_fit_holds_one_copy_of_the_model():
    """The model is evaluated once a step (the solver's linearisation); the history and the final residuals
    take its values, so the compiled program holds one copy of the model (it held four: the start's cost, the
    step, the cost after it and the final residuals), and XLA compiles a quarter of it."""

    def residuals(p, args):
        return jnp.stack([jnp.sinh(p["a"]) - 2.0, p["a"] + p["b"] - 1.0])  # sinh: the model's marker

    p0 = {"a": jnp.asarray(1.0), "b": jnp.asarray(0.5)}
    lo, hi = {"a": jnp.asarray(0.0), "b": jnp.asarray(-5.0)}, {"a": jnp.asarray(5.0), "b": jnp.asarray(5.0)}
    assert _count(jax.make_jaxpr(lambda: fit_traced(residuals, p0, lo, hi))().jaxpr, "sinh") == 1
    res = fit_traced(residuals, p0, lo, hi)
    assert float(res.params["a"]) == pytest.approx(np.arcsinh(2.0), rel=1e-10) and bool(res.met)
    np.testing.assert_allclose(np.asarray(res.residuals), np.asarray(residuals(res.params, None)), atol=1e-14)
    assert float(res.history[0]) == pytest.approx((np.sinh(1.0) - 2.0) ** 2 + 0.5**2, rel=1e-12)  # the start's


def test_the_augmented_lagrangian_rounds_evaluate_the_model_only_inside_bfgs():
    """Each round takes the objective, c and g at its solution from BFGS (the Lagrangian's aux), and the result
    is the last round's: the program holds the objective, constraints and inequalities where BFGS evaluates
    them (its step's value and gradient), not again after each round (it held 6, 6 and 14 copies of the
    markers below; now 2, 3 and 6). Given ``terms``, the three come from one evaluation of what they share (a
    hull model): its marker appears once at the start (which only marks the start's carry as batched, and which
    XLA drops) and once where BFGS evaluates it, with the same result. The result is the one a fresh evaluation
    gives."""

    def objective(p, args):
        return (p["x"] - 2.0) ** 2 + jnp.sinh(p["y"]) ** 2  # sinh: the objective's marker

    def constraints(p, args):
        return jnp.stack([jnp.cosh(p["x"]) + p["y"] - 2.0])  # cosh (also sinh's derivative)

    def inequalities(p, args):
        return jnp.stack([jnp.tanh(p["y"]) - 0.2 * p["x"] - 0.1])

    p0 = {"x": jnp.asarray(0.5), "y": jnp.asarray(0.1)}
    lo, hi = {"x": jnp.asarray(-5.0), "y": jnp.asarray(-5.0)}, {"x": jnp.asarray(5.0), "y": jnp.asarray(5.0)}

    def solve():
        return minimise_constrained(objective, constraints, p0, lo, hi, inequalities=inequalities, outer=4)

    def terms(p, args):
        m = jnp.exp(p["x"] * p["y"])  # exp: the shared model's marker (its derivative is itself)
        return objective(p, args) + 0 * m, constraints(p, args) + 0 * m, inequalities(p, args) + 0 * m

    def shared():
        return minimise_constrained(objective, constraints, p0, lo, hi, inequalities=inequalities, outer=4,
                                    terms=terms)

    jaxpr = jax.make_jaxpr(solve)().jaxpr
    assert [_count(jaxpr, k) for k in ("sinh", "cosh", "tanh")] == [2, 3, 6]
    assert _count(jax.make_jaxpr(shared)().jaxpr, "exp") == 2
    r, r_shared = jax.jit(solve)(), jax.jit(shared)()
    assert bool(r.met)
    assert float(r.objective) == pytest.approx(float(objective(r.params, None)), rel=1e-12)
    np.testing.assert_allclose(np.asarray(r.residuals), np.asarray(constraints(r.params, None)), atol=1e-14)
    assert float(r.objective_history[-1]) == float(r.objective)
    np.testing.assert_allclose(np.asarray(r_shared.params["x"]), np.asarray(r.params["x"]), rtol=1e-9)


@pytest.mark.slow
def test_objective_gradient_matches_finite_differences(wigley_design):
    """The full objective of the minimisation (sea-state mean added resistance, scaled, plus smoothness)
    and the target residuals, along random directions of all parameters."""
    model, p0, lo, hi, parent = wigley_design
    d = Design(model=model, draft=jnp.asarray(6.25), param_scale=hi,
               targets=make_targets({"cb": float(parent.cb), "lcb_pct": 0.0, "volume": float(parent.volume)}),
               objective=MeanAddedResistance(jnp.asarray(15 * KNOT), jnp.asarray(3.0), jnp.asarray(9.0),
                                             jnp.asarray(0.0), motion=False))  # motions' gradients: test_motions
    d = with_objective_scale(d, p0)
    p = jax.tree.map(lambda a: 0.2 * jnp.ones_like(a), p0)
    f = eqx.filter_jit(lambda q: jnp.concatenate([d.objective_value(q)[None], d.constraints(q)]))
    rng = np.random.default_rng(1)
    for _ in range(2):
        v = jax.tree.map(lambda a: jnp.asarray(rng.normal(size=a.shape)), p0)
        _, jvp = eqx.filter_jit(lambda q, t: jax.jvp(f, (q,), (t,)))(p, v)
        eps = 1e-6
        fd = (f(jax.tree.map(lambda a, b: a + eps * b, p, v)) - f(jax.tree.map(lambda a, b: a - eps * b, p, v))) / (2 * eps)
        np.testing.assert_allclose(jvp, fd, rtol=2e-5, atol=1e-9)


def test_minimise_constrained_vmaps_with_per_member_status():
    obj = lambda p, a: (p["a"] - 3.0) ** 2 + (p["b"] - 2.0) ** 2  # noqa: E731
    con = lambda p, a: jnp.array([p["a"] + p["b"] - a])  # noqa: E731
    p0 = {"a": jnp.array(1.0), "b": jnp.array(0.0)}
    lo = {"a": jnp.array(-5.0), "b": jnp.array(-5.0)}
    hi = {"a": jnp.array(5.0), "b": jnp.array(5.0)}
    t = jnp.array([0.0, 1.0, 2.0, 12.0])  # the last cannot be met within the bounds
    r = jax.jit(jax.vmap(lambda t: minimise_constrained(obj, con, p0, lo, hi, t, tol=1e-8)))(t)
    np.testing.assert_allclose(r.params["a"][:3], (t[:3] + 1) / 2, atol=1e-6)  # a − 3 = b − 2 on a + b = t
    np.testing.assert_allclose(r.params["b"][:3], (t[:3] - 1) / 2, atol=1e-6)
    assert np.asarray(r.met).tolist() == [True, True, True, False]


def test_fit_is_implicitly_differentiable_in_its_target():
    """d(solution)/d(target) by the implicit function theorem equals the analytic value."""
    res = lambda p, a: jnp.array([p["x"] ** 3 - a])  # noqa: E731
    p0, lo, hi = {"x": jnp.array(1.0)}, {"x": jnp.array(0.0)}, {"x": jnp.array(5.0)}
    g = jax.grad(lambda a: fit(res, p0, lo, hi, a, rtol=1e-12, atol=1e-14).params["x"])(8.0)
    assert float(g) == pytest.approx(1 / (3 * 4.0), rel=1e-6)  # x = a^(1/3): dx/da = 1/(3 x²)


def test_non_dominated_matches_brute_force():
    rng = np.random.default_rng(0)
    pts = rng.normal(size=(60, 2))
    pts[5] = np.nan
    mask = np.asarray(non_dominated(jnp.asarray(pts)))
    for i, p in enumerate(pts):
        if not np.all(np.isfinite(p)):
            assert not mask[i]
            continue
        dominated = any(np.all(q <= p) and np.any(q < p) for q in pts if np.all(np.isfinite(q)))
        assert mask[i] == (not dominated)


@pytest.mark.slow
def test_jaxopt_adapter_respects_bounds():
    p, value, ok = minimise_lbfgsb(lambda p, a: jnp.sum((p - a) ** 2), jnp.zeros(2), jnp.array([-1.0, -1.0]),
                                   jnp.array([2.0, 4.0]), 3.0)
    np.testing.assert_allclose(p, [2.0, 3.0], atol=1e-6)
    assert bool(ok) and float(value) == pytest.approx(1.0, abs=1e-9)


@pytest.mark.parametrize("kind", ["calm_resistance", "wind_added_resistance", "k_aw"])
@pytest.mark.slow
def test_other_objectives_differentiate_through_the_design(wigley_design, kind):
    model, p0, lo, hi, parent = wigley_design
    obj = OBJECTIVES[kind].from_config({"speed_kn": 15.0, "wind_speed": 15.0, "wind_angle_deg": np.degrees(0.4)})
    p = jax.tree.map(lambda a: 0.1 * jnp.ones_like(a), p0)
    f = eqx.filter_jit(lambda q: obj(model(q), 6.25))
    v = jax.tree.map(lambda a: jnp.ones_like(a), p0)
    _, jvp = eqx.filter_jit(lambda q, t: jax.jvp(f, (q,), (t,)))(p, v)
    eps = 1e-6
    fd = (f(jax.tree.map(lambda a, b: a + eps * b, p, v)) - f(jax.tree.map(lambda a, b: a - eps * b, p, v))) / (2 * eps)
    assert np.isfinite(float(jvp)) and float(jvp) == pytest.approx(float(fd), rel=1e-5, abs=1e-9 * abs(float(f(p))))


def test_objectives_registry_is_built_from_the_classes():
    """One class per kind, each registered by its name with an SI unit and a description; the config accepts
    exactly the registered kinds; a new subclass is one class (registered on definition)."""
    from hullopt.study import OPTIONS

    from hullopt.optimise import ProfileAddedResistance, ProfilePower, ProfileResistance

    assert OBJECTIVES == {"k_aw": KAw, "mean_added_resistance": MeanAddedResistance,
                          "calm_resistance": CalmResistance, "calm_resistance_michell": MichellCalmResistance,
                          "calm_resistance_dawson": DawsonCalmResistance,
                          "wind_added_resistance": WindAddedResistance, "profile_resistance": ProfileResistance,
                          "profile_power": ProfilePower, "profile_added_resistance": ProfileAddedResistance}
    assert {k: c.unit for k, c in OBJECTIVES.items()} == {"k_aw": "-", "mean_added_resistance": "N",
                                                          "calm_resistance": "N", "calm_resistance_michell": "N",
                                                          "calm_resistance_dawson": "N",
                                                          "wind_added_resistance": "N", "profile_resistance": "N",
                                                          "profile_power": "W", "profile_added_resistance": "N"}
    assert all(c.name == k and c.description and issubclass(c, Objective) for k, c in OBJECTIVES.items())
    assert {k: o.model_fields["kind"].annotation.__args__ for k, o in OPTIONS.items()} == {k: (k,) for k in OBJECTIVES}
    assert all(set(o.model_fields) == {"kind", *OBJECTIVES[k].options} for k, o in OPTIONS.items())
    with pytest.raises(TypeError):
        Objective()  # abstract
    # only the fields a kind needs; the config's units (knots, degrees) converted to SI
    m = MeanAddedResistance.from_config({"speed_kn": 10.0, "hs": 3.0, "tp": 9.0, "heading_deg": 90.0,
                                         "wind_speed": 7.0})
    assert {f.name for f in dataclasses.fields(m)} == {"speed", "hs", "tp", "heading", "smooth", "motion", "bf_band"}
    assert float(m.speed) == pytest.approx(10 * 1852 / 3600, rel=1e-15)
    assert float(m.heading) == pytest.approx(np.pi / 2, rel=1e-15)
    assert {f.name for f in dataclasses.fields(CalmResistance)} == {"speed", "weights", "method", "n_levels", "panels"}
    with pytest.raises(ValueError, match="needs a sea state"):
        MeanAddedResistance.from_config({"speed_kn": 10.0, "hs": 0.0, "tp": 9.0})
    with pytest.raises(ValueError, match="needs wind_speed"):
        WindAddedResistance.from_config({"speed_kn": 10.0})

    class Draft(Objective):
        name: ClassVar[str] = "test_draft_only"
        unit: ClassVar[str] = "m"
        description: ClassVar[str] = "the draft"
        options: ClassVar[tuple[str, ...]] = ()

        def __call__(self, sections, draft):
            return jnp.asarray(draft, dtype=float)

        @classmethod
        def from_config(cls, options):
            return cls()

    try:
        assert OBJECTIVES["test_draft_only"] is Draft and float(Draft()(None, 2.0)) == 2.0
    finally:
        del OBJECTIVES["test_draft_only"]


@pytest.mark.slow
def test_fairness_term_is_scaled_by_the_parent_and_penalises_wiggles(wigley_design):
    model, p0, lo, hi, parent = wigley_design
    d = Design(model=model, draft=jnp.asarray(6.25), targets=make_targets({"cb": float(parent.cb)}),
               objective=KAw(jnp.asarray(15 * KNOT)), fairness=0.5, param_scale=hi)
    d = with_objective_scale(d, p0)
    f = eqx.filter_jit(lambda q: d.objective_value(q))
    assert float(f(p0)) == pytest.approx(1.0 + 0.5, rel=1e-12)  # both terms are one at the parent
    bumpy = eqx.tree_at(lambda q: q.apex, p0, jnp.array([[1.2, -1.2], [-1.2, 1.2]]))
    from hullopt.fairing import unfairness

    assert float(unfairness(model(bumpy))) > float(unfairness(model(p0)))
    r = d.residuals(bumpy)
    assert r.shape == (1 + 7 + 1,) and np.all(np.isfinite(np.asarray(r)))


def test_target_kinds_measure_as_the_hydrostatics_say():
    """TARGETS keeps its shape {name: (relative, tol)} over the target classes; a hydrostatics field is
    read from the hydrostatics, GM = KM_T − KG needs kg, Bf is the head-sea bluntness; a Particular measures
    the same."""
    from hullopt.models import wigley
    from hullopt.optimise import (TARGET_KINDS, TARGETS, BluntnessTarget, GMTarget, HydrostaticsTarget,
                                  Particular, achieved)
    from hullopt.waves import bluntness

    assert list(TARGETS) == list(TARGET_KINDS) and TARGETS["volume"] == (True, 5e-4)
    assert TARGETS["gm"] == (False, 0.01) and TARGETS["bf"] == (False, 1e-4) and TARGETS["cb"] == (False, 1e-4)
    assert isinstance(TARGET_KINDS["gm"], GMTarget) and TARGET_KINDS["gm"].needs_kg
    assert isinstance(TARGET_KINDS["bf"], BluntnessTarget) and not TARGET_KINDS["bf"].needs_kg
    assert all(isinstance(t, HydrostaticsTarget) for k, t in TARGET_KINDS.items() if k not in ("gm", "bf"))
    hull = wigley(100.0, 10.0, 6.25, 10.0, n=21, m=11)
    names = tuple(TARGETS)

    @eqx.filter_jit
    def measured(s):
        h = hydrostatics(s, 6.25)
        return (h, achieved(h, s, names, kg=jnp.asarray(4.0)), bluntness(s, h.draft),
                [Particular(k)(s, 6.25) for k in ("bf", "cb", "wetted_surface")])

    h, got, bf, particulars = measured(hull)
    want = [float(h.kmt) - 4.0 if k == "gm" else float(bf) if k == "bf" else float(getattr(h, k)) for k in names]
    np.testing.assert_array_equal(np.asarray(got), want)
    np.testing.assert_allclose([float(v) for v in particulars], [float(bf), float(h.cb), float(h.wetted_surface)],
                               rtol=1e-13)
    with pytest.raises(ValueError, match="gm needs kg"):
        TARGET_KINDS["gm"].measure(hull, 6.25)


@pytest.mark.slow
def test_fit_by_lbfgsb_meets_the_target_and_ends_on_an_active_bound():
    """A Wigley fit by both solvers to two Cb targets (one program): +4 % (reachable; both meet it) and +30 %
    (beyond the bounds: the fullness parameter is stopped by its bound). L-BFGS-B keeps every parameter within
    its bounds exactly and ends exactly on the active one; Levenberg–Marquardt (tanh change of variables) ends
    on it to rounding."""
    h = load_parent("wigley")
    model = feature_model(h, [], [Distribution(0.0, 100.0, "all", 2)], [])
    p0 = model.zeros()
    hi = jax.tree.map(lambda a: jnp.full(a.shape, 0.3), p0)
    lo = jax.tree.map(lambda a: -a, hi)
    base = Design(model=model, draft=jnp.asarray(6.25), targets=make_targets({"cb": 0.44}), param_scale=hi)

    @eqx.filter_jit
    def solve(cb):
        d = eqx.tree_at(lambda x: x.targets.values, base, cb[None])
        rs = [solve_fit(d, p0, lo, hi, traced=True, method=m, max_steps=60) for m in ("optimistix", "lbfgsb")]
        return rs, [hydrostatics(model(r.params), 6.25).cb for r in rs]

    targets = jnp.array([0.46, 0.58])  # the parent's Cb 0.444
    (lm, lb), (cb_lm, cb_lb) = jax.tree.map(lambda *v: jnp.stack(v), *(solve(t) for t in targets))
    assert np.asarray(lm.met).tolist() == np.asarray(lb.met).tolist() == [True, False]
    np.testing.assert_allclose([cb_lm[0], cb_lb[0]], targets[0], atol=1e-4)  # Cb's tolerance
    assert bool(lb.solver_ok[0]) and bool(lm.solver_ok[0])
    x_lb, x_lm = np.asarray(lb.params.distribution), np.asarray(lm.params.distribution)
    assert np.all(x_lb >= -0.3) and np.all(x_lb <= 0.3)
    assert np.abs(x_lb[1]).max() == 0.3 and np.sum(np.abs(x_lb[1]) == 0.3) == 1  # one bound active, exactly
    active = np.abs(x_lb[1]) == 0.3
    np.testing.assert_allclose(x_lm[1][active], x_lb[1][active], atol=1e-9)  # the same bound
    n = int(lb.steps[0])
    history = np.asarray(lb.history[0])
    assert np.isfinite(history[: n + 1]).all() and np.isnan(history[n + 1:]).all()
    assert history[n] == pytest.approx(float(lb.objective[0]), rel=1e-9) and history[n] < 1e-3 * history[0]
    with pytest.raises(ValueError, match="expected one of optimistix, lbfgsb"):
        solve_fit(base, p0, lo, hi, method="bfgs")


def test_solver_method_is_a_config_choice():
    """``[solver] method``: the fit's solver, optimistix by default, lbfgsb by choice, nothing else."""
    from pydantic import ValidationError

    from hullopt.optimise import FIT_METHODS
    from hullopt.study import SolverConfig

    assert SolverConfig().method == "optimistix" and SolverConfig(method="lbfgsb").method == "lbfgsb"
    assert set(FIT_METHODS) == {"optimistix", "lbfgsb"}
    with pytest.raises(ValidationError):
        SolverConfig(method="bfgs")


@pytest.mark.slow
def test_a_minimums_history_keeps_the_objective_apart_from_the_merit():
    """The convergence a run shows is the objective's (scaled to 1 at the parent); the merit the solver minimises
    (objective + fairness + smoothness penalties: 0.5 U/U₀ here) is its own series. A Wigley whose
    beam scales by 1 + p with the volume held at 1.1× the parent's: p = 0.1 whatever the penalties."""
    from hullopt.geometry import Sections
    from hullopt.models import wigley

    hull = wigley(100, 10, 6.25, 10, n=21, m=21)

    def model(p):
        return Sections(hull.x, hull.yz * jnp.array([1.0 + p, 1.0]), hull.lpp)

    v0 = float(jax.jit(hydrostatics)(hull, 6.25).volume)
    d = with_objective_scale(Design(model=model, draft=6.25, targets=make_targets({"volume": 1.1 * v0}),
                                    objective=KAw(jnp.asarray(7.7)), fairness=0.5), jnp.asarray(0.0))
    from hullopt.optimise import solve_minimum

    r = eqx.filter_jit(lambda d: solve_minimum(d, jnp.asarray(0.0), jnp.asarray(-0.5), jnp.asarray(0.5), outer=4))(d)
    assert float(r.params) == pytest.approx(0.1, abs=1e-4)
    assert float(r.objective_history[-1]) == pytest.approx(float(d.objective_ratio(r.params)), rel=1e-12)
    assert float(r.merit_history[-1]) == pytest.approx(float(d.objective_value(r.params)), rel=1e-12)
    from hullopt.fairing import unfairness

    penalty = 0.5 * float(unfairness(model(r.params)) / unfairness(model(jnp.asarray(0.0))))
    assert float(r.merit_history[-1]) - float(r.objective_history[-1]) == pytest.approx(penalty, rel=1e-4)
