//! A seeded fuzzer of the FMU's C ABI (in process, through the crate's exported
//! `extern "C"` functions): random FMI 2.0 call sequences checked against a shadow state
//! machine that knows which calls FMI 2.0 requires to fail, and mutated serialized states
//! (bit flips, special values, random bytes; with and without recomputed checksums).
//!
//! Checked for every call: no fmi2Fatal (a panic caught at the boundary), no call over
//! [`CALL_LIMIT`] (a hang detector, not a speed measure), no OK or Warning where FMI 2.0
//! requires an error, and no non-finite value returned with a status below fmi2Error.
//! Used by `tests/fuzz_fmi2.rs` (the CI run) and `examples/fuzz_fmi2.rs` (long runs).
#![allow(dead_code)]

use geared_rotor::c_abi::*;
use geared_rotor::fmi2::types::*;
use geared_rotor::fmi2::variables::{Causality, VarType, Variability, Variable, GUID, VARIABLES};
use std::ffi::{c_void, CStr, CString};
use std::time::{Duration, Instant};

/// Counts of a run.
#[derive(Debug, Default, Clone)]
pub struct Report {
    pub sequences: u64,
    pub calls: u64,
    /// Returned statuses: OK, Warning, Discard, Error, Fatal, Pending.
    pub statuses: [u64; 6],
    /// Calls FMI requires to fail (all of them returned fmi2Error unless a violation is listed).
    pub required_errors: u64,
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
    fn count(&mut self, s: Fmi2Status) {
        self.calls += 1;
        self.statuses[s as usize] += 1;
    }
}

impl std::fmt::Display for Report {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let s = &self.statuses;
        writeln!(
            f,
            "sequences {}, calls {}: OK {}, Warning {}, Discard {}, Error {} (of them {} required by FMI), Fatal {}, Pending {}",
            self.sequences, self.calls, s[0], s[1], s[2], s[3], self.required_errors, s[4], s[5]
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

extern "C" fn record(
    env: *mut c_void,
    _name: Fmi2String,
    _status: Fmi2Status,
    _cat: Fmi2String,
    msg: Fmi2String,
) {
    // SAFETY: env is the Box<LastMessage> of the driver; msg is NUL-terminated.
    let last = unsafe { &mut *(env as *mut LastMessage) };
    last.0 = unsafe { CStr::from_ptr(msg) }
        .to_string_lossy()
        .into_owned();
    if last.1.is_none() && has_long_number(&last.0) {
        last.1 = Some(last.0.clone());
    }
}

fn logger() -> Fmi2CallbackLogger {
    // SAFETY: same fixed arguments; the FMU never passes varargs (see tests/common/fmi2.rs).
    Some(unsafe {
        std::mem::transmute::<
            extern "C" fn(*mut c_void, Fmi2String, Fmi2Status, Fmi2String, Fmi2String),
            unsafe extern "C" fn(*mut c_void, Fmi2String, Fmi2Status, Fmi2String, Fmi2String, ...),
        >(record)
    })
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
    c: Fmi2Component,
    last: Box<LastMessage>,
    _cb: Box<Fmi2CallbackFunctions>,
    sh: Shadow,
    states: Vec<(Fmi2FMUstate, Shadow)>,
}

impl Instance {
    fn new(logging: bool) -> Instance {
        let mut last = Box::new(LastMessage(String::new(), None));
        let cb = Box::new(Fmi2CallbackFunctions {
            logger: logger(),
            allocate_memory: None,
            free_memory: None,
            step_finished: None,
            component_environment: (&mut *last as *mut LastMessage).cast(),
        });
        let n = CString::new("fuzz").unwrap();
        let g = CString::new(GUID).unwrap();
        // SAFETY: valid strings and callbacks that outlive the instance.
        let c = unsafe {
            fmi2Instantiate(
                n.as_ptr(),
                1,
                g.as_ptr(),
                std::ptr::null(),
                &*cb,
                0,
                i32::from(logging),
            )
        };
        assert!(!c.is_null());
        Instance {
            c,
            last,
            _cb: cb,
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
                fmi2FreeFMUstate(self.c, s);
            }
            fmi2FreeInstance(self.c);
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
}

impl Fuzzer<'_> {
    /// Times a call, counts its status and checks the universal rules.
    fn call(&mut self, what: &str, must_fail: bool, f: impl FnOnce() -> Fmi2Status) -> Fmi2Status {
        let t0 = Instant::now();
        let s = f();
        let dt = t0.elapsed();
        self.rep.count(s);
        if dt > self.rep.slowest_call {
            self.rep.slowest_call = dt;
            self.rep.slowest_what = what.to_string();
        }
        if dt > CALL_LIMIT {
            self.violation(format!("{what}: took {:.2} s", dt.as_secs_f64()));
        }
        if s == Fmi2Status::Fatal {
            self.violation(format!("{what}: fmi2Fatal (caught panic)"));
        }
        if must_fail {
            self.rep.required_errors += 1;
            if matches!(s, Fmi2Status::OK | Fmi2Status::Warning) {
                self.violation(format!("{what}: {s:?} where FMI 2.0 requires an error"));
            }
        }
        s
    }

    fn violation(&mut self, v: String) {
        if self.rep.violations.len() < 1000 {
            self.rep.violations.push(v);
        }
    }

    fn finite(&mut self, what: &str, s: Fmi2Status, xs: &[f64]) {
        if matches!(s, Fmi2Status::OK | Fmi2Status::Warning) && !xs.iter().all(|x| x.is_finite()) {
            self.violation(format!("{what}: non-finite value with {s:?}: {xs:?}"));
        }
    }

    /// The shadow's phase after a call that returned `s` (Error -> Error state).
    fn after(inst: &mut Instance, s: Fmi2Status, ok_phase: Option<Phase>) {
        match s {
            Fmi2Status::OK | Fmi2Status::Warning => {
                if let Some(p) = ok_phase {
                    inst.sh.phase = p;
                }
            }
            Fmi2Status::Error => inst.sh.phase = Error,
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
            None => (0, None),
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

    fn set_real(&mut self, inst: &mut Instance) {
        let (vr, v) = self.random_var(VarType::Real);
        let x = match v {
            Some(v) => real_value(&mut self.rng, v),
            None => 1.0,
        };
        let must = Self::set_must_fail(inst.sh.phase, v, x);
        let what = format!(
            "fmi2SetReal({}, {x:e}) in {:?}",
            v.map_or("?", |v| v.name),
            inst.sh.phase
        );
        // SAFETY: one valid reference and value.
        let s = self.call(&what, must, || unsafe { fmi2SetReal(inst.c, &vr, 1, &x) });
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
        let must = Self::set_must_fail(inst.sh.phase, v, f64::from(x));
        let what = format!(
            "fmi2SetInteger({}, {x}) in {:?}",
            v.map_or("?", |v| v.name),
            inst.sh.phase
        );
        // SAFETY: one valid reference and value.
        let s = self.call(&what, must, || unsafe {
            fmi2SetInteger(inst.c, &vr, 1, &x)
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
            } else {
                self.random_var(VarType::Real)
            };
            must |= v.is_none();
            vrs.push(vr);
        }
        let mut out = vec![0.0; n];
        let what = format!("fmi2GetReal({vrs:?}) in {:?}", inst.sh.phase);
        // SAFETY: n references and n outputs.
        let s = self.call(&what, must, || unsafe {
            fmi2GetReal(inst.c, vrs.as_ptr(), n, out.as_mut_ptr())
        });
        self.finite(&what, s, &out);
        Self::after(inst, s, None);
    }

    fn do_step(&mut self, inst: &mut Instance) {
        let t = inst.sh.t;
        let h = match self.rng.below(20) {
            0 => *self
                .rng
                .pick(&[0.0, -1e-3, f64::NAN, f64::INFINITY, 1e-300, 5e-324]),
            1 => *self.rng.pick(&[1.0, 10.0, 1e6, 1e10, 1e300, f64::MAX]),
            2..=4 => self.rng.log(-12.0, -6.0),
            _ => self.rng.log(-6.0, -2.0),
        };
        let ccp = match self.rng.below(12) {
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
        let must = !acceptable;
        let what = format!(
            "fmi2DoStep({ccp:e}, {h:e}) at t = {t:e} in {:?}",
            inst.sh.phase
        );
        // SAFETY: valid instance.
        let s = self.call(&what, must, || unsafe { fmi2DoStep(inst.c, ccp, h, 1) });
        match s {
            Fmi2Status::OK | Fmi2Status::Warning => inst.sh.t = ccp + h,
            Fmi2Status::Discard => {
                inst.sh.phase = Failed;
                let mut last = f64::NAN;
                // SAFETY: valid instance and output.
                let s2 = self.call(
                    "fmi2GetRealStatus(last successful time)",
                    false,
                    || unsafe {
                        fmi2GetRealStatus(inst.c, status_kind::LAST_SUCCESSFUL_TIME, &mut last)
                    },
                );
                self.finite("fmi2GetRealStatus", s2, &[last]);
                if s2 == Fmi2Status::OK && !(last >= t && last <= ccp + h) {
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

    fn setup(&mut self, inst: &mut Instance) {
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
        let what = format!("fmi2SetupExperiment({tol:?}, {start:e}, {stop:?})");
        // SAFETY: valid instance.
        let s = self.call(&what, must, || unsafe {
            fmi2SetupExperiment(
                inst.c,
                i32::from(tol.is_some()),
                tol.unwrap_or(0.0),
                start,
                i32::from(stop.is_some()),
                stop.unwrap_or(0.0),
            )
        });
        if matches!(s, Fmi2Status::OK | Fmi2Status::Warning) {
            inst.sh.t = start;
            inst.sh.stop = stop;
        }
        Self::after(inst, s, None);
    }

    fn one_call(&mut self, inst: &mut Instance) {
        let p = inst.sh.phase;
        match self.rng.below(24) {
            0 => self.setup(inst),
            1 => {
                let must = !allowed(p, &[Instantiated]);
                // SAFETY: valid instance.
                let s = self.call("fmi2EnterInitializationMode", must, || unsafe {
                    fmi2EnterInitializationMode(inst.c)
                });
                Self::after(inst, s, Some(Init));
            }
            2 => {
                let must = !allowed(p, &[Init]);
                // SAFETY: valid instance.
                let s = self.call("fmi2ExitInitializationMode", must, || unsafe {
                    fmi2ExitInitializationMode(inst.c)
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
                let s = self.call("fmi2Terminate", must, || unsafe { fmi2Terminate(inst.c) });
                Self::after(inst, s, Some(Terminated));
            }
            14 => {
                if self.rng.chance(0.3) {
                    // SAFETY: valid instance.
                    let s = self.call("fmi2Reset", false, || unsafe { fmi2Reset(inst.c) });
                    Self::after(inst, s, Some(Instantiated));
                    if s == Fmi2Status::OK {
                        inst.sh.t = 0.0;
                        inst.sh.stop = None;
                        self.set_work_bound(inst);
                    }
                }
            }
            15 => {
                let mut st: Fmi2FMUstate = std::ptr::null_mut();
                // SAFETY: valid instance and output.
                let s = self.call("fmi2GetFMUstate", false, || unsafe {
                    fmi2GetFMUstate(inst.c, &mut st)
                });
                if s == Fmi2Status::OK && !st.is_null() {
                    inst.states.push((st, inst.sh));
                }
                Self::after(inst, s, None);
            }
            16 => {
                if !inst.states.is_empty() {
                    let (st, sh) = inst.states[self.rng.below(inst.states.len())];
                    // SAFETY: a state of this instance.
                    let s = self.call("fmi2SetFMUstate", false, || unsafe {
                        fmi2SetFMUstate(inst.c, st)
                    });
                    if s == Fmi2Status::OK {
                        inst.sh = sh;
                    } else {
                        self.violation(format!("fmi2SetFMUstate of an own state: {s:?}"));
                        Self::after(inst, s, None);
                    }
                }
            }
            17 => self.round_trip(inst),
            18 => {
                let kind = self.rng.below(5) as i32;
                let mut x = f64::NAN;
                let must = !allowed(p, STATUS_PHASES);
                // SAFETY: valid instance and output.
                let s = self.call(&format!("fmi2GetRealStatus({kind})"), must, || unsafe {
                    fmi2GetRealStatus(inst.c, kind, &mut x)
                });
                self.finite("fmi2GetRealStatus", s, &[x]);
                Self::after(inst, s, None);
            }
            19 => {
                let (vr, v) = self.random_var(VarType::Real);
                let order = if self.rng.chance(0.9) { 1 } else { 2 };
                let x = if self.rng.chance(0.9) {
                    self.rng.log(-3.0, 6.0) * if self.rng.chance(0.5) { -1.0 } else { 1.0 }
                } else {
                    f64::NAN
                };
                let must = !allowed(p, SET_PHASES)
                    || v.is_none_or(|v| v.causality != Causality::Input)
                    || order != 1
                    || !x.is_finite();
                // SAFETY: one reference, order and value.
                let s = self.call("fmi2SetRealInputDerivatives", must, || unsafe {
                    fmi2SetRealInputDerivatives(inst.c, &vr, 1, &order, &x)
                });
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
                let s = self.call("fmi2GetRealOutputDerivatives", must, || unsafe {
                    fmi2GetRealOutputDerivatives(inst.c, &vr, 1, &order, &mut x)
                });
                self.finite("fmi2GetRealOutputDerivatives", s, &[x]);
                Self::after(inst, s, None);
            }
            21 => {
                // SAFETY: valid instance.
                let s = self.call("fmi2SetDebugLogging", false, || unsafe {
                    fmi2SetDebugLogging(inst.c, 1, 0, std::ptr::null())
                });
                Self::after(inst, s, None);
            }
            22 => {
                let mut st = Fmi2Status::OK;
                // SAFETY: valid instance and output.
                let s = self.call("fmi2GetStatus", false, || unsafe {
                    fmi2GetStatus(inst.c, 0, &mut st)
                });
                Self::after(inst, s, None);
            }
            _ => {
                // A normal initialisation, so that sequences get to stepping often.
                if p == Instantiated {
                    // SAFETY: valid instance.
                    let s = self.call("fmi2EnterInitializationMode", false, || unsafe {
                        fmi2EnterInitializationMode(inst.c)
                    });
                    Self::after(inst, s, Some(Init));
                    let s = self.call("fmi2ExitInitializationMode", false, || unsafe {
                        fmi2ExitInitializationMode(inst.c)
                    });
                    Self::after(inst, s, Some(Step));
                } else {
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
        let mut back: Fmi2FMUstate = std::ptr::null_mut();
        // SAFETY: a buffer of blob.len() bytes.
        let s = self.call("fmi2DeSerializeFMUstate (own)", false, || unsafe {
            fmi2DeSerializeFMUstate(inst.c, blob.as_ptr().cast(), blob.len(), &mut back)
        });
        if s == Fmi2Status::OK {
            inst.states.push((back, sh));
        } else {
            let m = inst.last.0.clone();
            self.violation(format!("own state refused: {m}"));
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
        let s = self.call("fmi2SetInteger(max_internal_steps)", false, || unsafe {
            fmi2SetInteger(inst.c, &vr, 1, &n)
        });
        Self::after(inst, s, None);
    }

    /// One random call sequence on a fresh instance.
    fn sequence(&mut self) {
        let mut inst = Instance::new(self.rng.chance(0.2));
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

fn serialize(fz: &mut Fuzzer<'_>, c: Fmi2Component, st: Fmi2FMUstate) -> Option<Vec<u8>> {
    let mut n = 0usize;
    // SAFETY: a state of this instance.
    let s = fz.call("fmi2SerializedFMUstateSize", false, || unsafe {
        fmi2SerializedFMUstateSize(c, st, &mut n)
    });
    if s != Fmi2Status::OK {
        return None;
    }
    let mut buf = vec![0u8; n];
    // SAFETY: buffer of n bytes.
    let s = fz.call("fmi2SerializeFMUstate", false, || unsafe {
        fmi2SerializeFMUstate(c, st, buf.as_mut_ptr().cast(), n)
    });
    (s == Fmi2Status::OK).then_some(buf)
}

/// Mutated state blobs: a source instance runs a random short experiment, its state is
/// serialized, mutated (resealed or not) and read by a second instance that then steps.
fn blobs(fz: &mut Fuzzer<'_>, count: u64, snapshot_len: usize) {
    let mut src = Instance::new(false);
    let mut made = 0u64;
    while made < count {
        // A fresh source state every 50 blobs.
        if made.is_multiple_of(50) {
            src = Instance::new(false);
            let mu = 0.1 * fz.rng.f();
            let mvr = VARIABLES.iter().find(|v| v.name == "mu").unwrap().vr;
            // SAFETY: valid instance, one reference.
            unsafe {
                fmi2SetReal(src.c, &mvr, 1, &mu);
                fmi2SetupExperiment(src.c, 0, 0.0, 0.0, 0, 0.0);
                fmi2EnterInitializationMode(src.c);
                fmi2ExitInitializationMode(src.c);
                let k = fz.rng.below(20);
                for i in 0..k {
                    fmi2DoStep(src.c, i as f64 * 1e-4, 1e-4, 1);
                }
            }
        }
        let mut st: Fmi2FMUstate = std::ptr::null_mut();
        // SAFETY: valid instance and output.
        unsafe { fmi2GetFMUstate(src.c, &mut st) };
        let Some(good) = serialize(fz, src.c, st) else {
            made += 1;
            continue;
        };
        // SAFETY: own state.
        unsafe { fmi2FreeFMUstate(src.c, &mut st) };
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
        if blob == good {
            fz.rep.blobs_unchanged += 1;
            continue;
        }
        let dst = Instance::new(false);
        let mut back: Fmi2FMUstate = std::ptr::null_mut();
        // SAFETY: a buffer of blob.len() bytes.
        let s = fz.call("fmi2DeSerializeFMUstate (mutated)", !resealed, || unsafe {
            fmi2DeSerializeFMUstate(dst.c, blob.as_ptr().cast(), blob.len(), &mut back)
        });
        if s != Fmi2Status::OK {
            fz.rep.blobs_refused += 1;
            fz.rep.resealed_refused += u64::from(resealed);
            continue;
        }
        fz.rep.blobs_accepted += 1;
        fz.rep.resealed_accepted += u64::from(resealed);
        // SAFETY: a state of dst.
        let s = fz.call("fmi2SetFMUstate (mutated)", false, || unsafe {
            fmi2SetFMUstate(dst.c, back)
        });
        let mut t = f64::NAN;
        // SAFETY: valid instance.
        let s2 = fz.call("fmi2GetRealStatus", false, || unsafe {
            fmi2GetRealStatus(dst.c, status_kind::LAST_SUCCESSFUL_TIME, &mut t)
        });
        let outs: Vec<u32> = VARIABLES
            .iter()
            .filter(|v| v.ty == VarType::Real && v.causality == Causality::Output)
            .map(|v| v.vr)
            .collect();
        let mut y = vec![0.0; outs.len()];
        // SAFETY: outs.len() references and outputs.
        let s3 = fz.call("fmi2GetReal (after a mutated state)", false, || unsafe {
            fmi2GetReal(dst.c, outs.as_ptr(), outs.len(), y.as_mut_ptr())
        });
        fz.finite("fmi2GetReal (after a mutated state)", s3, &y);
        if s == Fmi2Status::OK && s2 == Fmi2Status::OK && t.is_finite() {
            for i in 0..3 {
                let tc = t + i as f64 * 1e-3;
                // SAFETY: valid instance.
                let s4 = fz.call("fmi2DoStep (after a mutated state)", false, || unsafe {
                    fmi2DoStep(dst.c, tc, 1e-3, 1)
                });
                if s4 != Fmi2Status::OK {
                    break;
                }
                let s5 = fz.call("fmi2GetReal (after a mutated state)", false, || unsafe {
                    fmi2GetReal(dst.c, outs.as_ptr(), outs.len(), y.as_mut_ptr())
                });
                fz.finite("fmi2GetReal (after a mutated state, stepped)", s5, &y);
            }
        }
        // SAFETY: own state.
        unsafe { fmi2FreeFMUstate(dst.c, &mut back) };
    }
}

/// Runs `sequences` call sequences and `blob_count` mutated blobs from `seed`.
pub fn run(seed: u64, sequences: u64, blob_count: u64, snapshot_len: usize) -> Report {
    let mut rep = Report::default();
    let mut fz = Fuzzer {
        rng: Rng(seed),
        rep: &mut rep,
    };
    for _ in 0..sequences {
        fz.sequence();
    }
    blobs(&mut fz, blob_count, snapshot_len);
    rep
}
