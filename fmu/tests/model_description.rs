//! The generated model descriptions agree with the variable tables the binary uses: every
//! variable appears with the value reference, causality and start value the instance uses.

use fmu::addressing::{fmi2_scalars, time_vr};
use fmu::exports::EXPORTS;
use fmu::xml;
use models::scene::Start;

#[test]
fn fmi2_description_lists_every_scalar_with_its_reference_and_start() {
    for model in &EXPORTS {
        let text = xml::fmi2(model);
        let scene = (model.create)();
        let scalars = fmi2_scalars(scene.variables());
        assert_eq!(text.matches("<ScalarVariable ").count(), scalars.len());
        for (i, s) in scalars.iter().enumerate() {
            let v = &scene.variables()[s.scene_vr as usize];
            let tag = format!(r#"name="{}" valueReference="{i}""#, s.name);
            let at = text
                .find(&tag)
                .unwrap_or_else(|| panic!("{}: {tag}", model.identifier));
            let line = &text[at..at + text[at..].find('\n').unwrap()];
            match &v.start {
                Start::Real(x) => assert!(line.contains(&format!(r#"start="{x:?}""#)), "{line}"),
                Start::String(x) => {
                    assert!(line.contains(&format!(r#"<String start="{x}""#)), "{line}")
                }
                Start::None => assert!(
                    line.contains(r#"initial="calculated""#) && !line.contains("start="),
                    "{line}"
                ),
            }
        }
        assert!(text.contains(&format!(r#"guid="{}""#, model.token())));
    }
}

#[test]
fn fmi3_description_uses_scene_references_and_arrays() {
    for model in &EXPORTS {
        let text = xml::fmi3(model);
        let scene = (model.create)();
        for v in scene.variables() {
            let tag = format!(r#"name="{}" valueReference="{}""#, v.name, v.vr);
            assert!(text.contains(&tag), "{}: {tag}", model.identifier);
            if v.len > 1 {
                let at = text.find(&tag).unwrap();
                let line = &text[at..at + text[at..].find('\n').unwrap()];
                assert!(
                    line.contains(&format!(r#"<Dimension start="{}"/>"#, v.len)),
                    "{line}"
                );
            }
        }
        let time = format!(
            r#"name="time" valueReference="{}" causality="independent""#,
            time_vr(scene.variables())
        );
        assert!(text.contains(&time));
    }
}

/// The token covers every field of the variable table: a description whose start values,
/// ranges, units or descriptions differ from the binary's gets another token, and the
/// generated descriptions carry the token the binary accepts.
#[test]
fn tokens_cover_the_whole_variable_table_and_the_descriptions_carry_them() {
    assert_ne!(EXPORTS[0].token(), EXPORTS[1].token());
    let scene = (EXPORTS[1].create)();
    let table = scene.variables().to_vec();
    let base = fmu::exports::token("cutblock", &table);
    assert_eq!(base, EXPORTS[1].token());
    let nu = table.iter().position(|v| v.name == "nu").unwrap();
    let changes: [fn(&mut models::scene::Variable); 5] = [
        |v| v.start = models::scene::Start::Real(0.3),
        |v| v.max = 0.49,
        |v| v.min = 0.0,
        |v| v.unit = "MPa",
        |v| v.description.push('.'),
    ];
    for (k, change) in changes.iter().enumerate() {
        let mut changed = table.clone();
        change(&mut changed[nu]);
        assert_ne!(
            fmu::exports::token("cutblock", &changed),
            base,
            "change {k}"
        );
    }
    for model in &EXPORTS {
        let token = model.token();
        assert!(xml::fmi2(model).contains(&format!("guid=\"{token}\"")));
        assert!(xml::fmi3(model).contains(&format!("instantiationToken=\"{token}\"")));
    }
}
