"""The design problem of a config: the feature model, its start point and bounds, the targets, the objective and
the limits (:class:`~hullopt.optimise.Design`). No hull is evaluated here; the parent comes in built."""

from __future__ import annotations

from dataclasses import dataclass

import jax
import numpy as np

from ..errors import HullError
from ..fairing import SHAPE_MEASURES
from ..models import (
    ApexMove,
    BowAttachment,
    ContourEdit,
    Distribution,
    FeatureHull,
    FeatureParams,
    feature_model,
)
from ..optimise import OBJECTIVES, Design, Limits, Particular, RegionVolume, make_targets
from ._config import DesignConfig, RunConfig


@dataclass
class Problem:
    """A design problem built from a config, with its start point and bounds."""

    design: Design
    p0: FeatureParams
    lower: FeatureParams
    upper: FeatureParams
    parent: str  # the config's ``[hull] parent``


def design_params(d: DesignConfig, hull: FeatureHull, where: str = "design.", draft: float | None = None) -> tuple:
    """The feature model of a design's tables on ``hull``, its start parameters and the half-widths of its bounds.

    Shared by ``hullopt run`` and ``hullopt deform``. The parameters are numpy leaves: no JAX op runs.

    Parameters
    ----------
    d : DesignConfig
        The design's tables (``[[apex_move]]``, ``[[distribution]]``, ``[[contour_edit]]``).
    hull : FeatureHull
        The parent's feature curves.
    where : str
        The field's prefix in error messages (``"design."`` for a run config).
    draft : float or None
        The draft [m] a bow attachment's stem is found at; None: the parent's design draft.

    Returns
    -------
    tuple of (FeatureModel, FeatureParams, FeatureParams)
        ``(model, p0, half)``: the feature model, its start parameters (apex moves ``(K, 2)`` (dy, dz) [m],
        warp coefficients ``(G, modes)``, contour-edit amplitudes ``(E,)`` [m]) and the half-widths of their bounds
        (a start value lies strictly inside: ``|p0| < half``).

    Raises
    ------
    HullError
        An inconsistent design (:func:`~hullopt.models.feature_model`), a distribution with more ``c`` values
        than modes, or a start value not inside its bound; the message names the field (``where`` + table).
    """
    model = feature_model(
        hull,
        [ApexMove(m.segment, m.x_fixed1, m.x_moved, m.x_fixed2, m.profile) for m in d.apex_move],
        [Distribution(g.x_a, g.x_b, g.curves if isinstance(g.curves, str) else tuple(g.curves), g.modes)
         for g in d.distribution],
        [ContourEdit(e.line, e.x_a, e.x_b, e.shape) for e in d.contour_edit],
        [BowAttachment(b.x_blend, b.z_lo, np.inf if b.z_hi is None else b.z_hi, b.blend, b.x_peak, b.x_stem, b.mode)
         for b in d.bow],
        beam=d.beam is not None, draft=draft, draft_scale=d.draft is not None,
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
    beam = [] if d.beam is None else [d.beam]
    scale = [] if d.draft is None else [d.draft]
    p0 = FeatureParams(np.array([m.d for m in d.apex_move], float).reshape(-1, 2), dist0,
                       np.array([e.amplitude for e in d.contour_edit], float), np.array([b.a for b in d.bow], float),
                       np.array([b.s for b in beam], float), np.array([b.s for b in scale], float))
    half = FeatureParams(np.array([[m.bound] * 2 for m in d.apex_move], float).reshape(-1, 2), dist_b,
                         np.array([e.bound for e in d.contour_edit], float), np.array([b.bound for b in d.bow], float),
                         np.array([b.bound for b in beam], float), np.array([b.bound for b in scale], float))
    for name, v, b in (("apex_move d", p0.apex, half.apex), ("distribution c", p0.distribution, half.distribution),
                       ("contour_edit amplitude", p0.contour, half.contour), ("bow a", p0.bow, half.bow),
                       ("beam s", p0.beam, half.beam), ("draft s", p0.draft, half.draft)):
        if np.any(np.abs(np.asarray(v)) >= np.asarray(b)):
            raise HullError(f"{where.rstrip('.') or 'design'}: a start value of {name} is not inside its bound")
    return model, p0, half


def build_problem(cfg: RunConfig, parent: FeatureHull, fairness: float, limits: bool) -> Problem:
    """The :class:`~hullopt.optimise.Design`, start and bounds of a config on the feature hull ``parent``, with
    the fairness weight ``fairness`` and, when ``limits``, the ``[constraints]`` (a study decides both);
    :class:`HullError` on a bad design.

    The objective and fairness scales (their values at the parent) are set by
    :func:`~hullopt.optimise.with_objective_scale` inside the jitted solve programs."""
    draft = cfg.hull.draft or parent.design_draft
    if draft is None:
        raise HullError(f"hull.draft: parent {cfg.hull.parent!r} has no design draft; give one")
    keel, deck = float(np.min(np.asarray(parent.keel)[:, 1])), float(np.max(np.asarray(parent.deck)[:, 1]))
    lo = max(0.0, keel)
    if not lo < draft <= deck:  # above the deck the hull is submerged: no waterplane, nothing to design
        where = "above the deck" if draft > deck else "outside the hull"
        raise HullError(f"hull.draft = {draft:g} m is {where} of {cfg.hull.parent!r}: expected a draft in "
                        f"({lo:g}, {deck:g}] m (keel or baseline to deck)")
    check_freeboard(cfg, parent, float(draft))
    if limits:
        check_regions(cfg, parent)
    model, p0, half = design_params(cfg.design, parent, draft=float(draft))
    lower = jax.tree.map(lambda h: -h, half)
    try:
        targets = make_targets(cfg.targets, cfg.tolerances, cfg.kg, cfg.hull.bf_band)
    except ValueError as e:
        raise HullError(f"targets: {e}") from None
    design = Design(model=model, draft=np.asarray(float(draft)), targets=targets,
                    objective=cfg.objective.build() if cfg.objective else None,
                    smoothness=cfg.solver.smoothness, param_scale=half, fairness=float(fairness),
                    limits=limits_from(cfg) if limits else None)
    return Problem(design, p0, lower, half, cfg.hull.parent)


def check_freeboard(cfg: RunConfig, parent: FeatureHull, draft: float) -> None:
    """:class:`HullError` naming the distribution that would re-read frames whose deck edge is at the draft (an
    offset table that stops at the DWL). Re-read frames blend the parent's feature points along the length
    (:mod:`hullopt.models._features`), which moves the deck edge by centimetres: where it sinks below the
    draft the waterline leaves the hull, its breadth there reads zero and the optimiser takes the lost
    waterplane as a design change (a Series 60 fit lost 18 % of its waterplane so)."""
    x, deck = np.asarray(parent.x), np.asarray(parent.deck)[:, 1]
    flush = deck <= draft + 1e-9 * max(1.0, draft)
    for i, g in enumerate(cfg.design.distribution):
        inside = flush & (x > g.x_a) & (x < g.x_b)
        if g.curves != "stations" and inside.any():
            at = x[inside]
            raise HullError(
                f"design.distribution[{i}]: {cfg.hull.parent!r} has no freeboard at x = {at.min():.4g}…"
                f"{at.max():.4g} m (its deck edge is at hull.draft = {draft:g} m: offsets that stop at the DWL); "
                f"re-reading its frames along the length (curves = {g.curves!r}) moves that edge by centimetres "
                "and the waterline off the hull. Move the frames themselves (curves = \"stations\") or give "
                "the parent sections above the waterline")


def check_regions(cfg: RunConfig, parent: FeatureHull) -> None:
    """:class:`HullError` naming a ``[[constraints.region_volume]]`` that holds none of the parent: forward of its
    last station, aft of its first or below its keel (a bound on nothing would be met by any design)."""
    x, keel = np.asarray(parent.x), float(np.min(np.asarray(parent.keel)[:, 1]))
    for i, r in enumerate(cfg.constraints.region_volume):
        where = f"constraints.region_volume[{i}] ({r.name})"
        if r.x_a is not None and r.x_a >= x[-1] or r.x_b is not None and r.x_b <= x[0]:
            raise HullError(f"{where}: x_a … x_b = {r.x_a if r.x_a is not None else '–'} … "
                            f"{r.x_b if r.x_b is not None else '–'} m is off {cfg.hull.parent!r}, whose stations "
                            f"run {x[0]:.4g} … {x[-1]:.4g} m from the AP")
        if r.z_top is not None and r.z_top <= keel:
            raise HullError(f"{where}: z_top = {r.z_top:g} m is at or below the keel of {cfg.hull.parent!r} "
                            f"({keel:.4g} m): the region holds no volume")


def constraint_measure(cfg: RunConfig, name: str):
    """The measure a ``[constraints]`` key names: an objective (with the options of
    :meth:`~hullopt.study.RunConfig.constraint_options`), a shape measure
    (:data:`~hullopt.fairing.SHAPE_MEASURES`), a region's volume (``region_volume:<name>``, a
    :class:`~hullopt.optimise.RegionVolume`) or a :class:`~hullopt.optimise.Particular`."""
    if name in SHAPE_MEASURES:
        return SHAPE_MEASURES[name]
    region = cfg.constraints.regions().get(name)
    if region is not None:
        ends = (region.x_a, -np.inf), (region.x_b, np.inf), (region.z_top, np.inf)
        return RegionVolume(*(np.asarray(default if v is None else float(v)) for v, default in ends))
    return cfg.constraint_options(name).build() if name in OBJECTIVES else Particular(name, cfg.hull.bf_band)


def limits_from(cfg: RunConfig) -> Limits:
    """The :class:`~hullopt.optimise.Limits` of a config's ``[constraints]``.

    Defaults: half-breadths within the parent's, no new bulge below the waterline, the local shape limits
    :data:`~hullopt.study.DEFAULT_LIMITS` and a bulb at either end frozen. A measure bounded on both sides is
    two entries of one name (:class:`~hullopt.optimise.Limits`).

    Parameters
    ----------
    cfg : RunConfig
        The run config; its ``[constraints]`` and, for an objective as a constraint, its objective options.

    Returns
    -------
    Limits
        The bounds' names, measures, senses (+1 at most, −1 at least), values (SI, or factors of the parent's
        where ``relative``) and margins [SI], the largest half-breadth [m] (NaN: the parent's; None: no limit),
        ``bulge``, the frozen stations and the tolerance.
    """
    c = cfg.constraints
    bounds = c.bounds()
    measures = {k: constraint_measure(cfg, k) for k in bounds}
    sides = [(k, b) for k, both in bounds.items() for b in both]  # a two-sided bound: two entries of one name
    mhb = {"parent": np.nan, "none": None}.get(c.max_half_breadth, c.max_half_breadth)
    frozen = c.frozen if isinstance(c.frozen, str) else tuple(map(tuple, c.frozen))
    return Limits(names=tuple(k for k, _ in sides), measures=tuple(measures[k] for k, _ in sides),
                  sense=np.array([b.sense for _, b in sides], float),
                  values=np.array([b.value for _, b in sides], float),
                  relative=tuple(b.relative for _, b in sides),
                  margins=np.array([b.margin for _, b in sides], float),
                  max_half_breadth=None if mhb is None else np.asarray(float(mhb)),
                  bulge=c.bulge == "forbid", frozen=frozen, tol=c.tolerance)


PARAM_KEYS = ("apex_move_d", "distribution_c", "contour_edit_amplitude", "bow_a", "beam_s", "draft_s")
"""The keys of a report's ``params``: the leaves of :class:`~hullopt.models.FeatureParams` in order."""


def params_to_dict(p: FeatureParams) -> dict:
    """A design's parameters as a report's ``params``.

    Parameters
    ----------
    p : FeatureParams
        The parameters: apex moves ``(K, 2)`` [m], warp coefficients ``(G, modes)``, contour-edit amplitudes
        ``(E,)`` [m].

    Returns
    -------
    dict
        ``{key: nested list}`` under :data:`PARAM_KEYS` (``apex_move_d``, ``distribution_c``,
        ``contour_edit_amplitude``).
    """
    return {k: np.asarray(v).tolist() for k, v in zip(PARAM_KEYS, _leaves(p))}


def _leaves(p: FeatureParams) -> tuple:
    return p.apex, p.distribution, p.contour, p.bow, p.beam, p.draft


def stack_params(params: list[FeatureParams]) -> FeatureParams:
    """Parameters stacked on a new leading axis (one row a design), as numpy float arrays, for a vmapped program.

    Parameters
    ----------
    params : list of FeatureParams
        The designs' parameters, all of one structure.

    Returns
    -------
    FeatureParams
        Each leaf ``(len(params), ...)``.
    """
    return jax.tree.map(lambda *a: np.stack([np.asarray(v, float) for v in a]), *params)


def stacked_like(p0: FeatureParams, n: int) -> FeatureParams:
    """The shapes :func:`stack_params` gives ``n`` designs of ``p0``'s structure, as
    :class:`jax.ShapeDtypeStruct` leaves (a program prepared before the designs exist)."""
    return jax.tree.map(lambda a: jax.ShapeDtypeStruct((n, *np.shape(a)), np.float64), p0)


def params_from_dict(values: dict, like: FeatureParams) -> FeatureParams:
    """The parameters of a report's ``params`` (the inverse of :func:`params_to_dict`).

    Parameters
    ----------
    values : dict
        A report's ``params``: nested lists under :data:`PARAM_KEYS`.
    like : FeatureParams
        The problem's start point, whose leaves' shapes the values take.

    Returns
    -------
    FeatureParams
        The parameters, numpy float leaves shaped as ``like``'s.

    Raises
    ------
    HullError
        When a key is missing or the values do not fit the problem's shapes.
    """
    try:
        # a report written before a leaf existed has no key for it: an empty leaf
        leaves = [np.asarray(values[k] if k in values or np.size(ref) else [], float).reshape(np.shape(ref))
                  for k, ref in zip(PARAM_KEYS, _leaves(like))]
    except (KeyError, ValueError, TypeError) as e:
        raise HullError(f"the report's params do not fit the run's design ({type(e).__name__}: {e})") from None
    return FeatureParams(*leaves)


def bound_warnings(prob: Problem, params: list[FeatureParams], who: str = "") -> list[str]:
    """Warnings of parameters within 1 % of their bound (the bound, not the physics, stopped the design);
    ``who`` is formatted with ``k``, the design's index."""
    out = []
    half = prob.upper
    for k, p in enumerate(params):
        for name, v, b in zip(("apex_move", "distribution", "contour_edit", "bow", "beam", "draft"), _leaves(p),
                                 _leaves(half)):
            v, b = np.asarray(v, float), np.asarray(b, float)
            for idx in zip(*np.nonzero(np.abs(v) >= 0.99 * b)):
                out.append(f"{who.format(k=k)}design.{name}[{idx[0]}]"
                           f"{'' if len(idx) == 1 else f' component {idx[1]}'} = {v[idx]:.4g} is within 1 % of its "
                           f"bound ±{b[idx]:.4g}")
    return out
