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


def main() -> int:
    """Install the Ctrl-C handler, then run :func:`jaxskip.cli.main` (argument parsing and the commands)."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, _interrupted)
    from jaxskip.cli import main as run

    return run()


if __name__ == "__main__":
    raise SystemExit(main())
