"""``hullopt run CONFIG``: a config-driven design run (fit, constrained minimum, Pareto sweep)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from .._app import app
from ..config import load_config
from ..output import console, print_json, table


@app.command("run")
def run_command(
    config: Annotated[Path, typer.Argument(help="Run config (TOML), e.g. configs/fit_cb_lcb.toml")],
    set_: Annotated[list[str] | None, typer.Option("--set", help="Override a config value: a.b=value")] = None,
    out: Annotated[Path | None, typer.Option(help="Run folder (default runs/<config name>)")] = None,
    json: Annotated[bool, typer.Option("--json", help="Print the report as JSON.")] = False,
) -> None:
    """Run a design config; exit code 3 when the targets cannot be met (the closest design is written)."""
    from ..run import run

    cfg, raw = load_config(config, set_ or [])
    folder = out or Path("runs") / config.stem
    report = run(cfg, raw, folder, quiet=json)
    if json:
        print_json(report)
    else:
        _summary(report, folder)
    if not report["met"]:
        raise typer.Exit(3)


def _summary(report: dict, folder: Path) -> None:
    if report["kind"] == "pareto":
        rows = [[f"{d['bf_target']:.3f}", d["measure"], d["objective"], "yes" if d["met"] else "NO",
                 "★" if d["pareto"] else ""] for d in report["designs"]]
        table(f"Pareto sweep ({report['pareto_count']} non-dominated)",
              ["Bf", report["objective"]["measure"], report["objective"]["name"], "targets met", "front"], rows)
    else:
        rows = [[k, v["target"], v["achieved"], v["error"], v["tolerance"], "yes" if v["met"] else "NO"]
                for k, v in report["targets"].items()]
        table(f"{report['kind']}: {report['iterations']} steps, converged: {report['converged']}",
              ["target", "wanted", "achieved", "error", "tolerance", "met"], rows)
        if "objective" in report:
            o = report["objective"]
            console.print(f"{o['name']}: {o['value']:.6g} (parent {o['parent']:.6g}, "
                          f"{100 * (o['value'] / o['parent'] - 1):+.2f} %)")
        if "message" in report:
            console.print(f"[red]{report['message']}[/red]")
    console.print(f"results in {folder}/ (report.json, hull.stl, offsets.csv, plots)")
