//! Speed versus error for the cut block (issue #11): each model — material law × element ×
//! mesh — runs the default test (full-width cut, 10 mm pull) and is compared with a
//! reference model (neo-Hookean tet10 on twice the cells along each axis): reaction force,
//! bottom lift and the top-surface profile along x = 50 mm, against its run time (set-up,
//! cut and pull, through the simulation loop). Cases run one after another so that their
//! times do not share the cores.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use models::scene::cutblock::PROFILE_STATIONS;
use models::scene::Scene;

use super::verification::cutblock::solved;

/// A model of the cut block: law, element and mesh refinement (cells × `refine` per axis).
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    pub material: &'static str,
    pub element: &'static str,
    pub refine: u32,
}

impl std::fmt::Display for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {} ×{}", self.material, self.element, self.refine)
    }
}

/// What a model answers at 10 mm pull and how long it took.
#[derive(Debug, Clone)]
pub struct Answer {
    pub reaction: f64,
    pub bottom_lift: f64,
    /// Top-surface heights along x = 50 mm (NaN where there is no surface).
    pub profile: Vec<f64>,
    pub seconds: f64,
}

/// One case: a model with its answer, or the error that stopped it.
#[derive(Debug, Clone)]
pub struct Case {
    pub model: Model,
    pub outcome: Result<Answer, String>,
}

/// Errors of a case against the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Errors {
    /// |F − F_ref| / F_ref.
    pub reaction: f64,
    /// |lift − lift_ref| / lift_ref.
    pub bottom_lift: f64,
    /// Largest |z − z_ref| (mm) over the stations where both have a surface.
    pub profile: f64,
}

impl Errors {
    /// The error the Pareto front is drawn for: the larger relative error of the two
    /// scalar outputs.
    pub fn combined(&self) -> f64 {
        self.reaction.max(self.bottom_lift)
    }
}

/// The study: the mesh (cells per axis at refine = 1), the models and the reference.
#[derive(Debug, Clone)]
pub struct Study {
    pub cells: [u32; 3],
    pub models: Vec<Model>,
    pub reference: Model,
}

impl Default for Study {
    /// {linear, neo-Hookean, StVK} × {tet4, tet10} × {1×, 2×} on the default block against
    /// neo-Hookean tet10 at 2×.
    fn default() -> Self {
        let mut models = Vec::new();
        for refine in [1, 2] {
            for element in ["tet4", "tet10"] {
                for material in ["linear", "neo-hookean", "stvk"] {
                    models.push(Model {
                        material,
                        element,
                        refine,
                    });
                }
            }
        }
        Self {
            cells: [6, 16, 14],
            models,
            reference: Model {
                material: "neo-hookean",
                element: "tet10",
                refine: 2,
            },
        }
    }
}

impl Study {
    /// The quick report's study: the three laws with tet4 on the default mesh against
    /// neo-Hookean tet10 on the same mesh (itself not mesh-converged: the full study
    /// measures it against twice the cells).
    pub fn quick() -> Self {
        let at_1x = |material, element| Model {
            material,
            element,
            refine: 1,
        };
        let reference = at_1x("neo-hookean", "tet10");
        Self {
            cells: [6, 16, 14],
            models: vec![
                at_1x("linear", "tet4"),
                at_1x("neo-hookean", "tet4"),
                at_1x("stvk", "tet4"),
                reference.clone(),
            ],
            reference,
        }
    }
}

/// Runs `model` on the block with `cells` at refine 1: full cut and 10 mm pull in one step.
pub fn run(cells: [u32; 3], model: &Model) -> Result<Answer> {
    let start = Instant::now();
    let cells: Vec<(&str, f64)> = ["cells_x", "cells_y", "cells_z"]
        .into_iter()
        .zip(cells.map(|c| f64::from(c * model.refine)))
        .collect();
    let strings = [("material", model.material), ("element", model.element)];
    let mut s = solved(&cells, &strings, &[("pull", 10.0), ("scalpel_x", 100.0)])?;
    let seconds = start.elapsed().as_secs_f64();
    let mut profile = vec![0.0; PROFILE_STATIONS];
    s.get_real(s.lookup("profile_x50")?, &mut profile)?;
    Ok(Answer {
        reaction: s.get("reaction_force")?,
        bottom_lift: s.get("bottom_lift")?,
        profile,
        seconds,
    })
}

/// Runs every model of `study` (the reference among them or separately), one after another;
/// `progress(k, n, model)` is called before each. Returns the cases and the reference's
/// answer.
pub fn measure(
    study: &Study,
    progress: &dyn Fn(usize, usize, &Model),
) -> Result<(Vec<Case>, Answer)> {
    let n = study.models.len() + usize::from(!study.models.contains(&study.reference));
    let mut cases = Vec::new();
    for (k, model) in study.models.iter().enumerate() {
        progress(k, n, model);
        let outcome = run(study.cells, model).map_err(|e| format!("{e:#}"));
        cases.push(Case {
            model: model.clone(),
            outcome,
        });
    }
    let reference = match cases.iter().find(|c| c.model == study.reference) {
        Some(c) => c.outcome.clone().map_err(anyhow::Error::msg),
        None => {
            progress(n - 1, n, &study.reference);
            run(study.cells, &study.reference)
        }
    }
    .with_context(|| format!("the reference model ({})", study.reference))?;
    Ok((cases, reference))
}

/// The errors of `answer` against `reference`.
pub fn errors(answer: &Answer, reference: &Answer) -> Errors {
    let profile = answer
        .profile
        .iter()
        .zip(&reference.profile)
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    Errors {
        reaction: ((answer.reaction - reference.reaction) / reference.reaction).abs(),
        bottom_lift: ((answer.bottom_lift - reference.bottom_lift) / reference.bottom_lift).abs(),
        profile,
    }
}

/// Writes the cases as CSV to `path` (atomically); failed cases keep their message.
pub fn write_csv(cases: &[Case], reference: &Answer, path: &Path) -> Result<PathBuf> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "material",
        "element",
        "refine",
        "run_s",
        "reaction_N",
        "bottom_lift_mm",
        "reaction_error",
        "bottom_lift_error",
        "profile_x50_deviation_mm",
        "failure",
    ])?;
    for c in cases {
        let m = &c.model;
        let mut row = vec![m.material.into(), m.element.into(), m.refine.to_string()];
        match &c.outcome {
            Ok(a) => {
                let e = errors(a, reference);
                row.extend([
                    format!("{:.3}", a.seconds),
                    format!("{:.6}", a.reaction),
                    format!("{:.6}", a.bottom_lift),
                    format!("{:.4e}", e.reaction),
                    format!("{:.4e}", e.bottom_lift),
                    format!("{:.4e}", e.profile),
                    String::new(),
                ]);
            }
            Err(message) => {
                row.extend(std::iter::repeat_n(String::new(), 6));
                row.push(message.clone());
            }
        }
        w.write_record(&row)?;
    }
    crate::atomic::write_atomic(path, &w.into_inner()?)?;
    Ok(path.to_path_buf())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A coarse block (3 × 8 × 7 cells) with the reference at 2×: the reference's own case
    /// has zero error; at the reference's mesh, the linear law is more than three times
    /// further from it than St. Venant–Kirchhoff in the combined error and the profile
    /// (12.5 % nominal strain: a model-form error, not a mesh one; measured 1.30 vs 0.36
    /// and 4.6 vs 0.32 mm — the linear reaction alone lands within 0.1 % by accident while
    /// its bottom lift is 130 % off); every error is finite and the CSV has a row per case.
    #[test]
    fn the_reference_matches_itself_and_the_linear_law_is_furthest() {
        let reference = Model {
            material: "neo-hookean",
            element: "tet10",
            refine: 2,
        };
        let at_2x = |material| Model {
            material,
            element: "tet10",
            refine: 2,
        };
        let study = Study {
            cells: [3, 8, 7],
            models: vec![
                Model {
                    material: "neo-hookean",
                    element: "tet4",
                    refine: 1,
                },
                at_2x("linear"),
                at_2x("stvk"),
                reference.clone(),
            ],
            reference,
        };
        let (cases, reference) = measure(&study, &|_, _, _| {}).unwrap();
        let e: Vec<Errors> = cases
            .iter()
            .map(|c| errors(c.outcome.as_ref().unwrap(), &reference))
            .collect();
        println!("{e:?}");
        assert_eq!(e[3].combined(), 0.0);
        assert_eq!(e[3].profile, 0.0);
        assert!(e[1].combined() > 3.0 * e[2].combined(), "{e:?}");
        assert!(e[1].profile > 3.0 * e[2].profile, "{e:?}");
        assert!(e
            .iter()
            .all(|e| e.combined().is_finite() && e.profile.is_finite()));
        let dir = tempfile::tempdir().unwrap();
        let path = write_csv(&cases, &reference, &dir.path().join("cut.csv")).unwrap();
        let text = std::fs::read_to_string(path).unwrap();
        assert_eq!(text.lines().count(), 1 + cases.len());
    }
}
