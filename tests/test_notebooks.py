"""Every notebook runs top to bottom in quick mode (JAXSKIP_QUICK=1) and writes its figure; what the
notebooks found is pinned here."""

import os
import re
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
NOTEBOOKS = sorted(f for f in os.listdir(os.path.join(ROOT, "notebooks")) if f.endswith(".py"))


def run_notebook(name, out):
    env = {**os.environ, "JAXSKIP_QUICK": "1", "JAXSKIP_NOTEBOOK_OUT": str(out),
           "PYTHONPATH": ROOT + os.pathsep + os.environ.get("PYTHONPATH", "")}
    p = subprocess.run([sys.executable, os.path.join(ROOT, "notebooks", name)], capture_output=True, text=True,
                       env=env, cwd=str(out), timeout=600)
    assert p.returncode == 0, p.stderr[-3000:]
    return p.stdout


@pytest.mark.parametrize("name", NOTEBOOKS)
def test_notebook_runs_in_quick_mode(name, tmp_path):
    out = run_notebook(name, tmp_path)
    figure = tmp_path / (name[:-3] + ".png")
    assert figure.exists() and figure.stat().st_size > 10_000, out[-2000:]
    if name == "bocquet.py":
        # The friction ratio measured from the mesh simulator's impulse is Bocquet's C~/C (5 %).
        m = re.search(r"mu = C~/C = ([\d.]+); measured from the mesh impulse ([\d.]+)", out)
        assert m and abs(float(m.group(2)) / float(m.group(1)) - 1) < 0.05, out
        # Mesh and reduced model give the same minimum speed on the quick grid.
        m = re.search(r"U_min: mesh ([\d.]+) m/s, reduced ([\d.]+) m/s", out)
        assert m and m.group(1) == m.group(2), out
    if name == "speed_vs_accuracy.py":
        # The default configuration lies on, or within 10 % of, the Pareto front.
        m = re.search(r"front's best at no more cost [\d.]+ \(([+-]\d+)%", out)
        assert m and int(m.group(1)) <= 10, out
