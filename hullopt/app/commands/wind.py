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
from .._app import app
from ..output import print_json, say, table
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


def _plot(path: Path, psi_deg, coeffs: dict[str, np.ndarray], title: str) -> None:
    """C(ψ) curves on Cartesian axes: the force coefficients C_X, C_Y above the moment coefficients C_N, C_K,
    against the wind angle ψ [deg] from ahead (0°) to astern (180°); missing (non-finite) ones left out."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True)
    for ax, group in ((ax1, (("cx", "C_X longitudinal force"), ("cy", "C_Y lateral force"))),
                      (ax2, (("cn", "C_N yaw moment"), ("ck", "C_K roll moment")))):
        for key, label in group:
            if np.all(np.isfinite(coeffs[key])):
                ax.plot(psi_deg, coeffs[key], "o-", ms=3, lw=1.3, label=label)
        ax.axhline(0.0, color="black", lw=0.8)
        ax.grid(alpha=0.3)
        if ax.get_lines()[:-1]:
            ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    ax1.set_ylabel("force coefficient [-]")
    ax2.set_ylabel("moment coefficient [-]")
    ax2.set_xlabel("wind angle ψ [deg] (0 = head wind, 180 = following)")
    ax2.set_xlim(0, 180)
    ax2.set_xticks(np.arange(0, 181, 30))
    ax1.set_title(f"Wind load coefficients — {title}", loc="left", fontsize=10)
    from ...drawing import save_figure

    save_figure(fig, path, dpi=120, bbox_inches="tight")


@app.command()
def wind(
    config: Annotated[Path, typer.Argument(help="A wind config .toml (hull + parts, or [drawings]) or a drawings .json.")],
    model: Annotated[str | None, typer.Option(help=f"Coefficient model: {', '.join(MODELS)} (default: the config's).")] = None,
    ship: Annotated[str | None, typer.Option("--ship-type", help="Blendermann ship type (name, prefix or number).")] = None,
    draft: Annotated[float | None, typer.Option(help="Draft [m] (overrides the config).")] = None,
    step: Annotated[float, typer.Option(help="Angle step of the table [deg].")] = 10.0,
    json: Annotated[bool, typer.Option("--json", help="Print JSON: variables and coefficients.")] = False,
    plot: Annotated[Path | None, typer.Option(help="Write a plot of the coefficients C(ψ) against the wind angle (PNG).")] = None,
) -> None:
    """Wind-load variables (L, B, A_T, A_L, …) and coefficients C_X, C_Y, C_N, C_K over ψ = 0…180°."""
    cfg = read_wind_config(config)
    model = model or cfg.model
    if model not in MODELS:
        raise HullError(f"--model {model!r}: expected one of {', '.join(MODELS)}")
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
    c = wind_coefficients(v, jnp.deg2rad(psi_deg), model, ship=ship, y56=cfg.y56)
    coeffs = {k: np.asarray(getattr(c, k)) for k in ("cx", "cy", "cn", "ck")}
    if plot is not None:
        if not plot.parent.is_dir():
            raise HullError(f"--plot {plot}: the folder {str(plot.parent)!r} does not exist")
        _plot(plot, psi_deg, coeffs, f"{model} — {name}")
    variables = v.to_dict() | extra
    if json:
        print_json({"model": model, "variables": variables, "coefficients": {"psi_deg": psi_deg, **coeffs}})
        return
    table(f"Wind variables — {name}", ["variable", "value"],
          [[f"{k} [{u}]" if u else k, int(round(variables[k])) if k == "M" else variables[k]] for k, u in ROWS] +
          [[k, variables[k]] for k in extra], by="row")
    table(f"Wind coefficients — {model}" + (f" ({ship})" if model == "blendermann" else ""),
          ["ψ [deg]", "C_X", "C_Y", "C_N", "C_K"],
          [[f"{p:g}", *(float(coeffs[k][i]) for k in ("cx", "cy", "cn", "ck"))] for i, p in enumerate(psi_deg)])
    if plot is not None:
        say(f"wrote {plot}")
