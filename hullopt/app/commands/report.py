"""``hullopt report RUN_DIR``: (re)write a run folder's ``report.html``."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ...errors import HullError
from .._app import app
from ..output import busy, print_json, say, table, warn, wrote


@app.command("report")
def report_command(
    run_dir: Annotated[Path, typer.Argument(help="Run folder (with config.json, parent.json, report.json)")],
) -> None:
    """Rebuild RUN_DIR/report.html: one self-contained page (plotly's JavaScript embedded: it opens offline)
    with the parent and design hulls in 3D, the body plan, the sectional-area curves, the targets, the
    objectives parent → design with their units, convergence, warnings and, for a sweep, the Pareto front.
    The hulls are rebuilt from the folder's config, parent and report, never from its meshes."""
    from ...report import write_report

    with busy(f"writing {run_dir}/report.html"):
        path = write_report(run_dir)
    wrote(path, f"{path.stat().st_size / 1e6:.1f} MB; open it in a browser")


@app.command("rescore")
def rescore_command(
    run_dir: Annotated[Path, typer.Argument(help="Run folder of a minimise or Pareto run")],
    json: Annotated[bool, typer.Option("--json", help="Print the re-scoring as JSON.")] = False,
) -> None:
    """Re-score a run's designs and its parent by every calm-water method (Holtrop–Mennen, Michell, panel) and
    every added-resistance method (NMRI, SNNM, STAWAVE-2) over the run's profile and off it (±10 % speed, ±2 s
    T_p); warn of each design whose gain does not hold under an independent method of each kind. Writes
    ``rescored`` and the warnings into report.json, the designs under each pair of methods into
    rescored_fronts.png, and rebuilds report.html."""
    from ...report import FRONTS_NAME, plot_rescored_fronts, read_run, write_json, write_report
    from ...study import folder_study, read_run_config
    from ..run import has_fronts

    cfg = read_run_config(run_dir)
    _, report = read_run(run_dir)
    if cfg.objective is None:
        raise HullError(f"{run_dir}: nothing to re-score (a run with an objective is needed; this is a "
                        f"{cfg.kind!r} run without one)")
    study = folder_study(run_dir, cfg)
    designs = study.designs_of(report)
    if not designs:
        raise HullError(f"{run_dir}: nothing to re-score (the report has no designs: an unfinished run?)")
    with busy(f"re-scoring {len(designs)} design(s) of {run_dir}", quiet=json):
        rescored, doubts = study.rescore(designs)
        old = report.get("rescored_warnings", [])
        report["warnings"] = [w for w in report.get("warnings", []) if w not in old] + doubts
        report["rescored"], report["rescored_warnings"] = rescored, doubts
        met = [d.get("met", True) for d in report["designs"]] if report.get("designs") else None
        written = ["report.json", "report.html"]
        if has_fronts(rescored):
            plot_rescored_fronts(rescored, run_dir / FRONTS_NAME, met)
            written.insert(0, FRONTS_NAME)
        write_json(run_dir / "report.json", report)
        write_report(run_dir, report)
    if json:
        print_json(rescored)
    else:
        _print_rescored(rescored)
    for name in written:
        wrote(run_dir / name, json=json)
    for w in doubts:  # on stderr, beside the JSON too
        warn(w)


def _print_rescored(r: dict) -> None:
    """Each method's parent value and each design's change at the nominal condition and at its worst."""
    methods = r["methods"]
    n = len(next(iter(methods.values()))["designs"])
    rows = [[f"{m['kind']}: {m['method']}" + (" (objective's)" if m["own"] else "")
             + (" (outside its validity)" if m.get("outside_validity") else ""), m["parent"] / 1e3,
             *(f"{m['change_pct'][k]:+.2f} / {m['worst_pct'][k]:+.2f}" + ("" if m["holds"][k] else " ✗")
               for k in range(n))] for m in methods.values()]
    table("Re-scored by independent methods (change against the parent: nominal / worst condition [%])",
          ["method", "parent [kN]", *(f"design {k}" for k in range(n))], rows)
    if r.get("note"):
        say(r["note"])
