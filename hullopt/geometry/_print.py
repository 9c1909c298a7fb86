"""Meshes for 3D printing (seed 003 §4): a scaled model split along its length into watertight pieces."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import trimesh  # imported where used: it takes ~0.5 s, and most commands need no mesh


def split_for_print(mesh: trimesh.Trimesh, pieces: int, scale: float = 1.0) -> list[trimesh.Trimesh]:
    """Scale a closed mesh by ``scale`` (e.g. ``1000 / 200`` for a 1:200 model in millimetres) and cut it
    into ``pieces`` equally long parts along x, aft to forward.

    The cuts are made by manifold3d (exact, double precision), which caps each cut and keeps every piece
    a closed 2-manifold even where the hull's two sides nearly touch (the thin centre wall of
    :func:`to_trimesh`), so the pieces are watertight and their volumes add up to the whole's.
    Raises ``ValueError`` if the mesh is not a closed manifold or a piece comes out open.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        A closed 2-manifold mesh, e.g. from :func:`to_trimesh` (vertices in m).
    pieces : int
        Number of parts, ≥ 1 (1 keeps the whole, scaled).
    scale : float
        Factor applied to every vertex coordinate before cutting (1 by default: the mesh's own unit).

    Returns
    -------
    list of trimesh.Trimesh
        ``pieces`` watertight meshes, ordered aft to forward, in the scaled unit.
    """
    import manifold3d
    import trimesh

    if pieces < 1:
        raise ValueError(f"pieces must be at least 1, got {pieces}")
    verts = np.asarray(mesh.vertices, dtype=np.float64) * float(scale)
    whole = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=verts,
                                                  tri_verts=np.asarray(mesh.faces, dtype=np.uint64)))
    if whole.status() != manifold3d.Error.NoError or whole.is_empty():
        raise ValueError(f"the mesh is not a closed manifold ({whole.status()}): it cannot be split into pieces")
    x0, x1 = verts[:, 0].min(), verts[:, 0].max()
    cuts = np.linspace(x0, x1, pieces + 1)
    out = []
    for i in range(pieces):
        part = whole
        if i > 0:
            part = part.trim_by_plane((1.0, 0.0, 0.0), float(cuts[i]))  # keep x ≥ cut
        if i < pieces - 1:
            part = part.trim_by_plane((-1.0, 0.0, 0.0), -float(cuts[i + 1]))  # keep x ≤ cut
        m = part.to_mesh64()
        piece = trimesh.Trimesh(np.asarray(m.vert_properties)[:, :3], np.asarray(m.tri_verts, dtype=np.int64),
                                process=False)
        if not piece.is_watertight:
            raise ValueError(f"piece {i + 1} of {pieces} is not watertight")
        out.append(piece)
    return out
