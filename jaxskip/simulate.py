r"""The pure step and the scanned rollout.

Time stepping ("model no more than the scene needs")
----------------------------------------------------
Air time is about a hundred times contact time, so flights are not spent in
fine steps. Each step first measures the gap :math:`\delta` between the
stone's lowest vertex and the water. No point of the stone can close the gap
faster than :math:`v_z - |\omega| R` (with :math:`R` the stone's bounding
radius) while gravity pulls at :math:`g`, so contact cannot begin before

.. math:: t^* = \frac{b + \sqrt{b^2 + 2 g \delta}}{g}, \qquad b = v_z - |\omega| R .

The step length is :math:`\mathrm{clip}(t^*, \Delta t, \Delta t_{\max})`:
a conservative-advancement jump through the air (``max_flight_step``
bounds it so the free rotation stays accurate, and so does :func:`rotation_cap` for a
spinning stone that is not axisymmetric), and the fine ``dt`` as soon
as the stone is within one step of the water or in it. Both integrators
integrate gravity exactly, so a jump follows the exact parabola. The bound
must allow for the rim speed :math:`|\omega| R`, so spin shortens the jumps:
the default throw (20 rev/s) crosses its 0.15 s of air in 252 steps instead
of 615 at fixed ``dt`` (179 instead of 843 without spin). A contact costs
``contact_time / dt``.

Integrators
-----------
``"euler"``: semi-implicit (symplectic) Euler on the water force, with
gravity integrated exactly; angular momentum is the integrated variable and
the attitude is advanced by the exponential map. ``"rk4"``: classical
Runge–Kutta on position, velocity, quaternion and angular momentum.

``attitude="fixed"`` holds the attitude (Bocquet's and Clanet's high-spin
limit): 3 degrees of freedom, no torque, and the water sees only the
centre-of-mass velocity.

Everything here is a pure function of pytrees; the rollout is a fixed-length
``lax.scan`` with an ``alive`` mask (no ``while_loop``), so it can be jitted,
vmapped over throws and differentiated in reverse mode.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import types
import warnings

import jax
import jax.numpy as jnp
import numpy as np

from ._docs import document_fields
from . import quaternion as quat
from ._arrays import face_max, face_min
from ._checks import ParameterError, check_bool, check_choice, check_int, check_positive, check_range, check_real
from .body import RigidStone
from .forces import (ForceModel, WaterParams, body_total_force, body_triangle_forces, body_water_load, flat_surface,
                     vertex_heights)
from .throw import MAX_SPEED, Throw, attitude

INTEGRATORS = ("euler", "rk4")
ATTITUDES = ("free", "fixed")
FLIGHTS = ("jump", "step")

#: Outcome codes of a rollout (:attr:`Tracker.outcome`), each an index into :data:`OUTCOMES`.
RUNNING, SANK, STOPPED, FLIPPED, TIME_LIMIT, STEP_LIMIT, DIVERGED = 0, 1, 2, 3, 4, 5, 6
#: The outcome names, indexed by outcome code: ``OUTCOMES[int(tracker.outcome)]``. ``"running"`` (0) only
#: while the stone is in play; a finished rollout ends ``"sank"`` (no point above the water),
#: ``"stopped"`` (slower than ``SimConfig.stop_speed`` in the water), ``"flipped"`` (face normal pointing
#: down), ``"time_limit"`` (``SimConfig.duration`` reached), ``"step_limit"`` (``SimConfig.max_steps``
#: ran out first) or ``"diverged"`` (the integration failed: the state is no longer finite, or the stone
#: moves faster than :data:`DIVERGED_SPEED`, which no throw can reach; the state is kept as it was then —
#: take a smaller ``dt``).
OUTCOMES = ("running", "sank", "stopped", "flipped", "time_limit", "step_limit", "diverged")
#: Speed [m/s] beyond which a run counts as diverged: ten times the fastest accepted throw
#: (:data:`jaxskip.throw.MAX_SPEED`); a fall from the highest release adds less than 45 m/s.
DIVERGED_SPEED = 10.0 * MAX_SPEED


def diverged_message(what: str, config: "SimConfig") -> str:
    """The warning for outcome ``"diverged"`` (``what``: which run, and when)."""
    return (f"{what} (outcome 'diverged'): the stone's state is no longer finite, or faster than "
            f"{DIVERGED_SPEED:g} m/s, so its distance and contacts from then on mean nothing; the contact step "
            f"dt = {config.dt:g} s is too long for this stone and throw (a light or thin stone, a fast throw, "
            f"a long dt): take a smaller dt")


# Contact phases.
AIR, WET, LEAVING = 0, 1, 2

MAX_STEPS = 10_000_000
"""Largest accepted ``SimConfig.max_steps``."""
MAX_DT = 0.01
"""Largest accepted ``SimConfig.dt`` [s] (above :data:`ACCURATE_DT` answers are unconverged)."""


MAX_BOUNCE_CLEARANCE = 0.01
"""Largest :attr:`SimConfig.bounce_clearance` [m]: 1 cm, ten times the default. (At 1 m the default throw
was one contact that never ended: 0 bounces, and no error.)"""

MAX_SLOPE = 1000.0
"""Largest ``max_slope`` [m/m] of a surface for :func:`make_step` (a steeper one: ``SimConfig(flight="step")``)."""


@document_fields
@dataclasses.dataclass(frozen=True)
class SimConfig:
    """Static simulation settings (hashable; a change recompiles, a new throw does not).

    >>> config = SimConfig(dt=1e-4, duration=2.0, max_steps=steps_for(2.0, 1e-4), attitude="fixed")
    >>> config.max_steps, config.record
    (20250, True)
    """

    dt: float = 2.5e-4
    """Time step in and near the water [s], in (0, 0.01]. Above :data:`ACCURATE_DT` (1 ms) answers are
    unconverged: :func:`jaxskip.simulate` and :func:`jaxskip.simulate_batch` then warn
    (:class:`AccuracyWarning`)."""
    duration: float = 5.0
    """Simulated time limit [s], >= dt. No step passes it (the last flight jump or contact step is cut short to end
    there), so a run ended by ``time_limit`` stops at ``duration`` exactly (as the step's float type holds it: in
    float32 0.2 s is 0.20000000298), whatever the throw: a state at a fixed time, whose gradient has no end-time
    term."""
    max_steps: int = 20250
    """Scan length: steps available for contacts and flights (outcome ``step_limit`` if too few).
    The default is :func:`steps_for` of the default ``duration`` and ``dt``: a stone may stay in the
    water for the whole ``duration`` and still end by ``time_limit``, not ``step_limit`` (fewer steps cut
    short fast, flat throws that plane for over 3 s). Raise it with ``duration`` or a smaller ``dt``
    (``steps_for`` gives the number). An integer in [1, 10^7]."""
    integrator: str = "euler"
    """``"euler"`` (semi-implicit, gravity exact) or ``"rk4"``."""
    attitude: str = "free"
    """``"free"`` (6-DoF with gyroscopic torques) or ``"fixed"`` (tilt held; high-spin limit: the stone does not
    turn, so the spin sets no motion and ``force.velocity`` ``"local"`` and ``"passive"`` act as ``"body"``)."""
    flight: str = "jump"
    """``"jump"``: conservative-advancement steps through the air; ``"step"``: fixed ``dt`` everywhere."""
    max_flight_step: float = 0.02
    """Longest step through the air [s] (bounds the free-rotation error of a jump), >= ``dt``."""
    force: ForceModel = ForceModel()
    """The water-force model (law, loaded faces, velocity, lift normalisation, smoothing)."""
    max_contacts: int = 64
    """Contacts logged in detail (more are still counted), in [1, 10^5]."""
    bounce_clearance: float = 1e-3
    """A contact ends in a bounce once the lowest point is this far above the water [m], in (0, 0.01]
    (:data:`MAX_BOUNCE_CLEARANCE`: the default throw's later hops rise only millimetres, so a larger
    clearance merges them into one contact that never ends and counts no bounce). Seen at a step's start,
    that height confirms the bounce from the flight's second dry step on (a spinning mesh's polygon rim can
    lift its lowest point for a single step without a flight); a step whose bound on the lowest point's
    path (vertical speed, less the rim's speed, under gravity) peaks above it confirms it at once."""
    stop_speed: float = 0.05
    """Below this speed [m/s] (in (0, 100], the fastest throw) in the water the stone counts as stopped."""
    record: bool = True
    """Return per-step records (a bool): time, position, attitude, wetted area, water force, gap, velocity
    and angular velocity, 19 numbers a step (76 / 152 B in float32 / float64: 1.5 / 3 MB for a
    vmapped 20250-step scan per throw); off for big batches."""
    segment: int = 50
    """Steps per segment. The scan runs in segments of this many steps; a segment that begins
    with the stone out of play is skipped whole, in the forward and the reverse pass, so a throw
    costs about its own steps rather than ``max_steps`` (a single throw, or a batch once every
    throw in it is out of play; under ``vmap`` a segment runs while any throw is in play).
    A segment longer than ``max_steps`` is capped at ``max_steps``. In [1, 10^7]."""
    checkpoint: int = 1
    """Reverse-mode memory/time trade-off (no effect on a forward run). 1 (default): nested
    rematerialisation — each segment is checkpointed and, inside it, each step: only one carry
    per segment plus one segment's carries are stored (sub-linear memory).
    0: every step's residuals are stored (memory grows with steps; and slower in every measurement: a reverse pass
    of 250 steps 3.7 ms against 2.1 ms, of 4250 steps 51.5 ms / 83 MB against 9.5 ms / 0.08 MB, float64, a
    review, stop 46; the stored residuals cost more to write and read than recomputing them)."""

    def __post_init__(self):
        # (checked values stored as plain floats: a NumPy scalar or 0-d array would not hash)
        set_ = functools.partial(object.__setattr__, self)
        set_("dt", check_range("dt", self.dt, 0.0, MAX_DT, unit="s", low_open=True))
        set_("duration", check_duration(self.duration, self.dt))
        set_("max_steps", check_int("max_steps", self.max_steps, minimum=1, maximum=MAX_STEPS))
        check_choice("integrator", self.integrator, INTEGRATORS)
        check_choice("attitude", self.attitude, ATTITUDES)
        check_choice("flight", self.flight, FLIGHTS)
        set_("max_flight_step", check_positive("max_flight_step", self.max_flight_step, unit="s"))
        if self.max_flight_step < self.dt:
            raise ParameterError(f"max_flight_step must be >= dt ({self.dt:g} s), got {self.max_flight_step:g} s "
                                 "(every step would shrink to it)")
        set_("max_contacts", check_int("max_contacts", self.max_contacts, minimum=1, maximum=100_000))
        set_("bounce_clearance", check_range("bounce_clearance", self.bounce_clearance, 0.0, MAX_BOUNCE_CLEARANCE,
                                             unit="m", low_open=True))
        set_("stop_speed", check_range("stop_speed", self.stop_speed, 0.0, MAX_SPEED, unit="m/s", low_open=True))
        set_("segment", check_int("segment", self.segment, minimum=1, maximum=MAX_STEPS))
        set_("checkpoint", check_int("checkpoint", self.checkpoint, minimum=0, maximum=1))
        set_("record", check_bool("record", self.record))
        if not isinstance(self.force, ForceModel):
            raise ParameterError(f"force must be a jaxskip.ForceModel (e.g. ForceModel(law='bocquet')), "
                                 f"got {self.force!r}")


#: Longest contact step [s] whose answers this project has validated. Measured over 128 random
#: throws of the human box (speed 3-12 m/s, tilt 5-45 deg, attack 0-30 deg, spin 5-20 rev/s;
#: ``benchmarks/accuracy_dt.py``, session 16) against dt = 0.125 ms: the mean bounce count is 3.56 / 4.05 /
#: 3.66 at dt = 0.25 / 0.5 / 1 ms against 4.30 (single counts are chaotic at any dt), then falls to
#: 2.16 at 2 ms and 0.49 at 5 ms; the median distance error is 0.4 / 1.1 / 2.6 / 5.1 / 43 % and the
#: first contact's duration 0.4 / 0.8 / 1.8 / 5.9 / 21 % at 0.25 / 0.5 / 1 / 2 / 5 ms.
ACCURATE_DT = 1e-3


class AccuracyWarning(UserWarning):
    """A setting is valid but outside the range whose answers have been validated."""


class StabilityWarning(AccuracyWarning):
    """The contact step ``dt`` is longer than the stone's stability estimate (:func:`warn_if_unstable`), or,
    after a throw with the tilt held, the stone gained energy, which only the step can give it there
    (:func:`jaxskip.api.held_energy_rise_message`).

    Its text names the fastest speed of the batch that raised it, so a search or sweep that runs many
    batches would print one per batch: they issue one for the whole run instead (at its fastest throw)
    and silence this category in their batches."""


class DivergedWarning(RuntimeWarning):
    """Some throw ended with outcome ``"diverged"`` (its state stopped being finite or passed
    :data:`DIVERGED_SPEED`): its count, distance and contacts mean nothing. A search or sweep silences
    this category in its batches and issues one for the whole run, with its own count."""


def coarse_dt_message(dt: float) -> str | None:
    """Why a contact step ``dt`` [s] above :data:`ACCURATE_DT` gives unconverged answers (None: it does not).

    >>> coarse_dt_message(2.5e-4) is None, "unconverged" in coarse_dt_message(5e-3)
    (True, True)
    """
    if dt <= ACCURATE_DT:
        return None
    return (f"dt = {dt * 1e3:g} ms resolves a contact (5-30 ms) in a few steps: answers are unconverged "
            f"(over 128 random throws the mean bounce count falls from 4.3 at 0.125 ms to 2.2 at 2 ms and "
            f"0.5 at 5 ms); keep dt <= {ACCURATE_DT * 1e3:g} ms (default 0.25 ms)")


def warn_if_coarse(config: "SimConfig", stacklevel: int = 3) -> None:
    """Issue an :class:`AccuracyWarning` if ``config.dt`` exceeds :data:`ACCURATE_DT`."""
    message = coarse_dt_message(config.dt)
    if message is not None:
        warnings.warn(message, AccuracyWarning, stacklevel=stacklevel)


def inert_velocity_message(config: "SimConfig") -> str | None:
    """Why ``config.force.velocity`` does nothing, or None: with ``attitude="fixed"`` no face turns, so every
    face moves at the centre of mass's velocity and ``"local"`` and ``"passive"`` give the body law's throw
    (to rounding: positions within ~3e-15 m, the same counts)."""
    if config.attitude == "fixed" and config.force.velocity != "body":
        v = config.force.velocity
        return (f"velocity='{v}' has no effect with attitude='fixed': with the tilt held no face turns, so every "
                "face moves at the centre of mass's velocity (the body law's throw)")
    return None


def warn_if_inert(config: "SimConfig", stacklevel: int = 3) -> None:
    """Issue a ``UserWarning`` if ``config``'s velocity option does nothing (:func:`inert_velocity_message`)."""
    message = inert_velocity_message(config)
    if message is not None:
        warnings.warn(message, UserWarning, stacklevel=stacklevel)


def contact_step_bound(stone: RigidStone, water: WaterParams, speed) -> float:
    r"""An estimate of the longest stable contact step [s] of the free stone at ``speed`` [m/s]:
    :math:`\Delta t^* = 1/\omega_\theta`, with :math:`\omega_\theta = V \sqrt{\rho_w C S R / (2 I_{min})}`
    the rate at which the water's lift, ~½ ρ_w C V² S on the wetted face (S: half the mesh's area; C the
    larger of ``c_lift`` and ``c_friction``), acting over the stone's radius R, swings the tilt of a stone
    whose smallest principal moment of inertia is :math:`I_{min}` [kg m²].

    Explicit steps of such a rotation go unstable beyond :math:`\omega \Delta t \approx 1`-2: the stone
    then gains energy in contact. Measured (session 27; semi-implicit Euler, 40 random throws at each
    speed 10-100 m/s, tilt 5-45°, attack 0-20°, spin 0-40 rev/s, for the paper stone at densities
    2650 / 1000 / 300 / 100 kg/m³ and a 5 cm × 0.5 mm disk at 2650 / 500 kg/m³, dt 0.25 / 0.125 /
    0.0625 ms): no throw gained speed where :math:`\Delta t \le \Delta t^*`; the first gains came at
    :math:`\Delta t/\Delta t^*` = 1.09-1.75 for the thin disks and 2.4-4.6 for the paper stone (a
    conservative bound for compact stones). The default paper stone at the default 0.25 ms is within it
    up to 64 m/s. But speed is not the whole story: with semi-implicit Euler the stone gains energy in its
    rotation (a wobble) and changes its outcome well inside the estimate, so :func:`warn_if_unstable` holds
    each integrator to its own fraction of it (:data:`STABLE_FRACTION`: a quarter for Euler, the whole for RK4).

    >>> from jaxskip import paper_stone, rigid_stone, water_params
    >>> stone = rigid_stone(paper_stone(), density=2650.0)
    >>> round(contact_step_bound(stone, water_params(), 8.0) * 1e3, 1)  # ms at 8 m/s
    2.0
    """
    areas = np.asarray(stone.areas, dtype=np.float64)
    inertia = np.linalg.eigvalsh(np.asarray(stone.inertia, dtype=np.float64))[0]
    c = max(float(water.c_lift), float(water.c_friction))
    rho_c_s = float(water.rho_water) * c * 0.5 * areas.sum()  # rho_w C S [kg/m], S half the mesh's area
    rate = float(speed) * math.sqrt(rho_c_s * float(stone.radius) / (2.0 * inertia))
    return math.inf if rate == 0.0 else 1.0 / rate


#: The fraction of :func:`contact_step_bound` within which each integrator's contact step is held
#: (:func:`warn_if_unstable`). Measured (a review and a calibration, stop 48; float64, 0.5 s throws, 20 random
#: throws per cell: tilt 5-45°, attack 0-20°, spin 0-40 rev/s, at 10 / 20 / 40 / 60 m/s, for the paper stone at
#: 2650 / 1000 / 300 kg/m³ and a 5 cm × 0.5 mm disk at 2650 / 500 kg/m³, against the same integrator at an
#: eighth of the estimate): with Euler, the share of throws whose peak energy passed the reference's by 5 % was
#: at its floor (0-5 %, as between an eighth and a sixteenth) at a quarter of the estimate, 9-10 % at a half,
#: 13-22 % at 0.7 and 18-51 % at 1 (thin disks: 35-65 %, a 90th-percentile rise near 50 %); the median distance
#: error 0.4-0.8 / 1.2-1.8 / 1.8-3.5 / 4.5-7.8 % against a 0.15 % floor. One thin disk (500 kg/m³, 40 m/s, tilt
#: 10°, attack 5°, 20 rev/s; estimate 0.062 ms) makes 1 bounce and sinks up to 0.4 of it, 2 at 0.5, and 19 at
#: 0.8, its energy rising 1.58 → 2.32 J (tested). RK4 gained no energy up to the whole estimate (its distances
#: 0.4 / 1 / 1.5-3 % off at 0.25 / 0.5 / 1 of it: truncation, not instability).
STABLE_FRACTION = types.MappingProxyType({"euler": 0.25, "rk4": 1.0})


def warn_if_unstable(config: "SimConfig", stone: RigidStone, water: WaterParams, speed, height,
                     stacklevel: int = 3) -> None:
    r"""Issue a :class:`StabilityWarning` (an :class:`AccuracyWarning`) if the free stone's contact step ``config.dt`` exceeds
    its integrator's :data:`STABLE_FRACTION` (Euler a quarter, RK4 the whole) of :func:`contact_step_bound` at the
    fastest it can meet the water (``speed`` [m/s] and release ``height`` [m], arrays of a batch's throws:
    :math:`\max \sqrt{V^2 + 2 g h}`), unless ``dt`` is above :data:`ACCURATE_DT` and that limit is not below it
    (:func:`warn_if_coarse` then already asks for a step that is stable)."""
    if config.attitude == "fixed":
        return
    fastest = float(np.max(np.sqrt(np.asarray(speed, np.float64) ** 2
                                   + 2.0 * float(water.gravity) * np.maximum(np.asarray(height, np.float64), 0.0))))
    bound = contact_step_bound(stone, water, fastest)
    fraction = STABLE_FRACTION[config.integrator]
    limit = fraction * bound
    # (beyond ACCURATE_DT, warn_if_coarse already asks for dt <= ACCURATE_DT: enough where the limit is above it)
    if config.dt > limit and not (config.dt > ACCURATE_DT and limit >= ACCURATE_DT):
        of = {1.0: "", 0.25: "a quarter of "}.get(fraction, f"{fraction:g} of ")
        rk4_dt = min(bound, ACCURATE_DT)   # (never past the accuracy limit, which warns of its own)
        rk4 = (f" (or integrator='rk4', held to the whole estimate: take dt <= {rk4_dt * 1e3:.3g} ms)"
               if config.integrator == "euler" and config.dt <= rk4_dt else "")
        warnings.warn(f"dt = {config.dt * 1e3:g} ms is longer than {of}this stone's contact-step stability estimate "
                      f"for integrator='{config.integrator}', {limit * 1e3:.3g} ms ({bound * 1e3:.3g} ms at {fastest:.3g} "
                      f"m/s: contact_step_bound of the module jaxskip.simulate, and STABLE_FRACTION): a light, thin or "
                      f"fast stone can then gain energy in contact and change its outcome; take dt <= "
                      f"{limit * 1e3:.3g} ms{rk4}", StabilityWarning, stacklevel=stacklevel)


def steps_for(duration: float, dt: float, multiple: int = 250) -> int:
    """Steps that let a stone spend ``duration`` [s] in the water at ``dt`` [s] and still end by
    ``time_limit``: ``ceil(duration / dt) + 1`` (the outcome is decided at the start of a step, so the
    step after the last one of ``duration`` is the one that ends it), rounded up to a multiple of
    ``multiple``, an integer >= 1 (default 250, so that :func:`jaxskip.simulate_batch` finds a chunk of
    that size). ``duration`` and ``dt`` must be > 0.

    >>> steps_for(5.0, 2.5e-4), steps_for(1.0, 1e-4)
    (20250, 10250)
    """
    check_positive("duration", duration, unit="s")
    check_positive("dt", dt, unit="s")
    check_int("multiple", multiple, minimum=1)
    ratio = duration / dt
    if not ratio < 1e15:   # (an infinite ratio raised a bare OverflowError; SimConfig takes at most 10^7 steps)
        raise ParameterError(f"duration / dt must be a countable number of steps (< 1e15), "
                             f"got {duration:g} s / {dt:g} s = {ratio:.3g}")
    n = math.ceil(ratio - 1e-9) + 1
    return int(multiple * math.ceil(n / multiple))


@document_fields
@jax.tree_util.register_dataclass
@dataclasses.dataclass(frozen=True)
class StoneState:
    """Kinematic state of the stone (world frame: z up, water at rest at z = 0)."""

    position: jax.Array
    """(3,) centre of mass [m]."""
    velocity: jax.Array
    """(3,) centre-of-mass velocity [m/s]."""
    orientation: jax.Array
    """(4,) unit quaternion (w, x, y, z), body to world [-]."""
    angular_velocity: jax.Array
    """(3,) angular velocity in the world frame [rad/s]."""
    time: jax.Array
    """() simulated time [s]."""


# Columns of ``Tracker.counters``.
_ALIVE, _OUTCOME, _PHASE, _BOUNCES, _CONTACTS, _CONTACT_STEPS = range(6)


@document_fields
@jax.tree_util.register_dataclass
@dataclasses.dataclass(frozen=True)
class Tracker:
    """What a rollout observes about contacts, carried through the scan. K = ``max_contacts``.

    Three arrays, so that a step updates three buffers instead of eleven (on the CPU each
    update is a kernel of its own); read them through the properties below. Leading batch
    axes, if any, come first in every array and every property.
    """

    counters: jax.Array
    """(6,) int32: alive (0/1), outcome, phase, bounces, contacts, contact steps (see the
    properties of the same names)."""
    leave: jax.Array
    """(5,) time [s], tilt [rad] and centre of mass (x, y, z) [m] at which the current contact lost
    its last wet triangle (NaN before the first); see ``t_leave``, ``tilt_leave``."""
    log: jax.Array
    """(K, 10) contact log, one row per contact: start time [s], centre of mass at the start
    (x, y, z) [m], tilt at the start [rad], end time [s], tilt at the end [rad], centre of mass at
    the end (x, y, z) [m]; NaN where not reached. Read it through ``t_start``, ``x_start``,
    ``tilt_start``, ``t_end``, ``tilt_end``, ``x_end``."""

    @property
    def alive(self) -> jax.Array:
        """(...) bool: the stone is still in play."""
        return self.counters[..., _ALIVE] > 0

    @property
    def outcome(self) -> jax.Array:
        """(...) int: index into :data:`OUTCOMES` (0 while running)."""
        return self.counters[..., _OUTCOME]

    @property
    def phase(self) -> jax.Array:
        """(...) int: 0 in the air, 1 in the water, 2 just left the water (bounce not yet confirmed)."""
        return self.counters[..., _PHASE]

    @property
    def bounces(self) -> jax.Array:
        """(...) int: contacts that ended with the stone leaving the water."""
        return self.counters[..., _BOUNCES]

    @property
    def contacts(self) -> jax.Array:
        """(...) int: contacts begun."""
        return self.counters[..., _CONTACTS]

    @property
    def contact_steps(self) -> jax.Array:
        """(...) int: steps taken in the water (cost accounting)."""
        return self.counters[..., _CONTACT_STEPS]

    @property
    def t_leave(self) -> jax.Array:
        """(...) time the current contact lost its last wet triangle [s]."""
        return self.leave[..., 0]

    @property
    def tilt_leave(self) -> jax.Array:
        """(...) tilt at ``t_leave`` [rad] (unsigned: the face normal's angle to the vertical, in [0, π])."""
        return self.leave[..., 1]

    @property
    def starts(self) -> jax.Array:
        """(..., K, 5) contact starts: time [s], centre of mass (x, y, z) [m], tilt [rad]."""
        return self.log[..., 0:5]

    @property
    def ends(self) -> jax.Array:
        """(..., K, 2) contact ends: time [s], tilt [rad]."""
        return self.log[..., 5:7]

    @property
    def t_start(self) -> jax.Array:
        """(..., K) contact start times [s] (NaN: not reached)."""
        return self.log[..., 0]

    @property
    def x_start(self) -> jax.Array:
        """(..., K, 3) centre of mass at contact start [m]."""
        return self.log[..., 1:4]

    @property
    def tilt_start(self) -> jax.Array:
        """(..., K) tilt at contact start [rad] (unsigned: the face normal's angle to the vertical, in [0, π])."""
        return self.log[..., 4]

    @property
    def t_end(self) -> jax.Array:
        """(..., K) contact end times [s] (NaN: not ended)."""
        return self.log[..., 5]

    @property
    def tilt_end(self) -> jax.Array:
        """(..., K) tilt at contact end [rad] (unsigned, as ``tilt_start``)."""
        return self.log[..., 6]

    @property
    def x_end(self) -> jax.Array:
        """(..., K, 3) centre of mass at contact end [m] (NaN: not ended)."""
        return self.log[..., 7:10]

    def finish(self) -> "Tracker":
        """The tracker at the end of a rollout: a stone still in play gets outcome ``step_limit``.

        Works on JAX and NumPy arrays alike (any leading batch axes).
        """
        xp = np if isinstance(self.counters, np.ndarray) else jnp
        c = self.counters
        outcome = xp.where(c[..., _ALIVE] > 0, STEP_LIMIT, c[..., _OUTCOME]).astype(c.dtype)
        if xp is np:
            c = c.copy()
            c[..., _OUTCOME] = outcome
        else:
            c = c.at[..., _OUTCOME].set(outcome)
        return dataclasses.replace(self, counters=c)

    def end_at_leave(self) -> "Tracker":
        """The tracker as host NumPy arrays (any leading batch axes), where a run that ended after its last contact's
        stone left the water but before it rose clear of it (a bounce is confirmed there) has that contact's end
        (``t_end``, ``tilt_end``, ``x_end``) where it left, not NaN ("not ended"): what :func:`jaxskip.simulate`
        and :func:`jaxskip.simulate_batch` report."""
        counters, leave, log = (np.asarray(a) for a in (self.counters, self.leave, self.log))
        flat_c = counters.reshape(-1, counters.shape[-1])
        flat_log = log.reshape((-1,) + log.shape[-2:]).copy()
        contacts = flat_c[:, _CONTACTS]
        k = np.minimum(contacts, flat_log.shape[-2])
        rows = np.flatnonzero((k > 0) & (k == contacts) & (flat_c[:, _PHASE] == LEAVING))
        rows = rows[~np.isfinite(flat_log[rows, k[rows] - 1, 5])]
        # (leave: time, tilt, x, y, z, in the log's order of t_end, tilt_end, x_end)
        flat_log[rows, k[rows] - 1, 5:10] = leave.reshape(-1, leave.shape[-1])[rows]
        return Tracker(counters=counters, leave=leave, log=flat_log.reshape(log.shape))


@document_fields
@jax.tree_util.register_dataclass
@dataclasses.dataclass(frozen=True)
class Record:
    """Per-step output of a rollout: one row per scan step, the state at the start of the step (world
    frame). Shapes are one step's; a rollout's records add a leading step axis (T,). Rows of steps taken
    out of play (frozen rows) repeat the final ``time``, ``position``, ``orientation``, ``velocity`` and
    ``angular_velocity``, with ``wetted_area``, ``force`` and ``gap`` set to 0."""

    time: jax.Array
    """() simulated time at the start of the step [s]"""
    position: jax.Array
    """(3,) centre of mass, world frame [m]"""
    orientation: jax.Array
    """(4,) unit quaternion (w, x, y, z), body to world [-]"""
    wetted_area: jax.Array
    """() immersed area [m^2]"""
    force: jax.Array
    """(3,) water force on the stone (total over its triangles, gravity not included), world frame [N]"""
    gap: jax.Array
    """() height of the stone's lowest vertex above the water under it [m] (negative: immersed)"""
    velocity: jax.Array
    """(3,) centre-of-mass velocity [m/s]"""
    angular_velocity: jax.Array
    """(3,) angular velocity, world frame [rad/s]"""


def _gravity(water: WaterParams):
    return jnp.stack([0.0 * water.gravity, 0.0 * water.gravity, -water.gravity])


def _tilt_from_matrix(R):
    """Angle between the face normal (body z) and the vertical [rad], in [0, π]; gradient-safe."""
    h2 = R[0, 2] ** 2 + R[1, 2] ** 2
    pos = h2 > 0.0
    h = jnp.where(pos, jnp.sqrt(jnp.where(pos, h2, 1.0)), 0.0)
    return jnp.arctan2(h, R[2, 2])


def check_duration(duration, dt: float) -> float:
    """``duration`` [s] as a float: finite and at least one step of ``dt`` [s] (a checked float), else a
    :class:`ParameterError`. :class:`SimConfig` and the CLI (which derives ``max_steps`` from it first) share it."""
    # (nan was told "> 0 s", -1 ">= dt": one rule, said alike; a review)
    duration = check_real("duration", duration, valid=f">= dt, the time step ({dt:g} s; --dt in the CLI)")
    if duration < dt:
        raise ParameterError(f"duration must be >= dt, the time step ({dt:g} s; --dt in the CLI), got {duration:g} s "
                             "(the first step would already overrun it)")
    return duration


_HINTS = {SimConfig: "jaxskip.SimConfig", Throw: "jaxskip.Throw",
          RigidStone: "jaxskip.RigidStone (see jaxskip.rigid_stone)",
          WaterParams: "jaxskip.WaterParams (see jaxskip.water_params)"}


def _require(call: str, **named) -> None:
    """Each ``name=(value, cls)`` must be a ``cls`` (static: checked while tracing too), else a
    :class:`ParameterError` naming ``call`` and the argument (arguments in another order met an
    AttributeError deep inside)."""
    for name, (value, cls) in named.items():
        if not isinstance(value, cls):
            raise ParameterError(f"{call}: {name} must be a {_HINTS[cls]}, got {type(value).__name__}")


def _one_throw(name: str, throw: Throw) -> None:
    """``throw`` must be one throw, every field of shape ``()`` (static: checked while tracing too; a batch met a
    raw JAX broadcasting error), else a :class:`ParameterError` naming the function ``name``."""
    shapes = {f.name: tuple(np.shape(getattr(throw, f.name))) for f in dataclasses.fields(throw)}
    if any(shape != () for shape in shapes.values()):
        raise ParameterError(f"{name} takes one throw (every field of shape ()), got shapes {shapes}: jax.vmap it "
                             "over a batch, or use jaxskip.simulate_batch")


def initial_state(throw: Throw, stone: RigidStone) -> StoneState:
    """State at release: lowest point ``throw.height`` above flat water, velocity and spin from the throw.

    ``throw``: one throw (shape ``()``; ``vmap`` for batches), already checked (:meth:`Throw.check`:
    this pure function does not validate its values, so that it can be traced; its arguments' types are).
    ``stone``: the :class:`RigidStone` thrown. Returns a :class:`StoneState`: ``position`` (3,) [m] (the centre
    of mass, above x = y = 0), ``velocity`` (3,) [m/s], ``orientation`` (4,) [-] (unit quaternion w, x, y, z,
    body to world), ``angular_velocity`` (3,) [rad/s] (world frame), ``time`` () [s] (0)."""
    _require("initial_state(throw, stone)", throw=(throw, Throw), stone=(stone, RigidStone))
    _one_throw("initial_state", throw)
    q = attitude(throw.tilt, throw.heading)
    R = quat.to_matrix(q)
    lowest = jnp.min(quat.rotate(R, stone.triangles)[..., 2])
    normal = R[:, 2]
    ca = jnp.cos(throw.attack)
    velocity = throw.speed * jnp.stack(
        [ca * jnp.cos(throw.heading), ca * jnp.sin(throw.heading), -jnp.sin(throw.attack)]
    )
    position = jnp.stack([0.0 * lowest, 0.0 * lowest, throw.height - lowest])
    return StoneState(position, velocity, q, throw.spin * normal, 0.0 * throw.speed)


def initial_carry(config: SimConfig, throw: Throw, stone: RigidStone) -> tuple[StoneState, Tracker]:
    """The carry :func:`make_step`'s step starts from: the throw's release state
    (:func:`initial_state`) and an empty tracker (alive, no contact yet, ``config.max_contacts`` rows).
    Pure; one throw (``vmap`` for batches). Floating leaves are cast to JAX's float type first, as
    :func:`rollout` casts them (the step casts its ``stone`` and ``water`` too)."""
    _require("initial_carry(config, throw, stone)", config=(config, SimConfig), throw=(throw, Throw),
             stone=(stone, RigidStone))
    throw, stone = _one_float_type(throw, stone)
    _one_throw("initial_carry", throw)
    state = initial_state(throw, stone)
    return state, _new_tracker(config.max_contacts, state.position.dtype)


def _new_tracker(k: int, dtype) -> Tracker:
    counters = jnp.zeros(6, jnp.int32).at[_ALIVE].set(1)
    return Tracker(counters=counters, leave=jnp.full(5, jnp.nan, dtype), log=jnp.full((k, 10), jnp.nan, dtype))


def _spin_from_momentum(stone, R, L):
    r"""Angular velocity (3,) [rad/s] from the world angular momentum ``L`` (3,) [kg m^2/s]:
    :math:`\omega = R I^{-1} R^T L` (the inertia is diagonal in the body frame)."""
    return quat.rotate(R, jnp.diagonal(stone.inv_inertia) * quat.rotate_inverse(R, L))


def _momentum_from_spin(stone, R, omega):
    r"""World angular momentum (3,) [kg m^2/s] of the angular velocity ``omega`` (3,) [rad/s]:
    :math:`L = R I R^T \omega`."""
    return quat.rotate(R, jnp.diagonal(stone.inertia) * quat.rotate_inverse(R, omega))


def _dynamics(config: SimConfig, stone: RigidStone, water: WaterParams, surface, per_face: bool = False):
    """Time derivative of (x, v, q, L) and the water force, for the integrators.

    The semi-implicit Euler step uses only the accelerations, so there the quaternion's rate
    (and the angular velocity, unless the force law needs it) is not formed. ``per_face``:
    also return each triangle's force and immersed centroid in the world frame (the coupled
    water's push); otherwise only the sums are formed (:func:`jaxskip.forces.body_water_load`).
    """
    fixed = config.attitude == "fixed"
    need_qdot = config.integrator != "euler" and not fixed
    need_omega = need_qdot or (config.force.velocity != "body" and not fixed)

    def deriv(x, v, q, L, R=None):
        R = quat.to_matrix(q) if R is None else R
        omega = _spin_from_momentum(stone, R, L) if need_omega else jnp.zeros(3) * L
        if per_face:
            parts = body_triangle_forces(config.force, water, stone, x, R, v, omega, surface)
            if config.force.velocity == "passive":  # (its friction acts at the centre of mass)
                F, tau, wet = body_water_load(config.force, water, stone, x, R, v, omega, surface)
            else:
                F, tau, wet = body_total_force(*parts, R)
            # + per-triangle forces and centroids in the world frame (the coupled water's push)
            aux = (F, wet, quat.rotate(R, parts[0]), quat.rotate(R, parts[1]) + x[None, :])
        else:
            F, tau, wet = body_water_load(config.force, water, stone, x, R, v, omega, surface)
            aux = (F, wet, None, None)
        a = F / stone.mass + _gravity(water)
        if fixed:
            return (v, a, jnp.zeros(4) * q, jnp.zeros(3) * L), aux
        if not need_qdot:
            return (v, a, jnp.zeros(4) * q, tau), aux
        qdot = 0.5 * quat.multiply(jnp.concatenate([jnp.zeros(1) * L[:1], omega]), q)
        return (v, a, qdot, tau), aux

    return deriv


FREE_ROTATION_SUBSTEPS = 2
"""Strang substeps of :func:`free_rotation` in a step (a jump through the air included)."""

ASYMMETRY_TOLERANCE = 1e-6
"""A stone whose :math:`|1/I_2 - 1/I_1|` is at most this fraction of :math:`|1/I_3 - 1/I_1|` is
axisymmetric for :func:`rotation_cap` (its free rotation is exact; a meshed disk's is ~1e-15)."""

LONGEST_CAP = 1e3
"""[s] :func:`rotation_cap` applies no cap longer than this: no jump is that long (the longest, a throw
straight up at 100 m/s from 100 m, is ~21 s). Nor does it divide by the rates that would give one: a
stone with next to no spin about its normal (1e-25 rad/s of rounding in a throw released flat without
spin) gave a ~1e25 s cap whose reverse pass multiplied a zero cotangent by 1/rate², which overflows in
float32: NaN gradients for the whole throw."""


@functools.partial(jax.custom_jvp, nondiff_argnums=(4,))
def free_rotation(q, L, stone: RigidStone, h, substeps: int = FREE_ROTATION_SUBSTEPS):
    r"""Torque-free rotation of the stone for a time ``h`` [s]: new quaternion (4,).

    ``L`` (3,) is the (conserved) angular momentum in the world frame [kg m^2/s].
    With principal moments :math:`I_1, I_2, I_3` the kinetic energy splits as

    .. math:: H = \frac{|L|^2}{2I_1} + \frac{L_3^2}{2}\Big(\frac1{I_3}-\frac1{I_1}\Big)
                 + \frac{L_2^2}{2}\Big(\frac1{I_2}-\frac1{I_1}\Big),

    whose first two terms commute and flow exactly (a rotation about
    :math:`L` at rate :math:`|L|/I_1`, and one about the body z axis at rate
    :math:`L_3(1/I_3 - 1/I_1)`): the free symmetric top is solved exactly.
    The asymmetric third term is Strang-split around them, so the error is
    second order in ``h`` times :math:`(1/I_2 - 1/I_1)`. Every sub-flow is a
    rotation, so the world angular momentum is conserved exactly; the energy
    error vanishes for an axisymmetric stone and, for an asymmetric one, stays
    bounded (a symplectic splitting: no drift) only while each substep turns the
    body-frame :math:`L` well under half a turn: near half a turn the splitting
    resonates and the attitude runs off (:func:`rotation_cap`, which the step's
    length keeps to).

    ``substeps`` Strang steps of ``h / substeps`` each. The asymmetric flow, a rotation
    about the body y axis, keeps the body-frame :math:`L_2` it turns at, so the half
    steps that meet between two Strang steps are one step of twice the length (the
    same algebra, fewer operations: ``substeps + 1`` asymmetric flows, not ``2 substeps``).

    Evaluated on scalar components (:func:`_free_rotation_scalar`: a few fused kernels on
    XLA:CPU); differentiated through the same algebra on small vectors
    (:func:`_free_rotation_vector`), whose reverse pass XLA compiles well, while the scalar
    form's reverse pass is pathologically slow there (a 200-step gradient of a throw took
    10.6 s instead of 11 ms).
    """
    return _free_rotation_scalar(q, L, stone, h, substeps)


@free_rotation.defjvp
def _free_rotation_jvp(substeps, primals, tangents):
    _, tangent = jax.jvp(lambda *a: _free_rotation_vector(*a, substeps), primals, tangents)
    return free_rotation(*primals, substeps), tangent


def _strang_lengths(substeps: int):
    """Fractions of ``h`` of the asymmetric flows around the ``substeps`` symmetric ones."""
    return [0.5] + [1.0] * (substeps - 1) + [0.5]


def _free_rotation_vector(q, L, stone: RigidStone, h, substeps: int):
    """:func:`free_rotation` on (3,)/(4,) vectors (for derivatives: the arrays keep the reverse
    pass to a few dozen kernels a step). The turns about body axes are written out: their
    quaternions have two zero entries, and a turn needs only one column of ``R``."""
    inv = jnp.diagonal(stone.inv_inertia)
    c2 = inv[1] - inv[0]
    c3 = inv[2] - inv[0]
    k = h / substeps

    def turn_y(q, angle):
        # q ⊗ (cos, 0, sin, 0)
        w, x, y, z = q[0], q[1], q[2], q[3]
        c, s = jnp.cos(0.5 * angle), jnp.sin(0.5 * angle)
        return c * q + s * jnp.stack([-y, -z, w, x])

    def turn_z(q, angle):
        # q ⊗ (cos, 0, 0, sin)
        w, x, y, z = q[0], q[1], q[2], q[3]
        c, s = jnp.cos(0.5 * angle), jnp.sin(0.5 * angle)
        return c * q + s * jnp.stack([-z, y, -x, w])

    def body_ly(q):
        # (R^T L)_y: the second column of R(q) against L
        w, x, y, z = q[0], q[1], q[2], q[3]
        return jnp.sum(jnp.stack([2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)]) * L)

    def body_lz(q):
        w, x, y, z = q[0], q[1], q[2], q[3]
        return jnp.sum(jnp.stack([2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)]) * L)

    about_l = quat.exp_map(L * (inv[0] * k))
    fracs = _strang_lengths(substeps)
    q = turn_y(q, body_ly(q) * c2 * (fracs[0] * k))
    for frac in fracs[1:]:
        q = quat.multiply(about_l, turn_z(q, body_lz(q) * c3 * k))
        q = turn_y(q, body_ly(q) * c2 * (frac * k))
    return quat.normalize(q)


def _free_rotation_scalar(q, L, stone: RigidStone, h, substeps: int):
    """:func:`free_rotation` on scalar components, for evaluation."""
    # Written on scalar components (no stacks, no reductions over 3- or 4-entry axes), so that
    # XLA:CPU fuses the whole chain into a few kernels instead of ~50 (per-kernel dispatch
    # dominates a step on the CPU). Same algebra as quat.multiply / exp_map / rotate_inverse,
    # with the products by axis rotations written out (half their terms are zero).
    inv = jnp.diagonal(stone.inv_inertia)
    c2 = inv[1] - inv[0]
    c3 = inv[2] - inv[0]
    k = h / substeps
    Lx, Ly, Lz = L[0], L[1], L[2]

    def asym(q, frac):
        # q ⊗ (cos, 0, sin, 0): the turn about body y at rate L_2 (1/I_2 - 1/I_1), L_2 = (R^T L)_y.
        w, x, y, z = q
        ly = 2 * (x * y - w * z) * Lx + (1 - 2 * (x * x + z * z)) * Ly + 2 * (y * z + w * x) * Lz
        half = 0.5 * ly * c2 * (frac * k)
        c, s = jnp.cos(half), jnp.sin(half)
        return (w * c - y * s, x * c - z * s, w * s + y * c, x * s + z * c)

    def sym(q):
        # exp(L k / I_1) ⊗ q ⊗ (cos, 0, 0, sin): about L, and about body z at rate L_3 (1/I_3 - 1/I_1).
        w, x, y, z = q
        lz = 2 * (x * z + w * y) * Lx + 2 * (y * z - w * x) * Ly + (1 - 2 * (x * x + y * y)) * Lz
        half = 0.5 * lz * c3 * k
        c, s = jnp.cos(half), jnp.sin(half)
        return _qmul(about_l, (w * c - z * s, x * c + y * s, y * c - x * s, w * s + z * c))

    about_l = _exp_vec(Lx * inv[0] * k, Ly * inv[0] * k, Lz * inv[0] * k)
    fracs = _strang_lengths(substeps)
    qt = asym((q[0], q[1], q[2], q[3]), fracs[0])
    for frac in fracs[1:]:
        qt = asym(sym(qt), frac)
    n = 1.0 / jnp.sqrt(qt[0] * qt[0] + qt[1] * qt[1] + qt[2] * qt[2] + qt[3] * qt[3])
    return jnp.stack([c * n for c in qt])


def _qmul(p, q):
    """Hamilton product on 4-tuples of scalars (see :func:`jaxskip.quaternion.multiply`)."""
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return (pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw)


def _exp_vec(x, y, z):
    """Quaternion 4-tuple of the rotation vector (x, y, z) [rad]; gradient-safe at zero
    (double ``where``, as :func:`jaxskip.quaternion.exp_map`)."""
    sq = x * x + y * y + z * z
    small = sq < 1e-16
    angle = jnp.sqrt(jnp.where(small, 1.0, sq))
    half = 0.5 * angle
    sinc = jnp.where(small, 0.5 - sq / 48.0, jnp.sin(half) / angle)
    cos = jnp.where(small, 1.0 - sq / 8.0, jnp.cos(half))
    return (cos, sinc * x, sinc * y, sinc * z)


def _integrate(config, stone, water, surface, state: StoneState, R, L, dt, first, dry):
    """Advance the state by ``dt``; ``R`` (3, 3) and ``L`` (3,) are the attitude matrix and
    angular momentum at the start, ``first`` the derivative already evaluated there, ``dry``
    says no point of the stone can touch the water during the step."""
    deriv = _dynamics(config, stone, water, surface)
    x, v, q = state.position, state.velocity, state.orientation
    g = _gravity(water)
    (_, a0, _, tau0), _ = first
    if config.integrator == "euler":
        a_water = a0 - g
        v1 = v + a0 * dt
        x1 = x + v * dt + (a_water + 0.5 * g) * dt * dt
        if config.attitude == "fixed":
            return x1, v1, q, state.angular_velocity
        # Kick the angular momentum with the torque, then rotate freely (Lie-Poisson splitting).
        L1 = L + tau0 * dt
        q1 = free_rotation(q, L1, stone, dt)
    else:
        k1, _ = first
        y = (x, v, q, L)

        def stage(k, h):
            # the stage's attitude is a unit quaternion: an unnormalised q + h q' scales the stone, and in a
            # long flight jump (|omega| h ~ 2 rad) the scaled stone reached into the water
            xs, vs, qs, Ls = (yi + h * ki for yi, ki in zip(y, k))
            return xs, vs, quat.normalize(qs), Ls

        k2, _ = deriv(*stage(k1, 0.5 * dt))
        k3, _ = deriv(*stage(k2, 0.5 * dt))
        k4, _ = deriv(*stage(k3, dt))
        x1, v1, q1, L1 = (
            yi + dt / 6.0 * (a + 2 * b + 2 * c + d) for yi, a, b, c, d in zip(y, k1, k2, k3, k4)
        )
        # In the air only gravity acts: the exact parabola (what RK4 gives when no stage touches the water,
        # and what no stage's error can spoil in a jump of many contact steps).
        x1 = jnp.where(dry, x + v * dt + 0.5 * a0 * dt * dt, x1)
        v1 = jnp.where(dry, v + a0 * dt, v1)
        if config.attitude == "fixed":
            return x1, v1, q, state.angular_velocity
        # In the air the torque is zero and the free flow is exact: use it for long flight steps.
        q1 = jnp.where(dry, free_rotation(q, L, stone, dt), quat.normalize(q1))
        L1 = jnp.where(dry, L, L1)
    omega1 = _spin_from_momentum(stone, quat.to_matrix(q1), L1)
    return x1, v1, q1, omega1


def rotation_cap(stone: RigidStone, R, L):
    r"""Longest step [s] whose free-rotation substeps each turn the body-frame angular momentum by at
    most 90° about the stone's z axis: :math:`h \le n\,\frac{\pi}{2}\,/\,|L_3 (1/I_3 - 1/I_1)|` with
    :math:`n` = :data:`FREE_ROTATION_SUBSTEPS` (``R`` (3, 3) attitude, ``L`` (3,) world angular
    momentum [kg m^2/s]); no cap (``inf``) for an axisymmetric stone, whose free rotation is exact.

    :func:`free_rotation` Strang-splits the asymmetric term around a rotation of the body-frame
    :math:`L` at :math:`\omega_p = L_3 (1/I_3 - 1/I_1)`; like any splitting of a fast rotation it
    resonates when a substep turns :math:`L` by half a turn, :math:`\omega_p h / n \approx \pi`:
    with 20 ms jumps (two 10 ms substeps) the ellipsoid pebble spinning at 50-200 rev/s tipped over
    by 140-165° in 0.6 s of flight that nothing touched (the irregular pebble by 21° at 50 and
    100 rev/s, 158° at 200), where the exact flow wobbles by 0.04°. Within the cap both follow the
    exact flow (0.01-0.04°). The default stone at its 20 rev/s is under the cap (~26 ms > 20 ms).
    A cap beyond :data:`LONGEST_CAP` is not applied (``inf``).
    """
    inv = jnp.diagonal(stone.inv_inertia)
    c2, c3 = inv[1] - inv[0], inv[2] - inv[0]
    rate = jnp.abs(jnp.sum(L * R[:, 2]) * c3)
    turn = FREE_ROTATION_SUBSTEPS * (0.5 * jnp.pi)  # a quarter turn per substep [rad]
    capped = (jnp.abs(c2) > ASYMMETRY_TOLERANCE * jnp.abs(c3)) & (rate > turn / LONGEST_CAP)
    return jnp.where(capped, turn / jnp.where(capped, rate, 1.0), jnp.inf)


def _closing_bound(config, stone, state: StoneState, max_slope: float):
    """``b`` [m/s]: no point of the stone comes down towards the surface faster than ``-b + g t`` (``b`` =
    the vertical speed less the rim's speed |ω| R, less ``max_slope`` times the fastest horizontal
    speed of a point of the stone: the surface under it rises at most that fast)."""
    spin = 0.0 if config.attitude == "fixed" else jnp.sqrt(jnp.sum(state.angular_velocity**2) + 1e-30)
    b = state.velocity[2] - spin * stone.radius
    if max_slope:   # (a static 0 for flat water: its graph unchanged)
        b = b - max_slope * (jnp.sqrt(jnp.sum(state.velocity[:2] ** 2) + 1e-30) + spin * stone.radius)
    return b


def _step_length(config, stone, water, state: StoneState, gap, wet, b, R, L):
    """Conservative-advancement step length [s] and whether the step is certainly dry.

    ``b``: :func:`_closing_bound`. No step, jump or contact step, passes ``config.duration`` (the last is cut
    to end there; the run ends by ``time_limit``). With smooth clipping (``ForceModel(sharpness=κ)``) the water loads the stone from
    ``1/(2κ)`` above the surface, so the jump aims that far above it. With the free attitude a jump is
    also held to :func:`rotation_cap` (``R`` (3, 3) and ``L`` (3,): the attitude and world angular momentum).
    """
    g = water.gravity
    if config.force.sharpness is not None:
        gap = gap - 0.5 / config.force.sharpness
    dry = (gap > 0.0) & (wet <= 0.0)
    arg = jnp.where(dry, b * b + 2.0 * g * gap, 1.0)
    t_star = jnp.where(dry, (b + jnp.sqrt(arg)) / g, 0.0)
    # No step passes ``config.duration``: the last one is cut to end there (exactly: ``t + (duration - t)`` rounds
    # to ``duration`` once t >= duration / 2), so a run ended by ``time_limit`` stops at a time that does not move
    # with the throw (a contact step was taken whole before, to up to one dt past it, and the final state's
    # gradient carried v dT/dθ; a review, stop 48). The floor 0 only matters out of play, where the step is dropped.
    left = jnp.maximum(config.duration - state.time, 0.0)
    if config.flight == "step":
        return jnp.minimum(jnp.asarray(config.dt, state.time.dtype) + 0.0 * gap, left), dry & (t_star >= config.dt)
    # ``dry`` for the integrator: the whole step ends before any contact can begin.
    step = jnp.clip(t_star, config.dt, config.max_flight_step)
    if config.attitude == "free":
        step = jnp.maximum(jnp.minimum(step, rotation_cap(stone, R, L)), config.dt)
    step = jnp.minimum(step, left)
    return step, dry & (t_star >= config.dt)


def _check_max_slope(config: SimConfig, surface, max_slope, ceiling=None):
    """``max_slope`` as a float: 0 for flat water, fixed steps or a surface bounded by a ``ceiling`` when not given;
    required (a :class:`ParameterError`) for another surface when the flight jumps (a jump that assumed flat water
    landed 10 mm inside a swell)."""
    if max_slope is None:
        if surface is flat_surface or config.flight == "step" or ceiling is not None:
            return 0.0
        raise ParameterError("max_slope: with a surface other than flat water, a flight jump must know how fast the "
                             "surface can rise under the moving stone: give max_slope, the steepest slope |grad h| "
                             "of the surface [m/m] where the stone flies (0 for a surface that is flat there), or "
                             "SimConfig(flight='step'), or (make_step) a ceiling, the surface's highest point [m]")
    return check_range("max_slope", max_slope, 0.0, MAX_SLOPE, unit="m/m")


def make_step(config: SimConfig, surface=flat_surface, push: bool = False, max_slope: float | None = None,
              ceiling=None):
    """Return the pure step ``step(carry, stone, water) -> (carry, record)``.

    ``carry = (StoneState, Tracker)``: start it from :func:`initial_carry` (a tracker whose ``alive``
    counter is 0 makes every step a no-op), scan the step with ``jax.lax.scan`` (``record`` is None
    unless ``config.record``), and call ``tracker.finish()`` at the end for the outcome, as
    :func:`rollout` does (which also skips finished segments and checkpoints the steps; a plain scan
    of this step equals it). Inside ``jax.shard_map`` give ``check_vma=False``: the step's branches
    mix device-varying and constant values. ``surface(x, y) -> h`` is the water height
    [m] (flat water by default; the height-field model supplies its own). ``max_slope``: the steepest
    slope |∇h| of ``surface`` [m/m, in [0, 1000]] over where the stone flies; a flight jump lets the
    surface rise that fast under the moving stone. Default 0 for flat water (or ``SimConfig(flight="step")``,
    whose steps are all fine, or with a ``ceiling``); required with another surface.
    ``push=True``: the step returns ``(carry, record, (forces, centroids))`` as well, the
    per-triangle water forces (F, 3) [N] on the stone at the start of the step and their
    immersed centroids (F, 3) [m] (zeros once out of play), for the coupled water.
    ``ceiling``: None (default), or an upper bound [m] (a real scalar, may be traced) of ``surface`` wherever the
    stone can fly during a step: a flight jump then ends before the stone's lowest vertex comes down to it,
    whatever the surface's shape below, and ``max_slope`` may be left out (0) (the coupled water passes the
    highest column the stone can reach, :func:`jaxskip.coupled.reach_ceiling`: a jump that took the ripples under
    the stone as the surface stepped over crests of its own wake, a review found). Only its shape and type are checked when it is a JAX array.
    """
    _require("make_step(config, surface, push)", config=(config, SimConfig))
    if not callable(surface):
        raise ParameterError(f"make_step: surface must be a callable surface(x, y) -> height [m], got "
                             f"{type(surface).__name__}")
    if not isinstance(push, (bool, np.bool_)):
        raise ParameterError(f"make_step: push must be True or False, got {push!r}")
    max_slope = _check_max_slope(config, surface, max_slope, ceiling)
    if isinstance(ceiling, jax.Array):   # (traced, or computed: its shape and type; its values are the caller's)
        if jnp.ndim(ceiling) != 0 or not jnp.issubdtype(ceiling.dtype, jnp.floating):
            raise ParameterError(f"make_step: ceiling must be None or a real scalar [m], got a {ceiling.dtype} array "
                                 f"of shape {jnp.shape(ceiling)}")
    elif ceiling is not None:
        ceiling = check_real("make_step: ceiling", ceiling)

    def live_step(carry, stone: RigidStone, water: WaterParams):
        state, tr = carry
        deriv = _dynamics(config, stone, water, surface, per_face=push)
        R = quat.to_matrix(state.orientation)
        L = _momentum_from_spin(stone, R, state.angular_velocity)
        first = deriv(state.position, state.velocity, state.orientation, L, R)
        F, wet_area, tri_forces, tri_centroids = first[1]
        # Height of every vertex above the water surface under it.
        above = vertex_heights(stone, state.position, R, surface)
        gap = face_min(above)
        top = face_max(above)
        b = _closing_bound(config, stone, state, max_slope)
        # (with a ceiling the jump aims above it: the lowest vertex's height over the ceiling is at most ``gap``)
        if ceiling is None:
            clear = gap
        else:
            lowest = face_min(vertex_heights(stone, state.position, R, flat_surface))   # world z [m]
            clear = jnp.minimum(gap, lowest - ceiling)
        dt, dry = _step_length(config, stone, water, state, clear, wet_area, b, R, L)

        # --- bookkeeping at the state at the start of the step ---
        t = state.time
        tilt = _tilt_from_matrix(R)
        wet = wet_area > 0.0
        k = config.max_contacts
        begin = tr.alive & wet & (tr.phase == AIR)
        leave = tr.alive & ~wet & (tr.phase == WET)
        rewet = tr.alive & wet & (tr.phase == LEAVING)
        # The lowest point is at least gap + b t - g t^2 / 2 above the surface t into the step: a step that
        # passes that bound's peak above the clearance confirms the bounce now (a jump stepped over the top of a
        # hop rising 1.08 mm and merged it into the contact before: checked at step starts alone).
        peak = (b > 0.0) & (b < water.gravity * dt) & (gap + b * b / (2.0 * water.gravity) > config.bounce_clearance)
        # A gap above the clearance at a step's start confirms a bounce from the flight's second dry step on (a
        # one-step dry spell can be a fast-spinning mesh's polygon rim, not a flight). The peak bound is a lower bound
        # of the lowest point's path, so it also confirms on the first dry step: a flight jump from there crossed the
        # whole hop, which was merged into the contact (2026-12-07, a review: the held default throw made 11 / 8 / 2 /
        # 0 bounces at max_flight_step 0.02 / 0.05 / 0.1 / 0.3 s on one trajectory; 11 at fixed steps).
        bounce = tr.alive & ~wet & (((tr.phase == LEAVING) & (gap > config.bounce_clearance))
                                    | ((tr.phase != AIR) & dry & peak))
        idx_new = jnp.minimum(tr.contacts, k - 1)
        log_new = begin & (tr.contacts < k)
        idx_cur = jnp.clip(tr.contacts - 1, 0, k - 1)
        log_end = bounce & (tr.contacts <= k)
        phase = jnp.where(begin | rewet, WET, jnp.where(bounce, AIR, jnp.where(leave, LEAVING, tr.phase)))

        speed = jnp.sqrt(jnp.sum(state.velocity**2) + 1e-30)
        # (a NaN fails every comparison below: without this test a failed integration ran on to the time limit)
        finite = jnp.all(jnp.isfinite(state.position)) & jnp.all(jnp.isfinite(state.angular_velocity))
        diverged = ~(finite & jnp.isfinite(top) & (speed <= DIVERGED_SPEED))
        outcome = jnp.where(
            diverged, DIVERGED,
            jnp.where(top < 0.0, SANK,
            jnp.where(R[2, 2] < 0.0, FLIPPED,
                      jnp.where(wet & (speed < config.stop_speed), STOPPED,
                                jnp.where(t >= config.duration, TIME_LIMIT, RUNNING)))))
        outcome = jnp.where(tr.alive, outcome, tr.outcome)
        alive = tr.alive & (outcome == RUNNING)

        # One kernel-sized update per buffer: a step begins a contact or ends one, never both
        # (``begin`` needs the air phase, ``bounce`` the leaving phase), so one log row is touched.
        counters = jnp.stack([
            alive.astype(jnp.int32), outcome.astype(jnp.int32), phase.astype(jnp.int32),
            tr.bounces + bounce.astype(jnp.int32), tr.contacts + begin.astype(jnp.int32),
            tr.contact_steps + (alive & wet).astype(jnp.int32)])
        row_idx = jnp.where(begin, idx_new, idx_cur)
        row = tr.log[row_idx]
        start_row = jnp.concatenate([t[None], state.position, tilt[None], row[5:]])
        left = jnp.where(leave, jnp.concatenate([t[None], tilt[None], state.position]), tr.leave)
        end_row = jnp.concatenate([row[:5], left])   # (this step's values where it both left and bounced)
        row = jnp.where(log_new, start_row, jnp.where(log_end, end_row, row))
        # The log itself is written in ``step``, outside the branch (see there).
        tr1 = Tracker(counters=counters, leave=left, log=None)

        # --- integrate; a stone out of play keeps its state ---
        x1, v1, q1, w1 = _integrate(config, stone, water, surface, state, R, L, dt, first, dry)
        new = StoneState(x1, v1, q1, w1, t + dt)
        state1 = jax.tree_util.tree_map(lambda a, b: jnp.where(alive, a, b), new, state)
        rec = (Record(t, state.position, state.orientation, wet_area, F, gap, state.velocity, state.angular_velocity)
               if config.record else None)
        pushed = (tri_forces, tri_centroids) if push else None
        return (state1, tr1), (row_idx, row), rec, pushed

    def frozen_step(carry, stone, water):
        state, tr = carry
        rec = _frozen_record(state) if config.record else None
        pushed = None
        if push:
            zero = jnp.zeros_like(stone.normals) * state.time
            pushed = (zero, zero)
        row_idx = jnp.zeros((), jnp.int32)
        return (state, dataclasses.replace(tr, log=None)), (row_idx, tr.log[row_idx]), rec, pushed

    def step(carry, stone: RigidStone, water: WaterParams):
        _require("step(carry, stone, water)", stone=(stone, RigidStone), water=(water, WaterParams))
        stone, water = _one_float_type(stone, water)   # (a float32 stone under x64: the step computes in one type)
        # Out of play: skip the work (a real branch for one throw; under vmap it becomes a select
        # of both branches' outputs). The (K, 10) contact log is not an output of the branch: each
        # branch returns the one row to write, and the row is written here. Under vmap a select
        # of the whole log copied it every step (~200 of ~850 us at 256 lanes in a per-kernel
        # profile; 5-12 % end to end).
        (state1, tr1), (row_idx, row), rec, pushed = jax.lax.cond(
            carry[1].alive, live_step, frozen_step, carry, stone, water)
        tr1 = dataclasses.replace(tr1, log=carry[1].log.at[row_idx].set(row))
        if push:
            return (state1, tr1), rec, pushed
        return (state1, tr1), rec

    return step


def _frozen_record(state: StoneState) -> Record:
    """The record of a step taken out of play: the state repeats, no water force."""
    zero = 0.0 * state.time
    return Record(state.time, state.position, state.orientation, zero, jnp.zeros(3) * zero, zero, state.velocity,
                  state.angular_velocity)


def _record_packing():
    """``(pack, unpack)``: a step's record as one flat row, and the stacked rows back as records.

    The scan then writes one (W,) row per step instead of one small array per record field
    (fewer update kernels per step). ``pack`` learns the record's structure when it is traced.
    """
    layout = {}

    def pack(rec):
        leaves, treedef = jax.tree_util.tree_flatten(rec)
        layout["treedef"], layout["shapes"] = treedef, [jnp.shape(a) for a in leaves]
        return jnp.concatenate([jnp.ravel(a) for a in leaves])

    def unpack(rows):
        lead, out, i = rows.shape[:-1], [], 0
        for shape in layout["shapes"]:
            size = math.prod(shape)
            out.append(rows[..., i:i + size].reshape(lead + shape))
            i += size
        return jax.tree_util.tree_unflatten(layout["treedef"], out)

    return pack, unpack


def _scan(config: SimConfig, step, carry, stone, water):
    """Run ``config.max_steps`` steps in segments of ``config.segment``; skip dead segments.

    A segment that starts with the stone out of play is replaced by its frozen
    records (``lax.cond``: a real branch for one throw, both branches and a
    select under ``vmap``), so neither pass pays for steps after the end.
    """
    pack, unpack = _record_packing()

    def body(c, _):
        c, rec = step(c, stone, water)
        return c, (pack(rec) if config.record else None)

    if config.checkpoint:
        body = jax.checkpoint(body)

    def segment(n):
        def live(c):
            return jax.lax.scan(body, c, None, length=n)

        def dead(c):
            if not config.record:
                return c, None
            row = pack(_frozen_record(c[0]))
            return c, jnp.broadcast_to(row, (n,) + row.shape)

        run = lambda c, _: jax.lax.cond(c[1].alive, live, dead, c)
        return jax.checkpoint(run) if config.checkpoint else run

    k = min(config.segment, config.max_steps)
    full, rest = divmod(config.max_steps, k)
    carry, recs = jax.lax.scan(segment(k), carry, None, length=full)
    if config.record:
        recs = recs.reshape((-1,) + recs.shape[2:])
    if rest:
        carry, tail = segment(rest)(carry, None)
        if config.record:
            recs = jnp.concatenate([recs, tail])
    return carry, (unpack(recs) if config.record else None)


def _check_rollout_args(config, throw, stone, water, name: str = "rollout",
                        signature: str = "(config, throw, stone, water)") -> None:
    """Types, and one throw (not a batch), checked while tracing (values cannot be): arguments in another
    order or a batch met an AttributeError or a broadcasting error deep inside the step. ``name`` and
    ``signature``: the function the messages name."""
    _require(name + signature, config=(config, SimConfig), throw=(throw, Throw),
             stone=(stone, RigidStone), water=(water, WaterParams))
    _one_throw(name, throw)
    # a batched stone or water (a forgotten in_axes) met a broadcasting error deep inside the step
    water_shapes = {f.name: tuple(np.shape(getattr(water, f.name))) for f in dataclasses.fields(water)}
    if any(shape != () for shape in water_shapes.values()):
        raise ParameterError(f"{name} takes one water (every WaterParams field of shape ()), got shapes "
                             f"{water_shapes}: jax.vmap over a batch of them")
    tri = tuple(np.shape(stone.triangles))
    if len(tri) != 3 or tri[1:] != (3, 3) or np.shape(stone.mass) != ():
        raise ParameterError(f"{name} takes one stone (triangles (F, 3, 3), mass ()), got triangles {tri} and mass "
                             f"{tuple(np.shape(stone.mass))}: jax.vmap over a batch of stones")


def _one_float_type(*trees):
    """``trees`` with every floating leaf in JAX's float type (float32, or float64 under
    ``jax_enable_x64``), the type the step's own constants take: a float32 throw made before x64 was switched
    on met a raw ``lax.cond`` "branches must have equal output types" error while tracing. A no-op for
    leaves of that type already."""
    dtype = jax.dtypes.canonicalize_dtype(np.float64)
    cast = lambda a: (a.astype(dtype) if hasattr(a, "dtype") and jnp.issubdtype(a.dtype, jnp.floating)  # noqa: E731
                      and a.dtype != dtype else a)
    return tuple(jax.tree_util.tree_map(cast, t) for t in trees)


def rollout(config: SimConfig, throw: Throw, stone: RigidStone, water: WaterParams, surface=flat_surface,
            max_slope: float | None = None):
    """Simulate one throw for ``config.max_steps`` steps: pure, jit/vmap/grad-able.

    Returns ``(state, tracker, records)``: the final :class:`StoneState`, the
    :class:`Tracker` and, if ``config.record``, a :class:`Record` with a leading
    axis of ``max_steps`` (else ``None``). A stone still in play when the steps
    run out gets outcome ``step_limit``. Its final state is then taken after a number of steps, not at a
    time, so its gradients also carry the step schedule (the flight jumps' lengths, which depend on
    ``stone.radius`` and the state): differentiate a state at a fixed time through a run that ends by
    ``config.duration`` or by the stone leaving play. A run that ends by leaving play (sank, stopped, flipped)
    stops at the first step whose start finds the stone out; that step's index does not move with the throw,
    so the final state's gradient is the state's at a fixed step and lacks the end time's own dependence on
    the throw, v dT/dθ (measured, a review of 2026-12-07: the default throw with
    the tilt held sinks at 1.503 s, and d x_final / d tilt is -13.1 m/rad by reverse mode against -15.5 m/rad
    for a line fitted through 201 throws over ±1e-4 rad, across which the sinking moves by 1 ms; d / d speed
    1.375 against 1.369). The distance objective (``optimize.make_objective("distance")``) inherits this.

    Floating leaves of ``throw``, ``stone`` and ``water`` are cast to JAX's float type (float32, or float64
    under ``jax_enable_x64``), in which the step computes.

    ``throw`` is one throw (every field of shape ``()``; ``jax.vmap`` over a batch). Its values are
    checked (:meth:`Throw.check`: a NaN speed or a tilt beyond ±90° is a :class:`ParameterError`) when
    they are concrete, here and in :data:`rollout_jit`; traced values (under ``jit``, ``vmap`` or
    ``grad``) cannot be, so check them before tracing, as :func:`jaxskip.simulate` and
    :func:`jaxskip.simulate_batch` do. A concrete ``stone`` and ``water`` are checked likewise
    (:meth:`RigidStone.check`, :meth:`WaterParams.check`). Build ``water`` with :func:`jaxskip.water_params`.

    ``surface``: the water surface, a pure, JAX-traceable callable ``surface(x, y) -> h`` giving the
    height [m] above the rest level z = 0 at world coordinates ``x, y`` [m] (arrays of any shape; ``h``
    of the same shape), fixed in time. Default :func:`jaxskip.forces.flat_surface` (flat water, the
    fast path). The release state is still placed ``throw.height`` above z = 0, not above ``surface``.
    It is passed to :func:`make_step`, with ``max_slope`` (required with a surface other than flat water
    unless ``config.flight == "step"``: the steepest slope of ``surface`` [m/m] where the stone flies); for
    :data:`rollout_jit` both are static arguments, so they must be hashable (a function is, by identity:
    each new function or lambda compiles anew).

    >>> import jax
    >>> from jaxskip import SimConfig, Throw, paper_stone, rigid_stone, water_params
    >>> stone, water = rigid_stone(paper_stone(), density=2650.0), water_params()
    >>> config = SimConfig(record=False)
    >>> state, tracker, _ = jax.jit(lambda t: rollout(config, t, stone, water))(Throw.from_degrees())
    >>> int(tracker.bounces) > 5, OUTCOMES[int(tracker.outcome)]
    (True, 'sank')
    """
    _check_rollout_args(config, throw, stone, water)
    _check_concrete(throw, stone, water)
    throw, stone, water = _one_float_type(throw, stone, water)
    step = make_step(config, surface, max_slope=max_slope)
    (state, tr), recs = _scan(config, step, initial_carry(config, throw, stone), stone, water)
    return state, tr.finish(), (recs if config.record else None)


def _check_concrete(throw, stone=None, water=None) -> None:
    """:meth:`Throw.check` when no field of ``throw`` is traced (a NaN throw came back "diverged", a tilt of
    3 rad "flipped", in silence); a traced throw passes unchecked. Likewise :meth:`RigidStone.check` and
    :meth:`WaterParams.check` of a concrete ``stone`` and ``water`` (a stone given a negative mass with
    ``dataclasses.replace`` "sank", a negative ``c_lift`` ran on, in silence)."""
    for tree in (throw, stone, water):
        if isinstance(tree, (Throw, RigidStone, WaterParams)) and not any(
                isinstance(getattr(tree, f.name), jax.core.Tracer) for f in dataclasses.fields(tree)):
            tree.check()


_rollout_compiled = jax.jit(rollout, static_argnames=("config", "surface", "max_slope"))


def rollout_jit(config: SimConfig, throw: Throw, stone: RigidStone, water: WaterParams, surface=flat_surface,
                max_slope: float | None = None):
    _check_rollout_args(config, throw, stone, water, name="rollout_jit")
    _check_concrete(throw, stone, water)   # (inside the jitted function the values are traced)
    max_slope = _check_max_slope(config, surface, max_slope)   # (checked before tracing; a float, hashable)
    return _rollout_compiled(config, throw, stone, water, surface=surface, max_slope=max_slope)


rollout_jit.lower = _rollout_compiled.lower
rollout_jit.__doc__ = """:func:`rollout` compiled once per (config, surface); new throws, stones
of the same size and water constants reuse it (leaves of the same dtype: a Python float or a weakly typed
scalar compiles apart, see :class:`Throw`). Arguments and returns as :func:`rollout`; ``config`` and
``surface`` are static (hashable: a :class:`SimConfig`, and a callable ``surface(x, y) -> height`` [m],
default flat water, hashed by identity; ``max_slope`` a number).

>>> from jaxskip import SimConfig, Throw, paper_stone, rigid_stone, water_params
>>> stone, water = rigid_stone(paper_stone(), density=2650.0), water_params()
>>> state, tracker, _ = rollout_jit(SimConfig(record=False), Throw.from_degrees(), stone, water)
>>> int(tracker.bounces) > 5
True
"""
