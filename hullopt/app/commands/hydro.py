"""``hullopt hydro`` (hydrostatics at a draft, a displacement or over drafts) and ``hullopt export``.

The table is one kept program (:func:`~hullopt.study.cached_call`): a warm ``hullopt hydro`` neither
imports the hydrostatics nor traces or compiles them. A displacement's draft is solved by one compiled program
too (kept by jax's compilation cache; it traces each call)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import typer

from ...constants import RHO_SEA
from ...errors import HullError
from ...geometry import EXPORT_FORMATS
from ...report import PARTICULARS, unit_places
from ...study import cached_call, load_hull, prepare_call, sections_like
from .._app import Strict, app
from ..output import parse_range, print_json, say, table, write_hull_file, wrote

HULL_HELP = ("builtin:wigley?L=..&B=..&T=..&D=.., parent:NAME (dtc, tanker, wigley, seed003 or a parent .json), "
             "a run folder, offsets .csv, a mesh (stl, stl.gz, obj, ply…; ?scale=&lpp=&axes=&shift=&half=) "
             "or a CAD surface (igs, step; ?tol=)")

# (key, label, unit, scale for display)
ROWS = [(key, *v) for key, v in PARTICULARS.items()]


def parse_displacement(text: str) -> float:
    """Displacement in tonnes (``177700`` or ``177700t``) or kilograms (``1.777e8kg``) → kg."""
    t = text.strip().lower()
    try:
        value = float(t[:-2]) if t.endswith("kg") else 1e3 * float(t.removesuffix("t"))
    except ValueError:
        raise HullError(f"--displacement {text!r}: expected a number of tonnes, e.g. 177700 or 1.777e8kg") from None
    if not (np.isfinite(value) and value > 0):
        raise HullError(f"--displacement {text!r}: must be positive")
    return value


def resolve_drafts(hull, draft, displacement, drafts, rho) -> np.ndarray:
    chosen = [o for o, v in (("--draft", draft), ("--displacement", displacement), ("--drafts", drafts)) if v is not None]
    if len(chosen) > 1:
        raise HullError(f"give only one of --draft, --displacement, --drafts (got {', '.join(chosen)})")
    if drafts is not None:
        return np.array([hull.check_draft(t, "--drafts value") for t in parse_range(drafts, "--drafts")])
    if displacement is not None:
        from ...hydro import draft_for_volume, volume_at

        volume = parse_displacement(displacement) / rho
        # one compiled program (kept by the compilation cache), not the solve operation by operation
        full, t = eqx.filter_jit(lambda s, v: (volume_at(s, s.depth), draft_for_volume(s, v)))(hull.sections, volume)
        if volume >= float(full):
            raise HullError(f"--displacement {displacement}: more than the hull displaces at its deck "
                            f"({rho * float(full) / 1e3:,.0f} t)")
        return np.array([float(t)])
    if draft is None:
        if hull.design_draft is None:
            raise HullError("give --draft, --displacement or --drafts (this hull has no design draft)")
        draft = hull.design_draft
    return np.array([hull.check_draft(draft)])


@app.command()
def hydro(
    hull: Annotated[str, typer.Argument(help=HULL_HELP)],
    draft: Annotated[float | None, typer.Option(help="Draft above the baseline [m].")] = None,
    displacement: Annotated[str | None, typer.Option(help="Displacement [t] (or '…kg'); the draft is solved for.")] = None,
    drafts: Annotated[str | None, typer.Option(help="Hydrostatic table over drafts START:STOP:COUNT [m].")] = None,
    rho: Annotated[float, typer.Option(help="Water density [kg/m³].")] = RHO_SEA,
    json: Annotated[bool, typer.Option("--json", help="Print JSON (SI units; lcb/lcf in m from AP).")] = False,
    strict: Strict = False,
) -> None:
    """Upright hydrostatics at a draft, at a displacement, or as a table over drafts."""
    if not (np.isfinite(rho) and rho > 0):
        raise HullError(f"--rho {rho}: must be a positive density in kg/m³")
    like = sections_like(hull)
    if like is not None and displacement is None:  # a mesh: its table's program is built while it is read
        count = 1 if drafts is None else len(parse_range(drafts, "--drafts"))
        prepare_call(*_table_program(like, jax.ShapeDtypeStruct((count,), np.float64), rho), quick=True)
    h = load_hull(hull)
    ts = resolve_drafts(h, draft, displacement, drafts, rho)
    res = hydro_table(h.sections, ts, rho)
    records = [{k: v[i] for k, v in res.items()} for i in range(len(ts))]
    if json:
        print_json(records[0] if len(records) == 1 and drafts is None else records)
        return
    rows = [[f"{label} [{unit}]" if unit else label, *(float(r[key]) * s for r in records)]
            for key, label, unit, s in ROWS]
    table(f"Hydrostatics — {h.name} (Lpp {float(h.sections.lpp):g} m, ρ {rho:g} kg/m³)",
          ["quantity at draft T →", *(f"{t:.3f} m" for t in ts)], rows, by="row",
          places=[unit_places(unit) for _, _, unit, _ in ROWS])


def _table(sections, drafts, rho) -> dict:
    from ...hydro import hydrostatic_table

    return dict(vars(hydrostatic_table(sections, drafts, rho)))


def _table_program(sections, drafts, rho: float) -> tuple:
    """The arguments of :func:`~hullopt.study.cached_call` (and ``prepare_call``) for the table's program;
    ``sections`` and ``drafts`` may be their shapes. ρ is a Python float in the program (as
    hydrostatic_table declares it): one program per density."""
    return "hydrostatic_table", _table, (sections, drafts), (float(rho),), "hydro v1"


def hydro_table(sections, drafts: np.ndarray, rho: float) -> dict[str, list[float]]:
    """:func:`~hullopt.hydro.hydrostatic_table` as ``Hydrostatics.to_dict`` gives it, through a kept program
    (the hydrostatics are imported only when the program is built)."""
    res = cached_call(*_table_program(sections, jnp.asarray(drafts, dtype=float), rho), quick=True)
    # the fields in Hydrostatics' order (PARTICULARS lists them so; a kept dict comes back sorted by key)
    order = [*(k for k in PARTICULARS if k in res), *(k for k in res if k not in PARTICULARS)]
    return {k: np.asarray(res[k]).tolist() for k in order}


@app.command()
def export(
    hull: Annotated[str, typer.Argument(help=HULL_HELP)],
    out: Annotated[Path, typer.Argument(help=f"Output mesh: .{', .'.join(EXPORT_FORMATS)}")],
    strict: Strict = False,
) -> None:
    """Export the closed, watertight hull mesh (both sides, deck, transom), refined along the length and
    welded for the file; the checks printed (watertight, winding, bodies, degenerate faces, volume [m³]) are
    those of the written file read back."""
    if out.suffix.lower().lstrip(".") not in EXPORT_FORMATS:
        raise HullError(f"{out}: unknown mesh format {out.suffix!r}; expected one of .{', .'.join(EXPORT_FORMATS)}")
    h = load_hull(hull)
    written = write_hull_file(h.sections, out, h.design_draft)
    wrote(out, f"{written.summary()}; read back")
