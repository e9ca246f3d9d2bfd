//! Nothing a master or a stored state can do hangs or poisons the FMU: the hang recipes of
//! a fuzz run return with a defined status, tunables and inputs are checked when set,
//! outputs after a Discard are those of fmi2LastSuccessfulTime, resealed state blobs with
//! wrong contents are refused, numbers in messages are short (docs/fmu.md "Robustness").
//!
//! A hang must fail a test, not block the suite: each suspicious call runs in a thread and
//! the test fails if it has not returned after a generous wait (this detects a call that
//! never returns; it is not a speed assertion).

mod common;

use common::fmi2::Fmu;
use geared_rotor::c_abi::*;
use geared_rotor::fmi2::types::*;
use geared_rotor::fmi2::variables::{by_name, Causality, VarType, VARIABLES};
use geared_rotor::radau5::Snapshot;
use geared_rotor::rotor::{Params, NY};
use geared_rotor::sim::{Simulation, SolverSettings};
use std::ptr;
use std::sync::mpsc;
use std::time::Duration;

/// Generous bound for "returned at all" (a hang runs forever; the slowest legitimate call
/// here takes well under a second on an idle machine).
const HANG: Duration = Duration::from_secs(120);

/// Runs `f` in a thread; fails the test if it does not return within [`HANG`].
fn returns<T: Send + 'static>(what: &str, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    match rx.recv_timeout(HANG) {
        Ok(v) => v,
        Err(_) => panic!("{what}: no return within {} s (hang)", HANG.as_secs()),
    }
}

fn last_successful_time(f: &Fmu) -> f64 {
    let mut t = f64::NAN;
    assert_eq!(
        unsafe { fmi2GetRealStatus(f.c, status_kind::LAST_SUCCESSFUL_TIME, &mut t) },
        Fmi2Status::OK
    );
    t
}

fn set_integer(f: &Fmu, name: &str, x: i32) -> Fmi2Status {
    let vr = by_name(name).unwrap().vr;
    unsafe { fmi2SetInteger(f.c, &vr, 1, &x) }
}

fn init_at(f: &Fmu, start: f64) {
    unsafe {
        assert_eq!(
            fmi2SetupExperiment(f.c, 0, 0.0, start, 0, 0.0),
            Fmi2Status::OK
        );
        assert_eq!(fmi2EnterInitializationMode(f.c), Fmi2Status::OK);
        assert_eq!(fmi2ExitInitializationMode(f.c), Fmi2Status::OK);
    }
}

// ------------------------------------------------------------------ hang recipes

/// Recipe 1: fmi2DoStep(0, h) without a stopTime over an enormous interval. The work per
/// doStep is bounded (max_internal_steps): fmi2Discard, stopped inside the interval, at a
/// time the master can read, with finite outputs there.
#[test]
fn an_enormous_communication_step_returns_with_a_discard_inside_it() {
    for h in [1e6, 1e10, 1e300] {
        let (status, last, outs, msg) = returns(&format!("fmi2DoStep(0, {h:e})"), move || {
            let f = Fmu::new("huge_h", false);
            f.init();
            let s = f.step(0.0, h);
            let last = last_successful_time(&f);
            (s, last, f.all_real_outputs(), f.last_message())
        });
        assert_eq!(status, Fmi2Status::Discard, "h = {h:e}: {msg}");
        assert!(last > 0.0 && last < h, "h = {h:e}: last = {last}");
        assert!(msg.contains("max_internal_steps"), "{msg}");
        assert!(outs.iter().all(|x| x.is_finite()));
    }
}

/// Recipe 2 (FMI): omega1 = 1e30 in initialisation mode from startTime = 1 is refused when
/// it is set (it lies outside the declared bounds of omega1), naming omega1 and the bound.
#[test]
fn an_absurd_omega1_is_refused_when_set() {
    for x in [1e30, 1e20, -1e30] {
        let f = Fmu::new("omega1", false);
        unsafe {
            assert_eq!(
                fmi2SetupExperiment(f.c, 0, 0.0, 1.0, 0, 0.0),
                Fmi2Status::OK
            );
            assert_eq!(fmi2EnterInitializationMode(f.c), Fmi2Status::OK);
        }
        assert_eq!(f.set_real("omega1", x), Fmi2Status::Error);
        let m = f.last_message();
        assert!(
            m.contains("omega1") && m.contains("max") || m.contains("min"),
            "{m}"
        );
    }
}

/// Recipe 2 (progress guard, below the FMI checks): the simulation with omega1 = 1e30
/// from t = 1 used to predict mesh events closer than t can resolve (t + dt == t) and loop
/// without end. Now each loop advances time or ends with a typed error.
#[test]
fn a_step_that_cannot_advance_time_ends_with_an_error() {
    for (t0, omega1) in [(1.0, 1e30), (1.0, 1e20), (0.0, 1e30), (1e6, 1e12)] {
        let r = returns(
            &format!("do_step at t0 = {t0} with omega1 = {omega1:e}"),
            move || {
                let settings = SolverSettings {
                    rtol: 1e-6,
                    h_max: 1e-4,
                };
                let mut sim = Simulation::new(Params::default(), settings, t0, omega1, 0.0)
                    .map_err(|e| e.to_string())?;
                sim.do_step(t0, 1e-4).map(|_| ()).map_err(|e| e.to_string())
            },
        );
        // The progress guard, not the work bound, ends it.
        let m = r.expect_err("an error");
        assert!(
            m.contains("step size too small"),
            "t0 = {t0}, omega1 = {omega1:e}: {m}"
        );
    }
}

/// Recipe 3: a long interval at a time where steps are small compared with t: bounded too.
#[test]
fn a_long_step_far_from_zero_returns() {
    let (status, last, outs) = returns("fmi2DoStep(1e3, 1e3)", || {
        let f = Fmu::new("far", false);
        init_at(&f, 1e3);
        let s = f.step(1e3, 1e3);
        (s, last_successful_time(&f), f.all_real_outputs())
    });
    assert_eq!(status, Fmi2Status::Discard);
    assert!(last > 1e3 && last < 2e3, "{last}");
    assert!(outs.iter().all(|x| x.is_finite()));
}

// ------------------------------------------------------------------ work bound

/// The bound is the parameter max_internal_steps: a doStep that needs more step attempts
/// stops after exactly that many with fmi2Discard; its outputs are those of a successful
/// doStep from the same start to fmi2LastSuccessfulTime (an independent run that takes the
/// same internal steps: bit-identical).
#[test]
fn outputs_after_a_discard_equal_those_of_a_run_to_the_last_successful_time() {
    let f = Fmu::new("bounded", false);
    assert_eq!(set_integer(&f, "max_internal_steps", 40), Fmi2Status::OK);
    f.init();
    assert_eq!(f.step(0.0, 0.05), Fmi2Status::Discard);
    let last = last_successful_time(&f);
    assert!(last > 0.0 && last < 0.05, "{last}");
    let after = f.all_real_outputs();
    assert!(after.iter().all(|x| x.is_finite()));

    let g = Fmu::new("reference", false);
    g.init();
    assert_eq!(g.step(0.0, last), Fmi2Status::OK, "{}", g.last_message());
    let reference = g.all_real_outputs();
    assert_eq!(after, reference);
}

/// After a solver failure (T_load = 1e5 N m pushes the centres apart) the outputs are
/// finite and are those at fmi2LastSuccessfulTime: a run from the same state to that time
/// agrees with them to the solver tolerance (phi1 advances with the filtered omega1).
#[test]
fn outputs_after_a_solver_discard_are_finite_and_at_the_last_successful_time() {
    let f = Fmu::new("discard", false);
    f.init();
    assert_eq!(f.step(0.0, 1e-4), Fmi2Status::OK);
    assert_eq!(f.set_real("T_load", 1e5), Fmi2Status::OK);
    assert_eq!(f.step(1e-4, 1e-2), Fmi2Status::Discard);
    let last = last_successful_time(&f);
    let after = f.all_real_outputs();
    assert!(after.iter().all(|x| x.is_finite()));
    let g = Fmu::new("reference", false);
    g.init();
    assert_eq!(g.step(0.0, 1e-4), Fmi2Status::OK);
    assert_eq!(g.set_real("T_load", 1e5), Fmi2Status::OK);
    assert_eq!(g.step(1e-4, last - 1e-4), Fmi2Status::OK);
    let (a, b) = (f.real("phi1"), g.real("phi1"));
    assert!((a - b).abs() < 1e-6 * b.abs(), "{a} vs {b}");
}

// ------------------------------------------------------------------ tunables

/// mu = DBL_MAX after initialisation used to be accepted (27 non-finite outputs with OK).
#[test]
fn mu_dbl_max_after_init_is_an_error_naming_mu() {
    let f = Fmu::new("mu", false);
    f.init();
    assert_eq!(f.step(0.0, 1e-4), Fmi2Status::OK);
    assert_eq!(f.set_real("mu", f64::MAX), Fmi2Status::Error);
    let m = f.last_message();
    assert!(m.contains("mu = 1.7976931348623157e308"), "{m}");
    assert!(m.contains("max"), "{m}");
    // The model was not touched: the outputs are those of before the set, finite.
    assert!(f.all_real_outputs().iter().all(|x| x.is_finite()));
    assert_eq!(f.real("mu"), 0.05);
}

/// Every input and tunable with declared bounds refuses a value just outside them and
/// accepts the bound itself (FMI bounds are inclusive).
#[test]
fn inputs_and_tunables_are_checked_against_their_declared_bounds_when_set() {
    let mut checked = 0;
    for v in VARIABLES.iter().filter(|v| {
        v.ty == VarType::Real
            && (v.causality == Causality::Input
                || v.variability == geared_rotor::fmi2::variables::Variability::Tunable)
    }) {
        let (min, max) = (v.min.expect(v.name), v.max.expect(v.name));
        for (x, ok) in [
            (min, true),
            (max, true),
            (min - min.abs().max(1.0), false),
            (max + max.abs().max(1.0), false),
        ] {
            let f = Fmu::new("bounds", false);
            f.init();
            let s = f.set_real(v.name, x);
            if ok {
                assert_eq!(
                    s,
                    Fmi2Status::OK,
                    "{} = {x:e}: {}",
                    v.name,
                    f.last_message()
                );
            } else {
                assert_eq!(s, Fmi2Status::Error, "{} = {x:e}", v.name);
                let m = f.last_message();
                assert!(m.contains(&format!("{} = ", v.name)), "{m}");
            }
        }
        checked += 1;
    }
    assert_eq!(checked, 4, "omega1, T_load, mu, d_phi");
}

// ------------------------------------------------------------------ messages

/// Numbers in messages are short (at most 17 significant digits, exponent notation for
/// large and small magnitudes): mu = 1e300 printed ~300 digits before.
#[test]
fn numbers_in_messages_are_short() {
    let f = Fmu::new("short", false);
    f.init();
    assert_eq!(f.set_real("mu", 1e300), Fmi2Status::Error);
    let m = f.last_message();
    assert!(m.contains("1e300"), "{m}");
    assert!(m.len() < 200, "{m}");
    // A communication point that does not match the FMU time: short numbers too.
    let g = Fmu::new("short2", false);
    g.init();
    assert_eq!(g.step(1e-300, 1e-310), Fmi2Status::Error);
    let m = g.last_message();
    assert!(m.contains("1e-300") && !m.contains("0.0000000"), "{m}");
    // At most 17 significant digits (runs of digits and points, leading zeros do not
    // count); the fuzzer checks every message of its run the same way.
    for (_, _, m) in f.messages().iter().chain(g.messages().iter()) {
        assert!(
            !m.split(|c: char| !(c.is_ascii_digit() || c == '.'))
                .any(|d| d.replace('.', "").trim_start_matches('0').len() > 17),
            "a number with more than 17 significant digits: {m}"
        );
    }
}

// ------------------------------------------------------------------ state blobs

fn serialize(f: &Fmu) -> Vec<u8> {
    unsafe {
        let mut st: Fmi2FMUstate = ptr::null_mut();
        assert_eq!(fmi2GetFMUstate(f.c, &mut st), Fmi2Status::OK);
        let mut n = 0usize;
        assert_eq!(fmi2SerializedFMUstateSize(f.c, st, &mut n), Fmi2Status::OK);
        let mut buf = vec![0u8; n];
        assert_eq!(
            fmi2SerializeFMUstate(f.c, st, buf.as_mut_ptr().cast(), n),
            Fmi2Status::OK
        );
        assert_eq!(fmi2FreeFMUstate(f.c, &mut st), Fmi2Status::OK);
        buf
    }
}

/// (status, the state handle or NULL).
fn deserialize(f: &Fmu, blob: &[u8]) -> (Fmi2Status, Fmi2FMUstate) {
    let mut st: Fmi2FMUstate = ptr::null_mut();
    let s = unsafe { fmi2DeSerializeFMUstate(f.c, blob.as_ptr().cast(), blob.len(), &mut st) };
    (s, st)
}

fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// Where the RADAU5 snapshot sits inside a blob: (start, length).
fn snapshot_span(blob: &[u8]) -> (usize, usize) {
    let start = blob
        .windows(8)
        .position(|w| w == b"RADAU5SN")
        .expect("blob holds a RADAU5 snapshot");
    (start, Snapshot::<NY>::serialized_len())
}

/// Recomputes both checksums (the snapshot's and the blob's): a blob that is consistent
/// but wrong, as a tool that edits it would write.
fn reseal(blob: &mut [u8]) {
    let (s, n) = snapshot_span(blob);
    let sum = fnv1a(&blob[s..s + n - 8]);
    blob[s + n - 8..s + n].copy_from_slice(&sum.to_le_bytes());
    let m = blob.len();
    let sum = fnv1a(&blob[..m - 8]);
    blob[m - 8..].copy_from_slice(&sum.to_le_bytes());
}

fn put_f64(blob: &mut [u8], at: usize, x: f64) {
    blob[at..at + 8].copy_from_slice(&x.to_bits().to_le_bytes());
}

fn find_f64(blob: &[u8], from: usize, x: f64) -> usize {
    from + blob[from..]
        .windows(8)
        .position(|w| w == x.to_bits().to_le_bytes())
        .unwrap_or_else(|| panic!("{x} not found"))
}

/// Offsets of fields of the RADAU5 snapshot inside the blob, located from the snapshot's
/// own t (the layout after t: y, t_prev, y_prev, f_prev, f0, f0_valid, h_next, h_old, ...).
struct SnapshotFields {
    y: usize,
    h_next: usize,
    h_old: usize,
    nsing: usize,
}

fn fields(blob: &[u8]) -> SnapshotFields {
    let (s, n) = snapshot_span(blob);
    let snap = Snapshot::<NY>::from_bytes(&blob[s..s + n]).unwrap();
    // t and t_prev with the N values of y between them pin the position of t.
    let mut from = s;
    let t_at = loop {
        let at = find_f64(blob, from, snap.t());
        let tp = f64::from_bits(u64::from_le_bytes(
            blob[at + 8 + 8 * NY..at + 16 + 8 * NY].try_into().unwrap(),
        ));
        if tp == snap.t_prev() {
            break at;
        }
        from = at + 1;
    };
    let y = t_at + 8;
    let h_next = y + 8 * NY + 8 + 3 * 8 * NY + 1;
    let h_old = h_next + 8;
    // Counters at the end: ..., action (u8), nsing (u64), naccpt_local, steps_since_stop,
    // 8 statistics, checksum.
    let nsing = s + n - 8 - 8 * 8 - 8 - 8 - 8;
    SnapshotFields {
        y,
        h_next,
        h_old,
        nsing,
    }
}

/// A blob resealed after a change is refused with fmi2Error and a message saying what is
/// wrong; the instance keeps its time and outputs, and a good state still restores.
#[test]
fn resealed_blobs_with_wrong_contents_are_refused_and_leave_the_instance_as_it_was() {
    let f = Fmu::new("blobs", false);
    f.init();
    for k in 0..5 {
        assert_eq!(f.step(f64::from(k) * 1e-3, 1e-3), Fmi2Status::OK);
    }
    let good = serialize(&f);
    let fl = fields(&good);
    let mu_bits = 0.05f64.to_bits().to_le_bytes();
    let mu_positions: Vec<usize> = good
        .windows(8)
        .enumerate()
        .filter(|(_, w)| *w == mu_bits)
        .map(|(i, _)| i)
        .collect();
    assert!(!mu_positions.is_empty());
    let mut cases: Vec<(&str, Vec<u8>, &str)> = Vec::new();
    let mut b = good.clone();
    put_f64(&mut b, fl.y + 8 * 3, f64::NAN);
    cases.push(("NaN in the solver state", b, "finite"));
    let mut b = good.clone();
    put_f64(&mut b, fl.y + 8 * 3, 1e300);
    cases.push(("absurd displacement", b, "constraint"));
    let mut b = good.clone();
    put_f64(&mut b, fl.h_next, -1e-5);
    cases.push(("h_next <= 0", b, "h"));
    let mut b = good.clone();
    put_f64(&mut b, fl.h_old, 0.0);
    cases.push(("h_old = 0", b, "h"));
    let mut b = good.clone();
    b[fl.nsing..fl.nsing + 8].copy_from_slice(&1_000_000u64.to_le_bytes());
    cases.push(("singular counter out of range", b, "nsing"));
    // The phase of the state machine (first field of the payload, after magic, version,
    // GUID and payload length): Fatal, which no FMU state can hold.
    let phase_at = 8 + 4 + 8 + geared_rotor::fmi2::variables::GUID.len() + 8;
    assert_eq!(
        good[phase_at..phase_at + 4],
        2u32.to_le_bytes(),
        "StepComplete"
    );
    let mut b = good.clone();
    b[phase_at..phase_at + 4].copy_from_slice(&6u32.to_le_bytes());
    cases.push(("phase Fatal", b, "Fatal"));
    for &at in &mu_positions {
        let mut b = good.clone();
        put_f64(&mut b, at, 7.5);
        cases.push(("mu = 7.5 (declared max 1)", b, "mu"));
    }
    let (t0, out0) = (last_successful_time(&f), f.all_real_outputs());
    for (what, mut blob, expect) in cases {
        reseal(&mut blob);
        let (s, st) = deserialize(&f, &blob);
        assert_eq!(s, Fmi2Status::Error, "{what} accepted");
        assert!(st.is_null());
        let m = f.last_message();
        assert!(m.contains(expect), "{what}: {m}");
        // The instance is as it was (its outputs can be read in the Error state).
        assert_eq!(last_successful_time(&f), t0, "{what}");
        assert_eq!(f.all_real_outputs(), out0, "{what}");
    }
    // The unmodified blob (resealed: checksums identical) is still accepted and restores.
    let mut same = good.clone();
    reseal(&mut same);
    assert_eq!(same, good);
    let (s, mut st) = deserialize(&f, &good);
    assert_eq!(s, Fmi2Status::OK, "{}", f.last_message());
    unsafe {
        assert_eq!(fmi2SetFMUstate(f.c, st), Fmi2Status::OK);
        assert_eq!(fmi2FreeFMUstate(f.c, &mut st), Fmi2Status::OK);
    }
    assert_eq!(f.step(5e-3, 1e-3), Fmi2Status::OK);
}

/// The declared default of max_internal_steps is the simulation's default.
#[test]
fn the_declared_work_bound_is_the_simulations_default() {
    let v = by_name("max_internal_steps").unwrap();
    assert_eq!(v.ty, VarType::Integer);
    assert_eq!(v.vr, 1020);
    assert_eq!(
        v.start,
        Some(geared_rotor::sim::DEFAULT_MAX_INTERNAL_STEPS as f64)
    );
    assert_eq!(v.min, Some(1.0));
}
