r"""Magic-angle sweeps: the bounce domain and the minimal speed for a bounce, resumable and sharded.

Clanet, Hersen & Bocquet (Nature 427:29, 2004) threw an aluminium disk
(R = 2.5 cm, 2.75 mm) from a catapult at Ω = 65 rev/s and found that a tilt
:math:`\alpha \approx 20°` minimises the speed needed for a bounce (about
2.5 m/s) and that disks tilted beyond about 45° do not bounce. Their analysis
is the high-spin limit, where the tilt stays constant during the impact: the
defaults here are their disk (``stone="clanet"``), ``attitude="fixed"`` and
their reference spin, an attack of 20° at release (their impact angle :math:`\beta`, which gravity steepens
by under a degree from the default release height at these speeds) and speed 3.5 m/s.

A sweep is a :func:`make_spec` of one of two kinds, run by :func:`run_sweep`:

* ``"domain"`` — bounce counts on a (tilt, attack) grid at one speed.
* ``"umin"`` — :math:`U_{min}(\alpha)`, the lowest speed that bounces, by batched
  bisection: every tilt of a chunk is bisected at once (one :func:`jaxskip.simulate_batch`
  call per iteration). Bisection assumes that a throw that bounces still bounces when faster:
  true of the fixed-attitude model over the ranges tested, not of a free stone, which can flip
  at speed (the free Clanet disk at 10° of tilt, 20° attack and 65 rev/s bounces at every speed from
  2.5 to 11.5 m/s in steps of 0.5, not at 12 or 12.5, again at 13; 2026-12-06). So the
  bracket's ends and :data:`SCAN_SPEEDS` speeds evenly spaced between them are thrown first;
  the bisection runs in the scan's first interval in which the count turns from 0 to a bounce (a
  bouncing window narrower than the scan's step below it can be missed), and a tilt where a faster
  speed of the scan fails to bounce after a slower one did is marked (``monotone`` 0). The answer
  is bracketed to the scan's step halved ``iterations`` times, :func:`umin_resolution`.
* :func:`parabola_minimum` — the magic angle between grid points: the vertex
  of the parabola through the lowest :math:`U_{min}` and its two neighbours
  (``best_tilt_fit``, ``best_umin_fit`` in a U_min sweep's result).

Scale: the work is cut into chunks (by default at most :data:`CHUNKS` of them, of
``ceil(n / CHUNKS)`` items each, a domain chunk at least :data:`DOMAIN_CHUNK` grid points:
:func:`default_chunk_size`; neither the chunk size nor the number of devices changes a number on a
given machine: every device advances at least :data:`jaxskip.batch.MIN_LANES_PER_DEVICE` lanes, and XLA:CPU
rounds alike for every batch that wide; another kind of machine may round differently, and a long,
chaotic throw's count with it); each finished chunk is written atomically (temporary
file + ``os.replace``) to ``out_dir/chunk-NNNNN.json`` and a re-run loads it
instead of computing it again, so an interrupted sweep resumes where it stopped
and gives the same file as an uninterrupted one. With
``num_shards > 1`` a machine computes only the chunks ``j`` with
``j % num_shards == shard_index``; :func:`merge` joins the chunk folders of all
machines. Every local JAX device is used (the lanes of
:func:`jaxskip.simulate_batch` are sharded over them). ``out_dir/spec.json`` pins the
sweep a folder holds, its resolved simulation configuration (and an ``.obj`` stone's SHA-256)
included: a re-run with other settings there is refused, and so are chunk files without it. An ``.obj``
stone is known by its contents, not its path: shards that read one file at different paths merge.
"""

from __future__ import annotations

import csv
import dataclasses
import hashlib
import json
import math
import numbers
import os
import types
import sys
import time
import warnings
from collections.abc import Iterable
from pathlib import Path

import jax
import numpy as np

from jaxskip import Throw
from jaxskip._checks import ParameterError, check_array, check_bool, check_int, check_range
from jaxskip._docs import document_fields
from jaxskip._files import check_picture_path, writing
from jaxskip._progress import ProgressLine
from jaxskip._text import duration_words
from jaxskip.forces import DEFAULT_COEFFICIENTS
from jaxskip.settings import SIM_DEFAULTS, describe, simulation
from jaxskip.simulate import AccuracyWarning, SimConfig, warn_if_inert
from jaxskip.stones import BUILTIN_STONES
from jaxskip.throw import MAX_SPEED, MAX_SPIN_REVS

from ._runs import batch, caller_level, silenced_batches, warn_diverged, warn_stability
from .bounds import check_interval

#: Clanet et al.'s reference throw (physics.md §4).
REFERENCE = types.MappingProxyType({"speed": 3.5, "spin": 65.0, "tilt": 20.0, "attack": 20.0})
#: A sweep is cut into about this many chunks by default (fewer if it is small): enough to resume
#: and to shard, few enough to keep each chunk's batch wide (one chunk per tilt made a 12-tilt
#: U_min sweep 2x slower, measured).
CHUNKS = 8
#: A bounce-domain sweep's smallest default chunk [grid points]: smaller domains are one chunk.
DOMAIN_CHUNK = 256
#: Most bisection iterations of a U_min sweep (:func:`make_spec`'s ``iterations``; 2^-40 of the bracket is
#: far below any speed that matters).
MAX_BISECTIONS = 40
#: The limits of every throw a sweep makes, user units: ``{name: (low, high, low_open, high_open, unit)}``. They
#: are :meth:`jaxskip.Throw.from_degrees`' (speed up to :data:`jaxskip.throw.MAX_SPEED`, spin up to
#: :data:`jaxskip.throw.MAX_SPIN_REVS`); :func:`make_spec` checks them and ``jaxskip sweep --help`` shows them
#: (:func:`limit_text`).
THROW_LIMITS = types.MappingProxyType({
    "speed": (0.0, MAX_SPEED, True, False, "m/s"),
    "tilt": (-90.0, 90.0, True, True, "degrees"),
    "attack": (-90.0, 90.0, False, False, "degrees"),
    "spin": (-MAX_SPIN_REVS, MAX_SPIN_REVS, False, False, "rev/s"),
})
#: The lists of numbers each kind's chunk file holds, one entry per work item: counts (non-negative
#: integers) and values (finite numbers or null).
CHUNK_COUNTS = {"domain": ("bounces", "diverged", "cut_off"),
                "umin": ("bounces_at_high", "bounces_at_low", "diverged", "cut_off", "monotone")}
#: Speeds a U_min sweep throws at each tilt between its bracket's ends, evenly spaced, before bisecting, to
#: see whether a faster throw always bounces once a slower one does (module docstring).
SCAN_SPEEDS = 8
#: Outcomes of a throw still in play when the run stopped it (its count is a lower bound).
CUT_OFF = ("time_limit", "step_limit")
CHUNK_VALUES = {"domain": ("first_contact_time",), "umin": ("umin",)}
#: A U_min chunk file's ``bisection``: where each tilt was bisected (inside the scan's interval in which the
#: count turns from 0). Chunks without it were bisected over the whole bracket by an earlier jaxskip.
UMIN_BISECTION = "scan-interval"


def umin_resolution(speed_range, iterations: int) -> float:
    """Width [m/s] of a U_min sweep's final bisection bracket at every tilt: the scan's step,
    ``(high - low) / (SCAN_SPEEDS + 1)``, halved ``iterations`` times.

    ``speed_range``: ``(low, high)`` [m/s], 0 < low < high <= 100; ``iterations``: an integer in [0, 40]
    (:data:`MAX_BISECTIONS`; 0: the scan's step). Anything else is refused with :class:`~jaxskip.ParameterError`.

    >>> umin_resolution((0.5, 8.0), 10)   # 7.5 / 9 / 1024
    0.0008138020833333334
    """
    # (an inverted range gave a negative resolution, text a raw TypeError)
    low, high = check_interval("speed_range", speed_range, 0.0, MAX_SPEED, unit="m/s", low_open=True, holdable=False)
    iterations = check_int("iterations", iterations, minimum=0, maximum=MAX_BISECTIONS)
    return (high - low) / (SCAN_SPEEDS + 1) / 2**iterations


def limit_text(name: str) -> str:
    """A sweep throw parameter's valid range as text, e.g. ``"(0, 100] m/s"`` (:data:`THROW_LIMITS`)."""
    low, high, low_open, high_open, unit = THROW_LIMITS[name]
    return f"{'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'} {unit}"


def _check_throws(name: str, value) -> np.ndarray:
    low, high, low_open, high_open, unit = THROW_LIMITS[name]
    return check_array(name, value, low, high, unit=unit, low_open=low_open, high_open=high_open)


def _check_throw(name: str, value) -> float:
    """One number (a sweep's ``speed`` or ``spin``), checked as :func:`_check_throws`."""
    low, high, low_open, high_open, unit = THROW_LIMITS[name]
    return check_range(name, value, low, high, unit=unit, low_open=low_open, high_open=high_open)


MAX_ANGLES = 100_000
"""Most tilts, or attacks, a sweep takes (a domain sweep's grid is their product: at most 10^7 points)."""
MAX_GRID = 10_000_000


def _angles(name: str, values) -> tuple:
    """``values`` (a number or a 1-D sequence of them, at most :data:`MAX_ANGLES`, none repeated) as a
    non-empty tuple of floats."""
    try:
        raw = np.atleast_1d(np.asarray(values))
        arr = raw.astype(float) if raw.dtype.kind in "iuf" else None  # not text, not True/False
    except (TypeError, ValueError):
        arr = None
    if arr is None or arr.ndim != 1 or arr.size == 0:
        raise ParameterError(f"{name} must be a number or a non-empty list of numbers [deg], got {values!r}")
    if arr.size > MAX_ANGLES:
        raise ParameterError(f"{name} must hold at most {MAX_ANGLES} angles, got {arr.size}")
    unique, counts = np.unique(arr, return_counts=True)
    if np.any(counts > 1):  # simulated and written twice over: a typo far more often than a wish
        n = int(counts[counts > 1][0])
        raise ParameterError(f"{name} must not repeat an angle, got {float(unique[counts > 1][0]):g} "
                             + ("twice" if n == 2 else f"{n} times"))
    return tuple(float(v) for v in arr)


def default_chunk_size(kind: str, items: int) -> int:
    """Work items per chunk when none is given: ``ceil(items / CHUNKS)`` tilts (umin), or as many grid
    points but at least :data:`DOMAIN_CHUNK` (domain)."""
    size = -(-items // CHUNKS)
    return size if kind == "umin" else max(size, DOMAIN_CHUNK)


@document_fields
@dataclasses.dataclass(frozen=True)
class SweepSpec:
    """A sweep's resolved configuration (user units: m/s, degrees, rev/s); stored with its results."""

    kind: str
    """``"domain"`` (bounce counts on a tilt x attack grid) or ``"umin"`` (minimal speed per tilt)."""
    tilts: tuple
    """Tilts [deg]."""
    attacks: tuple
    """Impact angles [deg] (one for ``umin``)."""
    speed: float
    """Speed [m/s] of a ``domain`` sweep."""
    speed_range: tuple
    """``(low, high)`` [m/s] bracketing the bisection of a ``umin`` sweep."""
    iterations: int
    """Bisection iterations of a ``umin`` sweep."""
    spin: float
    """Spin [rev/s]."""
    stone: str
    """Built-in stone name or .obj path."""
    attitude: str
    """``"fixed"`` (tilt held: Clanet's high-spin limit) or ``"free"``."""
    chunk_size: int
    """Work items per chunk file (throws for ``domain``, tilts for ``umin``)."""
    mass: float | None
    """Stone mass [kg] as given (None: from the density)."""
    density: float | None
    """Stone density [kg/m^3] as given (None: the stone's own)."""
    force_law: str
    """``"bocquet"`` or ``"seed"``."""
    c_lift: float | None
    """Lift coefficient [-] as given (None: the law's calibrated value, given or not)."""
    c_friction: float | None
    """Friction coefficient [-] as given (None: the law's calibrated value, given or not)."""
    velocity: str
    """``"body"``, ``"local"`` or ``"passive"`` (:class:`jaxskip.ForceModel`)."""
    integrator: str
    """``"euler"`` or ``"rk4"``."""
    dt: float
    """Time step in contact [s]."""
    duration: float
    """Simulated time limit [s]."""
    max_steps: int
    """Step budget per throw (resolved)."""
    bounce_clearance: float
    """What counts as a bounce [m]: the height the stone's lowest point must rise above the water after a contact
    (:attr:`jaxskip.SimConfig.bounce_clearance`; a spec.json written before it was recorded used 1e-3, the
    default then and now, and is read so)."""
    config: dict
    """The resolved simulation configuration (:func:`jaxskip.settings.describe`: the stone's mass, the law's
    coefficients, ...), as ``jaxskip optimize --json`` reports it, and ``precision``: ``"float64"`` or
    ``"float32"``, what the sweep is computed in (a resume or a merge in the other is refused)."""

    def to_dict(self) -> dict:
        """The spec as a JSON-ready dict (what ``out_dir/spec.json`` holds): every field by its name, user
        units (m/s, deg, rev/s; SI otherwise), tuples as lists."""
        return {k: (list(v) if isinstance(v, tuple) else v) for k, v in dataclasses.asdict(self).items()}


def make_spec(kind: str, *, tilts, attacks=(REFERENCE["attack"],), speed: float = REFERENCE["speed"],
              speed_range=(0.5, 8.0), iterations: int = 10, spin: float = REFERENCE["spin"],
              stone: str = "clanet", attitude: str = "fixed", chunk_size: int | None = None, **sim) -> SweepSpec:
    """Validate a sweep's parameters (user units) before anything is compiled or written.

    Every throw of the sweep must lie within :meth:`jaxskip.Throw.from_degrees`' limits,
    :data:`THROW_LIMITS` (speed in (0, 100] m/s, tilt in (-90, 90) deg, attack in [-90, 90] deg, spin in
    [-500, 500] rev/s).

    ``kind``: ``"domain"`` (the bounce count of every (tilt, attack) pair at ``speed``) or ``"umin"``
    (the minimal speed for a bounce at each tilt, by bisection). ``tilts``, ``attacks``: a number or a
    non-empty list of them [deg] (``umin``: one attack). ``speed`` [m/s], in (0, 100]: the speed of a
    ``domain`` sweep (default 3.5, Clanet's). ``speed_range``: ``(low, high)`` [m/s], 0 < low < high <=
    100, the bracket a ``umin`` bisection starts from (default (0.5, 8)). ``iterations``: bisection
    steps of a ``umin`` sweep, an integer in [1, 40] (:data:`MAX_BISECTIONS`), inside the scan's interval
    where the count turns from 0; the answer is bracketed to :func:`umin_resolution`,
    ``(high - low) / (SCAN_SPEEDS + 1) / 2**iterations`` m/s. ``spin`` [rev/s], in [-500, 500]: every throw's spin
    (default 65, Clanet's catapult). ``speed``, ``speed_range`` and ``iterations`` are checked for
    either kind (and stored in the spec), used by the one kind only. ``stone``: a built-in name
    (default ``"clanet"``, Clanet's aluminium disk) or an ``.obj`` path [m]. ``attitude``: ``"fixed"``
    (default: the tilt held, Clanet's high-spin limit) or ``"free"`` (6-DoF). ``sim``: the
    other simulation settings of ``jaxskip throw``, named and defaulted as
    :data:`jaxskip.settings.SIM_DEFAULTS` (``mass``, ``density``, ``force_law``, ``c_lift``, ``c_friction``,
    ``velocity``, ``integrator``, ``dt``, ``duration``, ``max_steps``, ``bounce_clearance`` [m]); the stone is loaded here and the
    resolved configuration kept in the spec's ``config``. ``chunk_size``: work items per chunk file, an
    integer >= 1: tilts (umin) or grid points (domain); default :func:`default_chunk_size` (about
    :data:`CHUNKS` chunks), so that a default sweep resumes and shards.

    Returns a :class:`SweepSpec` (frozen; user units) for :func:`run_sweep`. Nothing is compiled here.

    >>> spec = make_spec("umin", tilts=[10.0, 20.0, 30.0], iterations=4)
    >>> spec.speed_range, spec.spin, spec.chunk_size, umin_resolution(spec.speed_range, spec.iterations)
    ((0.5, 8.0), 65.0, 1, 0.052083333333333336)
    """
    if kind not in ("domain", "umin"):
        raise ParameterError(f"kind must be 'domain' or 'umin', got {kind!r}")
    unknown = set(sim) - set(SIM_DEFAULTS)
    if unknown:   # (a TypeError before: a ParameterError, as every other bad argument here; a review)
        raise ParameterError(f"make_spec() got unknown simulation settings: {', '.join(sorted(unknown))}; they are "
                             f"{', '.join(SIM_DEFAULTS)}")
    tilts = _angles("tilts", tilts)
    attacks = _angles("attacks", attacks)
    if kind == "umin" and len(attacks) != 1:
        raise ParameterError(f"attacks must be one angle for a umin sweep, got {len(attacks)}")
    if len(tilts) * len(attacks) > MAX_GRID:
        raise ParameterError(f"tilts and attacks: their grid must have at most {MAX_GRID} points, got "
                             f"{len(tilts)} x {len(attacks)}")
    lo, hi = check_interval("speed_range", speed_range, 0.0, MAX_SPEED, unit="m/s", low_open=True, holdable=False)
    iterations = check_int("iterations", iterations, minimum=1, maximum=MAX_BISECTIONS)
    # every speed, tilt, attack and spin the sweep throws: checked against THROW_LIMITS (what --help shows),
    # then as the throw checks them
    speed = _check_throw("speed", speed)   # one number each (a list ran into float() below)
    _check_throws("tilt", tilts)
    _check_throws("attack", attacks)
    spin = _check_throw("spin", spin)
    if not isinstance(stone, (str, os.PathLike)):  # the spec stores it as text, to be loaded again
        raise ParameterError(f"stone must be a built-in name or an .obj path, got {type(stone).__name__} (a sweep "
                             "records its stone by name in spec.json: write a mesh with jaxskip.write_obj)")
    stone = _stone_text(stone)
    Throw.from_degrees(speed=np.array([speed, lo, hi], dtype=float)[:, None, None], tilt=np.array(tilts)[:, None],
                       attack=np.array(attacks), spin=spin)
    sim = {**SIM_DEFAULTS, **sim, "stone": stone, "attitude": attitude}
    config, water, rigid = simulation(**sim)
    warn_if_inert(config, stacklevel=caller_level() + 1)
    # the resolved step budget, and plain floats (a NumPy float32 dt or mass ended a sweep with an out folder in
    # a raw 'not JSON serializable' error, and spec.to_dict() was not the JSON-ready dict it says)
    sim.update(max_steps=int(config.max_steps), dt=float(config.dt), duration=float(config.duration),
               bounce_clearance=float(config.bounce_clearance),
               **{k: None if sim[k] is None else float(sim[k]) for k in ("mass", "density", "c_lift", "c_friction")})
    # a coefficient given at the law's calibrated value is the default said aloud: stored as the default
    # (None), so that the same sweep resumes whether or not it was given (--c-lift 1 was another sweep)
    for name in ("c_lift", "c_friction"):
        if sim[name] is not None and float(sim[name]) == DEFAULT_COEFFICIENTS[config.force.law][name]:
            sim[name] = None
    # so is a mass or density that makes the stone's own mass (a mass copied from spec.json's config was
    # refused as another sweep, "it has mass=None")
    if sim["mass"] is not None or sim["density"] is not None:
        own = simulation(**{**sim, "mass": None, "density": None})[2]
        if float(own.mass) == float(rigid.mass):
            sim.update(mass=None, density=None)
    # an .obj stone is pinned by its contents too: a resume (or a shard) with another file at that path
    # would mix two stones' results
    mesh_file = {}
    if str(stone) not in BUILTIN_STONES:
        mesh_file["stone_sha256"] = hashlib.sha256(Path(stone).read_bytes()).hexdigest()
    if chunk_size is None:
        chunk_size = default_chunk_size(kind, len(tilts) if kind == "umin" else len(tilts) * len(attacks))
    chunk_size = check_int("chunk_size", chunk_size, minimum=1)
    return SweepSpec(kind=kind, tilts=tilts, attacks=attacks, speed=float(speed), speed_range=(lo, hi),
                     iterations=iterations, spin=float(spin), chunk_size=chunk_size, **sim,
                     config={**describe(stone, config, water, rigid), **mesh_file, "precision": _precision()})


def _precision() -> str:
    """``"float64"`` or ``"float32"``: what this process computes a sweep in (``jax_enable_x64``)."""
    return "float64" if jax.config.jax_enable_x64 else "float32"


def _sim(spec: SweepSpec):
    """``(SimConfig, WaterParams, RigidStone)`` of a sweep (no trajectories kept)."""
    config, water, rigid = simulation(**{k: getattr(spec, k) for k in SIM_DEFAULTS})
    return dataclasses.replace(config, record=False), water, rigid


def _batch(throws, sim, progress: bool):
    """The batch's :class:`jaxskip.BatchResult` and its (N,) mask of diverged throws (the sweep warns once)."""
    config, water, rigid = sim
    return batch(throws, rigid, water=water, config=config, progress=progress)


def _domain_chunk(spec: SweepSpec, sim, index: np.ndarray, progress: bool) -> dict:
    tilt = np.asarray(spec.tilts)[index // len(spec.attacks)]
    attack = np.asarray(spec.attacks)[index % len(spec.attacks)]
    throws = Throw.from_degrees(speed=np.full(len(index), spec.speed), tilt=tilt, attack=attack, spin=spec.spin)
    r, diverged = _batch(throws, sim, progress)
    t_end = r.tracker.t_end[:, 0]
    t_start = r.tracker.t_start[:, 0]
    # "first_contact_time": the first contact's duration [s] (t_end - t_start), NaN (None in the file) where
    # there was no contact or it never ended in a bounce; not the time at which it happened.
    # (its end was taken as the run's where the duration cut the contact off: 0.279 s "long", with 0 bounces; a
    # review) The first contact ended in a bounce exactly where the throw bounced at all.
    first = np.where((np.asarray(r.bounces) > 0) & np.isfinite(t_end), t_end - t_start, np.nan)
    # "diverged": 1 where the throw's integration failed (outcome 'diverged'): its count means nothing;
    # "cut_off": 1 where it was still in play at the duration or step limit: its count is a lower bound
    cut = np.isin(r.outcome_names, CUT_OFF)
    return {"bounces": r.bounces.tolist(), "first_contact_time": [_num(x) for x in first],
            "diverged": diverged.astype(int).tolist(), "cut_off": cut.astype(int).tolist()}


def _umin_throws(spec: SweepSpec) -> int:
    """Throws a U_min sweep makes at each tilt: the bracket's ends, the scan between them, one a bisection step."""
    return 2 + SCAN_SPEEDS + spec.iterations


def _umin_chunk(spec: SweepSpec, sim, index: np.ndarray, progress: bool) -> dict:
    tilt = np.asarray(spec.tilts)[index]
    n = len(index)
    lo = np.full(n, spec.speed_range[0])
    hi = np.full(n, spec.speed_range[1])

    failed = np.zeros(n, int)  # the tilt's throws that diverged
    unknown = np.zeros(n, int)  # ...and those cut off by the duration or step limit before a bounce

    def bounces(speed, show=False):
        """Counts (n, k) of the throws at speeds (n, k) [m/s], row i at tilt i (``show``: the batch's progress)."""
        nonlocal failed, unknown
        k = speed.shape[1]
        throws = Throw.from_degrees(speed=speed.ravel(), tilt=np.repeat(tilt, k), attack=spec.attacks[0],
                                    spin=spec.spin)
        r, diverged = _batch(throws, sim, show)
        failed = failed + diverged.reshape(n, k).sum(axis=1)
        # no bounce yet when the run stopped it: whether it would bounce is unknown, not "no"
        unknown = unknown + (np.isin(r.outcome_names, CUT_OFF) & (np.asarray(r.bounces) == 0)).reshape(n, k).sum(axis=1)
        return np.asarray(r.bounces).reshape(n, k)

    # the bracket's ends and SCAN_SPEEDS speeds between them, in one batch
    speeds = lo[:, None] + (hi - lo)[:, None] * (np.arange(SCAN_SPEEDS + 2) / (SCAN_SPEEDS + 1))[None, :]
    speeds[:, -1] = hi
    ladder = bounces(speeds, progress)   # (the largest batch: silent for a minute at 800 tilts; a review)
    at_low, at_high = ladder[:, 0], ladder[:, -1]
    bounced = ladder > 0
    monotone = np.all(bounced[:, 1:] >= bounced[:, :-1], axis=1)
    first = np.argmax(bounced, axis=1)   # the slowest speed of the scan that bounces (0 where none does)
    found = bounced.any(axis=1)
    # Bisect the scan's first interval in which the count turns from 0 to a bounce, at every tilt: the answer
    # never lies above a speed the scan saw bounce, and every tilt's bracket is the scan's step / 2**iterations.
    # (Until 2026-12-07 a monotone tilt was bisected over the whole bracket: its answer could lie above the
    # scan's own first bouncing speed (4.25 m/s at a tilt whose 2.17 m/s throw bounced, one iteration), and a
    # tilt bisected inside the scan was given the whole bracket's error bar, reaching below its low end.)
    rows = np.arange(n)
    inside = found & (first > 0)
    lo = np.where(inside, speeds[rows, np.maximum(first - 1, 0)], lo)
    hi = np.where(inside, speeds[rows, first], hi)
    line = ProgressLine()
    for i in range(spec.iterations):
        mid = 0.5 * (lo + hi)
        ok = bounces(mid[:, None])[:, 0] > 0
        hi, lo = np.where(ok, mid, hi), np.where(ok, lo, mid)
        if progress:
            line.update(f"    bisection {i + 1}/{spec.iterations}")
    if progress:
        line.close()
    umin = np.where(at_low > 0, spec.speed_range[0], np.where(found, hi, np.nan))
    # a bisection that met a diverged throw took a step on a count that means nothing: no U_min there
    umin = np.where(failed > 0, np.nan, umin)
    # ...and so did one that took a throw cut off before its first bounce for one that does not bounce
    umin = np.where(unknown > 0, np.nan, umin)
    return {"umin": [_num(x) for x in umin], "bounces_at_high": at_high.tolist(), "bounces_at_low": at_low.tolist(),
            "diverged": failed.tolist(), "cut_off": unknown.tolist(), "monotone": monotone.astype(int).tolist(),
            "bisection": UMIN_BISECTION}


def _num(x) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def _items(spec: SweepSpec) -> int:
    return len(spec.tilts) * len(spec.attacks) if spec.kind == "domain" else len(spec.tilts)


def _chunks(spec: SweepSpec) -> list[np.ndarray]:
    n = _items(spec)
    return [np.arange(i, min(i + spec.chunk_size, n)) for i in range(0, n, spec.chunk_size)]


def _stone_text(stone) -> str:
    """How spec.json records ``stone``: a built-in name as it is; a path normalised
    (:func:`os.path.normpath`), so that ``./peb.obj`` and ``peb.obj`` name one sweep, not two that refuse
    each other's folder (a path ends in ``.obj``: it never normalises to a built-in name)."""
    text = os.fspath(stone)
    return text if text in BUILTIN_STONES else os.path.normpath(text)


def _write_atomic(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` so that a reader never sees a partial file. Creates ``path``'s folder if
    missing, not the folders above it (:func:`_out_folder` checked that they exist).

    The file gets the usual mode, ``0o666`` less the umask, as ``open(path, "w")`` would give it (a
    temporary file from :func:`tempfile.mkstemp` would be private, 0600, whatever the umask)."""
    tmp = _temp_beside(path, text)
    try:
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _temp_beside(path: Path, text: str) -> Path:
    """A new temporary file beside ``path`` (creating ``path``'s folder if missing) holding ``text``, synced."""
    path.parent.mkdir(exist_ok=True)
    for _ in range(100):
        tmp = path.parent / f"{path.name}.{os.urandom(6).hex()}.tmp"
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)  # the kernel applies the umask
            break
        except FileExistsError:
            continue
    else:  # pragma: no cover - 100 collisions of 48 random bits
        raise FileExistsError(f"cannot create a temporary file beside {str(path)!r}")
    try:
        with writing(path), os.fdopen(fd, "w") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
    except BaseException:
        os.unlink(tmp)
        raise
    return tmp


def _write_new(path: Path, text: str) -> bool:
    """Write ``text`` to ``path`` as :func:`_write_atomic` does, unless ``path`` exists: then nothing is written
    and False returned (two runs starting at once: one of them creates it, the other reads it)."""
    tmp = _temp_beside(path, text)
    try:
        os.link(tmp, path)  # atomic, and fails if path exists (a rename would replace it)
    except FileExistsError:
        return False
    except OSError:  # pragma: no cover - a file system without hard links: a rename, as before
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
    return True


#: What to do about a damaged chunk file of the folder being computed.
RECOMPUTE = "delete it and run the sweep again in that folder to recompute the chunk"


def run_sweep(spec: SweepSpec, out_dir=None, *, shard_index: int | None = None, num_shards: int = 1,
              progress: bool = False, _stop_after: int | None = None) -> dict | None:
    """Compute the sweep's chunks (those of this shard), resuming from ``out_dir``.

    ``num_shards``: machines sharing the sweep, an integer >= 1 (> 1 needs ``out_dir``);
    ``shard_index``: this machine's shard, an integer in [0, num_shards): it computes the chunks ``j``
    with ``j % num_shards == shard_index``. ``progress``: True or False: progress lines on stderr.
    ``spec``: a :class:`SweepSpec` from :func:`make_spec`. ``out_dir``: the sweep's folder (None: keep
    nothing); it is created if missing, but its parent folder must exist (as ``jaxskip sweep --out``
    requires: a mistyped path is refused rather than built). A chunk file found there is checked
    (valid JSON, this sweep's chunk, one value per work item): a damaged one raises
    :class:`~jaxskip.ParameterError` naming it (delete it to have the chunk recomputed).

    Returns the assembled result (see :func:`assemble`) when every chunk is present in
    ``out_dir`` (or when ``out_dir`` is None), else None (other shards still to run).
    ``_stop_after`` (tests) raises ``KeyboardInterrupt`` after that many new chunks.
    """
    if not isinstance(spec, SweepSpec):
        raise ParameterError(f"spec must be an optimize.SweepSpec (build it with optimize.make_spec(kind, tilts=...)), "
                             f"got {type(spec).__name__}")
    num_shards = check_int("num_shards", num_shards, minimum=1)
    if out_dir is None and num_shards > 1:
        raise ParameterError("num_shards > 1 needs an out_dir: a shard's chunks are joined from the folders (merge)")
    if shard_index is None:
        if num_shards > 1:   # (it ran shard 0: a second machine that forgot its index repeated the first's work)
            raise ParameterError(f"num_shards={num_shards} needs shard_index, this machine's shard, in "
                                 f"[0, {num_shards - 1}]")
        shard_index = 0
    shard_index = check_int("shard_index", shard_index, minimum=0, maximum=num_shards - 1)
    progress = check_bool("progress", progress)
    made_in = spec.config.get("precision") if isinstance(spec.config, dict) else None
    if made_in != _precision():
        raise ParameterError(f"spec was made in {made_in} and this process computes in {_precision()}: make the spec "
                             "and run it in one precision (jax.config.update('jax_enable_x64', ...) before both), "
                             "so that its spec.json says what its chunks hold")
    _check_made(spec)
    out = None if out_dir is None else _out_folder(out_dir)
    sim = _sim(spec)  # before anything is written
    if out is not None:
        _check_spec_file(out, spec)
    chunks = _chunks(spec)
    results, computed = {}, 0
    paths = [None if out is None else out / f"chunk-{j:05d}.json" for j in range(len(chunks))]
    # every chunk already there is checked before any is computed (a damaged last chunk was found hours later, when
    # the loop reached it; a review)
    for j, (index, path) in enumerate(zip(chunks, paths)):
        if path is not None and path.exists():
            results[j] = _load_chunk(path, spec, j, index, RECOMPUTE)
    if progress and out is not None:
        kept = len(results)
        if kept:
            print(f"  {kept} of {len(chunks)} chunks already in {str(out)!r} (kept, not recomputed)", file=sys.stderr,
                  flush=True)
    if any(j % num_shards == shard_index and j not in results for j in range(len(chunks))):
        # once for the run, at its fastest throw (each batch's own warning is silenced)
        config, water, rigid = sim
        warn_stability(config, rigid, water, spec.speed_range[1] if spec.kind == "umin" else spec.speed,
                       stacklevel=caller_level() + 1)
    todo = sum(1 for j in range(len(chunks)) if j not in results and j % num_shards == shard_index)
    started = first_done = time.monotonic()
    with silenced_batches():
        for j, (index, path) in enumerate(zip(chunks, paths)):
            if j in results or j % num_shards != shard_index:
                continue
            if path is not None and path.exists():   # written meanwhile by another run in this folder: kept
                results[j] = _load_chunk(path, spec, j, index, RECOMPUTE)
                continue
            if _stop_after is not None and computed >= _stop_after:
                raise KeyboardInterrupt(f"stopped after {computed} chunks (test)")
            if progress:
                what = ("tilt" if spec.kind == "umin" else "grid point") + ("" if len(index) == 1 else "s")
                # (how long so far and how long to go: a 60-chunk sweep's log gave neither; a review) The pace is
                # taken after the first chunk, which compiles.
                pace = f"; {computed} of {todo} done in {duration_words(time.monotonic() - started)}" if computed else ""
                if computed > 1:
                    left = (time.monotonic() - first_done) / (computed - 1) * (todo - computed)
                    pace += f", about {duration_words(left)} left"
                print(f"  chunk {j + 1}/{len(chunks)} ({len(index)} {what}){pace}", file=sys.stderr, flush=True)
            work = _domain_chunk if spec.kind == "domain" else _umin_chunk
            data = {"chunk": j, "items": index.tolist(), "sweep": sweep_id(spec), **work(spec, sim, index, progress)}
            if path is not None:
                _write_atomic(path, json.dumps(data, sort_keys=True))
            results[j] = data
            computed += 1
            if computed == 1:
                first_done = time.monotonic()
    # chunks of the other shards, where they share this folder and finished meanwhile: the last to finish writes the
    # result (a review: checked only before the run, they were missed)
    for j, (index, path) in enumerate(zip(chunks, paths)):
        if j not in results and path is not None and path.exists():
            results[j] = _load_chunk(path, spec, j, index, RECOMPUTE)
    _warn_diverged(spec, list(results.values()), sim[0])
    _warn_cut_off(spec, list(results.values()), sim[0])
    _warn_not_monotone(spec, list(results.values()))
    if len(results) < len(chunks):
        return None
    result = assemble(spec, [results[j] for j in range(len(chunks))])
    if out is not None:
        write_results(result, out)
    return result


def _check_made(spec: SweepSpec) -> None:
    """Refuse a spec that :func:`make_spec` would not make of its own fields: one built by hand or changed with
    ``dataclasses.replace`` skips its checks (a kind ``"x"`` ran as a U_min sweep, an inverted speed range gave
    a negative resolution, a chunk size of 0 a raw ValueError, duplicate tilts ran twice)."""
    fields = {f.name: getattr(spec, f.name) for f in dataclasses.fields(SweepSpec) if f.name != "config"}
    with warnings.catch_warnings():   # (make_spec warned when the spec was made)
        warnings.simplefilter("ignore")
        remade = make_spec(fields.pop("kind"), **fields)   # raises ParameterError naming a bad field
    if remade != spec:
        differs = _spec_difference(spec.to_dict(), remade.to_dict()).replace("its spec.json", "it")
        raise ParameterError(f"spec is not what optimize.make_spec makes of its own fields ({differs}): build specs "
                             "with make_spec, not by hand or with dataclasses.replace, which skip its checks")


def _warn_diverged(spec: SweepSpec, chunks: list[dict], config) -> None:
    """One :class:`jaxskip.DivergedWarning` for the chunks a run holds, if any of their throws diverged."""
    failed = sum(sum(c["diverged"]) for c in chunks)
    total = sum(len(c["items"]) for c in chunks)
    if spec.kind == "domain":
        what, treatment = "domain sweep", "their counts mean nothing (1 in the result's 'diverged', written to result.json and result.csv when it has an out folder)"
    else:
        total *= _umin_throws(spec)
        bad = sum(1 for c in chunks for n in c["diverged"] if n)
        what, treatment = "U_min sweep", f"{bad} tilt(s) have no U_min ('diverged' counts them per tilt)"
    warn_diverged(failed, total, what, treatment, config, stacklevel=caller_level())


def _warn_not_monotone(spec: SweepSpec, chunks: list[dict]) -> None:
    """One :class:`jaxskip.AccuracyWarning` for the tilts of a U_min sweep's chunks at which a faster throw of the
    scan failed to bounce after a slower one bounced (``monotone`` 0): their ``umin`` is bisected in the scan's
    first interval in which the count turns from 0, and a narrower bouncing window may be missed."""
    if spec.kind != "umin":
        return
    # (a tilt without a U_min, its scan met a throw that diverged or was cut off, has its own warning)
    tilts = [spec.tilts[i] for c in chunks for i, m, u in zip(c["items"], c["monotone"], c["umin"]) if not m and u is not None]
    if tilts:
        step = (spec.speed_range[1] - spec.speed_range[0]) / (SCAN_SPEEDS + 1)
        warnings.warn(f"U_min sweep: at {len(tilts)} tilt(s) ({', '.join(f'{t:g}' for t in tilts)} deg) a faster throw "
                      f"failed to bounce where a slower one bounced ('monotone' 0 in the result, and in result.json and result.csv when it has an out folder; a "
                      f"free stone can flip at speed): U_min there is the lowest speed that bounces among the "
                      f"{SCAN_SPEEDS + 2} thrown {step:.3g} m/s apart, refined by bisection; a bouncing window "
                      f"narrower than {step:.3g} m/s below it would be missed", AccuracyWarning,
                      stacklevel=caller_level())


def _warn_cut_off(spec: SweepSpec, chunks: list[dict], config) -> None:
    """One :class:`jaxskip.AccuracyWarning` for the chunks a run holds, if any throw was still in play at the
    duration or step limit (domain: its count is a lower bound; U_min: the tilt has no U_min)."""
    cut = sum(sum(c["cut_off"]) for c in chunks)
    if not cut:
        return
    total = sum(len(c["items"]) for c in chunks)
    if spec.kind == "domain":
        what = (f"{cut} of the {total} throws of this domain sweep were still skipping when the run stopped them: "
                "their counts are lower bounds (1 in the result's 'cut_off', written to result.json and result.csv when it has an out folder)")
    else:
        bad = sum(1 for c in chunks for n in c["cut_off"] if n)
        what = (f"{cut} of the {total * _umin_throws(spec)} throws of this U_min sweep were stopped before their "
                f"first bounce, so whether they bounce is unknown: {bad} tilt(s) have no U_min ('cut_off' counts them "
                "per tilt)")
    warnings.warn(f"{what}; the run stops a throw at duration={config.duration:g} s or max_steps={config.max_steps}: "
                  "raise them (--duration, --max-steps in the CLI)", AccuracyWarning, stacklevel=caller_level())


def _out_folder(out_dir) -> Path:
    """``out_dir`` as a Path, refused unless it is a folder or can be made one in an existing folder."""
    if isinstance(out_dir, str) and not out_dir.strip():
        # (Path("") is the current folder: the sweep's files would land among the user's)
        raise ParameterError(f"out_dir must be a folder path, got {out_dir!r}")
    try:
        out = Path(out_dir)
    except TypeError:
        raise ParameterError(f"out_dir must be a folder path, got {out_dir!r}") from None
    parent = os.path.dirname(os.path.abspath(out))
    if out.exists() and not out.is_dir():
        raise ParameterError(f"out_dir {str(out)!r} is a file, not a folder")
    if not os.path.isdir(parent):
        raise ParameterError(f"out_dir {str(out)!r}: its parent folder {parent!r} does not exist (a sweep creates "
                             "its own folder, not the folders above it)")
    return out


def _read_json(path: Path, remedy: str):
    """The JSON in ``path``; a file that is not valid JSON (truncated, overwritten), or a folder in its place,
    is refused naming it."""
    if path.is_dir():
        raise ParameterError(f"{str(path)!r} is a folder, not a file; {remedy}")
    try:
        return json.loads(path.read_text())
    except ValueError as exc:  # json.JSONDecodeError, UnicodeDecodeError
        raise ParameterError(f"{str(path)!r} is damaged (not valid JSON: {exc}); {remedy}") from None


def _chunk_problem(data, spec: SweepSpec, j: int, index: np.ndarray) -> str | None:
    """What is wrong with chunk ``j``'s data (None: nothing)."""
    if not isinstance(data, dict):
        return "not a JSON object"
    lacks = [k for k in ("chunk", "items", *CHUNK_COUNTS[spec.kind], *CHUNK_VALUES[spec.kind]) if k not in data]
    if "monotone" in lacks and not set(lacks) - {"monotone", "diverged", "cut_off"}:
        return ("it was written by an earlier jaxskip, before the U_min sweep scanned each bracket (its U_min was "
                "bisected assuming a faster throw always bounces); delete the folder's chunk files to recompute them")
    if "diverged" in lacks and set(lacks) <= {"diverged", "cut_off"}:
        return ("it was written by an earlier jaxskip, which did not record the throws that diverged (their counts "
                "mean nothing), so it cannot be checked for them")
    if lacks == ["cut_off"]:
        return ("it was written by an earlier jaxskip, which did not record the throws the duration or step limit "
                "cut off (their counts are lower bounds), so it cannot be checked for them")
    if lacks:
        return f"it lacks {', '.join(map(repr, lacks))}"
    if data["chunk"] != j or data["items"] != index.tolist():
        return f"not chunk {j} of this sweep: its 'chunk' and 'items' differ"
    # (one copied from another sweep's folder, of the same size, was kept in silence: 9 bisections where the
    # spec said 10; a review) A chunk from before chunks named their sweep has no 'sweep': checked as before.
    if "sweep" in data and data["sweep"] != sweep_id(spec):
        return ("its 'sweep' is not this folder's: it is a chunk of another sweep (copied from another sweep's "
                "folder?)")
    n = len(index)
    for key in CHUNK_COUNTS[spec.kind] + CHUNK_VALUES[spec.kind]:
        values = data[key]
        if not isinstance(values, list) or len(values) != n:
            return f"{key!r} must be a list of {n} values, got {repr(values)[:40]}"
        if key == "monotone":   # a flag, not a count
            ok = all(isinstance(v, int) and not isinstance(v, bool) and v in (0, 1) for v in values)
        elif key in CHUNK_COUNTS[spec.kind]:
            ok = all(isinstance(v, int) and not isinstance(v, bool) and v >= 0 for v in values)
        else:
            ok = all(v is None or (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v))
                     for v in values)
        if not ok:
            what = "0 or 1" if key == "monotone" else "a count" if key in CHUNK_COUNTS[spec.kind] else "a number"
            return f"{key!r} holds a value that is not {what}"
        if key in CHUNK_VALUES[spec.kind]:  # a number the sweep cannot have produced: a hand edit, or another file
            low, high, unit = ((*spec.speed_range, "m/s, the bisection's bracket") if key == "umin"
                               else (0.0, spec.duration, "s, the throw's duration"))
            wrong = [v for v in values if v is not None and not low <= v <= high]
            if wrong:
                return f"{key!r} holds {wrong[0]!r}, outside [{low:g}, {high:g}] {unit}"
    if spec.kind == "umin" and data.get("bisection") != UMIN_BISECTION:
        return ("it was written by an earlier jaxskip, which bisected a tilt over the whole bracket (its U_min could "
                "lie above a speed its own scan saw bounce); delete the folder's chunk files to recompute them")
    return None


def _chunk_values(data: dict) -> dict:
    """A chunk's results, without the sweep it names (absent from chunks written before they named it)."""
    return {k: v for k, v in data.items() if k != "sweep"}


def _load_chunk(path: Path, spec: SweepSpec, j: int, index: np.ndarray, remedy: str) -> dict:
    """Chunk ``j`` of ``spec`` read from ``path``, checked; a damaged file is refused naming it and ``remedy``."""
    data = _read_json(path, remedy)
    problem = _chunk_problem(data, spec, j, index)
    if problem is not None:
        raise ParameterError(f"{str(path)!r} is damaged ({problem}); {remedy}")
    if spec.kind == "domain" and "sweep" not in data:
        # Written before stop 47, when a first contact the duration cut off had the run's end as its end: its time
        # is read as now written, None where the throw never bounced (the only such contacts), so that one
        # result does not mix the two meanings.
        data = {**data, "first_contact_time": [None if n == 0 else t
                                               for n, t in zip(data["bounces"], data["first_contact_time"])]}
    return data


#: What to do about a damaged spec.json: the chunks beside it cannot be checked without it.
SPEC_REMEDY = ("it records which sweep the folder holds, so the chunk files beside it cannot be checked: "
               "use a new folder (or delete this whole folder)")


#: Settings recorded in spec.json since sweeps were first written, with the value every sweep written before
#: used: such a folder is read as holding them, so that it resumes, and merges with shards made now.
SPEC_ADDED = {"bounce_clearance": 1e-3}


def _read_spec(path: Path) -> dict:
    data = _read_json(path, SPEC_REMEDY)
    if not isinstance(data, dict):
        raise ParameterError(f"{str(path)!r} is damaged (not a JSON object); {SPEC_REMEDY}")
    if "kind" in data:   # (what an older jaxskip wrote; a damaged file stays damaged)
        for key, value in SPEC_ADDED.items():
            data.setdefault(key, value)
            if isinstance(data.get("config"), dict):
                data["config"].setdefault(key, value)
    return data


def _shown(value) -> str:
    """``repr(value)`` for a message, a long list cut to its ends and its length (a 40-tilt grid is not
    quoted whole)."""
    text = repr(value)
    if len(text) <= 60:
        return text
    if isinstance(value, list) and len(value) > 4:
        return f"[{value[0]!r}, {value[1]!r}, ..., {value[-1]!r}] ({len(value)} values)"
    return text[:57] + "..."


RESUME_REMEDY = ("give those settings to resume it (a default that changed since the folder was made, such as "
                 "max_steps, can be given explicitly: --max-steps N), or use a new folder")


def _identity(spec: dict) -> dict:
    """What makes two spec.json dicts one sweep: everything, except that an ``.obj`` stone is known by its
    contents (``config["stone_sha256"]``), not by the path it was read from (a shard on another machine, or a
    resume from another folder, reads the same file at another path)."""
    config = spec.get("config")
    if not (isinstance(config, dict) and "stone_sha256" in config):
        return spec
    return {**{k: v for k, v in spec.items() if k != "stone"},
            "config": {k: v for k, v in config.items() if k != "stone"}}


def sweep_id(spec: SweepSpec) -> str:
    """The SHA-256 (hex) of what makes ``spec`` one sweep (as a folder's spec.json is compared: :func:`_identity`, so
    not an ``.obj`` stone's path): every chunk file records it as ``"sweep"``, so that a chunk of another sweep put
    in a folder is refused. Numbers are hashed as the comparison sees them (``-0.0`` as ``0.0``, ``1`` as ``1.0``:
    a spin of -0 resumed with 0 was refused, a review), and a setting of :data:`SPEC_ADDED` at its value from before
    it was recorded is left out, so that chunks written now still belong to their sweep once a later setting is
    added."""
    identity = _identity(spec.to_dict())
    for key, old in SPEC_ADDED.items():
        if identity.get(key) == old:
            identity = {k: v for k, v in identity.items() if k != key}
        config = identity.get("config")
        if isinstance(config, dict) and config.get(key) == old:
            identity = {**identity, "config": {k: v for k, v in config.items() if k != key}}
    return hashlib.sha256(json.dumps(_plain_numbers(identity), sort_keys=True).encode()).hexdigest()


def _plain_numbers(value):
    """``value`` (JSON-ready) with every number as a float and ``-0.0`` as ``0.0``: what ``==`` does not tell apart,
    written alike."""
    if isinstance(value, dict):
        return {k: _plain_numbers(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain_numbers(v) for v in value]
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value) + 0.0
    return value


def _spec_difference(old: dict, new: dict) -> str:
    """How a folder's spec.json ``old`` differs from ``new``: the keys, and what ``old`` has there."""
    held_old = old   # (what it holds is shown as written: an .obj stone by its path, not the None of _identity)
    old, new = _identity(old), _identity(new)
    keys = sorted(k for k in old.keys() | new.keys() if old.get(k) != new.get(k))
    # (what it holds: the resolved configuration's values, then the sweep's own that are not in it)
    config = {k: held_old.get("config", {}).get(k, v) for k, v in sorted(old.get("config", {}).items())
              if new.get("config", {}).get(k) != v}
    held = [f"{k}={_shown(v)}" for k, v in config.items()]
    held += [f"{k}={_shown(held_old.get(k))}" for k in keys if k != "config" and k not in config]
    return f"its spec.json differs in {', '.join(keys)}: it has {', '.join(held)}"


def _check_spec_file(out: Path, spec: SweepSpec, remedy: str = RESUME_REMEDY) -> None:
    """``out/spec.json`` pins the sweep a folder belongs to: resuming another sweep there is refused
    (``remedy``: what the message advises). Writes it (creating ``out``, not its parents:
    :func:`_out_folder` checked them) if missing; chunk files without one are refused (they cannot be
    checked against this sweep)."""
    path = out / "spec.json"
    text = json.dumps(spec.to_dict(), sort_keys=True, indent=1)
    if not path.exists():
        if out.is_dir() and any(p.is_file() for p in out.glob("chunk-*.json")):
            raise ParameterError(f"out_dir {str(out)!r} holds chunk files but no spec.json, so nothing says which sweep "
                                 "they belong to: use a new folder (or delete this whole folder)")
        # (a folder of the user's own result.json or result.csv was written over in silence; a review)
        mine = [n for n in ("result.json", "result.csv") if (out / n).exists()]
        if mine:
            raise ParameterError(f"out_dir {str(out)!r} holds {' and '.join(mine)} but no spec.json: not a sweep's "
                                 "folder, and the sweep would write over them; use a new folder")
        if _write_new(path, text):
            return
        # (another run created it meanwhile: this one must be the same sweep)
    old, new = _read_spec(path), json.loads(text)
    _spec_from_json(path, old)  # a damaged spec.json ({}, text for tilts) is named as damaged, not as another sweep
    if _identity(old) != _identity(new):
        was, now = (d.get("config", {}).get("precision") for d in (old, new))
        if was != now and was in ("float64", "float32"):
            raise ParameterError(f"out_dir {str(out)!r} holds a sweep computed in {was}, and this process computes "
                                 f"in {now}: resume it in {was} (jax.config.update('jax_enable_x64', "
                                 f"{was == 'float64'}) before any JAX work; the CLI computes in float64), "
                                 "or use a new folder")
        raise ParameterError(f"out_dir {str(out)!r} holds a different sweep ({_spec_difference(old, new)}); {remedy}")


def _samples(name: str, values, what: str, missing: bool) -> list:
    """``values`` (a 1-D sequence of numbers; ``missing``: None allowed) as a list of floats (or None);
    anything else (text, a number alone, nested lists, booleans) is refused naming ``name``."""
    def bad():
        return ParameterError(f"parabola_minimum: {name} must be a 1-D sequence of {what}, got {repr(values)[:80]}")

    if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
        raise bad()
    try:
        items = list(values)
    except TypeError:  # a 0-d array
        raise bad() from None
    out = []
    for v in items:
        if v is None and missing:
            out.append(None)
            continue
        if isinstance(v, numbers.Real) and not isinstance(v, bool):
            v = float(v)
        else:  # a 0-d array of a real type (NumPy, JAX); not text, booleans or nested sequences
            try:
                a = None if isinstance(v, (str, bytes)) else np.asarray(v)
            except (TypeError, ValueError):
                a = None
            if a is None or a.ndim != 0 or a.dtype.kind not in "iuf":
                raise bad()
            v = float(a)
        if not missing and not math.isfinite(v):
            raise bad()
        out.append(v)
    return out


def parabola_minimum(x, y):
    r"""Minimum of sampled values between the samples: ``(x*, y*)`` or ``(None, None)``.

    ``x`` (N,) sample positions (any order, e.g. tilts [deg]); ``y`` (N,) values (``None`` or
    NaN where missing, e.g. no bounce). Takes the lowest sample and its neighbours in ``x`` and
    returns the vertex of the parabola through the three points,

    .. math:: x^* = x_1 - \frac12\,\frac{(x_1-x_0)^2 (y_1-y_2) - (x_1-x_2)^2 (y_1-y_0)}
                                     {(x_1-x_0)(y_1-y_2) - (x_1-x_2)(y_1-y_0)},

    which lies between the neighbours and is exact for a quadratic. ``(None, None)`` when the
    lowest sample is at either end of the samples or next to a missing value (the minimum may
    lie outside: widen the sweep). Of equal lowest samples the first counts; of samples at the
    same position, the first.

    Examples
    --------
    >>> x, y = parabola_minimum([10.0, 12.0, 15.0, 20.0], [(t - 13.0) ** 2 + 1.0 for t in (10, 12, 15, 20)])
    >>> round(x, 12), round(y, 12)
    (13.0, 1.0)
    """
    x = _samples("x", x, "finite real numbers (sample positions, e.g. tilts [deg])", missing=False)
    y = _samples("y", y, "real numbers or None (missing)", missing=True)
    if len(x) != len(y):
        raise ParameterError(f"parabola_minimum: x and y must have the same length, got {len(x)} and {len(y)}")
    pts = sorted(((a, None if b is None or not math.isfinite(b) else b) for a, b in zip(x, y)), key=lambda p: p[0])
    pts = [p for k, p in enumerate(pts) if k == 0 or p[0] != pts[k - 1][0]]  # a repeated position: its first
    finite = [i for i, (_, v) in enumerate(pts) if v is not None]
    if not finite:
        return None, None
    i = min(finite, key=lambda j: pts[j][1])
    if i == 0 or i == len(pts) - 1 or pts[i - 1][1] is None or pts[i + 1][1] is None:
        return None, None
    (x0, y0), (x1, y1), (x2, y2) = pts[i - 1], pts[i], pts[i + 1]
    den = (x1 - x0) * (y1 - y2) - (x1 - x2) * (y1 - y0)   # < 0: the first lowest sample is below its left
    xs = x1 - 0.5 * ((x1 - x0) ** 2 * (y1 - y2) - (x1 - x2) ** 2 * (y1 - y0)) / den
    # Lagrange form of the same parabola, evaluated at its vertex.
    ys = (y0 * (xs - x1) * (xs - x2) / ((x0 - x1) * (x0 - x2))
          + y1 * (xs - x0) * (xs - x2) / ((x1 - x0) * (x1 - x2))
          + y2 * (xs - x0) * (xs - x1) / ((x2 - x0) * (x2 - x1)))
    return float(xs), float(ys)


def assemble(spec: SweepSpec, chunks: list[dict]) -> dict:
    """Join chunk results (in chunk order) into the sweep's result dictionary.

    Both kinds hold ``spec`` (:meth:`SweepSpec.to_dict`). A domain sweep's result: ``bounces``
    (n_tilts, n_attacks) [-] (nested lists, tilt first); ``first_contact_time`` (n_tilts, n_attacks): the
    *duration* of the first contact [s], from its first wet triangle to the time its last wet triangle left
    the water (not when the contact happened; None where there was none or it never ended in a bounce).

    A U_min sweep's result: ``umin`` per tilt [m/s] (None: no bounce at any speed thrown, the bracket's
    ends and the :data:`SCAN_SPEEDS` between them), ``best_tilt`` [deg] / ``best_umin`` [m/s] the lowest
    grid point (on a tie, the smallest of the tied tilts), ``tied_tilts`` [deg] the grid points that share that
    lowest ``umin`` when more than one does (a tie: no single minimum at this resolution; else empty), ``best_tilt_fit`` /
    ``best_umin_fit`` the minimum between grid points (:func:`parabola_minimum`; None at the
    sweep's edge, at a tie, and when any tilt bounces at the bracket's low end), ``resolution`` the width
    of the bisection's final bracket [m/s]. Each ``umin`` is
    that bracket's top (a speed that bounces), so the true minimal speed lies in
    ``(umin - resolution, umin]``; where the bracket's low end already bounces
    (``bounces_at_low`` > 0), ``umin`` is that low end and the true value lies at or below it.
    ``monotone``: 1 per tilt where every speed of the scan faster than one that bounced bounced too, 0 where
    one did not (a free stone flipping at speed): that tilt's ``umin`` is the lowest speed that bounces,
    bisected in the scan's first interval in which the count turns from 0 (module docstring).

    ``diverged``: throws whose integration failed (outcome ``"diverged"``: the contact step is too long for
    the stone and throw): for a domain sweep 1 or 0 per grid point, (n_tilts, n_attacks), whose count then
    means nothing; for a U_min sweep the number of the tilt's throws (its scan's and its bisection's) that diverged, and such a
    tilt's ``umin`` is None (a bisection step was taken on a count that means nothing).

    ``cut_off``: throws still in play when the run stopped them at ``duration`` or ``max_steps``: for a
    domain sweep 1 or 0 per grid point, whose count is then a lower bound; for a U_min sweep the number of
    the tilt's throws (its scan's and its bisection's) stopped before their first bounce, and such a tilt's ``umin`` is None
    (whether that throw bounces is unknown).
    """
    def cat(key):
        return [v for c in chunks for v in c[key]]

    result = {"spec": spec.to_dict()}
    if spec.kind == "domain":
        b = np.asarray(cat("bounces")).reshape(len(spec.tilts), len(spec.attacks))
        result.update(bounces=b.tolist(), first_contact_time=np.asarray(
            cat("first_contact_time"), dtype=object).reshape(b.shape).tolist(),
            diverged=np.asarray(cat("diverged")).reshape(b.shape).tolist(),
            cut_off=np.asarray(cat("cut_off")).reshape(b.shape).tolist())
    else:
        umin = cat("umin")
        finite = [(u, t) for u, t in zip(umin, spec.tilts) if u is not None]
        best = min(finite) if finite else (None, None)
        at_low = cat("bounces_at_low")
        # Where the bracket's low end bounces, umin is only a bound (the true value is at or below it), and
        # the true minimum lies at such a tilt: no parabola through bounds.
        # Equal answers at several grid points (a coarse bracket): no single minimum, and no parabola either
        # (the CLI, the JSON and the plot said three things: a tie, the first of them, and a fitted vertex)
        tied = [t for u, t, n in zip(umin, spec.tilts, at_low) if u is not None and u == best[0] and not n]
        tied = tied if len(tied) > 1 and best[0] > spec.speed_range[0] else []
        fit = ((None, None) if any(n > 0 for n in at_low) or tied
               else parabola_minimum(spec.tilts, umin))
        result.update(umin=umin, bounces_at_high=cat("bounces_at_high"), bounces_at_low=at_low, diverged=cat("diverged"),
                      cut_off=cat("cut_off"), monotone=cat("monotone"), tied_tilts=tied,
                      best_tilt=best[1], best_umin=best[0], best_tilt_fit=fit[0], best_umin_fit=fit[1],
                      resolution=umin_resolution(spec.speed_range, spec.iterations))
    return result


def write_results(result: dict, out: Path) -> None:
    """``result.json`` (everything) and ``result.csv`` (one row per tilt, or per tilt and attack), in the folder
    ``out`` (a path, ``str`` or ``os.PathLike``)."""
    out = Path(out)   # (a str met a raw TypeError at out / "result.json")
    spec = result["spec"]
    _write_atomic(out / "result.json", json.dumps(result, sort_keys=True, indent=1))
    rows = []
    if spec["kind"] == "domain":
        rows.append(["tilt_deg", "attack_deg", "speed_m_s", "spin_rev_s", "bounces", "first_contact_time_s", "diverged",
                     "cut_off"])
        for i, t in enumerate(spec["tilts"]):
            for k, a in enumerate(spec["attacks"]):
                tc = result["first_contact_time"][i][k]
                rows.append([t, a, spec["speed"], spec["spin"], result["bounces"][i][k], "" if tc is None else tc,
                             result["diverged"][i][k], result["cut_off"][i][k]])
    else:
        # bounces_at_low > 0: the bracket's low end bounces already, umin_m_s is only an upper bound (no low end);
        # else the true U_min lies in (umin_low_m_s, umin_m_s] (the file alone did not say: a review)
        # (the new column last: a script reading columns by position reads them as before)
        rows.append(["tilt_deg", "attack_deg", "spin_rev_s", "umin_m_s", "bounces_at_high", "bounces_at_low",
                     "diverged", "cut_off", "monotone", "umin_low_m_s"])
        for i, t in enumerate(spec["tilts"]):
            u = result["umin"][i]
            low = "" if u is None or result["bounces_at_low"][i] else u - result["resolution"]
            rows.append([t, spec["attacks"][0], spec["spin"], "" if u is None else u, result["bounces_at_high"][i],
                         result["bounces_at_low"][i], result["diverged"][i],
                         result["cut_off"][i], result["monotone"][i], low])
    from io import StringIO

    buf = StringIO()
    csv.writer(buf, lineterminator="\n").writerows(rows)
    _write_atomic(out / "result.csv", buf.getvalue())


def _spec_from_json(path: Path, data: dict) -> SweepSpec:
    """The :class:`SweepSpec` a folder's spec.json (``data``, read from ``path``) describes."""
    names = {f.name for f in dataclasses.fields(SweepSpec)}
    if set(data) != names:
        if set(data) == names - {"config"}:
            raise ParameterError(f"{str(path.parent)!r} holds a sweep of an older jaxskip (its spec.json lacks the "
                                 "simulation configuration): run it again")
        raise ParameterError(f"{str(path)!r} is damaged (its keys are not a sweep's); {SPEC_REMEDY}")
    spec = SweepSpec(**{k: (tuple(v) if isinstance(v, list) else v) for k, v in data.items()})
    all_numbers = lambda v: all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v)  # noqa: E731
    is_int = lambda v, low, high: isinstance(v, int) and not isinstance(v, bool) and low <= v <= high  # noqa: E731
    span = spec.speed_range
    if (spec.kind not in ("domain", "umin") or not spec.tilts or not all_numbers(spec.tilts) or not spec.attacks
            or not all_numbers(spec.attacks) or not is_int(spec.chunk_size, 1, math.inf)
            # (a null iterations, say, ended merge in a TypeError traceback)
            or not is_int(spec.iterations, 1, MAX_BISECTIONS) or not all_numbers((spec.speed, spec.spin))
            or not isinstance(span, tuple) or len(span) != 2 or not all_numbers(span) or not 0 < span[0] < span[1]):
        raise ParameterError(f"{str(path)!r} is damaged (its kind, tilts, attacks, speeds, spin, iterations or "
                             f"chunk_size are not a sweep's); {SPEC_REMEDY}")
    return spec


def merge(folders, out_dir) -> dict:
    """Join the chunk files of several shards' folders (same sweep) into ``out_dir``'s result.

    ``folders``: a non-empty list (any iterable) of sweep folders, each a ``str`` or ``os.PathLike``, or
    one such path alone: the ``out_dir`` of each shard's :func:`run_sweep`. Each must hold a ``spec.json``, all the same
    sweep's; together they must hold every chunk (a chunk found in several folders is taken once, when its
    copies agree; copies that differ are refused, naming both). ``out_dir``: the folder that receives the chunks, ``result.json`` and ``result.csv`` (it may
    be one of ``folders``). Returns the assembled result (:func:`assemble`).

    ``out_dir`` is created if missing (its parent must exist, as for :func:`run_sweep`). Every chunk file
    read is checked as :func:`run_sweep` checks it: a damaged one (or a damaged spec.json) raises
    :class:`~jaxskip.ParameterError` naming the file.
    """
    if isinstance(folders, (str, bytes, os.PathLike)):
        folders = [folders]  # one folder (iterating a str would give its characters)
    try:
        folders = [Path(os.fsdecode(f)) for f in folders]
    except TypeError:
        raise ParameterError(f"folders must be a path or a list of paths, got {type(folders).__name__}") from None
    if not folders:
        raise ParameterError("merge needs at least one folder")
    out = _out_folder(out_dir)
    specs = []
    for f in folders:
        if not (f / "spec.json").exists():
            raise ParameterError(f"{str(f)!r} is not a sweep folder (no spec.json)")
        specs.append(_read_spec(f / "spec.json"))
    for f, s in zip(folders, specs):
        if _identity(s) != _identity(specs[0]):
            raise ParameterError(f"the folders hold different sweeps: {str(f)!r} is not the sweep of "
                                 f"{str(folders[0])!r} ({_spec_difference(s, specs[0])})")
    spec = _spec_from_json(folders[0] / "spec.json", specs[0])
    chunks = _chunks(spec)
    found, source = {}, {}
    for f in folders:
        for j, index in enumerate(chunks):
            p = f / f"chunk-{j:05d}.json"
            if not p.exists():
                continue
            data = _load_chunk(p, spec, j, index, f"delete it and run the sweep again in {str(f)!r} (the shard that "
                               "computes that chunk), then merge")
            if j not in found:
                found[j], source[j] = data, p
            elif _chunk_values(data) != _chunk_values(found[j]):
                # (the first copy was taken in silence; a review) Machines of other kinds may round differently.
                raise ParameterError(f"{str(source[j])!r} and {str(p)!r} are two copies of chunk {j} that differ (two "
                                     "shards computed it, on machines or versions that round differently?): delete "
                                     "the one you do not trust, then merge")
    missing = [j for j in range(len(chunks)) if j not in found]
    if missing:
        raise ParameterError(f"chunks missing from every folder: {missing[:10]}{' ...' if len(missing) > 10 else ''}"
                             " (run the shards that compute them)")
    _check_spec_file(out, spec, "merge into a new folder (or into one of the shards' own)")
    for j, data in found.items():
        p = out / f"chunk-{j:05d}.json"
        if p.exists():  # what the folder holds is what its result says (a re-run there reads it)
            held = _load_chunk(p, spec, j, chunks[j], "delete it and merge again")
            if _chunk_values(held) != _chunk_values(data):   # (replaced the shards' copy unchecked; a review)
                raise ParameterError(f"{str(source[j])!r} and {str(p)!r} are two copies of chunk {j} that differ: "
                                     "delete the one you do not trust, then merge")
            found[j] = held
        else:
            _write_atomic(p, json.dumps(data, sort_keys=True))
    merged = [found[j] for j in range(len(chunks))]
    # the shards warned of their own throws; the merge warns once of all of them (its limits are the spec's)
    limits = SimConfig(dt=spec.config["dt"], duration=spec.config["duration"], max_steps=spec.config["max_steps"])
    _warn_diverged(spec, merged, limits)
    _warn_cut_off(spec, merged, limits)
    _warn_not_monotone(spec, merged)
    result = assemble(spec, merged)
    write_results(result, out)
    return result


def bracket_digits(resolution: float) -> int:
    """Decimals [-] that show a bisection bracket of ``resolution`` [m/s] as two different numbers
    (at least 2): the true U_min lies in ``(U - resolution, U]``."""
    return max(2, 1 - math.floor(math.log10(resolution))) if resolution > 0 else 2


def _umin_panel(ax, result: dict) -> None:
    """U_min(tilt): each bisection's bracket (U - resolution, U] as an error bar below its top U."""
    spec = result["spec"]
    low, high = spec["speed_range"]
    tilts = np.asarray(spec["tilts"], dtype=float)
    u = np.array([np.nan if v is None else v for v in result["umin"]], dtype=float)
    at_low = np.asarray(result.get("bounces_at_low") or [0] * len(u)) > 0
    res = result.get("resolution")
    if res is None:
        res = umin_resolution((low, high), spec["iterations"])
    bracketed = np.isfinite(u) & ~at_low
    # the line joins measured values only: an upper bound (bounces at the bracket's low end) joined to them drew a
    # slope that was never measured (a review)
    order = np.argsort(tilts, kind="stable")
    ax.plot(tilts[order], np.where(bracketed, u, np.nan)[order], "-", color="C0", lw=1, alpha=0.6)
    bars = None
    if bracketed.any():
        k = int(bracketed.sum())
        bars = ax.errorbar(tilts[bracketed], u[bracketed], yerr=[np.full(k, res), np.zeros(k)], fmt="o",
                           color="C0", ms=5, capsize=3,
                           label=f"{spec['stone']}, {spec['attitude']} attitude: bisection bracket, "
                                 f"true U_min in (U − {res:.3g}, U] m/s")
    if at_low.any():
        ax.plot(tilts[at_low], u[at_low], "v", color="C0", ms=7, mfc="none",
                label=f"bounces at the bracket's low end: U_min ≤ {low:g} m/s")
    # a tilt without U_min: no bounce up to the bracket's top, or unknown (its bisection met a throw that
    # diverged, or one the duration or step limit stopped before its first bounce)
    failed = np.asarray(result.get("diverged") or [0] * len(u)) > 0
    cut = (np.asarray(result.get("cut_off") or [0] * len(u)) > 0) & ~failed
    none = np.isnan(u) & ~failed & ~cut
    for where, marker, label in ((none, "x", f"no bounce at the {SCAN_SPEEDS + 2} speeds thrown up to {high:g} m/s"),
                                 (failed & np.isnan(u), "X", "no U_min: a bisection throw diverged (take a smaller dt)"),
                                 (cut & np.isnan(u), "^", "no U_min: a bisection throw was still in play at the "
                                                         "duration or step limit (raise it)")):
        if where.any():
            ax.plot(tilts[where], np.full(int(where.sum()), high), marker, color="gray", mfc="none", label=label)
    if result.get("best_tilt") is not None:
        u0 = result["best_umin"]
        d = bracket_digits(res)
        where = (f"U_min ≤ {u0:.2f} m/s" if u0 <= low else f"U_min in ({u0 - res:.{d}f}, {u0:.{d}f}] m/s")
        tied = result.get("tied_tilts") or []
        if tied:   # no single minimum: every tied grid point marked, none named the magic angle
            for k, t in enumerate(tied):
                ax.axvline(t, color="C3", lw=0.8, ls="--",
                           label=(f"no single minimum: {', '.join(f'{x:g}' for x in tied)}° tie, {where}" if k == 0
                                  else None))
        else:
            ax.axvline(result["best_tilt"], color="C3", lw=0.8, ls="--",
                       label=f"lowest grid point: {result['best_tilt']:g}°, {where}")
    rough = np.asarray(result.get("monotone") or [1] * len(u)) == 0
    if (rough & np.isfinite(u)).any():
        ax.plot(tilts[rough & np.isfinite(u)], u[rough & np.isfinite(u)], "o", color="C1", ms=9, mfc="none",
                label="a faster throw failed to bounce here: the lowest bouncing speed of a scan, bisected")
    if result.get("best_tilt_fit") is not None:
        ax.plot([result["best_tilt_fit"]], [result["best_umin_fit"]], "*", color="C3", ms=10,
                label=f"between grid points (parabola): "
                      f"{result['best_umin_fit']:.{bracket_digits(res)}f} m/s at "
                      f"{result['best_tilt_fit']:.1f}°")
    ax.set_xlabel("tilt α [deg]")
    ax.set_ylabel("minimal speed for a bounce U_min [m/s]")
    held = " (inert with the tilt held)" if spec.get("attitude") == "fixed" else ""
    ax.set_title(f"U_min(α) at attack {spec['attacks'][0]:g}° at release, spin {spec['spin']:g} rev/s{held}",
                 fontsize=10)
    handles, labels = ax.get_legend_handles_labels()
    order = sorted(range(len(handles)), key=lambda i: handles[i] is not bars)  # the error bars first
    ax.legend([handles[i] for i in order], [labels[i] for i in order], fontsize=8, loc="upper center",
              bbox_to_anchor=(0.5, -0.14), ncol=1, frameon=False)


def _cell_edges(values: np.ndarray) -> np.ndarray:
    """Edges [deg] of the cells centred on sorted grid ``values`` (n,) -> (n + 1,): halfway between
    neighbours, the outer ones as far out as the inner ones; a single value gets a cell 2 deg wide.

    >>> _cell_edges(np.array([10.0, 20.0, 40.0])).tolist(), _cell_edges(np.array([15.0])).tolist()
    ([5.0, 15.0, 30.0, 50.0], [14.0, 16.0])
    """
    if values.size == 1:
        return np.array([values[0] - 1.0, values[0] + 1.0])
    mid = 0.5 * (values[1:] + values[:-1])
    return np.concatenate([[2 * values[0] - mid[0]], mid, [2 * values[-1] - mid[-1]]])


def _domain_panel(fig, ax, result: dict) -> None:
    """Bounce counts on the (tilt, attack) grid, tilt on x as in the U_min panel and the magic-angle
    notebook, the edge of the bouncing region outlined."""
    from matplotlib.lines import Line2D
    from matplotlib.ticker import MaxNLocator

    spec = result["spec"]
    b = np.asarray(result["bounces"], dtype=float)
    top = int(np.nanmax(b)) if b.size and np.isfinite(b).any() else 0
    # Cells drawn between explicit edges, in increasing order: with one tilt or one attack, shading="nearest"
    # has no spacing to size a cell by and drew nothing (empty axes beside a colour bar).
    t_order, a_order = np.argsort(spec["tilts"]), np.argsort(spec["attacks"])
    tilts, attacks = np.asarray(spec["tilts"], dtype=float)[t_order], np.asarray(spec["attacks"], dtype=float)[a_order]
    t_edges, a_edges = _cell_edges(tilts), _cell_edges(attacks)
    cells = b[np.ix_(t_order, a_order)].T
    if top <= 20:  # a colour per count, each centred on its integer tick
        from matplotlib import colormaps

        mesh = ax.pcolormesh(t_edges, a_edges, cells, shading="flat",
                             cmap=colormaps["viridis"].resampled(top + 1), vmin=-0.5, vmax=top + 0.5)
    else:
        mesh = ax.pcolormesh(t_edges, a_edges, cells, shading="flat", cmap="viridis")
    cbar = fig.colorbar(mesh, ax=ax, label="true bounce count [bounces]")
    if top <= 20:   # whole counts only (with every count 0 the bar ran from -0.5 to 0.5 in tenths)
        cbar.set_ticks(np.arange(0, top + 1, max(1, math.ceil((top + 1) / 11))))
    else:
        cbar.ax.yaxis.set_major_locator(MaxNLocator(integer=True))
    handles = []
    if min(b.shape) >= 2 and (b > 0).any() and (b == 0).any():
        ax.contour(tilts, attacks, (cells > 0).astype(float), levels=[0.5], colors="C3", linewidths=1.5)
        handles.append(Line2D([], [], color="C3", lw=1.5,
                              label="edge of the bounce domain (≥ 1 bounce), halfway between grid points"))
    failed = np.asarray(result.get("diverged") or np.zeros(b.shape), dtype=bool)
    if failed.any():
        ti, ai = np.nonzero(failed)
        ax.plot(np.asarray(spec["tilts"])[ti], np.asarray(spec["attacks"])[ai], "x", color="w", mec="k", ms=7)
        handles.append(Line2D([], [], ls="", marker="x", color="k", ms=7,
                              label="diverged (the contact step is too long): its count means nothing"))
    cut = np.asarray(result.get("cut_off") or np.zeros(b.shape), dtype=bool)
    if cut.any():
        ti, ai = np.nonzero(cut)
        ax.plot(np.asarray(spec["tilts"])[ti], np.asarray(spec["attacks"])[ai], "^", color="w", mec="k", ms=6)
        handles.append(Line2D([], [], ls="", marker="^", color="w", mec="k", ms=6,
                              label="still skipping at the duration or step limit: its count is a lower bound"))
    if handles:
        ax.legend(handles=handles, fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), frameon=False)
    ax.set_xlabel("tilt α [deg]")
    ax.set_ylabel("attack at release [deg]")
    ax.set_title(f"bounce domain at speed {spec['speed']:g} m/s, spin {spec['spin']:g} rev/s ({spec['stone']}, "
                 f"{spec['attitude']} attitude)", fontsize=10)


def _sweep_figure(result: dict):
    """The figure :func:`plot_sweep` saves (a :class:`matplotlib.figure.Figure`, no pyplot state)."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(6.8, 5.2), layout="constrained")
    ax = fig.subplots()
    if result["spec"]["kind"] == "umin":
        _umin_panel(ax, result)
    else:
        _domain_panel(fig, ax, result)
    return fig


def plot_sweep(result: dict, path) -> None:
    """Save a picture of a sweep to ``path`` (its suffix picks the format: .png, .pdf, .svg or another
    matplotlib writes; a path without one is refused): U_min(tilt), each bisection's bracket
    ``(U - resolution, U]`` drawn as an error bar below its top U; or the bounce domain in the (tilt,
    attack) plane.

    ``result``: a sweep result dict as :func:`run_sweep` or :func:`merge` return it (or its
    ``result.json``); anything else is refused with :class:`~jaxskip.ParameterError`."""
    _check_sweep_result(result)
    check_picture_path("path", path)
    with writing(path):
        _sweep_figure(result).savefig(path, dpi=120)


def _check_sweep_result(result) -> None:
    """Refuse what is not a sweep result dict: a ``"spec"`` dict of a known kind with the settings the
    picture reads, and that kind's values (``"umin"`` or ``"bounces"``)."""
    spec = result.get("spec") if isinstance(result, dict) else None
    kind = spec.get("kind") if isinstance(spec, dict) else None
    values = {"umin": "umin", "domain": "bounces"}.get(kind)
    settings = ("tilts", "attacks", "spin", "stone", "attitude") + (
        ("speed_range", "iterations") if kind == "umin" else ("speed",))
    if values is None or values not in result or any(k not in spec for k in settings):
        what = f"a dict with keys {list(result)[:8]}" if isinstance(result, dict) else type(result).__name__
        raise ParameterError(f"result must be a sweep result dict as returned by run_sweep/merge (with its 'spec'), "
                             f"got {what}")
