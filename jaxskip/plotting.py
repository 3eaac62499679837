"""Pictures of a throw: the side view of the paper's Fig. 6 plus a top view."""

from __future__ import annotations

import math
import os

import numpy as np

from ._files import check_file_path, check_picture_path, writing
from ._text import plural


def _number_contacts(side, xs, xlim, fontsize: float = 7.0, rows: int = 3, last_note: str = "") -> None:
    """Number the contacts under the water line at downrange positions ``xs`` [m].

    Dense contacts (a stone chattering at the end of a throw) are numbered in up to ``rows``
    staggered rows so that no two numbers overlap. When not every number fits, every 5th is
    numbered (then every 10th, 20th, ...) with the first and the last, so that a gap in the
    numbering is a rule a reader sees, not a silent omission (``rows`` >= 2: the first and the last
    always fit). ``last_note``: added to the last number in brackets (e.g. "sank": the contact the
    stone ended in, which the bounce count does not count)."""
    width_pt = side.bbox.width * 72.0 / side.figure.dpi
    per_m = width_pt / (xlim[1] - xlim[0])             # points per metre along the axis
    char = 0.62 * fontsize                              # a digit's advance [pt], with a little air
    n = len(xs)
    for every in (1, 5, 10, 20, 50, 100, 200, 500, 1000, max(n, 1)):   # the last: first and last only
        wanted = [i for i in range(n) if i in (0, n - 1) or (i + 1) % every == 0]
        placed = [[] for _ in range(rows)]              # per row: (left, right, label, x) [pt, pt, str, m]
        fits = True
        for i in wanted:
            label = f"{i + 1} ({last_note})" if last_note and i == n - 1 else str(i + 1)
            half = 0.5 * len(label) * (char if label.isdigit() else 0.9 * char) + 1.0
            centre = (xs[i] - xlim[0]) * per_m
            free = [r for r in range(rows) if not placed[r] or centre - half >= placed[r][-1][1]]
            if not free:
                fits = False
                break
            placed[free[0]].append((centre - half, centre + half, label, xs[i]))
        if fits:
            break
    for row, items in enumerate(placed):
        for _, _, label, xc in items:
            side.annotate(label, (xc, 0.0), textcoords="offset points", xytext=(0, -11 - 8 * row), ha="center",
                          fontsize=fontsize, color="#d1495b")


def _one_row_legend(side) -> None:
    """The side view's legend: one row under the water line, below the contact numbers, made compact where it
    would run past the axes (a narrow panel of a grid, ``plot_throw(ax=...)``: "in contact (numbered)" ran ~90 px
    past the right edge; a review)."""
    legend = side.legend(loc="lower left", ncol=3, fontsize=8, frameon=False)
    try:
        renderer = side.figure.canvas.get_renderer()
        too_wide = legend.get_window_extent(renderer).width > side.get_window_extent(renderer).width
    except AttributeError:      # (a canvas without a renderer to measure with: the plain legend)
        return
    if too_wide:
        side.legend(loc="lower left", ncol=3, fontsize=7, frameon=False, handlelength=1.2, columnspacing=0.8,
                    handletextpad=0.4, borderaxespad=0.2)


def plot_throw(result, path=None, *, ax=None):
    """Draw a :class:`jaxskip.api.ThrowResult`: side view (trajectory, water line, contacts) and top view.

    Parameters
    ----------
    result : the throw to draw.
    path : if given, save the figure there and close it; its suffix picks the format (any matplotlib
        writes: .png, .pdf, .svg, .jpg, ...; a path without one is refused).
    ax : optional pair of matplotlib axes (side, top) to draw into (the figure's layout is then left to
        the caller; a panel under 6 inches wide gets its title on two lines).

    Returns
    -------
    The matplotlib figure.
    """
    import matplotlib

    _check_result(result)
    check_picture_path("path", path)
    if path is not None and ax is None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    times, pos = _arc_path(result)
    wet = _in_contact(result, times)
    if ax is None:
        fig, (side, top) = plt.subplots(2, 1, figsize=(10, 5.2), height_ratios=[2.2, 1], sharex=True)
    else:
        side, top = ax
        fig = side.figure
    x, y, z = _throw_frame(pos, float(result.throw.heading))

    xlim = _downrange_limits(x)
    # On the height field the surface moves (ripples, and the dent under the stone): z = 0 is its rest level.
    side.axhline(0.0, color="#2f6fb0", lw=1.2,
                 label="water at rest (the field's surface is not drawn)" if result.field else "water surface")
    side.plot(x, z * 100, color="0.2", lw=1.0, label="centre of mass")
    if wet.any():
        logged = len(result.contacts)
        side.plot(np.where(wet, x, np.nan), np.where(wet, z * 100, np.nan), color="#d1495b", lw=2.5,
                  label="in contact (numbered)" if result.n_contacts <= logged else
                  f"in contact (the first {logged} of {result.n_contacts} logged and numbered)")
    # The contact the stone ended in (it never left the water) is numbered but not a bounce: say so.
    ended_in = result.n_contacts == len(result.contacts) and result.bounces < result.n_contacts
    _number_contacts(side, [c.x for c in result.contacts], xlim,
                     last_note=result.outcome.replace("_", " ") if ended_in else "")
    side.set_xlim(*xlim)
    side.set_ylabel("height [cm]")
    top_cm = max(z.max() * 100 * 1.15, 2.0)
    # room under the water line for three rows of contact numbers and the legend's row
    bottom = min(-2.0, z.min() * 100 - 0.5, -0.45 * top_cm)
    side.set_ylim(bottom, top_cm)
    side.fill_between(xlim, bottom, 0.0, color="#cfe3f5", zorder=0)   # the water, down to the axis' bottom [cm]
    th = result.throw
    throw = (f"{result.stone_name} stone, {result.mass * 1e3:.1f} g: "
             f"{float(th.speed):.1f} m/s, tilt {math.degrees(float(th.tilt)):.1f}°, "
             f"attack {math.degrees(float(th.attack)):.1f}°, spin {float(th.spin) / (2 * math.pi):.1f} rev/s"
             # (the side view is drawn along the heading: a throw along +y looked like one along +x; a review)
             + (f", heading {math.degrees(float(th.heading)):.1f}°" if float(th.heading) != 0.0 else ""))
    # (three significant figures: a 4 cm throw read "0.0 m"; a review)
    far = f"{result.distance:.3g} m" if result.distance >= 1e-3 else "< 1 mm"
    outcome = f"{plural(result.bounces, 'bounce')}, {far}, {result.outcome.replace('_', ' ')}"
    # settings off the defaults, which change the answer: a held tilt read as a free throw (a review)
    force = result.config.force
    other = [w for w, on in (("tilt held", result.config.attitude == "fixed"), (f"{force.law} law", force.law != "bocquet"),
                             (f"velocity {force.velocity}", force.velocity != "body")) if on]
    if other:
        outcome += f" ({', '.join(other)})"
    wide = side.bbox.width / side.figure.dpi >= 6.0       # inches of axis
    side.set_title(f"{throw}  →  {outcome}" if wide else f"{throw}\n→  {outcome}", fontsize=10 if wide else 9)
    _one_row_legend(side)

    # a throw that never moves sideways or downrange (straight down) is one point: drawn as one (a bare line of
    # zero length left the panel blank; a review)
    still = np.ptp(x) < 1e-6 and np.ptp(y) < 1e-6   # [m]: rounding moves a plunging stone by ~1e-8 m
    top.plot(x, y * 100, color="0.2", lw=1.0, marker="o" if still else None, ms=4)
    if wet.any():
        top.plot(np.where(wet, x, np.nan), np.where(wet, y * 100, np.nan), color="#d1495b", lw=2.5)
    top.set_ylabel("sideways [cm]\n(+: left)")
    top.set_xlabel("downrange [m] (along the heading)")
    top.set_xlim(*xlim)
    # A throw that keeps its line (a held attitude) drifts by rounding alone: show at least ±1 cm, in
    # plain numbers, not a 1e-15 axis that draws the noise as a drift.
    lo, hi = float(y.min()) * 100, float(y.max()) * 100
    if hi - lo < 2.0:
        mid = 0.5 * (lo + hi)
        top.set_ylim(mid - 1.0, mid + 1.0)
    top.ticklabel_format(axis="y", useOffset=False, style="plain")
    if ax is None:      # axes passed in: their figure's layout is the caller's
        fig.tight_layout()
    # heights in cm against metres downrange: say how much the side view stretches them (bounces of 3-5° were
    # drawn as 45-60° slopes, unsaid; a review), from the axes' size on the page once laid out
    stretch = _vertical_stretch(side)
    if stretch >= 1.5:
        side.set_ylabel(f"height [cm]\n(drawn ×{stretch:.0f} tall)" if stretch >= 10 else
                        f"height [cm]\n(drawn ×{stretch:.1f} tall)")
    elif stretch <= 1 / 1.5:   # (a steep, short throw drawn flattened, unsaid: 63° looked shallow; a review)
        side.set_ylabel(f"height [cm]\n(drawn ×{stretch:.2f} tall)")
    if path is not None:
        with writing(path):
            fig.savefig(path, dpi=130)
        plt.close(fig)
    return fig


def _vertical_stretch(ax) -> float:
    """How many times taller than wide a length is drawn on the side view ``ax`` (heights in cm, downrange in m):
    the page's vertical scale over its horizontal one, from the axes' extent on the page."""
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    box = ax.get_window_extent()
    if box.width <= 0 or box.height <= 0 or x1 == x0 or y1 == y0:
        return 1.0
    return (box.height / ((y1 - y0) / 100.0)) / (box.width / (x1 - x0))


def _arc_path(result, spacing: float = 1e-3):
    """The centre of mass's path for drawing: ``(times (M,) [s], positions (M, 3) [m])``.

    The recorded steps, with every conservative-advancement jump through the air (a dry step longer
    than ``SimConfig.dt``) filled in along its parabola, ``x + v tau - g tau^2 / 2`` from the step's
    start, every ``spacing`` [s] or closer (at most 32 points a step): exact there, where the
    integrators carry gravity exactly, so the arcs are drawn curved rather than as the chords between
    a flight's few steps. Steps of ``dt`` (in contact, or every step with ``flight="step"``) are joined
    as recorded."""
    traj = result.trajectory
    t = np.asarray(traj["time"], dtype=np.float64)
    x = np.asarray(traj["position"], dtype=np.float64)
    v = np.asarray(traj["velocity"], dtype=np.float64)
    g = float(result.water.gravity) if getattr(result, "water", None) is not None else 9.81
    h = np.diff(t)
    jump = (h > float(result.config.dt) * (1.0 + 1e-3)) & ~(np.asarray(traj["wetted_area"])[:-1] > 0)
    n = np.where(jump & (h > spacing), np.minimum(32, np.ceil(h / spacing)), 1).astype(int)   # points per step
    k = np.repeat(np.arange(len(h)), n)                                                # their step
    j = np.arange(len(k)) - np.repeat(np.cumsum(n) - n, n) + 1                          # 1 .. n within it
    tau = h[k] * j / n[k]
    arc = x[k] + v[k] * tau[:, None] - 0.5 * g * np.array([0.0, 0.0, 1.0]) * tau[:, None] ** 2
    times = t[k] + tau
    last = j == n[k]
    arc[last], times[last] = x[k[last] + 1], t[k[last] + 1]   # each step's own end (the same point in flight)
    return np.concatenate([t[:1], times]), np.concatenate([x[:1], arc])


def _downrange_limits(x):
    """Axis limits [m] for downrange positions ``x``: the release point and the whole path, padded by
    5 % of their span (at least 2 cm) on either side."""
    lo, hi = min(float(x.min()), 0.0), float(x.max())
    pad = max(0.05 * (hi - lo), 0.02)
    return lo - pad, hi + pad


def _in_contact(result, times=None):
    """(N,) bool: each of ``times`` [s] (default: the trajectory's steps) lies within a logged contact,
    from its start to its end (to the end of the run for a contact still going on) — the contacts the
    bounce count numbers, so a hop inside a contact that clears the water by less than
    ``bounce_clearance`` stays part of it. Contacts beyond the log (``SimConfig.max_contacts``) are
    taken from the steps themselves: after the last logged contact, a time is in contact when the
    step it falls in had a wet triangle."""
    t = np.asarray(result.trajectory["time"])
    times = t if times is None else np.asarray(times)
    wet = np.zeros(times.shape, bool)
    for c in result.contacts:
        end = c.t_end if c.t_end is not None and np.isfinite(c.t_end) else np.inf
        wet |= (times >= c.t_start) & (times <= end)
    if result.n_contacts > len(result.contacts):
        last = result.contacts[-1].t_end if result.contacts else -np.inf
        step = np.clip(np.searchsorted(t, times, side="right") - 1, 0, len(t) - 1)
        wet |= (times > last) & (np.asarray(result.trajectory["wetted_area"])[step] > 0)
    return wet


def _throw_frame(pos, heading):
    """World positions (N, 3) [m] -> (downrange, sideways, height) [m] in the throw's frame: downrange
    along ``heading`` [rad] from the release point (the origin), sideways to its left."""
    c, s = math.cos(heading), math.sin(heading)
    return pos[:, 0] * c + pos[:, 1] * s, pos[:, 1] * c - pos[:, 0] * s, pos[:, 2]


def _stone_world(stone, position, orientation):
    """The stone's triangles in the world frame (F, 3, 3) [m] at a frame's pose (NumPy)."""
    from . import quaternion as quat

    R = np.asarray(quat.to_matrix(np.asarray(orientation)))
    return np.asarray(position)[None, None, :] + np.einsum("ij,ftj->fti", R, np.asarray(stone.triangles))


def _frame_extent(field, origin):
    nx, ny = field["shape"]
    l = field["spacing"]  # noqa: E741
    return (origin[0] - l / 2, origin[0] + (nx - 0.5) * l, origin[1] - l / 2, origin[1] + (ny - 0.5) * l)


def plot_water(result, stone=None, path=None, *, frame=None):
    """Ripples after impacts (the seed paper's Fig. 7): a shaded top view and a 3-D view with the stone.

    Parameters
    ----------
    result : a :class:`jaxskip.api.ThrowResult` from ``simulate(..., water_field=...)``.
    stone : the :class:`jaxskip.RigidStone` that was thrown (drawn at the frame's pose); None (default): the
        result's own, ``result.rigid`` (another stone is refused).
    path : if given, save there and close the figure; its suffix picks the format (any matplotlib writes;
        a path without one is refused).
    frame : index into ``result.field["frames"]``, an integer in [-n, n - 1] for n frames (negative: from
        the end); default the most disturbed frame.

    Returns the matplotlib figure.
    """
    import matplotlib

    check_picture_path("path", path)
    if path is not None:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from matplotlib.colors import LightSource
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    field = _check_field(result)
    stone = _check_stone(stone, result)
    frames = field["frames"]
    depth = field["depth"]
    chosen = frame is None
    if frame is None:
        frame = int(np.argmax([np.abs(f[2] - depth).max() for f in frames]))
    else:
        from ._checks import check_int

        frame = check_int("frame", frame, minimum=-len(frames), maximum=len(frames) - 1)
    t, origin, height, position, orientation = frames[frame]
    elev = (height - depth) * 1e3                      # [mm]
    extent = _frame_extent(field, origin)
    fig = plt.figure(figsize=(11, 4.6))
    ax = fig.add_subplot(1, 2, 1)
    lim = _elevation_limit(frames, depth)             # the animation's scale: one throw, one scale
    shade = LightSource(azdeg=315, altdeg=35).shade(elev.T, cmap=plt.get_cmap("RdBu_r"), vert_exag=20.0,
                                                    blend_mode="soft", vmin=-lim, vmax=lim)
    ax.imshow(shade, origin="lower", extent=extent, interpolation="bilinear")
    tri = _stone_world(stone, position, orientation)
    for f in tri:
        ax.fill(f[:, 0], f[:, 1], color="0.35", alpha=0.5, lw=0)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    # (a review: the default frame's moment, mid-throw, said nothing of why it was drawn)
    why = f" of {float(frames[-1][0]):.3f} s, the most disturbed moment" if chosen else ""
    ax.set_title(f"surface at t = {t:.3f} s{why}\n(±{lim:.2g} mm, clipped; shaded)", fontsize=10)
    sm = plt.cm.ScalarMappable(cmap="RdBu_r", norm=plt.Normalize(-lim, lim))
    fig.colorbar(sm, ax=ax, label="elevation [mm]", shrink=0.8)

    ax3 = fig.add_subplot(1, 2, 2, projection="3d")
    nx, ny = field["shape"]
    xs = origin[0] + field["spacing"] * np.arange(nx)
    ys = origin[1] + field["spacing"] * np.arange(ny)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    # The surface clipped at twice the colour scale: a single column's spike (a height field cannot
    # splash) would otherwise set the vertical scale and flatten every ripple.
    cap = 2.0 * lim
    # one colour scale for every picture (still water mid-blue), not each frame's own range
    ax3.plot_surface(X, Y, np.clip(elev, -cap, cap), cmap="Blues_r", norm=plt.Normalize(-cap, cap), linewidth=0,
                     antialiased=True, alpha=0.85)
    ax3.add_collection3d(Poly3DCollection(list(np.stack([tri[..., 0], tri[..., 1], tri[..., 2] * 1e3], -1)),
                                          facecolor="0.45", edgecolor="0.2", linewidths=0.3))
    # Heights in mm over a window of tens of cm: state the vertical exaggeration of the drawn box.
    z_all = np.concatenate([np.clip(elev, -cap, cap).ravel(), tri[..., 2].ravel() * 1e3])
    z_span = max(float(z_all.max() - z_all.min()), 1e-3) * 1e-3          # [m]
    box_z = 0.45
    ax3.set_box_aspect((1.0, ny / nx, box_z))
    exaggeration = box_z * (xs[-1] - xs[0]) / z_span
    ax3.set_xlabel("x [m]", labelpad=6)
    ax3.set_ylabel("y [m]", labelpad=8)
    ax3.set_zlabel(f"z [mm] (drawn ×{exaggeration:.0f} tall)", labelpad=6)
    ax3.set_title(f"the same moment in 3-D; throw: {plural(result.bounces, 'bounce')} in all; window {nx}×{ny}, "
                  f"{field['spacing'] * 100:.3g} cm columns\n(surface clipped at ±{cap:.2g} mm, twice the colour "
                  "scale)", fontsize=10)
    fig.tight_layout()
    if path is not None:
        with writing(path):
            fig.savefig(path, dpi=120, bbox_inches="tight")
        plt.close(fig)
    return fig


#: Narrowest colour scale of the water pictures [mm], 0.1 um: still water (a throw that never touched it) was drawn
#: on a scale of ±1e-6 mm, where rounding noise (~1e-14 mm) could show as ripples (a review); a drop's few
#: micrometres still get their own scale.
ELEVATION_FLOOR = 1e-4


def _elevation_limit(frames, depth) -> float:
    """Colour scale [mm] of the water pictures: the 99.5th percentile of |elevation| over all frames,
    not the maximum — one spike under the stone (tens of mm in a single column) would otherwise wash
    out every ripple. Elevations beyond it are drawn at the end of the scale (clipped)."""
    return max(float(np.percentile(np.abs(np.stack([f[2] for f in frames]) - depth), 99.5)) * 1e3, ELEVATION_FLOOR)


def _check_result(result):
    """``result`` must be a :class:`jaxskip.api.ThrowResult` (a clear error, not an AttributeError inside)."""
    from ._checks import ParameterError
    from .api import ThrowResult

    if not isinstance(result, ThrowResult):
        raise ParameterError(f"result must be a jaxskip ThrowResult (from jaxskip.simulate), got {type(result).__name__}")
    return result


def _check_stone(stone, result):
    """The stone to draw: ``stone``, or None for the one ``result`` was simulated with (``result.rigid``). A stone
    other than that one is refused: a Clanet throw drawn with the paper stone showed another footprint and
    another vertical scale, in silence (a review)."""
    from ._checks import ParameterError
    from .body import RigidStone

    thrown = getattr(result, "rigid", None)
    if stone is None:
        if thrown is None:
            raise ParameterError("stone: this result carries no stone (result.rigid is None): give the "
                                 "jaxskip.RigidStone that was thrown")
        return thrown
    if not isinstance(stone, RigidStone):
        raise ParameterError(f"stone must be the jaxskip.RigidStone that was thrown (e.g. rigid_stone(paper_stone(), "
                             f"density=2650.0)), or None for result.rigid; got {type(stone).__name__}")
    if thrown is not None and (np.shape(stone.triangles) != np.shape(thrown.triangles) or not np.allclose(
            np.asarray(stone.triangles, float), np.asarray(thrown.triangles, float), rtol=1e-6, atol=1e-9)):
        raise ParameterError(f"stone is not the stone this throw was simulated with ({result.stone_name}, "
                             f"{np.shape(thrown.triangles)[0]} triangles): give result.rigid, or None")
    return stone


def _check_field(result):
    from ._checks import ParameterError

    _check_result(result)
    if not getattr(result, "field", None) or not result.field.get("frames"):
        raise ParameterError("this result has no water field: simulate it with water_field=WaterGrid(...)")
    return result.field


def animate_throw(result, stone, path=None, *, fps: int = 20):
    """Write an animation (GIF by extension ``.gif``) of the stone over the water, one frame per snapshot, and in a
    long flight (a gap between snapshots over :data:`LONG_GAP` times their spacing in contact) frames of the stone
    along its arc over the water of the snapshot before (the title says so), :data:`GAP_FRAMES` at most.

    Top view of the window's surface elevation with the stone's footprint and a colour bar [mm],
    and the side view of the trajectory so far (contacts in red). ``result`` from
    ``simulate(..., water_field=...)``. The snapshots are uneven in simulated time (a flight is
    crossed in a few long steps), so each frame is shown for a time proportional to the simulated
    time it covers: the animation is the throw in uniform slow motion, ``fps`` frames a second on
    average (each frame shown 20 ms to 2 s: GIF viewers show shorter frames slower, so 50 is the most).

    ``stone``: the :class:`jaxskip.RigidStone` that was thrown (its triangles draw the footprint), or None for the
    result's own, ``result.rigid`` (another stone is refused).
    ``fps``: frames per second of the animation on average, in (0, 50]. Returns ``path``.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt
    from PIL import Image

    from ._checks import ParameterError, check_range

    if isinstance(stone, (str, os.PathLike)) and str(stone).lower().endswith(".gif"):   # (a raw TypeError before)
        raise ParameterError(f"animate_throw(result, stone, path): the path came second, as the stone ({stone!r}); "
                             f"give animate_throw(result, None, {str(stone)!r}) (None: the result's own stone)")
    if not str(path).lower().endswith(".gif"):
        raise ParameterError(f"the animation path must end in .gif, got {path!r}")
    check_file_path("path", path)
    fps = check_range("fps", fps, 0.0, 50.0, unit="frames/s", low_open=True)
    field = _check_field(result)
    stone = _check_stone(stone, result)
    snapshots = field["frames"]
    depth = field["depth"]
    lim = _elevation_limit(snapshots, depth)
    frames, water_time = _fill_long_gaps(result, snapshots)
    times, pos = _arc_path(result)                     # the side view's path, as plot_throw draws it
    wet = _in_contact(result, times)
    heading = float(result.throw.heading)
    down = _throw_frame(pos, heading)[0]
    # heights in cm, or in m for a throw that flies over 2 m high (released 100 m up it read 0-10000 cm; a review)
    scale, unit = (100.0, "cm") if float(np.abs(pos[:, 2]).max()) <= 2.0 else (1.0, "m")
    floor = 2.0 / (100.0 / scale)    # the view's least extent above and below the water: 2 cm
    fig, (top, side) = plt.subplots(1, 2, figsize=(11, 4.2), width_ratios=[1, 1.3], layout="constrained")
    sm = plt.cm.ScalarMappable(cmap="RdBu_r", norm=plt.Normalize(-lim, lim))
    fig.colorbar(sm, ax=top, label="elevation [mm]", shrink=0.85, pad=0.02)
    durations = _frame_durations([f[0] for f in frames], fps)
    slow = _pace(durations, frames[-1][0] - frames[0][0])

    def draw(i):
        top.clear()
        side.clear()
        t, origin, height, position, orientation = frames[i]
        top.imshow(((height - depth) * 1e3).T, origin="lower", extent=_frame_extent(field, origin),
                   cmap="RdBu_r", vmin=-lim, vmax=lim, interpolation="bilinear")
        for f in _stone_world(stone, position, orientation):
            top.fill(f[:, 0], f[:, 1], color="0.3", alpha=0.6, lw=0)
        held = f" (water: {water_time[i]:.3f} s)" if water_time[i] < t else ""
        # (two lines: with the water's own time added the one line ran past the figure's left edge; a review)
        top.set_title(f"t = {t:.3f} s{held}\n{slow.lstrip('; ')}{'; ' if slow else ''}colours clipped at "
                      f"±{lim:.2g} mm", fontsize=9)
        top.set_xlabel("x [m]")
        top.set_ylabel("y [m]")
        seen = times <= t
        side.axhline(0.0, color="#2f6fb0", lw=1.0)
        side.plot(down[seen], pos[seen, 2] * scale, color="0.2", lw=1.0)
        side.plot(np.where(seen & wet, down, np.nan), np.where(seen & wet, pos[:, 2] * scale, np.nan),
                  color="#d1495b", lw=2.0)
        # (red only in contact, as the title says: it was red in the air too; a review)
        now = bool(_in_contact(result, np.array([t]))[0])
        side.plot(_throw_frame(np.asarray(position)[None], heading)[0], [position[2] * scale], "o",
                  color="#d1495b" if now else "0.2")
        side.set_xlim(*_downrange_limits(down))
        side.set_ylim(min(-floor, pos[:, 2].min() * scale - floor / 4), max(pos[:, 2].max() * scale * 1.15, floor))
        side.set_xlabel("downrange [m] (along the heading)")
        side.set_ylabel(f"centre of mass height [{unit}]")
        side.set_title(f"the whole throw: {plural(result.bounces, 'bounce')}, {result.outcome.replace('_', ' ')} "
                       f"(red: in contact)", fontsize=9)

    images = []
    for i in range(len(frames)):
        draw(i)
        fig.canvas.draw()
        if i == 0:
            # the layout of the first frame for all: laid out anew, the panels moved by up to 16 pixels from frame
            # to frame as the moving window's tick labels changed (the picture shook; a review)
            fig.set_layout_engine("none")
        images.append(Image.fromarray(np.asarray(fig.canvas.buffer_rgba())[..., :3].copy()))
    plt.close(fig)
    images = _one_palette(images)
    with writing(path):
        images[0].save(path, save_all=True, append_images=images[1:], duration=durations, loop=0)
    return path


def _one_palette(images: list) -> list:
    """The RGB ``images`` as palette images sharing one palette, made from the first, middle and last (a GIF
    frame otherwise gets its own: one pixel of the colour bar took 24 colours over 36 frames; a review)."""
    from PIL import Image

    picks = [images[0], images[len(images) // 2], images[-1]]
    w, h = picks[0].size
    sheet = Image.new("RGB", (w, h * len(picks)))
    for k, im in enumerate(picks):
        sheet.paste(im, (0, h * k))
    palette = sheet.quantize(colors=256, method=Image.Quantize.MEDIANCUT)
    return [im.quantize(palette=palette, dither=Image.Dither.NONE) for im in images]


#: A gap between two water snapshots longer than this many times the snapshots' spacing in contact (a long flight,
#: crossed in a few long steps) gets frames of its own in :func:`animate_throw`: :data:`GAP_FRAMES` at most in all.
LONG_GAP = 3.0
GAP_FRAMES = 120


def _fill_long_gaps(result, snapshots) -> tuple:
    """``(frames, water_time)``: the snapshots, plus frames inside each gap longer than :data:`LONG_GAP` times the
    spacing of the snapshots in contact (the smaller of their median gap and ``simulate``'s default 10 ms): a
    flight, drawn with the stone at its exact pose along the arc (:func:`jaxskip.export.frames`) over the water as
    at the snapshot before (which the coupled water does not advance past in a long jump either); and for each
    frame the time [s] of the water it shows. (A throw released 100 m up was 8 frames, 0.8 s of flight apart.)"""
    from .api import FIELD_CHUNK_TIME

    t = np.array([f[0] for f in snapshots], dtype=float)
    gaps = np.diff(t)
    if gaps.size == 0 or not (gaps > 0).any():
        return list(snapshots), t.tolist()
    step = min(float(np.median(gaps[gaps > 0])), FIELD_CHUNK_TIME)
    long = gaps > LONG_GAP * step
    if not long.any():
        return list(snapshots), t.tolist()
    from .export import MAX_FPS
    from .export import frames as sample

    spacing = max(step, float(gaps[long].sum()) / GAP_FRAMES)   # evenly in time, GAP_FRAMES at most
    poses = sample(result, fps=min(1.0 / spacing, MAX_FPS))
    out, water_time = [], []
    for i, snap in enumerate(snapshots):
        out.append(snap)
        water_time.append(t[i])
        if i < gaps.size and long[i]:
            for k in np.flatnonzero((poses["time"] > t[i] + 0.5 * spacing) & (poses["time"] < t[i + 1] - 0.5 * spacing)):
                origin, height = _recentred(result.field, snap[1], snap[2], poses["position"][k])
                out.append((float(poses["time"][k]), origin, height, poses["position"][k], poses["orientation"][k]))
                water_time.append(t[i])
    return out, water_time


def _recentred(field: dict, origin, height, position) -> tuple:
    """The window of a snapshot (``origin`` (2,) [m], column ``height`` (nx, ny) [m]) moved by whole columns to
    centre on ``position`` (3,) [m], by :func:`jaxskip.coupled.recentre`'s rule: columns that enter hold still
    water (``field["depth"]``). Returns ``(origin, height)``, host arrays."""
    import jax.numpy as jnp

    from .coupled import _centred_offset, _shift

    l = field["spacing"]  # noqa: E741
    old = np.round(np.asarray(origin, dtype=float) / l).astype(np.int32)
    new = np.asarray(_centred_offset(l, height.shape, jnp.asarray(position)))
    return new * l, np.asarray(_shift(jnp.asarray(height), new - old, field["depth"]))


def _pace(durations, span: float) -> str:
    """The animation's pace against the throw's, for its title: ``durations`` [ms] of the frames, ``span`` [s]
    of simulated time they cover. A 4.45 s throw shown in 0.39 s read "slow motion ×0.1"; now "fast forward ×11".

    >>> _pace([50] * 30, 0.375), _pace([70] * 5 + [40], 4.45), _pace([50], 0.0), _pace([2000] * 10, 0.09)
    ('; slow motion ×4', '; fast forward ×11', '', '; slow motion ×222')
    """
    if span <= 0:
        return ""
    ratio = sum(durations) / 1000.0 / span
    k = ratio if ratio >= 1 else 1 / ratio
    # (whole numbers from 10 up: "×2e+02" read as code; a review)
    text = f"{k:.0f}" if k >= 10 else f"{k:.2g}"
    return f"; slow motion ×{text}" if ratio >= 1 else f"; fast forward ×{text}"


def _frame_durations(times, fps: float) -> list:
    """Display time [ms] of each frame: proportional to the simulated time [s] up to the next frame
    (the last frame: the mean), scaled so the frames average ``1000 / fps`` ms, each held within
    20 ms – 2 s, in whole 10 ms (a GIF's unit)."""
    t = np.asarray(times, dtype=float)
    gaps = np.diff(t)
    gaps = np.append(gaps, gaps.mean() if gaps.size else 1.0)
    gaps = np.maximum(gaps, 0.0)
    mean = gaps.mean()
    share = gaps / mean if mean > 0 else np.ones_like(gaps)
    ms = np.clip(share * 1000.0 / fps, 20.0, 2000.0)
    return [int(10 * round(m / 10)) for m in ms]
