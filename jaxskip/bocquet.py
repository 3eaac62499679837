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
    out = (_scalar("c_lift", c_lift, 0.0, COEFFICIENT_MAX, unit="[-]"),
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
    """A flat stone for the reduced model (static, hashable). SI units.

    ``size`` and ``mass`` are checked (real numbers > 0; not strings or bools) and stored as floats.

    >>> ReducedStone("disk", 0.025, 0.0135).size
    0.025
    """

    shape: str = "square"
    """``"square"`` (side ``size``) or ``"disk"`` (radius ``size``)."""
    size: float = 0.1
    """Side [m] of the square, or radius [m] of the disk, > 0. Bocquet's example: a 0.1 m square."""
    mass: float = 0.1
    """Mass M [kg], > 0. Bocquet's example: 0.1 kg."""

    def __post_init__(self):
        check_choice("shape", self.shape, SHAPES)
        object.__setattr__(self, "size", _scalar("size", self.size, 0.0, math.inf, unit="m", low_open=True))
        object.__setattr__(self, "mass", _scalar("mass", self.mass, 0.0, math.inf, unit="kg", low_open=True))


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
    """() downrange distance [m] from the first touch to where the stone stopped or sank."""
    contact_time: jax.Array
    """(K,) duration of each contact [s] (NaN after the last)."""
    contact_length: jax.Array
    """(K,) distance travelled during each contact [m] (NaN after the last)."""
    vx_in: jax.Array
    """(K,) horizontal speed at the start of each contact [m/s] (NaN after the last)."""
    impulse_x: jax.Array
    """(K,) horizontal impulse of the water per unit mass in each contact [m/s] (NaN after the last)."""
    impulse_z: jax.Array
    """(K,) vertical impulse of the water per unit mass in each contact [m/s] (NaN after the last)."""


def immersed_area(stone: ReducedStone, depth, tilt):
    """Immersed area [m^2] of the stone tilted by ``tilt`` [rad] whose trailing edge is ``depth`` [m] under water.

    A traceable helper of :func:`reduced_throw` (no checks): ``depth`` and ``tilt`` are numbers or arrays
    that broadcast together (a negative depth counts as 0); the result has their broadcast shape.

    >>> round(float(immersed_area(ReducedStone(), 0.01, math.radians(30.0))), 6)   # 0.1 m x 0.02 m wetted
    0.002
    """
    s = jnp.maximum(depth, 0.0) / jnp.sin(tilt)        # wetted length along the face
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
    """Bocquet's V² law for a square's bounce count: :math:`N \\approx V^2/(4\\mu g L)`, :math:`\\mu = \\tilde C/C`,
    :math:`L` the :func:`collision_length`: the kinetic energy over the least a contact costs, :math:`2\\mu M g L`
    at grazing incidence (a contact of length :math:`2L`; module docstring). An upper bound: a contact entered
    at vertical speed :math:`u` costs :math:`\\mu M V (g\\tau + 2u)`, more (:func:`reduced_throw` makes at most
    21 bounces at 12 m/s, against 39.5 here). physics.md §3's :math:`V^2/(2\\mu g L)` is twice this.

    Parameters
    ----------
    speed : horizontal speed at the first touch [m/s], in (0, 100]; a number or an array of them.
    stone, tilt, c_lift, c_friction, rho : as :func:`collision_length` (``tilt`` [rad]).
    g : gravitational acceleration [m/s^2], in [0.01, 100].

    Returns
    -------
    The estimated bounce count [-], not rounded: a float for a number ``speed``, else a float64 NumPy
    array of ``speed``'s shape.

    >>> round(estimated_bounces(12.0, ReducedStone(), math.radians(10.0)), 1)   # physics.md: 38 at ~12 m/s
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
                  rho=1000.0, g=9.81, dt=2e-5, contact_steps=5000, max_contacts=64) -> ReducedResult:
    """Skip a flat stone with Bocquet's reduced model; jit/vmap/grad-able in ``speed``, ``tilt``, ``attack``.

    Parameters
    ----------
    speed : speed at first touch [m/s], in (0, 100].
    tilt : the stone's fixed tilt θ [rad], in (0, π/2), with net lift
        :math:`C = C_l\\cos\\theta - C_f\\sin\\theta > 10^{-4} C_l` (:data:`NET_LIFT_FLOOR`), i.e. below
        :math:`\\arctan(C_l/C_f)`: 45° for C_l = C_f = 1, 73° for the library's 1 and 0.3.
    attack : angle of the velocity below the horizontal [rad], in [0, π/2).
    stone : :class:`ReducedStone`; default Bocquet's 0.1 m, 0.1 kg square.
    c_lift, c_friction : C_l, C_f [-], in [0, 10] (Bocquet's example: 1, 1).
    rho : water density [kg/m^3], in [10, 20000]; ``g``: gravity [m/s^2], in [0.01, 100].
    dt : contact time step [s] (> 0); ``contact_steps``: steps per contact before it counts as sunk,
        an integer in [1, 10^7] (``dt * contact_steps`` = 0.1 s by default); ``max_contacts``: contacts
        simulated (K), an integer in [1, 10^5].

    ``speed``, ``tilt`` and ``attack`` are numbers or arrays; arrays broadcast together to a batch
    shape B, and every field of the :class:`ReducedResult` gets B as leading axes (``jax.vmap`` over
    scalars gives the same). Concrete values are checked elementwise before tracing (finite, in range,
    net lift) and refused with :class:`~jaxskip.ParameterError`; traced values (inside ``jit``,
    ``vmap``, ``grad``) are used as given, and a traced tilt without net lift (C <= 0) gives 0 bounces.
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
    dt = _scalar("dt", dt, 0.0, math.inf, unit="s", low_open=True)
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

    def contact(vx, vz):
        """One contact from the surface (z = 0, vz < 0): fixed steps, alive while immersed."""
        def body(c, _):
            z, vx, vz, t, x, ix, iz, inside = c
            S = immersed_area(stone, -z, tilt)
            ax = -k * Ct * vx * vx * S
            az = -g + k * C * vx * vx * S
            vx1, vz1 = vx + ax * dt, vz + az * dt
            z1 = z + vz1 * dt
            keep = lambda new, old: jnp.where(inside, new, old)  # noqa: E731
            return (keep(z1, z), keep(vx1, vx), keep(vz1, vz), keep(t + dt, t), keep(x + vx1 * dt, x),
                    keep(ix + ax * dt, ix), keep(iz + (az + g) * dt, iz), inside & (z1 < 0.0)), None

        zero = 0.0 * vx
        init = (zero, vx, vz, zero, zero, zero, zero, jnp.asarray(True))
        (z, vx, vz, t, x, ix, iz, inside), _ = jax.lax.scan(body, init, None, length=contact_steps)
        return vx, vz, t, x, ix, iz, ~inside & (vx > 0.0)

    def one(carry, _):
        vx, vz, alive, n, dist = carry
        vx1, vz1, t, x, ix, iz, left = contact(vx, vz)
        nan = jnp.full_like(vx, jnp.nan)   # (not nan * vx: its zero cotangent times NaN made every gradient NaN)
        row = (jnp.where(alive, t, nan), jnp.where(alive, x, nan), jnp.where(alive, vx, nan),
               jnp.where(alive, ix, nan), jnp.where(alive, iz, nan))
        bounced = alive & left
        flight = jnp.where(bounced, 2.0 * vz1 / g, 0.0)        # lands with the vertical speed it left with
        dist = dist + jnp.where(alive, x, 0.0) + jnp.where(bounced, vx1 * flight, 0.0)
        return (jnp.where(bounced, vx1, vx), jnp.where(bounced, -vz1, vz), bounced,
                n + bounced.astype(jnp.int32), dist), row

    vx0 = speed * jnp.cos(attack)
    vz0 = -speed * jnp.sin(attack)
    init = (vx0, vz0, C > 0.0, jnp.asarray(0, jnp.int32), 0.0 * vx0)
    (_, _, _, n, dist), rows = jax.lax.scan(one, init, None, length=max_contacts)
    return ReducedResult(bounces=n, distance=dist, contact_time=rows[0], contact_length=rows[1], vx_in=rows[2],
                         impulse_x=rows[3], impulse_z=rows[4])
