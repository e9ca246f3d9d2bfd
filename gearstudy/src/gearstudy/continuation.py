"""Sweeps continued from a neighbour's periodic orbit (``[continuation]``, docs/dynamic_factor.md).

A grid study runs every point on its own (from rest or on the point's own periodic orbit), so a
system with two stable orbits at one speed (the softening resonance of a tooth contact that can
lose contact) shows only one of them, whichever the start falls to. A continuation runs the
points of a series in order instead, each started from the periodic orbit of the point before:
the slow sweep of an experiment, up and down, which shows the jump and the hysteresis between
the directions.

The work is the crate's ``periodic --sweep`` program (src/periodic/elastic.rs, ``continuation``):
one call per series and direction, with the series' values in SI (a ``--params`` file, as the
[damping] table does) and the speeds in the direction's order; it prints one JSON line per
point. gearstudy runs the calls as Dask tasks (one per series and direction; two directions of
one series run side by side) or serially, and writes ``continuation.csv`` (one row per point)
and ``continuation.json`` (the study, the closed-form mesh frequency, the CPU time) into the
results directory. ``gearstudy plot`` draws ``dynamic_factor.png`` from them.

Study file::

    [fixed]                       # every series: the FMU's parameters and T_load
    tooth_contact = "elastic"
    T_load = "100 N.m"

    [continuation]
    parameter = "omega1"          # the swept input (only omega1)
    values = {start = "500 rpm", stop = "15000 rpm", num = 30}
    directions = ["up", "down"]

    [[continuation.series]]       # one curve per series and direction
    name = "drive flank only"
    # set = {j_bn = "0.1 mm"}     # values of this series on top of [fixed]
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import damping
from .units import StudyError

CSV = "continuation.csv"
META = "continuation.json"
DIRECTIONS = ("up", "down")
COLUMNS = ("series", "direction", "index", "omega1", "rpm", "dynamic_factor", "fn_max", "fn_min",
           "fn_static", "free_flight", "periodic", "residual", "floquet_max_abs", "periods",
           "cpu_s", "note")


@dataclass(frozen=True)
class Series:
    name: str
    values: dict  # FMU name -> FMU value, on top of [fixed]


@dataclass
class Continuation:
    parameter: str
    values: list[float]  # ascending, rad/s
    directions: tuple[str, ...]
    series: list[Series]
    program: str
    timeout_s: float = 1800.0
    extra: dict = field(default_factory=dict)


def parse(table: dict, cat, base: Path | None, axis) -> Continuation:
    """The [continuation] table; `axis(name, spec, cat, where)` reads a list or a range."""
    allowed = {"parameter", "values", "directions", "series", "program", "timeout"}
    bad = set(table) - allowed
    if bad:
        raise StudyError(f"[continuation] unknown key(s) {sorted(bad)}; allowed: {sorted(allowed)}")
    parameter = table.get("parameter", "omega1")
    if parameter != "omega1":
        raise StudyError(f"[continuation] parameter = {parameter!r}: only the drive speed "
                         "\"omega1\" can be continued (the periodic orbit is one at constant speed)")
    if "values" not in table:
        raise StudyError("[continuation] needs values, e.g. {start = \"500 rpm\", stop = "
                         "\"15000 rpm\", num = 30} or a list")
    values = sorted(float(v) for v in axis(parameter, table["values"], cat, "[continuation] "))
    if len(values) < 2 or not all(v > 0 and math.isfinite(v) for v in values):
        raise StudyError("[continuation] values: give at least two positive speeds")
    dirs = tuple(table.get("directions", list(DIRECTIONS)))
    if not dirs or any(d not in DIRECTIONS for d in dirs) or len(set(dirs)) != len(dirs):
        raise StudyError(f"[continuation] directions = {list(dirs)}: give \"up\", \"down\" or both")
    raw = table.get("series", [{"name": "series 1"}])
    if not isinstance(raw, list) or not raw:
        raise StudyError("[continuation] series: give one or more [[continuation.series]] tables "
                         "with a name (and optional set = {...})")
    series = []
    for i, s in enumerate(raw):
        where = f"[[continuation.series]] {i + 1}: "
        bad = set(s) - {"name", "set"}
        if bad:
            raise StudyError(f"{where}unknown key(s) {sorted(bad)}; allowed: ['name', 'set']")
        vals = {n: cat.to_fmu_value(n, v, where) for n, v in s.get("set", {}).items()}
        if parameter in vals:
            raise StudyError(f"{where}'{parameter}' is the swept variable; it cannot be set per series")
        series.append(Series(str(s.get("name", f"series {i + 1}")), vals))
    names = [s.name for s in series]
    if len(set(names)) != len(names):
        raise StudyError(f"[continuation] series names must differ: {names}")
    prog = damping.find_program(table.get("program"), base)
    if not prog.is_file():
        raise StudyError(
            f"[continuation]: the program {prog} is not found; build it with "
            "`cargo build --release --bin periodic`, or give its path with [continuation] program "
            f"or ${damping.PROGRAM_ENV}"
        )
    return Continuation(parameter, values, dirs, series, str(prog),
                        float(table.get("timeout", 1800.0)))


def run_one(program: str, params_text: str, speeds: list[float], timeout: float) -> tuple[list[dict], dict, float]:
    """One `periodic --sweep` call: the rows (JSON lines), the summary line and the CPU time
    of the process (user + system, from the OS)."""
    with tempfile.TemporaryDirectory(prefix="gearstudy-continuation-") as d:
        pf = Path(d) / "series.txt"
        pf.write_text(params_text)
        before = os.times()
        proc = subprocess.run(
            [program, "--sweep", ",".join(repr(float(w)) for w in speeds), "--json",
             "--ignore-unknown", "--params", str(pf), "--out", d],
            capture_output=True, text=True, timeout=timeout,
        )
        after = os.times()
    cpu = (after.children_user - before.children_user) + (after.children_system - before.children_system)
    if proc.returncode != 0:
        msg = (proc.stderr.strip() or proc.stdout.strip()).splitlines()
        raise RuntimeError(msg[-1] if msg else f"exit status {proc.returncode}")
    lines = [json.loads(x) for x in proc.stdout.strip().splitlines() if x.startswith("{")]
    return lines[:-1], lines[-1], cpu


def _task(program, params_text, speeds, timeout, series_name, direction):
    t0 = time.perf_counter()
    rows, summary, cpu = run_one(program, params_text, speeds, timeout)
    for i, r in enumerate(rows):
        r.update(series=series_name, direction=direction, index=i,
                 rpm=r["omega1"] * 30.0 / math.pi)
    return {"series": series_name, "direction": direction, "rows": rows, "summary": summary,
            "cpu_s": cpu, "wall_s": time.perf_counter() - t0}


def tasks(study) -> list[tuple]:
    c: Continuation = study.continuation
    out = []
    for s in c.series:
        point = dict(study.fixed) | s.values
        text = damping.params_text(point, study.catalog)
        for d in c.directions:
            speeds = c.values if d == "up" else c.values[::-1]
            out.append((c.program, text, speeds, c.timeout_s, s.name, d))
    return out


def sweep(study, out, scheduler=None, workers=None, serial=False, client=None):
    """Run every series and direction of the study's [continuation]; write the results."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    jobs = tasks(study)
    t0 = time.perf_counter()
    if serial:
        done = [_task(*j) for j in jobs]
        n_workers = 1
    else:
        from distributed import Client

        from .engine import local_cluster

        own_cluster = own_client = None
        try:
            if client is None:
                if scheduler:
                    client = own_client = Client(scheduler)
                else:
                    own_cluster = local_cluster(workers or os.cpu_count() or 1)
                    client = own_client = Client(own_cluster)
            n_workers = max(1, sum(client.nthreads().values()))
            futures = [client.submit(_task, *j, pure=False) for j in jobs]
            done = client.gather(futures)
        finally:
            if own_client is not None:
                own_client.close()
            if own_cluster is not None:
                own_cluster.close()
    wall = time.perf_counter() - t0
    rows = [r for d in done for r in d["rows"]]
    with open(out / CSV, "w") as f:
        f.write(",".join(COLUMNS) + "\n")
        for r in rows:
            f.write(",".join(_csv(r.get(k)) for k in COLUMNS) + "\n")
    summary = done[0]["summary"] if done else {}
    f_m = float(summary.get("closed_form_hz", float("nan")))
    z1 = int(summary.get("z1", 0))
    meta = {
        "study": study.name,
        "description": study.extra.get("description", ""),
        "fixed": {k: v for k, v in study.fixed.items()},
        "series": [{"name": s.name, "set": s.values} for s in study.continuation.series],
        "directions": list(study.continuation.directions),
        "closed_form_hz": f_m,
        "k_mean": summary.get("k_mean"),
        "m_eq": summary.get("m_eq"),
        "z1": z1,
        "resonance_rpm": 60.0 * f_m / z1 if z1 else float("nan"),
        "cpu_s": sum(d["cpu_s"] for d in done),
        "cpu_s_per_task": {f"{d['series']}/{d['direction']}": d["cpu_s"] for d in done},
        "wall_s": wall,
        "workers": n_workers,
        "points": len(rows),
    }
    (out / META).write_text(json.dumps(meta, indent=1) + "\n")
    return ContinuationSummary(out, len(rows), len(jobs), meta["cpu_s"], wall, n_workers,
                               sum(not r["periodic"] for r in rows))


@dataclass
class ContinuationSummary:
    out: Path
    points: int
    tasks: int
    cpu_s: float
    wall_s: float
    workers: int
    simulated: int
    failed: int = 0
    ran: int = 0

    def __post_init__(self):
        self.ran = self.points

    def __str__(self) -> str:
        return (f"{self.points} points in {self.tasks} continuation(s) on {self.workers} worker(s): "
                f"{self.cpu_s:.1f} s CPU, {self.wall_s:.1f} s wall; {self.simulated} point(s) "
                f"without a stable periodic orbit taken from a simulation; results in {self.out}")


def _csv(v) -> str:
    if v is None:
        return ""
    if isinstance(v, bool):
        return "1" if v else "0"
    if isinstance(v, float):
        return repr(v)
    s = str(v)
    return '"' + s.replace('"', "'") + '"' if ("," in s or '"' in s) else s


def read(results) -> tuple[list[dict], dict]:
    """The rows of continuation.csv (numbers as float, periodic as bool) and the metadata."""
    import csv

    results = Path(results)
    with open(results / CSV, newline="") as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        for k in COLUMNS:
            if k in ("series", "direction", "note"):
                continue
            if k == "periodic":
                r[k] = r[k] == "1"
            else:
                r[k] = float(r[k]) if r[k] not in ("", "None") else float("nan")
    return rows, json.loads((results / META).read_text())


def is_continuation(results) -> bool:
    return (Path(results) / CSV).is_file() and (Path(results) / META).is_file()


# The dynamic-factor axis is cut here (see `plot`).
CAP = 12.0


def plot(results, out_dir=None) -> list[Path]:
    """dynamic_factor.png: max Fn / F_static against the drive speed in rpm, each series up
    (solid, filled markers) and down (dashed, open markers), the points without a stable
    periodic orbit (taken from the simulation) marked x; vertical lines where the mesh
    frequency z1 n / 60 meets the closed-form mesh natural frequency f_m (3.19), f_m / 2
    (the second harmonic of the stiffness excitation) and 2 f_m (the principal parametric
    resonance)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows, meta = read(results)
    out_dir = Path(out_dir) if out_dir else Path(results)
    out_dir.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(8.0, 4.6))
    colours = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd"]
    # An unbounded response (a parametric instability of a mesh without backlash grows
    # until the simulation stops) would flatten every other curve: above CAP the axis is
    # cut and such points are drawn at the top with their value.
    cap = CAP if any(r["dynamic_factor"] > CAP for r in rows) else None
    series = list(dict.fromkeys(r["series"] for r in rows))
    for i, s in enumerate(series):
        c = colours[i % len(colours)]
        for d, style, face in (("up", "-", c), ("down", "--", "none")):
            pts = sorted((r for r in rows if r["series"] == s and r["direction"] == d),
                         key=lambda r: r["rpm"])
            if not pts:
                continue
            x = np.array([p["rpm"] for p in pts])
            y = np.array([p["dynamic_factor"] for p in pts])
            per = np.array([p["periodic"] for p in pts])
            if cap is not None:
                y = np.minimum(y, cap)
            ax.plot(x, y, style, color=c, lw=1.3, label=f"{s}, sweep {d}")
            ax.plot(x[per], y[per], "o", ms=4, color=c, mfc=face)
            ax.plot(x[~per], y[~per], "x", ms=6, color=c)
            if cap is not None:
                for p in pts:
                    if p["dynamic_factor"] > cap:
                        ax.annotate(f"{p['dynamic_factor']:.0f}", (p["rpm"], cap), xytext=(4, -10),
                                    textcoords="offset points", fontsize=7, color=c)
    n_res = meta.get("resonance_rpm", float("nan"))
    if math.isfinite(n_res):
        ymin, ymax = ax.get_ylim()
        xmax = max(r["rpm"] for r in rows) if rows else 0.0
        for k, lab in ((1.0, "f_z = f_m"), (0.5, "f_z = f_m / 2"), (2.0, "f_z = 2 f_m")):
            if k * n_res > 1.02 * xmax:
                continue
            ax.axvline(k * n_res, color="k", lw=0.9, ls=":" if k != 1.0 else "-.")
            ax.text(k * n_res, ymin + 0.55 * (ymax - ymin), f" {lab}\n {k * n_res:.0f} rpm",
                    va="center", ha="left", fontsize=8)
    if cap is not None:
        ax.set_ylim(0.0, cap * 1.04)
    ax.set_xlabel("drive speed n1 [rpm]")
    ax.set_ylabel("max Fn / F_static")
    f_m = meta.get("closed_form_hz", float("nan"))
    ax.set_title(f"{meta.get('study', '')}: dynamic factor, elastic contact; "
                 f"f_m = {f_m:.0f} Hz (closed form (3.19))", fontsize=10)
    ax.grid(alpha=0.3)
    ax.plot([], [], "kx", label="no stable periodic orbit: max of a simulation")
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    path = out_dir / "dynamic_factor.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return [path]
