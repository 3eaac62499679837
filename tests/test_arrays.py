"""The face reductions of ``jaxskip._arrays``: the same values as jnp's, without XLA:CPU's reduce-window."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxskip._arrays import face_max, face_min, face_sum


@pytest.mark.parametrize("n", [1, 7, 32, 33, 38, 65, 200])
def test_face_reductions_equal_jnp(n):
    x = jnp.asarray(np.random.default_rng(n).normal(size=(n, 3)))
    np.testing.assert_allclose(face_sum(x), jnp.sum(x, axis=0), rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(face_sum(x[:, 0]), jnp.sum(x[:, 0]), rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(face_sum(x.T, axis=-1), jnp.sum(x, axis=0), rtol=1e-13, atol=1e-13)
    assert face_min(x) == jnp.min(x) and face_max(x) == jnp.max(x)
    assert face_min(x[:, 1]) == jnp.min(x[:, 1]) and face_max(x[:, 1]) == jnp.max(x[:, 1])


def test_face_sum_gradient_is_ones():
    x = jnp.asarray(np.random.default_rng(0).normal(size=(38, 3)))
    g = jax.grad(lambda a: jnp.sum(face_sum(a) ** 2))(x)
    np.testing.assert_allclose(g, 2.0 * jnp.broadcast_to(jnp.sum(x, axis=0), x.shape), rtol=1e-13)


def test_face_reductions_avoid_reduce_window_under_vmap():
    """The point of the helpers: a batched reduction over 38 faces compiles to plain reduces.

    XLA:CPU rewrites a reduce over more than 32 elements into a padded reduce-window (its
    tree-reduction pass); under vmap over throws that window cost more than the force itself.
    """
    x = jnp.zeros((256, 38, 3))
    plain = jax.jit(jax.vmap(lambda a: (jnp.sum(a, axis=0), jnp.min(a)))).lower(x).compile().as_text()
    folded = jax.jit(jax.vmap(lambda a: (face_sum(a), face_min(a)))).lower(x).compile().as_text()
    if "reduce-window" not in plain:
        pytest.skip("this XLA no longer rewrites wide reductions into reduce-windows")
    assert "reduce-window" not in folded
