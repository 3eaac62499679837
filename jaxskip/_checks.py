"""Input validation run on concrete Python values *before* any JAX tracing.

Every public entry point calls these, so a bad value is reported with the
parameter's name, its unit and the valid range instead of surfacing later as a
NaN or as an XLA error.
"""

from __future__ import annotations

import decimal
import math
import numbers


#: NumPy dtype kinds that are not real numbers (bool, complex, bytes, text, timedelta, datetime): refused
#: by :func:`_as_float` and :func:`check_array` (an object array is looked at element by element).
NON_REAL_KINDS = "bcSUmM"


class ParameterError(ValueError):
    """A parameter is invalid: outside its valid range, not one of its choices, or of the wrong type or shape
    (e.g. a string for a number, a batch of throws where one is expected); the message names it. A
    :class:`ValueError`, so ``except ValueError`` catches it too."""


def _as_float(name: str, value, valid: str = "") -> float:
    """``value`` as a finite float; ``valid`` (e.g. "in [0, 1] s") completes the messages.

    Refused: strings (``"0.02"``: ``float()`` would read them, and a config would then hold a
    string), bools (``True`` is not 1 s), complex numbers and anything ``float()`` cannot read;
    accepted: Python and NumPy real numbers, 0-d arrays and concrete JAX scalars.
    """
    import numpy as np

    if isinstance(value, (str, bytes, bool, np.bool_)) or getattr(getattr(value, "dtype", None), "kind", "f") in NON_REAL_KINDS + "O":
        raise ParameterError(f"{name} must be a real number{(' ' + valid) if valid else ''}, got {value!r}")
    import jax

    if isinstance(value, jax.core.Tracer):  # (float() of it raised a TypeError read as "not a real number")
        raise ParameterError(f"{name} is a traced value (inside jit, vmap or grad), and this checked constructor "
                             "needs a concrete number: trace a pytree's field instead (e.g. dataclasses.replace("
                             "water, c_lift=x) of a checked WaterParams, dataclasses.replace(stone, mass=m) of a "
                             "rigid_stone (its fields are independent leaves: a density scales mass and inertia "
                             "together, see help(RigidStone)), or a Throw(...) built directly); settings such as "
                             "SimConfig's and WaterGrid's (the water's spacing, depth, damping, time step: they fix "
                             "the compiled program) are static and cannot be traced or differentiated: vary them in "
                             "Python, each value compiling its own program")
    try:
        value = float(value)  # numpy scalars, 0-d arrays; an int beyond the float range overflows
    except OverflowError:
        raise ParameterError(f"{name} must be finite{(' and ' + valid) if valid else ''}, got a number beyond "
                             "the floating-point range") from None
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a real number{(' ' + valid) if valid else ''}, "
                             f"got {value!r}") from None
    if not math.isfinite(value):
        raise ParameterError(f"{name} must be finite{(' and ' + valid) if valid else ''}, got {value!r}")
    return value


def check_real(name: str, value, *, unit: str = "", valid: str = "") -> float:
    """Return ``value`` as a finite float or raise :class:`ParameterError`; ``valid`` (e.g. "> 0 kg") completes
    the message (the caller checks that range itself)."""
    return _as_float(name, value, valid)


def check_positive(name: str, value, *, unit: str = "") -> float:
    """Return ``value`` as a finite float > 0 or raise :class:`ParameterError`."""
    valid = f"> 0{(' ' + unit) if unit else ''}"
    v = _as_float(name, value, valid)
    if v <= 0.0:
        raise ParameterError(f"{name} must be {valid}, got {v!r}")
    return v


def check_range(
    name: str,
    value,
    low: float,
    high: float,
    *,
    unit: str = "",
    low_open: bool = False,
    high_open: bool = False,
) -> float:
    """Return ``value`` as a finite float inside ``[low, high]`` (ends optionally open)."""
    valid = f"in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}{(' ' + unit) if unit else ''}"
    v = _as_float(name, value, valid)
    too_low = v <= low if low_open else v < low
    too_high = v >= high if high_open else v > high
    if too_low or too_high:
        raise ParameterError(f"{name} must be {valid}, got {v!r}")
    return v


def check_int(name: str, value, *, minimum: int = 1, maximum: int | None = None) -> int:
    """Return ``value`` as an int in ``[minimum, maximum]`` or raise :class:`ParameterError`."""
    valid = f">= {minimum}" if maximum is None else f"in [{minimum}, {maximum}]"
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise ParameterError(f"{name} must be an integer {valid}, got {value!r}")
    v = int(value)
    if v < minimum or (maximum is not None and v > maximum):
        raise ParameterError(f"{name} must be an integer {valid}, got {v}")
    return v


def check_bool(name: str, value) -> bool:
    """Return ``value`` if it is a bool (``True``/``False``, NumPy's too) or raise :class:`ParameterError`
    (a string such as ``"False"`` would otherwise count as true)."""
    import numpy as np

    if not isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"{name} must be True or False, got {value!r}")
    return bool(value)


def check_choice(name: str, value, choices) -> str:
    """Return ``value`` if it is one of ``choices`` (a ``str``) or raise :class:`ParameterError`.

    Only a ``str`` is a choice: a 0-d NumPy string array compares equal elementwise and passed the
    membership test, then made its config unhashable (a TypeError at the first jit)."""
    if not isinstance(value, str) or value not in choices:
        raise ParameterError(f"{name} must be one of {', '.join(map(repr, choices))}; got {value!r}")
    return value


def check_array(name: str, value, low: float, high: float, *, unit: str = "", low_open: bool = False,
                high_open: bool = False, hint: str = ""):
    """Validate a scalar or array elementwise (finite, inside the range); return a float64 NumPy array.

    Used for batched throws: every element is checked on concrete values before tracing, and
    the message names the parameter, the valid range and the first offending value.
    """
    import numpy as np

    import jax

    if isinstance(value, jax.core.Tracer):
        raise ParameterError(f"{name} is a traced value: Throw.create / Throw.from_degrees check concrete values "
                             "before tracing; inside jit, vmap or grad build the throw from a checked one, e.g. "
                             "dataclasses.replace(Throw.from_degrees(), speed=v, tilt=theta) (SI: m/s, rad, rad/s), "
                             "or with Throw(speed, tilt, attack, spin, height, heading) directly")
    valid = f"finite and in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}{(' ' + unit) if unit else ''}"
    try:
        raw = np.asarray(value)
        # Real numbers of any type (ints, floats, bfloat16, Decimal, Fraction); not bools, complex numbers,
        # None or strings, which NumPy would turn into numbers (or NaN) without a word.
        if raw.dtype.kind in NON_REAL_KINDS or (raw.dtype.kind == "O" and not all(
                isinstance(v, (numbers.Real, decimal.Decimal)) and not isinstance(v, bool) for v in raw.flat)):
            raise TypeError
        arr = np.asarray(raw, dtype=np.float64)
    except OverflowError:
        raise ParameterError(f"{name} must be {valid}, got a number beyond the floating-point range") from None
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a real number or array of them, got {value!r}") from None
    nonfinite = ~np.isfinite(arr)
    with np.errstate(invalid="ignore"):
        bad = nonfinite | (arr <= low if low_open else arr < low) | (arr >= high if high_open else arr > high)
    if bad.any():
        # the first non-finite element, else the first out of range; which one, and how many are bad ("got nan"
        # alone left a user to search 10^5 throws for it; a review, stop 46)
        first = np.argwhere(nonfinite if nonfinite.any() else bad)[0]
        index = int(first[0]) if arr.ndim == 1 else tuple(int(i) for i in first)
        where = "" if arr.size == 1 else f" at index {index} ({int(bad.sum())} of {arr.size} elements bad)"
        raise ParameterError(f"{name} must be {valid}, got {float(arr[tuple(first)])!r}{where}"
                             + (f" ({hint})" if hint and not nonfinite.any() else ""))
    return arr
