"""Offset tables cut from sections, written in the two layouts :func:`hullopt.models.read_offsets` reads:
the wide layout (``x`` [m] × waterline heights [m]: machine data, a run's ``offsets.csv``) and the stations
layout of seed 003 (station numbers × waterline numbers: a yard's table of offsets, stations 0…20 and round
waterlines with the DWL)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from jaxtyping import ArrayLike, Float

from .._types import Stations, Waterlines
from ..geometry import SAME_POINT, TINY_LENGTH, Sections, atomic_write_bytes
from ._grid import lowest_deck, station_x, waterline_heights, waterline_spacing


def half_breadths(sections: Sections, x: Stations | Sequence[float], z: Waterlines) -> np.ndarray:
    """Half-breadths ``(len(x), len(z))`` [m]: at each station position (sections interpolated linearly
    along x, point by point) the outermost crossing of the section with each waterline, 0 where the section
    does not reach it.

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    x : (nx,) array_like
        Station positions [m from the AP]; clamped to the sections' extent.
    z : (nz,) array_like
        Waterline heights [m above the baseline].

    Returns
    -------
    numpy.ndarray
        (nx, nz) float half-breadths [m], ≥ 0.
    """
    xs = np.asarray(sections.x, float)
    yz = np.asarray(sections.yz, float)
    x, z = np.asarray(x, float), np.asarray(z, float)
    i = np.clip(np.searchsorted(xs, x) - 1, 0, len(xs) - 2)
    t = np.clip((x - xs[i]) / (xs[i + 1] - xs[i]), 0.0, 1.0)[:, None, None]
    sec = (1 - t) * yz[i] + t * yz[i + 1]
    p0, p1 = sec[:, None, :-1], sec[:, None, 1:]
    a, b = p0[..., 1], p1[..., 1]
    lev = z[None, :, None]
    hit = ((a - lev) * (b - lev) < 0) | (a == lev) | (b == lev)
    s = np.where(hit, (lev - a) / np.where(b != a, b - a, 1.0), 0.0)
    y = p0[..., 0] + s * (p1[..., 0] - p0[..., 0])
    return np.maximum(np.max(np.where(hit, y, 0.0), axis=-1), 0.0)


def _write(path, header: list[str], rows: list[list[str]], meta: dict[str, str], comment: str) -> Path:
    lines = [f"# {comment}"] + [f"# {k} = {v}" for k, v in meta.items()] + [",".join(header)]
    lines += [",".join(r) for r in rows]
    atomic_write_bytes(path, ("\n".join(lines) + "\n").encode())
    return Path(path)


def write_offset_grid(path: str | os.PathLike, x: Stations | Sequence[float], z: Waterlines,
                      y: Float[ArrayLike, "nx nz"], lpp: float, comment: str) -> Path:
    """An offset table given as a grid, in the wide layout (header ``x,<z1>,…``, one row per station), at full
    precision (a faired table read back is the table faired), written atomically.

    Parameters
    ----------
    path : str or os.PathLike
        The CSV file to write.
    x : (nx,) array_like
        Station positions [m from the AP].
    z : (nz,) array_like
        Waterline heights [m above the baseline].
    y : (nx, nz) array_like
        Half-breadths [m].
    lpp : float
        Length between perpendiculars [m] (the ``# lpp`` line).
    comment : str
        The first comment line (what the table is).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    rows = [[f"{xi:.17g}", *(f"{v:.9f}" for v in row)] for xi, row in zip(np.asarray(x, float), np.asarray(y, float))]
    return _write(path, ["x", *(f"{v:.17g}" for v in np.asarray(z, float))], rows, {"lpp": f"{float(lpp):.17g}"},
                  comment)


def write_offsets_wide(sections: Sections, path: str | os.PathLike, x: Stations | Sequence[float] | None = None,
                       z: Waterlines | None = None, name: str = "", dense: bool = False) -> Path:
    """Wide layout: header ``x,<z1>,…``, one row per station (default: the sections' own stations) with
    half-breadths [m] at waterlines ``z`` [m] (default: 11 from the keel to the lowest deck edge).

    With ``dense`` (what a run writes), the waterlines are :func:`dense_waterlines` plus the height of each
    station's knuckle (:func:`knuckles`: a chine, a transom edge), and ``# knuckles = x@z; …`` names them,
    so that the table read back — ``hullopt hydro offsets.csv`` — keeps the corners and gives the hull's ∇
    to about 1e-4 (the reader keeps the table's own waterlines, so the clustered ones resolve a flat bottom
    with a slight rise of floor, as the DTC's). Metadata: ``lpp`` [m] and ``deck``
    [m], the top waterline (the lowest deck edge), which the reader takes as the deck.

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    path : str or os.PathLike
        The CSV file to write.
    x : (nx,) array_like or None
        Station positions [m from the AP]; None: the sections' stations.
    z : (nz,) array_like or None
        Waterline heights [m above the baseline]; None: the default (or ``dense``) waterlines.
    name : str
        The hull's name for the comment line.
    dense : bool
        Use :func:`dense_waterlines` and the stations' knuckles (when ``z`` is None).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    x = np.asarray(sections.x, float) if x is None else np.asarray(x, float)
    corners: dict[int, float] = {}
    if z is None:
        z = dense_waterlines(sections) if dense else _default_waterlines(sections)
        if dense and np.array_equal(x, np.asarray(sections.x, float)):
            corners = knuckles(sections, float(z[-1]))
            z = np.union1d(z, np.fromiter(corners.values(), float, len(corners)))
    z = np.asarray(z, float)
    y = half_breadths(sections, x, z)
    fx, fz = [f"{v:.6g}" for v in x], [f"{v:.6g}" for v in z]
    rows = [[xi, *(f"{v:.6g}" for v in yi)] for xi, yi in zip(fx, y)]
    meta = {"lpp": f"{float(sections.lpp):.6g}", "deck": fz[-1]}
    if corners:
        meta["knuckles"] = "; ".join(f"{fx[i]}@{fz[int(np.searchsorted(z, zk))]}" for i, zk in sorted(corners.items()))
    return _write(path, ["x", *fz], rows, meta, f"offsets of {name or 'a hull'} (half-breadths, m)")


def knuckles(sections: Sections, top: float, angle_deg: float = 30.0) -> dict[int, float]:
    """The knuckle of each station that has one: ``{station index: height [m]}`` of its sharpest corner (a
    turn of the section polyline by more than ``angle_deg``), off the centreline and strictly between the
    baseline and ``top`` — one per station, as the offset reader splits a station's spline once. Corners
    closer than ``1e-4 · top`` in height share one height (so one waterline)."""
    yz = np.asarray(sections.yz, float)
    breadth = max(float(yz[..., 0].max()), TINY_LENGTH)
    out: dict[int, float] = {}
    heights: list[float] = []
    for i, p in enumerate(yz):
        p = p[np.r_[True, np.any(np.abs(np.diff(p, axis=0)) > SAME_POINT * breadth, axis=1)]]
        if len(p) < 3:
            continue
        d = np.diff(p, axis=0)
        ang = np.arctan2(d[:, 1], d[:, 0])
        turn = np.abs(np.angle(np.exp(1j * np.diff(ang))))
        v = p[1:-1]
        inside = (v[:, 1] > 1e-6 * top) & (v[:, 1] < top * (1 - 1e-6))
        ok = (turn > np.radians(angle_deg)) & (v[:, 0] > 1e-3 * breadth) & inside
        if not ok.any():
            continue
        zk = float(v[np.argmax(np.where(ok, turn, -1.0)), 1])
        near = [h for h in heights if abs(h - zk) <= 1e-4 * top]
        if near:
            zk = near[0]
        else:
            heights.append(zk)
        out[i] = zk
    return out


def dense_waterlines(sections: Sections, n: int = 41) -> np.ndarray:
    """``n`` waterlines [m] from the baseline to the lowest deck edge, spaced as the square of an even
    parameter: close together at the bottom, where a section's half-breadth rises fastest (the turn of the
    bilge), so the reader's splines along each station follow it (Wigley-form fit run: ∇ read back to
    −9e-5 with 41 of them, against −3.6e-4 with 11 even ones)."""
    top = float(_default_waterlines(sections, 2)[-1])
    return top * np.linspace(0.0, 1.0, n) ** 2


def offset_table(sections: Sections, draft: float, stations: int = 20, spacing: float | None = None
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """A yard's table of offsets: half-breadths at the stations 0 (AP) … ``stations`` (FP) — and at the hull's
    aft and fore ends where it reaches beyond the perpendiculars (a transom, a bulb) — and at the waterlines every
    ``spacing`` [m] from the baseline to below the lowest deck at side, with the DWL among them: the ordinates of
    the lines plan (:mod:`._grid`); 0 where a section has no breadth at a waterline.

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    draft : float
        The design draft [m above the baseline] (the DWL column).
    stations : int
        Station intervals over Lpp.
    spacing : float or None
        Waterline spacing [m]; None: the round spacing of :func:`~._grid.waterline_spacing`.

    Returns
    -------
    tuple
        ``x (s,)`` [m from the AP], ``z (w,)`` [m above the baseline], ``y (s, w)`` [m], ``spacing`` [m].
    """
    keel, depth = float(np.min(np.asarray(sections.yz)[..., 1])), float(np.max(np.asarray(sections.yz)[..., 1]))
    if spacing is None:
        spacing = waterline_spacing(float(draft), depth - max(keel, 0.0))
    z = np.union1d(waterline_heights(spacing, lowest_deck(sections, stations), keel), [float(draft)])
    xs, lpp = np.asarray(sections.x, float), float(sections.lpp)
    ends = [v for v in (xs[0], xs[-1]) if v < -1e-6 * lpp or v > lpp * (1 + 1e-6)]
    x = np.union1d(station_x(lpp, stations), ends)
    return x, z, half_breadths(sections, x, z), float(spacing)


def write_offsets_stations(sections: Sections, path: str | os.PathLike, draft: float, stations: int = 20,
                           spacing: float | None = None, name: str = "") -> Path:
    """The yard's table of offsets (:func:`offset_table`) in the stations layout that
    :func:`hullopt.models.read_offsets` reads back: one row per station, numbered 0 (AP) … ``stations`` (FP)
    (``# stations = N``) — ``AO`` and ``FO`` the hull's aft and fore ends beyond the perpendiculars, their station
    numbers as metadata — one column per waterline, headed by its number (its height over
    ``# waterline_spacing``: the DWL's may be fractional, 7.25 for 14.5 m at 2 m), half-breadths in m to the
    millimetre, 0 where the section has no breadth; a comment row above the header gives each waterline's height
    [m].

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    path : str or os.PathLike
        The CSV file to write.
    draft : float
        The design draft [m above the baseline].
    stations : int
        Station intervals over Lpp (20: stations 0…20).
    spacing : float or None
        Waterline spacing [m]; None: the round default.
    name : str
        The hull's name for the comment line.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    lpp = float(sections.lpp)
    x, z, y, spacing = offset_table(sections, draft, stations, spacing)
    numbers = [f"{v / spacing:.6g}" for v in z]
    meta = {"lpp": f"{lpp:.6g}", "stations": str(stations), "waterline_spacing": f"{spacing:g}",
            "design_draft": f"{float(draft):.6g}"}
    station = x * stations / lpp
    labels = [("AO" if k < 0 else "FO") if abs(k - round(k)) > 1e-9 else str(round(k)) for k in station]
    meta |= {label: f"{k:.6g}" for label, k in zip(labels, station) if label in ("AO", "FO")}
    rows = [[label, *(f"{v:.3f}" for v in yk)] for label, yk in zip(labels, y)]
    comment = (f"offsets of {name or 'a hull'}: half-breadths [m] at stations 0 (AP) … {stations} (FP), "
               f"{lpp / stations:.6g} m apart, and waterlines {spacing:g} m apart (DWL = waterline "
               f"{float(draft) / spacing:.6g}, T = {float(draft):.6g} m)")
    heights = "# z above base [m]," + ",".join(f"{v:.6g}" for v in z)
    lines = [f"# {comment}"] + [f"# {k} = {v}" for k, v in meta.items()] + [heights, ",".join(["station", *numbers])]
    lines += [",".join(r) for r in rows]
    atomic_write_bytes(path, ("\n".join(lines) + "\n").encode())
    return Path(path)


def _default_waterlines(sections: Sections, n: int = 11) -> np.ndarray:
    yz = np.asarray(sections.yz, float)
    wide = yz[:, -1, 0] > 0.05 * yz[..., 0].max()
    top = float(np.min(yz[wide, -1, 1])) if wide.any() else float(yz[..., 1].max())
    return np.linspace(0.0, top, n)
