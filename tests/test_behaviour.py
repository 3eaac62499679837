"""Physical behaviour of whole throws (float64, default model unless stated)."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxskip import OUTCOMES, ForceModel, SimConfig, Throw, rollout, simulate


def stack(throws):
    return jax.tree_util.tree_map(lambda *a: jnp.stack(a), *throws)


def run_batch(config, throws, stone, water):
    s, tr = jax.jit(jax.vmap(lambda t: rollout(config, t, stone, water)[:2]))(stack(throws))
    return np.asarray(tr.bounces), [OUTCOMES[o] for o in np.asarray(tr.outcome)]


def test_default_throw_skips_at_least_five_times():
    result = simulate()
    assert result.bounces >= 5, result.bounces
    assert result.outcome == "sank"
    assert len(result.contacts) == result.n_contacts == result.bounces + 1
    starts = [c.t_start for c in result.contacts]
    assert starts == sorted(starts) and all(c.t_end >= c.t_start for c in result.contacts)


def test_high_spin_count_does_not_fall_with_speed(paper, water):
    """High-spin limit (tilt held): strictly monotone. Free body at Clanet's reference spin of
    65 rev/s: the mean over an ensemble of attack angles is monotone (measured 2026-12-06: 2 / 4 / 7 /
    59.25 / 67.5 at 4-12 m/s), single free throws are not: the late hops are chaotic, and attack 8 deg
    counts 2 / 6 / 3 / 54 / 44 (docs/model.md, "Known limits"). At 30-50 rev/s the free stone is not yet in the
    high-spin regime (measured: at 30 rev/s throws flip at 12 m/s and the mean dips)."""
    speeds = [4.0, 6.0, 8.0, 10.0, 12.0]
    fixed = SimConfig(record=False, attitude="fixed", max_steps=20000, duration=20.0)
    n, out = run_batch(fixed, [Throw.from_degrees(speed=v, tilt=20.0, attack=5.0, spin=0.0) for v in speeds],
                       paper, water)
    assert np.all(np.diff(n) > 0), n
    assert set(out) == {"sank"}

    free = SimConfig(record=False, max_steps=20000, duration=20.0)
    attacks = [4.0, 6.0, 8.0, 10.0]
    n, _ = run_batch(free, [Throw.from_degrees(speed=v, tilt=20.0, attack=a, spin=65.0)
                            for v in speeds for a in attacks], paper, water)
    mean = n.reshape(len(speeds), len(attacks)).mean(axis=1)
    assert np.all(np.diff(mean) >= 0), mean


def test_steep_tilt_does_not_skip_at_clanet_conditions(paper, water):
    """Clanet et al. 2004 (attack 20 deg, U ~ 3.5 m/s): no bounce beyond ~45 deg of tilt, where the same
    throw at 20 deg of tilt does bounce (the control: without it a model with no lift passed; 2 m/s, asserted
    before 2026-12-07, bounces at no tilt, free or held, so it tested nothing and is dropped)."""
    tilts, speeds = (20.0, 60.0, 70.0, 80.0), (3.5, 6.0)
    for attitude in ("free", "fixed"):
        config = SimConfig(record=False, max_steps=4000, attitude=attitude)
        throws = [Throw.from_degrees(speed=v, tilt=t, attack=20.0, spin=20.0) for t in tilts for v in speeds]
        n, _ = run_batch(config, throws, paper, water)
        n = np.asarray(n).reshape(len(tilts), len(speeds))
        assert np.all(n[0] >= 1) and np.all(n[1:] == 0), (attitude, n)


@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "Known miss: on a face in horizontal flow the coded Bocquet law's vertical force is "
    "1/2 rho V^2 S cos(tilt) (C_l - C_f sin(tilt)), upwards at every tilt below 90 deg (C_f < C_l; with "
    "physics.md's V^2 friction it would stay upwards to atan(C_l/C_f) = 73 deg), so at 10 m/s a stone "
    "tilted 60-70 deg still skips (measured: "
    "1-4 bounces at 5-10 deg attack, none at 20 deg). Clanet's ~45 deg limit was measured at 3.5 m/s and "
    "20 deg attack (at 2-5 deg attack the model's 60-70 deg stone bounces once even at 3.5 m/s)."))
def test_steep_tilt_does_not_skip_when_fast(paper, water):
    config = SimConfig(record=False, max_steps=4000)
    throws = [Throw.from_degrees(speed=10.0, tilt=t, attack=a, spin=20.0)
              for t in (60.0, 70.0) for a in (5.0, 10.0, 20.0)]
    n, _ = run_batch(config, throws, paper, water)
    assert np.all(n == 0), n


def test_spin_precesses_the_tilt_towards_its_own_side(paper):
    """The water's lift acts behind the centre of mass, and its torque turns a spinning stone's angular
    momentum sideways (gyroscopic precession): released leading edge up (tilt direction 0), the face
    leaves its first contact banked to the left when spun anticlockwise seen from above (spin > 0) and
    to the right when spun clockwise; with the tilt held it stays as thrown; a negative tilt is
    leading edge down (180 deg). Reported per contact (Contact.tilt_direction_start/_end). Measured:
    +77 / -78 deg at +20 / -20 rev/s."""
    turned = {}
    for spin in (20.0, -20.0):
        c = simulate(Throw.from_degrees(spin=spin), stone=paper).contacts[0]
        assert abs(c.tilt_direction_start) < 1e-9, c  # as released
        turned[spin] = math.degrees(c.tilt_direction_end)
    assert turned[20.0] > 45.0 and turned[-20.0] < -45.0, turned
    held = simulate(Throw.from_degrees(), stone=paper, config=SimConfig(attitude="fixed")).contacts
    assert len(held) > 5 and all(abs(d) < 1e-9 for c in held for d in (c.tilt_direction_start, c.tilt_direction_end)
                                 if math.isfinite(d)), held
    down = simulate(Throw.from_degrees(tilt=-10.0), stone=paper).contacts[0]
    assert abs(abs(down.tilt_direction_start) - math.pi) < 1e-9, down


def _spin_grid(paper, water):
    """Bounce counts and flips of 25 throws at 10 m/s (tilt 10-30 deg x attack 2-20 deg), each at 0 / 10 / 20 /
    40 rev/s: two (25, 4) arrays."""
    from jaxskip import simulate_batch

    tilts, attacks, spins = [10.0, 15.0, 20.0, 25.0, 30.0], [2.0, 5.0, 10.0, 15.0, 20.0], [0.0, 10.0, 20.0, 40.0]
    T, A, S = np.meshgrid(tilts, attacks, spins, indexing="ij")
    r = simulate_batch(Throw.from_degrees(speed=10.0, tilt=T.ravel(), attack=A.ravel(), spin=S.ravel()), paper,
                       water=water, config=SimConfig(record=False))
    return r.bounces.reshape(-1, len(spins)), (r.outcome_names == "flipped").reshape(-1, len(spins))


def test_spin_stabilises_a_fast_throw(paper, water):
    """At 10 m/s, over 25 throws (tilt 10-30 deg x attack 2-20 deg): without spin most stones flip, and
    every one flips or skips less than when spun at 20 or at 40 rev/s (the acceptance's wording); the mean
    count rises with spin and flipping stops by 40 rev/s. Measured: flipped 84 / 84 / 56 / 0 % and mean 2.1 /
    2.6 / 12.2 / 35.7 bounces at 0 / 10 / 20 / 40 rev/s — at 10-15 rev/s the model's stone flips as often as
    an unspun one (the first contact's torque tips it: docs/model.md, "Known limits"), it only skips a little
    more. The acceptance's wording is met whenever the unspun stone flips, whatever the spun one does (an
    audit, 2026-12-07: at 20 rev/s four spun stones flipped with no bounce and counted as stabilised), so the
    claim is also asserted strictly: the spun stone stops flipping where the unspun one flipped, or skips more.
    That holds for 25 of 25 throws at 40 rev/s, 21 at 20 rev/s and 8 at 10 rev/s (asserted as measured at 20;
    10 rev/s is the next test, a known miss)."""
    n, flipped = _spin_grid(paper, water)
    assert flipped[:, 0].mean() >= 0.5 and not flipped[:, -1].any(), flipped.mean(axis=0)
    better = flipped[:, :1] | (n[:, :1] < n[:, 1:])      # (25, 3): at 10, 20, 40 rev/s, the acceptance's wording
    assert np.all(better[:, 1:]), (n[:, 0], n[:, 2], n[:, 3])
    strictly = (flipped[:, :1] & ~flipped[:, 1:]) | (n[:, 1:] > n[:, :1])
    assert np.all(strictly[:, 2]) and strictly[:, 1].sum() >= 21, strictly.sum(axis=0)
    assert np.all(np.diff(n.mean(axis=0)) > 0), n.mean(axis=0)


@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "Known miss: at exactly 10 rev/s the acceptance's 'a stone without spin flips or skips less than the same "
    "throw with >= 10 rev/s' holds for 24 of the 25 throws (tilt 25 deg, attack 2 deg: 4 bounces unspun, 4 and a "
    "flip at 10 rev/s), and the spun stone does strictly better (stops flipping, or skips more) for only 8: at "
    "10-15 rev/s the model's stone flips as often as an unspun one (docs/model.md, 'Known limits')."))
def test_spin_of_10_rev_s_stabilises_every_fast_throw(paper, water):
    n, flipped = _spin_grid(paper, water)
    assert np.all(flipped[:, 0] | (n[:, 0] < n[:, 1])), (n[:, 0], n[:, 1])


def test_bocquet_count_grows_like_speed_squared(paper, water):
    """Bocquet 2003: each impact dissipates ~ mu M g L, so N ~ V^2 (grazing incidence, tilt held)."""
    config = SimConfig(record=False, attitude="fixed", max_steps=20000, duration=20.0,
                       force=ForceModel(law="bocquet"))
    speeds = np.array([5.0, 6.0, 7.0, 8.0, 10.0, 12.0])
    n, out = run_batch(config, [Throw.from_degrees(speed=v, tilt=20.0, attack=2.0, spin=0.0) for v in speeds],
                       paper, water)
    assert set(out) == {"sank"}
    slope = np.polyfit(np.log(speeds), np.log(n), 1)[0]
    assert abs(slope - 2.0) <= 0.3, (slope, n)


def test_dt_convergence_of_the_fixed_attitude_throw(paper, water):
    """Halving dt changes the range by < 1 % and the count by <= 1 (tilt held)."""
    res = []
    for dt in (2.5e-4, 1.25e-4):
        config = SimConfig(record=False, attitude="fixed", dt=dt, max_steps=int(8000 * 2.5e-4 / dt))
        s, tr, _ = jax.jit(lambda t: rollout(config, t, paper, water))(Throw.from_degrees())
        res.append((float(s.position[0]), int(tr.bounces)))
    assert abs(res[0][0] / res[1][0] - 1) < 0.01 and abs(res[0][1] - res[1][1]) <= 1, res


def test_default_step_budget_lets_a_fast_flat_throw_finish():
    """A fast, flat, spun throw planes for over 3 s of contact (more than the 12000 steps the budget
    once was): at the defaults it still ends on its own (sank), not by running out of steps; the
    default budget covers the whole ``duration`` in the water."""
    config = SimConfig()
    assert config.max_steps * config.dt >= config.duration
    r = simulate(Throw.from_degrees(speed=12.0, tilt=10.06, attack=0.0, spin=20.0))
    assert r.outcome != "step_limit" and r.steps > 12000 and r.final_time > 3.0, (r.outcome, r.steps, r.final_time)
