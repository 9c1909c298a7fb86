"""``hullopt stability`` (GZ curve, cross curves, IS Code criteria) and ``hullopt print`` (a scaled model in
watertight pieces for 3D printing).

``stability`` runs one kept program (:func:`~hullopt.study.cached_call`) and imports the hydrostatics
only while it computes: a warm call neither traces nor compiles, and the imports overlap the solve."""

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
from ...geometry import export_mesh, split_for_print, to_trimesh
from ...models import LoadedHull
from ...report import fmt, quantity, unit_places
from ...study import cached_call, load_hull, prepare_call, sections_like
from .._app import Strict, app
from ..output import (
    EXIT_CRITERIA,
    busy,
    check_out,
    parse_range,
    print_json,
    say,
    styled,
    table,
    warn,
    wrote,
)
from .hydro import HULL_HELP, parse_displacement

RESERVE_MIN = 0.05
"""Below this reserve buoyancy (the hull's volume above the waterline up to its deck edge, over its
displacement) a GZ curve is that of a hull without topsides: ``hullopt stability`` warns."""
SHEER_HELP = "Deck line: 'none' (the sections' deck edge) or 'icll' (ICLL standard sheer added)."
PLOT_FORMATS = (".png", ".svg", ".pdf")
WIND_PRESSURE = 504.0  # Pa: hullopt.hydro.WIND_PRESSURE (IS Code §2.3.2), here so that --help loads no hydro
GRID = 91  # heels on [0, 90°] of the criteria's grid (1° steps), given to hullopt.hydro.stability


def _sectioned(hull: LoadedHull, sheer: str):
    s = sheer.strip().lower()
    if s == "none":
        return hull.sections
    if s == "icll":
        from ...hydro import icll_sheer, with_sheer

        return with_sheer(hull.sections, icll_sheer(hull.sections))
    raise HullError(f"--sheer {sheer!r}: expected 'none' or 'icll'")


def _volume(sections, displacement: str, rho: float, what: str = "--displacement") -> float:
    from ...hydro import heeled_integrals

    volume = parse_displacement(displacement) / rho
    full = float(heeled_integrals(sections, 0.0, float(sections.depth) + 1.0).volume)
    if volume >= full:
        raise HullError(f"{what} {displacement}: more than the hull displaces at its deck ({rho * full / 1e3:,.0f} t)")
    return volume


def _stability_program(sections, volume, kg, heels, lcg, fsc, flooding_angle, free_trim: bool, on_grid: bool):
    """:func:`~hullopt.hydro.stability`'s curve and criteria as dicts of their fields (a kept program's outputs
    then need no hydro class to be read back) and the volume the hull displaces at its deck [m³] (as
    :func:`_volume`)."""
    from ...hydro import heeled_integrals, stability

    full = heeled_integrals(sections, 0.0, jnp.max(sections.yz[..., 1]) + 1.0).volume
    res = stability(sections, volume, kg, heels, lcg, fsc, free_trim, flooding_angle, n_grid=GRID, on_grid=on_grid)
    return dict(vars(res.curve)), dict(vars(res.criteria)), full


def _stability_call(sections, volume: float, kg: float, heels: np.ndarray, lcg: float | None, fsc: float,
                    free_trim: bool, flooding_angle: float | None, call=cached_call):
    """Dispatch :func:`_stability_program` through a kept program (no tracing or compiling when warm; angles in
    radians, lengths in m) and return at once: ``(curve fields, criteria fields, volume at the deck)``, arrays
    still being computed. With ``call=prepare_call`` (``sections`` may be their shapes) only start building
    the program."""

    def arr(v):  # arrays, not Python floats: a float would be baked into the program
        return None if v is None else jnp.asarray(v, dtype=float)

    args = (sections, arr(volume), arr(kg), arr(heels), arr(lcg), arr(fsc), arr(flooding_angle))
    key = {"lcg": lcg is not None, "flooding_angle": flooding_angle is not None, "v": 2}
    # heels on the criteria's grid (the default 0:90:19 are) take its equilibria: known here, so the program is
    # built for that way or the other, not both (a lax.cond traces and compiles both)
    step = 0.5 * np.pi / (GRID - 1)
    on_grid = bool(np.all(np.abs(heels - np.round(heels / step) * step) <= 1e-12))
    return call("stability", _stability_program, args, (free_trim, on_grid), key=key)


@app.command("stability")
def stability_cmd(
    hull: Annotated[str, typer.Argument(help=HULL_HELP)],
    displacement: Annotated[str, typer.Option(help="Displacement [t] (or '…kg').")],
    kg: Annotated[float, typer.Option("--kg", help="Height of the centre of gravity above the baseline [m]; "
                                                   "at most the deck's (see --kg-above-deck).")],
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
    weather: Annotated[bool, typer.Option("--weather", help="Also the IS Code §2.3 weather criterion (windage: "
                                                        "the hull above the waterline).")] = False,
    windage_area: Annotated[float | None, typer.Option(help="Lateral area [m²] above the hull that its geometry "
                                                            "lacks (superstructure, deck cargo), added to the "
                                                            "hull's (with --windage-lever).")] = None,
    windage_lever: Annotated[float | None, typer.Option(help="Z of --windage-area [m]: its centre above the centre "
                                                             "of the underwater lateral area.")] = None,
    bilge_keel_area: Annotated[float, typer.Option(help="Total bilge-keel (and bar-keel) area A_k [m²] for the "
                                                        "roll angle.")] = 0.0,
    sharp_bilges: Annotated[bool, typer.Option("--sharp-bilges", help="A sharp-bilged hull (k = 0.7).")] = False,
    wind_pressure: Annotated[float, typer.Option(help="Wind pressure P [Pa] (504; less for restricted service, "
                                                      "as the Administration approves).")] = WIND_PRESSURE,
    kg_above_deck: Annotated[bool, typer.Option("--kg-above-deck", help="Accept a --kg above the hull's deck "
                                                                        "(heavy deck cargo or lifts; sections "
                                                                        "that stop below the deck).")] = False,
    strict: Strict = False,
) -> None:
    """GZ curve, GM₀, angle of vanishing stability and the IMO IS Code 2008 §2.2 criteria for a loading; with
    --weather also the §2.3 severe wind and rolling criterion.

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
    _check_weather(weather, windage_area, windage_lever, bilge_keel_area, sharp_bilges, wind_pressure)
    # the weather criterion takes GZ at every degree (the §2.2 criteria's grid: no extra equilibria)
    solve_deg = np.union1d(deg, np.arange(0.0, 91.0)) if weather else deg
    rows = np.searchsorted(solve_deg, deg)
    if plot is not None:
        check_out(plot, PLOT_FORMATS, "--plot")
    if kn_plot is not None:
        check_out(kn_plot, PLOT_FORMATS, "--kn-plot")
        if cross is None:
            raise HullError("--kn-plot needs --cross START:STOP:COUNT (displacements in t)")
    volume = parse_displacement(displacement) / rho
    theta_f = None if flooding_angle is None else np.deg2rad(flooding_angle)
    written: list[Path] = []  # the plots, said once at the end (wrote)
    with busy("reading the hull", quiet=json) as stage:
        like = sections_like(hull) if sheer.strip().lower() == "none" else None
        if like is not None:  # a mesh: the GZ program is built while it is read
            _stability_call(like, volume, kg, np.deg2rad(solve_deg), lcg, fsc, not fixed_trim, theta_f, prepare_call)
        h = load_hull(hull)
        sections = _sectioned(h, sheer)
        check_kg(kg, sections, kg_above_deck)
        x = np.asarray(sections.x)
        if lcg is not None and not (float(x[0]) <= lcg <= float(x[-1])):
            raise HullError(f"--lcg {lcg:g} m is outside the hull ({float(x[0]):g} … {float(x[-1]):g} m)")
        stage(f"GZ curve: equilibrium at {len(solve_deg)} heels")
        curve, criteria, full = _stability_call(sections, volume, kg, np.deg2rad(solve_deg), lcg, fsc,
                                                not fixed_trim, theta_f)
        from ...hydro import (  # imported while the program computes
            Criteria,
            StabilityCurve,
        )

        solved, crit = StabilityCurve(**curve), Criteria(**criteria)
        if volume >= float(full):  # the curve solved for it is thrown away
            raise HullError(f"--displacement {displacement}: more than the hull displaces at its deck "
                            f"({rho * float(full) / 1e3:,.0f} t)")
        c = jax.tree.map(lambda a: np.asarray(a)[rows] if np.ndim(a) == 1 else a, solved)  # the requested heels
        out = {
            "hull": h.name, "displacement": rho * volume, "volume": volume, "kg": kg, "lcg": float(c.lcg),
            "fsc": fsc, "sheer": sheer, "free_trim": not fixed_trim, "heel_deg": deg, "gz": c.gz, "kn": c.kn,
            "trim_deg": np.rad2deg(np.arctan(np.asarray(c.trim))), "level": c.level, "converged": c.converged,
            "gm0": float(c.gm0), "gz_max": float(crit.gz_max),
            "angle_gz_max_deg": np.rad2deg(float(crit.angle_gz_max)),
            "vanishing_angle_deg": np.rad2deg(float(crit.vanishing_angle)), "criteria": crit.to_list(),
        }
        wx = None
        if weather:
            stage("weather criterion")
            wx, out["weather"] = _weather(sections, solved, rho * volume, kg, rho, theta_f, windage_area,
                                          windage_lever, bilge_keel_area, sharp_bilges, wind_pressure)
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
                written.append(kn_plot)
        if plot is not None:
            from ...drawing import plot_gz

            stage("plotting the GZ curve")
            plot_gz(c, plot, crit, h.name, rho=rho, flooding_angle=theta_f, weather=wx)
            written.insert(0, plot)
    if not bool(np.all(np.asarray(solved.converged))):
        bad = solve_deg[~np.asarray(solved.converged)]
        warn(f"no equilibrium found at heels {', '.join(f'{b:g}' for b in bad)}°")
    if (reserve := float(full) / volume - 1) < RESERVE_MIN:  # a ship has ~15 % and more
        warn(f"the hull's reserve buoyancy is {reserve:.2%} of its displacement (its volume above "
             "this waterline up to the deck edge): heeled, its deck goes under at once, and the GZ curve is that of "
             "a hull without topsides, as from offsets that stop at the DWL; give the hull its sections above the "
             "waterline")
    if wx is not None and out["weather"]["outside"]:
        warn("the weather criterion's roll-angle tables rest on ships with B/d < 3.5, −0.3 ≤ KG/d − 1 ≤ 0.5 and "
             f"T < 20 s (IS Code 2008 §2.3.4); this loading has {'; '.join(out['weather']['outside'])}")
    records = out["criteria"] + out.get("weather", {}).get("criteria", [])
    failed = [r["criterion"] for r in records if not r["pass"]]
    if json:
        print_json(out)
    else:
        _print_stability(out, h.name, rho)
    for p in written:
        wrote(p, json=json)
    if failed:
        if not json:
            say(f"{len(failed)} of {len(records)} criteria fail: {'; '.join(failed)} (exit code "
                f"{EXIT_CRITERIA})", style="bold red")
        raise typer.Exit(EXIT_CRITERIA)


def check_kg(kg: float, sections, above_deck: bool = False) -> None:
    """Refuse a KG [m above the baseline] above the deck — the hull's highest point, its sheer included — (almost
    always a KG from another datum or another hull) unless ``above_deck`` (``--kg-above-deck``): a
    :class:`HullError` naming ``--kg`` and the deck's height [m]."""
    deck = float(np.asarray(sections.yz)[..., 1].max())
    if kg > deck and not above_deck:
        raise HullError(f"--kg {kg:g} m is above the deck, {deck:g} m above the baseline at its highest: KG is the "
                        "centre of gravity's height above the baseline (keel); give --kg-above-deck if it is meant "
                        "(heavy deck cargo, or sections that stop below the deck)")


def _check_weather(weather: bool, area: float | None, lever: float | None, bilge_keel_area: float,
                   sharp_bilges: bool, pressure: float) -> None:
    """The weather options: given only with --weather, finite, the windage area and its lever together."""
    given = [name for name, v in (("--windage-area", area is not None), ("--windage-lever", lever is not None),
                                  ("--bilge-keel-area", bilge_keel_area != 0.0), ("--sharp-bilges", sharp_bilges),
                                  ("--wind-pressure", pressure != WIND_PRESSURE)) if v]
    if given and not weather:
        raise HullError(f"{given[0]} applies to the weather criterion: add --weather")
    if (area is None) != (lever is None):
        raise HullError("--windage-area and --windage-lever go together: the extra lateral area [m²] and its "
                        "lever Z [m]")
    if area is not None and not (np.isfinite(area) and area >= 0):
        raise HullError(f"--windage-area {area}: expected an area ≥ 0 m²")
    if lever is not None and not np.isfinite(lever):
        raise HullError(f"--windage-lever {lever}: expected a finite lever Z in m")
    if not (np.isfinite(bilge_keel_area) and bilge_keel_area >= 0):
        raise HullError(f"--bilge-keel-area {bilge_keel_area}: expected an area ≥ 0 m²")
    if not (np.isfinite(pressure) and pressure > 0):
        raise HullError(f"--wind-pressure {pressure}: expected a positive pressure in Pa")


def _weather_program(sections, heel, gz, level, trim, gm0, displacement, kg, theta_f, extra_area, extra_lever,
                     bilge_keel_area, pressure, sharp_bilges: bool, rho: float):
    """The §2.3 weather criterion of a loading solved at every degree (``heel``, ``gz``, ``level``, ``trim``
    (91,)) as a dict of :class:`~hullopt.hydro.Weather`'s fields (a kept program's outputs then need no hydro
    class), and a dict of what it was computed from: the windage of the hull above its mean draft (its side,
    :func:`hullopt.wind.wind_variables`, with its lever Z to the centre of the underwater lateral plane) plus the
    extra area, B, C_B and L_WL from the hydrostatics at that draft, the deck-edge immersion angle along the
    curve (NaN: none to 90°)."""
    from ...hydro import (
        deck_immersion_angle,
        hydrostatics,
        lateral_plane,
        weather_criterion,
    )
    from ...wind import no_parts, wind_variables

    draft = level[0]  # heel 0: the mean draft (the waterplane at midship)
    hs = hydrostatics(sections, draft, rho)
    wv = wind_variables(sections, draft, no_parts())
    _, z_lateral = lateral_plane(sections, draft)
    hull_lever = draft + wv.H_C - z_lateral
    area = wv.A_L + extra_area
    lever = (wv.A_L * hull_lever + extra_area * extra_lever) / jnp.where(area > 0, area, 1.0)
    deck = deck_immersion_angle(sections, heel, level, trim)
    w = weather_criterion(heel, gz, gm0, displacement, area, lever, hs.bwl, draft, kg, hs.cb, hs.lwl,
                          bilge_keel_area, sharp_bilges, theta_f, deck, pressure)
    inputs = {"windage_area": area, "windage_lever": lever, "windage_area_hull": wv.A_L,
              "windage_lever_hull": hull_lever, "breadth": hs.bwl, "draft": draft, "cb": hs.cb, "lwl": hs.lwl,
              "deck_edge_angle": deck}
    return dict(vars(w)), inputs


def _weather(sections, curve, displacement: float, kg: float, rho: float, theta_f: float | None,
             extra_area: float | None, extra_lever: float | None, bilge_keel_area: float, sharp_bilges: bool,
             pressure: float):
    """:func:`_weather_program` through a kept program (no tracing or compiling when warm) for the ``curve``
    solved at every degree; returns the :class:`~hullopt.hydro.Weather` and its JSON record (angles in
    degrees)."""
    from ...hydro import Weather

    def arr(v):
        return jnp.asarray(v, dtype=float)

    args = (sections, *(arr(getattr(curve, f)) for f in ("heel", "gz", "level", "trim", "gm0")), arr(displacement),
            arr(kg), None if theta_f is None else arr(theta_f), arr(extra_area or 0.0), arr(extra_lever or 0.0),
            arr(bilge_keel_area), arr(pressure))
    fields, inputs = cached_call("weather", _weather_program, args, (sharp_bilges, float(rho)),
                                 key={"flooding_angle": theta_f is not None, "v": 1})
    w = Weather(**fields)
    inputs = {k: float(v) for k, v in inputs.items()}
    if not inputs["windage_area"] > 0:
        raise HullError("--weather: no lateral area above the waterline (the hull is under water to its deck); "
                        "give --windage-area and --windage-lever")
    deck = inputs.pop("deck_edge_angle")
    record = {
        "wind_pressure": pressure, **inputs, "windage_area_extra": extra_area or 0.0,
        "windage_lever_extra": extra_lever, "kg": kg, "gm0": float(curve.gm0), "bilge_keel_area": bilge_keel_area,
        "sharp_bilges": sharp_bilges, "deck_edge_angle_deg": float(np.rad2deg(deck)),
        "flooding_angle_deg": None if theta_f is None else float(np.rad2deg(theta_f)), **w.to_dict(),
    }
    return w, record


def _print_stability(out: dict, name: str, rho: float) -> None:
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
    if "weather" in out:
        _print_weather(out["weather"])
    if "cross_curves" in out:
        cc = out["cross_curves"]
        kn = np.asarray(cc["kn"])
        table("Cross curves KN [m]", ["Δ [t] \\ heel", *(f"{a:g}°" for a in cc["heel_deg"])],
              [[fmt(d / 1e3), *map(float, row)] for d, row in zip(cc["displacement"], kn)],
              scale=[None] + [float(np.abs(kn).max())] * kn.shape[1], places=[None] + [3] * kn.shape[1])

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
    strict: Strict = False,
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
    for i in range(1, len(parts) + 1):
        for f in fmts:
            wrote(out / f"{stem}_{i}of{pieces}.{f}")


def _print_weather(w: dict) -> None:
    """The §2.3 table of ``hullopt stability --weather``: the levers, angles and areas with their units, the
    two criteria with pass/FAIL, and the factors of the roll angle under it."""
    (heel, ratio) = w["criteria"]

    def verdict(r):
        return styled("pass", "green") if r["pass"] else styled("FAIL", "bold red")

    deck = w["deck_edge_angle_deg"]
    ends = {"θf": w["flooding_angle_deg"], "θc": w["theta_c_deg"]}
    rows = [
        ["Lateral windage area A", w["windage_area"], "", "m²", ""],
        ["Lever Z of A (to the underwater centre)", w["windage_lever"], "", "m", ""],
        ["Steady-wind lever lw1 = P·A·Z/(g·Δ)", w["lw1"], "", "m", ""],
        ["Gust lever lw2 = 1.5·lw1", w["lw2"], "", "m", ""],
        ["Roll period T = 2·C·B/√GM", w["roll_period"], "", "s", ""],
        ["Roll to windward φ1", w["phi1_deg"], "", "deg", ""],
        ["Steady heel φ0 (≤ 16° and 0.8 × deck edge)", heel["value"], f"≤ {fmt(heel['required'], sig=3, places=1)}",
         "deg", verdict(heel)],
        ["Roll-back angle φ0 − φ1", w["phi_roll_deg"], "", "deg", ""],
        ["First intercept with lw2", w["phi_c_deg"] if w["reaches_lw2"] else "none: GZ < lw2", "", "deg", ""],
        ["End of area b φ2 (50°, θf, θc)", w["phi2_deg"], "", "deg", ""],
        ["Area a", w["area_a"], "", "m·rad", ""],
        ["Area b", w["area_b"], "", "m·rad", ""],
        ["Area b / area a", ratio["value"], "≥ 1", "–", verdict(ratio)],
    ]
    table("IMO IS Code 2008 Part A §2.3 (weather criterion)", ["quantity", "value", "required", "unit", ""], rows,
          by="row", places=[unit_places(r[3]) for r in rows])
    given = "; ".join(f"{k} {quantity(v, '°', 3, ref=10)}" for k, v in ends.items() if v is not None and np.isfinite(v))
    f3 = lambda v: fmt(v, sig=3)
    say(f"φ1 = 109·k·X1·X2·√(r·s): X1 {f3(w['x1'])} (B/d {f3(w['b_over_d'])}), X2 {f3(w['x2'])} "
        f"(C_B {f3(w['cb'])}), k {f3(w['k'])} (100·A_k/(L·B) {f3(w['bilge_keel_ratio'])}), s {f3(w['s'])} "
        f"(T {quantity(w['roll_period'], 's', sig=3)}), r {f3(w['r'])} (OG/d {f3(w['og_over_d'])}); B "
        f"{quantity(w['breadth'], 'm', places=3)}, d {quantity(w['draft'], 'm', places=3)}, L_WL "
        f"{quantity(w['lwl'], 'm', places=3)}; P {fmt(w['wind_pressure'])} Pa; deck edge immerses at "
        + (quantity(deck, "°", 3, ref=10) if np.isfinite(deck) else "beyond 90°") + (f"; {given}" if given else ""))
