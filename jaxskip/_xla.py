"""One XLA:CPU setting that the simulator's loops need, applied when jaxskip is imported.

A throw is a ``lax.scan`` of small steps: ~80 fused kernels a step on arrays of a few
hundred bytes. XLA:CPU runs each kernel as a task of its own (~0.1 µs of dispatch each), so
a single throw spends most of its time between kernels. XLA has a pass that compiles a
small while loop — one whose bytes accessed are under ``xla_cpu_small_while_loop_byte_threshold``
(1 kB by default, far below a throw's loop) — into a single function with no per-kernel
dispatch. Raising that threshold to :data:`THRESHOLD` (100 MB) made, on the 2-core
development machine (``benchmarks/README.md``, session 11): one default throw 9-10 ms
-> 3.4-4.1 ms, its gradient 154 ms -> 18-27 ms, the 64² and 128² water steps ~2x faster,
and a rollout's compile 0.3-0.8 s shorter (a fresh process's first ``simulate()``
within the noise); wide batches (bound by their kernels' memory traffic) and 256² water
grids are unchanged. Results change at rounding level only.

The option travels in ``XLA_FLAGS``, which XLA reads once, when JAX first starts its CPU
backend. :func:`apply` therefore appends it to ``XLA_FLAGS`` at ``import jaxskip``:

* not if ``JAXSKIP_XLA_TUNING=0`` is set (opt out);
* not if ``XLA_FLAGS`` already sets ``--xla_backend_extra_options`` (the user's choice stands;
  add ``xla_cpu_small_while_loop_byte_threshold=100000000`` to it to keep the speed);
* to no effect if JAX's backend already started before jaxskip was imported (import
  jaxskip first, or export the flag yourself; :data:`jaxskip.XLA_TUNING` says which).

It applies to every JAX program in the process, which is why it is documented here and in the
README, and why the threshold is bounded: loops that stream more than 100 MB (big water grids,
wide batches) keep XLA's default, multi-threaded execution.
"""

from __future__ import annotations

import os

OPTION = "xla_cpu_small_while_loop_byte_threshold"
THRESHOLD = 100_000_000
"""Bytes accessed [B] below which XLA:CPU compiles a while loop into one function."""
OPT_OUT = "JAXSKIP_XLA_TUNING"
FLAG = f"--xla_backend_extra_options={OPTION}={THRESHOLD}"


def _backend_started() -> bool:
    try:
        from jax._src import xla_bridge
        return bool(xla_bridge.backends_are_initialized())
    except Exception:  # a JAX without the (private) query: assume not started
        return False


def apply() -> str:
    """Append :data:`FLAG` to ``XLA_FLAGS`` if appropriate; return what happened.

    ``"applied"``, ``"opted-out"`` (``JAXSKIP_XLA_TUNING=0``), ``"user"`` (``XLA_FLAGS`` already
    sets ``--xla_backend_extra_options``; includes the case where it holds this option) or
    ``"too-late"`` (JAX's backend started before jaxskip was imported: the flag was added but
    has no effect in this process).
    """
    if os.environ.get(OPT_OUT, "").strip().lower() in ("0", "false", "no", "off"):
        return "opted-out"
    flags = os.environ.get("XLA_FLAGS", "")
    if "xla_backend_extra_options" in flags:
        return "user"
    os.environ["XLA_FLAGS"] = f"{flags} {FLAG}".strip()
    return "too-late" if _backend_started() else "applied"
