//! Reads the model description (the XML that goes into the .fmu) for the documentation:
//! model attributes, units with display units, simple types and every ScalarVariable with
//! the attributes a reader needs. Whatever variables the XML declares appear in
//! index.html, including ones added later (Enumeration included); nothing here is a copy
//! of the variable list.

use quick_xml::events::{BytesStart, Event};
use quick_xml::Reader;
use std::collections::HashMap;

/// A display unit: `display = factor * value + offset`.
#[derive(Debug, Clone)]
pub struct DisplayUnit {
    pub name: String,
    pub factor: f64,
    pub offset: f64,
}

/// A SimpleType of TypeDefinitions.
#[derive(Debug, Clone, Default)]
pub struct SimpleType {
    /// Real, Integer, Boolean, String or Enumeration.
    pub base: String,
    pub attrs: HashMap<String, String>,
    /// Enumeration items: (value, name, description).
    pub items: Vec<(String, String, String)>,
}

/// One ScalarVariable with its type element's attributes merged over its declared type's.
#[derive(Debug, Clone, Default)]
pub struct ScalarVariable {
    pub attrs: HashMap<String, String>,
    /// Real, Integer, Boolean, String or Enumeration.
    pub base: String,
    /// Type element attributes, completed from the declared type (unit, displayUnit,
    /// min, max, quantity).
    pub ty: HashMap<String, String>,
}

impl ScalarVariable {
    pub fn get(&self, key: &str) -> &str {
        self.attrs.get(key).map(String::as_str).unwrap_or("")
    }
    pub fn ty(&self, key: &str) -> Option<&str> {
        self.ty.get(key).map(String::as_str)
    }
}

/// The parts of modelDescription.xml the documentation shows.
#[derive(Debug, Clone, Default)]
pub struct Description {
    pub model: HashMap<String, String>,
    pub default_experiment: HashMap<String, String>,
    pub units: HashMap<String, Vec<DisplayUnit>>,
    pub types: HashMap<String, SimpleType>,
    pub vars: Vec<ScalarVariable>,
}

impl Description {
    /// Display unit `name` of unit `unit`, if declared.
    pub fn display_unit(&self, unit: &str, name: &str) -> Option<&DisplayUnit> {
        self.units.get(unit)?.iter().find(|d| d.name == name)
    }
}

fn attrs(e: &BytesStart) -> Result<HashMap<String, String>, String> {
    let mut m = HashMap::new();
    for a in e.attributes() {
        let a = a.map_err(|err| format!("malformed attribute: {err}"))?;
        let key = String::from_utf8_lossy(a.key.as_ref()).into_owned();
        let val = a
            .unescape_value()
            .map_err(|err| format!("bad value of {key}: {err}"))?
            .into_owned();
        m.insert(key, val);
    }
    Ok(m)
}

const BASES: [&str; 5] = ["Real", "Integer", "Boolean", "String", "Enumeration"];

/// Parses the model description text.
pub fn parse(xml: &str) -> Result<Description, String> {
    let mut d = Description::default();
    let mut reader = Reader::from_str(xml);
    let mut stack: Vec<String> = Vec::new();
    let mut unit: Option<String> = None;
    let mut simple: Option<(String, SimpleType)> = None;
    let mut var: Option<ScalarVariable> = None;
    loop {
        let ev = reader
            .read_event()
            .map_err(|e| format!("XML error at byte {}: {e}", reader.buffer_position()))?;
        let (e, empty) = match &ev {
            Event::Start(e) => (e.clone(), false),
            Event::Empty(e) => (e.clone(), true),
            Event::End(_) => {
                match stack.pop().as_deref() {
                    Some("ScalarVariable") => d.vars.extend(var.take()),
                    Some("SimpleType") => {
                        if let Some((n, t)) = simple.take() {
                            d.types.insert(n, t);
                        }
                    }
                    Some("Unit") => unit = None,
                    _ => {}
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let name = String::from_utf8_lossy(e.name().as_ref()).into_owned();
        let a = attrs(&e)?;
        let parent = stack.last().map(String::as_str).unwrap_or("");
        match name.as_str() {
            "fmiModelDescription" => d.model = a.clone(),
            "DefaultExperiment" => d.default_experiment = a.clone(),
            "Unit" => {
                let n = a.get("name").cloned().unwrap_or_default();
                d.units.entry(n.clone()).or_default();
                unit = Some(n);
            }
            "DisplayUnit" => {
                if let Some(u) = &unit {
                    let num = |k: &str, dflt: f64| {
                        a.get(k)
                            .map(|v| v.parse::<f64>().map_err(|e| format!("{k}={v}: {e}")))
                            .unwrap_or(Ok(dflt))
                    };
                    let du = DisplayUnit {
                        name: a.get("name").cloned().unwrap_or_default(),
                        factor: num("factor", 1.0)?,
                        offset: num("offset", 0.0)?,
                    };
                    d.units.entry(u.clone()).or_default().push(du);
                }
            }
            "SimpleType" => {
                let n = a.get("name").cloned().unwrap_or_default();
                simple = Some((n, SimpleType::default()));
            }
            "ScalarVariable" => {
                var = Some(ScalarVariable {
                    attrs: a.clone(),
                    ..Default::default()
                });
            }
            "Item" if parent == "Enumeration" => {
                if let Some((_, t)) = simple.as_mut() {
                    t.items.push((
                        a.get("value").cloned().unwrap_or_default(),
                        a.get("name").cloned().unwrap_or_default(),
                        a.get("description").cloned().unwrap_or_default(),
                    ));
                }
            }
            b if BASES.contains(&b) => {
                if parent == "SimpleType" {
                    if let Some((_, t)) = simple.as_mut() {
                        t.base = b.to_string();
                        t.attrs = a.clone();
                    }
                } else if parent == "ScalarVariable" {
                    if let Some(v) = var.as_mut() {
                        v.base = b.to_string();
                        v.ty = a.clone();
                    }
                }
            }
            _ => {}
        }
        if !empty {
            stack.push(name);
        }
    }
    // complete each variable from its declared type (the variable's own attributes win)
    for v in &mut d.vars {
        if let Some(t) = v.ty.get("declaredType").and_then(|n| d.types.get(n)) {
            for (k, val) in &t.attrs {
                v.ty.entry(k.clone()).or_insert_with(|| val.clone());
            }
            if v.base == "Enumeration" && !t.items.is_empty() {
                let vals: Vec<i64> = t.items.iter().filter_map(|i| i.0.parse().ok()).collect();
                if let (Some(lo), Some(hi)) = (vals.iter().min(), vals.iter().max()) {
                    v.ty.entry("min".into()).or_insert_with(|| lo.to_string());
                    v.ty.entry("max".into()).or_insert_with(|| hi.to_string());
                }
            }
        }
    }
    Ok(d)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A variable added later with a declared Enumeration type appears with its items'
    /// range, and a Real inherits unit and display unit from its SimpleType.
    #[test]
    fn enumerations_and_declared_types_are_resolved() {
        let xml = r#"<?xml version="1.0"?>
<fmiModelDescription fmiVersion="2.0" modelName="M" guid="g">
  <UnitDefinitions><Unit name="rad"><BaseUnit rad="1"/><DisplayUnit name="deg" factor="57.29577951308232"/></Unit></UnitDefinitions>
  <TypeDefinitions>
    <SimpleType name="Angle"><Real quantity="Angle" unit="rad" displayUnit="deg"/></SimpleType>
    <SimpleType name="Init"><Enumeration><Item name="rest" value="1"/><Item name="static_equilibrium" value="2"/><Item name="periodic" value="3"/></Enumeration></SimpleType>
  </TypeDefinitions>
  <ModelVariables>
    <ScalarVariable name="beta" valueReference="5" causality="parameter" variability="fixed" initial="exact"><Real declaredType="Angle" start="0.1" max="0.7"/></ScalarVariable>
    <ScalarVariable name="initialization" valueReference="1010" causality="parameter" variability="fixed" initial="exact"><Enumeration declaredType="Init" start="1"/></ScalarVariable>
  </ModelVariables>
</fmiModelDescription>"#;
        let d = parse(xml).unwrap();
        assert_eq!(d.vars.len(), 2);
        let beta = &d.vars[0];
        assert_eq!(beta.ty("unit"), Some("rad"));
        assert_eq!(beta.ty("displayUnit"), Some("deg"));
        assert_eq!(beta.ty("max"), Some("0.7"));
        assert!(d.display_unit("rad", "deg").is_some());
        let init = &d.vars[1];
        assert_eq!(init.base, "Enumeration");
        assert_eq!((init.ty("min"), init.ty("max")), (Some("1"), Some("3")));
        assert_eq!(d.types["Init"].items.len(), 3);
    }
}
