"""The Python examples in examples/python run as a user runs them (on short settings), and
each number they print agrees with an independent path: the in-process scene through
`harness simulate` (the harness's own simulation loop, no FMU involved)."""

import csv
import io
import json
import re
import subprocess
import sys

import numpy as np
import pytest

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


def cut_and_pull_inputs(path, stop, step, pull, blade_end):
    """The example's trajectory as a CSV for `harness simulate`: the blade over the first
    half, the pull throughout (the example's docstring)."""
    t = np.linspace(0.0, stop, int(round(stop / step)) + 1)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", "pull", "scalpel_x"])
        for ti in t:
            w.writerow([repr(float(ti)), repr(float(pull * ti / stop)),
                        repr(float(min(1.0, 2.0 * ti / stop) * blade_end))])
    return path


# Each invocation the example's docstring shows, and one on small cells: (arguments, the
# settings, pull, blade end, stop time, step).
CUT_AND_PULL = [
    ([], {}, 10.0, 100.0, 1.0, 0.05),
    (["--pull", "5", "--blade-end", "60", "--set", "material=linear"],
     {"material": "linear"}, 5.0, 60.0, 1.0, 0.05),
    (["--pull", "4", "--stop-time", "1", "--step", "0.25", "--set", "cells_x=3",
      "--set", "cells_y=8", "--set", "cells_z=4"],
     {"cells_x": 3, "cells_y": 8, "cells_z": 4}, 4.0, 100.0, 1.0, 0.25),
]


@pytest.mark.parametrize("args,settings,pull,blade_end,stop,step", CUT_AND_PULL,
                         ids=["documented-default", "documented-linear", "small-cells"])
def test_cut_and_pull_prints_the_in_process_reaction(tmp_path, args, settings, pull,
                                                     blade_end, stop, step):
    out = example("cut_and_pull.py", *args, "--plot", "c.png", cwd=tmp_path)
    assert (tmp_path / "c.png").is_file()
    table = cut_and_pull_inputs(tmp_path / "inputs.csv", stop, step, pull, blade_end)
    expect = simulate("cutblock", stop, step, settings, ["reaction_force", "cut_length"],
                      table)
    assert number(out, "reaction_force") == expect[-1, 1]
    assert number(out, "cut_length") == expect[-1, 2] == blade_end


def test_compare_pelvis_documented_invocations(tmp_path):
    """The docstring's two invocations: the five shipped pelvises on the defaults rank the
    narrow, normal and wide pelvis by peak mean floor stress as docs/verification.md states
    (narrow highest); the fast path's peaks equal the in-process scene's."""
    out = example("compare_pelvis.py", cwd=tmp_path)
    assert (tmp_path / "pelvis_floor_stress.png").is_file()
    peak = {name: number(next(l for l in out.splitlines() if l.startswith(f"{name}:")),
                         "floor_stress_mean")
            for name in ["narrow", "normal", "wide", "lordotic", "tilted"]}
    assert peak["narrow"] > peak["normal"] > peak["wide"], peak
    fast = {"floor_E": 0.1, "kinematics": "linear", "model_order": "modal"}
    out = example("compare_pelvis.py", "--configurations", "narrow", "wide", "--set",
                  "floor_E=0.1", "--set", "kinematics=linear", "--set", "model_order=modal",
                  "--plot", "floor.png", cwd=tmp_path)
    assert (tmp_path / "floor.png").is_file()
    for name in ["narrow", "wide"]:
        line = next(l for l in out.splitlines() if l.startswith(f"{name}:"))
        expect = simulate("abdomen", 2.0, 0.01, {"configuration": name, **fast},
                          ["floor_stress_mean", "floor_stress_max"])
        assert number(line, "floor_stress_mean") == expect[:, 1].max()
        assert number(line, "floor_stress_max") == expect[:, 2].max()


def test_identify_specimen_documented_invocations(tmp_path):
    """The docstring's invocations: the shipped set A with the default model (neo-Hookean
    tet10, the model form that generated the data) fits at the noise level, as the data's
    README says the matching model must; a set of your own without profiles needs ν, which
    the script says and exits non-zero; with ν given it fits E alone and says so."""
    out = example("identify_specimen.py", "--set", "A", "--harness", str(HARNESS),
                  cwd=tmp_path)
    fit = json.loads((tmp_path / "identify_result" / "identify.json").read_text())
    assert number(out, "E") == fit["E_MPa"]["value"]
    assert number(out, "nu") == fit["nu"]["value"] and "95 %" in out
    assert fit["at_noise_level"] is True and "verdict: " in out, out
    mine = tmp_path / "my_data"
    mine.mkdir()
    data = ROOT / "experiments" / "data" / "cutblock"
    for kind, ext in [("specimen", "toml"), ("force_displacement", "csv")]:
        (mine / f"{kind}_B.{ext}").write_text((data / f"{kind}_A.{ext}").read_text())
    done = subprocess.run([sys.executable, str(EXAMPLES / "identify_specimen.py"), "--data",
                           str(mine), "--set", "B", "--harness", str(HARNESS)], cwd=tmp_path,
                          capture_output=True, text=True)
    assert done.returncode != 0 and "give ν (--nu)" in done.stderr, done.stderr
    out = example("identify_specimen.py", "--set", "A", "--nu", "0.43", "--material",
                  "linear", "--element", "tet4", "--out", "fast", "--harness", str(HARNESS),
                  cwd=tmp_path)
    assert "nu = 0.43 (given)" in out, out
    # E alone at a given ν is the least-squares slope of the measured forces on the model's
    # forces at E = 1 (linear law: proportional to E), here from the in-process scene.
    measured = np.loadtxt(data / "force_displacement_A.csv", delimiter=",", skiprows=1)
    table = tmp_path / "pulls.csv"
    with open(table, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", "pull"])
        for k, d in enumerate(measured[:, 0]):
            w.writerow([k, repr(float(d))])
    unit = simulate("cutblock", float(len(measured)), 1.0,
                    {"material": "linear", "element": "tet4", "E": "1.0", "nu": "0.43",
                     "scalpel_x": 100.0}, ["reaction_force"], table)[1:, 1]
    slope = np.dot(unit, measured[:, 1]) / np.dot(unit, unit)
    assert abs(number(out, "E") - slope) <= 1e-9 * slope, (out, slope)


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
