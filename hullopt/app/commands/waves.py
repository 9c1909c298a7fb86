"""``hullopt waves``: bluntness Bf, K_AW and added resistance in regular waves and in a sea state."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import jax
import jax.numpy as jnp
import numpy as np
import typer

from ...constants import KNOT, RHO_SEA, G
from ...errors import HullError
from ...models import blunt_bow as blunt_bow_modification
from ...study import cached_call, load_hull
from ...waves import (
    AFT_OPTIONS,
    METHODS,
    SPECTRA,
    WAVE_METHODS,
    mean_added_resistance,
    method_resistance,
    motion_validity_warning,
    nmri_added_resistance,
    omega_from_wavelength,
    select_lower_k_aw,
)
from .._app import Strict, app
from ..output import busy, console, parse_range, print_json, table, warn, wrote
from .hydro import HULL_HELP


def _finite(value: float, name: str, *, positive: bool = False, nonneg: bool = False) -> float:
    if not np.isfinite(value) or (positive and value <= 0) or (nonneg and value < 0):
        need = "a positive number" if positive else "a number ≥ 0" if nonneg else "a finite number"
        raise HullError(f"{name} {value:g}: expected {need}")
    return float(value)


def _parse_params(text: str) -> np.ndarray:
    try:
        vals = np.array([float(v) for v in text.split(",")])
    except ValueError:
        raise HullError(f"--blunt-bow {text!r}: expected comma-separated numbers, e.g. 0.5,1,2") from None
    if not np.all(np.isfinite(vals)) or np.any(vals <= -1.0):
        raise HullError(f"--blunt-bow {text!r}: each value must be a number above −1 (the half-breadth factor 1 + p)")
    return vals


def includes(method: str, motion: bool = True) -> str:
    """What ``method``'s R_AW counts (its class's description; ``hullopt waves --method all`` prints it beside
    its numbers; docs/methods.md says which to use when)."""
    return WAVE_METHODS[method]().label(motion)


def _waves_program(sections, draft, speed, omega, heading, kyy, smooth, sea, methods, aft, motion, spectrum,
                   spreading):
    """The NMRI quantities at ``omega (w,)`` [rad/s], each of ``methods``' R_AW [N per m² of ζ_a²] in those
    regular waves and, with a sea state ``sea = (hs [m], tp [s], γ)``, its mean [N]: dicts of arrays (a kept
    program's outputs, read back without the waves' classes)."""
    nm = nmri_added_resistance(sections, draft, speed, omega, heading, 1.0, smooth=smooth, aft=aft)
    out = {"nmri": {k: getattr(nm, k) for k in ("beam", "fn", "bf", "c_u", "k_aw_short", "alpha_t")},
           "regular": {}, "mean": {}}
    for m in methods:
        r = method_resistance(m, sections, draft, speed, omega, heading, 1.0, kyy=kyy, smooth=smooth, aft=aft,
                              motion=motion)
        out["regular"][m] = {"total": r.total, "reflection": r.reflection, "motion": r.motion}
        if sea is not None:
            hs, tp, gamma = sea
            mean = mean_added_resistance(m, sections, draft, speed, hs, tp, heading, spectrum=spectrum, gamma=gamma,
                                         spreading_s=spreading, kyy=kyy, smooth=smooth, aft=aft, motion=motion)
            out["mean"][m] = {"total": mean.total, "reflection": mean.reflection, "motion": mean.motion}
    return out


@app.command()
def waves(
    hull: Annotated[str, typer.Argument(help=HULL_HELP)],
    speed: Annotated[float, typer.Option(help="Ship speed [kn].")],
    draft: Annotated[float | None, typer.Option(help="Draft above the baseline [m] (default: the hull's).")] = None,
    heading: Annotated[float, typer.Option(help="Wave heading [deg]: 0 head seas, 180 following.")] = 0.0,
    hs: Annotated[float | None, typer.Option(help="Significant wave height of a sea state [m].")] = None,
    tp: Annotated[float | None, typer.Option(help="Peak period of the sea state [s].")] = None,
    lambda_over_l: Annotated[str, typer.Option("--lambda-over-l", help="Regular waves λ/L START:STOP:COUNT.")] = "0.2:2.0:19",
    method: Annotated[str, typer.Option(help=f"One of {', '.join(METHODS)}, or all (side by side: what each includes and its R_AW).")] = "nmri",
    spectrum: Annotated[str, typer.Option(help=f"Sea-state spectrum: {', '.join(SPECTRA)}.")] = "pm",
    gamma: Annotated[float, typer.Option(help="JONSWAP peak enhancement γ.")] = 3.3,
    spreading: Annotated[float | None, typer.Option(help="cos-2s spreading exponent s (short-crested); none: long-crested.")] = None,
    amplitude: Annotated[float, typer.Option(help="Regular-wave amplitude ζ_a [m] for r_awr.")] = 1.0,
    kyy: Annotated[float, typer.Option(help="Pitch radius of gyration / Lpp (STAWAVE-2, SNNM).")] = 0.25,
    smooth: Annotated[float | None, typer.Option(help="Soft-max width τ for C_U (default: exact max).")] = None,
    aft: Annotated[str, typer.Option(help="Lit range of the waterline for Bf: exclude (the lit entrance only, the default) or include (also the lit run and transom, Bf < 0 in following seas; R_AWR is never negative).")] = "exclude",
    blunt_bow: Annotated[str | None, typer.Option("--blunt-bow", help="Claim-6 program: bow-bluntness values p to try, e.g. 0.5,1,2.")] = None,
    motion: Annotated[bool, typer.Option("--motion/--no-motion", help="NMRI: include the motion part R_AWM (strip theory; see `hullopt motions`).")] = True,
    json: Annotated[bool, typer.Option("--json", help="Print JSON (SI units; forces in N).")] = False,
    plot: Annotated[Path | None, typer.Option(help="Write a plot of K_AW against λ/L (.png, .pdf, .svg).")] = None,
    strict: Strict = False,
) -> None:
    """Bf, K_AW (patent JP2009-286166 / NMRI) and R_AW in regular waves and in a sea state."""
    if method not in (*METHODS, "all"):
        raise HullError(f"--method {method!r}: expected one of {', '.join(METHODS)} or all")
    if spectrum not in SPECTRA:
        raise HullError(f"--spectrum {spectrum!r}: expected one of {', '.join(SPECTRA)}")
    if aft not in AFT_OPTIONS:
        raise HullError(f"--aft {aft!r}: expected one of {', '.join(AFT_OPTIONS)}")
    if not (np.isfinite(speed) and speed > 0):  # as `hullopt resistance` refuses it: R_AW is a ship's under way
        raise HullError(f"--speed {speed:g}: expected a positive number of knots")
    u = float(speed) * KNOT
    if not (np.isfinite(heading) and -360.0 <= heading <= 360.0):
        raise HullError(f"--heading {heading:g}: expected degrees within ±360")
    _finite(amplitude, "--amplitude", positive=True)
    _finite(kyy, "--kyy", positive=True)
    if smooth is not None:
        _finite(smooth, "--smooth", positive=True)
    if spreading is not None:
        _finite(spreading, "--spreading", positive=True)
    if (hs is None) != (tp is None):
        raise HullError("give both --hs and --tp for a sea state (or neither)")
    if hs is not None:
        _finite(hs, "--hs", positive=True)
        _finite(tp, "--tp", positive=True)
        _finite(gamma, "--gamma", positive=True)
    ratios = parse_range(lambda_over_l, "--lambda-over-l")
    if np.any(ratios <= 0):
        raise HullError(f"--lambda-over-l {lambda_over_l!r}: wave lengths must be positive")
    params = _parse_params(blunt_bow) if blunt_bow is not None else None

    with busy(f"added resistance in waves ({method})", quiet=json):
        h = load_hull(hull)
        if draft is None:
            if h.design_draft is None:
                raise HullError("give --draft (this hull has no design draft)")
            draft = h.design_draft
        t = h.check_draft(draft)
        s = h.sections
        lpp = float(s.lpp)
        alpha = np.radians(heading)
        omega = np.asarray(omega_from_wavelength(ratios * lpp))
        methods = METHODS if method == "all" else (method,)

        def arr(v):  # arrays, not Python floats: a float would be baked into the program
            return None if v is None else jnp.asarray(v, dtype=float)

        sea = None if hs is None else (arr(hs), arr(tp), arr(gamma))
        args = (s, arr(t), arr(u), arr(omega), arr(alpha), arr(kyy), arr(smooth), sea)
        res = jax.device_get(cached_call(
            "waves", _waves_program, args, (methods, aft, motion, spectrum, spreading),
            key={"smooth": smooth is not None, "sea": hs is not None, "v": 1}))
        nm = res["nmri"]
        half = 0.5 * RHO_SEA * G * float(nm["beam"])
        per = {}
        for m in methods:
            r = res["regular"][m]
            per[m] = {
                "includes": includes(m, motion), "k_aw_per_wave": np.asarray(r["total"]) / half,
                "r_awr": amplitude**2 * np.asarray(r["reflection"]), "r_awm": amplitude**2 * np.asarray(r["motion"]),
                "r_aw": amplitude**2 * np.asarray(r["total"]),
            }
            if hs is not None:
                mean = res["mean"][m]
                per[m].update(mean_raw=float(mean["total"]), mean_raw_motion=float(mean["motion"]),
                              mean_raw_reflection=float(mean["reflection"]))
        out = {
            "hull": h.name, "method": method, "draft": t, "speed": u, "speed_kn": speed, "heading_deg": heading,
            "lpp": lpp, "beam": float(nm["beam"]), "fn": float(nm["fn"]), "bf": float(nm["bf"]),
            "c_u": float(nm["c_u"]), "k_aw": float(nm["k_aw_short"]),
            "r_awr_short": float(half * amplitude**2 * nm["k_aw_short"]),
            "amplitude": amplitude, "lambda_over_l": ratios, "omega": omega,
            "alpha_t": np.asarray(nm["alpha_t"]),
        }
        if hs is not None:
            out.update(hs=hs, tp=tp, spectrum=spectrum, spreading=spreading)
        if method == "all":
            out["methods"] = per  # one record per method, the keys of a single method's
        else:
            out.update(per[method])
        if params is not None:
            prog = select_lower_k_aw(s, blunt_bow_modification, params, t, u, alpha)
            out["program"] = {
                "params": [None, *params.tolist()], "bf": np.asarray(prog.bf), "c_u": np.asarray(prog.c_u),
                "k_aw": np.asarray(prog.k_aw), "best": prog.best,
                "chosen": "original" if prog.best == 0 else f"blunt-bow p={params[prog.best - 1]:g}",
            }
        if plot is not None:
            _plot(plot, out)
            wrote(plot, json=json)
    for m in METHODS if method == "all" else (method,):
        wm = WAVE_METHODS[m]()
        if not bool(np.all(np.asarray(wm.valid(jnp.asarray(alpha))))):
            warn(f"{m} applies {wm.headings} only: at heading {heading:g}° it gives no added resistance (its 0 kN "
                 "is not a result); use nmri or snnm there")
    if motion and method in ("nmri", "all"):  # the methods whose R_AW has the strip-theory motion part
        note = motion_validity_warning(out["fn"], lpp / out["beam"])
        if note is not None:
            warn(note)
    if json:
        print_json(out)
        return
    (_print_all if method == "all" else _print)(out)



def _print(out: dict) -> None:
    table(f"Added resistance in waves — {out['hull']} ({out['method']}, T {out['draft']:g} m, "
          f"{out['speed_kn']:g} kn, heading {out['heading_deg']:g}°)",
          ["quantity", "value"],
          [["Fn", out["fn"]], ["B_wl [m]", out["beam"]], ["Bf", out["bf"]], ["C_U", out["c_u"]],
           ["includes", out["includes"]],
           ["K_AW (short waves, NMRI)", out["k_aw"]], [f"R_AWR short waves, ζ={out['amplitude']:g} m [kN]", out["r_awr_short"] / 1e3]]
          + ([[f"mean R_AW, Hs {out['hs']:g} m, Tp {out['tp']:g} s [kN]", out["mean_raw"] / 1e3],
              ["  motion part [kN]", out["mean_raw_motion"] / 1e3], ["  reflection part [kN]", out["mean_raw_reflection"] / 1e3]]
             if "mean_raw" in out else []), by="row")
    table("Regular waves", ["λ/L", "ω [rad/s]", "α_T", "K_AW", "R_AWM [kN]", "R_AWR [kN]", "R_AW [kN]"],
          [[f"{r:.3f}", w, a, k, m / 1e3, f / 1e3, tt / 1e3] for r, w, a, k, m, f, tt in zip(
              out["lambda_over_l"], out["omega"], out["alpha_t"], out["k_aw_per_wave"], out["r_awm"], out["r_awr"],
              out["r_aw"])])
    if "program" in out:
        p = out["program"]
        table("Claim-6 program: modify the bow, keep the lower K_AW", ["candidate", "Bf", "C_U", "K_AW"],
              [["original" if q is None else f"blunt-bow p={q:g}", b, c, k]
               for q, b, c, k in zip(p["params"], p["bf"], p["c_u"], p["k_aw"])])
        console.print(f"chosen: {p['chosen']}")


def _print_all(out: dict) -> None:
    """Every method side by side: what each includes, its mean R_AW in the sea state (or the largest R_AW in
    regular waves without one), and R_AW per regular wave."""
    table(f"Added resistance in waves — {out['hull']} (T {out['draft']:g} m, {out['speed_kn']:g} kn, "
          f"heading {out['heading_deg']:g}°)", ["quantity", "value"],
          [["Fn", out["fn"]], ["B_wl [m]", out["beam"]], ["Bf", out["bf"]], ["C_U", out["c_u"]],
           ["K_AW (short waves, NMRI)", out["k_aw"]]], by="row")
    per = out["methods"]
    if "hs" in out:
        table(f"By method: mean R_AW, Hs {out['hs']:g} m, Tp {out['tp']:g} s ({out['spectrum']})",
              ["method", "includes", "R_AW [kN]", "motion [kN]", "reflection [kN]"],
              [[m, r["includes"], r["mean_raw"] / 1e3, r["mean_raw_motion"] / 1e3, r["mean_raw_reflection"] / 1e3]
               for m, r in per.items()])
    else:
        x = out["lambda_over_l"]
        table(f"By method: largest R_AW in regular waves, ζ = {out['amplitude']:g} m",
              ["method", "includes", "max R_AW [kN]", "at λ/L"],
              [[m, r["includes"], float(np.max(r["r_aw"])) / 1e3, f"{x[int(np.argmax(r['r_aw']))]:.3f}"]
               for m, r in per.items()])
    table(f"R_AW in regular waves [kN], ζ = {out['amplitude']:g} m", ["λ/L", *per],
          [[f"{x:.3f}", *(r["r_aw"][i] / 1e3 for r in per.values())] for i, x in enumerate(out["lambda_over_l"])],
          caption="Which method when: docs/methods.md (linked from the README).")


def _plot(path: Path, out: dict) -> None:
    """K_AW = R_AW/(½ρgζ²B) against λ/L: the total of the method (or of every method with ``--method all``), its
    motion and reflection parts where it has both, and NMRI's short-wave reflection level; each legend entry
    says what is plotted."""
    if not path.parent.is_dir():
        raise HullError(f"--plot {path}: the folder {str(path.parent)!r} does not exist")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    half = 0.5 * RHO_SEA * G * out["beam"] * out["amplitude"] ** 2
    fig, ax = plt.subplots(figsize=(8.5, 4.8))
    x = out["lambda_over_l"]
    per = out["methods"] if "methods" in out else {out["method"]: out}
    for j, (m, r) in enumerate(per.items()):
        color = "k" if len(per) == 1 else f"C{j}"
        ax.plot(x, r["r_aw"] / half, "-o", ms=3, color=color, label=f"{m} R_AW: {r['includes']}")
        if np.any(r["r_awm"] != 0) and (len(per) == 1 or m == "nmri"):
            how = "strip theory" if m == "nmri" else "empirical"
            ax.plot(x, r["r_awm"] / half, "--", color=color, alpha=0.8, label=f"{m} motion part R_AWM ({how})")
            how = "Bf formula" if m == "nmri" else "empirical"
            ax.plot(x, r["r_awr"] / half, ":", color=color, alpha=0.8, label=f"{m} reflection part R_AWR ({how})")
    ax.axhline(out["k_aw"], color="grey", lw=0.8,
               label=f"NMRI short-wave reflection K_AW(Bf) = {out['k_aw']:.3f}")
    ax.set_xlabel("λ / L [-]")
    ax.set_ylabel("K_AW = R_AW / (½ρgζ²B) [-]")
    sigma = out["lpp"] / (2.0 * out["beam"])  # σ_aw = R_AW/(ρgζ²B²/L) of `hullopt motions` = K_AW·L/(2B)
    ax.set_title(f"Added resistance in regular waves — {out['hull']}: {out['speed_kn']:g} kn (Fn {out['fn']:.3f}), "
                 f"T {out['draft']:g} m, Bf {out['bf']:.3f}, heading {out['heading_deg']:g}°\n"
                 f"K_AW = R_AW/(½ρgζ²B); σ_aw = R_AW/(ρgζ²B²/L) (as `hullopt motions` plots it) = "
                 f"{sigma:.3g}·K_AW", loc="left", fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    from ...drawing import save_figure

    try:
        save_figure(fig, path, bbox_inches="tight")
    except (ValueError, OSError) as e:
        raise HullError(f"--plot {path}: {e}") from None
