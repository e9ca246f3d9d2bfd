//! The simulation's FMU state: a complete plain-data snapshot ([`SimState`]), restoring it
//! in place or rebuilding from it, and its byte layout (parameters, inputs, solver
//! snapshot) inside the versioned container of [`crate::bytes`].

use super::error::{solver_err, SimError};
use super::init::{InitReport, Initialization};
use super::settings::SolverSettings;
use super::validate::DEFAULT_MAX_INTERNAL_STEPS;
use super::validity::Monitor;
use super::{realtime, Simulation};
use crate::bytes::{DecodeError, Reader, Writer};
use crate::fmt_num::Short;
use crate::parameter::Kind;
use crate::radau5::{Radau5, Snapshot};
use crate::rotor::{param_table, GearedRotor, Inputs, Params, RotorProblem, ToothContact, NY};
use nalgebra::SVector;

/// The model state at initialisation; replayed when a serialized state is loaded, so that
/// whatever `GearedRotor::initialize` sets internally (e.g. the gap offset g0) is rebuilt
/// bit-identically without reaching into the model.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct InitRecord {
    pub(super) params: Params,
    pub(super) inputs: Inputs,
    pub(super) t_start: f64,
    /// The consistent initial state (recomputed by the replay for `Rest`, serialized for
    /// the others, whose computation is not repeated).
    pub(super) y0: SVector<f64, NY>,
    /// How y0 was set.
    pub(super) initialization: Initialization,
}

/// A complete, plain-data snapshot of a [`Simulation`].
#[derive(Clone)]
pub struct SimState {
    pub(super) solver: Snapshot<NY>,
    pub(super) t_comm: f64,
    pub(super) model: GearedRotor,
    pub(super) settings: SolverSettings,
    pub(super) init: InitRecord,
    pub(super) inputs: Inputs,
    pub(super) inputs_ref: Inputs,
    pub(super) der_set: [bool; 2],
    pub(super) restart_pending: bool,
    pub(super) contact_lost: bool,
    pub(super) last_successful_time: f64,
    pub(super) validity: Monitor,
    /// Real-time mode (`realtime`): the fixed internal step bound, 0 = adaptive.
    pub(super) h_fixed: f64,
    /// Contact onsets so far (`contact_events`).
    pub(super) impacts: u64,
}

impl Simulation {
    /// A complete snapshot (plain data; restoring it continues bit-identically).
    pub fn state(&self) -> SimState {
        SimState {
            solver: self.solver.snapshot(),
            t_comm: self.t_comm,
            model: self.problem.model.clone(),
            settings: self.settings,
            init: self.init,
            inputs: *self.problem.model.inputs(),
            inputs_ref: self.inputs_ref,
            der_set: self.der_set,
            restart_pending: self.restart_pending,
            contact_lost: self.contact_lost,
            last_successful_time: self.last_successful_time,
            validity: self.validity,
            h_fixed: self.h_fixed,
            impacts: self.impacts,
        }
    }

    /// Restores a snapshot in place when it belongs to the same parameter set and settings,
    /// else rebuilds the simulation from it.
    ///
    /// # Errors
    /// Rebuilding failed (cannot happen for a state this build produced).
    pub fn restore(&mut self, s: &SimState) -> Result<(), SimError> {
        if s.settings == self.settings && s.init == self.init {
            self.problem.model = s.model.clone();
            self.solver.restore(&s.solver);
            self.set_comm(s.t_comm);
            self.der_set = s.der_set;
            self.inputs_ref = s.inputs_ref;
            self.restart_pending = s.restart_pending;
            self.contact_lost = s.contact_lost;
            self.last_successful_time = s.last_successful_time;
            self.validity = s.validity;
            self.h_fixed = s.h_fixed;
            self.impacts = s.impacts;
            self.event_values.set(None);
        } else {
            *self = Simulation::from_state(s)?;
        }
        Ok(())
    }

    /// Builds a simulation from a snapshot.
    ///
    /// # Errors
    /// Invalid settings or a stepper that cannot be constructed.
    pub fn from_state(s: &SimState) -> Result<Self, SimError> {
        s.settings.validate()?;
        let mut problem = RotorProblem {
            model: s.model.clone(),
        };
        let mut solver = Radau5::new(
            &mut problem,
            s.settings
                .options_for(s.model.scales(), s.model.params().tooth_contact),
            s.init.t_start,
            s.init.y0,
        )
        .map_err(|e| solver_err(e, s.init.t_start))?;
        solver.restore(&s.solver);
        let mut sim = Simulation {
            problem,
            solver,
            t_comm: s.t_comm,
            y_comm: SVector::zeros(),
            settings: s.settings,
            init: s.init,
            der_set: s.der_set,
            inputs_ref: s.inputs_ref,
            restart_pending: s.restart_pending,
            contact_lost: s.contact_lost,
            last_successful_time: s.last_successful_time,
            validity: s.validity,
            init_report: InitReport::default(),
            max_internal_steps: DEFAULT_MAX_INTERNAL_STEPS,
            h_fixed: s.h_fixed,
            impacts: s.impacts,
            event_values: std::cell::Cell::new(None),
        };
        sim.set_comm(s.t_comm);
        Ok(sim)
    }
}

/// The parameters in the order of `rotor::param_table::all`: integers as i32, reals as
/// f64.
pub(super) fn write_params(w: &mut Writer, p: &Params) {
    for q in param_table::all() {
        match q.kind() {
            Kind::Integer => w.i32(q.get(p) as i32),
            Kind::Real => w.f64(q.get(p)),
        }
    }
    // The contact model (not in the table: the binding's Enumeration `tooth_contact`).
    w.i32(p.tooth_contact.code());
}

/// Reads what [`write_params`] wrote (reals must be finite, codes known).
pub(super) fn read_params(r: &mut Reader) -> Result<Params, DecodeError> {
    let mut p = Params::default();
    for q in param_table::all() {
        let x = match q.kind() {
            Kind::Integer => f64::from(r.i32(q.name())?),
            Kind::Real => r.finite(q.name())?,
        };
        q.set(&mut p, x).map_err(|e| DecodeError {
            message: e.to_string(),
        })?;
    }
    let code = r.i32("tooth_contact")?;
    p.tooth_contact = ToothContact::from_code(code).ok_or_else(|| DecodeError {
        message: format!("tooth_contact = {code}: not 1 (rigid) or 2 (elastic)"),
    })?;
    Ok(p)
}

pub(super) fn write_inputs(w: &mut Writer, i: &Inputs) {
    for x in [i.omega1, i.omega1_der, i.t_load, i.t_load_der, i.t_ref] {
        w.f64(x);
    }
}

pub(super) fn read_inputs(r: &mut Reader) -> Result<Inputs, DecodeError> {
    Ok(Inputs {
        omega1: r.finite("omega1")?,
        omega1_der: r.finite("omega1 derivative")?,
        t_load: r.finite("T_load")?,
        t_load_der: r.finite("T_load derivative")?,
        t_ref: r.finite("input reference time")?,
    })
}

impl SimState {
    /// Time of this snapshot.
    pub fn last_successful_time(&self) -> f64 {
        self.last_successful_time
    }

    /// Appends the payload (not sealed; the FMU layer adds magic, version, GUID, checksum).
    pub fn write(&self, w: &mut Writer) {
        write_params(w, &self.init.params);
        write_inputs(w, &self.init.inputs);
        w.f64(self.init.t_start);
        w.f64(self.settings.rtol);
        w.f64(self.settings.h_max);
        let p = self.model.params();
        w.f64(p.mu);
        w.f64(p.d_phi);
        write_inputs(w, &self.inputs);
        write_inputs(w, &self.inputs_ref);
        w.bool(self.der_set[0]);
        w.bool(self.der_set[1]);
        w.bool(self.restart_pending);
        w.bool(self.contact_lost);
        w.f64(self.last_successful_time);
        w.f64(self.t_comm);
        w.f64(self.h_fixed);
        w.bytes(&self.solver.to_bytes());
        w.i32(self.init.initialization.code());
        if self.init.initialization != Initialization::Rest {
            for x in self.init.y0.iter() {
                w.f64(*x);
            }
        }
        w.u32(self.validity.bits());
        w.f64(self.validity.t_checked);
        // The contact-line stick mode of f (model.md §4.1), since layout version 5.
        w.bool(self.model.stick());
        w.f64(self.model.released());
        // Contact onsets of the elastic flanks, since layout version 7.
        w.u64(self.impacts);
        // The flank whose line sticks or was released (coast: elastic teeth), since 9.
        w.bool(self.model.stick_flank_is_coast());
        // The creep mode of laws 1 and 3 near standstill (model.md §4.2), since 11.
        w.bool(self.model.creeps());
    }

    /// Reads what [`SimState::write`] wrote; the model is rebuilt by replaying its
    /// initialisation, then the tunables and inputs of the snapshot are applied.
    ///
    /// # Errors
    /// Truncated or inconsistent data, or parameters the model rejects.
    pub fn read(r: &mut Reader) -> Result<SimState, SimError> {
        let params = read_params(r)?;
        let inputs0 = read_inputs(r)?;
        let t_start = r.finite("start time")?;
        let settings = SolverSettings {
            rtol: r.finite("rtol")?,
            h_max: r.finite("h_max")?,
        };
        settings.validate()?;
        let mu = r.finite("mu")?;
        let d_phi = r.finite("d_phi")?;
        let inputs = read_inputs(r)?;
        let inputs_ref = read_inputs(r)?;
        let der_set = [r.bool("derivative flag")?, r.bool("derivative flag")?];
        let restart_pending = r.bool("restart flag")?;
        let contact_lost = r.bool("contact flag")?;
        let last_successful_time = r.finite("last successful time")?;
        let t_comm = r.finite("FMU time")?;
        let h_fixed = r.finite("h_fixed")?;
        realtime::check_h_fixed(h_fixed)?;
        let solver =
            Snapshot::<NY>::from_bytes(r.bytes("solver snapshot")?).map_err(|e| DecodeError {
                message: format!("RADAU5 snapshot: {e:?}"),
            })?;
        // The FMU time lies on the stepper's last step (look-ahead) or at its end.
        if !(t_comm <= solver.t() && (t_comm > solver.t_prev() || t_comm == solver.t())) {
            return Err(DecodeError {
                message: format!(
                    "FMU time {} outside the solver's last step ending at {}",
                    Short(t_comm),
                    Short(solver.t())
                ),
            }
            .into());
        }
        let initialization =
            Initialization::from_code(r.i32("initialization")?).ok_or_else(|| DecodeError {
                message: "unknown initialization".into(),
            })?;
        let mut init = InitRecord {
            params,
            inputs: inputs0,
            t_start,
            y0: SVector::zeros(),
            initialization,
        };
        let (mut problem, mut y0) = Simulation::replay(&init)?;
        if initialization != Initialization::Rest {
            for x in y0.iter_mut() {
                *x = r.finite("initial state")?;
            }
        } else {
            // As at the start (`stick::start_mode`), so that the record equals the live
            // one; the mode it sets is replaced by the state's own below.
            y0 = super::creep::start_creep(&mut problem.model, t_start, y0)?;
            y0 = super::stick::start_mode(&mut problem.model, t_start, y0)?;
        }
        init.y0 = y0;
        let bits = r.u32("validity flags")?;
        if bits >= 1 << 7 {
            return Err(DecodeError {
                message: format!("validity flags {bits:#x} use undefined bits"),
            }
            .into());
        }
        let validity = Monitor::from_bits(bits, r.finite("validity check time")?);
        let stick = r.bool("stick flag")?;
        let released = r.finite("release sense")?;
        if !(released == 0.0 || released.abs() == 1.0) || (stick && released != 0.0) {
            return Err(DecodeError {
                message: format!("stick mode {stick} with release sense {released}"),
            }
            .into());
        }
        problem.model.set_mu(mu)?;
        problem.model.set_d_phi(d_phi)?;
        problem.model.set_inputs(inputs);
        // (After the tunables: mu decides whether a line can stick.)
        if (stick || released != 0.0) && !problem.model.stick_possible() {
            return Err(DecodeError {
                message: "a stuck or released contact line for a pair or law where none can \
                          stick"
                    .into(),
            }
            .into());
        }
        let impacts = r.u64("impact count")?;
        let coast = r.bool("stick flank")?;
        if coast && !problem.model.has_coast_flanks() {
            return Err(DecodeError {
                message: "a stick on the coast flanks for a model without coast flanks".into(),
            }
            .into());
        }
        let creep = r.bool("creep flag")?;
        if creep && (!problem.model.creep_possible() || stick || released != 0.0) {
            return Err(DecodeError {
                message: format!(
                    "creep mode with friction law {} or with a stuck or released line",
                    problem.model.params().friction_law.code()
                ),
            }
            .into());
        }
        problem.model.set_creep(creep);
        problem.model.set_stick_flank(coast);
        problem.model.set_stick(stick, released);
        Ok(SimState {
            solver,
            t_comm,
            model: problem.model,
            settings,
            init,
            inputs,
            inputs_ref,
            der_set,
            restart_pending,
            contact_lost,
            last_successful_time,
            validity,
            h_fixed,
            impacts,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bytes::{Reader, Writer};
    use crate::sim::SolverSettings;

    /// A rigid spur pair from rest starts with a contact line on the pitch line, released in
    /// its sliding sense (`stick::start_mode`, which changes the start's lambda): the replay
    /// of a serialized state rebuilds the same start record, so that the state is restored
    /// in place (a different record made `restore` rebuild the simulation and drop what is
    /// not serialized, e.g. `max_internal_steps`).
    #[test]
    fn a_spur_start_on_the_pitch_line_replays_its_start_record() {
        let mut p = Params::default();
        p.gear.beta = 0.0;
        let settings = SolverSettings {
            rtol: 1e-6,
            h_max: 1e-4,
        };
        let sim =
            Simulation::with_initialization(p, settings, 0.0, 314.159, 0.0, Initialization::Rest)
                .unwrap();
        assert!(
            sim.problem.model.released() != 0.0,
            "no start on the pitch line"
        );
        let mut w = Writer::default();
        sim.state().write(&mut w);
        let read = SimState::read(&mut Reader::new(&w.buf)).unwrap();
        assert_eq!(read.init, sim.init);
    }
}
