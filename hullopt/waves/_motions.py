"""Heave and pitch in regular waves by strip theory, and the motion-induced added resistance R_AWM.

Strip theory: Salvesen, Tuck & Faltinsen (1970), "Ship motions and sea loads", Trans. SNAME 78 (STF), with
its forward-speed terms and the transom end terms (only where the hull's aftmost station is wet, a real
transom; for a hull ending in a point, or a transom above the water, the end terms vanish). Sectional added
mass a33(x) and damping b33(x) at the encounter frequency come from each section's own shape by Frank's
close-fit method (:mod:`hullopt.waves._sections2d`), on ``n_strips`` (25) strips equally spaced over the wet
length with the half-sections interpolated between the hull's stations (the mass and restoring come from the
hull's own stations). Excitation: Froude–Krylov from the incident pressure over each section plus diffraction
by the 2D Haskind relation (STF eq. 45 form) with STF's speed terms.

R_AWM: Gerritsma & Beukelman (1972), "Analysis of the resistance increase in waves of a fast cargo ship",
ISP 19 — the energy radiated by the damping waves, R_GB = (k cos α/(2ω_e)) ∫ b'33 |V_z|² dx with the
speed-corrected damping b'33 = b33 − U da33/dx and the relative vertical velocity of each section and the
water V_z = iω_e(η3 − ξη5) + Uη5 − V_w, V_w = iω κ(x) ζ_a e^{ikξ cos α} the water's vertical velocity
(κ the section's Smith factor, the mean of e^{kz} over its wetted girth weighted as the waterplane breadth).

hullopt's motion part is R_AWM = R_GB(free ship) − R_GB(ship held fixed, V_z = −V_w), clipped at 0. The
fixed-ship term is GB's share of the diffraction (reflection) resistance — in short waves, where the ship
no longer moves, GB alone tends to it and not to 0 (KCS at Fn 0.26: σ 1.0 at λ/L 0.3, 2.6 at 0.5) — and
that share is what the NMRI reflection part R_AWR(Bf) models; subtracting it makes R_AW = R_AWM + R_AWR
count the reflection once (KCS: σ_AWM 0.03 at λ/L 0.3, peak 9.7 at λ/L 1.1). GB is a head-to-beam-seas
method: it is used for |α| ≤ 90°, and its value in following seas (cos α < 0) is clipped to 0. Validated
against Journée's four Wigley models (TU Delft report 909) at Fn ≤ :data:`MOTION_FN_MAX` and L/B ≥
:data:`MOTION_L_OVER_B_MIN`; beyond, GB overpredicts the tank's peaks (1.8× at Fn 0.3) and the commands warn
(:func:`motion_validity_warning`).

Conventions: x forward from the AP, ξ = x − LCB (the centre of gravity is at the LCB), z up; wave heading
α = 0 head seas; time dependence e^{iω_e t}; incident elevation ζ_a e^{i(ω_e t + kξ cos α + ky sin α)} at
the ship's frame; heave η3 up, pitch η5 bow down positive (vertical displacement η3 − ξη5). Encounter
frequency ω_e = ω + kU cos α.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Complex, Float

from .._types import Angle, Angles, Draft, Frequencies, Length, Lengths, Scalar, Speed
from ..constants import G, RHO_SEA
from ..errors import HullError
from ..geometry import TINY_LENGTH, Sections, longitudinal_integrals, natural_cubic_spline, simpson_weights
from ._sections2d import heave_potential, section_panels


class Motions(eqx.Module):
    """Heave and pitch of a hull in regular waves of unit amplitude, shape W (the frequencies').

    omega [rad/s], omega_e (encounter) [rad/s], k [1/m]; heave (complex) η3/ζ_a [m/m], pitch (complex)
    η5/ζ_a [rad/m] (bow down positive), with phases relative to the wave crest at the LCB; r_awm: the
    motion-induced added resistance [N] for ζ_a = 1 m (scales as ζ_a²).
    """

    omega: Float[Array, "*W"]
    omega_e: Float[Array, "*W"]
    k: Float[Array, "*W"]
    heave: Complex[Array, "*W"]
    pitch: Complex[Array, "*W"]
    r_awm: Float[Array, "*W"]

    @property
    def heave_rao(self) -> Array:
        """|η3|/ζ_a [m/m]."""
        return jnp.abs(self.heave)

    @property
    def pitch_rao(self) -> Array:
        """|η5|/(kζ_a) [-]."""
        return jnp.abs(self.pitch) / self.k


def _station_coefficients(nodes, omega_e, k, sin_a, rho, g, n_gauss):
    """One station at one encounter frequency: (a33, b33, FK factor, diffraction factor, Smith factor)."""
    phi, mid, length, normal = heave_potential(nodes, omega_e, g, n_gauss)
    integral = 2.0 * jnp.sum(phi * (normal[:, 1] * length).astype(complex))
    a33, b33 = -rho * integral.real, rho * omega_e * integral.imag
    y, z = mid[:, 0], mid[:, 1]
    ang = k * y * sin_a
    ekz = jnp.exp(k * z)
    fk = jnp.sum(2.0 * jnp.cos(ang) * ekz * normal[:, 1] * length)  # ∮ e^{kz} e^{iky sin α} n_z ds
    dif = jnp.sum(phi * (ekz * (2.0 * normal[:, 1] * jnp.cos(ang) - 2.0 * sin_a * normal[:, 0] * jnp.sin(ang))
                         * length).astype(complex))  # ∮ ψ3 e^{kz} e^{iky sin α}(n_z + i sin α n_y) ds
    # Smith factor: the e^{kz} mean over the wetted girth weighted as the waterplane breadth (fk/(−B_wl));
    # a section with (almost) no waterline breadth — a bulb below the waterline ahead of the stem — takes
    # e^{kz} at its mean depth instead.
    denom = jnp.sum(2.0 * normal[:, 1] * length)
    girth = jnp.sum(2.0 * length)
    flat_enough = jnp.abs(denom) > 0.05 * girth
    z_mean = jnp.sum(z * length) / jnp.sum(length)
    kappa = jnp.where(flat_enough, fk / jnp.where(flat_enough, denom, -1.0), jnp.exp(k * z_mean))
    return a33, b33, fk, dif, kappa


def _one_frequency(nodes, wet, x, w, xi, lcb_terms, omega, heading, speed, kyy_m, rho, g, n_gauss):
    mass, c33, c35, c55 = lcb_terms
    k = omega**2 / g
    cos_a, sin_a = jnp.cos(heading), jnp.sin(heading)
    we = omega + k * speed * cos_a
    we = jnp.maximum(jnp.abs(we), 1e-3 * jnp.sqrt(g / jnp.maximum(x[-1] - x[0], TINY_LENGTH)))
    a, b, fk, dif, kappa = jax.vmap(lambda nd: _station_coefficients(nd, we, k, sin_a, rho, g, n_gauss))(nodes)
    a, b = jnp.where(wet, a, 0.0), jnp.where(wet, b, 0.0)
    fk, dif, kappa = jnp.where(wet, fk, 0.0), jnp.where(wet, dif, 0.0), jnp.where(wet, kappa, 0.0)
    u = speed
    # Transom terms only where the hull's own aft end is wet (a real transom): the first strip is then the
    # aftmost station; on a hull ending in a point it is dry and the end terms vanish (before, the first wet
    # strip stood in for a transom: on the Wigley with 25 strips one of 16 % of the maximum breadth).
    transom = wet[0]
    aa, ba, xa = jnp.where(transom, a[0], 0.0), jnp.where(transom, b[0], 0.0), xi[0]
    a0, b0 = w @ a, w @ b
    a1, b1 = w @ (xi * a), w @ (xi * b)
    a2, b2 = w @ (xi**2 * a), w @ (xi**2 * b)
    we2 = we**2
    A33 = a0 - u / we2 * ba
    B33 = b0 + u * aa
    A35 = -a1 - u / we2 * b0 + u / we2 * xa * ba - u**2 / we2 * aa
    B35 = -b1 + u * a0 - u * xa * aa - u**2 / we2 * ba
    A53 = -a1 + u / we2 * b0 + u / we2 * xa * ba
    B53 = -b1 - u * a0 - u * xa * aa
    A55 = a2 + u**2 / we2 * a0 - u / we2 * xa**2 * ba + u**2 / we2 * xa * aa
    B55 = b2 + u**2 / we2 * b0 + u * xa**2 * aa + u**2 / we2 * xa * ba
    # Excitation for ζ_a = 1: Froude–Krylov and diffraction per unit length, then STF's speed terms.
    def c(v):
        return jnp.asarray(v).astype(complex)

    phase = jnp.exp(jax.lax.complex(jnp.zeros_like(xi), k * xi * cos_a))
    f_fk = c(-rho * g * fk) * phase
    h = c(rho * we * omega) * phase * dif
    wc, xic = c(w), c(xi)
    u_iwe = c(u) / jax.lax.complex(0.0, we)
    h_a = jnp.where(transom, h[0], 0.0)
    f3 = wc @ (f_fk + h) + u_iwe * h_a
    f5 = -(wc @ (xic * (f_fk + h))) - u_iwe * (wc @ h) - u_iwe * c(xa) * h_a
    i55 = mass * kyy_m**2

    def z(re, im):
        return jax.lax.complex(re, im)

    m = jnp.stack([jnp.stack([z(-we2 * (mass + A33) + c33, we * B33), z(-we2 * A35 + c35, we * B35)]),
                   jnp.stack([z(-we2 * A53 + c35, we * B53), z(-we2 * (i55 + A55) + c55, we * B55)])])
    eta = jnp.linalg.solve(m, jnp.stack([f3, f5]))
    eta3, eta5 = eta[0], eta[1]
    # Gerritsma–Beukelman radiated energy.
    v_water = z(0.0, omega) * c(kappa) * phase
    vz = z(0.0, we) * (eta3 - xic * eta5) + c(u) * eta5 - v_water
    b_prime = b - u * jnp.gradient(a, x)
    # GB for the free ship minus GB for the ship held fixed (the diffraction part, which R_AWR represents).
    r = k * cos_a / (2.0 * we) * (w @ (b_prime * (jnp.abs(vz) ** 2 - jnp.abs(v_water) ** 2)))
    r = jnp.maximum(r, 0.0)
    return we, k, eta3, eta5, r


def motions(sections: Sections, draft: Draft, speed: Speed, omega: Frequencies, heading: Angle = 0.0,
            kg: Length | None = None, kyy: Scalar = 0.25, *, n_panels: int = 12, n_gauss: int = 2,
            n_strips: int | None = 25, rho: float = RHO_SEA, g: float = G) -> Motions:
    """Heave and pitch RAOs and R_AWM of a hull in regular waves by strip theory (STF 1970 + Frank close-fit).

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline); even keel at ``draft``.
    draft : float
        Draft [m above the baseline].
    speed : float
        Ship speed U [m/s], ahead positive.
    omega : (W,) float
        Wave frequencies [rad/s] (> 0).
    heading : float
        Wave heading α [rad], 0 = head seas (scalar; vmap for several).
    kg : float or None
        Height of the centre of gravity above the baseline [m]; None: at the waterline (KG = draft). It enters
        only C55 through GM_L, where BM_L dominates.
    kyy : float
        Pitch radius of gyration as a fraction of Lpp.
    n_panels, n_gauss : int
        Panels per immersed half-section and Gauss points per panel for the wave term. Measured on the KCS
        at Fn 0.26 (σ_aw at λ/L 0.5–2): 12 panels agree with 20 and 40 to 0.01 (0.2 % at the peak), and
        n_gauss 2 with 4 to 0.02; the Wigley's RAOs against Capytaine do not change between 8 and 20 panels.
        The cost is about proportional to n_panels² · n_gauss.
    n_strips : int or None
        Strips along the wet length on which the sectional coefficients are computed (half-sections
        interpolated between the hull's stations; odd, for Simpson's rule); None: the hull's own stations.
        Strip theory needs 20–30 strips, so a mesh hull's 201 stations cost 8× more for nothing.
    rho, g : float
        Water density [kg/m³] and gravity [m/s²].

    Returns
    -------
    Motions
        Complex heave η3/ζ_a and pitch η5/ζ_a, ω, ω_e, k and R_AWM [N] for ζ_a = 1 m, each (W,).

    Notes
    -----
    Pure JAX: jit-, grad- and vmap-able in the hull, draft, speed, frequencies, KG and kyy. Mass ρ∇ with the
    centre of gravity at the LCB; restoring from the waterplane, C55 = ρg(I_L + A_wp(LCF − LCB)²) +
    ρg∇(KB − KG).
    """
    omega = jnp.atleast_1d(jnp.asarray(omega, dtype=float))
    one = _solver(sections, draft, speed, kg, kyy, n_panels, n_gauss, rho, g, n_strips)
    heading = jnp.asarray(heading, dtype=float)
    we, k, eta3, eta5, r = jax.vmap(lambda om: one(om, heading))(omega)
    return Motions(omega=omega, omega_e=we, k=k, heave=eta3, pitch=eta5, r_awm=r)


def _strips(sections, t, lcb, n_panels, n_strips):
    """The strips the sectional coefficients are computed on: ``n_strips`` stations equally spaced over the wet
    length (from the aftmost station with an immersed section — a transom stays the aft end — or the dry
    station just aft of it, to the foremost one or the dry station just ahead of it), each half-section
    interpolated linearly in x between its two neighbouring stations (point by point); ``n_strips=None`` uses
    the hull's own stations. Returns x (S,), Simpson weights (S,), ξ = x − LCB, panel nodes
    (S, n_panels+1, 2) and the wet mask (S,)."""
    x = jnp.asarray(sections.x, dtype=float)
    if n_strips is None:
        nodes, wet = section_panels(sections, t, n_panels)
        return x, simpson_weights(x), x - lcb, nodes, wet
    _, wet0 = section_panels(sections, t, 2)  # which stations are immersed (cheap: no solve)
    n = x.shape[0]
    x_lo = x[jnp.maximum(jnp.argmax(wet0) - 1, 0)]  # a pointed end: from the dry station before the first wet
    x_hi = x[jnp.minimum(n - jnp.argmax(wet0[::-1]), n - 1)]
    xs = x_lo + (x_hi - x_lo) * jnp.linspace(0.0, 1.0, n_strips)
    i = jnp.clip(jnp.searchsorted(x, xs, side="right", method="compare_all") - 1, 0, n - 2)
    f = jnp.clip((xs - x[i]) / (x[i + 1] - x[i]), 0.0, 1.0)[:, None, None]
    yz = jnp.asarray(sections.yz)
    # a + f·(b − a), not (1 − f)·a + f·b: a height both neighbours share (a waterline at the draft) stays exact,
    # so the draft-on-a-vertex rule of section_panels sees it (else it moves by an ulp, differently in each of
    # the compiled program's kernels: reverse-mode gradients 0.25 % off in head seas)
    strips = Sections(x=xs, yz=yz[i] + f * (yz[i + 1] - yz[i]), lpp=sections.lpp)
    nodes, wet = section_panels(strips, t, n_panels)
    return xs, simpson_weights(xs), xs - lcb, nodes, wet


@jax.custom_jvp
def _hydrostatics(sections, t):
    """:func:`~hullopt.geometry.longitudinal_integrals` whose derivative at a draft exactly on a vertex of the
    section polylines is the mean of the one-sided derivatives (there the waterplane has a kink: A_wp, LCF and
    I_L have different derivatives above and below it), what central differences measure; elsewhere the
    ordinary derivative (the two sides are one function)."""
    return longitudinal_integrals(sections, t)


@_hydrostatics.defjvp
def _hydrostatics_jvp(primals, tangents):
    sections, t = primals
    d_sections, dt = tangents
    t_up, t_down = jnp.nextafter(t, jnp.inf), jnp.nextafter(t, -jnp.inf)
    _, up = jax.jvp(longitudinal_integrals, (sections, t_up), (d_sections, dt))
    _, down = jax.jvp(longitudinal_integrals, (sections, t_down), (d_sections, dt))
    return longitudinal_integrals(sections, t), jax.tree_util.tree_map(lambda a, b: 0.5 * (a + b), up, down)


def _solver(sections, draft: Draft, speed: Speed, kg, kyy, n_panels, n_gauss, rho, g, n_strips=None):
    """The hull's frequency-independent parts, and ``(omega, heading) -> (ω_e, k, η3, η5, R_AWM)``."""
    if n_strips is not None and (not isinstance(n_strips, int) or n_strips < 5 or n_strips % 2 == 0):
        raise HullError(f"n_strips: expected an odd integer >= 5 (or None for the hull's stations), got {n_strips!r}")
    t = jnp.asarray(draft, dtype=sections.yz.dtype)
    li = _hydrostatics(sections, t)
    kg_ = t if kg is None else jnp.asarray(kg, dtype=float)
    mass = rho * li.volume
    c33 = rho * g * li.awp
    c35 = -rho * g * li.awp * (li.lcf - li.lcb)
    c55 = rho * g * (li.i_l + li.awp * (li.lcf - li.lcb) ** 2) + rho * g * li.volume * (li.kb - kg_)
    x, w, xi, nodes, wet = _strips(sections, t, li.lcb, n_panels, n_strips)
    kyy_m = kyy * sections.lpp
    speed = jnp.asarray(speed, dtype=float)

    def one(om, hd):
        return _one_frequency(nodes, wet, x, w, xi, (mass, c33, c35, c55), om, hd, speed, kyy_m, rho, g, n_gauss)

    return one


def motion_added_resistance(sections: Sections, draft: Draft, speed: Speed, omega: Frequencies, heading: Angles = 0.0,
                            amplitude: Lengths = 1.0, *, kg: Length | None = None, kyy: Scalar = 0.25,
                            n_panels: int = 12, n_gauss: int = 2, n_strips: int | None = 25, rho: float = RHO_SEA,
                            g: float = G) -> Array:
    """R_AWM [N] in regular waves of amplitude ``amplitude`` [m], frequencies ``omega`` (W,) [rad/s] and
    headings ``heading`` (H,) [rad] (0 head seas), shape W + H as the other methods' (``omega`` outer
    ``heading``); see :func:`motions` for the model and the other parameters.

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline); even keel at ``draft``.
    draft : float
        Draft [m above the baseline].
    speed : float
        Ship speed U [m/s], ahead positive.
    omega : float or Array
        Wave frequencies [rad/s] (> 0), any shape W.
    heading : float or Array
        Wave headings α [rad], 0 = head seas, any shape H.
    amplitude : float or Array
        Wave amplitude ζ_a [m].
    kg, kyy, n_panels, n_gauss, n_strips, rho, g
        As :func:`motions` takes them (KG [m], k_yy/Lpp, discretisation, ρ [kg/m³], g [m/s²]).

    Returns
    -------
    Array
        R_AWM [N], positive a resistance, shape W + H.
    """
    omega = jnp.asarray(omega, dtype=float)
    heading = jnp.asarray(heading, dtype=float)
    om = omega.reshape(omega.shape + (1,) * heading.ndim)
    om, hd = jnp.broadcast_arrays(om, heading)
    one = _solver(sections, draft, speed, kg, kyy, n_panels, n_gauss, rho, g, n_strips)
    r = jax.vmap(lambda o, h: one(o, h)[4])(om.ravel(), hd.ravel())
    return jnp.asarray(amplitude, dtype=float) ** 2 * r.reshape(om.shape)


# Where the motion part R_AWM (strip theory + Gerritsma–Beukelman) holds, measured against Journée's four Wigley
# models (1992, TU Delft report 909; tests/test_motions_journee.py): peak σ_aw (R_AWM + NMRI's R_AWR) 0.93 and
# 0.88 of the tank at Fn 0.2 on the slender models (L/B 10), 0.82 and 0.55 on the beamy ones (L/B 5); at Fn 0.3
# 1.75–1.8× on the slender ones (heave at resonance within 10 %: GB's energy balance counts every radiated wave
# as resistance, and strip theory's pitch at speed is off), at Fn 0.4 1.8–4.2×.
# Against the tank's peaks interpolated linearly in Fn (I, III): 1.09/1.03 at Fn 0.22, 1.24/1.23 at 0.24,
# 1.33/1.30 at 0.25, 1.37/1.43 at 0.26 — hence the limit. Salvesen's (1978) motion term ½k cos α Im Σ η̄_j F_j
# (F_j Froude–Krylov + diffraction), tried on the same motions: 0.77/0.85 at Fn 0.2, 1.38/1.53 at 0.3, 1.8/1.5 at
# 0.4 (I/III) — rising with Fn as GB does where the tank's peak falls (I: 31.8, 27.6, 14.9): the excess is in
# strip theory's motions at speed, not in the energy formula, so GB stays.
MOTION_FN_MAX = 0.25
MOTION_L_OVER_B_MIN = 7.0


def motion_validity_warning(fn: float, lpp_over_b: float) -> str | None:
    """A one-line warning where the motion part R_AWM is outside the range it was validated in (Froude number
    ``fn`` > :data:`MOTION_FN_MAX` or L/B ``lpp_over_b`` < :data:`MOTION_L_OVER_B_MIN`), else None.

    Parameters
    ----------
    fn : float
        Froude number U/√(g Lpp) [-].
    lpp_over_b : float
        Length between perpendiculars over the waterline beam [-].

    Returns
    -------
    str or None
        The warning's text (the validated range and why this case is outside it), or None inside the range.
    """
    why = []
    if fn > MOTION_FN_MAX:
        why.append(f"Fn {fn:.2f} > {MOTION_FN_MAX:g} (Journée's slender Wigleys: 1.8× the tank's peak at Fn 0.3, "
                   "up to 4× at 0.4)")
    if lpp_over_b < MOTION_L_OVER_B_MIN:
        why.append(f"L/B {lpp_over_b:.1f} < {MOTION_L_OVER_B_MIN:g} "
                   "(Journée's L/B 5 Wigleys: 0.55–0.8 of the tank)")
    if not why:
        return None
    return (f"the motion part R_AWM (strip theory, Gerritsma–Beukelman) holds at Fn ≤ {MOTION_FN_MAX:g} on hulls "
            f"with L/B ≥ {MOTION_L_OVER_B_MIN:g} (peak σ_aw within 20 % of Journée's slender Wigley models at "
            "Fn 0.2); here " + "; ".join(why))


# λ/L knots of the motion part's response in a sea state (:func:`motion_response`): R_AWM(λ/L) is a resonance
# peak (λ/L ≈ 0.9–1.3 in head seas at Fn 0.2–0.35); outside 0.3–3 it is < 3 % of its peak on the Wigley and the
# KCS in head seas (0 beyond λ/L ≈ 2.3, where GB's free-ship share falls below the fixed ship's).
MOTION_LAMBDA_RANGE = (0.3, 3.0)


def motion_response(sections: Sections, draft: Draft, speed: Speed, *, knots: int = 20, kg: Length | None = None,
                    kyy: Scalar = 0.25, n_panels: int = 12, n_gauss: int = 2, n_strips: int | None = 25,
                    rho: float = RHO_SEA, g: float = G):
    """R_AWM/ζ_a² as a function of frequency and heading for a sea-state mean: computed by strip theory at
    ``knots`` wavelengths equally spaced in ln(λ/L) over :data:`MOTION_LAMBDA_RANGE` (the ship's own scale, so
    the cost does not depend on the spectrum's quadrature) and interpolated by a natural cubic spline in
    ln(λ/L); 0 outside the range, clipped at 0.

    Measured against a 100-point reference curve (Wigley at Fn 0.25 and 0.35, KCS at Fn 0.26; headings 0° and
    45°; Bretschneider and JONSWAP γ 3.3 with T_p 5–18 s): with 20 knots the mean is within 1.4 % of the
    largest mean over T_p (median 0.07 %), where the 54 spectral nodes per heading used before were off up to
    28 % (KCS, T_p 12 s: the nodes follow the spectrum, not the ship's response peak).

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    draft : float
        Draft [m above the baseline].
    speed : float
        Ship speed U [m/s], ahead positive.
    knots : int
        Number of λ/L knots (≥ 4).
    kg, kyy, n_panels, n_gauss, n_strips, rho, g
        As :func:`motions` takes them (KG [m], k_yy/Lpp, discretisation, ρ [kg/m³], g [m/s²]).

    Returns
    -------
    callable
        ``response(omega (k,), heading (h,)) -> (k, h)``: R_AWM/ζ_a² [N/m²] at wave frequencies ω [rad/s] and
        headings α [rad] (0 head seas), the form :func:`~hullopt.waves.spectral_mean` takes.
    """
    if not isinstance(knots, int) or knots < 4:
        raise HullError(f"knots: expected an integer >= 4, got {knots!r}")
    lo, hi = np.log(MOTION_LAMBDA_RANGE[0]), np.log(MOTION_LAMBDA_RANGE[1])
    t_knots = np.linspace(lo, hi, knots)
    lpp = sections.lpp
    omega_knots = jnp.sqrt(2.0 * jnp.pi * g / (jnp.asarray(np.exp(t_knots)) * lpp))

    def response(omega, heading):
        omega = jnp.asarray(omega, dtype=float)
        r = motion_added_resistance(sections, draft, speed, omega_knots, heading, 1.0, kg=kg, kyy=kyy,
                                    n_panels=n_panels, n_gauss=n_gauss, n_strips=n_strips, rho=rho, g=g)
        spline = natural_cubic_spline(jnp.asarray(t_knots), r)
        t = jnp.log(2.0 * jnp.pi * g / (jnp.maximum(omega, 1e-9) ** 2 * lpp))
        inside = (t >= lo) & (t <= hi)
        v = spline(jnp.clip(t, lo, hi))
        inside = inside.reshape(inside.shape + (1,) * (v.ndim - inside.ndim))
        return jnp.where(inside, jnp.maximum(v, 0.0), 0.0)

    return response


__all__ = ["MOTION_FN_MAX", "MOTION_LAMBDA_RANGE", "MOTION_L_OVER_B_MIN", "Motions", "motion_added_resistance",
           "motion_response", "motion_validity_warning", "motions"]
