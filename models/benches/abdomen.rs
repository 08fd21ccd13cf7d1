//! Abdomen scene benchmarks on the default configuration (≈ 6,000 triangles, 188 line
//! elements, Houbolt, dt = 1 ms).
//!
//! Run: `cargo bench -p models --bench abdomen`.

use divan::Bencher;
use models::scene::abdomen::Abdomen;
use models::scene::Scene;

fn main() {
    divan::main();
}

fn initialized() -> Abdomen {
    let mut s = Abdomen::new();
    s.initialize(0.0).unwrap();
    s
}

/// Configuration → outline → mesh → assembly → symbolic + numeric factorization.
#[divan::bench(sample_count = 30)]
fn setup(bencher: Bencher) {
    bencher.bench(initialized);
}

/// One Houbolt step (no outputs read).
#[divan::bench]
fn step(bencher: Bencher) {
    let mut s = initialized();
    let mut t = 0.0;
    bencher.bench_local(|| {
        s.do_step(t, 1e-3).unwrap();
        t += 1e-3;
    });
}

/// One Houbolt step and every scalar output read.
#[divan::bench]
fn step_with_outputs(bencher: Bencher) {
    let mut s = initialized();
    let vrs: Vec<u32> = s
        .variables()
        .iter()
        .filter(|v| v.causality == models::scene::Causality::Output)
        .map(|v| v.vr)
        .collect();
    let mut t = 0.0;
    let mut x = [0.0];
    bencher.bench_local(|| {
        s.do_step(t, 1e-3).unwrap();
        t += 1e-3;
        for &vr in &vrs {
            s.get_real(vr, &mut x).unwrap();
        }
    });
}

/// A sweep case: set-up plus 1 s of simulated time at dt = 1 ms, peak floor stress read
/// every 10 ms.
#[divan::bench(sample_count = 10)]
fn sweep_case_one_second(bencher: Bencher) {
    bencher.bench(|| {
        let mut s = initialized();
        let vr = s.lookup("floor_stress_max").unwrap();
        let mut peak = f64::NEG_INFINITY;
        for i in 0..1000 {
            s.do_step(i as f64 * 1e-3, 1e-3).unwrap();
            if i % 10 == 9 {
                let mut x = [0.0];
                s.get_real(vr, &mut x).unwrap();
                peak = peak.max(x[0]);
            }
        }
        peak
    });
}
