"""benchmarks/run.py's summary table: a GPU run's results (``results/<name>-gpu.json``, as ``_common.save`` names
them on a GPU) sit beside the CPU's, one measured column per device, and each device's goals are counted apart."""

import importlib.util
import json
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks"


@pytest.fixture
def run_module(tmp_path, monkeypatch):
    spec = importlib.util.spec_from_file_location("bench_run", BENCH / "run.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    monkeypatch.setattr(mod, "RESULTS", tmp_path)
    return mod


def _result(path: Path, platform: str, kind: str, goals: list[dict]) -> None:
    machine = {"python": "3.12", "jax": "0.11.2", "cores": 2, "cpu": "x86_64", "load_at_start": 0.5,
               "device": {"backend": platform, "platform": platform, "kind": kind, "count": 1},
               "date": "2026-11-26 12:00 UTC"}
    path.write_text(json.dumps({"machine": machine, "goals": goals}))


def _goal(name, value, met):
    return {"name": name, "value": value, "unit": "s", "target": "< 2", "met": met, "peer": None}


def test_cpu_and_gpu_side_by_side(run_module, tmp_path):
    _result(tmp_path / "sweep.json", "cpu", "cpu", [_goal("KCS sweep, cold", 298.0, False)])
    _result(tmp_path / "sweep-gpu.json", "gpu", "NVIDIA H100", [_goal("KCS sweep, cold", 41.0, True)])
    _result(tmp_path / "hydro.json", "cpu", "cpu", [_goal("table, warm", 0.025, True)])
    text = run_module.summary()
    assert "| benchmark | goal | measured (CPU) | measured (GPU) | target | met (CPU / GPU) |" in text
    assert "- GPU: 2 cores x86_64" in text and "NVIDIA H100" in text
    rows = {line.split(" | ")[1]: line for line in text.splitlines() if line.startswith("| sweep") or
            line.startswith("| hydro")}
    assert "| 298 s | 41 s | < 2 | **missed** / **met** |" in rows["KCS sweep, cold"]
    assert "| 0.025 s | — | < 2 | **met** / — |" in rows["table, warm"]  # no GPU result: a dash, not a guess
    assert "CPU: 1 goals met, 1 missed." in text and "GPU: 1 goals met, 0 missed." in text


def test_cpu_only_has_one_measured_column(run_module, tmp_path):
    _result(tmp_path / "hydro.json", "cpu", "cpu", [_goal("table, warm", 0.025, True)])
    text = run_module.summary(failed={"panel": "timed out after 60 s"})
    assert "| benchmark | goal | measured (CPU) | target | met (CPU) |" in text
    assert "the script failed (timed out after 60 s)" in text


def test_a_gpu_run_names_its_own_machine_and_the_cards_it_mixes(run_module, tmp_path):
    """Run on a GPU, the GPU line is that run's machine (not the CPU's), and results from two cards say so."""
    _result(tmp_path / "hydro.json", "cpu", "cpu", [_goal("table, warm", 0.025, True)])
    _result(tmp_path / "hydro-gpu.json", "gpu", "NVIDIA H100", [_goal("table, warm", 0.001, True)])
    _result(tmp_path / "panel-gpu.json", "gpu", "NVIDIA H200", [_goal("a design in a batch", 0.015, True)])
    here = {"python": "3.12", "jax": "0.11.2", "cores": 16, "cpu": "x86_64", "load_at_start": 0.1,
            "device": {"backend": "gpu", "platform": "gpu", "kind": "NVIDIA H200", "count": 1}}
    lines = run_module.summary("2026-11-27 06:00 UTC", run_machine=here).splitlines()
    cpu, gpu = (next(x for x in lines if x.startswith(f"- {d}:")) for d in ("CPU", "GPU"))
    assert "2 cores" in cpu and "device cpu" in cpu
    assert "16 cores" in gpu and "mix devices NVIDIA H100, NVIDIA H200" in gpu


def test_a_merged_row_keeps_its_own_date(run_module, tmp_path, monkeypatch):
    """A partial run (``_common.merge``: one benchmark's extra rows) dates its rows; the file's other rows keep
    the date they were measured on."""
    spec = importlib.util.spec_from_file_location("bench_common", BENCH / "_common.py")
    common = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(common)
    monkeypatch.setattr(common, "RESULTS", tmp_path)
    monkeypatch.setattr(common, "machine", lambda: {"date": "2026-11-29 18:42 UTC", "load_at_start": 0.6,
                                                    "device": {"platform": "cpu"}})
    _result(tmp_path / "panel.json", "cpu", "cpu", [_goal("one evaluation", 0.7, True)])
    common.merge("panel", {"extra": [1], "goals": [_goal("a new row", 1.5, None)]})
    text = run_module.summary()
    rows = {line.split(" | ")[1]: line for line in text.splitlines() if line.startswith("| panel")}
    assert rows["one evaluation"].endswith("| 2026-11-26 12:00 UTC; load 0.5 |")
    assert rows["a new row"].endswith("| 2026-11-29 18:42 UTC; load 0.6 |")
    assert json.loads((tmp_path / "panel.json").read_text())["extra"] == [1]
