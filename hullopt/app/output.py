"""Terminal and file output shared by the commands: numbers with units, tables, messages, progress, exit codes,
JSON and ranges.

Every command prints through here so that the terminal reads the same everywhere:

- :func:`fmt` / :func:`quantity` — a number (and its unit) with sensible significant figures, fixed-point for
  ordinary magnitudes, round-off noise (``-7.1e-15``) as ``0``;
- :func:`table` — a rich table whose float cells are formatted by :func:`fmt` with one number of decimals per
  column (or row), units in the headers or labels (``"GZ [m]"``: never eaten as rich markup), its title above
  it, sized to fit 100 columns;
- :func:`say`, :func:`warn`, :func:`busy` — plain messages (no markup), warnings on stderr, a progress spinner
  with the elapsed time on anything slow;
- :data:`EXIT_CODES` — the exit codes of every command, documented in ``hullopt --help`` and the README.
"""

from __future__ import annotations

import json
import math
import os
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np
from rich.console import Console
from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn
from rich.table import Table
from rich.text import Text

from ..errors import HullError
from ..geometry import atomic_write_bytes, export_mesh, hull_mesh, stl_header

WIDTH = 100  # tables are laid out to fit this many columns


def _width() -> int | None:
    """The console width: ``$COLUMNS`` or the terminal's (rich finds them), else :data:`WIDTH` (a pipe or a file
    gets 100-column tables, not rich's default 80)."""
    if os.environ.get("COLUMNS", "").isdigit() or sys.stdout.isatty():
        return None
    return WIDTH


console = Console(width=_width())
errors = Console(stderr=True, width=_width())

# ----------------------------------------------------------------------------------------------- exit codes

EXIT_OK, EXIT_INPUT, EXIT_TARGETS, EXIT_CRITERIA, EXIT_NOT_CONVERGED = 0, 2, 3, 4, 5
EXIT_CODES = {
    EXIT_OK: "success",
    1: "an internal error (a bug: please report it with the traceback)",
    EXIT_INPUT: "bad input or usage (a one-line 'error: …' on stderr)",
    EXIT_TARGETS: "run, merge: some target cannot be met (the closest design is written)",
    EXIT_CRITERIA: "stability: some IS Code criterion fails",
    EXIT_NOT_CONVERGED: "fair: the fairing did not converge (its result is still written)",
}
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
    "wind_added_resistance": ("wind added resistance R_AA", "kN", 1e-3),
}


def _units(key: str) -> tuple[str, str, float]:
    """``(label, displayed unit, factor from SI)`` of a report key: a particular, a target, an objective (one
    not listed here by the ``unit`` its class declares in :data:`hullopt.optimise.OBJECTIVES`, N shown in kN);
    an unknown key as it is, with no unit."""
    known = {**PARTICULARS, **TARGET_UNITS, **OBJECTIVE_UNITS}
    if key in known:
        return known[key]
    from ..optimise import OBJECTIVES

    unit = getattr(OBJECTIVES.get(key), "unit", "") if isinstance(OBJECTIVES, dict) else ""
    return {"N": (key, "kN", 1e-3), "-": (key, "", 1)}.get(unit, (key, unit or "", 1))


def unit_scale(unit: str) -> float:
    """The magnitude below which a quantity in ``unit`` is shown at this scale's decimals (a position in % Lpp
    or an angle in degrees reads 0.000, not 1.8e-09, at its round-off): 1 for those units, else 0."""
    return 1.0 if unit in ("% Lpp", "%", "°", "deg") else 0.0


# the least decimals a naval architect reads a quantity in these units to (m: to the mm, t: to 0.1 t)
UNIT_PLACES = {"m": 3, "m²": 1, "m³": 1, "t": 1, "% Lpp": 3, "t/cm": 2, "t·m/cm": 1, "m·rad": 3, "kN": 2,
               "°": 1, "deg": 1}


def unit_places(unit: str) -> int | None:
    """The least decimals of a quantity in ``unit`` (:data:`UNIT_PLACES`; None: by significant figures only)."""
    return UNIT_PLACES.get(unit)


def label(key: str, unit: bool = True, short: bool = False) -> str:
    """A report key as a table label with its unit (``lcb_pct`` → ``LCB from midship [% Lpp]``); ``short``: an
    objective by its symbol alone (``mean_added_resistance`` → ``R_AW [kN]``), for column headers."""
    name, u, _ = _units(key)
    if short and key in OBJECTIVE_UNITS:
        name = name.split()[-1]
    return f"{name} [{u}]" if unit and u else name


def displayed(key: str, value: Any) -> tuple[Any, str]:
    """``(value in the displayed unit, unit)`` of a report key (``displacement`` in kg → t, a resistance in N
    → kN)."""
    _, u, factor = _units(key)
    return (None if value is None else float(value) * factor), u


# ----------------------------------------------------------------------------------------------- numbers

NOISE = 1e-9  # magnitudes below this (in the displayed unit) are round-off: printed as 0
SIG = 4  # significant figures of the largest number of a column


def decimals(ref: float, sig: int = SIG) -> int | None:
    """Decimals that give ``sig`` significant figures to a number of magnitude ``ref``; None where
    fixed-point would not read well (``ref`` ≥ 1e9 or below 1e-4: scientific notation)."""
    ref = abs(float(ref))
    if ref < NOISE or not math.isfinite(ref):
        return 0
    if ref >= 1e9 or ref < 1e-4:
        return None
    return min(max(sig - 1 - math.floor(math.log10(ref)), 0), 10)


def _scalar(v: Any) -> Any:
    """numpy and JAX 0-d arrays → Python numbers; everything else unchanged."""
    if hasattr(v, "dtype") and np.ndim(v) == 0 and not isinstance(v, float | int):
        return np.asarray(v).item()
    return v


def _is_number(v: Any) -> bool:
    return isinstance(v, float | int) and not isinstance(v, bool)


def fmt(v: Any, sig: int = SIG, ref: float | None = None, places: int | None = None) -> str:
    """A number as a naval architect reads it: ``sig`` significant figures of ``ref`` (default ``|v|``; a
    column's largest value, so that the column shares its decimals) but at least ``places`` decimals (e.g. 3
    for metres, :func:`unit_places`), fixed-point (``52083``, ``0.4444``, ``-1.169``) unless the magnitude is
    below 1e-4 or from 1e9 (``3.21e-07``); round-off noise (``|v| < 1e-9``, or rounding to zero at ``ref``'s
    decimals) as ``0``, never ``-0.000``; NaN or None as ``–``, infinities as ``∞``. Integers print as they
    are, booleans as yes/no.

    >>> fmt(-7.105e-15), fmt(52083.3), fmt(0.44444), fmt(-1.222e-18, ref=6.1), fmt(2.5e-7), fmt(174.06, places=3)
    ('0', '52083', '0.4444', '0.000', '2.500e-07', '174.060')
    """
    v = _scalar(v)
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
    """``fmt(v)`` and its unit: ``quantity(52083.3, "m³")`` → ``'52083 m³'``; ``%`` and ``°`` sit on the number."""
    text = fmt(v, sig, ref, places)
    if not unit:
        return text
    return f"{text}{unit}" if unit in ("%", "°") else f"{text} {unit}"


def change(before: Any, after: Any, unit: str = "", sig: int = SIG) -> str:
    """``before → after unit (±x.x %)`` with both numbers at the same decimals (the relative change left out
    where ``before`` is zero)."""
    b, a = float(_scalar(before)), float(_scalar(after))
    ref = max(abs(b), abs(a))
    text = f"{fmt(b, sig, ref)} → {quantity(a, unit, sig, ref)}"
    if abs(b) >= NOISE and math.isfinite(a):
        text += f" ({100 * (a / b - 1):+.2f} %)"
    return text


# ----------------------------------------------------------------------------------------------- terminal


def _cell(v: Any, ref: float | None, sig: int, places: int | None = None) -> Text:
    v = _scalar(v)
    if isinstance(v, Text):
        return v
    if isinstance(v, float):
        return Text(fmt(v, sig, ref, places))
    return Text(fmt(v) if _is_number(v) or isinstance(v, bool) or v is None else str(v))


def styled(text: str, style: str) -> Text:
    """A table cell or message in a rich style (``styled("FAIL", "bold red")``); plain strings are never
    read as markup."""
    return Text(text, style=style)


def table(title: str, columns: Sequence[str], rows: Sequence[Sequence[Any]], *, by: str = "column",
          sig: int = SIG, scale: Sequence[float | None] | None = None, places: Sequence[int | None] | None = None,
          caption: str | None = None) -> None:
    """Print a table: its ``title`` above it, ``columns`` as headers (put units there, ``"GZ [m]"``, or in a
    row's label), float cells through :func:`fmt` sharing their decimals ``by`` column (or ``"row"``, for tables
    of one quantity per row: the first column then holds the labels) so that round-off prints as ``0``;
    ``scale``: per column (or row) a magnitude to show it at when larger than its largest value (e.g. a GZ
    column that is round-off at 0° only, shown at the KN's scale); ``places``: per column (or row) at least
    so many decimals (:func:`unit_places` of its unit: 3 for metres, 1 for tonnes). Strings are shown as they
    are (no rich markup: use :func:`styled`). The first column is left-aligned, the others right-aligned;
    cells never wrap, and a table wider than the console is split into tables that repeat its first column;
    ``caption``: a note printed under it."""
    if by not in ("column", "row"):
        raise ValueError(f"by={by!r}: expected 'column' or 'row'")
    rows = [[_scalar(v) for v in r] for r in rows]
    n = len(columns) if by == "column" else len(rows)
    scale = list(scale) if scale is not None else [None] * n
    places = list(places) if places is not None else [None] * n
    if len(scale) != n or len(places) != n:
        raise ValueError(f"scale, places: {len(scale)}, {len(places)} values for {n} {by}s")

    def ref(values, floor) -> float | None:
        mags = [abs(v) for v in values if isinstance(v, float) and math.isfinite(v)]
        mags += [abs(float(floor))] if floor is not None else []
        return max(mags) if mags else None

    if by == "column":
        refs = [ref([r[j] for r in rows if j < len(r)], scale[j]) for j in range(len(columns))]
        cells = [[_cell(v, refs[j], sig, places[j]) for j, v in enumerate(r)] for r in rows]
    else:
        cells = [[_cell(v, ref(r, f), sig, d) for v in r] for r, f, d in zip(rows, scale, places)]
    if title:
        console.print(Text(title, style="bold"))
    heads = [Text(c) for c in columns]
    for part in _split(heads, cells, console.width):
        t = Table()
        for i in part:
            t.add_column(heads[i], justify="left" if i == 0 else "right", no_wrap=True)
        for r in cells:
            t.add_row(*(r[i] if i < len(r) else Text("") for i in part))
        console.print(t)
    if caption:
        say(caption, style="dim")


def _split(heads: list[Text], cells: list[list[Text]], width: int) -> list[list[int]]:
    """Column indices of the tables a too-wide table is split into, each repeating the first column and no
    wider than ``width`` (a rich table takes 3 columns per column for padding and rule, and 1 more)."""
    w = [max([h.cell_len] + [r[j].cell_len for r in cells if j < len(r)]) + 3 for j, h in enumerate(heads)]
    parts, cur = [], [0]
    for j in range(1, len(heads)):
        if len(cur) > 1 and 1 + sum(w[i] for i in cur) + w[j] > width:
            parts.append(cur)
            cur = [0]
        cur.append(j)
    parts.append(cur)
    if len(parts) == 1:
        return parts
    # as many tables as the greedy split needs, but balanced (not 6 + 6 + 1 columns) where they still fit
    per = math.ceil((len(heads) - 1) / len(parts))
    even = [[0, *range(j, min(j + per, len(heads)))] for j in range(1, len(heads), per)]
    return even if all(1 + sum(w[i] for i in part) <= width for part in even) else parts


def say(text: str, style: str | None = None) -> None:
    """Print a message as written (``[m]`` stays ``[m]``: no rich markup) on one logical line: the terminal
    wraps it, so paths and the words scripts look for are never split."""
    console.print(Text(text, style=style or ""), soft_wrap=True)


def warn(text: str) -> None:
    """``warning: text`` on stderr (stdout stays the table or the JSON a script reads)."""
    errors.print(Text(f"warning: {text}", style="yellow"))


@contextmanager
def busy(description: str, quiet: bool = False) -> Iterator:
    """A transient spinner with ``description`` and the elapsed time while the block runs (nothing when
    ``quiet`` or when stdout is not a terminal); yields ``update(text)`` to name the current stage."""
    with Progress(SpinnerColumn(), TextColumn("{task.description}"), TimeElapsedColumn(), console=console,
                  disable=quiet or not console.is_terminal, transient=True) as bar:
        task = bar.add_task(description, total=None)
        yield lambda text: bar.update(task, description=text)


def exit_code_help() -> str:
    """The exit codes as one paragraph for ``--help``."""
    return "Exit codes: " + "; ".join(f"{k} {v}" for k, v in EXIT_CODES.items()) + "."


def to_builtin(obj: Any) -> Any:
    """Arrays and numpy scalars → lists and floats (NaN and inf → None), recursively."""
    if isinstance(obj, dict):
        return {k: to_builtin(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [to_builtin(v) for v in obj]
    if hasattr(obj, "tolist"):
        return to_builtin(np.asarray(obj).tolist())
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    return obj


def print_json(obj: Any) -> None:
    print(json.dumps(to_builtin(obj), indent=2))


def write_json(path: str | os.PathLike, obj: Any) -> Path:
    path = Path(path)
    atomic_write_bytes(path, (json.dumps(to_builtin(obj), indent=2) + "\n").encode())
    return path


def parse_range(text: str, name: str) -> np.ndarray:
    """``'a:b:n'`` → ``n`` equally spaced values from a to b (inclusive)."""
    try:
        a, b, n = text.split(":")
        a, b, n = float(a), float(b), int(n)
        if n < 1 or not (math.isfinite(a) and math.isfinite(b)):
            raise ValueError
    except ValueError:
        raise HullError(f"{name} {text!r}: expected START:STOP:COUNT, e.g. 2:8:7") from None
    return np.linspace(a, b, n)


def write_hull_file(sections, path: Path, draft: float | None = None):
    """Write the closed hull mesh of ``sections`` to ``path`` (its folder created; an STL carries the Lpp and
    ``draft`` [m] in its header) and return the checks of the file read back
    (:class:`~hullopt.geometry.MeshReport`); :class:`HullError` if the written file is not a valid mesh."""
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        return export_mesh(hull_mesh(sections), path, stl_header(float(sections.lpp), draft))
    except ValueError as e:
        raise HullError(str(e)) from None
