"""High-level entry point: simulate one throw and get plain Python/NumPy results.

:func:`simulate` validates everything before any tracing, runs the compiled
step in chunks (stopping as soon as the stone is out of play, so a short throw
costs only its own steps), and returns a :class:`ThrowResult` of host values.
For batches and gradients use the pure :func:`jaxskip.rollout`.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import os
import sys
import time
import warnings

import jax
import jax.numpy as jnp
import numpy as np

from ._docs import document_fields
from ._progress import ProgressLine
from ._text import plural
from ._arrays import float_array, float_leaves
from ._checks import ParameterError, check_bool, check_int, check_positive, check_range, check_real
from .body import DENSITY_RANGE, RigidStone, rigid_stone
from .forces import DEFAULT_COEFFICIENTS, WaterParams, water_params
from . import quaternion
from .mesh import TriMesh
from .coupled import (check_shared_constants, check_window_fits, coupled_interval, coupled_substeps, initial_field,
                      make_coupled_step)
from .simulate import (_ALIVE, DIVERGED, OUTCOMES, DivergedWarning, STEP_LIMIT, SimConfig, StabilityWarning,
                       StoneState, Tracker, _new_tracker, _scan, diverged_message, initial_state, make_step,
                       warn_if_coarse, warn_if_inert, warn_if_unstable)
from .stones import BUILTIN_STONES, load_stone
from .throw import Throw
from .water import WaterGrid, placeless, total_volume


@document_fields
@dataclasses.dataclass(frozen=True)
class Contact:
    """One contact of the stone with the water."""

    t_start: float
    """Time the first triangle got wet [s]."""
    t_end: float
    """Time the last triangle left the water [s] (the end of the run if it never left)."""
    x: float
    """Downrange position of the centre of mass at the contact's start [m]: its distance from the
    release point along the throw's heading."""
    tilt_start: float
    """Tilt at the start [rad]: the unsigned angle between the face normal and the vertical, in [0, π]
    (a throw tilted -10° reports +0.17 rad here)."""
    tilt_end: float
    """Tilt at the end [rad], as ``tilt_start`` (NaN if the stone never left the water)."""
    x_end: float
    """Downrange position of the centre of mass at the contact's end [m] (at the end of the run if
    the stone never left the water)."""
    tilt_direction_start: float = float("nan")
    """Which way the face is tilted at the start [rad], in (-π, π]: the azimuth of the face normal's
    horizontal part, measured from straight back along the heading. 0: leading edge up (the normal
    leans back, as a throw with tilt > 0 is released); +π/2: banked, the normal leaning to the left of
    the heading; ±π: leading edge down. A spinning stone's tilt precesses (the lift acts behind the
    centre of mass), so this turns from contact to contact while ``tilt_start`` may hardly change. 0
    for a level face; NaN if unknown."""
    tilt_direction_end: float = float("nan")
    """As ``tilt_direction_start``, at the end [rad] (NaN if the stone never left the water)."""

    def to_dict(self) -> dict:
        """JSON-ready: the fields (SI: s, m, rad), ``duration`` [s] and the tilts in degrees
        (``tilt_start_deg``, ``tilt_end_deg``, ``tilt_change_deg``, ``tilt_direction_start_deg``,
        ``tilt_direction_end_deg``); values that are not known (NaN, e.g. the tilt at the end of the
        last contact when the stone never left the water) become ``None``."""
        d = dataclasses.asdict(self)
        d["duration"] = self.t_end - self.t_start
        d["tilt_start_deg"] = math.degrees(self.tilt_start)
        d["tilt_end_deg"] = math.degrees(self.tilt_end)
        d["tilt_change_deg"] = math.degrees(self.tilt_end - self.tilt_start)
        d["tilt_direction_start_deg"] = math.degrees(self.tilt_direction_start)
        d["tilt_direction_end_deg"] = math.degrees(self.tilt_direction_end)
        return {k: (v if math.isfinite(v) else None) for k, v in d.items()}


def _tilt_directions(trajectory: dict, t: np.ndarray, heading: float) -> np.ndarray:
    """:attr:`Contact.tilt_direction_start` [rad] of the recorded states at times ``t`` (K,) [s] (for each,
    the last step starting at or before it); ``heading`` [rad]. NaN for a NaN time; 0 for a level face.
    On the host in float64, all contacts at once (a JAX call would dispatch, and in a fresh process
    compile, tiny ops; a Python loop over contacts cost ~1 ms of a 4 ms ``simulate()``)."""
    t = np.asarray(t, dtype=np.float64)
    i = np.maximum(np.searchsorted(trajectory["time"], np.where(np.isfinite(t), t, 0.0), side="right") - 1, 0)
    w, x, y, z = np.asarray(trajectory["orientation"], dtype=np.float64)[i].T
    # The face normal (body z) in the world, horizontal part: column 2 of quaternion.to_matrix.
    nx, ny = 2.0 * (x * z + w * y), 2.0 * (y * z - w * x)
    back = -(nx * math.cos(heading) + ny * math.sin(heading))
    left = -nx * math.sin(heading) + ny * math.cos(heading)
    # math.atan2 per contact: NumPy's vectorised arctan2 differs from it in the last bit
    angle = np.array([math.atan2(a, b) for a, b in zip(left.tolist(), back.tolist())], dtype=np.float64)
    angle = np.where(angle == -math.pi, math.pi, angle)   # (atan2(-0.0, b < 0) is -π: outside (-π, π])
    out = np.where(np.hypot(back, left) < 1e-12, 0.0, angle)
    return np.where(np.isfinite(t), out, np.nan)


@document_fields
@dataclasses.dataclass(frozen=True)
class ThrowResult:
    """Outcome of one simulated throw (host values, SI units)."""

    bounces: int
    """Contacts that ended with the stone leaving the water (by ``bounce_clearance``)."""
    contacts: list
    """List of :class:`Contact` (at most ``config.max_contacts`` are logged)."""
    n_contacts: int
    """All contacts begun, logged or not."""
    distance: float
    """Horizontal distance from release to where the stone ended [m]."""
    outcome: str
    """One of ``sank``, ``stopped``, ``flipped``, ``time_limit``, ``step_limit``, ``diverged`` (the
    integration failed: a warning says so; see :data:`jaxskip.simulate.OUTCOMES`)."""
    final_time: float
    """Simulated time at the end [s]."""
    steps: int
    """Steps taken (flight jumps included). The trajectory holds ``steps`` rows for a throw that ended, at the
    time limit included (its last row the final state), and ``steps + 1`` for one that ran out of steps in
    play (outcome ``step_limit``: the state after the last step appended)."""
    trajectory: dict
    """Per-step arrays, the state at the start of each step: ``time`` (N,) [s], ``position`` (N, 3) [m]
    (centre of mass), ``orientation`` (N, 4) [-] (unit quaternion (w, x, y, z), body to world),
    ``velocity`` (N, 3) [m/s], ``angular_velocity`` (N, 3) [rad/s] (world frame), ``wetted_area``
    (N,) [m^2], ``force`` (N, 3) [N] (water force on the stone, world frame, gravity not included;
    :attr:`jaxskip.Record.force`). Steps are not evenly spaced (fine in contact, long jumps in
    flight): :func:`jaxskip.export.frames` resamples them. The last row is the final state (a throw that
    ran out of steps in play gets it as an extra row, its wetted area and force held from the step
    before)."""
    throw: Throw
    """The throw simulated (SI, shape ())."""
    config: SimConfig
    """The simulation settings used."""
    stone_name: str
    """The stone's name: the built-in name asked for (``"clanet"``), a mesh's ``name`` for a
    :class:`TriMesh` (which need not say its size: ``paper_stone(radius=0.03)`` is ``"paper"``), the
    file's name without the folder and suffix for an ``.obj`` path, or ``"custom"`` for a RigidStone."""
    mass: float
    """Stone mass [kg]."""
    water: WaterParams
    """The water's constants used (C_l, C_f [-], ρ_w [kg/m^3], g [m/s^2])."""
    wall_time: float
    """Wall-clock time of the simulation, compile included [s]."""
    field: dict | None = None
    """With a height field (``simulate(water_field=...)``): ``shape`` (nx, ny), ``spacing`` [m],
    ``depth`` [m], ``time_step`` [s] (the stone time between advances of the water in contact,
    :func:`jaxskip.coupled.coupled_interval`: the whole number of stone steps that reaches 1 ms to within half a
    step, at least one: 1 ms at the default ``dt`` of 0.25 ms, 0.8 ms at 0.4 ms, 0.7 ms at 0.7 ms, ``dt`` beyond),
    ``substeps`` (the equal water steps each advance splits the time pending into,
    :func:`jaxskip.coupled.coupled_substeps`: 1 with the default window), ``clamp``, ``boundary``
    (``"closed"`` or ``"sponge"``: the grid's :attr:`jaxskip.WaterGrid.boundary`), ``volume_change``
    (relative change of the water volume in the window over the run: not a conservation check. The
    window follows the stone, dropping the columns it leaves behind (with their ripples) and taking
    in still water, and a sponge border relaxes towards rest, so it need not be 0 even on a closed grid;
    it reads exactly 0 once the window has left all the disturbed water behind. The coupling itself
    conserves volume: a closed window that does not move, under a stone dropped straight down, changes
    by ~1e-14 in float64) and
    ``frames``: list of snapshots ``(time [s], origin (2,) [m], height (nx, ny) [m],
    position (3,) [m], orientation (4,))``, one per chunk of steps (``simulate``'s ``chunk``: by default
    every :data:`FIELD_CHUNK_TIME` of contact, the frames of :func:`jaxskip.plotting.animate_throw`)."""
    rigid: RigidStone | None = None
    """The stone simulated (mass properties and mesh in the body frame)."""

    def __repr__(self) -> str:
        # (the dataclass's own repr printed every trajectory array, contact and triangle: 18-97 k characters)
        return (f"ThrowResult({plural(self.bounces, 'bounce')} over {self.distance:.3f} m, "
                f"{self.outcome} after {self.final_time:.3f} s in {plural(self.steps, 'step')}; "
                f"{self.stone_name} stone of {self.mass * 1e3:.1f} g"
                + (", on a height field" if self.field else "") + ")")

    def energy(self) -> dict:
        r"""The stone's mechanical energy along :attr:`trajectory` [J], each an (N,) array, one value per row:
        ``"translation"`` :math:`\tfrac12 m|v|^2`, ``"rotation"`` :math:`\tfrac12\,\omega^\top R I R^\top\omega`
        (about the centre of mass, ``I`` the body-frame inertia tensor), ``"height"`` :math:`m g z` (the centre
        of mass above the still water line z = 0) and their sum ``"total"``.

        Only the water takes energy from a real stone, so ``"total"`` should never rise. With the default
        ``velocity="body"`` it can: each face's force is computed from the centre of mass's velocity, and the
        lift's torque can pump a wobble (the default throw: 4.63 J at release, 7.98 J at the end; docs/model.md,
        "The default free stone gains energy"; so does ``law="seed"``'s, 4.63 J at release, 5.61 J at its peak, 5.42 J
        when it flips); with the tilt held or
        ``velocity="local"`` or ``"passive"`` the water never adds energy: it falls in the water, and rises by
        up to ~1e-8 J in flight come from the split free rotation of an asymmetric stone (the paper stone at 65
        rev/s; :func:`jaxskip.simulate.free_rotation`). With the tilt held a rise is the step's error (rounding
        with Bocquet's law; with ``law="seed"`` at the default 0.25 ms up to 0.55 % over 40 random human-box throws
        of the paper stone, but 2.3 % for it at 15 m/s and 5.7 % / 212 % for the Clanet disk at 4 / 24 m/s, each
        shrinking with dt), and :func:`simulate` issues a
        :class:`jaxskip.StabilityWarning` above :data:`HELD_ENERGY_RISE` (1 %). With a height field (``field``) the
        water's own energy is not included. With the tilt held (``attitude="fixed"``) the stone does not turn, and
        ``"rotation"`` is the throw's spin energy, carried along unchanged.

        >>> from jaxskip import SimConfig, Throw, simulate
        >>> r = simulate(Throw.from_degrees(), config=SimConfig(attitude="fixed"))
        >>> e = r.energy()
        >>> bool(e["total"][0] > 1.0), bool(e["total"].max() <= e["total"][0] * (1 + 1e-6))
        (True, True)
        """
        if self.rigid is None:
            raise ParameterError("energy() needs the stone's inertia: this ThrowResult has no 'rigid' (results of "
                                 "jaxskip.simulate always do)")
        tr = self.trajectory
        v = np.asarray(tr["velocity"], dtype=float)
        omega = np.asarray(tr["angular_velocity"], dtype=float)
        # R^T omega: the angular velocity in body axes; to_matrix of the (4, N) quaternions is R as (3, 3, N)
        R = np.asarray(quaternion.to_matrix(np.asarray(tr["orientation"], dtype=float).T), dtype=float)
        body = np.einsum("jin,nj->ni", R, omega)
        inertia = np.asarray(self.rigid.inertia, dtype=float)
        parts = {"translation": 0.5 * self.mass * np.sum(v * v, axis=1),
                 "rotation": 0.5 * np.einsum("ni,ij,nj->n", body, inertia, body),
                 "height": self.mass * float(self.water.gravity) * np.asarray(tr["position"], dtype=float)[:, 2]}
        parts["total"] = parts["translation"] + parts["rotation"] + parts["height"]
        return parts

    def _energy_summary(self) -> dict:
        """``to_dict()["energy"]``: the total at release, its peak and when, at the end, and its largest rise
        above an earlier value [J, s]; None for a value that is not finite (a diverged run), so that the dict
        stays strict JSON."""
        total = self.energy()["total"]
        finite = np.isfinite(total)
        k = int(np.argmax(np.where(finite, total, -np.inf))) if finite.any() else 0
        num = lambda x: float(x) if np.isfinite(x) else None
        # the most the total ever rose above an earlier value: energy the water added, even below the release's
        gain = np.max(total - np.minimum.accumulate(total)) if finite.all() else np.nan
        return {"release": num(total[0]), "peak": num(total[k]),
                "peak_time": num(np.asarray(self.trajectory["time"])[k]), "end": num(total[-1]), "gain": num(gain)}

    def to_dict(self) -> dict:
        """JSON-ready summary with the resolved parameters, in SI (m, m/s, s, kg, kg/m^3, m/s^2) except the
        throw's angles and spin in ``parameters``, which appear only in user units: ``tilt_deg``,
        ``attack_deg``, ``heading_deg`` [deg] and ``spin_rev_s`` [rev/s] (no radian values there). Each of
        ``contacts`` is :meth:`Contact.to_dict` (its tilts in rad and in degrees). ``parameters`` holds every
        setting that can change the answer: the throw, the stone and its mass, the water's coefficients and
        every :class:`SimConfig` and :class:`ForceModel` field but ``record``, ``segment`` and ``checkpoint``
        (how the run is stored and differentiated, not what it computes). ``energy``: the stone's mechanical
        energy (:meth:`energy`'s ``"total"``) at ``release``, its ``peak`` and ``peak_time`` [s], at the ``end``,
        and its ``gain``, the most it ever rose above an earlier value [J] (energy the water added; rounding
        only, ~1e-9 J, where the law is passive). ``water`` (only with a height field): :attr:`field` without its
        ``frames``, and their ``units`` (:data:`WATER_UNITS`)."""
        t = self.throw
        return {
            "bounces": self.bounces,
            "distance": self.distance,
            "outcome": self.outcome,
            "final_time": self.final_time,
            "n_contacts": self.n_contacts,
            "steps": self.steps,
            "contacts": [c.to_dict() for c in self.contacts],
            "parameters": {
                "speed": float(t.speed),
                "tilt_deg": math.degrees(float(t.tilt)),
                "attack_deg": math.degrees(float(t.attack)),
                "spin_rev_s": float(t.spin) / (2 * math.pi),
                "height": float(t.height),
                "heading_deg": math.degrees(float(t.heading)),
                **settings_dict(self.stone_name, self.mass, self.water, self.config),
            },
            **({"energy": self._energy_summary()} if self.rigid is not None else {}),
            "wall_time": self.wall_time,
            **({"water": {**{k: v for k, v in self.field.items() if k != "frames"}, "units": WATER_UNITS}}
               if self.field else {}),
        }


def settings_dict(stone_name: str, mass: float, water: WaterParams, config: SimConfig) -> dict:
    """Every setting besides the throw that can change a result, JSON-ready, SI: ``stone`` (its name), ``mass`` [kg],
    the force model's fields, the water's ``c_lift``, ``c_friction``, ``rho_water`` [kg/m^3] and ``gravity``
    [m/s^2], and every :class:`SimConfig` field but ``record``, ``segment`` and ``checkpoint`` (how a run is stored
    and differentiated, not what it computes): the ``parameters`` of :meth:`ThrowResult.to_dict` and of
    :meth:`jaxskip.batch.BatchResult.to_dict`."""
    f = config.force
    return {"stone": stone_name, "mass": float(mass), "force_law": f.law, "faces": f.faces, "velocity": f.velocity,
            "normalize_lift": f.normalize_lift, "sharpness": f.sharpness, "c_lift": float(water.c_lift),
            "c_friction": float(water.c_friction), "rho_water": float(water.rho_water),
            "gravity": float(water.gravity), "attitude": config.attitude, "integrator": config.integrator,
            "dt": config.dt, "duration": config.duration, "max_steps": config.max_steps, "flight": config.flight,
            "max_flight_step": config.max_flight_step, "bounce_clearance": config.bounce_clearance,
            "stop_speed": config.stop_speed, "max_contacts": config.max_contacts}


@functools.lru_cache(maxsize=32)
def _builtin_stone(name: str, entry: tuple, mass, density, x64: bool) -> tuple[RigidStone, str, tuple]:
    """A built-in stone, built once per (name, its ``BUILTIN_STONES`` entry, mass, density, precision):
    building the mesh and its mass properties took ~3 ms, 15 % of a warm ``simulate()``. A
    ``RigidStone`` is immutable, so sharing it is safe; ``x64`` keys the cache on the array precision,
    ``entry`` (factory, density) on what the public dict holds now (a stone registered again under
    its name is built again)."""
    factory, default_density = entry
    # (its warnings, a stone lighter than water, are kept and given on every call by resolve_stone: raised in here
    # they reached only the first call, and named this module's line; a review, stop 46)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        built = _rigid_from_mesh(factory(), default_density, mass=mass, density=density)
    return built + (tuple((w.category, str(w.message)) for w in caught),)


def _rigid_from_mesh(mesh, default_density, *, mass, density):
    if mass is not None:
        return rigid_stone(mesh, mass=check_real("mass", mass, valid="> 0 kg")), mesh.name   # (its range: rigid_stone)
    d = default_density if density is None else check_positive("density", density, unit="kg/m^3")
    return rigid_stone(mesh, density=d), mesh.name


def resolve_stone(stone, *, mass=None, density=None) -> tuple[RigidStone, str]:
    """Turn a built-in name, an ``.obj`` path, a :class:`TriMesh` or a :class:`RigidStone` into a rigid stone.

    ``mass`` [kg] or ``density`` [kg/m^3] (in [100, 25000] kg/m^3, or a mass giving such a density)
    override the stone's default density; a ready :class:`RigidStone` is checked
    (:meth:`RigidStone.check`) and taken as it is. Returns ``(RigidStone, name)``: the built-in name as
    given, a mesh's ``name``, an ``.obj`` file's stem, or ``"custom"`` for a ready stone.
    """
    if mass is not None and density is not None:
        raise ParameterError("give mass or density, not both")
    if isinstance(stone, RigidStone):
        if mass is not None or density is not None:
            raise ParameterError("mass/density cannot be changed on a ready RigidStone")
        return float_leaves(stone.check()), "custom"
    if isinstance(stone, str) and stone in BUILTIN_STONES:
        # validated (and made hashable floats) before the cache sees them
        mass = None if mass is None else check_real("mass", mass, valid="> 0 kg")   # (its range: rigid_stone)
        density = None if density is None else check_range("density", density, *DENSITY_RANGE,
                                                           unit="kg/m^3 (cork to osmium)")
        # named as asked: "clanet" is a mesh named "disk", another size than the built-in "disk"
        rigid, _, caught = _builtin_stone(stone, BUILTIN_STONES[stone], mass, density, bool(jax.config.jax_enable_x64))
        for category, message in caught:
            warnings.warn(message, category, stacklevel=3)
        return rigid, stone
    if isinstance(stone, (str, os.PathLike)):
        mesh, default_density = load_stone(stone)
        # checked under the path as typed, so that an error names the file given, not its stem
        rigid, _ = _rigid_from_mesh(dataclasses.replace(mesh, name=str(stone)), default_density, mass=mass,
                                    density=density)
        return rigid, mesh.name
    elif isinstance(stone, TriMesh):
        from .stones import STONE_DENSITY

        mesh, default_density = stone, STONE_DENSITY
    else:
        raise ParameterError(f"stone must be a built-in name, an .obj path, a TriMesh or a RigidStone; got {stone!r}")
    return _rigid_from_mesh(mesh, default_density, mass=mass, density=density)


def _chunk_program(config: SimConfig, chunk: int, grid=None):
    """:func:`_chunk_runner` for a chunk of ``chunk`` steps of ``config``, keyed on what the chunk's program
    depends on: not on ``record`` (always on here), ``checkpoint`` (none in a chunk), ``max_steps`` or a
    ``segment`` longer than the chunk, nor on ``grid.origin`` (ignored by the coupled step), so that
    configurations differing only there share one compiled program."""
    key = dataclasses.replace(config, record=True, max_steps=chunk, segment=min(config.segment, chunk), checkpoint=0)
    if grid is None:
        return _chunk_runner(key)
    return _chunk_runner(key, placeless(grid))


@functools.lru_cache(maxsize=32)
def _chunk_runner(config: SimConfig, grid=None):
    """One compiled chunk of ``config.max_steps`` steps per chunk configuration (memoised: no recompiles;
    built through :func:`_chunk_program`, which sets ``record`` and the chunk's length).

    ``run(carry, throw, start, stone, water)``: with ``start`` true the chunk begins from the
    throw's release state and an empty tracker (``carry`` then only gives shapes, see
    :func:`_blank_carry`), otherwise from ``carry``. Releasing the stone inside the chunk's
    program saves a first call in a fresh process a second compile (~0.3 s).
    With a :class:`jaxskip.water.WaterGrid` the step is the coupled one (carry includes the field).
    """
    step = make_step(config) if grid is None else make_coupled_step(config, grid)

    @jax.jit
    def run(carry, throw, start, stone, water):
        fresh = _release(throw, stone, config.max_contacts) + tuple(carry[2:])
        carry = jax.tree_util.tree_map(lambda a, b: jnp.where(start, a, b), fresh, carry)
        return _scan(config, step, carry, stone, water)

    return run


@functools.lru_cache(maxsize=8)
def _blank_carry(contacts: int, x64: bool):
    """Zeros shaped like a flat-water carry (state, tracker), made on the host: the first chunk
    replaces them with the release state (``start=True``). Memoised per (contacts, precision):
    JAX arrays are immutable, and eight transfers cost a warm call ~0.8 ms."""
    z = lambda *shape: float_array(np.zeros(shape))
    state = StoneState(z(3), z(3), z(4), z(3), z())
    return state, Tracker(counters=jax.device_put(np.zeros(6, np.int32)), leave=z(5), log=z(contacts, 10))


def _release(throw: Throw, stone: RigidStone, contacts: int):
    """The state at release and an empty tracker: the carry a throw starts from."""
    state = initial_state(throw, stone)
    return state, _new_tracker(contacts, state.position.dtype)


@functools.lru_cache(maxsize=4)
def _default_throw(x64: bool) -> Throw:
    """``Throw.from_degrees()``, made once per precision (immutable arrays; saves a warm call ~0.8 ms)."""
    return Throw.from_degrees()


def checked_config(config, stacklevel: int = 4) -> SimConfig:
    """``config`` (None: ``SimConfig()``) after its type check; warns if its ``dt`` is coarse
    (:class:`jaxskip.AccuracyWarning`) or its velocity option does nothing with the tilt held
    (``UserWarning``, :func:`jaxskip.simulate.inert_velocity_message`), attributed ``stacklevel`` frames up (4:
    the caller of the function that calls this one)."""
    config = SimConfig() if config is None else config
    if not isinstance(config, SimConfig):
        raise ParameterError(f"config must be a jaxskip.SimConfig, got {type(config).__name__}")
    warn_if_coarse(config, stacklevel=stacklevel)
    warn_if_inert(config, stacklevel=stacklevel)
    return config


def checked_water(water) -> WaterParams:
    """``water`` after its type and range checks (:meth:`WaterParams.check`)."""
    if not isinstance(water, WaterParams):
        raise ParameterError(f"water must be a jaxskip.WaterParams (see jaxskip.water_params), got {type(water).__name__}")
    return float_leaves(water.check())  # (a weakly typed or integer leaf would compile the programs apart)


def _default_water(law: str, x64: bool) -> WaterParams:
    """``water_params(law)``, made once per (law, its current defaults, precision)."""
    return _water_of(law, tuple(sorted(DEFAULT_COEFFICIENTS[law].items())), x64)


@functools.lru_cache(maxsize=8)
def _water_of(law: str, coefficients: tuple, x64: bool) -> WaterParams:
    """``water_params(law)``, memoised; ``coefficients`` and ``x64`` only key the memo."""
    return water_params(law)


#: :func:`_release` compiled as one program (op by op, a first call in a fresh process compiled
#: ~100 tiny kernels: ~0.6 s), for the coupled water, whose field starts under the released stone.
_start = functools.partial(jax.jit, static_argnames=("contacts",))(_release)


#: Contact time [s] between the water snapshots of ``simulate(water_field=...)`` (its default ``chunk``:
#: 40 steps of 0.25 ms). Measured on the default window: a snapshot per 40 steps costs ~0.03 s more over a
#: throw than one per 1000 (2026-12-06), and gives the 30 frames of the default throw's 0.38 s.
FIELD_CHUNK_TIME = 0.01

#: Units of the entries of :attr:`ThrowResult.field` (without ``frames``) as ``to_dict()["water"]``, the CLI's
#: ``--json`` and a trajectory JSON give them, under ``"units"`` (``volume_change`` is relative).
WATER_UNITS = {"shape": "columns", "spacing": "m", "depth": "m", "time_step": "s", "substeps": "-", "clamp": "-",
               "boundary": "-", "volume_change": "-"}

#: Largest rise of a held-tilt throw's mechanical energy above an earlier value, as a fraction of its release
#: value, that :func:`simulate` lets pass without a :class:`jaxskip.StabilityWarning`. With the tilt held no face
#: turns and the water does no positive work, so a rise is the step's error: at the default 0.25 ms it reached
#: 0.55 % with ``law="seed"`` over 40 random throws of the human box (the paper stone; 1e-16 relative with Bocquet's
#: law; it falls to rounding at dt / 4), while a step beyond stability gains far more (a 5 cm, 0.5 mm disk at
#: 500 kg/m^3, 100 m/s, tilt 2 deg: 227 times its release energy at 0.25 ms; measured 2026-12-07).
HELD_ENERGY_RISE = 0.01


def held_energy_rise_message(result: "ThrowResult") -> str | None:
    """Why ``result``, a throw with the tilt held on flat water, is not to be trusted, or None: its mechanical
    energy (:meth:`ThrowResult.energy`) rose above an earlier value by more than :data:`HELD_ENERGY_RISE` of its
    release value, which the water cannot do to a stone that does not turn (only the step can). None for a free
    stone (whose default ``velocity="body"`` law can add energy: docs/model.md), a height field's throw (moving
    water can push) or a diverged run (its own warning says so)."""
    if result.config.attitude != "fixed" or result.field or result.rigid is None or result.outcome == "diverged":
        return None
    e = result._energy_summary()
    if e["gain"] is None or not e["gain"] > HELD_ENERGY_RISE * abs(e["release"]):
        return None
    gain, release = e["gain"], e["release"]
    return (f"with the tilt held the water cannot add energy, but the stone's mechanical energy rose by {gain:.3g} J "
            f"({100 * gain / abs(release):.3g} % of its {release:.3g} J at release): "
            + held_step_advice(result.config.dt))


def held_step_advice(dt: float, many: bool = False) -> str:
    """What a held-tilt energy gain says of the step ``dt`` [s], and what to do (:func:`held_energy_rise_message`'s
    and :func:`jaxskip.simulate_batch`'s warnings; ``many``: of several throws)."""
    what = "these stones and speeds" if many else "this stone and speed"
    return (f"dt = {dt * 1e3:g} ms is too long for {what} (an explicit step of a stiff contact); take a smaller dt, "
            f"e.g. {dt * 250:g} ms, and compare")


def _snapshot(carry, grid: WaterGrid) -> tuple:
    """One frame of ``ThrowResult.field["frames"]``: (time [s], window origin (2,) [m], column heights
    (nx, ny) [m], stone position (3,) [m], orientation (4,)), host arrays."""
    f = carry[2]
    return (float(carry[0].time), np.asarray(f.offset) * grid.spacing, np.asarray(f.water.height),
            np.asarray(carry[0].position), np.asarray(carry[0].orientation))


def simulate(
    throw: Throw | None = None,
    stone="paper",
    *,
    mass: float | None = None,
    density: float | None = None,
    water: WaterParams | None = None,
    config: SimConfig | None = None,
    chunk: int | None = None,
    progress: bool = False,
    water_field: WaterGrid | None = None,
) -> ThrowResult:
    """Simulate one throw on flat water, or on a height field that follows the stone.

    Parameters
    ----------
    throw : one :class:`Throw` (SI; every field a scalar, shape ``()``; checked with :meth:`Throw.check`);
        default ``Throw.from_degrees()``. A batch is refused: use :func:`jaxskip.simulate_batch`.
    stone : built-in name (``paper``, ``disk``, ``clanet``, ``ellipsoid``, ``pebble``),
        a path to an ``.obj`` file [m], a :class:`TriMesh` or a :class:`RigidStone`.
    mass, density : override the stone's default density with a mass [kg] or a density [kg/m^3], in
        [100, 25000] kg/m^3 (cork to osmium; a mass must give such a density over the mesh's volume).
    water : :class:`WaterParams`; default ``water_params(config.force.law)``.
    config : :class:`SimConfig`; default ``SimConfig()`` (a ``dt`` above 1 ms is valid but unconverged:
        an :class:`jaxskip.AccuracyWarning` says so). Its ``record`` is not used: one throw's trajectory is
        always recorded (``result.trajectory``, and the contacts' tilts are read from it); for throws without
        trajectories use :func:`jaxskip.simulate_batch`.
    chunk : steps per compiled chunk, an integer >= 1 (capped at ``config.max_steps``); the run stops after
        the first chunk in which the stone goes out of play. Default None: 1000 on flat water; with
        ``water_field``, the steps of :data:`FIELD_CHUNK_TIME` (10 ms) at ``config.dt`` (40 at 0.25 ms), since
        the water is snapshot once per chunk (``result.field["frames"]``, the frames of an animation).
    progress : print a progress line to stderr.
    water_field : a :class:`jaxskip.water.WaterGrid` (e.g. :func:`jaxskip.coupled.default_window`):
        two-way coupled water in a window that follows the stone (:mod:`jaxskip.coupled`);
        ``result.field`` then holds the grid, the volume change and a snapshot per chunk.
        The window is placed under the released stone (its ``origin`` is ignored), and its
        ``gravity`` and ``rho`` must equal ``water``'s; the window must span at least the stone's
        diameter (``2 * radius``) along each side.
        Default None: flat water.

    Returns
    -------
    :class:`ThrowResult`: ``bounces``, ``contacts`` (each :class:`Contact`: start and end time [s],
    position along the heading [m], tilt in and out [rad]), ``distance`` [m], ``outcome`` (``sank``,
    ``stopped``, ``flipped``, ``time_limit``, ``step_limit`` or ``diverged``: the integration failed,
    with a :class:`jaxskip.simulate.DivergedWarning`, a ``RuntimeWarning``), ``final_time`` [s], the per-step
    ``trajectory`` (SI arrays), the resolved throw, config, stone and water; ``help(ThrowResult)``
    lists every field with its units.

    Examples
    --------
    >>> from jaxskip import Throw, simulate
    >>> r = simulate(Throw.from_degrees(speed=7.0, tilt=20.0, attack=5.0, spin=20.0))
    >>> r.bounces > 0, r.outcome in ("sank", "stopped", "flipped", "time_limit", "step_limit")
    (True, True)
    """
    t0 = time.perf_counter()
    x64 = bool(jax.config.jax_enable_x64)
    throw = _default_throw(x64) if throw is None else throw
    if not isinstance(throw, Throw):
        raise ParameterError(f"throw must be a jaxskip.Throw, got {type(throw).__name__}")
    throw.check()
    if throw.shape != ():
        raise ParameterError(f"simulate() takes one throw; this one has batch shape {throw.shape} "
                             "(use simulate_batch or jax.vmap(rollout) for batches)")
    config = checked_config(config)
    if chunk is None:
        chunk = 1000 if water_field is None else max(1, round(FIELD_CHUNK_TIME / config.dt))
    chunk = check_int("chunk", chunk, minimum=1)
    progress = check_bool("progress", progress)
    water = _default_water(config.force.law, x64) if water is None else checked_water(water)
    throw = float_leaves(throw)  # (Python floats, jnp.asarray(9.0): weak types would compile the chunk again)
    rigid, name = resolve_stone(stone, mass=mass, density=density)
    warn_if_unstable(config, rigid, water, throw.speed, throw.height, stacklevel=3)

    if water_field is not None:
        if not isinstance(water_field, WaterGrid):
            raise ParameterError(f"water_field must be a jaxskip.water.WaterGrid or None, got {water_field!r}")
        check_shared_constants(water_field, water, name="water_field")
        check_window_fits(water_field, rigid, name="water_field")
    misses = _chunk_runner.cache_info().misses

    def runner(n):
        return _chunk_program(config, n, water_field)

    runner(min(chunk, config.max_steps))  # the first chunk's program (lru_cache: built once)
    if progress and _chunk_runner.cache_info().misses > misses:  # (not currsize: it stops growing when full)
        print("  compiling the simulator for this configuration (once, ~2 s)...", file=sys.stderr, flush=True)

    frames = []
    if water_field is None:
        carry, start = _blank_carry(config.max_contacts, x64), True
    else:
        carry, start = _start(throw, rigid, config.max_contacts), False
        carry = carry + (initial_field(water_field, carry[0].position),)
        volume0 = float(total_volume(water_field, carry[2].water))
        frames.append(_snapshot(carry, water_field))   # the release (an animation began 10 ms in)
    records = []
    done, live, line = 0, 0, ProgressLine()
    while done < config.max_steps:
        n = min(chunk, config.max_steps - done)  # the last chunk stops at max_steps (compiled only if reached)
        carry, rec = runner(n)(carry, throw, np.bool_(start), rigid, water)
        start = False
        records.append(jax.device_get(rec))
        if water_field is not None:
            frames.append(_snapshot(carry, water_field))
        done += n
        # Read on the host: indexing the device array would compile three tiny kernels (~0.1 s) on a
        # first call.
        alive = bool(np.asarray(carry[1].counters)[_ALIVE])
        if progress:   # the steps in play so far (as ThrowResult.steps counts them), not the chunks' length
            live += int(np.sum(np.diff(records[-1].time, prepend=-1.0) > 0))
            line.update(f"  simulated {float(carry[0].time):6.3f} s in {plural(live, 'step')}")
        if not alive:
            break
    if progress:
        line.close()
    field = None
    if water_field is not None:
        volume1 = float(total_volume(water_field, carry[2].water))
        field = {"shape": list(water_field.shape), "spacing": water_field.spacing, "depth": water_field.depth,
                 "time_step": coupled_interval(config, water_field),
                 "substeps": coupled_substeps(config, water_field), "clamp": water_field.clamp,
                 "boundary": water_field.boundary, "volume_change": (volume1 - volume0) / volume0,
                 "frames": frames}
    state, tr = jax.device_get(carry[:2])
    n_alive = int(np.sum([np.sum(np.diff(r.time, prepend=-1.0) > 0) for r in records]))
    traj = {k: np.concatenate([getattr(r, k) for r in records])[:n_alive] for k in
            ("time", "position", "orientation", "wetted_area", "force", "velocity", "angular_velocity")}
    if tr.alive:
        # Out of steps while in play: the last step moved the state, which no record holds (an ended throw's
        # last record is its final state). Append it, its wetted area and force held from that step.
        for k in ("time", "position", "orientation", "velocity", "angular_velocity"):
            traj[k] = np.concatenate([traj[k], np.asarray(getattr(state, k))[None]])
        for k in ("wetted_area", "force"):
            traj[k] = np.concatenate([traj[k], traj[k][-1:]])
    outcome = OUTCOMES[STEP_LIMIT] if tr.alive else OUTCOMES[int(tr.outcome)]
    end_time = float(state.time)
    if outcome == OUTCOMES[DIVERGED]:
        warnings.warn(diverged_message(f"the throw diverged at t = {end_time:.4g} s", config), DivergedWarning,
                      stacklevel=2)
    k = min(int(tr.contacts), config.max_contacts)
    heading = float(throw.heading)
    along = np.array([math.cos(heading), math.sin(heading)])  # release is at x = y = 0
    # (a run that ended after the last contact's stone left the water: that contact ends where it left; it read as
    # "in the water at the end", t_end the run's end)
    tr = tr.end_at_leave()
    # The contact log's first k rows, as host float64 columns (one NumPy op per column, not per contact).
    t_start, t_end = (np.asarray(a[:k], dtype=np.float64) for a in (tr.t_start, tr.t_end))
    tilt_end = np.asarray(tr.tilt_end[:k], dtype=np.float64)
    x_end = np.asarray(tr.x_end[:k, :2], dtype=np.float64)
    ended = np.isfinite(t_end)
    x_end = np.where(ended[:, None], x_end, np.asarray(state.position[:2])[None])
    columns = dict(
        t_start=t_start,
        t_end=np.where(ended, t_end, end_time),
        x=[float(row @ along) for row in np.asarray(tr.x_start[:k, :2])],  # (row by row: the same rounding)
        tilt_start=np.asarray(tr.tilt_start[:k], dtype=np.float64),
        tilt_end=np.where(np.isfinite(tilt_end), tilt_end, np.nan),
        x_end=[float(row @ along) for row in x_end],
        tilt_direction_start=_tilt_directions(traj, t_start, heading),
        tilt_direction_end=_tilt_directions(traj, t_end, heading),
    )
    columns = {name: np.asarray(column, dtype=np.float64).tolist() for name, column in columns.items()}
    contacts = [Contact(**{name: column[i] for name, column in columns.items()}) for i in range(k)]
    release = traj["position"][0]  # the first record: the state at release
    distance = float(np.hypot(*(np.asarray(state.position)[:2] - release[:2])))
    result = ThrowResult(
        bounces=int(tr.bounces), contacts=contacts, n_contacts=int(tr.contacts), distance=distance,
        outcome=outcome, final_time=end_time, steps=n_alive, trajectory=traj, throw=throw, config=config,
        stone_name=name, mass=float(rigid.mass), water=water, wall_time=time.perf_counter() - t0, field=field,
        rigid=rigid,
    )
    message = held_energy_rise_message(result)
    if message is not None:
        warnings.warn(message, StabilityWarning, stacklevel=2)
    return result
