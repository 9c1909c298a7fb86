"""Design problems and solvers (optimistix core; jaxopt behind :func:`minimise_lbfgsb`)."""

from ._bounds import from_unbounded as from_unbounded
from ._bounds import to_unbounded as to_unbounded
from ._jaxopt import minimise_lbfgsb as minimise_lbfgsb
from ._solvers import SolveResult as SolveResult
from ._solvers import fit as fit
from ._solvers import fit_traced as fit_traced
from ._solvers import minimise_constrained as minimise_constrained
from ._objectives import OBJECTIVES as OBJECTIVES
from ._objectives import CalmResistance as CalmResistance
from ._objectives import KAw as KAw
from ._objectives import MeanAddedResistance as MeanAddedResistance
from ._objectives import Objective as Objective
from ._objectives import WindAddedResistance as WindAddedResistance
from ._problems import TARGETS as TARGETS
from ._problems import Design as Design
from ._problems import Targets as Targets
from ._problems import achieved as achieved
from ._problems import make_targets as make_targets
from ._problems import non_dominated as non_dominated
from ._problems import solve_fit as solve_fit
from ._problems import solve_minimum as solve_minimum
from ._problems import target_errors as target_errors
from ._problems import target_residuals as target_residuals
from ._problems import with_objective_scale as with_objective_scale
from ._pareto import ParetoResult as ParetoResult
from ._pareto import solve_pareto as solve_pareto
