"""``jaxskip optimize`` and ``jaxskip sweep``: the command-line edge of the :mod:`optimize` package.

Same conventions as ``jaxskip throw``: speed in m/s, angles in degrees, spin in rev/s, converted once;
``--json`` prints exactly one JSON object; bad input exits with status 2 and a one-line message.
"""

from __future__ import annotations

import json
import sys

from ._checks import ParameterError

RANGES = (("speed", "M/S", "speed [m/s]", (3.0, 12.0)), ("tilt", "DEG", "tilt [deg]", (5.0, 45.0)),
          ("attack", "DEG", "attack [deg]", (0.0, 30.0)), ("spin", "REV/S", "spin [rev/s]", (0.0, 20.0)))


def add_parsers(sub, number) -> None:
    """Add the ``optimize`` and ``sweep`` subcommands to ``sub`` (``number(name)`` parses a float)."""
    o = sub.add_parser("optimize", help="search for the throw with the most bounces", description=(
        "Search the throw parameters within bounds for the most bounces (true counts from the exact "
        "simulation). Each parameter is searched over --NAME-range LOW HIGH (default: the human box "
        "speed 3-12 m/s, tilt 5-45 deg, attack 0-30 deg, spin 0-20 rev/s) or held with --NAME VALUE."))
    for name, meta, text, (lo, hi) in RANGES:
        g = o.add_mutually_exclusive_group()
        g.add_argument(f"--{name}-range", nargs=2, type=number(f"--{name}-range"), metavar=("LOW", "HIGH"),
                       help=f"search {text} in [LOW, HIGH] (default {lo:g} {hi:g})")
        g.add_argument(f"--{name}", type=number(f"--{name}"), metavar=meta, help=f"hold {text} at this value")
    o.add_argument("--method", choices=("gradient", "perturbation", "grid", "random"), default="gradient",
                   help="gradient (optax on the smooth count, default), perturbation (randomised smoothing), "
                        "grid or random (exhaustive baselines)")
    o.add_argument("--objective", choices=("bounces", "distance"), default="bounces",
                   help="what the gradient search ascends (default bounces: the smooth count)")
    o.add_argument("--starts", type=int, default=8, metavar="N", help="random starts (default 8)")
    o.add_argument("--iterations", type=int, default=20, metavar="N", help="optimiser steps (default 20)")
    o.add_argument("--learning-rate", type=number("--learning-rate"), default=0.3, metavar="LR",
                   help="Adam step in the unconstrained coordinates (default 0.3)")
    o.add_argument("--polish", type=int, default=256, metavar="N",
                   help="(gradient, perturbation) exact throws sampled near the best throws found, after the "
                        "ascent (default 256; 0: none). The free stone's count is chaotic: sampling near the "
                        "ascent's best finds more than the ascent (21 -> 51 bounces in the default search)")
    o.add_argument("--samples", type=int, default=8, metavar="N",
                   help="(perturbation) antithetic pairs of exact throws per start and iteration (default 8)")
    o.add_argument("--horizon", type=int, default=None, metavar="STEPS",
                   help="(gradient) steps the surrogate is differentiated through (default: the whole rollout)")
    o.add_argument("--per-axis", type=int, default=6, metavar="N", help="grid points per searched parameter (grid)")
    o.add_argument("--throws", type=int, default=1000, metavar="N", help="random throws (random)")
    o.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    _common(o)

    s = sub.add_parser("sweep", help="magic-angle sweeps: U_min(tilt) or the bounce domain", description=(
        "umin: the minimal speed for a bounce at each tilt (batched bisection); domain: bounce counts on a "
        "tilt x attack grid at one speed; merge FOLDER...: join the folders of several shards. Defaults: "
        "Clanet's aluminium disk, tilt held (high-spin limit), 65 rev/s, attack 20 deg (physics.md section 4)."))
    s.add_argument("kind", choices=("umin", "domain", "merge"))
    s.add_argument("folders", nargs="*", metavar="FOLDER", help="(merge) the shards' --out folders")
    s.add_argument("--tilts", default="5:60:12", metavar="A:B:N|A,B,...",
                   help="tilts [deg]: N values from A to B, or a list (default 5:60:12)")
    s.add_argument("--attacks", default=None, metavar="A:B:N|A,B,...",
                   help="attack angles [deg] (default 20 for umin, 0:60:13 for domain)")
    s.add_argument("--speed", type=number("--speed"), default=3.5, metavar="M/S", help="(domain) speed (default 3.5)")
    s.add_argument("--speed-range", nargs=2, type=number("--speed-range"), default=(0.5, 8.0),
                   metavar=("LOW", "HIGH"), help="(umin) bisection bracket [m/s] (default 0.5 8)")
    s.add_argument("--iterations", type=int, default=10, metavar="N", help="(umin) bisection steps (default 10)")
    s.add_argument("--spin", type=number("--spin"), default=65.0, metavar="REV/S", help="spin (default 65)")
    s.add_argument("--out", metavar="DIR", default=None,
                   help="folder for chunk files and result.json/result.csv; re-running resumes there")
    s.add_argument("--chunk-size", type=int, default=None, metavar="N", help="work items per chunk file")
    s.add_argument("--shard-index", type=int, default=0, metavar="I", help="this machine's shard (default 0)")
    s.add_argument("--num-shards", type=int, default=1, metavar="N", help="machines sharing the sweep (default 1)")
    _common(s, stone="clanet", attitude="fixed")


def _common(p, stone="paper", attitude="free"):
    p.add_argument("--stone", default=stone, metavar="NAME|PATH.obj", help=f"stone (default {stone})")
    p.add_argument("--attitude", choices=("free", "fixed"), default=attitude,
                   help=f"6-DoF (free) or tilt held (fixed) (default {attitude})")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout")
    p.add_argument("--plot", metavar="PATH", default=None, help="write a picture (PNG/PDF/SVG)")


def _check_plot(path):
    if path is not None and not str(path).lower().endswith((".png", ".pdf", ".svg")):
        raise ParameterError(f"--plot must end in .png, .pdf or .svg, got {path!r}")


def _values(text: str, name: str) -> list:
    """``"A:B:N"`` -> N values from A to B; ``"A,B,C"`` -> the list (degrees)."""
    import numpy as np

    try:
        if ":" in text:
            a, b, n = text.split(":")
            n = int(n)
            if n < 1:
                raise ValueError
            return np.linspace(float(a), float(b), n).round(10).tolist()
        return [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise ParameterError(f"{name} must be A:B:N (N >= 1) or a comma list of numbers, got {text!r}") from None


def run_optimize(args) -> int:
    import dataclasses

    import jax

    jax.config.update("jax_enable_x64", True)
    from optimize import (EXPLODING, VANISHING, gradient_health, gradient_search, grid_search, make_box, perturbation_search,
                          plot_search, random_search)

    from . import SimConfig
    from .api import resolve_stone

    _check_plot(args.plot)
    searched, held = {}, {}
    for name, _, _, default in RANGES:
        value, rng = getattr(args, name), getattr(args, f"{name}_range")
        if value is not None:
            held[name] = value
        else:
            searched[name] = default if rng is None else tuple(rng)
    box = make_box(searched, held)
    resolve_stone(args.stone)  # validate before compiling
    config = SimConfig(attitude=args.attitude)
    progress = sys.stderr.isatty() and not args.json
    if args.method == "gradient":
        r = gradient_search(box, objective=args.objective, stone=args.stone, config=config, starts=args.starts,
                            iterations=args.iterations, learning_rate=args.learning_rate, seed=args.seed,
                            polish=args.polish, horizon=args.horizon, progress=progress)
    elif args.method == "perturbation":
        r = perturbation_search(box, stone=args.stone, config=config, starts=args.starts,
                                iterations=args.iterations, learning_rate=args.learning_rate, seed=args.seed,
                                samples=args.samples, polish=args.polish, progress=progress)
    elif args.method == "grid":
        r = grid_search(box, per_axis=args.per_axis, stone=args.stone, config=config, progress=progress)
    else:
        r = random_search(box, throws=args.throws, stone=args.stone, config=config, seed=args.seed,
                          progress=progress)
    if args.plot:
        plot_search(r, args.plot)
    health = gradient_health(r)
    if args.json:
        out = r.to_dict()
        if health is not None:
            out["gradient_norms"] = health
        out["config"] = {"stone": args.stone, "attitude": args.attitude, **{
            k: v for k, v in dataclasses.asdict(config).items() if k in ("dt", "max_steps", "duration")}}
        if args.plot:
            out["plot"] = str(args.plot)
        print(json.dumps(out, allow_nan=False))
    else:
        b = r.best
        print(f"{r.method} search: best {r.best_bounces} bounces at speed {b['speed']:.2f} m/s, tilt "
              f"{b['tilt']:.1f} deg, attack {b['attack']:.1f} deg, spin {b['spin']:.1f} rev/s")
        print(f"cost: {r.forward_throws} exact throws, {r.gradient_evals} gradient evaluations, "
              f"{r.wall_time:.1f} s wall")
        polish = [h for h in r.history if h.get("phase") == "polish"]
        if polish:
            ascent = max(h["best"] for h in r.history if h.get("phase") != "polish")
            print(f"  the ascent's best: {ascent} bounces; the polish ({len(polish[0]['bounces'])} exact throws near "
                  f"its best throws): {max(polish[0]['bounces'])}")
        if health is not None:
            fmt = lambda v: "n/a" if v is None else f"{v:.3g}"  # noqa: E731
            st = health["starts"]
            print(f"gradient norms (unconstrained units, before clipping): median {fmt(health['median'])}, "
                  f"max {fmt(health['max'])}; exploding (> {EXPLODING:g}) on {st['exploding']} of {st['n']} starts, "
                  f"vanishing (< {VANISHING:g}) on {st['vanishing']}")
            if st["exploding"]:
                print("  an exploding gradient comes from the rollout's chaos, not the count's trend: its step is "
                      "noise (a shorter --horizon tames it; --method perturbation smooths the count instead of "
                      "differentiating it)")
        if args.plot:
            print(f"picture: {args.plot}")
    return 0


def run_sweep_command(args) -> int:
    import jax

    jax.config.update("jax_enable_x64", True)
    from optimize import make_spec, merge, plot_sweep, run_sweep

    from .api import resolve_stone

    _check_plot(args.plot)
    if args.kind == "merge":
        if not args.folders or args.out is None:
            raise ParameterError("sweep merge needs the shards' folders and --out DIR")
        result = merge(args.folders, args.out)
    else:
        if args.folders:
            raise ParameterError(f"sweep {args.kind} takes no folders (did you mean --out?)")
        tilts = _values(args.tilts, "--tilts")
        default_attacks = "20" if args.kind == "umin" else "0:60:13"
        attacks = _values(args.attacks or default_attacks, "--attacks")
        spec = make_spec(args.kind, tilts=tilts, attacks=attacks, speed=args.speed,
                         speed_range=tuple(args.speed_range), iterations=args.iterations, spin=args.spin,
                         stone=args.stone, attitude=args.attitude, chunk_size=args.chunk_size)
        resolve_stone(args.stone)
        progress = sys.stderr.isatty() and not args.json
        result = run_sweep(spec, args.out, shard_index=args.shard_index, num_shards=args.num_shards,
                           progress=progress)
        if result is None:
            msg = (f"shard {args.shard_index}/{args.num_shards} done; chunks in {args.out}; join the shards with "
                   "`jaxskip sweep merge FOLDER... --out DIR`")
            print(json.dumps({"complete": False, "out": args.out}) if args.json else msg)
            return 0
    if args.plot:
        plot_sweep(result, args.plot)
    if args.json:
        print(json.dumps({"complete": True, **result, **({"plot": args.plot} if args.plot else {})}, allow_nan=False))
        return 0
    spec = result["spec"]
    if spec["kind"] == "umin":
        for t, u in zip(spec["tilts"], result["umin"]):
            shown = f"> {spec['speed_range'][1]:g} (no bounce)" if u is None else f"{u:.2f}"
            print(f"tilt {t:6.1f} deg: U_min {shown} m/s")
        if result["best_tilt"] is not None:
            print(f"magic angle: {result['best_tilt']:g} deg, U_min {result['best_umin']:.2f} m/s "
                  f"(+- {result['resolution']:.2g} m/s)")
            if result["best_tilt_fit"] is not None:
                print(f"  between grid points (parabola through its neighbours): {result['best_tilt_fit']:.1f} deg, "
                      f"U_min {result['best_umin_fit']:.2f} m/s")
    else:
        import numpy as np

        b = np.asarray(result["bounces"])
        print(f"bounce domain at {spec['speed']:g} m/s: {int((b > 0).sum())} of {b.size} (tilt, attack) pairs bounce;"
              f" most bounces {int(b.max())}")
    if args.out:
        print(f"results: {args.out}/result.json, {args.out}/result.csv")
    if args.plot:
        print(f"picture: {args.plot}")
    return 0


__all__ = ["add_parsers", "run_optimize", "run_sweep_command"]
