//! The variables <-> physics mapping of the geared rotor: parameters from the value store
//! ([`params`], the Enumerations, the solver settings), outputs from [`Outputs`], the
//! calculated parameters from the pair geometry, the inputs.

use crate::fmi2::model::Experiment;
use crate::fmi2::variables::{self, Var, N_VARIABLES, VARIABLES};
use crate::gear::friction::iso_mean;
use crate::gear::{stiffness, PairGeometry};
use crate::parameter::ParamError;
use crate::rotor::params::SolidBodies;
use crate::rotor::{param_table, GearedRotor, Outputs, Params, ToothContact};
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
/// `Params::validate` (names the parameter and the bound). A mass or inertia of 0 becomes
/// the solid steel gear body of the geometry (`Params::with_solid_bodies`).
pub fn params(values: &Values) -> Result<Params, ParamError> {
    let mut p = Params::default();
    for q in param_table::all() {
        // Every table name is a variable of the model description (checked by
        // tests/rotor_parameter_table.rs); a build whose description lost one says so here
        // instead of running with the default.
        let var = variables::by_name(q.name()).ok_or_else(|| ParamError {
            name: q.name(),
            value: q.default_value(),
            requirement: "a variable of the model description (the FMU was built without it)"
                .into(),
        })?;
        q.set(&mut p, values[var.var as usize])?;
    }
    p.tooth_contact = tooth_contact(values)?;
    Ok(p.with_solid_bodies())
}

/// The warnings of the start (logged by fmi2ExitInitializationMode): gear bodies whose
/// given masses or inertias are implausible for the geometry (`Params::implausible_bodies`),
/// friction law 3 outside its fitted range at the start inputs, and a pair outside the
/// derivation of the standard's loss factor H_V_iso.
pub fn init_warnings(model: &GearedRotor, t: f64) -> Vec<String> {
    let g = model.geometry();
    let mut out = model.params().implausible_bodies(g);
    if let Some(w) = iso_mean::ohlendorf_outside(g.eps_1, g.eps_2) {
        out.push(w);
    }
    let outside = model.law3_outside_fitted_range(t);
    if !outside.is_empty() {
        out.push(format!(
            "friction_law = 3 (ISO/TR 14179-2, Schlenk) at the start inputs: {}; the \
             formula was fitted for v_t >= {} m/s and F_bt/b >= {} N/mm (docs/friction.md, \
             law 3) and extrapolates here",
            outside.join(", "),
            iso_mean::FITTED_V_T_MIN,
            iso_mean::FITTED_LOAD_MIN
        ));
    }
    out
}

/// The Enumeration parameter `initialization` (values checked at the set as well).
pub fn initialization(values: &Values) -> Result<Initialization, ParamError> {
    let x = values[Var::initialization as usize];
    Initialization::from_code(x as i32)
        .filter(|_| x.fract() == 0.0)
        .ok_or_else(|| enum_error(Var::initialization, x))
}

/// The Enumeration parameter `tooth_contact` (docs/model.md §3.5).
pub fn tooth_contact(values: &Values) -> Result<ToothContact, ParamError> {
    let x = values[Var::tooth_contact as usize];
    ToothContact::from_code(x as i32)
        .filter(|_| x.fract() == 0.0)
        .ok_or_else(|| enum_error(Var::tooth_contact, x))
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

/// Writes the value of every output variable at `o` into `v` (table positions; other
/// entries untouched). Straight-line stores: one match per output and value reference
/// cost ~5 ns each in indirect-branch misses (perf, closed loop at H = 1e-5 s).
pub fn output_values(o: &Outputs, v: &mut Values) {
    v[Var::T_damp as usize] = o.t_damp;
    v[Var::P_damp_phi as usize] = o.p_damp_phi;
    v[Var::T1 as usize] = o.t1;
    v[Var::omega1_filtered as usize] = o.omega1;
    v[Var::omega2 as usize] = o.omega2;
    v[Var::phi1 as usize] = o.phi1;
    v[Var::phi2 as usize] = o.phi2;
    v[Var::Fn as usize] = o.fn_;
    v[Var::TE as usize] = o.te;
    v[Var::gap as usize] = o.gap;
    v[Var::P_in as usize] = o.p_in;
    v[Var::P_loss as usize] = o.p_loss;
    v[Var::mu_eff as usize] = o.mu_eff;
    v[Var::mu_mz as usize] = o.mu_mz;
    v[Var::P_damp as usize] = o.p_damp;
    v[Var::E_in as usize] = o.e_in;
    v[Var::E_loss as usize] = o.e_loss;
    v[Var::E_damp as usize] = o.e_damp;
    v[Var::E_mesh_damp as usize] = o.e_mesh_damp;
    v[Var::E_load as usize] = o.e_load;
    v[Var::E_kin as usize] = o.e_kin;
    v[Var::E_pot as usize] = o.e_pot;
    v[Var::contact_length as usize] = o.contact_length;
    v[Var::pairs_in_contact as usize] = f64::from(o.pairs_in_contact);
    v[Var::contact_lost as usize] = f64::from(u8::from(o.contact_lost));
    v[Var::stick as usize] = f64::from(u8::from(o.stick));
    v[Var::mesh_deflection as usize] = o.mesh_deflection;
    v[Var::mesh_stiffness as usize] = o.mesh_stiffness;
    v[Var::mesh_state as usize] = f64::from(o.mesh_state);
    v[Var::Fn_coast as usize] = o.fn_coast;
    // A count; f64 holds it exactly below 2^53, and the Integer getter clamps to i32.
    v[Var::impacts as usize] = o.impacts as f64;
    v[Var::W_mesh_stiffness as usize] = o.w_mesh_stiffness;
    v[Var::u1_x as usize] = o.u1[0];
    v[Var::u1_y as usize] = o.u1[1];
    v[Var::u1_z as usize] = o.u1[2];
    v[Var::u2_x as usize] = o.u2[0];
    v[Var::u2_y as usize] = o.u2[1];
    v[Var::u2_z as usize] = o.u2[2];
    v[Var::v1_x as usize] = o.v1[0];
    v[Var::v1_y as usize] = o.v1[1];
    v[Var::v1_z as usize] = o.v1[2];
    v[Var::v2_x as usize] = o.v2[0];
    v[Var::v2_y as usize] = o.v2[1];
    v[Var::v2_z as usize] = o.v2[2];
    v[Var::F_bearing1_x as usize] = o.f_bearing1[0];
    v[Var::F_bearing1_y as usize] = o.f_bearing1[1];
    v[Var::F_bearing1_z as usize] = o.f_bearing1[2];
    v[Var::F_bearing2_x as usize] = o.f_bearing2[0];
    v[Var::F_bearing2_y as usize] = o.f_bearing2[1];
    v[Var::F_bearing2_z as usize] = o.f_bearing2[2];
    v[Var::F_friction1_x as usize] = o.f_friction1[0];
    v[Var::F_friction1_y as usize] = o.f_friction1[1];
    v[Var::F_friction1_z as usize] = o.f_friction1[2];
    v[Var::F_friction2_x as usize] = o.f_friction2[0];
    v[Var::F_friction2_y as usize] = o.f_friction2[1];
    v[Var::F_friction2_z as usize] = o.f_friction2[2];
    v[Var::M_friction1_x as usize] = o.m_friction1[0];
    v[Var::M_friction1_y as usize] = o.m_friction1[1];
    v[Var::M_friction1_z as usize] = o.m_friction1[2];
    v[Var::M_friction2_x as usize] = o.m_friction2[0];
    v[Var::M_friction2_y as usize] = o.m_friction2[1];
    v[Var::M_friction2_z as usize] = o.m_friction2[2];
    v[Var::F_contact1_x as usize] = o.f_contact1[0];
    v[Var::F_contact1_y as usize] = o.f_contact1[1];
    v[Var::F_contact1_z as usize] = o.f_contact1[2];
    v[Var::F_contact2_x as usize] = o.f_contact2[0];
    v[Var::F_contact2_y as usize] = o.f_contact2[1];
    v[Var::F_contact2_z as usize] = o.f_contact2[2];
    v[Var::M_contact1_x as usize] = o.m_contact1[0];
    v[Var::M_contact1_y as usize] = o.m_contact1[1];
    v[Var::M_contact1_z as usize] = o.m_contact1[2];
    v[Var::M_contact2_x as usize] = o.m_contact2[0];
    v[Var::M_contact2_y as usize] = o.m_contact2[1];
    v[Var::M_contact2_z as usize] = o.m_contact2[2];
}

/// Value of a calculated parameter from the pair geometry (model.md §2, §2.1, §5, §9.7).
pub fn calculated_value(g: &PairGeometry, var: Var) -> Option<f64> {
    let solid = || SolidBodies::of(g);
    Some(match var {
        Var::H_V_iso => iso_mean::ohlendorf_h_v(
            f64::from(g.data.z1),
            f64::from(g.data.z2),
            g.cos_beta_b,
            g.eps_1,
            g.eps_2,
        ),
        Var::m1_solid => solid().m[0],
        Var::J1_solid => solid().j[0],
        Var::m2_solid => solid().m[1],
        Var::J2_solid => solid().j[1],
        Var::r_b1 => g.rb1,
        Var::r_b2 => g.rb2,
        Var::a_w => g.a_w,
        Var::alpha_wt => g.alpha_wt,
        Var::beta_b => g.beta_b,
        Var::p_bt => g.p_bt,
        Var::eps_alpha => g.eps_alpha,
        Var::eps_beta => g.eps_beta,
        Var::H_V => g.h_v,
        Var::c_gamma_used => stiffness::c_gamma_used(g),
        _ => return None,
    })
}
