"""Leaving the model's validity: lift-off (Fn < 0) and drive reversal (omega1_filtered
< 0), reported once per episode with fmi2Warning (on_lift_off = warn) or stopped with
fmi2Discard at the located instant (on_lift_off = discard).

The instant is checked against an independent location: a second instance runs with
communication steps of 10 us and warn, finds the communication interval where the sign
changes, and bisects it with fmi2GetFMUstate / fmi2SetFMUstate and doSteps that end
exactly on the trial times (no dense output involved) to 1e-11 s.
"""

from __future__ import annotations

import pytest
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import fmi2LastSuccessfulTime

from helpers.fmu_harness import FMI2_DISCARD, FMI2_OK, FMI2_WARNING

TOL = 1e-9  # FMU tolerance of the location checks


def step(inst, h: float) -> int:
    """fmi2DoStep returning the status (FMPy raises only above fmi2Warning)."""
    s = inst.slave
    try:
        st = s.fmi2DoStep(s.component, inst.time, h, 1)
    except FMICallException as e:
        st = e.status
    inst.time += h
    return int(st)


def set_ramp(inst, name: str, value: float, slope: float) -> None:
    inst.set({name: value})
    inst.slave.setRealInputDerivatives([inst.pkg.vr(name)], [1], [slope])


def warnings(inst) -> list[str]:
    return [r.message for r in inst.log if r.status == FMI2_WARNING]


def test_coast_load_warns_once_per_episode(pkg):
    """T_load = -200 N m (the load drives): Fn < 0 from the start. The first doStep returns
    fmi2Warning with a message naming the time, Fn and what it means; the next ones, still
    lifted off, return OK; after contact is regained and lost again, a new warning."""
    inst = pkg.instance("coast")
    try:
        inst.initialize({"T_load": -200.0})
        assert step(inst, 1e-4) == FMI2_WARNING
        w = warnings(inst)
        assert len(w) == 1, w
        assert "lift-off at t = 0.0" in w[0] and "Fn = -7" in w[0] and "separate" in w[0], w[0]
        assert inst.get1("contact_lost")
        for _ in range(5):
            assert step(inst, 1e-4) == FMI2_OK
        assert len(warnings(inst)) == 1
        inst.set({"T_load": 0.0})
        for _ in range(5):
            assert step(inst, 1e-4) == FMI2_OK
        assert not inst.get1("contact_lost")
        t_set = inst.time
        inst.set({"T_load": -200.0})
        statuses = []
        while FMI2_WARNING not in statuses and len(statuses) < 20:
            statuses.append(step(inst, 1e-4))
        # the load acts through the rotor inertia: Fn falls over a few steps
        assert statuses[-1] == FMI2_WARNING and set(statuses[:-1]) <= {FMI2_OK}, statuses
        assert len(warnings(inst)) == 2
        t_new = float(warnings(inst)[1].split("at t = ")[1].split(" s")[0])
        k = statuses.index(FMI2_WARNING)
        assert t_set + k * 1e-4 - 1e-12 <= t_new <= t_set + (k + 1) * 1e-4 + 1e-12
        assert inst.get1("contact_lost")
    finally:
        inst.terminate_and_free()


def test_reversed_drive_warns(pkg):
    """omega1 = -314.159 rad/s: both assumptions fail from the start; two messages."""
    inst = pkg.instance("reverse")
    try:
        inst.initialize({"omega1": -314.159})
        assert step(inst, 1e-4) == FMI2_WARNING
        text = " ".join(warnings(inst))
        assert "drive reversal at t = 0.0" in text and "lift-off" in text, text
    finally:
        inst.terminate_and_free()


def test_a_start_at_standstill_is_inside_the_model(pkg):
    """omega1 = 0 under 50 N m: standstill is inside the model (friction laws 1 and 3 creep
    there, model.md §4.2), so the first doStep is fmi2OK; before, it was a drive-reversal
    episode from the start (fmi2Warning, fmi2Discard with on_lift_off = discard)."""
    for policy in (1, 2):
        inst = pkg.instance("standstill")
        try:
            inst.initialize({"omega1": 0.0, "T_load": 50.0, "on_lift_off": policy})
            for _ in range(5):
                assert step(inst, 1e-4) == FMI2_OK, [r.message for r in inst.log]
            assert not warnings(inst)
        finally:
            inst.terminate_and_free()


def bisect_instant(pkg, params, ramp, indicator: str, h: float = 1e-5, t_max: float = 0.05) -> float:
    """First time the output `indicator` is < 0 (Fn or omega1_filtered), found with
    doSteps only: coarse scan with steps h, then bisection of the bracket with FMU states."""
    inst = pkg.instance("bisect")
    try:
        inst.initialize(params, tolerance=TOL)
        set_ramp(inst, *ramp)
        def outside(x: float) -> bool:
            return x < 0.0
        state = inst.slave.getFMUstate()
        t_a = inst.time
        while True:
            step(inst, h)
            if outside(inst.get1(indicator)):
                break
            inst.slave.freeFMUstate(state)
            state = inst.slave.getFMUstate()
            t_a = inst.time
            assert inst.time < t_max, f"{indicator} never left the validity"
        lo, hi = 0.0, h  # offsets from t_a
        while hi - lo > 1e-11:
            mid = 0.5 * (lo + hi)
            inst.slave.setFMUstate(state)
            inst.slave.fmi2DoStep(inst.slave.component, t_a, mid, 1)
            if outside(inst.get1(indicator)):
                hi = mid
            else:
                lo = mid
        inst.slave.freeFMUstate(state)
        return t_a + hi
    finally:
        inst.free()


CASES = {
    # T_load ramps down at 2e4 N m/s from the static equilibrium: Fn crosses 0 near 5 ms
    "lift-off": ({"initialization": 2}, ("T_load", 0.0, -2e4), "Fn", "lift-off"),
    # omega1 ramps down through 0 at 2000 rad/s^2 under a braking load (contact kept)
    "reversal": ({"initialization": 2, "omega1": 20.0, "T_load": 50.0}, ("omega1", 20.0, -2000.0),
                 "omega1_filtered", "drive reversal"),
}


@pytest.mark.parametrize("case", list(CASES))
def test_discard_at_the_located_instant(pkg, case):
    """on_lift_off = discard: the doStep that contains the instant returns fmi2Discard,
    fmi2LastSuccessfulTime is the instant to 1e-9 s of the independent bisection, and the
    outputs there are those at the instant (Fn or omega1_filtered ~ 0)."""
    params, ramp, indicator, what = CASES[case]
    t_ref = bisect_instant(pkg, params, ramp, indicator)
    inst = pkg.instance("discard")
    try:
        inst.initialize({**params, "on_lift_off": 2}, tolerance=TOL)
        set_ramp(inst, *ramp)
        h = 1e-3
        status = FMI2_OK
        while status == FMI2_OK:
            status = step(inst, h)
            assert inst.time < 0.05
        assert status == FMI2_DISCARD
        t_last = inst.slave.getRealStatus(fmi2LastSuccessfulTime)
        assert inst.time - h <= t_last <= inst.time
        assert abs(t_last - t_ref) <= 1e-9, f"{case}: located {t_last!r}, bisection {t_ref!r}"
        msg = " ".join(r.message for r in inst.log if r.status == FMI2_DISCARD)
        assert what in msg, msg
        scale = 1.0 if indicator == "omega1_filtered" else 1e3
        assert abs(inst.get1(indicator)) <= 1e-3 * scale
    finally:
        inst.free()


@pytest.mark.parametrize("case", list(CASES))
def test_warn_reports_the_same_instant(pkg, case):
    """on_lift_off = warn: the step completes with fmi2Warning; the message names the
    instant that the discard policy stops at."""
    params, ramp, indicator, what = CASES[case]
    inst = pkg.instance("warn")
    try:
        inst.initialize(params, tolerance=TOL)
        set_ramp(inst, *ramp)
        status = FMI2_OK
        while status == FMI2_OK:
            status = step(inst, 1e-3)
            assert inst.time < 0.05
        assert status == FMI2_WARNING
        w = [m for m in warnings(inst) if what in m]
        assert len(w) == 1, warnings(inst)
        t_msg = float(w[0].split("at t = ")[1].split(" s")[0])
        t_ref = bisect_instant(pkg, params, ramp, indicator)
        assert abs(t_msg - t_ref) <= 1e-9, (t_msg, t_ref)
    finally:
        inst.terminate_and_free()


def test_discard_instant_does_not_depend_on_the_communication_step(pkg):
    """T_load set to -200 N m at 5 ms (a held step, no ramp): with on_lift_off = discard the
    last successful time is the located instant for every communication step size, also
    when the steps are much shorter than the solver's (H = 1e-5 s: RADAU5's step runs past
    the communication point where the lift-off lies). The instants agree to 1e-9 s, Fn
    there is ~0, and the instant lies inside the discarded doStep."""
    t_set = 5e-3
    found = {}
    for h in (1e-3, 1e-4, 1e-5):
        inst = pkg.instance(f"discard_h{h:g}")
        try:
            inst.initialize({"on_lift_off": 2}, tolerance=1e-6)
            n_before = round(t_set / h)
            for _ in range(n_before):
                assert step(inst, h) == FMI2_OK
            inst.set({"T_load": -200.0})
            status = FMI2_OK
            while status == FMI2_OK:
                status = step(inst, h)
                assert inst.time < 0.02
            assert status == FMI2_DISCARD, status
            t_last = inst.slave.getRealStatus(fmi2LastSuccessfulTime)
            assert inst.time - h <= t_last < inst.time, (h, t_last, inst.time)
            fn = inst.get1("Fn")
            assert abs(fn) <= 1e-3, (h, fn)
            found[h] = t_last
        finally:
            inst.free()
    ts = list(found.values())
    assert max(ts) - min(ts) <= 1e-9, found
