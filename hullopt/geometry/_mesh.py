"""The structured surface grid of a hull, its wetted surface, and closed triangle meshes (trimesh).

The grid is the ``(n, m)`` array of section points in 3D; two triangles per cell. The closed mesh adds the
starboard side (mirror), the deck (across the deck edges) and the two end caps (transom and stem),
so it is watertight and its volume and centroid can be checked independently with trimesh.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import jax.numpy as jnp
import numpy as np
import trimesh
from jaxtyping import Array, Float

from ._sections import Sections

EXPORT_FORMATS = ("stl", "obj", "ply", "glb", "x3d")


def surface_grid(sections: Sections) -> Float[Array, "n m 3"]:
    """Port-side hull surface points ``(x, y, z)`` [m] on the structured station × point grid."""
    x = jnp.broadcast_to(sections.x[:, None], sections.yz.shape[:-1])
    return jnp.concatenate([x[..., None], sections.yz], axis=-1)


def grid_triangles(n: int, m: int) -> np.ndarray:
    """Triangle vertex indices ``(2 (n−1)(m−1), 3)`` into the flattened ``(n·m)`` grid.

    Wound so that normals point outward (to port) for a port-side grid running keel → deck.
    """
    i, j = np.meshgrid(np.arange(n - 1), np.arange(m - 1), indexing="ij")
    a = (i * m + j).ravel()
    b, c, d = a + m, a + m + 1, a + 1  # (i+1, j), (i+1, j+1), (i, j+1)
    return np.concatenate([np.stack([a, c, b], 1), np.stack([a, d, c], 1)])


def _area_fraction_below(z: Array, level: Array) -> Array:
    """Fraction of a planar triangle's area where the linear field with vertex values ``z (..., 3)`` is
    ≤ ``level``. Exact; finite gradients everywhere."""
    za, zb, zc = jnp.moveaxis(jnp.sort(z, axis=-1), -1, 0)
    lo = (level > za) & (level <= zb)
    hi = (level > zb) & (level < zc)
    den_lo = (zb - za) * (zc - za)
    den_hi = (zc - za) * (zc - zb)
    f_lo = jnp.where(lo, (level - za) ** 2 / jnp.where(lo, den_lo, 1.0), 0.0)
    f_hi = jnp.where(hi, 1.0 - (zc - level) ** 2 / jnp.where(hi, den_hi, 1.0), 0.0)
    return jnp.where(level >= zc, 1.0, f_lo + f_hi)


def _triangle_areas(tri: Array) -> Array:
    cross = jnp.cross(tri[..., 1, :] - tri[..., 0, :], tri[..., 2, :] - tri[..., 0, :])
    sq = jnp.sum(cross**2, axis=-1)
    ok = sq > 0.0
    return jnp.where(ok, 0.5 * jnp.sqrt(jnp.where(ok, sq, 1.0)), 0.0)  # double where: no NaN gradient


def wetted_surface(sections: Sections, draft) -> Float[Array, ""]:
    """Wetted surface [m²] of both sides below ``z = draft``: the grid's triangles, each clipped exactly.

    End caps (an immersed transom, a flat end) are not part of it; see :func:`transom_area`.
    Triangles lying in the centre plane (joints between disjoint parts of a section) are excluded.
    """
    tri = surface_grid(sections).reshape(-1, 3)[grid_triangles(sections.n, sections.m)]
    in_centreplane = jnp.all(tri[..., 1] == 0.0, axis=-1)
    frac = _area_fraction_below(tri[..., 2], jnp.asarray(draft))
    return 2.0 * jnp.sum(jnp.where(in_centreplane, 0.0, frac * _triangle_areas(tri)))


def _cap_faces(y: np.ndarray, yz: np.ndarray, port: int, stbd: int, outward_x: float) -> np.ndarray:
    """Faces closing one end station (a transom or a flat end); none where the section has no width.

    The half-section is split at its runs of centreline points (a section not started yet, the joint
    between a bulb and the hull); each part and its mirror image form one polygon, triangulated by
    manifold3d. ``port``/``stbd`` are the vertex indices of the station's first point on each side.
    """
    import manifold3d  # robust ear clipping that keeps the input's vertex order

    faces = []
    m = len(y)
    wide = np.flatnonzero(y > 0.0)
    runs = np.split(wide, np.flatnonzero(np.diff(wide) > 1) + 1) if wide.size else []
    for run in runs:
        lo, hi = max(run[0] - 1, 0), min(run[-1] + 1, m - 1)
        js = np.arange(lo, hi + 1)
        back = js[::-1][y[js[::-1]] > 0.0]  # the mirror image, skipping points on the centreline
        idx = np.concatenate([port + js, stbd + back])
        pts = np.concatenate([yz[js], yz[back] * np.array([-1.0, 1.0])])
        # Seen from +x (y right, z up) the loop port → deck → starboard runs counter-clockwise: its
        # triangles face +x.
        tri = np.asarray(manifold3d.triangulate([np.ascontiguousarray(pts)]), dtype=np.int64)
        faces.append(idx[tri] if outward_x > 0 else idx[tri][:, ::-1])
    return np.concatenate(faces) if faces else np.zeros((0, 3), np.int64)


def _pinch_free_triangles(y: np.ndarray, n: int, m: int) -> np.ndarray:
    """:func:`grid_triangles`, but a cell whose diagonal has both ends on the centreline while the other
    two corners are off it is split along the other diagonal: otherwise both sides would meet along that
    diagonal (an edge of four faces, not a 2-manifold)."""
    i, j = np.meshgrid(np.arange(n - 1), np.arange(m - 1), indexing="ij")
    a = (i * m + j).ravel()
    b, c, d = a + m, a + m + 1, a + 1
    on = y == 0.0
    flip = (on[a] & on[c] & ~(on[b] & on[d]))[:, None]
    t1 = np.where(flip, np.stack([a, d, b], 1), np.stack([a, c, b], 1))
    t2 = np.where(flip, np.stack([b, d, c], 1), np.stack([a, d, c], 1))
    return np.concatenate([t1, t2])


def to_trimesh(sections: Sections) -> trimesh.Trimesh:
    """The closed, watertight triangle mesh of the whole hull (both sides, deck, keel, end caps).

    The starboard side mirrors the port grid face for face, so faces in the centre plane come in
    back-to-back pairs; those and faces collapsed by merging coincident points are removed, which leaves a
    clean 2-manifold. Where the surface pinches to zero width between wider neighbours (both sides would
    touch along an edge), the points are moved off the centreplane by 1e-9 of the hull's size.
    """
    g = np.array(surface_grid(sections), dtype=np.float64)
    scale = max(np.abs(g).max(), 1.0)
    # Half-breadths below round-off are on the centreline: snap them so both sides' points merge.
    g[..., 1] = np.where(g[..., 1] < 1e-9 * scale, 0.0, g[..., 1])
    for _ in range(4):
        mesh = _closed_mesh(g)
        pinched = _pinch_points(mesh, g)
        if not pinched.any():
            break
        g[..., 1] = np.where(pinched, 2e-9 * scale, g[..., 1])
    return mesh


def _pinch_points(mesh: trimesh.Trimesh, g: np.ndarray) -> np.ndarray:
    """Grid points (on the centreline) at the ends of edges shared by more than two faces."""
    edges = np.sort(mesh.edges, axis=1)
    uniq, counts = np.unique(edges, axis=0, return_counts=True)
    bad = mesh.vertices[np.unique(uniq[counts > 2])]
    if not len(bad):
        return np.zeros(g.shape[:2], bool)
    key = lambda p: np.round(p / (1e-9 * max(np.abs(g).max(), 1.0))).astype(np.int64)  # noqa: E731
    bad_keys = {tuple(k) for k in key(bad)}
    on = g[..., 1] == 0.0
    return on & np.array([tuple(k) in bad_keys for k in key(g.reshape(-1, 3))]).reshape(on.shape)


def _closed_mesh(g: np.ndarray) -> trimesh.Trimesh:
    n, m, _ = g.shape
    port = g.reshape(-1, 3)
    verts = np.concatenate([port, port * np.array([1.0, -1.0, 1.0])])
    s0 = n * m
    grid = _pinch_free_triangles(port[:, 1], n, m)
    i = np.arange(n - 1)
    top_p, top_s = i * m + m - 1, s0 + i * m + m - 1
    bot_p, bot_s = i * m, s0 + i * m
    deck = [np.stack([top_p, top_s + m, top_p + m], 1), np.stack([top_p, top_s, top_s + m], 1)]
    keel = [np.stack([bot_p, bot_p + m, bot_s + m], 1), np.stack([bot_p, bot_s + m, bot_s], 1)]
    yz = g[..., 1:]
    caps = [
        _cap_faces(yz[0, :, 0], yz[0], 0, s0, -1.0),
        _cap_faces(yz[-1, :, 0], yz[-1], (n - 1) * m, s0 + (n - 1) * m, +1.0),
    ]
    faces = np.concatenate([grid, (grid + s0)[:, ::-1], *deck, *keel, *caps])
    return _clean(trimesh.Trimesh(verts, faces, process=False))


def _clean(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    mesh.merge_vertices(digits_vertex=9)
    f = mesh.faces
    keep = (f[:, 0] != f[:, 1]) & (f[:, 1] != f[:, 2]) & (f[:, 0] != f[:, 2])
    f = f[keep]
    # Back-to-back duplicates (the same triangle with both windings) cancel: both go.
    key = np.sort(f, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    f = f[counts[inverse.ravel()] == 1]
    out = trimesh.Trimesh(mesh.vertices, f, process=False)
    out.remove_unreferenced_vertices()
    return out


def write_x3d(mesh: trimesh.Trimesh, path: str | os.PathLike) -> None:
    """Write an X3D (XML) file with one IndexedFaceSet, as seed 003 uses for 3D printing."""
    coords = " ".join(f"{v[0]:.6g} {v[1]:.6g} {v[2]:.6g}" for v in mesh.vertices)
    index = " ".join(f"{a} {b} {c} -1" for a, b, c in mesh.faces)
    text = (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<X3D profile="Interchange" version="3.3">\n<Scene>\n<Shape>\n'
        "<Appearance><Material diffuseColor='0.8 0.8 0.8'/></Appearance>\n"
        f"<IndexedFaceSet solid='true' coordIndex='{index}'>\n<Coordinate point='{coords}'/>\n"
        "</IndexedFaceSet>\n</Shape>\n</Scene>\n</X3D>\n"
    )
    atomic_write_bytes(path, text.encode())


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """Write ``data`` to ``path`` via a temporary file in the same folder and a rename."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def export_mesh(mesh: trimesh.Trimesh, path: str | os.PathLike) -> Path:
    """Export a mesh to STL, OBJ, PLY, GLB or X3D (by the file's extension), atomically."""
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in EXPORT_FORMATS:
        raise ValueError(f"{path}: unknown mesh format {fmt!r}; expected one of {', '.join(EXPORT_FORMATS)}")
    if fmt == "x3d":
        write_x3d(mesh, path)
    else:
        data = mesh.export(file_type=fmt)
        atomic_write_bytes(path, data if isinstance(data, bytes) else data.encode())
    return path
