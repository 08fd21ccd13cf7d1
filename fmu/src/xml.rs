//! `modelDescription.xml` for FMI 2.0 and FMI 3.0, generated from a scene's variable table —
//! the same table the instance uses at run time, so the two cannot drift apart.

use std::fmt::Write;

use models::scene::{outputs, Causality, Start, Variable, VariableKind};

use crate::addressing::{fmi2_scalars, time_vr};
use crate::exports::Export;

/// Base-unit exponents and factor of every unit the scenes use (SI base: kg, m, s).
fn base_unit(unit: &str) -> Option<&'static str> {
    Some(match unit {
        "mm" => r#"m="1" factor="0.001""#,
        "mm2" => r#"m="2" factor="1e-06""#,
        "MPa" => r#"kg="1" m="-1" s="-2" factor="1000000""#,
        "N" => r#"kg="1" m="1" s="-2""#,
        "N/mm" => r#"kg="1" s="-2" factor="1000""#,
        "Hz" | "1/s" => r#"s="-1""#,
        "s" => r#"s="1""#,
        "t/mm3" => r#"kg="1" m="-3" factor="1e+12""#,
        _ => return None,
    })
}

/// Escapes text for an XML attribute.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A number as XML wants it (shortest round-trip form).
fn num(x: f64) -> String {
    format!("{x:?}")
}

/// Unit definitions for every unit the variables use, plus `extra` ones; for FMI 3 also a
/// `Float64Type` per unit, named after it.
fn units(vars: &[Variable], extra: &[&'static str], types: bool) -> String {
    let mut names: Vec<&str> = vars
        .iter()
        .map(|v| v.unit)
        .chain(extra.iter().copied())
        .filter(|u| base_unit(u).is_some())
        .collect();
    names.sort_unstable();
    names.dedup();
    let mut s = String::from("  <UnitDefinitions>\n");
    for u in &names {
        let _ = writeln!(
            s,
            r#"    <Unit name="{}"><BaseUnit {}/></Unit>"#,
            esc(u),
            base_unit(u).unwrap_or_default()
        );
    }
    s += "  </UnitDefinitions>\n";
    if types {
        s += "  <TypeDefinitions>\n";
        for u in &names {
            let _ = writeln!(s, r#"    <Float64Type name="{0}" unit="{0}"/>"#, esc(u));
        }
        s += "  </TypeDefinitions>\n";
    }
    s
}

/// How a real variable names its unit: FMI 2 directly (`unit`), FMI 3 through a type
/// definition named after the unit (`declaredType`), which every importer we tried reads
/// (the `fmi` crate's FMI 3 schema has no `unit` attribute on variables).
#[derive(Clone, Copy)]
enum UnitAttribute {
    Unit,
    DeclaredType,
}

/// unit, min and max attributes of a real variable.
fn real_attributes(v: &Variable, unit: UnitAttribute) -> String {
    let mut a = String::new();
    if base_unit(v.unit).is_some() {
        let key = match unit {
            UnitAttribute::Unit => "unit",
            UnitAttribute::DeclaredType => "declaredType",
        };
        let _ = write!(a, r#" {key}="{}""#, esc(v.unit));
    }
    if v.causality != Causality::Output {
        if v.min.is_finite() {
            let _ = write!(a, r#" min="{}""#, num(v.min));
        }
        if v.max.is_finite() {
            let _ = write!(a, r#" max="{}""#, num(v.max));
        }
    }
    a
}

/// FMI 2 `initial` attribute (none for inputs).
fn initial(v: &Variable) -> &'static str {
    match v.causality {
        Causality::Parameter => r#" initial="exact""#,
        Causality::Input => "",
        Causality::Output => r#" initial="calculated""#,
    }
}

const LOG_CATEGORIES: &str = "  <LogCategories>\n    <Category name=\"logStatusError\" description=\"errors, with the variable or cause\"/>\n    <Category name=\"logStatusWarning\" description=\"where an input takes the model beyond what it is valid for (strain, mesh)\"/>\n    <Category name=\"logCalls\" description=\"every FMI call and model build\"/>\n  </LogCategories>\n";

fn header(model: &Export, version: &str, token_attribute: &str) -> String {
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<fmiModelDescription fmiVersion=\"{version}\" modelName=\"{id}\" {token_attribute}=\"{token}\" description=\"{desc}\" generationTool=\"tissuefmu {tool}\" variableNamingConvention=\"structured\">\n",
        id = model.identifier,
        token = model.token(),
        desc = esc(model.description),
        tool = env!("CARGO_PKG_VERSION"),
    )
}

fn default_experiment(model: &Export) -> String {
    format!(
        "  <DefaultExperiment startTime=\"0.0\" stopTime=\"{}\" stepSize=\"{}\"/>\n",
        num(model.stop_time),
        num(model.step_size)
    )
}

/// The FMI 2.0 co-simulation model description. Arrays appear as indexed scalars
/// `name[i]`, numbered consecutively.
pub fn fmi2(model: &Export) -> String {
    let scene = (model.create)();
    let vars = scene.variables();
    let mut s = header(model, "2.0", "guid");
    let _ = writeln!(
        s,
        r#"  <CoSimulation modelIdentifier="{}" canHandleVariableCommunicationStepSize="true" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="true" canSerializeFMUstate="true"/>"#,
        model.identifier
    );
    s += &units(vars, &[], false);
    s += LOG_CATEGORIES;
    s += &default_experiment(model);
    s += "  <ModelVariables>\n";
    let scalars = fmi2_scalars(vars);
    let mut outputs = Vec::new();
    for (i, sc) in scalars.iter().enumerate() {
        let v = &vars[sc.scene_vr as usize];
        let _ = write!(
            s,
            r#"    <ScalarVariable name="{}" valueReference="{i}" causality="{}" variability="{}"{} description="{}">"#,
            esc(&sc.name),
            v.causality.name(),
            v.variability.name(),
            initial(v),
            esc(&v.description)
        );
        match (&v.kind, &v.start) {
            (VariableKind::String, Start::String(x)) => {
                let _ = write!(s, r#"<String start="{}"/>"#, esc(x));
            }
            (VariableKind::Real, Start::Real(x)) => {
                let _ = write!(
                    s,
                    r#"<Real start="{}"{}/>"#,
                    num(*x),
                    real_attributes(v, UnitAttribute::Unit)
                );
            }
            _ => {
                let _ = write!(s, r#"<Real{}/>"#, real_attributes(v, UnitAttribute::Unit));
            }
        }
        s += "</ScalarVariable>\n";
        if v.causality == Causality::Output {
            outputs.push(i + 1);
        }
    }
    s += "  </ModelVariables>\n  <ModelStructure>\n    <Outputs>\n";
    for i in &outputs {
        let _ = writeln!(s, r#"      <Unknown index="{i}"/>"#);
    }
    s += "    </Outputs>\n    <InitialUnknowns>\n";
    for i in &outputs {
        let _ = writeln!(s, r#"      <Unknown index="{i}"/>"#);
    }
    s + "    </InitialUnknowns>\n  </ModelStructure>\n</fmiModelDescription>\n"
}

/// The FMI 3.0 co-simulation model description. Value references are the scene's; arrays
/// are arrays (`<Dimension start="n"/>`); `time` is the independent variable.
pub fn fmi3(model: &Export) -> String {
    let scene = (model.create)();
    let vars = scene.variables();
    let mut s = header(model, "3.0", "instantiationToken");
    let _ = writeln!(
        s,
        r#"  <CoSimulation modelIdentifier="{}" canHandleVariableCommunicationStepSize="true" canGetAndSetFMUState="true" canSerializeFMUState="true" hasEventMode="false" providesIntermediateUpdate="false"/>"#,
        model.identifier
    );
    s += &units(vars, &["s"], true); // `s` is the unit of `time`
    s += LOG_CATEGORIES;
    s += &default_experiment(model);
    s += "  <ModelVariables>\n";
    let _ = writeln!(
        s,
        r#"    <Float64 name="time" valueReference="{}" causality="independent" variability="continuous" declaredType="s" description="simulation time"/>"#,
        time_vr(vars)
    );
    for v in vars {
        let common = format!(
            r#"name="{}" valueReference="{}" causality="{}" variability="{}"{} description="{}""#,
            esc(&v.name),
            v.vr,
            v.causality.name(),
            v.variability.name(),
            initial(v),
            esc(&v.description)
        );
        match (&v.kind, &v.start) {
            (VariableKind::String, Start::String(x)) => {
                let _ = writeln!(
                    s,
                    r#"    <String {common}><Start value="{}"/></String>"#,
                    esc(x)
                );
            }
            (VariableKind::Real, Start::Real(x)) => {
                let _ = writeln!(
                    s,
                    r#"    <Float64 {common} start="{}"{}/>"#,
                    num(*x),
                    real_attributes(v, UnitAttribute::DeclaredType)
                );
            }
            _ if v.len > 1 => {
                let _ = writeln!(
                    s,
                    r#"    <Float64 {common}{}><Dimension start="{}"/></Float64>"#,
                    real_attributes(v, UnitAttribute::DeclaredType),
                    v.len
                );
            }
            _ => {
                let _ = writeln!(
                    s,
                    r#"    <Float64 {common}{}/>"#,
                    real_attributes(v, UnitAttribute::DeclaredType)
                );
            }
        }
    }
    s += "  </ModelVariables>\n  <ModelStructure>\n";
    for v in outputs(vars) {
        let _ = writeln!(s, r#"    <Output valueReference="{}"/>"#, v.vr);
    }
    for v in outputs(vars) {
        let _ = writeln!(s, r#"    <InitialUnknown valueReference="{}"/>"#, v.vr);
    }
    s + "  </ModelStructure>\n</fmiModelDescription>\n"
}
