"""``hullopt resistance``: Michell's R_w against the Wigley's closed forms, the Holtrop–Mennen parts adding up,
effective power, the table, and bad input."""

import json

import numpy as np
import pytest
from test_michell import wigley_reference

import hullopt.app.cli as cli

HULL = "builtin:wigley?L=100&B=10&T=6.25&D=10&n=101&m=33"
KNOT = 1852.0 / 3600.0


@pytest.fixture(autouse=True)
def _no_global_config(monkeypatch):
    monkeypatch.setattr(cli, "configure_jax", lambda: None)  # tests already run in float64


def run(capsys, *args):
    code = cli.main(["resistance", *args])
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.slow
def test_json_records(capsys):
    code, out, _ = run(capsys, HULL, "--speed", "14.59,18.28", "--json", "--method", "holtrop,michell")
    assert code == 0
    recs = json.loads(out)
    assert [r["speed_kn"] for r in recs] == [14.59, 18.28]
    for r in recs:
        for key in ("speed_kn", "fn", "r_wave_michell", "r_f", "form_factor", "r_w", "r_b", "r_tr", "r_a",
                    "r_total_holtrop", "r_total_michell", "p_e_holtrop", "p_e_michell"):
            assert key in r and np.isfinite(r[key])
        u = r["speed_kn"] * KNOT
        assert r["fn"] == pytest.approx(u / np.sqrt(9.80665 * 100.0), rel=1e-12)
        # Michell against the Wigley's closed forms (the sections of 101 × 33: 6e-4 below, test_michell)
        assert r["r_wave_michell"] == pytest.approx(wigley_reference(r["fn"]), rel=1e-3)
        # Holtrop–Mennen's total is the sum of its parts; the Michell total swaps in R_w for R_W + R_B + R_TR
        parts = r["form_factor"] * r["r_f"] + r["r_app"] + r["r_a"]
        assert r["r_total_holtrop"] == pytest.approx(parts + r["r_w"] + r["r_b"] + r["r_tr"], rel=1e-12)
        assert r["r_total_michell"] == pytest.approx(parts + r["r_wave_michell"], rel=1e-12)
        # ITTC 1957 friction by hand: C_F = 0.075/(log10 Rn − 2)², ν = 1.18831e-6 m²/s (ITTC, sea water at 15 °C)
        cf = 0.075 / (np.log10(u * 100.0 / 1.18831e-6) - 2.0) ** 2
        assert r["cf"] == pytest.approx(cf, rel=1e-12)
        assert r["p_e_holtrop"] == pytest.approx(r["r_total_holtrop"] * u, rel=1e-12)
        assert r["p_e_michell"] == pytest.approx(r["r_total_michell"] * u, rel=1e-12)


@pytest.mark.slow
def test_table_and_range(capsys):
    code, out, _ = run(capsys, "builtin:wigley?L=100&B=10&T=6.25&D=10&n=21&m=9", "--speed", "10:20:3",
                       "--levels", "9", "--method", "michell,holtrop")
    assert code == 0 and "Calm-water resistance" in out and "R_W Michell [kN]" in out and "20.00" in out
    assert "R_T H-M [kN]" in out and "panel" not in out


@pytest.mark.slow
def test_all_methods_plot_and_warning(capsys, tmp_path):
    """Every method on one convention (the totals differ in R_W only), the panel methods' sinkage and trim,
    the plots written (curves, Dawson's wave pattern), and the KCS's warning: Michell and the Kelvin panel
    method several times Holtrop–Mennen on a full bulbous hull, named as outside their validity; Dawson's
    method a third of the Kelvin one's or less, and not named."""
    code, out, err = run(capsys, "examples/hulls/kcs_model_closed_from_igs.stl.gz?scale=31.6&lpp=230", "--draft",
                         "10.8", "--speed", "20,24", "--json", "--plot", str(tmp_path / "r.png"), "--pattern",
                         str(tmp_path / "w.png"))
    assert code == 0 and (tmp_path / "r.png").stat().st_size > 10_000 and (tmp_path / "w.png").stat().st_size > 10_000
    for r in json.loads(out):
        base = r["form_factor"] * r["r_f"] + r["r_app"] + r["r_a"]
        for m in ("holtrop", "michell", "panel", "dawson"):
            assert r[f"r_total_{m}"] == pytest.approx(base + r[f"r_wave_{m}"], rel=1e-12)
        assert r["r_wave_panel"] > 3 * r["r_wave_holtrop"] and r["sinkage_panel"] > 0 and r["trim_panel"] < 0
        assert r["r_wave_dawson"] < r["r_wave_panel"] / 3 and r["sinkage_dawson"] > 0 and r["trim_dawson"] < 0
    assert "michell is outside its validity (Cb 0.64 with a bulb" in " ".join(err.split())
    assert "panel is outside its validity" in " ".join(err.split())
    assert "dawson is outside" not in " ".join(err.split()) and "immersed transom" not in err


@pytest.mark.slow
def test_free_runs_dawson_free_to_sink_and_trim(capsys):
    """``--free``: Dawson's method with the hull sunk and trimmed as its pressure finds (its own iterations, as
    the API's ``attitude``); the record says so. On the Wigley at Fn 0.43 it sinks deeper and trims further bow
    up than fixed (the tank's free model: tests/test_dawson.py), and its R_W grows."""
    args = ("builtin:wigley?L=100&B=10&T=6.25&D=10&n=41&m=17", "--speed", "26.5", "--method", "dawson", "--json")
    (fixed, _), (free, err) = ((json.loads(o)[0], e) for _, o, e in (run(capsys, *args, *x) for x in ((), ("--free",))))
    assert (fixed["dawson_free"], free["dawson_free"]) == (False, True)
    assert free["sinkage_dawson"] > fixed["sinkage_dawson"] > 0 and free["trim_dawson"] > fixed["trim_dawson"] > 0
    assert free["r_wave_dawson"] > 1.1 * fixed["r_wave_dawson"]
    assert "above the hull's top" not in err  # 3.75 m of freeboard
    # its deck at the draft (offsets that stop at the DWL): sunk, the waterline leaves the hull's sides
    _, _, err = run(capsys, args[0].replace("D=10", "D=6.25"), *args[1:], "--free")
    err = " ".join(err.split())
    assert "dawson --free at 26.5 kn: sunk" in err and "above the hull's top" in err, err


@pytest.mark.parametrize("args,needle", [
    ([HULL, "--speed", "-3"], "--speed"),
    ([HULL, "--speed", "ten"], "--speed"),
    ([HULL, "--speed", "1:2"], "--speed"),
    ([HULL, "--speed", "10", "--draft", "12"], "--draft"),
    ([HULL, "--speed", "10", "--levels", "1"], "--levels"),
    ([HULL, "--speed", "10", "--method", "cfd"], "--method"),
    ([HULL, "--speed", "10", "--plot", "r.txt"], "--plot"),
    ([HULL, "--speed", "10", "--pattern", "w.txt"], "--pattern"),
])
def test_bad_input_is_one_clear_line(capsys, args, needle):
    code, out, err = run(capsys, *args)
    assert code == 2 and needle in err and err.count("\n") == 1


@pytest.mark.slow
def test_run_report_warns_when_calm_methods_disagree():
    """A run's report warns when its parent's calm-water R_T by Holtrop–Mennen and by Michell differ by more
    than 1.5× (the KCS bow sweep over 22–26 kn: 1875 vs 4104 kN at 24 kn), naming Michell as outside its
    validity; not when they agree."""
    from hullopt.study import load_config
    from hullopt.models import load_hull
    from hullopt.resistance import holtrop_hull
    from hullopt.study._assess import calm_disagreement

    cfg, _ = load_config("configs/pareto_bow.toml")
    kcs = load_hull("examples/hulls/kcs_model_closed_from_igs.stl.gz?scale=31.6&lpp=230").sections
    objectives = {"calm_resistance": {"parent": 1875e3}, "calm_resistance_michell": {"parent": 4104e3}}
    (msg,) = calm_disagreement(cfg, objectives, holtrop_hull(kcs, 10.8))
    assert "by michell is 2.2×" in msg and "michell is outside its validity (Cb 0.6" in msg and "22–26 kn" in msg
    objectives["calm_resistance_michell"]["parent"] = 2500e3
    assert calm_disagreement(cfg, objectives, holtrop_hull(kcs, 10.8)) == []


def test_validity_warnings_are_true_once_and_at_their_speed():
    """Issue 62: a full hull without a bulb (a box: its FP section is all area, none of it a bulb) is not said
    to have one; a method outside its validity is said so once, at the speeds where it is, each with its own
    Froude number (Dawson's below Fn 0.20 at 12 kn, not at 14 kn); a disagreement names the method without
    repeating why."""
    import jax.numpy as jnp

    from hullopt.app.commands.resistance import disagreements, validity_warnings
    from hullopt.models import box, wigley
    from hullopt.resistance import holtrop_hull, outside_validity

    full = holtrop_hull(box(120.0, 20.0, 10.0, n=21), jnp.asarray(7.5))
    assert float(full.A_BT) > 0 and float(full.bulb) == 0.0
    fn = {12.0: 0.18, 14.0: 0.21}
    records = [{"speed_kn": kn, "fn": f, "r_wave_michell": 300e3, "r_total_michell": 900e3,
                "r_wave_dawson": 50e3, "r_total_dawson": 650e3} for kn, f in fn.items()]
    invalid = [outside_validity(full, r["fn"], r["fn"]) for r in records]
    msgs = validity_warnings(records, ("michell", "dawson"), invalid)
    assert len(msgs) == 2 and not any("bulb" in m for m in msgs), msgs
    assert msgs[0].startswith("michell is outside its validity (Cb 1.00: linear Kelvin waves")
    assert msgs[1].startswith("dawson is outside its validity at 12 kn (Fn 0.18: below Fn 0.20") and "14 kn" not in msgs[1]
    (msg,) = disagreements(records, ("michell", "dawson"), invalid)
    assert msg.startswith("R_W by michell is 6.0× the other's (michell vs dawson) at 12 kn (Fn 0.18)")
    assert "michell and dawson are outside their validity there" in msg and "Kelvin" not in msg
    # inside every method's validity: nothing to say
    slender = holtrop_hull(wigley(100.0, 10.0, 6.25, 10.0, n=21, m=9), jnp.asarray(6.25))
    assert float(slender.bulb) == 0.0
    assert validity_warnings(records, ("michell",), [outside_validity(slender, 0.25)] * 2) == []
