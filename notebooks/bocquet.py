# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---

# %% [markdown]
# # Bocquet's stone skipping, reproduced with the mesh simulator
#
# Sources: L. Bocquet, *The physics of stone skipping*, Am. J. Phys. 71:150 (2003),
# arXiv:physics/0210015; C. Clanet, F. Hersen, L. Bocquet, *Secrets of successful
# stone-skipping*, Nature 427:29 (2004); the project's `docs/physics.md` §3–4.
#
# The full simulator (a triangle mesh, per-triangle lift and friction, `attitude="fixed"` = the
# high-spin limit) is set beside Bocquet's reduced model (`jaxskip.bocquet`: a flat plate, one ODE
# per contact). Same coefficients in both (C_l = 1, C_f = 0.3, the library's calibrated defaults),
# Clanet's aluminium disk. The laws differ in one respect: the reduced plate feels V_x² (Bocquet's
# equations), the mesh |V|², with friction ∝ |V||V_t|, so their friction ratios differ a little
# (μ = C̃/C = 0.503 at this notebook's tilt, 10°, in the reduced model by construction — 0.745 at 20°;
# the mesh's is what its impulse says).
#
# Run top to bottom: `python notebooks/bocquet.py` (full) or `JAXSKIP_QUICK=1 python
# notebooks/bocquet.py` (CI); `jupytext --to notebook notebooks/bocquet.py` makes a notebook. Figures
# go to `JAXSKIP_NOTEBOOK_OUT` (default `notebooks/figures/`). Run time on the 2-core development
# machine (2026-12-07): full ~30–40 s, quick ~20 s (wall time; load moves it).

# %%
import math
import jax
import jax.numpy as jnp
import matplotlib.pyplot as plt
import numpy as np

from jaxskip.notebook import notebook_mode

RUN = notebook_mode("bocquet", here=globals().get("__file__"))  # no __file__ in a Jupyter kernel
QUICK = RUN.quick

from jaxskip import ForceModel, SimConfig, Throw, clanet_disk, rigid_stone, rollout, water_params  # noqa: E402 (after the float64 switch)
from jaxskip.bocquet import ReducedStone, reduced_throw  # noqa: E402 (after the float64 switch)

disk = rigid_stone(clanet_disk(), density=2700.0)
water = water_params()
plate = ReducedStone("disk", 0.025, float(disk.mass))
coef = dict(c_lift=float(water.c_lift), c_friction=float(water.c_friction))
fixed = SimConfig(record=False, attitude="fixed")
mesh_batch = jax.jit(jax.vmap(lambda t: rollout(fixed, t, disk, water)))
print(f"Clanet disk: {float(disk.mass) * 1e3:.1f} g, R = {float(disk.radius) * 100:.2f} cm; C_l = {coef['c_lift']}, "
      f"C_f = {coef['c_friction']}")

# %% [markdown]
# ## 1. Bounce count against speed: N ∝ V² at grazing incidence
# While in contact the water's horizontal force is μ times its vertical one. Entered at grazing
# incidence (no vertical speed) a contact lasts a whole period of the immersed oscillation, the
# vertical impulse is just M g τ, and the contact costs μ M g L of kinetic energy, L = V τ its length
# (it does not depend on speed): the least any contact costs, hence Bocquet's count N ≈ V²/(2 μ g L)
# (physics.md §3; drawn in section 3b from the μ and length measured here). A contact entered faster
# lasts half a period, a length ℓ ≈ L/2 (section 2 measures ℓ), and each impact also loses μ·2v_z
# of speed, so the count grows more slowly than V². Two attack angles are run: 1° and 5°.

# %%
speeds = np.array([4.0, 6.0, 9.0, 12.0]) if QUICK else np.linspace(4.0, 14.0, 11)
tilt, attacks = 10.0, (1.0, 5.0)   # degrees here, at the notebook's edge; the library takes radians
counts = {}
for attack in attacks:
    throws = Throw.from_degrees(speed=jnp.asarray(speeds), tilt=tilt, attack=attack, spin=65.0)
    _, tr, _ = mesh_batch(throws)
    red = reduced_throw(jnp.asarray(speeds), np.radians(tilt), np.radians(attack), plate, max_contacts=256, **coef)
    counts[attack] = (np.asarray(tr.bounces), np.asarray(red.bounces))
    for name, n in zip(("mesh", "reduced"), counts[attack]):
        ok = n > 0
        slope = np.polyfit(np.log(speeds[ok]), np.log(n[ok]), 1)[0] if ok.sum() >= 2 else float("nan")
        print(f"attack {attack:>3} deg, {name:<7}: N = {n.tolist()}  log-log slope {slope:.2f}")

# %% [markdown]
# ## 2. Collision length and time
# The contact lasts τ ∝ 1/V, so its length V τ is the same at every speed. These first contacts, at 1°
# of attack, are entered at a vertical speed well above g/ω and last half an immersed oscillation:
# V τ here is ℓ, Bocquet's collision length (printed "l = V tau" below), half the grazing
# contact's L of section 1 (section 3b).

# %%
throws = Throw.from_degrees(speed=jnp.asarray(speeds), tilt=tilt, attack=1.0, spin=65.0)
_, tr, _ = mesh_batch(throws)
tau_mesh = np.asarray(tr.t_end[:, 0] - tr.t_start[:, 0])
red = reduced_throw(jnp.asarray(speeds), np.radians(tilt), np.radians(1.0), plate, max_contacts=4, **coef)
tau_red = np.asarray(red.contact_time[:, 0])
for v, a, b in zip(speeds, tau_mesh, tau_red):
    print(f"V = {v:5.2f} m/s: first contact {a * 1e3:5.2f} ms (mesh), {b * 1e3:5.2f} ms (reduced); "
          f"collision length l = V tau = {v * a * 100:.2f} cm")

# %% [markdown]
# ## 3. The friction ratio μ = C̃/C from the simulated impulse
# Over a contact the water's horizontal impulse over its vertical impulse should be
# (C_l sin θ + C_f cos θ)/(C_l cos θ − C_f sin θ).

# %%
one = SimConfig(attitude="fixed", max_steps=400)
_, tr1, rec = jax.jit(lambda t: rollout(one, t, disk, water))(Throw.from_degrees(speed=8.0, tilt=tilt, attack=1.0,
                                                                                     spin=65.0))
t = np.asarray(rec.time)
F = np.asarray(rec.force)
dt = np.diff(t, append=t[-1])
first = (t >= float(tr1.t_start[0])) & (t < float(tr1.t_end[0]))
Jx, Jz = (F[first, 0] * dt[first]).sum(), (F[first, 2] * dt[first]).sum()
th = math.radians(tilt)
mu_theory = (coef["c_lift"] * math.sin(th) + coef["c_friction"] * math.cos(th)) / (
    coef["c_lift"] * math.cos(th) - coef["c_friction"] * math.sin(th))
i8 = int(np.argmin(np.abs(speeds - 8.0)))   # the reduced throw nearest the mesh throw's 8 m/s (mu does not vary with V)
mu_red = -float(red.impulse_x[i8, 0]) / float(red.impulse_z[i8, 0])
# (the reduced model's ratio is C~/C at every step, by construction: a check of its bookkeeping, not a measurement)
print(f"mu = C~/C = {mu_theory:.3f}; measured from the mesh impulse {-Jx / Jz:.3f}, reduced model {mu_red:.3f} "
      "(C~/C by construction)")

# %% [markdown]
# ## 3b. Bocquet's absolute count against the simulated ones
# physics.md §3: each collision costs about μ M g L, so N ≈ V²/(2 μ g L), L the distance the stone
# travels in a contact that costs μ M g L: a grazing one (no vertical speed at entry), where the
# water's vertical impulse is just M g τ. Section 2's 1° contacts are not grazing: entered at a
# vertical speed u ≫ g/ω they last half an immersed oscillation, ℓ = V τ (Bocquet's collision
# length, `jaxskip.bocquet.collision_length`), while a grazing contact lasts a whole one, 2ℓ
# (`jaxskip.bocquet`'s docstring). The mesh disk cannot show that here: released at the water with
# no vertical speed it sinks in its first contact (printed below). The reduced plate can: its
# contacts at 0.05° of attack are measured against its 1° ones. So L = 2ℓ, with ℓ the median V τ
# of the mesh's 1° contacts, and μ from the mesh impulse (section 3); V is the release speed. The
# formula is the count if every contact cost only μ M g L and the stone skipped down to rest.
#
# Full mode, 2026-12-07 (printed below): ℓ = 6.45 cm (median V τ at 1°); the reduced plate's 0.05°
# contacts last 2.10× its 1° ones; the mesh disk released at the water sinks in its first contact at
# every speed (0 bounces). With μ = 0.498 and L = 2 × 6.45 = 12.9 cm the formula gives 13 bounces at
# 4 m/s and 156 at 14 m/s; at 1° of attack the reduced model makes 5 and 53 (2.9× fewer at 14 m/s) and
# the mesh 1 and 31 (5.0× fewer). The growth with V is near Bocquet's (log-log slopes 1.8 and 2.6;
# the dotted ∝ V² line in panel 1 is only a slope guide, pinned to the reduced model's last point),
# the absolute count is not: the simulated contacts are not grazing (each lands with a vertical
# speed and pays μ·2v_z on top), and the formula counts contacts down to rest, while a simulated
# stone stops when it sinks.

# %%
mu_mesh = -Jx / Jz
ell = float(np.nanmedian(speeds * tau_mesh))   # [m] half an oscillation (a contact that never ends, NaN: left out)
red_graze = reduced_throw(jnp.asarray(speeds), np.radians(tilt), np.radians(0.05), plate, max_contacts=4, **coef)
graze_ratio = float(np.nanmedian(np.asarray(red_graze.contact_time[:, 0]) / tau_red))
_, tr_flat, _ = mesh_batch(Throw.from_degrees(speed=jnp.asarray(speeds), tilt=tilt, attack=0.0, spin=65.0, height=0.0))
L_bocquet = 2 * ell
n_bocquet = speeds ** 2 / (2 * mu_mesh * float(water.gravity) * L_bocquet)
print(f"collision length: median V tau of the mesh's 1 deg contacts {ell * 100:.2f} cm (half an oscillation); "
      f"reduced plate: contacts at 0.05 deg last {graze_ratio:.2f}x its 1 deg contacts (median); mesh released at "
      f"the water, attack 0: bounces {np.asarray(tr_flat.bounces).tolist()}, first contact ended in "
      f"{int(np.isfinite(np.asarray(tr_flat.t_end[:, 0])).sum())} of {len(speeds)}")
print(f"Bocquet N = V^2/(2 mu g L), mu = {mu_mesh:.3f} (mesh impulse), L = 2 x {ell * 100:.2f} = {L_bocquet * 100:.1f} cm "
      f"(grazing contact): N = {np.round(n_bocquet).astype(int).tolist()} at V = {speeds.tolist()} m/s; at {speeds[-1]:g} m/s "
      f"{n_bocquet[-1]:.0f} vs reduced {counts[1.0][1][-1]} ({n_bocquet[-1] / max(counts[1.0][1][-1], 1):.1f}x fewer), "
      f"mesh {counts[1.0][0][-1]} ({n_bocquet[-1] / max(counts[1.0][0][-1], 1):.1f}x fewer) at 1 deg of attack")

# %% [markdown]
# ## 4. The minimum speed for a bounce (Clanet's reference throw: tilt 20°, attack 20°)

# %%
grid_v = np.linspace(0.5, 5.0, 10 if QUICK else 46)
throws = Throw.from_degrees(speed=jnp.asarray(grid_v), tilt=20.0, attack=20.0, spin=65.0)
_, trm, _ = mesh_batch(throws)
rv = reduced_throw(jnp.asarray(grid_v), np.radians(20.0), np.radians(20.0), plate, max_contacts=8, **coef)
umin_mesh = grid_v[np.argmax(np.asarray(trm.bounces) > 0)]
umin_red = grid_v[np.argmax(np.asarray(rv.bounces) > 0)]
print(f"U_min: mesh {umin_mesh:.2f} m/s, reduced {umin_red:.2f} m/s (Clanet et al. measured about 2.5 m/s)")

# %% [markdown]
# ## 5. Spin: the free stone needs it to keep its tilt
# With the 6-DoF body (`attitude="free"`) spin keeps the tilt's *size*, but not its direction:
# the water's lift acts behind the centre of mass, and on a spinning disk that pitching torque
# turns into precession (gyroscopic), so the tilt's azimuth turns by ~1/spin per contact and the
# disk ends up banked sideways (it also curves). Measured on this disk at 8 m/s, the first contact
# turns it 105° at 50 rev/s, 55° at 100 and 14° at 400 (tests/test_dynamics.py). With the default force
# law (`velocity="body"`) the banked disk makes far more bounces than the held tilt at 65–200 rev/s (51, 75,
# 140 against 12), but those hops run on energy the water adds: each face's force is computed from the
# centre of mass's velocity, so it can push on a face that is moving away from the water and pump the
# wobble (docs/model.md, "The default free stone gains energy"; here 4.02 → 5.68 J at 200 rev/s). The passive law
# (`velocity="passive"`, which never adds energy) makes 1, 2, 3 bounces there, and both laws approach the
# fixed-tilt (high-spin) count that Bocquet's and Clanet's analyses assume only as the drift per contact
# vanishes (500 rev/s: 8 and 9 bounces, against 12 with the tilt held).

# %%
spins = np.array([0.0, 10.0, 40.0]) if QUICK else np.array([0.0, 5.0, 10.0, 20.0, 40.0, 65.0, 100.0, 200.0, 500.0])
free = SimConfig(record=False, attitude="free", max_steps=60000)   # 200 rev/s: ~140 bounces
passive = SimConfig(record=False, attitude="free", max_steps=60000, force=ForceModel(velocity="passive"))
spun = Throw.from_degrees(speed=8.0, tilt=tilt, attack=5.0, spin=jnp.asarray(spins))
_, trs, _ = jax.jit(jax.vmap(lambda t: rollout(free, t, disk, water)))(spun)
_, trp, _ = jax.jit(jax.vmap(lambda t: rollout(passive, t, disk, water)))(spun)
_, trf, _ = jax.jit(lambda t: rollout(fixed, t, disk, water))(Throw.from_degrees(speed=8.0, tilt=tilt, attack=5.0,
                                                                                   spin=65.0))
print("free-body bounces vs spin:", dict(zip(spins.tolist(), np.asarray(trs.bounces).tolist())),
      "\n  passive law:", dict(zip(spins.tolist(), np.asarray(trp.bounces).tolist())), f"; fixed tilt: {int(trf.bounces)}")

# %%
from matplotlib.ticker import LogLocator, MaxNLocator, NullFormatter, ScalarFormatter  # noqa: E402

fig, ax = plt.subplots(1, 4, figsize=(17, 4))
# (1) log axes show positive counts only; a zero count (no bounce) is a 'v' at the bottom edge.
zero_any = False
for attack, marker, color in zip(attacks, ("o", "s"), ("C0", "C1")):
    n_mesh, n_red = counts[attack]
    ax[0].loglog(speeds, np.where(n_mesh > 0, n_mesh, np.nan), marker, color=color, label=f"mesh, attack {attack:g}°")
    ax[0].loglog(speeds, np.where(n_red > 0, n_red, np.nan), "-", color=color, label=f"reduced, attack {attack:g}°")
    for n, fill in ((n_mesh, color), (n_red, "none")):
        zero = n == 0
        if zero.any():   # (x in data, y in axes coordinates: at the bottom edge)
            zero_any = True
            ax[0].plot(speeds[zero], np.full(zero.sum(), 0.03), "v", color=color, mfc=fill, ms=8,
                       transform=ax[0].get_xaxis_transform())
ax[0].loglog(speeds, counts[1.0][1][-1] * (speeds / speeds[-1]) ** 2, "k:",
             label="slope guide ∝ V² (through the reduced 1° count\nat the top speed; not a prediction)")
ax[0].loglog(speeds, n_bocquet, "k-", lw=1.5,
             label=f"Bocquet: N = V²/(2μgL), μ = {mu_mesh:.3f} (measured),\nL = 2 × {ell * 100:.2f} cm = grazing contact (§3b)")
if zero_any:
    ax[0].plot([], [], "v", color="0.4", ms=8, ls="none", label="no bounce, N = 0 (bottom edge; open: reduced)")
positive = np.concatenate([n[n > 0] for pair in counts.values() for n in pair] + [n_bocquet])
low = positive.min() / 1.6   # room for the zeros below the lowest count
ax[0].set_ylim(low, low * (positive.max() / low) ** (1 / 0.65))   # the data in the lower 65 %, the legend above
ax[0].xaxis.set_major_locator(MaxNLocator(integer=True))
for axis in (ax[0].xaxis, ax[0].yaxis):
    axis.set_major_formatter(ScalarFormatter())
    axis.set_minor_formatter(NullFormatter())
ax[0].yaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
ax[0].set(xlabel="speed [m/s]", ylabel="bounces", title=f"N vs V (tilt {tilt:g}°)")
ax[0].legend(fontsize=7, loc="upper left")
ax[1].plot(speeds, tau_mesh * 1e3, "o", label="mesh")
ax[1].plot(speeds, tau_red * 1e3, "-", label="reduced")
missing = ~np.isfinite(tau_mesh)
if missing.any():   # the first contact never ended (t_end NaN); these throws are section 1's at attack 1°
    why = ("the disk sinks in its first contact (0 bounces)" if (counts[1.0][0][missing] == 0).all()
           else "its first contact does not end")
    ax[1].text(0.97, 0.72, f"no mesh contact time at {', '.join(f'{v:g}' for v in speeds[missing])} m/s:\n{why}",
               transform=ax[1].transAxes, ha="right", va="top", fontsize=7, color="0.3")
ax[1].set(xlabel="speed [m/s]", ylabel="first contact [ms]", title="contact time ∝ 1/V")
ax[1].legend(fontsize=7)
ax[2].plot(grid_v, np.asarray(trm.bounces), "o", label="mesh")
ax[2].plot(grid_v, np.asarray(rv.bounces), "-", drawstyle="steps-mid", label="reduced")
ax[2].axvline(2.5, color="0.6", ls="--", label="Clanet ≈ 2.5 m/s")
ax[2].yaxis.set_major_locator(MaxNLocator(integer=True))
ax[2].set(xlabel="speed [m/s]", ylabel="bounces", title="minimum speed (tilt 20°, attack 20°)")
ax[2].legend(fontsize=7)
ax[3].plot(spins, np.asarray(trs.bounces), "o-", label="free body (default law: the water adds energy)")
ax[3].plot(spins, np.asarray(trp.bounces), "s-", label='free body, velocity="passive" (never adds energy)')
ax[3].axhline(int(trf.bounces), color="k", ls=":", label="tilt held (infinite-spin limit)")
ax[3].set_xscale("symlog", linthresh=10.0)
ax[3].set_xlim(0.0, 1.5 * spins.max())
ax[3].set_xticks([s for s in (0, 5, 10, 20, 40, 100, 200, 500) if s <= spins.max()])   # (the points' spins; symlog
ax[3].xaxis.set_major_formatter(ScalarFormatter())                                            # ticked 0, 10, 100 only)
ax[3].yaxis.set_major_locator(MaxNLocator(integer=True))
ax[3].set(xlabel="spin [rev/s]", ylabel="bounces", title="free disk vs spin (8 m/s): the tilt precesses")
ax[3].legend(fontsize=7, loc="upper left")
fig.tight_layout()
path = RUN.figure("bocquet.png")
fig.savefig(path, dpi=110)
RUN.done(path)
