"""Strict numerics for the whole suite: float64 and no implicit rank promotion."""

import jax
import pytest

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_numpy_rank_promotion", "raise")


@pytest.fixture(scope="session")
def paper():
    """The default 38-triangle stone as a RigidStone (granite density)."""
    from jaxskip import paper_stone, rigid_stone

    return rigid_stone(paper_stone(), density=2650.0)


@pytest.fixture(scope="session")
def water():
    from jaxskip import water_params

    return water_params()
