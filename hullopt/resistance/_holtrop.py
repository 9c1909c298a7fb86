"""Calm-water resistance by Holtrop & Mennen (1982), from the hull's own geometry.

Holtrop, J. & Mennen, G.G.J. (1982), "An approximate power prediction method", International Shipbuilding
Progress 29(335), 166–170. Its section-5 worked example (L 205 m, 25 kn) is checked in the tests: 1792.13 kN
for the paper's 1793.26 kN (−0.063 %; the paper's R_A does not follow from its own C_A, see the test).

Conventions as the paper: L is the waterline length, ``lcb`` is in % of L forward of 0.5 L, ``ie`` the half
angle of entrance in degrees. The piecewise definitions (c7, c12, c15, λ, c4, c6) join continuously, so the
total is differentiable almost everywhere in the hull's parameters.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float

from .._types import Draft, Speeds
from ..constants import G, NU_SEA, RHO_SEA  # NU_SEA: sea water at 15 °C (ITTC), as the paper's example
from ..geometry import Sections, longitudinal_integrals, safe_div, section_necks, wetted_surface

#: m (of √A_BT) and dimensionless (of √c3): added under a square root that may be 0 (no bulb), so its derivative
#: stays finite there; far below any real bulb area.
_SQRT_FLOOR = 1e-30


class HoltropHull(eqx.Module):
    """Inputs of the method: lengths [m], areas [m²], volume [m³], ``lcb`` [% L fwd of 0.5 L], ``ie`` [deg]."""

    L: Float[ArrayLike, ""]
    B: Float[ArrayLike, ""]
    T: Float[ArrayLike, ""]
    T_F: Float[ArrayLike, ""]
    volume: Float[ArrayLike, ""]
    cm: Float[ArrayLike, ""]
    cwp: Float[ArrayLike, ""]
    lcb: Float[ArrayLike, ""]
    ie: Float[ArrayLike, ""]
    S: Float[ArrayLike, ""]
    A_BT: Float[ArrayLike, ""]
    h_B: Float[ArrayLike, ""]
    A_T: Float[ArrayLike, ""]
    c_stern: Float[ArrayLike, ""] = eqx.field(default_factory=lambda: jnp.asarray(0.0))
    S_app: Float[ArrayLike, ""] = eqx.field(default_factory=lambda: jnp.asarray(0.0))
    k2_app: Float[ArrayLike, ""] = eqx.field(default_factory=lambda: jnp.asarray(1.5))
    bulb: Float[ArrayLike, ""] | None = None  # 1.0: a bulbous bow seen on the sections (has_bulb), 0.0: none


#: A bulbous bow (:func:`has_bulb`): a section within this fraction of the stations' span from the forward end
#: whose outline under the waterline narrows above a wider part by more than ``BULB_NECK`` of the largest
#: half-breadth (as :func:`hullopt.optimise.bulb_stations` finds a bulb to freeze).
BULB_FORE, BULB_NECK = 0.15, 0.02


def has_bulb(sections: Sections, draft: Draft) -> Float[Array, ""]:
    """Whether ``sections`` have a bulbous bow: 1.0 where a forward section (within :data:`BULB_FORE` of the
    span) has a neck under the waterline — a point narrower than one below it by more than :data:`BULB_NECK`
    of the largest half-breadth — else 0.0 (no gradient). A section that only widens from the keel up (a
    plain stem, a full bow) has none, whatever its area at the FP.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m, keel to deck].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, scalar
        1.0 or 0.0.
    """
    x, y = jax.lax.stop_gradient(sections.x), jax.lax.stop_gradient(sections.yz[..., 0])
    fore = (x - x[0]) >= (1.0 - BULB_FORE) * (x[-1] - x[0])
    return jnp.any(fore & (section_necks(sections, draft) > BULB_NECK * jnp.max(y))).astype(y.dtype)


class HoltropResult(eqx.Module):
    """Resistance components [N] and the coefficients the paper prints, for checking."""

    total: Float[Array, "*speed"]
    friction: Float[Array, "*speed"]  # R_F, without the form factor
    form_factor: Float[Array, ""]  # 1 + k1
    appendages: Float[Array, "*speed"]
    wave: Float[Array, "*speed"]
    bulb: Float[Array, "*speed"]
    transom: Float[Array, "*speed"]
    correlation: Float[Array, "*speed"]
    cf: Float[Array, "*speed"]
    ca: Float[Array, ""]
    fn: Float[Array, "*speed"]
    c1: Float[Array, ""]
    c2: Float[Array, ""]
    c5: Float[Array, ""]
    m1: Float[Array, ""]
    m2: Float[Array, "*speed"]
    lam: Float[Array, ""]


def holtrop_mennen(h: HoltropHull, speed: Speeds, rho: float = RHO_SEA, nu: float = NU_SEA) -> HoltropResult:
    """Total calm-water resistance [N] at ``speed`` [m/s] (any shape: vectorised).

    Parameters
    ----------
    h : HoltropHull
        The method's inputs (lengths [m], areas [m²], volume [m³], ``lcb`` [% L fwd of 0.5 L], ``ie`` [deg]),
        e.g. from :func:`holtrop_hull`.
    speed : float or array_like
        Ship speed [m/s], any shape.
    rho : float
        Water density [kg/m³] (sea water 1025 by default).
    nu : float
        Kinematic viscosity [m²/s] (sea water at 15 °C, 1.18831e-6, by default).

    Returns
    -------
    HoltropResult
        Components [N] ``total``, ``friction`` (without 1 + k1), ``appendages``, ``wave``, ``bulb``,
        ``transom``, ``correlation`` and ``cf``, ``fn``, ``m2`` in the shape of ``speed``; ``form_factor``
        (1 + k1), ``ca``, ``c1``, ``c2``, ``c5``, ``m1``, ``lam`` scalars (dimensionless).
    """
    V = jnp.asarray(speed)
    L, B, T, vol = h.L, h.B, h.T, h.volume
    cb = vol / (L * B * T)
    cp = cb / h.cm
    fn = V / jnp.sqrt(G * L)
    q = 0.5 * rho * V**2
    # friction (ITTC 1957) and form factor
    rn = jnp.maximum(V * L / nu, 1e3)
    cf = 0.075 / (jnp.log10(rn) - 2.0) ** 2
    lr = L * (1.0 - cp + 0.06 * cp * h.lcb / (4.0 * cp - 1.0))
    tl = T / L
    c12 = jnp.where(tl > 0.05, tl**0.2228446, jnp.where(tl > 0.02, 48.20 * jnp.maximum(tl - 0.02, 0.0) ** 2.078 + 0.479948, 0.479948))
    c13 = 1.0 + 0.003 * h.c_stern
    k1 = c13 * (0.93 + c12 * (B / lr) ** 0.92497 * (0.95 - cp) ** -0.521448 * (1.0 - cp + 0.0225 * h.lcb) ** 0.6906)
    r_f = q * h.S * cf
    r_app = q * h.S_app * h.k2_app * cf
    # wave resistance
    bl = B / L
    c7 = jnp.where(bl < 0.11, 0.229577 * bl ** (1 / 3), jnp.where(bl < 0.25, bl, 0.5 - 0.0625 / bl))
    c1 = 2223105.0 * c7**3.78613 * (T / B) ** 1.07961 * (90.0 - h.ie) ** -1.37565
    sq_abt = jnp.sqrt(jnp.maximum(h.A_BT, 0.0) + _SQRT_FLOOR)
    c3 = 0.56 * sq_abt**3 / (B * T * (0.31 * sq_abt + h.T_F - h.h_B))
    c2 = jnp.exp(-1.89 * jnp.sqrt(c3 + _SQRT_FLOOR))
    c5 = 1.0 - 0.8 * h.A_T / (B * T * h.cm)
    c16 = jnp.where(cp < 0.8, 8.07981 * cp - 13.8673 * cp**2 + 6.984388 * cp**3, 1.73014 - 0.7067 * cp)
    m1 = 0.0140407 * L / T - 1.75254 * vol ** (1 / 3) / L - 4.79323 * B / L - c16
    l3v = L**3 / vol
    c15 = jnp.where(l3v < 512.0, -1.69385, jnp.where(l3v < 1727.0, -1.69385 + (L / vol ** (1 / 3) - 8.0) / 2.36, 0.0))
    fn_safe = jnp.maximum(fn, 1e-3)  # the wave terms vanish smoothly as Fn → 0
    m2 = c15 * cp**2 * jnp.exp(-0.1 * fn_safe**-2)
    lam = jnp.where(L / B < 12.0, 1.446 * cp - 0.03 * L / B, 1.446 * cp - 0.36)
    r_w = c1 * c2 * c5 * vol * rho * G * jnp.exp(m1 * fn_safe**-0.9 + m2 * jnp.cos(lam * fn_safe**-2))
    # bulb near the surface
    pb = 0.56 * sq_abt / (h.T_F - 1.5 * h.h_B)
    fni = V / jnp.sqrt(G * (h.T_F - h.h_B - 0.25 * sq_abt) + 0.15 * V**2)
    r_b = 0.11 * jnp.exp(-3.0 * pb**-2) * fni**3 * sq_abt**3 * rho * G / (1.0 + fni**2)
    # immersed transom
    has_t = h.A_T > 0.0
    fnt = V / jnp.sqrt(2.0 * G * jnp.where(has_t, h.A_T, 1.0) / (B + B * h.cwp))
    c6 = jnp.where(has_t & (fnt < 5.0), 0.2 * (1.0 - 0.2 * fnt), 0.0)
    r_tr = q * h.A_T * c6
    # model-ship correlation
    c4 = jnp.minimum(h.T_F / L, 0.04)
    ca = 0.006 * (L + 100.0) ** -0.16 - 0.00205 + 0.003 * jnp.sqrt(L / 7.5) * cb**4 * c2 * (0.04 - c4)
    r_a = q * h.S * ca
    total = r_f * k1 + r_app + r_w + r_b + r_tr + r_a
    return HoltropResult(total, r_f, k1, r_app, r_w, r_b, r_tr, r_a, cf, ca, fn, c1, c2, c5, m1, m2, lam)


def holtrop_hull(sections: Sections, draft: Draft, entrance_fraction: float = 0.05,
                 c_stern: float = 0.0) -> HoltropHull:
    """The method's inputs measured on our geometry at an even-keel ``draft`` [m].

    L, B = waterline length (between the waterline's ends) and breadth; S = wetted surface
    (:func:`hullopt.geometry.wetted_surface`); A_T = immersed transom area (``a_transom`` of
    :func:`hullopt.geometry.longitudinal_integrals`); A_BT, h_B = immersed area at the FP and its centroid
    height; ``ie`` = the angle of the waterline's chord over the forward ``entrance_fraction`` of L (Holtrop's
    half angle of entrance ignores the local rounding at the stem).

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Even-keel draft [m above the baseline]; also ``T_F``.
    entrance_fraction : float
        Fraction of L over which the half angle of entrance is measured (0.05 by default).
    c_stern : float
        Holtrop's stern-shape coefficient (0 normal sections by default; −25 pram, −10 V, +10 U).

    Returns
    -------
    HoltropHull
        Scalars ``L``, ``B``, ``T``, ``T_F``, ``h_B`` [m], ``volume`` [m³], ``S``, ``A_BT``, ``A_T`` [m²],
        ``cm``, ``cwp``, ``lcb`` [% L fwd of 0.5 L], ``ie`` [deg], ``c_stern``, ``bulb`` (1.0 where the FP area ``A_BT``
        is a bulb's: :func:`has_bulb` and ``A_BT`` > 0; for the warnings); no appendages.
    """
    t = jnp.asarray(draft, dtype=sections.yz.dtype)
    li = longitudinal_integrals(sections, t)
    x, bw = sections.x, li.half_breadth
    aft, fwd = li.x_aft, li.x_fwd  # the waterline's ends
    lcb = 100.0 * (li.lcb - 0.5 * (aft + fwd)) / li.lwl
    dx = entrance_fraction * li.lwl
    ie = jnp.degrees(jnp.arctan(jnp.interp(fwd - dx, x, bw) / dx))
    area_fp = jnp.interp(sections.lpp, x, li.area)
    mom_fp = jnp.interp(sections.lpp, x, li.moment_z)
    h_b = safe_div(mom_fp, area_fp, area_fp > 0.0)
    cm = jnp.interp(sections.lpp / 2.0, x, li.area) / (li.bwl * t)  # as hullopt.hydro.hydrostatics
    return HoltropHull(
        L=li.lwl, B=li.bwl, T=t, T_F=t, volume=li.volume, cm=cm, cwp=li.awp / (li.lwl * li.bwl), lcb=lcb,
        ie=ie, S=wetted_surface(sections, t), A_BT=area_fp, h_B=h_b, A_T=li.a_transom, c_stern=jnp.asarray(c_stern),
        bulb=jnp.where(area_fp > 0.0, has_bulb(sections, t), 0.0),  # a bulb reaching the FP (A_BT)
    )
