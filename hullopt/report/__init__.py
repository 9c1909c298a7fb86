"""What a run looks like to its reader: numbers with their units (:func:`fmt`, :func:`label`), the plots (PNG,
matplotlib) and ``report.html`` (one self-contained page: plotly figures, tables, warnings), built from a run
folder or a study's results. Below the app: the CLI prints and writes through here, and so can a script."""

import lazy_loader

# Names load from their modules on first use (listed in ``__init__.pyi``, which type checkers and the API
# reference read): the CLI's commands other than ``run`` need only the units, and the page and plots import the
# whole study (together 0.6–0.9 s of a warm ``hullopt stability``).
__getattr__, __dir__, __all__ = lazy_loader.attach_stub(__name__, __file__)
