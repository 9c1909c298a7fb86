"""The wetted surface of a hull at a draft, exact for its polyline sections and differentiable in every offset
(the immersed girth of each section, integrated along the length with the slope of the surface)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._types import Draft
from ._safe import safe_div, safe_sqrt
from ._sections import Sections

if TYPE_CHECKING:
    pass  # imported where used: it takes ~0.5 s, and most commands need no mesh

def _segment_distance2(py: Array, pz: Array, y0: Array, z0: Array, ey: Array, ez: Array, inv: Array
                       ) -> tuple[Array, Array]:
    """Squared distance from points ``(py, pz)`` to segments from ``(y0, z0)`` along ``(ey, ez)`` (broadcast,
    elementwise; ``inv`` = 1/|e|², 0 for a point segment) and the parameter ``s ∈ [0, 1]`` of the nearest
    point along the segment."""
    wy, wz = py - y0, pz - z0
    s = jnp.clip((wy * ey + wz * ez) * inv, 0.0, 1.0)
    ry, rz = wy - s * ey, wz - s * ez
    return ry * ry + rz * rz, s


def _edges(qy: Array, qz: Array) -> tuple[Array, Array, Array]:
    """The edge vectors ``(ey, ez)`` of polylines ``(k, m)`` and ``1/|e|²`` (0 for a point edge), ``(k, m−1)``."""
    ey, ez = jnp.diff(qy, axis=-1), jnp.diff(qz, axis=-1)
    ee = ey * ey + ez * ez
    return ey, ez, safe_div(1.0, ee, ee > 0.0)


def _edge(v: Array, e) -> Array:
    """Column ``e`` (a loop index) of ``v (k, m)``, kept as ``(k, 1)``."""
    return jax.lax.dynamic_slice_in_dim(v, e, 1, axis=-1)


def _nearest_edges(py: Array, pz: Array, qy: Array, qz: Array, real: Array, full: bool):
    """The search of :func:`_polyline_distance2`: a loop over the edges of ``(qy, qz) (k, m_q)``, each step
    elementwise over every point ``(py, pz) (k, m_p)`` of its row. Returns the squared distance to the nearest
    real edge (``inf`` where none); with ``full``, also the parameter ``s`` of its foot and its index ``e``
    (``−1`` where none)."""
    ey, ez, inv = _edges(qy, qz)

    def step(e, c):
        d, s = _segment_distance2(py, pz, _edge(qy, e), _edge(qz, e), _edge(ey, e), _edge(ez, e), _edge(inv, e))
        d = jnp.where(_edge(real, e), d, jnp.inf)
        if not full:
            return jnp.minimum(c, d)
        best, s_best, e_best = c
        better = d < best
        return jnp.where(better, d, best), jnp.where(better, s, s_best), jnp.where(better, e, e_best)

    inf = jnp.full(py.shape, jnp.inf, py.dtype)
    init = (inf, jnp.zeros_like(py), jnp.full(py.shape, -1, jnp.int32)) if full else inf
    n = qy.shape[-1] - 1
    return jax.lax.fori_loop(0, n, step, init, unroll=max(1, min(6, n)))


@jax.custom_jvp
def _polyline_distance2(py: Array, pz: Array, qy: Array, qz: Array, real: Array) -> Array:
    """Squared distance ``(k, m_p)`` from each point ``(py, pz)`` of ``k`` half-sections to the nearest surface
    edge of the polyline ``(qy, qz) (k, m_q)`` of the same row; ``real (k, m_q − 1)`` marks the edges that are
    surface; ``inf`` where a row has none.

    Every point against every edge (``O(m_p m_q)``), in a loop over the edges whose body is elementwise over
    all points and rows: no gather, no sort, no argmin, which on a CPU under ``vmap`` cost far more than this
    arithmetic. Its derivative (:func:`_polyline_distance2_jvp`) is that of the distance to the nearest edge.
    """
    return _nearest_edges(py, pz, qy, qz, real, full=False)


@_polyline_distance2.defjvp
def _polyline_distance2_jvp(primals, tangents):
    """``d(d²) = 2 (p − f)·(dp − df)`` with the foot ``f = q_e + s (q_{e+1} − q_e)`` on the nearest edge ``e``
    and ``df = (1 − s) dq_e + s dq_{e+1}`` (``s`` held: it is optimal inside the edge and fixed at its ends).

    The choice ``(e, s)`` is piecewise constant: one search loop finds it (with the distance, the primal
    output), then the feet and their tangents are four gathers (``take_along_axis``) whose transpose in
    reverse mode is one scatter-add each — no second loop over the edges, and no transposed loop. Points with
    no edge get 0.
    """
    py, pz, qy, qz, real = primals
    dpy, dpz, dqy, dqz, _ = tangents
    best, s, e = jax.lax.optimization_barrier(_nearest_edges(py, pz, qy, qz, real, full=True))
    has = e >= 0
    e = jnp.maximum(e, 0)

    def foot(v):  # (1 − s) v_e + s v_{e+1} at each point, v (k, m_q)
        return (1.0 - s) * jnp.take_along_axis(v, e, -1) + s * jnp.take_along_axis(v, e + 1, -1)

    ry, rz = jnp.where(has, py - foot(qy), 0.0), jnp.where(has, pz - foot(qz), 0.0)
    return best, 2.0 * (ry * (dpy - foot(dqy)) + rz * (dpz - foot(dqz)))


def _girth_weights(y: Array, z: Array, level: Array) -> tuple[Array, Array]:
    """Weights ``w (k, m)`` [m] such that ``Σ_j w_j f_j`` is the trapezoidal ``∫ f ds`` over the wet girth
    (``z ≤ level``, each edge clipped at the waterline exactly, ``f`` linear along it) of half-sections
    ``(y, z) (k, m)``, for any point values ``f``; and whether each section lies wholly in the centre plane
    (a stem: its edges count). Other centre-plane edges (joints, a section not yet started) weigh nothing."""
    knife = jnp.all(y == 0.0, axis=-1, keepdims=True)
    y0, y1, z0, z1 = y[..., :-1], y[..., 1:], z[..., :-1], z[..., 1:]
    length = safe_sqrt((y1 - y0) ** 2 + (z1 - z0) ** 2)
    up = z0 <= z1
    z_lo, z_hi = jnp.where(up, z0, z1), jnp.where(up, z1, z0)
    rises = z_hi > z_lo
    wet = jnp.clip(safe_div(level - z_lo, z_hi - z_lo, rises), 0.0, 1.0)  # wet fraction from the lower end
    wet = jnp.where(rises, wet, jnp.where(z_lo <= level, 1.0, 0.0))
    lw = jnp.where((y0 == 0.0) & (y1 == 0.0) & ~knife, 0.0, length * wet)
    # ∫ = lw · ½ (f_lo + f_top), f_top = f_lo + wet (f_hi − f_lo): f_lo weighs lw (1 − wet/2), f_hi lw·wet/2
    c_lo, c_hi = lw * (1.0 - 0.5 * wet), lw * 0.5 * wet
    c0, c1 = jnp.where(up, c_lo, c_hi), jnp.where(up, c_hi, c_lo)  # weights of the edge's first and second point
    pad = jnp.zeros_like(c0[..., :1])
    return jnp.concatenate([c0, pad], axis=-1) + jnp.concatenate([pad, c1], axis=-1), knife


def _slope_factor(y: Array, d2: Array, knife: Array, dx: Array) -> Array:
    """``√(1 + d²/dx²)`` at each point ``(k, m)``: ``d²`` its squared distance to the neighbouring section
    ``dx (k,)`` away, bounded by the centre plane's ``y²`` (a part with no counterpart there: a bulb or a
    bossing that ends between the stations), except on a stem; 0 where there is nothing to measure to."""
    d2 = jnp.where(knife, d2, jnp.minimum(d2, y**2))
    d2 = jnp.where(jnp.isfinite(d2), d2, 0.0)  # a stem beside a station with no surface
    return safe_sqrt(dx[..., None] ** 2 + d2) / dx[..., None]


def wetted_surface(sections: Sections, draft: Draft) -> Float[Array, ""]:
    """Wetted surface [m²] of both sides below ``z = draft``, from the sections' wet girths and the normal
    slope of the surface between neighbouring stations.

    The area of a surface swept by a section curve moving along x is ``∫∫ √(1 + v²) ds dx``, where ``v`` is
    the rate at which the curve moves along its own normal (a tangential motion adds no area). Over each slab
    between two stations, ``v`` is taken as the distance from each point of one section to the other
    section's polyline over the station spacing, and the slab's area is the mean of its two ends (the
    trapezoidal rule; each end's girth exact for the polyline and clipped at the waterline exactly). Unlike
    a surface of triangles joining point ``j`` of one station to point ``j`` of the next, this does not
    depend on how the points are numbered: sections read from a mesh, whose points shift along the girth
    from one station to the next and whose parts (bulb, bossing, skeg) come and go, would give twisted
    panels whose area grows as the stations get closer. Converges as the slicing gets finer; exact for a
    prism (a box, a V) and for any hull whose sections translate along their normals linearly between
    stations. The centre plane bounds the distance where a part of one section has no counterpart in the
    next (its end face is at most as far); a section wholly in the centre plane (a stem, the Wigley's ends)
    is surface.

    End caps (an immersed transom, a flat end face) are not part of it (the transom's immersed area is
    :func:`hullopt.geometry.longitudinal_integrals`' ``a_transom``). Edges lying in the centre plane (joints
    between disjoint parts of a section, a section that has not started) are not surface.

    Cost: ``O(n m²)`` elementwise arithmetic (every point against every edge of the neighbouring section, in
    a loop over the edges; no gather, sort or argmin), vectorised over stations and points and under
    ``vmap``; its derivatives (a custom JVP: the distance to the nearest edge, found by the same one loop,
    then gathers of its feet; in reverse mode one scatter-add each, no transposed loop).
    Differentiable in the offsets, the station positions and the draft.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, scalar
        Wetted surface of both sides [m²].
    """
    level = jnp.asarray(draft, dtype=sections.yz.dtype)
    y, z, dx = sections.yz[..., 0], sections.yz[..., 1], jnp.diff(sections.x)
    real = ~((y[..., :-1] == 0.0) & (y[..., 1:] == 0.0))  # (n, m−1) edges that are surface
    total = 0.0
    for a, b in ((slice(None, -1), slice(1, None)), (slice(1, None), slice(None, -1))):  # aft end, fwd end
        w, knife = _girth_weights(y[a], z[a], level)
        d2 = _polyline_distance2(y[a], z[a], y[b], z[b], real[b])
        total = total + jnp.sum(dx * jnp.sum(w * _slope_factor(y[a], d2, knife, dx), axis=-1))
    return total  # 2 sides × ½ (aft + fwd) dx
