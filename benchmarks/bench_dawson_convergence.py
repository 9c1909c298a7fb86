"""Grid convergence of hullopt's Dawson C_W on the DTMB 5415 at Fr 0.28 against WARP ([W4 2/6] item 3).

The hull: the DTMB 5415 model of configs/l2sea_5415.toml (examples/hulls' NavalToolbox mesh scaled to Lpp
5.720 m, 201 stations, draft 0.248 m, even keel), the L2-Sea benchmark's condition. hullopt's
:func:`hullopt.resistance.dawson_wave_resistance` on its default grid (48 × 12 hull panels, 96 × 14 free-surface
nodes) and on grids refined by √2 and 2 in every direction (and one coarsened by √2), the free surface's extent
held (one wet length behind the stern and beside the centreline); C_W = R_W/(½ρU²S), S hullopt's wetted surface
at rest. Against WARP's at its finest grid G1 (L2-Sea's own grid 8.48e-4; hullopt's 5415 written to WARP's grid
8.31e-4: benchmarks/l2sea/README.md). Value only (no gradient); the wall time of each grid is recorded (compile
included: each grid is its own program).

Run: ``cd benchmarks && ../.venv/bin/python bench_dawson_convergence.py [--quick] [--factors 0.7071,1,1.4142]``
(``--quick``: the default and √2 grids only; ``--factors``: those refinements only); results in
results/dawson_convergence.json.
"""

from __future__ import annotations

import time

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np  # noqa: E402
from _common import HULLS, goal, quick, save  # noqa: E402

from hullopt.constants import G  # noqa: E402
from hullopt.hydro import hydrostatics  # noqa: E402
from hullopt.models import load_hull  # noqa: E402
from hullopt.resistance import dawson_wave_resistance, wave_resistance_coefficient  # noqa: E402

SPEC = str(HULLS / "dtmb5415_navaltoolbox_fullscale.stl.gz") + "?scale=0.040281973816717&lpp=5.72"
SPEC_REL = "examples/hulls/dtmb5415_navaltoolbox_fullscale.stl.gz?scale=0.040281973816717&lpp=5.72"
DRAFT = 0.248
FROUDE = 0.28
WARP_G1 = {"l2sea_grid": 8.478672e-4, "written_grid": 8.31e-4}  # benchmarks/l2sea/README.md, this turn's G1 run
BASE = (48, 12, 96, 14)  # stations, girth (hull panels), columns, rows (free-surface nodes): the defaults
FACTORS = (1 / np.sqrt(2), 1.0, np.sqrt(2), 2.0)


def grid(f: float) -> dict:
    """The default grid refined by ``f`` in every direction (even counts)."""
    st, gi, co, ro = (max(2 * int(round(n * f / 2)), 4) for n in BASE)
    return {"stations": st, "girth": gi, "columns": co, "rows": ro}


def main() -> None:
    import sys

    only = [float(a) for a in sys.argv[sys.argv.index("--factors") + 1].split(",")] if "--factors" in sys.argv else None
    s = load_hull(SPEC).sections
    speed = FROUDE * np.sqrt(G * float(s.lpp))
    wetted = float(hydrostatics(s, DRAFT).wetted_surface)
    rows = []
    for f in only or (FACTORS[1:3] if quick() else FACTORS):
        kw = grid(f)
        t0 = time.perf_counter()
        r = jax.jit(lambda s, t: dawson_wave_resistance(s, t, speed, **kw).r_wave)(s, DRAFT)
        rw = float(r)
        dt = time.perf_counter() - t0
        cw = float(wave_resistance_coefficient(rw, speed, wetted))
        panels = kw["stations"] * kw["girth"] + kw["columns"] * kw["rows"]
        rows.append({"factor": float(f), **kw, "panels": panels, "r_wave_N": rw, "cw": cw, "seconds": dt,
                     "cw_over_warp_g1": cw / WARP_G1["l2sea_grid"],
                     "cw_over_warp_g1_written": cw / WARP_G1["written_grid"]})
        print(f"refined ×{f:.3f} {kw} ({panels} panels): C_W {cw:.4e} ({cw / WARP_G1['l2sea_grid']:.3f} of WARP "
              f"G1) {dt:.0f} s")
    cws = [r["cw"] for r in rows]
    # Richardson: the three finest grids (ratio √2), the observed order and the extrapolated value
    rich = None
    if len(cws) >= 3:
        c1, c2, c3 = cws[-3], cws[-2], cws[-1]
        ratio = (c2 - c1) / (c3 - c2) if c3 != c2 else np.inf
        if np.isfinite(ratio) and ratio > 0:
            p = float(np.log(ratio) / np.log(np.sqrt(2)))
            ext = c3 + (c3 - c2) / (np.sqrt(2) ** p - 1)
            rich = {"order": p, "cw_extrapolated": float(ext), "over_warp_g1": float(ext / WARP_G1["l2sea_grid"])}
    base = next((r for r in rows if r["factor"] == 1.0), rows[0])
    finest = rows[-1]
    data = {
        "hull": SPEC_REL, "draft": DRAFT, "froude": FROUDE, "speed": float(speed), "wetted_surface": wetted,
        "grids": rows, "richardson": rich, "warp_g1": WARP_G1,
        "goals": [
            goal("Dawson C_W of the DTMB 5415 at Fr 0.28, hullopt's default grid / WARP G1 (L2-Sea's grid)",
                 base["cw_over_warp_g1"] - 1.0, "rel.", "within ±15 %", bool(abs(base["cw_over_warp_g1"] - 1) <= 0.15),
                 f"WARP G1 {WARP_G1['l2sea_grid']:.3e}"),
            goal("the same on the finest grid", finest["cw_over_warp_g1"] - 1.0, "rel.", "within ±15 %",
                 bool(abs(finest["cw_over_warp_g1"] - 1) <= 0.15), f"×{finest['factor']:.2f}"),
            goal("grid change of the C_W, finest two grids", cws[-1] / cws[-2] - 1.0, "rel.", "—", None),
        ],
    }
    print("wrote", save("dawson_convergence", data))


if __name__ == "__main__":
    t0 = time.perf_counter()
    main()
    print(f"{time.perf_counter() - t0:.0f} s")
