"""hullopt vs ship_model_lib (SINTEF's open ship model library, `pip install ship-model-lib`): STAWAVE-2 and SNNM
added resistance of the KCS, values and timings (issue 18 item 5).

Both libraries get the same particulars — ours, measured on the KCS mesh (×31.6, Lpp 230 m, 61 stations) at the
design draft 10.8 m: B_wl, C_B on Lpp·B_wl·T, and SNNM's entrance and run lengths (to 99 % of the breadth) — and
the same g = 9.81 m/s² (ship_model_lib's constant), ρ = 1025 kg/m³, k_yy = 0.25 Lpp, U = Fn 0.26 (24 kn), head
seas. Compared:

1. σ_aw = R_AW/(ρgζ²B²/L) in regular waves at λ/L 0.3 … 2, motion and reflection parts apart;
2. the STAWAVE-2 reflection coefficient α_T(1.5kT) against scipy's modified Bessel functions I₁, K₁ (ITTC
   7.5-04-01-01.1 / ISO 15016: α_T = π²I₁²/(π²I₁² + K₁²)), and what ship_model_lib evaluates instead;
3. the mean added resistance in a sea state (H_s 4 m, T_p 10 s; ITTC 1978 spectrum with T₁ = 0.7717 T_p, which
   is our Bretschneider form in T_p) — STAWAVE-2 long-crested, SNNM short-crested (cos² spreading), each to the
   cut-off ship_model_lib integrates to (wave periods ≥ 2 s and ≥ 3 s);
4. the time of each: ours jitted and warm, theirs as called (numpy/scipy).

Run: ``cd benchmarks && ../.venv/bin/python bench_peers.py``; results in results/peers.json. Needs the ``bench``
extra and ``pip install --no-deps ship-model-lib==1.0.2`` (``make bench`` does both); without ship_model_lib the
script says so and exits 0.
"""

from __future__ import annotations

import time

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402
from _common import HULLS, goal, save, timeit  # noqa: E402
from scipy import integrate, special  # noqa: E402

from hullopt.waves import mean_added_resistance, particulars, snnm, stawave2  # noqa: E402
from hullopt.waves import alpha_t as our_alpha_t  # noqa: E402

G, RHO = 9.81, 1025.0  # ship_model_lib's constants (it has g = 9.81)
KN = 0.5144  # ship_model_lib's knot [m/s]
DRAFT, FN, KYY = 10.8, 0.26, 0.25
LAMBDA_OVER_L = np.array([0.3, 0.5, 0.7, 0.9, 1.0, 1.1, 1.2, 1.3, 1.4, 1.6, 2.0])
HS, TP = 4.0, 10.0
T1 = TP * (691.0 / (1.25 * (2 * np.pi) ** 4)) ** 0.25  # ITTC 1978's B = 691/T1⁴ equal to Bretschneider's 5ωp⁴/4


def kcs():
    from hullopt.study import load_hull

    return load_hull(str(HULLS / "kcs_model_closed_from_igs.stl.gz") + "?scale=31.6&lpp=230&n=61").sections


def rel(a, b):
    """Largest |a − b| over the largest |b| (relative to the curve's scale, not pointwise)."""
    return float(np.max(np.abs(np.asarray(a) - np.asarray(b))) / np.max(np.abs(np.asarray(b))))


def main() -> None:
    try:
        from ship_model_lib.added_resistance import AddedResistanceBySNNM, AddedResistanceByStaWave2
        from ship_model_lib.operation_profile_structure import Weather
        from ship_model_lib.ship_dimensions import ShipDimensionsAddedResistance
    except ImportError:
        print("ship_model_lib is not installed: pip install --no-deps ship-model-lib==1.0.2 (make bench does); "
              "skipped")
        return
    import logging

    logging.getLogger("ship_model_lib").setLevel(logging.ERROR)  # its range warnings (Lpp ≤ 350 m etc.)

    sections = kcs()
    p = jax.jit(particulars)(sections, DRAFT)
    lpp, b, t, cb = (float(v) for v in (p.lpp, p.beam, p.draft, p.cb))
    l_e, l_r = float(p.l_entrance), float(p.l_run)
    u = FN * np.sqrt(G * lpp)
    v_kn = u / KN
    omega = np.sqrt(2 * np.pi * G / (LAMBDA_OVER_L * lpp))
    scale = RHO * G * b**2 / lpp  # σ_aw = R_AW/(ρgζ²B²/L), ζ = 1 m
    print(f"KCS at T {t} m: Lpp {lpp:.1f} m, B {b:.3f} m, C_B {cb:.4f}, L_E {l_e:.2f} m, L_R {l_r:.2f} m; "
          f"U {u:.3f} m/s (Fn {FN}), g {G}")

    dims = ShipDimensionsAddedResistance(b_beam_m=b, lpp_length_between_perpendiculars_m=lpp, cb_block_coefficient=cb,
                                         ta_draft_aft_m=t, tf_draft_forward_m=t, lwl_length_water_line_m=lpp,
                                         kyy_radius_gyration_in_lateral_direction_non_dim=KYY)
    sw2 = AddedResistanceByStaWave2(dims)
    sn = AddedResistanceBySNNM(dims, length_of_entrance=l_e, length_of_run=l_r)

    class StaWave2IK(AddedResistanceByStaWave2):
        """ship_model_lib's STAWAVE-2 with the standard's modified Bessel functions I₁, K₁ in α_T."""

        def _get_alpha1(self, *, omega_rad_per_s, speed_m_per_s):
            x = 1.5 * omega_rad_per_s**2 / G * self.ship_dimension.tm_draft_mid_m
            i1, k1 = special.iv(1, x), special.kv(1, x)
            return np.pi**2 * i1**2 / (np.pi**2 * i1**2 + k1**2) * self._get_f1(speed_m_per_s=speed_m_per_s)

    class SNNMFolded(AddedResistanceBySNNM):
        """ship_model_lib's SNNM with the wave angle folded into [0, π] for the reflection part too (as it
        does for the motion part): as shipped, waves from 180°…360° (one bow's half of the spreading) reflect
        nothing."""

        def _get_non_dimensional_wave_resistance_due_to_reflection(self, *, wave_frequency_rad_per_s,
                                                                    wave_incident_angle_rad, vessel_speed_kn):
            a = wave_incident_angle_rad % (2 * np.pi)
            return super()._get_non_dimensional_wave_resistance_due_to_reflection(
                wave_frequency_rad_per_s=wave_frequency_rad_per_s,
                wave_incident_angle_rad=2 * np.pi - a if a > np.pi else a, vessel_speed_kn=vessel_speed_kn)

    sw2_ik = StaWave2IK(dims)
    sn_folded = SNNMFolded(dims, length_of_entrance=l_e, length_of_run=l_r)
    unit = Weather(significant_wave_height_m=1.0, mean_wave_period_s=T1)  # their regular-wave parts scale with H_s²

    def theirs_regular():
        s2m = np.array([sw2.get_resistance_due_to_motion(omega_rad_per_s=w, speed_m_per_s=u, weather=unit)[0]
                        for w in omega]) / scale
        s2r = np.array([sw2.get_resistance_due_to_reflection(omega_rad_per_s=w, speed_m_per_s=u, weather=unit)[0]
                        for w in omega]) / scale
        snm = sn._get_non_dimensional_wave_resistance_due_to_motion(
            wave_frequency_rad_per_s=omega, wave_incident_angle_rad=0.0, vessel_speed_kn=v_kn)
        snr = sn._get_non_dimensional_wave_resistance_due_to_reflection(
            wave_frequency_rad_per_s=omega, wave_incident_angle_rad=0.0, vessel_speed_kn=v_kn)[0]
        return {"stawave2": (s2m, s2r), "snnm": (snm, snr)}

    @jax.jit
    def ours_regular(p, om):
        a = stawave2(p, u, om, 0.0, 1.0, KYY, RHO, G)
        c = snnm(p, u, om, 0.0, 1.0, KYY, RHO, G)
        return {"stawave2": (a.motion / scale, a.reflection / scale),
                "snnm": (c.motion / scale, c.reflection / scale)}

    om = jnp.asarray(omega)
    ours = jax.tree.map(np.asarray, ours_regular(p, om))
    t_ours_reg = timeit(lambda: jax.block_until_ready(ours_regular(p, om)), 21)
    theirs = theirs_regular()
    t_theirs_reg = timeit(theirs_regular, 5)

    regular = {"lambda_over_l": LAMBDA_OVER_L.tolist()}
    print(f"\nσ_aw in regular head waves (ours / ship_model_lib)\n{'λ/L':>5} " + " ".join(
        f"{k:>17}" for k in ("STAWAVE-2 motion", "STAWAVE-2 refl.", "SNNM motion", "SNNM refl.")))
    for i, lam in enumerate(LAMBDA_OVER_L):
        cells = [f"{ours[m][j][i]:8.3f}/{theirs[m][j][i]:<8.3f}" for m in ("stawave2", "snnm") for j in (0, 1)]
        print(f"{lam:5.2f} " + " ".join(cells))
    for m in ("stawave2", "snnm"):
        regular[m] = {
            "ours": {"motion": ours[m][0].round(5).tolist(), "reflection": ours[m][1].round(5).tolist()},
            "ship_model_lib": {"motion": np.asarray(theirs[m][0]).round(5).tolist(),
                               "reflection": np.asarray(theirs[m][1]).round(5).tolist()},
            "max_rel_difference_motion": rel(ours[m][0], theirs[m][0]),
            "max_rel_difference_reflection": rel(ours[m][1], theirs[m][1]),
        }
        print(f"{m}: max difference over the curve's peak, motion {regular[m]['max_rel_difference_motion']:.1e}, "
              f"reflection {regular[m]['max_rel_difference_reflection']:.1e}")
    print(f"regular waves, all four curves at {len(omega)} λ: ours {t_ours_reg * 1e3:.3f} ms (jitted, warm), "
          f"ship_model_lib {t_theirs_reg * 1e3:.1f} ms")

    # STAWAVE-2's reflection coefficient: the standard's modified Bessel functions vs ship_model_lib's J₁, Y₁
    x = 1.5 * omega**2 / G * t
    i1, k1 = special.iv(1, x), special.kv(1, x)
    alpha_std = np.pi**2 * i1**2 / (np.pi**2 * i1**2 + k1**2)
    j1, y1 = special.jv(1, x), special.yv(1, x)
    alpha_jy = np.pi**2 * j1**2 / (np.pi**2 * j1**2 + y1**2)
    alpha_ours = np.asarray(jax.jit(our_alpha_t)(jnp.asarray(x)))
    f1 = 0.692 * (u / np.sqrt(t * G)) ** 0.769 + 1.81 * cb**6.95
    theirs_alpha = np.asarray(theirs["stawave2"][1]) * scale / (0.5 * RHO * G * b * f1)
    alpha = {"x_1p5kT": x.round(5).tolist(), "ittc_I1_K1": alpha_std.tolist(), "ours": alpha_ours.tolist(),
             "ship_model_lib": theirs_alpha.tolist(), "J1_Y1": alpha_jy.tolist(),
             "ours_vs_ittc": float(np.max(np.abs(alpha_ours / alpha_std - 1))),
             "ship_model_lib_vs_J1_Y1": float(np.max(np.abs(theirs_alpha / alpha_jy - 1)))}
    print(f"α_T(1.5kT): ours vs scipy I₁,K₁ {alpha['ours_vs_ittc']:.1e}; ship_model_lib equals J₁,Y₁ (ordinary "
          f"Bessel functions, not the standard's I₁,K₁) to {alpha['ship_model_lib_vs_J1_Y1']:.1e}: "
          f"α_T {alpha_std.min():.3f}…{alpha_std.max():.3f} by the standard, "
          f"{alpha_jy.min():.3f}…{alpha_jy.max():.3f} theirs")

    # sea-state means
    def ours_mean_fn(method, omega_max, spreading_s, heading=0.0):
        return jax.jit(lambda s: mean_added_resistance(method, s, DRAFT, u, HS, TP, heading, spectrum="pm",
                                                       spreading_s=spreading_s, omega_max=omega_max, kyy=KYY,
                                                       rho=RHO, g=G).total)

    sea = Weather(significant_wave_height_m=HS, mean_wave_period_s=T1, wave_direction_deg=0.0)
    cases = {
        "stawave2_long_crested": (ours_mean_fn("stawave2", 2 * np.pi / 2.0, None),
                                  lambda: sw2.get_added_resistance_newton(v_kn, sea)[0],
                                  lambda: sw2_ik.get_added_resistance_newton(v_kn, sea)[0]),
        "snnm_short_crested_cos2": (ours_mean_fn("snnm", 2 * np.pi / 3.0, 1.0),
                                    lambda: sn.get_added_resistance_newton(v_kn, sea, heading_deg=0.0)[0],
                                    lambda: sn_folded.get_added_resistance_newton(v_kn, sea, heading_deg=0.0)[0]),
    }
    means = {}
    for name, (fo, ft, fc) in cases.items():
        t0 = time.perf_counter()
        r_ours = float(fo(sections))
        t_compile = time.perf_counter() - t0
        t_o = timeit(lambda fo=fo: jax.block_until_ready(fo(sections)), 21)
        r_theirs = float(ft())
        t_t = timeit(ft, 3)
        r_fixed = float(fc())
        means[name] = {"ours_kN": r_ours / 1e3, "ship_model_lib_kN": r_theirs / 1e3,
                       "ship_model_lib_corrected_kN": r_fixed / 1e3, "rel_difference": r_ours / r_theirs - 1,
                       "rel_difference_corrected": r_ours / r_fixed - 1, "ours_ms": t_o * 1e3,
                       "ours_compile_s": t_compile, "ship_model_lib_ms": t_t * 1e3}
        print(f"{name}: ours {r_ours / 1e3:.1f} kN in {t_o * 1e3:.3f} ms (compile {t_compile:.1f} s), "
              f"ship_model_lib {r_theirs / 1e3:.1f} kN in {t_t * 1e3:.1f} ms: {r_ours / r_theirs - 1:+.1%}; "
              f"corrected {r_fixed / 1e3:.1f} kN: {r_ours / r_fixed - 1:+.2%}")
    # The short-crested mean's direction integral on a fine grid: our long-crested means at 801 headings,
    # Simpson over θ with D(θ) = (2/π)cos²θ (the SNNM reflection switches terms on and off at α = E1, E2, so a
    # Gauss rule over θ converges slowly)
    theta = np.linspace(-0.5 * np.pi, 0.5 * np.pi, 801)
    r_theta = jax.jit(jax.vmap(lambda th: mean_added_resistance("snnm", sections, DRAFT, u, HS, TP, th, spectrum="pm",
                                                              omega_max=2 * np.pi / 3.0, kyy=KYY, rho=RHO,
                                                              g=G).total))(jnp.asarray(theta))
    fine = float(integrate.simpson(np.asarray(r_theta) * 2 / np.pi * np.cos(theta) ** 2, x=theta))
    m = means["snnm_short_crested_cos2"]
    m["fine_direction_integral_kN"] = fine / 1e3
    m["ours_vs_fine"] = m["ours_kN"] * 1e3 / fine - 1
    m["ship_model_lib_corrected_vs_fine"] = m["ship_model_lib_corrected_kN"] * 1e3 / fine - 1
    print(f"SNNM short-crested, the direction integral on a fine grid (801 headings): {fine / 1e3:.1f} kN; ours "
          f"(default rule, split at its kinks) {m['ours_vs_fine']:+.2%}, ship_model_lib corrected "
          f"{m['ship_model_lib_corrected_vs_fine']:+.2%}")

    s2, sn_ = regular["stawave2"], regular["snnm"]
    goals = [
        goal("STAWAVE-2 motion part σ_aw vs ship_model_lib (KCS, 11 λ)", s2["max_rel_difference_motion"], "rel.",
             "≤ 1e-3", s2["max_rel_difference_motion"] <= 1e-3, "ship_model_lib 1.0.2"),
        goal("SNNM motion part σ_aw vs ship_model_lib", sn_["max_rel_difference_motion"], "rel.", "≤ 1e-3",
             sn_["max_rel_difference_motion"] <= 1e-3, "ship_model_lib 1.0.2"),
        goal("SNNM reflection part σ_aw vs ship_model_lib", sn_["max_rel_difference_reflection"], "rel.", "≤ 1e-3",
             sn_["max_rel_difference_reflection"] <= 1e-3, "ship_model_lib 1.0.2"),
        goal("STAWAVE-2 α_T vs scipy's I₁, K₁ (ITTC); ship_model_lib uses J₁, Y₁", alpha["ours_vs_ittc"], "rel.",
             "≤ 1e-9", alpha["ours_vs_ittc"] <= 1e-9,
             f"ship_model_lib reflection differs by {s2['max_rel_difference_reflection']:.0%} of its peak"),
    ]
    m2, ms_ = means["stawave2_long_crested"], means["snnm_short_crested_cos2"]
    goals += [
        goal("STAWAVE-2 mean R_AW (H_s 4 m, T_p 10 s) vs ship_model_lib with I₁, K₁", m2["rel_difference_corrected"],
             "rel.", "≤ 1e-2", abs(m2["rel_difference_corrected"]) <= 1e-2,
             f"as shipped {m2['ship_model_lib_kN']:.1f} kN, ours {m2['ours_kN']:.1f} kN"),
        goal("SNNM short-crested mean vs a fine direction integral", ms_["ours_vs_fine"], "rel.", "≤ 1e-2",
             abs(ms_["ours_vs_fine"]) <= 1e-2,
             f"as shipped {ms_['ship_model_lib_kN']:.1f} kN; folded {ms_['ship_model_lib_corrected_vs_fine']:+.1%}"),
        goal("STAWAVE-2 sea-state mean, warm", round(m2["ours_ms"], 3), "ms", "faster than the peer",
             m2["ours_ms"] < m2["ship_model_lib_ms"], f"{m2['ship_model_lib_ms']:.1f} ms"),
        goal("SNNM short-crested sea-state mean, warm", round(ms_["ours_ms"], 3), "ms", "faster than the peer",
             ms_["ours_ms"] < ms_["ship_model_lib_ms"], f"{ms_['ship_model_lib_ms']:.1f} ms"),
    ]
    out = {"hull": "KCS ×31.6, Lpp 230 m, 61 stations", "particulars": {"lpp": lpp, "beam": b, "draft": t, "cb": cb,
           "l_entrance": l_e, "l_run": l_r}, "speed": u, "g": G, "kyy": KYY, "hs": HS, "tp": TP, "t1": T1,
           "regular_head_waves": regular, "alpha_t": alpha, "sea_state_means": means,
           "regular_ms": {"ours": t_ours_reg * 1e3, "ship_model_lib": t_theirs_reg * 1e3}, "goals": goals}
    print(save("peers", out))


if __name__ == "__main__":
    main()
