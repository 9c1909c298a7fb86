"""Config-driven runs from the command line: the three use-case configs, resume of a killed sweep, and bad
configs failing fast with a message naming the field."""

import contextlib
import io
import json
import re
import tomllib
from pathlib import Path

import pytest


CONFIGS = Path(__file__).resolve().parents[1] / "configs"
DATA = Path(__file__).resolve().parent / "data"


@pytest.fixture(scope="module")
def fit_run(tmp_path_factory):
    """configs/fit_cb_lcb.toml run once for the module (a cold run: it traces, compiles and keeps its programs):
    ``(folder, report printed by --json)``. Checked by the test of the run folder and re-run warm by the test of
    the kept program, so the suite solves this config once rather than twice."""
    from hullopt.app.cli import main

    out = tmp_path_factory.mktemp("fit") / "fit"
    with pytest.MonkeyPatch.context() as mp:  # the session's throw-away cache, as conftest's autouse fixture sets
        mp.setenv("HULLOPT_CACHE", str(tmp_path_factory.getbasetemp().parent / "jax-cache"))
        with contextlib.redirect_stdout(io.StringIO()) as stdout:  # module fixtures have no capsys
            code = main(["run", str(CONFIGS / "fit_cb_lcb.toml"), "--out", str(out), "--json"])
    assert code == 0
    return out, json.loads(stdout.getvalue())


@pytest.mark.slow
def test_fit_config_meets_its_targets_and_writes_the_run_folder(cli, fit_run, monkeypatch):
    out, report = fit_run
    assert report["converged"] and report["met"] and report["iterations"] > 0
    assert abs(report["achieved"]["cb"] - 0.48) <= 1e-4 and abs(report["achieved"]["lcb_pct"] + 1.5) <= 0.01
    assert set(report["achieved"]) >= {"volume", "cb", "lcb_pct", "kb", "wetted_surface"}
    for f in ("report.json", "config.json", "parent.json", "hull.stl", "offsets.csv", "parent_offsets.csv",
              "overlay.png", "convergence.png", "report.html"):
        assert (out / f).stat().st_size > 0, f
    # every measure parent → design with its unit; a fit's bounds reached are warned of
    objectives = report["objectives"]
    assert set(objectives) >= {"bf", "unfairness", "sac_roughness", "section_roughness"}
    assert all(set(v) == {"parent", "design", "unit"} for v in objectives.values())
    assert isinstance(report["warnings"], list)
    # where the time went: each phase's wall time, in order, report.json holding the files' time too
    assert list(report["seconds"]) == ["setup", "solve", "assess", "rescore", "files"]
    assert all(t >= 0 for t in report["seconds"].values()) and report["seconds"]["solve"] > 0
    assert json.loads((out / "report.json").read_text())["seconds"] == report["seconds"]
    # the parent's offsets read back: the parent's volume (the dense table gives ∇ to about 1e-4)
    code, stdout, err = cli("hydro", str(out / "parent_offsets.csv"), "--draft", "6.25", "--json")
    assert code == 0, err
    assert json.loads(stdout)["volume"] == pytest.approx(report["parent"]["volume"], rel=5e-4)
    assert json.loads((out / "config.json").read_text())["targets"]["cb"] == 0.48
    # The run folder is a hull spec: its design, rebuilt from config.json and report.json, at the run's draft.
    code, stdout, err = cli("hydro", str(out), "--json")
    assert code == 0, err
    again = json.loads(stdout)
    assert again["draft"] == 6.25
    for k in ("volume", "cb", "lcb_pct", "wetted_surface"):
        assert again[k] == pytest.approx(report["achieved"][k], rel=1e-9, abs=1e-9), k
    code, _, err = cli("hydro", f"{out}?design=1")
    assert code == 2 and "?design applies to sweeps" in err
    # ... from the parent the run deformed, kept in the folder, not from the config's parent as it is now (a
    # library file rebuilt, an edited mesh, a cleared cache).
    from hullopt.study import _hulls

    monkeypatch.setattr(_hulls, "run_parent", lambda *a: pytest.fail("the config's parent was read"))
    code, stdout, err = cli("hydro", str(out), "--json")
    assert code == 0 and json.loads(stdout)["cb"] == again["cb"], err


@pytest.mark.slow
def test_a_fit_run_as_its_own_process_reports_what_the_optimised_program_does(cli_process, fit_run, tmp_path):
    """``hullopt run`` of a fit as a user types it compiles with XLA:CPU's classic emitters and its solver
    without LLVM's optimisation (``hullopt.app.cli``, ``quick="classic"``); the module's run is in-process,
    with the default emitters and an optimised program. The same steps, the same report to round-off."""
    import numpy as np

    _, first = fit_run
    code, stdout, err = cli_process("run", CONFIGS / "fit_cb_lcb.toml", "--json", "--out", tmp_path / "p")
    assert code == 0, err
    other = json.loads(stdout)
    assert other["met"] and other["iterations"] == first["iterations"]
    for key in ("achieved", "parent", "params"):
        for k, v in first[key].items():
            np.testing.assert_allclose(other[key][k], v, rtol=1e-9, atol=1e-9, err_msg=f"{key}.{k}")


@pytest.mark.slow
def test_a_warm_run_reuses_the_kept_program_and_reports_the_same(cli, fit_run, tmp_path, monkeypatch):
    """The second run of a config neither traces nor compiles (kept program + compilation cache): the module's
    fit run again, with the export (trace and lower) forbidden."""
    from hullopt.study import _programs as programs

    first_out, first = fit_run
    monkeypatch.setattr(programs, "_export", lambda *a: pytest.fail("the kept program was not used"))
    code, again, err = cli("run", str(CONFIGS / "fit_cb_lcb.toml"), "--json", "--out", str(tmp_path / "b"))
    assert code == 0, err
    untimed = [{k: v for k, v in r.items() if k != "seconds"} for r in (json.loads(again), first)]
    assert untimed[0] == untimed[1]  # the same report, but for the phases' wall times
    assert (tmp_path / "b" / "hull.stl").read_bytes() == (first_out / "hull.stl").read_bytes()


@pytest.mark.slow
def test_a_run_says_each_phase_as_it_ends(cli, fit_run, tmp_path):
    """Without --json a run names each phase on stderr as it ends, with the wall time report.json keeps."""
    code, _, err = cli("run", str(CONFIGS / "fit_cb_lcb.toml"), "--out", str(tmp_path / "said"))
    assert code == 0, err
    said = dict(re.findall(r"^(\w+) done in ([\d.]+) s$", err, re.M))
    seconds = json.loads((tmp_path / "said" / "report.json").read_text())["seconds"]
    assert {"solve", "files"} <= set(said) <= set(seconds)
    assert all(abs(float(v) - seconds[k]) <= 0.05 for k, v in said.items())
    assert [k for k in seconds if k in said] == list(said)  # in the order they ran


@pytest.mark.slow
def test_new_numbers_run_the_kept_program_without_tracing(cli, fit_run, tmp_path, monkeypatch):
    """Targets and the draft are arguments of the kept programs, not constants: a what-if run with other
    numbers and the same structure neither traces nor compiles, and meets its own targets (a program with the
    first run's numbers baked in would meet those)."""
    from hullopt.study import _programs as programs

    monkeypatch.setattr(programs, "_export", lambda *a: pytest.fail("traced again for new numbers"))
    code, out, err = cli("run", str(CONFIGS / "fit_cb_lcb.toml"), "--set", "targets.cb=0.47",
                         "--set", "targets.lcb_pct=-1.2", "--set", "hull.draft=6.0", "--json",
                         "--out", str(tmp_path / "what-if"))
    assert code == 0, err
    report = json.loads(out)
    assert abs(report["achieved"]["cb"] - 0.47) <= 1e-4 and abs(report["achieved"]["lcb_pct"] + 1.2) <= 0.01
    assert report["achieved"]["volume"] < 0.97 * fit_run[1]["achieved"]["volume"]  # at the new draft


@pytest.mark.slow
def test_infeasible_target_is_reported_with_the_closest_design(cli, tmp_path):
    out = tmp_path / "far"
    code, stdout, _ = cli("run", str(CONFIGS / "fit_cb_lcb.toml"), "--set", "targets.cb=0.75",
                          "--out", str(out), "--json")
    report = json.loads(stdout)
    assert code == 3 and not report["met"] and "cannot be met" in report["message"]
    assert (out / "hull.stl").exists() and report["targets"]["cb"]["met"] is False


@pytest.mark.slow
def test_a_station_shift_fit_keeps_every_section_and_reads_back(cli, tmp_path):
    """The frames themselves move along the length (``curves = "stations"``): the Wigley fitted to Cb 0.46 and
    LCB −1 % Lpp with every section the parent's own (section roughness equal to the parent's); the run folder and
    its mesh read back with those particulars (the mesh to its resolution)."""
    cfg = tmp_path / "st.toml"
    cfg.write_text('kind = "fit"\n[hull]\nparent = "wigley"\ndraft = 6.25\n'
                   '[[design.distribution]]\nx_a = 0.0\nx_b = 100.0\ncurves = "stations"\nmodes = 2\nbound = 0.4\n'
                   "[targets]\ncb = 0.46\nlcb_pct = -1.0\n")
    out = tmp_path / "st"
    code, stdout, err = cli("run", cfg, "--out", out, "--json")
    assert code == 0, err
    r = json.loads(stdout)
    assert r["met"] and not r["warnings"]
    rough = r["objectives"]["section_roughness"]
    assert rough["design"] == pytest.approx(rough["parent"], rel=1e-12)
    assert r["objectives"]["sac_roughness"]["design"] > 1.2 * r["objectives"]["sac_roughness"]["parent"]  # it moved
    for hull, rel in ((out, 1e-9), (f"{out / 'hull.stl'}", 5e-4)):
        code, stdout, err = cli("hydro", hull, "--draft", "6.25", "--json")
        assert code == 0, err
        h = json.loads(stdout)
        assert h["cb"] == pytest.approx(0.46, rel=rel) and h["lcb_pct"] == pytest.approx(-1.0, abs=2e-3)


@pytest.mark.slow
def test_min_added_resistance_config_lowers_it_with_particulars_held(cli, tmp_path):
    # the reflection part only: with the strip-theory motions in the objective the run takes far longer than a
    # test may (the motions and their gradients are tested in test_motions.py)
    code, stdout, err = cli("run", str(DATA / "min_added_resistance_wigley.toml"), "--out", str(tmp_path / "m"),
                            "--set", "objective.motion=false", "--json")
    assert code == 0, err
    r = json.loads(stdout)
    assert r["met"] and r["objective"]["value"] < r["objective"]["parent"]
    assert all(t["met"] for t in r["targets"].values())
    # calm water over the profile not above the parent's (0.1 % tolerance); every local limit met and reported
    calm = r["objectives"]["calm_resistance_michell"]
    assert calm["design"] <= 1.001 * calm["parent"] and calm["unit"] == "N"
    assert {"dwl_turns", "section_inflections", "waterline_angles", "sac_regions", "kmt", "frozen"} <= set(r["limits"])
    assert all(v["design"] <= v["tolerance"] for v in r["limits"].values()), r["limits"]
    assert not [w for w in r["warnings"] if "violated" in w or "rougher" in w], r["warnings"]
    for name in ("overlay.png", "rescored_fronts.png", "convergence.png"):
        assert (tmp_path / "m" / name).stat().st_size > 0


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda t: t.replace("[targets]", "[targets]\ncbb = 0.5"), "targets.cbb: unknown target"),
        (lambda t: t.replace("kind = \"fit\"", "kind = \"fit\"\ncolour = 1"), "colour: unknown key (expected one of"),
        (lambda t: t.replace("max_steps = 200", "max_step = 200"),
         "solver.max_step: unknown key; did you mean 'max_steps'? (expected one of fairness, max_steps,"),
        (lambda t: t.replace("max_steps = 200", "max_steps = \"many\""), "solver.max_steps"),
        (lambda t: t.replace("parent = \"wigley\"", "parent = \"nosuch\""), "unknown parent 'nosuch'"),
        (lambda t: t.replace("cb = 0.48", "cb = 1.4"), "cb = 1.4 is outside the physical range"),
        (lambda t: t.replace("[targets]", "[targetz]"), "targetz"),
        (lambda t: t.replace("draft = 6.25", "draft = 12.0"), "hull.draft = 12 m is above the deck of 'wigley'"),
        # a draft at the deck edge (an offset table that stops at the DWL) with frames re-read along the length
        (lambda t: t.replace("draft = 6.25", "draft = 10.0"), "design.distribution[0]: 'wigley' has no freeboard"),
    ],
)
def test_bad_configs_fail_fast(cli, tmp_path, edit, message):
    cfg = tmp_path / "bad.toml"
    cfg.write_text(edit((CONFIGS / "fit_cb_lcb.toml").read_text()))
    code, _, err = cli("run", str(cfg), "--out", str(tmp_path / "o"))
    assert code == 2 and message in err and "Traceback" not in err, err
    assert str(cfg) in err or "nosuch" in err or "hull.draft" in err
    assert not (tmp_path / "o").exists()  # nothing written for a config refused


def test_missing_config_file(cli, tmp_path):
    code, _, err = cli("run", str(tmp_path / "none.toml"))
    assert code == 2 and "cannot read the config" in err


def test_every_shipped_config_is_valid():
    """Each file in configs/ reads and validates as what it is (run, wind, or a deform design)."""
    from hullopt.app.commands.features import read_design
    from hullopt.study import load_config
    from hullopt.study import read_wind_config
    from hullopt.models import parent_names

    for path in sorted(CONFIGS.glob("*.toml")):
        top = tomllib.loads(path.read_text())
        if "kind" in top:
            cfg, _ = load_config(path)
            parent = cfg.hull.parent.partition("?")[0]
            assert parent in parent_names() or Path(parent).is_file(), path  # resolved beside the config
        elif "parent" in top:
            read_design(path)
        else:
            read_wind_config(path)


@pytest.mark.slow
def test_a_fit_by_lbfgsb_from_the_config(cli, tmp_path):
    """``[solver] method = "lbfgsb"``: the demo fit solved by jaxopt's L-BFGS-B (hard bounds) meets the same
    targets, its history named by its solver; a minimise run refuses it, naming the field."""
    code, out, err = cli("run", CONFIGS / "fit_cb_lcb.toml", "--set", 'solver.method="lbfgsb"', "--json",
                         "--out", tmp_path / "l")
    report = json.loads(out)
    assert code == 0 and report["met"], err
    assert abs(report["achieved"]["cb"] - 0.48) <= 1e-4 and abs(report["achieved"]["lcb_pct"] + 1.5) <= 0.01
    assert report["history"]["iteration"] == "L-BFGS-B step"
    code, _, err = cli("run", DATA / "min_added_resistance_wigley.toml", "--set", 'solver.method="lbfgsb"',
                       "--out", tmp_path / "m")
    assert code == 2 and "solver.method = 'lbfgsb' applies to fits" in err, err


def test_a_sweeps_design_writers_start_before_its_designs(tmp_path):
    """A sweep of four designs or more has its writers (a process per core, at most one a design) spawned, with
    their imports, when the pool is made, before the solve hands them any design; fewer designs are written in
    the run's own process. (The writers' output: tests/test_pareto_run.py.)"""
    import os

    from hullopt.app import run as app

    with app._writers(3) as pool:
        assert pool is None
    if (os.cpu_count() or 1) < 2:
        pytest.skip("one core: no writer processes")
    with app._writers(4) as pool:
        assert len(pool._processes) == min(4, os.cpu_count())  # already spawned
        app._write_designs(pool, [], tmp_path)()


def test_a_killed_rerun_leaves_the_old_folder_whole(tmp_path, monkeypatch):
    """A run is built in a staging sibling and put in its folder's place when complete (issue 62): killed
    part-way (its new config.json written, no report yet), the folder still holds the old run alone; the killed
    run's chunks are kept for the next, which replaces the folder in one step and leaves no staging folder."""
    import os

    from hullopt.app import run as app
    from hullopt.study import load_config

    cfg, raw = load_config(CONFIGS / "fit_cb_lcb.toml")
    out = tmp_path / "runs" / "x"
    (out / "chunks").mkdir(parents=True)
    (out / "config.json").write_text('{"old": true}')
    (out / "report.json").write_text('{"old": true}')
    (out / "chunks" / "chunk_0.json").write_text("old chunk")
    monkeypatch.setattr(app, "load_study", lambda cfg: None)

    def killed(cfg, raw, study, work, name, *rest):
        (work / "config.json").write_text('{"new": true}')
        (work / "chunks" / "chunk_1.json").write_text("new chunk")
        raise KeyboardInterrupt

    monkeypatch.setattr(app, "_solve_and_write", killed)
    with pytest.raises(KeyboardInterrupt):
        app.run(cfg, raw, out)
    assert sorted(p.name for p in out.iterdir()) == ["chunks", "config.json", "report.json"]
    assert json.loads((out / "config.json").read_text()) == {"old": True}  # beside the old report.json
    assert sorted(p.name for p in (out / "chunks").iterdir()) == ["chunk_0.json"]

    def finished(cfg, raw, study, work, name, *rest):
        assert name == "x" and sorted(p.name for p in (work / "chunks").iterdir()) == ["chunk_0.json", "chunk_1.json"]
        assert not (work / "config.json").exists()  # the killed run's files, but its chunks, are gone
        for f in ("config.json", "report.json"):
            (work / f).write_text('{"new": true}')
        return {"new": True}

    monkeypatch.setattr(app, "_solve_and_write", finished)
    assert app.run(cfg, raw, out) == {"new": True}
    assert json.loads((out / "config.json").read_text()) == json.loads((out / "report.json").read_text()) == {"new": True}
    assert sorted(p.name for p in out.parent.iterdir()) == ["x"]  # no staging or old folder left

    def plain(cfg, raw, study, work, name, *rest):
        (work / "report.json").write_text(json.dumps({"name": name}))
        return {}

    monkeypatch.setattr(app, "_solve_and_write", plain)
    app.run(cfg, raw, tmp_path / "fresh")  # a new folder: one rename
    assert json.loads((tmp_path / "fresh" / "report.json").read_text()) == {"name": "fresh"}
    monkeypatch.setattr(app, "_exchange", lambda a, b: False)  # no renameat2: moved aside, replaced, removed
    app.run(cfg, raw, out)
    assert sorted(p.name for p in out.iterdir()) == ["chunks", "report.json"]  # its chunks carried over
    assert sorted(os.listdir(out.parent)) == ["x"]


@pytest.mark.parametrize("sets, config, message", [
    (["hull.draftt=6"], "fit_cb_lcb", "hull.draftt: unknown key; did you mean 'draft'?"),
    (["design.distribution=[{x_a=1.0, x_b=50.0, curvs='stations'}]"], "fit_cb_lcb",
     "design.distribution.0.curvs: unknown key; did you mean 'curves'?"),
    (["targets.cbb=0.5"], "fit_cb_lcb", "targets.cbb: unknown target; did you mean 'cb'?"),
    (["tolerances.lcb=0.1"], "fit_cb_lcb", "tolerances.lcb: a tolerance for no target; did you mean 'cb'?"),
    (["objective.kind='calm_resistanse'"], "pareto_bow", "unknown kind; did you mean 'calm_resistance'?"),
    (["objective.motoin=false"], "pareto_bow", "takes no 'motoin' (expected one of profile, method, motion, "
     "bf_band; did you mean 'motion'?)"),
    (["constraints.wetted_surfac='<= parent'"], "pareto_bow", "unknown measure; did you mean 'wetted_surface'?"),
    (["profile=[{speed_kn=12.0, wieght=1.0}]"], "pareto_bow", "profile.0.wieght: unknown key; did you mean 'weight'?"),
])
def test_a_misspelled_key_gets_the_nearest_one(sets, config, message):
    """Every table of a run config (and a wind config, below) answers a misspelled key with the nearest key it
    takes (difflib), as ``--set`` gives it too (issue 62)."""
    from hullopt.errors import HullError
    from hullopt.study import load_config

    with pytest.raises(HullError, match=".") as e:
        load_config(CONFIGS / f"{config}.toml", sets)
    assert message in str(e.value), str(e.value)


def test_a_wind_configs_misspelled_key_gets_the_nearest_one(tmp_path):
    from hullopt.errors import HullError
    from hullopt.study import read_wind_config

    text = (CONFIGS / "wind_example.toml").read_text().replace("breadth = 36.0", "bredth = 36.0", 1)
    (tmp_path / "w.toml").write_text(text.replace("../examples", str(CONFIGS.parent / "examples")))
    with pytest.raises(HullError) as e:
        read_wind_config(tmp_path / "w.toml")
    assert "parts.0.bredth: unknown key; did you mean 'breadth'?" in str(e.value), str(e.value)
