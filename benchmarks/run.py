"""Run every benchmark script in this folder (``bench_*.py``), each in its own process, one after the other; then
write ``results/summary.md``: one table of every goal from the ``results/*.json`` files, with the date, the
machine (cores, load at the start), the jax version and the device, beside the peers' figures (NavalToolbox,
ship_model_lib, SLSQP). Paste it into README.md's "Goals at a glance". On a GPU (jax with CUDA: ``make bench-gpu``)
each script writes ``results/<name>-gpu.json`` beside the CPU's ``<name>.json`` and the table puts the two side
by side.

Usage (from anywhere)::

    python benchmarks/run.py                    # every bench_*.py, then the summary
    python benchmarks/run.py --quick            # HULLOPT_BENCH_QUICK=1: shorter runs where a script offers them
    python benchmarks/run.py --only hydro,peers # just these scripts (bench_hydro.py, bench_peers.py), in that order
    python benchmarks/run.py --timeout 300      # a script still running after 300 s is stopped and reported
    python benchmarks/run.py --summary          # only rewrite results/summary.md from the stored results
    python benchmarks/run.py --summary --readme # … and paste it into README.md's "Goals at a glance"

A script that fails is reported and the others still run; its stored result (if any) is then marked as older
than this run. The exit code is 1 if any script failed.

Goals: a result file may list its own under ``"goals"`` (rows made with ``_common.goal``: name, value, unit,
target, met, peer); for the files that don't, :data:`EXTRACT` below reads the goals stated in README.md from
their numbers.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"


def _g(name, value, unit, target, met, peer=None):
    return {"name": name, "value": value, "unit": unit, "target": target, "met": met, "peer": peer}


def _hydro(d):
    rel = d["max_relative_difference"]
    core = {k: v for k, v in rel.items() if k not in ("cb", "wetted_surface")}
    worst = max(core, key=core.get)
    t = d["table_seconds"]
    return [
        _g(f"hydrostatics vs NavalToolbox, DTC 20 drafts (worst: {worst})", core[worst], "rel.", "≤ 1e-3",
           core[worst] <= 1e-3, "NavalToolbox 0.9"),
        _g("wetted surface vs NavalToolbox", rel["wetted_surface"], "rel.", "≤ 1e-3", rel["wetted_surface"] <= 1e-3,
           "NavalToolbox 0.9"),
        _g("20-draft table, jitted, warm", t["hullopt_warm"] * 1e3, "ms", "faster than the peer",
           t["hullopt_warm"] < t["navaltoolbox"], f"{t['navaltoolbox'] * 1e3:.0f} ms"),
        _g("20-draft table, first call (compile)", t["hullopt_first"], "s", "—", None,
           f"{t['navaltoolbox']:.2f} s"),
        _g("value + gradient / value (every section vertex)", d["grad_over_value"], "×", "≤ 3",
           d["grad_over_value"] <= 3),
        _g("`hullopt hydro` Wigley, whole process, warm", d["cli_seconds"]["warm"], "s", "—", None),
    ]


def _stability(d):
    heel = d["heel_deg"]
    ours, ntb, cut = d["gz_hullopt"], d["gz_navaltoolbox"], d["gz_mesh_cut"]
    upto = [i for i, h in enumerate(heel) if 0 < h <= 40]
    rel = max(abs(ours[i] / ntb[i] - 1) for i in upto)
    dcut = max(abs(ours[i] - cut[i]) for i in upto)
    s = d["seconds"]
    return [
        _g("GZ vs NavalToolbox, DTC, heel ≤ 40°", rel, "rel.", "≤ 1e-2", rel <= 1e-2, "NavalToolbox 0.9"),
        _g("GZ vs the exact mesh cut, heel ≤ 40°", dcut, "m", "≤ 1e-3", dcut <= 1e-3, "manifold3d cut"),
        _g("GZ curve, 19 heels, warm", s["gz_warm"], "s", "faster than the peer", s["gz_warm"] < s["navaltoolbox"],
           f"{s['navaltoolbox']:.2f} s"),
        _g("GZ curve + IS Code criteria, warm", s["criteria_warm"], "s", "faster than the peer",
           s["criteria_warm"] < s["navaltoolbox"], f"{s['navaltoolbox']:.2f} s"),
    ]


def _design(d):
    o, g, v = d["objective"], d["gradient"], d["vmap"]
    rows = [
        _g(f"design objective value + gradient / value (P = {o['parameters']})", o["ratio"], "×", "≤ 3",
           o["ratio"] <= 3),
        _g("AD gradient vs central finite differences", g["speedup"], "× faster", f"≥ P/3 = {g['goal']:.1f}",
           g["speedup"] >= g["goal"], "central FD"),
        _g("vmap(256) gain per design", v["gain"], "×", "≥ 8 (CPU), ≥ 100 (GPU)",
           v["gain"] >= (8 if d["machine"]["device"]["platform"] == "cpu" else 100)),
    ]
    if "cli_run" in d:
        rows.append(_g("`hullopt run configs/fit_cb_lcb.toml`, warm", d["cli_run"]["warm_s"], "s", "< 2",
                       d["cli_run"]["warm_s"] < 2))
    return rows


def _fit(d):
    rows = []
    for case, r in d.items():
        if not isinstance(r, dict) or "ours_traced" not in r:
            continue
        ours, tol = r["ours_traced"], r["ours_jit_to_tolerance"]
        slsqp = {k: v for k, v in r.items() if k.startswith("slsqp_zero")}
        loose = next((v for k, v in slsqp.items() if k.endswith("ftol_1")), None)
        tight = next((v for k, v in slsqp.items() if not k.endswith("ftol_1")), None)
        rows.append(_g(f"fit Cb/LCB ({case}): targets met", ours["met"], "", "met", bool(ours["met"])))
        if loose:
            rows.append(_g(f"fit ({case}) to the tolerances, warm", tol["warm_s"] * 1e3, "ms", "faster than the peer",
                           tol["warm_s"] < loose["time_s"], f"SLSQP + FD {loose['time_s'] * 1e3:.1f} ms"))
        if tight:
            rows.append(_g(f"fit ({case}) converged, warm", ours["warm_s"] * 1e3, "ms", "faster than the peer",
                           ours["warm_s"] < tight["time_s"], f"SLSQP + FD {tight['time_s'] * 1e3:.1f} ms"))
    return rows


def _motions(d):
    rows = []
    w = next((v for k, v in d.items() if k.startswith("wigley")), None)
    if w:
        rows.append(_g("motions value + gradient / value (Wigley, 30 ω)", w["ratio"], "×", "—", None))
        chunk = f" (chunks of {w['vmap_chunk']})" if w.get("vmap_chunk", w["vmap_designs"]) < w["vmap_designs"] else ""
        rss = f"; peak RSS {w['peak_rss_gib_after_batch']:.1f} GiB" if "peak_rss_gib_after_batch" in w else ""
        rows.append(_g(f"motions vmap over {w['vmap_designs']} designs × 30 ω{chunk}, per design",
                       w["vmap_per_design_s"], "s", "—", None, f"alone {_fmt(w['value_s'], 's')}{rss}"))
    k = next((v for kk, v in d.items() if kk.startswith("kcs")), None)
    if k:
        lam, tot, mot = k["lambda_over_l"], k["nmri"]["total"], k["nmri"]["motion"]
        refl = k["nmri"]["reflection"]
        i = max(range(len(tot)), key=tot.__getitem__)
        ok = 6 <= tot[i] <= 14 and 0.95 <= lam[i] <= 1.4 and mot[i] > refl[i]
        peers = ", ".join(f"{m.upper()} {max(k[m]['total']):.1f}" for m in ("snnm", "stawave2") if m in k)
        rows.append(_g("KCS σ_aw peak (Fn 0.26, head seas), motion part dominant", tot[i], f"at λ/L {lam[i]}",
                       "6–14 at λ/L 0.95–1.4", ok, peers))
        short = [tot[j] for j, x in enumerate(lam) if x < 0.45]
        rows.append(_g("KCS σ_aw short-wave level (λ/L ≤ 0.4)", max(short), "", "1.5–3.5",
                       all(1.5 <= s <= 3.5 for s in short)))
    return rows


EXTRACT = {"hydro": _hydro, "stability": _stability, "design": _design, "fit": _fit, "motions": _motions}


def _fmt(value, unit):
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (int, float)) and unit == "rel.":
        return f"{value:.1e} rel."
    if isinstance(value, (int, float)):
        a = abs(value)
        text = f"{value:.1e}" if (a and (a < 1e-2 or a >= 1e5)) else f"{value:.3g}" if a < 100 else f"{value:,.0f}"
        return f"{text} {unit}".strip()
    return f"{value} {unit}".strip()


def _machine_line(m):
    dev = m.get("device") or {}
    dev_text = f"{dev.get('platform', '?')} ({dev.get('kind', '?')})" if dev else "not recorded"
    load = m.get("load_at_start")
    return (f"{m.get('cores', '?')} cores {m.get('cpu', '')}, load at start "
            f"{'not recorded' if load is None else load}, Python {m.get('python', '?')}, jax {m.get('jax', '?')}, "
            f"device {dev_text}")


def _device(stem: str) -> tuple[str, str]:
    """``(benchmark, device label)`` of a result file's stem: ``design`` → ``("design", "CPU")``,
    ``design-gpu`` → ``("design", "GPU")`` (``_common.save``'s suffix)."""
    name, _, backend = stem.partition("-")
    return name, (backend or "cpu").upper()


def summary(started: str | None = None, failed: dict | None = None, run_machine: dict | None = None) -> str:
    """The summary table (Markdown) of every ``results/*.json``, with one column of measured values per device
    (CPU, and GPU where ``results/*-gpu.json`` exist) side by side; ``started``: this run's start (older
    results are marked), ``failed``: script name → exit code, ``run_machine``: ``_common.machine()`` at the
    start (None: the newest result's)."""
    failed = failed or {}
    machines, table = {}, {}  # (benchmark, goal) -> {device: goal row with "when"}
    for path in sorted(RESULTS.glob("*.json")):
        name, dev = _device(path.stem)
        data = json.loads(path.read_text())
        m = data.get("machine", {})
        machines[(name, dev)] = m
        goals = data.get("goals")
        if goals is None and name in EXTRACT:
            try:
                goals = EXTRACT[name](data)
            except (KeyError, TypeError, ValueError, ZeroDivisionError) as e:
                goals = [_g(f"(could not read the goals: {type(e).__name__} {e})", "", "", "—", None)]
        if not goals:
            goals = [_g("(no goals recorded)", "", "", "—", None)]
        stale = " (older than this run)" if started and m.get("date", "") and m["date"][:16] < started[:16] else ""
        load = m.get("load_at_start")
        when = f"{m.get('date', '?')}{stale}; load {'not recorded' if load is None else load}"
        for g in goals:
            table.setdefault((name, g["name"]), {})[dev] = {"when": when} | g  # a merged row keeps its own
    devices = sorted({dev for _, dev in machines}, key=lambda d: (d != "CPU", d))
    rows = []
    for (name, goal_name), by_dev in table.items():
        first = by_dev[next(d for d in devices if d in by_dev)]
        peers = [by_dev[d].get("peer") or "—" if d in by_dev else "—" for d in devices]
        peer = peers[0] if len(set(peers)) == 1 else " / ".join(peers)  # one per device where they differ
        cells = [_fmt(by_dev[d]["value"], by_dev[d].get("unit", "")) if d in by_dev else "—" for d in devices]
        met = " / ".join({True: "**met**", False: "**missed**", None: "—"}[by_dev[d].get("met")] if d in by_dev
                         else "—" for d in devices)
        when = " / ".join(by_dev[d]["when"] if d in by_dev else "—" for d in devices)
        rows.append(f"| {name} | {goal_name} | {' | '.join(cells)} | {first.get('target', '—')} | {met} "
                    f"| {peer} | {when} |")
    for name, rc in failed.items():
        rc = f"exit {rc}" if isinstance(rc, int) else rc
        rows.append(f"| {name} | the script failed ({rc}): its row(s) above, if any, are from an earlier run "
                    f"| {' | '.join('—' for _ in devices)} | — | **failed** | — | — |")
    lines = []
    ran_on = run_machine and ("CPU" if run_machine["device"]["platform"] == "cpu" else "GPU")
    for dev in devices:
        ms = [m for (_, d), m in machines.items() if d == dev]
        m = run_machine if dev == ran_on else max(ms, key=lambda m: m.get("date", ""))
        mix = [f"{what} {', '.join(v)}" for what, v in (
            ("jax", sorted({x.get("jax", "?") for x in ms})),
            ("devices", sorted({x.get("device", {}).get("kind", "?") for x in ms}))) if len(v) > 1]
        mixed = f" (its results mix {'; '.join(mix)})" if mix else ""
        lines.append(f"- {dev}: {_machine_line(m)}{mixed}.")
    lines.insert(0, f"Run {started or 'of the stored results'}; machines:")
    lines.append("")
    lines.append(f"| benchmark | goal | {' | '.join(f'measured ({d})' for d in devices)} | target | met "
                 f"({' / '.join(devices)}) | peer | recorded (UTC; 1-min load at start) |")
    lines.append("|---" * (6 + len(devices)) + "|")
    lines += rows
    lines.append("")
    for dev in devices:
        mets = [by_dev[dev].get("met") for by_dev in table.values() if dev in by_dev]
        lines.append(f"{dev}: {mets.count(True)} goals met, {mets.count(False)} missed.")
    if failed:
        lines.append(f"{len(failed)} script(s) failed.")
    return "\n".join(lines) + "\n"


README = HERE / "README.md"
BEGIN = "<!-- goals-at-a-glance: paste results/summary.md below this line -->"
END = "<!-- end of goals-at-a-glance -->"


def paste_into_readme(text: str) -> None:
    """Replace what lies between README.md's goals-at-a-glance markers by ``text``."""
    readme = README.read_text()
    if BEGIN not in readme or END not in readme:
        raise SystemExit(f"{README}: the markers {BEGIN!r} … {END!r} are missing; paste results/summary.md by hand")
    head, rest = readme.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    README.write_text(f"{head}{BEGIN}\n\n{text.strip()}\n\n{END}{tail}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="HULLOPT_BENCH_QUICK=1 for every script: shorter runs")
    ap.add_argument("--only", default="", help="comma-separated names (hydro, peers, …): run just these scripts")
    ap.add_argument("--timeout", type=float, default=None, help="seconds each script may run (default: no limit)")
    ap.add_argument("--require-gpu", action="store_true", help="stop unless jax's default device is a GPU")
    ap.add_argument("--summary", action="store_true", help="only rewrite results/summary.md")
    ap.add_argument("--readme", action="store_true", help="also paste the table into README.md's Goals at a glance")
    args = ap.parse_args(argv)
    sys.path.insert(0, str(HERE))
    import _common  # its LOAD_AT_START: the load before any benchmark starts

    run_machine = None if args.summary else _common.machine()
    if args.require_gpu and run_machine["device"]["platform"] != "gpu":
        ap.error(f"--require-gpu: jax's default device is {run_machine['device']['platform']} "
                 f"({run_machine['device']['kind']}); install the gpu extra on a machine with an NVIDIA GPU")
    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    failed = {}
    if not args.summary:
        scripts = sorted(HERE.glob("bench_*.py"))
        if args.only:
            want = [f"bench_{n.strip().removeprefix('bench_').removesuffix('.py')}.py" for n in args.only.split(",")]
            unknown = set(want) - {s.name for s in scripts}
            if unknown:
                ap.error(f"--only: no such script(s) {sorted(unknown)}; expected names of {[s.name for s in scripts]}")
            scripts = [HERE / w for w in want]  # in the order given
        env = dict(os.environ, HULLOPT_BENCH_QUICK="1" if args.quick else os.environ.get("HULLOPT_BENCH_QUICK", ""))
        for script in scripts:
            print(f"== {script.name}", flush=True)
            t0 = time.perf_counter()
            # its own process group, so that a timeout also ends the hullopt processes it started
            proc = subprocess.Popen([sys.executable, str(script)], cwd=HERE, env=env, start_new_session=True)
            try:
                rc = proc.wait(timeout=args.timeout)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
                rc = f"timed out after {args.timeout:g} s"
            print(f"== {script.name}: {'ok' if rc == 0 else f'FAILED ({rc})'} in {time.perf_counter() - t0:.0f} s",
                  flush=True)
            if rc:
                failed[script.stem.removeprefix("bench_")] = rc
    text = summary(None if args.summary else started, failed, run_machine)
    (RESULTS / "summary.md").write_text(text)
    if args.readme:
        paste_into_readme(text)
    print(text)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
