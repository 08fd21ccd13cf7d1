"""FMU states through fmpy, FMI 2 and FMI 3, both models: a state taken mid-run and
serialized continues bit for bit as the uninterrupted run — set into a fresh instance in a
new process (fmpy's low-level API), and given to `simulate_fmu(fmu_state=…)`; bytes of
another model are refused."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Slave
from fmpy.fmi3 import FMU3Slave

from paths import FMUS

RUNS = {
    "cutblock": dict(parameters={"cells_x": 6.0, "cells_y": 4.0, "cells_z": 3.0},
                     inputs=lambda k: {"scalpel_x": 17.0 * k, "pull": 0.9 * k},
                     outputs=["reaction_force", "cut_opening"], h=1.0),
    "abdomen": dict(parameters={"target_triangles": 300.0},
                    inputs=lambda k: {"press_force": 0.02 * k},
                    outputs=["floor_stress_mean", "apex_uy"], h=0.01),
}
AT, END = 3, 7


def open_fmu(model, version, directory):
    path = FMUS / f"{model}-{version}.fmu"
    md = read_model_description(str(path))
    unzipdir = extract(str(path), str(directory))
    cls = FMU2Slave if version == "fmi2" else FMU3Slave
    fmu = cls(guid=md.guid if version == "fmi2" else md.instantiationToken,
              unzipDirectory=unzipdir, modelIdentifier=md.coSimulation.modelIdentifier,
              instanceName="state")
    vrs = {v.name: v.valueReference for v in md.modelVariables}
    return fmu, vrs


def set_real(fmu, version, vrs, values):
    refs = [vrs[n] for n in values]
    if version == "fmi2":
        fmu.setReal(refs, list(values.values()))
    else:
        fmu.setFloat64(refs, list(values.values()))


def get_real(fmu, version, vrs, names):
    refs = [vrs[n] for n in names]
    return fmu.getReal(refs) if version == "fmi2" else fmu.getFloat64(refs)


def steps(fmu, version, vrs, run, first, last):
    out = []
    for k in range(first, last):
        set_real(fmu, version, vrs, run["inputs"](k))
        fmu.doStep(currentCommunicationPoint=k * run["h"], communicationStepSize=run["h"])
        out.extend(get_real(fmu, version, vrs, run["outputs"]))
    return out


def run_and_save(model, version, directory):
    """The uninterrupted run: the state's bytes after AT steps and the outputs after."""
    run = RUNS[model]
    fmu, vrs = open_fmu(model, version, directory)
    fmu.instantiate()
    if version == "fmi2":
        fmu.setupExperiment(startTime=0.0)
    set_real(fmu, version, vrs, run["parameters"])
    fmu.enterInitializationMode()
    fmu.exitInitializationMode()
    steps(fmu, version, vrs, run, 0, AT)
    state = fmu.getFMUState()
    data = fmu.serializeFMUState(state)
    fmu.freeFMUState(state)
    expected = steps(fmu, version, vrs, run, AT, END)
    fmu.terminate()
    fmu.freeInstance()
    return data, expected


CONTINUE = """
import json, sys
sys.path.insert(0, {tests!r})
from test_fmu_state import RUNS, AT, END, open_fmu, steps
fmu, vrs = open_fmu({model!r}, {version!r}, {directory!r})
fmu.instantiate()
state = fmu.deserializeFMUState(open({state!r}, "rb").read())
fmu.setFMUState(state)
fmu.freeFMUState(state)
print(json.dumps([x.hex() for x in steps(fmu, {version!r}, vrs, RUNS[{model!r}], AT, END)]))
fmu.freeInstance()
"""


@pytest.mark.parametrize("model", ["cutblock", "abdomen"])
@pytest.mark.parametrize("version", ["fmi2", "fmi3"])
def test_a_serialized_state_continues_in_a_new_process(model, version, tmp_path):
    data, expected = run_and_save(model, version, tmp_path / "a")
    (tmp_path / "state.bin").write_bytes(data)
    script = CONTINUE.format(tests=str(Path(__file__).parent), model=model, version=version,
                             directory=str(tmp_path / "b"), state=str(tmp_path / "state.bin"))
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          check=True)
    got = [float.fromhex(x) for x in json.loads(done.stdout.strip().splitlines()[-1])]
    assert got == expected


@pytest.mark.parametrize("model", ["cutblock", "abdomen"])
@pytest.mark.parametrize("version", ["fmi2", "fmi3"])
def test_simulate_fmu_starts_from_a_serialized_state(model, version, tmp_path):
    run = RUNS[model]
    data, expected = run_and_save(model, version, tmp_path / "a")
    times = [k * run["h"] for k in range(AT, END + 1)]
    names = list(run["inputs"](0))
    table = np.array([(t, *run["inputs"](round(t / run["h"])).values()) for t in times],
                     dtype=[("time", float)] + [(n, float) for n in names])
    result = simulate_fmu(str(FMUS / f"{model}-{version}.fmu"), fmu_state=data,
                          start_time=AT * run["h"], stop_time=END * run["h"],
                          output_interval=run["h"], input=table, output=run["outputs"])
    got = [float(result[n][i]) for i in range(1, len(result)) for n in run["outputs"]]
    assert got == expected


def test_a_state_of_the_other_model_is_refused(tmp_path):
    data, _ = run_and_save("abdomen", "fmi2", tmp_path / "a")
    fmu, _ = open_fmu("cutblock", "fmi2", tmp_path / "b")
    fmu.instantiate()
    with pytest.raises(Exception, match="fmi2DeSerializeFMUstate failed"):
        fmu.deserializeFMUState(data)
    fmu.freeInstance()
