r"""Differentiable objectives of a throw: a smooth bounce count and the distance.

The bounce count is piecewise constant in the throw, so its gradient is zero
almost everywhere. The tracker counts a bounce when, after a contact, the
stone's lowest point rises more than ``bounce_clearance`` :math:`c` (1 mm)
above the water. The surrogate counts the same event smoothly. With the gap
:math:`g_i` between the lowest vertex and the water at step :math:`i` and the
soft indicator :math:`s_i = \sigma((g_i - c)/w)` (:math:`\sigma` the logistic
function),

.. math:: \tilde N = \sum_i \min\big(\max(0,\; s_{i+1} - s_i),\; a_i\big)

sums the rises of :math:`s`, each flight's at most 1: the budget :math:`a_i` is 1 at a wet step
and otherwise what the rises since the last wet step have left of it (:math:`a_{i+1} = a_i -` the
rise counted at step i), 0 before the first contact (a release that rises is no bounce). Each flight
after a contact that climbs well above :math:`c` adds about 1, a hop that barely reaches :math:`c`
adds :math:`\sigma((g_{peak} - c)/w) < 1`, and the stone that sinks adds nothing, like the true
count. The cap matters: a spinning stone's lowest vertex bobs by a millimetre or so as it wobbles,
and as it comes down to its next contact it dips below :math:`c` and rises again in the air; without
the cap each such flight added up to ~1 (measured: 13.1 against the true 12 over a default-like throw,
now 12.1). :math:`\tilde N` is continuous in the throw (a new hop
grows in from 0 as its height grows), so its gradient carries information
where the true count is flat.

Bias and knob: the width :math:`w` (``width`` [m]) sharpens it. A hop whose
peak lies within a few :math:`w` of :math:`c` counts partly (the surrogate
under- or over-counts it by up to 1/2); a bob in the air that dips below and
rises above :math:`c` again adds what the flight's rise left of its budget. Smaller :math:`w` approaches the true
count but concentrates the gradient on fewer steps. The true count always
comes from the exact simulation (:func:`jaxskip.simulate_batch`).

Where it fails: a stone whose lowest point jumps by millimetres in one step leaves and re-enters the
water one step at a time, and the surrogate counts each such hop while the tracker, which confirms a
bounce from a flight's second dry step (or at once where the step's bound on the lowest point's path peaks
above the clearance), counts none. That is a near-vertical stone spinning fast
(measured, a review of 2026-12-07, 0.3 s at the default 0.25 ms step: tilt -89° / +89° / 60°, 0.1 m/s,
200 rev/s: 11.7 / 10.3 / 9.0 against true counts of 2 / 1 / 1, whatever the width), far outside a human
throw (in the human box the surrogate tracks the count, tested). A search over such a box can climb
towards those throws: check their true counts, or keep the spin and tilt to throws a hand can make. Not
counting a flight's first dry step removes the overcount but makes :math:`\tilde N` jump by a whole hop
where a flight's length passes from one step to two; measured, it turned a small search that improved
its throw from 2 to 11 bounces in 6 steps into one that lost a bounce, so the surrogate keeps the continuous form.

Checking the gradient by finite differences: :math:`\tilde N` is continuous but has dense kinks (the
max and min above, faces switching on and off, the events of the step): on the default throw central
differences with relative steps of 1e-6 differ from the gradient by ~2× for speed, tilt and attack; with
steps of 1e-9 or less (float64) they agree (a review, 2026-12-06). The tests take 1e-7 (1e-5 for spin)
over a throw's first 400 steps, where the events lie further apart.

Cost: :func:`make_objective` accumulates :math:`\tilde N` in the scan's carry
(:func:`soft_bounce_rollout`) instead of stacking per-step records, so the
reverse pass stores no per-step outputs and the rollout's segment and step
checkpointing applies unchanged.
"""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp

from jaxskip import RigidStone, SimConfig, StoneState, Throw, WaterParams
from jaxskip.throw import in_domain
from jaxskip._checks import ParameterError, check_range
from jaxskip.simulate import (DIVERGED, MAX_BOUNCE_CLEARANCE, Record, _check_concrete, _check_rollout_args, _one_float_type,
                              _one_throw, _scan, initial_carry, initial_state, make_step, rollout)

#: Default clearance level [m]: the tracker's ``SimConfig.bounce_clearance``.
CLEARANCE = 1e-3
#: Default sigmoid width [m] of the soft indicator "lowest point above the clearance level".
WIDTH = 2e-4


#: Narrowest and widest sigmoid width [m]: below 1 nm the indicator is a step at float32's resolution of a
#: height (a width of 1e-50 m, 0 in float32, gave NaN gradients), above 1 cm it no longer resolves a hop.
WIDTH_RANGE = (1e-9, 0.01)


def check_width(width) -> float:
    """``width`` [m] in :data:`WIDTH_RANGE`, as a float (a :class:`~jaxskip.ParameterError` otherwise)."""
    return check_range("width", width, *WIDTH_RANGE, unit="m")


def _check_knobs(clearance, width) -> None:
    """``clearance`` [m] in (0, :data:`jaxskip.simulate.MAX_BOUNCE_CLEARANCE`] (the tracker's range) and
    ``width`` [m] in :data:`WIDTH_RANGE` (checked when concrete; traced values pass through)."""
    if not isinstance(clearance, jax.core.Tracer):
        check_range("clearance", clearance, 0.0, MAX_BOUNCE_CLEARANCE, unit="m", low_open=True)
    if not isinstance(width, jax.core.Tracer):
        check_width(width)


def soft_bounce_count(records, clearance: float = CLEARANCE, width: float = WIDTH):
    r"""Smooth bounce count :math:`\tilde N` from a rollout's per-step records.

    ``records``: the :class:`jaxskip.Record` of one throw's rollout (:func:`jaxskip.rollout` with
    ``config.record``), with a leading step axis of length T; read: ``time`` (T,) [s], ``gap`` (T,) [m]
    and ``wetted_area`` (T,) [m^2] (for a batch, ``jax.vmap`` this function over it). Returns a scalar [-]. ``clearance`` [m], in (0, 0.01]: the level the
    lowest point must rise above (the tracker's ``bounce_clearance``); ``width`` [m], in [1e-9, 0.01]: the sigmoid's
    width (the sharpening knob).
    Steps taken out of play repeat the time and are ignored.
    """
    _check_knobs(clearance, width)
    if not isinstance(records, Record):
        raise ParameterError(f"records must be a jaxskip.Record (rollout's third output, with config.record=True), "
                             f"got {type(records).__name__}")
    if jnp.ndim(records.time) != 1 or jnp.shape(records.time)[0] < 2:
        raise ParameterError(f"records must be one throw's, with one leading step axis (T,), T >= 2; got time of "
                             f"shape {jnp.shape(records.time)} (for a batch, jax.vmap this function over it)")
    t, gap = records.time, records.gap
    s = jax.nn.sigmoid((gap - clearance) / width)
    live_next = t[1:] > t[:-1]  # the next record is a real step, not a frozen repeat
    wet = records.wetted_area[:-1] > 0.0  # at the step a rise starts from

    def count(budget, pair):
        rise, is_wet, live = pair
        budget = jnp.where(is_wet, 1.0, budget)
        counted = jnp.where(live, jnp.minimum(rise, budget), 0.0)
        return budget - counted, counted

    _, counted = jax.lax.scan(count, jnp.zeros_like(s[0]), (jax.nn.relu(s[1:] - s[:-1]), wet, live_next))
    return jnp.sum(counted)


def soft_bounce_rollout(config: SimConfig, throw: Throw, stone: RigidStone, water: WaterParams,
                        clearance: float = CLEARANCE, width: float = WIDTH):
    r"""Roll a throw out; return ``(state, tracker, soft_count)``: :math:`\tilde N` summed in the carry.

    The same surrogate as :func:`soft_bounce_count` of the records, without the records: each
    live step adds :math:`\min(\max(0, s_k - s_{k-1}), a)` of the gap at its start, :math:`a` the
    flight's budget (1 after a wet step, less what the rises since have counted; 0 before the first
    contact); steps out of play add nothing. ``config.record`` is ignored (nothing is
    stacked). Pure, jit/vmap/grad-able.
    """
    _check_knobs(clearance, width)
    _check_rollout_args(config, throw, stone, water, name="soft_bounce_rollout")   # what rollout checks: types,
    _check_concrete(throw, stone, water)   # one throw, and concrete values (a NaN throw scored 0 in silence)
    throw, stone, water = _one_float_type(throw, stone, water)
    inner = make_step(dataclasses.replace(config, record=True))

    def step(carry, stone, water):
        state, tr, s_prev, budget, total = carry
        (state1, tr1), rec = inner((state, tr), stone, water)
        s = jax.nn.sigmoid((rec.gap - clearance) / width)
        live = tr.alive
        # the budget set by the previous step's record (1 if it was wet); 0 before the first contact
        counted = jnp.where(live, jnp.minimum(jax.nn.relu(s - s_prev), budget), 0.0)
        budget = jnp.where(live, jnp.where(rec.wetted_area > 0.0, 1.0, budget - counted), budget)
        return (state1, tr1, jnp.where(live, s, s_prev), budget, total + counted), None

    state, tracker = initial_carry(config, throw, stone)
    one = jnp.ones((), state.position.dtype)
    carry = (state, tracker, one, 0.0 * one, 0.0 * one)
    (state, tr, _s, _budget, total), _ = _scan(dataclasses.replace(config, record=False), step, carry, stone, water)
    return state, tr, total


def distance(state, throw: Throw, stone: RigidStone):
    """Horizontal distance [m] from release to the final position (differentiable).

    ``state``: a :class:`jaxskip.StoneState` (position (3,) [m]) of the ``throw`` (one :class:`Throw`,
    shape ()) of ``stone``; under ``vmap`` both carry the batch axis. Returns a scalar [m]."""
    for name, value, cls in (("throw", throw, Throw), ("stone", stone, RigidStone), ("state", state, StoneState)):
        if not isinstance(value, cls):
            raise ParameterError(f"distance(state, throw, stone): {name} must be a jaxskip.{cls.__name__}, got "
                                 f"{type(value).__name__}")
    start = initial_state(throw, stone).position
    d = state.position[:2] - start[:2]
    return jnp.sqrt(jnp.sum(d * d) + 1e-30)


def make_objective(kind: str, config: SimConfig, stone: RigidStone, water: WaterParams, width: float = WIDTH):
    r"""Return ``f(throw) -> ()`` to maximise: ``"bounces"`` (smooth count) or ``"distance"`` [m].

    ``kind``: ``"bounces"`` (:math:`\tilde N`, :func:`soft_bounce_rollout`, with the clearance
    ``config.bounce_clearance`` [m]) or ``"distance"`` (:func:`distance` [m] of the final state; its gradient
    lacks the sink time's own dependence on the throw, see :func:`jaxskip.rollout`).
    ``config``: a :class:`jaxskip.SimConfig` (the rollout: ``dt``, ``max_steps``, attitude, ...);
    ``stone``: a :class:`jaxskip.RigidStone` (:func:`jaxskip.rigid_stone`); ``water``: a
    :class:`jaxskip.WaterParams` (:func:`jaxskip.water_params`). ``width`` [m], in [1e-9, 0.01]
    (:data:`WIDTH_RANGE`): the soft indicator's sigmoid width (default :data:`WIDTH`, 0.2 mm; the sharpening knob, see the module
    docstring). Bad arguments raise :class:`~jaxskip.ParameterError` here, before any tracing.

    ``f`` takes one :class:`jaxskip.Throw` (SI, shape ()) and returns a scalar (bounces [-] or
    distance [m]); pure and differentiable, jit/vmap/grad-able; nothing per step is stored
    (``config.record`` is ignored). Traced throws cannot be checked before the run, so ``f`` returns NaN for a
    throw with a non-finite value or one outside :meth:`jaxskip.Throw.create`'s ranges, such as a speed not above
    0 or a tilt beyond ±90° (:func:`jaxskip.throw.in_domain`; its gradient 0: the default throw runs in its place),
    and for one whose integration diverged (its gradient may be NaN): a bad point is not scored as 0 bounces (a
    review, stop 46: a NaN speed under ``jit(vmap(...))`` gave 0.0 with NaN gradients).
    """
    if kind not in ("bounces", "distance"):
        raise ParameterError(f"kind (the objective) must be 'bounces' or 'distance', got {kind!r}")
    for name, value, cls, hint in (("config", config, SimConfig, "jaxskip.SimConfig"),
                                   ("stone", stone, RigidStone, "jaxskip.RigidStone (see jaxskip.rigid_stone)"),
                                   ("water", water, WaterParams, "jaxskip.WaterParams (see jaxskip.water_params)")):
        if not isinstance(value, cls):
            raise ParameterError(f"{name} must be a {hint}, got {type(value).__name__}")
    _check_knobs(config.bounce_clearance, width)
    config = dataclasses.replace(config, record=False)

    def f(throw: Throw):
        if not isinstance(throw, Throw):
            raise ParameterError(f"the objective of make_objective takes a jaxskip.Throw, got {type(throw).__name__}")
        _one_throw(f"the objective of make_objective({kind!r}, ...)", throw)   # (it named soft_bounce_rollout)
        _check_concrete(throw)   # (a concrete bad throw is refused by name, as rollout refuses it; a traced one: NaN)
        valid = in_domain(throw)   # (finite and in Throw.create's ranges: a tilt of 3 rad scored 0 bounces)
        # A bad throw is swapped for the default one before the run (the double-where: the run's backward pass
        # would multiply NaN Jacobians by the zero cotangent), so its gradient is 0, its value NaN below.
        throw = jax.tree_util.tree_map(lambda a, d: jnp.where(valid, a, jnp.asarray(d, jnp.result_type(a))), throw,
                                       Throw.create())
        if kind == "bounces":
            _state, tr, value = soft_bounce_rollout(config, throw, stone, water, config.bounce_clearance, width)
        else:
            state, tr, _ = rollout(config, throw, stone, water)
            value = distance(state, throw, stone)
        return jnp.where(valid & (tr.outcome != DIVERGED), value, jnp.nan)

    return f
