"""Meshes for 3D printing: every piece watertight, volumes adding up to the whole, files written."""

import numpy as np
import pytest
import trimesh

from conftest import REPO
from hullopt.app.cli import main
from hullopt.app.commands.stability import parse_scale
from hullopt.errors import HullError
from hullopt.geometry import split_for_print, to_trimesh
from hullopt.models import offsets_to_sections, read_offsets, wigley

SEED = str(REPO / "hullopt/data/offsets/seed003_table1.csv")


@pytest.fixture(autouse=True)
def _cache(tmp_path, monkeypatch):
    monkeypatch.setenv("HULLOPT_CACHE", str(tmp_path / "cache"))


@pytest.mark.parametrize("which", ["wigley", "seed003"])
def test_pieces_are_watertight_and_add_up(which):
    if which == "wigley":
        s = wigley(100.0, 10.0, 6.25, 10.0, n=21, m=21)
    else:  # sections starting above the baseline: the two sides meet in a thin centre wall
        from pathlib import Path

        s = offsets_to_sections(read_offsets(Path(__file__).parents[1] / SEED), 41, 31)
    mesh = to_trimesh(s)
    scale = 1000.0 / 200.0
    parts = split_for_print(mesh, 3, scale)
    assert len(parts) == 3 and all(p.is_watertight for p in parts)
    assert sum(p.volume for p in parts) == pytest.approx(mesh.volume * scale**3, rel=1e-9)
    x0, x1 = mesh.bounds[:, 0] * scale
    edges = np.linspace(x0, x1, 4)
    for p, a, b in zip(parts, edges[:-1], edges[1:]):
        assert p.bounds[0, 0] == pytest.approx(a, abs=1e-6) and p.bounds[1, 0] == pytest.approx(b, abs=1e-6)
        assert p.volume > 0


def test_scale_parsing():
    assert parse_scale("1:200") == 1 / 200 and parse_scale("200") == 1 / 200 and parse_scale("0.01") == 0.01
    for bad in ("1:0", "x", "-1:5"):
        with pytest.raises(HullError, match="--scale"):
            parse_scale(bad)


def test_cli_print_writes_pieces(capsys, tmp_path):
    out = tmp_path / "model"
    code = main(["print", "builtin:wigley?L=100&B=10&T=6.25&D=10&n=21&m=21", "--scale", "1:200", "--pieces", "2",
                 "--out", str(out), "--sheer", "icll"])
    assert code == 0, capsys.readouterr().err
    stls = sorted(out.glob("*.stl"))
    assert [p.name for p in stls] == ["wigley_1of2.stl", "wigley_2of2.stl"]
    assert len(list(out.glob("*.x3d"))) == 2 and "IndexedFaceSet" in (out / "wigley_1of2.x3d").read_text()
    pieces = [trimesh.load(p, force="mesh") for p in stls]
    assert all(p.is_watertight for p in pieces)
    # 1:200 in millimetres: 100 m → 500 mm long, the sheer raises the ends above the 50 mm depth
    assert pieces[0].bounds[0, 0] == pytest.approx(0.0, abs=1e-3) and pieces[1].bounds[1, 0] == pytest.approx(500.0)
    assert pieces[1].bounds[1, 2] > 50.0
    code = main(["print", "builtin:wigley?L=100&B=10&T=6.25&D=10", "--scale", "1:0", "--out", str(out)])
    assert code == 2 and "--scale" in capsys.readouterr().err
