"""The Coons-patch hull surface of seed 001 (Katsui & Norisada 2005, §2.1): a surface representation of the
kernel, beside the splines it is built from (its sampling into :class:`Sections` is
:func:`hullopt.models.coons_sections`; its curvature and unfairness are in :mod:`hullopt.fairing`).

The hull's port side is the graph ``y = f(x, z)`` over the offset grid: stations ``x (s,)`` [m from the AP],
waterlines ``z (w,)`` [m above the baseline] and half-breadths ``y (s, w)`` [m]. The frame lines (one per
station, ``y`` as a function of ``z``) and the waterlines (``y`` as a function of ``x``) are natural cubic
splines through the offsets. Each cell ``[x_i, x_i+1] × [z_j, z_j+1]`` of the grid is a bicubic Hermite
(Coons) patch in the local parameters ``u = (x − x_i)/hx_i``, ``v = (z − z_j)/hz_j`` ∈ [0, 1]::

    f(u, v) = h(u)ᵀ B h(v),   h = (H00, H01, H10, H11),
    H00 = 2t³ − 3t² + 1,  H01 = −2t³ + 3t²,  H10 = t³ − 2t² + t,  H11 = t³ − t²,

    B = [[ Q(0,0),  Q(0,1),  Qv(0,0),  Qv(0,1)],
         [ Q(1,0),  Q(1,1),  Qv(1,0),  Qv(1,1)],
         [Qu(0,0), Qu(0,1),  0,        0      ],     twist vectors Quv = 0, as in the seed
         [Qu(1,0), Qu(1,1),  0,        0      ]]

with the corner points ``Q`` the offsets and the corner tangents ``Qu = hx ∂y/∂x`` (waterline splines),
``Qv = hz ∂y/∂z`` (frame splines). A spline segment is a cubic fixed by its end values and slopes, so every
patch reproduces its four boundary curves exactly and neighbouring patches share value and cross slope
along their common edge (the surface is C¹); its curvature jumps across patch edges — the reason the
unfairness functionals of :mod:`hullopt.fairing` compare one-sided values there. The x and z components of
the patch are linear in (u, v), so the surface is the graph of ``f`` over (x, z).
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._types import Values
from ._splines import natural_cubic_spline


def hermite_basis(t: Values, nu: int = 0) -> Array:
    """The cubic Hermite blending functions ``(H00, H01, H10, H11)`` or a derivative of them.

    Parameters
    ----------
    t : array_like, any shape
        Local parameter, [0, 1] on a segment (dimensionless).
    nu : int, optional
        Derivative order with respect to ``t``, 0…3 (static).

    Returns
    -------
    Array, shape ``t.shape + (4,)``
        The four functions (or their ``nu``-th derivatives) on a new last axis.
    """
    t = jnp.asarray(t)
    one = jnp.ones_like(t)
    if nu == 0:
        rows = (2 * t**3 - 3 * t**2 + 1, -2 * t**3 + 3 * t**2, t**3 - 2 * t**2 + t, t**3 - t**2)
    elif nu == 1:
        rows = (6 * t**2 - 6 * t, -6 * t**2 + 6 * t, 3 * t**2 - 4 * t + 1, 3 * t**2 - 2 * t)
    elif nu == 2:
        rows = (12 * t - 6, -12 * t + 6, 6 * t - 4, 6 * t - 2)
    elif nu == 3:
        rows = (12 * one, -12 * one, 6 * one, 6 * one)
    else:
        raise ValueError(f"derivative order nu must be 0…3, got {nu}")
    return jnp.stack(rows, axis=-1)


class CoonsSurface(eqx.Module):
    """The composite Coons-patch surface ``y = f(x, z)`` (see the module docstring).

    Attributes
    ----------
    x : (s,) stations [m]; z : (w,) waterlines [m]; both strictly increasing.
    coef : (s−1, w−1, 4, 4) the patch matrices ``B`` (local parameters, so tangents are scaled by the
        cell sizes) [m].
    """

    x: Float[Array, " s"]
    z: Float[Array, " w"]
    coef: Float[Array, "s1 w1 4 4"]

    @property
    def hx(self) -> Float[Array, " s1"]:
        return jnp.diff(self.x)

    @property
    def hz(self) -> Float[Array, " w1"]:
        return jnp.diff(self.z)

    def cells(self, u, v, dx: int = 0, dz: int = 0) -> Float[Array, "s1 w1 p q"]:
        """``∂^(dx+dz) f / ∂x^dx ∂z^dz`` [m^(1−dx−dz)] on every cell at the local parameters ``u (p,)`` ×
        ``v (q,)`` (a tensor grid per cell)."""
        hu = hermite_basis(jnp.asarray(u, self.coef.dtype), dx)  # (p, 4)
        hv = hermite_basis(jnp.asarray(v, self.coef.dtype), dz)  # (q, 4)
        val = jnp.einsum("pa,ijab,qb->ijpq", hu, self.coef, hv)
        return val / (self.hx[:, None, None, None] ** dx * self.hz[None, :, None, None] ** dz)

    def __call__(self, xq, zq, dx: int = 0, dz: int = 0) -> Array:
        """``∂^(dx+dz) f / ∂x^dx ∂z^dz`` at the points ``(xq, zq)`` (broadcast together) [m^(1−dx−dz)].
        Points on a patch edge take the patch above/forward; outside the grid the end patches continue."""
        xq, zq = jnp.broadcast_arrays(jnp.asarray(xq, self.coef.dtype), jnp.asarray(zq, self.coef.dtype))
        i = jnp.clip(jnp.searchsorted(self.x, xq, side="right") - 1, 0, self.x.shape[0] - 2)
        j = jnp.clip(jnp.searchsorted(self.z, zq, side="right") - 1, 0, self.z.shape[0] - 2)
        hx, hz = self.hx[i], self.hz[j]
        hu = hermite_basis((xq - self.x[i]) / hx, dx)
        hv = hermite_basis((zq - self.z[j]) / hz, dz)
        return jnp.einsum("...a,...ab,...b->...", hu, self.coef[i, j], hv) / (hx**dx * hz**dz)


def spline_slopes(knots: Float[Array, " k"], values: Float[Array, "k ..."], end: str = "not-a-knot") -> Array:
    """Slopes at the knots of the cubic spline through ``(knots, values)``.

    ``end="natural"``: zero curvature at both ends (:func:`natural_cubic_spline`, the
    offset-table model of seed 003). ``end="not-a-knot"`` (``k ≥ 4``; fewer knots fall back to natural):
    the third derivative is continuous at the second and the last-but-one knot, so the spline reproduces
    any cubic — a parabolic waterline keeps its end curvature instead of gaining an artificial
    straightening at the ends that fairing would then "correct". Solves the slope equations
    (dense: k is a handful of stations or waterlines); differentiable in the values.

    Parameters
    ----------
    knots : Array, shape (k,)
        Strictly increasing abscissae (e.g. stations or waterlines) [m].
    values : Array, shape (k, ...)
        Values at the knots (several curves on trailing axes) [m].
    end : str, optional
        ``"not-a-knot"`` or ``"natural"``.

    Returns
    -------
    Array, shape (k, ...)
        ``d values / d knots`` at the knots (dimensionless for lengths over lengths).
    """
    knots, y = jnp.asarray(knots), jnp.asarray(values)
    k = knots.shape[0]
    if end == "natural" or k < 4:
        return natural_cubic_spline(knots, y)(knots, nu=1)
    if end != "not-a-knot":
        raise ValueError(f"unknown spline end condition {end!r}; expected 'not-a-knot' or 'natural'")
    h = jnp.diff(knots)
    shape = (-1,) + (1,) * (y.ndim - 1)
    dy = jnp.diff(y, axis=0) / h.reshape(shape)
    # interior rows: h_i s_{i−1} + 2(h_{i−1} + h_i) s_i + h_{i−1} s_{i+1} = 3(h_i δ_{i−1} + h_{i−1} δ_i)
    mat = jnp.diag(jnp.concatenate([h[1:2], 2.0 * (h[:-1] + h[1:]), h[-2:-1]]))
    mat = mat + jnp.diag(jnp.concatenate([knots[2:3] - knots[:1], h[:-1]]), 1)
    mat = mat + jnp.diag(jnp.concatenate([h[1:], knots[-1:] - knots[-3:-2]]), -1)
    d0, d1 = knots[2] - knots[0], knots[-1] - knots[-3]
    first = ((h[0] + 2.0 * d0) * h[1] * dy[0] + h[0] ** 2 * dy[1]) / d0
    last = (h[-1] ** 2 * dy[-2] + (2.0 * d1 + h[-1]) * h[-2] * dy[-1]) / d1
    inner = 3.0 * (h[1:].reshape(shape) * dy[:-1] + h[:-1].reshape(shape) * dy[1:])
    rhs = jnp.concatenate([first[None], inner, last[None]], axis=0)
    return jnp.linalg.solve(mat, rhs.reshape(k, -1)).reshape(y.shape)


def spline_curvatures(knots: Float[Array, " k"], values: Float[Array, "k ..."], end: str = "not-a-knot") -> Array:
    """Curvature ``κ = y''/(1 + y'²)^{3/2}`` of the cubic spline through ``(knots, values)`` at its knots.

    A cubic spline's ``y''`` is linear between knots, so the signs at the knots are its inflections.

    Parameters
    ----------
    knots : Array, shape (k,)
        Strictly increasing abscissae [m].
    values : Array, shape (k, ...)
        Values at the knots [m] (several curves on trailing axes).
    end : str, optional
        ``"not-a-knot"`` or ``"natural"`` (:func:`spline_slopes`).

    Returns
    -------
    Array, shape (k, ...)
        κ at the knots [1/m], positive where the curve turns towards +values.
    """
    knots, y = jnp.asarray(knots), jnp.asarray(values)
    s = spline_slopes(knots, y, end)
    h = jnp.diff(knots).reshape((-1,) + (1,) * (y.ndim - 1))
    d = jnp.diff(y, axis=0) / h
    left = (6.0 * d - 4.0 * s[:-1] - 2.0 * s[1:]) / h  # y'' at each segment's start (Hermite cubic)
    last = (-6.0 * d[-1:] + 2.0 * s[-2:-1] + 4.0 * s[-1:]) / h[-1:]
    return jnp.concatenate([left, last], axis=0) / (1.0 + s**2) ** 1.5


def coons_surface(x: Float[Array, " s"], z: Float[Array, " w"], y: Float[Array, "s w"],
                  end: str = "not-a-knot", twist: str = "zero") -> CoonsSurface:
    """The Coons-patch surface through an offset grid.

    Pure and differentiable in ``y`` (and in the grid); corner tangents from the cubic splines of the
    waterlines (``∂y/∂x``) and of the frame lines (``∂y/∂z``) with end condition ``end`` (see
    :func:`spline_slopes`). ``twist="zero"``: the seed's zero twist vectors (C¹ across patch edges, the
    surface the unfairness functionals are made for); ``twist="spline"``: the twists of the splines of the
    slopes, which makes the patches the tensor-product cubic spline through the same frame lines and
    waterlines — C², so its curvature shows no jumps at patch edges (what a curvature map draws).

    Parameters
    ----------
    x : Array, shape (s,)
        Stations [m from the AP], strictly increasing.
    z : Array, shape (w,)
        Waterlines [m above the baseline], strictly increasing.
    y : Array, shape (s, w)
        Half-breadths [m] (y to port ≥ 0).
    end : str, optional
        Spline end condition, ``"not-a-knot"`` or ``"natural"`` (static).
    twist : str, optional
        ``"zero"`` or ``"spline"`` (static).

    Returns
    -------
    CoonsSurface
        ``y = f(x, z)``: call it at points, or :meth:`CoonsSurface.cells` on every patch.
    """
    x, z, y = jnp.asarray(x), jnp.asarray(z), jnp.asarray(y)
    fx = spline_slopes(x, y, end)  # (s, w): slopes of the waterlines at the stations
    fz = spline_slopes(z, y.T, end).T  # (s, w): slopes of the frame lines at the waterlines

    def corners(a):  # (s, w) → (s−1, w−1, 2, 2): [u corner, v corner]
        return jnp.stack([jnp.stack([a[:-1, :-1], a[:-1, 1:]], -1), jnp.stack([a[1:, :-1], a[1:, 1:]], -1)], -2)

    q = corners(y)
    qu = corners(fx) * jnp.diff(x)[:, None, None, None]  # tangents in the local parameters
    qv = corners(fz) * jnp.diff(z)[None, :, None, None]
    top = jnp.concatenate([q, qv], axis=-1)  # (…, 2, 4)
    if twist == "zero":
        quv = jnp.zeros_like(qu)
    elif twist == "spline":
        fxz = spline_slopes(z, fx.T, end).T  # ∂²y/∂x∂z of the tensor-product spline at the offsets
        quv = corners(fxz) * jnp.diff(x)[:, None, None, None] * jnp.diff(z)[None, :, None, None]
    else:
        raise ValueError(f"unknown twist {twist!r}; expected 'zero' or 'spline'")
    bottom = jnp.concatenate([qu, quv], axis=-1)
    return CoonsSurface(x=x, z=z, coef=jnp.concatenate([top, bottom], axis=-2))
