"""The Lackenby shift: targets met (checked by the hydrostatics), dimensions and midship held, identity at zero
change, the closed form against its own first-order prediction and the Wigley's analytic integrals, bad input."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import simpson

from hullopt.errors import HullError
from hullopt.geometry import Sections
from hullopt.hydro import hydrostatics, sectional_areas
from hullopt.models import box, lackenby, wigley
from hullopt.models._lackenby import lackenby_basis, lackenby_first_order

T = 6.25
hydro = jax.jit(hydrostatics)
areas = jax.jit(sectional_areas)


@pytest.fixture(scope="module")
def parent():
    return wigley(100.0, 10.0, T, 10.0, n=41, m=41)


@pytest.fixture(scope="module")
def h0(parent):
    return hydro(parent, T)


def with_parallel_body(p: float, n: int = 41) -> Sections:
    """Wigley midship section scaled by an area curve with a parallel middle body of ``p`` half-lengths
    each side and parabolic ends: y = 1 − ((|ξ| − p)/(1 − p))²."""
    s = wigley(100.0, 10.0, T, 10.0, n=n, m=41)
    xi = np.abs(np.asarray(s.x) - 50.0) / 50.0
    f = np.where(xi <= p, 1.0, 1.0 - ((xi - p) / (1.0 - p)) ** 2)
    yz = np.array(np.broadcast_to(np.asarray(s.yz[n // 2]), s.yz.shape))
    yz[..., 0] *= f[:, None]
    return Sections(s.x, jnp.asarray(yz), s.lpp)


def test_reaches_targets_and_holds_the_rest(parent, h0):
    cb_t = 1.03 * float(h0.cb)
    s = lackenby(parent, T, cb=cb_t, lcb_pct=-1.0)
    h = hydro(s, T)
    assert abs(float(h.cb) - cb_t) < 1e-6 and abs(float(h.lcb_pct) + 1.0) < 1e-6
    assert s.yz is parent.yz  # only the stations move
    x, x0 = np.asarray(s.x), np.asarray(parent.x)
    assert np.all(np.diff(x) > 0) and np.max(np.abs(x - x0)) > 0.5  # really shifted, still in order
    mid = np.argmin(np.abs(x0 - 50.0))
    assert x[0] == x0[0] and x[-1] == x0[-1] and x[mid] == x0[mid] == 50.0 and float(s.lpp) == float(parent.lpp)
    for k in ("bwl", "lwl", "cm", "draft"):
        assert float(getattr(h, k)) == pytest.approx(float(getattr(h0, k)), rel=1e-12)
    area, area0 = areas(s, T), areas(parent, T)
    assert float(area[mid]) == float(area0[mid])
    assert float(h.volume) / float(h0.volume) == pytest.approx(1.03, rel=1e-9)  # Cb +3 % is volume +3 %


def test_one_target_holds_the_other(parent, h0):
    s = lackenby(parent, T, lcb_pct=0.8)
    h = hydro(s, T)
    assert abs(float(h.lcb_pct) - 0.8) < 1e-9 and abs(float(h.cb) - float(h0.cb)) < 1e-12


@pytest.mark.parametrize("kw", [{}, "parent"])
def test_zero_change_is_the_identity(parent, h0, kw):
    kw = {"cb": float(h0.cb), "lcb_pct": float(h0.lcb_pct)} if kw == "parent" else kw
    s = lackenby(parent, T, **kw)
    np.testing.assert_allclose(np.asarray(s.x), np.asarray(parent.x), rtol=0, atol=1e-12)


def test_parallel_middle_body_is_held():
    s = with_parallel_body(0.2)
    h0 = hydro(s, T)
    out = lackenby(s, T, cb=1.02 * float(h0.cb), lcb_pct=-0.5)
    h = hydro(out, T)
    assert abs(float(h.cb) - 1.02 * float(h0.cb)) < 1e-9 and abs(float(h.lcb_pct) + 0.5) < 1e-9
    x, x0 = np.asarray(out.x), np.asarray(s.x)
    parallel = np.abs(x0 - 50.0) <= 10.0 + 1e-9
    assert np.array_equal(x[parallel], x0[parallel]) and np.all(x[~parallel][1:-1] != x0[~parallel][1:-1])


def test_half_body_integrals_of_the_wigley(parent):
    """y = 1 − ξ²: Cp = 2/3, x̄ = 3/8, K² = 1/5 (Simpson exact up to the polyline), A = 1/6, h = 3/5."""
    _, _, info = lackenby_basis(parent, T)
    np.testing.assert_allclose(info["cp"], 2 / 3, rtol=1e-12)
    np.testing.assert_allclose(info["xbar"], 3 / 8, rtol=1e-12)
    np.testing.assert_allclose(info["k2"], 1 / 5, rtol=1e-4)  # x⁴ term: Simpson's error h⁴/180
    np.testing.assert_allclose(info["p"], 0.0)
    np.testing.assert_allclose(info["a"], 1 / 6, rtol=1e-12)
    np.testing.assert_allclose(info["lever"], 3 / 5, rtol=1e-4)


def cp_lcb(x, area, a_mid):
    """Cp and LCB [half-lengths from midship] by scipy's Simpson rule: independent of the JAX path."""
    volume = simpson(area, x=x)
    return np.array([volume / (a_mid * 100.0), (simpson(x * area, x=x) / volume - 50.0) / 50.0])


@pytest.mark.parametrize("p", [0.0, 0.2])
def test_closed_form_is_the_first_order_of_the_exact_shift(p):
    """Lackenby's A (δCp per unit c) and lever h against central differences of Cp and LCB of the shifted
    stations (with and without a parallel middle body)."""
    s = with_parallel_body(p)
    g, _, info = lackenby_basis(s, T)
    np.testing.assert_allclose(info["p"], p, atol=1e-12)
    x, area = np.asarray(s.x), np.asarray(areas(s, T))
    a_mid = area[len(x) // 2]
    step = 1e-5
    jac = np.stack([(cp_lcb(x + g @ e, area, a_mid) - cp_lcb(x - g @ e, area, a_mid)) / (2 * step)
                    for e in np.eye(2) * step], axis=1)
    cp, b = cp_lcb(x, area, a_mid)
    a, h = info["a"], info["lever"]
    moment = np.array([-a[0] * h[0], a[1] * h[1]])  # aft lever measured aft
    np.testing.assert_allclose(jac[0], a / 2.0, rtol=1e-7)  # whole Cp = mean of the halves'
    np.testing.assert_allclose(jac[1], (moment - b * a) / (2.0 * cp), rtol=1e-7)


def test_closed_form_error_is_second_order(parent, h0):
    """Without refinement the error is O(δ²): a quarter when the change halves, and small against δ."""
    errs = []
    for eps in (0.25, 0.125):
        cb_t, lcb_t = float(h0.cb) + 0.01 * eps, -1.0 * eps
        h = hydro(lackenby(parent, T, cb=cb_t, lcb_pct=lcb_t, refine=False), T)
        errs.append(np.array([float(h.cb) - cb_t, float(h.lcb_pct) - lcb_t]))
    assert np.all(np.abs(errs[0]) < 0.01 * np.array([0.01, 1.0]) * 0.25)  # < 1 % of the change
    np.testing.assert_allclose(errs[0] / errs[1], 4.0, rtol=0.05)


def test_split_formula_balances_volume_and_moment():
    """δCp_F + δCp_A = 2δCp and the moment balance, for arbitrary half-body levers."""
    info = {"lever": np.array([0.55, 0.62]), "a": np.array([1.0, 1.0])}
    cp, b, d_cp, d_b = 0.6, 0.02, 0.03, -0.01
    d_a, d_f = lackenby_first_order(info, cp, b, d_cp, d_b)
    assert d_a + d_f == pytest.approx(2 * d_cp)
    h_a, h_f = info["lever"]
    # moment about midship (units A_mid·(L/2)², forward +) of the whole hull before and after
    assert 2 * cp * b + d_f * h_f - d_a * h_a == pytest.approx(2 * (cp + d_cp) * (b + d_b))


@pytest.mark.parametrize(
    "sections, kw, match",
    [
        ("wigley", {"cb": 1.2}, "cb = 1.2"),
        ("wigley", {"cb": 0.0}, "cb = 0.0"),
        ("wigley", {"lcb_pct": 60.0}, "lcb_pct = 60"),
        ("wigley", {"draft": 12.0}, "draft 12"),
        ("wigley", {"cb": 0.62}, "beyond the reach"),
        ("wigley", {"cb": 0.67}, "prismatic"),
        ("even", {"cb": 0.45}, "station at midship"),
        ("box", {"cb": 0.9}, "parallel middle body"),
    ],
)
def test_bad_input(parent, sections, kw, match):
    s = {"wigley": parent, "even": wigley(100.0, 10.0, T, 10.0, n=40, m=21),
         "box": box(100.0, 10.0, 8.0, n=9)}[sections]
    kw = dict(kw)
    draft = kw.pop("draft", T)
    with pytest.raises(HullError, match=match):
        lackenby(s, draft, **kw)
