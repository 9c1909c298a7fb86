"""NMRI in oblique, quartering and following seas: the lit range of Bf on hulls whose Bf is known by hand at
0°, 45°, 90°, 135° and 180°, C_U only for Bf > 0 (patent eq. 11), no negative reflection part, and the KCS and
DTC sea-state means no longer negative behind the beam."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hullopt.geometry import Sections
from hullopt.waves import bluntness, mean_added_resistance, nmri_added_resistance
from hullopt.waves._added_resistance import positive_part

BF = jax.jit(bluntness, static_argnames="aft")
HEADINGS = np.array([0.0, 45.0, 90.0, 135.0, 180.0])
D = 10.0


def wall_sided(x, y, lpp):
    """Wall-sided hull with waterline half-breadths ``y`` at stations ``x`` (sections keel–bilge–deck)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    yz = np.stack([np.stack([np.zeros_like(y), np.zeros_like(y)], -1), np.stack([y, np.zeros_like(y)], -1),
                   np.stack([y, np.full_like(y, D)], -1)], axis=1)
    return Sections(x=jnp.asarray(x), yz=jnp.asarray(yz), lpp=jnp.asarray(float(lpp)))


def box():
    """A rectangle L 100 × B 10: a flat bow face and a flat transom, each of breadth B, and parallel sides."""
    return wall_sided([0.0, 100.0], [5.0, 5.0], 100.0)


def wedge(e, b=5.0):
    """Transom, parallel body, a straight wedge bow of half-angle ``e`` to the stem."""
    xs = 50.0 + b / np.tan(e)
    return wall_sided([0.0, 50.0, xs], [b, b, 0.0], xs)


# By hand. Waves from α travel along k̂ = (−cos α, −sin α); an element with outward normal n is lit when
# k̂·n < 0 and adds (k̂·n)² n_x dl / B.
# Box: the bow face (n = (1, 0), breadth B) is lit for α < 90° and adds cos²α; the transom (n = (−1, 0)) is lit
# beyond 90° and adds −cos²α (only with aft="include"); the sides have n_x = 0.
# Wedge of half-angle E (half-breadth b = B/2, each side b/sin E long): weather side n = (sin E, cos E),
# −k̂·n = sin(α + E); lee side n = (sin E, −cos E), −k̂·n = sin(E − α); each adds sin²(…)·b, so
# Bf = ½[sin²(α+E)·[α+E < 180°] + sin²(α−E)·[α < E]], plus −cos²α from the transom beyond 90° if included.
def box_bf(deg, include):
    c2 = np.cos(np.radians(deg)) ** 2
    return c2 if deg < 90.0 else (-c2 if include else 0.0)


def wedge_bf(deg, e_deg, include):
    a, e = np.radians(deg), np.radians(e_deg)
    bow = 0.5 * (np.sin(a + e) ** 2 * (deg + e_deg < 180.0) + np.sin(a - e) ** 2 * (deg < e_deg))
    return bow + (-np.cos(a) ** 2 if include and deg > 90.0 else 0.0)


@pytest.mark.parametrize("aft", ["exclude", "include"])
def test_box_and_wedge_bf_by_hand_at_five_headings(aft):
    a = jnp.radians(jnp.asarray(HEADINGS))
    include = aft == "include"
    got = np.asarray(BF(box(), 5.0, a, aft=aft))
    np.testing.assert_allclose(got, [box_bf(d, include) for d in HEADINGS], rtol=1e-13, atol=1e-15)
    for e in (30.0, 60.0):
        got = np.asarray(BF(wedge(np.radians(e)), 5.0, a, aft=aft))
        np.testing.assert_allclose(got, [wedge_bf(d, e, include) for d in HEADINGS], rtol=1e-12, atol=1e-15)
    # the default is the lit entrance only: never negative, 0 in following seas
    assert aft != "exclude" or np.array_equal(got, np.asarray(BF(wedge(np.radians(60.0)), 5.0, a)))


def test_wedge_values_quoted():
    """The hand values themselves, written out for E = 30°: 0.25, ½sin²75°, ½sin²120° = 0.375, ½sin²165°, 0."""
    vals = [wedge_bf(d, 30.0, False) for d in HEADINGS]
    np.testing.assert_allclose(vals, [0.25, 0.5 * np.sin(np.radians(75.0)) ** 2, 0.375,
                                      0.5 * np.sin(np.radians(15.0)) ** 2, 0.0], rtol=1e-14, atol=1e-15)


def test_reflection_part_is_never_negative_and_c_u_only_for_positive_bf():
    """With aft="include" the box's Bf is −cos²α behind the beam; eq. 11 holds for Bf > 0 only and a
    reflected wave never pushes the ship ahead: K_AW is 0 there, not Bf(1 + C_U(Bf)·Fn) < 0."""
    s = box()
    u, a = 8.0, jnp.radians(jnp.asarray(HEADINGS))
    fn = u / np.sqrt(9.80665 * 100.0)
    nmri = jax.jit(nmri_added_resistance, static_argnames="aft")
    for aft in ("exclude", "include"):
        r = nmri(s, 5.0, u, jnp.array([0.5, 3.0]), a, aft=aft)
        bf = np.array([box_bf(d, False) for d in HEADINGS])  # the positive part, either way
        cu = np.maximum(68.0 - 310.0 * bf, 10.0)
        np.testing.assert_allclose(r.k_aw_short, bf * (1.0 + cu * fn), rtol=1e-13, atol=1e-15)
        assert np.all(np.asarray(r.k_aw) >= 0.0) and np.all(np.asarray(r.r_awr)[:, 3:] == 0.0)  # 90°: cos²α ~ 1e-33
    np.testing.assert_allclose(r.bf, [box_bf(d, True) for d in HEADINGS], rtol=1e-13, atol=1e-15)  # reported


def test_smooth_positive_part():
    """The optimiser's Bf⁺: exact outside (0, w), w = τ/310, C¹ and below the exact value by at most 4w/27."""
    w = 1.0 / 310.0
    b = jnp.linspace(-0.01, 0.02, 3001)
    soft, exact = np.asarray(jax.jit(positive_part, static_argnums=1)(b, 1.0)), np.asarray(positive_part(b))
    out = (np.asarray(b) <= 0) | (np.asarray(b) >= w)
    np.testing.assert_array_equal(soft[out], exact[out])
    gap = exact - soft
    assert gap.min() >= 0.0 and gap.max() == pytest.approx(4 * w / 27, rel=1e-4)
    g = np.asarray(jax.jit(jax.vmap(jax.grad(lambda v: positive_part(v, 1.0))))(b))
    assert np.all(np.isfinite(g)) and np.abs(np.diff(g)).max() < 4.5 * 1e-5 / w  # continuous slope (f″ ≤ 4/w), 0 → 1
    # following seas stay exactly zero with the smooth form, and the gradient there is finite
    s = box()
    f = jax.jit(jax.value_and_grad(
        lambda t: nmri_added_resistance(s, t, 8.0, 0.6, jnp.pi, smooth=1.0, aft="include").k_aw))
    value, grad = f(5.0)
    assert float(value) == 0.0 and np.isfinite(float(grad))


@pytest.mark.parametrize("spec, draft, speed_kn", [
    ("kcs_model_closed_from_igs.stl.gz?scale=31.6&lpp=230", 10.8, 24.0),
    ("parent:dtc", None, 16.0),
])
def test_real_hulls_no_negative_mean_behind_the_beam(hulls, spec, draft, speed_kn):
    """The issue's cases: KCS 24 kn and DTC 16 kn, H_s 3 m, T_p 9 s: the mean R_AW by NMRI was −418 kN (KCS,
    180°), −271 kN (150°), −106 kN (135°). Now ≥ 0 at every heading, exactly 0 in following seas (no part of
    the entrance lit), and head seas unchanged by the lit-range rule (no aft-facing element lit there)."""
    from hullopt.study import load_hull

    h = load_hull(spec if spec.startswith("parent:") else str(hulls / spec))
    t = draft or h.design_draft
    s, u = h.sections, speed_kn * 0.514444
    a = jnp.radians(jnp.asarray(HEADINGS))
    bf = np.asarray(BF(s, t, a))
    assert np.all(bf >= 0.0) and bf[-1] == 0.0
    np.testing.assert_allclose(bf[0], float(BF(s, t, 0.0, aft="include")), rtol=1e-12)
    mean = jax.jit(jax.vmap(lambda hd: mean_added_resistance("nmri", s, t, u, 3.0, 9.0, hd, motion=False).total))(a)
    mean = np.asarray(mean)
    assert np.all(mean >= 0.0) and mean[-1] == 0.0 and mean[0] > 5e4
