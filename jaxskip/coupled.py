r"""Stone and height field, two-way coupled, in one pure step.

The stone sees the water it has disturbed, and the water feels the stone:

* **Water on stone.** Immersion is clipped against the local surface, read
  bilinearly from the height field under every vertex (:func:`jaxskip.water.height_at`),
  not against z = 0; the gap and the bounce test use the same surface.
* **Stone on water.** Each immersed triangle's force on the stone :math:`F_i`
  acts back on the water: its vertical part :math:`F_{i,z}` is spread
  bilinearly (:func:`jaxskip.water.deposit`) over the columns under the
  triangle's immersed centroid as an external pressure :math:`F_{i,z}/l^2`
  (seed paper §3: forces become external pressure on the volume model).
  Pressure moves water but never creates or destroys it, so the coupling
  conserves the water's volume (re-centring the window, below, does not: columns
  leave it behind the stone and still ones come in). The horizontal (friction) part is not passed on.

Scene-sized water ("model no more than the scene needs")
--------------------------------------------------------
A lake is huge; a contact patch is a few stone widths. The water here is a
window of ``grid.shape`` columns that follows the stone: before each step it
is re-centred, by whole columns, on the stone's centre of mass (the arrays are
shifted; columns entering the window are still water). Its border is a sponge
(``WaterGrid(boundary="sponge")``) so ripples leave rather than reflect. A long
hop (the default throw's first: 0.72 m, ~7 stone widths, 0.1 s) outruns the ripples,
which travel at :math:`\sqrt{gH}` (~0.5 m/s), and meets still water; short hops do
not: the default throw's 17 later flights cover under half a stone width in 1-7 ms,
so the stone lands in its own wake, which the window (centred on the stone, ~6
stone diameters wide) holds.

Time steps (multirate)
----------------------
The stone steps ``dt_s`` (the fine ``SimConfig.dt`` = 0.25 ms in contact, longer
conservative-advancement jumps in the air); the water steps once the stone's
steps since its last one add up to ``water_dt`` (default 1 ms, a tenth of a
contact; to within half a fine step, so that round-off in float32 cannot add a step),
with the stone's pressure averaged over them — four stone steps per
water step in contact. A water step never exceeds the grid's stable step (``grid.time_step``, a
fraction of :func:`jaxskip.water.stable_dt`): a stone step longer than that (a coarse
``SimConfig.dt``) is covered by :math:`\lceil dt_s / \text{time\_step} \rceil` water
substeps (as is the up to half a fine step by which a water step's due time overshoots
``water_dt``), so the water keeps the stone's time; only after a flight jump longer than
those substeps together does the water advance by less than the jump (the ripples
left behind lag; they are out of the stone's way). The window is re-centred at each
water step. A flight jump aims above the highest water it can reach (:func:`reach_ceiling`: the highest column
under the box the stone's footprint sweeps in ``max_flight_step``, less the depth, passed to
``make_step(ceiling=...)``): it ends before the stone's lowest vertex can come down to any crest of the water
as it stands at the jump's start, so the fine steps resolve the touches of the water (the water moves only after
the jump, by at most ``substeps * grid.time_step``: a crest can rise meanwhile, measured by up to 0.37 mm after a
jump, with no jump ending inside it in 4 throws checked step by step). Until 2026-12-07 (stop 46)
a jump took the surface under the stone at its start as the one it would meet and stepped over brief touches of
the crests of the stone's own wake (each a contact of ~1-9 ms just after a hop), which fixed steps count: with
the tilt held (no spin shortens the jumps) 24 random throws (seed 1: 4-10 m/s, tilt 8-30°, attack 2-15°, 0-20
rev/s) counted as fixed steps on 15 (up to 8 fewer bounces: 16 / 8, 17 / 10), now on 20 and never more than 2
apart; free, 17 of 24 either way (the differences at the level of halving dt). Fixed steps / jumps, bounces,
float64, 64² window: the default throw 13 / 13 at dt = 0.25 ms and 15 / 15 at 0.125 ms (over 1.737 / 1.762 m, re-measured
by a review at stop 48; 15 / 16 at stop 46, 14 jumps before);
6 m/s, 15°, 10°, 10 rev/s: 7 / 7 and 7 / 6; 10 m/s, 25°, 3°, 30 rev/s: 38 / 38 and 39 / 37 (41 jumps before).
The jumps are shorter for it: the coupled default throw at 128² runs 3.2–3.4× real time against 4.6× before (the
water also steps more in flight, keeping the stone's time). Until stop 47 the bound was the whole window's highest
column, often far behind the stone (the default throw: up to 0.10 m above rest, ~27 columns back; 296 of its 385
dry steps were held under it). The reachable columns' bound (stop 47) takes the default throw in 1216 steps
instead of 1496 at 128² (dry steps 521 → 239; 1352 → 1216 at 64²), the same 13 bounces; held-tilt jumps agree
with fixed steps on 22 of the 24 throws above (21 with the window's bound in the same run), free ones on 20 of 24
either way; but the speed barely moves (3.4–3.6× against 3.1–3.3× real time at 128², alternating runs): the water
advances every 1 ms whatever the stone's steps, and they are the cost.

The default window (:func:`default_window`): 64 × 64 columns of 1 cm
(0.64 m, ~6 stone diameters), effective depth 2 cm — so that
:math:`\sqrt{gH} = 0.44` m/s, near the deep-water phase speed :math:`\sqrt{g\lambda/2\pi}` of
ripples one stone wide (0.40 m/s at :math:`\lambda` = 0.1 m) — a sponge border of 8 columns and the smooth clamp (differentiable).
"""

from __future__ import annotations

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np

from ._docs import document_fields
from .body import RigidStone
from .forces import WaterParams
from .simulate import SimConfig, _check_concrete, _check_rollout_args, _scan, initial_carry, make_step
from ._checks import ParameterError, check_bool, check_int, check_range
from .throw import Throw
from .water import (WaterGrid, WaterState, _check_grid, _check_state, deposit, height_at, make_water_step,
                    still_water, water_substeps)


CLAMP_BLOCKS = (0.32, 0.64)
"""Sides [m] of the blocks, placed around the columns that can run short (under the stone and
in its wake), where the volume clamp's passes run: the smallest that holds them
(:func:`jaxskip.water.make_water_step`'s ``clamp_blocks``), the whole window when none does.
Speed only: the same answer."""


MAX_OFFSET = 1e9
"""Largest distance of the window from the origin that :func:`initial_field` takes, in columns (the offset is
an int32, whose range ends at 2.1e9; 1e9 columns of 1 cm are 10^4 km)."""


def default_window() -> WaterGrid:
    """The default moving water window: 64² columns of 1 cm, depth 2 cm, sponge border, smooth clamp."""
    return WaterGrid(shape=(64, 64), spacing=0.01, depth=0.02, boundary="sponge", sponge_width=8,
                     clamp="smooth")


def _spread(a, passes: int):
    """Smooth a column field with ``passes`` passes of the [1, 2, 1]/4 filter along x and y.

    Applied as one pass of their product, the binomial filter of ``2 passes + 1`` taps, per
    axis (half the kernels of pass after pass). Keeps the total (away from the window's
    border, where the push never is).
    """
    if passes == 0:
        return a
    w = [math.comb(2 * passes, k) / 4.0 ** passes for k in range(2 * passes + 1)]
    nx, ny = a.shape
    b = jnp.pad(a, ((passes, passes), (0, 0)))
    a = sum(wk * b[k:k + nx, :] for k, wk in enumerate(w))
    b = jnp.pad(a, ((0, 0), (passes, passes)))
    return sum(wk * b[:, k:k + ny] for k, wk in enumerate(w))


def default_water_dt(grid: WaterGrid) -> float:
    """The coupled water's step [s]: 1 ms (a tenth of a contact), or ``grid.time_step`` if shorter.

    ``grid.time_step`` is the grid's own water step: its ``dt`` if given, else ``cfl`` (default 0.5)
    times the stability bound :func:`jaxskip.water.stable_dt` — not the bound itself.

    >>> from jaxskip.water import WaterGrid, stable_dt
    >>> fine = WaterGrid(shape=(16, 16), spacing=0.001, depth=0.02)  # stable_dt 1.96 ms, time_step 0.98 ms
    >>> default_water_dt(fine) == fine.time_step == 0.5 * stable_dt(0.001, 0.02)
    True
    >>> default_water_dt(default_window())  # time_step 9.8 ms
    0.001
    """
    return min(1e-3, _check_grid(grid).time_step)


def _shift(a, d, fill):
    """``a`` moved by ``d`` whole cells (new[i, j] = old[i + d0, j + d1]); uncovered cells get ``fill``."""
    nx, ny = a.shape
    i = jnp.arange(nx) + d[0]
    j = jnp.arange(ny) + d[1]
    ok = ((i >= 0) & (i < nx))[:, None] & ((j >= 0) & (j < ny))[None, :]
    moved = a[jnp.clip(i, 0, nx - 1)][:, jnp.clip(j, 0, ny - 1)]
    return jnp.where(ok, moved, fill)


def _centred_offset(spacing: float, shape: tuple, position):
    """The window offset (2,) int32 [columns] that puts the column (nx // 2, ny // 2) of a window of ``shape``
    columns of ``spacing`` [m] under ``position``'s x and y [m]."""
    nx, ny = shape
    return jnp.round(position[:2] / spacing).astype(jnp.int32) - jnp.array([nx // 2, ny // 2], jnp.int32)


def _check_reach(grid: WaterGrid, position) -> None:
    """A concrete ``position`` (3,) [m] within the window offsets' int32 reach, ±:data:`MAX_OFFSET` columns."""
    far = MAX_OFFSET * grid.spacing
    if not isinstance(position, jax.core.Tracer) and float(jnp.max(jnp.abs(position[:2]))) > far:
        raise ParameterError(f"position's x and y must lie within ±{far:g} m ({MAX_OFFSET:g} columns of "
                             f"{grid.spacing:g} m: the window's offset counts columns in int32), got {position!r}")


def recentre(grid: WaterGrid, water: WaterState, offset, position):
    """Shift the window so the stone at ``position`` (3,) [m] sits at its centre.

    ``grid``: the window's :class:`jaxskip.WaterGrid`; ``water``: its :class:`jaxskip.WaterState` (column heights
    and pipe flows on that grid).

    ``offset`` (2,) int: world index of the window's column (0, 0) (column
    (i, j) is centred at ``(offset + (i, j)) * spacing``). Returns the shifted
    :class:`WaterState` and the new offset.
    """
    _check_grid(grid)
    _check_state(grid, water)   # (another grid's state was shifted in silence, None met a raw AttributeError)
    position = _checked_position(position)    # (a NaN position gave an offset of -4, -4 in silence)
    _check_reach(grid, position)              # (beyond it the int32 offset saturated in silence)
    if isinstance(offset, (list, tuple)):     # ([0, 0] met a raw "Cannot determine dtype")
        offset = np.asarray(offset)
    if jnp.shape(offset) != (2,) or not jnp.issubdtype(jnp.result_type(offset), jnp.integer):
        raise ParameterError(f"offset must be 2 integers (the window's column (0, 0) in world columns), got {offset!r}")
    new = _centred_offset(grid.spacing, grid.shape, position)
    d = new - offset
    zero = jnp.zeros((), water.height.dtype)

    def shift(w):
        return WaterState(height=_shift(w.height, d, grid.depth + zero), qx=_shift(w.qx, d, zero),
                          qy=_shift(w.qy, d, zero), qd=_shift(w.qd, d, zero), qa=_shift(w.qa, d, zero), time=w.time)
    # In contact the stone moves less than a column per water step: most calls shift by nothing.
    return jax.lax.cond(jnp.any(d != 0), shift, lambda w: w, water), new


def advance_field(grid: WaterGrid, water_step, f: "Field", position, spread: int, dt_max: float,
                  substeps: int = 1) -> "Field":
    """Water steps of the coupled window under the stone's pending push, then re-centring.

    ``grid``: the window's :class:`jaxskip.WaterGrid`; ``water_step``: its step, ``make_water_step(grid)`` (a
    pure ``(state, pressure (nx, ny) [Pa], dt [s]) -> state``, :func:`jaxskip.water.make_water_step`).

    ``f.impulse`` [Pa s] was deposited in the window as it stands (``f.offset``), so the water
    steps there, under the averaged pressure ``impulse / pending`` spread by ``spread`` filter
    passes: ``substeps`` (static) equal steps covering ``min(pending, substeps * dt_max)``
    seconds, each at most ``dt_max`` [s]; only then is the window re-centred on the stone at
    ``position`` (3,) [m] (re-centring first would shift the field under a push that stays put:
    the pressure would land a column or two away from the stone). Returns the new
    :class:`Field` with nothing pending. ``spread`` and ``substeps`` are static integers, >= 0 and >= 1.
    """
    # (checked: substeps -3 dropped the push in silence, spread -1 or 2.5 met raw Value/TypeErrors, a WaterState
    # for f a raw AttributeError; a review)
    if not isinstance(f, Field):
        raise ParameterError(f"f must be a jaxskip.coupled.Field (initial_field), got {type(f).__name__}")
    spread = check_int("spread", spread, minimum=0)
    substeps = check_int("substeps", substeps, minimum=1)
    # (nothing pending: no push, and water steps of no time; 0 / 0 was NaN in every column)
    some = f.pending > 0.0
    push = _spread(f.impulse / jnp.where(some, f.pending, 1.0), spread)
    h = jnp.minimum(f.pending, substeps * dt_max) / substeps
    if substeps == 1:
        field = water_step(f.water, push, h)
    else:  # a fixed-length loop: reverse-differentiable
        field = jax.lax.fori_loop(0, substeps, lambda _, w: water_step(w, push, h), f.water)
    field, offset = recentre(grid, field, f.offset, position)
    zero = jnp.zeros_like(f.pending)
    return Field(field, offset, jnp.zeros_like(f.impulse), zero)


def reach_ceiling(grid: WaterGrid, height, origin, position, velocity, radius, duration: float):
    """The highest water [m] above rest that a stone in flight can meet within ``duration`` [s]: the highest of the
    columns :func:`jaxskip.water.height_at` reads anywhere within ``radius`` [m] of the centre's path.

    In flight only gravity acts, so over ``t`` in [0, ``duration``] the centre of mass moves horizontally along
    ``position[:2] + velocity[:2] t`` [m, m/s], and every vertex stays within ``radius`` (the stone's bounding
    radius, :attr:`jaxskip.RigidStone.radius`) of it: its points lie in the box of that segment widened by
    ``radius``. A surface read there is bilinear between the columns next to the point (clamped into the
    window first, each coordinate apart), which lie within one column ``spacing`` of the box clamped to the
    window: the highest of those columns bounds the surface under the stone for the whole jump (a flight jump is
    never longer than ``SimConfig.max_flight_step``, which is ``duration`` here, a number >= 0). ``height``: the
    window's column heights ``(nx, ny)`` [m]; ``origin``: the centre ``(x, y)`` [m] of its column (0, 0), two
    numbers; ``position``, ``velocity``: the stone's (3,) [m], [m/s]; ``radius`` [m] > 0 (a leaf of the stone,
    traced inside the step: not checked). Returns a scalar [m].

    Until stop 47 the bound was the whole window's highest column, often the crest of the wake far behind the
    stone (the default throw: ~27 columns back), which held 296 of its 385 dry steps short.
    """
    s = grid.spacing
    nx, ny = grid.shape
    duration = check_range("duration", duration, 0.0, math.inf, unit="s")
    position, velocity = jnp.asarray(position), jnp.asarray(velocity)
    origin = jnp.asarray(origin, dtype=position.dtype)   # (grid.origin is a tuple; a review)
    p, v = position[:2], velocity[:2]
    lo = jnp.minimum(p, p + v * duration) - radius
    hi = jnp.maximum(p, p + v * duration) + radius
    top = origin + jnp.array([nx - 1.0, ny - 1.0], dtype=position.dtype) * s     # the last column's centre
    lo, hi = jnp.clip(lo, origin, top) - s, jnp.clip(hi, origin, top) + s
    x = origin[0] + jnp.arange(nx, dtype=position.dtype) * s
    y = origin[1] + jnp.arange(ny, dtype=position.dtype) * s
    near = ((x >= lo[0]) & (x <= hi[0]))[:, None] & ((y >= lo[1]) & (y <= hi[1]))[None, :]
    return jnp.max(jnp.where(near, height, -jnp.inf)) - grid.depth


def coupled_substeps(config: SimConfig, grid: WaterGrid, water_dt: float | None = None) -> int:
    """Water steps per advance of the coupled water (:func:`make_coupled_step`): enough equal steps, each
    at most ``grid.time_step``, to cover the time an advance can find pending in contact,
    ``max(config.dt, water_dt + min(config.dt, water_dt) / 2)`` (1 with the defaults). ``water_dt`` [s]
    as in :func:`make_coupled_step`: in (0, ``grid.time_step``], default None (:func:`default_water_dt`)."""
    _check_config(config)
    _check_grid(grid)
    water_dt = default_water_dt(grid) if water_dt is None else check_range(
        "water_dt", water_dt, 0.0, grid.time_step, unit="s", low_open=True)
    return water_substeps(grid, max(config.dt, water_dt + 0.5 * min(config.dt, water_dt)))


def coupled_interval(config: SimConfig, grid: WaterGrid, water_dt: float | None = None) -> float:
    """The stone time [s] between two advances of the coupled water while the stone is in contact
    (:func:`make_coupled_step`): the first whole number of stone steps ``k * config.dt`` that reaches
    ``water_dt`` to within half a step, ``k = max(1, ceil(water_dt / dt - 1/2))`` — ``water_dt`` itself
    when it is a whole number of steps (1 ms with the defaults), ``config.dt`` when that is longer.
    Each advance takes :func:`coupled_substeps` equal water steps. ``water_dt`` as in
    :func:`make_coupled_step`.

    >>> from jaxskip import SimConfig
    >>> coupled_interval(SimConfig(), default_window()), coupled_interval(SimConfig(dt=0.005), default_window())
    (0.001, 0.005)
    """
    _check_config(config)
    _check_grid(grid)
    water_dt = default_water_dt(grid) if water_dt is None else check_range(
        "water_dt", water_dt, 0.0, grid.time_step, unit="s", low_open=True)
    return _interval_steps(config, water_dt) * config.dt


def _interval_steps(config: SimConfig, water_dt: float) -> int:
    """Stone steps of ``config.dt`` between two advances of the water in contact (:func:`coupled_interval`)."""
    return max(1, math.ceil(water_dt / config.dt - 0.5 - 1e-9))


def check_window_fits(grid: WaterGrid, stone: RigidStone, name: str = "grid") -> None:
    """The window must span at least the stone's diameter (``2 * stone.radius``) along each side: under a
    narrower one the push beyond its edge is dropped and the surface read off its edge columns, an
    answer neither flat nor coupled. A traced radius (inside ``jit``) passes unchecked. Raises
    :class:`~jaxskip.ParameterError` naming the window as ``name``."""
    radius = stone.radius
    if isinstance(radius, jax.core.Tracer):
        return
    span = min(grid.shape) * grid.spacing
    if span < 2.0 * float(radius):
        raise ParameterError(f"{name} must be at least as wide as the stone: its window spans {span:g} m "
                             f"({min(grid.shape)} columns of {grid.spacing:g} m), the stone "
                             f"{2.0 * float(radius):.3g} m; take more columns (jaxskip.coupled."
                             "default_window() spans 0.64 m)")


def make_coupled_step(config: SimConfig, grid: WaterGrid, water_dt: float | None = None, two_way: bool = True,
                      spread: int = 2):
    """Return the pure coupled step ``step(carry, stone, water) -> (carry, record)``.

    ``carry = (StoneState, Tracker, Field)``; ``record`` is the stone's
    :class:`jaxskip.Record` (or None). ``grid.origin`` is ignored: the
    window's origin is ``offset * grid.spacing``. ``water_dt`` [s], in (0, ``grid.time_step``]
    (the grid's water step, :func:`default_water_dt`): the water
    steps once the stone steps since its last step add up to this, to within half a
    ``config.dt`` (or half of ``water_dt`` if less; default None:
    ``min(1 ms, grid.time_step)``); the stone's push is averaged over them.
    A water step covers the time pending, up to ``max(dt, water_dt + dt/2)`` in contact, in
    ``ceil(that / time_step)`` equal substeps (one with the defaults), so the water keeps the stone's time
    in contact; after a flight jump longer than those substeps together it falls behind (see the module's
    docs). ``two_way``: True (default) or False; False: the stone does not push the water (one-way: it
    reads a field that stays as it started; from still water this is flat water).
    ``spread``: an integer in [0, 100], passes of a [1, 2, 1]/4 filter over the push before it reaches
    the water (each triangle's force lands on the columns of its centroid; the
    filter spreads it over ~``spread`` columns, a triangle's size, instead of
    exciting the grid's shortest, checkerboard waves). 0: no spreading.
    """
    _check_config(config)
    _check_grid(grid)
    water_dt = default_water_dt(grid) if water_dt is None else check_range(
        "water_dt", water_dt, 0.0, grid.time_step, unit="s", low_open=True)
    check_int("spread", spread, minimum=0, maximum=100)
    two_way = check_bool("two_way", two_way)
    # Water steps are due once the pending time reaches ``due_after`` (below); a contact's fine steps then
    # leave up to water_dt + dt/2 pending (dt: config.dt, if not above water_dt), and a stone step longer
    # than the water's stable step comes whole: substeps cover either, so the water keeps the stone's time
    # in contact (with water_dt near grid.time_step a single step was cut to time_step: 0.9 of every 1 ms
    # was stepped, and the push of the rest dropped).
    substeps = coupled_substeps(config, grid, water_dt)
    water_step = make_water_step(grid, clamp_blocks=tuple(
        tuple(min(n, max(8, math.ceil(side / grid.spacing))) for n in grid.shape) for side in CLAMP_BLOCKS))
    dt_max = grid.time_step
    # Due once the stone's fine steps add up to the k of coupled_interval, tested halfway between k - 1 and k
    # steps: four 0.25 ms steps make 1 ms whatever the round-off of their sum. (A relative tolerance of 1e-9
    # did not: in float32 the time differences carry round-off of ~1e-5 relative, and 90 of the default throw's
    # ~240 contact water steps waited for a fifth stone step, 1.25 ms. Nor did water_dt - dt/2, for a water_dt
    # of k + 1/2 steps: at dt = 0.4 ms that is 0.8 ms, two steps exactly, and round-off made the interval 2 or
    # 3 steps at random.) Never due with nothing pending.
    due_after = (_interval_steps(config, water_dt) - 0.5) * config.dt

    def advance_water(f: Field, position):
        return advance_field(grid, water_step, f, position, spread, dt_max, substeps)

    def step(carry, stone: RigidStone, water: WaterParams):
        state, tr, f = carry
        origin = f.offset.astype(state.position.dtype) * grid.spacing
        surface = lambda x, y: height_at(grid, f.water.height, x, y, origin=origin)  # noqa: E731
        # The step also returns each triangle's force at the start-of-step state: the stone's push. A flight jump
        # aims above the highest column it can reach (bilinear heights never exceed their columns'), worked out here
        # from the water itself, so that no stored bound can fall out of step with it (see "Time steps" above).
        ceiling = reach_ceiling(grid, f.water.height, origin, state.position, state.velocity, stone.radius,
                                config.max_flight_step)
        (state1, tr1), rec, (forces, centroid) = make_step(config, surface, push=True, ceiling=ceiling)(
            (state, tr), stone, water)
        push = forces[:, 2] if two_way else 0.0 * forces[:, 2]
        h = state1.time - state.time          # 0 once the stone is out of play
        # pressure [Pa] = force / column area, times h: the impulse added in place (cost: the points)
        impulse = deposit(grid, centroid[:, 0], centroid[:, 1], push * (h / grid.spacing ** 2), origin=origin,
                          into=f.impulse)
        f = Field(f.water, f.offset, impulse, f.pending + h)
        f = jax.lax.cond(f.pending >= due_after, advance_water, lambda f, _: f, f, state1.position)
        return (state1, tr1, f), rec

    return step


@document_fields
@jax.tree_util.register_dataclass
@dataclasses.dataclass(frozen=True)
class Field:
    """The coupled rollout's water: the window, where it is, and the stone's push not yet applied."""

    water: WaterState
    """The window's height field (:class:`jaxskip.water.WaterState`, arrays ``(nx, ny)`` and pipes)."""
    offset: jax.Array
    """(2,) int32: world index of the window's column (0, 0); column (i, j) is centred at
    ``(offset + (i, j)) * spacing`` [m]."""
    impulse: jax.Array
    """(nx, ny) pressure impulse [Pa s] at column centres, accumulated since the last water step."""
    pending: jax.Array
    """() stone time [s] since the last water step."""


def initial_field(grid: WaterGrid, position) -> Field:
    """Still water in a window centred on ``position`` [m], nothing pending.

    ``position``: the stone's centre of mass, (3,) ``(x, y, z)`` or (2,) ``(x, y)`` [m] (only x and y
    place the window), finite real numbers; a JAX or NumPy float array keeps its dtype (the field's),
    anything else becomes an array of JAX's default float. A traced value (inside ``jit``) is checked
    for its shape and type only. Bad input raises :class:`~jaxskip.ParameterError`.

    >>> f = initial_field(default_window(), [0.1, 0.0, 0.01])
    >>> f.offset.tolist(), f.water.height.shape, float(f.pending)
    ([-22, -32], (64, 64), 0.0)
    """
    _check_grid(grid)
    position = _checked_position(position)
    _check_reach(grid, position)
    dtype = position.dtype
    offset = _centred_offset(grid.spacing, grid.shape, position)
    return Field(still_water(grid, dtype=dtype), offset, jnp.zeros(grid.shape, dtype), jnp.zeros((), dtype))


def check_shared_constants(grid: WaterGrid, water: WaterParams, name: str = "grid") -> None:
    """The grid's ``gravity`` and ``rho`` must equal ``water``'s ``gravity`` and ``rho_water`` (to 1e-6
    relative): the stone and the water it moves share them. A traced value (inside ``jit`` or ``vmap``)
    cannot be compared and is passed over. Raises :class:`~jaxskip.ParameterError` naming both (the grid
    as ``name``).

    >>> from jaxskip import water_params
    >>> check_shared_constants(default_window(), water_params())                # both 9.81 m/s^2, 1000 kg/m^3
    >>> try:
    ...     check_shared_constants(default_window(), water_params(gravity=3.71))  # a Martian stone
    ... except ParameterError as e:
    ...     print(e)
    grid.gravity (9.81 m/s^2) differs from water.gravity (3.71 m/s^2): the stone and the water it moves must share them
    """
    if not isinstance(water, WaterParams):
        raise ParameterError(f"water must be a jaxskip.WaterParams (see jaxskip.water_params), got {type(water).__name__}")
    for mine, theirs, unit in (("gravity", "gravity", "m/s^2"), ("rho", "rho_water", "kg/m^3")):
        value = getattr(water, theirs)
        if isinstance(value, jax.core.Tracer):
            continue
        a, b = float(getattr(grid, mine)), float(np.asarray(value))
        if not math.isclose(a, b, rel_tol=1e-6):
            raise ParameterError(f"{name}.{mine} ({a:g} {unit}) differs from water.{theirs} ({b:g} {unit}): "
                                 "the stone and the water it moves must share them")


def _check_config(config) -> SimConfig:
    """``config`` must be a :class:`jaxskip.SimConfig` (a clear error instead of an AttributeError inside)."""
    if not isinstance(config, SimConfig):
        raise ParameterError(f"config must be a jaxskip.SimConfig (e.g. SimConfig(dt=2.5e-4)), "
                             f"got {type(config).__name__}")
    return config


def _checked_position(position):
    """``position`` (2,) or (3,) [m] as a float JAX array; a concrete one must be finite real numbers."""
    valid = "2 or 3 finite real numbers, (x, y[, z]) [m]"
    if isinstance(position, jax.core.Tracer):
        if position.shape not in ((2,), (3,)) or not jnp.issubdtype(position.dtype, jnp.floating):
            raise ParameterError(f"position must be {valid}, got a traced {position.dtype} array of shape "
                                 f"{position.shape}")
        return position
    try:
        raw = np.asarray(position)
    except (TypeError, ValueError):
        raw = None
    if raw is None or raw.shape not in ((2,), (3,)) or raw.dtype.kind not in "iuf" or not np.all(np.isfinite(raw)):
        raise ParameterError(f"position must be {valid}, got {position!r}")
    if isinstance(position, (jax.Array, np.ndarray)) and raw.dtype.kind == "f":
        if raw.dtype not in (np.float32, np.float64):   # (float16 was refused as 'dtype must be ...', a name not given)
            raise ParameterError(f"position must be float32 or float64 (the field takes its type), got {raw.dtype}")
        return jnp.asarray(position)
    return jnp.asarray(raw, dtype=jnp.result_type(float))


def rollout_coupled(config: SimConfig, grid: WaterGrid, throw: Throw, stone: RigidStone, water: WaterParams,
                    water_dt: float | None = None, two_way: bool = True):
    """One throw on a height field that follows the stone: pure, jit/vmap/grad-able.

    Returns ``(state, tracker, records, field)``: as :func:`jaxskip.rollout`, plus
    the final :class:`Field` (the window's water and its offset). The water
    starts still. The field's water may lag the stone's clock by up to one water interval: its ``pending``
    [s] and ``impulse`` [Pa s] hold the last push not yet stepped (:func:`advance_field` applies it).
    ``water_dt`` and ``two_way`` as in :func:`make_coupled_step`. The window's own ``gravity``
    and ``rho`` are static fields of ``grid`` (checked equal to ``water``'s when concrete): a gradient with
    respect to ``water.rho_water`` or ``water.gravity`` moves the stone's forces only, not the water's.

    Batches: ``jax.lax.map`` it over the throws, not ``jax.vmap``. The step's conditionals (the water's advance
    every ``water_dt``, the clamp's blocks, the window's re-centring, the skip of finished segments) are real
    branches for one throw and become "compute every branch, then select" under ``vmap``: measured (a review,
    stop 48; the default throw, float64, 2 cores) 0.044 s unbatched or under ``lax.map``, 2.4 s under ``vmap``
    for a batch of one, 25.6 s for four throws (0.26 s one by one). The answers agree either way (to 1e-12 m).
    """
    _check_config(config)
    _check_grid(grid)
    _check_rollout_args(config, throw, stone, water, name="rollout_coupled",   # (a batched throw met a raw
                        signature="(config, grid, throw, stone, water)")     # broadcasting error)
    _check_concrete(throw, stone, water)   # (a NaN speed 'diverged', a mass of -0.1 'sank', in silence)
    check_shared_constants(grid, water)
    check_window_fits(grid, stone)
    state, tracker = initial_carry(config, throw, stone)
    carry = (state, tracker, initial_field(grid, state.position))
    step = make_coupled_step(config, grid, water_dt, two_way)
    (state, tr, field), recs = _scan(config, step, carry, stone, water)
    return state, tr.finish(), (recs if config.record else None), field


__all__ = ["Field", "advance_field", "check_shared_constants", "check_window_fits", "coupled_interval", "coupled_substeps", "default_water_dt", "default_window", "initial_field", "make_coupled_step", "reach_ceiling", "recentre", "rollout_coupled"]
