"""Wind forces and moments, true-to-relative wind, and the ISO 15016 wind added resistance.

Signs as in :mod:`._coefficients`: X forward +, Y to port +, N bow to port +, K heel to port +; wind angles
are where the wind comes from, 0 = ahead, positive from starboard.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._types import Angles, Density, Speeds
from ..constants import RHO_AIR
from ..geometry import safe_sqrt
from ._coefficients import DEFAULT_SHIP_TYPE, Coefficients, wind_coefficients
from ._variables import WindVariables



class WindLoads(eqx.Module):
    """X, Y [N] and N, K [N·m] (signs in the module docstring)."""

    X: Float[Array, "*angles"]
    Y: Float[Array, "*angles"]
    N: Float[Array, "*angles"]
    K: Float[Array, "*angles"]


def relative_wind(ship_speed: Speeds, wind_speed: Speeds, wind_angle: Angles) -> tuple[Array, Array]:
    """Relative wind speed [m/s] and angle ψ [rad] from the ship's speed through the air mass [m/s] and the
    true wind's speed [m/s] and angle off the bow [rad] (where it comes from; 0 = ahead, + from starboard).

    With compass directions pass ``wind_angle = wind_from − heading``. The ship meets the air at
    ``V_T(−cos β, sin β) − (U, 0)``, so ``V_R = √(U² + V_T² + 2 U V_T cos β)`` and
    ``ψ = atan2(V_T sin β, V_T cos β + U)``. Finite gradients in still air (then ψ = 0).

    Parameters
    ----------
    ship_speed : float or Array
        Ship speed U through the air mass [m/s], ahead positive.
    wind_speed : float or Array
        True wind speed V_T [m/s]; broadcasts.
    wind_angle : float or Array
        True wind angle β off the bow [rad]; broadcasts.

    Returns
    -------
    speed : Array
        Relative wind speed V_R [m/s], shape of the broadcast inputs.
    angle : Array
        Relative wind angle ψ [rad] in (−π, π], same shape.
    """
    u, vt, beta = (jnp.asarray(a, dtype=float) for a in (ship_speed, wind_speed, wind_angle))
    ax, ay = vt * jnp.cos(beta) + u, vt * jnp.sin(beta)
    sq = ax * ax + ay * ay
    ok = sq > 0
    speed = safe_sqrt(sq, ok)
    angle = jnp.where(ok, jnp.arctan2(jnp.where(ok, ay, 0.0), jnp.where(ok, ax, 1.0)), 0.0)
    return speed, angle


def wind_loads(v: WindVariables, c: Coefficients, speed: Speeds, rho_air: Density = RHO_AIR) -> WindLoads:
    """Loads for coefficients ``c`` at a relative wind ``speed`` [m/s]: X = qA_T C_X, Y = qA_L C_Y,
    N = qLA_L C_N, K = qA_L H_L C_K with q = ½ρU².

    Parameters
    ----------
    v : WindVariables
        The explanatory variables (:func:`wind_variables`, SI): A_T, A_L [m²], L, H_L [m].
    c : Coefficients
        Wind-load coefficients (:func:`wind_coefficients`), shape of its ``psi``.
    speed : float or Array
        Relative wind speed [m/s]; broadcasts with the coefficients.
    rho_air : float
        Air density [kg/m³].

    Returns
    -------
    WindLoads
        X, Y [N] and N, K [N·m], shape of the broadcast ``c`` and ``speed``.
    """
    q = 0.5 * rho_air * jnp.asarray(speed, dtype=float) ** 2
    return WindLoads(q * v.A_T * c.cx, q * v.A_L * c.cy, q * v.L * v.A_L * c.cn, q * v.A_L * v.H_L * c.ck)


def wind_added_resistance(v: WindVariables, ship_speed: Speeds, wind_speed: Speeds, wind_angle: Angles,
                          model: str = "fujiwara2005", *, rho_air: Density = RHO_AIR,
                          ship: str = DEFAULT_SHIP_TYPE) -> Array:
    """ISO 15016 wind added resistance ΔR_AA [N] (positive = more resistance) for a ship speed [m/s] and a
    true wind (speed [m/s], angle off the bow [rad]):

    ``ΔR_AA = ½ρ A_T (C_AA(ψ_R) V_R² − C_AA(0) U²)`` with C_AA = −C_X of ``model``; the second term, the
    still-air resistance at the ship's own speed, is already in the calm-water resistance.

    Parameters
    ----------
    v : WindVariables
        The explanatory variables (:func:`wind_variables`, SI).
    ship_speed : float or Array
        Ship speed U [m/s], ahead positive.
    wind_speed : float or Array
        True wind speed [m/s]; broadcasts.
    wind_angle : float or Array
        True wind angle off the bow [rad] (where it comes from, 0 = ahead, + from starboard); broadcasts.
    model : str
        Coefficient model, one of ``MODELS`` (see :func:`wind_coefficients`).
    rho_air : float
        Air density [kg/m³].
    ship : str
        Blendermann's ship type (``model="blendermann"`` only).

    Returns
    -------
    Array
        ΔR_AA [N], shape of the broadcast inputs.
    """
    vr, psi = relative_wind(ship_speed, wind_speed, wind_angle)
    caa = -wind_coefficients(v, jnp.stack([psi, jnp.zeros_like(psi)]), model, ship=ship).cx
    u = jnp.asarray(ship_speed, dtype=float)
    return 0.5 * rho_air * v.A_T * (caa[0] * vr**2 - caa[1] * u**2)
