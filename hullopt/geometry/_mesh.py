"""The structured surface grid of a hull, its wetted surface, and closed triangle meshes (trimesh).

The grid is the ``(n, m)`` array of section points in 3D; two triangles per cell. The closed mesh adds the
starboard side (mirror), the deck (across the deck edges) and the two end caps (transom and stem),
so it is watertight and its volume and centroid can be checked independently with trimesh.

Meshes written to files go through :func:`hull_mesh` (sections resampled by arc length and refined along x, so
the mesh is a fine loft of the hull rather than the coarse loft of its stations) and :func:`export_mesh`, which
welds the mesh to what the file can hold (float32 coordinates: vertices closer than a tolerance merged, faces
that collapse dropped, by manifold3d), writes it and reads the file back to check it: closed, consistently
wound, one body, no face of (near) zero area.
"""

from __future__ import annotations

import math
import os
import re
import tempfile
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float

from .._types import Draft
from ._safe import safe_div, safe_sqrt
from ._sections import Sections

if TYPE_CHECKING:
    import trimesh  # imported where used: it takes ~0.5 s, and most commands need no mesh

EXPORT_FORMATS = ("stl", "obj", "ply", "glb", "x3d")


def surface_grid(sections: Sections, xp: ModuleType = jnp) -> Float[ArrayLike, "n m 3"]:
    """Port-side hull surface points ``(x, y, z)`` [m] on the structured station × point grid; ``xp = numpy``
    for a numpy grid (exports, which run no JAX op).

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    xp : module
        The array module, ``jax.numpy`` (default) or ``numpy``.

    Returns
    -------
    Array or numpy.ndarray, (n, m, 3) float
        The points ``(x, y, z)`` [m].
    """
    yz = xp.asarray(sections.yz)
    x = xp.broadcast_to(xp.asarray(sections.x)[:, None], yz.shape[:-1])
    return xp.concatenate([x[..., None], yz], axis=-1)


def grid_triangles(n: int, m: int) -> np.ndarray:
    """Triangle vertex indices ``(2 (n−1)(m−1), 3)`` into the flattened ``(n·m)`` grid.

    Wound so that normals point outward (to port) for a port-side grid running keel → deck.

    Parameters
    ----------
    n, m : int
        Grid size: stations and points per section.

    Returns
    -------
    numpy.ndarray, (2 (n−1)(m−1), 3) int
        Vertex indices ``i·m + j`` of each triangle.
    """
    i, j = np.meshgrid(np.arange(n - 1), np.arange(m - 1), indexing="ij")
    a = (i * m + j).ravel()
    b, c, d = a + m, a + m + 1, a + 1  # (i+1, j), (i+1, j+1), (i, j+1)
    return np.concatenate([np.stack([a, c, b], 1), np.stack([a, d, c], 1)])


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


def _cap_faces(loop_yz: np.ndarray, offset: int, outward_x: float) -> np.ndarray:
    """Triangulate one end cap, a closed loop in (y, z), facing ``outward_x`` (±1)."""
    import manifold3d  # robust ear clipping that keeps the input's vertices and edge directions

    # Seen from +x (y right, z up) the loop port keel → deck edge → starboard runs counter-clockwise.
    tri = np.asarray(manifold3d.triangulate([np.ascontiguousarray(loop_yz)]), dtype=np.int64)
    tri = _flip_collinear(tri, np.asarray(loop_yz, np.float64)) + offset
    return tri if outward_x > 0 else tri[:, ::-1]


def _flip_collinear(tri: np.ndarray, p: np.ndarray) -> np.ndarray:
    """Remove the zero-area triangles of a planar triangulation by edge flips: a triangle whose vertex ``w``
    lies on its edge ``u v`` (ear clipping makes these from collinear loop points, e.g. an end station lying
    in the centre plane) and the triangle ``v u q`` across that edge become ``u w q`` and ``w v q``, which
    keeps the boundary and the orientation. Triangles that cannot be flipped are left as they are."""
    tri = tri.copy()
    scale = float(np.ptp(p, axis=0).max()) if len(p) else 1.0

    def signed(t):
        a, b, c = p[t[..., 0]], p[t[..., 1]], p[t[..., 2]]
        ab, ac = b - a, c - a
        return 0.5 * (ab[..., 0] * ac[..., 1] - ab[..., 1] * ac[..., 0])

    tiny = 1e-14 * scale**2
    for _ in range(4 * len(tri)):
        bad = np.flatnonzero(np.abs(signed(tri)) <= tiny)
        if not len(bad):
            break
        done = False
        for k in bad:
            t = tri[k]
            lengths = [np.hypot(*(p[t[(e + 1) % 3]] - p[t[e]])) for e in range(3)]
            e = int(np.argmax(lengths))
            u, v, w = t[e], t[(e + 1) % 3], t[(e + 2) % 3]
            other = np.flatnonzero(np.any((tri == v) & (np.roll(tri, -1, axis=1) == u), axis=1))
            if not len(other):
                continue
            j = int(other[0])
            q = int(next(a for a in tri[j] if a not in (u, v)))
            sign = np.sign(signed(tri[j]))
            new = np.array([[u, w, q], [w, v, q]])
            if sign == 0 or q == w or np.any(np.sign(signed(new)) != sign) or np.any(np.abs(signed(new)) <= tiny):
                continue  # the flip would fold the cap or leave a degenerate face
            tri[k], tri[j] = new
            done = True
            break
        if not done:
            break
    return tri


def to_trimesh(sections: Sections, wall: float = 1e-7) -> trimesh.Trimesh:
    """The closed, watertight triangle mesh of the whole hull (both sides, deck, keel, end caps).

    The port grid and its mirror image are joined along the keel and across the deck and closed by the two
    end stations, so the mesh is a closed tube by construction. Points on the centreline are moved off it by
    ``1e-7`` of the hull's size on each side: where sections have not started, or a bulb joins the hull, the
    two sides then form a thin double wall instead of touching (which would not be a 2-manifold). The
    volume this adds is negligible (2·1e-7·size × the centre-plane area); exclude faces with
    ``|y| ≤ 1e-7·size`` when summing areas. ``wall`` sets that fraction (:func:`hull_mesh` writes 1e-6, so
    the faces across the wall stay well above float32's resolution and the degenerate-face threshold).

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    wall : float
        Half-thickness of the centre-plane wall as a fraction of the hull's size (largest coordinate [m], at
        least 1 m); 1e-7 by default.

    Returns
    -------
    trimesh.Trimesh
        ``2·n·m`` vertices [m] (port grid, then its mirror), float64, closed and outward wound; not processed.
    """
    import trimesh

    g = surface_grid(sections, np).astype(np.float64)
    n, m, _ = g.shape
    eps = centreline_offset(g, wall)
    g[..., 1] = np.maximum(g[..., 1], eps)
    port = g.reshape(-1, 3)
    verts = np.concatenate([port, port * np.array([1.0, -1.0, 1.0])])
    s0 = n * m
    grid = grid_triangles(n, m)
    i = np.arange(n - 1)
    top_p, top_s = i * m + m - 1, s0 + i * m + m - 1
    bot_p, bot_s = i * m, s0 + i * m
    deck = [np.stack([top_p, top_s + m, top_p + m], 1), np.stack([top_p, top_s, top_s + m], 1)]
    keel = [np.stack([bot_p, bot_p + m, bot_s + m], 1), np.stack([bot_p, bot_s + m, bot_s], 1)]
    loop = np.concatenate([np.arange(m), s0 + np.arange(m)[::-1]])  # port up, starboard down
    caps = [
        loop[_cap_faces(verts[loop, 1:], 0, -1.0)],
        loop[_cap_faces(verts[loop + (n - 1) * m, 1:], 0, +1.0)] + (n - 1) * m,
    ]
    faces = np.concatenate([grid, (grid + s0)[:, ::-1], *deck, *keel, *caps])
    return trimesh.Trimesh(verts, faces, process=False)


def centreline_offset(points: np.ndarray, wall: float = 1e-7) -> float:
    """Half-thickness [m] given to the centre plane in closed meshes: ``wall`` (1e-7) of the hull's size."""
    return wall * max(float(np.abs(points).max()), 1.0)


# ------------------------------------------------------------------------------------------ meshes for files

# Faces smaller than this fraction of the total area count as degenerate (the checks of a written file).
TINY_FACE = 1e-12
# Weld tolerances tried in turn, as fractions of the hull's size: float32 (what STL and GLB store) resolves
# 6e-8 of it, so distinct vertices stay distinct once rounded.
_WELD_TOLERANCES = (1e-7, 1e-6, 1e-5)


def resample_sections(sections: Sections, stations: int = 200, points: tuple[int, int] = (80, 200),
                      max_twist: float = 0.25) -> Sections:
    """The hull on a finer grid for writing (numpy): every section resampled to ``2·m`` points clipped to
    ``points`` (equally spaced in its arc length, so that point ``j`` is the same fraction of the girth at
    every station and the loft between stations does not twist where the points crowd differently; the
    sample nearest each corner — a turn of more than 30° — moved onto it, so corners stay exact), then
    PCHIP-interpolated point by point along x (monotone: no overshoot) at ``k`` stations per interval: at
    least enough for ``stations`` intervals in all, and more (up to 64) where the loft twists — where the
    step from one point to the next changes between the two stations by more than ``max_twist`` of the
    mean step (a bulb or a stem tip ending in a line on the centreline), so that a cut across the mesh is
    a smooth polyline, which the mesh reader resamples. Each end section is also repeated ``1e-4`` of the
    length inside the end (a prism: the volume changes by that times the end's change of area, ~1e-8).

    The given stations stay stations (their sections to the resampling's rounding of gentle turns: about
    ``1e-4`` of ∇ for 40 points, less for more), so the mesh's hydrostatics match Simpson's rule over the
    given stations where the sectional-area curve is smooth, and where it is not the mesh is the better
    integral (DTC, 61 stations: the mesh's ∇ +0.02 %, LCB −0.007 % Lpp from the stations' Simpson sums).
    """
    from scipy.interpolate import PchipInterpolator

    x = np.asarray(sections.x, np.float64)
    yz = np.asarray(sections.yz, np.float64)
    n, m = yz.shape[:2]
    big_m = int(np.clip(2 * m, *points))
    even = _by_girth(yz, big_m)
    if n < 2:
        return Sections(x=x, yz=even, lpp=np.asarray(float(sections.lpp)))
    # stations per interval: enough for `stations` intervals in all, and more where the loft twists (the
    # step between neighbouring points changes between the two stations), so that a cut across the mesh
    # between stations is a smooth polyline and not a zigzag (each cell's diagonal kinks it)
    step = np.diff(even, axis=1)  # (n, M-1, 2)
    girth = np.hypot(*np.moveaxis(step, -1, 0)).sum(axis=1)
    ref = np.maximum(np.maximum(girth[:-1], girth[1:]) / (big_m - 1), 1e-12)
    twist = np.hypot(*np.moveaxis(np.diff(step, axis=0), -1, 0)).max(axis=1) / ref
    k = np.clip(np.ceil(twist / max_twist), math.ceil(stations / (n - 1)), 64).astype(int)
    t = [np.arange(ki) / ki for ki in k]
    xs = np.concatenate([x[i] + ti * (x[i + 1] - x[i]) for i, ti in enumerate(t)] + [x[-1:]])
    if len(xs) > n:
        even = PchipInterpolator(x, even, axis=0)(xs)
        even[..., 0] = np.maximum(even[..., 0], 0.0)
    even = _unfold_centreline(even, centreline_offset(np.r_[xs, even.ravel()], 1e-6))  # hull_mesh's wall
    # End prisms: each end section repeated a little inside the end (up to 1e-4 of the length), so a cut
    # just inside the end — where a mesh reader takes its first and last station — is that section, not a
    # cut through the loft's last cells, which twist most where the hull ends in a point or a line.
    d = min(1e-4 * (xs[-1] - xs[0]), 0.25 * float(np.diff(xs)[[0, -1]].min()))
    xs = np.concatenate([xs[:1], xs[:1] + d, xs[1:-1], xs[-1:] - d, xs[-1:]])
    even = np.concatenate([even[:1], even[:1], even[1:-1], even[-1:], even[-1:]])
    return Sections(x=xs, yz=even, lpp=np.asarray(float(sections.lpp)))


def _by_girth(yz: np.ndarray, big_m: int) -> np.ndarray:
    """Each half-section of ``yz (n, m, 2)`` [m] resampled to ``big_m`` points equally spaced in its arc
    length (point ``j`` the same fraction of the girth at every station), the sample nearest each corner
    (a turn of more than 30°) moved onto it (numpy)."""
    u = np.linspace(0.0, 1.0, big_m)
    even = np.empty((yz.shape[0], big_m, 2))
    for i, p in enumerate(yz):
        seg = np.hypot(*np.diff(p, axis=0).T)
        s = np.r_[0.0, np.cumsum(seg)]
        if s[-1] <= 0.0:  # a section collapsed to a point
            even[i] = p[0]
            continue
        s = s / s[-1]
        ui = u.copy()
        for c in _corners(p[np.r_[True, seg > 0]], s[np.r_[True, seg > 0]]):
            j = int(round(c * (big_m - 1)))  # the nearest sample moves onto the corner: corners stay exact
            if 0 < j < big_m - 1 and ui[j - 1] < c < ui[j + 1]:
                ui[j] = c
        even[i, :, 0] = np.interp(ui, s, p[:, 0])
        even[i, :, 1] = np.interp(ui, s, p[:, 1])
    return even


def sections_at(sections: Sections, x: np.ndarray, points: int = 200) -> np.ndarray:
    """The half-sections at stations ``x`` (numpy, for drawing): each given section resampled by its girth
    (as :func:`resample_sections`), then interpolated point by point along the length (PCHIP: monotone, no
    overshoot). A given station gives back its own section (to the resampling's rounding of gentle turns).
    Drawings at the stations 0…10 use it: a design whose frames moved along the length (a ``"stations"``
    distribution) has no section at a station, and its nearest one may stand metres away from the parent's.

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    x : (k,) array_like
        Stations [m from the AP]; clipped to the hull's ends.
    points : int
        Points per half-section, equally spaced in its girth.

    Returns
    -------
    numpy.ndarray, (k, points, 2) float
        The half-sections ``(y, z)`` [m], keel to deck edge.
    """
    from scipy.interpolate import PchipInterpolator

    xs = np.asarray(sections.x, np.float64)
    even = _by_girth(np.asarray(sections.yz, np.float64), points)
    out = PchipInterpolator(xs, even, axis=0)(np.clip(np.asarray(x, np.float64), xs[0], xs[-1]))
    out[..., 0] = np.maximum(out[..., 0], 0.0)
    return out


def _unfold_centreline(yz: np.ndarray, wall: float) -> np.ndarray:
    """Sections ``(n, m, 2)`` whose runs of points on the centreline (``y ≤ wall`` [m], inside
    :func:`hull_mesh`'s double wall, :func:`centreline_offset`: a section not started yet,
    the joint of a bulb) go straight from the run's first point to its last, evenly by index, instead of
    back and forth along the centreline (as cuts of a mesh near a stem may): such points add nothing to
    any integral, but a run folded on itself makes an end cap that no triangulation covers without faces
    of zero area."""
    yz = yz.copy()
    for p in yz:
        on = p[:, 0] <= wall
        if on.sum() < 3:
            continue
        edges = np.flatnonzero(np.diff(np.r_[0, on.astype(np.int8), 0]))
        for a, b in zip(edges[::2], edges[1::2] - 1):  # runs [a, b] of centreline points
            if b - a >= 2:
                p[a : b + 1, 1] = np.linspace(p[a, 1], p[b, 1], b - a + 1)
    return yz


def _corners(p: np.ndarray, s: np.ndarray, angle_deg: float = 30.0) -> np.ndarray:
    """Arc-length parameters ``s`` of the vertices of polyline ``p`` (no repeated points) where it turns by
    more than ``angle_deg`` (chines, knuckles, a box's bilge, the joints of a bulb with the centreline)."""
    if len(p) < 3:
        return np.empty(0)
    d = np.diff(p, axis=0)
    ang = np.arctan2(d[:, 1], d[:, 0])
    turn = np.abs(np.angle(np.exp(1j * np.diff(ang))))
    return s[1:-1][turn > np.radians(angle_deg)]


def hull_mesh(sections: Sections) -> trimesh.Trimesh:
    """The closed mesh to write for a hull [m]: :func:`to_trimesh` of :func:`resample_sections` (float64,
    not yet welded; :func:`export_mesh` welds it).

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].

    Returns
    -------
    trimesh.Trimesh
        The closed mesh [m], float64, on the resampled grid.
    """
    return to_trimesh(resample_sections(sections), wall=1e-6)


@dataclass(frozen=True)
class MeshReport:
    """A mesh file as read back by trimesh: ``faces``, ``watertight`` (every edge shared by exactly two
    faces), ``winding_consistent``, ``bodies`` (connected parts), ``tiny_faces`` (faces with an area below
    :data:`TINY_FACE` of the total), ``volume`` [file units³]; ``volume_change``, the relative change of the
    volume by welding (the written mesh against the float64 one given)."""

    path: Path
    faces: int
    watertight: bool
    winding_consistent: bool
    bodies: int
    tiny_faces: int
    volume: float
    volume_change: float = 0.0

    @property
    def ok(self) -> bool:
        """Closed, consistently oriented, one body, no degenerate face."""
        return self.watertight and self.winding_consistent and self.bodies == 1 and self.tiny_faces == 0

    def summary(self) -> str:
        return (f"{self.faces:,} faces, watertight: {self.watertight}, winding consistent: "
                f"{self.winding_consistent}, bodies: {self.bodies}, degenerate faces: {self.tiny_faces}, "
                f"volume {self.volume:,.6g} m³")


def mesh_checks(mesh: trimesh.Trimesh) -> dict:
    """``watertight, winding_consistent, bodies, tiny_faces, faces, volume`` of a mesh (as trimesh sees it)."""
    area = np.asarray(mesh.area_faces)
    return {
        "faces": len(mesh.faces), "watertight": bool(mesh.is_watertight),
        "winding_consistent": bool(mesh.is_winding_consistent), "bodies": int(mesh.body_count),
        "tiny_faces": int(np.count_nonzero(area < TINY_FACE * area.sum())), "volume": float(mesh.volume),
    }


def weld_mesh(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    """The mesh as a file stores it, and valid there: vertices in float32, closed, consistently wound, one
    body, no degenerate face.

    The vertices are rounded to float32 first; manifold3d then takes the (topologically closed) mesh,
    collapses its zero-length edges (repeated grid points: collapsed ends, sections not started yet,
    points float32 cannot tell apart) and removes the faces that degenerate, then simplifies with a weld
    tolerance (``1e-7`` of the hull's size [m], raised tenfold while the result is not valid), keeping a
    2-manifold whose vertices are a subset of the rounded ones; the result is checked as trimesh reads a
    file (equal vertices merged). The surface moves by less than the tolerance plus float32 rounding, so
    the volume changes by ~1e-8 of itself (DTC 2e-8, Wigley 7e-10). ``ValueError`` if the mesh is not a
    closed manifold or no tolerance gives a valid one.
    """
    import manifold3d
    import trimesh

    # float32 first: vertices that the file could not tell apart become equal, and manifold3d collapses the
    # zero-length edges between them (a collapse of a short float64 edge may be refused where the faces
    # around it are slivers). Copies: nanobind needs writeable arrays.
    verts = np.array(np.asarray(mesh.vertices, dtype=np.float32), dtype=np.float64, order="C")
    size = max(float(np.abs(verts).max()), 1.0)
    whole = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=verts,
                                                  tri_verts=np.array(mesh.faces, dtype=np.uint64, order="C")))
    if whole.status() != manifold3d.Error.NoError or whole.is_empty():
        raise ValueError(f"the mesh is not a closed manifold ({whole.status()}): it cannot be written watertight")
    checks = {}
    for rel in _WELD_TOLERANCES:
        out = whole.simplify(rel * size).to_mesh64()  # a subset of the (float32) vertices given
        welded = trimesh.Trimesh(np.asarray(out.vert_properties)[:, :3].astype(np.float32).astype(np.float64),
                                 np.asarray(out.tri_verts, np.int64), process=False)
        seen = welded.copy()
        seen.merge_vertices()  # what a reader does
        checks = mesh_checks(seen)
        if MeshReport(path=Path(), **checks).ok:
            return welded
    raise ValueError(f"the mesh cannot be made valid in float32 ({checks})")


def write_x3d(mesh: trimesh.Trimesh, path: str | os.PathLike) -> None:
    """Write an X3D (XML) file with one IndexedFaceSet, as seed 003 uses for 3D printing (coordinates to 9
    significant digits: float32 exactly)."""
    coords = " ".join(f"{v[0]:.9g} {v[1]:.9g} {v[2]:.9g}" for v in mesh.vertices)
    index = " ".join(f"{a} {b} {c} -1" for a, b, c in mesh.faces)
    text = (
        '<?xml version="1.0" encoding="UTF-8"?>\n'
        '<X3D profile="Interchange" version="3.3">\n<Scene>\n<Shape>\n'
        "<Appearance><Material diffuseColor='0.8 0.8 0.8'/></Appearance>\n"
        f"<IndexedFaceSet solid='true' coordIndex='{index}'>\n<Coordinate point='{coords}'/>\n"
        "</IndexedFaceSet>\n</Shape>\n</Scene>\n</X3D>\n"
    )
    atomic_write_bytes(path, text.encode())


def read_x3d(path: str | os.PathLike) -> trimesh.Trimesh:
    """Read back an X3D file of :func:`write_x3d` (one IndexedFaceSet of triangles)."""
    import trimesh

    text = Path(path).read_text()
    index = np.array(re.search(r"coordIndex='([^']*)'", text).group(1).split(), dtype=np.int64).reshape(-1, 4)
    coords = np.array(re.search(r"point='([^']*)'", text).group(1).split(), dtype=np.float64).reshape(-1, 3)
    return trimesh.Trimesh(coords, index[:, :3], process=True)


def read_back(path: str | os.PathLike) -> trimesh.Trimesh:
    """A written mesh file as trimesh reads it (vertices merged); X3D by :func:`read_x3d`."""
    import trimesh

    path = Path(path)
    if path.suffix.lower() == ".x3d":
        return read_x3d(path)
    return trimesh.load(path, force="mesh")


def atomic_write_bytes(path: str | os.PathLike, data: bytes) -> None:
    """Write ``data`` to ``path`` via a temporary file in the same folder and a rename; the file gets the
    permissions an ordinary ``open(path, "w")`` would give (mkstemp's are owner-only).

    Parameters
    ----------
    path : str or os.PathLike
        The file to write (replaced if it exists); its folder must exist.
    data : bytes
        The file's contents.

    Returns
    -------
    None
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def stl_header(lpp: float, draft: float | None = None) -> bytes:
    """The 80-byte binary-STL header hullopt writes: ``hullopt lpp=<m> [draft=<m>]``, so that reading the file
    back (:func:`read_stl_header`) needs no ``?lpp=`` and knows the design draft.

    Parameters
    ----------
    lpp : float
        Length between perpendiculars [m].
    draft : float, optional
        Design draft [m above the baseline]; ``None`` leaves it out.

    Returns
    -------
    bytes
        80 ASCII bytes, space padded.
    """
    text = f"hullopt lpp={lpp:.9g}" + ("" if draft is None else f" draft={draft:.9g}")
    return text.encode("ascii").ljust(80, b" ")


def read_stl_header(text: str) -> dict[str, float]:
    """``{"lpp": …, "draft": …}`` [m] from a header written by :func:`stl_header` (trimesh keeps it as
    ``mesh.metadata["header"]``); empty for any other header.

    Parameters
    ----------
    text : str
        The STL header as text.

    Returns
    -------
    dict of str to float
        ``"lpp"`` and, where written, ``"draft"`` [m] (any other ``key=number`` word too); ``{}`` for a header
        not starting with ``hullopt``.
    """
    words = text.split()
    if not words or words[0] != "hullopt":
        return {}
    out = {}
    for w in words[1:]:
        key, _, value = w.partition("=")
        try:
            out[key] = float(value)
        except ValueError:
            pass
    return out


def export_mesh(mesh: trimesh.Trimesh, path: str | os.PathLike, header: bytes | None = None) -> MeshReport:
    """Write a closed mesh to STL, OBJ, PLY, GLB or X3D (by the file's extension), atomically, welded first
    (:func:`weld_mesh`) so that the file holds a valid mesh; then read the file back and report its checks
    (:class:`MeshReport`, from the file, not from the mesh in memory). ``ValueError`` if the written file
    is not closed, consistently wound, one body and free of degenerate faces. ``header`` (80 bytes, see
    :func:`stl_header`) goes into a binary STL's header; other formats ignore it.

    Parameters
    ----------
    mesh : trimesh.Trimesh
        A closed 2-manifold mesh [m], e.g. from :func:`hull_mesh`.
    path : str or os.PathLike
        The file to write; its extension (``.stl``, ``.obj``, ``.ply``, ``.glb``, ``.x3d``) picks the format.
    header : bytes, optional
        A binary STL's 80-byte header (cut or space padded to 80); ``None`` keeps trimesh's.

    Returns
    -------
    MeshReport
        The checks of the file as read back: ``faces``, ``watertight``, ``winding_consistent``, ``bodies``,
        ``tiny_faces``, ``volume`` [m³], ``volume_change`` (relative, by welding).
    """
    path = Path(path)
    fmt = path.suffix.lower().lstrip(".")
    if fmt not in EXPORT_FORMATS:
        raise ValueError(f"{path}: unknown mesh format {fmt!r}; expected one of {', '.join(EXPORT_FORMATS)}")
    welded = weld_mesh(mesh)
    if fmt == "x3d":
        write_x3d(welded, path)
    else:
        data = welded.export(file_type=fmt)
        data = data if isinstance(data, bytes) else data.encode()
        if fmt == "stl" and header is not None:
            data = header[:80].ljust(80, b" ") + data[80:]
        atomic_write_bytes(path, data)
    checks = mesh_checks(read_back(path))
    before = float(mesh.volume)
    report = MeshReport(path=path, volume_change=checks["volume"] / before - 1.0 if before else 0.0, **checks)
    if not report.ok:
        raise ValueError(f"{path}: the written mesh is not valid when read back ({report.summary()})")
    return report
