"""``hullopt waves --method all``: every added-resistance method side by side with what it includes, STAWAVE-1
against its closed form, the parts adding up, and a plot whose legend names what each curve is."""

import json

import numpy as np
import pytest

import hullopt.app.cli as cli
from hullopt.waves import METHODS

L, B, T = 120.0, 16.0, 6.0
HULL = f"builtin:wigley?L={L:g}&B={B:g}&T={T:g}&D=10&n=41&m=5"
ARGS = ["waves", HULL, "--speed", "12", "--hs", "3", "--tp", "8", "--lambda-over-l", "0.5:1.5:3", "--method", "all"]


@pytest.fixture(autouse=True)
def _no_global_config(monkeypatch):
    monkeypatch.setattr(cli, "configure_jax", lambda: None)  # tests already run in float64


def test_all_methods_side_by_side(capsys, monkeypatch):
    """JSON: one record per method with what it includes; STAWAVE-1 is ½ρgζ²B√(B/L_BWL) per wave and
    ρgH_s²B√(B/L_BWL)/16 in the sea state, with the Wigley's L_BWL = (L/2)(1 − √0.05) (stem to 95 % of the
    beam; the 41-station polyline within 0.1 %); motion + reflection = total for each; NMRI counts its motions."""
    assert cli.main([*ARGS, "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["method"] == "all" and list(d["methods"]) == list(METHODS)
    rho, g = 1025.0, 9.80665
    l_bwl = 0.5 * L * (1 - np.sqrt(0.05))
    per_wave = 0.5 * rho * g * B * np.sqrt(B / l_bwl)
    s1 = d["methods"]["stawave1"]
    np.testing.assert_allclose(s1["r_aw"], per_wave, rtol=1e-3)
    np.testing.assert_allclose(s1["mean_raw"], rho * g * 3.0**2 * B * np.sqrt(B / l_bwl) / 16, rtol=1e-3)
    assert s1["includes"] == "reflection only, empirical" and s1["mean_raw_motion"] == 0.0
    for m, r in d["methods"].items():
        np.testing.assert_allclose(np.add(r["r_awm"], r["r_awr"]), r["r_aw"], rtol=1e-12)
        np.testing.assert_allclose(r["mean_raw_motion"] + r["mean_raw_reflection"], r["mean_raw"], rtol=1e-12)
    nmri = d["methods"]["nmri"]
    assert nmri["includes"] == "motion (strip theory) + reflection (Bf)" and nmri["mean_raw_motion"] > 0
    assert d["methods"]["snnm"]["includes"] == d["methods"]["stawave2"]["includes"] == "motion + reflection, empirical"


def test_all_methods_table_and_plot_legend(capsys, monkeypatch, tmp_path):
    """The table lists every method with what it includes and its mean R_AW [kN]; the plot's legend (outside the
    axes) names each curve: the method's total and what it counts, NMRI's two parts and its short-wave level."""
    import hullopt.drawing

    figures, save = [], hullopt.drawing.save_figure

    def keep(fig, path, **kw):
        fig.canvas.draw()
        figures.append((fig, fig.canvas.get_renderer()))
        return save(fig, path, **kw)

    monkeypatch.setattr(hullopt.drawing, "save_figure", keep)
    png = tmp_path / "raw.png"
    assert cli.main([*ARGS, "--plot", str(png)]) == 0
    out = capsys.readouterr().out
    assert png.stat().st_size > 1000
    assert "By method: mean R_AW, Hs 3 m, Tp 8 s" in out and "R_AW [kN]" in out and "reflection [kN]" in out
    for m in METHODS:
        line = next(ln for ln in out.splitlines() if ln.strip("│ ").startswith(m + " "))
        assert ("motion (strip theory) + reflection (Bf)" if m == "nmri" else
                "reflection only, empirical" if m == "stawave1" else "motion + reflection, empirical") in line
    assert "README" in out  # where to read which method to use when
    ((fig, renderer),) = figures
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["nmri R_AW: motion (strip theory) + reflection (Bf)",
                      "nmri motion part R_AWM (strip theory)",
                      "nmri reflection part R_AWR (Bf formula)",
                      "stawave1 R_AW: reflection only, empirical",
                      "stawave2 R_AW: motion + reflection, empirical",
                      "snnm R_AW: motion + reflection, empirical",
                      labels[-1]]
    assert labels[-1].startswith("NMRI short-wave reflection K_AW(Bf) = ")
    assert ax.get_legend().get_window_extent(renderer).x0 >= ax.get_window_extent(renderer).x1 - 1
    assert ax.get_xlabel() == "λ / L [-]" and ax.get_ylabel().startswith("K_AW = R_AW / (½ρgζ²B)")


def test_one_method_says_what_it_includes(capsys):
    assert cli.main(["waves", HULL, "--speed", "12", "--method", "stawave1", "--lambda-over-l", "0.5:1:2"]) == 0
    out = capsys.readouterr().out
    assert "includes" in out and "reflection only, empirical" in out


def test_nmri_without_motions_is_named_reflection_only(tmp_path, monkeypatch):
    """--no-motion: NMRI's R_AW is its reflection part, and the table and the legend say so (not 'total')."""
    import hullopt.drawing
    from hullopt.app.commands.waves import _plot, includes

    assert includes("nmri", motion=False) == "reflection only (Bf)"
    figures, save = [], hullopt.drawing.save_figure
    monkeypatch.setattr(hullopt.drawing, "save_figure", lambda fig, path, **kw: (figures.append(fig),
                                                                                 save(fig, path, **kw))[1])
    x = np.array([0.5, 1.0, 1.5])
    r = 1e4 * np.exp(-x)
    _plot(tmp_path / "r.png", dict(hull="h", method="nmri", beam=10.0, amplitude=1.0, lambda_over_l=x, k_aw=0.3,
                                   fn=0.2, bf=0.1, heading_deg=0.0, includes=includes("nmri", False),
                                   r_awm=0 * r, r_awr=r, r_aw=r))
    labels = [t.get_text() for t in figures[0].axes[0].get_legend().get_texts()]
    assert labels[0] == "nmri R_AW: reflection only (Bf)" and not any("motion part" in s for s in labels)
