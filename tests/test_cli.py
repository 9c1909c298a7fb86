"""The command line: JSON keys and values, tables, exports, and one-line errors for bad input."""

import json
import subprocess
import sys

import numpy as np
import pytest
import trimesh
from conftest import REPO

WIGLEY = "builtin:wigley?L=100&B=10&T=6.25&D=10&n=21&m=41"
KEYS = ["draft", "volume", "displacement", "wetted_surface", "a_transom", "cb", "cp", "cm", "cwp", "lcb", "lcb_pct",
        "kb", "awp", "lcf", "lcf_pct", "bmt", "bml", "kmt", "tpc", "mct", "lwl", "bwl"]


def test_hydro_json_has_exactly_the_documented_keys(cli):
    code, out, _ = cli("hydro", "builtin:box?L=100&B=10&D=10", "--draft", "4", "--json")
    assert code == 0
    d = json.loads(out)
    assert list(d) == KEYS
    assert d["volume"] == pytest.approx(4000) and d["displacement"] == pytest.approx(4000 * 1025)
    assert d["a_transom"] == pytest.approx(10 * 4)  # a box's transom: B·T
    assert d["lcb"] == pytest.approx(50) and d["lcb_pct"] == pytest.approx(0, abs=1e-12)


@pytest.mark.slow
def test_hydro_drafts_table_and_displacement(cli):
    code, out, _ = cli("hydro", WIGLEY, "--drafts", "2:6:3", "--json")
    rows = json.loads(out)
    assert code == 0 and [r["draft"] for r in rows] == [2, 4, 6]
    code, out, _ = cli("hydro", "builtin:box?L=100&B=10&D=10", "--displacement", "4100", "--json")
    assert code == 0 and json.loads(out)["draft"] == pytest.approx(4.0, abs=1e-9)
    code, out, _ = cli("hydro", WIGLEY)  # design draft, rich table
    assert code == 0 and "Cb" in out and "0.444" in out


def test_export_formats(cli, tmp_path):
    from hullopt.models import load_hull
    from hullopt.geometry._mesh import hull_mesh  # what export writes: refined, then welded to float32

    ours = hull_mesh(load_hull(WIGLEY).sections)
    for ext in ("stl", "obj", "ply", "glb"):
        out = tmp_path / f"h.{ext}"
        code, _, err = cli("export", WIGLEY, str(out))
        assert code == 0, err
        mesh = trimesh.load(out, force="mesh")
        assert mesh.is_watertight and mesh.volume == pytest.approx(ours.volume, rel=1e-6)  # float32 files
    code, _, _ = cli("export", WIGLEY, str(tmp_path / "h.x3d"))
    text = (tmp_path / "h.x3d").read_text()
    assert code == 0 and text.count(" -1") > 1000 and "<IndexedFaceSet" in text


@pytest.mark.parametrize(
    "args, message",
    [
        (["hydro", "builtin:wigley?L=100&B=10&D=10"], "missing parameter T"),
        (["hydro", "builtin:wigley?L=100&B=10&T=5&D=10&Q=1"], "unknown parameter 'Q'"),
        (["hydro", "builtin:ship?L=1"], "unknown builtin 'ship'"),
        (["hydro", "builtin:box?L=100&B=-1&D=10", "--draft", "1"], "B must be a positive number"),
        (["hydro", WIGLEY, "--draft", "0"], "--draft 0 m is outside the hull"),
        (["hydro", WIGLEY, "--draft", "11"], "--draft 11 m is above the deck"),
        (["hydro", WIGLEY, "--displacement", "99999999"], "more than the hull displaces"),
        (["hydro", WIGLEY, "--drafts", "1:2"], "expected START:STOP:COUNT"),
        (["hydro", "nofile.stl"], "no such file"),
        (["hydro", str(REPO / "README.md")], "unknown file type 'md'"),
        (["export", WIGLEY, "x.step"], "unknown mesh format"),
    ],
)
@pytest.mark.slow
def test_bad_input_one_line_error(cli, args, message):
    code, out, err = cli(*args)
    assert code == 2
    assert message in err and err.count("\n") == 1 and "Traceback" not in err


def test_open_mesh_and_bad_offsets_from_the_console(tmp_path):
    """As a user runs it: a separate process, exit code 2, one line on stderr."""
    bad = tmp_path / "bad.csv"
    bad.write_text("x,0,1\n0,1,1\n0,1,1\n")
    holed = trimesh.creation.box(extents=[100, 10, 10]).subdivide().subdivide()
    c = holed.triangles_center
    holed.update_faces(np.arange(len(c)) != np.argmin(np.linalg.norm(c - [0, 5, 1], axis=1)))  # a hole in the side
    holed.export(tmp_path / "holed.stl")
    for hull, message in ((str(tmp_path / "holed.stl"), "the mesh has a hole at x "),
                          (str(bad), "duplicate station")):
        p = subprocess.run([sys.executable, "-m", "hullopt", "hydro", hull, "--draft", "1"],
                           capture_output=True, text=True, env={"HULLOPT_CACHE": str(tmp_path), "PATH": ""})
        assert p.returncode == 2 and message in p.stderr and "Traceback" not in p.stderr, p.stderr


def test_each_command_is_registered_by_the_module_the_registry_names():
    """``hullopt CMD`` imports only CMD's module: the registry must name every command and its module."""
    import importlib

    from hullopt.app import commands
    from hullopt.app._app import app

    for name, module in commands.COMMANDS.items():
        mod = importlib.import_module(f"hullopt.app.commands.{module}")
        assert any(c.callback.__module__ == mod.__name__ and (c.name or c.callback.__name__) == name
                   for c in app.registered_commands), name
    assert {c.name or c.callback.__name__ for c in app.registered_commands} == set(commands.COMMANDS)


def test_a_command_that_reads_a_hull_loads_no_study():
    """``hullopt hydro``/``stability`` import the app, their command and the hull reader: not the configs, the
    studies, the optimiser or the report's page and plots (0.6 s of a warm call: hullopt.report and
    hullopt.study load their names on first use)."""
    code = ("import sys; from hullopt.app.cli import configure_jax; configure_jax(); import hullopt.app._app; "
            "import hullopt.app.commands.hydro, hullopt.app.commands.stability; "
            "print(*(m in sys.modules for m in ('hullopt.optimise', 'hullopt.study._config', "
            "'hullopt.study._study', 'hullopt.report._html', 'hullopt.report._plots', 'pydantic')))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False"] * 6


def test_help_lists_every_command():
    out = subprocess.run([sys.executable, "-m", "hullopt", "--help"], capture_output=True, text=True, check=True)
    from hullopt.app.commands import COMMANDS

    assert all(f" {name} " in out.stdout for name in COMMANDS)


def test_xla_scheduler_workaround_is_set_and_leaves_the_users_choice():
    """Importing hullopt (the CLI's first step, and the API's) turns off XLA:CPU's concurrency-optimised
    scheduler (it wedged the report's vmapped program of a sweep), before jax's backend starts; a user's own
    setting of that flag wins."""
    import os

    from hullopt import XLA_SCHEDULER_OFF, xla_flags

    assert XLA_SCHEDULER_OFF in os.environ["XLA_FLAGS"]
    assert xla_flags("") == XLA_SCHEDULER_OFF
    assert xla_flags("--xla_force_host_platform_device_count=2") == \
        f"--xla_force_host_platform_device_count=2 {XLA_SCHEDULER_OFF}"
    mine = "--xla_cpu_enable_concurrency_optimized_scheduler=true"
    assert xla_flags(mine) == mine
    import jax

    assert jax.devices()  # the backend started with these flags (no XLA error on an unknown flag)


def test_classic_emitters_for_a_process_of_small_programs_only(tmp_path):
    """A process started for a command of small programs (``hydro``, ``stability``, ``motions``…) or a fit run
    compiles with XLA:CPU's classic emitters (half the compile); a sweep, a minimisation, the other commands, an
    unreadable config and a user who chose the emitters keep XLA_FLAGS as they are."""
    from functools import partial

    from hullopt.app import cli

    CLASSIC_EMITTERS, xla_flags_for = cli.CLASSIC_EMITTERS, partial(cli.xla_flags_for, classic=True)
    base = "--xla_cpu_enable_concurrency_optimized_scheduler=false"
    for config in ("fit_cb_lcb", "fit_own_hull", "pareto_bow", "min_added_resistance"):
        path = str(REPO / "configs" / f"{config}.toml")
        flags = xla_flags_for(["run", path, "--set", "targets.cb=0.47"], base)
        assert flags == (f"{base} {CLASSIC_EMITTERS}" if config.startswith("fit") else base), config
    assert xla_flags_for(["hydro", WIGLEY, "--json"], "") == CLASSIC_EMITTERS
    assert xla_flags_for(["--help"], base) == base
    for argv in (["stability", "DTC.stl", "--kg", "20"], ["--json", "hydro", WIGLEY]):
        assert xla_flags_for(argv, base) == f"{base} {CLASSIC_EMITTERS}"
    for argv in (["resistance", WIGLEY], ["rescore", "runs/x"], ["run", str(tmp_path / "absent.toml")], ["run"]):
        assert xla_flags_for(argv, base) == base, argv
    (tmp_path / "bad.toml").write_text("kind = \n")
    assert xla_flags_for(["run", str(tmp_path / "bad.toml")], base) == base
    mine = "--xla_cpu_use_fusion_emitters=true"
    assert xla_flags_for(["hydro", WIGLEY], mine) == mine
    assert cli.xla_flags_for(["hydro", WIGLEY], base, classic=False) == base


def test_classic_emitters_only_where_xla_has_them():
    """jaxlib 0.11.1 removed XLA:CPU's classic emitters, and XLA aborts a process whose XLA_FLAGS name an unknown
    option (``hullopt hydro`` and a fit's run died at start on jax 0.11.1, 0.11.2 and 0.12.0.1; 0.11.0 takes it):
    the flag is set only for an older jaxlib. The suite's own jaxlib decides it without its version given."""
    import jaxlib

    from hullopt.app.cli import classic_emitters_available

    for v in ("0.10.1", "0.9.2", "0.11.0"):
        assert classic_emitters_available(v), v
    for v in ("0.11.1", "0.11.2", "0.12.0.1", "1.0.0", "0.12.dev20261101"):
        assert not classic_emitters_available(v), v
    assert classic_emitters_available() == classic_emitters_available(jaxlib.__version__)
