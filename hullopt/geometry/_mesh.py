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

    Ordered so that normals point outward (to port) for a port-side grid running keel → deck.
    """
    i, j = np.meshgrid(np.arange(n - 1), np.arange(m - 1), indexing="ij")
    a = (i * m + j).ravel()
    b, c, d = a + m, a + m + 1, a + 1  # (i+1, j), (i+1, j+1), (i, j+1)
    return np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


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


def _station_loops(sections: Sections) -> np.ndarray:
    """Closed full-section loops ``(n, 2m, 3)``: port keel → deck edge, across the deck, starboard back."""
    g = np.asarray(surface_grid(sections), dtype=np.float64)
    stbd = g[:, ::-1] * np.array([1.0, -1.0, 1.0])
    return np.concatenate([g, stbd], axis=1)


def _cap_faces(loop_yz: np.ndarray, offset: int, outward_x: float) -> np.ndarray:
    """Triangulate one end cap (a closed loop in (y, z)); faces oriented with normal along ``outward_x``."""
    import manifold3d  # its triangulator is robust to the degenerate, touching loops of end stations

    # Seen from +x (y right, z up) the loop (port keel → deck → starboard) runs counter-clockwise,
    # which is how the triangulator wants it; its triangles then face +x.
    faces = np.asarray(manifold3d.triangulate([np.ascontiguousarray(loop_yz)]), dtype=np.int64) + offset
    return faces if outward_x > 0 else faces[:, ::-1]


def to_trimesh(sections: Sections) -> trimesh.Trimesh:
    """The closed, watertight triangle mesh of the whole hull (both sides, deck, end caps).

    Coincident points (keel, centre-plane joints, zero-width stations) are merged, and faces that collapse
    or that pair up back to back in the centre plane are removed, so the mesh is a clean 2-manifold.
    """
    loops = _station_loops(sections)
    n, k, _ = loops.shape
    verts = loops.reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n - 1), np.arange(k), indexing="ij")
    a = (i * k + j).ravel()
    b = (i * k + (j + 1) % k).ravel()
    c, d = b + k, a + k
    side = np.concatenate([np.stack([a, c, d], 1), np.stack([a, b, c], 1)])
    aft = _cap_faces(loops[0, :, 1:], 0, -1.0)
    fwd = _cap_faces(loops[-1, :, 1:], (n - 1) * k, +1.0)
    mesh = trimesh.Trimesh(verts, np.concatenate([side, aft, fwd]), process=False)
    return _clean(mesh)


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
