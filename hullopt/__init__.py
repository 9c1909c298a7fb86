"""hullopt — a differentiable hull-form optimiser for naval architects, in JAX.

Enable float64 before use (``jax.config.update("jax_enable_x64", True)``); the CLI and the tests do.
"""

from . import geometry as geometry
from . import hydro as hydro
from . import models as models
from .errors import HullError as HullError
from .geometry import Sections as Sections

__version__ = "0.1.0"
