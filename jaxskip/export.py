r"""A throw as evenly spaced frames, for animation and for other tools (CSV or JSON).

The simulator's steps are uneven: 0.25 ms in contact, jumps of up to ``max_flight_step`` (20 ms)
through the air. :func:`frames` samples the motion at a fixed frame rate. A frame at time
:math:`t` inside the step that starts at :math:`t_i` with state :math:`(x_i, v_i, q_i, \omega_i)`
is that state carried forward by :math:`\tau = t - t_i` under gravity and torque-free rotation:

.. math:: x(t) = x_i + v_i\,\tau - \tfrac12 g\,\tau^2\,\hat z, \qquad
          q(t) = \mathrm{free\_rotation}(q_i, L_i, \tau),

the flow the simulator itself follows through the air (``free_rotation`` in the module ``jaxskip.simulate``),
so frames in flight lie on the simulated arc and turn at the simulated spin, however long the
jump (a straight line between steps would cut the parabola short by up to g dt²/8 = 0.5 mm in a
20 ms jump, and a slerp turns at most half a turn per jump, whatever the spin). Tested against the
same throw stepped every 0.25 ms through the air: equal to rounding. In contact a step lasts
0.25 ms, and the water's push over the part of a step before a frame is left out (a few µm).

>>> from jaxskip import simulate
>>> f = frames(simulate(), fps=30.0)
>>> f["time"][:3], f["position"].shape[1], f["orientation"].shape[1]
(array([0.        , 0.03333333, 0.06666667]), 3, 4)
"""

from __future__ import annotations

import dataclasses
import json
import math
import warnings
import os
import re

import jax
import jax.numpy as jnp
import numpy as np

from . import quaternion as quat
from ._checks import ParameterError, check_range
from ._files import writing
from .api import WATER_UNITS, ThrowResult
from .body import RigidStone, body_frame
from .mesh import TriMesh, obj_text, write_obj
from .simulate import _momentum_from_spin, _one_float_type, free_rotation

#: Highest frame rate :func:`frames` accepts [1/s].
MAX_FPS = 10_000.0
#: Columns of :func:`write_trajectory`'s CSV (its first line), each name ending in its unit: time [s],
#: position [m], quaternion (w, x, y, z) [-], velocity [m/s], in the water (0/1).
COLUMNS = ("t_s", "x_m", "y_m", "z_m", "qw", "qx", "qy", "qz", "vx_m_s", "vy_m_s", "vz_m_s", "in_water")
#: Suffix of the stone file written beside a trajectory (``throw.csv`` -> ``throw.stone.obj``).
STONE_SUFFIX = ".stone.obj"


@jax.jit
def _carry(x, v, q, w, tau, stone, g):
    """States (x, v, q, ω) carried forward by ``tau`` (all with a leading frame axis) through the air."""

    def one(x, v, q, w, tau):
        L = _momentum_from_spin(stone, quat.to_matrix(q), w)
        down = jnp.stack([0.0 * g, 0.0 * g, g])
        return x + v * tau - 0.5 * down * tau**2, v - down * tau, free_rotation(q, L, stone, tau)

    return jax.vmap(one)(x, v, q, w, tau)


def frames(result, fps: float = 60.0) -> dict:
    """The throw of ``result`` (:func:`jaxskip.simulate`) sampled every ``1 / fps`` s from release.

    ``fps`` [1/s] in (0, 10000]. Frames run from 0 to the last simulated step: when that step falls between
    two frames it is added as the last frame (a trajectory ended up to a frame early: a stone that sank was
    last seen above its plunge, a run shorter than a frame was a single row). Returns host arrays:
    ``time`` (M,) [s], ``position`` (M, 3) [m] (centre of mass), ``orientation`` (M, 4) [-] (unit
    quaternion (w, x, y, z), body to world), ``velocity`` (M, 3) [m/s], ``in_water`` (M,) bool (the
    step the frame falls in had a wet triangle). With ``attitude="fixed"`` the attitude is held, as
    in the simulation (the recorded spin is the throw's, never applied).

    ``result``: a :class:`jaxskip.ThrowResult` with its trajectory (as :func:`jaxskip.simulate`
    returns it); anything else is refused with :class:`~jaxskip.ParameterError`.

    >>> from jaxskip import simulate
    >>> f = frames(simulate(), fps=30.0)
    >>> float(f["time"][1]), f["position"].shape == (len(f["time"]), 3), bool(f["in_water"].any())
    (0.03333333333333333, True, True)
    """
    _check_result(result)
    fps = check_range("fps", fps, 0.0, MAX_FPS, unit="frames/s", low_open=True)
    if result.rigid is None:
        raise ParameterError("result has no stone (rigid): frames need a ThrowResult from jaxskip.simulate")
    traj = result.trajectory
    t = np.asarray(traj["time"], dtype=np.float64)
    times = np.arange(int(math.floor(t[-1] * fps + 1e-9)) + 1) / fps
    if t[-1] - times[-1] > 1e-9:   # the last simulated step, between frames
        times = np.append(times, t[-1])
    # the step each frame falls in (a frame within 1 ns of a step's start, as rounding leaves it, takes that step)
    i = np.clip(np.searchsorted(t, times + 1e-9, side="right") - 1, 0, len(t) - 1)
    m = len(times)
    # Padded to a power of two (at least 64 frames) so that throws of other lengths reuse one program.
    pad = max(64, 1 << (m - 1).bit_length())
    j, tau = np.concatenate([i, np.full(pad - m, i[-1])]), np.concatenate([times - t[i], np.zeros(pad - m)])
    # JAX's float type now (a result simulated in float32 before jax_enable_x64 was switched on met a raw
    # "lax.mul requires arguments to have the same dtypes" error: its stone was float32, the constants float64)
    dtype = jax.dtypes.canonicalize_dtype(np.float64)
    rigid = _one_float_type(result.rigid)[0]
    pick = lambda k: np.asarray(traj[k])[j]  # noqa: E731
    # the simulator holds q in fixed attitude: so do the frames (its recorded spin is never applied)
    spin = np.zeros_like(pick("angular_velocity")) if result.config.attitude == "fixed" else pick("angular_velocity")
    x, v, q = _carry(*(jnp.asarray(a, dtype=dtype) for a in (pick("position"), pick("velocity"),
                                                             pick("orientation"), spin, tau)),
                     rigid, jnp.asarray(result.water.gravity, dtype))
    return {"time": times, "position": np.asarray(x)[:m], "orientation": np.asarray(q)[:m],
            "velocity": np.asarray(v)[:m], "in_water": np.asarray(traj["wetted_area"])[i] > 0.0}


def _check_result(result) -> None:
    """Refuse anything but a :class:`jaxskip.ThrowResult` (a batch's result, a dict, ...)."""
    if not isinstance(result, ThrowResult):
        raise ParameterError(f"result must be a jaxskip.ThrowResult (as returned by jaxskip.simulate), "
                             f"got {type(result).__name__}")


def body_mesh(stone) -> TriMesh:
    """The stone's surface in its body frame [m] (origin at the centre of mass, axes along the principal
    axes: the frame :func:`frames`' positions and quaternions place), as a closed indexed mesh.

    ``stone``: a :class:`jaxskip.RigidStone` (e.g. a :class:`jaxskip.ThrowResult`'s ``rigid``);
    anything else is refused with :class:`~jaxskip.ParameterError`. A vertex of the body at ``v`` is at
    ``R(q) v + x`` in the world, with ``x`` a frame's position and ``R(q)`` its quaternion's rotation."""
    if not isinstance(stone, RigidStone):
        raise ParameterError(f"stone must be a jaxskip.RigidStone (e.g. a ThrowResult's .rigid, or "
                             f"jaxskip.rigid_stone(mesh)), got {type(stone).__name__}")
    tri = np.asarray(stone.triangles, dtype=np.float64)
    vertices, index = np.unique(tri.reshape(-1, 3), axis=0, return_inverse=True)
    return TriMesh(vertices, index.reshape(-1, 3), name="stone in its body frame")


def stone_path(path) -> str:
    """Where :func:`write_trajectory` puts the stone for a trajectory at ``path``: ``throw.csv`` ->
    ``throw.stone.obj``. ``path``: a file path (str or path-like)."""
    try:
        path = os.fspath(path)
    except TypeError:
        raise ParameterError(f"path must be a file path (a str or path-like), got {path!r:.60}") from None
    return os.path.splitext(path)[0] + STONE_SUFFIX


#: The first words of every stone file :func:`write_trajectory` writes (its OBJ comment line).
STONE_HEADER = "# jaxskip trajectory "


def _stone_file_owner(obj: str) -> str | None:
    """The trajectory file name an existing stone file ``obj`` was written for (None: no such file).
    Raises :class:`ParameterError` for a file :func:`write_trajectory` did not write (a user's own mesh)."""
    if not os.path.isfile(obj):
        return None
    try:
        with open(obj, encoding="utf-8", errors="replace") as fh:
            first = fh.readline()
    except OSError:
        first = ""
    if not first.startswith(STONE_HEADER):
        raise ParameterError(f"the trajectory's stone file {obj!r} exists and was not written by jaxskip (it may be "
                             "your own mesh): writing the trajectory would replace it; choose another trajectory "
                             "name or move that file")
    return _split_owner(first)[0]


def _split_owner(first: str) -> tuple:
    """A stone file's first line, ``# jaxskip trajectory NAME.csv: the throw``, as ``(NAME.csv, the throw)``. The
    name ends at its first ``.csv: `` or ``.json: `` (it may hold colons itself: ``run_12:30.csv`` read as
    ``run_12``), with runs of white space as one (the OBJ's comment line squeezes them)."""
    m = re.match(r"(.*?\.(?:csv|json)): ", first[len(STONE_HEADER):], flags=re.IGNORECASE | re.DOTALL)
    if m is None:    # (not a line this module wrote: no name to compare)
        return "", first
    return m.group(1), first[len(STONE_HEADER) + m.end():]


def _same_name(owner: str, path: str) -> bool:
    """Whether a stone file's trajectory ``owner`` is ``path``'s file name (white space runs as one)."""
    return owner.split() == os.path.basename(path).split()


def _siblings(path: str) -> list:
    """The other trajectories beside ``path`` that share its stone file, by file name: ``throw.json`` beside
    ``throw.csv`` (a suffix in any case), each one :func:`write_trajectory` wrote (a JSON naming the stone file, a
    CSV headed by :data:`COLUMNS`; a file of one's own of that name is not one: a review)."""
    folder = os.path.dirname(os.path.abspath(path))
    stem = os.path.splitext(os.path.basename(path))[0]
    obj = os.path.basename(stone_path(path))
    found = []
    for name in sorted(os.listdir(folder)):
        root, suffix = os.path.splitext(name)
        other = os.path.join(folder, name)
        if root != stem or suffix.lower() not in (".csv", ".json") or not os.path.isfile(other):
            continue
        if os.path.exists(path) and os.path.samefile(other, path):   # (itself, under another case, on a case-blind disk)
            continue
        try:
            with open(other, encoding="utf-8") as fh:
                if suffix.lower() == ".csv":
                    mine = fh.readline().strip() == ",".join(COLUMNS)
                else:
                    data = json.load(fh)
                    mine = isinstance(data, dict) and data.get("stone_obj") == obj
        except (OSError, ValueError):
            mine = False
        if mine:
            found.append(name)
    return found


def check_stone_file(path) -> None:
    """Refuse, before a run, a trajectory ``path`` whose stone file (:func:`stone_path`) exists and was not
    written by :func:`write_trajectory`: a user's own ``throw.stone.obj`` is never overwritten."""
    _stone_file_owner(stone_path(path))


def _drop_owner(text: str) -> str:
    """A stone file's text without the trajectory name in its first line."""
    first, _, rest = text.partition("\n")
    return _split_owner(first)[1] + "\n" + rest


def _water_words(result) -> str:
    """The water of ``result``'s throw, for the ``about`` text: flat, or the height field it ran on."""
    if not result.field:
        return "water at z = 0"
    nx, ny = result.field["shape"]
    return (f"water at rest at z = 0; the throw ran on a moving height field ({nx}x{ny} columns of "
            f"{result.field['spacing']:g} m following the stone), not written here")


def _quaternion(R: np.ndarray) -> np.ndarray:
    """The unit quaternion (w, x, y, z), w >= 0, of a rotation matrix ``R`` (3, 3) (Shepperd's method: the
    largest of the four squares first, so no division by a small number)."""
    t = np.trace(R)
    squares = np.array([1 + t, 1 + 2 * R[0, 0] - t, 1 + 2 * R[1, 1] - t, 1 + 2 * R[2, 2] - t])
    k = int(np.argmax(squares))
    r = 0.5 * math.sqrt(squares[k])
    if k == 0:
        q = [r, (R[2, 1] - R[1, 2]) / (4 * r), (R[0, 2] - R[2, 0]) / (4 * r), (R[1, 0] - R[0, 1]) / (4 * r)]
    elif k == 1:
        q = [(R[2, 1] - R[1, 2]) / (4 * r), r, (R[0, 1] + R[1, 0]) / (4 * r), (R[0, 2] + R[2, 0]) / (4 * r)]
    elif k == 2:
        q = [(R[0, 2] - R[2, 0]) / (4 * r), (R[0, 1] + R[1, 0]) / (4 * r), r, (R[1, 2] + R[2, 1]) / (4 * r)]
    else:
        q = [(R[1, 0] - R[0, 1]) / (4 * r), (R[0, 2] + R[2, 0]) / (4 * r), (R[1, 2] + R[2, 1]) / (4 * r), r]
    q = np.asarray(q)
    return q if q[0] >= 0 else -q


def mesh_frame(result, mesh: TriMesh) -> dict:
    """Where the body frame of ``result``'s stone lies in ``mesh``'s own frame, to drive your mesh (its vertex
    order, UVs and materials) by :func:`frames`: ``{"center_of_mass": (3,) [m], "rotation": (4,) quaternion
    (w, x, y, z)}``, so that the mesh's point ``p`` is at ``R(rotation) (p - center_of_mass)`` in the body frame
    and at ``x + R(q) R(rotation) (p - center_of_mass)`` in the world at a frame of position ``x`` and
    quaternion ``q`` (:func:`jaxskip.body.body_frame`).

    ``mesh``: the :class:`jaxskip.TriMesh` the stone was made from, in the frame you want the answer in
    (:func:`jaxskip.stones.source_mesh`: a built-in's mesh, or an ``.obj`` file's as written; ``load_stone``'s copy
    of a file is moved to its centre of mass); one whose triangles, so placed, are not the stone's is refused
    with a :class:`~jaxskip.ParameterError`.

    >>> from jaxskip import simulate
    >>> from jaxskip.stones import load_stone
    >>> m = mesh_frame(simulate(stone="clanet"), load_stone("clanet")[0])
    >>> bool(np.allclose(m["rotation"], [1.0, 0.0, 0.0, 0.0], atol=1e-9))     # the disk keeps its own axes
    True
    """
    centre, axes = _mesh_axes(result, mesh)
    return {"center_of_mass": centre, "rotation": _quaternion(axes.T)}


def _mesh_axes(result, mesh) -> tuple:
    """:func:`mesh_frame`'s checks, and its centre of mass (3,) [m] and principal axes (3, 3) (columns)."""
    _check_result(result)
    if not isinstance(mesh, TriMesh):
        raise ParameterError(f"mesh must be the jaxskip.TriMesh the stone was made from "
                             f"(jaxskip.stones.source_mesh(name)), got {type(mesh).__name__}")
    if result.rigid is None:
        raise ParameterError("result has no stone (rigid): a mesh frame needs a ThrowResult from jaxskip.simulate")
    centre, axes = body_frame(mesh)
    placed = ((np.asarray(mesh.vertices, dtype=np.float64) - centre) @ axes)[np.asarray(mesh.faces)]
    stone = np.asarray(result.rigid.triangles, dtype=np.float64)
    if placed.shape != stone.shape or not np.allclose(placed, stone, rtol=0.0, atol=1e-5 * float(result.rigid.radius)):
        raise ParameterError(f"mesh {mesh.name!r} is not the stone this throw was simulated with ({stone.shape[0]} "
                             f"triangles, {result.stone_name!r}): give the mesh it was made from")
    return centre, axes


def write_trajectory(result, path, fps: float = 60.0, mesh: TriMesh | None = None) -> str:
    """Write :func:`frames` of ``result`` to ``path`` and the stone beside it; return the stone's path.

    ``result``: a :class:`jaxskip.ThrowResult` (:func:`jaxskip.simulate`). ``path``: a ``str`` or
    :class:`os.PathLike` ending in ``.csv`` or ``.json`` (any case), in a folder that exists, and not
    itself a folder (nor is the stone's path); the file is overwritten. ``fps`` [1/s] in (0, 10000].
    Everything is checked before anything is written. SI units; quaternions (w, x, y, z) rotate body
    to world (z up, the water at z = 0).

    * ``.csv``: plain, no comment lines: the column names :data:`COLUMNS` on the first line, then one
      row per frame (9 significant digits, ``in_water`` 0 or 1).
    * ``.json``: one object ``{"about": text (the throw, as the OBJ's first line), "fps": fps, "units":
      {key: unit}, "stone_obj": the OBJ's file name, "frames": {key: list, one value per frame}}`` with
      the keys ``t, x, y, z, qw, qx, qy, qz, vx, vy, vz, in_water`` (not :data:`COLUMNS`: no units in
      the names; ``units`` gives them, ``in_water`` as true/false), and, for a throw on a height field
      (``simulate(water_field=...)``), ``"water"``: the grid as :attr:`jaxskip.ThrowResult.field` gives it,
      without its snapshots (the surface itself is not written; the ``about`` text says so).

    ``mesh``: optional, the :class:`jaxskip.TriMesh` the stone was made from
    (:func:`jaxskip.stones.source_mesh`; checked by :func:`mesh_frame`). With it the stone's OBJ keeps that
    mesh's vertex order, its comment line and the JSON (``"mesh_frame"``: ``center_of_mass`` [m], ``rotation``
    (w, x, y, z)) say where the body frame lies in the mesh's own frame: drive your own mesh (UVs, materials)
    by ``x + R(q) R(rotation) (p - center_of_mass)``.

    The stone is written in the body frame those quaternions rotate (:func:`body_mesh`) as an OBJ at
    :func:`stone_path` (``PATH`` with :data:`STONE_SUFFIX`: ``throw.csv`` -> ``throw.stone.obj``), its first
    line a comment describing the throw (stone, mass, speed, angles, spin, bounces, outcome and when the motion
    ends, the conventions; not the frame rate, so that one stone serves the throw's trajectories at any rate);
    that path is returned. An existing file there is overwritten only if this function wrote it, for this
    trajectory or for another of the same throw (``throw.json`` after ``throw.csv``); a file it did not
    write (your own mesh) or another throw's stone is refused with a :class:`ParameterError`, before
    anything is written.

    >>> import os, tempfile
    >>> from jaxskip import simulate
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     obj = write_trajectory(simulate(), os.path.join(folder, "throw.csv"), fps=400.0)
    ...     with open(os.path.join(folder, "throw.csv")) as fh:
    ...         header = fh.readline().strip()
    >>> os.path.basename(obj), header == ",".join(COLUMNS)
    ('throw.stone.obj', True)
    """
    _check_result(result)
    if not isinstance(path, (str, os.PathLike)) or not isinstance(os.fspath(path), str):
        raise ParameterError(f"path must be a str or os.PathLike ending in .csv or .json, got {path!r}")
    path = os.fspath(path)
    if not path.lower().endswith((".csv", ".json")):
        raise ParameterError(f"path must end in .csv or .json, got {path!r}")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise ParameterError(f"path's folder must exist, got {path!r} (no folder {folder!r})")
    obj = stone_path(path)
    for name, target in (("path", path), ("path's stone file", obj)):
        if os.path.isdir(target):
            raise ParameterError(f"{name} {target!r} is a folder, not a file: choose another trajectory path")
    owner = _stone_file_owner(obj)   # (a file jaxskip did not write is refused before anything is written)
    placed = None if mesh is None else _mesh_axes(result, mesh)
    if result.outcome == "diverged":   # (its files gave no sign of it: energy growing to 1e5 J, written as any other)
        from .simulate import DivergedWarning

        warnings.warn("this throw diverged (outcome 'diverged': the contact step was too long for it): the trajectory "
                      "written is not a motion; take a smaller dt", DivergedWarning, stacklevel=2)
    f = frames(result, fps)
    turn = spin_per_frame(result, fps)
    if turn > math.pi:   # (the default throw turned up to 296 deg between frames at 60 frames/s, in silence)
        said = f"{math.degrees(turn):.0f}" if turn < 1e6 else f"{math.degrees(turn):.3g}"   # (not 300 digits)
        warnings.warn(f"the stone turns up to {said} deg between frames at {fps:g} frames/s: a tool "
                      "that interpolates between keyframes turns it the short way, backwards; at least "
                      f"{math.ceil(fps * turn / (math.pi / 2)):d} frames/s keep it to a quarter turn a frame",
                      UserWarning, stacklevel=2)
    t = result.throw
    about = (f"jaxskip trajectory {os.path.basename(path)}: {result.stone_name} stone of {result.mass * 1e3:.1f} g "
             f"in its body frame (centre of mass, principal axes); speed {float(t.speed):g} m/s, tilt "
             f"{math.degrees(float(t.tilt)):g} deg, attack {math.degrees(float(t.attack)):g} deg, spin "
             f"{float(t.spin) / (2 * math.pi):g} rev/s; {result.bounces} bounces, {result.outcome}; the motion "
             # (the run's last time, whatever the frame rate: one stone file serves every rate)
             f"ends there, at t = {float(np.asarray(result.trajectory['time'])[-1]):.9g} s, the last frame's time "
             "(off the frame grid unless it falls on it); quaternions (w, x, y, z) rotate the body frame to the world frame, z up "
             "(an OBJ importer that assumes y up must be told z up); " + _water_words(result))
    if placed is None:
        stone = dataclasses.replace(body_mesh(result.rigid), name=about)
    else:   # the mesh's own vertex order; where its frame lies
        c, axes = placed
        about += (f"; vertices in the order of {mesh.name}, whose point p is at R(rotation) (p - c) here: c = "
                  f"({', '.join(f'{x:.9g}' for x in c)}) m, rotation (w, x, y, z) = "
                  f"({', '.join(f'{x:.9g}' for x in _quaternion(axes.T))})")
        stone = TriMesh((np.asarray(mesh.vertices, dtype=np.float64) - c) @ axes, np.asarray(mesh.faces), name=about)
    if owner is not None:
        # the stone of another trajectory (throw.json's, now writing throw.csv), or of this one beside another
        # (throw.csv again, throw.json beside it): replaced only if it is the same stone of the same throw, told
        # apart by nothing but the trajectory's name (a throw.csv of another stone gave throw.json its stone)
        with open(obj, encoding="utf-8", errors="replace") as fh:
            same = _drop_owner(fh.read()) == _drop_owner(obj_text(stone))
        beside = _siblings(path)
        if not same and not _same_name(owner, path):
            raise ParameterError(f"the trajectory's stone file {obj!r} holds the stone of another throw, written "
                                 f"with the trajectory {owner!r}: writing {os.path.basename(path)!r} would replace it; "
                                 "choose another trajectory name")
        if not same and beside:
            raise ParameterError(f"the trajectory's stone file {obj!r} holds the stone of another throw, which the "
                                 f"trajectory {beside[0]!r} beside it was written with: writing "
                                 f"{os.path.basename(path)!r} would give {beside[0]!r} this throw's stone; delete "
                                 f"{beside[0]!r} or choose another trajectory name")
    write_obj(obj, stone)
    table = np.column_stack([f["time"], f["position"], f["orientation"], f["velocity"],
                             f["in_water"].astype(np.float64)])
    if path.lower().endswith(".csv"):
        with writing(path):
            np.savetxt(path, table, delimiter=",", fmt=["%.9g"] * 11 + ["%d"],
                       header=",".join(COLUMNS), comments="")
        return obj
    keys = ("t", "x", "y", "z", "qw", "qx", "qy", "qz", "vx", "vy", "vz")
    out = {"about": about, "fps": fps, "units": dict(zip(keys + ("in_water",), ("s", "m", "m", "m", "-", "-", "-",
                                                                                "-", "m/s", "m/s", "m/s", "bool"))),
           "stone_obj": os.path.basename(obj),
           **({"mesh_frame": {"center_of_mass": placed[0].tolist(), "rotation": _quaternion(placed[1].T).tolist(),
                              "units": {"center_of_mass": "m", "rotation": "-"}}} if placed is not None else {}),
           **({"water": {**{k: v for k, v in result.field.items() if k != "frames"}, "units": WATER_UNITS}}
              if result.field else {}),
           # (NaN, a diverged throw's, as null: strict JSON has no NaN, and JSON.parse refused the file)
           "frames": {**{k: [None if math.isnan(v) else v for v in table[:, c].tolist()] for c, k in enumerate(keys)},
                      "in_water": f["in_water"].tolist()}}
    with writing(path), open(path, "w") as fh:
        json.dump(out, fh, allow_nan=False)
    return obj


def spin_per_frame(result, fps: float) -> float:
    """The largest angle [rad] the stone of ``result`` turns between two frames at ``fps`` [1/s] (a frame rate in
    (0, 10000]): the largest angular speed of its trajectory over ``fps`` (0 with the tilt held, where the stone does not
    turn). Above π a tool that interpolates between keyframes turns it the wrong way (:func:`write_trajectory`
    warns)."""
    _check_result(result)
    # (0 was a bare ZeroDivisionError, -30 a negative angle, "30" a TypeError; a review)
    fps = check_range("fps", fps, 0.0, MAX_FPS, unit="frames/s", low_open=True)
    if result.config.attitude == "fixed":
        return 0.0
    w = np.asarray(result.trajectory["angular_velocity"], dtype=np.float64)
    speed = np.sqrt(np.sum(w * w, axis=-1))
    return float(np.max(speed[np.isfinite(speed)], initial=0.0)) / fps


__all__ = ["COLUMNS", "MAX_FPS", "STONE_HEADER", "STONE_SUFFIX", "WATER_UNITS", "body_mesh", "check_stone_file", "frames",
           "mesh_frame", "spin_per_frame", "stone_path", "write_trajectory"]
