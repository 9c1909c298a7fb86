"""The one adapter to jaxopt (unmaintained, warns on import): bounded L-BFGS-B.

Imported lazily so that ``import hullopt`` never imports jaxopt.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable


def minimise_lbfgsb(objective: Callable, p0, lower, upper, args=None, *, tol: float = 1e-9, maxiter: int = 500):
    """Minimise ``objective(p, args)`` within box bounds by jaxopt's L-BFGS-B; returns ``(p, value, ok)``.

    Parameters
    ----------
    objective : callable
        ``objective(p, args)`` → scalar.
    p0 : pytree of Array
        Starting parameters.
    lower, upper : pytree of Array
        Box bounds, the structure of ``p0``.
    args : pytree or None
        Passed through to ``objective``.
    tol : float
        Stopping tolerance on the projected-gradient error.
    maxiter : int
        Largest number of iterations.

    Returns
    -------
    p : pytree of Array
        The solution, the structure of ``p0``.
    value : Array
        ``objective(p, args)``, scalar.
    ok : Array
        Scalar bool: the solver's error is within ``tol``.
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # jaxopt's import-time deprecation notice
        import jaxopt

    solver = jaxopt.LBFGSB(fun=objective, tol=tol, maxiter=maxiter, implicit_diff=True)
    res = solver.run(p0, (lower, upper), args)
    return res.params, objective(res.params, args), res.state.error <= tol


def minimise_lbfgsb_traced(objective: Callable, p0, lower, upper, args=None, *, tol: float = 1e-9,
                           maxiter: int = 500, stall: int = 5, record: Callable | None = None) -> tuple:
    """:func:`minimise_lbfgsb` as an explicit loop (``lax.while_loop``: jit- and vmap-able) of jaxopt's L-BFGS-B
    steps that records the objective after each; returns ``(p, value, ok, steps, history)``, and with ``record``
    ``recorded`` after them. The bounds are
    hard: every iterate is projected into them. Not differentiable in ``args``.

    It also stops, as converged, when the objective has fallen by less than 1e-4 (relative) in each of
    ``stall`` steps (as :func:`~hullopt.optimise.fit_traced` does): the slow polishing of a tiny
    regularisation, whose projected gradient may stay above ``tol`` for hundreds of steps.

    Parameters
    ----------
    objective : callable
        ``objective(p, args)`` → scalar.
    p0 : pytree of Array
        Starting parameters, within the bounds.
    lower, upper : pytree of Array
        Box bounds, the structure of ``p0``.
    args : pytree or None
        Passed through to ``objective``.
    tol : float
        Stopping tolerance on the projected-gradient error.
    maxiter : int
        Largest number of iterations.
    stall : int
        Steps of < 1e-4 relative progress after which the loop stops as converged.
    record : callable or None
        ``record(p)`` → scalar, kept at the start and after each iteration.

    Returns
    -------
    p : pytree of Array
        The solution, the structure of ``p0``.
    value : Array
        ``objective(p, args)``, scalar.
    ok : Array
        Scalar bool: the solver's error is within ``tol``, or the loop stalled.
    steps : Array
        Scalar int: the iterations taken.
    history : Array
        (maxiter + 1,) the objective at the start and after each iteration, NaN after the last.
    recorded : Array
        (maxiter + 1,) ``record`` likewise (only with ``record``).
    """
    import jax
    import jax.numpy as jnp

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # jaxopt's import-time deprecation notice
        import jaxopt

    solver = jaxopt.LBFGSB(fun=objective, tol=tol, maxiter=maxiter)
    bounds = (lower, upper)
    state0 = solver.init_state(p0, bounds, args)
    v0 = objective(p0, args)
    rec = (lambda p: jnp.zeros((), jnp.result_type(v0))) if record is None else record
    history0 = jnp.full((2, maxiter + 1), jnp.nan, jnp.result_type(v0)).at[:, 0].set(jnp.stack([v0, rec(p0)]))

    def cond(carry):
        _, state, _, still, _ = carry
        return (state.iter_num < maxiter) & (state.error > tol) & (still < stall)

    def body(carry):
        p, state, history, still, best = carry
        p, state = solver.update(p, state, bounds, args)
        still = jnp.where(state.value >= best * (1.0 - 1e-4), still + 1, 0)
        history = history.at[:, state.iter_num].set(jnp.stack([state.value, rec(p)]))
        return p, state, history, still, jnp.minimum(best, state.value)

    p, state, history, still, _ = jax.lax.while_loop(cond, body, (p0, state0, history0, jnp.asarray(0), v0))
    out = p, objective(p, args), (state.error <= tol) | (still >= stall), state.iter_num, history[0]
    return out if record is None else (*out, history[1])
