"""Wave spectra, directional spreading, and the mean added resistance in a sea state (METHODS.md §2.6).

R̄_AW = 2 ∫∫ S(ω) D(θ) · R_AW(ω, α = θ)/ζ_a² dω dθ, S the one-sided spectrum [m²·s/rad], D the spreading
[1/rad] (a single heading when long-crested).

The frequency integral is taken in u = (5/4)(ω_p/ω)⁴, for which the Pierson–Moskowitz/Bretschneider
spectrum is exactly S dω = (H_s²/16)·e^(−u) du: the high-frequency tail (which matters, because R_AWR tends
to a non-zero constant in short waves, METHODS §5.4) is integrated to ω = ∞ with no truncation, unless a
cut-off ``omega_max`` is asked for. Composite Gauss–Legendre panels break at fixed ω/ω_p, dense around the
peak (the JONSWAP peak enhancement is narrow). Nodes are static, so everything is jit/grad/vmap-able.
"""

from __future__ import annotations

from collections.abc import Callable
from math import gamma as _gamma

import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float

from .._types import Angle, Angles, Frequencies, Length, Lengths, Period, Scalar, Values
from ..constants import G

SPECTRA = ("pm", "jonswap")
# Panel edges in ω/ω_p (beyond the last, down to u_max: waves this long carry e^(−u) < 1e-17 of the energy).
_RATIO_EDGES = (np.inf, 3.0, 2.0, 1.5, 1.25, 1.12, 1.05, 1.0, 0.95, 0.9, 0.83, 0.75, 0.65, 0.58, 0.5, 0.45, 0.4, 0.35)
_U_MAX = 40.0

# Beaufort number → (mean wind speed range [m/s], probable significant wave height [m]) after the WMO sea-state
# code; T_p from the fully developed Pierson–Moskowitz relation, see :func:`beaufort_sea_state`.
BEAUFORT = {
    0: ((0.0, 0.2), 0.0), 1: ((0.3, 1.5), 0.1), 2: ((1.6, 3.3), 0.2), 3: ((3.4, 5.4), 0.6),
    4: ((5.5, 7.9), 1.0), 5: ((8.0, 10.7), 2.0), 6: ((10.8, 13.8), 3.0), 7: ((13.9, 17.1), 4.0),
    8: ((17.2, 20.7), 5.5), 9: ((20.8, 24.4), 7.0), 10: ((24.5, 28.4), 9.0), 11: ((28.5, 32.6), 11.5),
    12: ((32.7, 40.0), 14.0),
}


def bretschneider(omega: Frequencies, hs: Lengths, tp: Values) -> Array:
    """Two-parameter (modified) Pierson–Moskowitz spectrum S(ω) [m²s] for H_s [m] and peak period T_p [s]:
    S = (5/16) H_s² ω_p⁴ ω⁻⁵ exp(−(5/4)(ω_p/ω)⁴), ω_p = 2π/T_p; m0 = H_s²/16 exactly. The ITTC 1978 form
    (173 H_s²/T_1⁴, 691/T_1⁴) is this spectrum with rounded constants and T_1 = 0.772 T_p.

    Parameters
    ----------
    omega : float or Array
        Circular frequency ω [rad/s], any shape; ω ≤ 0 gives S = 0.
    hs : float or Array
        Significant wave height H_s [m]; broadcasts with ``omega``.
    tp : float or Array
        Peak period T_p [s]; broadcasts with ``omega``.

    Returns
    -------
    Array
        Spectral density S(ω) [m²·s/rad], shape of the broadcast inputs.
    """
    omega = jnp.asarray(omega, dtype=float)
    wp = 2.0 * jnp.pi / tp
    pos = omega > 0.0
    w = jnp.where(pos, omega, 1.0)
    return jnp.where(pos, 5.0 / 16.0 * hs**2 * wp**4 / w**5 * jnp.exp(-1.25 * (wp / w) ** 4), 0.0)


def ittc_1978(omega: Frequencies, hs: Lengths, t1: Values) -> Array:
    """ITTC 1978 spectrum S = A/ω⁵ exp(−B/ω⁴), A = 173 H_s²/T_1⁴, B = 691/T_1⁴, T_1 the mean period [s].

    Parameters
    ----------
    omega : float or Array
        Circular frequency ω [rad/s], any shape; ω ≤ 0 gives S = 0.
    hs : float or Array
        Significant wave height H_s [m]; broadcasts with ``omega``.
    t1 : float or Array
        Mean (centroid) period T_1 [s]; broadcasts with ``omega``.

    Returns
    -------
    Array
        Spectral density S(ω) [m²·s/rad], shape of the broadcast inputs.
    """
    omega = jnp.asarray(omega, dtype=float)
    pos = omega > 0.0
    w = jnp.where(pos, omega, 1.0)
    return jnp.where(pos, 173.0 * hs**2 / t1**4 / w**5 * jnp.exp(-691.0 / t1**4 / w**4), 0.0)


def _peak_enhancement(ratio, gamma):
    """JONSWAP γ^r with r = exp(−(ω/ω_p − 1)²/(2σ²)), σ = 0.07 below the peak and 0.09 above."""
    sigma = jnp.where(ratio <= 1.0, 0.07, 0.09)
    return gamma ** jnp.exp(-((ratio - 1.0) ** 2) / (2.0 * sigma**2))


def _jonswap_norm(gamma):
    return 1.0 - 0.287 * jnp.log(gamma)


def jonswap(omega: Frequencies, hs: Lengths, tp: Values, gamma: Values = 3.3) -> Array:
    """JONSWAP spectrum [m²s]: (1 − 0.287 ln γ)·:func:`bretschneider`·γ^r (DNV-RP-C205 §3.5.5), whose
    normalisation keeps m0 ≈ H_s²/16: within 0.33 % for 1 ≤ γ ≤ 5 (+0.24 % at γ = 3.3), within 1 % up to
    γ ≈ 6.3, then falling off (−1.75 % at γ = 7, −6.9 % at 10; measured by quadrature, the same for every
    H_s and T_p); γ = 1 is Bretschneider.

    Parameters
    ----------
    omega : float or Array
        Circular frequency ω [rad/s], any shape; ω ≤ 0 gives S = 0.
    hs : float or Array
        Significant wave height H_s [m]; broadcasts with ``omega``.
    tp : float or Array
        Peak period T_p [s]; broadcasts with ``omega``.
    gamma : float or Array
        Peak enhancement factor γ (dimensionless, > 0); 3.3 the mean JONSWAP value, 1 gives Bretschneider.

    Returns
    -------
    Array
        Spectral density S(ω) [m²·s/rad], shape of the broadcast inputs.
    """
    omega = jnp.asarray(omega, dtype=float)
    return _jonswap_norm(gamma) * bretschneider(omega, hs, tp) * _peak_enhancement(omega * tp / (2 * jnp.pi), gamma)


def spreading(theta: Angles, s: float = 1.0) -> Array:
    """cos-2s spreading D(θ) = 2^(2s) Γ(1+s)² / (π Γ(1+2s)) cos^(2s) θ for |θ| ≤ π/2, else 0 [1/rad];
    ∫D dθ = 1. s = 1 (wind sea) gives (2/π) cos² θ; s = 0.75 is used for swell.

    Parameters
    ----------
    theta : float or Array
        Direction θ relative to the mean wave heading [rad], any shape.
    s : float
        Spreading exponent s (dimensionless, ≥ 0, a Python number: it sets a static normalisation).

    Returns
    -------
    Array
        Spreading density D(θ) [1/rad], shape of ``theta``; 0 for |θ| ≥ π/2.
    """
    theta = jnp.asarray(theta, dtype=float)
    c = 2.0 ** (2 * s) * _gamma(1 + s) ** 2 / (np.pi * _gamma(1 + 2 * s))
    inside = jnp.abs(theta) < 0.5 * jnp.pi
    cos = jnp.where(inside, jnp.cos(theta), 1.0)
    return jnp.where(inside, c * cos ** (2 * s), 0.0)


def beaufort_sea_state(number: int) -> tuple[float, float]:
    """(H_s [m], T_p [s]) for a Beaufort number 1–12: H_s the WMO probable wave height, T_p of a fully
    developed Pierson–Moskowitz sea with that H_s (H_s = 0.21 U²/g, ω_p = 0.877 g/U, so
    T_p = 2π/0.877·√(H_s/(0.21 g)) ≈ 4.99 √H_s).

    Parameters
    ----------
    number : int
        Beaufort number, 1 to 12.

    Returns
    -------
    tuple of float
        (H_s [m], T_p [s]).

    Raises
    ------
    ValueError
        If ``number`` is not an integer 1 to 12.
    """
    if number not in BEAUFORT or number == 0:
        raise ValueError(f"Beaufort number {number!r}: expected an integer 1 to 12")
    hs = BEAUFORT[number][1]
    return hs, float(2 * np.pi / 0.877 * np.sqrt(hs / (0.21 * G)))


def frequency_nodes(tp: Period, omega_max: Scalar | None = None, order: int = 8) -> tuple[Array, Array]:
    """Quadrature nodes ω_i [rad/s] and weights w_i with ∫ f(ω) S_PM(ω) dω ≈ (H_s²/16) Σ w_i f(ω_i) for
    the Bretschneider spectrum of peak period ``tp`` [s] (over ω ≤ ``omega_max`` if given).

    Parameters
    ----------
    tp : float or Array
        Peak period T_p [s] (scalar).
    omega_max : float or None
        Short-wave cut-off [rad/s]; None integrates to ω = ∞.
    order : int
        Gauss–Legendre points per panel.

    Returns
    -------
    omega : Array
        Nodes ω_i [rad/s], shape (18·order,) float.
    weights : Array
        Weights w_i (dimensionless, summing to ≈ 1 without a cut-off), shape (18·order,) float.
    """
    ref, wref = np.polynomial.legendre.leggauss(order)
    edges = np.minimum(1.25 * np.asarray(_RATIO_EDGES) ** -4.0, _U_MAX)
    edges = np.append(edges, _U_MAX)
    a, b = jnp.asarray(edges[:-1]), jnp.asarray(edges[1:])
    wp = 2.0 * jnp.pi / tp
    if omega_max is not None:
        u_min = 1.25 * (wp / omega_max) ** 4
        a, b = jnp.maximum(a, u_min), jnp.maximum(b, u_min)  # panels below the cut-off shrink to nothing
    half = 0.5 * (b - a)
    u = (0.5 * (a + b))[:, None] + half[:, None] * jnp.asarray(ref)[None, :]
    w = half[:, None] * jnp.asarray(wref)[None, :] * jnp.exp(-u)
    u, w = u.reshape(-1), w.reshape(-1)
    return wp * (1.25 / u) ** 0.25, w


def direction_nodes(s: float | None = None, order: int = 16,
                    breaks: Float[ArrayLike, ' K'] | None = None) -> tuple[Array, Array]:
    """Relative directions θ_j [rad] and weights (summing to 1) for cos-2s spreading ``s``; a single
    direction (0, weight 1) when ``s`` is None (long-crested).

    Without ``breaks``: Gauss–Legendre over −π/2 … π/2 (static nodes). With ``breaks``, the relative
    directions where the response has a kink or a jump: each is taken modulo π into [−π/2, π/2) (a kink at
    θ_k and at θ_k ± π: exactly one of the two lies in the half-circle window, so none is wasted), the window
    is split there, and each of the K + 1 panels gets max(4, ⌈order/(K + 1)⌉) Gauss–Legendre points (the
    window narrowed to |θ| ≤ 4.5/√(2s) where that is less than π/2, so a narrow spreading is resolved). A
    Gauss rule across a kink converges only as 1/n² (1/n across a jump); split there it converges as for a
    smooth response. The nodes move with the breaks (traced values are fine: jit, grad, vmap), so the
    derivative of the mean with respect to where a jump lies is the jump times D there, as it should be.

    Parameters
    ----------
    s : float or None
        cos-2s spreading exponent (dimensionless); None for long-crested seas.
    order : int
        Gauss–Legendre points over −π/2 … π/2 (without ``breaks``), or the total the panels share.
    breaks : Array or None
        Relative directions [rad] of the response's kinks, shape (K,); None: one panel.

    Returns
    -------
    theta : Array
        Directions θ_j [rad] relative to the mean heading, shape (order,) float without ``breaks``,
        ((K + 1)·max(4, ⌈order/(K + 1)⌉),) with them, or (1,) when ``s`` is None.
    weights : Array
        Weights (dimensionless, summing to 1), same shape as ``theta``.
    """
    if s is None:
        return jnp.zeros(1), jnp.ones(1)
    if breaks is None:
        ref, wref = np.polynomial.legendre.leggauss(order)
        theta = 0.5 * np.pi * ref
        w = 0.5 * np.pi * wref * np.cos(theta) ** (2 * s)  # static numpy: nodes are fixed at trace time
        return jnp.asarray(theta), jnp.asarray(w / w.sum())  # exact normalisation: the energy is kept
    breaks = jnp.ravel(jnp.asarray(breaks, dtype=float))
    k = breaks.shape[0]
    m = max(4, -(-order // (k + 1)))
    ref, wref = np.polynomial.legendre.leggauss(m)
    # cos^(2s) θ ≈ exp(−sθ²): beyond |θ| = 4.5/√(2s) lies < 1e-5 of it; a narrow spreading is integrated there
    width = min(0.5 * np.pi, 4.5 / np.sqrt(2.0 * s)) if s > 0 else 0.5 * np.pi
    inner = jnp.mod(breaks + 0.5 * jnp.pi, jnp.pi) - 0.5 * jnp.pi
    end = jnp.full((1,), width)
    edges = jnp.sort(jnp.concatenate([-end, jnp.clip(inner, -width, width), end]))
    a, b = edges[:-1], edges[1:]
    half = 0.5 * (b - a)
    theta = (0.5 * (a + b))[:, None] + half[:, None] * jnp.asarray(ref)[None, :]
    c = jnp.cos(theta)
    pos = c > 0.0  # double where: cos^(2s) with a finite gradient at the window's ends
    d = jnp.where(pos, jnp.where(pos, c, 1.0) ** (2 * s), 0.0)
    w = (half[:, None] * jnp.asarray(wref)[None, :] * d).reshape(-1)
    return theta.reshape(-1), w / jnp.sum(w)  # exact normalisation: the energy is kept


def spectral_mean(response: Callable[[Array, Array], Array], hs: Length, tp: Period, heading: Angle = 0.0, *,
                  spectrum: str = "pm", gamma: Scalar = 3.3, spreading_s: float | None = None,
                  omega_max: Scalar | None = None, order: int = 8, n_dir: int = 16,
                  breaks: Float[ArrayLike, ' K'] | None = None) -> Array:
    """Mean added resistance [N] in a sea state: 2∫∫ S(ω) D(θ) response(ω, α + θ) dω dθ.

    ``response(omega (k,), heading (h,)) → (k, h, ...)`` is R_AW/ζ_a² [N/m²] in regular waves; ``hs`` [m], ``tp``
    peak period [s], ``heading`` the mean wave heading [rad] (0 = head seas); ``spectrum`` "pm"
    (Bretschneider / ITTC modified Pierson–Moskowitz) or "jonswap" (with ``gamma``); ``spreading_s``
    None for long-crested seas or the cos-2s exponent; ``omega_max`` an optional short-wave cut-off [rad/s].

    Parameters
    ----------
    response : callable
        ``response(omega, heading)`` with ``omega`` (k,) [rad/s] and ``heading`` (h,) [rad], returning
        R_AW/ζ_a² [N/m²] of shape (k, h, ...).
    hs : float or Array
        Significant wave height H_s [m] (scalar).
    tp : float or Array
        Peak period T_p [s] (scalar).
    heading : float or Array
        Mean wave heading [rad], 0 = head seas (scalar).
    spectrum : {"pm", "jonswap"}
        "pm": Bretschneider (ITTC modified Pierson–Moskowitz); "jonswap": with peak enhancement ``gamma``.
    gamma : float or Array
        JONSWAP peak enhancement factor γ (dimensionless); used only with ``spectrum="jonswap"``.
    spreading_s : float or None
        cos-2s spreading exponent; None for long-crested seas (a single heading).
    omega_max : float or None
        Short-wave cut-off [rad/s]; None integrates to ω = ∞.
    order : int
        Gauss–Legendre points per frequency panel.
    n_dir : int
        Gauss–Legendre points over direction (short-crested seas only); with ``breaks``, the total the
        panels between them share (at least 4 each), see :func:`direction_nodes`.
    breaks : Array or None
        Headings [rad] (absolute, 0 = head seas; shape (K,), traced values allowed) where ``response`` has a
        kink or a jump in heading: the direction integral is split there (short-crested seas only), which
        makes it converge as for a smooth response (a plain Gauss rule across SNNM's or STAWAVE's switches
        was off by several % at 16 points). None: one Gauss–Legendre panel.

    Returns
    -------
    Array
        Mean added resistance R̄_AW [N], shape of ``response``'s trailing dimensions ``...`` (scalar if none).

    Raises
    ------
    ValueError
        If ``spectrum`` is not one of ``SPECTRA``.
    """
    if spectrum not in SPECTRA:
        raise ValueError(f"spectrum {spectrum!r}: expected one of {SPECTRA}")
    om, w = frequency_nodes(tp, omega_max, order)
    if spectrum == "jonswap":
        w = w * _jonswap_norm(gamma) * _peak_enhancement(om * tp / (2 * jnp.pi), gamma)
    rel = None if breaks is None else jnp.asarray(breaks, dtype=float) - jnp.asarray(heading, dtype=float)
    th, wd = direction_nodes(spreading_s, n_dir, rel)
    r = response(om, jnp.asarray(heading, dtype=float) + th)
    return 2.0 * jnp.asarray(hs, dtype=float) ** 2 / 16.0 * jnp.einsum("k,kh...,h->...", w, r, wd)
