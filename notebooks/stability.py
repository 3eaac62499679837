# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---

# %% [markdown]
# # Where the methods fail
#
# (1) the stone's contact time step: beyond which the integrator creates energy in a contact, the tilt held,
# and (1b) a light, thin stone free to turn, with each integrator;
# (2) the water's time step: growth of ripples around the derived bound √3/2 · l/√(gH);
# (3) gradients against the horizon: the derivatives of the default throw's x after n steps (the
# distance, once the throw has ended within the n steps) with respect to its speed, tilt, attack and
# spin, each in its own unit, as the rollout grows over many bounces, and the spread of the smooth bounce count's gradient over random
# throws of the human box — its tail grows exponentially, the rollout being chaotic; (4) the smooth bounce count's width against the spread of its gradient;
# (5) float32: where single precision fails — the smooth clipping's cancellation and the gradient
# over long rollouts.
# The library's guards are marked: `SimConfig` caps `dt` at 0.01 s, `WaterGrid` refuses a water
# step beyond the bound, `optimize` clips gradients to norm 1 and zeroes non-finite ones.
#
# `python notebooks/stability.py` (full) or `JAXSKIP_QUICK=1 python notebooks/stability.py`; figures go to
# `JAXSKIP_NOTEBOOK_OUT` (default `notebooks/figures/`). Run time on the 2-core development machine
# (2026-12-08, with section 1b): full ~7.5 min, quick ~55 s (wall time; load moves it).

# %%
import dataclasses
import jax
import jax.numpy as jnp
import matplotlib.pyplot as plt
import numpy as np

from jaxskip.notebook import notebook_mode

RUN = notebook_mode("stability", here=globals().get("__file__"))  # no __file__ in a Jupyter kernel
QUICK = RUN.quick

from jaxskip import SimConfig, Throw, paper_stone, quaternion, rigid_stone, rollout, water_params  # noqa: E402
from jaxskip.clipping import immersed_areas  # noqa: E402
from jaxskip.forces import world_triangles  # noqa: E402
from jaxskip.simulate import contact_step_bound, initial_state  # noqa: E402
from jaxskip.water import WaterGrid, run_water, stable_dt, still_water  # noqa: E402
from optimize import make_objective  # noqa: E402

stone = rigid_stone(paper_stone(), density=2650.0)
water = water_params()

# %% [markdown]
# ## 1. The contact time step
# The fastest throw of the human box (12 m/s) and of the supported range (50 m/s), tilt held,
# 5° attack: the stone's speed after its first contact must not exceed its speed before it.
# "Fails" = energy gained, or a non-finite state. This is the paper stone at 2650 kg/m³ with its tilt
# held: a free stone, a lighter or a thinner one fails at shorter steps, where the water swings its
# tilt faster than the step resolves. `contact_step_bound` (`from jaxskip.simulate import contact_step_bound`) estimates that step
# (`simulate` warns beyond it; docs/model.md, "Stability of the contact step"), printed below for this stone.

# %%
dts = np.array([2.5e-4, 1e-3, 4e-3]) if QUICK else np.geomspace(1e-4, 8e-3, 14)
gain = {}
for speed in ((50.0,) if QUICK else (12.0, 50.0)):
    for integrator in (("euler",) if QUICK else ("euler", "rk4")):
        g = []
        for dt in dts:
            cfg = SimConfig(record=True, attitude="fixed", integrator=integrator, dt=float(dt),
                            max_flight_step=max(0.02, float(dt)), max_steps=400, duration=10.0)
            _, tr, rec = jax.jit(lambda t, c=cfg: rollout(c, t, stone, water))(
                Throw.from_degrees(speed=speed, tilt=20.0, attack=5.0, spin=20.0))
            v = np.linalg.norm(np.diff(np.asarray(rec.position), axis=0), axis=1) / np.maximum(
                np.diff(np.asarray(rec.time)), 1e-30)
            t = np.asarray(rec.time)[1:]
            out = t > float(tr.t_end[0]) if np.isfinite(float(tr.t_end[0])) else np.zeros_like(t, bool)
            after = v[out][0] if out.any() else np.nan
            g.append(after / speed if np.isfinite(after) else np.inf)
        gain[(speed, integrator)] = np.array(g)
        bad = dts[np.asarray(g) > 1.0]
        print(f"{speed:4.0f} m/s, {integrator:<5}: speed out/in = {np.round(g, 3).tolist()}; "
              f"first failing dt: {bad.min() if bad.size else 'none'} s")
fail = [dts[gain[(50.0, i)] > 1.0].min() if (gain[(50.0, i)] > 1.0).any() else np.inf for i in ("euler",)]
print(f"default dt 2.5e-4 s is {fail[0] / 2.5e-4:.1f}x inside the euler failure step at 50 m/s")
print("the free stone's contact-step estimate (contact_step_bound): "
      + ", ".join(f"{contact_step_bound(stone, water, v) * 1e3:.3g} ms at {v:g} m/s" for v in (12.0, 50.0)))

# %% [markdown]
# ## 1b. The free stone's contact step: Euler against RK4
# A light, thin stone (a 5 cm disk 0.5 mm thick at 500 kg/m³) thrown at 40 m/s, free to turn: the water swings
# its tilt at ω_θ, and `contact_step_bound` (1/ω_θ) is the estimate of the longest stable step. Peak mechanical
# energy of random throws (tilt 5–45°, attack 0–20°, spin 0–40 rev/s) against the same throw at an eighth of the
# estimate: Euler pumps the stone's wobble well inside the estimate, RK4 adds at most a few per cent up to it;
# hence the warning's `STABLE_FRACTION` (a quarter for Euler, the whole for RK4).

# %%
import warnings  # noqa: E402

from jaxskip import disk, simulate, steps_for  # noqa: E402
from jaxskip.simulate import STABLE_FRACTION  # noqa: E402

with warnings.catch_warnings():
    warnings.simplefilter("ignore")          # (lighter than water: no buoyancy in the force laws, warned of)
    thin = rigid_stone(disk(0.05, 0.0005), density=500.0)
thin_bound = contact_step_bound(thin, water, 40.0)
ratios = np.array([0.25, 1.0] if QUICK else [0.25, 0.5, 0.7, 1.0])
n_thin = 3 if QUICK else 8
rng = np.random.default_rng(0)
thin_throws = [dict(speed=40.0, tilt=float(a), attack=float(b), spin=float(c)) for a, b, c in
               zip(rng.uniform(5, 45, n_thin), rng.uniform(0, 20, n_thin), rng.uniform(0, 40, n_thin))]


def thin_peaks(r, integrator, duration=0.3):
    """Peak mechanical energy [J] of each thin-disk throw at dt = r * thin_bound."""
    dt = float(r * thin_bound)
    cfg = SimConfig(dt=dt, duration=duration, max_steps=steps_for(duration, dt), integrator=integrator)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")      # (the stability warning this section calibrates)
        return np.array([simulate(Throw.from_degrees(**t), thin, config=cfg).energy()["total"].max()
                         for t in thin_throws])


energy_rise = {}
for integrator in ("euler", "rk4"):
    ref = thin_peaks(0.125, integrator)
    energy_rise[integrator] = np.array([thin_peaks(r, integrator) / ref - 1.0 for r in ratios])   # (R, n)
    print(f"thin disk at 40 m/s, {integrator:<5}: peak energy over the reference's at dt / estimate = "
          + ", ".join(f"{r:g}: median {100 * np.median(e):+.1f} %, max {100 * e.max():+.1f} %"
                      for r, e in zip(ratios, energy_rise[integrator]))
          + f"; warned beyond {STABLE_FRACTION[integrator]:g} of the estimate ({thin_bound * 1e3:.3g} ms)")

# %% [markdown]
# ## 2. The water's time step

# %%
bound = stable_dt(0.01, 0.05)
factors = [0.5, 0.9, 0.99, 1.01, 1.05, 1.2]
noise = 1e-6 * np.random.default_rng(0).standard_normal((32, 32))
growth = []
for fct in factors:
    grid = WaterGrid(shape=(32, 32), spacing=0.01, depth=0.05)
    object.__setattr__(grid, "dt", fct * bound)      # past the guard, to show what it guards
    s = run_water(grid, still_water(grid, grid.depth + noise), 2000)
    growth.append(float(jnp.max(jnp.abs(s.height - grid.depth))) / np.abs(noise).max())
print("ripple growth after the run at dt/bound = " + ", ".join(f"{f}: {g:.3g}" for f, g in zip(factors, growth)))

# %% [markdown]
# ## 3. Gradient norm against the horizon

# %%
horizons = [600] if QUICK else [100, 200, 400, 800, 1600, 3200]
FIELDS = ("speed", "tilt", "attack", "spin")
grads64 = {}
for n in horizons:
    cfg = SimConfig(record=False, max_steps=n, duration=100.0)
    g = jax.jit(jax.grad(lambda t, c=cfg: rollout(c, t, stone, water)[0].position[0]))(Throw.from_degrees())
    grads64[n] = np.array([float(getattr(g, k)) for k in FIELDS])
norms = [float(np.linalg.norm(grads64[n])) for n in horizons]
# (the norm mixes units: m per m/s, m per rad, m per rad, m per rad/s; printed for the record, charted per component)
print("|d x_n / d throw| (norm over speed, tilt, attack, spin in SI) vs steps n: "
      + ", ".join(f"{n}: {v:.3g}" for n, v in zip(horizons, norms)))
print("d x_n / d (speed [m/s], tilt [rad], attack [rad], spin [rad/s]) vs steps n: "
      + "; ".join(f"{n}: " + ", ".join(f"{v:+.3g}" for v in grads64[n]) for n in horizons))

# The smooth bounce count's gradient over random throws of the human box, in the search's
# coordinates (optimize.gradient_search): its percentiles against the horizon.
from optimize import EXPLODING, make_box  # noqa: E402

box = make_box()
rng = np.random.default_rng(11)
n_random = 16 if QUICK else 128
u_random = jnp.asarray(box.from_user({k: rng.uniform(lo, hi, n_random) for k, lo, hi in box.searched}))
chaos_horizons = [400] if QUICK else [100, 200, 400, 800, 1600, 3200, 12000]   # (quick: one compile)
chaos = []
for n in chaos_horizons:
    f = make_objective("bounces", SimConfig(max_steps=n), stone, water)
    g = np.asarray(jax.jit(lambda u, f=f: jax.lax.map(jax.grad(lambda ui: f(box.to_throw(ui))), u))(u_random))
    chaos.append(np.percentile(np.linalg.norm(g, axis=1), [50, 90, 99]))
chaos = np.array(chaos)
print(f"smooth count, |gradient| per unit u over {n_random} random throws, p50/p90/p99 vs steps: "
      + "; ".join(f"{n}: " + "/".join(f"{v:.3g}" for v in row) for n, row in zip(chaos_horizons, chaos)))

# %% [markdown]
# ## 4. The smooth bounce count: width against gradient spread
# d(smooth count)/d(speed) of the default throw at 16 speeds 5 mm/s apart (8.000–8.075 m/s), 1500
# steps, for widths from 0.05 to 1 mm. The expectation was that a narrow width follows the true
# count's steps (spiky gradients) and a wide one smooths them out (and biases the count). Measured
# (full mode, 2026-12-07), it does not: the spread is 215, 137, 312, 728 and 587 per m/s at
# 0.05, 0.1, 0.2, 0.5 and 1 mm — smallest at 0.1 mm, largest at the two widest — and the mean is
# −41, −26, −82, −10 and +215 per m/s: it flips sign, and every mean is smaller than its spread. Over
# a whole throw the smooth count's gradient is as chaotic as the rollout it differentiates
# (section 3), whatever the width; the count's trend in speed is not read from one width's gradient.

# %%
speeds = 8.0 + 0.005 * np.arange(16 if not QUICK else 6)
widths = [2e-4] if QUICK else [5e-5, 1e-4, 2e-4, 5e-4, 1e-3]
spread = []
cfg = SimConfig(record=True, max_steps=1500)
for w in widths:
    f = make_objective("bounces", cfg, stone, water, width=w)
    gfun = jax.jit(jax.grad(lambda v, f=f: f(dataclasses.replace(Throw.from_degrees(), speed=v))))
    gs = np.array([float(gfun(jnp.asarray(v))) for v in speeds])
    spread.append(float(np.std(gs)))
    print(f"width {w:g} m: d(count)/d(speed) mean {gs.mean():+.3g}, std {gs.std():.3g} per m/s")

# %% [markdown]
# ## 5. float32 failure modes
# (a) Smooth clipping computes the wet area as a difference of two depth integrals divided by the
# ramp width, $S_\kappa = \kappa [D(w/2) - D(-w/2)]$: it converges to the exact area as the
# sharpness $\kappa$ grows, until the difference cancels to round-off. The paper stone at 20°
# tilt, its centre 1.7 mm above the water, 1.234 m downrange: relative error of the summed wet area
# against exact clipping. (b) The gradient of (3), computed in float32, against float64.

# %%
s0 = initial_state(Throw.from_degrees(tilt=20.0), stone)
tri, _ = world_triangles(stone, s0.position.at[2].set(0.0017), quaternion.to_matrix(s0.orientation))
tri = tri + jnp.array([1.234, 0.0, 0.0])
exact_area = float(jnp.sum(immersed_areas(tri, jnp.zeros(tri.shape[:2]))[0] * stone.areas))
kappas = np.geomspace(1e2, 1e9, 15)
clip_err = {}
for name, dtype in (("float64", jnp.float64), ("float32", jnp.float32)):
    t32, a32 = tri.astype(dtype), stone.areas.astype(dtype)
    clip_err[name] = np.array([
        abs(float(jnp.sum(immersed_areas(t32, jnp.zeros(t32.shape[:2], dtype), float(k))[0] * a32)) / exact_area - 1)
        for k in kappas])
    best = kappas[np.argmin(clip_err[name])]
    print(f"smooth clipping, {name}: area error at kappa = 1e2, 1e4, 1e6, 1e8 /m: "
          + ", ".join(f"{e:.1e}" for e in clip_err[name][[0, 4, 8, 12]]) + f"; smallest at kappa {best:.0e} /m")

horizons32 = [] if QUICK else horizons   # (quick mode, for CI: no float32 gradient compile; the full run has it)
jax.config.update("jax_enable_x64", False)
grads32 = []
for n in horizons32:
    cfg = SimConfig(record=False, max_steps=n, duration=100.0)
    st32 = jax.tree_util.tree_map(lambda a: jnp.asarray(a, jnp.float32), stone)
    w32 = jax.tree_util.tree_map(lambda a: jnp.asarray(a, jnp.float32), water)
    th32 = jax.tree_util.tree_map(lambda a: jnp.asarray(a, jnp.float32), Throw.from_degrees())
    g = jax.jit(jax.grad(lambda t, c=cfg: rollout(c, t, st32, w32)[0].position[0]))(th32)
    grads32.append(np.array([float(getattr(g, k)) for k in FIELDS]))
jax.config.update("jax_enable_x64", True)
grad_err = [float(np.linalg.norm(a - grads64[n]) / np.linalg.norm(grads64[n])) for a, n in zip(grads32, horizons32)]
print("float32 gradient relative error vs steps: " + (", ".join(f"{n}: {e:.2g}" for n, e in zip(horizons32, grad_err))
                                                      or "not computed in quick mode"))

# %%
from matplotlib.ticker import NullFormatter  # noqa: E402


def few_points_note(a, n):
    """A note in panel ``a`` when it holds fewer than 2 points (quick mode: its axis is auto-scaled)."""
    if n < 2:
        a.text(0.5, 0.94, f"quick mode: {'one point' if n else 'not computed'}", transform=a.transAxes, ha="center", va="top", fontsize=8,
               color="0.35", bbox=dict(boxstyle="round", fc="white", ec="0.7"))


CAP = 3.0  # panel (1): speed ratios above this (or non-finite) are drawn at the cap as upward triangles
fig, axes = plt.subplots(2, 4, figsize=(21, 8.5))
ax = list(axes.ravel())
thin_ax = ax.pop(1)   # (1b) beside (1)
ax[-1].set_axis_off()
for k, ((speed, integrator), g) in enumerate(gain.items()):
    off = ~(g <= CAP)   # above the cap, or non-finite
    line, = ax[0].semilogx(dts, np.where(off, np.nan, g), "o-", label=f"{speed:g} m/s, {integrator}")
    if off.any():   # (series off scale at the same dt side by side, 4 % apart, not on top of each other)
        ax[0].semilogx(dts[off] * 1.04 ** (k - 1.5), np.full(off.sum(), CAP), "^", color=line.get_color(), ms=8)
if any((~(g <= CAP)).any() for g in gain.values()):
    ax[0].plot([], [], "^", color="0.4", ms=9, ls="none", label=f"≥ {CAP:g} (off scale)")
ax[0].axhline(1.0, color="k", lw=0.8)
ax[0].axvline(2.5e-4, color="C3", ls="--", label="default dt")
ax[0].set_xlim(min(dts.min(), 1e-4) / 1.3, dts.max() * 1.3)   # at least two labelled decades
ax[0].set_ylim(top=CAP * 1.04)
ax[0].xaxis.set_minor_formatter(NullFormatter())
ax[0].set(xlabel="contact dt [s]", ylabel="speed out / in (first contact)", title="(1) stone time step")
ax[0].legend(fontsize=7)
for integrator, color in (("euler", "C0"), ("rk4", "C1")):
    e = 100 * energy_rise[integrator]
    thin_ax.plot(ratios, np.median(e, axis=1), "o-", color=color, label=f"{integrator}: median over {n_thin} throws")
    thin_ax.plot(ratios, e.max(axis=1), "v--", color=color, label=f"{integrator}: largest")
    thin_ax.axvline(STABLE_FRACTION[integrator], color=color, ls=":", lw=1.2,
                    label=f"{integrator}: warned beyond {STABLE_FRACTION[integrator]:g} (STABLE_FRACTION)")
thin_ax.axhline(0.0, color="k", lw=0.8)
thin_ax.set(xlabel="contact dt / contact_step_bound", ylabel="peak energy above the reference's [%]",
            title=f"(1b) free thin disk at 40 m/s: energy the step adds\n(reference: dt = 1/8 of the estimate, "
                  f"{thin_bound * 1e3:.3g} ms)")
thin_ax.legend(fontsize=7)
few_points_note(thin_ax, len(ratios))
ax[1].semilogy(factors, growth, "o-")
ax[1].axvline(1.0, color="C3", ls="--", label="bound (refused beyond)")
ax[1].set(xlabel="dt / bound", ylabel="ripple growth", title="(2) water time step")
ax[1].legend(fontsize=7)
UNITS = {"speed": "s (m per m/s)", "tilt": "m/rad", "attack": "m/rad", "spin": "m per rad/s"}
for k, marker, color in zip(FIELDS, "osD^", ("C0", "C1", "C2", "C9")):   # (red: the percentiles)
    ax[2].loglog(horizons, np.maximum(np.abs([grads64[n][FIELDS.index(k)] for n in horizons]), 1e-17),
                 marker + "-", color=color, ms=4, lw=0.9, label=f"default throw: |d x_n / d {k}| [{UNITS[k]}]")
for j, (q, style) in enumerate(((50, ":"), (90, "--"), (99, "-"))):
    ax[2].loglog(chaos_horizons, np.maximum(chaos[:, j], 1e-17), "o" + style, color="C3",
                 label=f"smooth count, {q}th percentile over {n_random} random throws [per unit u]")
ax[2].axhline(EXPLODING, color="C3", lw=0.6, alpha=0.5,
              label=f"'exploding' beyond {EXPLODING:g} (optimize.EXPLODING, gradient_health)")
ax[2].set(xlabel="rollout steps n", ylabel="|gradient| (units in the legend)",
          title="(3) gradient vs horizon: the tail explodes\n(x_n: the stone's x after n steps)")
lo, hi = ax[2].get_ylim()
ax[2].set_ylim(lo, hi * (hi / lo) ** 0.6)   # the data in the lower ~60 %, the legend above
ax[2].legend(fontsize=6, loc="upper left")
ax[3].semilogx(widths, spread, "o-")
ax[3].axvline(2e-4, color="C3", ls="--", label="default width")
ax[3].set(xlabel="width [m]", ylabel="std of d(count)/d(speed) [per m/s]", title="(4) surrogate width")
ax[3].legend(fontsize=7, loc="upper right")
few_points_note(ax[3], len(widths))
for name, e in clip_err.items():
    ax[4].loglog(kappas, np.maximum(e, 1e-17), "o-", label=name)
ax[4].axvspan(2e3, 2e4, color="C2", alpha=0.15,
              label="kappa of the two smooth-clipping variants\nin speed_vs_accuracy.py (library default: exact)")
ax[4].set(xlabel="sharpness kappa [1/m]", ylabel="relative wet-area error vs exact",
          title="(5a) smooth clipping: convergence, then cancellation")
ax[4].legend(fontsize=7)
ax[5].semilogy(horizons32, np.maximum(grad_err, 1e-17), "o-")
ax[5].set(xlabel="rollout steps", ylabel="|g32 - g64| / |g64|", title="(5b) float32 gradient vs float64")
few_points_note(ax[5], len(horizons32))
fig.tight_layout()
path = RUN.figure("stability.png")
fig.savefig(path, dpi=110)
RUN.done(path)
