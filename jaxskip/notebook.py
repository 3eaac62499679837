"""Shared set-up of the notebooks in ``notebooks/`` (quick/full mode, figure folder, float64).

>>> run = notebook_mode("example", default_out="/tmp/jaxskip-figures")
>>> run.figure("x.png").endswith("x.png")
True
"""

from __future__ import annotations

import dataclasses
import os
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


def notebook_mode(name: str, default_out: str | None = None, here: str | None = None) -> NotebookRun:
    """Read the mode from the environment, make the figure folder, switch on float64 and, run as a script,
    a file backend (in a Jupyter kernel the inline backend stays, so figures show).

    Figures go to ``JAXSKIP_NOTEBOOK_OUT``, else ``default_out``, else ``figures/`` beside ``here`` (the
    notebook's file: pass ``globals().get("__file__")``, which a Jupyter kernel does not define), else
    ``figures/`` in the working folder (a kernel's is the notebook's folder)."""
    import sys

    import jax
    import matplotlib

    if "ipykernel" not in sys.modules:
        matplotlib.use("Agg")
    jax.config.update("jax_enable_x64", True)
    if default_out is None:
        default_out = os.path.join(os.path.dirname(os.path.abspath(here)) if here else os.getcwd(), "figures")
    out = os.environ.get("JAXSKIP_NOTEBOOK_OUT", default_out)
    os.makedirs(out, exist_ok=True)
    return NotebookRun(name, os.environ.get("JAXSKIP_QUICK") == "1", out, time.perf_counter())
