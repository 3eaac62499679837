"""One progress line on stderr, for the library's long loops (``progress=True``).

On a terminal, and in a Jupyter notebook (whose output area honours a carriage return), the line is
rewritten in place with ``"\\r"``. Anywhere else — stderr redirected to a log file or a pipe — a
rewritten line would pile up as one ever longer line, so each update is written as a line of its
own instead, at most one every :data:`LOG_INTERVAL` seconds (the last one always).

Example::

    line = ProgressLine()
    for i in range(n):
        ...
        line.update(f"  {i + 1}/{n} done")
    line.close()
"""

from __future__ import annotations

import sys
import time

#: Seconds between two progress lines written to a file or a pipe (a terminal gets every update).
LOG_INTERVAL = 5.0


def rewrites_in_place(stream) -> bool:
    """True where ``stream`` shows a carriage return as a rewrite: a terminal or a Jupyter kernel's stream."""
    try:
        if stream.isatty():
            return True
    except (AttributeError, ValueError):  # no isatty, or a closed file
        return False
    return type(stream).__module__.split(".")[0] == "ipykernel"


class ProgressLine:
    """The progress line of one loop: :meth:`update` it with the whole text each time, :meth:`close` it
    at the end (ends the line; off a terminal, writes the last text if throttling held it back)."""

    def __init__(self, stream=None):
        self._stream = sys.stderr if stream is None else stream
        self._in_place = rewrites_in_place(self._stream)
        self._written = -float("inf")  # time of the last line written off a terminal
        self._held = None  # the latest text not yet written (off a terminal)
        self._open = False  # in place: a line without its newline yet

    def update(self, text: str) -> None:
        """Show ``text`` as the current progress."""
        if self._in_place:
            print("\r" + text, end="", file=self._stream, flush=True)
            self._open = True
            return
        now = time.monotonic()
        if now - self._written >= LOG_INTERVAL:
            print(text, file=self._stream, flush=True)
            self._written, self._held = now, None
        else:
            self._held = text

    def close(self) -> None:
        """End the progress line (a newline on a terminal; the held-back last update elsewhere)."""
        if self._open:
            print(file=self._stream, flush=True)
            self._open = False
        elif self._held is not None:
            print(self._held, file=self._stream, flush=True)
            self._held = None
