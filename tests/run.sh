#!/usr/bin/env bash
# The whole test suite, from a fresh clone: formatting, lints, every Rust test in release
# mode, then the packaged FMUs in fmpy (a Python venv in .venv with fmpy and pytest is
# created on first use).
set -euo pipefail
cd "$(dirname "$0")/.."

if ! command -v cargo >/dev/null; then
    echo "cargo not found: install the Rust toolchain (rustup)" >&2
    exit 1
fi

echo "== cargo fmt --check"
cargo fmt --all -- --check
echo "== cargo clippy (all targets, warnings are errors)"
cargo clippy --workspace --all-targets --release -- -D warnings
echo "== Rust tests (release)"
cargo test --workspace --release

echo "== build and bundle the FMUs"
cargo build --release -p fmu
./target/release/bundle

echo "== Python environment (fmpy, pytest)"
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check fmpy==0.3.32 pytest numpy
echo "== FMUs in fmpy"
.venv/bin/python -m pytest -q tests/python
