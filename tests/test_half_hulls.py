"""Half hulls (open at the centre plane) and meshes open along the top, against independent integrals.

* the KVLCC2 CAD half hull (open at the centre plane and the deck, two non-conforming seams) against the
  divergence theorem on its own open surface;
* a closed mesh (the DTC) cut in half — open, capped in the centre plane, or its starboard half — against
  the whole;
* the OpenFOAM Wigley (open top, both sides, normals inward) against the Wigley closed forms;
* a half hull read as a whole one, and a hull with a real hole: errors that say where the hole is.
"""

import gzip
import io
import re

import jax
import numpy as np
import pytest
import trimesh

from hullopt.models import load_hull
from hullopt.errors import HullError
from hullopt.hydro import hydrostatics
from hullopt.models import MeshTransform, read_mesh, slice_mesh

# compiled once per section shape (the same function as op by op, a few times faster; drafts are traced)
_hydro = jax.jit(hydrostatics)

KVLCC2 = "kvlcc2_model_half_open_from_igs.stl.gz"


def _raw(path) -> trimesh.Trimesh:
    return trimesh.load(io.BytesIO(gzip.decompress(path.read_bytes())), file_type="stl", force="mesh")


def _half_surface_integrals(mesh: trimesh.Trimesh, draft: float) -> tuple[float, float]:
    """Volume [m³] and LCB [m] of a whole hull from its port half surface (open at the centre plane and the
    top), below z = draft: the divergence theorem with the fields (0, y, 0) and (0, x·y, 0), which need
    nothing on the centre plane (y = 0) nor on the waterplane (n_y = 0); doubled for both sides."""
    wet = trimesh.intersections.slice_mesh_plane(mesh, plane_normal=[0, 0, -1], plane_origin=[0, 0, draft],
                                                 cap=False)
    tri = wet.triangles  # (k, 3, 3)
    area_y = 0.5 * np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])[:, 1]  # n_y dA
    x, y = tri[:, :, 0], tri[:, :, 1]
    vol = np.sum(y.mean(axis=1) * area_y)  # ∫ y n_y dA (y is linear on a triangle)
    xy = (np.einsum("ij,ij->i", x, y) + x.sum(axis=1) * y.sum(axis=1)) / 12.0  # mean of x·y on the triangle
    moment = np.sum(xy * area_y)  # ∫ x·y n_y dA = ∫ x dV
    sign = np.sign(vol)  # outward normals give a positive volume
    return 2.0 * sign * vol, moment / vol


def test_kvlcc2_half_hull_against_its_own_surface_integral(hulls):
    """The KVLCC2 half hull (model 1:58, open at the centre plane and the deck, two non-conforming seams) at
    T = 20.8 m: ∇ and LCB within 0.1 % of the exact integral over its own surface."""
    lpp, draft = 320.0, 20.8
    loaded = load_hull(f"{hulls / KVLCC2}?scale=58&lpp={lpp:g}")
    h = _hydro(loaded.sections, draft)
    surface = _raw(hulls / KVLCC2)
    surface.apply_scale(58.0)
    vol, lcb = _half_surface_integrals(surface, draft)
    assert vol == pytest.approx(312_669, rel=2e-3)  # the expected size (a check of the reference itself)
    assert float(h.volume) == pytest.approx(vol, rel=1e-3)
    assert float(h.lcb) == pytest.approx(lcb, abs=1e-3 * lpp)
    assert float(h.lcb_pct) == pytest.approx(3.49, abs=0.05)
    # the sections end at the open top edge (no deck to trim), off the centreline
    yz = np.asarray(loaded.sections.yz)
    mid = yz[len(yz) // 2]
    assert mid[0, 0] == 0.0 and mid[-1, 0] > 20.0 and mid[-1, 1] == pytest.approx(26.0, abs=0.1)


def test_kvlcc2_openings_are_recorded(hulls):
    mesh = read_mesh(hulls / KVLCC2, MeshTransform(scale=58.0))
    found = mesh.metadata["hullopt"]
    assert found.half and found.open_top and found.seam_edges > 0 and not found.mirrored


@pytest.fixture(scope="module")
def dtc_whole(hulls):
    mesh = _raw(hulls / "DTC-scaled.stl.gz")
    mesh.apply_scale(59.407)
    return mesh


RES = "n=101&m=80"


@pytest.fixture(scope="module")
def dtc_whole_hydro(hulls):
    return _hydro(load_hull(f"{hulls}/DTC-scaled.stl.gz?scale=59.407&lpp=355&{RES}").sections, 14.5)


@pytest.mark.parametrize("how", ["port open", "port capped", "starboard open"])
def test_closed_mesh_cut_in_half_gives_the_whole_hydrostatics(tmp_path, dtc_whole, dtc_whole_hydro, how):
    """The DTC halved at y = 0 (open there, capped there, or the starboard half) against the whole mesh."""
    side, cap = how.split()
    normal = [0, 1, 0] if side == "port" else [0, -1, 0]
    half = trimesh.intersections.slice_mesh_plane(dtc_whole, plane_normal=normal, plane_origin=[0, 0, 0],
                                                  cap=cap == "capped")
    path = tmp_path / "half.stl"
    half.export(path)
    whole = dtc_whole_hydro
    ours = _hydro(load_hull(f"{path}?lpp=355&{RES}").sections, 14.5)
    assert float(ours.volume) == pytest.approx(float(whole.volume), rel=5e-4)
    assert float(ours.lcb) == pytest.approx(float(whole.lcb), rel=5e-4)
    assert float(ours.bmt) == pytest.approx(float(whole.bmt), rel=5e-4)
    found = read_mesh(path).metadata["hullopt"]
    assert found.half and found.mirrored == (side == "starboard") and not found.open_top


def test_wigley_open_top_with_inward_normals(hulls):
    """The OpenFOAM Wigley (L = 1 m, x = 0 amidships, keel at z = -0.0625, open top at z = 0.04, normals
    inward) brought to L = 100 m, AP at x = 0, keel at z = 0: Cb 4/9, LCB 0 at T = 6.25 m."""
    loaded = load_hull(f"{hulls}/wigley_openfoam.stl.gz?scale=100&shift=50,0,6.25&lpp=100")
    h = _hydro(loaded.sections, 6.25)
    assert float(h.cb) == pytest.approx(4 / 9, rel=5e-3)
    assert float(h.volume) == pytest.approx(4 / 9 * 100 * 10 * 6.25, rel=5e-3)
    assert float(h.lcb_pct) == pytest.approx(0.0, abs=0.05)
    assert float(h.bwl) == pytest.approx(10.0, rel=1e-3)
    yz = np.asarray(loaded.sections.yz)
    mid = yz[len(yz) // 2]
    assert mid[0, 0] == 0.0 and mid[-1, 1] == pytest.approx(10.25) and mid[-1, 0] == pytest.approx(5.0, rel=1e-3)
    mesh = read_mesh(hulls / "wigley_openfoam.stl.gz")
    found = mesh.metadata["hullopt"]
    assert found.open_top and not found.half
    tri = mesh.triangles  # turned outward: ∫ y n_y dA (the volume) is positive
    n_y = 0.5 * np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])[:, 1]
    assert np.dot(tri[:, :, 1].mean(axis=1), n_y) > 0


def _ranges(message: str) -> dict[str, tuple[float, float]]:
    """The first hole's x, y, z ranges [m] in a HullError message."""
    return {k: (float(a), float(b)) for k, a, b in re.findall(r"\b([xyz]) (-?[\d.]+) to (-?[\d.]+) m", message)[:3]}


def test_half_hull_read_as_whole_is_a_hole_on_the_centre_plane(hulls):
    with pytest.raises(HullError) as e:
        load_hull(f"{hulls / KVLCC2}?scale=58&lpp=320&half=no")
    msg = str(e.value)
    assert KVLCC2 in msg and "half=auto" in msg
    r = _ranges(msg)
    assert r["x"][0] < 0 and r["x"][1] > 300 and r["z"] == (pytest.approx(0.0, abs=0.01), pytest.approx(26.0, abs=0.1))
    with pytest.raises(HullError, match="half='maybe'"):
        load_hull(f"{hulls / KVLCC2}?scale=58&lpp=320&half=maybe")


def test_real_hole_is_named_by_where_it_is(tmp_path, dtc_whole):
    """The DTC with a patch of its port side removed at mid-length (x 175…185 m, z 5…11 m)."""
    c = dtc_whole.triangles_center
    cut = (np.abs(c[:, 0] - 180.0) < 5.0) & (c[:, 1] > 0) & (np.abs(c[:, 2] - 8.0) < 3.0)
    holed = dtc_whole.copy()
    holed.update_faces(~cut)
    path = tmp_path / "holed.stl"
    holed.export(path)
    for half in ("auto", "no", "yes"):
        with pytest.raises(HullError, match="a hole at") as e:
            load_hull(f"{path}?lpp=355&half={half}")
        r = _ranges(str(e.value))
        assert 174 < r["x"][0] < 176 and 184 < r["x"][1] < 186, r
        assert 4 < r["z"][0] < 6 and 10 < r["z"][1] < 12, r
        assert r["y"][0] == pytest.approx(25.5, abs=0.1), r


def _box(extents, centre) -> trimesh.Trimesh:
    b = trimesh.creation.box(extents=extents)
    b.apply_translation(centre)
    return b


def _without_deck(mesh: trimesh.Trimesh, z_min: float) -> trimesh.Trimesh:
    up = (mesh.face_normals[:, 2] > 0.99) & (mesh.triangles_center[:, 2] > z_min)
    out = mesh.copy()
    out.update_faces(~up)
    return out


def test_half_hull_with_a_separate_bulb_and_an_open_top(tmp_path):
    """A box hull with a round bulb ahead of and below it (stations through the bulb alone, and through bulb
    and hull, whose cuts of a half hull are two pieces on the centre plane): its port half, open at the
    centre plane, with and without the deck, gives the whole's hydrostatics to rounding."""
    bulb = trimesh.creation.cylinder(radius=2.0, height=20, sections=64)
    bulb.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0]))
    bulb.apply_translation([105, 0, 2.5])
    solid = trimesh.boolean.union([_box([100, 10, 10], [50, 0, 5]), bulb, _box([20, 1.0, 0.4], [105, 0, 4.6])],
                                  engine="manifold")
    half = trimesh.intersections.slice_mesh_plane(solid, plane_normal=[0, 1, 0], plane_origin=[0, 0, 0], cap=False)
    meshes = {"whole": solid, "half": half, "half, no deck": _without_deck(half, 9.99)}
    found = {}
    for name, mesh in meshes.items():
        path = tmp_path / f"{name.replace(', ', '_').replace(' ', '_')}.stl"
        mesh.export(path)
        read = read_mesh(path)
        found[name] = read.metadata["hullopt"]
        s = slice_mesh(read, 100.0, 201, 120)
        meshes[name] = [_hydro(s, t) for t in (4.0, 8.0)]
    assert not found["whole"].half and found["half"].half and not found["half"].open_top
    assert found["half, no deck"].half and found["half, no deck"].open_top
    for name in ("half", "half, no deck"):
        for ours, whole in zip(meshes[name], meshes["whole"]):
            for key in ("volume", "lcb", "kb", "bmt", "bml", "awp"):
                assert float(getattr(ours, key)) == pytest.approx(float(getattr(whole, key)), rel=1e-9), (name, key)


def test_open_top_with_a_step_in_it(tmp_path):
    """A box with a raised forecastle, both without their decks: the top edge steps up (edges across the
    length, x = const) — not a hole; sections end at the top edge, at each part's own height."""
    stepped = trimesh.boolean.union([_box([100, 10, 10], [50, 0, 5]), _box([20, 10, 14], [90, 0, 7])],
                                    engine="manifold")
    for name, mesh in (("whole", stepped), ("half", trimesh.intersections.slice_mesh_plane(
            stepped, plane_normal=[0, 1, 0], plane_origin=[0, 0, 0], cap=False))):
        path = tmp_path / f"{name}.stl"
        _without_deck(mesh, 9.99).export(path)
        read = read_mesh(path)
        assert read.metadata["hullopt"].open_top and read.metadata["hullopt"].half == (name == "half")
        s = slice_mesh(read, 100.0, 101, 40)
        h = _hydro(s, 6.0)
        assert float(h.volume) == pytest.approx(100 * 10 * 6, rel=1e-4) and float(h.lcb) == pytest.approx(50.0)
        yz, x = np.asarray(s.yz), np.asarray(s.x)
        assert np.allclose(yz[x < 75][:, -1], [5.0, 10.0]) and np.allclose(yz[x > 85][:, -1], [5.0, 14.0])


def test_a_hull_read_in_the_wrong_axes_is_told_so(hulls):
    """The DTC with its y and z swapped: the message names the extents and the ``?axes=`` to fix, not only
    twin skegs."""
    with pytest.raises(HullError) as e:
        load_hull(f"{hulls}/DTC-scaled.stl.gz?axes=x,z,y&scale=59.407&lpp=355")
    msg = str(e.value)
    assert "symmetric about z = 0" in msg and "'?axes='" in msg and "z -25.5…25.5 m" in msg
