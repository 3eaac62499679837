# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---

# %% [markdown]
# # The magic angle: Clanet, Hersen & Bocquet's three figures
#
# Source: C. Clanet, F. Hersen, L. Bocquet, *Secrets of successful stone-skipping*, Nature 427:29
# (2004); `docs/physics.md` §4. Their aluminium disk (R = 2.5 cm, 2.75 mm), a catapult at 65 rev/s,
# impact angle β = 20°, and three figures, redrawn here from the model: (a) the minimal speed for a
# bounce against tilt, (b) the bounce domain in the (tilt, attack) plane at 3.5 m/s, (c) the contact
# time against tilt. The sweeps are `optimize.sweep` (batched bisection, the same code as `jaxskip
# sweep`); the model's minimum is also located between grid points, by a finer sweep and a parabola.
# Compared: Bocquet's law with the tilt held (the library's reference), the free 6-DoF body at
# 65 rev/s, and the seed paper's law.
#
# What Clanet et al. found: U_min lowest near 20° of tilt (the "magic angle"; ≈ 2.5 m/s there), no
# bounce beyond ≈ 45°, the widest range of attack angles near 20°, the contact time shortest near 20°.
# What the model finds (full mode, 2026-12-07; the last cell prints it beside Clanet's, point by
# point): with the tilt held U_min is lowest at 14.0° (1.745 m/s, 30.2 % below Clanet's 2.5 m/s: just
# outside the 30 % asked for); the disk still bounces at 50° (from 6.32 m/s) and, free at 65 rev/s,
# at 55° (from 6.42 m/s); the domain is widest (7 of 13 attack angles) at 10°, 15° and 20° alike; and
# the contact time (c) is shortest at the lowest tilt swept, 5° (16.8 ms), rising steadily to 55 ms at
# 35° — not shortest near 20°.
#
# `python notebooks/magic_angle.py` (full) or `JAXSKIP_QUICK=1 python notebooks/magic_angle.py`; figures
# go to `JAXSKIP_NOTEBOOK_OUT` (default `notebooks/figures/`). Run time on the 2-core development
# machine (2026-12-07): full ~25–75 s, quick ~10 s (wall time; load moves it).

# %%
import jax
import jax.numpy as jnp
import matplotlib.pyplot as plt
import numpy as np

from jaxskip.notebook import notebook_mode

RUN = notebook_mode("magic_angle", here=globals().get("__file__"))  # no __file__ in a Jupyter kernel
QUICK = RUN.quick

from jaxskip import ForceModel, SimConfig, Throw, clanet_disk, rigid_stone, rollout, water_params  # noqa: E402
from optimize.sweep import make_spec, run_sweep  # noqa: E402

tilts = (10.0, 20.0, 40.0, 50.0) if QUICK else tuple(np.arange(5.0, 61.0, 5.0))
iterations = 5 if QUICK else 8

# %% [markdown]
# ## (a) U_min(tilt) at β = 20°

# %%
umin = {}
for attitude in ("fixed", "free"):
    r = run_sweep(make_spec("umin", tilts=tilts, attacks=(20.0,), speed_range=(0.5, 8.0), iterations=iterations,
                            attitude=attitude))
    umin[attitude] = np.array([np.nan if u is None else u for u in r["umin"]], float)
    if attitude == "fixed":
        coarse = r
    print(f"{attitude:<5} (Bocquet law): U_min = " + ", ".join(f"{t:g}°: {u:.2f}" for t, u in zip(tilts,
                                                                                               umin[attitude]))
          + (f" m/s; lowest at {r['best_tilt']:g}° ({r['best_umin']:.2f} m/s)" if not r["tied_tilts"] else
             f" m/s; lowest at {', '.join(f'{t:g}' for t in r['tied_tilts'])}° (a tie at {r['best_umin']:.2f} m/s)"))

# The magic angle between grid points (tilt held): a finer sweep around the coarse minimum, and the
# vertex of the parabola through its lowest point and that point's neighbours.
step = 2.0 if QUICK else 1.0
fine_tilts = tuple(coarse["best_tilt"] + step * np.arange(-4, 5))
fine = run_sweep(make_spec("umin", tilts=fine_tilts, attacks=(20.0,), speed_range=(0.5, 8.0),
                           iterations=8 if QUICK else 12, attitude="fixed"))
if fine["best_tilt_fit"] is None:  # the finer sweep's lowest point at its edge: report the grid point
    fine["best_tilt_fit"], fine["best_umin_fit"] = fine["best_tilt"], fine["best_umin"]
print(f"fixed, every {step:g}° from {fine_tilts[0]:g}° to {fine_tilts[-1]:g}°: lowest at {fine['best_tilt']:g}° "
      f"({fine['best_umin']:.3f} m/s); between grid points {fine['best_tilt_fit']:.1f}° "
      f"({fine['best_umin_fit']:.3f} m/s; Clanet ≈ 20°, ≈ 2.5 m/s)")

# The seed paper's law, tilt held: the lowest speed of a grid that bounces.
disk = rigid_stone(clanet_disk(), density=2700.0)
seed_cfg = SimConfig(record=False, attitude="fixed", force=ForceModel(law="seed"))
seed_water = water_params("seed")
speeds = np.linspace(0.5, 8.0, 16 if QUICK else 61)
T, S = np.meshgrid(np.asarray(tilts), speeds, indexing="ij")
throws = Throw.from_degrees(speed=jnp.asarray(S.ravel()), tilt=jnp.asarray(T.ravel()), attack=20.0, spin=65.0)
_, tr, _ = jax.jit(jax.vmap(lambda t: rollout(seed_cfg, t, disk, seed_water)))(throws)
hit = np.asarray(tr.bounces).reshape(T.shape) > 0
umin["seed"] = np.array([speeds[np.argmax(h)] if h.any() else np.nan for h in hit])
print("seed law (fixed): U_min = " + ", ".join(f"{t:g}°: {u:.2f}" for t, u in zip(tilts, umin["seed"])) + " m/s")

# %% [markdown]
# ## (b) The bounce domain at 3.5 m/s and (c) the contact time

# %%
d_tilts = (10.0, 20.0, 30.0, 45.0) if QUICK else tuple(np.arange(5.0, 61.0, 5.0))
d_attacks = (5.0, 20.0, 35.0, 50.0) if QUICK else tuple(np.arange(0.0, 61.0, 5.0))
dom = run_sweep(make_spec("domain", tilts=d_tilts, attacks=d_attacks, speed=3.5))
B = np.asarray(dom["bounces"])
Tc = np.asarray([[np.nan if v is None else v for v in row] for row in dom["first_contact_time"]], float)
span = (B > 0).sum(axis=1)                     # attack angles that bounce, per tilt
widest = ", ".join(f"{t:g}" for t, n in zip(d_tilts, span) if n == span.max())   # every tilt that ties
j20 = int(np.argmin(np.abs(np.asarray(d_attacks) - 20.0)))
shortest = d_tilts[int(np.nanargmin(Tc[:, j20]))] if np.isfinite(Tc[:, j20]).any() else float("nan")
print(f"domain at 3.5 m/s: widest range of attack angles ({span.max()} of {len(d_attacks)}) at tilt {widest}°; "
      f"shortest first contact at attack {d_attacks[j20]:g}°: tilt {shortest:g}°")

# %%
fig, ax = plt.subplots(1, 3, figsize=(16, 4.2))
# A coarse U_min is the top of its bisection's final bracket: the true value lies in (U_min - res, U_min].
res = coarse["resolution"]
top_speed = coarse["spec"]["speed_range"][1]   # (the seed law's grid ends there too)
for key, style, text in (("fixed", "o-", "Bocquet law, tilt held"),
                         ("free", "s--", "Bocquet law, free body at 65 rev/s"),
                         ("seed", "^:", f"seed law, tilt held (speeds every {speeds[1] - speeds[0]:.3g} m/s)")):
    line, = ax[0].plot(tilts, umin[key], style, label=text)
    if key != "seed":
        ax[0].fill_between(tilts, umin[key] - res, umin[key], color=line.get_color(), alpha=0.2, lw=0)
    none = np.isnan(umin[key])   # no bounce up to the top of the speed range
    # (the curves' crosses sit at one height: each a little apart, or the last drawn hides the others)
    lift = {"fixed": 0.0, "free": 0.35, "seed": 0.7}[key]
    ax[0].plot(np.asarray(tilts)[none], np.full(none.sum(), top_speed + lift), "x", color=line.get_color(), ms=8)
    if key == "free":
        ax[0].fill_between([], [], [], color="0.5", alpha=0.3, lw=0,
                           label=f"shaded: bisection bracket (U_min − {res:.2g}, U_min]")
if any(np.isnan(u).any() for u in umin.values()):
    ax[0].plot([], [], "x", color="0.4", ms=8, ls="none", label=f"no bounce up to {top_speed:g} m/s")
ax[0].plot([fine["best_tilt_fit"]], [fine["best_umin_fit"]], "*", color="C3", ms=10,
           label=f"minimum, tilt held: {fine['best_tilt_fit']:.1f}°, {fine['best_umin_fit']:.2f} m/s\n"
                 f"(finer sweep every {step:g}°, bracket {fine['resolution']:.2g} m/s)")
ax[0].axhline(2.5, color="0.6", ls="--", lw=0.8)
ax[0].axvline(45.0, color="0.7", lw=0.8, label="Clanet: no bounce beyond ≈ 45°")
ax[0].text(0.62, 2.45, "Clanet ≈ 2.5 m/s", transform=ax[0].get_yaxis_transform(), ha="center", va="top",
           fontsize=7, color="0.4")
top = top_speed if any(np.isnan(u).any() for u in umin.values()) else np.nanmax([np.nanmax(u) for u in umin.values()])
ax[0].set_ylim(0.0, 1.6 * top)   # headroom for the legend
ax[0].set(xlabel="tilt α [deg]", ylabel="U_min [m/s]", title="(a) minimal speed for a bounce, β = 20°")
ax[0].legend(fontsize=6.5, loc="upper left")
im = ax[1].pcolormesh(np.asarray(d_tilts), np.asarray(d_attacks), B.T, cmap="Blues", shading="nearest")
fig.colorbar(im, ax=ax[1], label="bounces")
ax[1].set(xlabel="tilt α (of the disk) [deg]", ylabel="attack at release [deg] (Clanet's β is at impact)",
          title="(b) bounce domain at 3.5 m/s")
ax[2].plot(d_tilts, Tc[:, j20] * 1e3, "o-")
dropped = ~np.isfinite(Tc[:, j20])
if dropped.any():   # a first contact that never ends (t_end NaN): the disk sinks in it
    why = ("the disk sinks in its first contact (no bounce)" if (B[dropped, j20] == 0).all()
           else "first contact unfinished")
    ax[2].text(0.97, 0.04, f"tilt {', '.join(f'{t:g}°' for t in np.asarray(d_tilts)[dropped])} not drawn: no contact "
               f"time,\n{why}", transform=ax[2].transAxes, ha="right", va="bottom", fontsize=7, color="0.3")
ax[2].set_xlim(min(d_tilts) - 2.5, max(d_tilts) + 2.5)
ax[2].set(xlabel="tilt α [deg]", ylabel="first contact [ms]",
          title=f"(c) contact time at 3.5 m/s, β = {d_attacks[j20]:g}°")
fig.tight_layout()
path = RUN.figure("magic_angle.png")
fig.savefig(path, dpi=110)
RUN.done(path)

# %% [markdown]
# ## The model against Clanet et al., point by point
# Clanet's figures as physics.md §4 quotes them; the model's from the sweeps above (tilt held unless
# said; "no bounce" means none up to the sweep's top speed).

# %%
def steepest(u):
    """The steepest swept tilt that bounces below the top speed, and its U_min."""
    ok = np.isfinite(u)
    return (np.asarray(tilts)[ok][-1], u[ok][-1]) if ok.any() else (float("nan"), float("nan"))


Tc20 = Tc[:, j20] * 1e3
finite = np.isfinite(Tc20)
rows_vs = [
    ("magic angle (lowest U_min)", f"{fine['best_tilt_fit']:.1f} deg", "~20 deg"),
    ("U_min at the magic angle", f"{fine['best_umin_fit']:.3f} m/s ({fine['best_umin_fit'] / 2.5 - 1:+.1%})",
     "~2.5 m/s"),
    ("steepest tilt that bounces, held", "{:g} deg (from {:.2f} m/s)".format(*steepest(umin["fixed"])),
     "~45 deg, none beyond"),
    ("steepest tilt that bounces, free", "{:g} deg (from {:.2f} m/s)".format(*steepest(umin["free"])),
     "~45 deg, none beyond"),
    ("widest bounce domain, 3.5 m/s", f"tilt {widest} deg ({span.max()} of {len(d_attacks)} attacks)", "~20 deg"),
    (f"shortest contact, 3.5 m/s, attack {d_attacks[j20]:g}", f"tilt {shortest:g} deg"
     + (f" ({np.nanmin(Tc20):.1f} ms)" if finite.any() else ""), "~20 deg"),
]
print(f"{'':<38} {'model':<40} Clanet et al.")
for what, model, clanet in rows_vs:
    print(f"{what:<38} {model:<40} {clanet}")
print(f"contact time at 3.5 m/s, attack {d_attacks[j20]:g} deg: "
      + ", ".join(f"{t:g} deg: {c:.1f} ms" for t, c in zip(d_tilts, Tc20) if np.isfinite(c)))
