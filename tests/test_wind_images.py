"""Wind variables from drawings: rendered views of the same parts give the geometry's variables to pixel
resolution; box-counting dimension; moments; bad drawings; the CLI on configs and drawings."""

import json

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest
from skimage import draw, io, measure

from hullopt.app.cli import main
from hullopt.errors import HullError
from hullopt.models import box
from hullopt.wind import (PartSpec, ViewScale, box_counting_dimension, box_parts, drawing_variables, outline,
                          projections, render, variables_from_projections)

PPM = 2.0  # pixels per metre
COLOURS = [(0, 0, 128), (128, 0, 0), (0, 100, 0), (90, 60, 0), (60, 0, 90)]
T = 12.0


def ship_parts():
    # Sizes deliberately off the pixel grid (x.3 m, x.7 m), so the pixel tolerance is exercised.
    return box_parts(["bridge", "funnel", "stack", "mast"], ["superstructure", "superstructure", "cargo", "mast"],
                     [30.3, 20.1, 45.2, 230.0], [42.7, 27.6, 200.4, 231.3], 24.0, [60.2, 55.7, 40.3, 45.0],
                     [36.4, 8.2, 39.7, 0.9])


@pytest.fixture(scope="module")
def views():
    pr = eqx.filter_jit(projections)(box(250.0, 40.0, 24.0, n=5), jnp.asarray(T), ship_parts())
    geo = eqx.filter_jit(variables_from_projections)(pr)
    side_scale, front_scale = ViewScale(PPM, 140, origin_col=20), ViewScale(PPM, 140, origin_col=60)
    side = render([pr.hull_side, *pr.part_side], COLOURS, side_scale, (150, 540))
    front = render([pr.hull_front, *pr.part_front], [(0, 0, 0)] * 5, front_scale, (150, 120))
    names = ("hull", *pr.parts.names)
    kinds = ("hull", *pr.parts.kinds)
    specs = [PartSpec(n, k, c) for n, k, c in zip(names, kinds, COLOURS)]
    return geo, side, front, side_scale, front_scale, specs


def test_drawing_equals_geometry_to_pixel_resolution(views):
    geo, side, front, ss, fs, specs = views
    img = drawing_variables(side, front, ss, fs, specs).variables
    px = 1.0 / PPM
    for name in ("L", "B", "H_BR"):
        assert float(getattr(img, name)) == pytest.approx(float(getattr(geo, name)), abs=px)
    for name in ("C", "C_BR", "H_C"):  # centroids: within a pixel
        assert float(getattr(img, name)) == pytest.approx(float(getattr(geo, name)), abs=px)
    # Areas: within half a pixel along each outline (perimeter × px / 2, plus the union's shared edges).
    for name, perim in (("A_L", 2 * 250 + 4 * 48), ("A_T", 4 * 48), ("A_OD", 900.0), ("A_SS", 150.0)):
        assert abs(float(getattr(img, name)) - float(getattr(geo, name))) <= perim * px / 2
    assert float(img.S) == pytest.approx(float(geo.S), abs=12 * px)  # skimage's perimeter estimator: a few pixels per corner
    assert float(img.M) == float(geo.M) == 1.0
    assert img.part_names == geo.part_names
    # Each edge is rounded to pixel centres: at most half a pixel along the outline (+ the corners).
    assert np.all(np.abs(img.part_area - geo.part_area) <= geo.part_perimeter * px / 2 + 4 * px**2)
    np.testing.assert_allclose(img.part_x, geo.part_x, atol=px)
    np.testing.assert_allclose(img.part_h, geo.part_h, atol=px)
    # Moments ∬x^p h^q dA of each part about (mid-length, waterline), p + q ≤ 3: the same half-pixel band
    # along the outline, weighted by at most |x|^p |h|^q (|x| ≤ 125 m, |h| ≤ 48.2 m here).
    band = np.asarray(geo.part_perimeter) * px / 2 + 4 * px**2
    for p in range(4):
        for q in range(4 - p):
            err = np.abs(np.asarray(img.part_moments[:, p, q] - geo.part_moments[:, p, q]))
            assert np.all(err <= band * 126.0**p * 49.0**q), (p, q)


def test_moments_match_regionprops(views):
    geo, side, front, ss, fs, specs = views
    res = drawing_variables(side, front, ss, fs, specs)
    mask = res.side_mask
    rp = measure.regionprops(mask.astype(np.uint8))[0]
    # Central moments are translation-invariant: regionprops' (pixels, rows/cols) equal ours scaled to metres.
    from hullopt.wind import mask_moments

    m = mask_moments(mask, ss, 0.0) * ss.ppm**2  # pixel counts
    xc, hc = m[1, 0] / m[0, 0], m[0, 1] / m[0, 0]
    mu20 = m[2, 0] - xc * m[1, 0]  # Σ(x − x̄)² in m², regionprops: Σ(col − c̄)² in px²
    mu03 = m[0, 3] - 3 * hc * m[0, 2] + 2 * hc**2 * m[0, 1]
    assert m[0, 0] == rp.area
    assert mu20 * ss.ppm**2 == pytest.approx(rp.moments_central[0, 2], rel=1e-9)
    assert -mu03 * ss.ppm**3 == pytest.approx(rp.moments_central[3, 0], rel=1e-9, abs=1e-6 * rp.area**2.5)


@pytest.mark.slow
def test_box_counting_dimension():
    rect = np.zeros((512, 512), dtype=bool)
    rect[100:400, 50:450] = True
    assert box_counting_dimension(outline(rect)) == pytest.approx(1.0, abs=0.05)
    # Koch snowflake, 6 iterations, 480 px across: log 4 / log 3 = 1.2619.
    pts = np.array([[0.0, 0.0], [0.5, np.sqrt(3) / 2], [1.0, 0.0]])
    for _ in range(6):
        a, b = pts, np.roll(pts, -1, axis=0)
        d = (b - a) / 3
        rot = np.array([[0.5, np.sqrt(3) / 2], [-np.sqrt(3) / 2, 0.5]])  # −60°: the bump points outward
        tip = a + d + d @ rot.T
        pts = np.stack([a, a + d, tip, a + 2 * d], axis=1).reshape(-1, 2)
    img = np.zeros((700, 700), dtype=bool)
    rr, cc = draw.polygon(150 + 480 * pts[:, 1], 110 + 480 * pts[:, 0], img.shape)
    img[rr, cc] = True
    assert box_counting_dimension(outline(img)) == pytest.approx(np.log(4) / np.log(3), abs=0.06)


def test_bad_drawings(views):
    geo, side, front, ss, fs, specs = views
    with pytest.raises(HullError, match="pixels_per_metre"):
        ViewScale(0.0, 140)
    blank = np.full_like(side, 255)
    with pytest.raises(HullError, match="empty mask"):
        drawing_variables(blank, front, ss, fs, [])
    with pytest.raises(HullError, match="'crane': empty mask"):
        drawing_variables(side, front, ss, fs, [PartSpec("crane", "cargo", (200, 200, 0))])


@pytest.mark.slow
def test_cli_config_and_drawings(tmp_path, views, capsys):
    cfg = tmp_path / "ship.toml"
    cfg.write_text('hull = "builtin:box?L=250&B=40&D=24"\ndraft = 12.0\n'
                   '[[parts]]\nname = "bridge"\nkind = "superstructure"\nx = [30, 42]\nz = [24, 60]\nbreadth = 36\n'
                   '[[parts]]\nname = "funnel"\nside = [[20, 24], [28, 24], [27, 55], [21, 55]]\nbreadth = 8\n')
    assert main(["wind", str(cfg), "--json", "--model", "isherwood", "--plot", str(tmp_path / "p.png")]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["variables"]["A_L"] == pytest.approx(250 * 12 + 12 * 36 + (8 + 6) / 2 * 31, rel=1e-12)
    assert out["coefficients"]["psi_deg"][-1] == 180 and len(out["coefficients"]["cx"]) == 19
    assert out["coefficients"]["cx"][0] < 0 and out["coefficients"]["ck"][0] is None  # Isherwood: no C_K
    assert (tmp_path / "p.png").stat().st_size > 1000
    # Drawings: the rendered views as PNGs and a JSON spec with the scale and the part colours.
    geo, side, front, ss, fs, specs = views
    io.imsave(tmp_path / "side.png", side, check_contrast=False)
    io.imsave(tmp_path / "front.png", front, check_contrast=False)
    spec = {"side": "side.png", "front": "front.png",
            "side_scale": {"pixels_per_metre": PPM, "waterline_row": 140, "origin_col": 20},
            "front_scale": {"pixels_per_metre": PPM, "waterline_row": 140},
            "parts": [{"name": s.name, "kind": s.kind, "colour": list(s.colour)} for s in specs]}
    (tmp_path / "d.json").write_text(json.dumps(spec))
    assert main(["wind", str(tmp_path / "d.json"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["variables"]["A_L"] == pytest.approx(float(geo.A_L), rel=0.01)
    assert 0.9 < out["variables"]["fractal_dimension"] < 1.2
    # Bad input: one line on stderr, exit code 2.
    del spec["side_scale"]["pixels_per_metre"]
    (tmp_path / "d.json").write_text(json.dumps(spec))
    for args, msg in [([str(tmp_path / "d.json")], "pixels_per_metre"),
                      ([str(cfg), "--model", "holtrop"], "--model 'holtrop'"),
                      ([str(cfg), "--draft", "30"], "above the deck")]:
        assert main(["wind", *args]) == 2
        assert msg in capsys.readouterr().err
    cfg.write_text('hull = "builtin:box?L=250&B=40&D=24"\ndraft = 12.0\n'
                   '[[parts]]\nname = "crane"\nkind = "cargo"\nx = [240, 260]\nz = [24, 40]\nbreadth = 4\n')
    assert main(["wind", str(cfg)]) == 2
    assert "outside the ship" in capsys.readouterr().err


def test_cli_every_model_side_by_side_with_the_reference_areas(tmp_path, capsys):
    """``--model all`` as ``waves --method all``: each model's coefficients over the same angles (each model's
    own run gives the same numbers), the reference areas said, one plot with every model."""
    from hullopt.wind import MODELS

    cfg = tmp_path / "ship.toml"
    cfg.write_text('hull = "builtin:box?L=250&B=40&D=24"\ndraft = 12.0\n'
                   '[[parts]]\nname = "bridge"\nkind = "superstructure"\nx = [30, 42]\nz = [24, 60]\nbreadth = 36\n')
    assert main(["wind", str(cfg), "--json", "--model", "all", "--step", "30", "--plot", str(tmp_path / "a.png")]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["model"] == "all" and set(out["models"]) == set(MODELS) and len(out["psi_deg"]) == 7
    assert "C_X = X/(q A_T)" in out["references"] and "C_N = N/(q A_L L)" in out["references"]
    assert main(["wind", str(cfg), "--json", "--model", "isherwood", "--step", "30"]) == 0
    one = json.loads(capsys.readouterr().out)
    assert one["coefficients"]["cx"] == out["models"]["isherwood"]["cx"]
    assert (tmp_path / "a.png").stat().st_size > 1000
    assert main(["wind", str(cfg), "--step", "30"]) == 0
    assert "C_Y = Y/(q A_L)" in " ".join(capsys.readouterr().out.split())
