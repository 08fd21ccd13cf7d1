//! The generated model descriptions agree with the variable tables the binary uses: every
//! variable appears with the value reference, causality and start value the instance uses.

use fmu::instance::{fmi2_scalars, time_vr};
use fmu::model::MODELS;
use fmu::xml;
use models::scene::Start;

#[test]
fn fmi2_description_lists_every_scalar_with_its_reference_and_start() {
    for model in &MODELS {
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
    for model in &MODELS {
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

#[test]
fn tokens_differ_between_models_and_are_stable() {
    assert_ne!(MODELS[0].token(), MODELS[1].token());
    assert_eq!(MODELS[0].token(), MODELS[0].token());
}
