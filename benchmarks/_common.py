"""Shared helpers for benchmarks: timing, machine info, atomic result files."""

from __future__ import annotations

import json
import os
import platform
import statistics
import time
from pathlib import Path

RESULTS = Path(__file__).parent / "results"


HULLS = Path(__file__).resolve().parents[1] / "examples" / "hulls"  # real hulls (see SOURCES.md there)


def machine() -> dict:
    import jax

    return {
        "python": platform.python_version(),
        "jax": jax.__version__,
        "cpu": platform.processor() or platform.machine(),
        "cores": os.cpu_count(),
        "date": time.strftime("%Y-%m-%d %H:%M"),
    }


def timeit(fn, repeat: int = 7) -> float:
    """Median wall time [s] of ``fn()`` over ``repeat`` runs (after the caller's warm-up)."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def save(name: str, data: dict) -> Path:
    RESULTS.mkdir(exist_ok=True)
    path = RESULTS / f"{name}.json"
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps({"machine": machine(), **data}, indent=2) + "\n")
    tmp.replace(path)
    return path
