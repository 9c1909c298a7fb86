"""The calm_resistance objectives: R_T = (1 + k1)·R_F + R_APP + R_W + R_A with R_W by the method named
(calm_resistance_michell: Michell's), from a config's options, over an operating profile, differentiable in the
hull's shape."""

import equinox as eqx
import jax
import jax.numpy as jnp
import pytest
from helpers import check_grad

from hullopt.constants import KNOT
from hullopt.geometry import Sections
from hullopt.models import wigley
from hullopt.optimise import OBJECTIVES, MichellCalmResistance
from hullopt.resistance import LAMBDA_PANELS, holtrop_hull, holtrop_mennen, michell_wave_resistance

DRAFT = 6.25
HULL = wigley(100.0, 10.0, DRAFT, 10.0, n=41, m=17)


def shaped(p):
    """The Wigley with its half-breadths scaled along the length by 1 + p₀ + p₁ sin πξ + p₂ sin 2πξ."""
    xi = HULL.x / HULL.lpp
    f = 1.0 + p[0] + p[1] * jnp.sin(jnp.pi * xi) + p[2] * jnp.sin(2.0 * jnp.pi * xi)
    return Sections(HULL.x, HULL.yz * jnp.stack([f, jnp.ones_like(f)], -1)[:, None, :], HULL.lpp)


@pytest.mark.slow
def test_value_is_michell_plus_form_factor_friction():
    obj = OBJECTIVES["calm_resistance_michell"].from_config({"speed_kn": 18.0, "hs": 3.0})
    assert isinstance(obj, MichellCalmResistance) and obj.unit == "N"
    assert float(obj.speed) == pytest.approx(18.0 * KNOT, rel=1e-15)

    @jax.jit
    def parts(s):
        hm = holtrop_mennen(holtrop_hull(s, DRAFT), 18.0 * KNOT)
        return (hm.form_factor * hm.friction + hm.appendages + hm.correlation,
                michell_wave_resistance(s, DRAFT, 18.0 * KNOT, panels=LAMBDA_PANELS), hm.total)

    viscous, wave, holtrop = (float(v) for v in parts(HULL))
    assert float(eqx.filter_jit(obj)(HULL, DRAFT)) == pytest.approx(viscous + wave, rel=1e-12)
    assert 0.3 < wave / viscous < 3.0  # a Wigley at Fn 0.3: wave and viscous parts of one order
    # calm_resistance's default is Holtrop–Mennen's own total
    hm = OBJECTIVES["calm_resistance"].from_config({"speed_kn": 18.0})
    assert float(eqx.filter_jit(hm)(HULL, DRAFT)) == pytest.approx(holtrop, rel=1e-12)


@pytest.mark.slow
def test_profile_is_the_weighted_mean():
    """``speeds_kn`` with ``weights``: Σ wᵢ R_T(Uᵢ)/Σ wᵢ, each speed's R_T by the same method."""
    obj = OBJECTIVES["calm_resistance"].from_config({"speed_kn": 18.0, "speeds_kn": [16.0, 18.0, 20.0],
                                                      "weights": [1.0, 2.0, 1.0], "method": "michell"})
    one = [float(OBJECTIVES["calm_resistance"].from_config({"speed_kn": v, "method": "michell"})(HULL, DRAFT))
           for v in (16.0, 18.0, 20.0)]
    assert float(obj(HULL, DRAFT)) == pytest.approx((one[0] + 2 * one[1] + one[2]) / 4, rel=1e-12)
    with pytest.raises(ValueError, match="weights"):
        OBJECTIVES["calm_resistance"].from_config({"speed_kn": 18.0, "speeds_kn": [16.0, 18.0], "weights": [1.0]})


@pytest.mark.slow
def test_gradient_in_the_shape_matches_central_differences():
    obj = MichellCalmResistance(jnp.asarray(18.0 * KNOT), n_levels=17)
    check_grad(jax.jit(lambda p: obj(shaped(p), DRAFT)), jnp.array([0.05, -0.1, 0.08]), rtol=1e-6, h=1e-5)
