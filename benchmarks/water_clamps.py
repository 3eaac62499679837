"""Compare the three volume clamps on a drying scene: volume error, deviation from the reference,
gradient quality. Prints the figures and writes a picture (default docs/clamps.png).

    PYTHONPATH=. python benchmarks/water_clamps.py [--out docs/clamps.png] [--steps 2000]

The scene: 5 mm of water with a 15 mm mound on a 32 x 32 grid of 1 cm columns, closed
boundaries, so the troughs run dry and the clamp acts. Gradient quality: the derivative of the
height at two probes after the run with respect to the mound's height, by reverse mode, against
central differences (h = 1e-8), over a sweep of mound heights: smooth curves and agreement mean
usable gradients.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

import jax  # noqa: E402
import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

jax.config.update("jax_enable_x64", True)

from jaxskip.water import WaterGrid, make_water_step, still_water  # noqa: E402

VARIANTS = [("reference", dict(clamp="reference")), ("zero (seed eq. 4)", dict(clamp="zero")),
            ("smooth k=5", dict(clamp="smooth", sharpness=5.0)), ("smooth k=20", dict(clamp="smooth", sharpness=20.0)),
            ("smooth k=50 (default)", dict(clamp="smooth", sharpness=50.0)),
            ("smooth k=200", dict(clamp="smooth", sharpness=200.0))]


def scene(grid, amplitude):
    X, Y = grid.column_centres()
    return grid.depth + amplitude * jnp.exp(-((X - 0.155) ** 2 + (Y - 0.155) ** 2) / (2 * 0.03 ** 2))


def history(grid, steps, amplitude=0.015):
    """Heights every step's total volume and the final field."""
    step = make_water_step(grid)
    p = jnp.zeros(grid.shape)

    @jax.jit
    def go(h0):
        def body(c, _):
            c = step(c, p)
            return c, (jnp.sum(c.height) * grid.spacing ** 2, c.height)
        return jax.lax.scan(body, still_water(grid, h0), None, length=steps)[1]

    return go(scene(grid, amplitude))


def probe_fn(grid, steps):
    step = make_water_step(grid)
    p = jnp.zeros(grid.shape)

    def f(a):
        s = jax.lax.scan(jax.checkpoint(lambda c, _: (step(c, p), None)), still_water(grid, scene(grid, a)), None,
                         length=steps)[0]
        return s.height[5, 7] + s.height[25, 3]
    return jax.jit(f), jax.jit(jax.grad(f))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "docs", "clamps.png"))
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--grad-steps", type=int, default=500)
    args = ap.parse_args(argv)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    base = WaterGrid(shape=(32, 32), spacing=0.01, depth=0.005)
    t = base.time_step * np.arange(1, args.steps + 1)
    runs = {}
    for label, kw in VARIANTS:
        vol, heights = history(dataclasses.replace(base, **kw), args.steps)
        runs[label] = (np.asarray(vol), np.asarray(heights))
    v0 = runs["reference"][0][0]
    ref_h = runs["reference"][1]
    fig, axes = plt.subplots(1, 3, figsize=(14, 4))
    colour = {label: f"C{i}" for i, (label, _) in enumerate(VARIANTS)}
    print(f"drying scene, {args.steps} steps of {base.time_step * 1e3:.2f} ms:")
    for label, (vol, h) in runs.items():
        verr = np.abs(vol - v0) / v0
        dev = np.abs(h - ref_h).max(axis=(1, 2)) / base.depth
        axes[0].semilogy(t, np.maximum(verr, 1e-17), label=label, color=colour[label])
        if label != "reference":
            axes[1].semilogy(t, np.maximum(dev, 1e-17), label=label, color=colour[label])
        print(f"  {label:<22} volume error {verr.max():.1e}; max deviation from reference {dev.max():.1e} x depth; "
              f"lowest column {h.min() * 1e3:+.2e} mm")
    axes[0].set_title("relative volume error")
    axes[0].set_ylabel("|V - V0| / V0 [-]")
    axes[1].set_title("deviation from the reference clamp")
    axes[1].set_ylabel("max |h - h_reference| / depth [-]")
    for ax in axes[:2]:
        ax.set_xlabel("time [s]")
    axes[0].legend(fontsize=7)

    amps = np.linspace(0.010, 0.016, 25)
    print(f"gradient d(probe)/d(mound) after {args.grad_steps} steps, AD vs central differences (h = 1e-8):")
    for label, kw in VARIANTS:
        if label.startswith("zero"):
            continue
        f, g = probe_fn(dataclasses.replace(base, **kw), args.grad_steps)
        ad = np.array([float(g(a)) for a in amps])
        fd = np.array([(float(f(a + 1e-8)) - float(f(a - 1e-8))) / 2e-8 for a in amps])
        err = np.abs(ad - fd) / np.maximum(np.abs(fd), 1e-3)
        rough = np.abs(np.diff(ad, 2)).mean() / max(np.abs(ad).mean(), 1e-12)
        axes[2].plot(amps * 1e3, ad, label=label, color=colour[label])
        print(f"  {label:<22} median |AD - FD| / |FD| = {np.median(err):.1e}; roughness (mean |2nd diff| / mean) "
              f"{rough:.2f}")
    axes[2].set_ylabel("d(h1 + h2) / d(mound height) [-]")
    axes[2].set_title(f"gradient after {args.grad_steps} steps (h1, h2: two columns)")
    axes[2].set_xlabel("mound height [mm]")
    axes[2].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(f"picture: {args.out}")


if __name__ == "__main__":
    main()
