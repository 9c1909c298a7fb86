"""The bow attachment (JP2009-286166 claims 4–5, :mod:`hullopt.models._bow`) and the beam scale: closed forms on a
wall-sided wedge bow, the continuum Bf of the new waterline, gradients against central differences, the parent
back bit for bit at zero, and a watertight export."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import check_grad

from hullopt.errors import HullError
from hullopt.geometry import Sections, to_trimesh
from hullopt.hydro import hydrostatics
from hullopt.models import (BowAttachment, FeatureParams, attach_bow, attachment_plan, band_weight, feature_model,
                            load_parent, stem_station)
from hullopt.waves import bluntness

L, B0, T, D = 100.0, 10.0, 6.0, 10.0  # the wedge bow: length, beam, draft, depth [m]
ENTRANCE = 20.0  # the wedge's length [m]: half-angle atan(5/20)


def wedge(n: int = 801, m: int = 201) -> Sections:
    """A wall-sided hull whose waterlines are a rectangle ending in a wedge of half-angle atan(B0/2/ENTRANCE),
    with dense offsets up its side (so that a height band is sampled finely)."""
    x = np.linspace(0.0, L, n)
    b = 0.5 * B0 * np.minimum(1.0, (L - x) / ENTRANCE)
    z = np.linspace(0.0, D, m - 1)
    yz = np.zeros((n, m, 2))
    yz[:, 1:, 0] = b[:, None]
    yz[:, 1:, 1] = z
    return Sections(x=jnp.asarray(x), yz=jnp.asarray(yz), lpp=jnp.asarray(L))


ATT = BowAttachment(x_blend=60.0, z_lo=3.0, blend=1.5, x_peak=90.0, x_stem=100.0)


def test_band_weight_is_one_inside_zero_outside_and_c2():
    z = np.array([0.0, 1.49, 1.5, 2.25, 3.0, 5.0, 7.0, 7.75, 8.5, 9.0])
    v = np.asarray(band_weight(jnp.asarray(z), 3.0, 7.0, 1.5))
    np.testing.assert_allclose(v[[0, 1, 2, 9]], 0.0, atol=1e-12)
    np.testing.assert_allclose(v[[4, 5, 6]], 1.0)
    np.testing.assert_allclose(v[[3, 7]], 0.5)  # the smootherstep's middle
    # C²: first and second derivatives vanish at both ends of each ramp
    for z0 in (1.5, 3.0, 7.0, 8.5):
        d1 = jax.grad(lambda z: band_weight(z, 3.0, 7.0, 1.5))
        d2 = jax.grad(d1)
        for dz in (-1e-4, 1e-4):
            assert abs(float(d1(z0 + dz))) < 1e-6 and abs(float(d2(z0 + dz))) < 1e-2
    assert float(band_weight(jnp.asarray(50.0), 3.0, math.inf, 1.5)) == 1.0  # to the deck


def test_plan_form_closed_form():
    x = np.linspace(0.0, 100.0, 101)
    w = attachment_plan(x, ATT, stem=100)
    np.testing.assert_allclose(w[x <= 60.0], 0.0)
    np.testing.assert_allclose(w[75], math.sin(math.pi / 4) ** 2)
    np.testing.assert_allclose(w[90], 1.0)
    np.testing.assert_allclose(w[95], math.sqrt(1.0 - 0.25))
    assert w[100] == 0.0
    with pytest.raises(HullError, match="x_blend < x_peak < x_stem"):
        attachment_plan(x, BowAttachment(x_blend=95.0, z_lo=3.0, x_peak=90.0), stem=100)


def test_wedge_volume_and_bf_against_closed_forms():
    s = wedge()
    assert stem_station(s, T) == len(s.x) - 1
    np.testing.assert_allclose(float(bluntness(s, T)), math.sin(math.atan(0.5 * B0 / ENTRANCE)) ** 2, rtol=1e-9)
    a = 1.2
    w = attachment_plan(np.asarray(s.x), ATT, stem_station(s, T))
    band = np.array([[ATT.z_lo, ATT.z_hi, ATT.blend]])
    out = attach_bow(s, jnp.array([a]), w[None], band)
    # ∇ added: 2a ∫W dx ∫V dz, ∫W dx = (x_peak − x_blend)/2 + π/4 (x_stem − x_peak), ∫₀^T V dz = T − z_lo + blend/2
    added = 2 * a * (15.0 + math.pi / 4 * 10.0) * (T - 3.0 + 0.75)
    dv = float(hydrostatics(out, T).volume - hydrostatics(s, T).volume)
    np.testing.assert_allclose(dv, added, rtol=2e-4)
    # Bf of the new waterline y(x) = wedge + a·W(x) against the continuum (2/B)∫ (−y')³/(1 + y'²) dx where y' < 0
    xs = np.linspace(60.0, 100.0, 4_000_001)
    yw = 0.5 * B0 * np.minimum(1.0, (L - xs) / ENTRANCE)
    wx = np.where(xs <= 90.0, np.sin(0.5 * np.pi * (xs - 60.0) / 30.0) ** 2,
                  np.sqrt(np.clip(1.0 - ((xs - 90.0) / 10.0) ** 2, 0.0, 1.0)))
    y = yw + a * wx
    dy = -np.diff(y) / np.diff(xs)
    f = np.where(dy > 0, dy**3 / (1.0 + dy**2), 0.0)
    bf = 2.0 / (2.0 * y.max()) * np.sum(f * np.diff(xs))
    np.testing.assert_allclose(float(bluntness(out, T)), bf, rtol=4e-3)  # the nose, √ at the stem, on 0.125 m stations
    assert bf > 1.5 * math.sin(math.atan(0.5 * B0 / ENTRANCE)) ** 2  # blunter, as the patent means


def test_band_above_the_waterline_leaves_the_dwl_alone():
    """Fig. 16: a band from the waterline up changes nothing at or below it (∇, Bf at the DWL)."""
    s = wedge(n=201, m=201)
    att = BowAttachment(x_blend=60.0, z_lo=T + 2.0, blend=1.5, x_peak=90.0)  # ramp from T + 0.5 m
    w = attachment_plan(np.asarray(s.x), att, stem_station(s, T))
    out = attach_bow(s, jnp.array([2.0]), w[None], np.array([[att.z_lo, att.z_hi, att.blend]]))
    assert float(hydrostatics(out, T).volume) == pytest.approx(float(hydrostatics(s, T).volume), rel=1e-12)
    assert float(bluntness(out, T)) == pytest.approx(float(bluntness(s, T)), rel=1e-12)
    assert float(bluntness(out, T + 2.5)) > 1.5 * float(bluntness(s, T + 2.5))


@pytest.fixture(scope="module")
def wigley_bow():
    hull = load_parent("wigley")
    return hull, feature_model(hull, bows=[BowAttachment(x_blend=60.0, z_lo=4.0, blend=1.5)], beam=True)


def _params(model, a=0.0, s=0.0):
    p = model.zeros()
    return FeatureParams(p.apex, p.distribution, p.contour, jnp.array([a]), jnp.array([s]))


def test_zero_parameters_give_the_parent_exactly(wigley_bow):
    hull, model = wigley_bow
    np.testing.assert_array_equal(np.asarray(model(model.zeros()).yz), np.asarray(hull.sections().yz))


def test_beam_scale_scales_breadth_and_volume(wigley_bow):
    hull, model = wigley_bow
    h0, h1 = hydrostatics(hull.sections(), 6.25), hydrostatics(model(_params(model, s=0.04)), 6.25)
    np.testing.assert_allclose(float(h1.volume / h0.volume), 1.04, rtol=1e-12)
    np.testing.assert_allclose(float(h1.bwl / h0.bwl), 1.04, rtol=1e-12)
    np.testing.assert_allclose(float(h1.cb), float(h0.cb), rtol=1e-12)  # a scale in y keeps every coefficient


def test_gradients_against_central_differences(wigley_bow):
    _, model = wigley_bow

    def f(v):
        s = model(_params(model, v[0], v[1]))
        return bluntness(s, 6.25) + hydrostatics(s, 6.25).volume / 1e4

    check_grad(jax.jit(f), np.array([0.4, 0.02]), rtol=1e-5)


def test_export_is_watertight_and_holds_the_volume(wigley_bow):
    _, model = wigley_bow
    s = model(_params(model, a=1.0))
    mesh = to_trimesh(s)
    assert mesh.is_watertight
    deck = float(np.max(np.asarray(s.yz)[..., 1]))
    np.testing.assert_allclose(mesh.volume, float(hydrostatics(s, deck).volume), rtol=2e-3)


def test_scale_mode_makes_a_finer_bow_and_keeps_the_stem():
    """mode "scale": every half-breadth in the band times 1 + a·W, W = 1 from x_peak to the bow; a = −0.5 halves the
    wedge's entrance there: its Bf falls to the finer wedge's sin²E′, tan E′ = ½ tan E (the wedge from x_peak on)."""
    s = wedge(n=401, m=101)
    att = BowAttachment(x_blend=40.0, z_lo=-2.0, blend=1.0, x_peak=80.0, mode="scale")  # the whole depth
    w = attachment_plan(np.asarray(s.x), att, stem_station(s, T))
    np.testing.assert_allclose(w[np.asarray(s.x) >= 80.0], 1.0)
    out = attach_bow(s, jnp.array([-0.5]), w[None], np.array([[att.z_lo, att.z_hi, att.blend]]), (True,))
    y = np.asarray(out.yz)[:, 1:, 0]
    assert y[-1].max() == 0.0  # the stem stays a stem
    # the waterline: B0/2 aft of 40 m, shrinking smoothly to B0/4 at 80 m, then the half-width wedge; B = B0
    tan_e = 0.25 * B0 / ENTRANCE
    bf = float(bluntness(out, T))
    lo = math.sin(math.atan(tan_e)) ** 2 / 2  # the wedge alone, normalised by the full beam
    assert lo < bf < lo + 0.01 and bf < 0.5 * math.sin(math.atan(2 * tan_e)) ** 2
