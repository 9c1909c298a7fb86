"""Thin solver adapters over optimistix (the core); no domain code here.

* :func:`fit` — nonlinear least squares by Levenberg–Marquardt (targets to meet); :func:`fit_traced`, the same
  as an explicit loop that records the cost of each step;
* :func:`minimise_constrained` — an objective with equality and inequality constraints by an augmented
  Lagrangian whose inner problems are solved by BFGS.

Both work in bounded parameters through a tanh change of variables, take ``throw=False`` solves so they
``vmap`` (each member reports its own status), and are differentiable in ``args`` by the implicit function
theorem (optimistix's ``ImplicitAdjoint``).
"""

from __future__ import annotations

from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import optimistix as optx
from jax.flatten_util import ravel_pytree
from jaxtyping import Array, Bool, Float, Int, PyTree

from ._bounds import from_unbounded, to_unbounded


def bfgs(rtol: float, atol: float) -> optx.BFGS:
    """optimistix's BFGS whose Armijo backtracking cuts the step tenfold, not in half.

    BFGS takes its first step along the raw gradient (the identity as inverse Hessian). Our augmented
    Lagrangians scale the constraints by their tolerances, so that gradient is O(10³): halving from a unit step
    spent ~20 steps of a round before one was accepted, and short rounds left a design at the parent. Cutting
    tenfold reaches the right scale in 3–4 steps; on the small Wigley bow sweep (Bf* 0.028, 5 rounds of 100
    steps) it met in 428 steps where halving had not met in 1200, and it solves the toy problems of the tests
    in 40–60 % fewer steps. Later steps are Newton-like and take the unit step, so they are unaffected."""
    return eqx.tree_at(lambda s: s.search, optx.BFGS(rtol=rtol, atol=atol),
                       optx.BacktrackingArmijo(decrease_factor=0.1))


class SolveResult(eqx.Module):
    """Outcome of a solve. ``params`` is the solution (a pytree like the start), ``residuals`` the constraint
    (or target) residuals, ``max_violation`` the largest ``|residual| / tol`` — so ``met`` (≤ 1) means every
    one is within its tolerance —, ``objective`` the objective value (the sum of squares for a fit),
    ``solver_ok`` the solver's own success flag, ``steps`` the number of (inner) steps, ``history`` the cost
    after each step or round where the solver records it (NaN-padded to a fixed length);
    ``objective_history`` and ``violation_history`` the objective (or what the caller records in its place)
    and the largest ``|residual| / tol`` after each round, ``merit_history`` the minimised objective there
    (:func:`minimise_constrained`; None for the other solvers)."""

    params: PyTree[Float[Array, "..."]]
    residuals: Float[Array, " r"]
    objective: Float[Array, ""]
    max_violation: Float[Array, ""]
    met: Bool[Array, ""]
    solver_ok: Bool[Array, ""]
    steps: Int[Array, ""]
    history: Float[Array, " h"] | None = None
    objective_history: Float[Array, " h"] | None = None
    violation_history: Float[Array, " h"] | None = None
    merit_history: Float[Array, " h"] | None = None


def fit(
    residuals: Callable,
    p0,
    lower,
    upper,
    args=None,
    *,
    tol=1.0,
    rtol: float = 1e-6,
    atol: float = 1e-9,
    max_steps: int = 200,
) -> SolveResult:
    """Solve ``residuals(p, args) = 0`` in the least-squares sense within ``lower < p < upper``.

    ``residuals`` returns a vector normalised to order one (e.g. relative errors); ``tol`` (scalar or one per
    residual) is what counts as met. Levenberg–Marquardt from ``p0`` finds a solution near the start (the
    smallest change of the parent), which is what a designer expects of an auto-fit.

    Parameters
    ----------
    residuals : callable
        ``residuals(p, args)`` → (r,) float, normalised to order one.
    p0 : pytree of Array
        Starting parameters, strictly inside the bounds.
    lower, upper : pytree of Array
        Box bounds, the structure of ``p0``.
    args : pytree or None
        Passed through to ``residuals``; the solution is differentiable in it.
    tol : float or (r,) float
        What counts as met, per residual.
    rtol, atol : float
        Levenberg–Marquardt's relative and absolute step tolerances.
    max_steps : int
        Largest number of steps.

    Returns
    -------
    SolveResult
        ``params`` (the structure of ``p0``), ``residuals`` (r,), ``objective`` (Σ r²), ``max_violation``,
        ``met``, ``solver_ok``, ``steps``; ``history`` None.
    """
    u0 = to_unbounded(p0, lower, upper)

    def fn(u, args):
        return residuals(from_unbounded(u, lower, upper), args)

    sol = optx.least_squares(eqx.filter_jit(fn), optx.LevenbergMarquardt(rtol=rtol, atol=atol), u0, args,
                             max_steps=max_steps, throw=False)
    p = from_unbounded(sol.value, lower, upper)
    r = residuals(p, args)
    viol = jnp.max(jnp.abs(r) / tol)
    return SolveResult(p, r, jnp.sum(r**2), viol, viol <= 1.0, sol.result == optx.RESULTS.successful,
                       sol.stats["num_steps"])


def minimise_constrained(
    objective: Callable,
    constraints: Callable,
    p0,
    lower,
    upper,
    args=None,
    *,
    tol=1.0,
    inequalities: Callable | None = None,
    inequality_tol=1.0,
    outer: int = 10,
    mu0: float = 10.0,
    growth: float = 10.0,
    rtol: float = 1e-8,
    atol: float = 1e-8,
    max_steps: int = 300,
    record: Callable | None = None,
    terms: Callable | None = None,
) -> SolveResult:
    """Minimise ``objective(p, args)`` (a scalar, scaled to order one) subject to
    ``constraints(p, args) = 0`` (a vector normalised to order one; ``|c| ≤ tol`` counts as met) and, if
    given, ``inequalities(p, args) ≤ 0`` (a vector normalised to order one; ``g ≤ inequality_tol`` counts as
    met) within the bounds.

    Augmented Lagrangian, Powell–Hestenes–Rockafellar for the inequalities (Nocedal & Wright 2006, eq.
    17.65): ``f + λ·c + μ/2 |c|² + Σ (max(0, ν + μ g)² − ν²)/(2μ)``, ``outer`` rounds of BFGS
    (:func:`bfgs`) with ``λ ← λ + μ c``, ``ν ← max(0, ν + μ g)`` and ``μ ← growth · μ`` between them (a fixed number of
    rounds, so the whole solve is one ``vmap``-able computation). ``residuals`` are the equality residuals ``c``;
    ``max_violation`` and ``met`` count both kinds (an inequality's violation is ``max(g, 0) /
    inequality_tol``). ``history``: the augmented Lagrangian at the end of each round; ``objective_history`` and
    ``violation_history``: the objective — or ``record(p, args)``, when the objective minimised is a merit of
    several terms and the caller wants its own part — and the largest ``|c| / tol`` there (what a convergence
    plot shows: the Lagrangian itself rises as μ grows); ``merit_history``: the objective minimised there.

    Parameters
    ----------
    objective : callable
        ``objective(p, args)`` → scalar, scaled to order one.
    constraints : callable
        ``constraints(p, args)`` → (c,) float equality residuals, normalised to order one (c may be 0).
    p0 : pytree of Array
        Starting parameters, strictly inside the bounds.
    lower, upper : pytree of Array
        Box bounds, the structure of ``p0``.
    args : pytree or None
        Passed through to the callables; the solution is differentiable in it.
    tol : float or (c,) float
        What counts as met for the equalities.
    inequalities : callable or None
        ``inequalities(p, args)`` → (g,) float, ≤ 0 when satisfied; None: none.
    inequality_tol : float or (g,) float
        What counts as met for the inequalities.
    outer : int
        Number of augmented-Lagrangian rounds.
    mu0, growth : float
        Initial penalty μ and its factor per round.
    rtol, atol : float
        BFGS's relative and absolute tolerances.
    max_steps : int
        Largest number of BFGS steps per round.
    record : callable or None
        ``record(p, args)`` → scalar recorded after each round in ``objective_history``; None: the objective.
    terms : callable or None
        ``terms(p, args)`` → ``(objective, constraints, inequalities)``, the three from one evaluation, where they
        share work (a hull model), jitted; None: the three called apart, as traced.

    Returns
    -------
    SolveResult
        ``params``, ``residuals`` (c,), ``objective``, ``max_violation``, ``met``, ``solver_ok`` (of the last
        round), ``steps`` (all rounds), and ``history``, ``objective_history``, ``violation_history``,
        ``merit_history`` (outer,).
    """
    u0 = to_unbounded(p0, lower, upper)
    ineq = inequalities if inequalities is not None else (lambda p, args: jnp.zeros(0))
    if terms is None:
        c0, g0 = constraints(p0, args), ineq(p0, args)

        def evaluate(p, args):
            c, g = constraints(p, args), ineq(p, args)
            return objective(p, args), c, g
    else:
        # jitted (and the Lagrangian below), so that jax traces the model once and transforms its jaxpr once
        # (linearised, transposed, batched: each cached) however often BFGS and vmap trace through it: the KCS
        # sweep's solve traced in 32 s, now 21 s. (Not without ``terms``: the fairing's solve, on a knife-edge
        # between inflection counts, lands elsewhere when XLA fuses its arithmetic differently.)
        evaluate = eqx.filter_jit(terms)
        _, c0, g0 = evaluate(p0, args)
    n_c, n_g = jnp.shape(c0)[0], jnp.shape(g0)[0]

    def lagrangian(u, inner_args):
        """The augmented Lagrangian, and (aux) the objective, c and g at ``u``: BFGS keeps them for its
        accepted point, so a round does not evaluate them again (each copy of the model is compiled)."""
        lam, nu, mu, args = inner_args
        f, c, g = evaluate(from_unbounded(u, lower, upper), args)
        phr = jnp.sum(jnp.maximum(nu + mu * g, 0.0) ** 2 - nu**2) / (2.0 * mu) if n_g else 0.0
        return f + lam @ c + 0.5 * mu * c @ c + phr, (f, c, g)

    merit = lagrangian if terms is None else eqx.filter_jit(lagrangian)

    def violation(c, g):
        v = jnp.max(jnp.abs(c) / tol) if n_c else jnp.zeros((), c.dtype)
        return jnp.maximum(v, jnp.max(jnp.maximum(g, 0.0) / inequality_tol)) if n_g else v

    solver = bfgs(rtol, atol)

    def round_(carry, _):
        u, lam, nu, mu, steps, ok, _ = carry
        sol = optx.minimise(merit, solver, u, (lam, nu, mu, args), has_aux=True, max_steps=max_steps,
                            throw=False)
        f, c, g = sol.state.aux  # at sol.value, the last accepted point (``sol.aux`` is the one before it)
        recorded = f if record is None else record(from_unbounded(sol.value, lower, upper), args)
        return (sol.value, lam + mu * c, jnp.maximum(nu + mu * g, 0.0), mu * growth,
                steps + sol.stats["num_steps"], sol.result == optx.RESULTS.successful, (f, c, g)), \
            (sol.state.f_info.f, f, recorded, violation(c, g))

    dtype = ravel_pytree(u0)[0].dtype
    # Under vmap over what the constraints depend on (a sweep's targets) the rounds make the carry batched (all
    # but μ). Started so, by a select on a flag that is always true but computed from them, the scan is batched
    # in one pass over its body instead of two, each of which batches the BFGS loop inside it again.
    start = jnp.isnan(jnp.sum(c0) + jnp.sum(g0)) | True
    u0, lam0, nu0, steps0, ok0, last0 = jax.tree.map(lambda a: jnp.where(start, a, a), (
        u0, jnp.zeros(n_c, dtype), jnp.zeros(n_g, dtype), jnp.asarray(0), jnp.asarray(True),
        (jnp.zeros((), dtype), jnp.zeros(n_c, dtype), jnp.zeros(n_g, dtype))))  # the last round's f, c, g
    init = (u0, lam0, nu0, jnp.asarray(mu0, dtype), steps0, ok0, last0)
    (u, _, _, _, steps, ok, (f, c, g)), (history, merit, f_history, v_history) = jax.lax.scan(
        round_, init, None, length=outer)
    p = from_unbounded(u, lower, upper)
    viol = violation(c, g)
    return SolveResult(p, c, f, viol, viol <= 1.0, ok, steps, history, f_history, v_history, merit)


def fit_traced(residuals: Callable, p0, lower, upper, args=None, *, tol=1.0, rtol: float = 1e-6,
               atol: float = 1e-9, max_steps: int = 200, stall: int = 5) -> SolveResult:
    """:func:`fit` as an explicit Levenberg–Marquardt loop (``lax.while_loop``: jit- and vmap-able) that records
    the cost after each step in ``history`` and the largest ``|residual| / tol`` in ``violation_history`` (each
    ``(max_steps + 1,)``, entry 0 the start, NaN after the last step).

    It also stops, as converged, when the cost has fallen by less than 1e-4 (relative) in each of ``stall``
    steps: what is left is the slow polishing of a tiny regularisation, which the solver's own step test may
    take hundreds of steps to end. Not differentiable in ``args`` (use :func:`fit` for that).

    Parameters
    ----------
    residuals : callable
        ``residuals(p, args)`` → (r,) float, normalised to order one.
    p0 : pytree of Array
        Starting parameters, strictly inside the bounds.
    lower, upper : pytree of Array
        Box bounds, the structure of ``p0``.
    args : pytree or None
        Passed through to ``residuals``.
    tol : float or (r,) float
        What counts as met, per residual.
    rtol, atol : float
        Levenberg–Marquardt's relative and absolute step tolerances.
    max_steps : int
        Largest number of steps.
    stall : int
        Steps of < 1e-4 relative progress after which the loop stops as converged.

    Returns
    -------
    SolveResult
        As :func:`fit`, with ``history`` (max_steps + 1,) the cost Σ r² after each step and
        ``violation_history`` (max_steps + 1,) the largest ``|r| / tol`` (≤ 1: met; what converges when a
        smoothness term keeps the cost above zero).
    """
    if max_steps < 1:
        raise ValueError(f"max_steps={max_steps}: at least one step (the first evaluates the start)")
    solver = optx.LevenbergMarquardt(rtol=rtol, atol=atol)
    tags = frozenset()

    def fn(u, args):
        return residuals(from_unbounded(u, lower, upper), args), None

    u0 = to_unbounded(p0, lower, upper)
    # closure-converted, so the solver state's static part is the same each step; jitted, so its linearisation and
    # the Jacobian's batching are traced once from its jaxpr (the cold demo's trace 3.7-4.7 -> 2.9 s)
    fn = eqx.filter_closure_convert(eqx.filter_jit(fn), u0, args)
    f_struct, aux_struct = jax.eval_shape(lambda: fn(u0, args))
    state0 = solver.init(fn, u0, args, {}, f_struct, aux_struct, tags)
    done0, result0 = solver.terminate(fn, u0, args, {}, state0, tags)
    dynamic0, static = eqx.partition(state0, eqx.is_array)
    nan = jnp.full((), jnp.nan, f_struct.dtype)
    history0 = jnp.full((2, max_steps + 1), nan)

    def cond(carry):
        _, _, n, _, still, _, done, result = carry
        return ~done & (result == optx.RESULTS.successful) & (n < max_steps) & (still < stall)

    def body(carry):
        u_old, dynamic, n, best, still, history, _, _ = carry
        u, state, _ = solver.step(fn, u_old, args, {}, eqx.combine(static, dynamic), tags)
        # the residuals at u are the solver's own (its linearisation's value): the model is evaluated once a
        # step, which keeps one copy of it in the compiled loop. The first step evaluates the start and accepts
        # it as it is: its cost is the start's, the stall test's first reference
        r = state.f_info.residual
        c, v = jnp.sum(r**2), jnp.max(jnp.abs(r) / tol)
        best = jnp.where(n == 0, c, best)
        still = jnp.where(c >= best * (1.0 - 1e-4), still + 1, 0)
        done, result = solver.terminate(fn, u_old, args, {}, state, tags)  # as optimistix: old y, new state
        dynamic = eqx.partition(state, eqx.is_array)[0]
        history = history.at[:, n + 1].set(jnp.stack([c, v]))
        return u, dynamic, n + 1, jnp.minimum(best, c), still, history, done, result

    init = (u0, dynamic0, jnp.asarray(0), nan, jnp.asarray(0), history0, done0, result0)
    u, dynamic, n, _, still, history, done, result = jax.lax.while_loop(cond, body, init)
    history = history.at[:, 0].set(history[:, 1])  # the start's (see the body)
    p = from_unbounded(u, lower, upper)
    r = eqx.combine(static, dynamic).f_info.residual  # at u (the last accepted step's)
    viol = jnp.max(jnp.abs(r) / tol)
    ok = (done | (still >= stall)) & (result == optx.RESULTS.successful)
    return SolveResult(p, r, jnp.sum(r**2), viol, viol <= 1.0, ok, n, history[0], violation_history=history[1])
