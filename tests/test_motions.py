"""Heave and pitch by strip theory (hullopt/waves/_motions.py): zero-speed RAOs of a Wigley hull (L/B 10,
B/T 1.6) against Capytaine 3D BEM (tests/data/wigley_capytaine_raos.json, made by
benchmarks/capytaine_reference.py), derivatives in the hull against central differences, and the KCS
added-resistance curve against the towing-tank range (issue 16)."""

import json
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.geometry import Sections
from hullopt.models import wigley
from hullopt.waves import motions

DATA = Path(__file__).parent / "data"
G = 9.80665


@pytest.fixture(scope="module")
def capytaine():
    return json.loads((DATA / "wigley_capytaine_raos.json").read_text())


@pytest.fixture(scope="module")
def wigley_raos(capytaine):
    """RAOs and their derivative in the beam scale s (y → s·y) at zero speed, one compiled forward pass."""
    ref = capytaine
    hull = wigley(ref["L"], ref["B"], ref["T"], 1.5 * ref["T"], n=41, m=41)
    omega = jnp.asarray(ref["omega"])

    def raos(scale, speed):
        s = Sections(x=hull.x, yz=hull.yz * jnp.asarray([scale, 1.0]), lpp=hull.lpp)
        m = motions(s, ref["T"], speed, omega, kg=ref["kg"], kyy=ref["kyy_over_L"])
        return jnp.stack([m.heave_rao, m.pitch_rao, m.r_awm / 1e5])

    fn = jax.jit(lambda s, u: jax.jvp(lambda q: raos(q, u), (s,), (jnp.ones_like(s),)))
    return lambda s, u: fn(jnp.asarray(s, dtype=float), jnp.asarray(u, dtype=float))


@pytest.mark.slow
def test_zero_speed_raos_match_capytaine(capytaine, wigley_raos):
    val, _ = wigley_raos(1.0, 0.0)
    lam = np.asarray(capytaine["lambda_over_l"])
    long = lam >= 0.8
    dh = np.abs(np.asarray(val[0]) - np.asarray(capytaine["heave"]))
    dp = np.abs(np.asarray(val[1]) - np.asarray(capytaine["pitch"]))
    assert dh[long].max() < 0.04  # measured 0.025 (λ/L 0.8)
    assert dp[long].max() < 0.03  # measured 0.015
    assert dh.max() < 0.06 and dp.max() < 0.03  # λ/L 0.5–0.7 too


def test_motions_derivative_in_the_hull_matches_central_differences(wigley_raos):
    u = 0.2 * np.sqrt(G * 100.0)
    _, tangent = wigley_raos(1.0, u)
    h = 1e-5
    fd = (wigley_raos(1.0 + h, u)[0] - wigley_raos(1.0 - h, u)[0]) / (2 * h)
    assert np.all(np.isfinite(np.asarray(tangent)))
    np.testing.assert_allclose(np.asarray(tangent), np.asarray(fd), rtol=1e-5, atol=1e-6)


def test_n_strips_must_be_odd():
    from hullopt.errors import HullError

    with pytest.raises(HullError, match="n_strips"):
        motions(wigley(100.0, 10.0, 6.25, 9.0, n=21, m=11), 6.25, 0.0, [0.8], n_strips=24)


@pytest.mark.slow
def test_sea_state_motion_part_from_knots_matches_the_direct_quadrature():
    # The objective's motion part interpolates R_AWM from 20 λ/L knots (motion_response); against strip theory
    # at every node of the order-8 spectral quadrature (144 solves). (Pointwise, midway between knots, the
    # spline is within 7 % of the peak at the Wigley's sharp peak; the errors cancel in the mean.)
    from hullopt.waves import mean_added_resistance

    hull = wigley(100.0, 10.0, 6.25, 9.0, n=21, m=11)
    knotted, direct = (jax.jit(lambda h, k=k: mean_added_resistance("nmri", h, 6.25, 7.7, 3.0, 9.0,
                                                                   motion_knots=k).motion)(hull) for k in (20, None))
    assert float(knotted) == pytest.approx(float(direct), rel=0.005)  # measured -0.13 %


@pytest.mark.parametrize("draft", [6.25, 6.1])
@pytest.mark.slow
def test_draft_derivative_matches_central_differences_on_and_between_section_points(draft):
    # The builtin Wigley's sections have a point at z = 6.25 (its design draft): there the immersed shape has a
    # kink, and the derivative is the mean of the one-sided ones, what central differences measure (before the
    # fix AD missed the segment above the point: 73 400 vs 127 000 N/m here). 6.1 lies between points.
    from helpers import check_grad

    hull = wigley(100.0, 10.0, 6.25, 10.0, n=21, m=21)
    omega = jnp.sqrt(2 * jnp.pi * G / (0.9 * 100.0))
    f = jax.jit(lambda t: motions(hull, t, 0.2 * np.sqrt(G * 100.0), omega[None]).r_awm[0])
    check_grad(f, draft, rtol=2e-5, h=1e-6)


@pytest.mark.slow
def test_wigley_motions_converge_with_strips():
    # The Wigley ends in a point at both ends: no transom terms. (They were taken from the first wet strip,
    # one of 16 % of the maximum breadth with 25 strips: pitch moved 1.2 % and R_AWM 2.4 % from 25 to 101.)
    hull = wigley(100.0, 10.0, 6.25, 10.0, n=41, m=41)
    omega = jnp.sqrt(2 * jnp.pi * G / (jnp.asarray([1.0, 1.2, 1.5]) * 100.0))
    run = jax.jit(lambda n: motions(hull, 6.25, 0.3 * np.sqrt(G * 100.0), omega, n_strips=n), static_argnums=0)
    coarse, fine = run(25), run(101)
    for q in ("heave_rao", "pitch_rao"):
        np.testing.assert_allclose(getattr(coarse, q), getattr(fine, q), rtol=0.003)  # measured 0.1 %
    np.testing.assert_allclose(coarse.r_awm, fine.r_awm, rtol=0.01)  # measured 0.1 %
