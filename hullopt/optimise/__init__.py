"""Design problems and solvers (optimistix core; jaxopt behind :func:`minimise_lbfgsb`)."""

from ._bounds import check_bounds as check_bounds
from ._bounds import from_unbounded as from_unbounded
from ._bounds import to_unbounded as to_unbounded
from ._jaxopt import minimise_lbfgsb as minimise_lbfgsb
from ._solvers import SolveResult as SolveResult
from ._solvers import fit as fit
from ._solvers import minimise_constrained as minimise_constrained
