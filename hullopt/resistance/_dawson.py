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

A dry transom (where the hull has an immersed one, A_T > 0 as Holtrop–Mennen's; :class:`Transom`): the hull is
open at its aft end section, so the double-body flow passes the transom's edge instead of stagnating on a closed
face; the transom's hydrostatic thrust, lost when it runs dry, is added to R_w (as WARP does); and the free
surface behind it is a wake grid of its own, whose lines start from the transom: their upstream difference takes
the water at the edge's depth (and along the bottom's run) where the main grid's takes the undisturbed stream.
Below a transom Froude number U/√(g d_T) of 5 the depth is scaled by (F_nT/5)², the dead water behind a partly
wet transom (WARP's rule). Prescribing the elevation itself in the first wake columns, as WARP does, made the
dense system singular here (a flat panel's own in-plane velocity is nil): ζ of −50 to −900 m there. The start
does not pin the hollow behind the transom — the water rises at once — so C_W is 0.6× WARP's on the DTMB 5415
at Fn 0.28 (0.3× without the condition), 0.85× at 0.41 (benchmarks/README.md).

References: Dawson, C.W. (1977) A practical computer method for solving ship-wave problems. Proc. 2nd Int. Conf.
Numer. Ship Hydrodyn., Berkeley, 30–38. Raven, H.C. (1996) A solution method for the nonlinear ship wave
resistance problem, PhD thesis TU Delft (ch. 4, the linearised problem, its difference schemes and the transom
flow). Nakos, D.E. & Sclavounos, P.D. (1994) Kelvin wakes and wave resistance of cruiser- and transom-stern
ships, J. Ship Res. 38(1), 9–29. Havelock, T.H. (1932) Proc. R. Soc. A 138, 339–348 (the submerged sphere, the
test).
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
from ..geometry import Sections, safe_div, safe_norm, transom_area
from ._panel import (GIRTH, STATIONS, Panels, centre_velocities, double_body_flow, hull_panels, mirrored,
                     source_velocity, squat, waterplane)

UPSTREAM = 0.5  # free-surface grid ahead of the bow [L]
DOWNSTREAM = 1.0  # behind the stern [L]
WIDTH = 1.0  # beside the centreline [L]
COLUMNS = 96  # free-surface grid nodes along the stream
ROWS = 14  # and outwards
WAKE = 3  # wake-grid panel rows across a transom's half-breadth
POINTS = 3  # the upstream difference's points: second order
FN_DRY = 5.0
"""The transom Froude number U/√(g d_T) from which a transom runs dry (Holtrop 1984: its resistance R_TR vanishes
there); below it the dry-transom condition's depth is scaled by (F_nT/FN_DRY)², the dead water behind a
partly wet transom (as WARP's ``dryfr``)."""
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
                 waterline: tuple[Array, Array] | None = None, inner: ArrayLike = 0.0) -> FreeSurface:
    """The port side's free surface z = ``z`` [m] on the columns ``x`` [m] (descending: along the stream) and
    from the centreline — or the ``waterline`` (x ascending, half-breadth y) [m] beside the hull, and y =
    ``inner`` [m] behind it — to y = ``width`` [m] (``rows`` nodes, finer inboard: η^1.5).

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
    inner : float
        The inner edge behind the hull [m] (a transom's half-breadth: the wake grid's, :func:`hull_surface`).

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
        y_in = jnp.where(x < xw[0], inner, y_in)
    eta = jnp.linspace(0.0, 1.0, rows) ** 1.5
    y = y_in[:, None] + (width - y_in[:, None]) * eta[None, :]
    return FreeSurface(jnp.stack([jnp.broadcast_to(x[:, None], y.shape), y, jnp.full_like(y, z)], axis=-1))


def waterline(hull: Panels, stations: int, girth: int) -> tuple[Array, Array]:
    """The hull panels' (:func:`._panel.hull_panels`) waterline: x (stations,) [m], aft to fore, and the
    half-breadth there [m]."""
    wl = hull.vertices[: (stations - 1) * girth].reshape(stations - 1, girth, 4, 3)[:, -1]
    return jnp.concatenate([wl[:, 0, 0], wl[-1:, 3, 0]]), jnp.concatenate([wl[:, 1, 1], wl[-1:, 2, 1]])


def hull_surface(hull: Panels, stations: int, girth: int, columns: int, rows: int, upstream: float = UPSTREAM,
                 downstream: float = DOWNSTREAM, width: float = WIDTH,
                 wake: int = WAKE, on: ArrayLike = True) -> tuple[FreeSurface, FreeSurface]:
    """:func:`free_surface` fitted to the hull panels' waterline (:func:`._panel.hull_panels`' top corners),
    ``upstream``, ``downstream`` and ``width`` in wet lengths L: ``columns`` nodes about evenly spaced, with
    nodes on the hull's ends (so the waterline's ends, a transom's edge, do not move with the grid); and the wake
    grid: ``wake`` rows of panels evenly across the transom's half-breadth b_T behind it, on the same columns
    (the main grid's inner edge there at b_T) where ``on`` (an immersed transom); else a strip 10⁻³ L wide,
    left without sources (:func:`dawson_flow`)."""
    xw, yw = waterline(hull, stations, girth)
    length = xw[-1] - xw[0]
    total = upstream + 1.0 + downstream
    n_up = max(1, round((columns - 1) * upstream / total))
    n_hull = max(2, round((columns - 1) / total))
    n_down = columns - 1 - n_up - n_hull
    behind = xw[0] - downstream * length * jnp.arange(n_down + 1, dtype=xw.dtype) / n_down
    x = jnp.concatenate([xw[-1] + upstream * length * (1.0 - jnp.arange(n_up, dtype=xw.dtype) / n_up),
                         xw[-1] - length * jnp.arange(n_hull, dtype=xw.dtype) / n_hull, behind])
    b_w = jnp.where(on, jnp.maximum(yw[0], 1e-3 * length), 1e-3 * length)
    y = b_w * jnp.linspace(0.0, 1.0, wake + 1)
    wake_nodes = jnp.stack([jnp.broadcast_to(behind[:, None], (n_down + 1, wake + 1)),
                            jnp.broadcast_to(y[None, :], (n_down + 1, wake + 1)),
                            jnp.full((n_down + 1, wake + 1), hull.draft)], axis=-1)
    return free_surface(x, width * length, hull.draft, rows, (xw, yw), b_w), FreeSurface(wake_nodes)


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
        R_w/(½ρU²) [m²]: the perturbation pressure's x force over the wet hull, both sides, and a dry transom's
        lost hydrostatic thrust.
    cp : (k, N) float
        Hull pressure coefficient 1 − |v|²/U² at the hull panels' centres.
    zeta : (k, M) float
        Free-surface elevation × g/U² [−] (ζ·k₀) at the free-surface panels' centres (each grid's, flattened and
        in turn), up positive.
    """

    drag: Float[Array, " k"]
    cp: Float[Array, "k N"]
    zeta: Float[Array, "k M"]


class Transom(eqx.Module):
    """A dry transom (Raven 1996 §4.6; Nakos & Sclavounos 1994): the flow leaves the transom's lower edge
    clean, the transom itself is dry, and the water behind it starts at the edge's depth and along the bottom's
    run. On the wake grid (:func:`hull_surface`) that is where each grid line's Dawson condition starts: its
    upstream difference takes, in place of the undisturbed stream ahead, the perturbation velocity that puts
    the water there (the dynamic condition, ζ known).

    Attributes
    ----------
    on : () float
        1 where the condition holds (an immersed transom, A_T > 0), 0 elsewhere (the wake grid then inert).
    x : () float
        The transom's x [m].
    depth : (nw,) float
        The edge's depth below z = T [m] at each wake-grid row.
    slope : () float
        The run's rise aft −dz/dx at the transom (the girth's mean, clipped to ±0.1 as WARP does).
    greatest : () float
        The transom's greatest depth d_T [m].
    head : (girth,) float
        The transom panels' mean depth T − z [m] (exact for plane panels).
    area : (girth,) float
        Their areas projected on x [m²] (port side): ρg·Σ head·area is the hydrostatic thrust a dry transom
        loses.
    """

    on: Float[Array, ""]
    x: Float[Array, ""]
    depth: Float[Array, " nw"]
    slope: Float[Array, ""]
    greatest: Float[Array, ""]
    head: Float[Array, " girth"]
    area: Float[Array, " girth"]


def transom(hull: Panels, wake: FreeSurface, stations: int, girth: int, on: ArrayLike) -> tuple[Panels, Transom]:
    """The ``hull`` (:func:`._panel.hull_panels`) open at its aft end section where ``on`` (an immersed
    transom), and the dry-transom condition on the ``wake`` grid (:func:`hull_surface`)."""
    n = (stations - 1) * girth
    cap = hull.vertices[n: n + girth]  # aft end, keel to waterline; corner 2 the lower, 1 the upper point
    edge = jnp.concatenate([cap[:, 2], cap[-1:, 1]])  # (girth + 1, 3): the transom's edge, keel to waterline
    t = hull.draft
    on = jnp.asarray(on, dtype=t.dtype)
    run = hull.vertices[:girth]  # the aft panel column: corners 0, 1 on the transom, 3, 2 one station ahead
    slope = -(run[:, 3, 2] - run[:, 0, 2]) / jnp.maximum(run[:, 3, 0] - run[:, 0, 0], 1e-9)
    y = 0.5 * (wake.nodes[0, 1:, 1] + wake.nodes[0, :-1, 1])
    ramp = 1e-9 * jnp.arange(girth + 1, dtype=t.dtype)  # a closed end's edge is all y = 0: kept increasing
    tri = lambda a, b, d: 0.5 * jnp.cross(b - a, d - a)[:, 0] * (t - (a[:, 2] + b[:, 2] + d[:, 2]) / 3.0)  # noqa: E731
    moment = tri(cap[:, 0], cap[:, 1], cap[:, 2]) + tri(cap[:, 0], cap[:, 2], cap[:, 3])  # ∫(T − z) dA_x, exact
    area = hull.area_vector[n: n + girth, 0]
    closed = jnp.broadcast_to(jnp.stack([edge[0, 0], 0.0 * t, t]), cap.shape)
    open_hull = Panels(hull.vertices.at[n: n + girth].set(jnp.where(on > 0.0, closed, cap)), t)
    return open_hull, Transom(on=on, x=edge[0, 0], depth=t - jnp.interp(y, edge[:, 1] + ramp, edge[:, 2]),
                              slope=jnp.clip(jnp.mean(slope[:-1]), -0.1, 0.1), greatest=t - jnp.min(edge[:, 2]),
                              head=safe_div(moment, area, jnp.abs(area) > 0.0), area=jnp.abs(area) * on)


def dawson_flow(hull: Panels, surface: FreeSurface | tuple[FreeSurface, ...], k0: Float[Array, " k"],
                points: int = POINTS, dry: Transom | None = None) -> DawsonFlow:
    """Solve Dawson's problem for the port ``hull`` panels (mirrored in y and in z = ``hull.draft``) and the
    port free ``surface`` (one grid or several side by side; mirrored in y) at each k₀ = g/U² [1/m], per unit
    speed (the stream −x̂).

    Parameters
    ----------
    hull : Panels
        The port side's wet panels (:func:`._panel.hull_panels`, or any closed body's, e.g. a submerged one).
    surface : FreeSurface or tuple of FreeSurface
        The port side's free-surface grids on z = ``hull.draft`` (:func:`free_surface`, :func:`hull_surface`):
        each differenced along its own lines, the undisturbed stream ahead of its first column.
    k0 : (k,) Array
        g/U² [1/m] for each speed.
    points : int
        Points of the upstream difference (:func:`_upstream_d`; 3: second order).
    dry : Transom, optional
        A dry transom's condition (:func:`transom`) on the last grid of ``surface``, the wake behind it.

    Returns
    -------
    DawsonFlow
        ``drag`` R_w/(½ρU²) [m²], the hull's ``cp`` and the free surface's ``zeta``·k₀, one row per k₀.
    """
    surfaces = (surface,) if isinstance(surface, FreeSurface) else tuple(surface)
    v_hh = centre_velocities(hull)  # (nh, nh, 3) hull centres ← hull sources (with images)
    sigma_db, vel_db = double_body_flow(hull, v_hh)
    fp = Panels(jnp.concatenate([s.panels.vertices for s in surfaces]), hull.draft)
    nh, nf = hull.vertices.shape[0], fp.vertices.shape[0]
    dtype = fp.vertices.dtype
    both_h = Panels(mirrored(hull).vertices[: 2 * nh], hull.draft)  # the hull and its starboard mirror
    every_f = Panels(jnp.concatenate([fp.vertices, (fp.vertices * jnp.array([1.0, -1.0, 1.0]))[:, ::-1]]),
                     hull.draft)
    v_hf = source_velocity(hull.centre, every_f, images=2)  # hull centres ← free-surface sources
    # On the waterplane a panel and its image above it induce the mirror images of one velocity: the in-plane
    # parts double, the vertical ones cancel (half the work of the four images)
    v_fh = source_velocity(fp.centre, both_h, images=2) * jnp.array([2.0, 2.0, 0.0])
    v_ff = source_velocity(fp.centre, every_f, own=True, flat=True, images=2)
    v_f = jnp.concatenate([v_fh, v_ff], axis=1)  # (nf, nh + nf, 3) free-surface centres ← every unknown
    # l: the double body's streamlines (towards downstream), differenced along the grid lines that stand for them.
    # Φ_l is the double body's speed, not its part along a grid line: a line that bends across the stream (the
    # waterline's offsets carried outwards) would make Φ_ll of its bends a forcing across the whole width —
    # transverse waves outside Kelvin's wedge, R_w 8–30 % with the grid's extent (KCS: 2.7× too large).
    base = jnp.einsum("pnk,n->pk", v_fh, sigma_db) - jnp.array([1.0, 0.0, 0.0])  # (nf, 3)
    phi_l = safe_norm(base)
    t = base / jnp.maximum(phi_l, 1e-9)[:, None]
    along = jnp.einsum("pnk,pk->pn", v_f, t)  # the perturbation's φ_l from the unknowns [δσ_hull, σ_surface]
    m = points - 1
    rows, rhs_fs, lift_a, lift_b, start = [], [], [], [], 0
    for i, s in enumerate(surfaces):
        ncol, nrow = s.nodes.shape[0] - 1, s.nodes.shape[1] - 1
        block = slice(start, start + ncol * nrow)
        start += ncol * nrow
        c = fp.centre[block].reshape(ncol, nrow, 3)
        step = safe_norm(c[1:] - c[:-1])  # (ncol − 1, nrow)
        arc = jnp.concatenate([jnp.zeros((1, nrow), dtype), jnp.cumsum(step, axis=0)], axis=0)
        pl = phi_l[block].reshape(ncol, nrow)
        pll = jax.vmap(jnp.gradient, in_axes=(1, 1), out_axes=1)(pl, arc)
        w = jax.vmap(lambda q: _upstream_d(q, points), in_axes=1, out_axes=1)(arc)  # (ncol, nrow, points)
        a = along[block].reshape(ncol, nrow, nh + nf)
        pad = jnp.concatenate([jnp.zeros((m, nrow, nh + nf), dtype), a], axis=0)  # undisturbed ahead
        d_along = sum(w[:, :, k, None] * pad[m - k: m - k + ncol] for k in range(points))  # ∂_l φ_l
        rows.append(((pl**2)[..., None] * d_along + (2.0 * pl * pll)[..., None] * a).reshape(-1, nh + nf))
        rhs_fs.append(-(pl**2 * pll).reshape(-1))
        # behind a dry transom (the last grid) the lines' upstream difference starts from the transom instead
        # of the undisturbed stream: m ghosts ahead of the first column, j·Δ ahead (j = m..1), whose φ_l puts
        # the water at ζ = −depth + slope × distance behind the transom: φ_l = (½(1 − Φ_l²) − k₀ζ)/Φ_l with
        # Φ_l the first column's. Known values, so the right-hand side: per k₀, a − k₀·b.
        ghost = jnp.zeros((2, ncol, nrow), dtype)
        if dry is not None and i == len(surfaces) - 1:
            ahead = jnp.arange(m, 0, -1, dtype=dtype)[:, None] * (arc[1] - arc[0])[None, :]  # (m, nrow)
            p0 = jnp.maximum(pl[0], 0.1)
            g = jnp.stack([jnp.broadcast_to(0.5 * (1.0 - p0**2) / p0, ahead.shape),
                           (-dry.depth + dry.slope * (dry.x - c[0, :, 0] - ahead)) / p0])  # (2, m, nrow)
            first = jnp.stack([sum(w[j, :, k] * g[:, m - k + j] for k in range(j + 1, points))
                               for j in range(min(m, ncol))], axis=1)  # (2, ≤ m, nrow)
            ghost = ghost.at[:, : first.shape[1]].set((pl[: first.shape[1]] ** 2) * first)
        lift_a.append(ghost[0].reshape(-1))
        lift_b.append(ghost[1].reshape(-1))
    fs_rows, rhs_fs = jnp.concatenate(rows), jnp.concatenate(rhs_fs)
    lift_a, lift_b = jnp.concatenate(lift_a), jnp.concatenate(lift_b)
    up = v_f[..., 2]  # φ_z
    if dry is not None:  # no transom: no sources on the wake grid
        wake = jnp.arange(nf) >= nf - surfaces[-1].panels.vertices.shape[0]
        inert = wake & (dry.on <= 0.0)
        fs_rows = jnp.where(inert[:, None], jnp.eye(nf, nh + nf, nh, dtype=dtype), fs_rows)
        up = jnp.where(inert[:, None], 0.0, up)
        rhs_fs = jnp.where(inert, 0.0, rhs_fs)
    real = hull.real > 0.0
    hull_rows = jnp.concatenate([jnp.einsum("pnk,pk->pn", v_hh, hull.normal),
                                 jnp.einsum("pnk,pk->pn", v_hf, hull.normal)], axis=1)
    hull_rows = jnp.where(real[:, None], hull_rows, jnp.eye(nh, nh + nf, dtype=dtype))
    cp_db = 1.0 - jnp.sum(vel_db * vel_db, -1)
    ax = 2.0 * hull.area_vector[:, 0] * hull.real  # both sides

    def one(k):
        a = jnp.concatenate([hull_rows, fs_rows + k * up], axis=0)
        rhs, extra = rhs_fs, 0.0
        if dry is not None:
            # dry from F_nT = U/√(g d_T) = FN_DRY, below it the depth times (F_nT/FN_DRY)²: dead water
            wet = jnp.minimum(1.0, 1.0 / jnp.maximum(k * dry.greatest * FN_DRY**2, 1e-12))
            rhs = rhs_fs - dry.on * (lift_a - k * wet * lift_b)
            # the hydrostatic thrust the transom loses, per ½ρU² (both sides), the water behind at −wet·d_T
            extra = 4.0 * k * jnp.sum(jnp.minimum(dry.head, wet * dry.greatest) * dry.area)
        x = jnp.linalg.solve(a, jnp.concatenate([jnp.zeros(nh, dtype), rhs]))
        vh = vel_db + jnp.einsum("pnk,n->pk", v_hh, x[:nh]) + jnp.einsum("pnk,n->pk", v_hf, x[nh:])
        vf = base + jnp.einsum("pnk,n->pk", v_f, x)
        cp = 1.0 - jnp.sum(vh * vh, -1)
        return jnp.sum((cp - cp_db) * ax) + extra, cp, 0.5 * (1.0 - jnp.sum(vf * vf, -1))

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
    wake_zeta : (k, nw, WAKE) float
        ζ [m] on the wake grid behind the transom (:func:`hull_surface`), at ``wake_centres``.
    wake_centres : (nw, WAKE, 3) float
        Its panels' centres [m].
    """

    r_wave: Float[Array, "*k"]
    sinkage: Float[Array, "*k"]
    trim: Float[Array, "*k"]
    zeta: Float[Array, "*k nx ny"]
    centres: Float[Array, "nx ny 3"]
    wake_zeta: Float[Array, "*k nw nr"]
    wake_centres: Float[Array, "nw nr 3"]


def dawson_wave_resistance(sections: Sections, draft: Draft, speed: Speeds, *, rho: float = RHO_SEA,
                           g: float = G, stations: int = STATIONS, girth: int = GIRTH, columns: int = COLUMNS,
                           rows: int = ROWS, points: int = POINTS, downstream: float = DOWNSTREAM,
                           width: float = WIDTH, attitude: int = 0) -> DawsonResult:
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
    attitude : int
        Sinkage-and-trim iterations. 0 (the default): the hull at its static draft, its sinkage and trim
        reported from its pressure, not applied (a model fixed in the tank). n > 0: n more solves per speed, each
        with the hull sunk and trimmed as the solve before found (a model free to sink and trim): n + 1 times
        the work; the free-surface grid stays the static hull's.

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
    if not (isinstance(attitude, int) and attitude >= 0):
        raise HullError(f"dawson: attitude {attitude!r}: a whole number of sinkage-and-trim iterations ≥ 0 expected")
    level = hull_panels(sections, draft, stations, girth)
    on = transom_area(sections.x, sections.yz, draft) > 0.0  # an immersed transom, as Holtrop–Mennen's A_T
    surfaces = hull_surface(level, stations, girth, columns, rows, downstream=downstream, width=width, on=on)
    u = jnp.asarray(speed, dtype=level.vertices.dtype)
    flat = jnp.reshape(u, (-1,))
    ok = flat > 0.0
    u2 = jnp.where(ok, flat * flat, 1.0)
    xf = waterplane(level, stations, girth)[1]

    def solve(k0, sink=0.0, trim=0.0):
        """The flow at each k₀ with the hull sunk by ``sink`` [m] at x_F and trimmed by ``trim`` [rad, bow up]."""
        hull, wet = level, on
        if attitude:  # the hull lowered by the water's rise at each station (sheared: trims are small)
            z = sections.yz[..., 1] - sink + (sections.x - xf)[:, None] * trim
            moved = Sections(sections.x, jnp.stack([sections.yz[..., 0], z], axis=-1), sections.lpp)
            hull, wet = hull_panels(moved, draft, stations, girth), transom_area(moved.x, moved.yz, draft) > 0.0
        hull, dry = transom(hull, surfaces[1], stations, girth, wet)
        flow = dawson_flow(hull, surfaces, k0, points, dry)
        sink, trim = jax.vmap(lambda cp, k: squat(hull, cp, 0.5 / k, stations, girth))(flow.cp, k0)
        return flow, sink, trim

    if attitude:
        def free(k0):  # one speed: the attitude iterated, then the flow there
            step = lambda _, st: tuple(v[0] for v in solve(k0[None], *st)[1:])  # noqa: E731
            st = jax.lax.fori_loop(0, attitude, step, (jnp.zeros((), u.dtype), jnp.zeros((), u.dtype)))
            flow, sink, trim = solve(k0[None], *st)
            return jax.tree.map(lambda a: a[0], flow), sink[0], trim[0]

        flow, sink, trim = jax.vmap(free)(g / u2)
    else:
        flow, sink, trim = solve(g / u2)
    r = jnp.where(ok, 0.5 * rho * u2 * flow.drag, 0.0)
    zeta = jnp.where(ok[:, None], flow.zeta * (u2 / g)[:, None], 0.0)
    shape = jnp.shape(u)
    grids = [s.nodes.shape[:2] for s in surfaces]
    main, wake = [(n[0] - 1, n[1] - 1) for n in grids]
    centres = jnp.concatenate([s.panels.centre for s in surfaces])
    split = main[0] * main[1]
    return DawsonResult(r_wave=r.reshape(shape), sinkage=jnp.where(ok, sink, 0.0).reshape(shape),
                        trim=jnp.where(ok, trim, 0.0).reshape(shape),
                        zeta=zeta[:, :split].reshape(shape + main), centres=centres[:split].reshape(main + (3,)),
                        wake_zeta=zeta[:, split:].reshape(shape + wake),
                        wake_centres=centres[split:].reshape(wake + (3,)))
