"""``import jaxskip`` turns on XLA:CPU's single-function compilation of small loops and asks for one
JAX CPU device per core (jaxskip._xla).

Each case runs in a fresh interpreter: XLA reads ``XLA_FLAGS`` once per process.
"""

import json
import os
import subprocess
import sys

import pytest

PROBE = r"""
import json, os, sys
if sys.argv[1] == "onecore":
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})  # as if the machine had one core
if sys.argv[1] == "late":
    import jax.numpy as jnp
    jnp.zeros(2).block_until_ready()  # start JAX's backend before jaxskip is imported
import importlib
import jax
import jaxskip
sim = importlib.import_module("jaxskip.simulate")
stone = jaxskip.resolve_stone("paper")[0]
water = jaxskip.water_params()
config = sim.SimConfig(record=False, max_steps=100)
hlo = jax.jit(lambda t: sim.rollout(config, t, stone, water)[0].position).lower(
    jaxskip.Throw.from_degrees()).compile().as_text()
print(json.dumps({"status": jaxskip.XLA_TUNING, "flags": os.environ.get("XLA_FLAGS", ""),
                  "small_calls": hlo.count("xla_cpu_small_call"),
                  "devices": jaxskip.CPU_DEVICES, "n_devices": len(jax.devices("cpu")),
                  "cores": jaxskip._xla.usable_cores()}))
"""


def _probe(env_updates, mode="normal"):
    env = {k: v for k, v in os.environ.items() if k not in ("XLA_FLAGS", "JAXSKIP_XLA_TUNING", "JAXSKIP_CPU_DEVICES")}
    env.update(env_updates)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    env["PYTHONPATH"] = root + os.pathsep + env.get("PYTHONPATH", "")
    out = subprocess.run([sys.executable, "-c", PROBE, mode], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_import_compiles_the_rollout_loop_as_one_function():
    r = _probe({})
    assert r["status"] == "applied"
    assert "xla_cpu_small_while_loop_byte_threshold=100000000" in r["flags"]
    assert r["small_calls"] >= 1  # the scan became one compiled function (fails if XLA ignores the flag)


def test_opt_out_and_user_flags_are_respected():
    off = _probe({"JAXSKIP_XLA_TUNING": "0"})
    assert off["status"] == "opted-out" and off["flags"] == "" and off["small_calls"] == 0
    mine = "--xla_backend_extra_options=xla_cpu_small_while_loop_byte_threshold=0"
    user = _probe({"XLA_FLAGS": mine})
    assert user["status"] == "user" and user["flags"] == mine and user["small_calls"] == 0
    other = _probe({"XLA_FLAGS": "--xla_force_host_platform_device_count=2"})
    assert other["status"] == "applied" and other["flags"].startswith("--xla_force_host_platform_device_count=2 ")


def test_a_backend_started_first_is_reported():
    r = _probe({}, "late")
    assert r["status"] == "too-late" and r["small_calls"] == 0


def test_one_cpu_device_per_core():
    r = _probe({})
    if r["cores"] == 1:
        assert r["devices"] == "single-core" and r["n_devices"] == 1
    else:
        assert r["devices"] == "applied" and r["n_devices"] == r["cores"]
    assert _probe({"JAXSKIP_CPU_DEVICES": "3"})["n_devices"] == 3
    # (stop 47, a review) 10^20 reached JAX's CPU client: a raw RuntimeError in every command. Out of range is
    # warned of and ignored, as a non-number is.
    big = _probe({"JAXSKIP_CPU_DEVICES": "99999999999999999999"})
    assert big["n_devices"] == r["n_devices"]


def test_cpu_device_opt_out_and_user_choice():
    off = _probe({"JAXSKIP_CPU_DEVICES": "1"})
    assert off["devices"] == "opted-out" and off["n_devices"] == 1
    user = _probe({"XLA_FLAGS": "--xla_force_host_platform_device_count=3"})
    assert user["devices"] == "user" and user["n_devices"] == 3
    late = _probe({}, "late")
    assert late["n_devices"] == 1 and late["devices"] in ("too-late", "single-core")


def test_one_core_keeps_one_device():
    if not hasattr(os, "sched_setaffinity"):
        pytest.skip("no CPU affinity masks on this OS")
    r = _probe({}, "onecore")
    assert r["cores"] == 1 and r["devices"] == "single-core" and r["n_devices"] == 1
