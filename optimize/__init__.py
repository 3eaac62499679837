"""Throw search and magic-angle sweeps for jaxskip (installed with it: ``import optimize``).

* :mod:`optimize.bounds` — search boxes (user units at the edge, SI inside), reparameterisation.
* :mod:`optimize.objectives` — the smooth bounce count and the distance, differentiable.
* :mod:`optimize.search` — optax gradient search (with an optional local polish), randomised-smoothing,
  grid and random baselines.
* :mod:`optimize.sweep` — bounce domain and U_min(tilt) sweeps: chunked, resumable, sharded.
"""

from .bounds import HUMAN_BOX, Box, check_interval, make_box
from .objectives import distance, make_objective, soft_bounce_count
from .search import (EXPLODING, VANISHING, SearchResult, gradient_health, gradient_search, grid_search, local_search, perturbation_search, plot_search,
                     random_search, top_throws)
from .sweep import SweepSpec, make_spec, merge, parabola_minimum, plot_sweep, run_sweep

__all__ = ["EXPLODING", "HUMAN_BOX", "VANISHING", "Box", "SearchResult", "SweepSpec", "check_interval", "distance", "gradient_health",
           "gradient_search",
           "grid_search", "local_search", "make_box", "make_objective", "make_spec", "merge", "parabola_minimum",
           "perturbation_search", "plot_search", "plot_sweep", "random_search", "run_sweep", "soft_bounce_count", "top_throws"]
