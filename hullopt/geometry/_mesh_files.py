"""Mesh files: writing a hull's mesh (welded to what the format holds, read back and checked), the STL header
that carries its Lpp and draft, X3D, and the atomic write every file of hullopt's goes through."""

from __future__ import annotations

import os
import re
import tempfile
import threading
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np


if TYPE_CHECKING:
    import trimesh  # imported where used: it takes ~0.5 s, and most commands need no mesh

from ._mesh import EXPORT_FORMATS, MeshReport, mesh_checks, weld_mesh


def write_x3d(mesh: trimesh.Trimesh, path: str | os.PathLike) -> None:
    """Write an X3D (XML) file with one IndexedFaceSet, as seed 003 uses for 3D printing (coordinates to 9
    significant digits: float32 exactly)."""
    coords = " ".join(f"{v[0]:.9g} {v[1]:.9g} {v[2]:.9g}" for v in mesh.vertices)
    index = " ".join(f"{a} {b} {c} -1" for a, b, c in mesh.faces)
    text = (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<X3D profile="Interchange" version="3.3">\n<Scene>\n<Shape>\n'
        "<Appearance><Material diffuseColor='0.8 0.8 0.8'/></Appearance>\n"
        f"<IndexedFaceSet solid='true' coordIndex='{index}'>\n<Coordinate point='{coords}'/>\n"
        "</IndexedFaceSet>\n</Shape>\n</Scene>\n</X3D>\n"
    )
    atomic_write_bytes(path, text.encode())


def read_x3d(path: str | os.PathLike) -> trimesh.Trimesh:
    """Read back an X3D file of :func:`write_x3d` (one IndexedFaceSet of triangles)."""
    import trimesh

    text = Path(path).read_text()
    index = np.array(re.search(r"coordIndex='([^']*)'", text).group(1).split(), dtype=np.int64).reshape(-1, 4)
    coords = np.array(re.search(r"point='([^']*)'", text).group(1).split(), dtype=np.float64).reshape(-1, 3)
    return trimesh.Trimesh(coords, index[:, :3], process=True)


def read_back(path: str | os.PathLike) -> trimesh.Trimesh:
    """A written mesh file as trimesh reads it (vertices merged); X3D by :func:`read_x3d`."""
    import trimesh

    path = Path(path)
    if path.suffix.lower() == ".x3d":
        return read_x3d(path)
    return trimesh.load(path, force="mesh")


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """Write ``data`` to ``path`` via a temporary file in the same folder and a rename; the file gets the
    permissions an ordinary ``open(path, "w")`` would give (mkstemp's are owner-only).

    Parameters
    ----------
    path : str or os.PathLike
        The file to write (replaced if it exists); its folder must exist.
    data : bytes
        The file's contents.

    Returns
    -------
    None
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _umask() -> int:
    with _UMASK_LOCK:  # reading it sets it: two threads writing at once could leave the process at 0
        mask = os.umask(0)
        os.umask(mask)
    return mask


_UMASK_LOCK = threading.Lock()


def stl_header(lpp: float, draft: float | None = None) -> bytes:
    """The 80-byte binary-STL header hullopt writes: ``hullopt lpp=<m> [draft=<m>]``, so that reading the file
    back (:func:`read_stl_header`) needs no ``?lpp=`` and knows the design draft.

    Parameters
    ----------
    lpp : float
        Length between perpendiculars [m].
    draft : float, optional
        Design draft [m above the baseline]; ``None`` leaves it out.

    Returns
    -------
    bytes
        80 ASCII bytes, space padded.
    """
    text = f"hullopt lpp={lpp:.9g}" + ("" if draft is None else f" draft={draft:.9g}")
    return text.encode("ascii").ljust(80, b" ")


def read_stl_header(text: str) -> dict[str, float]:
    """``{"lpp": …, "draft": …}`` [m] from a header written by :func:`stl_header` (trimesh keeps it as
    ``mesh.metadata["header"]``); empty for any other header.

    Parameters
    ----------
    text : str
        The STL header as text.

    Returns
    -------
    dict of str to float
        ``"lpp"`` and, where written, ``"draft"`` [m] (any other ``key=number`` word too); ``{}`` for a header
        not starting with ``hullopt``.
    """
    words = text.split()
    if not words or words[0] != "hullopt":
        return {}
    out = {}
    for w in words[1:]:
        key, _, value = w.partition("=")
        try:
            out[key] = float(value)
        except ValueError:
            pass
    return out


def export_mesh(mesh: trimesh.Trimesh, path: str | os.PathLike, header: bytes | None = None) -> MeshReport:
    """Write a closed mesh to STL, OBJ, PLY, GLB or X3D (by the file's extension), atomically, welded first
    (:func:`weld_mesh`) so that the file holds a valid mesh; then read the file back and report its checks
    (:class:`MeshReport`, from the file, not from the mesh in memory). ``ValueError`` if the written file
    is not closed, consistently wound, one body and free of degenerate faces. ``header`` (80 bytes, see
    :func:`stl_header`) goes into a binary STL's header; other formats ignore it.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        A closed 2-manifold mesh [m], e.g. from :func:`hull_mesh`.
    path : str or os.PathLike
        The file to write; its extension (``.stl``, ``.obj``, ``.ply``, ``.glb``, ``.x3d``) picks the format.
    header : bytes, optional
        A binary STL's 80-byte header (cut or space padded to 80); ``None`` keeps trimesh's.

    Returns
    -------
    MeshReport
        The checks of the file as read back: ``faces``, ``watertight``, ``winding_consistent``, ``bodies``,
        ``tiny_faces``, ``volume`` [m³], ``volume_change`` (relative, by welding).
    """
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in EXPORT_FORMATS:
        raise ValueError(f"{path}: unknown mesh format {fmt!r}; expected one of {', '.join(EXPORT_FORMATS)}")
    welded = weld_mesh(mesh)
    if fmt == "x3d":
        write_x3d(welded, path)
    else:
        data = welded.export(file_type=fmt)
        data = data if isinstance(data, bytes) else data.encode()
        if fmt == "stl" and header is not None:
            data = header[:80].ljust(80, b" ") + data[80:]
        atomic_write_bytes(path, data)
    checks = mesh_checks(read_back(path))
    before = float(mesh.volume)
    report = MeshReport(path=path, volume_change=checks["volume"] / before - 1.0 if before else 0.0, **checks)
    if not report.ok:
        raise ValueError(f"{path}: the written mesh is not valid when read back ({report.summary()})")
    return report
