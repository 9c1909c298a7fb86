"""The feature-curve hull (seed 000, JP2006-79247): contour lines and feature curves, rebuilt frames, and the
deformations of claims 5–7 as one differentiable map ``parameters → Sections``.

A :class:`FeatureHull` holds, at each of ``n`` stations, the contour points (keel, end of the flat of bottom,
start of the flat of side, deck edge) and ``S`` segments between inflection points (apex and auxiliary apexes
in each segment's chord frame, :mod:`._feature_frame`). Joined along the length they are the contour lines and
the inflection, apex and auxiliary-apex lines. A :class:`FeatureModel` adds a design: which apex lines move and
between which fixed ends (claim 5), which feature curves are redistributed and where (claim 7), which contour
lines are edited; its parameters (:class:`FeatureParams`, arrays only) are zero for the parent, and
``model(params)`` is a pure, jit/grad/vmap-able function giving :class:`~hullopt.geometry.Sections`.

Order of operations (each is smooth in the parameters):

1. **distribution** (claim 7, §0026): the feature points of a group of feature curves slide along those
   curves: the station at ``x`` takes the parent's feature point at ``φ(x)``, a monotone warp of
   ``[x_a, x_b]`` onto itself, ``φ(x) = x_a + (x_b − x_a)(ξ + Σ_j c_j sin(jπξ)/(jπ))``. Closing the spacing
   steepens the surface along the curve, opening it softens it; with the group "all" the whole frames move
   along the length, which moves LCB and Cp. Feature curves are interpolated along the length by monotone
   cubic Hermite (PCHIP) curves: C¹ in the warp, no overshoot where a segment appears; the points of a frame
   as offsets along its chain (keel → segment ends → deck edge), so points that coincide at two stations
   coincide between them. Re-read frames are blends of the parent's feature data, not of its sections: where
   the segments change in number between two stations (a bulb's, a forefoot's) a blended frame is a new shape.
   The group ``"stations"`` instead moves the frames themselves, the one at ``x`` to ``φ(x)`` (Lackenby's
   station shift: each frame keeps the parent's shape, the stations are no longer the parent's);
2. **contour edits**: smooth bumps (``sin²`` window) or ramps (smoothstep) added to a contour line — keel
   height (the fore/aft profile), flat-of-bottom half-breadth, flat-of-side height, deck edge;
3. **apex moves** (claim 5): one apex of an apex line moves by ``d = (dy, dz)`` [m]; every apex between the
   two fixed ends E1, E2 moves by ``d`` times the ratio of its projected distance on E1E2 to the nearer end
   over the moved apex's (``profile="linear"``, the claim exactly; ``"smooth"`` uses the quintic smootherstep
   6r⁵ − 15r⁴ + 10r³ of that ratio r, so the displacement has zero slope and zero curvature at the moved apex
   and at the fixed ends: C² there, no kink and no jump of curvature in the sections or the sectional-area
   curve where the move starts — the cubic smoothstep 3r² − 2r³ it replaced was only C¹ and put the
   largest curvature of the move right at the fixed ends);
4. **frames** (claim 6): the auxiliary apexes keep their ratios along and across the chord, because they are
   stored as those ratios; each segment is rebuilt as the patent's cubic spline;
5. **bow attachments** (:mod:`._bow`) on the rebuilt frames, then 6. the **beam** scale (every half-breadth × 1 +
   s) and 7. the **draft** scale (every height × 1 + s from the baseline, and the draft the hull floats at with
   them: :meth:`FeatureModel.draft_factor`).

Deformations act in the (y, z) plane of each frame; stations stay where the parent has them unless a
``"stations"`` distribution moves them.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Bool, Float

from ..errors import HullError
from ..geometry import TINY_LENGTH, Sections, atomic_write_bytes, hermite, pchip_slopes, safe_div
from ._bow import BowAttachment, attach_bow, attachment_plan, stem_station
from ._feature_frame import apex_points, aux_points, rebuild_frames

PARENTS_DIR = Path(__file__).resolve().parents[1] / "data" / "parents"


class FeatureHull(eqx.Module):
    """Contour lines and feature curves of a hull at ``n`` stations, ``S`` segments, ``J`` auxiliary apexes per
    half-segment. Lengths in m; (y, z) pairs with y ≥ 0 to port and z up from the baseline.

    Attributes
    ----------
    x : (n,) station positions from the AP; ``lpp`` the length between perpendiculars.
    keel : (n, 2) keel point (on the centreline); ``deck`` (n, 2) the deck edge.
    ends : (n, S+1, 2) segment ends: ``ends[:, 0]`` the end of the flat of bottom (= keel where none),
        ``ends[:, S]`` the start of the flat of side (= deck edge where none), between them inflection points.
    apex : (n, S, 2) apex ``(β, η)`` in the segment's chord frame; ``aux`` (n, S, 2, J, 2) the auxiliary
        apexes' claim-6 ratios ``(ρ, σ)``, per half (from the first / from the second inflection).
    real : (n, S) whether the segment exists in the parent (False: zero-length padding).
    """

    x: Float[ArrayLike, " n"]  # numpy as read (building a design runs no JAX op), JAX under transforms
    lpp: Float[ArrayLike, ""]
    keel: Float[ArrayLike, "n 2"]
    deck: Float[ArrayLike, "n 2"]
    ends: Float[ArrayLike, "n S1 2"]
    apex: Float[ArrayLike, "n S 2"]
    aux: Float[ArrayLike, "n S 2 J 2"]
    real: Bool[ArrayLike, "n S"]
    q: int = eqx.field(static=True, default=2)
    name: str = eqx.field(static=True, default="hull")
    design_draft: float | None = eqx.field(static=True, default=None)

    @property
    def n_segments(self) -> int:
        return self.apex.shape[-2]

    def sections(self, q: int | None = None) -> Sections:
        """The rebuilt hull (no deformation); ``q`` samples per knot interval (default: the hull's)."""
        yz = rebuild_frames(self.keel, self.ends, self.apex, self.aux, self.deck, q or self.q)
        return Sections(x=self.x, yz=yz, lpp=self.lpp)

    def apex_points(self) -> ArrayLike:
        """(n, S, 2) absolute apex positions (y, z)."""
        return apex_points(self.ends, self.apex)

    def aux_points(self) -> ArrayLike:
        """(n, S, 2, J, 2) absolute auxiliary-apex positions (y, z)."""
        return aux_points(self.ends, self.apex, self.aux)

    def contour_lines(self) -> dict[str, np.ndarray]:
        """The patent's contour lines as ``(k, 3)`` arrays of (x, y, z): fore and aft profile (the keel
        line forward and aft of midship), deck side line, flat-of-side and flat-of-bottom lines (where the
        flats exist), transom end line (the aftmost frame's lowest edge, from the keel to its bilge)."""
        x = np.asarray(self.x)
        keel, deck, ends = (np.asarray(a) for a in (self.keel, self.deck, self.ends))
        xyz = lambda p: np.column_stack([x, p])  # noqa: E731
        fwd = x >= float(self.lpp) / 2
        fob, fos = ends[:, 0], ends[:, -1]
        has_fob = fob[:, 0] > keel[:, 0] + TINY_LENGTH
        has_fos = np.hypot(*(deck - fos).T) > TINY_LENGTH
        return {
            "fore_profile": xyz(keel)[fwd],
            "aft_profile": xyz(keel)[~fwd],
            "deck_side": xyz(deck),
            "flat_of_side": xyz(fos)[has_fos],
            "flat_of_bottom": xyz(fob)[has_fob],
            "transom_end": np.column_stack([np.full(2, x[0]), np.stack([keel[0], fob[0]])]),
        }

    def to_dict(self) -> dict:
        return {
            "name": self.name, "design_draft": self.design_draft, "q": self.q, "lpp": float(self.lpp),
            **{k: np.asarray(getattr(self, k)).tolist() for k in ("x", "keel", "deck", "ends", "apex", "aux")},
            "real": np.asarray(self.real).astype(int).tolist(),
        }


def feature_hull(features: dict, name: str = "hull", design_draft: float | None = None, q: int = 2) -> FeatureHull:
    """A :class:`FeatureHull` from the arrays of :func:`extract_features` (or a parent file).

    Parameters
    ----------
    features : dict
        Arrays (any array-likes) ``x (n,)``, ``keel (n, 2)``, ``deck (n, 2)``, ``ends (n, S+1, 2)``,
        ``apex (n, S, 2)``, ``aux (n, S, 2, J, 2)``, ``real (n, S)`` and the scalar ``lpp`` (lengths in m).
    name : str
        The hull's name ("hull" by default).
    design_draft : float, optional
        Design draft [m above the baseline]; ``None``: unknown.
    q : int
        Samples per knot interval when the frames are rebuilt (2 by default).

    Returns
    -------
    FeatureHull
        With numpy float64 leaves (``real`` bool).
    """
    # numpy leaves: reading a parent and building a design on it run no JAX op (each costs a compile)
    f = {k: np.asarray(features[k], dtype=np.float64) for k in ("x", "keel", "deck", "ends", "apex", "aux")}
    return FeatureHull(
        lpp=np.asarray(float(features["lpp"])), real=np.asarray(features["real"], bool),
        q=int(q), name=name, design_draft=design_draft, **f,
    )


def save_features(hull: FeatureHull, path: str | Path, **meta) -> Path:
    """Write a parent file (JSON: the arrays plus ``meta``, e.g. its source and how it was extracted).

    Parameters
    ----------
    hull : FeatureHull
        The parent to write.
    path : str or Path
        The JSON file to write (replaced atomically).
    **meta
        Extra JSON-serialisable entries written beside the arrays.

    Returns
    -------
    Path
        ``path``.
    """
    path = Path(path)
    atomic_write_bytes(path, (json.dumps({**meta, **hull.to_dict()}, separators=(",", ":")) + "\n").encode())
    return path


def read_features(path: str | Path) -> FeatureHull:
    """Read a parent file written by :func:`save_features`; :class:`HullError` if it is not one.

    Parameters
    ----------
    path : str or Path
        A parent JSON file.

    Returns
    -------
    FeatureHull
        Its name from the file (else the file's stem), ``design_draft`` [m] or ``None``, ``q`` (2 if absent).
    """
    path = Path(path)
    try:
        d = json.loads(path.read_text())
        return feature_hull(d, d.get("name", path.stem), d.get("design_draft"), d.get("q", 2))
    except (OSError, ValueError, KeyError, TypeError) as e:
        raise HullError(f"{path}: not a feature-curve parent file ({type(e).__name__}: {e})") from None


def parent_names() -> list[str]:
    """Names of the parents in the package library (``hullopt/data/parents/*.json``).

    Returns
    -------
    list of str
        The library parents' names, sorted.
    """
    return sorted(p.stem for p in PARENTS_DIR.glob("*.json"))


def load_parent(name: str) -> FeatureHull:
    """A library parent by name (see :func:`parent_names`), or a parent file path.

    Parameters
    ----------
    name : str
        A library parent's name, or the path of a parent JSON file.

    Returns
    -------
    FeatureHull
        The parent (raises :class:`HullError` if neither is found).
    """
    path = PARENTS_DIR / f"{name}.json"
    if path.is_file():
        return read_features(path)
    if Path(name).is_file():
        return read_features(name)
    raise HullError(f"unknown parent {name!r}; expected one of {', '.join(parent_names())} or a parent .json file")


# ----------------------------------------------------------------------------------------------- the design


@dataclass(frozen=True)
class ApexMove:
    """Claim 5: on apex line ``segment`` (0 = lowest, −1 = uppermost), the apexes at the stations nearest
    ``x_fixed1`` and ``x_fixed2`` [m from AP] stay, the apex nearest ``x_moved`` moves by the parameter
    vector; ``profile`` ``"linear"`` (the claim) or ``"smooth"`` (C² at the fixed ends and the moved apex)."""

    segment: int
    x_fixed1: float
    x_moved: float
    x_fixed2: float
    profile: str = "linear"


@dataclass(frozen=True)
class Distribution:
    """Claim 7: redistribute the feature points of ``curves`` between ``x_a`` and ``x_b`` with ``modes`` sine
    modes. ``curves`` is ``"all"`` (whole frames re-read along the length), a tuple of names ``"apex:<s>"``,
    ``"aux:<s>"``, ``"inflection:<k>"`` (``ends[:, k]``), ``"keel"``, ``"deck"``, or ``"stations"``: the
    frames themselves move, the one at ``x`` to ``φ(x)`` (a Lackenby-like shift; each keeps its shape)."""

    x_a: float
    x_b: float
    curves: str | tuple[str, ...] = "all"
    modes: int = 2


@dataclass(frozen=True)
class ContourEdit:
    """A contour-line edit of amplitude given by the parameter [m]: ``line`` one of ``keel_z`` (profile
    height), ``fob_y`` (flat-of-bottom half-breadth), ``fos_z`` (flat-of-side lower end), ``deck_y``,
    ``deck_z``; window ``shape`` ``"bump"`` (``sin²`` on ``[x_a, x_b]``) or ``"ramp"`` (smoothstep from 0 at
    ``x_a`` to 1 at ``x_b``, 1 beyond; with ``x_a > x_b`` it ramps the other way)."""

    line: str
    x_a: float
    x_b: float
    shape: str = "bump"


CONTOUR_LINES = ("keel_z", "fob_y", "fos_z", "deck_y", "deck_z")


class FeatureParams(eqx.Module):
    """Design parameters (zero = the parent): ``apex (K, 2)`` move vectors (dy, dz) [m] of the model's apex
    moves; ``distribution (G, modes)`` warp coefficients (|Σ c| < 1 keeps the warp monotone); ``contour (E,)``
    contour-edit amplitudes [m]; ``bow (W,)`` bow-attachment amplitudes [m] (:mod:`._bow`); ``beam (P,)``
    (P = 0 or 1) the relative change of every half-breadth, y ↦ (1 + beam)·y (Lpp and heights kept); ``draft
    (Q,)`` (Q = 0 or 1) the relative change of every height and of the draft the hull floats at, z ↦ (1 +
    draft)·z from the baseline (Lpp and breadths kept, the keel on the baseline; the draft a design is
    evaluated at is :meth:`FeatureModel.draft_factor` times the parent's)."""

    apex: Float[ArrayLike, "K 2"]  # numpy for a config's start and bounds, JAX when solved
    distribution: Float[ArrayLike, "G J"]
    contour: Float[ArrayLike, " E"]
    bow: Float[ArrayLike, " W"] = eqx.field(default_factory=lambda: np.zeros(0))
    beam: Float[ArrayLike, " P"] = eqx.field(default_factory=lambda: np.zeros(0))
    draft: Float[ArrayLike, " Q"] = eqx.field(default_factory=lambda: np.zeros(0))


def _smoothstep(r):
    return r * r * (3.0 - 2.0 * r)


def _smootherstep(r):
    """6r⁵ − 15r⁴ + 10r³: 0 and 1 at r = 0 and 1 with zero first and second derivatives there."""
    return r * r * r * (r * (6.0 * r - 15.0) + 10.0)


class FeatureModel(eqx.Module):
    """A parent plus a design (moves, distributions, edits): ``model(params) → Sections``. Build with
    :func:`feature_model`."""

    hull: FeatureHull
    base: Float[ArrayLike, "n C"]  # the parent's feature channels, flattened (numpy: built once)
    chained: Float[ArrayLike, "n C"]  # base in the columns a distribution interpolates in (_chain) …
    unchain: Float[ArrayLike, "C C"]  # … and back to the channels
    slopes: Float[ArrayLike, "n C"]  # PCHIP slopes along x of chained
    move_w: Float[ArrayLike, "K n"]
    move_seg: tuple[int, ...] = eqx.field(static=True)
    dist_mask: Float[ArrayLike, "G C"]
    dist_range: Float[ArrayLike, "G 2"]
    edit_w: Float[ArrayLike, "E n C"]
    design: tuple[tuple[ApexMove, ...], tuple[Distribution, ...], tuple[ContourEdit, ...]] = eqx.field(static=True)
    bow_plan: Float[ArrayLike, "W n"] = eqx.field(default_factory=lambda: np.zeros((0, 0)))  # plan forms W(x)
    bow_band: Float[ArrayLike, "W 3"] = eqx.field(default_factory=lambda: np.zeros((0, 3)))  # (z_lo, z_hi, blend)
    bows: tuple[BowAttachment, ...] = eqx.field(static=True, default=())
    beam_scale: bool = eqx.field(static=True, default=False)
    draft_scale: bool = eqx.field(static=True, default=False)

    def zeros(self) -> FeatureParams:
        """The parameters that give back the parent exactly."""
        k, g, e = len(self.move_seg), self.dist_mask.shape[0], self.edit_w.shape[0]
        modes = max([d.modes for d in self.design[1]], default=0)
        return FeatureParams(jnp.zeros((k, 2)), jnp.zeros((g, modes)), jnp.zeros((e,)), jnp.zeros(len(self.bows)),
                             jnp.zeros(int(self.beam_scale)), jnp.zeros(int(self.draft_scale)))

    def draft_factor(self, params: FeatureParams):
        """The design's draft over the parent's: ``1 + params.draft`` with a draft scale (its heights scaled
        alike from the baseline), else 1.0. A design is evaluated at ``draft · draft_factor(params)``
        (:class:`~hullopt.optimise.Design`)."""
        return 1.0 + params.draft[0] if self.draft_scale else 1.0

    def features(self, params: FeatureParams) -> FeatureHull:
        """The deformed feature hull (steps 1–3 of the module docstring)."""
        self = jax.tree.map(jnp.asarray, self)  # numpy leaves (built without JAX ops) as JAX constants
        h = self.hull
        x = h.x
        f = self.base
        # 1. distribution: warp x within each group's range and re-read its curves there, or (the group
        # "stations") move the frames themselves there.
        x_out = x
        c = _used_modes(self, params)
        for g in range(self.dist_mask.shape[0]):
            xa, xb = self.dist_range[g, 0], self.dist_range[g, 1]
            xi = jnp.clip((x - xa) / (xb - xa), 0.0, 1.0)
            j = jnp.arange(1, c.shape[1] + 1, dtype=x.dtype)
            dxi = jnp.sum(c[g] * jnp.sin(jnp.pi * j * xi[:, None]) / (jnp.pi * j), -1)
            t = xa + (xb - xa) * (xi + dxi)
            t = jnp.where((x > xa) & (x < xb), t, x)
            if self.design[1][g].curves == "stations":
                x_out = jnp.where((x > xa) & (x < xb), t, x_out)
            else:
                # the change only, so that zero parameters give the parent bit for bit
                warped = self.base + (hermite(x, self.chained, self.slopes, t, jnp) - self.chained) @ self.unchain
                f = jnp.where(self.dist_mask[g] > 0, warped, f)
        # 2. contour edits.
        f = f + jnp.einsum("e,enc->nc", params.contour, self.edit_w)
        out = eqx.tree_at(lambda t: t.x, _unflatten(h, f), x_out)
        # 3. apex moves (absolute displacement of the apex, re-expressed in the current chord frame).
        if self.move_seg:
            ends, apex = out.ends, out.apex
            c = ends[:, 1:] - ends[:, :-1]
            rc = jnp.stack([-c[..., 1], c[..., 0]], -1)
            cc = jnp.sum(c * c, -1)
            ok = cc > 1e-12 * (1.0 + h.lpp**2)
            disp = jnp.zeros_like(c)
            for k, s in enumerate(self.move_seg):
                disp = disp.at[:, s].add(self.move_w[k][:, None] * params.apex[k])
            d_beta = safe_div(jnp.sum(disp * c, -1), cc, ok)
            d_eta = safe_div(jnp.sum(disp * rc, -1), cc, ok)
            out = eqx.tree_at(lambda t: t.apex, out, apex + jnp.stack([d_beta, d_eta], -1))
        return out

    def __call__(self, params: FeatureParams) -> Sections:
        return self.finish(self.features(params).sections(), params)

    def finish(self, s: Sections, params: FeatureParams) -> Sections:
        """Steps 5–7 on the rebuilt frames ``s`` of :meth:`features`."""
        if self.bows:  # 5. bow attachments, on the rebuilt frames (they widen collapsed segments too)
            scale = tuple(b.mode == "scale" for b in self.bows)
            s = attach_bow(s, params.bow, self.bow_plan, self.bow_band, scale)
        if self.beam_scale:  # 6. the beam, every half-breadth alike
            s = Sections(x=s.x, yz=s.yz.at[..., 0].multiply(1.0 + params.beam[0]), lpp=s.lpp)
        if self.draft_scale:  # 7. the heights and the draft, from the baseline (the keel stays on it)
            s = Sections(x=s.x, yz=s.yz.at[..., 1].multiply(1.0 + params.draft[0]), lpp=s.lpp)
        return s


def _used_modes(model: FeatureModel, params: FeatureParams) -> Array:
    """``params.distribution`` with the modes beyond each group's own count zeroed (the array has as many
    columns as the group with the most)."""
    c = params.distribution
    used = np.arange(c.shape[-1]) < np.array([d.modes for d in model.design[1]], int).reshape(-1, 1)
    return jnp.where(used, c, 0.0)


def _channels(h: FeatureHull) -> list[tuple[str, tuple[int, ...]]]:
    return [(k, tuple(getattr(h, k).shape[1:])) for k in ("keel", "deck", "ends", "apex", "aux")]


def _flatten(h: FeatureHull) -> np.ndarray:
    """The hull's channels side by side, ``(n, C)`` (numpy: static preprocessing)."""
    n = h.x.shape[0]
    return np.concatenate([np.asarray(getattr(h, k)).reshape(n, -1) for k, _ in _channels(h)], -1)


def _columns(h: FeatureHull) -> dict[str, np.ndarray]:
    """Column indices of each field in the flattened channels, shaped like the field's trailing axes."""
    out, start = {}, 0
    for k, shape in _channels(h):
        size = int(np.prod(shape))
        out[k] = np.arange(start, start + size).reshape(shape)
        start += size
    return out


def _unflatten(h: FeatureHull, f: ArrayLike) -> FeatureHull:
    cols = _columns(h)
    n = f.shape[0]
    vals = {k: f[:, c.reshape(-1)].reshape((n,) + c.shape) for k, c in cols.items()}
    return eqx.tree_at(lambda t: (t.keel, t.deck, t.ends, t.apex, t.aux), h,
                       tuple(vals[k] for k in ("keel", "deck", "ends", "apex", "aux")))


def _chain(h: FeatureHull) -> np.ndarray:
    """``(C, C)`` change of columns: each point of a frame's chain keel → segment ends → deck edge becomes its
    offset from the previous one (apex and auxiliary-apex ratios unchanged). A distribution interpolates in
    these columns: monotone (PCHIP) interpolation keeps a zero offset at two stations zero between them, so
    feature points that coincide there (a collapsed segment, an inflection on the deck edge) stay together —
    interpolated one by one, their different slopes part them (by up to 0.15 m on the DTC): a stub segment that
    turns any way."""
    cols = _columns(h)
    chain = np.concatenate([cols["keel"][None], cols["ends"], cols["deck"][None]])  # (S + 3, 2)
    a = np.eye(_flatten(h).shape[1])
    a[chain[:-1].reshape(-1), chain[1:].reshape(-1)] = -1.0
    return a


def _station(x: np.ndarray, value: float, what: str) -> int:
    if not (math.isfinite(value) and x[0] <= value <= x[-1]):
        raise HullError(f"{what} = {value:g} m is outside the hull (stations from {x[0]:g} to {x[-1]:g} m)")
    return int(np.argmin(np.abs(x - value)))


def _move_weights(h: FeatureHull, mv: ApexMove) -> tuple[int, np.ndarray]:
    x = np.asarray(h.x)
    s_count = h.n_segments
    if not -s_count <= mv.segment < s_count:
        raise HullError(f"apex move: segment {mv.segment} does not exist; this hull has {s_count} (0..{s_count - 1})")
    s = mv.segment % s_count
    i1 = _station(x, mv.x_fixed1, "apex move x_fixed1")
    k = _station(x, mv.x_moved, "apex move x_moved")
    i2 = _station(x, mv.x_fixed2, "apex move x_fixed2")
    if i1 > i2:
        i1, i2 = i2, i1
    if not i1 < k < i2:
        raise HullError(
            f"apex move: the moved apex (x = {x[k]:g} m) must lie strictly between the fixed ends "
            f"(x = {x[i1]:g} and {x[i2]:g} m, nearest stations)"
        )
    real = np.asarray(h.real)[:, s]
    for i, what in ((i1, "fixed end E1"), (i2, "fixed end E2"), (k, "moved apex")):
        if not real[i]:
            raise HullError(
                f"apex move: the {what} at x = {x[i]:g} m is not on apex line {s}: that frame has no such "
                f"segment (it exists at x = {', '.join(f'{v:g}' for v in x[real][[0, -1]])} … m)"
            )
    if not real[i1 : i2 + 1].all():
        raise HullError(f"apex move: apex line {s} is interrupted between x = {x[i1]:g} and {x[i2]:g} m")
    if mv.profile not in ("linear", "smooth"):
        raise HullError(f"apex move: profile {mv.profile!r} must be 'linear' or 'smooth'")
    ap = np.asarray(h.apex_points())[:, s]
    p = np.column_stack([x, ap])  # 3-D apex line
    e1, e2 = p[i1], p[i2]
    axis = e2 - e1
    t = np.clip((p - e1) @ axis / (axis @ axis), 0.0, 1.0)  # projection on E1E2 (0 at E1, 1 at E2)
    tk = t[k]
    # Claim 5: ratio of the projected distances to the nearer fixed end.
    r = np.where(t <= tk, t / tk, (1.0 - t) / (1.0 - tk))
    r[: i1 + 1] = 0.0
    r[i2:] = 0.0
    r[k] = 1.0
    w = r if mv.profile == "linear" else _smootherstep(r)
    return s, w


def _dist_columns(h: FeatureHull, curves) -> np.ndarray:
    cols = _columns(h)
    c = np.zeros(_flatten(h).shape[1])
    if curves == "all":
        return c + 1.0
    if curves == "stations":
        return c
    for name in (curves,) if isinstance(curves, str) else curves:
        if name in ("all", "stations"):
            raise HullError(f"distribution: {name!r} is a group of its own: give it as curves = {name!r}, not in a "
                            "list")
        kind, _, idx = name.partition(":")
        try:
            if kind in ("keel", "deck") and not idx:
                c[cols[kind].reshape(-1)] = 1
            elif kind == "apex":
                c[cols["apex"][int(idx)].reshape(-1)] = 1
            elif kind == "aux":
                c[cols["aux"][int(idx)].reshape(-1)] = 1
            elif kind == "inflection":
                c[cols["ends"][int(idx)].reshape(-1)] = 1
            else:
                raise ValueError
        except (ValueError, IndexError):
            raise HullError(
                f"distribution: unknown feature curve {name!r}; expected 'all', 'stations', 'keel', 'deck', "
                f"'apex:<s>', 'aux:<s>' or 'inflection:<k>' with s < {h.n_segments}, k ≤ {h.n_segments}"
            ) from None
    # an inflection curve that coincides with the keel or the deck edge somewhere (no flat of bottom or side
    # there) slides with it: one without the other would open a gap in those sections
    ends = np.asarray(h.ends)
    for line in ("keel", "deck"):
        on = np.asarray(getattr(h, line))
        for k in np.flatnonzero(np.any(np.all(ends == on[:, None], -1), 0)):
            group = np.concatenate([cols[line].reshape(-1), cols["ends"][k].reshape(-1)])
            if c[group].any():
                c[group] = 1
    return c


def _window(x: np.ndarray, ed: ContourEdit) -> np.ndarray:
    if ed.shape == "bump":
        lo, hi = sorted((ed.x_a, ed.x_b))
        r = np.clip((x - lo) / (hi - lo), 0.0, 1.0)
        return np.sin(np.pi * r) ** 2
    if ed.shape == "ramp":
        return _smoothstep(np.clip((x - ed.x_a) / (ed.x_b - ed.x_a), 0.0, 1.0))
    raise HullError(f"contour edit: shape {ed.shape!r} must be 'bump' or 'ramp'")


def _edit_weights(h: FeatureHull, ed: ContourEdit) -> np.ndarray:
    if ed.line not in CONTOUR_LINES:
        raise HullError(f"contour edit: line {ed.line!r} must be one of {', '.join(CONTOUR_LINES)}")
    if not (math.isfinite(ed.x_a) and math.isfinite(ed.x_b) and ed.x_a != ed.x_b):
        raise HullError(f"contour edit {ed.line}: x_a and x_b must be two different numbers")
    x = np.asarray(h.x)
    cols = _columns(h)
    keel, deck, ends = (np.asarray(getattr(h, k)) for k in ("keel", "deck", "ends"))
    w = np.zeros((len(x), _flatten(h).shape[1]))
    win = _window(x, ed)
    for i in range(len(x)):
        same = lambda p: np.all(ends[i] == p, axis=-1)  # noqa: E731 - feature points coinciding with p
        if ed.line == "keel_z":
            targets = [cols["keel"][1], *cols["ends"][same(keel[i]), 1]]
        elif ed.line == "fob_y":
            targets = list(cols["ends"][same(ends[i, 0]), 0])
        elif ed.line == "fos_z":
            targets = [cols["ends"][-1, 1]]
        elif ed.line == "deck_y":
            targets = [cols["deck"][0], cols["ends"][-1, 0]]
        else:
            targets = [cols["deck"][1], *cols["ends"][same(deck[i]), 1]]
        w[i, targets] = win[i]
    return w


def feature_model(hull: FeatureHull, moves: Sequence[ApexMove] = (), distributions: Sequence[Distribution] = (),
                  edits: Sequence[ContourEdit] = (), bows: Sequence[BowAttachment] = (), beam: bool = False,
                  draft: float | None = None, draft_scale: bool = False) -> FeatureModel:
    """Precompute a design on ``hull`` (numpy, once): ``moves`` :class:`ApexMove`, ``distributions``
    :class:`Distribution` (each feature curve in at most one), ``edits`` :class:`ContourEdit`, ``bows``
    :class:`BowAttachment` (their stem found at ``draft`` [m], default the hull's design draft: one eager
    evaluation of the parent), ``beam`` whether the beam is a parameter, ``draft_scale`` whether the draft is.
    Raises :class:`HullError` on an inconsistent design (fixed ends not on the apex line, …).

    Parameters
    ----------
    hull : FeatureHull
        The parent's contour lines and feature curves (:func:`load_parent`, :func:`extract_features`),
        lengths in m (x from the AP, y to port, z up from the baseline).
    moves : sequence of ApexMove
        Claim 5: apex lines that move between two fixed ends (parameters in m).
    distributions : sequence of Distribution
        Claim 7: feature points that slide along their curves (sine-mode amplitudes, dimensionless).
    edits : sequence of ContourEdit
        Contour-line edits (keel profile, flat of bottom/side, deck edge; amplitudes in m).
    bows : sequence of BowAttachment
        Bow attachments (JP2009-286166 claims 4–5; :mod:`hullopt.models._bow`; amplitudes in m).
    beam : bool
        Whether the beam is a parameter (every half-breadth scaled by 1 + s).
    draft_scale : bool
        Whether the draft is a parameter (every height and the draft scaled by 1 + s from the baseline;
        :meth:`FeatureModel.draft_factor`).
    draft : float or None
        The draft [m] the attachments' stem is found at; None: the hull's design draft.

    Returns
    -------
    FeatureModel
        A callable ``model(params) → Sections``, pure JAX (jit/grad/vmap); ``model.zeros()`` are the
        parameters of the parent.

    Examples
    --------
    Zero parameters rebuild the parent: the library's Wigley (L 100, B 10, T 6.25 m) keeps Cb 4/9:

    >>> import jax; jax.config.update("jax_enable_x64", True)
    >>> from hullopt.models import load_parent, feature_model, ApexMove
    >>> from hullopt.hydro import hydrostatics
    >>> model = feature_model(load_parent("wigley"), moves=[ApexMove(-1, 50, 80, 100, "smooth")])
    >>> cb = jax.jit(lambda p: hydrostatics(model(p), 6.25).cb)
    >>> round(float(cb(model.zeros())), 3)
    0.444
    """
    moves, distributions, edits = tuple(moves), tuple(distributions), tuple(edits)
    x = np.asarray(hull.x)
    base = _flatten(hull)
    mw = [_move_weights(hull, m) for m in moves]
    masks = []
    for d in distributions:
        if not (math.isfinite(d.x_a) and math.isfinite(d.x_b) and x[0] <= d.x_a < d.x_b <= x[-1]):
            raise HullError(f"distribution: need {x[0]:g} ≤ x_a < x_b ≤ {x[-1]:g} m, got {d.x_a:g}, {d.x_b:g}")
        if d.modes < 1:
            raise HullError(f"distribution: modes must be ≥ 1, got {d.modes}")
        masks.append(_dist_columns(hull, d.curves))
    if masks and np.max(np.sum(masks, axis=0)) > 1:
        raise HullError("distribution: a feature curve is in two groups; give each curve to one group")
    shifts = sorted((d.x_a, d.x_b) for d in distributions if d.curves == "stations")
    if any(b1 > a2 for (_, b1), (a2, _) in zip(shifts, shifts[1:])):
        raise HullError(f"distribution: station shifts {shifts} overlap; give each station to one shift")
    c = base.shape[1]
    chain = _chain(hull)
    bows = tuple(bows)
    plan = np.zeros((0, len(x)))
    if bows:
        t = hull.design_draft if draft is None else draft
        if t is None:
            raise HullError("bow attachment: the parent has no design draft; give the draft its stem is found at")
        stem = stem_station(hull.sections(), float(t))
        plan = np.array([attachment_plan(x, b, stem) for b in bows])
    return FeatureModel(
        hull=hull,
        base=base,
        chained=base @ chain,
        unchain=np.linalg.inv(chain),
        slopes=pchip_slopes(x, base @ chain),
        move_w=np.array([w for _, w in mw]).reshape(len(mw), len(x)),
        move_seg=tuple(s for s, _ in mw),
        dist_mask=np.array(masks).reshape(len(masks), c),
        dist_range=np.array([[d.x_a, d.x_b] for d in distributions], float).reshape(len(distributions), 2),
        edit_w=np.array([_edit_weights(hull, e) for e in edits]).reshape(len(edits), len(x), c),
        design=(moves, distributions, edits),
        bow_plan=plan,
        bow_band=np.array([[b.z_lo, b.z_hi, b.blend] for b in bows], float).reshape(len(bows), 3),
        bows=bows,
        beam_scale=bool(beam),
        draft_scale=bool(draft_scale),
    )


# ----------------------------------------------------------------------------------------------- checks


def design_margins(model: FeatureModel, params: FeatureParams) -> dict[str, Array]:
    """Smooth-enough margins (≥ 0 when valid, JAX, differentiable) an optimiser can bound:
    ``apex`` min over real segments of β and 1 − β (the apex inside its segment); ``aux`` the least gap
    between consecutive knots along each half, as a fraction of the half; ``warp`` 1 − Σ|c| per group.

    Parameters
    ----------
    model : FeatureModel
        The parent and its design (see :func:`feature_model`).
    params : FeatureParams
        The design parameters: ``apex (K, 2)`` [m], ``distribution (G, J)``, ``contour (E,)`` [m].

    Returns
    -------
    dict of str to Array
        ``"apex"`` and ``"aux"`` scalars (fractions, dimensionless), ``"warp"`` ``(G,)`` (dimensionless).
    """
    f = model.features(params)
    real = f.real
    beta = f.apex[..., 0]
    big = jnp.asarray(1.0, beta.dtype)
    apex = jnp.min(jnp.where(real, jnp.minimum(beta, 1.0 - beta), big))
    rho = f.aux[..., 0]  # (n, S, 2, J)
    knots = jnp.concatenate([jnp.zeros_like(rho[..., :1]), rho, jnp.ones_like(rho[..., :1])], -1)
    gaps = jnp.min(jnp.diff(knots, axis=-1), axis=(-1, -2))
    aux = jnp.min(jnp.where(real, gaps, big))
    warp = 1.0 - jnp.sum(jnp.abs(_used_modes(model, params)), -1) if params.distribution.size else jnp.ones(0)
    return {"apex": apex, "aux": aux, "warp": warp}


@eqx.filter_jit
def _evaluated(model: FeatureModel, params: FeatureParams) -> tuple[dict[str, Array], FeatureHull, Sections]:
    """The margins, the deformed feature hull and its sections, in one compiled program (one executable
    loaded from the compilation cache by a warm CLI call, where operation by operation took seconds)."""
    f = model.features(params)
    return design_margins(model, params), f, model.finish(f.sections(), params)


def check_design(model: FeatureModel, params: FeatureParams) -> Sections:
    """The deformed hull, or :class:`HullError` saying what is wrong: an apex outside its segment, a folded
    frame (knots out of order, a frame crossing itself or the centreline, feature lines crossing), a
    non-monotone distribution. Not for use under ``jit`` (it inspects values).

    Parameters
    ----------
    model : FeatureModel
        The parent and its design (see :func:`feature_model`).
    params : FeatureParams
        The design parameters: ``apex (K, 2)`` [m], ``distribution (G, J)``, ``contour (E,)`` [m].

    Returns
    -------
    Sections
        The deformed hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    """
    from shapely.geometry import LineString

    p = {k: np.asarray(v) for k, v in vars(params).items()}
    for name, shape in (("apex", (len(model.move_seg), 2)), ("contour", (model.edit_w.shape[0],)),
                        ("bow", (len(model.bows),)), ("beam", (int(model.beam_scale),)),
                        ("draft", (int(model.draft_scale),))):
        if p[name].shape != shape:
            raise HullError(f"parameters: {name} has shape {p[name].shape}, expected {shape}")
    if not all(np.all(np.isfinite(v)) for v in p.values()):
        raise HullError("parameters: every value must be a finite number")
    margins, f, sec = _evaluated(model, params)
    m = {k: np.asarray(v) for k, v in margins.items()}
    if m["warp"].size and m["warp"].min() <= 0:
        g = int(np.argmin(m["warp"]))
        raise HullError(f"distribution {g}: Σ|c| = {1 - m['warp'][g]:.3g} must stay below 1 (the warp would fold)")
    x = np.asarray(f.x)
    beta = np.asarray(f.apex[..., 0])
    real = np.asarray(f.real)
    bad = real & ((beta <= 0) | (beta >= 1))
    if bad.any():
        i, s = np.argwhere(bad)[0]
        raise HullError(f"the apex of segment {s} at x = {x[i]:g} m is outside its segment (β = {beta[i, s]:.3g}, "
                        "expected 0 < β < 1): reduce the apex move")
    if m["aux"] <= 0:
        raise HullError("an auxiliary apex passed its apex or inflection point: the deformation folds a frame")
    yz = np.asarray(sec.yz)
    floor = min(0.0, float(np.asarray(model.hull.sections().yz)[..., 0].min())) - 1e-3 * float(f.lpp)
    if yz[..., 0].min() < floor:
        i = int(np.argmin(yz[..., 0].min(-1)))
        raise HullError(f"the frame at x = {x[i]:g} m crosses the centreline (y < 0): the deformation folds it")
    for i in range(len(x)):
        pts = yz[i][np.concatenate([[True], np.hypot(*np.diff(yz[i], axis=0).T) > TINY_LENGTH])]
        if len(pts) > 3 and not LineString(pts).is_simple:
            raise HullError(f"the frame at x = {x[i]:g} m crosses itself (feature lines crossing or a folded "
                            "segment): reduce the deformation")
    return sec
