"""Host values to device arrays without compiling anything.

``jnp.asarray`` of a NumPy array or a Python float lifts it through a compiled identity (one small
XLA compile per shape and dtype, ~10 ms each), which a first call in a fresh process pays for every
stone field, throw field and water constant. :func:`float_array` casts on the host to the float
type JAX runs in (float32, or float64 under ``jax_enable_x64``) and copies the buffer over.
"""

from __future__ import annotations

import jax
import numpy as np


def float_array(x) -> jax.Array:
    """``x`` (array-like) as a device array of JAX's default float dtype; no compile, no weak type."""
    return jax.device_put(np.asarray(x, dtype=jax.dtypes.canonicalize_dtype(np.float64)))
