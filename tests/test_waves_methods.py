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


@pytest.mark.slow
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


@pytest.mark.slow
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
    _plot(tmp_path / "r.png", dict(hull="h", method="nmri", beam=10.0, lpp=100.0, draft=6.25, speed_kn=12.0,
                                   amplitude=1.0, lambda_over_l=x, k_aw=0.3,
                                   fn=0.2, bf=0.1, heading_deg=0.0, includes=includes("nmri", False),
                                   r_awm=0 * r, r_awr=r, r_aw=r))
    labels = [t.get_text() for t in figures[0].axes[0].get_legend().get_texts()]
    assert labels[0] == "nmri R_AW: reflection only (Bf)" and not any("motion part" in s for s in labels)
    title = figures[0].axes[0].get_title(loc="left")  # the speed, and how K_AW and σ_aw relate
    assert "12 kn (Fn 0.200)" in title and "σ_aw = R_AW/(ρgζ²B²/L)" in title and "= 5·K_AW" in title


# --------------------------------------------------------------------------------- the methods as classes

# The coarse Wigley (L 100, B 10, T 6.25 m) at 7.7 m/s: per method, Σ R_AWM and Σ R_AWR [N] over 5 ω × 4 headings
# (ζ_a 1.5 m, kyy 0.26, NMRI with its motion part), the sea-state mean's motion and reflection parts [N]
# (H_s 3 m, T_p 9 s, 0.3 rad; NMRI reflection only) long-crested and short-crested (cos-2s, s = 2), and Σ|break|
# [rad] of heading_breaks with aft="include" — as the functions gave them before the methods were classes
# (bit-identical then; compared here to 1e-13).
STORED = {
    "nmri": (797141.8295752843, 997884.3419177901, 0.0, 40681.13884737911, 0.0, 33436.08852500035,
             3.1415926535897936),
    "stawave1": (0.0, 572617.6890224803, 0.0, 28630.8844477198, 0.0, 24343.97369301446, 1.5707963267948966),
    "stawave2": (349380.9975986476, 470508.8727062625, 28898.929715606067, 18750.60873624706, 24571.884464051785,
                 15943.074571681947, 1.5707963267948966),
    "snnm": (1303753.0008821513, 529793.9986099134, 102301.20544097335, 6582.0832253189665, 90953.20179067319,
             10191.725224279813, 2.009034433890674),
}


@pytest.mark.parametrize("name", list(STORED))
@pytest.mark.slow
def test_method_class_gives_the_stored_values(name):
    """Each method through its class (regular waves, the sea-state mean long- and short-crested, the heading
    breaks) gives the values the functions gave before, and the public functions dispatch to it unchanged."""
    import equinox as eqx
    import jax.numpy as jnp

    from hullopt.models import wigley
    from hullopt.waves import WAVE_METHODS, mean_added_resistance, method_resistance

    hull = wigley(100.0, 10.0, 6.25, 10.0, n=21, m=11)
    t, u = 6.25, 7.7
    om, hd = jnp.linspace(0.4, 1.6, 5), jnp.array([0.0, 0.5, 1.2, 2.5])
    method = WAVE_METHODS[name]()
    r = eqx.filter_jit(lambda s: method(s, t, u, om, hd, 1.5, kyy=0.26))(hull)
    long = eqx.filter_jit(lambda s: method.mean(s, t, u, 3.0, 9.0, 0.3, motion=False, order=6))(hull)
    short = eqx.filter_jit(lambda s: method.mean(s, t, u, 3.0, 9.0, 0.3, spreading_s=2.0, motion=False, order=6,
                                                 n_dir=8))(hull)
    breaks = method.heading_breaks(hull, t, "include")
    got = (jnp.sum(r.motion), jnp.sum(r.reflection), long.motion, long.reflection, short.motion, short.reflection,
           jnp.sum(jnp.abs(breaks)))
    np.testing.assert_allclose(np.array([float(v) for v in got]), STORED[name], rtol=1e-13, atol=0)
    old = eqx.filter_jit(method_resistance)(name, hull, t, u, om, hd, 1.5, kyy=0.26)
    # one program against another: XLA may fuse them differently, to a few ulps
    np.testing.assert_allclose(old.motion, r.motion, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(old.reflection, r.reflection, rtol=1e-12, atol=1e-9)
    m = eqx.filter_jit(mean_added_resistance)(name, hull, t, u, 3.0, 9.0, 0.3, motion=False, order=6)
    np.testing.assert_allclose(float(m.total), float(long.total), rtol=1e-12)


def test_method_registry():
    """The registry: names in order, what each includes and where it applies; STAWAVE is 0 beyond ±45°; an
    unknown name is refused naming the methods."""
    import jax.numpy as jnp

    from hullopt.models import wigley
    from hullopt.waves import WAVE_METHODS, WaveMethod, method_resistance, wave_method

    assert METHODS == tuple(WAVE_METHODS) == ("nmri", "stawave1", "stawave2", "snnm")
    assert all(issubclass(c, WaveMethod) and c.name == k for k, c in WAVE_METHODS.items())
    assert WAVE_METHODS["stawave1"].includes == ("reflection",)
    assert all(WAVE_METHODS[k].includes == ("motion", "reflection") for k in ("nmri", "stawave2", "snnm"))
    assert wave_method("nmri").label(motion=False) == "reflection only (Bf)"
    assert wave_method("snnm").label(motion=False) == "motion + reflection, empirical"
    hd = jnp.array([0.0, 0.7, 0.9, jnp.pi])
    np.testing.assert_array_equal(wave_method("stawave2").valid(hd), [True, True, False, False])
    np.testing.assert_array_equal(wave_method("snnm").valid(hd), [True] * 4)
    hull = wigley(100.0, 10.0, 6.25, 10.0, n=21, m=5)
    for name in ("stawave1", "stawave2"):
        r = method_resistance(name, hull, 6.25, 7.7, jnp.array([0.6, 1.0]), hd)
        assert np.all(np.asarray(r.total)[:, ~np.asarray(wave_method(name).valid(hd))] == 0.0)
    with pytest.raises(ValueError, match="expected one of"):
        wave_method("sta")
