"""The Series 60 C_B 0.60 parent read from Todd's (1963) offsets (examples/hulls/series60_cb060_todd1963.csv)
against the form coefficients Todd published for it (DTMB Report 1712; examples/hulls/SOURCES.md)."""

import json

import numpy as np
import pytest
import trimesh
from conftest import HULLS

from hullopt.geometry import export_mesh, hull_mesh
from hullopt.hydro import hydrostatics, sectional_areas
from hullopt.models import load_hull

FT = 0.3048
LPP, T = 400 * FT, 400 * FT / 7.5 / 2.5


@pytest.fixture(scope="module")
def series60():
    return load_hull(f"{HULLS}/series60_cb060_todd1963.csv").sections


def test_the_offsets_have_todds_coefficients(series60):
    """C_P, C_W and the LCB to Todd's three decimals; C_M and with it C_B 0.004 low: the natural splines
    through the table's waterlines at 0, 0.075 and 0.25 T cut inside the bilge's circle. The LWL ends where
    Todd's does, 406.7 ft, and nothing is left of a transom at the AP. C_W 0.7080: the waterlines whose natural
    spline would bulge past the widest offset (8.145 m for 8.128, the parallel middle body) or dip below zero
    are read by PCHIP (issue 62), which gives 0.0008 more than the natural splines' 0.7072."""
    hs = hydrostatics(series60, T)
    assert float(hs.cp) == pytest.approx(0.614, abs=1e-3)
    assert float(hs.cwp) == pytest.approx(0.706, abs=2.5e-3)
    assert float(hs.lcb_pct) == pytest.approx(-1.5, abs=0.05)  # per cent of Lpp, aft of amidships
    assert -0.006 < float(hs.cm) - 0.977 < -0.002
    assert -0.005 < float(hs.cb) - 0.600 < -0.001
    assert float(hs.lwl) == pytest.approx(406.7 * FT, abs=0.01)
    assert float(hs.a_transom) == 0.0


def test_the_exported_mesh_holds_the_same_volume(series60, tmp_path):
    """A second method: trimesh's mass properties of the STL hullopt writes (closed at the table's top, the DWL)
    against the section integrals, volume and LCB."""
    rep = export_mesh(hull_mesh(series60), tmp_path / "s60.stl")
    mesh = trimesh.load_mesh(tmp_path / "s60.stl")
    hs = hydrostatics(series60, T)
    assert rep.ok and mesh.volume == pytest.approx(float(hs.volume), rel=2e-4)  # 3e-5 measured
    assert mesh.center_mass[0] == pytest.approx(float(hs.lcb), abs=0.01)  # m; 0.5 mm measured


def test_the_entrance_and_run_have_todds_prismatics(series60):
    """The prismatic coefficients of the fore and aft bodies, each over Lpp/2 and the midship area: Todd's
    0.581 and 0.646 (a fuller run than entrance puts the LCB aft)."""
    x, a = np.asarray(series60.x), np.asarray(sectional_areas(series60, T))
    xf = np.linspace(0.0, LPP, 4001)
    af = np.interp(xf, x, a) / a.max()
    fore = xf >= LPP / 2
    assert np.trapezoid(af[fore], xf[fore]) / (LPP / 2) == pytest.approx(0.581, abs=1.5e-3)
    assert np.trapezoid(af[~fore], xf[~fore]) / (LPP / 2) == pytest.approx(0.646, abs=1.5e-3)


def test_stability_warns_that_the_hull_has_no_topsides(cli):
    """Floating at its DWL, the table's top, the hull has no reserve buoyancy: heeled, it goes under whole and
    its GZ is a submerged body's, (KB − KG) sin φ. The numbers are right for that body; the warning says why
    they are not the ship's."""
    code, out, err = cli("stability", f"{HULLS}/series60_cb060_todd1963.csv", "--kg", "6.0",
                         "--displacement", "7894.5", "--heels", "0:40:5", "--json")
    assert code == 4 and "reserve buoyancy is 0.01%" in err and "without topsides" in err, err
    r = json.loads(out)
    kb = 3.493  # hullopt hydro at the DWL
    assert r["gz"][-1] == pytest.approx((kb - 6.0) * np.sin(np.deg2rad(40.0)), abs=0.01)
    code, _, err = cli("stability", "parent:wigley", "--kg", "4", "--displacement", "2800", "--heels", "0:40:5")
    assert "reserve buoyancy" not in err  # 10 m deck over a 6.25 m draft


@pytest.mark.slow
def test_a_fit_from_the_offsets(cli, tmp_path):
    """A naval architect's parent from an offset table that stops at the DWL: its feature curves, then a fit to
    C_B 0.62 and LCB −0.5 % with the frames moved along the length. Re-reading the frames instead (curves =
    "all") would move the deck edge off the waterline; that is refused with the way out, not run."""
    code, _, err = cli("features", f"{HULLS}/series60_cb060_todd1963.csv", "--out", tmp_path / "f")
    assert code == 0, err
    cfg = tmp_path / "fit.toml"
    cfg.write_text(f"""kind = "fit"
[hull]
parent = "{tmp_path / 'f' / 'features.json'}"
draft = {T}
[[design.apex_move]]
segment = -1
x_fixed1 = 60.96
x_moved = 97.5
x_fixed2 = 121.92
bound = 1.0
[[design.distribution]]
x_a = 0.0
x_b = 121.92
modes = 2
bound = 0.4
curves = "stations"
[targets]
cb = 0.62
lcb_pct = -0.5
[solver]
fairness = 0.2
""")
    code, out, err = cli("run", cfg, "--out", tmp_path / "r", "--json")
    assert code == 0, err
    r = json.loads(out)
    assert r["met"] and not [w for w in r["warnings"] if "rougher" in w], r["warnings"]
    parent, design = r["parent"], r["achieved"]
    assert design["cwp"] > parent["cwp"]  # a fuller fore body: the waterplane grows with C_B, never collapses
    cfg.write_text(cfg.read_text().replace('curves = "stations"\n', ""))
    code, _, err = cli("run", cfg, "--out", tmp_path / "r2")
    assert code == 2 and "design.distribution[0]" in err and "no freeboard" in err, err
