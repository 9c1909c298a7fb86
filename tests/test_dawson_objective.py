"""Dawson's method as a design objective ([W4 2/6] item 4): the blocked, checkpointed influence matrices
(:func:`hullopt.resistance.source_velocity`'s ``block``) give the values and gradients stored before the change
(2026-12-02, the unblocked kernel) to 1e-10, blocks of any size agree, and the gradient of R_T by
``method = "dawson"`` equals central differences on a small grid."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.constants import G
from hullopt.models import box, wigley
from hullopt.resistance import Panels, calm_water, dawson_wave_resistance, source_velocity
from hullopt.resistance._panel import hull_panels, mirrored

from helpers import check_grad

# Computed before the change (the unblocked kernel; /tmp script, jit, float64): R_w [N], sinkage [m], trim [rad]
# at each Fn, Σζ and Σ|ζ| [m] on the grid, Σ|ζ| on the wake grid, and d(Σ R_w / 1e3)/d(draft, beam scale).
STORED = {
    "wigley": {"r_wave": [44715.56650838723, 176661.2698691446], "sinkage": [0.17979834761287092, 0.3897114040340667],
               "trim": [0.0004342696207841106, 0.005242346471166114], "zeta_sum": -5.803092766391374,
               "zeta_abs": 62.409285083608765, "wake_abs": 25.251831435743505,
               "grad": [88.52135749123121, 389.0679286326058]},
    "transom": {"r_wave": [2412.1596316984537, 2316.7776032632646], "sinkage": [0.06786654576501552, 0.0496953523273074],
                "trim": [-0.0034600859457536116, -0.0026611277748666163], "zeta_sum": -0.03812169776692248,
                "zeta_abs": 3.012097569802029, "wake_abs": 2.21667309442096,
                "grad": [38.56016118812914, 4.554779949670725]},
    "attitude": {"r_wave": [228336.2114856169], "sinkage": [0.4449818727977864], "trim": [0.009106912614787235],
                 "zeta_sum": -3.5425571097584316, "zeta_abs": 28.16589716038513, "wake_abs": 15.193681361174416,
                 "grad": [101.37002561163754, 441.8917014963944]},
}
CASES = {
    "wigley": (lambda: wigley(100, 10, 6.25, 10, n=21, m=17), 6.1, [0.3, 0.4], 100.0,
               {"stations": 16, "girth": 5, "columns": 40, "rows": 8}),
    "transom": (lambda: box(60.0, 8.0, 6.0, n=9), 0.25, [0.35, 0.3], 60.0,
                {"stations": 12, "girth": 4, "columns": 30, "rows": 6}),
    "attitude": (lambda: wigley(100, 10, 6.25, 10, n=21, m=17), 6.1, [0.42], 100.0,
                 {"stations": 12, "girth": 4, "columns": 30, "rows": 6, "attitude": 1}),
}


def _scale(h, s):
    return type(h)(x=h.x, yz=h.yz * jnp.stack([s, jnp.ones_like(s)]), lpp=h.lpp)


@pytest.mark.parametrize("name", ["wigley", "transom", "attitude"])
def test_values_and_gradients_as_stored(name):
    """R_w, sinkage, trim, the wave pattern and the gradient equal the unblocked kernel's to 1e-10 (a Wigley at
    two speeds, a box with a dry transom, a Wigley free to sink and trim)."""
    make, t, fns, length, kw = CASES[name]
    h = make()
    u = jnp.asarray(fns) * np.sqrt(G * length)

    def f(p):
        r = dawson_wave_resistance(_scale(h, p[1]), p[0], u, **kw)
        return r.r_wave, r.sinkage, r.trim, r.zeta, r.wake_zeta

    p = jnp.array([t, 1.0])
    r = jax.jit(f)(p)
    g = jax.jit(jax.grad(lambda q: jnp.sum(f(q)[0]) / 1e3))(p)
    want = STORED[name]
    for key, got in (("r_wave", r[0]), ("sinkage", r[1]), ("trim", r[2]), ("grad", g)):
        np.testing.assert_allclose(np.asarray(got), want[key], rtol=1e-10, err_msg=key)
    for key, got in (("zeta_sum", jnp.sum(r[3])), ("zeta_abs", jnp.sum(jnp.abs(r[3]))),
                     ("wake_abs", jnp.sum(jnp.abs(r[4])))):
        np.testing.assert_allclose(float(got), want[key], rtol=1e-10, err_msg=key)


@pytest.mark.parametrize("own, flat", [(True, False), (False, False), (True, True)])
def test_blocks_of_any_size_agree(own, flat):
    """source_velocity in blocks of 1, 7 (a padded last block) and all points: the same matrix and the same
    gradient of a contraction of it, own centroids and images folded included."""
    pan = hull_panels(wigley(100, 10, 6.25, 10, n=11, m=9), 6.1, 8, 3)
    if flat:
        x, y = jnp.meshgrid(jnp.linspace(0.0, 10.0, 6), jnp.linspace(0.0, 4.0, 4), indexing="ij")
        n = jnp.stack([x, y, jnp.full_like(x, 6.1)], -1)
        quad = jnp.stack([n[:-1, :-1], n[1:, :-1], n[1:, 1:], n[:-1, 1:]], axis=2).reshape(-1, 4, 3)
        pan = Panels(quad, jnp.asarray(6.1))
    sets = mirrored(pan) if not flat else Panels(jnp.concatenate([pan.vertices, pan.vertices]), pan.draft)
    pts = pan.centre if own else pan.centre + jnp.array([0.3, 0.7, -0.2])
    # a collapsed end panel's centroid lies on its neighbours' edges, where the logarithm's floor decides (its
    # row is replaced in every solve): real rows only
    real = np.asarray(pan.real > 0.0)
    w = jax.random.normal(jax.random.PRNGKey(0), (pts.shape[0], pan.vertices.shape[0], 3))
    w = w * real[:, None, None].astype(np.float64)
    images = 4 if not flat else 2

    def f(p, block):
        return source_velocity(p, sets, own=own, flat=flat, images=images, block=block)

    whole = f(pts, None if pts.shape[0] * sets.vertices.shape[0] <= 1 << 18 else pts.shape[0])
    gw = jax.grad(lambda p: jnp.sum(w * f(p, pts.shape[0])))(pts)
    for block in (1, 7):
        np.testing.assert_allclose(f(pts, block)[real], whole[real], rtol=1e-13, atol=1e-15)
        np.testing.assert_allclose(jax.grad(lambda p: jnp.sum(w * f(p, block)))(pts), gw, rtol=1e-11, atol=1e-13)


def test_calm_resistance_gradient_matches_differences():
    """d R_T/d(draft, beam scale) of calm_water(method="dawson") — the objective's — at two speeds, by AD through
    the blocked, checkpointed influence matrices and the dense solves, equals central differences (the Wigley
    on a small grid)."""
    h = wigley(100, 10, 6.25, 10, n=21, m=17)
    u = jnp.asarray([0.3, 0.4]) * np.sqrt(G * 100.0)
    f = jax.jit(lambda p: jnp.mean(calm_water(_scale(h, p[1]), p[0], u, "dawson", stations=12, girth=4).total) / 1e3)
    check_grad(f, np.array([6.1, 1.0]), rtol=1e-5, h=1e-5)
