#!/usr/bin/env bash
# The FMUs to ship: the library and the bundler built against glibc 2.28 (zig as C compiler
# and linker, fmu/zig.sh), then the four archives into target/fmu/. A plain
# `cargo build --release -p fmu && target/release/bundle` builds them against this machine's
# glibc instead.
set -euo pipefail
cd "$(dirname "$0")/.."
source fmu/zig.sh
cargo build --release -p fmu --lib --bin bundle --target "$ZIG_TARGET"
"target/$ZIG_TARGET/release/bundle" --out target/fmu
