"""Refactoring guard: records what the packaged .fmu does on a fixed set of runs and
compares two such recordings bit for bit.

A refactor (a change that must not change behaviour) is checked like this:

    .venv/bin/python scripts/golden_runs.py record target/golden-before   # old code
    ... refactor, rebuild the .fmu (cargo run --release --bin package-fmu) ...
    .venv/bin/python scripts/golden_runs.py record target/golden-after
    .venv/bin/python scripts/golden_runs.py compare target/golden-before target/golden-after

A change that alters the byte layout of serialized FMU states on purpose (and bumps the
layout version) compares with `compare --except-state-bytes A B`: everything else must
still be identical. Variables that only one recording has (added by the change) are left
out of the comparison.

What is recorded per run: every output and calculated parameter (Real as the
float's hex, Integer, Boolean) after initialization and after every doStep, the
status of every call, every log message (status, category, text) and a hash of
the serialized FMU state at the end. The runs cover the default pair, the
periodic start, a spur pair, another pair, each friction law, a held input step,
input derivatives, a rollback, serialization into a new instance, the real-time
mode and refused input. The recordings are not references for physics (the tests
hold those); they only say "the same as before", which is what a refactor must
keep.
"""

from __future__ import annotations

import hashlib
import json
import sys
from pathlib import Path
from typing import Callable

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from helpers.fmu_harness import FmuPackage, Instance, build_fmu, call_status  # noqa: E402

H = 1e-4


def snapshot(inst: Instance) -> dict:
    pkg = inst.pkg
    names = [v.name for v in pkg.md.modelVariables
             if v.causality in ("output", "calculatedParameter")]
    values = inst.get(names)
    return {n: (float(x).hex() if pkg.vars[n].type == "Real" else int(x))
            for n, x in values.items()}


class Run:
    """One instance driven through a scripted run, everything observable recorded."""

    def __init__(self, pkg: FmuPackage, name: str):
        self.inst = pkg.instance(name, logging_on=True)
        self.rows: list[dict] = []

    def call(self, what: str, fn: Callable, *args) -> int:
        status = call_status(fn, *args)
        self.rows.append({"call": what, "status": status})
        return status

    def init(self, params: dict, tolerance: float | None = None) -> int:
        s = self.inst.slave
        self.call("setup", s.setupExperiment, tolerance, 0.0, None)
        if params:
            self.call(f"set {sorted(params.items())}", self.inst.set, params)
        self.call("enter", s.enterInitializationMode)
        st = self.call("exit", s.exitInitializationMode)
        self.inst.time = 0.0
        if st <= 1:
            self.rows.append({"t": 0.0, "y": snapshot(self.inst)})
        return st

    def step(self, n: int, h: float = H, before: Callable | None = None) -> int:
        for _ in range(n):
            if before:
                before(self.inst.time)
            st = self.call(f"doStep {self.inst.time!r}", self.inst.slave.doStep,
                           self.inst.time, h, 1)
            if st > 1:
                return st
            self.inst.time += h
            self.rows.append({"t": self.inst.time, "y": snapshot(self.inst)})
        return 0

    def finish(self) -> list:
        s = self.inst.slave
        try:
            state = s.getFMUstate()
            blob = s.serializeFMUstate(state)
            self.rows.append({"state_sha256": hashlib.sha256(bytes(blob)).hexdigest()})
            s.freeFMUstate(state)
        except Exception as e:  # an instance in the error state has no state to give
            self.rows.append({"state": f"refused: {type(e).__name__}"})
        self.rows.append({"log": [[r.status, r.category, r.message] for r in self.inst.log]})
        self.inst.free()
        return self.rows


def simple(pkg: FmuPackage, name: str, params: dict, n: int = 200, h: float = H,
           tolerance: float | None = None) -> list:
    r = Run(pkg, name)
    if r.init(params, tolerance) <= 1:
        r.step(n, h)
    return r.finish()


def cases(pkg: FmuPackage) -> dict[str, Callable[[], list]]:
    def held_step() -> list:
        r = Run(pkg, "held_step")
        r.init({})

        def before(t: float) -> None:
            if abs(t - 0.01) < H / 2:
                r.inst.set({"omega1": 320.0, "T_load": 15.0})
        r.step(250, before=before)
        return r.finish()

    def closed_loop() -> list:
        r = Run(pkg, "closed_loop")
        r.init({"initialization": 3})
        import math

        def before(t: float) -> None:
            w = 314.159 * (1 + 0.01 * math.sin(2 * math.pi * 50 * t))
            r.inst.set({"omega1": w, "T_load": 10.0 + 5.0 * math.cos(2 * math.pi * 30 * t)})
        r.step(200, before=before)
        return r.finish()

    def derivatives() -> list:
        r = Run(pkg, "derivatives")
        r.init({})
        vr = pkg.vr("omega1")

        def before(t: float) -> None:
            r.inst.set({"omega1": 314.159 + 100.0 * t})
            r.call("setRealInputDerivatives", r.inst.slave.setRealInputDerivatives,
                   [vr], [1], [100.0])
        r.step(100, before=before)
        der = r.inst.slave.getRealOutputDerivatives(
            [pkg.vr(n) for n in ("T1", "omega2", "Fn")], [1, 1, 1])
        r.rows.append({"output_derivatives": [float(x).hex() for x in der]})
        return r.finish()

    def rollback() -> list:
        r = Run(pkg, "rollback")
        r.init({})
        r.step(100)
        s = r.inst.slave
        state = s.getFMUstate()
        r.step(50)
        s.setFMUstate(state)
        r.inst.time = 0.01
        r.rows.append({"rolled back to": 0.01, "y": snapshot(r.inst)})
        r.inst.set({"T_load": 25.0})
        r.step(50)
        s.freeFMUstate(state)
        return r.finish()

    def serialized() -> list:
        a = Run(pkg, "serialize_a")
        a.init({"friction_law": 3})
        a.step(80)
        s = a.inst.slave
        state = s.getFMUstate()
        blob = s.serializeFMUstate(state)
        s.freeFMUstate(state)
        b = Run(pkg, "serialize_b")
        sb = b.inst.slave
        b.call("setup", sb.setupExperiment, None, 0.0, None)
        b.call("enter", sb.enterInitializationMode)
        b.call("exit", sb.exitInitializationMode)
        st = sb.deSerializeFMUstate(blob)
        sb.setFMUstate(st)
        sb.freeFMUstate(st)
        b.inst.time = a.inst.time
        b.step(80)
        return a.finish() + b.finish()

    def refused() -> list:
        rows = []
        for bad in ({"mu": 2.0}, {"z1": 3}, {"omega1_filter_frequency": -1.0},
                    {"b": 0.0}, {"x2": 0.0, "z2": 61, "z1": 23},
                    # the rules of the parameter tables (Params::validate)
                    {"m1": 0.0}, {"J2": 0.0}, {"k2.z": -1.0}, {"d1.x": -1.0, "k1.y": -1.0},
                    {"eta_oil": 0.0}, {"nu1": 0.6}, {"Ra": 0.0}, {"E2": 0.0},
                    {"friction_law": 5}):
            r = Run(pkg, "refused")
            r.init(bad)
            rows += r.finish()
        return rows

    def lift_off() -> list:
        rows = []
        for mode in (1, 2):
            r = Run(pkg, "lift_off")
            r.init({"on_lift_off": mode, "initialization": 2})

            def before(t: float) -> None:
                if abs(t - 0.005) < H / 2:
                    r.inst.set({"T_load": -300.0})
            r.step(150, before=before)
            rows += r.finish()
        return rows

    return {
        "default": lambda: simple(pkg, "default", {}, 300),
        "default_h1e-5": lambda: simple(pkg, "h1e-5", {}, 300, h=1e-5),
        "periodic": lambda: simple(pkg, "periodic", {"initialization": 3}, 200),
        "static_rtol1e-9": lambda: simple(pkg, "static", {"initialization": 2}, 100,
                                          tolerance=1e-9),
        "spur": lambda: simple(pkg, "spur", {"beta": 0.0}, 200),
        "other_pair_law3": lambda: simple(pkg, "other", {
            "z1": 23, "z2": 57, "m_n": 0.003, "beta": 0.3, "b": 0.03,
            "friction_law": 3, "T_load": 30.0}, 200),
        "law2": lambda: simple(pkg, "law2", {"friction_law": 2, "v_reg": 0.05}, 150),
        "law4": lambda: simple(pkg, "law4", {"friction_law": 4, "T_load": 40.0}, 150),
        "spur_law4": lambda: simple(pkg, "spur4", {"beta": 0.0, "friction_law": 4}, 100),
        "realtime": lambda: simple(pkg, "rt", {"h_fixed": 2.5e-5, "initialization": 3}, 200),
        "held_step": held_step,
        "closed_loop": closed_loop,
        "derivatives": derivatives,
        "rollback": rollback,
        "serialized": serialized,
        "refused": refused,
        "lift_off": lift_off,
    }


def record(out: Path) -> None:
    pkg = FmuPackage(build_fmu(ROOT, quiet=True))
    out.mkdir(parents=True, exist_ok=True)
    for name, run in cases(pkg).items():
        rows = run()
        (out / f"{name}.json").write_text(json.dumps(rows, indent=0))
        print(f"{name}: {len(rows)} rows")


def only_common(ra: list, rb: list) -> tuple[list, list]:
    """Rows with the recorded values restricted to the variables both recordings have (a
    change that adds a variable compares what existed before)."""
    def keys(rows):
        return set().union(*(set(x["y"]) for x in rows if "y" in x)) if rows else set()
    common = keys(ra) & keys(rb)

    def cut(rows):
        return [{**x, "y": {k: v for k, v in x["y"].items() if k in common}} if "y" in x else x
                for x in rows]
    return cut(ra), cut(rb)


def compare(a: Path, b: Path, except_state_bytes: bool = False) -> int:
    bad = 0
    names = sorted(p.name for p in a.glob("*.json"))
    if names != sorted(p.name for p in b.glob("*.json")):
        print(f"different sets of runs: {names} vs {sorted(p.name for p in b.glob('*.json'))}")
        return 1
    for n in names:
        ra, rb = json.loads((a / n).read_text()), json.loads((b / n).read_text())
        if except_state_bytes:
            ra = [x for x in ra if "state_sha256" not in x]
            rb = [x for x in rb if "state_sha256" not in x]
        ra, rb = only_common(ra, rb)
        if ra == rb:
            print(f"{n}: identical ({len(ra)} rows)")
            continue
        bad += 1
        first = next((i for i, (x, y) in enumerate(zip(ra, rb)) if x != y), min(len(ra), len(rb)))
        print(f"{n}: DIFFERENT from row {first} of {len(ra)}/{len(rb)}")
        if first < min(len(ra), len(rb)):
            x, y = ra[first], rb[first]
            if "y" in x and "y" in y:
                diff = {k: (x["y"].get(k), y["y"].get(k)) for k in set(x["y"]) | set(y["y"])
                        if x["y"].get(k) != y["y"].get(k)}
                print(f"   t = {x.get('t')}: {len(diff)} values differ, e.g. "
                      f"{dict(list(diff.items())[:3])}")
            else:
                print(f"   {json.dumps(x)[:300]}\n   {json.dumps(y)[:300]}")
    print("all identical" if bad == 0 else f"{bad} runs differ")
    return 1 if bad else 0


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "record":
        record(Path(sys.argv[2]))
    elif len(sys.argv) == 4 and sys.argv[1] == "compare":
        sys.exit(compare(Path(sys.argv[2]), Path(sys.argv[3])))
    elif len(sys.argv) == 5 and sys.argv[1:3] == ["compare", "--except-state-bytes"]:
        sys.exit(compare(Path(sys.argv[3]), Path(sys.argv[4]), except_state_bytes=True))
    else:
        print(__doc__)
        sys.exit(2)
