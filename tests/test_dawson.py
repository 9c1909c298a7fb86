"""Dawson's method (hullopt.resistance._dawson): the upstream difference's exactness, Havelock's submerged sphere
(closed form) approached as the free-surface grid is refined, the Wigley's convergence with the grid, the Wigley,
KCS and DTMB 5415 models against the towing tank, and gradients against central differences."""

import csv
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import quad

from hullopt.constants import G, RHO_SEA
from hullopt.errors import HullError
from hullopt.geometry import wetted_surface
from hullopt.models import box, load_hull, wigley
from hullopt.resistance import (Panels, calm_water, dawson_flow, dawson_wave_resistance, free_surface, holtrop_hull,
                                transom_caveat)
from hullopt.resistance._dawson import _upstream_d, hull_surface, transom, waterline
from hullopt.resistance._panel import hull_panels

from helpers import fd_grad
from test_panel import _half_sphere, eqx_scale

DATA = Path(__file__).parent / "data"
HULLS = Path(__file__).parents[1] / "examples" / "hulls"


@pytest.mark.parametrize("points", [2, 3, 4])
def test_upstream_difference_is_exact_for_polynomials(points):
    """On uneven spacing the weights differentiate polynomials of degree points − 1 exactly from the node and
    the points upstream of it (the first nodes' missing points are the undisturbed stream, 0)."""
    s = jnp.cumsum(jnp.array([0.0, 1.0, 1.3, 0.7, 1.1, 0.9, 1.2]))
    w = np.asarray(_upstream_d(s, points))
    f, df = (lambda x: 1.0 + 2.0 * x - 0.3 * x**2 + 0.05 * x**3), (lambda x: 2.0 - 0.6 * x + 0.15 * x**2)
    if points < 4:
        f, df = (lambda x: 1.0 + 2.0 * x - 0.3 * x**2 * (points > 2)), (lambda x: 2.0 - 0.6 * x * (points > 2))
    v = f(np.asarray(s))
    for i in range(points - 1, len(s)):
        assert w[i] @ v[i - np.arange(points)] == pytest.approx(df(float(s[i])), rel=1e-10)


def _sphere_resistance(columns):
    """A unit sphere 3 m deep at 3 m/s (k₀f = 3.27) on a free surface from 1 wavelength ahead to 3 behind and 2
    beside: R_w by Dawson's method and by Havelock's (1932) closed form (a point doublet)."""
    u, f = 3.0, 3.0
    k0 = G / u**2
    lam = 2 * np.pi / k0
    pan = Panels(jnp.asarray(_half_sphere(1.0, 16, 8, -f)), jnp.array(0.0))
    r = 0.5 * RHO_SEA * u * u * float(dawson_flow(pan, free_surface(jnp.linspace(lam, -3 * lam, columns), 2 * lam, 0.0, 16),
                                                  jnp.array([k0])).drag[0])
    sec = lambda t: 1.0 / np.cos(t)  # noqa: E731
    want = 4 * np.pi * RHO_SEA * G * k0**3 * quad(lambda t: np.exp(-2 * k0 * f * sec(t) ** 2) * sec(t) ** 5,
                                                     0, np.pi / 2)[0]
    return r, want


@pytest.mark.slow
def test_sphere_approaches_havelock():
    """Deep down the double-body flow at the surface is the uniform stream, so Dawson's method is the Rankine
    source method of Kelvin's condition: R_w by pressure integration on the sphere approaches Havelock's closed
    form as the grid is refined (0.87 at 15 columns a wavelength, 0.94 at 22; the upstream difference's damping
    falls with the spacing; the inscribed panels' dipole is 2.7 % large)."""
    coarse, want = _sphere_resistance(61)
    fine, _ = _sphere_resistance(91)
    assert 0.8 < coarse / want < fine / want and abs(fine / want - 1) < 0.08


@pytest.mark.slow
def test_wigley_converges_with_the_grid():
    """Wigley (L 100, B 10, T 6.25 m) at Fn 0.3: C_W rises as the free-surface grid refines (less numerical
    damping), by less each time (measured +19 % from 64 to 96 columns, +5 % to 128, +5 % to 160); ζ is ahead of
    the bow ≈ 0 (no upstream waves)."""
    h = wigley(100.0, 10.0, 6.25, 10.0, n=61, m=33)
    u = 0.3 * np.sqrt(G * 100.0)
    res = [dawson_wave_resistance(h, 6.25, u, columns=c) for c in (64, 96, 128)]
    r = np.array([float(x.r_wave) for x in res])
    assert r[0] < r[1] < r[2] and r[2] - r[1] < 0.5 * (r[1] - r[0]) and r[2] / r[1] - 1 < 0.07
    z = np.asarray(res[1].zeta)
    assert np.abs(z[:5]).max() < 0.05 * np.abs(z).max()


def _rows(name):
    with open(DATA / name) as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


@pytest.mark.slow
def test_model_totals_against_the_tank():
    """Model C_T = (1 + k1)·C_F(ITTC-57) + C_W(Dawson) against the towing tank (tests/data/SOURCES.md): the KCS at
    Fn 0.26 (Tokyo 2015, case 2.1) and the DTMB 5415 (INSEAN/IIHR) at Fn 0.28 within 10 % — where the Kelvin panel
    method is +117 % on the KCS. The DTMB 5415 at Fn 0.41, with its dry transom, is low — measured −26 %, as the
    peer WARP's C_T is −21 % there (benchmarks/README.md): held in a bracket so a change shows. Without the
    dry-transom condition the DTMB 5415 was −15 % and −30 %."""
    kcs = [r for r in _rows("kcs_tokyo2015_resistance.csv") if r["case"] == "T2015_2.1" and float(r["Fn"]) == 0.26][0]
    dtmb = {float(r["Fn"]): float(r["value"]) for r in _rows("dtmb5415_resistance.csv") if r["quantity"] == "CT"}
    cases = [("kcs_model_closed_from_igs.stl.gz?scale=31.6&lpp=230", 10.8, 31.6, 1.27e-6,
              {0.26: (float(kcs["CT_x1e3"]) * 1e-3, (-0.10, 0.10))}),
             ("dtmb5415_navaltoolbox_fullscale.stl.gz?lpp=142", 6.15, 24.83, 1.14e-6,
              {0.28: (dtmb[0.28], (-0.10, 0.10)), 0.41: (dtmb[0.41], (-0.33, -0.19))})]
    for spec, t, scale, nu, tank in cases:
        h = load_hull(f"{HULLS}/{spec}").sections
        lpp = float(h.lpp)
        s = float(wetted_surface(h, t))
        fns = np.array(sorted(tank))
        u = fns * np.sqrt(G * lpp)
        cw = calm_water(h, t, jnp.asarray(u), "dawson")
        for i, fn in enumerate(fns):
            re = u[i] / np.sqrt(scale) * (lpp / scale) / nu
            ct = float(cw.form_factor) * 0.075 / (np.log10(re) - 2.0) ** 2 \
                + float(cw.r_wave[i]) / (0.5 * RHO_SEA * u[i] ** 2 * s)
            measured, (lo, hi) = tank[fn]
            assert lo < ct / measured - 1 < hi, (spec, fn, ct, measured)
            assert float(cw.r_wave[i]) > 0.0


@pytest.mark.slow
def test_wigley_against_insels_tank():
    """The Wigley fixed in sinkage and trim against Insel's (1990) towing tank (tests/data/SOURCES.md). His C_WP,
    from wave cuts, reads at or below the wave resistance: Dawson's C_W is 0.9–1.5× it at Fn 0.28–0.5 (measured
    0.96–1.46×; Michell's up to 2.5×, closer to it only at 0.32–0.35); the model's C_T = (1 + k1)·C_F + C_W is
    within 10 % of the measured C_T at Fn 0.41–0.5 (measured +4…+8 %; Michell +14…+18 %)."""
    rows = _rows("wigley_insel1990_resistance.csv")
    cwp = np.array([(float(r["Fn"]), float(r["value_x1e3"]) * 1e-3) for r in rows if r["quantity"] == "CWP"])
    ct = np.array([(float(r["Fn"]), float(r["value_x1e3"]) * 1e-3) for r in rows if r["quantity"] == "CT"])
    cwp = cwp[cwp[:, 0] >= 0.28]  # Insel: C_WP reads low below Fn ≈ 0.25, the waves a few millimetres high
    h = wigley(100.0, 10.0, 6.25, 10.0, n=61, m=33)
    u = np.concatenate([cwp[:, 0], ct[:, 0]]) * np.sqrt(G * 100.0)
    s = wetted_surface(h, 6.25)
    q = 0.5 * RHO_SEA * u**2 * float(s)
    cw = {m: np.asarray(calm_water(h, 6.25, jnp.asarray(u), m).r_wave) / q for m in ("dawson", "michell")}
    ratio = {m: c[: len(cwp)] / cwp[:, 1] for m, c in cw.items()}
    assert np.all((ratio["dawson"] > 0.9) & (ratio["dawson"] < 1.5)), ratio["dawson"]
    assert np.mean(abs(np.log(ratio["dawson"]))) < 0.6 * np.mean(abs(np.log(ratio["michell"])))  # 0.18 vs 0.39
    v = ct[:, 0] * np.sqrt(G * 1.8)  # Insel's model: L 1.8 m in fresh water at 15 °C (ν 1.141e-6 m²/s)
    cf = 0.075 / (np.log10(v * 1.8 / 1.141e-6) - 2.0) ** 2
    k1 = float(calm_water(h, 6.25, jnp.asarray(u[:1]), "holtrop").form_factor)
    err = {m: (k1 * cf + c[len(cwp):]) / ct[:, 1] - 1 for m, c in cw.items()}
    assert np.all(abs(err["dawson"]) < 0.10), err["dawson"]
    assert np.all(abs(err["dawson"]) < abs(err["michell"]))


@pytest.mark.slow
def test_a_free_wigley_sinks_and_trims_as_in_the_tank():
    """Free to sink and trim (``attitude`` iterations), the Wigley's model C_T at Fn 0.41–0.45 is within 5 % of
    Insel's free model (measured −1.6 … +1.7 %; fixed at its static draft −6 … −12 %) and its sinkage within 15 %
    of his (measured +2 … +5 %); two iterations are converged to 0.5 % (R_W)."""
    rows = _rows("wigley_insel1990_resistance.csv")
    ct = np.array([(float(r["Fn"]), float(r["value_x1e3"]) * 1e-3) for r in rows if r["quantity"] == "CT_free"])
    sink = np.array([(float(r["Fn"]), float(r["value_x1e3"]) * 1e-3) for r in rows
                     if r["quantity"] == "sinkage_over_T_free"])
    ct = ct[ct[:, 0] < 0.45]
    h = wigley(100.0, 10.0, 6.25, 10.0, n=61, m=33)
    u = jnp.asarray(ct[:, 0] * np.sqrt(G * 100.0))
    q = 0.5 * RHO_SEA * u**2 * wetted_surface(h, 6.25)
    run = {a: jax.jit(lambda h, u, a=a: dawson_wave_resistance(h, 6.25, u, attitude=a))(h, u) for a in (0, 2, 3)}
    v = ct[:, 0] * np.sqrt(G * 1.8)  # Insel's model: L 1.8 m in fresh water at 15 °C (ν 1.141e-6 m²/s)
    cf = 0.075 / (np.log10(v * 1.8 / 1.141e-6) - 2.0) ** 2
    k1 = float(calm_water(h, 6.25, u[:1], "holtrop").form_factor)
    err = {a: np.asarray(k1 * cf + r.r_wave / q) / ct[:, 1] - 1 for a, r in run.items()}
    assert np.all(abs(err[2]) < 0.05), err[2]
    assert np.all(err[0] < -0.05), err[0]  # the fixed hull misses the free one's resistance
    measured = np.interp(ct[:, 0], sink[:, 0], sink[:, 1])
    np.testing.assert_allclose(np.asarray(run[2].sinkage) / 6.25, measured, rtol=0.15)
    assert np.all(np.asarray(run[2].trim) > 0.0)  # bow up at these speeds, as the tank's
    np.testing.assert_allclose(run[2].r_wave, run[3].r_wave, rtol=5e-3)


@pytest.mark.slow
def test_kcs_waves_keep_to_kelvins_wedge():
    """KCS at 24 kn: R_w is the grid's, not its extent's — within 3 % on a free surface 1.5 L wide reaching 2 L
    behind (measured 0.6 %) — and the waves keep to Kelvin's wedge: outside 30° from the bow and 0.25 L out
    they are < 0.2 of the largest inside 19.47° (measured 0.17). With Φ_l a grid line's part of the double
    body's velocity instead of its speed, the grid's bends forced transverse waves across its whole width
    (outside: 1.3 m, 0.27 of inside; R_w 8–30 % with the extent)."""
    h = load_hull(f"{HULLS}/kcs_model_closed_from_igs.stl.gz?scale=31.6&lpp=230").sections
    u = 24 * 0.5144
    base = dawson_wave_resistance(h, 10.8, u)
    wide = dawson_wave_resistance(h, 10.8, u, columns=134, rows=18, downstream=2.0, width=1.5)
    assert float(wide.r_wave) / float(base.r_wave) == pytest.approx(1.0, abs=0.03)
    z, c = np.abs(np.asarray(base.zeta)), np.asarray(base.centres)
    behind = float(jnp.max(h.x)) - c[..., 0]
    angle = np.degrees(np.arctan2(c[..., 1], np.maximum(behind, 1e-9)))
    outside = (behind > 0) & (angle > 30.0) & (c[..., 1] > 0.25 * float(h.lpp))
    inside = (behind > 0) & (angle < 19.47)
    assert z[outside].max() < 0.2 * z[inside].max()


@pytest.mark.slow
@pytest.mark.parametrize("case", ["wigley", "dry transom", "free to sink and trim"])
def test_dawson_gradient_matches_differences(case):
    """dR_w/dT and dR_w/d(beam scale) by AD equal central differences: through the dense solve and the
    body-fitted grid (the Wigley at a draft between the sections' points, Fn 0.3); through the open hull, the wake
    grid and its transom start (a box 0.25 m deep, its transom dry at Fn 0.35: F_nT 5.4 > 5); and through two
    sinkage-and-trim iterations, each on the hull sheared by the last (the Wigley at Fn 0.42)."""
    # free: the sheared hull's waterline passes near the sections' points at some stations, where R_w's second
    # derivative jumps; the differences' own error there is 3e-4 at h 1e-5 (1e-3 at 1e-4), the beam's 1e-10
    hull, draft, fn, length, kw, rtol = {
        "wigley": (wigley(100, 10, 6.25, 10, n=41, m=33), 6.1, 0.3, 100.0, {}, 1e-4),
        "dry transom": (box(60.0, 8.0, 6.0, n=9), 0.25, 0.35, 60.0,
                        {"stations": 12, "girth": 4, "columns": 30, "rows": 6}, 1e-4),
        "free to sink and trim": (wigley(100, 10, 6.25, 10, n=41, m=33), 6.1, 0.42, 100.0, {"attitude": 2}, 1e-3),
    }[case]
    kw = {"stations": 16, "girth": 5, "columns": 40, "rows": 8} | kw
    u = fn * np.sqrt(G * length)
    f = jax.jit(lambda p: dawson_wave_resistance(eqx_scale(hull, p[1]), p[0], u, **kw).r_wave / 1e3)
    p = np.array([draft, 1.0])
    ad = np.asarray(jax.jit(jax.grad(f))(jnp.asarray(p)))
    fd = fd_grad(f, p, h=1e-5)
    np.testing.assert_allclose(ad, fd, rtol=rtol)


def test_low_speed_is_outside_its_validity():
    """Below FN_MIN (≈ 0.205: 10 grid columns a transverse wavelength 2πFn²L) the method says so, naming the
    Froude number; above it nothing is said of it."""
    from hullopt.resistance import holtrop_hull, outside_validity
    from hullopt.resistance._dawson import FN_MIN

    hull = holtrop_hull(wigley(100.0, 10.0, 6.25, 10.0, n=41, m=33), 6.25)
    assert FN_MIN == pytest.approx(0.2047, abs=1e-3)
    assert "Fn 0.15: below Fn 0.20" in outside_validity(hull, 0.3, 0.15)["dawson"]
    assert "dawson" not in outside_validity(hull, 0.3, 0.25) and "dawson" not in outside_validity(hull, 0.3)


def test_an_immersed_transom_is_named():
    """Dawson's dry-transom condition is an assumption the user is told of: the caveat names it on the DTMB 5415
    (A_T ≈ 4.6 m²) and is silent on the KCS, whose transom is clear of the water."""
    dtmb = holtrop_hull(load_hull(f"{HULLS}/dtmb5415_navaltoolbox_fullscale.stl.gz?lpp=142").sections, 6.15)
    kcs = holtrop_hull(load_hull(f"{HULLS}/kcs_model_closed_from_igs.stl.gz?scale=31.6&lpp=230").sections, 10.8)
    assert "immersed transom (A_T 4.6" in transom_caveat(dtmb) and transom_caveat(kcs) is None


@pytest.mark.parametrize("girth", [12, 48])
def test_a_transoms_lost_thrust_by_hand(girth):
    """A box's transom (B 10 m, T 4 m): the hydrostatic thrust a dry transom loses, ρg∫(T − z)dA = ρg·B·T²/2 —
    the panels cut the bilge corner, so within 2 % at 12 panels a girth and 0.5 % at 48; its depth is T, the
    run behind it flat; a hull without an immersed transom keeps its aft end closed and the condition off."""
    h, t = box(100.0, 10.0, 8.0, n=5), 4.0
    hull = hull_panels(h, t, 16, girth)
    main, wake = hull_surface(hull, 16, girth, 40, 8)
    opened, dry = transom(hull, wake, 16, girth, True)
    thrust = 2.0 * float(jnp.sum(dry.head * dry.area))
    assert thrust == pytest.approx(10.0 * t**2 / 2.0, rel=0.02 if girth == 12 else 0.005)
    assert float(dry.greatest) == pytest.approx(t) and float(dry.slope) == pytest.approx(0.0, abs=1e-12)
    aft = slice(15 * girth, 16 * girth)
    assert float(jnp.sum(opened.real)) == float(jnp.sum(hull.real)) - float(jnp.sum(hull.real[aft]))  # gone
    assert float(jnp.sum(opened.real[aft])) == 0.0 and float(jnp.sum(hull.real[aft])) > 0.0
    closed, off = transom(hull, wake, 16, girth, False)
    assert np.array_equal(np.asarray(closed.vertices), np.asarray(hull.vertices)) and float(off.area.sum()) == 0.0


@pytest.mark.slow
def test_a_hull_without_a_transom_is_as_before():
    """On a hull without an immersed transom (the Wigley) the wake grid carries no sources: R_w is the main
    grid's alone (its inner edge behind the stern moved 10⁻³ L out), within 0.5 %."""
    h = wigley(100, 10, 6.25, 10, n=41, m=33)
    u = 0.3 * np.sqrt(G * 100.0)
    r = float(dawson_wave_resistance(h, 6.25, u, stations=24, girth=6, columns=60, rows=10).r_wave)
    hull = hull_panels(h, 6.25, 24, 6)
    main = free_surface(np.asarray(hull_surface(hull, 24, 6, 60, 10)[0].nodes[:, 0, 0]), 100.0, 6.25, 10,
                        waterline(hull, 24, 6))
    alone = 0.5 * RHO_SEA * u * u * float(dawson_flow(hull, main, jnp.array([G / u**2])).drag[0])
    assert r == pytest.approx(alone, rel=0.005)


@pytest.mark.slow
def test_dtmb_transom_converges_with_the_grid():
    """The DTMB 5415 at Fn 0.28 with its dry transom: C_W on 64, 96 and 128 free-surface columns rises by
    shrinking steps (measured 0.484, 0.535, 0.550 × 10⁻³: +10.5 %, +2.8 %) and is the same on twice the rows
    (14 → 27: 0.535 → 0.536) — the wake grid's three rows across the transom resolve it."""
    h = load_hull(f"{HULLS}/dtmb5415_navaltoolbox_fullscale.stl.gz?lpp=142").sections
    u = 0.28 * np.sqrt(G * float(h.lpp))
    cw = [float(dawson_wave_resistance(h, 6.15, u, columns=c).r_wave) for c in (64, 96, 128)]
    assert 0.0 < abs(cw[2] - cw[1]) < 0.5 * abs(cw[1] - cw[0])
    assert abs(cw[2] / cw[1] - 1.0) < 0.05
    rows = float(dawson_wave_resistance(h, 6.15, u, rows=27).r_wave)
    assert rows == pytest.approx(cw[1], rel=0.02)


@pytest.mark.parametrize("kw", [{"columns": 4}, {"rows": 2}, {"width": 0.0}, {"downstream": -1.0},
                                {"attitude": -1}])
def test_a_bad_grid_is_one_clear_error(kw):
    h = wigley(100.0, 10.0, 6.25, 10.0, n=21, m=9)
    with pytest.raises(HullError, match=f"dawson: .*{next(iter(kw))}"):
        dawson_wave_resistance(h, 6.25, 9.0, **kw)
