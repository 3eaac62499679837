# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---

# %% [markdown]
# # Explore a throw with sliders
#
# In Jupyter with `ipywidgets` installed (`pip install ipywidgets`), the cell below shows sliders
# for speed, tilt, attack and spin that redraw the side view (the simulator is compiled once;
# each redraw is a few milliseconds of simulation). Run as a script, or without ipywidgets, it
# draws a few throws instead.
#
# `python notebooks/explore.py` or `JAXSKIP_QUICK=1 python notebooks/explore.py`; figures go to
# `JAXSKIP_NOTEBOOK_OUT` (default `notebooks/figures/`). Run time on the 2-core development machine
# (2026-12-07): full ~5 s, quick ~5 s (wall time; load moves it).

# %%
import matplotlib.pyplot as plt

from jaxskip.notebook import notebook_mode

RUN = notebook_mode("explore", here=globals().get("__file__"))  # no __file__ in a Jupyter kernel

from jaxskip import Throw, simulate  # noqa: E402
from jaxskip.plotting import plot_throw  # noqa: E402


def show(speed=8.0, tilt=20.0, attack=5.0, spin=20.0, ax=None):
    """Simulate one throw (user units: m/s, deg, deg, rev/s) and draw its side and top views."""
    result = simulate(Throw.from_degrees(speed=speed, tilt=tilt, attack=attack, spin=spin))
    if ax is None:
        fig = plot_throw(result)
        plt.show()
        return fig
    return plot_throw(result, ax=ax)


def in_notebook() -> bool:
    try:
        from IPython import get_ipython
    except ImportError:
        return False
    return get_ipython() is not None and "IPKernelApp" in get_ipython().config


# %%
if in_notebook():
    try:
        from ipywidgets import FloatSlider, fixed, interact
    except ImportError:
        print("pip install ipywidgets for sliders; drawing the default throw instead")
        show()
    else:
        interact(show, speed=FloatSlider(value=8.0, min=1.0, max=15.0, step=0.5, description="speed [m/s]"),
                 tilt=FloatSlider(value=20.0, min=0.0, max=60.0, step=1.0, description="tilt [deg]"),
                 attack=FloatSlider(value=5.0, min=0.0, max=40.0, step=1.0, description="attack [deg]"),
                 spin=FloatSlider(value=20.0, min=0.0, max=40.0, step=1.0, description="spin [rev/s]"),
                 ax=fixed(None))  # (interact makes a widget of every argument it is not told to hold)
else:
    presets = [dict(speed=8.0, tilt=20.0, attack=5.0, spin=20.0), dict(speed=8.0, tilt=20.0, attack=5.0, spin=0.0),
               dict(speed=8.0, tilt=50.0, attack=5.0, spin=20.0), dict(speed=4.0, tilt=10.0, attack=15.0, spin=20.0)]
    fig = plt.figure(figsize=(16, 8))
    grid = fig.add_gridspec(4, 2, height_ratios=[2.2, 1, 2.2, 1])
    for i, p in enumerate(presets):
        r, c = 2 * (i // 2), i % 2
        show(**p, ax=(fig.add_subplot(grid[r, c]), fig.add_subplot(grid[r + 1, c])))
    for ax in fig.axes:
        ax.title.set_fontsize(8)
    fig.tight_layout()
    path = RUN.figure("explore.png")
    fig.savefig(path, dpi=100)
    RUN.done(path)
