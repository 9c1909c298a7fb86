"""Pareto sweeps at scale: fixed-size chunks, each solved as one jitted ``vmap`` sharded over the local
devices, written atomically to ``chunks/chunk_KKKK.json`` and skipped on a rerun (resume).

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
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.sharding import PartitionSpec as P

from ..errors import HullError
from ..hydro import hydrostatics
from ..optimise import Design, make_targets, solve_minimum, with_objective_scale
from .config import RunConfig
from .output import write_json

PARTICULARS = ("volume", "cb", "lcb_pct", "cp", "cwp", "wetted_surface", "bwl", "lwl")


def parse_shard(text: str | None) -> tuple[int, int]:
    """``"k/N"`` (1 ≤ k ≤ N) → ``(k, N)``; ``None`` → ``(1, 1)``."""
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


def _solve_one(d: Design, measure, p0, lower, upper, e, i_bf: int, outer: int, max_steps: int):
    de = eqx.tree_at(lambda x: x.targets.values, d, d.targets.values.at[i_bf].set(e))
    r = solve_minimum(de, p0, lower, upper, outer=outer, max_steps=max_steps)
    s = de.model(r.params)
    return r, de.objective(s, de.draft), measure(s, de.draft), hydrostatics(s, de.draft)


@eqx.filter_jit
def solve_values(problem, values, i_bf: int, outer: int, max_steps: int, mesh):
    """Solve the sweep at ``values (k,)`` (k a multiple of the mesh size) as one ``vmap``, its batch split
    over the mesh's devices (sharding constraints; XLA partitions the computation). ``problem = (design,
    measure, p0, lower, upper)``. Module level, so the runs of one process share the compiled function.

    The Python route of the Pareto (ε-constraint) sweep: at each value the target ``i_bf`` is set to it and
    :func:`~hullopt.optimise.solve_minimum` minimises the objective with the targets held.

    Parameters
    ----------
    problem : tuple
        ``(design, measure, p0, lower, upper)``: a :class:`~hullopt.optimise.Design` with an objective,
        ``measure(sections, draft)`` a scalar recorded per design (the sweep's Bf), and the start and bounds
        of the parameters (pytrees).
    values : Array, shape (k,)
        The swept target's values, in its units (SI; Bf dimensionless); ``k`` a multiple of the mesh size.
    i_bf : int
        Index of the swept target in ``design.targets.names``.
    outer, max_steps : int
        Augmented-Lagrangian rounds and BFGS steps per round.
    mesh : jax.sharding.Mesh
        A 1-D mesh with axis ``"d"`` (:func:`device_mesh`).

    Returns
    -------
    tuple
        ``(result, objective, measure, hydrostatics)``, each batched over ``k``: the
        :class:`~hullopt.optimise.SolveResult`, the objective (unscaled, its units), the measure and the
        :class:`~hullopt.hydro.Hydrostatics` of each design.

    Examples
    --------
    Sweep the volume (target 0) of a Wigley whose beam is scaled by ``1 + p``: 1.1 and 1.2 times the parent's
    volume need ``p`` = 0.1 and 0.2, i.e. a beam of 11 and 12 m:

    >>> import jax; jax.config.update("jax_enable_x64", True)
    >>> import jax.numpy as jnp
    >>> from hullopt.geometry import Sections
    >>> from hullopt.models import wigley
    >>> from hullopt.hydro import hydrostatics
    >>> from hullopt.optimise import Design, KAw, make_targets
    >>> from hullopt.app.sweep import solve_values
    >>> hull = wigley(100, 10, 6.25, 10, n=21, m=21)
    >>> def model(p):
    ...     return Sections(hull.x, hull.yz * jnp.array([1.0 + p, 1.0]), hull.lpp)
    >>> v0 = float(jax.jit(hydrostatics)(hull, 6.25).volume)
    >>> design = Design(model=model, draft=6.25, targets=make_targets({"volume": v0}),
    ...                 objective=KAw(speed=jnp.asarray(7.7)))
    >>> beam = lambda s, draft: hydrostatics(s, draft).bwl
    >>> problem = (design, beam, jnp.asarray(0.0), jnp.asarray(-0.5), jnp.asarray(0.5))
    >>> mesh = jax.sharding.Mesh(jax.devices()[:1], ("d",))
    >>> r, objective, b, h = solve_values(problem, jnp.array([1.1, 1.2]) * v0, 0, 3, 100, mesh)
    >>> [round(float(p), 4) for p in r.params], [round(float(x), 3) for x in b]
    ([0.1, 0.2], [11.0, 12.0])
    """
    d, measure, p0, lower, upper = problem
    d = with_objective_scale(d, p0)
    batch = jax.sharding.NamedSharding(mesh, P("d"))
    values = jax.lax.with_sharding_constraint(values, batch)
    out = jax.vmap(lambda e: _solve_one(d, measure, p0, lower, upper, e, i_bf, outer, max_steps))(values)
    return jax.tree.map(lambda a: jax.lax.with_sharding_constraint(a, batch), out)


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
    Bf = Bf* held. ``values(k)`` are chunk k's Bf*, ``solve(k)`` its rows."""

    def __init__(self, cfg: RunConfig, prob):
        from .run import objective_from

        sw = cfg.sweep
        targets = dict(cfg.targets) | {"bf": 0.5 * (sw.start + sw.stop)}
        tgt = make_targets(targets, cfg.tolerances, cfg.kg)
        self.cfg, self.prob = cfg, prob
        self.design = eqx.tree_at(lambda x: x.targets, prob.design, tgt)
        self.i_bf = tgt.names.index("bf")
        self.measure = objective_from(sw.measure)
        self.chunk = sw.chunk
        self.n_chunks = -(-sw.count // sw.chunk)
        self.key = sweep_key(cfg)

    def values(self, k: int) -> np.ndarray:
        return chunk_values(self.cfg, k)

    def solve(self, k: int, mesh=None) -> list[dict]:
        """Rows of chunk ``k``: ``bf_target``, ``objective``, ``measure``, ``met``, ``max_violation``,
        ``iterations``, ``params``, ``particulars``. The chunk is padded (with its last value) to a multiple
        of the device count, so every chunk has one shape and compiles once."""
        from .run import _params_dict

        mesh = mesh or device_mesh()
        values = self.values(k)
        size = -(-self.chunk // mesh.size) * mesh.size
        padded = np.concatenate([values, np.full(size - len(values), values[-1])])
        c = self.cfg.solver
        problem = (self.design, self.measure, self.prob.p0, self.prob.lower, self.prob.upper)
        r, obj, meas, h = jax.device_get(solve_values(problem, jnp.asarray(padded), self.i_bf, c.outer,
                                                      c.max_steps, mesh))
        hd = h.to_dict()
        return [{
            "bf_target": float(e),
            "objective": float(obj[i]),
            "measure": float(meas[i]),
            "met": bool(r.met[i]),
            "max_violation": float(r.max_violation[i]),
            "iterations": int(r.steps[i]),
            "params": _params_dict(jax.tree.map(lambda a: a[i], r.params)),
            "particulars": {n: float(hd[n][i]) for n in PARTICULARS},
        } for i, e in enumerate(values)]

    def path(self, chunks: Path, k: int) -> Path:
        return chunk_path(chunks, k)

    def load(self, path: Path, k: int) -> list[dict] | None:
        return load_chunk(path, self.key, self.values(k))

    def write(self, chunks: Path, k: int, rows: list[dict]) -> None:
        write_json(self.path(chunks, k), {"key": self.key, "index": k, "values": self.values(k).tolist(),
                                          "designs": rows})


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
def _worker_plan(raw_json: str) -> SweepPlan:
    from .run import build_problem

    cfg = RunConfig.model_validate(json.loads(raw_json))
    return SweepPlan(cfg, build_problem(cfg))


def _dask_chunk(raw_json: str, k: int) -> list[dict]:
    """A Dask task: chunk ``k`` of the sweep of a config (as JSON), solved on the worker's devices."""
    jax.config.update("jax_enable_x64", True)  # a fresh worker process; a no-op in the client's
    return _worker_plan(raw_json).solve(k)


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
            raw_json = json.dumps(plan.cfg.model_dump(), sort_keys=True)
            futures = {client.submit(_dask_chunk, raw_json, k, pure=False): k for k in todo}
            for fut in as_completed(futures):
                plan.write(chunks, futures[fut], fut.result())
                if progress:
                    progress(1)
    finally:
        if cluster is not None:
            cluster.close()


# ----------------------------------------------------------------------------------------------- merge


def collect_chunks(dirs: list[Path], out: Path) -> tuple[RunConfig, dict]:
    """Copy the chunks of the run folders ``dirs`` (shards of one sweep) into ``out/chunks``; returns the
    sweep's config and raw config. :class:`HullError` when the folders hold different sweeps or a chunk is
    in none of them."""
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
