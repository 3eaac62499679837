"""Reverse-mode gradients through contact against central finite differences (float64)."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxskip import ForceModel, SimConfig, Throw, rollout
from jaxskip.forces import water_force
from jaxskip import quaternion as quat

FIELDS = ("speed", "tilt", "attack", "spin")


def fd_check(f, base, rtol, h=1e-7, value=None):
    """Reverse-mode gradient of ``f`` against central differences; ``value``: an already compiled
    evaluation of ``f`` to difference (saves a compile, which dominates these tests' time)."""
    grad = jax.jit(jax.grad(f))(base)
    f = jax.jit(f) if value is None else value
    for name in FIELDS:
        v = float(getattr(base, name))
        plus = float(f(dataclasses.replace(base, **{name: jnp.asarray(v + h)})))
        minus = float(f(dataclasses.replace(base, **{name: jnp.asarray(v - h)})))
        fd = (plus - minus) / (2 * h)
        ad = float(getattr(grad, name))
        assert np.isfinite(ad)
        assert abs(ad - fd) <= rtol * max(abs(fd), 1e-3), (name, ad, fd)


@pytest.mark.parametrize("steps,sharpness", [(300, None), (150, 2000.0)])
def test_free_body_gradients_through_contacts(paper, water, sharpness, steps):
    """Exact clipping through the first contact, its bounce and the next contact (300 steps); smooth
    clipping through the first contact and bounce (150 steps)."""
    config = SimConfig(record=False, max_steps=steps, duration=100.0, force=ForceModel(sharpness=sharpness))

    def reach_of(state):
        return state.position[0] + state.position[2]

    run = jax.jit(lambda t: rollout(config, t, paper, water)[:2])
    base = Throw.from_degrees(speed=8.0, tilt=20.0, attack=10.0, spin=20.0)
    assert int(run(base)[1].bounces) >= 1  # the check really crosses water entry and exit
    fd_check(lambda t: reach_of(rollout(config, t, paper, water)[0]), base, rtol=1e-5,
             value=lambda t: reach_of(run(t)[0]))


def test_fixed_attitude_gradient_of_a_whole_throw(paper, water):
    """Nine contacts to the stone's end (it sinks 1.5 s after release, 5.65 m out): the high-spin limit
    is not chaotic, so the whole throw's derivative matches finite differences. (Spin's is zero: the
    attitude is held.)"""
    from jaxskip.simulate import OUTCOMES

    config = SimConfig(record=False, max_steps=4000, duration=100.0, attitude="fixed")
    base = Throw.from_degrees(speed=8.0, tilt=20.0, attack=10.0, spin=20.0)
    run = jax.jit(lambda t: rollout(config, t, paper, water)[:2])
    s, tr = run(base)
    assert int(tr.contacts) >= 8 and OUTCOMES[int(tr.outcome)] == "sank", (int(tr.contacts), int(tr.outcome))
    fd_check(lambda t: rollout(config, t, paper, water)[0].position[0], base, rtol=1e-5,
             value=lambda t: run(t)[0].position[0])


def test_checkpointed_gradients_equal_plain(paper, water):
    """Nested rematerialisation (default), no rematerialisation and any segment length (with a
    remainder segment, or one step per segment) give the same gradient."""
    plain = SimConfig(record=False, max_steps=300, duration=100.0, checkpoint=0, segment=300)
    base = Throw.from_degrees()
    # (the default, checkpoint=1 with segment=50, is differentiated against finite differences above)
    configs = (plain, dataclasses.replace(plain, checkpoint=1, segment=7), dataclasses.replace(plain, segment=1))
    grads = [jax.jit(jax.grad(lambda t, c=c: rollout(c, t, paper, water)[0].position[0]))(base) for c in configs]
    for g in grads[1:]:
        for name in FIELDS:
            np.testing.assert_allclose(float(getattr(g, name)), float(getattr(grads[0], name)), rtol=1e-10)


def test_skipped_segments_match_stepping_to_the_end(paper, water):
    """A throw that ends early: skipping whole dead segments gives the same final state, records
    and gradient as stepping (frozen) through every step."""
    t = Throw.from_degrees(speed=3.0, tilt=30.0, attack=20.0, spin=10.0)
    one = SimConfig(max_steps=1200, duration=100.0, segment=1)
    seg = dataclasses.replace(one, segment=64)  # 1200 = 18 * 64 + 48: a remainder segment too
    (s1, tr1, r1), (s2, tr2, r2) = (jax.jit(lambda t, c=c: rollout(c, t, paper, water))(t) for c in (one, seg))
    ended = int(np.argmax(np.asarray(r1.time)))  # first step of the frozen tail
    assert not bool(tr1.alive) and ended < 1200 - 2 * 64  # whole segments were skipped
    for a, b in zip(jax.tree_util.tree_leaves((s1, tr1, r1)), jax.tree_util.tree_leaves((s2, tr2, r2))):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    g1, g2 = (jax.jit(jax.grad(lambda t, c=c: rollout(c, t, paper, water)[0].position[0]))(t) for c in (one, seg))
    for name in FIELDS:
        np.testing.assert_allclose(float(getattr(g2, name)), float(getattr(g1, name)), rtol=1e-12)


def test_gradient_finite_on_the_water_and_at_rest(paper, water):
    """Two releases with the lowest vertex exactly at z = 0 (zero immersion): the default throw, and a
    stone at rest (|v| = 0 and zero immersion at once; a throw the API refuses, but a traced rollout must
    not). The derivatives of where each ends and of its final velocity are finite (no 0/0 from a norm at
    rest inside the step), and so are those of the library's distance objective, whose norm of the
    displacement is zero at rest; the stone at rest settles into the water and stops. (2026-12-07, an audit:
    this test took its own guarded norm, sqrt(|v|^2 + 1e-30), and never differentiated the distance:
    optimize.objectives.distance written with jnp.linalg.norm gave NaN gradients at rest and passed.)"""
    from jaxskip.simulate import OUTCOMES

    config = SimConfig(record=False, max_steps=200, duration=100.0)

    def end(t):
        s = rollout(config, t, paper, water)[0]
        return jnp.sum(s.position) + jnp.sum(s.velocity)

    grad = jax.jit(jax.grad(end))
    throws = (Throw.from_degrees(height=0.0),
              dataclasses.replace(Throw.from_degrees(height=0.0, spin=0.0), speed=jnp.asarray(0.0)))
    for t in throws:
        g = grad(t)
        assert all(np.isfinite(float(getattr(g, f))) for f in FIELDS + ("height",)), g
    s, tr, _ = jax.jit(lambda t: rollout(config, t, paper, water))(throws[1])
    assert int(tr.contacts) == 1 and OUTCOMES[int(tr.outcome)] == "stopped"   # it touched the water at rest
    # the smooth contact measure the library exposes, the smooth bounce count, there too (2026-12-06, an audit:
    # checked by hand only)
    from optimize import make_objective

    for kind in ("bounces", "distance"):
        smooth = jax.jit(jax.grad(make_objective(kind, config, paper, water)))
        for t in throws:
            g = smooth(t)
            assert all(np.isfinite(float(getattr(g, f))) for f in FIELDS + ("height",)), (kind, g)


@pytest.mark.parametrize("law", ["bocquet", "seed"])
@pytest.mark.parametrize("normalize_lift", [True, False])
def test_water_force_gradient_finite_at_zero_speed(paper, water, law, normalize_lift):
    """A half-immersed stone at rest: |V| = 0 on every triangle."""
    model = ForceModel(law=law, normalize_lift=normalize_lift, faces="all")
    R = quat.to_matrix(jnp.array([1.0, 0.0, 0.0, 0.0]))

    def total(v, w, z):
        F, tau, wet = water_force(model, water, paper, jnp.array([0.0, 0.0, z]), R, v, w, lambda x, y: 0.0 * x)
        return jnp.sum(F) + jnp.sum(tau) + wet

    grads = jax.grad(total, argnums=(0, 1, 2))(jnp.zeros(3), jnp.zeros(3), 0.0)
    assert all(np.all(np.isfinite(np.asarray(g))) for g in grads)


def test_entry_gradient_has_the_physical_sign(paper, water):
    """Throwing faster makes the stone leave its first contact faster (no reflect-rule sign flip)."""
    config = SimConfig(record=False, max_steps=150, duration=100.0, attitude="fixed")
    speed_out = lambda t: jnp.sqrt(jnp.sum(rollout(config, t, paper, water)[0].velocity ** 2))
    g = jax.jit(jax.grad(speed_out))(Throw.from_degrees())
    assert 0.5 < float(g.speed) < 1.0  # friction takes a share of the extra speed, not all of it


@pytest.mark.parametrize("attitude,steps,contacts", [("free", 150, 1), ("fixed", 300, 4)])
def test_distance_objective_gradient_matches_finite_differences(paper, water, attitude, steps, contacts):
    """optimize's "distance" objective: reverse-mode d(distance)/d(speed, tilt, attack, spin) against
    central differences (float64) through water entry and exit: the free stone through its first
    contact and bounce, the held tilt through four contacts (spin then has no effect: gradient 0).
    The FD steps (1e-7 and 2.5e-8 times max(1, |value|)) are shown to lie in a smooth regime first:
    they agree to 1e-6. (The free stone's distance is smooth on a scale of ~1e-6 rad only: wet faces
    switching on or off at n.V = 0 make small jumps and kinks, so larger steps straddle events.)"""
    from optimize import distance, make_objective

    config = SimConfig(record=False, max_steps=steps, duration=100.0, attitude=attitude)
    f = make_objective("distance", config, paper, water)
    base = Throw.from_degrees(speed=8.0, tilt=20.0, attack=10.0, spin=20.0)
    state, tr, _ = jax.jit(lambda t: rollout(config, t, paper, water))(base)
    assert int(tr.contacts) >= contacts and int(tr.bounces) >= 1 and bool(tr.alive)  # entries and exits
    f = jax.jit(f)
    d0 = float(f(base))
    # Two compiled programs (the objective's and the rollout's): equal to rounding. They round apart by
    # 3.9e-14 relative when XLA:CPU compiles at LLVM level 1 (session 20), so 1e-12 (4e-13 m here).
    np.testing.assert_allclose(d0, float(distance(state, base, paper)), rtol=1e-12)
    assert d0 > 0.3
    grad = jax.jit(jax.grad(f))(base)

    def central(name, h):
        v = float(getattr(base, name))
        at = lambda x: float(f(dataclasses.replace(base, **{name: jnp.asarray(x)})))
        h *= max(1.0, abs(v))
        return (at(v + h) - at(v - h)) / (2 * h)

    for name in FIELDS:
        coarse, fine = central(name, 1e-7), central(name, 2.5e-8)
        scale = max(abs(fine), 1e-3)
        assert abs(coarse - fine) <= 1e-6 * scale, (name, coarse, fine)  # no event within the steps
        ad = float(getattr(grad, name))
        assert np.isfinite(ad) and abs(ad - fine) <= 1e-5 * scale, (name, ad, fine)
    if attitude == "free":
        assert abs(float(grad.spin)) > 1e-3  # spin matters to the free stone


def test_a_face_lying_on_the_water_is_not_cut_by_rounding_noise(water):
    """(2026-12-07, a review) a flat-faced stone at tilt exactly 0: its principal-frame face heights differ by
    rounding (~1e-18 m), a flight jump lands the face exactly on the water, and the clip split it by that noise:
    the final position depended on picometre changes of the release height (8.58-8.78 m), and its gradient
    w.r.t. tilt was -1.9e20 (free: -1.2e16), finite, so no guard caught it. Heights within
    clipping.surface_tolerance of the water now count as on it."""
    from jaxskip import clanet_disk, rigid_stone
    from jaxskip.clipping import clip_weights, surface_tolerance

    # the kernel: a horizontal triangle whose heights straddle the water by rounding is on it, with no derivative
    zeta = jnp.array([1e-18, -8e-19, 3e-19])
    jac = jax.jacfwd(lambda z: clip_weights(z)[0])(zeta)
    assert float(clip_weights(zeta)[0]) == 0.0 and float(jnp.max(jnp.abs(jac))) == 0.0
    assert surface_tolerance(jnp.float64) < 1e-15 and surface_tolerance(jnp.float32) < 1e-6
    # a real corner still cuts exactly: one vertex 1 mm under, the others 1 mm above -> fraction 1/4
    assert abs(float(clip_weights(jnp.array([-1e-3, 1e-3, 1e-3]))[0]) - 0.25) < 1e-15

    disk = rigid_stone(clanet_disk(), density=2700.0)
    for attitude in ("fixed", "free"):
        config = SimConfig(record=False, max_steps=300, duration=100.0, attitude=attitude)
        reach = jax.jit(lambda t: rollout(config, t, disk, water)[0].position[0])
        flat = dataclasses.replace(Throw.from_degrees(spin=0.0, attack=10.0), tilt=jnp.asarray(0.0))
        xs = [float(reach(dataclasses.replace(flat, height=flat.height + k * 1e-12))) for k in range(4)]
        assert max(xs) - min(xs) < 1e-9, (attitude, xs)      # was 0.2 m (fixed) and 19 mm (free) apart
        g = jax.jit(jax.grad(lambda t: rollout(config, t, disk, water)[0].position[0]))(flat)
        assert all(abs(float(getattr(g, k))) < 1e3 for k in ("speed", "tilt", "attack")), (attitude, g)


def test_a_run_ended_by_its_duration_stops_at_that_time_for_every_throw(paper, water):
    """A run ended by ``time_limit`` while the stone is in the water stops at ``duration`` exactly: its end time
    does not move with the throw (zero gradient), so its final state is a state at a fixed time, as ``rollout``'s
    docstring says to use one. Before stop 48 the contact step that began before the limit was taken whole: this
    throw stopped at 0.20015 s, dT/dtilt 0.865 s/rad, and d x / d tilt read 0.086 m/rad where the state at 0.2 s
    moves by -3.2 m/rad (a review). Its derivative against central differences too, exact and smooth clipping."""
    from jaxskip.simulate import OUTCOMES, steps_for

    duration = 0.2
    config = SimConfig(record=False, duration=duration, max_steps=steps_for(duration, 2.5e-4))
    base = Throw.from_degrees(speed=5.0, tilt=15.0, attack=8.0, spin=10.0)
    run = jax.jit(lambda t: rollout(config, t, paper, water)[:2])
    state, tr = run(base)
    assert OUTCOMES[int(tr.outcome)] == "time_limit"
    assert int(tr.contacts) >= 1 and int(tr.phase) != 0   # it ends in the water (not in a flight jump)
    assert float(state.time) == duration
    dtime = jax.jit(jax.grad(lambda t: rollout(config, t, paper, water)[0].time))(base)
    assert all(float(getattr(dtime, name)) == 0.0 for name in FIELDS), dtime
    # (1e-4: spin's derivative is 1.5e-3 m per rad/s, where the differences' rounding is ~2e-8; the end-time term
    # was as large as the derivative itself)
    fd_check(lambda t: rollout(config, t, paper, water)[0].position[0], base, rtol=1e-4,
             value=lambda t: run(t)[0].position[0])
    # fixed steps end there too (SimConfig(flight="step"))
    fixed = dataclasses.replace(config, flight="step")
    state, tr = jax.jit(lambda t: rollout(fixed, t, paper, water)[:2])(base)
    assert OUTCOMES[int(tr.outcome)] == "time_limit" and float(state.time) == duration
