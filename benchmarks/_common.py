"""Shared helpers for benchmarks: timing, machine info (with the jax device), goals, atomic result files.

The benchmarks run on jax's default backend: a GPU when jax with CUDA is installed (``pip install -e '.[gpu]'``)
and one is present, else the CPU (``JAX_PLATFORMS=cpu`` forces it); each result records the device.
"""

from __future__ import annotations

import json
import os
import platform
import statistics
import sys
import time
from pathlib import Path

RESULTS = Path(__file__).parent / "results"
# On a GPU, jax takes 75 % of its memory at the first operation: a benchmark that starts hullopt processes would
# leave them none. Each process takes what it needs instead (set before any benchmark initialises jax).
os.environ.setdefault("XLA_PYTHON_CLIENT_PREALLOCATE", "false")
# 1-minute load average when the benchmark started (importing this module), before its own work loads the
# machine: other jobs' load, which makes timings upper bounds (os.getloadavg: Unix only).
LOAD_AT_START = os.getloadavg()[0] if hasattr(os, "getloadavg") else None


HULLS = Path(__file__).resolve().parents[1] / "examples" / "hulls"  # real hulls (see SOURCES.md there)


def quick() -> bool:
    """True for a short run: ``--quick`` on the script's command line or ``HULLOPT_BENCH_QUICK=1`` (run.py
    sets it for every script when given ``--quick``)."""
    return "--quick" in sys.argv[1:] or os.environ.get("HULLOPT_BENCH_QUICK", "") not in ("", "0")


def device() -> dict:
    """The device the benchmark ran on: jax's default backend and its first device (platform, kind)."""
    import jax

    d = jax.devices()[0]
    return {"backend": jax.default_backend(), "platform": d.platform, "kind": d.device_kind,
            "count": jax.device_count()}


def machine() -> dict:
    """Python, jax and jaxlib versions, CPU, cores, the load average at the start, the jax device, the date."""
    import jax
    import jaxlib

    return {
        "python": platform.python_version(),
        "jax": jax.__version__,
        "jaxlib": jaxlib.__version__,
        "cpu": platform.processor() or platform.machine(),
        "cores": os.cpu_count(),
        "load_at_start": None if LOAD_AT_START is None else round(LOAD_AT_START, 2),
        "device": device(),
        "quick": quick(),
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
    }


def goal(name: str, value, unit: str, target: str, met: bool | None, peer: str | None = None) -> dict:
    """One row of the summary table (benchmarks/run.py): what is measured, its value and unit, the goal as
    text (``"≤ 3"``), whether it is met (None: no pass/fail, a side-by-side figure) and the peer's figure."""
    return {"name": name, "value": value, "unit": unit, "target": target, "met": met, "peer": peer}


def run_process(cmd: list[str], cache: str | os.PathLike, ok: tuple[int, ...] = (0,)) -> float:
    """Wall time [s] of one whole ``hullopt`` process with its own cache folder ``cache``. It inherits this
    process's environment (a GPU machine's CUDA paths, XLA flags) and, when it exits with a code not in ``ok``,
    raises with that code and the end of its stderr: a benchmark never dies on an unexplained
    ``CalledProcessError``. With ``HULLOPT_BENCH_LOG`` set, each process's stderr is appended to that file (with
    ``JAX_LOG_COMPILES=1``: what it traced and compiled, and how long each took)."""
    import subprocess

    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=os.environ | {"HULLOPT_CACHE": str(cache)})
    dt = time.perf_counter() - t0
    if log := os.environ.get("HULLOPT_BENCH_LOG"):
        with open(log, "a") as f:
            f.write(f"$ {' '.join(map(str, cmd))}  # exit {p.returncode}, {dt:.1f} s\n{p.stderr}\n")
    if p.returncode not in ok:
        raise RuntimeError(f"{' '.join(map(str, cmd))} exited {p.returncode}:\n{p.stderr[-3000:]}")
    return dt


def timeit(fn, repeat: int = 7) -> float:
    """Median wall time [s] of ``fn()`` over ``repeat`` runs (after the caller's warm-up)."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def suffix() -> str:
    """``""`` on the CPU, else ``"-<backend>"`` (``"-gpu"``): a GPU run's results sit beside the CPU's."""
    import jax

    backend = jax.default_backend()
    return "" if backend == "cpu" else f"-{backend}"


def save(name: str, data: dict) -> Path:
    """Write ``results/<name><suffix>.json`` (:func:`suffix`: ``design.json`` on the CPU, ``design-gpu.json`` on
    a GPU): the machine info and ``data`` (which may hold ``"goals"``: a list of :func:`goal` rows for the
    summary table), atomically."""
    return _write(RESULTS / f"{name}{suffix()}.json", {"machine": machine(), **data})


def merge(name: str, data: dict) -> Path:
    """Merge a partial run's ``data`` into ``results/<name><suffix>.json``: its keys replace the file's, its
    ``"goals"`` replace the rows of the same name and each carries this run's date and load (``"when"``), while
    the file's other rows keep the machine they were measured on."""
    path = RESULTS / f"{name}{suffix()}.json"
    kept = json.loads(path.read_text()) if path.exists() else {"machine": machine(), "goals": []}
    m = machine()
    goals = [g | {"when": f"{m['date']}; load {m['load_at_start']}"} for g in data.get("goals", [])]
    names = {g["name"] for g in goals}
    return _write(path, kept | data | {"goals": [g for g in kept.get("goals", []) if g["name"] not in names] + goals})


def _write(path: Path, data: dict) -> Path:
    RESULTS.mkdir(exist_ok=True)
    tmp = path.with_suffix(".tmp")
    tmp.write_text(json.dumps(data, indent=2) + "\n")
    tmp.replace(path)
    return path
