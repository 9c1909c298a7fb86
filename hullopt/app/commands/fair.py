"""``hullopt fair``: automatic fairing of an offset table (the Coons surface of seed 001; the unfairness
measures and the fairing problem are hullopt's own) with a before/after report and plots.

Its solve, the given frame lines and the report's measures and curvature fields are kept programs
(:func:`~hullopt.study.cached_call`): a warm call traces nothing, and a new draft, move cap or pull is an
argument, not a new program."""

from __future__ import annotations

from functools import partial
from pathlib import Path
from typing import Annotated

import jax
import jax.numpy as jnp
import numpy as np
import typer

from ...drawing import save_figure, write_offset_grid
from ...errors import HullError
from ...fairing import RESIDUALS, curve_curvature, graph_curvatures, measure
from ...geometry import Sections, coons_surface
from ...hydro import hydrostatics
from ...models import OffsetTable, offsets_to_sections, read_offsets
from ...optimise import aft_body_noise, fair_offsets, fixed_offsets
from ...report import fmt, quantity, write_json
from ...study import cached_call, load_hull
from .._app import Strict, app
from ..output import EXIT_NOT_CONVERGED, busy, print_json, say, table, warn, wrote

HOLD_PCT = 0.5  # displacement and Bwl of a faired table within this [%] of the given

FAIR_HULL_HELP = ("offsets .csv (faired as given), or any other hull spec (builtin:…, mesh): its sections are "
                  "resampled on --stations × --waterlines offsets")


def hull_offsets(spec: str, stations: int, waterlines: int):
    """``(x, z, y, lpp, design_draft, name)`` of a hull spec: an offset table as read, else the sections
    resampled at equally spaced stations and waterlines (each section must be single-valued in z)."""
    base = spec.partition("?")[0]
    if base.lower().endswith(".csv") and "?" not in spec:
        if not Path(base).is_file():
            raise HullError(f"hull {spec!r}: no such file {base!r}")
        t = read_offsets(base)
        if t.knuckles:
            raise HullError(f"{base}: fairing does not handle knuckles yet (a split spline would be faired across its corner)")
        return t.x, t.z, t.y, t.lpp, None, Path(base).name
    if stations < 4 or waterlines < 4:
        raise HullError(f"--stations {stations} and --waterlines {waterlines}: need at least 4 each")
    h = load_hull(spec)
    s = h.sections
    yz, xs = np.asarray(s.yz), np.asarray(s.x)
    if np.any(np.diff(yz[..., 1], axis=-1) < 0):
        raise HullError(f"hull {spec!r}: a section turns back downwards; fairing needs sections single-valued in z")
    z = np.linspace(max(float(s.keel), 0.0), float(s.depth), waterlines)
    per_station = np.array([np.interp(z, sec[:, 1], sec[:, 0], left=0.0, right=sec[-1, 0]) for sec in yz])
    x = np.linspace(xs[0], xs[-1], stations)
    y = np.array([np.interp(x, xs, per_station[:, j]) for j in range(waterlines)]).T
    return x, z, np.maximum(y, 0.0), float(s.lpp), h.design_draft, h.name


def _fields(x, z, y, n=161, m=81):
    """Mean and Gaussian curvature on a fine ``n × m`` (x, z) grid, and the frame lines with their curvature:
    ``(xf, zf, y on the grid, H, K, frame lines, their κ)``."""
    s = coons_surface(x, z, y, twist="spline")  # C²: curvature continuous across patch edges
    xf, zf = jnp.linspace(x[0], x[-1], n), jnp.linspace(z[0], z[-1], m)
    xx, zz, xs = xf[:, None], zf[None, :], x[:, None]
    k, h = graph_curvatures(*(s(xx, zz, a, b) for a, b in ((1, 0), (0, 1), (2, 0), (1, 1), (0, 2))))
    kappa = curve_curvature(s(xs, zz, 0, 1), s(xs, zz, 0, 2))
    return xf, zf, s(xx, zz), h, k, s(xs, zz), kappa


def _measured(x, z, tables, read: Sections, yz, draft):
    """What the report and the plots show of each table ``(k, s, w)``: ``particulars`` ``(k, 3)`` (∇ [m³],
    LCB [m from the AP], Bwl [m] of the sections ``yz`` ``(k, n, m, 2)`` at ``read``'s stations: each table's
    surface as ``hullopt hydro`` reads the written table), every unfairness ``measures`` ``(k,)`` and the
    curvature ``fields`` (:func:`_fields`, each with a leading ``k``). One kept program
    (:func:`~hullopt.study.cached_call`)."""
    def one(y, yz):
        h = hydrostatics(Sections(x=read.x, yz=yz, lpp=read.lpp), draft)
        s = coons_surface(x, z, y)
        return {"particulars": jnp.stack([h.volume, h.lcb, h.bwl]),
                "measures": {name: measure(s, name) for name in RESIDUALS}, "fields": _fields(x, z, y)}

    return jax.vmap(one)(tables, yz)


def _plots(out: Path, fields, x, before, lpp, title) -> list[str]:
    """``body_plan.png`` and ``curvature.png`` of the given and the faired table (``fields``: the two tables'
    :func:`_fields`); their paths."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    zf = fields[0][1]
    # body plan: aft half on the left (mirrored), fore half on the right; porcupines along the normals
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5), sharey=True)
    fig.suptitle(title)
    scale = 0.08 * float(np.max(before)) / max(np.percentile(np.abs(fields[0][6][fields[0][5] > 0]), 95), 1e-12)
    for ax, (_, _, _, _, _, frames, kappa), label in zip(axes, fields, ("before", "after")):
        bristles = [np.zeros((0, 2, 2))]
        for i, xi in enumerate(x):
            side = -1.0 if xi < lpp / 2 else 1.0
            yv, kv = frames[i], kappa[i]
            hull = yv > 0
            if hull.sum() < 2:
                continue
            yp, zp = side * yv[hull], zf[hull]
            ax.plot(yp, zp, color="k", lw=0.8)
            # bristles along the outward normal, outwards where the section is convex
            ty, tz = np.gradient(yp), np.gradient(zp)
            nrm = np.hypot(ty, tz) + 1e-300
            ny, nz = side * tz / nrm, -side * ty / nrm  # outward normal on either side of the plan
            b = scale * kv[hull]
            bristles.append(np.stack([np.stack([yp, zp], -1), np.stack([yp + b * ny, zp + b * nz], -1)], 1))
        # one collection, not a line per bristle (thousands of artists took seconds to build and draw)
        ax.add_collection(LineCollection(np.concatenate(bristles), colors="tab:red", linewidths=0.5))
        ax.axvline(0, color="0.6", lw=0.5)
        ax.set_aspect("equal")
        ax.set_title(f"body plan and section curvature, {label}")
        ax.set_xlabel("half-breadth y [m] (aft ← | → fore)")
    axes[0].set_ylabel("z [m]")
    fig.tight_layout()
    files = [out / "body_plan.png"]
    save_figure(fig, files[0], dpi=110)

    fig, axes = plt.subplots(2, 2, figsize=(13, 6.5), sharex=True, sharey=True)
    for col, (xf, zf_, yy, h, k, _, _), label in zip(range(2), fields, ("before", "after")):
        for row, (field, name) in enumerate(((h, "mean curvature H [1/m]"), (k, "Gaussian curvature K [1/m²]"))):
            ax = axes[row, col]
            f = np.where(yy > 0, field, np.nan)
            lim = np.nanpercentile(np.abs(fields[0][3 + row][fields[0][2] > 0]), 98) or 1.0
            im = ax.pcolormesh(xf, zf_, f.T, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="auto")
            ax.set_title(f"{name}, {label}")
            fig.colorbar(im, ax=ax)
            ax.set_ylabel("z [m]")
    for ax in axes[-1]:
        ax.set_xlabel("x [m from AP]")
    fig.suptitle(f"{title}: curvature-shaded hull side (x, z) of the C² spline surface through the offsets")
    fig.tight_layout()
    files.append(out / "curvature.png")
    save_figure(fig, files[1], dpi=110)
    return [str(f) for f in files]


@app.command()
def fair(
    hull: Annotated[str, typer.Argument(help=FAIR_HULL_HELP)],
    measure_name: Annotated[str, typer.Option("--measure", help=f"Unfairness measure: {', '.join(RESIDUALS)}.")] = "knots",
    draft: Annotated[float | None, typer.Option(help="Draft [m] at which displacement and LCB are held (default: the design draft).")] = None,
    max_move: Annotated[float | None, typer.Option(help="Largest move of one offset [m] (default 5 % of the largest half-breadth).")] = None,
    region: Annotated[str | None, typer.Option(help="Fair only stations with X0 ≤ x ≤ X1 [m], given as X0:X1.")] = None,
    proximity: Annotated[float, typer.Option(help="Weight of the pull towards the given offsets.")] = 1e-3,
    noise: Annotated[float, typer.Option(help="Demo: first add Gaussian noise of this size [m] to the aft-body offsets.")] = 0.0,
    seed: Annotated[int, typer.Option(help="Random seed of --noise.")] = 0,
    stations: Annotated[int, typer.Option(help="Stations when resampling a non-offset hull.")] = 21,
    waterlines: Annotated[int, typer.Option(help="Waterlines when resampling a non-offset hull.")] = 11,
    out: Annotated[Path | None, typer.Option(help="Folder for report.json, faired_offsets.csv, body_plan.png, curvature.png.")] = None,
    json: Annotated[bool, typer.Option("--json", help="Print the report as JSON.")] = False,
    strict: Strict = False,
) -> None:
    """Fair a hull's offsets by minimising an unfairness measure, holding displacement, LCB and the contour.

    No offset goes below zero or beyond the table's widest half-breadth, and no section gains an inflection
    (both are constraints). Exit code 5, with the stations named, when the result is not fit to hand on: the
    solver did not converge, an offset moved by the whole --max-move, a section has more inflections than
    given, or displacement or Bwl changed by more than 0.5 % (the report's "problems"; the offsets and plots
    are still written)."""
    if measure_name not in RESIDUALS:
        raise HullError(f"--measure {measure_name!r}: expected one of {', '.join(RESIDUALS)}")
    for name, v, ok in (("--proximity", proximity, proximity >= 0), ("--noise", noise, noise >= 0),
                        ("--max-move", max_move, max_move is None or max_move > 0)):
        if v is not None and not (np.isfinite(v) and ok):
            raise HullError(f"{name} {v}: must be a {'positive' if name == '--max-move' else 'non-negative'} number")
    if out is not None and out.exists() and not out.is_dir():
        raise HullError(f"--out {out}: exists and is not a folder")
    with busy("reading the hull", quiet=json) as stage:
        report = _fair(stage, hull, measure_name, draft, max_move, region, proximity, noise, seed, stations,
                       waterlines, out)
    if json:
        print_json(report)
    else:
        _print_fair(report)
    if report["problems"]:
        for p in report["problems"]:
            warn(p)
        warn(f"the faired table is not fit to hand on as it is (exit code {EXIT_NOT_CONVERGED})")
        raise typer.Exit(EXIT_NOT_CONVERGED)


def _fair(stage, hull, measure_name, draft, max_move, region, proximity, noise, seed, stations, waterlines,
          out) -> dict:
    """The work of ``hullopt fair`` (``stage(text)`` names each step on the progress display): its report."""
    x, z, y, lpp, design, name = hull_offsets(hull, stations, waterlines)
    t = draft if draft is not None else design
    if t is None:
        raise HullError("give --draft (this hull has no design draft)")
    if not (np.isfinite(t) and z[0] < t <= z[-1]):
        raise HullError(f"--draft {t:g} m is outside the offsets: expected a draft in ({z[0]:g}, {z[-1]:g}] m")
    free = ~fixed_offsets(y)
    if region is not None:
        try:
            lo, hi = (float(v) for v in region.split(":"))
        except ValueError:
            raise HullError(f"--region {region!r}: expected X0:X1 in m from the AP, e.g. 0:30") from None
        free &= (x[:, None] >= lo) & (x[:, None] <= hi)
    if not free.any():
        raise HullError("no offset is free to move (all are fixed: zero, contour, flat of side, or outside --region)")
    given = aft_body_noise(x, y, noise, seed, lpp=lpp, free=free) if noise > 0 else y
    stage(f"fairing {int(free.sum())} offsets ({measure_name}; BFGS in augmented-Lagrangian rounds)")
    call = partial(cached_call, key={"v": 2})  # kept programs: a warm call traces nothing
    res = fair_offsets(x, z, given, lpp, t, measure_name, free=free, max_move=max_move, proximity=proximity,
                       call=call)
    stage("measuring the faired surface")
    # the particulars of each table as `hullopt hydro` reads it back (natural splines, PCHIP where they overshoot)
    read = [offsets_to_sections(OffsetTable(x=x, z=z, y=v, lpp=lpp)) for v in (given, res.y)]
    got = jax.device_get(call("fair-measures", _measured, (jnp.asarray(x), jnp.asarray(z),
                                                           jnp.asarray(np.stack([given, res.y])), read[0],
                                                           jnp.stack([r.yz for r in read]),
                                                           jnp.asarray(float(t))), ()))
    (v0, lcb0, b0), (v1, lcb1, b1) = got["particulars"].tolist()
    all_measures = {m: {"before": float(v[0]), "after": float(v[1])} for m, v in got["measures"].items()}
    move = res.y - given
    report = {
        "hull": name, "measure": measure_name, "draft": t, "lpp": lpp,
        "before": res.before, "after": res.after, "reduction": res.reduction,
        "measures": all_measures,
        "free_offsets": int(free.sum()), "max_move": float(np.abs(move).max()),
        "rms_move": float(np.sqrt(np.mean(move[free] ** 2))),
        "volume_before": v0, "volume_after": v1, "volume_change_pct": 100 * (v1 / v0 - 1),
        "lcb_before": lcb0, "lcb_after": lcb1, "lcb_shift_pct_lpp": 100 * (lcb1 - lcb0) / lpp,
        "bwl_before": b0, "bwl_after": b1, "bwl_change_pct": 100 * (b1 / b0 - 1),
        "half_breadth_max": float(given.max()), "half_breadth_min_after": float(res.y.min()),
        "move_cap": res.bound,
        "inflections": {"x": [float(v) for v in x], "before": res.inflections0[0].tolist(),
                        "after": res.inflections[0].tolist()},
        "steps": res.steps, "converged": res.converged,
    }
    report["problems"] = _problems(report, x, res)
    if noise > 0:
        e0 = float(np.sqrt(np.mean((given - y)[free] ** 2)))
        e1 = float(np.sqrt(np.mean((res.y - y)[free] ** 2)))
        report.update(noise=noise, noise_rms=e0, residual_error_rms=e1, noise_removed=1 - e1 / e0 if e0 else 0.0)
    if out is not None:
        stage("writing the offsets and the plots")
        out.mkdir(parents=True, exist_ok=True)
        write_offset_grid(out / "faired_offsets.csv", x, z, res.y, lpp, f"{name} faired by hullopt ({measure_name})")
        report["files"] = [str(out / "report.json"), str(out / "faired_offsets.csv"),
                           *_plots(out, [[a[i] for a in got["fields"]] for i in (0, 1)], x, given, lpp, name)]
        write_json(out / "report.json", report)
    return report


def _stations(x, rows) -> str:
    """The stations ``x[rows]`` as a reader finds them: ``x = 9.5, 14.25 m``."""
    return "x = " + ", ".join(f"{float(v):.4g}" for v in np.asarray(x)[rows]) + " m"


def _problems(report: dict, x, res) -> list[str]:
    """What makes a faired table unfit to hand on (each a sentence naming the stations); empty when fit."""
    out = []
    if not res.converged:
        out.append(f"the solver did not converge in {res.steps} steps (the result is its last iterate)")
    for what, key in (("displacement", "volume_change_pct"), ("Bwl", "bwl_change_pct")):
        if abs(report[key]) > HOLD_PCT:
            out.append(f"{what} changed by {report[key]:+.2f} % (more than {HOLD_PCT:g} %)")
    new = np.flatnonzero(res.new_inflections[0])
    if new.size:
        out.append(f"new inflections in the sections at {_stations(x, new)}")
    cap = np.flatnonzero(res.at_cap.any(axis=1))
    if cap.size:
        out.append(f"offsets moved by the cap {quantity(res.bound, 'm', ref=1)} at {_stations(x, cap)}: the cap, "
                   "not fairness, stopped them; look at those stations, and give a larger --max-move only if "
                   "the table's errors are that large")
    return out


def _print_fair(report: dict) -> None:
    """The before/after table and the summary lines of ``hullopt fair``."""
    def pct(v):  # a change in %, to 3 significant figures, signed
        return "–" if v is None else ("+" if fmt(v, 3) != "0" and v > 0 else "") + fmt(v, 3)

    rows = [[f"unfairness ({m})", d["before"], d["after"],
             pct(100 * (d["after"] / d["before"] - 1) if d["before"] else None)]
            for m, d in report["measures"].items()]
    v0, v1, lcb0, lcb1 = (report[k] for k in ("volume_before", "volume_after", "lcb_before", "lcb_after"))
    inf0, inf1 = (sum(report["inflections"][k]) for k in ("before", "after"))
    rows += [["volume ∇ [m³]", v0, v1, pct(report["volume_change_pct"])],
             ["Bwl [m]", report["bwl_before"], report["bwl_after"], pct(report["bwl_change_pct"])],
             ["LCB [m from AP]", lcb0, lcb1, pct(report["lcb_shift_pct_lpp"]) + " Lpp"],
             ["inflections in the sections", inf0, inf1, "–"]]
    table(f"Fairing — {report['hull']} (measure {report['measure']}, T = {fmt(report['draft'])} m)",
          ["", "before", "after", "change [%]"], rows, by="row",
          caption="unfairness: the measure's sum of squares (dimensionless); the LCB's change is in % of Lpp")
    say(f"{report['measure']} fell by {100 * report['reduction']:.1f} % in {report['steps']} steps; largest move "
        f"{quantity(report['max_move'], 'm', ref=1)}; displacement {report['volume_change_pct']:+.4f} %, LCB "
        f"{report['lcb_shift_pct_lpp']:+.4f} % Lpp")
    if "noise" in report:
        say(f"noise removed: {100 * report['noise_removed']:.1f} % "
            f"(rms {quantity(report['noise_rms'], 'm', ref=1)} → "
            f"{quantity(report['residual_error_rms'], 'm', ref=1)})")
    if "files" in report:
        for f in report["files"]:
            wrote(f)
