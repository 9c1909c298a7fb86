"""Wind-load coefficient models, one code path each, all read from the package data ``hullopt/data/wind``.

Conventions (every model, tested): ψ is the relative wind angle [rad] the wind comes **from**, 0 = head
wind, π = following wind, ψ > 0 = wind from starboard. Coefficients are normalised as in seed 004 (1a–4a)::

    X = q A_T C_X   (forward +, so C_X(0) < 0 in a head wind)   Y = q A_L C_Y   (to port +, i.e. to lee)
    N = q L A_L C_N (bow to port +, right-handed about z up)     K = q A_L H_L C_K (heel to port +)

with q = ½ρU², H_L = A_L/L. C_X is even in ψ; C_Y, C_N, C_K are odd. For ψ in (0, π) a positive C_N turns
the bow to lee (area forward of mid-length) and a positive C_K heels to lee. Models without a roll moment
return C_K = NaN. Variables are those of :class:`~hullopt.wind.WindVariables` (C forward positive).

* ``fujiwara1998`` — Fujiwara, Ueno & Nimura (1998) harmonics (seed 004 eqs. 1–7). The variable of the term
  y56 is ``C·H_C/A_L`` by default, as every public implementation has it (the Fortran and Python sources the
  table is transcribed from); with it the Esso Osaka model's harmonics X3, X5, Y1, Y3, Y5, N1, N2, N3 equal
  the values published beside that code (Y5 −0.01529; tests/test_wind_coefficients.py). Seed 004 eq. (7)
  prints ``L·H_C/A_L`` (and so does one MATLAB port): pass ``y56="L*H_C/A_L"`` for the printed form (Esso
  Osaka: Y5 −0.0331, C_Y(90°) 1.7 % lower).
* ``fujiwara2005`` — the Fujiwara, Ueno & Ikeda (2005) C_X adopted by ISO 15016:2015 (C_AA = −C_X; at ψ = 90°
  the mean of 80° and 100°), with C_Y, C_N from ShipMMG.jl (single source, unverified; no C_K).
* ``isherwood`` — Isherwood (1972) tables, linear in angle (no C_K).
* ``blendermann`` — Blendermann (1994) by ship type (C_K from κ s_H).
"""

from __future__ import annotations

import csv
import io
import re
from functools import cache
from importlib import resources

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._types import Angles
from ..errors import HullError
from ._variables import WindVariables

MODELS = ("fujiwara1998", "fujiwara2005", "isherwood", "blendermann")
DEFAULT_SHIP_TYPE = "Container ship, loaded"
_ALIASES = {"A_YV": "A_L", "A_XV": "A_T", "A_F": "A_T", "L_OA": "L", "C_MC": "C"}


class Coefficients(eqx.Module):
    """C_X, C_Y, C_N, C_K at the angles ``psi`` [rad] (same shape); see the module docstring for signs."""

    psi: Float[Array, "*angles"]
    cx: Float[Array, "*angles"]
    cy: Float[Array, "*angles"]
    cn: Float[Array, "*angles"]
    ck: Float[Array, "*angles"]


def read_table(name: str) -> tuple[list[str], list[dict[str, str]]]:
    """A package data table ``hullopt/data/wind/<name>``: its ``#`` header lines and its rows.

    Parameters
    ----------
    name : str
        File name in ``hullopt/data/wind`` (e.g. ``"isherwood1972_cx.csv"``).

    Returns
    -------
    header : list of str
        The lines starting with ``#``, in order.
    rows : list of dict
        The CSV rows as column name → text.
    """
    text = resources.files("hullopt").joinpath("data", "wind", name).read_text(encoding="utf-8")
    lines = text.splitlines()
    header = [ln for ln in lines if ln.startswith("#")]
    rows = list(csv.DictReader(io.StringIO("\n".join(ln for ln in lines if not ln.startswith("#")))))
    return header, rows


def group_factors(expr: str) -> list[tuple[str, int]]:
    """A dimensionless group like ``A_L/(L*B)`` or ``L^2/A_T`` as ``[(name, power), …]`` ("1" → []).

    Parameters
    ----------
    expr : str
        The group: products of names with optional integer powers ``^k``, over an optional (bracketed)
        denominator; aliases such as ``A_YV`` map to the :class:`WindVariables` names.

    Returns
    -------
    list of (str, int)
        Variable name and power, negative in the denominator.

    Raises
    ------
    ValueError
        If a factor cannot be read.
    """
    expr = expr.replace(" ", "")
    if expr == "1":
        return []
    num, _, den = expr.partition("/")
    den = den[1:-1] if den.startswith("(") and den.endswith(")") else den
    out = []
    for sign, side in ((1, num), (-1, den)):
        for f in filter(None, side.split("*")):
            m = re.fullmatch(r"([A-Za-z_]+)(?:\^(\d))?", f)
            if not m:
                raise ValueError(f"cannot read the group {expr!r}")
            out.append((_ALIASES.get(m[1], m[1]), sign * int(m[2] or 1)))
    return out


def _group(v: dict[str, Array], expr: str) -> Array:
    val = jnp.ones(())
    for name, power in group_factors(expr):
        val = val * v[name] ** power if power > 0 else val / v[name] ** (-power)
    return val


def _wrap(psi) -> tuple[Array, Array]:
    """|ψ| in [0, π] and the sign used for the odd coefficients."""
    psi = jnp.asarray(psi, dtype=float)
    wrapped = jnp.arctan2(jnp.sin(psi), jnp.cos(psi))
    return jnp.abs(wrapped), jnp.where(wrapped < 0, -1.0, 1.0)


@cache
def _fujiwara1998_table(y56: str) -> dict[str, dict[int, list[tuple[float, str]]]]:
    _, rows = read_table("fujiwara1998_regression_coefficients.csv")
    table: dict[str, dict[int, list[tuple[float, str]]]] = {}
    for r in rows:
        expr = y56 if r["name"] == "y56" else r["explanatory_variable"]
        table.setdefault(r["component"], {}).setdefault(int(r["harmonic"]), []).append((float(r["value"]), expr))
    return table


Y56_OPTIONS = ("C*H_C/A_L", "L*H_C/A_L")  # the default (public implementations), seed 004 eq. (7) as printed


def fujiwara1998_harmonics(v: WindVariables, y56: str = "C*H_C/A_L") -> dict[str, dict[int, Array]]:
    """The harmonics X_i, Y_i, N_i, K_i of seed 004 eqs. (1b–4b): ``{"X": {0: X0, 1: X1, …}, …}``; ``y56``
    the variable of the Y5 term y56: ``"C*H_C/A_L"`` (default, the public implementations) or
    ``"L*H_C/A_L"`` (seed 004 eq. 7 as printed).

    Parameters
    ----------
    v : WindVariables
        The explanatory variables (:func:`wind_variables`, SI).
    y56 : {"C*H_C/A_L", "L*H_C/A_L"}
        The variable of the Y5 term y56.

    Returns
    -------
    dict of str to dict of int to Array
        Component (``"X"``, ``"Y"``, ``"N"``, ``"K"``) → harmonic index → dimensionless scalar coefficient.

    Raises
    ------
    HullError
        If ``y56`` is not one of ``Y56_OPTIONS``.
    """
    if y56 not in Y56_OPTIONS:
        raise HullError(f"y56 {y56!r}: expected 'C*H_C/A_L' (the default, as public implementations have it) "
                        "or 'L*H_C/A_L' (seed 004 eq. 7 as printed)")
    s = v.scalars()
    return {comp: {i: sum(c * _group(s, e) for c, e in terms) for i, terms in harm.items()}
            for comp, harm in _fujiwara1998_table(y56).items()}


def fujiwara1998(v: WindVariables, psi: Angles, y56: str = "C*H_C/A_L") -> Coefficients:
    """Fujiwara, Ueno & Nimura (1998): C_X = Σ X_i cos iψ, C_Y, C_N, C_K = Σ (·)_i sin iψ.

    Parameters
    ----------
    v : WindVariables
        The explanatory variables (:func:`wind_variables`, SI).
    psi : float or Array
        Relative wind angle ψ [rad] (where the wind comes from, 0 = head wind, + from starboard), any shape.
    y56 : {"C*H_C/A_L", "L*H_C/A_L"}
        The variable of the Y5 term y56, see :func:`fujiwara1998_harmonics`.

    Returns
    -------
    Coefficients
        Dimensionless ``cx``, ``cy``, ``cn``, ``ck``, shape of ``psi``.
    """
    h = fujiwara1998_harmonics(v, y56)
    psi = jnp.asarray(psi, dtype=float)

    def series(comp, fn):
        return sum(c * fn(i * psi) for i, c in h[comp].items())

    return Coefficients(psi, series("X", jnp.cos), series("Y", jnp.sin), series("N", jnp.sin), series("K", jnp.sin))


@cache
def _factor_table(name: str) -> list[dict[str, str]]:
    return read_table(name)[1]


def _factors(v: dict[str, Array], rows, rng: str) -> dict[str, Array]:
    out: dict[str, Array] = {}
    for r in rows:
        if r["psi_range"] in (rng, "all"):
            key = r.get("factor") or r["quantity"]
            if r.get("term") == "p0":  # ShipMMG's π·A_L/L² term
                val = float(r["value"]) * _group(v, "A_L/L^2")
            elif key == "C_N_lever":
                continue
            else:
                val = float(r["value"]) * _group(v, r["explanatory_variable"])
            out[key] = out.get(key, 0.0) + val
    return out


def _iso_caa(s: dict[str, Array], a: Array) -> Array:
    """ISO 15016 C_AA(ψ) for ψ in [0, π] (positive = resistance)."""
    rows = _factor_table("fujiwara2005_iso15016_cx_coefficients.csv")
    head, tail = _factors(s, rows, "0<=psi<90"), _factors(s, rows, "90<psi<=180")

    def caa(f, a):
        sn, cs = jnp.sin(a), jnp.cos(a)
        return f["C_LF"] * cs + f["C_XLI"] * (sn - 0.5 * sn * cs**2) * sn * cs + f["C_ALF"] * sn * cs**3

    mu = np.deg2rad(10.0)
    beam = 0.5 * (caa(head, jnp.pi / 2 - mu) + caa(tail, jnp.pi / 2 + mu))
    return jnp.where(a < jnp.pi / 2, caa(head, a), jnp.where(a > jnp.pi / 2, caa(tail, a), beam))


def fujiwara2005(v: WindVariables, psi: Angles) -> Coefficients:
    """ISO 15016:2015 C_X (Fujiwara, Ueno & Ikeda 2005) and the ShipMMG.jl C_Y, C_N (unverified); C_K = NaN.

    Parameters
    ----------
    v : WindVariables
        The explanatory variables (:func:`wind_variables`, SI).
    psi : float or Array
        Relative wind angle ψ [rad] (where the wind comes from, 0 = head wind, + from starboard), any shape.

    Returns
    -------
    Coefficients
        Dimensionless ``cx``, ``cy``, ``cn`` and ``ck`` = NaN, shape of ``psi``.
    """
    s = v.scalars()
    a, sign = _wrap(psi)
    cx = -_iso_caa(s, a)
    rows = _factor_table("fujiwara2005_cy_cn_shipmmg_unverified.csv")
    head, tail = _factors(s, rows, "0<=psi<=90"), _factors(s, rows, "90<psi<=180")
    sn, cs = jnp.sin(a), jnp.cos(a)
    c_yli = jnp.where(a <= jnp.pi / 2, head["C_YLI"], tail["C_YLI"])
    cy = head["C_CF"] * sn**2 + c_yli * (cs + 0.5 * sn**2 * cs) * sn * cs
    lever = {r["term"]: float(r["value"]) for r in rows if r["quantity"] == "C_N_lever"}
    cn = cy * (lever["n0"] * s["C"] / s["L"] + lever["n1"] * (a - jnp.pi / 2))
    return Coefficients(jnp.asarray(psi, dtype=float), cx, sign * cy, sign * cn, jnp.full_like(cx, jnp.nan))


@cache
def _isherwood_tables() -> dict[str, np.ndarray]:
    out = {}
    for c in ("cx", "cy", "cn"):
        _, rows = read_table(f"isherwood1972_{c}.csv")
        out[c] = np.array([[float(x) for x in r.values()] for r in rows])  # gamma, coefficients…
    return out


def isherwood(v: WindVariables, psi: Angles) -> Coefficients:
    """Isherwood (1972), interpolated linearly in angle; C (from the bow) is ``C_bow``; C_K = NaN.

    Parameters
    ----------
    v : WindVariables
        The explanatory variables (:func:`wind_variables`, SI).
    psi : float or Array
        Relative wind angle ψ [rad] (where the wind comes from, 0 = head wind, + from starboard), any shape.

    Returns
    -------
    Coefficients
        Dimensionless ``cx``, ``cy``, ``cn`` and ``ck`` = NaN, shape of ``psi``.
    """
    a, sign = _wrap(psi)
    deg = jnp.rad2deg(a)
    t = _isherwood_tables()
    groups = [1.0, 2 * v.A_L / v.L**2, 2 * v.A_T / v.B**2, v.L / v.B, v.S / v.L, v.C_bow / v.L]

    def fit(tab, extra):
        coef = [jnp.interp(deg, tab[:, 0], tab[:, j + 1]) for j in range(tab.shape[1] - 1)]
        return sum(c * g for c, g in zip(coef, [*groups, *extra]))

    cx = -fit(t["cx"], [v.M])
    cy = fit(t["cy"], [v.A_SS / v.A_L])
    cn = fit(t["cn"], [])
    return Coefficients(jnp.asarray(psi, dtype=float), cx, sign * cy, sign * cn, jnp.full_like(cx, jnp.nan))


@cache
def blendermann_types() -> dict[str, dict[str, float]]:
    """Blendermann's (1994) ship types: name → CDt, CDl_AF_bow, CDl_AF_stern, delta, kappa."""
    _, rows = read_table("blendermann1994_ship_types.csv")
    return {r["ship_type"]: {k: float(r[k]) for k in ("CDt", "CDl_AF_bow", "CDl_AF_stern", "delta", "kappa")}
            for r in rows}


def ship_type(name: str) -> str:
    """The Blendermann type matching ``name`` (case-insensitive, a unique prefix or its number 1–17).

    Parameters
    ----------
    name : str
        A type name, a unique case-insensitive prefix of one, or its number 1–17 as text.

    Returns
    -------
    str
        The full type name, a key of :func:`blendermann_types`.

    Raises
    ------
    HullError
        If ``name`` matches no type or more than one.
    """
    types = list(blendermann_types())
    if name.strip().isdigit() and 1 <= int(name) <= len(types):
        return types[int(name) - 1]
    hits = [t for t in types if t.lower() == name.strip().lower()] or \
           [t for t in types if t.lower().startswith(name.strip().lower())]
    if len(hits) != 1:
        raise HullError(f"ship type {name!r}: expected one of {'; '.join(types)} (or its number 1–{len(types)})")
    return hits[0]


def blendermann(v: WindVariables, psi: Angles, ship: str = DEFAULT_SHIP_TYPE) -> Coefficients:
    """Blendermann (1994) for a ship type (:func:`ship_type`); s_L = C, s_H = H_C, H_M = A_L/L.

    Parameters
    ----------
    v : WindVariables
        The explanatory variables (:func:`wind_variables`, SI).
    psi : float or Array
        Relative wind angle ψ [rad] (where the wind comes from, 0 = head wind, + from starboard), any shape.
    ship : str
        Blendermann's ship type, anything :func:`ship_type` accepts.

    Returns
    -------
    Coefficients
        Dimensionless ``cx``, ``cy``, ``cn``, ``ck``, shape of ``psi``.
    """
    p = blendermann_types()[ship_type(ship)]
    a, sign = _wrap(psi)
    cdl_af = jnp.where(a <= jnp.pi / 2, p["CDl_AF_bow"], p["CDl_AF_stern"])
    cdl = cdl_af * v.A_T / v.A_L
    den = 1.0 - 0.5 * p["delta"] * (1.0 - cdl / p["CDt"]) * jnp.sin(2 * a) ** 2
    cx = -cdl_af * jnp.cos(a) / den
    cy = p["CDt"] * jnp.sin(a) / den
    ck = p["kappa"] * (v.H_C / v.H_L) * cy
    cn = (v.C / v.L - 0.18 * (a - jnp.pi / 2)) * cy
    return Coefficients(jnp.asarray(psi, dtype=float), cx, sign * cy, sign * cn, sign * ck)


def wind_coefficients(v: WindVariables, psi: Angles, model: str = "fujiwara1998", *, ship: str = DEFAULT_SHIP_TYPE,
                      y56: str = "C*H_C/A_L") -> Coefficients:
    """C_X, C_Y, C_N, C_K of ``model`` (one of :data:`MODELS`) at the relative wind angles ``psi`` [rad].

    Parameters
    ----------
    v : WindVariables
        The explanatory variables of the hull above water and its parts (:func:`wind_variables`, SI).
    psi : float or Array
        Relative wind angle [rad]: 0 = head wind, the angle the wind comes *from*, positive from starboard.
    model : str
        One of :data:`MODELS` (``"fujiwara1998"``, ``"fujiwara2005"``, ``"isherwood"``, ``"blendermann"``).
    ship : str
        Blendermann's ship type (see :func:`blendermann_types`).
    y56 : str
        Fujiwara 1998: the variable of the Y5 term y56, ``"C*H_C/A_L"`` (default, as the public
        implementations) or ``"L*H_C/A_L"`` (seed 004 eq. 7 as printed).

    Returns
    -------
    Coefficients
        Dimensionless ``cx``, ``cy``, ``cn``, ``ck``, shape of ``psi``; signs in the module docstring (a head
        wind pushes astern: C_X < 0).

    Examples
    --------
    The coarse Wigley with a 20 × 8 × 10 m house: head wind pushes it astern with no side force (C_Y = 0
    by symmetry); C_X −0.884 is a measured value (Fujiwara 1998):

    >>> import jax; jax.config.update("jax_enable_x64", True)
    >>> from hullopt.models import wigley
    >>> from hullopt.wind import box_parts, wind_variables, wind_coefficients
    >>> house = box_parts(["house"], ["superstructure"], 10.0, 30.0, 10.0, 20.0, 8.0)
    >>> v = jax.jit(wind_variables)(wigley(100, 10, 6.25, 10, n=21, m=21), 6.25, house)
    >>> c = wind_coefficients(v, 0.0)
    >>> round(float(c.cx), 3), abs(round(float(c.cy), 6))
    (-0.884, 0.0)
    """
    if model == "fujiwara1998":
        return fujiwara1998(v, psi, y56)
    if model == "fujiwara2005":
        return fujiwara2005(v, psi)
    if model == "isherwood":
        return isherwood(v, psi)
    if model == "blendermann":
        return blendermann(v, psi, ship)
    raise HullError(f"wind model {model!r}: expected one of {', '.join(MODELS)}")
