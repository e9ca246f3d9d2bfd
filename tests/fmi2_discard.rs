//! Solver failure -> fmi2Discard with the state at fmi2LastSuccessfulTime; rollback after it;
//! tooth lift-off reported through logEvents and the contact_lost output.

mod common;

use common::fmi2::log_category;
use common::fmi2::Fmu;
use geared_rotor::c_abi::*;
use geared_rotor::fmi2::types::*;
use geared_rotor::fmi2::variables::by_name;
use std::ptr;

#[test]
fn solver_failure_is_a_discard_at_the_last_successful_time_and_can_be_rolled_back() {
    let f = Fmu::new("discard", false);
    f.init();
    assert_eq!(f.step(0.0, 1e-4), Fmi2Status::OK);
    let mut st: Fmi2FMUstate = ptr::null_mut();
    assert_eq!(unsafe { fmi2GetFMUstate(f.c, &mut st) }, Fmi2Status::OK);
    // 1e5 N m against a 27/41 pair with 2e8 N/m bearings: the centres are pushed apart until
    // no contact line is left in the active area; RADAU5 cannot continue.
    assert_eq!(f.set_real("T_load", 1e5), Fmi2Status::OK);
    assert_eq!(f.step(1e-4, 1e-2), Fmi2Status::Discard);
    let m = f.last_message();
    assert!(
        m.contains("fmi2DoStep") && m.contains("last successful time"),
        "{m}"
    );
    let mut last = 0.0;
    assert_eq!(
        unsafe { fmi2GetRealStatus(f.c, status_kind::LAST_SUCCESSFUL_TIME, &mut last) },
        Fmi2Status::OK
    );
    assert!(last > 1e-4 && last < 1e-4 + 1e-2, "{last}");
    // The outputs are those of the last successful time (finite) and E_in grew.
    assert!(f.all_real_outputs().iter().all(|x| x.is_finite()));
    // StepFailed: no further doStep, but rollback works.
    assert_eq!(f.step(last, 1e-5), Fmi2Status::Error);
    assert!(f.last_message().contains("illegal call sequence"));
    assert_eq!(unsafe { fmi2SetFMUstate(f.c, st) }, Fmi2Status::OK);
    assert_eq!(f.real("T_load"), 0.0);
    assert_eq!(f.step(1e-4, 1e-4), Fmi2Status::OK);
}

#[test]
fn tooth_lift_off_is_logged_under_log_events() {
    let f = Fmu::new("liftoff", false);
    assert_eq!(log_category(f.c, "logEvents"), Fmi2Status::OK);
    f.init();
    assert_eq!(f.step(0.0, 1e-4), Fmi2Status::OK);
    // A negative load larger than the damper torque drives gear 2: lambda < 0.
    assert_eq!(f.set_real("T_load", -1e3), Fmi2Status::OK);
    let mut t = 1e-4;
    let mut lost_seen = false;
    for _ in 0..50 {
        // The step in which the teeth lift off returns fmi2Warning (sim::validity).
        if !matches!(f.step(t, 1e-4), Fmi2Status::OK | Fmi2Status::Warning) {
            break;
        }
        t += 1e-4;
        let vr = by_name("contact_lost").unwrap().vr;
        let mut b = 0;
        unsafe { fmi2GetBoolean(f.c, &vr, 1, &mut b) };
        lost_seen |= b == FMI2_TRUE;
    }
    assert!(lost_seen);
    let msgs = f.messages();
    assert!(
        msgs.iter()
            .any(|m| m.1 == "logEvents" && m.2.contains("contact_lost changed")),
        "{msgs:?}"
    );
    assert!(
        msgs.iter()
            .any(|m| m.1 == "logStatusWarning" && m.2.contains("lift-off at t = ")),
        "{msgs:?}"
    );
    // logEvents names the located instant of the change, the one of the lift-off warning
    // (not the end of the step that revealed it).
    let after = |m: &str, key: &str| -> f64 {
        let rest = &m[m.find(key).unwrap() + key.len()..];
        rest.split(' ').next().unwrap().parse().unwrap()
    };
    let ev = msgs
        .iter()
        .find(|m| m.1 == "logEvents" && m.2.contains("contact_lost changed"))
        .unwrap();
    let warn = msgs
        .iter()
        .find(|m| m.1 == "logStatusWarning" && m.2.contains("lift-off at t = "))
        .unwrap();
    let (t_ev, t_warn) = (
        after(&ev.2, "first at t = "),
        after(&warn.2, "lift-off at t = "),
    );
    assert!((t_ev - t_warn).abs() <= 1e-9, "{t_ev} vs {t_warn}");
}
