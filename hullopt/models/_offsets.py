"""Offset tables (half-breadths at stations × waterlines) and the spline surface through them.

Two CSV layouts are read (comma or tab separated; ``#`` lines are comments, ``# key = value`` lines are
metadata):

* **wide**: header ``x,<z1>,<z2>,…`` (waterline heights in m); one row per station: its x [m from the AP],
  then the half-breadths [m]. Metadata: ``lpp`` (default: the largest x, i.e. the last station is the FP).
* **stations** (seed 003): header ``station,<wl0>,<wl1>,…`` (waterline numbers, a fractional one allowed:
  the DWL between two); rows named ``AP, 1/4, 1/2, 3/4, 1, 1 1/2, … 9 3/4, FP`` (or ``0`` … ``10``),
  ``AO``/``FO`` for the aft and fore ends. Metadata: ``lpp`` and ``waterline_spacing`` (required), ``AO``/``FO``
  (their station numbers), ``stations`` (the station intervals over Lpp, 10 by default: a yard's table of 0 … 20
  gives ``# stations = 20``, its FP is station 20).

Either layout may give ``knuckles = <station>@<z>; …``: the spline along that station is split at the
waterline ``z`` (a transom edge or chine), so the section keeps its corner.
Zero half-breadths mark where a section has not started yet (seed 003: "set to 0 and used as control
points"); the splines pass through them and the surface is clipped at y = 0.

A table read as a hull (:func:`offsets_to_sections`) keeps the natural spline of each curve — a station, or a
waterline along the length — that stays within its own offsets' range, and takes the shape-preserving PCHIP
(:func:`hullopt.geometry.pchip`, monotone between monotone offsets) for one that would overshoot: a flat
parallel middle body or a flat side bulges, a zero row dips below zero. So no offset of the hull exceeds the
table's extremes (Bwl is never wider than twice the widest offset, a zero AP row gives no immersed transom,
Lwl grows with the draft). The fairing's surface (:func:`offset_surface`) stays the linear natural-spline map.
"""

from __future__ import annotations

import csv
import math
import re
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..errors import HullError
from ..geometry import Sections, pchip, spline_matrix


@dataclass(frozen=True)
class OffsetTable:
    """A validated offset table. ``x (s,)`` stations [m] strictly increasing, ``z (w,)`` waterlines [m]
    strictly increasing, ``y (s, w)`` half-breadths [m] ≥ 0, ``knuckles`` maps a station index to the
    waterline index where its spline is split."""

    x: np.ndarray
    z: np.ndarray
    y: np.ndarray
    lpp: float
    knuckles: dict[int, int] = field(default_factory=dict)
    source: str = "<table>"

    def __post_init__(self):
        validate_offsets(self.x, self.z, self.y, self.source)
        if not (math.isfinite(self.lpp) and self.lpp > 0):
            raise HullError(f"{self.source}: lpp must be a positive number, got {self.lpp}")


def validate_offsets(x, z, y, source: str = "<table>", rows: list[int] | None = None) -> None:
    """Raise :class:`HullError` naming the row (file line when known) of the first problem."""
    x, z, y = np.asarray(x, float), np.asarray(z, float), np.asarray(y, float)
    line = (lambda i: f"line {rows[i]}") if rows else (lambda i: f"station {i}")
    if x.ndim != 1 or x.size < 2:
        raise HullError(f"{source}: need at least 2 stations, got {x.size}")
    if z.ndim != 1 or z.size < 2:
        raise HullError(f"{source}: need at least 2 waterlines, got {z.size}")
    if y.shape != (x.size, z.size):
        raise HullError(f"{source}: half-breadths have shape {y.shape}, expected {(x.size, z.size)}")
    for i in range(x.size):
        if not np.isfinite(x[i]):
            raise HullError(f"{source}, {line(i)}: station position is not a number")
        if i and x[i] <= x[i - 1]:
            what = "duplicate" if x[i] == x[i - 1] else "unsorted"
            raise HullError(
                f"{source}, {line(i)}: {what} station x = {x[i]:g} (after {x[i - 1]:g}); "
                "stations must be strictly increasing"
            )
        bad = ~np.isfinite(y[i]) | (y[i] < 0)
        if bad.any():
            j = int(np.argmax(bad))
            raise HullError(
                f"{source}, {line(i)}: half-breadth at waterline z = {z[j]:g} is {y[i, j]:g}; "
                "expected a number ≥ 0"
            )
    if not (np.all(np.isfinite(z)) and np.all(np.diff(z) > 0)):
        raise HullError(f"{source}: waterline heights {z.tolist()} must be numbers, strictly increasing")


_STATION_NAMES = {"AP": Fraction(0), "FP": Fraction(10)}


def parse_station(label: str) -> Fraction:
    """``'AP'`` → 0, ``'9 3/4'`` → 39/4, ``'1/2'`` → 1/2, ``'FP'`` → 10 (station numbers, Lpp/10 apart).

    Parameters
    ----------
    label : str
        A station label: ``AP``, ``FP``, a whole number, a fraction ``a/b`` or a mixed number ``n a/b``.

    Returns
    -------
    Fraction
        The station number (0 at the AP, 10 at the FP).
    """
    s = label.strip().upper()
    if s in _STATION_NAMES:
        return _STATION_NAMES[s]
    m = re.fullmatch(r"(-?\d+)?\s*(?:(\d+)/(\d+))?", s)
    if not s or not m or (m.group(1) is None and m.group(2) is None):
        raise ValueError(label)
    whole = Fraction(int(m.group(1))) if m.group(1) else Fraction(0)
    frac = Fraction(int(m.group(2)), int(m.group(3))) if m.group(2) else Fraction(0)
    return whole + frac if whole >= 0 else whole - frac


def _number(text: str, where: str) -> float:
    try:
        v = float(text)
    except ValueError:
        raise HullError(f"{where}: {text.strip()!r} is not a number") from None
    return v


def read_offsets(path: str | Path) -> OffsetTable:
    """Read an offset table in the wide or the stations layout (see the module docstring).

    Parameters
    ----------
    path : str or Path
        The CSV file (comma or tab separated).

    Returns
    -------
    OffsetTable
        ``x (s,)`` [m from the AP], ``z (w,)`` [m above the baseline], ``y (s, w)`` [m], ``lpp`` [m],
        ``knuckles``, ``source`` (the path); :class:`HullError` naming the line if the file is not a valid table.
    """
    path = Path(path)
    try:
        text = path.read_text()
    except (OSError, UnicodeDecodeError) as e:
        raise HullError(f"{path}: cannot read the offset table ({e})") from None
    meta: dict[str, str] = {}
    records: list[tuple[int, list[str]]] = []
    delim = "\t" if "\t" in text and "," not in text else ","
    for lineno, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith("#"):
            m = re.fullmatch(r"#\s*([A-Za-z_]\w*)\s*=\s*(.+?)\s*", stripped)
            if m:
                meta[m.group(1)] = m.group(2)
            continue
        records.append((lineno, [c.strip() for c in next(csv.reader([line], delimiter=delim))]))
    if len(records) < 3:
        raise HullError(f"{path}: expected a header and at least 2 station rows")
    (hline, header), body = records[0], records[1:]
    kind = header[0].lower()
    if kind not in ("x", "station"):
        raise HullError(
            f"{path}, line {hline}: the first header cell must be 'x' (wide layout) or 'station' "
            f"(seed-003 layout), got {header[0]!r}"
        )
    cols = [_number(h, f"{path}, line {hline}, waterline header") for h in header[1:]]
    for lineno, row in body:
        if len(row) != len(header):
            raise HullError(f"{path}, line {lineno}: {len(row)} cells, expected {len(header)} as in the header")
    y = np.array([[_number(c, f"{path}, line {ln}") for c in row[1:]] for ln, row in body])
    lines = [ln for ln, _ in body]
    if kind == "x":
        x = np.array([_number(row[0], f"{path}, line {ln}, station x") for ln, row in body])
        z = np.asarray(cols)
        lpp = _number(meta["lpp"], f"{path}, metadata lpp") if "lpp" in meta else float(np.max(x))
    else:
        for key in ("lpp", "waterline_spacing"):
            if key not in meta:
                raise HullError(f"{path}: the stations layout needs a metadata line '# {key} = <m>'")
        lpp = _number(meta["lpp"], f"{path}, metadata lpp")
        dz = _number(meta["waterline_spacing"], f"{path}, metadata waterline_spacing")
        x = np.array([_station_x(row[0], meta, lpp, f"{path}, line {ln}") for ln, row in body])
        z = np.asarray(cols) * dz
    validate_offsets(x, z, y, str(path), rows=lines)
    to_x = (lambda st: _station_x(st, meta, lpp, str(path))) if kind == "station" else float
    knuckles = _parse_knuckles(meta.get("knuckles", ""), x, z, to_x, str(path))
    return OffsetTable(x=x, z=z, y=y, lpp=lpp, knuckles=knuckles, source=str(path))


def _station_spacing(meta: dict[str, str], lpp: float, where: str) -> tuple[float, float]:
    """The station intervals over Lpp (``# stations``, 10 by default) and the station spacing [m]."""
    n = _number(meta.get("stations", "10"), f"{where}, metadata stations")
    if not (math.isfinite(n) and n >= 1):
        raise HullError(f"{where}: metadata stations = {n:g}; expected the station intervals over Lpp (≥ 1)")
    return n, lpp / n


def _station_x(label: str, meta: dict[str, str], lpp: float, where: str) -> float:
    key = label.strip().upper()
    n, dx = _station_spacing(meta, lpp, where)
    if key in ("AO", "FO"):
        if key not in meta:
            raise HullError(f"{where}: row {key} needs its station number as metadata '# {key} = <station>'")
        return _number(meta[key], f"{where}, metadata {key}") * dx
    if key == "FP":
        return n * dx
    try:
        return float(parse_station(label)) * dx
    except ValueError:
        raise HullError(
            f"{where}: unknown station {label!r}; expected AP, FP, AO, FO or a station number such as 9 3/4"
        ) from None


def _parse_knuckles(spec: str, x, z, to_x, where) -> dict[int, int]:
    out = {}
    for item in filter(None, (s.strip() for s in spec.split(";"))):
        try:
            st, zz = item.split("@")
            xs = to_x(st)
            i = int(np.flatnonzero(np.isclose(x, xs))[0])
            j = int(np.flatnonzero(np.isclose(z, float(zz)))[0])
        except (ValueError, IndexError, HullError):
            raise HullError(
                f"{where}: knuckle {item!r} must be '<station>@<z>' with a station and a waterline of the table"
            ) from None
        if not 0 < j < len(z) - 1:
            raise HullError(f"{where}: knuckle {item!r} must be at an interior waterline")
        out[i] = j
    return out


class OffsetSurface(eqx.Module):
    """The spline surface through an offset table, as a linear map ``half-breadths (s, w) → Sections``.

    Splines run along each station (split at knuckles), then along each fine waterline; both are natural
    cubic splines with fixed knots, precomputed as matrices, so the map is two matrix products and a clip
    at y = 0, differentiable in the offsets (the parameters for fairing).
    """

    x_fine: Float[Array, " n"]
    z_fine: Float[Array, " m"]
    along_z: Float[Array, "s m w"]  # per table station (knuckles differ)
    along_x: Float[Array, "n s"]
    lpp: Float[Array, ""]

    def __call__(self, y: Float[Array, "s w"]) -> Sections:
        fine_z = jnp.einsum("smw,sw->sm", self.along_z, y)
        yy = jnp.maximum(self.along_x @ fine_z, 0.0)
        zz = jnp.broadcast_to(self.z_fine, yy.shape)
        yz = jnp.stack([yy, zz], axis=-1)
        keel = jnp.stack([jnp.zeros_like(self.x_fine), jnp.full_like(self.x_fine, self.z_fine[0])], -1)
        return Sections(x=self.x_fine, yz=jnp.concatenate([keel[:, None], yz], axis=1), lpp=self.lpp)


def offset_surface(table: OffsetTable, n_stations: int = 121, n_points: int = 81) -> OffsetSurface:
    """Precompute the spline maps of ``table`` onto ``n_stations`` stations (equally spaced over the table's
    length, odd for Simpson's rule) and ``n_points`` heights per section (equally spaced, plus the table's own
    waterlines).

    Parameters
    ----------
    table : OffsetTable
        Stations ``x (s,)``, waterlines ``z (w,)``, half-breadths ``y (s, w)`` [m].
    n_stations : int
        Stations of the result (121 by default; made odd by adding 1).
    n_points : int
        Equally spaced heights per section before the table's waterlines are added (81 by default).

    Returns
    -------
    OffsetSurface
        The map ``y (s, w) → Sections`` with ``x (n,)``, ``yz (n, m+1, 2)`` [m] (keel point first),
        ``n = n_stations`` (odd), ``m`` = the heights.
    """
    n_stations += 1 - n_stations % 2
    x_fine = np.linspace(table.x[0], table.x[-1], n_stations)
    # The table's own waterlines stay on the fine grid, so the surface passes through every offset (a nearly
    # flat bottom, which the writer resolves with waterlines clustered there, is not cut off) and every
    # knuckle is a polyline vertex.
    z_fine = np.union1d(np.linspace(table.z[0], table.z[-1], n_points), table.z)
    default = spline_matrix(table.z, z_fine)
    along_z = np.repeat(default[None], len(table.x), axis=0)
    for i, j in table.knuckles.items():
        along_z[i] = _split_spline_matrix(table.z, z_fine, j)
    return OffsetSurface(
        x_fine=jnp.asarray(x_fine),
        z_fine=jnp.asarray(z_fine),
        along_z=jnp.asarray(along_z),
        along_x=jnp.asarray(spline_matrix(table.x, x_fine)),
        lpp=jnp.asarray(table.lpp),
    )


def _split_spline_matrix(knots: np.ndarray, at: np.ndarray, j: int) -> np.ndarray:
    """Spline matrix with two independent natural splines, on ``knots[:j+1]`` and ``knots[j:]``."""
    w = np.zeros((len(at), len(knots)))
    lower = at <= knots[j]
    w[lower, : j + 1] = spline_matrix(knots[: j + 1], at[lower])
    w[~lower, j:] = spline_matrix(knots[j:], at[~lower])
    return w


def offsets_to_sections(table: OffsetTable, n_stations: int = 121, n_points: int = 81) -> Sections:
    """Sections of the surface through ``table``: each station's and each waterline's natural spline (see
    :class:`OffsetSurface`), or PCHIP where the natural spline would leave the range of that curve's offsets
    (the module's docstring), so that no offset exceeds the table's extremes.

    Parameters
    ----------
    table : OffsetTable
        Stations ``x (s,)``, waterlines ``z (w,)``, half-breadths ``y (s, w)`` [m].
    n_stations, n_points : int
        As for :func:`offset_surface` (121 and 81 by default).

    Returns
    -------
    Sections
        ``x (n,)`` [m from the AP], ``yz (n, m+1, 2)`` [m], ``lpp`` [m] from the table.
    """
    surface = offset_surface(table, n_stations, n_points)
    y = np.asarray(table.y, dtype=float)
    x_fine, z_fine = np.asarray(surface.x_fine), np.asarray(surface.z_fine)
    # along each table station: the natural spline, or PCHIP (split at its knuckle as the spline is)
    fine_z = np.einsum("smw,sw->sm", np.asarray(surface.along_z), y)
    for i in np.flatnonzero(_overshoots(fine_z, y, axis=1)):
        fine_z[i] = _pchip_split(table.z, y[i], z_fine, table.knuckles.get(i))
    # along each fine waterline: the natural spline through the stations, or PCHIP
    yy = np.asarray(surface.along_x) @ fine_z
    bad = _overshoots(yy, fine_z, axis=0)
    if bad.any():
        yy[:, bad] = pchip(np.asarray(table.x, dtype=float), fine_z[:, bad], x_fine)
    yy = np.maximum(yy, 0.0)
    yz = np.stack([yy, np.broadcast_to(z_fine, yy.shape)], axis=-1)
    keel = np.stack([np.zeros_like(x_fine), np.full_like(x_fine, z_fine[0])], -1)
    return Sections(x=jnp.asarray(x_fine), yz=jnp.asarray(np.concatenate([keel[:, None], yz], axis=1)),
                    lpp=jnp.asarray(table.lpp))


def _overshoots(fine: np.ndarray, knots: np.ndarray, axis: int) -> np.ndarray:
    """Which curves (along ``axis``) of the interpolated ``fine`` leave the range of their ``knots`` (beyond
    round-off)."""
    lo, hi = knots.min(axis=axis), knots.max(axis=axis)
    tol = 1e-9 * max(float(np.abs(knots).max(initial=0.0)), 1.0)
    return (fine.min(axis=axis) < lo - tol) | (fine.max(axis=axis) > hi + tol)


def _pchip_split(knots: np.ndarray, y: np.ndarray, at: np.ndarray, j: int | None) -> np.ndarray:
    """PCHIP through ``(knots, y)`` at ``at``, split into two at knot ``j`` (a knuckle) when given."""
    knots = np.asarray(knots, dtype=float)
    if j is None:
        return pchip(knots, y, at)
    lower = at <= knots[j]
    out = np.empty(at.shape)
    out[lower] = pchip(knots[: j + 1], y[: j + 1], at[lower])
    out[~lower] = pchip(knots[j:], y[j:], at[~lower])
    return out
