"""The one adapter to jaxopt (unmaintained, warns on import): bounded L-BFGS-B.

Imported lazily so that ``import hullopt`` never imports jaxopt.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable


def minimise_lbfgsb(objective: Callable, p0, lower, upper, args=None, *, tol: float = 1e-9, maxiter: int = 500):
    """Minimise ``objective(p, args)`` within box bounds by jaxopt's L-BFGS-B; returns ``(p, value, ok)``."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # jaxopt's import-time deprecation notice
        import jaxopt

    solver = jaxopt.LBFGSB(fun=objective, tol=tol, maxiter=maxiter, implicit_diff=True)
    res = solver.run(p0, (lower, upper), args)
    return res.params, objective(res.params, args), res.state.error <= tol
