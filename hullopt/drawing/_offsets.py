"""Offset tables cut from sections, written in the two layouts :func:`hullopt.models.read_offsets` reads:
the wide layout (``x`` [m] × waterline heights [m]) and the seed-003 stations layout (AP, ¼, ½, … 9¾, FP ×
waterline numbers)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from fractions import Fraction
from pathlib import Path

import numpy as np
from jaxtyping import ArrayLike, Float

from .._types import Stations, Waterlines
from ..geometry import SAME_POINT, TINY_LENGTH, Sections, atomic_write_bytes

# The standard station list of seed 003 (station numbers, Lpp/10 apart).
SEED003_STATIONS = tuple(Fraction(s) for s in (
    "0", "1/4", "1/2", "3/4", "1", "3/2", "2", "5/2", "3", "4", "5", "6", "7", "15/2", "8", "17/2", "9",
    "37/4", "19/2", "39/4", "10"))


def station_label(s: Fraction) -> str:
    """``0`` → ``AP``, ``10`` → ``FP``, ``3/2`` → ``1 1/2``, ``1/4`` → ``1/4``.

    Parameters
    ----------
    s : fractions.Fraction
        Station number, 0 (AP) to 10 (FP).

    Returns
    -------
    str
        The label as the seed-003 layout writes it.
    """
    if s == 0:
        return "AP"
    if s == 10:
        return "FP"
    whole, rest = divmod(s, 1)
    if rest == 0:
        return str(int(whole))
    return f"{int(whole)} {rest}" if whole else str(rest)


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


def write_offsets_stations(sections: Sections, path: str | os.PathLike, n_waterlines: int = 11,
                           name: str = "") -> Path:
    """Seed-003 layout: rows AP, 1/4, … 9 3/4, FP; columns waterline numbers 0…n−1, equally spaced from
    the baseline to the lowest deck edge (``waterline_spacing`` metadata).

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    path : str or os.PathLike
        The CSV file to write.
    n_waterlines : int
        Number of waterlines, the baseline (0) to the lowest deck edge.
    name : str
        The hull's name for the comment line.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    lpp = float(sections.lpp)
    dz = float(_default_waterlines(sections, n_waterlines)[1])
    z = dz * np.arange(n_waterlines)
    x = np.array([float(s) * lpp / 10.0 for s in SEED003_STATIONS])
    y = half_breadths(sections, x, z)
    rows = [[station_label(s), *(f"{v:.6g}" for v in yi)] for s, yi in zip(SEED003_STATIONS, y)]
    meta = {"lpp": f"{lpp:.6g}", "waterline_spacing": f"{dz:.6g}"}
    return _write(path, ["station", *map(str, range(n_waterlines))], rows, meta,
                  f"offsets of {name or 'a hull'} (half-breadths, m; seed-003 station layout)")


def _default_waterlines(sections: Sections, n: int = 11) -> np.ndarray:
    yz = np.asarray(sections.yz, float)
    wide = yz[:, -1, 0] > 0.05 * yz[..., 0].max()
    top = float(np.min(yz[wide, -1, 1])) if wide.any() else float(yz[..., 1].max())
    return np.linspace(0.0, top, n)
