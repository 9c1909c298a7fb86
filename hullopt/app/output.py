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
from ..geometry import atomic_write_bytes

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
