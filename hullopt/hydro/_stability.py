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
from ._roots import level_for_volume
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


def _stations(sections: Sections, heel: Array, level: Array, trim: Array):
    """Each station's immersed-area integrals (:class:`~hullopt.geometry.EdgeIntegrals`, fields ``(n,)``) below
    the waterplane ``z' = level + trim·(x − Lpp/2)`` at ``heel``, and that waterplane's height there ``(n,)``."""
    levels = level + trim * (sections.x - 0.5 * sections.lpp)
    return polygon_integrals(_rotate(full_sections(sections.yz), heel), levels), levels


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
    s, _ = _stations(sections, *(jnp.asarray(v, dtype=dtype) for v in (heel, level, trim)))
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


class Equilibrium(eqx.Module):
    """Floating position at a heel (fields scalars, or ``(k,)`` at ``k`` heels): ``level`` [m], ``trim`` (tan θ,
    bow down positive), the buoyancy integrals there, and whether the solve converged (the volume, and with free
    trim the balance, met to 1e-8)."""

    level: Float[Array, "*k"]
    trim: Float[Array, "*k"]
    integrals: HeeledIntegrals
    converged: Bool[Array, "*k"]


def _level_bounds(sections: Sections, heel) -> tuple[Array, Array]:
    z = _rotate(full_sections(sections.yz), heel)[..., 1]
    return jnp.min(z), jnp.max(z)


def _integrals(sections: Sections, heels: Array, levels: Array, trims: Array) -> HeeledIntegrals:
    """:func:`heeled_integrals` at every heel ``(k,)`` with its level and trim ``(k,)``: fields ``(k,)``."""
    return jax.vmap(heeled_integrals, in_axes=(None, 0, 0, 0))(sections, heels, levels, trims)


def _levels(sections: Sections, heels: Array, volume: Array, tol: float) -> Array:
    """Levels ``(k,)`` [m] at which the hull heeled by ``heels (k,)`` [rad] (no trim) displaces ``volume``, to
    ``tol`` (:func:`~._roots.level_for_volume`). Not differentiable: see :func:`_level_root`."""
    lo, hi = jax.vmap(_level_bounds, in_axes=(None, 0))(sections, heels)
    trims = jnp.zeros_like(heels)

    def integrate(level):
        b = _integrals(sections, heels, level, trims)
        return b.volume, b.awp

    return level_for_volume(integrate, lo, hi, volume, tol)


def _cramer(jac: Array, r: Array) -> Array:
    """``x (k, 2)`` with ``jac[i] @ x[i] = r[i]`` for ``jac (k, 2, 2)``, ``r (k, 2)`` (a singular block gives 0):
    each heel's residual depends on its own unknowns only."""
    det = jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]
    det = jnp.where(det != 0.0, det, jnp.inf)
    return jnp.stack([jac[:, 1, 1] * r[:, 0] - jac[:, 0, 1] * r[:, 1],
                      jac[:, 0, 0] * r[:, 1] - jac[:, 1, 0] * r[:, 0]], -1) / det[:, None]


def _trim_residual(sections: Sections, heels: Array, y: Array, volume: Array, lcg: Array,
                   kg: Array) -> tuple[Array, Array]:
    """The free-trim residual ``(k, 2)`` at ``y = (level, trim) (k, 2)`` — the volume's relative error and B
    off the vertical through G [Lpp] — and its Jacobian ``(k, 2, 2)`` from the waterline breadths: at a
    station whose waterline is at ℓ = level + trim (x − Lpp/2), dA/dℓ = b and d(∫z' dA)/dℓ = ℓ b (one
    evaluation of the sections, where jax's forward Jacobian takes three)."""
    x, xm, w = sections.x, sections.x - 0.5 * sections.lpp, simpson_weights(sections.x)
    st, lv = jax.vmap(_stations, in_axes=(None, 0, 0, 0))(sections, heels, y[:, 0], y[:, 1])  # (k, n) each
    b, trim, zg = st.width, y[:, 1:], kg * jnp.cos(heels)[:, None]
    v = st.area @ w
    v_ = jnp.where(v > 0.0, v, 1.0)[:, None]
    xb, zb = ((st.area * x) @ w)[:, None] / v_, (st.moment_z @ w)[:, None] / v_

    def d(f):  # (k, 2): d(Σ w f A)/d(level, trim)
        return jnp.stack([(f * b) @ w, (f * b * xm) @ w], -1)

    dv = d(1.0)
    dxb, dzb = (d(x) - xb * dv) / v_, (d(lv) - zb * dv) / v_
    r = jnp.concatenate([v[:, None] / volume - 1.0, (xb - lcg + trim * (zb - zg)) / sections.lpp], -1)
    j1 = (dxb + trim * dzb + jnp.concatenate([jnp.zeros_like(zb), zb - zg], -1)) / sections.lpp
    return r, jnp.stack([dv / volume, j1], 1)


@jax.custom_jvp
def _level_root(sections: Sections, heels: Array, volume: Array) -> Array:
    """:func:`_levels` to 1e-12, differentiable by the implicit function theorem: at the root
    dℓ = −(∂V/∂p · dp − dvolume)/A_wp. A ``custom_jvp``, so that a program without gradients traces no
    linearisation."""
    return _levels(sections, heels, volume, BISECTION_TOL)


@_level_root.defjvp
def _level_root_jvp(primals, tangents):
    level = _level_root(*primals)

    def error(sections, heels, volume):  # [m³]
        b = _integrals(sections, heels, level, jnp.zeros_like(heels))
        return b.volume - volume, b.awp

    (_, awp), (d_error, _) = jax.jvp(error, primals, tangents)
    return level, -d_error / jnp.where(awp > 0.0, awp, jnp.inf)


@jax.custom_jvp
def _trim_root(sections: Sections, heels: Array, volume: Array, lcg: Array, kg: Array) -> Array:
    """``(level, trim) (k, 2)`` with the free-trim residual of :func:`_trim_residual` zero: the level to a
    volume within 1e-4 without trim (Newton's start), then Newton on both to 1e-11 (optimistix's test; its
    result and implicit gradient do not depend on the start). Differentiable by the implicit function theorem
    with the residual's own Jacobian (per heel, 2 × 2), traced only for gradients (a ``custom_jvp``)."""
    args = (volume, lcg, kg)
    y = jnp.stack([_levels(sections, heels, volume, 1e-4), jnp.zeros_like(heels)], -1)

    def body(carry):
        y, done, i = carry
        dy = _cramer(*_trim_residual(sections, heels, y, *args)[::-1])
        small = jnp.all(jnp.abs(dy) <= 1e-11 * (sections.lpp + jnp.abs(y)), axis=-1)
        return jnp.where(done[:, None], y, y - dy), done | small, i + 1

    start = (y, jnp.zeros(heels.shape, bool), 0)
    return jax.lax.while_loop(lambda c: ~jnp.all(c[1]) & (c[2] < 64), body, start)[0]


@_trim_root.defjvp
def _trim_root_jvp(primals, tangents):
    y = _trim_root(*primals)
    sections, heels, *args = primals

    def residual(sections, heels, *args):
        return _trim_residual(sections, heels, y, *args)

    (_, jac), (dr, _) = jax.jvp(residual, primals, tangents)
    return y, -_cramer(jac, dr)


def _equilibria(sections: Sections, heels: Array, volume: Array, lcg: Array, kg: Array,
                free_trim: bool) -> Equilibrium:
    """:func:`heeled_equilibrium` at every heel ``(k,)`` at once: fields ``(k,)``."""
    zeros = jnp.zeros_like(heels)
    if not free_trim:
        level = _level_root(sections, heels, volume)
        b = _integrals(sections, heels, level, zeros)
        return Equilibrium(level, zeros, b, jnp.abs(b.volume / volume - 1.0) < 1e-8)
    level, trim = jnp.moveaxis(_trim_root(sections, heels, volume, lcg, kg), -1, 0)
    b = _integrals(sections, heels, level, trim)
    off = (b.xb - lcg + trim * (b.zb - kg * jnp.cos(heels))) / sections.lpp  # the residual, from b
    return Equilibrium(level, trim, b, (jnp.abs(b.volume / volume - 1.0) < 1e-8) & (jnp.abs(off) < 1e-8))


def heeled_level(sections: Sections, heel: Angle, volume: Volume) -> Array:
    """The waterplane height [m] (heeled frame, no trim) at which the hull heeled by ``heel`` [rad] displaces
    ``volume`` [m³]: Newton's steps on the waterplane area, bisection where they would leave the bracket (the
    lowest and highest point of the hull; robust when the deck or the bilge leaves the water), to 1e-12 of
    the volume or of the hull's height; differentiable by the implicit function theorem.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    heel : float or Array, scalar
        Heel φ [rad], starboard down positive.
    volume : float or Array, scalar
        Displaced volume [m³], positive.

    Returns
    -------
    Array, scalar
        Waterplane height [m] at midship in the heeled frame (the solve does not raise: a volume out of
        reach is not reported).
    """
    dtype = sections.yz.dtype
    heel, volume = jnp.asarray(heel, dtype=dtype), jnp.asarray(volume, dtype=dtype)
    z = jnp.zeros((), dtype)
    return _equilibria(sections, heel[None], volume, z, z, free_trim=False).level[0]


def heeled_equilibrium(sections: Sections, heel: Angle, volume: Volume, lcg: Length, kg: Length,
                       free_trim: bool = True) -> Equilibrium:
    """Sink (and, with ``free_trim``, trim) the hull heeled by ``heel`` [rad] until it displaces ``volume``
    [m³] and, with free trim, B lies on the vertical through G = (lcg, 0, kg) in the longitudinal plane:
    ``(x_B − x_G) + s (z'_B − z'_G) = 0``. The level first (no trim; with free trim only to a volume within 1e-4,
    Newton's start), then Newton on (level, trim) from there to 1e-11; differentiable by the implicit function
    theorem.

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
        ``level`` [m] and ``trim`` (tan θ) as scalars, the :class:`HeeledIntegrals` there, ``converged`` (bool:
        the volume, and with free trim the balance, met to 1e-8).
    """
    dtype = sections.yz.dtype
    heel, volume, lcg, kg = (jnp.asarray(v, dtype=dtype) for v in (heel, volume, lcg, kg))
    return jax.tree.map(lambda a: a[0], _equilibria(sections, heel[None], volume, lcg, kg, free_trim))


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
    and free-surface correction ``fsc`` [m]. All heels solved in one loop; differentiable in the geometry and
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
    eq = _equilibria(sections, heels, volume, lcg, kg, free_trim)
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
    §2.2), from one solve of the requested heels and the criteria's heels. Requested heels that all lie on
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
