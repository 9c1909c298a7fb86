"""Design studies: a validated run config (:class:`RunConfig`) and its parent become a study — :class:`Fit`,
:class:`Minimise` or :class:`Pareto` (:data:`STUDIES`, by the config's ``kind``) — that solves the design
problem and assesses its designs. The app (``hullopt run``) reads the config, calls a study, writes and prints.

Parents and hull specs (:func:`load_hull`, :func:`run_parent`) are read here, with the caches that keep what
they extract, and so are run folders (a finished run's design hull, :func:`folder_study`)."""

import lazy_loader

# Names load from their modules on first use (listed in ``__init__.pyi``, which type checkers and the API
# reference read): a command that reads a hull (``load_hull``) or keeps a program (``cached_call``) does not
# import the configs, the studies and their solvers.
__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
