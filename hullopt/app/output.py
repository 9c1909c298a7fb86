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
- :data:`EXIT_CODES` — the exit codes of every command, documented in ``hullopt --help`` and docs/cli.md.
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
from ..geometry import export_mesh, hull_mesh, stl_header
from ..report import SIG, fmt, is_number, scalar, to_builtin

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
# ----------------------------------------------------------------------------------------------- terminal


def _cell(v: Any, ref: float | None, sig: int, places: int | None = None) -> Text:
    v = scalar(v)
    if isinstance(v, Text):
        return v
    if isinstance(v, float):
        return Text(fmt(v, sig, ref, places))
    return Text(fmt(v) if is_number(v) or isinstance(v, bool) or v is None else str(v))


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
    rows = [[scalar(v) for v in r] for r in rows]
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


def wrote(path: Path | str, detail: str = "", json: bool = False) -> None:
    """The one line every command prints for each file it wrote: ``wrote PATH`` or ``wrote PATH (detail)``; on
    stderr when stdout is the JSON a script reads (``json``)."""
    text = Text(f"wrote {path}" + (f" ({detail})" if detail else ""))
    (errors if json else console).print(text, soft_wrap=True)


def warn(text: str) -> None:
    """``warning: text`` on stderr (stdout stays the table or the JSON a script reads), on one logical line as
    :func:`say` prints (the terminal wraps it)."""
    errors.print(Text(f"warning: {text}", style="yellow"), soft_wrap=True)


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


def print_json(obj: Any) -> None:
    print(json.dumps(to_builtin(obj), indent=2))


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


def check_out(path: Path, formats: tuple[str, ...], what: str) -> Path:
    """``path`` for the option ``what``, if its suffix is one of ``formats`` and its folder exists; else a
    :class:`~hullopt.errors.HullError` naming the option and what it expected."""
    if path.suffix.lower() not in formats:
        raise HullError(f"{what} {path}: unknown format {path.suffix!r}; expected one of {', '.join(formats)}")
    if not path.parent.is_dir():
        raise HullError(f"{what} {path}: the folder {str(path.parent)!r} does not exist")
    return path
