"""The load-reversal and rattle runs of the elastic contact (docs/model.md §3.6), shared by
tests/test_coast_flank.py (which checks them) and scripts/coast_figures.py (which draws
them for the README): the inputs as functions of time and one driver for both."""

from __future__ import annotations

import math
import time

from helpers.fmu_harness import FMI2_OK, Recorder, call_status

OMEGA1 = 314.159
CALCULATED = ["r_b1", "r_b2", "a_w", "alpha_wt", "beta_b", "j_bn"]


def t_load_reversal(t: float) -> float:
    """+100 N m, ramp to -100 N m between 20 and 25 ms (tests/coast_flank.rs)."""
    if t < 0.02:
        return 100.0
    if t < 0.025:
        return 100.0 - 200.0 * (t - 0.02) / 0.005
    return -100.0


def omega1_rattle(t: float) -> float:
    """omega1 +-5 % at 30 Hz (tests/coast_flank.rs)."""
    return OMEGA1 * (1.0 + 0.05 * math.sin(2.0 * math.pi * 30.0 * t))


def simulate(pkg, name, params, inputs, n, h=1e-4, tolerance=1e-8, record=(),
             calculated=CALCULATED):
    """n steps of h from the static equilibrium with elastic teeth; `inputs(t)` set before
    each doStep. Returns the trajectory, the calculated parameters, the status of every
    doStep, the log records above OK and the CPU time of the steps."""
    inst = pkg.instance(name, logging_on=True)
    try:
        inst.initialize({"tooth_contact": 2, "initialization": 2, **params},
                        tolerance=tolerance)
        cal = inst.get(list(calculated))
        rec = Recorder(inst, list(record))
        rec.sample()
        statuses = []
        cpu = time.process_time()
        for k in range(n):
            inst.set(inputs(k * h))
            statuses.append(call_status(inst.do_step, h))
            rec.sample()
        cpu = time.process_time() - cpu
        above_ok = [str(r) for r in inst.log if r.status > FMI2_OK]
        return rec.trajectory(), cal, statuses, above_ok, cpu
    finally:
        inst.terminate_and_free()
