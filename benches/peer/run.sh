#!/usr/bin/env bash
# The peer benchmark (measures, asserts nothing about speed; not part of tests/run.sh): the
# default abdomen's full-order Houbolt step in tissuefmu against scipy's splu and CHOLMOD
# (scikit-sparse) on the same exported matrices, in one run. Prints a Markdown table and
# writes it to target/peer/peer.md. Needs Debian's libsuitesparse-dev (installed here if
# missing) for scikit-sparse 0.4.16; the Python packages go into target/peer-venv.
set -euo pipefail
cd "$(dirname "$0")/../.."

if [ ! -f /usr/include/suitesparse/cholmod.h ]; then
    echo "== installing libsuitesparse-dev (CHOLMOD headers for scikit-sparse)"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq && apt-get install -y -qq libsuitesparse-dev >/dev/null
fi
venv=target/peer-venv
if [ ! -x "$venv/bin/python" ]; then
    python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check -r benches/peer/requirements.txt

echo "== export the default abdomen and time tissuefmu's step on it"
cargo run --release --quiet -p harness -- peer-export --out target/peer
echo "== the same run with scipy splu and CHOLMOD"
"$venv/bin/python" benches/peer/houbolt_peer.py target/peer
