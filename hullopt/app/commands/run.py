"""``hullopt run CONFIG``: a config-driven design run (fit, constrained minimum, Pareto sweep)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ...errors import HullError
from .._app import app
from ..config import load_config
from ..output import console, print_json, table


@app.command("run")
def run_command(
    config: Annotated[Path, typer.Argument(help="Run config (TOML), e.g. configs/fit_cb_lcb.toml")],
    set_: Annotated[list[str] | None, typer.Option("--set", help="Override a config value: a.b=value")] = None,
    out: Annotated[Path | None, typer.Option(help="Run folder (default runs/<config name>)")] = None,
    json: Annotated[bool, typer.Option("--json", help="Print the report as JSON.")] = False,
    shard: Annotated[str | None, typer.Option(help="Sweeps: solve only chunks k-1, k-1+N, … (k/N, e.g. 2/8); "
                                              "combine the shards' folders with hullopt merge")] = None,
    executor: Annotated[str, typer.Option(help="Sweeps: where chunks run: local (this machine's devices) or "
                                          "dask")] = "local",
    address: Annotated[str | None, typer.Option(help="Dask scheduler address, e.g. tcp://host:8786 (default: "
                                                "a local cluster)")] = None,
) -> None:
    """Run a design config; exit code 3 when the targets cannot be met (the closest design is written)."""
    from ..run import run
    from ..sweep import parse_shard

    cfg, raw = load_config(config, set_ or [])
    k_n = parse_shard(shard)
    if executor not in ("local", "dask"):
        raise HullError(f"--executor {executor!r}: expected local or dask")
    if cfg.kind != "pareto" and (shard is not None or executor != "local" or address):
        raise HullError(f"--shard/--executor/--address apply to sweeps; {config} is a {cfg.kind!r} run")
    if address and executor != "dask":
        raise HullError("--address needs --executor dask")
    folder = out or Path("runs") / config.stem
    report = run(cfg, raw, folder, quiet=json, shard=k_n, executor=executor, address=address)
    if json:
        print_json(report)
    else:
        _summary(report, folder)
    if not report["met"]:
        raise typer.Exit(3)


def _summary(report: dict, folder: Path) -> None:
    if report.get("partial"):
        console.print(f"shard {report['shard']}: chunks {', '.join(map(str, report['chunks_done']))} of "
                      f"{report['chunks_total']} done in {folder}/chunks; when every shard has run, combine the "
                      "folders with: hullopt merge DIR… --out OUT")
        return
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
