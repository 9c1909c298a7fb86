"""Fit to Cb/LCB (issue [8/8]): hullopt's auto-fit vs a Lackenby (1950) shift of the same parent, and vs scipy
SLSQP with finite-difference gradients, on configs/fit_cb_lcb.toml (Wigley parent, Cb 0.444 → 0.48,
LCB 0 → −1.5 % Lpp: "large") and a change within Lackenby's usual range (Cb +3 %, LCB −0.5 % Lpp: "moderate").

* ours — Levenberg–Marquardt on the feature parameters (:func:`hullopt.optimise.solve_fit`): as
  ``hullopt run`` does it (the traced loop with its cost history, :func:`hullopt.optimise.fit_traced`), and as
  optimistix's own solve (to its own convergence and with just the steps that meet the tolerances) — each one
  jitted program, compile and warm run timed apart;
* Lackenby — :func:`hullopt.models.lackenby` on the parent sections (the model at zero parameters);
* SLSQP — ``scipy.optimize.minimize(method="SLSQP")`` on the same parameters and bounds, objective 0 (or the
  sum of squared residuals), equality constraints = the target residuals in units of their tolerances, FD
  Jacobians ('2-point'), values from the jitted residual function; ``ftol = 1`` stops at the targets'
  tolerances (Σ|r/tol| < 1), ``ftol = 1e-6`` converges fully.

Quality of each result: Cb/LCB errors, unfairness (:func:`hullopt.fairing.unfairness`) relative to the
parent, the largest change of half-breadth against the parent at the parent's stations (below the deck),
and whether the stations stay in order (the smallest ratio of new to old station spacing).

Run: ``cd benchmarks && ../.venv/bin/python bench_fit.py [--quick]`` (``--quick``: the large case only); results in
results/fit.json.
"""

from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

os.environ.setdefault("TF_CPP_MIN_LOG_LEVEL", "3")  # as the CLI: no XLA log line per cached executable

import jax  # noqa: E402

jax.config.update("jax_enable_x64", True)

import equinox as eqx  # noqa: E402
import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402
from _common import quick, save, timeit  # noqa: E402
from jax.flatten_util import ravel_pytree  # noqa: E402
from scipy.optimize import minimize  # noqa: E402

from hullopt.study import load_config  # noqa: E402
from hullopt.study import load_study  # noqa: E402
from hullopt.errors import HullError  # noqa: E402
from hullopt.fairing import unfairness  # noqa: E402
from hullopt.geometry import section_integrals  # noqa: E402
from hullopt.hydro import hydrostatics  # noqa: E402
from hullopt.models import lackenby  # noqa: E402
from hullopt.optimise import fit, solve_fit, with_objective_scale  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "configs" / "fit_cb_lcb.toml"
CASES = {"large": [], "moderate": ["targets.cb=0.4575", "targets.lcb_pct=-0.5"]}  # parent Cb 0.4442: +3 %

hydro = jax.jit(hydrostatics)
unfair = jax.jit(unfairness)


@jax.jit
def widths(sections, levels):
    """Half-breadths ``(k, n)`` [m] of every station at the waterlines ``levels (k,)``."""
    return jax.vmap(lambda t: section_integrals(sections, t).width)(levels)


def quality(s, parent, draft, targets: dict, tol: dict) -> dict:
    h = hydro(s, draft)
    err = {"cb": float(h.cb) - targets["cb"], "lcb_pct": float(h.lcb_pct) - targets["lcb_pct"]}
    x, x0 = np.asarray(s.x), np.asarray(parent.x)
    levels = jnp.linspace(0.01, 0.99, 50) * parent.depth
    w, w0 = np.asarray(widths(s, levels)), np.asarray(widths(parent, levels))
    # the new hull's waterlines (piecewise linear between its stations) at the parent's stations
    w_at = np.stack([np.interp(x0, x, row) for row in w])
    spacing = float(np.min(np.diff(x) / np.diff(x0)))
    return {
        "cb": float(h.cb), "lcb_pct": float(h.lcb_pct), "cb_error": err["cb"], "lcb_pct_error": err["lcb_pct"],
        "met": bool(all(abs(err[k]) <= tol[k] for k in err)),
        "unfairness_ratio": float(unfair(s)) / float(unfair(parent)),
        "max_half_breadth_change_m": float(np.max(np.abs(w_at - w0))),
        "max_half_breadth_change_pct_of_half_beam": float(100 * np.max(np.abs(w_at - w0)) / np.max(w0)),
        "min_station_spacing_ratio": spacing, "stations_monotone": bool(spacing > 0),
    }


def run_case(name: str, overrides: list[str]) -> dict:
    cfg, _ = load_config(CONFIG, overrides)
    prob = load_study(cfg).problem
    p0, lower, upper = prob.p0, prob.lower, prob.upper
    d = with_objective_scale(prob.design, p0)  # the fairness term as `hullopt run` scales it (U/U_parent)
    draft = float(d.draft)
    targets = {k: float(v) for k, v in zip(d.targets.names, np.asarray(d.targets.values))}
    tol = {k: float(v) for k, v in zip(d.targets.names, np.asarray(d.targets.tol))}
    parent = d.model(p0)
    h0 = hydro(parent, draft)
    out = {"targets": targets, "tolerances": tol, "parent": {"cb": float(h0.cb), "lcb_pct": float(h0.lcb_pct)},
           "parameters": int(ravel_pytree(p0)[0].shape[0])}
    print(f"\n== {name}: Cb {float(h0.cb):.4f} → {targets['cb']}, LCB {float(h0.lcb_pct):.2f} → "
          f"{targets['lcb_pct']} % Lpp ({out['parameters']} parameters)")

    # ours, as `hullopt run` does it: the traced LM loop in one jitted program (cost history kept)
    solve = eqx.filter_jit(lambda p0: solve_fit(d, p0, lower, upper, traced=True, max_steps=cfg.solver.max_steps))
    t0 = time.perf_counter()
    res = jax.block_until_ready(solve(p0))
    t_first = time.perf_counter() - t0
    t_warm = timeit(lambda: jax.block_until_ready(solve(p0)), 5)
    history = np.asarray(res.history)
    # cost = Σ(r/tol)² + a tiny regularisation: below 1 means every target met (Σ|r/tol|² < 1)
    n_met = int(np.argmax(history < 1.0))
    out["ours_traced"] = {"compile_s": t_first - t_warm, "warm_s": t_warm, "steps": int(res.steps),
                          "steps_to_tolerance": n_met, "step_ms": 1e3 * t_warm / max(int(res.steps), 1),
                          **quality(d.model(res.params), parent, draft, targets, tol)}

    # ours, one jitted solve: compile apart, warm time; to convergence and with the steps that meet the targets
    tols = d.fit_tolerances(p0)
    for key, steps in (("ours_jit", cfg.solver.max_steps), ("ours_jit_to_tolerance", n_met)):
        solve = eqx.filter_jit(lambda p0, steps=steps: fit(d.residuals, p0, lower, upper, tol=tols, max_steps=steps))
        t0 = time.perf_counter()
        res = jax.block_until_ready(solve(p0))
        t_first = time.perf_counter() - t0
        t_warm = timeit(lambda: jax.block_until_ready(solve(p0)), 5)
        out[key] = {"compile_s": t_first - t_warm, "warm_s": t_warm, "steps": int(res.steps),
                    "solver_ok": bool(res.solver_ok),
                    **quality(d.model(res.params), parent, draft, targets, tol)}

    # ours with the fairness penalty of the design problems (weight 1 on U/U_parent; targets in tolerance units)
    cfg_f, _ = load_config(CONFIG, overrides + ["solver.fairness=1.0"])
    d_f = with_objective_scale(load_study(cfg_f).problem.design, p0)  # U/U_parent
    solve = eqx.filter_jit(lambda p0: fit(d_f.residuals, p0, lower, upper, tol=d_f.fit_tolerances(p0),
                                          max_steps=cfg.solver.max_steps))
    t0 = time.perf_counter()
    res = jax.block_until_ready(solve(p0))
    t_first = time.perf_counter() - t0
    t_warm = timeit(lambda: jax.block_until_ready(solve(p0)), 3)
    out["ours_jit_fairness"] = {"compile_s": t_first - t_warm, "warm_s": t_warm, "steps": int(res.steps),
                                "solver_ok": bool(res.solver_ok),
                                **quality(d.model(res.params), parent, draft, targets, tol)}

    # Lackenby shift of the parent sections
    try:
        t0 = time.perf_counter()
        s_l = lackenby(parent, draft, cb=targets["cb"], lcb_pct=targets["lcb_pct"])
        t_first = time.perf_counter() - t0
        t_warm = timeit(lambda: lackenby(parent, draft, cb=targets["cb"], lcb_pct=targets["lcb_pct"]), 5)
        out["lackenby"] = {"valid": True, "first_call_s": t_first, "warm_s": t_warm,
                           **quality(s_l, parent, draft, targets, tol)}
        # station spacing next to midship: the map's slope on each side; unequal slopes make a jump of
        # (slope_F/slope_A)² in the waterline curvature at midship (the shift is only C¹ there)
        x, x0 = np.asarray(s_l.x), np.asarray(parent.x)
        i = int(np.argmin(np.abs(x0 - 0.5 * float(parent.lpp))))
        out["lackenby"]["midship_slope_aft"] = float((x[i] - x[i - 1]) / (x0[i] - x0[i - 1]))
        out["lackenby"]["midship_slope_fore"] = float((x[i + 1] - x[i]) / (x0[i + 1] - x0[i]))
    except HullError as e:
        out["lackenby"] = {"valid": False, "message": str(e)}
    # how far a Lackenby shift of this parent reaches (Cb up, at the case's LCB)
    reach = []
    for cb in (0.48, 0.50, 0.52, 0.54, 0.56, 0.58):
        try:
            s_r = lackenby(parent, draft, cb=cb, lcb_pct=targets["lcb_pct"])
            ratio = float(np.min(np.diff(np.asarray(s_r.x)) / np.diff(np.asarray(parent.x))))
            reach.append({"cb": cb, "valid": True, "min_station_spacing_ratio": ratio})
        except HullError as e:
            reach.append({"cb": cb, "valid": False, "message": str(e)})
    out["lackenby_reach"] = reach

    # scipy SLSQP, FD Jacobians, on the same parameters and bounds
    flat0, unravel = ravel_pytree(p0)
    lo, hi = np.asarray(ravel_pytree(lower)[0]), np.asarray(ravel_pytree(upper)[0])
    cons_j = jax.jit(lambda x: d.constraints(unravel(x)) / d.targets.tol)
    jax.block_until_ready(cons_j(flat0))
    calls = [0]

    def cons(x):
        calls[0] += 1
        return np.asarray(cons_j(jnp.asarray(x)))

    objectives = {"zero": lambda x: 0.0, "sum_of_squares": lambda x: float(np.sum(cons(x) ** 2))}
    for obj, ftol in (("zero", 1.0), ("zero", 1e-6), ("sum_of_squares", 1.0)):
        def solve(obj=obj, ftol=ftol):
            calls[0] = 0
            return minimize(objectives[obj], np.asarray(flat0), method="SLSQP", bounds=list(zip(lo, hi)),
                            constraints=[{"type": "eq", "fun": cons}], options={"ftol": ftol, "maxiter": 200})

        t = timeit(solve, 5)
        r = solve()
        out[f"slsqp_{obj}_ftol_{ftol:g}"] = {
            "time_s": t, "residual_evaluations": calls[0], "iterations": int(r.nit), "success": bool(r.success),
            "message": str(r.message), "max_abs_residual_over_tol": float(np.max(np.abs(cons(r.x)))),
            **quality(d.model(unravel(jnp.asarray(r.x))), parent, draft, targets, tol)}
    out["residual_eval_ms"] = 1e3 * timeit(lambda: cons(flat0), 21)
    return out


def table(name: str, res: dict) -> None:
    rows = [("ours (hullopt run, warm)", res["ours_traced"], "warm_s", "steps"),
            ("ours (jitted LM)", res["ours_jit"], "warm_s", "steps"),
            ("ours (jitted LM, to tolerance)", res["ours_jit_to_tolerance"], "warm_s", "steps"),
            ("ours (jitted LM + fairness term)", res["ours_jit_fairness"], "warm_s", "steps"),
            ("Lackenby", res["lackenby"], "warm_s", None)]
    rows += [(f"SLSQP {k[6:]}", v, "time_s", "residual_evaluations") for k, v in res.items() if k.startswith("slsqp")]
    print(f"{'method':34s} {'time ms':>8s} {'work':>5s} {'ΔCb':>9s} {'ΔLCB %':>9s} {'U/U0':>5s} {'maxΔy m':>7s} "
          f"{'spacing':>7s}")
    for label, r, key, work in rows:
        if not r.get("valid", True):
            print(f"{label:34s} invalid: {r['message']}")
            continue
        print(f"{label:34s} {1e3 * r[key]:8.1f} {r[work] if work else '':>5} {r['cb_error']:9.1e} "
              f"{r['lcb_pct_error']:9.1e} {r['unfairness_ratio']:5.2f} {r['max_half_breadth_change_m']:7.3f} "
              f"{r['min_station_spacing_ratio']:7.2f}")
    ok = [r["cb"] for r in res["lackenby_reach"] if r["valid"]]
    print(f"Lackenby reaches Cb {max(ok) if ok else '—'} at LCB {res['targets']['lcb_pct']} % Lpp; beyond: "
          + next((r["message"] for r in res["lackenby_reach"] if not r["valid"]), "all valid"))
    print("work: LM steps (one value + Jacobian each) or SLSQP residual evaluations; spacing: smallest new/old "
          "station spacing (> 0: stations in order)")


def main() -> None:
    with tempfile.TemporaryDirectory() as cache:  # as the CLI: a persistent compilation cache (here a fresh one)
        jax.config.update("jax_compilation_cache_dir", cache)
        jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
        jax.config.update("jax_persistent_cache_min_entry_size_bytes", 0)
        cases = {"large": CASES["large"]} if quick() else CASES  # --quick: the built-in example's case only
        out = {name: run_case(name, ov) for name, ov in cases.items()}
    for name, res in out.items():
        print(f"\n{name}")
        table(name, res)
    save("fit", out)


if __name__ == "__main__":
    main()
