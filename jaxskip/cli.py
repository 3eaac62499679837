"""Command line: ``jaxskip throw [options]`` (also ``python -m jaxskip``).

User units at this edge only: speed m/s, angles degrees, spin rev/s; converted
once into :class:`jaxskip.Throw` (SI). Bad input exits with status 2 and a
one-line message naming the parameter, before anything is compiled.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys

EXIT_USAGE = 2


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse's own errors: same style, exit 2
        self.print_usage(sys.stderr)
        print(f"jaxskip: error: {message}", file=sys.stderr)
        raise SystemExit(EXIT_USAGE)


def _float(name):
    def parse(text):
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number, got {text!r}") from None
        return value

    return parse


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="jaxskip", description="Differentiable stone-skipping simulator.")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    t = sub.add_parser("throw", help="simulate one throw on flat water", description=(
        "Simulate one throw. With no options: a good default throw that skips many times."))
    t.add_argument("--speed", type=_float("--speed"), default=8.0, metavar="M/S", help="speed [m/s] (default 8)")
    t.add_argument("--tilt", type=_float("--tilt"), default=20.0, metavar="DEG",
                   help="face angle to the water, leading edge up [deg], in (-90, 90) (default 20)")
    t.add_argument("--attack", type=_float("--attack"), default=5.0, metavar="DEG",
                   help="velocity angle below the horizontal [deg], in [-90, 90] (default 5)")
    t.add_argument("--spin", type=_float("--spin"), default=20.0, metavar="REV/S",
                   help="spin about the face normal [rev/s] (default 20)")
    t.add_argument("--height", type=_float("--height"), default=0.001, metavar="M",
                   help="clearance of the lowest point above the water at release [m] (default 0.001)")
    t.add_argument("--heading", type=_float("--heading"), default=0.0, metavar="DEG", help="direction [deg] (default 0)")
    t.add_argument("--stone", default="paper", metavar="NAME|PATH.obj",
                   help="paper (default), disk, clanet, ellipsoid, pebble, or an .obj file in metres")
    t.add_argument("--mass", type=_float("--mass"), default=None, metavar="KG", help="stone mass [kg] (default: from density)")
    t.add_argument("--density", type=_float("--density"), default=None, metavar="KG/M3", help="stone density [kg/m^3]")
    t.add_argument("--force-law", choices=("bocquet", "seed"), default="bocquet", help="water force law (default bocquet)")
    t.add_argument("--c-lift", type=_float("--c-lift"), default=None, help="lift coefficient (default: the law's)")
    t.add_argument("--c-friction", type=_float("--c-friction"), default=None, help="friction coefficient (default: the law's)")
    t.add_argument("--velocity", choices=("body", "local"), default="body",
                   help="velocity the water sees: centre of mass (body, default) or each triangle's v + w x r")
    t.add_argument("--attitude", choices=("free", "fixed"), default="free", help="6-DoF (free) or tilt held (fixed)")
    t.add_argument("--integrator", choices=("euler", "rk4"), default="euler", help="time integrator (default euler)")
    t.add_argument("--duration", type=_float("--duration"), default=5.0, metavar="S", help="simulated time limit [s] (default 5)")
    t.add_argument("--dt", type=_float("--dt"), default=2.5e-4, metavar="S", help="time step in contact [s] (default 2.5e-4)")
    t.add_argument("--max-steps", type=int, default=None, metavar="N",
                   help="step budget (default: enough to spend --duration in the water at --dt; 20000 at the defaults)")
    t.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    t.add_argument("--plot", metavar="PATH", default=None, help="write the side view (PNG/PDF/SVG)")
    t.add_argument("--water", choices=("flat", "field"), default="flat",
                   help="flat water (default, the validated model) or a two-way coupled height field in a "
                        "window that follows the stone (64x64 columns of 1 cm, depth 2 cm)")
    t.add_argument("--water-plot", metavar="PATH", default=None,
                   help="(--water field) write the ripples: shaded top view and 3-D view (PNG/PDF/SVG)")
    t.add_argument("--animate", metavar="PATH.gif", default=None,
                   help="(--water field) write an animation of the stone and the water (GIF)")
    from .cli_search import add_parsers

    add_parsers(sub, _float)
    return p


def _summary(result) -> str:
    lines = [
        f"{result.bounces} bounces over {result.distance:.2f} m; outcome: {result.outcome.replace('_', ' ')} "
        f"after {result.final_time:.2f} s ({result.steps} steps, {result.wall_time:.2f} s wall)",
        f"stone {result.stone_name} ({result.mass * 1e3:.1f} g), force law {result.config.force.law}, "
        f"attitude {result.config.attitude}, integrator {result.config.integrator}, dt {result.config.dt:g} s",
    ]
    if result.contacts:
        lines.append("  #   start [s]  length [ms]   x [m]   tilt in -> out [deg]")
        for i, c in enumerate(result.contacts[:40]):
            lines.append(
                f"{i + 1:3d}   {c.t_start:8.3f}   {1e3 * (c.t_end - c.t_start):9.1f}   {c.x:6.2f}   "
                f"{math.degrees(c.tilt_start):6.1f} -> {math.degrees(c.tilt_end):6.1f}"
            )
        if len(result.contacts) > 40:
            lines.append(f"  ... {len(result.contacts) - 40} more")
    if result.outcome == "step_limit":
        lines.append("note: the step budget ran out while the stone was still in play; raise --max-steps")
    return "\n".join(lines)


def _throw(args) -> int:
    import jax

    jax.config.update("jax_enable_x64", True)  # results match the float64 test suite
    from . import ForceModel, SimConfig, Throw, simulate, water_params
    from .api import resolve_stone
    from .simulate import steps_for

    throw = Throw.from_degrees(speed=args.speed, tilt=args.tilt, attack=args.attack, spin=args.spin,
                               height=args.height, heading=args.heading)
    max_steps = steps_for(args.duration, args.dt) if args.max_steps is None else args.max_steps
    config = SimConfig(dt=args.dt, duration=args.duration, max_steps=max_steps, integrator=args.integrator,
                       attitude=args.attitude, force=ForceModel(law=args.force_law, velocity=args.velocity))
    water = water_params(args.force_law, c_lift=args.c_lift, c_friction=args.c_friction)
    stone, _ = resolve_stone(args.stone, mass=args.mass, density=args.density)
    from ._checks import ParameterError

    for flag, path in (("--plot", args.plot), ("--water-plot", args.water_plot)):
        if path is not None and not str(path).lower().endswith((".png", ".pdf", ".svg")):
            raise ParameterError(f"{flag} must end in .png, .pdf or .svg, got {path!r}")
    if args.animate is not None and not str(args.animate).lower().endswith(".gif"):
        raise ParameterError(f"--animate must end in .gif, got {args.animate!r}")
    if args.water == "flat" and (args.animate or args.water_plot):
        raise ParameterError("--animate and --water-plot need --water field (flat water has no ripples to draw)")
    progress = sys.stderr.isatty() and not args.json
    field = None
    if args.water == "field":
        from .coupled import default_window

        field = default_window()
    # With a field, snapshot the water every 40 steps (10 ms in contact) for the pictures.
    chunk = 40 if (args.animate or args.water_plot) else 1000
    result = simulate(throw, stone, water=water, config=config, progress=progress, water_field=field, chunk=chunk)
    result = dataclasses.replace(result, stone_name=_stone_label(args.stone))
    if args.plot:
        from .plotting import plot_throw

        plot_throw(result, args.plot)
    if args.water_plot:
        from .plotting import plot_water

        plot_water(result, stone, args.water_plot)
    if args.animate:
        from .plotting import animate_throw

        animate_throw(result, stone, args.animate)
    if args.json:
        out = result.to_dict()
        for key in ("plot", "water_plot", "animate"):
            if getattr(args, key):
                out[key] = str(getattr(args, key))
        print(json.dumps(out, allow_nan=False))  # strict JSON: unknown values are null
    else:
        print(_summary(result))
        if result.field:
            w = result.field
            print(f"water: height field {w['shape'][0]}x{w['shape'][1]} columns of {w['spacing'] * 100:g} cm, "
                  f"depth {w['depth'] * 100:g} cm, step {w['time_step'] * 1e3:g} ms, clamp {w['clamp']}; "
                  f"window volume change {w['volume_change']:+.2e}")
        for label, key in (("picture", "plot"), ("ripples", "water_plot"), ("animation", "animate")):
            if getattr(args, key):
                print(f"{label}: {getattr(args, key)}")
    return 0


def _stone_label(stone) -> str:
    import os

    return os.path.basename(str(stone))


def main(argv=None) -> int:
    """Entry point of the ``jaxskip`` command; returns the exit status."""
    args = build_parser().parse_args(argv)
    from ._checks import ParameterError
    from .mesh import MeshError

    try:
        if args.command == "throw":
            return _throw(args)
        from .cli_search import run_optimize, run_sweep_command

        if args.command == "optimize":
            return run_optimize(args)
        if args.command == "sweep":
            return run_sweep_command(args)
    except (ParameterError, MeshError, ValueError) as exc:
        print(f"jaxskip: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except OSError as exc:
        print(f"jaxskip: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    return EXIT_USAGE


if __name__ == "__main__":
    raise SystemExit(main())
