"""Command line: ``jaxskip throw [options]`` (also ``python -m jaxskip``).

User units at this edge only: speed m/s, angles degrees, spin rev/s; converted
once into :class:`jaxskip.Throw` (SI). Bad input exits with status 2 and a
one-line message naming the flag, before anything is compiled or written.
The simulation flags (stone, force law, time step, ...) are shared by every
subcommand: :func:`add_common` defines them, :func:`simulation` builds them.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import re
import sys
import warnings

from ._checks import ParameterError, check_range
from ._files import STDOUT, writing
from ._text import plural
from ._progress import LOG_INTERVAL
from .body import DENSITY_RANGE
from .forces import COEFFICIENT_MAX, DEFAULT_COEFFICIENTS, VELOCITIES
from .simulate import DIVERGED_SPEED, MAX_BOUNCE_CLEARANCE, MAX_DT, MAX_STEPS, DivergedWarning, SimConfig
from .throw import MAX_HEADING, MAX_HEIGHT, MAX_SPEED, MAX_SPIN_REVS
from .settings import SIM_DEFAULTS, describe, environment, simulation  # noqa: F401 (shared with cli_search)

EXIT_USAGE = 2
EXIT_FAILED = 1  # valid input, failed run (a throw that diverged)
PICTURES = (".png", ".pdf", ".svg")

# A value that starts like a negative number: any notation Python's float() reads (e-notation, -inf, -nan),
# and the sweeps' lists and ranges (-10,10 or -10:10:3). argparse's own pattern (r'^-\d+$|^-\d*\.\d+$')
# takes "--tilt -1e1" or "--tilts -10:10:3" for a flag and fails with "expected one argument"; no flag
# of jaxskip starts with a digit, a dot, "inf" or "nan".
_NEGATIVE_NUMBER = re.compile(r"^-(\d|\.\d|inf|nan)", re.IGNORECASE)


class _Parser(argparse.ArgumentParser):
    def __init__(self, *args, **kwargs):
        kwargs.setdefault("allow_abbrev", False)  # `--spe 3` is a typo, not --speed (nor --spin)
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE_NUMBER   # (argparse reads this attribute; no flag looks like one)

    def error(self, message):  # argparse's own errors: same style, one line, exit 2
        if "required: command" in message:  # bare `jaxskip`: show what there is to do
            self.print_help(sys.stderr)
            print(f"jaxskip: error: {message}", file=sys.stderr)
        else:
            print(f"jaxskip: error: {message} (see '{self.prog} --help')", file=sys.stderr)
        raise SystemExit(EXIT_USAGE)


def _version() -> str:
    """``jaxskip X (jax Y, Python Z)`` for ``--version`` (the versions as installed)."""
    import platform
    from importlib import metadata

    from . import __version__

    try:
        jax_version = metadata.version("jax")
    except metadata.PackageNotFoundError:  # pragma: no cover - jax is a dependency
        jax_version = "not installed"
    return f"jaxskip {__version__} (jax {jax_version}, Python {platform.python_version()})"


def _number(text: str) -> float:
    """``text`` as a float, as Python's ``float()`` reads it but for digit-group underscores and non-ASCII
    digits: ``1_0`` is a typo on a command line far more often than ten, and ``float()`` reads full-width
    digits too. Raises ValueError."""
    if "_" in text or not text.isascii():
        raise ValueError(text)
    return float(text)


def _float(text: str) -> float:
    """argparse ``type`` for a decimal flag: :func:`_number`, or argparse's one-line error, which names the
    flag itself (``argument --speed: must be a number, got '1_0'``)."""
    try:
        return _number(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"must be a number, got {text!r}") from None


def _int(text: str) -> int:
    """argparse ``type`` for a count flag: ASCII digits with an optional sign, nothing else (``int()`` also reads
    ``1_0`` as 10, full-width digits and surrounding spaces)."""
    if not re.fullmatch(r"[+-]?[0-9]+", text):
        raise argparse.ArgumentTypeError(f"must be a whole number, got {text!r}")
    return int(text)


def add_common(p, *, stone="paper", attitude="free", plot="write a picture (PNG/PDF/SVG)"):
    """The simulation flags and ``--json``/``--plot``; every simulation flag defaults to None (not given),
    ``stone``/``attitude`` only name the default in the help."""
    p.add_argument("--stone", metavar="NAME|PATH.obj",
                   help="paper (the seed paper's 38-triangle flat stone), disk (8 cm stone disk), clanet (Clanet's "
                        "5 cm aluminium disk), ellipsoid (flattened ellipsoid), pebble (seeded irregular pebble), or "
                        f"an .obj file in metres (default {stone})")
    m = p.add_mutually_exclusive_group()
    density = f"[{DENSITY_RANGE[0]:g}, {DENSITY_RANGE[1]:g}]"
    m.add_argument("--mass", type=_float, metavar="KG",
                   help=f"stone mass [kg], such that the density is in {density} kg/m^3 (default: from the density)")
    m.add_argument("--density", type=_float, metavar="KG/M3",
                   help=f"stone density [kg/m^3], in {density} (default: the stone's own)")
    p.add_argument("--force-law", choices=("bocquet", "seed"), help="water force law (default bocquet)")
    for name in ("lift", "friction"):
        laws = ", ".join(f"{DEFAULT_COEFFICIENTS[law]['c_' + name]:g} for {law}" for law in ("bocquet", "seed"))
        p.add_argument(f"--c-{name}", type=_float,
                       help=f"{name} coefficient [-], in [0, {COEFFICIENT_MAX:g}] (default: the law's, {laws})")
    p.add_argument("--velocity", choices=VELOCITIES,
                   help="velocity the water sees: centre of mass (body, default), each triangle's v + w x r "
                        "(local), or the centre of mass's for the pressure and friction and each triangle's for the "
                        "lift's loading (passive: the water never adds energy; Bocquet's law only)")
    p.add_argument("--attitude", choices=("free", "fixed"),
                   help=f"6-DoF (free) or tilt held (fixed) (default {attitude})")
    p.add_argument("--integrator", choices=("euler", "rk4"), help="time integrator (default euler)")
    p.add_argument("--duration", type=_float, metavar="S",
                   help="simulated time limit [s], >= --dt (default 5)")
    p.add_argument("--dt", type=_float, metavar="S",
                   help=f"time step in contact [s], in (0, {MAX_DT:g}] (default 2.5e-4; above 1e-3 answers are "
                        "unconverged: a warning says so)")
    p.add_argument("--max-steps", type=_int, metavar="N",
                   help=f"step budget, in [1, {MAX_STEPS}] (default: enough to spend --duration in the water at "
                        f"--dt; {SimConfig().max_steps} at the defaults)")
    p.add_argument("--bounce-clearance", type=_float, metavar="M",
                   help=f"what counts as a bounce: the height [m] the stone's lowest point must rise above the water "
                        f"after a contact, in (0, {MAX_BOUNCE_CLEARANCE:g}] (default {SIM_DEFAULTS['bounce_clearance']:g};"
                        " the magic angle moves with it: docs/model.md)")
    p.add_argument("--json", action="store_true", help="print one JSON object on stdout (progress goes to stderr)")
    p.add_argument("--progress", action=argparse.BooleanOptionalAction,
                   help="a progress line on stderr: --progress also when stderr is a file or a pipe (a line every "
                        f"{LOG_INTERVAL:g} s, for a log), --no-progress never (default: on a terminal only)")
    p.add_argument("--plot", metavar="PATH", help=plot)


def show_progress(args) -> bool:
    """Whether to show progress on stderr: ``--progress``/``--no-progress`` if given, else whether stderr is a
    terminal (a redirected stderr is a log, read later: ``--progress`` asks for one there too)."""
    return sys.stderr.isatty() if args.progress is None else args.progress


def sim_values(args) -> dict:
    """The simulation flags' values: given, else :data:`SIM_DEFAULTS`."""
    return {k: v if getattr(args, k, None) is None else getattr(args, k) for k, v in SIM_DEFAULTS.items()}


def check_output(flag: str, path, suffixes=None) -> None:
    """Refuse, before any work, an output path that cannot be written: a wrong suffix, a folder that does not
    exist, a folder where a file goes (or a file where a folder goes: ``suffixes`` None)."""
    if path is None:
        return
    if not str(path).strip():   # "" means the current folder to pathlib: a sweep's files landed there
        raise ParameterError(f"{flag} must be a {'file' if suffixes else 'folder'} path, got {path!r}")
    if suffixes and not str(path).lower().endswith(suffixes):
        ends = " or ".join(filter(None, [", ".join(suffixes[:-1]), suffixes[-1]]))
        raise ParameterError(f"{flag} must end in {ends}, got {path!r}")
    if suffixes and not os.path.splitext(os.path.basename(path))[1]:  # '.pdf': matplotlib wrote '.pdf.png'
        raise ParameterError(f"{flag} needs a file name before its suffix, such as 'out{os.path.basename(path)}', "
                             f"got {path!r}")
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise ParameterError(f"{flag} {path!r}: the folder {folder!r} does not exist")
    if os.path.exists(path) and os.path.isdir(path) == bool(suffixes):
        raise ParameterError(f"{flag} {path!r} is {'a folder' if suffixes else 'a file, not a folder'}")
    if not os.access(path if os.path.isdir(path) else folder, os.W_OK):
        raise ParameterError(f"{flag} {path!r}: cannot write there (no permission)")
    _probe(flag, path, folder, bool(suffixes))


def _probe(flag: str, path, folder: str, is_file: bool) -> None:
    """Write-test ``path`` (a file) or the folder that will hold it, leaving nothing behind: the permission
    bits do not tell everything (``/proc``, a read-only mount, root), and a failure after the simulation
    lost its results."""
    import tempfile

    try:
        if is_file:
            existed = os.path.exists(path)
            open(path, "ab").close()        # appends nothing: an existing file is unchanged
            if not existed:
                os.unlink(path)
        else:
            fd, probe = tempfile.mkstemp(dir=path if os.path.isdir(path) else folder, prefix=".jaxskip-probe-")
            os.close(fd)
            os.unlink(probe)
    except OSError as exc:
        raise ParameterError(f"{flag} {str(path)!r}: cannot write there ({exc.strerror or exc})") from None


def _say(text: str) -> None:
    """Print ``text`` (one line or several) on stdout, flushed at once, so that a full disk under a
    redirected stdout is reported as ``cannot write standard output`` here, not at the interpreter's exit."""
    with writing(STDOUT):
        print(text)
        sys.stdout.flush()


def _finite(obj):
    """``obj`` with every non-finite float (NaN, inf) replaced by None: strict JSON."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v) for v in obj]
    return obj


def print_json(obj, args=None) -> None:
    """Print one strict JSON object on stdout (values that are not finite are null). With the command's
    ``args``, the object ends with ``warnings``: each warning the run printed on stderr, as
    ``{"category": "AccuracyWarning", "message": text}`` (empty: none), so that a pipeline that keeps only
    stdout still knows an answer is unconverged or beyond a stability bound."""
    if args is not None:
        obj = {**obj, "warnings": list(getattr(args, "_warnings", []))}
    _say(json.dumps(_finite(obj), allow_nan=False))


def build_parser(argv=None) -> argparse.ArgumentParser:
    """The ``jaxskip`` parser. ``argv`` (default ``sys.argv[1:]``) only decides whether the ``optimize`` and
    ``sweep`` help texts need their ranges (which import the search package: ``throw`` does without)."""
    p = _Parser(prog="jaxskip", description="Differentiable stone-skipping simulator. Start with `jaxskip throw` "
                "(a default throw); `jaxskip COMMAND --help` lists a command's options.")
    p.add_argument("--version", action="version", version=_version())
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)
    p.commands = sub.choices  # name -> the command's parser (its errors point to its own --help)
    t = sub.add_parser("throw", help="simulate one throw (flat water, or a coupled height field: --water field)",
                       description="Simulate one throw. With no options: a good default throw that skips many times.")
    t.add_argument("--speed", type=_float, default=8.0, metavar="M/S",
                   help=f"speed [m/s], in (0, {MAX_SPEED:g}] (default 8)")
    t.add_argument("--tilt", type=_float, default=20.0, metavar="DEG",
                   help="face angle to the water, leading edge up [deg], in (-90, 90) (default 20)")
    t.add_argument("--attack", type=_float, default=5.0, metavar="DEG",
                   help="velocity angle below the horizontal at release [deg], in [-90, 90] (default 5; Clanet's "
                        "beta is this angle at impact, which gravity steepens: by under ~0.6 deg from the default "
                        "--height at most speeds, more for slow or grazing throws)")
    t.add_argument("--spin", type=_float, default=20.0, metavar="REV/S",
                   help=f"spin about the face normal [rev/s], + is counter-clockwise seen from above, in "
                        f"[{-MAX_SPIN_REVS:g}, {MAX_SPIN_REVS:g}] (default 20)")
    t.add_argument("--height", type=_float, default=0.001, metavar="M",
                   help=f"clearance of the lowest point above the water at release [m], in [0, {MAX_HEIGHT:g}] "
                        "(default 0.001)")
    t.add_argument("--heading", type=_float, default=0.0, metavar="DEG",
                   help=f"direction of travel [deg], counter-clockwise from +x seen from above, in "
                        f"[-{MAX_HEADING:g}, {MAX_HEADING:g}] (default 0)")
    add_common(t, plot="write the side view (PNG/PDF/SVG)")
    t.add_argument("--water", choices=("flat", "field"), default="flat",
                   help="flat water (default, the validated model) or a two-way coupled height field in a "
                        "window that follows the stone (64x64 columns of 1 cm, depth 2 cm; stones up to 0.64 m across)")
    t.add_argument("--water-plot", metavar="PATH", default=None,
                   help="(--water field) write the ripples: shaded top view and 3-D view (PNG/PDF/SVG)")
    t.add_argument("--animate", metavar="PATH.gif", default=None,
                   help="(--water field) write an animation of the stone and the water (GIF)")
    t.add_argument("--trajectory", metavar="PATH.csv|.json", default=None,
                   help="write the motion as evenly spaced frames for animation or other tools: time, position, "
                        "quaternion (w, x, y, z), velocity, in water (SI); the stone in the body frame the "
                        "quaternions rotate goes beside it (PATH.stone.obj); z up; the last frame is the run's end "
                        "(the outcome), off the frame grid")
    t.add_argument("--fps", type=_float, default=None, metavar="N",
                   help="(--trajectory) frames per second, in (0, 10000] (default 60; a stone spinning faster "
                        "than a quarter turn a frame is warned of, with the rate that would show it)")
    from .cli_search import add_parsers

    words = [a for a in (sys.argv[1:] if argv is None else argv) if not a.startswith("-")]
    add_parsers(sub, ranges=not words or words[0] in ("optimize", "sweep"))
    return p


def _degrees(angle: float) -> str:
    """An angle [rad] as whole degrees for a table ("?" if unknown)."""
    return str(round(math.degrees(angle))) if math.isfinite(angle) else "?"


def _law_words(result) -> str:
    """The force law's settings that change the answer: the velocity option and the coefficients (a --velocity
    local run, 4 bounces against 15, read like a default one; a review)."""
    w = result.water
    return (f"velocity {result.config.force.velocity}, C_l {float(w.c_lift):g}, C_f {float(w.c_friction):g}"
            + (f", faces {result.config.force.faces}" if result.config.force.faces != "leading" else ""))


def _summary(result) -> str:
    lines = [
        f"{plural(result.bounces, 'bounce')} over {result.distance:.2f} m; outcome: {result.outcome.replace('_', ' ')} "
        f"after {result.final_time:.2f} s ({plural(result.steps, 'step')}, {result.wall_time:.2f} s wall)",
        f"stone {result.stone_name} ({result.mass * 1e3:.1f} g), force law {result.config.force.law} "
        f"({_law_words(result)}), attitude {result.config.attitude}, integrator {result.config.integrator}, "
        f"dt {result.config.dt:g} s" + ("" if result.config.bounce_clearance == SIM_DEFAULTS["bounce_clearance"] else
                                         f", bounce clearance {result.config.bounce_clearance:g} m"),
    ]
    if result.contacts:
        lines.append("  #   start [s]  length [ms]   downrange [m]   tilt in -> out [deg]   tilt direction in -> out [deg]")
        for i, c in enumerate(result.contacts[:40]):
            lines.append(
                f"{i + 1:3d}   {c.t_start:8.3f}   {1e3 * (c.t_end - c.t_start):9.1f}   {c.x:13.2f}   "
                f"{math.degrees(c.tilt_start):6.1f} -> "
                + (f"{math.degrees(c.tilt_end):6.1f}   {_degrees(c.tilt_direction_start):>10} -> "
                   f"{_degrees(c.tilt_direction_end):>4}" if math.isfinite(c.tilt_end)
                   else "   (in the water at the end)")
            )
        if result.n_contacts > 40:
            logged = (f" (the first {len(result.contacts)} of {result.n_contacts} are logged)"
                      if result.n_contacts > len(result.contacts) else "")
            lines.append(f"  ... {result.n_contacts - 40} more{logged}")
        lines.append("  (downrange: the centre of mass's distance from the release point along the heading, at "
                     "the contact's start; tilt direction: 0 leading edge up, +90 banked to the left, 180 leading "
                     "edge down)")
    lines.extend(_energy_lines(result))
    if result.outcome == "step_limit":
        lines.append("note: the step budget ran out while the stone was still in play; raise --max-steps")
    elif result.outcome == "time_limit":   # (said nothing before: a cut-off throw read like a finished one)
        lines.append(f"note: the run reached --duration ({result.config.duration:g} s) with the stone still in play; "
                     "its bounces and distance are those so far: raise --duration for the whole throw")
    return "\n".join(lines)


#: A rise of the stone's mechanical energy (above its release value, or above any earlier value) beyond this
#: fraction of its release value is reported as energy the water added (the passive laws rise by rounding
#: only: ~1e-9 J on the default throw's 4.63 J).
ENERGY_RISE = 1e-6


def _percent(p: float) -> str:
    """A percentage for the summary: whole numbers from 10 on, two significant figures below ("0.25", not "0")."""
    return f"{p:.0f}" if abs(p) >= 10 else f"{p:.2g}"


def _energy_lines(result) -> list:
    """The stone's mechanical energy in the summary: at release, at its peak and at the end [J], and a note
    when it rose above an earlier value: the water's doing with --velocity body (the default) or on the height field;
    with the tilt held on flat water the step's, noted only above simulate's warning (which it points to)."""
    if result.rigid is None:
        return []
    e = result.to_dict()["energy"]
    if None in e.values():  # (a diverged run: its error says so)
        return []
    lines = [f"mechanical energy of the stone: {e['release']:.3g} J at release, {e['end']:.3g} J at the end"]
    if result.config.attitude == "fixed":   # (its spin sets no motion: 171 J 'at release' at --spin -300 read as real)
        spin = float(result.energy()["rotation"][0])
        lines.append(f"  (with --attitude fixed the stone does not turn: --spin sets no motion, and its "
                     f"{spin:.3g} J of spin energy is carried unchanged in these figures)")
    if e["peak"] > e["release"] * (1 + ENERGY_RISE) + ENERGY_RISE:
        lines[0] += (f"; peak {e['peak']:.3g} J at {e['peak_time']:.2f} s "
                     f"(+{_percent(100 * (e['peak'] / e['release'] - 1))} %)")
    if result.config.attitude == "fixed" and not result.field:
        from .api import held_energy_rise_message

        # (with the tilt held no face turns: only the step can add energy. Under HELD_ENERGY_RISE it is the explicit
        # step's small error (a Clanet disk at 4 m/s: 6e-5 of its energy, which this note called the water's, with
        # advice to shorten the step); above it simulate's warning, printed before this summary, says so and
        # what to do: the note only points to it (it repeated the warning)
        if held_energy_rise_message(result) is not None:
            lines.append(f"  (the step added {e['gain']:.3g} J: see the warning above)")
    elif e["gain"] > e["release"] * ENERGY_RISE + ENERGY_RISE:
        # (on the height field moving water may push the stone, and the body law's pumping acts there as well; with
        # the tilt held no face turns, so the rest is the step's, too long for the stone and speed)
        why = ("with --attitude fixed no face turns, so the rest is the integration's: a smaller --dt tells them apart"
               if result.config.attitude == "fixed" else
               "with --velocity body each face's force comes from the centre of mass's velocity and can pump a "
               "wobble; --velocity passive never adds any; docs/model.md, 'The default free stone gains energy'"
               if result.config.force.velocity == "body" else "a smaller --dt resolves the contacts better")
        if result.field:
            why = "on the height field moving water can also push the stone; " + why
        lines.append(f"  (the water added energy: {e['gain']:.3g} J above an earlier low; {why})")
    return lines


def _distinct_outputs(args, flags) -> None:
    """Refuse two output flags that name one file: the second would overwrite the first's output."""
    seen = {}
    for flag in flags:
        path = getattr(args, flag[2:].replace("-", "_"))
        if path is None:
            continue
        key = os.path.normcase(os.path.realpath(path))
        if key in seen:
            raise ParameterError(f"{flag} and {seen[key]} name the same file, {path!r}: the second would overwrite "
                                 "the first; give each its own path")
        seen[key] = flag


def _throw(args) -> int:
    for flag, suffixes in (("--plot", PICTURES), ("--water-plot", PICTURES), ("--animate", (".gif",))):
        check_output(flag, getattr(args, flag[2:].replace("-", "_")), suffixes)
    check_output("--trajectory", args.trajectory, (".csv", ".json"))
    _distinct_outputs(args, ("--plot", "--water-plot", "--animate", "--trajectory"))
    if args.trajectory:
        from .export import check_stone_file, stone_path

        beside = stone_path(args.trajectory)
        check_output("--trajectory", beside, (".obj",))
        if args.stone and os.path.exists(args.stone) and os.path.exists(beside) and os.path.samefile(args.stone,
                                                                                                     beside):
            raise ParameterError(f"--trajectory {args.trajectory!r} would write the stone's body-frame mesh over "
                                 f"--stone {args.stone!r}: choose another trajectory name")
        try:
            check_stone_file(args.trajectory)   # a mesh jaxskip did not write is never overwritten
        except ParameterError as exc:
            raise ParameterError(f"--trajectory {args.trajectory!r}: {exc}") from None
    if args.water == "flat" and (args.animate or args.water_plot):
        raise ParameterError("--animate and --water-plot need --water field (flat water has no ripples to draw)")
    if args.fps is not None and args.trajectory is None:
        raise ParameterError("--fps is the frame rate of --trajectory; give --trajectory PATH.csv|.json too")
    if args.fps is not None:
        from .export import MAX_FPS

        check_range("--fps", args.fps, 0.0, MAX_FPS, unit="frames/s", low_open=True)
    import jax

    jax.config.update("jax_enable_x64", True)  # results match the float64 test suite
    from . import Throw, simulate

    throw = Throw.from_degrees(speed=args.speed, tilt=args.tilt, attack=args.attack, spin=args.spin,
                               height=args.height, heading=args.heading)
    values = sim_values(args)
    config, water, stone = simulation(**values)
    # (--velocity local or passive with --attitude fixed: simulate warns, jaxskip.simulate.inert_velocity_message)
    progress = show_progress(args)  # on stderr: stdout keeps its one JSON object
    field = None
    if args.water == "field":
        from .coupled import default_window

        field = default_window()
        span = min(field.shape) * field.spacing
        if 2.0 * float(stone.radius) > span:   # (simulate's message named its water_field argument)
            raise ParameterError(f"--water field: the stone is {2.0 * float(stone.radius):.3g} m across, wider than the "
                                 f"field's window ({span:g} m); use --water flat or a stone at most {span:g} m across")
    with warnings.catch_warnings():  # (a diverged throw is this command's error below, not also a warning)
        warnings.simplefilter("ignore", DivergedWarning)
        result = simulate(throw, stone, water=water, config=config, progress=progress, water_field=field)
    result = dataclasses.replace(result, stone_name=_stone_label(values["stone"]))
    if result.outcome == "diverged":
        # (a picture or a file of a failed integration would be read as a result)
        print(f"jaxskip: error: the throw diverged at t = {result.final_time:.4g} s (its state stopped being finite "
              f"or passed {DIVERGED_SPEED:g} m/s) with --dt {config.dt:g}: nothing written; take a smaller --dt",
              file=sys.stderr)
        return EXIT_FAILED
    stone_obj = None
    if args.trajectory:   # first: it may still refuse (another throw's stone file), before any picture is written
        from .export import write_trajectory

        from .stones import source_mesh

        # (the mesh the stone was made from, in its own frame: its vertex order in the stone file, and where the body
        # frame lies in it; load_stone's copy of a file is centred, which put an off-origin file's centre at 0)
        stone_obj = write_trajectory(result, args.trajectory, 60.0 if args.fps is None else args.fps,
                                     mesh=source_mesh(values["stone"]))
    if args.plot:
        from .plotting import plot_throw

        plot_throw(result, args.plot)
    if args.water_plot:
        from .plotting import plot_water

        plot_water(result, stone, args.water_plot)
    if args.animate:
        from .plotting import animate_throw

        if progress:
            print("writing animation ...", file=sys.stderr, flush=True)
        animate_throw(result, stone, args.animate)
    if args.json:
        out = result.to_dict()
        for key in ("plot", "water_plot", "animate", "trajectory"):
            if getattr(args, key):
                out[key] = str(getattr(args, key))
        if stone_obj:
            out["trajectory_stone"] = stone_obj
        out["environment"] = environment()
        print_json(out, args)
    else:
        _say(_summary(result))
        if result.field:
            w = result.field
            _say(f"water: height field {w['shape'][0]}x{w['shape'][1]} columns of {w['spacing'] * 100:g} cm, "
                 f"depth {w['depth'] * 100:g} cm, step {w['time_step'] * 1e3:g} ms"
                 + (f" in {w['substeps']} substeps" if w["substeps"] > 1 else "") + f", clamp {w['clamp']}; "
                 f"window volume change {w['volume_change']:+.2e} (relative; the window follows the stone, "
                 "leaving its wake behind: not a conservation check)")
        for label, key in (("picture", "plot"), ("ripples", "water_plot"), ("animation", "animate"),
                           ("trajectory", "trajectory")):
            if getattr(args, key):
                _say(f"{label}: {getattr(args, key)}")
        if stone_obj:
            _say(f"the stone in the trajectory's body frame: {stone_obj}")
    return 0


def _stone_label(stone) -> str:
    return os.path.basename(str(stone))


def _with_flag(message: str, args) -> str:
    """A library message begins with the parameter's name (``speed_range is inverted: ...``): at this edge,
    the flag's (``--speed-range is inverted: ...``); a setting quoted as ``velocity='passive'`` becomes
    ``--velocity passive``."""
    names = {d: "--" + d.replace("_", "-") for d in vars(args)
             if d not in ("command", "kind", "folders") and not d.startswith("_")}
    if args.command != "throw":
        from .cli_search import flag_names

        names.update(flag_names(args))
    # a library setting quoted as name='value' (velocity='passive', law='seed') is the flag and its value here
    names.setdefault("law", "--force-law")   # (ForceModel's name for --force-law)

    def flagged(m):
        return f"{names[m.group(1)]} {m.group(2)}" if m.group(1) in names else m.group(0)

    message = re.sub(r"\b([a-z_]+)='([^'\s]*)'", flagged, message)
    # and advice to take a setting below a value, "take dt <= 0.134 ms", names the flag (stop 48)
    message = re.sub(r"\btake ([a-z_]+) (<=|>=)", lambda m: f"take {names[m.group(1)]} {m.group(2)}"
                     if m.group(1) in names else m.group(0), message)
    word, space, rest = message.partition(" ")
    return f"{names[word]} {rest}" if space and word in names else message


def _warning_printer(args):
    """``warnings.showwarning`` for this edge: one line on stderr (``jaxskip: warning: ...``), no source
    line, the parameter named by its flag (``--dt = 5 ms ...``). Each text is printed once a run (a search's
    batches reset Python's own once-registry with their ``catch_warnings``), and so is one
    :class:`~jaxskip.StabilityWarning` (the first: a search or sweep issues it at its fastest throw; the
    re-thrown best throw would print another for its own speed)."""
    from .simulate import StabilityWarning

    shown = set()
    args._warnings = []

    def show(message, category, filename, lineno, file=None, line=None):
        key = StabilityWarning if issubclass(category, StabilityWarning) else str(message)
        if key in shown:
            return
        shown.add(key)
        text = _with_flag(str(message), args)
        args._warnings.append({"category": category.__name__, "message": text})   # (for --json)
        print(f"jaxskip: warning: {text}", file=sys.stderr, flush=True)

    return show


def main(argv=None) -> int:
    """Entry point of the ``jaxskip`` command; returns the exit status."""
    try:   # a stream the caller closed (``python -m jaxskip 2>&-``), as the ``jaxskip`` command does first
        from jaxskip_cli import _open_closed_streams
    except ImportError:   # (jaxskip_cli is installed beside the package; not on a bare PYTHONPATH of the package)
        pass
    else:
        _open_closed_streams()
    parser = build_parser(argv)
    args, extra = parser.parse_known_args(argv)
    if extra:  # said by the command's parser, whose --help lists the flags it takes
        parser.commands[args.command].error(f"unrecognized arguments: {' '.join(extra)}")
    from .mesh import MeshError
    from .simulate import AccuracyWarning

    with warnings.catch_warnings():
        warnings.simplefilter("once", AccuracyWarning)  # once per run, however many batches a search runs
        warnings.showwarning = _warning_printer(args)
        # Ctrl-C handled at the signal itself: a KeyboardInterrupt raised where Python ignores exceptions (a
        # garbage-collection callback of XLA's) was swallowed, and the command ran on to the end.
        import signal
        import threading

        handled = threading.current_thread() is threading.main_thread()
        previous = signal.signal(signal.SIGINT, lambda signum, frame: _interrupted(args)) if handled else None
        try:
            return _run(args, MeshError)
        except KeyboardInterrupt:
            _interrupted(args)
        finally:
            if handled:
                signal.signal(signal.SIGINT, previous)


EXIT_INTERRUPTED = 130
"""Exit status after Ctrl-C (SIGINT): 128 + 2, as a shell reports a command it interrupted."""


def _interrupted(args) -> None:
    """Ctrl-C: one line on stderr (for a sweep, what is kept and how to resume), then exit 130 at once.

    ``os._exit``, not a return: an interrupt that lands inside XLA's compiler leaves it mid-flight,
    and the interpreter's normal shutdown then crashed (segmentation fault, exit 139). A sweep writes
    each finished chunk atomically as it goes, so nothing finished is lost by leaving this way."""
    message = "jaxskip: interrupted"
    if args.command == "sweep" and getattr(args, "kind", None) in ("umin", "domain") and getattr(args, "out", None):
        message += (f"; the finished chunks are kept in {args.out!r}: run the same command again to resume "
                    f"(finished chunks are not recomputed)")
    try:
        sys.stdout.flush()
    except Exception:  # noqa: BLE001 - a closed pipe: nothing more to say there
        pass
    print(message, file=sys.stderr, flush=True)
    os._exit(EXIT_INTERRUPTED)


EXIT_BROKEN_PIPE = 141
"""Exit status when the reader of stdout went away (``jaxskip throw --json | head``): 128 + SIGPIPE, as a
shell reports a command killed by it."""


def _run(args, MeshError) -> int:
    try:
        if args.command == "throw":
            return _throw(args)
        from .cli_search import run_optimize, run_sweep_command

        return run_optimize(args) if args.command == "optimize" else run_sweep_command(args)
    except BrokenPipeError:
        # The reader closed the pipe: nothing to report. Point stdout at /dev/null so that the
        # interpreter's final flush does not raise again.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return EXIT_BROKEN_PIPE
    except (ParameterError, MeshError, ValueError, OSError) as exc:
        print(f"jaxskip: error: {_with_flag(str(exc), args)}", file=sys.stderr)
        return EXIT_USAGE


if __name__ == "__main__":
    raise SystemExit(main())
