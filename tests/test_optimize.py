"""The throw search: surrogate gradients, its agreement with the true count, bounds, the search itself."""

import dataclasses
import functools
import math
import warnings

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxskip import ParameterError, SimConfig, Throw, rollout, simulate_batch
from optimize import (EXPLODING, VANISHING, gradient_health, gradient_search, local_search, make_box,
                      make_objective, perturbation_search, random_search, top_throws)
from optimize import search as search_module
from optimize.search import SearchResult
from optimize.objectives import soft_bounce_count, soft_bounce_rollout

FIELDS = ("speed", "tilt", "attack", "spin")


def test_surrogate_gradient_matches_finite_differences(paper, water):
    """d(smooth count)/d(throw) against central differences, float64, over the first few bounces.

    The rollout is smooth only between events (a step-length switch, a contact beginning), which
    lie close together in a free throw, hence the small steps h."""
    config = SimConfig(max_steps=400, duration=100.0)
    f = jax.jit(make_objective("bounces", config, paper, water))
    base = Throw.from_degrees(speed=7.0, tilt=20.0, attack=10.0, spin=15.0)
    value = float(f(base))
    assert 1.5 < value < 30.0  # several hops inside the horizon: the surrogate is not flat here
    grad = jax.jit(jax.grad(f))(base)
    for name, h in zip(FIELDS, (1e-7, 1e-7, 1e-7, 1e-5)):
        up = Throw(**{**base.__dict__, name: getattr(base, name) + h})
        dn = Throw(**{**base.__dict__, name: getattr(base, name) - h})
        fd = (float(f(up)) - float(f(dn))) / (2 * h)
        g = float(getattr(grad, name))
        assert math.isfinite(g)
        np.testing.assert_allclose(g, fd, rtol=2e-4, atol=1e-6, err_msg=name)  # worst measured: 6.7e-5


@pytest.mark.parametrize("steps, n", [(400, 200), (None, 32)])
def test_surrogate_gradient_finite_over_random_throws(paper, water, steps, n):
    """Finite gradients over random throws uniform in the human box: the first 400 steps of 200
    throws, and 32 whole throws (the search's default; chaos makes their norms huge, ~1e13, but
    finite). The benchmark runs 1e4 throws through 1200 steps."""
    config = SimConfig() if steps is None else SimConfig(max_steps=steps, duration=100.0)
    box = make_box()
    f = make_objective("bounces", config, paper, water)
    rng = np.random.default_rng(0)
    u = jnp.asarray(box.from_user({name: rng.uniform(lo, hi, n) for name, lo, hi in box.searched}))
    g = jax.jit(lambda u: jax.lax.map(jax.grad(lambda ui: f(box.to_throw(ui))), u))(u)
    assert bool(jnp.all(jnp.isfinite(g)))
    assert float(jnp.mean(jnp.abs(g) > 0)) > 0.3  # not a flat function: most throws get a signal


def _human_box_throws(n, seed):
    """``n`` random throws of the human box (speed 3-12 m/s, tilt 5-45 deg, attack 0-30 deg, spin 0-20 rev/s)."""
    rng = np.random.default_rng(seed)
    return Throw.from_degrees(speed=rng.uniform(3, 12, n), tilt=rng.uniform(5, 45, n),
                              attack=rng.uniform(0, 30, n), spin=rng.uniform(0, 20, n))


def test_surrogate_agrees_with_true_count(paper, water):
    """Where the count is stable the rounded surrogate equals the exact count for most throws."""
    throws = _human_box_throws(16, seed=1)
    config = SimConfig(max_steps=4000)
    f = make_objective("bounces", config, paper, water)
    soft = np.asarray(jax.jit(jax.vmap(f))(throws))
    true = np.asarray(jax.jit(jax.vmap(lambda t: rollout(config, t, paper, water)[1].bounces))(throws))
    assert np.mean(np.round(soft) == true) >= 0.75, (soft.round(2), true)
    assert np.sum(true) > 10  # the sample does bounce


def test_soft_count_in_the_carry_equals_the_records(paper, water):
    """The objective sums the surrogate in the scan's carry; it equals the sum over stacked records."""
    throws = _human_box_throws(4, seed=3)
    config = SimConfig(max_steps=1500)
    from_records = jax.vmap(lambda t: soft_bounce_count(rollout(config, t, paper, water)[2]))(throws)
    in_carry = jax.vmap(lambda t: soft_bounce_rollout(config, t, paper, water)[2])(throws)
    np.testing.assert_allclose(np.asarray(in_carry), np.asarray(from_records), rtol=1e-12, atol=1e-12)
    assert float(jnp.sum(from_records)) > 2.0  # the sample does hop


def test_soft_count_ignores_frozen_steps():
    """Records repeated after the end (frozen) add nothing; a clean hop adds ~1."""
    from jaxskip.simulate import Record

    gap = jnp.array([1e-3, -1e-3, -2e-3, 1e-3, 5e-3, 2e-3, -1e-3, 0.0, 0.0])
    time = jnp.array([0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 6.0, 6.0])
    wet = jnp.where(gap < 0.0, 1e-4, 0.0)   # wetted area [m^2] where the lowest point is under water
    rec = Record(time, jnp.zeros((9, 3)), jnp.zeros((9, 4)), wet, jnp.zeros((9, 3)), gap, jnp.zeros((9, 3)),
                 jnp.zeros((9, 3)))
    n = float(soft_bounce_count(rec, clearance=1e-3, width=2e-4))
    assert abs(n - 1.0) < 0.01


def test_soft_count_caps_each_flight_at_one(paper, water):
    """A wobbling stone's lowest vertex dips below the clearance and rises again in the air before its next
    contact: the tracker counts one bounce per flight, the surrogate counted each rise (session 26: 13.1
    against 12 over a default-like throw, 2.1 against 1 over its first 300 steps)."""
    from jaxskip.simulate import Record

    # wet, up past c (a bounce), down to 0.4 mm and up to 1.6 mm in the air, wet again, up again
    gap = jnp.array([-1e-3, -5e-4, 2e-3, 4e-3, 4e-4, 1.6e-3, -1e-3, 3e-3, 5e-3])
    time = jnp.arange(9.0)
    wet = jnp.where(gap < 0.0, 1e-4, 0.0)
    rec = Record(time, jnp.zeros((9, 3)), jnp.zeros((9, 4)), wet, jnp.zeros((9, 3)), gap, jnp.zeros((9, 3)),
                 jnp.zeros((9, 3)))
    assert abs(float(soft_bounce_count(rec, clearance=1e-3, width=2e-4)) - 2.0) < 0.01  # was 2.95
    throw = Throw.from_degrees(speed=8.0, tilt=20.0, attack=10.0, spin=20.0)
    for steps, true in ((300, 1), (2000, 12)):
        config = SimConfig(max_steps=steps, duration=100.0)
        tr, soft = jax.jit(lambda t: soft_bounce_rollout(config, t, paper, water)[1:])(throw)
        assert int(tr.bounces) == true and abs(float(soft) - true) < 0.15, (steps, float(soft))  # 1.06, 12.10


def test_soft_count_ignores_rises_before_the_first_contact(paper, water):
    """A throw straight up and a stone dropped while spinning never bounce (true count 0), but the
    surrogate counted the rise from release (0.5) and the spinning stone's lowest vertex bobbing before it
    landed (1.58): rises count only once the stone has touched the water, in both forms."""
    throws = Throw.from_degrees(speed=jnp.array([8.0, 0.05]), tilt=20.0, attack=jnp.array([-90.0, 5.0]),
                                spin=jnp.array([20.0, 20.0]))
    config = SimConfig(max_steps=200)
    true = np.asarray(jax.vmap(lambda t: rollout(config, t, paper, water)[1].bounces)(throws))
    from_records = np.asarray(jax.vmap(lambda t: soft_bounce_count(rollout(config, t, paper, water)[2]))(throws))
    in_carry = np.asarray(jax.vmap(lambda t: soft_bounce_rollout(config, t, paper, water)[2])(throws))
    assert true.tolist() == [0, 0]
    np.testing.assert_allclose(in_carry, from_records, rtol=1e-12, atol=1e-12)
    # measured 0 and 0.106 (the slow stone's lowest point wiggling about the clearance after it landed:
    # the documented skim bias), against 0.5 and 1.58 before
    assert from_records[0] < 0.01 and from_records[1] < 0.2, from_records


@pytest.mark.parametrize("searched, message", [
    ({"speed": (12.0, 3.0)}, "speed is inverted"),
    ({"speed": (3.0, float("nan"))}, "speed must be finite"),
    ({"tilt": (20.0, 20.0)}, "tilt is empty"),
    ({"spin": (0.0, 500.0)}, "spin must lie within"),
    ({"attack": (-10.0, 20.0)}, "attack must lie within"),
    ({"velocity": (1.0, 2.0)}, "unknown throw parameter"),
    ({"speed": "fast"}, "speed must be a pair"),
    ({"speed": "39"}, "speed must be a pair"),          # was read as (3, 9) m/s
    ({"speed": (True, 5.0)}, "speed must be a pair"),   # was read as (1, 5) m/s
    ({}, "at least one searched"),
])
def test_bad_bounds(searched, message):
    with pytest.raises(ParameterError, match=message):
        make_box(searched)


def test_a_box_built_by_hand_stores_checked_floats_in_order():
    """Box(...) built directly kept a "3" (failing later in to_user) and took parameters out of order
    (u's last axis follows PARAMETERS): text is refused, numbers are stored as the checked floats, and
    another order is refused."""
    from optimize.bounds import Box

    with pytest.raises(ParameterError, match="speed must be a pair"):
        Box((("speed", "3", 12.0),), (("tilt", 5.0), ("attack", 5.0), ("spin", 20.0)))
    box = Box((("speed", 3, np.float32(12.0)),), (("tilt", 5), ("attack", 5.0), ("spin", np.float32(20.0))))
    assert box.searched == (("speed", 3.0, 12.0),) and type(box.searched[0][2]) is float
    assert all(type(v) is float for _, v in box.held)
    assert box == make_box({"speed": (3.0, 12.0)}, held={"tilt": 5.0, "attack": 5.0, "spin": 20.0})
    with pytest.raises(ParameterError, match="in the order speed, tilt, attack, spin"):
        Box((("tilt", 5.0, 45.0), ("speed", 3.0, 12.0)), (("attack", 5.0), ("spin", 20.0)))


def test_from_user_names_a_missing_parameter():
    box = make_box({"speed": (3.0, 12.0), "tilt": (5.0, 45.0)})
    with pytest.raises(ParameterError, match="missing tilt"):   # was a KeyError
        box.from_user({"speed": 5.0})


@pytest.mark.parametrize("values, message", [
    ({"speed": 7.0, "tilt": 80.0}, "only the searched parameters \\(speed\\): 'tilt' is held at 20 by the box"),
    ({"speed": 60.0}, r"speed must lie within the box \[6, 8\] m/s, got 60.0"),
    ({"speed": [7.0, float("nan")]}, r"speed must lie within the box \[6, 8\] m/s, got nan"),
    ({"sped": 7.0}, "'sped' is not a throw parameter"),
    ({"speed": "7"}, "speed must be a real number"),
    ({"speed": True}, "speed must be a real number"),
    ([7.0], "values must be a dict"),
])
def test_box_user_values_are_checked(values, message):
    """Box.from_user and Box.throws_from_user refuse what they once took (2026-12-05 review): a held
    parameter's value silently replaced the held one (tilt 80 for the box's 20), a value outside the
    box (and LIMITS) was thrown, a misspelt name was dropped or gave a KeyError, a string was converted."""
    box = make_box({"speed": (6.0, 8.0)}, {"tilt": 20.0, "attack": 5.0, "spin": 20.0})
    for convert in (box.from_user, box.throws_from_user):
        with pytest.raises(ParameterError, match=message):
            convert(values)
    t = box.throws_from_user({"speed": np.array([6.0, 7.5])})
    np.testing.assert_allclose(np.asarray(t.speed), [6.0, 7.5])
    np.testing.assert_allclose(np.rad2deg(np.asarray(t.tilt)), [20.0, 20.0])


def test_box_reparameterisation_stays_inside():
    box = make_box({"speed": (3.0, 12.0), "tilt": (5.0, 45.0)}, held={"spin": 10.0})
    t = box.to_throw(jnp.array([[-50.0, 50.0], [0.0, 0.0]]))
    assert np.all((np.asarray(t.speed) >= 3.0) & (np.asarray(t.speed) <= 12.0))
    np.testing.assert_allclose(np.rad2deg(np.asarray(t.tilt)), [45.0, 25.0], atol=1e-9)
    np.testing.assert_allclose(np.asarray(t.spin), 2 * np.pi * 10.0)
    u = box.from_user({"speed": np.array([4.0]), "tilt": np.array([30.0])})
    back = box.to_user(u)
    np.testing.assert_allclose([back["speed"][0], back["tilt"][0]], [4.0, 30.0], rtol=1e-9)
    # a list or an integer array, as to_user takes them (raw TypeErrors before, 2026-12-06)
    for given in ([0.0, 0.0], np.zeros(2, dtype=int)):
        t = box.to_throw(given)
        np.testing.assert_allclose([float(t.speed), np.rad2deg(float(t.tilt))], [7.5, 25.0], rtol=1e-12)


def test_gradient_search_improves_a_poor_throw(paper, water):
    """From slow, shallow starts the search finds more bounces (true counts, exact simulation)."""
    # The polish test below compiles this very program (same box layout, config and starts): run first on
    # the same pytest-xdist worker, it left this search nothing to compile (compile_time 0, asserted > 0).
    search_module._surrogate_program.cache_clear()
    box = make_box({"speed": (2.0, 10.0), "attack": (0.0, 30.0)}, held={"tilt": 20.0, "spin": 15.0})
    config = SimConfig(max_steps=3000, attitude="fixed")
    r = gradient_search(box, config=config, starts=2, iterations=6, learning_rate=0.5, seed=3)
    first, last = r.history[0]["best"], r.history[-1]["best"]
    assert last > first, [h["bounces"] for h in r.history]
    assert r.best_bounces == last and r.gradient_evals == 12 and len(r.history) == 7
    assert set(r.best) == set(FIELDS)
    # Gradient-norm monitoring: each iteration records every start's raw gradient norm, which is
    # the norm of the surrogate's gradient at that start's throw (recomputed here on its own).
    assert all(len(h["grad_norm"]) == 2 for h in r.history[:-1]) and "grad_norm" not in r.history[-1]
    # (2026-12-07) the iterates' true counts are simulated in one batch after the ascent: each entry's counts are
    # still its own points' (simulated here one iteration at a time), and its "best" the best up to it
    for h in r.history:
        pts = {k: np.asarray(v) for k, v in h["points"].items()}
        own = simulate_batch(box.throws_from_user(pts), config=dataclasses.replace(config, record=False)).bounces
        assert h["bounces"] == own.tolist(), (h["iteration"], h["bounces"], own)
    assert [h["best"] for h in r.history] == list(np.maximum.accumulate([max(h["bounces"]) for h in r.history]))

    @functools.partial(jax.jit, static_argnames="box")
    def grads(u, water, width, box):
        f = make_objective("bounces", config, paper, water, width)
        return jax.vmap(jax.grad(lambda ui: f(box.to_throw(ui))))(u)

    def norms(result, water, width, box=box):
        u = box.from_user({k: np.asarray(v) for k, v in result.history[0]["points"].items()})
        return np.linalg.norm(np.asarray(grads(jnp.asarray(u), water, width, box)), axis=-1)

    np.testing.assert_allclose(r.history[0]["grad_norm"], norms(r, water, 2e-4), rtol=1e-6)
    health = gradient_health(r)
    assert health["of"] == 12 and health["starts"]["n"] == 2 and health["max"] >= health["median"] > 0.0
    assert r.compile_time > 0.0
    # Searching again, with other values of everything that is not a shape or a setting (seed, step,
    # clip, surrogate width, the water's coefficients), reuses the compiled gradient (it took 15-40 s a
    # call) and differentiates the new surrogate, not the first search's.
    water2 = dataclasses.replace(water, c_lift=water.c_lift * 1.3)
    again = gradient_search(box, config=config, starts=2, iterations=1, learning_rate=0.2, clip=3.0,
                            width=4e-4, water=water2, seed=5)
    assert again.compile_time == 0.0 and again.gradient_evals == 2
    np.testing.assert_allclose(again.history[0]["grad_norm"], norms(again, water2, 4e-4), rtol=1e-6)
    assert not np.allclose(again.history[0]["grad_norm"], norms(again, water, 2e-4), rtol=1e-3)
    # Another box (other bounds, other held values) and a config that differs only in record (which the
    # surrogate ignores): the same program again (each compiled its own before), with the new box's numbers.
    box2 = make_box({"speed": (3.0, 9.0), "attack": (2.0, 25.0)}, held={"tilt": 25.0, "spin": 12.0})
    third = gradient_search(box2, config=dataclasses.replace(config, record=False), starts=2, iterations=1, seed=6,
                            water=water)
    assert third.compile_time == 0.0 and all(3.0 <= v <= 9.0 for v in third.history[0]["points"]["speed"])
    np.testing.assert_allclose(third.history[0]["grad_norm"], norms(third, water, 2e-4, box2), rtol=1e-6)
    assert not np.allclose(third.history[0]["grad_norm"], norms(third, water, 2e-4, box), rtol=1e-3)
    # screen=N: N random exact throws first, the best `starts` of them the starts (the same program again)
    fourth = gradient_search(box, config=config, starts=2, iterations=1, screen=6, seed=3, water=water)
    first = fourth.history[0]
    screened = first["screen"]
    assert len(screened["bounces"]) == 6 and all(len(v) == 6 for v in screened["points"].values())
    assert sorted(first["bounces"]) == sorted(screened["bounces"])[-2:]   # the starts: the two best, recounted
    chosen = np.argsort(screened["bounces"], kind="stable")[-2:]
    assert sorted(first["points"]["speed"]) == sorted(np.asarray(screened["points"]["speed"])[chosen].tolist())
    assert fourth.forward_throws == 6 + 2 * 2 and fourth.compile_time == 0.0
    assert fourth.best_bounces >= max(screened["bounces"])
    with pytest.raises(ParameterError, match=r"screen must be 0 or at least starts \(2\): .* got 1"):
        gradient_search(box, config=config, starts=2, screen=1)
    # (2026-12-06, a review) initial replaced the best screened start, which then was in no history entry's points,
    # where the polish looks for centres and the picture for the best distance. It replaces the weakest pick now.
    initial = {"speed": 5.0, "attack": 10.0}
    fifth = gradient_search(box, config=config, starts=2, iterations=1, screen=6, seed=3, water=water, initial=initial)
    best_screened = int(np.argmax(screened["bounces"]))   # (stable: the first of the best, as the starts are picked)
    assert fifth.history[0]["points"]["speed"][0] == screened["points"]["speed"][best_screened]
    assert [fifth.history[0]["points"][k][1] for k in initial] == list(initial.values())
    with pytest.raises(ParameterError, match=r"screen must be 0 when initial takes the only start"):
        gradient_search(box, config=config, starts=1, screen=6, initial=initial)


def test_polish_samples_near_the_best_throws_and_counts_exactly():
    """gradient_search(polish=N): N exact throws near the ascent's best; the best of all wins."""
    box = make_box({"speed": (2.0, 10.0), "attack": (0.0, 30.0)}, held={"tilt": 20.0, "spin": 15.0})
    config = SimConfig(max_steps=3000, attitude="fixed")
    r = gradient_search(box, config=config, starts=2, iterations=3, learning_rate=0.5, seed=3, polish=10,
                        polish_scale=0.05)
    ascent, polish = r.history[:-1], r.history[-1]
    assert polish["phase"] == "polish" and len(polish["bounces"]) == 10
    assert r.forward_throws == 2 * 4 + 10 and r.gradient_evals == 6
    every = [b for h in r.history for b in h["bounces"]]
    assert r.best_bounces == max(every) >= ascent[-1]["best"]
    # Each polish throw lies within a few scales of one of the ascent's best throws, inside the box.
    centres = top_throws(ascent, 2)
    pts = np.stack([polish["points"]["speed"], polish["points"]["attack"]], axis=-1)
    c = np.stack([centres["speed"], centres["attack"]], axis=-1)
    scaled = (pts[:, None, :] - c[None, :, :]) / (0.05 * np.array([8.0, 30.0]))
    assert np.all(np.min(np.max(np.abs(scaled), axis=-1), axis=1) < 6.0)
    assert np.all((pts >= [2.0, 0.0]) & (pts <= [10.0, 30.0]))
    # The reported count is the exact simulation's, throw by throw.
    i = int(np.argmax(polish["bounces"]))
    again = simulate_batch(box.throws_from_user({k: np.array([v[i]]) for k, v in polish["points"].items()}),
                           config=dataclasses.replace(config, record=False))
    assert int(again.bounces[0]) == polish["bounces"][i]


def test_distance_objective_picks_the_longest_true_distance():
    """objective="distance": the ascent climbs the distance, and the best throw is the one with the
    longest *true* distance among every throw simulated (ascent and polish), not the most bounces."""
    box = make_box({"speed": (2.0, 10.0), "attack": (0.0, 30.0)}, held={"tilt": 20.0, "spin": 15.0})
    config = SimConfig(max_steps=3000, attitude="fixed")
    r = gradient_search(box, objective="distance", config=config, starts=2, iterations=2, learning_rate=0.5,
                        seed=3, polish=6, polish_scale=0.05)
    assert r.objective == "distance" and r.history[-1]["phase"] == "polish"
    dists = np.concatenate([h["distance"] for h in r.history])
    counts = np.concatenate([h["bounces"] for h in r.history])
    i = int(np.argmax(dists))
    assert r.best_distance == dists[i] and r.best_bounces == counts[i]
    again = simulate_batch(box.throws_from_user({k: np.array([r.best[k]]) for k, _, _ in box.searched}),
                           config=dataclasses.replace(config, record=False))
    np.testing.assert_allclose(again.distance[0], r.best_distance, rtol=1e-12)
    assert r.to_dict()["best_distance"] == r.best_distance
    # On the same throws the two objectives pick different bests, each its own measure's maximum.
    kw = dict(throws=12, scale=0.3, config=config, seed=0)
    by_count = local_search(box, {"speed": [6.0], "attack": [10.0]}, **kw)
    by_dist = local_search(box, {"speed": [6.0], "attack": [10.0]}, objective="distance", **kw)
    d, n = np.array(by_dist.history[0]["distance"]), np.array(by_dist.history[0]["bounces"])
    assert by_count.history[0]["distance"] == by_dist.history[0]["distance"]
    assert (by_dist.best_distance, by_count.best_bounces) == (d.max(), n.max())
    assert by_dist.best_distance > by_count.best_distance and by_dist.best != by_count.best
    with pytest.raises(ParameterError, match="objective"):
        local_search(box, {"speed": [5.0], "attack": [5.0]}, objective="height")


def test_gradient_health_counts_exploding_and_vanishing_gradients():
    """Three starts over two iterations: start 0 vanishes throughout, start 1 turns non-finite,
    start 2 explodes once."""
    history = [{"grad_norm": [1e-8, 5.0, 10 * EXPLODING]}, {"grad_norm": [0.1 * VANISHING, None, 2.0]},
               {"bounces": [1, 2, 3]}]                                  # (the last entry: no gradients)
    r = SearchResult("gradient", {}, 3, history, make_box(), 1.0, 9, 6)
    h = gradient_health(r)
    assert h["of"] == 6 and h["exploding"] == 2 and h["vanishing"] == 2
    assert h["starts"] == {"n": 3, "exploding": 2, "vanishing": 1, "vanishing_some": 1}
    assert h["median"] == 2.0 and h["max"] == 10 * EXPLODING
    assert gradient_health(dataclasses.replace(r, history=[{"bounces": [1]}])) is None


def test_perturbation_search_polishes_near_the_best_evaluated_throws():
    """perturbation_search(polish=N): N exact throws near the best throws it evaluated (centres and
    antithetic samples alike); its history lists the centres it simulated."""
    box = make_box({"speed": (2.0, 10.0), "attack": (0.0, 30.0)}, held={"tilt": 20.0, "spin": 15.0})
    config = SimConfig(max_steps=3000, attitude="fixed")
    r = perturbation_search(box, config=config, starts=2, iterations=2, samples=2, polish=6, seed=1)
    assert r.forward_throws == 2 * 2 * (2 * 2 + 1) + 6 and r.gradient_evals == 0
    assert [h.get("phase") for h in r.history] == [None, None, "polish"] and len(r.history[-1]["bounces"]) == 6
    assert all(len(h["points"]["speed"]) == 2 for h in r.history[:2])
    assert r.history[-1]["best"] == r.best_bounces >= max(b for h in r.history for b in h["bounces"])
    pts = np.asarray(r.history[-1]["points"]["speed"])
    assert np.all((pts >= 2.0) & (pts <= 10.0))
    # The reported best is the exact simulation's count of the reported throw.
    again = simulate_batch(box.throws_from_user({k: np.array([r.best[k]]) for k in ("speed", "attack")}),
                           config=dataclasses.replace(config, record=False))
    assert int(again.bounces[0]) == r.best_bounces


def test_top_throws_are_distinct_and_best_first():
    history = [{"bounces": [3, 7], "points": {"speed": [4.0, 6.0]}},
               {"bounces": [7, 5], "points": {"speed": [6.0, 5.0]}}]
    top = top_throws(history, 3)
    np.testing.assert_array_equal(top["speed"], [6.0, 5.0, 4.0])
    with pytest.raises(ParameterError, match="no points"):
        top_throws([{"bounces": [1]}], 1)
    with pytest.raises(ParameterError, match="history must be a search's history"):  # was a raw TypeError
        top_throws(5, 2)


def test_a_box_refuses_u_without_one_column_per_searched_parameter():
    """A column short, JAX's clamped indexing made tilt reuse speed's coordinate; extra columns were ignored
    (to_user raised a raw IndexError). The shape is static: refused inside jit too."""
    box = make_box({"speed": (3.0, 12.0), "tilt": (5.0, 45.0)}, {"attack": 5.0, "spin": 20.0})
    assert box.to_throw(jnp.zeros((4, 2))).shape == (4,)
    for bad in (jnp.zeros((4, 1)), jnp.zeros((4, 3)), jnp.zeros(())):
        with pytest.raises(ParameterError, match=r"u must have shape \(\.\.\., 2\).*speed, tilt"):
            box.to_throw(bad)
        with pytest.raises(ParameterError, match=r"u must have shape"):
            box.to_user(np.asarray(bad))
    with pytest.raises(ParameterError, match=r"u must have shape"):
        jax.jit(lambda u: box.to_throw(u).speed)(jnp.zeros((4, 1)))
    with pytest.raises(ParameterError, match="searched must be a dict"):  # was a raw ValueError
        make_box([("speed", 3.0, 12.0)])
    with pytest.raises(ParameterError, match="held must be a dict"):
        make_box({"speed": (3.0, 12.0)}, [("tilt", 20.0)])


@pytest.mark.parametrize("search, kwargs", [("random_search", {"throws": 2}), ("grid_search", {"per_axis": 2}),
                                            ("local_search", {"throws": 2}), ("perturbation_search", {}),
                                            ("gradient_search", {})])
def test_every_search_checks_its_water(search, kwargs):
    """Four of the five searches met a raw AttributeError ('dict' object has no attribute 'gravity')."""
    import optimize

    box = make_box({"speed": (6.0, 8.0)}, {"tilt": 20.0, "attack": 5.0, "spin": 20.0})
    args = (box, {"speed": [7.0]}) if search == "local_search" else (box,)
    with pytest.raises(ParameterError, match="water must be a jaxskip.WaterParams"):
        getattr(optimize, search)(*args, water={"gravity": 9.81}, **kwargs)


@pytest.mark.parametrize("centres, kwargs, message", [
    ({"speed": [11.0]}, {}, "within the box"),
    ({}, {}, "missing 'speed'"),
    ({"speed": [5.0]}, {"scale": 0.0}, "scale"),
    ({"speed": [5.0]}, {"throws": 0}, "throws"),
    # (session 31) a raw TypeError; a held parameter's centre (even tilt 99 deg) was dropped silently
    (None, {}, "centres must be a dict"),
    ({"speed": [5.0], "tilt": [99.0]}, {}, "centres gives tilt, held by the box"),
    # (session 32) a raw ValueError naming nothing; a misspelt name ignored
    ({"speed": ["a"]}, {}, r"centres\['speed'\] must be numbers in user units, got \['a'\]"),
    ({"speed": [5.0], "height": [0.1]}, {}, "centres gives 'height', not a searched parameter; the box searches speed"),
    # (2026-12-05) a string centre was converted ("7" ran as 7 m/s), a bool too
    ({"speed": ["7"]}, {}, r"centres\['speed'\] must be numbers in user units, got \['7'\]"),
    ({"speed": [True]}, {}, r"centres\['speed'\] must be numbers"),
])
def test_local_search_bad_input(centres, kwargs, message):
    box = make_box({"speed": (3.0, 10.0)}, held={"tilt": 20.0, "attack": 10.0, "spin": 15.0})
    with pytest.raises(ParameterError, match=message):
        local_search(box, centres, **kwargs)


@pytest.mark.parametrize("kwargs, message", [({"polish": -1}, "polish"), ({"polish_scale": 0.0}, "polish_scale"),
                                             ({"horizon": 0}, "horizon")])
def test_gradient_search_bad_polish_and_horizon(kwargs, message):
    box = make_box({"speed": (3.0, 10.0)}, held={"tilt": 20.0, "attack": 10.0, "spin": 15.0})
    with pytest.raises(ParameterError, match=message):
        gradient_search(box, **kwargs)


@pytest.mark.parametrize("search", ["gradient_search", "perturbation_search", "random_search", "local_search"])
@pytest.mark.parametrize("seed", [-1, 1.5, "a", True])
def test_seed_must_be_a_non_negative_integer(search, seed):
    """A bad seed is a ParameterError naming it (not NumPy's ValueError or a TypeError), before any work."""
    import optimize

    box = make_box({"speed": (3.0, 10.0)}, held={"tilt": 20.0, "attack": 10.0, "spin": 15.0})
    args = (box, {"speed": [5.0]}) if search == "local_search" else (box,)
    with pytest.raises(ParameterError, match=r"seed must be an integer >= 0, got "):
        getattr(optimize, search)(*args, seed=seed)


def test_initial_may_not_give_a_held_parameter():
    """initial={'speed': 5, 'tilt': 40} with tilt held at 20: refused naming tilt (it was silently dropped)."""
    box = make_box({"speed": (3.0, 10.0)}, held={"tilt": 20.0, "attack": 10.0, "spin": 15.0})
    with pytest.raises(ParameterError, match=r"initial tilt is held at 20 deg by the box, not searched"):
        gradient_search(box, initial={"speed": 5.0, "tilt": 40.0})
    with pytest.raises(ParameterError, match="unknown throw parameter 'height'"):
        gradient_search(box, initial={"speed": 5.0, "height": 1.0})
    with pytest.raises(ParameterError, match="initial speed must be in"):
        gradient_search(box, initial={"speed": 11.0})


def test_the_default_box_less_what_is_held():
    """(session 32) make_box(held={"tilt": 20}) was refused ("both searched and held": the default searched box
    is the human box, tilt included); it is the human box with the tilt held. HUMAN_BOX is read-only (a change
    to it changed every later default search)."""
    import optimize

    box = make_box(held={"tilt": 20.0})
    assert box.names == ("speed", "attack", "spin") and dict(box.held) == {"tilt": 20.0}
    assert box.searched == tuple((k, *v) for k, v in optimize.HUMAN_BOX.items() if k != "tilt")
    with pytest.raises(TypeError):
        optimize.HUMAN_BOX["speed"] = (3.0, 20.0)
    assert make_box().searched[0] == ("speed", 3.0, 12.0)


def test_searches_take_a_box_dict_such_as_human_box():
    """gradient_search's docs call optimize.HUMAN_BOX its default box: passing it (or any such dict, values
    held) works as make_box would build it."""
    import optimize

    config = SimConfig(max_steps=400, attitude="fixed")
    r = optimize.random_search(optimize.HUMAN_BOX, throws=2, config=config)
    assert r.box == make_box() and r.forward_throws == 2
    r = optimize.grid_search({"speed": (5.0, 7.0), "tilt": 20.0, "spin": 10.0}, per_axis=2, config=config)
    assert r.box == make_box({"speed": (5.0, 7.0)}, {"tilt": 20.0, "spin": 10.0}) and r.best["tilt"] == 20.0
    # the box is accepted: the next check (starts) is the one that refuses
    with pytest.raises(ParameterError, match="starts"):
        gradient_search(box=optimize.HUMAN_BOX, starts=0)
    with pytest.raises(ParameterError, match="box must be an optimize.Box .* or a dict"):
        gradient_search(box=[(3.0, 12.0)])


@pytest.mark.parametrize("search", ["gradient_search", "perturbation_search", "local_search", "grid_search",
                                    "random_search"])
def test_search_docstrings_say_what_they_return(search):
    import optimize

    doc = getattr(optimize, search).__doc__
    for field in ("Returns a :class:`SearchResult`", "``best``", "``best_bounces``", "``best_distance``", "[m]",
                  "``forward_throws``", "``history``"):
        assert field in doc, field


def test_make_objective_refuses_wrong_types(paper, water):
    """A config, stone or water of the wrong type is a ParameterError naming it, before any tracing (config="x"
    was a raw AttributeError; a wrong stone or water passed until the rollout was traced)."""
    from optimize import make_objective

    for kwargs, name in ((dict(config="x"), "config must be a jaxskip.SimConfig, got str"),
                         (dict(stone="paper"), "stone must be a jaxskip.RigidStone"),
                         (dict(water=None), "water must be a jaxskip.WaterParams")):
        args = dict(config=SimConfig(), stone=paper, water=water) | kwargs
        with pytest.raises(ParameterError, match=name):
            make_objective("bounces", **args)
    # (2026-12-07, a review) the knobs' ranges: a width of 1e-50 m is 0 in float32 (NaN gradients), a clearance
    # of 1 km scored every throw 0; the tracker's clearance is at most 1 cm
    config = SimConfig(max_steps=50)
    for call, said in ((lambda: make_objective("bounces", config, paper, water, width=1e-50), r"width must be in \[1e-09"),
                       (lambda: make_objective("bounces", config, paper, water, width=0.5), r"width must be in \[1e-09"),
                       (lambda: soft_bounce_rollout(config, Throw.from_degrees(), paper, water, clearance=1e3),
                        r"clearance must be in \(0, 0.01\] m"),
                       (lambda: gradient_search(config=config, width=1e-50), r"width must be in \[1e-09")):
        with pytest.raises(ParameterError, match=said):
            call()


def test_the_bounce_objective_checks_and_casts_as_rollout_does(paper, water):
    """(session 32, a review of optimize) the "bounces" objective built its own scan: a float32 throw and stone
    under x64 met a raw lax.cond TypeError, and a batched throw a broadcasting error, where rollout (and the
    "distance" objective) cast or refuse; soft_bounce_count of a batch's records summed along the throws."""
    from optimize import make_objective
    from jaxskip import initial_carry, make_step

    config = SimConfig(duration=0.05, max_steps=200, record=False)
    f32 = lambda tree: jax.tree_util.tree_map(lambda a: jnp.asarray(a, jnp.float32), tree)  # noqa: E731
    throw32, stone32, water32 = f32(Throw.from_degrees()), f32(paper), f32(water)
    f64 = lambda tree: jax.tree_util.tree_map(lambda a: jnp.asarray(a, jnp.float64), tree)  # noqa: E731
    f = make_objective("bounces", config, stone32, water32)
    assert float(f(throw32)) == float(make_objective("bounces", config, f64(stone32), f64(water32))(f64(throw32)))
    g = make_objective("bounces", config, paper, water)
    with pytest.raises(ParameterError, match=r"the objective of make_objective\('bounces', ...\) takes one throw"):
        g(Throw.from_degrees(speed=np.array([6.0, 8.0])))
    # the user's own loop (README: "your own loop"): a float32 throw and stone step in float64 too
    step = make_step(config)
    carry = initial_carry(config, throw32, stone32)
    (state, tracker), _ = jax.lax.scan(lambda c, _: step(c, stone32, water32), carry, None, length=50)
    assert state.position.dtype == jnp.float64
    # records of a batch, or none
    rec_config = SimConfig(duration=0.3, max_steps=1200)
    _, tr, rec = jax.vmap(lambda t: rollout(rec_config, t, paper, water))(Throw.from_degrees(speed=np.array([6., 8.])))
    counts = jax.vmap(soft_bounce_count)(rec)
    assert np.all(np.abs(np.asarray(counts) - np.asarray(tr.bounces)) < 0.5)
    with pytest.raises(ParameterError, match=r"one leading step axis \(T,\), T >= 2; got time of shape \(2, 1200\)"):
        soft_bounce_count(rec)
    with pytest.raises(ParameterError, match="records must be a jaxskip.Record .*got NoneType"):
        soft_bounce_count(None)


def test_plot_search_refuses_what_is_not_a_search_result(tmp_path):
    from optimize import plot_search

    for result in ("x", {"best": {}}, None):
        with pytest.raises(ParameterError, match="result must be a SearchResult"):
            plot_search(result, tmp_path / "s.png")
    assert not (tmp_path / "s.png").exists()


def test_make_box_documents_the_limits_it_checks():
    """make_box's docstring gives every parameter's LIMITS (the numbers its checks use) with its unit."""
    from optimize.bounds import LIMITS

    doc = make_box.__doc__
    for name, (low, high, unit) in LIMITS.items():
        assert f"{name:<8}[{low:g}, {high:g}]" in doc and unit in doc, name


def test_gradients_beyond_float32_squares_still_step():
    """A chaotic throw's gradient reaches ~1e20 per unconstrained unit, finite in float32 but not its
    square: optax's global-norm clip then divided by inf and the start took a zero step, frozen, while
    the history recorded an infinite norm. The search scales such a gradient by a power of two first
    (exact: the same direction, still far above the clip) and records its norm in float64."""
    import optax

    from optimize.search import _CLIP_SAFE, _below_overflow

    g = np.array([[2e20, -1e19], [3.0, 4.0], [0.0, 0.0]], dtype=np.float32)
    scaled = _below_overflow(g)
    assert scaled.dtype == np.float32 and np.array_equal(scaled[1:], g[1:])        # ordinary rows untouched
    ratio = g[0] / scaled[0]
    assert ratio[0] == ratio[1] and np.log2(ratio[0]) == np.round(np.log2(ratio[0]))  # a power of two
    assert np.max(np.abs(scaled[0])) <= _CLIP_SAFE
    clip = optax.clip_by_global_norm(1.0)
    raw, _ = clip.update(jnp.asarray(g[0]), clip.init(jnp.asarray(g[0])))
    assert not np.any(np.asarray(raw))                          # the overflow this guards against: no step
    step, _ = clip.update(jnp.asarray(scaled[0]), clip.init(jnp.asarray(scaled[0])))
    step = np.asarray(step, dtype=np.float64)
    assert np.linalg.norm(step) == pytest.approx(1.0, rel=1e-6)
    assert step == pytest.approx(g[0] / np.linalg.norm(g[0].astype(np.float64)), rel=1e-6)


def test_perturbation_search_steps_with_adam_alone_bit_for_bit():
    """The optimizer step compiled once for every learning rate (traced) is plain optax Adam for the
    perturbation search: no clip stage, which rounded its centres differently from the third step on."""
    import optax

    from jaxskip._arrays import float_array
    from optimize.search import _ascend_all, _init_optimizer

    rng = np.random.default_rng(0)
    u0, rate = rng.standard_normal((4, 3)), 0.3
    opt = optax.adam(rate)

    def reference(g, s, u):
        updates, s = opt.update(-g, s, u)
        return optax.apply_updates(u, updates), s

    reference = jax.jit(jax.vmap(reference))
    s_ref, u_ref = jax.vmap(opt.init)(float_array(u0)), float_array(u0)
    s_new, u_new = _init_optimizer(float_array(u0), clipped=False), float_array(u0)
    for _ in range(12):
        g = float_array(rng.standard_normal((4, 3)) * 10.0 ** rng.uniform(-3, 3))
        u_ref, s_ref = reference(g, s_ref, u_ref)
        u_new, s_new = _ascend_all(g, s_new, u_new, float_array(rate), clipped=False)
    np.testing.assert_array_equal(np.asarray(u_new), np.asarray(u_ref))


def test_searches_never_pick_a_diverged_throw_and_warn_once():
    """A throw whose integration failed (outcome 'diverged') was scored by its meaningless count and distance,
    so it could be a search's best. Now it scores -1 bounces and -1 m, is
    never the best, is counted in SearchResult.diverged, and the search issues one DivergedWarning (not one
    per batch, with indices into the batch). A light disk at a 2 ms step, tilt held: 25-50 m/s diverge."""
    import warnings

    from jaxskip import DivergedWarning, clanet_disk, rigid_stone
    from optimize import random_search

    stone = rigid_stone(clanet_disk(), density=100.0)
    config = SimConfig(dt=0.002, max_steps=2000, attitude="fixed")
    box = make_box({"speed": (10.0, 50.0)}, {"tilt": 20.0, "attack": 10.0, "spin": 10.0})
    for search in (functools.partial(random_search, throws=24, seed=3),
                   functools.partial(local_search, centres={"speed": [30.0]}, throws=24, scale=0.5, seed=3,
                                     objective="distance")):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            r = search(box, stone=stone, config=config)
        assert sum(issubclass(w.category, DivergedWarning) for w in caught) == 1
        # (2026-12-06, a review) the coarse step was warned of twice, the first from inside optimize/search.py
        coarse = [w for w in caught if "resolves a contact" in str(w.message)]
        assert len(coarse) == 1 and coarse[0].filename == __file__, [(w.filename, str(w.message)[:50]) for w in coarse]
        assert r.diverged > 0 and r.to_dict()["diverged"] == r.diverged
        assert r.best["speed"] < 25.0  # the best throw is one that did not diverge
        again = simulate_batch(Throw.from_degrees(speed=np.array([r.best["speed"]]), tilt=20.0, attack=10.0,
                                                  spin=10.0), stone, config=config)
        assert again.outcome_names[0] != "diverged" and int(again.bounces[0]) == r.best_bounces


def test_a_search_records_what_it_ran_with_and_runs_again_from_it():
    """(session 32, a review of optimize) a saved result held no seed, starts, iterations, learning rate,
    config or precision: it could not be run again. ``settings`` holds every argument as resolved; a search
    rebuilt from it (through JSON) gives the same result."""
    import json

    from jaxskip import ForceModel, water_params

    import optimize

    box = make_box({"speed": (5.0, 8.0), "tilt": (10.0, 30.0)}, {"attack": 5.0, "spin": 10.0})
    r = optimize.gradient_search(box, config=SimConfig(duration=0.2, max_steps=800), starts=2, iterations=1,
                                 seed=5, learning_rate=0.2, screen=4)
    s = json.loads(json.dumps(r.to_dict()))["settings"]
    assert (s["starts"], s["iterations"], s["seed"], s["learning_rate"], s["screen"], s["polish"]) == (2, 1, 5, 0.2, 4, 0)
    assert s["stone"] == "paper" and s["precision"] == "float64" and s["config"]["duration"] == 0.2
    assert s["config"]["record"] is False   # (as the search ran its throws; it read true, stop 47's review)
    config = SimConfig(**{k: v for k, v in s["config"].items() if k != "force"}, force=ForceModel(**s["config"]["force"]))
    args = {k: v for k, v in s.items() if k not in ("stone", "config", "water", "precision")}
    again = optimize.gradient_search(r.box, stone=s["stone"], config=config, water=water_params(**{
        "c_lift": s["water"]["c_lift"], "c_friction": s["water"]["c_friction"]}), **args)
    assert again.best == r.best and again.best_bounces == r.best_bounces and again.settings == r.settings
    g = optimize.random_search(box, throws=3, seed=2, config=SimConfig(duration=0.1, max_steps=400))
    assert (g.settings["throws"], g.settings["seed"], g.settings["lanes"]) == (3, 2, None)


def test_perturbation_search_takes_no_step_it_never_simulates(monkeypatch):
    """(session 32, a review) the last iteration's Adam step was computed and thrown away: iterations
    evaluations take iterations - 1 steps."""
    import optimize

    calls = []
    real = search_module._ascend_all
    monkeypatch.setattr(search_module, "_ascend_all", lambda *a, **k: calls.append(1) or real(*a, **k))
    r = optimize.perturbation_search(make_box({"speed": (5.0, 8.0)}, {"tilt": 20.0, "attack": 5.0, "spin": 10.0}),
                                     config=SimConfig(duration=0.1, max_steps=400), starts=2, iterations=3, samples=1)
    assert len(calls) == 2 and len(r.history) == 3
    assert list(r.best) == ["speed", "tilt", "attack", "spin"]   # (the held ones came first)


def test_a_search_says_when_its_throws_were_stopped_in_play():
    """(2026-12-06, a review) a random search at a duration of 0.3 s reported 11 bounces (12 with the default
    duration) and no warning; with max_steps 3, 'best 0 bounces'. Now the result counts the throws stopped in
    play (cut_off), says whether the best is one of them, and the search warns once."""
    from jaxskip import AccuracyWarning

    with pytest.warns(AccuracyWarning, match=r"of the 8 exact throws of this random search were still in play when "
                                             r"the run stopped them at duration=0.3 s .*lower bounds, the best throw's"):
        r = random_search(throws=8, config=SimConfig(duration=0.3), seed=0)
    assert r.cut_off >= 1 and r.best_cut_off and r.to_dict()["cut_off"] == r.cut_off
    assert r.history[0]["cut_off"] == r.cut_off
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyWarning)      # (the default duration: nothing cut off here)
        full = random_search(throws=8, seed=0)
    assert full.cut_off == 0 and not full.best_cut_off and full.best_bounces >= r.best_bounces


def test_small_public_helpers_refuse_what_they_cannot_use(tmp_path, paper):
    """(2026-12-07, a review of the optimize API) raw AttributeErrors, IndexErrors, ValueErrors and TypeErrors, or
    silent answers, from the helpers a researcher calls on results: each is a ParameterError naming the argument."""
    from jaxskip import initial_state
    from optimize import distance, make_spec, plot_search, run_sweep
    from optimize.sweep import plot_sweep, umin_resolution, write_results

    r = random_search({"tilt": (10.0, 30.0)}, throws=4, config=SimConfig(duration=0.2))
    for plot, result in ((plot_search, r), (plot_sweep, run_sweep(make_spec("umin", tilts=[20.0], iterations=1,
                                                                               duration=0.3)))):
        with pytest.raises(ParameterError, match=r"path must be a file path .* or a binary file object, got int"):
            plot(result, 5)
    with pytest.raises(ParameterError, match=r"its points and its 'bounces' must give one value per throw"):
        top_throws([{"points": {"speed": [1.0, 2.0]}, "bounces": [1]}], 1)    # gave {'speed': [1.]}
    with pytest.raises(ParameterError, match=r"history entry 1: 'points' must be a dict of the same parameters"):
        top_throws([{"points": {"speed": [1.0]}, "bounces": [1]}, {"points": [1.0], "bounces": [1]}], 1)
    throw = Throw.from_degrees()
    with pytest.raises(ParameterError, match=r"state must be a jaxskip.StoneState, got NoneType"):
        distance(None, throw, paper)
    assert float(distance(initial_state(throw, paper), throw, paper)) < 1e-12
    with pytest.raises(ParameterError, match=r"u must be finite"):
        make_box().to_user(np.array([0.0, np.nan, 0.0, 0.0]))
    with pytest.raises(ParameterError, match=r"speed_range is inverted"):
        umin_resolution((8.0, 1.0), 3)                                        # was -0.097 m/s
    with pytest.raises(ParameterError, match=r"speed_range must be a pair"):
        umin_resolution("ab", 3)
    sweep = run_sweep(make_spec("domain", tilts=[20.0], attacks=[20.0], duration=0.3))
    write_results(sweep, str(tmp_path))                                         # a str folder: was a TypeError
    assert (tmp_path / "result.csv").exists() and (tmp_path / "result.json").exists()


def test_a_search_warns_at_the_users_call():
    """(2026-12-07, a review) a search's stability and accuracy warnings named the search's own lines (or its
    settings-recording wrapper's), whichever search ran: they name the caller's line now."""
    from jaxskip import StabilityWarning

    box, config = make_box({"speed": (30.0, 50.0)}), SimConfig(dt=0.002, duration=0.1)
    for search in (random_search, local_search):
        args = ({"speed": [40.0]},) if search is local_search else ()
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            search(box, *args, throws=2, config=config)
        stability = [w for w in caught if issubclass(w.category, StabilityWarning)]
        assert len(stability) == 1 and stability[0].filename == __file__, [(w.filename, w.lineno) for w in caught]
        assert all(w.filename == __file__ for w in caught), [(w.filename, w.lineno) for w in caught]


def test_an_inert_spin_axis_is_warned_of():
    """(2026-12-07, a review of the CLI) with the tilt held, a search over spin spent its throws on a parameter that
    changes nothing (a grid multiplied its cost by per_axis) and reported a 'best' spin; it is warned of."""
    config = SimConfig(attitude="fixed", duration=0.1)
    with pytest.warns(UserWarning, match=r"spin is searched with attitude='fixed'"):
        random_search({"spin": (0.0, 20.0), "tilt": (10.0, 30.0)}, throws=2, config=config)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        random_search({"tilt": (10.0, 30.0)}, throws=2, config=config)    # spin held: nothing to say
    assert not [w for w in caught if "spin is searched" in str(w.message)]


def test_an_objective_is_nan_for_a_bad_or_diverged_throw_not_zero(paper, water):
    """(stop 46, a review) traced throws cannot be checked, and under jit(vmap(value_and_grad)) a NaN speed scored
    0.0 bounces (with NaN gradients), which an optimiser or an argmax would take as a real point. Both objectives
    give NaN for a non-finite value, a speed not above 0, and a run that diverged; good lanes are untouched."""
    import dataclasses

    from jaxskip import rigid_stone, paper_stone
    from optimize.objectives import make_objective

    config = SimConfig(record=False, max_steps=2000)
    base = Throw.from_degrees(speed=6.0)
    # finite but outside Throw.create's ranges too (stop 48, a review: a tilt of 3 rad scored 0 bounces, the stone
    # flipping at once, and an optax loop stepping past 90 deg saw a real point)
    throws = jax.tree_util.tree_map(lambda *a: jnp.stack(a), base, dataclasses.replace(base, speed=jnp.nan),
                                    dataclasses.replace(base, speed=-3.0), dataclasses.replace(base, tilt=jnp.inf),
                                    dataclasses.replace(base, tilt=3.0), dataclasses.replace(base, attack=-2.0),
                                    dataclasses.replace(base, height=-0.01), dataclasses.replace(base, speed=101.0))
    light = rigid_stone(paper_stone(), density=100.0)     # 100 m/s flat at 0.25 ms: the integration diverges
    fast = Throw.from_degrees(speed=100.0, attack=0.0)
    for kind in ("bounces", "distance"):
        f = make_objective(kind, config, paper, water)
        values, grads = jax.jit(jax.vmap(jax.value_and_grad(f)))(throws)
        values = np.asarray(values)
        assert np.isfinite(values[0]) and values[0] > 0 and np.isfinite(float(grads.speed[0])), (kind, values)
        assert np.all(np.isnan(values[1:])), (kind, values)
        # the bad throws' gradients are 0, not NaN (the default throw ran in their place)
        for g in jax.tree_util.tree_leaves(grads):
            assert np.all(np.asarray(g)[1:] == 0.0), (kind, grads)
        assert np.isnan(float(jax.jit(make_objective(kind, config, light, water))(fast))), kind
        with pytest.raises(ParameterError, match=r"the objective of make_objective\('%s', ...\) takes one throw" % kind):
            f(throws)   # (a batch: the message named soft_bounce_rollout, which the user never called)
