"""The repository stands alone: no tracked file names a path outside it."""

import re
import subprocess

from conftest import REPO


def test_no_file_reaches_outside_the_repo():
    files = subprocess.run(["git", "ls-files"], cwd=REPO, capture_output=True, text=True, check=True).stdout.split()
    outside = re.compile(r"\.\./shared|/work/|(?<![\w.])/home/|/Users/")
    hits = []
    for name in files:
        path = REPO / name
        if path.suffix in {".gz", ".igs", ".png", ".json"} or not path.is_file():
            continue
        for k, line in enumerate(path.read_text(errors="ignore").splitlines(), 1):
            if outside.search(line) and name != "tests/test_repo.py":
                hits.append(f"{name}:{k}: {line.strip()}")
    assert not hits, "\n".join(hits)


def test_installed_jax_is_a_tested_one():
    """The installed jax and jaxlib lie in pyproject.toml's range (versions the suite has passed on);
    constraints.txt, which the Makefile installs with, pins one version inside that range for both, and the
    ``gpu`` extra asks for jax in the same range."""
    import tomllib
    from importlib.metadata import version

    from packaging.requirements import Requirement
    from packaging.version import Version

    project = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]
    ranges = {r.name: r.specifier for r in map(Requirement, project["dependencies"]) if r.name in ("jax", "jaxlib")}
    assert set(ranges) == {"jax", "jaxlib"}, f"pyproject.toml: expected jax and jaxlib requirements, got {ranges}"
    assert ranges["jax"] == ranges["jaxlib"], ranges
    assert any(s.operator == "<" for s in ranges["jax"]), f"jax {ranges['jax']}: expected an upper bound"
    pins = {}
    for line in (REPO / "constraints.txt").read_text().splitlines():
        line = line.split("#")[0].strip()
        if line:
            req = Requirement(line)
            (spec,) = req.specifier
            assert spec.operator == "==", f"constraints.txt: {line!r} is not a pin (name==version)"
            pins[req.name] = Version(spec.version)
    assert set(pins) >= {"jax", "jaxlib"}, f"constraints.txt pins {sorted(pins)}: expected jax and jaxlib"
    assert pins["jax"] == pins["jaxlib"], pins
    for name in ("jax", "jaxlib"):
        assert pins[name] in ranges[name], f"constraints.txt's {name}=={pins[name]} is outside pyproject's {ranges[name]}"
        installed = Version(version(name))
        assert installed in ranges[name], f"installed {name} {installed} is outside pyproject's {ranges[name]}"
    (gpu,) = map(Requirement, project["optional-dependencies"]["gpu"])
    assert gpu.name == "jax" and "cuda12" in gpu.extras and gpu.specifier == ranges["jax"], gpu
