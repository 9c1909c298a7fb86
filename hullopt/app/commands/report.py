"""``hullopt report RUN_DIR``: (re)write a run folder's ``report.html``."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from .._app import app
from ..output import busy, say


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
    say(f"wrote {path} ({path.stat().st_size / 1e6:.1f} MB; open it in a browser)")
