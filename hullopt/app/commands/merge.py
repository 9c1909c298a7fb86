"""``hullopt merge DIR…``: combine the run folders of the shards of one sweep (``hullopt run --shard k/N``)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from .._app import app
from ..output import print_json
from .run import summary


@app.command("merge")
def merge_command(
    dirs: Annotated[list[Path], typer.Argument(help="Run folders of the shards (each with config.json, chunks/)")],
    out: Annotated[Path, typer.Option(help="Folder of the combined run (may be one of DIRS)")],
    json: Annotated[bool, typer.Option("--json", help="Print the report as JSON.")] = False,
) -> None:
    """Combine sweep shards into one run folder and report, the same as the unsplit sweep's; nothing is solved
    (an error names the chunks that no folder holds). Exit code 3 when some design misses its targets."""
    from ..run import merge

    report = merge(dirs, out, quiet=json)
    if json:
        print_json(report)
    else:
        summary(report, out)
    if not report["met"]:
        raise typer.Exit(3)
