"""The public API is documented (ARCHITECTURE.md): every function exported from a package ``__init__`` has
numpydoc ``Parameters`` (when it takes any) and ``Returns`` sections, whose parameter names are its own."""

from __future__ import annotations

import importlib
import inspect
import re

import pytest

PACKAGES = ["geometry", "models", "hydro", "waves", "wind", "resistance", "fairing", "drawing", "optimise", "study",
            "report"]


def _exported_functions():
    for pkg in PACKAGES:
        module = importlib.import_module(f"hullopt.{pkg}")
        for name in sorted(getattr(module, "__all__", None) or dir(module)):
            obj = getattr(module, name)
            if not name.startswith("_") and inspect.isfunction(obj) and obj.__module__.startswith("hullopt"):
                yield f"{pkg}.{name}", obj


@pytest.mark.parametrize(("name", "fn"), list(_exported_functions()), ids=lambda v: v if isinstance(v, str) else "")
def test_exported_function_has_numpydoc_sections(name, fn):
    doc = inspect.getdoc(fn) or ""
    params = [p for p in inspect.signature(fn).parameters.values() if p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
    assert re.search(r"^Returns\n-+$", doc, re.M), f"{name}: no Returns section"
    if params:
        assert re.search(r"^Parameters\n-+$", doc, re.M), f"{name}: no Parameters section"
        section = doc.split("Parameters", 1)[1]
        documented = set(re.findall(r"^(\w+(?:\s*,\s*\w+)*)\s*(?::|$)", section.split("\nReturns\n", 1)[0], re.M))
        names = {n.strip() for group in documented for n in group.split(",")}
        missing = [p.name for p in params if p.name not in names]
        assert not missing, f"{name}: parameters not documented: {missing}"
