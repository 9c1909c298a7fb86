"""The `Examples` of the public API's main entry points run and print what their docstrings say.

Each example turns on float64 itself; conftest also runs the tests with strict dtype promotion, as the CLI
does. The expected values are closed forms (Wigley Cb 4/9, the wall-sided GZ of a box, the patent's K_AW
formula, a box's zero unfairness, beam scaling in the solvers) or measured values rounded in the docstring.
"""

import doctest

import pytest

from hullopt.fairing import unfairness
from hullopt.hydro import gz_curve, hydrostatics
from hullopt.models import feature_model
from hullopt.optimise import solve_fit, solve_minimum, solve_pareto
from hullopt.waves import k_aw, mean_added_resistance
from hullopt.wind import wind_coefficients

ENTRY_POINTS = [hydrostatics, gz_curve, feature_model, solve_fit, solve_minimum, solve_pareto, k_aw,
                mean_added_resistance, wind_coefficients, unfairness]
FLAGS = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS


@pytest.mark.parametrize("func", ENTRY_POINTS, ids=lambda f: f.__name__)
@pytest.mark.slow
def test_docstring_examples(func):
    tests = doctest.DocTestFinder(recurse=False).find(func, func.__name__, globs={})
    examples = [t for t in tests if t.examples]
    assert examples, f"{func.__name__} has no Examples"
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    for t in examples:
        runner.run(t)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} examples of {func.__name__} failed"


@pytest.mark.parametrize("func", ENTRY_POINTS, ids=lambda f: f.__name__)
def test_numpydoc_sections(func):
    doc = func.__doc__
    for section in ("Parameters\n", "Returns\n", "Examples\n"):
        assert section in doc, f"{func.__name__}: no {section.strip()} section"
