"""The KCS bow-bluntness sweep (configs/pareto_bow.toml) as a user runs it: one whole ``hullopt run`` process,
cold (a fresh ``$HULLOPT_CACHE``: every program traced and compiled), to the end (the rescoring of every design
by each method, the designs' folders, the plots, report.html).

* On the CPU: the config as it is, 6 designs in one chunk (issue 31's goal: < 2 min cold on 2 cores).
* On a GPU: 64 designs in one chunk (``--set sweep.count=64 sweep.chunk=64``; the goal: < 60 s cold).

``--designs N`` sets the count either way. A design that misses its targets (exit 3) is still a finished run. The
run's own phase times (report.json ``seconds``: setup, solve, assess, rescore, files) say where the time went.
The same run again with that cache is the warm run a user repeating it (or a what-if with new numbers) waits for:
recorded beside the cold one, with its phases. Writes ``results/sweep.json`` (``sweep-gpu.json`` on a GPU).

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
    runs = {}
    with tempfile.TemporaryDirectory(prefix="bench-sweep-") as tmp:
        for kind in ("cold", "warm"):
            wall = run_process(cmd + ["--out", f"{tmp}/{kind}"], f"{tmp}/cache", ok=(0, 3))
            report = json.loads((Path(tmp) / kind / "report.json").read_text())
            # the run's own phase times (setup, solve, assess, rescore, files)
            runs[kind] = wall, report.get("seconds", {})
            print(f"KCS bow sweep, {n} designs, {kind}: {wall:.1f} s ({wall / n:.2f} s a design); phases: "
                  + ", ".join(f"{k} {v:.1f} s" for k, v in runs[kind][1].items()))
    designs = report.get("designs", [])
    met = sum(bool(d.get("met")) for d in designs)
    wall, phases = runs["cold"]
    print(f"goal < {limit:.0f} s cold; {met} of {len(designs)} designs meet their targets")
    save("sweep", {"designs": n, "cold_s": wall, "per_design_s": wall / n, "met": met, "phases_s": phases,
                   "warm_s": runs["warm"][0], "warm_phases_s": runs["warm"][1],
                   "command": " ".join(cmd[1:]).replace(str(ROOT) + "/", ""),
                   "goals": [goal(f"KCS bow sweep (configs/pareto_bow.toml), {n} designs, whole process, cold", wall,
                                  "s", f"< {limit:.0f}", wall < limit),
                             goal(f"KCS bow sweep, {n} designs, whole process, warm", runs["warm"][0], "s", "—",
                                  None)]})


if __name__ == "__main__":
    main()
