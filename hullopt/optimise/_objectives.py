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
``calm_resistance``          N     Holtrop–Mennen 1982 total resistance in calm water
``calm_resistance_michell``  N     Michell wave resistance + (1 + k1)·ITTC-1957 friction in calm water
``wind_added_resistance``    N     ISO 15016 wind added resistance ΔR_AA
===========================  ====  ==============================================================
"""

from __future__ import annotations

import abc
from collections.abc import Mapping
from typing import Any, ClassVar

import equinox as eqx
import numpy as np
from jaxtyping import Array, ArrayLike, Float

from ..constants import KNOT
from ..geometry import Sections
from ..resistance import holtrop_hull, holtrop_mennen, michell_wave_resistance
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
    ``unit`` (SI, ``"-"`` for a coefficient) and ``description`` (one line), hold their parameters as fields (SI, radians) and implement
    ``__call__`` and ``from_config``. Defining one registers it in :data:`OBJECTIVES`.
    """

    name: eqx.AbstractClassVar[str]
    unit: eqx.AbstractClassVar[str]
    description: eqx.AbstractClassVar[str]

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
    smooth max of width ``smooth``); dimensionless."""

    name: ClassVar[str] = "k_aw"
    unit: ClassVar[str] = "-"
    description: ClassVar[str] = "K_AW in short head waves (patent; smooth C_U)"

    speed: Scalar
    smooth: float = eqx.field(static=True, default=1.0)

    def __call__(self, sections: Sections, draft: Scalar) -> Float[Array, ""]:
        fn = froude_number(self.speed, sections.lpp)
        return k_aw(bluntness(sections, draft), fn, smooth=self.smooth)

    @classmethod
    def from_config(cls, options: Mapping[str, Any]) -> KAw:
        return cls(_scalar(options["speed_kn"] * KNOT), smooth=float(options.get("smooth", 1.0)))


class MeanAddedResistance(Objective):
    """The sea-state mean added resistance R_AW [N] (NMRI method, motion + reflection) at ``speed`` [m/s] in
    long-crested waves of significant height ``hs`` [m], peak period ``tp`` [s] (Pierson–Moskowitz) from
    ``heading`` [rad, 0 = head seas]; ``smooth`` the width of the smooth max in C_U; ``motion``: include the
    motion part R_AWM (strip theory, :func:`hullopt.waves.motion_added_resistance`; False: reflection only)."""

    name: ClassVar[str] = "mean_added_resistance"
    unit: ClassVar[str] = "N"
    description: ClassVar[str] = "sea-state mean R_AW (NMRI, long-crested)"

    speed: Scalar
    hs: Scalar
    tp: Scalar
    heading: Scalar = 0.0
    smooth: float = eqx.field(static=True, default=1.0)
    motion: bool = eqx.field(static=True, default=True)

    def __call__(self, sections: Sections, draft: Scalar) -> Float[Array, ""]:
        r = mean_added_resistance("nmri", sections, draft, self.speed, self.hs, self.tp, self.heading,
                                  smooth=self.smooth, motion=self.motion)
        return r.motion + r.reflection

    @classmethod
    def from_config(cls, options: Mapping[str, Any]) -> MeanAddedResistance:
        if options.get("hs", 0.0) <= 0 or options.get("tp", 0.0) <= 0:
            raise ValueError("mean_added_resistance needs a sea state: hs > 0 [m] and tp [s]")
        return cls(_scalar(options["speed_kn"] * KNOT), _scalar(options["hs"]), _scalar(options["tp"]),
                   _scalar(np.radians(options.get("heading_deg", 0.0))), smooth=float(options.get("smooth", 1.0)),
                   motion=bool(options.get("motion", True)))


class CalmResistance(Objective):
    """Holtrop–Mennen 1982 total calm-water resistance [N] at ``speed`` [m/s], from the hull's own geometry
    (:func:`~hullopt.resistance.holtrop_hull`)."""

    name: ClassVar[str] = "calm_resistance"
    unit: ClassVar[str] = "N"
    description: ClassVar[str] = "Holtrop–Mennen 1982 total resistance in calm water"

    speed: Scalar

    def __call__(self, sections: Sections, draft: Scalar) -> Float[Array, ""]:
        return holtrop_mennen(holtrop_hull(sections, draft), self.speed).total

    @classmethod
    def from_config(cls, options: Mapping[str, Any]) -> CalmResistance:
        return cls(_scalar(options["speed_kn"] * KNOT))


class MichellCalmResistance(Objective):
    """Calm-water resistance [N] at ``speed`` [m/s] with the hull's own wave making: Michell's thin-ship wave
    resistance from the sections (:func:`~hullopt.resistance.michell_wave_resistance`) plus ITTC-1957
    friction times Holtrop–Mennen's form factor, (1 + k1)·R_F (:func:`~hullopt.resistance.holtrop_mennen` on
    :func:`~hullopt.resistance.holtrop_hull`). Unlike ``calm_resistance`` (Holtrop–Mennen's R_W sees Cp, LCB
    and the entrance angle only) it responds to the shape of every section, so a Pareto sweep against added
    resistance in waves has something to trade. ``n_levels`` heights and ``panels`` λ panels as Michell's."""

    name: ClassVar[str] = "calm_resistance_michell"
    unit: ClassVar[str] = "N"
    description: ClassVar[str] = "Michell wave resistance + (1 + k1)·ITTC-1957 friction in calm water"

    speed: Scalar
    n_levels: int = eqx.field(static=True, default=33)
    panels: int = eqx.field(static=True, default=128)

    def __call__(self, sections: Sections, draft: Scalar) -> Float[Array, ""]:
        hm = holtrop_mennen(holtrop_hull(sections, draft), self.speed)
        rw = michell_wave_resistance(sections, draft, self.speed, n_levels=self.n_levels, panels=self.panels)
        return hm.form_factor * hm.friction + rw

    @classmethod
    def from_config(cls, options: Mapping[str, Any]) -> MichellCalmResistance:
        return cls(_scalar(options["speed_kn"] * KNOT))


class WindAddedResistance(Objective):
    """ISO 15016 wind added resistance ΔR_AA [N] at ``speed`` [m/s] in a true wind of ``wind_speed`` [m/s]
    from ``wind_angle`` [rad off the bow, positive from starboard] on the hull above water plus ``parts``
    (superstructure, cargo; None: the bare hull)."""

    name: ClassVar[str] = "wind_added_resistance"
    unit: ClassVar[str] = "N"
    description: ClassVar[str] = "ISO 15016 wind added resistance"

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
