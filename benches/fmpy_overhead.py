#!/usr/bin/env python3
"""CPU cost of the default case through FMPy, per simulated 10 ms, at the
default tolerance; medians over repeats. Printed as figures, nothing asserted.

Measured in this process (time.process_time, 1 thread):
  - fmpy.simulate_fmu (FMPy's own master loop and recorder of all outputs,
    output interval = H; the FMU extracted and its description read beforehand)
  - a bare FMU2Slave loop (doStep + one getReal of all Real outputs per step),
    and the part of it spent inside fmi2DoStep (= the model + RADAU5 + the
    C ABI shell + one ctypes call): the rest is what the Python master adds
  - the number of internal RADAU5 steps per doStep, when the FMU reports its
    statistics on the logSolver category ("naccpt=N" / "nstep=N")
  - the in-process Rust benchmark, if the crate has one (see RUST_BENCH below)

usage: python benches/fmpy_overhead.py [--repeats 5] [--sim-time 0.05] [--no-build]
"""

from __future__ import annotations

import argparse
import re
import statistics
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))

from helpers.fmu_harness import FMU_PATH, FmuPackage, build_fmu  # noqa: E402

# Candidates for the in-process Rust benchmark binary (first one that exists is
# run with `cargo run --release --bin/--example NAME`).
RUST_BENCH = [("example", "fmu_bench"), ("bin", "bench-inprocess")]


def bare_loop(pkg: FmuPackage, sim_time: float, h: float) -> tuple[float, float, int]:
    inst = pkg.instance("bench")
    inst.initialize()
    vr = [pkg.vr(n) for n in pkg.real_outputs]
    n = int(round(sim_time / h))
    t = 0.0
    in_step = 0.0
    c0 = time.process_time()
    for _ in range(n):
        s0 = time.process_time()
        inst.slave.doStep(t, h)
        in_step += time.process_time() - s0
        t += h
        inst.slave.getReal(vr)
    total = time.process_time() - c0
    inst.terminate_and_free()
    return total, in_step, n


def internal_steps(pkg: FmuPackage, sim_time: float, h: float) -> int | None:
    """Accepted internal steps from the logSolver messages: the sum of the
    per-interval counts ("doStep [t0, t1] s: ... naccpt=N"), else the last
    (cumulative) count."""
    inst = pkg.instance("bench-log", logging_on=True)
    try:
        inst.slave.setDebugLogging(True, ["logSolver"])
    except Exception:
        inst.free()
        return None
    inst.initialize()
    for _ in range(int(round(sim_time / h))):
        inst.do_step(h)
    inst.terminate_and_free()
    per_interval, other = [], []
    for r in inst.log:
        m = re.search(r"naccpt=(\d+)", r.message) or re.search(r"nstep=(\d+)", r.message)
        if m:
            # "doStep [t0, t1] s: nfcn=.. naccpt=.." = statistics of one interval;
            # anything else (e.g. a summary at fmi2Terminate) is cumulative
            (per_interval if "doStep [" in r.message else other).append(int(m.group(1)))
    if per_interval:
        return sum(per_interval)
    return other[-1] if other else None


def rust_bench() -> str | None:
    cargo_toml = (REPO / "Cargo.toml").read_text()
    for kind, name in RUST_BENCH:
        declared = f'name = "{name}"' in cargo_toml or (
            kind == "example" and (REPO / "examples" / f"{name}.rs").exists()) or (
            kind == "bin" and (REPO / "src" / "bin" / f"{name}.rs").exists())
        if declared:
            cp = subprocess.run(["cargo", "run", "--release", "--quiet", f"--{kind}", name],
                                cwd=REPO, capture_output=True, text=True)
            return f"cargo run --release --{kind} {name} (exit {cp.returncode}):\n{cp.stdout}{cp.stderr[-2000:]}"
    return None


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--sim-time", type=float, default=0.05)
    ap.add_argument("--fmu", type=Path, default=None, help="use this .fmu (no build)")
    ap.add_argument("--no-build", action="store_true")
    args = ap.parse_args()

    from fmpy import simulate_fmu

    fmu = args.fmu or (FMU_PATH if args.no_build else build_fmu(REPO, quiet=True))
    pkg = FmuPackage(fmu)
    per10 = 0.01 / args.sim_time
    print(f"default case, default tolerance, {args.sim_time * 1e3:g} ms simulated per run, "
          f"median of {args.repeats} repeats, CPU per simulated 10 ms:")
    for h in (1e-5, 1e-4, 1e-3):
        fm = []
        for _ in range(args.repeats):
            c0 = time.process_time()
            # pre-extracted and pre-read: only FMPy's master loop and recorder are timed
            simulate_fmu(str(pkg.unzip_dir), stop_time=args.sim_time, output_interval=h,
                         validate=False, model_description=pkg.md)
            fm.append(time.process_time() - c0)
        tot, ins = [], []
        for _ in range(args.repeats):
            a, b, n = bare_loop(pkg, args.sim_time, h)
            tot.append(a)
            ins.append(b)
        m_fm, m_tot, m_in = (statistics.median(x) * per10 for x in (fm, tot, ins))
        print(f"  H = {h:g} s ({n} doSteps/run):")
        print(f"    fmpy.simulate_fmu              {1e3 * m_fm:9.2f} ms   ({10 / (1e3 * m_fm):6.2f} x real time)")
        print(f"    FMU2Slave loop (doStep+getReal){1e3 * m_tot:9.2f} ms")
        print(f"    inside fmi2DoStep              {1e3 * m_in:9.2f} ms   ({10 / (1e3 * m_in):6.2f} x real time)")
        print(f"    Python master overhead         {100 * (m_tot - m_in) / m_in:8.1f} % (bare loop), "
              f"{100 * (m_fm - m_in) / m_in:.1f} % (simulate_fmu)")
        steps = internal_steps(pkg, args.sim_time, h)
        if steps:
            print(f"    internal RADAU5 steps          {steps} -> {steps / n:.3f} per doStep, "
                  f"{n / steps:.3f} doSteps per internal step")
        else:
            print("    internal RADAU5 steps          (no naccpt=/nstep= in logSolver messages)")
    rb = rust_bench()
    print("in-process Rust benchmark:", rb if rb else "none found (RUST_BENCH candidates absent)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
