"""Automatic fairing of offsets, hullopt's own formulation (seed 001's text stops before it defines its
unfairness functionals): minimise an unfairness functional of :mod:`hullopt.fairing` over the offsets while
the hull keeps its character — bounded moves, fixed contour and flat lines, displacement and LCB held, no
section given an inflection.

A small design problem: the free offsets ``q`` are the parameters, bounded to ``y₀ ± b`` and to ``[0, max
y₀]`` (no negative offset, nothing wider than the table's widest; the solver's tanh change of variables), the
objective is

    ‖r(y)‖² / max(F₀, 1)  +  α · mean(((q − y₀)/b)²),

``r`` the residuals of the chosen measure on the offsets' Coons surface (``F₀`` its value on the given hull;
a value ≲ 1 counts as fair, so a fair hull is not pushed further) and ``α`` a small pull towards the given
offsets (so a fair hull stays put), with the constraints ``c = ((∇ − ∇₀)/(10⁻³ ∇₀), (LCB − LCB₀)/(5·10⁻⁴
Lpp))`` — displacement within 0.1 % and LCB within 0.05 % Lpp when ``|c| ≤ 1`` — and, for every frame line,
the inequalities ``V ≤ V₀ + 1/4`` (its smooth inflection count, :func:`hullopt.fairing.sign_variation`) and
``M ≤ M₀ + f²·depth`` (the size of its S-shapes, :func:`hullopt.fairing.mixed_curvature`; ``f`` the dead
band): a line may lose inflections or straighten, not gain them. A count alone let a given hair-line S grow
into a pinch of 0.35 m on the seed-003 table; an energy alone let one S become two. It is solved by
:func:`~hullopt.optimise.minimise_constrained` (an augmented Lagrangian over BFGS with a fixed number of
rounds, here with a constant penalty μ = 10): one jitted computation, ``vmap``-able over offsets.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..fairing import (
    RESIDUALS,
    count_inflections,
    floors,
    hull_knots,
    knot_weights,
    line_curvatures,
    mixed_curvature,
    sign_variation,
)
from ..geometry import Sections, coons_surface, longitudinal_integrals
from ..models import coons_sections
from ._solvers import SolveResult, minimise_constrained

VOLUME_TOL = 1e-3  # relative displacement tolerance
LCB_TOL = 5e-4  # LCB tolerance as a fraction of Lpp
MU = 10.0  # the augmented Lagrangian's penalty, constant over the rounds
V_TOL = 0.25  # a frame line's sign variation may exceed the given by a quarter of an inflection
AT_CAP = 0.99  # a move this close to the cap means the cap, not the measure, stopped it


def fixed_offsets(y, flat_rtol: float = 1e-6) -> np.ndarray:
    """Offsets that fairing must not move.

    Zero half-breadths (where a section has not begun), the end stations and the bottom and top waterlines
    (the contour: flat of bottom, deck line), and the flat of side (offsets within ``flat_rtol`` of the
    maximum half-breadth).

    Parameters
    ----------
    y : array_like, shape (s, w)
        Half-breadths [m] at stations × waterlines.
    flat_rtol : float, optional
        Relative distance from the maximum half-breadth within which an offset is on the flat of side.

    Returns
    -------
    numpy.ndarray of bool, shape (s, w)
        True where an offset is fixed.
    """
    y = np.asarray(y, dtype=np.float64)
    fixed = (y <= 0.0) | (y >= (1.0 - flat_rtol) * y.max())
    fixed[[0, -1], :] = True
    fixed[:, [0, -1]] = True
    return fixed


def aft_body_noise(x, y, sigma: float, seed: int = 0, aft: float = 0.35, lpp: float | None = None,
                   free=None) -> np.ndarray:
    """The seed's test case: offsets with Gaussian noise in the aft body (numpy; for tests and demos).

    Parameters
    ----------
    x : array_like, shape (s,)
        Stations [m from the AP].
    y : array_like, shape (s, w)
        Half-breadths [m].
    sigma : float
        Standard deviation of the noise [m], clipped at 3σ.
    seed : int, optional
        Seed of numpy's default generator.
    aft : float, optional
        The aft body is ``x < aft · lpp``.
    lpp : float, optional
        Length between perpendiculars [m]; default ``x[-1]``.
    free : array_like of bool, shape (s, w), optional
        The offsets that may change; default not :func:`fixed_offsets`.

    Returns
    -------
    numpy.ndarray, shape (s, w)
        ``y`` with the noise added on the free aft-body offsets; every offset stays ≥ half its value.
    """
    x, y = np.asarray(x, np.float64), np.asarray(y, np.float64)
    lpp = float(x[-1]) if lpp is None else float(lpp)
    free = ~fixed_offsets(y) if free is None else np.asarray(free, bool)
    where = free & (x[:, None] < aft * lpp)
    noise = np.clip(np.random.default_rng(seed).normal(0.0, sigma, y.shape), -3 * sigma, 3 * sigma)
    return np.where(where, np.maximum(y + noise, 0.5 * y), y)


@dataclass(frozen=True)
class FairResult:
    """Outcome of :func:`fair_offsets`. Offsets ``(s, w)`` [m]; volumes [m³]; LCB [m from the AP]; ``before``
    and ``after`` the measure (dimensionless); ``steps`` the BFGS steps of all rounds; ``converged``: the
    solver succeeded and displacement, LCB and the no-new-inflection constraint are met. ``bound`` the move
    cap [m]; ``inflections0``/``inflections``: inflections per frame line ``(s,)`` and per waterline ``(w,)``
    of the given and the faired table (:func:`hullopt.fairing.count_inflections`)."""

    y: np.ndarray
    y0: np.ndarray
    free: np.ndarray
    measure: str
    before: float
    after: float
    volume0: float
    volume: float
    lcb0: float
    lcb: float
    lpp: float
    steps: int
    converged: bool
    bound: float
    inflections0: tuple[np.ndarray, np.ndarray]
    inflections: tuple[np.ndarray, np.ndarray]

    @property
    def at_cap(self) -> np.ndarray:
        """``(s, w)`` bool: offsets whose move reached the cap (the cap, not fairness, decided them)."""
        return self.free & (np.abs(self.y - self.y0) >= AT_CAP * self.bound)

    @property
    def new_inflections(self) -> tuple[np.ndarray, np.ndarray]:
        """Frame lines ``(s,)`` and waterlines ``(w,)`` bool that have more inflections than given."""
        return tuple(a > b for a, b in zip(self.inflections, self.inflections0))

    @property
    def reduction(self) -> float:
        """Fraction by which the measure fell (1 = to zero)."""
        return 1.0 - self.after / self.before

    @property
    def volume_change(self) -> float:
        """Relative change of displacement."""
        return self.volume / self.volume0 - 1.0

    @property
    def lcb_shift_pct(self) -> float:
        """LCB shift [% Lpp]."""
        return 100.0 * (self.lcb - self.lcb0) / self.lpp

    @property
    def max_move(self) -> float:
        """Largest move of an offset [m]."""
        return float(np.max(np.abs(self.y - self.y0)))


class _Solved(eqx.Module):
    y: Float[Array, "s w"]
    result: SolveResult
    before: Float[Array, ""]
    after: Float[Array, ""]
    particulars0: Float[Array, " 2"]
    particulars: Float[Array, " 2"]


class _Frames(eqx.Module):
    """The given table's frame lines as the no-new-inflection constraints see them: interior hull knots,
    knot weights [m], the dead band [1/m], and per station the given sign variation ``V₀`` and mixed
    curvature ``M₀`` (:func:`hullopt.fairing.sign_variation`, :func:`hullopt.fairing.mixed_curvature`)."""

    knots: Array
    weights: Array
    floor: Array
    v0: Array
    m0: Array

    def measures(self, x, z, y, end):
        """``(V, M)`` per station, each ``(s,)``."""
        kappa = line_curvatures(x, z, y, end)[0]
        return (sign_variation(kappa, self.knots, self.floor, 1),
                mixed_curvature(kappa, self.knots, self.weights, self.floor, 1))

    def excess(self, x, z, y, end):
        """``((V − V₀)/V_TOL, (M − M₀)/(f²·depth))`` stacked, ``(2s,)``: ≤ 1 where a frame line turns both
        ways no more than given (no new crossing, no S-shape grown; ``f`` the dead band)."""
        v, m = self.measures(x, z, y, end)
        depth = z[-1] - z[0]
        return jnp.concatenate([(v - self.v0) / V_TOL, (m - self.m0) / (self.floor**2 * depth)])


def _frames(x, z, y0, end, call) -> _Frames:
    knots = hull_knots(y0)
    kappa = call("fairing-lines", line_curvatures, (x, z, y0), (end,))
    floor, knots = floors(*kappa, *knots)[0], knots[0]
    weights = np.broadcast_to(knot_weights(z), y0.shape)
    frames = _Frames(knots=jnp.asarray(knots), weights=jnp.asarray(weights), floor=jnp.asarray(floor),
                     v0=jnp.zeros(len(x)), m0=jnp.zeros(len(x)))
    v0, m0 = call("fairing-frames", _Frames.measures, (frames, x, z, y0), (end,))
    return eqx.tree_at(lambda f: (f.v0, f.m0), frames, (v0, m0))


def _jitted(name: str, fn: Callable, args: tuple, static: tuple):
    """``fn(*args, *static)`` compiled (``name`` unused: the signature of :func:`fair_offsets`' ``call``)."""
    return eqx.filter_jit(fn)(*args, *static)


def _solve(x, z, y0, idx, lower, upper, bound, lpp, draft, proximity, frames: _Frames, measure: str, end: str,
           to_sections: Callable | None, outer: int, max_steps: int, rtol: float) -> _Solved:
    """The fairing problem as one pure computation of the offsets ``y0`` (jit; vmap-able over ``y0``)."""
    residuals = RESIDUALS[measure]
    hull = y0 > 0.0  # hull patches of the given offsets: a constant of the problem
    if to_sections is None:
        def to_sections(yy):
            return coons_sections(coons_surface(x, z, yy, end), lpp, 41, 41)

    def offsets(q):
        return y0.ravel().at[idx].set(q).reshape(y0.shape)

    def unfair(yy):
        return residuals(coons_surface(x, z, yy, end), hull)

    def particulars(yy):
        li = longitudinal_integrals(to_sections(yy), draft)  # as hullopt.hydro.hydrostatics computes them
        return jnp.stack([li.volume, li.lcb])

    f0 = jnp.sum(unfair(y0) ** 2)
    p0 = particulars(y0)
    scale2 = jnp.maximum(f0, 1.0)  # F ≲ 1 is fair: no need to go further
    q0 = y0.ravel()[idx]

    def objective(q, args):
        r = unfair(offsets(q))
        return r @ r / scale2 + proximity * jnp.mean(((q - q0) / bound) ** 2)

    def constraints(q, args):
        v, lcb = particulars(offsets(q))
        return jnp.stack([(v - p0[0]) / (VOLUME_TOL * p0[0]), (lcb - p0[1]) / (LCB_TOL * lpp)])

    def no_new_inflections(q, args):
        return frames.excess(x, z, offsets(q), end)

    r = minimise_constrained(objective, constraints, q0, lower, upper, inequalities=no_new_inflections,
                             outer=outer, mu0=MU, growth=1.0, rtol=rtol, atol=rtol, max_steps=max_steps)
    yy = offsets(r.params)
    return _Solved(y=yy, result=r, before=f0, after=jnp.sum(unfair(yy) ** 2), particulars0=p0,
                   particulars=particulars(yy))


def fair_offsets(
    x, z, y, lpp: float, draft: float, measure: str = "knots", *,
    free=None, max_move: float | None = None, proximity: float = 1e-3,
    to_sections: Callable[[jax.Array], Sections] | None = None,
    end: str = "not-a-knot", max_steps: int = 2000, rtol: float = 1e-7, outer: int = 6,
    call: Callable | None = None,
) -> FairResult:
    """Fair an offset table: minimise an unfairness measure with displacement and LCB held.

    The measure is taken on the offsets' Coons surface (:func:`hullopt.geometry.coons_surface`, spline ends
    ``end``); displacement (0.1 %) and LCB (0.05 % Lpp) are held at ``draft`` (see the module docstring).
    The solve is :func:`~hullopt.optimise.minimise_constrained`: ``outer`` augmented-Lagrangian rounds of
    at most ``max_steps`` BFGS steps, jitted as one computation.

    Parameters
    ----------
    x : array_like, shape (s,)
        Stations [m from the AP], increasing.
    z : array_like, shape (w,)
        Waterlines [m above the baseline], increasing.
    y : array_like, shape (s, w)
        Half-breadths [m] (≥ 0; zero where a section has not begun).
    lpp : float
        Length between perpendiculars [m].
    draft : float
        Draft at which displacement and LCB are held [m].
    measure : str, optional
        ``"knots"``, ``"lines"``, ``"jumps"`` or ``"mean"`` (:data:`hullopt.fairing.RESIDUALS`).
    free : array_like of bool, shape (s, w), optional
        The offsets that may move; default not :func:`fixed_offsets`.
    max_move : float, optional
        Bound on each move [m]; default 5 % of the largest half-breadth.
    proximity : float, optional
        Weight α of the pull towards the given offsets.
    to_sections : callable, optional
        The hull model ``offsets (s, w) → Sections`` for the hydrostatics; default the Coons surface sampled
        on 41 × 41 points (:func:`hullopt.models.coons_sections`).
    end : str, optional
        Spline end condition of the surface, ``"not-a-knot"`` or ``"natural"``.
    max_steps : int, optional
        BFGS steps per round.
    rtol : float, optional
        BFGS relative and absolute tolerance.
    outer : int, optional
        Augmented-Lagrangian rounds.
    call : callable, optional
        How the compiled parts run: ``call(name, fn, args, static)`` returns ``fn(*args, *static)`` for a pure
        ``fn``, ``args`` a pytree of arrays; default ``eqx.filter_jit``. The CLI passes
        :func:`hullopt.study.cached_call` (with its ``key``), so that a warm call traces nothing.

    Returns
    -------
    FairResult
        The faired offsets and the measure, displacement and LCB before and after.
    """
    if measure not in RESIDUALS:
        raise ValueError(f"unknown unfairness measure {measure!r}; expected one of {', '.join(RESIDUALS)}")
    x, z, y0 = (np.asarray(a, np.float64) for a in (x, z, y))
    free = ~fixed_offsets(y0) if free is None else np.asarray(free, bool)
    if not free.any():
        raise ValueError("no free offsets to fair (all are fixed)")
    bound = float(0.05 * y0.max() if max_move is None else max_move)
    idx = np.flatnonzero(free)
    q0 = y0.ravel()[idx]
    # no offset below zero or beyond the table's widest: fairing must not widen the ship
    lower, upper = np.maximum(q0 - bound, 0.0), np.minimum(q0 + bound, y0.max())
    call = call or _jitted
    xj, zj, yj = jnp.asarray(x), jnp.asarray(z), jnp.asarray(y0)
    args = (xj, zj, yj, jnp.asarray(idx), jnp.asarray(lower), jnp.asarray(upper), jnp.asarray(bound),
            jnp.asarray(float(lpp)), jnp.asarray(float(draft)), jnp.asarray(float(proximity)),
            _frames(xj, zj, yj, end, call))
    s = jax.device_get(call("fairing", _solve, args, (measure, end, to_sections, outer, max_steps, rtol)))
    (v0, lcb0), (v, lcb) = (float(a) for a in s.particulars0), (float(a) for a in s.particulars)
    yy = np.asarray(s.y)
    return FairResult(
        y=yy, y0=y0, free=free, measure=measure, before=float(s.before), after=float(s.after),
        volume0=v0, volume=v, lcb0=lcb0, lcb=lcb, lpp=float(lpp), steps=int(s.result.steps),
        converged=bool(s.result.solver_ok & s.result.met), bound=bound,
        inflections0=count_inflections(x, z, y0, y0, end), inflections=count_inflections(x, z, yy, y0, end),
    )

