"""The severe wind and rolling criterion (weather criterion) of the IMO IS Code 2008, Part A §2.3, as margins.

A ship heeled to φ0 by a steady beam wind (lever lw1) rolls back to windward by φ1 and is then hit by a gust
(lever lw2 = 1.5 lw1); the energy the gust puts in, area *a*, must be at most what the GZ curve holds above
lw2 before it stops (area *b*):

- lw1 = P·A·Z/(g·Δ) [m] with P = 504 Pa, A [m²] the lateral windage area above the waterline, Z [m] the height
  of its centre above the centre of the underwater lateral area (or T/2), Δ [kg] (the Code's
  P·A·Z/(1000·g·Δ) with Δ in t); lw1 and lw2 are the same at every heel (§2.3.2).
- φ0: the first intercept of GZ with lw1 (the steady heel), at most min(16°, 0.8 × the deck-edge immersion
  angle) (§2.3.1.2).
- φ1 = 109·k·X1·X2·√(r·s) degrees (§2.3.4), r = 0.73 + 0.6·OG/d with OG = KG − d, X1 from B/d, X2 from C_B, k
  from 100·A_k/(L·B) (1.0 without bilge keels, 0.7 with sharp bilges), s from the roll period
  T = 2·C·B/√GM [s], C = 0.373 + 0.023·(B/d) − 0.043·(L_WL/100): Tables 2.3.4-1 to -4, linear between their
  entries (``jnp.interp``: piecewise linear, with kinks at the entries, and constant beyond the ends, as the
  tables' "≤" and "≥" rows say).
- area a = ∫ (lw2 − GZ) dφ from the roll-back φ0 − φ1 (GZ(−φ) = −GZ(φ): a symmetric hull) to the first
  intercept φc of GZ with lw2; area b = ∫ (GZ − lw2) dφ from φc to φ2 = min(50°, θf, θc), θc the second
  intercept. Criterion: b ≥ a (§2.3.1.1).

GZ is given at heels ``(k,)`` from 0 and taken as linear between them (with 1° steps the areas are within
~0.1 % of a smooth curve's); the intercepts and the areas are those of that piecewise-linear curve, exactly,
so they are continuous and piecewise smooth in GZ, the loading and the particulars. ``value`` reports them.
``margin`` is for an optimiser and is never above the exact margin: the two minima (φ2 and the limit on φ0)
are soft minima, −τ·log Σ exp(−θ/τ) ≤ min θ, which lowers the limit on φ0 and ends area b earlier (GZ ≥ lw2
up to θc, so a shorter b is a smaller b). Kinks remain where a table entry or an intercept's heel segment is
crossed (the margin stays continuous there). A GZ curve that never reaches lw2 (capsize under the gust)
takes φc = θc at the heel where GZ − lw2 is largest, so b = 0 and the margin meets the curves that touch it
continuously; likewise φ0 when GZ never reaches lw1.

The Code's tables rest on ships with B/d < 3.5, −0.3 ≤ KG/d − 1 ≤ 0.5 and T < 20 s (§2.3.4, note);
:meth:`Weather.outside` names the ones a loading leaves. Source: IMO resolution MSC.267(85), the International
Code on Intact Stability, 2008, Part A §2.3 (text as in the IMO's consolidated editions).
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Bool, Float

from .._types import Angle, Angles, Draft, Length, Lengths, Scalar
from ..constants import G
from ..geometry import Sections, safe_div, safe_sqrt

#: Pa (N/m²): the Code's steady wind pressure (may be reduced for restricted service, §2.3.2).
WIND_PRESSURE = 504.0

# Tables 2.3.4-1 to 2.3.4-4 of the Code: (argument, factor) entries, linear between them, constant beyond.
TABLE_X1 = ((2.4, 2.5, 2.6, 2.7, 2.8, 2.9, 3.0, 3.1, 3.2, 3.3, 3.4, 3.5),
            (1.00, 0.98, 0.96, 0.95, 0.93, 0.91, 0.90, 0.88, 0.86, 0.84, 0.82, 0.80))  # B/d → X1
TABLE_X2 = ((0.45, 0.50, 0.55, 0.60, 0.65, 0.70), (0.75, 0.82, 0.89, 0.95, 0.97, 1.00))  # C_B → X2
TABLE_K = ((0.0, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0), (1.00, 0.98, 0.95, 0.88, 0.79, 0.74, 0.72, 0.70))  # 100·A_k/(L·B) → k
TABLE_S = ((6.0, 7.0, 8.0, 12.0, 14.0, 16.0, 18.0, 20.0),
           (0.100, 0.098, 0.093, 0.065, 0.053, 0.044, 0.038, 0.035))  # T [s] → s

# (key, label, unit, sense): angles in degrees here and in reports; "≤": value at most required.
WEATHER_CRITERIA = (
    ("steady_heel", "Steady-wind heel φ0", "deg", "≤"),
    ("area_ratio", "Area b / area a", "–", "≥"),
)
_SENSE = np.array([-1.0, 1.0])  # margin = sense·(value − required)
_BIG = 10.0  # rad: "no such angle" inside the soft minimum (exp(−10/τ) underflows to 0)


def _table(table, x) -> Array:
    return jnp.interp(x, jnp.asarray(table[0]), jnp.asarray(table[1]))


def weather_factors(breadth: Length, draft: Draft, kg: Length, cb: Scalar, lwl: Length, gm0: Length,
                    bilge_keel_area: Scalar = 0.0, sharp_bilges: bool = False) -> dict[str, Array]:
    """The roll-back angle φ1 of §2.3.4 and the factors it is made of.

    Parameters
    ----------
    breadth : float or Array, scalar
        Moulded breadth B [m].
    draft : float or Array, scalar
        Mean moulded draft d [m].
    kg : float or Array, scalar
        Centre of gravity above the baseline KG [m] (OG = KG − d, positive above the waterline).
    cb : float or Array, scalar
        Block coefficient C_B.
    lwl : float or Array, scalar
        Waterline length L_WL [m] (also the L of 100·A_k/(L·B)).
    gm0 : float or Array, scalar
        Metacentric height GM [m], corrected for free surfaces; GM ≤ 0 gives T = ∞ (s at its last entry).
    bilge_keel_area : float or Array, scalar
        Total area of the bilge keels (and the lateral projection of a bar keel) A_k [m²]; 0 by default.
    sharp_bilges : bool
        A sharp-bilged hull: k = 0.7 whatever A_k.

    Returns
    -------
    dict of str to Array
        Scalars: ``phi1`` [rad], ``roll_period`` T [s], ``c`` C [s/√m], ``x1``, ``x2``, ``k``, ``s``, ``r`` and
        the tables' arguments ``b_over_d``, ``og_over_d`` (OG/d) and ``bilge_keel_ratio`` (100·A_k/(L·B)).
    """
    b, d, kg, cb, lwl, gm = (jnp.asarray(v, dtype=float) for v in (breadth, draft, kg, cb, lwl, gm0))
    b_d = b / d
    c = 0.373 + 0.023 * b_d - 0.043 * lwl / 100.0
    stable = gm > 0.0
    period = jnp.where(stable, safe_div(2.0 * c * b, safe_sqrt(gm, stable), stable), jnp.inf)
    ratio = 100.0 * jnp.asarray(bilge_keel_area, dtype=float) / (lwl * b)
    k = jnp.full_like(b, 0.7) if sharp_bilges else _table(TABLE_K, ratio)
    x1, x2, s = _table(TABLE_X1, b_d), _table(TABLE_X2, cb), _table(TABLE_S, period)
    og_d = (kg - d) / d
    r = 0.73 + 0.6 * og_d
    phi1 = jnp.deg2rad(109.0 * k * x1 * x2 * safe_sqrt(r * s))
    return {"phi1": phi1, "roll_period": period, "c": c, "x1": x1, "x2": x2, "k": k, "s": s, "r": r,
            "b_over_d": b_d, "og_over_d": og_d, "bilge_keel_ratio": ratio}


def _primitive(heels: Array, gz: Array, x: Array) -> Array:
    """∫₀ˣ GZ dφ [m·rad] of GZ linear between ``heels`` (extended linearly past the last); GZ odd, so even in x."""
    x = jnp.abs(x)
    h = jnp.diff(heels)
    cum = jnp.concatenate([jnp.zeros(1, gz.dtype), jnp.cumsum(0.5 * h * (gz[1:] + gz[:-1]))])
    i = jnp.clip(jnp.searchsorted(heels, x, side="right") - 1, 0, heels.shape[0] - 2)
    t = x - heels[i]
    return cum[i] + t * gz[i] + 0.5 * t**2 * (gz[i + 1] - gz[i]) / h[i]


def _intercepts(heels: Array, d: Array) -> tuple[Array, Array, Array]:
    """First up-crossing of ``d = GZ − lever`` (its heel where ``d`` is largest when there is none), the next
    down-crossing (``_BIG`` when none within the heels; the first one when there is no up-crossing), and
    whether the first exists."""
    up = d >= 0.0
    found = jnp.any(up)
    j = jnp.argmax(up)
    jm = jnp.maximum(j - 1, 0)
    first = heels[jm] + safe_div(d[jm], d[jm] - d[j], j > 0) * (heels[j] - heels[jm])
    first = jnp.where(found, first, heels[jnp.argmax(d)])
    idx = jnp.arange(heels.shape[0])
    down = (d < 0.0) & (idx > j) & found
    m = jnp.argmax(down)
    mm = jnp.maximum(m - 1, 0)
    second = heels[mm] + safe_div(d[mm], d[mm] - d[m], jnp.any(down)) * (heels[m] - heels[mm])
    second = jnp.where(jnp.any(down), second, jnp.where(found, _BIG, first))
    return first, second, found


def _softmin(angles: Array, tau: float) -> Array:
    return -tau * jnp.log(jnp.sum(jnp.exp(-(angles - jnp.min(angles)) / tau))) + jnp.min(angles)


class Weather(eqx.Module):
    """The weather criterion (IS Code 2008 §2.3) of one loading. ``value``, ``required``, ``margin`` ``(2,)`` in
    the order of :data:`WEATHER_CRITERIA`: the steady heel φ0 [deg] against its limit (passes at most), b/a
    against 1 (passes at least); ``margin`` for an optimiser, ≥ 0 passes and never above the exact margin
    (the module docstring says how). Scalars: ``lw1``, ``lw2`` [m]; angles [rad]: ``phi0`` (steady heel),
    ``phi0_limit`` (min(16°, 0.8 × deck-edge immersion)), ``phi1`` (roll to windward), ``phi_roll`` = φ0 − φ1,
    ``phi_c`` (first intercept with lw2), ``theta_c`` (the second; NaN when GZ stays above lw2 or never reaches
    it), ``phi2`` (the end of area b); ``area_a``, ``area_b`` [m·rad]; ``roll_period`` T [s] and the factors
    ``c``, ``x1``, ``x2``, ``k``, ``s``, ``r`` with the tables' arguments ``b_over_d``, ``og_over_d``,
    ``bilge_keel_ratio``;
    ``reaches_lw2``: whether GZ reaches lw2 at all (if not, the gust capsizes the ship: φc is where GZ comes
    nearest, b = 0)."""

    value: Float[Array, " 2"]
    required: Float[Array, " 2"]
    margin: Float[Array, " 2"]
    lw1: Float[Array, ""]
    lw2: Float[Array, ""]
    phi0: Float[Array, ""]
    phi0_limit: Float[Array, ""]
    phi1: Float[Array, ""]
    phi_roll: Float[Array, ""]
    phi_c: Float[Array, ""]
    theta_c: Float[Array, ""]
    phi2: Float[Array, ""]
    area_a: Float[Array, ""]
    area_b: Float[Array, ""]
    roll_period: Float[Array, ""]
    c: Float[Array, ""]
    x1: Float[Array, ""]
    x2: Float[Array, ""]
    k: Float[Array, ""]
    s: Float[Array, ""]
    r: Float[Array, ""]
    b_over_d: Float[Array, ""]
    og_over_d: Float[Array, ""]
    bilge_keel_ratio: Float[Array, ""]
    reaches_lw2: Bool[Array, ""]

    @property
    def passed(self) -> Array:
        return _SENSE * (self.value - self.required) >= 0.0

    def outside(self) -> list[str]:
        """The limits of the data behind the Code's tables that this loading leaves (§2.3.4): B/d < 3.5,
        −0.3 ≤ KG/d − 1 ≤ 0.5, T < 20 s; empty when inside."""
        out = []
        if float(self.b_over_d) >= 3.5:
            out.append(f"B/d = {float(self.b_over_d):.2f} ≥ 3.5")
        if not -0.3 <= float(self.og_over_d) <= 0.5:
            out.append(f"KG/d − 1 = {float(self.og_over_d):.2f} outside −0.3…0.5")
        if not float(self.roll_period) < 20.0:
            out.append(f"roll period T = {float(self.roll_period):.1f} s ≥ 20 s")
        return out

    def to_list(self) -> list[dict]:
        """One record per criterion (plain floats), as in ``hullopt stability --weather --json``."""
        v, r, m = (np.asarray(a).tolist() for a in (self.value, self.required, self.margin))
        return [
            {"key": key, "criterion": label, "unit": unit, "sense": sense, "value": v[i], "required": r[i],
             "margin": m[i], "margin_exact": float(_SENSE[i] * (v[i] - r[i])),
             "pass": bool(_SENSE[i] * (v[i] - r[i]) >= 0.0)}
            for i, (key, label, unit, sense) in enumerate(WEATHER_CRITERIA)
        ]

    def to_dict(self) -> dict:
        """Plain floats, angles in degrees (keys ``…_deg``), lengths in m, areas in m·rad, T in s; the
        criteria under ``criteria`` (:meth:`to_list`); ``outside`` (:meth:`outside`)."""
        angles = ("phi0", "phi0_limit", "phi1", "phi_roll", "phi_c", "theta_c", "phi2")
        out = {f"{k}_deg": float(np.rad2deg(getattr(self, k))) for k in angles}
        for k in ("lw1", "lw2", "area_a", "area_b", "roll_period", "c", "x1", "x2", "k", "s", "r", "b_over_d",
                  "og_over_d", "bilge_keel_ratio"):
            out[k] = float(getattr(self, k))
        out["area_ratio"] = float(self.value[1])
        out["reaches_lw2"] = bool(self.reaches_lw2)
        out["criteria"] = self.to_list()
        out["outside"] = self.outside()
        return out


def weather_criterion(heels: Angles, gz: Lengths, gm0: Length, displacement: Scalar, area: Scalar, lever: Length,
                      breadth: Length, draft: Draft, kg: Length, cb: Scalar, lwl: Length,
                      bilge_keel_area: Scalar = 0.0, sharp_bilges: bool = False, flooding_angle: Angle | None = None,
                      deck_edge_angle: Angle | None = None, pressure: Scalar = WIND_PRESSURE,
                      tau: float = 0.005) -> Weather:
    """The severe wind and rolling criterion of the IS Code 2008, Part A §2.3 (module docstring: formulas,
    smoothness, sources). Pure JAX: jit/grad/vmap-able in every array argument; no loop over heels.

    Parameters
    ----------
    heels : array_like, (k,) float
        Heels [rad], increasing from 0, covering [0, min(50°, θf)] (GZ is extended linearly past the last).
    gz : array_like, (k,) float
        Righting lever GZ [m] at ``heels`` (free-surface corrected), positive righting.
    gm0 : float or Array, scalar
        Metacentric height GM [m] (corrected), for the roll period.
    displacement : float or Array, scalar
        Displacement Δ [kg].
    area : float or Array, scalar
        Lateral windage area A [m²] above the waterline (hull, superstructure, deck cargo).
    lever : float or Array, scalar
        Z [m]: height of the centre of ``area`` above the centre of the underwater lateral area (or above T/2).
    breadth, draft, kg, cb, lwl
        B, mean draft d, KG [m], C_B and L_WL [m], as :func:`weather_factors` takes them.
    bilge_keel_area : float or Array, scalar
        A_k [m²], 0 by default (no bilge keels: k = 1).
    sharp_bilges : bool
        k = 0.7 (a sharp-bilged hull).
    flooding_angle : float or Array, scalar, optional
        Downflooding angle θf [rad]; None: none (area b ends at min(50°, θc)).
    deck_edge_angle : float or Array, scalar, optional
        Heel [rad] at which the deck edge immerses (:func:`deck_immersion_angle`); None or NaN: the limit on φ0 is
        16°.
    pressure : float or Array, scalar
        Wind pressure P [Pa], 504 by default.
    tau : float
        Temperature [rad] of the soft minima in ``margin`` (0.005 rad ≈ 0.3° by default; they lower an angle by
        at most τ·log 3).

    Returns
    -------
    Weather
        ``value``, ``required``, ``margin`` ``(2,)`` (φ0 [deg], b/a) and the quantities of the criterion.
    """
    heels = jnp.asarray(heels, dtype=float)
    gz = jnp.asarray(gz, dtype=float)
    lw1 = jnp.asarray(pressure, dtype=float) * area * lever / (G * displacement)
    lw2 = 1.5 * lw1
    f = weather_factors(breadth, draft, kg, cb, lwl, gm0, bilge_keel_area, sharp_bilges)
    phi0, _, _ = _intercepts(heels, gz - lw1)
    phi_c, theta_c, reaches = _intercepts(heels, gz - lw2)
    phi_roll = phi0 - f["phi1"]
    fifty, sixteen = jnp.deg2rad(50.0), jnp.deg2rad(16.0)
    theta_f = jnp.asarray(_BIG if flooding_angle is None else flooding_angle, dtype=float)
    ends = jnp.stack([fifty, theta_f, theta_c])
    phi2 = jnp.maximum(jnp.min(ends), phi_c)  # no area b when θf comes before the intercept
    deck = jnp.asarray(jnp.nan if deck_edge_angle is None else deck_edge_angle, dtype=float)
    limits = jnp.stack([sixteen, jnp.where(jnp.isnan(deck), _BIG, 0.8 * deck)])
    limit = jnp.min(limits)

    def prim(x):
        return _primitive(heels, gz, x)

    area_a = lw2 * (phi_c - phi_roll) - (prim(phi_c) - prim(phi_roll))

    def area_b(end):
        return prim(end) - prim(phi_c) - lw2 * (end - phi_c)

    b = area_b(phi2)
    b_soft = area_b(jnp.maximum(_softmin(ends, tau), phi_c))  # ≤ b: GZ ≥ lw2 from φc to θc
    limit_soft = _softmin(limits, tau)
    value = jnp.stack([jnp.rad2deg(phi0), safe_div(b, area_a, area_a > 0.0, jnp.inf)])
    required = jnp.stack([jnp.rad2deg(limit), jnp.ones(())])
    smooth = jnp.stack([jnp.rad2deg(limit_soft - phi0), safe_div(b_soft, area_a, area_a > 0.0, jnp.inf) - 1.0])
    return Weather(value=value, required=required, margin=smooth, lw1=lw1, lw2=lw2, phi0=phi0, phi0_limit=limit,
                   phi1=f["phi1"], phi_roll=phi_roll, phi_c=phi_c,
                   theta_c=jnp.where((theta_c >= _BIG) | ~reaches, jnp.nan, theta_c), phi2=phi2, area_a=area_a,
                   area_b=b,
                   roll_period=f["roll_period"], c=f["c"], x1=f["x1"], x2=f["x2"], k=f["k"], s=f["s"], r=f["r"],
                   b_over_d=f["b_over_d"], og_over_d=f["og_over_d"], bilge_keel_ratio=f["bilge_keel_ratio"],
                   reaches_lw2=reaches)


def deck_immersion_angle(sections: Sections, heels: Angles, level: Lengths, trim: Lengths) -> Array:
    """The heel [rad] at which the deck edge first reaches the water: the lowest freeboard of the immersing
    (starboard) deck edge over the stations, ``z'_edge − (level + trim·(x − Lpp/2))`` in the heeled frame (see
    :mod:`~hullopt.hydro._stability`), linear between ``heels``.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m]; a section's last point is its deck edge.
    heels : array_like, (k,) float
        Heels [rad], increasing from 0.
    level : array_like, (k,) float
        Waterplane height at midship [m] in the heeled frame at each heel (:class:`StabilityCurve` ``level``).
    trim : array_like, (k,) float
        Trim tan θ (bow down positive) at each heel (:class:`StabilityCurve` ``trim``).

    Returns
    -------
    Array, scalar
        The deck-edge immersion angle [rad]; NaN when the deck edge stays dry over ``heels`` (or is under water
        upright).
    """
    heels, level, trim = (jnp.asarray(v, dtype=float) for v in (heels, level, trim))
    edge = sections.yz[:, -1, :]
    c, s = jnp.cos(heels)[:, None], jnp.sin(heels)[:, None]
    z_edge = -edge[:, 0] * s + edge[:, 1] * c  # starboard edge, heeled frame: (k, n)
    water = level[:, None] + trim[:, None] * (sections.x - 0.5 * sections.lpp)
    free = jnp.min(z_edge - water, axis=1)
    wet = free <= 0.0
    j = jnp.argmax(wet)
    jm = jnp.maximum(j - 1, 0)
    ok = jnp.any(wet) & (j > 0)
    angle = heels[jm] + safe_div(free[jm], free[jm] - free[j], ok) * (heels[j] - heels[jm])
    return jnp.where(ok, angle, jnp.nan)


def lateral_plane(sections: Sections, draft: Draft) -> tuple[Array, Array]:
    """The underwater lateral plane of the upright hull at ``draft``: its area [m²] and the height of its centre
    above the baseline [m] — the profile between each station's lowest point and min(T, its highest), linear
    between stations (the same profile as :func:`hullopt.wind.projections` draws above the water); exact
    polygon integrals.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height T [m above the baseline].

    Returns
    -------
    tuple of Array
        ``(area, z)``: the lateral area [m²] and its centre's height above the baseline [m].
    """
    t = jnp.asarray(draft, dtype=float)
    z = sections.yz[..., 1]
    bot = jnp.minimum(jnp.min(z, axis=1), t)
    top = jnp.clip(jnp.max(z, axis=1), bot, t)
    x = sections.x
    poly = jnp.concatenate([jnp.stack([x, bot], -1), jnp.stack([x, top], -1)[::-1]])  # counter-clockwise
    nxt = jnp.roll(poly, -1, axis=0)
    cross = poly[:, 0] * nxt[:, 1] - nxt[:, 0] * poly[:, 1]
    area = 0.5 * jnp.sum(cross)
    zc = safe_div(jnp.sum((poly[:, 1] + nxt[:, 1]) * cross), 6.0 * area)
    return area, zc
