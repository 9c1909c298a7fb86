"""The Pareto (ε-constraint) sweep as one computation: at each value of a swept target, minimise the objective
with every target held (:func:`~hullopt.optimise.solve_minimum`), all values in one ``vmap`` — optionally
sharded over a device mesh.

This is the library's route to a Pareto front; ``hullopt run`` with ``kind = "pareto"`` (``app/sweep.py``)
cuts the values into chunks, writes them to files, resumes, splits them across machines or Dask workers and
calls :func:`solve_pareto` for each chunk.
"""

from __future__ import annotations

from collections.abc import Callable

import equinox as eqx
import jax
import jax.numpy as jnp
from jax.sharding import PartitionSpec as P
from jaxtyping import Array, ArrayLike, Float

from ..hydro import Hydrostatics, hydrostatics
from ._problems import Design, solve_minimum, with_objective_scale
from ._solvers import SolveResult


class ParetoResult(eqx.Module):
    """The designs of an ε-constraint sweep, each field batched over the ``k`` swept values.

    Attributes
    ----------
    values : Array, shape (k,)
        The swept target's values (as :func:`~hullopt.optimise.make_targets` takes them: SI, coefficients
        dimensionless).
    result : SolveResult
        The solves, each leaf with a leading axis ``k`` (``params``, ``met``, ``max_violation``, ``steps``…).
    objective : Array, shape (k,)
        The objective of each design, unscaled, in its own units.
    measure : Array, shape (k,), or None
        ``measure(sections, draft)`` of each design, when a measure was given.
    hydrostatics : Hydrostatics
        The upright hydrostatics of each design at the design draft (each field shape (k,)).
    """

    values: Float[Array, " k"]
    result: SolveResult
    objective: Float[Array, " k"]
    measure: Float[Array, " k"] | None
    hydrostatics: Hydrostatics


def _solve_one(d: Design, measure, p0, lower, upper, e, i: int, outer: int, max_steps: int):
    de = eqx.tree_at(lambda x: x.targets.values, d, d.targets.values.at[i].set(e))
    r = solve_minimum(de, p0, lower, upper, outer=outer, max_steps=max_steps)
    s = de.model(r.params)
    m = None if measure is None else measure(s, de.draft)
    return r, de.objective(s, de.draft), m, hydrostatics(s, de.draft)


@eqx.filter_jit
def solve_pareto(design: Design, target: str, values: ArrayLike, p0, lower, upper,
                 measure: Callable | None = None, *, outer: int = 10, max_steps: int = 300,
                 mesh: jax.sharding.Mesh | None = None, starts=None) -> ParetoResult:
    """Solve an ε-constraint (Pareto) sweep: minimise the objective at each value of one target.

    At each of the ``k`` values the target ``target`` of ``design`` is set to it and
    :func:`~hullopt.optimise.solve_minimum` minimises ``design.objective`` with all the targets held (the
    objective scaled by its value at ``p0``). The ``k`` solves are one jitted ``vmap``; with a ``mesh`` its
    batch is split over the mesh's devices (sharding constraints; XLA partitions the computation). Calls
    with the same design structure, shapes and static arguments share one compiled program.

    Parameters
    ----------
    design : Design
        The problem, with an ``objective`` and ``target`` among its targets (the value it holds there is
        replaced by each swept value).
    target : str
        Name of the swept target in ``design.targets.names`` (e.g. ``"bf"``, ``"volume"``).
    values : Array, shape (k,)
        The swept target's values, in the units :func:`~hullopt.optimise.make_targets` takes (SI; Bf and
        coefficients dimensionless); with a ``mesh``, ``k`` a multiple of ``mesh.size``.
    p0, lower, upper : pytree of Array
        Start and bounds of the parameters (same structure; ``lower < p0 < upper``).
    measure : callable, optional
        ``measure(sections, draft) → Array ()`` recorded for each design (e.g. the sweep's Bf).
    outer, max_steps : int, optional
        Augmented-Lagrangian rounds and BFGS steps per round (static).
    mesh : jax.sharding.Mesh, optional
        A 1-D mesh with axis ``"d"`` to shard the values over (e.g. ``jax.make_mesh((n,), ("d",))``);
        default: no sharding constraint.
    starts : pytree of Array, optional
        Each value's start, ``p0``'s structure with a leading axis ``k`` (e.g. a design variable seeded on the
        branch that reaches the value, :func:`~hullopt.study.bow_starts`); default ``p0`` for every value (the
        objective's scale is ``p0``'s either way).

    Returns
    -------
    ParetoResult
        ``values``, ``result`` (:class:`~hullopt.optimise.SolveResult`), ``objective``, ``measure`` and
        ``hydrostatics`` (:class:`~hullopt.hydro.Hydrostatics`), each batched over ``k``.

    Examples
    --------
    Sweep the volume of a Wigley whose beam is scaled by ``1 + p``: 1.1 and 1.2 times the parent's volume
    need ``p`` = 0.1 and 0.2, i.e. a beam of 11 and 12 m:

    >>> import jax; jax.config.update("jax_enable_x64", True)
    >>> import jax.numpy as jnp
    >>> from hullopt.geometry import Sections
    >>> from hullopt.models import wigley
    >>> from hullopt.hydro import hydrostatics
    >>> from hullopt.optimise import Design, KAw, make_targets, solve_pareto
    >>> hull = wigley(100, 10, 6.25, 10, n=21, m=21)
    >>> def model(p):
    ...     return Sections(hull.x, hull.yz * jnp.array([1.0 + p, 1.0]), hull.lpp)
    >>> v0 = float(jax.jit(hydrostatics)(hull, 6.25).volume)
    >>> design = Design(model=model, draft=6.25, targets=make_targets({"volume": v0}),
    ...                 objective=KAw(speed=jnp.asarray(7.7)))
    >>> beam = lambda s, draft: hydrostatics(s, draft).bwl
    >>> front = solve_pareto(design, "volume", jnp.array([1.1, 1.2]) * v0, jnp.asarray(0.0),
    ...                      jnp.asarray(-0.5), jnp.asarray(0.5), beam, outer=3, max_steps=100)
    >>> [round(float(p), 4) for p in front.result.params], [round(float(b), 3) for b in front.measure]
    ([0.1, 0.2], [11.0, 12.0])
    """
    if target not in design.targets.names:
        raise ValueError(f"target {target!r} is not one of the design's targets ({', '.join(design.targets.names)})")
    i = design.targets.names.index(target)
    values = jnp.asarray(values, dtype=design.targets.values.dtype)
    if values.ndim != 1:
        raise ValueError(f"values: expected a 1-D array of the swept target's values, got shape {values.shape}")
    if mesh is not None and values.shape[0] % mesh.size:
        raise ValueError(f"values: {values.shape[0]} values do not split over the mesh's {mesh.size} devices "
                         "(pad them to a multiple)")
    d = with_objective_scale(design, p0)

    def constrain(tree):
        if mesh is None:
            return tree
        batch = jax.sharding.NamedSharding(mesh, P("d"))
        return jax.tree.map(lambda a: jax.lax.with_sharding_constraint(a, batch), tree)

    values = constrain(values)
    if starts is None:
        starts = jax.tree.map(lambda a: jnp.broadcast_to(a, (values.shape[0], *jnp.shape(a))), p0)
    r, objective, m, h = constrain(
        jax.vmap(lambda e, s: _solve_one(d, measure, s, lower, upper, e, i, outer, max_steps))(values, starts))
    return ParetoResult(values=values, result=r, objective=objective, measure=m, hydrostatics=h)
