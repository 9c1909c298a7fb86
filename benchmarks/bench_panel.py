"""The panel methods' validation and speed (Kelvin's hull-panel method and Dawson's): the Wigley against
Michell's integral (and the thin-ship limit) and against Insel's (1990) measured C_WP and C_T, the KCS and DTMB
5415 models against towing-tank C_T, sinkage and trim (tests/data, see SOURCES.md there), Dawson's KCS C_W on
three free-surface grids, the Series 60 C_B 0.60 by every method side by side (no tank figure was reachable),
and the time of one evaluation at the default grid (value; value + gradient; compile) and of a design in a
vmapped batch (64 on a GPU, 4 on the CPU), with a figure. ``--speed`` or ``--quick``: the speed rows alone,
``--series60`` its rows alone, merged into the results file (a GPU's run: the validation's numbers do not
depend on the device).

Model-scale totals: C_T = (1 + k1)·C_F(ITTC-57, the model's Re) + C_W(method), Holtrop's 1 + k1, no C_A (a
model has none). Writes ``results/panel.json`` and ``results/panel.png``.
"""

from __future__ import annotations

import csv
import sys
import time
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
from _common import HULLS, RESULTS, goal, merge, quick, save, suffix, timeit

jax.config.update("jax_enable_x64", True)

from hullopt.constants import G  # noqa: E402
from hullopt.models import load_hull, wigley  # noqa: E402
from hullopt.resistance import (calm_water, dawson_wave_resistance, michell_wave_resistance,  # noqa: E402
                                panel_wave_resistance, wave_resistance_coefficient)
from hullopt.geometry import Sections, wetted_surface  # noqa: E402

DATA = Path(__file__).resolve().parents[1] / "tests" / "data"
RHO_FRESH, NU_KCS = 999.5, 1.27e-6  # the KCS tank (Tokyo 2015 case 2.1)


def _cf(re):
    return 0.075 / (np.log10(re) - 2.0) ** 2


def wigley_curves():
    """C_W of the Wigley (L 100, B 10, T 6.25 m) by the panel method and Michell, Fn 0.2–0.45, and the thin
    Wigley's (B 2 m) ratio panel/Michell."""
    fns = np.round(np.arange(0.2, 0.4501, 0.025), 3)
    out = {"fn": fns.tolist()}
    for b, key in ((10.0, "wigley"), (2.0, "thin")):
        h = wigley(100.0, b, 6.25, 10.0, n=61, m=33)
        u = jnp.asarray(fns * np.sqrt(G * 100.0))
        s = wetted_surface(h, 6.25)
        p = panel_wave_resistance(h, 6.25, u)
        rm = michell_wave_resistance(h, 6.25, u)
        rd = dawson_wave_resistance(h, 6.25, u).r_wave
        out[key] = {"cw_panel": np.asarray(wave_resistance_coefficient(p.r_wave, u, s)).tolist(),
                    "cw_dawson": np.asarray(wave_resistance_coefficient(rd, u, s)).tolist(),
                    "cw_michell": np.asarray(wave_resistance_coefficient(rm, u, s)).tolist(),
                    "sinkage_over_l": (np.asarray(p.sinkage) / 100.0).tolist()}
    return out


def wigley_tank():
    """The Wigley's C_W by Dawson's method and Michell's at the speeds of Insel's (1990) fixed model C2-FX (L 1.8 m,
    fresh water at 15 °C) against his measured wave-pattern resistance C_WP, and the model's C_T = (1 + k1)·C_F +
    C_W against his measured C_T (tests/data/wigley_insel1990_resistance.csv)."""
    rows = _read("wigley_insel1990_resistance.csv")
    cwp = [(float(r["Fn"]), float(r["value_x1e3"]) * 1e-3) for r in rows if r["quantity"] == "CWP"]
    ct = [(float(r["Fn"]), float(r["value_x1e3"]) * 1e-3) for r in rows if r["quantity"] == "CT"]
    h = wigley(100.0, 10.0, 6.25, 10.0, n=61, m=33)
    fns = np.array([f for f, _ in cwp + ct])
    u = jnp.asarray(fns * np.sqrt(G * 100.0))
    s = wetted_surface(h, 6.25)
    cw = {m: np.asarray(wave_resistance_coefficient(r, u, s)) for m, r in (
        ("dawson", dawson_wave_resistance(h, 6.25, u).r_wave), ("michell", michell_wave_resistance(h, 6.25, u)))}
    k1 = float(calm_water(h, 6.25, u[:1], "holtrop").form_factor)
    v = np.array([f for f, _ in ct]) * np.sqrt(G * 1.8)
    cf = _cf(v * 1.8 / 1.141e-6)  # Insel's model: 1.8 m, ν 1.141e-6 m²/s (15 °C)
    n = len(cwp)
    return {"cwp": {"fn": [f for f, _ in cwp], "tank": [c for _, c in cwp],
                    **{m: c[:n].tolist() for m, c in cw.items()}},
            "ct": {"fn": [f for f, _ in ct], "tank": [c for _, c in ct], "cf": cf.tolist(), "form_factor": k1,
                   **{m: (k1 * cf + c[n:]).tolist() for m, c in cw.items()}}}


def _read(name):
    with open(DATA / name) as f:
        return [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]


def model_totals(spec, draft, scale, fn, nu, ct_tank, label):
    """C_T of a model by each method at ``fn`` against the tank's, the panel method's sinkage and trim."""
    h = load_hull(spec).sections
    lpp = float(h.lpp)
    u = float(fn) * np.sqrt(G * lpp)
    re = (u / np.sqrt(scale)) * (lpp / scale) / nu
    rec = {"hull": label, "fn": fn, "re_model": re, "cf_model": _cf(re), "ct_tank": ct_tank}
    s = float(wetted_surface(h, draft))
    for m in ("holtrop", "michell", "panel", "dawson"):
        cw = calm_water(h, draft, u, m)
        c_w = float(cw.r_wave) / (0.5 * 1025.0 * u * u * s)
        rec[f"cw_{m}"] = c_w
        rec[f"ct_{m}"] = float(cw.form_factor) * _cf(re) + c_w
        if m == "panel":
            rec["sinkage_model_m"] = float(cw.sinkage) / scale
            rec["trim_deg"] = float(np.degrees(cw.trim))
        if m == "dawson":
            rec["sinkage_dawson_model_m"] = float(cw.sinkage) / scale
            rec["trim_dawson_deg"] = float(np.degrees(cw.trim))
    rec["form_factor"] = float(cw.form_factor)
    return rec


def dawson_grid(spec, draft, fn, columns=(64, 96, 128)):
    """Dawson's C_W of a hull at ``fn`` on free-surface grids of ``columns`` nodes along the stream."""
    h = load_hull(spec).sections
    u = fn * np.sqrt(G * float(h.lpp))
    s = wetted_surface(h, draft)
    return {"columns": list(columns), "cw": [float(wave_resistance_coefficient(
        dawson_wave_resistance(h, draft, u, columns=c).r_wave, u, s)) for c in columns]}


def speed(method=panel_wave_resistance):
    """Time of one evaluation at the default grid (48 × 12 + ends hull panels; Dawson's free surface 95 × 13) on
    the KCS at 24 kn."""
    h = load_hull(f"{HULLS}/kcs_model_closed_from_igs.stl.gz?scale=31.6&lpp=230").sections
    u = 24 * 1852 / 3600
    f = jax.jit(lambda s: method(s, 10.8, u).r_wave)
    g = jax.jit(jax.value_and_grad(lambda s: method(s, 10.8, u).r_wave))
    t0 = time.perf_counter()
    jax.block_until_ready(f(h))
    compile_value = time.perf_counter() - t0
    t0 = time.perf_counter()
    jax.block_until_ready(g(h))
    compile_grad = time.perf_counter() - t0
    tv = timeit(lambda: jax.block_until_ready(f(h)), 5)
    tg = timeit(lambda: jax.block_until_ready(g(h)), 5)
    return {"value_s": tv, "value_grad_s": tg, "ratio": tg / tv, "compile_value_s": compile_value,
            "compile_grad_s": compile_grad}


def batch(method=dawson_wave_resistance, n=64):
    """Time a design in a jitted ``vmap`` over ``n`` KCS variants at 24 kn (beams scaled 0.97–1.03): issue 27's
    GPU goal is ≤ 50 ms a design at n = 64. Returns the batch's compile and warm times and the time a design."""
    h = load_hull(f"{HULLS}/kcs_model_closed_from_igs.stl.gz?scale=31.6&lpp=230").sections
    u = 24 * 1852 / 3600
    # vmapped in chunks of 16: a design's influence matrices take ~1.2 GB while they are built (64 at once: 76 GB)
    f = jax.jit(lambda bs: jax.lax.map(lambda b: method(Sections(h.x, h.yz * jnp.array([b, 1.0]), h.lpp), 10.8,
                                                         u).r_wave, bs, batch_size=min(n, 16)))
    beams = jnp.linspace(0.97, 1.03, n)
    t0 = time.perf_counter()
    jax.block_until_ready(f(beams))
    compile_s = time.perf_counter() - t0
    t = timeit(lambda: jax.block_until_ready(f(beams)), 3)
    return {"designs": n, "compile_s": compile_s, "batch_s": t, "per_design_s": t / n}


def speed_goals(t, td, tb):
    """The speed rows: one evaluation and value + gradient of each method, a design in a vmapped batch."""
    gpu = suffix() != ""
    return [goal("panel: one evaluation (KCS, 24 kn, 48×12 panels)", round(t["value_s"], 3), "s", "≤ 2",
                 t["value_s"] <= 2.0),
            goal("panel: value + gradient / value", round(t["ratio"], 2), "×", "≤ 4", t["ratio"] <= 4.0),
            goal("dawson: one evaluation (KCS, 24 kn, 48×12 hull + 95×13 free-surface panels)",
                 round(td["value_s"], 3), "s", "≤ 2", td["value_s"] <= 2.0),
            goal("dawson: value + gradient / value", round(td["ratio"], 2), "×", "≤ 4", td["ratio"] <= 4.0),
            goal(f"dawson: a design in a vmapped batch of {tb['designs']} (KCS variants)",
                 round(tb["per_design_s"], 4), "s", "≤ 0.05 (GPU, batch of 64)",
                 tb["per_design_s"] <= 0.05 if gpu and tb["designs"] >= 64 else None)]


def plot(w, tank, rows, path):
    from matplotlib.figure import Figure

    fig = Figure(figsize=(11, 4))
    a, b = fig.subplots(1, 2)
    a.plot(w["fn"], np.array(w["wigley"]["cw_panel"]) * 1e3, "o-", label="panel")
    a.plot(w["fn"], np.array(w["wigley"]["cw_michell"]) * 1e3, "s--", label="Michell")
    a.plot(w["fn"], np.array(w["wigley"]["cw_dawson"]) * 1e3, "^-", label="Dawson")
    a.plot(tank["cwp"]["fn"], np.array(tank["cwp"]["tank"]) * 1e3, "kx", label="tank C_WP (Insel 1990, fixed)")
    a.set_xlim(0.19, 0.51)
    a.set(xlabel="Fn", ylabel="C_W × 10³", title="Wigley L/B 10, B/T 1.6")
    a.legend()
    a.grid(alpha=0.3)
    labels = [f"{r['hull']}\nFn {r['fn']}" for r in rows]
    x = np.arange(len(rows))
    for i, (key, name) in enumerate((("ct_tank", "tank"), ("ct_holtrop", "H-M"), ("ct_michell", "Michell"),
                                     ("ct_panel", "panel"), ("ct_dawson", "Dawson"))):
        b.bar(x + (i - 2) * 0.16, [r[key] * 1e3 for r in rows], 0.16, label=name)
    b.set_xticks(x, labels)
    b.set(ylabel="model C_T × 10³", title="(1+k1)·C_F + C_W against the tank")
    b.legend()
    b.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def series60(fns=(0.28, 0.316, 0.35)):
    """The Series 60 C_B 0.60 parent (Todd's offsets, examples/hulls; full scale, fixed: its table has no
    freeboard): C_W by each method at ``fns`` (0.316, the IIHR's tests' speed). Todd's own resistance tables
    were not reachable, so this records the methods beside each other, not against the tank."""
    h = load_hull(f"{HULLS}/series60_cb060_todd1963.csv").sections
    draft, u = 6.5024, np.asarray(fns) * np.sqrt(G * float(h.lpp))
    s = wetted_surface(h, draft)
    cw = {m: [float(c) for c in wave_resistance_coefficient(calm_water(h, draft, jnp.asarray(u), m).r_wave, u, s)]
          for m in ("holtrop", "michell", "panel", "dawson")}
    return {"fn": list(fns), "cw": cw}


def series60_goal(s6):
    k = lambda m: [round(c * 1e3, 3) for c in s6["cw"][m]]  # noqa: E731
    return goal(f"dawson: Series 60 C_B 0.60 C_W × 10³ at Fn {', '.join(map(str, s6['fn']))} (fixed; no tank data)",
                k("dawson"), "-", "—", None, peer=f"H-M {k('holtrop')}, Michell {k('michell')}, panel {k('panel')}")


def main():
    if "--series60" in sys.argv[1:]:
        s6 = series60()
        merge("panel", {"series60": s6, "goals": [series60_goal(s6)]})
        print(s6)
        return
    if "--speed" in sys.argv[1:] or quick():  # the speed rows alone (the validation is not the device's)
        t, td, tb = speed(), speed(dawson_wave_resistance), batch(n=64 if suffix() else 4)
        merge("panel", {"speed": t, "speed_dawson": td, "batch_dawson": tb, "goals": speed_goals(t, td, tb)})
        print(t, td, tb)
        return
    w = wigley_curves()
    kcs = {float(r["Fn"]): r for r in _read("kcs_tokyo2015_resistance.csv") if r["case"] == "T2015_2.1"}
    fixed = [r for r in _read("kcs_tokyo2015_resistance.csv") if r["case"] != "T2015_2.1"][0]
    dtmb = {float(r["Fn"]): float(r["value"]) for r in _read("dtmb5415_resistance.csv") if r["quantity"] == "CT"}
    kspec = f"{HULLS}/kcs_model_closed_from_igs.stl.gz?scale=31.6&lpp=230"
    dspec = f"{HULLS}/dtmb5415_navaltoolbox_fullscale.stl.gz?lpp=142"
    rows = [model_totals(kspec, 10.8, 31.6, 0.26, NU_KCS, float(kcs[0.26]["CT_x1e3"]) * 1e-3, "KCS (free)"),
            model_totals(kspec, 10.8, 31.6, 0.26, 1.1418e-6, float(fixed["CT_x1e3"]) * 1e-3, "KCS (fixed)"),
            model_totals(dspec, 6.15, 24.83, 0.28, 1.14e-6, dtmb[0.28], "DTMB 5415"),
            model_totals(dspec, 6.15, 24.83, 0.41, 1.14e-6, dtmb[0.41], "DTMB 5415")]
    rows[0]["sinkage_tank_m"] = -float(kcs[0.26]["sinkage_m"])  # the tank's sinks negative; ours down positive
    rows[0]["trim_tank_deg"] = float(kcs[0.26]["trim_deg"])  # negative bow down, as ours
    t = speed()
    td = speed(dawson_wave_resistance)
    grid = dawson_grid(kspec, 10.8, 0.26)
    tank = wigley_tank()
    plot(w, tank, rows, RESULTS / "panel.png")
    thin = np.array(w["thin"]["cw_panel"]) / np.array(w["thin"]["cw_michell"])
    goals = [goal("panel: thin Wigley (B/L 0.02) C_W / Michell's, Fn 0.2–0.45", [round(float(thin.min()), 3),
                  round(float(thin.max()), 3)], "-", "within 0.95–1.05", bool(np.all(abs(thin - 1) < 0.05)))]
    ratio = {m: np.array(tank["cwp"][m]) / np.array(tank["cwp"]["tank"]) for m in ("dawson", "michell")}
    fast = np.array(tank["cwp"]["fn"]) >= 0.28  # Insel: C_WP reads low below Fn ≈ 0.25 (waves of millimetres)
    err = {m: np.array(tank["ct"][m]) / np.array(tank["ct"]["tank"]) - 1 for m in ("dawson", "michell")}
    span = lambda a: [round(float(a.min()), 2), round(float(a.max()), 2)]  # noqa: E731
    goals += [goal("dawson: Wigley C_W / tank C_WP (Insel 1990, fixed), Fn 0.28–0.50", span(ratio["dawson"][fast]),
                   "-", "0.9–1.5 (C_WP reads at or below C_W)",
                   bool(np.all((ratio["dawson"][fast] > 0.9) & (ratio["dawson"][fast] < 1.5))),
                   peer=f"Michell {span(ratio['michell'][fast])}"),
              goal("dawson: Wigley model C_T / tank − 1 (Insel 1990, fixed), Fn 0.41–0.50", span(err["dawson"]), "-",
                   "within ±0.10", bool(np.all(abs(err["dawson"]) <= 0.10)), peer=f"Michell {span(err['michell'])}")]
    for m in ("panel", "dawson"):
        for r in rows:
            err = r[f"ct_{m}"] / r["ct_tank"] - 1
            goals.append(goal(f"{m}: model C_T {r['hull']} Fn {r['fn']} / tank − 1", round(err, 3), "-",
                              "within ±0.10", bool(abs(err) <= 0.10),
                              peer=f"H-M {r['ct_holtrop'] / r['ct_tank'] - 1:+.3f}"))
    goals.append(goal("dawson: KCS Fn 0.26 C_W × 10³ on 64, 96, 128 free-surface columns",
                      [round(c * 1e3, 3) for c in grid["cw"]], "-", "—", None,
                      peer=f"tank − (1+k1)·C_F {(rows[0]['ct_tank'] - rows[0]['form_factor'] * rows[0]['cf_model']) * 1e3:.3f}"))
    s6 = series60()
    goals.append(series60_goal(s6))
    tb = batch(n=64 if suffix() else 4)
    goals += speed_goals(t, td, tb)
    save("panel", {"wigley": w, "wigley_tank": tank, "models": rows, "series60": s6, "speed": t,
                   "speed_dawson": td, "batch_dawson": tb, "dawson_grid_kcs": grid, "goals": goals})
    for r in rows:
        print(r["hull"], r["fn"], {k: round(v * 1e3, 3) for k, v in r.items() if k.startswith("ct_")})
    print(t, td, grid)


if __name__ == "__main__":
    main()
