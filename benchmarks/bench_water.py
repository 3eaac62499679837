"""Height-field benchmark (issue 3): water steps/s, effective bandwidth, coupled throws vs real time,
and what the two-way coupling changes against flat water over a batch of throws.

    PYTHONPATH=. python benchmarks/bench_water.py            # all sections
    PYTHONPATH=. python benchmarks/bench_water.py --quick    # smaller batch, fewer repeats
    PYTHONPATH=. python benchmarks/bench_water.py --sections steps,throw --json out.json
    PYTHONPATH=. python benchmarks/bench_water.py --sections throw --float32   # the library's default precision

Sections:
  steps     water steps/s on 64^2, 128^2 and 256^2 grids for each clamp (compile time reported apart),
            and the effective memory bandwidth (bytes of state read and written per step / time)
            against a large-array copy measured in the same run and against the same working set
            streamed by the simplest step (at 64^2 and 128^2 it stays in cache, where the copy does
            not: the second is the ceiling there); every time is the best of a few runs;
  throw     the default throw, two-way coupled, with a 64^2 and a 128^2 window: wall time against
            simulated time (goal: >= 20x faster than real time with 128^2);
  coupling  a batch of random throws in the human box, flat water vs coupled: how often the bounce
            count agrees, its mean change, and the first contact's duration.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

import jax  # noqa: E402
import jax.numpy as jnp  # noqa: E402
import numpy as np  # noqa: E402

from jaxskip import SimConfig, Throw, paper_stone, rigid_stone, rollout, water_params  # noqa: E402
from jaxskip.coupled import default_window, rollout_coupled  # noqa: E402
from jaxskip.water import WaterGrid, make_water_step, still_water  # noqa: E402


def _best(fn, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        jax.block_until_ready(fn())
        times.append(time.perf_counter() - t0)
    return min(times)


def _compiled(fn, *args):
    """``(compiled, seconds)``: ``fn`` traced, lowered and compiled for ``args`` ahead of time, so that
    the compile time holds no run and the timed calls hold no compile."""
    t0 = time.perf_counter()
    compiled = jax.jit(fn).lower(*args).compile()
    return compiled, time.perf_counter() - t0


def section_steps(quick):
    out = {}
    item = jnp.zeros(()).dtype.itemsize               # 8 bytes (float64), 4 with --float32
    n_copy = 64 * 2 ** 20 // item                     # a 64 MiB array
    # Read and written in place (the input donated to the output), as a water step's state is: a fresh
    # 64 MiB output each call would time the allocation and its first-touch page faults too (2.3-2.6
    # against 15-17 GB/s measured in session 22; earlier sessions' "% of the copy" used that slow copy).
    update = jax.jit(lambda a: a * 0.999 + 1e-9, donate_argnums=0)
    box = [jax.block_until_ready(update(jnp.ones(n_copy)))]

    def in_place():
        box[0] = update(box[0])
        return box[0]

    t = _best(in_place, 3 if quick else 10)
    copy_bw = 2 * box[0].nbytes / t
    out["copy_GBps"] = copy_bw / 1e9
    print(f"large-array copy, in place (64 MiB read + 64 MiB written): {copy_bw / 1e9:.1f} GB/s")
    for n in (64, 128, 256):
        # The same working set streamed by the simplest step (read, scale, write five n^2 arrays) in a
        # scan of the same length: the bandwidth a water step could reach at this size (cache-resident
        # at 64^2 and 128^2, unlike the 64 MiB copy).
        steps = (200 if n == 256 else 1000) // (4 if quick else 1)
        arrays = tuple(jnp.ones((n, n)) for _ in range(5))
        stream = jax.jit(lambda s: jax.lax.scan(lambda c, _: (tuple(a * 0.999 + 1e-9 for a in c), None), s, None,
                                                length=steps)[0])
        jax.block_until_ready(stream(arrays))
        t_stream = _best(lambda: stream(arrays), 2 if quick else 5) / steps
        same_bw = 2 * 5 * n * n * item / t_stream
        out[f"{n}_same_size_GBps"] = same_bw / 1e9
        print(f"  {n:>3}^2 same-size stream (5 arrays read + written per step, in a scan): {same_bw / 1e9:.2f} GB/s "
              f"({t_stream * 1e6:.0f} us/step)")
        for clamp in ("zero", "reference", "smooth"):
            grid = WaterGrid(shape=(n, n), spacing=0.01, depth=0.02, clamp=clamp, boundary="sponge")
            X, Y = grid.column_centres()
            c = 0.01 * (n - 1) / 2
            # A ripple that never dries a column: the clamp is tested for and skipped, as in most steps.
            s0 = still_water(grid, grid.depth + 1e-3 * jnp.exp(-((X - c) ** 2 + (Y - c) ** 2) / 1e-3))
            step = make_water_step(grid)
            # The pressure is an argument, as in run_water and the coupling: a constant zero would be folded
            # away by XLA (the step then measured ~30 % faster than any real use of it, session 17).
            p = jnp.zeros(grid.shape)
            run, compile_s = _compiled(lambda s, p: jax.lax.scan(lambda c, _: (step(c, p), None), s, None,
                                                                 length=steps)[0], s0, p)
            repeats = 2 if quick else 5
            t = _best(lambda: run(s0, p), repeats) / steps
            # State read and written each step (heights and four pipe arrays: 5 n^2 values each way) and the
            # pressure read (n^2; left out before 2026-12-07, a review: bandwidths then ~10 % low).
            nbytes = (2 * 5 + 1) * n * n * item
            bw = nbytes / t
            out[f"{n}_{clamp}"] = {"steps_per_s": 1 / t, "us_per_step": t * 1e6, "compile_s": compile_s,
                                   "GBps": bw / 1e9, "share_of_copy": bw / copy_bw, "share_of_same_size": bw / same_bw}
            print(f"  {n:>3}^2 {clamp:<9}: {1 / t:8.0f} steps/s ({t * 1e6:7.0f} us/step, best of {repeats} scans; "
                  f"compile {compile_s:.1f} s); "
                  f"{bw / 1e9:.2f} GB/s = {bw / copy_bw:.0%} of the 64 MiB copy, {bw / same_bw:.0%} of the same-size "
                  f"stream (goal >= 50 %)")
    return out


def section_throw(quick):
    out = {}
    stone = rigid_stone(paper_stone(), density=2650.0)
    water = water_params()
    config = SimConfig(record=False)
    throw = Throw.from_degrees()
    flat = jax.jit(lambda t: rollout(config, t, stone, water))
    jax.block_until_ready(flat(throw))
    t_flat = _best(lambda: flat(throw), 5)
    s, tr, _ = flat(throw)
    print(f"flat water: {int(tr.bounces)} bounces, {float(s.time):.2f} s simulated, {t_flat * 1e3:.1f} ms wall")
    out["flat"] = {"bounces": int(tr.bounces), "sim_s": float(s.time), "wall_s": t_flat}
    for n in (64, 128):
        grid = dataclasses.replace(default_window(), shape=(n, n))
        f, compile_s = _compiled(lambda t, g=grid: rollout_coupled(config, g, t, stone, water), throw)
        wall = _best(lambda: f(throw), 2 if quick else 3)
        s, tr, _, fld = f(throw)
        sim = float(s.time)
        out[str(n)] = {"bounces": int(tr.bounces), "sim_s": sim, "wall_s": wall, "compile_s": compile_s,
                       "faster_than_real_time": sim / wall}
        print(f"coupled, {n}^2 window: {int(tr.bounces)} bounces, {sim:.2f} s simulated in {wall:.2f} s wall "
              f"(best of {2 if quick else 3} runs) "
              f"(compile {compile_s:.1f} s): {sim / wall:.1f}x real time (goal >= 20x at 128^2)")
    return out


def section_coupling(quick):
    stone = rigid_stone(paper_stone(), density=2650.0)
    water = water_params()
    config = SimConfig(record=False)
    n = 16 if quick else 64
    rng = np.random.default_rng(0)
    throws = Throw.from_degrees(speed=rng.uniform(3, 12, n), tilt=rng.uniform(5, 45, n),
                                attack=rng.uniform(0, 30, n), spin=rng.uniform(0, 20, n))
    flat = jax.jit(jax.vmap(lambda t: rollout(config, t, stone, water)))
    _, tf, _ = flat(throws)
    out = {"throws": n}
    for label, grid in (("coupled 64^2 smooth", default_window()),):
        # lax.map, not vmap: one throw at a time keeps the rollout's skip of out-of-play segments
        # (under vmap every throw pays for all max_steps: the 64-throw run took over 15 minutes).
        coupled, compile_s = _compiled(
            lambda ts, g=grid: jax.lax.map(lambda t: rollout_coupled(config, g, t, stone, water), ts), throws)
        t0 = time.perf_counter()
        _, tc, _, _ = jax.block_until_ready(coupled(throws))
        wall = time.perf_counter() - t0
        bf, bc = np.asarray(tf.bounces), np.asarray(tc.bounces)
        d1f = np.asarray(tf.t_end[:, 0] - tf.t_start[:, 0])
        d1c = np.asarray(tc.t_end[:, 0] - tc.t_start[:, 0])
        ok = np.isfinite(d1f) & np.isfinite(d1c)
        r = {"agree": float(np.mean(bf == bc)), "mean_flat": float(bf.mean()), "mean_coupled": float(bc.mean()),
             "mean_abs_change": float(np.mean(np.abs(bf - bc))),
             "first_contact_ms_flat": float(np.median(d1f[ok]) * 1e3) if ok.any() else None,
             "first_contact_ms_coupled": float(np.median(d1c[ok]) * 1e3) if ok.any() else None, "wall_s": wall,
             "compile_s": compile_s}
        out[label] = r
        print(f"{label} vs flat over {n} random throws: same count {r['agree']:.0%}; mean bounces "
              f"{r['mean_flat']:.2f} flat, {r['mean_coupled']:.2f} coupled (mean |change| {r['mean_abs_change']:.2f}); "
              f"median first contact {r['first_contact_ms_flat']:.1f} ms flat, "
              f"{r['first_contact_ms_coupled']:.1f} ms coupled; {wall:.0f} s wall (compile {compile_s:.0f} s apart)")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--sections", default="steps,throw,coupling")
    ap.add_argument("--json", metavar="PATH")
    ap.add_argument("--float32", action="store_true",
                    help="compute in float32 (JAX's and the library's default precision) instead of float64 (the CLI's and the tests')")
    args = ap.parse_args(argv)
    jax.config.update("jax_enable_x64", not args.float32)
    print(f"precision: {'float32' if args.float32 else 'float64'}")
    sections = {"steps": section_steps, "throw": section_throw, "coupling": section_coupling}
    out = {}
    for name in args.sections.split(","):
        if name not in sections:
            ap.error(f"--sections: unknown section {name!r}; choose from {', '.join(sections)}")
        print(f"== {name}", flush=True)
        out[name] = sections[name](args.quick)
    out["precision"] = "float32" if args.float32 else "float64"
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(out, fh, indent=1)


if __name__ == "__main__":
    main()
