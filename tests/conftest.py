"""Strict numerics for the whole suite: float64 and no implicit rank promotion.

The suite is compile-bound (most tests jit their own rollouts and gradients), so it asks XLA:CPU
for LLVM's lowest optimisation level (``--xla_backend_optimization_level=0``) before JAX starts:
XLA's own HLO passes (fusion, layout, the small-loop tuning of ``jaxskip._xla``) run as usual, only
the machine code is less tuned. Measured on a 2-core AVX2 machine (session 20): the whole suite
784 s against ~1035 s, ``tests/test_gradients.py`` 113 s against 157 s; every test passes at both
levels. The run-bound notebooks run at the shipped level (``tests/test_notebooks.py``).
``JAXSKIP_TEST_XLA_OPT=default`` runs the whole suite at the level users get; an optimisation level
already in ``XLA_FLAGS`` is left alone.
"""

import os

TEST_OPT_FLAG = "--xla_backend_optimization_level=0"
if (os.environ.get("JAXSKIP_TEST_XLA_OPT", "").strip().lower() != "default"
        and "xla_backend_optimization_level" not in os.environ.get("XLA_FLAGS", "")):
    os.environ["XLA_FLAGS"] = f"{os.environ.get('XLA_FLAGS', '')} {TEST_OPT_FLAG}".strip()

import jax  # noqa: E402  (after XLA_FLAGS: XLA reads them once, when its backend starts)
import pytest  # noqa: E402

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
