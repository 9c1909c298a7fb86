"""Hydrostatic curves, the GZ curve and the cross curves (KN) as figures (matplotlib, Agg): PNG, SVG, PDF."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Protocol, runtime_checkable

import numpy as np
from jaxtyping import ArrayLike, Float

from ..constants import RHO_SEA
from ..geometry import TINY_LENGTH
from ._save import save_figure


# What the plots read of hydro's results (drawing sits beside hydro, not above it: it takes them by shape)
@runtime_checkable
class HydrostaticTable(Protocol):
    """Hydrostatics at k drafts (:func:`hullopt.hydro.hydrostatic_table`): ``draft`` and each curve, (k,) SI."""

    draft: ArrayLike
    displacement: ArrayLike


@runtime_checkable
class GZCurve(Protocol):
    """A GZ curve (:class:`hullopt.hydro.StabilityCurve`): heels [rad], GZ [m], GM₀ [m], ∇ [m³], KG [m]."""

    heel: ArrayLike
    gz: ArrayLike
    gm0: ArrayLike
    volume: ArrayLike
    kg: ArrayLike


@runtime_checkable
class GZCriteria(Protocol):
    """Criteria of a GZ curve (:class:`hullopt.hydro.Criteria`): GZ max [m], its angle and the vanishing angle
    [rad]."""

    gz_max: ArrayLike
    angle_gz_max: ArrayLike
    vanishing_angle: ArrayLike


@runtime_checkable
class GZWeather(Protocol):
    """The weather criterion of a GZ curve (:class:`hullopt.hydro.Weather`): the levers ``lw1``, ``lw2`` [m], the
    steady heel ``phi0``, the roll-back angle ``phi_roll`` = φ0 − φ1, the first intercept ``phi_c`` with lw2 and
    the end ``phi2`` of area b [rad], the areas ``area_a``, ``area_b`` [m·rad], and whether GZ reaches lw2
    (``reaches_lw2``)."""

    lw1: ArrayLike
    lw2: ArrayLike
    phi0: ArrayLike
    phi_roll: ArrayLike
    phi_c: ArrayLike
    phi2: ArrayLike
    area_a: ArrayLike
    area_b: ArrayLike
    reaches_lw2: ArrayLike


def _figure(*args, **kw):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt, *plt.subplots(*args, **kw)


def _save(plt, fig, path) -> Path:
    return save_figure(fig, path, dpi=150, bbox_inches="tight")


# Panels of the hydrostatic curves: (title, x-axis label with unit, [(field of Hydrostatics, legend, scale)]).
# Each quantity is shown in its own unit; quantities share a panel only where they share the unit.
_HYDRO_PANELS = [
    ("Displacement", "Δ [t]", [("displacement", "Δ", 1e-3)]),
    ("Areas", "area [m²]", [("awp", "A_WP waterplane", 1.0), ("wetted_surface", "S wetted", 1.0)]),
    ("Tonnes per cm", "TPC [t/cm]", [("tpc", "TPC", 1.0)]),
    ("Moment to trim 1 cm", "MCT 1 cm [t·m/cm]", [("mct", "MCT", 1.0)]),
    ("Longitudinal centres", "x from AP [m]", [("lcb", "LCB", 1.0), ("lcf", "LCF", 1.0)]),
    ("Vertical centres", "height above base [m]", [("kb", "KB", 1.0), ("kmt", "KM_T", 1.0)]),
    ("Longitudinal metacentre", "BM_L [m]", [("bml", "BM_L", 1.0)]),
    ("Form coefficients", "coefficient [-]", [("cb", "C_B", 1.0), ("cp", "C_P", 1.0), ("cm", "C_M", 1.0),
                                              ("cwp", "C_WP", 1.0)]),
]


def plot_hydrostatic_curves(table: HydrostaticTable, path: str | os.PathLike, name: str = "",
                            depth: float | None = None, design_draft: float | None = None,
                            rho: float = RHO_SEA) -> Path:
    """Curves of form: the quantities of a :class:`~hullopt.hydro.Hydrostatics` table (fields ``(k,)``, SI)
    against the draft T [m] (the vertical axis of every panel, as drawn by hand), grouped in eight panels
    by unit (Δ [t] with ∇ [m³] on the top axis at density ``rho`` [kg/m³]; areas [m²]; TPC [t/cm];
    MCT 1 cm [t·m/cm]; LCB, LCF [m from AP]; KB, KM_T [m]; BM_L [m]; C_B, C_P, C_M, C_WP). Drafts at or
    above ``depth`` [m] (the deck) are left out; ``design_draft`` [m] is marked as the DWL.

    Parameters
    ----------
    table : Hydrostatics
        Hydrostatics at k drafts (:func:`~hullopt.hydro.hydrostatics` over a draft array), fields (k,) SI.
    path : str or os.PathLike
        The figure file; its suffix picks the format (PNG, SVG, PDF).
    name : str
        The hull's name for the title.
    depth : float or None
        Depth to the deck [m]; drafts at or above it are left out. None: keep every draft.
    design_draft : float or None
        Design draft [m], marked as the DWL; None: no mark.
    rho : float
        Water density [kg/m³] for the ∇ axis.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    plt, fig, axes = _figure(2, 4, figsize=(15, 8), sharey=True)
    t = np.asarray(table.draft, dtype=float)
    keep = t < depth - TINY_LENGTH if depth is not None else np.ones(t.shape, bool)
    t = t[keep]
    for ax, (title, xlabel, curves) in zip(axes.flat, _HYDRO_PANELS):
        drawn = []
        for j, (key, label, s) in enumerate(curves):
            drawn.append(v := np.asarray(getattr(table, key), dtype=float)[keep] * s)
            ax.plot(v, t, lw=1.4, color=f"C{j}", label=label)
        _span_beyond_round_off(ax, np.concatenate(drawn))
        ax.set_title(title, fontsize=9, loc="left", pad=16 if curves[0][0] == "displacement" else 6)
        ax.set_xlabel(xlabel, fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
        if len(curves) > 1:
            ax.legend(fontsize=7, loc="best", frameon=True)
        if design_draft is not None:
            ax.axhline(float(design_draft), color="tab:green", lw=0.8, ls="-.")
        if key == "displacement":  # ∇ [m³] on the top axis: ∇ = Δ/ρ
            top = ax.secondary_xaxis("top", functions=(lambda d: d * 1e3 / rho, lambda v: v * rho / 1e3))
            top.set_xlabel("∇ [m³]", fontsize=8)
            top.tick_params(labelsize=7)
    for ax in axes[:, 0]:
        ax.set_ylabel("draft T [m]")
    if design_draft is not None:
        axes[0, 0].annotate(f"DWL {float(design_draft):.3g} m", (0.02, float(design_draft)),
                            xycoords=("axes fraction", "data"), xytext=(0, 2), textcoords="offset points",
                            fontsize=7, color="tab:green")
    fig.suptitle(f"Hydrostatic curves — {name}" if name else "Hydrostatic curves", x=0.01, ha="left")
    fig.tight_layout()
    return _save(plt, fig, path)


def _span_beyond_round_off(ax, v: np.ndarray) -> None:
    """A panel whose values are constant but for round-off (a symmetric hull's LCB) spans ±5 % of them, as
    matplotlib draws an exactly constant curve, not its last digits on an axis offset by the value."""
    v = v[np.isfinite(v)]
    if v.size and np.ptp(v) <= 1e-9 * max(np.abs(v).max(), 1.0):
        mid = float(np.mean(v))
        half = 0.05 * abs(mid) or 0.05
        ax.set_xlim(mid - half, mid + half)


def plot_gz(curve: GZCurve, path: str | os.PathLike, criteria: GZCriteria | None = None, name: str = "",
            rho: float = RHO_SEA, flooding_angle: float | None = None, weather: GZWeather | None = None) -> Path:
    """The GZ curve of a :class:`~hullopt.hydro.StabilityCurve`, the GM₀ tangent (GZ = GM₀·φ, drawn to
    1 rad) and, with ``criteria``, the maximum, the angle of vanishing stability and the 30°/40° marks; the
    flooding angle θf when given. With ``weather`` (IS Code §2.3) the levers lw1 and lw2, the steady heel φ0,
    the roll-back angle φ0 − φ1 (the curve continued to windward, GZ(−φ) = −GZ(φ)) and the areas a and b
    shaded; without it the §2.2 areas under GZ to 30° and from 30° to 40° (or θf) lightly shaded. The shading
    follows the drawn curve (straight between its heels); the legend gives the areas computed.

    Parameters
    ----------
    curve : StabilityCurve
        The GZ curve (:class:`~hullopt.hydro.StabilityCurve`: heel [rad], GZ [m], GM₀ [m], ∇ [m³], KG [m]).
    path : str or os.PathLike
        The figure file; its suffix picks the format (PNG, SVG, PDF).
    criteria : Criteria or None
        :class:`~hullopt.hydro.Criteria` of the curve (GZ max [m], its angle and the vanishing angle [rad]);
        None: no marks.
    name : str
        The hull's name for the title.
    rho : float
        Water density [kg/m³] for the displacement in the title (sea water by default).
    flooding_angle : float or None
        Downflooding angle θf [rad], marked; None: none.
    weather : Weather or None
        :class:`~hullopt.hydro.Weather` of the curve; None: no weather criterion.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    plt, fig, ax = _figure(figsize=(9, 5))
    deg = np.rad2deg(np.asarray(curve.heel, dtype=float))
    gz = np.asarray(curve.gz, dtype=float)
    ax.plot(deg, gz, "o-", ms=3, lw=1.5, color="tab:blue", label="GZ")
    gm0 = float(curve.gm0)
    ax.plot([0, 57.3], [0, gm0], "--", color="0.5", lw=1, label=f"GM₀ = {gm0:.3g} m")
    ax.axhline(0.0, color="black", lw=0.8)
    for a in (30, 40):
        ax.axvline(a, color="0.8", lw=0.8)
    if flooding_angle is not None:
        tf = float(np.rad2deg(flooding_angle))
        ax.axvline(tf, color="tab:purple", ls="--", lw=1, label=f"flooding angle θf = {tf:.1f}°")
    lo, hi = min(gz.min(), 0.0), max(gz.max(), gm0 * 0.1)
    if weather is None:
        end = 40.0 if flooding_angle is None else min(40.0, float(np.rad2deg(flooding_angle)))
        for a, b, alpha in ((0.0, 30.0, 0.10), (30.0, end, 0.18)):
            x = np.linspace(a, b, 61)
            ax.fill_between(x, np.interp(x, deg, gz), 0.0, color="tab:blue", alpha=alpha, lw=0)
    else:
        lo, hi = min(lo, _plot_weather(ax, deg, gz, weather)), max(hi, float(weather.lw2))
    if criteria is not None:
        ax.plot(np.rad2deg(float(criteria.angle_gz_max)), float(criteria.gz_max), "v", color="tab:red",
                label=f"GZmax {float(criteria.gz_max):.3g} m at {np.rad2deg(float(criteria.angle_gz_max)):.1f}°")
        v = float(criteria.vanishing_angle)
        if np.isfinite(v):
            ax.plot(np.rad2deg(v), 0.0, "x", color="tab:red", label=f"vanishing {np.rad2deg(v):.1f}°")
    span = max(abs(gz).max(), 1e-3)
    ax.set_ylim(lo * 1.1 - 0.05 * span, hi * 1.25)
    ax.set_xlabel("heel φ [deg]")
    ax.set_ylabel("GZ [m]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    disp = rho * float(curve.volume) / 1e3
    title = f"GZ curve — Δ {disp:,.0f} t, KG {float(curve.kg):.3g} m"
    ax.set_title(f"{title} — {name}" if name else title, loc="left", fontsize=10)
    return _save(plt, fig, path)


def _plot_weather(ax, deg: np.ndarray, gz: np.ndarray, w: GZWeather) -> float:
    """The weather criterion on the GZ axes: the curve continued to the roll-back angle, lw1, lw2, φ0 and
    the areas a (red) and b (green); returns the lowest GZ drawn [m]."""
    lw1, lw2 = float(w.lw1), float(w.lw2)
    roll, phi0, phic, phi2 = (float(np.rad2deg(getattr(w, k))) for k in ("phi_roll", "phi0", "phi_c", "phi2"))
    xs, ys = np.concatenate([-deg[:0:-1], deg]), np.concatenate([-gz[:0:-1], gz])  # GZ(−φ) = −GZ(φ)
    left = min(roll, 0.0) - 5.0
    back = (xs >= left) & (xs <= 0.0)
    ax.plot(xs[back], ys[back], "-", lw=1.2, color="tab:blue", alpha=0.6)
    ax.set_xlim(left, max(deg.max(), 50.0) + 2.0)
    ax.axhline(lw1, color="tab:orange", lw=1, ls="-.", label=f"lw1 = {lw1:.3f} m (steady wind)")
    gust = "gust" if bool(w.reaches_lw2) else "gust, above GZ: no area b"
    ax.axhline(lw2, color="tab:red", lw=1, ls="-.", label=f"lw2 = 1.5·lw1 = {lw2:.3f} m ({gust})")
    ax.axvline(0.0, color="black", lw=0.6)
    ax.plot([phi0], [lw1], "o", color="tab:orange", ms=4, label=f"φ0 = {phi0:.1f}° (steady heel)")
    ax.axvline(roll, color="tab:red", lw=0.8, ls=":",
               label=f"φ0 − φ1 = {roll:.1f}° (rolled to windward)".replace("= -", "= −"))
    ax.axvline(phi2, color="tab:green", lw=0.8, ls=":", label=f"φ2 = {phi2:.1f}° (end of area b)")
    xa = np.linspace(roll, phic, 200)
    ax.fill_between(xa, np.interp(xa, xs, ys), lw2, color="tab:red", alpha=0.3, lw=0,
                    label=f"area a = {float(w.area_a):.4f} m·rad")
    if phi2 > phic:
        xb = np.linspace(phic, phi2, 200)
        ax.fill_between(xb, np.interp(xb, xs, ys), lw2, color="tab:green", alpha=0.3, lw=0,
                        label=f"area b = {float(w.area_b):.4f} m·rad")
    return float(np.interp(roll, xs, ys))


def plot_cross_curves(displacements: Float[ArrayLike, ' k'], heels: Float[ArrayLike, ' h'], kn: Float[ArrayLike, 'k h'],
                      path: str | os.PathLike, name: str = "") -> Path:
    """Cross curves of stability: KN [m] against displacement [t] (``displacements (k,)``), one line per heel
    [rad] (``heels (h,)``, ``kn (k, h)``), each in its own colour and labelled at its end, the legend outside
    the axes.

    Parameters
    ----------
    displacements : (k,) array_like
        Displacements Δ [t].
    heels : (h,) array_like
        Heel angles [rad] (labelled in degrees).
    kn : (k, h) array_like
        KN [m] at each displacement and heel.
    path : str or os.PathLike
        The figure file; its suffix picks the format (PNG, SVG, PDF).
    name : str
        The hull's name for the title.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    plt, fig, ax = _figure(figsize=(9, 5.5))
    d = np.asarray(displacements)
    kn = np.asarray(kn)
    deg = np.rad2deg(np.asarray(heels))
    # one colour per heel from a perceptually ordered map (as many as there are heels, none repeated) and
    # the heel written at the line's end, so each curve reads without the legend
    colors = plt.get_cmap("turbo")(np.linspace(0.03, 0.97, max(len(deg), 2)))
    for j, h in enumerate(deg):
        ax.plot(d, kn[:, j], lw=1.3, color=colors[j], label=f"{h:g}°")
        ax.annotate(f"{h:g}°", (d[-1], kn[-1, j]), xytext=(3, 0), textcoords="offset points", fontsize=6,
                    va="center", color=colors[j])
    ax.set_xlabel("displacement Δ [t]")
    ax.set_ylabel("KN [m]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=1 if len(deg) <= 20 else 2, title="heel φ", loc="upper left",
              bbox_to_anchor=(1.06, 1.0), borderaxespad=0)
    ax.set_title(f"Cross curves — {name}" if name else "Cross curves", loc="left")
    return _save(plt, fig, path)
