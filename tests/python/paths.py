"""What the Python tests run: the repository, the packaged FMUs (`target/fmu`, written by the
bundler) and the harness binary. `tests/run.sh` builds for x86_64-unknown-linux-gnu against
glibc 2.28 and says where its harness is in TISSUEFMU_HARNESS; without it the tests take the
plain release build's (`cargo build --release -p harness`)."""

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FMUS = ROOT / "target" / "fmu"
HARNESS = Path(os.environ.get("TISSUEFMU_HARNESS", ROOT / "target" / "release" / "harness"))
