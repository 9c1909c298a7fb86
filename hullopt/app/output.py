"""Terminal and file output shared by the commands: JSON, rich tables, ranges."""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np
from rich.console import Console
from rich.table import Table

from ..errors import HullError
from ..geometry import atomic_write_bytes, export_mesh, hull_mesh, stl_header

console = Console()


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


def table(title: str, columns: list[str], rows: list[list[Any]]) -> None:
    t = Table(title=title, title_justify="left")
    for i, c in enumerate(columns):
        t.add_column(c, justify="left" if i == 0 else "right")
    for r in rows:
        t.add_row(*(f"{v:,.4g}" if isinstance(v, float) else str(v) for v in r))
    console.print(t)


def write_hull_file(sections, path: Path, draft: float | None = None):
    """Write the closed hull mesh of ``sections`` to ``path`` (its folder created; an STL carries the Lpp and
    ``draft`` [m] in its header) and return the checks of the file read back
    (:class:`~hullopt.geometry.MeshReport`); :class:`HullError` if the written file is not a valid mesh."""
    path.parent.mkdir(parents=True, exist_ok=True)
    try:
        return export_mesh(hull_mesh(sections), path, stl_header(float(sections.lpp), draft))
    except ValueError as e:
        raise HullError(str(e)) from None
