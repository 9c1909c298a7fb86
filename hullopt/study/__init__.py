"""Design studies: a validated run config (:class:`RunConfig`) and its parent become a study — :class:`Fit`,
:class:`Minimise` or :class:`Pareto` (:data:`STUDIES`, by the config's ``kind``) — that solves the design
problem and assesses its designs. The app (``hullopt run``) reads the config, calls a study, writes and prints.

Parents and hull specs (:func:`load_hull`, :func:`run_parent`) are read here, with the caches that keep what
they extract, and so are run folders (a finished run's design hull, :func:`folder_study`)."""

from ._config import FAIRNESS as FAIRNESS
from ._config import OPTIONS as OPTIONS
from ._config import conditions_text as conditions_text
from ._config import ConstraintsConfig as ConstraintsConfig
from ._config import DeformConfig as DeformConfig
from ._config import DesignConfig as DesignConfig
from ._config import ObjectiveConfig as ObjectiveConfig
from ._config import ObjectiveOptions as ObjectiveOptions
from ._config import RunConfig as RunConfig
from ._config import SolverConfig as SolverConfig
from ._config import load_config as load_config
from ._config import load_design as load_design
from ._config import objective_options as objective_options
from ._config import DEFAULT_LIMITS as DEFAULT_LIMITS
from ._config import Bound as Bound
from ._config import parse_bound as parse_bound
from ._config import resolve_spec as resolve_spec
from ._hulls import cache_folder as cache_folder
from ._hulls import folder_study as folder_study
from ._hulls import load_hull as load_hull
from ._hulls import load_study as load_study
from ._hulls import parent_digest as parent_digest
from ._hulls import read_run_config as read_run_config
from ._hulls import run_parent as run_parent
from ._problem import Problem as Problem
from ._problem import design_params as design_params
from ._problem import limits_from as limits_from
from ._problem import params_from_dict as params_from_dict
from ._problem import params_to_dict as params_to_dict
from ._programs import cached_call as cached_call
from ._study import STUDIES as STUDIES
from ._study import VIOLATION as VIOLATION
from ._study import Fit as Fit
from ._study import Minimise as Minimise
from ._study import Outcome as Outcome
from ._study import Pareto as Pareto
from ._study import Solution as Solution
from ._study import Study as Study
from ._study import design_outcomes as design_outcomes
from ._study import structure as structure
from ._sweep import collect_chunks as collect_chunks
from ._sweep import parse_shard as parse_shard
from ._wind_config import DrawingsConfig as DrawingsConfig
from ._wind_config import config_parts as config_parts
from ._wind_config import read_wind_config as read_wind_config
from ._rescore import rescore as rescore
