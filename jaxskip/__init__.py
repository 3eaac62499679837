"""jaxskip: a differentiable, batched stone-skipping simulator in JAX.

A rigid triangle-mesh stone gets lift and friction from the water on each
triangle, in proportion to the triangle's immersed area found by clipping it
against the water surface (Do, Lee & Ryu, "Real-time Simulation of Stone
Skipping"); Bocquet's (2003) per-face law is the calibrated default. The step
is a pure JAX function, scanned over time, vmapped over throws and
differentiable end to end.

Units are SI throughout (m, s, kg, rad); degrees and rev/s appear only at the
edges (:meth:`Throw.from_degrees`, the CLI, the ``optimize`` package's boxes, sweeps and search results, and
results' ``to_dict()``, each saying so).

Quick start
-----------
>>> from jaxskip import Throw, simulate
>>> result = simulate(Throw.from_degrees(speed=7.0, tilt=20.0, attack=5.0, spin=20.0))
>>> result.bounces >= 1
True
"""

from . import _xla

XLA_TUNING: str = _xla.apply()
"""What ``import jaxskip`` did about XLA:CPU's small-loop option (see :mod:`jaxskip._xla`):
``"applied"``, ``"opted-out"`` (``JAXSKIP_XLA_TUNING=0``), ``"user"`` (``XLA_FLAGS`` sets
``--xla_backend_extra_options`` itself) or ``"too-late"`` (JAX's backend had started)."""

CPU_DEVICES: str = _xla.apply_cpu_devices()
"""What ``import jaxskip`` did about JAX's CPU devices (see :func:`jaxskip._xla.apply_cpu_devices`):
``"applied"`` (one device per usable core, so batches and sweeps use every core),
``"opted-out"`` (``JAXSKIP_CPU_DEVICES=1``), ``"user"`` (the count was set already),
``"single-core"`` or ``"too-late"`` (JAX's backend had started)."""

from ._checks import ParameterError  # noqa: E402
from .api import Contact, ThrowResult, resolve_stone, simulate  # noqa: E402
from .batch import BatchResult, simulate_batch  # noqa: E402
from .body import RigidStone, rigid_stone  # noqa: E402
from .forces import ForceModel, WaterParams, water_params  # noqa: E402
from .mesh import MassProperties, MeshError, TriMesh, mass_properties, read_obj, validate_mesh, write_obj  # noqa: E402
from .simulate import (OUTCOMES, AccuracyWarning, DivergedWarning, Record, SimConfig, StoneState, Tracker, initial_carry, initial_state, make_step, rollout,  # noqa: E402
                       rollout_jit, StabilityWarning, steps_for)
from .stones import BUILTIN_STONES, clanet_disk, disk, ellipsoid_pebble, irregular_pebble, load_stone, paper_stone  # noqa: E402
from .throw import Throw  # noqa: E402
from .water import WaterGrid, WaterState, height_at, make_water_step, run_water, stable_dt, still_water  # noqa: E402

__all__ = [
    "AccuracyWarning", "BUILTIN_STONES", "DivergedWarning", "StabilityWarning", "BatchResult", "CPU_DEVICES", "XLA_TUNING", "Contact", "ForceModel", "MassProperties", "MeshError", "OUTCOMES", "ParameterError",
    "Record", "RigidStone", "SimConfig", "StoneState", "Throw", "ThrowResult", "Tracker", "TriMesh", "WaterParams",
    "clanet_disk", "disk", "ellipsoid_pebble", "initial_carry", "initial_state", "irregular_pebble", "load_stone", "make_step",
    "mass_properties", "paper_stone", "read_obj", "resolve_stone", "rigid_stone", "rollout", "rollout_jit",
    "simulate", "simulate_batch", "steps_for", "validate_mesh", "water_params", "write_obj",
    "WaterGrid", "WaterState", "height_at", "make_water_step", "run_water", "stable_dt", "still_water",
]
__version__ = "0.1.0"
