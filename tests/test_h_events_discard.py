"""Behaviour around the edges of the model (fmu.md "Behaviour"): tooth lift-off
is flagged (contact_lost, logEvents) and a solver that cannot go on returns
fmi2Discard with fmi2LastSuccessfulTime and the state of that time; the load
torque input acts as model.md 9.5 says."""

from __future__ import annotations

import math

import pytest

from helpers.fmu_harness import FMI2_DISCARD, call_status, run

Z1, Z2 = 27, 41
OMEGA1 = 314.159
D_PHI = 0.5
FMI2_LAST_SUCCESSFUL_TIME = 2


def _steady_lambda(t_load: float, r_b2: float, beta_b: float) -> float:
    """J2 equation at steady state: lambda r_b2 cos beta_b = d_phi omega2 + T_load (mu = 0)."""
    return (D_PHI * OMEGA1 * Z1 / Z2 + t_load) / (r_b2 * math.cos(beta_b))


def test_load_torque_shifts_the_contact_force(pkg):
    """mu = 0: lambda = (d_phi omega2 + T_load)/(r_b2 cos beta_b) at steady state;
    E_load accumulates T_load omega2."""
    t_load = 40.0
    r = run(pkg, 0.2, 1e-3, params={"mu": 0.0, "T_load": t_load}, tolerance=1e-8,
            record=["Fn", "E_load", "omega2", "r_b2", "beta_b"], name="load")
    lam = _steady_lambda(t_load, r["r_b2"][-1], r["beta_b"][-1])
    assert r["Fn"][-1] == pytest.approx(lam, rel=1e-6)
    # E_load over the last 50 ms = T_load * mean omega2 * 50 ms
    i = -51
    de = r["E_load"][-1] - r["E_load"][i]
    assert de == pytest.approx(t_load * OMEGA1 * Z1 / Z2 * (r.t[-1] - r.t[i]), rel=1e-6)


def test_tooth_lift_off_is_flagged_and_logged(pkg):
    """A load torque that drives gear 2 harder than the damper brakes it
    (T_load < -d_phi omega2 ~ -103 N m) makes lambda negative: the one-flank
    contact of the paper would open. The FMU must say so (contact_lost, a
    logEvents message when it changes), not hide it."""
    inst = pkg.instance("liftoff", logging_on=True)
    inst.slave.setDebugLogging(True, ["logEvents", "logStatusWarning", "logStatusError"])
    inst.initialize({"mu": 0.0})
    seen = []
    for k in range(150):
        if k == 50:
            inst.set({"T_load": -300.0})
        inst.do_step(1e-4)
        seen.append(inst.get(["contact_lost", "Fn"]))
    inst.terminate_and_free()
    assert not any(s["contact_lost"] for s in seen[:50]) and all(s["Fn"] > 0 for s in seen[:50])
    assert seen[-1]["contact_lost"] and seen[-1]["Fn"] < 0.0
    events = [r for r in inst.log if r.category == "logEvents"]
    assert events, inst.log_text()


def test_discard_reports_last_successful_time(pkg):
    """A load torque of 1e5 N m pushes the centres apart (2e8 N/m bearings) until
    no contact line is left in the active area: the model's assumptions fail
    and RADAU5 cannot continue. fmi2DoStep returns fmi2Discard,
    fmi2LastSuccessfulTime lies inside the step, the outputs are those of that
    time (phi1 advanced by omega1 t: the filter is at rest at constant omega1),
    and a rollback to an earlier FMU state continues normally."""
    inst = pkg.instance("discard", logging_on=True)
    inst.initialize()
    inst.do_step(1e-4, no_set_prior=False)
    phi_a = inst.get1("phi1")
    state = inst.slave.getFMUstate()
    inst.set({"T_load": 1e5})
    status = call_status(inst.slave.doStep, 1e-4, 1e-2, 0)
    assert status == FMI2_DISCARD, inst.log_text()
    t_last = inst.slave.getRealStatus(FMI2_LAST_SUCCESSFUL_TIME)
    assert 1e-4 < t_last < 1e-4 + 1e-2
    phi_b = inst.get1("phi1")
    assert phi_b - phi_a == pytest.approx(OMEGA1 * (t_last - 1e-4), rel=1e-9)
    assert all(math.isfinite(x) for x in inst.slave.getReal([pkg.vr(n) for n in pkg.real_outputs]))
    assert any(r.status == FMI2_DISCARD and pkg.fmi_name("fmi2DoStep") in r.message for r in inst.log), inst.log_text()
    # rollback (what an iterating master does after a Discard) and go on
    inst.slave.setFMUstate(state)
    inst.slave.freeFMUstate(state)
    assert inst.get1("T_load") == 0.0
    inst.slave.doStep(1e-4, 1e-4)
    assert math.isfinite(inst.get1("T1"))
    inst.terminate_and_free()
