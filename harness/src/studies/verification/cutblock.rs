//! The cut block against seed 002: the comparison, refinement, ν → 0.5, cut strategies and
//! step timings.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::time::Instant;

use anyhow::Result;
use models::scene::cutblock::CutBlock;
use models::scene::Scene;

use crate::sweep::{simulate, InProcess, InputTable, Schedule, Value};

/// The default cut block with `settings` and `strings` applied before initialization,
/// solved for one step of constant `inputs`.
pub fn solved(
    settings: &[(&str, f64)],
    strings: &[(&str, &str)],
    inputs: &[(&str, f64)],
) -> Result<CutBlock> {
    let mut all: Vec<(String, Value)> = settings
        .iter()
        .map(|&(k, v)| (k.to_string(), Value::Real(v)))
        .collect();
    all.extend(
        strings
            .iter()
            .map(|&(k, v)| (k.to_string(), Value::Text(v.to_string()))),
    );
    let inputs: BTreeMap<String, InputTable> = inputs
        .iter()
        .map(|&(k, v)| (k.to_string(), InputTable::constant(v)))
        .collect();
    let schedule = Schedule {
        start_time: 0.0,
        stop_time: 1.0,
        step: 1.0,
        settings: &all,
        inputs: &inputs,
        record: &[],
    };
    let mut s = InProcess(Box::new(CutBlock::new()));
    simulate(&mut s, &schedule)?;
    Ok(*s.0)
}

const CUT_AND_PULL: [(&str, f64); 2] = [("pull", 10.0), ("scalpel_x", 100.0)];

/// Seed 002's model: the linear law (the scene's default is neo-Hookean).
const LINEAR: [(&str, &str); 1] = [("material", "linear")];

/// Writes the section's tables to `out`.
pub fn run(out: &mut String) -> Result<()> {
    writeln!(
        out,"4. Cut block (seed 002): 100 × 80 × 17 mm, 6 × 16 × 14 cubes × 6 tetrahedra, cut at y = 45 mm,")?;
    writeln!(
        out,
        "   8.5 mm deep over the full width, 10 mm pull; E = 0.0385 MPa (displacement loading: the"
    )?;
    writeln!(out, "   displacements below do not depend on E)")?;
    writeln!(
        out,
        "   {:<34} {:>9} {:>10} {:>10} {:>14} {:>10} {:>10}",
        "quantity", "seed 002", "ν = 0.43", "ν = 0.49", "ν = 0.43 grip", "NH 0.43", "NH 0.45"
    )?;
    let neo_hookean = [("material", "neo-hookean"), ("element", "tet10")];
    let mut columns = [
        solved(&[], &LINEAR, &CUT_AND_PULL)?,
        solved(&[("nu", 0.49)], &LINEAR, &CUT_AND_PULL)?,
        solved(&[], &[LINEAR[0], ("support", "gripped")], &CUT_AND_PULL)?,
        solved(&[], &neo_hookean, &CUT_AND_PULL)?,
        solved(&[("nu", 0.45)], &neo_hookean, &CUT_AND_PULL)?,
    ];
    for (name, label, seed) in [
        ("bottom_lift", "bottom lift under the cut (mm)", "2.096"),
        ("x_contraction", "x-displacement at the x-ends (mm)", "6.6"),
        ("cut_opening", "cut opening at the top (mm)", "-"),
        ("reaction_force", "reaction force (N)", "-"),
    ] {
        write!(out, "   {label:<34} {seed:>9}")?;
        for (column, width) in columns.iter_mut().zip([10, 10, 14, 10, 10]) {
            write!(out, " {:>width$.3}", column.get(name)?)?;
        }
        writeln!(out)?;
    }
    writeln!(
        out,
        "   (linear tet4 unless NH: neo-Hookean tet10, ν = 0.45 as fitted to set A; grip: the \
         pulled face also held in x and z, as a rigid clamp would)"
    )?;
    writeln!(out)?;

    writeln!(
        out,
        "   Reaction force (N) under refinement, 10 mm pull (linear tet4):"
    )?;
    writeln!(
        out,
        "   {:>8} {:>10} {:>12} {:>12}",
        "cells ×", "tets", "uncut", "cut"
    )?;
    for m in [0.5, 1.0, 2.0] {
        let cells = [
            ("cells_x", 6.0 * m),
            ("cells_y", 16.0 * m),
            ("cells_z", 14.0 * m),
        ];
        let mut uncut_settings = cells.to_vec();
        uncut_settings.push(("cut_depth", 0.0));
        let mut uncut = solved(&uncut_settings, &LINEAR, &CUT_AND_PULL)?;
        let mut cut = solved(&cells, &LINEAR, &CUT_AND_PULL)?;
        let tets = cut.field().map_or(0, |(solid, _)| solid.len());
        writeln!(
            out,
            "   {m:>8} {tets:>10} {:>12.4} {:>12.4}",
            uncut.get("reaction_force")?,
            cut.get("reaction_force")?
        )?;
    }
    writeln!(out)?;

    writeln!(
        out,
        "   Reaction force (N) as ν → 0.5 (linear tetrahedra lock: the force keeps rising):"
    )?;
    for nu in [0.3, 0.43, 0.49, 0.499, 0.4999] {
        let mut s = solved(&[("nu", nu)], &LINEAR, &CUT_AND_PULL)?;
        writeln!(out, "   ν = {nu:<8} {:>10.4}", s.get("reaction_force")?)?;
    }
    writeln!(out)?;

    writeln!(
        out,
        "   Cut strategies (linear tet4, default block, full cut, 10 mm pull):"
    )?;
    for strategy in ["duplicate", "delete"] {
        let mut s = solved(&[], &[LINEAR[0], ("cut_strategy", strategy)], &CUT_AND_PULL)?;
        writeln!(
            out,
            "   {strategy:<10} reaction {:>8.4} N, opening {:>7.3} mm, bottom lift {:>7.3} mm",
            s.get("reaction_force")?,
            s.get("cut_opening")?,
            s.get("bottom_lift")?
        )?;
    }
    writeln!(out)?;

    // The median of 20 steps, the value of `name` at step i being `value(i)`.
    let time = |s: &mut CutBlock, name: &str, value: &dyn Fn(f64) -> f64| -> Result<f64> {
        let mut t = Vec::new();
        for i in 0..20 {
            s.set(name, value(f64::from(i)))?;
            let start = Instant::now();
            s.do_step(0.0, 1.0)?;
            t.push(start.elapsed().as_secs_f64() * 1e3);
        }
        t.sort_by(f64::total_cmp);
        Ok(t[t.len() / 2])
    };
    let alternate = |a: f64, b: f64| move |i: f64| if i % 2.0 == 0.0 { a } else { b };
    writeln!(out, "   step timings (median of 20; blade at 50 mm, pull 5 ↔ 10 mm, E 0.04 ↔ 0.0385 MPa, then the blade advanced 1 mm per step at a 10 mm pull):")?;
    for law in ["linear", "neo-hookean"] {
        let mut s = solved(&[], &[("material", law)], &[("scalpel_x", 50.0)])?;
        writeln!(
            out,
            "   {law:<12} tet4: load only {:.3} ms, E changed {:.3} ms, blade advanced 1 mm {:.3} ms",
            time(&mut s, "pull", &alternate(5.0, 10.0))?,
            time(&mut s, "E", &alternate(0.04, 0.0385))?,
            time(&mut s, "scalpel_x", &|i| 51.0 + i)?
        )?;
    }
    Ok(())
}
