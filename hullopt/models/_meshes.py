"""Hulls from triangle meshes: read any format trimesh reads (also ``.stl.gz``), bring the mesh into our
axes and units, and slice it into :class:`~hullopt.geometry.Sections` (static preprocessing, numpy).

Each station's cut is a set of closed loops (the hull, a bulb below it, …). Each loop's port half runs from
its lower to its upper crossing of the centreline; the halves are stacked from the lowest up and joined
along the centreline, which adds nothing to any integral. The deck is trimmed off the top half (the
polyline ends at the deck edge), and every station is resampled to the same number of points, denser
where the section turns (bilge, knuckles).
"""

from __future__ import annotations

import gzip
import io
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import jax.numpy as jnp
import numpy as np

from ..errors import HullError
from ..geometry import Sections

if TYPE_CHECKING:
    import trimesh  # imported where used: it takes ~0.5 s, and most commands need no mesh

_AXES = {"x": 0, "y": 1, "z": 2}


@dataclass(frozen=True)
class MeshTransform:
    """Maps a source mesh into hullopt's axes: ``ours = scale · (axes(source)) + shift``.

    ``axes`` names, for our x, y, z in turn, the source axis and its sign, e.g. ``"-x,z,y"``;
    ``shift`` [m, after scaling] moves the origin to the AP on the baseline.
    """

    scale: float = 1.0
    axes: str = "x,y,z"
    shift: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def matrix(self) -> np.ndarray:
        parts = [p.strip().lower() for p in self.axes.split(",")]
        if len(parts) != 3 or any(p.lstrip("+-") not in _AXES for p in parts):
            raise HullError(f"axes {self.axes!r}: expected three of x, y, z with optional signs, e.g. '-x,z,y'")
        if sorted(p.lstrip("+-") for p in parts) != ["x", "y", "z"]:
            raise HullError(f"axes {self.axes!r}: each of x, y, z must appear exactly once")
        if not (np.isfinite(self.scale) and self.scale > 0):
            raise HullError(f"scale must be a positive number, got {self.scale}")
        rot = np.zeros((3, 3))
        for row, p in enumerate(parts):
            rot[row, _AXES[p.lstrip("+-")]] = -1.0 if p.startswith("-") else 1.0
        out = np.eye(4)
        out[:3, :3] = self.scale * rot
        out[:3, 3] = self.shift
        return out


def _load_raw(path: Path, tolerance: float | None = None) -> trimesh.Trimesh:
    """The file's triangles as they are: a mesh trimesh reads (also ``.gz``), or an IGES/STEP surface
    tessellated by :func:`~hullopt.models._cad.read_cad` at ``tolerance`` [m, largest triangle edge at the
    file's scale; ignored for meshes]; :class:`HullError` if unreadable."""
    import trimesh

    from ._cad import is_cad, read_cad

    if is_cad(path):
        return read_cad(path, tolerance)
    name = path.name.lower()
    gz = name.endswith(".gz")
    ext = Path(name[:-3] if gz else name).suffix.lstrip(".")
    if ext not in trimesh.available_formats():
        raise HullError(
            f"{path}: unknown file type {ext!r}; expected an offsets .csv, an IGES/STEP file or a mesh trimesh reads"
        )
    try:
        raw = path.read_bytes()
        data = gzip.decompress(raw) if gz else raw
        return trimesh.load(io.BytesIO(data), file_type=ext, force="mesh")
    except Exception as e:  # trimesh raises many types for a bad file
        raise HullError(f"{path}: cannot read the mesh ({type(e).__name__}: {e})") from None


def read_mesh(
    path: str | Path, transform: MeshTransform = MeshTransform(), tolerance: float | None = None
) -> trimesh.Trimesh:
    """Read a closed hull mesh (or an IGES/STEP surface, tessellated with largest triangle edge ``tolerance``
    [m, at the file's scale]) and transform it into our axes; :class:`HullError` if it is unreadable,
    empty or open (not watertight)."""
    import trimesh

    path = Path(path)
    mesh = _load_raw(path, tolerance)
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise HullError(f"{path}: the file holds no triangles")
    mesh.merge_vertices()
    if not mesh.is_watertight:
        raise HullError(
            f"{path}: the mesh is open (not watertight); hullopt needs a closed hull (both sides and the deck)"
        )
    mesh.apply_transform(transform.matrix())
    if mesh.volume < 0:
        mesh.invert()
    return mesh


def station_positions(x_min: float, x_max: float, n: int) -> np.ndarray:
    """``n`` stations (odd) just inside ``[x_min, x_max]``: half equally spaced, half cosine-clustered
    toward the ends, where the hull changes fastest (stem, bulb, transom)."""
    n += 1 - n % 2
    u = np.linspace(0.0, 1.0, n)
    u = 0.5 * u + 0.25 * (1.0 - np.cos(np.pi * u))
    inset = 1e-5 * (x_max - x_min)
    return x_min + inset + (x_max - x_min - 2 * inset) * u


def slice_mesh(mesh: trimesh.Trimesh, lpp: float, n_stations: int = 201, n_points: int = 96) -> Sections:
    """Slice a closed hull mesh (in our axes) into ``n_stations`` half-sections of ``n_points`` points."""
    x = station_positions(*mesh.bounds[:, 0], n_stations)
    z_lo, z_hi = mesh.bounds[:, 2]
    sections = np.stack([_station(mesh, xi, z_lo, z_hi, n_points) for xi in x])
    return Sections(x=jnp.asarray(x), yz=jnp.asarray(sections), lpp=jnp.asarray(float(lpp)))


def _station(mesh: trimesh.Trimesh, x: float, z_lo: float, z_hi: float, m: int) -> np.ndarray:
    path = mesh.section(plane_origin=[x, 0.0, 0.0], plane_normal=[1.0, 0.0, 0.0])
    if path is None:
        return np.zeros((m, 2))
    arcs = [_port_arc(loop[:, 1:], x) for loop in path.discrete]
    arcs = sorted((a for a in arcs if a is not None), key=lambda a: a[0, 1])
    if not arcs:
        return np.zeros((m, 2))
    if arcs[-1][:, 1].max() >= z_lo + 0.75 * (z_hi - z_lo):
        arcs[-1] = _trim_deck(arcs[-1])
    return _resample(arcs, m)


def _port_arc(loop: np.ndarray, x: float) -> np.ndarray | None:
    """The port half (y ≥ 0) of a closed section loop, from its lower to its upper centreline crossing."""
    if np.allclose(loop[0], loop[-1]):
        loop = loop[:-1]
    y = loop[:, 0]
    tiny = 1e-9 * max(np.abs(loop).max(), 1.0)
    if np.all(y < tiny) or np.all(y > -tiny):
        if np.all(np.abs(y) < tiny):
            return None  # a sliver in the centre plane
        raise HullError(
            f"the section at x = {x:.3f} m has a part that does not cross the centreline "
            "(twin skegs or an asymmetric appendage are not supported yet)"
        )
    # Insert the centreline crossings, then walk from the lower crossing through y > 0 to the upper one.
    pts = []
    nxt = np.roll(loop, -1, axis=0)
    for p, q in zip(loop, nxt):
        pts.append(p)
        if (p[0] > 0) != (q[0] > 0) and p[0] != q[0]:
            t = p[0] / (p[0] - q[0])
            pts.append(np.array([0.0, p[1] + t * (q[1] - p[1])]))
    pts = np.asarray(pts)
    on = np.flatnonzero(np.abs(pts[:, 0]) <= tiny)
    pts[on, 0] = 0.0
    # Rotate so the loop starts at a centreline point followed by a port point.
    start = next(i for i in on if pts[(i + 1) % len(pts), 0] > 0)
    pts = np.roll(pts, -start, axis=0)
    end = 1 + next(i for i in range(1, len(pts)) if pts[i, 0] <= 0)
    arc = pts[:end]
    if arc[0, 1] > arc[-1, 1]:
        arc = arc[::-1]
    return np.maximum(arc, [0.0, -np.inf])


def _trim_deck(arc: np.ndarray) -> np.ndarray:
    """Cut the deck off a top arc: drop the tail that runs inboard near the top, ending at the deck edge."""
    tol = 0.02 * (arc[:, 1].max() - arc[:, 1].min())
    k = len(arc) - 1
    while k > 1 and arc[k - 1, 0] >= arc[k, 0] and arc[k - 1, 1] >= arc[-1, 1] - tol:
        k -= 1
    return arc[: k + 1]


def _resample(arcs: list[np.ndarray], m: int, corner_deg: float = 30.0) -> np.ndarray:
    """Resample the stacked arcs to ``m`` points in all. Every arc keeps its ends and every corner (a turn
    sharper than ``corner_deg``: bilge chine, transom edge, keel corner) so no area is cut off; the other
    points are spread by arc length plus turning angle, so curved parts get more of them."""
    pieces: list[tuple[np.ndarray, bool]] = []  # (points, shares its first point with the previous piece)
    for a in arcs:
        a = a[np.r_[True, np.any(np.diff(a, axis=0) != 0, axis=1)]]  # drop repeated points
        seg = np.diff(a, axis=0)
        ang = np.arctan2(seg[:, 1], seg[:, 0])
        turn = np.abs(np.angle(np.exp(1j * np.diff(ang))))
        corners = np.flatnonzero(turn > np.radians(corner_deg)) + 1
        bounds = [0, *corners, len(a) - 1]
        pieces += [(a[lo : hi + 1], k > 0) for k, (lo, hi) in enumerate(zip(bounds[:-1], bounds[1:]))]
    weights = []
    for p, _ in pieces:
        seg = np.diff(p, axis=0)
        length = np.hypot(*seg.T)
        ang = np.arctan2(seg[:, 1], seg[:, 0])
        turn = np.r_[0.0, np.abs(np.angle(np.exp(1j * np.diff(ang))))] * length.sum() / np.pi
        weights.append(np.r_[0.0, np.cumsum(length + 0.5 * turn)])
    fixed = sum(2 - shared for _, shared in pieces)
    extra = m - fixed
    if extra < 0:
        raise HullError(f"{m} points per section are too few for its {len(pieces)} parts and corners; raise m")
    total = sum(w[-1] for w in weights) or 1.0
    share = np.array([w[-1] / total * extra for w in weights])
    counts = np.floor(share).astype(int)
    counts[np.argsort(share - counts)[::-1][: extra - counts.sum()]] += 1  # largest remainders
    out = []
    for (p, shared), w, c in zip(pieces, weights, counts):
        t = np.linspace(0.0, w[-1], c + 2)
        pts = np.stack([np.interp(t, w, p[:, 0]), np.interp(t, w, p[:, 1])], axis=1)
        out.append(pts[1:] if shared else pts)
    return np.concatenate(out)
