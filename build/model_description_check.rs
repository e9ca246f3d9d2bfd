//! The model-description checker and code generator used by `build.rs` (included there with
//! `#[path]`), kept here so that its rules are unit-tested with the crate.
//!
//! Reads `modelDescription/modelDescription.xml` (the single source of truth for the FMU's
//! variables), checks it against the rules of FMI 2.0 (fmi-standard 2.0.x, section 2.2.7:
//! causality/variability/initial tables, start values, ModelStructure) and generates into
//! OUT_DIR:
//! - `variables_gen.rs`: the variable table (value reference -> `Var` variant, type,
//!   causality, variability, name, unit, start, description), the GUID and the log categories;
//! - `modelDescription.xml`: the description with the GUID placeholder filled in (what the
//!   packager writes into the .fmu, byte for byte).
//!
//! The GUID is derived from the description's content (placeholder left in, CRLF -> LF):
//! two 64-bit FNV-1a hashes with different offset bases give 128 bits. Same file, same GUID;
//! any change of the file, a new GUID. A bad description stops the build with a message
//! naming the variable and the rule it breaks.

use crate::hash::{fnv1a64, fnv1a64_with_basis};
use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

pub const SOURCE: &str = "modelDescription/modelDescription.xml";
const PLACEHOLDER: &str = "@GUID@";

/// Variable names the FMU binding refers to by name (docs/fmu.md "Variables"); missing ones
/// would otherwise surface as an obscure compile error in src/binding. The model
/// parameters are described once in `rotor::param_table`, and tests/rotor_parameter_table.rs
/// checks that table against this description.
const REQUIRED: &[&str] = &[
    "omega1",
    "T_load",
    "T1",
    "omega1_filtered",
    "omega2",
    "phi1",
    "phi2",
    "Fn",
    "TE",
    "gap",
    "P_in",
    "P_loss",
    "P_damp",
    "E_in",
    "E_loss",
    "E_damp",
    "E_load",
    "E_kin",
    "E_pot",
    "contact_length",
    "pairs_in_contact",
    "contact_lost",
    "d_phi",
    "mu",
    "omega1_filter_frequency",
    "rtol",
    "h_max",
    "r_b1",
    "r_b2",
    "a_w",
    "alpha_wt",
    "beta_b",
    "p_bt",
    "eps_alpha",
    "eps_beta",
    "H_V",
];
const REQUIRED_VECTORS: &[&str] = &[
    "u1",
    "u2",
    "v1",
    "v2",
    "F_bearing1",
    "F_bearing2",
    "F_friction1",
    "F_friction2",
    "M_friction1",
    "M_friction2",
    "F_contact1",
    "F_contact2",
    "M_contact1",
    "M_contact2",
];
const REQUIRED_CATEGORIES: &[&str] = &[
    "logStatusError",
    "logStatusWarning",
    "logEvents",
    "logSolver",
];

#[derive(Debug, Default, Clone)]
struct Var {
    index: usize, // 1-based position in ModelVariables
    name: String,
    vr: u32,
    description: Option<String>,
    causality: String,
    variability: String,
    initial: Option<String>,
    ty: String,
    declared_type: Option<String>,
    unit: Option<String>,
    display_unit: Option<String>,
    start: Option<String>,
    min: Option<String>,
    max: Option<String>,
    /// Enumeration: the item names of the declared type, values 1..=n in order.
    items: Vec<String>,
}

fn fail(msg: String) -> ! {
    // Unwinds to `process`, which turns it into Err(message).
    std::panic::panic_any(CheckError(msg))
}

/// Why the description was rejected.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckError(pub String);

fn attrs(e: &BytesStart) -> HashMap<String, String> {
    let mut m = HashMap::new();
    for a in e.attributes() {
        let a = a.unwrap_or_else(|err| fail(format!("malformed attribute: {err}")));
        let key = String::from_utf8_lossy(a.key.as_ref()).into_owned();
        if a.value.contains(&b'<') {
            // quick-xml tolerates it, XML (and FMPy's lxml) does not.
            fail(format!("attribute {key} contains a raw '<' (write &lt;)"));
        }
        let val = a
            .unescape_value()
            .unwrap_or_else(|err| fail(format!("bad attribute value of {key}: {err}")))
            .into_owned();
        m.insert(key, val);
    }
    m
}

fn guid_of(content: &str) -> String {
    let norm = content.replace("\r\n", "\n");
    // 64-bit FNV-1a twice, with the standard and a second offset basis.
    let a = fnv1a64(norm.as_bytes());
    let b = fnv1a64_with_basis(norm.as_bytes(), 0x6c62_272e_07bb_0142);
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}

struct Parsed {
    root: HashMap<String, String>,
    cosim: Option<HashMap<String, String>>,
    units: HashMap<String, Vec<String>>, // unit -> display units
    types: HashMap<String, (Option<String>, Option<String>)>, // name -> (unit, displayUnit)
    /// Enumeration SimpleTypes: name -> (item name, item value) in declaration order.
    enums: HashMap<String, Vec<(String, String)>>,
    categories: Vec<String>,
    vars: Vec<Var>,
    outputs: Vec<usize>,
    /// Per entry of `outputs`: its `dependencies` (None when absent) and the number of
    /// `dependenciesKind` entries (None when absent).
    output_deps: Vec<(Option<Vec<usize>>, Option<usize>)>,
    initial_unknowns: Vec<usize>,
}

fn parse(text: &str) -> Parsed {
    let mut reader = Reader::from_str(text);
    reader.config_mut().trim_text(true);
    let mut p = Parsed {
        root: HashMap::new(),
        cosim: None,
        units: HashMap::new(),
        types: HashMap::new(),
        enums: HashMap::new(),
        categories: Vec::new(),
        vars: Vec::new(),
        outputs: Vec::new(),
        output_deps: Vec::new(),
        initial_unknowns: Vec::new(),
    };
    let mut stack: Vec<String> = Vec::new();
    let mut cur_var: Option<Var> = None;
    let mut cur_unit: Option<String> = None;
    let mut cur_type: Option<String> = None;
    loop {
        let ev = reader.read_event().unwrap_or_else(|e| {
            fail(format!(
                "XML error at byte {}: {e}",
                reader.buffer_position()
            ))
        });
        let (e, empty) = match &ev {
            Event::Start(e) => (e.clone(), false),
            Event::Empty(e) => (e.clone(), true),
            Event::End(_) => {
                let name = stack.pop().unwrap_or_default();
                match name.as_str() {
                    "ScalarVariable" => {
                        if let Some(v) = cur_var.take() {
                            p.vars.push(v);
                        }
                    }
                    "Unit" => cur_unit = None,
                    "SimpleType" => cur_type = None,
                    _ => {}
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
        let a = attrs(&e);
        let parent = stack.last().cloned().unwrap_or_default();
        match name.as_str() {
            "fmiModelDescription" => p.root = a.clone(),
            "CoSimulation" => p.cosim = Some(a.clone()),
            "ModelExchange" => {
                fail("this FMU is Co-Simulation only; remove <ModelExchange>".into())
            }
            "Unit" => {
                let n = a
                    .get("name")
                    .cloned()
                    .unwrap_or_else(|| fail("Unit without name".into()));
                if p.units.insert(n.clone(), Vec::new()).is_some() {
                    fail(format!("unit {n} defined twice"));
                }
                cur_unit = Some(n);
            }
            "DisplayUnit" => {
                let u = cur_unit
                    .clone()
                    .unwrap_or_else(|| fail("DisplayUnit outside Unit".into()));
                let n = a
                    .get("name")
                    .cloned()
                    .unwrap_or_else(|| fail("DisplayUnit without name".into()));
                if let Some(d) = p.units.get_mut(&u) {
                    d.push(n);
                }
            }
            "SimpleType" => {
                let n = a
                    .get("name")
                    .cloned()
                    .unwrap_or_else(|| fail("SimpleType without name".into()));
                cur_type = Some(n);
            }
            "Real" | "Integer" | "Boolean" | "String" | "Enumeration" if parent == "SimpleType" => {
                if let Some(t) = &cur_type {
                    p.types.insert(
                        t.clone(),
                        (a.get("unit").cloned(), a.get("displayUnit").cloned()),
                    );
                    if name == "Enumeration" {
                        p.enums.insert(t.clone(), Vec::new());
                    }
                }
            }
            "Item" if parent == "Enumeration" => {
                let t = cur_type
                    .clone()
                    .unwrap_or_else(|| fail("Item outside an Enumeration SimpleType".into()));
                let item = (
                    a.get("name")
                        .cloned()
                        .unwrap_or_else(|| fail(format!("{t}: Item without name"))),
                    a.get("value")
                        .cloned()
                        .unwrap_or_else(|| fail(format!("{t}: Item without value"))),
                );
                if let Some(items) = p.enums.get_mut(&t) {
                    items.push(item);
                }
            }
            "Category" => p.categories.push(
                a.get("name")
                    .cloned()
                    .unwrap_or_else(|| fail("Category without name".into())),
            ),
            "ScalarVariable" => {
                let vname = a
                    .get("name")
                    .cloned()
                    .unwrap_or_else(|| fail("ScalarVariable without name".into()));
                let vr = a
                    .get("valueReference")
                    .and_then(|s| s.parse::<u32>().ok())
                    .unwrap_or_else(|| fail(format!("{vname}: missing or bad valueReference")));
                cur_var = Some(Var {
                    index: p.vars.len() + 1,
                    name: vname,
                    vr,
                    description: a.get("description").cloned(),
                    causality: a
                        .get("causality")
                        .cloned()
                        .unwrap_or_else(|| "local".into()),
                    variability: a.get("variability").cloned().unwrap_or_default(),
                    initial: a.get("initial").cloned(),
                    ..Var::default()
                });
            }
            "Real" | "Integer" | "Boolean" | "String" | "Enumeration"
                if parent == "ScalarVariable" =>
            {
                let v = cur_var
                    .as_mut()
                    .unwrap_or_else(|| fail("type element outside ScalarVariable".into()));
                v.ty = name.clone();
                v.declared_type = a.get("declaredType").cloned();
                v.unit = a.get("unit").cloned();
                v.display_unit = a.get("displayUnit").cloned();
                v.start = a.get("start").cloned();
                v.min = a.get("min").cloned();
                v.max = a.get("max").cloned();
            }
            "Unknown" => {
                let idx = a
                    .get("index")
                    .and_then(|s| s.parse::<usize>().ok())
                    .unwrap_or_else(|| fail("ModelStructure Unknown without a valid index".into()));
                let deps = a.get("dependencies").map(|d| {
                    d.split_whitespace()
                        .map(|x| {
                            x.parse::<usize>().unwrap_or_else(|_| {
                                fail(format!("Unknown {idx}: dependency {x:?} is not an index"))
                            })
                        })
                        .collect::<Vec<_>>()
                });
                let kinds = a
                    .get("dependenciesKind")
                    .map(|k| k.split_whitespace().count());
                match parent.as_str() {
                    "Outputs" => {
                        p.outputs.push(idx);
                        p.output_deps.push((deps, kinds));
                    }
                    "InitialUnknowns" => p.initial_unknowns.push(idx),
                    "Derivatives" => fail("Derivatives are for Model Exchange only".into()),
                    _ => {}
                }
            }
            _ => {}
        }
        if !empty {
            stack.push(name);
        }
    }
    p
}

/// FMI 2.0 section 2.2.7: which (causality, variability) pairs exist, which `initial`
/// values each allows (first = default), and whether a start value is required.
fn allowed_initial(c: &str, v: &str) -> Option<&'static [&'static str]> {
    match (c, v) {
        ("parameter", "fixed" | "tunable") => Some(&["exact"]),
        ("calculatedParameter", "fixed" | "tunable") => Some(&["calculated", "approx"]),
        ("input", "discrete" | "continuous") => Some(&[]),
        ("output", "constant") => Some(&["exact"]),
        ("output", "discrete" | "continuous") => Some(&["calculated", "exact", "approx"]),
        ("local", "constant") => Some(&["exact"]),
        ("local", "fixed" | "tunable") => Some(&["calculated", "approx"]),
        ("local", "discrete" | "continuous") => Some(&["calculated", "exact", "approx"]),
        ("independent", "continuous") => Some(&[]),
        _ => None,
    }
}

fn check(p: &mut Parsed) {
    if p.root.get("fmiVersion").map(String::as_str) != Some("2.0") {
        fail("fmiVersion must be \"2.0\"".into());
    }
    if p.root.get("guid").map(String::as_str) != Some(PLACEHOLDER) {
        fail(format!(
            "the guid attribute must be the placeholder {PLACEHOLDER} (build.rs fills it in)"
        ));
    }
    if p.root.get("variableNamingConvention").map(String::as_str) != Some("structured") {
        fail("variableNamingConvention must be \"structured\"".into());
    }
    let cs = p
        .cosim
        .clone()
        .unwrap_or_else(|| fail("missing <CoSimulation>".into()));
    if cs.get("modelIdentifier").map(String::as_str) != Some("GearedRotor") {
        fail("CoSimulation modelIdentifier must be GearedRotor".into());
    }
    for c in REQUIRED_CATEGORIES {
        if !p.categories.iter().any(|x| x == c) {
            fail(format!("LogCategories lacks {c}"));
        }
    }
    let mut names = HashSet::new();
    let mut vrs = HashSet::new();
    for v in p.vars.iter_mut() {
        let n = v.name.clone();
        if !names.insert(n.clone()) {
            fail(format!("variable name {n} is not unique"));
        }
        if v.ty.is_empty() {
            fail(format!("{n}: no type element (Real/Integer/Boolean)"));
        }
        if !matches!(
            v.ty.as_str(),
            "Real" | "Integer" | "Boolean" | "Enumeration"
        ) {
            fail(format!("{n}: type {} is not supported by this FMU", v.ty));
        }
        if v.ty == "Enumeration" {
            v.items = enum_items(&n, v.declared_type.as_deref(), &p.enums);
        }
        // Enumerations are read and written with fmi2Get/SetInteger: one namespace.
        let access = if v.ty == "Enumeration" {
            "Integer"
        } else {
            v.ty.as_str()
        };
        if !vrs.insert((access.to_string(), v.vr)) {
            fail(format!(
                "{n}: valueReference {} is used twice for type {access}",
                v.vr
            ));
        }
        let ok_name = !n.is_empty()
            && n.split('.').all(|part| {
                let mut ch = part.chars();
                matches!(ch.next(), Some(c) if c.is_ascii_alphabetic() || c == '_')
                    && ch.all(|c| c.is_ascii_alphanumeric() || c == '_')
            });
        if !ok_name {
            fail(format!(
                "{n}: not a valid structured name (identifiers separated by '.')"
            ));
        }
        if v.description
            .as_deref()
            .map(str::trim)
            .unwrap_or("")
            .is_empty()
        {
            fail(format!("{n}: every variable needs a description"));
        }
        if v.variability.is_empty() {
            v.variability = "continuous".into();
        }
        if v.variability == "continuous" && v.ty != "Real" {
            fail(format!(
                "{n}: only Real variables can be continuous (use variability=\"discrete\")"
            ));
        }
        let allowed = allowed_initial(&v.causality, &v.variability).unwrap_or_else(|| {
            fail(format!(
                "{n}: causality=\"{}\" with variability=\"{}\" is not allowed (FMI 2.0 table 2.2.7)",
                v.causality, v.variability
            ))
        });
        let initial = match (&v.initial, allowed.first()) {
            (Some(i), _) if allowed.contains(&i.as_str()) => i.clone(),
            (Some(i), _) => fail(format!(
                "{n}: initial=\"{i}\" is not allowed for causality={} variability={} (allowed: {allowed:?})",
                v.causality, v.variability
            )),
            (None, Some(d)) => (*d).to_string(),
            (None, None) => String::new(),
        };
        let needs_start = matches!(initial.as_str(), "exact" | "approx") || v.causality == "input";
        if needs_start && v.start.is_none() {
            fail(format!(
                "{n}: a start value is required (causality={}, initial={initial})",
                v.causality
            ));
        }
        if initial == "calculated" && v.start.is_some() {
            fail(format!(
                "{n}: initial=\"calculated\" must not have a start value"
            ));
        }
        if let Some(s) = &v.start {
            let ok = match v.ty.as_str() {
                "Real" => s.parse::<f64>().map(f64::is_finite).unwrap_or(false),
                "Integer" => s.parse::<i32>().is_ok(),
                "Enumeration" => s
                    .parse::<usize>()
                    .is_ok_and(|k| k >= 1 && k <= v.items.len()),
                _ => matches!(s.as_str(), "true" | "false" | "1" | "0"),
            };
            if !ok {
                fail(format!("{n}: start value {s:?} is not a valid {}", v.ty));
            }
        }
        if let Some(dt) = &v.declared_type {
            let (u, du) = p.types.get(dt).cloned().unwrap_or_else(|| {
                fail(format!("{n}: declaredType {dt} is not in TypeDefinitions"))
            });
            if v.unit.is_none() {
                v.unit = u;
            }
            if v.display_unit.is_none() {
                v.display_unit = du;
            }
        }
        if let Some(u) = &v.unit {
            let dus = p
                .units
                .get(u)
                .unwrap_or_else(|| fail(format!("{n}: unit {u} is not in UnitDefinitions")));
            if let Some(du) = &v.display_unit {
                if !dus.contains(du) {
                    fail(format!(
                        "{n}: displayUnit {du} is not a DisplayUnit of unit {u}"
                    ));
                }
            }
        } else if v.ty == "Real" {
            fail(format!(
                "{n}: every Real needs a unit (directly or via declaredType)"
            ));
        }
        v.initial = if initial.is_empty() {
            None
        } else {
            Some(initial)
        };
    }
    // ModelStructure: Outputs = exactly the outputs, in index order.
    let outs: Vec<usize> = p
        .vars
        .iter()
        .filter(|v| v.causality == "output")
        .map(|v| v.index)
        .collect();
    for &i in &p.outputs {
        if i == 0 || i > p.vars.len() || p.vars[i - 1].causality != "output" {
            fail(format!(
                "ModelStructure/Outputs index {i} is not an output variable"
            ));
        }
    }
    for v in p.vars.iter().filter(|v| v.causality == "output") {
        if !p.outputs.contains(&v.index) {
            fail(format!(
                "output {} (index {}) is missing from ModelStructure/Outputs",
                v.name, v.index
            ));
        }
    }
    if p.outputs != outs {
        fail("ModelStructure/Outputs must list every output once, in ascending index order".into());
    }
    // dependencies of an output (Co-Simulation): inputs only, ascending; dependenciesKind,
    // if given, one per dependency and only with dependencies.
    for (&i, (deps, kinds)) in p.outputs.iter().zip(&p.output_deps) {
        if let Some(d) = deps {
            for &k in d {
                if k == 0 || k > p.vars.len() || p.vars[k - 1].causality != "input" {
                    fail(format!(
                        "ModelStructure/Outputs index {i}: dependency {k} is not an input variable"
                    ));
                }
            }
            if d.windows(2).any(|w| w[0] >= w[1]) {
                fail(format!(
                    "ModelStructure/Outputs index {i}: dependencies not ascending"
                ));
            }
        }
        match (deps, kinds) {
            (Some(d), Some(n)) if d.len() != *n => fail(format!(
                "ModelStructure/Outputs index {i}: {} dependencies but {n} dependenciesKind",
                d.len()
            )),
            (None, Some(_)) => fail(format!(
                "ModelStructure/Outputs index {i}: dependenciesKind without dependencies"
            )),
            _ => {}
        }
    }
    let init: Vec<usize> = p
        .vars
        .iter()
        .filter(|v| {
            (v.causality == "output"
                && matches!(v.initial.as_deref(), Some("approx" | "calculated")))
                || v.causality == "calculatedParameter"
        })
        .map(|v| v.index)
        .collect();
    if p.initial_unknowns != init {
        fail(format!(
            "ModelStructure/InitialUnknowns must be exactly the outputs with initial approx/calculated \
             and the calculated parameters, ascending: expected indices {init:?}"
        ));
    }
    for r in REQUIRED {
        if !names.contains(*r) {
            fail(format!(
                "required variable {r} (docs/fmu.md \"Variables\") is missing"
            ));
        }
    }
    for r in REQUIRED_VECTORS {
        for ax in ["x", "y", "z"] {
            let n = format!("{r}.{ax}");
            if !names.contains(&n) {
                fail(format!(
                    "required variable {n} (docs/fmu.md \"Variables\") is missing"
                ));
            }
        }
    }
}

/// Items of an Enumeration variable's declared type; their values must be 1..=n in
/// declaration order (the FMU checks a set value against that range and names the items).
fn enum_items(
    n: &str,
    declared: Option<&str>,
    enums: &HashMap<String, Vec<(String, String)>>,
) -> Vec<String> {
    let dt = declared.unwrap_or_else(|| {
        fail(format!(
            "{n}: an Enumeration variable needs a declaredType (an Enumeration SimpleType)"
        ))
    });
    let items = enums.get(dt).unwrap_or_else(|| {
        fail(format!(
            "{n}: declaredType {dt} is not an Enumeration SimpleType"
        ))
    });
    if items.is_empty() {
        fail(format!("{n}: Enumeration {dt} has no Item"));
    }
    for (k, (name, value)) in items.iter().enumerate() {
        if value.parse::<usize>().ok() != Some(k + 1) {
            fail(format!(
                "{n}: Item {name} of {dt} has value {value}; items must be numbered 1, 2, ... in order"
            ));
        }
    }
    items.iter().map(|(name, _)| name.clone()).collect()
}

fn rust_variant(name: &str) -> String {
    name.replace('.', "_")
}

fn generate(p: &Parsed, guid: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "// Generated by build.rs from {SOURCE}. Do not edit.");
    let _ = writeln!(
        s,
        "/// GUID of this model description (derived from its content)."
    );
    let _ = writeln!(s, "pub const GUID: &str = {guid:?};");
    let _ = writeln!(
        s,
        "/// Log categories declared in the description, in order."
    );
    let _ = writeln!(
        s,
        "pub const LOG_CATEGORIES: &[&str] = &{:?};",
        p.categories
    );
    let _ = writeln!(s, "/// Number of variables.");
    let _ = writeln!(s, "pub const N_VARIABLES: usize = {};", p.vars.len());
    let _ = writeln!(
        s,
        "/// One variant per variable (dots of structured names become underscores)."
    );
    let _ = writeln!(s, "#[allow(non_camel_case_types)]");
    let _ = writeln!(s, "#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]");
    let _ = writeln!(s, "pub enum Var {{");
    for v in &p.vars {
        let _ = writeln!(s, "    /// `{}`", v.name);
        let _ = writeln!(s, "    {},", rust_variant(&v.name));
    }
    let _ = writeln!(s, "}}");
    let _ = writeln!(
        s,
        "/// The variable table, in the order of ModelVariables (index = position + 1)."
    );
    let _ = writeln!(s, "pub static VARIABLES: [Variable; N_VARIABLES] = [");
    for v in &p.vars {
        let ty = match v.ty.as_str() {
            "Real" => "VarType::Real",
            "Integer" | "Enumeration" => "VarType::Integer",
            _ => "VarType::Boolean",
        };
        let caus = match v.causality.as_str() {
            "parameter" => "Causality::Parameter",
            "calculatedParameter" => "Causality::CalculatedParameter",
            "input" => "Causality::Input",
            "output" => "Causality::Output",
            "independent" => "Causality::Independent",
            _ => "Causality::Local",
        };
        let var = match v.variability.as_str() {
            "constant" => "Variability::Constant",
            "fixed" => "Variability::Fixed",
            "tunable" => "Variability::Tunable",
            "discrete" => "Variability::Discrete",
            _ => "Variability::Continuous",
        };
        let num = |o: &Option<String>| -> String {
            match o.as_deref() {
                None => "None".into(),
                Some("true") => "Some(1.0)".into(),
                Some("false") => "Some(0.0)".into(),
                Some(x) => format!(
                    "Some({:?})",
                    x.parse::<f64>()
                        .unwrap_or_else(|_| fail(format!("{}: bad number {x}", v.name)))
                ),
            }
        };
        let _ = writeln!(
            s,
            "    Variable {{ var: Var::{}, name: {:?}, vr: {}, ty: {ty}, causality: {caus}, variability: {var}, \
             start: {}, min: {}, max: {}, unit: {:?}, display_unit: {:?}, description: {:?}, items: &{:?} }},",
            rust_variant(&v.name),
            v.name,
            v.vr,
            num(&v.start),
            num(&v.min),
            num(&v.max),
            v.unit.clone().unwrap_or_default(),
            v.display_unit.clone().unwrap_or_default(),
            v.description.clone().unwrap_or_default(),
            v.items
        );
    }
    let _ = writeln!(s, "];");
    // One dense table per type, indexed by vr - (smallest vr of that type): a lookup is
    // a subtraction and a load (masters look up every value reference of every call).
    let _ = writeln!(s, "const NO_VAR: u16 = u16::MAX;");
    assert!(
        p.vars.len() < usize::from(u16::MAX),
        "more variables than the tables hold"
    );
    let mut arms = String::new();
    for ty in ["Real", "Integer", "Boolean"] {
        let of_ty: Vec<(usize, u32)> = p
            .vars
            .iter()
            .enumerate()
            .filter(|(_, v)| {
                let t = if v.ty == "Enumeration" {
                    "Integer"
                } else {
                    v.ty.as_str()
                };
                t == ty
            })
            .map(|(i, v)| (i, v.vr))
            .collect();
        let min = of_ty.iter().map(|&(_, vr)| vr).min().unwrap_or(0);
        let max = of_ty.iter().map(|&(_, vr)| vr).max().unwrap_or(0);
        let len = if of_ty.is_empty() {
            0
        } else {
            (max - min + 1) as usize
        };
        if len > 100_000 {
            fail(format!(
                "{ty} value references span {min}..={max}: too sparse for a table"
            ));
        }
        let mut table = vec!["NO_VAR".to_string(); len];
        for &(i, vr) in &of_ty {
            table[(vr - min) as usize] = i.to_string();
        }
        let upper = ty.to_uppercase();
        let _ = writeln!(
            s,
            "static {upper}_INDEX: [u16; {len}] = [{}];",
            table.join(", ")
        );
        let _ = writeln!(arms, "        VarType::{ty} => ({min}, &{upper}_INDEX),");
    }
    let _ = writeln!(
        s,
        "/// Position in [`VARIABLES`] of the variable with this type and value reference."
    );
    let _ = writeln!(
        s,
        "pub fn index_of(ty: VarType, vr: u32) -> Option<usize> {{"
    );
    let _ = writeln!(s, "    let (min, table): (u32, &[u16]) = match ty {{");
    let _ = write!(s, "{arms}");
    let _ = writeln!(s, "    }};");
    let _ = writeln!(s, "    match table.get(vr.checked_sub(min)? as usize) {{");
    let _ = writeln!(
        s,
        "        Some(&i) if i != NO_VAR => Some(usize::from(i)),"
    );
    let _ = writeln!(s, "        _ => None,");
    let _ = writeln!(s, "    }}");
    let _ = writeln!(s, "}}");
    s
}

/// Checks the description and returns (generated Rust table, XML with the GUID filled in).
///
/// # Errors
/// A message naming the variable and the rule it breaks.
pub fn process(text: &str) -> Result<(String, String), String> {
    let r = std::panic::catch_unwind(|| {
        let mut parsed = parse(text);
        check(&mut parsed);
        let guid = guid_of(text);
        let filled = text.replace("\r\n", "\n").replacen(PLACEHOLDER, &guid, 1);
        (generate(&parsed, &guid), filled)
    });
    r.map_err(|p| match p.downcast::<CheckError>() {
        Ok(e) => e.0,
        Err(p) => match p.downcast::<String>() {
            Ok(s) => *s,
            Err(_) => "internal error of the checker".into(),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const XML: &str = include_str!("../modelDescription/modelDescription.xml");

    fn rejects(mutated: &str, expect: &str) {
        assert_ne!(mutated, XML, "mutation did not apply");
        match process(mutated) {
            Ok(_) => panic!("accepted a description that should fail with {expect:?}"),
            Err(m) => assert!(m.contains(expect), "message {m:?} lacks {expect:?}"),
        }
    }

    #[test]
    fn the_real_description_passes_and_the_guid_is_deterministic() {
        let (table, xml) = process(XML).expect("valid");
        assert!(table.contains("pub const GUID"));
        assert!(!xml.contains(PLACEHOLDER));
        assert_eq!(guid_of(XML), guid_of(XML));
        assert_ne!(guid_of(XML), guid_of(&XML.replace("Coulomb", "coulomb")));
        assert_eq!(guid_of(XML), guid_of(&XML.replace('\n', "\r\n")));
    }

    #[test]
    fn bad_descriptions_are_rejected_with_a_clear_message() {
        rejects(
            &XML.replacen("name=\"T_load\"", "name=\"omega1\"", 1),
            "omega1 is not unique",
        );
        rejects(
            &XML.replacen("valueReference=\"2\" ", "valueReference=\"1\" ", 1),
            "used twice",
        );
        rejects(
            &XML.replacen(" start=\"27\"", "", 1),
            "z1: a start value is required",
        );
        rejects(
            &XML.replacen(
                "causality=\"input\" variability=\"continuous\"",
                "causality=\"input\" variability=\"fixed\"",
                1,
            ),
            "not allowed",
        );
        rejects(
            &XML.replacen(
                "causality=\"output\" variability=\"continuous\" initial=\"calculated\"",
                "causality=\"output\" variability=\"continuous\" initial=\"exact\"",
                1,
            ),
            "start value is required",
        );
        let first_output = XML
            .find("<Outputs>")
            .map(|i| &XML[i..])
            .and_then(|s| s.find("<Unknown"))
            .unwrap();
        let i = XML.find("<Outputs>").unwrap() + first_output;
        let j = i + XML[i..].find("/>").unwrap() + 2;
        let removed = format!("{}{}", &XML[..i], &XML[j..]);
        rejects(&removed, "missing from ModelStructure/Outputs");
        rejects(
            &XML.replacen(
                "dependencies=\"2\" dependenciesKind",
                "dependencies=\"45\" dependenciesKind",
                1,
            ),
            "is not an input variable",
        );
        rejects(
            &XML.replacen(
                "dependenciesKind=\"dependent\"",
                "dependenciesKind=\"dependent fixed\"",
                1,
            ),
            "dependenciesKind",
        );
        rejects(
            &XML.replacen("unit=\"N.m\"/>", "unit=\"Nm\"/>", 1),
            "not in UnitDefinitions",
        );
        rejects(
            &XML.replacen("guid=\"@GUID@\"", "guid=\"{x}\"", 1),
            "placeholder",
        );
        rejects(
            &XML.replacen("description=\"Normal module\"", "description=\" \"", 1),
            "description",
        );
        rejects(
            &XML.replacen("name=\"psi0\"", "name=\"psi 0\"", 1),
            "structured name",
        );
        rejects(
            &XML.replacen("(0 &lt; alpha_n", "(0 < alpha_n", 1),
            "raw '<'",
        );
        rejects(
            &XML.replacen("name=\"H_V\"", "name=\"H_W\"", 1),
            "required variable H_V",
        );
    }

    #[test]
    fn enumerations_are_checked_and_read_as_integers() {
        let (table, _) = process(XML).expect("valid");
        // read and written with fmi2Get/SetInteger, items listed for the messages
        assert!(table.contains("vr: 1010, ty: VarType::Integer"));
        // and found as an Integer: entry 1010 - 1001 of the Integer table is a variable
        assert!(table.contains("VarType::Integer => (1001, &INTEGER_INDEX)"));
        let row = table
            .lines()
            .find(|l| l.starts_with("static INTEGER_INDEX"))
            .expect("Integer table");
        let list = &row[row.rfind('[').unwrap() + 1..row.rfind(']').unwrap()];
        let entry = list
            .split(',')
            .map(str::trim)
            .nth(1010 - 1001)
            .expect("entry");
        assert_ne!(entry, "NO_VAR", "{row}");
        assert!(table.contains("items: &[\"rest\", \"static_equilibrium\", \"periodic\"]"));
        assert!(table.contains("items: &[\"warn\", \"discard\"]"));
        rejects(
            &XML.replacen(
                "<Enumeration declaredType=\"Initialization\" start=\"1\"/>",
                "<Enumeration declaredType=\"Initialization\" start=\"4\"/>",
                1,
            ),
            "initialization: start value \"4\" is not a valid Enumeration",
        );
        rejects(
            &XML.replacen(
                "<Enumeration declaredType=\"Initialization\" start=\"1\"/>",
                "<Enumeration start=\"1\"/>",
                1,
            ),
            "initialization: an Enumeration variable needs a declaredType",
        );
        rejects(
            &XML.replacen(
                "<Item name=\"periodic\" value=\"3\"",
                "<Item name=\"periodic\" value=\"4\"",
                1,
            ),
            "items must be numbered 1, 2, ... in order",
        );
        // Integer and Enumeration share the value references of fmi2Get/SetInteger
        rejects(
            &XML.replacen("valueReference=\"1011\"", "valueReference=\"1001\"", 1),
            "valueReference 1001 is used twice for type Integer",
        );
    }
}
