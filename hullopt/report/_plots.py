"""Plots of design runs (matplotlib, Agg): body plans and sectional-area curves before/after, solver
convergence, Pareto fronts."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..drawing import save_figure, station_sections
from ._units import displayed, label


def _figure(*args, figsize=None, **kw):
    """``(fig, axes)``: a figure on matplotlib's Agg canvas, made without pyplot (its import and
    figure manager cost ~0.3 s of a run; :func:`hullopt.drawing.save_figure` closes pyplot's figures only)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize)
    FigureCanvasAgg(fig)
    return fig, fig.subplots(*args, **kw)


_SUPERSCRIPTS = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def _log_labels(*axes) -> None:
    """Label the log-scaled y axes as matplotlib's default does (decades as 10⁻⁵; between decades, where it
    labels them, 2×10⁻⁵) in plain text with Unicode superscripts: the default's mathtext parser costs ~0.2 s
    of a run's plots."""
    from matplotlib.ticker import LogFormatter

    class Plain(LogFormatter):
        def _num_to_string(self, x, vmin, vmax):
            e = int(np.floor(np.log10(x) + 1e-9))
            c = x / 10.0**e
            power = "10" + str(e).translate(_SUPERSCRIPTS)
            return power if abs(c - 1.0) < 1e-6 else f"{c:.3g}" if e == 0 else f"{c:.3g}×{power}"

    for ax in axes:
        ax.yaxis.set_major_formatter(Plain(labelOnlyBase=False))
        ax.yaxis.set_minor_formatter(Plain(labelOnlyBase=False, minor_thresholds=(1, 0.4)))


def _save(fig, path: Path) -> Path:
    return save_figure(fig, path, dpi=130, bbox_inches="tight")


def _draw_body_plan(ax, before, after, every: int | None, draft: float | None) -> None:
    """The body plan of :func:`plot_body_plans` on ``ax`` (no legend box, no title)."""
    lpp = float(after.lpp)
    mid = 0.5 * lpp
    top = max(float(np.max(np.asarray(s.yz)[..., 1])) for s in (before, after))
    for s, style in ((before, dict(color="0.55", lw=0.8, ls="--")), (after, dict(color="C0", lw=1.0))):
        if every:
            x, yz = np.asarray(s.x)[::every], np.asarray(s.yz)[::every]
        else:
            _, x, yz = station_sections(s, per_station=2)
        for i in range(len(x)):
            sign = 1.0 if x[i] >= mid else -1.0
            ax.plot(sign * yz[i, :, 0], yz[i, :, 1], **style)
            st = x[i] / lpp * 10.0
            if s is after and not every and abs(st - round(st)) < 1e-9:
                # the label above the section's deck edge, fore body right, aft body left
                ax.annotate(f"{round(st):d}", (sign * yz[i, -1, 0], yz[i, -1, 1]), xytext=(2 * sign, 3),
                            textcoords="offset points", ha="left" if sign > 0 else "right", va="bottom",
                            fontsize=7, color="C0")
    ax.plot([], [], color="0.55", ls="--", label="parent")
    ax.plot([], [], color="C0", label="design")
    if draft is not None:
        ax.axhline(float(draft), color="tab:green", lw=0.8, ls="-.", label=f"DWL T = {float(draft):.3g} m")
    ax.axvline(0, color="k", lw=0.5)
    ax.set_aspect("equal")
    ax.set_ylim(top=top * 1.08)
    ax.set_xlabel("half-breadth y [m]  (aft body ← | → fore body)")
    ax.set_ylabel("height above baseline z [m]")


def plot_body_plans(before, after, path: Path, every: int | None = None, title: str = "",
                    draft: float | None = None) -> Path:
    """Body plan of the parent (dashed grey) and the design (blue): aft body left, fore body right.

    As naval architects draw it: at the half stations (interpolated there; ``every``: every ``every``-th given
    section instead), integer station numbers written above the design's sections, the DWL at ``draft`` [m].

    Parameters
    ----------
    before : Sections
        The parent: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m], ``lpp`` [m].
    after : Sections
        The design, same layout; its ``lpp`` places midship and the station numbers.
    path : pathlib.Path
        The image file (PNG; :func:`hullopt.drawing.save_figure`).
    every : int or None
        Draw every ``every``-th given section (no station numbers); None: the half stations.
    title : str
        The title; empty: a default naming the station numbers 0 = AP … 10 = FP.
    draft : float or None
        The DWL's height [m above the baseline]; None: no DWL.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    fig, ax = _figure(figsize=(9, 6))
    _draw_body_plan(ax, before, after, every, draft)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0)
    ax.set_title(title or "Body plan: parent and design (station numbers 0 = AP … 10 = FP)", loc="left",
                 fontsize=10)
    return _save(fig, path)


def plot_convergence(history, path: Path, xlabel: str = "step", violation=None, title: str = "",
                     fit: bool = False) -> Path:
    """Solver convergence on log scales: above, what the solver minimises; below, ``violation``, the largest
    ``|residual| / tolerance`` (≤ 1 met, the line).

    A fit (``fit``): the cost (the sum of squared scaled residuals, the smoothness penalty included: it levels
    off above zero) at the start and after each step; the violation is what converges. A constrained minimum:
    ``history`` the objective alone after each round (scaled to 1 at the parent, drawn as round 0; the fairness
    and smoothness penalties the solver adds are the report's merit series). Non-finite entries (rounds or
    steps not taken) are left out.

    Parameters
    ----------
    history : array_like, (k,)
        The fit's cost at the start and after each step, or the scaled objective after each round [-].
    path : pathlib.Path
        The image file (PNG; :func:`hullopt.drawing.save_figure`).
    xlabel : str
        The x axis's label.
    violation : array_like, (k,) or None
        The largest constraint violation, as ``history`` [-]; None: the upper panel alone.
    title : str
        The title; empty: a default.
    fit : bool
        ``history`` is a fit's cost (no round 0 added).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    h = np.asarray(history, dtype=float)
    v = None if violation is None else np.asarray(violation, dtype=float)
    if not fit:  # round 0: the parent, where the objective is 1 by its scaling (the rounds read as the gain)
        h = np.concatenate([[1.0], h])
        v = None if v is None else np.concatenate([[np.nan], v])
    if v is None:
        fig, ax1 = _figure(figsize=(6.5, 4))
        ax2 = None
    else:
        fig, (ax1, ax2) = _figure(2, 1, figsize=(6.5, 5.5), sharex=True)
    it = np.arange(len(h))
    ok = np.isfinite(h)
    ax1.semilogy(it[ok], np.maximum(np.abs(h[ok]), 1e-300), ".-" if fit else "o-", ms=4, color="C0")
    _log_labels(ax1)
    fin = np.abs(h[np.isfinite(h)])
    if fin.size and fin.min() > 0 and fin.max() / fin.min() < 10:  # within a decade: plain numbers on the ticks
        from matplotlib.ticker import FuncFormatter

        span = fin.max() - fin.min()
        digits = max(3, int(np.ceil(-np.log10(span / fin.max()))) + 1) if span > 0 else 3
        plain = FuncFormatter(lambda v, _: f"{v:.{digits}g}")
        ax1.yaxis.set_major_formatter(plain)
        ax1.yaxis.set_minor_formatter(plain)
    ax1.set_ylabel("cost: Σ (scaled residual)² [-]" if fit else "objective / parent's [-]")
    ax1.grid(alpha=0.3, which="both")
    ax1.set_title(title or ("Convergence of the fit" if fit else "Convergence: objective and constraint violation"),
                  loc="left", fontsize=10)
    last = ax1
    if ax2 is not None:
        ok = np.isfinite(v)
        ax2.semilogy(it[ok], np.maximum(v[ok], 1e-16), "s-", ms=3 if fit else 4, color="C3",
                     label="max |target error| / tolerance" if fit else "max |residual| / tolerance")
        _log_labels(ax2)
        ax2.axhline(1.0, color="k", lw=0.8, ls="--", label="tolerance (≤ 1: targets met)")
        ax2.set_ylabel("max target error [-]" if fit else "max constraint violation [-]")
        ax2.grid(alpha=0.3, which="both")
        ax2.legend(fontsize=8, loc="upper right")
        last = ax2
    last.set_xlabel(xlabel)
    from matplotlib.ticker import MaxNLocator

    last.xaxis.set_major_locator(MaxNLocator(integer=True))  # steps and rounds are counted
    return _save(fig, path)


def _axis(name: str, about: dict | None = None) -> tuple[str, float]:
    """A report key's axis label with its unit, as the report's tables name it (a force in kN), and the factor
    from SI to that unit."""
    return label(name, about=about), displayed(name, 1.0)[0]


def plot_pareto(designs: list[dict], xname: str, yname: str, path: Path,
                parent: tuple[float, float, float] | None = None, conditions: str = "",
                about: dict | None = None) -> Path:
    """The Pareto front of a Bf sweep: ``yname`` (the objective) against ``xname`` (the measure), forces in kN.

    Each design is labelled with its Bf target to 4 significant digits (a label once per position); designs that
    miss their targets as crosses, dominated ones grey; the parent a black star, to read the designs against.

    Parameters
    ----------
    designs : list of dict
        The sweep's designs as in ``report.json``: ``measure`` and ``objective`` (SI), ``met``, ``bf_target`` and
        optionally ``pareto`` (on the front).
    xname : str
        The measure's report key (axis label and unit by :func:`label`).
    yname : str
        The objective's report key.
    path : pathlib.Path
        The image file (PNG; :func:`hullopt.drawing.save_figure`).
    parent : tuple of (float, float, float) or None
        ``(measure, objective, Bf)`` of the parent (SI); None: no parent drawn.
    conditions : str
        Where the two are measured (speeds, sea states: :func:`hullopt.study.conditions_text`), under the title.
    about : dict or None
        ``report.json``'s ``objective.about``: ``{"name": …, "measure": …}``, each the objective's
        :func:`~hullopt.report.objective_about`, so that the axes name what is plotted (an operating profile
        without sea states: calm-water R_T by its method). None: the keys' labels.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    fig, ax = _figure(figsize=(7.5, 5))
    xa, ya = (about or {}).get("measure"), (about or {}).get("name")
    (xlabel, sx), (ylabel, sy) = _axis(xname, xa), _axis(yname, ya)
    if parent is not None:
        px, py = parent[0] * sx, parent[1] * sy
        ax.plot([px], [py], "*", color="k", markersize=11, label="parent", zorder=4)
        ax.annotate(f"parent (Bf {parent[2]:.4g})", (px, py), xytext=(5, -10), textcoords="offset points",
                    fontsize=7, color="k")
    pts = np.array([[d["measure"] * sx, d["objective"] * sy] for d in designs]).reshape(-1, 2)
    front = np.array([d.get("pareto", False) for d in designs], dtype=bool)
    met = np.array([d["met"] for d in designs], dtype=bool)
    ax.scatter(pts[met & ~front, 0], pts[met & ~front, 1], color="0.6", label="dominated", zorder=2)
    if (~met).any():
        ax.scatter(pts[~met, 0], pts[~met, 1], marker="x", color="C3", label="targets not met", zorder=2)
    order = np.argsort(pts[front, 0])
    ax.plot(pts[front, 0][order], pts[front, 1][order], "o-", color="C0", label="Pareto front", zorder=3)
    seen = set()
    for d, (px, py) in zip(designs, pts):
        key = (f"{d['bf_target']:.3f}", f"{px:.4g}", f"{py:.4g}")
        if key in seen or not np.isfinite([px, py]).all():
            continue
        seen.add(key)
        ax.annotate(f"Bf {d['bf_target']:.4g}", (px, py), xytext=(4, 3), textcoords="offset points",
                    fontsize=7, color="0.25")
    ax.margins(0.08)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    ax.grid(alpha=0.3)
    bf = [d["bf_target"] for d in designs]
    span = f", Bf {min(bf):.4g} … {max(bf):.4g}" if bf else ""
    ax.set_title(f"Pareto front: {label(yname, unit=False, about=ya)} against {label(xname, unit=False, about=xa)}"
                 f"{span}\n"
                 + (f"{conditions}\n" if conditions else "")
                 + "(each design labelled with its bluntness target Bf)", loc="left", fontsize=9)
    return _save(fig, path)


def plot_resistance(records: list[dict], methods, path: Path, title: str = "") -> Path:
    """Calm-water R_T [kN] and P_E [MW] against speed [kn] and C_W against Fn, one curve per wave-resistance method.

    Parameters
    ----------
    records : list of dict
        One record a speed, as ``hullopt resistance --json`` prints them: ``speed_kn``, ``fn`` and, for each
        method ``<m>``, ``r_total_<m>`` [N], ``p_e_<m>`` [W] and ``c_w_<m>``.
    methods : sequence of str
        The wave-resistance methods to draw: ``"holtrop"``, ``"michell"``, ``"panel"``, ``"dawson"``.
    path : pathlib.Path
        The image file (PNG; :func:`hullopt.drawing.save_figure`).
    title : str
        The figure's title.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    fig, axes = _figure(1, 3, figsize=(14, 4.2))
    kn = [r["speed_kn"] for r in records]
    fn = [r["fn"] for r in records]
    names = {"holtrop": "Holtrop–Mennen", "michell": "Michell", "panel": "panel", "dawson": "Dawson"}
    for i, m in enumerate(methods):
        style = dict(color=f"C{i}", marker="o", ms=3, label=names[m])
        axes[0].plot(kn, [r[f"r_total_{m}"] / 1e3 for r in records], **style)
        axes[1].plot(kn, [r[f"p_e_{m}"] / 1e6 for r in records], **style)
        axes[2].plot(fn, [r[f"c_w_{m}"] * 1e3 for r in records], **style)
    for ax, (x, y) in zip(axes, (("speed [kn]", "R_T [kN]"), ("speed [kn]", "P_E [MW]"), ("Fn", "C_W × 10³"))):
        ax.set_xlabel(x)
        ax.set_ylabel(y)
        ax.grid(alpha=0.3)
    axes[0].legend(title="R_W by")
    axes[0].set_title("R_T = (1+k1)·R_F + R_APP + R_W + R_A", fontsize=9)
    axes[2].set_title("C_W = R_W / (½ρU²S)", fontsize=9)
    fig.suptitle(title)
    return _save(fig, path)


def plot_wave_pattern(x, y, zeta, lpp: float, path: Path, title: str = "", wake=None) -> Path:
    """The wave pattern ζ(x, y) [m] in plan view, port side up.

    The hull's waterline length is marked and the 19.47° Kelvin wedge from the bow dashed.

    Parameters
    ----------
    x : array_like, (nx,) or (nx, ny)
        Longitudinal positions [m from the AP], the ship moving to +x: a regular grid's, or each point's.
    y : array_like, (ny,) or (nx, ny)
        Transverse positions [m] (port up), likewise; the axis spans their range.
    zeta : array_like, (nx, ny)
        Wave elevation [m].
    lpp : float
        The hull's length [m]: the bow at ``x = lpp``.
    path : pathlib.Path
        The image file (PNG; :func:`hullopt.drawing.save_figure`).
    title : str
        The title.
    wake : tuple of three (nw, nr) array_like, optional
        A second curvilinear grid's x, y, ζ [m] drawn alike (Dawson's wake grid behind a transom).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    fig, ax = _figure(figsize=(11, 4.5))
    m = float(np.percentile(np.abs(zeta), 99.5)) or 1.0
    x, y, zeta = np.asarray(x), np.asarray(y), np.asarray(zeta)
    if x.ndim == 2:  # a curvilinear grid (Dawson's, body-fitted)
        im = ax.pcolormesh(x, y, zeta, cmap="RdBu_r", vmin=-m, vmax=m, shading="gouraud")
        if wake is not None:
            ax.pcolormesh(*(np.asarray(a) for a in wake), cmap="RdBu_r", vmin=-m, vmax=m, shading="gouraud")
    else:
        im = ax.pcolormesh(x, y, zeta.T, cmap="RdBu_r", vmin=-m, vmax=m, shading="auto")
    ax.plot([0.0, lpp], [0.0, 0.0], color="k", lw=4, solid_capstyle="butt")
    xs = np.linspace(x.min(), min(x.max(), lpp), 50)
    ax.plot(xs, np.tan(np.radians(19.47)) * (lpp - xs), "k--", lw=0.7, label="Kelvin wedge 19.47°")
    ax.set_aspect("equal")
    ax.set_xlim(x.min(), x.max())
    ax.set_ylim(min(0.0, float(y.min())), float(y.max()))
    ax.set_xlabel("x from the AP [m] (the ship moves to the right)")
    ax.set_ylabel("y [m]")
    ax.legend(loc="upper right", fontsize=8)
    fig.colorbar(im, ax=ax, label="wave elevation ζ [m]", shrink=0.8)
    ax.set_title(title, fontsize=10)
    return _save(fig, path)


def plot_overlay(before, after, draft: float, path: Path, title: str = "", measures=None) -> Path:
    """A design against its parent in one figure, as a naval architect checks it: the body plan (left), the
    waterlines' half-breadths at the heights of :data:`~hullopt.fairing.WATERLINE_FRACTIONS` of the draft
    and :data:`~hullopt.fairing.WATERLINES_ABOVE` above the DWL, dotted (top right: where a bow change above the water shows) and the sectional-area curve with the design's change (bottom right); the parent dashed.

    Parameters
    ----------
    before, after : Sections
        The parent and the design: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m], ``lpp`` [m].
    draft : float
        The DWL [m above the baseline].
    path : pathlib.Path
        The image file (PNG).
    title : str
        The figure's title; empty: a default.
    measures : tuple, optional
        ``(areas, levels, widths)`` where the caller has them (a run's :class:`~hullopt.study.Outcome`): the
        sectional areas ``(2, n)`` [m²] of parent and design at ``draft``, and their waterlines
        (:func:`hullopt.fairing.waterlines`: heights ``(h,)`` [m], half-breadths ``(2, n, h)`` [m]); computed
        here when not.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    import jax

    fig = _figure(figsize=(15, 6.5))[0]
    fig.clear()
    grid = fig.add_gridspec(2, 2, width_ratios=(1.0, 1.35), hspace=0.32, wspace=0.12)
    ax_bp, ax_wl, ax_a = fig.add_subplot(grid[:, 0]), fig.add_subplot(grid[0, 1]), fig.add_subplot(grid[1, 1])
    _draw_body_plan(ax_bp, before, after, None, draft)
    # below the plot: inside it the legend hid the aft stations' numbers along the top
    ax_bp.legend(loc="upper center", bbox_to_anchor=(0.5, -0.08), ncol=3, fontsize=8, frameon=False)
    ax_bp.set_title("Body plan", loc="left", fontsize=10)
    areas, z, widths = jax.tree.map(np.asarray, measures or _overlay_measures(before, after, float(draft)))
    dry = z > float(draft) + 1e-9  # above the DWL: dotted, so that the wetted lines read first
    for s, y, style in ((before, widths[0], dict(ls="--", lw=0.9)), (after, widths[1], dict(lw=1.1))):
        for k in range(len(z)):
            ax_wl.plot(np.asarray(s.x), y[:, k], color=f"C{k}", **(style | (dict(ls=":") if dry[k] and s is after else {})))
    for k, zk in enumerate(z):
        ax_wl.plot([], [], color=f"C{k}", ls=":" if dry[k] else "-",
                   label=f"z = {zk:.2f} m" + (" (DWL)" if abs(zk - float(draft)) < 1e-6 else " (above)" * bool(dry[k])))
    ax_wl.plot([], [], color="0.4", ls="--", label="parent (dashed)")
    ax_wl.set_ylabel("half-breadth y [m]")
    ax_wl.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, borderaxespad=0)
    ax_wl.grid(alpha=0.3)
    ax_wl.set_title("Waterlines", loc="left", fontsize=10)
    ax_a.plot(np.asarray(before.x), areas[0], color="0.55", ls="--", label="parent")
    ax_a.plot(np.asarray(after.x), areas[1], color="C0", label="design")
    diff = areas[1] - np.interp(np.asarray(after.x), np.asarray(before.x), areas[0])
    twin = ax_a.twinx()
    twin.plot(np.asarray(after.x), diff, color="C3", lw=0.8, label="design − parent")
    twin.axhline(0.0, color="C3", lw=0.4)
    twin.set_ylabel("change [m²]", color="C3")
    ax_a.set_xlabel("x from AP [m]")
    ax_a.set_ylabel(f"sectional area at T = {float(draft):g} m [m²]")
    lines = ax_a.get_legend_handles_labels()
    more = twin.get_legend_handles_labels()
    ax_a.legend(lines[0] + more[0], lines[1] + more[1], fontsize=8, loc="upper left")
    ax_a.grid(alpha=0.3)
    ax_a.set_title("Sectional-area curve", loc="left", fontsize=10)
    fig.suptitle(title or "Design against its parent", x=0.02, ha="left", fontsize=11)
    return _save(fig, path)


def _overlay_measures(before, after, draft: float) -> tuple:
    """What :func:`plot_overlay` draws of two hulls, as a run's program measures it (one jitted program each,
    not the ~30 eager operations, a second, they are op by op)."""
    import jax

    from ..fairing import WATERLINES_ABOVE, waterlines
    from ..hydro import sectional_areas

    areas = [jax.jit(sectional_areas)(s, draft) for s in (before, after)]
    z, widths = jax.jit(waterlines, static_argnums=2)([before, after], draft, WATERLINES_ABOVE)
    return areas, z, widths


def _non_dominated(points: np.ndarray) -> np.ndarray:
    """``(k,)`` bool: rows of ``points (k, 2)`` (both minimised) that no other row beats in one and matches in both."""
    le = np.all(points[:, None, :] <= points[None, :, :], axis=-1)
    lt = np.any(points[:, None, :] < points[None, :, :], axis=-1)
    return ~np.any(le & lt, axis=0)


def plot_rescored_fronts(rescored: dict, path: Path, met: list[bool] | None = None) -> Path:
    """The designs and the parent under each pair of methods of a re-scoring (``report.json``'s ``rescored``):
    a panel per calm-water method (rows) and added-resistance method (columns), each design's R_AW against its
    R_T [kN] at the profile, labelled with its number; the designs non-dominated under that pair (parent
    included) joined. A front that one pair of methods draws and another does not is no front to sign.

    Parameters
    ----------
    rescored : dict
        ``methods``: per method (``calm_holtrop`` …, ``waves_nmri`` …) its ``kind``, ``method``, ``parent`` and
        ``designs`` [N].
    path : pathlib.Path
        The image file (PNG).
    met : list of bool or None
        Per design whether it met its targets (those that did not are crosses, off every front); None: all met.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    methods = rescored["methods"]
    calm = [m for m in methods.values() if m["kind"] == "calm"]
    waves = [m for m in methods.values() if m["kind"] == "waves"]
    fig, axes = _figure(len(calm), len(waves), figsize=(3.6 * len(waves) + 0.6, 3.0 * len(calm) + 0.8),
                        squeeze=False)
    n = len(calm[0]["designs"])
    ok = np.ones(n, bool) if met is None else np.asarray(met, bool)
    for i, c in enumerate(calm):
        for j, w in enumerate(waves):
            ax = axes[i, j]
            pts = 1e-3 * np.array([[w["parent"], c["parent"]]] + [[a, b] for a, b in zip(w["designs"], c["designs"])])
            keep = np.concatenate([[True], ok])
            front = np.zeros(n + 1, bool)
            front[keep] = _non_dominated(pts[keep])
            order = np.argsort(pts[front, 0])
            ax.plot(pts[front, 0][order], pts[front, 1][order], "-", color="C0", lw=0.8, zorder=1)
            ax.scatter(pts[1:][ok & front[1:], 0], pts[1:][ok & front[1:], 1], color="C0", s=18, zorder=3)
            ax.scatter(pts[1:][ok & ~front[1:], 0], pts[1:][ok & ~front[1:], 1], color="0.6", s=18, zorder=2)
            ax.scatter(pts[1:][~ok, 0], pts[1:][~ok, 1], marker="x", color="C3", s=18, zorder=2)
            ax.plot(pts[0, 0], pts[0, 1], "*", color="k", markersize=10, zorder=4)
            for k in range(n):
                ax.annotate(str(k), pts[k + 1], xytext=(3, 2), textcoords="offset points", fontsize=7, color="0.25")
            ax.grid(alpha=0.3)
            ax.margins(0.12)
            for values, limits in ((pts[:, 0], ax.set_xlim), (pts[:, 1], ax.set_ylim)):
                mid = float(np.mean(values))
                if np.ptp(values) < 1e-4 * abs(mid):  # a method blind to the change: no offset ticks
                    limits(mid - 0.005 * abs(mid), mid + 0.005 * abs(mid))
            if i == len(calm) - 1:
                ax.set_xlabel(f"R_AW by {w['method'].upper()} [kN]")
            if j == 0:
                ax.set_ylabel(f"R_T by {c['method']} [kN]"
                              + ("\n(outside its validity)" if c.get("outside_validity") else ""))
            ax.tick_params(labelsize=7)
    fig.suptitle("The designs (numbered) and the parent (★) under each pair of methods; blue: non-dominated under "
                 "that pair, grey: dominated, ×: targets not met", x=0.01, ha="left", fontsize=10)
    return _save(fig, path)


def plot_patent(bf: list[float], beam: list[float], fn: list[float], path: Path, met: list[bool] | None = None,
                rescored: dict | None = None, names: list[str] | None = None) -> Path:
    """A bluntness sweep in the patent's form (JP2009-286166 Figs 10–13, the claim-3 table): the short-wave
    K_AW = Bf·(1 + C_U·Fn), C_U = max(68 − 310·Bf, 10) (α_T → 1, exact max) against Bf, and ½ρgζ_a²B·K_AW
    [kN, per m² of ζ_a²] against B·Bf [m], a curve per Froude number of the profile with the parent (★) and
    each design on it; the kink (Bf 0.1871) and the patent's windows (0.04–0.187 slender → 0.12–0.32) shaded.
    With ``rescored`` (``report.json``'s) a third panel: the profile's mean R_AW of each design against its Bf
    by every re-scoring method — what the sea states give, motion part included, and who sees the gain.

    Parameters
    ----------
    bf, beam : list of float
        Bf (head seas, dimensionless) and waterline breadth B [m], the parent first, then each design.
    fn : list of float
        The profile's Froude numbers (on Lpp), one curve each.
    path : pathlib.Path
        The image file (PNG).
    met : list of bool or None
        Per design whether it met its targets (crosses where not); None: all met.
    rescored : dict or None
        ``methods`` per method: ``kind``, ``method``, ``parent`` and ``designs`` [N].
    names : list of str or None
        A label per design (default its index).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    from ..constants import G, RHO_SEA

    bf, beam = np.asarray(bf, float), np.asarray(beam, float)
    n = len(bf) - 1
    ok = np.ones(n, bool) if met is None else np.asarray(met, bool)
    names = names or [str(k) for k in range(n)]
    waves = [m for m in (rescored or {}).get("methods", {}).values() if m["kind"] == "waves"]
    fig, axes = _figure(1, 3 if waves else 2, figsize=(16 if waves else 11, 4.6))
    grid = np.linspace(0.0, max(0.35, float(bf.max()) * 1.1), 400)
    k_of = lambda b, f: b * (1.0 + np.maximum(68.0 - 310.0 * b, 10.0) * f)  # noqa: E731 - patent eq. 2, α_T = 1
    q = 0.5 * RHO_SEA * G * 1e-3  # ½ρg [kN/m³]: ½ρgζ²B·K per m² of ζ_a² and m of B
    for i, f in enumerate(fn):
        style = dict(color=f"C{i}", lw=1.0)
        axes[0].plot(grid, k_of(grid, f), label=f"Fn {f:.3f}", **style)
        axes[1].plot(grid * beam[0], q * beam[0] * k_of(grid, f), **style)
        for ax, x, y in ((axes[0], bf, k_of(bf, f)), (axes[1], bf * beam, q * beam * k_of(bf, f))):
            ax.plot(x[0], y[0], "*", color="k", markersize=11, zorder=4)
            ax.scatter(x[1:][ok], y[1:][ok], color=f"C{i}", s=22, zorder=3, edgecolor="k", lw=0.4)
            ax.scatter(x[1:][~ok], y[1:][~ok], color=f"C{i}", marker="x", s=22, zorder=3)
    for k in range(n):
        axes[0].annotate(names[k], (bf[k + 1], k_of(bf[k + 1], fn[0])), xytext=(3, 4), textcoords="offset points",
                         fontsize=7, color="0.25")
    for ax, scale in ((axes[0], 1.0), (axes[1], beam[0])):
        ax.axvline(58.0 / 310.0 * scale, color="0.4", ls="--", lw=0.8)
        ax.axvspan(0.04 * scale, 0.187 * scale, color="C3", alpha=0.06, lw=0)
        ax.axvspan(0.12 * scale, 0.32 * scale, color="C2", alpha=0.08, lw=0)
        ax.grid(alpha=0.3)
    axes[0].set_xlabel("Bf (head seas, at the DWL)")
    axes[0].set_ylabel("K_AW in short waves (α_T → 1)")
    axes[0].legend(fontsize=7, title="patent eq. 2", title_fontsize=7)
    axes[0].set_title("K_AW = Bf·(1 + C_U·Fn); kink at Bf 0.1871 (dashed);\nshaded: slender 0.04–0.187 (red), "
                      "re-set 0.12–0.32 (green)", fontsize=8, loc="left")
    axes[1].set_xlabel("B·Bf [m]")
    axes[1].set_ylabel("½ρgζ_a²B·K_AW [kN per m² of ζ_a²]")
    axes[1].set_title(f"the claim-3 table's axes (B of the parent, {beam[0]:.2f} m, for the curves)", fontsize=8,
                      loc="left")
    if waves:
        ax = axes[2]
        for j, m in enumerate(waves):
            y = 1e-3 * np.asarray([m["parent"], *m["designs"]], float)
            ax.plot(bf[0], y[0], "*", color=f"C{j}", markeredgecolor="k", markersize=12, zorder=4)
            order = np.argsort(bf[1:][ok])
            ax.plot(bf[1:][ok][order], y[1:][ok][order], "o-", color=f"C{j}", ms=4, lw=1.0,
                    label=m["method"].upper() + (" (the run's)" if m.get("own") else ""))
            ax.scatter(bf[1:][~ok], y[1:][~ok], marker="x", color=f"C{j}", s=22)
        ax.axvline(58.0 / 310.0, color="0.4", ls="--", lw=0.8)
        ax.set_xlabel("Bf (head seas, at the DWL)")
        ax.set_ylabel("profile mean R_AW [kN]")
        ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
        ax.set_title("the profile's sea states (motion part included), by each method (★ the parent):\nonly "
                     "NMRI's C_U sees the patent's mechanism", fontsize=8, loc="left")
    return _save(fig, path)
