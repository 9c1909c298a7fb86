"""Thin solver adapters over optimistix (the core); no domain code here.

* :func:`fit` — nonlinear least squares by Levenberg–Marquardt (targets to meet);
* :func:`minimise_constrained` — an objective with equality constraints by an augmented Lagrangian whose
  inner problems are solved by BFGS.

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
from jaxtyping import Array

from ._bounds import from_unbounded, to_unbounded


class SolveResult(eqx.Module):
    """Outcome of a solve. ``params`` is the solution (a pytree like the start), ``residuals`` the constraint
    (or target) residuals, ``max_violation`` the largest ``|residual| / tol`` — so ``met`` (≤ 1) means every
    one is within its tolerance —, ``objective`` the objective value (the sum of squares for a fit),
    ``solver_ok`` the solver's own success flag, ``steps`` the number of (inner) steps."""

    params: object
    residuals: Array
    objective: Array
    max_violation: Array
    met: Array
    solver_ok: Array
    steps: Array


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
    """
    u0 = to_unbounded(p0, lower, upper)

    def fn(u, args):
        return residuals(from_unbounded(u, lower, upper), args)

    sol = optx.least_squares(fn, optx.LevenbergMarquardt(rtol=rtol, atol=atol), u0, args,
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
    outer: int = 10,
    mu0: float = 10.0,
    growth: float = 10.0,
    rtol: float = 1e-8,
    atol: float = 1e-8,
    max_steps: int = 300,
) -> SolveResult:
    """Minimise ``objective(p, args)`` (a scalar, scaled to order one) subject to
    ``constraints(p, args) = 0`` (a vector normalised to order one; ``|c| ≤ tol`` counts as met) within
    the bounds.

    Augmented Lagrangian: ``f + λ·c + μ/2 |c|²``, ``outer`` rounds of BFGS with ``λ ← λ + μ c`` and
    ``μ ← growth · μ`` between them (a fixed number of rounds, so the whole solve is one ``vmap``-able
    computation).
    """
    u0 = to_unbounded(p0, lower, upper)
    n_c = jnp.shape(constraints(p0, args))[0]

    def lagrangian(u, inner_args):
        lam, mu, args = inner_args
        p = from_unbounded(u, lower, upper)
        c = constraints(p, args)
        return objective(p, args) + lam @ c + 0.5 * mu * c @ c

    solver = optx.BFGS(rtol=rtol, atol=atol)

    def round_(carry, _):
        u, lam, mu, steps, ok = carry
        sol = optx.minimise(lagrangian, solver, u, (lam, mu, args), max_steps=max_steps, throw=False)
        c = constraints(from_unbounded(sol.value, lower, upper), args)
        return (sol.value, lam + mu * c, mu * growth, steps + sol.stats["num_steps"],
                sol.result == optx.RESULTS.successful), None

    dtype = ravel_pytree(u0)[0].dtype
    init = (u0, jnp.zeros(n_c, dtype), jnp.asarray(mu0, dtype), jnp.asarray(0), jnp.asarray(True))
    (u, _, _, steps, ok), _ = jax.lax.scan(round_, init, None, length=outer)
    p = from_unbounded(u, lower, upper)
    c = constraints(p, args)
    viol = jnp.max(jnp.abs(c) / tol) if n_c else jnp.asarray(0.0, dtype)
    return SolveResult(p, c, objective(p, args), viol, viol <= 1.0, ok, steps)


def fit_stepwise(residuals: Callable, p0, lower, upper, args=None, *, tol=1.0, rtol: float = 1e-6,
                 atol: float = 1e-9, max_steps: int = 200, callback: Callable | None = None) -> SolveResult:
    """:func:`fit`, one jitted Levenberg–Marquardt step at a time, calling ``callback(step, params, cost)``
    after each (for progress bars and convergence histories); not ``vmap``-able. It also stops, as converged,
    when the cost has fallen by less than 1e-4 (relative) in each of 5 steps: what is left is the slow
    polishing of a tiny regularisation, which the solver's own step test may take hundreds of steps to end."""
    solver = optx.LevenbergMarquardt(rtol=rtol, atol=atol)

    def fn(u, args):
        return residuals(from_unbounded(u, lower, upper), args), None

    u = to_unbounded(p0, lower, upper)
    f_struct, aux_struct = jax.eval_shape(lambda: fn(u, args))
    state = solver.init(fn, u, args, {}, f_struct, aux_struct, frozenset())
    step = eqx.filter_jit(lambda u, s: solver.step(fn, u, args, {}, s, frozenset()))
    done_fn = eqx.filter_jit(lambda u, s: solver.terminate(fn, u, args, {}, s, frozenset()))
    cost = eqx.filter_jit(lambda u: jnp.sum(fn(u, args)[0] ** 2))
    n, done, result = 0, False, optx.RESULTS.successful
    best, still = float(cost(u)), 0
    while n < max_steps and still < 5:
        done, result = done_fn(u, state)
        if bool(done):
            break
        u, state, _ = step(u, state)
        n += 1
        c = float(cost(u))
        still = still + 1 if c >= best * (1.0 - 1e-4) else 0
        best = min(best, c)
        if callback is not None:
            callback(n, from_unbounded(u, lower, upper), c)
    done = bool(done) or still >= 5
    p = from_unbounded(u, lower, upper)
    r = residuals(p, args)
    viol = jnp.max(jnp.abs(r) / tol)
    ok = jnp.asarray(bool(done) and result == optx.RESULTS.successful)
    return SolveResult(p, r, jnp.sum(r**2), viol, viol <= 1.0, ok, jnp.asarray(n))
