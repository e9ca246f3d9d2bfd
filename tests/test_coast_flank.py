"""The coast flanks and the backlash of the elastic contact (tooth_contact = elastic,
docs/model.md §3.6) through the packaged .fmu, FMI 2.0 and FMI 3.0: the declarations of
j_bn, Fn_coast and impacts; the refusal of j_bn outside 0 <= j_bn <= m_n/2 by name; their
rigid values; a load reversal from the drive to the coast flanks through the play (static
balance of Fn_coast, the drive gap and the transmission error against the play computed
here from the outputs and the calculated parameters) and a rattle on both flanks (impacts
seen in mesh_state and the forces, counted by `impacts`), both with fmi2OK at every
step and nothing logged above OK. The physics against independent computations in Rust:
tests/coast_flank.rs and tests/coast_geometry.rs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from helpers.coast_cases import OMEGA1, omega1_rattle, simulate, t_load_reversal
from helpers.fmu_harness import FMI2_ERROR, FMI2_OK, call_status, run
from helpers.gear_theory import inv

ON_LIFT_OFF = {"warn": 1, "discard": 2}


def transitions(states: np.ndarray) -> list[int]:
    """The mesh states in the order they were seen (repeats removed)."""
    seq = [int(states[0])]
    for s in states[1:]:
        if int(s) != seq[-1]:
            seq.append(int(s))
    return seq


# -- declarations and refusals --------------------------------------------------------

def test_declarations(pkg):
    j = pkg.vars["j_bn"]
    assert j.causality == "parameter" and j.variability == "fixed" and j.type == "Real"
    assert pkg.start("j_bn") == 1e-4
    assert j.declaredType.unit == "m" and float(j.min) == 0.0
    fc = pkg.vars["Fn_coast"]
    assert fc.causality == "output" and fc.type == "Real" and fc.declaredType.unit == "N"
    imp = pkg.vars["impacts"]
    assert imp.causality == "output" and imp.type == "Integer"
    assert imp.variability == "discrete"


@pytest.mark.parametrize("tooth_contact", [1, 2], ids=["rigid", "elastic"])
@pytest.mark.parametrize("bad, shown", [(-1e-5, "-1e-5"), (0.6 * 0.002, "0.0012")],
                         ids=["negative", "0.6m_n"])
def test_j_bn_outside_its_range_is_refused_by_name(pkg, bad, shown, tooth_contact):
    """j_bn = -1e-5 m and 0.6 m_n fail fmi2ExitInitializationMode with fmi2Error and a
    message that names j_bn, its value and its limit m_n/2; j_bn = m_n/2 is accepted."""
    m_n = pkg.start("m_n")
    assert m_n == 0.002
    for value, refused in ((bad, True), (0.5 * m_n, False)):
        inst = pkg.instance("j_bn", logging_on=True)
        try:
            inst.slave.setupExperiment(startTime=0.0)
            inst.set({"j_bn": value, "tooth_contact": tooth_contact})
            inst.slave.enterInitializationMode()
            status = call_status(inst.slave.exitInitializationMode)
            text = inst.log_text()
            if refused:
                assert status >= FMI2_ERROR, (value, text)
                assert f"parameter j_bn = {shown} violates" in text, text
                assert "m_n / 2 = 0.001 m" in text, text
            else:
                assert status == FMI2_OK, (value, text)
        finally:
            inst.free()


def test_rigid_teeth_have_no_coast_force_and_no_impacts(pkg):
    """The rigid model (default) does not use j_bn: Fn_coast 0 and impacts 0, also when
    the load reverses (the rigid outputs' bit-identity is tested elsewhere)."""
    tr = run(pkg, 0.03, 1e-4, params={"T_load": 100.0, "d_phi": 0.05, "j_bn": 3e-4},
             inputs=lambda t: {"T_load": t_load_reversal(t)},
             record=["Fn_coast", "impacts", "mesh_state", "Fn"], name="rigid")
    assert np.all(tr["Fn_coast"] == 0.0)
    assert np.all(tr["impacts"] == 0)
    assert np.all(tr["mesh_state"] == 1)


# -- load reversal --------------------------------------------------------------------

@pytest.mark.parametrize("on_lift_off", list(ON_LIFT_OFF), ids=list(ON_LIFT_OFF))
def test_load_reversal_moves_through_the_play_to_the_coast_flanks(pkg, on_lift_off):
    """T_load +100 -> -100 N m (ramp 20..25 ms), d_phi 0.05, law 1 with mu = 0, from the
    static equilibrium at 3000 rpm: drive flanks, free flight, coast flanks; fmi2OK at
    every step and nothing logged above OK whatever on_lift_off says. At the end the coast
    force carries the reversed load (torque balance of gear 2 over the last 10 ms), the
    drive gap is the play at the displaced centres plus the coast flanks' approach, and
    TE moved by the play and both flanks' approaches less what the centres' motion takes."""
    d_phi = 0.05
    names = ["mesh_state", "Fn", "Fn_coast", "TE", "gap", "mesh_stiffness", "omega2",
             "impacts", "u1.x", "u1.y", "u1.z", "u2.x", "u2.y", "u2.z"]
    tr, cal, statuses, above_ok, _ = simulate(
        pkg, "reversal",
        {"T_load": 100.0, "d_phi": d_phi, "mu": 0.0, "friction_law": 1, "omega1": OMEGA1,
         "on_lift_off": ON_LIFT_OFF[on_lift_off]},
        lambda t: {"T_load": t_load_reversal(t)}, 600, record=names)
    assert set(statuses) == {FMI2_OK}, statuses
    assert not above_ok, above_ok
    ms = tr["mesh_state"]
    assert transitions(ms) == [1, 0, -1], transitions(ms)
    # One flank pair at a time: each force is 0 while the other flanks touch or in flight.
    assert np.all(tr["Fn"] >= 0.0) and np.all(tr["Fn_coast"] >= 0.0)
    assert np.all(tr["Fn_coast"][ms >= 0] == 0.0) and np.all(tr["Fn"][ms <= 0] == 0.0)
    assert np.all(tr["mesh_stiffness"][ms == 0] == 0.0)
    assert np.all(tr["mesh_stiffness"][ms != 0] > 0.0)
    assert np.all(np.diff(tr["impacts"]) >= 0) and tr["impacts"][-1] >= 1

    r_sum, cos_bb = cal["r_b1"] + cal["r_b2"], math.cos(cal["beta_b"])
    tail = tr.t > 0.05 + 1e-9
    fc = np.mean(tr["Fn_coast"][tail])
    fc_static = (100.0 - d_phi * np.mean(tr["omega2"][tail])) / (cal["r_b2"] * cos_bb)

    def centres(i):
        """alpha, theta of the line of centres and the axial offset at sample i."""
        dx = cal["a_w"] + tr["u2.x"][i] - tr["u1.x"][i]
        dy = tr["u2.y"][i] - tr["u1.y"][i]
        return (math.acos(r_sum / math.hypot(dx, dy)), math.atan2(dy, dx),
                tr["u2.z"][i] - tr["u1.z"][i])

    a1, th1, z1 = centres(-1)
    a0, th0, z0 = centres(0)
    play = cal["j_bn"] / cos_bb + 2.0 * r_sum * (inv(a1) - inv(cal["alpha_wt"]))
    approach_coast = tr["Fn_coast"][-1] / (tr["mesh_stiffness"][-1] * cos_bb)
    approach_drive = tr["Fn"][0] / (tr["mesh_stiffness"][0] * cos_bb)
    gap_expected = play + approach_coast
    # TE = r_b2 phi2 - r_b1 phi1: from the drive contact (gap -approach_drive) to the
    # coast contact (gap_expected), less what the centres' motion opens of the gap.
    centres_share = (r_sum * (inv(a1) + th1 - inv(a0) - th0)
                     + math.tan(cal["beta_b"]) * (z1 - z0))
    te_expected = gap_expected + approach_drive - centres_share
    te_moved = tr["TE"][-1] - tr["TE"][0]
    t_free = tr.t[np.argmax(ms == 0)]
    t_coast = tr.t[np.argmax(ms == -1)]
    print(f"\n{pkg.md.fmiVersion} on_lift_off={on_lift_off}: mesh states "
          f"{transitions(ms)} (free flight from {1e3 * t_free:.1f} ms, coast from "
          f"{1e3 * t_coast:.1f} ms), impacts {tr['impacts'][-1]}; mean Fn_coast {fc:.3f} N vs "
          f"static {fc_static:.3f} N ({fc / fc_static - 1:+.2e}); drive gap "
          f"{tr['gap'][-1]:.6e} m vs play + approach {gap_expected:.6e} m "
          f"({(tr['gap'][-1] - gap_expected) / play:+.1e} of the play {play:.5e} m); TE moved "
          f"{te_moved:.6e} m vs {te_expected:.6e} m ({(te_moved - te_expected) / play:+.1e} "
          f"of the play; centres' share {centres_share:.3e} m)")
    assert abs(fc - fc_static) < 1e-3 * fc_static, (fc, fc_static)
    assert abs(tr["gap"][-1] - gap_expected) < 1e-3 * play, (tr["gap"][-1], gap_expected)
    assert abs(te_moved - te_expected) < 1e-3 * play, (te_moved, te_expected)
    # The play dominates: TE moved forward by more than j_bn / cos(beta_b).
    assert te_moved > cal["j_bn"] / cos_bb


# -- rattle ---------------------------------------------------------------------------

_RATTLE: dict[str, tuple] = {}


def rattle(pkg):
    """T_load 0, d_phi 0.01, omega1 +-5 % at 30 Hz set at every communication point
    (0.1 ms) for 0.1 s, on_lift_off = discard (one run per .fmu, shared by the tests)."""
    key = str(pkg.fmu_path)
    if key not in _RATTLE:
        h, n = 1e-4, 1000
        _RATTLE[key] = (h, n) + simulate(
            pkg, "rattle",
            {"T_load": 0.0, "d_phi": 0.01, "omega1": OMEGA1, "on_lift_off": 2},
            lambda t: {"omega1": omega1_rattle(t)}, n, h=h,
            record=["mesh_state", "Fn", "Fn_coast", "impacts", "mesh_stiffness"])
    return _RATTLE[key]


def seen_onsets(ms: np.ndarray) -> np.ndarray:
    """Per communication interval: the flanks touch at its end and did not at its start
    (free flight before, or the other flanks)."""
    return (ms[1:] != 0) & (ms[1:] != ms[:-1])


def test_rattle_hits_both_flanks_and_counts_the_impacts(pkg):
    """The teeth fly through the play and hit both flanks (mesh_state -1, 0, 1; Fn and
    Fn_coast > 0 in their states, 0 elsewhere); `impacts` never decreases and is at least
    the number of contact onsets the communication points see (several onsets may fall
    into one interval); fmi2OK at every step and nothing logged above OK, with
    on_lift_off = discard."""
    h, n, tr, _, statuses, above_ok, cpu = rattle(pkg)
    assert set(statuses) == {FMI2_OK}, statuses
    assert not above_ok, above_ok
    ms, fn, fc, imp = tr["mesh_state"], tr["Fn"], tr["Fn_coast"], tr["impacts"]
    assert set(np.unique(ms)) == {-1, 0, 1}, np.unique(ms)
    assert np.all(fn >= 0.0) and np.all(fc >= 0.0)
    assert np.any(fn[ms == 1] > 0.0) and np.any(fc[ms == -1] > 0.0)
    assert np.all(fc[ms >= 0] == 0.0) and np.all(fn[ms <= 0] == 0.0)
    assert np.all(tr["mesh_stiffness"][ms == 0] == 0.0)
    onset = seen_onsets(ms)
    drive, coast = int(np.sum(onset & (ms[1:] == 1))), int(np.sum(onset & (ms[1:] == -1)))
    assert imp[0] == 0 and np.all(np.diff(imp) >= 0)
    assert imp[-1] >= drive + coast, (imp[-1], drive, coast)
    t_sim = n * h
    print(f"\n{pkg.md.fmiVersion} rattle {t_sim:.1f} s: {imp[-1]} impacts ({imp[-1] / t_sim:.0f} "
          f"per second; onsets seen at the communication points: {drive} drive, {coast} "
          f"coast); samples drive/free/coast {np.sum(ms == 1)}/{np.sum(ms == 0)}/"
          f"{np.sum(ms == -1)}; max Fn {fn.max():.0f} N, max Fn_coast {fc.max():.0f} N; "
          f"CPU {cpu / t_sim:.2f} s per simulated second (tolerance 1e-8)")
    assert drive > 0 and coast > 0, (drive, coast)
    assert 200 < imp[-1] / t_sim < 1000, imp[-1] / t_sim


def test_rattle_counts_each_onset_in_its_interval(pkg):
    """Every communication interval at whose end the flanks touch and at whose start they
    did not raises `impacts` by at least 1 (the onset is in that interval)."""
    _, _, tr, *_ = rattle(pkg)
    ms, imp = tr["mesh_state"], tr["impacts"]
    onset = seen_onsets(ms)
    missed = tr.t[1:][onset & (np.diff(imp) < 1)]
    assert missed.size == 0, f"onsets not counted in the interval ending at {missed} s"


# -- outside the model: tooth overload ------------------------------------------------

@pytest.mark.parametrize("on_lift_off", list(ON_LIFT_OFF), ids=list(ON_LIFT_OFF))
def test_tooth_overload_is_reported_once(pkg, on_lift_off):
    """A spur pair without backlash driven onto its parametrically unstable orbit (6500 rpm
    for 50 ms, then 6000 rpm; docs/dynamic_factor.md): the vibration grows until the flanks
    overlap by more than m_n/20, where the model leaves its validity. warn: one warning
    naming the tooth overload in the log, the run goes on; discard: fmi2Discard, and the FMU time (the
    last successful time) is the located instant, where |mesh_deflection| is m_n/20."""
    rpm = math.pi / 30.0
    params = {"T_load": 100.0, "d_phi": 0.0, "mu": 0.0, "friction_law": 1, "beta": 0.0,
              "j_bn": 0.0, "omega1": 6500.0 * rpm, "on_lift_off": ON_LIFT_OFF[on_lift_off]}
    inst = pkg.instance("overload", logging_on=True)
    try:
        inst.initialize({"tooth_contact": 2, "initialization": 2, **params}, tolerance=1e-8)
        m_n = inst.get(["m_n"])["m_n"]
        h, t, statuses = 1e-4, 0.0, []
        for k in range(1500):
            inst.set({"omega1": (6500.0 if k < 500 else 6000.0) * rpm})
            st = call_status(inst.do_step, h)
            statuses.append(st)
            if st != FMI2_OK and on_lift_off == "discard":
                break
            t += h
        warnings = [str(r) for r in inst.log if r.status > FMI2_OK]
        print(on_lift_off, set(statuses), warnings[:1])
        if on_lift_off == "warn":
            # (FMPy raises only above fmi2Warning: the warning shows in the log.)
            assert set(statuses) == {FMI2_OK}, set(statuses)
            assert len(warnings) == 1 and "tooth overload" in warnings[0], warnings
        else:
            assert statuses[-1] == 2, statuses[-1]
            assert any("tooth overload" in w for w in warnings), warnings
            delta = abs(inst.get(["mesh_deflection"])["mesh_deflection"])
            print(f"stopped with |mesh_deflection| = {delta:.6e} m (limit {0.05 * m_n:.1e} m)")
            assert delta == pytest.approx(0.05 * m_n, rel=0.02)
    finally:
        inst.terminate_and_free()
