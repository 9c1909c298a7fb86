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
