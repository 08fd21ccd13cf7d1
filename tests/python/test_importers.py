"""The FMUs in three independent importers — fmpy, libcosim (Open Simulation Platform,
through libcosimpy) and Ecos (through ecospy) — running the same two scenarios, compared with
the in-process scene (`harness simulate`, the harness's one simulation loop):

- cut block: the default block pulled 0 → 9.5 mm while the scalpel crosses it (inputs set at
  the start of every communication step, held over it);
- abdomen: 0.5 s of the default pressing with the abdominal wall stiffened from 22.5 to
  50 kPa at t = 0.26 s (a tunable parameter changed mid-run).

Every importer reads the outputs in Initialization Mode or right after it (libcosim reads
every variable there). The cut block is quasi-static, so every importer must match to the
last bit. The abdomen's load follows the FMI time: fmpy computes communication points as
k · h like the harness and matches to the last bit; libcosim (integer nanoseconds) and Ecos
(a running sum) compute them otherwise in the last bits, so they are held to 1e-12 of the
largest value instead. libcosim is FMI 2 only (it refuses FMI 3 FMUs); fmpy and Ecos run
both versions.
"""

import csv
import io
import subprocess

import numpy as np
import pytest
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

from paths import FMUS, HARNESS


class Scenario:
    """Parameters before initialization, inputs per communication step, outputs."""

    def __init__(self, model, steps, h, params, inputs, outputs, bitwise):
        self.model, self.steps, self.h = model, steps, h
        self.params, self.inputs, self.outputs = params, inputs, outputs
        self.bitwise = bitwise  # importers whose time arithmetic is the harness's

    def at(self, k):
        """The inputs held over step k (from t_k = k h)."""
        return {name: f(k * self.h) for name, f in self.inputs.items()}


CUTBLOCK = Scenario(
    "cutblock", 20, 0.1, {},
    {"pull": lambda t: 5.0 * t, "scalpel_x": lambda t: 60.0 * t},
    ["reaction_force", "cut_opening", "bottom_lift", "cut_length"],
    bitwise={"fmpy", "libcosim", "ecos"},
)

ABDOMEN = Scenario(
    "abdomen", 50, 0.01, {"target_triangles": 800.0},
    {"wall_E": lambda t: 0.05 if t > 0.255 else 0.0225},
    ["floor_stress_max", "apex_uy", "press_total"],
    bitwise={"fmpy"},
)


def fmu(model, version):
    path = FMUS / f"{model}-{version}.fmu"
    assert path.is_file(), f"{path} missing: run the bundler first"
    return path


def reference(s, tmp_path):
    """The in-process run: rows [t, outputs…] at t_0 … t_n."""
    table = tmp_path / "inputs.csv"
    with open(table, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", *s.inputs])
        for k in range(s.steps + 1):
            w.writerow([repr(k * s.h), *(repr(v) for v in s.at(k).values())])
    args = [str(HARNESS), "simulate", s.model, "--stop-time", repr(s.steps * s.h),
            "--step", repr(s.h), "--inputs", str(table), "--record", ",".join(s.outputs)]
    args += [f"--set={k}={v!r}" for k, v in s.params.items()]
    text = subprocess.run(args, check=True, capture_output=True, text=True).stdout
    return np.loadtxt(io.StringIO(text), delimiter=",", skiprows=1, ndmin=2)


def run_fmpy(s, version):
    path = fmu(s.model, version)
    md = read_model_description(path)
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    cls = FMU2Slave if version == "fmi2" else FMU3Slave
    slave = cls(guid=md.guid, unzipDirectory=extract(path),
                modelIdentifier=md.coSimulation.modelIdentifier, instanceName="s")
    slave.instantiate()
    set_ = slave.setReal if version == "fmi2" else slave.setFloat64
    get = slave.getReal if version == "fmi2" else slave.getFloat64
    for name, x in {**s.params, **s.at(0)}.items():
        set_([vrs[name]], [x])
    if version == "fmi2":
        slave.setupExperiment(startTime=0.0)
        slave.enterInitializationMode()
    else:
        slave.enterInitializationMode(startTime=0.0)
    out = [vrs[n] for n in s.outputs]
    first = get(out)  # read in Initialization Mode
    slave.exitInitializationMode()
    assert get(out) == first, "Initialization Mode reads equal the reads after it"
    rows = [[0.0, *first]]
    for k in range(s.steps):
        for name, x in s.at(k).items():
            set_([vrs[name]], [x])
        t = k * s.h
        slave.doStep(t, (k + 1) * s.h - t)
        rows.append([(k + 1) * s.h, *get(out)])
    slave.terminate()
    slave.freeInstance()
    return np.array(rows)


def run_libcosim(s):
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    step_ns = round(s.h * 1e9)
    execution = CosimExecution.from_step_size(step_size=step_ns)
    index = execution.add_local_slave(CosimLocalSlave(fmu_path=str(fmu(s.model, "fmi2")),
                                                      instance_name="s"))
    vrs = {v.name.decode(): v.reference for v in execution.slave_variables(index)}
    observer = CosimObserver.create_last_value()
    execution.add_observer(observer)
    manipulator = CosimManipulator.create_override()
    execution.add_manipulator(manipulator)
    for name, x in {**s.params, **s.at(0)}.items():
        assert execution.real_initial_value(index, vrs[name], x), name
    out = [vrs[n] for n in s.outputs]
    rows = []
    for k in range(s.steps):
        for name, x in s.at(k).items():
            manipulator.slave_real_values(index, [vrs[name]], [x])
        assert execution.step(), f"step {k}"
        rows.append([(k + 1) * s.h, *observer.last_real_values(index, out)])
    return np.array(rows)


def run_ecos(s, version):
    from ecospy import EcosSimulation, EcosSimulationStructure

    structure = EcosSimulationStructure()
    structure.add_model("s", str(fmu(s.model, version)))
    structure.add_parameter_set("start", {f"s::{k}": v for k, v in {**s.params, **s.at(0)}.items()})
    sim = EcosSimulation(structure=structure, step_size=s.h)
    assert sim.init(parameter_set="start")
    rows = [[0.0, *(sim.get_real(f"s::{n}") for n in s.outputs)]]
    for k in range(s.steps):
        for name, x in s.at(k).items():
            sim.set_real(f"s::{name}", x)
        sim.step()
        rows.append([(k + 1) * s.h, *(sim.get_real(f"s::{n}") for n in s.outputs)])
    sim.terminate()
    return np.array(rows)


def compare(name, s, got, want):
    """Bit for bit where the importer's time arithmetic is the harness's, else 1e-12 of the
    largest value of each output."""
    assert got.shape == want.shape, (got.shape, want.shape)
    for j, output in enumerate(s.outputs, start=1):
        if name in s.bitwise:
            np.testing.assert_array_equal(got[:, j], want[:, j], err_msg=f"{name} {output}")
        else:
            scale = np.max(np.abs(want[:, j]))
            np.testing.assert_allclose(got[:, j], want[:, j], rtol=0, atol=1e-12 * scale,
                                       err_msg=f"{name} {output}")


@pytest.mark.parametrize("scenario", [CUTBLOCK, ABDOMEN], ids=["cutblock", "abdomen"])
@pytest.mark.parametrize("version", ["fmi2", "fmi3"])
def test_fmpy_matches_the_in_process_run(scenario, version, tmp_path):
    compare("fmpy", scenario, run_fmpy(scenario, version), reference(scenario, tmp_path))


@pytest.mark.parametrize("scenario", [CUTBLOCK, ABDOMEN], ids=["cutblock", "abdomen"])
def test_libcosim_matches_the_in_process_run(scenario, tmp_path):
    want = reference(scenario, tmp_path)[1:]  # libcosim observes after each step
    compare("libcosim", scenario, run_libcosim(scenario), want)


@pytest.mark.parametrize("scenario", [CUTBLOCK, ABDOMEN], ids=["cutblock", "abdomen"])
@pytest.mark.parametrize("version", ["fmi2", "fmi3"])
def test_ecos_matches_the_in_process_run(scenario, version, tmp_path):
    compare("ecos", scenario, run_ecos(scenario, version), reference(scenario, tmp_path))
