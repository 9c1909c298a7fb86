"""``report.html``: a run folder as one page a naval architect can open offline or send.

The page is self-contained: plotly's JavaScript bundle (the ``plotly`` package's own copy) is embedded once in
its ``<head>`` and every figure is drawn from data embedded beside it, so it opens with no network. It shows

* the run: kind, convergence, steps, the largest constraint violation, and the report's warnings;
* an interactive 3D view of the parent and the design hull(s) (plotly ``Mesh3d`` of both sides of the hull's
  surface grid, :func:`hullopt.geometry.surface_grid`), the body plan and the sectional-area curves at the
  draft;
* the targets (wanted, achieved, error, tolerance, met), the particulars and objectives parent → design, each
  with its unit (:mod:`hullopt.report`'s units: resistances in kN, displacement in t);
* convergence: each series the run recorded (``report.json``'s ``history``) against the iteration, log scale;
* for a sweep, the Pareto front (in kN) with each design's Bf to 3 decimals on hover, and a table of designs
  linking to their hull files (``designs/<k>/hull.stl``) where the folder has them.

It is written at the end of ``hullopt run`` and ``hullopt merge`` (:func:`write_report` with the hulls the run
has in memory) and rebuilt by ``hullopt report RUN_DIR``, which rebuilds the hulls from ``config.json``,
``parent.json`` and ``report.json`` as a run-folder hull spec does (never from the mesh).
"""

from __future__ import annotations

import hashlib
import html
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..drawing import station_sections
from ..errors import HullError
from ..geometry import Sections, atomic_write_bytes, grid_triangles, surface_grid
from ..hydro import sectional_areas
from ..optimise import TARGETS
from ..study import (
    VIOLATION,
    cached_call,
    folder_study,
    params_from_dict,
    read_run_config,
    stack_params,
    structure,
)
from ._units import displayed, fmt, label, quantity, to_builtin, unit_scale

REPORT_NAME = "report.html"
PAGE_TEMPLATE = "plotly_white"  # plotly's template of every figure on the page
MAX_SWEEP_HULLS = 8  # a sweep's page draws at most this many designs in 3D (evenly picked along the front)
PARENT_COLOUR, DESIGN_COLOURS = "#7f7f7f", ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b",
                                            "#e377c2", "#17becf")


@dataclass
class Hulls:
    """The hulls a report draws: the parent and its designs at the draft [m] (sections and their
    sectional-area curves [m²], numpy). ``designs``: ``(name, sections, areas)``; a sweep's names are
    ``design k``."""

    draft: float
    parent: Sections
    parent_areas: np.ndarray
    designs: list[tuple[str, Sections, np.ndarray]] = field(default_factory=list)

    @classmethod
    def of(cls, parent: Sections, design: Sections, areas, draft) -> Hulls:
        """A run's parent and design with their sectional-area curves ``areas (2, n)`` [m²] at ``draft``."""
        areas = np.asarray(areas, float)
        return cls(float(draft), _numpy(parent), areas[0], [("design", _numpy(design), areas[1])])


def _numpy(s: Sections) -> Sections:
    return Sections(np.asarray(s.x, float), np.asarray(s.yz, float), np.asarray(s.lpp, float))


def run_hulls(folder: Path, report: dict) -> Hulls:
    """Rebuild the parent and the design hulls of a run folder, in one jitted program.

    From its config, its kept ``parent.json`` and the parameters in its report (a sweep: the designs on the front,
    at most :data:`MAX_SWEEP_HULLS`, :func:`sweep_picks`).

    Parameters
    ----------
    folder : pathlib.Path
        The run folder (its ``config.json`` and, when kept, ``parent.json`` are read).
    report : dict
        The run's report (``report.json``): ``params``, or a sweep's ``designs`` with theirs.

    Returns
    -------
    Hulls
        The parent and the designs at the run's draft [m], with their sectional-area curves [m²] (numpy).

    Raises
    ------
    HullError
        When the folder's files do not fit each other (a config that is not a run config, params that do not fit
        the design).
    """
    import jax

    cfg = read_run_config(folder)
    prob = folder_study(folder, cfg).problem
    picked = sweep_picks(report) if "designs" in report else []
    if "designs" in report:
        values = [report["designs"][k]["params"] for k in picked]
        names = [f"design {k}" for k in picked]
    elif "params" in report:
        values, names = [report["params"]], ["design"]
    else:
        values, names = [], []
    params = [prob.p0] + [params_from_dict(v, prob.p0) for v in values]
    stacked = stack_params(params)
    draft = float(prob.design.draft)

    # the program's key: the config's structure and the parent's content (the draft is an argument)
    digest = hashlib.sha256(json.dumps(prob.design.model.hull.to_dict(), sort_keys=True).encode()).hexdigest()
    sections, areas = jax.device_get(cached_call("report", _evaluate, (prob.design.model, stacked,
                                                                       np.asarray(draft)), (),
                                                 key=[structure(cfg), digest], quick=True))
    one = [_numpy(jax.tree.map(lambda a, i=i: a[i], sections)) for i in range(len(params))]
    areas = np.asarray(areas)
    return Hulls(draft, one[0], areas[0], [(n, s, a) for n, s, a in zip(names, one[1:], areas[1:])])


def _evaluate(model, params, draft):
    """The sections and sectional-area curves [m²] of a model at stacked parameters, each at its own draft
    (``draft`` [m] the parent's, times the model's draft factor: a draft scale)."""
    import jax

    s = jax.vmap(model)(params)
    return s, jax.vmap(lambda one, p: sectional_areas(one, draft * model.draft_factor(p)))(s, params)


def sweep_picks(report: dict) -> list[int]:
    """The designs of a sweep whose hulls the page draws.

    Those on the Pareto front (else those that meet their targets, else all), at most :data:`MAX_SWEEP_HULLS`,
    evenly spaced in Bf; only designs with ``params``.

    Parameters
    ----------
    report : dict
        A run's report; a sweep's has ``designs`` (each with ``pareto``, ``met`` and ``params``).

    Returns
    -------
    list of int
        The picked designs' indices in ``report["designs"]``, ascending; empty without designs.
    """
    designs = report.get("designs", [])
    for keep in (lambda d: d.get("pareto") and d.get("met"), lambda d: d.get("met"), lambda d: True):
        ks = [k for k, d in enumerate(designs) if keep(d) and d.get("params")]
        if ks:
            break
    else:
        return []
    if len(ks) > MAX_SWEEP_HULLS:
        ks = [ks[round(i)] for i in np.linspace(0, len(ks) - 1, MAX_SWEEP_HULLS)]
    return ks


# ----------------------------------------------------------------------------------------------- figures


def _figure(title: str, **layout):
    import plotly.graph_objects as go

    fig = go.Figure()
    fig.update_layout(title=dict(text=title, x=0.02), template=PAGE_TEMPLATE, margin=dict(l=60, r=20, t=50, b=50),
                      legend=dict(orientation="h", yanchor="bottom", y=1.0, xanchor="right", x=1.0), **layout)
    return fig


def _hull_surface(s: Sections) -> tuple[np.ndarray, np.ndarray]:
    """Vertices ``(2·n·m, 3)`` [m] and triangles of both sides of the hull (the port grid and its mirror
    image), float32 and int32 for the page; the deck and the end sections left open (a view, not a solid)."""
    g = np.asarray(surface_grid(s, np), np.float32)
    n, m, _ = g.shape
    tri = grid_triangles(n, m)
    verts = np.concatenate([g.reshape(-1, 3), (g * np.array([1, -1, 1], np.float32)).reshape(-1, 3)])
    faces = np.concatenate([tri, tri[:, ::-1] + n * m]).astype(np.int32)
    return verts, faces


def _hull_trace(s: Sections, name: str, colour: str, opacity: float, visible: Any = True):
    import plotly.graph_objects as go

    v, f = _hull_surface(s)
    return go.Mesh3d(x=v[:, 0], y=v[:, 1], z=v[:, 2], i=f[:, 0], j=f[:, 1], k=f[:, 2], name=name, color=colour,
                     opacity=opacity, flatshading=False, showlegend=True, visible=visible, hoverinfo="name",
                     lighting=dict(ambient=0.45, diffuse=0.8, specular=0.15, roughness=0.8),
                     lightposition=dict(x=-3e4, y=6e4, z=1e5))


def _colour(i: int) -> str:
    return DESIGN_COLOURS[i % len(DESIGN_COLOURS)]


def fig_hulls_3d(h: Hulls):
    """The design(s) in 3D (shaded, translucent) over the parent (its half-station sections and waterline as
    lines), to scale (x forward, y to port, z up) [m]; a sweep's first design shown, the others a click on
    the legend away."""
    fig = _figure("Hulls in 3D: design (shaded) and parent (grey stations and waterlines); drag to turn, "
                  "scroll to zoom", height=540)
    for i, (name, s, _) in enumerate(h.designs):
        fig.add_trace(_hull_trace(s, name, _colour(i), 0.55 if i == 0 else 0.8, True if i == 0 else "legendonly"))
    fig.add_trace(_wireframe(h.parent, "parent", h.draft))
    # true scale: the scene box in proportion to the hull's extents, its length 2 units; the eye outside it
    v = _hull_surface(h.parent)[0]
    ext = np.maximum(np.ptp(v, axis=0), 1e-9)
    ratio = 2.0 * ext / ext.max()
    axis = dict(nticks=4, title=dict(font=dict(size=11)))
    fig.update_layout(scene=dict(aspectmode="manual", aspectratio=dict(x=ratio[0], y=ratio[1], z=ratio[2]),
                                 xaxis=dict(axis, title_text="x from AP [m]", nticks=8),
                                 yaxis=dict(axis, title_text="y [m]"),
                                 zaxis=dict(axis, title_text="z [m]"),
                                 camera=dict(eye=dict(x=-0.95, y=-1.3, z=0.62), center=dict(x=0, y=0, z=-0.12))),
                      margin=dict(l=0, r=0, t=50, b=0))
    return fig


def _waterline_half_breadth(yz: np.ndarray, draft: float) -> float:
    """Half-breadth [m] where a half-section polyline ``(m, 2)`` (keel → deck) last crosses z = ``draft``
    (the outermost crossing of a bulb or a flared section); 0 where it does not reach the draft."""
    dz = yz[:, 1] - draft
    cross = np.flatnonzero(dz[:-1] * dz[1:] <= 0)
    if not len(cross):
        return 0.0
    j = cross[-1]
    t = dz[j] / (dz[j] - dz[j + 1]) if dz[j] != dz[j + 1] else 0.0
    return float(yz[j, 0] + t * (yz[j + 1, 0] - yz[j, 0]))


def _wireframe(s: Sections, name: str, draft: float):
    """A hull as lines on both sides: its sections at the half stations and its waterline at ``draft``."""
    import plotly.graph_objects as go

    x, yz = np.asarray(s.x), np.asarray(s.yz)
    gap = np.full((1, 3), np.nan)  # a break in the line (float arrays: plotly takes them without converting)
    pts = []
    for xk, section in zip(*station_sections(s, per_station=2)[1:]):
        for side in (1.0, -1.0):
            pts += [np.column_stack([np.full(len(section), xk), side * section[:, 0], section[:, 1]]), gap]
    wl = np.array([_waterline_half_breadth(p, draft) for p in yz])
    for side in (1.0, -1.0):
        pts += [np.column_stack([x, side * wl, np.full(len(x), draft)]), gap]
    a = np.concatenate(pts)
    return go.Scatter3d(x=a[:, 0], y=a[:, 1], z=a[:, 2], mode="lines", name=name, hoverinfo="name",
                        line=dict(color="#444444", width=2))


def _body_plan_lines(s: Sections) -> tuple[np.ndarray, np.ndarray, list]:
    """The half-sections at the half stations (interpolated there) as one polyline with gaps (NaN): aft body to
    the left (negative y), fore body to the right; hover names the station (0 at the AP, 10 at the FP) and x."""
    ys, zs, text = [], [], []
    for st, xk, section in zip(*station_sections(s, per_station=2)):
        sign = 1.0 if st >= 5.0 else -1.0
        ys += [sign * section[:, 0], [np.nan]]
        zs += [section[:, 1], [np.nan]]
        text += [f"station {st:g}, x = {xk:.2f} m"] * len(section) + [None]
    return np.concatenate(ys), np.concatenate(zs), text


def _station_labels(s: Sections) -> tuple[list, list, list]:
    """Integer station numbers above the deck edge of their sections (fore body right, aft body left)."""
    st, _, yz = station_sections(s)
    return list(np.where(st >= 5.0, 1.0, -1.0) * yz[:, -1, 0]), list(yz[:, -1, 1]), [f"{k:g}" for k in st]


def fig_body_plan(h: Hulls):
    """Body plan: aft body left, fore body right (as drawn by naval architects), at the half stations
    (interpolated there), parent dashed, integer station numbers above the (first) design's sections, the DWL."""
    import plotly.graph_objects as go

    fig = _figure("Body plan", height=500)
    styles = [("parent", h.parent, dict(color=PARENT_COLOUR, width=1, dash="dash"), True)]
    styles += [(name, s, dict(color=_colour(i), width=1.4), True if i == 0 else "legendonly")
               for i, (name, s, _) in enumerate(h.designs)]
    for name, s, line, visible in styles:
        ys, zs, text = _body_plan_lines(s)
        fig.add_trace(go.Scatter(x=ys, y=zs, mode="lines", name=name, line=line, text=text, visible=visible,
                                 hovertemplate="%{text}<br>y = %{x:.3f} m, z = %{y:.3f} m<extra>" + name + "</extra>"))
    xs, zs, text = _station_labels(h.designs[0][1] if h.designs else h.parent)
    fig.add_trace(go.Scatter(x=xs, y=zs, mode="text", text=text, textposition="top center", showlegend=False,
                             textfont=dict(size=10, color=_colour(0)), hoverinfo="skip"))
    b = max(float(np.max(np.asarray(s.yz)[..., 0])) for _, s, _, _ in styles)
    fig.add_trace(go.Scatter(x=[-1.1 * b, 1.1 * b], y=[h.draft, h.draft], mode="lines", name=f"DWL T = {h.draft:g} m",
                             line=dict(color="#2ca02c", width=1, dash="dashdot"), hoverinfo="name"))
    fig.add_vline(x=0, line=dict(color="black", width=0.6))
    fig.update_xaxes(title="half-breadth y [m]: aft body ← | → fore body; stations 0 = AP … 10 = FP",
                     zeroline=False)
    fig.update_yaxes(title="height above baseline z [m]", scaleanchor="x", scaleratio=1)
    return fig


def fig_sectional_areas(h: Hulls):
    """Sectional-area curves A(x) at the draft [m²] of the parent (dashed) and the design(s)."""
    import plotly.graph_objects as go

    fig = _figure(f"Sectional-area curve at T = {h.draft:g} m", height=400)
    fig.add_trace(go.Scatter(x=np.asarray(h.parent.x), y=np.asarray(h.parent_areas), name="parent", mode="lines",
                             line=dict(color=PARENT_COLOUR, dash="dash"),
                             hovertemplate="x = %{x:.2f} m<br>A = %{y:.2f} m²<extra>parent</extra>"))
    for i, (name, s, a) in enumerate(h.designs):
        fig.add_trace(go.Scatter(x=np.asarray(s.x), y=np.asarray(a), name=name, mode="lines",
                                 line=dict(color=_colour(i)), visible=True if i == 0 else "legendonly",
                                 hovertemplate="x = %{x:.2f} m<br>A = %{y:.2f} m²<extra>" + name + "</extra>"))
    fig.update_xaxes(title="x from AP [m]")
    fig.update_yaxes(title="sectional area A [m²]", rangemode="tozero")
    return fig


def history_series(report: dict) -> tuple[str, dict[str, np.ndarray]]:
    """``(iteration label, {series name: values})`` of a report's ``history`` (see :func:`history_record`):
    every list of numbers in it, non-finite entries dropped; empty when the run recorded none."""
    hist = report.get("history")
    if isinstance(hist, list):
        hist = {"series": {"cost": hist}}
    if not isinstance(hist, dict):
        return "iteration", {}
    series = hist.get("series", {k: v for k, v in hist.items() if isinstance(v, list)})
    out = {}
    for name, values in series.items():
        v = np.asarray([np.nan if x is None else x for x in values], float).ravel()
        if np.isfinite(v).any():
            out[str(name)] = v
    return str(hist.get("iteration", "iteration")), out


def fig_convergence(report: dict):
    """Each recorded series against the iteration, one panel each, log scale (|value|; the value itself on
    hover); a constraint violation with its tolerance line (≤ 1: met)."""
    import plotly.graph_objects as go
    from plotly.subplots import make_subplots

    xlabel, series = history_series(report)
    if not series:
        return None
    n = len(series)
    fig = make_subplots(rows=n, cols=1, shared_xaxes=True, vertical_spacing=0.08)
    fig.update_layout(title=dict(text="Convergence (log scale)", x=0.02), template=PAGE_TEMPLATE,
                      height=200 + 180 * n, margin=dict(l=70, r=20, t=50, b=50), showlegend=False)
    for i, (name, v) in enumerate(series.items()):
        it = np.flatnonzero(np.isfinite(v))
        y = np.maximum(np.abs(v[it]), 1e-300)
        first = 1 if xlabel.endswith("round") else 0
        fig.add_trace(go.Scatter(x=it + first, y=y, name=name, mode="lines+markers", marker=dict(size=6),
                                 line=dict(color=_colour(3 * i)), customdata=v[it],
                                 hovertemplate=f"{xlabel} %{{x}}<br>%{{customdata:.4g}}"
                                               f"<extra>{html.escape(name)}</extra>"),
                      row=i + 1, col=1)
        if name == VIOLATION:
            fig.add_hline(y=1.0, line=dict(color="black", width=1, dash="dash"), row=i + 1, col=1,
                          annotation_text="tolerance (≤ 1: met)", annotation_position="top right")
        fig.update_yaxes(title=dict(text=name, font=dict(size=11)), type="log", tickformat=".3~g",
                         row=i + 1, col=1)
    fig.update_xaxes(title=xlabel, row=n, col=1)
    longest = max(len(v) for v in series.values())
    if longest <= 25:
        fig.update_xaxes(dtick=1)
    return fig


def fig_pareto(report: dict, folder: Path):
    """A sweep's designs: measure against objective in their displayed units (kN), the front joined, each
    point's Bf target (4 significant digits), values and hull file on hover; a click opens the hull file."""
    import plotly.graph_objects as go

    o = report.get("objective", {})
    mname, oname = o.get("measure", "measure"), o.get("name", "objective")
    ma, oa = (o.get("about") or {}).get("measure"), (o.get("about") or {}).get("name")
    designs = report.get("designs", [])
    fig = _figure(f"Pareto front: {label(oname, unit=False, about=oa)} against {label(mname, unit=False, about=ma)} "
                  "(hover: each design; click: its hull file)", height=460)
    groups = (("Pareto front", lambda d: d.get("pareto") and d.get("met"), dict(color=_colour(0), size=10),
               "lines+markers"),
              ("dominated", lambda d: d.get("met") and not d.get("pareto"), dict(color="#999999", size=8), "markers"),
              ("targets not met", lambda d: not d.get("met"), dict(color="#d62728", size=9, symbol="x"), "markers"))
    for name, keep, marker, mode in groups:
        ks = [k for k, d in enumerate(designs) if keep(d)]
        if not ks:
            continue
        ks.sort(key=lambda k: designs[k]["measure"])
        xs = [displayed(mname, designs[k]["measure"])[0] for k in ks]
        ys = [displayed(oname, designs[k]["objective"])[0] for k in ks]
        hover = [_pareto_hover(k, designs[k], mname, oname, folder, o.get("about")) for k in ks]
        fig.add_trace(go.Scatter(x=xs, y=ys, mode=mode, name=name, marker=marker, text=hover,
                                 customdata=[_hull_link(folder, k) or "" for k in ks],
                                 hovertemplate="%{text}<extra></extra>"))
    objectives = report.get("objectives", {})
    if all(isinstance(objectives.get(k), dict) for k in (mname, oname, "bf")):  # the parent, to read them against
        x, y = (displayed(k, objectives[k]["parent"])[0] for k in (mname, oname))
        fig.add_trace(go.Scatter(x=[x], y=[y], mode="markers", name="parent",
                                 marker=dict(color="black", size=13, symbol="star"),
                                 hovertemplate=f"parent: Bf {objectives['bf']['parent']:.4g}<extra></extra>"))
    fig.update_xaxes(title=label(mname, about=ma))
    fig.update_yaxes(title=label(oname, about=oa))
    return fig


def _pareto_hover(k: int, d: dict, mname: str, oname: str, folder: Path, about: dict | None = None) -> str:
    ma, oa = (about or {}).get("measure"), (about or {}).get("name")
    m, mu = displayed(mname, d["measure"])
    v, vu = displayed(oname, d["objective"])
    link = _hull_link(folder, k)
    lines = [f"<b>design {k}</b>: Bf target {d['bf_target']:.4g}",
             f"{label(mname, unit=False, about=ma)}: {fmt(m, 4)} {mu}".rstrip(),
             f"{label(oname, unit=False, about=oa)}: {fmt(v, 4)} {vu}".rstrip(),
             f"targets met: {'yes' if d.get('met') else 'NO'}",
             f"hull: {link} (click to open)" if link else "hull: hullopt export RUN_DIR?design=" + str(k)]
    return "<br>".join(html.escape(s, quote=False).replace("&lt;b&gt;", "<b>").replace("&lt;/b&gt;", "</b>")
                       for s in lines)


def _hull_link(folder: Path, k: int) -> str | None:
    """The relative path of design ``k``'s hull file in a sweep's folder, if it is there."""
    for name in ("hull.stl", "hull.obj", "hull.ply", "hull.glb"):
        if (folder / "designs" / str(k) / name).is_file():
            return f"designs/{k}/{name}"
    return None


# ----------------------------------------------------------------------------------------------- tables


def _table(head: list[str], rows: list[list[str]], cls: str = "") -> str:
    th = "".join(f"<th>{html.escape(h)}</th>" for h in head)
    body = "".join("<tr>" + "".join(f"<td>{c}</td>" for c in r) + "</tr>" for r in rows)
    return f'<table class="{cls}"><thead><tr>{th}</tr></thead><tbody>{body}</tbody></table>'


def _e(v: Any) -> str:
    return html.escape(str(v))


def _number(key: str, v: Any, ref: float | None = None) -> str:
    """``v`` of a report key in its displayed unit (no unit: the column head has it)."""
    if isinstance(v, bool) or v is None:
        return _e(fmt(v))
    if not isinstance(v, int | float):
        return _e(v)
    d, u = displayed(key, v)
    return _e(fmt(d, 5, ref))


def _ref(key: str, *values) -> float:
    ds = [abs(displayed(key, v)[0]) for v in values if isinstance(v, int | float) and not isinstance(v, bool)]
    return max([*ds, unit_scale(displayed(key, 0.0)[1]), 0.0])


def targets_table(report: dict) -> str:
    """Targets: wanted, achieved, error (as the solver measures it), tolerance and met; a sweep's held
    targets as they are."""
    targets = report.get("targets") or {}
    if not targets:
        return "<p>No targets.</p>"
    rows = []
    full = all(isinstance(t, dict) for t in targets.values())
    for k, t in targets.items():
        if not isinstance(t, dict):
            rows.append([_e(label(k)), _number(k, t, _ref(k, t))])
            continue
        ref = _ref(k, t.get("target"), t.get("achieved"))
        met = t.get("met")
        scale, eunit = _error_scale(k)
        err, tol = (v * scale if isinstance(v, int | float) else v for v in (t.get("error"), t.get("tolerance")))
        tol_ref = abs(tol) if isinstance(tol, int | float) else None
        rows.append([_e(label(k)), _number(k, t.get("target"), ref), _number(k, t.get("achieved"), ref),
                     _e(quantity(err, eunit, 2, ref=tol_ref)), _e(quantity(tol, eunit, 2)),
                     '<span class="ok">yes</span>' if met else '<span class="bad">NO</span>' if met is False else "–"]
                    + [_e(_plain(v)) for kk, v in t.items()
                       if kk not in ("target", "achieved", "error", "tolerance", "met")])
    if full:
        extra = list(dict.fromkeys(kk for t in targets.values() for kk in t
                                   if kk not in ("target", "achieved", "error", "tolerance", "met")))
        return _table(["target", "wanted", "achieved", "error", "tolerance", "met", *extra], rows)
    return _table(["target (held)", "value"], [r[:2] for r in rows])


def _error_scale(key: str) -> tuple[float, str]:
    """How a target's error and tolerance read: a relative target's in %, the others in the particular's
    unit (as the solvers measure them; :data:`hullopt.optimise.TARGETS`)."""

    if TARGETS.get(key, (False,))[0]:
        return 100.0, "%"
    return 1.0, displayed(key, 0.0)[1]


def _plain(v: Any) -> str:
    if isinstance(v, float):
        return fmt(v)
    return json.dumps(to_builtin(v)) if isinstance(v, dict | list) else str(v)


def particulars_table(report: dict, picks: list[int] | None = None) -> str:
    """The hydrostatic particulars parent → design with units, the change and the relative change; a sweep's
    (``picks``: its designs' ``particulars``) parent and designs side by side."""
    parent = report.get("parent") or {}
    if picks is not None:
        designs = [(report["designs"][k].get("particulars") or {}) for k in picks]
        keys = [k for k in dict.fromkeys(k for d in designs for k in d) if k in parent]
        rows = []
        for k in keys:
            values = [parent[k], *(d.get(k) for d in designs)]
            ref = _ref(k, *values)
            rows.append([_e(label(k)), *(_number(k, v, ref) for v in values)])
        return _table(["particular", "parent", *(f"design {j}" for j in picks)], rows) if rows else ""
    design = report.get("achieved") or {}
    keys = [k for k in design if k in parent]
    if not keys:
        return ""
    rows = []
    for k in keys:
        a, b = parent[k], design[k]
        if not all(isinstance(v, int | float) and not isinstance(v, bool) for v in (a, b)):
            continue
        ref = _ref(k, a, b)
        (da, unit), (db, _) = displayed(k, a), displayed(k, b)
        rel = "" if unit == "% Lpp" or abs(da) < 1e-12 else f"{100 * (db / da - 1):+.2f}"
        rows.append([_e(label(k)), _e(fmt(da, 5, ref)), _e(fmt(db, 5, ref)), _e(_signed(db - da, ref)), _e(rel)])
    return _table(["particular", "parent", "design", "change", "change [%]"], rows)


def _signed(v: float, ref: float) -> str:
    text = fmt(v, 5, ref)
    return text if text.startswith("-") or float(text) == 0 else f"+{text}"


def _shown(key: str, unit: str | None = None) -> tuple[str, str, float]:
    """``(label with unit, displayed unit, factor from SI)`` of a report key: a known particular or objective
    by :func:`units_of`, any other by the SI ``unit`` the report gives (N → kN, kg → t)."""
    lab, (_, u) = label(key), displayed(key, 0.0)
    if u or unit in (None, "", "-"):
        return lab, u, displayed(key, 1.0)[0]
    u, factor = {"N": ("kN", 1e-3), "kg": ("t", 1e-3), "W": ("kW", 1e-3)}.get(unit, (unit, 1.0))
    return f"{lab} [{u}]", u, factor


def objective_rows(report: dict) -> list[tuple[str, str | None, Any, list]]:
    """``(key, SI unit, parent, [design values])`` of every objective and measure the report compares: its
    ``objectives`` (a mapping of name → {parent, design | designs | value, unit} or → a number, or a list of
    such records with a ``name``) and its ``objective`` ({name, value, parent}) when not among them."""
    out: list[tuple[str, str | None, Any, list]] = []

    def add(name, rec):
        if isinstance(rec, dict):
            if isinstance(rec.get("designs"), list):
                values = rec["designs"]
            else:
                values = [next((rec[k] for k in ("design", "value", "achieved") if k in rec), None)]
            if rec.get("parent") is None and all(v is None for v in values):
                return
            out.append((str(rec.get("name", name)), rec.get("unit"), rec.get("parent"), values))
        elif isinstance(rec, int | float) and not isinstance(rec, bool):
            out.append((str(name), None, None, [rec]))

    objs = report.get("objectives")
    if isinstance(objs, dict):
        for name, rec in objs.items():
            add(name, rec)
    elif isinstance(objs, list):
        for rec in objs:
            if isinstance(rec, dict):
                add(rec.get("name", "objective"), rec)
    o = report.get("objective")
    if isinstance(o, dict) and "value" in o and not any(r[0] == o.get("name") for r in out):
        add(o.get("name", "objective"), o)
    return out


def _num(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and bool(np.isfinite(v))


def objectives_table(report: dict, picks: list[int] | None = None) -> str:
    """Objectives and measures parent → design, each with its unit in a column ("–": dimensionless; a run: the
    change and the relative change; a sweep: the designs ``picks``); the run's own objective first and in
    bold."""
    rows = []
    main = (report.get("objective") or {}).get("name")
    entries = sorted(objective_rows(report), key=lambda r: r[0] != main)
    sweep = picks is not None
    for k, unit, a, values in entries:
        lab, u, factor = _shown(k, unit)
        da = a * factor if _num(a) else None
        ds = [v * factor if _num(v) else None for v in values]
        if sweep:
            ds = [ds[j] if j < len(ds) else None for j in picks]
        ref = max([abs(v) for v in (da, *ds) if v is not None] + [unit_scale(u)])
        lab = lab.removesuffix(f" [{u}]") if u else lab  # the unit has its own column
        name = f"<b>{_e(lab)}</b>" if k == main else _e(lab)
        cells = [name, _e(u or "–"), _e(fmt(da, 5, ref))] + [_e(fmt(v, 5, ref)) for v in ds]
        if not sweep:
            db = ds[0] if ds else None
            ch = _signed(db - da, ref) if da is not None and db is not None else ""
            rel = f"{100 * (db / da - 1):+.2f}" if da and db is not None and u != "% Lpp" else ""
            cells += [_e(ch), _e(rel)]
        rows.append(cells)
    if not rows:
        return ""
    head = ["objective or measure", "unit", "parent"] + ([f"design {j}" for j in picks] if sweep
                                                 else ["design", "change", "change [%]"])
    return _table(head, rows)


def report_warnings(report: dict) -> list[str]:
    """The report's ``warnings``, its ``message`` (targets not met), a solver that stopped short, and for a
    sweep the designs that miss their targets."""
    out = []
    for w in report.get("warnings") or []:
        out.append(w if isinstance(w, str) else json.dumps(to_builtin(w)))
    if report.get("message"):
        out.append(str(report["message"]))
    if report.get("met") and not report.get("converged", True):
        out.append("the solver stopped before it converged (the targets are met)")
    missed = [k for k, d in enumerate(report.get("designs") or []) if not d.get("met")]
    if missed:
        out.append(f"{len(missed)} of {len(report['designs'])} designs miss their targets "
                   f"({', '.join(map(str, missed))}); they are left off the front")
    if report.get("partial"):
        out.append(f"a partial sweep: chunks {report.get('chunks_done')} of {report.get('chunks_total')} done")
    return out


def designs_table(report: dict, folder: Path) -> str:
    """A sweep's designs: Bf target (4 significant digits), measure and objective in kN, met, front, link to
    the hull."""
    o = report.get("objective", {})
    mname, oname = o.get("measure", "measure"), o.get("name", "objective")
    ma, oa = (o.get("about") or {}).get("measure"), (o.get("about") or {}).get("name")
    rows = []
    for k, d in enumerate(report.get("designs") or []):
        link = _hull_link(folder, k)
        rows.append([str(k), f"{d.get('bf_target', float('nan')):.4g}",
                     _e(fmt(displayed(mname, d.get("measure"))[0], 4)),
                     _e(fmt(displayed(oname, d.get("objective"))[0], 4)),
                     '<span class="ok">yes</span>' if d.get("met") else '<span class="bad">NO</span>',
                     "★" if d.get("pareto") else "", f'<a href="{_e(link)}">{_e(link)}</a>' if link else "–"])
    return _table(["design", "Bf target", _e(label(mname, short=True, about=ma)), _e(label(oname, short=True, about=oa)),
                   "targets met",
                   "front", "hull"], rows)


def summary_list(report: dict) -> str:
    items = [("kind", report.get("kind")), ("converged", report.get("converged")), ("targets met", report.get("met")),
             ("iterations", report.get("iterations"))]
    if "max_violation" in report:
        items.append(("largest constraint violation [tolerances]", report["max_violation"]))
    if "pareto_count" in report:
        items.append(("non-dominated designs", report["pareto_count"]))
    cells = "".join(f"<div><span class=k>{_e(k)}</span> <b>{_e(fmt(v) if not isinstance(v, str) else v)}</b></div>"
                    for k, v in items if v is not None)
    return f'<div class="summary">{cells}</div>'


# ----------------------------------------------------------------------------------------------- page

_CSS = """
body{font-family:system-ui,-apple-system,"Segoe UI",Roboto,sans-serif;margin:0 auto;max-width:1200px;padding:1em 2em;
color:#222}
h1{font-size:1.6em;margin-bottom:.2em}h2{font-size:1.2em;margin-top:1.6em;border-bottom:1px solid #ddd}
.sub{color:#666;margin-top:0}.summary{display:flex;flex-wrap:wrap;gap:.4em 2em;margin:.8em 0}.k{color:#666}
table{border-collapse:collapse;margin:.5em 0;font-size:.92em}th,td{padding:.25em .8em;border-bottom:1px solid #eee}
th{text-align:left;background:#f6f6f6}td{font-variant-numeric:tabular-nums}td:not(:first-child){text-align:right}
.ok{color:#1a7f37}.bad{color:#c62828;font-weight:bold}.warn{background:#fff6e0;border-left:4px solid #f0a020;
padding:.5em 1em}td .warn{padding:.1em .3em;white-space:nowrap}.plot{margin:.5em 0}.grid{display:grid;grid-template-columns:1fr 1fr;gap:1em}
@media (max-width:900px){.grid{grid-template-columns:1fr}}
"""

_CLICK = """
document.getElementById('{plot_id}').on('plotly_click', function (e) {
  var link = e.points && e.points[0] && e.points[0].customdata;
  if (link) { window.open(link, '_blank'); }
});
"""


def _div(fig, name: str, click: bool = False) -> str:
    import plotly.io as pio

    if fig is None:
        return ""
    return '<div class="plot">' + pio.to_html(
        fig, full_html=False, include_plotlyjs=False, include_mathjax=False, div_id=name,
        config={"displaylogo": False, "responsive": True}, post_script=_CLICK if click else None) + "</div>"


def rescored_table(report: dict) -> str:
    """The report's ``rescored`` as a table: each method's parent value [kN] at the nominal condition and each
    design's change there and its worst change over every condition [%] (marked where the gain does not hold),
    the conditions above it."""
    r = report["rescored"]
    c = r["conditions"]
    lines = [f"operating points (speed × {', '.join(f'{f:g}' for f in c['speed_factors'])}; T_p "
             f"{', '.join(f'{t:+g}' for t in c['tp_shifts_s'])} s):"]
    for u, w, sea in zip(c["speeds_kn"], c["weights"], c["sea_states"]):
        lines.append(f"{u:g} kn, weight {w:g}, " + ("calm water" if not sea else
                                                    f"H_s {sea[0]:g} m, T_p {sea[1]:g} s, heading {sea[2]:g}°"))
    if r.get("note"):
        lines.append(r["note"])
    if r.get("mechanism"):
        lines.append(r["mechanism"])
    methods = r["methods"]
    n = len(next(iter(methods.values()))["designs"]) if methods else 0
    head = ["method", "parent [kN]"] + [f"design {k}: nominal / worst [%]" for k in range(n)]
    rows = []
    for name, m in methods.items():
        what = ("calm water R_T" if m["kind"] == "calm" else "waves mean R_AW") + f": {m['method']}"
        note = " (the objective's)" if m["own"] else ""
        note += " (outside its validity: not counted)" if m.get("outside_validity") else ""
        note += " (blind to the bow's mechanism, NMRI's C_U: not counted)" if m.get("blind") else ""
        cells = [_e(what + note), f"{m['parent'] / 1e3:.2f}"]
        for k in range(n):
            text = f"{m['change_pct'][k]:+.2f} / {m['worst_pct'][k]:+.2f}"
            cells.append(_e(text) if m["holds"][k] else f'<span class="warn">{_e(text)} ✗</span>')
        rows.append(cells)
    return ("<p>" + "<br>".join(_e(x) for x in lines) + "</p>"
            + _table(head, rows)
            + "<p class=\"sub\">✗: the design is above the parent's value in some condition (the gain does not "
              "hold under that method).</p>")


FRONTS_NAME = "rescored_fronts.png"
"""The figure of the designs under each pair of re-scoring methods in a run folder."""

PATENT_NAME = "patent.png"
"""A bluntness sweep's figure in the patent's form (K_AW against Bf, ½ρgζ²B·K_AW against B·Bf) in a run folder."""

OVERLAY_NAME = "overlay.png"
"""The figure of a design against its parent (body plan, waterlines, sectional-area curve) in its folder."""


def overlays(report: dict, folder: Path) -> str:
    """The overlay figure of the run's design, or of each of a sweep's designs (``designs/<k>/``), embedded as
    PNG (the page opens offline); empty when the folder holds none."""
    ks = [None] if report.get("kind") != "pareto" else list(range(len(report.get("designs") or [])))
    out = []
    for k in ks:
        path = folder / OVERLAY_NAME if k is None else folder / "designs" / str(k) / OVERLAY_NAME
        name = "the design" if k is None else f"design {k}"
        img = _png(path, f"{name} against the parent")
        if img:
            out.append(f'<p class="sub">{_e(name)}</p>{img}')
    return "\n".join(out)


def _png(path: Path, alt: str) -> str:
    """An ``<img>`` of a PNG file embedded as data (the page opens offline); empty when there is no file."""
    import base64

    if not path.is_file():
        return ""
    data = base64.b64encode(path.read_bytes()).decode("ascii")
    return f'<img alt="{_e(alt)}" style="max-width:100%" src="data:image/png;base64,{data}">'


def limits_table(report: dict) -> str:
    """The limits of the report's ``limits``: each one's bound and its largest normalised value ``g`` (≤ its
    tolerance: met; ``g`` the excess in units of the bound) of the parent and each design."""
    lim = report.get("limits") or {}
    if not lim:
        return ""
    n = len(next(iter(lim.values())).get("designs", [None]))
    head = ["limit", "bound", "parent g"] + (["design g"] if n == 1 and "design" in next(iter(lim.values()))
                                             else [f"design {k} g" for k in range(n)])
    rows = []
    for name, v in lim.items():
        values, tol = [v["design"]] if "design" in v else v["designs"], v.get("tolerance", 1e-3)
        cells = [_e(name), _e(v.get("bound", "")), _e(f"{v['parent']:+.3g}")]
        cells += [f'<span class="bad">{_e(f"{g:+.3g}")} ✗</span>' if g > tol else _e(f"{g:+.3g}") for g in values]
        rows.append(cells)
    return (_table(head, rows) + '<p class="sub">g: the largest excess over the bound, in units of the bound (≤ 0 '
            "met; a limit per station, height or region gives its worst); ✗ violated.</p>")


def build_html(folder: Path, report: dict, hulls: Hulls | None, title: str | None = None,
               name: str | None = None) -> str:
    """The page of a run folder (see the module's docstring) as one HTML string, plotly's JS embedded once;
    ``name``: the folder's name as shown (None: ``folder``'s own; a run built in a staging folder gives its
    final one)."""
    from plotly.offline import get_plotlyjs

    name = name or folder.resolve().name
    title = title or f"hullopt run: {name}"
    kind = report.get("kind", "run")
    parts = [f"<h1>{_e(title)}</h1>",
             f'<p class="sub">{_e(kind)} run in <code>{_e(name)}/</code>; units as labelled '
             "(lengths m, areas m², displacement t, resistances kN)</p>", summary_list(report)]
    warns = report_warnings(report)
    parts.append("<h2>Warnings</h2>" + ("".join(f'<p class="warn">{_e(w)}</p>' for w in warns) if warns
                                         else "<p>None.</p>"))
    if kind == "pareto" and report.get("designs"):
        parts += ["<h2>Pareto front</h2>", _div(fig_pareto(report, folder), "pareto", click=True),
                  "<h2>Designs</h2>", designs_table(report, folder)]
    if hulls is not None:
        parts += ["<h2>Hulls</h2>", _div(fig_hulls_3d(hulls), "hull3d"),
                  '<div class="grid">', _div(fig_body_plan(hulls), "bodyplan"),
                  _div(fig_sectional_areas(hulls), "sac"), "</div>"]
    over = overlays(report, folder)
    if over:
        parts += ["<h2>Designs against the parent: body plan, waterlines, sectional-area curve</h2>", over]
    parts += ["<h2>Targets and constraints</h2>", targets_table(report)]
    lim = limits_table(report)
    if lim:
        parts += ["<h2>Local shape limits</h2>", lim]
    obj = objectives_table(report, sweep_picks(report) if kind == "pareto" else None)
    if obj:
        parts += ["<h2>Objectives and measures: parent → design</h2>", obj]
    part = particulars_table(report, sweep_picks(report) if kind == "pareto" else None)
    if part:
        parts += ["<h2>Particulars: parent → design</h2>", part]
    if report.get("rescored"):
        parts += ["<h2>Second opinion: every design re-scored by independent methods</h2>",
                  rescored_table(report), _png(folder / FRONTS_NAME, "the designs under each pair of methods")]
    if (folder / PATENT_NAME).is_file():
        parts += ["<h2>The sweep in the patent's form (JP2009-286166 Figs 10–13, claim 3)</h2>",
                  _png(folder / PATENT_NAME, "K_AW against Bf and ½ρgζ²B·K_AW against B·Bf, the parent and designs")]
    conv = fig_convergence(report)
    if kind != "pareto":
        parts += ["<h2>Convergence</h2>", _div(conv, "convergence") if conv is not None
                  else "<p>This run folder holds no convergence history (rerun it to record one).</p>"]
    body = "\n".join(parts)
    return (f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
            f'<meta name="viewport" content="width=device-width, initial-scale=1">'
            f"<title>{_e(title)}</title><style>{_CSS}</style>"
            f'<script type="text/javascript">{get_plotlyjs()}</script></head>\n<body>\n{body}\n'
            f'<p class="sub">Written by hullopt; rebuild with <code>hullopt report RUN_DIR</code>.</p></body></html>\n')


def read_run(folder: Path) -> tuple[dict, dict]:
    """The config and the report of a run folder.

    Parameters
    ----------
    folder : pathlib.Path
        The run folder.

    Returns
    -------
    tuple of (dict, dict)
        ``(config, report)``: its ``config.json`` (the raw config) and its ``report.json``, as read.

    Raises
    ------
    HullError
        When it is not a run folder: either file missing or not JSON.
    """
    try:
        raw = json.loads((folder / "config.json").read_text())
        report = json.loads((folder / "report.json").read_text())
    except (OSError, ValueError) as e:
        raise HullError(f"{folder} is not a run folder with config.json and report.json "
                        f"({type(e).__name__}: {e})") from None
    return raw, report


def write_report(folder: Path, report: dict | None = None, hulls: Hulls | None = None,
                 name: str | None = None) -> Path:
    """Write ``folder/report.html`` atomically and return its path.

    Parameters
    ----------
    folder : pathlib.Path
        The run folder.
    report : dict or None
        The run's report; None: its ``report.json``.
    hulls : Hulls or None
        The parent and design hulls; None: rebuilt from the folder by :func:`run_hulls` (a partial sweep's page
        has none).
    name : str or None
        The run folder's name as the page shows it; None: ``folder``'s (``hullopt run`` builds its folder in a
        staging sibling and gives the final name).

    Returns
    -------
    pathlib.Path
        ``folder / "report.html"`` (:data:`REPORT_NAME`).

    Raises
    ------
    HullError
        When the folder is needed (``report`` or ``hulls`` None) and is not a run folder, or its files do not fit
        each other.
    """
    folder = Path(folder)
    _, kept = read_run(folder) if report is None or hulls is None else (None, None)
    report = report if report is not None else kept
    report = to_builtin(report)
    if hulls is None and not report.get("partial"):
        hulls = run_hulls(folder, report)
    text = build_html(folder, report, hulls, name=name)
    path = folder / REPORT_NAME
    atomic_write_bytes(path, text.encode("utf-8"))
    return path


__all__ = ["REPORT_NAME", "Hulls", "build_html", "history_record", "history_series", "run_hulls", "write_report"]
