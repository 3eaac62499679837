r"""A throw: how the stone leaves the hand (or the catapult), and its initial state.

Angles (physics.md §1): ``tilt`` is the angle of the stone's face to the
water surface, leading edge up (Bocquet's θ, Clanet's α; the "magic angle"
≈ 20° is a tilt). ``attack`` is the angle of the velocity *below* the
horizontal at release (Clanet's β is the same angle at impact, which gravity
steepens: from the default 1 mm ``height`` by under ~0.6° at the default throw
and at 20° from 1.7 m/s up, but 0° at 3.5 m/s meets the water at 2.0° and 5°
at 1 m/s at 8.7° with the paper stone, 2.3° and 9.4° with the Clanet disk; 5° at
release from 1 m at 8 m/s at ~29°). ``heading`` turns the whole throw
about the vertical. ``spin`` is the angular speed about the face normal,
positive counter-clockwise seen from above.

:class:`Throw` holds SI values (m/s, rad, rad/s, m). Degrees and rev/s belong
to the edges of the program: use :meth:`Throw.from_degrees`, which converts once.
"""

from __future__ import annotations

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np

from ._docs import document_fields
from . import quaternion
from ._arrays import float_array, float_dtype
from ._checks import ParameterError, check_array

MAX_SPEED = 100.0
"""Largest accepted throw speed [m/s] (far beyond any human or catapult)."""
MAX_SPIN_REVS = 500.0
"""Largest accepted spin [rev/s] (:meth:`Throw.from_degrees`, the command line)."""
MAX_SPIN = 2 * math.pi * MAX_SPIN_REVS
"""Largest accepted spin [rad/s] (500 rev/s)."""
MAX_HEIGHT = 100.0
"""Largest accepted release height [m]."""
MAX_HEADING = 1e6
"""Largest accepted |heading| [rad, or deg in :meth:`Throw.from_degrees`]."""


@document_fields
@jax.tree_util.register_dataclass
@dataclasses.dataclass(frozen=True)
class Throw:
    """Initial conditions of a throw (pytree: every field is traced, so new values never recompile).

    Every field has the same shape: ``()`` for one throw, ``(N,)`` (or more axes) for a batch.
    Build throws with :meth:`create` or :meth:`from_degrees` (arrays of JAX's float type): under your own
    ``jax.jit``, fields given as Python floats or ``jnp.asarray(9.0)`` are weakly typed, and jit compiles
    those apart (:func:`jaxskip.simulate` converts them itself).

    Examples
    --------
    >>> t = Throw.from_degrees(speed=5.0, tilt=20.0, attack=10.0, spin=10.0)  # m/s, deg, deg, rev/s
    >>> round(float(t.tilt), 4), round(float(t.spin), 3)  # rad, rad/s
    (0.3491, 62.832)
    """

    speed: jax.Array
    """() speed of the centre of mass [m/s], in (0, 100]."""
    tilt: jax.Array
    """() angle of the face to the water, leading edge up [rad], in (-π/2, π/2)."""
    attack: jax.Array
    """() angle of the velocity below the horizontal at release [rad], in [-π/2, π/2] (the impact angle, Clanet's
    β, for a release just above the water, the default ``height``)."""
    spin: jax.Array
    """() angular speed about the face normal [rad/s], in [-1000π, 1000π] (±500 rev/s); positive is
    counter-clockwise seen from above."""
    height: jax.Array
    """() clearance of the stone's lowest point above the water at release [m], in [0, 100]."""
    heading: jax.Array
    """() direction of travel, counter-clockwise from +x [rad], in [-1e6, 1e6]."""

    @classmethod
    def create(cls, speed=8.0, tilt=math.radians(20.0), attack=math.radians(5.0), spin=2 * math.pi * 20.0,
               height=0.001, heading=0.0) -> "Throw":
        """Validated constructor in SI units (m/s, rad, rad/s, m); raises :class:`ParameterError`.

        Ranges: speed (0, 100] m/s, tilt (-π/2, π/2), attack [-π/2, π/2], spin ±1000π rad/s, height
        [0, 100] m, heading ±1e6 rad.

        Each argument may be a scalar or an array; they are broadcast together, so
        ``Throw.create(tilt=np.linspace(0.1, 0.8, 64))`` is a batch of 64 throws for ``vmap``.

        >>> import math, numpy as np
        >>> t = Throw.create(speed=8.0, tilt=math.radians(20.0), spin=2 * math.pi * 20.0)   # 20 rev/s
        >>> t.shape, round(float(t.spin), 2)
        ((), 125.66)
        >>> Throw.create(tilt=np.linspace(0.1, 0.8, 64)).shape
        (64,)
        """
        fields = _checked(speed, tilt, attack, spin, height, heading)
        try:
            shape = np.broadcast_shapes(*(a.shape for a in fields.values()))
        except ValueError:
            raise ParameterError("the throw's parameters must broadcast to one batch shape, got "
                                 + ", ".join(f"{k} {a.shape}" for k, a in fields.items())) from None
        _check_as_stored(np.broadcast_to(fields["speed"], shape), np.broadcast_to(fields["tilt"], shape))
        return cls(**{k: float_array(np.broadcast_to(a, shape)) for k, a in fields.items()})

    @classmethod
    def from_degrees(cls, speed=8.0, tilt=20.0, attack=5.0, spin=20.0, height=0.001, heading=0.0) -> "Throw":
        """Build a throw from user units: speed [m/s], angles [deg], spin [rev/s], height [m].

        Ranges: speed (0, 100] m/s, tilt (-90, 90) deg, attack [-90, 90] deg, spin [-500, 500] rev/s,
        height [0, 100] m, heading ±1e6 deg.

        Scalars or arrays (broadcast together, as in :meth:`create`).
        """
        tilt = check_array("tilt", tilt, -90.0, 90.0, unit="degrees", low_open=True, high_open=True)
        attack = check_array("attack", attack, -90.0, 90.0, unit="degrees")
        spin = check_array("spin", spin, -MAX_SPIN_REVS, MAX_SPIN_REVS, unit="rev/s")
        heading = check_array("heading", heading, -MAX_HEADING, MAX_HEADING, unit="degrees")
        return cls.create(speed=speed, tilt=np.radians(tilt), attack=np.radians(attack), spin=2 * math.pi * spin,
                          height=height, heading=np.radians(heading))

    def check(self) -> "Throw":
        """Check a throw built without :meth:`create` (e.g. ``Throw(...)`` or ``dataclasses.replace``)
        as :meth:`create` does; returns it unchanged. Needs concrete values: :func:`jaxskip.simulate`
        and :func:`jaxskip.simulate_batch` call it before tracing."""
        for f in dataclasses.fields(self):
            value = getattr(self, f.name)
            if isinstance(value, jax.core.Tracer):
                raise ParameterError(f"throw.{f.name} is a traced value (inside jit, vmap or grad): simulate and "
                                     "simulate_batch check concrete throws and run their own compiled loop; to "
                                     "trace or differentiate a throw use jaxskip.rollout (jax.vmap it for a batch)")
            if isinstance(value, (list, tuple)):  # a pytree of its own: jax.tree_util would split it up
                raise ParameterError(f"throw.{f.name} must be a number or an array, got a {type(value).__name__} "
                                     "(Throw.create and Throw.from_degrees take lists and make the arrays)")
        values = {f.name: np.asarray(getattr(self, f.name)) for f in dataclasses.fields(self)}
        shapes = {k: v.shape for k, v in values.items()}
        if len(set(shapes.values())) > 1:
            raise ParameterError("every field of a Throw must have the same shape, got "
                                 + ", ".join(f"{k} {v}" for k, v in shapes.items())
                                 + " (Throw.create and Throw.from_degrees broadcast them for you)")
        # Stored in float32 (x64 off, or a throw made before it was switched on), a bound that :meth:`create`
        # accepted may round one ulp outside it: float32's rounding is allowed, and no more (a float16 field's
        # own eps widened every bound by 0.1 %: a speed of 100.06 m/s passed).
        f32 = float_dtype() == np.float32 or any(v.dtype == np.float32 for v in values.values())
        checked = _checked(**values, slack=float(np.finfo(np.float32).eps) if f32 else 0.0)
        _check_as_stored(checked["speed"], checked["tilt"])   # (as create: 1e-50 m/s is 0 in float32)
        return self

    @property
    def shape(self) -> tuple:
        """Batch shape of the throw (``()`` for a single throw)."""
        return tuple(np.shape(self.speed))


def _check_as_stored(speed, tilt) -> None:
    """``speed`` [m/s] and ``tilt`` [rad] (arrays, as given) must stay in range once stored in the float type JAX
    runs in: a speed that is 0 there, or a tilt that is ±π/2, was refused by simulate with a value never given
    (or ran: a 1e-50 m/s throw sank, a tilt of π/2 - 1e-9 flipped). Checked in NumPy: ``float_array`` inside a
    jit trace gives a tracer."""
    stored = np.asarray(speed, dtype=float_dtype())
    if not np.all(stored > 0):  # in (0, 100] as given, 0 as stored
        given = float(np.asarray(speed)[~(stored > 0)].flat[0])
        raise ParameterError(f"speed must be finite and in (0, {MAX_SPEED:g}] m/s, got {given!r}, which is 0 in "
                             f"{stored.dtype} (the float type JAX runs in)")
    stored = np.asarray(tilt, dtype=float_dtype())
    edge = np.abs(stored) >= np.asarray(math.pi / 2, dtype=stored.dtype)   # the open range's end, as stored
    if np.any(edge):
        given = float(np.asarray(tilt)[edge].flat[0])
        raise ParameterError(f"tilt must be in (-π/2, π/2) rad, i.e. (-90, 90) deg, got {given!r} rad "
                             f"({math.degrees(given):.10g} deg), which is ±π/2 in {stored.dtype} (the float type "
                             "JAX runs in)")


#: Said with an angle or spin out of its range (a review: ``Throw.create(tilt=20.0)`` meant degrees).
_DEGREES = "SI units here: Throw.from_degrees takes degrees and rev/s"


def _ranges(slack: float = 0.0) -> dict:
    """Each field's valid range in SI units, ``{name: (low, high, low_open, high_open, unit)}``: the one table
    :func:`_checked` (concrete values, by name) and :func:`in_domain` (traced ones) both read. ``slack`` widens
    the bounds by that fraction of themselves (see :func:`_checked`)."""
    pi2, w = math.pi / 2, 1.0 + slack
    return {"speed": (0.0, MAX_SPEED * w, True, False, "m/s"), "tilt": (-pi2 * w, pi2 * w, True, True, "rad"),
            "attack": (-pi2 * w, pi2 * w, False, False, "rad"),
            "spin": (-MAX_SPIN * w, MAX_SPIN * w, False, False, "rad/s"),
            "height": (0.0, MAX_HEIGHT * w, False, False, "m"),
            "heading": (-MAX_HEADING * w, MAX_HEADING * w, False, False, "rad")}


def _checked(speed, tilt, attack, spin, height, heading, slack: float = 0.0) -> dict:
    """The fields of a throw in SI units, checked elementwise (NumPy float64 arrays).

    ``slack``: relative widening of the closed bounds (and narrowing of nothing else), for values that
    were checked in float64 and then stored in float32: ``attack`` = -90 deg becomes
    float32(-π/2), one rounding beyond -π/2, and must still pass."""
    values = dict(speed=speed, tilt=tilt, attack=attack, spin=spin, height=height, heading=heading)
    return {name: check_array(name, values[name], lo, hi, unit=unit, low_open=lo_open, high_open=hi_open,
                              hint=_DEGREES if name in ("tilt", "attack", "spin") else "")
            for name, (lo, hi, lo_open, hi_open, unit) in _ranges(slack).items()}


def in_domain(throw: "Throw"):
    """A boolean array of ``throw``'s batch shape: True where every field is finite and inside the ranges that
    :meth:`Throw.create` checks (SI: speed in (0, :data:`MAX_SPEED`], tilt in (-π/2, π/2), attack in [-π/2, π/2],
    spin within ±:data:`MAX_SPIN`, height in [0, :data:`MAX_HEIGHT`], heading within ±:data:`MAX_HEADING`).
    Traceable: the check of a throw that cannot be checked before tracing (``optimize.make_objective`` scores a
    throw outside it NaN; :meth:`Throw.check` refuses a concrete one by name)."""
    ok = True
    for name, (lo, hi, lo_open, hi_open, _) in _ranges().items():
        a = jnp.asarray(getattr(throw, name))
        # (a NaN fails every comparison, so the range tests also refuse it)
        ok = ok & jnp.isfinite(a) & ((a > lo) if lo_open else (a >= lo)) & ((a < hi) if hi_open else (a <= hi))
    return ok


def attitude(tilt, heading):
    """Quaternion (4,) of a stone tilted by ``tilt`` [rad] (leading edge up) and turned by ``heading`` [rad].

    The body z axis (face normal) becomes ``(-sin tilt cos heading, -sin tilt sin heading, cos tilt)``.
    """
    q_tilt = quaternion.from_axis_angle(jnp.array([0.0, 1.0, 0.0]), -tilt)
    q_head = quaternion.from_axis_angle(jnp.array([0.0, 0.0, 1.0]), heading)
    return quaternion.multiply(q_head, q_tilt)
