"""Explanatory variables of the wind-load regressions (seed 004 §0008, Fujiwara et al. 1998; Isherwood 1972),
from the projections of :mod:`._parts`, exact for the polygons and differentiable in the draft and the sizes.

Sign and reference conventions (used by every coefficient model):

* lengths in m, areas in m², heights above the waterline;
* ``C``, ``C_BR`` are measured from the middle of the overall length above water, **forward positive**
  (seed 004 §0008: "negative when left of midship", with the bow drawn to the right as in its Figs. 2–3);
  ``C_bow = L/2 − C`` is Isherwood's distance from the bow;
* ``H_C`` is the height of the centroid of the lateral area A_L (as in Fujiwara 1998 and ISO 15016; the
  patent's §0008 text names the frontal area here, we follow the paper);
* ``H_BR`` is the top of the superstructure parts above the waterline (of all parts if there is none, of
  the hull if there are no parts); ``C_BR`` the centroid of A_SS (0 without superstructure).

Overlapping projections are counted once: A_L, A_OD, A_SS and A_T are areas of unions, integrated over strips
between all vertex abscissae with two Gauss points each — exact as long as outlines do not cross inside a
strip (boxes, triangles and parts sitting on the deck are exact).
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Bool, Float

from .._types import Draft
from ..geometry import Sections, safe_div, safe_norm
from ._parts import Parts, Projections, projections

NAMES = ("L", "B", "A_T", "A_L", "A_OD", "A_SS", "C", "C_BR", "H_BR", "H_C", "S", "M")
"""The variables named in issue 5 / seed 004, in the order they are reported."""

_BIG = 1e7  # stands for "no interval" on a cut; far outside any ship, never differentiated
GAUSS2_OFFSET = 1.0 / (2.0 * np.sqrt(3.0))  # two-point Gauss–Legendre offset, in strip widths from the middle


def polygon_moments(poly: Float[Array, "... k 2"], order: int = 3) -> Float[Array, "... o o"]:
    """Raw area moments ``M[p, q] = ∬ u^p v^q du dv`` (p + q ≤ order, else 0) of counter-clockwise polygons.

    By Green's theorem ``M[p, q] = ∮ u^(p+1) v^q /(p+1) dv``: a polynomial of degree ≤ order + 1 along each
    edge, integrated exactly by three-point Gauss–Legendre (exact to degree 5). ``M[0, 0]`` is the shoelace
    area; ``M[1, 0]/M[0, 0]``, ``M[0, 1]/M[0, 0]`` the centroid.

    Parameters
    ----------
    poly : (..., k, 2) float
        Counter-clockwise polygons, vertices (u, v) [m]; any leading batch shape.
    order : int
        Highest total order p + q, at most 4.

    Returns
    -------
    Array
        (..., order + 1, order + 1) float moments [m^(2+p+q)], indexed [p, q].

    Raises
    ------
    ValueError
        If ``order`` > 4.
    """
    if order > 4:
        raise ValueError("order ≤ 4 (three-point Gauss–Legendre is exact to degree 5)")
    a, b = poly, jnp.roll(poly, -1, axis=-2)
    nodes = jnp.array([0.5 - 0.5 * np.sqrt(0.6), 0.5, 0.5 + 0.5 * np.sqrt(0.6)])
    weights = jnp.array([5.0, 8.0, 5.0]) / 18.0
    pts = a[..., None, :] + nodes[:, None] * (b - a)[..., None, :]  # (..., k, 3, 2)
    u, v = pts[..., 0], pts[..., 1]
    dv = (b - a)[..., 1][..., None]
    e = np.arange(order + 1)
    up = jnp.stack([u ** (i + 1) / (i + 1.0) for i in range(order + 1)], axis=-1)  # u^(p+1)/(p+1), (..., k, 3, o)
    vq = jnp.stack([v**i for i in range(order + 1)], axis=-1)
    terms = up[..., :, None] * vq[..., None, :]  # (..., k, 3, o, o)
    m = jnp.sum(weights[:, None, None] * terms * dv[..., None, None], axis=(-4, -3))
    return jnp.where(jnp.asarray(e[:, None] + e[None, :] <= order), m, 0.0)


def _cuts(polys: Array, u: Array, axis: int) -> tuple[Array, Array, Array]:
    """Where lines ``coordinate[axis] = u`` meet each convex polygon: intervals ``[lo, hi]`` in the other
    coordinate, ``(G, S)`` each, and ``empty`` (no meeting; then lo = hi = a far-away constant)."""
    a, b = polys, jnp.roll(polys, -1, axis=-2)
    au, av, bu, bv = a[..., axis], a[..., 1 - axis], b[..., axis], b[..., 1 - axis]
    du = bu - au
    t = safe_div(u[:, None, None] - au, du)
    valid = (du != 0) & (t >= 0) & (t <= 1)
    v = av + t * (bv - av)
    empty = ~jnp.any(valid, axis=-1)
    lo = jnp.where(empty, _BIG, jnp.min(jnp.where(valid, v, jnp.inf), axis=-1))
    hi = jnp.where(empty, _BIG, jnp.max(jnp.where(valid, v, -jnp.inf), axis=-1))
    return lo, hi, empty


def _profile_cuts(x: Array, bot: Array, top: Array, u: Array) -> tuple[Array, Array, Array]:
    """:func:`_cuts` of the hull profile of :func:`~hullopt.wind.projections` (the polygon ``(x, bot)``
    forward, then ``(x, top)`` back, ``x`` strictly increasing, ``bot ≤ top``) by the lines ``x = u``, in
    closed form: between stations the line meets the bottom and the top edge of that interval only (the two
    end edges are vertical), so the cut is the two edges' values there — with the same formulas as
    :func:`_cuts`. ``(G, 1)`` each. Where the lines and the stations are unbatched (the stations of a hull
    model), the interval search is done once for a whole vmapped batch and only the edge values are per design."""
    x = jnp.asarray(x)  # a model's stations may be a numpy array: index it as a JAX one
    n = x.shape[0]
    i = jnp.clip(jnp.searchsorted(x, u, side="right") - 1, 0, n - 2)
    x0, x1 = x[i], x[i + 1]
    t_bot = (u - x0) / (x1 - x0)  # bottom edge i, from x_i to x_{i+1}
    t_top = (u - x1) / (x0 - x1)  # top edge i, from x_{i+1} back to x_i
    b0, b1, t0, t1 = bot[i], bot[i + 1], top[i], top[i + 1]
    v_bot = b0 + t_bot * (b1 - b0)
    v_top = t1 + t_top * (t0 - t1)
    empty = ~((u >= x[0]) & (u <= x[-1]))
    lo = jnp.where(empty, _BIG, jnp.minimum(v_bot, v_top))
    hi = jnp.where(empty, _BIG, jnp.maximum(v_bot, v_top))
    return lo[:, None], hi[:, None], empty[:, None]


def _front_integrals(h: Array, w: Array) -> tuple[Array, Array]:
    """Area and ∫h dA of the hull's front view alone (no parts), in closed form: the same values as
    :func:`_union_integrals` of :func:`_strips` of the polygon ``(w, h)`` up, ``(−w, h)`` back down (``h``
    nondecreasing, ``w`` the half-breadths at the levels ``h``). The strip edges are then the levels, each
    twice (their zero-width strips add nothing, neither to the values nor to the gradients), and between
    levels ``i`` and ``i+1`` the line ``h = u`` meets the right and the left edge ``i`` only — with the same
    formulas as :func:`_cuts`; no sort or gather over batched data."""
    h0, h1, w0, w1 = h[:-1], h[1:], w[:-1], w[1:]
    mid, dh = 0.5 * (h1 + h0), h1 - h0
    u = jnp.stack([mid - GAUSS2_OFFSET * dh, mid + GAUSS2_OFFSET * dh], -1)  # (K, 2)
    wt = jnp.repeat(0.5 * dh, 2).reshape(-1, 2)
    t_r = safe_div(u - h0[:, None], dh[:, None])  # right edge i: (w_i, h_i) → (w_{i+1}, h_{i+1})
    du_l = h0 - h1
    t_l = safe_div(u - h1[:, None], du_l[:, None])  # left edge i: (−w_{i+1}, h_{i+1}) → (−w_i, h_i)
    v_r = w0[:, None] + t_r * (w1 - w0)[:, None]
    v_l = -w1[:, None] + t_l * (w1 - w0)[:, None]
    ok = (dh != 0)[:, None] & (t_r >= 0) & (t_r <= 1) & (t_l >= 0) & (t_l <= 1)
    length = jnp.where(ok, jnp.maximum(v_r, v_l) - jnp.minimum(v_r, v_l), 0.0)
    return jnp.sum(wt * length), jnp.sum(wt * u * length)


def _union(lo: Array, hi: Array) -> tuple[Array, Array]:
    """Disjoint pieces ``[a, b]`` (``(G, S)``) whose union is the union of the intervals on each row."""
    if lo.shape[-1] == 1:  # one shape: nothing to merge (and no sort or gather)
        return lo, hi
    order = jnp.argsort(lo, axis=-1)
    lo, hi = jnp.take_along_axis(lo, order, -1), jnp.take_along_axis(hi, order, -1)
    reach = jax.lax.cummax(hi, axis=hi.ndim - 1)
    prev = jnp.concatenate([lo[..., :1], reach[..., :-1]], axis=-1)
    return jnp.maximum(lo, prev), jnp.maximum(hi, prev)


class _Strips(eqx.Module):
    u: Float[Array, " G"]  # Gauss abscissae, two per strip
    w: Float[Array, " G"]  # weights
    lo: Float[Array, "G S"]
    hi: Float[Array, "G S"]
    empty: Bool[Array, "G S"]


def _strips(polys: list[Array | None], axis: int, profile: tuple[Array, Array, Array] | None = None) -> _Strips:
    """Strips between all vertex abscissae of ``polys`` and the cuts there. With ``profile = (x, bot, top)``
    the first polygon is the hull profile of :func:`~hullopt.wind.projections` (``polys[0]`` may then be
    None), cut in closed form (:func:`_profile_cuts`)."""
    flat = [None if p is None else p.reshape(-1, *p.shape[-2:]) for p in polys]
    coords = [p[..., axis].ravel() for p in flat[1:]]
    coords.insert(0, jnp.concatenate([profile[0], profile[0][::-1]]) if profile is not None else flat[0][..., axis].ravel())
    edges = jnp.sort(jnp.concatenate(coords))
    mid, h = 0.5 * (edges[1:] + edges[:-1]), edges[1:] - edges[:-1]
    u = jnp.stack([mid - GAUSS2_OFFSET * h, mid + GAUSS2_OFFSET * h], -1).ravel()
    w = jnp.repeat(0.5 * h, 2)
    cuts = [_profile_cuts(*profile, u) if (k == 0 and profile is not None) else _cuts(p, u, axis)
            for k, p in enumerate(flat)]
    lo, hi, empty = (jnp.concatenate([c[i] for c in cuts], axis=-1) for i in range(3))
    return _Strips(u, w, lo, hi, empty)


def _union_integrals(st: _Strips, cols: list[int]) -> tuple[Array, Array, Array]:
    """Area, ∫u dA and ∫v dA of the union of the shapes ``cols``."""
    if not cols:
        z = jnp.zeros(())
        return z, z, z
    a, b = _union(st.lo[:, cols], st.hi[:, cols])
    length = jnp.sum(b - a, axis=-1)
    area = jnp.sum(st.w * length)
    return area, jnp.sum(st.w * st.u * length), jnp.sum(st.w * jnp.sum(b * b - a * a, axis=-1) / 2)


def _outline_length(st: _Strips, cols: list[int]) -> Array:
    """Length of the outline of a profile standing on the waterline, less the waterline: the upper
    envelope (linear in each strip), its jumps, and the two ends. Holes and overhangs are not counted."""
    top = jnp.maximum(jnp.max(jnp.where(st.empty[:, cols], 0.0, st.hi[:, cols]), axis=-1), 0.0)
    t1, t2 = top[0::2], top[1::2]
    h = 2.0 * st.w[0::2]
    rise = np.sqrt(3.0) * (t2 - t1)  # the Gauss points are h/√3 apart
    inner = jnp.sum(safe_norm(jnp.stack([h, rise], -1)))
    left, right = t1 - 0.5 * (rise - (t2 - t1)), t2 + 0.5 * (rise - (t2 - t1))
    return inner + jnp.sum(jnp.abs(left[1:] - right[:-1])) + left[0] + right[-1]


class WindVariables(eqx.Module):
    """Explanatory variables of one loading condition (module docstring: units, signs, references).

    Scalars: ``L`` overall length above water, ``B`` breadth, ``A_T`` frontal and ``A_L`` lateral projected
    areas, ``A_OD`` lateral area of all parts (superstructure, deck cargo, masts), ``A_SS`` of the
    superstructure, ``C``/``C_BR`` centroids of A_L/A_SS from mid-length (forward +), ``H_BR`` top of the
    superstructure, ``H_C`` centroid height of A_L, ``H_T`` of A_T, ``H_L = A_L/L``, ``S`` outline length
    of the lateral projection without the waterline and masts, ``M`` number of mast groups, ``C_bow``,
    ``x_mid`` mid-length from the AP.

    Per part (``part_names``; the hull above water first, named ``hull``): ``part_area`` (P,),
    ``part_x`` (from mid-length, forward +) and ``part_h`` (above the waterline) centroid, ``part_moments``
    (P, 4, 4) raw moments ``∬ x^p h^q dA`` about (mid-length, waterline) for p + q ≤ 3 [m^(2+p+q)],
    ``part_perimeter`` (P,) and ``part_front_area`` (P,), all from the side view except the last.
    """

    L: Float[Array, ""]
    B: Float[Array, ""]
    A_T: Float[Array, ""]
    A_L: Float[Array, ""]
    A_OD: Float[Array, ""]
    A_SS: Float[Array, ""]
    C: Float[Array, ""]
    C_BR: Float[Array, ""]
    H_BR: Float[Array, ""]
    H_C: Float[Array, ""]
    S: Float[Array, ""]
    M: Float[Array, ""]
    H_T: Float[Array, ""]
    H_L: Float[Array, ""]
    C_bow: Float[Array, ""]
    x_mid: Float[Array, ""]
    part_area: Float[Array, " P"]
    part_x: Float[Array, " P"]
    part_h: Float[Array, " P"]
    part_moments: Float[Array, "P 4 4"]
    part_perimeter: Float[Array, " P"]
    part_front_area: Float[Array, " P"]
    part_names: tuple[str, ...] = eqx.field(static=True)
    part_kinds: tuple[str, ...] = eqx.field(static=True)

    @classmethod
    def from_scalars(cls, **values) -> WindVariables:
        """Variables given by value (e.g. read off a drawing by hand): the :data:`NAMES` [m, m²] (``S`` and
        ``M`` default to 0), with ``H_L = A_L/L`` and ``C_bow = L/2 − C`` derived; no parts."""
        unknown = set(values) - set(NAMES) - {"H_T", "x_mid"}
        if unknown:
            raise ValueError(f"unknown variables {sorted(unknown)}; expected {', '.join(NAMES)}")
        v = {k: jnp.asarray(values.get(k, 0.0), dtype=float) for k in (*NAMES, "H_T", "x_mid")}
        empty = jnp.zeros((0,))
        return cls(**v, H_L=v["A_L"] / v["L"], C_bow=0.5 * v["L"] - v["C"], part_area=empty, part_x=empty,
                   part_h=empty, part_moments=jnp.zeros((0, 4, 4)), part_perimeter=empty, part_front_area=empty,
                   part_names=(), part_kinds=())

    def scalars(self) -> dict[str, Array]:
        """The named variables (``NAMES`` plus ``H_T``, ``H_L``, ``C_bow``, ``x_mid``)."""
        return {k: getattr(self, k) for k in (*NAMES, "H_T", "H_L", "C_bow", "x_mid")}

    def to_dict(self) -> dict:
        """Plain floats and lists, keyed by name; parts as a list of records."""
        out = {k: float(v) for k, v in self.scalars().items()}
        out["parts"] = [
            {"name": n, "kind": k, "area": float(self.part_area[i]), "x": float(self.part_x[i]),
             "h": float(self.part_h[i]), "perimeter": float(self.part_perimeter[i]),
             "front_area": float(self.part_front_area[i]), "moments": np.asarray(self.part_moments[i]).tolist()}
            for i, (n, k) in enumerate(zip(self.part_names, self.part_kinds))
        ]
        return out


def variables_from_projections(pr: Projections) -> WindVariables:
    """:class:`WindVariables` of given projections (see :func:`wind_variables`).

    Parameters
    ----------
    pr : Projections
        Projections of the hull and its parts (:func:`projections`).

    Returns
    -------
    WindVariables
        The explanatory variables (SI: lengths [m], areas [m²]).
    """
    return _variables(pr, pr.hull_side[: pr.present.shape[0], 0])


def _variables(pr: Projections, x: Array) -> WindVariables:
    """:func:`variables_from_projections` with the stations ``x`` of the hull profile given apart (the same
    values as ``pr.hull_side[:n, 0]``; kept unbatched under vmap when they are a model's fixed stations)."""
    parts: Parts = pr.parts
    kinds = parts.kinds
    ss = [1 + i for i, k in enumerate(kinds) if k == "superstructure"]
    od = [1 + i for i in range(parts.p)]
    solid = [0] + [1 + i for i, k in enumerate(kinds) if k != "mast"]

    # Length and mid-length from the profile's stations that bound area above water, and the parts.
    n = pr.present.shape[0]
    px = pr.part_side[..., 0].ravel()
    x_lo = jnp.minimum(jnp.min(jnp.where(pr.present, x, jnp.inf)), jnp.min(px, initial=jnp.inf))
    x_hi = jnp.maximum(jnp.max(jnp.where(pr.present, x, -jnp.inf)), jnp.max(px, initial=-jnp.inf))
    length, x_mid = x_hi - x_lo, 0.5 * (x_hi + x_lo)

    profile = (x, pr.hull_side[:n, 1], pr.hull_side[n:, 1][::-1])
    side = _strips([None, pr.part_side], axis=0, profile=profile)
    a_l, mx_l, mh_l = _union_integrals(side, [0, *od])
    a_od, _, _ = _union_integrals(side, od)
    a_ss, mx_ss, _ = _union_integrals(side, ss)
    s_outline = _outline_length(side, solid)

    if parts.p:
        front = _strips([pr.hull_front[None], pr.part_front], axis=1)
        a_t, mh_t, _ = _union_integrals(front, [0, *od])
    else:
        k1 = pr.hull_front.shape[0] // 2
        a_t, mh_t = _front_integrals(pr.hull_front[:k1, 1], pr.hull_front[:k1, 0])
    fy = jnp.concatenate([pr.hull_front[:, 0], pr.part_front[..., 0].ravel()])
    breadth = jnp.max(fy) - jnp.min(fy)

    if ss:
        h_br = jnp.max(pr.part_side[jnp.array(ss) - 1][..., 1])
    elif parts.p:
        h_br = jnp.max(pr.part_side[..., 1])
    else:
        h_br = jnp.max(pr.hull_side[:, 1])

    c = safe_div(mx_l, a_l) - x_mid
    # Per part, the hull above water first: exact polygon moments about (mid-length, waterline).
    ks = max(pr.hull_side.shape[0], pr.part_side.shape[1])
    pad = lambda a, k: jnp.concatenate([a, jnp.repeat(a[..., -1:, :], k - a.shape[-2], axis=-2)], axis=-2)  # noqa: E731
    polys = jnp.concatenate([pad(pr.hull_side, ks)[None], pad(pr.part_side, ks)])
    polys = polys - jnp.stack([x_mid, jnp.zeros(())])
    mom = polygon_moments(polys, 3)
    area = mom[:, 0, 0]
    kf = max(pr.hull_front.shape[0], pr.part_front.shape[1])
    fronts = jnp.concatenate([pad(pr.hull_front, kf)[None], pad(pr.part_front, kf)])
    mast_groups = {g for g, k in zip(parts.groups, kinds) if k == "mast"}
    return WindVariables(
        L=length, B=breadth, A_T=a_t, A_L=a_l, A_OD=a_od, A_SS=a_ss, C=c,
        C_BR=jnp.where(a_ss > 0, safe_div(mx_ss, a_ss) - x_mid, 0.0), H_BR=h_br, H_C=safe_div(mh_l, a_l),
        S=s_outline, M=jnp.asarray(float(len(mast_groups))), H_T=safe_div(mh_t, a_t), H_L=safe_div(a_l, length),
        C_bow=0.5 * length - c, x_mid=x_mid,
        part_area=area, part_x=safe_div(mom[:, 1, 0], area), part_h=safe_div(mom[:, 0, 1], area), part_moments=mom,
        part_perimeter=jnp.sum(safe_norm(jnp.roll(polys, -1, axis=-2) - polys), axis=-1),
        part_front_area=polygon_moments(fronts, 0)[:, 0, 0],
        part_names=("hull", *parts.names), part_kinds=("hull", *kinds),
    )


def wind_variables(sections: Sections, draft: Draft, parts: Parts, levels: int = 24) -> WindVariables:
    """The wind-load explanatory variables of a hull at ``draft`` [m] with its above-deck ``parts``.

    Pure JAX: jit/grad/vmap-able in the sections, the draft and the parts' polygons. See the module
    docstring for the conventions and :func:`~hullopt.wind.projections` for the geometry.

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    draft : float or Array
        Draft T [m above the baseline] (scalar).
    parts : Parts
        The above-deck parts (:func:`box_parts`, :func:`polygon_parts`, :func:`no_parts`).
    levels : int
        Level intervals of the frontal hull outline (see :func:`projections`).

    Returns
    -------
    WindVariables
        L, B, A_T, A_L, … (lengths [m], areas [m²]; M a count) and the per-part areas and moments, the hull first.
    """
    return _variables(projections(sections, draft, parts, levels), sections.x)
