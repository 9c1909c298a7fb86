"""``hullopt resistance``: calm-water resistance over speeds by one convention, R_T = (1 + k1)·R_F + R_APP +
R_W + R_A, with the wave resistance R_W by Holtrop–Mennen 1982, Michell's thin-ship integral and the panel method
side by side, the effective power, and a warning where the methods disagree."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import jax
import jax.numpy as jnp
import numpy as np
import typer

from ...constants import KNOT
from ...errors import HullError
from ...resistance import (
    DISAGREE,
    METHODS,
    calm_water,
    dawson_wave_resistance,
    holtrop_hull,
    holtrop_mennen,
    outside_validity,
    transom_caveat,
    wave_pattern,
)
from ...study import cached_call, load_hull
from .._app import Strict, app
from ..output import parse_range, print_json, table, warn, wrote
from .hydro import HULL_HELP

FREE_STEPS = 2  # Dawson's sinkage-and-trim iterations for --free: C_W within 0.3 % of 4 on the Wigley at Fn 0.45
NAMES = {"holtrop": "H-M", "michell": "Michell", "panel": "panel", "dawson": "Dawson"}

# JSON key → (table label, unit, display scale); forces in N and powers in W in the JSON
COLUMNS = {
    "speed_kn": ("speed", "kn", 1.0),
    "fn": ("Fn", "", 1.0),
    "r_f": ("R_F ITTC-57", "kN", 1e-3),
    "form_factor": ("1+k1", "", 1.0),
    "r_a": ("R_A", "kN", 1e-3),
}
PER_METHOD = {"r_wave": ("R_W", "kN", 1e-3), "r_total": ("R_T", "kN", 1e-3), "p_e": ("P_E", "kW", 1e-3)}


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


def parse_methods(text: str) -> tuple[str, ...]:
    """``all`` or a comma list of :data:`~hullopt.resistance.METHODS` → the methods, in that order."""
    names = METHODS if text.strip() == "all" else tuple(m.strip() for m in text.split(",") if m.strip())
    bad = [m for m in names if m not in METHODS]
    if bad or not names:
        raise HullError(f"--method {text!r}: expected 'all' or a comma list of {', '.join(METHODS)}")
    return names


def _evaluate(sections, draft, speeds, methods, n_levels, pattern=False, attitude=0):
    """The calm-water parts by each method, the hull's particulars and Holtrop–Mennen's own parts, and with
    ``pattern`` Dawson's wave pattern at the first speed (None otherwise; its solve is the calm-water one's,
    merged by XLA); ``attitude``: Dawson's sinkage-and-trim iterations. All in one kept program: the
    particulars evaluated op by op took ~270 small compiles (11 s) of a cold call, and tracing the panel
    methods ~2.7 s of every warm one."""
    out = {m: calm_water(sections, draft, speeds, m, n_levels=n_levels, lambda_panels=256, attitude=attitude)
           for m in methods}
    waves = dawson_wave_resistance(sections, draft, speeds[:1], attitude=attitude) if pattern else None
    particulars = holtrop_hull(sections, draft)
    return out, particulars, holtrop_mennen(particulars, speeds), waves


def above_the_sides(sections, draft: float, records: list[dict]) -> list[str]:
    """Warnings where Dawson's free hull, sunk and trimmed (``sinkage_dawson`` [m, down] at the centre of
    flotation, ``trim_dawson`` [rad, bow up]), has the waterline above a section's top: the hull has no sides
    there (offsets that stop at the DWL), so the flow sees an open hull."""
    from ...hydro import hydrostatics

    x, y, z = (np.asarray(a) for a in (sections.x, sections.yz[..., 0], sections.yz[..., 1]))
    real = np.any(y > 0.0, axis=-1)  # stations with a surface (not an end's closing row)
    xf = float(hydrostatics(sections, draft).lcf)
    msgs = []
    for r in records:
        top = z.max(axis=-1) - r["sinkage_dawson"] + (x - xf) * r["trim_dawson"]
        gap = np.where(real, draft - top, -np.inf)
        if gap.max() > 1e-6 * max(1.0, draft):
            i, deg = int(np.argmax(gap)), float(np.degrees(r["trim_dawson"]))
            msgs.append(f"dawson --free at {r['speed_kn']:g} kn: sunk {r['sinkage_dawson']:.3g} m and trimmed "
                        f"{abs(deg):.3g}° bow {'up' if deg >= 0 else 'down'}, the waterline is {gap[i]:.3g} m "
                        f"above the hull's top at x = {x[i]:.4g} m: it has no sides there (offsets that stop at the "
                        "DWL), so its R_W, sinkage and trim are not the ship's; give the sections above the waterline")
    return msgs


def validity_warnings(records: list[dict], methods, invalid: list[dict[str, str]]) -> list[str]:
    """One warning per method of ``methods`` outside its validity at some speed, with why: once for a reason
    that holds at every speed (Michell's on a full hull), else with each speed and its own Froude number
    (Holtrop–Mennen above Fn 0.45, Dawson's method below its grid's least Fn); ``invalid``: each record's
    :func:`~hullopt.resistance.outside_validity` at its own Froude number."""
    msgs = []
    for m in methods:
        at = [(r["speed_kn"], bad[m]) for r, bad in zip(records, invalid) if m in bad]
        if not at:
            continue
        reasons = dict.fromkeys(why for _, why in at)
        if len(reasons) == 1 and len(at) == len(records):
            msgs.append(f"{m} is outside its validity ({next(iter(reasons))})")
        else:
            msgs.append(f"{m} is outside its validity at " + "; ".join(f"{kn:g} kn ({why})" for kn, why in at))
    return msgs


def disagreements(records: list[dict], methods, invalid: list[dict[str, str]]) -> list[str]:
    """Warnings where two methods' R_W differ by more than :data:`DISAGREE` at a speed whose wave part matters
    (≥ 5 % of R_T by either), naming the method outside its validity at that speed (``invalid``: each record's
    :func:`~hullopt.resistance.outside_validity`; why is said once, by :func:`validity_warnings`)."""
    msgs = []
    for i, a in enumerate(methods):
        for b in methods[i + 1:]:
            worst = None
            for k, r in enumerate(records):
                wa, wb = r[f"r_wave_{a}"], r[f"r_wave_{b}"]
                big = max(wa / r[f"r_total_{a}"], wb / r[f"r_total_{b}"]) >= 0.05
                ratio = max(wa, wb) / max(min(wa, wb), 1e-300)
                if big and ratio > DISAGREE and (worst is None or ratio > worst[0]):
                    worst = (ratio, k, a if wa > wb else b)
            if worst:
                ratio, k, high = worst
                out = [m for m in (a, b) if m in invalid[k]]
                why = (f": {' and '.join(out)} {'is' if len(out) == 1 else 'are'} outside "
                       f"{'its' if len(out) == 1 else 'their'} validity there" if out else "")
                msgs.append(f"R_W by {high} is {ratio:.1f}× the other's ({a} vs {b}) at {records[k]['speed_kn']:g} kn "
                            f"(Fn {records[k]['fn']:.2f}){why}")
    return msgs


@app.command()
def resistance(
    hull: Annotated[str, typer.Argument(help=HULL_HELP)],
    speed: Annotated[str, typer.Option(help="Speeds [kn]: a list 12,14,16 or START:STOP:COUNT.")],
    draft: Annotated[float | None, typer.Option(help="Draft above the baseline [m] (default: the hull's).")] = None,
    method: Annotated[str, typer.Option(help="Wave resistance by: all, or a comma list of holtrop, michell, "
                                             "panel, dawson.")] = "all",
    levels: Annotated[int, typer.Option(help="Heights from the keel to the draft sampled by Michell's integral.")] = 33,
    plot: Annotated[Path | None, typer.Option(help="Draw R_T and P_E against speed and C_W against Fn, each "
                                                   "method's curve (.png, .svg, .pdf).")] = None,
    pattern: Annotated[Path | None, typer.Option(help="Draw the wave pattern at the first speed: Dawson's when "
                                                      "--method has dawson (all does), else the panel method's "
                                                      "Kelvin waves (.png, .svg, .pdf).")] = None,
    free: Annotated[bool, typer.Option("--free", help="Dawson's method with the hull free to sink and trim (two "
                                                       "iterations: 3× its time); default: fixed at the draft.")] = False,
    json: Annotated[bool, typer.Option("--json", help="Print JSON: a list with one record per speed (SI: N, W, m/s).")] = False,
    strict: Strict = False,
) -> None:
    """Calm-water resistance over speeds: R_T = (1 + k1)·R_F + R_APP + R_W + R_A — ITTC-1957 friction with
    Holtrop's form factor 1 + k1, appendages and correlation allowance R_A — with the wave resistance R_W by
    Holtrop & Mennen 1982 (R_W + R_B + R_TR), Michell's thin-ship integral, the Rankine-source panel method
    (with its double-body sinkage and trim) and Dawson's method (free-surface panels), and effective power P_E = R_T·U. Warns where two methods' R_W differ
    by more than 1.5× and names the one outside its validity.
    """
    knots = parse_speeds(speed)
    methods = parse_methods(method)
    if levels < 2:
        raise HullError(f"--levels {levels}: expected at least 2 heights")
    for opt, p in (("--plot", plot), ("--pattern", pattern)):
        if p is not None and p.suffix.lower() not in (".png", ".svg", ".pdf"):
            raise HullError(f"{opt} {str(p)!r}: expected a .png, .svg or .pdf file")
    h = load_hull(hull)
    if draft is None:
        if h.design_draft is None:
            raise HullError("give --draft (this hull has no design draft)")
        draft = h.design_draft
    t = h.check_draft(draft)
    u = knots * KNOT
    static = (methods, levels, pattern is not None and "dawson" in methods, FREE_STEPS if free else 0)
    args = (h.sections, jnp.asarray(t, dtype=float), jnp.asarray(u, dtype=float))
    out, particulars, hm, dawson = jax.device_get(cached_call("resistance", _evaluate, args, static, key={"v": 1}))
    s = float(particulars.S)
    records = []
    for i, kn in enumerate(knots):
        rec = {"speed_kn": float(kn), "speed": float(u[i]), "draft": t, "fn": float(np.asarray(hm.fn)[i]),
               "wetted_surface": s, "r_f": float(hm.friction[i]), "cf": float(hm.cf[i]),
               "form_factor": float(hm.form_factor), "r_app": float(np.broadcast_to(hm.appendages, u.shape)[i]),
               "r_a": float(np.broadcast_to(hm.correlation, u.shape)[i]), "ca": float(hm.ca)}
        for m, cw in out.items():
            rw, rt = float(cw.r_wave[i]), float(cw.total[i])
            rec.update({f"r_wave_{m}": rw, f"r_total_{m}": rt, f"p_e_{m}": rt * u[i],
                        f"c_w_{m}": rw / (0.5 * 1025.0 * u[i] ** 2 * s)})
        if "holtrop" in methods:
            rec.update(r_w=float(hm.wave[i]), r_b=float(hm.bulb[i]), r_tr=float(hm.transom[i]))
        for m in ("panel", "dawson"):
            if m in out:
                rec.update({f"sinkage_{m}": float(out[m].sinkage[i]), f"trim_{m}": float(out[m].trim[i])})
        if "dawson" in out:
            rec["dawson_free"] = free  # its hull sunk and trimmed (--free), else fixed at the draft
        records.append(rec)
    invalid = [outside_validity(particulars, r["fn"], r["fn"]) for r in records]  # each at its own speed
    for msg in validity_warnings(records, methods, invalid):
        warn(msg)
    if "dawson" in methods and (caveat := transom_caveat(particulars)):
        warn(caveat)
    for msg in disagreements(records, methods, invalid) + (above_the_sides(h.sections, t, records)
                                                           if free and "dawson" in methods else []):
        warn(msg)
    if plot is not None:
        from ...report import plot_resistance

        plot_resistance(records, methods, plot, title=f"{h.name} — T {t:g} m")
        wrote(plot, json=json)
    if pattern is not None:
        from ...report import plot_wave_pattern

        lpp, wake = float(h.sections.lpp), None
        if dawson is not None:  # on its own free-surface grid; the near field included
            c = np.asarray(dawson.centres)
            x, y, zeta, by = c[..., 0], c[..., 1], np.asarray(dawson.zeta[0]), "Dawson's method"
            if particulars.A_T > 0.0:  # the wake grid behind the transom, joined to the main grid's first row
                nw = dawson.wake_centres.shape[0]
                w = np.concatenate([np.asarray(dawson.wake_centres), c[-nw:, :1]], axis=1)
                wz = np.concatenate([np.asarray(dawson.wake_zeta[0]), zeta[-nw:, :1]], axis=1)
                wake = (w[..., 0], w[..., 1], wz)
        else:  # the far field of the panel method's sources
            x, y = np.linspace(-1.5 * lpp, 1.15 * lpp, 240), np.linspace(0.0, 0.75 * lpp, 80)
            zeta, by = np.asarray(wave_pattern(h.sections, t, float(u[0]), x, y)), "Kelvin waves by the panel method"
        plot_wave_pattern(x, y, zeta, lpp, pattern, title=f"{h.name} — {by}, {knots[0]:g} kn "
                          f"(Fn {records[0]['fn']:.3f}), T {t:g} m", wake=wake)
        wrote(pattern, json=json)
    if json:
        print_json(records)
        return
    cols = [f"{label} [{unit}]" if unit else label for label, unit, _ in COLUMNS.values()]
    keys = list(COLUMNS)
    scales = [sc for _, _, sc in COLUMNS.values()]
    for key, (label, unit, sc) in PER_METHOD.items():
        for m in methods:
            cols.append(f"{label} {NAMES[m]} [{unit}]")
            keys.append(f"{key}_{m}")
            scales.append(sc)
    rows = [[float(r[k]) * sc for k, sc in zip(keys, scales)] for r in records]
    table(f"Calm-water resistance — {h.name} (T {t:g} m, Lpp {float(h.sections.lpp):g} m); "
          f"R_T = (1+k1)·R_F + R_APP + R_W + R_A" + ("; Dawson free to sink and trim" if free and "dawson" in methods
                                                    else ""), cols, rows)
