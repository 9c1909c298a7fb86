"""Box bounds by a smooth change of variables, so unconstrained solvers respect them exactly."""

from __future__ import annotations

import jax
import jax.numpy as jnp


def to_unbounded(p, lower, upper):
    """``p`` inside ``(lower, upper)`` → ``u`` with ``p = lower + (upper − lower)(1 + tanh u)/2`` (per leaf).

    Parameters
    ----------
    p : pytree of Array
        Parameters (any units), each leaf strictly inside its bounds (values on a bound are clipped just inside).
    lower, upper : pytree of Array
        Bounds in the units of ``p``, same structure, broadcasting with its leaves.

    Returns
    -------
    pytree of Array
        ``u`` (dimensionless), the structure and shapes of ``p``.
    """

    def leaf(p, lo, hi):
        s = jnp.clip(2.0 * (p - lo) / (hi - lo) - 1.0, -1.0 + 1e-12, 1.0 - 1e-12)
        return jnp.arctanh(s)

    return jax.tree.map(leaf, p, lower, upper)


def from_unbounded(u, lower, upper):
    """Inverse of :func:`to_unbounded`: always strictly inside the bounds, smooth in ``u``.

    Parameters
    ----------
    u : pytree of Array
        Unbounded variables (dimensionless).
    lower, upper : pytree of Array
        Bounds, same structure, broadcasting with the leaves of ``u``.

    Returns
    -------
    pytree of Array
        ``p`` in the units of the bounds, the structure and shapes of ``u``.
    """
    return jax.tree.map(lambda u, lo, hi: lo + 0.5 * (hi - lo) * (1.0 + jnp.tanh(u)), u, lower, upper)

