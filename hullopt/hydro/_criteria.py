"""Intact stability criteria of the IMO IS Code 2008, Part A §2.2, as margins (value − required).

2.2.1 area under the GZ curve up to 30° ≥ 0.055 m·rad, up to 40° (or the flooding angle θf if less)
≥ 0.090 m·rad, between 30° and 40° (or θf) ≥ 0.030 m·rad; 2.2.2 GZ ≥ 0.20 m at a heel ≥ 30°; 2.2.3 the
maximum GZ at a heel ≥ 25°; 2.2.4 GM₀ ≥ 0.15 m.

Areas are Gauss–Legendre quadratures of GZ (smooth in the geometry). The maximum GZ beyond 30° and the angle
of the maximum are taken on a uniform heel grid: ``value`` is the exact one (grid maximum refined by the
parabola through its neighbours), and ``passed`` judges by it. ``margin`` is for an optimiser and is
conservative — it is never positive when the exact check fails: the max GZ beyond 30° is a softmax-weighted
mean of GZ (temperature ``tau`` [m]; a mean is never above the maximum); the angle of the maximum is the
smaller of the soft argmax (the softmax-weighted mean heel) and the exact angle. The soft argmax alone is not
conservative: on a curve that peaks early and then falls slowly, heels past the peak keep their weight and pull
it aft (GZ = 0.08·(φ/φm)·e^(1−φ/φm), φm = 22.3°: soft 25.9°, exact 22.3°, so a soft margin would pass a
curve that fails 2.2.3). Where the soft argmax is the smaller the margin is smooth; elsewhere it follows the
exact angle, which is continuous in GZ (the parabola's vertex moves continuously when the grid maximum passes
to a neighbour) and smooth between such switches.
"""

from __future__ import annotations

from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._types import Angle, Length
from ..geometry import safe_div
from ._tolerances import ANGLE_TOL

# (key, label, unit, required); angles in degrees in this table and in reports, radians in code.
CRITERIA = (
    ("area_0_30", "Area under GZ 0–30°", "m·rad", 0.055),
    ("area_0_40", "Area under GZ 0–40° (or θf)", "m·rad", 0.090),
    ("area_30_40", "Area under GZ 30–40° (or θf)", "m·rad", 0.030),
    ("gz_30", "Max GZ at heel ≥ 30°", "m", 0.20),
    ("angle_gz_max", "Heel of max GZ", "deg", 25.0),
    ("gm0", "Initial GM₀ (corrected)", "m", 0.15),
)
_GL_ORDER = 10
_GL_X, _GL_W = np.polynomial.legendre.leggauss(_GL_ORDER)


class Criteria(eqx.Module):
    """IS Code 2008 §2.2 criteria, each ``(6,)`` in the order of :data:`CRITERIA` (angles in degrees):
    ``value`` exact, ``required``, ``margin`` for an optimiser (value − required: equal to the exact margin
    for the areas and GM₀, smooth and never above it for the max GZ and its angle, so a margin ≥ 0 never
    passes a criterion the exact check fails). Also ``gz_max`` [m], ``angle_gz_max`` and ``vanishing_angle`` [rad] (the first zero of
    GZ past its maximum on the grid, NaN if GZ stays positive)."""

    value: Float[Array, " 6"]
    required: Float[Array, " 6"]
    margin: Float[Array, " 6"]
    gz_max: Float[Array, ""]
    angle_gz_max: Float[Array, ""]
    vanishing_angle: Float[Array, ""]

    @property
    def passed(self) -> Array:
        return self.value >= self.required

    def to_list(self) -> list[dict]:
        """One record per criterion (plain floats), as in ``hullopt stability --json``."""
        v, r, m = (np.asarray(a).tolist() for a in (self.value, self.required, self.margin))
        return [
            {"key": k, "criterion": label, "unit": unit, "value": v[i], "required": r[i], "margin": m[i],
             "margin_exact": v[i] - r[i], "pass": bool(v[i] >= r[i])}
            for i, (k, label, unit, _) in enumerate(CRITERIA)
        ]


def _upper(flooding_angle) -> Array:
    forty = jnp.deg2rad(40.0)
    return forty if flooding_angle is None else jnp.minimum(forty, jnp.asarray(flooding_angle))


def criteria_heels(flooding_angle: Angle | None = None, n_grid: int = 91, max_heel: float = np.pi / 2) -> Array:
    """The heels [rad] at which :func:`criteria_from_gz` needs GZ: Gauss nodes on [0, 30°] and
    [30°, min(40°, θf)], then a uniform grid of ``n_grid`` heels on [0, max_heel] (``max_heel`` > 30°).

    Parameters
    ----------
    flooding_angle : float or Array, scalar, optional
        Downflooding angle θf [rad]; ``None`` means none (the upper limit is 40°).
    n_grid : int
        Number of heels on the uniform grid (91 by default: 1° steps to 90°).
    max_heel : float
        The uniform grid's last heel [rad], above 30° (π/2 by default).

    Returns
    -------
    Array, (20 + n_grid,) float
        10 Gauss nodes on [0, 30°], 10 on [30°, min(40°, θf)], then the grid [rad].
    """
    a, b = jnp.deg2rad(30.0), _upper(flooding_angle)
    x = jnp.asarray(_GL_X)
    return jnp.concatenate([0.5 * a * (x + 1.0), a + 0.5 * (b - a) * (x + 1.0), jnp.linspace(0.0, max_heel, n_grid)])


def _parabola_peak(g: Array, i: Array, h, lowest: Array | int = 1) -> tuple[Array, Array]:
    """Offset [rad] and value of the vertex of the parabola through g[i−1], g[i], g[i+1] (grid step ``h``);
    no refinement at an end of the grid or below index ``lowest``."""
    n = g.shape[0]
    j = jnp.clip(i, 1, n - 2)
    g0, g1, g2 = g[j - 1], g[j], g[j + 1]
    den = g0 - 2.0 * g1 + g2
    ok = (i == j) & (i >= lowest) & (den < 0.0)
    d = safe_div(0.5 * (g0 - g2), den, ok)
    d = jnp.clip(d, -1.0, 1.0)
    return d * h, jnp.where(ok, g1 - 0.25 * (g0 - g2) * d, g[i])


def criteria_from_gz(gz: Array, gm0: Length, flooding_angle: Angle | None = None, n_grid: int = 91,
                     max_heel: float = np.pi / 2, tau: float = 0.01) -> Criteria:
    """The criteria from GZ [m] at :func:`criteria_heels` (same arguments) and GM₀ [m].

    Parameters
    ----------
    gz : Array, (20 + n_grid,) float
        Righting lever GZ [m] at the heels of :func:`criteria_heels`, in that order.
    gm0 : float or Array, scalar
        Initial metacentric height GM₀ [m] (corrected for free surfaces).
    flooding_angle, n_grid, max_heel
        As given to :func:`criteria_heels` (θf and ``max_heel`` in rad).
    tau : float
        Softmax temperature [m] of the smooth margins for the max GZ and its angle (0.01 by default).

    Returns
    -------
    Criteria
        ``value``, ``required``, ``margin`` ``(6,)`` in the order of :data:`CRITERIA` (m·rad, m, degrees);
        ``gz_max`` [m], ``angle_gz_max`` and ``vanishing_angle`` [rad].
    """
    gz = jnp.asarray(gz)
    a, b = jnp.deg2rad(30.0), _upper(flooding_angle)
    w = jnp.asarray(_GL_W)
    g1, g2, grid = gz[:_GL_ORDER], gz[_GL_ORDER:2 * _GL_ORDER], gz[2 * _GL_ORDER:]
    area_30 = 0.5 * a * (w @ g1)
    area_30_40 = 0.5 * (b - a) * (w @ g2)
    heel = jnp.linspace(0.0, max_heel, n_grid)
    h = max_heel / (n_grid - 1)
    # max GZ at heels ≥ 30°
    beyond = heel >= a - ANGLE_TOL
    masked = jnp.where(beyond, grid, -jnp.inf)
    i30 = jnp.argmax(masked)
    _, gz30 = _parabola_peak(grid, i30, h, lowest=jnp.argmax(beyond) + 1)
    gz30_soft = jax.nn.softmax(masked / tau) @ jnp.where(beyond, grid, 0.0)  # ≤ the maximum: conservative
    # angle of the maximum GZ
    imax = jnp.argmax(grid)
    dphi, gz_max = _parabola_peak(grid, imax, h)
    angle = heel[imax] + dphi
    # soft argmax, capped by the exact angle: the soft one overestimates on a curve that falls slowly past its peak
    angle_soft = jnp.minimum(jax.nn.softmax(grid / tau) @ heel, angle)
    # first zero past the maximum (linear between the grid points around the sign change)
    k = jnp.arange(n_grid)
    neg = (grid < 0.0) & (k > imax)
    kz = jnp.argmax(neg)
    ga, gb = grid[jnp.maximum(kz - 1, 0)], grid[kz]
    ok = jnp.any(neg) & (ga > gb)
    frac = safe_div(ga, ga - gb, ok)
    vanishing = jnp.where(jnp.any(neg), heel[jnp.maximum(kz - 1, 0)] + frac * h, jnp.nan)
    gm0 = jnp.asarray(gm0)
    value = jnp.stack([area_30, area_30 + area_30_40, area_30_40, gz30, jnp.rad2deg(angle), gm0])
    smooth = jnp.stack([area_30, area_30 + area_30_40, area_30_40, gz30_soft, jnp.rad2deg(angle_soft), gm0])
    required = jnp.asarray([c[3] for c in CRITERIA], dtype=value.dtype)
    return Criteria(value, required, smooth - required, gz_max, angle, vanishing)


def intact_criteria(gz_fn: Callable[[Array], Array], gm0: Length, flooding_angle: Angle | None = None, n_grid: int = 91,
                    max_heel: float = np.pi / 2, tau: float = 0.01) -> Criteria:
    """The criteria for a GZ curve given as a function ``gz_fn(heels (k,) [rad]) -> (k,) [m]``.

    Parameters
    ----------
    gz_fn : callable
        ``gz_fn(heels)``: GZ [m] ``(k,)`` at heels ``(k,)`` [rad].
    gm0 : float or Array, scalar
        Initial metacentric height GM₀ [m].
    flooding_angle, n_grid, max_heel, tau
        As for :func:`criteria_from_gz` (θf and ``max_heel`` in rad, ``tau`` in m).

    Returns
    -------
    Criteria
        As :func:`criteria_from_gz`.
    """
    heels = criteria_heels(flooding_angle, n_grid, max_heel)
    return criteria_from_gz(gz_fn(heels), gm0, flooding_angle, n_grid, max_heel, tau)
