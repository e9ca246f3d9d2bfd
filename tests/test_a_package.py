"""(a) The packaged .fmu: FMPy's validation finds no problems, simulate_fmu runs
the defaults for 50 ms, and the description matches the contract (fmu.md
"Variables"): names, causalities, capabilities, start values of model.md
section 10, calculated parameters against an independent computation."""

from __future__ import annotations

import math
import zipfile

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from helpers.gear_theory import (
    GearData,
    face_width_for_overlap,
    geometry,
    h_v_helical_integer_overlap,
    h_v_ohlendorf,
    h_v_spur,
)

VEC = (".x", ".y", ".z")
REAL_OUTPUTS = [
    "T1", "omega1_filtered", "omega2", "phi1", "phi2", "Fn", "TE", "gap", "P_in", "P_loss",
    "P_damp", "E_in", "E_loss", "E_damp", "E_load", "E_kin", "E_pot", "contact_length",
] + [
    v + c
    for v in ["u1", "u2", "v1", "v2", "F_bearing1", "F_bearing2", "F_friction1", "F_friction2",
              "M_friction1", "M_friction2", "F_contact1", "F_contact2", "M_contact1", "M_contact2"]
    for c in VEC
]
PARAMETERS_REAL = ["m_n", "alpha_n", "beta", "b", "x1", "x2", "h_aP", "a_w_set", "psi0", "m1", "J1",
                   "m2", "J2", "d_phi", "mu", "omega1_filter_frequency", "rtol", "h_max"] + [
    p + c for p in ["k1", "d1", "k2", "d2"] for c in VEC]
CALCULATED = ["r_b1", "r_b2", "a_w", "alpha_wt", "beta_b", "p_bt", "eps_alpha", "eps_beta", "H_V"]

# model.md section 10 (the defaults the start values must equal)
DEFAULTS = {
    "z1": 27, "z2": 41, "m_n": 2.0e-3, "alpha_n": math.radians(20), "beta": math.radians(20),
    "b": 18e-3, "x1": 0.0, "x2": 0.0, "h_aP": 1.0, "psi0": 0.0,
    "m1": 2.0, "J1": 1.0e-3, "k1.x": 2e8, "k1.y": 2e8, "k1.z": 1e8,
    "d1.x": 1200.0, "d1.y": 1200.0, "d1.z": 850.0,
    "m2": 4.0, "J2": 5.0e-3, "k2.x": 2e8, "k2.y": 2e8, "k2.z": 1e8,
    "d2.x": 1700.0, "d2.y": 1700.0, "d2.z": 1200.0,
    "d_phi": 0.5, "mu": 0.05, "omega1": 314.159, "T_load": 0.0,
    "omega1_filter_frequency": 1000.0, "rtol": 1e-6, "friction_law": 1,
}


def test_validate_fmu_reports_no_problems(fmu_path):
    problems = validate_fmu(str(fmu_path))
    assert problems == [], "\n".join(problems)


def test_archive_layout(fmu_path):
    names = set(zipfile.ZipFile(fmu_path).namelist())
    for required in ("modelDescription.xml", "binaries/linux64/GearedRotor.so",
                     "documentation/index.html"):
        assert required in names, f"{required} missing from the .fmu ({sorted(names)})"


def test_simulate_fmu_defaults_50ms(fmu_path):
    res = simulate_fmu(str(fmu_path), stop_time=0.05, output=["T1", "omega2", "Fn", "TE", "P_loss"])
    t = res["time"]
    assert t[0] == 0.0 and t[-1] == pytest.approx(0.05, abs=1e-12)
    for name in ("T1", "omega2", "Fn", "TE", "P_loss"):
        assert np.all(np.isfinite(res[name])), name
    # physics sanity (independent of the code): mean omega2 ~ omega1 z1/z2 in the
    # second half, mean T1 ~ the frictionless steady torque d_phi omega1 (z1/z2)^2
    # raised by a few per cent of friction loss.
    w1 = DEFAULTS["omega1"]
    ratio = DEFAULTS["z1"] / DEFAULTS["z2"]
    late = t >= 0.025
    assert np.mean(res["omega2"][late]) == pytest.approx(w1 * ratio, rel=1e-3)
    t_steady = DEFAULTS["d_phi"] * w1 * ratio**2
    assert t_steady < np.mean(res["T1"][late]) < 1.1 * t_steady
    assert np.all(res["P_loss"] >= 0.0)


def test_interface_names_types_causalities(pkg):
    v = pkg.vars
    assert pkg.md.fmiVersion == "2.0"
    assert pkg.md.coSimulation is not None and pkg.md.coSimulation.modelIdentifier == "GearedRotor"
    assert pkg.md.variableNamingConvention == "structured"
    for n in ("omega1", "T_load"):
        assert v[n].causality == "input" and v[n].type == "Real", n
    for n in REAL_OUTPUTS:
        assert n in v, f"output {n} missing"
        assert v[n].causality == "output" and v[n].type == "Real", n
    assert v["pairs_in_contact"].causality == "output" and v["pairs_in_contact"].type == "Integer"
    assert v["contact_lost"].causality == "output" and v["contact_lost"].type == "Boolean"
    for n in PARAMETERS_REAL:
        assert n in v and v[n].causality == "parameter" and v[n].type == "Real", n
    for n in ("z1", "z2", "friction_law"):
        assert v[n].causality == "parameter" and v[n].type == "Integer", n
    assert v["mu"].variability == "tunable" and v["d_phi"].variability == "tunable"
    for n in ("z1", "m_n", "beta", "b"):
        assert v[n].variability == "fixed", n
    for n in CALCULATED:
        assert v[n].causality == "calculatedParameter", n
    for var in pkg.md.modelVariables:
        assert var.description, f"{var.name} has no description"
    structure = {u.variable.name for u in pkg.md.outputs}
    assert structure == {o.name for o in pkg.outputs}


def test_capabilities_declared(pkg):
    cs = pkg.md.coSimulation
    assert cs.canHandleVariableCommunicationStepSize
    assert cs.canInterpolateInputs
    assert cs.maxOutputDerivativeOrder >= 1
    assert cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    assert cs.canNotUseMemoryManagementFunctions
    assert not cs.canBeInstantiatedOnlyOncePerProcess
    cats = {c.name for c in pkg.md.logCategories}
    assert {"logStatusError", "logStatusWarning", "logEvents", "logSolver"} <= cats


def test_start_values_are_model_md_defaults(pkg):
    for name, value in DEFAULTS.items():
        assert pkg.start(name) == pytest.approx(value, rel=1e-12, abs=0.0), name


def test_units_and_display_units(pkg):
    units = {u.name: u for u in pkg.md.unitDefinitions}
    assert units, "no UnitDefinitions"
    display = {d.name for u in units.values() for d in u.displayUnits}
    for wanted in ("rpm", "deg", "mm"):
        assert wanted in display, f"display unit {wanted} missing ({sorted(display)})"


def _calculated(pkg, params=None):
    inst = pkg.instance("calc")
    try:
        inst.initialize(params)
        return inst.get(CALCULATED)
    finally:
        inst.terminate_and_free()


def test_default_geometry_matches_model_md_reference(pkg):
    """model.md section 2 reference values (published with the spec)."""
    c = _calculated(pkg)
    assert c["r_b1"] == pytest.approx(26.793197e-3, rel=1e-7)
    assert c["r_b2"] == pytest.approx(40.685966e-3, rel=1e-7)
    assert math.degrees(c["beta_b"]) == pytest.approx(18.747237, rel=1e-7)
    assert math.degrees(c["alpha_wt"]) == pytest.approx(21.172832, rel=1e-7)
    assert c["a_w"] == pytest.approx(72.364089e-3, rel=1e-7)
    assert c["p_bt"] == pytest.approx(6.235060e-3, rel=1e-6)
    assert c["eps_alpha"] == pytest.approx(1.536206, rel=1e-6)
    assert c["eps_beta"] == pytest.approx(0.979816, rel=1e-6)


@pytest.mark.parametrize(
    "changes",
    [
        {},
        {"x1": 0.3, "x2": -0.1, "beta": math.radians(15.0), "z1": 23, "z2": 52},
        {"beta": 0.0},
        {"a_w_set": 73.0e-3},
    ],
    ids=["defaults", "shifted-15deg", "spur", "a_w-given"],
)
def test_calculated_parameters_match_independent_formulas(pkg, changes):
    g = GearData().with_(**changes)
    geo = geometry(g)
    c = _calculated(pkg, changes)
    for name in ("r_b1", "r_b2", "a_w", "alpha_wt", "beta_b", "p_bt", "eps_alpha", "eps_beta"):
        assert c[name] == pytest.approx(getattr(geo, name), rel=1e-9, abs=1e-15), name


def test_h_v_for_integer_overlap_matches_independent_formula(pkg):
    g = GearData()
    b = face_width_for_overlap(g, 1.0)
    c = _calculated(pkg, {"b": b})
    assert c["eps_beta"] == pytest.approx(1.0, rel=1e-12)
    assert c["H_V"] == pytest.approx(h_v_helical_integer_overlap(g.with_(b=b)), rel=1e-9)


def test_h_v_for_spur_matches_independent_formula(pkg):
    g = GearData().with_(beta=0.0)
    c = _calculated(pkg, {"beta": 0.0})
    assert c["H_V"] == pytest.approx(h_v_spur(g), rel=1e-9)
    # eps_1, eps_2 <= 1 here, so Ohlendorf's closed form must agree as well
    assert c["H_V"] == pytest.approx(h_v_ohlendorf(g), rel=1e-9)
