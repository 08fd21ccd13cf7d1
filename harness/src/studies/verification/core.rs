//! The FE-core verification report: what the core computes, how accurately, how fast.

use std::fmt::Write as _;
use std::time::{Duration, Instant};

use anyhow::Result;
use models::assembly::{plane, tetrahedra};
use models::element::Elastic;
use models::linalg::{Factorization, Ordering};
use models::solve::{Damping, IntegratorKind, Statics};
use models::verify::{lame::Lame, oscillator, problems};

/// Prints the three tables.
pub fn run(out: &mut String) -> Result<()> {
    writeln!(out, "tissuefmu FE-core verification report\n")?;
    convergence(out)?;
    spectral(out)?;
    timings(out)?;
    Ok(())
}

fn convergence(out: &mut String) -> Result<()> {
    writeln!(
        out,
        "1. Lamé cylinder (a = 10 mm, b = 20 mm, p = 0.1 MPa, E = 1 MPa, ν = 0.3), plane strain"
    )?;
    writeln!(
        out,
        "   {:>6} {:>10} {:>14} {:>8}",
        "nr", "triangles", "L2 rel error", "rate"
    )?;
    let lame = Lame {
        a: 10.0,
        b: 20.0,
        p: 0.1,
        material: Elastic::new("m", 1.0, 0.3)?,
    };
    let mut previous: Option<f64> = None;
    for n in [4, 8, 16, 32, 64] {
        let s = lame.solve(n, 2 * n)?;
        let rate = previous.map_or(String::from("-"), |p| {
            format!("{:.3}", (p / s.l2_error).log2())
        });
        writeln!(
            out,
            "   {n:>6} {:>10} {:>14.4e} {rate:>8}",
            s.triangles, s.l2_error
        )?;
        previous = Some(s.l2_error);
    }
    writeln!(out)?;
    Ok(())
}

fn spectral(out: &mut String) -> Result<()> {
    writeln!(
        out,
        "2. Houbolt on the undamped oscillator: theory (characteristic equation) vs measured"
    )?;
    writeln!(
        out,
        "   {:>6} {:>12} {:>12} {:>12} {:>12}",
        "dt/T", "PE theory", "PE measured", "AD theory", "AD measured"
    )?;
    for ratio in [0.01, 0.05, 0.1, 0.2] {
        let t = oscillator::houbolt_theory(ratio);
        let m = oscillator::measure(IntegratorKind::Houbolt, ratio, 14)?;
        writeln!(
            out,
            "   {ratio:>6} {:>11.2}% {:>11.2}% {:>11.2}% {:>11.2}%",
            100.0 * t.period_elongation,
            100.0 * m.period_elongation,
            100.0 * t.amplitude_decay,
            100.0 * m.amplitude_decay
        )?;
    }
    writeln!(
        out,
        "   (PE: period elongation, AD: amplitude decay per cycle)\n"
    )?;
    Ok(())
}

/// Median wall time of `runs` calls of `f`.
fn median(runs: usize, mut f: impl FnMut()) -> Duration {
    let mut t: Vec<Duration> = (0..runs)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed()
        })
        .collect();
    t.sort();
    t[runs / 2]
}

fn row(out: &mut String, what: &str, d: Duration) -> Result<()> {
    writeln!(out, "   {what:<52} {:>10.3} ms", d.as_secs_f64() * 1e3)?;
    Ok(())
}

fn timings(out: &mut String) -> Result<()> {
    writeln!(out, "3. Timings (median of repeated runs, one core)")?;
    let p = problems::plane(60, 50)?;
    let a = p.assemble();
    writeln!(
        out,
        "   2D: {} triangles + {} line elements, {} dofs",
        p.mesh.triangles().len(),
        p.mesh.lines().len(),
        p.mesh.n_dofs()
    )?;
    let mut k = a.asm.zeros();
    row(
        out,
        "stiffness assembly (pattern reused)",
        median(30, || plane::stiffness(&p.mesh, &a.asm, &p.props, &mut k)),
    )?;
    let s = a.structure(
        &p.fixed,
        Damping {
            alpha: 1.0,
            beta: 1e-4,
        },
        Factorization::Simplicial,
    )?;
    row(
        out,
        "symbolic analysis (AMD, simplicial)",
        median(10, || drop(s.analyze())),
    )?;
    let mut h = IntegratorKind::Houbolt.create();
    h.prepare(&s, 1e-3)?;
    let mut load = |t: f64, f: &mut [f64]| f.fill(1e-3 * (10.0 * t).sin());
    h.start(&s, 0.0, &vec![0.0; s.n()], &vec![0.0; s.n()], &mut load)?;
    for _ in 0..3 {
        h.step(&s, &mut load)?; // past the two starting steps
    }
    row(
        out,
        "Houbolt effective matrix: numeric refactorization",
        median(10, || h.prepare(&s, 1e-3).expect("factorizes")),
    )?;
    let mut dt = 1e-3;
    row(
        out,
        "new dt: Houbolt + Newmark-starter refactorizations",
        median(10, || {
            dt = if dt == 1e-3 { 2e-3 } else { 1e-3 };
            h.prepare(&s, dt).expect("factorizes");
        }),
    )?;
    h.prepare(&s, 1e-3)?;
    let mut load = |t: f64, f: &mut [f64]| f.fill(1e-3 * (10.0 * t).sin());
    h.start(&s, 0.0, &vec![0.0; s.n()], &vec![0.0; s.n()], &mut load)?;
    row(
        out,
        "Houbolt step (Rayleigh damping, one solve)",
        median(200, || h.step(&s, &mut load).expect("steps")),
    )?;
    let b = problems::block([6, 16, 14], 10.0)?;
    let ba = b.assemble();
    writeln!(
        out,
        "   3D: {} tetrahedra, {} dofs",
        b.mesh.tets().len(),
        b.mesh.n_dofs()
    )?;
    let mut k = ba.asm.zeros();
    row(
        out,
        "stiffness assembly (pattern reused)",
        median(20, || {
            tetrahedra::stiffness(&b.mesh, &ba.asm, &b.material, &mut k)
        }),
    )?;
    let mut statics = Statics::new(
        &ba.asm,
        &b.fixed,
        Factorization::Supernodal(Ordering::NestedDissection),
    )?;
    row(
        out,
        "numeric factorization (supernodal)",
        median(10, || statics.factorize(&ba.k).expect("factorizes")),
    )?;
    let f = vec![0.0; b.mesh.n_dofs()];
    let mut u = b.prescribed.clone();
    row(
        out,
        "solve",
        median(50, || statics.solve(ba.asm.matrix(&ba.k), &f, &mut u)),
    )?;
    row(
        out,
        "static solve total (assembly + factorization + solve)",
        median(10, || {
            tetrahedra::stiffness(&b.mesh, &ba.asm, &b.material, &mut k);
            statics.factorize(&k).expect("factorizes");
            statics.solve(ba.asm.matrix(&k), &f, &mut u);
        }),
    )?;
    Ok(())
}
