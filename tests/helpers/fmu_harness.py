"""A small harness around FMPy's low-level FMI 2.0 API (fmpy.fmi2.FMU2Slave) for
the packaged GearedRotor.fmu: build, extract, instantiate with a logger that
collects messages, set/get by variable name, step with a fixed communication
step and record every output at every communication point.

Used by the pytest suite, the main job (scripts/main_job.py) and the benchmark
(benches/fmpy_overhead.py).
"""

from __future__ import annotations

import math
import subprocess
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Iterable, Mapping, Sequence

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import (
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
)
from fmpy import calloc, free

REPO_ROOT = Path(__file__).resolve().parents[2]
FMU_PATH = REPO_ROOT / "target" / "fmu" / "GearedRotor.fmu"

STATUS_NAMES = ["OK", "Warning", "Discard", "Error", "Fatal", "Pending"]
FMI2_OK, FMI2_WARNING, FMI2_DISCARD, FMI2_ERROR, FMI2_FATAL = 0, 1, 2, 3, 4


def build_fmu(repo_root: Path = REPO_ROOT, quiet: bool = False) -> Path:
    """Build the .fmu with the project's packager (cargo run --release --bin
    package-fmu) and return its path. Raises CalledProcessError on failure."""
    cmd = ["cargo", "run", "--release", "--quiet", "--bin", "package-fmu"]
    subprocess.run(
        cmd,
        cwd=repo_root,
        check=True,
        stdout=subprocess.DEVNULL if quiet else None,
    )
    fmu = repo_root / "target" / "fmu" / "GearedRotor.fmu"
    if not fmu.is_file():
        raise FileNotFoundError(f"{' '.join(cmd)} did not write {fmu}")
    return fmu


@dataclass
class LogRecord:
    instance: str
    status: int
    category: str
    message: str

    def __str__(self) -> str:
        return f"[{STATUS_NAMES[self.status] if 0 <= self.status < 6 else self.status}] " \
               f"{self.category}: {self.message}"


# FMI 3.0 type names as the FMI 2.0 ones the suite uses (GearedRotor-fmi3.fmu has the same
# variables; helpers/fmi3_compat.py maps the calls).
FMI3_TYPES = {"Float64": "Real", "Int32": "Integer"}


class FmuPackage:
    """The extracted .fmu and its model description (extract once, instantiate often).
    Either version: `fmi3` says which."""

    def __init__(self, fmu_path: Path, unzip_dir: Path | None = None):
        self.fmu_path = Path(fmu_path)
        self.md = read_model_description(str(self.fmu_path))
        self.fmi3 = self.md.fmiVersion.startswith("3")
        if self.fmi3:
            for v in self.md.modelVariables:
                v.type = FMI3_TYPES.get(v.type, v.type)
        if unzip_dir is None:
            unzip_dir = Path(extract(str(self.fmu_path)))
        self.unzip_dir = Path(unzip_dir)
        self.vars = {v.name: v for v in self.md.modelVariables}
        self.outputs = [v for v in self.md.modelVariables if v.causality == "output"]
        self.real_outputs = [v.name for v in self.outputs if v.type == "Real"]
        self.int_outputs = [v.name for v in self.outputs if v.type == "Integer"]
        self.bool_outputs = [v.name for v in self.outputs if v.type == "Boolean"]

    def fmi_name(self, fmi2_name: str) -> str:
        """The name of an FMI 2.0 function in this package's FMI version (for messages)."""
        if not self.fmi3:
            return fmi2_name
        special = {"fmi2DeSerializeFMUstate": "fmi3DeserializeFMUState",
                   "fmi2GetFMUstate": "fmi3GetFMUState", "fmi2SetFMUstate": "fmi3SetFMUState",
                   "fmi2GetReal": "fmi3GetFloat64", "fmi2SetReal": "fmi3SetFloat64",
                   "fmi2SetupExperiment": "fmi3EnterInitializationMode"}
        return special.get(fmi2_name, fmi2_name.replace("fmi2", "fmi3", 1))

    def vr(self, name: str) -> int:
        return self.vars[name].valueReference

    def start(self, name: str) -> float:
        v = self.vars[name]
        return float(v.start) if v.type == "Real" else int(v.start)

    def instance(self, name: str = "inst", logging_on: bool = False) -> "Instance":
        return Instance(self, name, logging_on=logging_on)


class Instance:
    """One FMU2Slave instance with a logger that collects the FMU's messages.

    Messages are stored unformatted (no printf proxy): the FMU promises never to
    emit a raw '%' (fmu.md), and a test checks exactly that.
    """

    def __init__(self, pkg: FmuPackage, name: str = "inst", logging_on: bool = False):
        self.pkg = pkg
        self.name = name
        self.log: list[LogRecord] = []
        if pkg.fmi3:
            from helpers.fmi3_compat import Fmi3Slave

            self.slave = Fmi3Slave(
                enumerations={v.valueReference for v in pkg.md.modelVariables
                              if v.type == "Enumeration"},
                guid=pkg.md.guid,
                unzipDirectory=str(pkg.unzip_dir),
                modelIdentifier=pkg.md.coSimulation.modelIdentifier,
                instanceName=name,
            )
            self.slave.instantiate(
                loggingOn=logging_on,
                logMessage=lambda env, status, cat, msg: self._logger(
                    env, name.encode(), status, cat, msg),
            )
            self.time = 0.0
            self.freed = False
            return
        self.slave = FMU2Slave(
            guid=pkg.md.guid,
            unzipDirectory=str(pkg.unzip_dir),
            modelIdentifier=pkg.md.coSimulation.modelIdentifier,
            instanceName=name,
        )
        cb = fmi2CallbackFunctions()
        # keep the ctypes callback objects alive as long as the instance
        self._logger_fn = fmi2CallbackLoggerTYPE(self._logger)
        cb.logger = self._logger_fn
        cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        cb.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        self._callbacks = cb
        self.slave.instantiate(callbacks=cb, loggingOn=logging_on)
        self.time = 0.0
        self.freed = False

    # -- logging ---------------------------------------------------------
    def _logger(self, env, instance_name, status, category, message):
        self.log.append(
            LogRecord(
                instance=(instance_name or b"").decode("utf-8", "replace"),
                status=int(status),
                category=(category or b"").decode("utf-8", "replace"),
                message=(message or b"").decode("utf-8", "replace"),
            )
        )

    def messages(self, min_status: int = 0) -> list[str]:
        return [r.message for r in self.log if r.status >= min_status]

    def log_text(self) -> str:
        return "\n".join(str(r) for r in self.log)

    # -- life cycle ------------------------------------------------------
    def initialize(
        self,
        params: Mapping[str, float] | None = None,
        start_time: float = 0.0,
        tolerance: float | None = None,
        stop_time: float | None = None,
    ) -> None:
        self.slave.setupExperiment(tolerance=tolerance, startTime=start_time, stopTime=stop_time)
        if params:
            self.set(params)
        self.slave.enterInitializationMode()
        self.slave.exitInitializationMode()
        self.time = start_time

    def free(self) -> None:
        if not self.freed:
            self.slave.fmi2FreeInstance(self.slave.component)
            self.freed = True

    def terminate_and_free(self) -> None:
        try:
            self.slave.terminate()
        finally:
            self.free()

    # -- values ----------------------------------------------------------
    def set(self, values: Mapping[str, float | int | bool]) -> None:
        reals, ints, bools = [], [], []
        for name, value in values.items():
            v = self.pkg.vars[name]
            if v.type == "Real":
                reals.append((v.valueReference, float(value)))
            elif v.type in ("Integer", "Enumeration"):
                # FMI 2.0: Enumerations are written with fmi2SetInteger
                ints.append((v.valueReference, int(value)))
            elif v.type == "Boolean":
                bools.append((v.valueReference, bool(value)))
            else:
                raise TypeError(f"{name}: unsupported type {v.type}")
        if reals:
            self.slave.setReal([r[0] for r in reals], [r[1] for r in reals])
        if ints:
            self.slave.setInteger([r[0] for r in ints], [r[1] for r in ints])
        if bools:
            self.slave.setBoolean([r[0] for r in bools], [r[1] for r in bools])

    def get(self, names: Sequence[str]) -> dict[str, float]:
        by_type: dict[str, list[str]] = {"Real": [], "Integer": [], "Boolean": []}
        for n in names:
            t = self.pkg.vars[n].type
            by_type["Integer" if t == "Enumeration" else t].append(n)
        out: dict[str, float] = {}
        if by_type["Real"]:
            vals = self.slave.getReal([self.pkg.vr(n) for n in by_type["Real"]])
            out.update(zip(by_type["Real"], vals))
        if by_type["Integer"]:
            vals = self.slave.getInteger([self.pkg.vr(n) for n in by_type["Integer"]])
            out.update(zip(by_type["Integer"], vals))
        if by_type["Boolean"]:
            vals = self.slave.getBoolean([self.pkg.vr(n) for n in by_type["Boolean"]])
            out.update(zip(by_type["Boolean"], vals))
        return out

    def get1(self, name: str) -> float:
        return self.get([name])[name]

    def do_step(self, h: float, no_set_prior: bool = True) -> None:
        self.slave.doStep(self.time, h, 1 if no_set_prior else 0)
        self.time += h  # the master's own bookkeeping (FMPy sums steps too)


def call_status(fn: Callable, *args, **kwargs) -> int:
    """Run an FMPy call; return the FMI status (0 when FMPy raised nothing)."""
    try:
        fn(*args, **kwargs)
    except FMICallException as e:
        return e.status
    return FMI2_OK


@dataclass
class Trajectory:
    """Outputs recorded at communication points: t and one array per variable."""

    t: np.ndarray
    data: dict[str, np.ndarray] = field(default_factory=dict)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.data[name]

    def names(self) -> list[str]:
        return list(self.data)

    def at_index(self, i: int) -> dict[str, float]:
        return {k: v[i] for k, v in self.data.items()}


class Recorder:
    """Reads all outputs (Real, Integer, Boolean) with one call per type."""

    def __init__(self, inst: Instance, names: Iterable[str] | None = None):
        pkg = inst.pkg
        names = list(names) if names is not None else (
            pkg.real_outputs + pkg.int_outputs + pkg.bool_outputs
        )
        self.inst = inst
        self.real = [n for n in names if pkg.vars[n].type == "Real"]
        self.int = [n for n in names if pkg.vars[n].type == "Integer"]
        self.bool = [n for n in names if pkg.vars[n].type == "Boolean"]
        self.real_vr = [pkg.vr(n) for n in self.real]
        self.int_vr = [pkg.vr(n) for n in self.int]
        self.bool_vr = [pkg.vr(n) for n in self.bool]
        self.t: list[float] = []
        self.rows_r: list[list[float]] = []
        self.rows_i: list[list[int]] = []
        self.rows_b: list[list[int]] = []

    def sample(self) -> None:
        s = self.inst.slave
        self.t.append(self.inst.time)
        self.rows_r.append(s.getReal(self.real_vr) if self.real_vr else [])
        self.rows_i.append(s.getInteger(self.int_vr) if self.int_vr else [])
        self.rows_b.append(s.getBoolean(self.bool_vr) if self.bool_vr else [])

    def trajectory(self) -> Trajectory:
        tr = Trajectory(t=np.array(self.t))
        r = np.array(self.rows_r, dtype=float).reshape(len(self.t), len(self.real))
        i = np.array(self.rows_i, dtype=np.int64).reshape(len(self.t), len(self.int))
        b = np.array(self.rows_b, dtype=np.int64).reshape(len(self.t), len(self.bool))
        for k, n in enumerate(self.real):
            tr.data[n] = r[:, k]
        for k, n in enumerate(self.int):
            tr.data[n] = i[:, k]
        for k, n in enumerate(self.bool):
            tr.data[n] = b[:, k] != 0
        return tr


def run(
    pkg: FmuPackage,
    t_end: float,
    h: float,
    params: Mapping[str, float] | None = None,
    tolerance: float | None = None,
    record: Iterable[str] | None = None,
    record_every: int = 1,
    inputs: Callable[[float], Mapping[str, float] | None] | None = None,
    name: str = "run",
) -> Trajectory:
    """Simulate 0..t_end with a fixed communication step h (n = round(t_end/h)
    steps, the master's time summed step by step as FMPy does), sampling the
    outputs after initialisation and after every `record_every`-th step.

    `inputs(t)` is called before each doStep at communication point t and may
    return input values to set (zero-order hold, as FMPy's Input does).
    """
    inst = pkg.instance(name)
    try:
        inst.initialize(params, tolerance=tolerance)
        rec = Recorder(inst, record)
        rec.sample()
        n = int(round(t_end / h))
        for k in range(n):
            if inputs is not None:
                u = inputs(inst.time)
                if u:
                    inst.set(u)
            inst.do_step(h)
            if (k + 1) % record_every == 0 or k + 1 == n:
                rec.sample()
        return rec.trajectory()
    finally:
        inst.terminate_and_free()


def whole_period_window(t: np.ndarray, t_start: float, period: float) -> tuple[float, float, int]:
    """The longest window [t_start, t_start + n period] inside the samples."""
    n = int(math.floor((t[-1] - t_start) / period + 1e-9))
    if n < 1:
        raise ValueError("less than one whole period after t_start")
    return t_start, t_start + n * period, n
