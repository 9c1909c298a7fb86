"""``hullopt resistance``: calm-water resistance over speeds — Michell's thin-ship wave resistance from the
sections beside Holtrop & Mennen (1982), and the effective power."""

from __future__ import annotations

from typing import Annotated

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import typer

from ...constants import KNOT
from ...errors import HullError
from ...resistance import holtrop_hull, holtrop_mennen, michell_wave_resistance
from .._app import app
from ..hulls import load_hull
from ..output import parse_range, print_json, table
from .hydro import HULL_HELP, check_draft

# JSON key → (table label, unit, display scale); forces in N and powers in W in the JSON
COLUMNS = {
    "speed_kn": ("speed", "kn", 1.0),
    "fn": ("Fn", "", 1.0),
    "r_wave_michell": ("R_w Michell", "kN", 1e-3),
    "r_f": ("R_F ITTC-57", "kN", 1e-3),
    "form_factor": ("1+k1", "", 1.0),
    "r_w": ("R_W H-M", "kN", 1e-3),
    "r_b": ("R_B", "kN", 1e-3),
    "r_tr": ("R_TR", "kN", 1e-3),
    "r_a": ("R_A", "kN", 1e-3),
    "r_total_holtrop": ("R_T H-M", "kN", 1e-3),
    "r_total_michell": ("R_T Michell", "kN", 1e-3),
    "p_e_holtrop": ("P_E H-M", "kW", 1e-3),
    "p_e_michell": ("P_E Michell", "kW", 1e-3),
}


def parse_speeds(text: str) -> np.ndarray:
    """``12,14,16`` or ``START:STOP:COUNT`` [kn] → speeds in knots (positive, finite)."""
    if ":" in text:
        v = parse_range(text, "--speed")
    else:
        try:
            v = np.array([float(s) for s in text.split(",") if s.strip()])
        except ValueError:
            raise HullError(f"--speed {text!r}: expected knots as a list 12,14,16 or START:STOP:COUNT") from None
    if v.size == 0 or not np.all(np.isfinite(v) & (v > 0)):
        raise HullError(f"--speed {text!r}: every speed must be a positive number of knots")
    return v


@eqx.filter_jit
def _evaluate(sections, draft, speeds, n_levels):
    """Michell's R_w and the Holtrop–Mennen parts at ``speeds`` [m/s]; the calm-water total with Michell's
    wave part is (1 + k1)·R_F + R_APP + R_w(Michell) + R_A (Holtrop's form factor, friction and correlation)."""
    rw = michell_wave_resistance(sections, draft, speeds, n_levels=n_levels)
    hm = holtrop_mennen(holtrop_hull(sections, draft), speeds)
    calm = hm.form_factor * hm.friction + hm.appendages + rw + hm.correlation
    return rw, hm, calm


@app.command()
def resistance(
    hull: Annotated[str, typer.Argument(help=HULL_HELP)],
    speed: Annotated[str, typer.Option(help="Speeds [kn]: a list 12,14,16 or START:STOP:COUNT.")],
    draft: Annotated[float | None, typer.Option(help="Draft above the baseline [m] (default: the hull's).")] = None,
    levels: Annotated[int, typer.Option(help="Heights from the keel to the draft sampled by Michell's integral.")] = 33,
    json: Annotated[bool, typer.Option("--json", help="Print JSON: a list with one record per speed (SI: N, W, m/s).")] = False,
) -> None:
    """Calm-water resistance over speeds: Michell's thin-ship wave resistance from the sections (deep water),
    Holtrop & Mennen 1982's parts, the total with either wave part, and effective power P_E = R_T·U.

    R_T Michell = (1 + k1)·R_F + R_APP + R_w(Michell) + R_A: Holtrop's form factor, ITTC-1957 friction and
    correlation allowance with Michell's wave resistance in place of Holtrop's R_W + R_B + R_TR.
    """
    knots = parse_speeds(speed)
    if levels < 2:
        raise HullError(f"--levels {levels}: expected at least 2 heights")
    h = load_hull(hull)
    if draft is None:
        if h.design_draft is None:
            raise HullError("give --draft (this hull has no design draft)")
        draft = h.design_draft
    t = check_draft(h, draft)
    u = knots * KNOT
    rw, hm, calm = _evaluate(h.sections, t, jnp.asarray(u), levels)
    rw, calm = np.asarray(rw), np.asarray(calm)
    parts = {k: np.broadcast_to(np.asarray(getattr(hm, a)), u.shape) for k, a in (
        ("fn", "fn"), ("r_f", "friction"), ("form_factor", "form_factor"), ("r_app", "appendages"), ("r_w", "wave"),
        ("r_b", "bulb"), ("r_tr", "transom"), ("r_a", "correlation"), ("r_total_holtrop", "total"), ("cf", "cf"),
        ("ca", "ca"))}
    records = []
    for i, kn in enumerate(knots):
        rec = {"speed_kn": float(kn), "speed": float(u[i]), "draft": t, "fn": float(parts["fn"][i]),
               "r_wave_michell": float(rw[i])}
        rec.update({k: float(v[i]) for k, v in parts.items() if k != "fn"})
        rec.update(r_total_michell=float(calm[i]), p_e_holtrop=float(parts["r_total_holtrop"][i] * u[i]),
                   p_e_michell=float(calm[i] * u[i]))
        records.append(rec)
    if json:
        print_json(records)
        return
    cols = [f"{label} [{unit}]" if unit else label for label, unit, _ in COLUMNS.values()]
    rows = [[float(r[k]) * s for k, (_, _, s) in COLUMNS.items()] for r in records]
    table(f"Calm-water resistance — {h.name} (T {t:g} m, Lpp {float(h.sections.lpp):g} m)", cols, rows)
