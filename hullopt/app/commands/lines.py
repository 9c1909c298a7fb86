"""``hullopt lines``: the lines plan (sheer, half-breadth and body plans) on an A3 or A1 sheet at a standard
scale, or in DXF at full scale, and, optionally, the hydrostatic curves and the table of offsets."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace
from typing import Annotated

import numpy as np
import typer

from ...constants import RHO_SEA
from ...errors import HullError
from ...study import load_hull
from .._app import Strict, app
from ..output import check_out, wrote
from .hydro import HULL_HELP, hydro_table
from .stability import PLOT_FORMATS


@app.command()
def lines(
    hull: Annotated[str, typer.Argument(help=HULL_HELP)],
    out: Annotated[list[Path], typer.Option(help="Lines plan: .png, .svg, .pdf (on the sheet) or .dxf (full scale, m); "
                                                 "repeat for several.")],
    draft: Annotated[float | None, typer.Option(help="Design draft T [m above the baseline]: the DWL; default: the "
                                                     "hull's design draft.")] = None,
    stations: Annotated[int, typer.Option(help="Station intervals over Lpp: stations 0 (AP) … N (FP).")] = 20,
    sheet: Annotated[str, typer.Option(help="Sheet: A3 (420 × 297 mm) or A1 (841 × 594 mm), at true size.")] = "A3",
    spacing: Annotated[float | None, typer.Option("--waterline-spacing",
                                                  help="Waterline spacing [m]; default: a round one from the draft "
                                                       "(5 to 10 waterlines below the DWL).")] = None,
    buttocks: Annotated[int, typer.Option(help="At most this many buttocks, at a round spacing.")] = 4,
    diagonals: Annotated[int, typer.Option(help="Diagonals across the bilge.")] = 3,
    dpi: Annotated[int, typer.Option(help="Resolution of a PNG [dots per inch].")] = 200,
    curves: Annotated[Path | None, typer.Option(help="Also save the hydrostatic curves (.png, .svg, .pdf).")] = None,
    offsets: Annotated[Path | None, typer.Option(help="Also write the table of offsets (.csv): the plan's stations "
                                                      "× its waterlines and the DWL.")] = None,
    layout: Annotated[str, typer.Option(help="Offset table layout: 'stations' (a yard's table, read back by "
                                             "hullopt) or 'wide' (x × z, machine data).")] = "stations",
    strict: Strict = False,
) -> None:
    """Lines plan (sheer, half-breadth and body plans, title block) and, optionally, hydrostatic curves and offsets."""
    from ...drawing import (
        LINES_FORMATS,
        SHEETS,
        lines_plan,
        offset_table,
        plot_hydrostatic_curves,
        save_lines,
        write_offsets_stations,
        write_offsets_wide,
    )

    for p in out:
        check_out(p, tuple(f".{f}" for f in LINES_FORMATS), "--out")
    if curves is not None:
        check_out(curves, PLOT_FORMATS, "--curves")
    if offsets is not None:
        check_out(offsets, (".csv",), "--offsets")
    if layout not in ("wide", "stations"):
        raise HullError(f"--layout {layout!r}: expected 'wide' or 'stations'")
    sheet = sheet.upper()
    if sheet not in SHEETS:
        raise HullError(f"--sheet {sheet!r}: expected one of {', '.join(SHEETS)}")
    for name, v, lo, hi in (("--stations", stations, 2, 200), ("--buttocks", buttocks, 0, 20),
                            ("--diagonals", diagonals, 0, 10), ("--dpi", dpi, 50, 1200)):
        if not lo <= v <= hi:
            raise HullError(f"{name} {v}: expected {lo}…{hi}")
    if spacing is not None and not (np.isfinite(spacing) and spacing > 0):
        raise HullError(f"--waterline-spacing {spacing:g}: expected a positive spacing in m")
    h = load_hull(hull)
    if draft is None:
        if h.design_draft is None:
            raise HullError(f"{h.name} has no design draft: give the DWL with --draft T [m above the baseline]")
        draft = h.design_draft
    draft = h.check_draft(float(draft))
    drafts = [draft]
    if curves is not None:
        lo = max(0.0, float(h.sections.keel))
        drafts += np.linspace(lo, float(h.sections.depth), 22)[1:-1].tolist()  # 20 drafts, the deck left out
        for t in drafts[1:]:
            h.check_draft(t, "draft")
    # one kept program: the title block's particulars at the DWL, then the curves' drafts
    particulars = hydro_table(h.sections, np.array(drafts), RHO_SEA)
    plan = lines_plan(h.sections, h.name, draft=draft, stations=stations, spacing=spacing, n_buttocks=buttocks,
                      n_diagonals=diagonals, displacement=particulars["displacement"][0] / 1e3,
                      cb=particulars["cb"][0])
    for p in out:
        save_lines(plan, p, sheet, dpi)
        wrote(p)
    if curves is not None:
        table = SimpleNamespace(**{k: np.asarray(v[1:]) for k, v in particulars.items()})  # a HydrostaticTable
        plot_hydrostatic_curves(table, curves, h.name, depth=float(h.sections.depth), design_draft=draft)
        wrote(curves)
    if offsets is not None:
        if layout == "wide":
            x, z, _, _ = offset_table(h.sections, draft, stations, spacing)
            write_offsets_wide(h.sections, offsets, x=x, z=z, name=h.name)
        else:
            write_offsets_stations(h.sections, offsets, draft, stations, spacing, name=h.name)
        wrote(offsets, f"{layout} layout")
