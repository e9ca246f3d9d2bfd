//! A seeded fuzzer of the FMU's FMI 3.0 C ABI (in process, through the crate's exported
//! `extern "C"` functions of `c_abi3`), the mirror of `tests/fuzz_fmi2/driver.rs`: random
//! FMI 3.0 call sequences checked against a shadow state machine that knows which calls
//! FMI 3.0 requires to fail (wrong state, bad arguments, wrong integer type, nValues that
//! do not match, NULL out-arguments of fmi3DoStep, functions this FMU does not provide,
//! setting the independent variable), instances with and without earlyReturnAllowed, and
//! mutated serialized states (bit flips, special values, random bytes; with and without
//! recomputed checksums; FMI 2.0 blobs, which the 3.0 FMU must refuse).
//!
//! Checked for every call: no fmi3Fatal (a panic caught at the boundary), no call over
//! [`CALL_LIMIT`] (a hang detector, not a speed measure), no OK or Warning where FMI 3.0
//! requires an error, no non-finite value returned with a status below fmi3Error, and the
//! out-arguments of fmi3DoStep consistent (lastSuccessfulTime inside the step; the end of
//! the step unless it returned early). Used by `tests/fuzz_fmi3.rs` (the CI run) and
//! `examples/fuzz_fmi3.rs` (long runs).
#![allow(dead_code)]

use geared_rotor::c_abi3::*;
use geared_rotor::fmi2::variables::{Causality, VarType, Variability, Variable, GUID, VARIABLES};
use geared_rotor::fmi3::types::*;
use geared_rotor::fmi3::TIME_VR;
use std::ffi::{c_void, CStr, CString};
use std::time::{Duration, Instant};

/// Counts of a run.
#[derive(Debug, Default, Clone)]
pub struct Report {
    pub sequences: u64,
    pub calls: u64,
    /// Returned statuses: OK, Warning, Discard, Error, Fatal, (unused: FMI 3.0 has no Pending).
    pub statuses: [u64; 6],
    /// Calls FMI requires to fail (all of them returned fmi2Error unless a violation is listed).
    pub required_errors: u64,
    /// fmi3DoStep calls that returned early (earlyReturn = true).
    pub early_returns: u64,
    pub blobs: u64,
    pub blobs_unchanged: u64,
    pub blobs_accepted: u64,
    pub blobs_refused: u64,
    pub resealed_accepted: u64,
    pub resealed_refused: u64,
    pub slowest_call: Duration,
    pub slowest_what: String,
    pub violations: Vec<String>,
}

impl Report {
    fn count(&mut self, s: Fmi3Status) {
        self.calls += 1;
        self.statuses[s as usize] += 1;
    }
}

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = &self.statuses;
        writeln!(
            f,
            "sequences {}, calls {}: OK {}, Warning {}, Discard {}, Error {} (of them {} required by FMI), Fatal {}; early returns {}",
            self.sequences, self.calls, s[0], s[1], s[2], s[3], self.required_errors, s[4], self.early_returns
        )?;
        writeln!(
            f,
            "blobs {}: unchanged by the mutation {}, accepted {} (resealed {}), refused {} (resealed {})",
            self.blobs,
            self.blobs_unchanged,
            self.blobs_accepted,
            self.resealed_accepted,
            self.blobs_refused,
            self.resealed_refused
        )?;
        writeln!(
            f,
            "slowest call {:.3} s ({})",
            self.slowest_call.as_secs_f64(),
            self.slowest_what
        )?;
        write!(f, "violations {}", self.violations.len())?;
        for v in self.violations.iter().take(20) {
            write!(f, "\n  {v}")?;
        }
        Ok(())
    }
}

/// Last message per instance (through componentEnvironment), and the first message with
/// a number of more than 17 digits (numbers in messages must be short).
struct LastMessage(String, Option<String>);

extern "C" fn record(env: *mut c_void, _status: Fmi3Status, _cat: Fmi3String, msg: Fmi3String) {
    // SAFETY: env is the Box<LastMessage> of the driver; msg is NUL-terminated.
    let last = unsafe { &mut *(env as *mut LastMessage) };
    last.0 = unsafe { CStr::from_ptr(msg) }
        .to_string_lossy()
        .into_owned();
    if last.1.is_none() && has_long_number(&last.0) {
        last.1 = Some(last.0.clone());
    }
}

fn logger() -> Fmi3LogMessageCallback {
    Some(record)
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    Instantiated,
    Init,
    Step,
    Failed,
    Terminated,
    Error,
}

/// What the shadow knows of an FMU state it holds.
#[derive(Debug, Clone, Copy)]
struct Shadow {
    phase: Phase,
    t: f64,
    stop: Option<f64>,
}

struct Instance {
    c: Fmi3Instance,
    last: Box<LastMessage>,
    /// earlyReturnAllowed
    early: bool,
    sh: Shadow,
    states: Vec<(Fmi3FMUState, Shadow)>,
}

impl Instance {
    fn new(logging: bool, early: bool) -> Instance {
        let mut last = Box::new(LastMessage(String::new(), None));
        let n = CString::new("fuzz").unwrap();
        let g = CString::new(GUID).unwrap();
        // SAFETY: valid strings and a callback environment that outlives the instance.
        let c = unsafe {
            fmi3InstantiateCoSimulation(
                n.as_ptr(),
                g.as_ptr(),
                std::ptr::null(),
                0,
                u8::from(logging),
                0,
                u8::from(early),
                std::ptr::null(),
                0,
                (&mut *last as *mut LastMessage).cast(),
                logger(),
                None,
            )
        };
        assert!(!c.is_null());
        Instance {
            c,
            last,
            early,
            sh: Shadow {
                phase: Phase::Instantiated,
                t: 0.0,
                stop: None,
            },
            states: Vec::new(),
        }
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: states and the instance came from this FMU.
        unsafe {
            for (s, _) in self.states.iter_mut() {
                fmi3FreeFMUState(self.c, s);
            }
            fmi3FreeInstance(self.c);
        }
    }
}

fn allowed(p: Phase, set: &[Phase]) -> bool {
    set.contains(&p)
}

use Phase::*;

#[path = "../fuzz_common/mod.rs"]
mod fuzz_common;
pub use fuzz_common::*;
const SET_PHASES: &[Phase] = &[Instantiated, Init, Step];
const GET_PHASES: &[Phase] = &[Init, Step, Failed, Terminated, Error];
const STATUS_PHASES: &[Phase] = &[Step, Failed, Terminated, Error];

struct Fuzzer<'r> {
    rng: Rng,
    rep: &'r mut Report,
    /// The calls of the current sequence (for the report of a violation).
    history: Vec<String>,
}

impl Fuzzer<'_> {
    /// Times a call, counts its status and checks the universal rules.
    fn call(&mut self, what: &str, must_fail: bool, f: impl FnOnce() -> Fmi3Status) -> Fmi3Status {
        let t0 = Instant::now();
        let s = f();
        let dt = t0.elapsed();
        self.rep.count(s);
        if self.history.len() < 200 {
            self.history.push(format!("{what} -> {s:?}"));
        }
        if dt > self.rep.slowest_call {
            self.rep.slowest_call = dt;
            self.rep.slowest_what = what.to_string();
        }
        if dt > CALL_LIMIT {
            self.violation(format!("{what}: took {:.2} s", dt.as_secs_f64()));
        }
        if s == Fmi3Status::Fatal {
            self.violation(format!("{what}: fmi3Fatal (caught panic)"));
        }
        if must_fail {
            self.rep.required_errors += 1;
            if matches!(s, Fmi3Status::OK | Fmi3Status::Warning) {
                self.violation(format!("{what}: {s:?} where FMI 3.0 requires an error"));
            }
        }
        s
    }

    fn violation(&mut self, v: String) {
        if self.rep.violations.len() < 1000 {
            self.rep.violations.push(v);
        }
    }

    fn finite(&mut self, what: &str, s: Fmi3Status, xs: &[f64]) {
        if matches!(s, Fmi3Status::OK | Fmi3Status::Warning) && !xs.iter().all(|x| x.is_finite()) {
            self.violation(format!("{what}: non-finite value with {s:?}: {xs:?}"));
        }
    }

    /// The shadow's phase after a call that returned `s` (Error -> Error state).
    fn after(inst: &mut Instance, s: Fmi3Status, ok_phase: Option<Phase>) {
        match s {
            Fmi3Status::OK | Fmi3Status::Warning => {
                if let Some(p) = ok_phase {
                    inst.sh.phase = p;
                }
            }
            Fmi3Status::Error => inst.sh.phase = Error,
            _ => {}
        }
    }

    fn random_var(&mut self, ty: VarType) -> (u32, Option<&'static Variable>) {
        if self.rng.chance(0.03) {
            return (900_000 + self.rng.below(1000) as u32, None);
        }
        // Mostly the interesting ones.
        let interesting = [
            "omega1",
            "T_load",
            "mu",
            "d_phi",
            "h_max",
            "rtol",
            "omega1_filter_frequency",
            "max_internal_steps",
            "z1",
        ];
        let v = if self.rng.chance(0.6) {
            let name = *self.rng.pick(&interesting);
            VARIABLES.iter().find(|v| v.name == name)
        } else {
            Some(self.rng.pick(&VARIABLES[..]))
        };
        match v {
            Some(v) if v.ty == ty => (v.vr, Some(v)),
            Some(v) => (v.vr, VARIABLES.iter().find(|w| w.ty == ty && w.vr == v.vr)),
            None => (900_000, None),
        }
    }

    fn set_must_fail(phase: Phase, v: Option<&Variable>, x: f64) -> bool {
        if !allowed(phase, SET_PHASES) {
            return true;
        }
        let Some(v) = v else { return true };
        let settable = match (v.causality, v.variability) {
            (Causality::Input, _) => true,
            (Causality::Parameter, Variability::Tunable) => true,
            (Causality::Parameter, _) => phase != Step,
            _ => false,
        };
        !settable || !x.is_finite() || (bounds_checked_at_set(v) && out_of_declared(v, x))
    }

    /// nValues: mostly 1 (one scalar), sometimes another count, which must fail.
    fn n_values(&mut self) -> usize {
        if self.rng.chance(0.03) {
            *self.rng.pick(&[0, 2, 7])
        } else {
            1
        }
    }

    fn set_real(&mut self, inst: &mut Instance) {
        let (vr, v) = if self.rng.chance(0.02) {
            (TIME_VR, None) // the independent variable: never settable
        } else {
            self.random_var(VarType::Real)
        };
        let x = match v {
            // A coasting load now and then: lift-off, so that steps return early.
            Some(v) if v.name == "T_load" && self.rng.chance(0.3) => -self.rng.log(2.0, 3.5),
            Some(v) => real_value(&mut self.rng, v),
            None => 1.0,
        };
        let nv = self.n_values();
        let must = Self::set_must_fail(inst.sh.phase, v, x) || nv != 1;
        let what = format!(
            "fmi3SetFloat64({}, {x:e}, nValues {nv}) in {:?}",
            v.map_or("?", |v| v.name),
            inst.sh.phase
        );
        let xs = [x; 8];
        // SAFETY: one valid reference and up to 8 values.
        let s = self.call(&what, must, || unsafe {
            fmi3SetFloat64(inst.c, &vr, 1, xs.as_ptr(), nv)
        });
        Self::after(inst, s, None);
    }

    fn set_integer(&mut self, inst: &mut Instance) {
        let (vr, v) = self.random_var(VarType::Integer);
        let work_bound = v.is_some_and(|v| v.name == "max_internal_steps");
        let x: i32 = match self.rng.below(6) {
            0 if work_bound => *self.rng.pick(&[i32::MIN, -1, 0]),
            0 => *self.rng.pick(&[i32::MIN, -1, 0, i32::MAX]),
            _ if work_bound => 1 + self.rng.below(MAX_WORK) as i32,
            1..=3 => 1 + self.rng.below(3000) as i32,
            _ => v.and_then(|v| v.start).unwrap_or(1.0) as i32,
        };
        // Enumerations are Int64 in FMI 3.0; mostly the right function, sometimes the
        // other (must fail).
        let is_enum = v.is_some_and(|v| !v.items.is_empty());
        let as_int64 = if self.rng.chance(0.9) {
            is_enum
        } else {
            !is_enum
        };
        let must = Self::set_must_fail(inst.sh.phase, v, f64::from(x))
            || (v.is_some() && as_int64 != is_enum);
        let what = format!(
            "fmi3SetInt{}({}, {x}) in {:?}",
            if as_int64 { 64 } else { 32 },
            v.map_or("?", |v| v.name),
            inst.sh.phase
        );
        let x64 = i64::from(x);
        // SAFETY: one valid reference and value.
        let s = self.call(&what, must, || unsafe {
            if as_int64 {
                fmi3SetInt64(inst.c, &vr, 1, &x64, 1)
            } else {
                fmi3SetInt32(inst.c, &vr, 1, &x, 1)
            }
        });
        Self::after(inst, s, None);
    }

    fn get_real(&mut self, inst: &mut Instance) {
        let n = 1 + self.rng.below(8);
        let mut vrs = Vec::with_capacity(n);
        let mut must = !allowed(inst.sh.phase, GET_PHASES);
        for _ in 0..n {
            let (vr, v) = if self.rng.chance(0.6) {
                let outs: Vec<&Variable> = VARIABLES
                    .iter()
                    .filter(|v| v.ty == VarType::Real && v.causality == Causality::Output)
                    .collect();
                let v = *self.rng.pick(&outs);
                (v.vr, Some(v))
            } else if self.rng.chance(0.05) {
                (TIME_VR, None) // the independent variable: readable
            } else {
                self.random_var(VarType::Real)
            };
            must |= v.is_none() && vr != TIME_VR;
            vrs.push(vr);
        }
        let mut out = vec![0.0; n];
        let nv = if self.rng.chance(0.03) { n + 1 } else { n };
        must |= nv != n;
        let what = format!("fmi3GetFloat64({vrs:?}) in {:?}", inst.sh.phase);
        // SAFETY: n references and n outputs (nValues n + 1 is refused before any write).
        let s = self.call(&what, must, || unsafe {
            fmi3GetFloat64(inst.c, vrs.as_ptr(), n, out.as_mut_ptr(), nv)
        });
        self.finite(&what, s, &out);
        Self::after(inst, s, None);
    }

    fn do_step(&mut self, inst: &mut Instance) {
        self.do_step_h(inst, None);
    }

    /// fmi3DoStep from the shadow's time over `h`, or over a random step from a random
    /// communication point.
    fn do_step_h(&mut self, inst: &mut Instance, fixed_h: Option<f64>) {
        let t = inst.sh.t;
        let h = match self.rng.below(20) {
            _ if fixed_h.is_some() => fixed_h.unwrap_or(1e-4),
            0 => *self
                .rng
                .pick(&[0.0, -1e-3, f64::NAN, f64::INFINITY, 1e-300, 5e-324]),
            1 => *self.rng.pick(&[1.0, 10.0, 1e6, 1e10, 1e300, f64::MAX]),
            2..=4 => self.rng.log(-12.0, -6.0),
            _ => self.rng.log(-6.0, -2.0),
        };
        let ccp = match self.rng.below(12) {
            _ if fixed_h.is_some() => t,
            0 => t + 1e-3,
            1 => *self.rng.pick(&[f64::NAN, -1.0, 1e300]),
            _ => t,
        };
        let tol = comm_tolerance(t, h);
        let stepping = allowed(inst.sh.phase, &[Step]);
        let past_stop = inst.sh.stop.is_some_and(|s| ccp + h > s + tol);
        let acceptable = stepping
            && h > 0.0
            && h.is_finite()
            && ccp.is_finite()
            && (ccp - t).abs() <= tol
            && !past_stop
            && ccp + h > t;
        // Sometimes a NULL out-argument (must fail).
        let null_out = self.rng.chance(0.02);
        let must = !acceptable || null_out;
        let what = format!(
            "fmi3DoStep({ccp:e}, {h:e}) at t = {t:e} in {:?}{}",
            inst.sh.phase,
            if null_out { " (NULL earlyReturn)" } else { "" }
        );
        let (mut ev, mut term, mut early, mut last) = (7u8, 7u8, 7u8, f64::NAN);
        let early_ptr: *mut Fmi3Boolean = if null_out {
            std::ptr::null_mut()
        } else {
            &mut early
        };
        // SAFETY: valid instance and out-pointers (or NULL).
        let s = self.call(&what, must, || unsafe {
            fmi3DoStep(inst.c, ccp, h, 1, &mut ev, &mut term, early_ptr, &mut last)
        });
        if matches!(
            s,
            Fmi3Status::OK | Fmi3Status::Warning | Fmi3Status::Discard
        ) {
            self.finite(&what, s, &[last]);
            if ev != 0 || term != 0 || early > 1 {
                self.violation(format!(
                    "{what}: eventHandlingNeeded {ev}, terminateSimulation {term}, earlyReturn {early}"
                ));
            }
            if early == 1 && !(inst.early && s == Fmi3Status::Warning) {
                self.violation(format!(
                    "{what}: earlyReturn with {s:?}, earlyReturnAllowed = {}",
                    inst.early
                ));
            }
        }
        match s {
            Fmi3Status::OK | Fmi3Status::Warning if early == 1 => {
                self.rep.early_returns += 1;
                if !(last >= t && last <= ccp + h) {
                    self.violation(format!(
                        "{what}: early return at {last:e}, outside the step"
                    ));
                }
                inst.sh.t = last;
            }
            Fmi3Status::OK | Fmi3Status::Warning => {
                if last != ccp + h {
                    self.violation(format!(
                        "{what}: completed with lastSuccessfulTime {last:e}, not {:e}",
                        ccp + h
                    ));
                }
                inst.sh.t = ccp + h;
            }
            Fmi3Status::Discard => {
                inst.sh.phase = Failed;
                if !(last >= t && last <= ccp + h) {
                    self.violation(format!(
                        "{what}: Discard with last successful time {last:e} outside the step"
                    ));
                }
                inst.sh.t = last;
            }
            _ => {}
        }
        Self::after(inst, s, None);
    }

    /// fmi3EnterInitializationMode with a random experiment.
    fn enter_init(&mut self, inst: &mut Instance) {
        let tol = match self.rng.below(5) {
            0 => Some(*self.rng.pick(&[0.0, -1.0, f64::NAN, 1e-20, 1.0, 1e-6])),
            1 => Some(self.rng.log(-12.0, -2.0)),
            _ => None,
        };
        let start = match self.rng.below(8) {
            0 => *self.rng.pick(&[f64::NAN, 1e300, -1e3, 1.0, 1e6]),
            1 => self.rng.log(-3.0, 3.0),
            _ => 0.0,
        };
        let stop = match self.rng.below(4) {
            0 => Some(start + self.rng.log(-4.0, 0.0)),
            1 => Some(start - 1.0),
            _ => None,
        };
        let must = !allowed(inst.sh.phase, &[Instantiated])
            || tol.is_some_and(|t| !(t > 0.0 && t.is_finite()))
            || !start.is_finite()
            || stop.is_some_and(|s| s.is_nan() || s < start);
        let what = format!("fmi3EnterInitializationMode({tol:?}, {start:e}, {stop:?})");
        // SAFETY: valid instance.
        let s = self.call(&what, must, || unsafe {
            fmi3EnterInitializationMode(
                inst.c,
                u8::from(tol.is_some()),
                tol.unwrap_or(0.0),
                start,
                u8::from(stop.is_some()),
                stop.unwrap_or(0.0),
            )
        });
        if matches!(s, Fmi3Status::OK | Fmi3Status::Warning) {
            inst.sh.t = start;
            inst.sh.stop = stop;
        }
        Self::after(inst, s, Some(Init));
    }

    fn one_call(&mut self, inst: &mut Instance) {
        let p = inst.sh.phase;
        match self.rng.below(24) {
            0 | 1 => self.enter_init(inst),
            2 => {
                let must = !allowed(p, &[Init]);
                // SAFETY: valid instance.
                let s = self.call("fmi3ExitInitializationMode", must, || unsafe {
                    fmi3ExitInitializationMode(inst.c)
                });
                Self::after(inst, s, Some(Step));
            }
            3..=5 => self.set_real(inst),
            6 => self.set_integer(inst),
            7 | 8 => self.get_real(inst),
            9..=12 => self.do_step(inst),
            13 => {
                let must = !allowed(p, &[Step, Failed, Error]);
                // SAFETY: valid instance.
                let s = self.call("fmi3Terminate", must, || unsafe { fmi3Terminate(inst.c) });
                Self::after(inst, s, Some(Terminated));
            }
            14 => {
                if self.rng.chance(0.3) {
                    // SAFETY: valid instance.
                    let s = self.call("fmi3Reset", false, || unsafe { fmi3Reset(inst.c) });
                    Self::after(inst, s, Some(Instantiated));
                    if s == Fmi3Status::OK {
                        inst.sh.t = 0.0;
                        inst.sh.stop = None;
                        self.set_work_bound(inst);
                    }
                }
            }
            15 => {
                let mut st: Fmi3FMUState = std::ptr::null_mut();
                // SAFETY: valid instance and output.
                let s = self.call("fmi3GetFMUState", false, || unsafe {
                    fmi3GetFMUState(inst.c, &mut st)
                });
                if s == Fmi3Status::OK && !st.is_null() {
                    inst.states.push((st, inst.sh));
                }
                Self::after(inst, s, None);
            }
            16 => {
                if !inst.states.is_empty() {
                    let (st, sh) = inst.states[self.rng.below(inst.states.len())];
                    // SAFETY: a state of this instance.
                    let s = self.call("fmi3SetFMUState", false, || unsafe {
                        fmi3SetFMUState(inst.c, st)
                    });
                    if s == Fmi3Status::OK {
                        inst.sh = sh;
                    } else {
                        self.violation(format!("fmi3SetFMUState of an own state: {s:?}"));
                        Self::after(inst, s, None);
                    }
                }
            }
            17 => self.round_trip(inst),
            18 => {
                // A function this FMU does not provide: always an error.
                let which = self.rng.below(4);
                let mut n = 0usize;
                // SAFETY: valid instance and outputs.
                let s = self.call(&format!("unsupported function {which}"), true, || unsafe {
                    match which {
                        0 => fmi3EnterEventMode(inst.c),
                        1 => fmi3EnterStepMode(inst.c),
                        2 => fmi3GetNumberOfContinuousStates(inst.c, &mut n),
                        _ => fmi3SetTime(inst.c, 0.0),
                    }
                });
                Self::after(inst, s, None);
            }
            19 => {
                // Int64 of the Enumerations (and of an Integer: must fail).
                let (vr, v) = self.random_var(VarType::Integer);
                let must = !allowed(p, GET_PHASES) || v.is_none_or(|v| v.items.is_empty());
                let mut x = 0i64;
                let what = format!("fmi3GetInt64({}) in {p:?}", v.map_or("?", |v| v.name));
                // SAFETY: one reference and output.
                let s = self.call(&what, must, || unsafe {
                    fmi3GetInt64(inst.c, &vr, 1, &mut x, 1)
                });
                if s == Fmi3Status::OK {
                    if let Some(v) = v {
                        if !(1..=v.items.len() as i64).contains(&x) {
                            self.violation(format!("{what}: {x} is not an item"));
                        }
                    }
                }
                Self::after(inst, s, None);
            }
            20 => {
                let (vr, v) = self.random_var(VarType::Real);
                let order = if self.rng.chance(0.9) { 1 } else { 2 };
                let mut x = 0.0;
                let must = !allowed(p, STATUS_PHASES)
                    || v.is_none_or(|v| v.causality != Causality::Output)
                    || order != 1;
                // SAFETY: one reference, order and output.
                let s = self.call("fmi3GetOutputDerivatives", must, || unsafe {
                    fmi3GetOutputDerivatives(inst.c, &vr, 1, &order, &mut x, 1)
                });
                self.finite("fmi3GetOutputDerivatives", s, &[x]);
                Self::after(inst, s, None);
            }
            21 => {
                // SAFETY: valid instance.
                let s = self.call("fmi3SetDebugLogging", false, || unsafe {
                    fmi3SetDebugLogging(inst.c, 1, 0, std::ptr::null())
                });
                Self::after(inst, s, None);
            }
            22 => {
                // Int32 of the Integer outputs and parameters.
                let (vr, v) = self.random_var(VarType::Integer);
                let must = !allowed(p, GET_PHASES) || v.is_none_or(|v| !v.items.is_empty());
                let mut x = 0i32;
                // SAFETY: one reference and output.
                let s = self.call("fmi3GetInt32", must, || unsafe {
                    fmi3GetInt32(inst.c, &vr, 1, &mut x, 1)
                });
                Self::after(inst, s, None);
            }
            _ => {
                // A normal initialisation, so that sequences get to stepping often.
                if p == Instantiated {
                    // SAFETY: valid instance.
                    let s = self.call("fmi3EnterInitializationMode", false, || unsafe {
                        fmi3EnterInitializationMode(inst.c, 0, 0.0, inst.sh.t, 0, 0.0)
                    });
                    inst.sh.stop = None;
                    Self::after(inst, s, Some(Init));
                    let s = self.call("fmi3ExitInitializationMode", false, || unsafe {
                        fmi3ExitInitializationMode(inst.c)
                    });
                    Self::after(inst, s, Some(Step));
                } else {
                    if p == Step && self.rng.chance(0.7) {
                        // A coasting load: lift-off, so that steps return early.
                        let vr = VARIABLES
                            .iter()
                            .find(|v| v.name == "T_load")
                            .map_or(0, |v| v.vr);
                        let x = -80.0 - 220.0 * self.rng.f();
                        // SAFETY: one reference and value.
                        let s = self.call("fmi3SetFloat64(T_load, coasting)", false, || unsafe {
                            fmi3SetFloat64(inst.c, &vr, 1, &x, 1)
                        });
                        Self::after(inst, s, None);
                        // Steps of 0.2 ms: the contact force swings and crosses zero
                        // inside some of them.
                        for _ in 0..self.rng.below(8) {
                            self.do_step_h(inst, Some(2e-4));
                        }
                    }
                    self.do_step(inst);
                }
            }
        }
    }

    /// Serialize a state and read it back: a state of this instance must be accepted.
    fn round_trip(&mut self, inst: &mut Instance) {
        if inst.states.is_empty() {
            return;
        }
        let (st, sh) = inst.states[self.rng.below(inst.states.len())];
        let Some(blob) = serialize(self, inst.c, st) else {
            return;
        };
        let mut back: Fmi3FMUState = std::ptr::null_mut();
        // SAFETY: a buffer of blob.len() bytes.
        let s = self.call("fmi3DeserializeFMUState (own)", false, || unsafe {
            fmi3DeserializeFMUState(inst.c, blob.as_ptr(), blob.len(), &mut back)
        });
        if s == Fmi3Status::OK {
            inst.states.push((back, sh));
        } else {
            let m = inst.last.0.clone();
            let calls = self.history.join("\n    ");
            self.violation(format!(
                "own state refused: {m}; the sequence:\n    {calls}"
            ));
            Self::after(inst, s, None);
        }
    }

    /// A work bound of at most [`MAX_WORK`] internal steps per doStep, so that the 2-s hang
    /// detector stays meaningful on a loaded machine (the default bound is tested by
    /// tests/fmi2_robustness.rs).
    fn set_work_bound(&mut self, inst: &mut Instance) {
        let n = 1 + self.rng.below(MAX_WORK) as i32;
        let vr = VARIABLES
            .iter()
            .find(|v| v.name == "max_internal_steps")
            .map_or(0, |v| v.vr);
        // SAFETY: one reference and value.
        let s = self.call("fmi3SetInt32(max_internal_steps)", false, || unsafe {
            fmi3SetInt32(inst.c, &vr, 1, &n, 1)
        });
        Self::after(inst, s, None);
    }

    /// A sequence aimed at early return: an instance with earlyReturnAllowed runs, a
    /// coasting load makes the contact force swing through zero, and random steps (with FMU
    /// states taken, serialized and read back between them) meet the lift-offs.
    fn event_sequence(&mut self) {
        self.history.clear();
        let mut inst = Instance::new(false, true);
        self.set_work_bound(&mut inst);
        // SAFETY: valid instance.
        let s = self.call("fmi3EnterInitializationMode", false, || unsafe {
            fmi3EnterInitializationMode(inst.c, 0, 0.0, 0.0, 0, 0.0)
        });
        Self::after(&mut inst, s, Some(Init));
        let s = self.call("fmi3ExitInitializationMode", false, || unsafe {
            fmi3ExitInitializationMode(inst.c)
        });
        Self::after(&mut inst, s, Some(Step));
        let h0 = self.rng.log(-4.0, -2.5);
        self.do_step_h(&mut inst, Some(h0));
        let vr = VARIABLES
            .iter()
            .find(|v| v.name == "T_load")
            .map_or(0, |v| v.vr);
        let x = -80.0 - 220.0 * self.rng.f();
        // SAFETY: one reference and value.
        let s = self.call("fmi3SetFloat64(T_load, coasting)", false, || unsafe {
            fmi3SetFloat64(inst.c, &vr, 1, &x, 1)
        });
        Self::after(&mut inst, s, None);
        for _ in 0..5 + self.rng.below(20) {
            match self.rng.below(6) {
                0 => self.one_call(&mut inst),
                1 => self.round_trip(&mut inst),
                _ => {
                    let h = self.rng.log(-5.0, -3.0);
                    self.do_step_h(&mut inst, Some(h));
                }
            }
        }
        self.rep.sequences += 1;
    }

    /// One random call sequence on a fresh instance.
    fn sequence(&mut self) {
        self.history.clear();
        let mut inst = Instance::new(self.rng.chance(0.2), self.rng.chance(0.5));
        self.set_work_bound(&mut inst);
        let n = 3 + self.rng.below(30);
        for _ in 0..n {
            self.one_call(&mut inst);
            if let Some(m) = inst.last.1.take() {
                self.violation(format!("a number of more than 17 digits: {m}"));
            }
        }
        self.rep.sequences += 1;
    }
}

fn serialize(fz: &mut Fuzzer<'_>, c: Fmi3Instance, st: Fmi3FMUState) -> Option<Vec<u8>> {
    let mut n = 0usize;
    // SAFETY: a state of this instance.
    let s = fz.call("fmi3SerializedFMUStateSize", false, || unsafe {
        fmi3SerializedFMUStateSize(c, st, &mut n)
    });
    if s != Fmi3Status::OK {
        return None;
    }
    let mut buf = vec![0u8; n];
    // SAFETY: buffer of n bytes.
    let s = fz.call("fmi3SerializeFMUState", false, || unsafe {
        fmi3SerializeFMUState(c, st, buf.as_mut_ptr(), n)
    });
    (s == Fmi3Status::OK).then_some(buf)
}

/// The serialized state of an FMI 2.0 instance after a few steps (the 3.0 FMU refuses it).
fn fmi2_blob() -> Vec<u8> {
    use geared_rotor::c_abi as c2;
    use geared_rotor::fmi2::types::{Fmi2CallbackFunctions, Fmi2FMUstate};
    let cb = Fmi2CallbackFunctions {
        logger: None,
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    };
    let n = CString::new("fmi2").unwrap();
    let g = CString::new(GUID).unwrap();
    // SAFETY: valid strings and callbacks; the instance is freed here.
    unsafe {
        let c = c2::fmi2Instantiate(n.as_ptr(), 1, g.as_ptr(), std::ptr::null(), &cb, 0, 0);
        assert!(!c.is_null());
        c2::fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0);
        c2::fmi2EnterInitializationMode(c);
        c2::fmi2ExitInitializationMode(c);
        c2::fmi2DoStep(c, 0.0, 1e-4, 1);
        let mut st: Fmi2FMUstate = std::ptr::null_mut();
        c2::fmi2GetFMUstate(c, &mut st);
        let mut size = 0usize;
        c2::fmi2SerializedFMUstateSize(c, st, &mut size);
        let mut buf = vec![0u8; size];
        c2::fmi2SerializeFMUstate(c, st, buf.as_mut_ptr().cast(), size);
        c2::fmi2FreeFMUstate(c, &mut st);
        c2::fmi2FreeInstance(c);
        buf
    }
}

/// Mutated state blobs: a source instance runs a random short experiment, its state is
/// serialized, mutated (resealed or not) and read by a second instance that then steps.
fn blobs(fz: &mut Fuzzer<'_>, count: u64, snapshot_len: usize) {
    let mut src = Instance::new(false, false);
    let mut made = 0u64;
    let blob2 = fmi2_blob();
    while made < count {
        // A fresh source state every 50 blobs.
        if made.is_multiple_of(50) {
            src = Instance::new(false, false);
            let mu = 0.1 * fz.rng.f();
            let mvr = VARIABLES.iter().find(|v| v.name == "mu").unwrap().vr;
            let (mut ev, mut term, mut early, mut last) = (0u8, 0u8, 0u8, 0.0);
            // SAFETY: valid instance, one reference, out-pointers.
            unsafe {
                fmi3SetFloat64(src.c, &mvr, 1, &mu, 1);
                fmi3EnterInitializationMode(src.c, 0, 0.0, 0.0, 0, 0.0);
                fmi3ExitInitializationMode(src.c);
                let k = fz.rng.below(20);
                for i in 0..k {
                    fmi3DoStep(
                        src.c,
                        i as f64 * 1e-4,
                        1e-4,
                        1,
                        &mut ev,
                        &mut term,
                        &mut early,
                        &mut last,
                    );
                }
            }
        }
        let mut st: Fmi3FMUState = std::ptr::null_mut();
        // SAFETY: valid instance and output.
        unsafe { fmi3GetFMUState(src.c, &mut st) };
        let good = if fz.rng.chance(0.02) {
            // An FMI 2.0 blob, unchanged or mutated: always refused.
            Some(blob2.clone())
        } else {
            serialize(fz, src.c, st)
        };
        // SAFETY: own state.
        unsafe { fmi3FreeFMUState(src.c, &mut st) };
        let Some(good) = good else {
            made += 1;
            continue;
        };
        let foreign = good == blob2;
        let resealed = fz.rng.chance(0.7);
        let mut blob = good.clone();
        let k = 1 + fz.rng.below(3);
        for _ in 0..k {
            mutate(&mut fz.rng, &mut blob);
        }
        if resealed {
            reseal(&mut blob, snapshot_len);
        }
        made += 1;
        fz.rep.blobs += 1;
        if blob == good && !foreign {
            fz.rep.blobs_unchanged += 1;
            continue;
        }
        let dst = Instance::new(false, fz.rng.chance(0.5));
        let mut back: Fmi3FMUState = std::ptr::null_mut();
        let what = if foreign {
            "fmi3DeserializeFMUState (FMI 2.0 blob)"
        } else {
            "fmi3DeserializeFMUState (mutated)"
        };
        // FUZZ_LAST_BLOB=path: each blob is written there before it is read (to keep the
        // one a hang or crash happened on).
        if let Ok(path) = std::env::var("FUZZ_LAST_BLOB") {
            let _ = std::fs::write(path, &blob);
        }
        // SAFETY: a buffer of blob.len() bytes.
        let s = fz.call(what, !resealed || foreign, || unsafe {
            fmi3DeserializeFMUState(dst.c, blob.as_ptr(), blob.len(), &mut back)
        });
        if s != Fmi3Status::OK {
            fz.rep.blobs_refused += 1;
            fz.rep.resealed_refused += u64::from(resealed);
            continue;
        }
        fz.rep.blobs_accepted += 1;
        fz.rep.resealed_accepted += u64::from(resealed);
        // SAFETY: a state of dst.
        let s = fz.call("fmi3SetFMUState (mutated)", false, || unsafe {
            fmi3SetFMUState(dst.c, back)
        });
        let mut t = f64::NAN;
        // SAFETY: valid instance, the time variable.
        let s2 = fz.call("fmi3GetFloat64(time)", false, || unsafe {
            fmi3GetFloat64(dst.c, &TIME_VR, 1, &mut t, 1)
        });
        let outs: Vec<u32> = VARIABLES
            .iter()
            .filter(|v| v.ty == VarType::Real && v.causality == Causality::Output)
            .map(|v| v.vr)
            .collect();
        let mut y = vec![0.0; outs.len()];
        // SAFETY: outs.len() references and outputs.
        let s3 = fz.call("fmi3GetFloat64 (after a mutated state)", false, || unsafe {
            fmi3GetFloat64(dst.c, outs.as_ptr(), outs.len(), y.as_mut_ptr(), outs.len())
        });
        fz.finite("fmi3GetFloat64 (after a mutated state)", s3, &y);
        if s == Fmi3Status::OK && s2 == Fmi3Status::OK && t.is_finite() {
            let mut tc = t;
            for _ in 0..3 {
                let (mut ev, mut term, mut early, mut last) = (0u8, 0u8, 0u8, f64::NAN);
                // SAFETY: valid instance and out-pointers.
                let s4 = fz.call("fmi3DoStep (after a mutated state)", false, || unsafe {
                    fmi3DoStep(
                        dst.c, tc, 1e-3, 1, &mut ev, &mut term, &mut early, &mut last,
                    )
                });
                if !matches!(s4, Fmi3Status::OK | Fmi3Status::Warning) {
                    break;
                }
                tc = last;
                let s5 = fz.call("fmi3GetFloat64 (after a mutated state)", false, || unsafe {
                    fmi3GetFloat64(dst.c, outs.as_ptr(), outs.len(), y.as_mut_ptr(), outs.len())
                });
                fz.finite("fmi3GetFloat64 (after a mutated state, stepped)", s5, &y);
            }
        }
        // SAFETY: own state.
        unsafe { fmi3FreeFMUState(dst.c, &mut back) };
    }
}

/// Runs `sequences` call sequences and `blob_count` mutated blobs from `seed`.
pub fn run(seed: u64, sequences: u64, blob_count: u64, snapshot_len: usize) -> Report {
    let mut rep = Report::default();
    let mut fz = Fuzzer {
        rng: Rng(seed),
        rep: &mut rep,
        history: Vec::new(),
    };
    for k in 0..sequences {
        // one in 20 aimed at early return
        if k % 20 == 19 {
            fz.event_sequence();
        } else {
            fz.sequence();
        }
    }
    blobs(&mut fz, blob_count, snapshot_len);
    rep
}
