"""Modifications of a hull: pure ``(Sections, p) -> Sections`` maps, differentiable in ``p``.

:func:`blunt_bow` is the simple bow-bluntness modification that drives the patent's program
(JP2009-286166 claim 6, :func:`hullopt.waves.select_lower_k_aw`); any other pure map of the same signature (a
feature-curve deformation, a Lackenby shift) can take its place there.
"""

from __future__ import annotations

import jax.numpy as jnp
from jaxtyping import Array, ArrayLike

from ..geometry import Sections


def blunt_bow(sections: Sections, p: ArrayLike, x_start: ArrayLike | None = None) -> Sections:
    """Blunt (``p > 0``) or sharpen (``−1 < p < 0``) the entrance of a hull.

    Half-breadths y are scaled by 1 + p·sin²(πξ/2), ξ = (x − x_start)/(x_fwd − x_start) ∈ [0, 1] from
    ``x_start`` to the forward-most station. Stations aft of ``x_start`` are unchanged and the scaling starts
    with zero slope, so the hull stays smooth; heights and station positions are kept, and a stem (y = 0)
    stays a stem. Near the stem the entrance half-angle E becomes atan((1 + p)·tan E). Pure and
    differentiable in ``p`` (jit/grad/vmap).

    Parameters
    ----------
    sections : Sections
        The hull (x forward from the AP, m).
    p : float or scalar array
        Bluntness parameter, dimensionless; 0 leaves the hull unchanged, ``p > −1`` keeps half-breadths
        positive.
    x_start : float, optional
        Where the modification starts, m from the AP; default midship (``lpp / 2``).

    Returns
    -------
    Sections
        The modified hull, same stations and shapes as ``sections``.
    """
    x = sections.x
    x0 = 0.5 * sections.lpp if x_start is None else jnp.asarray(x_start, dtype=x.dtype)
    xi = jnp.clip((x - x0) / (x[-1] - x0), 0.0, 1.0)
    f: Array = 1.0 + p * jnp.sin(0.5 * jnp.pi * xi) ** 2
    yz = sections.yz.at[..., 0].multiply(f[:, None])
    return Sections(x=x, yz=yz, lpp=sections.lpp)
