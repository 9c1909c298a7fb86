"""Inflections of the frame lines and waterlines of an offset table — what fairing must not add.

A line's curvature (the cubic spline through its offsets, :func:`hullopt.geometry.spline_curvatures`) is
taken at its knots; a cubic spline's ``y''`` is linear between knots, so its sign changes there are the
line's inflections. Only *interior hull knots* count: the knot and both neighbours have ``y > 0`` (where a
section begins from zero offsets, the spline turns sharply for no reason of shape). Curvatures within a
dead band ``± floor`` are taken as straight: a flat of side read to the table's last digit turns both ways
by a hair.

Two views of the same thing:

* :func:`inflection_counts` — the exact count per line, knots within twice the dead band skipped (numpy;
  what a report and a test judge by);
* :func:`sign_variation` — a smooth count for an optimiser: the total variation of a smoothed sign of ``κ``
  along the line, which is 0 inside the dead band and ±1 beyond twice it. Holding ``V ≤ V₀`` line by line
  keeps a one-signed line one-signed and lets a line that turns both ways turn less, not more; it sees an
  S-shape whose curvature is small as well as a large one (an energy such as ``Σ max(0, −κ)²`` does not,
  and lets one lobe become two).
"""

from __future__ import annotations

from functools import partial

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float

from .._types import Lengths, Mask, Scalar
from ..geometry import spline_curvatures

Table = Float[ArrayLike, "s w"]  # half-breadths [m] at stations × waterlines, or a value at each offset

FLOOR_FRACTION = 0.02  # the dead band, as a fraction of the largest |κ| of a line family on the given table
_EPS = 0.05  # smoothing of |Δσ| in sign_variation


@partial(jax.jit, static_argnames="end")  # one program, not operation by operation (a CLI call's seconds)
def line_curvatures(x: Lengths, z: Lengths, y: Table, end: str = "not-a-knot") -> tuple[Array, Array]:
    """Curvature at the knots of every frame line (``y(z)`` at a station) and every waterline (``y(x)``).

    Parameters
    ----------
    x : array_like, shape (s,)
        Stations [m from the AP].
    z : array_like, shape (w,)
        Waterlines [m above the baseline].
    y : array_like, shape (s, w)
        Half-breadths [m].
    end : str, optional
        Spline end condition (:func:`hullopt.geometry.spline_slopes`).

    Returns
    -------
    frames, waterlines : Array, shape (s, w) each
        ``κ`` [1/m] of the frame line through each offset (along z) and of the waterline (along x); positive
        where the line turns towards +y (hollow), negative where it bulges out.
    """
    y = jnp.asarray(y)
    return spline_curvatures(jnp.asarray(z), y.T, end).T, spline_curvatures(jnp.asarray(x), y, end)


def hull_knots(y: Table) -> tuple[np.ndarray, np.ndarray]:
    """Interior hull knots of the frame lines and of the waterlines: the offset and its two neighbours along
    the line are > 0 (a constant of a fairing problem: the given table's).

    Parameters
    ----------
    y : array_like, shape (s, w)
        Half-breadths [m].

    Returns
    -------
    frames, waterlines : numpy.ndarray of bool, shape (s, w) each
        The knots that count along the frame lines (z) and along the waterlines (x).
    """
    h = np.asarray(y) > 0.0
    frames, waterlines = np.zeros_like(h), np.zeros_like(h)
    frames[:, 1:-1] = h[:, :-2] & h[:, 1:-1] & h[:, 2:]
    waterlines[1:-1, :] = h[:-2, :] & h[1:-1, :] & h[2:, :]
    return frames, waterlines


def knot_weights(knots: Lengths) -> np.ndarray:
    """Each knot's share of its line's length: half of each adjacent interval.

    Parameters
    ----------
    knots : array_like, shape (k,)
        Knot positions along a line [m], increasing.

    Returns
    -------
    numpy.ndarray, shape (k,)
        The shares [m]; they sum to the line's length.
    """
    h = np.diff(np.asarray(knots, np.float64))
    return np.concatenate([h[:1], h[:-1] + h[1:], h[-1:]]) / 2.0


def floors(frames: Table, waterlines: Table, frame_knots: Mask, waterline_knots: Mask) -> tuple[float, float]:
    """The dead bands of the frame lines and of the waterlines: :data:`FLOOR_FRACTION` of each family's
    largest ``|κ|`` at its interior hull knots (the two families' curvatures differ by orders of magnitude).

    Parameters
    ----------
    frames, waterlines : array_like, shape (s, w) each
        Curvatures at the knots [1/m] (:func:`line_curvatures`).
    frame_knots, waterline_knots : array_like of bool, shape (s, w) each
        The knots that count (:func:`hull_knots`).

    Returns
    -------
    tuple of (float, float)
        The frame lines' and the waterlines' dead bands [1/m] (0 for a family without a counted knot).
    """
    def one(k, m):
        a = np.abs(np.asarray(k))[np.asarray(m)]
        return FLOOR_FRACTION * float(a.max()) if a.size else 0.0

    return one(frames, frame_knots), one(waterlines, waterline_knots)


def inflection_counts(kappa: Table, knots: Mask, floor: float, axis: int) -> np.ndarray:
    """Inflections of each line: sign changes of ``κ`` along ``axis`` over the knots marked in ``knots``,
    curvatures within ``± floor`` skipped (numpy, exact).

    Parameters
    ----------
    kappa : array_like, shape (s, w)
        Curvatures at the knots [1/m] (:func:`line_curvatures`).
    knots : array_like of bool, shape (s, w)
        The knots that count (:func:`hull_knots`).
    floor : float
        Dead band [1/m].
    axis : int
        1 for frame lines (one per station), 0 for waterlines (one per waterline).

    Returns
    -------
    numpy.ndarray of int, shape (s,) or (w,)
        Inflections per line.
    """
    k, m = np.moveaxis(np.asarray(kappa), axis, -1), np.moveaxis(np.asarray(knots, bool), axis, -1)
    signs = np.where(m & (np.abs(k) > floor), np.sign(k), 0.0)  # 0: skipped (off the hull or in the band)
    # the last counted knot at or before each knot, so a sign is compared with the previous counted one
    last = np.maximum.accumulate(np.where(signs != 0, np.arange(signs.shape[-1]), -1), axis=-1)
    before = np.take_along_axis(signs, np.maximum(last[..., :-1], 0), axis=-1) * (last[..., :-1] >= 0)
    return np.count_nonzero(signs[..., 1:] * before < 0, axis=-1)


def mixed_curvature(kappa: Float[Array, "s w"], knots: Mask, weights: Table, floor: Scalar,
                    axis: int) -> Float[Array, " n"]:
    """How much each line turns against its main sense: ``M = P·N/(P + N)`` with ``P = Σ w·max(0, κ −
    floor)²`` and ``N = Σ w·max(0, −κ − floor)²`` over the interior hull knots [1/m]; zero for a line whose
    curvature beyond the dead band has one sign, about the smaller of P and N otherwise. It measures the size
    of an S-shape where :func:`sign_variation` counts it. Differentiable (C¹ where P + N > 0).

    Parameters
    ----------
    kappa : Array, shape (s, w)
        Curvatures at the knots [1/m].
    knots : array_like of bool, shape (s, w)
        The knots that count (:func:`hull_knots`).
    weights : array_like, shape (s, w)
        Each knot's share of its line's length [m] (:func:`knot_weights`).
    floor : float
        Dead band [1/m].
    axis : int
        1 for frame lines, 0 for waterlines.

    Returns
    -------
    Array, shape (s,) or (w,)
        ``M`` per line [1/m].
    """
    w = jnp.where(jnp.asarray(knots, bool), jnp.asarray(weights), 0.0)
    p = jnp.sum(w * jnp.maximum(kappa - floor, 0.0) ** 2, axis=axis)
    n = jnp.sum(w * jnp.maximum(-kappa - floor, 0.0) ** 2, axis=axis)
    both = p + n > 0.0
    return jnp.where(both, p * n / jnp.where(both, p + n, 1.0), 0.0)  # double where: no NaN gradient at 0/0


def sign_variation(kappa: Float[Array, "s w"], knots: Mask, floor: Scalar, axis: int) -> Float[Array, " n"]:
    """Smooth inflection count of each line (module docstring): ``V = ½ Σ |σ_{j+1} − σ_j|`` over consecutive
    interior hull knots, ``σ = sign(κ)·S((|κ| − floor)/floor)`` with ``S`` the C¹ smoothstep (0 inside the dead
    band, ±1 beyond twice it) and ``|·|`` smoothed by ``√(d² + ε²) − ε`` (ε = 0.05). A crossing from beyond
    ``2·floor`` on one side to beyond it on the other adds 1, directly or through knots in the band; a step
    into the band and back adds 1 too (so ``V`` bounds the count from above); a line whose curvature keeps
    one sign beyond the band has ``V = 0``. Differentiable in ``kappa``.

    Parameters
    ----------
    kappa : Array, shape (s, w)
        Curvatures at the knots [1/m].
    knots : array_like of bool, shape (s, w)
        The knots that count (:func:`hull_knots`).
    floor : float
        Dead band [1/m].
    axis : int
        1 for frame lines (one per station), 0 for waterlines (one per waterline).

    Returns
    -------
    Array, shape (s,) or (w,)
        ``V`` per line (dimensionless).
    """
    t = jnp.clip((jnp.abs(kappa) - floor) / floor, 0.0, 1.0)
    sigma = jnp.sign(kappa) * t * t * (3.0 - 2.0 * t)
    m = jnp.asarray(knots, bool)
    sigma, m = jnp.moveaxis(jnp.where(m, sigma, 0.0), axis, -1), jnp.moveaxis(m, axis, -1)
    d = jnp.diff(sigma, axis=-1)
    pair = m[..., 1:] & m[..., :-1]
    return 0.5 * jnp.sum(jnp.where(pair, jnp.sqrt(d * d + _EPS**2) - _EPS, 0.0), axis=-1)


def count_inflections(x: Lengths, z: Lengths, y: Table, given: Table | None = None,
                      end: str = "not-a-knot") -> tuple[np.ndarray, np.ndarray]:
    """Inflections per frame line and per waterline of an offset table (numpy), judged on the hull knots and
    dead bands of the table ``given``, the dead bands doubled: a line counts as turned only where it turns
    clearly more than a fairing constraint on :func:`sign_variation` (held with the single dead band) allows.

    Parameters
    ----------
    x : array_like, shape (s,)
        Stations [m from the AP].
    z : array_like, shape (w,)
        Waterlines [m above the baseline].
    y : array_like, shape (s, w)
        Half-breadths [m] of the table judged.
    given : array_like, shape (s, w), optional
        The table whose knots and dead bands judge it (a faired table is judged by its given one); default ``y``.
    end : str, optional
        Spline end condition (:func:`hullopt.geometry.spline_slopes`).

    Returns
    -------
    frames, waterlines : numpy.ndarray of int, shapes (s,) and (w,)
        Inflections of each frame line and of each waterline.
    """
    given = y if given is None else given
    knots = hull_knots(given)
    f = floors(*line_curvatures(x, z, given, end), *knots)
    return tuple(inflection_counts(k, m, 2.0 * fl, axis)
                 for k, m, fl, axis in zip(line_curvatures(x, z, y, end), knots, f, (1, 0)))
