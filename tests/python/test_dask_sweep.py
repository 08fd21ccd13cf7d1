"""The Dask path: the same sweep run by the Rust harness (in process) and by
harness/python/dask_sweep.py on a local Dask cluster of two workers with fmpy importing the
FMU gives the same case results, records the same failure, and resumes. The input table has
a breakpoint inside a communication step (0.155 s with 0.01 s steps), so equal results show
that both runners follow the same input rule: sampled at each step's start and held."""

import subprocess
import sys

import numpy as np

from paths import FMUS, HARNESS, ROOT

DASK_SWEEP = ROOT / "harness" / "python" / "dask_sweep.py"
FMU = FMUS / "abdomen-fmi2.fmu"

EXPERIMENT = """
name = "dask_check"
scene = "abdomen"
stop_time = 0.2
step = 0.01
jobs = 2
record = ["floor_stress_max", "apex_uy"]
[parameters]
target_triangles = 500
[inputs.press_force]
time = [0.0, 0.155, 0.2]
value = [0.0, 0.4, 0.1]
[[sweep]]
design = "list"
values = { configuration = ["normal", "wide", "wide"], memory_limit = [8000, 1, 8000] }
[[sweep]]
design = "latin-hypercube"
samples = 3
seed = 5
ranges = { "anatomy.outlet" = { min = 100.0, max = 130.0 }, floor_E = { min = 0.02, max = 0.2, log = true } }
"""


def load(path):
    return np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)


def test_dask_workers_reproduce_the_rust_sweep(tmp_path):
    assert HARNESS.is_file() and FMU.is_file(), "build the harness and bundle the FMUs first"
    exp = tmp_path / "dask_check.toml"
    exp.write_text(EXPERIMENT)
    rust = tmp_path / "rust"
    subprocess.run([str(HARNESS), "sweep", str(exp), "--out", str(rust)], check=True,
                   capture_output=True)
    dask_out = tmp_path / "dask"
    run = [sys.executable, str(DASK_SWEEP), str(rust / "plan.json"), "--fmu", str(FMU),
           "--local-workers", "2", "--out", str(dask_out)]
    subprocess.run(run, check=True, capture_output=True, timeout=600)

    worst = 0.0
    for case in range(6):
        name = f"cases/case_{case:04d}"
        if case == 1:
            assert not (dask_out / f"{name}.csv").exists()
            # Over its memory_limit: the FMU's message on the worker, the scene's in Rust.
            assert "above memory_limit = 1 MB" in (dask_out / f"{name}.error").read_text()
            assert "above memory_limit = 1 MB" in (rust / f"{name}.error").read_text()
            continue
        a, b = load(rust / f"{name}.csv"), load(dask_out / f"{name}.csv")
        assert a.shape == b.shape == (21, 3)
        np.testing.assert_allclose(b, a, rtol=1e-12, atol=0.0, err_msg=name)
        worst = max(worst, float(np.max(np.abs(a - b))))
    print(f"largest difference Rust vs Dask/fmpy: {worst:.3e}")

    # Re-running skips the finished cases: their files stay untouched.
    before = (dask_out / "cases/case_0000.csv").stat().st_mtime_ns
    subprocess.run(run, check=True, capture_output=True, timeout=600)
    assert (dask_out / "cases/case_0000.csv").stat().st_mtime_ns == before
    summary = (dask_out / "summary.csv").read_text().splitlines()
    assert len(summary) == 7 and sum(",finished," in line for line in summary) == 5
