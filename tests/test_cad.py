"""CAD surfaces in (models/_cad.py): IGES and STEP read through gmsh/OpenCASCADE, in metres, tessellated.

The KCS IGES (examples/hulls/SOURCES.md) is a half hull in mm at model scale 1:31.6, open at the centre plane
and along the top (z = 475 mm, no deck). Its displaced volume comes straight from the divergence theorem:
below a draft T, ∇_half = Σ ∫ y n_y dA over the triangles clipped at z ≤ T (the centre plane, y = 0, and the
waterplane, n_y = 0, add nothing), and the same sum over the closed KCS mesh gives its whole ∇.
"""

from __future__ import annotations

import gzip
import io
import sys

import jax
import numpy as np
import pytest

pytest.importorskip("gmsh")

from hullopt.errors import HullError  # noqa: E402
from hullopt.models._cad import read_cad  # noqa: E402

KCS_IGES = "kcs_ship_kcs_overture.igs"
KCS_CLOSED = "kcs_model_closed_from_igs.stl.gz"
SCALE = 31.6  # model scale of both KCS files
T_DESIGN = 10.8  # [m] KCS design draft, full scale


def _y_flux_below(mesh, t: float) -> float:
    """Σ ∫ y n_y dA [m³] over the part of ``mesh`` below z = t (exact for flat triangles: y is linear)."""
    part = mesh.slice_plane([0.0, 0.0, t], [0.0, 0.0, -1.0])
    tri = part.triangles
    area_y = 0.5 * np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])[:, 1]  # n_y · A
    return float(tri[:, :, 1].mean(axis=1) @ area_y)


@pytest.fixture(scope="module")
def kcs_cad(hulls):
    """The KCS IGES read at a few tolerances [m], each once for the module."""
    cache = {}

    def read(tol: float):
        if tol not in cache:
            cache[tol] = read_cad(hulls / KCS_IGES, tolerance=tol)
        return cache[tol]

    return read


def test_kcs_iges_is_read_in_metres_as_a_half_hull_open_at_the_centre_plane_and_top(kcs_cad):
    mesh = kcs_cad(0.1)
    # SOURCES.md: x −189.9 … 7500.4 mm, y 0 … 510.8 mm, z 0 … 475.0 mm (the file's unit is mm)
    np.testing.assert_allclose(mesh.bounds, [[-0.1899, 0.0, 0.0], [7.5004, 0.5108, 0.4750]], atol=2e-3)
    assert mesh.is_winding_consistent
    # The 18 faces are sewn into one conforming surface: its only free edges lie in y = 0 or z = 0.475 m.
    edges, counts = np.unique(mesh.edges_sorted, axis=0, return_counts=True)
    assert counts.max() == 2
    free = mesh.vertices[edges[counts == 1]]  # (k, 2, 3)
    at_centre = np.all(np.abs(free[:, :, 1]) < 1e-4, axis=1)
    at_top = np.all(np.abs(free[:, :, 2] - 0.475) < 1e-3, axis=1)
    assert np.all(at_centre | at_top)
    assert at_centre.sum() > 100 and at_top.sum() > 20
    # normals outward: the half volume below the top is positive
    assert _y_flux_below(mesh, 0.475) > 0


@pytest.mark.slow
def test_kcs_iges_area_and_volume_converge_as_the_tolerance_is_refined(kcs_cad):
    t = T_DESIGN / SCALE
    meshes = [kcs_cad(tol) for tol in (0.2, 0.1, 0.05)]
    area = np.array([m.area for m in meshes])
    vol = np.array([_y_flux_below(m, t) for m in meshes])
    # Inscribed triangles: both grow toward the surface's values, each step ~4× smaller than the last.
    for q in (area, vol):
        d = np.diff(q)
        assert np.all(d > 0)
        assert d[1] < 0.4 * d[0]
    np.testing.assert_allclose(len(meshes[2].faces) / len(meshes[1].faces), 4.0, rtol=0.35)


def test_kcs_iges_volume_matches_the_closed_kcs_mesh(kcs_cad, hulls):
    """∇ at the design draft of the half IGES surface (doubled) against the closed mesh made from it."""
    import trimesh

    t = T_DESIGN / SCALE
    half = _y_flux_below(kcs_cad(0.05), t)
    data = gzip.decompress((hulls / KCS_CLOSED).read_bytes())
    closed = trimesh.load(io.BytesIO(data), file_type="stl", force="mesh")
    closed.merge_vertices()
    whole = _y_flux_below(closed, t)
    assert 2 * half == pytest.approx(whole, rel=3e-3)
    # full scale: 52,030 m³ published for the KCS at 10.8 m
    assert 2 * half * SCALE**3 == pytest.approx(52030.0, rel=3e-3)


def _write_cylinder(path, radius_mm: float, height_mm: float) -> None:
    """A closed cylinder solid written by gmsh's OpenCASCADE (which writes STEP and IGES in mm)."""
    import gmsh

    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.occ.addCylinder(0, 0, 0, 0, 0, height_mm, radius_mm)
        gmsh.model.occ.synchronize()
        gmsh.write(str(path))
    finally:
        gmsh.finalize()


@pytest.mark.parametrize("suffix", [".step", ".igs"])
def test_cad_round_trip_of_a_closed_cylinder(tmp_path, suffix):
    path = tmp_path / f"cyl{suffix}"
    _write_cylinder(path, 100.0, 300.0)  # R 0.1 m, H 0.3 m
    mesh = read_cad(path, tolerance=0.01)
    assert mesh.is_watertight and mesh.is_winding_consistent
    sagitta = 0.1 * (1 - np.cos(np.pi / 63))  # the polygon's vertices need not lie at y = ±R
    np.testing.assert_allclose(mesh.bounds, [[-0.1, -0.1, 0.0], [0.1, 0.1, 0.3]], atol=sagitta)
    volume, area = np.pi * 0.1**2 * 0.3, 2 * np.pi * 0.1 * (0.1 + 0.3)
    # inscribed polygons with edges ≤ 10 mm: 2πR/N with N ≥ 63 loses at most (2π²/3)/N² ≈ 0.17 %
    assert volume * (1 - 2e-3) < mesh.volume < volume
    assert area * (1 - 2e-3) < mesh.area < area


def test_step_in_metres_is_read_in_metres(tmp_path):
    mm = tmp_path / "cyl_mm.step"
    _write_cylinder(mm, 100.0, 300.0)
    text = mm.read_text()
    assert text.count("SI_UNIT(.MILLI.,.METRE.)") == 1
    metres = tmp_path / "cyl_m.step"
    metres.write_text(text.replace("SI_UNIT(.MILLI.,.METRE.)", "SI_UNIT($,.METRE.)"))
    mesh = read_cad(metres, tolerance=10.0)
    np.testing.assert_allclose(mesh.bounds, [[-100.0, -100.0, 0.0], [100.0, 100.0, 300.0]], atol=0.15)
    assert mesh.volume == pytest.approx(np.pi * 100.0**2 * 300.0, rel=2e-3)


def test_missing_gmsh_gives_the_install_hint(monkeypatch, hulls):
    monkeypatch.setitem(sys.modules, "gmsh", None)  # `import gmsh` raises ImportError
    with pytest.raises(HullError, match=r"pip install 'hullopt\[cad\]'") as err:
        read_cad(hulls / KCS_IGES)
    assert KCS_IGES in str(err.value) and "\n" not in str(err.value)


@pytest.mark.parametrize(
    "name, content",
    [("bad.igs", b"this is not an IGES file\n"), ("bad.step", b"ISO-10303-21;\nHEADER;\ngarbage"), ("empty.stp", b"")],
)
def test_unreadable_cad_file_names_the_file(tmp_path, name, content):
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(HullError, match=name) as err:
        read_cad(path)
    assert "\n" not in str(err.value)


def test_truncated_iges_names_the_file(tmp_path, hulls):
    path = tmp_path / "cut.igs"
    path.write_bytes((hulls / KCS_IGES).read_bytes()[:5000])
    with pytest.raises(HullError, match="cut.igs"):
        read_cad(path)


def test_bad_tolerances_are_refused(hulls):
    from hullopt.models import load_hull

    with pytest.raises(HullError, match="tolerance"):
        read_cad(hulls / KCS_IGES, tolerance=-1.0)
    with pytest.raises(HullError, match="tol must be a positive"):
        load_hull(f"{hulls / KCS_IGES}?scale=31.6&tol=-0.01")


@pytest.mark.slow
@pytest.mark.slow
def test_kcs_iges_hull_spec_end_to_end_matches_the_closed_mesh(hulls):
    """The IGES as a hull spec (half hull, no deck: read_mesh closes it) against the closed KCS mesh: ∇ at
    the design draft, full scale (each sliced into sections as every mesh is)."""
    from hullopt.models import load_hull
    from hullopt.hydro import volume_at

    iges = load_hull(f"{hulls / KCS_IGES}?scale={SCALE}&lpp=230")
    closed = load_hull(f"{hulls / KCS_CLOSED}?scale={SCALE}&lpp=230")
    vol = jax.jit(volume_at)  # compiled: the same integrals as op by op, a few times faster here
    v_iges, v_closed = (float(vol(h.sections, T_DESIGN)) for h in (iges, closed))
    assert v_iges == pytest.approx(v_closed, rel=3e-3)
    assert v_iges == pytest.approx(52030.0, rel=3e-3)  # published
