"""Many throws to completion on a fixed pool of lanes (host driver; forward only).

``jax.vmap(rollout)`` runs every throw of a batch for ``max_steps`` steps, and
under ``vmap`` a finished throw still pays for each step (the skip becomes a
select): in a tilt x attack grid only about one throw-step in eight is live.
:func:`simulate_batch` keeps a fixed number of *lanes* busy instead. The
compiled, vmapped step advances every lane ``chunk`` steps; after each chunk the
host collects the throws that went out of play and refills their lanes with
the next throws. Each throw still runs exactly the steps it would run alone
(its lane is started fresh at a chunk boundary and stopped after
``max_steps``), so the results equal ``vmap(rollout)``'s (to rounding: in
float32 a long throw's chaotic count may differ between differently compiled
programs; in float64 they agree, tested); only the idle work is gone. One compile per ``(config, lanes, chunk)``, memoised.

For gradients use :func:`jaxskip.rollout` under ``jax.vmap``: this
driver is a host loop.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import sys
import time
import warnings

import jax
import jax.numpy as jnp
import numpy as np

from ._docs import document_fields
from ._progress import ProgressLine
from ._checks import ParameterError, check_bool, check_int
from .api import HELD_ENERGY_RISE, checked_config, checked_water, held_step_advice, resolve_stone, settings_dict
from .forces import WaterParams, water_params
from .simulate import (DIVERGED, OUTCOMES, DivergedWarning, SimConfig, StabilityWarning, StoneState, Tracker,
                       _new_tracker, _scan, diverged_message, initial_state, make_step, warn_if_unstable)
from .throw import Throw


@document_fields
@dataclasses.dataclass(frozen=True)
class BatchResult:
    """Outcomes of ``N`` throws (host NumPy arrays, SI units)."""

    bounces: np.ndarray
    """(N,) int: contacts that ended with the stone leaving the water."""
    n_contacts: np.ndarray
    """(N,) int: contacts begun."""
    outcome: np.ndarray
    """(N,) int: index into :data:`jaxskip.OUTCOMES` (see :attr:`outcome_names`)."""
    distance: np.ndarray
    """(N,) horizontal distance from release to where the stone ended [m]."""
    final_time: np.ndarray
    """(N,) simulated time at the end [s]."""
    state: StoneState
    """Final states, every field with a leading axis N."""
    tracker: Tracker
    """Final trackers (contact logs ``t_start``/``t_end`` (N, K) [s], ...), leading axis N."""
    throws: Throw
    """The throws as simulated, shape (N,), in SI units (m/s, rad, rad/s, m): host NumPy arrays in JAX's float type
    (float32, or float64 under ``jax_enable_x64``), whatever types they were given in."""
    config: SimConfig
    """The :class:`jaxskip.SimConfig` every throw ran with (checked; ``record`` ignored)."""
    stone_name: str
    """The stone: the built-in name as given, a mesh's ``name``, an ``.obj`` file's stem, or ``"custom"`` for a ready
    :class:`jaxskip.RigidStone`."""
    mass: float
    """The stone's mass [kg]."""
    water: WaterParams
    """The water's coefficients and constants the throws ran with."""
    lanes: int
    """Lanes in the pool (throws advanced together)."""
    chunk: int
    """Steps between refills."""
    lane_steps: int
    """Steps computed over all lanes, idle lanes included (the cost)."""
    wall_time: float
    """Wall-clock time, compile included [s]."""

    def to_dict(self) -> dict:
        """JSON-ready per-throw lists (one entry per throw): ``bounces``, ``n_contacts``, ``outcome`` (names),
        ``distance`` [m] and ``final_time`` [s] (None where not finite), the throws in user units (``speed``
        [m/s], ``tilt_deg``, ``attack_deg``, ``heading_deg`` [deg], ``spin_rev_s`` [rev/s], ``height`` [m]),
        ``parameters``, every other setting that can change a result (:func:`jaxskip.api.settings_dict`: the stone,
        its mass [kg], the force model, the water and the :class:`SimConfig`), and ``lanes``, ``chunk``,
        ``lane_steps`` and ``wall_time`` [s].

        >>> import json, numpy as np
        >>> from jaxskip import Throw
        >>> d = simulate_batch(Throw.from_degrees(speed=np.array([6.0, 8.0]))).to_dict()
        >>> sorted(d["throws"]), len(json.dumps(d)) > 0
        (['attack_deg', 'heading_deg', 'height', 'speed', 'spin_rev_s', 'tilt_deg'], True)
        """
        def numbers(a):
            return [float(x) if np.isfinite(x) else None for x in np.asarray(a, dtype=np.float64).ravel()]

        t = self.throws
        throws = {"speed": numbers(t.speed), "tilt_deg": numbers(np.degrees(t.tilt)),
                  "attack_deg": numbers(np.degrees(t.attack)), "spin_rev_s": numbers(np.asarray(t.spin) / (2 * np.pi)),
                  "height": numbers(t.height), "heading_deg": numbers(np.degrees(t.heading))}
        return {"bounces": np.asarray(self.bounces).tolist(), "n_contacts": np.asarray(self.n_contacts).tolist(),
                "outcome": self.outcome_names.tolist(), "distance": numbers(self.distance),
                "final_time": numbers(self.final_time), "throws": throws,
                "parameters": settings_dict(self.stone_name, self.mass, self.water, self.config),
                "lanes": int(self.lanes), "chunk": int(self.chunk), "lane_steps": int(self.lane_steps),
                "wall_time": float(self.wall_time)}

    def __repr__(self) -> str:
        # (the dataclass's own repr printed every state, tracker and throw array: tens of k characters)
        b = np.asarray(self.bounces)
        names, counts = np.unique(self.outcome_names, return_counts=True)
        told = ", ".join(f"{c} {n}" for n, c in zip(names.tolist(), counts.tolist()))
        spread = f"bounces {b.min()}-{b.max()} (median {np.median(b):g})" if b.size else "no throws"
        return f"BatchResult({b.size} throws: {spread}; {told}; {self.lanes} lanes, {self.wall_time:.2f} s)"

    @property
    def outcome_names(self) -> np.ndarray:
        """(N,) outcome strings (``sank``, ``stopped``, ``flipped``, ``time_limit``, ``step_limit``,
        ``diverged``: see :data:`jaxskip.simulate.OUTCOMES`)."""
        return np.asarray(OUTCOMES, dtype=object)[self.outcome]


def _pool(config: SimConfig, lanes: int, chunk: int):
    """Compiled (advance, start, refill) for one pool shape, keyed on what the programs depend on: not on
    ``record`` (off here), ``checkpoint`` (none in a chunk), ``max_steps`` or ``segment`` (a chunk is one
    segment), so that configurations differing only there share the programs."""
    return _pool_programs(dataclasses.replace(config, record=False, max_steps=chunk, segment=chunk, checkpoint=0),
                          lanes)


@functools.lru_cache(maxsize=16)
def _pool_programs(config: SimConfig, lanes: int):
    """Compiled (advance, start, refill) for ``lanes`` lanes advancing ``config.max_steps`` steps (a chunk)
    a call (memoised: no recompiles; built through :func:`_pool`)."""
    step = make_step(config)

    def advance(carry, stone, water):
        return jax.vmap(lambda c: _scan(config, step, c, stone, water)[0])(carry)

    def start(throws, stone):
        state = jax.vmap(lambda t: initial_state(t, stone))(throws)
        tr = _new_tracker(config.max_contacts, state.position.dtype)
        return state, jax.tree_util.tree_map(lambda a: jnp.broadcast_to(a, (lanes,) + a.shape), tr)

    def refill(carry, throws, fresh, stone):
        new = start(throws, stone)
        def pick(n, o):
            return jnp.where(fresh.reshape((lanes,) + (1,) * (n.ndim - 1)), n, o)

        return jax.tree_util.tree_map(pick, new, carry)

    # start's lanes come out already split over the devices: a device_put of its single-device output
    # would compile a slicing program per leaf shape (7 compiles, ~1 s on a first call)
    return jax.jit(advance), jax.jit(start, out_shardings=_lane_sharding()), jax.jit(refill)


MIN_LANES_PER_DEVICE = 8
"""Fewest lanes a device advances. XLA:CPU compiles a batch of 1-4 lanes per device differently from a
wider one, and the results differ at rounding level, which a long, chaotic throw's count amplifies:
on the development machine (float64, 256 random throws near the box's best corner) 1 / 2-4 lanes a
device gave other bits than 5-256 lanes, which all agreed to the bit, and 68-74 of the 256 counts
changed. A pool of at least 8 lanes a device (idle lanes ride along) makes a throw's numbers
independent of the batch it is in, of ``lanes``, of a sweep's chunk size and of the device count."""


@jax.jit
def _select_lanes(mask, new, old):
    """``new`` on the lanes where ``mask`` (lanes,) is true, ``old`` elsewhere (every leaf has the lane axis first)."""
    return jax.tree_util.tree_map(lambda n, o: jnp.where(mask.reshape(mask.shape + (1,) * (n.ndim - 1)), n, o),
                                  new, old)


def _lane_sharding():
    """Shard the lane axis over every local device (``None`` with one device)."""
    devices = jax.local_devices()
    if len(devices) == 1:
        return None
    mesh = jax.sharding.Mesh(np.array(devices), ("lanes",))
    return jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec("lanes"))


def _take(tree, index):
    return jax.tree_util.tree_map(lambda a: np.asarray(a)[index], tree)


def simulate_batch(
    throws: Throw,
    stone="paper",
    *,
    mass: float | None = None,
    density: float | None = None,
    water: WaterParams | None = None,
    config: SimConfig | None = None,
    lanes: int | None = None,
    chunk: int | None = None,
    progress: bool = False,
) -> BatchResult:
    """Simulate every throw of a batch to completion on a pool of ``lanes`` lanes.

    Parameters
    ----------
    throws : a :class:`Throw` with one batch axis, shape (N,) (e.g. ``Throw.from_degrees`` of arrays).
    stone, mass, density : as in :func:`jaxskip.simulate` (built-in name, ``.obj`` path, mesh or
        :class:`RigidStone`; mass [kg] or density [kg/m^3], the density in [100, 25000] kg/m^3).
    water : :class:`WaterParams`; default ``water_params(config.force.law)``.
    config : :class:`SimConfig` (its ``record`` is ignored: no trajectories are kept; a ``dt`` above 1 ms
        is valid but unconverged: an :class:`jaxskip.AccuracyWarning` says so).
    lanes : throws advanced together (the vmapped batch), an integer in [1, 10^6]; at most N, then raised to at
        least :data:`MIN_LANES_PER_DEVICE` per device and rounded up to a multiple of the device count (idle lanes
        ride along), so that a throw's numbers do not depend on N, on ``lanes`` or on the device count. Default
        (``None``): :func:`default_lanes` of N and the device count — about N/32 lanes per
        device, a power of two in [8, 128]. With several local JAX devices (``import jaxskip``
        makes one CPU device per core) the lanes are sharded over all of them
        (``jax.sharding``; a given count is rounded up to a multiple of the device count).
    chunk : steps between refills, an integer in [1, ``config.max_steps``] (default :func:`chunk_for`: the divisor of
        ``max_steps`` nearest 250 by ratio, or ``min(250, max_steps)`` where none lies within a factor 4 of it).
        Smaller wastes less on finished throws, larger costs fewer host round trips. Where it does not divide ``max_steps``, a throw still
        in play after its last whole chunk runs the remaining steps in a second program (compiled when first
        needed), so every throw runs exactly the steps it would run alone.
    progress : print a progress line to stderr.

    Examples
    --------
    >>> import numpy as np
    >>> from jaxskip import Throw
    >>> from jaxskip.batch import simulate_batch
    >>> throws = Throw.from_degrees(speed=np.array([4.0, 7.0]), tilt=20.0, attack=10.0, spin=20.0)
    >>> r = simulate_batch(throws, lanes=2)
    >>> r.bounces.shape, bool(r.bounces[1] >= r.bounces[0])
    ((2,), True)
    """
    t0 = time.perf_counter()
    if not isinstance(throws, Throw):
        raise ParameterError(f"throws must be a jaxskip.Throw, got {type(throws).__name__}")
    throws.check()
    if len(throws.shape) != 1 or throws.shape[0] < 1:
        raise ParameterError(f"throws must have exactly one batch axis with at least one throw; got shape {throws.shape}")
    config = checked_config(config)
    progress = check_bool("progress", progress)
    sharding = _lane_sharding()
    n_devices = 1 if sharding is None else len(sharding.mesh.devices.flat)
    lanes = default_lanes(throws.shape[0], n_devices) if lanes is None else check_int(
        "lanes", lanes, minimum=1, maximum=1_000_000)
    chunk = chunk_for(config.max_steps) if chunk is None else chunk
    chunk = check_int("chunk", chunk, minimum=1, maximum=config.max_steps)
    water = water_params(config.force.law) if water is None else checked_water(water)
    rigid, stone_name = resolve_stone(stone, mass=mass, density=density)
    warn_if_unstable(config, rigid, water, throws.speed, throws.height, stacklevel=3)

    n = throws.shape[0]
    lanes = max(min(lanes, n), MIN_LANES_PER_DEVICE * n_devices)
    lanes = -(-lanes // n_devices) * n_devices
    misses = _pool_programs.cache_info().misses
    advance, start, refill = _pool(config, lanes, chunk)
    if progress and _pool_programs.cache_info().misses > misses:
        print(f"  compiling the pool's program ({lanes} lanes, {chunk} steps a chunk; once per configuration, a few "
              "seconds)...", file=sys.stderr, flush=True)
    result_water = water   # (as checked: the result's; the copy placed on the devices below is the pool's)
    if sharding is not None:
        # The stone and the water, placed once on every device: passed as they are, each of the ~120 calls a
        # grid makes would copy their leaves to the devices again (a host-side cost that stalls the devices).
        rigid, water = jax.device_put((rigid, water), jax.sharding.NamedSharding(sharding.mesh,
                                                                                 jax.sharding.PartitionSpec()))
    # in JAX's float type: a float16 or integer throw would compile the pool apart (or fail in it)
    host_throws = jax.tree_util.tree_map(lambda a: np.asarray(a, dtype=jax.dtypes.canonicalize_dtype(np.float64)),
                                         throws)
    # A throw runs ``chunks_max`` whole chunks, then (where ``chunk`` does not divide ``max_steps``) the ``rest`` in the
    # tail program, on every lane at once but kept only on the lanes that are due: a throw ending by the step limit
    # is rare, and a prime max_steps otherwise forced a chunk of 1 (a host round trip a step: 22x slower) or of
    # max_steps (every lane idling to the longest throw's end: 3.5x; a review, stop 46).
    chunks_max, rest = divmod(config.max_steps, chunk)

    lane_throw = np.where(np.arange(lanes) < n, np.arange(lanes), -1)  # throw index of each lane (-1: idle)
    lane_chunks = np.zeros(lanes, int)      # chunks run by the lane's current throw
    carry = start(_take(host_throws, np.maximum(lane_throw, 0)), rigid)
    next_throw, finished, lane_steps = min(lanes, n), 0, 0
    final_state = final_tracker = None
    line = ProgressLine()
    while finished < n:
        carry = advance(carry, rigid, water)
        lane_steps += lanes * chunk
        lane_chunks += 1
        state, tr = jax.device_get(carry)
        busy = lane_throw >= 0
        due = busy & np.asarray(tr.alive) & (lane_chunks >= chunks_max)
        if rest and due.any():
            misses = _pool_programs.cache_info().misses
            tail = _pool(config, lanes, rest)[0]
            if progress and _pool_programs.cache_info().misses > misses:
                line.close()
                print(f"  compiling the pool's last, {rest}-step chunk (max_steps {config.max_steps} is not a multiple "
                      f"of the chunk, {chunk})...", file=sys.stderr, flush=True)
            carry = _select_lanes(due, tail(carry, rigid, water), carry)
            lane_steps += lanes * rest
            state, tr = jax.device_get(carry)
        done = busy & (~np.asarray(tr.alive) | (lane_chunks >= chunks_max))
        if done.any():
            if final_state is None:  # allocate the outputs like the first lane's values
                final_state = jax.tree_util.tree_map(lambda a: np.zeros((n,) + a.shape[1:], a.dtype), state)
                final_tracker = jax.tree_util.tree_map(lambda a: np.zeros((n,) + a.shape[1:], a.dtype), tr)
            idx = lane_throw[done]
            for out, src in ((final_state, state), (final_tracker, tr)):
                for o, s in zip(jax.tree_util.tree_leaves(out), jax.tree_util.tree_leaves(src)):
                    o[idx] = s[done]
            finished += int(done.sum())
            # Refill the finished lanes with the next throws; lanes left without work go idle.
            new = np.full(lanes, -1)
            k = min(int(done.sum()), n - next_throw)
            slots = np.flatnonzero(done)
            new[slots[:k]] = np.arange(next_throw, next_throw + k)
            next_throw += k
            lane_throw = np.where(done, new, lane_throw)
            lane_chunks = np.where(done, 0, lane_chunks)
            if k:
                fresh = np.zeros(lanes, bool)
                fresh[slots[:k]] = True
                carry = refill(carry, _take(host_throws, np.maximum(np.where(fresh, new, 0), 0)), fresh, rigid)
        if progress:
            line.update(f"  {finished}/{n} throws done ({lane_steps} lane-steps, {time.perf_counter() - t0:.0f} s)")
    if progress:
        line.close()

    final_tracker = final_tracker.finish().end_at_leave()
    outcome = final_tracker.outcome
    failed = np.flatnonzero(outcome == DIVERGED)
    if failed.size:
        warnings.warn(diverged_message(f"{failed.size} of {n} throws diverged (indices {failed[:5].tolist()}"
                                       + (", ..." if failed.size > 5 else "") + ")", config), DivergedWarning,
                      stacklevel=2)
    if config.attitude == "fixed":
        _warn_if_held_energy_rose(config, rigid, water, host_throws, final_state, outcome)
    # Horizontal distance from release: ``initial_state`` releases every throw above x = y = 0.
    distance = np.hypot(final_state.position[:, 0], final_state.position[:, 1])
    return BatchResult(
        bounces=final_tracker.bounces.astype(int), n_contacts=final_tracker.contacts.astype(int), outcome=outcome,
        distance=distance, final_time=np.asarray(final_state.time), state=final_state, tracker=final_tracker,
        throws=host_throws, config=config, stone_name=stone_name, mass=float(rigid.mass), water=result_water,
        lanes=lanes, chunk=chunk, lane_steps=lane_steps, wall_time=time.perf_counter() - t0,
    )


def _warn_if_held_energy_rose(config, rigid, water, throws: Throw, final: StoneState, outcome) -> None:
    """A :class:`jaxskip.StabilityWarning` naming the throws whose mechanical energy at the end exceeds their
    release energy by more than :data:`jaxskip.api.HELD_ENERGY_RISE` of it: with the tilt held only the step can
    add energy (:func:`jaxskip.simulate` checks every step of its one throw; here the end alone is seen). Host
    arithmetic: the attitude and spin are the release's all along, so the spin energy cancels and the release
    height of the centre of mass is ``height`` less the lowest vertex's offset in the final attitude."""
    m, g = float(rigid.mass), float(water.gravity)
    spin = 0.5 * float(np.asarray(rigid.inertia)[2, 2]) * np.asarray(throws.spin, dtype=np.float64) ** 2
    w, x, y, z = np.moveaxis(np.asarray(final.orientation, dtype=np.float64), -1, 0)
    row = np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1)   # R's z row
    lowest = np.min(np.asarray(rigid.triangles, dtype=np.float64).reshape(-1, 3) @ row.T, axis=0)
    e0 = (0.5 * m * np.asarray(throws.speed, dtype=np.float64) ** 2
          + m * g * (np.asarray(throws.height, dtype=np.float64) - lowest) + spin)
    v = np.asarray(final.velocity, dtype=np.float64)
    e1 = 0.5 * m * np.sum(v * v, axis=-1) + m * g * np.asarray(final.position, dtype=np.float64)[:, 2] + spin
    bad = np.flatnonzero((e1 - e0 > HELD_ENERGY_RISE * np.abs(e0)) & (outcome != DIVERGED))
    if bad.size:
        rise = 100 * float(np.max((e1 - e0)[bad] / np.abs(e0[bad])))
        warnings.warn(f"{bad.size} of {len(e0)} throws held at their tilt ended with more mechanical energy than "
                      f"at release, by over {100 * HELD_ENERGY_RISE:g} % (up to {rise:.3g} %; indices "
                      f"{bad[:5].tolist()}{', ...' if bad.size > 5 else ''}): with the tilt held the water cannot add "
                      "energy, so " + held_step_advice(config.dt, many=True), StabilityWarning, stacklevel=3)


def default_lanes(n: int, devices: int = 1) -> int:
    """Lanes for a batch of ``n`` throws on ``devices`` devices: per device, the power of two
    nearest below ``n / 32``, within [8, 128].

    A lane whose throw has finished idles (and still costs) once no throws are left to refill
    it, so a pool as wide as a small batch pays for the longest throw in every lane; a wider
    pool costs less per lane-step. Measured, n / 32 lanes on each device balance the two (32 throws
    a lane on one device, 16 on two: each device advances its own share of the lanes at the same
    time), 8 lanes amortise the per-step dispatch, and beyond 128 a step on this kind of CPU is
    arithmetic-bound. Measured on the 2-core
    development VM (2026-12-06, float32, medians of 3 runs in turn; benchmarks/README.md): on two
    devices, 512 random throws of the human box took 1.29 / 1.07 s at 16 / 32 lanes, 2048 took
    3.47 / 3.26 / 2.93 s at 32 / 64 / 128, the 4096-throw tilt x attack grid 8.09 / 5.91 / 5.15 s at
    64 / 128 / 256 and 8192 random throws 8.80 / 8.98 / 9.99 s at 128 / 256 / 512; on one device,
    2048 throws 4.64 / 3.98 / 3.58 / 4.30 s at 16 / 32 / 64 / 128 lanes and the grid 10.1 / 9.26 /
    8.85 / 9.39 s at 32 / 64 / 128 / 256, and 512 throws 1.43 / 1.52 / 1.41 s at 8 / 16 / 32. Until
    then the rule was n / 64 within [8, 256]: this one is 4-17 % faster at 2048 and 4096 throws and at
    512 on two devices, the same at 8192, and 6 % slower at 512 on one device (16 lanes against 8).
    A throw's numbers do not depend on the lane count (:data:`MIN_LANES_PER_DEVICE`): speed only.

    >>> default_lanes(100), default_lanes(4096), default_lanes(10**6), default_lanes(4096, devices=2)
    (8, 128, 128, 256)
    """
    n = check_int("n", n, minimum=1)
    devices = check_int("devices", devices, minimum=1)
    return devices * int(min(128, max(8, 2 ** math.floor(math.log2(max(n / 32, 1.0))))))


def chunk_for(max_steps: int, target: int = 250) -> int:
    """A ``chunk`` for :func:`simulate_batch` [steps]: the divisor of ``max_steps`` nearest to ``target`` by ratio if
    one lies within a factor :data:`CHUNK_SLACK` (4) of it, else ``min(target, max_steps)`` (the last chunk of a throw
    still in play then runs in a shorter program); both integers >= 1.

    A divisor where one is near spares that second program; by ratio, not difference, and never far from
    ``target``: for ``max_steps`` 20249 (a prime) the nearest divisor is 20249 itself (every lane then idles
    from its throw's end to the longest throw's: measured 3.5x slower on 64 throws) and for 100003 it is 1 (a
    host round trip every step: 22x slower; a review, stop 46).

    >>> chunk_for(20250), chunk_for(2000), chunk_for(2003), chunk_for(100), chunk_for(20249)
    (250, 250, 250, 100, 250)
    """
    max_steps = check_int("max_steps", max_steps, minimum=1)
    target = check_int("target", target, minimum=1)
    divisors = [d for d in range(1, math.isqrt(max_steps) + 1) if max_steps % d == 0]
    divisors += [max_steps // d for d in divisors]
    best = min(divisors, key=lambda d: (abs(math.log(d / target)), d))
    return best if abs(math.log(best / target)) <= math.log(CHUNK_SLACK) else min(target, max_steps)


CHUNK_SLACK = 4
"""How far (as a ratio) :func:`chunk_for` lets a divisor of ``max_steps`` lie from its target before it takes the
target itself."""


__all__ = ["BatchResult", "CHUNK_SLACK", "MIN_LANES_PER_DEVICE", "chunk_for", "default_lanes", "simulate_batch"]
