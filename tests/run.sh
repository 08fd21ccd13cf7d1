#!/usr/bin/env bash
# The whole test suite, from a fresh clone: formatting, lints, and every Rust test in release
# mode (the verification tests solve meshes of up to 20,000 tetrahedra).
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
echo "== cargo test (release)"
cargo test --workspace --release
