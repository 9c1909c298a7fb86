"""The floors of the house (README "Layout"): data flows one way, checked on the source.

geometry (the kernel) ← models ← analyses (hydro, waves, wind, resistance, fairing, drawing) ← optimise ← study ← report ← app.
Every ``import``/``from … import`` of every module under ``hullopt/`` is parsed (also those inside functions)
and resolved to the package it reaches; ``hullopt.errors``, ``hullopt.constants`` and ``hullopt._types`` (the
annotations' aliases) are the ground floor, importable from anywhere. A departure that exists today is listed in
:data:`KNOWN`, so the test fails on any new one — and on a listed one that has gone (then strike it from the
list).
"""

from __future__ import annotations

import ast
from pathlib import Path

from conftest import REPO

PKG = REPO / "hullopt"
BASE = {"errors", "constants", "_types"}
ANALYSES = {"hydro", "waves", "wind", "resistance", "fairing", "drawing"}
#: what each floor may import besides itself
ALLOWED = {
    "errors": set(),
    "constants": set(),
    "_types": set(),
    "geometry": BASE,
    "models": BASE | {"geometry"},
    **{a: BASE | {"geometry"} for a in ANALYSES},
    "optimise": BASE | {"geometry", "models"} | ANALYSES,
    "study": BASE | {"geometry", "models", "optimise"} | ANALYSES,
    "report": BASE | {"geometry", "models", "optimise", "study"} | ANALYSES,
    "app": BASE | {"geometry", "models", "optimise", "study", "report"} | ANALYSES,
    "__main__": {"app"},  # ``python -m hullopt``: the CLI's entry point, part of the app floor
    "__init__": BASE,  # ``import hullopt`` stays light: subpackages load lazily (importlib)
}

#: Departures from the floors that exist today: (importing module, imported package), e.g.
#: ``("hullopt.waves._program", "models")``. Each is a debt, not a licence — move what is shared into the
#: kernel, or take it as an argument, and strike the entry. Empty since resistance._holtrop and the fairing
#: take ∇, LCB and the waterplane from the kernel (geometry.longitudinal_integrals) instead of hullopt.hydro.
KNOWN: set[tuple[str, str]] = set()


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(REPO).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _is_package(path: Path) -> bool:
    return path.name == "__init__.py"


def _floor(module: str) -> str | None:
    """The floor of ``hullopt.X…``: ``X`` (``__init__`` for ``hullopt`` itself); None outside hullopt."""
    parts = module.split(".")
    if parts[0] != "hullopt":
        return None
    return parts[1] if len(parts) > 1 else "__init__"


def _imports(path: Path) -> list[str]:
    """Absolute names of the hullopt modules (or packages) that ``path`` imports, anywhere in the file."""
    return _imports_in(path.read_text(), _module_name(path), _is_package(path), str(path))


def _imports_in(source: str, name: str, is_package: bool, filename: str = "<string>") -> list[str]:
    package = name if is_package else name.rpartition(".")[0]
    out = []
    for node in ast.walk(ast.parse(source, filename)):
        if isinstance(node, ast.Import):
            out += [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module
            if node.module is None:  # ``from .. import waves``: each name may be a subpackage
                out += [f"{target}.{a.name}" for a in node.names]
            else:
                out.append(target)
    return [m for m in out if m == "hullopt" or m.startswith("hullopt.")]


def _modules() -> dict[str, list[str]]:
    return {_module_name(p): _imports(p) for p in sorted(PKG.rglob("*.py"))}


def _edges() -> set[tuple[str, str]]:
    """(importing module, imported floor) for every import that leaves the importer's own floor."""
    edges = set()
    for module, targets in _modules().items():
        src = _floor(module)
        for t in targets:
            dst = _floor(t)
            if dst is not None and dst != src:
                edges.add((module, dst))
    return edges


def test_every_module_parses_and_every_floor_is_known():
    floors = {_floor(m) for m in _modules()}
    assert floors <= set(ALLOWED), f"packages with no floor in ALLOWED: {sorted(floors - set(ALLOWED))}"


def test_floors():
    bad = {(m, dst) for m, dst in _edges() if dst not in ALLOWED[_floor(m)]}
    new = sorted(bad - KNOWN)
    gone = sorted(KNOWN - bad)
    assert not new, "imports against the floors (README 'Layout'):\n" + "\n".join(f"  {m} imports hullopt.{d}"
                                                                                 for m, d in new)
    assert not gone, "KNOWN departures that no longer exist (strike them):\n" + "\n".join(map(str, gone))


def test_nothing_imports_the_app():
    bad = sorted(m for m, dst in _edges() if dst == "app" and _floor(m) != "__main__")
    assert not bad, f"modules importing hullopt.app: {bad}"


def test_no_cycles_between_packages():
    graph: dict[str, set[str]] = {}
    for m, dst in _edges():
        graph.setdefault(_floor(m), set()).add(dst)
    cycles = []

    def visit(node, path):
        for nxt in sorted(graph.get(node, ())):
            if nxt in path:
                cycles.append(" → ".join(path[path.index(nxt):] + [nxt]))
            else:
                visit(nxt, path + [nxt])

    for start in sorted(graph):
        visit(start, [start])
    assert not cycles, "import cycles between packages:\n" + "\n".join(sorted(set(cycles)))


def test_no_cycles_within_a_package():
    """The modules of one package import each other one way too (a package's ``__init__`` imports its
    modules, so a module importing its own package closes a circle)."""
    modules = _modules()
    graph = {m: {t for t in ts if t in modules and t != m and t.rpartition(".")[0] == m.rpartition(".")[0]
                 or t == m.rpartition(".")[0] and m.rpartition(".")[2] != "__init__"}
             for m, ts in modules.items()}
    cycles = set()

    def visit(node, path):
        for nxt in sorted(graph.get(node, ())):
            if nxt in path:
                cycles.add(" → ".join(path[path.index(nxt):] + [nxt]))
            elif len(path) < 12:
                visit(nxt, path + [nxt])

    for start in sorted(graph):
        visit(start, [start])
    assert not cycles, "import cycles within a package:\n" + "\n".join(sorted(cycles))


def test_no_private_name_is_used_across_files():
    """A name with a leading underscore stays in its file, and a private module in its package: what another
    file needs is public (exported from the package)."""
    bad = []
    for path in sorted(PKG.rglob("*.py")):
        name = _module_name(path)
        package = name if _is_package(path) else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if not isinstance(node, ast.ImportFrom) or not (node.level or (node.module or "").startswith("hullopt")):
                continue
            base = package.split(".")[: len(package.split(".")) - (node.level - 1)] if node.level else []
            target = ".".join(base + ([node.module] if node.module else [])) if node.level else node.module
            private = [a.name for a in node.names if a.name.startswith("_") and a.name != "__version__"]
            parts = target.split(".")
            owner = ".".join(parts[:-1])  # a private module is used within its package (and subpackages)
            foreign = any(p.startswith("_") and not p.startswith("__") for p in parts[2:-1]) or (
                parts[-1].startswith("_") and not parts[-1].startswith("__")
                and not (package == owner or package.startswith(owner + ".")))
            if private or foreign:
                bad.append(f"{name}: from {target} import {', '.join(a.name for a in node.names)}")
    assert not bad, "private names used across files:\n" + "\n".join(bad)


def test_the_parser_sees_imports_inside_functions_and_resolves_relative_ones():
    src = ("import numpy\nfrom . import _waterline\n\ndef f():\n    from ..models import wigley\n"
           "    import hullopt.hydro\n    from .. import fairing, errors\n")
    got = _imports_in(src, "hullopt.waves._probe", is_package=False)
    assert sorted(got) == ["hullopt.errors", "hullopt.fairing", "hullopt.hydro", "hullopt.models",
                           "hullopt.waves._waterline"]
    assert _imports_in("from ._x import y\n", "hullopt.wind", is_package=True) == ["hullopt.wind._x"]
