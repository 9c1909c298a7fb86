"""Test set-up: float64 and strict dtype promotion, as the CLI runs (never a side effect of importing), and
every annotation of the package checked (jaxtyping's import hook with beartype)."""

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
    """The example hull files (``examples/hulls``: DTC, KCS, KVLCC2, DTMB 5415, Wigley)."""
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


@pytest.fixture(autouse=True)
def _compilation_cache(tmp_path_factory, monkeypatch):
    """CLI calls in tests use a throw-away persistent compilation cache, never the user's; one folder for the
    whole session (shared by the xdist workers), so a program compiled by one test is loaded by the next."""
    monkeypatch.setenv("HULLOPT_CACHE", str(tmp_path_factory.getbasetemp().parent / "jax-cache"))


@pytest.fixture
def cli(capsys):
    """Run the CLI in-process: ``code, stdout, stderr = cli("hydro", HULL, "--json")``."""
    from hullopt.app.cli import main

    def run(*args):
        code = main([str(a) for a in args])
        out = capsys.readouterr()
        return code, out.out, out.err

    return run
