"""The waterline at a draft and the bluntness coefficient Bf(α) (JP2009-286166 eq. 3; DESIGN.md §4).

The waterline is the curve the hull cuts from the plane z = T. Between stations the hull is the ruled surface
joining neighbouring half-sections, so the waterline is exactly the polyline through the station
half-breadths ``(x_i, y_i)`` — closed at both ends along x = x_0 and x = x_{n−1} down to the centreline when
the end stations are wet (a transom or a blunt bow face). Stations forward of the stem (dry at T) add segments
of zero length, which contribute nothing. Resolution at the stem is the hull model's: meshes are sliced with
stations clustered at the ends.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float

from .._types import Angles, Draft, Scalar
from ..geometry import Sections, safe_div, section_integrals

AFT_OPTIONS = ("exclude", "include")  # the first is the default (see bluntness_of_waterline)


class Waterline(eqx.Module):
    """The port waterline at one draft as a closed polyline of ``n + 1`` segments.

    Attributes
    ----------
    x, y : (n,) float
        Station positions [m] and waterline half-breadths [m] (0 where a station is dry).
    dx, dy : (n + 1,) float
        Segment increments [m], going forward: first the aft closing segment (0, y_0), then the station-to-
        station segments, then the forward closing segment (0, −y_{n−1}).
    """

    x: Float[ArrayLike, " n"]
    y: Float[ArrayLike, " n"]
    dx: Float[ArrayLike, " n+1"]
    dy: Float[ArrayLike, " n+1"]

    @property
    def beam(self) -> Float[Array, ""]:
        """Waterline breadth B_wl = 2·max y [m]."""
        return 2.0 * jnp.max(self.y)

    @property
    def slope(self) -> Float[Array, " segments"]:  # n − 1 (a method's check cannot see the fields' n)
        """dy/dx of each station-to-station segment (0 where stations coincide)."""
        dxs = self.dx[1:-1]
        ok = dxs > 0.0
        return safe_div(self.dy[1:-1], dxs, ok)

    @property
    def angle(self) -> Float[Array, " edges"]:  # n + 1
        """β_w [rad] of each segment: the waterline angle to the x axis, positive where the half-breadth
        shrinks going forward (the entrance), negative in the run; ±π/2 for the closing segments."""
        return jnp.arctan2(-self.dy, self.dx)


def waterline(sections: Sections, draft: Draft) -> Waterline:
    """The waterline at ``draft`` [m above the baseline], exact for the sections' ruled surface.

    Parameters
    ----------
    sections : Sections
        The hull's n stations (offsets in metres).
    draft : float or Array
        Waterline height T [m] above the baseline (scalar).

    Returns
    -------
    Waterline
        ``x``, ``y`` (n,) [m] and segment increments ``dx``, ``dy`` (n + 1,) [m].
    """
    t = jnp.asarray(draft, dtype=sections.yz.dtype)
    y = section_integrals(sections, t).width
    zero = jnp.zeros((1,), dtype=y.dtype)
    dx = jnp.concatenate([zero, jnp.diff(sections.x), zero])
    dy = jnp.concatenate([y[:1], jnp.diff(y), -y[-1:]])
    return Waterline(x=sections.x, y=y, dx=dx, dy=dy)


def _side_integral(wl: Waterline, kx, ky, aft: str):
    """∫ max(0, −k̂·n)² n_x dl over the port waterline for an incident direction k̂ = (kx, ky).

    Per segment, with n = (−dy, dx)/dl the outward normal, the integrand is constant, so the integral is
    (k̂·n)² n_x dl = (ky·dx − kx·dy)²·(−dy)/dl² — exact for the polyline. Lit segments face the waves
    (k̂·n < 0). ``aft="exclude"`` drops lit segments facing aft (n_x < 0).
    """
    dx, dy = wl.dx[..., None], wl.dy[..., None]  # broadcast against headings in the last axis
    l2 = dx * dx + dy * dy
    proj = ky * dx - kx * dy  # = dl · (k̂·n)
    lit = (l2 > 0.0) & (proj < 0.0)
    if aft == "exclude":
        lit = lit & (dy < 0.0)
    return jnp.sum(safe_div(proj * proj * (-dy), l2, lit), axis=0)


def bluntness_of_waterline(wl: Waterline, heading: Angles = 0.0, aft: str = "exclude") -> Array:
    """Bf(α) of a waterline, for headings ``α`` [rad] (any shape; 0 = head seas, π = following seas).

    Bf = (1/B)[∫_I sin²(α+β_w) sin β_w dl + ∫_II sin²(α−β_w) sin β_w dl] (patent eq. 3), I and II the lit
    parts of the weather and lee sides: elements whose outward normal n faces the incident wave direction
    k̂ = (−cos α, −sin α) (waves from the port bow for α > 0). On the weather side −k̂·n = sin(α+β_w), on the
    lee side sin(β_w−α), and n_x = sin β_w, so the integrand is (k̂·n)² n_x — the mean reflected-wave
    force of a locally straight, fully reflecting wall. Illumination is judged locally, which is exact for
    convex waterlines (concave ones would need shadowing by other parts of the hull).

    ``aft`` — which lit elements count. ``"exclude"`` (default) integrates over the lit elements that face
    forward (n_x > 0, the entrance) only. Source: the patent quotes eq. 3 from Fujii & Takahashi (1975) and
    defines I and II only by its Fig. 1 (not in the text hullopt has); Fujii & Takahashi's model, and
    Kuroda, Tsujimoto et al.'s extension of it to oblique seas (the patent's eqs. 11–12, "for Bf > 0"),
    is the reflection of the incident waves by the bow — the patent calls Bf the bluntness of the bow and
    changes only the bow to change it. The rule hullopt applies is therefore: an element counts when the
    incident waves illuminate it (−k̂·n > 0, judged locally) and it belongs to the entrance
    (sin β_w > 0). Then Bf ≥ 0 at every heading; it is 0 from where the waves no longer reach the entrance
    (α ≥ π − E for a wedge of half-angle E; α ≥ π/2 for a flat bow face) to following seas, and equals the
    head-sea value at α = 0. ``"include"`` also counts the lit run and transom with their negative
    contribution (β_w < 0: a thrust), as Faltinsen's asymptotic formula and SNNM's run terms do; in
    following and quartering seas it makes Bf negative (a square-ended box: Bf = −cos²α beyond 90°),
    outside the range of eq. 11 — kept for comparison; :func:`~hullopt.waves.nmri_added_resistance`
    counts no negative reflection part whichever is chosen. The two agree in head seas (|α| below the
    smallest entrance angle), where no aft-facing element is lit. In head seas
    Bf = (2/B) ∫_entrance sin³β_w dl; a wedge of half-angle E gives sin²E, a semicircle 2/3, and in
    oblique seas a wedge bow (half-breadth b = B/2) gives Bf = ½[sin²(α+E)·[α+E < π] + sin²(α−E)·[α < E]].

    Parameters
    ----------
    wl : Waterline
        The waterline (:func:`waterline`).
    heading : float or Array
        Wave headings α [rad], any shape H; 0 = head seas.
    aft : {"exclude", "include"}
        Which lit elements count (see above).

    Returns
    -------
    Array
        Bf (dimensionless), shape H; 0 where the waterline has no breadth.

    Raises
    ------
    ValueError
        If ``aft`` is not one of ``AFT_OPTIONS``.
    """
    if aft not in AFT_OPTIONS:
        raise ValueError(f"aft={aft!r}: expected one of {AFT_OPTIONS}")
    a = jnp.asarray(heading, dtype=wl.y.dtype)
    shape = a.shape
    a = a.reshape(-1)
    kx, ky = -jnp.cos(a), -jnp.sin(a)
    total = _side_integral(wl, kx, ky, aft) + _side_integral(wl, kx, -ky, aft)  # starboard = mirror of k̂
    b = wl.beam
    pos = b > 0.0
    return safe_div(total, b, pos).reshape(shape)


BAND_NODES, BAND_WEIGHTS = (np.polynomial.legendre.leggauss(5)[0], np.polynomial.legendre.leggauss(5)[1] / 2.0)
"""The waterlines of a band [T − a, T + a] (:func:`bluntness`): 5-point Gauss–Legendre nodes on [−1, 1] and weights summing to 1
(exact for a Bf that is a polynomial of degree 9 in the height)."""


def band_waterlines(sections: Sections, draft: Draft, band: float) -> Waterline:
    """The waterlines at the heights ``draft + band·BAND_NODES`` [m]: each field with a leading axis of 5."""
    return jax.vmap(lambda t: waterline(sections, t))(jnp.asarray(draft, dtype=sections.yz.dtype) + band * BAND_NODES)


def bluntness(sections: Sections, draft: Draft, heading: Angles = 0.0, aft: str = "exclude",
              band: float = 0.0) -> Array:
    """Bluntness coefficient Bf of the waterline at ``draft`` [m] for headings ``heading`` [rad];
    see :func:`bluntness_of_waterline`. With ``band`` a > 0 [m], the mean of Bf over the waterlines in
    [T − a, T + a] (5-point Gauss–Legendre in the height): the bow the waves meet over the range of water
    surface they sweep (JP2009-286166 shapes the bow "over the waterlines met in service"; its tables and
    formula use the waterline at the draft, the default ``band = 0``).

    Parameters
    ----------
    sections : Sections
        The hull's stations (offsets in metres).
    draft : float or Array
        Waterline height T [m] above the baseline (scalar).
    heading : float or Array
        Wave headings α [rad], any shape H; 0 = head seas.
    aft : {"exclude", "include"}
        Which lit elements count, see :func:`bluntness_of_waterline`.
    band : float
        Half-height a [m] of the band of waterlines averaged over (static); 0: the waterline at ``draft``.

    Returns
    -------
    Array
        Bf (dimensionless), shape H.
    """
    if not band:
        return bluntness_of_waterline(waterline(sections, draft), heading, aft)
    bf = jax.vmap(lambda wl: bluntness_of_waterline(wl, heading, aft))(band_waterlines(sections, draft, band))
    return jnp.tensordot(jnp.asarray(BAND_WEIGHTS), bf, axes=1)


def entrance_lengths(wl: Waterline, fraction: Scalar) -> tuple[Array, Array]:
    """Lengths [m] from the forward and the aft end of the waterline to where its half-breadth first
    reaches ``fraction`` of its maximum (STAWAVE-1's L_BWL at 0.95; SNNM's L_E, L_R at 0.99).

    Parameters
    ----------
    wl : Waterline
        The waterline (:func:`waterline`).
    fraction : float or Array
        Fraction of the maximum half-breadth (dimensionless, 0 … 1; scalar).

    Returns
    -------
    forward : Array
        Length [m] from the forward end of the waterline to the crossing (the entrance), scalar.
    aft : Array
        Length [m] from the aft end of the waterline to the crossing (the run), scalar.
    """
    y, x = wl.y, wl.x
    level = fraction * jnp.max(y)
    n = x.shape[0]
    wet = y > 0.0
    # Ends of the waterline: one station beyond the last/first wet one (the ruled surface runs to it),
    # or the end station itself when it is wet (a transom or blunt bow).
    last = n - 1 - jnp.argmax(wet[::-1])
    first = jnp.argmax(wet)
    x_fwd = x[jnp.minimum(last + 1, n - 1)]
    x_aft = x[jnp.maximum(first - 1, 0)]
    above = y >= level
    i_f = n - 1 - jnp.argmax(above[::-1])  # last station at or above the level
    i_a = jnp.argmax(above)  # first one
    # Linear interpolation of the crossing on the neighbouring segment (exact for the polyline).
    j = jnp.minimum(i_f + 1, n - 1)
    den = y[i_f] - y[j]
    ok = (j > i_f) & (den > 0.0)
    xf = x[i_f] + safe_div(y[i_f] - level, den, ok) * (x[j] - x[i_f])
    j = jnp.maximum(i_a - 1, 0)
    den = y[i_a] - y[j]
    ok = (j < i_a) & (den > 0.0)
    xa = x[i_a] - safe_div(y[i_a] - level, den, ok) * (x[i_a] - x[j])
    return x_fwd - xf, xa - x_aft
