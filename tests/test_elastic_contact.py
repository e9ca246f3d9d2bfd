"""The elastic contact through the packaged .fmu (tooth_contact = elastic, docs/model.md
§3.5): the new variables' declarations, their rigid values, an elastic run on the drive
flanks whose outputs obey (3.13)-(3.17) and the energy balance (3.21), a rattle run without
Discard or warning (with on_lift_off = discard) whose free flight has no force and no
stiffness, and the start on the periodic orbit. The coast flanks and the backlash (load
reversal, impacts on both flanks, j_bn): tests/test_coast_flank.py. The physics checks
against independent computations are in tests/elastic_contact.rs and tests/coast_flank.rs."""

from __future__ import annotations

import math

import numpy as np

from helpers.fmu_harness import FMI2_OK, call_status, run
from helpers.gear_theory import GearData, geometry

NEW_OUTPUTS = ["mesh_deflection", "mesh_stiffness", "mesh_state", "W_mesh_stiffness",
               "Fn_coast", "impacts"]
ENERGIES = ["E_in", "E_load", "E_kin", "E_pot", "E_loss", "E_damp", "W_mesh_stiffness"]


def test_declarations(pkg):
    tc = pkg.vars["tooth_contact"]
    assert tc.causality == "parameter" and tc.variability == "fixed"
    assert tc.type == "Enumeration" and pkg.start("tooth_contact") == 1
    assert [i.name for i in tc.declaredType.items] == ["rigid", "elastic"]
    assert pkg.start("zeta_mesh") == 0.05
    for n in NEW_OUTPUTS:
        assert pkg.vars[n].causality == "output", n


def test_rigid_values_of_the_new_outputs(pkg):
    tr = run(pkg, 2e-3, 1e-4, params={"T_load": 50.0}, record=NEW_OUTPUTS + ["Fn"])
    assert np.all(tr["mesh_deflection"] == 0.0) and np.all(tr["mesh_stiffness"] == 0.0)
    assert np.all(tr["mesh_state"] == 1) and np.all(tr["W_mesh_stiffness"] == 0.0)
    assert np.all(tr["Fn_coast"] == 0.0) and np.all(tr["impacts"] == 0)


def balance(tr):
    d = {n: tr[n] - tr[n][0] for n in ENERGIES}
    return (d["E_in"] + d["W_mesh_stiffness"]
            - (d["E_load"] + d["E_kin"] + d["E_pot"] + d["E_loss"] + d["E_damp"]))


def test_elastic_run_follows_the_contact_law_and_balances_energy(pkg):
    params = {"tooth_contact": 2, "initialization": 2, "T_load": 80.0}
    tr = run(pkg, 0.01, 1e-4, params=params, tolerance=1e-8,
             record=NEW_OUTPUTS + ENERGIES + ["Fn", "contact_length", "c_gamma_used"])
    g = geometry(GearData())
    cos_bb = math.cos(g.beta_b)
    c_l = tr["c_gamma_used"][0] * cos_bb / g.eps_alpha
    assert np.allclose(tr["mesh_stiffness"], c_l * tr["contact_length"], rtol=1e-12)
    # 80 N m keeps the drive flanks in contact: the coast flanks never touch.
    assert np.all(tr["mesh_state"] == 1) and np.all(tr["Fn"] > 0)
    assert np.all(tr["Fn_coast"] == 0.0) and np.all(tr["impacts"] == 0)
    # Fn = k delta + damping: within a few per cent of the static relation.
    static = tr["mesh_stiffness"] * tr["mesh_deflection"]
    assert np.all(np.abs(tr["Fn"] - static) < 0.05 * tr["Fn"])
    worst = np.max(np.abs(balance(tr))) / tr["E_in"][-1]
    assert worst < 1e-8, worst


def test_rattle_without_discard_or_warning(pkg):
    """omega1 +-5 % at 30 Hz without load: the drive flanks part and meet again (and,
    through the play j_bn, the coast flanks are hit: mesh_state -1), never a Discard or a
    warning with on_lift_off = discard. In free flight (mesh_state 0) no flank force and no
    stiffness (mesh_stiffness is that of the flanks in contact, 0 in flight); Fn only on
    the drive flanks."""
    w = 314.159
    params = {"tooth_contact": 2, "initialization": 2, "d_phi": 0.01, "on_lift_off": 2,
              "omega1": w}
    inst = pkg.instance("rattle", logging_on=True)
    try:
        inst.initialize(params)
        states, fn_min = [], math.inf
        h = 1e-4
        for k in range(500):
            t = k * h
            inst.set({"omega1": w * (1 + 0.05 * math.sin(2 * math.pi * 30 * t))})
            assert call_status(inst.do_step, h) == FMI2_OK, inst.messages()
            o = inst.get(["Fn", "Fn_coast", "mesh_state", "mesh_stiffness"])
            states.append(int(o["mesh_state"]))
            fn_min = min(fn_min, o["Fn"])
            if o["mesh_state"] == 0:
                assert o["mesh_stiffness"] == 0.0 and o["Fn"] == 0.0 and o["Fn_coast"] == 0.0
            else:
                assert o["mesh_stiffness"] > 0.0
            if o["mesh_state"] == -1:
                assert o["Fn"] == 0.0
        free = states.count(0)
        assert free > 10, free
        assert states.count(1) > 10 and states.count(-1) > 0, states
        assert fn_min >= 0.0
        assert not inst.messages(min_status=1), inst.messages(min_status=1)
    finally:
        inst.terminate_and_free()


def test_periodic_start_in_elastic_mode_is_on_the_orbit(pkg):
    """initialization = periodic with elastic teeth (src/periodic/elastic.rs,
    docs/dynamic_factor.md): the run starts on the periodic orbit, so every output repeats
    after one mesh period T_m = 2 pi / (z1 omega1) (model.md (9.4)), from the first period on;
    the orbit is a real vibration (Fn and TE vary over the period)."""
    omega1, z1, n = 314.159, 27, 20
    t_m = 2.0 * math.pi / (z1 * omega1)
    tr = run(pkg, 2.0 * t_m, t_m / n, params={"tooth_contact": 2, "initialization": 3,
                                              "T_load": 50.0, "omega1": omega1},
             tolerance=1e-8, record=["Fn", "TE", "mesh_deflection"], name="periodic_elastic")
    for name in ("Fn", "TE", "mesh_deflection"):
        x = tr[name]
        pp = np.ptp(x[: n + 1])
        assert pp > 1e-6 * np.max(np.abs(x)), name
        dev = np.max(np.abs(x[n:] - x[: n + 1]))
        print(f"{name}: peak to peak {pp:.4g}, repeats after T_m to {dev / pp:.2e} of it")
        assert dev <= 1e-4 * pp, name


def test_serialized_elastic_state_continues_identically(pkg):
    """The FMU state carries the contact model: an elastic state deserialised into an
    instance initialised with the default (rigid) contact continues as the original."""
    from helpers.fmu_harness import Recorder

    names = ["Fn", "TE", "mesh_deflection", "mesh_state", "E_pot", "W_mesh_stiffness"]
    h = 1e-4

    def steps(inst, n):
        rec = Recorder(inst, names)
        for _ in range(n):
            inst.do_step(h, no_set_prior=False)
            rec.sample()
        return rec.trajectory()

    inst = pkg.instance("elastic_state")
    inst.initialize({"tooth_contact": 2, "T_load": 50.0})
    for _ in range(20):
        inst.do_step(h, no_set_prior=False)
    t1 = inst.time
    state = inst.slave.getFMUstate()
    blob = inst.slave.serializeFMUstate(state)
    inst.slave.freeFMUstate(state)
    first = steps(inst, 30)
    inst.terminate_and_free()
    assert np.all(first["mesh_deflection"] > 0)

    other = pkg.instance("rigid_then_elastic")
    other.initialize({"T_load": 50.0})
    s = other.slave.deSerializeFMUstate(blob)
    other.slave.setFMUstate(s)
    other.slave.freeFMUstate(s)
    other.time = t1
    again = steps(other, 30)
    other.terminate_and_free()
    for n in names:
        assert np.array_equal(first[n], again[n]), n
