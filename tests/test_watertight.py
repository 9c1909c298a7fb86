"""Every mesh hullopt writes is valid as written: the file, read back by trimesh, is closed, consistently
wound, one body, with no face of (near) zero area; and reading it back (``hullopt hydro FILE``) gives the
writer's hydrostatics (∇ within 0.2 %, LCB within 0.05 % Lpp). The same for a run's ``offsets.csv`` (∇)."""

import json
import re
from pathlib import Path

import jax
import numpy as np
import pytest
import trimesh

from hullopt.geometry import Sections, to_trimesh
from hullopt.geometry import export_mesh
from hullopt.geometry._mesh import TINY_FACE

REPO = Path(__file__).resolve().parents[1]
CONFIGS = REPO / "configs"
SEED003 = REPO / "hullopt" / "data" / "offsets" / "seed003_table1.csv"

DV, DLCB = 2e-3, 5e-4  # ∇ relative; LCB as a fraction of Lpp


def assert_valid_file(path) -> trimesh.Trimesh:
    """The file as trimesh reads it (vertices merged): watertight, consistently wound, one body, no tiny face."""
    mesh = trimesh.load(path, force="mesh")
    area = mesh.area_faces
    assert mesh.is_watertight, f"{path}: open"
    assert mesh.is_winding_consistent, f"{path}: winding"
    assert mesh.body_count == 1, f"{path}: {mesh.body_count} bodies"
    assert np.count_nonzero(area < TINY_FACE * area.sum()) == 0, f"{path}: degenerate faces"
    return mesh


def read_back(cli, spec, draft) -> dict:
    code, out, err = cli("hydro", spec, "--draft", draft, "--json")
    assert code == 0, err
    return json.loads(out)


def assert_round_trip(got: dict, volume: float, lcb: float, lpp: float, dv: float = DV):
    assert got["volume"] == pytest.approx(volume, rel=dv)
    assert abs(got["lcb"] - lcb) < DLCB * lpp, (got["lcb"], lcb)


def chine_table(tmp_path) -> Path:
    """A small hard-chine hull (wide layout, 60 m): the half-breadth rises linearly to a chine at z = 2 m
    and flares above it; every station's spline is split there (``# knuckles``)."""
    x = np.linspace(0.0, 60.0, 13)
    z = np.arange(7.0)
    f = 0.35 + 0.65 * (1.0 - (2.0 * x / 60.0 - 1.0) ** 2)
    g = np.where(z <= 2.0, 1.0 + 1.5 * z, 4.0 + 0.25 * (z - 2.0))
    rows = [",".join([f"{xi:g}", *(f"{v:.4f}" for v in fi * g)]) for xi, fi in zip(x, f)]
    knuckles = "; ".join(f"{xi:g}@2" for xi in x)
    text = "\n".join(["# lpp = 60", f"# knuckles = {knuckles}", "x," + ",".join(f"{v:g}" for v in z), *rows])
    path = tmp_path / "chine.csv"
    path.write_text(text + "\n")
    return path


# ------------------------------------------------------------------------------------------------ the kernel


def test_weld_makes_degenerate_grids_valid_in_float32(tmp_path):
    """Collapsed ends, repeated points, a section not started yet and points closer than float32 resolves:
    the float64 mesh is closed in memory, the file of it (welded) is valid, and its volume is the same."""
    n, m = 9, 12
    x = np.linspace(0.0, 100.0, n)
    t = np.linspace(0.0, 1.0, m)
    yz = np.zeros((n, m, 2))
    for i, xi in enumerate(x):
        w = 4.0 * np.sin(np.pi * xi / 100.0)  # 0 at both ends: collapsed end stations
        yz[i, :, 0] = w * np.sin(0.5 * np.pi * t) ** 0.5
        yz[i, :, 1] = 8.0 * t
    yz[:, 3] = yz[:, 2]  # repeated points on every station
    yz[2, :5] = [0.0, yz[2, 5, 1]]  # a section that starts above the baseline (points on the centreline)
    yz[:, 7, 1] = yz[:, 6, 1] + 1e-9  # closer than float32 resolves at 8 m
    sec = Sections(x=x, yz=yz, lpp=np.asarray(100.0))
    raw = to_trimesh(sec)
    area = raw.area_faces
    assert raw.is_watertight and np.count_nonzero(area < TINY_FACE * area.sum()) > 0  # closed, but degenerate
    for ext in ("stl", "obj", "ply", "glb"):
        report = export_mesh(raw, tmp_path / f"g.{ext}")
        mesh = assert_valid_file(tmp_path / f"g.{ext}")
        assert report.ok and report.faces == len(mesh.faces)
        assert mesh.volume == pytest.approx(raw.volume, rel=1e-6) and abs(report.volume_change) < 1e-6
    assert export_mesh(raw, tmp_path / "g.x3d").ok


# ------------------------------------------------------------------------------------------------- writers


@pytest.mark.slow
def test_run_writes_a_valid_hull_and_offsets_that_read_back(cli, tmp_path):
    """`hullopt run` (the Wigley fit): hull.stl valid as read back; it and offsets.csv give the run's ∇ and
    LCB back through `hullopt hydro`."""
    out = tmp_path / "run"
    code, stdout, err = cli("run", CONFIGS / "fit_cb_lcb.toml", "--out", out, "--json")
    assert code == 0, err
    report = json.loads((out / "report.json").read_text())
    got, draft = report["achieved"], report["achieved"]["draft"]
    lpp = 100.0
    assert_valid_file(out / "hull.stl")
    assert_round_trip(read_back(cli, out / "hull.stl", draft), got["volume"], got["lcb"], lpp)
    table = read_back(cli, out / "offsets.csv", draft)
    assert_round_trip(table, got["volume"], got["lcb"], lpp)
    assert table["cb"] == pytest.approx(got["cb"], rel=DV)
    text = (out / "offsets.csv").read_text()
    assert "# lpp = 100" in text and "# deck = " in text


def _deformed(cli, tmp_path, parent: str, design: str, draft: float):
    """Run `hullopt deform` and return (the file, ∇ [m³] and LCB [% Lpp] it printed for the deformed hull)."""
    toml = tmp_path / f"{parent}.toml"
    toml.write_text(design)
    out = tmp_path / f"{parent}.stl"
    code, stdout, err = cli("deform", parent, toml, "--out", out, "--draft", draft)
    assert code == 0, err
    assert "watertight: True" in stdout and "degenerate faces: 0" in stdout and "bodies: 1" in stdout
    assert "enclosed volume (the closed hull, to the deck; not ∇)" in " ".join(stdout.split())  # beside ∇
    after = lambda label: float(re.search(re.escape(label) + r"\s+\S+\s+→\s+(\S+)", stdout).group(1))  # noqa: E731
    return out, after("∇ [m³]"), after("LCB [% Lpp fwd of midship]")


@pytest.mark.parametrize("parent, draft, design", [
    ("wigley", 6.25, """
        [[apex_move]]
        segment = -1
        x_fixed1 = 50.0
        x_moved = 80.0
        x_fixed2 = 100.0
        d = [0.4, -0.3]
        [[distribution]]
        x_a = 0.0
        x_b = 100.0
        c = [0.06, 0.08]
    """),
    ("dtc", 14.5, (REPO / "configs" / "deform_example.toml").read_text().replace('parent = "dtc"', "")),
])
def test_deform_writes_a_valid_mesh_that_reads_back(cli, tmp_path, parent, draft, design):
    from hullopt.models import load_parent

    lpp = float(load_parent(parent).lpp)
    out, volume, lcb_pct = _deformed(cli, tmp_path, parent, "\n".join(s.strip() for s in design.splitlines()), draft)
    assert_valid_file(out)
    assert_round_trip(read_back(cli, out, draft), volume, lpp * (0.5 + lcb_pct / 100.0), lpp)


@pytest.mark.parametrize("which", ["seed003", "chine", "kcs"])
@pytest.mark.slow
def test_export_prints_the_checks_of_the_file_and_reads_back(cli, tmp_path, which):
    """`hullopt export` of offset tables (seed 003; a hard-chine hull with knuckles) and of a mesh (the KCS,
    whose bulb ends in a point: the loft's last cells twist): the printed checks are those of the file,
    which is valid and gives the hull's hydrostatics back."""
    table, draft, lpp, formats = {
        "seed003": (SEED003, 5.6, 95.0, ("stl", "ply")),
        "chine": (chine_table(tmp_path), 4.0, 60.0, ("stl", "ply")),
        "kcs": (f"{REPO}/examples/hulls/kcs_model_closed_from_igs.stl.gz?scale=31.6&lpp=230", 10.8, 230.0, ("stl",)),
    }[which]
    want = read_back(cli, table, draft)
    for ext in formats:
        out = tmp_path / f"{which}.{ext}"
        code, stdout, err = cli("export", table, out)
        assert code == 0, err
        mesh = assert_valid_file(out)
        assert f"{len(mesh.faces):,} faces" in stdout and "watertight: True" in stdout and "read back" in stdout
        assert "winding consistent: True" in stdout and "bodies: 1" in stdout and "degenerate faces: 0" in stdout
    assert_round_trip(read_back(cli, tmp_path / f"{which}.stl", draft), want["volume"], want["lcb"], lpp)


def test_print_pieces_are_valid_files(cli, tmp_path):
    out = tmp_path / "model"
    code, _, err = cli("print", SEED003, "--scale", "1:100", "--pieces", "3", "--out", out, "--format", "stl,glb")
    assert code == 0, err
    files = sorted(out.glob("*.stl")) + sorted(out.glob("*.glb"))
    assert len(files) == 6
    pieces = [assert_valid_file(f) for f in files]
    from hullopt.models import load_hull

    whole = to_trimesh(load_hull(str(SEED003)).sections)
    assert sum(p.volume for p in pieces[:3]) == pytest.approx(whole.volume * 10.0**3, rel=1e-5)  # 1:100 in mm


@pytest.mark.slow
def test_offsets_of_a_knuckled_hull_carry_the_knuckles_and_read_back(tmp_path):
    """A run's offsets.csv writer (dense) on a hard-chine hull: the chine is a waterline and a ``# knuckles``
    entry at each station, and the table read back gives ∇ and LCB back."""
    from hullopt.models import load_hull
    from hullopt.drawing import write_offsets_wide
    from hullopt.hydro import hydrostatics

    sec = load_hull(str(chine_table(tmp_path))).sections
    out = write_offsets_wide(sec, tmp_path / "offsets.csv", name="chine", dense=True)
    text = out.read_text()
    line = next(s for s in text.splitlines() if s.startswith("# knuckles = "))
    assert len(line.split(";")) > sec.n // 2 and all(k.strip().endswith("@2") for k in line[13:].split(";"))
    assert "# lpp = 60" in text and "# deck = 6" in text
    hydro = jax.jit(hydrostatics)  # compiled: the same integrals as op by op, a few times faster here
    want, got = hydro(sec, 4.0), hydro(load_hull(str(out)).sections, 4.0)
    assert float(got.volume) == pytest.approx(float(want.volume), rel=DV) and abs(float(got.lcb - want.lcb)) < DLCB * 60


def test_offsets_of_the_dtc_read_back(tmp_path):
    """A run's offsets.csv writer on the DTC (a flat bottom with a slight rise of floor, a bulb, a transom):
    the reader keeps the table's clustered waterlines, so the bottom is not cut off."""
    from hullopt.models import load_hull
    from hullopt.drawing import write_offsets_wide
    from hullopt.hydro import hydrostatics

    sec = load_hull("parent:dtc").sections
    out = write_offsets_wide(sec, tmp_path / "offsets.csv", name="dtc", dense=True)
    hydro = jax.jit(hydrostatics)  # compiled: the same integrals as op by op, a few times faster here
    want, got = hydro(sec, 14.5), hydro(load_hull(str(out)).sections, 14.5)
    # measured: ∇ −0.021 %, LCB −0.006 % Lpp (the issue asks 0.2 %)
    assert float(got.volume) == pytest.approx(float(want.volume), rel=5e-4)
    assert abs(float(got.lcb - want.lcb)) < 2e-4 * 355


def test_an_stl_hullopt_wrote_carries_its_lpp_and_draft(cli, tmp_path):
    """The binary STL header (``hullopt lpp=… draft=…``) lets ``hydro FILE`` read it back with no ``?lpp=``
    or ``--draft``: the same particulars as the hull it came from; any other header changes nothing."""
    from hullopt.geometry import read_stl_header, stl_header

    assert read_stl_header(stl_header(355.0, 14.5).decode()) == {"lpp": 355.0, "draft": 14.5}
    assert read_stl_header("solid exported by CAD") == {} and read_stl_header("") == {}
    code, _, err = cli("export", "parent:wigley", tmp_path / "w.stl")
    assert code == 0, err
    code, out, err = cli("hydro", tmp_path / "w.stl", "--json")
    assert code == 0, err
    got, (_, want, _) = json.loads(out), cli("hydro", "parent:wigley", "--json")
    want = json.loads(want)
    assert got["draft"] == 6.25
    for k in ("volume", "cb", "bwl"):
        assert got[k] == pytest.approx(want[k], rel=DV), k
    assert got["lcb_pct"] == pytest.approx(want["lcb_pct"], abs=100 * DLCB)
