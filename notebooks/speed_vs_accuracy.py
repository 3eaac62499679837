# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---

# %% [markdown]
# # Speed against accuracy: one Pareto chart for every knob
#
# "Both speed and accuracy count: chart one against the other." For each knob — the contact
# time step and integrator, the flight treatment, exact vs smooth clipping, float32 vs float64,
# the mesh resolution, and the water (flat, or a height field: its spacing and clamp) — a batch of random throws in the human box (speed 3–12 m/s, tilt
# 5–45°, attack 0–30°, spin 0–20 rev/s) is run and compared with a converged reference (a 10×
# finer time step, RK4, float64; 5× in quick mode). Error: the share of the batch whose bounce count differs from
# the reference, plus the median relative errors of the first contact's duration and of the
# trajectory (where the stone touches down a second time, after one contact and one flight). Cost: wall time
# per throw of the compiled rollout (compile time excluded): for the paper stone and the disk series the
# whole batch run to completion by `simulate_batch` (the fastest of 3 runs, divided by the batch size);
# for the water series (flat and height field) a subset run one throw at a time. The two bases differ
# (the default configuration costs more per throw batched than one at a time, printed below), so costs
# compare within a series, not across; the chart's legend says which basis each series has. The default
# configuration is marked.
#
# `python notebooks/speed_vs_accuracy.py` (full: 128 throws) or `JAXSKIP_QUICK=1 ...` (CI: 16 throws; 3 of
# them on the height field); figures go to `JAXSKIP_NOTEBOOK_OUT` (default `notebooks/figures/`). Run time
# on the 2-core development machine (2026-12-07): full ~3–4 min, quick ~35 s (wall time; load moves it).

# %%
import dataclasses
import time

import jax
import jax.numpy as jnp
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.ticker import LogFormatter
from matplotlib.transforms import Bbox

from jaxskip.notebook import notebook_mode

RUN = notebook_mode("speed_vs_accuracy", here=globals().get("__file__"))  # no __file__ in a Jupyter kernel
QUICK = RUN.quick

from jaxskip import ForceModel, SimConfig, Throw, disk, paper_stone, rigid_stone, rollout, simulate_batch, water_params  # noqa: E402 (after the float64 switch)
N = 16 if QUICK else 128
rng = np.random.default_rng(1)
box = dict(speed=rng.uniform(3, 12, N), tilt=rng.uniform(5, 45, N), attack=rng.uniform(0, 30, N),
           spin=rng.uniform(0, 20, N))
water = water_params()
DEFAULT = SimConfig(record=False)
REPEATS = 3  # timed runs per configuration (the cost is the fastest)


def run(config, stone, dtype=jnp.float64, timed=True):
    """Bounce counts, first contact durations [s], second touchdown x [m] and wall time per throw [s].

    Runs the batch to completion with ``simulate_batch`` (finished throws stop costing): once to
    compile, then ``REPEATS`` times; the fastest of those calls' wall times is the cost (other load
    on the machine only adds time, so the minimum is the figure least moved by it)."""
    cast = lambda a: jnp.asarray(a, dtype)  # noqa: E731
    throws = jax.tree_util.tree_map(cast, Throw.from_degrees(**box))
    st = jax.tree_util.tree_map(cast, stone)
    wt = jax.tree_util.tree_map(cast, water)
    if timed:
        simulate_batch(throws, st, water=wt, config=config, lanes=min(N, 64))
    walls = []
    for _ in range(REPEATS if timed else 1):
        t0 = time.perf_counter()
        r = simulate_batch(throws, st, water=wt, config=config, lanes=min(N, 64))
        walls.append(time.perf_counter() - t0)
    wall = min(walls) / N
    return (np.asarray(r.bounces), np.asarray(r.tracker.t_end[:, 0] - r.tracker.t_start[:, 0], float),
            np.asarray(r.tracker.x_start[:, 1, 0], float), wall)


def _median_rel(got, ref):
    """Median relative error over the throws where both are finite and the reference is positive."""
    ok = np.isfinite(ref) & np.isfinite(got) & (ref > 0)
    return float(np.median(np.abs(got[ok] / ref[ok] - 1))) if ok.any() else float("nan")


def report(label, got, ref, width=28):
    """Compare with the reference, print, and keep a row (label, cost, count miss, contact error, trajectory error).

    Errors: the share of throws whose bounce count differs; the median relative error of the first
    contact's duration; the median relative error of where the stone touches down a second time
    (the trajectory through one contact and one flight; release at x = 0)."""
    miss = 1.0 - float(np.mean(ref[0] == got[0]))
    row = (label, got[3], miss, _median_rel(got[1], ref[1]), _median_rel(got[2], ref[2]))
    rows.append(row)
    print(f"{label:<{width}} {got[3] * 1e3:8.2f} ms/throw; count differs on {miss:5.1%}; "
          f"first contact error {row[3]:.2%}; trajectory error {row[4]:.2%}")


def error(row):
    """The charted error: count miss + contact error + trajectory error (a missing one counts 1)."""
    return sum(e if np.isfinite(e) else 1.0 for e in row[2:])


# %% [markdown]
# ## The paper's stone: time step, integrator, flight, clipping, precision

# %%
paper = rigid_stone(paper_stone(), density=2650.0)
ref_dt = 5e-5 if QUICK else 2.5e-5
ref_cfg = dataclasses.replace(DEFAULT, dt=ref_dt, integrator="rk4", max_steps=120_000, segment=500)
ref = run(ref_cfg, paper, timed=False)
print(f"reference (dt {ref_dt:g} s, rk4, float64): mean {ref[0].mean():.2f} bounces, {ref[3] * 1e3:.1f} ms per throw")
variants = {
    "default (euler, dt 2.5e-4)": (DEFAULT, paper, jnp.float64),
    "dt 1e-3": (dataclasses.replace(DEFAULT, dt=1e-3), paper, jnp.float64),
    "dt 5e-4": (dataclasses.replace(DEFAULT, dt=5e-4), paper, jnp.float64),
    "dt 1e-4": (dataclasses.replace(DEFAULT, dt=1e-4, max_steps=40_000), paper, jnp.float64),
    "rk4, dt 2.5e-4": (dataclasses.replace(DEFAULT, integrator="rk4"), paper, jnp.float64),
    "rk4, dt 5e-4": (dataclasses.replace(DEFAULT, integrator="rk4", dt=5e-4), paper, jnp.float64),
    "flight stepped at dt": (dataclasses.replace(DEFAULT, flight="step", max_steps=40_000), paper, jnp.float64),
    "smooth clipping k=2000/m": (dataclasses.replace(DEFAULT, force=ForceModel(sharpness=2000.0)), paper, jnp.float64),
    "smooth clipping k=20000/m": (dataclasses.replace(DEFAULT, force=ForceModel(sharpness=20000.0)), paper,
                                  jnp.float64),
    "float32": (DEFAULT, paper, jnp.float32),
}
if QUICK:
    variants = {k: v for k, v in variants.items() if k in ("default (euler, dt 2.5e-4)", "dt 1e-3", "float32")}
rows = []
for label, (cfg, stone, dtype) in variants.items():
    if dtype == jnp.float32:
        jax.config.update("jax_enable_x64", False)
    got = run(cfg, stone, dtype)
    jax.config.update("jax_enable_x64", True)
    report(label, got, ref)

# %% [markdown]
# ## Mesh resolution (a 5 cm, 12 mm disk from 32 to 512 triangles, against 1024)
# The disk series has its own reference: the same disk with 1024 triangles at the *same* time step
# and integrator, so its error is the mesh's alone (the time step's share is charted above).

# %%
segs = (8, 16) if QUICK else (8, 16, 32, 64, 128)
ref_segs = 64 if QUICK else 256
ref_disk = run(DEFAULT, rigid_stone(disk(0.05, 0.012, segments=ref_segs), density=2650.0), timed=False)
print(f"disk reference: {4 * ref_segs} triangles, dt {DEFAULT.dt:g} s, euler: mean {ref_disk[0].mean():.2f} bounces")
for n in segs:
    stone = rigid_stone(disk(0.05, 0.012, segments=n), density=2650.0)
    report(f"disk, {int(stone.triangles.shape[0])} triangles", run(DEFAULT, stone), ref_disk)

# %% [markdown]
# ## The water: flat, or a height field — its grid spacing, clamp and time step
# The library's default is flat water; `simulate(water_field=default_window())` couples the stone to
# a moving 64 cm window of O'Brien–Hodgins columns (1 cm, smooth clamp, a water step every 1 ms of
# stone time). Reference: the same window at half the spacing (0.5 cm, 128² columns) with the
# paper's clamp, stepped every 0.25 ms in full mode. Each throw runs on its own (compiled once per
# configuration; compile excluded), on a subset of the batch — flat water too, so that the series
# compares like with like: a coupled throw costs 4.7–12.0× a flat one, timed the same way (printed
# below; full mode, 2026-12-07, stop 47). Full mode also varies the water's step (0.5 and 4 ms against the default 1 ms): the
# multirate coupling's own knob.

# %%
from jaxskip.coupled import default_window, rollout_coupled  # noqa: E402

NW = 3 if QUICK else 24
window = default_window()
# label: (grid, water step [s]; None: the coupling's default, 1 ms)
water_grids = {
    "field 2 cm, smooth clamp": (dataclasses.replace(window, shape=(32, 32), spacing=0.02, sponge_width=4), None),
    "field 1 cm, smooth (coupled default)": (window, None),
}
if not QUICK:
    water_grids["field 1 cm, zero clamp"] = (dataclasses.replace(window, clamp="zero"), None)
    water_grids["field 1 cm, paper's clamp"] = (dataclasses.replace(window, clamp="reference"), None)
    water_grids["field 1 cm, water step 0.5 ms"] = (window, 5e-4)
    water_grids["field 1 cm, water step 4 ms"] = (window, 4e-3)
fine = ((dataclasses.replace(window, shape=(128, 128), spacing=0.005, sponge_width=16, clamp="reference"), 2.5e-4)
        if not QUICK else (dataclasses.replace(window, clamp="reference"), None))


def run_field(grid, water_dt=None):
    """As :func:`run`, one throw at a time, on a height field (``grid``, stepped every ``water_dt``
    [s] of stone time, None: the coupling's default; ``grid`` None: flat water)."""
    cfg = DEFAULT
    if grid is None:
        fn = lambda th: rollout(cfg, th, paper, water)[1]  # noqa: E731
    else:
        fn = lambda th: rollout_coupled(cfg, grid, th, paper, water, water_dt=water_dt)[1]  # noqa: E731
    throws = Throw.from_degrees(**{k: v[:NW] for k, v in box.items()})
    one = lambda i: jax.tree_util.tree_map(lambda a: a[i], throws)  # noqa: E731
    compiled = jax.jit(fn).lower(one(0)).compile()
    counts, durations, touchdown = [], [], []
    t0 = time.perf_counter()
    for i in range(NW):
        tr = jax.block_until_ready(compiled(one(i)))
        counts.append(int(tr.bounces))
        durations.append(float(tr.t_end[0] - tr.t_start[0]))
        touchdown.append(float(tr.x_start[1, 0]))
    return np.array(counts), np.array(durations), np.array(touchdown), (time.perf_counter() - t0) / NW


ref_water = run_field(*fine)
print(f"water reference: {fine[0].spacing * 100:g} cm columns {fine[0].shape}, {fine[0].clamp} clamp, water step "
      f"{(fine[1] or 1e-3) * 1e3:g} ms: mean {ref_water[0].mean():.2f} bounces, {ref_water[3]:.2f} s per throw")
for label, (grid, water_dt) in [("flat water (library default)", (None, None))] + list(water_grids.items()):
    report("water: " + label, run_field(grid, water_dt), ref_water, width=43)
flat_one = next(r[1] for r in rows if r[0] == "water: flat water (library default)")
field_cost = [r[1] / flat_one for r in rows if r[0].startswith("water: field")]
default_batch = next(r[1] for r in rows if r[0] == "default (euler, dt 2.5e-4)")
print(f"cost bases: the default configuration on flat water costs {default_batch * 1e3:.2f} ms/throw batched "
      f"(simulate_batch, {N} throws to completion) and {flat_one * 1e3:.2f} ms/throw one throw at a time (the first {NW}); "
      f"the height field costs {min(field_cost):.1f}-{max(field_cost):.1f}x flat water, both one at a time")

# %% [markdown]
# ## The Pareto chart
# On the paper's stone, a configuration is on the front when no other is both cheaper and more
# accurate (error = share of counts that differ + first-contact error + trajectory error). The disk series (mesh
# resolution) and the water series have their own references and are drawn beside the front, not on it.

# %%
paper_rows = [r for r in rows if not r[0].startswith(("disk", "water"))]
disk_rows = [r for r in rows if r[0].startswith("disk")]
water_rows = [r for r in rows if r[0].startswith("water")]
cost = np.array([r[1] for r in paper_rows])
err = np.array([error(r) for r in paper_rows])
front = [i for i in range(len(cost)) if not any(cost[j] <= cost[i] and err[j] < err[i] for j in range(len(cost)))]
d = [r[0] for r in paper_rows].index("default (euler, dt 2.5e-4)")
best_err = min(err[i] for i in front if cost[i] <= cost[d])
gap = (err[d] - best_err) / max(best_err, 1e-12)
print(f"default on the front: {d in front}; its error {err[d]:.3f} vs the front's best at no more cost "
      f"{best_err:.3f} ({gap:+.0%}; criterion: within 10 %)")

FLOOR = 1e-3  # a zero error (a series' reference against itself in quick mode) is drawn here on the log axis


def place_labels(ax, labels, fontsize=7):
    """Write each ``(text, (x, y), color)`` of ``labels`` beside its point (data coordinates), greedily,
    the first label and then the most crowded points first: of a few candidate offsets, nearest first,
    the first whose box overlaps no label already placed, keeps clear of the other labelled points, the
    lines drawn and the legend, stays inside the axes, and whose leader line crosses no label, other
    point or leader line (if none does, the candidate with the fewest clashes, weighted). A label set
    away from its point gets a thin leader line. Call after the layout is final. Returns each label's
    weighted clashes (0: clear of everything)."""
    fig = ax.figure
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    px = fig.dpi / 72   # pixels per point
    xy_px = ax.transData.transform(np.asarray([xy for _, xy, _ in labels], float))
    r = 7.0 * px   # a marker's half-size (the default's ring)
    markers = [Bbox.from_extents(x - r, y - r, x + r, y + r) for x, y in xy_px]
    boxes = [ax.get_legend().get_window_extent(renderer)] if ax.get_legend() is not None else []
    leaders = []   # (start, end) of the leader lines drawn so far [px]
    drawn = [ax.transData.transform(np.asarray(line.get_xydata(), float)) for line in ax.get_lines()
             if line.get_linestyle() not in ("None", "", " ") and len(line.get_xydata()) > 1]
    # points along the lines drawn (Pareto front, series): a label on a line is harder to read
    drawn = np.vstack([a + np.linspace(0, 1, 40)[:, None] * (b - a) for xy in drawn for a, b in zip(xy[:-1], xy[1:])]
                      or [np.zeros((0, 2))])
    frame = ax.get_window_extent(renderer)
    ways = [(1, 0), (1, 1), (1, -1), (-1, 0), (-1, 1), (-1, -1), (0, 1), (0, -1),
            (2, 1), (2, -1), (-2, 1), (-2, -1), (1, 2), (1, -2), (-1, 2), (-1, -2)]
    candidates = [(dist, dx, dy) for dist in (9, 18, 28, 40, 54, 70, 88, 108, 130) for dx, dy in ways]

    def crosses(p, q, box, skip=0.0):   # the segment p-q passes through the box (sampled; ``skip`` px from p)
        pts = p + np.linspace(min(skip / max(np.hypot(*(q - p)), 1e-9), 1.0), 1.0, 16)[:, None] * (q - p)
        return bool(((pts[:, 0] > box.x0) & (pts[:, 0] < box.x1) & (pts[:, 1] > box.y0) & (pts[:, 1] < box.y1)).any())

    def intersect(p, q, a, b):   # the segments p-q and a-b cross
        def side(u, v, w):
            return np.sign((v[0] - u[0]) * (w[1] - u[1]) - (v[1] - u[1]) * (w[0] - u[0]))
        return side(p, q, a) * side(p, q, b) < 0 and side(a, b, p) * side(a, b, q) < 0

    gap = np.hypot(*(xy_px[:, None, :] - xy_px[None, :, :]).transpose(2, 0, 1))
    crowd = (gap < 40 * px).sum(axis=1)
    clashes = {}
    for k in [0] + sorted(range(1, len(labels)), key=lambda j: -crowd[j]):
        text, xy, color = labels[k]
        # other points, with a margin: a label next to another point would read as that point's
        others = [m.padded(4 * px) for j, m in enumerate(markers) if j != k]
        # (a leader may cross the markers of points on top of its own: it cannot avoid them)
        apart = [m for j, m in enumerate(markers) if j != k and gap[j, k] > 2 * r]
        best = None
        for dist, dx, dy in candidates:
            n = np.hypot(dx, dy)
            off = (dist * dx / n, dist * dy / n)
            align = dict(ha="left" if dx > 0 else "right" if dx < 0 else "center",
                         va="bottom" if dy > 0 else "top" if dy < 0 else "center")
            t = ax.annotate(text, xy, xytext=off, textcoords="offset points", fontsize=fontsize, **align)
            box = t.get_window_extent(renderer).padded(2)
            t.remove()
            start, end = xy_px[k], xy_px[k] + np.asarray(off) * px
            lead = dist > 9
            # clashes, weighted: on a label or out of the axes, worst; on a point; a crossed line, least
            clash = (10 * sum(box.overlaps(o) for o in boxes) + 3 * sum(box.overlaps(o) for o in others)
                     + 3 * sum(crosses(a, b, box) for a, b in leaders)
                     + 2 * bool(((drawn[:, 0] > box.x0) & (drawn[:, 0] < box.x1) & (drawn[:, 1] > box.y0)
                                 & (drawn[:, 1] < box.y1)).any())
                     + (3 * sum(crosses(start, end, o, r) for o in boxes)
                        + sum(crosses(start, end, o, r) for o in apart)
                        + sum(intersect(start, end, a, b) for a, b in leaders) if lead else 0)
                     + 100 * (box.x0 < frame.x0 or box.x1 > frame.x1 or box.y0 < frame.y0 or box.y1 > frame.y1))
            if best is None or clash < best[0]:
                best = (clash, off, align, box, lead, (start, end))
            if clash == 0:
                break
        clash, off, align, box, lead, segment = best
        clashes[text] = clash
        # (the leader starts at the label's anchor, the corner or edge facing its point: relpos)
        relpos = ({"left": 0.0, "center": 0.5, "right": 1.0}[align["ha"]],
                  {"bottom": 0.0, "center": 0.5, "top": 1.0}[align["va"]])
        ax.annotate(text, xy, xytext=off, textcoords="offset points", fontsize=fontsize, color=color, **align,
                    arrowprops=dict(arrowstyle="-", lw=0.6, color=color, alpha=0.6, shrinkA=1, shrinkB=4,
                                    relpos=relpos) if lead else None)
        boxes.append(box)
        if lead:
            leaders.append(segment)
    return clashes


fig, ax = plt.subplots(figsize=(9, 6), dpi=110)
ax.scatter(cost * 1e3, err, color="C0", label=f"paper stone: dt, integrator, flight, clipping, precision\n"
                                              f"(cost: batch of {N} to completion)")
order = sorted(front, key=lambda i: cost[i])
ax.plot(cost[order] * 1e3, err[order], "k--", lw=0.8, label="Pareto front")
ax.scatter([cost[d] * 1e3], [err[d]], s=160, facecolors="none", edgecolors="C3", lw=2,
           label="default (batched; the same configuration one throw at a time: 'flat water')")
dc = np.array([r[1] for r in disk_rows])
de = np.array([error(r) for r in disk_rows])
ax.plot(dc * 1e3, np.maximum(de, FLOOR), "s-", color="C2",
        label=f"disk: mesh resolution (own reference; cost: batch of {N} to completion)")
wc = np.array([r[1] for r in water_rows])
we = np.array([error(r) for r in water_rows])
ax.scatter(wc * 1e3, np.maximum(we, FLOOR), marker="^", color="C4",
           label=f"water: flat vs height field (own reference;\ncost: {NW} throws one at a time, not batched)")
ax.set_xscale("log")
ax.set_yscale("log")
for fmt in (ax.xaxis.set_major_formatter, ax.xaxis.set_minor_formatter):
    fmt(LogFormatter(labelOnlyBase=False))   # plain numbers (2, 3, 10), not 2×10⁰
ax.set_ylim(FLOOR / 2, 5 * max(err.max(), we.max(), de.max()))
ax.set(xlabel="wall time per throw [ms] (paper stone, disk: batch to completion; water: one throw at a time)",
       ylabel="error: count share + first-contact + trajectory (0 at 1e-3)",
       title=f"speed vs accuracy over {N} random throws (reference: dt {ref_dt:g} s, RK4, float64)")
ax.legend(fontsize=8, loc="lower left")
fig.tight_layout()
# Point labels (the default's first), in their series' colours, placed clear of each other, of the points
# and of the legend.
labels = ([(paper_rows[d][0], (cost[d] * 1e3, err[d]), "k")]
          + [(r[0], (cost[i] * 1e3, err[i]), "k") for i, r in enumerate(paper_rows) if i != d]
          + [(r[0].replace("disk, ", ""), (c * 1e3, max(e, FLOOR)), "C2") for r, c, e in zip(disk_rows, dc, de)]
          + [(r[0].replace("water: ", "").replace("(library default)", "(the default, one at a time)"),
              (c * 1e3, max(e, FLOOR)), "C4") for r, c, e in zip(water_rows, wc, we)])
place_labels(ax, labels)
path = RUN.figure("speed_vs_accuracy.png")
fig.savefig(path, dpi=110)
RUN.done(path)

# %% [markdown]
# ## Reading the chart
# Full mode on the 2-core development machine (2026-12-07; the figures print above; the machine is
# shared, and its timings move by tens of per cent between runs — the errors do not):
#
# * **Bounce counts of the free stone are chaotic.** Even a 2.5× finer step or RK4 disagrees with
#   the 10× finer RK4 reference on 16–18 % of the throws, the default on 25 %; the first contact's
#   duration and the trajectory to the second touchdown converge (0.5 % and 0.3 % at the default,
#   0.2 % and 0.1 % at dt 1e-4). The default sits within 10 % of the front (6 %); float32 is
#   cheaper at the same accuracy on the batch, but
#   loses to round-off where gradients and sharp smoothing matter (`stability.py`, section 5).
# * **Mesh.** From 32 to 512 triangles the disk's count disagreement with 1024 triangles falls
#   from 19 % to 5 % at roughly linear cost; the paper's 38-triangle stone is at the coarse end.
# * **Water.** The height field is *not converged* in its spacing: at 1 cm the counts differ from
#   the 0.5 cm reference on 62.5–70.8 % of throws, the first contact by 13.2 % and the second
#   touchdown by 16.4–17.4 %, whatever the clamp (reference stepped every 0.25 ms; stop 47, the
#   flight jumps aiming above the water they can reach; stop 46: 66.7–75.0 %, 14.1 %, 16.0–16.9 %;
#   session 13, with a 1 ms reference: ~75 %, ~21 %, 26–27 %). Its time step matters less than its
#   spacing: a water step of 0.5 ms instead of the default 1 ms gains little (first contact 15.9 %,
#   worse than the default step's 13.2 %; second touchdown 17.0 % against 17.4 %) at 1.5× the cost
#   (25.54 against 17.15 ms), 4 ms loses a lot (32.4 % / 44.9 %) for a 1.7× saving (10.02 ms) — so
#   1 ms stays. The
#   coupling also changes the contact itself: flat water's first contact differs from the 0.5 cm
#   field's by ~110 %. Flat water stays the library's default; the coupled field is an experimental
#   option (docs/water.md).
# * **Cost bases.** The water series is timed one throw at a time on the first 24 throws, the
#   rest as batches of 128 run to completion: the default configuration costs 4.26 ms/throw batched
#   and 2.13 ms/throw one at a time (the "flat water" point), so the water points' costs compare
#   with each other (the height field costs 4.7–12.0× flat water), not with the paper stone's.
