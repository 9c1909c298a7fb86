"""Hull surfaces from CAD files: IGES (``.igs``, ``.iges``) and STEP (``.stp``, ``.step``), read with gmsh's
OpenCASCADE kernel and tessellated into a triangle mesh (static preprocessing, numpy).

An optional extra: ``pip install 'hullopt[cad]'`` installs gmsh. gmsh is imported only when a CAD file is read.

Units: OpenCASCADE converts every IGES and STEP file from the unit its header declares (IGES global section,
STEP ``LENGTH_UNIT``) into its session unit, the millimetre; :func:`read_cad` scales that to metres. (gmsh's
``Geometry.OCCTargetUnit``, which would ask OpenCASCADE for metres directly, fails in gmsh 4.15.2 with "Could
not set OpenCASCADE target unit"; the millimetre default is what ``tests/test_cad.py`` pins, with an IGES in mm
and STEP files in mm and in m.)
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import HullError

if TYPE_CHECKING:
    import trimesh

CAD_SUFFIXES = (".igs", ".iges", ".stp", ".step")
_OCC_UNIT = 1e-3  # [m] OpenCASCADE's session length unit (xstep.cascade.unit = MM), into which files are read
_DEFAULT_SIZE = 1 / 200  # default largest triangle edge, as a fraction of the model's largest extent L
# Curved parts: edges of at most 2πR/N for a radius of curvature R, with N = _CURVATURE_SCALE · L / size
# (N = 32 at the default size): the refinement follows the size, so halving the size halves every edge and
# the area and volume errors fall about fourfold (a fixed N would leave the bilge and the bulb as they were).
_CURVATURE_SCALE = 32 * _DEFAULT_SIZE


def is_cad(path: str | Path) -> bool:
    """Whether ``path`` names an IGES or STEP file (by its extension).

    Parameters
    ----------
    path : str or Path
        A file name.

    Returns
    -------
    bool
        True for ``.igs``, ``.iges``, ``.stp`` or ``.step`` (any case).
    """
    return Path(path).suffix.lower() in CAD_SUFFIXES


def read_cad(
    path: str | Path, tolerance: float | None = None, sew_tolerance: float = 1e-3
) -> trimesh.Trimesh:
    """Read the surfaces of an IGES or STEP file and tessellate them into one triangle mesh, in metres.

    The file's own length unit is honoured (an IGES in mm gives coordinates in m); no other transform is
    applied: axes, scale (a model-scale hull stays at model scale), origin, half or whole hull, open or closed,
    are all as in the file (mirroring, capping and scaling to full size are :func:`read_mesh`'s and
    :class:`MeshTransform`'s business).

    Args:
        path: the ``.igs``/``.iges``/``.stp``/``.step`` file.
        tolerance: largest triangle edge [m, at the file's scale, after the unit conversion]. Curved parts are
            refined in proportion: an edge is at most ``tolerance · min(1, 39 R / L)`` for a local radius of
            curvature R and the model's largest extent L. ``None`` (default): L/200 (the 7.69 m KCS model:
            38 mm, about 40,000 triangles for its half hull; ∇ at the design draft 0.06 % below the converged
            value). Area and volume errors fall about fourfold when the tolerance is halved.
        sew_tolerance: faces whose edges lie within this distance [m, at the file's scale] are sewn together
            (OpenCASCADE sewing), so neighbouring faces share their edges' vertices (a conforming mesh).

    Returns:
        A :class:`trimesh.Trimesh`: vertices merged, degenerate triangles dropped, faces wound consistently
        within each connected part and turned so that their normals point away from the bounding-box centre
        on the whole (outward for a hull, closed or half).

    Raises:
        HullError: gmsh is not installed (with the install hint), the file cannot be read, it holds no
            surfaces, or a tolerance is not a positive number.
    """
    import trimesh

    path = Path(path)
    for name, value in (("tolerance", tolerance), ("sew_tolerance", sew_tolerance)):
        if value is not None and not (np.isfinite(value) and value > 0):
            raise HullError(f"{path}: {name} must be a positive length in m, got {value}")
    if not path.is_file():
        raise HullError(f"{path}: no such CAD file")
    try:
        import gmsh
    except ImportError:
        raise HullError(
            f"{path}: reading IGES/STEP needs gmsh, which is not installed; pip install 'hullopt[cad]'"
        ) from None

    own = not gmsh.isInitialized()
    with _quiet():  # OpenCASCADE prints its transfer statistics straight to stdout
        if own:
            gmsh.initialize(readConfigFiles=False, interruptible=False)  # keep Python's own Ctrl-C handling
        try:
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.model.add(f"hullopt-cad-{os.getpid()}")
            nodes, triangles = _tessellate(gmsh, path, tolerance, sew_tolerance)
        finally:
            if own:
                gmsh.finalize()
            else:
                gmsh.model.remove()  # someone else's gmsh session: leave it as it was, less our model

    mesh = trimesh.Trimesh(nodes * _OCC_UNIT, triangles, process=True)  # merges coincident vertices
    mesh.update_faces(mesh.nondegenerate_faces())
    mesh.remove_unreferenced_vertices()
    if len(mesh.faces) == 0:
        raise HullError(f"{path}: the surfaces gave no triangles")
    if not mesh.is_winding_consistent:
        trimesh.repair.fix_winding(mesh)
    centre = mesh.bounds.mean(axis=0)
    if np.einsum("ij,ij->", mesh.triangles_center - centre, mesh.face_normals * mesh.area_faces[:, None]) < 0:
        mesh.invert()
    return mesh


def _tessellate(gmsh, path: Path, tolerance: float | None, sew_tolerance: float) -> tuple[np.ndarray, np.ndarray]:
    """Import ``path`` into the current gmsh model, sew and mesh its surfaces; (nodes [mm], triangles)."""
    gmsh.option.setNumber("Geometry.OCCSewFaces", 1)
    gmsh.option.setNumber("Geometry.Tolerance", sew_tolerance / _OCC_UNIT)
    try:
        gmsh.model.occ.importShapes(str(path), highestDimOnly=False)
        gmsh.model.occ.synchronize()
    except Exception as e:  # gmsh raises a bare Exception carrying its last error
        msg = " ".join(str(e).split()) or "OpenCASCADE could not read it"
        raise HullError(f"{path}: cannot read the CAD file ({msg})") from None
    if not gmsh.model.getEntities(2):
        raise HullError(f"{path}: no surfaces read from the CAD file (not an IGES/STEP file, or one without surfaces)")
    lo, hi = np.reshape(gmsh.model.getBoundingBox(-1, -1), (2, 3))
    extent = float(np.max(hi - lo))  # [mm]
    if not extent > 0:
        raise HullError(f"{path}: the CAD surfaces have no extent")
    size = tolerance / _OCC_UNIT if tolerance is not None else _DEFAULT_SIZE * extent
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.MeshSizeMin", size / 50)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", max(8, round(_CURVATURE_SCALE * extent / size)))
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay: the fastest robust one on trimmed NURBS
    try:
        gmsh.model.mesh.generate(2)
    except Exception as e:
        raise HullError(f"{path}: cannot tessellate the CAD surfaces ({' '.join(str(e).split())})") from None
    tags, coords, _ = gmsh.model.mesh.getNodes()
    types, _, conns = gmsh.model.mesh.getElements(2)
    conn = [c for t, c in zip(types, conns) if t == 2]  # 3-node triangles (the only 2D type meshed here)
    if not conn or len(tags) == 0:
        raise HullError(f"{path}: the surfaces gave no triangles")
    index = np.zeros(int(tags.max()) + 1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    triangles = index[np.concatenate(conn).astype(np.int64)].reshape(-1, 3)
    return coords.reshape(-1, 3), triangles


@contextlib.contextmanager
def _quiet() -> Iterator[None]:
    """Silence what native code writes to the process's stdout and stderr (file descriptors 1 and 2)."""
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(Exception):
            stream.flush()
    try:
        saved = [os.dup(1), os.dup(2)]
    except OSError:  # no real descriptors (an embedded interpreter): nothing to silence
        yield
        return
    with tempfile.TemporaryFile() as sink:
        try:
            os.dup2(sink.fileno(), 1)
            os.dup2(sink.fileno(), 2)
            yield
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)
