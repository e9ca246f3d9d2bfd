//! The parameter table (`rotor::param_table`: each model parameter's name, unit, default,
//! declared bounds and rule, written once on the Rust side) against the model description
//! (the interface's source of truth, read at build time into `fmi2::variables`): same
//! names, start values, min/max and units, and every model parameter of the description is
//! in the table.

use geared_rotor::fmi2::variables::{self, Causality, VarType, VARIABLES};
use geared_rotor::parameter::{Kind, Rule};
use geared_rotor::rotor::{param_table, Params};
use std::collections::BTreeSet;

/// Parameters of the model description that are not model parameters (`Params`) but
/// settings of the solver and of the FMU binding.
const SETTINGS: &[&str] = &[
    "initialization",
    "on_lift_off",
    "tooth_contact",
    "rtol",
    "h_max",
    "max_internal_steps",
    "h_fixed",
];

#[test]
fn table_equals_model_description() {
    let mut seen = BTreeSet::new();
    for q in param_table::all() {
        let name = q.name();
        assert!(seen.insert(name), "{name} twice in the table");
        let v = variables::by_name(name).unwrap_or_else(|| panic!("{name}: not in the XML"));
        assert_eq!(v.causality, Causality::Parameter, "{name}");
        let ty = match q.kind() {
            Kind::Real => VarType::Real,
            Kind::Integer => VarType::Integer,
        };
        assert_eq!(v.ty, ty, "{name}: type");
        assert_eq!(v.start, Some(q.default_value()), "{name}: start value");
        assert_eq!((v.min, v.max), q.declared(), "{name}: declared min/max");
        assert_eq!(v.unit, q.unit(), "{name}: unit");
    }
    let xml: BTreeSet<&str> = VARIABLES
        .iter()
        .filter(|v| v.causality == Causality::Parameter)
        .map(|v| v.name)
        .collect();
    let expected: BTreeSet<&str> = seen
        .iter()
        .copied()
        .chain(SETTINGS.iter().copied())
        .collect();
    assert_eq!(
        xml, expected,
        "XML parameters = table + solver/binding settings"
    );
}

#[test]
fn declared_bounds_and_defaults_obey_the_rules() {
    let p = Params::default();
    p.validate()
        .expect("the defaults form a valid parameter set");
    for q in param_table::all() {
        let rule = q.rule();
        assert!(rule.holds(q.default_value()), "{}: default", q.name());
        assert_eq!(
            q.get(&p),
            q.default_value(),
            "{}: Params::default",
            q.name()
        );
        let (min, max) = q.declared();
        for b in [min, max].into_iter().flatten() {
            assert!(
                rule.holds(b),
                "{}: declared bound {b} breaks its rule",
                q.name()
            );
        }
        // A rule that bounds the value must be declared (FMI bounds are inclusive: > 0 is
        // declared as min = 1e-300).
        match rule {
            Rule::Positive => assert!(min.is_some_and(|m| m > 0.0), "{}", q.name()),
            Rule::NonNegative => assert_eq!(min, Some(0.0), "{}", q.name()),
            Rule::Open(..) | Rule::Code(..) => assert!(min.is_some() && max.is_some()),
            Rule::Finite | Rule::Elsewhere => {}
        }
    }
}

#[test]
fn rules_refuse_by_name() {
    for q in param_table::all() {
        let bad = match q.rule() {
            Rule::Positive => 0.0,
            Rule::NonNegative => -1.0,
            Rule::Finite => f64::NAN,
            Rule::Open(lo, _) => lo,
            Rule::Code(max, _) => f64::from(max + 1),
            Rule::Elsewhere => continue,
        };
        let mut p = Params::default();
        let e = match q.set(&mut p, bad) {
            Err(e) => e,
            Ok(()) => q.check(&p).expect_err(q.name()),
        };
        assert_eq!(e.name, q.name());
        assert!(e.to_string().contains(q.name()), "{e}");
    }
}
