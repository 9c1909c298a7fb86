"""Design-objective benchmarks (issue [8/8]) on the Wigley library parent of tests/data/min_added_resistance_wigley.toml (the shipped
configs/min_added_resistance.toml until 2026-12-02).

1. Value-and-gradient over value of the full objective: hydrostatics (∇, KB, BM_T) + K_AW + sea-state mean
   added resistance + wind added resistance + Holtrop–Mennen, as a function of the P design parameters.
2. The AD gradient vs central finite differences (2P evaluations of the jitted value), values compared.
3. vmap batch efficiency: time per design in a batch of 256 vs a batch of 1.
4. Cost vs resolution (Wigley stations × points, gradient w.r.t. every vertex) and vs the number of
   parameters (modes of the frame-spacing distribution).
5. ``hullopt run configs/fit_cb_lcb.toml`` (the built-in example) cold and warm (persistent compilation cache).

Run: ``cd benchmarks && ../.venv/bin/python bench_design.py [--quick]`` (``--quick``: without the cost sweeps of
item 4); results in results/design.json.
"""

from __future__ import annotations

import json
import sys
import tempfile
import time
from pathlib import Path

import jax

jax.config.update("jax_enable_x64", True)

import equinox as eqx  # noqa: E402
import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402
from _common import quick, run_process, save, timeit  # noqa: E402
from jax.flatten_util import ravel_pytree  # noqa: E402

from hullopt.study import load_config  # noqa: E402
from hullopt.study import load_study  # noqa: E402
from hullopt.constants import KNOT  # noqa: E402
from hullopt.hydro import hydrostatics  # noqa: E402
from hullopt.models import wigley  # noqa: E402
from hullopt.optimise import CalmResistance, KAw, MeanAddedResistance, WindAddedResistance  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "tests" / "data" / "min_added_resistance_wigley.toml"
V = jnp.asarray(15.0 * KNOT)
OBJECTIVES = (
    KAw(speed=V),
    # the reflection part (Bf): the objective these numbers were recorded for; the strip-theory motion part
    # (MeanAddedResistance's default since issue 16) costs seconds per evaluation and is timed in bench_motions.py
    MeanAddedResistance(speed=V, hs=jnp.asarray(3.0), tp=jnp.asarray(9.0), motion=False),
    WindAddedResistance(speed=V, wind_speed=jnp.asarray(15.0), wind_angle=jnp.asarray(0.3)),
    CalmResistance(speed=V),
)


def full_objective(sections, draft):
    """Order-one sum of every analysis of the design objective (scaled so each term weighs alike)."""
    h = hydrostatics(sections, draft)
    terms = [h.volume / 1e3, h.kb, h.bmt]
    terms += [o(sections, draft) / s for o, s in zip(OBJECTIVES, (1.0, 1e4, 1e4, 1e5))]
    return sum(terms)


def problem(overrides=()):
    cfg, _ = load_config(CONFIG, list(overrides))
    prob = load_study(cfg).problem
    flat, unravel = ravel_pytree(prob.p0)
    d = prob.design
    f = lambda x: full_objective(d.model(unravel(x)), d.draft)  # noqa: E731
    return f, flat


def ms(t):
    return round(t * 1e3, 3)


def main() -> None:
    out = {}
    f, x0 = problem()
    p = x0.shape[0]
    x = x0 + 0.05  # off the parent (zero parameters): a generic point
    fj, vg = jax.jit(f), jax.jit(jax.value_and_grad(f))
    t0 = time.perf_counter()
    jax.block_until_ready(fj(x))
    t_cf = time.perf_counter() - t0
    t0 = time.perf_counter()
    jax.block_until_ready(vg(x))
    t_cg = time.perf_counter() - t0
    t_f = timeit(lambda: jax.block_until_ready(fj(x)), 21)
    t_vg = timeit(lambda: jax.block_until_ready(vg(x)), 21)
    print(f"P = {p}; value {ms(t_f)} ms, value+grad {ms(t_vg)} ms: ratio {t_vg / t_f:.2f} (goal ≤ 3); "
          f"compile {t_cf:.1f} s / {t_cg:.1f} s")
    out["objective"] = {"parameters": p, "value_ms": ms(t_f), "value_and_grad_ms": ms(t_vg),
                        "ratio": t_vg / t_f, "compile_value_s": t_cf, "compile_value_and_grad_s": t_cg}

    # AD vs central finite differences (2P jitted evaluations; step h ~ eps^(1/3))
    h = 1e-5
    eye = np.eye(p) * h

    def fd():
        return np.array([(float(fj(x + e)) - float(fj(x - e))) / (2 * h) for e in eye])

    g_fd = fd()
    g_ad = np.asarray(vg(x)[1])
    t_fd = timeit(fd, 5)
    rel = float(np.max(np.abs(g_ad - g_fd)) / np.max(np.abs(g_ad)))
    print(f"gradient: AD {ms(t_vg)} ms, central FD {ms(t_fd)} ms: {t_fd / t_vg:.1f}× (goal ≥ P/3 = {p / 3:.1f}); "
          f"max difference {rel:.1e} of max |g|")
    out["gradient"] = {"ad_ms": ms(t_vg), "fd_ms": ms(t_fd), "speedup": t_fd / t_vg, "goal": p / 3,
                       "max_rel_difference": rel, "fd_step": h}

    # vmap batch efficiency
    bf = jax.jit(jax.vmap(f))
    rng = np.random.default_rng(0)
    per = {}
    for b in (1, 256):
        xs = jnp.asarray(x0 + rng.uniform(-0.1, 0.1, (b, p)))
        jax.block_until_ready(bf(xs))
        per[b] = timeit(lambda: jax.block_until_ready(bf(xs)), 7) / b
    print(f"vmap: {ms(per[1])} ms per design alone, {ms(per[256])} ms in a batch of 256: "
          f"{per[1] / per[256]:.1f}× (goal ≥ 8× on a CPU, ≥ 100× on a GPU)")
    out["vmap"] = {"per_design_ms_batch_1": ms(per[1]), "per_design_ms_batch_256": ms(per[256]),
                   "gain": per[1] / per[256]}

    if quick():  # --quick: the goals only (objective, gradient, vmap, hullopt run), not the cost sweeps
        out["resolution"], out["parameters"] = [], []
        return cli_run(out)

    # cost vs resolution: Wigley sections, gradient w.r.t. every vertex
    def on_sections(yz, s):
        return full_objective(eqx.tree_at(lambda q: q.yz, s, yz), jnp.asarray(6.25))

    res = []
    for n, m in ((21, 25), (41, 49), (81, 97), (161, 193)):
        s = wigley(100.0, 10.0, 6.25, 10.0, n=n, m=m)
        fv = jax.jit(lambda yz, s=s: on_sections(yz, s))
        gv = jax.jit(jax.value_and_grad(lambda yz, s=s: on_sections(yz, s)))
        jax.block_until_ready(fv(s.yz))
        jax.block_until_ready(gv(s.yz))
        tv = timeit(lambda: jax.block_until_ready(fv(s.yz)), 7)
        tg = timeit(lambda: jax.block_until_ready(gv(s.yz)), 7)
        res.append({"stations": n, "points": int(s.yz.shape[1]), "value_ms": ms(tv), "value_and_grad_ms": ms(tg)})
        print(f"resolution {n}×{s.yz.shape[1]}: value {ms(tv)} ms, value+grad {ms(tg)} ms")
    out["resolution"] = res

    # cost vs number of parameters (distribution modes 1…8)
    par = []
    for modes in (1, 2, 4, 8):
        fm, xm = problem([f"design.distribution=[{{x_a = 0.0, x_b = 100.0, modes = {modes}, bound = 0.45}}]"])
        fv, gv = jax.jit(fm), jax.jit(jax.value_and_grad(fm))
        xm = xm + 0.01
        jax.block_until_ready(fv(xm))
        jax.block_until_ready(gv(xm))
        tv = timeit(lambda: jax.block_until_ready(fv(xm)), 11)
        tg = timeit(lambda: jax.block_until_ready(gv(xm)), 11)
        par.append({"parameters": int(xm.shape[0]), "value_ms": ms(tv), "value_and_grad_ms": ms(tg)})
        print(f"P = {xm.shape[0]}: value {ms(tv)} ms, value+grad {ms(tg)} ms")
    out["parameters"] = par
    cli_run(out)


def cli_run(out: dict) -> None:
    # hullopt run on the built-in example: cold (empty cache) and warm
    cli = [sys.executable, "-m", "hullopt", "run", str(ROOT / "configs" / "fit_cb_lcb.toml"), "--json"]
    with tempfile.TemporaryDirectory() as tmp:
        # the whole environment, not an empty one: on a GPU machine the run needs its CUDA paths (it exited 1 there)
        starts = [run_process(cli + ["--out", f"{tmp}/run{i}"], f"{tmp}/cache") for i in range(3)]
        t_import = run_process([sys.executable, "-c", "import hullopt.app.cli, jax"], f"{tmp}/cache")
        phases = [json.loads(Path(f"{tmp}/run{i}/report.json").read_text()).get("seconds", {}) for i in range(3)]
    print(f"hullopt run fit_cb_lcb: cold {starts[0]:.1f} s, warm {min(starts[1:]):.1f} s (goal < 2 s; "
          f"python + imports alone {t_import:.1f} s); phases cold {phases[0]}, warm {phases[-1]}")
    out["cli_run"] = {"cold_s": starts[0], "warm_s": min(starts[1:]), "import_s": t_import,
                      "phases_cold_s": phases[0], "phases_warm_s": phases[-1]}
    save("design", out)


if __name__ == "__main__":
    main()
