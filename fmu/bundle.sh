#!/usr/bin/env bash
# The FMUs to ship: the library built against glibc 2.28 (cargo-zigbuild with zig, both from
# PyPI, installed into .venv), so that the FMUs load on Linux from glibc 2.28 on (RHEL 8,
# Debian 10, Ubuntu 20.04 and later), then the four archives into target/fmu/. A plain
# `cargo build --release -p fmu && target/release/bundle` builds them against this machine's
# glibc instead.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ ! -x .venv/bin/python ]; then
    python3 -m venv .venv
fi
.venv/bin/python -m pip install --quiet --disable-pip-version-check \
    ziglang==0.17.1 cargo-zigbuild==0.24.1
target=x86_64-unknown-linux-gnu
PATH="$PWD/.venv/bin:$PATH" cargo zigbuild --release -p fmu --lib --target "$target.2.28"
# The test suite builds the bundler with the rest of the workspace first (its features
# differ from `-p fmu`'s, so building it here again would recompile the models crate).
if [ "${1:-}" != "--bundler-built" ]; then
    cargo build --release -p fmu --bin bundle
fi
./target/release/bundle --library "target/$target/release/libfmu.so"
