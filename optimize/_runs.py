"""Warnings of a whole search or sweep, issued once per run rather than once per batch.

A search or sweep runs many :func:`jaxskip.simulate_batch` calls. Each call checks the contact step
against the stone's stability estimate at *its* fastest throw and reports *its* diverged throws with
indices into *its* batch, so a 10-step bisection printed up to 12 stability warnings with 12 different
speeds, and a diverged throw's indices pointed into a batch the user never saw. Here the run checks the
step once, at the fastest throw it can make (:func:`warn_stability`), its batches run with both
warnings silenced (:func:`silenced_batches`), and the run reports its diverged throws once, counted over the
run (:func:`warn_diverged`).
"""

from __future__ import annotations

import contextlib
import os
import sys
import warnings

import numpy as np

import jaxskip
from jaxskip import simulate_batch
from jaxskip.simulate import (DIVERGED, AccuracyWarning, DivergedWarning, StabilityWarning, diverged_message,
                              warn_if_unstable)

#: Release height [m] of every throw of the searches and sweeps (``Throw.from_degrees``' default).
RELEASE_HEIGHT = 0.001
#: The folders of the two packages: a run's warnings name the first frame outside them (:func:`caller_level`).
_LIBRARY = tuple(os.path.dirname(os.path.abspath(f)) + os.sep for f in (jaxskip.__file__, __file__))


def caller_level() -> int:
    """The ``stacklevel`` that attributes a warning issued by the function calling this one to the first frame
    outside jaxskip and optimize: the user's call, however deep the run's helpers (a search's warnings named the
    search's own lines, or its settings-recording wrapper's). Use ``warnings.warn(..., stacklevel=caller_level())``
    there; a helper that warns one frame further down takes one more."""
    frame, level = sys._getframe(1), 1
    while frame is not None and os.path.abspath(frame.f_code.co_filename).startswith(_LIBRARY):
        frame, level = frame.f_back, level + 1
    return level


@contextlib.contextmanager
def silenced_batches(coarse: bool = False):
    """Silence :class:`~jaxskip.StabilityWarning`, :class:`~jaxskip.DivergedWarning` and the inert-velocity warning
    (:func:`jaxskip.simulate.inert_velocity_message`) for a run's batches
    (the run issues them once); with ``coarse`` every :class:`~jaxskip.AccuracyWarning`, the coarse-``dt``
    one included (for a caller that has issued it already). Each ``catch_warnings`` clears Python's memory
    of "once" warnings: entered per batch without ``coarse``, the coarse-``dt`` warning came again after
    every batch."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning if coarse else StabilityWarning)
        warnings.simplefilter("ignore", DivergedWarning)
        # (an inert velocity option is said once, by the search's or the sweep spec's check of the config)
        warnings.filterwarnings("ignore", message=r"velocity='\w+' has no effect with attitude='fixed'")
        yield


def batch(throws, stone, *, water, config, lanes=None, progress=False):
    """:func:`jaxskip.simulate_batch`'s :class:`~jaxskip.BatchResult` and the (N,) bool mask of the throws
    that diverged (call it inside :func:`silenced_batches`)."""
    r = simulate_batch(throws, stone, water=water, config=config, lanes=lanes, progress=progress)
    return r, np.asarray(r.outcome) == DIVERGED


def warn_stability(config, stone, water, fastest: float, stacklevel: int = 3) -> None:
    """One :class:`~jaxskip.StabilityWarning` for the run if ``config.dt`` exceeds the stone's contact-step
    estimate at the run's fastest throw, ``fastest`` [m/s] released :data:`RELEASE_HEIGHT` above the water."""
    warn_if_unstable(config, stone, water, np.array([float(fastest)]), np.array([RELEASE_HEIGHT]),
                     stacklevel=stacklevel + 1)


def warn_diverged(diverged: int, total: int, what: str, treatment: str, config, stacklevel: int = 3) -> None:
    """One :class:`~jaxskip.DivergedWarning` for the run if ``diverged`` of its ``total`` exact throws
    diverged; ``what`` names the run, ``treatment`` says what it did with them."""
    if diverged:
        warnings.warn(diverged_message(f"{diverged} of the {total} throws of this {what} diverged; {treatment}",
                                       config), DivergedWarning, stacklevel=stacklevel + 1)
