"""The Lackenby (1950) transformation: stations shifted along the length to reach a target Cb and LCB.

H. Lackenby, "On the systematic geometrical variation of ship forms", Trans. INA 92 (1950) 289–316; the form
used by hull-design programs (e.g. Schneekluth & Bertram, *Ship Design for Efficiency and Economy*, 1998).

Notation, per half body (aft, fore), in half-lengths from midship: ``ξ ∈ [0, 1]`` (0 at midship, 1 at the
perpendicular), the sectional-area curve ``y(ξ) = A/A_mid``, its prismatic coefficient ``Cp = ∫y dξ``,
centroid ``x̄ = ∫ξ y dξ / Cp``, radius of gyration ``K² = ∫ξ² y dξ / Cp`` and parallel middle body ``p``
(stations next to midship with the midship area). Lackenby's shift, with the parallel body held
(δp = 0)::

    δξ = (1 − ξ) [δp/(1 − p) + (ξ − p)/A · (δCp − δp (1 − Cp)/(1 − p))]  =  c (1 − ξ)(ξ − p),   ξ ≥ p
    A  = Cp (1 − 2x̄) − p (1 − Cp),          c = δCp / A

moves volume ``δCp`` (first order) with its centroid at the lever
``h = Cp [2(1 + p) x̄ − 3K² − p] / A``. The whole hull's change ``δCp`` and LCB shift ``δB`` (half-lengths,
forward +, from ``B``) are split between the fore and aft bodies by the volume and moment balance::

    δCp_F = [ 2(Cp + δCp) δB + 2 δCp (h_A + B)] / (h_F + h_A)
    δCp_A = [−2(Cp + δCp) δB + 2 δCp (h_F − B)] / (h_F + h_A)

(``Cp`` the whole hull's, ``δCp_F``/``δCp_A`` the half bodies' own changes, ``h_A`` measured aft). These are
first order; :func:`lackenby` then refines ``(c_A, c_F)`` by Newton's method on the exact hydrostatics of the
shifted stations (Simpson's rule as in :func:`hullopt.hydro.hydrostatics`: the kernel's :func:`~hullopt.geometry.volume_lcb`), so the targets are met to
round-off. Only the station positions change: the sections, the midship section, length, breadth and draft
stay — which is exactly what a Lackenby shift is.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._types import Draft
from ..errors import HullError
from ..geometry import SAME_POINT, Sections, longitudinal_integrals, simpson_weights, volume_lcb

_NEWTON_STEPS = 8  # quadratic convergence from the first-order start: round-off in 3–4 steps


def _particulars(x, area, bwl, draft: Draft, lpp):
    """Cb and LCB [% Lpp from midship, forward +] of stations at ``x`` with full-section areas ``area``,
    by the same rules as :func:`hullopt.hydro.hydrostatics` (the kernel's :func:`volume_lcb`)."""
    volume, lcb = volume_lcb(x, area)
    return jnp.stack([volume / (lpp * bwl * draft), 100.0 * (lcb - lpp / 2.0) / lpp])


_simpson = jax.jit(simpson_weights)
_particulars_jit = jax.jit(_particulars)


@jax.jit
def _section_data(sections: Sections, draft: Draft):
    """Full-section areas ``(n,)`` [m²] and the waterline breadth [m] at ``draft``."""
    li = longitudinal_integrals(sections, draft)
    return li.area, li.bwl


def _half_body(xi, y):
    """Lackenby's integrals of one half body: ``Cp, x̄, K², p`` (numpy; ``xi`` increasing from 0)."""
    keep = xi <= 1.0 + 1e-12  # stations beyond the perpendicular (a bulb, an overhang) are not shifted
    xi, y = xi[keep], y[keep]
    w = np.asarray(_simpson(jnp.asarray(xi)))
    cp = w @ y
    xbar = (w @ (xi * y)) / cp
    k2 = (w @ (xi**2 * y)) / cp
    flat = np.cumprod(y >= 1.0 - 1e-6)  # the run of full sections from midship
    p = float(xi[int(flat.sum()) - 1])
    return cp, xbar, k2, p


def lackenby_basis(sections: Sections, draft: Draft) -> tuple[np.ndarray, np.ndarray, dict]:
    """The static part of a Lackenby shift: ``G (n, 2)`` with ``x_new = x + G @ (c_A, c_F)`` [m], the
    full-section areas ``(n,)`` [m²] at ``draft`` and the half-body integrals (``cp``, ``xbar``, ``k2``,
    ``p``, ``lever``, ``a`` — each ``(aft, fore)`` — and the waterline breadth ``bwl`` [m]). HullError if the hull has no midship station or too few
    stations in a half body."""
    x = np.asarray(sections.x, dtype=np.float64)
    lpp = float(sections.lpp)
    mid = lpp / 2.0
    if np.any(np.diff(x) <= 0.0):
        raise HullError("sections.x: stations must be strictly increasing for a Lackenby shift")
    at_mid = np.flatnonzero(np.abs(x - mid) <= SAME_POINT * lpp)
    if at_mid.size == 0:
        raise HullError(f"sections.x: a Lackenby shift needs a station at midship (x = Lpp/2 = {mid:g} m), "
                        "the section it holds; this hull has none")
    i_mid = int(at_mid[0])
    if i_mid < 2 or x.size - i_mid < 3:
        raise HullError("sections.x: a Lackenby shift needs at least 2 stations in each half body besides "
                        "midship")
    area, bwl = (np.asarray(v) for v in _section_data(sections, jnp.asarray(draft, dtype=sections.yz.dtype)))
    a_mid = area[i_mid]
    if not a_mid > 0.0:
        raise HullError(f"draft {float(draft):g} m: the midship section is dry, nothing to shift")
    y = area / a_mid
    halves = {}
    g = np.zeros((x.size, 2))
    for k, idx in enumerate((np.arange(i_mid, -1, -1), np.arange(i_mid, x.size))):  # aft, fore
        xi = np.abs(x[idx] - mid) / mid
        cp, xbar, k2, p = _half_body(xi, y[idx])
        a = cp * (1.0 - 2.0 * xbar) - p * (1.0 - cp)
        if not a > 1e-9:
            body = ("aft", "fore")[k]
            raise HullError(f"sections: the {body} body is all parallel middle body (Cp = {cp:.4g}): a Lackenby "
                            "shift cannot change it")
        shift = np.where((xi > p) & (xi < 1.0), (1.0 - xi) * (xi - p), 0.0)
        g[idx, k] = (1.0 if k else -1.0) * mid * shift
        halves[k] = {"cp": cp, "xbar": xbar, "k2": k2, "p": p, "a": a,
                     "lever": cp * (2.0 * (1.0 + p) * xbar - 3.0 * k2 - p) / a}
    info = {key: np.array([halves[0][key], halves[1][key]]) for key in halves[0]} | {"bwl": bwl}
    return g, area, info


def lackenby_first_order(info: dict, cp: float, b: float, d_cp: float, d_b: float) -> np.ndarray:
    """Lackenby's closed form: the shift coefficients ``(c_A, c_F)`` for a change ``d_cp`` of the whole
    hull's prismatic ``cp`` and ``d_b`` of its LCB ``b`` (both in half-lengths from midship, forward +)."""
    h_a, h_f = info["lever"]
    d_f = (2.0 * (cp + d_cp) * d_b + 2.0 * d_cp * (h_a + b)) / (h_f + h_a)
    d_a = (-2.0 * (cp + d_cp) * d_b + 2.0 * d_cp * (h_f - b)) / (h_f + h_a)
    return np.array([d_a, d_f]) / info["a"]


@jax.jit
def _newton(x, g, c0, area, bwl, draft: Draft, lpp, target):
    def residual(c):
        r = _particulars(x + g @ c, area, bwl, draft, lpp) - target
        return r * jnp.asarray([1.0, 0.01])  # LCB in fractions of Lpp: both of order one alike

    def step(c, _):
        return c - jnp.linalg.solve(jax.jacfwd(residual)(c), residual(c)), None

    c, _ = jax.lax.scan(step, c0, None, length=_NEWTON_STEPS)
    return c, _particulars(x + g @ c, area, bwl, draft, lpp)


def lackenby(sections: Sections, draft: Draft, *, cb: float | None = None, lcb_pct: float | None = None,
             refine: bool = True) -> Sections:
    """Shift the stations of ``sections`` (Lackenby 1950, see the module) to reach block coefficient ``cb``
    and LCB ``lcb_pct`` [% Lpp from midship, forward +] at ``draft`` [m]; ``None`` holds the parent's.

    Returns the same sections at new positions ``x``: midship section, Lpp, breadth and draft unchanged.
    With ``refine`` (the default) the targets are met to round-off by Newton's method on the exact
    hydrostatics; ``refine=False`` gives Lackenby's first-order closed form alone.

    Raises :class:`HullError` for a target outside the physical range, a draft outside the hull, a hull
    without a midship station, and a target beyond the reach of the shift (stations would cross).

    Parameters
    ----------
    sections : Sections
        The parent: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m], with a station at midship.
    draft : float
        Draft [m above the baseline], above the keel and at most at the deck.
    cb : float, optional
        Target block coefficient in (0, 1); ``None`` keeps the parent's.
    lcb_pct : float, optional
        Target LCB [% Lpp from midship, forward +] in (−50, 50); ``None`` keeps the parent's.
    refine : bool
        Meet the targets exactly by Newton's method (True, default) or stop at the first-order shift.

    Returns
    -------
    Sections
        ``sections`` with new station positions ``x (n,)`` [m from the AP]; ``yz`` and ``lpp`` unchanged.
    """
    draft = float(draft)
    if not (np.isfinite(draft) and max(0.0, float(sections.keel)) < draft <= float(sections.depth)):
        raise HullError(f"draft {draft:g} m is outside the hull: expected ({max(0.0, float(sections.keel)):g}, "
                        f"{float(sections.depth):g}] m")
    if cb is not None and not (np.isfinite(cb) and 0.0 < cb < 1.0):
        raise HullError(f"cb = {cb}: a block coefficient must lie in (0, 1)")
    if lcb_pct is not None and not (np.isfinite(lcb_pct) and -50.0 < lcb_pct < 50.0):
        raise HullError(f"lcb_pct = {lcb_pct}: the LCB must lie within the length, in (-50, 50) % Lpp")
    g, area, info = lackenby_basis(sections, draft)
    x = np.asarray(sections.x, dtype=np.float64)
    lpp = float(sections.lpp)
    bwl = float(info["bwl"])
    cb0, lcb0 = np.asarray(_particulars_jit(*(jnp.asarray(a, dtype=jnp.float64) for a in (x, area, bwl, draft, lpp))))
    cb_t = cb0 if cb is None else float(cb)
    lcb_t = lcb0 if lcb_pct is None else float(lcb_pct)
    cm = float(area[np.argmin(np.abs(x - lpp / 2.0))]) / (bwl * draft)
    if cb_t / cm >= 1.0:
        raise HullError(f"cb = {cb_t:g}: a prismatic coefficient Cb/Cm = {cb_t / cm:.4g} ≥ 1 cannot be reached")
    c = lackenby_first_order(info, cb0 / cm, lcb0 / 50.0, (cb_t - cb0) / cm, (lcb_t - lcb0) / 50.0)
    if refine:
        arrays = (x, g, c, area, bwl, draft, lpp, [cb_t, lcb_t])
        c, got = _newton(*(jnp.asarray(a, dtype=jnp.float64) for a in arrays))
        c, got = np.asarray(c), np.asarray(got)
        if not (np.all(np.isfinite(got)) and abs(got[0] - cb_t) < 1e-9 and abs(got[1] - lcb_t) < 1e-7):
            raise HullError(f"cb = {cb_t:g}, lcb_pct = {lcb_t:g}: beyond the reach of a Lackenby shift of this hull")
    # δξ = c(1 − ξ)(ξ − p) keeps the stations in order while its slope 1 + c(1 + p − 2ξ) > 0 on [p, 1]
    stretch = 1.0 - np.abs(c) * (1.0 - info["p"])
    if np.any(stretch <= 0.0):
        body = ("aft", "fore")[int(np.argmin(stretch))]
        raise HullError(f"cb = {cb_t:g}, lcb_pct = {lcb_t:g}: beyond the reach of a Lackenby shift — the {body} "
                        f"body's stations would cross (c = {c[int(np.argmin(stretch))]:.3g}, needs |c|(1 − p) < 1)")
    return eqx.tree_at(lambda s: s.x, sections, jnp.asarray(x + g @ c, dtype=sections.x.dtype))
