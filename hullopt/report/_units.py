"""Numbers as a naval architect reads them, in every output hullopt writes (terminal tables, plots,
report.html): each report key's label and displayed unit, significant figures and decimals, JSON with SI units.

- :func:`fmt` / :func:`quantity` — a number (and its unit) with sensible significant figures, fixed-point for
  ordinary magnitudes, round-off noise (``-7.1e-15``) as ``0``;
- :func:`label` / :func:`displayed` — a report key's label with its unit and its value in that unit (kg → t,
  N → kN); an objective's label says what it computes (:func:`objective_about`: its method, calm water or
  waves);
- :func:`write_json` — JSON in SI units (:data:`JSON_UNITS`), written atomically.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from ..geometry import atomic_write_bytes

JSON_UNITS = ("JSON (--json, report.json) is in SI units: m, m², m³, kg, N, s, rad; a key ending in _deg is in "
              "degrees, _kn in knots, _pct in per cent (LCB, LCF: of Lpp from midship, forward positive); tpc "
              "[t/cm] and mct [t·m/cm] keep their definitions' units.")

# ----------------------------------------------------------------------------------------------- units

# ``hullopt hydro``'s keys (report.json's "parent" and "achieved"): label, displayed unit, and the factor from
# the JSON's value to the displayed one
PARTICULARS: dict[str, tuple[str, str, float]] = {
    "draft": ("Draft T", "m", 1), "volume": ("Volume ∇", "m³", 1), "displacement": ("Displacement Δ", "t", 1e-3),
    "wetted_surface": ("Wetted surface S", "m²", 1), "a_transom": ("Immersed transom A_T", "m²", 1),
    "cb": ("Cb", "", 1), "cp": ("Cp", "", 1), "cm": ("Cm", "", 1),
    "cwp": ("Cwp", "", 1), "lcb": ("LCB from AP", "m", 1), "lcb_pct": ("LCB from midship", "% Lpp", 1),
    "kb": ("KB", "m", 1), "awp": ("Awp", "m²", 1), "lcf": ("LCF from AP", "m", 1),
    "lcf_pct": ("LCF from midship", "% Lpp", 1), "bmt": ("BM_T", "m", 1), "bml": ("BM_L", "m", 1),
    "kmt": ("KM_T", "m", 1), "tpc": ("TPC", "t/cm", 1), "mct": ("MCT 1 cm", "t·m/cm", 1),
    "lwl": ("Lwl", "m", 1), "bwl": ("Bwl", "m", 1),
}
# the run targets that are no hydrostatics key, and the objectives (optimise.OBJECTIVES): the same triples
TARGET_UNITS: dict[str, tuple[str, str, float]] = {"gm": ("GM", "m", 1), "bf": ("Bf", "", 1)}
OBJECTIVE_UNITS: dict[str, tuple[str, str, float]] = {
    "k_aw": ("K_AW", "", 1), "mean_added_resistance": ("mean added resistance R_AW", "kN", 1e-3),
    "calm_resistance": ("calm-water resistance R_T", "kN", 1e-3),
    "calm_resistance_michell": ("calm-water resistance (Michell) R_T", "kN", 1e-3),
    "calm_resistance_dawson": ("calm-water resistance (Dawson) R_T", "kN", 1e-3),
    "wind_added_resistance": ("wind added resistance R_AA", "kN", 1e-3),
    "profile_resistance": ("operating profile R_T + R_AW", "kN", 1e-3),
    "profile_power": ("operating profile power P_E", "kW", 1e-3),
    "profile_added_resistance": ("operating profile added resistance R_AW", "kN", 1e-3),
}
# an objective's symbol where it is not the last word of its name (column headers, plot axes)
SYMBOLS = {"profile_resistance": "R_T + R_AW (profile)", "profile_power": "P_E (profile)",
           "profile_added_resistance": "R_AW (profile)"}
# the shape measures a report compares (fairing.SHAPE_MEASURES): the same triples
SHAPE_UNITS: dict[str, tuple[str, str, float]] = {
    "unfairness": ("unfairness U", "", 1), "sac_roughness": ("SAC roughness Σ (A'')² Δx", "m", 1),
    "section_roughness": ("section roughness Σ (Δκ)²/Δs", "m⁻³", 1),
    "section_knuckle": ("section knuckles Σ θ⁴", "rad⁴", 1),
    "entrance_angle": ("waterline half-angle of entrance (largest)", "°", 180.0 / math.pi),
    "run_angle": ("waterline half-angle of the run (largest)", "°", 180.0 / math.pi),
}


def units_of(key: str) -> tuple[str, str, float]:
    """The label, displayed unit and factor from SI of a report key.

    Parameters
    ----------
    key : str
        A report key: a particular (:data:`PARTICULARS`), a target (:data:`TARGET_UNITS`) or an objective
        (:data:`OBJECTIVE_UNITS`; one not listed there by the ``unit`` its class declares in
        :data:`hullopt.optimise.OBJECTIVES`, N shown in kN).

    Returns
    -------
    tuple of (str, str, float)
        ``(label, displayed unit, factor from SI)``; an unknown key as it is, with no unit and factor 1.
    """
    known = {**PARTICULARS, **TARGET_UNITS, **OBJECTIVE_UNITS, **SHAPE_UNITS}
    if key in known:
        return known[key]
    from ..optimise import OBJECTIVES  # here: the units of the known keys need no solver library

    unit = getattr(OBJECTIVES.get(key), "unit", "") if isinstance(OBJECTIVES, dict) else ""
    return {"N": (key, "kN", 1e-3), "-": (key, "", 1)}.get(unit, (key, unit or "", 1))


def unit_scale(unit: str) -> float:
    """The magnitude below which a quantity in ``unit`` is shown at this scale's decimals.

    A position in % Lpp or an angle in degrees reads 0.000, not 1.8e-09, at its round-off.

    Parameters
    ----------
    unit : str
        A displayed unit (``"m"``, ``"% Lpp"``, ``"°"``, …).

    Returns
    -------
    float
        1 for ``% Lpp``, ``%``, ``°`` and ``deg``, else 0.
    """
    return 1.0 if unit in ("% Lpp", "%", "°", "deg") else 0.0


# the least decimals a naval architect reads a quantity in these units to (m: to the mm, t: to 0.1 t)
UNIT_PLACES = {"m": 3, "m²": 1, "m³": 1, "t": 1, "% Lpp": 3, "t/cm": 2, "t·m/cm": 1, "m·rad": 3, "kN": 2,
               "°": 1, "deg": 1}


def unit_places(unit: str) -> int | None:
    """The least decimals of a quantity in ``unit`` (:data:`UNIT_PLACES`).

    Parameters
    ----------
    unit : str
        A displayed unit (``"m"``, ``"t"``, ``"kN"``, …).

    Returns
    -------
    int or None
        The decimals (m: 3, to the mm; t: 1); None for a unit not listed: by significant figures only.
    """
    return UNIT_PLACES.get(unit)


# how a run names its wave-resistance methods in labels
METHOD_NAMES = {"holtrop": "Holtrop", "michell": "Michell", "panel": "panel", "dawson": "Dawson"}


def objective_about(objective: Any) -> dict:
    """What an objective's label must say beyond its kind: the wave-resistance method of its calm-water R_T and
    whether it adds added resistance in waves (an operating profile with sea states).

    Parameters
    ----------
    objective : hullopt.optimise.Objective
        The objective (its ``method`` and ``waves`` fields where it has them; read, not imported).

    Returns
    -------
    dict
        ``{"method": str or None, "waves": bool or None}``, as ``report.json``'s ``objective.about`` keeps it
        for :func:`label`'s ``about``.
    """
    method, waves = getattr(objective, "method", None), getattr(objective, "waves", None)
    return {"method": str(method) if method is not None else None,
            "waves": bool(waves) if waves is not None else None}


def _described(key: str, about: Any) -> tuple[str, str] | None:
    """``(label, symbol)`` of an objective whose kind alone does not say what it computes, else None."""
    if not about:
        return None
    method = about.get("method")
    name = METHOD_NAMES.get(method, method) if method else ""
    who, also = (f" ({name})", f", {name}") if name else ("", "")
    calm = about.get("waves") is False  # an operating profile without a sea state: calm water only
    if key == "profile_resistance":
        return ((f"operating profile calm-water R_T{who}", f"R_T (profile{also})") if calm else
                (f"operating profile R_T{who} + R_AW (NMRI)", "R_T + R_AW (profile)"))
    if key == "profile_power":
        return ((f"operating profile calm-water power P_E = U·R_T{who}", "P_E (profile, calm)") if calm else
                (f"operating profile power P_E = U·(R_T{who} + R_AW)", "P_E (profile)"))
    if key == "calm_resistance" and method:
        return f"calm-water resistance{who} R_T", f"R_T{who}"
    return None


def label(key: str, unit: bool = True, short: bool = False, about: Any = None) -> str:
    """A report key as a table label with its unit (``lcb_pct`` → ``LCB from midship [% Lpp]``).

    Parameters
    ----------
    key : str
        A report key (:func:`units_of`).
    unit : bool
        Append the displayed unit in brackets (when the key has one).
    short : bool
        An objective by its symbol alone (``mean_added_resistance`` → ``R_AW [kN]``), for column headers.
    about : dict or None
        An objective's :func:`objective_about` (``report.json``'s ``objective.about``): the label names what
        is computed — an operating profile without sea states as calm-water R_T by its method, not
        "R_T + R_AW". None: by the key alone.

    Returns
    -------
    str
        The label.
    """
    name, u, _ = units_of(key)
    told = _described(key, about)
    if told is not None:
        name = told[1] if short else told[0]
    elif short and key in OBJECTIVE_UNITS:
        name = SYMBOLS.get(key, name.split()[-1])
    return f"{name} [{u}]" if unit and u else name


def displayed(key: str, value: Any) -> tuple[Any, str]:
    """A report key's value in its displayed unit (``displacement`` in kg → t, a resistance in N → kN).

    Parameters
    ----------
    key : str
        A report key (:func:`units_of`).
    value : float or None
        The value in SI units (as in ``report.json``).

    Returns
    -------
    tuple of (float or None, str)
        ``(value in the displayed unit, unit)``; None for a None ``value``.
    """
    _, u, factor = units_of(key)
    return (None if value is None else float(value) * factor), u


# ----------------------------------------------------------------------------------------------- numbers

NOISE = 1e-9  # magnitudes below this (in the displayed unit) are round-off: printed as 0
SIG = 4  # significant figures of the largest number of a column


def decimals(ref: float, sig: int = SIG) -> int | None:
    """Decimals that give ``sig`` significant figures to a number of magnitude ``ref``.

    Parameters
    ----------
    ref : float
        The magnitude (its absolute value is taken): a number, or the largest of a column.
    sig : int
        Significant figures.

    Returns
    -------
    int or None
        The decimals, between 0 and 10; 0 for round-off noise (``|ref|`` < :data:`NOISE`) or a non-finite
        ``ref``; None where fixed-point would not read well (``|ref|`` ≥ 1e9 or below 1e-4: scientific notation).
    """
    ref = abs(float(ref))
    if ref < NOISE or not math.isfinite(ref):
        return 0
    if ref >= 1e9 or ref < 1e-4:
        return None
    return min(max(sig - 1 - math.floor(math.log10(ref)), 0), 10)


def scalar(v: Any) -> Any:
    """numpy and JAX 0-d arrays → Python numbers; everything else unchanged.

    Parameters
    ----------
    v : Any
        A value.

    Returns
    -------
    Any
        ``v.item()`` for a 0-d array or numpy scalar, else ``v`` itself.
    """
    if hasattr(v, "dtype") and np.ndim(v) == 0 and not isinstance(v, float | int):
        return np.asarray(v).item()
    return v


def is_number(v: Any) -> bool:
    """Whether ``v`` is a Python number (an int or a float, not a bool).

    Parameters
    ----------
    v : Any
        A value.

    Returns
    -------
    bool
        True for an int or a float (NaN and infinities included), False for a bool, an array or anything else.
    """
    return isinstance(v, float | int) and not isinstance(v, bool)


def fmt(v: Any, sig: int = SIG, ref: float | None = None, places: int | None = None) -> str:
    """A number as a naval architect reads it.

    ``sig`` significant figures of ``ref`` (default ``|v|``; a column's largest value, so that the column shares
    its decimals) but at least ``places`` decimals (e.g. 3 for metres, :func:`unit_places`), fixed-point
    (``52083``, ``0.4444``, ``-1.169``) unless the magnitude is below 1e-4 or from 1e9 (``3.21e-07``); round-off
    noise (``|v| < 1e-9``, or rounding to zero at ``ref``'s decimals) as ``0``, never ``-0.000``; NaN or None as
    ``–``, infinities as ``∞``. Integers print as they are, booleans as yes/no.

    Parameters
    ----------
    v : Any
        A number (Python, numpy or a JAX 0-d array), a bool, or None.
    sig : int
        Significant figures.
    ref : float or None
        The magnitude that sets the decimals; None: ``|v|``.
    places : int or None
        The least decimals in fixed-point; None: by significant figures only.

    Returns
    -------
    str
        The number as text.

    Examples
    --------
    >>> fmt(-7.105e-15), fmt(52083.3), fmt(0.44444), fmt(-1.222e-18, ref=6.1), fmt(2.5e-7), fmt(174.06, places=3)
    ('0', '52083', '0.4444', '0.000', '2.500e-07', '174.060')
    """
    v = scalar(v)
    if v is None:
        return "–"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return str(v)
    v = float(v)
    if math.isnan(v):
        return "–"
    if math.isinf(v):
        return "∞" if v > 0 else "−∞"
    d = decimals(abs(v) if ref is None else max(abs(float(ref)), abs(v) if abs(v) >= NOISE else 0.0), sig)
    if d is not None and places is not None:
        d = max(d, places)
    if abs(v) < NOISE:
        v = 0.0
    text = f"{v:.{sig - 1}e}" if d is None else f"{v:.{d}f}"
    if text.startswith("-") and float(text) == 0:
        text = text[1:]
    return text


def quantity(v: Any, unit: str = "", sig: int = SIG, ref: float | None = None, places: int | None = None) -> str:
    """``fmt(v)`` and its unit: ``quantity(52083.3, "m³")`` → ``'52083 m³'``; ``%`` and ``°`` sit on the number.

    Parameters
    ----------
    v : Any
        A number, as :func:`fmt` takes it.
    unit : str
        The unit written after the number; empty: none.
    sig : int
        Significant figures.
    ref : float or None
        The magnitude that sets the decimals; None: ``|v|``.
    places : int or None
        The least decimals in fixed-point; None: by significant figures only.

    Returns
    -------
    str
        The number and its unit, a space between them (none before ``%`` or ``°``).
    """
    text = fmt(v, sig, ref, places)
    if not unit:
        return text
    return f"{text}{unit}" if unit in ("%", "°") else f"{text} {unit}"


def change(before: Any, after: Any, unit: str = "", sig: int = SIG) -> str:
    """``before → after unit (±x.x %)`` with both numbers at the same decimals.

    Parameters
    ----------
    before : Any
        The value before (the parent's), a number or a 0-d array.
    after : Any
        The value after (the design's), in the same unit.
    unit : str
        The unit, written after ``after``.
    sig : int
        Significant figures of the larger magnitude.

    Returns
    -------
    str
        Both values and the relative change to two decimals; the change left out where ``before`` is zero
        (below :data:`NOISE`) or ``after`` is not finite.
    """
    b, a = float(scalar(before)), float(scalar(after))
    ref = max(abs(b), abs(a))
    text = f"{fmt(b, sig, ref)} → {quantity(a, unit, sig, ref)}"
    if abs(b) >= NOISE and math.isfinite(a):
        text += f" ({100 * (a / b - 1):+.2f} %)"
    return text


def to_builtin(obj: Any) -> Any:
    """Arrays and numpy scalars → lists and floats (NaN and inf → None), recursively.

    Parameters
    ----------
    obj : Any
        A value: dicts, lists and tuples are walked, arrays and numpy scalars converted.

    Returns
    -------
    Any
        The same structure in Python builtins (tuples as lists), JSON-serialisable when its leaves are.
    """
    if isinstance(obj, dict):
        return {k: to_builtin(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [to_builtin(v) for v in obj]
    if hasattr(obj, "tolist"):
        return to_builtin(np.asarray(obj).tolist())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def write_json(path: str | os.PathLike, obj: Any) -> Path:
    """Write ``obj`` as indented JSON (:func:`to_builtin`: arrays as lists, NaN and inf as null), atomically.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write.
    obj : Any
        The value, in SI units (:data:`JSON_UNITS`).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    path = Path(path)
    atomic_write_bytes(path, (json.dumps(to_builtin(obj), indent=2) + "\n").encode())
    return path
