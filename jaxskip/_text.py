"""Small wording helpers shared by the CLI, the pictures and the results' reprs."""

from __future__ import annotations


def plural(n: int, word: str) -> str:
    """``n`` and ``word``, with an ``s`` unless ``n`` is 1: ``1 bounce``, ``0 bounces``, ``14 bounces``.

    >>> plural(1, "bounce"), plural(14, "bounce")
    ('1 bounce', '14 bounces')
    """
    return f"{n} {word}{'' if n == 1 else 's'}"


def duration_words(seconds: float) -> str:
    """A duration [s] as a person reads it: ``42 s``, ``3.5 min``, ``2.1 h``.

    >>> duration_words(42.4), duration_words(210.0), duration_words(7560.0)
    ('42 s', '3.5 min', '2.1 h')
    """
    if seconds < 90.0:
        return f"{seconds:.0f} s"
    if seconds < 5400.0:
        return f"{seconds / 60.0:.1f} min"
    return f"{seconds / 3600.0:.1f} h"
