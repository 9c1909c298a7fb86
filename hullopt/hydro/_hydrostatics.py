"""Upright, even-keel hydrostatics from :class:`~hullopt.geometry.Sections` (DESIGN.md §4).

All functions are pure JAX, differentiable in the geometry and the draft, and ``vmap``-able over drafts.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._types import Draft, Drafts, Volume
from ..constants import RHO_SEA
from ..geometry import Sections, longitudinal_integrals, section_integrals, wetted_surface
from ._roots import level_for_volume
from ._tolerances import BISECTION_TOL


class Hydrostatics(eqx.Module):
    """Hydrostatic particulars at one draft. SI units unless stated; x positions from the AP.

    ``lcb``/``lcf`` in m from the AP; ``lcb_pct``/``lcf_pct`` in % Lpp from midship, forward positive.
    ``tpc`` in t/cm and ``mct`` (moment to change trim 1 cm, with GM_L ≈ BM_L) in t·m/cm by their
    definitions; ``displacement`` in kg. Coefficients use Lpp and the waterline breadth ``bwl``.
    """

    draft: Float[Array, ""]
    volume: Float[Array, ""]
    displacement: Float[Array, ""]
    wetted_surface: Float[Array, ""]
    a_transom: Float[Array, ""]
    cb: Float[Array, ""]
    cp: Float[Array, ""]
    cm: Float[Array, ""]
    cwp: Float[Array, ""]
    lcb: Float[Array, ""]
    lcb_pct: Float[Array, ""]
    kb: Float[Array, ""]
    awp: Float[Array, ""]
    lcf: Float[Array, ""]
    lcf_pct: Float[Array, ""]
    bmt: Float[Array, ""]
    bml: Float[Array, ""]
    kmt: Float[Array, ""]
    tpc: Float[Array, ""]
    mct: Float[Array, ""]
    lwl: Float[Array, ""]
    bwl: Float[Array, ""]

    def to_dict(self) -> dict[str, float | list[float]]:
        """Plain floats (or lists for a table), keyed as in ``hullopt hydro --json``."""
        return {k: np.asarray(v).tolist() for k, v in vars(self).items()}


def sectional_areas(sections: Sections, draft: Draft) -> Float[Array, " n"]:
    """Immersed area of each full section (both sides) [m²]: the sectional-area curve A(x).

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, (n,) float
        Immersed full-section areas [m²] at the stations.
    """
    return 2.0 * section_integrals(sections, draft).area


def hydrostatics(sections: Sections, draft: Draft, rho: float = RHO_SEA) -> Hydrostatics:
    """Hydrostatics at ``draft`` [m above the baseline]; see :class:`Hydrostatics`.

    Exact for the polyline sections; along x, Simpson's rule on the station positions (the kernel's
    :func:`~hullopt.geometry.longitudinal_integrals`).
    The draft must lie above the keel and at most at the deck, where the waterplane is the deck edge's (the
    caller checks: see :meth:`hullopt.models.LoadedHull.check_draft`).

    Parameters
    ----------
    sections : Sections
        The hull: stations ``x (n,)`` [m from the AP], half-sections ``yz (n, m, 2)`` [m] (y to port ≥ 0,
        z up from the baseline).
    draft : float or Array, scalar
        Waterline height [m above the baseline], above the keel and at most at the deck.
    rho : float
        Water density [kg/m³] (sea water 1025 by default).

    Returns
    -------
    Hydrostatics
        Scalars in SI: ``volume`` [m³], ``displacement`` [kg], ``cb``, ``cp``, ``cm``, ``cwp`` […],
        ``lcb``/``lcf`` [m from the AP] and ``lcb_pct``/``lcf_pct`` [% Lpp from midship, forward
        positive], ``kb``, ``bmt``, ``bml``, ``kmt`` [m], ``awp`` [m²], ``tpc`` [t/cm], ``mct`` [t·m/cm];
        ``wetted_surface`` [m²] (:func:`~hullopt.geometry.wetted_surface`), ``a_transom`` [m²] (the immersed
        transom area, Holtrop's A_T), ``lwl`` [m] between the waterline's ends where it meets the stem and
        stern profiles, ``bwl`` [m].

    Examples
    --------
    The Wigley hull's block coefficient is 4/9 = 0.4444… (0.44417 with 21 points a section):

    >>> import jax; jax.config.update("jax_enable_x64", True)
    >>> from hullopt.models import wigley
    >>> from hullopt.hydro import hydrostatics
    >>> h = jax.jit(hydrostatics)(wigley(100, 10, 6.25, 10, n=21, m=21), 6.25)  # pure JAX: jit, grad, vmap
    >>> round(float(h.cb), 3), abs(round(float(h.lcb_pct), 6))  # symmetric fore and aft: LCB at midship
    (0.444, 0.0)
    """
    t = jnp.asarray(draft, dtype=sections.yz.dtype)
    x, lpp = sections.x, sections.lpp
    li = longitudinal_integrals(sections, t)
    volume, lcb, kb, awp, lcf, bwl = li.volume, li.lcb, li.kb, li.awp, li.lcf, li.bwl
    bmt, bml = li.i_t / volume, li.i_l / volume
    cb = volume / (lpp * bwl * t)
    cm = jnp.interp(lpp / 2.0, x, li.area) / (bwl * t)
    displacement = rho * volume
    return Hydrostatics(
        draft=t,
        volume=volume,
        displacement=displacement,
        wetted_surface=wetted_surface(sections, t),
        a_transom=li.a_transom,
        cb=cb,
        cp=cb / cm,
        cm=cm,
        cwp=awp / (lpp * bwl),
        lcb=lcb,
        lcb_pct=100.0 * (lcb - lpp / 2.0) / lpp,
        kb=kb,
        awp=awp,
        lcf=lcf,
        lcf_pct=100.0 * (lcf - lpp / 2.0) / lpp,
        bmt=bmt,
        bml=bml,
        kmt=kb + bmt,
        tpc=rho * awp / 100.0 / 1000.0,
        mct=displacement / 1000.0 * bml / (100.0 * lpp),
        lwl=li.lwl,
        bwl=bwl,
    )


def hydrostatic_table(sections: Sections, drafts: Drafts, rho: float = RHO_SEA) -> Hydrostatics:
    """:func:`hydrostatics` at every draft of ``drafts (k,)``: each field becomes ``(k,)`` (one ``vmap``).

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    drafts : array_like, (k,) float
        Waterline heights [m above the baseline], each above the keel and at most at the deck.
    rho : float
        Water density [kg/m³] (sea water 1025 by default).

    Returns
    -------
    Hydrostatics
        Every field ``(k,)``, units as in :func:`hydrostatics`.
    """
    return jax.vmap(hydrostatics, in_axes=(None, 0, None))(sections, jnp.asarray(drafts), rho)


def volume_at(sections: Sections, draft: Draft) -> Array:
    """Displaced volume [m³] at ``draft`` (cheaper than the full :func:`hydrostatics`).

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, scalar
        Displaced volume ∇ [m³] (both sides).
    """
    return longitudinal_integrals(sections, draft).volume


def draft_for_volume(sections: Sections, volume: Volume) -> Array:
    """The draft [m] at which the hull displaces ``volume`` [m³].

    Newton's steps on the waterplane area between keel and deck, a bisection step wherever one would leave the
    bracket (the volume curve is flat above the deck, where Newton alone would stall), to 1e-12
    (:func:`~._roots.level_for_volume`); differentiable by the implicit function theorem, so
    ``d draft / d volume = 1 / Awp``.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    volume : float or Array, scalar
        Target displaced volume [m³], positive.

    Returns
    -------
    Array, scalar
        The draft [m above the baseline], between the keel and the deck (the solve does not raise: a volume
        out of reach is not reported).
    """
    return _draft_root(sections, jnp.asarray(volume, dtype=sections.yz.dtype))


@jax.custom_jvp
def _draft_root(sections: Sections, volume: Array) -> Array:
    """:func:`draft_for_volume`'s solve; its derivative at the root dT = −(∂V/∂p · dp − dvolume)/A_wp."""
    def integrate(t):
        li = longitudinal_integrals(sections, t[0])
        return li.volume[None], li.awp[None]

    return level_for_volume(integrate, sections.keel[None], sections.depth[None], volume, BISECTION_TOL)[0]


@_draft_root.defjvp
def _draft_root_jvp(primals, tangents):
    draft = _draft_root(*primals)

    def error(sections, volume):  # [m³]
        li = longitudinal_integrals(sections, draft)
        return li.volume - volume, li.awp

    (_, awp), (d_error, _) = jax.jvp(error, primals, tangents)
    return draft, -d_error / jnp.where(awp > 0.0, awp, jnp.inf)
