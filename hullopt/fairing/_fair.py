"""Automatic fairing, hullopt's own formulation (seed 001's text stops before it defines its unfairness
functionals): minimise an unfairness functional over the offsets while the hull
keeps its character — bounded moves, fixed contour and flat lines, displacement and LCB held.

This composes the Coons surface and the hydrostatics (a small design problem of its own): the offsets
are the parameters, ``y = y₀ + b·tanh(p)`` on the free offsets (each move bounded by ``b``, smoothly),
and the solver minimises

    ‖r(y)‖² / max(F₀, 1)  +  α · mean((δ/b)²)  +  (μ/2) ‖c + λ/μ‖²,

with BFGS (optimistix): ``r`` the residuals of the chosen measure (``F₀`` its value on the given hull; a
value ≲ 1 counts as fair, so a fair hull is not pushed further), ``α`` a small pull towards
the given offsets (so a fair hull stays put), and an augmented Lagrangian on the two constraints
``c = ((∇ − ∇₀)/(10⁻³ ∇₀), (LCB − LCB₀)/(5·10⁻⁴ Lpp))`` — i.e. displacement within 0.1 % and LCB within
0.05 % Lpp when ``|c| ≤ 1`` — with the multipliers ``λ`` updated between solves until ``|c| ≤ 1/2``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx

from ..geometry import Sections, coons_surface, longitudinal_integrals
from ..models import coons_sections
from ._unfairness import RESIDUALS

VOLUME_TOL = 1e-3  # relative displacement tolerance
LCB_TOL = 5e-4  # LCB tolerance as a fraction of Lpp


def fixed_offsets(y, flat_rtol: float = 1e-6) -> np.ndarray:
    """Offsets that fairing must not move, ``(s, w)`` bool: zero half-breadths (where a section has not
    begun), the end stations and the bottom and top waterlines (the contour: flat of bottom, deck line),
    and the flat of side (offsets within ``flat_rtol`` of the maximum half-breadth)."""
    y = np.asarray(y, dtype=np.float64)
    fixed = (y <= 0.0) | (y >= (1.0 - flat_rtol) * y.max())
    fixed[[0, -1], :] = True
    fixed[:, [0, -1]] = True
    return fixed


def aft_body_noise(x, y, sigma: float, seed: int = 0, aft: float = 0.35, lpp: float | None = None,
                   free=None) -> np.ndarray:
    """The seed's test case: ``y`` with Gaussian noise (standard deviation ``sigma`` [m], clipped at 3σ)
    on the free offsets of the aft body (``x < aft · Lpp``); offsets stay > 0. Numpy; for tests and demos."""
    x, y = np.asarray(x, np.float64), np.asarray(y, np.float64)
    lpp = float(x[-1]) if lpp is None else float(lpp)
    free = ~fixed_offsets(y) if free is None else np.asarray(free, bool)
    where = free & (x[:, None] < aft * lpp)
    noise = np.clip(np.random.default_rng(seed).normal(0.0, sigma, y.shape), -3 * sigma, 3 * sigma)
    return np.where(where, np.maximum(y + noise, 0.5 * y), y)


@dataclass(frozen=True)
class FairResult:
    """Outcome of :func:`fair_offsets`. Offsets ``(s, w)`` [m]; volumes [m³]; LCB [m from the AP]."""

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
        return float(np.max(np.abs(self.y - self.y0)))


def fair_offsets(
    x, z, y, lpp: float, draft: float, measure: str = "knots", *,
    free=None, max_move: float | None = None, proximity: float = 1e-3,
    to_sections: Callable[[jax.Array], Sections] | None = None,
    end: str = "not-a-knot", max_steps: int = 2000, rtol: float = 1e-7, outer: int = 6,
) -> FairResult:
    """Fair the offsets ``y (s, w)`` [m] (stations ``x (s,)``, waterlines ``z (w,)`` [m]) by minimising
    the unfairness ``measure`` (``"knots"``, ``"lines"``, ``"jumps"``, ``"mean"``; see
    :mod:`._unfairness`) of their Coons surface (spline ends ``end``), holding
    displacement (0.1 %) and LCB (0.05 % Lpp) at ``draft`` [m] (see the module docstring).

    ``free (s, w)`` bool: the offsets that may move (default: not :func:`fixed_offsets`); ``max_move``
    [m]: bound on each move (default 5 % of the largest half-breadth); ``proximity``: weight α of the
    pull towards the given offsets; ``to_sections``: the hull model ``offsets → Sections`` used for the
    hydrostatics (default: the Coons surface sampled on 41 × 41 points).
    """
    if measure not in RESIDUALS:
        raise ValueError(f"unknown unfairness measure {measure!r}; expected one of {', '.join(RESIDUALS)}")
    x, z, y0 = (np.asarray(a, np.float64) for a in (x, z, y))
    free = ~fixed_offsets(y0) if free is None else np.asarray(free, bool)
    if not free.any():
        raise ValueError("no free offsets to fair (all are fixed)")
    bound = float(0.05 * y0.max() if max_move is None else max_move)
    hull = jnp.asarray(y0 > 0.0)  # hull patches of the parent: a constant of the problem
    idx = jnp.asarray(np.flatnonzero(free))
    xj, zj, yj = jnp.asarray(x), jnp.asarray(z), jnp.asarray(y0)
    if to_sections is None:
        def to_sections(yy):
            return coons_sections(coons_surface(xj, zj, yy, end), lpp, 41, 41)
    residuals = RESIDUALS[measure]

    def offsets(p):
        return yj.ravel().at[idx].add(bound * jnp.tanh(p)).reshape(y0.shape)

    def particulars(yy):
        li = longitudinal_integrals(to_sections(yy), draft)  # as hullopt.hydro.hydrostatics computes them
        return li.volume, li.lcb

    def unfair(yy):
        r = residuals(coons_surface(xj, zj, yy, end), hull)
        return r

    f0 = float(jnp.sum(unfair(yj) ** 2))
    v0, lcb0 = (float(v) for v in particulars(yj))
    scale = jnp.sqrt(jnp.asarray(max(f0, 1.0)))  # F ≲ 1 is fair: no need to go further
    n_free = idx.shape[0]

    def constraints(yy):
        v, lcb = particulars(yy)
        return jnp.stack([(v - v0) / (VOLUME_TOL * v0), (lcb - lcb0) / (LCB_TOL * lpp)])

    def objective(p, args):
        lam, mu = args
        yy = offsets(p)
        r = unfair(yy) / scale
        c = constraints(yy)
        return r @ r + proximity * jnp.mean(jnp.tanh(p) ** 2) + 0.5 * mu * jnp.sum((c + lam / mu) ** 2)

    solver = optx.BFGS(rtol=rtol, atol=rtol)

    @eqx.filter_jit
    def solve(p, lam, mu):
        sol = optx.minimise(objective, solver, p, args=(lam, mu), max_steps=max_steps, throw=False)
        return sol.value, sol.stats["num_steps"], sol.result == optx.RESULTS.successful, constraints(offsets(sol.value))

    p = jnp.zeros(n_free)
    lam, mu = jnp.zeros(2), jnp.asarray(10.0)
    steps, ok = 0, False
    for _ in range(outer):
        p, k, ok, c = solve(p, lam, mu)
        steps += int(k)
        if float(jnp.max(jnp.abs(c))) <= 0.5:
            break
        lam = lam + mu * c
    yy = offsets(p)
    v, lcb = (float(t) for t in particulars(yy))
    return FairResult(
        y=np.asarray(yy), y0=y0, free=free, measure=measure, before=f0, after=float(jnp.sum(unfair(yy) ** 2)),
        volume0=v0, volume=v, lcb0=lcb0, lcb=lcb, lpp=float(lpp), steps=steps, converged=bool(ok),
    )
