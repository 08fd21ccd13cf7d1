//! The cut block pulled by a fixed amount while the blade crosses it in equal steps: prints
//! blade position, cut length, reaction, opening, bottom lift, and the step's time (s),
//! Newton iterations and factorizations per step; then the largest change of the reaction
//! per step against the mean change, and the steps' median and longest time and their
//! iterations, factorizations and returns to the unloaded block.
//!
//! `cargo run --release -p models --example blade_path -- [PULL] [STEP] [MATERIAL] [ELEMENT]
//! [REFINE] [FROM]` (defaults: 10 mm, 0.5 mm, neo-hookean, tet4, 1, 0 mm: the blade starts
//! at FROM); MATERIAL `accurate` takes the accurate setting (`ACCURATE`, ELEMENT then
//! ignored), its cells × REFINE. Warnings the scene gave are printed at the end.

use std::time::Instant;

use models::scene::cutblock::{CutBlock, Setting};
use models::scene::Scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let number = |i: usize, default: f64| -> Result<f64, String> {
        args.get(i)
            .map_or(Ok(default), |v| v.parse())
            .map_err(|e| format!("argument {i} must be a number: {e}"))
    };
    let (pull, step, refine) = (number(1, 10.0)?, number(2, 0.5)?, number(5, 1.0)?);
    let from = number(6, 0.0)?;
    let material = args.get(3).map_or("neo-hookean", String::as_str);
    let setting = Setting::named(material, args.get(4).map_or("tet4", String::as_str))?;
    let mut s = CutBlock::new();
    let setting = setting.refined(refine);
    setting.apply(&mut s)?;
    s.initialize(0.0)?;
    s.set("pull", pull)?;
    s.set("scalpel_x", from)?;
    s.do_step(0.0, 1.0)?;
    let steps = ((100.0 - from) / step).round() as usize;
    let mut forces = vec![s.get("reaction_force")?];
    let mut times = Vec::with_capacity(steps);
    let total = s.work();
    println!("blade_mm,cut_length_mm,reaction_N,opening_mm,bottom_lift_mm,step_s,iterations,factorizations");
    for k in 1..=steps {
        let x = from + k as f64 * step;
        s.set("scalpel_x", x)?;
        let (start, before) = (Instant::now(), s.work());
        s.do_step(k as f64, 1.0)?;
        times.push(start.elapsed().as_secs_f64());
        let (f, after) = (s.get("reaction_force")?, s.work());
        forces.push(f);
        println!(
            "{x},{},{f:.6},{:.5},{:.5},{:.4},{},{}",
            s.get("cut_length")?,
            s.get("cut_opening")?,
            s.get("bottom_lift")?,
            times[k - 1],
            after.iterations - before.iterations,
            after.factorizations - before.factorizations
        );
    }
    let changes: Vec<f64> = forces.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    let mean = (forces[0] - forces[forces.len() - 1]).abs() / changes.len() as f64;
    let largest = changes.iter().copied().fold(0.0, f64::max);
    eprintln!(
        "reaction {:.5} → {:.5} N; mean change per step {mean:.3e} N, largest {largest:.3e} N ({:.2}×)",
        forces[0],
        forces[forces.len() - 1],
        largest / mean
    );
    times.sort_by(f64::total_cmp);
    let done = s.work();
    if let Some(longest) = times.last() {
        eprintln!(
            "steps: median {:.3} s, longest {longest:.3} s, all {:.1} s",
            times[times.len() / 2],
            times.iter().sum::<f64>(),
        );
        eprintln!(
            "{} Newton iterations (and {} in increments that failed), {} factorizations, \
             {} returns to the unloaded block",
            done.iterations - total.iterations,
            done.failed_iterations - total.failed_iterations,
            done.factorizations - total.factorizations,
            done.returns_to_unloaded - total.returns_to_unloaded
        );
    }
    for w in s.take_warnings() {
        eprintln!("warning: {w}");
    }
    Ok(())
}
