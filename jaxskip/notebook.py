"""Shared set-up of the notebooks in ``notebooks/`` (quick/full mode, figure folder, float64).

Two environment variables steer a notebook: ``JAXSKIP_QUICK`` (``1``/``true``/``yes``: quick mode, small
batches for CI; ``0``/``false``/``no`` or unset/empty: full mode; case-insensitive, anything else is
refused) and ``JAXSKIP_NOTEBOOK_OUT`` (the folder for figures; made if missing, and checked to be
writable before any computation starts).

>>> run = notebook_mode("example", default_out="/tmp/jaxskip-figures")
>>> run.figure("x.png").endswith("x.png")
True
"""

from __future__ import annotations

import dataclasses
import os
import tempfile
import time

from ._docs import document_fields


@document_fields
@dataclasses.dataclass(frozen=True)
class NotebookRun:
    """How a notebook runs: ``quick`` (``JAXSKIP_QUICK=1``, for CI) or full, where figures go."""

    name: str
    """The notebook's name, as given to :func:`notebook_mode` (e.g. ``"magic_angle"``, the file's stem)."""
    quick: bool
    """True in quick mode (small batches, few points)."""
    out: str
    """Folder for figures (``JAXSKIP_NOTEBOOK_OUT``, default ``notebooks/figures``)."""
    started: float
    """``time.perf_counter()`` at set-up [s]."""

    def figure(self, filename: str) -> str:
        """Path of a figure in :attr:`out`."""
        return os.path.join(self.out, filename)

    def done(self, path: str) -> None:
        """Print the figure's path, the elapsed time and the mode."""
        print(f"figure: {path}; {time.perf_counter() - self.started:.0f} s ({'quick' if self.quick else 'full'} mode)")


QUICK_VALUES = {"1": True, "true": True, "yes": True, "0": False, "false": False, "no": False, "": False}
"""The values ``JAXSKIP_QUICK`` may take (after stripping and lower-casing) and the mode each means."""


def quick_from_env(environ=None) -> bool:
    """Quick mode from ``JAXSKIP_QUICK`` (of ``environ``, default ``os.environ``): see :data:`QUICK_VALUES`.

    Raises ``ValueError`` naming the variable for any other value (``"true"`` once ran full silently)."""
    raw = (os.environ if environ is None else environ).get("JAXSKIP_QUICK", "")
    try:
        return QUICK_VALUES[raw.strip().lower()]
    except KeyError:
        raise ValueError(f"JAXSKIP_QUICK={raw!r} is not understood: use 1, true or yes for quick mode, 0, false, no "
                         "or leave it unset for full mode") from None


def writable_folder(out: str) -> str:
    """Make the figure folder ``out`` (if missing) and check that a file can be written in it, by creating and
    removing a temporary file; raises ``OSError`` naming ``JAXSKIP_NOTEBOOK_OUT`` if not (at set-up, not at
    the ``savefig`` after the whole computation). Returns ``out``."""
    try:
        os.makedirs(out, exist_ok=True)
        fd, probe = tempfile.mkstemp(prefix=".jaxskip-write-check-", dir=out)
        os.close(fd)
        os.remove(probe)
    except OSError as e:
        raise OSError(e.errno, f"the figure folder {out!r} cannot be written ({e.strerror or e}); set "
                               "JAXSKIP_NOTEBOOK_OUT to a folder you can write") from e
    return out


def notebook_mode(name: str, default_out: str | None = None, here: str | None = None) -> NotebookRun:
    """Read the mode from the environment, make and check the figure folder, switch on float64 and, run
    as a script, a file backend (in a Jupyter kernel the inline backend stays, so figures show).

    Quick mode: ``JAXSKIP_QUICK`` (:func:`quick_from_env`; a value it does not know raises ``ValueError``).
    Figures go to ``JAXSKIP_NOTEBOOK_OUT``, else ``default_out``, else ``figures/`` beside ``here`` (the
    notebook's file: pass ``globals().get("__file__")``, which a Jupyter kernel does not define), else
    ``figures/`` in the working folder (a kernel's is the notebook's folder); a folder that cannot be
    written raises ``OSError`` here (:func:`writable_folder`). Both checks run before anything else."""
    import sys

    quick = quick_from_env()
    if default_out is None:
        default_out = os.path.join(os.path.dirname(os.path.abspath(here)) if here else os.getcwd(), "figures")
    out = writable_folder(os.environ.get("JAXSKIP_NOTEBOOK_OUT") or default_out)

    import jax
    import matplotlib

    if "ipykernel" not in sys.modules:
        matplotlib.use("Agg")
    jax.config.update("jax_enable_x64", True)
    return NotebookRun(name, quick, out, time.perf_counter())
