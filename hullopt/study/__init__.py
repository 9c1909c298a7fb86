"""Design studies: a validated run config (:class:`RunConfig`) and its parent become a study — :class:`Fit`,
:class:`Minimise` or :class:`Pareto` (:data:`STUDIES`, by the config's ``kind``) — that solves the design
problem and assesses its designs. The app (``hullopt run``) reads the config, calls a study, writes and prints.

Parents and hull specs (:func:`load_hull`, :func:`run_parent`) are read here, with the caches that keep what
they extract, and so are run folders (a finished run's design hull, :func:`folder_study`)."""

import lazy_loader

# Names load from their modules on first use: a command that reads a hull (``load_hull``) or keeps a program
# (``cached_call``) does not import the configs, the studies and their solvers.
__getattr__, __dir__, __all__ = lazy_loader.attach(__name__, submod_attrs={
    "_config": [
        "FAIRNESS", "OPTIONS", "conditions_text", "ConstraintsConfig", "DeformConfig", "DesignConfig",
        "ObjectiveConfig", "ObjectiveOptions", "RunConfig", "SolverConfig", "load_config", "load_design",
        "objective_options", "DEFAULT_LIMITS", "Bound", "parse_bound", "resolve_spec",
    ],
    "_hulls": [
        "cache_folder", "folder_study", "load_hull", "load_study", "parent_digest", "read_run_config", "run_parent",
    ],
    "_problem": [
        "Problem", "design_params", "limits_from", "params_from_dict", "params_to_dict",
    ],
    "_programs": [
        "cached_call",
    ],
    "_study": [
        "STUDIES", "VIOLATION", "Fit", "Minimise", "Outcome", "Pareto", "Solution", "Study", "design_outcomes",
        "structure",
    ],
    "_sweep": [
        "collect_chunks", "parse_shard",
    ],
    "_wind_config": [
        "DrawingsConfig", "config_parts", "read_wind_config",
    ],
    "_rescore": [
        "rescore",
    ],
})
