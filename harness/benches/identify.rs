//! The identification of the shipped sets with the model their data were made with
//! (neo-Hookean tet10): the whole fit of E and ν, Gauss–Newton on the derivatives in ν
//! (issue 55's target: ≤ 15 s per set on 2 cores).
//!
//! Run: `cargo bench -p harness --bench identify`.

use harness::studies::identify::{identify, ModelForm};
use harness::studies::measurements::{Measurements, Source};

fn main() {
    divan::main();
}

/// One fit of set `set` (A or C), from the first run to the intervals.
#[divan::bench(args = ["A", "C"], sample_count = 3, sample_size = 1)]
fn neo_hookean_tet10_fit(bencher: divan::Bencher, set: &str) {
    let data = Measurements::load(&Source::Shipped, set).unwrap();
    let model = ModelForm::parse("neo-hookean", "tet10").unwrap();
    bencher.bench_local(|| identify(&data, &model, None, &|_, _| {}).unwrap());
}
