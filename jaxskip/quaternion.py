r"""Unit quaternions for rigid-body attitude, written per element for ``vmap``.

Convention: ``q = (w, x, y, z)`` with scalar part first; ``q`` maps body-frame
vectors to the world frame, :math:`v_w = q \otimes v_b \otimes q^*`. The world
frame has :math:`z` up, the undisturbed water surface at :math:`z = 0` and the
throw heading along :math:`+x` (for heading 0).

Small 3x3 products are written as broadcast multiply-and-sum rather than
``jnp.dot``: on the CPU, XLA sends tiny matrix products to a slow library path.
"""

from __future__ import annotations

import jax.numpy as jnp


def multiply(p, q):
    """Hamilton product :math:`p \\otimes q`; shapes ``(4,), (4,) -> (4,)``."""
    pw, px, py, pz = p[0], p[1], p[2], p[3]
    qw, qx, qy, qz = q[0], q[1], q[2], q[3]
    return jnp.stack(
        [
            pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw,
        ]
    )


def to_matrix(q):
    """Rotation matrix ``R`` (3, 3) of a unit quaternion, so that ``v_w = R @ v_b``."""
    w, x, y, z = q[0], q[1], q[2], q[3]
    return jnp.stack(
        [
            jnp.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)]),
            jnp.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)]),
            jnp.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]),
        ]
    )


def from_axis_angle(axis, angle):
    """Quaternion of a rotation by ``angle`` [rad] about the unit vector ``axis`` (3,)."""
    half = 0.5 * angle
    return jnp.concatenate([jnp.cos(half)[None], jnp.sin(half) * jnp.asarray(axis)])


def exp_map(rotvec):
    r"""Quaternion of the rotation vector ``rotvec`` (3,) [rad]: :math:`\exp(\tfrac12 \phi)`.

    Gradient-safe at ``rotvec = 0`` (double ``where``: the norm and the
    ``sin(x)/x`` are never evaluated at zero on the branch that is kept).
    """
    sq = jnp.sum(rotvec * rotvec)
    small = sq < 1e-16
    sq_safe = jnp.where(small, 1.0, sq)
    angle = jnp.sqrt(sq_safe)
    half = 0.5 * angle
    # sin(|φ|/2)/|φ| with its Taylor series near zero.
    sinc = jnp.where(small, 0.5 - sq / 48.0, jnp.sin(half) / angle)
    cos = jnp.where(small, 1.0 - sq / 8.0, jnp.cos(half))
    return jnp.concatenate([cos[None], sinc * rotvec])


def normalize(q):
    """Return ``q / |q|`` (a quaternion is never near zero here, so no guard is needed)."""
    return q / jnp.sqrt(jnp.sum(q * q))


def _expand(R, v):
    """``R`` with leading unit axes to match the batch axes of ``v`` (explicit broadcasting)."""
    return R.reshape((1,) * (v.ndim - 1) + R.shape)


def rotate(R, v):
    """``R @ v`` for ``R`` (3, 3) and ``v`` (..., 3), as multiply-and-sum."""
    return jnp.sum(_expand(R, v) * v[..., None, :], axis=-1)


def rotate_inverse(R, v):
    """``R.T @ v`` for ``R`` (3, 3) and ``v`` (..., 3), as multiply-and-sum."""
    return jnp.sum(_expand(R, v) * v[..., :, None], axis=-2)


def congruence(R, A):
    """``R @ A @ R.T`` for 3x3 ``R`` and ``A`` (rotating a tensor to the world frame)."""
    RA = jnp.sum(R[:, :, None] * A[None, :, :], axis=1)
    return jnp.sum(RA[:, None, :] * R[None, :, :], axis=2)
