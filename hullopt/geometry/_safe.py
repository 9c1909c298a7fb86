"""Division and roots with finite gradients everywhere: the double-``where`` idiom, written once.

``jnp.where(ok, num / den, 0)`` alone is not enough: where ``ok`` is false the untaken branch still divides
by ``den`` (0, say), and its infinite or NaN derivative poisons the gradient (0 · inf = NaN). Replacing the
denominator by 1 there first keeps both branches finite.
"""

from __future__ import annotations

import jax.numpy as jnp
from jaxtyping import Array


def safe_div(num, den, ok=None, fill=0.0) -> Array:
    """``num / den`` where ``ok`` (default ``den != 0``), else ``fill``, with finite gradients on both
    branches."""
    if ok is None:
        ok = den != 0
    return jnp.where(ok, num / jnp.where(ok, den, 1.0), fill)


def safe_sqrt(sq, ok=None) -> Array:
    """``√sq`` where ``ok`` (default ``sq > 0``), else 0, with finite gradients (also at 0)."""
    if ok is None:
        ok = sq > 0
    return jnp.where(ok, jnp.sqrt(jnp.where(ok, sq, 1.0)), 0.0)


def safe_norm(v) -> Array:
    """Euclidean norm along the last axis, with a finite gradient (0) at the zero vector."""
    return safe_sqrt(jnp.sum(v * v, axis=-1))
