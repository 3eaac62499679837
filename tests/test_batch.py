"""vmap over throws equals one at a time; new throw values never recompile."""

import dataclasses
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxskip import OUTCOMES, SimConfig, Throw, WaterParams, rollout, simulate, simulate_batch
from jaxskip.api import _chunk_program


def stack(throws):
    return jax.tree_util.tree_map(lambda *a: jnp.stack(a), *throws)


THROWS = [(8, 20, 10, 20), (5, 15, 5, 30), (10, 30, 15, 10), (3, 60, 20, 0), (7, 20, 3, 50)]


def test_batch_equals_one_at_a_time(paper, water):
    """Same results to rounding: 1e-12 m through the first contacts; over whole throws the
    same counts and outcomes, positions within 1e-9 m (vmap may order sums differently, and
    contacts amplify that last-bit difference: measured 8e-15 m at 300 steps and 4.9e-12 m at 3000 on
    2026-12-07, when an audit found the 1e-6 m allowed then 2e5 times looser than needed)."""
    throws = [Throw.from_degrees(speed=s, tilt=t, attack=a, spin=f) for s, t, a, f in THROWS]
    for steps, atol in [(300, 1e-12), (3000, 1e-9)]:
        config = SimConfig(record=False, max_steps=steps)
        one = jax.jit(lambda t: rollout(config, t, paper, water)[:2])
        s_b, tr_b = jax.jit(jax.vmap(lambda t: rollout(config, t, paper, water)[:2]))(stack(throws))
        for i, throw in enumerate(throws):
            s, tr = one(throw)
            assert int(tr.bounces) == int(tr_b.bounces[i])
            assert int(tr.contacts) == int(tr_b.contacts[i])
            assert int(tr.outcome) == int(tr_b.outcome[i])
            np.testing.assert_allclose(np.asarray(s.position), np.asarray(s_b.position[i]), rtol=0, atol=atol)


def test_new_throw_values_do_not_recompile(paper, water):
    traces = []
    config = SimConfig(record=False, max_steps=50)

    @jax.jit
    def run(throw, stone, w):
        traces.append(1)  # runs only while tracing
        return rollout(config, throw, stone, w)[0].position

    for speed, tilt in [(5.0, 10.0), (6.0, 20.0), (9.5, 33.0)]:
        run(Throw.from_degrees(speed=speed, tilt=tilt), paper, water)
    from jaxskip import water_params

    run(Throw.from_degrees(), paper, water_params(c_friction=0.2))  # new water constants too
    assert len(traces) == 1


def test_simulate_reuses_its_compiled_chunk():
    config = SimConfig(max_steps=2000)
    simulate(Throw.from_degrees(speed=6.0), config=config, chunk=500)
    runner = _chunk_program(config, 500)
    before = runner._cache_size()
    simulate(Throw.from_degrees(speed=7.5, tilt=25.0, spin=12.0), config=config, chunk=500)
    simulate(Throw.from_degrees(speed=4.0), stone="paper", mass=0.1, config=config, chunk=500)
    # throws and water of Python floats or weakly typed scalars (as a finite-difference check builds them):
    # the same program (they compiled it again)
    simulate(Throw(speed=8.0, tilt=0.3, attack=0.1, spin=100.0, height=0.001, heading=0.0), config=config, chunk=500)
    simulate(dataclasses.replace(Throw.from_degrees(), speed=jnp.asarray(9.0)), config=config, chunk=500)
    simulate(Throw.from_degrees(), water=WaterParams(1.0, 0.3, 1000.0, 9.81), config=config, chunk=500)
    assert runner._cache_size() == before == 1
    # settings a chunk's program does not use (simulate always records, a chunk has no checkpoint, and
    # runs its own number of steps) share it: each compiled a program of its own (~3 s) before
    for other in (dataclasses.replace(config, record=False), dataclasses.replace(config, checkpoint=0),
                  dataclasses.replace(config, max_steps=1500)):
        assert _chunk_program(other, 500) is runner
    # segments longer than the chunk are the chunk (a segment is a skip unit; the default is 50 steps)
    assert _chunk_program(dataclasses.replace(config, segment=500), 500) is _chunk_program(
        dataclasses.replace(config, segment=100_000), 500)
    simulate(Throw.from_degrees(speed=6.0), config=dataclasses.replace(config, max_steps=1500, record=False), chunk=500)
    assert runner._cache_size() == 1


def test_simulate_batch_shares_its_pool_across_settings_it_does_not_use():
    """record, checkpoint and max_steps do not change the pool's programs (a chunk is one segment without
    checkpoints; max_steps only bounds the host loop): one compile serves them all (7-9 s each before)."""
    from jaxskip.batch import _pool, _pool_programs

    config = SimConfig()   # 20250 steps: these throws end long before either step count
    throws = Throw.from_degrees(speed=[5.0, 6.0])
    first = simulate_batch(throws, config=config, chunk=250)
    misses = _pool_programs.cache_info().misses
    for other in (dataclasses.replace(config, record=False), dataclasses.replace(config, checkpoint=0),
                  dataclasses.replace(config, max_steps=20000), dataclasses.replace(config, segment=50)):
        assert _pool(other, first.lanes, 250) is _pool(config, first.lanes, 250)
        again = simulate_batch(throws, config=other, chunk=250)
        np.testing.assert_array_equal(again.bounces, first.bounces)
    assert _pool_programs.cache_info().misses == misses


def test_first_simulate_in_a_fresh_process_compiles_one_program():
    """The first throw's cost is its compile: one program for a 2-chunk throw (the release state
    is computed inside the chunk, the stone, throw and water constants reach the device without
    a compiled lift each, the loop test reads the tracker on the host)."""
    import subprocess
    import sys

    code = ("import logging, jax, jaxskip\n"
            "jax.config.update('jax_enable_x64', True)\n"
            "logging.basicConfig(level=logging.WARNING)\n"
            "jax.config.update('jax_log_compiles', True)\n"
            "r = jaxskip.simulate()\n"
            "print('steps', r.steps)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, check=True)
    compiles = [line for line in out.stderr.splitlines() if "Compiling jit(" in line]
    assert "steps 1147" in out.stdout  # two chunks of 1000 steps: the second one reuses the program
    assert len(compiles) == 1, compiles


def test_simulate_stops_at_max_steps_that_is_not_a_multiple_of_the_chunk(paper, water):
    """simulate() runs exactly ``max_steps`` steps (its last chunk is shortened), like rollout():
    the default throw needs 1147 steps, so 1100 end it by the step limit, at the same state."""
    config = SimConfig(max_steps=1100)
    r = simulate(Throw.from_degrees(), paper, water=water, config=config)
    state, tr, _ = jax.jit(lambda t: rollout(config, t, paper, water))(Throw.from_degrees())
    assert r.outcome == "step_limit" == OUTCOMES[int(tr.outcome)]
    # 1100 records of the state at the start of each step, and the state after the last (which ended
    # no throw: no record held it, so the picture and the export stopped a step short of the result)
    assert r.steps == 1100 and len(r.trajectory["time"]) == 1101
    assert r.trajectory["time"][-1] == r.final_time
    np.testing.assert_allclose(r.trajectory["position"][-1], np.asarray(state.position), rtol=0, atol=1e-12)
    assert r.bounces == int(tr.bounces)
    # The same time to rounding: the chunked program and the rollout are different XLA programs, which an
    # AVX2 host (session 19) rounds apart in the last bits (3e-15 s); a step more or less would be 2.5e-4 s.
    assert r.final_time == pytest.approx(float(state.time), rel=1e-12, abs=0.0)
    short = simulate(Throw.from_degrees(), paper, water=water, config=SimConfig(max_steps=100))
    assert short.outcome == "step_limit" and short.steps == 100


def test_simulate_accepts_a_batch_config():
    """A config made for batches (record=False) still gives simulate() its trajectory."""
    a = simulate(Throw.from_degrees(speed=6.0), config=SimConfig(record=False, max_steps=2000))
    b = simulate(Throw.from_degrees(speed=6.0), config=SimConfig(max_steps=2000))
    assert a.bounces == b.bounces and a.steps == b.steps == len(a.trajectory["time"])
    assert a.distance == b.distance


def test_pool_equals_vmapped_rollout(paper, water):
    """simulate_batch (lanes refilled as throws finish) gives what vmap(rollout) gives."""
    from jaxskip.batch import simulate_batch

    from jaxskip.batch import MIN_LANES_PER_DEVICE

    config = SimConfig(record=False, max_steps=2400)
    # more throws than the narrowest pool has lanes, so that lanes are refilled
    n = 2 * MIN_LANES_PER_DEVICE * jax.local_device_count() + 3
    speed = np.resize([3.0, 8.0, 5.0, 2.0, 7.0, 6.0, 4.0], n)
    tilt = np.resize([20.0, 20.0, 35.0, 10.0, 5.0, 45.0, 15.0, 25.0], n)
    throws = Throw.from_degrees(speed=jnp.asarray(speed), tilt=jnp.asarray(tilt), attack=10.0, spin=20.0)
    pool = simulate_batch(throws, paper, water=water, config=config, lanes=3, chunk=200)
    state, tr, _ = jax.jit(jax.vmap(lambda t: rollout(config, t, paper, water)))(throws)
    np.testing.assert_array_equal(pool.bounces, np.asarray(tr.bounces))
    np.testing.assert_array_equal(pool.outcome, np.asarray(tr.outcome))
    # Two different XLA programs (chunks of 200 steps on refilled lanes vs one scan): fusion may
    # round the last bit differently and contacts amplify it (measured 2.3e-12 m after 2400 steps);
    # the counts and outcomes above are exact.
    np.testing.assert_allclose(pool.state.position, np.asarray(state.position), rtol=0, atol=1e-10)
    np.testing.assert_allclose(pool.tracker.t_start, np.asarray(tr.t_start), rtol=0, atol=1e-12)
    assert pool.lanes == MIN_LANES_PER_DEVICE * jax.local_device_count()   # lanes=3 is raised to the minimum
    assert len(set(pool.bounces.tolist())) > 2 and pool.lane_steps < n * config.max_steps  # refills did happen
    assert set(pool.outcome_names) <= set(OUTCOMES)


def test_a_throws_numbers_do_not_depend_on_its_batch(paper, water):
    """The same throw, alone, in a batch of 5 and in a batch of 40, with the default lanes and with lanes=1:
    the same bits. (XLA:CPU compiled a pool of 1-4 lanes a device differently from a wider one, and a
    sweep's numbers moved with its chunk size and device count: measured 68-74 of 256 chaotic counts.)"""
    from jaxskip.batch import simulate_batch

    config = SimConfig(record=False, max_steps=2000)
    rng = np.random.default_rng(3)
    big = Throw.from_degrees(speed=jnp.asarray(rng.uniform(5.0, 9.0, 40)), tilt=jnp.asarray(rng.uniform(10.0, 30.0, 40)),
                             attack=jnp.asarray(rng.uniform(2.0, 15.0, 40)), spin=20.0)
    first = lambda t, k: jax.tree_util.tree_map(lambda a: a[:k], t)  # noqa: E731
    runs = [simulate_batch(first(big, 1), paper, water=water, config=config),
            simulate_batch(first(big, 5), paper, water=water, config=config),
            simulate_batch(first(big, 5), paper, water=water, config=config, lanes=1),
            simulate_batch(big, paper, water=water, config=config)]
    for r in runs[1:]:
        k = min(5, len(r.bounces))
        np.testing.assert_array_equal(r.state.position[:1], runs[0].state.position)
        np.testing.assert_array_equal(r.state.position[:k], runs[1].state.position[:k])
        np.testing.assert_array_equal(r.tracker.t_start[:k], runs[1].tracker.t_start[:k])
    assert runs[3].bounces.max() >= 3


def test_a_stone_planing_for_the_whole_duration_ends_by_the_time_limit(paper, water):
    """The default step budget covers ``duration`` in the water and the step that ends it: a 30 m/s throw
    at 2 deg of tilt skims the water for all 5 s and ends by ``time_limit`` (with 20000 steps it ended one
    step short, by ``step_limit``). Its hops are so low that every step is about ``dt``, but whether a
    few of them are jumped depends on rounding (LLVM's optimisation level moved the count by 3), so
    the budget's worst case, every step exactly ``dt``, is checked with ``flight="step"``."""
    throw = Throw.from_degrees(speed=30.0, tilt=2.0, attack=0.0)
    r = simulate(throw, paper, water=water)
    assert r.outcome == "time_limit", (r.outcome, r.final_time, r.steps)
    r = simulate(throw, paper, water=water, config=SimConfig(flight="step"))
    assert r.outcome == "time_limit", (r.outcome, r.final_time, r.steps)
    assert r.steps == math.ceil(SimConfig().duration / SimConfig().dt) + 1 <= SimConfig().max_steps


def test_memoised_stone_and_water_follow_the_public_dicts(monkeypatch):
    """simulate() memoises built-in stones and default water constants; a stone registered again under
    its name in BUILTIN_STONES is used, not the memo (simulate kept the old stone). The default coefficients
    are read-only since stop 48 (test_validation.py, test_the_module_tables_a_call_reads_are_read_only): a whole
    table put in their place is followed by simulate and simulate_batch alike (simulate kept c_lift 1.0 while
    simulate_batch used a new 0.5)."""
    import functools

    import types

    from jaxskip import api, forces, rigid_stone, stones

    config = SimConfig(max_steps=400)
    throw = Throw.from_degrees(speed=7.0)
    before = simulate(throw, "disk", config=config)
    bigger = (functools.partial(stones.disk, 0.06, 0.01), stones.STONE_DENSITY)
    monkeypatch.setitem(stones.BUILTIN_STONES, "disk", bigger)
    after = simulate(throw, "disk", config=config)
    assert after.mass == pytest.approx(float(rigid_stone(stones.disk(0.06, 0.01), density=stones.STONE_DENSITY).mass))
    assert after.mass > 2.0 * before.mass
    table = types.MappingProxyType({**forces.DEFAULT_COEFFICIENTS, "bocquet": types.MappingProxyType(
        dict(c_lift=0.5, c_friction=0.3))})
    for module in (forces, api):   # (api reads it by its own name)
        monkeypatch.setattr(module, "DEFAULT_COEFFICIENTS", table)
    one = simulate(throw, config=config)
    many = simulate_batch(Throw.from_degrees(speed=[7.0]), config=config)
    assert float(one.water.c_lift) == 0.5
    assert one.distance == pytest.approx(float(many.distance[0]), abs=1e-9)


def test_results_print_short_and_keep_the_throws_as_simulated(paper, water):
    """(2026-12-06, a review) the results' dataclass reprs printed every array (18-97 k characters);
    BatchResult.throws held the user's float16 / JAX arrays, not the float arrays simulated; a face tilted
    leading edge down read -180 deg on some headings, outside the documented (-180, 180]."""
    r = simulate(Throw.from_degrees(), stone="paper", water=water)
    assert repr(r) == "ThrowResult(18 bounces over 1.742 m, sank after 0.375 s in 1147 steps; paper stone of 120.7 g)"
    one = dataclasses.replace(r, steps=1, bounces=1)   # (read "1 steps" before 2026-12-07)
    assert "1 bounce over" in repr(one) and "in 1 step;" in repr(one)
    b = simulate_batch(Throw.from_degrees(speed=np.linspace(4.0, 9.0, 8).astype(np.float16)), paper, water=water)
    assert len(repr(b)) < 200 and repr(b).startswith("BatchResult(8 throws: bounces ")
    assert isinstance(b.throws.speed, np.ndarray) and b.throws.speed.dtype == np.float64
    for heading in (0.0, 45.0):
        c = simulate(Throw.from_degrees(tilt=-20.0, speed=10.0, heading=heading), stone=paper, water=water).contacts[0]
        assert -math.pi < c.tilt_direction_start <= math.pi and c.to_dict()["tilt_direction_start_deg"] != -180.0


def test_a_batch_result_is_json_ready(paper, water):
    """(2026-12-06, a review) a BatchResult had no to_dict, and its outcome names (an object array) did not
    serialise: saving a batch needed hand conversion. to_dict gives per-throw lists in user units."""
    import json

    throws = Throw.from_degrees(speed=np.array([6.0, 8.0]), tilt=20.0, attack=5.0, spin=np.array([10.0, 20.0]))
    b = simulate_batch(throws, paper, water=water)
    d = json.loads(json.dumps(b.to_dict(), allow_nan=False))
    assert d["bounces"] == b.bounces.tolist() and d["outcome"] == b.outcome_names.tolist()
    assert d["throws"]["spin_rev_s"] == pytest.approx([10.0, 20.0]) and d["throws"]["tilt_deg"] == pytest.approx([20.0] * 2)
    assert d["distance"] == pytest.approx(b.distance.tolist())


def test_a_chunk_that_does_not_divide_max_steps_still_stops_every_throw_at_max_steps(paper, water):
    """(stop 46, a review) chunk had to divide max_steps, so a prime max_steps got a chunk of 1 (a host round trip a
    step: 22x slower for 100003) or of max_steps (3.5x for 20249). chunk_for stays near 250 now, and a throw still
    in play after its last whole chunk runs the rest in a shorter program: the step limit is where rollout's is."""
    from jaxskip.batch import chunk_for, simulate_batch

    assert (chunk_for(20249), chunk_for(100003), chunk_for(20250), chunk_for(50)) == (250, 250, 250, 50)
    config = SimConfig(record=False, max_steps=1001)
    rng = np.random.default_rng(0)
    n = 20
    throws = Throw.from_degrees(speed=jnp.asarray(rng.uniform(3, 12, n)), tilt=jnp.asarray(rng.uniform(5, 45, n)),
                                attack=jnp.asarray(rng.uniform(0, 30, n)), spin=jnp.asarray(rng.uniform(0, 20, n)))
    pool = simulate_batch(throws, paper, water=water, config=config, chunk=250)
    state, tr, _ = jax.jit(jax.vmap(lambda t: rollout(config, t, paper, water)))(throws)
    assert pool.chunk == 250 and np.sum(pool.outcome_names == "step_limit") >= 3
    np.testing.assert_array_equal(pool.outcome, np.asarray(tr.outcome))
    np.testing.assert_array_equal(pool.bounces, np.asarray(tr.bounces))
    # (a step more or less would move the time by dt = 2.5e-4 s; measured equal)
    np.testing.assert_allclose(pool.final_time, np.asarray(state.time), rtol=1e-12, atol=0)


def test_a_held_throw_that_gains_energy_is_warned_of_in_a_batch_too():
    """(stop 46, a review) simulate warns when a throw held at its tilt gains energy (only the step can add it);
    simulate_batch said nothing: the light Clanet disk under the seed law at 24 m/s ends 11 % above its release
    energy. It warns now (from the end state), naming the throw; a batch of sound held throws does not."""
    import warnings

    from jaxskip import ForceModel, StabilityWarning

    config = SimConfig(attitude="fixed", force=ForceModel(law="seed"), record=False)
    throws = Throw.from_degrees(speed=np.array([4.0, 24.0]), tilt=5.0, attack=10.0, spin=20.0)
    with pytest.warns(StabilityWarning, match=r"1 of 2 throws held at their tilt ended with more mechanical energy "
                                              r"than at release, by over 1 % \(up to 1\d\.?\d* %; indices \[1\]\)"):
        simulate_batch(throws, "clanet", config=config)
    with warnings.catch_warnings():
        warnings.simplefilter("error", StabilityWarning)
        simulate_batch(Throw.from_degrees(speed=np.array([4.0, 8.0]), tilt=20.0), config=dataclasses.replace(
            config, force=ForceModel()))


def test_a_contact_the_stone_left_before_the_run_ended_has_its_end_as_in_simulate():
    """(stop 46, a review) a run that ended after the last contact's stone left the water but before a bounce was
    confirmed: simulate gives the contact's end where the stone left; simulate_batch left it NaN ("not ended")."""
    from jaxskip.simulate import LEAVING

    config = SimConfig(duration=0.459)
    throw = dict(speed=9.89128324247895, tilt=9.115500964580377, attack=5.220296030373842, spin=18.824397337836878)
    one = simulate(Throw.from_degrees(**throw), config=config)
    batch = simulate_batch(Throw.from_degrees(**{k: np.array([v]) for k, v in throw.items()}), config=config)
    k = one.n_contacts
    assert int(batch.tracker.phase[0]) == LEAVING and batch.n_contacts[0] == k and one.outcome == "time_limit"
    last = one.contacts[-1]
    assert last.t_end < one.final_time
    assert float(batch.tracker.t_end[0, k - 1]) == pytest.approx(last.t_end, abs=1e-12)
    assert float(batch.tracker.tilt_end[0, k - 1]) == pytest.approx(last.tilt_end, abs=1e-12)


def test_a_batch_result_says_what_produced_it():
    """(stop 46, a review) a batch's to_dict() held the throws and outcomes but not the stone, its mass, the water or
    the simulation settings, so a saved batch could not be run again; its ``parameters`` are simulate's now."""
    import json

    from jaxskip import ForceModel

    config = SimConfig(record=False, attitude="fixed", dt=2e-4, force=ForceModel(law="seed"))
    d = simulate_batch(Throw.from_degrees(speed=np.array([5.0, 7.0])), "clanet", mass=0.02, config=config).to_dict()
    one = simulate(Throw.from_degrees(speed=5.0), "clanet", mass=0.02, config=config).to_dict()["parameters"]
    throw_keys = {"speed", "tilt_deg", "attack_deg", "spin_rev_s", "height", "heading_deg"}
    assert d["parameters"] == {k: v for k, v in one.items() if k not in throw_keys}
    assert d["parameters"]["stone"] == "clanet" and d["parameters"]["mass"] == pytest.approx(0.02)
    assert d["parameters"]["force_law"] == "seed" and d["parameters"]["dt"] == 2e-4 and d["chunk"] >= 1
    json.dumps(d)
