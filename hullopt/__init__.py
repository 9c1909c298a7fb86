"""hullopt — a differentiable hull-form optimiser for naval architects, in JAX.

Enable float64 before use (``jax.config.update("jax_enable_x64", True)``); the CLI and the tests do.
Subpackages load on first use (``hullopt.hydro``, ``hullopt.models``…), so ``import hullopt`` stays light.
"""

import importlib
import os

from .errors import HullError as HullError

# XLA:CPU's concurrency-optimised scheduler wedges its thread pool on the report's program of a sweep (every
# design's measures, strip-theory motions included, in one vmap): all workers parked, no CPU, forever (KCS bow
# sweep, jax 0.10.1: 3 of 3 runs hung at 3 or 6 designs; with the scheduler off 3 of 3 finished in ~33 s; single-
# threaded Eigen still hung). Off it also runs a batch of 256 designs faster (the design objective's vmap gain
# 2-6x -> 5-11x a design on 2 cores; benchmarks/README.md). Set here, for the CLI and the Python API alike: jax reads
# XLA_FLAGS when it starts its backend, so this holds where hullopt is imported before jax computes anything.
XLA_SCHEDULER_OFF = "--xla_cpu_enable_concurrency_optimized_scheduler=false"


def xla_flags(current: str) -> str:
    """``XLA_FLAGS`` with :data:`XLA_SCHEDULER_OFF` appended, unless the user's flags set that option."""
    if "xla_cpu_enable_concurrency_optimized_scheduler" in current:
        return current
    return f"{current} {XLA_SCHEDULER_OFF}".strip()


os.environ["XLA_FLAGS"] = xla_flags(os.environ.get("XLA_FLAGS", ""))

__version__ = "0.1.0"
_SUBPACKAGES = ("geometry", "models", "hydro", "waves", "wind", "resistance", "fairing", "optimise", "drawing")


def __getattr__(name: str):
    if name in _SUBPACKAGES:
        return importlib.import_module(f"{__name__}.{name}")
    if name == "Sections":
        return importlib.import_module(f"{__name__}.geometry").Sections
    raise AttributeError(f"module 'hullopt' has no attribute {name!r}")
