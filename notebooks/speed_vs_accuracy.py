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
# and the mesh resolution — a batch of random throws in the human box (speed 3–12 m/s, tilt
# 5–45°, attack 0–30°, spin 0–20 rev/s) is run and compared with a converged reference (a 10×
# finer time step, RK4, float64; 5× in quick mode). Error: the share of the batch whose bounce count differs from
# the reference, and the median relative error of the first contact's duration. Cost: wall time
# per throw of the batched, compiled rollout (compile time excluded). The default
# configuration is marked.
#
# `python notebooks/speed_vs_accuracy.py` (full: 128 throws) or `JAXSKIP_QUICK=1 ...` (CI: 24).

# %%
import dataclasses
import os
import time

import jax
import jax.numpy as jnp
import matplotlib.pyplot as plt
import numpy as np

from jaxskip.notebook import notebook_mode

RUN = notebook_mode("speed_vs_accuracy", default_out=os.path.join(os.path.dirname(os.path.abspath(__file__)), "figures"))
QUICK = RUN.quick

from jaxskip import ForceModel, SimConfig, Throw, disk, paper_stone, rigid_stone, simulate_batch, water_params  # noqa: E402 (after the float64 switch)
N = 16 if QUICK else 128
rng = np.random.default_rng(1)
box = dict(speed=rng.uniform(3, 12, N), tilt=rng.uniform(5, 45, N), attack=rng.uniform(0, 30, N),
           spin=rng.uniform(0, 20, N))
water = water_params()
DEFAULT = SimConfig(record=False)


def run(config, stone, dtype=jnp.float64, timed=True):
    """Bounce counts, first contact durations and wall time per throw of one configuration.

    Runs the batch to completion with ``simulate_batch`` (finished throws stop costing), twice:
    the second call's wall time, compile excluded, is the cost."""
    cast = lambda a: jnp.asarray(a, dtype)  # noqa: E731
    throws = jax.tree_util.tree_map(cast, Throw.from_degrees(**box))
    st = jax.tree_util.tree_map(cast, stone)
    wt = jax.tree_util.tree_map(cast, water)
    if timed:
        simulate_batch(throws, st, water=wt, config=config, lanes=min(N, 64))
    t0 = time.perf_counter()
    r = simulate_batch(throws, st, water=wt, config=config, lanes=min(N, 64))
    wall = (time.perf_counter() - t0) / N
    return np.asarray(r.bounces), np.asarray(r.tracker.t_end[:, 0] - r.tracker.t_start[:, 0], float), wall


def compare(ref, got):
    agree = float(np.mean(ref[0] == got[0]))
    ok = np.isfinite(ref[1]) & np.isfinite(got[1]) & (ref[1] > 0)
    t_err = float(np.median(np.abs(got[1][ok] / ref[1][ok] - 1))) if ok.any() else float("nan")
    return 1.0 - agree, t_err


# %% [markdown]
# ## The paper's stone: time step, integrator, flight, clipping, precision

# %%
paper = rigid_stone(paper_stone(), density=2650.0)
ref_dt = 5e-5 if QUICK else 2.5e-5
ref_cfg = dataclasses.replace(DEFAULT, dt=ref_dt, integrator="rk4", max_steps=120_000, segment=500)
ref = run(ref_cfg, paper, timed=False)
print(f"reference (dt {ref_dt:g} s, rk4, float64): mean {ref[0].mean():.2f} bounces, {ref[2] * 1e3:.1f} ms per throw")
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
    miss, t_err = compare(ref, got)
    rows.append((label, got[2], miss, t_err))
    print(f"{label:<28} {got[2] * 1e3:7.2f} ms/throw; count differs on {miss:5.1%}; first contact error {t_err:.2%}")

# %% [markdown]
# ## Mesh resolution (a 5 cm, 12 mm disk from 32 to 256 triangles, against 512; its own reference)

# %%
# (a 2048-triangle reference did not finish in 20 minutes on the 2-core machine: 512 is the reference)
segs = (16,) if QUICK else (8, 16, 32, 64)
ref_disk = run(ref_cfg, rigid_stone(disk(0.05, 0.012, segments=64 if QUICK else 128), density=2650.0), timed=False)
for n in segs:
    stone = rigid_stone(disk(0.05, 0.012, segments=n), density=2650.0)
    got = run(DEFAULT, stone)
    miss, t_err = compare(ref_disk, got)
    label = f"disk, {int(stone.triangles.shape[0])} triangles"
    rows.append((label, got[2], miss, t_err))
    print(f"{label:<28} {got[2] * 1e3:7.2f} ms/throw; count differs on {miss:5.1%}; first contact error {t_err:.2%}")

# %% [markdown]
# ## The Pareto chart
# On the paper's stone, a configuration is on the front when no other is both cheaper and more
# accurate (error = share of counts that differ + first-contact error). The disk series (mesh
# resolution) has its own reference and is drawn beside the front, not on it.

# %%
paper_rows = [r for r in rows if not r[0].startswith("disk")]
disk_rows = [r for r in rows if r[0].startswith("disk")]
cost = np.array([r[1] for r in paper_rows])
err = np.array([r[2] + (r[3] if np.isfinite(r[3]) else 1.0) for r in paper_rows])
front = [i for i in range(len(cost)) if not any(cost[j] <= cost[i] and err[j] < err[i] for j in range(len(cost)))]
d = [r[0] for r in paper_rows].index("default (euler, dt 2.5e-4)")
best_err = min(err[i] for i in front if cost[i] <= cost[d])
gap = (err[d] - best_err) / max(best_err, 1e-12)
print(f"default on the front: {d in front}; its error {err[d]:.3f} vs the front's best at no more cost "
      f"{best_err:.3f} ({gap:+.0%}; criterion: within 10 %)")

fig, ax = plt.subplots(figsize=(9, 6))
ax.scatter(cost * 1e3, err, color="C0", label="paper stone: dt, integrator, flight, clipping, precision")
for i, r in enumerate(paper_rows):
    ax.annotate(r[0], (cost[i] * 1e3, err[i]), fontsize=7, xytext=(4, 3), textcoords="offset points")
order = sorted(front, key=lambda i: cost[i])
ax.plot(cost[order] * 1e3, err[order], "k--", lw=0.8, label="Pareto front")
ax.scatter([cost[d] * 1e3], [err[d]], s=160, facecolors="none", edgecolors="C3", lw=2, label="default")
dc = np.array([r[1] for r in disk_rows])
de = np.array([r[2] + (r[3] if np.isfinite(r[3]) else 1.0) for r in disk_rows])
ax.plot(dc * 1e3, de, "s-", color="C2", label="disk: mesh resolution (own reference)")
for r, c, e in zip(disk_rows, dc, de):
    ax.annotate(r[0].replace("disk, ", ""), (c * 1e3, e), fontsize=7, xytext=(4, -9), textcoords="offset points")
ax.set_xscale("log")
ax.set(xlabel="wall time per throw, batch to completion [ms]",
       ylabel="error: share of counts that differ + first-contact error",
       title=f"speed vs accuracy over {N} random throws (reference: dt {ref_dt:g} s, RK4, float64)")
ax.legend(fontsize=8)
fig.tight_layout()
path = RUN.figure("speed_vs_accuracy.png")
fig.savefig(path, dpi=110)
RUN.done(path)
