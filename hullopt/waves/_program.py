"""The patent's program (JP2009-286166 claim 6, fig. 18): compute Bf and K_AW of a hull, modify the hull,
recompute, and keep the hull with the lower K_AW. The modification is any pure ``(Sections, p) -> Sections``
passed in, e.g. :func:`hullopt.models.blunt_bow` (models own the hull modifications)."""

from __future__ import annotations

from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._types import Angle, Angles, Draft, Speed, Values
from ..constants import G
from ..geometry import Sections
from ._added_resistance import froude_number, k_aw, speed_coefficient
from ._waterline import bluntness


class ProgramResult(eqx.Module):
    """Candidates of the claim-6 program: index 0 is the original hull, 1… the modified ones.

    ``params`` (k,): modification parameters; ``bf``, ``c_u``, ``k_aw`` (k + 1,): Bf, C_U and the short-wave
    K_AW = Bf(1 + C_U·Fn) of each; ``fn``: Froude number; ``best``: index of the lowest K_AW;
    ``sections``: the chosen hull."""

    params: Float[Array, "k *p"]
    bf: Float[Array, "k+1 *H"]
    c_u: Float[Array, "k+1 *H"]
    k_aw: Float[Array, "k+1 *H"]
    fn: Float[Array, ""]
    best: int = eqx.field(static=True)
    sections: Sections


def evaluate_modifications(sections: Sections, modify: Callable[[Sections, Array], Sections], params: Values,
                           draft: Draft, speed: Speed, heading: Angles = 0.0, g: float = G,
                           smooth: float | None = None):
    """(Bf, C_U, K_AW) of the original hull and of ``modify(sections, p)`` for each ``p`` in ``params`` (k,)
    (one ``vmap``); each output is (k + 1,), the original first. Pure: jit/grad-able.

    Parameters
    ----------
    sections : Sections
        The original hull (offsets in metres).
    modify : callable
        Pure ``modify(sections, p) -> Sections``.
    params : Array
        Modification parameters, shape (k, ...) (one leading axis of k candidates).
    draft : float or Array
        Draft T [m] (scalar).
    speed : float or Array
        Ship speed U [m/s] (scalar).
    heading : float or Array
        Wave heading α [rad], 0 = head seas; any shape H.
    g : float
        Gravitational acceleration [m/s²].
    smooth : float or None
        Width τ of the soft maximum in C_U (:func:`speed_coefficient`); None: the exact maximum.

    Returns
    -------
    tuple of Array
        (Bf, C_U, K_AW, Fn): the first three dimensionless of shape (k + 1, *H), original first; Fn scalar.
    """
    fn = froude_number(speed, sections.lpp, g)

    def one(s):
        bf = bluntness(s, draft, heading)
        return bf, speed_coefficient(bf, smooth), k_aw(bf, fn, 1.0, smooth)

    base = one(sections)
    mods = jax.vmap(lambda p: one(modify(sections, p)))(jnp.asarray(params))
    return tuple(jnp.concatenate([b[None], m]) for b, m in zip(base, mods)) + (fn,)


def select_lower_k_aw(sections: Sections, modify: Callable[[Sections, Array], Sections], params: Values, draft: Draft,
                      speed: Speed, heading: Angle = 0.0, g: float = G) -> ProgramResult:
    """Claim 6: compute Bf, K_AW of ``sections`` (steps 1802–1803), modify it by ``modify(sections, p)`` for
    every ``p`` in ``params`` (1804), recompute (1806), compare and keep the hull with the lowest K_AW
    (1807–1808; the original on ties). ``modify`` may be any pure ``(Sections, p) -> Sections``, e.g.
    :func:`hullopt.models.blunt_bow` or a feature-curve deformation.

    Parameters
    ----------
    sections : Sections
        The original hull (offsets in metres).
    modify : callable
        Pure ``modify(sections, p) -> Sections``.
    params : float or Array
        Modification parameters, shape (k, ...) (a scalar is one candidate).
    draft : float or Array
        Draft T [m] (scalar).
    speed : float or Array
        Ship speed U [m/s] (scalar).
    heading : float or Array
        Wave heading α [rad], 0 = head seas (scalar).
    g : float
        Gravitational acceleration [m/s²].

    Returns
    -------
    ProgramResult
        Every candidate's Bf, C_U, K_AW (k + 1,), the index ``best`` and the chosen ``sections``.
    """
    params = jnp.atleast_1d(jnp.asarray(params, dtype=sections.yz.dtype))
    bf, c_u, kaw, fn = eqx.filter_jit(evaluate_modifications)(sections, modify, params, draft, speed, heading, g)
    best = int(jnp.argmin(kaw))  # argmin keeps the first (the original) on ties
    chosen = sections if best == 0 else modify(sections, params[best - 1])
    return ProgramResult(params=params, bf=bf, c_u=c_u, k_aw=kaw, fn=fn, best=best, sections=chosen)
