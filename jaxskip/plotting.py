"""Pictures of a throw: the side view of the paper's Fig. 6 plus a top view."""

from __future__ import annotations

import math

import numpy as np


def plot_throw(result, path=None, *, ax=None):
    """Draw a :class:`jaxskip.api.ThrowResult`: side view (trajectory, water line, contacts) and top view.

    Parameters
    ----------
    result : the throw to draw.
    path : if given, save the figure there (PNG, PDF, SVG by extension) and close it.
    ax : optional pair of matplotlib axes (side, top) to draw into.

    Returns
    -------
    The matplotlib figure.
    """
    import matplotlib

    if path is not None and ax is None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    traj = result.trajectory
    pos = np.asarray(traj["position"])
    wet = np.asarray(traj["wetted_area"]) > 0
    if ax is None:
        fig, (side, top) = plt.subplots(2, 1, figsize=(10, 5.2), height_ratios=[2.2, 1], sharex=True)
    else:
        side, top = ax
        fig = side.figure
    x, y, z = pos[:, 0], pos[:, 1], pos[:, 2]

    side.axhline(0.0, color="#2f6fb0", lw=1.2, label="water surface")
    side.fill_between([min(x.min(), 0) - 0.2, x.max() + 0.5], -0.05, 0.0, color="#cfe3f5", zorder=0)
    side.plot(x, z * 100, color="0.2", lw=1.0, label="centre of mass")
    if wet.any():
        side.plot(np.where(wet, x, np.nan), np.where(wet, z * 100, np.nan), color="#d1495b", lw=2.5, label="in contact")
    for i, c in enumerate(result.contacts):
        side.annotate(str(i + 1), (c.x, 0.0), textcoords="offset points", xytext=(0, -11), ha="center",
                      fontsize=7, color="#d1495b")
    side.set_ylabel("height [cm]")
    side.set_ylim(min(-2.0, z.min() * 100 - 0.5), max(z.max() * 100 * 1.15, 2.0))
    th = result.throw
    side.set_title(
        f"{result.stone_name} stone, {result.mass * 1e3:.0f} g: "
        f"{float(th.speed):.1f} m/s, tilt {math.degrees(float(th.tilt)):.0f}°, "
        f"attack {math.degrees(float(th.attack)):.0f}°, spin {float(th.spin) / (2 * math.pi):.0f} rev/s"
        f"  →  {result.bounces} bounces, {result.distance:.1f} m, {result.outcome.replace('_', ' ')}",
        fontsize=10,
    )
    side.legend(loc="upper right", fontsize=8, frameon=False)

    top.plot(x, y * 100, color="0.2", lw=1.0)
    if wet.any():
        top.plot(np.where(wet, x, np.nan), np.where(wet, y * 100, np.nan), color="#d1495b", lw=2.5)
    top.set_ylabel("sideways [cm]")
    top.set_xlabel("downrange x [m]")
    top.set_xlim(min(x.min(), 0) - 0.2, x.max() + 0.5)
    fig.tight_layout()
    if path is not None:
        fig.savefig(path, dpi=130)
        plt.close(fig)
    return fig
