"""The mesh stiffness of ISO 6336-1, method B, through the packaged .fmu (docs/model.md
§2.1): the calculated parameter c_gamma_used for the default pair and for c_gamma set
explicitly, its unit and display unit, the refusal of invalid h_fP / c_gamma, and that
neither parameter changes the rigid model's outputs (issue 27: reported only)."""

from __future__ import annotations

import math

import pytest

from helpers.fmu_harness import FMI2_ERROR, call_status, run
from helpers.gear_theory import GearData, geometry

N_PER_MM_UM = 1e9  # 1 N/(mm um) in N/m^2


def iso_6336_c_gamma(z1, z2, alpha_n, beta, x1, x2, h_fp, eps_alpha):
    """c_gamma_alpha in N/m^2, written out here from ISO 6336-1, method B (solid steel
    gears), independently of the model's Rust code."""
    beta_b = math.asin(math.sin(beta) * math.cos(alpha_n))
    k = math.cos(beta_b) ** 2 * math.cos(beta)
    zn1, zn2 = z1 / k, z2 / k
    q = (0.04723 + 0.15551 / zn1 + 0.25791 / zn2 - 0.00635 * x1 - 0.11654 * x1 / zn1
         - 0.00193 * x2 - 0.24188 * x2 / zn2 + 0.00529 * x1 ** 2 + 0.00182 * x2 ** 2)
    c_b = (1 + 0.5 * (1.2 - h_fp)) * (1 - 0.02 * (20 - math.degrees(alpha_n)))
    c_prime = (1 / q) * 0.8 * 1.0 * c_b * math.cos(beta)
    return c_prime * (0.75 * eps_alpha + 0.25) * N_PER_MM_UM


def calculated(pkg, params=None):
    inst = pkg.instance("stiffness")
    try:
        inst.initialize(params)
        return inst.get(["c_gamma_used", "eps_alpha", "c_gamma", "h_fP"])
    finally:
        inst.terminate_and_free()


def test_declaration(pkg):
    for name in ("c_gamma", "c_gamma_used"):
        t = pkg.vars[name].declaredType
        assert t.unit == "N/m2" and t.displayUnit == "N/(mm.um)", name
    unit = next(u for u in pkg.md.unitDefinitions if u.name == "N/m2")
    assert {d.name: d.factor for d in unit.displayUnits} == {"N/(mm.um)": 1e-9}
    assert pkg.vars["c_gamma"].causality == "parameter"
    assert pkg.vars["c_gamma_used"].causality == "calculatedParameter"
    assert pkg.start("c_gamma") == 0.0 and pkg.start("h_fP") == 1.25


@pytest.mark.parametrize(
    "changes",
    [{}, {"h_fP": 1.4}, {"x1": 0.3, "x2": -0.1, "beta": math.radians(15.0), "z1": 23, "z2": 52},
     {"beta": 0.0}],
    ids=["defaults", "h_fP-1.4", "shifted-15deg", "spur"],
)
def test_c_gamma_used_from_iso_6336(pkg, changes):
    g = GearData().with_(**{k: v for k, v in changes.items() if k != "h_fP"})
    eps_alpha = geometry(g).eps_alpha
    c = calculated(pkg, changes)
    assert c["eps_alpha"] == pytest.approx(eps_alpha, rel=1e-9)
    want = iso_6336_c_gamma(g.z1, g.z2, g.alpha_n, g.beta, g.x1, g.x2,
                            changes.get("h_fP", 1.25), eps_alpha)
    assert c["c_gamma_used"] == pytest.approx(want, rel=1e-12)


def test_default_pair_value(pkg):
    """The default pair (z 27/41, m_n 2 mm, beta 20 deg, h_fP 1.25): 17.9097 N/(mm um)
    (the hand value of tests/gear_stiffness.rs)."""
    c = calculated(pkg)
    assert f"{c['c_gamma_used'] / N_PER_MM_UM:.4f}" == "17.9097"


def test_c_gamma_given_is_used_as_is(pkg):
    c = calculated(pkg, {"c_gamma": 14.0e9, "h_fP": 1.4})
    assert c["c_gamma_used"] == 14.0e9
    assert c["c_gamma"] == 14.0e9


@pytest.mark.parametrize("bad", [{"h_fP": 0.0}, {"c_gamma": -1.0}], ids=["h_fP", "c_gamma"])
def test_invalid_values_are_refused(pkg, bad):
    inst = pkg.instance("refused", logging_on=True)
    try:
        inst.slave.setupExperiment(startTime=0.0)
        inst.set(bad)
        inst.slave.enterInitializationMode()
        assert call_status(inst.slave.exitInitializationMode) >= FMI2_ERROR
        name = next(iter(bad))
        assert f"parameter {name} =" in inst.log_text(), inst.log_text()
    finally:
        inst.free()


def test_rigid_model_does_not_use_them(pkg):
    names = ["T1", "Fn", "TE", "u1.x", "u2.y", "P_loss"]
    a = run(pkg, 2e-3, 1e-4, record=names)
    b = run(pkg, 2e-3, 1e-4, params={"c_gamma": 5.0e9, "h_fP": 1.4}, record=names)
    for n in names:
        assert list(a[n]) == list(b[n]), n
