"""Sectional (2D) heave hydrodynamics by Frank's close-fit source method, deep water.

Each station's immersed half-section (below the draft) is resampled to ``n_panels`` straight panels, mirrored
to the starboard side, and the heave radiation problem at frequency ω is solved with constant-strength
pulsating sources on the panels (Frank 1967, "Oscillation of cylinders in or below the free surface of deep
fluids", NSRDC Report 2375). Everything has a fixed shape, so it vmaps over stations, frequencies and designs.

Conventions
-----------
Time dependence e^{iωt}; local coordinates (y to port, z up from the *waterline*, fluid z < 0); n is the
body's normal pointing into the fluid. With ν = ω²/g the Green function of a unit source at (η, ζ) is

    G = ln r − ln r₁ − 2 Re[e^w (E₁(w) + iπ)] + 2πi e^{ν(z+ζ)} cos ν(y−η),   w = ν(z + ζ + i|y − η|),

(r, r₁ the distances to the source and to its image above the free surface), which satisfies the free-surface
condition ∂G/∂z = νG at z = 0 and radiates outgoing waves e^{i(ωt − ν|y|)}. (The principal-value wave
integral −2 PV∫₀^∞ e^{k(z+ζ)} cos k(y−η)/(k − ν) dk equals the E₁ term; E₁ is the exponential integral of
complex argument, :func:`exp1`.) The heave potential φ (unit heave velocity, ∂φ/∂n = n_z) gives the
sectional added mass and damping per unit length, both sides together,

    a33 = −ρ Re ∮ φ n_z ds,      b33 = ρ ω Im ∮ φ n_z ds,

i.e. the radiation force −a33 η̈ − b33 η̇. The Rankine parts (ln r, ln r₁) are integrated over each panel in
closed form; the wave part by Gauss–Legendre quadrature (``n_gauss`` points per panel).

Irregular frequencies: the source formulation fails at the eigenfrequencies of the interior (sloshing)
problem with φ = 0 on the inner waterline; for a rectangle of beam B and draft T the first is
ν = (π/B) coth(πT/B), for a semicircle νR ≈ 2.8. At zero speed ship strips meet them only at high frequency
(ω²B/2g ≳ 1.5, i.e. λ/L ≲ 0.25 for B/L ≈ 0.15–0.2); at speed the encounter frequency is higher: the KCS at
Fn 0.26 has ω_e²B/2g ≈ 7 already at λ/L 0.3, and R_AWM shows spikes there (11× its peak at λ/L 0.20, bumps of
a few % of the peak at λ/L 0.3–0.7). Nothing removes them here (no lid, no modified Green function): the
sea-state mean takes R_AWM from λ/L ≥ 0.3 only (:func:`hullopt.waves.motion_response`), and
``heave_coefficients`` documents the range in which they are validated (see tests/test_sections2d.py).
"""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float

from .._types import Complexes, Draft, Scalar
from ..constants import G, RHO_SEA
from ..geometry import TINY_LENGTH, Sections, safe_div, safe_sqrt

EULER_GAMMA = 0.5772156649015329
# Both branches of exp1_scaled are evaluated for every element (vectorised, then selected), so the cost is
# _N_SERIES + _N_CF loop steps per element, a step of the fraction (a complex division) costing about twice one
# of the series: the series takes the hard region near the negative real axis (within 45° of it, |z| < 25;
# there the fraction converges slowly) and the fraction only what it reaches in 30 steps. Measured against
# scipy over the second quadrant, |z| ≤ 300: relative error < 1e-11 (|z| < 20), < 2e-9 everywhere; the former
# 60 + 60 steps gave 2e-12 and 2e-7, at 1.9× this cost.
_N_SERIES = 75  # terms of the E1 power series (|z| < 25 near the negative real axis, < 8 elsewhere)
_N_CF = 30  # depth of the backward-evaluated continued fraction
_SERIES_RADIUS = 8.0
_CUT_RADIUS = 25.0
_CUT_SLOPE = 1.0  # |Im z| < _CUT_SLOPE·|Re z|: within 45° of the negative real axis


_SERIES_COEF = 1.0 / (np.arange(1, _N_SERIES + 1) * np.cumprod(np.arange(1, _N_SERIES + 1, dtype=float)))


def _exp1_series(z):
    """E₁(z) = −γ − Log z − Σ_{n≥1} (−z)ⁿ/(n·n!) (principal branch, cut on the negative real axis); the sum
    by Horner's rule in a loop (no per-term arrays)."""
    u = -z
    coef = jnp.asarray(_SERIES_COEF, dtype=complex)

    def body(i, acc):
        return coef[_N_SERIES - 1 - i] + u * acc

    acc = jax.lax.fori_loop(0, _N_SERIES, body, jnp.zeros_like(z))
    return -EULER_GAMMA - jnp.log(z) - u * acc


def _exp1_cf_scaled(z):
    """e^z E₁(z) by the continued fraction 1/(z+1− 1²/(z+3− 2²/(z+5− …))) evaluated backwards (Re z > 0 or
    |z| large away from the negative real axis)."""

    def body(i, t):
        n = (_N_CF - i).astype(z.dtype)
        return n * n / (z + 2.0 * n + 1.0 - t)

    t = jax.lax.fori_loop(0, _N_CF, body, jnp.zeros_like(z))
    return 1.0 / (z + 1.0 - t)


@jax.custom_jvp
def exp1_scaled(z):
    """e^z E₁(z) for complex ``z`` (principal branch), finite gradients everywhere but z = 0.

    Power series (75 terms) for |z| < 8, and for |z| < 25 within 45° of the negative real axis (where the
    continued fraction converges slowly); continued fraction (30 steps) elsewhere. Measured against
    ``scipy.special.exp1`` over the second quadrant, |z| ≤ 300: relative error < 1e-11 for |z| < 20, < 2e-9
    everywhere. The two are selected with a double ``where`` so neither branch's gradient can be NaN.
    """
    z = jnp.asarray(z, dtype=complex)
    az = jnp.abs(z)
    near_cut = (z.real < 0.0) & (jnp.abs(z.imag) < _CUT_SLOPE * jnp.abs(z.real)) & (az < _CUT_RADIUS)
    small = (az < _SERIES_RADIUS) | near_cut
    zs = jnp.where(small, z, 1.0)
    zl = jnp.where(small, _SERIES_RADIUS + 0j, z)
    return jnp.where(small, jnp.exp(zs) * _exp1_series(zs), _exp1_cf_scaled(zl))


@exp1_scaled.defjvp
def _exp1_scaled_jvp(primals, tangents):
    # d/dz [e^z E₁(z)] = e^z E₁(z) − 1/z (holomorphic): no derivative through the series or the fraction.
    (z,), (dz,) = primals, tangents
    z = jnp.asarray(z, dtype=complex)
    f = exp1_scaled(z)
    return f, (f - 1.0 / z) * jnp.asarray(dz, dtype=complex)


def exp1(z: Complexes):
    """The exponential integral E₁(z) = ∫_z^∞ e^{−t}/t dt for complex ``z`` (principal branch).

    Parameters
    ----------
    z : complex or Array
        Argument (complex; real input is cast), any shape.

    Returns
    -------
    Array
        E₁(z), complex, shape of ``z``.
    """
    z = jnp.asarray(z, dtype=complex)
    return jnp.exp(-z) * exp1_scaled(z)


def _wave_term(dy, yz_sum, nu):
    """Wave part of G and its gradient in the field point: returns (W, ∂W/∂y, ∂W/∂z) with
    W = −2 Re f(w) + 2πi e^{νY} cos νX, f(w) = e^w (E₁(w) + iπ), w = ν(Y + i|X|), X = y − η, Y = z + ζ."""
    ax = jnp.abs(dy)
    w = jax.lax.complex(nu * yz_sum, nu * ax)
    f = exp1_scaled(w) + 1j * jnp.pi * jnp.exp(w)
    fp = f - 1.0 / w  # f'(w)
    ev = jnp.exp(nu * yz_sum)
    c, s = jnp.cos(nu * dy), jnp.sin(nu * dy)
    zero = jnp.zeros_like(c)
    val = jax.lax.complex(-2.0 * f.real, 2.0 * jnp.pi * ev * c)
    d_ax = 2.0 * nu * fp.imag  # −2 Re(i ν f') = 2ν Im f'
    dy_ = jax.lax.complex(jnp.sign(dy) * d_ax, -2.0 * jnp.pi * nu * ev * s)
    dz_ = jax.lax.complex(-2.0 * nu * fp.real, 2.0 * jnp.pi * nu * ev * c + zero)
    return val, dy_, dz_


def _log_panel(p, a, b):
    """∫ ln|p − q| ds over the straight panel a → b and its gradient in p, in closed form.

    ``p`` (..., 2) field points, ``a``, ``b`` (..., 2) panel ends. Returns (value, grad_y, grad_z, theta)
    where theta is the angle the panel subtends (the η-derivative in the panel frame).
    """
    d = b - a
    length = safe_sqrt(jnp.sum(d * d, axis=-1))
    t = d / length[..., None]
    nl = jnp.stack([-t[..., 1], t[..., 0]], axis=-1)  # t rotated by +90°
    rel = p - a
    xi = jnp.sum(rel * t, axis=-1)
    eta = jnp.sum(rel * nl, axis=-1)
    r0sq = xi**2 + eta**2
    r1sq = (length - xi) ** 2 + eta**2
    theta = jnp.arctan2(eta * length, eta**2 + xi**2 - xi * length)
    # F(s) = (s − ξ) ln r(s) − s + η atan((s − ξ)/η);  value = F(L) − F(0)
    value = 0.5 * ((length - xi) * jnp.log(r1sq) + xi * jnp.log(r0sq)) - length + eta * theta
    d_xi = 0.5 * (jnp.log(r0sq) - jnp.log(r1sq))
    d_eta = theta
    gy = d_xi * t[..., 0] + d_eta * nl[..., 0]
    gz = d_xi * t[..., 1] + d_eta * nl[..., 1]
    return value, gy, gz, theta


def _gauss(n):
    xg, wg = np.polynomial.legendre.leggauss(n)
    return jnp.asarray(0.5 * (xg + 1.0)), jnp.asarray(0.5 * wg)


def _mirror(p):
    return p * jnp.asarray([-1.0, 1.0])


def _image(p):
    return p * jnp.asarray([1.0, -1.0])


def panel_geometry(nodes):
    """Midpoints (N, 2), lengths (N,) and fluid-side normals (N, 2) of the panels between ``nodes`` (N+1, 2),
    ordered from the keel (y = 0) to the waterline on the port side (the fluid on the right)."""
    a, b = nodes[:-1], nodes[1:]
    d = b - a
    length = safe_sqrt(jnp.sum(d * d, axis=-1))
    t = d / length[:, None]
    normal = jnp.stack([t[:, 1], -t[:, 0]], axis=-1)
    return 0.5 * (a + b), length, normal


def _influence(nodes, nu, n_gauss, infinite):
    """Potential (N, N) and normal-velocity (N, N) influence of unit sources on panel j (and its mirror, same
    strength) at the midpoint of panel i."""
    mid, length, normal = panel_geometry(nodes)
    a, b = nodes[:-1], nodes[1:]
    n_pan = mid.shape[0]
    p = mid[:, None, :]
    eye = jnp.eye(n_pan, dtype=bool)
    # Rankine parts: the panel, its mirror (same strength), and their images above the free surface (opposite).
    ends_a = jnp.stack([a, _mirror(a), _image(a), _image(_mirror(a))])  # (4, N, 2)
    ends_b = jnp.stack([b, _mirror(b), _image(b), _image(_mirror(b))])
    # At finite frequency the wave term's logarithmic part 2 ln r₁ is moved to the images (sign +1, integrated
    # in closed form) and only the bounded remainder W − 2 ln r₁ is left to the Gauss points; at ω → ∞ the
    # images carry −1 and there is no wave term.
    img = -1.0 if infinite else 1.0
    sgn = jnp.asarray([1.0, 1.0, img, img])[:, None, None]
    v, gy, gz, _ = _log_panel(p[None], ends_a[:, None], ends_b[:, None])  # (4, N, N)
    dnr = gy * normal[None, :, None, 0] + gz * normal[None, :, None, 1]
    pot = jnp.sum(sgn * v, axis=0).astype(complex)
    # Own panel, approached from the fluid side: the jump +π (the closed form's θ there is ±π by rounding).
    dn = (jnp.sum(sgn * dnr, axis=0) - jnp.where(eye, dnr[0], 0.0) + jnp.where(eye, jnp.pi, 0.0)).astype(complex)
    if not infinite:
        sg, wg = _gauss(n_gauss)
        q = a[:, None, :] + sg[None, :, None] * (b - a)[:, None, :]  # (N, G, 2) Gauss points, port side
        q = jnp.stack([q, _mirror(q)])  # (2, N, G, 2) both sides
        dy = p[None, :, :, None, 0] - q[:, None, :, :, 0]  # (2, N, N, G)
        ysum = p[None, :, :, None, 1] + q[:, None, :, :, 1]
        val, wy, wz = _wave_term(dy, ysum, nu)
        r1sq = dy * dy + ysum * ysum  # > 0: field points are panel midpoints, below the free surface
        val = val - jnp.log(r1sq).astype(complex)
        wy, wz = wy - (2.0 * dy / r1sq).astype(complex), wz - (2.0 * ysum / r1sq).astype(complex)
        wts = wg[None, None, None, :] * length[None, None, :, None]
        wts = wts.astype(complex)
        nyc, nzc = normal[None, :, None, None, 0].astype(complex), normal[None, :, None, None, 1].astype(complex)
        pot = pot + jnp.sum(val * wts, axis=(0, 3))
        dn = dn + jnp.sum((wy * nyc + wz * nzc) * wts, axis=(0, 3))
    return pot, dn, mid, length, normal


def heave_potential(nodes, omega, g: float = G, n_gauss: int = 4, infinite: bool = False):
    """Heave radiation potential for unit heave velocity at the panel midpoints of one half-section.

    Parameters
    ----------
    nodes : (N+1, 2) float
        Panel ends (y ≥ 0, z ≤ 0 from the waterline) from the keel to the waterline.
    omega : float
        Frequency [rad/s] (> 0); ignored when ``infinite``.
    infinite : bool
        The ω → ∞ limit (φ = 0 on the free surface).

    Returns
    -------
    phi (N,) complex, mid (N, 2), length (N,), normal (N, 2)
    """
    phi, _, mid, length, normal = _solve_heave(nodes, omega, g, n_gauss, infinite)
    return phi, mid, length, normal


def _solve_heave(nodes, omega, g, n_gauss, infinite):
    nu = omega**2 / g
    pot, dn, mid, length, normal = _influence(nodes, nu, n_gauss, infinite)
    sigma = jnp.linalg.solve(dn, normal[:, 1].astype(complex))
    return pot @ sigma, sigma, mid, length, normal


def far_field_damping(nodes, omega, rho: float = RHO_SEA, g: float = G, n_gauss: int = 4):
    """b33 [kg/(m s)] from the energy the radiated waves carry away (both sides), ρω|Φ∞|², with Φ∞ the
    far-field potential amplitude per unit heave velocity, 2πi Σ_j σ_j ∫ e^{νζ} 2cos(νη) ds: an independent
    check of the pressure integral in :func:`heave_coefficients` (same sources, another functional)."""
    nu = omega**2 / g
    _, sigma, _, _, _ = _solve_heave(nodes, omega, g, n_gauss, False)
    sg, wg = _gauss(n_gauss)
    a, b = nodes[:-1], nodes[1:]
    d = b - a
    q = a[:, None, :] + sg[None, :, None] * d[:, None, :]
    length = safe_sqrt(jnp.sum(d * d, axis=-1))
    kern = jnp.sum(wg * jnp.exp(nu * q[..., 1]) * 2.0 * jnp.cos(nu * q[..., 0]), axis=-1) * length
    far = 2.0 * jnp.pi * jnp.sum(sigma * kern.astype(complex))
    return rho * omega * jnp.abs(far) ** 2


def heave_coefficients(nodes: Float[ArrayLike, 'N 2'], omega: Scalar, rho: float = RHO_SEA, g: float = G,
                       n_gauss: int = 4, infinite: bool = False):
    """Sectional heave added mass a33 [kg/m] and damping b33 [kg/(m s)] of one section (both sides).

    ``nodes`` (N+1, 2): the port half-section's panel ends, keel to waterline (z ≤ 0 measured from the
    waterline). Validated (tests/test_sections2d.py) for ω²B/2g ≤ 2 on sections with B/T 0.5–4.

    Parameters
    ----------
    nodes : (N+1, 2) float
        Panel ends (y ≥ 0, z ≤ 0 from the waterline) [m] from the keel to the waterline.
    omega : float
        Frequency [rad/s] (> 0); ignored when ``infinite``.
    rho, g : float
        Water density [kg/m³] and gravity [m/s²].
    n_gauss : int
        Gauss points per panel for the wave term.
    infinite : bool
        The ω → ∞ limit (φ = 0 on the free surface; b33 = 0).

    Returns
    -------
    a33 : Array
        Added mass per unit length [kg/m], scalar.
    b33 : Array
        Damping per unit length [kg/(m s)], scalar.
    """
    phi, _, length, normal = heave_potential(nodes, omega, g, n_gauss, infinite)
    integral = 2.0 * jnp.sum(phi * (normal[:, 1] * length).astype(complex))
    return -rho * integral.real, rho * omega * integral.imag


def _clip_below(yz, draft: Draft, on_vertex_below: bool):
    """Each segment's part below ``draft`` in one convention for a vertex exactly at the draft: below
    (``on_vertex_below``, the branch of drafts just above it) or above (just below it). Returns the part's ends
    a, b (m−1, 2), its length (m−1,) — linear in the draft along a crossing segment, so a zero-length part
    still carries its derivative — and whether the segment has a part below (or touches the water)."""
    p0, p1 = yz[:-1], yz[1:]
    z0, z1 = p0[:, 1], p1[:, 1]
    dz = z1 - z0
    b0, b1 = (z0 <= draft, z1 <= draft) if on_vertex_below else (z0 < draft, z1 < draft)
    s = safe_div(draft - z0, dz, b0 != b1)  # the crossing's position along a crossing segment, in [0, 1]
    s_a = jnp.where(b0, 0.0, jnp.where(b1, s, 1.0))
    s_b = jnp.where(b1, 1.0, jnp.where(b0, s, 0.0))
    d = p1 - p0
    full = safe_sqrt(jnp.sum(d * d, axis=-1))
    a = p0 + s_a[:, None] * d
    b = p0 + s_b[:, None] * d
    a = a.at[:, 1].set(jnp.where(b0, z0, draft))
    b = b.at[:, 1].set(jnp.where(b1, z1, draft))
    # drop edges above the water, on the centreline, and lying on the waterline itself (in either convention)
    keep = (b0 | b1) & ((p0[:, 0] > 0.0) | (p1[:, 0] > 0.0)) & ~((z0 == draft) & (z1 == draft))
    return a, b, jnp.where(keep, (s_b - s_a) * full, 0.0), keep


def _resample_one(yz, draft: Draft, n_panels, min_half_breadth, on_vertex_below):
    a, b, seg, keep = _clip_below(yz, draft, on_vertex_below)
    cum = jnp.concatenate([jnp.zeros(1), jnp.cumsum(seg)])
    total = cum[-1]
    u = 0.5 * (1.0 - jnp.cos(jnp.linspace(0.0, jnp.pi, n_panels + 1)))  # cosine spacing in [0, 1]
    u = 0.5 * u + 0.5 * jnp.linspace(0.0, 1.0, n_panels + 1)  # half cosine, half uniform
    target = u * total
    n_seg = seg.shape[0]
    idx = jnp.clip(jnp.searchsorted(cum, target, side="right", method="compare_all") - 1, 0, n_seg - 1)
    frac = safe_div(target - cum[idx], seg[idx], seg[idx] > 0.0)
    p = a[idx] + frac[:, None] * (b[idx] - a[idx])
    # The last node is the waterline end of the last segment that reaches the water (in polyline order), also
    # where that part has zero length (a vertex on the draft) or dry segments follow it.
    last = n_seg - 1 - jnp.argmax(keep[::-1])
    p = p.at[-1].set(b[last])
    y = jnp.maximum(p[:, 0], min_half_breadth)
    return jnp.stack([y, p[:, 1] - draft], axis=-1), total


def _resample_polyline(yz, draft: Draft, n_panels, min_half_breadth):
    """The part of one half-section polyline (m, 2) below ``draft``, resampled to ``n_panels`` + 1 nodes
    equally spaced in arclength (cosine-clustered towards the waterline and keel), z from the waterline.

    A draft exactly on a vertex of the polyline (the Wigley at its design draft, an offset table with a
    waterline at T) is a kink of the immersed shape: drafts above it move along the segment above the vertex,
    drafts below along the one below. The nodes are the mean of the two branches — equal in value, and in
    derivative the mean of the one-sided derivatives, what central differences measure; between vertices both
    branches are the same function."""
    up, total = _resample_one(yz, draft, n_panels, min_half_breadth, True)
    down, _ = _resample_one(yz, draft, n_panels, min_half_breadth, False)
    return 0.5 * (up + down), total


def section_panels(sections: Sections, draft: Draft, n_panels: int = 20):
    """Every station's immersed half-section as ``n_panels`` panels: nodes (n, n_panels+1, 2) with z from the
    waterline (≤ 0), keel to waterline, and ``wet`` (n,) bool: the station has an immersed section (stations
    without one get a small semicircle, so the solve stays regular; mask their coefficients with ``wet``).

    Parameters
    ----------
    sections : Sections
        The hull's n stations (offsets [m] above the baseline).
    draft : float or Array
        Draft T [m above the baseline] (scalar).
    n_panels : int
        Panels per half-section.

    Returns
    -------
    nodes : Array
        (n, n_panels + 1, 2) float: panel ends (y, z) [m], z from the waterline.
    wet : Array
        (n,) bool: the station has an immersed section.
    """
    t = jnp.asarray(draft, dtype=sections.yz.dtype)
    b_ref = jnp.maximum(sections.max_half_breadth, TINY_LENGTH)
    nodes, total = jax.vmap(lambda yz: _resample_polyline(yz, t, n_panels, 1e-3 * b_ref))(sections.yz)
    depth = -jnp.min(nodes[..., 1], axis=-1)
    halfb = jnp.max(nodes[..., 0], axis=-1)
    wet = (total > 1e-3 * t) & (depth > 1e-3 * t) & (halfb > 2e-3 * b_ref)
    ang = jnp.linspace(0.0, 0.5 * jnp.pi, n_panels + 1)
    r = 0.1 * t
    dummy = jnp.stack([r * jnp.sin(ang), -r * jnp.cos(ang)], axis=-1)
    nodes = jnp.where(wet[:, None, None], nodes, dummy[None])
    return nodes, wet
