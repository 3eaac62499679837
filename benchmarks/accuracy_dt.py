"""How the contact step ``dt`` moves the answers: the evidence behind ``jaxskip.simulate.ACCURATE_DT``.

    PYTHONPATH=. python benchmarks/accuracy_dt.py [--throws 128] [--seed 5]

Random throws of the human box (speed 3-12 m/s, tilt 5-45 deg, attack 0-30 deg, spin 5-20 rev/s),
float64, each simulated to completion (``simulate_batch``, ``max_steps = steps_for(5 s, dt)``) at a
reference dt of 0.125 ms and at 0.25 / 0.5 / 1 / 2 / 5 / 10 ms. Printed per dt: the share of
throws with the reference's bounce count (single counts are chaotic, so this stays well below 100 %
at any dt), the mean count, the median relative error of the distance and of the first contact's
duration. ~30 s on the 2-core development machine.
"""

from __future__ import annotations

import argparse
import os
import sys
import warnings

sys.path.insert(0, os.path.join(os.path.dirname(__file__), ".."))

import jax  # noqa: E402
import numpy as np  # noqa: E402

jax.config.update("jax_enable_x64", True)

from jaxskip import SimConfig, simulate_batch, steps_for  # noqa: E402
from optimize import make_box  # noqa: E402

REFERENCE_DT = 1.25e-4
DTS = (2.5e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2)


def run(throws, dt):
    """(bounces, distance [m], first contact's duration [s]) of every throw at contact step ``dt`` [s]."""
    r = simulate_batch(throws, "paper", config=SimConfig(dt=dt, max_steps=steps_for(5.0, dt), record=False))
    first = np.asarray(r.tracker.t_end)[:, 0] - np.asarray(r.tracker.t_start)[:, 0]
    return r.bounces, r.distance, first


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--throws", type=int, default=128)
    ap.add_argument("--seed", type=int, default=5)
    args = ap.parse_args(argv)
    box = make_box({"speed": (3, 12), "tilt": (5, 45), "attack": (0, 30), "spin": (5, 20)})
    rng = np.random.default_rng(args.seed)
    values = {name: rng.uniform(lo, hi, args.throws) for name, lo, hi in box.searched}
    throws = box.throws_from_user(values)
    ref_n, ref_d, ref_c = run(throws, REFERENCE_DT)
    print(f"{args.throws} random throws; reference dt {REFERENCE_DT * 1e3:g} ms: mean count {ref_n.mean():.2f}")
    print("dt [ms]  same count  mean count  distance error (median)  first contact duration error (median)")
    for dt in DTS:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the AccuracyWarning above 1 ms is what this script measures
            n, d, c = run(throws, dt)
        ok = np.isfinite(c) & np.isfinite(ref_c)
        dist = np.median(np.abs(d - ref_d) / np.maximum(ref_d, 1e-9))
        dur = np.median(np.abs(c[ok] - ref_c[ok]) / ref_c[ok])
        print(f"{dt * 1e3:7.2f}  {np.mean(n == ref_n):10.0%}  {n.mean():10.2f}  {dist:23.1%}  {dur:38.1%}")


if __name__ == "__main__":
    main()
