"""Evenly spaced frames of a throw (jaxskip.export): on the simulated motion, in flight as in contact."""

import dataclasses
import json

import numpy as np
import pytest

from jaxskip import ParameterError, SimConfig, simulate
from jaxskip.export import COLUMNS, frames, write_trajectory


@pytest.fixture(scope="module")
def default_throw():
    return simulate()


def _same_as_stepped(jumped, throw, fps, until):
    """Frames of ``jumped`` (flights crossed in jumps) at or before ``until`` [s] against the same throw stepped
    every 0.25 ms through the air (flight="step"), at the times both have."""
    fine = simulate(throw, config=SimConfig(flight="step"))
    f = frames(jumped, fps=fps)
    t_fine = fine.trajectory["time"]
    checked = 0
    for j in np.flatnonzero(f["time"] <= until):
        k = int(np.argmin(np.abs(t_fine - f["time"][j])))
        assert abs(t_fine[k] - f["time"][j]) < 1e-12
        np.testing.assert_allclose(f["position"][j], fine.trajectory["position"][k], atol=1e-12)
        np.testing.assert_allclose(f["velocity"][j], fine.trajectory["velocity"][k], atol=1e-10)
        assert abs(abs(f["orientation"][j] @ fine.trajectory["orientation"][k]) - 1.0) < 1e-12
        checked += 1
    return f, checked


def test_frames_in_flight_lie_on_the_simulated_motion(default_throw):
    """Frames every 2.5 ms against the same throw stepped every 0.25 ms through the air: the same positions,
    velocities and attitudes (to rounding) through the default throw's first contact and first flight."""
    f, checked = _same_as_stepped(default_throw, default_throw.throw, 400.0, 0.125)
    t = f["time"]
    assert checked == 51 and f["in_water"][(t > 0.002) & (t < 0.025)].all()  # the first contact: 1-29 ms
    assert not f["in_water"][(t > 0.035) & (t < 0.125)].any()  # the first flight


def test_frames_inside_long_jumps():
    """Released 0.5 m above the water at 5 rev/s, the stone falls for ~0.3 s in jumps of the full 20 ms
    (``max_flight_step``), turning 0.63 rad in each: frames inside the jumps carry the state along the arc
    and the free rotation, and agree with the 0.25 ms-stepped fall to rounding (a straight line between
    jumps would be off by up to g dt^2 / 8 = 0.5 mm)."""
    from jaxskip import Throw

    throw = Throw.from_degrees(height=0.5, spin=5.0)
    jumped = simulate(throw)
    t = jumped.trajectory["time"]
    first = jumped.contacts[0].t_start
    assert np.diff(t[t < first]).max() == pytest.approx(0.02)
    _, checked = _same_as_stepped(jumped, throw, 400.0, first - 1e-3)
    assert checked > 100


def test_frames_are_evenly_spaced_unit_quaternions_and_flag_the_contacts(default_throw):
    f = frames(default_throw, fps=60.0)
    t_last = default_throw.trajectory["time"][-1]
    # every 1/60 s, and the last simulated step as the last frame (2026-12-07, a review: the file ended up to a
    # frame early, a stone that sank last seen above its plunge)
    assert len(f["time"]) == int(np.floor(t_last * 60.0)) + 2 and f["time"][-1] == t_last
    np.testing.assert_allclose(np.diff(f["time"][:-1]), 1 / 60.0, rtol=1e-12)
    assert 0 < f["time"][-1] - f["time"][-2] < 1 / 60.0
    np.testing.assert_allclose(f["position"][-1], default_throw.trajectory["position"][-1], atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(f["orientation"], axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(f["position"][0], default_throw.trajectory["position"][0], atol=0)
    c = default_throw.contacts
    wet = np.zeros(len(f["time"]), bool)
    for contact in c:
        wet |= (f["time"] > contact.t_start + 1e-3) & (f["time"] < contact.t_end - 1e-3)
    assert np.all(f["in_water"][wet])  # frames well inside a contact are in the water
    assert not f["in_water"][(f["time"] > c[0].t_end + 1e-3) & (f["time"] < c[1].t_start - 1e-3)].any()


def test_csv_and_json_files(default_throw, tmp_path):
    write_trajectory(default_throw, tmp_path / "t.csv", fps=30.0)
    text = (tmp_path / "t.csv").read_text().splitlines()
    assert text[0] == ",".join(COLUMNS)  # a plain CSV: column names (with units) first, for any CSV reader
    import csv

    rows = list(csv.DictReader(open(tmp_path / "t.csv")))
    assert float(rows[1]["t_s"]) == pytest.approx(1 / 30, abs=1e-6) and rows[0]["in_water"] == "0"
    assert "18 bounces" in (tmp_path / "t.stone.obj").read_text().splitlines()[0]  # the throw, described
    table = np.loadtxt(tmp_path / "t.csv", delimiter=",", skiprows=1)
    f = frames(default_throw, fps=30.0)
    assert table.shape == (len(f["time"]), len(COLUMNS))
    np.testing.assert_allclose(table[:, 1:4], f["position"], rtol=1e-8, atol=1e-12)
    write_trajectory(default_throw, tmp_path / "t.json", fps=30.0)
    j = json.loads((tmp_path / "t.json").read_text())
    assert j["fps"] == 30.0 and j["units"]["x"] == "m" and len(j["frames"]["t"]) == len(f["time"])
    assert j["frames"]["in_water"] == f["in_water"].tolist()
    assert j["stone_obj"] == "t.stone.obj" and j["units"]["in_water"] == "bool"


def test_the_stone_file_is_in_the_frame_the_quaternions_rotate(default_throw, tmp_path):
    """The OBJ written beside a trajectory is the stone in its body frame: placed by a frame's quaternion
    and position, its lowest vertex at release is the throw's 1 mm above the water, and its volume gives
    the stone's mass at the paper stone's density."""
    from jaxskip import mass_properties, read_obj
    from jaxskip import quaternion as quat

    obj = write_trajectory(default_throw, tmp_path / "t.csv", fps=30.0)
    assert obj == str(tmp_path / "t.stone.obj")
    mesh = read_obj(obj)  # validated: closed, outward
    f = frames(default_throw, fps=30.0)
    world = mesh.vertices @ np.asarray(quat.to_matrix(f["orientation"][0])).T + f["position"][0]
    assert world[:, 2].min() == pytest.approx(float(default_throw.throw.height), abs=1e-12)
    assert mass_properties(mesh, density=2650.0).mass == pytest.approx(default_throw.mass, rel=1e-12)
    np.testing.assert_allclose(mass_properties(mesh, density=2650.0).center_of_mass, 0.0, atol=1e-12)


@pytest.mark.parametrize("fps", [0.0, -1.0, float("nan"), 1e5])
def test_bad_frame_rate(default_throw, fps):
    with pytest.raises(ParameterError, match="fps must"):
        frames(default_throw, fps=fps)


def test_bad_inputs(default_throw, tmp_path):
    with pytest.raises(ParameterError, match=r"path must end in .csv or .json"):
        write_trajectory(default_throw, tmp_path / "t.txt")
    with pytest.raises(ParameterError, match="no stone"):
        frames(dataclasses.replace(default_throw, rigid=None))


def test_throws_of_other_lengths_reuse_one_compiled_program(default_throw):
    """Frames are computed in batches padded to a power of two: a throw with another number of frames
    (here 23 and 21 at 60 frames/s) does not compile again (~0.5 s each before)."""
    from jaxskip import Throw
    from jaxskip.export import _carry

    frames(default_throw)
    before = _carry._cache_size()
    other = simulate(Throw.from_degrees(speed=6.0))
    f = frames(other)
    assert len(f["time"]) != len(frames(default_throw)["time"])
    assert _carry._cache_size() == before


def test_a_fixed_attitude_is_held_in_the_frames():
    """With attitude="fixed" the simulator holds the quaternion (the spin is recorded, never applied):
    so do the frames, in flight too (they used to spin the stone forward by up to 144 deg and snap back)."""
    held = simulate(config=SimConfig(attitude="fixed"))
    q0 = held.trajectory["orientation"][0]
    assert np.all(np.abs(held.trajectory["orientation"] - q0) == 0.0)
    f = frames(held, fps=240.0)
    np.testing.assert_allclose(f["orientation"], np.broadcast_to(q0, f["orientation"].shape), atol=1e-15)


def test_what_is_not_a_throw_result_is_refused(default_throw, tmp_path):
    """frames, write_trajectory and body_mesh refuse a wrong type with a ParameterError naming it (they raised
    AttributeError), and write_trajectory writes nothing."""
    from jaxskip.export import body_mesh

    for bad in ("x", {"rigid": None}, None):
        with pytest.raises(ParameterError, match="result must be a jaxskip.ThrowResult"):
            frames(bad)
        with pytest.raises(ParameterError, match="result must be a jaxskip.ThrowResult"):
            write_trajectory(bad, tmp_path / "t.csv")
        with pytest.raises(ParameterError, match="stone must be a jaxskip.RigidStone"):
            body_mesh(bad)
    with pytest.raises(ParameterError, match="stone must be a jaxskip.RigidStone"):
        body_mesh(default_throw)  # the result, not its stone (default_throw.rigid)
    assert body_mesh(default_throw.rigid).n_triangles == default_throw.rigid.triangles.shape[0]
    assert list(tmp_path.iterdir()) == []


def test_bad_trajectory_paths_are_refused_before_anything_is_written(default_throw, tmp_path):
    """A path that is not a str/PathLike (a TypeError before), or a folder where the trajectory or its stone
    file goes (an IsADirectoryError once the .stone.obj was already written): a ParameterError, nothing
    written."""
    for path in (42, b"t.csv", None):
        with pytest.raises(ParameterError, match="path must be a str or os.PathLike ending in .csv or .json"):
            write_trajectory(default_throw, path)
    (tmp_path / "x.csv").mkdir()
    with pytest.raises(ParameterError, match=r"path .*x\.csv' is a folder, not a file"):
        write_trajectory(default_throw, tmp_path / "x.csv")
    (tmp_path / "y.stone.obj").mkdir()
    with pytest.raises(ParameterError, match=r"path's stone file .*y\.stone\.obj' is a folder, not a file"):
        write_trajectory(default_throw, str(tmp_path / "y.json"))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.csv", "y.stone.obj"]
    assert not any((tmp_path / "x.csv").iterdir()) and not any((tmp_path / "y.stone.obj").iterdir())


def test_a_stone_file_jaxskip_did_not_write_is_never_overwritten(default_throw, tmp_path):
    """(session 32, a review) write_trajectory(r, "t.csv") replaced the user's own t.stone.obj (the mesh the
    throw was made with) by the body-frame mesh, silently; and x.csv after x.json of another throw replaced
    the first throw's stone. Both refused before anything is written; the same throw in both formats, or
    the same trajectory again, still overwrites."""
    from jaxskip import simulate, write_obj
    from jaxskip.stones import irregular_pebble

    mine = tmp_path / "t.stone.obj"
    write_obj(mine, irregular_pebble(seed=3))
    before = mine.read_bytes()
    with pytest.raises(ParameterError, match="exists and was not written by jaxskip"):
        write_trajectory(default_throw, tmp_path / "t.csv")
    assert mine.read_bytes() == before and not (tmp_path / "t.csv").exists()
    # the same throw as JSON then CSV, and the CSV again: one stone, overwritten
    write_trajectory(default_throw, tmp_path / "u.json")
    write_trajectory(default_throw, tmp_path / "u.csv")
    write_trajectory(default_throw, tmp_path / "u.csv")
    assert "jaxskip trajectory u.csv:" in (tmp_path / "u.stone.obj").read_text().splitlines()[0]
    # another throw's stone is not replaced
    other = simulate(stone="clanet", config=SimConfig(duration=0.05))
    with pytest.raises(ParameterError, match=r"holds the stone of another throw, written with the trajectory 'u.csv'"):
        write_trajectory(other, tmp_path / "u.json")
    assert "jaxskip trajectory u.csv:" in (tmp_path / "u.stone.obj").read_text().splitlines()[0]


def test_frames_of_a_float32_result_after_x64_is_switched_on():
    """(2026-12-06, a review) a result simulated in float32 and exported once jax_enable_x64 was on (a
    notebook that switches x64 on half-way) met a raw "lax.mul requires arguments to have the same
    dtypes" error: its stone was float32, the step's constants float64. The frames now compute in JAX's
    float type of the moment and agree with the float32 ones to float32's rounding."""
    import jax

    config = SimConfig(duration=0.2)
    jax.config.update("jax_enable_x64", False)
    try:
        result = simulate(config=config)
        f32 = frames(result, fps=100.0)
    finally:
        jax.config.update("jax_enable_x64", True)
    assert result.trajectory["position"].dtype == np.float32
    f64 = frames(result, fps=100.0)
    assert f64["position"].dtype == np.float64
    np.testing.assert_array_equal(f64["time"], f32["time"])
    np.testing.assert_allclose(f64["position"], f32["position"], rtol=0, atol=1e-5)
    np.testing.assert_allclose(f64["orientation"], f32["orientation"], rtol=0, atol=1e-5)


def test_a_field_throws_trajectory_says_which_water_it_ran_on(tmp_path):
    """(2026-12-06, a review) a trajectory of a throw on the moving height field said "water at z = 0", as for
    flat water; now its about text names the field and the JSON carries the grid (not its snapshots)."""
    from jaxskip.water import WaterGrid

    grid = WaterGrid(shape=(24, 24), spacing=0.01, depth=0.02, boundary="sponge", sponge_width=4, clamp="smooth")
    r = simulate(config=SimConfig(duration=0.05), water_field=grid)
    write_trajectory(r, tmp_path / "t.json", fps=100.0)
    out = json.loads((tmp_path / "t.json").read_text())
    assert out["about"].endswith("the throw ran on a moving height field (24x24 columns of 0.01 m following the "
                                 "stone), not written here")
    assert out["water"]["shape"] == [24, 24] and "frames" not in out["water"]
    assert "height field (24x24 columns of 0.01 m following the stone), not written here" in (
        tmp_path / "t.stone.obj").read_text().splitlines()[0]
    write_trajectory(simulate(config=SimConfig(duration=0.05)), tmp_path / "flat.json", fps=100.0)
    flat = json.loads((tmp_path / "flat.json").read_text())
    assert flat["about"].endswith("water at z = 0") and "water" not in flat


def test_writing_a_diverged_throw_warns(tmp_path):
    """(2026-12-06, a review) the trajectory of a diverged throw (energy growing to 1e5 J) was written as any
    other, its files giving no sign of it."""
    import dataclasses as dc

    from jaxskip import DivergedWarning

    r = dc.replace(simulate(config=SimConfig(duration=0.05)), outcome="diverged")
    with pytest.warns(DivergedWarning, match="this throw diverged .*the trajectory written is not a motion"):
        write_trajectory(r, tmp_path / "d.csv", fps=100.0)


@pytest.mark.parametrize("name", ["run_12:30", "run  2", "a: b.csv"])
def test_a_trajectory_name_with_colons_or_spaces_is_its_own_stone_files_owner(default_throw, tmp_path, name):
    """(2026-12-07, a review) the stone file's owner was read as the text before the first ':' of its first line,
    and the OBJ comment squeezes runs of spaces: writing 'run_12:30.csv' (or 'run  2.csv') again, for another
    throw, was refused as 'written with the trajectory run_12'. A trajectory overwrites its own stone file."""
    from jaxskip import simulate

    path = tmp_path / f"{name}.csv"
    write_trajectory(default_throw, path)
    other = simulate(stone="clanet", config=SimConfig(duration=0.05))
    write_trajectory(other, path)                               # its own stone file: replaced
    assert "clanet" in (tmp_path / f"{name}.stone.obj").read_text().splitlines()[0]
    with pytest.raises(ParameterError, match="holds the stone of another throw"):
        write_trajectory(default_throw, tmp_path / f"{name}.json")   # another trajectory's, of another throw


def test_the_mesh_frame_drives_your_own_mesh(tmp_path):
    """(2026-12-07, a review) the stone file beside a trajectory had its vertices sorted (np.unique) and nothing
    said where the body frame lay in the user's mesh, so an animator could not drive their own (textured) mesh
    by the frames. mesh_frame gives it (centre of mass, rotation); with mesh= the stone file keeps the mesh's
    vertex order and the JSON records the frame; a mesh that is not the stone is refused."""
    import jax.numpy as jnp

    from jaxskip import TriMesh, read_obj
    from jaxskip.export import mesh_frame
    from jaxskip.quaternion import to_matrix
    from jaxskip.stones import irregular_pebble

    pebble = irregular_pebble(seed=2)
    turn = np.asarray(to_matrix(jnp.asarray([0.9, 0.1, -0.3, 0.2]) / np.linalg.norm([0.9, 0.1, -0.3, 0.2])))
    mine = TriMesh(np.asarray(pebble.vertices) @ turn.T + np.array([0.3, -0.2, 0.05]), pebble.faces, name="mine")
    r = simulate(stone=mine, config=SimConfig(duration=0.05))
    m = mesh_frame(r, mine)
    R = np.asarray(to_matrix(jnp.asarray(m["rotation"])))
    p = np.asarray(mine.vertices)
    body = (p - m["center_of_mass"]) @ R.T
    np.testing.assert_allclose(body[np.asarray(mine.faces)], np.asarray(r.rigid.triangles), atol=1e-6)
    # the world vertices at a frame: x + R(q) R(rotation) (p - c), as the simulator places the stone
    f = frames(r, fps=100.0)
    k = len(f["time"]) // 2
    Q = np.asarray(to_matrix(jnp.asarray(f["orientation"][k])))
    world = f["position"][k] + body @ Q.T
    np.testing.assert_allclose(world[np.asarray(mine.faces)],
                               f["position"][k] + np.asarray(r.rigid.triangles) @ Q.T, atol=1e-6)
    obj = write_trajectory(r, tmp_path / "t.json", mesh=mine)
    back = read_obj(obj)
    np.testing.assert_allclose(np.asarray(back.vertices), body, atol=1e-12)    # the mesh's own vertex order
    np.testing.assert_array_equal(np.asarray(back.faces), np.asarray(mine.faces))
    saved = json.loads((tmp_path / "t.json").read_text())["mesh_frame"]
    np.testing.assert_allclose(saved["center_of_mass"], m["center_of_mass"], rtol=0, atol=1e-15)
    np.testing.assert_allclose(saved["rotation"], m["rotation"], rtol=0, atol=1e-15)
    with pytest.raises(ParameterError, match="is not the stone this throw was simulated with"):
        mesh_frame(r, irregular_pebble(seed=3))


def test_trajectory_json_is_strict_and_says_its_spin_and_units(default_throw, tmp_path):
    """(2026-12-07, a review) a NaN (a diverged throw's) was written as a bare NaN token, which strict parsers
    (JavaScript's JSON.parse) refuse: it is null now; spin_per_frame says how far the stone turns between frames
    (the default throw: ~490 deg at 60 frames/s, which write_trajectory warns of); the water entries have units."""
    import dataclasses
    import json
    import math
    import warnings

    from jaxskip.export import WATER_UNITS, spin_per_frame

    assert math.degrees(spin_per_frame(default_throw, 60.0)) == pytest.approx(488, abs=5)
    traj = dict(default_throw.trajectory)
    traj["position"] = np.asarray(traj["position"]).copy()
    traj["position"][5:] = np.nan
    broken = dataclasses.replace(default_throw, trajectory=traj)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        write_trajectory(broken, tmp_path / "t.json", fps=400.0)
    assert not [w for w in caught if "between frames" in str(w.message)]     # 400 frames/s shows the spin
    text = (tmp_path / "t.json").read_text()
    data = json.loads(text, parse_constant=lambda c: pytest.fail(f"bare {c} in the JSON"))
    assert None in data["frames"]["x"] and "NaN" not in text
    assert set(WATER_UNITS) >= {"shape", "spacing", "depth", "time_step", "volume_change"}


def test_one_stone_file_serves_a_throw_at_any_frame_rate_and_another_throw_never_takes_it(default_throw, tmp_path):
    """(stop 47, an animator's review) throw.json at 60 frames/s then throw.csv of the same throw at 24 was refused
    as "the stone of another throw": the stone file's first line held the frame rate. And throw.csv of another
    stone, written again beside throw.json, replaced their shared stone file in silence, leaving throw.json with
    the wrong stone. Now the first is accepted (one stone file, its text independent of the rate) and the second
    refused, naming throw.json, before anything is written."""
    from jaxskip import simulate

    write_trajectory(default_throw, tmp_path / "throw.json", fps=60.0)
    stone = (tmp_path / "throw.stone.obj").read_text()
    write_trajectory(default_throw, tmp_path / "throw.csv", fps=24.0)
    again = (tmp_path / "throw.stone.obj").read_text()
    assert again.replace("throw.csv:", "throw.json:", 1) == stone
    before = (tmp_path / "throw.csv").read_bytes()
    other = simulate(stone="clanet", config=SimConfig(duration=0.05))
    with pytest.raises(ParameterError, match=r"holds the stone of another throw, which the trajectory 'throw.json' "
                                             r"beside it was written with: .*delete 'throw.json'"):
        write_trajectory(other, tmp_path / "throw.csv")
    assert (tmp_path / "throw.stone.obj").read_text() == again and (tmp_path / "throw.csv").read_bytes() == before
    write_trajectory(other, tmp_path / "alone.csv")     # a trajectory with nothing beside it: its own, as before
    write_trajectory(default_throw, tmp_path / "alone.csv")
    assert "paper stone" in (tmp_path / "alone.stone.obj").read_text().splitlines()[0]


def test_the_files_say_when_the_motion_ends_and_how_quaternions_turn(default_throw, tmp_path):
    """(stop 47, an animator's review) the CSV's times had 6 decimals, so at 3000 frames/s they stepped 0.000333 and
    0.000334 by turns; the last frame (the run's end, off the grid) and the quaternions' direction were said only in
    docstrings. Times have 9 significant digits now; the stone file's first line and the JSON's ``about`` say
    both."""
    import csv

    write_trajectory(default_throw, tmp_path / "fast.csv", fps=3000.0)
    with open(tmp_path / "fast.csv") as fh:
        t = np.array([float(row["t_s"]) for row in csv.DictReader(fh)])
    f = frames(default_throw, fps=3000.0)
    np.testing.assert_allclose(np.diff(t[:-1]), 1 / 3000, rtol=0, atol=2e-9)
    assert t[-1] == pytest.approx(f["time"][-1], abs=1e-9) and f["time"][-1] - f["time"][-2] < 1 / 3000
    write_trajectory(default_throw, tmp_path / "t.json", fps=60.0)
    about = json.loads((tmp_path / "t.json").read_text())["about"]
    assert f"18 bounces, sank; the motion ends there, at t = {f['time'][-1]:.9g} s, the last frame's time" in about
    assert "quaternions (w, x, y, z) rotate the body frame to the world frame, z up" in about
    first = (tmp_path / "t.stone.obj").read_text().splitlines()[0]
    assert " ".join(first.split()).startswith(" ".join(("# " + about + ":").split()))   # (+ the mesh's size)


def test_the_spin_warning_at_a_tiny_frame_rate_is_a_readable_number(default_throw, tmp_path):
    """(stop 47, a review) At --fps 1e-300 the turn between frames was printed with every digit, ~300 of them."""
    with pytest.warns(UserWarning, match=r"the stone turns up to \d\.\d\de\+\d+ deg between frames at 1e-300 "
                                         r"frames/s") as caught:
        write_trajectory(default_throw, tmp_path / "slow.csv", fps=1e-300)
    assert max(len(str(w.message)) for w in caught) < 300


def test_spin_per_frame_checks_its_frame_rate(default_throw):
    """(stop 47, a docs review) spin_per_frame took any fps: 0 was a bare ZeroDivisionError, -30 a negative angle."""
    from jaxskip.export import spin_per_frame

    assert spin_per_frame(default_throw, 60.0) == pytest.approx(2 * spin_per_frame(default_throw, 120.0))
    for bad in (0.0, -30.0, float("nan"), "30"):
        with pytest.raises(ParameterError, match="fps must be"):
            spin_per_frame(default_throw, bad)


def test_only_a_trajectory_beside_it_guards_the_stone_file(default_throw, tmp_path):
    """(stop 47, a review of the session's diff) Any run.json beside run.csv, one's own settings file too, was taken
    for a trajectory sharing the stone file (and the user told to delete it); a trajectory named with a suffix in
    mixed case (run.Json) was not seen at all."""
    from jaxskip import simulate

    other = simulate(stone="clanet", config=SimConfig(duration=0.05))
    write_trajectory(default_throw, tmp_path / "run.csv")
    (tmp_path / "run.json").write_text('{"my": "settings"}')
    write_trajectory(other, tmp_path / "run.csv")                 # its own stone file, replaced as before
    assert "clanet" in (tmp_path / "run.stone.obj").read_text().splitlines()[0]
    write_trajectory(default_throw, tmp_path / "x.Json")
    write_trajectory(default_throw, tmp_path / "x.csv")           # the same throw: one stone file
    with pytest.raises(ParameterError, match=r"which the trajectory 'x.Json' beside it was written with"):
        write_trajectory(other, tmp_path / "x.csv")
