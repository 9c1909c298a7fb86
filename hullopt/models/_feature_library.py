"""Parents for the feature-curve hull: extraction from any sections, generation without a parent
(embodiments 2 and 3), and the recipes of the library's parents (``hullopt/data/parents/*.json``).

The library files are made once by :func:`build_library` (the DTC reads the repository's
``examples/hulls``); at run time only the
JSON files are read. Recipes:

* ``dtc`` — the Duisburg Test Case container ship (el Moctar et al. 2012), sliced at 61 stations × 96 points,
  design draft 14.5 m, two levels of auxiliary apexes beyond the patent's (``level = 3``: a single auxiliary
  apex per half cannot hold the long straight flare of its forebody to 0.5 % of B; at ``level = 2`` ∇ is
  0.05 % short). Rebuilt (61 × 163 points) it holds the sliced mesh's ∇ to 0.003 % and LCB to 0.001 % Lpp
  at 14.5 m;
* ``tanker`` — a full, tanker-like form generated from principal dimensions (Lpp 320 m, B 58 m, D 30 m,
  T 20.8 m, the KVLCC2's) and a sectional-area curve with a parallel midbody (:func:`generate_hull`);
* ``wigley`` — the analytic Wigley hull (L 100 m, B 10 m, T 6.25 m, D 10 m);
* ``seed003`` — the seed-003 offset table (its stated assumptions: Lpp 95 m, waterlines 0.8 m apart).

The analytic and generated parents (``wigley``, ``seed003``, ``tanker``) keep their flats as first extracted
(``cut_tol = inf``): the example configs' targets are their particulars.

A user's hull (a mesh, an offsets table) is extracted by :func:`extract_faithful`, which raises the level of
auxiliary apexes until the rebuilt hull holds ∇ and LCB (:data:`FAITHFUL`).
"""

from __future__ import annotations

import math
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array

from .._types import Draft
from ..errors import HullError
from ..geometry import Sections, longitudinal_integrals, wetted_surface
from ._feature_extract import extract_features
from ._features import PARENTS_DIR, FeatureHull, feature_hull, save_features


def extract_parent(sections: Sections, name: str = "hull", design_draft: float | None = None, level: int = 2,
                   q: int = 2, **kw) -> FeatureHull:
    """Contour lines and feature curves of ``sections`` (see :func:`extract_features` for ``kw``).

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    name : str
        The parent's name ("hull" by default).
    design_draft : float, optional
        Design draft [m above the baseline]; ``None``: unknown.
    level : int
        Levels of auxiliary apexes (2 by default).
    q : int
        Samples per knot interval when the frames are rebuilt (2 by default).
    **kw
        ``flat_tol``, ``lobe_tol``, ``smoothing``, ``dense``, ``cut_tol`` of :func:`extract_features`.

    Returns
    -------
    FeatureHull
        The parent's contour lines and feature curves (lengths in m).
    """
    f = extract_features(np.asarray(sections.x), np.asarray(sections.yz), float(sections.lpp), level=level, **kw)
    return feature_hull(f, name, design_draft, q)


#: How a parent from a user's hull is extracted (:func:`extract_faithful`): smoothing λ, the levels of
#: auxiliary apexes tried in turn, and the fidelity asked of the rebuilt hull against its source sections
#: (relative ∇ and LCB in fractions of Lpp) at the drafts ``fractions`` of the depth and the design draft.
FAITHFUL = dict(smoothing=1e-7, levels=(2, 3, 4), tol_volume=5e-4, tol_lcb=1e-4, fractions=(0.2, 0.4, 0.6, 0.8, 0.95))


def extraction_error(source: Sections, hull: FeatureHull, drafts) -> np.ndarray:
    """``(k, 2)`` errors of the rebuilt ``hull`` (:meth:`FeatureHull.sections`) against its ``source``
    sections at each draft [m]: relative displacement volume ∇₁/∇₀ − 1 and LCB shift as a fraction of Lpp
    (both hulls integrated on their own stations by Simpson's rule)."""
    zs = np.asarray(drafts, np.float64).reshape(-1)
    (v0, l0), (v1, l1) = (tuple(map(np.asarray, _volume_lcb(h, zs))) for h in (source, _rebuild(hull)))
    return np.stack([v1 / v0 - 1.0, (l1 - l0) / float(source.lpp)], -1)


@eqx.filter_jit
def _rebuild(hull: FeatureHull) -> Sections:
    return hull.sections()


@eqx.filter_jit
def _wetted(s: Sections, draft: Draft) -> Array:
    return wetted_surface(s, jnp.asarray(draft, dtype=s.yz.dtype))


@eqx.filter_jit
def _volume_lcb(s: Sections, zs) -> tuple[Array, Array]:
    """∇ [m³, both sides] and LCB [m from the AP] of ``s`` at the drafts ``zs (k,)``: the kernel's
    :func:`~hullopt.geometry.longitudinal_integrals` (one program per hull shape)."""
    li = jax.vmap(lambda t: longitudinal_integrals(s, t))(jnp.asarray(zs))
    return li.volume, li.lcb


def extract_faithful(sections: Sections, name: str = "hull", design_draft: float | None = None,
                     **settings) -> tuple[FeatureHull, dict]:
    """Extract a parent that holds its source: the cheapest level of auxiliary apexes (``FAITHFUL["levels"]``
    in turn) whose rebuilt hull matches ``sections`` within ``tol_volume`` in ∇ and ``tol_lcb`` (fraction of
    Lpp) in LCB at the drafts ``fractions`` of the depth above the keel and at ``design_draft`` [m] when given.
    If no level meets them, the most faithful one is kept.

    Parameters
    ----------
    sections : Sections
        The source hull.
    name : str
        The parent's name.
    design_draft : float, optional
        Design draft [m above the baseline], also checked when given.
    **settings
        Overrides of :data:`FAITHFUL`.

    Returns
    -------
    tuple of (FeatureHull, dict)
        The hull and a report: ``level``, ``drafts`` [m], ``volume_error`` (relative) and ``lcb_error``
        (fraction of Lpp), the worst over the drafts, ``met``, the tolerances ``tol_volume`` and ``tol_lcb``,
        and with ``design_draft`` the rebuilt hull's wetted surface against the source's there,
        ``wetted_surface_error`` (relative, signed: how far a run's particulars, the model's, are from the
        file's).
    """
    cfg = {**FAITHFUL, **settings}
    yz = np.asarray(sections.yz)
    z_lo, z_hi = float(yz[..., 1].min()), float(yz[..., 1].max())
    drafts = [z_lo + f * (z_hi - z_lo) for f in cfg["fractions"]]
    if design_draft is not None and z_lo < design_draft < z_hi:
        drafts.append(float(design_draft))
    best = None
    for level in cfg["levels"]:
        hull = extract_parent(sections, name, design_draft, level=level, smoothing=cfg["smoothing"])
        err = np.abs(extraction_error(sections, hull, drafts)).max(0)
        score = max(err[0] / cfg["tol_volume"], err[1] / cfg["tol_lcb"])
        if best is None or score < best[0]:
            best = (score, hull, level, err)
        if score <= 1.0:
            break
    score, hull, level, err = best
    report = {"level": level, "drafts": drafts, "volume_error": float(err[0]), "lcb_error": float(err[1]),
              "met": bool(score <= 1.0), "tol_volume": float(cfg["tol_volume"]), "tol_lcb": float(cfg["tol_lcb"])}
    if design_draft is not None and z_lo < design_draft < z_hi:
        s0, s1 = float(_wetted(sections, design_draft)), float(_wetted(_rebuild(hull), design_draft))
        report["wetted_surface_error"] = s1 / s0 - 1.0 if s0 > 0 else 0.0
    return hull, report


def generate_hull(lpp: float, breadth: float, depth: float, draft: float, parallel: tuple[float, float] = (0.3, 0.65),
                  entrance: float = 2.2, run: float = 1.8, bilge_radius: float = 3.0, n: int = 61, m: int = 64,
                  **extract_kw) -> FeatureHull:
    """A hull from principal dimensions and a sectional-area curve, with no parent (seed 000, embodiment 2).

    The target sectional-area curve (the Cp curve) is 1 on the parallel midbody ``parallel`` (fractions of
    Lpp from the AP) and ``1 − ξ^entrance`` / ``1 − ξ^run`` towards the FP / AP (ξ from the midbody's end);
    times the midship area ``B·T − (4 − π)·r²/2``. Each frame is a flat of bottom, an elliptic bilge and a
    vertical flat of side to the deck: at full breadth the flat of bottom shrinks to meet the target area;
    where it is gone the breadth does (so the contour lines — flat of bottom, flat of side, deck side — follow
    from the Cp curve). The frames are then read as feature curves like any parent's.

    Parameters
    ----------
    lpp, breadth, depth, draft : float
        Length between perpendiculars, breadth, depth and design draft [m], positive, ``draft < depth``.
    parallel : tuple of float
        Aft and forward ends of the parallel midbody, fractions of Lpp from the AP, ``0 < a ≤ b < 1``.
    entrance, run : float
        Exponents of the sectional-area curve forward and aft of the midbody (2.2 and 1.8 by default).
    bilge_radius : float
        Midship bilge radius [m], below the draft and half the breadth (3 by default).
    n : int
        Equally spaced stations from the AP to the FP (61 by default).
    m : int
        Points per generated half-section (64 by default).
    **extract_kw
        Passed to :func:`extract_parent` (``smoothing`` 1e-9 by default).

    Returns
    -------
    FeatureHull
        Named "generated", ``design_draft = draft``; lengths in m.
    """
    for k, v in dict(lpp=lpp, breadth=breadth, depth=depth, draft=draft, bilge_radius=bilge_radius).items():
        if not (math.isfinite(v) and v > 0):
            raise HullError(f"generate: {k} must be a positive number, got {v}")
    if not draft < depth:
        raise HullError(f"generate: draft {draft:g} m must be below the depth {depth:g} m")
    if not 0 < parallel[0] <= parallel[1] < 1:
        raise HullError(f"generate: parallel midbody {parallel} must be fractions 0 < a ≤ b < 1 of Lpp")
    if not bilge_radius < min(draft, breadth / 2):
        raise HullError(f"generate: bilge_radius {bilge_radius:g} m must be below the draft and half the breadth")
    b0, r, t = breadth / 2, bilge_radius, draft
    k = 1.0 - math.pi / 4.0
    x = np.linspace(0.0, lpp, n)
    u = x / lpp
    xi_f = np.clip((u - parallel[1]) / (1 - parallel[1]), 0, 1)
    xi_a = np.clip((parallel[0] - u) / parallel[0], 0, 1)
    a = (1 - xi_f**entrance) * (1 - xi_a**run)
    half_area = a * (b0 * t - k * r * r)
    yz = np.zeros((n, m, 2))
    for i in range(n):
        zf = r + (t - r) * (1 - a[i])  # the bilge rises towards the ends
        yf = b0 - (b0 * t - half_area[i]) / (zf * k) if zf > 0 else 0.0
        b = b0
        if yf < 0:  # no flat of bottom left: narrow the frame instead
            yf, b = 0.0, half_area[i] / (t - zf * k)
        ry = b - yf
        th = np.linspace(0, np.pi / 2, m - 3)
        bilge = np.column_stack([yf + ry * np.sin(th), zf * (1 - np.cos(th))])
        yz[i] = np.vstack([[0.0, 0.0], bilge, [b, 0.5 * (zf + depth)], [b, depth]])[: m]
    sec = Sections(x=jnp.asarray(x), yz=jnp.asarray(yz), lpp=jnp.asarray(float(lpp)))
    extract_kw.setdefault("smoothing", 1e-9)
    return extract_parent(sec, "generated", draft, **extract_kw)




def dtc_sections(hulls: Path) -> Sections:
    """The DTC sliced as its recipe says, from ``hulls/DTC-scaled.stl.gz`` (the repository's ``examples/hulls``)."""
    from ..models import MeshTransform, read_mesh, slice_mesh

    mesh = read_mesh(hulls / "DTC-scaled.stl.gz", MeshTransform(scale=59.407))
    return slice_mesh(mesh, 355.0, 61, 96)


RECIPES = {
    "dtc": dict(level=3, q=2, smoothing=1e-7, design_draft=14.5,
                source="DTC (el Moctar, Shigunov & Zorn 2012), OpenFOAM DTC-scaled.stl.gz ×59.407, 61 stations"),
    "tanker": dict(source="generated: Lpp 320, B 58, D 30, T 20.8 m, parallel midbody 0.3–0.65 Lpp"),
    "wigley": dict(level=2, q=2, smoothing=1e-9, design_draft=6.25, cut_tol=math.inf,
                   source="Wigley hull L 100, B 10, T 6.25, D 10 m"),
    "seed003": dict(level=2, q=2, smoothing=1e-9, design_draft=None, cut_tol=math.inf,
                    source="seed 003 Table 1 (assumed Lpp 95 m, waterlines 0.8 m), spline surface 41 × 41"),
}


def recipe_sections(name: str, hulls: Path | None = None) -> Sections:
    """The parent sections a library recipe extracts from."""
    from ._builtins import wigley
    from ._offsets import offsets_to_sections, read_offsets

    if name == "dtc":
        if hulls is None:
            raise HullError("the dtc recipe needs the folder of example hulls (examples/hulls)")
        return dtc_sections(hulls)
    if name == "wigley":
        return wigley(100.0, 10.0, 6.25, 10.0, n=41, m=41)
    if name == "seed003":
        table = read_offsets(Path(__file__).resolve().parents[1] / "data" / "offsets" / "seed003_table1.csv")
        return offsets_to_sections(table, 41, 41)
    raise HullError(f"no sections for recipe {name!r}")


def build_parent(name: str, hulls: Path | None = None) -> FeatureHull:
    """Make a library parent from its recipe (numpy; the DTC reads ``hulls``)."""
    r = dict(RECIPES[name])
    r.pop("source")
    if name == "tanker":
        h = generate_hull(320.0, 58.0, 30.0, 20.8, cut_tol=math.inf)
        return feature_hull(_arrays(h), "tanker", 20.8, h.q)
    draft = r.pop("design_draft")
    return extract_parent(recipe_sections(name, hulls), name, draft, **r)


def _arrays(h: FeatureHull) -> dict:
    return {**{k: np.asarray(getattr(h, k)) for k in ("x", "keel", "deck", "ends", "apex", "aux", "real")},
            "lpp": float(h.lpp)}


def build_library(hulls: Path, out: Path = PARENTS_DIR) -> list[Path]:
    """Write every library parent to ``out`` (run once; ``python -m hullopt.models._feature_library``)."""
    out.mkdir(parents=True, exist_ok=True)
    return [save_features(build_parent(k, hulls), out / f"{k}.json", source=RECIPES[k]["source"]) for k in RECIPES]


if __name__ == "__main__":  # pragma: no cover - the one-off build of the package data
    import jax

    jax.config.update("jax_enable_x64", True)
    for p in build_library(Path(__file__).resolve().parents[2] / "examples" / "hulls"):
        print("wrote", p)
