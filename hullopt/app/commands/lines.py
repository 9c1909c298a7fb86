"""``hullopt lines``: the lines plan (body, half-breadth and sheer plans) and, optionally, the hydrostatic
curves and the offset table."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import equinox as eqx
import numpy as np
import typer

from ...errors import HullError
from ...study import load_hull
from .._app import app
from ..output import say
from .hydro import HULL_HELP
from .stability import PLOT_FORMATS, _check_out


@app.command()
def lines(
    hull: Annotated[str, typer.Argument(help=HULL_HELP)],
    out: Annotated[list[Path], typer.Option(help="Lines plan: .png, .svg, .pdf or .dxf (repeat for several).")],
    waterlines: Annotated[int, typer.Option(help="Number of waterlines.")] = 8,
    buttocks: Annotated[int, typer.Option(help="Number of buttocks.")] = 4,
    curves: Annotated[Path | None, typer.Option(help="Also save the hydrostatic curves (.png, .svg, .pdf).")] = None,
    offsets: Annotated[Path | None, typer.Option(help="Also write the offset table (.csv).")] = None,
    layout: Annotated[str, typer.Option(help="Offset table layout: 'wide' (x × z) or 'stations' (seed 003).")] = "stations",
) -> None:
    """Lines plan (body, half-breadth and sheer plans) and, optionally, hydrostatic curves and offsets."""
    from ...drawing import (
        LINES_FORMATS,
        lines_plan,
        plot_hydrostatic_curves,
        save_lines,
        write_offsets_stations,
        write_offsets_wide,
    )

    for p in out:
        _check_out(p, tuple(f".{f}" for f in LINES_FORMATS), "--out")
    if curves is not None:
        _check_out(curves, PLOT_FORMATS, "--curves")
    if offsets is not None:
        _check_out(offsets, (".csv",), "--offsets")
    if layout not in ("wide", "stations"):
        raise HullError(f"--layout {layout!r}: expected 'wide' or 'stations'")
    for name, v in (("--waterlines", waterlines), ("--buttocks", buttocks)):
        if not 1 <= v <= 100:
            raise HullError(f"{name} {v}: expected 1…100")
    h = load_hull(hull)
    plan = lines_plan(h.sections, h.name, n_waterlines=waterlines, n_buttocks=buttocks, draft=h.design_draft)
    for p in out:
        save_lines(plan, p)
        say(f"wrote {p}")
    if curves is not None:
        lo = max(0.0, float(h.sections.keel))
        drafts = np.linspace(lo, float(h.sections.depth), 22)[1:-1]  # 20 drafts, the deck left out
        for t in drafts:
            h.check_draft(float(t), "draft")
        from ...hydro import hydrostatic_table

        plot_hydrostatic_curves(eqx.filter_jit(hydrostatic_table)(h.sections, drafts), curves, h.name,
                                depth=float(h.sections.depth), design_draft=h.design_draft)
        say(f"wrote {curves}")
    if offsets is not None:
        (write_offsets_wide if layout == "wide" else write_offsets_stations)(h.sections, offsets, name=h.name)
        say(f"wrote {offsets} ({layout} layout)")
