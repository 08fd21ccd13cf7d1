# Sourced by fmu/bundle.sh and tests/run.sh: zig (PyPI's ziglang) and cargo-zigbuild, whose
# `zig cc` filters the arguments zig does not take, into .venv; then cargo set to compile C
# and link for $ZIG_TARGET with fmu/zigcc.sh, against glibc 2.28, so that the FMUs' library
# loads on Linux from glibc 2.28 on (RHEL 8, Debian 10, Ubuntu 20.04 and later). Build with
# `--target "$ZIG_TARGET"`: the output goes to target/$ZIG_TARGET/, apart from the plain
# host build's.
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
if [ ! -x "$root/.venv/bin/python" ]; then
    python3 -m venv "$root/.venv"
fi
"$root/.venv/bin/python" -m pip install --quiet --disable-pip-version-check \
    ziglang==0.17.1 cargo-zigbuild==0.24.1
ZIG_TARGET=x86_64-unknown-linux-gnu
export CARGO_TARGET_X86_64_UNKNOWN_LINUX_GNU_LINKER="$root/fmu/zigcc.sh"
export CC_x86_64_unknown_linux_gnu="$root/fmu/zigcc.sh"
# The harness's VTU writer (vtkio, through xz2) would link this machine's liblzma, which
# needs a newer glibc: its bundled source is compiled instead.
export LZMA_API_STATIC=1
