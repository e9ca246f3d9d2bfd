"""(e) Instances share nothing mutable: two instances with different parameters
stepped alternately give exactly what each gives alone (also from two threads);
fmi2Reset returns an instance to the state right after fmi2Instantiate."""

from __future__ import annotations

import threading

import numpy as np
import pytest

from helpers.fmu_harness import Recorder, run

H = 1e-4
N = 150
PARAMS_A: dict = {}
PARAMS_B = {"mu": 0.1, "d_phi": 0.3, "omega1": 280.0, "k2.x": 1.5e8, "psi0": 0.25}


def _identical(a, b, names):
    return [n for n in names if not np.array_equal(a[n], b[n])]


@pytest.fixture(scope="module")
def alone(pkg):
    return {
        "A": run(pkg, N * H, H, params=PARAMS_A, name="A"),
        "B": run(pkg, N * H, H, params=PARAMS_B, name="B"),
    }


def test_alternating_instances_equal_each_alone(pkg, alone):
    a, b = pkg.instance("A"), pkg.instance("B")
    a.initialize(PARAMS_A)
    b.initialize(PARAMS_B)
    ra, rb = Recorder(a), Recorder(b)
    ra.sample()
    rb.sample()
    for _ in range(N):
        a.do_step(H)
        ra.sample()
        b.do_step(H)
        rb.sample()
    ta, tb = ra.trajectory(), rb.trajectory()
    a.terminate_and_free()
    b.terminate_and_free()
    names = ta.names()
    assert not _identical(ta, alone["A"], names)
    assert not _identical(tb, alone["B"], names)
    # and the two parameter sets really give different runs
    assert not np.array_equal(alone["A"]["T1"], alone["B"]["T1"])


def test_instances_in_two_threads_equal_each_alone(pkg, alone):
    results = {}

    def worker(key, params):
        results[key] = run(pkg, N * H, H, params=params, name=f"thread-{key}")

    threads = [threading.Thread(target=worker, args=("A", PARAMS_A)),
               threading.Thread(target=worker, args=("B", PARAMS_B))]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    names = results["A"].names()
    assert not _identical(results["A"], alone["A"], names)
    assert not _identical(results["B"], alone["B"], names)


def _run_on(inst, params):
    inst.initialize(params)
    rec = Recorder(inst)
    rec.sample()
    for _ in range(N):
        inst.do_step(H)
        rec.sample()
    return rec.trajectory()


def test_reset_then_rerun_equals_first_run(pkg, alone):
    inst = pkg.instance("reset")
    first = _run_on(inst, PARAMS_B)
    inst.slave.terminate()
    inst.slave.reset()
    inst.time = 0.0
    second = _run_on(inst, PARAMS_B)
    names = first.names()
    assert not _identical(first, second, names)
    assert not _identical(first, alone["B"], names)
    # Reset also forgets the parameters set before: a run without setting any
    # is the default run (reset straight from step mode, without terminate)
    inst.slave.reset()
    inst.time = 0.0
    third = _run_on(inst, None)
    inst.terminate_and_free()
    assert not _identical(third, alone["A"], names)
