"""The Pareto sweep from the command line (configs/pareto_bow.toml's reduced copy): every design met, the front
non-dominated, each design's hull written, a killed sweep resumed. Its own file so that pytest-xdist's
``--dist loadfile`` runs it beside tests/test_run.py rather than after it (each takes minutes)."""

import json
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow  # minutes of solving: `make test-slow` (CI runs both)


CONFIGS = Path(__file__).resolve().parents[1] / "configs"


def test_pareto_sweep_is_non_dominated_and_resumes(cli_process, tmp_path):
    """configs/pareto_bow.toml's sweep (Michell + friction against R_AW, motion + reflection; the frames moved
    along the length) on the Wigley: the KCS's takes longer than a test may (tests/data/pareto_wigley.toml, the
    reduced copy). A design of the sweep, rebuilt from the run folder with its moved stations, reads back."""
    out = tmp_path / "p"
    args = ["run", str(CONFIGS.parent / "tests" / "data" / "pareto_wigley.toml"), "--set", "sweep.count=4",
            "--set", "sweep.chunk=2", "--out", str(out), "--json"]
    code, stdout, err = cli_process(*args)
    assert code == 0, err
    r = json.loads(stdout)
    designs = r["designs"]
    assert len(designs) == 4 and all(d["met"] for d in designs)
    pts = [(d["measure"], d["objective"]) for d in designs]
    for d, p in zip(designs, pts):  # truly non-dominated
        dominated = any(q[0] <= p[0] and q[1] <= p[1] and q != p for q in pts)
        assert d["pareto"] == (not dominated)
    assert (out / "pareto.png").stat().st_size > 0
    for k in range(4):  # each design's hull
        assert (out / "designs" / str(k) / "hull.stl").stat().st_size > 0
        assert (out / "designs" / str(k) / "offsets.csv").stat().st_size > 0
        assert (out / "designs" / str(k) / "overlay.png").stat().st_size > 0
    assert not (out / "hull.stl").exists() and not (out / "overlay.png").exists()  # no parent posing as a design
    assert len(r["objectives"]["mean_added_resistance"]["designs"]) == 4
    assert "Pareto front" in (out / "report.html").read_text(encoding="utf-8")  # the designs rebuilt for the page
    code, stdout, err = cli_process("hydro", f"{out}?design=2", "--json")  # one design of the sweep as a hull
    assert code == 0, err
    assert json.loads(stdout)["cb"] == pytest.approx(designs[2]["particulars"]["cb"], rel=1e-9)
    code, _, err = cli_process("hydro", str(out))
    assert code == 2 and "needs ?design=K with K in 0…3" in err
    # Kill simulation: chunk 1 lost, chunk 0 kept (marked, to see that it is not recomputed).
    c0, c1 = out / "chunks" / "chunk_0000.json", out / "chunks" / "chunk_0001.json"
    data = json.loads(c0.read_text())
    data["designs"][0]["iterations"] = -12345
    c0.write_text(json.dumps(data))
    c1.unlink()
    code, stdout, _ = cli_process(*args)
    again = json.loads(stdout)["designs"]
    assert code == 0 and again[0]["iterations"] == -12345 and c1.exists()
    assert again[3]["objective"] == pytest.approx(designs[3]["objective"], rel=1e-9)  # deterministic
