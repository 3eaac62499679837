"""Small wording helpers shared by the CLI, the pictures and the results' reprs."""

from __future__ import annotations


def plural(n: int, word: str) -> str:
    """``n`` and ``word``, with an ``s`` unless ``n`` is 1: ``1 bounce``, ``0 bounces``, ``14 bounces``.

    >>> plural(1, "bounce"), plural(14, "bounce")
    ('1 bounce', '14 bounces')
    """
    return f"{n} {word}{'' if n == 1 else 's'}"
