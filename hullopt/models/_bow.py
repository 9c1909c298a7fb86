"""The bow attachment of JP2009-286166 claims 4–5: volume added at (or, with a negative amplitude, taken from)
the fore body over a height band, so that the bow at and around the waterline becomes blunter (or finer).

A :class:`BowAttachment` is a half-breadth ``a·W(x)·V(z)`` [m] added to every offset of the sections:

* the **plan form** ``W(x)`` (static, from the parent's stations): 0 aft of ``x_blend``, rising as
  ``sin²(πξ/2)`` to 1 at ``x_peak`` (zero slope at the blend: no knuckle there), then closing as a quarter
  ellipse ``√(1 − η²)`` to 0 at the stem ``x_stem`` (a round nose; the stem itself, where the waterline has no
  breadth, stays where it is, so the stem profile is the parent's);
* the **height band** ``V(z)`` (evaluated on each offset's height, so it follows the deformed frame): 0 below
  ``z_lo − blend``, rising by the quintic smootherstep to 1 at ``z_lo``, 1 up to ``z_hi`` and falling the same
  way to 0 at ``z_hi + blend`` (``z_hi`` ∞: up to the deck — the patent's Fig. 15, from the bulb's top to the
  upper deck; ``z_lo`` at the waterline: its Fig. 16, "above the waterline vicinity only"). V is C², so the
  sections stay as smooth as the parent's where the band starts and ends.

The map is pure, linear in the amplitude and keeps every station's topology, so the hull stays watertight and a
sweep's designs have one shape of arrays. The amplitude is the half-breadth added at ``x_peak`` inside the band;
with ``mode = "scale"`` it is the fraction every half-breadth there grows by (negative: a finer bow, the way of
the patent's background documents 1–3 for full ships).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, ArrayLike, Float

from ..errors import HullError
from ..geometry import Sections, section_integrals


@dataclass(frozen=True)
class BowAttachment:
    """Where a bow attachment sits: plan form from ``x_blend`` (W = 0) through ``x_peak`` (W = 1) to the stem
    ``x_stem`` (W = 0) [m from the AP; ``None``: found from the parent, see :func:`attachment_plan`], height
    band ``z_lo`` … ``z_hi`` [m above the baseline; ``z_hi = inf``: to the deck] with smooth ramps of height
    ``blend`` [m] outside it. ``mode`` ``"add"``: the amplitude is a half-breadth [m] added (a bulge, the nose
    closing to the stem); ``"scale"``: a fraction, every half-breadth times 1 + a·W·V, W staying 1 from
    ``x_peak`` to the bow (a stem stays a stem: the way to a finer bow on a full ship)."""

    x_blend: float
    z_lo: float
    z_hi: float = math.inf
    blend: float = 1.0
    x_peak: float | None = None
    x_stem: float | None = None
    mode: str = "add"


def _smootherstep(r):
    return r * r * r * (r * (6.0 * r - 15.0) + 10.0)


def stem_station(sections: Sections, draft: float) -> int:
    """Index of the stem at the waterline: the first station forward of midship with no breadth at ``draft``.

    Parameters
    ----------
    sections : Sections
        The hull (x forward from the AP, m).
    draft : float
        The waterline's height [m above the baseline].

    Returns
    -------
    int
        The station's index; the last station's where the bow is a wet face (a box).
    """
    x = np.asarray(sections.x)
    y = np.asarray(section_integrals(sections, draft).width)
    fwd = np.flatnonzero((x > 0.5 * float(sections.lpp)) & (y <= 1e-9 * float(sections.lpp)))
    return int(fwd[0]) if fwd.size else len(x) - 1


def attachment_plan(x: np.ndarray, att: BowAttachment, stem: int) -> np.ndarray:
    """The plan form W(x) of an attachment at the stations (numpy, static).

    Parameters
    ----------
    x : (n,) array_like
        Station positions [m from the AP], increasing.
    att : BowAttachment
        The attachment; ``x_stem`` None: the stem at station ``stem``; ``x_peak`` None: the station aft of it.
    stem : int
        Index of the stem at the waterline (:func:`stem_station`).

    Returns
    -------
    numpy.ndarray
        (n,) W, dimensionless: 0 aft of ``x_blend``, sin² rising to 1 at ``x_peak``, a quarter ellipse to 0 at
        the stem, 0 forward of it.

    Raises
    ------
    HullError
        Unless ``x_blend < x_peak < x_stem`` within the stations.
    """
    if att.mode not in ("add", "scale"):
        raise HullError(f"bow attachment: mode {att.mode!r} must be 'add' or 'scale'")
    x = np.asarray(x, float)
    x_stem = float(x[stem]) if att.x_stem is None else float(att.x_stem)
    x_peak = float(x[max(np.searchsorted(x, x_stem) - 1, 0)]) if att.x_peak is None else float(att.x_peak)
    if not (x[0] <= att.x_blend < x_peak < x_stem <= x[-1] + 1e-9):
        raise HullError(f"bow attachment: need x_blend < x_peak < x_stem within the stations ({x[0]:g} … {x[-1]:g} m), "
                        f"got {att.x_blend:g}, {x_peak:g}, {x_stem:g} m")
    xi = np.clip((x - att.x_blend) / (x_peak - att.x_blend), 0.0, 1.0)
    eta = np.clip((x - x_peak) / (x_stem - x_peak), 0.0, 1.0)
    nose = 1.0 if att.mode == "scale" else np.sqrt(1.0 - eta**2)
    return np.where(x <= x_peak, np.sin(0.5 * np.pi * xi) ** 2, nose)


def band_weight(z: ArrayLike, z_lo: ArrayLike, z_hi: ArrayLike, blend: ArrayLike) -> Array:
    """The height band V(z) of an attachment: 1 on [z_lo, z_hi], C² (smootherstep) ramps to 0 outside.

    Parameters
    ----------
    z : array_like
        Heights [m above the baseline], any shape.
    z_lo, z_hi : float or array_like
        The band's ends [m]; ``z_hi`` may be ∞ (to the deck).
    blend : float or array_like
        Height of each ramp [m], > 0.

    Returns
    -------
    Array
        V, dimensionless, shaped as ``z``; pure JAX (jit/grad/vmap).
    """
    lo = _smootherstep(jnp.clip((z - z_lo + blend) / blend, 0.0, 1.0))
    over = jnp.clip((z - z_hi) / blend, 0.0, 1.0)  # z_hi = ∞: 0
    return lo * (1.0 - _smootherstep(over))


def attach_bow(sections: Sections, amplitude: Float[ArrayLike, " W"], plan: Float[ArrayLike, "W n"],
               band: Float[ArrayLike, "W 3"], scale: tuple[bool, ...] | None = None) -> Sections:
    """The hull with ``W`` attachments: y ↦ y + Σ_w a_w·W_w(x)·V_w(z)·(y where ``scale[w]``, else 1).

    Parameters
    ----------
    sections : Sections
        The hull (x forward from the AP, y ≥ 0 to port, z up from the baseline; m).
    amplitude : (W,) array
        Half-breadth added at each attachment's peak [m]; negative takes volume away.
    plan : (W, n) array
        Plan forms W(x) at the stations (:func:`attachment_plan`), dimensionless.
    band : (W, 3) array
        ``(z_lo, z_hi, blend)`` of each attachment [m] (:func:`band_weight`).
    scale : tuple of bool or None
        Per attachment whether it scales the half-breadths (its amplitude a fraction) instead of adding to
        them (a half-breadth [m]); None: all add.

    Returns
    -------
    Sections
        Same stations and array shapes; a zero amplitude gives ``sections`` back exactly.
    """
    yz = jnp.asarray(sections.yz)
    z = yz[..., 1]
    v = band_weight(z[None], band[:, 0, None, None], band[:, 1, None, None], band[:, 2, None, None])  # (W, n, m)
    by = jnp.where(jnp.asarray(scale or (False,) * v.shape[0])[:, None, None], yz[None, ..., 0], 1.0)
    dy = jnp.einsum("w,wn,wnm->nm", jnp.asarray(amplitude), jnp.asarray(plan), v * by)
    return Sections(x=sections.x, yz=yz.at[..., 0].add(dy), lpp=sections.lpp)
