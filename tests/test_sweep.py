"""Magic-angle sweeps: physics of U_min(tilt), resumption after a kill, shards, several devices."""

import functools
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from jaxskip import MeshError, ParameterError
from optimize import make_spec, merge, parabola_minimum, run_sweep
from optimize.sweep import DOMAIN_CHUNK, default_chunk_size

ROOT = Path(__file__).resolve().parent.parent


def small_domain():
    return make_spec("domain", tilts=[10.0, 30.0], attacks=[10.0, 40.0], speed=3.5, chunk_size=1)


def test_umin_has_a_magic_angle():
    """Clanet disk, fixed attitude, beta = 20 deg, 65 rev/s: of 5, 20, 40 and 60 deg U_min is lowest at 20 deg
    (the model's minimum lies at ~14 deg), within 30 % of 2.5 m/s,
    and a disk tilted 60 deg does not bounce below 8 m/s (physics.md section 4)."""
    spec = make_spec("umin", tilts=[5.0, 20.0, 40.0, 60.0], speed_range=(0.5, 8.0), iterations=6)
    r = run_sweep(spec)
    u = r["umin"]
    assert u[3] is None and r["bounces_at_high"][3] == 0
    assert r["best_tilt"] == 20.0 and abs(r["best_umin"] - 2.5) < 0.3 * 2.5
    assert u[0] > u[1] and u[2] > u[1]
    assert 5.0 < r["best_tilt_fit"] < 40.0


def _umin_curve(stone, tilts, config, iterations: int) -> np.ndarray:
    """U_min [m/s] at each of ``tilts`` [deg] (tilt held by ``config``, beta = 20 deg, 65 rev/s: Clanet's reference
    conditions), bisected ``iterations`` times in [1, 3] m/s (2 m/s / 2^iterations)."""
    from jaxskip import Throw, simulate_batch

    lo, hi = np.full(tilts.size, 1.0), np.full(tilts.size, 3.0)
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        ok = simulate_batch(Throw.from_degrees(speed=mid, tilt=tilts, attack=20.0, spin=65.0), stone,
                            config=config).bounces > 0
        hi, lo = np.where(ok, mid, hi), np.where(ok, lo, mid)
    return hi


@functools.lru_cache(maxsize=1)
def _clanet_umin_curve():
    """U_min(tilt) of the Clanet disk at its reference conditions, tilts 11-20 deg every 1.5 deg, to ~1e-3 m/s:
    (tilts, U_min) [deg, m/s] as tuples (computed once per process for the two tests that read it)."""
    from jaxskip import SimConfig, clanet_disk, rigid_stone
    from jaxskip.stones import ALUMINIUM_DENSITY

    tilts = np.arange(11.0, 20.5, 1.5)
    umin = _umin_curve(rigid_stone(clanet_disk(), density=ALUMINIUM_DENSITY), tilts,
                       SimConfig(record=False, attitude="fixed", max_steps=5000), iterations=11)
    return tuple(tilts.tolist()), tuple(umin.tolist())


@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "Known miss (issue 4): the model's magic angle, the vertex of U_min(tilt) for the Clanet disk at its "
    "reference conditions, is 14.0-14.5 deg (1.74-1.75 m/s); Clanet et al. put it between 15 and 25 deg. Converged "
    "in mesh and dt to that range (next test); docs/model.md, 'Calibration', gives the physical reason. Not tuned "
    "away."))
def test_magic_angle_lies_between_15_and_25_degrees():
    tilts, umin = _clanet_umin_curve()
    vertex, _ = parabola_minimum(tilts, umin)
    assert 15.0 <= vertex <= 25.0, (vertex, dict(zip(tilts, umin)))


@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "Known miss (issue 4), by a hair: U_min at the model's magic angle is 1.741-1.745 m/s, 30.2-30.4 % below "
    "Clanet's ~2.5 m/s, where the issue asks for within 30 % (>= 1.75 m/s). It read 1.76 m/s, 29.6 % below and "
    "met, until 2026-12-07, when the tracker stopped missing the first hop near U_min (a flight jump from the "
    "first dry step crossed it and merged it into the contact; fixed steps, the reference, agree with the jumps "
    "now to 1e-3 m/s). Not tuned away."))
def test_umin_at_the_magic_angle_is_within_30_percent_of_clanets():
    tilts, umin = _clanet_umin_curve()
    _, lowest = parabola_minimum(tilts, umin)
    assert abs(lowest - 2.5) <= 0.3 * 2.5, (lowest, dict(zip(tilts, umin)))


def test_magic_angle_is_converged_in_mesh_and_time_step():
    """The model's U_min(tilt) minimum (Clanet disk, fixed tilt, beta = 20 deg, 65 rev/s) is the same
    with a 32- or a 128-segment rim and with dt = 0.25 or 0.125 ms: U_min moves by < 0.5 % and the vertex
    stays in [13.5, 15) deg, below Clanet's 15-25 deg window in every discretisation, so the miss is the
    model's, not its discretisation's (benchmarks/README.md, session 14). Measured 2026-12-07: vertices 13.97 /
    14.52 / 14.12 deg, U_min 1.7446 / 1.7415 / 1.7454 m/s; fixed-step flight gives 13.94 / 14.51 deg. Until that
    day the vertex was asserted to move by < 0.3 deg (14.1-14.3 deg): the tracker then missed the first hop near
    U_min where a flight jump crossed it, and the 128-segment vertex read 14.12 deg against fixed steps' 14.51.
    The minimum is flat (at 128 segments U_min at 14 and 15 deg differ by 0.3 mm/s), so its vertex moves by
    0.55 deg with the mesh."""
    from jaxskip import SimConfig, disk, rigid_stone
    from jaxskip.stones import ALUMINIUM_DENSITY

    tilts = np.arange(12.0, 17.5, 1.0)
    found = []
    for segments, dt in ((32, 2.5e-4), (128, 2.5e-4), (32, 1.25e-4)):
        stone = rigid_stone(disk(0.025, 0.00275, segments), density=ALUMINIUM_DENSITY)
        config = SimConfig(record=False, attitude="fixed", dt=dt, max_steps=int(round(5000 * 2.5e-4 / dt)))
        found.append(parabola_minimum(tilts, _umin_curve(stone, tilts, config, iterations=14)))   # ~1e-4 m/s
    vertices, umins = np.array([f[0] for f in found]), np.array([f[1] for f in found])
    assert np.all((13.5 <= vertices) & (vertices < 15.0)) and np.ptp(umins) < 0.005 * umins.mean(), found


def test_parabola_minimum_finds_the_vertex_between_grid_points():
    """Exact for a quadratic on an uneven grid, in any order; refuses a minimum at the edge."""
    x = np.array([20.0, 8.0, 11.0, 14.0, 16.5])
    y = 0.004 * (x - 12.3) ** 2 + 1.76
    xs, ys = parabola_minimum(x, list(y))
    assert abs(xs - 12.3) < 1e-9 and abs(ys - 1.76) < 1e-12
    # A cubic term moves the vertex, but it stays between the lowest point's neighbours.
    y3 = y + 1e-4 * (x - 12.3) ** 3
    xs3, _ = parabola_minimum(x, list(y3))
    assert 11.0 < xs3 < 14.0 and abs(xs3 - 12.3) > 1e-3
    assert parabola_minimum([5.0, 10.0, 15.0], [1.0, 2.0, 3.0]) == (None, None)    # lowest at the edge
    assert parabola_minimum([5.0, 10.0, 15.0], [None, 1.0, 2.0]) == (None, None)   # neighbour missing
    assert parabola_minimum([5.0, 10.0, 15.0], [None, None, None]) == (None, None)
    assert parabola_minimum([5.0, 10.0, 15.0], [1.0, 1.0, 1.0]) == (None, None)    # level: the first is lowest
    assert parabola_minimum([5.0, 10.0, 15.0, 20.0], [2.0, 1.0, 1.0, 2.0])[0] == 12.5  # a flat bottom: its middle
    assert parabola_minimum([5.0, 10.0, 15.0], [np.nan, 1.0, 2.0]) == (None, None)  # NaN counts as missing
    assert np.allclose(parabola_minimum([5.0, 10.0, 10.0, 20.0], [2.0, 1.0, 1.0, 2.0]), (12.5, 0.875))  # repeated tilt
    with pytest.raises(ParameterError, match="same length"):
        parabola_minimum([5.0, 10.0, 15.0], [1.0, 2.0])


def test_interrupted_sweep_resumes_to_the_same_file(tmp_path):
    spec = small_domain()
    whole = run_sweep(spec, tmp_path / "whole")
    with pytest.raises(KeyboardInterrupt):
        run_sweep(spec, tmp_path / "cut", _stop_after=2)
    done = sorted(p.name for p in (tmp_path / "cut").glob("chunk-*.json"))
    assert done == ["chunk-00000.json", "chunk-00001.json"]
    assert not list((tmp_path / "cut").glob("*.tmp"))
    stamp = (tmp_path / "cut" / "chunk-00000.json").stat().st_mtime_ns
    resumed = run_sweep(spec, tmp_path / "cut")
    assert (tmp_path / "cut" / "chunk-00000.json").stat().st_mtime_ns == stamp  # not recomputed
    assert resumed == whole
    for name in ("result.json", "result.csv"):
        assert (tmp_path / "cut" / name).read_bytes() == (tmp_path / "whole" / name).read_bytes()
    assert sum(map(sum, whole["bounces"])) > 0 and min(map(min, whole["bounces"])) == 0  # a real boundary


def test_sweep_killed_mid_way_and_rerun_gives_the_same_files(tmp_path):
    """The CLI sweep killed (SIGKILL) after its first chunk file and run again gives byte-identical
    result files to an uninterrupted run, without recomputing the chunk it had finished."""
    import signal
    import time

    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
    argv = [sys.executable, "-m", "jaxskip", "sweep", "umin", "--tilts", "8:40:5", "--iterations", "8",
            "--chunk-size", "1"]
    cut, whole = tmp_path / "cut", tmp_path / "whole"
    proc = subprocess.Popen(argv + ["--out", str(cut)], env=env, cwd=ROOT, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    first = cut / "chunk-00000.json"
    deadline = time.monotonic() + 300
    while not first.exists() and proc.poll() is None and time.monotonic() < deadline:
        time.sleep(0.005)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    done = list(cut.glob("chunk-*.json"))
    assert first.exists() and len(done) < 5 and not (cut / "result.json").exists()  # killed mid-way
    stamp = first.stat().st_mtime_ns
    subprocess.run(argv + ["--out", str(cut)], env=env, cwd=ROOT, check=True, capture_output=True, timeout=600)
    subprocess.run(argv + ["--out", str(whole)], env=env, cwd=ROOT, check=True, capture_output=True, timeout=600)
    assert first.stat().st_mtime_ns == stamp  # the finished chunk was kept, not recomputed
    for name in ("result.json", "result.csv"):
        assert (cut / name).read_bytes() == (whole / name).read_bytes()


def test_shards_and_merge_equal_one_machine(tmp_path):
    spec = small_domain()
    whole = run_sweep(spec, tmp_path / "whole")
    assert run_sweep(spec, tmp_path / "s0", shard_index=0, num_shards=2) is None  # the other shard is missing
    assert run_sweep(spec, tmp_path / "s1", shard_index=1, num_shards=2) is None
    with pytest.raises(ParameterError, match="chunks missing"):
        merge([tmp_path / "s0"], tmp_path / "merged0")
    merged = merge([tmp_path / "s0", tmp_path / "s1"], tmp_path / "merged")
    assert merged == whole
    assert merge(str(tmp_path / "merged"), tmp_path / "again") == whole  # one folder, not in a list
    with pytest.raises(ParameterError, match="folders must be a path or a list of paths, got int"):
        merge(5, tmp_path / "bad")
    assert (tmp_path / "merged" / "result.csv").read_bytes() == (tmp_path / "whole" / "result.csv").read_bytes()


def test_a_chunk_of_another_sweep_is_refused_and_every_chunk_is_checked_before_any_is_computed(tmp_path):
    """(stop 47, a review) A chunk file copied in from another sweep of the same layout (9 bisections where the
    spec says 10) was kept in silence: a chunk names its sweep now (``"sweep"``, :func:`optimize.sweep.sweep_id`)
    and another sweep's is refused, by run_sweep and by merge. A damaged chunk was found only when the loop
    reached it, after computing the chunks before it: every chunk in the folder is checked first."""
    from optimize.sweep import sweep_id

    def spec(iterations):
        return make_spec("umin", tilts=[10.0, 20.0, 30.0], iterations=iterations, chunk_size=1, max_steps=2000)

    ten, nine = spec(10), spec(9)
    assert sweep_id(ten) != sweep_id(nine)
    run_sweep(nine, tmp_path / "nine")
    with pytest.raises(KeyboardInterrupt):
        run_sweep(ten, tmp_path / "ten", _stop_after=1)
    assert json.loads((tmp_path / "ten" / "chunk-00000.json").read_text())["sweep"] == sweep_id(ten)
    copied = tmp_path / "ten" / "chunk-00002.json"
    copied.write_bytes((tmp_path / "nine" / "chunk-00002.json").read_bytes())
    with pytest.raises(ParameterError, match=r"chunk-00002.json' is damaged \(its 'sweep' is not this folder's: it is "
                                             r"a chunk of another sweep"):
        run_sweep(ten, tmp_path / "ten")
    assert not (tmp_path / "ten" / "chunk-00001.json").exists()   # refused before chunk 1 was computed
    with pytest.raises(ParameterError, match="a chunk of another sweep"):
        merge([tmp_path / "ten"], tmp_path / "merged")
    copied.unlink()
    whole = run_sweep(ten, tmp_path / "ten")
    assert whole == run_sweep(ten, None)
    # a chunk written before chunks named their sweep (no "sweep") is checked as before, and kept
    old = json.loads(copied.read_text())
    del old["sweep"]
    copied.write_text(json.dumps(old, sort_keys=True))
    (tmp_path / "ten" / "result.json").unlink()
    assert run_sweep(ten, tmp_path / "ten") == whole


def test_merge_refuses_two_copies_of_a_chunk_that_differ(tmp_path):
    """(stop 47, a review) Merging folders that both held chunk 0, with other values (shards computed twice, on
    machines that round differently), took the first copy in silence."""
    spec = small_domain()
    whole = run_sweep(spec, tmp_path / "a")
    run_sweep(spec, tmp_path / "b")
    assert merge([tmp_path / "a", tmp_path / "b"], tmp_path / "ab") == whole   # equal copies: fine
    path = tmp_path / "b" / "chunk-00000.json"
    data = json.loads(path.read_text())
    data["bounces"] = [data["bounces"][0] + 1]
    path.write_text(json.dumps(data, sort_keys=True))
    with pytest.raises(ParameterError, match=r"chunk-00000.json' and '.*chunk-00000.json' are two copies of chunk 0 "
                                             r"that differ"):
        merge([tmp_path / "a", tmp_path / "b"], tmp_path / "ab2")


def test_a_first_contact_cut_off_by_the_time_limit_has_no_duration():
    """(stop 47, a review) A domain sweep gave a "first contact time" of 0.279 s, with 0 bounces, for a contact
    the duration (0.3 s) cut off: its end was the run's. It is None now, as where a contact never ended in a
    bounce (the throw with 5 s sinks in that contact)."""
    cut = run_sweep(make_spec("domain", tilts=[5.0], attacks=[0.0], speed=6.0, duration=0.3), None)
    assert cut["cut_off"] == [[1]] and cut["bounces"] == [[0]] and cut["first_contact_time"] == [[None]]
    bounced = run_sweep(make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5, duration=0.3), None)
    assert bounced["bounces"][0][0] > 0 and 0.0 < bounced["first_contact_time"][0][0] < 0.05


def test_folder_of_another_sweep_is_refused(tmp_path):
    run_sweep(make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5), tmp_path)
    with pytest.raises(ParameterError, match="different sweep"):
        run_sweep(make_spec("domain", tilts=[25.0], attacks=[20.0], speed=3.5), tmp_path)
    # the simulation's configuration is part of the sweep: another stone mass is another sweep
    with pytest.raises(ParameterError, match=r"different sweep \(its spec.json differs in config, mass: it has "
                                             r"mass=0.01\d+\); give those settings to resume it"):
        run_sweep(make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5, mass=0.02), tmp_path)
    # a default that changed (max_steps 20000 before session 17) is named with its old value: passing it resumes
    spec = make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5, max_steps=20000)
    with pytest.raises(ParameterError, match=r"differs in config, max_steps: it has max_steps=20250\)"):
        run_sweep(spec, tmp_path)


def test_bounce_clearance_is_part_of_a_sweep_and_older_folders_resume(tmp_path):
    """What counts as a bounce (``bounce_clearance`` [m], ``--bounce-clearance``) moves a sweep's answer, so
    spec.json records it: another clearance is refused in the folder, naming it; a folder written before it was
    recorded (its spec.json without it: every such sweep used the 1 mm default) resumes as the same sweep, to
    the same files."""
    spec = small_domain()
    whole = run_sweep(spec, tmp_path / "whole")
    high = make_spec("domain", tilts=[10.0, 30.0], attacks=[10.0, 40.0], speed=3.5, chunk_size=1,
                     bounce_clearance=0.01)
    assert high.bounce_clearance == 0.01 and high.config["bounce_clearance"] == 0.01
    assert run_sweep(high, None)["bounces"] == [[1, 0], [0, 0]] != whole["bounces"] == [[4, 0], [1, 0]]
    with pytest.raises(ParameterError, match=r"different sweep \(its spec.json differs in bounce_clearance, config: "
                                              r"it has bounce_clearance=0.001"):
        run_sweep(high, tmp_path / "whole")
    with pytest.raises(KeyboardInterrupt):
        run_sweep(spec, tmp_path / "old", _stop_after=2)
    path = tmp_path / "old" / "spec.json"
    data = json.loads(path.read_text())
    del data["bounce_clearance"], data["config"]["bounce_clearance"]   # as an older jaxskip wrote it
    path.write_text(json.dumps(data, sort_keys=True, indent=1))
    assert run_sweep(spec, tmp_path / "old") == whole
    for name in ("result.json", "result.csv"):
        assert (tmp_path / "old" / name).read_bytes() == (tmp_path / "whole" / name).read_bytes()
    with pytest.raises(ParameterError, match="differs in bounce_clearance"):
        run_sweep(high, tmp_path / "old")


def test_a_folder_of_another_sweep_is_named_briefly(tmp_path):
    """The refusal quotes a long grid by its ends and length (it quoted all 40 tilts: a 2 kB 'one line'), and
    a merge is told to merge elsewhere (it was told to give settings that merge does not take)."""
    tilts = [float(t) for t in np.linspace(5.0, 60.0, 40)]
    run_sweep(make_spec("domain", tilts=tilts, attacks=[20.0], speed=3.5, max_steps=400), tmp_path / "big")
    small = make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5, max_steps=400)
    with pytest.raises(ParameterError) as err:
        run_sweep(small, tmp_path / "big")
    message = str(err.value)
    assert "tilts=[5.0, 6.41" in message and "60.0] (40 values)" in message and len(message) < 500, message
    run_sweep(small, tmp_path / "small")
    with pytest.raises(ParameterError, match=r"it has tilts=\[5.0, .*\(40 values\)\); merge into a new folder"):
        merge([tmp_path / "small"], tmp_path / "big")


def test_an_empty_out_dir_is_refused(tmp_path, monkeypatch):
    """run_sweep(spec, "") wrote chunk and result files into the current folder (Path("") is "."); the CLI
    refused an empty --out, the API did not. Big grids are refused before any work too."""
    monkeypatch.chdir(tmp_path)
    spec = make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5)
    for empty in ("", "  "):
        with pytest.raises(ParameterError, match="out_dir must be a folder path, got"):
            run_sweep(spec, empty)
    assert list(tmp_path.iterdir()) == []
    # a folder where a chunk file belongs: named (was "[Errno 21] Is a directory")
    (tmp_path / "s" / "chunk-00000.json").mkdir(parents=True)
    with pytest.raises(ParameterError, match=r"chunk-00000.json' is a folder, not a file; "):
        run_sweep(spec, tmp_path / "s")
    with pytest.raises(ParameterError, match="tilts must hold at most 100000 angles, got 100001"):
        make_spec("umin", tilts=np.linspace(5.0, 60.0, 100_001))


def test_no_parabola_through_speeds_that_are_only_bounds(tmp_path):
    """Where the bracket's low end already bounces, U_min is only a bound (<= low): the fit drew a parabola
    through such bounds and put the magic angle at 12 deg, 1.79 m/s (a wide bracket: 14 deg, 1.76 m/s).
    The CSV says which speeds are bounds."""
    from optimize.sweep import assemble, write_results

    spec = make_spec("umin", tilts=[6.0, 12.0, 18.0, 24.0], speed_range=(1.85, 6.0), iterations=6)
    chunk = {"umin": [2.30, 1.85, 1.85, 2.04], "bounces_at_high": [1, 1, 1, 1], "bounces_at_low": [0, 1, 1, 0],
             "diverged": [0, 0, 0, 0], "cut_off": [0, 0, 0, 0], "monotone": [1, 1, 1, 1]}
    r = assemble(spec, [chunk])
    assert r["best_tilt_fit"] is None and r["best_umin_fit"] is None and r["best_umin"] == 1.85
    write_results(r, tmp_path)
    rows = (tmp_path / "result.csv").read_text().splitlines()
    assert rows[0].endswith(",umin_m_s,bounces_at_high,bounces_at_low,diverged,cut_off,monotone,umin_low_m_s")
    assert rows[2].endswith(",1.85,1,1,0,0,1,")                       # a bound: no low end
    # a bracketed U_min gives its bracket, (umin - resolution, umin] (stop 47: the file alone did not say; the new
    # column last, so that columns read by position read as before)
    high, low = float(rows[1].split(",")[3]), float(rows[1].split(",")[-1])
    assert high == 2.30 and high - low == pytest.approx(r["resolution"], rel=1e-12)
    r = assemble(spec, [dict(chunk, bounces_at_low=[0, 0, 0, 0], umin=[2.30, 1.90, 1.88, 2.04])])
    assert 12.0 < r["best_tilt_fit"] < 18.0  # measured speeds: the parabola stands


def test_a_sweep_is_resumed_and_merged_only_in_its_precision(tmp_path):
    """spec.json pins the precision a sweep is computed in: a float32 folder (written by the API without
    x64) was resumed in float64, or merged with a float64 shard, without a word."""
    spec = make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5)
    assert spec.config["precision"] == "float64"  # the tests compute in float64
    data = spec.to_dict()
    data["config"]["precision"] = "float32"
    (tmp_path / "spec.json").write_text(json.dumps(data, sort_keys=True, indent=1))
    with pytest.raises(ParameterError, match=r"holds a sweep computed in float32, and this process computes in "
                                             r"float64: resume it in float32"):
        run_sweep(spec, tmp_path)


def test_default_chunks_resume_and_shard_without_changing_the_numbers(tmp_path):
    """By default a sweep is cut into about CHUNKS chunks (a domain chunk holds at least DOMAIN_CHUNK
    grid points): a default sweep resumes and shards, and gives the numbers of one chunk."""
    assert [default_chunk_size("umin", n) for n in (1, 3, 8, 9, 12)] == [1, 1, 1, 2, 2]
    assert [default_chunk_size("domain", n) for n in (72, 4096)] == [DOMAIN_CHUNK, 512]
    umin = make_spec("umin", tilts=[10.0, 20.0, 40.0], iterations=3)
    assert umin.chunk_size == 1
    assert run_sweep(umin, tmp_path / "u1", shard_index=1, num_shards=2) is None  # shard 1 has work
    assert [p.name for p in (tmp_path / "u1").glob("chunk-*.json")] == ["chunk-00001.json"]
    whole = run_sweep(make_spec("umin", tilts=[10.0, 20.0, 40.0], iterations=3, chunk_size=3))
    assert {k: v for k, v in run_sweep(umin).items() if k != "spec"} == {k: v for k, v in whole.items() if k != "spec"}
    tilts, attacks = np.linspace(10.0, 50.0, 9), np.linspace(0.0, 35.0, 8)  # 72 grid points
    domain = make_spec("domain", tilts=tilts, attacks=attacks, chunk_size=64)  # two chunks
    chunked = run_sweep(domain, tmp_path / "d")
    assert len(list((tmp_path / "d").glob("chunk-*.json"))) == 2
    one = run_sweep(make_spec("domain", tilts=tilts, attacks=attacks))
    assert one["spec"]["chunk_size"] == DOMAIN_CHUNK  # the default: one chunk
    assert chunked["bounces"] == one["bounces"] and chunked["first_contact_time"] == one["first_contact_time"]
    assert 0 < sum(map(sum, one["bounces"])) and min(map(min, one["bounces"])) == 0


def test_spec_carries_the_resolved_configuration():
    spec = make_spec("umin", tilts=[20.0], force_law="seed", c_lift=0.8, dt=1e-4, duration=2.0, density=2000.0)
    assert (spec.max_steps, spec.c_friction, spec.config["c_friction"], spec.config["c_lift"]) == (20250, None, 0.1, 0.8)
    assert spec.config["mass"] == pytest.approx(2000.0 / 2700.0 * 0.0144855, rel=1e-4)  # the Clanet disk, lighter
    assert spec.to_dict()["config"] == spec.config and spec.config["dt"] == 1e-4
    with pytest.raises(MeshError, match="granite"):  # the stone is loaded before anything is written
        make_spec("umin", tilts=[20.0], stone="granite")
    with pytest.raises(ParameterError, match="unknown simulation settings: c_drag"):   # (a TypeError until stop 48)
        make_spec("umin", tilts=[20.0], c_drag=1.0)
    with pytest.raises(ParameterError, match="num_shards > 1 needs an out_dir"):
        run_sweep(spec, num_shards=2)


def _sweep_in_subprocess(out, env_updates, devices):
    code = (
        "import jax, sys; jax.config.update('jax_enable_x64', True)\n"
        "from optimize import make_spec, run_sweep\n"
        f"assert len(jax.local_devices()) == {devices}, jax.local_devices()\n"
        "spec = make_spec('domain', tilts=[11.0, 13.0, 15.0], attacks=[0.5, 1.0], speed=12.0, attitude='free',\n"
        "                 spin=20.0, stone='paper')\n"
        "run_sweep(spec, sys.argv[1])\n"
    )
    env = {k: v for k, v in os.environ.items() if k not in ("XLA_FLAGS", "JAXSKIP_CPU_DEVICES")}
    env.update(env_updates, JAX_PLATFORMS="cpu",
               PYTHONPATH=os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))
    subprocess.run([sys.executable, "-c", code, str(out)], check=True, env=env, cwd=ROOT, timeout=600)
    return json.loads((out / "result.json").read_text())


def test_four_host_devices_equal_one(tmp_path):
    """The lanes sharded over 4 forced CPU devices give the same sweep file as 1 device, to the bit, on
    chaotic throws (the free paper stone near the box's best corner: 35-89 bounces; before session 22 the
    counts moved with the device count, [[69, 69], [78, 7], ...] against [[89, 50], [59, 7], ...]).

    Both run in fresh interpreters: ``import jaxskip`` asks JAX for one CPU device per core, so
    the single-device run opts out (``JAXSKIP_CPU_DEVICES=1``).
    """
    one = _sweep_in_subprocess(tmp_path / "one", {"JAXSKIP_CPU_DEVICES": "1"}, 1)
    four = _sweep_in_subprocess(tmp_path / "four", {"XLA_FLAGS": "--xla_force_host_platform_device_count=4"}, 4)
    assert one["bounces"] == four["bounces"]
    assert sum(b > 1 for row in one["bounces"] for b in row) >= 4, one["bounces"]  # not a batch of non-events
    # to the bit: every device advances at least MIN_LANES_PER_DEVICE lanes, which XLA:CPU rounds alike
    # (1-4 lanes a device rounded apart, and chaotic counts moved with the device count)
    np.testing.assert_array_equal(np.array(four["first_contact_time"], dtype=float),
                                  np.array(one["first_contact_time"], dtype=float))


@pytest.mark.parametrize("kwargs, message", [
    ({"kind": "both", "tilts": [20.0]}, "kind"),
    ({"kind": "umin", "tilts": [95.0]}, "tilt"),
    ({"kind": "umin", "tilts": [20.0], "speed_range": (8.0, 1.0)}, "speed_range is inverted"),
    ({"kind": "umin", "tilts": [20.0], "speed_range": (0.0, 8.0)}, r"speed_range must lie within \(0, 100\] m/s"),
    ({"kind": "umin", "tilts": [20.0], "attacks": [10.0, 20.0]}, "attacks must be one angle for a umin sweep, got 2"),
    # (session 32) a repeated tilt was simulated and written twice
    ({"kind": "umin", "tilts": [20.0, 30.0, 20.0]}, "tilts must not repeat an angle, got 20 twice"),
    ({"kind": "domain", "tilts": [20.0], "attacks": [5, 5, 5]}, "attacks must not repeat an angle, got 5 3 times"),
    ({"kind": "domain", "tilts": [20.0], "spin": float("nan")}, "spin"),
    # the throw's own limits (Throw.from_degrees): spin within +-500 rev/s, speed within (0, 100] m/s
    ({"kind": "umin", "tilts": [20.0], "spin": 800.0}, r"spin must be in \[-500, 500\] rev/s, got 800.0"),
    ({"kind": "domain", "tilts": [20.0], "speed": 150.0}, r"speed must be in \(0, 100\] m/s, got 150.0"),
    ({"kind": "umin", "tilts": [20.0], "speed_range": (1.0, 150.0)}, "speed_range must"),
    ({"kind": "umin", "tilts": [20.0], "dt": 0.0}, "dt"),
    ({"kind": "umin", "tilts": [20.0], "mass": -1.0}, "mass"),
    ({"kind": "umin", "tilts": [20.0], "c_lift": -1.0}, "c_lift"),
    ({"kind": "umin", "tilts": []}, "tilts must be a number or a non-empty list of numbers"),
    ({"kind": "umin", "tilts": "20"}, "tilts must be a number or a non-empty list"),
    ({"kind": "domain", "tilts": [20.0], "attacks": []}, "attacks must be a number or a non-empty list"),
    ({"kind": "domain", "tilts": [[10.0, 20.0]]}, "tilts must be"),
])
def test_bad_sweep_input(kwargs, message):
    with pytest.raises(ParameterError, match=message):
        make_spec(**kwargs)


def _finished_umin(out):
    """A finished three-chunk U_min sweep in ``out`` (tiny: one bisection step)."""
    spec = make_spec("umin", tilts=[10.0, 20.0, 30.0], iterations=1, chunk_size=1)
    return spec, run_sweep(spec, out)


@pytest.mark.parametrize("text, problem", [
    ("{}", "it lacks 'chunk', 'items'"),
    ('{"bounces_at_high": [1], "bou', "not valid JSON"),                                  # truncated
    ('{"chunk": 1, "items": [1], "umin": [1.0, 2.0], "bounces_at_high": [1], "bounces_at_low": [0], "diverged": [0], "cut_off": [0], "monotone": [1]}',
     "'umin' must be a list of 1 values"),
    ('{"chunk": 0, "items": [0], "umin": [1.0], "bounces_at_high": [1], "bounces_at_low": [0], "diverged": [0], "cut_off": [0], "monotone": [1]}',
     "not chunk 1 of this sweep"),
    ('{"chunk": 1, "items": [1], "umin": ["x"], "bounces_at_high": [1], "bounces_at_low": [0], "diverged": [0], "cut_off": [0], "monotone": [1]}',
     "'umin' holds a value that is not a number"),
    ("[]", "not a JSON object"),
    # (session 32) a U_min outside the bisection's bracket was taken as found
    ('{"chunk": 1, "items": [1], "umin": [-5.0], "bounces_at_high": [1], "bounces_at_low": [0], "diverged": [0], "cut_off": [0], "monotone": [1]}',
     "'umin' holds -5.0, outside [0.5, 8] m/s, the bisection's bracket"),
    # (2026-12-06, a review) 'monotone' is a flag: 7 passed as a count
    ('{"chunk": 1, "items": [1], "umin": [1.0], "bounces_at_high": [1], "bounces_at_low": [0], "diverged": [0], "cut_off": [0], "monotone": [7]}',
     "'monotone' holds a value that is not 0 or 1"),
], ids=["empty", "truncated", "too-long", "another-chunk", "not-a-number", "not-an-object", "outside-bracket",
        "monotone-not-a-flag"])
def test_damaged_chunk_is_refused_naming_it_and_recomputed_once_deleted(tmp_path, text, problem):
    """A damaged chunk file stops the resume and the merge with a ParameterError naming the file and what
    is wrong (not a KeyError or a bare JSON message); deleted, it is recomputed to the same result."""
    spec, whole = _finished_umin(tmp_path / "s")
    bad = tmp_path / "s" / "chunk-00001.json"
    bad.write_text(text)
    with pytest.raises(ParameterError, match="damaged") as exc:
        run_sweep(spec, tmp_path / "s")
    assert str(bad) in str(exc.value) and problem in str(exc.value) and "delete it" in str(exc.value)
    with pytest.raises(ParameterError, match="damaged") as exc:
        merge([tmp_path / "s"], tmp_path / "m")
    assert str(bad) in str(exc.value) and problem in str(exc.value)
    assert not (tmp_path / "m").exists()  # refused before anything was written
    bad.unlink()
    assert run_sweep(spec, tmp_path / "s") == whole
    assert json.loads(bad.read_text())["chunk"] == 1


@pytest.mark.parametrize("text, problem", [("garbage", "not valid JSON: Expecting value"),
                                           ("[1, 2]", "not a JSON object"), ("{}", "its keys are not a sweep's")],
                         ids=["garbage", "not-an-object", "empty-object"])
def test_damaged_spec_file_is_refused_naming_it(tmp_path, text, problem):
    spec, _ = _finished_umin(tmp_path / "s")
    (tmp_path / "s" / "spec.json").write_text(text)
    for call in (lambda: run_sweep(spec, tmp_path / "s"), lambda: merge([tmp_path / "s"], tmp_path / "m")):
        with pytest.raises(ParameterError, match="damaged") as exc:
            call()
        assert str(tmp_path / "s" / "spec.json") in str(exc.value) and problem in str(exc.value)
        assert "use a new folder" in str(exc.value)


@pytest.mark.parametrize("umask", [0o022, 0o007])
def test_sweep_files_get_the_usual_mode(tmp_path, umask):
    """Chunk, spec and result files are written 0o666 less the umask, like any file the tools write (a
    mkstemp file would stay 0600)."""
    old = os.umask(umask)
    try:
        spec = make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5)
        run_sweep(spec, tmp_path / "s")
        merge([tmp_path / "s"], tmp_path / "m")
        plain = tmp_path / "plain.txt"
        plain.write_text("x")
    finally:
        os.umask(old)
    expected = 0o666 & ~umask
    assert plain.stat().st_mode & 0o777 == expected
    for folder in ("s", "m"):
        names = sorted(p.name for p in (tmp_path / folder).iterdir())
        assert names == ["chunk-00000.json", "result.csv", "result.json", "spec.json"]
        assert {n: (tmp_path / folder / n).stat().st_mode & 0o777 for n in names} == dict.fromkeys(names, expected)


def test_run_sweep_refuses_what_the_command_refuses(tmp_path):
    """Like `jaxskip sweep --out`, run_sweep and merge create their folder but not the folders above it; a
    file is not a folder; a spec must be a SweepSpec (make_spec)."""
    spec = make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5)
    missing = tmp_path / "no" / "such" / "sweep"
    with pytest.raises(ParameterError, match=r"out_dir .*its parent folder .* does not exist"):
        run_sweep(spec, missing)
    with pytest.raises(ParameterError, match=r"out_dir .*its parent folder .* does not exist"):
        merge([tmp_path / "s"], missing)
    assert not (tmp_path / "no").exists()
    (tmp_path / "file").write_text("")
    with pytest.raises(ParameterError, match="is a file, not a folder"):
        run_sweep(spec, tmp_path / "file")
    with pytest.raises(ParameterError, match="spec must be an optimize.SweepSpec .*got dict"):
        run_sweep({"kind": "umin"})
    assert run_sweep(spec, tmp_path / "new")["bounces"] and (tmp_path / "new" / "result.json").exists()


@pytest.mark.parametrize("change, message", [
    ({"kind": "x"}, "kind must be 'domain' or 'umin'"),                    # ran as a U_min sweep
    ({"speed_range": (8.0, 1.0)}, "speed_range is inverted"),              # a negative resolution
    ({"attacks": (10.0, 20.0)}, "attacks must be one angle for a umin sweep"),   # the second ignored
    ({"tilts": ()}, "tilts must be a number or a non-empty list"),         # an empty result
    ({"tilts": (10.0, 10.0)}, "tilts must not repeat an angle"),           # simulated twice
    ({"chunk_size": 0}, "chunk_size must be an integer >= 1"),             # a raw ValueError from range()
    ({"max_steps": 5}, r"spec is not what optimize.make_spec makes .*differs in config"),   # a stale config
])
def test_run_sweep_refuses_a_spec_make_spec_would_not_make(change, message):
    """A SweepSpec changed with dataclasses.replace (or built by hand) skips make_spec's checks: run_sweep checks
    it again, before anything is simulated or written."""
    import dataclasses
    spec = make_spec("umin", tilts=[10.0, 20.0], iterations=1, duration=0.3)
    with pytest.raises(ParameterError, match=message):
        run_sweep(dataclasses.replace(spec, **change))


def test_numpy_settings_make_a_json_ready_spec(tmp_path):
    """NumPy float32 settings (dt, mass, duration, coefficients) are stored as plain floats: the spec's dict is
    JSON-ready, as it says, and a sweep with an out folder runs (it raised 'float32 is not JSON serializable')."""
    f32 = np.float32
    spec = make_spec("domain", tilts=[20.0], attacks=[20.0], dt=f32(2.5e-4), duration=f32(0.5), mass=f32(0.05),
                     c_lift=f32(0.9), c_friction=f32(0.25))
    assert all(type(getattr(spec, k)) is float for k in ("dt", "duration", "mass", "c_lift", "c_friction"))
    assert json.loads(json.dumps(spec.to_dict())) == spec.to_dict()
    assert run_sweep(spec, tmp_path / "s")["bounces"] == run_sweep(spec)["bounces"]


@pytest.mark.parametrize("x, y, name", [
    ("ab", "cd", "x"),                                   # text: was a raw ValueError from float('a')
    (5.0, 6.0, "x"),                                     # a number alone: was a TypeError
    ([5.0, 10.0, 15.0], "cde", "y"),
    ([5.0, 10.0, 15.0], [[1.0, 2.0], [3.0, 4.0], [5.0, 6.0]], "y"),  # nested: was a TypeError
    ([5.0, 10.0, 15.0], [True, False, True], "y"),       # booleans are not values (were taken as 1, 0)
    ([5.0, float("nan"), 15.0], [2.0, 1.0, 2.0], "x"),   # a position must be finite (NaN broke the sort)
    ([5.0, None, 15.0], [2.0, 1.0, 2.0], "x"),           # None marks a missing value, not a position
])
def test_parabola_minimum_refuses_what_is_not_samples(x, y, name):
    """Non-numeric or mis-shaped samples are a ParameterError naming x or y (not a raw ValueError/TypeError);
    NumPy and JAX arrays, tuples and None (missing) in y are still taken."""
    with pytest.raises(ParameterError, match=rf"parabola_minimum: {name} must be a 1-D sequence of"):
        parabola_minimum(x, y)
    import jax.numpy as jnp

    assert parabola_minimum(np.array([1.0, 2.0, 3.0]), jnp.array([1.0, 0.0, 1.0])) == (2.0, 0.0)
    assert parabola_minimum((1, 2, 3, 4), [None, 1.0, 0.0, 1.0]) == (3.0, 0.0)


@pytest.mark.parametrize("result", ["result.json", {}, {"spec": {"kind": "umin"}}, {"umin": [1.0]}])
def test_plot_sweep_refuses_what_is_not_a_sweep_result(result, tmp_path):
    from optimize import plot_sweep

    with pytest.raises(ParameterError, match="result must be a sweep result dict as returned by run_sweep/merge"):
        plot_sweep(result, tmp_path / "s.png")
    assert not (tmp_path / "s.png").exists()


def test_an_obj_stone_is_pinned_by_its_contents(tmp_path):
    """A sweep of an .obj stone resumed with another file at the same path (same mass, the mesh turned
    90 deg) mixed two stones' chunks without a word: spec.json records the file's SHA-256 as well."""
    import dataclasses
    import hashlib

    from jaxskip import irregular_pebble, write_obj

    mesh, path = irregular_pebble(seed=1), tmp_path / "peb.obj"
    write_obj(path, mesh)
    settings = dict(tilts=[20.0], attacks=[20.0], speed=3.5, stone=str(path), attitude="free", max_steps=400)
    spec = make_spec("domain", **settings)
    assert spec.config["stone_sha256"] == hashlib.sha256(path.read_bytes()).hexdigest()
    run_sweep(spec, tmp_path / "s")
    turned = np.asarray(mesh.vertices)[:, [1, 0, 2]] * np.array([-1.0, 1.0, 1.0])  # 90 deg about z
    write_obj(path, dataclasses.replace(mesh, vertices=turned))
    again = make_spec("domain", **settings)
    assert again.config["mass"] == pytest.approx(spec.config["mass"], rel=1e-12)
    with pytest.raises(ParameterError, match=r"different sweep \(its spec.json differs in config: it has "
                                             r"stone_sha256="):
        run_sweep(again, tmp_path / "s")
    assert "stone_sha256" not in small_domain().config  # a built-in stone is pinned by its name
    # (2026-12-07, a review) resumed with a built-in stone, the refusal named the folder's stone as None
    with pytest.raises(ParameterError, match=r"differs in config, stone: it has .*stone=" + repr(str(path))[:20]):
        run_sweep(make_spec("domain", **{**settings, "stone": "paper"}), tmp_path / "s")


def test_one_obj_stone_spelt_two_ways_is_one_sweep(tmp_path, monkeypatch):
    """``./peb.obj`` and ``peb.obj`` (and ``sub/../peb.obj``) are one file: a sweep started with one spelling
    resumes with another instead of refusing its own folder as a different sweep."""
    from jaxskip import irregular_pebble, write_obj

    monkeypatch.chdir(tmp_path)
    (tmp_path / "sub").mkdir()
    write_obj("peb.obj", irregular_pebble(seed=1))
    settings = dict(tilts=[20.0], attacks=[20.0], speed=3.5, attitude="free", max_steps=400)
    first = run_sweep(make_spec("domain", stone="./peb.obj", **settings), tmp_path / "s")
    for spelling in ("peb.obj", "sub/../peb.obj", tmp_path / "sub" / ".." / "peb.obj"):
        spec = make_spec("domain", stone=spelling, **settings)
        if not isinstance(spelling, str):  # an absolute path is another text, and stays one
            assert spec.config["stone"] == os.path.join(str(tmp_path), "peb.obj")
        else:
            assert spec.config["stone"] == "peb.obj"
        assert run_sweep(spec, tmp_path / "s")["bounces"] == first["bounces"]
    assert make_spec("domain", stone="paper", **settings).config["stone"] == "paper"


def test_shards_reading_one_obj_stone_at_two_paths_merge(tmp_path):
    """(2026-12-06) Shards on two machines read the same .obj file from different paths; the merge refused them
    as different sweeps (and a resume from an absolute spelling refused its own folder), although spec.json
    pins an .obj stone by its SHA-256. The path no longer counts; the contents still do."""
    from jaxskip import irregular_pebble, write_obj

    mesh = irregular_pebble(seed=1)
    for machine in ("a", "b"):
        (tmp_path / machine).mkdir()
        write_obj(tmp_path / machine / "peb.obj", mesh)
    settings = dict(tilts=[10.0, 20.0], attacks=[20.0], speed=3.5, attitude="free", max_steps=400, chunk_size=1)
    whole = run_sweep(make_spec("domain", stone=str(tmp_path / "a" / "peb.obj"), **settings), tmp_path / "whole")
    for i, machine in enumerate(("a", "b")):
        spec = make_spec("domain", stone=str(tmp_path / machine / "peb.obj"), **settings)
        run_sweep(spec, tmp_path / f"s{i}", shard_index=i, num_shards=2)
    merged = merge([tmp_path / "s0", tmp_path / "s1"], tmp_path / "m")
    assert merged["bounces"] == whole["bounces"]
    write_obj(tmp_path / "b" / "peb.obj", irregular_pebble(seed=2))   # another stone at b's path: refused
    with pytest.raises(ParameterError, match=r"different sweep \(its spec.json differs in config: it has .*stone_sha256="):
        run_sweep(make_spec("domain", stone=str(tmp_path / "b" / "peb.obj"), **settings), tmp_path / "s1")


def test_a_coefficient_given_at_its_default_is_the_same_sweep(tmp_path):
    """(session 32) ``--c-lift 1`` (Bocquet's calibrated C_l, said aloud) made another spec than no flag, so a
    sweep started without it refused to resume with it. A coefficient off the default is still another sweep."""
    settings = dict(tilts=[20.0], attacks=[20.0], speed=3.5, max_steps=400)
    plain = make_spec("domain", **settings)
    first = run_sweep(plain, tmp_path / "s")
    for given in (dict(c_lift=1.0), dict(c_friction=0.3), dict(c_lift=1, c_friction=0.3)):
        spec = make_spec("domain", **settings, **given)
        assert spec == plain, given
        assert run_sweep(spec, tmp_path / "s")["bounces"] == first["bounces"]
    # the seed law's calibrated friction is 0.1: 0.3 there is a choice, and kept
    assert make_spec("domain", force_law="seed", c_friction=0.3, **settings).c_friction == 0.3
    assert make_spec("domain", force_law="seed", c_friction=0.1, **settings).c_friction is None
    with pytest.raises(ParameterError, match="holds a different sweep"):
        run_sweep(make_spec("domain", c_lift=1.1, **settings), tmp_path / "s")
    # (2026-12-07, a review) so is a mass or density that makes the stone's own mass: spec.json's config.mass
    # given back, or the aluminium's 2700 kg/m^3; another mass is another sweep
    own = plain.config["mass"]
    for given in (dict(mass=own), dict(density=2700.0)):
        assert make_spec("domain", **settings, **given) == plain, given
    assert make_spec("domain", **settings, mass=own * 1.01).mass == pytest.approx(own * 1.01)


def test_chunks_without_their_spec_file_are_refused(tmp_path):
    """With spec.json deleted (read as "delete this one" of the damaged-spec message) a run of another sweep
    adopted the chunk files there and reported the first sweep's numbers as its own."""
    spec = small_domain()
    run_sweep(spec, tmp_path / "s")
    (tmp_path / "s" / "spec.json").unlink()
    other = make_spec("domain", tilts=[10.0, 30.0], attacks=[10.0, 40.0], speed=3.5, chunk_size=1, stone="disk")
    for s in (spec, other):
        with pytest.raises(ParameterError, match="holds chunk files but no spec.json, so nothing says which sweep"):
            run_sweep(s, tmp_path / "s")
    assert not (tmp_path / "s" / "spec.json").exists()


def test_a_spec_is_run_in_the_precision_it_was_made_in(tmp_path):
    """A spec made in float32 (spec.json says so) and run in a float64 process wrote float64 chunks under a
    float32 label, which a float32 run then resumed."""
    import jax

    with jax.enable_x64(False):
        spec32 = make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5)
    assert spec32.config["precision"] == "float32"
    with pytest.raises(ParameterError, match="spec was made in float32 and this process computes in float64"):
        run_sweep(spec32, tmp_path / "s")
    assert not (tmp_path / "s").exists()


def test_merge_reports_what_its_folder_holds(tmp_path):
    """Merging into a folder that already holds a chunk keeps that chunk file, so the result must be
    assembled from it: result.json said one thing and the chunk (read by a re-run there) another. Since stop 47 a
    copy there that differs from the shards' is refused, as two shards' differing copies are."""
    import shutil

    spec = small_domain()
    for i in range(2):
        run_sweep(spec, tmp_path / f"s{i}", shard_index=i, num_shards=2)
    shutil.copytree(tmp_path / "s0", tmp_path / "x")
    chunk = tmp_path / "x" / "chunk-00000.json"
    data = json.loads(chunk.read_text())
    data["bounces"] = [data["bounces"][0] + 5]  # as another machine's rounding might have it
    chunk.write_text(json.dumps(data, sort_keys=True))
    with pytest.raises(ParameterError, match="are two copies of chunk 0 that differ"):
        merge([tmp_path / "s0", tmp_path / "s1"], tmp_path / "x")
    shutil.copy(tmp_path / "s0" / "chunk-00000.json", chunk)     # the same copy: kept, and the result from it
    merged = merge([tmp_path / "s0", tmp_path / "s1"], tmp_path / "x")
    assert merged["bounces"][0][0] == data["bounces"][0] - 5
    assert json.loads((tmp_path / "x" / "result.json").read_text())["bounces"] == merged["bounces"]
    assert run_sweep(spec, tmp_path / "x")["bounces"] == merged["bounces"]  # a re-run there agrees


def test_merge_names_the_folder_of_another_sweep(tmp_path):
    spec = make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5)
    run_sweep(spec, tmp_path / "a")
    run_sweep(make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5, stone="disk"), tmp_path / "b")
    with pytest.raises(ParameterError, match=r"the folders hold different sweeps: '.*b' is not the sweep of "
                                             r"'.*a' \(its spec.json differs in config, stone: it has .*stone='disk'"):
        merge([tmp_path / "a", tmp_path / "b"], tmp_path / "m")


def test_spec_file_is_created_once_never_replaced(tmp_path):
    """Two runs starting at once in one folder: spec.json is created exclusively (a rename replaced the other
    run's), so the second reads the first's and is refused if it is another sweep."""
    from optimize.sweep import _write_new

    path = tmp_path / "spec.json"
    assert _write_new(path, "first") and path.read_text() == "first"
    assert not _write_new(path, "second") and path.read_text() == "first"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.json"]  # no temporary file left


# A light Clanet disk (100 kg/m^3) at a coarse 2 ms step, tilt held: at 25-55 m/s the integration fails
# (outcome 'diverged'), at 10 m/s it does not (measured, float64).
DIVERGING = dict(density=100.0, dt=0.002, max_steps=2000, spin=10.0)


def test_domain_sweep_marks_diverged_throws_and_warns_once(tmp_path):
    """A diverged throw's count went into result.json and result.csv like any other, with no sign of it (and
    each batch warned with indices into itself). Now the grid point is marked 1 in 'diverged', the CSV has the
    column, and the sweep issues one DivergedWarning counting its throws."""
    import warnings

    from jaxskip import DivergedWarning

    spec = make_spec("domain", tilts=[20.0], attacks=[10.0], speed=30.0, chunk_size=1, **DIVERGING)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = run_sweep(spec, tmp_path / "s")
    diverged = [w for w in caught if issubclass(w.category, DivergedWarning)]
    assert r["diverged"] == [[1]] and len(diverged) == 1
    assert "1 of the 1 throws of this domain sweep diverged" in str(diverged[0].message)
    rows = (tmp_path / "s" / "result.csv").read_text().splitlines()
    assert rows[0].endswith(",diverged,cut_off") and rows[1].endswith(",1,0")
    calm = run_sweep(make_spec("domain", tilts=[20.0], attacks=[10.0], speed=10.0, chunk_size=1, **DIVERGING))
    assert calm["diverged"] == [[0]]


def test_umin_sweep_gives_no_umin_where_its_bisection_met_a_diverged_throw():
    """A bisection step taken on a diverged throw's count means nothing: such a tilt's U_min is None and
    'diverged' counts its bisection throws that diverged (the bracket's top, 40 m/s, diverges at both tilts)."""
    import warnings

    from jaxskip import DivergedWarning

    spec = make_spec("umin", tilts=[20.0, 30.0], speed_range=(0.5, 40.0), iterations=3, chunk_size=1, **DIVERGING)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = run_sweep(spec)
    assert r["umin"] == [None, None] and all(n >= 1 for n in r["diverged"])
    assert sum(issubclass(w.category, DivergedWarning) for w in caught) == 1


@pytest.mark.parametrize("missing, said", [
    (("diverged", "cut_off"), "earlier jaxskip, which did not record the throws that diverged"),
    (("cut_off",), "earlier jaxskip, which did not record the throws the duration or step limit cut off"),
    # (2026-12-06, a review) a U_min chunk from before the speed scan lacks 'monotone' too: "damaged" before
    (("monotone",), "earlier jaxskip, before the U_min sweep scanned each bracket"),
    (("diverged", "cut_off", "monotone"), "earlier jaxskip, before the U_min sweep scanned each bracket"),
], ids=["before-diverged", "before-cut-off", "before-scan", "before-all"])
def test_chunk_of_an_earlier_version_is_refused_as_such(tmp_path, missing, said):
    """A chunk file written before sweeps recorded diverged throws (and, later, throws cut off by the duration)
    cannot be checked for them: refused with a message that says so (not as an unexplained 'damaged' file)."""
    spec, _ = _finished_umin(tmp_path / "s")
    path = tmp_path / "s" / "chunk-00001.json"
    data = json.loads(path.read_text())
    for key in missing:
        del data[key]
    path.write_text(json.dumps(data))
    with pytest.raises(ParameterError, match=said):
        run_sweep(spec, tmp_path / "s")


def test_domain_sweep_marks_throws_the_duration_cut_off_and_warns_once(tmp_path):
    """A throw still in the air or on the water when the run stopped it (outcome 'time_limit') went into the
    result with its count so far and no sign that it is a lower bound. Now the grid point is marked 1 in
    'cut_off' (JSON and CSV) and the sweep issues one AccuracyWarning naming the duration; with the default
    duration the same throws end in play and nothing is marked."""
    import warnings

    from jaxskip import AccuracyWarning

    spec = make_spec("domain", tilts=[20.0, 30.0], attacks=[20.0], duration=0.05, chunk_size=1)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = run_sweep(spec, tmp_path / "s")
    cut = [w for w in caught if issubclass(w.category, AccuracyWarning) and "still skipping" in str(w.message)]
    assert r["cut_off"] == [[1], [1]] and len(cut) == 1
    assert "2 of the 2 throws" in str(cut[0].message) and "duration=0.05 s" in str(cut[0].message)
    rows = (tmp_path / "s" / "result.csv").read_text().splitlines()
    assert rows[0].endswith(",diverged,cut_off") and all(row.endswith(",0,1") for row in rows[1:])
    with warnings.catch_warnings(record=True) as caught:   # a merge of the folder warns as the run did
        warnings.simplefilter("always")
        assert merge([tmp_path / "s"], tmp_path / "m")["cut_off"] == [[1], [1]]
    assert sum("2 of the 2 throws" in str(w.message) for w in caught if issubclass(w.category, AccuracyWarning)) == 1
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        whole = run_sweep(make_spec("domain", tilts=[20.0, 30.0], attacks=[20.0], chunk_size=1))
    assert whole["cut_off"] == [[0], [0]] and not [w for w in caught if "still skipping" in str(w.message)]


def test_umin_sweep_gives_no_umin_where_its_bisection_met_a_cut_off_throw():
    """A throw stopped by the duration before its first bounce was taken for one that does not bounce, and
    the bisection moved up past speeds that bounce. Now such a tilt gets no U_min and 'cut_off' counts those
    throws; with the default duration the same sweep finds a U_min at every tilt."""
    import warnings

    from jaxskip import AccuracyWarning

    spec = make_spec("umin", tilts=[20.0, 30.0], iterations=3, duration=0.05, chunk_size=1)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = run_sweep(spec)
    # the bracket's top (8 m/s) bounces within 0.05 s; slower throws are still in their first contact
    assert r["bounces_at_high"] == [1, 1] and r["umin"] == [None, None] and all(n >= 1 for n in r["cut_off"])
    assert sum("whether they bounce is unknown" in str(w.message) for w in caught
               if issubclass(w.category, AccuracyWarning)) == 1
    whole = run_sweep(make_spec("umin", tilts=[20.0, 30.0], iterations=3, chunk_size=1))
    assert None not in whole["umin"] and whole["cut_off"] == [0, 0]


def test_stability_warning_is_issued_once_per_sweep_at_its_fastest_throw():
    """Each batch of a U_min bisection warned about the contact step at its own fastest throw (two or more
    warnings with different speeds a sweep); the sweep now warns once, at the bracket's top."""
    import warnings

    from jaxskip import StabilityWarning

    spec = make_spec("umin", tilts=[20.0, 30.0], speed_range=(0.5, 8.0), iterations=3, attitude="free",
                     density=300.0, dt=0.001, max_steps=2000)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        run_sweep(spec)
    stability = [w for w in caught if issubclass(w.category, StabilityWarning)]
    assert len(stability) == 1 and "at 8 m/s" in str(stability[0].message)


def test_umin_of_a_free_stone_that_flips_at_speed_is_its_lowest_bouncing_speed(tmp_path):
    """(2026-12-06, a review) bisection assumes a faster throw still bounces; the free Clanet disk at 10 deg
    (20 deg attack, 65 rev/s) bounces at every speed from 2.5 to 11.5 m/s in steps of 0.5 but not at 12 or 2.0,
    so a bracket of (0.5, 12) m/s read 'no bounce up to 12 m/s'. A scan of the bracket now finds the
    bouncing speeds: U_min is bisected where the count first turns from 0, the tilt marked not monotone,
    and the run warns."""
    from jaxskip import AccuracyWarning

    spec = make_spec("umin", tilts=[10.0], speed_range=(0.5, 12.0), iterations=3, attitude="free", duration=1.0)
    with pytest.warns(AccuracyWarning, match=r"at 1 tilt\(s\) \(10 deg\) a faster throw failed to bounce"):
        r = run_sweep(spec, tmp_path / "s")
    assert r["bounces_at_high"] == [0] and r["monotone"] == [0] and r["cut_off"] == [0]
    assert 2.0 < r["umin"][0] <= 2.5 + (12.0 - 0.5) / 9 / 2**3, r["umin"]
    row = (tmp_path / "s" / "result.csv").read_text().splitlines()[1].split(",")
    assert row[6:9] == ["0", "0", "0"]                    # diverged, cut_off, monotone


def test_a_tie_for_the_lowest_umin_is_one_answer_in_the_result():
    """(2026-12-06, a review) two tilts tying for the lowest U_min: the CLI said 'no single minimum' and showed
    no parabola, while result.json gave best_tilt 10 and a parabola vertex at 15 deg. The result now says
    which tilts tie and fits no parabola through a tie; a strict minimum is fitted as before."""
    from optimize.sweep import assemble

    spec = make_spec("umin", tilts=[5.0, 10.0, 20.0, 30.0], iterations=3)
    chunk = {"umin": [3.31, 2.38, 2.38, 2.85], "bounces_at_high": [1] * 4, "bounces_at_low": [0] * 4,
             "diverged": [0] * 4, "cut_off": [0] * 4, "monotone": [1] * 4}
    r = assemble(spec, [chunk])
    assert r["tied_tilts"] == [10.0, 20.0] and r["best_tilt_fit"] is None and r["best_umin_fit"] is None
    r = assemble(spec, [dict(chunk, umin=[3.31, 2.38, 2.30, 2.85])])
    assert r["tied_tilts"] == [] and 10.0 < r["best_tilt_fit"] < 30.0


def _fake_counts(monkeypatch, bounces):
    """Replace the sweep's simulator by ``bounces(speeds) -> counts`` (every throw 'sank')."""
    import optimize.sweep as sweep_module

    class Fake:
        def __init__(self, speeds):
            self.bounces = bounces(speeds)
            self.outcome_names = np.full(speeds.shape, "sank", dtype=object)

    def fake_batch(throws, sim, progress):
        v = np.asarray(throws.speed, dtype=float)
        return Fake(v), np.zeros(v.shape, bool)

    monkeypatch.setattr(sweep_module, "_batch", fake_batch)


def test_a_gap_between_the_scan_speeds_cannot_catch_the_bisection(tmp_path, monkeypatch):
    """(2026-12-06, a review) where the scan looked monotone, the whole bracket was bisected; a gap in the
    bouncing speeds narrower than the scan's step (here 11.8-12.8 m/s, the scan 2.6 m/s apart) caught its
    first midpoint, 12.25 m/s, and U_min came out 12.80 m/s although the scan had seen 3.11 m/s bounce. Since
    2026-12-07 every tilt is bisected inside the scan's interval where the count turns from 0, so the gap is
    never thrown: U_min is right, and the tilt reads monotone (nothing thrown contradicts it)."""
    _fake_counts(monkeypatch, lambda v: np.where((v > 2.3) & ~((v >= 11.8) & (v <= 12.8)), 3, 0))
    spec = make_spec("umin", tilts=[10.0], speed_range=(0.5, 24.0), iterations=10)
    r = run_sweep(spec)
    step = (24.0 - 0.5) / 9
    assert r["monotone"] == [1] and 2.3 < r["umin"][0] <= 2.3 + step / 2 ** 10, r["umin"]
    assert r["resolution"] == pytest.approx(step / 2**10, rel=1e-12)


def test_umin_never_lies_above_a_speed_its_scan_saw_bounce(monkeypatch):
    """(2026-12-07, a review) a monotone tilt was bisected over the whole bracket: with one iteration
    `jaxskip sweep umin --tilts 10,15,20,25 --iterations 1` read U_min 4.25 m/s at every tilt, a four-way
    'tie', although the scan had thrown 2.17 m/s at tilt 15 and it bounced; and a tilt bisected inside the
    scan (not monotone) got the whole bracket's error bar, (0.72, 2.16] for a bracket starting at 2 m/s.
    Every tilt is now bisected inside the scan's interval, and `resolution` is that interval's width halved
    `iterations` times: the same bracket for every tilt, never below the bracket's low end."""
    import optimize.sweep as sweep_module

    thresholds = {10.0: 2.9, 15.0: 2.1, 20.0: 2.3, 25.0: 2.6}     # each tilt's true U_min [m/s]

    def fake_batch(throws, sim, progress):
        v = np.asarray(throws.speed, dtype=float)
        t = np.round(np.degrees(np.asarray(throws.tilt, dtype=float)), 6)
        u = np.array([thresholds[float(x)] for x in t])

        class R:
            bounces = np.where(v > u, 2, 0)
            outcome_names = np.full(v.shape, "sank", dtype=object)
        return R(), np.zeros(v.shape, bool)

    monkeypatch.setattr(sweep_module, "_batch", fake_batch)
    spec = make_spec("umin", tilts=list(thresholds), iterations=1)
    r = run_sweep(spec)
    step = (8.0 - 0.5) / 9
    scan = 0.5 + step * np.arange(10)
    for (tilt, u0), u in zip(thresholds.items(), r["umin"]):
        first = scan[np.argmax(scan > u0)]          # the scan's slowest bouncing speed
        assert u0 < u <= first and u - u0 <= step / 2, (tilt, u, first)
    assert r["resolution"] == pytest.approx(step / 2, rel=1e-12)
    assert r["best_tilt"] == 15.0 and r["tied_tilts"] == [], r


def test_a_umin_chunk_bisected_over_the_whole_bracket_is_refused(tmp_path, monkeypatch):
    """A U_min chunk file written before 2026-12-07 (no 'bisection' key: each monotone tilt bisected over the
    whole bracket) would mix two answers in a resumed sweep: it is refused, naming what to do."""
    _fake_counts(monkeypatch, lambda v: np.where(v > 2.3, 3, 0))
    spec = make_spec("umin", tilts=[10.0, 20.0], iterations=2, chunk_size=1)
    run_sweep(spec, tmp_path / "s")
    chunk = tmp_path / "s" / "chunk-00000.json"
    data = json.loads(chunk.read_text())
    assert data["bisection"] == "scan-interval"
    del data["bisection"]
    chunk.write_text(json.dumps(data))
    with pytest.raises(ParameterError, match="bisected a tilt over the whole bracket"):
        run_sweep(spec, tmp_path / "s")


def test_a_folder_holding_results_but_no_sweep_is_refused(tmp_path):
    """(2026-12-07, a review) --out into a folder with the user's own result.json wrote over it in silence."""
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "result.json").write_text('{"mine": 1}')
    with pytest.raises(ParameterError, match=r"holds result.json but no spec.json: not a sweep's folder"):
        run_sweep(make_spec("domain", tilts=[20.0], attacks=[20.0], duration=0.3), tmp_path / "other")
    assert (tmp_path / "other" / "result.json").read_text() == '{"mine": 1}'


def test_a_sweeps_progress_says_what_is_kept_and_how_long_is_left(tmp_path, capsys):
    """(stop 47, a review) A sweep's progress named each chunk but neither the time spent nor the time left (a
    60-chunk sweep's log); it also counts the chunks it keeps from an earlier run."""
    import re

    spec = make_spec("umin", tilts=[10.0, 20.0, 30.0, 40.0], iterations=2, chunk_size=1, max_steps=2000)
    with pytest.raises(KeyboardInterrupt):
        run_sweep(spec, tmp_path / "s", _stop_after=1)
    capsys.readouterr()
    run_sweep(spec, tmp_path / "s", progress=True)
    err = capsys.readouterr().err
    assert "  1 of 4 chunks already in" in err and "(kept, not recomputed)" in err
    assert "  chunk 2/4 (1 tilt)\n" in err                              # the first to compute: no pace yet
    # the pace from the second on (the first compiles): the time left from the third
    assert re.search(r"  chunk 3/4 \(1 tilt\); 1 of 3 done in \d+ s\n", err), err
    assert re.search(r"  chunk 4/4 \(1 tilt\); 2 of 3 done in \d+ s, about \d+ s left\n", err), err


def test_the_sweep_id_agrees_with_the_spec_check(tmp_path):
    """(stop 47, a review of the session's diff) The chunks' sweep id hashed the spec's JSON text, which tells -0.0 from
    0.0 where the folder's check (dict equality) does not: a sweep at spin -0 resumed with spin 0 passed the check and
    then refused its own chunk as "of another sweep". Numbers are hashed as they compare."""
    from optimize.sweep import sweep_id

    def spec(spin):
        return make_spec("domain", tilts=[20.0], attacks=[20.0], speed=3.5, spin=spin, max_steps=400)

    assert sweep_id(spec(-0.0)) == sweep_id(spec(0.0)) != sweep_id(spec(1.0))
    whole = run_sweep(spec(-0.0), tmp_path / "s")
    (tmp_path / "s" / "result.json").unlink()
    assert run_sweep(spec(0.0), tmp_path / "s") == whole


def test_merge_refuses_a_differing_copy_in_its_out_folder_and_old_domain_chunks_read_as_now(tmp_path):
    """(stop 47, a review of the session's diff) merge compared the shards' copies of a chunk but replaced them with the
    out folder's own copy unchecked; and a domain chunk written before stop 47 kept a first-contact time where the
    duration cut the contact off (the run's end), beside new chunks' None."""
    spec = small_domain()
    whole = run_sweep(spec, tmp_path / "a")
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "spec.json").write_text((tmp_path / "a" / "spec.json").read_text())
    data = json.loads((tmp_path / "a" / "chunk-00000.json").read_text())
    (tmp_path / "out" / "chunk-00000.json").write_text(json.dumps({**data, "bounces": [data["bounces"][0] + 1]}))
    with pytest.raises(ParameterError, match="are two copies of chunk 0 that differ"):
        merge([tmp_path / "a"], tmp_path / "out")
    # an old chunk (no "sweep"): where the throw never bounced its first contact has no duration, as now written
    old = {k: v for k, v in data.items() if k != "sweep"}
    assert data["bounces"] == [4] and data["first_contact_time"][0] is not None
    (tmp_path / "a" / "chunk-00000.json").write_text(json.dumps({**old, "bounces": [0], "first_contact_time": [0.2]}))
    (tmp_path / "a" / "result.json").unlink()
    again = run_sweep(spec, tmp_path / "a")
    assert again["bounces"][0][0] == 0 and again["first_contact_time"][0][0] is None
    assert again["bounces"][1:] == whole["bounces"][1:]


def test_the_api_needs_a_shard_index_with_several_shards(tmp_path):
    """(stop 47, a review) run_sweep(num_shards=2) without shard_index ran shard 0, as the CLI did."""
    with pytest.raises(ParameterError, match=r"num_shards=2 needs shard_index, this machine's shard, in \[0, 1\]"):
        run_sweep(small_domain(), tmp_path / "s", num_shards=2)
    assert not (tmp_path / "s").exists()
