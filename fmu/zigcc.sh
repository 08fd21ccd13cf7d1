#!/bin/sh
# zig cc (from the venv's ziglang) as the C compiler and linker for x86_64-unknown-linux-gnu,
# against glibc 2.28, through cargo-zigbuild's filter of the arguments zig does not take.
root=$(cd "$(dirname "$0")/.." && pwd)
export CARGO_ZIGBUILD_ZIG_COMMAND="$root/.venv/bin/python3"
export CARGO_ZIGBUILD_ZIG_COMMAND_ARGS='-m ziglang'
exec "$root/.venv/bin/cargo-zigbuild" zig cc -- -g -fno-sanitize=all -target x86_64-linux-gnu.2.28 "$@"
