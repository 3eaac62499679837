r"""Bocquet's reduced model of stone skipping: the analytic reference for the mesh simulator.

Bocquet, "The physics of stone skipping", Am. J. Phys. 71:150 (2003); physics.md §3.
A flat stone (a square of side :math:`a` or a disk of radius :math:`R`) held at a fixed
tilt :math:`\theta` (the high-spin limit) meets flat water. With :math:`z` the depth of its
trailing edge (negative when immersed) and :math:`S(z)` the immersed area,

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
:math:`\omega^2 = C\rho_w V_x^2 a/(2M\sin\theta)`, so the contact lasts
:math:`\approx\pi/\omega \propto 1/V_x` and the **collision length** :math:`L = V_x\pi/\omega =
\pi\sqrt{2M\sin\theta/(C\rho_w a)}` does not depend on speed; each contact costs
:math:`\mu M g L` of kinetic energy with :math:`\mu = \tilde C/C`, hence
:math:`N \approx V_{x0}^2/(2\mu g L)`: the count grows like :math:`V^2`.

>>> r = reduced_throw(speed=12.0, tilt_deg=10.0, attack_deg=1.0)   # Bocquet's square, C_l = C_f = 1
>>> int(r.bounces) >= 10
True
"""

from __future__ import annotations

import dataclasses
import math

import jax
import jax.numpy as jnp

from ._docs import document_fields
from ._checks import ParameterError, check_choice, check_int, check_positive, check_range

SHAPES = ("square", "disk")


@document_fields
@dataclasses.dataclass(frozen=True)
class ReducedStone:
    """A flat stone for the reduced model (static, hashable). SI units."""

    shape: str = "square"
    """``"square"`` (side ``size``) or ``"disk"`` (radius ``size``)."""
    size: float = 0.1
    """Side [m] of the square, or radius [m] of the disk. Bocquet's example: a 0.1 m square."""
    mass: float = 0.1
    """Mass M [kg]. Bocquet's example: 0.1 kg."""

    def __post_init__(self):
        check_choice("shape", self.shape, SHAPES)
        check_positive("size", self.size, unit="m")
        check_positive("mass", self.mass, unit="kg")


@document_fields
@jax.tree_util.register_dataclass
@dataclasses.dataclass(frozen=True)
class ReducedResult:
    """What :func:`reduced_throw` returns (add a leading axis for a batch). K = ``max_contacts``."""

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
    """Immersed area [m^2] of the tilted stone whose trailing edge is ``depth`` [m] under water (≥ 0)."""
    s = jnp.maximum(depth, 0.0) / jnp.sin(tilt)        # wetted length along the face
    if stone.shape == "square":
        return stone.size * jnp.minimum(s, stone.size)
    R = stone.size
    u = 1.0 - jnp.clip(s, 0.0, 2.0 * R) / R             # in [-1, 1]
    inner = jnp.clip(1.0 - u * u, 0.0, 1.0)
    root = jnp.where(inner > 0, jnp.sqrt(jnp.where(inner > 0, inner, 1.0)), 0.0)
    return R * R * (jnp.arccos(jnp.clip(u, -1.0, 1.0)) - u * root)


def coefficients(tilt, c_lift=1.0, c_friction=1.0):
    """Bocquet's :math:`C = C_l\\cos\\theta - C_f\\sin\\theta` and :math:`\\tilde C = C_l\\sin\\theta + C_f\\cos\\theta`."""
    return (c_lift * jnp.cos(tilt) - c_friction * jnp.sin(tilt),
            c_lift * jnp.sin(tilt) + c_friction * jnp.cos(tilt))


def collision_length(stone: ReducedStone, tilt_deg, c_lift=1.0, c_friction=1.0, rho=1000.0):
    """Analytic collision length [m] of a square: :math:`L = \\pi\\sqrt{2M\\sin\\theta/(C\\rho_w a)}`.

    >>> round(collision_length(ReducedStone(), 10.0), 3)
    0.065
    """
    if stone.shape != "square":
        raise ParameterError("collision_length is derived for a square stone (shape='square')")
    th = math.radians(check_range("tilt_deg", tilt_deg, 0.0, 90.0, low_open=True, high_open=True))
    C = c_lift * math.cos(th) - c_friction * math.sin(th)
    if C <= 0:
        raise ParameterError(f"no lift at tilt {tilt_deg} deg: C = C_l cos - C_f sin = {C:.3g} <= 0")
    return math.pi * math.sqrt(2.0 * stone.mass * math.sin(th) / (C * rho * stone.size))


def estimated_bounces(speed, stone: ReducedStone, tilt_deg, c_lift=1.0, c_friction=1.0, rho=1000.0, g=9.81):
    """Bocquet's estimate :math:`N \\approx V^2/(2\\mu g L)` for a square (``speed`` horizontal, m/s)."""
    th = math.radians(tilt_deg)
    C = c_lift * math.cos(th) - c_friction * math.sin(th)
    mu = (c_lift * math.sin(th) + c_friction * math.cos(th)) / C
    return speed ** 2 / (2.0 * mu * g * collision_length(stone, tilt_deg, c_lift, c_friction, rho))


def reduced_throw(speed, tilt_deg, attack_deg, stone: ReducedStone | None = None, *, c_lift=1.0, c_friction=1.0,
                  rho=1000.0, g=9.81, dt=2e-5, contact_steps=5000, max_contacts=64) -> ReducedResult:
    """Skip a flat stone with Bocquet's reduced model; jit/vmap/grad-able in ``speed``, ``tilt_deg``, ``attack_deg``.

    Parameters
    ----------
    speed : speed at first touch [m/s] (> 0); ``attack_deg``: its angle below the horizontal [deg].
    tilt_deg : the stone's fixed tilt [deg], in (0, 90).
    stone : :class:`ReducedStone`; default Bocquet's 0.1 m, 0.1 kg square.
    c_lift, c_friction : C_l, C_f (Bocquet's example: 1, 1); ``rho`` [kg/m^3], ``g`` [m/s^2].
    dt : contact time step [s]; ``contact_steps``: steps per contact before it counts as sunk
        (``dt * contact_steps`` = 0.1 s by default); ``max_contacts``: contacts simulated.

    Python numbers are checked before tracing; arrays (a batch, or tracers) are used as given.
    """
    stone = ReducedStone() if stone is None else stone
    if not isinstance(stone, ReducedStone):
        raise ParameterError(f"stone must be a ReducedStone, got {stone!r}")
    for name, v in (("speed", speed), ("tilt_deg", tilt_deg), ("attack_deg", attack_deg)):
        if isinstance(v, (int, float)):
            if name == "speed":
                check_positive("speed", v, unit="m/s")
            elif name == "tilt_deg":
                check_range("tilt_deg", v, 0.0, 90.0, unit="deg", low_open=True, high_open=True)
            else:
                check_range("attack_deg", v, 0.0, 90.0, unit="deg", high_open=True)
    check_positive("dt", dt, unit="s")
    check_int("contact_steps", contact_steps, minimum=1, maximum=10_000_000)
    check_int("max_contacts", max_contacts, minimum=1, maximum=100_000)
    for name, v in (("c_lift", c_lift), ("c_friction", c_friction), ("rho", rho), ("g", g)):
        check_positive(name, v)

    tilt = jnp.deg2rad(tilt_deg)
    attack = jnp.deg2rad(attack_deg)
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
        nan = jnp.nan * vx
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
