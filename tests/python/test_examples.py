"""The Python examples in examples/python run as a user runs them (on short settings), and
each number they print agrees with an independent path: the in-process scene through
`harness simulate` (the harness's own simulation loop, no FMU involved)."""

import csv
import io
import re
import subprocess
import sys

import numpy as np

from paths import ROOT, HARNESS

EXAMPLES = ROOT / "examples" / "python"


def example(name, *args, cwd):
    done = subprocess.run([sys.executable, str(EXAMPLES / name), *args], cwd=cwd,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stdout


def simulate(scene, stop, step, settings, record, inputs=None):
    """Rows [t, outputs…] of the in-process scene."""
    args = [str(HARNESS), "simulate", scene, "--stop-time", repr(stop), "--step", repr(step),
            "--record", ",".join(record)]
    args += [f"--set={k}={v}" for k, v in settings.items()]
    if inputs is not None:
        args += ["--inputs", str(inputs)]
    text = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return np.loadtxt(io.StringIO(text), delimiter=",", skiprows=1, ndmin=2)


def number(text, name):
    """The number printed as `name = <repr>`."""
    m = re.search(rf"{name} = ([-+0-9.eE]+)", text)
    assert m, f"no {name} in {text}"
    return float(m.group(1))


def test_compare_pelvis_prints_the_in_process_peaks(tmp_path):
    out = example("compare_pelvis.py", "--configurations", "narrow", "normal",
                  "--stop-time", "0.1", "--set", "target_triangles=300", "--plot", "p.png",
                  cwd=tmp_path)
    assert (tmp_path / "p.png").is_file()
    for name in ["narrow", "normal"]:
        line = next(l for l in out.splitlines() if l.startswith(f"{name}:"))
        expect = simulate("abdomen", 0.1, 0.01,
                          {"configuration": name, "target_triangles": 300.0},
                          ["floor_stress_mean", "floor_stress_max"])
        # Peaks over every output row, t = 0 included, as the example takes them.
        assert number(line, "floor_stress_mean") == expect[:, 1].max()
        assert number(line, "floor_stress_max") == expect[:, 2].max()


def test_cut_and_pull_prints_the_in_process_reaction(tmp_path):
    small = ["--set", "cells_x=3", "--set", "cells_y=8", "--set", "cells_z=4"]
    out = example("cut_and_pull.py", "--pull", "4", "--stop-time", "1", "--step", "0.25",
                  *small, "--plot", "c.png", cwd=tmp_path)
    assert (tmp_path / "c.png").is_file()
    table = tmp_path / "inputs.csv"
    with open(table, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", "pull", "scalpel_x"])
        for t in (0.0, 0.25, 0.5, 0.75, 1.0):
            w.writerow([repr(t), repr(4.0 * t), repr(min(1.0, 2.0 * t) * 100.0)])
    expect = simulate("cutblock", 1.0, 0.25, {"cells_x": 3, "cells_y": 8, "cells_z": 4},
                      ["reaction_force", "cut_length"], table)
    assert number(out, "reaction_force") == expect[-1, 1]
    assert number(out, "cut_length") == expect[-1, 2] == 100.0


def test_identify_specimen_reports_the_residual_of_its_own_fit(tmp_path):
    """The fit's force residual, recomputed by running the fitted model in process."""
    data = ROOT / "experiments" / "data" / "cutblock"
    out = example("identify_specimen.py", "--data", str(data), "--set", "A",
                  "--material", "linear", "--element", "tet4", "--out", "fit",
                  "--harness", str(HARNESS), cwd=tmp_path)
    assert (tmp_path / "fit" / "identify.json").is_file()
    e, nu = number(out, "E"), number(out, "nu")
    measured = np.loadtxt(data / "force_displacement_A.csv", delimiter=",", skiprows=1)
    table = tmp_path / "pulls.csv"
    with open(table, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", "pull"])
        for k, d in enumerate(measured[:, 0]):
            w.writerow([k, repr(float(d))])
    n = len(measured)
    model = simulate("cutblock", float(n), 1.0,
                     {"material": "linear", "element": "tet4", "E": repr(e), "nu": repr(nu),
                      "scalpel_x": 100.0},
                     ["reaction_force"], table)
    residual = np.sqrt(np.mean((measured[:, 1] - model[1:, 1]) ** 2))
    assert abs(number(out, "force RMS residual") - residual) <= 1e-9 * residual
    assert "not at the noise level" in out
