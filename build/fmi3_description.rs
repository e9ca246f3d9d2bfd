//! The FMI 3.0 model description, generated from the FMI 2.0 one (the single source of
//! truth, `modelDescription/modelDescription.xml`, after `model_description_check` accepted
//! it and filled in the GUID) by `build.rs`; included there and, for its unit tests, in the
//! crate (`src/lib.rs`).
//!
//! The same variables with the same names, value references, descriptions, units, display
//! units, start values, bounds, causalities and variabilities, in the 3.0 schema:
//! - `fmiVersion="3.0"`, the GUID as `instantiationToken`;
//! - `<CoSimulation>` with the capabilities of the FMI 3.0 shell (`crate::c_abi3`):
//!   variable step size, output derivatives of order 1, FMU state get/set/serialize,
//!   `mightReturnEarlyFromDoStep` (early return at a lift-off, docs/fmu.md "FMI 3.0"), no
//!   event mode, no intermediate update, no directional derivatives;
//! - `SimpleType`s become `Float64Type` / `EnumerationType`;
//! - `ScalarVariable` + `Real` / `Integer` / `Boolean` / `Enumeration` becomes `Float64` /
//!   `Int32` / `Boolean` / `Enumeration` (an FMI 3.0 Enumeration is read with fmi3GetInt64);
//! - the independent variable `time` (value reference [`TIME_VR`], which FMI 3.0 requires
//!   and FMI 2.0 left implicit) first;
//! - `<ModelStructure>`: `<Output>` and `<InitialUnknown>` with value references instead
//!   of indices (dependencies too);
//! - FMI 2.0 function names in descriptions are replaced by their 3.0 counterparts.

use quick_xml::events::Event;
use quick_xml::Reader;
use std::fmt::Write as _;

/// Value reference of the independent variable `time` (unused by the 2.0 description).
pub const TIME_VR: u32 = 0;

/// One element of the parsed 2.0 description.
#[derive(Debug, Clone, Default)]
struct El {
    name: String,
    attrs: Vec<(String, String)>,
    children: Vec<El>,
}

impl El {
    fn attr(&self, k: &str) -> Option<&str> {
        self.attrs
            .iter()
            .find(|(a, _)| a == k)
            .map(|(_, v)| v.as_str())
    }
    fn child(&self, name: &str) -> Option<&El> {
        self.children.iter().find(|c| c.name == name)
    }
}

fn parse(xml: &str) -> Result<El, String> {
    let mut reader = Reader::from_str(xml);
    let mut stack: Vec<El> = vec![El::default()];
    loop {
        let ev = reader
            .read_event()
            .map_err(|e| format!("XML error at byte {}: {e}", reader.buffer_position()))?;
        let (e, empty) = match ev {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::End(_) => {
                let el = stack.pop().ok_or("unbalanced XML")?;
                stack.last_mut().ok_or("unbalanced XML")?.children.push(el);
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let mut el = El {
            name: String::from_utf8_lossy(e.name().as_ref()).into_owned(),
            ..El::default()
        };
        for a in e.attributes() {
            let a = a.map_err(|err| format!("malformed attribute: {err}"))?;
            let v = a
                .unescape_value()
                .map_err(|err| format!("bad attribute value: {err}"))?;
            el.attrs.push((
                String::from_utf8_lossy(a.key.as_ref()).into_owned(),
                v.into_owned(),
            ));
        }
        if empty {
            stack.last_mut().ok_or("unbalanced XML")?.children.push(el);
        } else {
            stack.push(el);
        }
    }
    let mut root = stack.pop().ok_or("empty XML")?;
    root.children
        .pop()
        .filter(|r| r.name == "fmiModelDescription")
        .ok_or_else(|| "no fmiModelDescription element".to_string())
}

fn esc(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            c => o.push(c),
        }
    }
    o
}

/// FMI 2.0 function and status names in a description, in FMI 3.0 words.
fn to_fmi3_words(s: &str) -> String {
    s.replace(
        "fmi2LastSuccessfulTime",
        "the lastSuccessfulTime of fmi3DoStep",
    )
    .replace("fmi2SetupExperiment", "fmi3EnterInitializationMode")
    .replace("fmi2", "fmi3")
}

fn write_attrs(out: &mut String, attrs: &[(&str, String)]) {
    for (k, v) in attrs {
        let _ = write!(out, " {k}=\"{}\"", esc(v));
    }
}

/// The attributes of `el` named in `keys`, in that order (descriptions in 3.0 words).
fn pick(el: &El, keys: &[&'static str]) -> Vec<(&'static str, String)> {
    keys.iter()
        .filter_map(|&k| {
            el.attr(k).map(|v| {
                let v = if k == "description" {
                    to_fmi3_words(v)
                } else {
                    v.to_string()
                };
                (k, v)
            })
        })
        .collect()
}

/// The FMI 3.0 model description for the (checked, GUID-filled) FMI 2.0 description `xml`.
///
/// # Errors
/// A message naming what the 2.0 description lacks or holds that 3.0 cannot take.
pub fn fmi3_description(xml: &str) -> Result<String, String> {
    let root = parse(xml)?;
    let mut o = String::new();
    o.push_str("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    o.push_str("<!-- Generated by build.rs from modelDescription/modelDescription.xml (FMI 2.0), the single source of truth. -->\n");
    o.push_str("<fmiModelDescription fmiVersion=\"3.0\"");
    let mut ra = pick(&root, &["modelName"]);
    ra.push((
        "instantiationToken",
        root.attr("guid").ok_or("no guid attribute")?.to_string(),
    ));
    ra.extend(pick(
        &root,
        &[
            "description",
            "author",
            "version",
            "copyright",
            "license",
            "generationTool",
            "generationDateAndTime",
            "variableNamingConvention",
        ],
    ));
    write_attrs(&mut o, &ra);
    o.push_str(">\n");
    let cs = root
        .child("CoSimulation")
        .ok_or("no CoSimulation element")?;
    let flag = |k: &str| cs.attr(k).unwrap_or("false").to_string();
    o.push_str("  <CoSimulation");
    write_attrs(
        &mut o,
        &[
            (
                "modelIdentifier",
                cs.attr("modelIdentifier")
                    .ok_or("no modelIdentifier")?
                    .to_string(),
            ),
            ("needsExecutionTool", flag("needsExecutionTool")),
            (
                "canBeInstantiatedOnlyOncePerProcess",
                flag("canBeInstantiatedOnlyOncePerProcess"),
            ),
            ("canGetAndSetFMUState", flag("canGetAndSetFMUstate")),
            ("canSerializeFMUState", flag("canSerializeFMUstate")),
            ("providesDirectionalDerivative", "false".into()),
            ("providesAdjointDerivatives", "false".into()),
            ("providesPerElementDependencies", "false".into()),
            (
                "canHandleVariableCommunicationStepSize",
                flag("canHandleVariableCommunicationStepSize"),
            ),
            (
                "maxOutputDerivativeOrder",
                cs.attr("maxOutputDerivativeOrder")
                    .unwrap_or("0")
                    .to_string(),
            ),
            ("providesIntermediateUpdate", "false".into()),
            ("mightReturnEarlyFromDoStep", "true".into()),
            ("canReturnEarlyAfterIntermediateUpdate", "false".into()),
            ("hasEventMode", "false".into()),
            ("providesEvaluateDiscreteStates", "false".into()),
        ],
    );
    o.push_str("/>\n");
    if let Some(units) = root.child("UnitDefinitions") {
        o.push_str("  <UnitDefinitions>\n");
        for u in &units.children {
            o.push_str("    <Unit");
            write_attrs(&mut o, &pick(u, &["name"]));
            o.push('>');
            for c in &u.children {
                let keys: &[&'static str] = match c.name.as_str() {
                    "BaseUnit" => &[
                        "kg", "m", "s", "A", "K", "mol", "cd", "rad", "factor", "offset",
                    ],
                    "DisplayUnit" => &["name", "factor", "offset"],
                    other => {
                        return Err(format!(
                            "unit {:?}: unknown element {other}",
                            u.attr("name")
                        ))
                    }
                };
                let _ = write!(o, "<{}", c.name);
                write_attrs(&mut o, &pick(c, keys));
                o.push_str("/>");
            }
            o.push_str("</Unit>\n");
        }
        o.push_str("  </UnitDefinitions>\n");
    }
    let mut enum_types: Vec<String> = Vec::new();
    if let Some(types) = root.child("TypeDefinitions") {
        o.push_str("  <TypeDefinitions>\n");
        for t in &types.children {
            let name = t.attr("name").ok_or("SimpleType without name")?;
            let base = t.children.first().ok_or("SimpleType without type")?;
            match base.name.as_str() {
                "Real" => {
                    o.push_str("    <Float64Type");
                    let mut a = pick(t, &["name", "description"]);
                    a.extend(pick(
                        base,
                        &[
                            "quantity",
                            "unit",
                            "displayUnit",
                            "relativeQuantity",
                            "min",
                            "max",
                            "nominal",
                            "unbounded",
                        ],
                    ));
                    write_attrs(&mut o, &a);
                    o.push_str("/>\n");
                }
                "Enumeration" => {
                    enum_types.push(name.to_string());
                    o.push_str("    <EnumerationType");
                    let mut a = pick(t, &["name", "description"]);
                    a.extend(pick(base, &["quantity"]));
                    write_attrs(&mut o, &a);
                    o.push_str(">\n");
                    for item in &base.children {
                        o.push_str("      <Item");
                        write_attrs(&mut o, &pick(item, &["name", "value", "description"]));
                        o.push_str("/>\n");
                    }
                    o.push_str("    </EnumerationType>\n");
                }
                other => {
                    return Err(format!(
                        "SimpleType {name}: base type {other} is not converted"
                    ))
                }
            }
        }
        o.push_str("  </TypeDefinitions>\n");
    }
    if let Some(cats) = root.child("LogCategories") {
        o.push_str("  <LogCategories>\n");
        for c in &cats.children {
            o.push_str("    <Category");
            write_attrs(&mut o, &pick(c, &["name", "description"]));
            o.push_str("/>\n");
        }
        o.push_str("  </LogCategories>\n");
    }
    if let Some(d) = root.child("DefaultExperiment") {
        o.push_str("  <DefaultExperiment");
        write_attrs(
            &mut o,
            &pick(d, &["startTime", "stopTime", "tolerance", "stepSize"]),
        );
        o.push_str("/>\n");
    }
    let vars = root.child("ModelVariables").ok_or("no ModelVariables")?;
    o.push_str("  <ModelVariables>\n");
    let _ = writeln!(
        o,
        "    <Float64 name=\"time\" valueReference=\"{TIME_VR}\" description=\"Simulation time (the independent variable; FMI 2.0 leaves it implicit)\" causality=\"independent\" variability=\"continuous\" declaredType=\"Time\"/>"
    );
    // 1-based index of the 2.0 description -> value reference
    let mut vr_of_index: Vec<String> = vec![String::new()];
    for v in &vars.children {
        let name = v.attr("name").ok_or("ScalarVariable without name")?;
        let vr = v
            .attr("valueReference")
            .ok_or_else(|| format!("{name}: no valueReference"))?;
        if vr == TIME_VR.to_string() {
            return Err(format!("{name}: value reference {TIME_VR} is the independent variable time of the FMI 3.0 description"));
        }
        if name == "time" {
            return Err("a variable named time clashes with the independent variable of the FMI 3.0 description".into());
        }
        vr_of_index.push(vr.to_string());
        let ty = v
            .children
            .iter()
            .find(|c| c.name != "Annotations")
            .ok_or_else(|| format!("{name}: no type element"))?;
        let (el, keys): (&str, &[&'static str]) = match ty.name.as_str() {
            "Real" => (
                "Float64",
                &[
                    "declaredType",
                    "quantity",
                    "unit",
                    "displayUnit",
                    "relativeQuantity",
                    "min",
                    "max",
                    "nominal",
                    "unbounded",
                    "start",
                ],
            ),
            "Integer" => (
                "Int32",
                &["declaredType", "quantity", "min", "max", "start"],
            ),
            "Boolean" => ("Boolean", &["declaredType", "start"]),
            "Enumeration" => {
                let dt = ty.attr("declaredType").unwrap_or("");
                if !enum_types.iter().any(|t| t == dt) {
                    return Err(format!(
                        "{name}: Enumeration without a declared EnumerationType"
                    ));
                }
                (
                    "Enumeration",
                    &["declaredType", "quantity", "min", "max", "start"],
                )
            }
            other => return Err(format!("{name}: type {other} is not converted")),
        };
        let _ = write!(o, "    <{el}");
        let mut a = pick(
            v,
            &[
                "name",
                "valueReference",
                "description",
                "causality",
                "variability",
                "initial",
            ],
        );
        a.extend(pick(ty, keys));
        write_attrs(&mut o, &a);
        o.push_str("/>\n");
    }
    o.push_str("  </ModelVariables>\n");
    let ms = root.child("ModelStructure").ok_or("no ModelStructure")?;
    let vr_list = |idx: &str, what: &str| -> Result<String, String> {
        idx.split_whitespace()
            .map(|i| {
                i.parse::<usize>()
                    .ok()
                    .and_then(|i| vr_of_index.get(i).filter(|v| !v.is_empty()).cloned())
                    .ok_or_else(|| format!("ModelStructure {what}: no variable of index {i}"))
            })
            .collect::<Result<Vec<_>, _>>()
            .map(|v| v.join(" "))
    };
    o.push_str("  <ModelStructure>\n");
    for (section, el) in [("Outputs", "Output"), ("InitialUnknowns", "InitialUnknown")] {
        for u in ms
            .child(section)
            .map(|s| s.children.as_slice())
            .unwrap_or(&[])
        {
            let idx = u
                .attr("index")
                .ok_or_else(|| format!("{section}: Unknown without index"))?;
            let mut a = vec![("valueReference", vr_list(idx, section)?)];
            if let Some(d) = u.attr("dependencies") {
                a.push(("dependencies", vr_list(d, section)?));
            }
            a.extend(pick(u, &["dependenciesKind"]));
            let _ = write!(o, "    <{el}");
            write_attrs(&mut o, &a);
            o.push_str("/>\n");
        }
    }
    o.push_str("  </ModelStructure>\n</fmiModelDescription>\n");
    Ok(o)
}

#[cfg(test)]
mod tests {
    use super::*;

    const XML: &str = include_str!("../modelDescription/modelDescription.xml");

    /// Every 2.0 variable is in the 3.0 description with its value reference, the
    /// dependencies are value references, and descriptions speak of FMI 3.0 functions.
    #[test]
    fn the_fmi3_description_keeps_every_variable() {
        let x3 = fmi3_description(XML).expect("converts");
        let root2 = parse(XML).unwrap();
        let root3 = parse(&x3).unwrap();
        assert_eq!(root3.attr("fmiVersion"), Some("3.0"));
        assert_eq!(root3.attr("instantiationToken"), root2.attr("guid"));
        let v2 = &root2.child("ModelVariables").unwrap().children;
        let v3 = &root3.child("ModelVariables").unwrap().children;
        assert_eq!(v3.len(), v2.len() + 1);
        assert_eq!(v3[0].attr("causality"), Some("independent"));
        for (a, b) in v2.iter().zip(&v3[1..]) {
            for k in [
                "name",
                "valueReference",
                "causality",
                "variability",
                "initial",
            ] {
                assert_eq!(a.attr(k), b.attr(k), "{k} of {:?}", a.attr("name"));
            }
            let t = &a.children[0];
            for k in ["start", "min", "max", "unit", "displayUnit", "declaredType"] {
                assert_eq!(t.attr(k), b.attr(k), "{k} of {:?}", a.attr("name"));
            }
        }
        let ms2 = root2.child("ModelStructure").unwrap();
        let ms3 = root3.child("ModelStructure").unwrap();
        let outs: Vec<&El> = ms3.children.iter().filter(|c| c.name == "Output").collect();
        assert_eq!(outs.len(), ms2.child("Outputs").unwrap().children.len());
        // T1 depends on T_load (value reference 2) at the same instant
        let t1_vr = v2
            .iter()
            .find(|v| v.attr("name") == Some("T1"))
            .unwrap()
            .attr("valueReference");
        let t1 = outs
            .iter()
            .find(|o| o.attr("valueReference") == t1_vr)
            .unwrap();
        assert_eq!(t1.attr("dependencies"), Some("2"));
        assert!(!x3.contains("fmi2"), "an FMI 2.0 name is left");
    }

    #[test]
    fn a_variable_on_the_time_value_reference_is_refused() {
        let bad = XML.replacen("valueReference=\"2\"", "valueReference=\"0\"", 1);
        let e = fmi3_description(&bad).unwrap_err();
        assert!(e.contains("T_load") && e.contains("independent"), "{e}");
    }
}
