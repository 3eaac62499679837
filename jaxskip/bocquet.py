r"""Bocquet's reduced model of stone skipping: the analytic reference for the mesh simulator.

Bocquet, "The physics of stone skipping", Am. J. Phys. 71:150 (2003); physics.md §3.
A flat stone (a square of side :math:`a` or a disk of radius :math:`R`) held at a fixed
tilt :math:`\theta` (the high-spin limit) meets flat water. With :math:`z` the height of its
trailing edge above the water (negative when immersed) and :math:`S(z)` the immersed area,

.. math::
    M\ddot z = -Mg + \tfrac12 C \rho_w V_x^2 S(z), \qquad
    M\dot V_x = -\tfrac12 \tilde C \rho_w V_x^2 S(z),

    C = C_l\cos\theta - C_f\sin\theta, \qquad \tilde C = C_l\sin\theta + C_f\cos\theta .

Square: :math:`S = a|z|/\sin\theta` (up to :math:`a^2`); disk: the disk segment of chord
depth :math:`s = |z|/\sin\theta` (physics.md §2). Between contacts the stone flies a
parabola and lands with the vertical speed it left with, so the model is a map from one
contact to the next; each contact is integrated with a fixed fine step (semi-implicit Euler)
inside a fixed-length ``lax.scan`` with an alive mask, so it jits, vmaps and differentiates.
The stone sinks when its whole face goes under (the trailing edge :math:`a\sin\theta` deep, :math:`2R\sin\theta`
for the disk): Bocquet's condition for a bounce, that the stone is not completely immersed, which sets his
minimal speed (:math:`\sqrt{4Mg/(C\rho_w a^2)}` for a square entering at grazing incidence: 0.70 m/s for his
0.1 m, 0.1 kg square at 10°). Until 2026-12-07 the wetted area was capped at the whole face and the contact
went on, so a stone whose face went under could still bounce (a review); every result says how its throw
ended (:data:`OUTCOMES`). With the rule, Clanet's disk at 20° of attack (C_l = 1, C_f = 0.3) has its lowest
minimal speed near 5° of tilt (1.0 m/s; 2.0 m/s at 20°, none at 2° and below, where the face is under at a
depth of a few millimetres), lower than the mesh's 14° (the plate has no thickness and feels only
:math:`V_x^2`); Bocquet's square at 10° needs 2.6-5 m/s (3.6 at 1° of attack), above physics.md's
0.3-0.7 m/s, because in a slow contact friction takes metres per second of :math:`V_x`, which his estimate
holds constant (measured 2026-12-07).

Consequences (tested): for the square, immersed motion is harmonic with
:math:`\omega^2 = C\rho_w V_x^2 a/(2M\sin\theta)` about the depth :math:`-g/\omega^2` where lift
balances weight. Entered at vertical speed :math:`u`, the stone stays in for
:math:`\tau = [2\pi - 2\arctan(u\omega/g)]/\omega`: half a period, :math:`\pi/\omega \propto 1/V_x`,
when :math:`u \gg g/\omega` — the **collision length** :math:`L = V_x\pi/\omega =
\pi\sqrt{2M\sin\theta/(C\rho_w a)}` does not depend on speed — and a whole period, a length of
:math:`2L`, at grazing incidence. The water's vertical impulse is :math:`M(g\tau + 2u)` and its
horizontal one :math:`\mu = \tilde C/C` times that, so a contact costs :math:`\mu M V_x (g\tau + 2u)
\ge 2\mu M g L` of kinetic energy, the least at grazing (measured: 2.05 :math:`\mu M g L` at 0.05° of
attack, 3.5 at 0.3°, 8.8 at 1°; 12 m/s, Bocquet's square at 10° of tilt), hence at most
:math:`N \approx V_{x0}^2/(4\mu g L)` bounces (:func:`estimated_bounces`): the count grows like
:math:`V^2`. physics.md §3 writes :math:`N \approx V_{x0}^2/(2\mu g L)`, a cost of :math:`\mu M g L`, a
contact of length :math:`L` at grazing; with its parameters that gives 79 bounces at 12 m/s, where the
same section quotes the 38-bounce record at about 12 m/s, as :math:`V^2/(4\mu g L)` gives (39.5). The
model itself makes at most 21 at 12 m/s (its best attack, ~0.3°): the :math:`2u` term.

Units are SI throughout, angles included: ``tilt`` and ``attack`` are in radians (convert
degrees once, at the caller's edge, e.g. ``math.radians(10.0)``). Every public function checks
its concrete inputs before any tracing and raises :class:`~jaxskip.ParameterError` naming the
parameter and its valid range.

>>> r = reduced_throw(speed=12.0, tilt=math.radians(10.0), attack=math.radians(1.0))  # Bocquet's square
>>> int(r.bounces) >= 10
True
"""

from __future__ import annotations

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np

from ._docs import document_fields
from ._checks import ParameterError, check_array, check_choice, check_int
from . import forces as _forces
from .forces import COEFFICIENT_MAX
from .throw import MAX_SPEED

SHAPES = ("square", "disk")

NET_LIFT_FLOOR = 1e-4
"""Smallest accepted net lift coefficient, relative to C_l: a tilt is refused when
:math:`C = C_l\\cos\\theta - C_f\\sin\\theta \\le 10^{-4} C_l`. :math:`C` is the difference of two
terms of order :math:`C_l`; near :math:`\\theta = \\arctan(C_l/C_f)` it is mostly rounding (in float64
:math:`C \\approx 10^{-16}` there, which gave a collision length of 1e7 m; float32 rounds at 1e-7), and
:math:`L \\propto C^{-1/2}`, :math:`\\mu = \\tilde C/C` blow up. The floor lies well above either rounding,
and excludes only tilts within :math:`10^{-4} C_l/\\tilde C \\le 10^{-4}` rad (0.006°) of the limit,
where no stone skips anyway: the speed a fully immersed square needs to carry its weight,
:math:`\\sqrt{2Mg/(C\\rho_w a^2)}`, is 44 m/s for Bocquet's 0.1 m, 0.1 kg square at the floor."""

OUTCOMES = ("sank", "cut_off", "stopped", "max_contacts")
"""How a reduced throw ended, by :attr:`ReducedResult.outcome`: ``"sank"`` (its whole face went under water, or
the tilt leaves no net lift), ``"cut_off"`` (a contact still going after ``contact_steps`` steps: its time,
length and impulses are NaN, the distance counts it up to the cut, a lower bound), ``"stopped"`` (the water
stopped it in a contact) and ``"max_contacts"`` (still bouncing after ``max_contacts`` contacts: the count and
the distance are lower bounds)."""

SIZE_RANGE = (1e-3, 10.0)
"""Accepted :attr:`ReducedStone.size` [m]: 1 mm (the mesh stones' smallest) to 10 m (a water-ski board's scale)."""
MASS_RANGE = (1e-6, 1e4)
"""Accepted :attr:`ReducedStone.mass` [kg]: 1 mg to 10 t."""
MAX_DT = 1e-3
"""Largest accepted contact step ``dt`` [s] of :func:`reduced_throw`: a contact lasts milliseconds (Clanet's
disk at 3.5 m/s: ~20 ms); at 0.1 s the integration ran backwards (a distance of -81 m)."""

RHO_RANGE = _forces.RHO_RANGE
"""Accepted water density [kg/m^3]: [10, 20000], as :func:`jaxskip.water_params`."""
G_RANGE = _forces.GRAVITY_RANGE
"""Accepted gravitational acceleration [m/s^2]: [0.01, 100], as :func:`jaxskip.water_params`."""


def _scalar(name: str, value, low: float, high: float, *, unit: str = "", low_open: bool = False,
            high_open: bool = False) -> float:
    """A concrete real number (not a string, bool, array or tracer) in the range, as a float; else ParameterError."""
    if isinstance(value, jax.core.Tracer):
        raise ParameterError(f"{name} must be a concrete number (it is checked before tracing), not a traced value")
    arr = check_array(name, value, low, high, unit=unit, low_open=low_open, high_open=high_open)
    if arr.ndim:
        raise ParameterError(f"{name} must be a single number, got an array of shape {arr.shape}")
    return float(arr)


def _batch(name: str, value, low: float, high: float, *, unit: str = "", low_open: bool = False,
           high_open: bool = False):
    """Concrete ``value`` (number or array) checked elementwise (float64 NumPy array); a tracer: ``None``."""
    if isinstance(value, jax.core.Tracer):
        return None
    return check_array(name, value, low, high, unit=unit, low_open=low_open, high_open=high_open)


def _constants(c_lift, c_friction, rho, g=None) -> tuple:
    """The water's constants checked against :func:`jaxskip.water_params`' ranges (floats)."""
    out = (_scalar("c_lift", c_lift, 0.0, COEFFICIENT_MAX, unit="[-]", low_open=True),   # (0: no lift at all)
           _scalar("c_friction", c_friction, 0.0, COEFFICIENT_MAX, unit="[-]"),
           _scalar("rho", rho, *RHO_RANGE, unit="kg/m^3"))
    return out if g is None else out + (_scalar("g", g, *G_RANGE, unit="m/s^2"),)


def _check_tilt(tilt, c_lift: float, c_friction: float) -> np.ndarray:
    """Concrete ``tilt`` [rad] in (0, π/2) with net lift C > NET_LIFT_FLOOR * C_l, as a float64 array;
    else :class:`ParameterError` naming the limit atan(C_l/C_f)."""
    t = check_array("tilt", tilt, 0.0, math.pi / 2, unit="rad (convert degrees with math.radians)",
                    low_open=True, high_open=True)
    C = c_lift * np.cos(t) - c_friction * np.sin(t)
    bad = C <= NET_LIFT_FLOOR * c_lift
    if bad.any():
        first, c = float(t[bad].flat[0]), float(C[bad].flat[0])
        limit = math.atan2(c_lift, c_friction)
        raise ParameterError(
            f"tilt = {first!r} rad ({math.degrees(first):.4g} deg) leaves no net lift: C = C_l cos(tilt) - C_f "
            f"sin(tilt) = {c:.3g} <= {NET_LIFT_FLOOR:g} C_l (c_lift = {c_lift:g}, c_friction = {c_friction:g}); "
            f"tilt must be below atan(C_l/C_f) = {limit:.6g} rad ({math.degrees(limit):.4g} deg)")
    return t


def _check_stone(stone) -> "ReducedStone":
    if not isinstance(stone, ReducedStone):
        raise ParameterError(f"stone must be a ReducedStone, got {stone!r}")
    return stone


@document_fields
@dataclasses.dataclass(frozen=True)
class ReducedStone:
    """A flat stone for the reduced model (static, hashable: a pytree with no leaves, so it passes through
    ``jax.jit``). SI units.

    ``size`` and ``mass`` are checked (real numbers in :data:`SIZE_RANGE` and :data:`MASS_RANGE`; not strings
    or bools) and stored as floats.

    >>> ReducedStone("disk", 0.025, 0.0135).size
    0.025
    """

    shape: str = "square"
    """``"square"`` (side ``size``) or ``"disk"`` (radius ``size``)."""
    size: float = 0.1
    """Side [m] of the square, or radius [m] of the disk, in [0.001, 10]. Bocquet's example: a 0.1 m square."""
    mass: float = 0.1
    """Mass M [kg], in [1e-6, 1e4]. Bocquet's example: 0.1 kg."""

    def __post_init__(self):
        check_choice("shape", self.shape, SHAPES)
        # (unbounded, a size of 1e300 m gave a distance of -8e291 m and a mass of 5e-324 kg NaN, with 0 bounces)
        object.__setattr__(self, "size", _scalar("size", self.size, *SIZE_RANGE, unit="m"))
        object.__setattr__(self, "mass", _scalar("mass", self.mass, *MASS_RANGE, unit="kg"))

    @property
    def face_length(self) -> float:
        """Length [m] of the face along the tilt: the side ``size`` of the square, the diameter of the disk."""
        return self.size if self.shape == "square" else 2.0 * self.size


jax.tree_util.register_static(ReducedStone)   # (jax.jit(reduced_throw) met a raw TypeError for the stone)


@document_fields
@jax.tree_util.register_dataclass
@dataclasses.dataclass(frozen=True)
class ReducedResult:
    """What :func:`reduced_throw` returns. K = ``max_contacts``; for a batch of shape B (the broadcast
    shape of ``speed``, ``tilt`` and ``attack``) every field gets B as leading axes: ``bounces`` B,
    ``contact_time`` B + (K,)."""

    bounces: jax.Array
    """() int: contacts the stone left again."""
    distance: jax.Array
    """() downrange distance [m] from the first touch to where the stone sank or stopped (a lower bound when
    ``outcome`` is ``cut_off`` or ``max_contacts``)."""
    contact_time: jax.Array
    """(K,) duration of each contact [s] (NaN after the last, and for a contact cut off)."""
    contact_length: jax.Array
    """(K,) distance travelled during each contact [m] (NaN after the last, and for a contact cut off)."""
    vx_in: jax.Array
    """(K,) horizontal speed at the start of each contact [m/s] (NaN after the last)."""
    impulse_x: jax.Array
    """(K,) horizontal impulse of the water per unit mass in each contact [m/s] (NaN after the last, and for a
    contact cut off)."""
    impulse_z: jax.Array
    """(K,) vertical impulse of the water per unit mass in each contact [m/s] (NaN after the last, and for a
    contact cut off)."""
    outcome: jax.Array
    """() int: how the throw ended, an index into :data:`OUTCOMES` (``OUTCOMES[int(r.outcome)]``)."""


def immersed_area(stone: ReducedStone, depth, tilt):
    """Immersed area [m^2] of the stone tilted by ``tilt`` [rad] whose trailing edge is ``depth`` [m] under water.

    A traceable helper of :func:`reduced_throw` (no checks): ``depth`` and ``tilt`` are numbers or arrays
    that broadcast together (a negative depth counts as 0); the result has their broadcast shape.

    >>> round(float(immersed_area(ReducedStone(), 0.01, math.radians(30.0))), 6)   # 0.1 m x 0.02 m wetted
    0.002
    """
    # wetted length along the face; at tilt <= 0 (traced: unchecked) the whole face is wet from any depth. A double
    # where: depth / sin(0) made the value and every gradient NaN (a review, stop 48)
    wet, sin_t = jnp.maximum(depth, 0.0), jnp.sin(tilt)
    tilted = sin_t > 0.0
    s = jnp.where(tilted, wet / jnp.where(tilted, sin_t, 1.0), jnp.where(wet > 0.0, 2.0 * stone.size, 0.0))
    if stone.shape == "square":
        return stone.size * jnp.minimum(s, stone.size)
    R = stone.size
    u = 1.0 - jnp.clip(s, 0.0, 2.0 * R) / R             # in [-1, 1]
    inner = jnp.clip(1.0 - u * u, 0.0, 1.0)
    root = jnp.where(inner > 0, jnp.sqrt(jnp.where(inner > 0, inner, 1.0)), 0.0)
    # arccos has an infinite slope at ±1 (dry, and wholly wet), where every contact starts: a double where,
    # or every gradient of a disk's throw was NaN (the area's own slope there is 0)
    edge = (u <= -1.0) | (u >= 1.0)
    angle = jnp.where(edge, jnp.where(u <= -1.0, math.pi, 0.0), jnp.arccos(jnp.where(edge, 0.0, u)))
    return R * R * (angle - u * root)


def coefficients(tilt, c_lift=1.0, c_friction=1.0):
    """Bocquet's :math:`C = C_l\\cos\\theta - C_f\\sin\\theta` and :math:`\\tilde C = C_l\\sin\\theta + C_f\\cos\\theta`.

    A traceable helper (no checks): ``tilt`` [rad] (number or array), ``c_lift`` and ``c_friction`` [-].
    Returns ``(C, C~)`` [-], each of ``tilt``'s shape. :math:`C` is the net lift: it vanishes at
    :math:`\\theta = \\arctan(C_l/C_f)` and is negative beyond.

    >>> [round(float(c), 3) for c in coefficients(math.radians(10.0))]
    [0.811, 1.158]
    """
    return (c_lift * jnp.cos(tilt) - c_friction * jnp.sin(tilt),
            c_lift * jnp.sin(tilt) + c_friction * jnp.cos(tilt))


def collision_length(stone: ReducedStone, tilt, c_lift=1.0, c_friction=1.0, rho=1000.0) -> float:
    """Analytic collision length [m] of a square: :math:`L = \\pi\\sqrt{2M\\sin\\theta/(C\\rho_w a)}`.

    Parameters
    ----------
    stone : a square :class:`ReducedStone` (side a [m], mass M [kg]).
    tilt : the stone's fixed tilt θ [rad], a number in (0, π/2) with net lift
        :math:`C = C_l\\cos\\theta - C_f\\sin\\theta > 10^{-4} C_l` (:data:`NET_LIFT_FLOOR`), i.e. below
        :math:`\\arctan(C_l/C_f)` (45° for the defaults).
    c_lift, c_friction : C_l, C_f [-], in [0, 10] (as :func:`jaxskip.water_params`).
    rho : water density [kg/m^3], in [10, 20000].

    Returns
    -------
    float: the distance [m] the stone travels in half an oscillation of its immersed motion (independent of
    speed): one contact's length when it enters fast, :math:`|v_z| \\gg g/\\omega` (measured 1.05 L at 1° of
    attack); a grazing contact lasts a whole oscillation, 2 L (module docstring).

    >>> round(collision_length(ReducedStone(), math.radians(10.0)), 3)
    0.065
    """
    stone = _check_stone(stone)
    if stone.shape != "square":
        raise ParameterError("collision_length is derived for a square stone (shape='square')")
    c_lift, c_friction, rho = _constants(c_lift, c_friction, rho)
    th = _scalar("tilt", tilt, 0.0, math.pi / 2, unit="rad (convert degrees with math.radians)",
                 low_open=True, high_open=True)
    _check_tilt(th, c_lift, c_friction)
    C = c_lift * math.cos(th) - c_friction * math.sin(th)
    return math.pi * math.sqrt(2.0 * stone.mass * math.sin(th) / (C * rho * stone.size))


def estimated_bounces(speed, stone: ReducedStone, tilt, c_lift=1.0, c_friction=1.0, rho=1000.0, g=9.81):
    """An upper bound on a square's bounce count after Bocquet's V² argument (this module's bound; physics.md §3's
    formula is twice it): :math:`N \\approx V^2/(4\\mu g L)`, :math:`\\mu = \\tilde C/C`,
    :math:`L` the :func:`collision_length`: the kinetic energy over the least a contact costs, :math:`2\\mu M g L`
    at grazing incidence (a contact of length :math:`2L`; module docstring). An upper bound: a contact entered
    at vertical speed :math:`u` costs :math:`\\mu M V (g\\tau + 2u)`, more (:func:`reduced_throw` makes at most
    21 bounces at 12 m/s, against 39.5 here). physics.md §3's :math:`V^2/(2\\mu g L)` is twice this.

    Parameters
    ----------
    speed : horizontal speed at the first touch [m/s], in (0, 100]; a number or an array of them (note:
        :func:`reduced_throw` takes the whole speed, ``speed * cos(attack)`` of it horizontal).
    stone, tilt, c_lift, c_friction, rho : as :func:`collision_length` (``tilt`` [rad]).
    g : gravitational acceleration [m/s^2], in [0.01, 100].

    Returns
    -------
    The estimated bounce count [-], not rounded: a float for a number ``speed``, else a float64 NumPy
    array of ``speed``'s shape.

    >>> round(estimated_bounces(12.0, ReducedStone(), math.radians(10.0)), 1)   # the record, 38, is quoted at ~12 m/s
    39.5
    """
    v = _batch("speed", speed, 0.0, MAX_SPEED, unit="m/s", low_open=True)
    if v is None:
        raise ParameterError("speed must be concrete (estimated_bounces is plain Python arithmetic, not traceable)")
    g = _scalar("g", g, *G_RANGE, unit="m/s^2")
    L = collision_length(stone, tilt, c_lift, c_friction, rho)       # checks stone, tilt and the constants
    th, c_lift, c_friction = float(tilt), float(c_lift), float(c_friction)    # checked above: plain numbers
    mu = (c_lift * math.sin(th) + c_friction * math.cos(th)) / (c_lift * math.cos(th) - c_friction * math.sin(th))
    n = v ** 2 / (4.0 * mu * g * L)
    return float(n) if n.ndim == 0 else n


def reduced_throw(speed, tilt, attack, stone: ReducedStone | None = None, *, c_lift=1.0, c_friction=1.0,
                  rho=1000.0, g=9.81, dt=2e-5, contact_steps=20000, max_contacts=64) -> ReducedResult:
    """Skip a flat stone with Bocquet's reduced model; jit/vmap/grad-able in ``speed``, ``tilt``, ``attack``.

    Parameters
    ----------
    speed : speed at first touch [m/s], in (0, 100].
    tilt : the stone's fixed tilt θ [rad], in (0, π/2), with net lift
        :math:`C = C_l\\cos\\theta - C_f\\sin\\theta > 10^{-4} C_l` (:data:`NET_LIFT_FLOOR`), i.e. below
        :math:`\\arctan(C_l/C_f)`: 45° for C_l = C_f = 1, 73° for the library's 1 and 0.3.
    attack : angle of the velocity below the horizontal [rad], in [0, π/2).
    stone : :class:`ReducedStone`; default Bocquet's 0.1 m, 0.1 kg square.
    c_lift, c_friction : C_l in (0, 10], C_f in [0, 10] [-] (Bocquet's example: 1, 1).
    rho : water density [kg/m^3], in [10, 20000]; ``g``: gravity [m/s^2], in [0.01, 100].
    dt : contact time step [s], in (0, 1e-3] (:data:`MAX_DT`); ``contact_steps``: steps a contact may last,
        an integer in [1, 10^7] (``dt * contact_steps`` = 0.4 s by default; a contact still going then ends
        the throw, outcome ``"cut_off"``: 0.1 s, the default until 2026-12-07, cut off the last contact of
        Bocquet's square at 4-12 m/s, 10° of tilt, 1° of attack, and its distance 0.2 m short);
        ``max_contacts``: contacts simulated (K), an integer in [1, 10^5]
        (a throw still bouncing after them ends with outcome ``"max_contacts"``).

    A contact ends when the stone leaves the water (a bounce), when its whole face is under water (it sinks,
    Bocquet's condition), or when the water has stopped it. A contact entered at exactly zero attack
    (``attack=0``) starts with no lift and no vertical speed: the stone goes under and, slowed in the water,
    does not come out (0 bounces; 5 at 0.05° for Bocquet's square at 12 m/s).

    ``speed``, ``tilt`` and ``attack`` are numbers or arrays; arrays broadcast together to a batch
    shape B, and every field of the :class:`ReducedResult` gets B as leading axes (``jax.vmap`` over
    scalars gives the same). Concrete values are checked elementwise before tracing (finite, in range,
    net lift) and refused with :class:`~jaxskip.ParameterError`; traced values (inside ``jit``,
    ``vmap``, ``grad``) are used as given: a traced tilt without net lift (C <= 0) gives 0 bounces, and one
    at or below 0 (the whole face wet at once, its trailing edge's depth for sinking 0) sinks in the first contact.
    The other arguments must be concrete.

    >>> r = reduced_throw(jnp.array([4.0, 8.0]), math.radians(10.0), math.radians(1.0), max_contacts=8)
    >>> r.bounces.shape, r.contact_time.shape          # B = (2,), K = 8
    ((2,), (2, 8))
    >>> one = jax.vmap(lambda v: reduced_throw(v, math.radians(10.0), math.radians(1.0), max_contacts=8))
    >>> bool((one(jnp.array([4.0, 8.0])).bounces == r.bounces).all())
    True
    """
    stone = _check_stone(ReducedStone() if stone is None else stone)
    c_lift, c_friction, rho, g = _constants(c_lift, c_friction, rho, g)
    _batch("speed", speed, 0.0, MAX_SPEED, unit="m/s", low_open=True)
    if not isinstance(tilt, jax.core.Tracer):
        _check_tilt(tilt, c_lift, c_friction)
    _batch("attack", attack, 0.0, math.pi / 2, unit="rad (convert degrees with math.radians)", high_open=True)
    dt = _scalar("dt", dt, 0.0, MAX_DT, unit="s", low_open=True)
    contact_steps = check_int("contact_steps", contact_steps, minimum=1, maximum=10_000_000)
    max_contacts = check_int("max_contacts", max_contacts, minimum=1, maximum=100_000)

    shape = jnp.broadcast_shapes(jnp.shape(speed), jnp.shape(tilt), jnp.shape(attack))
    run = lambda v, th, a: _throw(v, th, a, stone, c_lift, c_friction, rho, g, dt, contact_steps,  # noqa: E731
                                  max_contacts)
    if shape == ():
        return run(speed, tilt, attack)
    flat = [jnp.broadcast_to(jnp.asarray(x), shape).reshape(-1) for x in (speed, tilt, attack)]
    result = jax.vmap(run)(*flat)
    return jax.tree_util.tree_map(lambda x: x.reshape(shape + x.shape[1:]), result)


def _throw(speed, tilt, attack, stone, c_lift, c_friction, rho, g, dt, contact_steps, max_contacts) -> ReducedResult:
    """One throw of :func:`reduced_throw` (scalars ``speed``, ``tilt`` [rad], ``attack`` [rad]; checked constants)."""
    C, Ct = coefficients(tilt, c_lift, c_friction)
    k = 0.5 * rho / stone.mass
    under = stone.face_length * jnp.sin(tilt)    # the trailing edge's depth [m] when the whole face is under

    def contact(vx, vz):
        """One contact from the surface (z = 0, vz < 0): fixed steps, alive while immersed and not sunk."""
        def body(c, _):
            z, vx, vz, t, x, ix, iz, inside, sank = c
            S = immersed_area(stone, -z, tilt)
            ax = -k * Ct * vx * vx * S
            az = -g + k * C * vx * vx * S
            vx1, vz1 = vx + ax * dt, vz + az * dt
            z1 = z + vz1 * dt
            keep = lambda new, old: jnp.where(inside, new, old)  # noqa: E731
            sinks = inside & (-z1 >= under)
            return (keep(z1, z), keep(vx1, vx), keep(vz1, vz), keep(t + dt, t), keep(x + vx1 * dt, x),
                    keep(ix + ax * dt, ix), keep(iz + (az + g) * dt, iz), inside & (z1 < 0.0) & ~sinks,
                    sank | sinks), None

        zero = 0.0 * vx
        init = (zero, vx, vz, zero, zero, zero, zero, jnp.asarray(True), jnp.asarray(False))
        (z, vx, vz, t, x, ix, iz, inside, sank), _ = jax.lax.scan(body, init, None, length=contact_steps)
        return vx, vz, t, x, ix, iz, ~inside & ~sank & (vx > 0.0), sank, inside

    def one(carry, _):
        vx, vz, alive, n, dist, outcome = carry
        vx1, vz1, t, x, ix, iz, left, sank, cut = contact(vx, vz)
        nan = jnp.full_like(vx, jnp.nan)   # (not nan * vx: its zero cotangent times NaN made every gradient NaN)
        ended = alive & ~cut      # a contact cut off has no duration, length or impulse
        row = (jnp.where(ended, t, nan), jnp.where(ended, x, nan), jnp.where(alive, vx, nan),
               jnp.where(ended, ix, nan), jnp.where(ended, iz, nan))
        bounced = alive & left
        flight = jnp.where(bounced, 2.0 * vz1 / g, 0.0)        # lands with the vertical speed it left with
        dist = dist + jnp.where(alive, x, 0.0) + jnp.where(bounced, vx1 * flight, 0.0)
        why = jnp.where(sank, OUTCOMES.index("sank"), jnp.where(cut, OUTCOMES.index("cut_off"),
                                                                 OUTCOMES.index("stopped")))
        outcome = jnp.where(alive & ~left, why, outcome)
        return (jnp.where(bounced, vx1, vx), jnp.where(bounced, -vz1, vz), bounced,
                n + bounced.astype(jnp.int32), dist, outcome), row

    vx0 = speed * jnp.cos(attack)
    vz0 = -speed * jnp.sin(attack)
    lift = C > 0.0
    first = jnp.where(lift, OUTCOMES.index("max_contacts"), OUTCOMES.index("sank")).astype(jnp.int32)
    init = (vx0, vz0, lift, jnp.asarray(0, jnp.int32), 0.0 * vx0, first)
    (_, _, _, n, dist, outcome), rows = jax.lax.scan(one, init, None, length=max_contacts)
    return ReducedResult(bounces=n, distance=dist, contact_time=rows[0], contact_length=rows[1], vx_in=rows[2],
                         impulse_x=rows[3], impulse_z=rows[4], outcome=outcome)
