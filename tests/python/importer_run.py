"""One importer's run of one scenario, in a process of its own: the FMU tests run each
importer (fmpy, libcosim, Ecos) here, so that no two importers' native libraries are ever
loaded into one process (no user does that, and their libraries are not made for it).

    python importer_run.py IMPORTER SCENARIO VERSION OUT.npy

writes the rows [t, outputs…] of the run to OUT.npy. The scenarios are defined here and
imported by the tests.
"""

import sys

import numpy as np
from fmpy import extract, read_model_description
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

from paths import FMUS


class Scenario:
    """Parameters before initialization, inputs per communication step, outputs."""

    def __init__(self, model, steps, h, params, inputs, outputs, bitwise):
        self.model, self.steps, self.h = model, steps, h
        self.params, self.inputs, self.outputs = params, inputs, outputs
        self.bitwise = bitwise  # importers whose time arithmetic is the harness's

    def at(self, k):
        """The inputs held over step k (from t_k = k h)."""
        return {name: f(k * self.h) for name, f in self.inputs.items()}

    def held_at_start(self):
        """The scenario with its inputs held at their values at t = 0."""
        held = {name: (lambda v: lambda t: v)(f(0.0)) for name, f in self.inputs.items()}
        return Scenario(self.model, self.steps, self.h, self.params, held, self.outputs,
                        self.bitwise)


CUTBLOCK = Scenario(
    "cutblock", 20, 0.1, {},
    {"pull": lambda t: 5.0 * t, "scalpel_x": lambda t: 60.0 * t},
    ["reaction_force", "cut_opening", "bottom_lift", "cut_length"],
    bitwise={"fmpy", "libcosim", "ecos"},
)

# The pelvic floor stiffened fourfold at t = 0.26 s, mid-press: a tunable parameter that
# acts on the default abdomen (its wall is held, so the wall's would not).
STIFFER_FLOOR = 4.0
ABDOMEN = Scenario(
    "abdomen", 50, 0.01, {"target_triangles": 800.0},
    {"floor_E": lambda t: 0.05 * (STIFFER_FLOOR if t > 0.255 else 1.0)},
    ["floor_stress_max", "apex_uy", "press_total", "floor_mid_uy"],
    bitwise={"fmpy"},
)

SCENARIOS = {"cutblock": CUTBLOCK, "abdomen": ABDOMEN}

RUNS = {
    "fmpy": lambda s, version: run_fmpy(s, version),
    "libcosim": lambda s, version: run_libcosim(s),
    "ecos": lambda s, version: run_ecos(s, version),
}


def fmu(model, version):
    path = FMUS / f"{model}-{version}.fmu"
    assert path.is_file(), f"{path} missing: run the bundler first"
    return path


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




if __name__ == "__main__":
    importer, scenario, version, out = sys.argv[1:]
    np.save(out, RUNS[importer](SCENARIOS[scenario], version))
