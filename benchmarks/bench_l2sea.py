"""hullopt vs CNR-INM's L2-Sea (NATO AVT-331 L2 Sea benchmark, its WARP linear potential-flow solver): wave
resistance of DTMB 5415 shape variants at Fr 0.28 (issue 27 item 5, the peer comparison).

The hulls: the DTMB 5415 of examples/hulls (NavalToolbox's full-scale mesh, Lpp 142 m, sliced at 201 stations,
a midship station added by interpolation for the Lackenby shift) at L2-Sea's draft 6.16 m, and variants made
with hullopt's own differentiable modifications — Lackenby shifts of Cb (Cp) ±3 % and LCB ±1.5 % Lpp (combined
both ways), :func:`hullopt.models.blunt_bow` over the fore body (p ±0.1) and over the bow region only (from
0.75 Lpp, p ±0.15). :func:`variants` returns them as ``(name, Sections, draft)`` in full scale, so that any
other wave-resistance code runs on exactly the same hulls.

Each is written as an L2-Sea hull grid (benchmarks/l2sea/l2sea.py: ``write_grid``) and run through L2-Sea at
Fr 0.28, even keel, at grid level 5 (90 × 25 nodes on the half hull; ~10 s a run; three grids of 88, 90 and 92
stations, the median kept, as one grid in a few gives an outlier there) and, unless ``--quick``, level 3
(127 × 35; ~40 s), recording its pressure-integral C_W (L2-Sea's Cw_pi, on the wetted surface at rest; its
wave-cut value is recorded beside it but is not the one to compare). The writer is checked on the parent: the
grid written from hullopt's sections against L2-Sea's own grid of the 5415 (5415_90_25_fs.x), at Fr 0.28 and
0.41. When :func:`hullopt.resistance.panel_wave_resistance` exists, hullopt's own C_W of the same hulls is
computed too and the Spearman rank correlation of the two lists recorded.

Run: ``benchmarks/l2sea/build.sh`` once (gfortran, LAPACK), then ``cd benchmarks && ../.venv/bin/python
bench_l2sea.py [--quick]``; results in results/l2sea.json. Without L2-Sea built the script says so and exits 0.
``bench_l2sea.py --rescore`` recomputes hullopt's C_W, the rank correlations and the goals on the stored L2-Sea
results without running L2-Sea (so also where it is not built).

``bench_l2sea.py --optimum RUN_FOLDER [--level N]``: the L2-Sea benchmark's judgement of a hullopt design run
(``configs/l2sea_5415.toml``): the run's optimum and its parent (both as hullopt holds them, scaled to L2-Sea's
full scale) written to WARP's grid at level N (default 1, the benchmark's G1), run through WARP at Fr 0.28 beside
L2-Sea's own parent grid; ΔR/R0 by WARP and by hullopt, the benchmark's constraints (Lpp, ∇, B and T within ±5 %,
the sonar dome's volume), hullopt's wall time and iterations, and that time in G1-equivalents (WARP's G1 run
time measured in the same call), against the published best (:data:`PUBLISHED`); results in
results/l2sea_optimum.json. ``bench_l2sea.py --ranking [RUN_FOLDER] [--level N]`` (default level 3): hullopt's Dawson
C_W ranking of the eleven variants, four principal-dimension changes and (given a run) its optimum against WARP's
(:func:`ranking_main`); results/l2sea_ranking.json.
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402
from _common import HULLS, goal, quick, save  # noqa: E402

sys.path.insert(0, str(Path(__file__).parent / "l2sea"))
import l2sea  # noqa: E402

from hullopt.constants import G  # noqa: E402
from hullopt.geometry import Sections  # noqa: E402
from hullopt.hydro import hydrostatics  # noqa: E402
from hullopt.models import blunt_bow, lackenby, load_hull  # noqa: E402

SPEC_REL = "examples/hulls/dtmb5415_navaltoolbox_fullscale.stl.gz?lpp=142"  # as recorded
SPEC = str(HULLS / "dtmb5415_navaltoolbox_fullscale.stl.gz") + "?lpp=142"
LPP = 142.0
DRAFT = 6.16  # L2-Sea's draft of the 5415 [m]
FROUDE = 0.28
FROUDE_HIGH = 0.41
LEVELS = (5, 3)  # L2-Sea grid levels run for every variant (5 only with --quick)
# grids written with ni + d stations a variant at each level, C_W the median: at level 5 one grid in a few gives an
# outlier (bow_finer: 0.686e-3 at ni = 90, 0.861e-3 at ni = 88; the parent 0.8816-0.8841e-3 at ni = 88, 90, 92)
SPREAD = {5: (-2, 0, 2), 3: (0,)}

# (name, description, modification, its parameters); Lackenby targets are relative to the parent's Cb, LCB
VARIANTS = [
    ("parent", "DTMB 5415 as sliced from the mesh", "none", {}),
    ("cp_plus3", "Lackenby: Cb (and Cp) +3 %, LCB held", "lackenby", {"cb_factor": 1.03}),
    ("cp_minus3", "Lackenby: Cb (and Cp) −3 %, LCB held", "lackenby", {"cb_factor": 0.97}),
    ("lcb_fwd1.5", "Lackenby: LCB 1.5 % Lpp forward, Cb held", "lackenby", {"d_lcb_pct": 1.5}),
    ("lcb_aft1.5", "Lackenby: LCB 1.5 % Lpp aft, Cb held", "lackenby", {"d_lcb_pct": -1.5}),
    ("cp_plus3_lcb_fwd1.5", "Lackenby: Cb +3 % and LCB 1.5 % Lpp forward", "lackenby",
     {"cb_factor": 1.03, "d_lcb_pct": 1.5}),
    ("cp_minus3_lcb_aft1.5", "Lackenby: Cb −3 % and LCB 1.5 % Lpp aft", "lackenby",
     {"cb_factor": 0.97, "d_lcb_pct": -1.5}),
    ("forebody_fuller", "blunt_bow p = +0.10 from midship: fore-body breadths × (1 + p sin²)", "blunt_bow",
     {"p": 0.10, "x_start": 0.5 * LPP}),
    ("forebody_finer", "blunt_bow p = −0.10 from midship", "blunt_bow", {"p": -0.10, "x_start": 0.5 * LPP}),
    ("bow_fuller", "blunt_bow p = +0.15 from 0.75 Lpp: bow-region breadths only", "blunt_bow",
     {"p": 0.15, "x_start": 0.75 * LPP}),
    ("bow_finer", "blunt_bow p = −0.15 from 0.75 Lpp: bow-region breadths only", "blunt_bow",
     {"p": -0.15, "x_start": 0.75 * LPP}),
]


def with_midship_station(s: Sections) -> Sections:
    """``s`` with a station at Lpp/2 (Lackenby holds it), its points interpolated between its two neighbours."""
    x = np.asarray(s.x, dtype=float)
    yz = np.asarray(s.yz, dtype=float)
    mid = 0.5 * float(s.lpp)
    if np.any(np.abs(x - mid) <= 1e-9 * float(s.lpp)):
        return s
    k = int(np.searchsorted(x, mid))
    w = (mid - x[k - 1]) / (x[k] - x[k - 1])
    sec = (1 - w) * yz[k - 1] + w * yz[k]
    return Sections(x=jnp.asarray(np.insert(x, k, mid)), yz=jnp.asarray(np.insert(yz, k, sec, axis=0)), lpp=s.lpp)


def parent() -> Sections:
    return with_midship_station(load_hull(SPEC).sections)


def _particulars(s: Sections) -> dict:
    h = hydrostatics(s, DRAFT)
    return {k: float(getattr(h, k)) for k in ("volume", "cb", "cp", "cm", "lcb_pct", "wetted_surface", "lwl", "bwl")}


def variant_specs() -> list[dict]:
    """Every variant: name, description, modification and parameters, its Sections (full scale) and draft."""
    s0 = parent()
    h0 = hydrostatics(s0, DRAFT)
    out = []
    for name, desc, kind, params in VARIANTS:
        if kind == "none":
            s = s0
        elif kind == "lackenby":
            s = lackenby(s0, DRAFT, cb=float(h0.cb) * params.get("cb_factor", 1.0),
                         lcb_pct=float(h0.lcb_pct) + params.get("d_lcb_pct", 0.0))
        elif kind == "blunt_bow":
            s = blunt_bow(s0, params["p"], params["x_start"])
        else:
            raise ValueError(kind)
        out.append({"name": name, "description": desc, "modification": kind, "params": params, "sections": s,
                    "draft": DRAFT})
    return out


def variants() -> list[tuple[str, Sections, float]]:
    """The hulls compared, full scale: ``(name, Sections, draft [m])``; the first is the parent."""
    return [(v["name"], v["sections"], v["draft"]) for v in variant_specs()]


def spearman(a, b) -> float:
    """Spearman's rank correlation of two equally long lists (average ranks for ties)."""
    from scipy.stats import spearmanr

    return float(spearmanr(a, b).statistic)


def hullopt_cw(specs: list[dict], method: str = "panel", froude: float = FROUDE) -> list[float]:
    """hullopt's C_W = R_W/(½ρU²S) of the variants by ``method`` at its default grid: ``"panel"``
    (:func:`hullopt.resistance.panel_wave_resistance`, Kelvin's condition), ``"dawson"``
    (:func:`hullopt.resistance.dawson_wave_resistance`, Dawson's) or ``"michell"`` (the thin-ship reference);
    S hullopt's wetted surface at rest."""
    from hullopt.resistance import (dawson_wave_resistance, michell_wave_resistance, panel_wave_resistance,
                                    wave_resistance_coefficient)

    speed = froude * np.sqrt(G * LPP)
    f = {"panel": jax.jit(lambda s, t: panel_wave_resistance(s, t, speed).r_wave),
         "dawson": jax.jit(lambda s, t: dawson_wave_resistance(s, t, speed).r_wave),
         "michell": lambda s, t: michell_wave_resistance(s, t, speed)}[method]
    out = []
    for v in specs:
        s = hydrostatics(v["sections"], v["draft"]).wetted_surface
        out.append(float(wave_resistance_coefficient(f(v["sections"], v["draft"]), speed, s)))
    return out


def main() -> None:
    if l2sea.binary() is None:
        print(f"bench_l2sea: L2-Sea is not built (looked in {l2sea.l2sea_dir()}); run benchmarks/l2sea/build.sh "
              "(needs gfortran and LAPACK) and run this again. Skipped.")
        return
    levels = LEVELS[:1] if quick() else LEVELS
    specs = variant_specs()
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench-l2sea-") as tmp:
        # the writer checked on the parent: L2-Sea's own grid against the one written from hullopt's sections
        check = {}
        for level in levels:
            ni, nj = l2sea.NODES[level]
            own = l2sea.run_warp(l2sea.parent_grid(), [FROUDE, FROUDE_HIGH], level)
            path = l2sea.write_grid(specs[0]["sections"], DRAFT, Path(tmp) / "parent.x", ni, nj)
            ours = l2sea.run_warp(path, [FROUDE, FROUDE_HIGH], level)
            check[str(level)] = {"l2sea_grid": own, "written_grid": ours,
                                 "cw_rel_diff": [o / w - 1.0 for o, w in zip(ours["cw"], own["cw"])]}
            print(f"level {level}: parent C_W at Fr {FROUDE}, {FROUDE_HIGH}: L2-Sea's grid {own['cw']}, "
                  f"written {ours['cw']} ({own['seconds']:.0f} s, {ours['seconds']:.0f} s)")
        for v in specs:
            row = {k: v[k] for k in ("name", "description", "modification", "params", "draft")}
            row["particulars"] = _particulars(v["sections"])
            row["l2sea"] = {}
            for level in levels:
                ni, nj = l2sea.NODES[level]
                runs = []
                for d in SPREAD.get(level, (0,)):
                    path = l2sea.write_grid(v["sections"], DRAFT, Path(tmp) / f"{v['name']}.x", ni + d, nj)
                    runs.append(l2sea.run_warp(path, FROUDE, level))
                r = dict(runs[list(SPREAD.get(level, (0,))).index(0)])
                r["ni_runs"] = [ni + d for d in SPREAD.get(level, (0,))]
                r["cw_runs"] = [x["cw"] for x in runs]
                r["cw"] = float(np.median(r["cw_runs"]))
                r["seconds"] = float(np.mean([x["seconds"] for x in runs]))
                row["l2sea"][str(level)] = r
                print(f"{v['name']:22s} level {level}: C_W {r['cw']:.4e} (runs {r['cw_runs']}; wave cut "
                      f"{r['cw_wavecut']:.4e}) {r['seconds']:.1f} s a run")
            rows.append(row)
    names = [r["name"] for r in rows]
    cw = {str(lv): [r["l2sea"][str(lv)]["cw"] for r in rows] for lv in levels}
    data = {
        "peer": "L2-Sea (CNR-INM, NATO AVT-331 L2 Sea benchmark), WARP linear potential flow, double-body "
                "linearisation, even keel; github.com/MAORG-CNR-INM/NATO-AVT-331-L2-Sea-Benchmark",
        "l2sea_commit": (l2sea.l2sea_dir() / "COMMIT").read_text().strip()
        if (l2sea.l2sea_dir() / "COMMIT").is_file() else None,
        "hull": SPEC_REL, "lpp": LPP, "draft": DRAFT, "froude": FROUDE, "levels": list(levels),
        "nodes": {str(lv): l2sea.NODES[lv] for lv in levels},
        "parent_check": check,
        "variants": rows,
        "names": names,
        "l2sea_cw": cw,
    }
    score(data, specs)
    print("wrote", save("l2sea", data))


def score(data: dict, specs: list[dict] | None = None) -> dict:
    """Add to ``data`` (the L2-Sea results) hullopt's own C_W of the same hulls by Michell, the panel method and
    Dawson's, the Spearman rank correlations and the goal rows."""
    levels = data["levels"]
    cw = data["l2sea_cw"]
    n = len(data["names"])
    goals = []
    for lv in levels:
        c = data["parent_check"][str(lv)]
        goals.append(goal(f"L2-Sea C_W (pressure) of the parent at Fr {FROUDE}, level {lv}: hullopt's 5415 written "
                          "vs L2-Sea's own grid (README: the waterline cut and the STL's facets)",
                          c["cw_rel_diff"][0], "rel.", "—", None, f"L2-Sea's grid {c['l2sea_grid']['cw'][0]:.4e}"))
    if len(levels) > 1:
        rho = spearman(cw[str(levels[0])], cw[str(levels[1])])
        data["spearman_l2sea_levels"] = rho
        goals.append(goal(f"L2-Sea C_W ranking of the {n} hulls, level {levels[0]} vs {levels[1]} (Spearman)",
                          rho, "", "—", None))
    specs = specs if specs is not None else variant_specs()
    for method, key, what, target in (("michell", "michell", "Michell thin ship", None),
                                      ("panel", "", "panel", 0.9), ("dawson", "dawson", "Dawson", 0.9)):
        cws = hullopt_cw(specs, method)
        data["hullopt_" + (key + "_" if key else "") + "cw"] = cws
        for lv in levels:
            rho = spearman(cws, cw[str(lv)])
            data.setdefault("spearman" + ("_" + key if key else ""), {})[str(lv)] = rho
            goals.append(goal(f"C_W ranking of {n} DTMB 5415 variants, hullopt {what} vs L2-Sea level {lv} (Spearman"
                              + ("; reference)" if target is None else ")"), rho, "", "—" if target is None else "≥ 0.9",
                              None if target is None else bool(rho >= target), "L2-Sea WARP"))
    data["goals"] = goals
    return data


def rescore() -> None:
    """``--rescore``: recompute hullopt's C_W, the correlations and the goals on the stored L2-Sea results
    (results/l2sea.json), without running L2-Sea (so also where it is not built)."""
    import json

    from _common import RESULTS

    path = RESULTS / "l2sea.json"
    data = json.loads(path.read_text())
    run_machine = data.pop("machine", None)
    data.setdefault("l2sea_run_machine", run_machine)  # where and when L2-Sea ran (its timings)
    data["hull"] = SPEC_REL
    print("wrote", save("l2sea", score(data)))


# The benchmark's published best (Pellegrini, Serani, Liuzzi, Rinaldi, Lucidi, Diez 2022, Mathematics 10(3):481,
# the NATO AVT-331 L2-Sea problem: DTMB 5415 model, Fr 0.28, Lpp and ∇ fixed, B and T within ±5 %, the sonar
# dome's volume not below the parent's; WARP at G1): MF-CS-DFN's optimum, and its figure at a small budget.
PUBLISHED = {"rt0_N": 41.50, "rt_N": 36.3, "delta_r": -0.125, "g1_equivalents": 628,
             "delta_r_small_budget": -0.115, "g1_equivalents_small_budget": 6.2,
             "source": "Pellegrini et al. 2022, Mathematics 10(3):481 (MF-CS-DFN, WARP G1)"}
DOME = {"x_a": 4.9, "z_top": 0.0}  # the sonar dome at model scale: forward of 4.9 m, below the baseline [m]


def _scaled(s: Sections, k: float) -> Sections:
    """``s`` scaled by ``k`` (model → full scale)."""
    return Sections(x=s.x * k, yz=s.yz * k, lpp=s.lpp * k)


def benchmark_measures(s: Sections, draft: float) -> dict:
    """The L2-Sea benchmark's constrained quantities of a hull (model scale, as hullopt holds it).

    Parameters
    ----------
    s : Sections
        The hull [m].
    draft : float
        Its draft [m].

    Returns
    -------
    dict
        ``lpp``, ``draft``, ``volume`` [m³], ``bwl`` (waterline beam) and ``beam`` (largest breadth) [m],
        ``wetted_surface`` [m²], ``cb``, ``lcb_pct`` and ``dome_volume`` [m³] (:data:`DOME`: the part forward of
        ``x_a`` below ``z_top``, by :func:`hullopt.geometry.region_volume`).
    """
    from hullopt.geometry import region_volume

    h = hydrostatics(s, draft)
    return {"lpp": float(s.lpp), "draft": float(draft), "volume": float(h.volume), "bwl": float(h.bwl),
            "beam": 2.0 * float(jnp.max(s.yz[..., 0])), "wetted_surface": float(h.wetted_surface),
            "cb": float(h.cb), "lcb_pct": float(h.lcb_pct),
            "dome_volume": float(region_volume(s, draft, DOME["x_a"], jnp.inf, DOME["z_top"]))}


def optimum(folder: str | Path, level: int = 1, reuse: bool = False) -> dict:
    """Judge a hullopt run on the L2-Sea benchmark by WARP: the run's optimum and its parent written to WARP's
    grid at ``level`` and run at Fr 0.28 (even keel), beside L2-Sea's own parent grid.

    Parameters
    ----------
    folder : str or pathlib.Path
        A ``hullopt run`` folder of a minimise run on the DTMB 5415 (``configs/l2sea_5415.toml``).
    level : int
        L2-Sea's grid level (1: the benchmark's G1).
    reuse : bool
        Take a WARP run kept in the run folder by an earlier call (``l2sea_g<level>_<hull>/warp.json``: its
        results and wall time) instead of running it again.

    Returns
    -------
    dict
        ``warp``: each run's result (:func:`l2sea.run_warp`) for ``own_parent``, ``parent`` and ``optimum``;
        ``delta_r_warp`` (R_T of the written optimum over the written parent, − 1), ``delta_r_warp_vs_own``
        (against L2-Sea's own parent), ``delta_r_hullopt`` (the run's objective); ``measures`` of both hulls
        (:func:`benchmark_measures`) and their ratios; ``hullopt`` (wall time, iterations), ``g1_seconds``
        (the mean WARP run time here) and ``g1_equivalents``; ``published`` (:data:`PUBLISHED`).
    """
    import json

    from hullopt.study import load_hull as load_run

    folder = Path(folder)
    report = json.loads((folder / "report.json").read_text())
    config = json.loads((folder / "config.json").read_text())
    design = load_run(str(folder))
    par = load_run(config["hull"]["parent"])
    t0, t1 = float(config["hull"]["draft"]), float(design.design_draft)
    s0, s1 = par.sections, design.sections
    k = LPP / float(s0.lpp)
    ni, nj = l2sea.NODES[level]
    warp = {}
    with tempfile.TemporaryDirectory(prefix="bench-l2sea-opt-") as tmp:
        for name, s, t in (("own_parent", None, None), ("parent", s0, t0), ("optimum", s1, t1)):
            keep = folder / f"l2sea_g{level}_{name}"
            if reuse and (keep / "warp.json").is_file():  # a run kept by an earlier call: its results and time
                warp[name] = json.loads((keep / "warp.json").read_text()) | {"reused": True}
            else:
                if s is None:
                    warp[name] = l2sea.run_warp(l2sea.parent_grid(), FROUDE, level, keep=keep)
                else:
                    path = l2sea.write_grid(_scaled(s, k), t * k, Path(tmp) / f"{name}.x", ni, nj)
                    warp[name] = l2sea.run_warp(path, FROUDE, level, lpp=LPP, draft=t * k, keep=keep)
                (keep / "warp.json").write_text(json.dumps(warp[name], indent=1))
            print(f"WARP level {level} {name}: R_T {warp[name]['rt_N']:.3f} N, C_W {warp[name]['cw']:.4e} "
                  f"({warp[name]['seconds']:.0f} s)")
    m0, m1 = benchmark_measures(s0, t0), benchmark_measures(s1, t1)
    g1_seconds = float(np.mean([w["seconds"] for w in warp.values()]))
    seconds = report.get("seconds", {})
    wall = float(sum(v for v in seconds.values() if isinstance(v, (int, float))))
    obj0, obj1 = float(report["objective"]["parent"]), float(report["objective"]["value"])
    data = {
        "run": folder.name, "level": level, "nodes": l2sea.NODES[level], "froude": FROUDE, "scale": k,
        "warp": warp,
        "rt_own_parent_N": warp["own_parent"]["rt_N"],
        "delta_r_warp": warp["optimum"]["rt_N"] / warp["parent"]["rt_N"] - 1.0,
        "delta_r_warp_vs_own": warp["optimum"]["rt_N"] / warp["own_parent"]["rt_N"] - 1.0,
        "delta_cw_warp": warp["optimum"]["cw"] / warp["parent"]["cw"] - 1.0,
        "hullopt_objective_N": [obj0, obj1],
        "delta_r_hullopt": obj1 / obj0 - 1.0,
        "measures": {"parent": m0, "optimum": m1, "ratio": {q: m1[q] / m0[q] for q in m0}},
        "met": bool(report.get("met")),
        "hullopt": {"seconds": seconds, "wall_s": wall, "iterations": report.get("iterations"),
                    "params": report.get("params")},
        "g1_seconds": g1_seconds,
        "g1_equivalents": wall / g1_seconds,
        "published": PUBLISHED,
        "lines": sorted(p.name for p in folder.glob("*.png")),
    }
    return data


def optimum_main(folder: str, level: int, reuse: bool = False) -> None:
    """``--optimum RUN_FOLDER [--level N] [--reuse]``: :func:`optimum`, its goals, saved to
    results/l2sea_optimum.json."""
    if l2sea.binary() is None:
        print(f"bench_l2sea: L2-Sea is not built (looked in {l2sea.l2sea_dir()}); run benchmarks/l2sea/build.sh. "
              "Skipped.")
        return
    d = optimum(folder, level, reuse)
    pub = PUBLISHED
    r = d["measures"]["ratio"]
    d["goals"] = [
        goal(f"L2-Sea's own DTMB 5415 grid, R_T at level {level} (the benchmark's R0 41.50 N at G1)",
             d["rt_own_parent_N"], "N", "41.50 ± 0.05" if level == 1 else "—",
             abs(d["rt_own_parent_N"] - 41.50) <= 0.05 if level == 1 else None),
        goal(f"hullopt's optimum: ΔR/R0 by WARP level {level} (written optimum / written parent − 1)",
             d["delta_r_warp"], "rel.", f"≤ {pub['delta_r']}", bool(d["delta_r_warp"] <= pub["delta_r"]),
             f"{pub['delta_r']} ({pub['source']}); {pub['delta_r_small_budget']} at "
             f"{pub['g1_equivalents_small_budget']} G1-eq."),
        goal("hullopt's optimum: ΔR/R0 by hullopt's own objective (Dawson R_W + (1 + k1)·ITTC-57)",
             d["delta_r_hullopt"], "rel.", "—", None),
        goal("compute spent: hullopt's wall time in WARP G1-equivalents (same machine)", d["g1_equivalents"],
             "G1-eq.", f"< {pub['g1_equivalents_small_budget']}",
             bool(d["g1_equivalents"] < pub["g1_equivalents_small_budget"]), f"{pub['g1_equivalents']} (best)"),
        goal("benchmark constraints: Lpp held, ∇ within 0.5 %, B (waterline) and T within ±5 %, dome volume ≥ "
             "parent's", {q: r[q] for q in ("lpp", "volume", "bwl", "draft", "dome_volume")}, "ratio", "—",
             bool(abs(r["lpp"] - 1) < 1e-9 and abs(r["volume"] - 1) <= 5e-3 and abs(r["bwl"] - 1) <= 0.05 + 1e-6
                  and abs(r["draft"] - 1) <= 0.05 + 1e-6 and r["dome_volume"] >= 1 - 1e-3)),
    ]
    print(f"ΔR/R0: WARP {d['delta_r_warp']:+.2%} (vs L2-Sea's own parent {d['delta_r_warp_vs_own']:+.2%}), "
          f"hullopt {d['delta_r_hullopt']:+.2%}; {d['hullopt']['wall_s']:.0f} s = {d['g1_equivalents']:.2f} "
          f"G1-equivalents; published {pub['delta_r']:+.1%}")
    print("wrote", save("l2sea_optimum", d))


def _dims(s: Sections, draft: float, beam: float, height: float) -> tuple[Sections, float]:
    """``s`` with every half-breadth × ``beam`` and every height (and the draft) × ``height`` from the baseline."""
    yz = s.yz * jnp.array([beam, height])
    return Sections(x=s.x, yz=yz, lpp=s.lpp), draft * height


def ranking_specs(folder: str | Path | None = None) -> list[dict]:
    """The ranking study's hulls beyond :func:`variant_specs`' eleven, full scale: principal-dimension changes of
    the parent (beam ±5 % with the draft the other way, ∇ held; beam or draft +5 % alone) and, given a run folder
    of ``configs/l2sea_5415.toml``, its optimum and the parent with only the optimum's beam and draft.

    Parameters
    ----------
    folder : str or pathlib.Path, optional
        A minimise run's folder on the DTMB 5415 model.

    Returns
    -------
    list of dict
        As :func:`variant_specs`: ``name``, ``description``, ``modification``, ``params``, ``sections`` and
        ``draft`` (full scale, Lpp 142 m).
    """
    import json

    s0 = parent()
    out = []
    for name, desc, b, h in (("beam+5_draft-5", "beam × 1.05, heights and draft ÷ 1.05 (∇ held)", 1.05, 1 / 1.05),
                             ("beam-5_draft+5", "beam ÷ 1.05, heights and draft × 1.05 (∇ held)", 1 / 1.05, 1.05),
                             ("beam+5", "beam × 1.05 (∇ + 5 %)", 1.05, 1.0),
                             ("draft+5", "heights and draft × 1.05 (∇ + 5 %)", 1.0, 1.05)):
        s, t = _dims(s0, DRAFT, b, h)
        out.append({"name": name, "description": desc, "modification": "dims", "params": {"beam": b, "height": h},
                    "sections": s, "draft": t})
    if folder is not None:
        from hullopt.study import load_hull as load_run

        folder = Path(folder)
        report = json.loads((folder / "report.json").read_text())
        design = load_run(str(folder))
        k = LPP / float(design.sections.lpp)
        out.append({"name": "optimum", "description": f"the optimum of {folder.name}", "modification": "run",
                    "params": report.get("params"), "sections": _scaled(design.sections, k),
                    "draft": float(design.design_draft) * k})
        b = 1.0 + float(np.ravel(report["params"].get("beam_s", [0.0]))[0])
        h = 1.0 + float(np.ravel(report["params"].get("draft_s", [0.0]))[0])
        s, t = _dims(s0, DRAFT, b, h)
        out.append({"name": "optimum_dims_only", "description": f"the parent at the optimum's beam × {b:.4f} and "
                    f"draft × {h:.4f}", "modification": "dims", "params": {"beam": b, "height": h},
                    "sections": s, "draft": t})
    return out


def ranking_main(folder: str | None, level: int) -> None:
    """``--ranking [RUN_FOLDER] [--level N]``: WARP at ``level`` on :func:`ranking_specs`' hulls (the eleven
    variants' WARP C_W at that level taken from results/l2sea.json where it has them, else run), hullopt's
    Dawson C_W of all, their Spearman rank correlation; saved to results/l2sea_ranking.json."""
    import json

    from _common import RESULTS

    if l2sea.binary() is None:
        print(f"bench_l2sea: L2-Sea is not built (looked in {l2sea.l2sea_dir()}). Skipped.")
        return
    stored = json.loads((RESULTS / "l2sea.json").read_text())
    specs = variant_specs() + ranking_specs(folder)
    ni, nj = l2sea.NODES[level]
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench-l2sea-rank-") as tmp:
        for v in specs:
            old = next((r for r in stored["variants"] if r["name"] == v["name"]), None)
            if old is not None and str(level) in old["l2sea"]:
                cw, sec, src = old["l2sea"][str(level)]["cw"], None, "results/l2sea.json"
            else:
                path = l2sea.write_grid(v["sections"], v["draft"], Path(tmp) / "h.x", ni, nj)
                r = l2sea.run_warp(path, FROUDE, level, draft=v["draft"])
                cw, sec, src = r["cw"], r["seconds"], "run"
            rows.append({k: v[k] for k in ("name", "description", "modification", "draft")} |
                        {"warp_cw": cw, "warp_seconds": sec, "warp_source": src})
            print(f"{v['name']:22s} WARP level {level} C_W {cw:.4e} ({src})")
    dawson = hullopt_cw(specs, "dawson")
    for r, c in zip(rows, dawson):
        r["hullopt_dawson_cw"] = c
    rho = spearman(dawson, [r["warp_cw"] for r in rows])
    data = {"level": level, "froude": FROUDE, "hulls": rows, "spearman_dawson": rho,
            "goals": [goal(f"C_W ranking of {len(rows)} DTMB 5415 hulls (shape, principal dimensions, the optimum), "
                           f"hullopt Dawson vs WARP level {level} (Spearman)", rho, "", "≥ 0.9", bool(rho >= 0.9),
                           "L2-Sea WARP")]}
    print(f"Spearman (hullopt Dawson vs WARP level {level}, {len(rows)} hulls): {rho:.3f}")
    print("wrote", save("l2sea_ranking", data))


if __name__ == "__main__":
    t0 = time.perf_counter()
    argv = sys.argv[1:]
    if "--ranking" in argv:
        i = argv.index("--ranking")
        run_folder = argv[i + 1] if i + 1 < len(argv) and not argv[i + 1].startswith("--") else None
        ranking_main(run_folder, int(argv[argv.index("--level") + 1]) if "--level" in argv else 3)
    elif "--optimum" in argv:
        lv = int(argv[argv.index("--level") + 1]) if "--level" in argv else 1
        optimum_main(argv[argv.index("--optimum") + 1], lv, "--reuse" in argv)
    else:
        rescore() if "--rescore" in argv else main()
    print(f"{time.perf_counter() - t0:.0f} s")
