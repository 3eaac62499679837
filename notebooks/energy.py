# ---
# jupyter:
#   jupytext:
#     formats: py:percent
# ---

# %% [markdown]
# # Where the water adds energy: the force laws' energy budget
#
# Only the water can take energy from a skipping stone, so its mechanical energy — translation
# ½ m|v|², rotation ½ ωᵀIω about the centre of mass, height m g z — should never rise. This notebook
# follows it (`ThrowResult.energy()`) through the default throw (the paper stone, 8 m/s, tilt 20°,
# attack 5°, 20 rev/s) under each way the force law can take the stone's velocity
# (`ForceModel(velocity=...)`; docs/model.md, "The default free stone gains energy"):
#
# * `"body"` (the default): every face sees the centre of mass's velocity, so the lift's torque does
#   not feel how fast each side of the stone moves into the water, and it can pump a wobble;
# * `"local"`: each face's own v + ω × r (the spin's in-plane speed then lifts the stone);
# * `"passive"`: the pressure from the centre of mass's speed, the lift on the part of each wet face whose
#   own velocity moves into the water, the friction at the centre of mass — the water's power is never positive;
# * the tilt held (`attitude="fixed"`, the high-spin limit): no rotation to pump.
#
# Run: `python notebooks/energy.py` (quick mode, `JAXSKIP_QUICK=1`, is the same run: four throws); figures go to
# `JAXSKIP_NOTEBOOK_OUT` (default `notebooks/figures/`). Run time on the 2-core development machine
# (2026-12-07): full ~10 s, quick the same run (wall time; load moves it).

# %%
import matplotlib.pyplot as plt
import numpy as np

from jaxskip.notebook import notebook_mode

RUN = notebook_mode("energy", here=globals().get("__file__"))  # no __file__ in a Jupyter kernel

from jaxskip import SimConfig, Throw, simulate  # noqa: E402
from jaxskip.forces import ForceModel  # noqa: E402

throw = Throw.from_degrees()
cases = {
    'velocity="body" (default)': SimConfig(),
    'velocity="local"': SimConfig(force=ForceModel(velocity="local")),
    'velocity="passive"': SimConfig(force=ForceModel(velocity="passive")),
    'tilt held (attitude="fixed")': SimConfig(attitude="fixed"),
}
runs = {name: simulate(throw, "paper", config=config) for name, config in cases.items()}
energy = {name: r.energy() for name, r in runs.items()}
for name, r in runs.items():
    total = energy[name]["total"]
    rise = np.max(np.diff(total))
    print(f"{name}: {r.bounces} bounces over {r.distance:.2f} m ({r.outcome}); energy {total[0]:.2f} J at release, "
          f"peak {total.max():.2f} J, {total[-1]:.2f} J at the end; largest rise in a step {rise:.1e} J")

# %% [markdown]
# Left: the total against time, each throw to its end. Right: where the default law's gain goes —
# nearly all of it into the rotation, a wobble of the face that grows contact by contact.

# %%
fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 4.8))
for name, r in runs.items():
    ax.plot(r.trajectory["time"], energy[name]["total"], label=f"{name}: {r.bounces} bounces, {r.distance:.1f} m")
ax.axhline(energy['velocity="body" (default)']["total"][0], color="k", lw=0.7, ls=":", label="at release")
ax.set(xlabel="time [s]", ylabel="mechanical energy of the stone [J]",
       title="default throw: the stone's energy under each velocity option")
ax.legend(fontsize=8)
body = runs['velocity="body" (default)']
for part in ("translation", "rotation", "height"):
    bx.plot(body.trajectory["time"], energy['velocity="body" (default)'][part], label=part)
for c in body.contacts:
    bx.axvspan(c.t_start, c.t_end, color="C0", alpha=0.08, lw=0)
bx.set(xlabel="time [s]", ylabel="energy [J]",
       title='velocity="body": its parts (shaded: contacts)')
bx.legend(fontsize=8)
fig.tight_layout()
path = RUN.figure("energy.png")
fig.savefig(path, dpi=110)
RUN.done(path)
