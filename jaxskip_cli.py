"""Entry point of the ``jaxskip`` command (``pyproject.toml``'s ``[project.scripts]``).

It lives outside the ``jaxskip`` package on purpose: importing anything in the package first runs
``jaxskip/__init__.py``, which loads JAX (2-3 s). A Ctrl-C in that time raised a KeyboardInterrupt that
XLA's garbage-collection callback swallowed ("Exception ignored in ... _xla_gc_callback"), and the
command then ran to its end. Here Ctrl-C is caught before anything is imported: one line, exit 130.
:func:`jaxskip.cli.main` then installs its own handler (which also says what a sweep keeps).
"""

import os
import signal
import sys
import threading

#: Exit status after Ctrl-C (SIGINT): 128 + 2, as a shell reports a command it interrupted.
EXIT_INTERRUPTED = 130


def _interrupted(signum, frame) -> None:
    sys.stderr.write("jaxskip: interrupted\n")
    sys.stderr.flush()
    os._exit(EXIT_INTERRUPTED)  # (not an exception: one raised inside an import can be swallowed, as above)


def _open_closed_streams() -> None:
    """Give a standard stream the caller closed (``2>&-``, a daemon's) the null device, descriptor and all.

    Python sets ``sys.stderr`` to None then: the command crashed in a raw traceback, or, with ``print(...,
    file=None)`` writing to stdout, put its warnings before ``--json``'s object. And a file opened later (a
    picture) would take the free descriptor 2, where the compiler's own messages go."""
    for fd, name, mode in ((0, "stdin", "r"), (1, "stdout", "w"), (2, "stderr", "w")):
        try:
            os.fstat(fd)
        except OSError:
            got = os.open(os.devnull, os.O_RDWR)   # (the lowest free descriptor: this one, unless a lower one is)
            if got != fd:
                os.dup2(got, fd)
                os.close(got)
        if getattr(sys, name) is None:
            setattr(sys, name, open(fd, mode, closefd=False))


def main() -> int:
    """Install the Ctrl-C handler, then run :func:`jaxskip.cli.main` (argument parsing and the commands)."""
    _open_closed_streams()
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, _interrupted)
    from jaxskip.cli import main as run

    return run()


if __name__ == "__main__":
    raise SystemExit(main())
