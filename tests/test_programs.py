"""Kept programs (jax.export) of the app layer: a warm run reuses the traced program, never a stale one."""

import json
import os
import subprocess
import sys
import threading

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.study import _programs as programs


class Out(eqx.Module):
    total: jax.Array
    scaled: dict
    name: str = eqx.field(static=True)


def model(p, k):
    """A small program with a LAPACK kernel (QR) in it, as the Levenberg–Marquardt solve has."""
    q, r = jnp.linalg.qr(p["a"])
    return Out(jnp.sum(p["a"]) * k, {"b": p["b"] * k, "r": r}, name=f"k={k}")


@pytest.fixture
def folder(tmp_path, monkeypatch):
    monkeypatch.setattr(programs, "programs_dir", lambda: tmp_path / "programs")
    return tmp_path / "programs"


def args():
    return ({"a": jnp.arange(12.0).reshape(4, 3), "b": jnp.asarray([1.0, 2.0])},)


def test_a_kept_program_is_reused_without_tracing(folder, monkeypatch):
    first = programs.cached_call("t", model, args(), (3,), key={"config": 1})
    files = list(folder.glob("t-*.bin"))
    assert len(files) == 1
    monkeypatch.setattr(programs, "_export", lambda *a: pytest.fail("traced again"))
    again = programs.cached_call("t", model, args(), (3,), key={"config": 1})
    assert isinstance(again, Out) and again.name == "k=3"
    for x, y in zip(jax.tree.leaves(first), jax.tree.leaves(again)):
        np.testing.assert_array_equal(x, y)
    np.testing.assert_allclose(again.scaled["b"], [3.0, 6.0])
    np.testing.assert_allclose(again.scaled["r"], jnp.linalg.qr(args()[0]["a"])[1])


def test_ready_is_called_once_the_program_is_traced_or_loaded(folder):
    """``ready`` (a sweep starts building its next programs there) runs once a call: when the program is built,
    after its trace and before XLA compiles and keeps it; when it is loaded, after loading. Without kept
    programs it is not called (tests below)."""
    calls = []
    for _ in range(2):  # built, then loaded
        out = programs.cached_call("t", model, args(), (3,), key="ready",
                                   ready=lambda: calls.append(len(list(folder.glob("t-*.bin")))))
        assert float(out.total) == pytest.approx(3 * 66.0)
    assert calls == [0, 1]


def test_another_key_static_value_or_shape_is_another_program(folder):
    programs.cached_call("t", model, args(), (3,), key={"config": 1})
    programs.cached_call("t", model, args(), (3,), key={"config": 2})
    out = programs.cached_call("t", model, args(), (4,), key={"config": 1})
    assert out.name == "k=4" and float(out.total) == pytest.approx(4 * 66.0)
    bigger = ({"a": jnp.ones((5, 3)), "b": jnp.ones(2)},)
    assert float(programs.cached_call("t", model, bigger, (3,), key={"config": 1}).total) == pytest.approx(45.0)
    assert len(list(folder.glob("t-*.bin"))) == 4


def test_a_quick_program_is_another_program_compiled_without_llvm_optimisation(folder, monkeypatch):
    compiled = []

    def compile_fresh(lowered, options):
        compiled.append(options)
        return lowered.compile(options), False

    monkeypatch.setattr(programs, "_compile_fresh", compile_fresh)
    slow = programs.cached_call("t", model, args(), (3,), key="k")
    quick = programs.cached_call("t", model, args(), (3,), key="k", quick=True)
    # each built; the quick one with XLA's optimisation level 0 (on the CPU, where it was measured)
    assert compiled == [{}, programs.QUICK if jax.default_backend() == "cpu" else {}]
    assert len(list(folder.glob("t-*.bin"))) == 2
    for x, y in zip(jax.tree.leaves(slow), jax.tree.leaves(quick)):
        np.testing.assert_allclose(x, y, rtol=1e-13)


def test_a_program_quick_with_the_classic_emitters_is_quick_only_where_the_process_uses_them(folder, monkeypatch):
    """``quick="classic"`` (a fit's solver): optimisation level 0 where XLA_FLAGS select XLA:CPU's classic
    emitters (a CLI fit run), XLA's default elsewhere; the flags are part of the program's key."""
    chosen, paths = [], set()
    for flags in ("", "--xla_cpu_use_fusion_emitters=true", "--a=1 --xla_cpu_use_fusion_emitters=false"):
        monkeypatch.setenv("XLA_FLAGS", flags)
        path, *_, options = programs._locate("t", args(), (3,), "k", "classic")
        chosen.append(options)
        paths.add(path)
    cpu = jax.default_backend() == "cpu"
    assert chosen == [{}, {}, programs.QUICK if cpu else {}] and len(paths) == 3


def test_a_kept_program_loads_and_runs_where_there_are_two_devices(tmp_path):
    """A kept executable runs on the one device a jit runs on, also where jax has several (loaded with its
    defaults, it expected a shard on each: every warm call failed with ``jax_num_cpu_devices = 2``)."""
    script = ("import sys, jax; jax.config.update('jax_num_cpu_devices', 2)\n"
              "from hullopt.app.cli import configure_jax; configure_jax()\n"
              "import jax.numpy as jnp\n"
              "from hullopt.study import _programs as P\n"
              "out = P.cached_call('two', lambda a, k: jnp.sum(a) * k, (jnp.arange(4.0),), (3,), key='k')\n"
              "print(float(out), len(list(P.programs_dir().glob('two-*.bin'))))\n")
    env = dict(os.environ, HULLOPT_CACHE=str(tmp_path), TF_CPP_MIN_LOG_LEVEL="3")
    runs = [subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, timeout=300)
            for _ in range(2)]  # the first compiles and keeps it, the second loads it
    for p in runs:
        assert p.returncode == 0, p.stderr[-2000:]
        assert p.stdout.split() == ["18.0", "1"]


def test_a_corrupt_program_file_is_rebuilt(folder):
    programs.cached_call("t", model, args(), (3,), key="k")
    (path,) = folder.glob("t-*.bin")
    path.write_bytes(b"not a program")
    assert float(programs.cached_call("t", model, args(), (3,), key="k").total) == pytest.approx(3 * 66.0)
    assert path.read_bytes() != b"not a program"


def test_without_a_compilation_cache_nothing_is_kept(monkeypatch):
    monkeypatch.setattr(programs, "programs_dir", lambda: None)
    out = programs.cached_call("t", model, args(), (2,), key=0, ready=lambda: pytest.fail("no program to be ready"))
    assert float(out.total) == pytest.approx(132.0)


def test_programs_unused_for_30_days_are_pruned_when_one_is_written(folder):
    import os
    import time

    programs.cached_call("t", model, args(), (3,), key="used")
    (used,) = folder.glob("t-*.bin")
    stale = folder / "t-stale.bin"
    stale.write_bytes(b"old")
    month_ago = time.time() - 31 * 86400
    for p in (used, stale):
        os.utime(p, (month_ago, month_ago))
    programs.cached_call("t", model, args(), (3,), key="used")  # read: marks it in use
    programs.cached_call("t", model, args(), (3,), key="new")  # written: prunes
    assert used.exists() and not stale.exists() and len(list(folder.glob("t-*.bin"))) == 2


class Scaled(eqx.Module):
    factor: jax.Array
    how: str = eqx.field(static=True)


def scaled(m, x):
    return m.factor * x if m.how == "times" else m.factor + x


def test_numbers_are_arguments_and_what_is_baked_in_is_in_the_signature(folder, monkeypatch):
    """Another number in an array reuses the program (and is used: no stale constant); another static field
    or Python number in the arguments is another program, whatever the caller's key says."""
    x = jnp.arange(3.0)
    assert float(programs.cached_call("s", scaled, (Scaled(jnp.asarray(2.0), "times"), x), (), key="k")[2]) == 4.0
    exports = []
    real = programs._export
    monkeypatch.setattr(programs, "_export", lambda *a: exports.append(1) or real(*a))
    again = programs.cached_call("s", scaled, (Scaled(jnp.asarray(5.0), "times"), x), (), key="k")
    assert float(again[2]) == 10.0 and not exports
    assert float(programs.cached_call("s", scaled, (Scaled(jnp.asarray(5.0), "plus"), x), (), key="k")[2]) == 7.0
    assert float(programs.cached_call("s", lambda a, b: a * b, (3.0, x), (), key="k2")[2]) == 6.0
    assert float(programs.cached_call("s", lambda a, b: a * b, (4.0, x), (), key="k2")[2]) == 8.0
    assert len(exports) == 3


def test_a_configs_structure_blanks_its_numbers_but_not_its_design_solver_or_counts():
    from conftest import REPO
    from hullopt.study import structure
    from hullopt.study._config import load_config

    a, _ = load_config(REPO / "configs/pareto_bow.toml", ['constraints.sac_regions="<= 2 * parent"'])
    b, _ = load_config(REPO / "configs/pareto_bow.toml", ["targets.cb=0.66", "sweep.start=0.058", "hull.draft=10.5",
                                                         'constraints.sac_regions="<= 3 * parent"'])
    assert structure(a) == structure(b) and structure(a)["targets"]["cb"] == "#"
    assert structure(b)["constraints"]["sac_regions"] == "<= # * parent"
    for other in ("sweep.count=7", "solver.max_steps=81", "solver.fairness=0.2"):  # counts, what programs close over
        c, _ = load_config(REPO / "configs/pareto_bow.toml", ['constraints.sac_regions="<= 2 * parent"', other])
        assert structure(c) != structure(a), other


def test_the_assessment_traces_each_measure_once_with_the_parent_first_in_the_batch():
    """The parent is measured in the designs' batch, so each measure is traced (and compiled) once: traced apart,
    the parent doubled the assessment's program (the KCS sweep's first assessment 78 -> 54 s)."""
    from conftest import REPO

    from hullopt.study import load_study
    from hullopt.study._assess import _assess_program
    from hullopt.study._config import load_config

    cfg, _ = load_config(REPO / "tests/data/pareto_wigley.toml")
    prob = load_study(cfg).problem
    d, p0 = prob.design, prob.p0
    traced = []

    def volume_like(s, draft):
        traced.append(1)
        return jnp.sum(s.yz[..., 0]) * draft

    designs = jax.tree.map(lambda a: jnp.stack([a, a * 1.01]), p0)
    p, g_p, vals, groups = jax.jit(lambda p, ds: _assess_program({"v": volume_like}, d, p, ds))(p0, designs)
    assert len(traced) == 1
    assert float(p["v"]) == pytest.approx(float(volume_like(d.model(p0), d.draft)), rel=1e-12)
    assert vals["v"].shape == (2,) and float(vals["v"][0]) == pytest.approx(float(p["v"]), rel=1e-12)
    assert set(groups) == set(g_p) and all(np.shape(v) == (2,) for v in groups.values())
    assert all(float(g_p[k]) == pytest.approx(float(groups[k][0]), abs=1e-12) for k in g_p)


def test_the_parents_particulars_are_one_kept_program(folder, monkeypatch):
    """Holtrop–Mennen's inputs of the parent (the assessment's and the rescoring's) come from a kept program:
    evaluated op by op, a cold KCS sweep compiled ~400 small programs for them (13 s in each of the two)."""
    from conftest import REPO

    from hullopt.resistance import holtrop_hull
    from hullopt.study import load_study
    from hullopt.study._assess import parent_particulars
    from hullopt.study._config import load_config

    cfg, _ = load_config(REPO / "tests/data/pareto_wigley.toml")
    study = load_study(cfg)
    prob = study.problem
    hull = parent_particulars(prob, study.key)
    direct = holtrop_hull(prob.design.model(prob.p0), prob.design.draft)
    for name in ("L", "B", "T", "volume", "S", "cm", "cwp", "lcb", "ie"):
        assert float(getattr(hull, name)) == pytest.approx(float(getattr(direct, name)), rel=1e-11), name
    assert len(list(folder.glob("parent-particulars-*.bin"))) == 1
    monkeypatch.setattr(programs, "_export", lambda *a: pytest.fail("traced again"))
    assert float(parent_particulars(prob, study.key).S) == float(hull.S)


def _shapes(tree):
    return jax.tree.map(lambda a: jax.ShapeDtypeStruct(a.shape, a.dtype), tree)


def test_a_program_prepared_from_shapes_is_the_one_the_call_runs(folder, monkeypatch):
    built = []
    real = programs._program
    monkeypatch.setattr(programs, "_program", lambda path, *a: built.append(path) or real(path, *a))
    programs.prepare_call("t", model, _shapes(args()), (3,), key="k")  # the inputs' shapes only
    out = programs.cached_call("t", model, args(), (3,), key="k")
    assert len(built) == 1 and not programs._PENDING  # built once, on the preparing thread, and taken
    assert float(out.total) == pytest.approx(3 * 66.0) and out.name == "k=3"
    np.testing.assert_allclose(out.scaled["r"], jnp.linalg.qr(args()[0]["a"])[1])


def test_a_program_prepared_for_other_shapes_is_not_used(folder):
    programs.prepare_call("t", model, _shapes(({"a": jnp.ones((5, 3)), "b": jnp.ones(2)},)), (3,), key="k")
    ((path, pending),) = programs._PENDING.items()
    try:
        assert float(programs.cached_call("t", model, args(), (3,), key="k").total) == pytest.approx(3 * 66.0)
        assert pending.result() is not None  # the guess was built all the same, and kept for its shapes
        assert len(list(folder.glob("t-*.bin"))) == 2
    finally:
        programs._PENDING.pop(path, None)


def test_a_prepared_program_that_fails_raises_in_the_call(folder):
    def broken(p, k):
        raise ValueError(f"no model for k={k}")

    programs.prepare_call("bad", broken, _shapes(args()), (3,), key="k")
    with pytest.raises(ValueError, match="no model for k=3"):
        programs.cached_call("bad", broken, args(), (3,), key="k")
    assert not programs._PENDING


def test_a_command_that_fails_after_preparing_its_program_leaves_none_prepared(cli, hulls, tmp_path, monkeypatch):
    """A mesh command prepares its program before it reads the file; when reading fails (here: a parameter
    the mesh does not take) the CLI drops the preparation, which a long-lived process (the tests, a notebook)
    would otherwise hold."""
    monkeypatch.setenv("HULLOPT_CACHE", str(tmp_path))
    prepared = []
    real = programs.prepare_call
    monkeypatch.setattr("hullopt.app.commands.hydro.prepare_call",
                        lambda *a, **k: prepared.append(a[0]) or real(*a, **k))
    code, _, err = cli("hydro", f"{hulls / 'wigley_openfoam.stl.gz'}?n=31&m=24&bogus=1", "--drafts", "1:2:3")
    assert code == 2 and "bogus" in err
    assert prepared == ["hydrostatic_table"] and not programs._PENDING


@pytest.mark.parametrize("command", ["hydro", "stability"])
def test_the_commands_build_their_program_while_a_mesh_is_read(command, cli, hulls, tmp_path, monkeypatch):
    from hullopt.study import load_hull, sections_like

    spec = f"{hulls / 'wigley_openfoam.stl.gz'}?scale=2&shift=1,0,0.125&n=31&m=24"  # a 2 m model, AP and keel at 0
    like = sections_like(spec)
    assert sections_like("builtin:wigley?L=100&B=10&T=6.25&D=10") is None  # quick to load: nothing to overlap
    monkeypatch.setenv("HULLOPT_CACHE", str(tmp_path))  # nothing kept yet: the sections and programs
    hull = load_hull(spec)
    assert jax.tree.structure(like) == jax.tree.structure(hull.sections)
    assert _shapes(jax.tree.map(jnp.asarray, hull.sections)) == like
    built = []
    real = programs._program
    monkeypatch.setattr(programs, "_program", lambda *a: built.append(threading.current_thread().name) or real(*a))
    draft = float(np.asarray(hull.sections.yz[..., 1]).max()) / 2
    args = (["--drafts", f"{draft / 2}:{draft}:3"] if command == "hydro" else
            ["--displacement", "0.002", "--kg", f"{draft}", "--heels", "0:60:4"])
    code, out, err = cli(command, spec, *args, "--json")
    assert code in (0, 4), err
    # one program, built on the thread that prepared it while the mesh was read, and taken by the call
    assert built == [f"prepare-{'hydrostatic_table' if command == 'hydro' else 'stability'}"]
    # the same output as a call that builds its program from the real sections (nothing prepared, nothing kept)
    monkeypatch.setattr(f"hullopt.app.commands.{command}.sections_like", lambda spec: None)
    monkeypatch.setenv("HULLOPT_CACHE", str(tmp_path / "unprepared"))
    again = cli(command, spec, *args, "--json")
    assert again[0] == code and again[1] == out
    assert built[1:] == ["MainThread"]


def test_stack_params_puts_each_design_on_a_leading_axis():
    from conftest import REPO

    from hullopt.study import load_study, stack_params
    from hullopt.study._config import load_config

    cfg, _ = load_config(REPO / "tests/data/pareto_wigley.toml")
    p0 = load_study(cfg).problem.p0
    p1 = jax.tree.map(lambda a: np.asarray(a) + 1.0, p0)
    stacked = stack_params([p0, p1])
    for a, b, s in zip(jax.tree.leaves(p0), jax.tree.leaves(p1), jax.tree.leaves(stacked)):
        assert isinstance(s, np.ndarray) and s.dtype == np.float64 and s.shape == (2, *np.shape(a))
        np.testing.assert_array_equal(s[0], a)
        np.testing.assert_array_equal(s[1], b)


def test_a_sweep_prepares_the_very_programs_its_designs_then_take(folder, monkeypatch):
    """``Pareto.prepare`` (while the chunks solve) asks for the programs that the assessment, the rescoring and the
    designs' outcomes then call with the real designs: the same files, so none is built twice."""
    from conftest import REPO

    from hullopt.study import _study, load_study, stack_params
    from hullopt.study._assess import assess_program
    from hullopt.study._config import load_config
    from hullopt.study._rescore import rescore_program

    def where(name, fn, args, static, key, quick=False):
        return programs._locate(name, args, static, key, quick)[0]

    prepared = []
    monkeypatch.setattr(_study, "programs_dir", programs.programs_dir)
    monkeypatch.setattr(_study, "prepare_call", lambda *call: prepared.append(where(*call)))
    cfg, _ = load_config(REPO / "tests/data/pareto_wigley.toml")
    study = load_study(cfg)
    prob = study.problem
    study.prepare(2)
    moved = [jax.tree.map(lambda a, k=k: np.asarray(a) + 0.01 * k, prob.p0) for k in (1, 2)]  # two designs
    taken = [where(*assess_program(cfg, prob, stack_params(moved), study.key)),
             where(*rescore_program(cfg, prob, stack_params(moved), study.key)[0]),
             where(*_study._outcomes_program(study, stack_params([prob.p0, *moved])))]
    assert prepared == taken and len(set(taken)) == 3


def test_a_kept_program_bypasses_the_compilation_cache_on_its_own_thread_only(folder):
    """A program kept with its executable is compiled fresh (not loaded from jax's cache) on its thread, while
    other threads' compiles meanwhile (a sweep's chunks beside its prepared programs) keep using the cache."""
    from jax._src import compilation_cache as cc

    programs.cached_call("t", model, args(), (3,), key="fresh")
    assert hasattr(cc.is_cache_used, "bypassed")  # jax's check, wrapped once
    check = programs._bypassable(lambda backend: True)  # as it answers with the cache on
    inside, done = threading.Event(), threading.Event()
    seen = []

    def keeping():  # a thread in the middle of compiling a program it keeps
        programs._BYPASS.on = True
        seen.append(check(None))
        inside.set()
        done.wait(10)
        programs._BYPASS.on = False
        seen.append(check(None))

    thread = threading.Thread(target=keeping)
    thread.start()
    inside.wait(10)
    assert check(None)  # the main thread meanwhile: the cache used
    done.set()
    thread.join()
    assert seen == [False, True]


def test_a_warm_fair_traces_nothing_and_new_numbers_keep_its_programs(cli, tmp_path, monkeypatch):
    """``hullopt fair`` runs its solve, its frame lines and its report's measures as kept programs: a second
    call with another draft, move cap and pull traces none of them, and faires to its own numbers (the held
    displacement is the new draft's)."""
    monkeypatch.setenv("HULLOPT_CACHE", str(tmp_path))
    spec = "builtin:wigley?L=100&B=10&T=6.25&D=6.25&n=9&m=9"
    base = ("fair", spec, "--stations", "7", "--waterlines", "5", "--noise", "0.05", "--json")
    built = []
    real = programs._export
    monkeypatch.setattr(programs, "_export", lambda *a: built.append(a[0]) or real(*a))
    code, out, err = cli(*base)
    assert code in (0, 5), err
    assert len(built) == 4, built  # fairing-lines, fairing-frames, fairing, fair-measures
    monkeypatch.setattr(programs, "_export", lambda *a: pytest.fail("traced again for new numbers"))
    code2, out2, err2 = cli(*base, "--draft", "5", "--max-move", "0.4", "--proximity", "0.01")
    assert code2 in (0, 5), err2
    first, second = json.loads(out), json.loads(out2)
    assert first["draft"] == 6.25 and second["draft"] == 5.0 and second["move_cap"] == 0.4
    assert second["volume_before"] < 0.85 * first["volume_before"]
