"""Small array helpers: host values to device arrays without compiling, and reductions over faces.

``jnp.asarray`` of a NumPy array or a Python float lifts it through a compiled identity (one small
XLA compile per shape and dtype, ~10 ms each), which a first call in a fresh process pays for every
stone field, throw field and water constant. :func:`float_array` casts on the host to the float
type JAX runs in (float32, or float64 under ``jax_enable_x64``) and copies the buffer over.
"""

from __future__ import annotations

import jax
import numpy as np


def float_dtype() -> np.dtype:
    """JAX's default float dtype now: float64 under ``jax_enable_x64``, else float32."""
    return jax.dtypes.canonicalize_dtype(np.float64)


def float_array(x) -> jax.Array:
    """``x`` (array-like) as a device array of JAX's default float dtype; no compile, no weak type."""
    return jax.device_put(np.asarray(x, dtype=float_dtype()))


def float_leaves(tree):
    """Every leaf of ``tree`` (a :class:`jaxskip.Throw`, :class:`jaxskip.WaterParams`, ...) as
    :func:`float_array`: a Python float or ``jnp.asarray(9.0)`` is *weakly* typed, which jit keys apart
    from the strong arrays :meth:`jaxskip.Throw.from_degrees` and :func:`jaxskip.water_params` make, so
    the same computation would compile again. A tree whose leaves are all such arrays already (and not
    committed to a device, which a program with other arguments on another device would refuse) is
    returned as it is (the same object)."""
    dtype = jax.dtypes.canonicalize_dtype(np.float64)
    if all(isinstance(a, jax.Array) and a.dtype == dtype and not a.weak_type and not a.committed
           for a in jax.tree_util.tree_leaves(tree)):
        return tree
    return jax.tree_util.tree_map(float_array, tree)


# XLA:CPU rewrites a reduction over more than 32 elements into a padded ``reduce-window`` and a
# second reduce (its tree-reduction pass, kept for float accuracy). Over a stone's faces (F = 38)
# under ``vmap`` those windows cost more than the force arithmetic itself. Folding the axis in
# halves first (``x[:h] + x[h:2h]``, which fuses into the producer) keeps every reduce at or
# under 32 elements and never builds the window. The sum is a pairwise sum, as accurate as XLA's.
_FOLD_LIMIT = 32


def _fold(x, axis: int, op, reduce):
    axis = axis % x.ndim
    n = x.shape[axis]
    while n > _FOLD_LIMIT:
        h = n // 2
        head = op(jax.lax.slice_in_dim(x, 0, h, axis=axis), jax.lax.slice_in_dim(x, h, 2 * h, axis=axis))
        x = head if n % 2 == 0 else jax.numpy.concatenate([head, jax.lax.slice_in_dim(x, 2 * h, n, axis=axis)], axis)
        n = x.shape[axis]
    return reduce(x, axis=axis)


def face_sum(x, axis: int = 0) -> jax.Array:
    """``jnp.sum(x, axis)`` for one axis, folded in halves down to 32 elements first (see above)."""
    return _fold(x, axis, jax.numpy.add, jax.numpy.sum)


def _face_extreme(x, reduce, op):
    x = x.reshape(x.shape[0], -1)
    return _fold(reduce(x, axis=1), 0, op, reduce)


def face_min(x) -> jax.Array:
    """Minimum of every element of ``x`` (F, ...), ``F`` folded first: ``jnp.min(x)``."""
    return _face_extreme(x, jax.numpy.min, jax.numpy.minimum)


def face_max(x) -> jax.Array:
    """Maximum of every element of ``x`` (F, ...), ``F`` folded first: ``jnp.max(x)``."""
    return _face_extreme(x, jax.numpy.max, jax.numpy.maximum)
