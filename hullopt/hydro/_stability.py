"""Large-angle stability from :class:`~hullopt.geometry.Sections`: heeled hydrostatics, GZ and KN curves
(DESIGN.md §4, seed 003 §3.4).

Frames and signs. The body frame is the hull's (x forward from the AP, y to port, z up from the baseline).
A heel ``φ > 0`` puts the **starboard side down** (as NavalToolbox). The *heeled frame* ``(x, y', z')`` is the
body frame turned by ``φ`` about x::

    y' = y cos φ − z sin φ,    z' = y sin φ + z cos φ,

so z' is vertical, y' horizontal, and the immersed side has y' < 0. The waterplane is
``z' = level + s (x − Lpp/2)``: ``level`` is its height at midship and ``s = tan θ`` the trim, positive
bow down. Sections stay at fixed x (body frame), so at every station the water is a horizontal line in the
rotated section, and the kernel's exact clipped integrals (:func:`~hullopt.geometry.polygon_integrals`) give
the immersed area and its moments; Simpson's rule integrates them along x. The trim rotates about y', which
stays horizontal, so transverse levers need no correction for trim.

Righting lever: ``GZ = y'_G − y'_B`` (positive when righting), with G at ``(x_G, 0, KG)`` in the body frame;
``KN = −y'_B`` (the lever about the keel point K, i.e. GZ for KG = 0). With no trim, GZ = KN − KG sin φ.

Deck and sheer: a section's last polyline point is its deck edge; the closed section runs across a flat deck
(no camber) to the starboard deck edge. :func:`with_sheer` raises each deck edge by a given deck line, e.g.
the ICLL standard sheer of :func:`icll_sheer`.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float

from .._types import Angle, Angles, Length, Lengths, Scalar, Volume, Volumes
from ..geometry import Sections, polygon_integrals, safe_div, simpson_weights
from ._criteria import Criteria, criteria_from_gz, criteria_heels
from ._tolerances import ANGLE_TOL, BISECTION_TOL


def icll_sheer(sections: Sections) -> Float[Array, " n"]:
    """The ICLL standard sheer at each station [m] (seed 003 eqs. 12–13, L = Lpp in m, heights in cm):
    ``y_f = (1.666 L + 50.8)(2ξ/L)²`` forward of midship and ``y_a = (0.833 L + 25.4)(2ξ/L)²`` aft, ξ the
    distance from midship; so 1.666 L + 50.8 cm at the FP and half that at the AP.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``lpp`` [m].

    Returns
    -------
    Array, (n,) float
        Standard sheer [m] above the deck edge at each station.
    """
    lpp = sections.lpp
    xi = 2.0 * (sections.x - 0.5 * lpp) / lpp
    forward = (1.666 * lpp + 50.8) * xi**2
    aft = (0.833 * lpp + 25.4) * xi**2
    return 0.01 * jnp.where(xi > 0.0, forward, aft)


def with_sheer(sections: Sections, sheer: Lengths) -> Sections:
    """Sections with each deck edge raised by ``sheer`` ((n,) or scalar, m ≥ 0): one point is appended
    straight above the deck edge, so ``m`` grows by one. Pass a given deck line as ``z_deck(x) − z_edge``.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    sheer : float or array_like, scalar or (n,)
        Rise of each deck edge [m], ≥ 0.

    Returns
    -------
    Sections
        The same stations with ``yz (n, m+1, 2)`` [m].
    """
    edge = sections.yz[:, -1, :]
    rise = jnp.broadcast_to(jnp.asarray(sheer, dtype=sections.yz.dtype), edge.shape[:1])
    top = edge + jnp.stack([jnp.zeros_like(rise), rise], axis=-1)
    return Sections(x=sections.x, yz=jnp.concatenate([sections.yz, top[:, None, :]], axis=1), lpp=sections.lpp)


def full_sections(yz: Float[Array, "n m 2"]) -> Float[Array, "n 2*m 2"]:
    """Closed full sections, counter-clockwise in (y, z): the port polyline keel → deck edge, then the
    mirrored starboard one deck edge → keel (the closing edge is the flat deck). Centreline joints of the
    two sides are traversed in opposite directions and cancel.

    Parameters
    ----------
    yz : Array, (n, m, 2) float
        Port half-sections ``(y, z)`` [m], keel to deck edge.

    Returns
    -------
    Array, (n, 2m, 2) float
        Closed full sections ``(y, z)`` [m] (last point joins the first).
    """
    starboard = yz[:, ::-1, :] * jnp.array([-1.0, 1.0], dtype=yz.dtype)
    return jnp.concatenate([yz, starboard], axis=1)


def _rotate(poly: Array, heel: Array) -> Array:
    c, s = jnp.cos(heel), jnp.sin(heel)
    y, z = poly[..., 0], poly[..., 1]
    return jnp.stack([y * c - z * s, y * s + z * c], axis=-1)


class HeeledIntegrals(eqx.Module):
    """Immersed volume [m³] and centre of buoyancy ``(xb, yb, zb)`` [m] in the heeled frame, and the
    waterplane's area ``awp`` [m²] and second moment about its own centreline ``it`` [m⁴] (exact for a
    waterplane that is one strip per station)."""

    volume: Float[Array, ""]
    xb: Float[Array, ""]
    yb: Float[Array, ""]
    zb: Float[Array, ""]
    awp: Float[Array, ""]
    it: Float[Array, ""]


def heeled_integrals(sections: Sections, heel: Angle, level: Length, trim: Scalar = 0.0) -> HeeledIntegrals:
    """Volume and centre of buoyancy below the waterplane ``z' = level + trim·(x − Lpp/2)`` at ``heel``
    [rad] (see the module docstring). Exact per section, Simpson along x; differentiable in everything.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    heel : float or Array, scalar
        Heel φ [rad], starboard down positive.
    level : float or Array, scalar
        Waterplane height z' at midship [m] in the heeled frame (the body frame turned by ``heel`` about x).
    trim : float or Array, scalar
        Trim slope ``s = tan θ``, bow down positive (0 by default).

    Returns
    -------
    HeeledIntegrals
        ``volume`` [m³]; ``xb`` [m from the AP], ``yb``, ``zb`` [m, heeled frame] (0 where dry); ``awp`` [m²];
        ``it`` [m⁴].
    """
    dtype = sections.yz.dtype
    heel, level, trim = (jnp.asarray(v, dtype=dtype) for v in (heel, level, trim))
    poly = _rotate(full_sections(sections.yz), heel)
    levels = level + trim * (sections.x - 0.5 * sections.lpp)
    s = polygon_integrals(poly, levels)
    w = simpson_weights(sections.x)
    volume = w @ s.area
    wet = volume > 0.0
    return HeeledIntegrals(
        volume=volume,
        xb=safe_div(w @ (sections.x * s.area), volume, wet),
        yb=safe_div(w @ s.moment_y, volume, wet),
        zb=safe_div(w @ s.moment_z, volume, wet),
        awp=w @ s.width,
        it=w @ s.width**3 / 12.0,
    )


def _level_bounds(sections: Sections, heel) -> tuple[Array, Array]:
    z = _rotate(full_sections(sections.yz), heel)[..., 1]
    return jnp.min(z), jnp.max(z)


def heeled_level(sections: Sections, heel: Angle, volume: Volume, rtol: float = BISECTION_TOL,
                 atol: float | None = None) -> Array:
    """The waterplane height [m] (heeled frame, no trim) at which the hull heeled by ``heel`` [rad]
    displaces ``volume`` [m³]. Bisection between the lowest and highest point of the hull (robust when the
    deck or the bilge leaves the water), differentiable by the implicit function theorem.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    heel : float or Array, scalar
        Heel φ [rad], starboard down positive.
    volume : float or Array, scalar
        Displaced volume [m³], positive.
    rtol : float
        Relative tolerance of the bisection on the level (1e-12 by default).
    atol : float or None
        Absolute tolerance of the bisection: on the level [m] and on the volume's relative error (both must
        be met); None (default): 1e-12 × the hull's heeled height.

    Returns
    -------
    Array, scalar
        Waterplane height [m] at midship in the heeled frame (the solve does not raise: a volume out of
        reach is not reported).
    """
    import optimistix as optx  # here, not at import time (0.25 s of a one-off CLI call)

    dtype = sections.yz.dtype
    heel = jnp.asarray(heel, dtype=dtype)
    lo, hi = _level_bounds(sections, heel)

    def residual(h, args):
        sec, phi, target = args
        return heeled_integrals(sec, phi, h).volume / target - 1.0

    solver = optx.Bisection(rtol=rtol, atol=BISECTION_TOL * (hi - lo) if atol is None else atol, flip=False)
    sol = optx.root_find(
        residual, solver, 0.5 * (lo + hi), args=(sections, heel, jnp.asarray(volume, dtype=dtype)),
        options={"lower": lo, "upper": hi}, max_steps=256, throw=False,
    )
    return sol.value


class Equilibrium(eqx.Module):
    """Floating position at one heel: ``level`` [m], ``trim`` (tan θ, bow down positive), the buoyancy
    integrals there, and whether the solve converged."""

    level: Float[Array, ""]
    trim: Float[Array, ""]
    integrals: HeeledIntegrals
    converged: Bool[Array, ""]


def heeled_equilibrium(sections: Sections, heel: Angle, volume: Volume, lcg: Length, kg: Length,
                       free_trim: bool = True) -> Equilibrium:
    """Sink (and, with ``free_trim``, trim) the hull heeled by ``heel`` [rad] until it displaces ``volume``
    [m³] and, with free trim, B lies on the vertical through G = (lcg, 0, kg) in the longitudinal plane:
    ``(x_B − x_G) + s (z'_B − z'_G) = 0``. Sinkage first by bisection (no trim; with free trim only to a volume
    within 1e-4, Newton's start), then Newton on (level, trim) from there to 1e-11; both differentiable by the implicit function theorem.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    heel : float or Array, scalar
        Heel φ [rad], starboard down positive.
    volume : float or Array, scalar
        Displaced volume [m³].
    lcg : float or Array, scalar
        Longitudinal centre of gravity [m from the AP] (used only with ``free_trim``).
    kg : float or Array, scalar
        Centre of gravity [m above the baseline] (used only with ``free_trim``).
    free_trim : bool
        Solve for the trim too (True, default), or float on even keel.

    Returns
    -------
    Equilibrium
        ``level`` [m] and ``trim`` (tan θ) as scalars, the :class:`HeeledIntegrals` there, ``converged`` (bool).
    """
    import optimistix as optx  # here, not at import time (0.25 s of a one-off CLI call)

    dtype = sections.yz.dtype
    heel, volume, lcg, kg = (jnp.asarray(v, dtype=dtype) for v in (heel, volume, lcg, kg))
    if not free_trim:
        level0 = heeled_level(sections, heel, volume)
        hi = heeled_integrals(sections, heel, level0)
        return Equilibrium(level0, jnp.zeros_like(level0), hi, jnp.abs(hi.volume / volume - 1.0) < 1e-8)
    # Newton's start: a coarse bisection (level and volume to 1e-4), about half the bisection steps of a full
    # one; Newton then converges as from the exact level (its result and implicit gradient do not depend on it)
    level0 = heeled_level(sections, heel, volume, rtol=1e-4, atol=1e-4)
    lpp = sections.lpp

    def residual(y, args):
        sec, phi, target, xg, zg = args
        b = heeled_integrals(sec, phi, y[0], y[1])
        zg_heeled = zg * jnp.cos(phi)
        return jnp.stack([b.volume / target - 1.0, (b.xb - xg + y[1] * (b.zb - zg_heeled)) / sec.lpp])

    y0 = jnp.stack([level0, jnp.zeros_like(level0)])
    solver = optx.Newton(rtol=1e-11, atol=1e-11 * lpp)
    sol = optx.root_find(residual, solver, y0, args=(sections, heel, volume, lcg, kg), max_steps=64, throw=False)
    level, trim = sol.value[0], sol.value[1]
    hi = heeled_integrals(sections, heel, level, trim)
    ok = (sol.result == optx.RESULTS.successful) & (jnp.abs(hi.volume / volume - 1.0) < 1e-8)
    return Equilibrium(level, trim, hi, ok)


class Upright(eqx.Module):
    """Upright, even-keel floating position at a volume: ``level`` (the draft) [m], ``lcb`` [m from the
    AP], ``kb`` and ``bmt`` [m]."""

    level: Float[Array, ""]
    lcb: Float[Array, ""]
    kb: Float[Array, ""]
    bmt: Float[Array, ""]


def upright(sections: Sections, volume: Volume) -> Upright:
    """Draft, LCB, KB and BM_T upright on even keel at ``volume`` [m³], from the full (heel 0) sections, so
    a raised deck line is included. ``lcb`` is the LCG that floats the hull level;
    GM₀ = KB + BM_T − KG − FSC.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    volume : float or Array, scalar
        Displaced volume [m³].

    Returns
    -------
    Upright
        Scalars ``level`` [m above the baseline], ``lcb`` [m from the AP], ``kb`` [m], ``bmt`` [m].
    """
    level = heeled_level(sections, 0.0, volume)
    b = heeled_integrals(sections, 0.0, level)
    return Upright(level, b.xb, b.zb, b.it / b.volume)


class StabilityCurve(eqx.Module):
    """A GZ curve. ``heel (k,)`` [rad]; ``gz (k,)`` [m] righting lever with the free-surface correction
    (``gz = y'_G − y'_B − fsc·sin φ``); ``kn (k,)`` [m] = GZ without correction + KG sin φ; ``level (k,)``
    [m] waterplane height at midship (heeled frame); ``trim (k,)`` tan θ, bow down positive; ``converged
    (k,)``. Scalars: ``volume`` [m³], ``kg``, ``lcg``, ``fsc`` [m], ``gm0`` [m] (corrected)."""

    heel: Float[Array, " k"]
    gz: Float[Array, " k"]
    kn: Float[Array, " k"]
    level: Float[Array, " k"]
    trim: Float[Array, " k"]
    converged: Bool[Array, " k"]
    volume: Float[Array, ""]
    kg: Float[Array, ""]
    lcg: Float[Array, ""]
    fsc: Float[Array, ""]
    gm0: Float[Array, ""]


def gz_curve(sections: Sections, volume: Volume, kg: Length, heels: Angles, lcg: Length | None = None,
             fsc: Length = 0.0, free_trim: bool = True) -> StabilityCurve:
    """Righting levers at ``heels (k,)`` [rad] for the loading ``volume`` [m³], ``kg`` [m above the
    baseline], ``lcg`` [m from the AP] (default: the upright LCB, so the hull floats on even keel upright)
    and free-surface correction ``fsc`` [m]. One ``vmap`` over heels; differentiable in the geometry and
    the loading.

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    volume : float
        Displaced volume [m³] of the loading.
    kg : float
        Centre of gravity [m above the baseline].
    heels : Array, shape (k,)
        Heel angles [rad], positive to starboard (either side gives the same levers for a symmetric hull).
    lcg : float or None
        Longitudinal centre of gravity [m from the AP]; None: the upright LCB.
    fsc : float
        Free-surface correction [m], subtracted as ``fsc·sin φ``.
    free_trim : bool
        Find the trim that balances the LCG at each heel (True) or keep the upright trim.

    Returns
    -------
    StabilityCurve
        ``gz (k,)`` [m], righting positive; ``kn (k,)`` [m]; ``gm0`` [m]; see :class:`StabilityCurve`.

    Examples
    --------
    A box barge 100 × 20 m at 5 m draft with KG 5 m: GM = KB + BM − KG = 2.5 + 20²/(12·5) − 5 = 4.1667 m,
    and before the deck edge immerses the wall-sided formula GZ = sin φ (GM + ½ BM tan² φ) = 0.8550 m at
    φ = 0.2 rad:

    >>> import jax; jax.config.update("jax_enable_x64", True)
    >>> import jax.numpy as jnp
    >>> from hullopt.models import box
    >>> from hullopt.hydro import gz_curve
    >>> gz = jax.jit(gz_curve, static_argnames="free_trim")
    >>> c = gz(box(100, 20, 10), 10000.0, 5.0, jnp.array([0.2]), free_trim=False)
    >>> round(float(c.gm0), 4), round(float(c.gz[0]), 4)
    (4.1667, 0.855)
    """
    dtype = sections.yz.dtype
    volume, kg, fsc = (jnp.asarray(v, dtype=dtype) for v in (volume, kg, fsc))
    up = upright(sections, volume)
    lcg = up.lcb if lcg is None else jnp.asarray(lcg, dtype=dtype)
    heels = jnp.asarray(heels, dtype=dtype)
    eq = jax.vmap(heeled_equilibrium, in_axes=(None, 0, None, None, None, None))(
        sections, heels, volume, lcg, kg, free_trim
    )
    s = jnp.sin(heels)
    gz_dry = -kg * s - eq.integrals.yb
    return StabilityCurve(
        heel=heels, gz=gz_dry - fsc * s, kn=gz_dry + kg * s, level=eq.level, trim=eq.trim,
        converged=eq.converged, volume=volume, kg=kg, lcg=lcg, fsc=fsc, gm0=up.kb + up.bmt - kg - fsc,
    )


def cross_curves(sections: Sections, volumes: Volumes, heels: Angles, free_trim: bool = True) -> Float[Array, "v k"]:
    """KN [m] at every volume ``(v,)`` [m³] and heel ``(k,)`` [rad]: the cross curves of stability, each
    with KG = 0 and LCG at the upright LCB of its volume (free trim) or even keel (fixed trim).

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    volumes : array_like, (v,) float
        Displaced volumes [m³].
    heels : array_like, (k,) float
        Heels [rad], starboard down positive.
    free_trim : bool
        Trim free at each heel (True, default) or even keel.

    Returns
    -------
    Array, (v, k) float
        KN [m].
    """
    dtype = sections.yz.dtype

    def one(v):
        return gz_curve(sections, v, jnp.zeros((), dtype), heels, free_trim=free_trim).kn

    return jax.vmap(one)(jnp.asarray(volumes, dtype=dtype))


class Stability(eqx.Module):
    """A GZ curve at the requested heels and the IS Code criteria of the same loading."""

    curve: StabilityCurve
    criteria: Criteria


def stability(sections: Sections, volume: Volume, kg: Length, heels: Angles, lcg: Length | None = None,
              fsc: Length = 0.0, free_trim: bool = True, flooding_angle: Angle | None = None, n_grid: int = 91,
              tau: float = 0.01, on_grid: bool | None = None) -> Stability:
    """:func:`gz_curve` at ``heels`` [rad] and :func:`~hullopt.hydro.criteria_from_gz` (IS Code 2008
    §2.2), from one ``vmap`` over the requested heels and the criteria's heels. Requested heels that all lie on
    the criteria's uniform grid (within 1e-12 rad; e.g. 0…90° in 5° steps with the default grid) are not solved
    again: the curve takes the grid's equilibria. ``flooding_angle`` θf
    [rad] or None; ``n_grid`` heels on [0, 90°] for the maximum; ``tau`` [m] the soft-max temperature.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    volume : float
        Displaced volume [m³] of the loading.
    kg : float
        Centre of gravity [m above the baseline].
    heels : array_like, (k,) float
        Heels [rad] of the returned curve.
    lcg : float or None
        Longitudinal centre of gravity [m from the AP]; None: the upright LCB.
    fsc : float
        Free-surface correction [m] (0 by default).
    free_trim : bool
        Trim free at each heel (True, default) or the upright trim.
    flooding_angle : float or None
        Downflooding angle θf [rad]; None: no limit below 40°.
    n_grid : int
        Uniform heels on [0, 90°] for the criteria's maximum (91 by default).
    tau : float
        Softmax temperature [m] of the smooth margins (0.01 by default).
    on_grid : bool or None
        Whether every requested heel lies on the uniform grid, for a caller that traces ``heels`` and knows
        it (then one way is compiled; a wrong True returns the nearest grid heels' values); None (default):
        read off ``heels``, by a ``lax.cond`` that compiles both ways when they are traced.

    Returns
    -------
    Stability
        ``curve``, the :class:`StabilityCurve` at ``heels`` (fields ``(k,)``), and ``criteria``, the
        :class:`Criteria`.
    """
    heels = jnp.asarray(heels, dtype=sections.yz.dtype)
    k = heels.shape[0]
    extra = criteria_heels(flooding_angle, n_grid).astype(heels.dtype)
    n_gauss = extra.shape[0] - n_grid
    step = 0.5 * jnp.pi / (n_grid - 1)
    idx = jnp.clip(jnp.round(heels / step), 0, n_grid - 1).astype(int)  # the nearest heel of the uniform grid
    near = jnp.all(jnp.abs(heels - extra[n_gauss + idx]) <= ANGLE_TOL)
    fields = ("heel", "gz", "kn", "level", "trim", "converged")

    def solve(at: Array, take: Array) -> Stability:
        """GZ at the heels ``at``; the curve is ``at[take]`` (shown at the requested heels)."""
        c = gz_curve(sections, volume, kg, at, lcg, fsc, free_trim)
        crit = criteria_from_gz(c.gz[at.shape[0] - extra.shape[0]:], c.gm0, flooding_angle, n_grid, tau=tau)
        curve = eqx.tree_at(lambda t: tuple(getattr(t, f) for f in fields), c,
                            (heels, *(getattr(c, f)[take] for f in fields[1:])))
        return Stability(curve, crit)

    def shared() -> Stability:  # every requested heel on the grid: one heel set (the default 0:90:19 does)
        return solve(extra, n_gauss + idx)

    def apart() -> Stability:
        return solve(jnp.concatenate([heels, extra]), jnp.arange(k))

    if on_grid is None:
        try:  # heels known while tracing: one branch compiled
            on_grid = bool(near)
        except jax.errors.ConcretizationTypeError:  # heels traced and the caller silent: chosen when run
            return jax.lax.cond(near, shared, apart)
    return shared() if on_grid else apart()
