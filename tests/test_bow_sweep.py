"""A Bf sweep with the bow attachment as its lever: each design starts on the blunting branch of Bf(a)
(:func:`hullopt.study.bow_starts`), and :func:`hullopt.optimise.solve_pareto` takes those starts."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.models import BowAttachment, FeatureParams, feature_model, load_parent
from hullopt.optimise import Design, make_targets, solve_pareto
from hullopt.study import bow_starts
from hullopt.waves import bluntness

T = 6.25


def _design():
    hull = load_parent("wigley")
    model = feature_model(hull, bows=[BowAttachment(x_blend=60.0, z_lo=4.0, blend=1.5, x_peak=85.0)])
    return Design(model=model, draft=np.asarray(T), targets=make_targets({"bf": 0.1})), model


def test_starts_reach_each_bf_on_the_blunting_branch():
    design, model = _design()
    p0 = model.zeros()
    upper = FeatureParams(*(np.ones(np.shape(a)) for a in (p0.apex, p0.distribution, p0.contour)),
                          np.array([3.0]), np.zeros(0))
    bf0 = float(jax.jit(lambda p: bluntness(model(p), T))(p0))
    values = jnp.array([bf0, 0.06, 0.12, 0.9])  # the parent's, two blunter, one out of reach
    starts = eqx.filter_jit(bow_starts)(design, values, p0, upper, upper)
    a = np.asarray(starts.bow)[:, 0]
    assert a[0] == 0.0 and a[3] == 0.0  # the parent, and the parent again where no amplitude reaches Bf*
    assert 0.0 < a[1] < a[2] <= 3.0
    got = np.asarray(jax.jit(jax.vmap(lambda p: bluntness(model(p), T)))(starts))
    np.testing.assert_allclose(got[1:3], values[1:3], rtol=0.02)  # linear between 33 amplitudes on [0, 3] m
    # the branch: Bf rises from each start outward (a gradient there leads a solve to the target, not away)
    slope = jax.jit(jax.grad(lambda a: bluntness(model(eqx.tree_at(lambda q: q.bow, p0, a)), T)))
    assert all(float(slope(jnp.array([x]))[0]) > 0 for x in a[1:3])


@pytest.mark.slow  # a vmapped constrained solve (~1 min)
def test_solve_pareto_takes_the_starts():
    design, model = _design()
    p0 = model.zeros()
    half = FeatureParams(*(np.ones(np.shape(a)) for a in (p0.apex, p0.distribution, p0.contour)),
                         np.array([3.0]), np.zeros(0))
    lower = jax.tree.map(lambda h: -h, half)
    values = jnp.array([0.06, 0.12])
    from hullopt.optimise import KAw

    d = eqx.tree_at(lambda x: x.objective, design, KAw(speed=jnp.asarray(7.7)), is_leaf=lambda v: v is None)
    starts = eqx.filter_jit(bow_starts)(d, values, p0, lower, half)
    front = solve_pareto(d, "bf", values, p0, lower, half, outer=3, max_steps=60, starts=starts)
    assert bool(np.all(front.result.met))
    bf = np.asarray(jax.vmap(lambda p: bluntness(model(p), T))(front.result.params))
    np.testing.assert_allclose(bf, values, atol=2e-4)
    assert np.all(np.asarray(front.result.params.bow)[:, 0] > 0)  # blunter by adding volume
