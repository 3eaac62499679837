"""The command line as a user meets it: output, JSON, pictures, and clear errors (exit 2)."""

import json
import os
import subprocess
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(*args, cwd=None):
    env = {**os.environ, "PYTHONPATH": ROOT + os.pathsep + os.environ.get("PYTHONPATH", "")}
    return subprocess.run([sys.executable, "-m", "jaxskip", *args], capture_output=True, text=True,
                          cwd=cwd or ROOT, env=env, timeout=300)


def test_default_throw_json_and_plot(tmp_path):
    png = tmp_path / "throw.png"
    p = run("throw", "--json", "--plot", str(png))
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout, parse_constant=lambda c: pytest.fail(f"non-strict JSON token {c}"))
    # exactly one strict JSON object on stdout (no NaN/Infinity tokens)
    assert isinstance(out["bounces"], int) and out["bounces"] >= 5
    assert out["outcome"] == "sank" and out["distance"] > 1.0
    assert len(out["contacts"]) == out["bounces"] + 1
    assert {"t_start", "t_end", "x"} <= set(out["contacts"][0])
    params = out["parameters"]
    assert params["speed"] == 8.0 and params["tilt_deg"] == pytest.approx(20.0)
    assert params["force_law"] == "bocquet" and params["stone"] == "paper"
    assert png.stat().st_size > 10_000 and png.read_bytes()[:4] == b"\x89PNG"


def test_human_summary_and_options():
    p = run("throw", "--speed", "5", "--tilt", "15", "--spin", "10", "--stone", "clanet",
            "--attitude", "fixed", "--force-law", "seed", "--duration", "2")
    assert p.returncode == 0, p.stderr
    assert "bounces over" in p.stdout and "clanet" in p.stdout and "seed" in p.stdout


def test_obj_stone(tmp_path):
    from jaxskip import ellipsoid_pebble, write_obj

    path = tmp_path / "mine.obj"
    write_obj(path, ellipsoid_pebble())
    p = run("throw", "--stone", str(path), "--json", "--mass", "0.08")
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    assert out["parameters"]["mass"] == pytest.approx(0.08)


@pytest.mark.parametrize("args, needle", [
    (["--speed", "0"], "speed"),
    (["--speed", "-3"], "speed"),
    (["--speed", "nan"], "speed"),
    (["--speed", "inf"], "speed"),
    (["--speed", "fast"], "--speed"),
    (["--tilt", "90"], "tilt"),
    (["--tilt", "-95"], "tilt"),
    (["--mass", "0"], "mass"),
    (["--mass", "-1"], "mass"),
    (["--dt", "0"], "dt"),
    (["--dt", "nan"], "dt"),
    (["--duration", "-1"], "duration"),
    (["--duration", "inf"], "duration"),
    (["--stone", "granite"], "granite"),
    (["--stone", "/no/such/stone.obj"], "stone.obj"),
    (["--force-law", "magic"], "force-law"),
    (["--max-steps", "0"], "max_steps"),
    (["--plot", "out.txt"], "--plot"),
])
def test_bad_input_exits_2_without_traceback(args, needle):
    p = run("throw", *args)
    assert p.returncode == 2
    assert "Traceback" not in p.stderr
    assert needle in p.stderr
    assert p.stdout == ""


def test_open_obj_is_refused(tmp_path):
    path = tmp_path / "open.obj"
    path.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n")
    p = run("throw", "--stone", str(path))
    assert p.returncode == 2 and "Traceback" not in p.stderr and "open.obj" in p.stderr


def test_water_field_json_animation_and_picture(tmp_path):
    """--water field: the JSON gains `water` (grid, step, volume change); the GIF and the ripple
    picture are written. A short throw keeps it quick."""
    gif, png = tmp_path / "throw.gif", tmp_path / "ripples.png"
    p = run("throw", "--water", "field", "--json", "--speed", "4", "--duration", "0.15",
            "--animate", str(gif), "--water-plot", str(png))
    assert p.returncode == 0, p.stderr
    out = json.loads(p.stdout)
    w = out["water"]
    assert w["shape"] == [64, 64] and w["spacing"] == 0.01 and 0 < w["time_step"] <= 1e-3
    assert abs(w["volume_change"]) < 0.05
    assert gif.read_bytes()[:6] in (b"GIF89a", b"GIF87a") and gif.stat().st_size > 10_000
    assert png.read_bytes()[:4] == b"\x89PNG"


@pytest.mark.parametrize("args,needle", [
    (("--animate", "x.gif"), "--water field"),
    (("--water", "field", "--animate", "x.png"), "--animate"),
    (("--water", "field", "--water-plot", "x.gif"), "--water-plot"),
    (("--water", "lake"), "--water"),
])
def test_water_flags_bad_input(args, needle):
    p = run("throw", *args)
    assert p.returncode == 2 and needle in p.stderr and "Traceback" not in p.stderr
