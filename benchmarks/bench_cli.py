"""One-off CLI calls against a whole NavalToolbox process on the same work (issue 18, item 2).

Each timing is a whole process, start to exit, measured in this one run with the commands interleaved (hullopt,
then NavalToolbox, then hullopt…) so both see the same machine load:

* **hydro** — ``hullopt hydro 'DTC-scaled.stl.gz?scale=59.407&lpp=355' --drafts 2:20:20 --json`` against
  ``python -c``: import navaltoolbox, load the full-scale DTC STL (written once, before timing), 20 drafts;
* **stability** — ``hullopt stability DTC --displacement 177804 --kg 20 --json`` (∇ 173,467 m³, 19 heels
  0…90°, free trim, the IS Code criteria) against NavalToolbox's GZ curve at the same 19 heels, loading and LCG
  (hullopt's upright LCB);
* **run** — ``hullopt run configs/fit_cb_lcb.toml`` (no peer);
* **fair** — the README's ``hullopt fair`` example (the noisy Wigley's 21 × 9 offsets; no peer, no goal).

hullopt **cold** is its first call with a fresh ``$HULLOPT_CACHE`` (the mesh read and sliced, the program
traced and compiled); **warm** the later calls (the sections and the compiled program kept there). Medians of
3 calls (2 with ``--quick``), cold ones too (a fresh cache each; the run's cold is one call, ~30 s). hullopt
runs from a snapshot of the package copied before timing (kept programs are keyed by hullopt's source: an edit
to the working tree during the run would make a warm call cold), its bytecode compiled first as ``pip install``
does (a cold call is a fresh cache, not a fresh Python). Writes ``results/cli.json``.

Run: ``.venv/bin/python benchmarks/bench_cli.py`` (or ``python benchmarks/run.py --only cli``).
"""

from __future__ import annotations

import compileall
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _common import HULLS, goal, quick, save

REPO = Path(__file__).resolve().parents[1]
DTC = f"{HULLS / 'DTC-scaled.stl.gz'}?scale=59.407&lpp=355"
DISPLACEMENT_T, VOLUME, KG = 177804.0, 173467.0, 20.0  # ≈ 1.025 t/m³ · ∇ (bench_stability.py's loading)
HULLOPT = [sys.executable, "-m", "hullopt"]  # the snapshot's, on PYTHONPATH (no console script needed)

NTB_HYDRO = """
import sys
import numpy as np
import navaltoolbox as ntb
v = ntb.Vessel(ntb.Hull(sys.argv[1])); v.ap, v.fp = 0.0, 355.0
calc = ntb.HydrostaticsCalculator(v, water_density=1025.0)
states = [calc.from_draft(float(t)) for t in np.linspace(2.0, 20.0, 20)]
print(states[-1].volume)
"""
NTB_GZ = """
import sys
import numpy as np
import navaltoolbox as ntb
v = ntb.Vessel(ntb.Hull(sys.argv[1])); v.ap, v.fp = 0.0, 355.0
curve = ntb.StabilityCalculator(v, 1025.0).gz_curve(1025.0 * float(sys.argv[2]), (float(sys.argv[3]), 0.0,
                                                     float(sys.argv[4])), [float(h) for h in np.linspace(0, 90, 19)])
print(curve.points()[-1])
"""


CPU: dict[str, list[float]] = {}  # CPU seconds (user + system) of each timed process, by label


def timed(cmd: list[str], env: dict | None = None, ok=(0,), cwd: Path = REPO, label: str = "") -> tuple[float, str]:
    """Wall time [s] of one whole process, and its stdout; its CPU time (user + system, all its threads; less
    sensitive to other jobs' load than the wall time) is appended to ``CPU[label]``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=cwd)
    dt = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    CPU.setdefault(label, []).append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    if p.returncode not in ok:
        raise RuntimeError(f"{' '.join(cmd)} exited {p.returncode}: {p.stderr[-2000:]}")
    return dt, p.stdout


def main() -> None:
    import json

    import numpy as np

    repeat = 2 if quick() else 3
    tmp = Path(tempfile.mkdtemp(prefix="bench-cli-"))
    stl = tmp / "dtc_fullscale.stl"
    from hullopt.models import MeshTransform, read_mesh

    read_mesh(HULLS / "DTC-scaled.stl.gz", MeshTransform(scale=59.407)).export(stl)  # NavalToolbox's input
    snapshot = tmp / "snapshot"
    shutil.copytree(REPO / "hullopt", snapshot / "hullopt", ignore=shutil.ignore_patterns("__pycache__"))
    compileall.compile_dir(snapshot, quiet=1)

    hydro = [*HULLOPT, "hydro", DTC, "--drafts", "2:20:20", "--json"]
    stab = [*HULLOPT, "stability", DTC, "--displacement", f"{DISPLACEMENT_T:g}", "--kg", f"{KG:g}", "--json"]
    run = [*HULLOPT, "run", str(REPO / "configs" / "fit_cb_lcb.toml"), "--out", str(tmp / "run")]
    fair = [*HULLOPT, "fair", "builtin:wigley?L=100&B=10&T=6.25&D=6.25", "--stations", "21", "--waterlines", "9",
            "--noise", "0.05", "--out", str(tmp / "fair")]
    loads = [os.getloadavg()[0]]
    res: dict = {}
    for name, cmd, ok in (("hydro", hydro, (0,)), ("stability", stab, (0, 4)), ("run", run, (0, 3)),
                          ("fair", fair, (0, 5))):
        path = [str(snapshot), *filter(None, [os.environ.get("PYTHONPATH")])]  # the snapshot before any wheels
        colds = []  # a fresh cache each; `repeat` of them but for the run's and the fairing's (~20 s each)
        for k in range(1 if name in ("run", "fair") else repeat):
            env = dict(os.environ, HULLOPT_CACHE=str(tmp / f"cache-{name}-{k}"), PYTHONPATH=os.pathsep.join(path))
            cold, out = timed(cmd, env, ok, snapshot, f"{name} cold")
            colds.append(cold)
        shown = " ".join(cmd[3:]).replace(str(REPO) + "/", "").replace(str(tmp), "TMP")  # no local paths
        res[name] = {"command": shown, "cold_s": statistics.median(colds), "cold_each_s": colds, "warm_s": []}
        if name == "stability":
            lcg = json.loads(out)["lcg"]
            peer = [sys.executable, "-c", NTB_GZ, str(stl), f"{VOLUME}", f"{lcg}", f"{KG}"]
        elif name == "hydro":
            peer = [sys.executable, "-c", NTB_HYDRO, str(stl)]
        else:
            peer = None
        if peer is not None:
            res[name]["navaltoolbox_s"] = []
        for _ in range(repeat):
            res[name]["warm_s"].append(timed(cmd, env, ok, snapshot, f"{name} warm")[0])
            if peer is not None:
                res[name]["navaltoolbox_s"].append(timed(peer, label=f"{name} navaltoolbox")[0])
        loads.append(os.getloadavg()[0])
    goals = []
    print(f"whole processes, medians of {repeat} (1-min load {min(loads):.1f}…{max(loads):.1f}):")
    for name, r in res.items():
        r["warm_median_s"] = statistics.median(r["warm_s"])
        r["cpu_s"] = {k.split(" ", 1)[1]: v for k, v in CPU.items() if k.startswith(f"{name} ")}
        cpu = {k: statistics.median(v) for k, v in r["cpu_s"].items()}
        line = (f"  {name:<10} hullopt cold {r['cold_s']:6.2f} s (median of {len(r['cold_each_s'])}), "
                f"warm {r['warm_median_s']:6.2f} s (CPU {cpu['warm']:.2f} s)")
        if "navaltoolbox_s" in r:
            r["navaltoolbox_median_s"] = statistics.median(r["navaltoolbox_s"])
            r["warm_over_navaltoolbox"] = r["warm_median_s"] / r["navaltoolbox_median_s"]
            line += f"; NavalToolbox process {r['navaltoolbox_median_s']:6.2f} s (CPU {cpu['navaltoolbox']:.2f} s; " \
                    f"hullopt warm / NTB {r['warm_over_navaltoolbox']:.2f})"
            peer = f"{r['navaltoolbox_median_s']:.2f} s (NavalToolbox process)"
            goals.append(goal(f"`hullopt {name}` DTC, one-off process, warm", r["warm_median_s"], "s",
                              "< NavalToolbox process", r["warm_median_s"] < r["navaltoolbox_median_s"], peer))
            goals.append(goal(f"`hullopt {name}` DTC, one-off process, cold (fresh cache)", r["cold_s"], "s",
                              "< 5", r["cold_s"] < 5, peer))  # issue 31
        elif name == "fair":
            goals.append(goal("`hullopt fair` (README example), whole process, warm", r["warm_median_s"], "s", "—",
                              None))
        else:
            goals.append(goal("`hullopt run configs/fit_cb_lcb.toml`, whole process, warm", r["warm_median_s"],
                              "s", "< 2", r["warm_median_s"] < 2))
            goals.append(goal("`hullopt run configs/fit_cb_lcb.toml`, whole process, cold (fresh cache)", r["cold_s"],
                              "s", "< 15", r["cold_s"] < 15))  # issue 31
        print(line)
    save("cli", {"repeat": repeat, "load_during": [round(v, 2) for v in loads], "navaltoolbox_stl": "DTC × 59.407",
                 "results": res, "goals": goals, "numpy": np.__version__})


if __name__ == "__main__":
    main()
