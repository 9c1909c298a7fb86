"""``hullopt stability`` (GZ curve, cross curves, IS Code criteria) and ``hullopt print`` (a scaled model in
watertight pieces for 3D printing).

``stability`` runs one kept program (:func:`~hullopt.study.cached_call`) and imports the hydrostatics
only while it computes: a warm call neither traces nor compiles, and the imports overlap the solve."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import typer

from ...constants import RHO_SEA
from ...errors import HullError
from ...geometry import export_mesh, split_for_print, to_trimesh
from ...models import LoadedHull
from ...report import fmt, quantity, unit_places
from ...study import load_hull
from .._app import app
from ..output import (
    EXIT_CRITERIA,
    busy,
    parse_range,
    print_json,
    say,
    styled,
    table,
    warn,
)
from .hydro import HULL_HELP, parse_displacement

SHEER_HELP = "Deck line: 'none' (the sections' deck edge) or 'icll' (ICLL standard sheer added)."
PLOT_FORMATS = (".png", ".svg", ".pdf")


def _sectioned(hull: LoadedHull, sheer: str):
    s = sheer.strip().lower()
    if s == "none":
        return hull.sections
    if s == "icll":
        from ...hydro import icll_sheer, with_sheer

        return with_sheer(hull.sections, icll_sheer(hull.sections))
    raise HullError(f"--sheer {sheer!r}: expected 'none' or 'icll'")


def _check_out(path: Path, formats: tuple[str, ...], what: str) -> Path:
    if path.suffix.lower() not in formats:
        raise HullError(f"{what} {path}: unknown format {path.suffix!r}; expected one of {', '.join(formats)}")
    if not path.parent.is_dir():
        raise HullError(f"{what} {path}: the folder {str(path.parent)!r} does not exist")
    return path


def _volume(sections, displacement: str, rho: float, what: str = "--displacement") -> float:
    from ...hydro import heeled_integrals

    volume = parse_displacement(displacement) / rho
    full = float(heeled_integrals(sections, 0.0, float(sections.depth) + 1.0).volume)
    if volume >= full:
        raise HullError(f"{what} {displacement}: more than the hull displaces at its deck ({rho * full / 1e3:,.0f} t)")
    return volume


def _stability_program(sections, volume, kg, heels, lcg, fsc, flooding_angle, free_trim: bool):
    """:func:`~hullopt.hydro.stability`'s curve and criteria as dicts of their fields (a kept program's outputs
    then need no hydro class to be read back) and the volume the hull displaces at its deck [m³] (as
    :func:`_volume`)."""
    from ...hydro import heeled_integrals, stability

    full = heeled_integrals(sections, 0.0, jnp.max(sections.yz[..., 1]) + 1.0).volume
    res = stability(sections, volume, kg, heels, lcg, fsc, free_trim, flooding_angle)
    return dict(vars(res.curve)), dict(vars(res.criteria)), full


def _stability_call(sections, volume: float, kg: float, heels: np.ndarray, lcg: float | None, fsc: float,
                    free_trim: bool, flooding_angle: float | None):
    """Dispatch :func:`_stability_program` through a kept program (no tracing or compiling when warm; angles in
    radians, lengths in m) and return at once: ``(curve fields, criteria fields, volume at the deck)``, arrays
    still being computed."""
    from ...study import cached_call

    def arr(v):  # arrays, not Python floats: a float would be baked into the program
        return None if v is None else jnp.asarray(v, dtype=float)

    args = (sections, arr(volume), arr(kg), arr(heels), arr(lcg), arr(fsc), arr(flooding_angle))
    key = {"lcg": lcg is not None, "flooding_angle": flooding_angle is not None, "v": 2}
    return cached_call("stability", _stability_program, args, (free_trim,), key=key)


@app.command("stability")
def stability_cmd(
    hull: Annotated[str, typer.Argument(help=HULL_HELP)],
    displacement: Annotated[str, typer.Option(help="Displacement [t] (or '…kg').")],
    kg: Annotated[float, typer.Option("--kg", help="Height of the centre of gravity above the baseline [m].")],
    lcg: Annotated[float | None, typer.Option(help="LCG [m from AP]; default: the upright LCB (level trim).")] = None,
    fsc: Annotated[float, typer.Option(help="Free-surface correction GG' [m].")] = 0.0,
    heels: Annotated[str, typer.Option(help="Heels START:STOP:COUNT [deg], within 0…90.")] = "0:90:19",
    sheer: Annotated[str, typer.Option(help=SHEER_HELP)] = "none",
    fixed_trim: Annotated[bool, typer.Option("--fixed-trim", help="Even keel at every heel (no free trim).")] = False,
    flooding_angle: Annotated[float | None, typer.Option(help="Downflooding angle θf [deg] for the areas.")] = None,
    cross: Annotated[str | None, typer.Option(help="Cross curves KN over displacements START:STOP:COUNT [t].")] = None,
    rho: Annotated[float, typer.Option(help="Water density [kg/m³].")] = RHO_SEA,
    json: Annotated[bool, typer.Option("--json", help="Print JSON (heels in degrees, lengths in m).")] = False,
    plot: Annotated[Path | None, typer.Option(help="Save the GZ curve (.png, .svg, .pdf).")] = None,
    kn_plot: Annotated[Path | None, typer.Option(help="Save the cross curves (needs --cross).")] = None,
) -> None:
    """GZ curve, GM₀, angle of vanishing stability and the IMO IS Code 2008 §2.2 criteria for a loading.

    Exit code 4 when some criterion fails (the table and the JSON say which), so that a script can gate on it."""
    if not (np.isfinite(rho) and rho > 0):
        raise HullError(f"--rho {rho}: must be a positive density in kg/m³")
    for name, v in (("--kg", kg), ("--fsc", fsc), ("--lcg", 0.0 if lcg is None else lcg)):
        if not np.isfinite(v):
            raise HullError(f"{name} {v}: must be a finite number of metres")
    if fsc < 0:
        raise HullError(f"--fsc {fsc}: a free-surface correction is ≥ 0 m")
    if flooding_angle is not None and not (0 < flooding_angle <= 90):
        raise HullError(f"--flooding-angle {flooding_angle}: expected an angle in (0, 90] degrees")
    deg = parse_range(heels, "--heels")
    if deg.min() < 0 or deg.max() > 90:
        raise HullError(f"--heels {heels}: heels must lie within 0…90 degrees")
    if plot is not None:
        _check_out(plot, PLOT_FORMATS, "--plot")
    if kn_plot is not None:
        _check_out(kn_plot, PLOT_FORMATS, "--kn-plot")
        if cross is None:
            raise HullError("--kn-plot needs --cross START:STOP:COUNT (displacements in t)")
    with busy("reading the hull", quiet=json) as stage:
        h = load_hull(hull)
        sections = _sectioned(h, sheer)
        x = np.asarray(sections.x)
        if lcg is not None and not (float(x[0]) <= lcg <= float(x[-1])):
            raise HullError(f"--lcg {lcg:g} m is outside the hull ({float(x[0]):g} … {float(x[-1]):g} m)")
        volume = parse_displacement(displacement) / rho
        stage(f"GZ curve: equilibrium at {len(deg)} heels")
        curve, criteria, full = _stability_call(sections, volume, kg, np.deg2rad(deg), lcg, fsc, not fixed_trim,
                                                None if flooding_angle is None else np.deg2rad(flooding_angle))
        from ...hydro import (  # imported while the program computes
            Criteria,
            StabilityCurve,
        )

        c, crit = StabilityCurve(**curve), Criteria(**criteria)
        if volume >= float(full):  # the curve solved for it is thrown away
            raise HullError(f"--displacement {displacement}: more than the hull displaces at its deck "
                            f"({rho * float(full) / 1e3:,.0f} t)")
        out = {
            "hull": h.name, "displacement": rho * volume, "volume": volume, "kg": kg, "lcg": float(c.lcg),
            "fsc": fsc, "sheer": sheer, "free_trim": not fixed_trim, "heel_deg": deg, "gz": c.gz, "kn": c.kn,
            "trim_deg": np.rad2deg(np.arctan(np.asarray(c.trim))), "level": c.level, "converged": c.converged,
            "gm0": float(c.gm0), "gz_max": float(crit.gz_max),
            "angle_gz_max_deg": np.rad2deg(float(crit.angle_gz_max)),
            "vanishing_angle_deg": np.rad2deg(float(crit.vanishing_angle)), "criteria": crit.to_list(),
        }
        if cross is not None:
            disp_t = parse_range(cross, "--cross")
            stage(f"cross curves: {len(disp_t)} displacements × {len(deg)} heels")
            vols = np.array([_volume(sections, f"{float(d)}", rho, "--cross value") for d in disp_t])
            from ...hydro import cross_curves

            kn = eqx.filter_jit(cross_curves)(sections, jnp.asarray(vols), jnp.deg2rad(jnp.asarray(deg)),
                                              not fixed_trim)
            out["cross_curves"] = {"displacement": disp_t * 1e3, "heel_deg": deg, "kn": kn}
            if kn_plot is not None:
                from ...drawing import plot_cross_curves

                stage("plotting the cross curves")
                plot_cross_curves(disp_t, np.deg2rad(deg), kn, kn_plot, h.name)
        if plot is not None:
            from ...drawing import plot_gz

            stage("plotting the GZ curve")
            plot_gz(c, plot, crit, h.name)
    if not bool(np.all(np.asarray(c.converged))):
        bad = deg[~np.asarray(c.converged)]
        warn(f"no equilibrium found at heels {', '.join(f'{b:g}' for b in bad)}°")
    failed = [r["criterion"] for r in out["criteria"] if not r["pass"]]
    if json:
        print_json(out)
    else:
        _print_stability(out, h.name, rho, plot, kn_plot)
    if failed:
        if not json:
            say(f"{len(failed)} of {len(out['criteria'])} criteria fail: {'; '.join(failed)} (exit code "
                f"{EXIT_CRITERIA})", style="bold red")
        raise typer.Exit(EXIT_CRITERIA)


def _print_stability(out: dict, name: str, rho: float, plot: Path | None, kn_plot: Path | None) -> None:
    """The GZ table, the IS Code criteria with their units and the cross curves of ``hullopt stability``."""
    deg = np.asarray(out["heel_deg"])
    rows = [[f"{a:g}", float(g), float(k), float(t)] for a, g, k, t in zip(deg, out["gz"], out["kn"], out["trim_deg"])]
    # the GZ and KN columns share one scale (KN's), so that a GZ of round-off next to an upright ship reads 0
    scale = max(float(np.max(np.abs(out["kn"]))), float(np.max(np.abs(out["gz"]))), 1.0)
    table(f"GZ curve — {name}: Δ {fmt(out['displacement'] / 1e3, places=1)} t, "
          f"KG {quantity(out['kg'], 'm', places=3)}, LCG {quantity(out['lcg'], 'm', places=3)} from AP, GM₀ {quantity(out['gm0'], 'm', places=3)}"
          + (f", FSC {quantity(out['fsc'], 'm', places=3)}" if out["fsc"] else ""),
          ["heel [°]", "GZ [m]", "KN [m]", "trim [°, bow down]"], rows, scale=[None, scale, scale, 1.0],
          places=[None, 3, 3, 3])
    crows = [[r["criterion"], float(r["value"]), float(r["required"]), float(r["margin_exact"]), r["unit"],
              styled("pass", "green") if r["pass"] else styled("FAIL", "bold red")] for r in out["criteria"]]
    table("IMO IS Code 2008 Part A §2.2", ["criterion", "value", "required ≥", "margin", "unit", ""], crows,
          by="row", sig=3, places=[unit_places(r["unit"]) for r in out["criteria"]])
    van = out["vanishing_angle_deg"]
    say(f"GZmax {quantity(out['gz_max'], 'm', places=3)} at {quantity(out['angle_gz_max_deg'], '°', 3, ref=10)}; "
        "angle of vanishing stability " + (quantity(van, "°", 3, ref=10) if np.isfinite(van) else "beyond 90°"))
    if "cross_curves" in out:
        cc = out["cross_curves"]
        kn = np.asarray(cc["kn"])
        table("Cross curves KN [m]", ["Δ [t] \\ heel", *(f"{a:g}°" for a in cc["heel_deg"])],
              [[fmt(d / 1e3), *map(float, row)] for d, row in zip(cc["displacement"], kn)],
              scale=[None] + [float(np.abs(kn).max())] * kn.shape[1], places=[None] + [3] * kn.shape[1])
    for p in (plot, kn_plot):
        if p is not None:
            say(f"wrote {p}")

def parse_scale(text: str) -> float:
    """``'1:200'`` (or ``'200'``, ``'0.005'``) → the model scale factor (0.005)."""
    t = text.strip()
    try:
        if ":" in t:
            a, b = (float(v) for v in t.split(":"))
            s = a / b
        else:
            v = float(t)
            s = 1.0 / v if v > 1 else v
    except (ValueError, ZeroDivisionError):
        raise HullError(f"--scale {text!r}: expected a ratio such as 1:200") from None
    if not (np.isfinite(s) and s > 0):
        raise HullError(f"--scale {text!r}: expected a positive ratio such as 1:200")
    return s


@app.command("print")
def print_cmd(
    hull: Annotated[str, typer.Argument(help=HULL_HELP)],
    out: Annotated[Path, typer.Option(help="Output folder (created if missing).")],
    scale: Annotated[str, typer.Option(help="Model scale, e.g. 1:200.")] = "1:100",
    pieces: Annotated[int, typer.Option(help="Number of pieces along the length.")] = 3,
    formats: Annotated[str, typer.Option("--format", help="Comma-separated: stl, x3d, obj, ply, glb.")] = "stl,x3d",
    sheer: Annotated[str, typer.Option(help=SHEER_HELP)] = "none",
) -> None:
    """A scaled model for 3D printing, in millimetres, split into watertight pieces along the length."""
    s = parse_scale(scale)
    if not 1 <= pieces <= 100:
        raise HullError(f"--pieces {pieces}: expected 1…100")
    fmts = [f.strip().lower().lstrip(".") for f in formats.split(",") if f.strip()]
    bad = [f for f in fmts if f not in ("stl", "x3d", "obj", "ply", "glb")]
    if bad or not fmts:
        raise HullError(f"--format {formats!r}: expected some of stl, x3d, obj, ply, glb")
    if out.exists() and not out.is_dir():
        raise HullError(f"--out {out}: exists and is not a folder")
    h = load_hull(hull)
    mesh = to_trimesh(_sectioned(h, sheer))
    try:
        parts = split_for_print(mesh, pieces, 1000.0 * s)
    except ValueError as e:
        raise HullError(f"hull {hull!r}: {e}") from None
    out.mkdir(parents=True, exist_ok=True)
    stem = Path(h.name.split(" ")[0]).name.split(".")[0] or "hull"
    rows = []
    for i, p in enumerate(parts, start=1):
        # each file welded for its format and checked as read back (watertight, one body, no degenerate face)
        written = [export_mesh(p, out / f"{stem}_{i}of{pieces}.{f}") for f in fmts]
        ext = p.bounds[:, 0]
        rows.append([f"{i}", float(ext[0]), float(ext[1]), float(p.volume / 1e3), all(w.ok for w in written)])
    whole = mesh.volume * (1000.0 * s) ** 3 / 1e3
    table(f"{h.name} at 1:{1 / s:g} in {out} (mm)", ["piece", "x from [mm]", "x to [mm]", "volume [cm³]", "watertight"],
          rows + [["whole", float(mesh.bounds[0, 0] * 1000 * s), float(mesh.bounds[1, 0] * 1000 * s), float(whole), ""]])
