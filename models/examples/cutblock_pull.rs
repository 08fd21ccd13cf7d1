//! The default cut block, fully cut, pulled 0 → 10 mm in one step (load increments of
//! `max_increment`):
//! prints the time, the reaction, and the solver's work (increments, Newton iterations,
//! factorizations, assembly / factorization / solve time). The timing companion of the
//! `pull_to_10mm` benchmark.
//!
//! `cargo run --release -p models --example cutblock_pull -- [MATERIAL] [ELEMENT] [REFINE]
//! [MAX_INCREMENT]` (defaults: neo-hookean tet10 1 and the scene's `max_increment`; REFINE
//! multiplies the cells along each axis), or `-- accurate [REFINE] [MAX_INCREMENT]` for the
//! accurate setting (`ACCURATE`: its cells × REFINE).

use std::time::Instant;

use models::scene::cutblock::{CutBlock, Setting};
use models::scene::Scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let material = args.first().map_or("neo-hookean", String::as_str);
    let setting = Setting::named(material, args.get(1).map_or("tet10", String::as_str))?;
    let rest = match material {
        "accurate" => args.get(1..),
        _ => args.get(2..),
    }
    .unwrap_or_default();
    let refine: f64 = rest
        .first()
        .map_or(Ok(1.0), |v| v.parse())
        .map_err(|e| format!("REFINE must be a number: {e}"))?;
    let max_increment: Option<f64> = rest
        .get(1)
        .map(|v| v.parse())
        .transpose()
        .map_err(|e| format!("MAX_INCREMENT must be a number: {e}"))?;
    let mut s = CutBlock::new();
    if let Some(m) = max_increment {
        s.set("max_increment", m)?;
    }
    let setting = setting.refined(refine);
    setting.apply(&mut s)?;
    let start = Instant::now();
    s.initialize(0.0)?;
    s.set("scalpel_x", 100.0)?;
    s.do_step(0.0, 1.0)?;
    let setup = start.elapsed();
    let (before, before_timing) = (s.work(), s.timing());
    s.set("pull", 10.0)?;
    let start = Instant::now();
    s.do_step(1.0, 1.0)?;
    let pull = start.elapsed();
    let (w, timing) = (s.work(), s.timing());
    let dofs = s.field().map_or(0, |(solid, _)| solid.n_dofs());
    let [x, y, z] = setting.cells;
    println!(
        "{} {}, {x} × {y} × {z} cubes β = {}, {dofs} dofs:",
        setting.law.name(),
        setting.element.name(),
        setting.grading
    );
    println!("set-up and cut {setup:.2?}, pull 0 → 10 mm {pull:.2?}");
    println!("reaction at 10 mm: {:.4} N", s.get("reaction_force")?);
    let increments = w.increments - before.increments;
    let iterations = w.iterations - before.iterations;
    println!(
        "{increments} increments, {iterations} Newton iterations ({:.1} per increment), {} factorizations",
        iterations as f64 / increments.max(1) as f64,
        w.factorizations - before.factorizations
    );
    println!(
        "assembly {:.2?}, factorization {:.2?}, solve {:.2?}",
        timing.assembly - before_timing.assembly,
        timing.factorization - before_timing.factorization,
        timing.solve - before_timing.solve
    );
    Ok(())
}
