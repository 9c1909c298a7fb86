"""Config-driven runs: build the design problem from a :class:`~hullopt.app.config.RunConfig`, solve it (fit,
constrained minimum, or a Pareto sweep in resumable chunks) and write the run folder:

    config.json   the resolved config           report.json   results (see :func:`run`)
    parent.json   the parent it deformed        hull.stl      the final hull (closed mesh; Lpp, draft in its header)
    offsets.csv   its offset table (wide layout)
    body_plan.png, sectional_area.png, convergence.png, pareto.png (sweeps), chunks/ (sweeps)
    report.html   the run as one self-contained page (3D hulls, plots, tables: :mod:`hullopt.app.report`)
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float
from rich.progress import BarColumn, MofNCompleteColumn, Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

from ..constants import G, KNOT
from ..drawing import write_offsets_wide
from ..errors import HullError
from ..geometry import Sections, safe_norm
from ..hydro import Hydrostatics, hydrostatics, sectional_areas
from ..models import ApexMove, ContourEdit, Distribution, FeatureHull, FeatureParams, feature_model, save_features
from ..optimise import (
    OBJECTIVES,
    Design,
    Limits,
    Objective,
    Particular,
    achieved,
    make_targets,
    non_dominated,
    solve_fit,
    solve_minimum,
    target_errors,
    with_objective_scale,
)
from ..resistance import DISAGREE, holtrop_hull, outside_validity
from .config import DesignConfig, ObjectiveConfig, RunConfig
from .output import console, write_hull_file, write_json
from .parents import parent_digest, run_parent
from .programs import cached_call


@dataclass
class Problem:
    """A design problem built from a config, with its start point and bounds."""

    design: Design
    p0: FeatureParams
    lower: FeatureParams
    upper: FeatureParams
    parent: str


def objective_from(cfg: ObjectiveConfig) -> Objective:
    """The objective of a config's ``[objective]`` table, by its kind's class in
    :data:`~hullopt.optimise.OBJECTIVES`."""
    return cfg.build()


def design_params(d: DesignConfig, hull: FeatureHull, where: str = "design.") -> tuple:
    """``(model, p0, half)``: the feature model of a design's tables on ``hull``, its start parameters and the
    half-widths of its bounds (numpy leaves); :class:`HullError` naming the field (``where`` + table) when a
    start value is not inside its bound. Shared by ``hullopt run`` and ``hullopt deform``."""
    model = feature_model(
        hull,
        [ApexMove(m.segment, m.x_fixed1, m.x_moved, m.x_fixed2, m.profile) for m in d.apex_move],
        [Distribution(g.x_a, g.x_b, g.curves if isinstance(g.curves, str) else tuple(g.curves), g.modes)
         for g in d.distribution],
        [ContourEdit(e.line, e.x_a, e.x_b, e.shape) for e in d.contour_edit],
    )
    modes = max((g.modes for g in d.distribution), default=0)
    dist0 = np.zeros((len(d.distribution), modes))
    dist_b = np.ones((len(d.distribution), modes))
    for i, g in enumerate(d.distribution):
        c = g.c or []
        if len(c) > g.modes:
            raise HullError(f"{where}distribution[{i}].c: {len(c)} values for {g.modes} modes")
        dist0[i, : len(c)] = c
        dist_b[i] = g.bound
    # numpy leaves: building a problem runs no JAX op (each eager op costs a compile or a cache read)
    p0 = FeatureParams(np.array([m.d for m in d.apex_move], float).reshape(-1, 2), dist0,
                       np.array([e.amplitude for e in d.contour_edit], float))
    half = FeatureParams(np.array([[m.bound] * 2 for m in d.apex_move], float).reshape(-1, 2), dist_b,
                         np.array([e.bound for e in d.contour_edit], float))
    for name, v, b in (("apex_move d", p0.apex, half.apex), ("distribution c", p0.distribution, half.distribution),
                       ("contour_edit amplitude", p0.contour, half.contour)):
        if np.any(np.abs(np.asarray(v)) >= np.asarray(b)):
            raise HullError(f"{where.rstrip('.') or 'design'}: a start value of {name} is not inside its bound")
    return model, p0, half


def build_problem(cfg: RunConfig, parent: FeatureHull | None = None) -> Problem:
    """The :class:`~hullopt.optimise.Design`, start and bounds of a config (HullError on a bad design);
    ``parent``: the feature hull to deform instead of the config's (a run folder's kept ``parent.json``).

    No hull is evaluated here: the objective and fairness scales (their values at the parent) are set by
    :func:`~hullopt.optimise.with_objective_scale` inside the jitted solve programs."""
    # a hull spec's features: extracted once, then kept
    hull = parent if parent is not None else run_parent(cfg.hull.parent, cfg.hull.draft)
    draft = cfg.hull.draft or hull.design_draft
    if draft is None:
        raise HullError(f"hull.draft: parent {cfg.hull.parent!r} has no design draft; give one")
    model, p0, half = design_params(cfg.design, hull)
    lower = jax.tree.map(lambda h: -h, half)
    try:
        targets = make_targets(cfg.targets, cfg.tolerances, cfg.kg)
    except ValueError as e:
        raise HullError(f"targets: {e}") from None
    design = Design(model=model, draft=np.asarray(float(draft)), targets=targets,
                    objective=objective_from(cfg.objective) if cfg.objective else None,
                    smoothness=cfg.solver.smoothness, param_scale=half, fairness=cfg.solver.fairness_for(cfg.kind),
                    limits=None if cfg.kind == "fit" else limits_from(cfg))
    return Problem(design, p0, lower, half, cfg.hull.parent)


def constraint_measure(cfg: RunConfig, name: str):
    """The measure a ``[constraints]`` key names: an objective (with the options of
    :meth:`~hullopt.app.config.RunConfig.constraint_options`), a fairness measure (:data:`ROUGHNESS_MEASURES`)
    or a :class:`~hullopt.optimise.Particular`."""
    if name in ROUGHNESS_MEASURES:
        return ROUGHNESS_MEASURES[name]
    return objective_from(cfg.constraint_options(name)) if name in OBJECTIVES else Particular(name)


def limits_from(cfg: RunConfig) -> Limits:
    """The :class:`~hullopt.optimise.Limits` of a config's ``[constraints]`` (defaults: half-breadths within
    the parent's, no new bulge below the waterline)."""
    c = cfg.constraints
    bounds = c.bounds()
    mhb = {"parent": np.nan, "none": None}.get(c.max_half_breadth, c.max_half_breadth)
    return Limits(names=tuple(bounds), measures=tuple(constraint_measure(cfg, k) for k in bounds),
                  sense=np.array([b[0] for b in bounds.values()], float),
                  values=np.array([b[1] for b in bounds.values()], float),
                  relative=tuple(b[2] for b in bounds.values()),
                  max_half_breadth=None if mhb is None else np.asarray(float(mhb)),
                  bulge=c.bulge == "forbid", tol=c.tolerance)


def _params_dict(p: FeatureParams) -> dict:
    return {"apex_move_d": np.asarray(p.apex).tolist(), "distribution_c": np.asarray(p.distribution).tolist(),
            "contour_edit_amplitude": np.asarray(p.contour).tolist()}


def params_from_dict(values: dict, like: FeatureParams) -> FeatureParams:
    """The parameters of a report's ``params`` (the inverse of what a run writes), shaped ``like`` the
    problem's start point; :class:`HullError` if they do not fit the problem."""
    try:
        leaves = [np.asarray(values[k], float).reshape(np.shape(ref)) for k, ref in
                  (("apex_move_d", like.apex), ("distribution_c", like.distribution),
                   ("contour_edit_amplitude", like.contour))]
    except (KeyError, ValueError, TypeError) as e:
        raise HullError(f"the report's params do not fit the run's design ({type(e).__name__}: {e})") from None
    return FeatureParams(*leaves)


class Outcome(eqx.Module):
    """Everything a run folder shows of a parent and a final design, computed in one jitted program."""

    before: Sections  # the parent
    after: Sections  # the final design
    parent: Hydrostatics  # of the parent at the draft
    final: Hydrostatics  # of the final design
    achieved: Float[Array, " t"]  # the target particulars of the final design
    errors: Float[Array, " t"]  # ... their errors (optimise.target_errors: the solvers' residuals, normalised units)
    areas: Float[Array, "2 n"]  # sectional-area curves [m²]: parent, final
    objective: Float[Array, ""] | None  # the objective of the final design (None without one)
    objective_parent: Float[Array, ""] | None  # ... and of the parent


def measure(d: Design, p0, final) -> Outcome:
    """The :class:`Outcome` of the parameters ``p0`` (the parent) and ``final`` at the design's draft."""
    before, after = d.model(p0), d.model(final)
    h0, h1 = hydrostatics(before, d.draft), hydrostatics(after, d.draft)
    areas = jnp.stack([sectional_areas(before, d.draft), sectional_areas(after, d.draft)])
    obj = (d.objective(after, d.draft), d.objective(before, d.draft)) if d.objective is not None else (None, None)
    a = achieved(h1, after, d.targets.names, d.targets.kg)
    return Outcome(before, after, h0, h1, a, target_errors(a, d.targets), areas, *obj)


def solve_and_measure(d: Design, p0, lower, upper, kind: str, max_steps: int, outer: int):
    """The solve of a fit or minimum run and the :class:`Outcome`, as one program (one trace, one compile;
    :func:`~hullopt.app.programs.cached_call` keeps it for the next run)."""
    d = with_objective_scale(d, p0)
    if kind == "fit":
        res = solve_fit(d, p0, lower, upper, traced=True, max_steps=max_steps)
    else:
        res = solve_minimum(d, p0, lower, upper, outer=outer, max_steps=max_steps)
    return res, measure(d, p0, res.params)


def _file_digest(name: str) -> str | None:
    """Digest of a parent given as a file (its content shapes the program): a parent .json's SHA-256, a hull
    spec's feature key (file digest, parameters, extraction; :func:`~hullopt.app.parents.parent_digest`),
    None for a library parent."""
    return parent_digest(name)


def _particulars(h) -> dict:
    return {k: float(v) for k, v in h.to_dict().items()}


def _target_report(d: Design, achieved_values, errors) -> dict:
    """Target, achieved value, error (:func:`~hullopt.optimise.target_errors`, computed in the measuring
    program), tolerance and met per target."""
    out = {}
    for k, t, tol, v, err in zip(d.targets.names, np.asarray(d.targets.values), np.asarray(d.targets.tol),
                                 np.asarray(achieved_values), np.asarray(errors)):
        out[k] = {"target": float(t), "achieved": float(v), "error": float(err), "tolerance": float(tol),
                  "met": bool(abs(err) <= tol)}
    return out


def run(cfg: RunConfig, raw: dict, out: Path, quiet: bool = False, shard: tuple[int, int] = (1, 1),
        executor: str = "local", address: str | None = None) -> dict:
    """Solve the config's problem and write the run folder ``out``; returns the report.

    ``report.json``: ``kind``, ``converged`` (the solver finished and every target is met), ``met``,
    ``iterations``, ``targets`` (target, achieved, error, tolerance, met per particular), ``achieved`` and
    ``parent`` (the ``hullopt hydro --json`` keys of the final and the parent hull), ``objective``
    (value, parent value, name), ``params``; for sweeps ``designs`` (one per sweep value, with its
    objectives, particulars, parameters and whether it is Pareto-optimal). ``shard = (k, N)``, ``executor``
    (``"local"`` or ``"dask"``) and ``address`` (the Dask scheduler) apply to sweeps: a shard whose sweep is
    not complete yet returns a partial report and writes no hull files.
    """
    from .plots import plot_convergence, plot_pareto
    from .report import Hulls, history_record, write_report

    out.mkdir(parents=True, exist_ok=True)
    write_json(out / "config.json", raw)
    prob = build_problem(cfg)
    save_features(prob.design.model.hull, out / "parent.json")  # the run folder rebuilds its designs from it
    d = prob.design
    if cfg.kind == "pareto":
        report = _pareto(cfg, prob, out, quiet, shard, executor, address)
        if report.get("partial"):
            write_json(out / "report.json", report)
            return report
        m = eqx.filter_jit(measure)(d, prob.p0, prob.p0)
    else:
        with _progress(quiet) as bar:
            name = "fit (Levenberg–Marquardt)" if cfg.kind == "fit" else "minimise (augmented Lagrangian)"
            bar.add_task(f"{name}: {prob.parent}", total=None)
            res, m = jax.device_get(cached_call(
                "run", solve_and_measure, (d, prob.p0, prob.lower, prob.upper),
                (cfg.kind, cfg.solver.max_steps, cfg.solver.outer), key=[raw, _file_digest(cfg.hull.parent)]))
        met = bool(res.met)
        report = {
            "kind": cfg.kind,
            "converged": bool(res.solver_ok) and met,
            "met": met,
            "iterations": int(res.steps),
            "max_violation": float(res.max_violation),
            "targets": _target_report(d, m.achieved, m.errors),
            "params": _params_dict(res.params),
        }
        if d.objective is not None:
            report["objective"] = {"name": d.objective.name, "value": float(m.objective),
                                   "parent": float(m.objective_parent)}
        if not met:
            worst = max(report["targets"].items(), key=lambda kv: abs(kv[1]["error"]) / kv[1]["tolerance"])
            report["message"] = (f"the targets cannot be met within the bounds: {worst[0]} is off by "
                                 f"{worst[1]['error']:.3g} (tolerance {worst[1]['tolerance']:.3g}); "
                                 "the closest design found is saved")
        report["history"] = history_record(cfg.kind, res)  # report.html's convergence plot
        if cfg.kind == "fit":
            history = np.asarray(res.history)
            plot_convergence(history[np.isfinite(history)], out / "convergence.png", "step")
        else:  # the objective and the worst constraint per round (the Lagrangian itself rises with μ)
            plot_convergence(np.asarray(res.objective_history), out / "convergence.png", "augmented-Lagrangian round",
                             violation=np.asarray(res.violation_history))
    report["achieved"] = _particulars(m.final)
    report["parent"] = _particulars(m.parent)
    if cfg.kind == "pareto":
        designs = _write_designs(prob, report["designs"], out)
        report["objectives"], active = assess(cfg, prob, designs)
        report["warnings"] = _bound_warnings(prob, report["designs"], "design {k}: ") + active
        o, kinds = report["objectives"], (cfg.sweep.measure.kind, cfg.objective.kind, "bf")
        plot_pareto(report["designs"], *kinds[:2], out / "pareto.png", parent=tuple(o[k]["parent"] for k in kinds))
    else:
        report["objectives"], active = assess(cfg, prob, [res.params])
        report["warnings"] = _bound_warnings(prob, [report]) + active
    write_offsets_wide(m.before, out / "parent_offsets.csv", name="the parent hull", dense=True)
    if cfg.kind != "pareto":  # a sweep's hulls are its designs' (designs/<k>/), not one final hull
        _write_hull(m, d.draft, out)
    write_json(out / "report.json", report)
    # report.html: a sweep's designs are rebuilt from the folder, a run's hulls are the ones measured here
    write_report(out, report, None if cfg.kind == "pareto" else Hulls.of(m.before, m.after, m.areas, d.draft))
    return report


# ----------------------------------------------------------------------------------------------- assessment

SI_UNITS = {"volume": "m³", "displacement": "kg", "wetted_surface": "m²", "lcb": "m", "lcf": "m", "kb": "m",
            "awp": "m²", "bmt": "m", "bml": "m", "kmt": "m", "tpc": "t/cm", "mct": "t·m/cm", "lwl": "m", "bwl": "m",
            "lcb_pct": "% Lpp", "lcf_pct": "% Lpp", "draft": "m"}
ROUGHNESS = 2.0
"""A design's sectional-area curve or sections rougher than this many times the parent's is warned of."""


def report_measures(cfg: RunConfig, d: Design) -> dict:
    """``{name: measure(sections, draft)}`` that a report compares, parent and design: every objective of
    :data:`~hullopt.optimise.OBJECTIVES` its options build (the ``[objective]`` table's; the sweep's measure
    with its own), the constraints' measures and Bf."""
    from pydantic import ValidationError

    out = {}
    base = cfg.objective
    if base is not None:
        for kind in OBJECTIVES:
            try:
                out[kind] = objective_from(ObjectiveConfig.model_validate(base.model_dump() | {"kind": kind}))
            except ValidationError:
                pass  # e.g. a sea state for mean_added_resistance when the objective is calm-water resistance
        out[base.kind] = d.objective
    if cfg.sweep is not None:
        out[cfg.sweep.measure.kind] = objective_from(cfg.sweep.measure)
    for name in cfg.constraints.bounds():
        if name != "station_knuckles":  # one value per station: its activity is warned of, not tabled
            out.setdefault(name, constraint_measure(cfg, name))
    out.setdefault("bf", Particular("bf"))
    return out


def _measure_all(measures: dict, d: Design, p0, designs) -> tuple:
    """The measures of the parent and of each design (params stacked on a leading axis), and each limit
    group's largest normalised value per design."""
    parent = d.model(p0)
    d = with_objective_scale(d, p0)
    out_p = {k: m(parent, d.draft) for k, m in measures.items()}

    def one(params):
        s = d.model(params)
        g = {} if d.limits is None else {k: jnp.max(v) for k, v in d.limits.groups(s, d.draft).items()}
        return {k: m(s, d.draft) for k, m in measures.items()}, g, s

    vals, groups, sections = jax.vmap(one)(designs)
    return out_p, vals, groups, parent, sections


def _assess_program(measures: dict, d: Design, p0, designs) -> tuple:
    """:func:`_measure_all` and the sectional-area curves [m²] at the design draft of the parent ``(n,)`` and of
    each design ``(k, n)``, as one program."""
    p, vals, groups, parent, sections = _measure_all(measures, d, p0, designs)
    areas = jax.vmap(lambda s: sectional_areas(s, d.draft))(sections)
    return p, vals, groups, parent, sections, sectional_areas(parent, d.draft), areas


def _sac_roughness(x, a) -> float:
    """Σ (A'')² Δx of a sectional-area curve ``a (n,)`` [m²] at stations ``x (n,)`` [m], second divided
    differences (m⁻²·m: compared between parent and design only)."""
    x, a = np.asarray(x, float), np.asarray(a, float)
    h0, h1 = np.diff(x)[:-1], np.diff(x)[1:]
    d2 = 2.0 * ((a[2:] - a[1:-1]) / h1 - (a[1:-1] - a[:-2]) / h0) / (h0 + h1)
    return float(np.sum(d2**2 * 0.5 * (h0 + h1)))


# Section offsets closer than this [m] are one point in the section measures: feature points that coincide
# at the parent (a collapsed segment, the deck edge where there is no flat of side) drift apart by 1e-9 m
# under a deformation, and a segment that short turns any way — a 1e-8 step from the KCS parent multiplied its
# section roughness 1e8-fold. No hull's offsets resolve a millimetre.
MERGE = 1e-3


def _section_roughness(yz) -> float:
    """The sections' variation of curvature, mean over stations of Σ (Δκ)²/Δs [m⁻³] of each half-section
    polyline (its centreline and repeated points left out): compared between parent and design only."""
    total = []
    for p in np.asarray(yz, float):
        p = p[p[:, 0] > 1e-9]
        d = np.diff(p, axis=0)
        ds = np.hypot(d[:, 0], d[:, 1])
        d, ds = d[ds > MERGE], ds[ds > MERGE]
        if len(ds) < 3:
            total.append(0.0)
            continue
        t = d / ds[:, None]
        turn = np.arctan2(t[:-1, 0] * t[1:, 1] - t[:-1, 1] * t[1:, 0], np.sum(t[:-1] * t[1:], 1))
        kappa = turn / (0.5 * (ds[:-1] + ds[1:]))
        total.append(float(np.sum(np.diff(kappa) ** 2 / ds[1:-1])))
    return float(np.mean(total))


def sac_roughness(sections: Sections, draft) -> Array:
    """:func:`_sac_roughness` in JAX, as a constraint measure: Σ (A'')² Δx [m²] of the sectional-area curve
    at ``draft`` [m] (second divided differences over the stations; compared with the parent's only)."""
    x, a = sections.x, sectional_areas(sections, draft)
    h0, h1 = jnp.diff(x)[:-1], jnp.diff(x)[1:]
    d2 = 2.0 * ((a[2:] - a[1:-1]) / h1 - (a[1:-1] - a[:-2]) / h0) / (h0 + h1)
    return jnp.sum(d2**2 * 0.5 * (h0 + h1))


def _compact(keep, *arrays):
    """The rows of ``arrays`` where ``keep``, moved to the front in order (the rest after them), and how
    many there are: a fixed-shape stand-in for ``array[keep]``."""
    order = jnp.argsort(~keep, stable=True)
    return (*(v[order] for v in arrays), jnp.sum(keep))


def _turns(p):
    """Turning angles [rad] between neighbouring segments of a half-section polyline ``p (m, 2)`` [m] and the
    segment lengths [m], its centreline points (``y ≤ 1e-9`` m) and segments under :data:`MERGE` left out, as
    fixed-shape arrays: ``(turn (m−2,), ds (m−1,), s)`` with the ``s`` kept segments first (the rest padded:
    turns 0, lengths 1 m). Finite gradients: the left-out entries are replaced before any division or angle."""
    p, k = _compact(jax.lax.stop_gradient(p[:, 0] > 1e-9), p)
    d = jnp.diff(p, axis=0)
    ds = safe_norm(d)
    idx = jnp.arange(d.shape[0])
    d, ds, s = _compact(jax.lax.stop_gradient((idx < k - 1) & (ds > MERGE)), d, ds)
    ok = idx < s
    ds = jnp.where(ok, ds, 1.0)
    t = jnp.where(ok[:, None], d / ds[:, None], jnp.array([1.0, 0.0]))
    cross = t[:-1, 0] * t[1:, 1] - t[:-1, 1] * t[1:, 0]
    return jnp.arctan2(cross, jnp.sum(t[:-1] * t[1:], 1)), ds, s


def section_roughness(sections: Sections, draft=None) -> Array:
    """:func:`_section_roughness` in JAX, as a constraint measure: the mean over stations of Σ (Δκ)²/Δs
    [m⁻³] of each half-section polyline, its centreline and repeated points left out as there (the draft
    unused). A wavy section raises it; compared with the parent's only."""

    def one(p):
        turn, ds, s = _turns(p)
        kappa = turn / (0.5 * (ds[:-1] + ds[1:]))
        terms = jnp.diff(kappa) ** 2 / ds[1:-1]
        return jnp.sum(jnp.where(jnp.arange(terms.shape[0]) + 2 < s, terms, 0.0))

    return jnp.mean(jax.vmap(one)(sections.yz))


def section_knuckle(sections: Sections, draft=None) -> Array:
    """The sections' knuckles, as a constraint measure: the mean over stations of Σ θ⁴ [rad⁴], θ the turning
    angle between neighbouring segments of each half-section polyline (centreline and repeated points left
    out; the draft unused) — a soft maximum of the sharpest turn, which :func:`section_roughness` misses
    where a knuckle sits beside a long segment (a section straight-sided up to just below the waterline, then
    vertical: Σ (Δκ)²/Δs falls while the turn there triples). ``"<= 2 * parent"`` lets no turn grow by more
    than about 2^(1/4) ≈ 1.19× the parent's sharpest where that is one turn (see :func:`station_knuckles` for
    a real hull's). Compared with the parent's on the same offsets only."""
    return jnp.mean(_turns4(sections))


def _turns4(sections: Sections) -> Array:
    """Σ θ⁴ [rad⁴] of each station's turning angles ``(n,)`` (:func:`_turns`)."""

    def one(p):
        turn, _, s = _turns(p)
        return jnp.sum(jnp.where(jnp.arange(turn.shape[0]) + 1 < s, turn**4, 0.0))

    return jax.vmap(one)(sections.yz)


def assess(cfg: RunConfig, prob: Problem, designs: list) -> tuple[dict, list[str]]:
    """``(objectives, warnings)`` of a run: every measure of :func:`report_measures` of the parent and the
    design(s) as ``{name: {"parent", "design" (or "designs", a list for a sweep), "unit"}}`` (SI: N, m, m²,
    m³, kg; ``"-"`` dimensionless), the fairness measures ``unfairness`` (:func:`hullopt.fairing.unfairness`),
    ``sac_roughness`` and ``section_roughness`` (:func:`_sac_roughness`, :func:`_section_roughness`), and
    warnings of the constraints that are active (within their tolerance of the bound) or violated and of a
    sectional-area curve or sections more than :data:`ROUGHNESS` times as rough as the parent's."""
    d = prob.design
    measures = report_measures(cfg, d)
    measures["unfairness"] = _unfairness
    stacked = jax.tree.map(lambda *leaves: np.stack([np.asarray(v) for v in leaves]), *designs)
    # one kept program (no tracing when warm), keyed like the run's: the config and the parent's content
    key = [cfg.model_dump(mode="json"), _file_digest(cfg.hull.parent)]
    p, vals, groups, parent, sections, areas_p, areas_d = jax.device_get(
        cached_call("assess", _assess_program, (measures, d, prob.p0, stacked), (), key=key))
    areas = [np.asarray(areas_p), *np.asarray(areas_d)]
    sac = [_sac_roughness(s.x, a) for s, a in zip((parent, *_unstack(sections)), areas)]
    sec = [_section_roughness(s.yz) for s in (parent, *_unstack(sections))]
    one = len(designs) == 1
    objectives = {}
    for k in measures:
        unit = "-" if k == "unfairness" else getattr(measures[k], "unit", SI_UNITS.get(k, "-"))
        v = [float(x) for x in np.asarray(vals[k])]
        objectives[k] = {"parent": float(p[k]), "design" if one else "designs": v[0] if one else v, "unit": unit}
    for k, r in (("sac_roughness", sac), ("section_roughness", sec)):
        objectives[k] = {"parent": r[0], "design" if one else "designs": r[1] if one else r[1:], "unit": "-"}
    warnings = []
    tol = cfg.constraints.tolerance
    blend = _blend_hint(cfg, prob)
    for i in range(len(designs)):
        who = "" if one else f"design {i}: "
        for k, g in groups.items():
            g = float(np.asarray(g)[i])
            extra = cfg.constraints.model_extra or {}
            what = {"max_half_breadth": "the maximum half-breadth", "bulge": "no bulge below the waterline"}.get(
                k, f"{k} {extra[k]}" if k in extra else k)
            if g > tol:
                warnings.append(f"{who}constraint violated: {what} (by {g:.3g} of its bound)")
            elif g >= -tol and k not in ("max_half_breadth", "bulge"):  # those are on their bound at the parent
                warnings.append(f"{who}constraint active: {what}")
        for k, r in (("sectional-area curve is", sac), ("sections are", sec)):
            if r[i + 1] > ROUGHNESS * r[0] * (1.0 + tol):  # as a constraint at the bound is met
                warnings.append(f"{who}the {k} rougher than the parent's: {r[i + 1] / r[0]:.2f}× "
                                f"(more than {ROUGHNESS:g}×); raise [solver] fairness" + blend * (k == "sections are"))
    warnings += _calm_disagreement(cfg, objectives, parent, d.draft)
    return objectives, warnings


def _calm_disagreement(cfg: RunConfig, objectives: dict, parent: Sections, draft) -> list[str]:
    """A warning when the parent's calm-water R_T by Holtrop–Mennen and by Michell (both in every report with an
    objective) differ by more than :data:`~hullopt.resistance.DISAGREE`, naming the method outside
    its validity (``hullopt resistance --method all`` shows the panel method beside them)."""
    ho, mi = objectives.get("calm_resistance"), objectives.get("calm_resistance_michell")
    if ho is None or mi is None or cfg.objective is None:
        return []
    ratio = max(ho["parent"], mi["parent"]) / max(min(ho["parent"], mi["parent"]), 1e-300)
    if ratio <= DISAGREE:
        return []
    hull = holtrop_hull(parent, draft)
    u = cfg.objective.speed_kn * KNOT
    invalid = outside_validity(hull, u / np.sqrt(G * float(hull.L)))
    high = "michell" if mi["parent"] > ho["parent"] else "holtrop"
    why = "; ".join(f"{m} is outside its validity ({invalid[m]})" for m in ("michell", "holtrop") if m in invalid)
    return [f"calm-water R_T of the parent by {high} is {ratio:.1f}× the other's (holtrop vs michell) at "
            f"{cfg.objective.speed_kn:g} kn" + (f": {why}" if why else "")
            + "; compare the methods with hullopt resistance --method all"]


def _blend_hint(cfg: RunConfig, prob: Problem) -> str:
    """A hint for the section-roughness warning: the distributions that re-read frames where the parent's
    segments change in number (a bulb, a forefoot), which blend frames of different make-up into new shapes."""
    real = np.asarray(prob.design.model.hull.real)
    x = np.asarray(prob.design.model.hull.x)
    changes = x[1:][np.any(real[1:] != real[:-1], -1)]
    bad = [i for i, g in enumerate(cfg.design.distribution)
           if g.curves != "stations" and np.any((changes > g.x_a) & (changes < g.x_b))]
    if not bad:
        return ""
    return (f", or move the frames themselves (curves = \"stations\") in design.distribution[{bad[0]}]: it re-reads "
            f"frames across stations where the parent's segments change in number (x = {changes.min():.0f}…"
            f"{changes.max():.0f} m)")


def _unfairness(sections: Sections, draft) -> Array:
    """:func:`hullopt.fairing.unfairness` as a measure (the draft unused)."""
    from ..fairing import unfairness

    return unfairness(sections)


KNUCKLE_FLOOR = np.deg2rad(5.0) ** 4
"""rad⁴: a station's Σ θ⁴ counts at least this (one 5° turn) in :func:`station_knuckles`, so that a bound
relative to a parent's nearly straight station still allows it a gentle turn."""


def station_knuckles(sections: Sections, draft=None) -> Array:
    """Each station's knuckles ``(n,)`` [rad⁴]: Σ θ⁴ of its turning angles as :func:`section_knuckle`, floored
    at :data:`KNUCKLE_FLOOR`. As a constraint (``"<= 2 * parent"``) every station is held against the
    parent's same station: :func:`section_knuckle`'s mean over stations is ruled by a real hull's sharpest
    turns (on the KCS, 99 % of it is a 66° turn at the skeg and a 72° one at the forefoot), so that twice it
    allowed a new 60° knuckle anywhere else. Not a report measure (it is one value per station)."""
    return jnp.maximum(_turns4(sections), KNUCKLE_FLOOR)


ROUGHNESS_MEASURES = {"unfairness": _unfairness, "sac_roughness": sac_roughness,
                      "section_roughness": section_roughness, "section_knuckle": section_knuckle,
                      "station_knuckles": station_knuckles}
"""The fairness measures a ``[constraints]`` key may name (``name = "<= 2 * parent"``), by function: the
unfairness U (:func:`hullopt.fairing.unfairness`), the sectional-area curve's and the sections' roughness and
the sections' knuckles (in the mean, and station by station)."""


def _unstack(tree) -> list:
    n = np.shape(jax.tree.leaves(tree)[0])[0]
    return [jax.tree.map(lambda a: a[i], tree) for i in range(n)]


def _bound_warnings(prob: Problem, rows: list[dict], who: str = "") -> list[str]:
    """Warnings of parameters within 1 % of their bound (the bound, not the physics, stopped the design)."""
    out = []
    half = prob.upper
    for k, row in enumerate(rows):
        p = params_from_dict(row["params"], prob.p0)
        for name, v, b in (("apex_move", p.apex, half.apex), ("distribution", p.distribution, half.distribution),
                           ("contour_edit", p.contour, half.contour)):
            v, b = np.asarray(v, float), np.asarray(b, float)
            for idx in zip(*np.nonzero(np.abs(v) >= 0.99 * b)):
                out.append(f"{who.format(k=k)}design.{name}[{idx[0]}]"
                           f"{'' if len(idx) == 1 else f' component {idx[1]}'} = {v[idx]:.4g} is within 1 % of its "
                           f"bound ±{b[idx]:.4g}")
    return out


def _write_designs(prob: Problem, rows: list[dict], out: Path) -> list:
    """Each design of a sweep in ``designs/<k>/`` as a run's hull: ``hull.stl``, ``offsets.csv`` and the
    body-plan and sectional-area plots against the parent; returns their parameters."""
    params = [params_from_dict(r["params"], prob.p0) for r in rows]
    d = prob.design
    m = eqx.filter_jit(measure)
    for k, p in enumerate(params):
        _write_hull(jax.device_get(m(d, prob.p0, p)), d.draft, out / "designs" / str(k))
    return params


def _write_hull(m: Outcome, draft, out: Path) -> None:
    """Write the final hull's files to ``out``: ``hull.stl`` [m] (refined along the length and welded for
    float32, checked as read back: closed, one body, no degenerate face — :func:`~hullopt.geometry._mesh.
    export_mesh`), ``offsets.csv`` (dense enough that ``hullopt hydro offsets.csv`` gives the run's ∇ back;
    knuckles and deck carried), and the body-plan and sectional-area plots at ``draft`` [m]."""
    from .plots import plot_body_plans, plot_sectional_areas

    write_hull_file(m.after, out / "hull.stl", float(draft))
    write_offsets_wide(m.after, out / "offsets.csv", name="the designed hull", dense=True)
    plot_body_plans(m.before, m.after, out / "body_plan.png", draft=float(draft),
                    title=f"Body plan: parent (dashed) and design {out.name} (stations 0 AP … 10 FP)")
    plot_sectional_areas(m.before.x, m.after.x, m.areas, draft, out / "sectional_area.png")


def _progress(quiet: bool, counted: bool = False) -> Progress:
    """A transient progress display: a spinner with the elapsed time, plus a bar and "k/N" when ``counted``."""
    counts = [BarColumn(), MofNCompleteColumn()] if counted else []
    return Progress(SpinnerColumn(), TextColumn("{task.description}"), *counts, TimeElapsedColumn(),
                    console=console, disable=quiet or not console.is_terminal, transient=True)


# ----------------------------------------------------------------------------------------------- sweeps


def _pareto(cfg: RunConfig, prob: Problem, out: Path, quiet: bool, shard=(1, 1), executor: str = "local",
            address: str | None = None) -> dict:
    """ε-constraint sweep on Bf (see :mod:`hullopt.app.sweep`): this shard's chunks are solved and written
    to ``chunks/``; when every chunk is there the report of the whole sweep, else a partial report
    (``partial``: true, ``chunks_done``, ``chunks_total``, ``designs`` of the chunks done)."""
    from .sweep import SweepPlan, run_chunks

    plan = SweepPlan(cfg, prob)
    n_mine = len(range(shard[0] - 1, plan.n_chunks, shard[1]))
    with _progress(quiet, counted=True) as bar:
        task = bar.add_task("Pareto sweep" + (f" shard {shard[0]}/{shard[1]}" if shard[1] > 1 else ""), total=n_mine)
        designs = run_chunks(plan, out, shard, executor, address, progress=lambda n: bar.update(task, advance=n))
    if designs is None:
        done = [k for k in range(plan.n_chunks) if plan.load(plan.path(out / "chunks", k), k) is not None]
        rows = [r for k in done for r in plan.load(plan.path(out / "chunks", k), k)]
        met = all(r["met"] for r in rows)
        return {"kind": "pareto", "partial": True, "shard": f"{shard[0]}/{shard[1]}", "converged": met, "met": met,
                "chunks_done": done, "chunks_total": plan.n_chunks, "designs": rows}
    pts = jnp.asarray([[r["measure"], r["objective"]] if r["met"] else [np.nan, np.nan] for r in designs])
    front = np.asarray(non_dominated(pts))
    for r, f in zip(designs, front):
        r["pareto"] = bool(f)
    met = all(r["met"] for r in designs)
    return {"kind": "pareto", "converged": met, "met": met, "iterations": sum(r["iterations"] for r in designs),
            "targets": {k: float(v) for k, v in cfg.targets.items()}, "designs": designs,
            "objective": {"name": cfg.objective.kind, "measure": cfg.sweep.measure.kind},
            "pareto_count": int(front.sum())}


def merge(dirs: list[Path], out: Path, quiet: bool = False) -> dict:
    """Combine the run folders of the shards of one sweep into ``out``: the same folder and report as the
    unsplit sweep (nothing is solved; :class:`HullError` if a chunk is missing)."""
    from .sweep import collect_chunks

    cfg, raw = collect_chunks(list(dirs), out)
    return run(cfg, raw, out, quiet)
