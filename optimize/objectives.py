r"""Differentiable objectives of a throw: a smooth bounce count and the distance.

The bounce count is piecewise constant in the throw, so its gradient is zero
almost everywhere. The tracker counts a bounce when, after a contact, the
stone's lowest point rises more than ``bounce_clearance`` :math:`c` (1 mm)
above the water. The surrogate counts the same event smoothly. With the gap
:math:`g_i` between the lowest vertex and the water at step :math:`i` and the
soft indicator :math:`s_i = \sigma((g_i - c)/w)` (:math:`\sigma` the logistic
function),

.. math:: \tilde N = \sum_i h_i \max(0,\; s_{i+1} - s_i)

sums the rises of :math:`s` once the stone has touched the water (:math:`h_i` = 1 from the step
after its first wet step, 0 before: a release that rises, or a spinning stone whose lowest vertex
bobs before it lands, is no bounce): each flight after a contact that climbs well
above :math:`c` adds about 1, a hop that barely reaches :math:`c` adds
:math:`\sigma((g_{peak} - c)/w) < 1`, and the stone that sinks adds nothing,
like the true count. :math:`\tilde N` is continuous in the throw (a new hop
grows in from 0 as its height grows), so its gradient carries information
where the true count is flat.

Bias and knob: the width :math:`w` (``width`` [m]) sharpens it. A hop whose
peak lies within a few :math:`w` of :math:`c` counts partly (the surrogate
under- or over-counts it by up to 1/2); wiggles of the gap around :math:`c`
during a long skim add small amounts. Smaller :math:`w` approaches the true
count but concentrates the gradient on fewer steps. The true count always
comes from the exact simulation (:func:`jaxskip.simulate_batch`).

Cost: :func:`make_objective` accumulates :math:`\tilde N` in the scan's carry
(:func:`soft_bounce_rollout`) instead of stacking per-step records, so the
reverse pass stores no per-step outputs and the rollout's segment and step
checkpointing applies unchanged.
"""

from __future__ import annotations

import dataclasses

import jax
import jax.numpy as jnp

from jaxskip import RigidStone, SimConfig, Throw, WaterParams
from jaxskip._checks import ParameterError, check_positive
from jaxskip.simulate import _new_tracker, _scan, initial_state, make_step, rollout

#: Default clearance level [m]: the tracker's ``SimConfig.bounce_clearance``.
CLEARANCE = 1e-3
#: Default sigmoid width [m] of the soft indicator "lowest point above the clearance level".
WIDTH = 2e-4


def _check_knobs(clearance, width) -> None:
    """``clearance`` and ``width`` [m] must be > 0 (checked when concrete; traced values pass through)."""
    for name, v in (("clearance", clearance), ("width", width)):
        if not isinstance(v, jax.core.Tracer):
            check_positive(name, v, unit="m")


def soft_bounce_count(records, clearance: float = CLEARANCE, width: float = WIDTH):
    r"""Smooth bounce count :math:`\tilde N` from a rollout's per-step records.

    ``records``: the :class:`jaxskip.Record` of one throw's rollout (:func:`jaxskip.rollout` with
    ``config.record``), with a leading step axis of length T; read: ``time`` (T,) [s], ``gap`` (T,) [m]
    and ``wetted_area`` (T,) [m^2] (for a batch, ``jax.vmap`` this function over it). Returns a scalar [-]. ``clearance`` [m]: the level the
    lowest point must rise above (the tracker's ``bounce_clearance``); ``width`` [m]: the sigmoid's
    width (the sharpening knob).
    Steps taken out of play repeat the time and are ignored.
    """
    _check_knobs(clearance, width)
    t, gap = records.time, records.gap
    s = jax.nn.sigmoid((gap - clearance) / width)
    live_next = t[1:] > t[:-1]  # the next record is a real step, not a frozen repeat
    touched = jnp.cumsum(records.wetted_area > 0.0)[:-1] > 0  # wet at or before the step a rise starts from
    return jnp.sum(jnp.where(live_next & touched, jax.nn.relu(s[1:] - s[:-1]), 0.0))


def soft_bounce_rollout(config: SimConfig, throw: Throw, stone: RigidStone, water: WaterParams,
                        clearance: float = CLEARANCE, width: float = WIDTH):
    r"""Roll a throw out; return ``(state, tracker, soft_count)``: :math:`\tilde N` summed in the carry.

    The same surrogate as :func:`soft_bounce_count` of the records, without the records: each
    live step after the first contact began adds :math:`\max(0, s_k - s_{k-1})` of the gap at its
    start; steps before it and steps out of play add nothing. ``config.record`` is ignored (nothing is
    stacked). Pure, jit/vmap/grad-able.
    """
    _check_knobs(clearance, width)
    inner = make_step(dataclasses.replace(config, record=True))

    def step(carry, stone, water):
        state, tr, s_prev, total = carry
        (state1, tr1), rec = inner((state, tr), stone, water)
        s = jax.nn.sigmoid((rec.gap - clearance) / width)
        live = tr.alive
        touched = tr.contacts > 0   # a contact began before this step: rises before the first are no bounce
        total = total + jnp.where(live & touched, jax.nn.relu(s - s_prev), 0.0)
        return (state1, tr1, jnp.where(live, s, s_prev), total), None

    state = initial_state(throw, stone)
    one = jnp.ones((), state.position.dtype)
    carry = (state, _new_tracker(config.max_contacts, state.position.dtype), one, 0.0 * one)
    (state, tr, _s, total), _ = _scan(dataclasses.replace(config, record=False), step, carry, stone, water)
    return state, tr, total


def distance(state, throw: Throw, stone: RigidStone):
    """Horizontal distance [m] from release to the final position (differentiable).

    ``state``: a :class:`jaxskip.StoneState` (position (3,) [m]) of the ``throw`` (one :class:`Throw`,
    shape ()) of ``stone``; under ``vmap`` both carry the batch axis. Returns a scalar [m]."""
    for name, value, cls in (("throw", throw, Throw), ("stone", stone, RigidStone)):
        if not isinstance(value, cls):
            raise ParameterError(f"distance(state, throw, stone): {name} must be a jaxskip.{cls.__name__}, got "
                                 f"{type(value).__name__}")
    start = initial_state(throw, stone).position
    d = state.position[:2] - start[:2]
    return jnp.sqrt(jnp.sum(d * d) + 1e-30)


def make_objective(kind: str, config: SimConfig, stone: RigidStone, water: WaterParams, width: float = WIDTH):
    r"""Return ``f(throw) -> ()`` to maximise: ``"bounces"`` (smooth count) or ``"distance"`` [m].

    ``kind``: ``"bounces"`` (:math:`\tilde N`, :func:`soft_bounce_rollout`, with the clearance
    ``config.bounce_clearance`` [m]) or ``"distance"`` (:func:`distance` [m] of the final state).
    ``config``: a :class:`jaxskip.SimConfig` (the rollout: ``dt``, ``max_steps``, attitude, ...);
    ``stone``: a :class:`jaxskip.RigidStone` (:func:`jaxskip.rigid_stone`); ``water``: a
    :class:`jaxskip.WaterParams` (:func:`jaxskip.water_params`). ``width`` [m], > 0: the soft
    indicator's sigmoid width (default :data:`WIDTH`, 0.2 mm; the sharpening knob, see the module
    docstring). Bad arguments raise :class:`~jaxskip.ParameterError` here, before any tracing.

    ``f`` takes one :class:`jaxskip.Throw` (SI, shape ()) and returns a scalar (bounces [-] or
    distance [m]); pure and differentiable, jit/vmap/grad-able; nothing per step is stored
    (``config.record`` is ignored).
    """
    if kind not in ("bounces", "distance"):
        raise ParameterError(f"objective must be 'bounces' or 'distance', got {kind!r}")
    for name, value, cls, hint in (("config", config, SimConfig, "jaxskip.SimConfig"),
                                   ("stone", stone, RigidStone, "jaxskip.RigidStone (see jaxskip.rigid_stone)"),
                                   ("water", water, WaterParams, "jaxskip.WaterParams (see jaxskip.water_params)")):
        if not isinstance(value, cls):
            raise ParameterError(f"{name} must be a {hint}, got {type(value).__name__}")
    _check_knobs(config.bounce_clearance, width)
    config = dataclasses.replace(config, record=False)

    def f(throw: Throw):
        if kind == "bounces":
            return soft_bounce_rollout(config, throw, stone, water, config.bounce_clearance, width)[2]
        state, _tr, _ = rollout(config, throw, stone, water)
        return distance(state, throw, stone)

    return f
