"""``jaxskip optimize`` and ``jaxskip sweep``: the command-line edge of the :mod:`optimize` package.

Same conventions as ``jaxskip throw`` (and its simulation flags, :func:`jaxskip.cli.add_common`): speed in
m/s, angles in degrees, spin in rev/s, converted once; ``--json`` prints exactly one JSON object; bad input
exits with status 2 and a one-line message naming the flag, before anything is compiled or written. A flag
that the chosen method (or sweep kind) does not use is refused, not ignored.
"""

from __future__ import annotations

import math
import sys

from ._checks import ParameterError, check_int
from .cli import (PICTURES, SIM_DEFAULTS, _energy_lines, _float, _int, _say, add_common, check_output, describe,
                  environment, plural, print_json, show_progress, sim_values, simulation)

RANGES = (("speed", "M/S", "speed [m/s]", (3.0, 12.0)), ("tilt", "DEG", "tilt [deg]", (5.0, 45.0)),
          ("attack", "DEG", "attack [deg]", (0.0, 30.0)), ("spin", "REV/S", "spin [rev/s]", (0.0, 20.0)))

METHODS = GRADIENT, PERTURBATION, GRID, RANDOM = ("gradient", "perturbation", "grid", "random")
ASCENTS = (GRADIENT, PERTURBATION)
#: ``optimize`` flags that only some methods use (dest: those methods); given to another method: an error.
METHOD_FLAGS = {"objective": (GRADIENT,), "starts": ASCENTS, "iterations": ASCENTS, "learning_rate": ASCENTS,
                "polish": ASCENTS, "samples": (PERTURBATION,), "horizon": (GRADIENT,), "screen": (GRADIENT,),
                "per_axis": (GRID,),
                "throws": (RANDOM,), "seed": (GRADIENT, PERTURBATION, RANDOM)}
#: Where the command line's default differs from the search function's (the others: the function's).
METHOD_DEFAULTS = {"polish": 256, "per_axis": 6, "screen": 64}
KINDS = ("umin", "domain")
#: ``sweep`` flags by the kinds that use them (``merge`` uses none of them: it reads the shards' spec.json).
SWEEP_FLAGS = {"tilts": KINDS, "attacks": KINDS, "speed": ("domain",), "speed_range": ("umin",),
               "iterations": ("umin",), "spin": KINDS, "chunk_size": KINDS, "shard_index": KINDS,
               "num_shards": KINDS, "progress": KINDS, **dict.fromkeys(SIM_DEFAULTS, KINDS)}


def _only(p, table, flag, text, **kw):
    """A flag that only some methods (kinds) use: its help names them; default None (not given)."""
    p.add_argument(flag, help=f"({', '.join(table[flag[2:].replace('-', '_')])}) {text}", **kw)


def _count(n: int) -> str:
    """A count limit as help text: a power of ten from 10^4 on as ``10^k`` (``10^8``), others as digits."""
    k = len(str(n)) - 1
    return f"10^{k}" if k >= 4 and n == 10 ** k else str(n)


def add_parsers(sub, ranges: bool = True) -> None:
    """Add the ``optimize`` and ``sweep`` subcommands to ``sub``.

    ``ranges``: give the flags' valid ranges in their help, from the constants the checks use (not copied
    by hand). That imports ``optimize`` (and optax, ~0.2 s), which ``jaxskip throw`` does not need: the
    command line asks for them only when it runs ``optimize`` or ``sweep``."""
    if ranges:
        from optimize.bounds import LIMITS
        from optimize.search import (MAX_GRID_POINTS, MAX_ITERATIONS, MAX_PER_AXIS, MAX_SAMPLES, MAX_STARTS,
                                     MAX_STEP, MAX_THROWS)
        from optimize.sweep import MAX_BISECTIONS, limit_text

        spans = {"starts": (1, MAX_STARTS), "iterations": (1, MAX_ITERATIONS), "polish": (0, MAX_THROWS),
                 "samples": (1, MAX_SAMPLES), "per_axis": (2, MAX_PER_AXIS), "throws": (1, MAX_THROWS),
                 "bisections": (1, MAX_BISECTIONS), "screen": (0, MAX_THROWS)}
        span = lambda name: f"[{_count(spans[name][0])}, {_count(spans[name][1])}]"  # noqa: E731
        points = _count(MAX_GRID_POINTS)
    else:  # (help texts that are never shown)
        LIMITS = {name: (math.nan, math.nan, None) for name, *_ in RANGES}
        limit_text = span = lambda name: "range"  # noqa: E731
        points, MAX_STEP = "N", math.nan

    o = sub.add_parser("optimize", help="search for the throw with the most bounces", description=(
        "Search the throw parameters within bounds for the most bounces (true counts from the exact "
        "simulation). Each parameter is searched over --NAME-range LOW HIGH (default: the human box "
        "speed 3-12 m/s, tilt 5-45 deg, attack 0-30 deg, spin 0-20 rev/s) or held with --NAME VALUE, within "
        "the search's limits (each flag's help), which are narrower than jaxskip throw's. "
        "The simulation flags are jaxskip throw's."))
    for name, meta, text, (lo, hi) in RANGES:
        low, high, _ = LIMITS[name]
        g = o.add_mutually_exclusive_group()
        g.add_argument(f"--{name}-range", nargs=2, type=_float, metavar=("LOW", "HIGH"),
                       help=f"search {text} in [LOW, HIGH], within [{low:g}, {high:g}] (default {lo:g} {hi:g})")
        g.add_argument(f"--{name}", type=_float, metavar=meta,
                       help=f"hold {text} at this value, in [{low:g}, {high:g}]")
    o.add_argument("--method", choices=METHODS, default=GRADIENT,
                   help="gradient (optax on the smooth count, default), perturbation (randomised smoothing), "
                        "grid or random (exhaustive baselines); for the most bounces of a free stone, whose count is "
                        "spiky, perturbation or random find more at the same cost (docs/search.md)")
    _only(o, METHOD_FLAGS, "--objective", "what the gradient search ascends (default bounces: the smooth count)",
          choices=("bounces", "distance"))
    _only(o, METHOD_FLAGS, "--starts", f"random starts, in {span('starts')} (default 8)", type=_int, metavar="N")
    _only(o, METHOD_FLAGS, "--iterations", f"gradient: N Adam steps (N + 1 exact evaluations of the starts); "
          f"perturbation: N evaluations of the centres, N - 1 steps between them; in {span('iterations')} (default 20)",
          type=_int, metavar="N")
    _only(o, METHOD_FLAGS, "--learning-rate", f"Adam step in the unconstrained coordinates [-], in (0, {MAX_STEP:g}] (default 0.3)",
          type=_float, metavar="LR")
    _only(o, METHOD_FLAGS, "--polish", f"exact throws sampled near the best throws found, after the ascent, in "
          f"{span('polish')} (default {METHOD_DEFAULTS['polish']}; 0: none). The free stone's count is chaotic: "
          "sampling near the ascent's best usually finds more than the ascent", type=_int, metavar="N")
    _only(o, METHOD_FLAGS, "--screen", f"random exact throws simulated first, the best --starts of them the "
          f"ascent's starts, in {span('screen')} (default {METHOD_DEFAULTS['screen']} or --starts, whichever is more; "
          "0: random starts). A random "
          "start often sinks at once, where the surrogate is flat and the ascent never moves", type=_int, metavar="N")
    _only(o, METHOD_FLAGS, "--samples", f"antithetic pairs of exact throws per start and iteration, in "
          f"{span('samples')} (default 8)", type=_int, metavar="N")
    _only(o, METHOD_FLAGS, "--horizon", "steps the surrogate is differentiated through, in [1, --max-steps] "
          "(default: the whole rollout)", type=_int, metavar="STEPS")
    _only(o, METHOD_FLAGS, "--per-axis", f"grid points per searched parameter, in {span('per_axis')}, at most "
          f"{points} grid points in all (default {METHOD_DEFAULTS['per_axis']})", type=_int, metavar="N")
    _only(o, METHOD_FLAGS, "--throws", f"random throws, in {span('throws')} (default 1000)", type=_int, metavar="N")
    _only(o, METHOD_FLAGS, "--seed", "random seed, >= 0 (default 0)", type=_int)
    add_common(o)

    s = sub.add_parser("sweep", help="magic-angle sweeps: U_min(tilt) or the bounce domain", description=(
        "umin: the minimal speed for a bounce at each tilt (bisection, the tilts of a chunk batched); domain: bounce counts on a "
        "tilt x attack grid at one speed; merge FOLDER... --out DIR: join the folders of several shards (it "
        "takes no other flag but --json and --plot). Defaults: Clanet's aluminium disk, tilt held (high-spin "
        "limit), 65 rev/s, attack 20 deg (docs/physics.md section 4). The work is cut into chunks (default: at "
        "most 8, of ceil(n/8) tilts or grid points each, a domain chunk at least 256 points: a small domain sweep "
        "is one chunk), each written to --out as it finishes: re-running resumes there, and "
        "--shard-index/--num-shards split the chunks between machines."))
    s.add_argument("kind", choices=KINDS + ("merge",))
    s.add_argument("folders", nargs="*", default=[], metavar="FOLDER", help="(merge) the shards' --out folders")
    _only(s, SWEEP_FLAGS, "--tilts", f"tilts, each in {limit_text('tilt')}: N values from A to B, or a "
          "comma list (default 5:60:12)", metavar="A:B:N|A,B,...")
    _only(s, SWEEP_FLAGS, "--attacks", f"attack angles, each in {limit_text('attack')}: as --tilts "
          "(default 20 for umin, 0:60:13 for domain)", metavar="A:B:N|A,B,...")
    _only(s, SWEEP_FLAGS, "--speed", f"speed, in {limit_text('speed')} (default 3.5)", type=_float,
          metavar="M/S")
    _only(s, SWEEP_FLAGS, "--speed-range", f"bisection bracket, within {limit_text('speed')} (default 0.5 8)",
          nargs=2, type=_float, metavar=("LOW", "HIGH"))
    _only(s, SWEEP_FLAGS, "--iterations", f"bisection steps, in {span('bisections')} (default 10)", type=_int,
          metavar="N")
    _only(s, SWEEP_FLAGS, "--spin", f"spin, in {limit_text('spin')} (default 65)", type=_float,
          metavar="REV/S")
    s.add_argument("--out", metavar="DIR", help="folder (its parent must exist) for chunk files and "
                   "result.json/result.csv; re-running resumes there")
    _only(s, SWEEP_FLAGS, "--chunk-size", "work items per chunk file, >= 1: tilts (umin) or grid points (domain) "
          "(default: ceil(items / 8), at least 256 grid points for domain)", type=_int, metavar="N")
    _only(s, SWEEP_FLAGS, "--shard-index", "this machine's shard, in [0, N-1] for --num-shards N (default 0; "
          "needs --out; required when N > 1)", type=_int, metavar="I")
    _only(s, SWEEP_FLAGS, "--num-shards", "machines sharing the sweep, >= 1 (default 1; needs --out)", type=_int,
          metavar="N")
    add_common(s, stone="clanet", attitude="fixed")


def flag_names(args) -> dict:
    """Library parameter names -> this command's flags, where they differ from ``--NAME``."""
    if args.command == "optimize":  # a box parameter is --NAME when held, --NAME-range when searched
        return {name: f"--{name}-range" for name, *_ in RANGES if getattr(args, name) is None}
    return {"tilt": "--tilts", "attack": "--attacks", "out_dir": "--out"}


def _check_used(args, label: str, choice: str, table: dict) -> None:
    for dest, users in table.items():
        value = getattr(args, dest, None)
        if value is not None and choice not in users:
            flag = f"--{dest.replace('_', '-')}"
            if value is False:   # (a BooleanOptionalAction given as --no-NAME: name the flag the user typed)
                flag = f"--no-{dest.replace('_', '-')}"
            raise ParameterError(f"{flag} is not used by {label} (only by {', '.join(users)})")


def _values(text: str, name: str) -> list:
    """``"A:B:N"`` -> N values from A to B; ``"A,B,C"`` -> the list (degrees). Refused, naming the flag: an
    empty text, an empty item (``5,,10``, ``5,``), anything that is not a number (``1_0`` included), more than
    :data:`optimize.sweep.MAX_ANGLES` values."""
    import numpy as np

    from optimize.sweep import MAX_ANGLES

    try:
        if "_" in text or not text.isascii():  # float() and int() read 1_0 as 10 and full-width digits: typos here
            raise ValueError
        if ":" not in text:
            items = text.split(",")
            if any(not v.strip() for v in items):
                raise ValueError
            return [float(v) for v in items]
        a, b, n = text.split(":")
        a, b, n = float(a), float(b), int(n)
        if n < 1 or not (math.isfinite(a) and math.isfinite(b)):
            raise ValueError
    except ValueError:
        raise ParameterError(f"{name} must be A:B:N (N >= 1 values from A to B, finite) or a comma list of numbers such as "
                             f"5,10,20 (no empty items), got {text!r}") from None
    if n > MAX_ANGLES:
        raise ParameterError(f"{name} A:B:N must have N <= {MAX_ANGLES}, got {text!r}")
    if n == 1 and a != b:   # (np.linspace(a, b, 1) is [a]: B was dropped in silence)
        raise ParameterError(f"{name} A:B:1 is one value, but A ({a:g}) and B ({b:g}) differ: give N >= 2 values from A "
                             f"to B, or the one value alone ({a:g}), got {text!r}")
    # rounded so that 5:10:6 gives 5, 6, ... (not 6.000000000000001), but never past A or B: 89.99999999999
    # rounds to 90, outside the tilts' open range
    return np.linspace(a, b, n).round(10).clip(min(a, b), max(a, b)).tolist()


def _default(function, name: str):
    """The default of ``function``'s keyword ``name`` (read from its signature, not copied here)."""
    import inspect

    return inspect.signature(function).parameters[name].default


def run_optimize(args) -> int:
    """Run ``jaxskip optimize`` on the parsed ``args`` (:func:`add_parsers`); returns the exit status, 0.

    The box comes from ``--NAME-range LOW HIGH`` (searched; default :data:`RANGES`) or ``--NAME VALUE``
    (held), in user units (m/s, deg, rev/s); the method's flags (:data:`METHOD_FLAGS`) and the simulation
    flags (:func:`jaxskip.cli.add_common`) are checked before anything is compiled. Prints the best throw and
    the search's cost (``--json``: one JSON object, :meth:`optimize.search.SearchResult.to_dict` with the
    gradient norms, the resolved configuration and the environment); ``--plot`` saves
    :func:`optimize.plot_search`'s picture. Bad input raises :class:`~jaxskip.ParameterError` (the command
    line turns it into exit status 2 and a one-line message).
    """
    _check_used(args, f"--method {args.method}", args.method, METHOD_FLAGS)
    check_output("--plot", args.plot, PICTURES)
    if args.seed is not None:
        check_int("seed", args.seed, minimum=0)
    import jax

    jax.config.update("jax_enable_x64", True)
    from optimize import (EXPLODING, VANISHING, gradient_health, gradient_search, grid_search, make_box,
                          perturbation_search, plot_search, random_search)

    searched, held = {}, {}
    for name, _, _, default in RANGES:
        value, rng = getattr(args, name), getattr(args, f"{name}_range")
        if value is not None:
            held[name] = value
        else:
            searched[name] = default if rng is None else tuple(rng)
    box = make_box(searched, held)
    values = sim_values(args)
    config, water, rigid = simulation(**values)  # validated before compiling
    given = {d: METHOD_DEFAULTS.get(d) if getattr(args, d) is None else getattr(args, d)
             for d, users in METHOD_FLAGS.items() if args.method in users}
    if args.method == GRADIENT:  # the screen picks the starts: at least as many throws as --starts
        starts = given["starts"] if given["starts"] is not None else _default(gradient_search, "starts")
        if args.screen is None:
            given["screen"] = max(METHOD_DEFAULTS["screen"], starts)
        elif 0 < given["screen"] < starts:
            raise ParameterError(f"--screen must be 0 or at least --starts ({starts}): the starts are the best of "
                                 f"the screened throws; got {given['screen']}")
    search = {GRADIENT: gradient_search, PERTURBATION: perturbation_search, GRID: grid_search,
              RANDOM: random_search}[args.method]
    progress = show_progress(args)  # on stderr: stdout keeps its one JSON object (the search says it compiles)
    r = search(box, stone=rigid, config=config, water=water, progress=progress,
               **{d: v for d, v in given.items() if v is not None})
    if args.plot:
        plot_search(r, args.plot)
    health = gradient_health(r)
    command, single = _reproduction(r.best, args, rigid, water, config)
    if args.json:
        out = r.to_dict()
        out["throw_command"] = command
        out["throw_command_bounces"], out["throw_command_distance"] = single.bounces, single.distance
        # (its stone's mechanical energy, as jaxskip throw --json gives it: a count the water's energy made shows)
        out["throw_command_energy"] = single.to_dict()["energy"]
        if health is not None:
            out["gradient_norms"] = health
        # the stone as the user named it (the search was given the loaded RigidStone, which has no name)
        out["settings"] = {**out["settings"], "stone": str(values["stone"])}
        out["config"] = describe(values["stone"], config, water, rigid)
        out["environment"] = environment()
        if args.plot:
            out["plot"] = str(args.plot)
        print_json(out, args)
    else:
        b = r.best
        what = (f"longest distance {r.best_distance:.2f} m ({plural(r.best_bounces, 'bounce')})"
                if r.objective == "distance" else f"best {plural(r.best_bounces, 'bounce')} ({r.best_distance:.2f} m)")
        _say(f"{r.method} search: {what} at speed {b['speed']:.2f} m/s, tilt "
             f"{b['tilt']:.1f} deg, attack {b['attack']:.1f} deg, spin {b['spin']:.1f} rev/s")
        if r.best_cut_off:
            limits = _limits({"config": {"duration": config.duration, "max_steps": config.max_steps}})
            _say(f"  note: that throw was still in play when the run stopped it at {limits}: its count and distance "
                 "are lower bounds (raise them)")
        _say(f"cost: {plural(r.forward_throws, 'exact throw')}, {plural(r.gradient_evals, 'gradient evaluation')}, "
             f"{r.wall_time:.1f} s wall")
        _say(f"to throw it again: {command}")
        for line in _energy_lines(single):   # (a record count may run on energy the default law's water adds)
            _say(f"  {line}")
        if single.bounces != r.best_bounces:
            _say(f"  note: that command counts {plural(single.bounces, 'bounce')} ({single.distance:.2f} m): the search "
                 "counted its throws in batches, whose rounding differs from one throw's, and a long throw's "
                 "count is chaotic down to the last bit")
        polish = [h for h in r.history if h.get("phase") == "polish"]
        if polish:
            ascent = max(h["best"] for h in r.history if h.get("phase") != "polish")
            if r.objective == "bounces":
                _say(f"  the ascent's best: {ascent} bounces; the polish ({len(polish[0]['bounces'])} exact throws "
                     f"near its best throws): {max(polish[0]['bounces'])}")
            else:   # (the distance objective said nothing of what the polish added; a review)
                far = max((d for h in r.history if h.get("phase") != "polish" for d in h.get("distance") or ()
                           if d is not None and math.isfinite(d)), default=None)
                if far is not None:
                    _say(f"  the ascent's farthest: {far:.2f} m; the polish ({len(polish[0]['distance'])} exact throws "
                         f"near its farthest): {max(polish[0]['distance']):.2f} m")
        if health is not None:
            fmt = lambda v: "n/a" if v is None else f"{v:.3g}"  # noqa: E731
            st = health["starts"]
            _say(f"gradient norms (unconstrained units, before clipping): median {fmt(health['median'])}, "
                 f"max {fmt(health['max'])}; of {plural(st['n'], 'start')}, exploding (> {EXPLODING:g}) at some iteration on "
                 f"{st['exploding']}, vanishing (< {VANISHING:g}) at every iteration on {st['vanishing']} and at some "
                 f"iteration on {st['vanishing_some']}")
            if st["exploding"]:
                _say("  an exploding gradient comes from the rollout's chaos, not the count's trend: its step is "
                     "noise (a shorter --horizon tames it; --method perturbation smooths the count instead of "
                     "differentiating it)")
        if args.plot:
            _say(f"picture: {args.plot}")
    return 0


def _reproduction(best: dict, args, rigid, water, config):
    """The ``jaxskip throw`` command line that throws ``best`` (user units, every digit) with this run's
    simulation flags, and that command's result (:func:`jaxskip.simulate`, as ``jaxskip throw`` runs it)."""
    import shlex

    from . import Throw, simulate

    values = {name: float(best[name]) for name, _, _, _ in RANGES}
    words = ["jaxskip", "throw"] + [w for name, v in values.items() for w in (f"--{name}", repr(v))]
    for name in SIM_DEFAULTS:
        given = getattr(args, name, None)
        if given is not None:
            words += [f"--{name.replace('_', '-')}", str(given)]
    single = simulate(Throw.from_degrees(**values), rigid, water=water, config=config)
    return shlex.join(words), single


def run_sweep_command(args) -> int:
    """Run ``jaxskip sweep umin|domain|merge`` on the parsed ``args`` (:func:`add_parsers`); returns the exit
    status, 0.

    ``umin``/``domain``: the sweep's settings (degrees, m/s, rev/s) are validated by
    :func:`optimize.make_spec` and its chunks computed by :func:`optimize.run_sweep` (this shard's, with
    ``--shard-index``/``--num-shards``), resuming in ``--out``; ``merge``: the shards' folders joined into
    ``--out`` (:func:`optimize.merge`). Prints U_min per tilt and the magic angle, or the bounce domain's
    summary (``--json``: one JSON object with ``"complete"``: False while other shards' chunks are missing);
    ``--plot`` saves :func:`optimize.plot_sweep`'s picture. Bad input raises :class:`~jaxskip.ParameterError`
    before anything is compiled or written (the command line turns it into exit status 2).
    """
    _check_used(args, f"sweep {args.kind}", args.kind, SWEEP_FLAGS)
    check_output("--plot", args.plot, PICTURES)
    check_output("--out", args.out)
    if args.kind == "merge":
        if not args.folders or args.out is None:
            raise ParameterError("sweep merge needs the shards' folders and --out DIR")
    else:
        if args.folders:
            raise ParameterError(f"sweep {args.kind} takes no folders (did you mean --out?)")
        if args.out is None and (args.shard_index, args.num_shards) != (None, None):
            raise ParameterError("--shard-index/--num-shards need --out DIR: a shard's chunks are kept there "
                                 "for `jaxskip sweep merge`")
        if args.shard_index is not None and args.num_shards is None:
            raise ParameterError("--shard-index needs --num-shards N (the number of machines sharing the sweep)")
        if args.num_shards is not None and args.num_shards > 1 and args.shard_index is None:
            # (it ran shard 0: a second machine that forgot the flag repeated the first's work; a review)
            raise ParameterError(f"--num-shards {args.num_shards} needs --shard-index I, this machine's shard, in "
                                 f"[0, {args.num_shards - 1}]")
        # (an empty --tilts "" is refused, not taken for the default)
        tilts = _values("5:60:12" if args.tilts is None else args.tilts, "--tilts")
        attacks = _values(("20" if args.kind == "umin" else "0:60:13") if args.attacks is None else args.attacks,
                          "--attacks")
    import jax

    jax.config.update("jax_enable_x64", True)
    from optimize import make_spec, merge, plot_sweep, run_sweep
    from optimize.sweep import SCAN_SPEEDS, _chunks, bracket_digits

    if args.kind == "merge":
        result = merge(args.folders, args.out)
    else:
        given = {d: getattr(args, d) for d in SWEEP_FLAGS
                 if d not in ("tilts", "attacks", "shard_index", "num_shards", "progress")
                 and getattr(args, d) is not None}
        spec = make_spec(args.kind, tilts=tilts, attacks=attacks, **given)  # everything validated here
        progress = show_progress(args)  # on stderr: stdout keeps its one JSON object
        # given values are checked by run_sweep (--num-shards 0 is refused, not taken for 1)
        shard = 0 if args.shard_index is None else args.shard_index
        shards = 1 if args.num_shards is None else args.num_shards
        result = run_sweep(spec, args.out, shard_index=shard, num_shards=shards, progress=progress)
        if result is None:
            n_chunks = len(_chunks(spec))
            msg = (f"shard {shard}/{shards} done; chunks in {args.out}; join the shards with "
                   "`jaxskip sweep merge FOLDER... --out DIR`")
            if shard >= n_chunks:
                msg = (f"shard {shard}/{shards} has no chunk to compute: the sweep has only {n_chunks} (for the "
                       f"shards below {n_chunks}); a smaller --chunk-size cuts it into more")
            no_plot = "no picture: the sweep is not complete here (give --plot to the merge)"
            if args.json:
                print_json({"complete": False, "out": args.out, "shard_index": shard, "num_shards": shards,
                            "chunks": n_chunks, "chunks_of_this_shard": len(range(shard, n_chunks, shards)),
                            **({"plot": None} if args.plot else {})}, args)
                if args.plot:
                    print(f"jaxskip: note: {no_plot}", file=sys.stderr)
            else:
                _say(msg + (f"\n{no_plot}" if args.plot else ""))
            return 0
    if args.plot:
        plot_sweep(result, args.plot)
    if args.json:
        # (a merge joins chunks computed elsewhere: the environment here says nothing about them)
        here = {} if args.kind == "merge" else {"environment": environment()}
        print_json({"complete": True, **({"out": args.out} if args.out else {}), **result,
                    **({"plot": args.plot} if args.plot else {}), **here}, args)
        return 0
    spec = result["spec"]
    if spec["kind"] == "umin":
        low, high = spec["speed_range"]
        # U_min to the bisection's bracket (2 decimals hid the curve near its minimum: 1.74 / 1.75 / 1.76 m/s where
        # the bracket was 0.8 mm/s; a review)
        dec = bracket_digits(result["resolution"]) if result.get("resolution") else 2
        failed = result.get("diverged") or [0] * len(spec["tilts"])
        cut = result.get("cut_off") or [0] * len(spec["tilts"])
        monotone = result.get("monotone") or [1] * len(spec["tilts"])
        for t, u, n_low, n_failed, n_cut, steady in zip(spec["tilts"], result["umin"], result["bounces_at_low"], failed,
                                                        cut, monotone):
            if n_failed:
                shown = f"no U_min: {n_failed} of its throws (scan and bisection) diverged (take a smaller --dt)"
            elif n_cut:
                shown = (f"no U_min: {n_cut} of its throws (scan and bisection) were still in their first contact or flight "
                         f"when {_limits(spec)} stopped them (raise them)")
            elif u is None:
                shown = f"no bounce at the {SCAN_SPEEDS + 2} speeds thrown from {low:g} to {high:g} m/s"
            elif n_low > 0:
                shown = f"U_min <= {low:g} m/s (bounces at the bracket's low end)"
            else:
                shown = f"U_min {u:.{dec}f} m/s"
            if u is not None and not steady:
                shown += " (not monotone: a faster throw failed to bounce; the lowest bouncing speed found)"
            _say(f"tilt {t:6.1f} deg: {shown}")
        if result["best_tilt"] is not None:
            u, res = result["best_umin"], result["resolution"]
            if u <= low:
                tied = [f"{t:g}" for t, n in zip(spec["tilts"], result["bounces_at_low"]) if n > 0]
                where = (f"it bounces at the bracket's low end: U_min <= {low:g} m/s, as at tilts {', '.join(tied)} "
                         f"deg; the minimum lies among them (lower --speed-range)")
            else:
                # the bisection's answer is its final bracket's top (a speed that bounces): the true value lies
                # within one bracket width below it
                digits = bracket_digits(res)
                where = (f"bisection: the true U_min lies in ({u - res:.{digits}f}, {u:.{digits}f}] m/s, a bracket "
                         f"of {res:.2g} m/s")
            tied = [f"{t:g}" for t in result["tied_tilts"]]
            tie = bool(tied)   # the first of equal answers is not a minimum (nor is there a parabola: assemble)
            if tie:
                _say(f"magic angle: no single minimum: tilts {', '.join(tied)} deg tie at U_min {u:.{dec}f} m/s ({where}; "
                     "more --iterations narrow the bracket)")
            elif u <= low:   # (an upper bound, not a value: "U_min 7.90 m/s (... U_min <= 7.9 m/s)"; a review)
                _say(f"magic angle: {result['best_tilt']:g} deg, U_min <= {low:g} m/s ({where})")
            else:
                _say(f"magic angle: {result['best_tilt']:g} deg, U_min {u:.{dec}f} m/s ({where})")
            if result["best_tilt_fit"] is not None:
                _say(f"  between grid points (parabola through its neighbours): {result['best_tilt_fit']:.1f} deg, "
                     f"U_min {result['best_umin_fit']:.{dec}f} m/s")
            unknown = [f"{t:g}" for t, v, n_failed, n_cut in zip(spec["tilts"], result["umin"], failed, cut)
                       if v is None and (n_failed or n_cut)]
            if unknown:
                many = len(unknown) > 1
                _say(f"  (tilt{'s' if many else ''} {', '.join(unknown)} deg {'have' if many else 'has'} no U_min, "
                     "above: the minimum may lie there)")
    else:
        import numpy as np

        b = np.asarray(result["bounces"])
        failed = np.asarray(result.get("diverged") or np.zeros(b.shape), dtype=bool)
        cut = np.asarray(result.get("cut_off") or np.zeros(b.shape), dtype=bool)
        _say(f"bounce domain at {spec['speed']:g} m/s: {int((b > 0).sum())} of {b.size} (tilt, attack) pairs bounce;"
             f" most bounces {int(b.max())}" + (f"; {int(failed.sum())} diverged (their counts mean nothing: take a "
                                                 f"smaller --dt)" if failed.any() else "")
             + (f"; {int(cut.sum())} still skipping when {_limits(spec)} stopped them (their counts are lower "
                "bounds: raise them)" if cut.any() else ""))
    if args.out:
        _say(f"results: {args.out}/result.json, {args.out}/result.csv")
    if args.plot:
        _say(f"picture: {args.plot}")
    return 0


def _limits(spec: dict) -> str:
    """The run's limits on a throw, as flags: ``--duration 5 s or --max-steps 20250``."""
    return f"--duration {spec['config']['duration']:g} s or --max-steps {spec['config']['max_steps']}"


__all__ = ["add_parsers", "flag_names", "run_optimize", "run_sweep_command"]
