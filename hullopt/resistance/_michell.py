"""Wave resistance by Michell's (1898) thin-ship integral, from the sections, in deep water.

The hull is y = ±Y(x, z) (half-breadths of the sections, z from the keel up to the draft T); thin-ship theory
replaces it by Havelock sources of strength 2U·∂Y/∂x on the centreplane, and the energy their Kelvin waves
carry away is (Michell 1898; in this form Tuck 1989 and Wehausen & Laitone 1960, whose
∫₀^{π/2} … sec³θ dθ over the wave directions θ is this integral with λ = sec θ)::

    R_w = (4ρg²/(πU²)) ∫₁^∞ (P² + Q²) λ²/√(λ² − 1) dλ,
    P + iQ = ∫₀^T ∫ (∂Y/∂x) e^{k₀λ²(z − T)} e^{i k₀ λ x} dx dz,      k₀ = g/U².

Checks of the constant: a single source of strength σ [m³/s] at depth f gives, by the same formula with
∂Y/∂x dA = σ/(2U), R = (ρg²σ²/(πU⁴)) ∫ e^{−2k₀fλ²} λ²/√(λ²−1) dλ = 16πρk₀²m²∫₀^{π/2} e^{−2k₀f sec²θ}
sec³θ dθ with m = σ/(4π), the form of Havelock's submerged-source resistance (a doublet, the submerged
sphere, has sec⁵θ); the Wigley hull's closed-form x and z integrals check the discretisation (tests).

Discretisation, exact for the sections' ruled surface sampled at ``n_levels`` heights:

* x: between stations Y is linear in x at each height, so ∂Y/∂x is a constant s_i on each interval and
  ∫ e^{ikx} dx over it is (E_{i+1} − E_i)/(ik), E_j = e^{ikx_j} — exact at any k = k₀λ, so the bow–stern
  oscillation of low Froude numbers needs no finer stations. Summed by parts, Σ_i s_i (E_{i+1} − E_i) =
  Σ_j E_j (s_{j−1} − s_j): one cos and one sin a station and wave number (the sinc form over each interval took
  a third transcendental and its derivative; 1.75× faster with the gradient, equal to 1e-14). Wet end stations
  (a transom, a blunt bow face) close the hull with a jump of Y at the end (a source sheet on the end face), as
  if the flow left a dry transom smoothly — thin-ship theory has no better model of a transom, and it
  overestimates the stern waves of a dry one.
* z: Y is linear between the levels; the integral of each hat function against e^{c(z−T)}, c = k₀λ², is
  taken in closed form (stable for any c), so the steep decay at large λ costs no extra levels.
* λ: λ = 1 + t² on [1, 2] (removes the inverse-square-root singularity at λ = 1: the integrand becomes
  2λ²/√(2 + t²)·|P + iQ|²) and λ itself on [2, Λ], each by composite Gauss–Legendre panels; the tail beyond
  Λ = 20 (only the waterline's algebraic λ⁻⁴ decay is left there) is below 3·10⁻⁵ of the total on the
  Wigley hull at Fn 0.2–0.45. The bow–stern interference oscillates with period 2π/(k₀L) = 2πFn² in λ:
  the default 256 panels of 8 points on [2, 20] (0.07 wide) take half a period each at Fn 0.15, and 128
  panels already hold the Wigley's closed forms to 1e-4 at Fn 0.12. The analyses that evaluate it many times
  (objectives, rescoring: :func:`.calm_water`) take ``LAMBDA_PANELS`` = 64, against 1024 panels: the Wigley
  (sharp ends, the strongest bow–stern interference) within 1.3e-5 at Fn 0.12, 8e-9 at Fn 0.15 and 6e-12 at
  Fn 0.2; the KCS at 22–26 kn and the DTC at Fn 0.1–0.3 within 1e-13. 2.4× faster with the gradient than 128.

Everything is pure JAX: differentiable in the sections, the draft and the speed, vmapped over speeds.

References: Michell, J.H. (1898) Phil. Mag. 45, 106–123. Tuck, E.O. (1989) J. Austral. Math. Soc. B 30,
365–377. Wehausen, J.V. & Laitone, E.V. (1960) Surface waves, Handbuch der Physik 9, §13.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array

from .._types import Draft, Speeds, Values
from ..constants import G, RHO_SEA
from ..errors import HullError
from ..geometry import Sections, closed_half_polygon, level_widths, safe_div

LAMBDA_MAX = 20.0  # upper end Λ of the λ integral (tail < 3e-5 of the total on the Wigley, Fn 0.2–0.45)
LAMBDA_PANELS = 64  # λ panels of the analyses evaluated many times (module docstring: accuracy at Fn ≥ 0.12)
_GL = 8  # Gauss–Legendre points per panel


def _gauss_panels(a, b, panels: int):
    """Nodes and weights of composite ``panels``-panel Gauss–Legendre on [a, b] (a, b may be traced)."""
    t, w = np.polynomial.legendre.leggauss(_GL)
    edges = np.linspace(0.0, 1.0, panels + 1)
    h = np.diff(edges)[:, None]
    s = (edges[:-1, None] + 0.5 * h * (t[None, :] + 1.0)).ravel()  # in [0, 1]
    ws = (0.5 * h * w[None, :]).ravel()
    return a + (b - a) * jnp.asarray(s), (b - a) * jnp.asarray(ws)


def lambda_nodes(panels: int = 256, lam_max: float = LAMBDA_MAX):
    """Nodes λ and weights of ∫₁^Λ f(λ) λ²/√(λ² − 1) dλ ≈ Σ w·f(λ): λ = 1 + t² on [1, 2], λ on [2, Λ].

    ``panels`` Gauss–Legendre panels of 8 points on [2, Λ] and ``panels // 8`` (at least 4) on t ∈ [0, 1]."""
    t, wt = _gauss_panels(0.0, 1.0, max(4, panels // 8))
    lam1 = 1.0 + t * t
    w1 = wt * 2.0 * lam1 * lam1 / jnp.sqrt(2.0 + t * t)
    lam2, w2 = _gauss_panels(2.0, lam_max, panels)
    w2 = w2 * lam2 * lam2 / jnp.sqrt(lam2 * lam2 - 1.0)
    return jnp.concatenate([lam1, lam2]), jnp.concatenate([w1, w2])


def _phi(a):
    """(1 − (1 + a)e^{−a})/a² and (a − 1 + e^{−a})/a² for a > 0 (∫₀¹ r e^{−ar} dr, ∫₀¹ (1 − r) e^{−ar} dr),
    by their series below a = 1e-3 (finite values and gradients at any a ≥ 0)."""
    small = a < 1e-3
    s = jnp.where(small, 1.0, a)
    e = jnp.exp(-s)
    lo = (1.0 - (1.0 + s) * e) / (s * s)  # weight of the level below (distance r from the top)
    up = (s + jnp.expm1(-s)) / (s * s)  # weight of the level above
    lo_series = 0.5 - a / 3.0 + a * a / 8.0
    up_series = 0.5 - a / 6.0 + a * a / 24.0
    return jnp.where(small, lo_series, lo), jnp.where(small, up_series, up)


def _depth_weights(levels, draft: Draft, c):
    """Weights W_j(c) with ∫_{z_0}^{T} Y(z) e^{c(z − T)} dz = Σ_j W_j Y(z_j) for Y linear between the equally
    spaced levels ``z_j`` (z_{K−1} = T); ``c`` (L,) → (L, K)."""
    h = (levels[-1] - levels[0]) / (levels.shape[0] - 1)  # the levels are equally spaced: one φ per c
    top = jnp.exp(c[:, None] * (levels[None, 1:] - draft))  # e^{c(z_{j+1} − T)} ≤ 1
    lo, up = _phi(c * h)
    w_lo = top * (h * lo)[:, None]  # to level j (the lower end of interval j)
    w_up = top * (h * up)[:, None]  # to level j + 1
    zero = jnp.zeros_like(c)[:, None]
    return jnp.concatenate([w_lo, zero], axis=1) + jnp.concatenate([zero, w_up], axis=1)


def half_breadths(sections: Sections, draft: Draft, n_levels: int = 33):
    """Half-breadths Y (n, K) [m] of the sections at ``n_levels`` equally spaced heights from the keel to
    ``draft``, and the heights (K,) [m]. At the keel itself Y is extrapolated linearly from the two levels
    above (second order, like the rest): a flat bottom's crossing rule is ambiguous there, and a deformed
    KCS dips 1e-8 to 1e-3 m below its flat bottom here and there, so a probe just above the keel switched
    between 0 and the flat's 12.5 m (R_W jumped 1.5 % between designs 1e-10 apart; every solve stalled)."""
    t = jnp.asarray(draft, dtype=sections.yz.dtype)
    keel = sections.keel
    levels = keel + (t - keel) * jnp.linspace(0.0, 1.0, n_levels)
    y = level_widths(closed_half_polygon(sections.yz), levels[1:])
    y0 = 2.0 * y[:, :1] - y[:, 1:2] if n_levels > 2 else y[:, :1]
    return jnp.concatenate([y0, y], axis=1), levels


def michell_integrand(sections: Sections, draft: Draft, k0: Values, lam: Values, n_levels: int = 33) -> Array:
    """|P + iQ|² [m⁴] at the wave numbers ``lam`` (any shape) of Michell's integral, k₀ = g/U² [1/m].

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Draft T [m above the baseline].
    k0 : float or Array, scalar
        Wave number g/U² [1/m].
    lam : array_like, any shape
        λ = sec θ ≥ 1 (dimensionless); the wave number is k₀λ.
    n_levels : int
        Heights from the keel to the draft sampled (33 by default), ≥ 2.

    Returns
    -------
    Array
        |P + iQ|² [m⁴], shape of ``lam``.
    """
    y, levels = half_breadths(sections, draft, n_levels)  # (n, K)
    x = sections.x
    shape = jnp.shape(lam)
    lam = jnp.reshape(lam, (-1,))
    k = k0 * lam  # (L,)
    slope = jnp.diff(y, axis=0) / jnp.diff(x)[:, None]  # (n−1, K): ∂Y/∂x between stations
    zero = jnp.zeros_like(y[:1])
    turn = jnp.concatenate([zero, slope], axis=0) - jnp.concatenate([slope, zero], axis=0)  # s_{j−1} − s_j
    kx = k[:, None] * x[None, :]
    c, s = jnp.cos(kx), jnp.sin(kx)  # (L, n)
    # P + iQ = Σ_j E_j (jump_j + turn_j/(ik)): the jumps +Y_0 at the first station and −Y_{n−1} at the last
    # close the hull at wet ends
    jump_c = c[:, :1] * y[None, 0] - c[:, -1:] * y[None, -1]  # (L, K)
    jump_s = s[:, :1] * y[None, 0] - s[:, -1:] * y[None, -1]
    w = _depth_weights(levels, jnp.asarray(draft, dtype=levels.dtype), k0 * lam * lam)  # (L, K)
    p = jnp.sum((jump_c + (s @ turn) / k[:, None]) * w, axis=1)
    q = jnp.sum((jump_s - (c @ turn) / k[:, None]) * w, axis=1)
    return jnp.reshape(p * p + q * q, shape)


def _check(n_levels: int, panels: int):
    if not (isinstance(n_levels, int) and n_levels >= 2):
        raise HullError(f"n_levels {n_levels!r}: expected an integer ≥ 2 (heights from the keel to the draft)")
    if not (isinstance(panels, int) and panels >= 1):
        raise HullError(f"panels {panels!r}: expected a positive integer (Gauss–Legendre panels in λ)")


def michell_wave_resistance(sections: Sections, draft: Draft, speed: Speeds, *, rho: float = RHO_SEA, g: float = G,
                            n_levels: int = 33, panels: int = 256, lam_max: float = LAMBDA_MAX) -> Array:
    """Wave resistance R_w [N] by Michell's thin-ship integral (deep water) at ``speed`` U [m/s].

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y half-breadths to port, z up from the baseline); its stations and
        sections define the ruled surface integrated (see the module docstring).
    draft : float
        Draft T [m above the baseline]; the hull below it is the centreplane source sheet.
    speed : float or Array
        Ship speed U [m/s] > 0, any shape (vmapped).
    rho, g : float
        Water density [kg/m³] and gravity [m/s²].
    n_levels : int
        Heights from the keel to the draft at which the half-breadths are sampled (linear between).
    panels : int
        Gauss–Legendre panels (8 points each) on λ ∈ [2, Λ]; ``panels // 8`` more on [1, 2].
    lam_max : float
        Upper end Λ of the λ integral.

    Returns
    -------
    Array
        R_w [N] ≥ 0, shape of ``speed``.

    Examples
    --------
    A Wigley hull (L 100, B 10, T 6.25 m) at Fn 0.3: 144.1 kN by the closed forms of its x and z integrals
    (tests/test_michell.py); from 101 stations and 33 levels:

    >>> import jax; jax.config.update("jax_enable_x64", True)
    >>> from hullopt.models import wigley
    >>> from hullopt.resistance import michell_wave_resistance
    >>> u = 0.3 * (9.80665 * 100.0) ** 0.5
    >>> r = jax.jit(michell_wave_resistance)(wigley(100, 10, 6.25, 10, n=101, m=33), 6.25, u)
    >>> round(float(r) / 1e3, 1)
    144.1
    """
    _check(n_levels, panels)
    lam, wts = lambda_nodes(panels, lam_max)
    speed = jnp.asarray(speed, dtype=sections.yz.dtype)

    def one(u):
        ok = u > 0.0
        u2 = jnp.where(ok, u * u, 1.0)
        k0 = g / u2
        f = michell_integrand(sections, draft, k0, lam, n_levels)
        r = 4.0 * rho * g * g / (jnp.pi * u2) * jnp.sum(wts * f)
        return jnp.where(ok, r, 0.0)

    flat = jnp.reshape(speed, (-1,))
    return jnp.reshape(jax.vmap(one)(flat), speed.shape)


def wave_resistance_coefficient(r_w: Values, speed: Speeds, wetted_surface: Values, rho: float = RHO_SEA) -> Array:
    """C_w = R_w/(½ρU²S) (dimensionless) from R_w [N], U [m/s] and the wetted surface S [m²].

    Parameters
    ----------
    r_w : float or array_like
        Wave resistance [N].
    speed : float or array_like
        Ship speed [m/s], broadcast with ``r_w``.
    wetted_surface : float or array_like
        Wetted surface [m²].
    rho : float
        Water density [kg/m³] (sea water 1025 by default).

    Returns
    -------
    Array
        C_w (dimensionless) in the broadcast shape; 0 where the dynamic pressure is 0.
    """
    q = 0.5 * rho * jnp.asarray(speed) ** 2 * jnp.asarray(wetted_surface)
    return safe_div(jnp.asarray(r_w), q, q > 0.0)
