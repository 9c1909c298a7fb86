"""Division and roots with finite gradients everywhere: the double-``where`` idiom, written once.

``jnp.where(ok, num / den, 0)`` alone is not enough: where ``ok`` is false the untaken branch still divides
by ``den`` (0, say), and its infinite or NaN derivative poisons the gradient (0 · inf = NaN). Replacing the
denominator by 1 there first keeps both branches finite.
"""

from __future__ import annotations

import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float

from .._types import Mask, Reals


def safe_div(num: Reals, den: Reals, ok: Mask | None = None, fill: Reals = 0.0) -> Array:
    """``num / den`` where ``ok`` (default ``den != 0``), else ``fill``, with finite gradients on both
    branches.

    Parameters
    ----------
    num, den : array_like
        Numerator and denominator, broadcast together (any shapes, any unit).
    ok : array_like of bool, optional
        Where to divide, broadcast with ``num / den``; ``None`` means ``den != 0``.
    fill : float or array_like
        The value where ``ok`` is false (0 by default).

    Returns
    -------
    Array
        ``num / den`` or ``fill``, in the broadcast shape, unit of ``num / den``.
    """
    if ok is None:
        ok = den != 0
    return jnp.where(ok, num / jnp.where(ok, den, 1.0), fill)


def safe_sqrt(sq: Reals, ok: Mask | None = None) -> Array:
    """``√sq`` where ``ok`` (default ``sq > 0``), else 0, with finite gradients (also at 0).

    Parameters
    ----------
    sq : array_like
        The radicand (any shape, any unit).
    ok : array_like of bool, optional
        Where to take the root, broadcast with ``sq``; ``None`` means ``sq > 0``.

    Returns
    -------
    Array
        ``√sq`` where ``ok``, else 0; shape of ``sq`` (broadcast with ``ok``), unit the square root of ``sq``'s.
    """
    if ok is None:
        ok = sq > 0
    return jnp.where(ok, jnp.sqrt(jnp.where(ok, sq, 1.0)), 0.0)


def safe_norm(v: Float[ArrayLike, '... d']) -> Array:
    """Euclidean norm along the last axis, with a finite gradient (0) at the zero vector.

    Parameters
    ----------
    v : array_like, (..., d)
        Vectors along the last axis (any unit).

    Returns
    -------
    Array, (...)
        Their Euclidean lengths, in the unit of ``v``.
    """
    return safe_sqrt(jnp.sum(v * v, axis=-1))
