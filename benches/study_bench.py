#!/usr/bin/env python3
"""Cost of a gearstudy study: a 200-point study (omega1 10 x T_load 10 x mu 2, the example
study's window: start on the periodic orbit (initialization = 3; on an FMU without it, a
100 ms transient cut) + 10 mesh periods at 32 samples) run

  bare     a bare FMPy loop: one FMU2Slave reused (fmi2Reset), set, initialise, one doStep
           over the cut, 320 doStep + getReal of the same outputs; no reduction, no files
  serial   gearstudy.sweep(serial=True): the same in this process + reductions + Parquet
  dask-1   gearstudy.sweep on a LocalCluster with 1 worker process (cluster already up; the
           cluster sweep starts itself: engine.local_cluster)
  dask-2   the same with 2 worker processes

and the scheduler's own cost per task (2000 no-op tasks on the 2-worker cluster: wall clock,
and CPU of this process, which hosts the LocalCluster's scheduler). Figures are medians over
--repeats runs: wall clock (time.perf_counter) and CPU (this process + every worker process via
Client.run(time.process_time)); on a machine shared with other jobs the wall clock mostly
measures the others, the CPU figures do not. The 50- and 200-point runs of bare and dask-1 give
the CPU per additional point; their difference is the Dask path's overhead per point.

From them, the projected time of a 1e5-point study on 64 workers (model in docs/studies.md):

  T = t_start + N t_point / W + (N / c) t_task + c t_point

t_point: the Dask path's CPU per additional point (dask-1), W workers, c points per task (the
engine's chunk_size rule with the measured t_task), t_task: the scheduler's CPU per task (one
scheduler serves all workers, so this part is serial), c t_point: the last chunk's tail,
t_start: cluster start. The client's Parquet writing per row is printed too; it overlaps with
the computation and must stay below t_point / W per row.

usage: python benches/study_bench.py [--repeats 3] [--points 200]
Prints figures; asserts nothing.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
FMU = REPO / "target" / "fmu" / "GearedRotor.fmu"


def study_dict(n_speed: int, n_torque: int) -> dict:
    return {
        "study": {"name": "bench"},
        "grid": {
            "mu": [0.03, 0.06],
            "omega1": {"start": "1000 rpm", "stop": "6000 rpm", "num": n_speed},
            "T_load": {"start": 0.0, "stop": 200.0, "num": n_torque},
        },
        "outputs": {"names": ["P_in", "P_loss", "T1", "Fn", "TE", "omega2", "H_V"],
                    "orders": ["TE", "Fn", "T1"]},
        "window": {"transient": "100 ms", "periods": 10, "samples_per_period": 32, "n_orders": 3},
    }


def bare_loop(study) -> float:
    """The minimum a hand-written FMPy master does for the same points."""
    from fmpy import extract
    from fmpy.fmi2 import FMU2Slave

    cat = study.catalog
    unzip = extract(str(study.fmu))
    s = FMU2Slave(guid=cat.guid, unzipDirectory=unzip, modelIdentifier=cat.model_identifier,
                  instanceName="bare")
    s.instantiate()
    names = ["P_in", "P_loss", "T1", "Fn", "TE", "omega2", "E_in", "E_loss"]
    vr = [cat.variables[n].value_reference for n in names]
    w = study.window
    # As gearstudy does: start on the periodic orbit where the FMU offers it (no cut),
    # otherwise cut the transient.
    periodic = "initialization" in cat.variables
    cut = 0.0 if periodic else w.transient
    t0 = time.perf_counter()
    c0 = time.process_time()
    for p in study.points:
        s.setupExperiment(startTime=0.0)
        s.setReal([cat.variables[k].value_reference for k in p], [float(v) for v in p.values()])
        if periodic:
            s.setInteger([cat.variables["initialization"].value_reference], [3])
        s.enterInitializationMode()
        s.exitInitializationMode()
        t_mesh = 2 * math.pi / (27 * p["omega1"])
        h = t_mesh / w.samples_per_period
        if cut > 0.0:
            s.doStep(0.0, cut)
        y = np.empty((w.periods * w.samples_per_period + 1, len(vr)))
        y[0] = s.getReal(vr)
        for j in range(w.periods * w.samples_per_period):
            s.doStep(cut + j * h, h)
            y[j + 1] = s.getReal(vr)
        s.terminate()
        s.reset()
    dt, cpu = time.perf_counter() - t0, time.process_time() - c0
    s.freeInstance()
    return dt, cpu


def all_cpu(client, workers: bool = True) -> float:
    """CPU seconds used so far by this process (client and, for a LocalCluster, the
    scheduler) plus, with workers=True, every worker process (Client.run)."""
    total = time.process_time()
    if workers:
        total += sum(client.run(time.process_time).values())
    return total


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--points", type=int, default=200, help="2 x n x n; 200 -> 10 x 10")
    a = ap.parse_args()
    import gearstudy
    from distributed import Client, wait
    from gearstudy.engine import chunk_size, local_cluster
    from gearstudy.results import ResultStore

    n_side = max(1, int(round(math.sqrt(a.points / 2))))
    study = gearstudy.study_from_dict(study_dict(n_side, n_side), fmu=FMU)
    n = len(study.points)
    # a quarter of the points (same window): the difference of the two sizes separates the
    # per-point cost from the per-study one (cluster plugin, FMU extraction, first instance)
    small = gearstudy.study_from_dict(study_dict(n_side, n_side), fmu=FMU)
    small.points = study.points[::4]
    n_small = len(small.points)
    print(f"{n} points; machine: {os.cpu_count()} cores, load average at start "
          f"{' '.join(f'{x:.2f}' for x in os.getloadavg())} (shared with other jobs)")
    res: dict[str, list[float]] = {k: [] for k in ("bare", "serial", "dask-1", "dask-2",
                                                   "bare-small", "dask-1-small")}
    cpu: dict[str, list[float]] = {k: [] for k in res}  # process CPU, or the workers' rows
    cpu_point: list[float] = []
    starts: dict[int, list[float]] = {1: [], 2: []}
    task_cost: list[float] = []
    task_cpu: list[float] = []
    cpu_point_dask: dict[int, list[float]] = {1: [], 2: []}
    idle: dict[int, list[float]] = {1: [], 2: []}  # CPU of an idle cluster per wall second
    write_row: list[float] = []  # CPU of the client process (which hosts the scheduler)
    for rep in range(a.repeats):
        for tag, st in (("bare", study), ("bare-small", small)):
            wall, c = bare_loop(st)
            res[tag].append(wall)
            cpu[tag].append(c)
        with tempfile.TemporaryDirectory() as d:
            t0, c0 = time.perf_counter(), time.process_time()
            gearstudy.sweep(study, out=Path(d) / "s", serial=True, progress=False)
            res["serial"].append(time.perf_counter() - t0)
            cpu["serial"].append(time.process_time() - c0)
            rows = gearstudy.read_results(Path(d) / "s").to_pylist()
            cpu_point += [r["cpu_s"] for r in rows]
            # the client's serial share: one Parquet part per chunk of rows
            store = ResultStore(Path(d) / "w", study)
            t0 = time.perf_counter()
            for i in range(0, len(rows), 100):
                store.write(rows[i : i + 100])
            write_row.append((time.perf_counter() - t0) / len(rows))
        for workers in (1, 2):
            t0 = time.perf_counter()
            cluster = local_cluster(workers)  # what sweep starts by itself
            client = Client(cluster)
            client.wait_for_workers(workers)
            starts[workers].append(time.perf_counter() - t0)
            try:
                runs = [("", study)] + ([("-small", small)] if workers == 1 else [])
                for suffix, st in runs:
                    with tempfile.TemporaryDirectory() as d:
                        c0 = all_cpu(client)
                        t0 = time.perf_counter()
                        gearstudy.sweep(st, out=Path(d) / "s", client=client, progress=False)
                        res[f"dask-{workers}{suffix}"].append(time.perf_counter() - t0)
                        cpu[f"dask-{workers}{suffix}"].append(all_cpu(client) - c0)
                        if not suffix:
                            cpu_point_dask[workers] += gearstudy.read_results(Path(d) / "s").column("cpu_s").to_pylist()
                time.sleep(0.5)
                c0, t0 = all_cpu(client), time.perf_counter()
                time.sleep(3.0)
                idle[workers].append((all_cpu(client) - c0) / (time.perf_counter() - t0))
                if workers == 2:
                    m = 2000
                    c0 = all_cpu(client, workers=False)
                    t0 = time.perf_counter()
                    futs = client.map(lambda i: i, range(m), pure=False)
                    wait(futs)
                    task_cost.append((time.perf_counter() - t0) / m)
                    task_cpu.append((all_cpu(client, workers=False) - c0) / m)
                    del futs
            finally:
                client.close()
                cluster.close()
        print(f"repeat {rep + 1}: " + ", ".join(f"{k} {v[-1]:.2f} s" for k, v in res.items())
              + f", no-op task {task_cost[-1] * 1e3:.2f} ms")

    med = {k: statistics.median(v) for k, v in res.items()}
    mcpu = {k: statistics.median(v) for k, v in cpu.items()}
    t_point = statistics.median(cpu_point)
    t_task_wall = statistics.median(task_cost)
    t_task = statistics.median(task_cpu)
    t_start = statistics.median(starts[2])
    print(f"\nmedians of {a.repeats} repeats (wall clock, {n} points; '-small': {n_small}):")
    for k, v in med.items():
        what = "process CPU" if not k.startswith("dask") else "CPU of client+scheduler+workers"
        m = n_small if k.endswith("small") else n
        print(f"  {k:12s} {v:7.2f} s   {v / m * 1e3:6.1f} ms/point   range "
              f"{min(res[k]):.2f}-{max(res[k]):.2f} s;  {what} {mcpu[k] / m * 1e3:5.1f} ms/point")
    print("  cores this study obtained (CPU / wall): " + ", ".join(
        f"{k} {mcpu[k] / med[k]:.2f}" for k in ("bare", "serial", "dask-1", "dask-2")))
    print(f"  speed-up dask-2 vs serial: {med['serial'] / med['dask-2']:.2f}x, "
          f"vs bare loop: {med['bare'] / med['dask-2']:.2f}x")
    print(f"  overhead per point, wall: serial gearstudy - bare = "
          f"{(med['serial'] - med['bare']) / n * 1e3:.2f} ms, dask-1 - bare = "
          f"{(med['dask-1'] - med['bare']) / n * 1e3:.2f} ms")
    print(f"  overhead per point, CPU: serial gearstudy - bare = "
          f"{(mcpu['serial'] - mcpu['bare']) / n * 1e3:.2f} ms, dask-1 - bare = "
          f"{(mcpu['dask-1'] - mcpu['bare']) / n * 1e3:.2f} ms, dask-2 - bare = "
          f"{(mcpu['dask-2'] - mcpu['bare']) / n * 1e3:.2f} ms")
    dn = n - n_small
    slope = {k: (mcpu[k] - mcpu[k + "-small"]) / dn for k in ("bare", "dask-1")}
    fixed = mcpu["dask-1"] - n * slope["dask-1"]
    print(f"  CPU per additional point ({n_small} -> {n} points): bare {slope['bare'] * 1e3:.2f} ms, "
          f"dask-1 {slope['dask-1'] * 1e3:.2f} ms -> Dask overhead "
          f"{(slope['dask-1'] - slope['bare']) * 1e3:.2f} ms/point; Dask fixed CPU per study "
          f"(plugin, extraction, first instance, idle workers) {fixed:.2f} s")
    print(f"  an idle cluster's own CPU (heartbeats, monitors, event loops): 1 worker "
          f"{statistics.median(idle[1]) * 100:.1f} %, 2 workers {statistics.median(idle[2]) * 100:.1f} % of a core")
    print(f"  speed-up an idle 2-core machine would give (CPU-bound): "
          f"2 x bare CPU / dask-2 CPU = {2 * mcpu['bare'] / mcpu['dask-2']:.2f}x")
    print(f"  CPU per point (rows' cpu_s = the worker thread, median): serial {t_point * 1e3:.1f} ms, "
          f"dask-1 {statistics.median(cpu_point_dask[1]) * 1e3:.1f} ms, "
          f"dask-2 {statistics.median(cpu_point_dask[2]) * 1e3:.1f} ms")
    print(f"  scheduler cost per no-op task (2 workers): wall {t_task_wall * 1e3:.2f} ms, "
          f"CPU of the client+scheduler process {t_task * 1e3:.2f} ms")
    print(f"  LocalCluster start: 1 worker {statistics.median(starts[1]):.2f} s, "
          f"2 workers {t_start:.2f} s")
    t_write = statistics.median(write_row)
    print(f"  client writing rows (Parquet, 100 rows per part): {t_write * 1e3:.3f} ms/row")
    # the projection uses the Dask path's CPU per additional point (worker thread + the
    # worker's own threads), not the bare loop's
    t_pt = slope["dask-1"]
    N, W = 100_000, 64
    c = chunk_size(N, W, t_pt, task_s=t_task)
    tasks = math.ceil(N / c)
    compute = N * t_pt / W
    sched = tasks * t_task
    tail = c * t_pt
    total = t_start + compute + sched + tail
    print(f"\nprojection, {N} points on {W} workers (t_point {t_pt * 1e3:.1f} ms, t_task "
          f"{t_task * 1e3:.2f} ms): chunk {c} points -> {tasks} tasks;")
    print(f"  T = t_start {t_start:.1f} s + N t_point / W {compute:.0f} s + tasks x t_task "
          f"{sched:.1f} s + tail c t_point {tail:.1f} s = {total:.0f} s ({total / 60:.1f} min)")
    print(f"  (one core: {N * t_pt / 3600:.2f} h; scheduler share {sched / total * 100:.1f} %; the "
          f"client writes {N * t_write:.0f} s of rows meanwhile, "
          f"{N * t_write / compute * 100:.0f} % of the compute time, overlapped)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
