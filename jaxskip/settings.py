"""Simulation settings in user terms -> the library's objects, shared by the CLI and the sweeps.

One place turns the values of ``jaxskip throw``'s simulation flags (stone, mass or density, force
law and coefficients, velocity, attitude, integrator, dt [s], duration [s], max_steps, bounce
clearance [m]) into a validated ``(SimConfig, WaterParams, RigidStone)``, and back into a JSON-ready
description.
"""

from __future__ import annotations

import os
import types

from ._checks import ParameterError

#: The simulation flags' values when not given (``stone`` and ``attitude``: ``jaxskip throw``'s).
#: ``max_steps`` None: enough steps to spend ``duration`` in the water at ``dt``.
#: Read-only (every command reads it for its defaults).
SIM_DEFAULTS = types.MappingProxyType({
    "stone": "paper", "mass": None, "density": None, "force_law": "bocquet", "c_lift": None, "c_friction": None,
    "velocity": "body", "attitude": "free", "integrator": "euler", "dt": 2.5e-4, "duration": 5.0, "max_steps": None,
    "bounce_clearance": 1e-3})


def simulation(*, stone, mass, density, force_law, c_lift, c_friction, velocity, attitude, integrator, dt, duration,
               max_steps, bounce_clearance):
    """User values (the keys of :data:`SIM_DEFAULTS`) -> validated ``(SimConfig, WaterParams, RigidStone)``.

    ``stone``: a built-in name or an ``.obj`` path [m]; ``mass`` [kg] or ``density`` [kg/m^3] (None: the
    stone's own); ``c_lift``/``c_friction`` None: the force law's calibrated values; ``dt`` and
    ``duration`` [s]; ``max_steps`` None: :func:`jaxskip.steps_for` of ``duration`` and ``dt``;
    ``bounce_clearance`` [m]: how high the stone's lowest point must rise for a contact to count as a bounce
    (:attr:`jaxskip.SimConfig.bounce_clearance`).
    """
    from . import ForceModel, SimConfig, water_params
    from .api import resolve_stone
    from .mesh import MeshError
    from ._checks import check_range
    from .simulate import MAX_DT, MAX_STEPS, check_duration, steps_for

    if isinstance(stone, (str, os.PathLike)) and os.path.isdir(stone):
        raise ParameterError(f"stone {str(stone)!r} is a directory, not a stone name or an .obj file")
    if max_steps is None:
        dt = check_range("dt", dt, 0.0, MAX_DT, unit="s", low_open=True)  # (the message SimConfig would give)
        duration = check_duration(duration, dt)   # (said "> 0 s" for 0 and -1, where the rule is >= dt)
        max_steps = steps_for(duration, dt)
        if max_steps > MAX_STEPS:  # (named after what the user gave, not the derived step budget)
            raise ParameterError(f"duration ({duration:g} s) needs {max_steps} steps of dt = {dt:g} s, more than the "
                                 f"{MAX_STEPS} a run may take: shorten duration or lengthen dt (--duration, --dt in the CLI)")
    config = SimConfig(dt=dt, duration=duration, max_steps=max_steps, integrator=integrator, attitude=attitude,
                       force=ForceModel(law=force_law, velocity=velocity), bounce_clearance=bounce_clearance)
    water = water_params(force_law, c_lift=c_lift, c_friction=c_friction)
    try:
        rigid, _ = resolve_stone(stone, mass=mass, density=density)
    except MeshError as exc:   # a faulty .obj named by its line only ('bad.obj, line 1: ...'): say which stone
        if isinstance(stone, (str, os.PathLike)) and os.fspath(stone) not in str(exc):
            raise MeshError(f"stone {os.fspath(stone)!r}: {exc}") from None
        raise
    return config, water, rigid


def environment() -> dict:
    """What produced a result, for ``--json`` outputs: package versions, Python, whether JAX computes in
    float64 (``jax_enable_x64``; float32 otherwise) and its devices. Long throws' bounce counts are chaotic
    down to the last bit, so the precision and versions are part of a reproducible answer."""
    import platform

    import jax
    import jaxlib
    import numpy as np

    from . import __version__

    devices = jax.devices()
    return {"jaxskip": __version__, "jax": jax.__version__, "jaxlib": jaxlib.__version__, "numpy": np.__version__,
            "python": platform.python_version(), "float64": bool(jax.config.jax_enable_x64),
            "devices": f"{len(devices)} x {devices[0].platform}"}


def describe(stone, config, water, rigid) -> dict:
    """The resolved simulation configuration, JSON-ready (SI units; the stone as given)."""
    return {"stone": str(stone), "mass": float(rigid.mass), "attitude": config.attitude,
            "integrator": config.integrator, "force_law": config.force.law, "velocity": config.force.velocity,
            "c_lift": float(water.c_lift), "c_friction": float(water.c_friction), "dt": config.dt,
            "duration": config.duration, "max_steps": config.max_steps, "bounce_clearance": config.bounce_clearance}
