"""A second opinion on a study's designs: each design and the parent re-scored by every calm-water method
(Holtrop–Mennen, Michell, the panel method, and Dawson's on a full or bulbous parent: :func:`calm_methods`)
and every added-resistance method a naval architect compares (NMRI, SNNM, STAWAVE-2), over the config's
operating profile and off it (±10 % speed, ±2 s T_p). In each kind the run claims a gain in (the objective's,
and a Pareto sweep's measure's) a gain counts only if a method other than the objective's own, and inside its
validity on the parent, finds the design lower than the parent at the profile (by more than :data:`HOLDS`: a
method blind to the change confirms nothing) and nowhere higher off it; in the other kind, if one finds it
nowhere higher. Where the objective is the sum of both (an operating profile with sea states) its gain counts
only if a pair of such methods, not both the objective's own, finds the sum so. Each design where that fails
is warned of.

The operating points (:func:`conditions`): an operating-profile objective's own, else the objective's speeds
with the sea state of the objective or of the sweep's measure. Each method's value is the profile's weighted
mean, in the conditions :data:`CONDITIONS` (no sea state anywhere: no added-resistance opinion, and the report
says so).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from ..constants import G, KNOT
from ..models import FeatureParams
from ..optimise import point_groups, vmap_grouped
from ..resistance import HoltropHull, calm_water, outside_validity
from ..waves import mean_added_resistance
from ._assess import parent_particulars
from ._config import RunConfig
from ._problem import Problem, stack_params
from ._programs import cached_call

RESCORE_WAVES = ("nmri", "snnm", "stawave2")
"""The added-resistance methods a design is re-scored by (STAWAVE-1 is STAWAVE-2's simpler sibling)."""

SPEED_FACTORS = (0.9, 1.0, 1.1)
"""Off the profile: the speeds a design is re-scored at, as factors of the profile's (reported)."""

TP_SHIFTS = (-2.0, 0.0, 2.0)
"""s: the peak periods a design is re-scored at, as shifts of the sea states' (reported)."""

HOLDS = 1e-3
"""A design holds a gain under a method when its value is at most the parent's times (1 + HOLDS) in every
condition (the constraints' default tolerance)."""


def _own_method(cfg: RunConfig) -> dict[str, str | None]:
    """The method of each kind the run claims a gain in (``None``: none of that kind): the objective's, and a
    Pareto sweep's measure's (the front's other axis)."""
    own = {"calm": None, "waves": None}
    for o in (cfg.objective, getattr(cfg.sweep, "measure", None)):
        if o is None:
            continue
        if o.kind in ("calm_resistance", "calm_resistance_michell", "calm_resistance_dawson", "profile_resistance",
                      "profile_power"):
            own["calm"] = own["calm"] or o.method or o.build().method
        if o.kind == "mean_added_resistance" or (o.kind.startswith("profile_") and o.build().waves):
            own["waves"] = "nmri"
    return own


def _combined(cfg: RunConfig) -> bool:
    """Whether the objective itself is calm-water plus added resistance (an operating profile with sea states):
    then its gain is the sum's, and either part may rise."""
    o = cfg.objective
    return o is not None and o.kind in ("profile_resistance", "profile_power") and o.build().waves


def _confirmed(methods: dict, kind: str, k: int) -> tuple[bool | None, str | None]:
    """Whether design ``k`` holds in ``kind`` under a method other than the run's own and inside its validity,
    and the warning where it does not. Where the run's own method finds a gain (lower than the parent's by more
    than :data:`HOLDS`) such a method must find one too; else it must find no loss. ``None`` (and no warning)
    where no method can judge it: every other one outside its validity or blind to the mechanism."""
    others = [m for m in methods.values() if m["kind"] == kind and not m["own"]]
    independent = [m for m in others if not m.get("outside_validity") and not m.get("blind")]
    if not independent:
        return None, None
    claimed = any(m["own"] and m["change_pct"][k] < -100.0 * HOLDS for m in methods.values() if m["kind"] == kind)
    what = "calm-water resistance" if kind == "calm" else "added resistance in waves"
    worst = ", ".join(f"{m['method']} {m['change_pct'][k]:+.2f} % (worst {m['worst_pct'][k]:+.2f} %)"
                      for m in independent)
    if any(m.get("outside_validity") for m in others):
        worst += "; not counted, outside their validity on the parent: " + ", ".join(
            f"{m['method']} {m['change_pct'][k]:+.2f} %" for m in others if m.get("outside_validity"))
    if any(m.get("blind") for m in others):
        worst += "; not counted, blind to the mechanism (NMRI's C_U): " + ", ".join(
            f"{m['method']} {m['change_pct'][k]:+.2f} %" for m in others if m.get("blind"))
    if claimed:
        held = any(m["holds"][k] and m["change_pct"][k] < -100.0 * HOLDS for m in independent)
        return held, None if held else (f"design {k}: its gain in {what} is not confirmed by any independent method "
                                        f"(lower than the parent's at the profile, and nowhere higher off it): {worst}")
    held = any(m["holds"][k] for m in independent)
    return held, None if held else (f"design {k}: no independent method finds its {what} at or below the parent's "
                                    f"in every condition of the profile and off it: {worst}")


def _total_holds(values: dict, methods: dict, k: int) -> tuple[bool, str]:
    """Whether design ``k``'s calm-water R_T plus mean R_AW (each the profile's weighted mean) is lower than the
    parent's at the profile by more than :data:`HOLDS` and nowhere higher off it, under a pair of methods
    other than the objective's own pair; and the pairs' changes as text."""
    held, parts = False, []
    for c, m_c in ((n, m) for n, m in methods.items() if m["kind"] == "calm" and not m.get("outside_validity")):
        for w, m_w in ((n, m) for n, m in methods.items() if m["kind"] == "waves"):
            if m_c["own"] and m_w["own"]:
                continue
            calm = np.asarray(values[c], float)[:, :3]
            calm = np.concatenate([calm, calm[:, :1].repeat(len(CONDITIONS) - 3, axis=1)], axis=1)
            t = calm + np.asarray(values[w], float)  # (1 + k, conditions)
            change = 100.0 * (t[k + 1] / t[0] - 1.0)
            ok = bool(change[0] < -100.0 * HOLDS and np.all(t[k + 1] <= t[0] * (1.0 + HOLDS)))
            held |= ok
            parts.append(f"{m_c['method']} + {m_w['method']} {change[0]:+.2f} % (worst {change.max():+.2f} %)")
    return held, ", ".join(parts)


def conditions(cfg: RunConfig) -> dict:
    """The operating points of :func:`rescore` (config units): ``speeds_kn``, ``weights`` and per point a
    ``sea_states`` entry ``[hs, tp, heading_deg]`` or None (calm water only). An operating-profile objective
    gives its points; another objective its speeds (``speeds_kn`` and ``weights``, else ``speed_kn``) with the
    sea state of the objective or of the sweep's measure when either is ``mean_added_resistance`` (else none)."""
    o = cfg.objective
    profile = getattr(o, "profile", None)
    measure = getattr(getattr(cfg.sweep, "measure", None), "profile", None)
    if measure and not any(p.hs > 0 for p in profile or ()):  # the sweep's measure has the sea states
        profile = measure
    if profile:
        return {"speeds_kn": [p.speed_kn for p in profile], "weights": [p.weight for p in profile],
                "sea_states": [[p.hs, p.tp, p.heading_deg] if p.hs > 0 else None for p in profile]}
    speeds = list(getattr(o, "speeds_kn", None) or [o.speed_kn])
    weights = list(getattr(o, "weights", None) or [1.0] * len(speeds))
    sea = None
    for table in (o, getattr(cfg.sweep, "measure", None)):
        if table is not None and table.kind == "mean_added_resistance":
            sea = [table.hs, table.tp, table.heading_deg]
            break
    return {"speeds_kn": speeds, "weights": weights, "sea_states": [sea] * len(speeds)}


CONDITIONS = ((1.0, 0.0), *((f, 0.0) for f in SPEED_FACTORS if f != 1.0), *((1.0, t) for t in TP_SHIFTS if t))
"""(speed factor, T_p shift [s]) of the conditions every design is re-scored in: the profile, ±10 % speed, ±2 s
T_p (calm water sees only the first three)."""
_CALM_FACTORS = tuple(dict.fromkeys(f for f, _ in CONDITIONS))  # the distinct speed factors, in order
_CALM_OF = np.array([_CALM_FACTORS.index(f) for f, _ in CONDITIONS])  # each condition's calm water among them


def calm_methods(hull: HoltropHull, fn: float) -> tuple[tuple[str, ...], dict[str, str]]:
    """The calm-water methods a study re-scores by, and those of them outside their validity on the parent (its
    particulars ``hull``, :func:`parent_particulars`) up to Froude number ``fn`` (with why): Holtrop–Mennen,
    Michell and the panel method, and Dawson's where the parent is full or bulbous (there Kelvin's waves, Michell's and the panel
    method's, are outside their validity; on a slender hull Dawson's would add its cost and no independent
    view). A method outside its validity is shown but confirms no gain."""
    invalid = outside_validity(hull, fn)
    return ("holtrop", "michell", "panel") + (("dawson",) if "panel" in invalid else ()), invalid


def _program(model, p0, stacked, draft, speeds, weights, hs, tp, heading, waves: bool, calm: tuple[str, ...],
             groups: tuple[tuple[int, ...], ...], by_speed: tuple[tuple[int, ...], ...], band: float = 0.0):
    """Every method's value [N] of the parent and each design (stacked on a leading axis) in each condition of
    :data:`CONDITIONS` ``(1 + k, 5)``: calm-water R_T and, when ``waves``, the mean R_AW, each the profile's
    weighted mean (the points without a sea state, ``hs`` 0, add no R_AW). ``groups``: the conditions' points
    (condition-major) by speed and heading (:func:`_groups`), which share a strip-theory solve; ``by_speed``:
    the profile's points by speed (:func:`~hullopt.optimise.point_groups`), which share calm water's R_T;
    ``band``: the run's band of waterlines for NMRI's Bf [m] (the empirical methods take no Bf)."""
    params = jax.tree.map(lambda a, b: jnp.concatenate([a[None], b]), p0, stacked)
    factors = jnp.asarray([c[0] for c in CONDITIONS])
    calm_factors = jnp.asarray(_CALM_FACTORS)
    shifts = jnp.asarray([c[1] for c in CONDITIONS])
    w = weights / jnp.sum(weights)
    n = len(CONDITIONS)
    # every condition's points in one flat list: speed, heading (shared within a group), H_s, T_p
    shared = ((factors[:, None] * speeds).ravel(), jnp.tile(heading, n))
    each = (jnp.tile(hs, n), (tp + shifts[:, None]).ravel())
    # calm water once a speed and speed factor: a profile's sea states at one speed share it, and a T_p shift has
    # its speed's (the panel methods' cost is per speed)
    u = speeds[np.array([g[0] for g in by_speed])]
    w_u = jnp.stack([w[np.array(g)].sum() for g in by_speed])

    def one(p):
        s, at = model(p), draft * model.draft_factor(p)  # each design at its own draft (a draft scale)
        out = {f"calm_{m}": (calm_water(s, at, calm_factors[:, None] * u, m).total @ w_u)[_CALM_OF] for m in calm}
        if waves:
            for m in RESCORE_WAVES:
                def point(u, a, h, t, m=m):
                    r = mean_added_resistance(m, s, at, u, jnp.where(h > 0, h, 1.0), t, a, band=band).total
                    return jnp.where(h > 0, r, 0.0)

                out[f"waves_{m}"] = vmap_grouped(point, groups, shared, each).reshape(n, -1) @ w
        return out

    return jax.lax.map(one, params)


def _groups(speeds: np.ndarray, heading: np.ndarray) -> tuple[tuple[int, ...], ...]:
    """The points of every condition of :data:`CONDITIONS` (condition-major, as :func:`_program` lays them out)
    grouped by speed and heading (:func:`~hullopt.optimise.point_groups`): ±2 s of T_p and the profile's sea
    states at one speed share a strip-theory solve."""
    factors = np.asarray([c[0] for c in CONDITIONS])
    return point_groups((factors[:, None] * speeds).ravel(), np.tile(heading, len(CONDITIONS)))


def rescore_program(cfg: RunConfig, prob: Problem, stacked, key) -> tuple[tuple, dict[str, str]]:
    """The arguments of :func:`~hullopt.study.cached_call` (or :func:`~hullopt.study.prepare_call`) of the
    re-scoring of the designs ``stacked`` (:func:`~hullopt.study.stack_params`; to prepare it, their shapes),
    and the calm-water methods outside their validity on the parent (:func:`calm_methods`)."""
    cond = conditions(cfg)
    d = prob.design
    seas = [s or [0.0, 10.0, 0.0] for s in cond["sea_states"]]
    hs, tp, heading = (np.asarray([s[i] for s in seas], float) for i in range(3))
    speeds = np.asarray(cond["speeds_kn"], float) * KNOT
    hull = parent_particulars(prob, key)
    fn = max(SPEED_FACTORS) * float(np.max(speeds)) / float(np.sqrt(G * float(hull.L)))
    calm, invalid = calm_methods(hull, fn)
    args = (d.model, prob.p0, stacked, d.draft, speeds, np.asarray(cond["weights"], float), hs, tp,
            np.radians(heading))
    band = max((getattr(o, "bf_band", 0.0) for o in (cfg.objective, getattr(cfg.sweep, "measure", None)) if o),
               default=0.0)
    static = (bool(np.any(hs > 0)), calm, _groups(speeds, args[8]), point_groups(speeds, np.zeros_like(speeds)),
              float(band))
    return ("rescore", _program, args, static, [key, "rescore"]), invalid


def rescore(cfg: RunConfig, prob: Problem, designs: list[FeatureParams], key) -> tuple[dict, list[str]]:
    """``(rescored, warnings)``: the designs and the parent by every method of each kind (see the module).

    Parameters
    ----------
    cfg : RunConfig
        The run's config (its objective names the profile and the sea state).
    prob : Problem
        The run's problem (the model, the parent's parameters, the draft).
    designs : list of FeatureParams
        The designs to re-score.
    key : object
        The study's program key (what a kept program depends on).

    Returns
    -------
    tuple of (dict, list of str)
        ``rescored``: ``conditions`` (the operating points of :func:`conditions`: ``speeds_kn``, ``weights``,
        ``sea_states`` [hs m, tp s, heading deg] or None each; ``speed_factors``, ``tp_shifts_s``), and
        ``methods``: per method (``calm_holtrop``, … ``waves_snnm``) its ``kind``, ``own`` (the run's method),
        ``parent`` and ``designs`` [N] at the nominal condition, ``change_pct`` per design at the nominal
        condition and ``worst_pct`` over every condition, and ``holds`` per design; ``verdict``: per design and
        kind (or ``total``, for an objective that is the sum) whether the gain holds under at least one
        independent method (None: no method can judge it). The warnings name each design and kind where it does not.
    """
    cond = conditions(cfg)
    call, invalid = rescore_program(cfg, prob, stack_params(designs), key)
    waves = call[3][0]
    values = jax.device_get(cached_call(*call))
    own = _own_method(cfg)
    methods = {}
    for name, v in values.items():
        v = np.asarray(v, float)  # (1 + k, conditions); column 0 the profile itself
        kind, method = name.split("_", 1)
        v = v[:, :3] if kind == "calm" else v  # calm water does not see the sea state
        change = 100.0 * (v[1:] / v[:1] - 1.0)
        methods[name] = {
            "kind": kind, "method": method, "own": own[kind] == method, "unit": "N",
            "outside_validity": invalid.get(method) if kind == "calm" else None,
            "parent": float(v[0, 0]), "designs": [float(x) for x in v[1:, 0]],
            "change_pct": [float(x) for x in change[:, 0]],
            "worst_pct": [float(x) for x in change.max(axis=1)],
            "holds": [bool(x) for x in np.all(v[1:] <= v[:1] * (1.0 + HOLDS), axis=1)],
        }
    mechanism = None
    if waves and own["waves"] == "nmri" and (cfg.kind == "pareto" or cfg.design.bow):
        mechanism = mechanism_note(methods)
        for m in methods.values():
            if m["kind"] == "waves" and not m["own"]:
                m["blind"] = BLIND[m["method"]]
    verdict, warnings = [], [] if mechanism is None else [mechanism]
    total = _combined(cfg)
    for k in range(len(designs)):
        row = {}
        if total:  # the objective is the sum: a pair of methods, one of them independent, confirms the sum
            row["total"], text = _total_holds(values, methods, k)
            if not row["total"]:
                warnings.append(f"design {k}: its gain in the profile's resistance (calm water + waves) is not "
                                f"confirmed by any pair of methods other than the objective's own: {text}")
            verdict.append(row)
            continue
        for kind in ("calm", "waves"):
            if any(m["kind"] == kind and not m["own"] for m in methods.values()):
                row[kind], warning = _confirmed(methods, kind, k)
                if warning:
                    warnings.append(warning)
        verdict.append(row)
    for kind, what in (("calm", "calm-water resistance"), ("waves", "added resistance in waves")):
        unjudged = [k for k, row in enumerate(verdict) if kind in row and row[kind] is None]
        if unjudged and not (kind == "waves" and mechanism):  # the mechanism note says why for the waves
            why = "; ".join(f"{m['method']}: {m.get('outside_validity') or m.get('blind')}" for m in methods.values()
                            if m["kind"] == kind and not m["own"])
            warnings.append(f"no independent method judges the {what} of design(s) "
                            f"{', '.join(map(str, unjudged))}: {why}")
    rescored = {"conditions": {**cond, "speed_factors": list(SPEED_FACTORS), "tp_shifts_s": list(TP_SHIFTS)},
                "methods": methods, "verdict": verdict}
    if not waves:
        rescored["note"] = ("no sea state in the objective or the sweep's measure: the designs are not re-scored "
                            "in waves")
    if mechanism is not None:
        rescored["mechanism"] = mechanism
    return rescored, warnings


BLIND = {
    "snnm": "SNNM sees the bow only through L, B, T, C_B, k_yy and its waterline's entrance angle (a regression "
            "of tank data on ordinary hulls), not through Bf",
    "stawave2": "STAWAVE-2 sees only L, B, T, C_B and k_yy: no bow shape at all",
    "stawave1": "STAWAVE-1 sees only B and L_BWL",
}
"""Why each empirical wave method cannot see a change of R_AW made by the bow's bluntness through NMRI's speed
coefficient C_U (JP2009-286166's mechanism): a run that changes Bf counts none of them for or against it."""


def mechanism_note(methods: dict) -> str:
    """One sentence for a run that changes the bow's bluntness: how each wave method's R_AW changes over the
    designs (min … max, % of the parent's at the profile), who predicts the gain and why the others differ."""
    waves = [m for m in methods.values() if m["kind"] == "waves"]
    spans = ", ".join(f"{m['method'].upper()} {min(m['change_pct']):+.1f} … {max(m['change_pct']):+.1f} %"
                      for m in waves)
    why = "; ".join(BLIND[m["method"]] for m in waves if m["method"] in BLIND)
    return (f"who sees the bow: over the designs the profile's R_AW changes by {spans}. NMRI's gain, where there "
            "is one, is the patent's mechanism: the reflection part's speed factor 1 + C_U·Fn with C_U = "
            "max(68 − 310·Bf, 10), NMRI's tank-derived finding (JP2009-286166), which falls fastest up to the kink "
            f"at Bf 0.1871; {why}. They cannot confirm or refute a gain that comes from C_U, so they are not "
            "counted for or against it (a towing tank or a 3D code at speed could); the calm-water methods give "
            "its cost.")
