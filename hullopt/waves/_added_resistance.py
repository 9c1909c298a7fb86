"""Added resistance from wave reflection by the bluntness coefficient (JP2009-286166, NMRI; DESIGN.md §4).

R_AWR = ½ρgζ_a²·B·Bf·α_T·(1 + α_U),  K_AW = R_AWR / (½ρgζ_a²B) = Bf·α_T·(1 + α_U),
α_T = π²I₁²(k_e d)/(π²I₁²(k_e d) + K₁²(k_e d)), k_e = k(1 + Ω cos α)², Ω = ωU/g, k = ω²/g (patent eqs. 6–8),
1 + α_U = 1 + C_U·Fn, C_U = max(68 − 310·Bf(α), 10) (eqs. 9, 11, 12), Fn = U/√(g·Lpp).

Eq. 11 holds "for Bf > 0" and a reflected wave pushes the ship back, never forward: K_AW uses
Bf⁺ = max(Bf, 0) (:func:`positive_part`), so C_U is only ever evaluated at Bf ≥ 0 and the reflection part is
never negative. With the default lit range (``aft="exclude"``, :func:`~hullopt.waves.bluntness_of_waterline`)
Bf ≥ 0 already; the clamp matters for ``aft="include"``, whose lit run and transom make Bf < 0 in following
and quartering seas.

Shapes: ``omega`` (any shape W) and ``heading`` (any shape H) give per-wave results of shape W + H.
Units SI: ω [rad/s], U [m/s], α [rad] (0 = head seas), ζ_a [m], forces [N].
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._types import Angles, Draft, Frequencies, Lengths, Speed, Speeds, Values
from ..constants import G, RHO_SEA
from ..geometry import Sections
from ._bessel import alpha_t
from ._waterline import bluntness, bluntness_of_waterline, waterline
C_U_SLOPE, C_U_INTERCEPT, C_U_MIN = -310.0, 68.0, 10.0
BF_KINK = (C_U_INTERCEPT - C_U_MIN) / -C_U_SLOPE  # 58/310 = 0.1871: where C_U reaches its floor


def speed_coefficient(bf: Values, smooth: float | None = None) -> Array:
    """C_U = max(68 − 310·Bf, 10) (patent eqs. 11–12), or with ``smooth = τ`` the soft maximum
    10 + τ·softplus((58 − 310·Bf)/τ), which is C^∞, lies above the exact value by at most τ·ln 2 (at the
    kink Bf = 0.1871) and within 1 % of τ beyond |Bf − 0.1871| > 4.6τ/310 (τ = 1: ±0.015 in Bf).

    Parameters
    ----------
    bf : float or Array
        Bluntness coefficient Bf (dimensionless), any shape.
    smooth : float or None
        Width τ of the soft maximum (dimensionless, in units of C_U); None: the exact, kinked maximum.

    Returns
    -------
    Array
        C_U (dimensionless), shape of ``bf``.
    """
    bf = jnp.asarray(bf, dtype=float)
    lin = C_U_INTERCEPT + C_U_SLOPE * bf
    if smooth is None:
        return jnp.maximum(lin, C_U_MIN)
    return C_U_MIN + smooth * jax.nn.softplus((lin - C_U_MIN) / smooth)


def positive_part(bf, smooth: float | None = None) -> Array:
    """Bf⁺ = max(Bf, 0), or with ``smooth = τ`` the C¹ ramp 2b²/w − b³/w² on 0 < b < w = τ/310 (the Bf width
    of :func:`speed_coefficient`'s soft maximum; 0.0032 for τ = 1): exact for Bf ≤ 0 and Bf ≥ w, below the
    exact value by at most 4w/27 inside, so following seas stay exactly 0 and the gradient is finite."""
    bf = jnp.asarray(bf, dtype=float)
    if smooth is None:
        return jnp.maximum(bf, 0.0)
    w = smooth / -C_U_SLOPE
    b = jnp.clip(bf, 0.0, w)
    ramp = (2.0 - b / w) * b * b / w
    return jnp.where(bf >= w, bf, ramp)


def k_aw(bf: Values, fn: Values, alpha_T: Values = 1.0, smooth: float | None = None) -> Array:
    """K_AW = Bf⁺·α_T·(1 + C_U(Bf⁺)·Fn) (patent eq. 2 over ½ρgζ²B; claim 1), Bf⁺ = max(Bf, 0)
    (:func:`positive_part`: eq. 11 holds for Bf > 0 and the reflection part is never negative). With
    α_T = 1 this is the short-wave value the patent's tables list.

    Parameters
    ----------
    bf : float or Array
        Bluntness coefficient Bf of the waterline (dimensionless, 0 … 1; :func:`bluntness`).
    fn : float or Array
        Froude number U/√(g·Lpp) (:func:`froude_number`), ahead positive; broadcasts with ``bf``.
    alpha_T : float or Array
        Draft coefficient α_T (:func:`alpha_t`); 1 in short waves.
    smooth : float or None
        Width τ of the soft maximum in C_U (:func:`speed_coefficient`) and of the ramp in Bf⁺
        (:func:`positive_part`); None: the patent's kinked maximum and the exact max(Bf, 0).

    Returns
    -------
    Array
        K_AW, dimensionless (the added resistance over ½ρgζ²B), shape of ``bf``, ``fn`` broadcast.

    Examples
    --------
    C_U = max(68 − 310·Bf, 10): 37 at Bf = 0.1 and 10 at Bf = 0.5, so at Fn = 0.2 K_AW = 0.1·(1 + 37·0.2)
    = 0.84 and 0.5·(1 + 10·0.2) = 1.5:

    >>> import jax; jax.config.update("jax_enable_x64", True)
    >>> import jax.numpy as jnp
    >>> from hullopt.waves import k_aw
    >>> [round(float(k), 6) for k in k_aw(jnp.array([0.1, 0.5]), 0.2)]
    [0.84, 1.5]
    """
    bf = positive_part(bf, smooth)
    return bf * alpha_T * (1.0 + speed_coefficient(bf, smooth) * fn)


def froude_number(speed: Speeds, lpp: Lengths, g: float = G) -> Array:
    """Fn = U/√(g·Lpp).

    Parameters
    ----------
    speed : float or Array
        Ship speed U [m/s], any shape.
    lpp : float or Array
        Length between perpendiculars Lpp [m]; broadcasts with ``speed``.
    g : float
        Gravitational acceleration [m/s²].

    Returns
    -------
    Array
        Froude number Fn (dimensionless), shape of the broadcast inputs.
    """
    return jnp.asarray(speed, dtype=float) / jnp.sqrt(g * jnp.asarray(lpp, dtype=float))


def omega_from_wavelength(wavelength: Lengths, g: float = G) -> Array:
    """Deep-water circular frequency ω = √(2πg/λ) [rad/s] of waves of length λ [m].

    Parameters
    ----------
    wavelength : float or Array
        Wave length λ [m], any shape.
    g : float
        Gravitational acceleration [m/s²].

    Returns
    -------
    Array
        Circular frequency ω [rad/s], shape of ``wavelength``.
    """
    return jnp.sqrt(2.0 * jnp.pi * g / jnp.asarray(wavelength, dtype=float))


def encounter_wavenumber(omega: Frequencies, speed: Speeds, heading: Angles, g: float = G) -> Array:
    """k_e = k(1 + Ω cos α)² with k = ω²/g, Ω = ωU/g [1/m] (patent eq. 7). In following seas k_e → 0 where
    U cos α meets the phase speed (the reflected wave cannot catch the ship), and grows again beyond.

    Parameters
    ----------
    omega : float or Array
        Wave circular frequency ω [rad/s], any shape.
    speed : float or Array
        Ship speed U [m/s], ahead positive; broadcasts.
    heading : float or Array
        Wave heading α [rad], 0 = head seas; broadcasts.
    g : float
        Gravitational acceleration [m/s²].

    Returns
    -------
    Array
        Wavenumber k_e [1/m], shape of the broadcast inputs.
    """
    omega = jnp.asarray(omega, dtype=float)
    k = omega**2 / g
    return k * (1.0 + omega * speed / g * jnp.cos(heading)) ** 2


class NMRIResult(eqx.Module):
    """Added resistance by reflection, NMRI/patent formula. Shapes: H = heading's, W + H per wave.

    bf (H): bluntness coefficient (as computed; < 0 only with ``aft="include"``); fn (): Froude number;
    c_u (H): speed coefficient C_U at Bf⁺ = max(Bf, 0) (68 where Bf ≤ 0, where it multiplies 0);
    k_aw_short (H): Bf⁺(1 + C_U Fn) ≥ 0, the short-wave limit (α_T = 1); alpha_t (W+H); k_aw (W+H);
    r_awr (W+H): R_AWR [N] for the given amplitude; beam (): B_wl [m].
    """

    bf: Float[Array, "*H"]
    fn: Float[Array, ""]
    c_u: Float[Array, "*H"]
    k_aw_short: Float[Array, "*H"]
    alpha_t: Float[Array, "*WH"]
    k_aw: Float[Array, "*WH"]
    r_awr: Float[Array, "*WH"]
    beam: Float[Array, ""]


def outer_grid(omega, heading):
    omega = jnp.asarray(omega, dtype=float)
    heading = jnp.asarray(heading, dtype=float)
    return omega.reshape(omega.shape + (1,) * heading.ndim), heading


def nmri_added_resistance(sections: Sections, draft: Draft, speed: Speed, omega: Frequencies, heading: Angles = 0.0,
                          amplitude: Lengths = 1.0, *, rho: float = RHO_SEA, g: float = G, smooth: float | None = None,
                          aft: str = "exclude", band: float = 0.0) -> NMRIResult:
    """R_AWR and K_AW in regular waves of frequencies ``omega`` [rad/s] from headings ``heading`` [rad].

    ``draft`` [m] is both the waterline for Bf and d in α_T; ``speed`` U [m/s]; ``amplitude`` ζ_a [m];
    ``smooth`` τ for :func:`speed_coefficient` and :func:`positive_part` (None: the exact max); ``aft``: the
    lit range, see :func:`~hullopt.waves.bluntness_of_waterline` (default ``"exclude"``: the lit entrance).
    The reflection part is never negative (Bf⁺ = max(Bf, 0)): in following seas it is 0. Pure and
    differentiable in the sections, draft, speed and ω;
    finite (0) as ω → 0.

    Parameters
    ----------
    sections : Sections
        The hull's stations (offsets in metres).
    draft : float or Array
        Draft d [m] (scalar): the waterline for Bf and d in α_T.
    speed : float or Array
        Ship speed U [m/s] (scalar), ahead positive.
    omega : float or Array
        Wave circular frequencies ω [rad/s], any shape W.
    heading : float or Array
        Wave headings α [rad], 0 = head seas, any shape H.
    amplitude : float or Array
        Wave amplitude ζ_a [m]; broadcasts with the W + H results.
    rho : float
        Water density [kg/m³].
    g : float
        Gravitational acceleration [m/s²].
    smooth : float or None
        Width τ of the soft maximum in C_U and of the ramp in Bf⁺; None: the exact maxima.
    aft : {"exclude", "include"}
        Lit range of the waterline, see :func:`~hullopt.waves.bluntness_of_waterline`.
    band : float
        Bf averaged over the waterlines in [d − band, d + band] (band in m) (:func:`~hullopt.waves.bluntness`; static);
        0 (default): the waterline at the draft, as the patent's tables. B is the waterline's at the draft.

    Returns
    -------
    NMRIResult
        ``bf``, ``c_u``, ``k_aw_short`` of shape H; ``alpha_t``, ``k_aw``, ``r_awr`` [N] of shape W + H;
        ``fn`` and ``beam`` [m] scalars.
    """
    wl = waterline(sections, draft)
    om, hd = outer_grid(omega, heading)
    bf = bluntness(sections, draft, hd, aft, band) if band else bluntness_of_waterline(wl, hd, aft)
    fn = froude_number(speed, sections.lpp, g)
    bfp = positive_part(bf, smooth)
    c_u = speed_coefficient(bfp, smooth)
    short = bfp * (1.0 + c_u * fn)
    at = alpha_t(encounter_wavenumber(om, speed, hd, g) * draft)
    kaw = at * short
    b = wl.beam
    r = 0.5 * rho * g * jnp.asarray(amplitude, dtype=float) ** 2 * b * kaw
    return NMRIResult(bf=bf, fn=fn, c_u=c_u, k_aw_short=short, alpha_t=at, k_aw=kaw, r_awr=r, beam=b)
