"""Semi-empirical methods users compare the NMRI formula with: STAWAVE-1, STAWAVE-2, SNNM (METHODS.md §2).

Every method returns the motion-induced and reflection parts side by side, in regular waves of amplitude
ζ_a, as :class:`WaveResistance` (shape W + H for ``omega`` W and ``heading`` H). Conventions: α = 0 head
seas (folded to [0, π] by symmetry), Fr on Lpp, kyy the pitch radius of gyration over Lpp. The hull enters
through :class:`Particulars` (Lpp, B_wl, T, C_B and waterline lengths), all computed from the sections.

Each method is a :class:`WaveMethod` (NMRI, STAWAVE-1, STAWAVE-2, SNNM), registered in :data:`WAVE_METHODS` by
name: what it includes, where it applies, its kinks in heading, its R_AW in regular waves and in a sea state.
:func:`method_resistance`, :func:`heading_breaks` and :func:`mean_added_resistance` take the name.
"""

from __future__ import annotations

import abc
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._types import Angle, Angles, Density, Draft, Frequencies, Gravity, Length, Lengths, Period, Scalar, Speed
from ..constants import G, RHO_SEA
from ..geometry import DIVISION_FLOOR, Sections, longitudinal_integrals
from ._added_resistance import BF_KINK, outer_grid, froude_number, nmri_added_resistance
from ._motions import motion_added_resistance, motion_response
from ._bessel import alpha_t
from ._spectra import spectral_mean
from ._waterline import bluntness_of_waterline, entrance_lengths, waterline


class Particulars(eqx.Module):
    """Main particulars at a draft [m]: ``lpp``, ``beam`` (B_wl), ``draft``, ``cb`` (on Lpp·B_wl·T), ``l_bwl``
    (stem to 95 % of the maximum breadth, STAWAVE-1), ``l_entrance``, ``l_run`` (ends to 99 %, SNNM)."""

    lpp: Float[Array, ""]
    beam: Float[Array, ""]
    draft: Float[Array, ""]
    cb: Float[Array, ""]
    l_bwl: Float[Array, ""]
    l_entrance: Float[Array, ""]
    l_run: Float[Array, ""]


def particulars(sections: Sections, draft: Draft) -> Particulars:
    """:class:`Particulars` of the hull at ``draft`` (even keel); exact for the polyline sections,
    Simpson along x.

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    draft : float or Array
        Draft T [m above the baseline] (scalar).

    Returns
    -------
    Particulars
        Lpp, B_wl, T [m], C_B (dimensionless) and the waterline lengths L_BWL, L_E, L_R [m], all scalars.
    """
    t = jnp.asarray(draft, dtype=sections.yz.dtype)
    wl = waterline(sections, t)
    volume = longitudinal_integrals(sections, t).volume
    b = wl.beam
    l_bwl, _ = entrance_lengths(wl, 0.95)
    l_e, l_r = entrance_lengths(wl, 0.99)
    return Particulars(lpp=sections.lpp, beam=b, draft=t, cb=volume / (sections.lpp * b * t), l_bwl=l_bwl,
                       l_entrance=l_e, l_run=l_r)


class WaveResistance(eqx.Module):
    """Added resistance in regular waves [N], shape W + H: ``motion`` + ``reflection`` = ``total``."""

    motion: Float[Array, "*shape"]
    reflection: Float[Array, "*shape"]

    @property
    def total(self) -> Array:
        return self.motion + self.reflection


def _pos_pow(x, p):
    """x^p for x > 0, 0 for x ≤ 0, with a finite gradient at 0 (double where)."""
    pos = x > 0.0
    return jnp.where(pos, jnp.where(pos, x, 1.0) ** p, 0.0)


def _jf_shape(wbar, d_low, d_high):
    """Jinkine–Ferdinande form ω̄^b exp[(b/d)(1 − ω̄^d)], b = 11, d = d_low for ω̄ < 1; b = −8.5, d = d_high
    above (continuous at ω̄ = 1; 0 at ω̄ = 0 with finite gradients)."""
    low = wbar < 1.0
    wl, wh = jnp.where(low, wbar, 0.5), jnp.where(low, 2.0, wbar)
    lo = _pos_pow(wl, 11.0) * jnp.exp(11.0 / d_low * (1.0 - _pos_pow(wl, d_low)))
    hi = wh**-8.5 * jnp.exp(-8.5 / d_high * (1.0 - wh**d_high))
    return jnp.where(low, lo, hi)


def _fold(heading):
    """Heading folded to [0, π] (the hull is symmetric); differentiable, with derivative 0 at α = 0."""
    return jnp.abs(jnp.mod(heading + jnp.pi, 2.0 * jnp.pi) - jnp.pi)


def _within_45(heading):
    return jnp.cos(heading) >= jnp.cos(jnp.pi / 4) - 1e-12


def stawave1(p: Particulars, omega: Frequencies, heading: Angles = 0.0, amplitude: Lengths = 1.0,
             rho: Density = RHO_SEA, g: Gravity = G) -> WaveResistance:
    """STAWAVE-1 (ITTC 7.5-04-01-01.1, ISO 15016): R = (1/16)ρgH_s²B√(B/L_BWL) in a sea state, i.e. the
    frequency-independent reflection ½ρgζ_a²B√(B/L_BWL) per regular wave (so the spectral mean gives the
    published formula exactly); heading within ±45° of the bow only, no speed dependence, no motion part.

    Parameters
    ----------
    p : Particulars
        Main particulars (:func:`particulars`).
    omega : float or Array
        Wave circular frequencies ω [rad/s], any shape W (the result does not depend on them).
    heading : float or Array
        Wave headings α [rad], 0 = head seas, any shape H.
    amplitude : float or Array
        Wave amplitude ζ_a [m].
    rho, g : float
        Water density [kg/m³] and gravity [m/s²].

    Returns
    -------
    WaveResistance
        ``motion`` (0) and ``reflection`` [N], shape W + H.
    """
    om, hd = outer_grid(omega, heading)
    r = 0.5 * rho * g * amplitude**2 * p.beam * jnp.sqrt(p.beam / p.l_bwl)
    r = jnp.where(_within_45(hd), r, 0.0) * jnp.ones_like(om)
    return WaveResistance(motion=jnp.zeros_like(r), reflection=r)


def stawave2(p: Particulars, speed: Speed, omega: Frequencies, heading: Angles = 0.0, amplitude: Lengths = 1.0,
             kyy: Scalar = 0.25, rho: Density = RHO_SEA, g: Gravity = G) -> WaveResistance:
    """STAWAVE-2 (ITTC 7.5-04-01-01.1, ISO 15016:2015; METHODS §2.2), headings within ±45° of the bow.

    R_AWML = 4ρgζ²(B²/L) ω̄^b1 exp[(b1/d1)(1 − ω̄^d1)] 60.3 C_B^1.34 Fr^1.5 e^(−3.5Fr),
    ω̄ = √(L/g) kyy^(1/3) ω Fr^0.143/1.17; R_AWRL = ½ρgζ²B α_T(1.5kT) f1, f1 = 0.692 (U/√(gT))^0.769 + 1.81 C_B^6.95.

    Parameters
    ----------
    p : Particulars
        Main particulars (:func:`particulars`).
    speed : float or Array
        Ship speed U [m/s] (scalar), ahead positive.
    omega : float or Array
        Wave circular frequencies ω [rad/s], any shape W.
    heading : float or Array
        Wave headings α [rad], 0 = head seas, any shape H.
    amplitude : float or Array
        Wave amplitude ζ_a [m].
    kyy : float or Array
        Pitch radius of gyration over Lpp (dimensionless).
    rho, g : float
        Water density [kg/m³] and gravity [m/s²].

    Returns
    -------
    WaveResistance
        ``motion`` (R_AWML) and ``reflection`` (R_AWRL) [N], shape W + H; 0 beyond ±45° of the bow.
    """
    om, hd = outer_grid(omega, heading)
    lpp, b, t, cb = p.lpp, p.beam, p.draft, p.cb
    fr = froude_number(speed, lpp, g)
    wbar = jnp.sqrt(lpp / g) * kyy ** (1.0 / 3.0) * om * _pos_pow(fr, 0.143) / 1.17
    shape = _jf_shape(wbar, 14.0, -566.0 * (lpp / b) ** -2.66)
    r_aw = shape * 60.3 * cb**1.34 * _pos_pow(fr, 1.5) * jnp.exp(-3.5 * fr)
    ok = _within_45(hd)
    motion = jnp.where(ok, 4.0 * rho * g * amplitude**2 * b**2 / lpp * r_aw, 0.0)
    f1 = 0.692 * _pos_pow(speed / jnp.sqrt(t * g), 0.769) + 1.81 * cb**6.95
    refl = 0.5 * rho * g * amplitude**2 * b * alpha_t(1.5 * om**2 / g * t) * f1
    return WaveResistance(motion=motion, reflection=jnp.where(ok, refl, 0.0) * jnp.ones_like(motion))


def snnm(p: Particulars, speed: Speed, omega: Frequencies, heading: Angles = 0.0, amplitude: Lengths = 1.0,
         kyy: Scalar = 0.25, rho: Density = RHO_SEA, g: Gravity = G) -> WaveResistance:
    """SNNM (Liu & Papanikolaou 2020; ITTC 7.5-04-01-01.1 Rev 06), all headings; METHODS §2.3, even keel.

    Motion part as published for 0 ≤ α ≤ π/2; for π/2 < α ≤ π it is taken linearly in α down to 0 at
    following seas (the public codes disagree on the following-sea expression, METHODS §2.3 caveat 1).
    Reflection part R1–R4 for all headings with E1, E2 from the entrance and run lengths at 99 % breadth
    and the fullness factor on R1, R2 only. σ = R/(ρgζ²B²/L).

    Parameters
    ----------
    p : Particulars
        Main particulars (:func:`particulars`).
    speed : float or Array
        Ship speed U [m/s] (scalar), ahead positive.
    omega : float or Array
        Wave circular frequencies ω [rad/s], any shape W.
    heading : float or Array
        Wave headings α [rad], 0 = head seas, any shape H.
    amplitude : float or Array
        Wave amplitude ζ_a [m].
    kyy : float or Array
        Pitch radius of gyration over Lpp (dimensionless).
    rho, g : float
        Water density [kg/m³] and gravity [m/s²].

    Returns
    -------
    WaveResistance
        ``motion`` and ``reflection`` [N], shape W + H.
    """
    om, hd = outer_grid(omega, heading)
    a = _fold(hd)
    lpp, b, t, cb = p.lpp, p.beam, p.draft, p.cb
    fr = froude_number(speed, lpp, g)
    k = om**2 / g
    sqrt_l_over_lambda = jnp.sqrt(lpp * k / (2.0 * jnp.pi))
    # Motion part, evaluated at min(α, π/2) and ramped to 0 at π.
    am = jnp.minimum(a, 0.5 * jnp.pi)
    ca = jnp.cos(am)
    wbar = (2.142 * kyy ** (1.0 / 3.0) * sqrt_l_over_lambda * (cb / 0.65) ** 0.17
            * (1.0 - 0.111 / cb * (jnp.log(b / t) - jnp.log(2.75)))
            * ((-1.377 * fr**2 + 1.157 * fr) * jnp.abs(ca) + 0.618 * (13.0 + jnp.cos(2.0 * am)) / 14.0))
    theta = 0.0  # even keel: θ = atan(|T_A − T_F|/L)
    shape = _jf_shape(wbar, 566.0 * (lpp * cb / b) ** -2.66, -566.0 * (lpp / b) ** -2.66 * (4.0 - 125.0 * theta))
    a1 = (0.87 / cb) ** ((1.0 + fr) * ca) / jnp.log(b / t) * (1.0 + 2.0 * ca) / 3.0
    a2 = jnp.where(fr < 0.12, 0.0072 + 0.1676 * fr, _pos_pow(fr, 1.5) * jnp.exp(-3.5 * fr))
    a3 = 1.0 + 28.7 * theta
    sig_m = 3859.2 * cb**1.34 * kyy**2 * a1 * a2 * a3 * shape
    sig_m = sig_m * jnp.where(a <= 0.5 * jnp.pi, 1.0, (jnp.pi - a) / (0.5 * jnp.pi))
    # Reflection part.
    e1 = jnp.arctan(0.99 * 0.5 * b / p.l_entrance)
    e2 = jnp.arctan(0.99 * 0.5 * b / p.l_run)
    two_wu_g = 2.0 * om * speed / g

    def kern(e, ang):
        return jnp.sin(ang) ** 2 + two_wu_g * (jnp.cos(a) - jnp.cos(e) * jnp.cos(ang))

    lam_over_l = 2.0 * jnp.pi / jnp.maximum(k * lpp, DIVISION_FLOOR)

    def a_t(ti):
        return jnp.where(lam_over_l <= 2.5, 1.0 - jnp.exp(-4.0 * jnp.pi * (ti * k / (2 * jnp.pi) - ti / (2.5 * lpp))), 0.0)

    t12 = t
    root = _pos_pow(jnp.abs(jnp.cos(a)), 0.5)
    t34 = jnp.where(cb <= 0.75, t * (4.0 + root) / 5.0, t * (2.0 + root) / 3.0)
    c12 = (0.87 / cb) ** ((1.0 + 4.0 * _pos_pow(fr, 0.5)) * jnp.where(a <= e1, jnp.cos(a), 0.0))
    sig_r = (jnp.where(a <= jnp.pi - e1, a_t(t12) * kern(e1, e1 + a) * c12, 0.0)
             + jnp.where(a <= e1, a_t(t12) * kern(e1, e1 - a) * c12, 0.0)
             - jnp.where(a >= e2, a_t(t34) * kern(e2, e2 - a), 0.0)
             - jnp.where(a >= jnp.pi - e2, a_t(t34) * kern(e2, e2 + a), 0.0))
    sig_r = 2.25 / 4.0 * lpp / b * sig_r
    scale = rho * g * amplitude**2 * b**2 / lpp
    return WaveResistance(motion=scale * sig_m, reflection=scale * sig_r)


# ------------------------------------------------------------------------------------------ the methods as classes

WAVE_METHODS: dict[str, type[WaveMethod]] = {}
"""The added-resistance methods by name (``hullopt waves --method``), filled by defining a subclass of
:class:`WaveMethod`."""


class WaveMethod(eqx.Module):
    """A method of added resistance in waves: ``method(sections, draft, speed, omega, heading, amplitude)`` →
    :class:`WaveResistance` [N] in regular waves (shape W + H), and :meth:`mean` in a sea state.

    Subclasses set the class variables ``name`` (unique; what ``--method`` takes), ``description`` (one line:
    what its R_AW counts, as ``hullopt waves`` prints it), ``includes`` (the parts it has, of ``"motion"`` and
    ``"reflection"``) and ``headings`` (where it applies, in words), and implement ``__call__``,
    :meth:`valid` and :meth:`heading_breaks`. Defining one registers it in :data:`WAVE_METHODS`. Headings:
    α [rad], 0 = head seas.
    """

    name: eqx.AbstractClassVar[str]
    description: eqx.AbstractClassVar[str]
    includes: eqx.AbstractClassVar[tuple[str, ...]]
    headings: eqx.AbstractClassVar[str]

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        name = cls.__dict__.get("name")
        if isinstance(name, str):
            if name in WAVE_METHODS and WAVE_METHODS[name].__qualname__ != cls.__qualname__:
                raise TypeError(f"wave method name {name!r} is taken by {WAVE_METHODS[name].__qualname__}")
            WAVE_METHODS[name] = cls

    @abc.abstractmethod
    def __call__(self, sections: Sections, draft: Draft, speed: Speed, omega: Frequencies, heading: Angles = 0.0,
                 amplitude: Lengths = 1.0, *, kyy: Scalar = 0.25, rho: Density = RHO_SEA, g: Gravity = G,
                 smooth: float | None = None, aft: str = "exclude", kg: Length | None = None,
                 motion: bool = True, band: float = 0.0) -> WaveResistance:
        """Added resistance [N] in regular waves of amplitude ζ_a [m], shape W + H for ``omega`` [rad/s] W and
        ``heading`` [rad] H, as :func:`method_resistance` takes the arguments (those the method does not use
        are ignored)."""

    @abc.abstractmethod
    def valid(self, heading: Angles) -> Array:
        """Whether the method applies at ``heading`` [rad] (bool, the shape of ``heading``); elsewhere its
        R_AW is 0."""

    @abc.abstractmethod
    def heading_breaks(self, sections: Sections, draft: Draft, aft: str = "exclude") -> Array:
        """Headings [rad] where the response has a kink or a jump in heading (:func:`heading_breaks`)."""

    def label(self, motion: bool = True) -> str:
        """What this method's R_AW counts (``description``); ``motion=False`` for a method whose motion part
        can be left out says so."""
        return self.description

    def reflection_directions(self, n_dir: int) -> int:
        """Points of the direction integral of the reflection part for ``n_dir`` of the motion part."""
        return n_dir

    def mean(self, sections: Sections, draft: Draft, speed: Speed, hs: Length, tp: Period, heading: Angle = 0.0, *,
             spectrum: str = "pm", gamma: Scalar = 3.3, spreading_s: float | None = None,
             omega_max: Scalar | None = None, kyy: Scalar = 0.25, rho: Density = RHO_SEA, g: Gravity = G,
             smooth: float | None = None, aft: str = "exclude", order: int = 8, n_dir: int = 16,
             kg: Length | None = None, motion: bool = True, motion_knots: int | None = 20,
             band: float = 0.0) -> WaveResistance:
        """Mean added resistance [N] in a sea state, as :func:`mean_added_resistance` takes the arguments: one
        spectral mean of both parts, the direction integral split at :meth:`heading_breaks`."""
        opts = self._spectral_options(sections, draft, aft, spectrum, gamma, spreading_s, omega_max, order)

        def response(om, hd):
            r = self(sections, draft, speed, om, hd, 1.0, kyy=kyy, rho=rho, g=g, smooth=smooth, aft=aft, kg=kg,
                     motion=motion, band=band)
            return jnp.stack([r.motion, r.reflection], axis=-1)

        m = spectral_mean(response, hs, tp, heading, n_dir=self.reflection_directions(n_dir), **opts)
        return WaveResistance(motion=m[0], reflection=m[1])

    def _spectral_options(self, sections, draft: Draft, aft, spectrum, gamma, spreading_s, omega_max, order) -> dict:
        return dict(spectrum=spectrum, gamma=gamma, spreading_s=spreading_s, omega_max=omega_max, order=order,
                    breaks=None if spreading_s is None else self.heading_breaks(sections, draft, aft))


class NMRI(WaveMethod):
    """NMRI (patent JP2009-286166): R_AW = R_AWM + R_AWR(Bf), the motion part by strip theory
    (:func:`~hullopt.waves.motion_added_resistance`, with ``kg`` [m] and ``kyy``; ``motion=False`` leaves it out,
    0), the reflection part by the patent's formula (:func:`~hullopt.waves.nmri_added_resistance`); all headings."""

    name: ClassVar[str] = "nmri"
    description: ClassVar[str] = "motion (strip theory) + reflection (Bf)"
    includes: ClassVar[tuple[str, ...]] = ("motion", "reflection")
    headings: ClassVar[str] = "all"

    def __call__(self, sections: Sections, draft: Draft, speed: Speed, omega: Frequencies, heading: Angles = 0.0,
                 amplitude: Lengths = 1.0, *, kyy: Scalar = 0.25, rho: Density = RHO_SEA, g: Gravity = G,
                 smooth: float | None = None, aft: str = "exclude", kg: Length | None = None,
                 motion: bool = True, band: float = 0.0) -> WaveResistance:
        r = nmri_added_resistance(sections, draft, speed, omega, heading, amplitude, rho=rho, g=g, smooth=smooth,
                                  aft=aft, band=band).r_awr
        if not motion:
            return WaveResistance(motion=jnp.zeros_like(r), reflection=r)
        m = motion_added_resistance(sections, draft, speed, omega, heading, amplitude, kg=kg, kyy=kyy, rho=rho, g=g)
        return WaveResistance(motion=m, reflection=r)

    def valid(self, heading: Angles) -> Array:
        return jnp.ones(jnp.shape(heading), dtype=bool)

    def label(self, motion: bool = True) -> str:
        return self.description if motion else "reflection only (Bf)"

    def reflection_directions(self, n_dir: int) -> int:
        # NMRI's reflection part has more structure in heading than its kinks (METHODS §2.6)
        return 5 * n_dir // 2

    def heading_breaks(self, sections: Sections, draft: Draft, aft: str = "exclude") -> Array:
        grid = jnp.linspace(0.0, jnp.pi, 64)
        bf = bluntness_of_waterline(waterline(sections, draft), grid, aft)
        out = []
        for level in (BF_KINK, 0.0) if aft == "include" else (BF_KINK,):
            d = bf - level
            cross = (d[:-1] > 0.0) != (d[1:] > 0.0)
            i = jnp.argsort(~cross, stable=True)[:2]  # the first two cells with a crossing
            d0, d1 = d[i], d[i + 1]
            ok = cross[i] & (d0 != d1)
            t = jnp.where(ok, d0 / jnp.where(ok, d0 - d1, 1.0), 0.0)
            root = jnp.where(ok, grid[i] + t * (grid[1] - grid[0]), 0.0)  # none: a harmless split at 0
            out += [root, -root]
        return jnp.concatenate(out)

    def mean(self, sections: Sections, draft: Draft, speed: Speed, hs: Length, tp: Period, heading: Angle = 0.0, *,
             spectrum: str = "pm", gamma: Scalar = 3.3, spreading_s: float | None = None,
             omega_max: Scalar | None = None, kyy: Scalar = 0.25, rho: Density = RHO_SEA, g: Gravity = G,
             smooth: float | None = None, aft: str = "exclude", order: int = 8, n_dir: int = 16,
             kg: Length | None = None, motion: bool = True, motion_knots: int | None = 20,
             band: float = 0.0) -> WaveResistance:
        """As :meth:`WaveMethod.mean`; with the motion part, the two parts apart: the motion part (smooth in
        heading) by one plain Gauss rule in direction, from ``motion_knots`` λ/L knots
        (:func:`~hullopt.waves.motion_response`; None: a strip-theory solve at every node)."""
        if not motion:
            return super().mean(sections, draft, speed, hs, tp, heading, spectrum=spectrum, gamma=gamma,
                                spreading_s=spreading_s, omega_max=omega_max, kyy=kyy, rho=rho, g=g, smooth=smooth,
                                aft=aft, order=order, n_dir=n_dir, kg=kg, motion=False, motion_knots=motion_knots,
                                band=band)
        opts = self._spectral_options(sections, draft, aft, spectrum, gamma, spreading_s, omega_max, order)

        def reflection(om, hd):
            return self(sections, draft, speed, om, hd, 1.0, rho=rho, g=g, smooth=smooth, aft=aft,
                        motion=False, band=band).reflection

        def motion_part(om, hd):
            return motion_added_resistance(sections, draft, speed, om, hd, 1.0, kg=kg, kyy=kyy, rho=rho, g=g)

        if motion_knots is not None:
            motion_part = motion_response(sections, draft, speed, knots=motion_knots, kg=kg, kyy=kyy, rho=rho, g=g)
        motion_opts = opts | {"breaks": None}  # one plain Gauss rule (smooth in heading)
        return WaveResistance(
            motion=spectral_mean(motion_part, hs, tp, heading, n_dir=n_dir, **motion_opts),
            reflection=spectral_mean(reflection, hs, tp, heading, n_dir=self.reflection_directions(n_dir), **opts))


class Stawave1(WaveMethod):
    """STAWAVE-1 (ITTC 7.5-04-01-01.1, ISO 15016; :func:`stawave1`): the reflection part only, independent of
    frequency and speed, within ±45° of the bow."""

    name: ClassVar[str] = "stawave1"
    description: ClassVar[str] = "reflection only, empirical"
    includes: ClassVar[tuple[str, ...]] = ("reflection",)
    headings: ClassVar[str] = "within ±45° of the bow"

    def __call__(self, sections: Sections, draft: Draft, speed: Speed, omega: Frequencies, heading: Angles = 0.0,
                 amplitude: Lengths = 1.0, *, kyy: Scalar = 0.25, rho: Density = RHO_SEA, g: Gravity = G,
                 smooth: float | None = None, aft: str = "exclude", kg: Length | None = None,
                 motion: bool = True, band: float = 0.0) -> WaveResistance:
        return stawave1(particulars(sections, draft), omega, heading, amplitude, rho, g)

    def valid(self, heading: Angles) -> Array:
        return _within_45(heading)

    def heading_breaks(self, sections: Sections, draft: Draft, aft: str = "exclude") -> Array:
        """±π/4: the ±45° validity limit, a jump to 0."""
        return jnp.array([0.25 * jnp.pi, -0.25 * jnp.pi])


class Stawave2(Stawave1):
    """STAWAVE-2 (ITTC 7.5-04-01-01.1, ISO 15016:2015; :func:`stawave2`): empirical motion and reflection
    parts, within ±45° of the bow."""

    name: ClassVar[str] = "stawave2"
    description: ClassVar[str] = "motion + reflection, empirical"
    includes: ClassVar[tuple[str, ...]] = ("motion", "reflection")

    def __call__(self, sections: Sections, draft: Draft, speed: Speed, omega: Frequencies, heading: Angles = 0.0,
                 amplitude: Lengths = 1.0, *, kyy: Scalar = 0.25, rho: Density = RHO_SEA, g: Gravity = G,
                 smooth: float | None = None, aft: str = "exclude", kg: Length | None = None,
                 motion: bool = True, band: float = 0.0) -> WaveResistance:
        return stawave2(particulars(sections, draft), speed, omega, heading, amplitude, kyy, rho, g)


class SNNM(WaveMethod):
    """SNNM (Liu & Papanikolaou 2020; ITTC 7.5-04-01-01.1 Rev 06; :func:`snnm`): empirical motion and
    reflection parts, all headings."""

    name: ClassVar[str] = "snnm"
    description: ClassVar[str] = "motion + reflection, empirical"
    includes: ClassVar[tuple[str, ...]] = ("motion", "reflection")
    headings: ClassVar[str] = "all"

    def __call__(self, sections: Sections, draft: Draft, speed: Speed, omega: Frequencies, heading: Angles = 0.0,
                 amplitude: Lengths = 1.0, *, kyy: Scalar = 0.25, rho: Density = RHO_SEA, g: Gravity = G,
                 smooth: float | None = None, aft: str = "exclude", kg: Length | None = None,
                 motion: bool = True, band: float = 0.0) -> WaveResistance:
        return snnm(particulars(sections, draft), speed, omega, heading, amplitude, kyy, rho, g)

    def valid(self, heading: Angles) -> Array:
        return jnp.ones(jnp.shape(heading), dtype=bool)

    def heading_breaks(self, sections: Sections, draft: Draft, aft: str = "exclude") -> Array:
        """±E1 (the reflection's fullness factor switches: a jump), ±E2 (kinks; a kink at θ is one at θ ± π
        too, so ±(π − E1), ±(π − E2) need no entry), π/2 (the motion part's cap and the |cos α|^½ in T34) and
        0 ≡ π (the fold in following seas)."""
        p = particulars(sections, draft)
        e1 = jnp.arctan(0.99 * 0.5 * p.beam / p.l_entrance)
        e2 = jnp.arctan(0.99 * 0.5 * p.beam / p.l_run)
        return jnp.stack([e1, -e1, e2, -e2, jnp.full_like(e1, 0.5 * jnp.pi), jnp.zeros_like(e1)])


METHODS = tuple(WAVE_METHODS)
"""The names of :data:`WAVE_METHODS`, in the order they are defined."""


def wave_method(method: str) -> WaveMethod:
    """The method named ``method``, a :class:`WaveMethod`.

    Parameters
    ----------
    method : str
        One of :data:`METHODS` (``"nmri"``, ``"stawave1"``, ``"stawave2"``, ``"snnm"``).

    Returns
    -------
    WaveMethod
        An instance of ``WAVE_METHODS[method]``.

    Raises
    ------
    ValueError
        If ``method`` is not one of :data:`METHODS`.
    """
    if method not in WAVE_METHODS:
        raise ValueError(f"method {method!r}: expected one of {METHODS}")
    return WAVE_METHODS[method]()


def method_resistance(method: str, sections: Sections, draft: Draft, speed: Speed, omega: Frequencies,
                      heading: Angles = 0.0, amplitude: Lengths = 1.0, *, kyy: Scalar = 0.25, rho: Density = RHO_SEA,
                      g: Gravity = G, smooth: float | None = None, aft: str = "exclude", kg: Length | None = None,
                      motion: bool = True, band: float = 0.0) -> WaveResistance:
    """Added resistance [N] in regular waves by ``method`` (one of :data:`METHODS`), motion and reflection
    parts. NMRI: R_AW = R_AWM + R_AWR(Bf), the motion part by strip theory
    (:func:`~hullopt.waves.motion_added_resistance`, with ``kg`` [m] and ``kyy``; ``motion=False`` leaves it
    out, 0), the reflection part by the patent's formula.

    Parameters
    ----------
    method : str
        One of :data:`METHODS` (``"nmri"``, ``"stawave1"``, ``"stawave2"``, ``"snnm"``).
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    draft : float or Array
        Draft T [m above the baseline] (scalar).
    speed : float or Array
        Ship speed U [m/s] (scalar), ahead positive.
    omega : float or Array
        Wave circular frequencies ω [rad/s], any shape W.
    heading : float or Array
        Wave headings α [rad], 0 = head seas, any shape H.
    amplitude : float or Array
        Wave amplitude ζ_a [m].
    kyy : float or Array
        Pitch radius of gyration over Lpp (STAWAVE-2, SNNM, and NMRI's motion part).
    rho, g : float
        Water density [kg/m³] and gravity [m/s²].
    smooth, aft
        NMRI only: as :func:`nmri_added_resistance` takes them.
    kg : float or None
        NMRI only: KG [m] for the motion part (None: KG = draft).
    motion : bool
        NMRI only: include the strip-theory motion part (False: it is 0).
    band : float
        NMRI only: Bf over the waterlines within ``band`` [m] of the draft (:func:`~hullopt.waves.bluntness`).

    Returns
    -------
    WaveResistance
        ``motion``, ``reflection`` and ``total`` [N], shape W + H.

    Raises
    ------
    ValueError
        If ``method`` is not one of :data:`METHODS`.
    """
    return wave_method(method)(sections, draft, speed, omega, heading, amplitude, kyy=kyy, rho=rho, g=g,
                               smooth=smooth, aft=aft, kg=kg, motion=motion, band=band)


def heading_breaks(method: str, sections: Sections, draft: Draft, aft: str = "exclude") -> Array:
    """Headings [rad] (0 = head seas) where ``method``'s response has a kink or a jump in heading, for the
    direction integral of a short-crested sea (:func:`~hullopt.waves.spectral_mean`'s ``breaks``).

    STAWAVE-1/2: ±π/4 (the ±45° validity limit, a jump to 0). SNNM: ±E1 (its reflection's fullness factor
    switches: a jump), ±E2 (kinks; a kink at θ is one at θ ± π too, so ±(π − E1), ±(π − E2) need no entry),
    π/2 (its motion part's cap and the |cos α|^½ in T34) and 0 ≡ π (the fold in following seas). NMRI's
    reflection: where Bf(α) crosses the C_U kink 0.1871 (and 0 with ``aft="include"``), the first two
    crossings over 0 … π on a 64-heading grid, linearly interpolated and mirrored (differentiable: the
    gradient is that of the quadrature as computed).

    Parameters
    ----------
    method : str
        One of :data:`METHODS`.
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    draft : float or Array
        Draft T [m above the baseline] (scalar).
    aft : {"exclude", "include"}
        NMRI's lit range (:func:`~hullopt.waves.bluntness_of_waterline`).

    Returns
    -------
    Array
        Headings [rad], shape (2,) STAWAVE, (6,) SNNM, (4,) or (8,) NMRI.

    Raises
    ------
    ValueError
        If ``method`` is not one of :data:`METHODS`.
    """
    return wave_method(method).heading_breaks(sections, draft, aft)


def mean_added_resistance(method: str, sections: Sections, draft: Draft, speed: Speed, hs: Length, tp: Period,
                          heading: Angle = 0.0, *, spectrum: str = "pm", gamma: Scalar = 3.3,
                          spreading_s: float | None = None, omega_max: Scalar | None = None, kyy: Scalar = 0.25,
                          rho: Density = RHO_SEA, g: Gravity = G, smooth: float | None = None, aft: str = "exclude",
                          order: int = 8, n_dir: int = 16, kg: Length | None = None, motion: bool = True,
                          motion_knots: int | None = 20, band: float = 0.0) -> WaveResistance:
    """Mean added resistance [N] in a sea state (H_s [m], peak period T_p [s], mean heading [rad]) by
    ``method``, motion and reflection parts; see :func:`~hullopt.waves.spectral_mean` for the spectrum,
    spreading and cut-off options.

    Parameters
    ----------
    method : str
        One of :data:`METHODS` (``"nmri"``, ``"stawave1"``, ``"stawave2"``, ``"snnm"``).
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    draft : float
        Draft [m above the baseline].
    speed : float
        Ship speed [m/s], ahead positive.
    hs, tp : float
        Significant wave height H_s [m] and peak period T_p [s].
    heading : float
        Mean wave heading [rad], 0 = head seas.
    spectrum, gamma, spreading_s, omega_max, order, n_dir
        The spectrum (``"pm"``, ``"jonswap"``, …), JONSWAP γ, cos-2s spreading (None: long-crested),
        cut-off [rad/s] and quadrature orders; see :func:`spectral_mean`. Short-crested, the direction
        integral is split at the method's kinks (:func:`heading_breaks`), ``n_dir`` points shared by the
        panels (at least 4 each; NMRI's reflection part 5·n_dir/2, its motion part one plain Gauss rule).
    kyy : float
        Pitch radius of gyration over Lpp (STAWAVE-2, SNNM, and NMRI's strip-theory motion part).
    rho, g : float
        Water density [kg/m³] and gravity [m/s²].
    smooth, aft
        As :func:`nmri_added_resistance` takes them.
    band : float
        NMRI: Bf averaged over the waterlines in [T − band, T + band] (band in m) (:func:`~hullopt.waves.bluntness`);
        0: the waterline at the draft (the patent's). The empirical methods take no Bf and ignore it.
    kg, motion, motion_knots
        NMRI: KG [m] for the motion part (None: KG = draft), whether to include it (default yes), and the
        number of λ/L knots its response is computed at and interpolated from
        (:func:`~hullopt.waves.motion_response`: 20 strip-theory solves per heading, whatever the spectrum;
        the mean within about 1 % of a 100-point reference); None computes it at every node of the spectral
        quadrature (``order`` · 18 solves per heading, for checking).

    Returns
    -------
    WaveResistance
        ``motion``, ``reflection`` and ``total`` [N], positive a resistance (NMRI: motion = R_AWM by strip
        theory, reflection = R_AWR(Bf)).

    Examples
    --------
    The coarse Wigley (L 100, B 10, T 6.25 m) at 15 kn in head seas, H_s 3 m, T_p 9 s, by NMRI's reflection
    part alone: a measured 13.45 kN (hullopt 0.1.0; the response is linear in ζ², so the mean scales as H_s²).
    With the strip-theory motion part (the default; 20–30 s to compile) the mean is 79.4 kN, 66.0 kN of
    it from the motions:

    >>> import jax; jax.config.update("jax_enable_x64", True)
    >>> from hullopt.models import wigley
    >>> from hullopt.waves import mean_added_resistance
    >>> r = jax.jit(lambda hull: mean_added_resistance("nmri", hull, 6.25, 7.7, 3.0, 9.0, motion=False))(
    ...     wigley(100, 10, 6.25, 10, n=21, m=21))
    >>> float(r.motion), round(float(r.total) / 1e3, 2)
    (0.0, 13.45)
    """

    return wave_method(method).mean(sections, draft, speed, hs, tp, heading, spectrum=spectrum, gamma=gamma,
                                    spreading_s=spreading_s, omega_max=omega_max, kyy=kyy, rho=rho, g=g,
                                    smooth=smooth, aft=aft, order=order, n_dir=n_dir, kg=kg, motion=motion,
                                    motion_knots=motion_knots, band=band)
