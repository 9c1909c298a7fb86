"""Bf over a band of waterlines [T − a, T + a] (:func:`hullopt.waves.bluntness` with ``band``): the draft's at a = 0,
a wall-sided hull's at any a, the mean of Bf(z) over the band against a fine trapezoid rule, the same Bf in NMRI's
R_AW, and a config's ``[hull] bf_band`` reaching the objective, the sweep's measure and the targets."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import check_grad

from hullopt.geometry import Sections
from hullopt.models import attach_bow, attachment_plan, BowAttachment, wigley
from hullopt.waves import bluntness, nmri_added_resistance


def _wall_sided(n=81):
    x = np.linspace(0.0, 100.0, n)
    b = 5.0 * np.minimum(1.0, (100.0 - x) / 20.0)
    z = np.linspace(0.0, 10.0, 41)
    yz = np.zeros((n, 42, 2))
    yz[:, 1:, 0], yz[:, 1:, 1] = b[:, None], z
    return Sections(x=jnp.asarray(x), yz=jnp.asarray(yz), lpp=jnp.asarray(100.0))


def test_band_zero_is_the_draft_and_a_wall_sided_hull_is_the_same_at_every_band():
    s = _wall_sided()
    bf = float(bluntness(s, 6.0))
    assert float(bluntness(s, 6.0, band=0.0)) == bf
    np.testing.assert_allclose(float(bluntness(s, 6.0, band=2.0)), bf, rtol=1e-12)


def test_band_mean_against_a_fine_trapezoid_over_the_heights():
    hull = wigley(100.0, 10.0, 6.25, 10.0, n=41, m=81)
    a = 1.5
    z = np.linspace(6.25 - a, 6.25 + a, 301)
    f = jax.jit(jax.vmap(lambda t: bluntness(hull, t)))
    ref = np.trapezoid(np.asarray(f(jnp.asarray(z))), z) / (2 * a)
    got = float(bluntness(hull, 6.25, band=a))
    np.testing.assert_allclose(got, ref, rtol=1e-5)
    assert abs(got - float(bluntness(hull, 6.25))) > 5e-3 * ref  # the band differs from the draft, by far more


def test_nmri_takes_the_band_mean_bf():
    hull = wigley(100.0, 10.0, 6.25, 10.0, n=41, m=41)
    r = nmri_added_resistance(hull, 6.25, 7.0, jnp.array([1.2]), band=1.0)
    np.testing.assert_allclose(np.asarray(r.bf), float(bluntness(hull, 6.25, band=1.0)), rtol=1e-12)


def test_band_gradient_through_an_attachment_above_the_waterline():
    """Fig. 16's attachment above the DWL: the draft's Bf cannot see it, the band's can (and its gradient)."""
    s = _wall_sided()
    att = BowAttachment(x_blend=60.0, z_lo=7.25, blend=1.0, x_peak=90.0)  # from 6.25 m up: dry at T = 6 m
    w = attachment_plan(np.asarray(s.x), att, len(s.x) - 1)[None]
    band = np.array([[att.z_lo, att.z_hi, att.blend]])

    def bf(a, width):
        return bluntness(attach_bow(s, a, w, band), 6.0, band=width)

    assert float(bf(jnp.array([1.0]), 0.0)) == pytest.approx(float(bluntness(s, 6.0)), rel=1e-12)
    assert float(bf(jnp.array([1.0]), 1.5)) > 1.05 * float(bluntness(s, 6.0))
    check_grad(jax.jit(lambda a: bf(a, 1.5)), np.array([0.8]), rtol=1e-5)


def test_config_band_reaches_objective_measure_and_targets(tmp_path):
    from hullopt.study import load_config

    text = (Path_cfg := tmp_path / "c.toml")
    text.write_text('''kind = "pareto"
[hull]
parent = "wigley"
bf_band = 1.25
[[design.bow]]
x_blend = 60.0
z_lo = 5.5
[targets]
volume = 2770.0
[objective]
kind = "k_aw"
speed_kn = 15.0
[sweep]
start = 0.1
stop = 0.2
count = 2
[sweep.measure]
kind = "mean_added_resistance"
speed_kn = 15.0
hs = 3.0
tp = 9.0
''')
    cfg, _ = load_config(Path_cfg)
    assert cfg.objective.bf_band == 1.25 and cfg.sweep.measure.bf_band == 1.25
    assert cfg.objective.build().bf_band == 1.25 and cfg.sweep.measure.build().bf_band == 1.25
