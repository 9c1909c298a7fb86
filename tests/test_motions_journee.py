"""Strip-theory motions and added resistance against Journée's four Wigley models in head seas (Journée 1992,
"Experiments and calculations on four Wigley hullforms", TU Delft report 909; the values in
tests/data/journee1992_wigley.json, quoted from the report by a public secondary source, see SOURCES.md):
displacement, heave RAOs (Wigley III at Fn 0.2 and 0.3, Wigley I at its resonance), and the peak added
resistance σ_aw = R_AW/(ρgζ²B²/L) (R_AWM by strip theory + R_AWR by NMRI's Bf) — within 20 % at Fn 0.2 on the
slender models, and outside the 35 % aimed at from Fn 0.3, where ``hullopt motions``/``waves`` warn
(:func:`motion_validity_warning`)."""

import json
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.geometry import Sections, longitudinal_integrals
from hullopt.waves import MOTION_FN_MAX, motion_validity_warning, motions, nmri_added_resistance

DATA = json.loads((Path(__file__).parent / "data" / "journee1992_wigley.json").read_text())
L, D, RHO, G = DATA["L"], DATA["d"], DATA["rho"], 9.81
KYY = DATA["kyy_m"] / L
LAMBDAS = np.arange(0.8, 1.61, 0.05)


def journee_wigley(name, n=41, m=41):
    """Journée's Wigley ``name`` from the report's formula, stations at x [m from the AP], vertical sides from the
    waterline to 1.6 d."""
    b, alpha = DATA["models"][name]["B"], DATA["models"][name]["alpha"]
    x = np.linspace(0.0, L, n)
    xi = (2.0 * x / L - 1.0)[:, None]
    zeta = np.linspace(-1.0, 0.0, m)[None, :]
    eta = (1 - zeta**2) * (1 - xi**2) * (1 + 0.2 * xi**2) + alpha * zeta**2 * (1 - zeta**8) * (1 - xi**2) ** 4
    y = 0.5 * b * np.maximum(eta, 0.0)
    yz = np.stack([y, np.broadcast_to(D * (1.0 + zeta), y.shape)], axis=-1)
    deck = np.stack([y[:, -1], np.full(n, 1.6 * D)], axis=-1)[:, None]
    return Sections(x=jnp.asarray(x), yz=jnp.asarray(np.concatenate([yz, deck], axis=1)), lpp=L), b


@jax.jit
def _r_aw(hull, speed, omega):
    m = motions(hull, D, speed, omega, kyy=KYY, rho=RHO, g=G)
    nm = nmri_added_resistance(hull, D, speed, omega, 0.0, rho=RHO, g=G)
    return m.r_awm + jnp.ravel(nm.r_awr)


def peak_sigma(name, fn):
    hull, b = journee_wigley(name)
    omega = jnp.sqrt(2 * np.pi * G / (jnp.asarray(LAMBDAS) * L))
    return float(jnp.max(_r_aw(hull, fn * np.sqrt(G * L), omega) / (RHO * G * b**2 / L)))


@pytest.mark.parametrize("name", ["I", "II", "III", "IV"])
@pytest.mark.slow
def test_models_have_the_reported_displacement(name):
    hull, _ = journee_wigley(name)
    assert float(longitudinal_integrals(hull, D).volume) == pytest.approx(DATA["models"][name]["volume"], rel=0.005)


@pytest.mark.parametrize("name", ["I", "III"])
@pytest.mark.slow
def test_heave_in_head_waves(name):
    hull, _ = journee_wigley(name)
    for fn, lam, measured in DATA[f"heave_rao_{name}"]["rows"]:
        m = motions(hull, D, fn * np.sqrt(G * L), jnp.sqrt(2 * np.pi * G / (jnp.asarray([lam]) * L)), kyy=KYY,
                    rho=RHO, g=G)
        assert float(m.heave_rao[0]) / measured - 1.0 == pytest.approx(0.04, abs=0.07)  # measured +0.3 … +10 % (III), +2.4 % (I at resonance)


@pytest.mark.slow
def test_peak_added_resistance_of_the_slender_models():
    rows = {(name, fn): v for name, fn, v in DATA["peak_sigma_aw"]["rows"]}
    for name in ("I", "III"):
        # Fn 0.2: measured 0.93 (I) and 0.88 (III) of the tank; validated range, no warning.
        assert peak_sigma(name, 0.2) / rows[name, 0.2] == pytest.approx(1.0, abs=0.2)
        assert motion_validity_warning(0.2, 10.0) is None
        # Fn 0.3: 1.75–1.8× the tank (GB's known excess at speed) — outside 35 %: the commands warn there. Should a
        # method change bring it within 35 %, widen MOTION_FN_MAX with it.
        ratio = peak_sigma(name, 0.3) / rows[name, 0.3]
        assert 1.35 < ratio < 2.0  # measured 1.75 (I), 1.79 (III)
        assert 0.3 > MOTION_FN_MAX and "Fn 0.30" in motion_validity_warning(0.3, 10.0)
    assert "L/B 5.0" in motion_validity_warning(0.2, 5.0)  # the beamy models: 0.82 (II), 0.55 (IV) at Fn 0.2
