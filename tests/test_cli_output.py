"""What a user reads: units in every --help and table, numbers without round-off noise or scientific notation,
tables within 100 columns, --version, and exit codes a script can gate on (4: stability criteria fail,
5: fairing not converged)."""

import json
import re
import sys
from importlib.metadata import version

import numpy as np
import pytest
from rich.cells import cell_len

from hullopt.app import output
from hullopt.app.output import EXIT_CODES
from hullopt.report import change, fmt, quantity

BOX = "builtin:box?L=100&B=20&D=10"
WIGLEY = "builtin:wigley?L=100&B=10&T=6.25&D=10&n=21&m=41"
SCI = re.compile(r"\d[eE][+-]?\d")  # 5.2e+04, 7.105e-15


@pytest.fixture
def wide(monkeypatch):
    """The console 100 columns wide, whatever the terminal or $COLUMNS of the test run."""
    monkeypatch.setattr(output.console, "width", 100)


def _plain(text: str) -> str:
    """Help text without its box drawing, whitespace collapsed (rich wraps long help over lines)."""
    return " ".join(re.sub(r"[│╭╮╰╯─]", " ", text).split())


# ----------------------------------------------------------------------------------------------- numbers


@pytest.mark.parametrize("value, kwargs, text", [
    (-7.105e-15, {}, "0"),                      # LCB % Lpp of a symmetric hull: round-off
    (-1.222e-18, {"ref": 6.1}, "0.000"),        # GZ at 0° in a column of metres
    (3.395e-15, {"ref": 1.0}, "0.000"),         # trim [°]
    (52083.3, {}, "52083"),                     # ∇ [m³], was 5.2e+04
    (14270.6, {}, "14271"),
    (0.444444, {}, "0.4444"),
    (-1.16912, {}, "-1.169"),
    (-0.0004, {"ref": 2.0}, "0.000"),           # never "-0.000"
    (2.5e-7, {}, "2.500e-07"),                  # a genuinely small quantity keeps its digits
    (float("nan"), {}, "–"),
    (None, {}, "–"),
    (7, {}, "7"),
    (True, {}, "yes"),
])
def test_fmt(value, kwargs, text):
    assert fmt(value, **kwargs) == text


def test_quantity_and_change():
    assert quantity(52083.3, "m³") == "52083 m³"
    assert quantity(-7.1e-15, "% Lpp", ref=1) == "0.000 % Lpp"
    assert quantity(12.5, "°", 3) == "12.5°"
    assert change(13453.2, 5856.81, "N") == "13453 → 5857 N (-56.47 %)"


def test_table_shares_decimals_per_column_and_fits_100_columns(capsys, wide):
    output.table("GZ curve [m]", ["heel [°]", "GZ [m]", "KN [m]"],
                 [["0", -3.4e-18, -3.4e-18], ["30", 1.1824, 2.68213], ["90", 2.875, 5.875]])
    text = capsys.readouterr().out
    assert "GZ curve [m]" in text and "heel [°]" in text and "GZ [m]" in text  # brackets are no markup
    assert "0.000" in text and "1.182" in text and "2.682" in text and not SCI.search(text)
    output.table("many columns", ["quantity", *(f"{t:.3f} m" for t in range(1, 15))],
                 [["Volume ∇ [m³]", *(1234.5 * t for t in range(1, 15))]], by="row")
    text = capsys.readouterr().out
    assert max(cell_len(line) for line in text.splitlines()) <= 100 and text.count("Volume ∇ [m³]") >= 2
    output.table("", ["only column"], [["x"]])  # nothing to split
    assert "only column" in capsys.readouterr().out


# ----------------------------------------------------------------------------------------------- help


def test_every_help_keeps_its_units(cli):
    """Each command's help prints every bracketed unit of its source (rich markup would eat ``[kn]``)."""
    import typer.main

    from hullopt.app._app import app
    from hullopt.app.commands import COMMANDS, register

    register([])
    group = typer.main.get_command(app)
    checked = 0
    for name in COMMANDS:
        code, out, _ = cli(name, "--help")
        assert code == 0
        text = _plain(out)
        for p in group.commands[name].params:
            for unit in re.findall(r"\[[^\]]+\]", (p.help or "").replace("\\[", "[")):
                assert _plain(unit) in text, (name, p.name, unit)
                checked += 1
    assert checked >= 20
    code, out, _ = cli("waves", "--help")
    assert "Ship speed [kn]" in _plain(out) and "Wave heading [deg]" in _plain(out)
    code, out, _ = cli("hydro", "--help")
    assert "Draft above the baseline [m]" in _plain(out) and "Water density [kg/m³]" in _plain(out)


def test_top_help_states_json_units_and_exit_codes(cli):
    code, out, _ = cli("--help")
    text = _plain(out)
    assert code == 0 and "SI units" in text and "_deg is in degrees" in text and "--version" in text
    for k, meaning in EXIT_CODES.items():
        assert f"{k} {_plain(meaning)}" in text
    assert EXIT_CODES[3].startswith("run, merge") and 4 in EXIT_CODES and 5 in EXIT_CODES


def test_version(cli):
    code, out, _ = cli("--version")
    assert code == 0 and out.strip() == f"hullopt {version('hullopt')}"


# ----------------------------------------------------------------------------------------------- tables


def test_console_width_follows_columns(monkeypatch):
    """$COLUMNS sets the width (rich reads it); off a terminal without it, tables are laid out for 100."""
    monkeypatch.setenv("COLUMNS", "100")
    assert output.Console(width=output._width()).width == 100
    monkeypatch.delenv("COLUMNS")
    monkeypatch.setattr(sys.stdout, "isatty", lambda: False, raising=False)
    assert output._width() == 100


@pytest.mark.slow
def test_hydro_table_units_no_noise_within_100_columns(cli, wide):
    """Units on every row, LCB of a symmetric hull 0.000, no scientific notation, nothing truncated, and more
    drafts than fit in 100 columns split into tables that repeat the labels."""
    code, text, err = cli("hydro", WIGLEY, "--drafts", "1:6:9")
    assert code == 0, err
    assert max(cell_len(line) for line in text.splitlines()) <= 100
    assert not SCI.search(text) and "…" not in text
    for label in ("Volume ∇ [m³]", "Displacement Δ [t]", "LCB from midship [% Lpp]", "TPC [t/cm]", "KB [m]"):
        assert text.count(label) == 2, label  # two tables, labels repeated
    lcb = [line for line in text.splitlines() if "LCB from midship" in line]
    assert all(set(re.findall(r"-?\d+\.\d+", line)) == {"0.000"} for line in lcb)
    assert re.search(r"Draft T \[m\] +│ +1\.000 │", text)  # lengths to the mm


@pytest.mark.slow
def test_stability_exit_code_and_table(cli, wide):
    """IS Code criteria failing → exit code 4 (0 when all pass); the table has units and no round-off noise."""
    args = ["stability", BOX, "--displacement", "8200", "--heels", "0:60:4"]
    code, out, err = cli(*args, "--kg", "6")
    assert code == 0, err
    assert "GZ [m]" in out and "KN [m]" in out and "m·rad" in out and "pass" in out and "FAIL" not in out
    assert not SCI.search(out) and max(cell_len(line) for line in out.splitlines()) <= 100
    code, out, err = cli(*args, "--kg", "12", "--kg-above-deck")  # GM₀ < 0: every criterion fails
    assert code == 4 and "FAIL" in out and "criteria fail" in out and "exit code 4" in out
    assert "GZmax 0.000 m" in out and "-0.000" not in out
    code, out, _ = cli(*args, "--kg", "12", "--kg-above-deck", "--json")
    assert code == 4 and not all(c["pass"] for c in json.loads(out)["criteria"])  # stdout stays JSON


@pytest.mark.slow
def test_fair_not_converged_exit_code(cli, capsys, monkeypatch, wide):
    """A fairing that stops short of convergence exits 5 and says so on stderr; its report says "converged":
    false; the table of the report has its units and no scientific notation."""
    from hullopt.app.commands import fair as fair_cmd
    from hullopt.optimise import FairResult

    def stopped(x, z, y, *args, **kwargs):  # the solver's result when it runs out of steps: the offsets unfaired
        y = np.asarray(y)
        counts = (np.zeros(y.shape[0], int), np.zeros(y.shape[1], int))
        return FairResult(y=y, y0=y, free=np.ones(y.shape, bool), measure="knots", before=1.0, after=1.0,
                          volume0=1.0, volume=1.0, lcb0=0.0, lcb=0.0, lpp=100.0, steps=2, converged=False,
                          bound=0.25, inflections0=counts, inflections=counts)

    monkeypatch.setattr(fair_cmd, "fair_offsets", stopped)
    code, out, err = cli("fair", "builtin:wigley?L=100&B=10&T=6.25&D=6.25&n=9&m=9", "--stations", "7",
                         "--waterlines", "5", "--noise", "0.05", "--json")
    report = json.loads(out)
    assert code == 5 and report["converged"] is False and "did not converge" in err and "exit code 5" in err
    fair_cmd._print_fair(report)
    text = capsys.readouterr().out
    assert "volume ∇ [m³]" in text and "LCB [m from AP]" in text and "change [%]" in text
    assert not SCI.search(text) and max(cell_len(line) for line in text.splitlines()) <= 100


def test_run_summary_parent_to_design_with_units_and_warnings(capsys, wide):
    """The summary of ``hullopt run`` from a report: targets and particulars parent → design with units, the
    objective in kN, and the report's warnings on stderr."""
    from hullopt.app.commands.run import summary

    parent = {"displacement": 2844021.0, "volume": 2774.6, "cb": 0.444201, "lcb_pct": 2.3e-15, "kb": 3.907}
    design = {"displacement": 2843900.0, "volume": 2774.5, "cb": 0.444210, "lcb_pct": -1.79e-9, "kb": 3.7986}
    report = {
        "kind": "minimise", "converged": False, "met": False, "iterations": 42,
        "targets": {"cb": {"target": 0.444201, "achieved": 0.44421, "error": 9e-6, "tolerance": 1e-4, "met": True},
                    "volume": {"target": 2774.59, "achieved": 2774.5, "error": -3.2e-5, "tolerance": 5e-4,
                               "met": True},
                    "lcb_pct": {"target": 0.0, "achieved": 0.03, "error": 0.03, "tolerance": 0.01, "met": False}},
        "objective": {"name": "mean_added_resistance", "value": 5856.81, "parent": 13453.2},
        "message": "the targets cannot be met within the bounds: lcb_pct is off by 0.03 (tolerance 0.01)",
        "warnings": ["a warning the report holds"], "parent": parent, "achieved": design,
    }
    summary(report, output.Path("runs/x"))
    out, err = capsys.readouterr()
    text = " ".join(out.split())
    assert "Displacement Δ [t] │ 2844.0 │ 2843.9" in text and "Volume ∇ [m³]" in text and "KB [m]" in text
    assert "mean added resistance R_AW [kN] │ 13.453 │ 5.857 │ -7.596 │ -56.5" in text
    assert "LCB from midship [% Lpp] │ 0.0000 │ 0.0000" in text and not SCI.search(out)
    assert "a warning the report holds" in err and "cannot be met" in err
    assert max(cell_len(line) for line in out.splitlines()) <= 100


def test_pareto_summary_names_a_calm_water_profile(capsys, wide):
    """The printed Pareto table of a calm-water operating profile (no sea state) names Michell's calm-water R_T,
    not "R_T + R_AW" (issue 62): its header and title follow the report's ``objective.about``."""
    from hullopt.app.commands.run import summary

    designs = [{"bf_target": 0.06 + 0.001 * i, "measure": 2.2e5 - 1e3 * i, "objective": 4.3e6 + 1e4 * i,
                "met": True, "pareto": True} for i in range(2)]
    report = {"kind": "pareto", "designs": designs, "pareto_count": 2, "warnings": [],
              "objective": {"name": "profile_resistance", "measure": "mean_added_resistance",
                            "about": {"name": {"method": "michell", "waves": False},
                                      "measure": {"method": None, "waves": None}}}}
    summary(report, output.Path("runs/x"))
    text = " ".join(capsys.readouterr().out.split())
    assert "operating profile calm-water R_T (Michell)" in text and "R_T (profile, Michell) [kN]" in text
    assert "R_T + R_AW" not in text


def test_every_file_written_is_said_in_one_format(capsys, tmp_path, monkeypatch):
    """``wrote PATH`` or ``wrote PATH (detail)``, one line a file, on stdout — on stderr beside a command's JSON
    (issue 62: only ``stability`` said so); ``resistance --plot`` says it too."""
    from hullopt.app.output import wrote

    wrote(tmp_path / "a.png")
    wrote(tmp_path / "b.csv", "stations layout")
    wrote(tmp_path / "c.png", json=True)
    out, err = capsys.readouterr()
    assert out.splitlines() == [f"wrote {tmp_path / 'a.png'}", f"wrote {tmp_path / 'b.csv'} (stations layout)"]
    assert err.splitlines() == [f"wrote {tmp_path / 'c.png'}"]
    import hullopt.app.cli as cli
    import hullopt.report

    monkeypatch.setattr(cli, "configure_jax", lambda: None)
    monkeypatch.setattr(hullopt.report, "plot_resistance", lambda records, methods, path, title="": path)
    code = cli.main(["resistance", "builtin:wigley?L=100&B=10&T=6.25&D=10&n=21&m=9", "--speed", "15", "--levels", "5",
                     "--method", "holtrop", "--json", "--plot", str(tmp_path / "r.png")])
    out, err = capsys.readouterr()
    assert code == 0 and f"wrote {tmp_path / 'r.png'}" in err and "wrote" not in out
