"""The KCS's motion part of the added resistance does not depend on how finely the hull mesh is sliced: in short
waves (λ/L 0.3–0.5, heave < 0.06) and at the peak. (Before the waterline node of a flared section was taken from
a dry segment and the first wet strip stood in for a transom, σ_AWM at λ/L 0.3 was 0.08 with 61 stations and
0.36 with 201.) KCS at 24 kn (Fn 0.26), draft 10.8 m, as in the README."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.study import load_hull
from hullopt.constants import G, KNOT, RHO_SEA
from hullopt.waves import motions, omega_from_wavelength

LAMBDAS = np.array([0.3, 0.4, 0.5, 1.2])


@pytest.mark.slow
@pytest.mark.slow
def test_kcs_motion_part_converges_with_slicing(hulls, monkeypatch):
    monkeypatch.chdir(hulls.parent.parent)
    omega = jnp.asarray(omega_from_wavelength(LAMBDAS * 230.0))
    run = jax.jit(lambda s: motions(s, 10.8, 24 * KNOT, omega, kg=7.28))
    sig, heave = {}, {}
    for n in (61, 201):
        h = load_hull(f"examples/hulls/kcs_model_closed_from_igs.stl.gz?scale=31.6&lpp=230&n={n}")
        m = run(h.sections)
        sig[n] = np.asarray(m.r_awm) / (RHO_SEA * G * 32.2**2 / 230.0)
        heave[n] = np.asarray(m.heave_rao)
    assert np.all(heave[201][:3] < 0.06)
    # measured 0.033/0.025, 0.137/0.148, 0.460/0.418 (λ/L 0.3, 0.4, 0.5), 8.81/8.73 at λ/L 1.2
    np.testing.assert_allclose(sig[61][:3], sig[201][:3], atol=0.08)
    assert sig[61][3] == pytest.approx(sig[201][3], rel=0.03)
