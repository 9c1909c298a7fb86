"""Smooth apex moves (claim 5, ``profile="smooth"``): C² at the fixed ends and the moved apex, so the
sectional-area curve of a moved DTC has no spike in its second difference where the move starts or ends."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.geometry import section_integrals
from hullopt.models import ApexMove, feature_model, load_parent
from hullopt.models._features import _smootherstep

DRAFT = 14.5


def test_smootherstep_is_c2_at_its_ends():
    r = jnp.array([0.0, 1.0])
    d1 = jax.vmap(jax.grad(_smootherstep))(r)
    d2 = jax.vmap(jax.grad(jax.grad(_smootherstep)))(r)
    np.testing.assert_array_equal(_smootherstep(r), [0.0, 1.0])
    np.testing.assert_array_equal(d1, [0.0, 0.0])
    np.testing.assert_array_equal(d2, [0.0, 0.0])


@pytest.fixture(scope="module")
def sac_second_differences():
    """ΔA(x)'' of the DTC's sectional areas at the draft for an apex move 80 → 150 → 250 m of the uppermost
    apex line by (1, −1) m, per profile, with the stations of the fixed ends."""
    hull = load_parent("dtc")
    out = {}
    for profile in ("linear", "smooth"):
        model = feature_model(hull, [ApexMove(-1, 80.0, 150.0, 250.0, profile)])
        zero = model.zeros()
        moved = type(zero)(jnp.array([[1.0, -1.0]]), zero.distribution, zero.contour)
        area = jax.jit(lambda p: section_integrals(model(p), DRAFT).area)
        da = np.asarray(area(moved)) - np.asarray(area(zero))
        x = np.asarray(model.hull.x)
        out[profile] = (np.diff(da, 2) / np.diff(x)[:-1] ** 2, x)
    return out


def test_no_spike_in_the_sac_at_the_fixed_ends(sac_second_differences):
    """Smooth: the second difference rises from 0 at each fixed end (measured 0.005 → 0.021 → 0.022 m²/m² from
    x = 80 m; the cubic smoothstep gave 0.015, 0.0225, then fell to 0.011 — a jump of curvature at the end);
    near the ends it stays below the largest value inside the move (0.023). Linear (the claim): a kink, the
    second difference at the fixed end 3× anything inside."""
    d2, x = sac_second_differences["smooth"]
    i1, i2 = int(np.argmin(abs(x - 80.0))), int(np.argmin(abs(x - 250.0)))
    # d2[j] is centred on station j + 1: the three stations from each fixed end into the move
    near = np.abs(np.r_[d2[i1 - 1 : i1 + 2], d2[i2 - 3 : i2]])
    inside = np.abs(d2[i1 + 2 : i2 - 3]).max()
    assert near.max() <= inside
    assert abs(d2[i1 - 1]) < 0.3 * inside  # the first moved station barely curves
    lin, _ = sac_second_differences["linear"]
    assert abs(lin[i1 - 1]) > 2.0 * np.abs(lin[i1 + 2 : i2 - 3]).max()
