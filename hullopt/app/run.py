"""``hullopt run``: a config's study (:mod:`hullopt.study`) solved and written as a run folder:

    config.json   the resolved config           report.json   results (see :func:`run`)
    parent.json   the parent it deformed        hull.stl      the final hull (closed mesh; Lpp, draft in its header)
    offsets.csv   its offset table (wide layout: machine data, read back to the run's ∇)
    offsets_table.csv  its table of offsets for a yard (stations 0–20 × round waterlines and the DWL)
    overlay.png   the design against its parent (body plan, waterlines, sectional-area curve)
    convergence.png, pareto.png (sweeps), chunks/ (sweeps)
    report.html   the run as one self-contained page (3D hulls, plots, tables: :mod:`hullopt.report`)
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import shutil
import threading
import time
import warnings
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    SpinnerColumn,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)
from rich.text import Text

from ..drawing import write_offsets_stations, write_offsets_wide
from ..constants import KNOT, G
from ..errors import FidelityWarning
from ..geometry import Sections
from ..models import plausibility_warnings, save_features
from ..report import (
    FRONTS_NAME,
    OVERLAY_NAME,
    PATENT_NAME,
    PAGE_TEMPLATE,
    Hulls,
    label,
    objective_about,
    plot_convergence,
    plot_overlay,
    plot_pareto,
    plot_patent,
    plot_rescored_fronts,
    write_json,
    write_report,
)
from ..study import (
    VIOLATION,
    Outcome,
    RunConfig,
    Study,
    collect_chunks,
    conditions_text,
    load_study,
)
from .output import console, errors, write_hull_file


def run(cfg: RunConfig, raw: dict, out: Path, quiet: bool = False, **options) -> dict:
    """Solve the config's study and write the run folder ``out``; returns the report.

    ``report.json``: ``kind``, ``converged`` (the solver finished and every target is met), ``met``,
    ``iterations``, ``targets`` (target, achieved, error, tolerance, met per particular), ``achieved`` and
    ``parent`` (the ``hullopt hydro --json`` keys of the final and the parent hull), ``objective``
    (value, parent value, name), ``params``, ``objectives`` (every measure, parent and design), ``warnings`` (the
    parent's first: its feature curves missing the hull they were extracted from,
    :class:`~hullopt.errors.FidelityWarning`, then its plausibility, :func:`~hullopt.models.plausibility_warnings`);
    for sweeps ``designs`` (one per sweep value, with its objectives, particulars, parameters and whether it is
    Pareto-optimal); ``seconds``: the wall time of each phase (``setup``: the config's hull and study;
    ``solve``; ``assess``: every measure of parent and design; ``rescore``: the second opinions; ``files``:
    hulls, plots, report.html), so that a slow run says where its time went. ``options``: the study's (a sweep's
    ``shard = (k, N)``, ``executor`` and ``address``); a shard whose sweep is not complete yet returns a partial
    report and writes no hull files.

    The folder is built in a staging sibling (``.<name>.partial``, :func:`_staging`) and put in the place of
    ``out`` when it is complete (:func:`_replace`): a run killed or failed part-way leaves ``out`` as it was
    (an earlier run's folder stays whole, with no new ``config.json`` beside its old ``report.json``), and a
    re-run resumes from the staging folder's chunks.
    """
    clock = _Clock(quiet)
    _warm_up_in_background()
    with warnings.catch_warnings(record=True) as seen:  # the parent's warnings, issued as it is read
        study: Study = load_study(cfg)  # a bad design or draft is refused before anything is written
    for w in seen:  # shown as they would have been; a parent that misses its source is in the report too
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    notes = [f"parent: {w.message}" for w in seen if issubclass(w.category, FidelityWarning)]
    final = out.resolve()
    work = _staging(final)  # built beside it, then put in its place: one run in a folder, always
    report = _solve_and_write(cfg, raw, study, work, final.name, clock, quiet, options, notes)
    _replace(work, final)
    return report


def _staging(out: Path) -> Path:
    """The staging sibling a run folder ``out`` is built in, ``.<name>.partial``: a killed run's, its chunks kept
    (a sweep resumes from them) and the rest cleared, with the chunks of the folder it will replace added (a
    re-run resumes from those too; each chunk is keyed by its sweep, so a stale one is solved again)."""
    work = out.with_name(f".{out.name}.partial")
    if work.is_dir():
        for child in work.iterdir():
            if child.name != "chunks":
                shutil.rmtree(child) if child.is_dir() and not child.is_symlink() else child.unlink()
    work.mkdir(parents=True, exist_ok=True)
    if (out / "chunks").is_dir():
        (work / "chunks").mkdir(exist_ok=True)
        for chunk in (out / "chunks").iterdir():
            if chunk.is_file() and not (work / "chunks" / chunk.name).exists():
                try:
                    os.link(chunk, work / "chunks" / chunk.name)
                except OSError:
                    shutil.copy2(chunk, work / "chunks" / chunk.name)
    return work


def has_fronts(rescored: dict) -> bool:
    """Whether a re-scoring has a front to draw: a calm-water and an added-resistance method (a calm-water
    minimum is re-scored by calm-water methods alone)."""
    kinds = {m["kind"] for m in rescored["methods"].values()}
    return {"calm", "waves"} <= kinds


def _exchange(a: Path, b: Path) -> bool:
    """Swap the directories ``a`` and ``b`` in one step (Linux renameat2 RENAME_EXCHANGE); False where the system
    cannot."""
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        at_fdcwd, rename_exchange = -100, 2
        return libc.renameat2(at_fdcwd, os.fsencode(a), at_fdcwd, os.fsencode(b), rename_exchange) == 0
    except (OSError, AttributeError):
        return False


def _replace(work: Path, out: Path) -> None:
    """Put the finished run folder ``work`` in the place of ``out``: a new folder by one rename; an existing one
    swapped with it in one step where the system can (else moved aside, replaced, then removed), so that ``out``
    holds the old run or the new one, never a mixture."""
    if not out.exists():
        work.rename(out)
        return
    if out.is_dir() and _exchange(work, out):
        shutil.rmtree(work)  # the old run, now at the staging path
        return
    old = out.with_name(f".{out.name}.old-{os.getpid()}")
    out.rename(old)
    work.rename(out)
    shutil.rmtree(old) if old.is_dir() else old.unlink()


def _solve_and_write(cfg: RunConfig, raw: dict, study: Study, out: Path, name: str, clock: _Clock, quiet: bool,
                     options: dict, notes: list[str] = ()) -> dict:
    """:func:`run`'s solve and files, written to ``out`` (the staging folder); ``name``: the run folder's final
    name, as its page shows it; ``notes``: warnings of the parent, first in the report's."""
    write_json(out / "config.json", raw)
    d = study.problem.design
    save_features(d.model.hull, out / "parent.json")  # the run folder rebuilds its designs from it
    shard = options.get("shard", (1, 1))
    title = f"{study.title}: {cfg.hull.parent}" + (f" shard {shard[0]}/{shard[1]}" if shard[1] > 1 else "")
    clock("setup")
    # a sweep's design folders are written by other processes; they start (and import) while it solves
    with _writers(cfg.sweep.count if cfg.kind == "pareto" else 1) as pool:
        with _progress(quiet, study.units(options), title) as (bar, task):
            solution = study.solve(out, progress=lambda n: bar.update(task, advance=n), **options)
        clock("solve")
        report = solution.report
        report["seconds"] = clock.seconds
        if isinstance(report.get("objective"), dict) and cfg.objective is not None:  # what it (and a measure) compute
            report["objective"]["about"] = {"name": objective_about(cfg.objective.build()), **(
                {"measure": objective_about(cfg.sweep.measure.build())} if cfg.kind == "pareto" else {})}
        if solution.partial:
            write_json(out / "report.json", report)
            return report
        m = solution.outcome
        # the design folders are written while the designs are assessed and re-scored
        designs_written = None if solution.final else _write_designs(pool, solution.outcomes, out / "designs")
        report["achieved"] = {k: float(v) for k, v in m.final.to_dict().items()}
        report["parent"] = {k: float(v) for k, v in m.parent.to_dict().items()}
        report["objectives"], report["limits"], assessed = study.assess(solution)
        # the parent's plausibility (a mesh in mm, in the wrong axes…), judged at the run's draft, comes first
        doubtful = plausibility_warnings(m.before, float(m.parent.draft), cfg.hull.parent)
        report["warnings"] = [*notes, *(f"parent: {w}" for w in doubtful), *assessed]
        clock("assess")
        rescored, doubts = study.rescore(solution.designs)
        clock("rescore")
        if rescored is not None:
            report["rescored"], report["rescored_warnings"] = rescored, doubts
            report["warnings"] += doubts
            met = [d["met"] for d in report["designs"]] if not solution.final else None
            if has_fronts(rescored):  # a calm-water run is re-scored by calm-water methods only: no front
                plot_rescored_fronts(rescored, out / FRONTS_NAME, met)
        if "history" in report:
            h = report["history"]
            # the PNG: the first series (a fit's cost, a minimum's objective), the violation below
            series = dict(h["series"])
            violation = series.pop(VIOLATION, None)
            plot_convergence(next(iter(series.values())), out / "convergence.png", h["iteration"], violation=violation,
                             fit=cfg.kind == "fit")
        if solution.final:
            _write_hull(m, out)
            hulls = Hulls.of(m.before, m.after, m.areas, m.parent.draft)  # each area curve at its own draft
        else:  # a sweep: each design's hull in designs/<k>/; report.html rebuilds them from the folder
            designs_written()
            o, kinds = report["objectives"], (cfg.sweep.measure.kind, cfg.objective.kind, "bf")
            about = report["objective"]["about"]
            where = "; ".join(f"{label(k, unit=False, about=about[a])}: {conditions_text(c)}"
                              for k, a, c in zip(kinds[1::-1], ("name", "measure"), (cfg.objective, cfg.sweep.measure)))
            plot_pareto(report["designs"], *kinds[:2], out / "pareto.png", parent=tuple(o[k]["parent"] for k in kinds),
                        conditions=where, about=about)
            speeds = sorted(set(rescored["conditions"]["speeds_kn"])) if rescored is not None else []
            plot_patent([o["bf"]["parent"], *o["bf"]["designs"]],
                        [report["parent"]["bwl"], *(r["particulars"]["bwl"] for r in report["designs"])],
                        [u * KNOT / (G * float(m.before.lpp)) ** 0.5 for u in speeds], out / PATENT_NAME,
                        [r["met"] for r in report["designs"]], rescored)
            hulls = None
        write_offsets_wide(m.before, out / "parent_offsets.csv", name="the parent hull", dense=True)
        write_json(out / "report.json", report)  # before report.html: a failure there loses no result
        write_report(out, report, hulls, name=name)
        clock("files")
        write_json(out / "report.json", report)  # again, with the files' time (report.html's included)
        return report


def _warm_up_in_background() -> None:
    """Import the files' libraries, and load plotly's page template, on a daemon thread. The solve's kept
    program loads and runs with the GIL released (~1.5 s of a warm demo run): time in which matplotlib, trimesh
    and plotly (~1.6 s) are imported and the template read (~0.4 s) rather than after it. The writers import
    them again where they use them (a no-op once done; Python's import lock makes them wait for a half-done
    import), so a failure here costs nothing but the time."""

    def load():
        with contextlib.suppress(Exception):
            import matplotlib.backends.backend_agg  # noqa: F401
            import matplotlib.figure  # noqa: F401
            import plotly.io
            import trimesh  # noqa: F401

            plotly.io.templates[PAGE_TEMPLATE]

    threading.Thread(target=load, name="hullopt-warm-up", daemon=True).start()


class _Clock:
    """Wall time [s] of consecutive phases: ``clock("name")`` ends the phase begun at the previous call and,
    unless ``quiet``, says so on stderr (a long run tells where it is and where its time went as it goes)."""

    def __init__(self, quiet: bool = True):
        self.seconds: dict[str, float] = {}
        self._t = time.perf_counter()
        self._quiet = quiet

    def __call__(self, phase: str) -> None:
        t = time.perf_counter()
        self.seconds[phase] = round(t - self._t, 3)
        self._t = t
        if not self._quiet and self.seconds[phase] >= 0.05:  # a phase with nothing to do is not news
            errors.print(Text(f"{phase} done in {self.seconds[phase]:.1f} s", style="dim"), soft_wrap=True)


def _write_hull(m: Outcome, out: Path) -> None:
    """Write the final hull's files to ``out``: ``hull.stl`` [m] (refined along the length and welded for
    float32, checked as read back: closed, one body, no degenerate face), its offsets (:func:`write_offsets`), and
    the overlay plot (body plan, waterlines, sectional-area curve against the parent), all at the design's own
    draft [m] (``m.final.draft``: a draft scale floats it deeper or shallower than the parent)."""
    draft = m.final.draft
    write_hull_file(m.after, out / "hull.stl", float(draft))
    write_offsets(m.after, float(draft), out, "the designed hull")
    who = f"Design {out.name}" if out.parent.name == "designs" else "The design"
    plot_overlay(m.before, m.after, float(draft), out / OVERLAY_NAME,
                 title=f"{who} against its parent at T = {float(draft):g} m (parent dashed)",
                 measures=(m.areas, m.levels, m.widths))


@contextlib.contextmanager
def _writers(designs: int):
    """A pool of processes, one per core, that write ``designs`` design folders (:func:`_write_designs`), or
    None when there are fewer than four or one core. Spawned, not forked (jax's threads do not survive a fork),
    on the CPU backend (they only draw and write), and started at once with their imports, so that they are ready
    when the solve ends (the GPU's 64-design KCS sweep: its files phase 18.7 → 12.2 s). Closed on
    leaving, its unfinished work cancelled when the run failed."""
    workers = min(designs, os.cpu_count() or 1)
    if workers < 2 or designs < 4:
        yield None
        return
    pool = ProcessPoolExecutor(workers, mp_context=multiprocessing.get_context("spawn"), initializer=_writer_process)
    ok = False
    try:
        for _ in range(workers):  # each submit without an idle worker spawns one, which runs the initializer
            pool.submit(int)
        yield pool
        ok = True
    finally:
        pool.shutdown(wait=ok, cancel_futures=not ok)


def _write_designs(pool: ProcessPoolExecutor | None, outcomes: list[Outcome], out: Path) -> Callable[[], None]:
    """Start writing each design's files (:func:`_write_hull`) in ``out/<k>/`` on ``pool`` (:func:`_writers`)
    beside the parent process's work; returns the function that waits for them (and raises a writer's error).
    Without a pool they are written when waited for."""
    if pool is None:
        def write():
            for k, mk in enumerate(outcomes):
                _write_hull(mk, out / str(k))
        return write
    jobs = [pool.submit(_write_hull, mk, out / str(k)) for k, mk in enumerate(outcomes)]

    def wait():
        for job in jobs:
            job.result()  # a failure is raised here, with the worker's traceback
    return wait


def _writer_process() -> None:
    """A design writer's set-up: float64 on the CPU (the parent process holds the GPU, if any), and the plots' and
    meshes' libraries imported."""
    import jax

    jax.config.update("jax_platforms", "cpu")
    jax.config.update("jax_enable_x64", True)
    import matplotlib.backends.backend_agg  # noqa: F401
    import trimesh  # noqa: F401


def write_offsets(sections: Sections, draft: float, out: Path, name: str) -> None:
    """A hull's offsets in a run folder ``out``: ``offsets.csv``, machine data (the wide layout, dense enough that
    ``hullopt hydro offsets.csv`` gives the run's ∇ back; knuckles and deck carried), and ``offsets_table.csv``,
    the table a yard reads (the stations layout: stations 0 (AP) … 20 (FP) × waterlines at a round spacing and
    the DWL at ``draft`` [m], as ``hullopt lines --offsets`` writes it; read back by ``hullopt hydro`` too)."""
    write_offsets_wide(sections, out / "offsets.csv", name=name, dense=True)
    write_offsets_stations(sections, out / "offsets_table.csv", draft, name=name)


@contextlib.contextmanager
def _progress(quiet: bool, total: int | None, title: str):
    """A transient progress display: a spinner with the elapsed time, plus a bar, "k/N" and an estimate of the
    time left (from the rate so far) when ``total`` is given; yields ``(progress, task)``."""
    counts = [BarColumn(), MofNCompleteColumn(), TextColumn("left"), TimeRemainingColumn()] if total is not None else []
    with Progress(SpinnerColumn(), TextColumn("{task.description}"), *counts, TimeElapsedColumn(),
                  console=console, disable=quiet or not console.is_terminal, transient=True) as bar:
        yield bar, bar.add_task(title, total=total)


def merge(dirs: list[Path], out: Path, quiet: bool = False) -> dict:
    """Combine the run folders of the shards of one sweep into ``out``: the same folder and report as the
    unsplit sweep (nothing is solved; :class:`HullError` if a chunk is missing)."""
    cfg, raw = collect_chunks(list(dirs), _staging(out.resolve()))  # where run builds the folder
    return run(cfg, raw, out, quiet)
