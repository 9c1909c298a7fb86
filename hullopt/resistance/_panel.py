"""Wave resistance by a Rankine-source panel method on the hull's true surface, in deep water.

The hull below the draft T, panelled from its sections, carries constant-strength sources σ (flat quadrilateral
panels, Hess & Smith 1964). Step 1, the double-body flow: the hull and its mirror image in the waterplane z = T
(a rigid free surface, the zero-Froude limit) in the stream −U·x̂ of a ship moving ahead; σ from the Neumann
condition ∂φ/∂n = U·n_x at the panel centroids, a dense second-kind system (port/starboard and the waterplane
mirror by images, so only the port side's wet panels are unknowns). Step 2, the waves: the submerged sources
radiate Kelvin waves through Havelock's far-field spectrum (λ = sec θ, k₀ = g/U²)::

    R_w = (ρ g²/(π U⁴)) ∫₁^∞ |S(λ)|² λ²/√(λ² − 1) dλ,
    S(λ) = Σ_panels σ ∫_panel e^{k₀λ²(z − T)} e^{i k₀λ x} 2 cos(k₀λ√(λ² − 1) y) dA    (both sides),

the same constant and λ rule as :mod:`._michell`'s integral, which this is when the sources are Michell's thin-ship
ones (σ = U·n_x on each side of a thin hull): the thin Wigley gives Michell's value (tests). The true-surface
sources add what thin-ship theory lacks — the hull's thickness, its flat bottom, the bulb's and the stern's 3-D
flow — so the method stays meaningful on full and bulbous hulls. It is the zeroth order of the Neumann–Michell
family (Noblesse, Huang & Yang 2013): hull panels only, no free-surface panels; the free-surface condition is
Kelvin's (linearised about the stream), not Dawson's double-body one.

Panel integrals of the wave spectrum are exact for rectangles, ∫ e^{a·r} dA = A e^{a·c} shc(a·h₁) shc(a·h₂)
(c the centre, h₁, h₂ the half-sides, shc(s) = sinh(s)/s): each panel is taken as the rectangle of its area in
its plane with one side horizontal and the other spanning its heights, so the short waves of large λ and the
steep decay e^{k₀λ²(z−T)} of the top panel row need no finer panels, and no corner rises above the waterline
(a parallelogram of the mean edges did on twisted bow panels: e^{k₀λ²δ} blew up at low speed). Panel velocities are Hess & Smith's
closed forms: in-plane from the edges' logarithms, normal from the solid angle (van Oosterom & Strackee 1983).

A dry transom is closed by flat panels on the end section (as Michell closes it by a source sheet): the
double-body flow stagnates there, and a transom stern's waves are overestimated at low speed — as in thin-ship
theory. Sinkage and trim come from the double-body pressure (the low-speed squat, not iterated), against the
waterplane's area and longitudinal moment of inertia.

Everything is pure JAX: differentiable in the sections, the draft and the speed; vmapped over speeds (the
double-body solve is done once: σ scales with U). Differentiating the dense solve costs one transposed solve.

References: Hess, J.L. & Smith, A.M.O. (1964) J. Ship Res. 8(2), 22–44. Havelock, T.H. (1932) Proc. R. Soc. A 138,
339–348 (the submerged sphere, the test). van Oosterom, A. & Strackee, J. (1983) IEEE Trans. Biomed. Eng. 30,
125–126. Noblesse, F., Huang, F. & Yang, C. (2013) J. Eng. Math. 79, 51–71.
"""

from __future__ import annotations

import functools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float

from .._types import Draft, Speed, Speeds, Values
from ..constants import G, RHO_SEA
from ..errors import HullError
from ..geometry import Sections, safe_div, safe_norm, safe_sqrt
from ._michell import LAMBDA_MAX, lambda_nodes

STATIONS = 48  # default panel columns along the length (cosine-clustered towards the ends)
GIRTH = 12  # default panel rows from the keel to the waterline
BLOCK_PAIRS = 1 << 18
"""Panel pairs a block of :func:`source_velocity` (~80 intermediates of 8 bytes each: ~170 MB a block)."""


class Panels(eqx.Module):
    """Flat source panels (the port side's), with their geometry.

    Attributes
    ----------
    vertices : (N, 4, 3) float
        Corners [m] (x forward from the AP, y to port, z up from the baseline), ordered counter-clockwise seen
        from outside the hull (the normal points into the water).
    draft : () float
        The waterplane z = T [m] the double body is mirrored in.
    """

    vertices: Float[Array, "N 4 3"]
    draft: Float[Array, ""]

    @property
    def centre(self) -> Float[Array, "N 3"]:
        return jnp.mean(self.vertices, axis=1)

    @property
    def area_vector(self) -> Float[Array, "N 3"]:
        """½ d₁ × d₂ of the diagonals: the outward normal times the (projected) area [m²]."""
        v = self.vertices
        return 0.5 * jnp.cross(v[:, 2] - v[:, 0], v[:, 3] - v[:, 1])

    @property
    def area(self) -> Float[Array, " N"]:
        return safe_norm(self.area_vector)

    @property
    def normal(self) -> Float[Array, "N 3"]:
        a = self.area
        return safe_div(self.area_vector, a[:, None], (a > 0.0)[:, None])

    @property
    def real(self) -> Float[Array, " N"]:
        """1 for a panel with an area, 0 for a collapsed one (a closed end, a section on the centreline)."""
        scale = jnp.max(self.area)
        return (self.area > 1e-10 * scale).astype(self.vertices.dtype)


def _girth(yz: Array, draft: Array, count: int, below: bool) -> tuple[Array, Array]:
    """The part of one half-section polyline (m, 2) below ``draft``, as ``count`` points equally spaced in girth
    from the keel to the waterline (edges on the centreline skipped), and the wet girth [m]. Each edge's wet
    part is a fraction of it, [0, s] or [s, 1] with s = (T − z₀)/(z₁ − z₀), so the wet girth has a one-sided
    derivative in T also when T sits on a point of the polyline (no square root of a clipped length): from
    above, or with ``below`` (a point at T counted dry) from below."""
    p0, p1 = yz[:-1], yz[1:]
    z0, z1 = p0[:, 1], p1[:, 1]
    dz = z1 - z0
    b0, b1 = (z0 < draft, z1 < draft) if below else (z0 <= draft, z1 <= draft)
    s = safe_div(draft - z0, dz, dz != 0.0)  # in [0, 1] where used (no clip: its tie at 0 halves dT)
    lo = jnp.where(b0, 0.0, s)
    hi = jnp.where(b1, 1.0, s)
    hi = jnp.where(b0 | b1, hi, lo)  # both ends above: nothing wet
    keep = (p0[:, 0] > 0.0) | (p1[:, 0] > 0.0)  # edges on the centreline get points only when all are there
    full = safe_norm(p1 - p0)
    weighted = full * jnp.where(keep, 1.0, 1e-9)
    seg = (hi - lo) * weighted
    cum = jnp.concatenate([jnp.zeros(1, yz.dtype), jnp.cumsum(seg)])
    u = 0.5 * (1.0 - jnp.cos(jnp.linspace(0.0, jnp.pi, count)))
    u = 0.5 * u + 0.5 * jnp.linspace(0.0, 1.0, count)  # half cosine (keel and waterline), half uniform
    target = u * cum[-1]
    # the edge each point falls on, at most the last edge with a wet end (the waterline's point is on the edge
    # whose fraction moves with T, so the points have the derivative the wet girth has)
    last = jnp.max(jnp.where(b0 | b1, jnp.arange(seg.shape[0]), 0))
    idx = jnp.searchsorted(cum, target, side="right", method="compare_all").astype(last.dtype) - 1
    idx = jnp.minimum(idx, last)
    idx = jnp.maximum(idx, 0)
    t = lo[idx] + safe_div(target - cum[idx], weighted[idx], weighted[idx] > 0.0)
    return p0[idx] + t[:, None] * (p1[idx] - p0[idx]), jnp.sum((hi - lo) * full)


@functools.partial(jax.custom_jvp, nondiff_argnums=(2,))
def _girth_points(yz: Array, draft: Array, count: int) -> tuple[Array, Array]:
    """:func:`_girth` with the derivative the mean of its one-sided ones where the draft sits on a polyline
    point (where the wet girth has a kink; elsewhere both sides agree): what central differences measure."""
    return _girth(yz, draft, count, False)


@_girth_points.defjvp
def _girth_points_jvp(count, primals, tangents):
    out, above = jax.jvp(lambda y, t: _girth(y, t, count, False), primals, tangents)
    _, below = jax.jvp(lambda y, t: _girth(y, t, count, True), primals, tangents)
    return out, jax.tree.map(lambda a, b: 0.5 * (a + b), above, below)


def hull_panels(sections: Sections, draft: Draft, stations: int = STATIONS, girth: int = GIRTH) -> Panels:
    """The port side of the hull below ``draft`` as ``(stations − 1)·girth`` panels, plus ``girth`` panels on each
    end section (a wet transom or bow face; collapsed to nothing on a closed end).

    Each section's wet part is resampled to ``girth + 1`` points equally spaced in its girth (half cosine:
    finer at the keel and the waterline); the stations are ``stations`` cosine-spaced positions between the
    wet length (the first to the last station with a wet section), each section linearly interpolated between
    the given ones.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array
        Draft T [m above the baseline].
    stations, girth : int
        Panel columns + 1 along the length, panel rows around the girth.

    Returns
    -------
    Panels
        ``(stations − 1)·girth + 2·girth`` panels.
    """
    if not (isinstance(stations, int) and stations >= 3 and isinstance(girth, int) and girth >= 2):
        raise HullError(f"panels: stations {stations!r} ≥ 3 and girth {girth!r} ≥ 2 expected (integers)")
    t = jnp.asarray(draft, dtype=sections.yz.dtype)
    xs = jnp.asarray(sections.x, dtype=sections.yz.dtype)
    yz, wet = jax.vmap(lambda p: _girth_points(p, t, girth + 1))(jnp.asarray(sections.yz))  # (n, g+1, 2)
    wet = wet > 1e-6 * (t - sections.keel)
    x_lo, x_hi = jnp.min(jnp.where(wet, xs, xs[-1])), jnp.max(jnp.where(wet, xs, xs[0]))
    u = 0.5 * (1.0 - jnp.cos(jnp.linspace(0.0, jnp.pi, stations)))
    x = x_lo + (x_hi - x_lo) * u
    flat = yz.reshape(yz.shape[0], -1)
    grid = jax.vmap(lambda col: jnp.interp(x, xs, col), in_axes=1, out_axes=1)(flat).reshape(stations, girth + 1, 2)
    pts = jnp.concatenate([jnp.broadcast_to(x[:, None, None], (stations, girth + 1, 1)), grid], axis=-1)
    # hull: (i, j) → (i, j+1) → (i+1, j+1) → (i+1, j): counter-clockwise seen from port (x forward, z up)
    hull = jnp.stack([pts[:-1, :-1], pts[:-1, 1:], pts[1:, 1:], pts[1:, :-1]], axis=2).reshape(-1, 4, 3)

    def cap(p, forward):  # the end section closed to the centreline at each height
        on = p.at[:, 1].set(0.0)
        q = jnp.stack([on[:-1], p[:-1], p[1:], on[1:]], axis=1)
        return q if forward else q[:, ::-1]

    caps = jnp.concatenate([cap(pts[0], False), cap(pts[-1], True)])
    return Panels(vertices=jnp.concatenate([hull, caps]), draft=t)


def _plane_frames(panels: Panels):
    """Each panel's unit normal n, in-plane axes (e₁, e₂) and corners in them (N, 4, 2), projected on the mean
    plane through the centroid."""
    n = panels.normal
    c = panels.centre
    d = panels.vertices[:, 2] - panels.vertices[:, 0]
    d = d - jnp.sum(d * n, -1, keepdims=True) * n
    dn = safe_norm(d)
    e1 = safe_div(d, dn[:, None], (dn > 0.0)[:, None])
    e2 = jnp.cross(n, e1)
    r = panels.vertices - c[:, None]
    local = jnp.stack([jnp.sum(r * e1[:, None], -1), jnp.sum(r * e2[:, None], -1)], axis=-1)
    return c, n, e1, e2, local


def source_velocity(points: Float[Array, "P 3"], panels: Panels, own: bool = False, flat: bool = False,
                    images: int = 1, block: int | None = None) -> Float[Array, "P M 3"]:
    """Velocity induced at ``points`` by each panel's unit source density (outflow 1 m³/s per m²),
    (1/4π) ∫ (p − q)/|p − q|³ dA, by Hess & Smith's closed forms: in-plane from the edges' logarithms, normal
    from the solid angle.

    The pairs are taken in blocks of ``block`` points (default: about :data:`BLOCK_PAIRS` pairs a block), one
    block at a time (``lax.map``) and each block checkpointed (``jax.checkpoint``): a gradient keeps only the
    points and the result, and recomputes a block's intermediates in the backward pass. Without the blocks the
    backward pass kept every pair's ~80 intermediates — a DTMB 5415 Dawson gradient 5.1 GB of its 5.1 GB peak
    (benchmarks/README.md, "Dawson's method as a design objective"); the values are the same (elementwise).

    Parameters
    ----------
    points : (P, 3) Array
        Field points (x, y, z) [m].
    panels : Panels
        N flat panels (non-planar corners are projected on the mean plane).
    own : bool
        The points are the first P panels' own centroids: a panel's velocity at its own centroid is the outside
        limit (normal part ½).
    flat : bool
        The points and the panels all lie in one plane (a flat free surface): the normal part is 0 there (½ at
        an own centroid), so the solid angle is not computed.
    images : int
        The panels are ``images`` sets of M = N/``images`` (a body and its mirror images, :func:`mirrored`),
        each set's velocities summed: (P, M, 3).
    block : int, optional
        Points a block (``block ≥ P``: one block, no map and no checkpoint).

    Returns
    -------
    (P, M, 3) Array
        Velocity [m/s per m/s of source density]; 0 from a collapsed panel.
    """
    frames = _plane_frames(panels)
    real = panels.real
    n_p, n_n = points.shape[0], panels.vertices.shape[0]
    rows = max(1, BLOCK_PAIRS // n_n) if block is None else int(block)

    def kernel(pts, idx):
        v = _source_kernel(pts, idx, frames, real, own, flat)
        return v if images == 1 else jnp.sum(v.reshape(v.shape[0], images, -1, 3), axis=1)

    if rows >= n_p:
        return kernel(points, jnp.arange(n_p))
    blocks = -(-n_p // rows)
    pad = blocks * rows - n_p  # the last block filled with copies of the first point (its row, then dropped)
    pts = jnp.concatenate([points, jnp.broadcast_to(points[:1], (pad, 3))]).reshape(blocks, rows, 3)
    idx = jnp.concatenate([jnp.arange(n_p), jnp.zeros(pad, int)]).reshape(blocks, rows)
    v = jax.lax.map(jax.checkpoint(lambda a: kernel(*a)), (pts, idx))
    return v.reshape(blocks * rows, *v.shape[2:])[:n_p]


def _source_kernel(points, idx, frames, real, own, flat):
    """:func:`source_velocity` of the points ``points`` (P, 3), rows ``idx`` (P,) of the whole (an own
    centroid: row i is panel i's), on the panels of ``frames`` (:func:`_plane_frames`) and ``real``."""
    c, n, e1, e2, local = frames
    # Every quantity is a list of (P, N) arrays, one per corner or edge k (its successor k + 1 by index, not by
    # rolling an axis): elementwise arithmetic XLA fuses, where stacked (P, N, 4, 3) arrays and their rolls made
    # copies of ~1 GB each way (a KCS Dawson solve's gradient spent most of its time in them).
    r = points[:, None, :] - c[None]  # (P, N, 3); exactly 0 at a panel's own centroid
    px, py, pz = (jnp.sum(r * e, -1) for e in (e1, e2, n))  # the points in each panel's frame
    ax, ay = [local[None, :, k, 0] for k in range(4)], [local[None, :, k, 1] for k in range(4)]
    nxt = [1, 2, 3, 0]
    ex, ey = [ax[nxt[k]] - ax[k] for k in range(4)], [ay[nxt[k]] - ay[k] for k in range(4)]
    dk = [safe_sqrt(ex[k] ** 2 + ey[k] ** 2) for k in range(4)]
    floor = 1e-13 * (jnp.max(jnp.stack(dk)) + 1.0)

    rx, ry = [a - px for a in ax], [a - py for a in ay]  # from the point to the corners, in the panel's frame
    rk = [safe_sqrt(rx[k] ** 2 + ry[k] ** 2 + pz**2) for k in range(4)]
    # a panel's own centroid (p ≈ 0: the solid angle jumps there) is masked out of the solid angle below and
    # takes the outside limit instead; the corners are shared with the edges' logarithms, not computed again
    eye = idx[:, None] == jnp.arange(px.shape[1])[None, :] if own else jnp.zeros((), dtype=bool)
    vx = vy = 0.0  # (1/4π)·Σ ν_k ∫ 1/r dl along the edges, times 4π; ν_k the edge's outward normal
    for k in range(4):
        s, d = rk[k] + rk[nxt[k]], dk[k]
        log = jnp.log(jnp.maximum(s + d, 1e-13) / jnp.maximum(s - d, floor))
        ok = d > 0.0
        vx = vx + safe_div(ey[k], d, ok) * log
        vy = vy - safe_div(ex[k], d, ok) * log
    # solid angle Ω: the fan of triangles (corner k, corner k+1, the frame's origin at the corners' mean)
    r3 = safe_sqrt(px**2 + py**2 + pz**2)
    z = -pz  # every corner's, and the origin's
    wn = jnp.zeros_like(pz)
    for k in range(0 if flat else 4):
        j = nxt[k]
        x1, y1, x2, y2 = rx[k], ry[k], rx[j], ry[j]
        # corners R = (x1, y1, z), R2 = (x2, y2, z), the origin R3 = (−px, −py, z); tan(Ω_k/2) = num/den
        num = x1 * (y2 + py) * z - y1 * (px + x2) * z + z * (y2 * px - x2 * py)  # R·(R2 × R3)
        den = (rk[k] * rk[j] * r3 + (x1 * x2 + y1 * y2 + z * z) * r3 - (x1 * px + y1 * py + z * pz) * rk[j]
               - (x2 * px + y2 * py + z * pz) * rk[k])
        ok = ((num != 0.0) | (den != 0.0)) & ~eye  # both 0 only on a collapsed panel (masked below) or at p = 0
        wn = wn - jnp.arctan2(jnp.where(ok, num, 0.0), jnp.where(ok, den, 1.0)) / (2.0 * jnp.pi)  # Ω/(4π)
    if own:
        wn = jnp.where(eye, 0.5, wn)
    v = (vx[..., None] * e1[None] + vy[..., None] * e2[None]) / (4.0 * jnp.pi) + wn[..., None] * n[None]
    return jnp.where(real[None, :, None] > 0.0, v, 0.0)  # a collapsed panel induces nothing


def mirrored(panels: Panels) -> Panels:
    """The port panels and their mirrors (starboard, above the waterplane z = ``panels.draft``, both), stacked
    in that order (4N panels), corners re-ordered so every image's normal points out of its own image of the
    hull."""
    v = panels.vertices
    t = panels.draft
    ys = v * jnp.array([1.0, -1.0, 1.0])
    zs = v.at[..., 2].set(2.0 * t - v[..., 2])
    yzs = zs * jnp.array([1.0, -1.0, 1.0])
    flip = lambda w: w[:, ::-1]  # noqa: E731  a mirror turns the winding
    return Panels(jnp.concatenate([v, flip(ys), flip(zs), yzs]), t)


def centre_velocities(panels: Panels) -> Float[Array, "N N 3"]:
    """Velocity at each panel centroid from unit σ on each panel and its three images (N, N, 3): the images
    stacked into one panel set (one program, not four), the own panel first (its diagonal is the own limit)."""
    return source_velocity(panels.centre, mirrored(panels), own=True, images=4)


def double_body_flow(panels: Panels, v: Float[Array, "N N 3"] | None = None
                     ) -> tuple[Float[Array, " N"], Float[Array, "N 3"]]:
    """The double-body flow past the hull at unit speed (the stream −x̂: the ship moves ahead).

    Parameters
    ----------
    panels : Panels
        The port side's wet panels (their images complete the hull and its mirror in the waterplane).
    v : (N, N, 3) Array, optional
        :func:`centre_velocities` of ``panels``, when the caller has it (computed here otherwise): a caller
        that uses it too shares one influence matrix, and one backward pass through it.

    Returns
    -------
    sigma : (N,) float
        Source densities [m/s per m/s of speed] from ∂φ/∂n = n_x at every real panel's centroid (σ = 0 on a
        collapsed panel).
    velocity : (N, 3) float
        The total velocity at the centroids [per m/s of speed]: the stream plus the sources'.
    """
    real = panels.real > 0.0
    v = centre_velocities(panels) if v is None else v
    a = jnp.sum(v * panels.normal[:, None, :], axis=-1)
    a = jnp.where(real[:, None] & real[None, :], a, jnp.eye(a.shape[0], dtype=a.dtype))
    sigma = jnp.linalg.solve(a, jnp.where(real, panels.normal[:, 0], 0.0))
    return sigma, jnp.einsum("pnk,n->pk", v, sigma) - jnp.array([1.0, 0.0, 0.0])


def _shc(s):
    """sinh(s)/s for complex s, by its series near 0 (finite derivatives everywhere)."""
    small = jnp.abs(s) < 1e-4
    ss = jnp.where(small, jnp.ones_like(s), s)
    return jnp.where(small, 1.0 + s * s / 6.0, jnp.sinh(ss) / ss)


def _sinc(y):
    """sin(y)/y for real y, by its series near 0 (finite derivatives everywhere): :func:`_shc` of i·y."""
    small = jnp.abs(y) < 1e-4
    yy = jnp.where(small, jnp.ones_like(y), y)
    return jnp.where(small, 1.0 - y * y / 6.0, jnp.sin(yy) / yy)


def _spectral_rectangles(panels: Panels):
    """Each panel as a rectangle in its own plane for the wave spectrum: centre (N, 3) and half-sides h₁ (N, 3)
    along the plane's steepest slope, spanning the panel's heights exactly, and h₂ (N, 3) horizontal
    (so no corner rises above the panel's highest point, where e^{k₀λ²(z − T)} would grow) with the panel's
    area. A horizontal panel takes its in-plane x direction for the slope."""
    c, n, _, _, _ = _plane_frames(panels)
    zhat = jnp.array([0.0, 0.0, 1.0])
    xhat = jnp.array([1.0, 0.0, 0.0])
    up = zhat - n[:, 2:3] * n
    flat = safe_norm(up) < 1e-6
    up = jnp.where(flat[:, None], xhat - n[:, 0:1] * n, up)
    ev = safe_div(up, safe_norm(up)[:, None], (safe_norm(up) > 0.0)[:, None])
    eh = jnp.cross(n, ev)
    v = jnp.sum((panels.vertices - c[:, None]) * ev[:, None], -1)  # (N, 4) along the slope
    lo, hi = jnp.min(v, -1), jnp.max(v, -1)
    span = hi - lo
    width = safe_div(panels.area, span, span > 0.0)
    centre = c + (0.5 * (lo + hi))[:, None] * ev
    return centre, 0.5 * span[:, None] * ev, 0.5 * width[:, None] * eh


def kelvin_spectrum(panels: Panels, sigma: Float[ArrayLike, ' N'], k0: Values, lam: Values) -> Array:
    """The submerged sources' (both sides) Havelock amplitude S(λ) at wave numbers k₀λ; each panel's integral
    exact for the rectangle of :func:`_spectral_rectangles`: A·e^{a·c}·shc(a·h₁)·shc(a·h₂), h the half-sides.

    Parameters
    ----------
    panels : Panels
        The port side's wet panels (the starboard side is added by symmetry).
    sigma : (N,) Array
        Source densities [m/s].
    k0 : float or Array
        g/U² [1/m].
    lam : (L,) Array
        λ = sec θ ≥ 1.

    Returns
    -------
    (L,) complex Array
        S(λ) [m³/s] (``sigma``'s unit times m²).
    """
    c, h1, h2 = _spectral_rectangles(panels)
    q = sigma * panels.area * panels.real  # (N,)
    kl = k0 * lam[:, None]  # (L, 1)
    ky = kl * jnp.sqrt(jnp.maximum(lam * lam - 1.0, 0.0))[:, None]
    kz = kl * lam[:, None]

    def along(r, sign):  # the imaginary part of a·r for a = (i kλ, i·sign·kλ√(λ²−1), k λ²), r (N, 3) → (L, N)
        return kl * r[None, :, 0] + sign * ky * r[None, :, 1]

    # real where they can be: e^{kλ²(z − T)} is both sides', and h₂ is horizontal, so shc(a·h₂) = sin(y)/y
    depth = jnp.exp(kz * (c[None, :, 2] - panels.draft)) * q  # (L, N)
    total = 0.0
    for sign in (1.0, -1.0):  # the port and starboard sources
        x = along(c, sign)
        h = _shc(jax.lax.complex(kz * h1[None, :, 2], along(h1, sign)))
        real = (depth * _sinc(along(h2, sign))).astype(h.dtype)
        total = total + jnp.sum(jax.lax.complex(jnp.cos(x), jnp.sin(x)) * h * real, axis=1)
    return total


class PanelResult(eqx.Module):
    """The panel method's calm-water wave results at k speeds (SI).

    Attributes
    ----------
    r_wave : (k,) float
        Wave resistance R_w [N].
    sinkage : (k,) float
        Sinkage at the centre of flotation [m], positive down (double-body pressure, not iterated).
    trim : (k,) float
        Trim [rad], positive bow up (by the stern).
    """

    r_wave: Float[Array, "*k"]
    sinkage: Float[Array, "*k"]
    trim: Float[Array, "*k"]


def waterplane(panels: Panels, stations: int, girth: int):
    """Waterplane area [m²], centre x [m] and longitudinal moment of inertia about it [m⁴], from the hull
    panels' waterline corners (trapezoids between panel columns)."""
    top = panels.vertices[: (stations - 1) * girth].reshape(stations - 1, girth, 4, 3)[:, -1]
    x0, x1 = top[:, 0, 0], top[:, 3, 0]  # the waterline edge: corners (i, g) and (i+1, g)
    y0, y1 = top[:, 1, 1], top[:, 2, 1]
    dx = x1 - x0
    awp = jnp.sum(dx * (y0 + y1))
    mx = jnp.sum(dx * (x0 * y0 + x1 * y1))  # trapezoid of 2·x·y
    xf = safe_div(mx, awp)
    ix = jnp.sum(dx * ((x0 - xf) ** 2 * y0 + (x1 - xf) ** 2 * y1))
    return awp, xf, ix


def squat(panels: Panels, cp: Float[Array, " N"], head: Float[ArrayLike, ""], stations: int,
          girth: int) -> tuple[Array, Array]:
    """Sinkage [m, down] at the centre of flotation and trim [rad, bow up] from the hull pressure ``cp`` (N,)
    [per ½ρU²] at ``head`` = U²/(2g) [m], against the waterplane's area and longitudinal moment of inertia
    (``panels`` from :func:`hull_panels` with ``stations``, ``girth``; not iterated)."""
    w = panels.area_vector * panels.real[:, None]
    awp, xf, ix = waterplane(panels, stations, girth)
    fz = -2.0 * jnp.sum(cp * w[:, 2])  # both sides; per ½ρU², upward positive
    my = -2.0 * jnp.sum(cp * (w[:, 2] * (panels.centre[:, 0] - xf)))  # about the centre of flotation, bow up
    return -safe_div(head * fz, awp), safe_div(head * my, ix)


def panel_wave_resistance(sections: Sections, draft: Draft, speed: Speeds, *, rho: float = RHO_SEA, g: float = G,
                          stations: int = STATIONS, girth: int = GIRTH, lambda_panels: int = 256,
                          lam_max: float = LAMBDA_MAX) -> PanelResult:
    """Wave resistance R_w [N], sinkage and trim by the Rankine-source panel method at ``speed`` U [m/s].

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y half-breadths to port, z up from the baseline).
    draft : float or Array
        Draft T [m above the baseline].
    speed : float or Array
        Ship speed U [m/s] > 0, shape (k,) or scalar.
    rho, g : float
        Water density [kg/m³], gravity [m/s²].
    stations, girth : int
        Panelling (:func:`hull_panels`).
    lambda_panels, lam_max : int, float
        The λ rule (:func:`hullopt.resistance._michell.lambda_nodes`).

    Returns
    -------
    PanelResult
        ``r_wave``, ``sinkage``, ``trim``, each of ``speed``'s shape (0 at a speed ≤ 0).

    Examples
    --------
    >>> import jax; jax.config.update("jax_enable_x64", True)
    >>> from hullopt.models import wigley
    >>> from hullopt.resistance import panel_wave_resistance
    >>> u = 0.3 * (9.80665 * 100.0) ** 0.5
    >>> r = panel_wave_resistance(wigley(100, 10, 6.25, 10, n=41, m=33), 6.25, u).r_wave
    >>> 100 < float(r) / 1e3 < 180
    True
    """
    panels = hull_panels(sections, draft, stations, girth)
    sigma, vel = double_body_flow(panels)
    cp = 1.0 - jnp.sum(vel * vel, -1)  # pressure coefficient of the double body (per ½ρU²)
    lam, wts = lambda_nodes(lambda_panels, lam_max)
    speed = jnp.asarray(speed, dtype=sections.yz.dtype)

    def one(u):
        ok = u > 0.0
        u2 = jnp.where(ok, u * u, 1.0)
        s = kelvin_spectrum(panels, sigma, g / u2, lam)
        r = rho * g * g / (jnp.pi * u2) * jnp.sum(wts * (s.real**2 + s.imag**2))
        sink, trim = squat(panels, cp, 0.5 * u2 / g, stations, girth)
        return jnp.where(ok, r, 0.0), jnp.where(ok, sink, 0.0), jnp.where(ok, trim, 0.0)

    flat = jnp.reshape(speed, (-1,))
    r, s, t = jax.vmap(one)(flat)
    return PanelResult(r_wave=r.reshape(speed.shape), sinkage=s.reshape(speed.shape), trim=t.reshape(speed.shape))


def wave_pattern(sections: Sections, draft: Draft, speed: Speed, x: Float[ArrayLike, ' P'], y: Float[ArrayLike, ' Q'],
                 *, g: float = G, stations: int = STATIONS, girth: int = GIRTH, angles: int = 600,
                 theta_max: float = 1.35) -> Array:
    """The Kelvin wave pattern ζ(x, y) [m] of the panel method's sources at ``speed``: each source's free waves
    behind it (far-field, no local disturbance), from the linearised free surface with the radiation condition
    (derivation: ζ = (U/g)φ_x, the pole of each Fourier mode),

        ζ = (k₀/(πU)) Re ∫ sec³θ · conj(S_x(θ)) · e^{i k₀ sec²θ (x cos θ + y sin θ)} dθ,   |θ| < π/2,

    with S_x the spectrum (:func:`kelvin_spectrum`, σ·U) of the panel columns ahead of x — the magnitude that
    carries Havelock's R_w, so the pattern and R_w are one spectrum.

    Parameters
    ----------
    sections : Sections
        The hull.
    draft : float
        Draft T [m above the baseline].
    speed : float
        Ship speed U [m/s] > 0 (the ship moves to +x).
    x, y : (P,) and (Q,) array_like
        Where [m]: x from the AP (behind the stern is negative), y to port.
    g : float
        Gravity [m/s²].
    stations, girth : int
        Panelling (:func:`hull_panels`).
    angles, theta_max : int, float
        Gauss–Legendre points on |θ| < ``theta_max`` [rad] (the shortest divergent waves beyond it are left out).

    Returns
    -------
    (P, Q) Array
        Free-surface elevation ζ [m], up positive.
    """
    panels = hull_panels(sections, draft, stations, girth)
    sigma, _ = double_body_flow(panels)
    u = jnp.asarray(speed, dtype=panels.vertices.dtype)
    k0 = g / (u * u)
    t, w = (jnp.asarray(a) for a in np.polynomial.legendre.leggauss(angles))
    theta, w = theta_max * t, theta_max * w
    sec = 1.0 / jnp.cos(theta)
    c, h1, h2 = _spectral_rectangles(panels)
    q = sigma * u * panels.area * panels.real
    k = k0 * sec * sec  # (A,)
    cz = c.at[:, 2].add(-panels.draft)

    def phase(r, sign):  # a·r with a = (i k cos θ, i k sin θ·sign, k) → (A, N)
        return jax.lax.complex(k[:, None] * r[None, :, 2],
                               k[:, None] * (jnp.cos(theta)[:, None] * r[None, :, 0]
                                             + sign * jnp.sin(theta)[:, None] * r[None, :, 1]))

    e = sum(jnp.exp(phase(cz, s)) * _shc(phase(h1, s)) * _shc(phase(h2, s)) for s in (1.0, -1.0))
    e = e * q.astype(e.dtype)  # (A, N): each panel's part of S(θ), both sides
    n_hull = (stations - 1) * girth
    column = jnp.concatenate([jnp.arange(n_hull) // girth, jnp.zeros(girth, int), jnp.full(girth, stations - 2)])
    xs = panels.centre[:n_hull:girth, 0]  # (stations − 1,) column centres
    per = jax.ops.segment_sum(e.T, column, num_segments=stations - 1).T  # (A, stations − 1)
    ahead = jnp.cumsum(per[:, ::-1], axis=1)[:, ::-1]  # S of the columns from j forward
    ahead = jnp.concatenate([ahead, jnp.zeros_like(ahead[:, :1])], axis=1)
    x = jnp.asarray(x, dtype=c.dtype)
    y = jnp.asarray(y, dtype=c.dtype)
    j = jnp.searchsorted(xs, x)  # the first column ahead of x
    s = ahead[:, j]  # (A, P)
    ph = k[:, None, None] * (jnp.cos(theta)[:, None, None] * x[None, :, None]
                             + jnp.sin(theta)[:, None, None] * y[None, None, :])
    wt = (w * sec**3)[:, None, None]
    zeta = jnp.sum(wt * (jnp.conj(s)[:, :, None] * jnp.exp(jax.lax.complex(jnp.zeros_like(ph), ph))).real, axis=0)
    return k0 / (jnp.pi * u) * zeta
