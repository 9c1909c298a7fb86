"""Test set-up: float64 and strict dtype promotion, as the CLI runs (never a side effect of importing)."""

from pathlib import Path

import jax
import pytest

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_numpy_dtype_promotion", "strict")


def _find_shared() -> Path:
    """The reference folder: $HULLOPT_SHARED, else ``../shared`` beside the checkout, else /work/shared."""
    import os

    candidates = [os.environ.get("HULLOPT_SHARED"), Path(__file__).resolve().parents[1].parent / "shared",
                  "/work/shared"]
    for c in candidates:
        if c and (Path(c) / "hulls").is_dir():
            return Path(c)
    return Path(__file__).resolve().parents[1].parent / "shared"


SHARED = _find_shared()


@pytest.fixture(scope="session")
def shared() -> Path:
    """The read-only reference folder ``../shared`` (hulls, data, seeds)."""
    if not SHARED.is_dir():
        pytest.fail(f"reference folder {SHARED} is missing")
    return SHARED


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
