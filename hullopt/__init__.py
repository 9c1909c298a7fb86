"""hullopt — a differentiable hull-form optimiser for naval architects, in JAX.

Enable float64 before use (``jax.config.update("jax_enable_x64", True)``); the CLI and the tests do.
Subpackages load on first use (``hullopt.hydro``, ``hullopt.models``…), so ``import hullopt`` stays light.
"""

import importlib

from .errors import HullError as HullError

__version__ = "0.1.0"
_SUBPACKAGES = ("geometry", "models", "hydro", "waves", "wind", "resistance", "fairing", "optimise", "drawing")


def __getattr__(name: str):
    if name in _SUBPACKAGES:
        return importlib.import_module(f"{__name__}.{name}")
    if name == "Sections":
        return importlib.import_module(f"{__name__}.geometry").Sections
    raise AttributeError(f"module 'hullopt' has no attribute {name!r}")
