r"""Search for the throw with the most bounces: optax gradient ascent, and baselines.

* :func:`gradient_search` — multi-start gradient ascent (optax Adam, gradient
  clipping, non-finite guard) on the smooth surrogate of
  :mod:`optimize.objectives`, over any subset of the throw parameters within a
  :class:`~optimize.bounds.Box` (sigmoid reparameterisation). The starts are
  batched with ``lax.map`` rather than ``vmap``: under ``vmap`` a finished
  throw still pays for every remaining step, while ``lax.map`` keeps the
  rollout's skip of out-of-play segments. After every iteration the true
  bounce count of every start is simulated exactly
  (:func:`jaxskip.simulate_batch`); the best true count wins. Optionally
  (``polish=N``) the search ends with :func:`local_search`: N exact throws
  sampled around the best throws the ascent visited.
* :func:`local_search` — exact counts of random throws near given centres: the
  count is chaotic on scales far below what a gradient resolves (neighbouring
  throws differ by tens of bounces), so a smooth ascent finds the *region* of
  long throws and sampling finds the long throws in it.
* :func:`perturbation_search` — the randomised-smoothing baseline: the
  gradient of :math:`E[N(\theta + \sigma\epsilon)]` estimated from antithetic
  pairs of exact simulations (no derivative of the simulator), with the same
  optional polish. On the free stone it finds far more bounces than the
  gradient search: the rollout is chaotic, and its pathwise gradients grow
  e-fold every ~40-50 ms of contact (:func:`gradient_health` monitors them;
  benchmarks/README.md, session 14).
* :func:`grid_search`, :func:`random_search` — exhaustive and random
  baselines on exact counts, run in lane-pooled batches with a progress line.

Costs are reported as wall time and as simulator evaluations (forward throws
and gradient evaluations counted separately) so that they can be compared
with a grid measured in the same run.
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import numbers
import os
import sys
import time
import warnings
from collections.abc import Mapping

import jax
import numpy as np
import optax

from jaxskip import SimConfig, WaterParams, water_params
from jaxskip.simulate import AccuracyWarning
from jaxskip._arrays import float_array, float_leaves
from jaxskip._docs import document_fields
from jaxskip._files import check_picture_path, writing
from jaxskip._progress import ProgressLine
from jaxskip._checks import ParameterError, check_bool, check_int, check_positive, check_range
from jaxskip.api import checked_config, checked_water, resolve_stone

from .bounds import LIMITS, PARAMETERS, Box, make_box, throw_in_box
from .objectives import WIDTH, check_width, make_objective
from ._runs import batch, caller_level, silenced_batches, warn_diverged, warn_stability


@document_fields
@dataclasses.dataclass(frozen=True)
class SearchResult:
    """Outcome of a search (user units: m/s, deg, rev/s)."""

    method: str
    """``gradient``, ``perturbation``, ``grid``, ``random`` or ``local``."""
    best: dict
    """The best throw found: {parameter: value} for all four parameters (user units)."""
    best_bounces: int
    """Its true bounce count (exact simulation)."""
    history: list
    """One dict per iteration (then one for a polish), user units. The keys depend on the method (each
    search's Returns section says which it writes): ``"iteration"`` (int); ``"bounces"`` (list of true
    bounce counts [-]: each start's (gradient), each centre's (perturbation), each throw's (local, a
    polish), or a one-element list of the best count (grid, random)); ``"objective"`` (list per start:
    the surrogate [-], or the distance [m] with ``objective="distance"`` (gradient); the mean true count
    of each start's ``2 * samples + 1`` throws (perturbation); None where there is none); ``"best"``
    (the true bounce count of the best throw so far [-]); ``"nonfinite"`` (starts whose gradient was
    non-finite and replaced by zero; 0 without gradients); ``"points"`` ({parameter: list} of the
    throws (perturbation: the centres) simulated, user units; not grid, random); ``"distance"`` (list
    of true distances [m], as ``"bounces"``: a local search, a polish with ``objective="distance"``, and
    a gradient search with ``objective="distance"``); ``"grad_norm"`` (a gradient search's iterations
    with a gradient: each start's raw gradient norm before clipping, in bounces [-] per unconstrained
    unit, m per unconstrained unit with ``objective="distance"``; None where non-finite);
    ``"phase"`` (``"polish"``: a polish's entry and a local search's); ``"count_histogram"`` (grid,
    random: throws per true bounce count, indexed by the count); ``"screen"`` (a gradient search's first
    entry, with ``screen=N``: the N screened throws' ``"points"`` and true ``"bounces"``); ``"diverged"``
    (grid, random: the throws that diverged); ``"cut_off"`` (grid, random: the throws stopped while in play at
    the duration or step limit; local, a polish: 1 or 0 per throw). A throw that diverged is listed with
    :data:`DIVERGED_SCORE` (-1) as its count and distance (see ``diverged``)."""
    box: Box
    """The search's bounds (:class:`optimize.bounds.Box`, user units)."""
    wall_time: float
    """Wall-clock time, compile included [s]."""
    forward_throws: int
    """Exact forward simulations run."""
    gradient_evals: int
    """Gradient evaluations of the surrogate (one throw each)."""
    gradient_time: float = 0.0
    """Run time of all gradient evaluations, compile excluded [s] (their measured cost: a gradient
    costs more on the long throws a search climbs to than on a typical throw)."""
    compile_time: float = 0.0
    """Time spent compiling the gradient function [s] (in ``wall_time``, not in ``gradient_time``; 0 when an
    earlier search in the same process compiled it: the program is kept for the same configuration,
    box, number of starts, stone and water shapes and precision)."""
    best_distance: float | None = None
    """The best throw's true distance [m] (exact simulation, as ``best_bounces``)."""
    objective: str = "bounces"
    """What "best" means: ``"bounces"`` (the most true bounces) or ``"distance"`` (the longest true
    distance; :func:`gradient_search` and :func:`local_search` with ``objective="distance"``)."""
    diverged: int = 0
    """Exact throws whose integration failed (outcome ``"diverged"``: the contact step is too long for the
    stone and throw). Their count and distance mean nothing: the history lists them as
    :data:`DIVERGED_SCORE` (-1 bounces, -1 m), they are never the best, and the search issues one
    :class:`jaxskip.DivergedWarning` for them."""

    cut_off: int = 0
    """Exact throws still in play when the run stopped them at ``config.duration`` or ``config.max_steps``
    (outcome ``"time_limit"`` or ``"step_limit"``): their counts and distances are lower bounds, and the search
    issues one :class:`jaxskip.AccuracyWarning` for them (raise the limits)."""
    best_cut_off: bool = False
    """True when the best throw is one of those: ``best_bounces`` and ``best_distance`` are lower bounds."""
    settings: dict = dataclasses.field(default_factory=dict)
    """What the search was run with, JSON-ready, so that it can be run again: every argument of the search
    function as resolved (defaults included; ``seed``, ``starts``, ``iterations``, ``learning_rate``, ...,
    user units), ``stone`` (its name or path, else its type and mass), ``config`` (every
    :class:`jaxskip.SimConfig` field), ``water`` (every :class:`jaxskip.WaterParams` field [SI]) and
    ``precision`` (``"float64"`` or ``"float32"``: what the search computed in)."""

    def to_dict(self) -> dict:
        """The result as a JSON-ready dict (``jaxskip optimize --json``), user units (m/s, deg, rev/s; times
        [s], distances [m]): every field by its name, ``box`` as :meth:`optimize.bounds.Box.to_dict`."""
        return {"method": self.method, "objective": self.objective, "best": self.best,
                "best_bounces": self.best_bounces, "best_distance": self.best_distance,
                "history": self.history, "box": self.box.to_dict(), "wall_time": self.wall_time,
                "forward_throws": self.forward_throws, "gradient_evals": self.gradient_evals,
                "gradient_time": self.gradient_time, "compile_time": self.compile_time, "diverged": self.diverged,
                "cut_off": self.cut_off, "best_cut_off": self.best_cut_off, "settings": self.settings}


def _plain(value):
    """``value`` as JSON-ready plain Python: arrays and NumPy numbers as lists and numbers, mappings as dicts."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (np.ndarray, np.generic, jax.Array)):
        return _plain(np.asarray(value).tolist())
    return value


def _recorded(search):
    """``search`` with its :attr:`SearchResult.settings` filled in from the arguments it was called with."""
    signature = inspect.signature(search)

    @functools.wraps(search)
    def run(*args, **kwargs):
        result = search(*args, **kwargs)
        bound = signature.bind(*args, **kwargs)
        bound.apply_defaults()
        given = dict(bound.arguments)
        config = given.pop("config")   # (checked, and warned of, by the search itself: _common)
        config = SimConfig() if config is None else config
        water = given.pop("water")
        water = water_params(config.force.law) if water is None else water
        stone = given.pop("stone")
        given.pop("progress", None)
        given.pop("box", None)  # (the result's own field)
        settings = {**{k: _plain(v) for k, v in given.items()},
                    "stone": (os.fspath(stone) if isinstance(stone, (str, os.PathLike))
                              else f"a {type(stone).__name__} of {float(resolve_stone(stone)[0].mass):.6g} kg"),
                    # (as run: every search's throws keep no trajectory; it read "record": true, a review)
                    "config": _plain(dataclasses.asdict(dataclasses.replace(config, record=False))),
                    "water": {f.name: float(getattr(water, f.name)) for f in dataclasses.fields(water)},
                    "precision": "float64" if jax.config.jax_enable_x64 else "float32"}
        return dataclasses.replace(result, settings=settings)

    return run


#: Raw gradient norm (before clipping) above which :func:`gradient_health` calls a gradient exploding: the
#: norm of the objective's gradient with respect to the box's unconstrained coordinates, in bounces [-] per
#: unconstrained unit (m per unconstrained unit with ``objective="distance"``, compared with the same
#: number). The smooth count's real slopes across the box are a few bounces per unit (its mean changes
#: by tens of bounces across a range, ~10 units); norms beyond 1e3 come from the rollout's chaos
#: (benchmarks/README.md, session 14: the tail of the norms grows e-fold every ~150-190 contact steps,
#: 40-50 ms, to ~1e13 over a whole throw), and the clipped step then follows noise.
EXPLODING = 1e3
#: Raw gradient norm below which :func:`gradient_health` calls a gradient vanishing (units as
#: :data:`EXPLODING`): the smooth count is flat there (typically a throw that sinks at its first contact).
VANISHING = 1e-6

# Limits of the searches' counts (the checks and ``jaxskip optimize --help`` use these).
#: Most random starts of :func:`gradient_search` and :func:`perturbation_search`.
MAX_STARTS = 4096
#: Most iterations of :func:`gradient_search` and :func:`perturbation_search`.
MAX_ITERATIONS = 100_000
#: Most antithetic pairs per start and iteration of :func:`perturbation_search`.
MAX_SAMPLES = 4096
#: Most exact throws of :func:`random_search` and :func:`local_search`, and of a polish.
MAX_THROWS = 100_000_000
#: Largest ``learning_rate`` (and ``sigma`` of :func:`perturbation_search`) in the unconstrained search
#: coordinates u (a parameter is low + (high - low) sigmoid(u)): a step of 10 already crosses the whole box
#: (sigmoid(-5) to sigmoid(5) is 0.7 % to 99.3 % of it); beyond, Adam's steps only pin the starts to its edges.
MAX_STEP = 10.0
#: Best distinct throws an ascent visited that its polish samples around (fewer if it visited fewer).
POLISH_CENTRES = 4
#: Most grid points per searched parameter of :func:`grid_search` (:func:`grid_points`).
MAX_PER_AXIS = 10_000
#: Most grid points in all of :func:`grid_search` (:func:`grid_points`).
MAX_GRID_POINTS = 100_000_000


def gradient_health(result: SearchResult) -> dict | None:
    """Summary of a gradient search's raw gradient norms (gradient-norm monitoring).

    The norms are those of the objective's gradient with respect to the box's unconstrained
    coordinates (``"grad_norm"`` in the history): bounces [-] per unconstrained unit, m per
    unconstrained unit for a search with ``objective="distance"``.

    Returns ``None`` for a search without gradients, else a dict: ``median`` and ``max`` of the
    finite norms (units as above), ``of`` (evaluations), ``exploding`` (evaluations above
    :data:`EXPLODING`, or non-finite), ``vanishing`` (below :data:`VANISHING`), and per start
    ``starts`` = {``"n"``, ``"exploding"``: starts with an exploding gradient at some
    iteration, ``"vanishing"``: starts whose gradients all vanished, ``"vanishing_some"``: starts whose
    gradient vanished at some iteration}. An exploding start follows
    the rollout's chaos rather than the count's trend (a shorter ``horizon`` tames it); a
    vanishing one has nothing to climb.
    """
    if not isinstance(result, SearchResult):
        raise ParameterError(f"result must be an optimize.SearchResult (what the searches return), got "
                             f"{type(result).__name__}")
    rows = [h["grad_norm"] for h in result.history if h.get("grad_norm")]
    if not rows:
        return None
    norms = [v for r in rows for v in r]
    finite = np.array([v for v in norms if v is not None], dtype=float)
    big = lambda v: v is None or v > EXPLODING  # noqa: E731
    small = lambda v: v is not None and v < VANISHING  # noqa: E731
    per_start = list(zip(*rows))
    return {"median": float(np.median(finite)) if finite.size else None,
            "max": float(np.max(finite)) if finite.size else None,
            "of": len(norms), "exploding": sum(map(big, norms)), "vanishing": sum(map(small, norms)),
            "starts": {"n": len(per_start), "exploding": sum(any(map(big, c)) for c in per_start),
                       "vanishing": sum(all(map(small, c)) for c in per_start),
                       "vanishing_some": sum(any(map(small, c)) for c in per_start)}}


def _full(box: Box, values: dict) -> dict:
    """A whole throw {parameter: value} (user units) from the searched ``values`` and the box's held ones,
    in :data:`~optimize.bounds.PARAMETERS` order (speed, tilt, attack, spin)."""
    out = {**dict(box.held), **{k: float(v) for k, v in values.items()}}
    return {k: out[k] for k in PARAMETERS if k in out}


#: The count and distance [m] a search gives a throw that diverged (outcome ``"diverged"``: its own count and
#: distance mean nothing): below every true value, so such a throw is never the best, and marked in the history.
DIVERGED_SCORE = -1
#: Outcomes of an exact throw still in play when the run stopped it (its count and distance are lower bounds).
CUT_OFF = ("time_limit", "step_limit")


def _exact(box: Box, values: dict, stone, config: SimConfig, lanes: int | None = None,
           progress: bool = False, water=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Exact bounce counts and distances [m] of the throws ``values`` (user units), lane-pooled
    (:func:`jaxskip.simulate_batch`; ``water`` None: the force law's constants); a throw that diverged gets
    :data:`DIVERGED_SCORE` for both. Also a mask of the throws still in play when the run stopped them
    (:data:`CUT_OFF` outcomes: lower bounds). The batch's own accuracy and divergence warnings are silenced:
    the search issues them once (:func:`_warn_stability`, :meth:`_Best.warn`)."""
    throws = box.throws_from_user(values)
    with silenced_batches(coarse=True):  # (the coarse dt: checked_config warned already)
        r, failed = batch(throws, stone, water=water, config=dataclasses.replace(config, record=False), lanes=lanes,
                          progress=progress)
    return (np.where(failed, DIVERGED_SCORE, r.bounces),
            np.where(failed, float(DIVERGED_SCORE), np.asarray(r.distance, dtype=float)),
            np.isin(r.outcome_names, CUT_OFF) & ~np.asarray(failed))


def _warn_stability(box: Box, rigid, config: SimConfig, water) -> None:
    """One :class:`jaxskip.StabilityWarning` for a search, at the fastest throw of its box."""
    speed = dict(box.held).get("speed")
    speed = speed if speed is not None else next(hi for name, _, hi in box.searched if name == "speed")
    warn_stability(config, rigid, water_params(config.force.law) if water is None else water, speed,
                   stacklevel=caller_level() + 1)


def _true_counts(box: Box, values: dict, stone, config: SimConfig, lanes: int | None = None,
                 progress: bool = False) -> np.ndarray:
    """Exact bounce counts of the throws ``values`` (user units)."""
    return _exact(box, values, stone, config, lanes, progress)[0]


def _check_objective(objective: str) -> str:
    if objective not in ("bounces", "distance"):
        raise ParameterError(f"objective must be 'bounces' or 'distance', got {objective!r}")
    return objective


class _Best:
    """The best throw seen so far by ``objective`` (true counts or true distances)."""

    def __init__(self, box: Box, objective: str):
        self.box, self.objective = box, objective
        self.score, self.throw, self.bounces, self.distance = -np.inf, None, -1, None
        self.seen, self.diverged, self.cut_off, self.best_cut = 0, 0, 0, False

    def update(self, values: dict, counts, distances, cut) -> None:
        """Take in exact throws: ``counts``, ``distances`` [m] and ``cut`` (True: stopped while in play) of
        the throws ``values``."""
        score = np.asarray(counts if self.objective == "bounces" else distances, dtype=float).ravel()
        failed = np.asarray(counts).ravel() < 0  # DIVERGED_SCORE
        cut = np.asarray(cut, dtype=bool).ravel()
        self.seen += failed.size
        self.diverged += int(failed.sum())
        self.cut_off += int(cut.sum())
        score = np.where(failed, -np.inf, score)
        i = int(np.argmax(score))
        if score[i] > self.score:
            self.score = float(score[i])
            self.throw = _full(self.box, {k: np.ravel(v)[i] for k, v in values.items()})
            self.bounces, self.distance = int(np.ravel(counts)[i]), float(np.ravel(distances)[i])
            self.best_cut = bool(cut[i])

    def result(self, method: str, history: list, t0: float, forward: int, **more) -> "SearchResult":
        """The :class:`SearchResult` of a search that started at ``t0`` (``time.perf_counter``) and ran
        ``forward`` exact throws; ``more``: its other fields."""
        return SearchResult(method, self.throw, self.bounces, history, self.box, time.perf_counter() - t0, forward,
                            more.pop("gradient_evals", 0), best_distance=self.distance, diverged=self.diverged,
                            cut_off=self.cut_off, best_cut_off=self.best_cut, **more)

    def warn(self, what: str, config: SimConfig) -> None:
        """One :class:`jaxskip.DivergedWarning` for the search, if any of its exact throws diverged; a
        :class:`jaxskip.ParameterError` naming ``dt`` if all of them did (there is no best throw)."""
        if self.throw is None and self.seen:
            raise ParameterError(f"every one of the {self.seen} exact throws of this {what} diverged (outcome "
                                 f"'diverged'): config.dt = {config.dt:g} s is too long for this stone and box; "
                                 "take a smaller dt")
        warn_diverged(self.diverged, self.seen, what, f"they score {DIVERGED_SCORE} bounces and {DIVERGED_SCORE} m "
                      "in its history and are never its best", config, stacklevel=caller_level())
        if self.cut_off:   # (a search at --duration 0.3 reported a best count one short, in silence)
            warnings.warn(f"{self.cut_off} of the {self.seen} exact throws of this {what} were still in play when the "
                          f"run stopped them at duration={config.duration:g} s or max_steps={config.max_steps}: their "
                          f"counts and distances are lower bounds"
                          + (", the best throw's among them" if self.best_cut else "")
                          + "; raise them (--duration, --max-steps in the CLI)", AccuracyWarning,
                          stacklevel=caller_level())


def _as_box(box) -> Box:
    """``box`` as a :class:`~optimize.bounds.Box`: None is the human box (:data:`~optimize.bounds.HUMAN_BOX`);
    a dict such as :data:`~optimize.bounds.HUMAN_BOX` maps each searched parameter to ``(low, high)`` and
    each held one to a value (:func:`~optimize.bounds.make_box`; parameters it leaves out are held at
    make_box's defaults)."""
    if box is None:
        return make_box()
    if isinstance(box, Mapping):
        scalar = {k for k, v in box.items() if isinstance(v, numbers.Real) or np.ndim(v) == 0}
        return make_box({k: v for k, v in box.items() if k not in scalar}, {k: box[k] for k in scalar})
    if not isinstance(box, Box):
        raise ParameterError(f"box must be an optimize.Box (make_box({{name: (low, high)}}, {{name: value}})) or a "
                             f"dict such as optimize.HUMAN_BOX, got {type(box).__name__}")
    return box


def _common(box, config, progress) -> tuple:
    """The arguments every search takes, checked: ``(Box, SimConfig, bool)`` (:func:`_as_box`). A coarse ``dt`` is
    warned of once, attributed to the search's caller (through the search and :func:`_recorded`'s wrapper)."""
    box, config = _as_box(box), checked_config(config, stacklevel=6)
    if config.attitude == "fixed" and "spin" in box.names:   # (searched for nothing: a grid multiplied its cost)
        warnings.warn("spin is searched with attitude='fixed', where the stone does not turn and the spin sets no "
                      "motion: every spin gives the same throw; hold it (a single value) to spend the throws on the "
                      "other parameters", UserWarning, stacklevel=caller_level())
    return box, config, check_bool("progress", progress)


def _check_seed(seed) -> int:
    """A random seed: an integer >= 0 (NumPy's generators refuse negative ones)."""
    return check_int("seed", seed, minimum=0)


def _check_initial(box: Box, initial) -> dict:
    """``initial`` {parameter: value}: exactly the searched parameters (a held one is refused, not dropped)."""
    if not isinstance(initial, Mapping):
        raise ParameterError(f"initial must be a dict {{parameter: value}} of the searched parameters "
                             f"({', '.join(box.names)}), got {type(initial).__name__}")
    held = dict(box.held)
    for name in initial:
        if name not in LIMITS:
            raise ParameterError(f"initial: unknown throw parameter {name!r}; choose from {', '.join(PARAMETERS)}")
        if name in held:
            raise ParameterError(f"initial {name} is held at {held[name]:g} {LIMITS[name][2]} by the box, not "
                                 f"searched: drop it from initial, or search it (make_box({{{name!r}: (low, high)}}))")
    out = {}
    for name, lo, hi in box.searched:
        if name not in initial:
            raise ParameterError(f"initial must give every searched parameter; missing {name!r}")
        out[name] = check_range(f"initial {name}", initial[name], lo, hi, unit=LIMITS[name][2])
    return out


def _random_points(box: Box, n: int, rng) -> dict:
    return {name: rng.uniform(lo, hi, n) for name, lo, hi in box.searched}


@_recorded
def gradient_search(box: Box | None = None, *, objective: str = "bounces", stone="paper",
                    config: SimConfig | None = None, starts: int = 8, iterations: int = 20,
                    learning_rate: float = 0.3, clip: float = 1.0, width: float = WIDTH, seed: int = 0,
                    initial: dict | None = None, polish: int = 0, polish_scale: float = 0.03,
                    horizon: int | None = None, water: WaterParams | None = None, screen: int = 0,
                    progress: bool = False) -> SearchResult:
    """Multi-start gradient ascent on a smooth objective; returns a :class:`SearchResult` whose ``best``
    is the throw with the most true bounces found (``objective="distance"``: the longest true distance).

    ``box``: a :class:`~optimize.bounds.Box` (:func:`~optimize.bounds.make_box`), or a dict such as
    :data:`optimize.HUMAN_BOX` ({name: (low, high)} searched, {name: value} held; default: the human
    box, :data:`optimize.bounds.HUMAN_BOX`). ``objective``
    (``"bounces"``: the smooth count; ``"distance"`` [m]), ``starts`` random starting throws
    (seeded; an integer in [1, 4096], :data:`MAX_STARTS`), ``iterations`` Adam steps (an integer in
    [1, 10^5], :data:`MAX_ITERATIONS`) of ``learning_rate`` (in (0, 10], :data:`MAX_STEP`; in the unconstrained, dimensionless
    coordinates of the box), gradients clipped to global norm ``clip`` (> 0, same coordinates) per
    start; a non-finite gradient is replaced by zero (and counted in the history). ``width`` [m], in
    [1e-9, 0.01] (:data:`~optimize.objectives.WIDTH_RANGE`): the surrogate's sharpness knob
    (:mod:`optimize.objectives`).
    ``initial``: a throw to start from, {parameter: value} in user units for every searched
    parameter (inside the box), and no other (a held parameter is refused, not dropped); it
    replaces the first start (with ``screen``, the last: the weakest screened throw picked, and then
    ``starts`` must be at least 2). A value on a bound (attack 0 in
    :data:`~optimize.bounds.HUMAN_BOX`) maps to u = ±13.8, where the sigmoid's slope is ~1e-6: Adam moves u
    by at most about ``learning_rate`` a step, so the parameter stays on the bound for ~13.8 /
    ``learning_rate`` iterations (46 at the default 0.3; a review measured attack 0.0001 deg after 8):
    give a value a little inside. ``seed``: an integer >= 0 (the random starts).
    ``screen``: exact throws (0, or an integer in [``starts``, 10^8]) drawn at random in the box (seeded)
    and simulated before the ascent; the ``starts`` best of them (most true bounces; longest distance
    for the distance objective) become the starts (0, the default: the starts are random draws). A
    random start often lies where the stone sinks at once and the surrogate is flat (gradient norms
    down to 1e-12: it never moves); screening spends a few exact throws to start where the stone
    skips. Measured on the human box with ``polish=256``, seeds 0-7: ``screen=64`` raised the best count
    from a mean of 35 to 58 (the ascent's own best from 25 to 36; best of the eight 60 against 90) for
    64 more exact throws.
    The screen's throws are listed in the first history entry under ``"screen"`` (``"points"`` and
    ``"bounces"``, user units) and counted in ``forward_throws``.
    ``polish``: exact throws (an integer in [0, 10^8], :data:`MAX_THROWS`) spent after the ascent by
    :func:`local_search` around the (up to 4) best distinct throws the ascent visited, each parameter
    perturbed by ``polish_scale`` (in (0, 1] [-]) times its searched range (0 throws: no polish). The
    history then ends with an entry of ``"phase": "polish"``; every entry lists the throws it simulated
    under ``"points"`` (user units).
    With ``objective="distance"`` the best throw is the one with the longest true distance (the
    history then also lists each start's true distance [m] under ``"distance"``).
    Every iteration's history entry records each start's raw gradient norm (``"grad_norm"``,
    unconstrained coordinates, before clipping; ``None`` where non-finite): see
    :func:`gradient_health` and :data:`EXPLODING`.
    ``horizon``: steps of the rollout the surrogate is differentiated through, an integer in
    [1, ``config.max_steps``] (default None: all of ``config.max_steps``). A short horizon (e.g.
    1200 steps, 0.3 s of contacts) is truncated backpropagation: cheaper gradients (4 against 15 ms,
    measured) that see only the first bounces, over fewer e-foldings of the rollout's chaos (its
    gradients' tail still reaches ~1e5 at 1200 steps); true counts always use the whole rollout.
    ``water``: the water's constants (:func:`jaxskip.water_params`; default: the force law's).
    ``stone``: a built-in name (default ``"paper"``), an ``.obj`` path [m], a :class:`jaxskip.TriMesh`
    or a :class:`jaxskip.RigidStone` (:func:`jaxskip.resolve_stone`). ``config``: the
    :class:`jaxskip.SimConfig` of every rollout (default ``SimConfig()``; its ``record`` is ignored).
    ``progress``: True or False: print a progress line to stderr (the smooth objective during the ascent: the
    true counts of the throws it visited are simulated together after it, in one batch on the pool's full width,
    2.4x faster than the starts at each iteration).

    Returns a :class:`SearchResult` (user units: m/s, deg, rev/s): ``best`` the best throw found,
    {parameter: value} for all four parameters; ``best_bounces`` its true bounce count and
    ``best_distance`` its true distance [m] (exact simulation); ``forward_throws`` the exact
    simulations run, ``gradient_evals`` the surrogate's gradient evaluations; ``wall_time``,
    ``gradient_time`` and ``compile_time`` [s]; ``box``, ``method`` (``"gradient"``) and ``objective``;
    ``history`` holds one entry per iteration and one after the last step (then the
    polish's): its ``"iteration"``, each start's true ``"bounces"`` (and ``"distance"`` [m] for the
    distance objective), its surrogate ``"objective"`` (None in the entry after the last step), the
    ``"best"`` count so far, ``"nonfinite"`` gradients, ``"points"`` and (entries with a gradient)
    ``"grad_norm"`` (bounces, or m for the distance objective, per unconstrained unit); a polish's
    entry has ``"phase": "polish"`` (:func:`local_search`'s keys; ``"distance"`` only for the distance
    objective).
    """
    t0 = time.perf_counter()
    box, config, progress = _common(box, config, progress)
    objective = _check_objective(objective)
    seed = _check_seed(seed)
    if initial is not None:
        initial = _check_initial(box, initial)
    starts = check_int("starts", starts, minimum=1, maximum=MAX_STARTS)
    iterations = check_int("iterations", iterations, minimum=1, maximum=MAX_ITERATIONS)
    polish = check_int("polish", polish, minimum=0, maximum=MAX_THROWS)
    screen = check_int("screen", screen, minimum=0, maximum=MAX_THROWS)
    if 0 < screen < starts:
        raise ParameterError(f"screen must be 0 or at least starts ({starts}): the starts are the best of the "
                             f"screened throws; got {screen}")
    if screen and initial is not None and starts == 1:
        # (the best screened throw was then in no history entry the polish and the picture read)
        raise ParameterError("screen must be 0 when initial takes the only start (starts=1): the screen picks the "
                             "starts; give starts >= 2 to start from both")
    check_range("polish_scale", polish_scale, 0.0, 1.0, low_open=True)
    check_range("learning_rate", learning_rate, 0.0, MAX_STEP, low_open=True)
    check_positive("clip", clip)
    check_width(width)
    rigid, _ = resolve_stone(stone)
    water = water_params(config.force.law) if water is None else checked_water(water)
    if horizon is not None:
        if isinstance(horizon, numbers.Integral) and not isinstance(horizon, bool) and horizon > config.max_steps:
            # (the bare range [1, 2250] did not say where 2250 came from)
            raise ParameterError(f"horizon must be at most the step budget, {config.max_steps} steps (config.max_steps, "
                                 f"--max-steps in the CLI: {config.max_steps * config.dt:.3g} s of fine steps at "
                                 f"dt {config.dt:g} s; the duration is {config.duration:g} s), got {horizon}")
        horizon = check_int("horizon", horizon, minimum=1, maximum=config.max_steps)
    # (the surrogate ignores record: configurations differing only there share one program)
    program_config = dataclasses.replace(config, record=False, max_steps=config.max_steps if horizon is None else horizon)

    _warn_stability(box, rigid, config, water)
    rng = np.random.default_rng(seed)
    history, best, forward = [], _Best(box, objective), 0
    screened = None
    if screen:
        pool = _random_points(box, screen, rng)
        counts, dists, cut = _exact(box, pool, rigid, config, water=water)
        forward += screen
        best.update(pool, counts, dists, cut)
        order = np.argsort(-(dists if objective == "distance" else counts), kind="stable")[:starts]
        points = {k: np.asarray(v)[order] for k, v in pool.items()}
        screened = {"points": {k: np.asarray(v, dtype=float).tolist() for k, v in pool.items()},
                    "bounces": counts.tolist(), **({"distance": dists.tolist()} if objective == "distance" else {})}
    else:
        points = _random_points(box, starts, rng)
    if initial is not None:
        # the first start, or with a screen the last (the weakest picked: the best screened throw still starts, so
        # the history's points, which the polish and the picture read, hold it)
        slot = starts - 1 if screen else 0
        for name, value in initial.items():
            points[name][slot] = value
    u = float_array(box.from_user(points))
    args = (u, tuple(float_array(a) for a in box.numbers()), float_leaves(rigid), float_leaves(water),
            float_array(width))
    if progress:  # (a compile of the whole throw's gradient: 10-40 s on 2 cores, silent otherwise)
        print("  preparing the gradient program ...", file=sys.stderr, flush=True)
    t_compile, misses = time.perf_counter(), _surrogate_program.cache_info().misses
    value_and_grad, sharding = _surrogate_program(objective, program_config, box.layout, _signature(args))
    # 0 when an earlier search compiled the same program
    t_compile = time.perf_counter() - t_compile if _surrogate_program.cache_info().misses > misses else 0.0
    if progress:
        print(f"  {f'compiled in {t_compile:.1f} s' if t_compile else 'reused from an earlier search'}",
              file=sys.stderr, flush=True)
    # from the host: a device array's device_put to the sharding compiles a slicing program first
    place = (lambda a: a) if sharding is None else (lambda a: jax.device_put(np.asarray(a), sharding))  # noqa: E731
    hyper = (float_array(learning_rate), float_array(clip))
    t_grad = 0.0
    state = _init_optimizer(u)
    line = ProgressLine()
    # The ascent needs the surrogate alone; the iterates' true counts are simulated together after it, on the
    # pool's full width: one batch of (iterations + 1) x starts throws ran 2.4x faster than a batch of the starts
    # per iteration (measured 2026-12-07, 128 long throws: 2.5 against 6.2 s), which had cost the search most of
    # its wall time (a benchmark audit).
    visited = []
    for it in range(iterations + 1):
        values = box.to_user(np.asarray(u))
        entry = {"iteration": it, "objective": None, "nonfinite": 0,
                 "points": {k: np.asarray(v, dtype=float).tolist() for k, v in values.items()}}
        visited.append((values, entry))
        if it == iterations:
            break
        t1 = time.perf_counter()
        obj, g = jax.block_until_ready(value_and_grad(place(u), *args[1:]))
        t_grad += time.perf_counter() - t1
        g = np.asarray(g)  # (starts, P): checked on the host (eager jnp ops would compile each)
        finite = np.all(np.isfinite(g), axis=-1)
        g = np.where(finite[:, None], g, 0.0)
        # the norms in float64: a float32 gradient's square overflows from ~1.8e19 (chaos reaches 1e20)
        norms = [float(v) if ok else None for v, ok in zip(np.linalg.norm(g.astype(np.float64), axis=-1), finite)]
        u, state = _ascend_all(float_array(_below_overflow(g)), state, u, *hyper)
        entry.update(objective=np.asarray(obj).tolist(), nonfinite=int(np.sum(~np.asarray(finite))), grad_norm=norms,
                     **({"screen": screened} if it == 0 and screened else {}))
        if progress:
            big = sum(1 for v in norms if v is None or v > EXPLODING)
            # (the mean of the finite values: a diverged start's objective is NaN)
            ok = np.asarray(obj)[np.isfinite(np.asarray(obj))]
            mean = f"{float(np.mean(ok)):.2f}" if ok.size else "nan"
            found = f"mean distance {mean} m" if objective == "distance" else f"smooth count's mean {mean}"
            line.update(f"  iteration {it + 1}/{iterations}: {found}, {big}/{starts} gradients exploding")
    if progress:
        line.close()
        print(f"  simulating the {len(visited) * starts} throws the ascent visited ...", file=sys.stderr, flush=True)
    every = {k: np.concatenate([np.asarray(v[k], dtype=float) for v, _ in visited]) for k in visited[0][0]}
    counts_all, dists_all, cut_all = _exact(box, every, rigid, config, water=water, progress=progress)
    forward += len(visited) * starts
    for i, (values, entry) in enumerate(visited):
        part = slice(i * starts, (i + 1) * starts)
        counts, dists, cut = counts_all[part], dists_all[part], cut_all[part]
        best.update(values, counts, dists, cut)
        exact = {"bounces": counts.tolist(), **({"distance": dists.tolist()} if objective == "distance" else {})}
        # (the keys in the order the history has always had them)
        history.append({"iteration": entry.pop("iteration"), **exact, "objective": entry.pop("objective"),
                        "best": best.bounces, **entry})
    if progress:
        found = f"longest {best.distance:.2f} m" if objective == "distance" else f"best {best.bounces} bounces"
        print(f"  the ascent's throws: {found}", file=sys.stderr, flush=True)
    if polish:
        forward += _polish(box, history, POLISH_CENTRES, polish, polish_scale, rigid, config, water, seed, progress,
                           best, iterations + 1)
    best.warn("gradient search", config)
    return best.result("gradient", history, t0, forward, gradient_evals=starts * iterations, gradient_time=t_grad,
                       compile_time=t_compile, objective=objective)


def _polish(box, visited, k, throws, scale, rigid, config, water, seed, progress, best: _Best, iteration) -> int:
    """:func:`local_search` of ``throws`` exact throws around the ``k`` best distinct throws in
    ``visited`` (entries with ``"points"`` and ``"bounces"``, or ``"distance"`` when ``best`` ranks by
    distance); updates ``best``, appends the polish's history entry (``"phase": "polish"``) to
    ``visited`` and returns the throws it simulated."""
    with silenced_batches(coarse=True):  # (the search warns once for all its throws, these included)
        local = local_search(box, top_throws(visited, k, best.objective), throws=throws, scale=scale, stone=rigid,
                             config=config, water=water, seed=seed, objective=best.objective, progress=progress)
    entry = local.history[0]
    best.update(entry["points"], entry["bounces"], entry["distance"], entry["cut_off"])
    if best.objective == "bounces":
        entry = {k: v for k, v in entry.items() if k != "distance"}
    visited.append(dict(entry, iteration=iteration, best=best.bounces))
    return local.forward_throws


def top_throws(history: list, k: int, objective: str = "bounces") -> dict:
    """The ``k`` distinct throws with the highest true counts (``objective="distance"``: the longest
    true distances) in a search's ``history``.

    Returns {parameter: (m,) array} in user units, best first (``m <= k``). Needs the
    ``"points"`` of each history entry (:func:`gradient_search` records them), and their
    ``"distance"`` for the distance objective.
    """
    k = check_int("k", k, minimum=1)
    key = _check_objective(objective)
    if not isinstance(history, (list, tuple)) or not all(isinstance(h, dict) for h in history):
        raise ParameterError("history must be a search's history, a list of dicts (SearchResult.history), got "
                             f"{type(history).__name__}")
    names = list(history[0]["points"]) if history and "points" in history[0] else []
    if not names:
        raise ParameterError("history has no points: top_throws needs a gradient_search history")
    if any(key not in h for h in history if "points" in h):
        raise ParameterError(f"history has no {key!r} for every entry: search with objective={key!r}")
    for i, h in enumerate(history):   # (a hand-edited or reloaded history met raw ValueErrors and IndexErrors)
        if "points" not in h:
            continue
        points = h["points"]
        if not isinstance(points, dict) or sorted(points) != sorted(names):
            raise ParameterError(f"history entry {i}: 'points' must be a dict of the same parameters as the first "
                                 f"entry's ({', '.join(names)}), got {points!r:.80}")
        sizes = {np.size(points[n]) for n in names} | {np.size(h[key])}
        if len(sizes) != 1:
            raise ParameterError(f"history entry {i}: its points and its {key!r} must give one value per throw, got "
                                 f"lengths {sorted(np.size(points[n]) for n in names)} and {np.size(h[key])}")
    pts = np.stack([np.concatenate([np.asarray(h["points"][n], float) for h in history if "points" in h])
                    for n in names], axis=-1)
    counts = np.concatenate([np.asarray(h[key], float) for h in history if "points" in h])
    chosen = []
    for i in np.argsort(-counts, kind="stable"):
        if not any(np.allclose(pts[i], pts[j]) for j in chosen):
            chosen.append(i)
        if len(chosen) == k:
            break
    return {n: pts[chosen, c] for c, n in enumerate(names)}


@_recorded
def local_search(box: Box, centres: dict, *, throws: int = 256, scale: float = 0.03, stone="paper",
                 config: SimConfig | None = None, lanes: int | None = None, seed: int = 0,
                 objective: str = "bounces", water: WaterParams | None = None, progress: bool = False) -> SearchResult:
    """Exact counts of ``throws`` random throws near ``centres`` (the best one wins: the most bounces,
    or with ``objective="distance"`` the longest distance).

    ``box``: the bounds, as in :func:`gradient_search`: a :class:`~optimize.bounds.Box`
    (:func:`~optimize.bounds.make_box`), a dict such as :data:`optimize.HUMAN_BOX` ({name: (low, high)}
    searched, {name: value} held) or None (the human box); anything else is refused with
    :class:`~jaxskip.ParameterError`.
    ``centres``: {parameter: (m,) array} in user units, one entry per searched parameter of
    ``box`` (e.g. :func:`top_throws` of a gradient search). Throw ``i`` perturbs centre
    ``i mod m``: each searched parameter by a normal deviate of ``scale`` (in (0, 1] [-]) times its
    range (0.03: ±0.27 m/s, ±1.2°, ±0.9°, ±0.6 rev/s in the human box), clipped to the box.
    ``throws``: an integer in [1, 10^8] (:data:`MAX_THROWS`). ``seed`` and ``water`` as in
    :func:`gradient_search`; ``stone``, ``config``, ``lanes`` and ``progress`` as in
    :func:`grid_search` (``stone``: name, ``.obj`` path, mesh or :class:`jaxskip.RigidStone`;
    ``config``: a :class:`jaxskip.SimConfig`; ``lanes``: throws side by side, in [1, 10^6], default
    :func:`jaxskip.batch.default_lanes`; ``progress``: True or False, a progress line on stderr).

    Returns a :class:`SearchResult` (user units: m/s, deg, rev/s; fields as for :func:`gradient_search`):
    ``best`` the best throw, ``best_bounces`` its true count, ``best_distance`` its true distance [m],
    ``forward_throws`` the exact simulations run, ``wall_time`` [s]; ``history`` holds one entry
    (``"phase": "polish"``, ``"iteration"`` 0): every throw's ``"points"``, true ``"bounces"`` and
    ``"distance"`` [m], the ``"best"`` count, ``"objective"`` None and ``"nonfinite"`` 0.

    >>> from optimize import make_box
    >>> box = make_box({"speed": (6.0, 8.0)}, {"tilt": 20.0, "attack": 5.0, "spin": 20.0})
    >>> r = local_search(box, {"speed": [7.0]}, throws=4)
    >>> r.forward_throws, 6.0 <= r.best["speed"] <= 8.0
    (4, True)
    """
    t0 = time.perf_counter()
    box, config, progress = _common(box, config, progress)
    objective = _check_objective(objective)
    seed = _check_seed(seed)
    n = check_int("throws", throws, minimum=1, maximum=MAX_THROWS)
    check_range("scale", scale, 0.0, 1.0, low_open=True)
    if not isinstance(centres, Mapping):
        raise ParameterError(f"centres must be a dict {{parameter: (m,) array}} of the searched parameters "
                             f"({', '.join(box.names)}), got {type(centres).__name__}")
    held = sorted(set(centres) & set(dict(box.held)))
    if held:  # (dropped silently before, even tilt 99 deg)
        raise ParameterError(f"centres gives {', '.join(held)}, held by the box, not searched: drop it from centres, "
                             "or search it (make_box({name: (low, high)}))")
    unknown = sorted(map(repr, set(centres) - set(box.names)))
    if unknown:  # (ignored before: a misspelt name ran as if it were not there)
        raise ParameterError(f"centres gives {', '.join(unknown)}, not a searched parameter; the box searches "
                             f"{', '.join(box.names)}")
    m = None
    for name, lo, hi in box.searched:
        if name not in centres:
            raise ParameterError(f"centres must give every searched parameter; missing {name!r}")
        try:
            c = np.atleast_1d(np.asarray(centres[name]))
            if c.dtype.kind not in "iuf":   # ("7" converted to 7.0 before; True to 1.0)
                raise TypeError
            c = c.astype(float)
        except (TypeError, ValueError):
            raise ParameterError(f"centres[{name!r}] must be numbers in user units, got {centres[name]!r:.60}") from None
        if c.ndim != 1 or c.size == 0 or (m is not None and c.size != m):
            raise ParameterError(f"centres[{name!r}] must be a non-empty 1-D array of the same length as the others")
        tol = 1e-9 * (hi - lo)  # to_user's rounding at a saturated coordinate may overshoot by an ulp
        if not np.all((c >= lo - tol) & (c <= hi + tol)):
            raise ParameterError(f"centres[{name!r}] must lie within the box [{lo}, {hi}], got {c}")
        m = c.size
    rng = np.random.default_rng(seed)
    pick = np.arange(n) % m
    values = {}
    for name, lo, hi in box.searched:
        c = np.atleast_1d(np.asarray(centres[name], dtype=float))[pick]
        values[name] = np.clip(c + scale * (hi - lo) * rng.standard_normal(n), lo, hi)
    rigid, _ = resolve_stone(stone)
    water = None if water is None else checked_water(water)
    _warn_stability(box, rigid, config, water)
    counts, dists, cut = _exact(box, values, rigid, config, lanes, progress, water)
    best = _Best(box, objective)
    best.update(values, counts, dists, cut)
    best.warn("local search", config)
    hist = [{"iteration": 0, "phase": "polish", "bounces": counts.tolist(), "distance": dists.tolist(),
             "cut_off": cut.astype(int).tolist(), "objective": None, "best": best.bounces, "nonfinite": 0,
             "points": {k: v.tolist() for k, v in values.items()}}]
    return best.result("local", hist, t0, n, objective=objective)


def _starts_sharding(starts: int):
    """The starts' axis split over as many local devices as divide it evenly (None: one device)."""
    devices = jax.local_devices()
    d = max(k for k in range(1, len(devices) + 1) if starts % k == 0)
    if d == 1:
        return None
    mesh = jax.sharding.Mesh(np.array(devices[:d]), ("starts",))
    return jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec("starts"))


def _optimizer(learning_rate, clip) -> optax.GradientTransformation:
    """Adam after a clip to global norm ``clip`` (per start; ``clip=None``: Adam alone). The
    hyperparameters may be traced: the compiled step below serves every value, and the optimizer's state
    does not depend on them."""
    adam = optax.adam(learning_rate)
    return adam if clip is None else optax.chain(optax.clip_by_global_norm(clip), adam)


@functools.partial(jax.jit, static_argnames="clipped")
def _init_optimizer(u, clipped: bool = True):
    """The optimizer's state for each start: ``u`` (starts, P) -> a batched optax state."""
    return jax.vmap(_optimizer(1.0, 1.0 if clipped else None).init)(u)


@functools.partial(jax.jit, static_argnames="clipped")
def _ascend_all(g, state, u, learning_rate, clip=None, clipped: bool = True):
    """One optax step per start that *increases* the objective (optax minimises: it is fed -g).
    ``g``, ``u`` (starts, P); ``learning_rate``, ``clip`` () (traced: one compile for all values; with
    ``clipped=False`` no clip, ``clip`` unused: Adam alone, as the perturbation search steps)."""
    opt = _optimizer(learning_rate, clip if clipped else None)

    def one(g, state, u):
        updates, state = opt.update(-g, state, u)
        return optax.apply_updates(u, updates), state

    return jax.vmap(one)(g, state, u)


def _signature(args) -> tuple:
    """What a compiled program is keyed on besides the static configuration: the arguments' tree
    structure and each leaf's shape and dtype (hashable)."""
    leaves, tree = jax.tree_util.tree_flatten(args)
    return tree, tuple((tuple(a.shape), str(a.dtype)) for a in leaves)


@functools.lru_cache(maxsize=8)
def _surrogate_program(objective: str, config: SimConfig, layout: tuple, signature: tuple):
    """The compiled ``(u, box_numbers, stone, water, width) -> (values, gradients)`` of the surrogate for
    every start (``u`` (starts, P) unconstrained; the box's numbers (:meth:`~optimize.bounds.Box.numbers`:
    bounds and held values), ``stone``, ``water``, ``width`` [m] are arguments, not constants, so a
    search with other values, or a repeated search, reuses the program: compiling the whole throw's
    reverse pass takes 15-40 s on a 2-core machine). Memoised on the static configuration, the box's
    ``layout`` (:attr:`~optimize.bounds.Box.layout`: which parameters are searched) and ``signature``
    (:func:`_signature`); returns ``(compiled, sharding of u)``.

    The starts are split over the local devices (``import jaxskip`` makes one CPU device per core):
    each device runs ``lax.map`` over its share (shard_map; a map, not a vmap, so every rollout keeps
    its skip of finished segments)."""
    tree, leaves = signature

    def value_and_grad(u, numbers, stone, water, width):
        f = make_objective(objective, config, stone, water, width)
        return jax.lax.map(jax.value_and_grad(lambda ui: f(throw_in_box(layout, ui, *numbers))), u)

    starts = leaves[0][0][0]
    sharding = _starts_sharding(starts)
    if sharding is not None:
        spec, rep = sharding.spec, jax.sharding.PartitionSpec()
        value_and_grad = jax.shard_map(value_and_grad, mesh=sharding.mesh, in_specs=(spec, rep, rep, rep, rep),
                                       out_specs=(spec, spec), check_vma=False)  # per-shard work, no collectives
    shapes = [jax.ShapeDtypeStruct(shape, np.dtype(dtype)) for shape, dtype in leaves]
    if sharding is not None:
        shapes[0] = jax.ShapeDtypeStruct(shapes[0].shape, shapes[0].dtype, sharding=sharding)
    abstract = jax.tree_util.tree_unflatten(tree, shapes)
    return jax.jit(value_and_grad).lower(*abstract).compile(), sharding


@_recorded
def perturbation_search(box: Box | None = None, *, stone="paper", config: SimConfig | None = None,
                        starts: int = 8, iterations: int = 20, samples: int = 8, sigma: float = 0.3,
                        learning_rate: float = 0.3, seed: int = 0, polish: int = 0, polish_scale: float = 0.03,
                        water: WaterParams | None = None, progress: bool = False) -> SearchResult:
    r"""Randomised smoothing: ascend :math:`E[N(u + \sigma\epsilon)]` with antithetic estimates.

    The gradient of the smoothed exact count at ``u`` (unconstrained coordinates) is
    :math:`\frac{1}{2\sigma m}\sum_k [N(u+\sigma\epsilon_k) - N(u-\sigma\epsilon_k)]\,\epsilon_k`
    over ``samples`` = m pairs (an integer in [1, 4096], :data:`MAX_SAMPLES`), :math:`\epsilon_k`
    standard normal; ``sigma`` (in (0, 10], :data:`MAX_STEP`) is the smoothing scale in the unconstrained (logit) coordinates
    of the box (dimensionless: 0.3 moves a parameter at the middle of its range by ~7 % of the range);
    every count is an exact simulation. Nothing is differentiated,
    so the rollout's chaos (its pathwise gradients grow e-fold every ~40-50 ms of contact,
    benchmarks/README.md) does not reach the estimate: it is the estimator a chaotic count calls
    for. ``starts`` random centres (an integer in [1, 4096]) are each evaluated ``iterations`` times (an
    integer in [1, 10^5]), with an Adam step of ``learning_rate`` between two evaluations
    (``iterations - 1`` steps: one after the last would never be simulated); ``learning_rate`` in (0, 10]
    (:data:`MAX_STEP`; unconstrained coordinates).
    ``polish`` (an integer in [0, 10^8]) / ``polish_scale`` (in (0, 1] [-]) as in
    :func:`gradient_search`: exact throws near the best (up to 4) distinct throws evaluated, centres
    and samples alike. Every history entry lists the centres it simulated under ``"points"`` (their
    counts under ``"bounces"``). ``box``, ``seed``, ``water``, ``stone``, ``config`` and ``progress``
    as in :func:`gradient_search`. Each iteration simulates ``starts * (2 * samples + 1)`` throws.

    Returns a :class:`SearchResult` (user units: m/s, deg, rev/s; fields as for :func:`gradient_search`):
    ``best`` the best throw, ``best_bounces`` its true count, ``best_distance`` its true distance [m],
    ``forward_throws`` the exact simulations run, ``wall_time`` [s]; ``gradient_evals`` is 0 (nothing
    is differentiated); ``history`` holds one entry per iteration: its ``"iteration"``, the centres' true
    ``"bounces"``, the mean true count of each start's ``2 * samples + 1`` throws, centre included
    (``"objective"``), the ``"best"`` count so far, ``"nonfinite"`` 0 and the centres' ``"points"``
    (then the polish's entry, ``"phase": "polish"``, as :func:`local_search`'s without ``"distance"``).
    """
    t0 = time.perf_counter()
    box, config, progress = _common(box, config, progress)
    seed = _check_seed(seed)
    starts = check_int("starts", starts, minimum=1, maximum=MAX_STARTS)
    iterations = check_int("iterations", iterations, minimum=1, maximum=MAX_ITERATIONS)
    samples = check_int("samples", samples, minimum=1, maximum=MAX_SAMPLES)
    polish = check_int("polish", polish, minimum=0, maximum=MAX_THROWS)
    check_range("polish_scale", polish_scale, 0.0, 1.0, low_open=True)
    check_range("sigma", sigma, 0.0, MAX_STEP, low_open=True)
    check_range("learning_rate", learning_rate, 0.0, MAX_STEP, low_open=True)
    rigid, _ = resolve_stone(stone)
    water = None if water is None else checked_water(water)
    _warn_stability(box, rigid, config, water)
    rng = np.random.default_rng(seed)
    u = box.from_user(_random_points(box, starts, rng))
    state = _init_optimizer(float_array(u), clipped=False)  # no clip: the estimates are finite counts
    rate = float_array(learning_rate)
    p = u.shape[-1]
    history, visited, best, forward = [], [], _Best(box, "bounces"), 0
    line = ProgressLine()
    for it in range(iterations):
        eps = rng.standard_normal((starts, samples, p))
        pts = np.concatenate([u[:, None, :] + sigma * eps, u[:, None, :] - sigma * eps, u[:, None, :]], axis=1)
        values = box.to_user(pts.reshape(-1, p))
        counts, dists, cut = _exact(box, values, rigid, config, water=water)
        counts = counts.reshape(starts, 2 * samples + 1)
        forward += counts.size
        best.update(values, counts, dists, cut)
        best_n = best.bounces
        visited.append({"bounces": counts.ravel().tolist(), "points": {k: v.tolist() for k, v in values.items()}})
        scored = np.maximum(counts, 0)  # a diverged throw (DIVERGED_SCORE) counts as no bounce in the estimate
        diff = (scored[:, :samples] - scored[:, samples:2 * samples]).astype(float)
        g = np.einsum("sk,skp->sp", diff, eps) / (2.0 * sigma * samples)
        if it + 1 < iterations:  # (a step after the last evaluation would never be simulated)
            u, state = _ascend_all(float_array(g), state, float_array(u), rate, clipped=False)
            u = np.asarray(u)
        centres = {k: np.asarray(v).reshape(starts, -1)[:, -1].tolist() for k, v in values.items()}
        history.append({"iteration": it, "bounces": counts[:, -1].tolist(), "objective": scored.mean(1).tolist(),
                        "best": best_n, "nonfinite": 0, "points": centres})
        if progress:
            line.update(f"  iteration {it + 1}/{iterations}: best {best_n} bounces")
    if progress:
        line.close()
    if polish:
        forward += _polish(box, visited, POLISH_CENTRES, polish, polish_scale, rigid, config, water, seed, progress,
                           best, iterations)
        history.append(visited[-1])
    best.warn("perturbation search", config)
    return best.result("perturbation", history, t0, forward)


def grid_points(box: Box, per_axis: int) -> dict:
    """A regular grid with ``per_axis`` points along every searched parameter (user units); at most
    10^8 points in all."""
    box = _as_box(box)
    per_axis = check_int("per_axis", per_axis, minimum=2, maximum=MAX_PER_AXIS)
    if per_axis ** len(box.searched) > MAX_GRID_POINTS:
        top = int(MAX_GRID_POINTS ** (1.0 / len(box.searched)) + 1e-9)
        raise ParameterError(f"per_axis must be at most {top} for {len(box.searched)} searched parameters "
                             f"(at most 10^8 grid points), got {per_axis}")
    axes = [np.linspace(lo, hi, per_axis) for _, lo, hi in box.searched]
    mesh = np.meshgrid(*axes, indexing="ij")
    return {name: m.ravel() for (name, _, _), m in zip(box.searched, mesh)}


def _exhaustive(method: str, box: Box, values: dict, stone, config: SimConfig, lanes: int, progress: bool, water):
    t0 = time.perf_counter()
    rigid, _ = resolve_stone(stone)
    water = None if water is None else checked_water(water)
    _warn_stability(box, rigid, config, water)
    counts, dists, cut = _exact(box, values, rigid, config, lanes, progress, water)
    best = _Best(box, "bounces")
    best.update(values, counts, dists, cut)
    best.warn(f"{method} search", config)
    # (the histogram of the true counts: a diverged throw has none)
    hist = [{"iteration": 0, "bounces": [best.bounces], "objective": None, "best": best.bounces,
             "nonfinite": 0, "count_histogram": np.bincount(counts[counts >= 0], minlength=1).tolist(),
             "diverged": int(np.sum(counts < 0)), "cut_off": int(np.sum(cut))}]
    return best.result(method, hist, t0, int(counts.size))


@_recorded
def grid_search(box: Box | None = None, *, per_axis: int = 10, stone="paper", config: SimConfig | None = None,
                lanes: int | None = None, water: WaterParams | None = None, progress: bool = False) -> SearchResult:
    """Exhaustive search: every point of a regular grid simulated exactly (``per_axis`` ** P throws for
    P searched parameters, :func:`grid_points`).

    ``per_axis``: grid points along each searched parameter, its ends included, an integer in
    [2, 10^4] (:data:`MAX_PER_AXIS`), with at most 10^8 points in all (:data:`MAX_GRID_POINTS`).
    ``box`` and ``water`` as in :func:`gradient_search`. ``stone``: a built-in name (default
    ``"paper"``), an ``.obj`` path [m], a :class:`jaxskip.TriMesh` or a :class:`jaxskip.RigidStone`.
    ``config``: the :class:`jaxskip.SimConfig` of every throw (default ``SimConfig()``; its ``record``
    is ignored). ``lanes``: throws simulated side by side, an integer in [1, 10^6] (default None:
    :func:`jaxskip.batch.default_lanes`; :func:`jaxskip.simulate_batch`). ``progress``: True or False:
    print a progress line to stderr.

    Returns a :class:`SearchResult` (user units: m/s, deg, rev/s; fields as for :func:`gradient_search`):
    ``best`` the best throw, ``best_bounces`` its true count, ``best_distance`` its true distance [m],
    ``forward_throws`` the exact simulations run, ``wall_time`` [s]; ``history`` holds one entry, with
    the histogram of the counts (``"count_histogram"``), ``"iteration"`` 0, ``"bounces"`` (a one-element
    list: the best count), the ``"best"`` count, ``"objective"`` None and ``"nonfinite"`` 0.

    >>> from optimize import make_box
    >>> box = make_box({"speed": (6.0, 8.0)}, {"tilt": 20.0, "attack": 5.0, "spin": 20.0})
    >>> r = grid_search(box, per_axis=4)  # speeds 6, 6.67, 7.33, 8 m/s
    >>> r.forward_throws, sum(r.history[0]["count_histogram"]), bool(r.best["speed"] in grid_points(box, 4)["speed"])
    (4, 4, True)
    """
    box, config, progress = _common(box, config, progress)
    return _exhaustive("grid", box, grid_points(box, per_axis), stone, config, lanes, progress, water)


@_recorded
def random_search(box: Box | None = None, *, throws: int = 1000, stone="paper", config: SimConfig | None = None,
                  lanes: int | None = None, seed: int = 0, water: WaterParams | None = None,
                  progress: bool = False) -> SearchResult:
    """Random search: ``throws`` uniform random points of the box simulated exactly.

    ``throws``: an integer in [1, 10^8] (:data:`MAX_THROWS`). ``box``, ``seed`` and ``water`` as in
    :func:`gradient_search`; ``stone``, ``config``, ``lanes`` and ``progress`` as in
    :func:`grid_search` (``stone``: name, ``.obj`` path, mesh or :class:`jaxskip.RigidStone`;
    ``config``: a :class:`jaxskip.SimConfig`; ``lanes``: throws side by side, in [1, 10^6], default
    :func:`jaxskip.batch.default_lanes`; ``progress``: True or False, a progress line on stderr).

    Returns a :class:`SearchResult` (user units: m/s, deg, rev/s; fields as for :func:`gradient_search`):
    ``best`` the best throw, ``best_bounces`` its true count, ``best_distance`` its true distance [m],
    ``forward_throws`` the exact simulations run, ``wall_time`` [s]; ``history`` holds one entry, with
    the histogram of the counts (``"count_histogram"``), ``"iteration"`` 0, ``"bounces"`` (a one-element
    list: the best count), the ``"best"`` count, ``"objective"`` None and ``"nonfinite"`` 0.

    >>> from optimize import make_box
    >>> box = make_box({"speed": (6.0, 8.0)}, {"tilt": 20.0, "attack": 5.0, "spin": 20.0})
    >>> r = random_search(box, throws=4, seed=1)
    >>> r.forward_throws, 6.0 <= r.best["speed"] <= 8.0, r.best["tilt"]
    (4, True, 20.0)
    """
    box, config, progress = _common(box, config, progress)
    n = check_int("throws", throws, minimum=1, maximum=MAX_THROWS)
    seed = _check_seed(seed)
    return _exhaustive("random", box, _random_points(box, n, np.random.default_rng(seed)), stone, config, lanes,
                       progress, water)


def _throw_text(throw: dict) -> str:
    """A throw in words, with the precision ``jaxskip optimize`` prints it:
    ``"speed 7.51 m/s, tilt 31.1°, attack 17.5°, spin 17.5 rev/s"``."""
    return (f"speed {throw['speed']:.2f} m/s, tilt {throw['tilt']:.1f}°, attack {throw['attack']:.1f}°, "
            f"spin {throw['spin']:.1f} rev/s")


def _best_text(result: SearchResult) -> str:
    """The best throw's score in words: its true count (and distance), or for the distance objective its
    distance (and count)."""
    d = result.best_distance
    # (a best throw the duration cut off was drawn as a final, "true" count: a review)
    cut = ", cut off: a lower bound" if result.best_cut_off else ""
    if result.objective == "distance" and d is not None:
        return f"longest distance {d:.2f} m ({result.best_bounces} bounces{cut})"
    return f"best {result.best_bounces} bounces" + ("" if d is None else f" ({d:.2f} m{cut})")


def _cut_note(result: SearchResult) -> str:
    """A legend line for the throws a search's run stopped while in play ("" when none was)."""
    if not result.cut_off:
        return ""
    return (f"{result.cut_off} throw{'s' if result.cut_off != 1 else ''} cut off while in play (duration, "
            "max_steps): lower bounds")


def _count_histogram(result: SearchResult) -> np.ndarray | None:
    """Throws per true bounce count (index: the count) of a search without iterations: the
    ``"count_histogram"`` a grid or random search records, or a local search's counts; None for an
    iterative search."""
    h = result.history
    if len(h) == 1 and "count_histogram" in h[0]:
        return np.asarray(h[0]["count_histogram"], dtype=int)
    if result.method == "local" and len(h) == 1:
        counts = np.asarray(h[0]["bounces"], dtype=int)
        return np.bincount(counts[counts >= 0], minlength=1)   # a diverged throw (DIVERGED_SCORE) has no count
    return None


def _histogram_figure(result: SearchResult, hist: np.ndarray):
    """A grid, random or local search: the histogram of the true bounce counts of every throw
    evaluated, the best count marked."""
    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator

    n = int(hist.sum())
    fig = Figure(figsize=(7.0, 4.6), layout="constrained")
    ax = fig.subplots()
    counts = np.arange(hist.size)
    best = result.best_bounces
    marked = (counts == best) & (hist > 0)
    failed = f"; {result.diverged} more diverged, not drawn" if result.diverged else ""
    cut = f"\n{_cut_note(result)}" if result.cut_off else ""
    ax.bar(counts[~marked], hist[~marked], width=0.8, color="C0", label=f"throws per count ({n} throws{failed}){cut}")
    if marked.any():
        k = int(hist[best])
        what = "the longest throw's count" if result.objective == "distance" else "the best count found"
        ax.bar([best], [k], width=0.8, color="C3", label=f"{what}: {best} bounces ({k} throw{'s' if k != 1 else ''})")
    nonzero = hist[hist > 0]
    log = nonzero.size > 0 and nonzero.max() > 30 * nonzero.min()
    if log:
        from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

        ax.set_yscale("log")  # ticks at 1, 2, 5, 10, 20, ... written as plain numbers (not 10^0, 10^1 alone)
        ax.yaxis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.yaxis.set_minor_formatter(NullFormatter())
    else:
        ax.yaxis.set_major_locator(MaxNLocator(integer=True))
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_xlim(-0.6, hist.size - 0.4)
    ax.set_xlabel("true bounce count (exact simulation) [bounces]")
    ax.set_ylabel("number of throws" + (" (log scale)" if log else ""))
    per_axis = round((n + result.diverged) ** (1.0 / max(len(result.box.searched), 1)))   # the grid had them all
    what = {"grid": f"regular grid, {per_axis} per searched parameter", "random": "uniform random throws",
            "local": "random throws near centres"}
    ax.set_title(f"{result.method} search ({what.get(result.method, 'exact throws')}, {n + result.diverged} throws): "
                 f"{_best_text(result)}\nat {_throw_text(result.best)}", fontsize=9)
    # below the panel, as the other pictures' (loc="best" put it over the best count's bar; a review)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=1, frameon=False)
    return fig


#: Largest gradient component [-] handed to the clip as it is (2^50): the clip squares it, and a square
#: beyond ~3.4e38 overflows float32 (the clip then divided by inf: a zero step, the start frozen).
_CLIP_SAFE = 2.0 ** 50


def _below_overflow(g: np.ndarray) -> np.ndarray:
    """Each start's gradient (a row of ``g``) scaled by a power of two down to at most :data:`_CLIP_SAFE`
    in its largest component, if beyond: exact in floating point, the same direction, and still far above
    any clip, so the clipped step is the one the unscaled gradient would give without overflow."""
    top = np.max(np.abs(g), axis=-1, initial=0.0)
    shift = np.where(top > _CLIP_SAFE, np.ceil(np.log2(np.maximum(top, 1.0) / _CLIP_SAFE)), 0.0).astype(int)
    return np.ldexp(g, -shift[:, None]).astype(g.dtype)


def _start_colours(n: int) -> list:
    """One colour per start (the same start in both panels); more than 10 starts share grey."""
    return [f"C{i}" for i in range(n)] if n <= 10 else ["0.6"] * n


def _iteration_ticks(ax, first: int, last: int, polish_at: int | None) -> None:
    """Integer iteration ticks from ``first`` to ``last``, and a tick labelled "polish" at ``polish_at``."""
    from matplotlib.ticker import MaxNLocator

    ticks = [int(t) for t in MaxNLocator(nbins=8, integer=True, min_n_ticks=1).tick_values(first, last)
             if first <= t <= last]
    labels = [str(t) for t in ticks]
    if polish_at is not None:
        ticks.append(polish_at)
        labels.append("polish")
    ax.set_xticks(ticks, labels)


def _search_figure(result: SearchResult):
    """The figure :func:`plot_search` saves (a :class:`matplotlib.figure.Figure`, no pyplot state)."""
    from matplotlib.figure import Figure
    from matplotlib.ticker import MaxNLocator

    hist = _count_histogram(result)
    if hist is not None:
        return _histogram_figure(result, hist)
    distance = result.objective == "distance" and all("distance" in h for h in result.history)
    key, unit = ("distance", "m") if distance else ("bounces", "bounces")
    steps = [h for h in result.history if h.get("phase") != "polish"]
    polish = [h for h in result.history if h.get("phase") == "polish"]
    norms = [h for h in steps if h.get("grad_norm")]
    fig = Figure(figsize=(12.5 if norms else 6.8, 5.2), layout="constrained")
    axes = fig.subplots(1, 2 if norms else 1, squeeze=False, sharex=True)[0]
    ax = axes[0]
    its = [int(h["iteration"]) for h in steps]
    per = np.array([h[key] for h in steps], dtype=float).reshape(len(steps), -1)
    colours = _start_colours(per.shape[1])
    what = "distance" if distance else "count"
    centres = result.method == "perturbation"  # its history lists the centres; its best counts their samples too
    start_label = (f"each start's centre: true {what}" if centres else f"each start's true {what}") + (
        " (a colour per start, as on the right)" if norms and per.shape[1] <= 10 else "")
    for i in range(per.shape[1]):
        ax.plot(its, per[:, i], "-", marker=".", color=colours[i], lw=0.9, ms=4, alpha=0.8,
                label=start_label if i == 0 else None)
    xs = list(its)
    if distance:  # the best so far: the running maximum of the distances evaluated
        best = list(np.maximum.accumulate(np.nanmax(per, axis=1)))
    else:
        best = [h["best"] for h in steps]
    polish_at = None
    if polish:
        polish_at = its[-1] + 1
        p = np.asarray(polish[-1][key], dtype=float)
        jitter = np.linspace(-0.3, 0.3, p.size) if p.size > 1 else np.zeros(1)
        ax.plot(polish_at + jitter, p, "o", color="0.35", ms=3, alpha=0.5, mec="none",
                label=f"polish: {p.size} exact throws near the best (spread sideways)")
        ax.axvline(polish_at - 0.5, color="0.6", ls=":", lw=0.8)
        xs.append(polish_at)
        best.append(max(best[-1], float(np.max(p))) if distance else polish[-1]["best"])
    ax.plot(xs, best, "k-o", ms=4, lw=1.6, zorder=1.5,
            label=f"best true {what} so far" + (" (centres and their samples)" if centres else ""))
    _iteration_ticks(ax, its[0], its[-1], polish_at)
    if not distance:
        ax.yaxis.set_major_locator(MaxNLocator(integer=True))
        low, high = np.nanmin(per), np.nanmax(np.append(per.ravel(), best))
        if high - low < 2:   # (equal counts gave ticks of 4.74...5.22 or -0.045...0.045 bounces: a review)
            ax.set_ylim(low - 1.5, high + 1.5)
    if result.cut_off:
        ax.plot([], [], " ", label=_cut_note(result))
    ax.set_xlabel("iteration")
    ax.set_ylabel(f"true {'distance' if distance else 'bounce count'} (exact simulation) [{unit}]")
    ax.set_title(f"{result.method} search: {_best_text(result)}\nat {_throw_text(result.best)}", fontsize=9)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=1 if result.cut_off else 2,
              frameon=False)
    if norms:
        _norm_panel(axes[1], norms, colours, its[-1] if polish_at is None else polish_at, unit,
                    gradient_health(result)["starts"])
    return fig


def _norm_panel(ax, norms: list, colours: list, last: int, unit: str, starts: dict) -> None:
    """Every start's raw gradient norm per iteration (log scale), :data:`EXPLODING` and :data:`VANISHING`
    marked; ``last``: the last position of the shared iteration axis (the final evaluation, or the polish);
    ``starts``: :func:`gradient_health`'s per-start counts, for the title (one definition of exploding
    and vanishing)."""
    its = [int(h["iteration"]) for h in norms]
    g = np.array([[np.nan if v is None else v for v in h["grad_norm"]] for h in norms], dtype=float)
    shown = np.where(g > 0, g, np.nan)
    edge = ax.get_xaxis_transform()  # x in data, y in axes fraction
    flagged = {"non-finite (drawn at the top edge)": (~np.isfinite(g), 0.97, "x"),
               "exactly 0 (drawn at the bottom edge)": (g == 0, 0.03, "v")}
    labelled = set()
    for i in range(g.shape[1]):
        ax.plot(its, shown[:, i], "o-", color=colours[i], ms=3, lw=0.9, alpha=0.8)
        for label, (mask, y, marker) in flagged.items():
            if mask[:, i].any():
                ax.plot(np.asarray(its)[mask[:, i]], np.full(int(mask[:, i].sum()), y), marker, color=colours[i],
                        transform=edge, ms=6, label=None if label in labelled else label)
                labelled.add(label)
    ax.set_yscale("log")
    ax.axhline(EXPLODING, color="k", ls="--", lw=1, label=f"exploding: above {EXPLODING:g} (chaos, not trend)")
    ax.axhline(VANISHING, color="k", ls=":", lw=1.2, label=f"vanishing: below {VANISHING:g} (flat, nothing to climb)")
    # the final evaluation (and the polish) only simulate: no gradient there
    if max(its) < last:
        ax.axvspan(max(its) + 0.5, last + 0.5, color="0.92", lw=0,
                   label="no gradient: final evaluation" + (" and polish" if last > max(its) + 1 else ""))
    ax.set_xlabel("iteration")
    ax.set_ylabel(f"raw gradient norm [{unit} per unconstrained unit]")
    n = starts["n"]
    ax.set_title(f"raw gradient norms (before clipping) of {n} start{'s' if n != 1 else ''}\n"
                 f"starts whose gradient exploded at some iteration: {starts['exploding']}\n"
                 f"starts whose gradient vanished at every iteration: {starts['vanishing']}; "
                 f"at some iteration: {starts['vanishing_some']}", fontsize=9)
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.13), ncol=2, frameon=False)


def plot_search(result: SearchResult, path) -> None:
    """Save a picture of a search to ``path`` (its suffix picks the format: .png, .pdf, .svg or another matplotlib
    writes; a path without one is refused).

    An iterative search (gradient, perturbation): every start's true count (or distance) and the best
    so far per iteration, the polish's throws at the tick "polish"; for a gradient search, a second
    panel with every start's raw gradient norm per iteration (log scale, :data:`EXPLODING` and
    :data:`VANISHING` marked): gradient-norm monitoring at a glance. A grid, random or local search:
    the histogram of the true bounce counts of every throw evaluated, the best count marked.

    ``result``: a :class:`SearchResult` (of :func:`gradient_search`, :func:`perturbation_search`,
    :func:`grid_search`, :func:`random_search` or :func:`local_search`); anything else is refused with
    :class:`~jaxskip.ParameterError`."""
    if not isinstance(result, SearchResult):
        raise ParameterError("result must be a SearchResult (as returned by gradient_search, perturbation_search, "
                             f"grid_search, random_search or local_search), got {type(result).__name__}")
    check_picture_path("path", path)
    with writing(path):
        _search_figure(result).savefig(path, dpi=120)


__all__ = ["EXPLODING", "VANISHING", "SearchResult", "gradient_health", "gradient_search", "grid_points", "grid_search", "local_search", "perturbation_search",
           "plot_search", "random_search", "top_throws"]
