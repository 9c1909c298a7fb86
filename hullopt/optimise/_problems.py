"""Design problems: a hull model (parameters → Sections) composed with analyses into target residuals,
objectives and constraints — pure functions of the parameters, ready for the solvers.

Targets are normalised to order one (relative for sizes, absolute for coefficients and % Lpp) and each has a
tolerance in those units, so "met" means the same thing for every particular:

=================  ===================================  ==========================
name               residual                             default tolerance
=================  ===================================  ==========================
volume             (∇ − ∇*)/∇*                          5e-4 (0.05 %)
displacement       (Δ − Δ*)/Δ*                          5e-4
cb, cp, cm, cwp    c − c*                               1e-4
lcb_pct, lcf_pct   % Lpp from midship, forward +        0.01 (% Lpp)
kb                 (KB − KB*)/KB*                       1e-3
bwl, lwl           relative                             1e-4 (fixed main dimensions)
gm                 GM_T − GM* [m] (needs ``kg``)        0.01 m
bf                 Bf(head seas) − Bf*                  1e-4
=================  ===================================  ==========================

Constraints (:class:`Limits`) are inequalities ``g ≤ 0`` beside the targets, each normalised to order one and
met when ``g ≤ tol`` (default 1e-3): a measure (an objective or a particular) against a number or the parent's
value, ``q ≤ b`` as ``(q − b)/|b|``; every offset's half-breadth within a maximum, ``(y − y_max)/y_max``; and
no section below the waterline wider than its waterline half-breadth by more than the parent's section is
there, ``(y − w − a)/y_max``.
"""

from __future__ import annotations

import abc
from collections.abc import Callable
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.flatten_util import ravel_pytree
from jaxtyping import Array, ArrayLike, Float, PyTree

from ..geometry import Sections, region_volume, safe_div, section_integrals, section_necks
from ..hydro import Hydrostatics, hydrostatics
from ..waves import bluntness
from ._jaxopt import minimise_lbfgsb_traced
from ._objectives import Objective
from ._solvers import SolveResult, fit, fit_traced

class Target(eqx.Module):
    """A kind of target particular: its ``name`` (the config's key), whether its error is ``relative``
    ((a − a*)/a*) or absolute (a − a*, in its unit), its default tolerance ``tol`` (in those units) and the
    ``physical`` range (lo, hi) a target value must lie strictly within. Subclasses say how the achieved value
    is measured (:meth:`achieved`, :meth:`measure`) and whether it ``needs_kg``."""

    name: str = eqx.field(static=True)
    relative: bool = eqx.field(static=True)
    tol: float = eqx.field(static=True)
    physical: tuple[float, float] = eqx.field(static=True, default=(0.0, float("inf")))
    needs_kg: ClassVar[bool] = False

    @abc.abstractmethod
    def achieved(self, h: Hydrostatics, sections: Sections, kg=None, band: float = 0.0) -> Array:
        """The particular of the hull ``sections`` whose hydrostatics at its draft are ``h`` (SI; % Lpp for
        lcb_pct, lcf_pct), ``kg`` [m] where it ``needs_kg``, ``band`` [m] the waterlines' band of Bf."""

    @abc.abstractmethod
    def measure(self, sections: Sections, draft, kg=None, band: float = 0.0) -> Array:
        """The particular of the hull ``sections`` floating upright at ``draft`` [m] (as :meth:`achieved`)."""


class HydrostaticsTarget(Target):
    """A field ``name`` of :class:`~hullopt.hydro.Hydrostatics` (volume [m³], displacement [kg], kb, bwl, lwl
    [m], lcb_pct, lcf_pct [% Lpp]; coefficients dimensionless)."""

    def achieved(self, h: Hydrostatics, sections: Sections, kg=None, band: float = 0.0) -> Array:
        return getattr(h, self.name)

    def measure(self, sections: Sections, draft, kg=None, band: float = 0.0) -> Array:
        return getattr(hydrostatics(sections, draft), self.name)


class GMTarget(Target):
    """The transverse metacentric height GM_T = KM_T − KG [m], given KG [m above the baseline]."""

    needs_kg: ClassVar[bool] = True

    def achieved(self, h: Hydrostatics, sections: Sections, kg=None, band: float = 0.0) -> Array:
        return h.kmt - kg

    def measure(self, sections: Sections, draft, kg=None, band: float = 0.0) -> Array:
        if kg is None:
            raise ValueError(f"{self.name} needs kg")
        return self.achieved(hydrostatics(sections, draft), sections, kg)


class BluntnessTarget(Target):
    """The bluntness Bf of the waterline in head seas (dimensionless; :func:`hullopt.waves.bluntness`), or its mean
    over the waterlines within ``band`` [m] of the draft."""

    def achieved(self, h: Hydrostatics, sections: Sections, kg=None, band: float = 0.0) -> Array:
        return bluntness(sections, h.draft, band=band)

    def measure(self, sections: Sections, draft, kg=None, band: float = 0.0) -> Array:
        return bluntness(sections, draft, band=band)


TARGET_KINDS: dict[str, Target] = {t.name: t for t in (
    HydrostaticsTarget("volume", True, 5e-4), HydrostaticsTarget("displacement", True, 5e-4),
    HydrostaticsTarget("cb", False, 1e-4, (0.2, 1.0)), HydrostaticsTarget("cp", False, 1e-4, (0.3, 1.0)),
    HydrostaticsTarget("cm", False, 1e-4, (0.3, 1.0)), HydrostaticsTarget("cwp", False, 1e-4, (0.3, 1.0)),
    HydrostaticsTarget("lcb_pct", False, 0.01, (-15.0, 15.0)), HydrostaticsTarget("lcf_pct", False, 0.01, (-20.0, 20.0)),
    HydrostaticsTarget("kb", True, 1e-3), HydrostaticsTarget("bwl", True, 1e-4), HydrostaticsTarget("lwl", True, 1e-4),
    GMTarget("gm", False, 0.01), BluntnessTarget("bf", False, 1e-4, (0.0, 1.0)),
)}
"""The target kinds by name (the module's table), in the order of the table."""

TARGETS: dict[str, tuple[bool, float]] = {k: (t.relative, t.tol) for k, t in TARGET_KINDS.items()}
"""``{name: (relative?, default tolerance)}`` of :data:`TARGET_KINDS`."""
PHYSICAL = {k: t.physical for k, t in TARGET_KINDS.items() if t.physical != (0.0, float("inf"))}


class Targets(eqx.Module):
    """Target particulars: ``names`` (static) with ``values`` and ``tol`` (normalised units, see the module
    table); ``kg`` [m] for a GM target."""

    names: tuple[str, ...] = eqx.field(static=True)
    values: Float[ArrayLike, " t"]  # numpy as made (no JAX op), JAX under transforms
    tol: Float[ArrayLike, " t"]
    kg: Float[ArrayLike, ""] | None = None
    bf_band: float = eqx.field(static=True, default=0.0)  # m: the waterlines' band of a bf target


def make_targets(values: dict[str, float], tol: dict[str, float] | None = None, kg: float | None = None,
                 bf_band: float = 0.0) -> Targets:
    """Targets from ``{name: value}``; raises ``ValueError`` naming an unknown or unphysical target.

    Parameters
    ----------
    values : dict of str to float
        Target name (a key of ``TARGETS``) → value in SI (volume [m³], displacement [kg], kb, bwl, lwl, gm [m];
        lcb_pct, lcf_pct [% Lpp from midship, forward +]; coefficients and bf dimensionless).
    tol : dict of str to float or None
        Tolerances in the normalised units of the module's table, by target name; None or a missing name: the
        default.
    kg : float or None
        Height of the centre of gravity above the baseline [m]; needed for a ``gm`` target.
    bf_band : float
        A ``bf`` target's band of waterlines [m] (:func:`~hullopt.waves.bluntness`); 0: the draft's.

    Returns
    -------
    Targets
        ``names`` (t,) in the order of ``values``, ``values`` and ``tol`` (t,) float, ``kg``.

    Raises
    ------
    ValueError
        For an unknown or unphysical target, a ``gm`` target without ``kg``, or a tolerance for no target.
    """
    tol = tol or {}
    for k, v in values.items():
        if k not in TARGETS:
            raise ValueError(f"unknown target {k!r}; expected one of {', '.join(TARGETS)}")
        lo, hi = TARGET_KINDS[k].physical
        if not (lo < float(v) < hi):
            raise ValueError(f"target {k} = {v} is outside the physical range ({lo}, {hi})")
        if TARGET_KINDS[k].needs_kg and kg is None:
            raise ValueError(f"a {k} target needs kg")
    for k in tol:
        if k not in values:
            raise ValueError(f"tolerance for {k!r}, which is not a target")
    names = tuple(values)
    return Targets(
        names=names,
        values=np.array([float(values[k]) for k in names]),
        tol=np.array([float(tol.get(k, TARGET_KINDS[k].tol)) for k in names]),
        kg=None if kg is None else np.asarray(float(kg)),
        bf_band=float(bf_band),
    )


def achieved(h: Hydrostatics, sections: Sections, names: tuple[str, ...], kg=None, band: float = 0.0) -> Array:
    """The particulars ``names`` of a hull with hydrostatics ``h`` at its draft.

    Parameters
    ----------
    h : Hydrostatics
        Hydrostatics of the hull at one draft (scalar fields).
    sections : Sections
        The hull (for ``bf``).
    names : tuple of str
        Target names (keys of ``TARGETS``).
    kg : float or Array or None
        KG [m] above the baseline; needed for ``gm``.
    band : float
        The band of waterlines of ``bf`` [m] (0: the draft's).

    Returns
    -------
    Array
        (len(names),) float values in the units of :class:`~hullopt.hydro.Hydrostatics` (SI; % Lpp for
        lcb_pct, lcf_pct); GM_T [m] for ``gm``, Bf in head seas for ``bf``.
    """
    out = [TARGET_KINDS[k].achieved(h, sections, kg, band) for k in names]
    return jnp.stack(out) if out else jnp.zeros(0)


def target_errors(values, targets: Targets) -> Array:
    """The error of each target given its achieved ``values`` (:func:`achieved`), in the normalised units of the
    module's table (relative or absolute): what the solvers drive to zero and the run report shows; a target
    is met when ``|error| ≤ targets.tol``.

    Parameters
    ----------
    values : (t,) array_like
        Achieved values of ``targets.names``, in SI as :func:`achieved` returns them.
    targets : Targets
        The targets (:func:`make_targets`).

    Returns
    -------
    Array
        (t,) float errors: relative (dimensionless) or absolute (the target's unit) per the module's table.
    """
    a = jnp.asarray(values)
    rel = jnp.asarray([TARGET_KINDS[k].relative for k in targets.names], dtype=bool)
    # safe_div: a zero target (LCB amidships) must not poison the gradient
    return jnp.where(rel, safe_div(a, targets.values, rel) - 1.0, a - targets.values)


def target_residuals(sections: Sections, draft, targets: Targets) -> Array:
    """Normalised residuals of ``targets`` (order one; compare with ``targets.tol``).

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y to port, z up from the baseline).
    draft : float or Array
        Draft T [m above the baseline] (scalar).
    targets : Targets
        The targets (:func:`make_targets`).

    Returns
    -------
    Array
        (t,) float errors as :func:`target_errors` returns them.
    """
    h = hydrostatics(sections, draft)
    return target_errors(achieved(h, sections, targets.names, targets.kg, targets.bf_band), targets)


# ----------------------------------------------------------------------------------------------- the problem


class Particular(eqx.Module):
    """A particular of the upright hull as a measure, called like an objective: ``particular(sections, draft)``
    → the :class:`~hullopt.hydro.Hydrostatics` field ``name`` (SI: m, m², m³, kg, % Lpp; coefficients
    dimensionless), or the bluntness Bf (head seas) for ``"bf"``."""

    name: str = eqx.field(static=True)
    bf_band: float = eqx.field(static=True, default=0.0)  # m: Bf's band of waterlines

    def __call__(self, sections: Sections, draft) -> Array:
        target = TARGET_KINDS.get(self.name)
        if target is None:  # a hydrostatics field that is no target (wetted_surface, awp, …)
            return getattr(hydrostatics(sections, draft), self.name)
        return target.measure(sections, draft, band=self.bf_band)


class RegionVolume(eqx.Module):
    """The displaced volume [m³] of a region of the hull as a measure, called like an objective:
    ``region(sections, draft)`` → :func:`hullopt.geometry.region_volume`, the part forward of ``x_a`` and aft
    of ``x_b`` [m from the AP] below ``z_top`` [m above the baseline] and the waterline (a sonar dome's,
    a bulb's). The region's numbers are arrays (a run with other numbers reuses its programs); ``inf``
    (``-inf`` for ``x_a``) is no bound."""

    x_a: Float[ArrayLike, ""] = eqx.field(default_factory=lambda: np.asarray(-np.inf))
    x_b: Float[ArrayLike, ""] = eqx.field(default_factory=lambda: np.asarray(np.inf))
    z_top: Float[ArrayLike, ""] = eqx.field(default_factory=lambda: np.asarray(np.inf))
    unit: ClassVar[str] = "m³"

    def __call__(self, sections: Sections, draft) -> Array:
        return region_volume(sections, draft, self.x_a, self.x_b, self.z_top)


FROZEN = 0.01
"""m: how far a frozen station (:class:`Limits`) or any of its offsets may move."""

BULB_EXCESS = 0.02
"""A bulb's neck: a section under the waterline narrower than somewhere below it by more than this fraction of
the hull's largest half-breadth (:func:`bulb_stations`)."""

BULB_END = 0.15
"""A bulb lies within this fraction of the stations' span from either end (:func:`bulb_stations`)."""


def bulb_stations(sections: Sections, draft) -> Array:
    """Stations ``(n,)`` (1 or 0) of a bulb at either end: from the end to the station furthest from it,
    within :data:`BULB_END` of the span, whose section has a neck under the waterline — a point narrower than
    one below it by more than :data:`BULB_EXCESS` of the largest half-breadth — and one station more (the
    blend into the hull). A bulbous bow, or a stern bulb or stern-tube boss; none on a hull without one (a
    section that widens from the keel up has no neck).

    Parameters
    ----------
    sections : Sections
        The hull: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m, keel to deck].
    draft : float or Array, scalar
        Waterline height [m above the baseline].

    Returns
    -------
    Array, (n,)
        1.0 at a bulb's stations, 0.0 elsewhere (no gradient).
    """
    s = jax.lax.stop_gradient(sections)
    excess = section_necks(s, draft) > BULB_EXCESS * jnp.max(s.yz[..., 0])
    t = (s.x - s.x[0]) / (s.x[-1] - s.x[0])
    n, idx = s.x.shape[0], jnp.arange(s.x.shape[0])
    fore = jnp.min(jnp.where(excess & (t >= 1.0 - BULB_END), idx, n))  # n: none
    aft = jnp.max(jnp.where(excess & (t <= BULB_END), idx, -1))
    return (((idx >= fore - 1) & (fore < n)) | ((idx <= aft + 1) & (aft >= 0))).astype(float)


def frozen_stations(sections: Sections, draft, frozen: str | tuple) -> Array:
    """The stations that ``frozen`` holds.

    Parameters
    ----------
    sections : Sections
        The parent: ``x (n,)`` [m from the AP], ``yz (n, m, 2)`` [m].
    draft : float or Array, scalar
        Waterline height [m above the baseline].
    frozen : "auto" or tuple of (float, float)
        ``"auto"``: a bulb at either end (:func:`bulb_stations`); else ranges ``((x_a, x_b), …)`` [m from the
        AP] of the parent's stations.

    Returns
    -------
    Array, (n,)
        1.0 at a frozen station, 0.0 elsewhere.
    """
    if frozen == "auto":
        return bulb_stations(sections, draft)
    x = sections.x
    return jnp.any(jnp.stack([(x >= a) & (x <= b) for a, b in frozen]), axis=0).astype(float)


class Limits(eqx.Module):
    """Inequality constraints of a design (``g ≤ 0``, each normalised to order one; ``g ≤ tol`` is met).

    * ``measures[j](sections, draft)`` (an :class:`~hullopt.optimise.Objective` or a :class:`Particular`) at
      most (``sense[j] = +1``) or at least (``−1``) a bound: ``values[j]`` itself, or ``values[j]`` times the
      parent's value where ``relative[j]``; ``g = sense·(q − b)/|b|`` (elementwise for a measure with one value
      per station, each against the parent's at that station). A name given twice is one measure bounded on
      both sides (``"bwl" ≥ 0.95·parent`` and ``≤ 1.05·parent``): measured once, its group holds both sides' ``g``.
    * ``max_half_breadth`` [m] (``NaN``: the parent's largest half-breadth; ``None``: no limit): every
      offset's ``y`` at most it, ``g = (y − y_max)/y_max``, one per offset (n·m).
    * ``bulge`` (forbid): below the waterline no offset wider than its section's waterline half-breadth ``w``
      by more than the parent's is at the same offset (``a = max(0, y − w)`` of the parent: its bulb is
      allowed, a new bulge is not), ``g = (y − w − a)/y_ref`` with ``y_ref`` the parent's largest half-breadth;
      one per offset (n·m, ``−1`` above the waterline).

    * ``frozen``: stations that must not change — their position and every offset within :data:`FROZEN` of
      the parent's, ``g = |Δ|²/FROZEN² − 1`` per offset (n·m, ``−1`` elsewhere). ``"auto"``: a bulb at
      either end (:func:`bulb_stations`), ``"none"``, or ranges ``((x_a, x_b), …)`` [m from the AP] of the
      parent's stations.

    ``at_parent`` fixes the parent's values (bounds, ``y_max``, the allowance ``a``, the frozen stations); the
    design problems call it with the objective's scale (:func:`with_objective_scale`).
    """

    names: tuple[str, ...] = eqx.field(static=True, default=())
    measures: tuple[Callable, ...] = ()
    sense: Float[ArrayLike, " k"] = eqx.field(default_factory=lambda: np.zeros(0))
    values: Float[ArrayLike, " k"] = eqx.field(default_factory=lambda: np.zeros(0))
    relative: tuple[bool, ...] = eqx.field(static=True, default=())
    max_half_breadth: Float[ArrayLike, ""] | None = None
    bulge: bool = eqx.field(static=True, default=True)
    margins: Float[ArrayLike, " k"] | None = None  # added to a relative bound [SI]: "parent - 0.1"
    frozen: str | tuple = eqx.field(static=True, default="none")
    tol: float = eqx.field(static=True, default=1e-3)
    bounds: tuple | None = None  # resolved by at_parent: one scalar (or array, as its measure) per measure
    y_ref: Float[ArrayLike, ""] | None = None
    allowance: Float[ArrayLike, "n m"] | None = None
    held: Float[ArrayLike, " n"] | None = None  # resolved by at_parent: 1 where a station is frozen
    reference: Sections | None = None  # the parent, for the frozen stations

    def at_parent(self, sections: Sections, draft) -> Limits:
        """These limits with the parent's values resolved (``sections`` the parent at ``draft``)."""
        q = self._measured(sections, draft)
        values = jnp.asarray(self.values, float)
        margins = jnp.zeros_like(values) if self.margins is None else jnp.asarray(self.margins, float)
        # one bound per side; a measure may be an array (one value per station), bounded elementwise
        bounds = tuple(jnp.where(r, v * q[k] + o, v) for k, r, v, o in zip(self.names, self.relative, values, margins))
        y = sections.yz[..., 0]
        y_ref = jnp.max(y)
        y_max = None if self.max_half_breadth is None else \
            jnp.where(jnp.isnan(self.max_half_breadth), y_ref, self.max_half_breadth)
        allowance = jnp.maximum(self._excess(sections, draft), 0.0) if self.bulge else None
        held, reference = None, None
        if self.frozen != "none":
            held, reference = frozen_stations(sections, draft, self.frozen), jax.lax.stop_gradient(sections)
        return eqx.tree_at(lambda lim: (lim.bounds, lim.y_ref, lim.allowance, lim.max_half_breadth, lim.held,
                                        lim.reference), self,
                           (bounds, y_ref, allowance, y_max, held, reference), is_leaf=lambda v: v is None)

    def _measured(self, sections: Sections, draft) -> dict[str, Array]:
        """Each named measure's value, once a name (a two-sided bound names its measure twice)."""
        q = {}
        for name, m in zip(self.names, self.measures):
            if name not in q:
                q[name] = m(sections, draft)
        return q

    @staticmethod
    def _excess(sections: Sections, draft) -> Array:
        """``y − w`` of every offset below the waterline [m], ``−∞``-like (−1e3 m) above it."""
        w = section_integrals(sections, draft).width
        below = jax.lax.stop_gradient(sections.yz[..., 1] < draft)
        return jnp.where(below, sections.yz[..., 0] - w[:, None], -1e3)

    def groups(self, sections: Sections, draft) -> dict[str, Array]:
        """The normalised constraints by name: each measure's (a scalar, or its value per station; a measure
        bounded on both sides both sides' concatenated), ``"max_half_breadth"`` and ``"bulge"`` (each
        ``(n·m,)``), those there are."""
        out = {}
        q = self._measured(sections, draft)
        for name, s, b in zip(self.names, jnp.asarray(self.sense, float), self.bounds):
            g = s * safe_div(q[name] - b, jnp.abs(b))
            out[name] = jnp.concatenate([jnp.ravel(out[name]), jnp.ravel(g)]) if name in out else g
        if self.max_half_breadth is not None:
            out["max_half_breadth"] = (sections.yz[..., 0].ravel() - self.max_half_breadth) / self.y_ref
        if self.bulge:
            out["bulge"] = jnp.maximum((self._excess(sections, draft) - self.allowance) / self.y_ref, -1.0).ravel()
        if self.held is not None:
            moved = (sections.x - self.reference.x)[:, None] ** 2 + jnp.sum((sections.yz - self.reference.yz) ** 2, -1)
            out["frozen"] = jnp.where(self.held[:, None] > 0, moved / FROZEN**2 - 1.0, -1.0).ravel()
        return out

    def __call__(self, sections: Sections, draft) -> Array:
        g = [jnp.ravel(v) for v in self.groups(sections, draft).values()]
        return jnp.concatenate(g) if g else jnp.zeros(0)


class Design(eqx.Module):
    """A design problem: ``model(params) → Sections`` at ``draft`` [m] with ``targets`` to hold, an optional
    ``objective`` to minimise (an :class:`~hullopt.optimise.Objective`, scaled by ``objective_scale``, its value
    at the parent), a small penalty ``smoothness`` · |params / param_scale|² that keeps the deformation the least
    needed, and a fairness penalty ``fairness`` · U/U₀ (:func:`hullopt.fairing.unfairness`, U₀ =
    ``fairness_scale``, the parent's), and ``limits`` (:class:`Limits`, inequality constraints; the solvers
    resolve their parent values with :func:`with_objective_scale`).

    ``draft`` is the parent's; a model with a draft scale (a ``draft_factor(params)`` method, as
    :class:`~hullopt.models.FeatureModel` has) floats each design at ``draft · draft_factor(params)``
    (:meth:`draft_of`): its targets, objective and limits are evaluated there, and so should anything that measures
    a design (:meth:`hull` gives both)."""

    model: Callable[..., Sections]
    draft: Float[ArrayLike, ""]
    targets: Targets
    objective: Objective | None = None
    objective_scale: Float[ArrayLike, ""] = eqx.field(default_factory=lambda: np.asarray(1.0))
    smoothness: float = eqx.field(static=True, default=1e-6)
    param_scale: PyTree[Float[ArrayLike, "..."]] | None = None  # like the parameters
    fairness: float = eqx.field(static=True, default=0.0)
    fairness_scale: Float[ArrayLike, ""] = eqx.field(default_factory=lambda: np.asarray(1.0))
    limits: Limits | None = None

    def sections(self, params) -> Sections:
        return self.model(params)

    def draft_of(self, params):
        """The draft [m above the baseline] the design ``params`` floats at: ``draft`` times the model's
        ``draft_factor(params)`` where it has one (a draft scale), else ``draft``."""
        factor = getattr(self.model, "draft_factor", None)
        return jnp.asarray(self.draft if factor is None else self.draft * factor(params), dtype=float)

    def hull(self, params) -> tuple[Sections, Array]:
        """``(sections, draft)`` of the design ``params``: what every analysis of it takes."""
        return self.model(params), self.draft_of(params)

    def residuals(self, params, args=None) -> Array:
        """Target residuals in units of their tolerances (so every target weighs alike in the least-squares
        cost), followed by the smoothness residuals (tolerance: infinite)."""
        s, t = self.hull(params)
        r = target_residuals(s, t, self.targets) / self.targets.tol
        flat = ravel_pytree(self._scaled(params))[0]
        extra = [jnp.sqrt(self.fairness * self._unfairness(s) + 1e-30)[None]] if self.fairness else []
        return jnp.concatenate([r, jnp.sqrt(self.smoothness) * flat, *extra])

    def fit_tolerances(self, params) -> Array:
        n = ravel_pytree(params)[0].shape[0] + (1 if self.fairness else 0)
        return jnp.concatenate([jnp.ones_like(self.targets.tol), jnp.full(n, jnp.inf)])

    def constraints(self, params, args=None) -> Array:
        return target_residuals(*self.hull(params), self.targets)

    def inequalities(self, params, args=None) -> Array:
        """The limits' normalised inequalities ``g ≤ 0`` (empty without limits)."""
        return self._inequalities(*self.hull(params))

    def objective_value(self, params, args=None) -> Array:
        """The scaled objective plus the smoothness penalty (order one at the parent)."""
        return self._objective_value(params, *self.hull(params))

    def terms(self, params, args=None) -> tuple[Array, Array, Array]:
        """``(objective_value, constraints, inequalities)`` from one evaluation of the model: what a constrained
        solve needs at each point (three evaluations would be traced, differentiated and compiled three times)."""
        s, t = self.hull(params)
        return self._objective_value(params, s, t), target_residuals(s, t, self.targets), self._inequalities(s, t)

    def _objective_value(self, params, s: Sections, t) -> Array:
        flat = ravel_pytree(self._scaled(params))[0]
        value = self.objective(s, t) / self.objective_scale + self.smoothness * flat @ flat
        return value + self.fairness * self._unfairness(s) if self.fairness else value

    def _inequalities(self, s: Sections, t) -> Array:
        return jnp.zeros(0) if self.limits is None else self.limits(s, t)

    def objective_ratio(self, params, args=None) -> Array:
        """The objective alone, scaled by its value at the parent (1 there): what a run's convergence shows."""
        return self.objective(*self.hull(params)) / self.objective_scale

    def _unfairness(self, sections: Sections) -> Array:
        from ..fairing import unfairness

        return unfairness(sections) / self.fairness_scale

    def _scaled(self, params):
        if self.param_scale is None:
            return params
        return jax.tree.map(lambda p, s: p / s, params, self.param_scale)


def with_objective_scale(design: Design, params) -> Design:
    """The design with ``objective_scale`` (and ``fairness_scale``) set to their values for ``params``
    (the parent), so that both terms start at one.

    Parameters
    ----------
    design : Design
        The design problem.
    params : pytree of Array
        The parent's parameters.

    Returns
    -------
    Design
        A copy with ``objective_scale``, ``fairness_scale`` and the limits' parent values set (``design`` itself
        when it has no objective, fairness or limits).
    """
    from ..fairing import unfairness

    if design.objective is None and not design.fairness and design.limits is None:
        return design
    s, t = design.hull(params)
    if design.limits is not None:
        design = eqx.tree_at(lambda d: d.limits, design, design.limits.at_parent(s, t))
    if design.objective is not None:
        design = eqx.tree_at(lambda d: d.objective_scale, design, jnp.abs(design.objective(s, t)) + 1e-30)
    if design.fairness:
        design = eqx.tree_at(lambda d: d.fairness_scale, design, unfairness(s) + 1e-30)
    return design


def non_dominated(points: Array) -> Array:
    """Mask of the Pareto-optimal rows of ``points (k, 2)`` (both objectives minimised; NaN rows excluded).

    Parameters
    ----------
    points : (k, 2) array_like
        Objective values of k candidates, each minimised.

    Returns
    -------
    Array
        (k,) bool: the row is finite and no other row is at least as good in both and better in one.
    """
    p = jnp.asarray(points)
    ok = jnp.all(jnp.isfinite(p), axis=1)
    le = jnp.all(p[:, None, :] <= p[None, :, :], axis=-1)
    lt = jnp.any(p[:, None, :] < p[None, :, :], axis=-1)
    dominated = jnp.any(le & lt & ok[:, None], axis=0)
    return ok & ~dominated


FIT_METHODS = ("optimistix", "lbfgsb")
"""The solvers of a fit (:func:`solve_fit`'s ``method``, a run config's ``[solver] method``)."""


def solve_fit(design: Design, p0, lower, upper, *, traced: bool = False, method: str = "optimistix", **kw):
    """Auto-fit: meet the targets with the least deformation, minimising the sum of squares of
    :meth:`Design.residuals` (targets in units of their tolerances, plus the small smoothness term) within the
    bounds. ``method``: ``"optimistix"``, Levenberg–Marquardt in the bounded parameters' tanh change of
    variables (the bounds approached, never reached); ``"lbfgsb"``, jaxopt's L-BFGS-B with the bounds hard
    (:func:`~hullopt.optimise.minimise_lbfgsb_traced`; a parameter may end exactly on its bound). With
    ``traced`` the cost of each step is kept in ``history``; both ``vmap``.

    Parameters
    ----------
    design : Design
        The problem: ``design.model(params) → Sections`` at ``design.draft`` [m], its ``targets`` (SI, as
        :func:`make_targets` takes them) and tolerances.
    p0, lower, upper : pytree of Array
        Start and bounds of the parameters (same structure; ``lower < p0 < upper``, units of the model's
        parameters).
    traced : bool
        Keep the cost after each step in ``result.history``.
    method : {"optimistix", "lbfgsb"}
        The solver (:data:`FIT_METHODS`).
    **kw
        Passed to the solver: ``max_steps`` for both; ``rtol``, ``atol`` for ``"optimistix"``
        (:func:`~hullopt.optimise.fit`); ``gtol``, L-BFGS-B's tolerance on the projected gradient of the cost
        (default 1e-6), for ``"lbfgsb"``.

    Returns
    -------
    SolveResult
        ``params`` (like ``p0``), ``residuals`` (target − achieved, SI), ``max_violation`` (≤ 1: ``met``),
        ``objective``, ``solver_ok``, ``steps``, ``history`` and ``violation_history`` when traced ((max_steps
        + 1,), the cost Σ r² and the largest |target error| / tolerance at the start and after each step, NaN
        after the last).

    Raises
    ------
    ValueError
        If ``method`` is not one of :data:`FIT_METHODS`.

    Examples
    --------
    A Wigley hull whose beam is scaled by ``1 + p``: its volume scales by ``1 + p``, so the fit to 1.2 times the
    parent's volume is ``p = 0.2``:

    >>> import jax; jax.config.update("jax_enable_x64", True)
    >>> import jax.numpy as jnp
    >>> from hullopt.geometry import Sections
    >>> from hullopt.models import wigley
    >>> from hullopt.hydro import hydrostatics
    >>> from hullopt.optimise import Design, make_targets, solve_fit
    >>> hull = wigley(100, 10, 6.25, 10, n=21, m=21)
    >>> def model(p):
    ...     return Sections(hull.x, hull.yz * jnp.array([1.0 + p, 1.0]), hull.lpp)
    >>> v0 = float(jax.jit(hydrostatics)(hull, 6.25).volume)
    >>> design = Design(model=model, draft=6.25, targets=make_targets({"volume": 1.2 * v0}))
    >>> r = solve_fit(design, jnp.asarray(0.0), jnp.asarray(-0.5), jnp.asarray(0.5))
    >>> round(float(r.params), 4), bool(r.met)
    (0.2, True)
    """
    if method not in FIT_METHODS:
        raise ValueError(f"fit method {method!r}: expected one of {', '.join(FIT_METHODS)}")
    tol = design.fit_tolerances(p0)
    if method == "optimistix":
        return (fit_traced if traced else fit)(design.residuals, p0, lower, upper, tol=tol, **kw)
    max_steps, gtol = kw.pop("max_steps", 200), kw.pop("gtol", 1e-6)
    if kw:
        raise TypeError(f"solve_fit(method='lbfgsb') takes max_steps and gtol, not {', '.join(kw)}")

    def cost(p, args):
        r = design.residuals(p, args)
        return r @ r

    worst = lambda p: jnp.max(jnp.abs(design.residuals(p)) / tol)  # noqa: E731
    p, _, ok, steps, history, violations = minimise_lbfgsb_traced(cost, p0, lower, upper, tol=gtol,
                                                                   maxiter=max_steps, record=worst)
    r = design.residuals(p)
    viol = jnp.max(jnp.abs(r) / tol)
    return SolveResult(p, r, jnp.sum(r**2), viol, viol <= 1.0, ok, jnp.asarray(steps), history if traced else None,
                       violation_history=violations if traced else None)


MU0, GROWTH = 1.0, 4.0
"""The augmented Lagrangian's first penalty μ and its growth per round in :func:`solve_minimum`, for
constraints in units of their tolerances: μ = 1 holds the targets within a fraction of a tolerance from the
first round on the Wigley Pareto sweep (tests/data/pareto_wigley.toml), and a growth of 4 keeps the inner BFGS
problems well enough conditioned to converge (10 from μ = 10 stalled them at 2–10 tolerances)."""


def solve_minimum(design: Design, p0, lower, upper, **kw):
    """Minimise the objective with the targets held (augmented Lagrangian over BFGS, bounded).

    Parameters
    ----------
    design : Design
        The problem: ``design.model(params) → Sections`` at ``design.draft`` [m], its ``targets`` (SI, as
        :func:`make_targets` takes them) and tolerances, and the ``objective`` to minimise (scaled by its
        value at the parent).
    p0, lower, upper : pytree of Array
        Start and bounds of the parameters (same structure; ``lower < p0 < upper``, units of the model's
        parameters).
    **kw
        Passed to the solver (:func:`~hullopt.optimise.minimise_constrained`: ``max_steps``, ``rtol``,
        ``atol``, ``outer`` rounds; ``mu0`` and ``growth``, default :data:`MU0` and :data:`GROWTH`, for the
        constraints in units of their tolerances — the targets' ``|c|/tol`` and the limits' ``g/tol``).

    Returns
    -------
    SolveResult
        ``params`` (like ``p0``), ``residuals`` (target − achieved, SI), ``max_violation`` (≤ 1: ``met``),
        ``objective``, ``solver_ok``, ``steps``, ``history`` (per round).

    Examples
    --------
    A Wigley hull whose beam is scaled by ``1 + p``: its volume scales by ``1 + p``, so with the volume held
    at 1.2 times the parent's the minimum is ``p = 0.2`` (the target pins it):

    >>> import jax; jax.config.update("jax_enable_x64", True)
    >>> import jax.numpy as jnp
    >>> from hullopt.geometry import Sections
    >>> from hullopt.models import wigley
    >>> from hullopt.hydro import hydrostatics
    >>> from hullopt.optimise import Design, KAw, make_targets, solve_minimum
    >>> hull = wigley(100, 10, 6.25, 10, n=21, m=21)
    >>> def model(p):
    ...     return Sections(hull.x, hull.yz * jnp.array([1.0 + p, 1.0]), hull.lpp)
    >>> v0 = float(jax.jit(hydrostatics)(hull, 6.25).volume)
    >>> design = Design(model=model, draft=6.25, targets=make_targets({"volume": 1.2 * v0}),
    ...                 objective=KAw(speed=jnp.asarray(7.7)))
    >>> r = solve_minimum(design, jnp.asarray(0.0), jnp.asarray(-0.5), jnp.asarray(0.5))
    >>> round(float(r.params), 4), bool(r.met)
    (0.2, True)
    """
    from ._solvers import minimise_constrained

    # Constraints in units of their tolerances: the penalty μ/2·|c/tol|² then weighs a miss of one tolerance
    # alike for every target and against the objective (order one). Raw residuals (tolerances 1e-4 for Cb and
    # Bf) made μ = 10…10⁴ a negligible penalty: the first rounds left the targets by hundreds of tolerances,
    # and the multipliers had not caught up after the last round (issue 16: 3 of 4 Wigley Pareto designs missed).
    tol = jnp.asarray(design.targets.tol)
    tol_g = 1.0 if design.limits is None else design.limits.tol
    ineq = None if design.limits is None else (lambda p, args: design.inequalities(p, args) / tol_g)

    def terms(p, args):
        f, c, g = design.terms(p, args)
        return f, c / tol, g / tol_g

    kw = {"mu0": MU0, "growth": GROWTH, "record": design.objective_ratio} | kw
    r = minimise_constrained(design.objective_value, lambda p, args: design.constraints(p, args) / tol, p0, lower,
                             upper, inequalities=ineq, terms=terms, **kw)
    return eqx.tree_at(lambda res: res.residuals, r, r.residuals * tol)
