"""The Python snippets of the README and the user guide run as written (from the repository
root, where their FMU paths point) and print what their comments say."""

import re
import subprocess
import sys

import pytest

from paths import ROOT

PAGES = ["README.md", "docs/user-guide.md"]


def snippets():
    for page in PAGES:
        text = (ROOT / page).read_text()
        for k, code in enumerate(re.findall(r"```python\n(.*?)```", text, re.S)):
            yield pytest.param(code, id=f"{page}[{k}]")


@pytest.mark.parametrize("code", list(snippets()))
def test_a_documented_snippet_runs_and_prints_what_it_says(code):
    done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    printed = done.stdout.split()
    if "profile_x50" in code:
        # `print(r["reaction_force"][-1], r["profile_x50"].shape)   # N, (11, 181)`
        assert float(printed[0]) > 0.0 and " ".join(printed[1:]) == "(11, 181)", done.stdout
    else:
        # `print(r["floor_stress_mean"].max())   # MPa`: a positive stress of kPa order.
        assert 1e-4 < float(printed[0]) < 1e-1, done.stdout


def test_the_pages_have_the_snippets_this_file_runs():
    assert len(list(snippets())) == 3
