"""Automatic fairing: noise in the aft body is removed, a fair hull stays, particulars are held; CLI."""

import json

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from conftest import REPO
from hullopt.app.cli import main
from hullopt.fairing import count_inflections
from hullopt.geometry import coons_surface
from hullopt.hydro import hydrostatics
from hullopt.models import OffsetTable, coons_sections, offsets_to_sections, read_offsets
from hullopt.optimise import aft_body_noise, fair_offsets, fixed_offsets

L, B, T = 100.0, 10.0, 6.25


pytestmark = pytest.mark.slow  # minutes of solving: `make test-slow` (CI runs both)


def wigley_offsets(ns, nw):
    x, z = np.linspace(0, L, ns), np.linspace(0, T, nw)
    return x, z, (B / 2) * (1 - (2 * (x[:, None] - L / 2) / L) ** 2) * (1 - ((T - z[None, :]) / T) ** 2)


@pytest.fixture(autouse=True)
def _cache(tmp_path, monkeypatch):
    monkeypatch.setenv("HULLOPT_CACHE", str(tmp_path / "cache"))


@pytest.fixture(scope="module")
def noisy_case():
    x, z, y = wigley_offsets(31, 11)
    noisy = aft_body_noise(x, y, 0.05, seed=0, lpp=L)
    return x, z, y, noisy, fair_offsets(x, z, noisy, L, T)


def test_fixed_offsets_and_noise_region():
    t = read_offsets(str(REPO / "hullopt/data/offsets/seed003_table1.csv"))
    fixed = fixed_offsets(t.y)
    assert fixed[t.y == 0].all() and fixed[[0, -1]].all() and fixed[:, [0, -1]].all()
    assert fixed[t.y == t.y.max()].all() and not fixed[5, 5]  # flat of side fixed, a bilge offset free
    noisy = aft_body_noise(t.x, t.y, 0.05, seed=3, lpp=t.lpp)
    changed = noisy != t.y
    assert changed.any() and not (changed & fixed).any() and (t.x[changed.any(axis=1)] < 0.35 * t.lpp).all()
    assert (noisy >= 0.5 * t.y).all()


def test_fairing_removes_aft_body_noise_and_holds_the_particulars(noisy_case):
    x, z, y, noisy, res = noisy_case
    free = ~fixed_offsets(y)
    assert res.reduction > 0.99  # the knots measure falls by more than 99 %
    removed = 1 - np.sqrt(np.mean((res.y - y)[free] ** 2)) / np.sqrt(np.mean((noisy - y)[free] ** 2))
    assert removed > 0.5
    np.testing.assert_array_equal(res.y[~free], noisy[~free])  # contour, zeros held exactly
    assert res.max_move <= 0.05 * y.max() + 1e-12
    # particulars by a second model of the same offsets: the spline surface of the offset-table reader
    hydro = jax.jit(hydrostatics)  # compiled once for both tables: op by op took seconds a call

    def particulars(yy):
        h = hydro(offsets_to_sections(OffsetTable(x=x, z=z, y=yy, lpp=L), 121, 61), T)
        return float(h.volume), float(h.lcb)

    (v0, lcb0), (v1, lcb1) = particulars(noisy), particulars(res.y)
    assert abs(v1 / v0 - 1) < 1e-3 and abs(lcb1 - lcb0) / L < 5e-4
    assert abs(res.volume_change) < 1e-3 and abs(res.lcb_shift_pct) < 0.05


def test_a_fair_hull_stays_unchanged(noisy_case):
    # the noisy case's grid and solver settings: the same compiled solve (the draft is an input), run after it
    x, z, y = wigley_offsets(31, 11)
    res = fair_offsets(x, z, y, L, 0.8 * T)
    assert res.max_move < 1e-6 * B and res.after <= res.before + 1e-12


def test_bad_measure_and_nothing_free():
    x, z, y = wigley_offsets(7, 5)
    with pytest.raises(ValueError, match="unknown unfairness measure"):
        fair_offsets(x, z, y, L, T, "strain")
    with pytest.raises(ValueError, match="no free offsets"):
        fair_offsets(x, z, y, L, T, free=np.zeros_like(y, bool))


def test_coons_sections_hydrostatics_match_the_offset_model():
    x, z, y = wigley_offsets(21, 9)  # parabolic lines: the not-a-knot surface is the Wigley up to twist
    a = jax.jit(lambda yy: hydrostatics(coons_sections(coons_surface(jnp.asarray(x), jnp.asarray(z), yy), L, 81, 61), T))(
        jnp.asarray(y))
    exact_volume = (2 / 3) * (2 / 3) * L * B * T  # Wigley: Cb = 4/9
    assert float(a.volume) == pytest.approx(exact_volume, rel=2e-3)
    assert float(a.lcb) == pytest.approx(L / 2, abs=1e-9)


def run(capsys, *args):
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_cli_fair_report_files_and_offsets(capsys, tmp_path):
    out = tmp_path / "fair"
    code, text, err = run(capsys, "fair", "builtin:wigley?L=100&B=10&T=6.25&D=6.25&n=13&m=13", "--stations", "13",
                          "--waterlines", "7", "--noise", "0.05", "--seed", "2", "--out", str(out), "--json")
    assert code == 0, err
    rep = json.loads(text)
    assert rep == json.loads((out / "report.json").read_text())
    assert rep["measure"] == "knots" and rep["after"] < 0.01 * rep["before"]
    assert abs(rep["volume_change_pct"]) < 0.1 and abs(rep["lcb_shift_pct_lpp"]) < 0.05
    assert set(rep["measures"]) == {"knots", "lines", "jumps", "mean"} and 0 < rep["noise_removed"] <= 1
    for name in ("faired_offsets.csv", "body_plan.png", "curvature.png"):
        assert (out / name).stat().st_size > 0
    t = read_offsets(out / "faired_offsets.csv")
    assert t.lpp == 100 and t.y.shape == (13, 7) and np.abs(t.y - t.y.round(9)).max() < 1e-12
    code, text, err = run(capsys, "hydro", str(out / "faired_offsets.csv"), "--draft", "6.25", "--json")
    assert code == 0 and json.loads(text)["volume"] == pytest.approx(rep["volume_after"], rel=1e-9)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--measure", "strain"], "--measure 'strain'"),
        (["--draft", "9"], "--draft 9 m is outside"),
        (["--region", "a:b"], "--region 'a:b'"),
        (["--region", "200:300"], "no offset is free"),
        (["--max-move", "-1"], "--max-move"),
    ],
)
def test_cli_fair_bad_input(capsys, args, message):
    code, _, err = run(capsys, "fair", "builtin:wigley?L=100&B=10&T=6.25&D=6.25&n=9&m=9", "--stations", "7",
                       "--waterlines", "5", *args)
    assert code == 2 and message in err and err.count("\n") == 1


def test_cli_fair_needs_a_draft_and_refuses_knuckles(capsys, tmp_path):
    code, _, err = run(capsys, "fair", str(REPO / "hullopt/data/offsets/seed003_table1.csv"))
    assert code == 2 and "give --draft" in err
    csv = tmp_path / "k.csv"
    csv.write_text("# knuckles = 5@1\nx,0,1,2\n0,1,1,1\n5,1,2,2\n10,1,1,1\n")
    code, _, err = run(capsys, "fair", str(csv), "--draft", "1")
    assert code == 2 and "knuckles" in err


def test_cli_fair_keeps_the_seed003_table_a_ship(capsys, tmp_path):
    """The README's table faired with the defaults (issue: a 7.36 m bulge past the 7.2 m half-beam, S-shaped
    fore-body sections, negative offsets under --region, the cap reached silently with exit 0)."""
    table = REPO / "hullopt/data/offsets/seed003_table1.csv"
    t = read_offsets(table)
    for extra in ([], ["--region", "0:33"]):
        out = tmp_path / ("fair" + "_".join(extra).replace(":", "-"))
        code, text, err = run(capsys, "fair", str(table), "--draft", "5.6", "--out", str(out), "--json", *extra)
        rep = json.loads(text)
        f = read_offsets(out / "faired_offsets.csv")
        assert f.y.min() >= 0.0 and f.y.max() <= t.y.max()  # no negative offset, nothing wider than the ship
        assert abs(rep["volume_change_pct"]) < 0.5 and abs(rep["bwl_change_pct"]) < 0.5
        before, after = count_inflections(t.x, t.z, t.y), count_inflections(t.x, t.z, f.y, t.y)
        assert (after[0] <= before[0]).all() and rep["inflections"]["after"] == after[0].tolist()
        assert sum(after[0]) < sum(before[0])  # the table's own wiggles are faired out
        # the measure wants more than the 0.36 m cap allows: exit 5, the stations named, the file still written
        cap = np.abs(f.y - t.y).max(axis=1) >= 0.99 * rep["move_cap"]
        assert cap.any() and code == 5 and "moved by the cap" in err
        named = next(p for p in rep["problems"] if "moved by the cap" in p)
        assert all(f"{v:.4g}" in named for v in t.x[cap])
        code, text, _ = run(capsys, "hydro", str(out / "faired_offsets.csv"), "--draft", "5.6", "--json")
        assert code == 0 and json.loads(text)["volume"] == pytest.approx(rep["volume_after"], rel=1e-6)


def test_cli_fair_noisy_wigley_is_a_clean_wigley_again(capsys, tmp_path):
    """The README's demo: every inflection the noise put in a section is faired out and none is added;
    exit 0 with nothing to report."""
    out = tmp_path / "demo"
    code, text, err = run(capsys, "fair", "builtin:wigley?L=100&B=10&T=6.25&D=6.25", "--stations", "21",
                          "--waterlines", "9", "--noise", "0.05", "--out", str(out), "--json")
    rep = json.loads(text)
    assert code == 0 and rep["problems"] == [], err
    assert sum(rep["inflections"]["before"]) >= 10 and sum(rep["inflections"]["after"]) == 0
    assert rep["max_move"] < 0.99 * rep["move_cap"]
    assert abs(rep["volume_change_pct"]) < 0.1 and abs(rep["bwl_change_pct"]) < 0.5
