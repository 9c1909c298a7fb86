"""The KCS bow-bluntness sweep (configs/pareto_bow.toml) as a user runs it: one whole ``hullopt run`` process,
cold (a fresh ``$HULLOPT_CACHE``: every program traced and compiled), to the end (the rescoring of every design
by each method, the designs' folders, the plots, report.html).

* On the CPU: the config as it is, 6 designs in one chunk (issue 31's goal: < 2 min cold on 2 cores).
* On a GPU: 64 designs in one chunk (``--set sweep.count=64 sweep.chunk=64``; the goal: < 60 s cold).

``--designs N`` sets the count either way. A design that misses its targets (exit 3) is still a finished run. The
run's own phase times (report.json ``seconds``: setup, solve, assess, rescore, files) say where the time went.
Writes ``results/sweep.json`` (``sweep-gpu.json`` on a GPU).

Run: ``cd benchmarks && ../.venv/bin/python bench_sweep.py [--designs N]``.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

from _common import goal, run_process, save, suffix

ROOT = Path(__file__).resolve().parents[1]
CONFIG = ROOT / "configs" / "pareto_bow.toml"


def main() -> None:
    gpu = suffix() != ""
    n = int(sys.argv[sys.argv.index("--designs") + 1]) if "--designs" in sys.argv else (64 if gpu else 6)
    limit = 60.0 if gpu else 120.0
    cmd = [sys.executable, "-m", "hullopt", "run", str(CONFIG), "--json",
           "--set", f"sweep.count={n}", "--set", f"sweep.chunk={n}"]
    with tempfile.TemporaryDirectory(prefix="bench-sweep-") as tmp:
        wall = run_process(cmd + ["--out", f"{tmp}/run"], f"{tmp}/cache", ok=(0, 3))
        report = json.loads((Path(tmp) / "run" / "report.json").read_text())
    designs = report.get("designs", [])
    met = sum(bool(d.get("met")) for d in designs)
    phases = report.get("seconds", {})  # the run's own phase times (setup, solve, assess, rescore, files)
    print(f"KCS bow sweep, {n} designs, cold: {wall:.1f} s ({wall / n:.2f} s a design; goal < {limit:.0f} s); "
          f"{met} of {len(designs)} meet their targets; phases: " + ", ".join(f"{k} {v:.1f} s" for k, v in phases.items()))
    save("sweep", {"designs": n, "cold_s": wall, "per_design_s": wall / n, "met": met, "phases_s": phases,
                   "command": " ".join(cmd[1:]).replace(str(ROOT) + "/", ""),
                   "goals": [goal(f"KCS bow sweep (configs/pareto_bow.toml), {n} designs, whole process, cold", wall,
                                  "s", f"< {limit:.0f}", wall < limit)]})


if __name__ == "__main__":
    main()
