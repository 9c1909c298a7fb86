"""Design studies: one class per run kind (``fit``, ``minimise``, ``pareto``), like the objectives. A study is
built from a validated :class:`~hullopt.study.RunConfig` and the parent's feature curves; ``solve`` returns a
:class:`Solution` (the report's data, the parent and final hull measured, the designs to assess). Writing files
and printing are the app's.

Defining a subclass with a ``kind`` registers it in :data:`STUDIES`.
"""

from __future__ import annotations

import abc
import dataclasses
import functools
import hashlib
import json
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..geometry import Sections
from ..fairing import WATERLINES_ABOVE, waterlines
from ..hydro import Hydrostatics, hydrostatics, sectional_areas
from ..models import FeatureHull, FeatureParams
from ..optimise import (
    Design,
    achieved,
    non_dominated,
    solve_fit,
    solve_minimum,
    target_errors,
    with_objective_scale,
)
from ._assess import assess, assess_program
from ._config import FAIRNESS, RunConfig
from ._problem import (
    Problem,
    bound_warnings,
    build_problem,
    params_from_dict,
    params_to_dict,
    stack_params,
    stacked_like,
)
from ._programs import cached_call, prepare_call, programs_dir
from ._rescore import rescore, rescore_program
from ._sweep import SweepPlan, run_chunks

STUDIES: dict[str, type[Study]] = {}
"""The studies by run kind (the config's ``kind``), filled by defining a subclass of :class:`Study`."""

VIOLATION = "max constraint violation |residual| / tolerance"
MERIT = "merit: objective + fairness and smoothness penalties"
"""The name of the constraint-violation series in a study's history (≤ 1: met)."""


class Outcome(eqx.Module):
    """Everything a run folder shows of a parent and a final design, computed in one jitted program."""

    before: Sections  # the parent
    after: Sections  # the final design
    parent: Hydrostatics  # of the parent at the draft
    final: Hydrostatics  # of the final design
    achieved: Float[Array, " t"]  # the target particulars of the final design
    errors: Float[Array, " t"]  # ... their errors (optimise.target_errors: the solvers' residuals, normalised units)
    areas: Float[Array, "2 n"]  # sectional-area curves [m²]: parent, final
    levels: Float[Array, " h"]  # the heights [m] of the waterlines below (fairing.waterlines)
    widths: Float[Array, "2 n h"]  # the waterlines' half-breadths [m]: parent, final
    objective: Float[Array, ""] | None  # the objective of the final design (None without one)
    objective_parent: Float[Array, ""] | None  # ... and of the parent


def measure(d: Design, p0: FeatureParams, final: FeatureParams) -> Outcome:
    """The :class:`Outcome` of the parameters ``p0`` (the parent) and ``final``, each at its own draft
    (:meth:`~hullopt.optimise.Design.hull`: a draft scale floats a design deeper or shallower; the waterlines
    compared at the parent's heights)."""
    (before, t0), (after, t1) = d.hull(p0), d.hull(final)
    h0, h1 = hydrostatics(before, t0), hydrostatics(after, t1)
    areas = jnp.stack([sectional_areas(before, t0), sectional_areas(after, t1)])
    levels, widths = waterlines([before, after], t0, above=WATERLINES_ABOVE)
    obj = (d.objective(after, t1), d.objective(before, t0)) if d.objective is not None else (None, None)
    a = achieved(h1, after, d.targets.names, d.targets.kg, d.targets.bf_band)
    return Outcome(before, after, h0, h1, a, target_errors(a, d.targets), areas, levels, jnp.stack(widths), *obj)


@dataclass
class Solution:
    """What a study's solve found.

    ``report``: the JSON-able results (``kind``, ``converged``, ``met``, ``iterations``, …; see
    :func:`hullopt.app.run.run`, which writes it as ``report.json``); ``outcome``: the parent and the final design measured (a sweep: the parent
    twice); ``designs``: the parameters of the designs to assess and write (one, or the sweep's); ``final``:
    whether there is one final hull (a sweep's hulls are its designs); ``partial``: a shard of a sweep whose other
    chunks are not done yet (nothing to assess or write); ``outcomes``: a sweep's designs measured
    (:func:`design_outcomes`), for their files."""

    report: dict
    outcome: Outcome | None
    designs: list[FeatureParams] = field(default_factory=list)
    final: bool = True
    partial: bool = False
    outcomes: list[Outcome] = field(default_factory=list)


def _digest(parent: FeatureHull) -> str:
    """The parent's content, for the keys of the kept programs."""
    return hashlib.sha256(json.dumps(parent.to_dict(), sort_keys=True).encode()).hexdigest()


_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def structure(cfg: RunConfig) -> dict:
    """The config as a kept program depends on it.

    The numbers of the targets, tolerances, kg, the draft, the objective, the sweep's ends and the constraint
    bounds enter the programs as arrays: each is replaced by ``"#"``, so a run with other numbers reuses the
    program. The design's and the solver's sections, which the programs close over, and every count (an
    array's shape) stay as they are. What else a program bakes in is read off its arguments
    (:func:`hullopt.study.cached_call`).

    Parameters
    ----------
    cfg : RunConfig
        The run config.

    Returns
    -------
    dict
        Its JSON dump with those numbers blanked.
    """
    def blank(v, in_text: bool):
        if isinstance(v, dict):
            return {k: blank(x, in_text) for k, x in v.items()}
        if isinstance(v, list):
            return [blank(x, in_text) for x in v]
        if isinstance(v, float):
            return "#"
        if isinstance(v, str) and in_text:
            return _NUMBER.sub("#", v)
        return v

    d = cfg.model_dump(mode="json")
    return {k: v if k in ("design", "solver", "kind") else blank(v, k == "constraints") for k, v in d.items()}


class Study(abc.ABC):
    """A design study of a config on a parent: :attr:`problem` (the :class:`~hullopt.study.Problem`),
    :meth:`solve`, and the second look at its designs (:meth:`assess`, :meth:`rescore`). Subclasses set ``kind`` (the config's), ``title`` (what the progress display shows),
    ``limits`` (whether ``[constraints]`` hold) and ``fairness`` (the default fairness weight)."""

    kind: ClassVar[str]
    title: ClassVar[str]
    limits: ClassVar[bool] = True
    fairness: ClassVar[float] = FAIRNESS

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        if "kind" in cls.__dict__:
            STUDIES[cls.kind] = cls

    def __init__(self, cfg: RunConfig, parent: FeatureHull):
        self.cfg = cfg
        fairness = self.fairness if cfg.solver.fairness is None else cfg.solver.fairness
        self.problem: Problem = build_problem(cfg, parent, fairness, self.limits)
        self.key = [structure(cfg), _digest(parent)]  # what a kept program depends on besides its arrays

    @abc.abstractmethod
    def solve(self, out: Path, progress: Callable[[int], None] | None = None, **options) -> Solution:
        """Solve the study; ``out`` the run folder (a sweep keeps its chunks there), ``progress(n)`` told of
        ``n`` more units of work done (a sweep's chunks), ``options`` the kind's (a sweep's shard, executor,
        address)."""

    def units(self, options: dict) -> int | None:
        """How many units of work :meth:`solve` reports to ``progress`` (None: one, uncounted)."""
        return None

    def final_params(self, report: dict, design: int = -1) -> tuple[FeatureParams, str]:
        """The parameters of a finished run's design (its report's ``params``; a sweep: design ``design``) and a
        label for it; ``ValueError`` when the report has none."""
        if design != -1:
            raise ValueError(f"?design applies to sweeps; this is a {self.kind!r} run")
        if "params" not in report:
            raise ValueError("the report has no params (an unfinished run?)")
        return params_from_dict(report["params"], self.problem.p0), ""

    def assess(self, solution: Solution) -> tuple[dict, dict, list[str]]:
        """The report's ``objectives``, ``limits`` and ``warnings`` of a solution's designs
        (:func:`~hullopt.study.assess`, plus parameters stopped by their bounds)."""
        objectives, limits, warnings = assess(self.cfg, self.problem, solution.designs, self.key)
        who = "" if solution.final else "design {k}: "
        return objectives, limits, bound_warnings(self.problem, solution.designs, who) + warnings

    def rescore(self, designs: list[FeatureParams]) -> tuple[dict | None, list[str]]:
        """The designs and the parent re-scored by every method of each kind (:func:`~hullopt.study.rescore`);
        ``(None, [])`` for a study without an objective."""
        if self.cfg.objective is None:
            return None, []
        return rescore(self.cfg, self.problem, designs, self.key)

    def designs_of(self, report: dict) -> list[FeatureParams]:
        """The parameters of a finished run's designs (its report's ``params``, or each of a sweep's)."""
        rows = report.get("designs") or [report]
        return [params_from_dict(r["params"], self.problem.p0) for r in rows if "params" in r]


class _Single(Study):
    """A study with one final design, solved and measured in one kept program."""

    @abc.abstractmethod
    def _solve(self, d: Design, p0, lower, upper):
        """The solver's result (a :class:`~hullopt.optimise.SolveResult`) from ``p0`` within the bounds."""

    @abc.abstractmethod
    def history(self, result) -> dict:
        """``{"iteration": label, "series": {name: values}}``: what the solver recorded, for the report's plot."""

    def _program(self, d: Design, p0, lower, upper):
        d = with_objective_scale(d, p0)
        res = self._solve(d, p0, lower, upper)
        return res, measure(d, p0, res.params)

    def solve(self, out: Path, progress=None, **options) -> Solution:
        prob = self.problem
        d = prob.design
        res, m = jax.device_get(cached_call(f"run-{self.kind}", self._program, (d, prob.p0, prob.lower, prob.upper),
                                            (), key=self.key, quick="classic"))
        met = bool(res.met)
        report = {
            "kind": self.kind,
            "converged": bool(res.solver_ok) and met,
            "met": met,
            "iterations": int(res.steps),
            "max_violation": float(res.max_violation),
            "targets": target_report(d, m.achieved, m.errors),
            "params": params_to_dict(res.params),
        }
        if d.objective is not None:
            report["objective"] = {"name": d.objective.name, "value": float(m.objective),
                                   "parent": float(m.objective_parent)}
        if not met:
            worst = max(report["targets"].items(), key=lambda kv: abs(kv[1]["error"]) / kv[1]["tolerance"])
            report["message"] = (f"the targets cannot be met within the bounds: {worst[0]} is off by "
                                 f"{worst[1]['error']:.3g} (tolerance {worst[1]['tolerance']:.3g}); "
                                 "the closest design found is saved")
        report["history"] = self.history(res)
        return Solution(report, m, [res.params])


def _series(values) -> list:
    """Recorded values as a JSON list (steps not taken, NaN, as None)."""
    return [None if not np.isfinite(v) else float(v) for v in np.asarray(values, float).ravel()]


class Fit(_Single):
    """Deform the parent the least needed to meet the targets (Levenberg–Marquardt, or L-BFGS-B with `[solver]
    method = "lbfgsb"`; no constraints)."""

    kind: ClassVar[str] = "fit"
    title: ClassVar[str] = "fit"
    limits: ClassVar[bool] = False
    fairness: ClassVar[float] = 0.0
    SOLVERS: ClassVar[dict[str, str]] = {"optimistix": "Levenberg–Marquardt", "lbfgsb": "L-BFGS-B"}

    def __init__(self, cfg: RunConfig, parent: FeatureHull):
        super().__init__(cfg, parent)
        self.solver = self.SOLVERS[cfg.solver.method]
        self.title = f"fit ({self.solver})"

    def _solve(self, d, p0, lower, upper):
        return solve_fit(d, p0, lower, upper, traced=True, max_steps=self.cfg.solver.max_steps,
                         method=self.cfg.solver.method)

    def history(self, result) -> dict:
        """The cost Σ (residual / tolerance)² (the smoothness penalty in it: it does not fall to zero) and the
        largest target error / tolerance (≤ 1: met) at the start and after each step of the solver."""
        return {"iteration": f"{self.solver} step",
                "series": {"cost Σ (residual / tolerance)²": _series(result.history),
                           VIOLATION: _series(result.violation_history)}}


class Minimise(_Single):
    """Minimise the objective with the targets and ``[constraints]`` held (augmented Lagrangian)."""

    kind: ClassVar[str] = "minimise"
    title: ClassVar[str] = "minimise (augmented Lagrangian)"

    def _solve(self, d, p0, lower, upper):
        c = self.cfg.solver
        return solve_minimum(d, p0, lower, upper, outer=c.outer, max_steps=c.max_steps)

    def history(self, result) -> dict:
        """The objective (scaled to 1 at the parent), the merit the solver minimises (the objective plus the fairness
        and smoothness penalties, 1 + fairness at the parent) and the largest constraint violation after each
        round."""
        return {"iteration": "augmented-Lagrangian round",
                "series": {"objective / parent's": _series(result.objective_history),
                           MERIT: _series(result.merit_history),
                           VIOLATION: _series(result.violation_history)}}


class Pareto(Study):
    """An ε-constraint sweep on Bf: at each Bf* of ``[sweep]`` minimise the objective with the targets and
    Bf = Bf* held, in resumable chunks (:mod:`hullopt.study._sweep`); the front of the sweep's measure against
    the objective."""

    kind: ClassVar[str] = "pareto"
    title: ClassVar[str] = "Pareto sweep"

    def prepare(self, n: int) -> None:
        """Start building the programs that assess, re-score and measure ``n`` designs (and the parent) on
        background threads (:func:`~hullopt.study.prepare_call`), to trace and compile on the core the chunks'
        solve leaves free. Nothing without kept programs (the persistent compilation cache off: the Python API's
        default)."""
        if programs_dir() is None:
            return
        stacked = stacked_like(self.problem.p0, n)
        prepare_call(*assess_program(self.cfg, self.problem, stacked, self.key))
        prepare_call(*rescore_program(self.cfg, self.problem, stacked, self.key)[0])
        prepare_call(*_outcomes_program(self, stacked_like(self.problem.p0, n + 1)))

    def units(self, options: dict) -> int:
        k, n = options.get("shard", (1, 1))
        return len(range(k - 1, SweepPlan(self.cfg, self.problem).n_chunks, n))

    def final_params(self, report: dict, design: int = -1) -> tuple[FeatureParams, str]:
        designs = report.get("designs", [])
        if not 0 <= design < len(designs):
            raise ValueError(f"a sweep's run folder needs ?design=K with K in 0…{len(designs) - 1}")
        return params_from_dict(designs[design]["params"], self.problem.p0), f" design {design}"

    def solve(self, out: Path, progress=None, shard=(1, 1), executor: str = "local",
              address: str | None = None) -> Solution:
        cfg, prob = self.cfg, self.problem
        # a run that ends with every design builds its last programs once the chunks' is traced: they trace
        # while it compiles and compile while it runs, which leave the GIL and a core free
        ready = functools.partial(self.prepare, cfg.sweep.count) if shard == (1, 1) else None
        plan = SweepPlan(cfg, prob, self.key, ready)
        designs = run_chunks(plan, out, shard, executor, address, progress=progress)
        if designs is None:
            done = [k for k in range(plan.n_chunks) if plan.load(plan.path(out / "chunks", k), k) is not None]
            rows = [r for k in done for r in plan.load(plan.path(out / "chunks", k), k)]
            met = all(r["met"] for r in rows)
            report = {"kind": self.kind, "partial": True, "shard": f"{shard[0]}/{shard[1]}", "converged": met,
                      "met": met, "chunks_done": done, "chunks_total": plan.n_chunks, "designs": rows}
            return Solution(report, None, final=False, partial=True)
        pts = jnp.asarray([[r["measure"], r["objective"]] if r["met"] else [np.nan, np.nan] for r in designs])
        front = np.asarray(non_dominated(pts))
        for r, f in zip(designs, front):
            r["pareto"] = bool(f)
        met = all(r["met"] for r in designs)
        report = {"kind": self.kind, "converged": met, "met": met,
                  "iterations": sum(r["iterations"] for r in designs),
                  "targets": {k: float(v) for k, v in cfg.targets.items()}, "designs": designs,
                  "objective": {"name": cfg.objective.kind, "measure": cfg.sweep.measure.kind},
                  "pareto_count": int(front.sum())}
        params = [params_from_dict(r["params"], prob.p0) for r in designs]
        m, *outcomes = design_outcomes(self, [prob.p0, *params])  # the parent's, then the designs': one program
        return Solution(report, m, params, final=False, outcomes=outcomes)


def target_report(d: Design, achieved_values, errors) -> dict:
    """Target, achieved value, error (:func:`~hullopt.optimise.target_errors`), tolerance and met per target."""
    out = {}
    for k, t, tol, v, err in zip(d.targets.names, np.asarray(d.targets.values), np.asarray(d.targets.tol),
                                 np.asarray(achieved_values), np.asarray(errors)):
        out[k] = {"target": float(t), "achieved": float(v), "error": float(err), "tolerance": float(tol),
                  "met": bool(abs(err) <= tol)}
    return out


def design_outcomes(study: Study, params: list[FeatureParams]) -> list[Outcome]:
    """Each design measured against the parent (:func:`measure`), one jitted program for all.

    Parameters
    ----------
    study : Study
        The study whose problem (design, parent parameters ``p0``, draft) the designs belong to.
    params : list of FeatureParams
        The designs' parameters.

    Returns
    -------
    list of Outcome
        One :class:`Outcome` a design, on the host: parent and design sections and hydrostatics at the draft,
        achieved targets and their errors, sectional-area curves ``(2, n)`` [m²]; no objective (None: the
        designs' files draw none). The KCS sweep's parent and 6 designs, cold: 7.8 s; measured one at a time with
        the objective, 10.2 s.
    """
    out = jax.device_get(cached_call(*_outcomes_program(study, stack_params(params))))
    return [jax.tree.map(lambda a, k=k: a[k], out) for k in range(len(params))]


def _outcomes_program(study: Study, stacked) -> tuple:
    """The arguments of :func:`cached_call` (or :func:`prepare_call`) of :func:`design_outcomes` of the designs
    ``stacked`` (or their shapes)."""
    d = dataclasses.replace(study.problem.design, objective=None)
    return "outcomes", _outcomes, (d, study.problem.p0, stacked), (), study.key, True


def _outcomes(d: Design, p0: FeatureParams, stacked: FeatureParams) -> Outcome:
    """:func:`measure` of each design (params stacked on a leading axis)."""
    return jax.vmap(lambda p: measure(d, p0, p))(stacked)
