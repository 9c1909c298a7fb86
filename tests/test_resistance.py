"""Holtrop & Mennen (1982) against the paper's own worked example (section 5: L 205 m, B 32 m, 25 kn)."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import check_grad

from hullopt.models import wigley
from hullopt.resistance import HoltropHull, holtrop_hull, holtrop_mennen

KN = 1852.0 / 3600.0
f64 = lambda v: jnp.asarray(v, dtype=jnp.float64)  # noqa: E731

# The example's data (Holtrop & Mennen 1982, §5): lcb −0.75 % L, iE 12.08°, S 7381.45 m², 1 + k2 = 1.5.
EXAMPLE = HoltropHull(
    L=f64(205.0), B=f64(32.0), T=f64(10.0), T_F=f64(10.0), volume=f64(37500.0), cm=f64(0.98), cwp=f64(0.75),
    lcb=f64(-0.75), ie=f64(12.08), S=f64(7381.45), A_BT=f64(20.0), h_B=f64(4.0), A_T=f64(16.0),
    c_stern=f64(10.0), S_app=f64(50.0), k2_app=f64(1.5),
)


def test_worked_example_components():
    """Printed in the paper: R_F 869.63 kN, 1+k1 1.156, R_APP 8.83, R_W 557.11, R_B 0.049, R_TR 0,
    R_A 221.98 kN, total 1793.26 kN; C_F 0.001390, C_A 0.000352, c1 1.398, c2 0.7595, c5 0.9592,
    m1 −2.1274, m2 −0.17087, λ 0.6513."""
    r = holtrop_mennen(EXAMPLE, 25 * KN)
    kn = lambda v: float(v) / 1e3  # noqa: E731
    assert kn(r.friction) == pytest.approx(869.63, rel=1e-3)
    assert float(r.form_factor) == pytest.approx(1.156, abs=1e-3)
    assert kn(r.appendages) == pytest.approx(8.83, rel=2e-3)
    assert kn(r.wave) == pytest.approx(557.11, rel=2e-3)
    assert kn(r.bulb) == pytest.approx(0.049, rel=0.05)
    assert kn(r.transom) == pytest.approx(0.0, abs=1e-9)  # Fn_T > 5: the transom runs dry
    # The total: hullopt 1792.13 kN for the paper's 1793.26 kN (−0.063 %), measured and checked at that. The gap
    # is the paper's own arithmetic, not a different method: (1) it prints C_A = 0.000352 (the formula gives
    # 0.0003525, ours) but R_A = 221.98 kN, which needs C_A = 0.0003547 — ours is R_A = ½ρV²·S·C_A = 220.57 kN,
    # −1.41 kN; (2) its total uses 1 + k1 rounded to 1.156 (ours 1.15644: +0.39 kN on R_F(1 + k1)); (3) R_W
    # 556.98 vs 557.11 kN (−0.13 kN, −0.02 %: within the rounding of its printed c1, c2, c5, m1, m2, λ).
    # g = 9.81 instead of 9.80665 would not close it (1792.01 kN: Fn falls, and R_W with it).
    q = 0.5 * 1025.0 * (25 * KN) ** 2
    assert float(r.correlation) == pytest.approx(q * float(EXAMPLE.S) * float(r.ca), rel=1e-12)
    assert kn(r.correlation) == pytest.approx(220.57, abs=0.01)
    assert kn(r.total) == pytest.approx(1792.13, abs=0.01)
    assert kn(r.total) == pytest.approx(1793.26, rel=7e-4)  # −0.063 %
    # with the paper's R_A and its rounded 1 + k1 the rest agrees to −0.006 % (1793.15 kN)
    as_printed = kn(r.total) - kn(r.correlation) + 221.98 - kn(r.friction) * (float(r.form_factor) - 1.156)
    assert as_printed == pytest.approx(1793.26, rel=1e-4)
    for name, value, tol in [("cf", 0.001390, 2e-6), ("ca", 0.000352, 1e-6), ("c1", 1.398, 3e-3), ("c2", 0.7595, 5e-4),
                             ("c5", 0.9592, 5e-4), ("m1", -2.1274, 2e-3), ("m2", -0.17087, 5e-4), ("lam", 0.6513, 5e-4)]:
        assert float(getattr(r, name)) == pytest.approx(value, abs=tol), name


def test_resistance_rises_with_speed_and_is_differentiable():
    speeds = jnp.linspace(5, 25, 9) * KN
    total = np.asarray(holtrop_mennen(EXAMPLE, speeds).total)
    assert np.all(np.diff(total) > 0)
    check_grad(jax.jit(lambda v: holtrop_mennen(EXAMPLE, v).total / 1e6), np.array(20 * KN), rtol=1e-6)


@pytest.mark.slow
def test_inputs_from_a_wigley_hull():
    """Measured on the geometry: L, B, T, Cm = 2/3, Cwp = 2/3, lcb = 0, no transom or bulb, and the
    entrance angle of the parabolic waterline y = (B/2)(1 − (2ξ/L)²) over its last 5 %: atan(2B·0.95/L)."""
    hull = wigley(100.0, 10.0, 6.25, 10.0, n=81, m=51)
    h = jax.jit(holtrop_hull)(hull, 6.25)
    assert float(h.L) == pytest.approx(100.0) and float(h.B) == pytest.approx(10.0)
    assert float(h.cm) == pytest.approx(2 / 3, rel=3e-4) and float(h.cwp) == pytest.approx(2 / 3, rel=1e-9)
    assert float(h.lcb) == pytest.approx(0.0, abs=1e-9)
    assert float(h.A_T) == 0.0 and float(h.A_BT) == 0.0
    assert float(h.ie) == pytest.approx(np.degrees(np.arctan(2 * 10.0 * 0.95 / 100.0)), rel=1e-9)
    r = holtrop_mennen(h, 15 * KN)
    assert np.isfinite(float(r.total)) and float(r.total) > float(r.friction)
    g = jax.jit(jax.grad(lambda t: holtrop_mennen(holtrop_hull(hull, t), 15 * KN).total))(5.0)
    assert np.isfinite(float(g)) and float(g) > 0
