"""The parameter `initialization` (1 = rest, 2 = static_equilibrium, 3 = periodic),
applied in fmi2ExitInitializationMode, through FMPy on the packaged .fmu.

References are independent of the FMU's initialisation code:
- `periodic`: the orbit of the project's shooting program (`cargo run --bin periodic`:
  full Newton from a 20-period transient, RADAU5 at rtol 1e-13, its own sampling on the
  dense output), and periodicity itself (period k against period 1);
- `static_equilibrium` with mu = 0: an equilibrium of the equations, so every output is
  constant (angles and cumulative energies grow linearly);
- the transient from rest that `periodic` removes: TE from 50 to 60 ms against a long run.
"""

from __future__ import annotations

import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

from helpers.fmu_harness import FMI2_ERROR, REPO_ROOT, call_status, run

TOL = 1e-12  # FMU tolerance of the periodicity and orbit checks (shooting at 1e-13)
CASES = {
    "helical": ({}, 314.159),
    "spur": ({"beta": 0.0}, 314.159),
    "helical-200rad/s": ({}, 200.0),
    # no rotational damper: the load torque alone loads the mesh (the periodic module's
    # scales once ignored it and called this stable orbit unstable)
    "no-damper-100Nm": ({"d_phi": 0.0, "T_load": 100.0}, 314.159),
}
POSITIONS = ["u1.x", "u1.y", "u2.x", "u2.y"]


def mesh_period(z1: int, omega1: float) -> float:
    return 2.0 * math.pi / (z1 * omega1)


def shooting_orbit(tmp_path: Path, params: dict, omega1: float) -> np.ndarray:
    """The orbit of src/bin/periodic (400 equidistant samples over one period from phi1 = 0)."""
    pfile = tmp_path / "params.txt"
    pfile.write_text("".join(f"{k} = {v!r}\n" for k, v in params.items()))
    out = tmp_path / "orbit"
    subprocess.run(
        ["cargo", "run", "--release", "--quiet", "--bin", "periodic", "--", "--params", str(pfile),
         "--omega1", repr(omega1), "--out", str(out), "--n-max", "1"],
        cwd=REPO_ROOT, check=True, stdout=subprocess.DEVNULL,
    )
    return np.genfromtxt(out / "shooting_orbit.csv", delimiter=",", names=True)


@pytest.mark.parametrize("case", list(CASES))
def test_periodic_start_is_the_shooting_orbit(pkg, tmp_path, case):
    """Over the first mesh period the FMU's centre positions, TE and Fn equal the shooting
    orbit: positions to 1e-6 of the orbit's peak to peak, TE and Fn to 1e-6 relative."""
    params, omega1 = CASES[case]
    orbit = shooting_orbit(tmp_path, params, omega1)
    n = len(orbit)
    period = mesh_period(27, omega1)
    tr = run(pkg, period, period / n, params={**params, "omega1": omega1, "initialization": 3},
             tolerance=TOL, record=["TE", "Fn"] + POSITIONS)
    assert len(tr.t) == n + 1
    # positions: the largest deviation of a centre relative to the largest peak to peak
    pp = max(np.ptp(orbit[c]) for c in ("u1x", "u1y", "u2x", "u2y"))
    dev = 0.0
    for j in (1, 2):
        dx = tr[f"u{j}.x"][:n] - orbit[f"u{j}x"]
        dy = tr[f"u{j}.y"][:n] - orbit[f"u{j}y"]
        dev = max(dev, np.max(np.hypot(dx, dy)))
    assert dev <= 1e-6 * pp, f"{case}: centre deviation {dev:.3e} m = {dev / pp:.2e} of pp {pp:.3e} m"
    for name, ref in (("TE", orbit["xi"]), ("Fn", orbit["lambda"])):
        rel = np.max(np.abs(tr[name][:n] - ref)) / np.max(np.abs(ref))
        assert rel <= 1e-6, f"{case}: {name} deviates by {rel:.2e} relative from the shooting orbit"


@pytest.mark.parametrize("case", list(CASES))
def test_periodic_start_stays_periodic(pkg, case):
    """Every mesh period over 50 ms repeats the first one to 1e-6 of its range (T1, Fn, TE
    and the centre positions); 1e-6 of the range plus 1e-14 m for TE, whose range without
    the damper is only 4.3 nm (the run's absolute error allowance is 1e-17 m per step)."""
    params, omega1 = CASES[case]
    period = mesh_period(27, omega1)
    m = 40  # samples per period
    periods = int(0.05 / period)
    names = ["T1", "Fn", "TE"] + POSITIONS
    tr = run(pkg, periods * period, period / m, params={**params, "omega1": omega1, "initialization": 3},
             tolerance=TOL, record=names)
    assert len(tr.t) == periods * m + 1
    for name in names:
        x = tr[name]
        first = x[: m + 1]
        rng = np.ptp(first)
        assert rng > 0.0, name
        dev = max(np.max(np.abs(x[k * m: k * m + m + 1] - first)) for k in range(1, periods))
        floor = 1e-14 if name == "TE" else 0.0
        assert dev <= 1e-6 * rng + floor, f"{case}: {name} period k vs 1: {dev:.3e} = {dev / rng:.2e} of the range"


def test_periodic_start_removes_the_transient(pkg):
    """TE peak to peak from 50 to 60 ms: from rest the transient still dominates (more than
    5 times the steady value of a 150 ms run from rest); from the periodic start it is the
    steady value to 1 %."""
    def te_pp(init: int, t0: float, t1: float, t_end: float) -> float:
        tr = run(pkg, t_end, 1e-5, params={"initialization": init}, tolerance=1e-8, record=["TE"])
        sel = (tr.t >= t0 - 1e-12) & (tr.t <= t1 + 1e-12)
        return float(np.ptp(tr["TE"][sel]))

    steady = te_pp(1, 0.14, 0.15, 0.15)
    rest = te_pp(1, 0.05, 0.06, 0.06)
    periodic = te_pp(3, 0.05, 0.06, 0.06)
    assert rest > 5 * steady, (rest, steady)
    assert abs(periodic - steady) <= 0.01 * steady, (periodic, steady)


def test_static_equilibrium_without_friction_is_constant(pkg):
    """mu = 0 (and a load torque): the frictionless static equilibrium is an equilibrium of
    the DAE. Every Real output stays at its start value to 1e-9 relative (of the largest
    value of that unit among the outputs, so that zero outputs are held to the same
    absolute level), except phi1, phi2 and the cumulative energies, which grow linearly,
    and the quantities of the contact-line geometry, which follow the mesh phase even in
    rigid rotation: contact_length, pairs_in_contact and the tilting moments of the
    distributed normal load (M_contact.x/y; no tilt degrees of freedom take them up)."""
    t_end, h = 0.02, 1e-4
    tr = run(pkg, t_end, h, params={"initialization": 2, "mu": 0.0, "T_load": 40.0}, tolerance=1e-8)
    units = {v.name: (v.unit or v.declaredType.unit) for v in pkg.outputs if v.type == "Real"}
    scale: dict[str, float] = {}
    for name, u in units.items():
        scale[u] = max(scale.get(u, 0.0), float(np.max(np.abs(tr[name]))))
    linear = {"phi1", "phi2", "E_in", "E_loss", "E_damp", "E_load"}
    geometric = {"contact_length", "M_contact1.x", "M_contact1.y", "M_contact2.x", "M_contact2.y"}
    for name, u in units.items():
        if name in geometric:
            continue
        x = tr[name]
        if name in linear:
            ref = x[0] + (x[-1] - x[0]) * (tr.t - tr.t[0]) / (tr.t[-1] - tr.t[0])
            assert np.max(np.abs(x - ref)) <= 1e-9 * max(np.max(np.abs(x)), 1e-300), name
        else:
            assert np.max(np.abs(x - x[0])) <= 1e-9 * scale[u], f"{name}: {np.ptp(x):.3e} {u}"
    # and the start is the frictionless static equilibrium, not rest: loaded bearings
    assert abs(tr["F_bearing1.y"][0]) > 100.0
    assert tr["E_in"][-1] > 0.0


def test_initialization_errors_say_why(pkg):
    """No periodic orbit without a positive constant speed: fmi2ExitInitializationMode
    fails with a message naming the speed and the way out; an item outside 1..3 is
    refused at the set, naming the items."""
    inst = pkg.instance("noorbit")
    try:
        inst.slave.setupExperiment(startTime=0.0)
        inst.set({"initialization": 3, "omega1": 0.0})
        inst.slave.enterInitializationMode()
        # A calculated parameter comes from the parameters alone: its read neither builds
        # the start state (here it cannot exist) nor fails; r_b1 = z1 m_n cos(alpha_t) /
        # (2 cos beta) of the default pair (model.md §2: 26.793197 mm).
        assert inst.get1("r_b1") == pytest.approx(26.793197e-3, rel=1e-7)
        assert not inst.messages(FMI2_ERROR)
        assert call_status(inst.slave.exitInitializationMode) == FMI2_ERROR
        msg = " ".join(inst.messages(FMI2_ERROR))
        assert "omega1" in msg and "initialization = rest" in msg, msg
    finally:
        inst.free()
    inst = pkg.instance("baditem")
    try:
        vr = pkg.vr("initialization")
        assert call_status(inst.slave.setInteger, [vr], [4]) == FMI2_ERROR
        msg = " ".join(inst.messages(FMI2_ERROR))
        assert "initialization" in msg and "3 = periodic" in msg, msg
    finally:
        inst.free()


def test_enumerations_declared(pkg):
    """The interface other code relies on: value references, start values and items."""
    md = pkg.md
    types = {t.name: t for t in md.typeDefinitions}
    v = pkg.vars["initialization"]
    assert (v.type, v.valueReference, v.causality, v.variability, int(v.start)) == \
        ("Enumeration", 1010, "parameter", "fixed", 1)
    assert [(i.name, int(i.value)) for i in types["Initialization"].items] == \
        [("rest", 1), ("static_equilibrium", 2), ("periodic", 3)]
    v = pkg.vars["on_lift_off"]
    assert (v.type, v.valueReference, v.causality, v.variability, int(v.start)) == \
        ("Enumeration", 1011, "parameter", "fixed", 1)
    assert [(i.name, int(i.value)) for i in types["OnLiftOff"].items] == [("warn", 1), ("discard", 2)]


def test_periodic_start_survives_serialization(pkg):
    """A state of a periodic-start run (the start state is not recomputed: it is part of
    the serialized state) continues bit-identically in another instance that was
    initialised from rest, and with its on_lift_off and episode state."""
    names = ["T1", "Fn", "TE", "u1.x"]
    inst = pkg.instance("src")
    inst.initialize({"initialization": 3, "on_lift_off": 2})
    for _ in range(30):
        inst.do_step(1e-5)
    blob = inst.slave.serializeFMUstate(inst.slave.getFMUstate())
    t1 = inst.time
    first = []
    for _ in range(30):
        inst.do_step(1e-5)
        first.append(inst.get(names))
    inst.terminate_and_free()
    other = pkg.instance("dst")
    try:
        other.initialize()
        state = other.slave.deSerializeFMUstate(blob)
        other.slave.setFMUstate(state)
        other.slave.freeFMUstate(state)
        other.time = t1
        assert other.get1("initialization") == 3 and other.get1("on_lift_off") == 2
        for row in first:
            other.do_step(1e-5)
            assert other.get(names) == row
    finally:
        other.terminate_and_free()
