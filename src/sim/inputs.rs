//! The two model inputs and the input function they describe (value, first derivative,
//! reference time): rebasing to a time and deciding whether f changes.

use crate::rotor::Inputs;

/// One of the two model inputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Input {
    /// Reference speed of rotor 1 [rad/s].
    Omega1,
    /// Load torque on gear 2 [N m].
    TLoad,
}

impl Input {
    pub(super) fn name(self) -> &'static str {
        match self {
            Input::Omega1 => "omega1",
            Input::TLoad => "T_load",
        }
    }
    pub(super) fn index(self) -> usize {
        match self {
            Input::Omega1 => 0,
            Input::TLoad => 1,
        }
    }
}

/// Inputs rebased to time t: value(t) = value + der (t - t_ref).
pub(super) fn rebase(i: &Inputs, t: f64) -> Inputs {
    Inputs {
        omega1: i.omega1 + i.omega1_der * (t - i.t_ref),
        omega1_der: i.omega1_der,
        t_load: i.t_load + i.t_load_der * (t - i.t_ref),
        t_load_der: i.t_load_der,
        t_ref: t,
    }
}

/// Whether two input records (rebased to the same time) describe the same input function,
/// up to round-off (1e-12 relative): a master that re-sends u(t_n) and u'(t_n) of a ramp
/// computes the value in its own arithmetic, and a restart for an ulp is wasted work.
pub(super) fn same_function(a: &Inputs, b: &Inputs) -> bool {
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-12 * x.abs().max(y.abs());
    close(a.omega1, b.omega1)
        && close(a.omega1_der, b.omega1_der)
        && close(a.t_load, b.t_load)
        && close(a.t_load_der, b.t_load_der)
}
