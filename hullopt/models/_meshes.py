"""Hulls from triangle meshes: read any format trimesh reads (also ``.stl.gz``), bring the mesh into our
axes and units, check where it is open, and slice it into :class:`~hullopt.geometry.Sections` (static
preprocessing, numpy).

Meshes may be closed (watertight, both sides and the deck) or open in the two ways CAD exports usually are:

* a **half hull**, the port side only (all y ≥ 0), open at the centre plane y = 0 (or closed there by faces
  in the centre plane, which are dropped); a starboard half (all y ≤ 0) is mirrored to port;
* **open along the top**: the deck is missing, the boundary runs along the top of the hull (the highest
  point of each section, so a sheer line or a step in it is fine).

Non-conforming CAD seams (T-junctions, where boundary edges of two patches lie on each other) and slivers
narrower than 0.2 % of the hull's largest extent are bridged, not counted as holes; any other opening is a
:class:`~hullopt.errors.HullError` that says where it is (x, y and z range in our axes).
:func:`read_mesh` records what it found in ``mesh.metadata["hullopt"]`` (a :class:`MeshOpenings`), which
:func:`slice_mesh` reads.

Each station is cut at once for all stations (one vectorised pass over the mesh edges and faces) and the
cut segments are chained into pieces: closed loops (a closed hull, a bulb) and open polylines (a half hull,
an open top). Pieces split by a seam are joined end to end across the gap. Each closed loop's port half
runs from its lower to its upper crossing of the centreline; an open piece's port part runs from the
centreline (the keel, or a crossing of it) to the top edge. The parts are stacked from the lowest up and
joined along the centreline, which adds nothing to any integral; the part that ends at an open top edge
goes last, so the section ends there. The deck of a closed hull is trimmed off the top part (the polyline
ends at the deck edge), and every station is resampled to the same number of points, denser where the
section turns (bilge, knuckles). A half hull needs nothing else: sections are half-sections anyway, and the
hydrostatics integrate the half and double.
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
from ..geometry import DIVISION_FLOOR, SAME_POINT, Sections

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


_PLANE_TOL = 1e-4  # on the centre plane / at the top: within this fraction of the mesh's largest extent
_GAP_TOL = 2e-3  # seams and slivers narrower than this fraction of the largest extent are bridged
_HALF = ("auto", "yes", "no")


@dataclass(frozen=True)
class MeshOpenings:
    """Where a mesh read by :func:`read_mesh` is open; kept in ``mesh.metadata["hullopt"]`` for
    :func:`slice_mesh`.

    Attributes:
        half: the mesh is the port half of the hull (y ≥ 0), open at the centre plane y = 0.
        open_top: the mesh is open along its top (no deck): sections end at the top edge.
        seam_edges: boundary edges bridged as non-conforming seams or narrow slivers (not holes).
        mirrored: a starboard half (y ≤ 0) was mirrored to port.
    """

    half: bool = False
    open_top: bool = False
    seam_edges: int = 0
    mirrored: bool = False


def read_mesh(
    path: str | Path, transform: MeshTransform = MeshTransform(), half: str = "auto",
    tolerance: float | None = None,
) -> trimesh.Trimesh:
    """Read a hull mesh (or an IGES/STEP surface, tessellated with largest triangle edge ``tolerance``
    [m, at the file's scale]), transform it into our axes [m] and check where it is open.

    Accepted: a closed mesh (both sides and the deck); a half hull open at the centre plane y = 0; a mesh
    open along its top (no deck); both at once. Seams between CAD patches that do not share vertices, and
    slivers narrower than 0.2 % of the largest extent, are not holes.

    Parameters
    ----------
    path : str or Path
        The mesh file (any format trimesh reads, also ``.gz``) or an IGES/STEP file.
    transform : MeshTransform
        Scale, axes and shift into our axes (x forward from the AP, y to port, z up); identity by default.
    half : str
        ``"auto"`` (default) — a half hull if every vertex has y ≥ 0 (within 1e-4 of the largest extent; a
        starboard half, y ≤ 0, is mirrored) and the mesh is open (or has faces) in the centre plane;
        ``"yes"`` — treat it as a half hull (its port side, y ≥ 0, is used); ``"no"`` — a whole hull: an
        opening in the centre plane is a hole.
    tolerance : float, optional
        Largest triangle edge [m, at the file's scale], for IGES/STEP only (see
        :func:`~hullopt.models._cad.read_cad`); ``None``: its default.

    Returns
    -------
    trimesh.Trimesh
        The mesh in our axes [m], faces turned outward, with a :class:`MeshOpenings` in
        ``mesh.metadata["hullopt"]`` (faces lying in the centre plane of a half hull are dropped).

    Raises
    ------
    HullError
        Unreadable or empty, a bad ``half``, or a hole anywhere else: the message names the file and gives
        each hole's x, y and z range [m, our axes].
    """
    import trimesh

    path = Path(path)
    if half not in _HALF:
        raise HullError(f"{path}: half={half!r}: expected one of {', '.join(_HALF)}")
    mesh = _load_raw(path, tolerance)
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise HullError(f"{path}: the file holds no triangles")
    mesh.merge_vertices()
    f = mesh.faces
    keep = (f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])
    if not keep.all():
        mesh.update_faces(keep)
    mesh.apply_transform(transform.matrix())
    tol = _PLANE_TOL * float(np.ptp(mesh.bounds, axis=0).max())
    is_half = mirrored = False
    if half != "no":
        y = mesh.vertices[:, 1]
        mirrored = bool(y.max() <= tol and y.min() < -tol)  # a starboard half
        in_plane = np.all(np.abs(y[mesh.faces]) <= tol, axis=1)
        is_half = half == "yes" or bool(
            (-y if mirrored else y).min() >= -tol and (in_plane.any() or _on_plane_boundary(mesh, tol))
        )
        mirrored = mirrored and is_half
        if mirrored:
            mesh.apply_transform(np.diag([1.0, -1.0, 1.0, 1.0]))
        if is_half and in_plane.any():  # a half hull closed at the centre plane: drop those faces
            mesh.update_faces(~in_plane)
            mesh.remove_unreferenced_vertices()
    openings = MeshOpenings() if mesh.is_watertight else _openings(mesh, path, is_half)
    openings = MeshOpenings(is_half, openings.open_top, openings.seam_edges, mirrored)
    # turn the faces outward: the volume by the divergence theorem with the field (0, y, 0), which needs
    # nothing at the centre plane (y = 0) nor across a missing flat deck (n_y = 0)
    tri = mesh.triangles
    n_y = 0.5 * np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])[:, 1]
    if np.dot(tri[:, :, 1].mean(axis=1), n_y) < 0:
        mesh.invert()
    mesh.metadata["hullopt"] = openings
    return mesh


def _boundary_edges(mesh: trimesh.Trimesh) -> np.ndarray:
    """Vertex pairs (k, 2) of the edges used by exactly one face."""
    import trimesh

    edges = mesh.edges_sorted
    return edges[trimesh.grouping.group_rows(edges, require_count=1)]


def _on_plane_boundary(mesh: trimesh.Trimesh, tol: float) -> bool:
    be = _boundary_edges(mesh)
    return bool(len(be)) and bool(np.any(np.all(np.abs(mesh.vertices[be, 1]) <= tol, axis=1)))


def _openings(mesh: trimesh.Trimesh, path: Path, is_half: bool) -> MeshOpenings:
    """Classify the boundary edges of an open mesh: on the centre plane (a half hull), along the top (no
    deck), seams and slivers (bridged), or holes (:class:`HullError` naming where they are)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    v = mesh.vertices
    ext = float(np.ptp(mesh.bounds, axis=0).max())
    tol, gap = _PLANE_TOL * ext, _GAP_TOL * ext
    be = _boundary_edges(mesh)
    p = v[be]  # (k, 2, 3)
    centre = np.all(np.abs(p[:, :, 1]) <= tol, axis=1) if is_half else np.zeros(len(be), bool)
    # across: an edge in a plane x = const (a step in the top edge, a transom) is judged with its neighbours
    across = np.abs(p[:, 0, 0] - p[:, 1, 0]) <= tol
    top = np.zeros(len(be), bool)
    test = ~centre & ~across
    if test.any():
        xm = 0.5 * (p[test, 0, 0] + p[test, 1, 0])
        zm = 0.5 * (p[test, 0, 2] + p[test, 1, 2])
        top[test] = zm >= _section_tops(mesh, xm) - tol
    rest = ~centre & ~top
    seam = np.zeros(len(be), bool)
    if rest.any():
        seam[rest] = _near_other_edges(p, be, np.flatnonzero(rest), gap)
    hole = rest & ~seam & ~across
    keep = np.flatnonzero(rest)
    where = []
    if len(keep) and not seam[keep].all():
        # connected parts of what is left: a hole if it holds a hole edge, or is all across (x = const) and
        # does not join the top or the centre plane (a step in the top edge does); a hole's seams go with it
        nodes, inv = np.unique(be[keep], return_inverse=True)
        inv = inv.reshape(-1, 2)
        g = coo_matrix((np.ones(len(keep)), (inv[:, 0], inv[:, 1])), shape=(len(nodes), len(nodes)))
        _, label = connected_components(g, directed=False)
        part = label[inv[:, 0]]
        legit = np.zeros(len(v), bool)
        legit[be[top | centre].ravel()] = True
        for c in np.unique(part):
            mine = keep[part == c]
            if not hole[mine].any() and (~across[mine] | legit[be[mine]].any(axis=1)).any():
                continue  # seams, and steps in the top edge
            q = p[mine].reshape(-1, 3)
            lo, hi = q.min(axis=0), q.max(axis=0)
            where.append((lo[0], f"x {lo[0]:.3f} to {hi[0]:.3f} m, y {lo[1]:.3f} to {hi[1]:.3f} m, "
                                 f"z {lo[2]:.3f} to {hi[2]:.3f} m"))
    if where:
        bad = p[hole].reshape(-1, 3)
        where = [w for _, w in sorted(where)]
        more = f" (and {len(where) - 3} more)" if len(where) > 3 else ""
        hint = ""
        if not is_half and np.any(np.abs(bad[:, 1]) <= tol) and v[:, 1].min() >= -tol:
            hint = "; it is open at the centre plane y = 0 like a half hull: read it with half=auto or half=yes"
        raise HullError(
            f"{path}: the mesh has {'a hole' if len(where) == 1 else f'{len(where)} holes'} at "
            + "; ".join(where[:3]) + more
            + " (our axes, after scale/axes/shift); hullopt reads closed meshes and meshes open only at the "
            f"centre plane y = 0 (half hulls) and along the top (no deck){hint}"
        )
    return MeshOpenings(half=is_half, open_top=bool(top.any()), seam_edges=int(seam.sum()))


def _section_tops(mesh: trimesh.Trimesh, x: np.ndarray) -> np.ndarray:
    """Highest z [m] of the mesh's cut by each plane x = x[i]."""
    order = np.argsort(x)
    out = np.full(len(x), -np.inf)
    for chunk in np.array_split(order, max(1, len(order) // 1024)):  # bounded memory for long open edges
        node_s, _, yz, _ = _edge_crossings(mesh, x[chunk])
        top = np.full(len(chunk), -np.inf)
        np.maximum.at(top, node_s, yz[:, 1])
        out[chunk] = top
    return out


def _near_other_edges(p: np.ndarray, ids: np.ndarray, which: np.ndarray, gap: float) -> np.ndarray:
    """For the boundary edges ``p[which]`` (``p``: all of them, (k, 2, 3); ``ids``: their vertices, (k, 2)):
    whether the points at 1/4, 1/2 and 3/4 of each lie within ``gap`` of another boundary edge running
    within 30° of parallel to it — the other side of a seam or of a sliver narrower than ``gap``. The edge
    that continues the boundary past a shared vertex does not count (its nearest point is that vertex)."""
    a, d = p[:, 0], p[:, 1] - p[:, 0]
    dd = np.maximum(np.einsum("ij,ij->i", d, d), DIVISION_FLOOR)
    unit = d / np.sqrt(dd)[:, None]
    seg_lo = np.minimum(p[:, 0, 0], p[:, 1, 0]) - gap
    seg_hi = np.maximum(p[:, 0, 0], p[:, 1, 0]) + gap
    pts = np.concatenate([a[which] + f * d[which] for f in (0.25, 0.5, 0.75)])
    own = np.tile(which, 3)
    near = np.zeros(len(pts), bool)
    order = np.argsort(pts[:, 0])
    for chunk in np.array_split(order, max(1, len(order) // 256)):
        q, me = pts[chunk], own[chunk]
        cand = np.flatnonzero((seg_hi >= q[:, 0].min()) & (seg_lo <= q[:, 0].max()))
        w = q[:, None, :] - a[cand][None]
        t = np.clip(np.einsum("ijk,jk->ij", w, d[cand]) / dd[cand], 0.0, 1.0)
        dist = np.linalg.norm(w - t[..., None] * d[cand][None], axis=-1)
        at_shared = ((t <= 0.0) & np.any(ids[cand, 0][None, :, None] == ids[me][:, None, :], axis=-1)) | (
            (t >= 1.0) & np.any(ids[cand, 1][None, :, None] == ids[me][:, None, :], axis=-1)
        )
        parallel = np.abs(unit[me] @ unit[cand].T) >= np.cos(np.radians(30.0))
        dist[(me[:, None] == cand[None, :]) | at_shared | ~parallel] = np.inf
        near[chunk] = dist.min(axis=1, initial=np.inf) <= gap
    return near.reshape(3, -1).all(axis=0)


def station_positions(x_min: float, x_max: float, n: int) -> np.ndarray:
    """``n`` stations (odd) just inside ``[x_min, x_max]``: half equally spaced, half cosine-clustered
    toward the ends, where the hull changes fastest (stem, bulb, transom).

    Parameters
    ----------
    x_min, x_max : float
        The mesh's aft and forward ends [m from the AP].
    n : int
        Number of stations (made odd by adding 1).

    Returns
    -------
    numpy.ndarray, (n,) float
        Station positions [m from the AP], increasing, ``1e-5 (x_max − x_min)`` inside each end.
    """
    n += 1 - n % 2
    u = np.linspace(0.0, 1.0, n)
    u = 0.5 * u + 0.25 * (1.0 - np.cos(np.pi * u))
    inset = 1e-5 * (x_max - x_min)
    return x_min + inset + (x_max - x_min - 2 * inset) * u


def slice_mesh(
    mesh: trimesh.Trimesh, lpp: float, n_stations: int = 201, n_points: int = 96, half: bool | None = None
) -> Sections:
    """Slice a hull mesh in our axes into ``n_stations`` half-sections of ``n_points`` points.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        A closed hull, a half hull open at the centre plane, or either open along its top, in our axes [m]
        (as :func:`read_mesh` returns it).
    lpp : float
        Length between perpendiculars [m]; the FP is at x = lpp.
    n_stations : int
        Stations (made odd), spread over the mesh's length by :func:`station_positions` (201 by default).
    n_points : int
        Points per half-section (96 by default).
    half : bool, optional
        Whether the mesh is a half hull (its negative y, rounding in a CAD export, is clipped to 0);
        ``None``: as :func:`read_mesh` found it (``mesh.metadata["hullopt"]``), else a whole hull.

    Returns
    -------
    Sections
        ``x (n,)`` [m from the AP], ``yz (n, n_points, 2)`` [m], from the keel on y = 0 to the deck edge
        (a closed hull) or the top edge (an open top); zeros at a station that cuts nothing; ``lpp`` [m].

    Raises
    ------
    HullError
        A section with a part that does not reach the centreline (twin skegs, an asymmetric appendage), two
        open top edges, or too few points for its parts.
    """
    if half is None:
        half = getattr(mesh.metadata.get("hullopt"), "half", False)
    x = station_positions(*mesh.bounds[:, 0], n_stations)
    z_lo, z_hi = mesh.bounds[:, 2]
    ext = float(np.ptp(mesh.bounds, axis=0).max())
    cuts = _cut(mesh, x)
    try:
        sections = np.stack([
            _station(pieces, xi, z_lo, z_hi, n_points, bool(half), _PLANE_TOL * ext, _GAP_TOL * ext)
            for xi, pieces in zip(x, cuts)
        ])
    except HullError as e:
        raise HullError(f"{e}; {_axes_hint(mesh, bool(half))}") from None
    return Sections(x=jnp.asarray(x), yz=jnp.asarray(sections), lpp=jnp.asarray(float(lpp)))


def _axes_hint(mesh: trimesh.Trimesh, half: bool) -> str:
    """What a section that misses the centreline may mean: the mesh's extent in our axes, and which of our
    axes looks like the one across the ship (a whole hull is symmetric about its centre plane)."""
    lo, hi = mesh.bounds
    span = ", ".join(f"{a} {lo[i]:.4g}…{hi[i]:.4g}" for i, a in enumerate("xyz"))
    text = f"the mesh spans {span} m in hullopt's axes (x forward from the AP, y to port, z up)"
    if abs(lo[2] + hi[2]) <= 0.02 * (hi[2] - lo[2]):  # up and down alike: the beam is on z, not y
        return (f"{text}: it is symmetric about z = 0, as a hull is about its centre plane, so it is probably read in the "
                "wrong axes; give the file's axes in the hull spec's '?axes=' (our x, y, z from the file's, with "
                "signs, e.g. '?axes=x,-z,y')")
    if not half and abs(lo[1] + hi[1]) > 0.02 * (hi[1] - lo[1]):
        return f"{text}: a whole hull should be symmetric about y = 0; check the hull spec's '?axes='"
    return f"{text}; if the hull has no twin skegs, check the hull spec's '?axes='"


def _edge_crossings(mesh: trimesh.Trimesh, xs: np.ndarray):
    """Where the mesh's unique edges cross the planes x = xs (sorted): for every crossing its station index,
    its edge and its (y, z) [m]; a vertex counts as ahead of a plane when its x is greater, so every face
    cut by a plane has exactly two crossing edges."""
    v = mesh.vertices
    e = mesh.edges_unique
    ex = v[e, 0]
    lo = np.searchsorted(xs, ex.min(axis=1), "left")
    hi = np.searchsorted(xs, ex.max(axis=1), "left")
    count = np.maximum(hi - lo, 0)
    base = np.concatenate([[0], np.cumsum(count)[:-1]])
    edge = np.repeat(np.arange(len(e)), count)
    s = lo[edge] + np.arange(len(edge)) - base[edge]
    a, b = v[e[edge, 0]], v[e[edge, 1]]
    t = (xs[s] - a[:, 0]) / (b[:, 0] - a[:, 0])
    yz = a[:, 1:] + t[:, None] * (b[:, 1:] - a[:, 1:])
    return s, edge, yz, (lo, hi, base)


def _cut(mesh: trimesh.Trimesh, xs: np.ndarray) -> list[list[tuple[np.ndarray, bool]]]:
    """Cut the mesh by every plane x = xs[i] at once; per station, the pieces of the cut as ``(yz points
    (k, 2), closed)``, chained along the mesh's own edges (seams leave separate pieces)."""
    node_s, _, yz, (lo, hi, base) = _edge_crossings(mesh, xs)
    v, f, fe = mesh.vertices, mesh.faces, mesh.faces_unique_edges
    fx = v[f, 0]
    flo = np.searchsorted(xs, fx.min(axis=1), "left")
    fhi = np.searchsorted(xs, fx.max(axis=1), "left")
    fcount = np.maximum(fhi - flo, 0)
    face = np.repeat(np.arange(len(f)), fcount)
    s = flo[face] + np.arange(len(face)) - np.concatenate([[0], np.cumsum(fcount)[:-1]])[face]
    edges = fe[face]  # (P, 3)
    crosses = (lo[edges] <= s[:, None]) & (s[:, None] < hi[edges])
    pick = np.argsort(~crosses, axis=1, kind="stable")[:, :2]
    two = np.take_along_axis(edges, pick, axis=1)
    seg = base[two] + (s[:, None] - lo[two])  # node ids of each segment's ends
    order = np.argsort(s, kind="stable")
    seg, s = seg[order], s[order]
    bounds = np.searchsorted(s, np.arange(len(xs) + 1))
    out = []
    for i in range(len(xs)):
        sg = seg[bounds[i] : bounds[i + 1]]
        out.append([(yz[ids], closed) for ids, closed in _chains(sg)] if len(sg) else [])
    return out


def _chains(seg: np.ndarray) -> list[tuple[np.ndarray, bool]]:
    """Chain segments (k, 2) of node ids into polylines: ``(node ids, closed)``, open chains first from
    their ends, then the loops."""
    nodes, local = np.unique(seg, return_inverse=True)
    local = local.reshape(-1, 2)
    k = len(local)
    inc_node = local.ravel()
    order = np.argsort(inc_node, kind="stable")
    start = np.searchsorted(inc_node[order], np.arange(len(nodes) + 1)).tolist()
    inc = (order // 2).tolist()
    ends = local.tolist()
    deg = np.diff(start)
    used = [False] * k
    chains = []
    for n0 in [*np.flatnonzero(deg % 2 == 1).tolist(), *range(len(nodes))]:
        while True:
            path, cur = [n0], n0
            while True:
                for j in inc[start[cur] : start[cur + 1]]:
                    if not used[j]:
                        break
                else:
                    break
                used[j] = True
                a, b = ends[j]
                cur = b if a == cur else a
                path.append(cur)
            if len(path) == 1:
                break
            closed = path[0] == path[-1] and len(path) > 2
            chains.append((nodes[np.asarray(path[:-1] if closed else path)], closed))
    return chains


def _station(pieces: list[tuple[np.ndarray, bool]], x: float, z_lo: float, z_hi: float, m: int, half: bool,
             tol: float, gap: float) -> np.ndarray:
    """One station's half-section (m, 2) from the pieces of its cut."""
    pieces = _join_seams(pieces, tol, gap)
    arcs: list[tuple[np.ndarray, bool]] = []  # (arc from the centreline up, ends at an open top edge)
    for pts, closed in pieces:
        if closed:
            arc = _port_arc(pts, x)
            if arc is not None:
                arcs.append((arc, False))
            continue
        runs = [np.maximum(pts, [0.0, -np.inf])] if half else _port_runs(pts, x)
        for run in runs:
            on = run[[0, -1], 0] <= tol
            if not on.any():
                raise HullError(
                    f"the section at x = {x:.3f} m has a part that does not reach the centreline "
                    "(twin skegs or an asymmetric appendage are not supported yet)"
                )
            if on.all():
                run[[0, -1], 0] = 0.0
                arcs.append((run if run[0, 1] <= run[-1, 1] else run[::-1], False))
            else:
                run = run if on[0] else run[::-1]
                run[0, 0] = 0.0
                arcs.append((run, True))
    if not arcs:
        return np.zeros((m, 2))
    if sum(free for _, free in arcs) > 1:
        raise HullError(f"the section at x = {x:.3f} m has more than one open top edge (a hole in the hull?)")
    arcs.sort(key=lambda a: (a[1], a[0][0, 1]))
    stack = [a for a, _ in arcs]
    if not arcs[-1][1] and stack[-1][:, 1].max() >= z_lo + 0.75 * (z_hi - z_lo):
        stack[-1] = _trim_deck(stack[-1])
    return _resample(stack, m)


def _join_seams(pieces: list[tuple[np.ndarray, bool]], tol: float, gap: float) -> list[tuple[np.ndarray, bool]]:
    """Join open pieces end to end across seams and slivers: the nearest two ends off the centreline closer
    than ``gap``, again and again (an open piece whose own ends meet becomes a loop)."""
    loops = [p for p in pieces if p[1]]
    open_ = [p for p, closed in pieces if not closed]
    while len(open_) > 0:
        ends = np.array([[p[0], p[-1]] for p in open_])  # (k, 2 ends, 2)
        pts = ends.reshape(-1, 2)
        d = np.linalg.norm(pts[:, None] - pts[None], axis=-1)
        off = np.abs(pts[:, 0]) > tol
        d[~off, :] = np.inf
        d[:, ~off] = np.inf
        np.fill_diagonal(d, np.inf)
        for i in range(len(open_)):
            if len(open_[i]) < 3:  # a piece's two ends are one segment apart: not a loop
                d[2 * i, 2 * i + 1] = d[2 * i + 1, 2 * i] = np.inf
        i, j = np.unravel_index(np.argmin(d), d.shape)
        if d[i, j] > gap:
            break
        a, b = open_[i // 2], open_[j // 2]
        if i // 2 == j // 2:  # its own ends meet: a loop
            loops.append((a, True))
            del open_[i // 2]
            continue
        a = a if i % 2 else a[::-1]  # a ends at the join
        b = b if j % 2 == 0 else b[::-1]  # b starts there
        for k in sorted((i // 2, j // 2), reverse=True):
            del open_[k]
        open_.append(np.concatenate([a, b]))
    return loops + [(p, False) for p in open_]


def _port_runs(piece: np.ndarray, x: float) -> list[np.ndarray]:
    """The port parts (y ≥ 0) of an open piece of a whole hull's cut: each runs between centreline
    crossings or to the piece's ends."""
    tiny = SAME_POINT * max(np.abs(piece).max(), 1.0)
    y = piece[:, 0]
    cross = np.flatnonzero((y[:-1] > 0) != (y[1:] > 0))
    pts = []
    prev = 0
    for i in cross:
        pts.append(piece[prev : i + 1])
        p, q = piece[i], piece[i + 1]
        if p[0] != q[0]:
            t = p[0] / (p[0] - q[0])
            pts.append(np.array([[0.0, p[1] + t * (q[1] - p[1])]]))
        prev = i + 1
    pts.append(piece[prev:])
    pts = np.concatenate(pts)
    pts[np.abs(pts[:, 0]) <= tiny, 0] = 0.0
    port = pts[:, 0] >= 0.0
    runs = []
    idx = np.flatnonzero(np.diff(np.r_[0, port.astype(int), 0]))
    for a, b in zip(idx[::2], idx[1::2]):
        run = pts[a:b]
        if len(run) > 1 and run[:, 0].max() > tiny:
            runs.append(run.copy())
    return runs


def _port_arc(loop: np.ndarray, x: float) -> np.ndarray | None:
    """The port half (y ≥ 0) of a closed section loop, from its lower to its upper centreline crossing."""
    if np.allclose(loop[0], loop[-1]):
        loop = loop[:-1]
    y = loop[:, 0]
    tiny = SAME_POINT * max(np.abs(loop).max(), 1.0)
    if np.all(y < tiny) or np.all(y > -tiny):
        if np.all(np.abs(y) < tiny):
            return None  # a sliver in the centre plane
        raise HullError(
            f"the section at x = {x:.3f} m has a part that does not cross the centreline "
            "(twin skegs or an asymmetric appendage are not supported yet)"
        )
    # Insert the centreline crossings, then walk from the lower crossing through y > 0 to the upper one.
    p, q = loop, np.roll(loop, -1, axis=0)
    cross = np.flatnonzero(((p[:, 0] > 0) != (q[:, 0] > 0)) & (p[:, 0] != q[:, 0]))
    p, q = p[cross], q[cross]
    t = p[:, 0] / (p[:, 0] - q[:, 0])
    pts = np.insert(loop, cross + 1, np.stack([np.zeros_like(t), p[:, 1] + t * (q[:, 1] - p[:, 1])], axis=1), axis=0)
    on = np.flatnonzero(np.abs(pts[:, 0]) <= tiny)
    pts[on, 0] = 0.0
    # Rotate so the loop starts at a centreline point followed by a port point.
    start = on[np.roll(pts[:, 0], -1)[on] > 0][0]
    pts = np.roll(pts, -start, axis=0)
    end = 2 + np.flatnonzero(pts[1:, 0] <= 0)[0]
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
