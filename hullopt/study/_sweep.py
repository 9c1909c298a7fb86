"""Pareto sweeps at scale: fixed-size chunks, each solved as one jitted ``vmap`` sharded over the local
devices (:func:`hullopt.optimise.solve_pareto`, the library's ε-constraint sweep), written atomically to
``chunks/chunk_KKKK.json`` and skipped on a rerun (resume).

* ``shard=(k, N)`` solves only the chunks with ``index % N == k - 1`` (N machines, e.g. a Slurm array, split
  one sweep deterministically); :func:`merge` combines their run folders into the unsplit sweep's report.
* ``executor="dask"`` sends the chunks to a Dask cluster (``distributed.Client(address)``; an in-process
  ``LocalCluster`` when no address is given); the workers return the rows and the client writes the chunks,
  so the run folder need not be on a shared file system.

A chunk file holds ``key`` (a hash of the config without the solver's progress-irrelevant parts),
``index``, the sweep ``values`` and one row per value (see :meth:`SweepPlan.solve`).
"""

from __future__ import annotations

import functools
import hashlib
import json
import shutil
from collections.abc import Callable
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..errors import HullError
from ..geometry import atomic_write_bytes
from ..models import feature_hull
from ..optimise import TARGET_KINDS, make_targets, solve_pareto
from ._config import RunConfig
from ._problem import Problem, build_problem, params_to_dict
from ._programs import cached_call

PARTICULARS = ("volume", "cb", "lcb_pct", "cp", "cwp", "wetted_surface", "bwl", "lwl")


def parse_shard(text: str | None) -> tuple[int, int]:
    """A ``--shard`` option: ``"k/N"`` (1 ≤ k ≤ N) as ``(k, N)``.

    Parameters
    ----------
    text : str or None
        ``"k/N"``; None: no sharding.

    Returns
    -------
    tuple of (int, int)
        ``(k, N)``: this shard's number (from 1) and the number of shards; ``(1, 1)`` for None.

    Raises
    ------
    HullError
        When ``text`` is not ``k/N`` with integers 1 ≤ k ≤ N.
    """
    if text is None:
        return 1, 1
    try:
        k, n = (int(v) for v in text.split("/"))
    except ValueError:
        raise HullError(f"--shard {text!r}: expected k/N, e.g. 2/8") from None
    if not 1 <= k <= n:
        raise HullError(f"--shard {text!r}: expected 1 ≤ k ≤ N")
    return k, n


def sweep_key(cfg: RunConfig) -> str:
    """A hash of everything that changes a sweep's results (the whole config)."""
    return hashlib.sha256(json.dumps(cfg.model_dump(), sort_keys=True).encode()).hexdigest()[:16]


@functools.cache
def device_mesh() -> jax.sharding.Mesh:
    """A 1-D mesh ``("d",)`` over the local devices (CPU cores with ``jax_num_cpu_devices``). Auto axes:
    explicit sharding in types breaks optimistix's solvers."""
    devices = jax.local_devices()
    return jax.make_mesh((len(devices),), ("d",), axis_types=(jax.sharding.AxisType.Auto,), devices=devices)


def chunk_values(cfg: RunConfig, k: int) -> np.ndarray:
    """The Bf* of chunk ``k`` of a sweep."""
    sw = cfg.sweep
    return np.linspace(sw.start, sw.stop, sw.count)[k * sw.chunk: (k + 1) * sw.chunk]


def chunk_path(chunks: Path, k: int) -> Path:
    return chunks / f"chunk_{k:04d}.json"


def load_chunk(path: Path, key: str, values: np.ndarray) -> list[dict] | None:
    """The rows in ``path`` if it is a finished chunk of the sweep ``key`` at ``values``, else None."""
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if data.get("key") != key or np.shape(data.get("values")) != np.shape(values) \
            or not np.allclose(data["values"], values):
        return None
    return data["designs"]


class SweepPlan:
    """The ε-constraint sweep of a config: at each Bf* minimise the objective with the targets and
    Bf = Bf* held. ``values(k)`` are chunk k's Bf*, ``solve(k)`` its rows.

    With a ``program_key`` (the study's :attr:`~hullopt.study.Study.key`) a chunk on one device is solved by a
    kept program (:func:`~hullopt.study.cached_call`): a warm run loads it instead of tracing the solve again
    (~25 s on the KCS sweep), and ``ready()`` is called once it is traced (or loaded), before it compiles and
    runs the first chunk."""

    def __init__(self, cfg: RunConfig, prob: Problem, program_key: object = None,
                 ready: Callable[[], None] | None = None):
        sw = cfg.sweep
        targets = dict(cfg.targets) | {"bf": 0.5 * (sw.start + sw.stop)}
        tgt = make_targets(targets, cfg.tolerances, cfg.kg, cfg.hull.bf_band)
        self.cfg, self.prob = cfg, prob
        self.design = eqx.tree_at(lambda x: x.targets, prob.design, tgt)
        self.measure = sw.measure.build()
        self.chunk = sw.chunk
        self.n_chunks = -(-sw.count // sw.chunk)
        self.key = sweep_key(cfg)
        self.program_key, self.ready = program_key, ready

    def values(self, k: int) -> np.ndarray:
        return chunk_values(self.cfg, k)

    def solve(self, k: int, mesh=None) -> list[dict]:
        """Rows of chunk ``k``: ``bf_target``, ``objective``, ``measure``, ``met``, ``max_violation``,
        ``iterations``, ``params``, ``particulars``. The chunk is padded (with its last value) to a multiple
        of the device count, so every chunk has one shape and compiles once."""
        mesh = mesh or device_mesh()
        values = self.values(k)
        size = -(-self.chunk // mesh.size) * mesh.size
        padded = np.concatenate([values, np.full(size - len(values), values[-1])])
        c = self.cfg.solver
        args = (self.design, jnp.asarray(padded), self.prob.p0, self.prob.lower, self.prob.upper, self.measure)
        if mesh.size == 1 and self.program_key is not None:
            ready, self.ready = self.ready, None
            front = cached_call("sweep", _solve_chunk, args, (c.outer, c.max_steps), key=self.program_key,
                                ready=ready)
        else:  # several devices: a sharded jit, its compile from jax's cache (kept programs run on one device)
            starts = eqx.filter_jit(bow_starts)(*args[:5]) if np.size(self.prob.p0.bow) else None
            front = solve_pareto(self.design, "bf", *args[1:], outer=c.outer, max_steps=c.max_steps, mesh=mesh,
                                 starts=starts)
        front = jax.device_get(front)
        r, obj, meas, hd = front.result, front.objective, front.measure, front.hydrostatics.to_dict()
        return [{
            "bf_target": float(e),
            "objective": float(obj[i]),
            "measure": float(meas[i]),
            "met": bool(r.met[i]),
            "max_violation": float(r.max_violation[i]),
            "iterations": int(r.steps[i]),
            "params": params_to_dict(jax.tree.map(lambda a: a[i], r.params)),
            "particulars": {n: float(hd[n][i]) for n in PARTICULARS},
        } for i, e in enumerate(values)]

    def path(self, chunks: Path, k: int) -> Path:
        return chunk_path(chunks, k)

    def load(self, path: Path, k: int) -> list[dict] | None:
        return load_chunk(path, self.key, self.values(k))

    def write(self, chunks: Path, k: int, rows: list[dict]) -> None:
        data = {"key": self.key, "index": k, "values": self.values(k).tolist(), "designs": rows}
        atomic_write_bytes(self.path(chunks, k), (json.dumps(data, indent=2) + "\n").encode())


def bow_starts(design, values, p0, lower, upper, n: int = 65):
    """Each Bf* its start: ``p0`` with the first bow attachment's amplitude at the root of Bf(a) = Bf* nearest 0
    on the side that adds volume (a ≥ 0) for a blunter bow, takes it away (a ≤ 0) for a finer one.

    Bf(a) is not monotone: the attachment's rise aft of the nose first flattens the entrance (Bf falls), then
    the nose dominates; from the parent a gradient would take the run down the wrong branch (a finer
    shoulder). The root is found on ``n`` amplitudes across the bounds (linear between them).

    Parameters
    ----------
    design : Design
        The sweep's design (its model with a bow attachment, its draft, its targets' ``bf_band``).
    values : (k,) array
        The swept Bf* (dimensionless).
    p0, lower, upper : FeatureParams
        The start (the parent) and the bounds (``upper.bow[0]`` [m] spans the search).
    n : int
        Amplitudes tried across [−bound, bound] (static).

    Returns
    -------
    FeatureParams
        ``p0``'s structure with a leading axis k; the amplitude 0 (the parent) within the target's tolerance
        of the parent's Bf or where no amplitude reaches Bf*.
    """
    t = jnp.linspace(-1.0, 1.0, 2 * (n // 2) + 1) * upper.bow[0]
    mid = n // 2
    target = TARGET_KINDS["bf"]
    names = design.targets.names
    tol = design.targets.tol[names.index("bf")] if "bf" in names else target.tol

    def bf(a):
        p = eqx.tree_at(lambda q: q.bow, p0, jnp.asarray(p0.bow).at[0].set(a))
        return target.measure(*design.hull(p), band=design.targets.bf_band)

    b = jax.vmap(bf)(t)

    def root(e):
        up = e >= b[mid]
        tt = jnp.where(up, t[mid:], t[mid::-1])  # from 0 outward on the chosen side
        bb = jnp.where(up, b[mid:], b[mid::-1])
        hit = jnp.where(up, bb >= e, bb <= e)
        k = jnp.clip(jnp.argmax(hit), 1, tt.shape[0] - 1)
        f = jnp.clip((e - bb[k - 1]) / jnp.where(bb[k] == bb[k - 1], 1.0, bb[k] - bb[k - 1]), 0.0, 1.0)
        near = jnp.abs(e - b[mid]) <= tol  # the parent's own Bf: the parent
        return jnp.where(jnp.any(hit) & ~near, tt[k - 1] + f * (tt[k] - tt[k - 1]), 0.0)

    a = jax.vmap(root)(values)
    stacked = jax.tree.map(lambda x: jnp.broadcast_to(x, (values.shape[0], *jnp.shape(x))), p0)
    return eqx.tree_at(lambda q: q.bow, stacked, jnp.asarray(stacked.bow).at[:, 0].set(a))


def _solve_chunk(design, values, p0, lower, upper, measure, outer: int, max_steps: int):
    """:func:`~hullopt.optimise.solve_pareto` on Bf, as a kept program calls it; a design with a bow attachment
    starts each Bf* on its branch (:func:`bow_starts`)."""
    starts = bow_starts(design, values, p0, lower, upper) if np.size(p0.bow) else None
    return solve_pareto(design, "bf", values, p0, lower, upper, measure, outer=outer, max_steps=max_steps,
                        starts=starts)


def run_chunks(plan: SweepPlan, out: Path, shard=(1, 1), executor: str = "local", address: str | None = None,
               progress=None) -> list[dict] | None:
    """Solve this shard's missing chunks into ``out/chunks``; all the sweep's rows in order when every chunk
    is there (from any shard), else None. ``progress(done)`` is called after each chunk."""
    chunks = out / "chunks"
    chunks.mkdir(parents=True, exist_ok=True)
    k_shard, n_shard = shard
    mine = [k for k in range(plan.n_chunks) if k % n_shard == k_shard - 1]
    todo = [k for k in mine if plan.load(plan.path(chunks, k), k) is None]
    if progress:
        progress(len(mine) - len(todo))
    if executor == "dask":
        _run_dask(plan, chunks, todo, address, progress)
    elif executor == "local":
        for k in todo:
            plan.write(chunks, k, plan.solve(k))
            if progress:
                progress(1)
    else:
        raise HullError(f"--executor {executor!r}: expected local or dask")
    rows = [plan.load(plan.path(chunks, k), k) for k in range(plan.n_chunks)]
    if any(r is None for r in rows):
        return None
    return [d for r in rows for d in r]


# ----------------------------------------------------------------------------------------------- dask


@functools.lru_cache(maxsize=4)
def _worker_plan(task_json: str) -> SweepPlan:
    task = json.loads(task_json)
    cfg = RunConfig.model_validate(task["config"])
    p = task["parent"]
    parent = feature_hull(p, p["name"], p["design_draft"], p["q"])
    return SweepPlan(cfg, build_problem(cfg, parent, task["fairness"], True), task["program_key"])


def _dask_chunk(task_json: str, k: int) -> list[dict]:
    """A Dask task: chunk ``k`` of the sweep of a config on a parent (as JSON), solved on the worker's devices."""
    jax.config.update("jax_enable_x64", True)  # a fresh worker process; a no-op in the client's
    return _worker_plan(task_json).solve(k)


def _run_dask(plan: SweepPlan, chunks: Path, todo: list[int], address: str | None, progress) -> None:
    try:
        from distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise HullError("--executor dask needs Dask: pip install 'dask[distributed]'") from None
    if not todo:
        return
    cluster = None
    try:
        if address:
            try:
                client = Client(address, timeout="20s")
            except OSError as e:
                raise HullError(f"--address {address}: cannot reach the Dask scheduler ({e})") from None
        else:
            cluster = LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None)
            client = Client(cluster)
        with client:
            task = {"config": plan.cfg.model_dump(), "parent": plan.prob.design.model.hull.to_dict(),
                    "fairness": float(plan.prob.design.fairness), "program_key": plan.program_key}
            task_json = json.dumps(task, sort_keys=True)
            futures = {client.submit(_dask_chunk, task_json, k, pure=False): k for k in todo}
            for fut in as_completed(futures):
                plan.write(chunks, futures[fut], fut.result())
                if progress:
                    progress(1)
    finally:
        if cluster is not None:
            cluster.close()


# ----------------------------------------------------------------------------------------------- merge


def collect_chunks(dirs: list[Path], out: Path) -> tuple[RunConfig, dict]:
    """Copy the chunks of the run folders ``dirs`` (shards of one sweep) into ``out/chunks``.

    Parameters
    ----------
    dirs : list of pathlib.Path
        The shards' run folders.
    out : pathlib.Path
        The merged run folder (its ``chunks`` folder created when missing).

    Returns
    -------
    tuple of (RunConfig, dict)
        The sweep's config and its raw config (the first folder's ``config.json``).

    Raises
    ------
    HullError
        When no folders are given, a folder has no readable or valid ``config.json``, the config is not a sweep,
        the folders hold different sweeps, or a chunk is in none of them.
    """
    if not dirs:
        raise HullError("merge: give the run folders of the shards")
    raws = []
    for d in dirs:
        try:
            raws.append(json.loads((d / "config.json").read_text()))
        except (OSError, ValueError):
            raise HullError(f"{d}: not a run folder (no readable config.json)") from None
    try:
        cfgs = [RunConfig.model_validate(r) for r in raws]
    except ValueError as e:
        raise HullError(f"merge: a config.json is not a valid run config ({e})") from None
    cfg = cfgs[0]
    if cfg.kind != "pareto":
        raise HullError(f"{dirs[0]}: not a sweep (kind = {cfg.kind!r})")
    key = sweep_key(cfg)
    for d, c in zip(dirs[1:], cfgs[1:]):
        if sweep_key(c) != key:
            raise HullError(f"{d}: a different sweep config from {dirs[0]}")
    n_chunks = -(-cfg.sweep.count // cfg.sweep.chunk)
    (out / "chunks").mkdir(parents=True, exist_ok=True)
    missing = []
    for k in range(n_chunks):
        values = chunk_values(cfg, k)
        src = next((chunk_path(d / "chunks", k) for d in dirs
                    if load_chunk(chunk_path(d / "chunks", k), key, values) is not None), None)
        if src is None:
            missing.append(k)
        elif src.resolve() != chunk_path(out / "chunks", k).resolve():
            shutil.copyfile(src, chunk_path(out / "chunks", k))
    if missing:
        raise HullError(f"merge: chunk(s) {', '.join(map(str, missing))} of {n_chunks} are in none of the folders "
                        "(run the missing shards first)")
    return cfg, raws[0]
