"""A second opinion on a study's designs: each design and the parent re-scored by every calm-water method
(Holtrop–Mennen, Michell, the panel method) and every added-resistance method a naval architect compares (NMRI,
SNNM, STAWAVE-2), over the config's operating profile and off it (±10 % speed, ±2 s T_p). A gain over the parent
counts only if it holds under at least one method of each kind other than the objective's own, in every
condition; each design where it does not is warned of.

Conditions: the calm-water speeds and weights of the ``[objective]`` (``speeds_kn`` and ``weights``, else
``speed_kn``), the profile's weighted mean at 0.9, 1 and 1.1 times them; the sea state (H_s, T_p, heading) of
the objective or the sweep's measure when either is ``mean_added_resistance``, at T_p − 2 s, T_p, T_p + 2 s and
at 0.9 and 1.1 times the speed (no sea state: no added-resistance opinion, and the report says so).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from ..constants import KNOT
from ..models import FeatureParams
from ..resistance import METHODS as CALM_METHODS
from ..resistance import calm_water
from ..waves import mean_added_resistance
from ._config import RunConfig
from ._problem import Problem
from ._programs import cached_call

RESCORE_WAVES = ("nmri", "snnm", "stawave2")
"""The added-resistance methods a design is re-scored by (STAWAVE-1 is STAWAVE-2's simpler sibling)."""

SPEED_FACTORS = (0.9, 1.0, 1.1)
"""Off the profile: the speeds a design is re-scored at, as factors of the profile's."""

TP_SHIFTS = (-2.0, 0.0, 2.0)
"""s: the peak periods a design is re-scored at, as shifts of the sea state's."""

HOLDS = 1e-3
"""A design holds a gain under a method when its value is at most the parent's times (1 + HOLDS) in every
condition (the constraints' default tolerance)."""


def _own_method(cfg: RunConfig) -> dict[str, str | None]:
    """The method of each kind the run's objective itself uses (``None``: the objective is not of that kind)."""
    o = cfg.objective
    own = {"calm": None, "waves": None}
    if o is None:
        return own
    if o.kind in ("calm_resistance", "calm_resistance_michell"):
        own["calm"] = o.method or o.build().method
    elif o.kind == "mean_added_resistance":
        own["waves"] = "nmri"
    return own


def conditions(cfg: RunConfig) -> dict:
    """The conditions of :func:`rescore` (config units): ``speeds_kn``, ``weights``, and ``sea_state`` ``(hs, tp,
    heading_deg)`` or None when neither the objective nor the sweep's measure has one."""
    o = cfg.objective
    speeds = list(getattr(o, "speeds_kn", None) or [o.speed_kn])
    weights = list(getattr(o, "weights", None) or [1.0] * len(speeds))
    sea = None
    for table in (o, getattr(cfg.sweep, "measure", None)):
        if table is not None and table.kind == "mean_added_resistance":
            sea = (table.hs, table.tp, table.heading_deg)
            break
    return {"speeds_kn": speeds, "weights": weights, "sea_state": sea}


def _program(model, p0, stacked, draft, speeds, weights, sea):
    """Every method's value [N] of the parent and each design (stacked on a leading axis): calm-water R_T's
    profile mean per speed factor ``(1 + k, 3)``, and the mean R_AW per condition ``(1 + k, 5)`` (T_p shifts at
    the mean speed, then the speed factors at T_p)."""
    params = jax.tree.map(lambda a, b: jnp.concatenate([a[None], b]), p0, stacked)
    factors = jnp.asarray(SPEED_FACTORS)
    u_mean = jnp.sum(weights * speeds) / jnp.sum(weights)

    def one(p):
        s = model(p)
        out = {}
        for m in CALM_METHODS:
            r = jax.vmap(lambda f, m=m: calm_water(s, draft, f * speeds, m).total)(factors)  # (3, k)
            out[f"calm_{m}"] = r @ weights / jnp.sum(weights)
        if sea is not None:
            hs, tp, heading = sea
            cond = [(u_mean, tp + dt) for dt in TP_SHIFTS] + [(f * u_mean, tp) for f in (SPEED_FACTORS[0],
                                                                                      SPEED_FACTORS[2])]
            u = jnp.stack([c[0] for c in cond])
            t = jnp.stack([jnp.asarray(c[1], dtype=float) for c in cond])
            for m in RESCORE_WAVES:
                out[f"waves_{m}"] = jax.vmap(
                    lambda ui, ti, m=m: mean_added_resistance(m, s, draft, ui, hs, ti, heading).total)(u, t)
        return out

    return jax.lax.map(one, params)


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
        ``rescored``: ``conditions`` (``speeds_kn``, ``weights``, ``speed_factors``, ``sea_state`` [hs m, tp s,
        heading deg] or None, ``tp_shifts_s``), and ``methods``: per method (``calm_holtrop``, … ``waves_snnm``)
        its ``kind``, ``own`` (the objective's method), ``parent`` and ``designs`` [N] at the nominal
        condition, ``change_pct`` per design at the nominal condition and ``worst_pct`` over every condition, and
        ``holds`` per design; ``verdict``: per design and kind whether the gain holds under at least one
        independent method. The warnings name each design and kind where it does not.
    """
    cond = conditions(cfg)
    d = prob.design
    speeds = np.asarray(cond["speeds_kn"], float) * KNOT
    weights = np.asarray(cond["weights"], float)
    sea = None if cond["sea_state"] is None else (float(cond["sea_state"][0]), float(cond["sea_state"][1]),
                                                  float(np.radians(cond["sea_state"][2])))
    stacked = jax.tree.map(lambda *a: np.stack([np.asarray(v, float) for v in a]), *designs)
    values = jax.device_get(cached_call("rescore", _program, (d.model, prob.p0, stacked, d.draft, speeds, weights),
                                        (sea,), key=[key, "rescore"]))
    own = _own_method(cfg)
    nominal = {"calm": 1, "waves": 1}  # the nominal condition's column: speed factor 1; T_p shift 0
    methods = {}
    for name, v in values.items():
        v = np.asarray(v, float)
        kind, method = name.split("_", 1)
        change = 100.0 * (v[1:] / v[:1] - 1.0)  # (k, conditions)
        methods[name] = {
            "kind": kind, "method": method, "own": own[kind] == method, "unit": "N",
            "parent": float(v[0, nominal[kind]]), "designs": [float(x) for x in v[1:, nominal[kind]]],
            "change_pct": [float(x) for x in change[:, nominal[kind]]],
            "worst_pct": [float(x) for x in change.max(axis=1)],
            "holds": [bool(x) for x in np.all(v[1:] <= v[:1] * (1.0 + HOLDS), axis=1)],
        }
    verdict, warnings = [], []
    for k in range(len(designs)):
        row = {}
        for kind in ("calm", "waves"):
            independent = [m for m in methods.values() if m["kind"] == kind and not m["own"]]
            if not independent:
                continue
            row[kind] = any(m["holds"][k] for m in independent)
            if not row[kind]:
                worst = ", ".join(f"{m['method']} {m['worst_pct'][k]:+.1f} %" for m in independent)
                what = "calm-water resistance" if kind == "calm" else "added resistance in waves"
                warnings.append(f"design {k}: no independent method finds its {what} at or below the parent's in "
                                f"every condition of the profile and off it (worst change: {worst})")
        verdict.append(row)
    rescored = {"conditions": {**cond, "speed_factors": list(SPEED_FACTORS), "tp_shifts_s": list(TP_SHIFTS)},
                "methods": methods, "verdict": verdict}
    if sea is None:
        rescored["note"] = ("no sea state in the objective or the sweep's measure: the designs are not re-scored "
                            "in waves")
    return rescored, warnings
