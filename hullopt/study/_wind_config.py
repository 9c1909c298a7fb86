"""Wind configs: a hull with named above-deck parts (TOML), or drawings with a scale (TOML or JSON).

Geometry (``configs/wind_example.toml``)::

    hull = "builtin:box?L=250&B=40&D=24"      # a hull spec; relative paths are relative to the config
    draft = 12.0                                # [m]; default: the hull's design draft
    model = "fujiwara1998"                      # or fujiwara2005, isherwood, blendermann
    ship_type = "Container ship, loaded"        # Blendermann's type
    [[parts]]                                   # a box: x = [aft, fore] from the AP, z = [low, top] from
    name = "bridge"                             #   the baseline, full breadth (centred on y_centre)
    kind = "superstructure"                     # superstructure | cargo | mast
    x = [30, 42]
    z = [24, 60]
    breadth = 36
    [[parts]]                                   # or convex polygons: side [[x, z], …], front [[y, z], …]
    name = "funnel"                             #   (without front: a rectangle of `breadth` over the
    kind = "superstructure"                     #   side polygon's height)
    side = [[20, 24], [28, 24], [27, 55], [21, 55]]
    breadth = 8

Drawings (seed 004): ``[drawings]`` in TOML, or the same keys at the top of a JSON file::

    side = "side.png"; front = "front.png"      # relative to the config
    side_scale = {pixels_per_metre = 2, waterline_row = 150, origin_col = 0, bow = "right"}
    front_scale = {pixels_per_metre = 2, waterline_row = 150}
    parts = [{name = "bridge", kind = "superstructure", colour = [128, 0, 0]},
             {name = "mast", kind = "mast", polygon = [[400, 20], [402, 20], [402, 149], [400, 149]]}]
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path
from typing import Literal

from pydantic import (
    BaseModel,
    ConfigDict,
    ValidationError,
    field_validator,
    model_validator,
)

from ..constants import RHO_AIR
from ..errors import HullError
from ._config import unknown_key
from ..wind import (
    DEFAULT_SHIP_TYPE,
    MODELS,
    Parts,
    PartSpec,
    ViewScale,
    box_parts,
    concat_parts,
    polygon_parts,
)

Kind = Literal["superstructure", "cargo", "mast"]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid")


class PartConfig(_Strict):
    """One part: a box (``x``, ``z``, ``breadth``) or convex polygons (``side`` and ``front`` or ``breadth``)."""

    name: str
    kind: Kind = "superstructure"
    group: str | None = None
    x: tuple[float, float] | None = None
    z: tuple[float, float] | None = None
    breadth: float | None = None
    y_centre: float = 0.0
    side: list[tuple[float, float]] | None = None
    front: list[tuple[float, float]] | None = None

    @model_validator(mode="after")
    def _shape(self):
        if self.side is None:
            if self.x is None or self.z is None or self.breadth is None:
                raise ValueError("a box needs x = [aft, fore], z = [low, top] and breadth (or give side = [[x, z], …])")
            if not (self.x[0] < self.x[1] and self.z[0] < self.z[1] and self.breadth > 0):
                raise ValueError("a box needs x[0] < x[1], z[0] < z[1] and breadth > 0")
        elif self.front is None and not (self.breadth and self.breadth > 0):
            raise ValueError("a polygon part needs front = [[y, z], …] or a breadth > 0")
        return self


class HullWindConfig(_Strict):
    """A hull spec, a draft, the parts and the model settings."""

    hull: str
    draft: float | None = None
    model: str = "fujiwara1998"
    ship_type: str = DEFAULT_SHIP_TYPE
    rho_air: float = RHO_AIR
    y56: str = "C*H_C/A_L"  # Fujiwara 1998's Y5 group; "L*H_C/A_L" as seed 004 eq. (7) prints it
    parts: list[PartConfig] = []

    @field_validator("model")
    @classmethod
    def _model(cls, v):
        if v not in MODELS:
            raise ValueError(f"expected one of {', '.join(MODELS)}")
        return v


class ScaleConfig(_Strict):
    pixels_per_metre: float
    waterline_row: float
    origin_col: float = 0.0
    bow: Literal["right", "left"] = "right"

    def scale(self) -> ViewScale:
        return ViewScale(self.pixels_per_metre, self.waterline_row, self.origin_col, self.bow)


class DrawingPartConfig(_Strict):
    name: str
    kind: Literal["hull", "superstructure", "cargo", "mast"] = "superstructure"
    colour: tuple[int, int, int] | None = None
    polygon: list[tuple[float, float]] | None = None
    group: str = ""
    tolerance: float = 8.0


class DrawingsConfig(_Strict):
    """Side and front views with their scales and the parts picked in the side view."""

    side: str
    front: str
    side_scale: ScaleConfig
    front_scale: ScaleConfig
    threshold: float = 0.5
    parts: list[DrawingPartConfig] = []
    model: str = "fujiwara1998"
    ship_type: str = DEFAULT_SHIP_TYPE
    rho_air: float = RHO_AIR
    y56: str = "C*H_C/A_L"  # Fujiwara 1998's Y5 group; "L*H_C/A_L" as seed 004 eq. (7) prints it

    def part_specs(self) -> list[PartSpec]:
        return [PartSpec(p.name, p.kind, p.colour, p.polygon and [list(q) for q in p.polygon], p.group, p.tolerance)
                for p in self.parts]


def _validate(cls, data: dict, where: str):
    try:
        return cls.model_validate(data)
    except ValidationError as e:
        err = e.errors()[0]
        loc = ".".join(str(x) for x in err["loc"]) or "(top level)"
        msg = err["msg"].removeprefix("Value error, ")
        if err["type"] == "missing" and err["loc"][-1] in ("pixels_per_metre", "waterline_row", "side_scale", "front_scale"):
            msg += " (a drawing needs its scale: pixels_per_metre and waterline_row)"
        if err["type"] == "extra_forbidden":  # the nearest key that table takes
            raise HullError(f"{where}: {unknown_key(cls, tuple(err['loc']))}") from None
        raise HullError(f"{where}: {loc}: {msg}") from None


def read_wind_config(path: str | Path) -> HullWindConfig | DrawingsConfig:
    """Read a wind config (TOML: a hull with parts, or ``[drawings]``; JSON: drawings).

    Paths in it are made relative to the config's folder.

    Parameters
    ----------
    path : str or pathlib.Path
        The config file: ``.toml`` or ``.json``.

    Returns
    -------
    HullWindConfig or DrawingsConfig
        The validated config: a hull spec, draft [m], parts and model settings, with a hull file beside the
        config made absolute; or the drawings with their paths made absolute.

    Raises
    ------
    HullError
        A missing file, another suffix, a file that cannot be parsed, or an invalid config; the message names the
        file and the field.
    """
    path = Path(path)
    if not path.is_file():
        raise HullError(f"{path}: no such config file")
    try:
        if path.suffix.lower() == ".json":
            data = json.loads(path.read_text(encoding="utf-8"))
            data = {"drawings": data}
        elif path.suffix.lower() == ".toml":
            data = tomllib.loads(path.read_text(encoding="utf-8"))
        else:
            raise HullError(f"{path}: expected a .toml config or a .json drawings spec")
    except (tomllib.TOMLDecodeError, json.JSONDecodeError, UnicodeDecodeError) as e:
        raise HullError(f"{path}: cannot read it: {e}") from None
    if not isinstance(data, dict):
        raise HullError(f"{path}: expected a table of settings")
    base = path.resolve().parent
    if "drawings" in data:
        extra = sorted(set(data) - {"drawings"})
        if extra:
            raise HullError(f"{path}: {extra[0]}: unexpected beside [drawings]")
        cfg = _validate(DrawingsConfig, data["drawings"], str(path))
        return cfg.model_copy(update={"side": str(base / cfg.side), "front": str(base / cfg.front)})
    cfg = _validate(HullWindConfig, data, str(path))
    spec, _, query = cfg.hull.partition("?")
    if not spec.startswith("builtin:") and not Path(spec).is_absolute() and (base / spec).exists():
        cfg = cfg.model_copy(update={"hull": str(base / spec) + (f"?{query}" if query else "")})
    return cfg


def config_parts(parts: list[PartConfig]) -> Parts:
    """The :class:`~hullopt.wind.Parts` of a config (boxes and polygons, in config order).

    Parameters
    ----------
    parts : list of PartConfig
        The config's ``[[parts]]``: boxes (``x``, ``z`` [m], ``breadth`` [m]) or polygons (``side = [[x, z], …]``
        and ``front = [[y, z], …]`` [m], or ``breadth``).

    Returns
    -------
    Parts
        The parts, concatenated: a polygon without ``front`` has a rectangular front of ``breadth`` over its side
        polygon's height, centred on ``y_centre``.
    """
    out = []
    for p in parts:
        group = [p.group] if p.group is not None else None
        if p.side is None:
            out.append(box_parts([p.name], [p.kind], p.x[0], p.x[1], p.z[0], p.z[1], p.breadth, p.y_centre, group))
        else:
            zs = [q[1] for q in p.side]
            b = p.breadth or 0.0
            front = p.front or [(p.y_centre - b / 2, min(zs)), (p.y_centre + b / 2, min(zs)),
                                (p.y_centre + b / 2, max(zs)), (p.y_centre - b / 2, max(zs))]
            out.append(polygon_parts([p.name], [p.kind], [p.side], [front], group))
    return concat_parts(*out)
