"""Running a study: serially in this process, or on dask.distributed.

Dask path: the .fmu's bytes travel once to every worker in a worker plugin
(``Client.register_plugin``); the plugin extracts the FMU into the worker's local directory at
``setup`` and keeps one FMU instance per worker thread, reused between points (fmi2Reset).
Points go out in chunks (one task = one chunk, see :func:`chunk_size`); each finished chunk is
written as its own Parquet file as soon as it arrives (results.py), so an interrupted study
keeps what it finished and a rerun with the same study file runs only the missing points.
"""

from __future__ import annotations

import logging
import math
import os
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

from .results import ResultStore
from .runner import RunnerPool, prepare_settings
from .study import Study, load_study, point_key

#: rough CPU cost of a point (2 cores, default rtol): per simulated second of the transient
#: cut (one doStep) and per sampled communication step; only used to size chunks
CPU_PER_SIMULATED_S = 0.15
CPU_PER_SAMPLE_S = 30e-6
#: a task should carry at least this much work ...
TARGET_TASK_S = 0.5
#: ... and, since the one scheduler handles tasks one after another (~1-3 ms each, measured
#: by benches/study_bench.py), W workers finish tasks W times as fast as one: a task's work must
#: be >= W t_task / OVERHEAD_SHARE for the scheduler to stay below that share of the time
SCHEDULER_TASK_S = 2.5e-3
OVERHEAD_SHARE = 0.02
#: ... but every worker should get several tasks, for load balance and incremental results
TASKS_PER_WORKER = 4


@dataclass
class SweepSummary:
    out: Path
    points: int
    skipped: int
    ran: int
    failed: int
    wall_s: float
    chunk_size: int
    workers: int

    def __str__(self) -> str:
        if self.ran == 0:
            what = "all done already" if self.skipped == self.points else "none run now"
            return f"{self.points} points: {what}; results in {self.out}"
        return (
            f"{self.points} points: {self.skipped} already done, {self.ran} run "
            f"({self.failed} failed) on {self.workers} worker(s) in chunks of {self.chunk_size}, "
            f"{self.wall_s:.1f} s; results in {self.out}"
        )


def estimated_point_cpu(study: Study, mesh_period: float = 2 * math.pi / (27 * 314.16)) -> float:
    w = study.window
    cut = w.transient * (mesh_period if w.transient_unit == "periods" else 1.0)
    samples = w.periods * w.samples_per_period
    return CPU_PER_SIMULATED_S * (cut + w.periods * mesh_period) + CPU_PER_SAMPLE_S * samples


def chunk_size(n_points: int, workers: int, point_cpu_s: float,
               task_s: float = SCHEDULER_TASK_S) -> int:
    """Points per task: enough work per task to hide the scheduler's per-task cost
    (TARGET_TASK_S, and W t_task / OVERHEAD_SHARE for W workers), but at least
    TASKS_PER_WORKER tasks per worker."""
    work = max(TARGET_TASK_S, workers * task_s / OVERHEAD_SHARE)
    by_overhead = math.ceil(work / max(point_cpu_s, 1e-6))
    by_balance = math.ceil(n_points / max(1, workers * TASKS_PER_WORKER))
    return max(1, min(by_overhead, by_balance))


def sweep(
    study: Study | str | os.PathLike,
    out: str | os.PathLike | None = None,
    scheduler: str | None = None,
    workers: int | None = None,
    serial: bool = False,
    max_points: int | None = None,
    progress: bool | None = None,
    fmu: str | os.PathLike | None = None,
    client=None,
    overwrite: bool = False,
) -> SweepSummary:
    """Run the study's points not yet in ``out`` and append their rows there.

    scheduler: address of a running Dask scheduler (``tcp://host:8786``); default: a
    LocalCluster with ``workers`` worker processes (default: one per core), one thread each.
    serial: run in this process without Dask. max_points: run at most this many new points
    (the rest stays for a later call). client: an existing ``distributed.Client`` to use.
    overwrite: delete the rows already in ``out`` first (else they are kept and skipped).
    """
    if not isinstance(study, Study):
        study = load_study(study, fmu=fmu)
    out = Path(out) if out is not None else Path("out") / "studies" / _slug(study.name)
    if study.continuation is not None:
        # series continued from a neighbour's orbit (continuation.py): ordered, not points
        from . import continuation

        return continuation.sweep(study, out, scheduler=scheduler, workers=workers,
                                  serial=serial, client=client)
    store = ResultStore(out, study, overwrite=overwrite)
    items = [(i, point_key(p), p) for i, p in enumerate(study.points)]
    done = store.done_keys()
    todo = [it for it in items if it[1] not in done]
    # Counted before --max-points cuts the list: the points already done, not the ones left.
    n_done = len(items) - len(todo)
    if max_points is not None:
        todo = todo[: max(0, int(max_points))]
    settings = prepare_settings(study.settings(), study.catalog)
    if progress is None:
        progress = sys.stdout.isatty()
    t0 = time.perf_counter()
    failed = 0
    if not todo:
        return SweepSummary(out, len(items), n_done, 0, 0, 0.0, 0, 0)
    if serial:
        pool = RunnerPool(study.fmu)
        n = study.chunk_size or chunk_size(len(todo), 1, estimated_point_cpu(study))
        try:
            for c in _chunks(todo, n):
                rows = pool.run_chunk(c, settings)
                store.write(rows)
                failed += sum(r["status"] not in ("OK", "Warning") for r in rows)
                if progress:
                    print(f"\r{store.written} / {len(todo)} points", end="", flush=True)
        finally:
            pool.close()
        if progress:
            print()
        return SweepSummary(out, len(items), n_done, len(todo), failed,
                            time.perf_counter() - t0, n, 1)

    from distributed import Client

    own_cluster = own_client = None
    try:
        if client is None:
            if scheduler:
                client = own_client = Client(scheduler)
            else:
                own_cluster = local_cluster(workers or os.cpu_count() or 1)
                client = own_client = Client(own_cluster)
        n_workers = max(1, sum(client.nthreads().values()))
        n = study.chunk_size or chunk_size(len(todo), n_workers, estimated_point_cpu(study))
        plugin = install_fmu(client, study.fmu)
        futures = [
            client.submit(run_chunk_on_worker, plugin, c, settings, pure=False,
                          key=f"gearstudy-{store.session}-chunk-{j}")
            for j, c in enumerate(_chunks(todo, n))
        ]
        bar = None
        if progress:
            from distributed.diagnostics.progressbar import progress as dask_progress

            bar = threading.Thread(
                target=dask_progress, args=(futures,), kwargs={"notebook": False}, daemon=True
            )
            bar.start()
        from distributed import as_completed

        for fut, rows in as_completed(futures, with_results=True):
            store.write(rows)
            failed += sum(r["status"] not in ("OK", "Warning") for r in rows)
        if bar is not None:
            bar.join(timeout=5)
            print()
        return SweepSummary(out, len(items), n_done, len(todo), failed,
                            time.perf_counter() - t0, n, n_workers)
    finally:
        if own_client is not None:
            own_client.close()
        if own_cluster is not None:
            own_cluster.close()


def local_cluster(workers: int):
    """A LocalCluster of `workers` processes with one thread each, no dashboard, and no
    statistical profiler in the workers (it samples every 10 ms for the dashboard and cost
    ~1.7 % of a core per busy worker, measured)."""
    import dask
    from distributed import LocalCluster

    with dask.config.set({"distributed.worker.profile.enabled": False}):
        return LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            dashboard_address=None,
            silence_logs=logging.ERROR,
        )


def _chunks(seq, n):
    return [seq[i : i + n] for i in range(0, len(seq), n)]


def _slug(name: str) -> str:
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name).strip("_") or "study"


# -- worker side -------------------------------------------------------------------------

def _fmu_plugin_class():
    from distributed.diagnostics.plugin import WorkerPlugin

    class FmuPlugin(WorkerPlugin):
        """Carries the .fmu to a worker; extracts it there once and keeps the instances."""

        def __init__(self, fmu_bytes: bytes, fmu_name: str, name: str):
            self.fmu_bytes = fmu_bytes
            self.fmu_name = fmu_name
            self.name = name
            self.pool = None

        def setup(self, worker):
            d = Path(worker.local_directory) / self.name
            d.mkdir(parents=True, exist_ok=True)
            path = d / self.fmu_name
            path.write_bytes(self.fmu_bytes)
            self.pool = RunnerPool(path, workdir=str(d))

        def teardown(self, worker):
            if self.pool is not None:
                self.pool.close()

    return FmuPlugin


def install_fmu(client, fmu_path) -> str:
    """Register the FMU plugin on every worker (also on workers that join later); returns
    the plugin name tasks use to find it. Same FMU bytes -> same name -> no re-install."""
    import hashlib

    data = Path(fmu_path).read_bytes()
    name = "gearstudy-fmu-" + hashlib.sha256(data).hexdigest()[:16]
    plugin = _fmu_plugin_class()(data, Path(fmu_path).name, name)
    client.register_plugin(plugin, name=name)
    return name


def run_chunk_on_worker(plugin_name: str, items, settings) -> list[dict]:
    from distributed import get_worker

    pool = get_worker().plugins[plugin_name].pool
    return pool.run_chunk(items, settings)
