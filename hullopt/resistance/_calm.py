"""Calm-water resistance with one convention for every wave-resistance method.

    R_T = (1 + k1)·R_F + R_APP + R_W(method) + R_A

R_F is ITTC-1957 friction on the hull's wetted surface, 1 + k1 Holtrop & Mennen's (1982) form factor, R_APP
their appendage resistance (0 for a bare hull) and R_A their correlation allowance (C_A·½ρU²S, its own term);
R_W is the wave resistance by the chosen method:

* ``"holtrop"`` — Holtrop & Mennen's regression R_W + R_B + R_TR (wave, bulb, transom): sees Cp, LCB, the
  entrance angle and the bulb and transom areas, not the shape of each section; valid for ordinary merchant
  hulls inside its data (Cp 0.55–0.85, Fn < 0.45).
* ``"michell"`` — Michell's thin-ship integral from the sections (:mod:`._michell`): sees every section; valid
  for slender hulls (B/L ≲ 0.15, fine ends); overpredicts full and bulbous hulls several-fold.
* ``"panel"`` — the Rankine-source panel method (:mod:`._panel`): the true hull surface, its thickness, flat bottom
  and bulb; like Michell it radiates through Kelvin's uniform-stream waves, so it overpredicts the stern waves of
  full hulls (no viscous wake, no double-body free-surface condition) — see ``benchmarks/README.md``.
* ``"dawson"`` — Dawson's method (:mod:`._dawson`): the same hull panels plus free-surface panels, the free
  surface linearised about the double-body flow, so the waves of the slowed flow at a full hull's bow and run are
  not overstated; the method for full and bulbous hulls (≈ 2× the panel method's time a speed). An immersed
  transom runs dry: its lost hydrostatic thrust is in R_W, as Holtrop & Mennen's R_TR is in theirs.

With ``"holtrop"`` the total is Holtrop & Mennen's own; the totals differ in R_W only.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._types import Draft, Speeds
from ..errors import HullError
from ..geometry import Sections
from ._holtrop import HoltropHull, holtrop_hull, holtrop_mennen
from ._dawson import FN_MIN as DAWSON_FN_MIN
from ._dawson import dawson_wave_resistance
from ._michell import LAMBDA_PANELS, michell_wave_resistance
from ._panel import GIRTH, STATIONS, panel_wave_resistance

METHODS = ("holtrop", "michell", "panel", "dawson")
"""The wave-resistance methods of :func:`calm_water`."""

DISAGREE = 1.5
"""Two methods whose wave (or total) resistances differ by more than this factor get a warning."""


class CalmWater(eqx.Module):
    """Calm-water resistance at k speeds [N] by one convention (see the module).

    Attributes
    ----------
    fn : (k,) Froude number on the waterline length (Holtrop's L).
    r_f : (k,) ITTC-1957 friction R_F [N].
    form_factor : () Holtrop's 1 + k1.
    r_app : (k,) appendage resistance [N].
    r_wave : (k,) wave resistance R_W by ``method`` [N].
    r_a : (k,) correlation allowance R_A [N].
    total : (k,) R_T = (1 + k1)·R_F + R_APP + R_W + R_A [N].
    method : str, the wave-resistance method.
    sinkage, trim : (k,) the panel methods' sinkage [m, down] and trim [rad, bow up] (``"panel"``: the double
        body's; ``"dawson"``: with its waves); None otherwise.
    """

    fn: Float[Array, "*k"]
    r_f: Float[Array, "*k"]
    form_factor: Float[Array, ""]
    r_app: Float[Array, "*k"]
    r_wave: Float[Array, "*k"]
    r_a: Float[Array, "*k"]
    total: Float[Array, "*k"]
    method: str = eqx.field(static=True)
    sinkage: Float[Array, "*k"] | None = None
    trim: Float[Array, "*k"] | None = None


def check_method(method: str, what: str = "method") -> str:
    """``method`` if it is one of :data:`METHODS`, else a :class:`HullError` naming them.

    Parameters
    ----------
    method : str
        A wave-resistance method's name.
    what : str
        How the error names it (an option, a config field).

    Returns
    -------
    str
        ``method``.
    """
    if method not in METHODS:
        raise HullError(f"{what} {method!r}: expected one of {', '.join(METHODS)}")
    return method


def calm_water(sections: Sections, draft: Draft, speed: Speeds, method: str = "holtrop", *, n_levels: int = 33,
               lambda_panels: int = LAMBDA_PANELS, stations: int = STATIONS, girth: int = GIRTH,
               attitude: int = 0) -> CalmWater:
    """Calm-water resistance R_T [N] and its parts at ``speed`` U [m/s] (any shape), R_W by ``method``.

    Parameters
    ----------
    sections : Sections
        The hull (x [m from the AP], y half-breadths to port, z up from the baseline).
    draft : float or Array
        Draft T [m above the baseline].
    speed : float or array_like
        Ship speed [m/s] > 0, any shape.
    method : {"holtrop", "michell", "panel", "dawson"}
        The wave-resistance method.
    n_levels, lambda_panels, stations, girth : int
        Michell's heights, the λ rule's panels (Michell and panel), the panel method's panelling. The λ rule's
        default 64 panels hold the Wigley within 1.3e-5 (Michell, against 1024 panels) and 1.9e-4 (panel, against
        512) at Fn 0.12, 8e-9 and 2.4e-5 at Fn 0.15, 6e-12 and 7e-7 at Fn 0.2 (tests/test_michell.py,
        tests/test_panel.py); below Fn 0.12 take 128 or more (Michell at Fn 0.1: 8e-4 with 64, 9e-8 with 128).
        ``hullopt resistance`` takes 256.
    attitude : int
        Dawson's sinkage-and-trim iterations (:func:`.dawson_wave_resistance`): 0, the hull fixed at its static
        draft; 2, free to sink and trim (three solves a speed). Other methods ignore it.

    Returns
    -------
    CalmWater
        The parts and the total, each of ``speed``'s shape.
    """
    check_method(method)
    u = jnp.asarray(speed, dtype=jnp.asarray(sections.yz).dtype)
    hm = holtrop_mennen(holtrop_hull(sections, draft), u)
    panel = None
    if method == "holtrop":
        rw = hm.wave + hm.bulb + hm.transom
    elif method == "michell":
        rw = michell_wave_resistance(sections, draft, u, n_levels=n_levels, panels=lambda_panels)
    elif method == "dawson":
        panel = dawson_wave_resistance(sections, draft, u, stations=stations, girth=girth, attitude=attitude)
        rw = panel.r_wave
    else:
        panel = panel_wave_resistance(sections, draft, u, stations=stations, girth=girth,
                                      lambda_panels=lambda_panels)
        rw = panel.r_wave
    shape = jnp.shape(u)
    r_app = jnp.broadcast_to(hm.appendages, shape)
    total = hm.form_factor * hm.friction + r_app + rw + hm.correlation
    return CalmWater(fn=hm.fn, r_f=hm.friction, form_factor=hm.form_factor, r_app=r_app, r_wave=rw,
                     r_a=jnp.broadcast_to(hm.correlation, shape), total=total, method=method,
                     sinkage=None if panel is None else panel.sinkage, trim=None if panel is None else panel.trim)


def transom_caveat(hull: HoltropHull) -> str | None:
    """What Dawson's method assumes of ``hull``'s immersed transom (A_T > 0), else None (numpy; for warnings).

    It takes the transom dry — the flow leaving its lower edge clean (from F_nT = U/√(g d_T) = 5; below, the
    water behind it raised by WARP's dead-water rule) — and starts the wake's waves from there, but does not
    pin the hollow behind it: the water rises at once. Measured on the DTMB 5415: C_W 0.6× the peer WARP's at
    Fn 0.28, 0.85× at 0.41; model C_T −9 % and −26 % of the tank (WARP's −21 % at 0.41; benchmarks/README.md).

    Parameters
    ----------
    hull : HoltropHull
        The hull's particulars (concrete values); ``A_T`` the immersed transom area [m²].

    Returns
    -------
    str or None
        The caveat's text, or None without an immersed transom.
    """
    if float(hull.A_T) <= 0.0:
        return None
    return (f"immersed transom (A_T {float(hull.A_T):.3g} m²): dawson takes it dry (the flow leaving its edge clean; "
            "partly wet below F_nT 5) without the hollow behind it — DTMB 5415: C_W 0.6× WARP's at Fn 0.28, "
            "C_T −9 % of the tank; compare variants by it rather than totals")


def outside_validity(hull: HoltropHull, fn: float, fn_min: float | None = None) -> dict[str, str]:
    """Each method of :data:`METHODS` that is outside its validity on ``hull`` at Froude number ``fn``, with
    why (numpy; for warnings): Michell and the panel method on a full or bulbous hull (Cb > 0.55 or a bulb,
    ``hull.bulb`` where :func:`~hullopt.resistance.holtrop_hull` measured it, else an area at the FP:
    uniform-stream Kelvin waves overpredict its waves several-fold — KCS 5–10×; Dawson's method is the one for
    it), Holtrop–Mennen outside its data (Cp 0.55–0.85, Fn ≤ 0.45), Dawson's method below
    :data:`._dawson.FN_MIN` when ``fn_min`` is given.

    Parameters
    ----------
    hull : HoltropHull
        The hull's particulars (concrete values).
    fn : float
        The highest Froude number asked for.
    fn_min : float, optional
        The lowest (Dawson's method below :data:`._dawson.FN_MIN`: its default grid too coarse for the waves).

    Returns
    -------
    dict[str, str]
        Method → why it is outside its validity (methods inside it are absent).
    """
    cb = float(hull.volume) / (float(hull.L) * float(hull.B) * float(hull.T))
    cp = cb / float(hull.cm)
    # a bulb seen on the sections (holtrop_hull's); a hull given by its particulars alone: any area at the FP
    bulb = float(hull.bulb) > 0.0 if hull.bulb is not None else float(hull.A_BT) > 0.0
    out = {}
    if cb > 0.55 or bulb:
        why = (f"Cb {cb:.2f}{' with a bulb' if bulb else ''}: linear Kelvin waves overpredict a full hull's; "
               "dawson sees its slowed flow")
        out.update(michell=why, panel=why)
    if not 0.55 <= cp <= 0.85 or fn > 0.45:
        out["holtrop"] = f"Cp {cp:.2f}, Fn {fn:.2f}: outside its data (Cp 0.55–0.85, Fn ≤ 0.45)"
    if fn_min is not None and fn_min < DAWSON_FN_MIN:
        out["dawson"] = (f"Fn {fn_min:.2f}: below Fn {DAWSON_FN_MIN:.2f} its free-surface grid has fewer than 10 "
                         "columns a transverse wave, whose damping lowers C_W")
    return out
