//! The FMI layer is model-agnostic: `fmi2::instance::Instance<M>` runs a toy model (a
//! first-order lag, nothing of gears) through the contract `fmi2::model::Model`, with the
//! FMU's variable table. Checked: the state machine and the argument checks happen in the
//! layer (the model never sees an illegal call, an unknown reference, a NaN or a value
//! outside the declared bounds), the model's error decides Discard vs Error only in
//! fmi2DoStep, FMU states go through the layer's envelope and come back bit-identical.

use geared_rotor::bytes::{Reader, Writer};
use geared_rotor::fmi2::error::{FmuError, ModelError};
use geared_rotor::fmi2::instance::Instance;
use geared_rotor::fmi2::logging::Logger;
use geared_rotor::fmi2::model::{Experiment, Model, Phase, Status};
use geared_rotor::fmi2::types::Fmi2Status;
use geared_rotor::fmi2::variables::{by_name, Causality, VarType, Variable};
use geared_rotor::fmi3::FMI3;
use std::fmt;

/// x' = (u - x) / tau with u = the input omega1, tau = the parameter mu (a stand-in with
/// declared bounds [0, 1]); output T1 = x. A step with u > 1000 "fails" as a discard.
#[derive(Default)]
struct Lag {
    u: f64,
    tau: f64,
    x: f64,
    t: Option<f64>,
    calls_seen: u32,
}

#[derive(Debug)]
enum LagError {
    TooFast(f64),
    NotInitialised,
}

impl fmt::Display for LagError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LagError::TooFast(u) => write!(f, "input {u} too fast for the lag"),
            LagError::NotInitialised => write!(f, "not initialised"),
        }
    }
}

impl ModelError for LagError {
    fn is_discard(&self) -> bool {
        matches!(self, LagError::TooFast(_))
    }
}

impl Model for Lag {
    type Error = LagError;
    type State = (f64, f64, f64, Option<f64>);
    const TOLERANCE_RANGE: (f64, f64) = (1e-10, 1e-2);
    const TOLERANCE_NAME: &'static str = "the lag's tolerance";

    fn instantiate() -> Self {
        Lag {
            tau: 0.5,
            ..Lag::default()
        }
    }
    fn invalidate(&mut self) {}
    fn exit_initialization(
        &mut self,
        _: &'static str,
        exp: &Experiment,
        _: &Logger,
    ) -> Result<(), LagError> {
        self.t = Some(exp.start);
        Ok(())
    }
    fn terminate(&self, _: &Logger) {}
    fn get(&mut self, var: &'static Variable, _: Phase, _: &Experiment) -> Result<f64, LagError> {
        self.calls_seen += 1;
        Ok(match var.name {
            "omega1" => self.u,
            "mu" => self.tau,
            "T1" => self.x,
            _ if var.causality == Causality::Output => f64::NAN,
            _ => 0.0,
        })
    }
    fn set(&mut self, var: &'static Variable, x: f64, _: bool) -> Result<(), LagError> {
        self.calls_seen += 1;
        assert!(x.is_finite(), "the layer passed a non-finite value");
        match var.name {
            "omega1" => self.u = x,
            "mu" => self.tau = x,
            _ => {}
        }
        Ok(())
    }
    fn set_input_derivative(
        &mut self,
        _: &'static Variable,
        _: f64,
        _: bool,
    ) -> Result<(), LagError> {
        Ok(())
    }
    fn output_derivatives(&mut self, _: &[u32], out: &mut [f64]) -> Result<(), LagError> {
        out.fill((self.u - self.x) / self.tau);
        Ok(())
    }
    fn do_step(&mut self, _: &'static str, t: f64, h: f64, _: &Logger) -> Result<Status, LagError> {
        if self.u > 1000.0 {
            return Err(LagError::TooFast(self.u));
        }
        let t0 = self.t.ok_or(LagError::NotInitialised)?;
        assert!((t - t0).abs() < 1e-12);
        // exact solution over h
        self.x = self.u + (self.x - self.u) * (-h / self.tau).exp();
        self.t = Some(t + h);
        Ok(Status::OK)
    }
    fn step_tolerance(_: f64, h: f64) -> f64 {
        1e-9 * h
    }
    fn time(&self) -> Option<f64> {
        self.t
    }
    fn last_successful_time(&self) -> Option<f64> {
        self.t
    }
    fn snapshot(&self) -> Self::State {
        (self.u, self.tau, self.x, self.t)
    }
    fn restore(&mut self, s: &Self::State) -> Result<(), LagError> {
        (self.u, self.tau, self.x, self.t) = *s;
        Ok(())
    }
    fn write_state(s: &Self::State, w: &mut Writer) {
        for x in [s.0, s.1, s.2, s.3.unwrap_or(f64::NAN)] {
            w.f64(x);
        }
    }
    fn read_state(r: &mut Reader<'_>) -> Result<Self::State, LagError> {
        let mut v = [0.0; 4];
        for x in &mut v {
            *x = r.f64("lag").map_err(|_| LagError::NotInitialised)?;
        }
        Ok((v[0], v[1], v[2], (!v[3].is_nan()).then_some(v[3])))
    }
    fn validate_state(s: &Self::State, _: Phase, _: &Experiment) -> Result<(), String> {
        if s.1 > 0.0 {
            Ok(())
        } else {
            Err("tau must be > 0".into())
        }
    }
}

fn vr(name: &str) -> u32 {
    by_name(name).unwrap().vr
}

fn get1(inst: &mut Instance<Lag>, name: &str) -> f64 {
    let mut x = f64::NAN;
    inst.get("fmi2GetReal", VarType::Real, &[vr(name)], &mut |_, v| x = v)
        .unwrap();
    x
}

#[test]
fn generic_layer_runs_a_toy_model() {
    let mut inst: Instance<Lag> = Instance::new("lag", None, std::ptr::null_mut(), false);
    // State machine: doStep before initialisation is the layer's error; the model is not asked.
    let e = inst.do_step(0.0, 0.1).unwrap_err();
    assert!(
        matches!(
            e,
            FmuError::IllegalCall {
                phase: Phase::Instantiated,
                ..
            }
        ),
        "{e}"
    );
    assert_eq!(e.status(), Status::Error);
    inst.setup_experiment(Some(1e-6), 0.0, Some(1.0)).unwrap();
    inst.enter_initialization_mode().unwrap();
    // Argument checks in the layer: unknown vr, NaN, declared bounds of mu ([0, 1]), an output.
    let seen = inst.model().calls_seen;
    let set = |inst: &mut Instance<Lag>, name: &str, x: f64| {
        inst.set("fmi2SetReal", VarType::Real, &[vr(name)], &|_| x)
    };
    assert!(matches!(
        inst.set("fmi2SetReal", VarType::Real, &[999_999], &|_| 1.0),
        Err(FmuError::UnknownValueReference { vr: 999_999, .. })
    ));
    assert!(matches!(
        set(&mut inst, "omega1", f64::NAN),
        Err(FmuError::NonFinite { .. })
    ));
    assert!(matches!(
        set(&mut inst, "mu", 1.5),
        Err(FmuError::OutOfBounds { .. })
    ));
    assert!(matches!(
        set(&mut inst, "T1", 1.0),
        Err(FmuError::NotSettable { .. })
    ));
    assert_eq!(
        inst.model().calls_seen,
        seen,
        "the model saw a refused call"
    );
    set(&mut inst, "omega1", 2.0).unwrap();
    set(&mut inst, "mu", 0.25).unwrap();
    inst.exit_initialization_mode().unwrap();
    // Steps: the exact lag response.
    for k in 0..4 {
        inst.do_step(0.1 * f64::from(k), 0.1).unwrap();
    }
    let x = get1(&mut inst, "T1");
    let exact = 2.0 * (1.0 - (-0.4f64 / 0.25).exp());
    assert!((x - exact).abs() < 1e-12, "{x} vs {exact}");
    // A non-finite output never leaves with a status below Error.
    let e = inst
        .get("fmi2GetReal", VarType::Real, &[vr("Fn")], &mut |_, _| {})
        .unwrap_err();
    assert!(matches!(e, FmuError::OutputNotFinite { .. }), "{e}");
    // FMU state through the layer's envelope: bit-identical after a round trip.
    let s = inst.get_state().unwrap();
    let blob = Instance::<Lag>::serialize_state(&s);
    inst.do_step(0.4, 0.1).unwrap();
    let back = Instance::<Lag>::deserialize_state(&blob).unwrap();
    inst.set_state(&back).unwrap();
    assert_eq!(get1(&mut inst, "T1").to_bits(), x.to_bits());
    assert_eq!(inst.last_successful_time(), 0.4);
    // The FMI 3.0 blob of the same state: read back by the FMI 3.0 side, refused by the
    // FMI 2.0 side with a message naming the version, and the other way round.
    let blob3 = Instance::<Lag>::serialize_state_as(&s, &FMI3);
    assert_ne!(blob3, blob);
    Instance::<Lag>::deserialize_state_as(&blob3, &FMI3).unwrap();
    let e = Instance::<Lag>::deserialize_state(&blob3)
        .err()
        .expect("FMI 3.0 blob refused by FMI 2.0")
        .to_string();
    assert!(e.contains("state of the FMI 3.0 FMU"), "{e}");
    let e = Instance::<Lag>::deserialize_state_as(&blob, &FMI3)
        .err()
        .expect("FMI 2.0 blob refused by FMI 3.0")
        .to_string();
    assert!(
        e.starts_with("fmi3DeserializeFMUState") && e.contains("state of the FMI 2.0 FMU"),
        "{e}"
    );
    // The model's error: a discard in fmi2DoStep.
    set(&mut inst, "omega1", 5000.0).unwrap();
    let e = inst.do_step(0.4, 0.1).unwrap_err();
    assert_eq!(e.status(), Status::Discard, "{e}");
    assert_eq!(inst.fail(&e), Fmi2Status::Discard);
    assert_eq!(inst.phase(), Phase::StepFailed);
    // Past stopTime: the layer's error.
    let mut inst2: Instance<Lag> = Instance::new("lag2", None, std::ptr::null_mut(), false);
    inst2.setup_experiment(None, 0.0, Some(0.15)).unwrap();
    inst2.enter_initialization_mode().unwrap();
    inst2.exit_initialization_mode().unwrap();
    inst2.do_step(0.0, 0.1).unwrap();
    let e = inst2.do_step(0.1, 0.1).unwrap_err();
    assert!(e.to_string().contains("stopTime"), "{e}");
    // A tolerance outside the model's range is clamped with a warning.
    let mut inst3: Instance<Lag> = Instance::new("lag3", None, std::ptr::null_mut(), false);
    assert_eq!(
        inst3.setup_experiment(Some(0.5), 0.0, None).unwrap(),
        Status::Warning
    );
}
