# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---

# %% [markdown]
# # From a poor throw to a great one
#
# The bounce count is piecewise constant in the throw, so its gradient is zero almost
# everywhere; `optimize` climbs a smooth count instead (the lowest vertex's height over the
# clearance level, through a sigmoid; `optimize.objectives`) and always reports the exact
# simulation's count. Here: a clumsy throw (slow, steep, little spin) is the first start of a
# gradient search in the human box (speed 3–12 m/s, tilt 5–45°, attack 0–30°, spin 0–20 rev/s).
# The free stone's count is chaotic (neighbouring throws differ by tens of bounces), so the
# search ends with a polish: exact throws sampled near the best throws the ascent visited
# (`polish=`, `optimize.local_search`). The search records every start's raw gradient norm at
# every iteration (gradient-norm monitoring, `optimize.gradient_health`): on long throws the
# norms explode, because the rollout is chaotic and a gradient over a whole throw measures that
# chaos rather than the count's trend (`benchmarks/README.md`, session 14).
#
# `python notebooks/optimize_throw.py` (full) or `JAXSKIP_QUICK=1 python notebooks/optimize_throw.py`; figures go to
# `JAXSKIP_NOTEBOOK_OUT` (default `notebooks/figures/`). Run time on the 2-core development machine
# (2026-12-07): full ~40 s, quick ~15 s (wall time; load moves it).

# %%
import matplotlib.pyplot as plt

from jaxskip.notebook import notebook_mode

RUN = notebook_mode("optimize_throw", here=globals().get("__file__"))  # no __file__ in a Jupyter kernel
QUICK = RUN.quick

from jaxskip import Throw, simulate  # noqa: E402
from jaxskip.plotting import plot_throw  # noqa: E402
from optimize import EXPLODING, gradient_health, gradient_search, make_box  # noqa: E402

poor = {"speed": 4.0, "tilt": 40.0, "attack": 25.0, "spin": 3.0}
before = simulate(Throw.from_degrees(**poor))
print(f"poor throw {poor}: {before.bounces} bounces, {before.distance:.2f} m, {before.outcome}")

# %%
result = gradient_search(make_box(), starts=2 if QUICK else 8, iterations=4 if QUICK else 20, initial=poor,
                         polish=8 if QUICK else 256)
ascent = [h for h in result.history if h.get("phase") != "polish"]
first = [h["bounces"][0] for h in ascent]
print(f"the poor throw's own path: {first}")
print(f"best of the ascent: {ascent[-1]['best']} bounces; after the polish: {result.best_bounces}")
print(f"best found: {result.best_bounces} bounces at " + ", ".join(f"{k} {v:.1f}" for k, v in result.best.items())
      + f"; {result.gradient_evals} gradients + {result.forward_throws} exact throws, {result.wall_time:.0f} s")
health = gradient_health(result)
print(f"raw gradient norms: median {health['median']:.3g}, max {health['max']:.3g}; exploding (> {EXPLODING:g}) "
      f"on {health['starts']['exploding']} of {health['starts']['n']} starts")
after = simulate(Throw.from_degrees(**result.best))

# %%
fig = plt.figure(figsize=(15, 6))
grid = fig.add_gridspec(2, 3, height_ratios=[2.2, 1])
plot_throw(before, ax=(fig.add_subplot(grid[0, 0]), fig.add_subplot(grid[1, 0])))
plot_throw(after, ax=(fig.add_subplot(grid[0, 1]), fig.add_subplot(grid[1, 1])))
hist = fig.add_subplot(grid[0, 2])
its = [h["iteration"] for h in ascent]
hist.plot(its, first, "C0-o", ms=3, label="from the poor throw")
hist.plot([h["iteration"] for h in result.history], [h["best"] for h in result.history], "C3-",
          label="best of all starts (last point: after the polish)")
hist.set(xlabel="iteration", ylabel="bounces (exact simulation)", title="gradient search")
hist.legend(fontsize=8)
norm = fig.add_subplot(grid[1, 2])
with_grad = [h for h in ascent if h.get("grad_norm")]
norm.semilogy([h["iteration"] for h in with_grad],
              [[float("nan") if v is None else v for v in h["grad_norm"]] for h in with_grad], ".-", lw=0.6, ms=3)
norm.axhline(EXPLODING, color="C3", ls="--", lw=1)
norm.set(xlabel="iteration", ylabel="|gradient| per start", title=f"raw gradient norms (dashed: {EXPLODING:g}, exploding)")
for ax in fig.axes[:4] + fig.axes[5:]:
    ax.title.set_fontsize(7)
fig.tight_layout()
path = RUN.figure("optimize_throw.png")
fig.savefig(path, dpi=110)
RUN.done(path)
