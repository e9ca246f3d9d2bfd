//! The declared bounds (min, max of the model description): those of the inputs and the
//! tunable parameters are checked when a value is set (by the FMI layer); the model checks
//! others where it needs them (the binding: parameters without a rule of their own in
//! fmi2ExitInitializationMode, all of them when a stored state is read); a value outside
//! them never reaches the model (docs/fmu.md "Robustness"). FMI 2.0 bounds are inclusive.

use super::variables::{Causality, Variability, Variable};
use crate::fmt_num::Short;

/// Whether `var`'s declared bounds are checked when it is set (inputs and tunables: a new
/// value reaches the running model at once).
pub fn checked_when_set(var: &Variable) -> bool {
    var.causality == Causality::Input
        || (var.causality == Causality::Parameter && var.variability == Variability::Tunable)
}

/// A value outside the declared bounds of its variable.
#[derive(Debug, Clone, PartialEq)]
pub struct OutOfBounds {
    /// Variable name.
    pub name: &'static str,
    /// The value.
    pub value: f64,
    /// Declared min (None: unbounded below).
    pub min: Option<f64>,
    /// Declared max.
    pub max: Option<f64>,
}

impl std::fmt::Display for OutOfBounds {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let side = match self.min {
            Some(m) if self.value < m => format!("below its declared min {}", Short(m)),
            _ => format!(
                "above its declared max {}",
                Short(self.max.unwrap_or(f64::INFINITY))
            ),
        };
        let range = format!(
            "[{}, {}]",
            self.min.map_or("-inf".into(), |m| Short(m).to_string()),
            self.max.map_or("inf".into(), |m| Short(m).to_string())
        );
        write!(
            f,
            "{} = {} is {side}; use a value in {range}",
            self.name,
            Short(self.value)
        )
    }
}

/// Checks `x` against the declared min and max of `var`.
///
/// # Errors
/// [`OutOfBounds`] naming the variable and the bound.
pub fn check(var: &Variable, x: f64) -> Result<(), OutOfBounds> {
    let below = var.min.is_some_and(|m| x < m);
    let above = var.max.is_some_and(|m| x > m);
    if below || above || x.is_nan() {
        return Err(OutOfBounds {
            name: var.name,
            value: x,
            min: var.min,
            max: var.max,
        });
    }
    Ok(())
}
