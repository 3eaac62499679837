"""The O'Brien–Hodgins height field (jaxskip.water): conservation, waves, clamps, stability, gradients."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxskip import ParameterError
from jaxskip.water import (WaterGrid, height_at, make_water_step, run_water, stable_dt, still_water,
                           total_volume, water_substeps)


def _scan_min(grid, state, steps, pressure=None):
    """Run ``steps`` steps; return the final state and the lowest column height seen, as the clamped flows
    leave it before the step sets a rounding below zero to zero (the returned flows are the ones that moved the
    water: the clamped ones, on a sponge grid relaxed first; the sponge's relaxation of the heights towards the
    rest depth then keeps a non-negative column non-negative). (2026-12-06, an audit: the step's own heights are
    never below zero, so a test of them could not fail; with the clamp's margin broken this one does.)"""
    from jaxskip.water import _net_out

    step = make_water_step(grid)
    p = jnp.zeros(grid.shape) if pressure is None else pressure

    @jax.jit
    def go(s):
        def body(c, _):
            new = step(c, p)
            unclipped = c.height - (grid.time_step / grid.spacing ** 2) * _net_out(new.qx, new.qy, new.qd, new.qa)
            return new, jnp.minimum(jnp.min(new.height), jnp.min(unclipped))
        return jax.lax.scan(body, s, None, length=steps)

    final, lows = go(state)
    return final, float(jnp.min(lows))


def _drying(clamp="reference", shape=(32, 32), **kw):
    """Shallow water (5 mm) with a 15 mm mound: the troughs dry out, so the clamp must act."""
    grid = WaterGrid(shape=shape, spacing=0.01, depth=0.005, clamp=clamp, **kw)
    X, Y = grid.column_centres()
    c = 0.01 * (shape[0] - 1) / 2
    h0 = grid.depth + 0.015 * jnp.exp(-((X - c) ** 2 + (Y - c) ** 2) / (2 * 0.03 ** 2))
    return grid, still_water(grid, h0)


def test_still_water_stays_still():
    """Flat water, with or without a uniform external pressure, does not move (exactly)."""
    for clamp in ("reference", "zero", "smooth"):
        grid = WaterGrid(shape=(20, 24), spacing=0.02, depth=0.1, clamp=clamp)
        s = run_water(grid, still_water(grid), 500, pressure=jnp.full(grid.shape, 250.0))
        assert float(jnp.max(jnp.abs(s.height - grid.depth))) == 0.0
        assert float(jnp.max(jnp.abs(s.qx))) == 0.0


def test_volume_conserved_with_reference_clamp():
    """10^4 steps, closed boundaries, columns drying out: total volume to 1e-10 relative.
    The seed's zeroing clamp (eq. 4) on the same scene adds volume — the clamp is really active."""
    grid, s0 = _drying("reference")
    v0 = float(total_volume(grid, s0))
    s, low = _scan_min(grid, s0, 10_000)
    assert low >= 0.0
    assert low < 1e-4 * grid.depth            # columns did run dry: the clamp was exercised
    assert abs(float(total_volume(grid, s)) - v0) / v0 < 1e-10
    gz, z0 = _drying("zero")
    sz = run_water(gz, z0, 10_000)
    assert (float(total_volume(gz, sz)) - v0) / v0 > 1e-6


@pytest.mark.parametrize("clamp,iterations", [("reference", 4), ("reference", 0), ("smooth", 4)])
def test_no_column_goes_negative(clamp, iterations):
    """Every pass of the clamp is safe, even with no relaxation passes at all; volume conserved."""
    grid, s0 = _drying(clamp, clamp_iterations=iterations)
    v0 = float(total_volume(grid, s0))
    s, low = _scan_min(grid, s0, 3000)
    assert low >= 0.0
    assert low < 1e-4 * grid.depth            # columns did run dry (measured 1e-37 to 1e-20 of the depth)
    assert abs(float(total_volume(grid, s)) - v0) / v0 < 1e-10


@pytest.mark.parametrize("clamp", ["reference", "smooth"])
def test_no_column_goes_negative_on_a_sponge_grid(clamp):
    """With a sponge border the flows are relaxed in the flow update, before the clamp, so the clamp sees the
    flows that move the water and no column goes below zero (2026-12-06: the relaxation came after the height
    update before; a relaxation after the clamp would cut inflows the clamp had counted on)."""
    grid, s0 = _drying(clamp, boundary="sponge", sponge_width=8, sponge_rate=20.0)
    X, Y = grid.column_centres()
    c = 0.01 * (grid.shape[0] - 1) / 2
    # 3 cm of head on 5 mm of water, centred 4 columns from the edge, inside the sponge, where the pipes relax
    # (relaxed after the clamp instead, the drained columns there dipped to -1.8e-5 m: measured 2026-12-06)
    push = 300.0 * jnp.exp(-((X - 0.04) ** 2 + (Y - c) ** 2) / (2 * 0.015 ** 2))
    _, low = _scan_min(grid, s0, 3000, push)
    assert low >= 0.0
    assert low < 1e-4 * grid.depth            # columns did run dry under the push: the clamp was exercised


@pytest.mark.parametrize("clamp", ["reference", "smooth"])
def test_no_column_goes_negative_in_float32(clamp):
    """The same scene in float32, JAX's default precision: the clamp's margin follows the dtype's round-off
    (a fixed 1e-9 vanished in 1 + 1e-9, and drained columns dipped to -2e-10 m in 100 of 3000 steps)."""
    with jax.enable_x64(False):
        grid, s0 = _drying(clamp)
        assert s0.height.dtype == jnp.float32
        _, low = _scan_min(grid, s0, 3000)
    assert low >= 0.0


def test_the_pure_step_checks_the_pressure_shape():
    """make_water_step's step took a (ny,) pressure and broadcast it over the rows in silence."""
    grid = WaterGrid(shape=(8, 6), spacing=0.01, depth=0.02)
    step = make_water_step(grid)
    s = still_water(grid)
    for bad in (jnp.zeros(6), jnp.zeros((6, 8)), jnp.zeros(())):
        with pytest.raises(ParameterError, match=r"must have the grid's shape \(8, 6\)"):
            step(s, bad)
    assert step(s, jnp.zeros(grid.shape)).height.shape == grid.shape


def test_unclamped_scheme_would_go_negative():
    """Without scaling, the same scene drives columns below zero: the clamp tests are not vacuous."""
    grid, s0 = _drying("reference")
    step = make_water_step(dataclasses.replace(grid, clamp="zero"))
    lows = []
    s = s0
    for _ in range(200):
        s = step(s, jnp.zeros(grid.shape))
        lows.append(float(jnp.min(s.height)))
    assert min(lows) == 0.0    # the zeroing clamp had to clip (a negative column was produced)


def _peak(profile, spacing):
    """Sub-cell position of the maximum of a sampled 1-D profile (parabola through 3 points)."""
    i = int(np.argmax(profile))
    a, b, c = profile[i - 1], profile[i], profile[i + 1]
    return (i + 0.5 * (a - c) / (a - 2 * b + c)) * spacing


def test_small_bump_spreads_at_shallow_water_speed():
    """A small bump spreads at sqrt(gH) within 5 %, along the axes and along the diagonals."""
    grid = WaterGrid(shape=(161, 161), spacing=0.01, depth=0.1, cfl=0.3)
    X, Y = grid.column_centres()
    c0 = 0.8
    h0 = grid.depth + 1e-4 * jnp.exp(-((X - c0) ** 2 + (Y - c0) ** 2) / (2 * 0.03 ** 2))
    n1, n2 = 80, 200
    s1 = run_water(grid, still_water(grid, h0), n1)
    s2 = run_water(grid, s1, n2 - n1)
    r = np.linspace(0.0, 0.7, 701)
    ds = r[1] - r[0]
    elapsed = (n2 - n1) * grid.time_step
    for direction in [(1, 0), (0, 1), (-1, 0), (1, 1), (-1, 1), (1, -1)]:
        u = np.asarray(direction, float) / np.hypot(*direction)
        prof = [np.asarray(height_at(grid, s.height, c0 + r * u[0], c0 + r * u[1])) for s in (s1, s2)]
        speed = (_peak(prof[1], ds) - _peak(prof[0], ds)) / elapsed
        assert speed == pytest.approx(grid.wave_speed, rel=0.05), direction


def test_smooth_clamp_converges_to_reference():
    """On a drying scene, the smooth clamp's heights approach the reference's as sharpness grows."""
    grid, s0 = _drying("reference")
    ref = run_water(grid, s0, 400).height
    errs = []
    for k in (3.0, 10.0, 30.0, 100.0, 1000.0):
        g = dataclasses.replace(grid, clamp="smooth", sharpness=k)
        errs.append(float(jnp.max(jnp.abs(run_water(g, s0, 400).height - ref))))
    assert all(b < a for a, b in zip(errs, errs[1:])), errs
    assert errs[-1] < 1e-3 * grid.depth, errs


def test_stable_at_bound_unstable_beyond():
    """The derived bound sqrt(3)/2 l/sqrt(gH) is sharp: at the bound (accepted by the grid) and at 0.99
    of it random ripples stay bounded over 1000 steps, at 1.05 of it the checkerboard mode explodes.
    The grid refuses a dt beyond the bound. (Measured, largest ripple / initial noise: 1.33 at 0.99,
    2.38 at the bound, where the checkerboard mode is neutral: at most 1.65 and 2.4 over 4000 steps.)"""
    bound = stable_dt(0.01, 0.1)
    noise = 1e-6 * np.random.default_rng(0).standard_normal((24, 24))
    amp = {}
    for factor in (0.99, 1.0, 1.05):
        if factor <= 1.0:
            grid = WaterGrid(shape=(24, 24), spacing=0.01, depth=0.1, dt=factor * bound)
        else:
            grid = WaterGrid(shape=(24, 24), spacing=0.01, depth=0.1)
            object.__setattr__(grid, "dt", factor * bound)   # bypass the guard to show what it guards
        s = run_water(grid, still_water(grid, grid.depth + noise), 1000)
        amp[factor] = float(jnp.max(jnp.abs(s.height - grid.depth)))
    assert amp[0.99] < 2 * np.abs(noise).max(), amp
    assert amp[1.0] < 3 * np.abs(noise).max(), amp
    assert not np.isfinite(amp[1.05]) or amp[1.05] > 1e3 * np.abs(noise).max()
    with pytest.raises(ParameterError, match="dt"):
        WaterGrid(shape=(24, 24), spacing=0.01, depth=0.1, dt=1.01 * bound)
    grid = WaterGrid(shape=(24, 24), spacing=0.01, depth=0.1)
    n = water_substeps(grid, 0.02)
    assert 0.02 / n <= bound and 0.02 / (n - 1) > grid.time_step


def test_checkerboard_at_the_bound_swings_but_stays_bounded():
    """The stiffest mode, started on its own, at exactly the bound over 4 x 10^4 steps: symplectic Euler keeps
    it bounded (no secular growth: the last 10^4 steps swing no wider than 1.5x the first 10^4; measured
    28x and 24x the start, 29x at most, and 32x at most over 10^5 steps), though near-checkerboard modes
    swing to many times their start; at the default cfl 0.5, over 10^4 steps, to a few times (3.0x)."""
    bound = stable_dt(0.01, 0.1)
    i, j = np.indices((16, 16))
    start = 1e-6 * (-1.0) ** (i + j)
    widest = {}
    for cfl in (1.0, 0.5):
        grid = WaterGrid(shape=(16, 16), spacing=0.01, depth=0.1, dt=cfl * bound)
        s, swing = still_water(grid, grid.depth + start), []
        for _ in range(40 if cfl == 1.0 else 10):
            s = run_water(grid, s, 1000)
            swing.append(float(jnp.max(jnp.abs(s.height - grid.depth))) / 1e-6)
        widest[cfl] = (max(swing[:10]), max(swing[-10:]), max(swing))
    first, last, most = widest[1.0]
    assert 5.0 < first and last < 1.5 * first and most < 50.0, widest
    assert widest[0.5][2] < 5.0, widest


def _probe(grid, steps, checkpoint=True):
    """The height at two probe columns after ``steps`` steps from a mound of height ``a`` [m] on
    shallow water (troughs dry out, so the clamp acts): ``f(a)`` [m] (pure; steps checkpointed for
    reverse mode unless ``checkpoint`` is false) and its jit-compiled gradient."""
    step = make_water_step(grid)
    p = jnp.zeros(grid.shape)
    X, Y = grid.column_centres()
    body = lambda c, _: (step(c, p), None)  # noqa: E731

    def f(a):
        h0 = grid.depth + a * jnp.exp(-((X - 0.1) ** 2 + (Y - 0.12) ** 2) / (2 * 0.03 ** 2))
        s = jax.lax.scan(jax.checkpoint(body) if checkpoint else body, still_water(grid, h0), None, length=steps)[0]
        return s.height[5, 7] + s.height[18, 3]

    return f, jax.jit(jax.grad(f))


def test_gradients_through_1000_steps_match_finite_differences():
    """d(height at a probe after 1000 smooth-clamped steps)/d(mound height), with columns drying."""
    f, grad = _probe(WaterGrid(shape=(24, 24), spacing=0.01, depth=0.005, clamp="smooth", sharpness=20.0), 1000)
    f = jax.jit(f)
    a = 0.012
    g = float(grad(a))
    # Drying makes the probe strongly curved in a after 1000 steps: central differences converge
    # to the AD value as h shrinks (1e-5: 8e-3 off, 1e-6: 8e-5, 1e-7: 8e-7, 1e-8: 1e-8).
    h = 1e-8
    fd = (float(f(a + h)) - float(f(a - h))) / (2 * h)
    assert np.isfinite(g)
    assert g == pytest.approx(fd, rel=1e-6)


def test_clamp_gradient_quality():
    """The clamps' derivatives compared (issue: "gradient quality"). The derivative of the probe of
    :func:`_probe` w.r.t. the mound height matches central differences for the reference and the
    smooth clamp alike, but across mound heights it is rough where the clamp switches columns on
    and off, and a soft smooth clamp smooths it: roughness (mean |2nd difference| / mean |value|
    over 9 heights, 300 steps) measured 0.47 for the reference, 0.12 at k = 5, 0.43 at k = 20
    (at 500 steps over 13 heights: 0.69 reference, 0.16 / 0.45 / 0.68 at k = 5 / 20 / 50, the
    default; `benchmarks/water_clamps.py` charts it). The zero clamp adds water (tested above)."""
    amps = np.linspace(0.010, 0.016, 9)
    h = 1e-8
    probes = np.concatenate([amps, amps[::4] + h, amps[::4] - h])
    rough = {}
    for label, kw in [("reference", dict(clamp="reference")), ("k=5", dict(clamp="smooth", sharpness=5.0))]:
        f, _ = _probe(WaterGrid(shape=(24, 24), spacing=0.01, depth=0.005, **kw), 300, checkpoint=False)
        # forward mode, all heights in one call: the same derivative as reverse mode, far cheaper here
        value, slope = jax.jit(jax.vmap(lambda a: jax.jvp(f, (a,), (jnp.ones_like(a),))))(jnp.asarray(probes))
        value, ad = np.asarray(value), np.asarray(slope)[:amps.size]
        k = amps[::4].size
        fd = (value[amps.size:amps.size + k] - value[amps.size + k:]) / (2 * h)
        np.testing.assert_allclose(ad[::4], fd, rtol=1e-5, err_msg=label)
        rough[label] = np.abs(np.diff(ad, 2)).mean() / np.abs(ad).mean()
    assert rough["k=5"] < 0.5 * rough["reference"], rough


def test_batch_equals_one_at_a_time():
    grid = WaterGrid(shape=(16, 20), spacing=0.01, depth=0.02, clamp="smooth")
    X, Y = grid.column_centres()
    amps = jnp.array([0.0, 0.005, 0.02])
    h0 = grid.depth + amps[:, None, None] * jnp.exp(-((X - 0.07) ** 2 + (Y - 0.1) ** 2) / 0.001)[None]
    step = make_water_step(grid)
    p = jnp.zeros(grid.shape)
    run = lambda h: jax.lax.scan(lambda c, _: (step(c, p), None), still_water(grid, h), None, length=300)[0]
    batch = jax.jit(jax.vmap(run))(h0)
    for i in range(3):
        one = jax.jit(run)(h0[i])
        np.testing.assert_allclose(np.asarray(batch.height[i]), np.asarray(one.height), rtol=0, atol=1e-15)


def test_sponge_absorbs_waves_closed_box_keeps_them():
    """After the ring has reached the edges, a sponge border has taken most of the wave energy out;
    the closed box still holds it (reflected)."""
    def energy_left(boundary):
        grid = WaterGrid(shape=(64, 64), spacing=0.01, depth=0.05, boundary=boundary, sponge_width=10)
        X, Y = grid.column_centres()
        h0 = grid.depth + 1e-4 * jnp.exp(-((X - 0.315) ** 2 + (Y - 0.315) ** 2) / (2 * 0.02 ** 2))
        s0 = still_water(grid, h0)
        s = run_water(grid, s0, 600)            # ~4 crossings of the box
        e = lambda st: float(jnp.sum((st.height - grid.depth) ** 2))
        return e(s) / e(s0)
    closed, sponge = energy_left("closed"), energy_left("sponge")
    assert sponge < 0.05 * closed



def test_damping_takes_wave_energy_out_at_its_rate():
    """``WaterGrid.damping`` = γ [1/s] damps every pipe flow as q' = -γ q, so a weakly damped wave
    (γ well below its frequency) loses energy as exp(-γ t): the surface's variance about its mean,
    averaged over 100 steps (many periods, potential and kinetic energy trading places), relative to
    the same run undamped. Measured ratios: 1.002 / 0.999 / 1.001 at γ = 0.5, 1.010 / 1.003 / 1.007 at
    γ = 1 (closer to 1 the weaker the damping; at γ = 5 the slowest modes are near critical and the
    ratio is 1.24-1.32). Volume is untouched by damping (flows are only scaled)."""
    grid0 = WaterGrid(shape=(32, 32), spacing=0.01, depth=0.1)
    X, Y = grid0.column_centres()
    h0 = grid0.depth + 1e-3 * jnp.exp(-((X - 0.155) ** 2 + (Y - 0.155) ** 2) / (2 * 0.02 ** 2))

    def variance(gamma):
        grid = dataclasses.replace(grid0, damping=gamma)
        step, p = make_water_step(grid), jnp.zeros(grid.shape)

        def body(s, _):
            s = step(s, p)
            return s, jnp.sum((s.height - jnp.mean(s.height)) ** 2)
        s0 = still_water(grid, h0)
        s, e = jax.jit(lambda s: jax.lax.scan(body, s, None, length=400))(s0)
        v0 = float(total_volume(grid, s0))
        assert abs(float(total_volume(grid, s)) - v0) < 1e-12 * v0
        return np.asarray(e)

    e0, dt = variance(0.0), grid0.time_step
    for gamma in (0.5, 1.0):
        e = variance(gamma)
        for a in (100, 200, 300):
            t = dt * (a + 50)
            ratio = e[a:a + 100].mean() / e0[a:a + 100].mean()
            assert abs(ratio / np.exp(-gamma * t) - 1.0) < 0.02, (gamma, t, ratio, np.exp(-gamma * t))

def test_height_at_is_bilinear():
    grid = WaterGrid(shape=(10, 12), spacing=0.05, depth=0.1, origin=(-0.2, 0.3))
    X, Y = grid.column_centres()
    h = grid.depth + 0.01 * X - 0.02 * Y + 0.003
    x = jnp.array([-0.2, 0.013, 0.21, 0.24])
    y = jnp.array([0.3, 0.41, 0.77, 0.84])
    np.testing.assert_allclose(np.asarray(height_at(grid, h, x, y)), np.asarray(0.01 * x - 0.02 * y + 0.003),
                               atol=1e-14)


@pytest.mark.parametrize("kwargs,name", [
    (dict(spacing=0.0), "spacing"), (dict(spacing=-1.0), "spacing"), (dict(depth=float("nan")), "depth"),
    (dict(depth=0.0), "depth"), (dict(shape=(2, 10)), "shape"), (dict(shape=(10,)), "shape"),
    (dict(shape=(5000, 5000)), "shape"), (dict(shape=(10.0, 10)), "shape"), (dict(clamp="clip"), "clamp"),
    (dict(sharpness=0.5), "sharpness"), (dict(cfl=1.5), "cfl"), (dict(boundary="open"), "boundary"),
    (dict(dt=-1e-3), "dt"), (dict(damping=-1.0), "damping"),
])
def test_bad_grid_input(kwargs, name):
    with pytest.raises(ParameterError, match=name):
        WaterGrid(**kwargs)


def test_new_water_data_does_not_recompile():
    """run_water compiles once per (grid, steps): new heights and pressures reuse it."""
    from jaxskip.water import _water_runner

    grid = WaterGrid(shape=(12, 14), spacing=0.01, depth=0.03)
    run_water(grid, still_water(grid), 7)
    runner = _water_runner(grid, 7)
    before = runner._cache_size()
    run_water(grid, still_water(grid, grid.depth + 0.001 * jnp.ones(grid.shape)), 7)
    run_water(grid, still_water(grid), 7, pressure=jnp.full(grid.shape, 10.0))
    # the grid somewhere else: the water step does not use where it is (it compiled again before)
    misses = _water_runner.cache_info().misses
    run_water(dataclasses.replace(grid, origin=(2.0, -1.0)), still_water(grid), 7)
    assert runner._cache_size() == before == 1 and _water_runner.cache_info().misses == misses


@pytest.mark.parametrize("clamp", ["reference", "smooth"])
def test_clamp_on_a_block_gives_the_whole_grid_answer(clamp):
    """A dent moving across shallow water drains the columns under and behind it. Running the
    clamp on a small block around them (``clamp_blocks``) gives the same water as clamping the
    whole grid, step after step; so do the larger block when a second dent (from step 120) drains
    columns the first block cannot hold with the moving one's, and the whole grid when a third,
    distant one (from step 200) leaves no block that holds them all."""
    grid = WaterGrid(shape=(48, 40), spacing=0.01, depth=0.005, clamp=clamp)
    whole, block = make_water_step(grid), make_water_step(grid, clamp_blocks=((8, 6), (14, 12)))

    def pressure(k):   # 200 Pa (2 cm of water on 5 mm) on 3 x 3 columns, one column further every 8 steps
        moving = jax.lax.dynamic_update_slice(jnp.zeros(grid.shape), jnp.full((3, 3), 200.0), (8 + k // 8, 18))
        near = jnp.zeros(grid.shape).at[30:33, 12:15].set(200.0)   # with the moving one: the 2nd block
        far = jnp.zeros(grid.shape).at[40:43, 2:5].set(200.0)      # no block: the whole grid
        return moving + jnp.where(k >= 120, 1.0, 0.0) * near + jnp.where(k >= 200, 1.0, 0.0) * far

    @jax.jit
    def run(s0):
        def body(c, k):
            a, b = c
            p = pressure(k)
            return (whole(a, p), block(b, p)), jnp.min(a.height)
        return jax.lax.scan(body, (s0, s0), jnp.arange(240))

    (a, b), lows = run(still_water(grid))
    assert float(jnp.min(lows)) < 1e-3 * grid.depth          # the clamp really acted
    for x, y in zip(jax.tree_util.tree_leaves(a), jax.tree_util.tree_leaves(b)):
        np.testing.assert_allclose(np.asarray(y), np.asarray(x), rtol=1e-12, atol=1e-18)


@pytest.mark.parametrize("blocks", [((0, 4),), ((4,),), ((49, 4),), ([4, 4],), ((4.0, 4),), (4, 4), [(4, 4)]])
def test_bad_clamp_blocks(blocks):
    grid = WaterGrid(shape=(48, 40), spacing=0.01, depth=0.005)
    with pytest.raises(ParameterError, match="clamp_blocks"):
        make_water_step(grid, clamp_blocks=blocks)


@pytest.mark.parametrize("clamp", ["smooth", "reference"])
def test_gradients_stay_finite_and_right_as_columns_drain(clamp):
    """A 2 mm pool pushed down by 50 Pa drains its middle columns; their outflows shrink towards zero
    (below 1e-154 m^3 within 40 steps), where the clamp's ratio avail/out had the derivative
    avail/out^2, which overflowed and gave NaN gradients (inf times a zero cotangent) from 40 steps
    on (found by a review, session 23). Measured now: the gradient matches central differences to
    ~1e-10 at 40 and 80 steps."""
    g = WaterGrid(shape=(16, 16), spacing=0.01, depth=0.002, clamp=clamp)
    step = make_water_step(g)

    def loss(a, n):
        p = jnp.zeros(g.shape).at[6:10, 6:10].set(a)
        st = jax.lax.fori_loop(0, n, lambda i, s: step(s, p), still_water(g))
        return jnp.sum(st.height[5:11, 5:11] ** 2)

    for n in (40, 80):
        assert int(jnp.sum(jax.lax.fori_loop(0, n, lambda i, s: step(s, jnp.zeros(g.shape).at[6:10, 6:10].set(50.0)),
                                             still_water(g)).height == 0.0)) > 0  # columns ran dry
        grad = float(jax.grad(loss)(50.0, n))
        h = 1e-3
        fd = float((loss(50.0 + h, n) - loss(50.0 - h, n)) / (2 * h))
        assert np.isfinite(grad) and abs(grad / fd - 1) < 1e-6, (n, grad, fd)


def test_states_and_points_are_checked_where_they_enter():
    """(session 32, a review of the water) each of these ran on: an integer height made an int state that
    met a scan TypeError in run_water; bool, complex and text heights; bfloat16, whose clock stopped at 2 s;
    a NaN or negative column in a hand-made state (the NaN filled the grid in 20 steps); pipes of the
    wrong shape (a raw broadcasting error); deposit into an array of another shape (written to clamped
    columns); total_volume of another grid's state."""
    import dataclasses

    import jax.numpy as jnp
    import numpy as np

    from jaxskip import ParameterError
    from jaxskip.water import WaterGrid, deposit, run_water, still_water, total_volume

    g = WaterGrid(shape=(16, 16), spacing=0.01, depth=0.05)
    s = still_water(g, np.full((16, 16), 1))            # 1 m, written as an integer
    assert jnp.issubdtype(s.height.dtype, jnp.floating) and float(run_water(g, s, 3).height[0, 0]) == 1.0
    for bad, what in ((np.ones((16, 16), bool), "dtype bool"), (np.ones((16, 16), complex), "dtype complex128"),
                      ("abc", "got str")):
        with pytest.raises(ParameterError, match=f"height must be an \\(nx, ny\\) array of real column heights.*{what}"):
            still_water(g, bad)
    with pytest.raises(ParameterError, match="dtype must be float32 or float64: bfloat16 cannot hold the clock"):
        still_water(g, dtype=jnp.bfloat16)
    s = still_water(g)
    for height, shown in ((s.height.at[3, 3].set(jnp.nan), "nan"), (s.height.at[3, 3].set(-1.0), "-1.0")):
        with pytest.raises(ParameterError, match=f"state.height must be finite and >= 0 m in every column, got {shown}"):
            run_water(g, dataclasses.replace(s, height=height), 20)
    with pytest.raises(ParameterError, match=r"state.qx must have shape \(15, 16\) for the grid's shape \(16, 16\), got \(3, 3\)"):
        run_water(g, dataclasses.replace(s, qx=jnp.zeros((3, 3))), 3)
    with pytest.raises(ParameterError, match=r"into must have the grid's shape \(16, 16\), got \(4, 4\)"):
        deposit(g, jnp.array([0.105]), jnp.array([0.105]), jnp.array([1.0]), into=jnp.zeros((4, 4)))
    with pytest.raises(ParameterError, match="x, y and value must have one shape"):
        deposit(g, jnp.array([0.1, 0.2]), jnp.array([0.1]), jnp.array([1.0]))
    with pytest.raises(ParameterError, match=r"state.height must have shape \(16, 16\)"):
        total_volume(g, still_water(WaterGrid(shape=(20, 20), depth=0.05)))


def test_flows_clock_dtypes_and_dt_are_checked_too():
    """(2026-12-05, a review) run_water checked only the heights: a NaN flow filled the grid with NaN and a
    NaN clock ran on; a float16 flow, integer heights or a float32 height among float64 flows met raw scan /
    cond type errors; the step took a NaN, negative or unstable dt in silence (NaN heights), and a float64
    pressure turned a float32 state's heights float64 under x64 (a scan over the step then failed)."""
    import dataclasses

    import jax.numpy as jnp
    import numpy as np

    from jaxskip import ParameterError
    from jaxskip.water import WaterGrid, make_water_step, run_water, stable_dt, still_water

    g = WaterGrid(shape=(8, 8), spacing=0.01, depth=0.05)
    s = still_water(g)
    for name, value in (("qx", s.qx.at[0, 0].set(jnp.nan)), ("qa", s.qa.at[1, 1].set(jnp.inf)),
                        ("time", jnp.array(jnp.nan))):
        with pytest.raises(ParameterError, match=f"state.{name} must be finite"):
            run_water(g, dataclasses.replace(s, **{name: value}), 3)
    for name, value, shown in (("qx", s.qx.astype(jnp.float16), "qx float16"),
                               ("height", jnp.ones((8, 8), jnp.int32), "height int32"),
                               ("height", s.height.astype(jnp.float32), "height float32")):
        with pytest.raises(ParameterError, match=f"state's arrays must all be float32 or all float64.*{shown}"):
            run_water(g, dataclasses.replace(s, **{name: value}), 3)
    step = make_water_step(g)
    bound = stable_dt(g.spacing, g.depth)
    for dt in (float("nan"), -1e-4, 1.01 * bound, np.ones(2) * 1e-4, "0.001"):
        with pytest.raises(ParameterError, match=r"dt must be a number in \[0, 0.0123655\] s"):
            step(s, jnp.zeros((8, 8)), dt)
    with pytest.raises(ParameterError, match="state's arrays must all be float32"):
        step(dataclasses.replace(s, qy=s.qy.astype(jnp.float16)), jnp.zeros((8, 8)))
    # at the bound and traced dts still run; the pressure takes the state's float type
    assert bool(jnp.all(jnp.isfinite(step(s, jnp.zeros((8, 8)), bound).height)))
    s32 = still_water(g, dtype=jnp.float32)
    push = jnp.zeros((8, 8), jnp.float64).at[4, 4].set(100.0)
    out = jax.lax.scan(lambda c, _: (step(c, push, jnp.float32(1e-3)), None), s32, None, length=3)[0]
    assert out.height.dtype == jnp.float32 and float(out.height[4, 4]) < g.depth


def test_clamp_blocks_take_numpy_integers_and_pressures_must_be_real():
    """(session 32, a review) WaterGrid.shape takes NumPy integers but clamp_blocks refused them; a complex
    pressure was cast with only a ComplexWarning, its imaginary part dropped."""
    import jax.numpy as jnp
    import numpy as np

    from jaxskip import ParameterError
    from jaxskip.water import WaterGrid, make_water_step, run_water, still_water

    g = WaterGrid(shape=(16, 16), spacing=0.01, depth=0.05)
    push = jnp.zeros((16, 16)).at[8, 8].set(100.0)
    a = make_water_step(g, clamp_blocks=((np.int64(8), np.int32(8)),))(still_water(g), push)
    b = make_water_step(g, clamp_blocks=((8, 8),))(still_water(g), push)
    np.testing.assert_array_equal(np.asarray(a.height), np.asarray(b.height))
    with pytest.raises(ParameterError, match="pressure must be real"):
        run_water(g, still_water(g), 2, pressure=np.ones((16, 16), complex))


def test_no_column_dips_below_zero_in_float32_after_a_strong_push():
    """(session 32, a review) with the reference clamp in float32 two columns held -1.2e-35 m right after a
    1e5 Pa push was lifted; the clamps promise non-negative columns (and a user's sqrt(h) gave NaN)."""
    import jax.numpy as jnp

    from jaxskip.water import WaterGrid, make_water_step, still_water

    for clamp in ("reference", "smooth"):
        g = WaterGrid(shape=(32, 32), spacing=0.01, depth=0.02, clamp=clamp)
        X, Y = g.column_centres()
        p = (1e5 * jnp.exp(-((X - 0.10) ** 2 + (Y - 0.16) ** 2) / (2 * 0.015 ** 2))).astype(jnp.float32)
        step = jax.jit(make_water_step(g))
        s = still_water(g, dtype=jnp.float32)
        lowest = []
        for k in range(200):
            s = step(s, jnp.roll(p, k // 10, axis=0) if k < 150 else jnp.zeros_like(p))
            lowest.append(float(s.height.min()))
        assert min(lowest) >= 0.0, (clamp, min(lowest), lowest.index(min(lowest)))


def test_the_pure_step_refuses_a_non_finite_pressure_and_a_missing_state():
    """(2026-12-06, a review) make_water_step's step turned a NaN or infinite pressure into NaN heights in
    silence (run_water refused it) and met None with a raw AttributeError; traced values still pass."""
    grid = WaterGrid(shape=(8, 8), spacing=0.01, depth=0.02)
    step = make_water_step(grid)
    w = still_water(grid)
    for bad in (jnp.nan, jnp.inf):
        with pytest.raises(ParameterError, match=r"pressure must be finite in every column \[Pa\]"):
            step(w, jnp.full((8, 8), bad))
    with pytest.raises(ParameterError, match="state must be a jaxskip.WaterState .*got NoneType"):
        step(None, jnp.zeros((8, 8)))
    h = jax.jit(step)(w, jnp.zeros((8, 8))).height                  # traced pressure: no check, still water
    np.testing.assert_array_equal(np.asarray(h), np.asarray(w.height))


def test_a_grid_origin_may_be_a_list():
    """(2026-12-06, a review) origin=[0.1, 0.2] was refused ("must be a tuple"); it is stored as a tuple."""
    g = WaterGrid(shape=(8, 8), origin=[0.1, 0.2])
    assert g.origin == (0.1, 0.2) and hash(g) == hash(WaterGrid(shape=(8, 8), origin=(0.1, 0.2)))


def test_water_review_2026_12_07(monkeypatch):
    """(2026-12-07, a review of the water as a library) a float32 state on a sponge grid met a raw cond/scan type
    error under x64 (the sponge's factors were float64); deposit added a NaN point's NaN weights into the columns
    of a good one beside it, and into a float32 array it met a raw dtype error; the pure step ran on concrete
    negative or NaN heights that run_water refuses (the clamp made water); a state with a weakly typed clock
    compiled run_water again; water_substeps(grid, 1e300) gave a 303-digit count."""
    from jaxskip.water import deposit, total_volume, water_substeps

    sponge = WaterGrid(shape=(12, 12), spacing=0.01, depth=0.02, boundary="sponge", sponge_width=3)
    for clamp in ("reference", "smooth", "zero"):
        g = dataclasses.replace(sponge, clamp=clamp)
        s = still_water(g, dtype=jnp.float32)
        bump = s.height.at[5, 5].add(jnp.float32(0.005))
        out = run_water(g, dataclasses.replace(s, height=bump), 20)
        assert all(a.dtype == jnp.float32 for a in (out.height, out.qx, out.qd, out.time)), clamp
        assert float(total_volume(g, out)) > 0
    small = WaterGrid(shape=(5, 4), spacing=0.1, depth=1.0)
    d = deposit(small, jnp.array([jnp.nan, 0.1]), jnp.array([0.1, 0.1]), jnp.array([1.0, 1.0]))
    assert not bool(jnp.any(jnp.isnan(d))) and float(d.sum()) == pytest.approx(1.0, abs=1e-12)
    into = deposit(small, jnp.array([0.1]), jnp.array([0.1]), jnp.array([1.0]), into=jnp.zeros((5, 4), jnp.float32))
    assert into.dtype == jnp.float32 and float(into.sum()) == pytest.approx(1.0)
    g = WaterGrid(shape=(8, 8), spacing=0.01, depth=0.02)
    step = make_water_step(g)
    for bad in (-0.01, float("nan")):
        with pytest.raises(ParameterError, match=r"state.height must be finite and >= 0 m"):
            step(dataclasses.replace(still_water(g), height=jnp.full((8, 8), bad)), jnp.zeros((8, 8)))
    import jaxskip.water as water_module

    run_water(g, still_water(g), 3)
    runner = water_module._water_program(g, 3)
    before = runner._cache_size()
    weak = run_water(g, dataclasses.replace(still_water(g), time=0.0), 3)
    assert runner._cache_size() == before and not weak.time.weak_type, (runner._cache_size(), before)
    with pytest.raises(ParameterError, match=r"dt must be at most .* s \(1e\+08 water steps"):
        water_substeps(g, 1e300)


def test_height_at_and_deposit_refuse_what_they_would_silently_spoil():
    """(stop 48, a review) height_at read NaN for a NaN height or point, where its docstring promised an error;
    deposit wrote a NaN value into its 2 x 2 columns, and into an integer array truncated the weights (a value of
    1 deposited 0, into a bool array 4). Each is refused, naming the argument; traced values pass (unchecked)."""
    from jaxskip.water import deposit

    grid = WaterGrid(shape=(8, 8), spacing=0.01, depth=0.02)
    h = np.full(grid.shape, 0.02)
    for kwargs, name in ((dict(height=np.full(grid.shape, np.nan), x=0.0, y=0.0), "height"),
                         (dict(height=h, x=np.nan, y=0.0), "x"), (dict(height=h, x=0.0, y=np.inf), "y")):
        with pytest.raises(ParameterError, match=f"{name} must be finite"):
            height_at(grid, **kwargs)
    with pytest.raises(ParameterError, match="value must be finite"):
        deposit(grid, 0.025, 0.025, np.nan)
    for dtype in (jnp.int32, jnp.bool_):
        with pytest.raises(ParameterError, match="into must be a floating array"):
            deposit(grid, 0.025, 0.025, 1.0, into=jnp.zeros(grid.shape, dtype))
    assert float(deposit(grid, 0.025, 0.025, 1.0, into=jnp.zeros(grid.shape)).sum()) == pytest.approx(1.0)
    # traced: unchecked, as documented
    assert np.isnan(float(jax.jit(lambda x: height_at(grid, h, x, 0.0))(np.nan)))


def test_run_water_with_progress_gives_the_same_water_and_says_how_far(capsys):
    """(stop 48, a review) run_water on a large grid sat silent for minutes (a 4096² grid under a push: ~6 s a
    step). With progress=True it runs in scans of PROGRESS_CHUNK steps, printing a progress line on stderr, and
    gives the same water to the bit."""
    from jaxskip.water import PROGRESS_CHUNK

    grid = WaterGrid(shape=(16, 16), spacing=0.01, depth=0.02)
    i, j = np.meshgrid(np.arange(16), np.arange(16), indexing="ij")
    push = 3e3 * np.exp(-((i - 8) ** 2 + (j - 8) ** 2) / 8.0)
    steps = 2 * PROGRESS_CHUNK + 37
    plain = run_water(grid, still_water(grid), steps, push)
    shown = run_water(grid, still_water(grid), steps, push, progress=True)
    for a, b in zip(jax.tree_util.tree_leaves(plain), jax.tree_util.tree_leaves(shown)):
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    assert f"{steps} of {steps} steps" in capsys.readouterr().err
    with pytest.raises(ParameterError, match="progress"):
        run_water(grid, still_water(grid), 3, progress="yes")
