"""The worked drivetrain (examples/drivetrain.py): motor under PI speed control, two
GearedRotor stages (27/41, 23/61) coupled explicitly in FMPy, a load step.

- Power balance over a steady window (after the load step): the motor's shaft power (the
  master's own account of the work it delivered with the held torque) equals the load power
  plus the friction and damper losses of both stages plus the rate of change of their
  kinetic and potential energy, to 1e-3 of the motor power at H = 1e-4 s. Each term comes
  from the FMUs' energy outputs (integrals inside the FMUs), the motor side from the master;
  what is left is the energy the explicit coupling creates or destroys at the two
  interfaces (docs/drivetrain.md).
- H = 1e-4 s against 5e-5 s: the net motor power (shaft power minus the rate of change of
  the stored energy) differs by no more than the coupling error of the two runs, the
  interface power mismatch measured in each (everything else in the balance is the FMUs'
  own physics, integrated to rtol 1e-8).
- The stability limit: a motor inertia below the gearbox inertia it drives, J_m = 1e-3
  kg m^2, diverges at H = 3e-4 s (wc H = 1.9, where the sampled loop is least stable), and
  J_m = 5e-3 kg m^2 stays bounded at the same H.
"""

from __future__ import annotations

import importlib.util
import math
import sys

import numpy as np
import pytest

from helpers.fmu_harness import REPO_ROOT

_spec = importlib.util.spec_from_file_location("drivetrain", REPO_ROOT / "examples" / "drivetrain.py")
drivetrain = importlib.util.module_from_spec(_spec)
sys.modules["drivetrain"] = drivetrain  # dataclasses look their module up there
_spec.loader.exec_module(drivetrain)

WINDOW = (0.12, 0.15)  # 70-100 ms after the load step at 50 ms


@pytest.fixture(scope="module")
def runs(fmu_path):
    return {H: drivetrain.simulate(drivetrain.Config(H=H), fmu_path) for H in (1e-4, 5e-5)}


def test_power_balance_closes(runs):
    res = runs[1e-4]
    assert res["failed"] is None, res["failed"]
    b = drivetrain.power_balance(res, *WINDOW)
    motor = b["motor (shaft)"]
    # the load step really happened and the load takes most of the power
    assert res["T_load"][-1] == 60.0 and b["load"] > 0.5 * motor
    assert abs(b["residual"]) <= 1e-3 * motor, b
    # the residual is the coupling mismatch at the interfaces, nothing else
    assert abs(b["residual"] - b["coupling motor/1"] - b["coupling 1/2"]) <= 1e-5 * motor, b


def test_steps_agree_to_the_coupling_error(runs):
    def net(b):
        return b["motor (shaft)"] - b["dE_kin+pot 1"] - b["dE_kin+pot 2"]

    ba = drivetrain.power_balance(runs[1e-4], *WINDOW)
    bb = drivetrain.power_balance(runs[5e-5], *WINDOW)
    coupling = sum(abs(b[k]) for b in (ba, bb) for k in ("coupling motor/1", "coupling 1/2"))
    assert coupling < 1e-3 * ba["motor (shaft)"]
    assert abs(net(ba) - net(bb)) <= coupling, (net(ba), net(bb), coupling)
    # the steady operating point: output speed and load power
    t = runs[1e-4]["t"]
    sel = (t >= WINDOW[0]) & (t <= WINDOW[1])
    w_out = np.mean(runs[1e-4]["s2.omega2"][sel])
    ratio = (41 / 27) * (61 / 23)
    assert w_out == pytest.approx(314.159 / ratio, rel=1e-3)
    assert ba["load"] == pytest.approx(bb["load"], rel=1e-5)


def test_stability_limit(fmu_path):
    def swing(J_m: float, H: float):
        res = drivetrain.simulate(drivetrain.Config(H=H, J_m=J_m, t_end=0.04, t_step=1.0, tolerance=1e-6),
                                  fmu_path)
        t, w = res["t"], res["w_m"] - 314.159
        return res["failed"], float(np.ptp(w[t > t[-1] - 0.01])) if len(t) > 10 else math.inf

    failed, _ = swing(1e-3, 3e-4)
    assert failed is not None and "diverged" in failed
    failed, amp = swing(5e-3, 3e-4)
    assert failed is None and amp < 0.05, (failed, amp)
