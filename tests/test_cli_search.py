"""`jaxskip optimize` and `jaxskip sweep`: JSON out, bad input exits 2 with one line and no traceback."""

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

from jaxskip.cli import main

ROOT = Path(__file__).resolve().parent.parent


@pytest.mark.parametrize("argv, word", [
    (["optimize", "--speed-range", "12", "3"], "--speed-range is inverted"),
    (["optimize", "--tilt-range", "5", "nan"], "--tilt-range must be finite"),
    (["optimize", "--spin", "500"], "--spin must lie within"),
    (["optimize", "--starts", "0"], "--starts must be an integer"),
    (["optimize", "--stone", "granite"], "stone"),
    (["optimize", "--seed", "-1"], "--seed must be an integer >= 0, got -1"),
    (["optimize", "--dt", "0"], "--dt"),
    (["sweep", "umin", "--tilts", "5:x:3"], "--tilts"),
    (["sweep", "umin", "--tilts", "95"], "--tilts must be finite and in (-90, 90)"),
    (["sweep", "umin", "--speed-range", "0", "8"], "--speed-range must lie within (0, 100] m/s"),
    (["sweep", "umin", "--spin", "800"], "--spin must be in [-500, 500] rev/s, got 800.0"),
    (["sweep", "domain", "--speed", "150"], "--speed must be in (0, 100] m/s, got 150.0"),
    (["sweep", "umin", "--c-friction", "-1"], "--c-friction must be in [0, 10]"),
    (["sweep", "merge"], "merge needs"),
    (["optimize", "--polish", "-1"], "--polish"),
    (["optimize", "--horizon", "0"], "--horizon"),
    (["sweep", "domain", "--plot", "out.txt"], "--plot"),
    # a flag the chosen method or kind does not use is refused, not ignored
    (["optimize", "--method", "grid", "--polish", "3"], "--polish is not used by --method grid (only by gradient, "),
    (["optimize", "--samples", "2"], "--samples is not used by --method gradient (only by perturbation)"),
    (["optimize", "--method", "perturbation", "--horizon", "100"], "--horizon is not used by --method perturbation"),
    (["optimize", "--method", "random", "--objective", "distance"], "--objective is not used by --method random"),
    (["optimize", "--method", "grid", "--seed", "1"], "--seed is not used by --method grid"),
    (["optimize", "--throws", "10"], "--throws is not used by --method gradient (only by random)"),
    (["optimize", "--screen", "3"], "--screen must be 0 or at least --starts (8): the starts are the best of the "
                                    "screened throws; got 3"),
    # (session 32, a CLI review) each of these was accepted, or its message named no flag
    (["optimize", "--starts", "100", "--screen", "70"], "--screen must be 0 or at least --starts (100)"),
    (["sweep", "umin", "--attacks", "5,10"], "--attacks must be one angle for a umin sweep, got 2"),
    (["optimize", "--plot", ".pdf"], "--plot needs a file name before its suffix, such as 'out.pdf', got '.pdf'"),
    (["sweep", "umin", "--tilts", "\uff11\uff10"], "--tilts must be A:B:N"),
    (["optimize", "--method", "perturbation", "--screen", "64"], "--screen is not used by --method perturbation"),
    (["sweep", "umin", "--speed", "3"], "--speed is not used by sweep umin (only by domain)"),
    (["sweep", "domain", "--iterations", "3"], "--iterations is not used by sweep domain (only by umin)"),
    (["sweep", "merge", "a", "--out", "m", "--tilts", "5,6"], "--tilts is not used by sweep merge"),
    (["sweep", "merge", "a", "--out", "m", "--chunk-size", "2"], "--chunk-size is not used by sweep merge"),
    (["sweep", "merge", "a", "--out", "m", "--force-law", "seed"], "--force-law is not used by sweep merge"),
    # sharding keeps its chunks in --out: without it the work would be lost
    (["sweep", "umin", "--num-shards", "2"], "--shard-index/--num-shards need --out"),
    (["sweep", "umin", "--shard-index", "0"], "--shard-index/--num-shards need --out"),
    # output paths that cannot be written are refused before the search
    (["optimize", "--plot", "/nonexistent/x.png"], "--plot '/nonexistent/x.png': the folder '/nonexistent' does"),
    (["sweep", "umin", "--plot", "/nonexistent/x.svg"], "--plot"),
    (["sweep", "umin", "--out", "/nonexistent/a/b"], "--out '/nonexistent/a/b': the folder"),
    (["sweep", "merge", "a", "--out", "/nonexistent/a/b"], "--out"),
    # an empty or sloppy list is refused naming its flag and the format (not run as the default list)
    (["sweep", "umin", "--iterations", "1", "--tilts", ""], "--tilts must be A:B:N (N >= 1 values from A to B, finite) or a "
                                                            "comma list of numbers such as 5,10,20 (no empty items)"),
    (["sweep", "umin", "--iterations", "1", "--attacks", ""], "--attacks must be A:B:N"),
    (["sweep", "umin", "--iterations", "1", "--tilts", "5,,10"], "--tilts must be A:B:N"),
    (["sweep", "umin", "--iterations", "1", "--tilts", "5,10,"], "--tilts must be A:B:N"),
    (["sweep", "umin", "--iterations", "1", "--tilts", " , "], "--tilts must be A:B:N"),
    (["sweep", "domain", "--attacks", "10,,20"], "--attacks must be A:B:N"),
    # (session 30) float() and int() read digit-group underscores: 1_0 ran as 10
    (["sweep", "umin", "--iterations", "1", "--tilts", "5,1_0"], "--tilts must be A:B:N"),
    (["sweep", "umin", "--iterations", "1", "--tilts", "5:10:1_0"], "--tilts must be A:B:N"),
    # (session 21) a list starting with a negative number was taken for a flag ("expected one argument");
    # an empty --out wrote the sweep into the current folder
    (["sweep", "umin", "--iterations", "1", "--tilts", "-95,10"], "--tilts must be finite and in (-90, 90)"),
    (["sweep", "umin", "--iterations", "1", "--tilts", "-95:10:3"], "--tilts must be finite and in (-90, 90)"),
    (["sweep", "domain", "--tilts", "10", "--attacks", "-95,0"], "--attacks must be finite and in [-90, 90]"),
    (["sweep", "umin", "--iterations", "1", "--tilts", "10", "--out", ""], "--out must be a folder path, got ''"),
    # (session 22) an oversized A:B:N ended in a MemoryError traceback (7.28 TiB for 10^12 tilts)
    (["sweep", "umin", "--tilts", "5:60:1000000000000"], "--tilts A:B:N must have N <= 100000"),
    (["sweep", "domain", "--tilts", "5:60:100000", "--attacks", "0:30:1000"],
     "their grid must have at most 10000000 points, got 100000 x 1000"),
    # (session 23) inf:5:3 gave NumPy warnings and 'got nan'; a learning rate of 1e308 ran 96 s pinned to the edges
    (["sweep", "umin", "--tilts", "inf:5:3"], "--tilts must be A:B:N (N >= 1 values from A to B, finite)"),
    (["optimize", "--learning-rate", "1e308"], "--learning-rate must be in (0, 10], got 1e+308"),
])
def test_bad_input_exits_2(argv, word, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert word in err and "Traceback" not in err and err.count("\n") == 1


def test_default_screen_grows_to_the_starts(monkeypatch):
    """The screen picks the ascent's starts from its throws: with --starts above the default screen (64) and
    no --screen, the screen is --starts (it was 64, and ``--starts 100`` alone was refused)."""
    import optimize

    class Called(Exception):
        pass

    def fake(box, *, starts=8, screen=0, **kw):
        raise Called(starts, screen)

    monkeypatch.setattr(optimize, "gradient_search", fake)
    for argv, want in ((["--starts", "100"], (100, 100)), ([], (8, 64)), (["--starts", "3", "--screen", "0"], (3, 0))):
        with pytest.raises(Called) as e:
            main(["optimize", "--no-progress", *argv])
        assert e.value.args == want, argv


@pytest.mark.parametrize("argv, word", [
    (["optimize", "--method", "random", "--throws", "1_6"], "argument --throws: must be a whole number, got '1_6'"),
    (["optimize", "--starts", "\uff18"], "argument --starts: must be a whole number"),  # a full-width 8: int() reads it
    (["sweep", "umin", "--chunk-size", " 4"], "argument --chunk-size: must be a whole number, got ' 4'"),
])
def test_count_flags_take_plain_digits_only(argv, word, capsys):
    """(session 32) argparse's int() read 1_6 as 16 and full-width digits as digits: argparse's one-line error."""
    with pytest.raises(SystemExit) as e:
        main(argv)
    err = capsys.readouterr().err
    assert e.value.code == 2 and word in err and err.count("\n") == 1, err


def test_tilt_lists_are_rounded_but_never_past_their_ends():
    """(session 32) A:B:N is rounded to 10 decimals (5:10:6 is 5, 6, ..., 10), which took 89.99999999999 to
    90, outside the tilts' open range: refused though the user gave a valid tilt."""
    from jaxskip.cli_search import _values

    assert _values("5:10:6", "--tilts") == [5.0, 6.0, 7.0, 8.0, 9.0, 10.0]
    assert _values("89.99999999999:89.99999999999:1", "--tilts") == [89.99999999999]
    assert _values("-89.99999999999:89.99999999999:3", "--tilts") == [-89.99999999999, 0.0, 89.99999999999]


def test_bare_sweep_asks_for_the_kind_only(capsys):
    """argparse's own error (exit 2, one line): ``sweep`` needs a kind; FOLDER is only merge's."""
    with pytest.raises(SystemExit) as e:
        main(["sweep"])
    err = capsys.readouterr().err
    assert e.value.code == 2 and err.count("\n") == 1
    assert "the following arguments are required: kind (see 'jaxskip sweep --help')" in err, err


def test_no_traceback_from_the_command():
    p = subprocess.run([sys.executable, "-m", "jaxskip", "optimize", "--speed-range", "3", "3"], capture_output=True,
                       text=True, cwd=ROOT, timeout=120)
    assert p.returncode == 2 and "--speed-range is empty" in p.stderr and "Traceback" not in p.stderr


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
    assert r["config"] == {"stone": "paper", "mass": pytest.approx(0.1207, abs=1e-4), "attitude": "fixed",
                           "integrator": "euler", "force_law": "bocquet", "velocity": "body", "c_lift": 1.0,
                           "c_friction": 0.3, "dt": 2.5e-4, "duration": 5.0, "max_steps": 20250,
                           "bounce_clearance": 1e-3}
    assert r["environment"]["float64"] is True and r["environment"]["jaxskip"]  # the tests run in float64


def test_optimize_prints_the_throw_command_that_reproduces_its_best(capsys):
    """The best throw is printed as a `jaxskip throw` command with every digit and this run's simulation flags;
    the JSON says what that command counts, and running it gives exactly that (the best used to be printed to
    2 digits: 11.55 m/s, 6.7 deg ... gave 6 bounces and a flip against the search's 29)."""
    import shlex

    argv = ["optimize", "--method", "random", "--throws", "8", "--attitude", "fixed", "--dt", "5e-4", "--c-lift", "1.6"]
    assert main(argv + ["--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    words = shlex.split(r["throw_command"])
    assert words[:2] == ["jaxskip", "throw"] and ["--attitude", "fixed"] == words[words.index("--attitude"):][:2]
    assert all(float(words[words.index(f"--{k}") + 1]) == r["best"][k] for k in ("speed", "tilt", "attack", "spin"))
    assert main(words[1:] + ["--json"]) == 0
    t = json.loads(capsys.readouterr().out)
    assert (t["bounces"], t["distance"]) == (r["throw_command_bounces"], r["throw_command_distance"])
    assert (t["parameters"]["dt"], t["parameters"]["c_lift"], t["parameters"]["attitude"]) == (5e-4, 1.6, "fixed")
    assert main(argv) == 0
    assert f"to throw it again: {r['throw_command']}" in capsys.readouterr().out
    assert r["throw_command_energy"] == t["energy"]   # (2026-12-06) its energy too, as the throw command gives it


def test_optimize_says_when_its_best_throw_ran_on_energy_the_water_added(capsys):
    """(2026-12-06, a review) A search over spins up to 200 rev/s returned a record throw whose stone gained energy
    from the water (the default law's known fault), without a word. The summary gives the best throw's energy, and
    notes the gain as `jaxskip throw` does."""
    argv = ["optimize", "--method", "random", "--throws", "4", "--spin-range", "25", "200", "--duration", "0.5",
            "--seed", "0"]
    assert main(argv + ["--json"]) == 0
    energy = json.loads(capsys.readouterr().out)["throw_command_energy"]
    assert energy["peak"] > energy["release"] and energy["gain"] > 0.0
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert f"mechanical energy of the stone: {energy['release']:.3g} J at release" in out
    assert "(the water added energy:" in out and "--velocity passive never adds any" in out


def test_optimize_takes_the_simulation_flags_of_throw(capsys):
    """optimize shares throw's simulation flags: they change the configuration it runs (and reports)."""
    assert main(["optimize", "--method", "random", "--throws", "4", "--dt", "5e-4", "--duration", "2",
                 "--force-law", "seed", "--mass", "0.1", "--velocity", "local", "--json"]) == 0
    c = json.loads(capsys.readouterr().out)["config"]
    assert (c["dt"], c["duration"], c["max_steps"]) == (5e-4, 2.0, 4250)  # the step budget follows dt and duration
    assert (c["force_law"], c["c_friction"], c["mass"]) == ("seed", 0.1, 0.1)
    assert c["velocity"] == "local"


def test_optimize_searches_with_the_given_coefficients(capsys):
    """--c-lift/--c-friction reach the exact simulations of the search: the best throw's reported count
    is what that throw makes with those coefficients, not with the law's own."""
    import numpy as np

    from jaxskip import SimConfig, Throw, simulate_batch, water_params

    assert main(["optimize", "--method", "random", "--throws", "6", "--c-lift", "1.6", "--c-friction", "0.5",
                 "--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert (r["config"]["c_lift"], r["config"]["c_friction"]) == (1.6, 0.5)
    b = r["best"]
    throw = Throw.from_degrees(**{k: np.array([b[k]]) for k in ("speed", "tilt", "attack", "spin")})
    mine = simulate_batch(throw, water=water_params(c_lift=1.6, c_friction=0.5), config=SimConfig(record=False))
    theirs = simulate_batch(throw, config=SimConfig(record=False))
    assert r["best_bounces"] == int(mine.bounces[0]) != int(theirs.bounces[0])


def test_sweep_config_is_reported_and_pinned_to_its_folder(tmp_path, capsys):
    """The sweep's spec carries the resolved simulation configuration (like optimize's `config`); a re-run in
    the same --out with other settings is refused, the same settings resume (nothing recomputed)."""
    out = tmp_path / "s"
    argv = ["sweep", "umin", "--tilts", "20", "--iterations", "1", "--out", str(out), "--json"]
    assert main(argv + ["--force-law", "seed", "--dt", "5e-4"]) == 0
    r = json.loads(capsys.readouterr().out)
    c = r["spec"]["config"]
    assert (c["force_law"], c["c_lift"], c["c_friction"], c["dt"], c["max_steps"]) == ("seed", 1.0, 0.1, 5e-4, 10250)
    assert c["stone"] == "clanet" and c["mass"] == pytest.approx(0.01449, abs=1e-5)
    assert json.loads((out / "result.json").read_text())["spec"]["config"] == c
    stamp = (out / "chunk-00000.json").stat().st_mtime_ns
    assert main(argv) == 2  # the default force law and dt: another sweep
    err = capsys.readouterr().err
    assert "--out" in err and "different sweep" in err and "force_law" in err and "dt" in err
    assert main(argv + ["--force-law", "seed", "--dt", "5e-4"]) == 0
    assert json.loads(capsys.readouterr().out) == r and (out / "chunk-00000.json").stat().st_mtime_ns == stamp


def test_default_sweep_is_sharded(tmp_path, capsys):
    """Default chunks (one tilt for umin): each of two shards computes one tilt; merged they are the sweep."""
    argv = ["sweep", "umin", "--tilts", "10,20", "--iterations", "2", "--json"]
    for i in (0, 1):
        assert main(argv + ["--out", str(tmp_path / f"s{i}"), "--shard-index", str(i), "--num-shards", "2"]) == 0
        assert json.loads(capsys.readouterr().out) == {"complete": False, "out": str(tmp_path / f"s{i}"),
                                                          "shard_index": i, "num_shards": 2, "chunks": 2,
                                                          "chunks_of_this_shard": 1, "warnings": []}
        assert [p.name for p in (tmp_path / f"s{i}").glob("chunk-*.json")] == [f"chunk-0000{i}.json"]
    assert main(["sweep", "merge", str(tmp_path / "s0"), str(tmp_path / "s1"), "--out", str(tmp_path / "m"),
                 "--json"]) == 0
    merged = json.loads(capsys.readouterr().out)
    assert main(argv) == 0
    direct = json.loads(capsys.readouterr().out)
    # the same results; only the run that computed them reports its environment (a merge did not compute)
    assert "environment" not in merged and direct.pop("environment")["float64"] is True
    assert merged.pop("out") == str(tmp_path / "m")   # (the direct run here kept no folder)
    assert direct == merged and merged["umin"][1] is not None


@pytest.mark.parametrize("bad", [["--spin", "800"], ["--stone", "granite"], ["--dt", "0"], ["--mass", "-1"]])
def test_bad_sweep_settings_write_nothing(bad, tmp_path, capsys):
    out = tmp_path / "sp"
    assert main(["sweep", "umin", "--tilts", "20", "--out", str(out), *bad]) == 2
    assert not out.exists() and "Traceback" not in capsys.readouterr().err


def test_a_logged_sweep_shows_its_progress_with_the_flag(tmp_path, monkeypatch, capsys):
    """``jaxskip sweep ... --progress 2> log``: the chunks' progress is written to a stderr that is not a
    terminal (it was silent there); a merge, which computes nothing, refuses the flag."""
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False)
    argv = ["sweep", "umin", "--tilts", "20", "--iterations", "1", "--duration", "0.3", "--out", str(tmp_path / "s")]
    assert main(argv + ["--progress"]) == 0
    err = capsys.readouterr().err
    assert "\r" not in err and "1/1" in err
    assert main(["sweep", "merge", str(tmp_path / "s"), "--out", str(tmp_path / "m"), "--progress"]) == 2
    assert "--progress is not used by sweep merge" in capsys.readouterr().err


def test_optimize_gradient_reports_gradient_norms(tmp_path, capsys, monkeypatch):
    """Gradient-norm monitoring at the CLI: a line of text (and a picture panel), a JSON summary."""
    argv = ["optimize", "--method", "gradient", "--starts", "2", "--iterations", "1", "--attitude", "fixed",
            "--speed-range", "5", "7", "--tilt", "20", "--attack", "10", "--spin", "10", "--polish", "8"]
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)  # a terminal: progress lines on stderr
    assert main(argv + ["--plot", str(tmp_path / "search.png")]) == 0
    text, err = capsys.readouterr()
    # not silent while the gradient compiles: said by the search itself (session 32: the Python API was silent)
    assert "  preparing the gradient program ...\n" in err
    assert re.search(r"  (compiled in \d+\.\d s|reused from an earlier search)\n", err), err
    assert "best 1 bounces" not in err and "smooth count's mean" in err
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False)
    assert "gradient norms (unconstrained units, before clipping): median" in text
    # (2026-12-05) "vanishing on 0" meant "at every iteration" while "exploding" meant "at some": now both say
    assert re.search(r"of 2 starts, exploding \(> 1000\) at some iteration on \d, vanishing \(< 1e-06\) at every "
                     r"iteration on \d and at some iteration on \d\n", text), text
    assert "the polish (8 exact throws near its best throws)" in text
    assert (tmp_path / "search.png").stat().st_size > 10_000
    assert main(argv + ["--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    h = r["gradient_norms"]
    assert h["of"] == 2 and h["starts"]["n"] == 2 and h["max"] >= h["median"] > 0.0
    # 64 screened throws (the default --screen), 2 starts counted twice, 8 polish throws
    assert r["forward_throws"] == 64 + 2 * 2 + 8 and r["history"][-1]["phase"] == "polish"
    assert len(r["history"][0]["screen"]["bounces"]) == 64
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


def test_optimize_distance_reports_the_longest_throw(capsys):
    """--objective distance: the summary and the JSON name the longest true distance, not a count."""
    argv = ["optimize", "--objective", "distance", "--starts", "1", "--iterations", "1", "--polish", "2",
            "--speed", "8", "--tilt", "20", "--spin", "20", "--max-steps", "4000"]
    assert main(argv) == 0
    text = capsys.readouterr().out
    assert text.startswith("gradient search: longest distance ") and " m (" in text
    # (stop 47, a review) what the polish added was said for the count only
    assert "the ascent's farthest: " in text and "the polish (2 exact throws near its farthest): " in text
    assert main(argv + ["--json"]) == 0
    r = json.loads(capsys.readouterr().out)
    assert r["objective"] == "distance" and r["best_distance"] == max(d for h in r["history"] for d in h["distance"])


def test_zero_shards_are_refused_like_negative_ones(tmp_path, capsys):
    """--num-shards 0 is refused (it was taken for 1), before anything is written."""
    for n in ("0", "-1"):
        out = tmp_path / f"p{n}"
        assert main(["sweep", "umin", "--tilts", "20", "--iterations", "1", "--num-shards", n, "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert err == f"jaxskip: error: --num-shards must be an integer >= 1, got {n}\n" and not out.exists()


@pytest.mark.parametrize("name, text, problem", [
    ("chunk-00001.json", "{}", "it lacks 'chunk'"),
    ("chunk-00001.json", '{"chunk": 1, "items": [1], "umin', "not valid JSON: "),
    ("spec.json", "garbage", "not valid JSON: Expecting value"),
], ids=["empty-chunk", "truncated-chunk", "garbage-spec"])
def test_damaged_sweep_file_exits_2_naming_it(tmp_path, capsys, name, text, problem):
    """Resume and merge of a folder with a damaged file: exit 2, one line naming the file and what is wrong
    (not a KeyError traceback, not a bare JSON message)."""
    argv = ["sweep", "umin", "--tilts", "10,20", "--iterations", "1", "--chunk-size", "1", "--out", str(tmp_path / "s")]
    assert main(argv) == 0
    capsys.readouterr()
    (tmp_path / "s" / name).write_text(text)
    for command in (argv, ["sweep", "merge", str(tmp_path / "s"), "--out", str(tmp_path / "m")]):
        assert main(command) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"jaxskip: error: {str(tmp_path / 's' / name)!r} is damaged ({problem}")
        assert err.count("\n") == 1 and "Traceback" not in err
        assert ("delete it" if name.startswith("chunk") else "use a new folder") in err


def test_damaged_spec_values_exit_2_and_write_nothing(tmp_path, capsys):
    """A spec.json whose keys are right but whose values are not (a null ``iterations``) ended merge in a
    TypeError traceback and left a half-written folder: now exit 2 naming the file, before writing."""
    argv = ["sweep", "umin", "--tilts", "10", "--iterations", "1", "--out", str(tmp_path / "s")]
    assert main(argv) == 0
    capsys.readouterr()
    spec = tmp_path / "s" / "spec.json"
    for key, value in (("iterations", None), ("speed_range", [3.0, 1.0]), ("spin", "fast")):
        data = json.loads(spec.read_text())
        good = data[key]
        data[key] = value
        spec.write_text(json.dumps(data))
        assert main(["sweep", "merge", str(tmp_path / "s"), "--out", str(tmp_path / "m")]) == 2
        err = capsys.readouterr().err
        assert err.startswith(f"jaxskip: error: {str(spec)!r} is damaged") and "Traceback" not in err
        assert not (tmp_path / "m").exists()
        data[key] = good
        spec.write_text(json.dumps(data))


def test_a_shard_that_leaves_the_sweep_incomplete_says_there_is_no_picture(tmp_path, capsys):
    """--plot on a shard whose sweep is not complete was skipped in silence: the run now says so."""
    argv = ["sweep", "umin", "--tilts", "10,20", "--iterations", "1", "--out", str(tmp_path / "s"),
            "--shard-index", "0", "--num-shards", "2", "--plot", str(tmp_path / "s.png")]
    assert main(argv) == 0
    assert "no picture: the sweep is not complete here" in capsys.readouterr().out
    assert main(argv + ["--json"]) == 0
    out, err = capsys.readouterr()
    assert json.loads(out) == {"complete": False, "out": str(tmp_path / "s"), "shard_index": 0, "num_shards": 2,
                               "chunks": 2, "chunks_of_this_shard": 1, "plot": None, "warnings": []}
    assert "no picture" in err and not (tmp_path / "s.png").exists()


def _help(argv, capsys) -> str:
    with pytest.raises(SystemExit):
        main(argv + ["--help"])
    return " ".join(capsys.readouterr().out.split())


def test_range_flags_show_the_limits_that_are_checked(capsys):
    """optimize's box limits differ from throw's: each range flag's help names the range its check enforces
    (from the same constants), and so does sweep's."""
    from optimize.bounds import LIMITS
    from optimize.sweep import THROW_LIMITS

    text = _help(["optimize"], capsys)
    for name, (low, high, unit) in LIMITS.items():
        assert f"--{name}-range LOW HIGH search {name} [{unit}] in [LOW, HIGH], within [{low:g}, {high:g}]" in text
        assert f"at this value, in [{low:g}, {high:g}]" in text
    assert "hold spin [rev/s] at this value, in [0, 200]" in text
    assert main(["optimize", "--spin=-10"]) == 2
    assert "--spin must lie within [0, 200] rev/s" in capsys.readouterr().err
    text = _help(["sweep", "umin"], capsys)
    assert THROW_LIMITS["tilt"][:2] == (-90.0, 90.0) and THROW_LIMITS["spin"][:2] == (-500.0, 500.0)
    for flag, shown in (("--tilts", "tilts, each in (-90, 90) degrees"),
                        ("--attacks", "attack angles, each in [-90, 90] degrees"),
                        ("--speed M/S", "speed, in (0, 100] m/s"), ("--speed-range", "within (0, 100] m/s"),
                        ("--spin", "spin, in [-500, 500] rev/s")):
        assert shown in text, flag


def test_umin_text_words_the_bisection_bracket(tmp_path, capsys):
    """The reported U_min is the top of the bisection's last bracket: the text says the true value lies in
    (U - resolution, U]; a tilt that never bounces reads 'no bounce at the 10 speeds thrown from 0.5 to 8 m/s'; one that bounces at the
    bracket's low end reads 'U_min <= LOW'."""
    out = tmp_path / "s"
    assert main(["sweep", "umin", "--tilts", "5,20,60", "--iterations", "3", "--out", str(out)]) == 0
    text = capsys.readouterr().out
    r = json.loads((out / "result.json").read_text())
    u, res = r["best_umin"], r["resolution"]
    assert r["best_tilt"] == 20.0 and r["umin"][2] is None and res == (8.0 - 0.5) / 9 / 2 ** 3
    assert "tilt   60.0 deg: no bounce at the 10 speeds thrown from 0.5 to 8 m/s\n" in text and "(no bounce)" not in text
    assert f"magic angle: 20 deg, U_min {u:.2f} m/s (bisection: the true U_min lies in ({u - res:.2f}, {u:.2f}] m/s"\
        in text and "+-" not in text
    assert main(["sweep", "umin", "--tilts", "20,60", "--iterations", "1", "--speed-range", "2.5", "8"]) == 0
    text = capsys.readouterr().out
    assert "tilt   20.0 deg: U_min <= 2.5 m/s (bounces at the bracket's low end)" in text
    assert ("magic angle: 20 deg, U_min <= 2.5 m/s (it bounces at the bracket's low end: U_min <= 2.5 m/s, as at "
            "tilts 20 deg; the minimum lies among them (lower --speed-range))") in text
    # (session 32, a review) tilts that tie named the first of them "the magic angle". (Their U_min, 1.85 and
    # 1.96 m/s, lie in one interval of the scan, (1.33, 2.17]; one bisection step at 1.75 m/s leaves both there.)
    assert main(["sweep", "umin", "--tilts", "15,20", "--iterations", "1"]) == 0
    text = capsys.readouterr().out
    assert text.count("U_min 2.17 m/s") == 3, text
    assert ("magic angle: no single minimum: tilts 15, 20 deg tie at U_min 2.17 m/s (bisection: the true U_min "
            "lies in (1.75, 2.17] m/s, a bracket of 0.42 m/s; more --iterations narrow the bracket)") in text
    assert "between grid points" not in text


def test_count_flags_show_the_ranges_that_are_checked(capsys):
    """Every count flag's help gives its valid range, from the constants the searches and sweeps check (not
    copied by hand): a value just outside it is refused naming the flag."""
    text = _help(["optimize"], capsys)
    for shown in ("random starts, in [1, 4096] (default 8)", "gradient: N Adam steps (N + 1 exact evaluations of the starts); perturbation: N evaluations of the centres, N - 1 steps between them; in [1, 10^5] (default 20)",
                  "Adam step in the unconstrained coordinates [-], in (0, 10] (default 0.3)",
                  "after the ascent, in [0, 10^8] (default 256; 0: none)",
                  "per start and iteration, in [1, 4096] (default 8)",
                  "differentiated through, in [1, --max-steps] (default: the whole rollout)",
                  "grid points per searched parameter, in [2, 10^4], at most 10^8 grid points in all (default 6)",
                  "random throws, in [1, 10^8] (default 1000)"):
        assert shown in text, shown
    text = _help(["sweep", "umin"], capsys)
    for shown in ("bisection steps, in [1, 40] (default 10)", "work items per chunk file, >= 1:",
                  "this machine's shard, in [0, N-1] for --num-shards N (default 0; needs --out; required when "
                  "N > 1)",
                  "machines sharing the sweep, >= 1 (default 1; needs --out)"):
        assert shown in text, shown
    from optimize.search import MAX_ITERATIONS, MAX_PER_AXIS, MAX_SAMPLES, MAX_STARTS, MAX_THROWS
    from optimize.sweep import MAX_BISECTIONS

    assert (MAX_STARTS, MAX_ITERATIONS, MAX_SAMPLES, MAX_THROWS, MAX_PER_AXIS, MAX_BISECTIONS) == (
        4096, 10 ** 5, 4096, 10 ** 8, 10 ** 4, 40)
    for argv, refused in (
            (["optimize", "--starts", str(MAX_STARTS + 1)], f"--starts must be an integer in [1, {MAX_STARTS}]"),
            (["optimize", "--iterations", str(MAX_ITERATIONS + 1)], "--iterations must be an integer in [1, 100000]"),
            (["optimize", "--method", "perturbation", "--samples", "0"], "--samples must be an integer in [1, 4096]"),
            (["optimize", "--method", "grid", "--per-axis", "1"], "--per-axis must be an integer in [2, 10000]"),
            (["optimize", "--method", "random", "--throws", "0"], "--throws must be an integer in [1, 100000000]"),
            (["optimize", "--learning-rate", "0"], "--learning-rate must be in (0, 10], got 0.0"),
            (["optimize", "--horizon", "5001", "--max-steps", "5000"], "--horizon must be at most the step budget, 5000 "
                                                                      "steps"),
            (["sweep", "umin", "--iterations", str(MAX_BISECTIONS + 1)], "--iterations must be an integer in [1, 40]"),
            (["sweep", "umin", "--chunk-size", "0"], "--chunk-size must be an integer >= 1"),
            (["sweep", "umin", "--out", "x", "--num-shards", "2", "--shard-index", "2"],
             "--shard-index must be an integer in [0, 1]")):
        assert main(argv) == 2, argv
        assert refused in capsys.readouterr().err, argv


def test_shard_flags_say_what_is_missing_or_idle(tmp_path, capsys):
    """--shard-index without --num-shards said "--shard-index must be an integer in [0, 0], got 1"; a shard
    beyond the sweep's chunks said it was done, with no chunk in its folder."""
    argv = ["sweep", "domain", "--tilts", "20", "--attacks", "20", "--max-steps", "400"]
    assert main(argv + ["--shard-index", "1", "--out", str(tmp_path / "a")]) == 2
    assert capsys.readouterr().err == ("jaxskip: error: --shard-index needs --num-shards N (the number of machines "
                                       "sharing the sweep)\n")
    # (stop 47, a review) --num-shards 2 alone ran shard 0: a second machine that forgot its index repeated it
    assert main(argv + ["--num-shards", "2", "--out", str(tmp_path / "c")]) == 2
    assert capsys.readouterr().err == ("jaxskip: error: --num-shards 2 needs --shard-index I, this machine's shard, "
                                       "in [0, 1]\n") and not (tmp_path / "c").exists()
    assert main(argv + ["--num-shards", "1", "--out", str(tmp_path / "d")]) == 0   # one machine: its only shard
    capsys.readouterr()
    assert main(argv + ["--shard-index", "1", "--num-shards", "2", "--out", str(tmp_path / "b")]) == 0
    out = capsys.readouterr().out
    assert out.startswith("shard 1/2 has no chunk to compute: the sweep has only 1 (for the shards below 1)"), out
    assert not list((tmp_path / "b").glob("chunk-*.json"))


def test_optimize_and_sweep_print_each_warning_once_and_mark_diverged_throws(tmp_path, capsys):
    """A search or sweep printed a stability warning per batch (each at its own speed), its coarse-dt warning
    again after every batch, and nothing of its diverged throws but per-batch indices. Now: one line each,
    and the summary says which tilts have no U_min. A light disk at a 2 ms step: 25-50 m/s diverge."""
    light = ["--density", "100", "--dt", "0.002", "--max-steps", "2000", "--spin", "10"]
    assert main(["optimize", "--method", "random", "--throws", "24", "--speed-range", "10", "50", "--tilt", "20",
                 "--attack", "10", "--stone", "clanet", "--attitude", "fixed", *light]) == 0
    err = capsys.readouterr().err.splitlines()
    assert sum("resolves a contact" in line for line in err) == 1  # the coarse dt
    assert sum("throws of this random search diverged" in line for line in err) == 1
    assert main(["sweep", "umin", "--tilts", "20,30", "--speed-range", "0.5", "40", "--iterations", "3",
                 "--out", str(tmp_path / "s"), *light]) == 0
    captured = capsys.readouterr()
    assert sum("resolves a contact" in line for line in captured.err.splitlines()) == 1
    assert sum("U_min sweep diverged" in line for line in captured.err.splitlines()) == 1
    assert "tilt   20.0 deg: no U_min:" in captured.out and "of its throws (scan and bisection) diverged" in captured.out
    rows = (tmp_path / "s" / "result.csv").read_text().splitlines()
    assert rows[0].endswith(",diverged,cut_off,monotone,umin_low_m_s") and rows[1].split(",")[-4:-2] != ["0", "0"]


def test_sweep_says_which_answers_the_duration_cut_off(tmp_path, capsys):
    """A U_min tilt whose bisection met throws still in their first contact at --duration read 'no bounce up to
    8 m/s' (or a U_min too high); a domain sweep's counts of throws still skipping read as final."""
    assert main(["sweep", "umin", "--tilts", "20", "--iterations", "3", "--duration", "0.05"]) == 0
    out = capsys.readouterr().out
    assert "tilt   20.0 deg: no U_min:" in out and "when --duration 0.05 s or --max-steps 250 stopped them (raise" in out, out
    # a magic angle found among tilts some of which have no U_min says the minimum may lie at those
    assert main(["sweep", "umin", "--tilts", "5,20,30", "--iterations", "3", "--duration", "0.3"]) == 0
    out = capsys.readouterr().out
    assert "magic angle: 20 deg" in out and "(tilt 5 deg has no U_min, above: the minimum may lie there)" in out, out
    assert main(["sweep", "domain", "--tilts", "20", "--attacks", "20", "--duration", "0.05"]) == 0
    out = capsys.readouterr().out
    assert "1 still skipping when --duration 0.05 s or --max-steps 250 stopped them (their counts are lower" in out, out


def test_review_nits_of_the_search_commands(tmp_path, capsys):
    """(2026-12-06, a review) --no-progress on a merge was named --progress; --horizon beyond the step budget
    named a range without saying where its top came from; optimize --json recorded the stone as 'a RigidStone
    of 0.120663 kg'; a shard's JSON did not say which shard it was, a complete sweep's not where it was."""
    assert main(["sweep", "merge", str(tmp_path / "a"), "--out", str(tmp_path / "m"), "--no-progress"]) == 2
    assert "--no-progress is not used by sweep merge" in capsys.readouterr().err
    assert main(["optimize", "--horizon", "99999", "--duration", "0.5"]) == 2
    assert ("--horizon must be at most the step budget, 2250 steps (config.max_steps, --max-steps in the CLI: 0.562 s "
            "of fine steps at dt 0.00025 s; the duration is 0.5 s), got 99999") in capsys.readouterr().err
    # (2026-12-07, a review) an explicit --max-steps 100 read '100 steps (...; 5 s at dt 0.00025 s)'
    assert main(["optimize", "--horizon", "200", "--max-steps", "100"]) == 2
    assert "100 steps (config.max_steps, --max-steps in the CLI: 0.025 s of fine steps" in capsys.readouterr().err
    # a U_min sweep's bracket cannot be held at one value (that advice is a search box's)
    assert main(["sweep", "umin", "--speed-range", "2", "2"]) == 2
    err = capsys.readouterr().err
    assert "--speed-range is empty" in err and "hold" not in err, err
    # A:B:1 with A != B dropped B in silence
    assert main(["sweep", "domain", "--tilts", "5:60:1", "--attacks", "10"]) == 2
    assert "--tilts A:B:1 is one value, but A (5) and B (60) differ" in capsys.readouterr().err
    assert main(["optimize", "--method", "random", "--throws", "2", "--duration", "0.2", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["settings"]["stone"] == "paper"
    argv = ["sweep", "umin", "--tilts", "10,20", "--iterations", "1", "--duration", "0.5", "--chunk-size", "1", "--json"]
    assert main([*argv, "--out", str(tmp_path / "p1"), "--shard-index", "1", "--num-shards", "2"]) == 0
    shard = json.loads(capsys.readouterr().out)
    assert (shard["complete"], shard["shard_index"], shard["num_shards"], shard["chunks"],
            shard["chunks_of_this_shard"]) == (False, 1, 2, 2, 1)
    assert main([*argv, "--out", str(tmp_path / "whole")]) == 0
    whole = json.loads(capsys.readouterr().out)
    assert whole["complete"] and whole["out"] == str(tmp_path / "whole")
