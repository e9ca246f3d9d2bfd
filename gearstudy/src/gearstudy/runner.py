"""One FMU instance that runs study points one after another (fmi2Reset between them).

A point: fmi2SetupExperiment(start 0), its values set by name (Real, Integer, Enumeration,
Boolean), the initialisation, then

- if the FMU has a variable ``initialization`` (1 = rest, 2 = static equilibrium,
  3 = periodic), it is set to 3 unless the point sets it, and the window starts after
  ``periodic_settle`` (default 0);
- otherwise the run starts from rest and the window starts after the transient cut
  ``transient`` (default 100 ms: at 3000 rpm and 10 N m the TE peak to peak of the start-up
  transient falls ~10x per 20 ms and reaches its steady value, ~5e-9 m, by ~80 ms);

the cut is one doStep, then ``periods`` whole mesh periods ``2 pi / (z1 omega1)`` are sampled at
``samples_per_period`` points each and reduced (reduce.py). A failing call ends the point with
its FMI status and the FMU's messages in the row; the instance is reset (or re-created when a
reset is refused) for the next point.
"""

from __future__ import annotations

import math
import os
import shutil
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
from fmpy import calloc, extract, free, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)

from . import damping, reduce
from .units import Catalog

STATUS = ["OK", "Warning", "Discard", "Error", "Fatal", "Pending"]
INITIALIZATION = "initialization"  # FMI Enumeration parameter, when the FMU has it
PERIODIC = 3
REST = 1
#: words of the FMU's message when the start on the periodic orbit failed (src/sim/init.rs):
#: such a point is run again from rest with the cut [window] fallback_transient
PERIODIC_FAILED = ("no periodic orbit", "periodic orbit is unstable")
TEETH_DRIVING = "z1"
SPEED_INPUT = "omega1"
ENERGY_IN, ENERGY_LOSS = "E_in", "E_loss"
MEAN_FROM_ENERGY = {"P_in": ENERGY_IN, "P_loss": ENERGY_LOSS}
#: environment variable: a file that gets one line per FMU run (point key, pid); a diagnostic
#: used by the tests to count runs across worker processes
RUN_LOG_ENV = "GEARSTUDY_RUN_LOG"

META_COLUMNS = [
    ("point", "int64"),
    ("key", "string"),
    ("status", "string"),
    ("message", "string"),
    ("cpu_s", "float64"),
    ("worker", "string"),
    ("init", "string"),
    ("t_window", "float64"),
    ("mesh_period", "float64"),
]


def result_columns(settings: dict, catalog: Catalog) -> list[tuple[str, str]]:
    """Columns of a row: meta, the point's variables, then the figures (all float64)."""
    cols = list(META_COLUMNS)
    for n in settings["variables"]:
        t = catalog.variables[n].type
        cols.append((n, "float64" if t == "Real" else "bool" if t == "Boolean" else "int64"))
    cols.append(("efficiency", "float64"))
    for n in settings["outputs"]:
        if catalog.variables[n].causality == "output":
            cols += [(f"{n}.mean", "float64"), (f"{n}.p2p", "float64")]
        else:
            cols.append((n, "float64"))
    for n in settings["orders"]:
        cols += [(f"{n}.order{k}", "float64") for k in range(1, settings["window"]["n_orders"] + 1)]
    if "damping" in settings:
        cols += damping.columns(settings["damping"]["modes"])
    seen, out = set(), []
    for c in cols:
        if c[0] not in seen:
            seen.add(c[0])
            out.append(c)
    return out


class PointRunner:
    """An extracted FMU and one reusable instance (not thread-safe: one per thread)."""

    def __init__(self, fmu_path, unzip_dir: str | None = None, name: str = "gearstudy"):
        self.fmu_path = str(fmu_path)
        md = read_model_description(self.fmu_path)
        self.catalog = Catalog(md)
        self._own_dir = unzip_dir is None
        self.unzip_dir = unzip_dir or extract(self.fmu_path)
        self.name = name
        self.has_initialization = INITIALIZATION in self.catalog
        self.log: list[tuple[int, str, str]] = []
        self.slave: FMU2Slave | None = None
        self.runs = 0
        self.worker_label = f"{os.uname().nodename}:{os.getpid()}"

    # -- instance life cycle ----------------------------------------------------------
    def _logger(self, env, instance_name, status, category, message):
        self.log.append(
            (
                int(status),
                (category or b"").decode("utf-8", "replace"),
                (message or b"").decode("utf-8", "replace"),
            )
        )

    def _instantiate(self) -> None:
        cat = self.catalog
        self.slave = FMU2Slave(
            guid=cat.guid,
            unzipDirectory=self.unzip_dir,
            modelIdentifier=cat.model_identifier,
            instanceName=self.name,
        )
        cb = fmi2CallbackFunctions()
        self._logger_fn = fmi2CallbackLoggerTYPE(self._logger)  # kept alive with the instance
        cb.logger = self._logger_fn
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        self._callbacks = cb
        self.slave.instantiate(callbacks=cb, loggingOn=False)
        self._enable_warnings()

    def _enable_warnings(self) -> None:
        try:
            self.slave.setDebugLogging(True, ["logStatusWarning"])
        except FMICallException:
            pass  # an FMU without that category: its errors still reach the logger

    def _ready(self) -> FMU2Slave:
        if self.slave is None:
            self._instantiate()
        return self.slave

    def _recycle(self, terminate: bool) -> None:
        """Bring the instance back to the instantiated state for the next point."""
        s = self.slave
        if s is None:
            return
        try:
            if terminate:
                s.terminate()
            s.reset()
            self._enable_warnings()
        except Exception:
            self._discard_instance()

    def _discard_instance(self) -> None:
        s, self.slave = self.slave, None
        if s is not None:
            try:
                s.freeInstance()
            except Exception:
                pass

    def close(self) -> None:
        self._discard_instance()
        if self._own_dir:
            shutil.rmtree(self.unzip_dir, ignore_errors=True)

    # -- one point ------------------------------------------------------------------
    def _set(self, values: dict) -> None:
        groups: dict[str, tuple[list, list]] = {}
        for name, value in values.items():
            v = self.catalog.variables[name]
            kind = "Integer" if v.type == "Enumeration" else v.type
            vrs, vals = groups.setdefault(kind, ([], []))
            vrs.append(v.value_reference)
            vals.append(value)
        s = self.slave
        for kind, (vrs, vals) in groups.items():
            if kind == "Real":
                s.setReal(vrs, [float(x) for x in vals])
            elif kind == "Integer":
                s.setInteger(vrs, [int(x) for x in vals])
            elif kind == "Boolean":
                s.setBoolean(vrs, [bool(x) for x in vals])
            else:
                raise TypeError(f"{kind} variables cannot be set by a study")

    def _get(self, names: list[str]) -> np.ndarray:
        """Values of variables of any numeric type, as float64, in the order of names."""
        out = np.empty(len(names))
        by: dict[str, list[int]] = {}
        for i, n in enumerate(names):
            t = self.catalog.variables[n].type
            by.setdefault("Integer" if t == "Enumeration" else t, []).append(i)
        vr = [self.catalog.variables[n].value_reference for n in names]
        for t, idx in by.items():
            refs = [vr[i] for i in idx]
            vals = (
                self.slave.getReal(refs)
                if t == "Real"
                else self.slave.getInteger(refs)
                if t == "Integer"
                else self.slave.getBoolean(refs)
            )
            out[idx] = np.asarray(vals, dtype=float)
        return out

    def run(self, point: dict, settings: dict, index: int = -1, key: str = "") -> dict:
        """Run one point; returns its row (column name -> value), never raises for a
        failing point."""
        columns = settings["_columns"]
        row = {c: _missing(t) for c, t in columns}
        row.update(point)
        row.update(point=index, key=key, worker=self.worker_label, message="")
        win = settings["window"]
        t_start = time.thread_time()
        terminate = False
        self.log.clear()
        try:
            s = self._ready()
            self._log_run(key)
            s.setupExperiment(tolerance=settings["tolerance"], startTime=0.0)
            values = dict(point)
            if self.has_initialization and INITIALIZATION not in values:
                values[INITIALIZATION] = PERIODIC
            self._set(values)
            s.enterInitializationMode()
            periodic = self.has_initialization and int(values.get(INITIALIZATION)) == PERIODIC
            fallback = None
            try:
                s.exitInitializationMode()
            except FMICallException as e:
                msg = self._messages(min_status=2) or str(e)
                if not (periodic and INITIALIZATION not in point
                        and any(w in msg for w in PERIODIC_FAILED)):
                    raise
                # the periodic start failed: from rest, with a transient long enough to
                # reach the steady state ([window] fallback_transient)
                fallback = msg
                self._recycle(False)
                s = self._ready()
                self.log.clear()
                s.setupExperiment(tolerance=settings["tolerance"], startTime=0.0)
                values[INITIALIZATION] = REST
                self._set(values)
                s.enterInitializationMode()
                s.exitInitializationMode()
                periodic = False
            terminate = True
            z1, w1 = self._get([TEETH_DRIVING, SPEED_INPUT])
            if not (w1 != 0.0 and math.isfinite(w1)) or z1 <= 0:
                raise ValueError(
                    f"{SPEED_INPUT} = {w1} rad/s: no mesh period; give a speed != 0"
                )
            t_mesh = 2.0 * math.pi / (z1 * abs(w1))
            if periodic:
                cut, unit = win["periodic_settle"], win["periodic_settle_unit"]
                row["init"] = "periodic"
            elif fallback is not None:
                cut, unit = win["fallback_transient"], win["fallback_transient_unit"]
                row["init"] = "rest+cut (periodic start failed)"
            else:
                cut, unit = win["transient"], win["transient_unit"]
                row["init"] = "rest+cut"
            t0 = cut * t_mesh if unit == "periods" else cut
            row["mesh_period"], row["t_window"] = t_mesh, t0
            row.update(self._window(t0, t_mesh, settings))
            row["status"] = "OK"
            if fallback is not None:
                self.log.append((1, "", f"the start on the periodic orbit failed ({fallback}); "
                                        f"started from rest, window after {t0:g} s"))
        except FMICallException as e:
            row["status"] = STATUS[e.status] if 0 <= e.status < len(STATUS) else str(e.status)
            row["message"] = self._messages(min_status=2) or str(e)
        except Exception as e:  # a study goes on: the row carries the error
            row["status"] = "Error"
            row["message"] = f"{type(e).__name__}: {e}"
            terminate = False
        if "damping" in settings:
            # the modal damping of the point's periodic orbit (damping.py), whatever the run
            try:
                row.update(damping.modal(point, self.catalog, settings["damping"]["program"],
                                         settings["damping"]["modes"],
                                         warn=lambda m: self.log.append((1, "", m))))
            except Exception as e:
                self.log.append((1, "", f"damping: {type(e).__name__}: {e}"))
        warnings = [m for st, _, m in self.log if st == 1]
        if row["status"] == "OK" and warnings:
            row["status"] = "Warning"
            row["message"] = " | ".join(warnings)
        self._recycle(terminate and row["status"] in ("OK", "Warning"))
        row["cpu_s"] = time.thread_time() - t_start
        self.runs += 1
        return row

    def _window(self, t0: float, t_mesh: float, settings: dict) -> dict:
        win = settings["window"]
        s = self.slave
        if t0 > 0.0:
            s.doStep(0.0, t0)
        n_per, m = win["periods"], win["samples_per_period"]
        n = n_per * m
        h = t_mesh / m
        names = list(dict.fromkeys(list(settings["outputs"]) + list(settings["orders"])))
        sampled = [x for x in names if self.catalog.variables[x].causality == "output"]
        fixed = [x for x in names if x not in sampled]
        energy = [ENERGY_IN, ENERGY_LOSS] if ENERGY_IN in self.catalog and ENERGY_LOSS in self.catalog else []
        read = sampled + energy
        y = np.empty((n + 1, len(read)))
        if all(self.catalog.variables[x].type == "Real" for x in read):
            vrs = [self.catalog.variables[x].value_reference for x in read]
            get = lambda: s.getReal(vrs)  # noqa: E731 - one call per sample
        else:
            get = lambda: self._get(read)  # noqa: E731
        y[0] = get()
        for j in range(n):
            s.doStep(t0 + j * h, h)
            y[j + 1] = get()
        out: dict = {}
        col = {x: y[:, i] for i, x in enumerate(read)}
        de = {}
        if energy:
            de = {x: col[x][-1] - col[x][0] for x in energy}
            out["efficiency"] = reduce.efficiency_from_energies(de[ENERGY_IN], de[ENERGY_LOSS])
        elif "P_in" in col and "P_loss" in col:
            out["efficiency"] = 1.0 - reduce.mean_over_periods(col["P_loss"]) / reduce.mean_over_periods(col["P_in"])
        t_win = n * h
        for x in settings["outputs"]:
            if x in fixed:
                out[x] = float(self._get([x])[0])
                continue
            e = MEAN_FROM_ENERGY.get(x)
            out[f"{x}.mean"] = de[e] / t_win if e in de else reduce.mean_over_periods(col[x])
            out[f"{x}.p2p"] = reduce.peak_to_peak(col[x])
        for x in settings["orders"]:
            for k, a in enumerate(reduce.order_amplitudes(col[x], n_per, win["n_orders"]), 1):
                out[f"{x}.order{k}"] = a
        return out

    def _messages(self, min_status: int) -> str:
        return " | ".join(m for st, _, m in self.log if st >= min_status)

    def _log_run(self, key: str) -> None:
        path = os.environ.get(RUN_LOG_ENV)
        if path:
            with open(path, "a") as f:
                f.write(f"{key} {os.getpid()}\n")


def _missing(t: str):
    return {"float64": float("nan"), "int64": None, "bool": None}.get(t, None)


class RunnerPool:
    """One PointRunner per thread over one extracted copy of the FMU (a Dask worker may run
    several threads)."""

    def __init__(self, fmu_path, workdir: str | None = None):
        self.fmu_path = str(fmu_path)
        self._dir = tempfile.mkdtemp(prefix="gearstudy-fmu-", dir=workdir)
        self.unzip_dir = extract(self.fmu_path, unzipdir=self._dir)
        self._local = threading.local()
        self._all: list[PointRunner] = []
        self._lock = threading.Lock()

    def runner(self) -> PointRunner:
        r = getattr(self._local, "runner", None)
        if r is None:
            r = PointRunner(self.fmu_path, unzip_dir=self.unzip_dir, name=f"gearstudy-{threading.get_ident()}")
            self._local.runner = r
            with self._lock:
                self._all.append(r)
        return r

    def run_chunk(self, items: list[tuple[int, str, dict]], settings: dict) -> list[dict]:
        r = self.runner()
        return [r.run(p, settings, index=i, key=k) for i, k, p in items]

    def close(self) -> None:
        for r in self._all:
            r.close()
        shutil.rmtree(self._dir, ignore_errors=True)


def prepare_settings(settings: dict, catalog: Catalog) -> dict:
    """Settings as a runner needs them (with the column list)."""
    s = dict(settings)
    s["_columns"] = result_columns(settings, catalog)
    return s


def run_serial(fmu_path, items, settings) -> list[dict]:
    """All points in this thread with one reused instance (no Dask)."""
    pool = RunnerPool(fmu_path)
    try:
        return pool.run_chunk(items, settings)
    finally:
        pool.close()


__all__ = ["PointRunner", "RunnerPool", "run_serial", "result_columns", "prepare_settings"]
