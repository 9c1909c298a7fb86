"""Hull sources: offset tables (both layouts, knuckles, bad input), meshes (transform, slicing, bad input)."""

import gzip
import textwrap

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import trimesh

from conftest import REPO
from hullopt import HullError
from hullopt.geometry import to_trimesh
from hullopt.hydro import hydrostatics
from hullopt.models import (
    MeshTransform,
    offset_surface,
    offsets_to_sections,
    parse_station,
    read_mesh,
    read_offsets,
    slice_mesh,
)

hydro = jax.jit(hydrostatics)


def write(tmp_path, text, name="t.csv"):
    p = tmp_path / name
    p.write_text(textwrap.dedent(text).lstrip())
    return p


WIDE = """\
    # lpp = 20
    x,0,1,2,3
    0,0,1,2,2
    10,1,2,2,2
    20,0,1,2,2
"""


def test_wide_layout_reads_and_interpolates(tmp_path):
    t = read_offsets(write(tmp_path, WIDE))
    assert t.lpp == 20 and t.x.tolist() == [0, 10, 20] and t.z.tolist() == [0, 1, 2, 3]
    s = offsets_to_sections(t, 21, 31)
    yz = np.asarray(s.yz)
    assert yz[:, 0].tolist() == [[0.0, 0.0]] * 21  # every section starts on the centreline at the keel
    # the spline passes through the table's offsets at its stations and waterlines
    np.testing.assert_allclose(yz[10, 1:, 0][::10], t.y[1], atol=1e-12)
    np.testing.assert_allclose(yz[0, 1:, 0][::10], t.y[0], atol=1e-12)


def test_stations_layout_names_and_metadata():
    assert [float(parse_station(s)) for s in ("AP", "1/4", "9 3/4", "FP", "1 1/2", "10")] == [0, 0.25, 9.75, 10, 1.5, 10]
    t = read_offsets(str(REPO / "hullopt/data/offsets/seed003_table1.csv"))
    assert t.lpp == 95 and len(t.x) == 23 and t.z[-1] == pytest.approx(8.0)
    assert t.x[1] == 0 and t.x[-2] == pytest.approx(95) and t.x[0] < 0 < 95 < t.x[-1]  # AO, AP … FP, FO


def test_knuckle_keeps_the_corner(tmp_path):
    """A transom-like station with a hard chine at z = 2: split splines reproduce the straight sides exactly."""
    text = """\
        # lpp = 10
        # knuckles = 0@2
        x,0,1,2,3,4
        0,1,2,3,3,3
        10,1,2,3,3,3
    """
    t = read_offsets(write(tmp_path, text))
    s = offsets_to_sections(t, 3, 9)
    yz = np.asarray(s.yz[0, 1:])
    # below the knuckle the points lie on y = 1 + z, above it on y = 3
    below, above = yz[yz[:, 1] <= 2], yz[yz[:, 1] >= 2]
    np.testing.assert_allclose(below[:, 0], 1 + below[:, 1], atol=1e-12)
    np.testing.assert_allclose(above[:, 0], 3.0, atol=1e-12)
    plain = offsets_to_sections(read_offsets(write(tmp_path, text.replace("# knuckles = 0@2\n", ""), "p.csv")), 3, 9)
    assert np.abs(np.asarray(plain.yz[0, 1:, 0]) - np.where(yz[:, 1] <= 2, 1 + yz[:, 1], 3)).max() > 1e-2


@pytest.mark.parametrize(
    "body, message",
    [
        ("x,0,1\n0,1,1\n0,1,1\n", "line 3: duplicate station"),
        ("x,0,1\n5,1,1\n2,1,1\n", "line 3: unsorted station"),
        ("x,0,1\n0,1,-1\n2,1,1\n", "line 2: half-breadth at waterline z = 1 is -1"),
        ("x,0,1\n0,1,nan\n2,1,1\n", "line 2: half-breadth at waterline z = 1 is nan"),
        ("x,0,1\n0,1\n2,1,1\n", "line 2: 2 cells, expected 3"),
        ("x,0,1\n0,1,a\n2,1,1\n", "line 2: 'a' is not a number"),
        ("y,0,1\n0,1,1\n2,1,1\n", "first header cell must be 'x'"),
        ("station,0,1\nAP,1,1\nFP,1,1\n", "needs a metadata line '# lpp"),
        ("# lpp = 10\n# waterline_spacing = 1\nstation,0,1\nAP,1,1\nQQ,1,1\n", "unknown station 'QQ'"),
        ("x,1,0\n0,1,1\n2,1,1\n", "strictly increasing"),
    ],
)
def test_bad_offset_tables_name_the_problem(tmp_path, body, message):
    with pytest.raises(HullError, match=message.replace("(", r"\(").replace("'", "'")) as e:
        read_offsets(write(tmp_path, body))
    assert str(tmp_path) in str(e.value)


def test_offset_surface_is_differentiable_in_offsets():
    t = read_offsets(str(REPO / "hullopt/data/offsets/seed003_table1.csv"))
    surf = offset_surface(t, 31, 21)
    volume_and_grad = jax.jit(jax.value_and_grad(lambda y: hydrostatics(surf(y), 4.0).volume))
    volume = lambda y: volume_and_grad(y)[0]  # noqa: E731
    y = jnp.asarray(t.y)
    g = volume_and_grad(y)[1]
    # ∇ is positively homogeneous of degree 1 in the half-breadths (every offset × s: ∇ × s), so by Euler's
    # theorem Σ y ∂∇/∂y = ∇ (measured 3e-16)
    assert float(jnp.sum(g * y)) == pytest.approx(float(volume(y)), rel=1e-12)
    assert float(volume(1.1 * y)) == pytest.approx(1.1 * float(volume(y)), rel=1e-12)


# --- meshes ---------------------------------------------------------------------------------------------------


def _export(tmp_path, mesh, name):
    p = tmp_path / name
    data = mesh.export(file_type=name.split(".")[1])
    if name.endswith(".gz"):
        p.write_bytes(gzip.compress(data))
    else:
        p.write_bytes(data)
    return p


def test_mesh_box_sliced_exactly_with_transform(tmp_path):
    """A box barge given in model scale with z forward and x up comes in at full scale in our axes."""
    box = trimesh.creation.box(extents=[0.5, 0.2, 2.0])  # source: x up (depth), y breadth, z length
    box.apply_translation([0.25, 0.0, 1.0])
    p = _export(tmp_path, box, "b.stl.gz")
    mesh = read_mesh(p, MeshTransform(scale=50.0, axes="z,y,x"))
    np.testing.assert_allclose(mesh.bounds, [[0, -5, 0], [100, 5, 25]], atol=1e-9)
    s = slice_mesh(mesh, lpp=100.0, n_stations=11, n_points=12)
    h = hydro(s, 10.0)
    assert float(h.volume) == pytest.approx(100 * 10 * 10, rel=1e-4)  # stations inset 1e-5 L from the ends
    assert float(h.kb) == pytest.approx(5.0, rel=1e-9) and float(h.bmt) == pytest.approx(100 / 120, rel=1e-4)
    assert float(h.wetted_surface) == pytest.approx(100 * (10 + 20), rel=1e-4)


def test_mesh_with_bulb_only_station_and_bulb_and_hull_station(tmp_path):
    """A box hull with a separate round bulb ahead of and below it, fused by a thin neck."""
    hull = trimesh.creation.box(extents=[100, 10, 10])
    hull.apply_translation([50, 0, 5])
    bulb = trimesh.creation.cylinder(radius=2.0, height=20, sections=64)
    bulb.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [0, 1, 0]))
    bulb.apply_translation([105, 0, 2.5])
    neck = trimesh.creation.box(extents=[20, 1.0, 0.4])
    neck.apply_translation([105, 0, 4.6])
    solid = trimesh.boolean.union([hull, bulb, neck], engine="manifold")
    p = _export(tmp_path, solid, "bulb.stl")
    mesh = read_mesh(p)
    s = slice_mesh(mesh, lpp=100.0, n_stations=201, n_points=120)
    x = np.asarray(s.x)
    # a station through the bulb alone (the neck reaches up to z = 4.8 < the hull's deck)
    i = int(np.argmin(np.abs(x - 112)))
    yz = np.asarray(s.yz[i])
    assert yz[:, 1].max() < 5 and yz[:, 0].max() == pytest.approx(2.0, rel=1e-3)
    ref = mesh.slice_plane([0, 0, 4.0], [0, 0, -1], cap=True)
    h = hydro(s, 4.0)
    assert float(h.volume) == pytest.approx(ref.volume, rel=2e-3)
    assert float(h.lcb) == pytest.approx(ref.center_mass[0], abs=0.05)
    assert to_trimesh(s).is_watertight


def test_bad_meshes(tmp_path):
    holed = trimesh.creation.box(extents=[100, 10, 10]).subdivide().subdivide()  # x ±50, y ±5, z ±5
    c = holed.triangles_center
    holed.update_faces(np.arange(len(c)) != np.argmin(np.linalg.norm(c - [0, 5, 1], axis=1)))  # one side face
    where = r"holed.stl: the mesh has a hole at x -?[\d.]+ to [\d.]+ m, y 5.000 to 5.000 m, z"
    with pytest.raises(HullError, match=where):
        read_mesh(_export(tmp_path, holed, "holed.stl"))
    junk = tmp_path / "junk.stl"
    junk.write_bytes(b"\x00\x01 not a mesh")
    with pytest.raises(HullError, match="junk.stl"):
        read_mesh(junk)
    with pytest.raises(HullError, match="unknown file type 'xyz1'"):
        read_mesh(tmp_path / "a.xyz1")
    with pytest.raises(HullError, match="axes"):
        MeshTransform(axes="x,x,z").matrix()


CARGO = """\
    # a hand-written 120 m cargo ship (issue 62): a flat side and a parallel middle body at the widest offset
    # 10.000 m, no bulb, no transom (the AP row zero), a stern profile rising to the AP, a stem above the keel
    # lpp = 120
    x,0,1,2,4,6,8,10
    0,0,0,0,0,0,0,0
    3,0,0,0,0,0.8,2.5,4.0
    6,0,0,0,0.6,2.8,4.8,6.2
    12,0,0.3,1.2,3.8,6.2,7.8,8.8
    18,1.5,4.0,5.8,8.0,9.2,9.7,9.9
    24,5.6,7.8,8.9,9.6,9.9,10.0,10.0
    36,8.5,9.7,10.0,10.0,10.0,10.0,10.0
    60,8.5,9.7,10.0,10.0,10.0,10.0,10.0
    84,8.5,9.7,10.0,10.0,10.0,10.0,10.0
    96,3.9,5.8,6.9,7.9,8.5,8.9,9.2
    108,0.7,1.8,2.7,3.8,4.7,5.4,6.0
    120,0,0,0,0,0,0.3,0.8
"""


def test_offsets_never_exceed_the_tables_extremes(tmp_path):
    """Where the natural spline overshoots (a flat side bulging past the widest offset, a zero row dipping
    below zero) the reader takes the shape-preserving PCHIP (issue 62): no offset outside [0, the widest], Bwl
    never above twice the widest offset, no immersed transom at a zero AP row, Lwl growing with the draft;
    every offset of the table still on the surface. A table the natural spline does not overshoot is read as
    before."""
    t = read_offsets(write(tmp_path, CARGO))
    spline = offset_surface(t, 121, 41)(jnp.asarray(t.y))
    natural = np.asarray(spline.yz[..., 0])
    assert natural.max() > 10.0 + 0.1  # what the natural spline alone does on this table: Bwl 21.2 m at 2 m
    lwl = [float(hydro(spline, jnp.asarray(d)).lwl) for d in (2.0, 4.0, 6.0)]
    assert lwl[1] < min(lwl[0], lwl[2]) - 1.0  # and its Lwl not monotone in the draft (120, 117, 120 m)
    s = offsets_to_sections(t, 121, 41)  # every table station on the grid
    y = np.asarray(s.yz[..., 0])
    assert y.max() <= 10.0 + 1e-12 and y.min() >= 0.0
    on = np.isin(np.asarray(s.x), t.x)
    rows = np.isin(np.asarray(s.yz[0, 1:, 1]), t.z)
    np.testing.assert_allclose(y[on][:, 1:][:, rows], t.y, atol=1e-12)  # through every offset
    h = [hydro(s, jnp.asarray(d)) for d in (2.0, 4.0, 6.0, 7.0, 8.0)]
    assert max(float(v.bwl) for v in h) <= 20.0 + 1e-12
    assert all(float(v.a_transom) == 0.0 for v in h)
    lwl = [float(v.lwl) for v in h]
    assert all(b >= a - 1e-9 for a, b in zip(lwl, lwl[1:])), lwl
    # a table without overshoot: the natural spline, unchanged
    w = read_offsets(write(tmp_path, WIDE.replace("0,0,1,2,2\n", "0,0.5,1,1.5,2\n").replace("10,1,2,2,2", "10,1,1.5,2,2.5")
                           .replace("20,0,1,2,2", "20,0.5,1,1.5,2"), "w.csv"))
    np.testing.assert_array_equal(np.asarray(offsets_to_sections(w, 21, 31).yz),
                                  np.asarray(offset_surface(w, 21, 31)(jnp.asarray(w.y)).yz))
