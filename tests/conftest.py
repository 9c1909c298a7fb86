"""Test set-up: float64 and strict dtype promotion, as the CLI runs (never a side effect of importing), and
every annotation of the package checked (jaxtyping's import hook with beartype)."""

import ctypes
import subprocess
import sys
from pathlib import Path

import jax
import jaxtyping
import pytest

# Every annotation in hullopt (Module fields, arguments, returns: dtypes and shapes) is checked while the tests
# run: jaxtyping's import hook with beartype, installed before anything imports hullopt. is_pep484_tower: an int
# passes for a float, as PEP 484 has it (lengths are annotated float; callers write 100).
jaxtyping.install_import_hook("hullopt", "beartype.beartype(conf=beartype.BeartypeConf(is_pep484_tower=True))")

import hullopt.app.cli  # noqa: E402,F401  XLA's flags as the CLI sets them, before jax starts its backend

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_numpy_dtype_promotion", "strict")


REPO = Path(__file__).resolve().parents[1]
HULLS = REPO / "examples" / "hulls"  # real hull meshes, with their provenance in SOURCES.md
DATA = REPO / "tests" / "data"  # reference tables, with their provenance in SOURCES.md


@pytest.fixture(scope="session")
def hulls() -> Path:
    """The example hull files (``examples/hulls``: DTC, KCS, KVLCC2, DTMB 5415, Wigley, Series 60)."""
    return HULLS


# The closed real hull meshes in examples/hulls: file, hull-spec parameters (scale to full size, Lpp [m]) and the
# design draft [m] (DTC: el Moctar et al. 2012; KCS: SIMMAN/Tokyo 2015; DTMB 5415: the model-basin's 6.15 m)
MESH_HULLS = {
    "dtc": ("DTC-scaled.stl.gz", "scale=59.407&lpp=355", 14.5),
    "kcs": ("kcs_model_closed_from_igs.stl.gz", "scale=31.6&lpp=230", 10.8),
    "dtmb5415": ("dtmb5415_navaltoolbox_fullscale.stl.gz", "lpp=142", 6.15),
}


@pytest.fixture(scope="session")
def dtmb5415() -> tuple[str, float]:
    """The DTMB 5415 (full scale, a closed coarse mesh with a sonar dome): its hull spec and design draft [m]."""
    name, params, draft = MESH_HULLS["dtmb5415"]
    return f"{HULLS / name}?{params}", draft


# what the CLI's configure_jax sets for its process: every compile written to the persistent cache
CACHE_OPTIONS = ("jax_compilation_cache_dir", "jax_persistent_cache_min_compile_time_secs",
                 "jax_persistent_cache_min_entry_size_bytes")


@pytest.fixture(autouse=True)
def _compilation_cache(tmp_path_factory, monkeypatch):
    """CLI calls in tests use a throw-away persistent compilation cache, never the user's; one folder for the
    whole session (shared by the xdist workers), so a program compiled by one test is loaded by the next. The
    CLI's cache options hold for its call only: a worker that ran one would otherwise serialise every later
    test's compiles, eager operations included, and XLA has crashed a worker inside that write (late in the
    slow suite, in tests that pass alone)."""
    monkeypatch.setenv("HULLOPT_CACHE", str(tmp_path_factory.getbasetemp().parent / "jax-cache"))
    before = {name: getattr(jax.config, name) for name in CACHE_OPTIONS}
    yield
    for name, value in before.items():
        jax.config.update(name, value)


_LIBC = ctypes.CDLL(None) if sys.platform.startswith("linux") else None


@pytest.fixture(autouse=True)
def _return_freed_memory():
    """After each test, hand the memory glibc keeps for reuse back to the system: a worker that ran the panel
    methods' grids otherwise holds ~3 GB it no longer uses (measured), and two such workers crowd 24 GiB."""
    yield
    if _LIBC is not None and hasattr(_LIBC, "malloc_trim"):
        _LIBC.malloc_trim(0)


@pytest.fixture
def cli(capsys):
    """Run the CLI in-process: ``code, stdout, stderr = cli("hydro", HULL, "--json")``."""
    from hullopt.app.cli import main

    def run(*args):
        code = main([str(a) for a in args])
        out = capsys.readouterr()
        return code, out.out, out.err

    return run


@pytest.fixture
def cli_process():
    """Run the CLI as its own process, as a user types it: ``code, stdout, stderr = cli_process("run", CFG)``.
    For the longest end-to-end runs: a fresh process holds none of the test worker's programs, and a crash in
    XLA fails one test instead of killing the worker (late in the slow suite, the Pareto sweep aborted twice in
    ``executable.serialize()`` inside a worker that had run ~90 tests, while it passes alone; pytest-xdist then
    hung until CI's limit). A run past ``timeout`` seconds fails the test rather than hold CI."""

    def run(*args, timeout=1800):
        p = subprocess.run([sys.executable, "-m", "hullopt", *map(str, args)], capture_output=True, text=True,
                           timeout=timeout)
        return p.returncode, p.stdout, p.stderr

    return run
