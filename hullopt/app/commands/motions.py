"""``hullopt motions``: heave and pitch RAOs by strip theory and the added resistance σ_aw in regular waves."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import jax
import jax.numpy as jnp
import numpy as np
import typer

from ...constants import KNOT, RHO_SEA, G
from ...errors import HullError
from ...study import cached_call, load_hull
from ...waves import (
    motion_validity_warning,
    nmri_added_resistance,
    omega_from_wavelength,
)
from ...waves import motions as strip_motions
from .._app import Strict, app
from ..output import parse_range, print_json, table, warn, wrote
from .hydro import HULL_HELP


def _lambdas(text: str) -> np.ndarray:
    """``'0.5,1,1.5'`` or ``'START:STOP:COUNT'`` → λ/L values (positive)."""
    if ":" in text:
        vals = parse_range(text, "--lambdas")
    else:
        try:
            vals = np.array([float(v) for v in text.split(",")])
        except ValueError:
            raise HullError(f"--lambdas {text!r}: expected comma-separated numbers or START:STOP:COUNT") from None
    if vals.size == 0 or not np.all(np.isfinite(vals)) or np.any(vals <= 0):
        raise HullError(f"--lambdas {text!r}: wave lengths over Lpp must be positive numbers")
    return vals


def _motions_program(sections, draft, speed, omega, heading, kg, kyy):
    """The strip-theory motions and the NMRI reflection part at ``omega (w,)`` [rad/s]: dicts of arrays (a kept
    program's outputs, read back without the waves' classes)."""
    m = strip_motions(sections, draft, speed, omega, heading, kg=kg, kyy=kyy)
    nm = nmri_added_resistance(sections, draft, speed, omega, heading)
    return ({k: getattr(m, k) for k in ("r_awm", "omega_e", "heave_rao", "pitch_rao")},
            {k: getattr(nm, k) for k in ("beam", "r_awr", "fn", "bf")})


@app.command()
def motions(
    hull: Annotated[str, typer.Argument(help=HULL_HELP)],
    speed: Annotated[float, typer.Option(help="Ship speed [kn].")],
    draft: Annotated[float | None, typer.Option(help="Draft above the baseline [m] (default: the hull's).")] = None,
    heading: Annotated[float, typer.Option(help="Wave heading [deg]: 0 head seas, 90 beam seas.")] = 0.0,
    kg: Annotated[float | None, typer.Option(help="KG, centre of gravity above the baseline [m] (default: the draft).")] = None,
    kyy: Annotated[float, typer.Option(help="Pitch radius of gyration as a fraction of Lpp.")] = 0.25,
    lambdas: Annotated[str, typer.Option(help="Wave lengths λ/L: a list 0.5,1,1.5 or START:STOP:COUNT.")] = "0.3:2.0:18",
    json: Annotated[bool, typer.Option("--json", help="Print JSON (SI units; arrays over λ/L).")] = False,
    plot: Annotated[Path | None, typer.Option(help="Write a plot of the RAOs and σ_aw against λ/L (.png, .pdf, .svg).")] = None,
    strict: Strict = False,
) -> None:
    """Heave and pitch RAOs (strip theory, Salvesen–Tuck–Faltinsen with Frank close-fit sections) and the added
    resistance σ_aw = R_AW/(ρgζ²B²/L) = motion part (Gerritsma–Beukelman) + reflection part (NMRI Bf)."""
    if not (np.isfinite(speed) and speed >= 0):
        raise HullError(f"--speed {speed:g}: expected a number ≥ 0 [kn]")
    if not (np.isfinite(heading) and -360.0 <= heading <= 360.0):
        raise HullError(f"--heading {heading:g}: expected degrees within ±360")
    if not (np.isfinite(kyy) and 0.0 < kyy < 1.0):
        raise HullError(f"--kyy {kyy:g}: expected a fraction of Lpp between 0 and 1 (typically 0.22–0.28)")
    if kg is not None and not (np.isfinite(kg) and kg > 0):
        raise HullError(f"--kg {kg:g}: expected a positive height above the baseline [m]")
    ratios = _lambdas(lambdas)
    h = load_hull(hull)
    if draft is None:
        if h.design_draft is None:
            raise HullError("give --draft (this hull has no design draft)")
        draft = h.design_draft
    t = h.check_draft(draft)
    s = h.sections
    lpp = float(s.lpp)
    u = speed * KNOT
    alpha = np.radians(heading)
    omega = np.asarray(omega_from_wavelength(ratios * lpp))
    args = tuple(None if v is None else jnp.asarray(v, dtype=float) for v in (t, u, omega, alpha, kg, kyy))
    m, nm = jax.device_get(cached_call("motions", _motions_program, (s, *args), (), key={"kg": kg is not None}))
    beam = float(nm["beam"])
    scale = RHO_SEA * G * beam**2 / lpp
    sig_m = np.asarray(m["r_awm"]) / scale
    sig_r = np.ravel(np.asarray(nm["r_awr"])) / scale
    out = {
        "hull": h.name, "draft": t, "speed": u, "speed_kn": speed, "fn": float(nm["fn"]), "heading_deg": heading,
        "lpp": lpp, "beam": beam, "kg": t if kg is None else float(kg), "kyy": kyy, "bf": float(nm["bf"]),
        "lambda_over_l": ratios, "omega": omega, "omega_e": np.asarray(m["omega_e"]),
        "heave": np.asarray(m["heave_rao"]), "pitch": np.asarray(m["pitch_rao"]),
        "sigma_aw": sig_m + sig_r, "sigma_aw_motion": sig_m, "sigma_aw_reflection": sig_r,
    }
    if plot is not None:
        _plot(plot, out)
        wrote(plot, json=json)
    note = motion_validity_warning(out["fn"], lpp / beam)
    if note is not None:
        warn(note)
    if json:
        print_json(out)
        return
    table(f"Motions in regular waves — {out['hull']} (T {t:g} m, {speed:g} kn, Fn {out['fn']:.3f}, "
          f"heading {heading:g}°, kyy {kyy:g} Lpp)",
          ["λ/L", "ω [rad/s]", "ω_e [rad/s]", "heave |z|/ζ", "pitch |θ|/kζ", "σ_aw", "σ motion", "σ reflection"],
          [[f"{r:.3f}", w, we, hv, p, a, am, ar] for r, w, we, hv, p, a, am, ar in zip(
              ratios, omega, out["omega_e"], out["heave"], out["pitch"], out["sigma_aw"], sig_m, sig_r)])


def _plot(path: Path, out: dict) -> None:
    if not path.parent.is_dir():
        raise HullError(f"--plot {path}: the folder {str(path.parent)!r} does not exist")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = out["lambda_over_l"]
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 7), sharex=True)
    ax1.plot(x, out["heave"], "-o", ms=3, label="heave |z|/ζ")
    ax1.plot(x, out["pitch"], "-s", ms=3, label="pitch |θ|/(kζ)")
    ax1.set_ylabel("RAO")
    ax1.grid(alpha=0.3)
    ax1.legend()
    ax1.set_title(f"{out['hull']}: {out['speed_kn']:g} kn (Fn {out['fn']:.3f}), T {out['draft']:g} m, "
                  f"heading {out['heading_deg']:g}°, kyy {out['kyy']:g} Lpp", fontsize=10)
    ax2.plot(x, out["sigma_aw"], "k-o", ms=3, label="total")
    ax2.plot(x, out["sigma_aw_motion"], "--", label="motion part (strip theory, GB)")
    ax2.plot(x, out["sigma_aw_reflection"], ":", label="reflection part (NMRI Bf)")
    ax2.set_xlabel("λ / L")
    ax2.set_ylabel("σ_aw = R_AW / (ρgζ²B²/L) [-]")
    ax2.set_title(f"σ_aw = {out['lpp'] / (2.0 * out['beam']):.3g}·K_AW, with K_AW = R_AW/(½ρgζ²B) as "
                  "`hullopt waves` plots it", fontsize=8, loc="left")
    ax2.grid(alpha=0.3)
    ax2.legend()
    fig.tight_layout()
    from ...drawing import save_figure

    try:
        save_figure(fig, path)
    except (ValueError, OSError) as e:
        raise HullError(f"--plot {path}: {e}") from None
