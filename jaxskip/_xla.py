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

It applies to every JAX program in the process, which is why it is documented here and in
docs/speed.md, and why the threshold is bounded: loops that stream more than 100 MB (big water grids,
wide batches) keep XLA's default, multi-threaded execution. XLA also refuses the single-function
form for any loop whose body holds a scatter (``x.at[i].add(...)`` with traced indices), whatever
its size: the loops of the simulator avoid scatters for that reason
(:func:`jaxskip.water.deposit` adds its points' weights with slice updates).
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


# --- One JAX CPU device per core ---------------------------------------------------------------

DEVICES_ENV = "JAXSKIP_CPU_DEVICES"
"""Environment variable: the number of JAX CPU devices ``import jaxskip`` asks for (``1``: leave
JAX's single CPU device alone)."""


#: Most CPU devices ``JAXSKIP_CPU_DEVICES`` may ask for.
MAX_CPU_DEVICES = 1024


def usable_cores() -> int:
    """CPU cores this process may run on (its affinity mask where the OS has one)."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):  # macOS, Windows
        return os.cpu_count() or 1


def apply_cpu_devices() -> str:
    """Ask JAX for one CPU device per usable core; return what happened.

    JAX's CPU backend has one device by default, and a batch of throws on it runs its kernels
    mostly on one core (each step's arrays are a few kB to a few hundred kB: too small for XLA to
    split a kernel across threads). With one device per core, :func:`jaxskip.simulate_batch` and
    the sweeps of ``optimize`` shard their lanes over the devices (``jax.sharding``) and every core
    advances its own share: a 4096-throw grid 1.9x faster on the 2-core development machine
    (``benchmarks/README.md``), results unchanged. Programs that are not sharded run on the first
    device exactly as before (a single throw, a gradient, the water).

    Set through ``jax.config.update("jax_num_cpu_devices", n)``, which must happen before JAX
    starts its CPU backend. Returns:

    * ``"applied"``: ``jax.devices("cpu")`` will list one device per usable core (or
      ``JAXSKIP_CPU_DEVICES`` of them);
    * ``"opted-out"``: ``JAXSKIP_CPU_DEVICES=1``;
    * ``"user"``: the user chose already (``jax_num_cpu_devices`` set, or ``XLA_FLAGS`` has
      ``--xla_force_host_platform_device_count``): left as it is;
    * ``"single-core"``: one usable core, nothing to split;
    * ``"too-late"``: JAX's backend started before jaxskip was imported (nothing changed).
    """
    import warnings

    import jax

    wanted = os.environ.get(DEVICES_ENV, "").strip()
    if wanted:
        try:
            n = int(wanted)
            # (10^20 reached JAX and ended every command in a raw RuntimeError from the CPU client; a review)
            if not 1 <= n <= MAX_CPU_DEVICES:
                raise ValueError
        except ValueError:
            warnings.warn(f"{DEVICES_ENV} must be an integer in [1, {MAX_CPU_DEVICES}] (1: one CPU device, JAX's "
                          f"default), got {wanted[:40]!r}; ignored", stacklevel=3)
            n = usable_cores()
        else:
            if n == 1:
                return "opted-out"
    else:
        n = usable_cores()
    if "xla_force_host_platform_device_count" in os.environ.get("XLA_FLAGS", ""):
        return "user"
    if jax.config.jax_num_cpu_devices != -1:
        return "user"
    if n <= 1:
        return "single-core"
    if _backend_started():
        return "too-late"
    jax.config.update("jax_num_cpu_devices", n)
    return "applied"
