//! The variables <-> physics mapping of the geared rotor: parameters from the value store
//! ([`params`], the Enumerations, the solver settings), outputs from [`Outputs`], the
//! calculated parameters from the pair geometry, the inputs.

use crate::fmi2::model::Experiment;
use crate::fmi2::variables::{self, Var, N_VARIABLES, VARIABLES};
use crate::gear::{PairGeometry, ParamError};
use crate::rotor::{param_table, Outputs, Params};
use crate::sim::{Initialization, Input, OnViolation, SolverSettings};

/// The value store: one f64 per variable, in table order (Integer, Boolean and
/// Enumeration values as f64).
pub type Values = [f64; N_VARIABLES];

/// Fixed parameters whose declared bounds fmi2ExitInitializationMode checks (rtol has a
/// rule of its own, `SolverSettings::validate`, equal to its declared bounds; the other
/// parameters are checked by the model's rules).
pub const CHECKED_AT_INIT: &[&str] = &["omega1_filter_frequency", "h_max"];

/// Every variable at its start value.
pub fn start_values() -> Values {
    let mut v = [0.0; N_VARIABLES];
    for (x, var) in v.iter_mut().zip(VARIABLES.iter()) {
        *x = var.start.unwrap_or(0.0);
    }
    v
}

/// Parameters from the store, through the parameter table (`rotor::param_table`): every
/// parameter of [`Params`] is read from the variable of the same name; the integer and
/// code parameters are checked here (e.g. the friction-law code), the rest by
/// `Params::validate` (names the parameter and the bound).
pub fn params(values: &Values) -> Result<Params, ParamError> {
    let mut p = Params::default();
    for q in param_table::all() {
        // Every table name is a variable of the model description (tests/rotor_parameter_table.rs).
        if let Some(var) = variables::by_name(q.name()) {
            q.set(&mut p, values[var.var as usize])?;
        }
    }
    Ok(p)
}

/// The Enumeration parameter `initialization` (values checked at the set as well).
pub fn initialization(values: &Values) -> Result<Initialization, ParamError> {
    let x = values[Var::initialization as usize];
    Initialization::from_code(x as i32)
        .filter(|_| x.fract() == 0.0)
        .ok_or_else(|| enum_error(Var::initialization, x))
}

/// The Enumeration parameter `on_lift_off`.
pub fn on_violation(values: &Values) -> Result<OnViolation, ParamError> {
    let x = values[Var::on_lift_off as usize];
    OnViolation::from_code(x as i32)
        .filter(|_| x.fract() == 0.0)
        .ok_or_else(|| enum_error(Var::on_lift_off, x))
}

/// The solver settings: rtol from fmi2SetupExperiment if it gave a tolerance, else the
/// parameter; and where rtol came from (for the log).
pub fn settings(values: &Values, exp: &Experiment) -> (SolverSettings, &'static str) {
    match exp.tolerance {
        Some(t) => (
            SolverSettings {
                rtol: t,
                h_max: values[Var::h_max as usize],
            },
            "fmi2SetupExperiment",
        ),
        None => (
            SolverSettings {
                rtol: values[Var::rtol as usize],
                h_max: values[Var::h_max as usize],
            },
            "the parameter rtol",
        ),
    }
}

/// The error for an Enumeration value outside its items, listing them.
fn enum_error(var: Var, x: f64) -> ParamError {
    let v = variables::variable(var);
    let items: Vec<String> = v
        .items
        .iter()
        .enumerate()
        .map(|(k, n)| format!("{} = {n}", k + 1))
        .collect();
    ParamError {
        name: v.name,
        value: x,
        requirement: format!("one of {}", items.join(", ")),
    }
}

/// The simulation input a variable is, if any.
pub fn input_of(var: Var) -> Option<Input> {
    match var {
        Var::omega1 => Some(Input::Omega1),
        Var::T_load => Some(Input::TLoad),
        _ => None,
    }
}

fn vec3(o: &[f64; 3], ax: usize) -> f64 {
    o[ax]
}

/// Value of an output variable in an [`Outputs`] (None if `var` is not an output).
pub fn output_value(o: &Outputs, var: Var) -> Option<f64> {
    use Var::*;
    Some(match var {
        T1 => o.t1,
        omega1_filtered => o.omega1,
        omega2 => o.omega2,
        phi1 => o.phi1,
        phi2 => o.phi2,
        Fn => o.fn_,
        TE => o.te,
        gap => o.gap,
        P_in => o.p_in,
        P_loss => o.p_loss,
        mu_eff => o.mu_eff,
        mu_mz => o.mu_mz,
        P_damp => o.p_damp,
        E_in => o.e_in,
        E_loss => o.e_loss,
        E_damp => o.e_damp,
        E_load => o.e_load,
        E_kin => o.e_kin,
        E_pot => o.e_pot,
        contact_length => o.contact_length,
        pairs_in_contact => f64::from(o.pairs_in_contact),
        contact_lost => f64::from(u8::from(o.contact_lost)),
        u1_x => vec3(&o.u1, 0),
        u1_y => vec3(&o.u1, 1),
        u1_z => vec3(&o.u1, 2),
        u2_x => vec3(&o.u2, 0),
        u2_y => vec3(&o.u2, 1),
        u2_z => vec3(&o.u2, 2),
        v1_x => vec3(&o.v1, 0),
        v1_y => vec3(&o.v1, 1),
        v1_z => vec3(&o.v1, 2),
        v2_x => vec3(&o.v2, 0),
        v2_y => vec3(&o.v2, 1),
        v2_z => vec3(&o.v2, 2),
        F_bearing1_x => vec3(&o.f_bearing1, 0),
        F_bearing1_y => vec3(&o.f_bearing1, 1),
        F_bearing1_z => vec3(&o.f_bearing1, 2),
        F_bearing2_x => vec3(&o.f_bearing2, 0),
        F_bearing2_y => vec3(&o.f_bearing2, 1),
        F_bearing2_z => vec3(&o.f_bearing2, 2),
        F_friction1_x => vec3(&o.f_friction1, 0),
        F_friction1_y => vec3(&o.f_friction1, 1),
        F_friction1_z => vec3(&o.f_friction1, 2),
        F_friction2_x => vec3(&o.f_friction2, 0),
        F_friction2_y => vec3(&o.f_friction2, 1),
        F_friction2_z => vec3(&o.f_friction2, 2),
        M_friction1_x => vec3(&o.m_friction1, 0),
        M_friction1_y => vec3(&o.m_friction1, 1),
        M_friction1_z => vec3(&o.m_friction1, 2),
        M_friction2_x => vec3(&o.m_friction2, 0),
        M_friction2_y => vec3(&o.m_friction2, 1),
        M_friction2_z => vec3(&o.m_friction2, 2),
        F_contact1_x => vec3(&o.f_contact1, 0),
        F_contact1_y => vec3(&o.f_contact1, 1),
        F_contact1_z => vec3(&o.f_contact1, 2),
        F_contact2_x => vec3(&o.f_contact2, 0),
        F_contact2_y => vec3(&o.f_contact2, 1),
        F_contact2_z => vec3(&o.f_contact2, 2),
        M_contact1_x => vec3(&o.m_contact1, 0),
        M_contact1_y => vec3(&o.m_contact1, 1),
        M_contact1_z => vec3(&o.m_contact1, 2),
        M_contact2_x => vec3(&o.m_contact2, 0),
        M_contact2_y => vec3(&o.m_contact2, 1),
        M_contact2_z => vec3(&o.m_contact2, 2),
        _ => return None,
    })
}

/// Value of a calculated parameter from the pair geometry (model.md §2, §9.7).
pub fn calculated_value(g: &PairGeometry, var: Var) -> Option<f64> {
    Some(match var {
        Var::r_b1 => g.rb1,
        Var::r_b2 => g.rb2,
        Var::a_w => g.a_w,
        Var::alpha_wt => g.alpha_wt,
        Var::beta_b => g.beta_b,
        Var::p_bt => g.p_bt,
        Var::eps_alpha => g.eps_alpha,
        Var::eps_beta => g.eps_beta,
        Var::H_V => g.h_v,
        _ => return None,
    })
}
