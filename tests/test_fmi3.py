"""The FMI 3.0 GearedRotor-fmi3.fmu beside the FMI 2.0 GearedRotor.fmu: the same interface,
bit-identical results through FMPy, its own FMU-state blob (each version refuses the
other's), the FMI 3.0 value types, and early return at a lift-off (docs/fmu.md "FMI 3.0").
The main suite runs on both files too (conftest.py); this module holds what only 3.0 has.
"""

from __future__ import annotations

import zipfile
from ctypes import byref

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException
from fmpy.fmi3 import FMU3Slave, fmi3Boolean, fmi3Float64
from fmpy.util import read_csv

from helpers.fmu_harness import REPO_ROOT, FMI2_DISCARD, FMI2_ERROR, FMI2_OK, FMI2_WARNING

REF_IN = REPO_ROOT / "data" / "reference_run" / "GearedRotor_in.csv"


def test_archive_layout(fmu3_path):
    names = set(zipfile.ZipFile(fmu3_path).namelist())
    for required in ("modelDescription.xml", "binaries/x86_64-linux/GearedRotor.so",
                     "documentation/index.html", "documentation/fmu.md"):
        assert required in names, f"{required} missing from {fmu3_path.name} ({sorted(names)})"
    html = zipfile.ZipFile(fmu3_path).read("documentation/index.html").decode()
    assert "FMI 3.0 Co-Simulation FMU" in html


def test_same_interface_as_fmi2(pkg2, pkg3):
    """Every variable of the 2.0 description, with the same value reference, causality,
    variability, start, bounds, unit and display unit; the only addition is the
    independent variable time that FMI 3.0 requires."""
    md2, md3 = (pkg.md for pkg in (pkg2, pkg3))
    assert md3.fmiVersion == "3.0" and md3.guid == md2.guid
    v2 = {v.name: v for v in md2.modelVariables}
    v3 = {v.name: v for v in md3.modelVariables}
    assert set(v3) - set(v2) == {"time"} and set(v2) <= set(v3)
    assert v3["time"].causality == "independent" and v3["time"].type == "Real"
    for name, a in v2.items():
        b = v3[name]
        for attr in ("valueReference", "causality", "variability", "initial", "start",
                     "min", "max", "unit", "displayUnit", "declaredType", "description"):
            x, y = getattr(a, attr, None), getattr(b, attr, None)
            if attr == "declaredType":
                x, y = getattr(x, "name", None), getattr(y, "name", None)
            if attr == "description":
                x, y = (x or "").replace("fmi2", ""), (y or "").replace("fmi3", "")
                continue  # function names differ on purpose; checked below
            assert x == y, f"{name}.{attr}: 2.0 {x!r}, 3.0 {y!r}"
        t2 = "Integer" if a.type == "Enumeration" else a.type
        t3 = "Integer" if b.type == "Enumeration" else b.type
        assert t2 == t3 and (a.type == "Enumeration") == (b.type == "Enumeration"), name
    # the same outputs with the same direct feedthrough
    deps = lambda md: {u.variable.name: sorted(d.name for d in (u.dependencies or []))
                       for u in md.outputs}
    assert deps(md3) == deps(md2)
    assert {u.variable.name for u in md3.initialUnknowns} == \
        {u.variable.name for u in md2.initialUnknowns}


def test_capabilities_declared(pkg3):
    cs = pkg3.md.coSimulation
    assert cs.canHandleVariableCommunicationStepSize
    assert cs.maxOutputDerivativeOrder == 1
    # FMPy keeps the FMI 2.0 spelling of these two flags for 3.0 too
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    assert cs.mightReturnEarlyFromDoStep
    assert not cs.hasEventMode and not cs.providesIntermediateUpdate
    assert not cs.providesDirectionalDerivative and not cs.canBeInstantiatedOnlyOncePerProcess


CASES = {
    "default": {},
    "periodic": {"initialization": 3},
    "law4": {"friction_law": 4},
    "realtime": {"h_fixed": 2.5e-5},
}


@pytest.mark.parametrize("case", list(CASES))
def test_reference_run_bit_identical_to_fmi2(fmu2_path, fmu3_path, case):
    """FMPy simulate of the shipped reference run (same inputs, same tolerance): every
    output of the 3.0 .fmu equals the 2.0 one to the last bit."""
    inp = read_csv(str(REF_IN))
    kw = dict(stop_time=0.01, output_interval=1e-4, input=inp, relative_tolerance=1e-6,
              start_values=CASES[case])
    r2 = simulate_fmu(str(fmu2_path), **kw)
    r3 = simulate_fmu(str(fmu3_path), **kw)
    assert len(r2) == len(r3) == 101
    names = r2.dtype.names
    assert len(names) > 60 and names == r3.dtype.names
    bad = [n for n in names if not np.array_equal(r2[n], r3[n])]
    assert not bad, f"{case}: not bit-identical: {bad}"


def _state_blob(pkg, steps=50):
    inst = pkg.instance("blob")
    inst.initialize()
    for _ in range(steps):
        inst.do_step(1e-4)
    s = inst.slave.getFMUstate()
    blob = inst.slave.serializeFMUstate(s)
    inst.slave.freeFMUstate(s)
    inst.terminate_and_free()
    return blob


@pytest.mark.parametrize("direction", ["fmi2 blob into fmi3", "fmi3 blob into fmi2"])
def test_the_other_versions_state_is_refused(pkg2, pkg3, direction):
    src, dst = (pkg2, pkg3) if direction.startswith("fmi2") else (pkg3, pkg2)
    blob = _state_blob(src)
    assert blob == _state_blob(src)  # deterministic
    inst = dst.instance("dst", logging_on=True)
    try:
        inst.initialize()
        with pytest.raises(FMICallException) as e:
            inst.slave.deSerializeFMUstate(blob)
        assert e.value.status == FMI2_ERROR
        want = "FMI 2.0 FMU (GearedRotor.fmu)" if src is pkg2 else "FMI 3.0 FMU (GearedRotor-fmi3.fmu)"
        msgs = inst.messages(FMI2_ERROR)
        assert any(want in m and "reads only its own states" in m for m in msgs), msgs
        assert any(dst.fmi_name("fmi2DeSerializeFMUstate") in m for m in msgs), msgs
    finally:
        inst.free()


def test_states_differ_only_by_their_seal(pkg2, pkg3):
    """The two blobs of the same run hold the same state: same length except the tag."""
    b2, b3 = _state_blob(pkg2), _state_blob(pkg3)
    assert b2 != b3 and len(b3) - len(b2) == len(" FMI 3.0")


def test_fmi3_value_types(pkg3):
    """Integer variables are Int32, Enumerations Int64 (the other getter is refused with a
    message naming the right one); time is read with fmi3GetFloat64 and cannot be set."""
    inst = pkg3.instance("types", logging_on=True)
    s = inst.slave
    try:
        inst.initialize({"initialization": 2})
        assert s.getInt64([pkg3.vr("initialization")]) == [2]
        assert s.getInt32([pkg3.vr("z1")]) == [27]
        inst.do_step(1e-4)
        inst.do_step(1e-4)
        assert s.getFloat64([pkg3.vr("time")]) == [2e-4]
        assert s.getInt32([pkg3.vr("pairs_in_contact")])[0] in (1, 2, 3)
        with pytest.raises(FMICallException):
            s.getInt32([pkg3.vr("initialization")])
        assert any("is an Enumeration: use fmi3GetInt64" in m for m in inst.messages(FMI2_ERROR))
    finally:
        inst.free()
    inst = pkg3.instance("time", logging_on=True)
    try:
        inst.initialize()
        with pytest.raises(FMICallException):
            inst.slave.setFloat64([pkg3.vr("time")], [1.0])
        assert any("time cannot be set" in m for m in inst.messages(FMI2_ERROR))
    finally:
        inst.free()


# -- early return ------------------------------------------------------------------


class Raw:
    """An FMU3Slave with earlyReturnAllowed as asked, whose doStep returns the status and
    the out-arguments."""

    def __init__(self, pkg3, early: bool, params: dict):
        self.log = []
        self.s = FMU3Slave(guid=pkg3.md.guid, unzipDirectory=str(pkg3.unzip_dir),
                           modelIdentifier="GearedRotor", instanceName="early")
        self.s.instantiate(earlyReturnAllowed=early, loggingOn=False,
                           logMessage=lambda env, st, cat, msg: self.log.append((st, msg.decode())))
        self.s.enterInitializationMode(tolerance=1e-9)
        for name, x in params.items():
            v = pkg3.vars[name]
            (self.s.setInt64 if v.type == "Enumeration" else self.s.setFloat64)(
                [v.valueReference], [x])
        self.s.exitInitializationMode()
        self.pkg = pkg3
        self.t = 0.0

    def step(self, h: float):
        ev, term, early, last = fmi3Boolean(), fmi3Boolean(), fmi3Boolean(), fmi3Float64()
        try:
            st = self.s.fmi3DoStep(self.s.component, self.t, h, fmi3Boolean(True),
                                   byref(ev), byref(term), byref(early), byref(last))
        except FMICallException as e:
            st = e.status
        assert not ev.value and not term.value
        return int(st), bool(early.value), last.value

    def get(self, name: str) -> float:
        return self.s.getFloat64([self.pkg.vr(name)])[0]

    def set(self, name: str, x: float):
        self.s.setFloat64([self.pkg.vr(name)], [x])


def _to_lift_off(raw: Raw, h: float = 1e-3):
    """2 ms at rest load, then T_load = -200 N m (a coasting load): Fn falls through 0
    within a few ms. Steps of h until a step does not end OK; returns its outcome."""
    for _ in range(2):
        assert raw.step(h)[0] == FMI2_OK
        raw.t += h
    raw.set("T_load", -200.0)
    for _ in range(20):
        st, early, last = raw.step(h)
        if st != FMI2_OK or early:
            return st, early, last
        raw.t += h
    raise AssertionError("no lift-off within 20 steps")


def _discard_instant_of_fmi2(pkg2, h=1e-3) -> float:
    """The instant the FMI 2.0 FMU stops at with on_lift_off = discard."""
    inst = pkg2.instance("discard2")
    try:
        inst.initialize({"initialization": 2, "on_lift_off": 2}, tolerance=1e-9)
        inst.do_step(h)
        inst.do_step(h)
        inst.set({"T_load": -200.0})
        for _ in range(20):
            try:
                inst.do_step(h)
            except FMICallException as e:
                assert e.status == FMI2_DISCARD
                from fmpy.fmi2 import fmi2LastSuccessfulTime
                return inst.slave.getRealStatus(fmi2LastSuccessfulTime)
        raise AssertionError("no discard")
    finally:
        inst.free()


def test_early_return_at_the_located_lift_off(pkg2, pkg3):
    """earlyReturnAllowed, on_lift_off = warn: the doStep that meets the lift-off returns
    fmi3Warning with earlyReturn = true and lastSuccessfulTime at the located instant (the
    instant where the 2.0 FMU with on_lift_off = discard stops, to 1e-9 s); Fn ~ 0 there;
    the master goes on from that instant: the next step completes, and every later step
    either completes or returns early inside itself at a new episode (the rigid contact
    can regain and lose contact again, each a new lift-off as for fmi2Warning)."""
    t_discard = _discard_instant_of_fmi2(pkg2)
    raw = Raw(pkg3, True, {"initialization": 2})
    try:
        st, early, last = _to_lift_off(raw)
        assert st == FMI2_WARNING and early, (st, early, last)
        assert raw.t < last < raw.t + 1e-3
        assert abs(last - t_discard) <= 1e-9, (last, t_discard)
        assert raw.s.getFloat64([pkg3.vr("time")]) == [last]
        assert abs(raw.get("Fn")) < 1.0  # N, against ~1e3 N before
        assert any("returning early" in m and "lift-off" in m for s, m in raw.log if s == 1), raw.log
        raw.t = last
        st, early, end = raw.step(1e-3)  # the same episode: no new event
        assert (st, early) == (FMI2_OK, False) and end == raw.t + 1e-3
        raw.t = end
        while raw.t < 0.01:
            st, early, end = raw.step(1e-3)
            assert (st, early) in ((FMI2_OK, False), (FMI2_WARNING, True)), (st, early)
            assert raw.t < end <= raw.t + 1e-3
            assert early or end == raw.t + 1e-3
            raw.t = end
            assert np.isfinite(raw.get("T1")) and np.isfinite(raw.get("Fn"))
    finally:
        raw.s.freeInstance()


def test_without_early_return_it_behaves_as_fmi2(pkg3):
    """earlyReturnAllowed = false: the step completes with fmi3Warning (as fmi2Warning of the
    2.0 FMU); on_lift_off = discard: fmi3Discard at the instant, with or without it."""
    raw = Raw(pkg3, False, {"initialization": 2})
    try:
        st, early, last = _to_lift_off(raw)
        assert (st, early) == (FMI2_WARNING, False)
        assert last == pytest.approx(raw.t + 1e-3, abs=1e-15)
    finally:
        raw.s.freeInstance()
    for allowed in (False, True):
        raw = Raw(pkg3, allowed, {"initialization": 2, "on_lift_off": 2})
        try:
            st, early, last = _to_lift_off(raw)
            assert (st, early) == (FMI2_DISCARD, False)
            assert raw.t < last < raw.t + 1e-3
        finally:
            raw.s.freeInstance()


def test_fmpy_simulate_with_early_return(pkg2, fmu3_path):
    """FMPy's own master with early_return_allowed: a sample at each located lift-off
    (the first at the 2.0 FMU's discard instant), Fn ~ 0 there, and the run goes on to the
    stop time; without it, the regular grid only."""
    inp = np.array([(0.0, 0.0), (0.002, 0.0), (0.002, -200.0), (0.01, -200.0)],
                   dtype=[("time", float), ("T_load", float)])
    kw = dict(stop_time=0.01, output_interval=1e-3, input=inp, relative_tolerance=1e-9,
              start_values={"initialization": 2}, output=["Fn", "contact_lost"])
    grid = simulate_fmu(str(fmu3_path), **kw)
    assert len(grid) == 11
    r = simulate_fmu(str(fmu3_path), early_return_allowed=True, **kw)
    t = r["time"]
    off_grid = [k for k, x in enumerate(t) if abs(x * 1e3 - round(x * 1e3)) > 1e-6]
    assert len(off_grid) >= 1 and t[-1] == pytest.approx(0.01, abs=1e-15), t
    first = off_grid[0]
    assert abs(t[first] - _discard_instant_of_fmi2(pkg2)) <= 1e-9
    for k in off_grid:
        assert abs(r["Fn"][k]) < 1.0 and r["contact_lost"][k], (t[k], r["Fn"][k])
