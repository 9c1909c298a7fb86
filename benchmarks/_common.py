"""Shared helpers for benchmarks: timing, machine info, atomic result files."""

from __future__ import annotations

import json
import os
import platform
import statistics
import time
from pathlib import Path

RESULTS = Path(__file__).parent / "results"


def _find_shared() -> Path:
    """The reference folder: $HULLOPT_SHARED, else ``../shared`` beside the checkout, else /work/shared."""
    candidates = [os.environ.get("HULLOPT_SHARED"), Path(__file__).resolve().parents[1].parent / "shared",
                  "/work/shared"]
    for c in candidates:
        if c and (Path(c) / "hulls").is_dir():
            return Path(c)
    return Path(__file__).resolve().parents[1].parent / "shared"


SHARED = _find_shared()


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
