"""Run configs (TOML), validated strictly with pydantic: unknown keys are rejected and every error names its
field. One config describes a parent, a design (which feature curves may move, within which bounds),
targets, an objective, a solver and, for Pareto runs, a sweep.

    kind = "fit" | "minimise" | "pareto"
    [hull]       parent = "dtc" | "my_hull.stl?scale=…&lpp=…" (any hull spec), draft = 14.5
    [[design.apex_move]]  segment, x_fixed1, x_moved, x_fixed2, profile, d (start), bound (|d| ≤, m)
    [[design.distribution]]  x_a, x_b, curves, modes, c (start), bound (|c_j| ≤)
    [[design.contour_edit]]  line, x_a, x_b, shape, amplitude (start), bound (m)
    [targets]    cb = 0.64, lcb_pct = -2.0, volume = …      [tolerances] (optional, same names)
    [objective]  kind, speed_kn, hs, tp, heading_deg
    [sweep]      start, stop, count, chunk, measure (an objective table: the second Pareto axis)
    [constraints]  calm_resistance = "<= parent", cwp = ">= 0.98 * parent", kmt = ">= parent - 0.05",
                 wetted_surface = "<= 9000", dwl_turns = "none" (a default off), bwl = [">= 0.95 * parent",
                 "<= 1.05 * parent"] (both sides), max_half_breadth = "parent" |
                 M | "none", bulge = "forbid" | "allow", frozen = "auto" | "none" | [[x_a, x_b], …],
                 tolerance = 1e-3
    [[constraints.region_volume]]  name, x_a, x_b, z_top (m), bound: a region's displaced volume
    [solver]     max_steps, smoothness, fairness, outer
"""

from __future__ import annotations

import difflib
import re
import tomllib
from collections.abc import Iterable
from pathlib import Path
from typing import Annotated, Literal, NamedTuple, Union, get_args

from pydantic import (
    BaseModel,
    ConfigDict,
    Field,
    TypeAdapter,
    ValidationError,
    create_model,
    model_validator,
)

from ..errors import HullError
from ..fairing import SHAPE_MEASURES
from ..hydro import Hydrostatics
from ..models import parent_names
from ..optimise import OBJECTIVES, TARGETS, Objective, make_targets
from ..resistance import METHODS

FAIRNESS = 0.05
"""The default weight of the fairness penalty (``[solver] fairness``) of minimise and Pareto runs, where an
objective pulls the shape (a fit's default is 0: it already deforms the least needed)."""


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


def did_you_mean(key: str, known: Iterable[str]) -> str:
    """The nearest of ``known`` to a misspelled ``key``, as a config error's suggestion (difflib).

    Parameters
    ----------
    key : str
        The key (or name) as written, e.g. ``max_step``.
    known : iterable of str
        The keys (or names) that place takes.

    Returns
    -------
    str
        ``"; did you mean 'max_steps'?"``, or ``""`` when none is close.
    """
    close = difflib.get_close_matches(str(key), [str(k) for k in known], n=1, cutoff=0.6)
    return f"; did you mean {close[0]!r}?" if close else ""


def _models_in(annotation) -> list[type[BaseModel]]:
    """The pydantic models an annotation holds (in a list, a union, an ``Annotated``, an optional)."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return [annotation]
    return [m for a in get_args(annotation) for m in _models_in(a)]


def unknown_key(root: type[BaseModel], loc: tuple) -> str:
    """A config's unknown key, as one line: where it is, the nearest key that table takes and the keys it takes.

    Parameters
    ----------
    root : type of pydantic.BaseModel
        The model the config was validated against (:class:`RunConfig`, a wind config's).
    loc : tuple
        The error's location (pydantic's ``loc``): the tables down to the key, list indices and a union's tag
        included.

    Returns
    -------
    str
        ``"solver.max_step: unknown key; did you mean 'max_steps'? (expected one of fairness, max_steps, …)"``.
    """
    models: list[type[BaseModel]] = [root]
    for part in loc[:-1]:
        if isinstance(part, int):
            continue  # a list's item
        if part in OPTIONS and not any(part in m.model_fields for m in models):
            models = [OPTIONS[part]]  # a union's tag: the objective kind's own model
            continue
        models = [o for m in models if part in m.model_fields for o in _models_in(m.model_fields[part].annotation)]
    known = sorted({k for m in models for k in m.model_fields})
    key = loc[-1] if loc else ""
    where = ".".join(str(p) for p in loc if p not in OPTIONS)
    return f"{where}: unknown key{did_you_mean(key, known)} (expected one of {', '.join(known)})"


class HullConfig(_Strict):
    parent: str = Field(description="library parent (dtc, tanker, wigley, seed003), a parent .json file, or any "
                                    "hull spec (a mesh 'hull.stl?scale=…&lpp=…', an offsets .csv, builtin:…); "
                                    "paths relative to the config's folder")
    draft: float | None = Field(default=None, gt=0, description="m; default: the parent's design draft (required "
                                                                "for a hull spec without one, e.g. a mesh)")
    bf_band: float = Field(default=0.0, ge=0, description="m: Bf (its target, constraint, sweep and NMRI's R_AW) "
                           "averaged over the waterlines within this of the draft; 0: at the draft (the patent's)")


class ApexMoveConfig(_Strict):
    segment: int
    x_fixed1: float
    x_moved: float
    x_fixed2: float
    profile: Literal["linear", "smooth"] = "smooth"
    d: tuple[float, float] = (0.0, 0.0)
    bound: float = Field(default=2.0, gt=0, description="|dy|, |dz| ≤ bound [m]")


class DistributionConfig(_Strict):
    x_a: float
    x_b: float
    curves: str | list[str] = Field(default="all", description="'all' (whole frames re-read along the length), "
                                    "'stations' (the frames themselves move), or curve names 'apex:<s>', "
                                    "'aux:<s>', 'inflection:<k>', 'keel', 'deck'")
    modes: int = Field(default=2, ge=1, le=8)
    c: list[float] | None = None
    bound: float = Field(default=0.3, gt=0, lt=1, description="|c_j| ≤ bound (the warp stays monotone)")


class ContourEditConfig(_Strict):
    line: Literal["keel_z", "fob_y", "fos_z", "deck_y", "deck_z"]
    x_a: float
    x_b: float
    shape: Literal["bump", "ramp"] = "bump"
    amplitude: float = 0.0
    bound: float = Field(default=1.0, gt=0, description="|amplitude| ≤ bound [m]")


class BowConfig(_Strict):
    """``[[design.bow]]``: a bow attachment (JP2009-286166 claims 4–5; :mod:`hullopt.models._bow`)."""

    x_blend: float = Field(description="m from the AP: where the attachment starts (zero slope)")
    z_lo: float = Field(description="m above the baseline: the band's lower end (full width from here up)")
    z_hi: float | None = Field(default=None, description="m: the band's upper end; default none (to the deck)")
    blend: float = Field(default=1.0, gt=0, description="m: height of the smooth ramps outside the band")
    x_peak: float | None = Field(default=None, description="m: full width here; default the station aft of the stem")
    x_stem: float | None = Field(default=None, description="m: the nose closes here; default the stem at the draft")
    mode: Literal["add", "scale"] = Field(default="add", description="'add': a half-breadth [m] added, the nose "
                                          "closing to the stem; 'scale': the half-breadths times 1 + a (a fraction)")
    a: float = Field(default=0.0, description="start: half-breadth added at x_peak [m] (mode 'scale': the fraction)")
    bound: float = Field(default=5.0, gt=0, description="|a| ≤ bound (m; mode 'scale': a fraction)")

    @model_validator(mode="after")
    def _band(self):
        if self.z_hi is not None and self.z_hi <= self.z_lo:
            raise ValueError(f"z_hi = {self.z_hi:g} m must be above z_lo = {self.z_lo:g} m")
        return self


class BeamConfig(_Strict):
    """``[design.beam]``: every half-breadth scaled by 1 + s, Lpp and heights kept (with a ∇ target the fit
    takes the volume back elsewhere)."""

    s: float = Field(default=0.0, description="start: the relative change of the beam")
    bound: float = Field(default=0.05, gt=0, lt=0.5, description="|s| ≤ bound (0.05: ±5 %)")


class DraftConfig(_Strict):
    """``[design.draft]``: every height and the draft the hull floats at scaled by 1 + s from the baseline (the keel
    stays on it), Lpp and breadths kept; the targets, objective and constraints are evaluated at the design's own
    draft, ``hull.draft · (1 + s)``."""

    s: float = Field(default=0.0, description="start: the relative change of the draft")
    bound: float = Field(default=0.05, gt=0, lt=0.5, description="|s| ≤ bound (0.05: ±5 %)")


class DesignConfig(_Strict):
    apex_move: list[ApexMoveConfig] = []
    distribution: list[DistributionConfig] = []
    contour_edit: list[ContourEditConfig] = []
    bow: list[BowConfig] = []
    beam: BeamConfig | None = None
    draft: DraftConfig | None = None

    @model_validator(mode="after")
    def _some(self):
        if not (self.apex_move or self.distribution or self.contour_edit or self.bow or self.beam or self.draft):
            raise ValueError("the design has no parameters: give [[design.apex_move]], [[design.distribution]], "
                             "[[design.contour_edit]], [[design.bow]], [design.beam] or [design.draft]")
        return self


class DeformConfig(DesignConfig):
    """``hullopt deform``'s design TOML: the run config's ``[design]`` tables at the top level
    (``[[apex_move]]``, ``[[distribution]]``, ``[[contour_edit]]``, same fields and defaults) and, optionally,
    the parent (any spec a run config's ``[hull] parent`` takes, relative to the TOML's folder)."""

    parent: str | None = None


class ProfilePoint(_Strict):
    """One point of an operating profile (``[[profile]]``): a speed, its weight (time share or importance) and
    optionally a sea state (``hs`` 0: calm water)."""

    speed_kn: float = Field(gt=0, description="ship speed [kn]")
    weight: float = Field(default=1.0, ge=0, description="the point's weight (e.g. its share of the time)")
    hs: float = Field(default=0.0, ge=0, description="significant wave height [m] (0: calm water)")
    tp: float = Field(default=10.0, gt=0, description="peak period [s]")
    heading_deg: float = Field(default=0.0, ge=-360, le=360, description="wave heading [deg, 0 head seas]")


#: Every objective option a config may give, in config units; an objective kind takes those its class names
#: in ``options`` (:class:`~hullopt.optimise.Objective`).
OPTION_FIELDS: dict[str, tuple] = {
    "speed_kn": (float, Field(gt=0, description="ship speed [kn]")),
    "hs": (float, Field(default=0.0, ge=0, description="significant wave height [m]")),
    "tp": (float, Field(default=10.0, gt=0, description="peak period [s]")),
    "heading_deg": (float, Field(default=0.0, ge=-360, le=360, description="wave heading [deg, 0 head seas]")),
    "smooth": (float, Field(default=1.0, gt=0, description="width of the smooth max in C_U")),
    "motion": (bool, Field(default=True, description="include the motion part R_AWM (strip theory)")),
    "bf_band": (float, Field(default=0.0, ge=0, description="Bf averaged over the waterlines within this of the "
                             "draft [m] (0: the draft's, the patent's)")),
    "wind_speed": (float, Field(default=0.0, ge=0, description="true wind [m/s]")),
    "wind_angle_deg": (float, Field(default=0.0, ge=-360, le=360, description="true wind off the bow [deg]")),
    "method": (Literal[METHODS] | None, Field(  # type: ignore[valid-type]
        default=None, description="the wave-resistance method (default: the kind's)")),
    "speeds_kn": (list[Annotated[float, Field(gt=0)]] | None, Field(
        default=None, min_length=1, description="an operating profile's speeds [kn]")),
    "weights": (list[Annotated[float, Field(ge=0)]] | None, Field(
        default=None, description="the profile's weights, one a speed")),
    "profile": (list[ProfilePoint], Field(min_length=1, description="the operating profile's points "
                                                                    "(the config's [[profile]] tables)")),
}


def _owners(key: str) -> list[str]:
    return [k for k, cls in OBJECTIVES.items() if key in cls.options]


class ObjectiveOptions(_Strict):
    """An ``[objective]`` table: ``kind`` one of :data:`~hullopt.optimise.OBJECTIVES` and the options its class
    takes (:data:`OPTION_FIELDS`); an option of another kind is an error naming the kinds that take it."""

    kind: str

    @model_validator(mode="before")
    @classmethod
    def _own_options(cls, data):
        if isinstance(data, dict):
            own = cls.model_fields
            for key in data:
                if key not in own:
                    owners = _owners(key)
                    where = (f"it is an option of {', '.join(owners)}" if owners
                             else f"expected one of {', '.join(k for k in own if k != 'kind')}"
                             f"{did_you_mean(key, [k for k in own if k != 'kind'])}")
                    raise ValueError(f"{key}: kind = {data.get('kind')!r} takes no {key!r} ({where})")
        return data

    @model_validator(mode="after")
    def _options(self):
        self.build()  # the kind's own checks (a sea state, a wind), as ValueError
        return self

    def build(self) -> Objective:
        """The :class:`~hullopt.optimise.Objective` of this table (SI; no JAX op runs)."""
        return OBJECTIVES[self.kind].from_config(self.model_dump())


OPTIONS: dict[str, type[ObjectiveOptions]] = {
    kind: create_model(f"{cls.__name__}Options", __base__=ObjectiveOptions, __doc__=cls.description,
                       kind=(Literal[kind], ...), **{k: OPTION_FIELDS[k] for k in cls.options})
    for kind, cls in OBJECTIVES.items()
}
"""One options model per objective kind (pydantic, strict)."""

ObjectiveConfig = Annotated[Union[tuple(OPTIONS.values())], Field(discriminator="kind")]  # noqa: UP007
"""An ``[objective]`` table: the options model of its ``kind`` (a discriminated union of :data:`OPTIONS`)."""

_OBJECTIVE = TypeAdapter(ObjectiveConfig)


def objective_options(table: dict) -> ObjectiveOptions:
    """The validated options model of an ``[objective]``-like table.

    Parameters
    ----------
    table : dict
        The table: ``kind`` (one of :data:`~hullopt.optimise.OBJECTIVES`) and the options that kind takes, in
        config units (``speed_kn`` [kn], ``hs`` [m], ``tp`` [s], …).

    Returns
    -------
    ObjectiveOptions
        The options model of ``table["kind"]`` (one of :data:`OPTIONS`), defaults filled in.

    Raises
    ------
    pydantic.ValidationError
        An unknown kind, an option that kind does not take, a value out of range, or a kind's own check failing.
    """
    return _OBJECTIVE.validate_python(table)


def options_as(options: ObjectiveOptions, kind: str) -> ObjectiveOptions:
    """``options`` as those of the objective ``kind``: the options that kind takes, the rest dropped
    (``ValidationError`` when it lacks one it needs, e.g. a sea state). An operating profile gives a kind that
    takes ``speeds_kn`` (calm-water resistance) its points' speeds and weights: calm water over the profile."""
    take = OBJECTIVES[kind].options
    data = options.model_dump()
    profile = data.get("profile")
    if profile and "speeds_kn" in take and "profile" not in take:
        data |= {"speed_kn": profile[0]["speed_kn"], "speeds_kn": [p["speed_kn"] for p in profile],
                 "weights": [p["weight"] for p in profile]}
    return objective_options({k: v for k, v in data.items() if k in take} | {"kind": kind})


class SweepConfig(_Strict):
    variable: Literal["bf"] = "bf"
    start: float
    stop: float
    count: int = Field(ge=2, le=4096)
    chunk: int = Field(default=4, ge=1)
    measure: ObjectiveConfig


_BOUND = re.compile(r"^\s*(<=|>=)\s*(?:(?:([-+0-9.eE]+)\s*\*\s*)?(parent)\s*(?:([-+])\s*([0-9.eE]+))?"
                    r"|([-+0-9.eE]+))\s*$")


class Bound(NamedTuple):
    """A constraint's bound: ``sense`` +1 for at most, −1 for at least; ``value`` the bound in SI units, or
    the factor of the parent's value where ``relative``; ``margin`` [SI] added to a relative bound
    (``"parent - 0.05"``)."""

    sense: int
    value: float
    relative: bool
    margin: float = 0.0


def parse_bound(name: str, text) -> Bound:
    """A constraint's bound ``"<= parent"``, ``">= 0.98 * parent"``, ``">= parent - 0.05"``, ``"<= 1.2e5"``
    (SI) → :class:`Bound`.

    Parameters
    ----------
    name : str
        The constraint's name (the ``[constraints]`` key), for the error message.
    text : str
        The bound as written; anything but a string is an error.

    Returns
    -------
    Bound
        ``(sense, value, relative, margin)``.

    Raises
    ------
    ValueError
        When ``text`` is none of these forms; the message names the constraint.
    """
    m = _BOUND.match(text) if isinstance(text, str) else None
    try:
        if m and m[3]:
            margin = float(m[5]) * (-1 if m[4] == "-" else 1) if m[4] else 0.0
            bound = Bound(1 if m[1] == "<=" else -1, float(m[2]) if m[2] else 1.0, True, margin)
        else:
            bound = Bound(1 if m[1] == "<=" else -1, float(m[6]), False) if m else None
    except ValueError:
        bound = None
    if bound is None:
        raise ValueError(f"constraints.{name} = {text!r}: expected '<= parent', '>= 0.98 * parent', "
                         "'>= parent - 0.05' or '<= NUMBER' (SI units), or 'none'")
    return bound


def parse_bounds(name: str, value) -> tuple[Bound, ...]:
    """A constraint's bound or bounds: one bound string (:func:`parse_bound`), or a list of two, one each way —
    ``[">= 0.95 * parent", "<= 1.05 * parent"]``, the measure between them.

    Parameters
    ----------
    name : str
        The constraint's name (the ``[constraints]`` key), for the error message.
    value : str or list of str
        The bound as written.

    Returns
    -------
    tuple of Bound
        ``(bound,)``, or ``(lower, upper)`` for a two-sided bound.

    Raises
    ------
    ValueError
        When a bound is malformed, a list is not two bound strings, both point the same way, or two bounds in
        SI units leave no value between them; the message names the constraint (and the list's item).
    """
    if not isinstance(value, list | tuple):
        return (parse_bound(name, value),)
    if len(value) != 2 or not all(isinstance(v, str) for v in value):
        raise ValueError(f"constraints.{name} = {list(value)!r}: a two-sided bound is a list of two bound strings, "
                         "one '>=' and one '<=' (e.g. ['>= 0.95 * parent', '<= 1.05 * parent'])")
    sides = tuple(parse_bound(f"{name}[{i}]", v) for i, v in enumerate(value))
    if sides[0].sense == sides[1].sense:
        way = "'<='" if sides[0].sense > 0 else "'>='"
        raise ValueError(f"constraints.{name} = {list(value)!r}: both bounds are {way}; a two-sided bound takes one "
                         "'>=' and one '<='")
    lower, upper = sorted(sides, key=lambda b: b.sense)
    if not (lower.relative or upper.relative) and lower.value > upper.value:
        raise ValueError(f"constraints.{name} = {list(value)!r}: no value is both >= {lower.value:g} and <= "
                         f"{upper.value:g}")
    return lower, upper


def bound_text(value) -> str:
    """A bound as a report writes it: the string, or a two-sided bound's two joined
    (``">= 0.95 * parent and <= 1.05 * parent"``)."""
    return " and ".join(value) if isinstance(value, list | tuple) else value


DEFAULT_LIMITS = {
    "station_knuckles": "<= 2 * parent",
    "section_roughness": "<= 2 * parent",
    "dwl_turns": "<= parent",
    "section_inflections": "<= parent",
    "waterline_angles": "<= 1.25 * parent",
    "sac_regions": "<= 2 * parent",
    "kmt": ">= parent - 0.05",
}
"""The local shape limits every minimise and Pareto run holds unless its ``[constraints]`` sets the key
(another bound, or ``"none"``): no station's knuckles sharper than 2^(1/4) ≈ 1.19× the parent's, no section
rougher than twice; no turn near the DWL sharper than the parent's sharpest there; no new inflection under the DWL;
waterline half-angles of entrance and run at six heights at most 1.25× the parent's (a 20° run → 25°); the
sectional-area curve's curvature per region (run, aft shoulder, fore shoulder, entrance) at most twice the
parent's (its curvature ≈ 1.4×); KM_T — GM_T at the same KG — at most 5 cm below the parent's. With
``frozen = "auto"`` (default) a bulb at either end does not change."""


def measure_names() -> tuple[str, ...]:
    """What a ``[constraints]`` key may name: the objectives (:data:`~hullopt.optimise.OBJECTIVES`), the
    upright hydrostatics' fields (``hullopt hydro --json``), ``bf`` and the shape measures
    (:data:`~hullopt.fairing.SHAPE_MEASURES`, as ``"<= 2 * parent"``)."""
    return (*OBJECTIVES, *(k for k in Hydrostatics.__dataclass_fields__ if k != "draft"), "bf", *SHAPE_MEASURES)


class RegionVolumeConfig(_Strict):
    """``[[constraints.region_volume]]``: the displaced volume of a region of the hull bounded — the part
    forward of ``x_a`` and aft of ``x_b`` [m from the AP] below ``z_top`` [m above the baseline] and the
    waterline (:func:`hullopt.geometry.region_volume`), e.g. a sonar dome's not below the parent's. Its
    constraint (and measure in the report) is ``region_volume:<name>``."""

    name: str = Field(pattern=r"^[A-Za-z][A-Za-z0-9_]*$", description="the region's name (letters, digits, _): "
                      "the report's 'region_volume:<name>'")
    x_a: float | None = Field(default=None, description="m from the AP: the region's aft end; default the hull's")
    x_b: float | None = Field(default=None, description="m from the AP: its forward end; default the hull's")
    z_top: float | None = Field(default=None, description="m above the baseline: its top; default the waterline "
                                "(a higher one is clipped there)")
    bound: str | list[str] = Field(description="'>= parent', '>= 0.98 * parent', '<= NUMBER' [m³], or a list of "
                                   "two, one each way")


REGION = "region_volume:"
"""The prefix of a region's constraint and measure names: ``region_volume:<name>``."""


class ConstraintsConfig(_Strict):
    """``[constraints]``: inequalities beside the targets, held by minimise and Pareto runs (a fit has
    none). Any objective or particular (:func:`measure_names`) as ``name = "<= parent"`` (an objective's
    options, such as the speed, are the ``[objective]`` table's, or the sweep's measure's for its kind);
    ``max_half_breadth``: no offset wider than this [m] (``"parent"``: the parent's largest half-breadth;
    ``"none"``: no limit); ``bulge = "forbid"``: no section wider below the waterline than its waterline
    half-breadth, beyond what the parent's is at the same offset; ``tolerance``: how far (relative to the
    bound, or to the parent's half-breadth) a constraint may be exceeded and still be met. A measure may be
    bounded on both sides by a list of two bounds, ``bwl = [">= 0.95 * parent", "<= 1.05 * parent"]``;
    ``[[region_volume]]`` bounds the displaced volume of regions of the hull (:class:`RegionVolumeConfig`)."""

    model_config = ConfigDict(extra="allow")

    max_half_breadth: float | Literal["parent", "none"] = "parent"
    bulge: Literal["forbid", "allow"] = "forbid"
    frozen: Literal["auto", "none"] | list[tuple[float, float]] = Field(
        default="auto", description="stations that must not change: 'auto' (a bulb at either end), 'none', or "
        "ranges [[x_a, x_b], …] [m from the AP] of the parent's stations")
    tolerance: float = Field(default=1e-3, gt=0, lt=0.1)
    region_volume: list[RegionVolumeConfig] = Field(
        default_factory=list, description="regions whose displaced volume is bounded (a sonar dome's, a bulb's)")

    @model_validator(mode="after")
    def _bounds(self):
        names = measure_names()
        for name, text in (self.model_extra or {}).items():
            if name not in names:
                near = did_you_mean(name, [*names, *type(self).model_fields])
                raise ValueError(f"constraints.{name}: unknown measure{near} (expected one of {', '.join(names)}, "
                                 "max_half_breadth, bulge, frozen, tolerance or [[constraints.region_volume]])")
            if text != "none":
                parse_bounds(name, text)
        seen = set()
        for i, r in enumerate(self.region_volume):
            where = f"constraints.region_volume[{i}]"
            if r.name in seen:
                raise ValueError(f"{where}: name {r.name!r} is given twice; each region needs its own")
            seen.add(r.name)
            parse_bounds(f"region_volume[{i}].bound", r.bound)
            if r.x_a is None and r.x_b is None and r.z_top is None:
                raise ValueError(f"{where} ({r.name}): give x_a, x_b or z_top (the whole hull's is the volume "
                                 "constraint)")
            if r.x_a is not None and r.x_b is not None and not r.x_a < r.x_b:
                raise ValueError(f"{where} ({r.name}): x_a = {r.x_a:g}, x_b = {r.x_b:g}: expected x_a < x_b "
                                 "[m from the AP]")
        for a, b in self.frozen if isinstance(self.frozen, list) else ():
            if not a < b:
                raise ValueError(f"constraints.frozen: range [{a}, {b}]: expected x_a < x_b [m from the AP]")
        if isinstance(self.max_half_breadth, float) and self.max_half_breadth <= 0:
            raise ValueError(f"constraints.max_half_breadth = {self.max_half_breadth}: expected a positive "
                             "half-breadth [m], 'parent' or 'none'")
        return self

    def held(self) -> dict[str, str | list[str]]:
        """The bounds as the run holds them, as written: :data:`DEFAULT_LIMITS` with the config's own over
        them, less those set to ``"none"``, and each region's (``region_volume:<name>``)."""
        out = {k: v for k, v in {**DEFAULT_LIMITS, **(self.model_extra or {})}.items() if v != "none"}
        return out | {REGION + r.name: r.bound for r in self.region_volume}

    def written(self) -> dict[str, str]:
        """:meth:`held` as text (:func:`bound_text`: a two-sided bound's two joined by "and")."""
        return {k: bound_text(v) for k, v in self.held().items()}

    def bounds(self) -> dict[str, tuple[Bound, ...]]:
        """``{measure: (Bound,) or (lower, upper)}`` (:func:`parse_bounds`) of :meth:`held`."""
        return {k: parse_bounds(k, v) for k, v in self.held().items()}

    def regions(self) -> dict[str, RegionVolumeConfig]:
        """``{"region_volume:<name>": region}`` of ``[[region_volume]]``."""
        return {REGION + r.name: r for r in self.region_volume}


class SolverConfig(_Strict):
    max_steps: int = Field(default=200, ge=1)
    method: Literal["optimistix", "lbfgsb"] = Field(
        default="optimistix", description="a fit's solver: optimistix's Levenberg–Marquardt (bounds by a change of "
        "variables) or jaxopt's L-BFGS-B (bounds hard)")
    smoothness: float = Field(default=1e-6, ge=0)
    fairness: float | None = Field(default=None, ge=0, description="weight of the unfairness penalty U/U_parent "
                                   "(default: the study's, FAIRNESS for minimise and pareto runs, 0 for fits)")

    outer: int = Field(default=8, ge=1, le=50)


class RunConfig(_Strict):
    kind: Literal["fit", "minimise", "pareto"]
    hull: HullConfig
    design: DesignConfig
    targets: dict[str, float] = {}
    tolerances: dict[str, float] = {}
    kg: float | None = Field(default=None, description="m, for a gm target")
    objective: ObjectiveConfig | None = None
    sweep: SweepConfig | None = None
    solver: SolverConfig = SolverConfig()
    constraints: ConstraintsConfig = ConstraintsConfig()

    @model_validator(mode="before")
    @classmethod
    def _profile(cls, data):
        """``[[profile]]`` at the top level is the operating profile of the objective (its ``profile`` option);
        ``[hull] bf_band`` is the band of every objective that takes one and gives none."""
        band = data.get("hull", {}).get("bf_band") if isinstance(data, dict) else None
        if band is not None:
            data = dict(data)
            if isinstance(data.get("objective"), dict):
                data["objective"] = _with_band(data["objective"], band)
            if isinstance(data.get("sweep"), dict) and isinstance(data["sweep"].get("measure"), dict):
                data["sweep"] = {**data["sweep"], "measure": _with_band(data["sweep"]["measure"], band)}
        if isinstance(data, dict) and "profile" in data:
            data = dict(data)
            profile = data.pop("profile")
            if isinstance(data.get("objective"), dict):
                data["objective"] = {**data["objective"], "profile": profile}
            else:
                raise ValueError("profile: an operating profile needs an [objective] (kind = \"profile_resistance\" "
                                 "or \"profile_power\")")
        return data

    def constraint_options(self, name: str) -> ObjectiveOptions:
        """The options of the objective ``name`` as a constraint: the sweep's measure's if it is that kind,
        else the ``[objective]`` table's with this kind (``ValueError`` naming the constraint)."""
        if self.sweep is not None and self.sweep.measure.kind == name:
            return self.sweep.measure
        if self.objective is None:
            raise ValueError(f"constraints.{name}: an objective as a constraint takes its options (speed_kn, …) "
                             "from [objective]; give one")
        try:
            return options_as(self.objective, name)
        except ValidationError as e:
            raise ValueError(f"constraints.{name}: {e.errors()[0]['msg'].removeprefix('Value error, ')}") from None

    @model_validator(mode="after")
    def _consistent(self):
        for k in self.targets:
            if k not in TARGETS:
                raise ValueError(f"targets.{k}: unknown target{did_you_mean(k, TARGETS)} (expected one of "
                                 f"{', '.join(TARGETS)})")
        for k in self.tolerances:
            if k not in self.targets:
                raise ValueError(f"tolerances.{k}: a tolerance for no target{did_you_mean(k, self.targets)} "
                                 f"(the targets: {', '.join(self.targets) or 'none'})")
        make_targets(self.targets, self.tolerances, self.kg)  # physical ranges, tolerances of non-targets
        if self.kind == "fit" and not self.targets:
            raise ValueError("a fit needs [targets]")
        if self.kind in ("minimise", "pareto") and self.objective is None:
            raise ValueError(f"kind = {self.kind!r} needs an [objective]")
        if self.kind == "pareto" and self.sweep is None:
            raise ValueError("kind = 'pareto' needs a [sweep]")
        if self.kind != "fit" and self.solver.method != "optimistix":
            raise ValueError(f"solver.method = {self.solver.method!r} applies to fits; kind = {self.kind!r} is solved by "
                             "the augmented Lagrangian (optimistix)")
        if self.kind == "fit" and "constraints" in self.model_fields_set:
            raise ValueError("constraints: a fit holds targets only; [constraints] apply to minimise and pareto runs")
        for name in self.constraints.bounds():
            if name in OBJECTIVES:
                self.constraint_options(name)
        return self


def _with_band(table: dict, band) -> dict:
    cls = OBJECTIVES.get(table.get("kind"))
    return {"bf_band": band, **table} if cls is not None and "bf_band" in cls.options else table


def _set(tree: dict, dotted: str, text: str) -> None:
    """Apply one ``--set a.b=value`` (the value parsed as TOML, else kept as a string)."""
    keys = dotted.split(".")
    try:
        value = tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        value = text
    node = tree
    for k in keys[:-1]:
        node = node.setdefault(k, {})
        if not isinstance(node, dict):
            raise HullError(f"--set {dotted}: {k} is not a table")
    node[keys[-1]] = value


def load_config(path: str | Path, overrides: list[str] = ()) -> tuple[RunConfig, dict]:
    """Read, override and validate a run config.

    Parameters
    ----------
    path : str or pathlib.Path
        The config's TOML file.
    overrides : list of str
        ``KEY=VALUE`` overrides (``--set``), a dotted key (``targets.cb=0.62``) and a value parsed as TOML (else
        kept as a string), applied in order before validation.

    Returns
    -------
    tuple of (RunConfig, dict)
        The validated config and the resolved raw dict (a parent file given relative to the config's folder made
        absolute in both).

    Raises
    ------
    HullError
        A file that cannot be read or is not TOML, a malformed override, or an invalid config; the message names
        the file and the field of the problem.
    """
    path = Path(path)
    raw = _read_toml(path, "config")
    for item in overrides:
        key, sep, text = item.partition("=")
        if not sep or not key:
            raise HullError(f"--set {item!r}: expected KEY=VALUE, e.g. targets.cb=0.62")
        _set(raw, key.strip(), text.strip())
    try:
        cfg = RunConfig.model_validate(raw)
    except ValidationError as e:
        raise _invalid(path, e, RunConfig) from None
    parent = resolve_spec(cfg.hull.parent, path.resolve().parent)  # a file beside the config, as wind's hull
    if parent != cfg.hull.parent:
        cfg.hull.parent = raw["hull"]["parent"] = parent  # config.json then names the file wherever it is read
    return cfg, raw


def _read_toml(path: Path, what: str) -> dict:
    """The TOML table of ``path``; :class:`HullError` naming the file if it cannot be read or parsed."""
    try:
        return tomllib.loads(path.read_text())
    except OSError as e:
        raise HullError(f"{path}: cannot read the {what} ({e.strerror})") from None
    except tomllib.TOMLDecodeError as e:
        raise HullError(f"{path}: not valid TOML ({e})") from None


def _invalid(path: Path, e: ValidationError, root: type[BaseModel] = BaseModel) -> HullError:
    """One line naming the file and the field of the first problem; an unknown key with the nearest key its
    table takes (:func:`unknown_key`), an unknown objective kind with the nearest kind."""
    err = e.errors()[0]
    where = ".".join(str(p) for p in err["loc"] if p not in OPTIONS)  # a union's tag: the message names the kind
    msg = err["msg"].removeprefix("Value error, ")
    more = f" (and {len(e.errors()) - 1} more)" if len(e.errors()) > 1 else ""
    if err["type"] == "extra_forbidden":
        return HullError(f"{path}: {unknown_key(root, tuple(err['loc']))}{more}")
    if err["type"] == "union_tag_invalid":
        tag = (err.get("ctx") or {}).get("tag", "")
        msg = f"kind = {tag!r}: unknown kind{did_you_mean(tag, OPTIONS)} (expected one of {', '.join(OPTIONS)})"
    return HullError(f"{path}: {where + ': ' if where else ''}{msg}{more}")


def load_design(path: str | Path) -> DeformConfig:
    """Read and validate ``hullopt deform``'s design TOML with the run config's models (strict, the same defaults).

    Parameters
    ----------
    path : str or pathlib.Path
        The design's TOML file.

    Returns
    -------
    DeformConfig
        The validated design; a parent file given relative to the TOML's folder made absolute.

    Raises
    ------
    HullError
        A file that cannot be read or is not TOML, or an invalid design; the message names the file and the
        field of the problem.
    """
    path = Path(path)
    raw = _read_toml(path, "design")
    try:
        cfg = DeformConfig.model_validate(raw)
    except ValidationError as e:
        raise _invalid(path, e, DeformConfig) from None
    if cfg.parent is not None:
        cfg.parent = resolve_spec(cfg.parent, path.resolve().parent)
    return cfg


def resolve_spec(spec: str, folder: Path) -> str:
    """``spec`` with a relative file path made relative to ``folder`` (a config's folder).

    As the wind config's ``hull``: only when the file or run folder exists there; library names, builtins and
    absolute paths are unchanged.

    Parameters
    ----------
    spec : str
        A hull spec or parent (``parent:`` prefix and ``?…`` parameters kept as given).
    folder : pathlib.Path
        The folder a relative path is read from.

    Returns
    -------
    str
        ``spec`` with its file part as ``folder / path`` where that exists, else ``spec`` unchanged.
    """
    prefix = "parent:" if spec.startswith("parent:") else ""
    base, sep, query = spec.removeprefix(prefix).partition("?")
    if base.startswith("builtin:") or base in parent_names() or Path(base).is_absolute():
        return spec
    if not (folder / base).exists():
        return spec
    return prefix + str(folder / base) + sep + query


def conditions_text(objective: ObjectiveConfig) -> str:
    """Where an objective (or a sweep's measure) config is evaluated, as a caption.

    Parameters
    ----------
    objective : ObjectiveConfig
        The ``[objective]`` or ``[sweep.measure]`` config.

    Returns
    -------
    str
        Its profile (``"22, 24, 26 kn × (Hs 2.5 m/Tp 8 s, Hs 4 m/Tp 10 s), weighted"`` when the points are
        every speed in every sea), its speed list, or its speed and sea state; ``""`` without a speed.
    """
    def sea(hs, tp, heading):
        return "calm" if not hs else f"Hs {hs:g} m/Tp {tp:g} s" + (f" at {heading:g}°" if heading else "")

    profile = getattr(objective, "profile", None)
    if profile:
        speeds = list(dict.fromkeys(p.speed_kn for p in profile))
        seas = list(dict.fromkeys(sea(p.hs, p.tp, p.heading_deg) for p in profile))
        weighted = ", weighted" if len({p.weight for p in profile}) > 1 else ""
        if len(profile) == len(speeds) * len(seas):
            kn = ", ".join(f"{v:g}" for v in speeds) + " kn"
            return kn + ("" if seas == ["calm"] else f" × ({', '.join(seas)})") + weighted
        return "; ".join(f"{p.speed_kn:g} kn {sea(p.hs, p.tp, p.heading_deg)}" for p in profile) + weighted
    speeds = getattr(objective, "speeds_kn", None)
    if speeds:
        return ", ".join(f"{v:g}" for v in speeds) + " kn"
    speed = getattr(objective, "speed_kn", None)
    if speed is None:
        return ""
    hs = getattr(objective, "hs", 0.0)
    return f"{speed:g} kn" + (f", {sea(hs, objective.tp, getattr(objective, 'heading_deg', 0.0))}" if hs else "")
