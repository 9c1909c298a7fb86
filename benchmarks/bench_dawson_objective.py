"""Dawson's method as a design objective ([W4 2/6] item 4): peak memory and wall time of value + gradient of the
calm-water R_T by ``method = "dawson"`` (:func:`hullopt.resistance.calm_water`, what ``calm_resistance`` and
``profile_resistance`` call) on the DTMB 5415 (``dtmb5415_navaltoolbox_fullscale.stl.gz?lpp=142``, draft 6.15 m)
at Fn 0.28, at the default grid a run uses (48 × 12 hull panels, 96 × 14 free-surface nodes), the gradient with
respect to the sections' offsets and the draft (every design variable reaches R_T through them), and the
compile time; also a three-speed profile (Fn 0.25, 0.28, 0.31), a coarse grid (64 × 10) and a sweep chunk (a
vmapped batch of designs, the sweep's default ``chunk = 4``).

Each case runs in a process of its own, so its peak resident memory (``resource.getrusage``, ru_maxrss) is its
own. ``--label before`` / ``--label after`` (default ``after``) names the code's state; the results merge into
``results/dawson_objective.json`` under that label. ``--quick``: the single-speed case alone. ``--case NAME``:
one case (the subprocess entry point).
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import time

import numpy as np
from _common import HULLS, RESULTS, goal, machine, quick, suffix

SPEC = f"{HULLS}/dtmb5415_navaltoolbox_fullscale.stl.gz?lpp=142"
DRAFT = 6.15
GIB = 1024.0**3
CASES = {  # name: (Froude numbers, grid keywords, designs in a vmapped batch)
    "one_speed": ((0.28,), {}, 0),
    "profile_3": ((0.25, 0.28, 0.31), {}, 0),
    "coarse_64x10": ((0.28,), {"columns": 64, "rows": 10}, 0),
    "chunk_4": ((0.28,), {}, 4),
}


def _rss_gib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024.0 / GIB  # Linux: KiB


def run_case(name: str) -> dict:
    """Compile and time value + gradient of the mean R_T over the case's speeds (and value alone)."""
    import jax
    import jax.numpy as jnp

    jax.config.update("jax_enable_x64", True)
    from hullopt.constants import G
    from hullopt.geometry import Sections
    from hullopt.models import load_hull
    from hullopt.resistance import calm_water
    from hullopt.resistance._dawson import dawson_wave_resistance

    fns, grid, batch = CASES[name]
    h = load_hull(SPEC).sections
    u = jnp.asarray(fns) * np.sqrt(G * float(h.lpp))
    base = _rss_gib()

    def r_total(yz, draft):
        s = Sections(h.x, yz, h.lpp)
        if grid:  # calm_water's R_T with Dawson's R_W on another grid
            cw = calm_water(s, draft, u, "holtrop")
            hm_wave = cw.r_wave
            rw = dawson_wave_resistance(s, draft, u, **grid).r_wave
            return jnp.mean(cw.total - hm_wave + rw)
        return jnp.mean(calm_water(s, draft, u, "dawson").total)

    vg = jax.value_and_grad(r_total, argnums=(0, 1))
    if batch:
        scale = jnp.linspace(0.98, 1.02, batch)
        f_v = jax.jit(lambda yz, t: jax.vmap(lambda b: r_total(yz * jnp.array([b, 1.0]), t))(scale))
        f_g = jax.jit(lambda yz, t: jax.vmap(lambda b: vg(yz * jnp.array([b, 1.0]), t))(scale))
    else:
        f_v, f_g = jax.jit(r_total), jax.jit(vg)
    yz, t = jnp.asarray(h.yz), jnp.asarray(DRAFT)
    t0 = time.perf_counter()
    c_g = f_g.lower(yz, t).compile()
    compile_s = time.perf_counter() - t0
    rss_compile = _rss_gib()
    t0 = time.perf_counter()
    out = jax.block_until_ready(c_g(yz, t))
    first_s = time.perf_counter() - t0
    times = []
    for _ in range(2):
        t0 = time.perf_counter()
        out = jax.block_until_ready(c_g(yz, t))
        times.append(time.perf_counter() - t0)
    rss_grad = _rss_gib()
    value, (g_yz, g_t) = out
    c_v = f_v.lower(yz, t).compile()
    jax.block_until_ready(c_v(yz, t))
    t0 = time.perf_counter()
    jax.block_until_ready(c_v(yz, t))
    value_s = time.perf_counter() - t0
    return {"case": name, "fn": list(fns), "grid": grid, "batch": batch,
            "value_N": np.asarray(value).tolist(), "grad_draft_N_per_m": np.asarray(g_t).tolist(),
            "grad_yz_norm": float(np.linalg.norm(np.asarray(g_yz))),
            "compile_grad_s": compile_s, "first_grad_s": first_s, "value_grad_s": float(np.median(times)),
            "value_s": value_s, "peak_rss_gib": _rss_gib(), "peak_rss_after_grad_gib": rss_grad,
            "rss_after_load_gib": base, "peak_rss_after_compile_gib": rss_compile}


LIMIT_GIB = 10.0  # a case past this resident size is stopped (the machine is shared): "failed" -9


def _watched(cmd):
    """Run ``cmd``, stopping it when its resident memory passes :data:`LIMIT_GIB`."""
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=os.environ | {"OMP_NUM_THREADS": os.environ.get("OMP_NUM_THREADS", "2")})
    peak = 0.0
    while p.poll() is None:
        try:
            with open(f"/proc/{p.pid}/status") as f:
                kib = next(int(line.split()[1]) for line in f if line.startswith("VmRSS"))
            peak = max(peak, kib * 1024.0 / GIB)
        except (OSError, StopIteration):
            pass
        if peak > LIMIT_GIB:
            p.kill()
        time.sleep(0.2)
    out, err = p.communicate()
    return subprocess.CompletedProcess(cmd, p.returncode, out, err + f"\n[watched peak RSS {peak:.2f} GiB]")


def main():
    if "--case" in sys.argv:
        print(json.dumps(run_case(sys.argv[sys.argv.index("--case") + 1])))
        return
    label = sys.argv[sys.argv.index("--label") + 1] if "--label" in sys.argv else "after"
    names = ["one_speed"] if quick() else list(CASES)
    if "--cases" in sys.argv:
        names = sys.argv[sys.argv.index("--cases") + 1].split(",")
    path = RESULTS / f"dawson_objective{suffix()}.json"
    data = json.loads(path.read_text()) if path.exists() else {}
    runs = data.setdefault(label, {})
    for name in names:
        t0 = time.perf_counter()
        p = _watched([sys.executable, __file__, "--case", name])
        if p.returncode != 0:
            runs[name] = {"case": name, "failed": p.returncode, "stderr": p.stderr[-1500:],
                          "wall_s": time.perf_counter() - t0, "machine": machine()}
        else:
            runs[name] = json.loads(p.stdout.strip().splitlines()[-1]) | {"machine": machine()}
        print(json.dumps(runs[name]), flush=True)
    one = data.get("after", {}).get("one_speed")
    if one and "failed" not in one:
        data["goals"] = [
            goal("dawson objective: value + gradient, DTMB 5415 Fn 0.28 (default grid)", round(one["value_grad_s"], 2),
                 "s", "≤ 6 (300 steps in 30 min)", one["value_grad_s"] <= 6.0),
            goal("dawson objective: peak RSS of value + gradient", round(one["peak_rss_gib"], 2), "GiB", "≤ 8",
                 one["peak_rss_gib"] <= 8.0)]
    RESULTS.mkdir(exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, indent=2) + "\n")
    tmp.replace(path)


if __name__ == "__main__":
    main()
