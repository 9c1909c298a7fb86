"""The L2-Sea hull-grid writer of benchmarks/l2sea/l2sea.py (the peer comparison, issue 27 item 5): layout,
spacing and waterline placement, the immersed volume it describes, the PLOT3D file; and one run of L2-Sea
when it is built (benchmarks/l2sea/build.sh), skipped otherwise."""

import importlib.util

import numpy as np
import pytest
from conftest import REPO

from hullopt.hydro import hydrostatics
from hullopt.models import wigley


def _module():
    spec = importlib.util.spec_from_file_location("l2sea", REPO / "benchmarks" / "l2sea" / "l2sea.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


l2sea = _module()
L2SEA_DIR = l2sea.l2sea_dir()  # where build.sh put it, before the suite points HULLOPT_CACHE elsewhere
T = 6.25


@pytest.fixture(scope="module")
def hull():
    return wigley(100.0, 10.0, T, 10.0, n=41, m=41)


def _immersed_volume(X, Y, Z, draft):
    """Twice the half-hull volume below ``draft`` from the grid's lines (each line closed on the centreline,
    trapezoidal along x) — the lines are constant-x stations except the end profiles, which hold no area."""
    areas = []
    for i in range(X.shape[1]):
        y, z = Y[:, i], Z[:, i]
        zc = np.minimum(z, draft)
        # clip the line at the waterline: above it y counts only at the waterline
        a = 0.5 * np.sum((y[1:] + y[:-1]) * (zc[:-1] - zc[1:]))  # ∫ y dz from the keel up
        areas.append(2.0 * a)
    x = X[-1, :]
    return abs(np.trapezoid(areas, x))


def test_layout_spacing_and_waterline(hull):
    ni, nj = 90, 25
    X, Y, Z = l2sea.sections_to_grid(hull, T, ni, nj)
    assert X.shape == Y.shape == Z.shape == (nj, ni)
    assert np.all(Y >= 0.0)
    assert np.all(Y[:, 0] == 0.0) and np.all(Y[:, -1] == 0.0)  # stem and (closed) stern profiles
    assert np.all(Y[-1, :] == 0.0)  # keel points on the centreline
    assert X[0, 0] > X[0, 1] and X[0, -1] < X[0, -2]  # i = 0 forward, i = ni − 1 aft
    n_below = round(2 * nj / 3)
    for i in range(1, ni - 1):  # stations: even spacing, waterline 0.25 of a spacing above the first node below
        p = np.stack([Y[:, i], Z[:, i]], axis=1)
        seg = np.linalg.norm(np.diff(p, axis=0), axis=1)
        h = seg[nj - n_below :].mean()
        assert np.allclose(seg[nj - n_below :], h, rtol=0.05)
        assert Z[nj - n_below, i] < T < Z[nj - n_below - 1, i]
        assert T - Z[nj - n_below, i] == pytest.approx(0.25 * h, rel=0.1)


def test_immersed_volume(hull):
    X, Y, Z = l2sea.sections_to_grid(hull, T)
    assert _immersed_volume(X, Y, Z, T) == pytest.approx(float(hydrostatics(hull, T).volume), rel=0.03)


def test_plot3d_round_trip(hull, tmp_path):
    X, Y, Z = l2sea.sections_to_grid(hull, T, 30, 12)
    path = l2sea.write_plot3d(tmp_path / "hull.x", X, Y, Z)
    head = path.read_text().split()
    assert head[:4] == ["1", "30", "12", "1"]
    for a, b in zip(l2sea.read_grid(path), (X, Y, Z)):
        assert np.allclose(a, b, rtol=1e-7, atol=1e-6)


@pytest.mark.slow
@pytest.mark.skipif(l2sea.binary() is None, reason="L2-Sea is not built (benchmarks/l2sea/build.sh)")
def test_run_warp_on_its_own_parent_grid(monkeypatch):
    monkeypatch.setenv("HULLOPT_L2SEA_DIR", str(L2SEA_DIR))
    r = l2sea.run_warp(l2sea.parent_grid(), 0.28, grid_level=7)
    # L2-Sea's DTMB 5415 at its coarsest level (static-locals build, see benchmarks/l2sea/README.md)
    assert r["cw"] == pytest.approx(1.570e-3, rel=0.02)
    assert r["ct"] == pytest.approx(r["cw"] + r["cf"], rel=1e-3)
