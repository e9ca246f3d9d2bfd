//! How a model parameter is described (once: name, unit, default, declared bounds, the
//! model's rule, the field it sets) and the error a violated rule gives. The geared rotor's
//! table of all its parameters is `crate::rotor::param_table`; the FMI model description
//! declares the same facts for the interface, and a test checks that both agree.

use crate::fmt_num::Short;
use std::fmt;

/// A parameter (or a parameter combination) that violates a rule of the model.
///
/// `name` is the parameter held responsible (for derived conditions the one whose
/// change most directly repairs the set), `requirement` states the bound and, for
/// derived conditions, the derived quantity that violates it.
#[derive(Debug, Clone, PartialEq)]
pub struct ParamError {
    /// Parameter name as in the FMI model description (`z1`, `m_n`, `b`, ...).
    pub name: &'static str,
    /// The offending value of that parameter.
    pub value: f64,
    /// The violated bound, human readable.
    pub requirement: String,
}

impl fmt::Display for ParamError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "parameter {} = {} violates {}",
            self.name,
            Short(self.value),
            self.requirement
        )
    }
}

impl std::error::Error for ParamError {}

/// A default for a message: `2e8` rather than `200000000`.
fn readable(x: f64) -> String {
    if x != 0.0 && !(1e-3..1e5).contains(&x.abs()) {
        format!("{x:e}")
    } else {
        Short(x).to_string()
    }
}

/// Whether a parameter is a real number or an integer (stored as f64 in tables, as i32
/// in the model).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Any f64.
    Real,
    /// An integer that fits an i32 (FMI Integer).
    Integer,
}

/// The model's own rule for a parameter's value (the declared bounds of the interface
/// may be tighter).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Rule {
    /// 0 < x < inf.
    Positive,
    /// 0 <= x < inf.
    NonNegative,
    /// Any finite value.
    Finite,
    /// lo < x < hi.
    Open(f64, f64),
    /// An integer code 1..=max, with the meaning of each code (e.g. "1 Coulomb, 2 ...").
    Code(i32, &'static str),
    /// Checked elsewhere, by the rules that involve other parameters too (the pair
    /// geometry, `gear::PairGeometry::new`; the friction-law code).
    Elsewhere,
}

impl Rule {
    /// Whether `x` satisfies the rule (always true for [`Rule::Elsewhere`]).
    pub fn holds(self, x: f64) -> bool {
        match self {
            Rule::Positive => x > 0.0 && x.is_finite(),
            Rule::NonNegative => x >= 0.0 && x.is_finite(),
            Rule::Finite => x.is_finite(),
            Rule::Open(lo, hi) => x > lo && x < hi,
            Rule::Code(max, _) => x.fract() == 0.0 && x >= 1.0 && x <= f64::from(max),
            Rule::Elsewhere => true,
        }
    }

    /// The rule as text for `name`.
    pub fn text(self, name: &str) -> String {
        match self {
            Rule::Positive => format!("0 < {name} < inf"),
            Rule::NonNegative => format!("0 <= {name} < inf"),
            Rule::Finite => format!("{name} finite"),
            Rule::Open(lo, hi) => format!("{} < {name} < {}", Short(lo), Short(hi)),
            Rule::Code(max, meaning) => format!("{name} in 1..={max} ({meaning})"),
            Rule::Elsewhere => format!("the rules of {name}"),
        }
    }
}

/// One parameter of a model `T`, described once.
#[derive(Clone, Copy)]
pub struct Parameter<T> {
    /// Name as in the FMI model description.
    pub name: &'static str,
    /// SI unit as in the model description's unit definitions ("1": dimensionless).
    pub unit: &'static str,
    /// Real or integer.
    pub kind: Kind,
    /// Default value (the model description's start value).
    pub default: f64,
    /// Declared min of the interface (inclusive, as in FMI), if any.
    pub min: Option<f64>,
    /// Declared max of the interface (inclusive), if any.
    pub max: Option<f64>,
    /// The model's own rule, checked when the parameter set is validated.
    pub rule: Rule,
    /// Reads the field.
    pub get: fn(&T) -> f64,
    /// Writes the field (integers and codes already checked by [`Parameter::set`]).
    pub put: fn(&mut T, f64),
}

impl<T> Parameter<T> {
    /// Sets the field from `x` after checking that an integer parameter gets an integer
    /// and a code one of its codes.
    ///
    /// # Errors
    /// A non-integer or out-of-range value for an integer parameter, an unknown code.
    pub fn set(&self, p: &mut T, x: f64) -> Result<(), ParamError> {
        if let Rule::Code(..) = self.rule {
            if !self.rule.holds(x) {
                return Err(ParamError {
                    name: self.name,
                    value: x,
                    requirement: self.rule.text(self.name),
                });
            }
        }
        if self.kind == Kind::Integer
            && !(x.fract() == 0.0 && x >= f64::from(i32::MIN) && x <= f64::from(i32::MAX))
        {
            return Err(ParamError {
                name: self.name,
                value: x,
                requirement: format!("{} an integer", self.name),
            });
        }
        (self.put)(p, x);
        Ok(())
    }

    /// Checks the model's rule on the value in `p`.
    ///
    /// # Errors
    /// The rule, with the unit and the default as a hint.
    pub fn check(&self, p: &T) -> Result<(), ParamError> {
        self.check_value((self.get)(p))
    }

    /// Checks the model's rule on a value `x` of this parameter (e.g. a new tunable value).
    ///
    /// # Errors
    /// The rule, with the unit and the default as a hint.
    pub fn check_value(&self, x: f64) -> Result<(), ParamError> {
        if self.rule.holds(x) {
            Ok(())
        } else {
            Err(ParamError {
                name: self.name,
                value: x,
                requirement: format!(
                    "{} (unit {}, default {})",
                    self.rule.text(self.name),
                    self.unit,
                    readable(self.default)
                ),
            })
        }
    }
}
