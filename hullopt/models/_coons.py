"""Sections from a Coons-patch surface (:class:`~hullopt.geometry.CoonsSurface`, seed 001): the hull that the
fairing's offsets describe, as :class:`~hullopt.geometry.Sections` for hydrostatics and the other analyses."""

from __future__ import annotations

import jax.numpy as jnp
from jaxtyping import ArrayLike

from ..geometry import CoonsSurface, Sections


def coons_sections(surface: CoonsSurface, lpp: ArrayLike, n_stations: int = 121, n_points: int = 81) -> Sections:
    """Sample a Coons-patch surface into sections.

    ``n_stations`` equally spaced stations from ``surface.x[0]`` to ``surface.x[-1]`` (made odd, for
    Simpson's rule) and ``n_points`` equally spaced heights from ``surface.z[0]`` to ``surface.z[-1]``;
    half-breadths are clipped at ``y = 0`` and each section is closed at the keel with a centreline point, as
    the offset-table model does. Pure and differentiable in the surface (jit/grad/vmap).

    Parameters
    ----------
    surface : CoonsSurface
        The hull's port side ``y = f(x, z)`` [m] (:func:`hullopt.geometry.coons_surface`).
    lpp : float
        Length between perpendiculars [m].
    n_stations : int, optional
        Number of stations (static); an even number is raised by one.
    n_points : int, optional
        Number of heights per station (static); each section has ``n_points + 1`` points with the keel point.

    Returns
    -------
    Sections
        ``x (n_stations,)`` [m from the AP], ``yz (n_stations, n_points + 1, 2)`` [m], ``lpp`` [m].
    """
    n_stations += 1 - n_stations % 2
    xf = jnp.linspace(surface.x[0], surface.x[-1], n_stations)
    zf = jnp.linspace(surface.z[0], surface.z[-1], n_points)
    yy = jnp.maximum(surface(xf[:, None], zf[None, :]), 0.0)
    yz = jnp.stack([yy, jnp.broadcast_to(zf, yy.shape)], axis=-1)
    keel = jnp.stack([jnp.zeros_like(xf), jnp.full_like(xf, zf[0])], -1)
    return Sections(x=xf, yz=jnp.concatenate([keel[:, None], yz], axis=1), lpp=jnp.asarray(lpp, yy.dtype))
