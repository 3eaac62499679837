r"""Search boxes over throw parameters, in user units at the edge and SI inside.

A :class:`Box` holds, for each throw parameter, either an interval
(searched) or a single value (held). Searched parameters are reparameterised
so that an unconstrained optimiser never leaves the box:

.. math:: \theta = \theta_{lo} + (\theta_{hi} - \theta_{lo})\,\sigma(u),
          \qquad \sigma(u) = 1 / (1 + e^{-u}).
"""

from __future__ import annotations

import dataclasses
import math
import types
from collections.abc import Mapping

import jax
import jax.numpy as jnp
import numpy as np

from jaxskip import Throw
from jaxskip._checks import ParameterError, check_real
from jaxskip._docs import document_fields

#: Physical limits of each throw parameter in user units: (low, high, unit). Read-only (make_box reads it at each
#: call: widening it let every later box through; a review, stop 48).
LIMITS = types.MappingProxyType({
    "speed": (0.1, 50.0, "m/s"),
    "tilt": (-89.0, 89.0, "deg"),
    "attack": (0.0, 89.0, "deg"),
    "spin": (0.0, 200.0, "rev/s"),
})
#: The parameters a search may vary, in this order.
PARAMETERS = tuple(LIMITS)
#: The user's box of issue 4: a human throw (speed 3-12 m/s, tilt 5-45 deg, attack 0-30 deg, spin 0-20 rev/s).
#: Read-only (a change here changed every later default search): ``dict(HUMAN_BOX)`` gives a copy to edit.
HUMAN_BOX = types.MappingProxyType({"speed": (3.0, 12.0), "tilt": (5.0, 45.0), "attack": (0.0, 30.0),
                                    "spin": (0.0, 20.0)})


def check_interval(name: str, value, low: float, high: float, *, unit: str = "",
                   low_open: bool = False, holdable: bool = True) -> tuple[float, float]:
    """Validate ``value = (lo, hi)``: finite, ``lo < hi``, inside ``[low, high]`` (``(low, high]`` with
    ``low_open``); returns floats. ``name``: the parameter's name in the message; ``unit``: its unit there
    (e.g. ``"m/s"``; the interval is in that unit). ``holdable``: an empty interval's message suggests a single
    value to hold the parameter instead (a search's box; not a U_min sweep's bisection bracket)."""
    u = f" {unit}" if unit else ""
    valid = f"within {'(' if low_open else '['}{low:g}, {high:g}]{u}"
    pair = f"a pair (low, high) of numbers {valid}"
    if isinstance(value, (str, bytes)):   # "39" would unpack to (3, 9)
        raise ParameterError(f"{name} must be {pair}, got {value!r}")
    try:
        lo, hi = value
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be {pair}, got {value!r}") from None
    if any(isinstance(v, (str, bytes, bool, np.bool_)) for v in (lo, hi)):   # True is not 1 m/s
        raise ParameterError(f"{name} must be {pair}, got {value!r}")
    try:
        lo, hi = float(lo), float(hi)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be {pair}, got {value!r}") from None
    if not (math.isfinite(lo) and math.isfinite(hi)):
        raise ParameterError(f"{name} must be finite and lie {valid}, got ({lo}, {hi})")
    if lo > hi:
        raise ParameterError(f"{name} is inverted: low {lo} > high {hi}{u} (give low < high, {valid})")
    if lo == hi:
        raise ParameterError(f"{name} is empty: low = high = {lo}{u} (give low < high, {valid}"
                             + (", or a single value to hold it instead)" if holdable else ")"))
    if lo < low or (low_open and lo == low) or hi > high:
        raise ParameterError(f"{name} must lie {valid}, got ({lo}, {hi})")
    return lo, hi


@document_fields
@dataclasses.dataclass(frozen=True)
class Box:
    """Bounds of a search, user units (m/s, deg, rev/s). Static and hashable.

    ``searched`` is a tuple of ``(name, low, high)`` entries, one per varied parameter;
    ``held`` a tuple of ``(name, value)`` entries for the others (tuples, not dicts, so
    that the box hashes; :meth:`to_dict` gives the dict form). Build it with :func:`make_box`,
    which takes dicts ``{name: (low, high)}`` and ``{name: value}``.
    """

    searched: tuple
    """((name, low, high), ...) in :data:`PARAMETERS` order, user units, each inside :data:`LIMITS`."""
    held: tuple
    """((name, value), ...) for the parameters kept fixed, user units, each inside :data:`LIMITS`."""

    def __post_init__(self):
        # (the checked floats are stored: a Box built by hand with "3" for 3 m/s failed later, in to_user)
        seen, searched, held = [], [], []
        for entry in self.searched:
            if not (isinstance(entry, tuple) and len(entry) == 3 and entry[0] in LIMITS):
                raise ParameterError(f"Box.searched entries must be (name, low, high) with a name from "
                                     f"{', '.join(PARAMETERS)}; got {entry!r} (build boxes with make_box)")
            low, high, unit = LIMITS[entry[0]]
            searched.append((entry[0], *check_interval(entry[0], entry[1:], low, high, unit=unit)))
            seen.append(entry[0])
        for entry in self.held:
            if not (isinstance(entry, tuple) and len(entry) == 2 and entry[0] in LIMITS):
                raise ParameterError(f"Box.held entries must be (name, value) with a name from "
                                     f"{', '.join(PARAMETERS)}; got {entry!r} (build boxes with make_box)")
            held.append((entry[0], _held_value(entry[0], entry[1])))
            seen.append(entry[0])
        if not self.searched or sorted(seen) != sorted(PARAMETERS):
            raise ParameterError(f"a Box must search at least one of {', '.join(PARAMETERS)} and give each exactly "
                                 f"once (searched or held); got {seen} (build boxes with make_box)")
        names = [e[0] for e in searched]
        if names != [n for n in PARAMETERS if n in names]:   # u's last axis follows this order
            raise ParameterError(f"Box.searched must list its parameters in the order {', '.join(PARAMETERS)}; "
                                 f"got {', '.join(names)} (build boxes with make_box, which orders them)")
        object.__setattr__(self, "searched", tuple(searched))
        object.__setattr__(self, "held", tuple(held))

    @property
    def names(self) -> tuple:
        """Names of the searched parameters, in the order of ``u``'s last axis."""
        return tuple(n for n, _, _ in self.searched)

    @property
    def layout(self) -> tuple:
        """``(searched names, held names)``: the box without its numbers (what a compiled search program
        depends on; :meth:`numbers` are its arguments)."""
        return self.names, tuple(n for n, _ in self.held)

    def numbers(self) -> tuple:
        """``(low (P,), high (P,), held (H,))`` host float arrays, user units: the bounds of the searched
        parameters and the held values, in :attr:`layout`'s order (see :func:`throw_in_box`)."""
        return (np.array([lo for _, lo, _ in self.searched]), np.array([hi for _, _, hi in self.searched]),
                np.array([v for _, v in self.held]))

    def to_throw(self, u) -> Throw:
        """Unconstrained ``u`` (..., P) -> a :class:`Throw` inside the box (SI), released 1 mm above the
        water (``height``) heading along +x, as every search throws (:func:`throw_in_box` of this box)."""
        self._check_columns(u)
        return throw_in_box(self.layout, u, *self.numbers())

    def _check_columns(self, u) -> None:
        """Refuse a ``u`` whose last axis is not one column per searched parameter (a shape is static, so
        this holds for traced ``u`` too): with a column short, indexing clamped and tilt reused speed's."""
        shape = tuple(np.shape(u))
        if not shape or shape[-1] != len(self.names):
            raise ParameterError(f"u must have shape (..., {len(self.names)}): one column per searched parameter "
                                 f"({', '.join(self.names)}), got shape {shape}")

    def to_user(self, u) -> dict:
        """Unconstrained ``u`` (..., P), finite -> user-unit values of the searched parameters (host floats)."""
        self._check_columns(u)
        u = np.asarray(u, dtype=float)
        if not np.all(np.isfinite(u)):   # (NaN came back as a NaN speed; from_user refuses it)
            raise ParameterError(f"u must be finite (unconstrained coordinates; ±inf is no bound either), got "
                                 f"{u[~np.isfinite(u)].flat[0]!r}")
        return {name: lo + (hi - lo) / (1.0 + np.exp(-u[..., i])) for i, (name, lo, hi) in enumerate(self.searched)}

    def _searched_values(self, values) -> dict:
        """``values`` checked: a dict giving every searched parameter and no other (a held or unknown name
        is refused, not dropped or allowed to replace the held value), each a real number or array of them
        (no strings or bools), finite and inside the box (to 1e-9 of its range); returns float arrays."""
        if not isinstance(values, Mapping):
            raise ParameterError(f"values must be a dict {{parameter: value}} of the searched parameters "
                                 f"({', '.join(self.names)}) in user units, got {type(values).__name__}")
        missing = [name for name in self.names if name not in values]
        extra = [name for name in values if name not in self.names]
        if extra:
            held = dict(self.held)
            why = [f"{n!r} is held at {held[n]:g} by the box" if n in held else f"{n!r} is not a throw parameter"
                   for n in extra]
            raise ParameterError(f"values may give only the searched parameters ({', '.join(self.names)}): "
                                 f"{'; '.join(why)}")
        if missing:
            raise ParameterError(f"values must give every searched parameter ({', '.join(self.names)}); "
                                 f"missing {', '.join(missing)}")
        out = {}
        for name, lo, hi in self.searched:
            raw = np.asarray(values[name])
            if raw.dtype.kind not in "iuf":
                raise ParameterError(f"{name} must be a real number or an array of them (user units), got "
                                     f"{values[name]!r}")
            v = raw.astype(float)
            tol = 1e-9 * (hi - lo)
            inside = (v >= lo - tol) & (v <= hi + tol)   # False for NaN
            if not np.all(inside):
                bad = float(v[~inside].flat[0]) if v.ndim else float(v)
                raise ParameterError(f"{name} must lie within the box [{lo:g}, {hi:g}] {LIMITS[name][2]}, "
                                     f"got {bad!r}")
            out[name] = v
        return out

    def from_user(self, values: dict) -> np.ndarray:
        """User-unit values of the searched parameters (inside the box) -> unconstrained ``u`` (..., P).

        A value on a bound maps to ±13.8 (the logit of 1e-6 from it); one outside the box, NaN, a string,
        a missing searched parameter, or a held or unknown one is refused (:class:`~jaxskip.ParameterError`)."""
        checked = self._searched_values(values)
        cols = []
        for name, lo, hi in self.searched:
            f = np.clip((checked[name] - lo) / (hi - lo), 1e-6, 1 - 1e-6)
            cols.append(np.log(f / (1.0 - f)))
        return np.stack(cols, axis=-1)

    def throws_from_user(self, values: dict) -> Throw:
        """Validated :class:`Throw` batch from user-unit arrays of the searched parameters (every one, inside
        the box, checked as in :meth:`from_user`), with the box's held values for the others."""
        full = {**dict(self.held), **self._searched_values(values)}
        return Throw.from_degrees(speed=full["speed"], tilt=full["tilt"], attack=full["attack"], spin=full["spin"])

    def to_dict(self) -> dict:
        """The box as a JSON-ready dict, user units (m/s, deg, rev/s): ``{"searched": {name: [low, high]},
        "held": {name: value}}``."""
        return {"searched": {n: [lo, hi] for n, lo, hi in self.searched}, "held": dict(self.held)}


def throw_in_box(layout: tuple, u, low, high, held) -> Throw:
    """Unconstrained ``u`` (..., P) -> a :class:`Throw` (SI) inside a box given by its ``layout``
    (:attr:`Box.layout`: the names of the P searched and H held parameters) and its numbers, user units
    (m/s, deg, rev/s; :meth:`Box.numbers`): ``low``, ``high`` (P,) and ``held`` (H,), which may be traced.
    Parameter i is ``low[i] + (high[i] - low[i]) * sigmoid(u[..., i])``; the throw is released 1 mm above
    the water (``height``) heading along +x, as every search throws."""
    names, held_names = layout
    dtype = jnp.result_type(float)
    u = jnp.asarray(u)   # (a list met a raw TypeError at u[..., i], an integer array one in the sigmoid)
    if not jnp.issubdtype(u.dtype, jnp.floating):
        u = u.astype(dtype)
    low, high, held = (jnp.asarray(a, dtype=dtype) for a in (low, high, held))
    values = {name: held[j] for j, name in enumerate(held_names)}
    for i, name in enumerate(names):
        values[name] = low[i] + (high[i] - low[i]) * jax.nn.sigmoid(u[..., i])
    shape = jnp.shape(u)[:-1]
    full = {k: jnp.broadcast_to(jnp.asarray(v, dtype=dtype), shape) for k, v in values.items()}
    return Throw(speed=full["speed"], tilt=jnp.deg2rad(full["tilt"]), attack=jnp.deg2rad(full["attack"]),
                 spin=2.0 * jnp.pi * full["spin"], height=jnp.full(shape, 0.001), heading=jnp.zeros(shape))


def make_box(searched=None, held=None) -> Box:
    """Validate a search box, in user units: speed [m/s], tilt and attack [deg], spin [rev/s].

    ``searched``: {name: (low, high)} with low < high (default :data:`HUMAN_BOX`: speed 3-12 m/s, tilt
    5-45 deg, attack 0-30 deg, spin 0-20 rev/s, less the parameters ``held`` gives: ``make_box(held={"tilt":
    20.0})`` is the human box with the tilt held); ``held``: {name: value} for the others (defaults: speed
    8 m/s, tilt 20 deg, attack 5 deg, spin 20 rev/s). A name is one of :data:`PARAMETERS`, searched or
    held, not both; at least one is searched. Every bound and value lies within :data:`LIMITS`:

    ======  ===============  =====
    name    range            unit
    ======  ===============  =====
    speed   [0.1, 50]        m/s
    tilt    [-89, 89]        deg
    attack  [0, 89]          deg
    spin    [0, 200]         rev/s
    ======  ===============  =====

    Returns a :class:`Box`; anything else is refused with :class:`~jaxskip.ParameterError`.

    >>> make_box({"speed": (3.0, 12.0)}, {"tilt": 20.0}).searched
    (('speed', 3.0, 12.0),)
    """
    for label, value in (("searched", searched), ("held", held)):
        if value is not None and not isinstance(value, Mapping):
            raise ParameterError(f"{label} must be a dict ({'{name: (low, high)}' if label == 'searched' else '{name: value}'}"
                                 f" in user units), got {type(value).__name__}")
    held = dict(held or {})
    searched = ({k: v for k, v in HUMAN_BOX.items() if k not in held} if searched is None else dict(searched))
    for name in list(searched) + list(held):
        if name not in LIMITS:
            raise ParameterError(f"unknown throw parameter {name!r}; choose from {', '.join(PARAMETERS)}")
    both = set(searched) & set(held)
    if both:
        raise ParameterError(f"parameters both searched and held: {sorted(both)}")
    if not searched:
        raise ParameterError("a search needs at least one searched parameter")
    defaults = {"speed": 8.0, "tilt": 20.0, "attack": 5.0, "spin": 20.0}
    out_s, out_h = [], []
    for name in PARAMETERS:
        low, high, unit = LIMITS[name]
        if name in searched:
            lo, hi = check_interval(name, searched[name], low, high, unit=unit)
            out_s.append((name, lo, hi))
        else:
            out_h.append((name, _held_value(name, held.get(name, defaults[name]))))
    return Box(tuple(out_s), tuple(out_h))


def _held_value(name: str, value) -> float:
    """A held parameter's value, checked against :data:`LIMITS` (user units)."""
    low, high, unit = LIMITS[name]
    v = check_real(name, value)
    if not low <= v <= high:
        raise ParameterError(f"{name} must lie within [{low:g}, {high:g}] {unit}, got {v:g}")
    return v
