"""Objectives: one class per kind, like optimistix's solvers. Each is a small :class:`equinox.Module` holding
only the parameters it needs, called as ``objective(sections, draft) → scalar`` (pure JAX: jit, grad, vmap),
with a class-level ``name`` (the config's ``kind``), ``unit`` (SI) and ``description``, and a classmethod
``from_config`` that builds it from a config's ``[objective]`` options.

Defining a subclass with a ``name`` registers it in :data:`OBJECTIVES` (``{name: class}``), which the run
configs accept as ``kind``: adding an objective is one class.

===========================  ====  ==============================================================
name                         unit  value
===========================  ====  ==============================================================
``k_aw``                     -     K_AW in short head waves (patent; smooth C_U)
``mean_added_resistance``    N     sea-state mean R_AW (NMRI, long-crested; motion + reflection)
``calm_resistance``          N     calm-water R_T = (1 + k1)·R_F + R_APP + R_W(method) + R_A
``calm_resistance_michell``  N     the same with Michell's R_W
``calm_resistance_dawson``   N     the same with Dawson's R_W
``wind_added_resistance``    N     ISO 15016 wind added resistance ΔR_AA
===========================  ====  ==============================================================
"""

from __future__ import annotations

import abc
from collections.abc import Callable, Mapping, Sequence
from typing import Any, ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float

from ..constants import KNOT
from ..geometry import Sections
from ..resistance import LAMBDA_PANELS, calm_water
from ..waves import bluntness, froude_number, k_aw, mean_added_resistance
from ..wind import Parts, no_parts, wind_added_resistance, wind_variables

OBJECTIVES: dict[str, type[Objective]] = {}
"""The objectives by name (the config's ``kind``), filled by defining a subclass of :class:`Objective`."""

Scalar = Float[ArrayLike, ""]  # a float, a numpy or a JAX scalar (configs build them without running JAX)


def _scalar(v: float) -> np.ndarray:
    return np.asarray(float(v))


class Objective(eqx.Module):
    """An objective of a hull at a draft, to minimise: ``objective(sections, draft) → Array ()`` in
    :attr:`unit`.

    Subclasses set the class variables (annotated ``ClassVar[str]``) ``name`` (unique; the config's ``kind``),
    ``unit`` (SI, ``"-"`` for a coefficient), ``description`` (one line) and ``options`` (the config options
    ``from_config`` reads: a config giving another is refused, naming this kind), hold their parameters as fields (SI, radians) and implement
    ``__call__`` and ``from_config``. Defining one registers it in :data:`OBJECTIVES`.
    """

    name: eqx.AbstractClassVar[str]
    unit: eqx.AbstractClassVar[str]
    description: eqx.AbstractClassVar[str]
    options: eqx.AbstractClassVar[tuple[str, ...]]

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        name = cls.__dict__.get("name")
        if isinstance(name, str):
            if name in OBJECTIVES and OBJECTIVES[name].__qualname__ != cls.__qualname__:
                raise TypeError(f"objective name {name!r} is taken by {OBJECTIVES[name].__qualname__}")
            OBJECTIVES[name] = cls

    @abc.abstractmethod
    def __call__(self, sections: Sections, draft: Scalar) -> Float[Array, ""]:
        """The objective of the hull ``sections`` floating upright at ``draft`` [m], in :attr:`unit`."""

    @classmethod
    @abc.abstractmethod
    def from_config(cls, options: Mapping[str, Any]) -> Objective:
        """The objective from a config's ``[objective]`` options, in the config's units: ``speed_kn`` [kn],
        ``hs`` [m], ``tp`` [s], ``heading_deg`` [deg], ``smooth``, ``wind_speed`` [m/s], ``wind_angle_deg``
        [deg] (missing keys: not used). ``ValueError`` naming an option this objective needs and lacks."""


class KAw(Objective):
    """K_AW = R_AW/(½ρgζ²B) in short head waves at ``speed`` [m/s] (patent eq. 2: Bf·(1 + C_U·Fn), C_U a
    smooth max of width ``smooth``; Bf over the waterlines within ``bf_band`` [m] of the draft, 0: at it);
    dimensionless."""

    name: ClassVar[str] = "k_aw"
    unit: ClassVar[str] = "-"
    description: ClassVar[str] = "K_AW in short head waves (patent; smooth C_U)"
    options: ClassVar[tuple[str, ...]] = ("speed_kn", "smooth", "bf_band")

    speed: Scalar
    smooth: float = eqx.field(static=True, default=1.0)
    bf_band: float = eqx.field(static=True, default=0.0)

    def __call__(self, sections: Sections, draft: Scalar) -> Float[Array, ""]:
        fn = froude_number(self.speed, sections.lpp)
        return k_aw(bluntness(sections, draft, band=self.bf_band), fn, smooth=self.smooth)

    @classmethod
    def from_config(cls, options: Mapping[str, Any]) -> KAw:
        return cls(_scalar(options["speed_kn"] * KNOT), smooth=float(options.get("smooth", 1.0)),
                   bf_band=float(options.get("bf_band", 0.0)))


class MeanAddedResistance(Objective):
    """The sea-state mean added resistance R_AW [N] (NMRI method, motion + reflection) at ``speed`` [m/s] in
    long-crested waves of significant height ``hs`` [m], peak period ``tp`` [s] (Pierson–Moskowitz) from
    ``heading`` [rad, 0 = head seas]; ``smooth`` the width of the smooth max in C_U; ``motion``: include the
    motion part R_AWM (strip theory, :func:`hullopt.waves.motion_added_resistance`; False: reflection only);
    ``bf_band`` [m]: Bf over the waterlines within it of the draft (:func:`hullopt.waves.bluntness`; 0: at it)."""

    name: ClassVar[str] = "mean_added_resistance"
    unit: ClassVar[str] = "N"
    description: ClassVar[str] = "sea-state mean R_AW (NMRI, long-crested)"
    options: ClassVar[tuple[str, ...]] = ("speed_kn", "hs", "tp", "heading_deg", "smooth", "motion", "bf_band")

    speed: Scalar
    hs: Scalar
    tp: Scalar
    heading: Scalar = 0.0
    smooth: float = eqx.field(static=True, default=1.0)
    motion: bool = eqx.field(static=True, default=True)
    bf_band: float = eqx.field(static=True, default=0.0)

    def __call__(self, sections: Sections, draft: Scalar) -> Float[Array, ""]:
        r = mean_added_resistance("nmri", sections, draft, self.speed, self.hs, self.tp, self.heading,
                                  smooth=self.smooth, motion=self.motion, band=self.bf_band)
        return r.motion + r.reflection

    @classmethod
    def from_config(cls, options: Mapping[str, Any]) -> MeanAddedResistance:
        if options.get("hs", 0.0) <= 0 or options.get("tp", 0.0) <= 0:
            raise ValueError("mean_added_resistance needs a sea state: hs > 0 [m] and tp [s]")
        return cls(_scalar(options["speed_kn"] * KNOT), _scalar(options["hs"]), _scalar(options["tp"]),
                   _scalar(np.radians(options.get("heading_deg", 0.0))), smooth=float(options.get("smooth", 1.0)),
                   motion=bool(options.get("motion", True)), bf_band=float(options.get("bf_band", 0.0)))


class CalmResistance(Objective):
    """Calm-water resistance R_T = (1 + k1)·R_F + R_APP + R_W + R_A [N] (:func:`~hullopt.resistance.calm_water`)
    with R_W by ``method`` ("holtrop", "michell", "panel" or "dawson"), at ``speed`` [m/s] — or over an operating profile:
    speeds (k,) with ``weights`` (k,), the weighted mean Σ wᵢ R_T(Uᵢ) / Σ wᵢ. Holtrop–Mennen's R_W sees Cp, LCB
    and the entrance angle only; Michell's and the panel method's see every section (a Pareto sweep against
    added resistance has something to trade), within their validity (slender hulls, see the module)."""

    name: ClassVar[str] = "calm_resistance"
    unit: ClassVar[str] = "N"
    description: ClassVar[str] = "calm-water R_T = (1 + k1)·R_F + R_APP + R_W(method) + R_A"
    options: ClassVar[tuple[str, ...]] = ("speed_kn", "method", "speeds_kn", "weights")
    default_method: ClassVar[str] = "holtrop"

    speed: Float[ArrayLike, "*k"]
    weights: Float[ArrayLike, "*k"] | None = None
    method: str = eqx.field(static=True, default="holtrop")
    n_levels: int = eqx.field(static=True, default=33)
    panels: int = eqx.field(static=True, default=LAMBDA_PANELS)

    def __call__(self, sections: Sections, draft: Scalar) -> Float[Array, ""]:
        r = calm_water(sections, draft, self.speed, self.method, n_levels=self.n_levels,
                       lambda_panels=self.panels).total
        w = jnp.ones_like(r) if self.weights is None else jnp.asarray(self.weights, dtype=r.dtype)
        return jnp.sum(w * r) / jnp.sum(w)

    @classmethod
    def from_config(cls, options: Mapping[str, Any]) -> CalmResistance:
        speeds, weights = options.get("speeds_kn"), options.get("weights")
        method = options.get("method") or cls.default_method
        if speeds is None:
            if weights is not None:
                raise ValueError("weights: give them with speeds_kn (one weight a speed)")
            return cls(_scalar(options["speed_kn"] * KNOT), method=method)
        w = np.ones(len(speeds)) if weights is None else np.asarray(weights, float)
        if w.shape != (len(speeds),) or np.any(w < 0) or w.sum() <= 0:
            raise ValueError(f"weights {[float(v) for v in w]}: expected one non-negative weight a speed of speeds_kn "
                             f"({len(speeds)}), not all 0")
        return cls(np.asarray(speeds, float) * KNOT, w, method=method)


class MichellCalmResistance(CalmResistance):
    """``calm_resistance`` with ``method = "michell"``: the same R_T convention (kept for configs that name it)."""

    name: ClassVar[str] = "calm_resistance_michell"
    description: ClassVar[str] = "calm-water R_T with Michell's wave resistance"
    default_method: ClassVar[str] = "michell"

    method: str = eqx.field(static=True, default="michell")


class DawsonCalmResistance(CalmResistance):
    """``calm_resistance`` with ``method = "dawson"``: Dawson's double-body panel method for R_W, the one
    validated on full, bulbous hulls (KCS, DTMB 5415) — the calm-water constraint a bow change is held to."""

    name: ClassVar[str] = "calm_resistance_dawson"
    description: ClassVar[str] = "calm-water R_T with Dawson's wave resistance"
    default_method: ClassVar[str] = "dawson"

    method: str = eqx.field(static=True, default="dawson")


class WindAddedResistance(Objective):
    """ISO 15016 wind added resistance ΔR_AA [N] at ``speed`` [m/s] in a true wind of ``wind_speed`` [m/s]
    from ``wind_angle`` [rad off the bow, positive from starboard] on the hull above water plus ``parts``
    (superstructure, cargo; None: the bare hull)."""

    name: ClassVar[str] = "wind_added_resistance"
    unit: ClassVar[str] = "N"
    description: ClassVar[str] = "ISO 15016 wind added resistance"
    options: ClassVar[tuple[str, ...]] = ("speed_kn", "wind_speed", "wind_angle_deg")

    speed: Scalar
    wind_speed: Scalar
    wind_angle: Scalar = 0.0
    parts: Parts | None = None

    def __call__(self, sections: Sections, draft: Scalar) -> Float[Array, ""]:
        v = wind_variables(sections, draft, self.parts if self.parts is not None else no_parts())
        return wind_added_resistance(v, self.speed, self.wind_speed, self.wind_angle)

    @classmethod
    def from_config(cls, options: Mapping[str, Any]) -> WindAddedResistance:
        if options.get("wind_speed", 0.0) <= 0:
            raise ValueError("wind_added_resistance needs wind_speed > 0 [m/s]")
        return cls(_scalar(options["speed_kn"] * KNOT), _scalar(options["wind_speed"]),
                   _scalar(np.radians(options.get("wind_angle_deg", 0.0))))


def point_groups(speed: ArrayLike | Sequence[float],
                 heading: ArrayLike | Sequence[float]) -> tuple[tuple[int, ...], ...]:
    """The indices of an operating profile's points grouped by equal (speed, heading), in order of first
    appearance (numpy; any units): ``point_groups([12, 12, 15], [0, 0, 0])`` is ``((0, 1), (2,))``.

    Parameters
    ----------
    speed, heading : array_like, (k,)
        Each point's speed and heading.

    Returns
    -------
    tuple of tuple of int
        The groups, each the points' indices in order.
    """
    out: dict[tuple[float, float], list[int]] = {}
    for i, key in enumerate(zip(np.asarray(speed, float).tolist(), np.asarray(heading, float).tolist())):
        out.setdefault(key, []).append(i)
    return tuple(tuple(g) for g in out.values())


def vmap_grouped(fn: Callable, groups: tuple[tuple[int, ...], ...], shared: tuple, each: tuple) -> Array:
    """``fn(*shared[:, i], *each[:, i])`` for every point i, vmapped so that within a group (points whose
    ``shared`` values are equal, :func:`point_groups`) those stay unbatched: what ``fn`` computes from them
    alone runs once a group (an operating profile's strip theory at one speed and heading, whatever the sea
    state).

    Parameters
    ----------
    fn : callable
        ``fn(*shared_i, *each_i)`` → Array (any shape).
    groups : tuple of tuple of int
        Every point index 0…k−1 exactly once, grouped.
    shared, each : tuple of Array, each (k,)
        The per-point arguments equal within a group, and the others.

    Returns
    -------
    Array, (k, ...)
        ``fn``'s value for each point, in the points' order.
    """
    q = max(len(g) for g in groups)
    slots = np.array([[*g, *(g[0],) * (q - len(g))] for g in groups])  # (groups, q), padded with the first
    inner = jax.vmap(fn, in_axes=(None,) * len(shared) + (0,) * len(each))
    out = jax.vmap(inner)(*(jnp.asarray(a)[slots[:, 0]] for a in shared), *(jnp.asarray(a)[slots] for a in each))
    where = {i: (n, j) for n, g in enumerate(groups) for j, i in enumerate(g)}
    n, j = (np.array(v) for v in zip(*(where[i] for i in range(len(where)))))
    return out[n, j]


class ProfileResistance(Objective):
    """An operating profile's resistance [N]: the weighted mean over its points i of calm-water R_T(U_i) by
    ``method`` (:func:`~hullopt.resistance.calm_water`) plus, where the point has a sea state (``hs`` > 0), the
    mean added resistance in it (NMRI, long-crested, motion part when ``motion``): Σ wᵢ (R_T + R_AW)ᵢ / Σ wᵢ.
    Points: ``speed`` [m/s], ``weights``, ``hs`` [m] (0: calm water), ``tp`` [s], ``heading`` [rad], each (k,);
    ``bf_band`` [m] the band of waterlines NMRI's Bf is averaged over (0: the draft's).

    ``groups`` (static; :func:`point_groups`, which ``from_config`` applies) lists the points by their speed and
    heading: the sea states of one group share its strip-theory solve, which does not depend on the sea state,
    and its calm-water R_T (a profile of 3 speeds in 2 sea states solves 3 times, not 6). ``None``: each point
    alone."""

    name: ClassVar[str] = "profile_resistance"
    unit: ClassVar[str] = "N"
    description: ClassVar[str] = "operating profile: weighted mean of R_T + R_AW over speeds and sea states"
    options: ClassVar[tuple[str, ...]] = ("profile", "method", "motion", "bf_band")
    power: ClassVar[bool] = False
    calm: ClassVar[bool] = True

    speed: Float[ArrayLike, " k"]
    weights: Float[ArrayLike, " k"]
    hs: Float[ArrayLike, " k"]
    tp: Float[ArrayLike, " k"]
    heading: Float[ArrayLike, " k"]
    method: str = eqx.field(static=True, default="holtrop")
    motion: bool = eqx.field(static=True, default=True)
    waves: bool = eqx.field(static=True, default=True)
    groups: tuple[tuple[int, ...], ...] | None = eqx.field(static=True, default=None)
    bf_band: float = eqx.field(static=True, default=0.0)

    def __call__(self, sections: Sections, draft: Scalar) -> Float[Array, ""]:
        u = jnp.asarray(self.speed, dtype=float)
        groups = self.groups or tuple((i,) for i in range(u.shape[0]))
        r = jnp.zeros_like(u)
        if self.calm:  # once a group: its points share the speed (the panel methods' cost is per speed)
            of = np.zeros(u.shape[0], int)
            for n, g in enumerate(groups):
                of[list(g)] = n
            r = calm_water(sections, draft, u[np.array([g[0] for g in groups])], self.method).total[of]
        if self.waves:  # a point without a sea state adds nothing (its H_s replaced before, its R_AW after)
            wet = jnp.asarray(self.hs) > 0

            def point(ui, a, h, t):
                return mean_added_resistance("nmri", sections, draft, ui, h, t, a, motion=self.motion,
                                             band=self.bf_band).total

            raw = vmap_grouped(point, groups, (u, jnp.asarray(self.heading, dtype=float)),
                               (jnp.where(wet, self.hs, 1.0), jnp.asarray(self.tp, dtype=float)))
            r = r + jnp.where(wet, raw, 0.0)
        w = jnp.asarray(self.weights, dtype=r.dtype)
        return jnp.sum(w * r * (u if self.power else 1.0)) / jnp.sum(w)

    @classmethod
    def from_config(cls, options: Mapping[str, Any]) -> ProfileResistance:
        points = options.get("profile") or []
        if not points:
            raise ValueError(f"{cls.name} needs a profile: [[profile]] tables with speed_kn (weight, hs, tp, "
                             "heading_deg)")
        col = {k: np.asarray([float(p[k]) for p in points]) for k in ("speed_kn", "weight", "hs", "tp", "heading_deg")}
        if col["weight"].sum() <= 0:
            raise ValueError("profile: the weights are all 0")
        if not cls.calm and np.any(col["hs"] <= 0):
            k = int(np.argmin(col["hs"]))
            raise ValueError(f"profile[{k}]: hs = {col['hs'][k]:g}; {cls.name} needs a sea state (hs > 0) at every "
                             "point")
        return cls(col["speed_kn"] * KNOT, col["weight"], col["hs"], col["tp"], np.radians(col["heading_deg"]),
                   method=options.get("method") or "holtrop", motion=bool(options.get("motion", True)),
                   waves=bool(np.any(col["hs"] > 0)), groups=point_groups(col["speed_kn"], col["heading_deg"]),
                   bf_band=float(options.get("bf_band", 0.0)))


class ProfilePower(ProfileResistance):
    """An operating profile's effective power [W]: Σ wᵢ Uᵢ (R_T + R_AW)ᵢ / Σ wᵢ (see :class:`ProfileResistance`)."""

    name: ClassVar[str] = "profile_power"
    unit: ClassVar[str] = "W"
    description: ClassVar[str] = "operating profile: weighted mean effective power U (R_T + R_AW)"
    power: ClassVar[bool] = True


class ProfileAddedResistance(ProfileResistance):
    """An operating profile's mean added resistance in waves [N]: Σ wᵢ R_AW,i / Σ wᵢ over its points, each with
    a sea state (NMRI, long-crested, motion part when ``motion``; see :class:`ProfileResistance`)."""

    name: ClassVar[str] = "profile_added_resistance"
    unit: ClassVar[str] = "N"
    description: ClassVar[str] = "operating profile: weighted mean R_AW over speeds and sea states"
    options: ClassVar[tuple[str, ...]] = ("profile", "motion", "bf_band")
    calm: ClassVar[bool] = False
