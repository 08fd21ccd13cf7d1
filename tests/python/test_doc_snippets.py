"""The Python snippets of the README and the user guide run as written (from the repository
root, where their FMU paths point) and print what the in-process scene gives for the same
run (`harness simulate`, no FMU involved)."""

import csv
import re
import subprocess
import sys

import numpy as np
import pytest

from paths import ROOT
from test_examples import simulate


def abdomen_peak(settings):
    """The peak mean floor stress of the snippets' abdomen run (2 s, outputs every 10 ms)."""
    return simulate("abdomen", 2.0, 0.01, settings, ["floor_stress_mean"])[:, 1].max()


def cutblock_final(tmp_path):
    """The last reaction force of the README's cut-block run: pull 10 t, blade 100 t, no
    press, outputs every 0.1 s to 1 s."""
    table = tmp_path / "inputs.csv"
    with open(table, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["time", "pull", "scalpel_x", "press_force"])
        for t in np.linspace(0.0, 1.0, 11):
            w.writerow([repr(float(t)), repr(float(10 * t)), repr(float(100 * t)), "0.0"])
    return simulate("cutblock", 1.0, 0.1, {}, ["reaction_force"], table)[-1, 1]


# Each snippet, in page order, with what it must print.
SNIPPETS = {
    "README.md": [
        lambda tmp: [abdomen_peak({"configuration": "narrow"})],
        lambda tmp: [cutblock_final(tmp), "(11, 181)"],
    ],
    "docs/user-guide.md": [
        lambda tmp: [abdomen_peak({"configuration": "narrow", "floor_E": 0.1})],
    ],
}


def snippets():
    for page, expected in SNIPPETS.items():
        text = (ROOT / page).read_text()
        found = re.findall(r"```python\n(.*?)```", text, re.S)
        assert len(found) == len(expected), f"{page}: {len(found)} snippets"
        for k, (code, expect) in enumerate(zip(found, expected)):
            yield pytest.param(code, expect, id=f"{page}[{k}]")


@pytest.mark.parametrize("code,expect", list(snippets()))
def test_a_documented_snippet_prints_what_the_scene_gives(code, expect, tmp_path):
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    assert done.stderr == "", done.stderr
    want = expect(tmp_path)
    printed = done.stdout.split(maxsplit=1)
    assert float(printed[0]) == want[0], (done.stdout, want)
    if len(want) > 1:
        assert printed[1].strip() == want[1], done.stdout
