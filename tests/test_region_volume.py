"""The displaced volume of a region of the hull (issue [W4 2/6] item 2: the NATO AVT-331 L2-Sea benchmark holds
the DTMB 5415's sonar-dome volume): the quadrature restricted to a range against closed forms (a box's
B·(x_b − x_a)·min(z_top, T), the Wigley's), its gradients against central differences, the config's
``[[constraints.region_volume]]`` parsed strictly, and the bound held by the constrained solver."""

import tomllib
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from helpers import check_grad

from hullopt.geometry import (
    Sections,
    longitudinal_integrals,
    region_volume,
    section_integrals,
    simpson_weights,
    simpson_weights_between,
)
from hullopt.models import box, wigley

ONE_CONDITION = Path(__file__).resolve().parent / "data" / "rescore_wigley.toml"  # a minimise run on the Wigley


def _stations(n, seed=0):
    """``n`` unevenly spaced stations from 0 to 10 m."""
    x = np.sort(np.random.default_rng(seed).uniform(0.0, 10.0, n))
    x[0], x[-1] = 0.0, 10.0
    return x


@pytest.mark.parametrize("n", [2, 3, 4, 5, 8, 9])
def test_the_restricted_rule_is_simpsons_over_the_stations_and_exact_for_quadratics(n):
    """Over the whole hull (and beyond it) the weights are :func:`simpson_weights`'; over any part of it the rule
    integrates a quadratic exactly (n = 2, the trapezoidal rule: a line), wherever the range starts or ends —
    between stations, on one, outside the hull; an empty range gives nothing."""
    x = _stations(n, seed=n)
    for lo, hi in ((-np.inf, np.inf), (-3.0, 12.0), (0.0, 10.0)):
        np.testing.assert_allclose(simpson_weights_between(x, lo, hi), simpson_weights(x), rtol=1e-12, atol=1e-12)
    f, F = (lambda t: 1.0 + 2.0 * t - 0.3 * t**2, lambda t: t + t**2 - 0.1 * t**3) if n > 2 else \
        (lambda t: 1.0 + 2.0 * t, lambda t: t + t**2)
    for lo, hi in ((2.3, 7.1), (x[1], 9.0), (-1.0, 4.4), (6.5, 20.0), (0.3, 0.31)):
        a, b = max(lo, 0.0), min(hi, 10.0)
        want = F(b) - F(a) if a < b else 0.0
        assert float(simpson_weights_between(x, lo, hi) @ f(x)) == pytest.approx(want, rel=1e-11, abs=1e-12)
    assert np.all(np.asarray(simpson_weights_between(x, 7.0, 3.0)) == 0.0)


@pytest.mark.parametrize("x_a, x_b, z_top", [
    (63.7, np.inf, 3.2),      # forward of a point between stations, below a height under the draft
    (60.0, np.inf, 3.2),      # from a station
    (-5.0, 41.3, 9.0),        # aft of a point; z_top above the draft: clipped at the waterline
    (12.4, 87.9, 5.0),        # both ends between stations, z_top at the draft
    (-np.inf, np.inf, np.inf),  # the whole hull: ∇
])
def test_a_box_region_is_b_times_its_length_times_its_height(x_a, x_b, z_top):
    """A box 100 × 10 m (11 stations, 10 m apart) at T = 5 m: B·(min(x_b, L) − max(x_a, 0))·min(z_top, T)."""
    s = box(100.0, 10.0, 8.0, n=11)
    want = 10.0 * (min(x_b, 100.0) - max(x_a, 0.0)) * min(z_top, 5.0)
    assert float(jax.jit(region_volume)(s, 5.0, x_a, x_b, z_top)) == pytest.approx(want, rel=1e-13)


def test_the_wigleys_region_by_its_closed_form():
    """The Wigley y = B/2 (1 − ξ²)(1 − ζ²) (ξ = 2x/L − 1, ζ = (T − z)/T): its volume forward of x_a below
    h ≤ T is B·T·L/2 · [2/3 − (s − s³/3)] · [2/3 − (ξ_a − ξ_a³/3)], s = 1 − h/T — the polyline's 201 points a
    section within 3e-5 of it (the keel's the least well drawn); its sectional-area curve is quadratic, so the restricted rule is exact along x
    (against the midship polygon's own area, to round-off); the whole region is the hull's ∇."""
    L, B, T = 100.0, 10.0, 6.25
    s = wigley(L, B, T, 10.0)
    volume = jax.jit(lambda x_a, h: region_volume(s, T, x_a, jnp.inf, h))
    midship = jax.jit(lambda h: 2.0 * section_integrals(s, h).area[40])  # the midship polygon's area below h
    for x_a, h in ((71.3, 2.0), (50.0, T), (3.1, 4.4), (88.8, 9.0)):
        xi, sh = 2 * x_a / L - 1, 1 - min(h, T) / T
        want = B * T * L / 2 * (2 / 3 - (sh - sh**3 / 3)) * (2 / 3 - (xi - xi**3 / 3))
        got = float(volume(x_a, h))
        assert got == pytest.approx(want, rel=3e-5)
        mid = float(midship(min(h, T)))
        assert got == pytest.approx(mid * L / 2 * (2 / 3 - (xi - xi**3 / 3)), rel=1e-12)
    whole = jax.jit(lambda s: (region_volume(s, T), longitudinal_integrals(s, T).volume))(s)
    assert float(whole[0]) == pytest.approx(float(whole[1]), rel=1e-14)


def _flared(p, x_a=63.7, z_top=3.3):
    """The region's volume of a box 100 × 10 × 8 m whose half-breadths grow by ``p[0]`` per metre up and
    ``p[1]`` per metre forward, with the region's ``x_a`` and ``z_top`` moved by ``p[2]``, ``p[3]``."""
    s = box(100.0, 10.0, 8.0, n=11)
    yz = jnp.stack([jnp.array([[0.0, 0.0], [5.0, 0.0], [5.0, 2.0], [5.0, 4.0], [5.0, 8.0]])] * 11)
    y = yz[..., 0] * (1.0 + p[0] * yz[..., 1] + p[1] * s.x[:, None])
    return region_volume(Sections(s.x, yz.at[..., 0].set(y), s.lpp), 5.0, x_a + p[2], jnp.inf, z_top + p[3])


def test_the_gradient_in_the_sections_and_the_region_against_central_differences():
    """∂/∂ of the half-breadths (flare, a taper along the length), of ``x_a`` (−A at x_a of the quadrature's
    parabola) and of ``z_top`` (the region's waterplane breadth over its length) against central differences;
    on the straight box ∂V/∂x_a = −B·z_top and ∂V/∂z_top = B·(L − x_a) exactly."""
    check_grad(jax.jit(_flared), np.array([0.02, 0.003, 0.0, 0.0]), rtol=1e-7)
    g = np.asarray(jax.jit(jax.grad(_flared))(jnp.zeros(4)))
    assert g[2] == pytest.approx(-10.0 * 3.3, rel=1e-12) and g[3] == pytest.approx(10.0 * (100.0 - 63.7), rel=1e-12)


def test_the_gradient_as_the_stations_move_and_the_volume_is_continuous_across_a_station():
    """Stations that move (a Lackenby shift) under a fixed ``x_a``: the weights' gradient in the stations against
    central differences; the volume is continuous and smooth as ``x_a`` crosses a station (the Wigley's
    stations 1.25 m apart: the one-sided slopes agree with −A there)."""
    w = wigley(100.0, 10.0, 6.25, 10.0, n=21, m=41)

    def shifted(d):
        x = w.x + d[0] * jnp.sin(jnp.pi * w.x / 100.0) + d[1] * jnp.sin(2 * jnp.pi * w.x / 100.0)
        return region_volume(Sections(x, w.yz, w.lpp), 6.25, 71.3, 97.0, 4.0)

    check_grad(jax.jit(shifted), np.array([0.4, -0.2]), rtol=1e-7)
    v = jax.jit(lambda a: region_volume(w, 6.25, a, jnp.inf, 4.0))
    at = 75.0  # a station
    h = 1e-5
    left, right = (float(v(at - h)) - float(v(at))) / -h, (float(v(at + h)) - float(v(at))) / h
    area = 2.0 * float(jax.jit(section_integrals)(w, 4.0).area[15])
    assert float(w.x[15]) == at
    assert left == pytest.approx(-area, rel=1e-5) and right == pytest.approx(-area, rel=1e-5)


def _raw(**constraints) -> dict:
    raw = tomllib.loads(ONE_CONDITION.read_text())
    raw["constraints"] = constraints
    return raw


DOME = {"name": "sonar_dome", "x_a": 80.0, "z_top": 3.0, "bound": ">= parent"}


def test_a_region_volume_config_reaches_the_limits_beside_the_frozen_bulb():
    """``[[constraints.region_volume]]``: the measure ``region_volume:<name>`` with its bound, the region's
    numbers as arrays (a run with other numbers keeps its programs: ``structure`` blanks them), the unit the
    report shows, and the default limits and ``frozen = "auto"`` still held beside it."""
    from hullopt.optimise import RegionVolume
    from hullopt.study import DEFAULT_LIMITS, RunConfig, limits_from, structure

    text = """
        [[constraints.region_volume]]
        name = "sonar_dome"
        x_a = 80.0
        z_top = 3.0
        bound = ">= parent"
        [[constraints.region_volume]]
        name = "stern"
        x_b = 20.0
        bound = [">= 0.9 * parent", "<= 1.1 * parent"]
    """
    raw = _raw()
    raw["constraints"] = tomllib.loads(text)["constraints"]
    cfg = RunConfig.model_validate(raw)
    c = cfg.constraints
    assert c.written()["region_volume:sonar_dome"] == ">= parent"
    assert c.written()["region_volume:stern"] == ">= 0.9 * parent and <= 1.1 * parent"
    assert c.bounds()["region_volume:sonar_dome"] == ((-1, 1.0, True, 0.0),)
    assert set(DEFAULT_LIMITS) <= set(c.bounds()) and c.frozen == "auto"
    lim = limits_from(cfg)
    assert lim.names[-3:] == ("region_volume:sonar_dome", "region_volume:stern", "region_volume:stern")
    dome, stern = lim.measures[-3], lim.measures[-1]
    assert isinstance(dome, RegionVolume) and dome.unit == "m³" and lim.frozen == "auto"
    assert (float(dome.x_a), float(dome.x_b), float(dome.z_top)) == (80.0, np.inf, 3.0)
    assert (float(stern.x_a), float(stern.x_b), float(stern.z_top)) == (-np.inf, 20.0, np.inf)
    np.testing.assert_array_equal(lim.sense[-3:], [-1.0, -1.0, 1.0])
    moved = RunConfig.model_validate({**raw, "constraints": {"region_volume": [{**DOME, "x_a": 82.5}]}})
    base = RunConfig.model_validate({**raw, "constraints": {"region_volume": [DOME]}})
    assert structure(moved) == structure(base)


@pytest.mark.parametrize("region, message", [
    ({**DOME, "bound": ">= parents"}, "constraints.region_volume[0].bound = '>= parents': expected '<= parent'"),
    ({**DOME, "x_b": 70.0}, "constraints.region_volume[0] (sonar_dome): x_a = 80, x_b = 70: expected x_a < x_b"),
    ({"name": "dome", "bound": ">= parent"}, "constraints.region_volume[0] (dome): give x_a, x_b or z_top"),
    ({**DOME, "z_bottom": 1.0}, "constraints.region_volume.0.z_bottom"),
    ({**DOME, "name": "sonar dome"}, "constraints.region_volume.0.name"),
    ({k: v for k, v in DOME.items() if k != "bound"}, "constraints.region_volume.0.bound"),
    ({**DOME, "bound": [">= parent"]}, "constraints.region_volume[0].bound = ['>= parent']: a two-sided bound is"),
])
def test_a_bad_region_fails_with_its_field(region, message):
    from hullopt.study import RunConfig

    with pytest.raises(ValueError, match="1 validation error") as e:
        RunConfig.model_validate(_raw(region_volume=[region]))
    assert message in str(e.value)


def test_two_regions_of_one_name_are_refused():
    from hullopt.study import RunConfig

    with pytest.raises(ValueError, match=r"constraints.region_volume\[1\]: name 'sonar_dome' is given twice"):
        RunConfig.model_validate(_raw(region_volume=[DOME, {**DOME, "x_a": 90.0}]))


@pytest.mark.parametrize("change, message", [
    ({"x_a": 120.0}, r"constraints.region_volume\[0\] \(sonar_dome\): x_a … x_b = 120.0 … – m is off 'wigley'"),
    ({"z_top": -0.5}, r"constraints.region_volume\[0\] \(sonar_dome\): z_top = -0.5 m is at or below the keel"),
])
def test_a_region_off_the_parent_is_refused_before_the_run(change, message):
    """A bound on a region that holds none of the parent would be met by any design: refused, naming it."""
    from hullopt.errors import HullError
    from hullopt.study import RunConfig, load_study

    with pytest.raises(HullError, match=message):
        load_study(RunConfig.model_validate(_raw(region_volume=[{**DOME, **change}])))


def _tapered(p):
    """A box 10 × 2 × 3 m (11 stations) whose half-breadth is 1 + p·x/L: the forward body fills as p grows."""
    x = jnp.linspace(0.0, 10.0, 11)
    y = 1.0 + p[0] * x / 10.0
    z = jnp.array([0.0, 0.0, 3.0])
    yz = jnp.stack([jnp.stack([jnp.zeros(11), jnp.zeros(11)], -1), jnp.stack([y, jnp.zeros(11)], -1),
                    jnp.stack([y, jnp.full(11, z[2])], -1)], axis=1)
    return Sections(x, yz, 10.0)


def test_a_region_volume_bound_is_active_in_the_solver():
    """min (p + 1)² (the forward body emptied) with the volume forward of x_a = 6.3 m below z 1.5 m (T 2 m) at
    least 0.9× the parent's (p = 0): V(p) = 2·1.5·[(L − x_a) + p (L² − x_a²)/(2L)], so the bound is
    p ≥ −0.2 L/(L + x_a) = −0.1227…, where the solution sits, the constraint met and on it."""
    from hullopt.optimise import Limits, RegionVolume, minimise_constrained

    region = RegionVolume(np.asarray(6.3), np.asarray(np.inf), np.asarray(1.5))
    lim = Limits(names=("region_volume:fore",), measures=(region,), sense=-np.ones(1), values=np.full(1, 0.9),
                 relative=(True,), max_half_breadth=None, bulge=False).at_parent(_tapered(jnp.zeros(1)), 2.0)
    assert float(lim.groups(_tapered(jnp.zeros(1)), 2.0)["region_volume:fore"]) == pytest.approx(-0.1 / 0.9)

    def solve():
        return minimise_constrained(lambda p, a: (p[0] + 1.0) ** 2, lambda p, a: jnp.zeros(1), jnp.zeros(1),
                                    -2.0 * jnp.ones(1), 2.0 * jnp.ones(1), tol=1e-6,
                                    inequalities=lambda p, a: lim(_tapered(p), 2.0),
                                    inequality_tol=1e-6, outer=8, max_steps=100)

    r = jax.jit(solve)()
    assert bool(r.met) and float(r.params[0]) == pytest.approx(-0.2 * 10.0 / 16.3, abs=1e-6)
    assert float(lim.groups(_tapered(r.params), 2.0)["region_volume:fore"]) == pytest.approx(0.0, abs=1e-6)
