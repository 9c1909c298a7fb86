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
