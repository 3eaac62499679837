"""`jaxskip optimize` and `jaxskip sweep`: JSON out, bad input exits 2 with one line and no traceback."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from jaxskip.cli import main

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("argv, word", [
    (["optimize", "--speed-range", "12", "3"], "speed is inverted"),
    (["optimize", "--tilt-range", "5", "nan"], "tilt must be finite"),
    (["optimize", "--spin", "500"], "spin must lie within"),
    (["optimize", "--starts", "0"], "starts"),
    (["optimize", "--stone", "granite"], "stone"),
    (["sweep", "umin", "--tilts", "5:x:3"], "--tilts"),
    (["sweep", "umin", "--speed-range", "0", "8"], "speed_range"),
    (["sweep", "merge"], "merge needs"),
    (["optimize", "--polish", "-1"], "polish"),
    (["optimize", "--horizon", "0"], "horizon"),
    (["sweep", "domain", "--plot", "out.txt"], "--plot"),
])
def test_bad_input_exits_2(argv, word, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert word in err and "Traceback" not in err and err.count("\n") == 1


def test_no_traceback_from_the_command():
    p = subprocess.run([sys.executable, "-m", "jaxskip", "optimize", "--speed-range", "3", "3"], capture_output=True,
                       text=True, cwd=ROOT, timeout=120)
    assert p.returncode == 2 and "speed is empty" in p.stderr and "Traceback" not in p.stderr


def test_sweep_json_and_files(tmp_path, capsys):
    out = tmp_path / "sweep"
    assert main(["sweep", "domain", "--tilts", "20,60", "--attacks", "20", "--speed", "3.5", "--out", str(out),
                 "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["complete"] and r["spec"]["stone"] == "clanet" and r["spec"]["attitude"] == "fixed"
    assert r["bounces"][0][0] > 0 and r["bounces"][1][0] == 0  # 20 deg skips, 60 deg does not
    assert (out / "result.csv").read_text().splitlines()[0].startswith("tilt_deg,attack_deg")


def test_optimize_random_json(capsys):
    assert main(["optimize", "--method", "random", "--throws", "16", "--attitude", "fixed", "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["method"] == "random" and r["forward_throws"] == 16 and r["best_bounces"] >= 1
    assert set(r["best"]) == {"speed", "tilt", "attack", "spin"}


def test_optimize_gradient_reports_gradient_norms(tmp_path, capsys):
    """Gradient-norm monitoring at the CLI: a line of text (and a picture panel), a JSON summary."""
    argv = ["optimize", "--method", "gradient", "--starts", "2", "--iterations", "1", "--attitude", "fixed",
            "--speed-range", "5", "7", "--tilt", "20", "--attack", "10", "--spin", "10", "--polish", "8"]
    assert main(argv + ["--plot", str(tmp_path / "search.png")]) == 0
    text = capsys.readouterr().out
    assert "gradient norms (unconstrained units, before clipping): median" in text
    assert "the polish (8 exact throws near its best throws)" in text
    assert (tmp_path / "search.png").stat().st_size > 10_000
    assert main(argv + ["--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    h = r["gradient_norms"]
    assert h["of"] == 2 and h["starts"]["n"] == 2 and h["max"] >= h["median"] >= 0.0
    assert r["forward_throws"] == 2 * 2 + 8 and r["history"][-1]["phase"] == "polish"
    assert r["history"][0]["grad_norm"] and len(r["history"][0]["grad_norm"]) == 2


def test_optimize_perturbation_with_samples_and_polish(capsys):
    argv = ["optimize", "--method", "perturbation", "--starts", "2", "--iterations", "1", "--samples", "1",
            "--polish", "4", "--attitude", "fixed", "--speed-range", "5", "7", "--tilt", "20", "--attack", "10",
            "--spin", "10"]
    assert main(argv + ["--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["method"] == "perturbation" and r["forward_throws"] == 2 * (2 * 1 + 1) + 4
    assert r["history"][-1]["phase"] == "polish" and "gradient_norms" not in r
    assert main(argv) == 0
    assert "the polish (4 exact throws near its best throws)" in capsys.readouterr().out
