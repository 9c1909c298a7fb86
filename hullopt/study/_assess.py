"""A study's second look at its designs: every measure a report compares (each objective kind the config's
options build, the constraints' measures, Bf, the shape measures) of the parent and each design, in one kept
program, and the warnings a naval architect needs (active or violated constraints, a rougher hull than the
parent's, calm-water methods that disagree)."""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from pydantic import ValidationError

from ..constants import KNOT, G
from ..fairing import ARRAY_MEASURES, SHAPE_MEASURES, SHAPE_UNITS
from ..models import FeatureParams
from ..optimise import OBJECTIVES, Design, Particular
from ..resistance import DISAGREE, HoltropHull, holtrop_hull, outside_validity
from ._config import RunConfig, options_as
from ._problem import Problem, constraint_measure, stack_params
from ._programs import cached_call

SI_UNITS = {"volume": "m³", "displacement": "kg", "wetted_surface": "m²", "lcb": "m", "lcf": "m", "kb": "m",
            "awp": "m²", "bmt": "m", "bml": "m", "kmt": "m", "tpc": "t/cm", "mct": "t·m/cm", "lwl": "m", "bwl": "m",
            "lcb_pct": "% Lpp", "lcf_pct": "% Lpp", "draft": "m", **SHAPE_UNITS}
"""The units of the particulars and shape measures a report tables (an objective carries its own)."""

ROUGHNESS = 2.0
"""A design's sectional-area curve or sections rougher than this many times the parent's is warned of."""

COMPARED = ("unfairness", "sac_roughness", "section_roughness", "entrance_angle", "run_angle")
"""The shape measures every report compares, parent and design (the roughness warnings read sac_roughness and
section_roughness; the largest waterline half-angles of entrance and run, in rad)."""


def report_measures(cfg: RunConfig, d: Design) -> dict:
    """``{name: measure(sections, draft)}`` that a report compares, parent and design: every objective kind the
    ``[objective]`` table's options build (the sweep's measure with its own), the constraints' measures
    (those with one value a station, height or region, :data:`~hullopt.fairing.ARRAY_MEASURES`, left out), Bf
    and :data:`COMPARED`."""
    out = {}
    base = cfg.objective
    if base is not None:
        for kind in OBJECTIVES:
            try:
                options = options_as(base, kind)
            except ValidationError:
                continue  # e.g. a sea state for mean_added_resistance when the objective is calm-water resistance
            if kind == "calm_resistance" and kind != base.kind:  # Holtrop's, beside Michell's, whatever the
                options = options.model_copy(update={"method": None})  # objective's method
            out[kind] = options.build()
        out[base.kind] = d.objective
    if cfg.sweep is not None:
        out[cfg.sweep.measure.kind] = cfg.sweep.measure.build()
    for name in cfg.constraints.bounds():
        if name not in ARRAY_MEASURES:
            out.setdefault(name, constraint_measure(cfg, name))
    out.setdefault("bf", Particular("bf", cfg.hull.bf_band))
    for name in COMPARED:
        out.setdefault(name, SHAPE_MEASURES[name])
    return out


def _assess_program(measures: dict, d: Design, p0, designs) -> tuple:
    """The measures of the parent and of each design (params stacked on a leading axis), and each limit group's
    largest normalised value of the parent and per design. The parent is mapped with the
    designs, as the first of the batch: traced once, the measures compile once (traced apart, the parent
    doubled the program and its compile)."""
    parent, t0 = d.hull(p0)
    if d.limits is not None:  # the limits measured against the parent's shape
        d = eqx.tree_at(lambda d: d.limits, d, d.limits.at_parent(parent, t0))

    def one(params):
        s, t = d.hull(params)  # each design at its own draft (a draft scale)
        g = {} if d.limits is None else {k: jnp.max(v) for k, v in d.limits.groups(s, t).items()}
        return {k: m(s, t) for k, m in measures.items()}, g

    both = jax.tree.map(lambda a, b: jnp.concatenate([jnp.asarray(a)[None], b]), p0, designs)
    vals, groups = jax.vmap(one)(both)
    first, rest = (lambda t: jax.tree.map(lambda a: a[0], t)), (lambda t: jax.tree.map(lambda a: a[1:], t))
    return first(vals), first(groups), rest(vals), rest(groups)


def assess_program(cfg: RunConfig, prob: Problem, stacked, key) -> tuple:
    """The arguments of :func:`~hullopt.study.cached_call` (or :func:`~hullopt.study.prepare_call`) of the
    assessment of the designs ``stacked`` (:func:`~hullopt.study.stack_params`; to prepare it, their shapes).
    Quick for one design (a fit's, a minimisation's): it then evaluates two hulls once (the demo fit's: compile
    1.6 -> 0.65 s, run 3 -> 5 ms); a sweep's maps every design."""
    d = prob.design
    one = jax.tree.leaves(stacked)[0].shape[0] == 1
    return "assess", _assess_program, (report_measures(cfg, d), d, prob.p0, stacked), (), key, one


LIMIT_NAMES = {"max_half_breadth": "the maximum half-breadth", "bulge": "no bulge below the waterline",
               "frozen": "the frozen stations"}
"""How the warnings name the limits that are no ``[constraints]`` bound."""


def assess(cfg: RunConfig, prob: Problem, designs: list[FeatureParams], key) -> tuple[dict, dict, list[str]]:
    """``(objectives, limits, warnings)`` of a study's designs: every measure of :func:`report_measures` of
    the parent and the design(s) as ``{name: {"parent", "design" (or "designs", a list for several),
    "unit"}}`` (SI); each limit's largest normalised value ``g`` (≤ 0 met; :class:`~hullopt.optimise.Limits`)
    the same way, with its ``bound``; and warnings of the constraints that are active (within their tolerance
    of the bound where the parent is not) or violated, of a sectional-area curve or sections more than
    :data:`ROUGHNESS` times as rough as the parent's and of calm-water methods that disagree. ``key``: the
    study's (what the kept program depends on)."""
    call = assess_program(cfg, prob, stack_params(designs), key)
    measures = call[2][0]
    p, g_p, vals, groups = jax.device_get(cached_call(*call))
    one = len(designs) == 1
    key_ = "design" if one else "designs"

    def entry(parent_value, values, **more):
        v = [float(x) for x in np.asarray(values)]
        return {"parent": float(parent_value), key_: v[0] if one else v, **more}

    objectives = {k: entry(p[k], vals[k], unit=getattr(m, "unit", SI_UNITS.get(k, "-"))) for k, m in measures.items()}
    written = cfg.constraints.written()
    tol = cfg.constraints.tolerance
    limits = {k: entry(g_p[k], groups[k], bound=written.get(k, LIMIT_NAMES.get(k, k)), tolerance=tol) for k in groups}
    warnings = []
    blend = blend_hint(cfg, prob)
    for i in range(len(designs)):
        who = "" if one else f"design {i}: "
        for k, g in groups.items():
            g = float(np.asarray(g)[i])
            what = f"{k} {written[k]}" if k in written else LIMIT_NAMES.get(k, k)
            if g > tol:
                warnings.append(f"{who}constraint violated: {what} (by {g:.3g} of its bound)")
            elif g >= -tol and float(g_p[k]) < -tol:  # pushed to its bound (the parent is not on it)
                warnings.append(f"{who}constraint active: {what}")
        for k, what in (("sac_roughness", "sectional-area curve is"), ("section_roughness", "sections are")):
            r0, r = float(p[k]), float(np.asarray(vals[k])[i])
            if r > ROUGHNESS * r0 * (1.0 + tol):  # as a constraint at the bound is met
                warnings.append(f"{who}the {what} rougher than the parent's: {r / r0:.2f}× "
                                f"(more than {ROUGHNESS:g}×); raise [solver] fairness"
                                + blend * (k == "section_roughness"))
    if cfg.objective is not None:
        warnings += calm_disagreement(cfg, objectives, parent_particulars(prob, key))
    return objectives, limits, warnings


def parent_particulars(prob: Problem, key) -> HoltropHull:
    """Holtrop–Mennen's inputs (:func:`~hullopt.resistance.holtrop_hull`) measured on the parent at the design
    draft, through a kept program (``key``: the study's). Evaluated op by op instead, a cold run compiled ~400
    small programs for them (13 s of the KCS sweep's assessment, as much again in its rescoring)."""
    return jax.device_get(cached_call("parent-particulars", _parent_particulars,
                                      (prob.design.model, prob.p0, np.asarray(prob.design.draft)), (), key=key,
                                      quick=True))


def _parent_particulars(model, p0, draft) -> HoltropHull:
    return holtrop_hull(model(p0), draft * model.draft_factor(p0))


def calm_disagreement(cfg: RunConfig, objectives: dict, hull: HoltropHull) -> list[str]:
    """A warning when the parent's calm-water R_T by Holtrop–Mennen and by Michell (both in every report with an
    objective) differ by more than :data:`~hullopt.resistance.DISAGREE`, naming the method outside
    its validity (``hullopt resistance --method all`` shows the panel method beside them); ``hull``: the parent's
    particulars (:func:`parent_particulars`)."""
    ho, mi = objectives.get("calm_resistance"), objectives.get("calm_resistance_michell")
    if ho is None or mi is None or cfg.objective is None:
        return []
    ratio = max(ho["parent"], mi["parent"]) / max(min(ho["parent"], mi["parent"]), 1e-300)
    if ratio <= DISAGREE:
        return []
    o = cfg.objective
    profile = getattr(o, "profile", None)
    speeds = [p.speed_kn for p in profile] if profile else list(getattr(o, "speeds_kn", None) or [o.speed_kn])
    u = max(speeds) * KNOT  # the fastest point: the furthest from a slender, slow hull's validity
    invalid = outside_validity(hull, u / np.sqrt(G * float(hull.L)))
    high = "michell" if mi["parent"] > ho["parent"] else "holtrop"
    why = "; ".join(f"{m} is outside its validity ({invalid[m]})" for m in ("michell", "holtrop") if m in invalid)
    at = f"{min(speeds):g}–{max(speeds):g} kn" if min(speeds) < max(speeds) else f"{speeds[0]:g} kn"
    return [f"calm-water R_T of the parent by {high} is {ratio:.1f}× the other's (holtrop vs michell) at "
            f"{at}" + (f": {why}" if why else "")
            + "; compare the methods with hullopt resistance --method all"]


def blend_hint(cfg: RunConfig, prob: Problem) -> str:
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
