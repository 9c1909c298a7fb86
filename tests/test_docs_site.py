"""The documentation: the mkdocs site (docs/, mkdocs.yml) builds with no warning, README stays a five-minute read
that keeps the two entry points, and the measured numbers the docs quote are those the benchmarks stored
(benchmarks/results/*.json) or the code's own constants — none copied by hand to drift."""

import json
import subprocess
import sys

import pytest

from conftest import REPO

README_MAX_LINES = 120
RESULTS = REPO / "benchmarks" / "results"


def test_mkdocs_build_strict(tmp_path):
    # mkdocs comes with the test extra (`make test` installs it); missing, this fails with the import error
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
                          cwd=REPO, capture_output=True, text=True, env={**_env(), "NO_MKDOCS_2_WARNING": "1"})
    assert proc.returncode == 0, f"mkdocs build --strict failed:\n{proc.stderr}\n{proc.stdout}"
    assert "WARNING" not in proc.stderr, proc.stderr
    # the API reference shows every name a package exports (docs/griffe_reexports.py)
    html = (tmp_path / "site" / "api" / "hydro" / "index.html").read_text()
    assert 'id="hullopt.hydro.hydrostatics"' in html and 'id="hullopt.hydro.gz_curve"' in html
    # also where the names load on first use (their ``__init__.pyi`` lists them)
    html = (tmp_path / "site" / "api" / "study" / "index.html").read_text()
    assert 'id="hullopt.study.load_hull"' in html and 'id="hullopt.study.RunConfig"' in html
    html = (tmp_path / "site" / "api" / "report" / "index.html").read_text()
    assert 'id="hullopt.report.fmt"' in html and 'id="hullopt.report.write_report"' in html


def _env():
    import os

    # griffe reads this checkout's sources (mkdocs.yml: paths [.]); keep imports of hullopt on it too
    return {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}


def test_readme_is_short_and_keeps_the_two_commands():
    text = (REPO / "README.md").read_text()
    lines = text.splitlines()
    assert len(lines) <= README_MAX_LINES, f"README.md has {len(lines)} lines (at most {README_MAX_LINES})"
    assert "make demo" in text and "make test" in text
    assert "## Layout" in text  # the floors (tests/test_floors.py)
    for page in ("install", "cli", "configs", "methods", "python", "validation"):
        assert f"docs/{page}.md" in text, f"README links no docs/{page}.md"
        assert (REPO / "docs" / f"{page}.md").is_file()


def _sci(x: float, digits: int) -> str:
    """Scientific notation as the docs print it: 3.90e-3."""
    mantissa, exponent = f"{x:.{digits}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def _minus(s: str) -> str:
    return s.replace("-", "−")


def _pct(x: float) -> str:
    """A relative difference as the docs print it: +17 %, −5 %."""
    return _minus(f"{100 * x:+.0f} %")


def _quoted_numbers():
    """(page, text) pairs: each text is a sentence fragment of the page, built from the stored results."""
    models = json.loads((RESULTS / "panel.json").read_text())["models"]
    kcs = next(m for m in models if m["hull"] == "KCS (free)")
    dtmb = next(m for m in models if m["hull"] == "DTMB 5415" and m["fn"] == pytest.approx(0.28))

    def rel(m, key):
        return _pct(m[key] / m["ct_tank"] - 1)

    methods = "docs/methods.md"
    yield methods, (f"DTMB 5415 at Fn {dtmb['fn']:.2f}: the panel method's C_T {rel(dtmb, 'ct_panel')} against the "
                    f"tank's, Michell {rel(dtmb, 'ct_michell')}, Holtrop {rel(dtmb, 'ct_holtrop')}.")
    yield methods, (f"KCS at Fn {kcs['fn']:.2f}: {_sci(kcs['ct_tank'], 3)} measured, Holtrop {_sci(kcs['ct_holtrop'], 2)} "
                    f"({rel(kcs, 'ct_holtrop')}), Michell {_sci(kcs['ct_michell'], 2)}, panel {_sci(kcs['ct_panel'], 2)} "
                    f"(its C_W alone {_sci(kcs['cw_panel'], 1)}); its sinkage {1e3 * kcs['sinkage_model_m']:.1f} mm "
                    f"(tank {1e3 * kcs['sinkage_tank_m']:.1f} mm) and trim {_minus(format(kcs['trim_deg'], '.2f'))}° "
                    f"(tank {_minus(format(kcs['trim_tank_deg'], '.2f'))}°)")
    d41 = next(m for m in models if m["hull"] == "DTMB 5415" and m["fn"] == pytest.approx(0.41))
    yield methods, (f"Dawson's method: KCS {_sci(kcs['ct_dawson'], 2)} ({rel(kcs, 'ct_dawson')}), DTMB 5415 at Fn "
                    f"{dtmb['fn']:.2f} {rel(dtmb, 'ct_dawson')} and at Fn {d41['fn']:.2f} {rel(d41, 'ct_dawson')}; its "
                    f"KCS sinkage {1e3 * kcs['sinkage_dawson_model_m']:.1f} mm and trim "
                    f"{_minus(format(kcs['trim_dawson_deg'], '.2f'))}°.")

    # thresholds the docs state are the code's own
    from hullopt.resistance._calm import DISAGREE
    from hullopt.waves import MOTION_FN_MAX, MOTION_L_OVER_B_MIN

    yield methods, f"differ by more than {DISAGREE:g}× it warns"
    yield methods, f"holds to about Fn {MOTION_FN_MAX:g} on slender hulls; `motions` and `waves` warn beyond it (and below L/B {MOTION_L_OVER_B_MIN:g})"


QUOTED = list(_quoted_numbers())


@pytest.mark.parametrize(("page", "text"), QUOTED, ids=[f"{page}-{k}" for k, (page, _) in enumerate(QUOTED)])
def test_quoted_numbers_come_from_the_results(page, text):
    body = " ".join((REPO / page).read_text().split())  # line breaks in the page are spaces
    assert text in body, f"{page} should say (from the stored results or the code):\n{text}"
