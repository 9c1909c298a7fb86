"""Wave resistance by Dawson's method: Rankine sources on the hull and on the free surface, the free-surface
condition linearised about the double-body flow (Dawson 1977).

The double-body flow Φ (:func:`._panel.double_body_flow`: the hull and its mirror in the waterplane z = T in the
stream −U·x̂) is the base. The free surface z = T is panelled too (port side; body-fitted: its longitudinal grid
lines follow the waterline beside the hull and stand for Φ's streamlines l). The perturbation φ, from the hull
sources' change δσ_h and the free-surface sources σ_f, satisfies

    hull:          ∂φ/∂n = 0,
    free surface:  Φ_l² ∂_l(φ_l) + 2 Φ_l Φ_ll φ_l + g φ_z = −Φ_l² Φ_ll                         (Dawson 1977)

Φ_l is the double body's speed |∇Φ| and φ_l the perturbation's velocity along ∇Φ, both from the panels'
velocities at the free-surface panels' centres; φ_z too (the hull and its mirror induce none on z = T, coplanar
panels none either: φ_z is a panel's own −σ_f/2). Φ_ll by central differences of Φ_l, and ∂_l by an upstream
difference along each grid line, which carries the radiation condition (no waves
ahead: the perturbation vanishes upstream of the grid). The difference is second order (three points): the
four-point one exact for cubics lets the KCS's transverse waves grow downstream (they double over a ship
length), the two-point one damps them out within a wavelength. A dense solve a speed; its VJP is one transposed
solve.

Wave resistance by pressure integration over the wet hull, of the perturbation's pressure C_p − C_p,Φ with
C_p = 1 − |∇φ_total|²/U² (the double body's integrates to zero; on flat panels only roughly); the free-surface
elevation ζ = (U² − |∇φ_total|²)/(2g) on z = T.

Why this beside :mod:`._panel`: Kelvin's condition there (and Michell's) sees the full stream speed everywhere;
Dawson's sees the slowed flow at a full hull's bow and run, whose waves the former overstate many-fold
(KCS: C_W 4.8e-3 against Dawson's 0.17e-3).

No dry-transom condition: an immersed transom is closed by panels, wet, and the double-body flow stagnates
behind it, so the waves of the flow leaving a dry transom's edge are missing (DTMB 5415: C_W 0.3× the peer
WARP's at Fn 0.28; :func:`._calm.transom_caveat`).

References: Dawson, C.W. (1977) A practical computer method for solving ship-wave problems. Proc. 2nd Int. Conf.
Numer. Ship Hydrodyn., Berkeley, 30–38. Raven, H.C. (1996) A solution method for the nonlinear ship wave
resistance problem, PhD thesis TU Delft (ch. 4, the linearised problem and its difference schemes). Havelock,
T.H. (1932) Proc. R. Soc. A 138, 339–348 (the submerged sphere, the test).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, ArrayLike, Float

from .._types import Draft, Speeds
from ..constants import G, RHO_SEA
from ..errors import HullError
from ..geometry import Sections, safe_norm
from ._panel import (GIRTH, STATIONS, Panels, centre_velocities, double_body_flow, hull_panels, mirrored,
                     source_velocity, squat)

UPSTREAM = 0.5  # free-surface grid ahead of the bow [L]
DOWNSTREAM = 1.0  # behind the stern [L]
WIDTH = 1.0  # beside the centreline [L]
COLUMNS = 96  # free-surface grid nodes along the stream
ROWS = 14  # and outwards
POINTS = 3  # the upstream difference's points: second order
FN_MIN = (10.0 * (UPSTREAM + 1.0 + DOWNSTREAM) / (2.0 * math.pi * (COLUMNS - 1))) ** 0.5
"""The lowest Froude number at which the default grid has 10 columns a transverse wavelength 2πFn²L (≈ 0.205);
below it the upstream difference's damping lowers C_W (Wigley at Fn 0.2: 0.28e-3, Michell's 0.89e-3)."""


class FreeSurface(eqx.Module):
    """The port side's free-surface grid on z = T.

    Attributes
    ----------
    nodes : (nx, ny, 3) float
        Grid nodes [m]; i along the stream (0 ahead of the bow), j outwards (0 on the waterline, or the
        centreline ahead of and behind the hull).
    """

    nodes: Float[Array, "nx ny 3"]

    @property
    def panels(self) -> Panels:
        """(nx − 1)(ny − 1) panels, normal −ẑ (into the water below)."""
        p = self.nodes
        quad = jnp.stack([p[:-1, :-1], p[1:, :-1], p[1:, 1:], p[:-1, 1:]], axis=2).reshape(-1, 4, 3)
        return Panels(vertices=quad, draft=p[0, 0, 2])


def free_surface(x: ArrayLike, width: ArrayLike, z: ArrayLike, rows: int,
                 waterline: tuple[Array, Array] | None = None) -> FreeSurface:
    """The port side's free surface z = ``z`` [m] on the columns ``x`` [m] (descending: along the stream) and
    from the centreline — or the ``waterline`` (x ascending, half-breadth y) [m] beside the hull — to
    y = ``width`` [m] (``rows`` nodes, finer inboard: η^1.5).

    Parameters
    ----------
    x : (nx,) array_like
        The grid's columns [m], from ahead of the body to behind it.
    width : float
        The grid's outer edge y [m].
    z : float
        The free surface's height [m] (the draft T above the baseline for a hull).
    rows : int
        Nodes from the inner edge to ``width``.
    waterline : tuple of (m,) Array, optional
        The hull's waterline (x ascending [m], half-breadth [m]): the inner edge beside the hull.

    Returns
    -------
    FreeSurface
        ``(nx, rows)`` nodes.
    """
    x = jnp.asarray(x)
    y_in = jnp.zeros_like(x)
    if waterline is not None:
        xw, yw = waterline
        y_in = jnp.where((x >= xw[0]) & (x <= xw[-1]), jnp.interp(x, xw, yw), 0.0)
    eta = jnp.linspace(0.0, 1.0, rows) ** 1.5
    y = y_in[:, None] + (width - y_in[:, None]) * eta[None, :]
    return FreeSurface(jnp.stack([jnp.broadcast_to(x[:, None], y.shape), y, jnp.full_like(y, z)], axis=-1))


def hull_surface(hull: Panels, stations: int, girth: int, columns: int, rows: int, upstream: float = UPSTREAM,
                 downstream: float = DOWNSTREAM, width: float = WIDTH) -> FreeSurface:
    """:func:`free_surface` fitted to the hull panels' waterline (:func:`._panel.hull_panels`' top corners),
    ``upstream``, ``downstream`` and ``width`` in wet lengths L: ``columns`` nodes about evenly spaced, with
    nodes on the hull's ends (so the waterline's ends, a transom's edge, do not move with the grid)."""
    wl = hull.vertices[: (stations - 1) * girth].reshape(stations - 1, girth, 4, 3)[:, -1]
    xw = jnp.concatenate([wl[:, 0, 0], wl[-1:, 3, 0]])  # aft to fore
    yw = jnp.concatenate([wl[:, 1, 1], wl[-1:, 2, 1]])
    length = xw[-1] - xw[0]
    total = upstream + 1.0 + downstream
    n_up = max(1, round((columns - 1) * upstream / total))
    n_hull = max(2, round((columns - 1) / total))
    n_down = columns - 1 - n_up - n_hull
    x = jnp.concatenate([xw[-1] + upstream * length * (1.0 - jnp.arange(n_up, dtype=xw.dtype) / n_up),
                         xw[-1] - length * jnp.arange(n_hull, dtype=xw.dtype) / n_hull,
                         xw[0] - downstream * length * jnp.arange(n_down + 1, dtype=xw.dtype) / n_down])
    return free_surface(x, width * length, hull.draft, rows, (xw, yw))


def _upstream_d(s: Array, points: int = 4) -> Array:
    """The upstream difference on each grid line: weights (nx, points) so that ∂f/∂l at node i ≈
    Σ_k w_k f_{i−k} (k = 0..points−1, i − k upstream; missing upstream points are the undisturbed stream, f = 0),
    exact for polynomials of degree points − 1 on the (uneven) spacing ``s`` (nx,) [m] along the line."""
    n = s.shape[0]
    m = points - 1
    pad = jnp.concatenate([s[0] - (s[1] - s[0]) * jnp.arange(m, 0, -1.0), s])  # ghosts evenly ahead
    idx = jnp.arange(n)[:, None] + m - jnp.arange(points)[None, :]
    d = pad[idx] - pad[idx[:, :1]]  # (n, points) offsets from node i, 0 first

    def weights(o):  # Lagrange basis derivatives at offset 0
        w = []
        for k in range(points):
            others = [j for j in range(points) if j != k]
            den = jnp.prod(jnp.stack([o[k] - o[j] for j in others]))
            num = sum(jnp.prod(jnp.stack([-o[q] for q in others if q != r] or [jnp.ones(())])) for r in others)
            w.append(num / den)
        return jnp.stack(w)

    return jax.vmap(weights)(d)


class DawsonFlow(eqx.Module):
    """Dawson's solution at k values of k₀ = g/U², per unit speed.

    Attributes
    ----------
    drag : (k,) float
        R_w/(½ρU²) [m²]: the perturbation pressure's x force over the wet hull, both sides.
    cp : (k, N) float
        Hull pressure coefficient 1 − |v|²/U² at the hull panels' centres.
    zeta : (k, nx − 1, ny − 1) float
        Free-surface elevation × g/U² [−] (ζ·k₀) at the free-surface panels' centres, up positive.
    """

    drag: Float[Array, " k"]
    cp: Float[Array, "k N"]
    zeta: Float[Array, "k nx ny"]


def dawson_flow(hull: Panels, surface: FreeSurface, k0: Float[Array, " k"], points: int = POINTS) -> DawsonFlow:
    """Solve Dawson's problem for the port ``hull`` panels (mirrored in y and in z = ``hull.draft``) and the
    port ``surface`` (mirrored in y) at each k₀ = g/U² [1/m], per unit speed (the stream −x̂).

    Parameters
    ----------
    hull : Panels
        The port side's wet panels (:func:`._panel.hull_panels`, or any closed body's, e.g. a submerged one).
    surface : FreeSurface
        The port side's free-surface grid on z = ``hull.draft`` (:func:`free_surface`).
    k0 : (k,) Array
        g/U² [1/m] for each speed.
    points : int
        Points of the upstream difference (:func:`_upstream_d`; 3: second order).

    Returns
    -------
    DawsonFlow
        ``drag`` R_w/(½ρU²) [m²], the hull's ``cp`` and the free surface's ``zeta``·k₀, one row per k₀.
    """
    sigma_db, vel_db = double_body_flow(hull)
    fp = surface.panels
    nh, nf = hull.vertices.shape[0], fp.vertices.shape[0]
    ncol, nrow = surface.nodes.shape[0] - 1, surface.nodes.shape[1] - 1
    every_h = mirrored(hull)
    every_f = Panels(jnp.concatenate([fp.vertices, (fp.vertices * jnp.array([1.0, -1.0, 1.0]))[:, ::-1]]),
                     hull.draft)
    fold = lambda v, images: jnp.sum(v.reshape(v.shape[0], images, -1, 3), axis=1)  # noqa: E731
    v_hh = centre_velocities(hull)  # (nh, nh, 3) hull centres ← hull sources (with images)
    v_hf = fold(source_velocity(hull.centre, every_f), 2)  # hull centres ← free-surface sources
    v_fh = fold(source_velocity(fp.centre, every_h), 4)
    v_ff = fold(source_velocity(fp.centre, every_f, own=True), 2)
    # l: the double body's streamlines (towards downstream), differenced along the grid lines that stand for them.
    # Φ_l is the double body's speed, not its part along a grid line: a line that bends across the stream (the
    # waterline's offsets carried outwards) would make Φ_ll of its bends a forcing across the whole width —
    # transverse waves outside Kelvin's wedge, R_w 8–30 % with the grid's extent (KCS: 2.7× too large).
    c = fp.centre.reshape(ncol, nrow, 3)
    step = safe_norm(c[1:] - c[:-1])  # (ncol − 1, nrow)
    s = jnp.concatenate([jnp.zeros((1, nrow), c.dtype), jnp.cumsum(step, axis=0)], axis=0)
    base = (jnp.einsum("pnk,n->pk", v_fh, sigma_db) - jnp.array([1.0, 0.0, 0.0])).reshape(ncol, nrow, 3)
    phi_l = safe_norm(base)  # Φ_l (ncol, nrow)
    t = base / jnp.maximum(phi_l, 1e-9)[..., None]
    phi_ll = jax.vmap(jnp.gradient, in_axes=(1, 1), out_axes=1)(phi_l, s)
    w = jax.vmap(lambda q: _upstream_d(q, points), in_axes=1, out_axes=1)(s)  # (ncol, nrow, points)
    # the perturbation's φ_l and φ_z at the free-surface centres from the unknowns [δσ_hull, σ_surface]
    tl = t.reshape(nf, 3)
    along = jnp.concatenate([jnp.einsum("pnk,pk->pn", v_fh, tl), jnp.einsum("pnk,pk->pn", v_ff, tl)], axis=1)
    along = along.reshape(ncol, nrow, nh + nf)
    m = points - 1
    pad = jnp.concatenate([jnp.zeros((m, nrow, nh + nf), c.dtype), along], axis=0)  # undisturbed ahead
    d_along = sum(w[:, :, k, None] * pad[m - k: m - k + ncol] for k in range(points))  # ∂_l φ_l
    up = jnp.concatenate([v_fh[..., 2], v_ff[..., 2]], axis=1).reshape(ncol, nrow, nh + nf)
    fs_rows = (phi_l**2)[..., None] * d_along + (2.0 * phi_l * phi_ll)[..., None] * along
    real = hull.real > 0.0
    hull_rows = jnp.concatenate([jnp.einsum("pnk,pk->pn", v_hh, hull.normal),
                                 jnp.einsum("pnk,pk->pn", v_hf, hull.normal)], axis=1)
    hull_rows = jnp.where(real[:, None], hull_rows, jnp.eye(nh, nh + nf, dtype=c.dtype))
    rhs = jnp.concatenate([jnp.zeros(nh, c.dtype), -(phi_l**2 * phi_ll).reshape(nf)])
    cp_db = 1.0 - jnp.sum(vel_db * vel_db, -1)
    ax = 2.0 * hull.area_vector[:, 0] * hull.real  # both sides

    def one(k):
        a = jnp.concatenate([hull_rows, (fs_rows + k * up).reshape(nf, nh + nf)], axis=0)
        x = jnp.linalg.solve(a, rhs)
        vh = vel_db + jnp.einsum("pnk,n->pk", v_hh, x[:nh]) + jnp.einsum("pnk,n->pk", v_hf, x[nh:])
        vf = base.reshape(nf, 3) + jnp.einsum("pnk,n->pk", v_fh, x[:nh]) + jnp.einsum("pnk,n->pk", v_ff, x[nh:])
        cp = 1.0 - jnp.sum(vh * vh, -1)
        return jnp.sum((cp - cp_db) * ax), cp, 0.5 * (1.0 - jnp.sum(vf * vf, -1)).reshape(ncol, nrow)

    drag, cp, zeta = jax.vmap(one)(jnp.reshape(k0, (-1,)))
    return DawsonFlow(drag=drag, cp=cp, zeta=zeta)


class DawsonResult(eqx.Module):
    """Dawson's method at k speeds (SI).

    Attributes
    ----------
    r_wave : (k,) float
        Wave resistance R_w [N].
    sinkage : (k,) float
        Sinkage at the centre of flotation [m], positive down, from the hull pressure (not iterated).
    trim : (k,) float
        Trim [rad], positive bow up.
    zeta : (k, nx − 1, ny − 1) float
        Free-surface elevation ζ [m], up positive, at ``centres``: Kelvin's pattern, its waves within the
        19.47° wedge (KCS, tests/test_dawson.py); not compared with measured wave cuts.
    centres : (nx − 1, ny − 1, 3) float
        The free-surface panels' centres [m] (port side; i along the stream from ahead of the bow).
    """

    r_wave: Float[Array, "*k"]
    sinkage: Float[Array, "*k"]
    trim: Float[Array, "*k"]
    zeta: Float[Array, "*k nx ny"]
    centres: Float[Array, "nx ny 3"]


def dawson_wave_resistance(sections: Sections, draft: Draft, speed: Speeds, *, rho: float = RHO_SEA,
                           g: float = G, stations: int = STATIONS, girth: int = GIRTH, columns: int = COLUMNS,
                           rows: int = ROWS, points: int = POINTS, downstream: float = DOWNSTREAM,
                           width: float = WIDTH) -> DawsonResult:
    """Wave resistance R_w [N] and the wave pattern by Dawson's method at ``speed`` U [m/s].

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y half-breadths to port, z up from the baseline).
    draft : float or Array
        Draft T [m above the baseline].
    speed : float or Array
        Ship speed U [m/s] > 0, scalar or (k,).
    rho, g : float
        Water density [kg/m³], gravity [m/s²].
    stations, girth : int
        Hull panelling (:func:`._panel.hull_panels`).
    columns, rows : int
        Free-surface grid nodes along the stream and outwards (:func:`hull_surface`).
    points : int
        Points of the upstream difference (:func:`_upstream_d`).
    downstream, width : float
        The free surface's extent behind the stern and beside the centreline [wet lengths L].

    Returns
    -------
    DawsonResult
        ``r_wave``, ``sinkage``, ``trim`` of ``speed``'s shape, ``zeta`` (speed's shape + the grid's),
        ``centres``.
    """
    if not (isinstance(columns, int) and isinstance(rows, int) and columns >= 8 and rows >= 3
            and downstream > 0 and width > 0):
        raise HullError(f"dawson: columns {columns!r} ≥ 8 and rows {rows!r} ≥ 3 (integers), downstream "
                        f"{downstream!r} > 0 and width {width!r} > 0 [L] expected")
    hull = hull_panels(sections, draft, stations, girth)
    surface = hull_surface(hull, stations, girth, columns, rows, downstream=downstream, width=width)
    u = jnp.asarray(speed, dtype=hull.vertices.dtype)
    flat = jnp.reshape(u, (-1,))
    ok = flat > 0.0
    u2 = jnp.where(ok, flat * flat, 1.0)
    flow = dawson_flow(hull, surface, g / u2, points)
    r = jnp.where(ok, 0.5 * rho * u2 * flow.drag, 0.0)
    sink, trim = jax.vmap(lambda cp, h: squat(hull, cp, h, stations, girth))(flow.cp, 0.5 * u2 / g)
    zeta = jnp.where(ok[:, None, None], flow.zeta * (u2 / g)[:, None, None], 0.0)
    shape = jnp.shape(u)
    return DawsonResult(r_wave=r.reshape(shape), sinkage=jnp.where(ok, sink, 0.0).reshape(shape),
                        trim=jnp.where(ok, trim, 0.0).reshape(shape), zeta=zeta.reshape(shape + zeta.shape[1:]),
                        centres=surface.panels.centre.reshape(zeta.shape[1:] + (3,)))
