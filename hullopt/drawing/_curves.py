"""Hydrostatic curves, the GZ curve and the cross curves (KN) as figures (matplotlib, Agg): PNG, SVG, PDF."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ._save import save_figure


def _figure(*args, **kw):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt, *plt.subplots(*args, **kw)


def _save(plt, fig, path) -> Path:
    return save_figure(fig, path, dpi=150, bbox_inches="tight")


# (field of Hydrostatics, label, scale for display)
_HYDRO_CURVES = [
    ("displacement", "Δ [1000 t]", 1e-6), ("volume", "∇ [1000 m³]", 1e-3), ("lcb", "LCB [m from AP]", 1.0),
    ("lcf", "LCF [m from AP]", 1.0), ("kb", "KB [m]", 1.0), ("kmt", "KM_T [m]", 1.0), ("bml", "BM_L [10 m]", 0.1),
    ("tpc", "TPC [t/cm]", 1.0), ("mct", "MCT 1 cm [100 t·m/cm]", 0.01), ("awp", "Awp [100 m²]", 0.01),
    ("wetted_surface", "S [100 m²]", 0.01), ("cb", "Cb [0.01]", 100.0),
]


def plot_hydrostatic_curves(table, path: str | os.PathLike, name: str = "") -> Path:
    """Curves of form: each quantity of a :class:`~hullopt.hydro.Hydrostatics` table (fields ``(k,)``)
    against the draft (vertical axis, as drawn by hand), scaled to share one horizontal axis."""
    plt, fig, ax = _figure(figsize=(9, 6))
    t = np.asarray(table.draft)
    for key, label, s in _HYDRO_CURVES:
        v = np.asarray(getattr(table, key)) * s
        (line,) = ax.plot(v, t, lw=1.2)
        ax.annotate(label, (v[-1], t[-1]), fontsize=7, color=line.get_color(), xytext=(2, 2),
                    textcoords="offset points")
    ax.set_ylabel("draft T [m]")
    ax.set_xlabel("value (units in each label)")
    ax.grid(alpha=0.3)
    ax.set_title(f"Hydrostatic curves — {name}" if name else "Hydrostatic curves", loc="left")
    return _save(plt, fig, path)


def plot_gz(curve, path: str | os.PathLike, criteria=None, name: str = "") -> Path:
    """The GZ curve of a :class:`~hullopt.hydro.StabilityCurve`, the GM₀ tangent (GZ = GM₀·φ, drawn to
    1 rad) and, with ``criteria``, the maximum, the angle of vanishing stability and the 30°/40° marks."""
    plt, fig, ax = _figure(figsize=(8, 5))
    deg = np.rad2deg(np.asarray(curve.heel))
    gz = np.asarray(curve.gz)
    ax.plot(deg, gz, "o-", ms=3, lw=1.5, label="GZ")
    gm0 = float(curve.gm0)
    ax.plot([0, 57.3], [0, gm0], "--", color="0.5", lw=1, label=f"GM₀ = {gm0:.3g} m")
    ax.axhline(0.0, color="black", lw=0.8)
    for a in (30, 40):
        ax.axvline(a, color="0.8", lw=0.8)
    if criteria is not None:
        ax.plot(np.rad2deg(float(criteria.angle_gz_max)), float(criteria.gz_max), "v", color="tab:red",
                label=f"GZmax {float(criteria.gz_max):.3g} m at {np.rad2deg(float(criteria.angle_gz_max)):.1f}°")
        v = float(criteria.vanishing_angle)
        if np.isfinite(v):
            ax.plot(np.rad2deg(v), 0.0, "x", color="tab:red", label=f"vanishing {np.rad2deg(v):.1f}°")
    ax.set_ylim(min(gz.min(), 0.0) * 1.1 - 0.05 * abs(gz).max(), max(gz.max(), gm0 * 0.1) * 1.25)
    ax.set_xlabel("heel φ [deg]")
    ax.set_ylabel("GZ [m]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    title = f"GZ curve — ∇ {float(curve.volume):,.0f} m³, KG {float(curve.kg):.3g} m"
    ax.set_title(f"{title} — {name}" if name else title, loc="left", fontsize=10)
    return _save(plt, fig, path)


def plot_cross_curves(displacements, heels, kn, path: str | os.PathLike, name: str = "") -> Path:
    """Cross curves of stability: KN [m] against displacement [t], one line per heel [rad]."""
    plt, fig, ax = _figure(figsize=(8, 5))
    d = np.asarray(displacements)
    kn = np.asarray(kn)
    for j, h in enumerate(np.rad2deg(np.asarray(heels))):
        ax.plot(d, kn[:, j], lw=1.2, label=f"{h:g}°")
    ax.set_xlabel("displacement Δ [t]")
    ax.set_ylabel("KN [m]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, ncol=2, title="heel")
    ax.set_title(f"Cross curves — {name}" if name else "Cross curves", loc="left")
    return _save(plt, fig, path)
