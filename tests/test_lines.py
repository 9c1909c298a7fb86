"""Lines plan, offset export and the stability/lines CLI: curves against the Wigley hull's closed form,
files made and sane (PNG, SVG, DXF read back), offset tables read back in both layouts, bad input."""

import json

import ezdxf
import numpy as np
import pytest

from hullopt.app.cli import main
from hullopt.drawing import (half_breadths, lines_plan, plot_gz, save_lines, station_sections, write_offsets_stations,
                             write_offsets_wide)
from hullopt.errors import HullError
from hullopt.models import read_offsets, wigley

Lw, Bw, Tw, Dw = 100.0, 10.0, 6.25, 10.0
WIGLEY = f"builtin:wigley?L={Lw:g}&B={Bw:g}&T={Tw:g}&D={Dw:g}&n=41&m=41"


def wigley_y(x, z):
    """Exact half-breadth of the Wigley hull (vertical sides above T)."""
    beam = (Bw / 2) * (1 - (2 * (np.asarray(x) - Lw / 2) / Lw) ** 2)
    zz = np.minimum(np.asarray(z), Tw)
    return beam * (1 - ((Tw - zz) / Tw) ** 2)


@pytest.fixture(scope="module")
def hull():
    return wigley(Lw, Bw, Tw, Dw, n=41, m=401)


@pytest.fixture(autouse=True)
def _cache(tmp_path, monkeypatch):
    monkeypatch.setenv("HULLOPT_CACHE", str(tmp_path / "cache"))


def test_stations_are_drawn_at_the_stations_between_the_given_sections():
    """37 intervals put the Wigley's sections off the ten stations (by up to 1.35 m); the drawings show the
    hull at each station, interpolated there: its half-breadths match the closed form to 5 mm where the
    nearest given section is off by up to 0.1 m (a design whose frames moved along the length has no section
    at a station either)."""
    h = wigley(Lw, Bw, Tw, Dw, n=38, m=201)
    st, x, yz = station_sections(h)
    np.testing.assert_array_equal(st, np.arange(11.0))
    np.testing.assert_allclose(x, np.arange(11) * Lw / 10)
    z = np.linspace(0.3, Tw, 9)
    drawn = np.array([np.interp(z, p[:, 1], p[:, 0]) for p in yz])
    exact = wigley_y(x[:, None], z[None, :])
    assert np.max(np.abs(drawn - exact)) < 5e-3
    near = np.asarray(h.yz)[np.argmin(np.abs(np.asarray(h.x)[:, None] - x), 0)]
    assert np.max(np.abs(np.array([np.interp(z, p[:, 1], p[:, 0]) for p in near]) - exact)) > 0.05
    plan = lines_plan(h, "wigley")  # the lines plan's body plan is those sections
    body = [c[2] for c in plan.body if c[0] == "station"]
    np.testing.assert_allclose(np.abs(np.stack(body)), yz, atol=1e-12)


def test_waterlines_and_buttocks_follow_the_closed_form(hull):
    plan = lines_plan(hull, "wigley", waterlines=[2.0, 4.0], buttocks=[1.5])
    wl = [c for c in plan.half_breadth if c[0] == "waterline"]
    assert len(wl) == 2
    for (_, label, pts), z in zip(wl, (2.0, 4.0)):
        np.testing.assert_allclose(pts[:, 1], wigley_y(pts[:, 0], z), atol=2e-4)
    (bt,) = [c for c in plan.sheer if c[0] == "buttock"]
    x, z = bt[2][:, 0], bt[2][:, 1]
    # buttock y = 1.5: invert y(x, z) = 1.5 for the depth below the waterline
    beam = (Bw / 2) * (1 - (2 * (x - Lw / 2) / Lw) ** 2)
    np.testing.assert_allclose(z, Tw - Tw * np.sqrt(1 - 1.5 / beam), atol=2e-3)
    stations = [c for c in plan.body if c[0] == "station"]
    assert len(stations) == 11
    assert all(np.all(c[2][:, 0] <= 1e-12) for c in stations[:5]) and all(np.all(c[2][:, 0] >= 0) for c in stations[6:])


def test_drawings_are_written(hull, tmp_path):
    plan = lines_plan(hull, "wigley")
    for ext in ("png", "svg", "dxf"):
        p = save_lines(plan, tmp_path / f"lines.{ext}")
        assert p.stat().st_size > 10_000
    assert (tmp_path / "lines.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "<svg" in (tmp_path / "lines.svg").read_text()[:2000]
    doc = ezdxf.readfile(tmp_path / "lines.dxf")
    layers = {e.dxf.layer for e in doc.modelspace()}
    assert {"STATION", "WATERLINE", "BUTTOCK", "OUTLINE", "GRID"} <= layers
    n_curves = len(plan.sheer) + len(plan.half_breadth) + len(plan.body)
    assert len(doc.modelspace().query("LWPOLYLINE")) == n_curves
    with pytest.raises(HullError, match="unknown drawing format"):
        save_lines(plan, tmp_path / "lines.jpg")
    assert not list(tmp_path.glob(".*tmp*"))  # no temporary files left behind


def test_offset_tables_read_back_in_both_layouts(hull, tmp_path):
    z = np.linspace(0.0, Dw, 11)
    exact = wigley_y(np.linspace(0, Lw, 41)[:, None], z[None, :])
    np.testing.assert_allclose(half_breadths(hull, np.linspace(0, Lw, 41), z), exact, atol=2e-4)
    wide = read_offsets(write_offsets_wide(hull, tmp_path / "wide.csv", z=z))
    np.testing.assert_allclose(wide.x, np.linspace(0, Lw, 41))
    np.testing.assert_allclose(wide.y, exact, atol=2e-4)
    st = read_offsets(write_offsets_stations(hull, tmp_path / "st.csv", n_waterlines=11))
    assert st.lpp == Lw and len(st.x) == 21 and st.x[1] == pytest.approx(Lw / 40)  # AP, 1/4, …
    np.testing.assert_allclose(st.y, wigley_y(st.x[:, None], st.z[None, :]), atol=2e-4)
    assert [r.split(",")[0] for r in (tmp_path / "st.csv").read_text().splitlines()[4:8]] == ["AP", "1/4", "1/2", "3/4"]


def run(capsys, *args):
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.mark.slow
def test_cli_lines_curves_offsets(capsys, tmp_path):
    code, _, err = run(capsys, "lines", WIGLEY, "--out", str(tmp_path / "l.png"), "--out", str(tmp_path / "l.dxf"),
                       "--curves", str(tmp_path / "c.svg"), "--offsets", str(tmp_path / "o.csv"), "--layout", "wide")
    assert code == 0, err
    assert all((tmp_path / f).stat().st_size > 1000 for f in ("l.png", "l.dxf", "c.svg", "o.csv"))
    assert read_offsets(tmp_path / "o.csv").y.shape[0] == 41
    code, _, err = run(capsys, "lines", WIGLEY, "--out", str(tmp_path / "l.jpg"))
    assert code == 2 and "--out" in err and ".jpg" in err
    code, _, err = run(capsys, "lines", WIGLEY, "--out", str(tmp_path / "nope" / "l.png"))
    assert code == 2 and "does not exist" in err


@pytest.mark.slow
def test_cli_stability_json_and_plot(capsys, tmp_path):
    code, out, err = run(capsys, "stability", "builtin:box?L=100&B=20&D=10", "--displacement", "8200", "--kg", "6",
                         "--heels", "0:60:4", "--json", "--plot", str(tmp_path / "gz.png"))
    assert code == 0, err
    d = json.loads(out)
    assert {"heel_deg", "gz", "kn", "gm0", "criteria"} <= set(d)
    assert d["heel_deg"] == [0, 20, 40, 60]
    bm = 20**2 / (12 * 4.0)
    assert d["gm0"] == pytest.approx(2.0 + bm - 6.0) and d["volume"] == pytest.approx(8000.0)
    phi = np.deg2rad(20.0)  # wall-sided at 20°
    assert d["gz"][1] == pytest.approx(np.sin(phi) * (d["gm0"] + 0.5 * bm * np.tan(phi) ** 2), rel=1e-9)
    assert [c["key"] for c in d["criteria"]] == ["area_0_30", "area_0_40", "area_30_40", "gz_30", "angle_gz_max", "gm0"]
    assert all(c["pass"] for c in d["criteria"])
    assert (tmp_path / "gz.png").stat().st_size > 10_000


@pytest.mark.parametrize("args, words", [
    (["--displacement", "8200", "--kg", "nan"], ["--kg"]),
    (["--displacement", "30000", "--kg", "6"], ["--displacement", "more than"]),
    (["--displacement", "8200", "--kg", "6", "--heels", "0:120:5"], ["--heels", "0…90"]),
    (["--displacement", "8200", "--kg", "6", "--sheer", "wavy"], ["--sheer", "icll"]),
    (["--displacement", "8200", "--kg", "6", "--flooding-angle", "120"], ["--flooding-angle"]),
    (["--displacement", "8200", "--kg", "6", "--kn-plot", "kn.png"], ["--kn-plot", "--cross"]),
    (["--displacement", "8200", "--kg", "6", "--plot", "gz.bmp"], ["--plot", ".bmp"]),
])
@pytest.mark.slow
def test_cli_stability_bad_input(capsys, args, words):
    code, _, err = run(capsys, "stability", "builtin:box?L=100&B=20&D=10", *args)
    assert code == 2 and err.startswith("error:") and len(err.strip().splitlines()) == 1
    assert all(w in err for w in words), err


@pytest.fixture
def drawn(monkeypatch):
    """The figures the curve plots save (their files are still written): a list of matplotlib figures."""
    from hullopt.drawing import _curves

    figures, save = [], _curves._save
    monkeypatch.setattr(_curves, "_save", lambda plt, fig, path: (figures.append(fig), save(plt, fig, path))[1])
    return figures


@pytest.mark.slow
def test_plot_gz_draws_the_wall_sided_curve(tmp_path, drawn):
    """A box barge 50 × 10 × 5 m at T = 2 m, KG = 3 m: the GZ line is the wall-sided formula to 20° (the bilge
    emerges at 21.8°), the GM₀ tangent reaches GM₀ = T/2 + B²/12T − KG = 2.1667 m at 1 rad."""
    import equinox as eqx
    import jax.numpy as jnp

    from hullopt.hydro import stability
    from hullopt.models import box

    b, t, kg = 10.0, 2.0, 3.0
    heels = np.linspace(0.0, 90.0, 10)
    res = eqx.filter_jit(stability)(box(50.0, b, 5.0), jnp.asarray(50 * b * t), jnp.asarray(kg),  # compiled
                                    jnp.deg2rad(jnp.asarray(heels)), free_trim=False, n_grid=31)
    path = plot_gz(res.curve, tmp_path / "gz.svg", res.criteria, "box")
    assert path.stat().st_size > 5000 and path.read_text().startswith("<?xml")
    (ax,) = drawn[0].axes
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    gz, bm = lines["GZ"], b**2 / (12 * t)
    gm = t / 2 + bm - kg
    np.testing.assert_allclose(gz.get_xdata(), heels, rtol=1e-12)
    phi = np.deg2rad(heels[:3])
    np.testing.assert_allclose(gz.get_ydata()[:3], np.sin(phi) * (gm + 0.5 * bm * np.tan(phi) ** 2), rtol=1e-10,
                               atol=1e-12)
    tangent = lines[f"GM₀ = {gm:.3g} m"]
    np.testing.assert_allclose(tangent.get_ydata(), [0.0, gm], rtol=1e-10)
    gz_max = float(res.criteria.gz_max)
    marker = next(ln for label, ln in lines.items() if label.startswith("GZmax"))
    assert marker.get_ydata()[0] == pytest.approx(gz_max) and ax.get_title(loc="left").endswith("— box")


def test_plot_cross_curves_draws_each_heel(tmp_path, drawn):
    """One line per heel through the given (Δ, KN) points, labelled in degrees (the wall-sided KN of a box
    barge B = 10 m at three drafts)."""
    import jax.numpy as jnp

    from hullopt.drawing import plot_cross_curves

    b, t = 10.0, np.array([1.0, 2.0, 3.0])
    disp = 1.025 * 50 * b * t  # t
    heels = np.deg2rad([0.0, 5.0, 10.0])
    tc = t[:, None]
    kn = np.sin(heels) * (tc / 2 + b**2 / (12 * tc) * (1 + 0.5 * np.tan(heels) ** 2))  # (drafts, heels)
    path = plot_cross_curves(jnp.asarray(disp), jnp.asarray(heels), jnp.asarray(kn), tmp_path / "kn.png", "box")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    (ax,) = drawn[0].axes
    lines = ax.get_lines()
    assert [ln.get_label() for ln in lines] == ["0°", "5°", "10°"]
    for j, ln in enumerate(lines):
        np.testing.assert_allclose(ln.get_xdata(), disp, rtol=1e-15)
        np.testing.assert_allclose(ln.get_ydata(), kn[:, j], rtol=1e-15)
    assert ax.get_title(loc="left") == "Cross curves — box"

def test_save_figure_is_atomic_and_closes_the_figure(tmp_path):
    """The one figure saver: the PNG opens, no temporary file is left (also after a failed save), the figure is
    closed either way."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from PIL import Image

    from hullopt.drawing import save_figure

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    out = save_figure(fig, tmp_path / "a.png", dpi=50)
    assert not plt.fignum_exists(fig.number)
    with Image.open(out) as im:
        im.verify()
        assert im.format == "PNG"
    fig, _ = plt.subplots()
    with pytest.raises(ValueError):
        save_figure(fig, tmp_path / "b.nosuchformat")
    assert not plt.fignum_exists(fig.number)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.png"]
