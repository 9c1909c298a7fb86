"""Hydrostatics benchmarks (issue [1/8]).

1. A 20-draft hydrostatic table of the DTC: hullopt vs NavalToolbox on the same (full-scale) mesh — values
   side by side and the time ratio.
2. The cost of value-and-gradient over value for the hydrostatics (gradient w.r.t. every section vertex).
3. Cold and warm start of ``hullopt hydro`` (JAX persistent compilation cache).

Run: ``make bench`` (or ``.venv/bin/python benchmarks/bench_hydro.py``); results in results/hydro.json.
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
from _common import HULLS, run_process, save, timeit  # noqa: E402

from hullopt.hydro import hydrostatic_table, hydrostatics  # noqa: E402
from hullopt.models import MeshTransform, read_mesh, slice_mesh  # noqa: E402

DTC = HULLS / "DTC-scaled.stl.gz"
DRAFTS = np.linspace(2.0, 20.0, 20)


def navaltoolbox_table(stl: Path) -> tuple[dict, float]:
    import navaltoolbox as ntb

    vessel = ntb.Vessel(ntb.Hull(str(stl)))
    vessel.ap, vessel.fp = 0.0, 355.0
    calc = ntb.HydrostaticsCalculator(vessel, water_density=1025.0)
    states = [calc.from_draft(float(t)) for t in DRAFTS]  # warm-up
    t = timeit(lambda: [calc.from_draft(float(t)) for t in DRAFTS], repeat=3)
    out = {
        "volume": [s.volume for s in states], "lcb": [s.lcb for s in states], "kb": [s.vcb for s in states],
        "awp": [s.waterplane_area for s in states], "lcf": [s.lcf for s in states], "bmt": [s.bmt for s in states],
        "bml": [s.bml for s in states], "wetted_surface": [s.wetted_surface_area for s in states],
        "cb": [s.cb for s in states],
    }
    return out, t


def main() -> None:
    t0 = time.perf_counter()
    mesh = read_mesh(DTC, MeshTransform(scale=59.407))
    sections = slice_mesh(mesh, 355.0)
    t_slice = time.perf_counter() - t0
    table = jax.jit(hydrostatic_table)
    t0 = time.perf_counter()
    ours = jax.block_until_ready(table(sections, jnp.asarray(DRAFTS)))
    t_first = time.perf_counter() - t0
    t_ours = timeit(lambda: jax.block_until_ready(table(sections, jnp.asarray(DRAFTS))))

    with tempfile.TemporaryDirectory() as tmp:
        stl = Path(tmp) / "dtc_fullscale.stl"
        mesh.export(stl)
        theirs, t_theirs = navaltoolbox_table(stl)

    keys = list(theirs)
    rel = {k: float(np.max(np.abs(np.asarray(getattr(ours, k)) / np.asarray(theirs[k]) - 1))) for k in keys}
    print(f"DTC {sections.n}×{sections.m} sections (slicing {t_slice:.2f} s); 20 drafts {DRAFTS[0]}…{DRAFTS[-1]} m")
    print(f"{'draft':>6} " + " ".join(f"{k:>22}" for k in keys))
    for i, t in enumerate(DRAFTS):
        cells = [f"{float(getattr(ours, k)[i]):>10.5g}/{theirs[k][i]:<11.5g}" for k in keys]
        print(f"{t:6.2f} " + " ".join(cells))
    print("max relative difference:", {k: f"{v:.2e}" for k, v in rel.items()})
    print(f"hullopt table: {t_ours * 1e3:.2f} ms warm ({t_first:.2f} s first call with compile); "
          f"NavalToolbox: {t_theirs * 1e3:.1f} ms; ratio {t_theirs / t_ours:.1f}× faster")

    # value vs value-and-gradient (w.r.t. every vertex of every section and the draft)
    def objective(yz, t):
        h = hydrostatics(eqx_replace(sections, yz), t)
        return h.volume + h.kb + h.bmt + h.lcb + h.wetted_surface

    f = jax.jit(objective)
    vg = jax.jit(jax.value_and_grad(objective, argnums=(0, 1)))
    jax.block_until_ready(f(sections.yz, 14.5))
    jax.block_until_ready(vg(sections.yz, 14.5))
    t_f = timeit(lambda: jax.block_until_ready(f(sections.yz, 14.5)), 21)
    t_vg = timeit(lambda: jax.block_until_ready(vg(sections.yz, 14.5)), 21)
    print(f"value {t_f * 1e3:.2f} ms, value+gradient ({sections.yz.size + 1} inputs) {t_vg * 1e3:.2f} ms: "
          f"ratio {t_vg / t_f:.2f}")

    # CLI start-up: cold (empty compilation cache) and warm
    cli = [sys.executable, "-m", "hullopt", "hydro", "builtin:wigley?L=100&B=10&T=6.25&D=10", "--json"]
    with tempfile.TemporaryDirectory() as cache:
        starts = [run_process(cli, cache) for _ in range(3)]
    print(f"hullopt hydro: cold {starts[0]:.2f} s, warm {min(starts[1:]):.2f} s")
    save("hydro", {
        "dtc_sections": [sections.n, sections.m], "slice_seconds": t_slice, "drafts": DRAFTS.tolist(),
        "hullopt": {k: np.asarray(getattr(ours, k)).tolist() for k in keys}, "navaltoolbox": theirs,
        "max_relative_difference": rel, "table_seconds": {"hullopt_warm": t_ours, "hullopt_first": t_first,
                                                          "navaltoolbox": t_theirs},
        "value_seconds": t_f, "value_and_grad_seconds": t_vg, "grad_over_value": t_vg / t_f,
        "cli_seconds": {"cold": starts[0], "warm": min(starts[1:])},
    })


def eqx_replace(sections, yz):
    import equinox as eqx

    return eqx.tree_at(lambda s: s.yz, sections, yz)


if __name__ == "__main__":
    main()
