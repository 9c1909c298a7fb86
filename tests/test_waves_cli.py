"""``hullopt waves``: JSON keys and values against the API, the plot, the claim-6 program, and bad input."""

import json

import numpy as np
import pytest

import hullopt.app.cli as cli
from hullopt.models import wigley
from hullopt.waves import bluntness, mean_added_resistance

HULL = "builtin:wigley?L=120&B=16&T=6&D=10&n=41&m=5"


@pytest.fixture(autouse=True)
def _no_global_config(monkeypatch):
    monkeypatch.setattr(cli, "configure_jax", lambda: None)  # tests already run in float64


def run(capsys, *args):
    code = cli.main(["waves", HULL, *args])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.slow
def test_json_matches_api(capsys):
    code, out, _ = run(capsys, "--speed", "15", "--heading", "20", "--hs", "3", "--tp", "8",
                       "--lambda-over-l", "0.5:1.5:3", "--json", "--blunt-bow", "0.5,2", "--no-motion")
    assert code == 0
    d = json.loads(out)
    for key in ("bf", "fn", "c_u", "k_aw", "r_awr", "mean_raw", "program"):
        assert key in d
    s = wigley(120.0, 16.0, 6.0, 10.0, n=41, m=5)
    u = 15 * 1852 / 3600
    np.testing.assert_allclose(d["bf"], bluntness(s, 6.0, np.radians(20.0)), rtol=1e-12)
    np.testing.assert_allclose(d["fn"], u / np.sqrt(9.80665 * 120), rtol=1e-12)
    np.testing.assert_allclose(d["k_aw"], d["bf"] * (1 + max(68 - 310 * d["bf"], 10) * d["fn"]), rtol=1e-12)
    assert len(d["r_awr"]) == 3 and np.all(np.diff(d["r_awr"]) < 0)  # longer waves reflect less
    ref = mean_added_resistance("nmri", s, 6.0, u, 3.0, 8.0, np.radians(20.0), motion=False)
    np.testing.assert_allclose(d["mean_raw"], ref.total, rtol=1e-12)
    p = d["program"]
    assert p["params"] == [None, 0.5, 2.0] and p["best"] == int(np.argmin(p["k_aw"]))


@pytest.mark.slow
def test_other_methods_and_plot(capsys, tmp_path):
    png = tmp_path / "raw.png"
    code, out, _ = run(capsys, "--speed", "12", "--method", "snnm", "--json", "--plot", str(png))
    assert code == 0 and png.stat().st_size > 1000
    d = json.loads(out)
    np.testing.assert_allclose(np.add(d["r_awm"], d["r_awr"]), d["r_aw"], rtol=1e-12)
    code, out, _ = run(capsys, "--speed", "12", "--method", "stawave2", "--hs", "2", "--tp", "7")
    assert code == 0 and "mean R_AW" in out


@pytest.mark.parametrize("args,needle", [
    (["--speed", "-3"], "--speed"),
    (["--speed", "10", "--hs", "-1", "--tp", "8"], "--hs"),
    (["--speed", "10", "--hs", "2", "--tp", "0"], "--tp"),
    (["--speed", "10", "--hs", "2"], "--tp"),
    (["--speed", "10", "--heading", "400"], "--heading"),
    (["--speed", "10", "--draft", "12"], "--draft"),
    (["--speed", "10", "--method", "faltinsen"], "--method"),
    (["--speed", "10", "--lambda-over-l", "0:1:3"], "--lambda-over-l"),
    (["--speed", "10", "--blunt-bow", "-2"], "--blunt-bow"),
    (["--speed", "10", "--no-motion", "--plot", "/no/such/dir/x.png"], "--plot"),
])
def test_bad_input_is_one_clear_line(capsys, args, needle):
    code, out, err = run(capsys, *args)
    assert code == 2 and needle in err and err.count("\n") == 1


def test_a_method_outside_its_headings_warns_instead_of_a_silent_zero(capsys):
    """STAWAVE-2 holds within ±45° of the bow: at 90° the command says so (its 0 kN is no result); at 30° not."""
    code, _, err = run(capsys, "--speed", "15", "--heading", "90", "--method", "stawave2", "--lambda-over-l",
                       "1:1:1", "--json")
    assert code == 0 and "stawave2 applies within ±45° of the bow only" in " ".join(err.split()), err
    code, _, err = run(capsys, "--speed", "15", "--heading", "30", "--method", "stawave2", "--lambda-over-l",
                       "1:1:1", "--json")
    assert code == 0 and "applies" not in err, err
