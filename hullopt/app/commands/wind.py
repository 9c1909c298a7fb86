"""``hullopt wind``: wind-load variables and coefficients from a hull with parts, or from drawings."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import typer

from ...errors import HullError
from ...study import load_hull
from ...wind import (
    MODELS,
    check_parts,
    drawing_variables,
    ship_type,
    wind_coefficients,
    wind_variables,
)
from .._app import Strict, app
from ..output import print_json, say, table, wrote
from ...study import DrawingsConfig, config_parts, read_wind_config

ROWS = [("L", "m"), ("B", "m"), ("A_T", "m²"), ("A_L", "m²"), ("A_OD", "m²"), ("A_SS", "m²"), ("C", "m"),
        ("C_BR", "m"), ("H_BR", "m"), ("H_C", "m"), ("S", "m"), ("M", ""), ("H_L", "m"), ("C_bow", "m")]


def _read_image(path: str):
    from skimage import io

    if not Path(path).is_file():
        raise HullError(f"{path}: no such image")
    try:
        return io.imread(path)
    except (OSError, ValueError) as e:
        raise HullError(f"{path}: cannot read the image: {e}") from None


def _plot(path: Path, psi_deg, by_model: dict[str, dict[str, np.ndarray]], title: str) -> None:
    """C(ψ) curves on Cartesian axes: the force coefficients C_X, C_Y above the moment coefficients C_N, C_K,
    against the wind angle ψ [deg] from ahead (0°) to astern (180°), a line style per model; missing
    (non-finite) ones left out."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    styles = ("o-", "s--", "^:", "d-.", "v-")
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7.5, 6.5), sharex=True)
    for ax, group in ((ax1, (("cx", "C_X longitudinal force", "C0"), ("cy", "C_Y lateral force", "C1"))),
                      (ax2, (("cn", "C_N yaw moment", "C2"), ("ck", "C_K roll moment", "C3")))):
        for (model, coeffs), style in zip(by_model.items(), styles):
            for key, label, colour in group:
                if np.all(np.isfinite(coeffs[key])):
                    name = label if len(by_model) == 1 else f"{label.split()[0]} {model}"
                    ax.plot(psi_deg, coeffs[key], style, ms=3, lw=1.2, color=colour, label=name)
        ax.axhline(0.0, color="black", lw=0.8)
        ax.grid(alpha=0.3)
        if ax.get_lines()[:-1]:
            ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    ax1.set_ylabel("force coefficient [-]")
    ax2.set_ylabel("moment coefficient [-]")
    ax2.set_xlabel("wind angle ψ [deg] (0 = head wind, 180 = following)")
    ax2.set_xlim(0, 180)
    ax2.set_xticks(np.arange(0, 181, 30))
    ax1.set_title(f"Wind load coefficients — {title}\n{REFERENCES}", loc="left", fontsize=9)
    from ...drawing import save_figure

    save_figure(fig, path, dpi=120, bbox_inches="tight")


REFERENCES = "C_X = X/(q A_T), C_Y = Y/(q A_L), C_N = N/(q A_L L), C_K = K/(q A_L H_L); q = ½ρU², H_L = A_L/L"
"""The coefficients' reference areas and lengths (hullopt.wind), printed with every table and plot."""


@app.command()
def wind(
    config: Annotated[Path, typer.Argument(help="A wind config .toml (hull + parts, or [drawings]) or a drawings .json.")],
    model: Annotated[str | None, typer.Option(
        help=f"Coefficient model: {', '.join(MODELS)} or all (side by side; default: the config's).")] = None,
    ship: Annotated[str | None, typer.Option("--ship-type", help="Blendermann ship type (name, prefix or number).")] = None,
    draft: Annotated[float | None, typer.Option(help="Draft [m] (overrides the config).")] = None,
    step: Annotated[float, typer.Option(help="Angle step of the table [deg].")] = 10.0,
    json: Annotated[bool, typer.Option("--json", help="Print JSON: variables and coefficients.")] = False,
    plot: Annotated[Path | None, typer.Option(help="Write a plot of the coefficients C(ψ) against the wind angle (PNG).")] = None,
    strict: Strict = False,
) -> None:
    """Wind-load variables (L, B, A_T, A_L, …) and coefficients C_X, C_Y, C_N, C_K over ψ = 0…180°."""
    cfg = read_wind_config(config)
    model = model or cfg.model
    if model not in (*MODELS, "all"):
        raise HullError(f"--model {model!r}: expected one of {', '.join(MODELS)} or all")
    models = MODELS if model == "all" else (model,)
    ship = ship_type(ship or cfg.ship_type)
    if not (np.isfinite(step) and 0 < step <= 180):
        raise HullError(f"--step {step:g}: expected an angle in (0, 180] degrees")
    if plot is not None and plot.suffix.lower() != ".png":
        raise HullError(f"--plot {plot}: expected a .png file")
    extra = {}
    if isinstance(cfg, DrawingsConfig):
        if draft is not None:
            raise HullError("--draft: a drawing has its waterline; give it as waterline_row in the config")
        res = drawing_variables(_read_image(cfg.side), _read_image(cfg.front), cfg.side_scale.scale(),
                                cfg.front_scale.scale(), cfg.part_specs(), cfg.threshold)
        v, name = res.variables, Path(cfg.side).name
        extra["fractal_dimension"] = res.fractal_dimension
    else:
        hull = load_hull(cfg.hull)
        t = draft if draft is not None else cfg.draft if cfg.draft is not None else hull.design_draft
        if t is None:
            raise HullError(f"{config}: give draft = … (this hull has no design draft)")
        t = hull.check_draft(t, "draft")
        parts = config_parts(cfg.parts)
        check_parts(hull.sections, t, parts)
        v, name = eqx.filter_jit(wind_variables)(hull.sections, jnp.asarray(t), parts), f"{hull.name}, T = {t:g} m"
    psi_deg = np.arange(0.0, 180.0 + 1e-9, step)
    by_model = {}
    for m in models:
        c = wind_coefficients(v, jnp.deg2rad(psi_deg), m, ship=ship, y56=cfg.y56)
        by_model[m] = {k: np.asarray(getattr(c, k)) for k in ("cx", "cy", "cn", "ck")}
    if plot is not None:
        if not plot.parent.is_dir():
            raise HullError(f"--plot {plot}: the folder {str(plot.parent)!r} does not exist")
        _plot(plot, psi_deg, by_model, f"{'every model' if model == 'all' else model} — {name}")
        wrote(plot, json=json)
    variables = v.to_dict() | extra
    if json:
        out = {"variables": variables, "references": REFERENCES}
        if model == "all":
            out |= {"model": "all", "psi_deg": psi_deg, "models": by_model}
        else:
            out |= {"model": model, "coefficients": {"psi_deg": psi_deg, **by_model[model]}}
        print_json(out)
        return
    table(f"Wind variables — {name}", ["variable", "value"],
          [[f"{k} [{u}]" if u else k, int(round(variables[k])) if k == "M" else variables[k]] for k, u in ROWS] +
          [[k, variables[k]] for k in extra], by="row")
    for m, coeffs in by_model.items():
        table(f"Wind coefficients — {m}" + (f" ({ship})" if m == "blendermann" else ""),
              ["ψ [deg]", "C_X", "C_Y", "C_N", "C_K"],
              [[f"{p:g}", *(float(coeffs[k][i]) for k in ("cx", "cy", "cn", "ck"))] for i, p in enumerate(psi_deg)])
    say(REFERENCES)
