"""Plots of design runs (matplotlib, Agg): body plans and sectional-area curves before/after, solver
convergence, Pareto fronts."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..drawing import save_figure


def _figure(*args, **kw):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt, *plt.subplots(*args, **kw)


def _save(plt, fig, path: Path) -> Path:
    return save_figure(fig, path, dpi=130, bbox_inches="tight")


def plot_body_plans(before, after, path: Path, every: int | None = None) -> Path:
    """Body plan (aft body left, fore body right, as drawn by naval architects), parent dashed."""
    plt, fig, ax = _figure(figsize=(8, 5))
    x = np.asarray(after.x)
    mid = 0.5 * float(after.lpp)
    every = every or max(1, len(x) // 20)
    for s, style in ((before, dict(color="0.6", lw=0.8, ls="--")), (after, dict(color="C0", lw=1.0))):
        yz = np.asarray(s.yz)
        for i in range(0, len(x), every):
            sign = 1.0 if x[i] >= mid else -1.0
            ax.plot(sign * yz[i, :, 0], yz[i, :, 1], **style)
    ax.plot([], [], color="0.6", ls="--", label="parent")
    ax.plot([], [], color="C0", label="design")
    ax.axvline(0, color="k", lw=0.5)
    ax.set_aspect("equal")
    ax.set_xlabel("half-breadth y [m] (aft body left, fore body right)")
    ax.set_ylabel("z [m]")
    ax.legend(loc="lower right")
    return _save(plt, fig, path)


def plot_sectional_areas(x_before, x_after, areas, draft, path: Path) -> Path:
    """Sectional-area curves of the parent (dashed) and the design: ``areas (2, n)`` [m²] at stations
    ``x_before``, ``x_after (n,)`` [m from AP]."""
    plt, fig, ax = _figure(figsize=(8, 4))
    for x, a, label, style in ((x_before, areas[0], "parent", dict(color="0.6", ls="--")),
                               (x_after, areas[1], "design", dict(color="C0"))):
        ax.plot(np.asarray(x), np.asarray(a), label=label, **style)
    ax.set_xlabel("x from AP [m]")
    ax.set_ylabel(f"sectional area at T = {float(draft):g} m [m²]")
    ax.legend()
    ax.grid(alpha=0.3)
    return _save(plt, fig, path)


def plot_convergence(history, path: Path, xlabel: str = "step") -> Path:
    """The solver's cost after each step (or round), log scale."""
    plt, fig, ax = _figure(figsize=(6, 4))
    if len(history):
        ax.semilogy(np.arange(len(history)), np.maximum(history, 1e-300), marker=".")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("cost (sum of squared scaled residuals)" if xlabel == "step" else "augmented Lagrangian")
    ax.grid(alpha=0.3)
    return _save(plt, fig, path)


def _label(name: str) -> str:
    """An objective's axis label with its unit from its class (none for a coefficient)."""
    from ..optimise import OBJECTIVES

    unit = OBJECTIVES[name].unit if name in OBJECTIVES else "-"
    return name.replace("_", " ") + (f" [{unit}]" if unit != "-" else "")


def plot_pareto(designs: list[dict], xname: str, yname: str, path: Path) -> Path:
    plt, fig, ax = _figure(figsize=(6, 4.5))
    pts = np.array([[d["measure"], d["objective"]] for d in designs])
    front = np.array([d["pareto"] for d in designs])
    met = np.array([d["met"] for d in designs])
    ax.scatter(pts[met & ~front, 0], pts[met & ~front, 1], color="0.6", label="dominated")
    ax.scatter(pts[~met, 0], pts[~met, 1], marker="x", color="C3", label="targets not met")
    order = np.argsort(pts[front, 0])
    ax.plot(pts[front, 0][order], pts[front, 1][order], "o-", color="C0", label="Pareto front")
    for d in designs:
        ax.annotate(f"{d['bf_target']:.2f}", (d["measure"], d["objective"]), fontsize=7, alpha=0.7)
    ax.set_xlabel(_label(xname))
    ax.set_ylabel(_label(yname))
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    ax.set_title("labels: Bf")
    return _save(plt, fig, path)
