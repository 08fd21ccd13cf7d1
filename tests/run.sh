#!/usr/bin/env bash
# The whole test suite, from a fresh clone: formatting, lints, every Rust test in release
# mode, then the packaged FMUs in fmpy and the Dask sweep runner (a Python venv in .venv with
# fmpy, pytest and dask is created on first use).
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v cargo >/dev/null; then
    echo "cargo not found: install the Rust toolchain (rustup)" >&2
    exit 1
fi

echo "== cargo fmt --check"
cargo fmt --all -- --check
if ! ldconfig -p 2>/dev/null | grep -q 'libclang[-.0-9]*\.so'; then
    echo "== installing libclang (bindgen in the fmi crate, the importer the tests and the harness's FMU backend use, needs it)"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq && apt-get install -y -qq libclang-dev >/dev/null
fi
echo "== cargo clippy (all targets and features, warnings are errors)"
cargo clippy --workspace --all-targets --all-features --release -- -D warnings

echo "== build and bundle the FMUs (the import tests load them)"
cargo build --release -p fmu
./target/release/bundle

echo "== Rust tests (release, with the harness's FMU backend)"
cargo test --workspace --all-features --release
cargo build --release -p harness --all-features

echo "== Python environment (fmpy, pytest)"
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check \
    fmpy==0.3.32 pytest numpy meshio==5.3.5 "dask[distributed]==2026.8.0"
echo "== FMUs in fmpy, the Dask sweep runner on a local two-worker cluster, VTU files in meshio"
.venv/bin/python -m pytest -q tests/python
