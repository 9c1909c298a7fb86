"""Built-in analytic hulls for examples and tests: a box barge and the Wigley hull."""

from __future__ import annotations

import jax.numpy as jnp
import numpy as np

from ..errors import HullError
from ..geometry import Sections


def _positive(**kw: float) -> None:
    for name, v in kw.items():
        if not (np.isfinite(v) and v > 0):
            raise HullError(f"parameter {name} must be a positive number, got {v}")


def box(L: float, B: float, D: float, n: int = 3) -> Sections:
    """Rectangular barge of length ``L``, breadth ``B`` and depth ``D`` [m], AP at its aft end.

    Each half-section is three points: keel ``(0, 0)``, bilge corner ``(B/2, 0)``, deck edge ``(B/2, D)``.

    Parameters
    ----------
    L, B, D : float
        Length [m] (also Lpp), breadth [m] and depth [m], each positive.
    n : int
        Number of equally spaced stations from 0 to ``L`` (3 by default).

    Returns
    -------
    Sections
        ``x (n,)`` [m from the AP], ``yz (n, 3, 2)`` [m], ``lpp = L``.
    """
    _positive(L=L, B=B, D=D)
    x = jnp.linspace(0.0, L, n)
    sec = jnp.array([[0.0, 0.0], [B / 2, 0.0], [B / 2, D]])
    return Sections(x=x, yz=jnp.broadcast_to(sec, (n, 3, 2)), lpp=jnp.asarray(float(L)))


def wigley(L: float, B: float, T: float, D: float, n: int = 81, m: int = 201) -> Sections:
    """The Wigley hull ``y = (B/2)(1 − (2ξ/L)²)(1 − (ζ/T)²)`` below the design draft ``T``, with
    vertical sides from ``T`` up to the deck at ``D`` (ξ from midship, ζ depth below the waterline).

    ``n`` stations (odd, equally spaced, so Simpson's rule is exact for its quadratic area curve) and ``m``
    points on the curved part of each section (the polyline's area error is ≈ 1/(4(m−1)²) relative).

    Parameters
    ----------
    L, B, T, D : float
        Length [m] (also Lpp), breadth [m], design draft [m] and depth [m], each positive, ``D ≥ T``.
    n : int
        Number of equally spaced stations from 0 to ``L`` (81 by default; odd for exact Simpson sums).
    m : int
        Points on each section's curved part from the keel to ``T`` (201 by default).

    Returns
    -------
    Sections
        ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m], or ``(n, m+1, 2)`` with the deck-edge point where
        ``D > T``; ``lpp = L``.
    """
    _positive(L=L, B=B, T=T, D=D)
    if D < T:
        raise HullError(f"parameter D (depth {D}) must be at least T (draft {T})")
    x = jnp.linspace(0.0, L, n)
    z = jnp.linspace(0.0, T, m)
    beam = (B / 2) * (1.0 - (2.0 * (x - L / 2) / L) ** 2)  # (n,)
    y = beam[:, None] * (1.0 - ((T - z) / T) ** 2)[None, :]
    yz = jnp.stack([y, jnp.broadcast_to(z, y.shape)], axis=-1)
    if D > T:
        deck = jnp.stack([beam, jnp.full_like(beam, D)], axis=-1)[:, None, :]
        yz = jnp.concatenate([yz, deck], axis=1)
    return Sections(x=x, yz=yz, lpp=jnp.asarray(float(L)))


BUILTINS = {"box": (box, ("L", "B", "D")), "wigley": (wigley, ("L", "B", "T", "D"))}
