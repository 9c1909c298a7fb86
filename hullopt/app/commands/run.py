"""``hullopt run CONFIG``: a config-driven design run (fit, constrained minimum, Pareto sweep)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from ...errors import HullError
from ...optimise import TARGETS
from ...report import displayed, fmt, label, quantity, unit_scale
from ...study import load_config
from .._app import Strict, app
from ..output import print_json, say, styled, table, warn


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
    strict: Strict = False,
) -> None:
    """Run a design config; exit code 3 when the targets cannot be met (the closest design is written)."""
    from ...study import parse_shard
    from ..run import run

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
        summary(report, folder)
    if not report["met"]:
        raise typer.Exit(3)


# the particulars the summary of a run compares, parent → design (with the targets' own keys)
SUMMARY_KEYS = ("displacement", "volume", "wetted_surface", "cb", "cp", "cm", "cwp", "lcb_pct", "lcf_pct", "kb",
                "kmt", "awp", "lwl", "bwl")


def _signed(v: float, sig: int = 3, ref: float | None = None) -> str:
    text = fmt(v, sig, ref)
    return text if text.startswith("-") or float(text.replace("−", "-")) == 0 else f"+{text}"


def summary(report: dict, folder: Path) -> None:
    """What a run did, as a naval architect reads it: the targets with their units, the particulars and the
    objective parent → design with the change, and the report's warnings."""
    if report.get("partial"):
        say(f"shard {report['shard']}: chunks {', '.join(map(str, report['chunks_done']))} of "
            f"{report['chunks_total']} done in {folder}/chunks; when every shard has run, combine the "
            "folders with: hullopt merge DIR… --out OUT")
        return
    if report["kind"] == "pareto":
        o = report["objective"]
        ma, oa = (o.get("about") or {}).get("measure"), (o.get("about") or {}).get("name")
        rows = [[f"{d['bf_target']:.4g}", displayed(o["measure"], d["measure"])[0],
                 displayed(o["name"], d["objective"])[0], "yes" if d["met"] else "NO", "★" if d["pareto"] else ""]
                for d in report["designs"]]
        table(f"Pareto sweep: {len(rows)} designs, {report['pareto_count']} non-dominated (★); "
              f"{label(o['measure'], unit=False, about=ma)} against {label(o['name'], unit=False, about=oa)}",
              ["Bf target", label(o["measure"], short=True, about=ma), label(o["name"], short=True, about=oa),
               "targets met", "front"], rows)
        missed = sum(not d["met"] for d in report["designs"])
        if missed:
            warn(f"{missed} of {len(rows)} designs miss their targets (exit code 3); they are left off the front")
    else:
        say(f"{report['kind']}: {report['iterations']} steps, converged: {'yes' if report['converged'] else 'no'}, "
            f"targets met: {'yes' if report['met'] else 'NO'}", style="bold")
        _targets(report["targets"])
        _changes(report)
    for w in _warnings(report):
        warn(w)
    hulls = "pareto.png, designs/<k>/ (hull.stl, offsets.csv, body plan, sectional-area curve)" \
        if report["kind"] == "pareto" else "hull.stl, offsets.csv, plots"
    say(f"results in {folder}/: report.html (open it in a browser), report.json, {hulls}")


def _targets(targets: dict) -> None:
    """The targets table: wanted and achieved in the particular's unit; the error and its tolerance as the
    solvers measure them (relative ones in %, the others in the particular's unit)."""
    rows = []
    for k, v in targets.items():
        (want, unit), (got, _) = displayed(k, v["target"]), displayed(k, v["achieved"])
        relative = TARGETS.get(k, (False,))[0]
        scale, eunit = (100.0, "%") if relative else (1.0, unit)
        ref = max(abs(want), abs(got), unit_scale(unit))
        tol = v["tolerance"] * scale
        rows.append([label(k), fmt(want, 5, ref), fmt(got, 5, ref),
                     quantity(v["error"] * scale, eunit, 2, ref=tol), quantity(tol, eunit, 2),
                     "yes" if v["met"] else styled("NO", "bold red")])
    table("Targets", ["target", "wanted", "achieved", "error", "tolerance", "met"], rows)


def _changes(report: dict) -> None:
    """Particulars (and the objective) parent → design: both values, the change and the relative change."""
    keys = [k for k in (*SUMMARY_KEYS, *report["targets"]) if k in report.get("parent", {})]
    rows = []
    for k in dict.fromkeys(keys):
        (a, _), (b, unit) = displayed(k, report["parent"][k]), displayed(k, report["achieved"][k])
        ref = max(abs(a), abs(b), unit_scale(unit))
        rel = "" if unit == "% Lpp" or abs(a) < 1e-12 else _signed(100 * (b / a - 1), 3, ref=1)
        rows.append([label(k), fmt(a, 5, ref), fmt(b, 5, ref), _signed(b - a, 5, ref), rel])
    if "objective" in report:
        o = report["objective"]
        (a, _), (b, unit) = displayed(o["name"], o["parent"]), displayed(o["name"], o["value"])
        ref = max(abs(a), abs(b))
        rel = _signed(100 * (b / a - 1), 3, ref=1) if abs(a) > 1e-12 else ""
        about = (o.get("about") or {}).get("name")
        rows.append([styled(f"objective: {label(o['name'], about=about)}", "bold"), fmt(a, 5, ref), fmt(b, 5, ref),
                     _signed(b - a, 5, ref), rel])
    table("Parent → design", ["", "parent", "design", "change", "change [%]"], rows)


def _warnings(report: dict) -> list[str]:
    """The report's warnings: its ``warnings`` list, its ``message`` (targets not met), and a solver that
    stopped short of converging."""
    out = [str(w) for w in report.get("warnings", [])]
    if report.get("message"):
        out.append(report["message"])
    if report.get("met") and not report.get("converged", True):
        out.append("the solver stopped before it converged (the targets are met)")
    return out
