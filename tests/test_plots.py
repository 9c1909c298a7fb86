"""Plots a naval architect would print: each renders with its labels (axis labels with units, titles, station and
waterline labels, the DWL, a title block whose scale is the one drawn, legends outside the curves, distinct
colours), checked on the matplotlib figures the plot functions save, built from small hulls."""

from pathlib import Path

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.geometry import Sections
from hullopt.models import wigley

L, B, T, D = 100.0, 10.0, 6.25, 10.0


@pytest.fixture(scope="module")
def hull():
    return wigley(L, B, T, D, n=21, m=21)


@pytest.fixture
def drawn(monkeypatch):
    """The figures saved through drawing.save_figure (drawn, then saved as usual): a list."""
    import hullopt.drawing
    from hullopt.drawing import _curves, _save, _sheet
    from hullopt.report import _plots

    figures, save = [], _save.save_figure

    def keep(fig, path, **kw):
        fig.canvas.draw()
        fig.test_renderer = fig.canvas.get_renderer()  # kept: closing the figure takes its canvas
        figures.append(fig)
        return save(fig, path, **kw)

    for mod in (hullopt.drawing, _curves, _sheet, _plots):
        monkeypatch.setattr(mod, "save_figure", keep)
    return figures


def texts(fig) -> list[str]:
    """Every text of a figure: titles, axis labels, annotations, legend entries, figure texts."""
    return [t.get_text() for t in fig.findobj(lambda a: hasattr(a, "get_text")) if t.get_text()]


def outside(fig, legend, ax) -> bool:
    """The legend's box lies right of the axes' box (no overlap with the curves)."""
    r = fig.test_renderer
    return legend.get_window_extent(r).x0 >= ax.get_window_extent(r).x1 - 1.0


def test_hydrostatic_curves_in_panels_by_unit(hull, tmp_path, drawn):
    """Eight panels sharing the draft axis, each with its unit; the deck draft left out; Δ at the design draft is
    the Wigley's closed form ρ·(4/9)·LBT (the 21 × 21 polygons: −0.0625 %)."""
    import jax

    from hullopt.drawing import plot_hydrostatic_curves
    from hullopt.hydro import hydrostatic_table

    drafts = jnp.asarray([2.0, 4.0, T, 8.0, D])
    plot_hydrostatic_curves(jax.jit(hydrostatic_table)(hull, drafts), tmp_path / "h.png", "wigley", depth=D,
                            design_draft=T)
    (fig,) = drawn
    axes = [ax for ax in fig.axes if ax.get_ylabel() or ax.get_xlabel()]
    assert len([ax for ax in axes if ax.get_title(loc="left")]) == 8
    xlabels = [ax.get_xlabel() for ax in axes]
    for unit in ("Δ [t]", "area [m²]", "TPC [t/cm]", "MCT 1 cm [t·m/cm]", "x from AP [m]", "BM_L [m]",
                 "coefficient [-]"):
        assert unit in xlabels, (unit, xlabels)
    assert "∇ [m³]" in texts(fig)  # the displacement panel's top axis
    assert "draft T [m]" in [ax.get_ylabel() for ax in axes]
    disp = next(ax for ax in axes if ax.get_xlabel() == "Δ [t]")
    (line,) = [ln for ln in disp.get_lines() if ln.get_label() == "Δ"]
    t = np.asarray(line.get_ydata())
    assert t.max() < D and len(t) == 4  # the deck draft is not drawn
    closed = 1.025 * 4 / 9 * L * B * T
    assert line.get_xdata()[list(t).index(T)] == pytest.approx(closed, rel=1.5e-3)
    assert any(s.startswith("DWL 6.25") for s in texts(fig))
    assert "Hydrostatic curves — wigley" in texts(fig)


def test_a_curve_constant_but_for_round_off_is_drawn_as_constant(hull, tmp_path, drawn):
    """The symmetric Wigley's LCB and LCF are L/2 at every draft to round-off: their panel spans ±5 % of L/2,
    not the last digits on an axis offset by 50 m (how one compiled table drew it)."""
    import jax

    from hullopt.drawing import plot_hydrostatic_curves
    from hullopt.hydro import hydrostatic_table

    table = jax.jit(hydrostatic_table)(hull, jnp.asarray([2.0, 4.0, T, 8.0]))
    noisy = eqx.tree_at(lambda h: h.lcb, table, table.lcb + jnp.asarray([0.0, 1e-11, -2e-11, 3e-11]))
    plot_hydrostatic_curves(noisy, tmp_path / "h.png", "wigley", depth=D)
    (fig,) = drawn
    (ax,) = [ax for ax in fig.axes if ax.get_xlabel() == "x from AP [m]"]
    assert ax.get_xlim() == pytest.approx((0.95 * L / 2, 1.05 * L / 2))
    varying = next(ax for ax in fig.axes if ax.get_xlabel() == "Δ [t]")
    assert varying.get_xlim()[1] - varying.get_xlim()[0] > 0.5 * float(table.displacement[-1]) / 1e3


def test_cross_curves_distinct_colours_legend_outside(tmp_path, drawn):
    """19 heels: 19 different colours, each curve labelled at its end, the legend right of the axes."""
    from hullopt.drawing import plot_cross_curves

    heels = np.deg2rad(np.arange(0.0, 95.0, 5.0))
    disp = np.array([1000.0, 2000.0, 3000.0])
    kn = np.sin(heels)[None, :] * np.array([3.0, 2.5, 2.2])[:, None]
    plot_cross_curves(disp, heels, kn, tmp_path / "kn.png", "box")
    (fig,) = drawn
    ax = fig.axes[0]
    lines = ax.get_lines()
    assert len(lines) == 19
    colours = {tuple(np.round(np.asarray(ln.get_color(), float), 6)) for ln in lines}
    assert len(colours) == 19
    assert outside(fig, ax.get_legend(), ax)
    assert ax.get_xlabel() == "displacement Δ [t]" and ax.get_ylabel() == "KN [m]"
    assert {f"{h:g}°" for h in np.rad2deg(heels)} <= set(texts(fig))


def test_body_plans_title_stations_and_dwl(hull, tmp_path, drawn):
    from hullopt.report import plot_body_plans

    after = Sections(hull.x, hull.yz * jnp.array([1.1, 1.0]), hull.lpp)
    plot_body_plans(hull, after, Path(tmp_path / "b.png"), draft=T, title="Body plan: run x")
    (fig,) = drawn
    ax = fig.axes[0]
    assert ax.get_title(loc="left") == "Body plan: run x"
    assert sorted(int(t.get_text()) for t in ax.texts) == list(range(11))
    assert "[m]" in ax.get_xlabel() and "[m]" in ax.get_ylabel()
    assert "DWL T = 6.25 m" in [t.get_text() for t in ax.get_legend().get_texts()]
    assert outside(fig, ax.get_legend(), ax)


def test_convergence_shows_objective_and_violation_on_log_scales(tmp_path, drawn):
    from hullopt.report import plot_convergence

    f, v = np.array([1.0, 0.8, 0.7, 0.69]), np.array([3.0, 0.5, 1e-3, 1e-6])
    plot_convergence(f, tmp_path / "c.png", "augmented-Lagrangian round", violation=v)
    (fig,) = drawn
    top, bottom = fig.axes
    assert top.get_yscale() == bottom.get_yscale() == "log"
    assert "objective" in top.get_ylabel() and "violation" in bottom.get_ylabel()
    np.testing.assert_array_equal(top.get_lines()[0].get_ydata(), [1.0, *f])  # round 0: the parent, 1
    np.testing.assert_array_equal(top.get_lines()[0].get_xdata(), np.arange(5))
    np.testing.assert_array_equal(bottom.get_lines()[0].get_ydata(), v)
    np.testing.assert_array_equal(bottom.get_lines()[0].get_xdata(), np.arange(1, 5))
    assert bottom.get_xlabel() == "augmented-Lagrangian round"
    assert any(np.all(np.asarray(ln.get_ydata()) == 1.0) for ln in bottom.get_lines())  # the tolerance line
    # a fit: the cost from the start (step 0), levelling off at the smoothness penalty, and what converges
    cost, err = np.array([4.0, 1.0, 0.1, 0.09, np.nan]), np.array([2.0, 1.0, 0.3, 0.01, np.nan])
    plot_convergence(cost, tmp_path / "fit.png", "Levenberg–Marquardt step", violation=err, fit=True)
    top, bottom = drawn[1].axes
    np.testing.assert_array_equal(top.get_lines()[0].get_xdata(), np.arange(4))
    np.testing.assert_array_equal(bottom.get_lines()[0].get_ydata(), err[:4])
    assert "target error" in bottom.get_ylabel() and top.get_title(loc="left") == "Convergence of the fit"


def test_pareto_in_kn_with_bf_labels(tmp_path, drawn):
    """Forces in kN (N / 1000), each design's Bf to 4 significant digits once, a title that says what is plotted."""
    from hullopt.report import plot_pareto

    bf = [0.3, 0.3125, 0.325, 0.3375]  # two decimals would make 0.31/0.31 and 0.33/0.34, three 0.312/0.338
    designs = [dict(bf_target=b, measure=5e5 - 1e5 * i, objective=3e4 + 1e4 * i, met=True, pareto=True)
               for i, b in enumerate(bf)]
    plot_pareto(designs, "calm_resistance", "mean_added_resistance", tmp_path / "p.png", parent=(4.5e5, 3.5e4, 0.32))
    (fig,) = drawn
    ax = fig.axes[0]
    (star,) = [ln for ln in ax.get_lines() if ln.get_label() == "parent"]  # the parent, to read the front against
    assert (star.get_xdata()[0], star.get_ydata()[0]) == (450.0, 35.0)
    assert ax.get_xlabel() == "calm-water resistance R_T [kN]" and ax.get_ylabel() == "mean added resistance R_AW [kN]"
    (front,) = [ln for ln in ax.get_lines() if ln.get_label() == "Pareto front"]
    np.testing.assert_allclose(sorted(front.get_xdata()), [200.0, 300.0, 400.0, 500.0])
    labels = [t.get_text() for t in ax.texts]
    assert sorted(labels) == ["Bf 0.3", "Bf 0.3125", "Bf 0.325", "Bf 0.3375", "parent (Bf 0.32)"]
    assert ax.get_title(loc="left").startswith("Pareto front: mean added resistance R_AW against calm-water resistance R_T")
    assert outside(fig, ax.get_legend(), ax)


def test_wind_coefficients_on_cartesian_axes(tmp_path, drawn):
    from hullopt.app.commands.wind import _plot

    psi = np.arange(0.0, 181.0, 30.0)
    c = {"cx": -np.cos(np.deg2rad(psi)), "cy": np.sin(np.deg2rad(psi)), "cn": 0.1 * np.sin(np.deg2rad(2 * psi)),
         "ck": np.full(psi.shape, np.nan)}
    _plot(tmp_path / "w.png", psi, {"model": c}, "model — hull")  # one model: labels without its name
    (fig,) = drawn
    forces, moments = fig.axes[:2]
    assert forces.name == moments.name == "rectilinear"
    assert moments.get_xlabel().startswith("wind angle ψ [deg]") and moments.get_xlim() == (0.0, 180.0)
    np.testing.assert_allclose(forces.get_lines()[0].get_ydata(), c["cx"])  # negative values as drawn
    assert [t.get_text() for t in moments.get_legend().get_texts()] == ["C_N yaw moment"]  # C_K missing
    assert outside(fig, forces.get_legend(), forces)


def test_features_legend_off_the_curves(tmp_path, drawn):
    from hullopt.app.commands.features import plot_features
    from hullopt.models import load_parent

    plot_features(load_parent("wigley"), tmp_path / "features.png")
    (fig,) = drawn
    ax = fig.axes[0]
    assert outside(fig, ax.get_legend(), ax)
    assert ax.get_xlabel().startswith("y [m]") and ax.get_ylabel() == "z [m]"


def test_rescored_fronts_draw_each_pair_of_methods(tmp_path, drawn):
    """A panel per calm-water method and wave method, in kN; under the first pair design 0 beats the parent in
    both (the front: design 0 alone), under the second all three trade (all on it)."""
    from hullopt.report import plot_rescored_fronts

    m = {"calm_a": {"kind": "calm", "method": "a", "parent": 2000.0, "designs": [1900.0, 2100.0]},
         "calm_b": {"kind": "calm", "method": "b", "parent": 2000.0, "designs": [2100.0, 1900.0]},
         "waves_x": {"kind": "waves", "method": "x", "parent": 300.0, "designs": [290.0, 310.0]}}
    plot_rescored_fronts({"methods": m}, tmp_path / "f.png", met=[True, True])
    (fig,) = drawn
    axes = [ax for ax in fig.axes if ax.get_xlabel() or ax.get_ylabel()]
    assert len(fig.axes) == 2 and axes[-1].get_xlabel() == "R_AW by X [kN]"
    first, second = fig.axes
    np.testing.assert_allclose(first.get_lines()[0].get_xydata(), [[0.29, 1.9]])  # the front: design 0
    np.testing.assert_allclose(second.get_lines()[0].get_xydata(), [[0.29, 2.1], [0.3, 2.0], [0.31, 1.9]])
    assert first.get_ylabel() == "R_T by a [kN]"


def test_patent_form_puts_parent_and_designs_on_the_patent_curve(tmp_path, drawn):
    """K_AW = Bf(1 + C_U·Fn) against Bf (a curve per Fn, each design on it: the patent's table at Fn 0.40 gives
    K 1.10 at Bf 0.05 and 1.00 at 0.2), ½ρgζ²B·K_AW against B·Bf, and the re-scored profile R_AW per method."""
    from hullopt.report import plot_patent

    m = {"waves_nmri": {"kind": "waves", "method": "nmri", "own": True, "parent": 3e5, "designs": [2.9e5, 3.1e5]},
         "waves_snnm": {"kind": "waves", "method": "snnm", "parent": 2e5, "designs": [2.2e5, 2.4e5]},
         "calm_a": {"kind": "calm", "method": "a", "parent": 1e6, "designs": [1e6, 1e6]}}
    plot_patent([0.05, 0.2, 0.125], [40.0, 40.0, 40.0], [0.4], tmp_path / "p.png", [True, False], {"methods": m})
    (fig,) = drawn
    k, q, waves = fig.axes
    assert [t.get_text() for t in k.get_legend().get_texts()] == ["Fn 0.400"]
    star = k.get_lines()[1].get_xydata()  # the curve, then the parent's star
    np.testing.assert_allclose(star, [[0.05, 1.10]], atol=1e-9)
    met, missed = (c.get_offsets() for c in k.collections[:2])
    np.testing.assert_allclose(met, [[0.2, 1.0]], atol=1e-9)
    np.testing.assert_allclose(missed, [[0.125, 0.125 * (1 + (68 - 310 * 0.125) * 0.4)]], atol=1e-9)
    # ½ρgζ²B·K_AW per m² of ζ²: 201.0 kN × K at B = 40 m (½ρgζ²B = 1809.3 kN at ζ = 3 m, DESIGN.md)
    np.testing.assert_allclose(q.get_lines()[1].get_xydata(), [[2.0, 1809.3 / 9 * 1.10]], rtol=1e-4)
    assert waves.get_ylabel() == "profile mean R_AW [kN]"
    assert [t.get_text() for t in waves.get_legend().get_texts()] == ["NMRI (the run's)", "SNNM"]


def test_pareto_axes_name_a_calm_water_profile_as_calm_water(tmp_path, drawn):
    """An operating profile without a sea state (``profile_resistance``, Michell) is calm-water R_T by Michell:
    the axis and the title say so, not "R_T + R_AW" (issue 62); its ``objective_about`` comes from the config."""
    from hullopt.report import label, objective_about, plot_pareto
    from hullopt.study import objective_options

    calm = objective_options({"kind": "profile_resistance", "method": "michell",
                              "profile": [{"speed_kn": 12.0}, {"speed_kn": 14.0, "weight": 2.0}]}).build()
    wavy = objective_options({"kind": "profile_resistance", "method": "michell",
                              "profile": [{"speed_kn": 12.0, "hs": 2.0, "tp": 8.0}]}).build()
    about = {"name": objective_about(calm), "measure": {"method": None, "waves": None}}
    assert about["name"] == {"method": "michell", "waves": False}
    designs = [dict(bf_target=0.3 + 0.01 * i, measure=3e4 + 1e4 * i, objective=5e5 - 1e5 * i, met=True, pareto=True)
               for i in range(3)]
    plot_pareto(designs, "mean_added_resistance", "profile_resistance", tmp_path / "p.png", about=about)
    (fig,) = drawn
    ax = fig.axes[0]
    assert ax.get_ylabel() == "operating profile calm-water R_T (Michell) [kN]"
    assert "R_AW" not in ax.get_ylabel() and "calm-water R_T (Michell)" in ax.get_title(loc="left")
    assert label("profile_resistance", about=objective_about(wavy)) == \
        "operating profile R_T (Michell) + R_AW (NMRI) [kN]"
    assert label("profile_resistance", short=True, about=about["name"]) == "R_T (profile, Michell) [kN]"
    assert label("profile_resistance") == "operating profile R_T + R_AW [kN]"  # an old report: by its key


def test_overlay_legends_hide_no_station_number(hull, tmp_path, drawn):
    """The overlay's body-plan legend sits below the plot: inside it, it covered the aft stations' numbers
    along the top (issue 62); no legend of the figure overlaps a station number."""
    from hullopt.report import plot_overlay

    fuller = Sections(hull.x, hull.yz * jnp.array([1.1, 1.0]), hull.lpp)
    plot_overlay(hull, fuller, T, tmp_path / "o.png")
    fig = drawn[-1]
    r = fig.test_renderer
    numbers = [t for ax in fig.axes for t in ax.texts if t.get_text().isdigit()]
    assert len(numbers) >= 10
    legends = [ax.get_legend() for ax in fig.axes if ax.get_legend() is not None]
    assert len(legends) == 3
    for legend in legends:
        box = legend.get_window_extent(r)
        assert not any(box.overlaps(t.get_window_extent(r)) for t in numbers)
