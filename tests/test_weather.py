"""The IS Code 2008 §2.3 weather criterion (hullopt.hydro.weather_criterion) and ``hullopt stability --weather``.

No published worked example of the whole criterion was reachable (tests/data/SOURCES.md); instead: the factor
tables at and between their entries (the Code's tables, copied apart in tests/data), closed forms for a linear
and a sine GZ curve, an independent implementation (scipy roots and quadrature of the analytic curve, the
tables by np.interp), gradients against central differences, conservative margins, and the command end to end
on a box barge, whose windage, lever and deck-edge immersion have closed forms."""

from __future__ import annotations

import csv
import json
from types import SimpleNamespace

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from conftest import DATA
from helpers import check_grad
from scipy.integrate import quad
from scipy.optimize import brentq

from hullopt.constants import G
from hullopt.hydro import (
    WIND_PRESSURE,
    deck_immersion_angle,
    gz_curve,
    lateral_plane,
    weather_criterion,
    weather_factors,
)
from hullopt.models import box

BOX = "builtin:box?L=100&B=20&D=10"


def _tables() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    with open(DATA / "is_code_2008_weather_tables.csv", encoding="utf-8") as f:
        rows = [r for r in csv.reader(f) if r and not r[0].startswith("#")]
    out: dict[str, list] = {}
    for name, arg, factor in rows[1:]:
        out.setdefault(name, []).append((float(arg), float(factor)))
    return {k: (np.array([a for a, _ in v]), np.array([f for _, f in v])) for k, v in out.items()}


TABLES = _tables()


def _factor(name: str, x: float) -> float:
    return float(np.interp(x, *TABLES[name]))


# A ship-like loading: B/d 2.5, C_B 0.6, L_WL 130 m, KG 8.4 m (OG/d 0.05), GM 1.2 m
SHIP = {"breadth": 20.0, "draft": 8.0, "kg": 8.4, "cb": 0.6, "lwl": 130.0}


def _reference(gz, gm0, displacement, area, lever, breadth, draft, kg, cb, lwl, bilge_keel_area=0.0,
               flooding_angle=None, deck_edge_angle=None, pressure=WIND_PRESSURE):
    """The criterion by the Code's text for an analytic odd GZ(φ) [m] (φ in rad): roots by brentq, areas by
    quad, the tables from tests/data by np.interp — nothing of hullopt's."""
    lw1 = pressure * area * lever / (1000.0 * G * displacement / 1000.0)
    lw2 = 1.5 * lw1
    c = 0.373 + 0.023 * breadth / draft - 0.043 * lwl / 100.0
    t = 2.0 * c * breadth / np.sqrt(gm0)
    r = 0.73 + 0.6 * (kg - draft) / draft
    k = _factor("k", 100.0 * bilge_keel_area / (lwl * breadth))
    x1, x2, s = _factor("X1", breadth / draft), _factor("X2", cb), _factor("s", t)
    phi1 = np.deg2rad(109.0 * k * x1 * x2 * np.sqrt(r * s))
    phi0 = brentq(lambda p: gz(p) - lw1, 0.0, np.deg2rad(30))
    phic = brentq(lambda p: gz(p) - lw2, 0.0, np.deg2rad(30))
    hump = np.deg2rad(np.arange(0.0, 90.0, 0.5))[np.argmax([gz(p) for p in np.deg2rad(np.arange(0.0, 90.0, 0.5))])]
    theta_c = brentq(lambda p: gz(p) - lw2, hump, np.pi / 2) if gz(np.pi / 2) < lw2 else np.inf
    phi2 = min(np.deg2rad(50.0), np.inf if flooding_angle is None else flooding_angle, theta_c)
    roll = phi0 - phi1
    a = quad(lambda p: lw2 - gz(p), roll, phic, epsabs=1e-13, epsrel=1e-12)[0]
    b = quad(lambda p: gz(p) - lw2, phic, phi2, epsabs=1e-13, epsrel=1e-12)[0]
    limit = min(16.0, np.inf if deck_edge_angle is None else 0.8 * np.rad2deg(deck_edge_angle))
    return {"lw1": lw1, "roll_period": t, "phi1": phi1, "phi0": phi0, "phi_c": phic, "theta_c": theta_c,
            "phi2": phi2, "area_a": a, "area_b": b, "limit": limit, "x1": x1, "x2": x2, "k": k, "s": s, "r": r}


# ------------------------------------------------------------------------------------------------- the tables


@pytest.mark.parametrize("name", ["X1", "X2", "k", "s"])
def test_factor_tables_at_their_entries_between_and_beyond(name):
    """Each factor at every entry of the Code's table, halfway between entries (linear), and held beyond both
    ends (the tables' "≤" and "≥" rows)."""
    args, factors = TABLES[name]
    mids = 0.5 * (args[1:] + args[:-1])
    xs = np.concatenate([args, mids, [args[0] - 1.0, args[-1] + 5.0]])
    want = np.concatenate([factors, 0.5 * (factors[1:] + factors[:-1]), [factors[0], factors[-1]]])
    base = {"breadth": 20.0, "draft": 8.0, "kg": 8.0, "cb": 0.6, "lwl": 100.0, "gm0": 1.0}
    for x, f in zip(xs, want):
        p = dict(base)
        if name == "X1":
            p["draft"] = p["breadth"] / x
        elif name == "X2":
            p["cb"] = x
        elif name == "k":
            p["bilge_keel_area"] = x * p["lwl"] * p["breadth"] / 100.0
        else:  # T = 2·C·B/√GM → GM for the wanted T
            c = 0.373 + 0.023 * 2.5 - 0.043
            p["gm0"] = (2.0 * c * p["breadth"] / x) ** 2
        got = weather_factors(**p)
        key = {"X1": "x1", "X2": "x2", "k": "k", "s": "s"}[name]
        assert float(got[key]) == pytest.approx(f, abs=1e-12), (name, x)
    assert float(weather_factors(**base, bilge_keel_area=30.0, sharp_bilges=True)["k"]) == 0.7


def test_roll_angle_by_hand():
    """φ1 = 109·k·X1·X2·√(r·s) for B/d 2.5 (X1 0.98), C_B 0.6 (X2 0.95), KG = d (r 0.73), GM 1 m:
    C = 0.373 + 0.023·2.5 − 0.043·1.3 = 0.3746, T = 2·0.3746·20 = 14.984 s, s = 0.053 − 0.984·0.0045."""
    f = weather_factors(20.0, 8.0, 8.0, 0.6, 130.0, 1.0)
    s = 0.053 - 0.984 * (0.053 - 0.044) / 2.0
    assert float(f["c"]) == pytest.approx(0.3746, abs=1e-14)
    assert float(f["roll_period"]) == pytest.approx(14.984, abs=1e-12)
    assert float(f["s"]) == pytest.approx(s, abs=1e-14) and float(f["r"]) == pytest.approx(0.73, abs=1e-14)
    assert np.rad2deg(float(f["phi1"])) == pytest.approx(109.0 * 0.98 * 0.95 * np.sqrt(0.73 * s), rel=1e-14)
    assert np.isinf(float(weather_factors(20.0, 8.0, 8.0, 0.6, 130.0, -0.1)["roll_period"]))  # GM < 0: s = 0.035
    assert float(weather_factors(20.0, 8.0, 8.0, 0.6, 130.0, -0.1)["s"]) == 0.035


# ---------------------------------------------------------------------------------------------- closed forms


def test_linear_gz_closed_forms():
    """GZ = GM·φ (straight, so the piecewise-linear curve is exact): φ0 = lw1/GM, φc = lw2/GM, no second
    intercept (φ2 = 50°, or θf), a = lw2·(φc − φr) − GM(φc² − φr²)/2, b = GM(φ2² − φc²)/2 − lw2·(φ2 − φc)."""
    gm, disp, area, lever = 1.2, 12.0e6, 2500.0, 9.0
    heels = np.deg2rad(np.linspace(0.0, 90.0, 31))  # 3° steps: exact all the same
    w = weather_criterion(heels, gm * heels, gm, disp, area, lever, **SHIP)
    lw1 = WIND_PRESSURE * area * lever / (G * disp)
    phi0, phic = lw1 / gm, 1.5 * lw1 / gm
    f = weather_factors(gm0=gm, **SHIP)
    roll, phi2 = phi0 - float(f["phi1"]), np.deg2rad(50.0)
    a = 1.5 * lw1 * (phic - roll) - 0.5 * gm * (phic**2 - roll**2)
    b = 0.5 * gm * (phi2**2 - phic**2) - 1.5 * lw1 * (phi2 - phic)
    for got, want in ((w.lw1, lw1), (w.lw2, 1.5 * lw1), (w.phi0, phi0), (w.phi_c, phic), (w.phi_roll, roll),
                      (w.phi2, phi2), (w.area_a, a), (w.area_b, b), (w.value[1], b / a), (w.value[0], np.rad2deg(phi0))):
        assert float(got) == pytest.approx(want, rel=1e-12)
    assert np.isnan(float(w.theta_c)) and float(w.required[0]) == 16.0 and bool(np.all(w.passed))
    # a flooding angle of 30° ends area b there; a deck edge immersing at 15° limits φ0 to 12°
    w = weather_criterion(heels, gm * heels, gm, disp, area, lever, **SHIP, flooding_angle=np.deg2rad(30.0),
                          deck_edge_angle=np.deg2rad(15.0))
    b30 = 0.5 * gm * (np.deg2rad(30.0) ** 2 - phic**2) - 1.5 * lw1 * (np.deg2rad(30.0) - phic)
    assert float(w.area_b) == pytest.approx(b30, rel=1e-12) and float(w.required[0]) == pytest.approx(12.0)


def test_sine_gz_against_an_independent_implementation():
    """GZ = A·sin(πφ/60°) on a 0.1° grid against the Code done apart (scipy roots and quadrature of the analytic
    curve): a case where the second intercept θc ends area b, one with a flooding angle, one with bilge keels."""
    amp, gm = 1.0, np.pi / np.deg2rad(60.0)  # GM = dGZ/dφ at 0

    def gz(p):
        return amp * np.sin(np.pi * p / np.deg2rad(60.0))

    heels = np.deg2rad(np.linspace(0.0, 90.0, 901))
    cases = [{"area": 4000.0, "lever": 8.0, "displacement": 4.0e6},  # θc ≈ 47.3°
             {"area": 1500.0, "lever": 7.0, "displacement": 8.0e6, "flooding_angle": np.deg2rad(33.0)},
             {"area": 1500.0, "lever": 7.0, "displacement": 8.0e6, "bilge_keel_area": 52.0,
              "deck_edge_angle": np.deg2rad(18.0)}]
    for case in cases:
        ref = _reference(gz, gm, **case, **SHIP)
        w = weather_criterion(heels, gz(heels), gm, **case, **SHIP)
        assert float(w.lw1) == pytest.approx(ref["lw1"], rel=1e-13)
        assert float(w.roll_period) == pytest.approx(ref["roll_period"], rel=1e-13)
        for k in ("x1", "x2", "k", "s", "r"):
            assert float(getattr(w, k)) == pytest.approx(ref[k], rel=1e-13), k
        assert float(w.phi1) == pytest.approx(ref["phi1"], rel=1e-13)
        for k in ("phi0", "phi_c", "phi2"):
            assert float(getattr(w, k)) == pytest.approx(ref[k], abs=1e-6), k  # linear between 0.1° heels
        for k in ("area_a", "area_b"):
            assert float(getattr(w, k)) == pytest.approx(ref[k], rel=2e-5), k
        assert float(w.required[0]) == pytest.approx(ref["limit"], rel=1e-12)
    assert np.rad2deg(_reference(gz, gm, **cases[0], **SHIP)["theta_c"]) < 50.0  # the first case ends at θc


# ----------------------------------------------------------------------------------- margins for an optimiser


def _margins(x, heels):
    """Both margins for x = (amplitude of GZ [m], A [m²], Z [m], KG [m], C_B, GM [m])."""
    amp, area, lever, kg, cb, gm = (x[i] for i in range(6))
    gz = amp * jnp.sin(jnp.pi * heels / jnp.deg2rad(60.0))
    return weather_criterion(heels, gz, gm, 4.0e6, area, lever, 20.0, 8.0, kg, cb, 130.0,
                             deck_edge_angle=jnp.deg2rad(19.9)).margin


def test_margin_gradients_match_finite_differences():
    """Both margins (the steady heel's, with the deck edge's soft limit 0.8 × 19.9° near 16°; b/a, whose end
    is the soft minimum of 50° and θc ≈ 50.8°) differentiate like central differences in the GZ curve, the
    windage, KG, C_B and GM."""
    heels = jnp.deg2rad(jnp.linspace(0.0, 90.0, 181))
    m = jax.jit(lambda x: _margins(x, heels))
    x = np.array([1.0, 3000.0, 8.0, 8.3, 0.61, 2.9])
    assert np.all(np.isfinite(np.asarray(m(x))))
    for i in range(2):
        check_grad(lambda v, i=i: m(v)[i], x, rtol=1e-5, atol=1e-8)


def test_margins_are_conservative_and_values_exact():
    """Over random loadings the optimiser's margins never exceed the exact ones, and fall short of them by at
    most the soft minima's bias; a curve that never reaches lw2 (capsize) fails with b = 0."""
    heels = jnp.deg2rad(jnp.linspace(0.0, 90.0, 181))
    f = jax.jit(lambda x, deck, flood: weather_criterion(
        heels, x[0] * jnp.sin(jnp.pi * heels / jnp.deg2rad(60.0)), x[5], 4.0e6, x[1], x[2], 20.0, 8.0, x[3], x[4],
        130.0, flooding_angle=flood, deck_edge_angle=deck))
    rng = np.random.default_rng(1)
    for _ in range(40):
        x = np.array([rng.uniform(0.3, 1.5), rng.uniform(500, 6000), rng.uniform(4, 12), rng.uniform(7, 9),
                      rng.uniform(0.5, 0.7), rng.uniform(0.5, 3.0)])
        w = f(x, np.deg2rad(rng.uniform(15, 25)), np.deg2rad(rng.uniform(40, 55)))
        exact = np.array([-1.0, 1.0]) * (np.asarray(w.value) - np.asarray(w.required))  # φ0 ≤, b/a ≥
        assert np.all(np.asarray(w.margin) <= exact + 1e-12)
        # the soft minimum lowers φ0's limit by at most τ·log 2 (0.2°); b ends at most τ·log 3 earlier
        assert np.all(np.asarray(w.margin) >= exact - [np.rad2deg(0.005 * np.log(2.0)) + 1e-9, 0.1])
    w = f(np.array([0.05, 6000.0, 12.0, 8.0, 0.6, 0.2]), np.deg2rad(20.0), np.deg2rad(45.0))
    assert float(w.area_b) == 0.0 and float(w.value[1]) == 0.0 and not bool(w.passed[1])
    assert not bool(w.reaches_lw2) and np.isnan(float(w.theta_c))
    assert np.all(np.isfinite(np.asarray(w.margin)))


# ------------------------------------------------------------------------------------------------- geometry


def test_deck_edge_immersion_and_lateral_plane_of_a_box():
    """A box barge 100 × 20 × 10 m at T = 6 m stays wall-sided until its deck edge immerses, at
    atan((D − T)/(B/2)) = 21.80° (before the bilge emerges, at 31°); its underwater lateral plane is L·T with
    its centre at T/2."""
    s = box(100.0, 20.0, 10.0)
    heels = jnp.deg2rad(jnp.linspace(0.0, 30.0, 61))
    c = gz_curve(s, 12000.0, 6.0, heels)
    got = float(deck_immersion_angle(s, heels, c.level, c.trim))
    assert np.rad2deg(got) == pytest.approx(np.rad2deg(np.arctan(0.4)), abs=1e-3)
    assert np.isnan(float(deck_immersion_angle(s, heels[:20], c.level[:20], c.trim[:20])))  # dry to 9.5°
    area, z = lateral_plane(s, 6.0)
    assert float(area) == pytest.approx(600.0, rel=1e-12) and float(z) == pytest.approx(3.0, rel=1e-12)


# --------------------------------------------------------------------------------------------- plot and CLI


def test_plot_gz_shades_the_weather_areas(tmp_path, monkeypatch):
    """The GZ plot titles Δ in t; with the weather criterion it draws lw1, lw2, θf and shades a and b; without,
    the §2.2 areas."""
    from hullopt.drawing import _curves, plot_gz

    figures, save = [], _curves._save
    monkeypatch.setattr(_curves, "_save", lambda plt, fig, path: (figures.append(fig), save(plt, fig, path))[1])
    heels = np.deg2rad(np.linspace(0.0, 90.0, 19))
    curve = SimpleNamespace(heel=heels, gz=np.sin(np.pi * heels / np.deg2rad(60.0)), gm0=3.0, volume=8000.0, kg=6.0)
    w = weather_criterion(heels, curve.gz, 3.0, 4.0e6, 3000.0, 8.0, **SHIP, flooding_angle=np.deg2rad(45.0))
    plot_gz(curve, tmp_path / "gz.png", name="sine", rho=1025.0, flooding_angle=np.deg2rad(45.0), weather=w)
    plot_gz(curve, tmp_path / "gz22.png", name="sine")
    (ax,) = figures[0].axes
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert ax.get_title(loc="left") == "GZ curve — Δ 8,200 t, KG 6 m — sine"
    assert any(lb.startswith("lw1 = ") for lb in labels) and any(lb.startswith("lw2 = ") for lb in labels)
    assert any("θf = 45.0°" in lb for lb in labels)
    assert f"area a = {float(w.area_a):.4f} m·rad" in labels and f"area b = {float(w.area_b):.4f} m·rad" in labels
    assert ax.get_xlim()[0] < np.rad2deg(float(w.phi_roll))  # the roll to windward is on the plot
    (ax2,) = figures[1].axes
    assert len(ax2.collections) == 2 and not any("lw1" in t.get_text() for t in ax2.get_legend().get_texts())


@pytest.mark.slow
def test_cli_weather_on_a_box_barge(cli):
    """``stability --weather`` on a box 100 × 20 × 10 m at Δ 8200 t (T = 4 m): the windage is the side above
    the water, A = L·(D − T) = 600 m², its lever Z = (D − T)/2 + T/2 = 5 m, lw1 = P·A·Z/(g·Δ); with 20 000 m² at
    Z = 20 m more the gust lever exceeds GZmax: the weather criterion alone fails (exit code 4)."""
    code, out, err = cli("stability", BOX, "--displacement", "8200", "--kg", "6", "--weather", "--json")
    assert code == 0, err
    w = json.loads(out)["weather"]
    assert w["windage_area"] == pytest.approx(600.0, rel=1e-9) and w["windage_lever"] == pytest.approx(5.0, rel=1e-9)
    assert w["lw1"] == pytest.approx(504.0 * 600.0 * 5.0 / (G * 8.2e6), rel=1e-9)
    assert w["draft"] == pytest.approx(4.0, rel=1e-9) and w["breadth"] == pytest.approx(20.0)
    assert w["cb"] == pytest.approx(1.0) and w["lwl"] == pytest.approx(100.0)
    assert [c["key"] for c in w["criteria"]] == ["steady_heel", "area_ratio"] and all(c["pass"] for c in w["criteria"])
    assert w["outside"] == ["B/d = 5.00 ≥ 3.5"]
    code, out, err = cli("stability", BOX, "--displacement", "8200", "--kg", "6", "--weather", "--windage-area",
                         "20000", "--windage-lever", "20", "--heels", "0:60:7")
    assert code == 4 and "IMO IS Code 2008 Part A §2.3 (weather criterion)" in out
    assert "m·rad" in out and "FAIL" in out and "Area b / area a" in out.split("criteria fail")[-1]
    assert "none: GZ < lw2" in out  # the gust lever is above GZmax: no intercept
    assert "B/d = 5.00 ≥ 3.5" in " ".join(err.split())  # the console wraps the warning at its width


@pytest.mark.parametrize("args, words", [
    (["--bilge-keel-area", "5"], ["--bilge-keel-area", "--weather"]),
    (["--weather", "--windage-area", "100"], ["--windage-area", "--windage-lever"]),
    (["--weather", "--windage-area", "-1", "--windage-lever", "3"], ["--windage-area", "≥ 0"]),
    (["--weather", "--bilge-keel-area", "nan"], ["--bilge-keel-area"]),
    (["--weather", "--wind-pressure", "0"], ["--wind-pressure", "Pa"]),
])
def test_cli_weather_bad_input(cli, args, words):
    code, _, err = cli("stability", BOX, "--displacement", "8200", "--kg", "6", *args)
    assert code == 2 and err.startswith("error:") and len(err.strip().splitlines()) == 1
    assert all(w in err for w in words), err


def test_cli_wind_pressure_default_is_the_codes():
    from hullopt.app.commands.stability import WIND_PRESSURE as cli_default

    assert cli_default == WIND_PRESSURE == 504.0
