"""The README's Python API example runs as written, in a fresh interpreter, and prints what its
comments say: the default throw's count, distance and outcome; one count per tilt from the vmapped
rollout; the same counts from ``simulate_batch``; the trajectory files it writes."""

import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def readme_python_example() -> str:
    with open(os.path.join(ROOT, "README.md"), encoding="utf-8") as f:
        section = f.read().split("## Python API", 1)[1]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_readme_python_example_runs_as_documented(tmp_path):
    code = readme_python_example()
    env = {**os.environ, "PYTHONPATH": ROOT + os.pathsep + os.environ.get("PYTHONPATH", "")}
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=str(tmp_path),
                       timeout=900)
    assert p.returncode == 0, p.stderr[-3000:]

    first, rest = p.stdout.split("\n", 1)
    said = re.search(r"print\(result\.bounces, result\.distance, result\.outcome\)\s*#\s*(\d+) ([\d.]+?)\.\.\. (\w+)",
                     code)
    bounces, distance, outcome = first.split()
    assert (int(bounces), outcome) == (int(said[1]), said[3]) and distance.startswith(said[2]), (first, said.groups())

    arrays = [[int(v) for v in block.split()] for block in re.findall(r"\[([^\]]*)\]", rest)]
    n = int(re.search(r"jnp\.linspace\([^)]*?, (\d+)\)", code)[1])
    assert re.search(rf"shape \({n},\)", code) and len(arrays) == 2 and len(arrays[0]) == n, rest
    assert arrays[0] == arrays[1], "simulate_batch gave other counts than vmap(rollout)"  # "the same counts"
    assert max(arrays[0]) > 0 and min(arrays[0]) < max(arrays[0])  # counts that depend on the tilt

    assert (tmp_path / "throw.csv").stat().st_size > 1000 and (tmp_path / "throw.stone.obj").exists()
