"""Sweeps at scale: a sweep split in shards and merged equals the unsplit sweep; two CPU devices give the
one-device results; a Dask local cluster gives the same rows; a sweep with new numbers does not trace; bad
shard options fail with a message.

One small sweep (4 values in chunks of 2, 2 outer rounds of 40 steps), solved once for the module with its own
cache (its kept programs: the chunks' and those it prepares while they run); the other runs are compared with
it."""

import json
import os
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

from hullopt.app.cli import main

pytestmark = pytest.mark.slow  # minutes of solving: `make test-slow` (CI runs both)


CONFIG = Path(__file__).resolve().parent / "data" / "sweep_small.toml"  # configs/pareto_bow.toml is the KCS's
SMALL = ["--set", "sweep.count=4", "--set", "sweep.chunk=2", "--set", "solver.outer=2", "--set", "solver.max_steps=40"]


def run(capsys, *args):
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def sweep(capsys, out: Path, *extra) -> tuple[int, dict]:
    code, stdout, err = run(capsys, "run", str(CONFIG), *SMALL, "--out", str(out), "--json", *extra)
    assert code == 3, err  # 3: with 2 rounds of 40 steps no design meets its targets; the rows are still compared
    report = json.loads(stdout)
    assert not any(d["met"] for d in report["designs"])
    return code, report


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    folder = tmp_path_factory.mktemp("sweeps")
    with pytest.MonkeyPatch.context() as mp:  # the unsplit sweep's own cache (the tests take the session's)
        mp.setenv("HULLOPT_CACHE", str(folder / "cache"))
        yield folder


BUILT: list[tuple[str, str]] = []  # the unsplit sweep's kept programs built (not loaded): (name, thread)


@pytest.fixture(scope="module")
def unsplit(folder):
    from hullopt.study import _programs as programs

    real = programs._program

    def recorded(path, *a):
        if not path.exists():
            BUILT.append((path.name.rsplit("-", 1)[0], threading.current_thread().name))
        return real(path, *a)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(programs, "_program", recorded)
        code = main(["run", str(CONFIG), *SMALL, "--out", str(folder / "full"), "--json"])
    assert code == 3  # module fixtures have no capsys: the report is read from the run folder
    report = json.loads((folder / "full" / "report.json").read_text())
    assert not report["met"] and not any(d["met"] for d in report["designs"])  # why the code is 3
    # the designs left the parent, each its own way: the comparisons below compare solves, not the parent
    # (with 20 steps a round the line search's backtracking from BFGS's first, unscaled step used them all)
    objectives = [d["objective"] for d in report["designs"]]
    assert len(set(objectives)) == len(objectives)
    assert all(np.abs(np.ravel(d["params"]["distribution_c"])).max() > 1e-3 for d in report["designs"])
    return report


def test_unsplit_sweep_has_every_chunk(unsplit, folder):
    assert len(unsplit["designs"]) == 4 and "partial" not in unsplit
    # the chunks' program built once (the second chunk loads it), and the assessment's, rescoring's and
    # outcomes' each once, on the thread that prepared it while the chunks compiled and ran
    assert BUILT.count(("sweep", "MainThread")) == 1
    for name in ("assess", "rescore", "outcomes"):
        assert [t for n, t in BUILT if n == name] == [f"prepare-{name}"], BUILT
    assert sorted(p.name for p in (folder / "full" / "chunks").iterdir()) == ["chunk_0000.json", "chunk_0001.json"]
    assert [d["bf_target"] for d in unsplit["designs"]] == pytest.approx([0.012, 0.017333333, 0.022666667, 0.028])


def test_shards_merged_equal_the_unsplit_sweep(capsys, unsplit, folder):
    a, b, m = folder / "s1", folder / "s2", folder / "merged"
    _, r1 = sweep(capsys, a, "--shard", "1/2")
    assert r1["partial"] and r1["chunks_done"] == [0] and r1["chunks_total"] == 2
    assert [p.name for p in (a / "chunks").iterdir()] == ["chunk_0000.json"]  # only its own chunk
    assert not (a / "hull.stl").exists()
    code, stdout, err = run(capsys, "merge", str(a), "--out", str(m))
    assert code == 2 and "chunk(s) 1 of 2" in err
    _, r2 = sweep(capsys, b, "--shard", "2/2")
    assert r2["chunks_done"] == [1]
    code, stdout, err = run(capsys, "merge", str(a), str(b), "--out", str(m), "--json")
    merged = json.loads(stdout)
    assert code == 3, err  # as the unsplit sweep: no design meets its targets
    assert merged["designs"] == unsplit["designs"]  # the same compiled solver: bit for bit
    assert merged["pareto_count"] == unsplit["pareto_count"] and merged["parent"] == unsplit["parent"]
    assert (m / "pareto.png").stat().st_size > 0 and (m / "report.json").exists()


def test_new_sweep_numbers_run_the_kept_programs_without_tracing(capsys, unsplit, folder, monkeypatch):
    """The sweep's values are arguments of its kept chunk program (and the designs those of the assessment's,
    the rescoring's and the outcomes' programs): a sweep to another stop neither traces nor compiles, solves at
    its own values, and its first value, which the unsplit sweep shares, comes back bit for bit."""
    from hullopt.study import _programs as programs

    monkeypatch.setenv("HULLOPT_CACHE", str(folder / "cache"))  # the unsplit sweep's programs
    monkeypatch.setattr(programs, "_export", lambda *a: pytest.fail("traced again for new numbers"))
    _, r = sweep(capsys, folder / "what-if", "--set", "sweep.stop=0.026")
    assert [d["bf_target"] for d in r["designs"]] == pytest.approx([0.012, 0.016666667, 0.021333333, 0.026])
    assert r["designs"][0] == unsplit["designs"][0]
    assert all(a["objective"] != b["objective"] for a, b in zip(r["designs"][1:], unsplit["designs"][1:]))


def test_merge_refuses_different_sweeps(capsys, unsplit, folder, tmp_path):
    other = tmp_path / "other"
    (other / "chunks").mkdir(parents=True)
    raw = json.loads((folder / "full" / "config.json").read_text())
    raw["sweep"]["stop"] = 0.03
    (other / "config.json").write_text(json.dumps(raw))
    code, _, err = run(capsys, "merge", str(folder / "full"), str(other), "--out", str(tmp_path / "m"))
    assert code == 2 and "a different sweep config" in err
    code, _, err = run(capsys, "merge", str(tmp_path / "nothing"), "--out", str(tmp_path / "m"))
    assert code == 2 and "not a run folder" in err


@pytest.mark.parametrize("args, message", [
    (["--shard", "3/2"], "expected 1 ≤ k ≤ N"),
    (["--shard", "half"], "expected k/N"),
    (["--executor", "spark"], "expected local or dask"),
    (["--address", "tcp://localhost:1"], "--address needs --executor dask"),
])
def test_bad_sweep_options(capsys, tmp_path, args, message):
    code, _, err = run(capsys, "run", str(CONFIG), "--out", str(tmp_path / "o"), *args)
    assert code == 2 and message in err, err


def test_shard_of_a_fit_is_an_error(capsys, tmp_path):
    fit = CONFIG.parents[2] / "configs" / "fit_cb_lcb.toml"
    code, _, err = run(capsys, "run", str(fit), "--out", str(tmp_path / "o"), "--shard", "1/2")
    assert code == 2 and "apply to sweeps" in err


def test_two_cpu_devices_give_the_one_device_results(unsplit, folder):
    out = folder / "two"
    script = ("import sys, jax; jax.config.update('jax_num_cpu_devices', 2); assert jax.device_count() == 2; "
              "from hullopt.app.cli import main; sys.exit(main(sys.argv[1:]))")
    env = dict(os.environ, HULLOPT_CACHE=str(folder / "cache2"))
    p = subprocess.run([sys.executable, "-c", script, "run", str(CONFIG), *SMALL, "--out", str(out), "--json"],
                       capture_output=True, text=True, env=env, timeout=900)
    assert p.returncode == 3, p.stderr  # as the unsplit sweep
    two = json.loads(p.stdout)["designs"]
    for a, b in zip(unsplit["designs"], two, strict=True):
        # the batch is split over the devices: the same solves up to round-off (amplified by the stopped solver)
        assert b["objective"] == pytest.approx(a["objective"], rel=1e-7)
        for k in a["params"]:
            assert np.ravel(b["params"][k]) == pytest.approx(np.ravel(a["params"][k]), abs=1e-6)
        assert b["iterations"] == a["iterations"] and b["met"] == a["met"]


def test_dask_local_cluster_gives_the_same_rows(capsys, unsplit, folder):
    pytest.importorskip("distributed")
    _, r = sweep(capsys, folder / "dask", "--executor", "dask")
    assert r["designs"] == unsplit["designs"]
