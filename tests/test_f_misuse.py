"""(f) Misuse through FMPy's low-level API: every wrong call returns fmi2Error
and logs a message (through the master's logger, with the instance name, no
raw '%') that names the function or the parameter; the process survives and
other instances are not disturbed."""

from __future__ import annotations

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy.fmi2 import FMU2Slave, fmi2CallbackFunctions, fmi2CallbackLoggerTYPE

from helpers.fmu_harness import FMI2_ERROR, Recorder, call_status, run

H = 1e-4
HELPER = Path(__file__).resolve().parent / "helpers" / "null_pointer_calls.py"


def _check_error(inst, status, mention):
    """status is fmi2Error and an error-level log record mentions every word in
    `mention` (a str or a list of alternatives lists)."""
    assert status == FMI2_ERROR, f"status {status}, log:\n{inst.log_text()}"
    errors = [r for r in inst.log if r.status >= FMI2_ERROR]
    assert errors, "no message logged at status Error"
    for r in inst.log:
        assert "%" not in r.message, f"raw '%' in a log message: {r.message!r}"
        assert r.instance == inst.name, f"logger got instance name {r.instance!r}"
    for alternatives in mention:
        if isinstance(alternatives, str):
            alternatives = [alternatives]
        pats = [re.compile(r"(?<![A-Za-z0-9_.])" + re.escape(a) + r"(?![A-Za-z0-9_])")
                for a in alternatives]
        assert any(p.search(r.message) for r in errors for p in pats), (
            f"no error message mentions {alternatives}; log:\n{inst.log_text()}")


@pytest.fixture
def fresh(pkg):
    made = []

    def make(initialized=True, name="misuse"):
        inst = pkg.instance(name, logging_on=True)
        if initialized:
            inst.initialize()
            inst.do_step(H)
        made.append(inst)
        return inst

    yield make
    for inst in made:
        inst.free()


# --- call sequence ---------------------------------------------------------

def test_do_step_before_initialisation(fresh):
    inst = fresh(initialized=False)
    _check_error(inst, call_status(inst.slave.doStep, 0.0, H), ["fmi2DoStep"])


def test_do_step_in_initialization_mode(fresh):
    inst = fresh(initialized=False)
    inst.slave.setupExperiment(startTime=0.0)
    inst.slave.enterInitializationMode()
    _check_error(inst, call_status(inst.slave.doStep, 0.0, H), ["fmi2DoStep"])


def test_exit_initialization_without_enter(fresh):
    inst = fresh(initialized=False)
    _check_error(inst, call_status(inst.slave.exitInitializationMode),
                 ["fmi2ExitInitializationMode"])


def test_do_step_after_terminate(fresh):
    inst = fresh()
    inst.slave.terminate()
    _check_error(inst, call_status(inst.slave.doStep, inst.time, H), ["fmi2DoStep"])


# --- value references and values -------------------------------------------

def test_get_real_unknown_value_reference(fresh):
    inst = fresh()
    _check_error(inst, call_status(inst.slave.getReal, [999999]),
                 ["fmi2GetReal", ["999999"]])


def test_set_real_on_an_output(fresh, pkg):
    inst = fresh()
    vr = pkg.vr("T1")
    _check_error(inst, call_status(inst.slave.setReal, [vr], [1.0]),
                 ["fmi2SetReal", ["T1", str(vr)]])


def test_set_integer_on_a_real_value_reference(fresh, pkg):
    inst = fresh(initialized=False)
    vr = pkg.vr("m_n")
    if any(v.valueReference == vr and v.type == "Integer" for v in pkg.md.modelVariables):
        pytest.skip("value reference shared by a Real and an Integer")
    _check_error(inst, call_status(inst.slave.setInteger, [vr], [3]),
                 ["fmi2SetInteger", ["m_n", str(vr)]])


def test_set_fixed_parameter_in_step_mode(fresh, pkg):
    inst = fresh()
    _check_error(inst, call_status(inst.slave.setReal, [pkg.vr("m_n")], [3e-3]),
                 ["fmi2SetReal", ["m_n"]])


@pytest.mark.parametrize("name,value", [("omega1", math.nan), ("omega1", math.inf),
                                        ("T_load", -math.inf), ("mu", math.nan)])
def test_non_finite_value_rejected(fresh, pkg, name, value):
    inst = fresh()
    _check_error(inst, call_status(inst.slave.setReal, [pkg.vr(name)], [value]),
                 ["fmi2SetReal", [name]])


def test_non_finite_input_rejected_before_initialisation(fresh, pkg):
    inst = fresh(initialized=False)
    _check_error(inst, call_status(inst.slave.setReal, [pkg.vr("omega1")], [math.nan]),
                 ["fmi2SetReal", ["omega1"]])


# --- doStep arguments --------------------------------------------------------

@pytest.mark.parametrize("h", [0.0, -1e-4, math.nan, math.inf])
def test_do_step_with_bad_step_size(fresh, h):
    inst = fresh()
    _check_error(inst, call_status(inst.slave.doStep, inst.time, h), ["fmi2DoStep"])


@pytest.mark.parametrize("offset", [1e-3, -5e-5, 3 * H])
def test_do_step_at_wrong_communication_point(fresh, offset):
    inst = fresh()
    _check_error(inst, call_status(inst.slave.doStep, inst.time + offset, H), ["fmi2DoStep"])


def test_communication_point_round_off_is_accepted(pkg):
    """Summing 0.1 ms a thousand times does not land on k*H exactly: the FMU
    must accept it (tolerance relative to the step, fmu.md) and stay on time."""
    inst = pkg.instance("roundoff")
    inst.initialize()
    t = 0.0
    for _ in range(1000):
        inst.slave.doStep(t, 1e-4)
        t += 1e-4
    assert t != 0.1  # the point of the test
    phi_a = inst.get1("phi1")
    inst.slave.doStep(0.1, 1e-4)  # the exact point is accepted as well
    phi_b = inst.get1("phi1")
    inst.terminate_and_free()
    # no drift of the FMU's time: phi1 advanced by omega1 * 1e-4 exactly enough
    assert phi_b - phi_a == pytest.approx(314.159 * 1e-4, rel=1e-9)


# --- invalid parameter sets --------------------------------------------------

@pytest.mark.parametrize(
    "params,names",
    [
        ({"z1": 3}, ["z1"]),
        ({"z2": 4}, ["z2"]),
        ({"beta": math.radians(50.0)}, ["beta"]),
        ({"beta": math.radians(-50.0)}, ["beta"]),
        ({"b": 0.0}, ["b"]),
        ({"b": -1e-3}, ["b"]),
        ({"m_n": 0.0}, ["m_n"]),
        ({"alpha_n": math.radians(50.0)}, ["alpha_n"]),
        ({"mu": -0.1}, ["mu"]),
        ({"m1": -1.0}, ["m1"]),  # 0 is the solid body of the geometry (docs/model.md §5)
        ({"J2": -1.0}, ["J2"]),
        ({"omega1_filter_frequency": 0.0}, ["omega1_filter_frequency"]),
        ({"rtol": 0.0}, ["rtol"]),
        # tips beyond the line of action (interference): huge addendum
        ({"h_aP": 3.0}, None),
    ],
    ids=lambda x: str(x) if not isinstance(x, dict) else ",".join(f"{k}={v:g}" for k, v in x.items()),
)
def test_invalid_parameter_set_rejected(fresh, params, names):
    """Rejected with fmi2Error at the set (if the FMU checks min/max there) or in
    fmi2ExitInitializationMode, with a message naming the parameter."""
    inst = fresh(initialized=False)
    inst.slave.setupExperiment(startTime=0.0)
    status = 0
    for name, value in params.items():
        setter = inst.slave.setInteger if inst.pkg.vars[name].type == "Integer" else inst.slave.setReal
        status = max(status, call_status(setter, [inst.pkg.vr(name)], [value]))
    if status < FMI2_ERROR:
        status = call_status(inst.slave.enterInitializationMode)
    if status < FMI2_ERROR:
        status = call_status(inst.slave.exitInitializationMode)
    _check_error(inst, status, [names] if names else [])


# --- logging and optional functions ----------------------------------------

def test_unknown_log_category(fresh):
    inst = fresh(initialized=False)
    _check_error(inst, call_status(inst.slave.setDebugLogging, True, ["noSuchCategory"]),
                 [["noSuchCategory"]])


def test_known_log_categories_accepted(fresh, pkg):
    inst = fresh(initialized=False)
    cats = [c.name for c in pkg.md.logCategories]
    assert call_status(inst.slave.setDebugLogging, True, cats) == 0
    inst.initialize()
    inst.do_step(H)
    assert any(r.category == "logSolver" for r in inst.log), "no logSolver message while enabled"


def test_debug_logging_filters_by_category(fresh):
    """FMI 2.0: loggingOn with a list of categories prints only those; loggingOn
    = false prints none of the debug categories (errors are still reported)."""
    inst = fresh(initialized=False)
    inst.slave.setDebugLogging(True, ["logEvents"])
    inst.initialize()
    inst.do_step(H)
    assert not [r for r in inst.log if r.category == "logSolver"], inst.log_text()
    inst.slave.setDebugLogging(False, [])
    n = len(inst.log)
    inst.do_step(H)
    assert not [r for r in inst.log[n:] if r.status < FMI2_ERROR], inst.log_text()


def test_unsupported_directional_derivative(fresh, pkg):
    if pkg.md.coSimulation.providesDirectionalDerivative:
        pytest.skip("directional derivatives declared")
    inst = fresh()
    st = call_status(inst.slave.getDirectionalDerivative, [pkg.vr("T1")], [pkg.vr("omega1")], [1.0])
    _check_error(inst, st, [["fmi2GetDirectionalDerivative"]])


def test_wrong_guid_is_refused(pkg):
    records = []

    def logger(env, name, status, cat, msg):
        records.append((status, (msg or b"").decode()))

    cb = fmi2CallbackFunctions()
    lg = fmi2CallbackLoggerTYPE(logger)
    cb.logger = lg
    slave = FMU2Slave(guid="{00000000-0000-0000-0000-000000000000}", unzipDirectory=str(pkg.unzip_dir),
                      modelIdentifier="GearedRotor", instanceName="badguid")
    with pytest.raises(Exception, match="instantiate"):
        slave.instantiate(callbacks=cb)
    assert any(s >= FMI2_ERROR and ("GUID" in m or "guid" in m) for s, m in records), records


# --- null pointers and the survival of other instances ------------------------

def test_null_pointers_in_child_process(pkg):
    cp = subprocess.run([sys.executable, str(HELPER), str(pkg.fmu_path), str(pkg.unzip_dir)],
                        capture_output=True, text=True, timeout=300)
    assert cp.returncode == 0, f"child crashed (rc {cp.returncode}): {cp.stderr[-2000:]}"
    out = json.loads(cp.stdout)
    not_error = {k: v for k, v in out["statuses"].items() if v != FMI2_ERROR}
    assert not not_error, f"expected fmi2Error from every call: {not_error}"
    assert all("%" not in m for m in out["messages"])


def test_misuse_does_not_disturb_another_instance(pkg):
    n = 100
    alone = run(pkg, n * H, H, name="victim-alone")
    victim = pkg.instance("victim")
    victim.initialize()
    rec = Recorder(victim)
    rec.sample()
    for k in range(n):
        bully = pkg.instance(f"bully{k % 3}", logging_on=True)
        call_status(bully.slave.doStep, 0.0, H)
        call_status(bully.slave.getReal, [999999])
        call_status(bully.slave.setReal, [pkg.vr("omega1")], [math.nan])
        if k % 10 == 0:
            call_status(bully.slave.deSerializeFMUstate, b"garbage" * 10)
        bully.free()
        victim.do_step(H)
        rec.sample()
    tr = rec.trajectory()
    victim.terminate_and_free()
    bad = [name for name in tr.names() if not np.array_equal(tr[name], alone[name])]
    assert not bad, f"victim changed by misuse of other instances: {bad}"


def test_many_instantiate_free_cycles(pkg):
    for k in range(200):
        inst = pkg.instance(f"cycle{k}")
        if k % 2:
            inst.initialize()
            inst.do_step(H)
        inst.free()
