r"""A plain-NumPy re-implementation of jaxskip's flat-water model, vectorised over a batch of throws.

This is the reference point for ``bench_core.py``: it is what one would write
without JAX, as fast as NumPy allows (every array carries a leading batch axis
``B``; there is no Python loop over throws or triangles, only over time
steps). It runs in float64.

It reproduces :func:`jaxskip.simulate.rollout` for the default configuration
and refuses what it does not implement:

* force law: Bocquet's per-face law (``law="bocquet"``) with exact clipping;
  loaded faces ``"leading"`` or ``"all"`` and triangle velocity ``"body"``
  (centre-of-mass velocity) or ``"local"`` (``v + ω × r``), as
  ``config.force`` says (``ForceModel()``'s defaults are followed);
* ``attitude="free"``, ``integrator="euler"``: semi-implicit Euler for the
  water force with gravity integrated exactly; angular-momentum kick followed
  by :func:`free_rotation` (Lie-Poisson splitting, 2 Strang substeps);
* ``flight="jump"``: conservative-advancement step length through the air;
* the same contact bookkeeping (phases AIR/WET/LEAVING, ``bounce_clearance``,
  outcomes sank/flipped/stopped/time_limit/step_limit) and the same freezing
  of throws that are out of play.

The formulas are the JAX code's (the same law, clipping cases and integrator), though not always in the
same order: the clipping sorts each triangle's vertices in the world frame and divides out the immersed
centroid, where the JAX step weighs body-frame moments without sorting, and the free rotation
normalises the quaternion every substep, where JAX merges the half-steps and normalises once. In
float64 the two agree to rounding (positions within ~4e-14 m after 300 steps: ``bench_core.py
--check``) until the trajectories' own sensitivity amplifies the last-bit differences.
Per-contact logs (start/end times, tilts) are not kept; only the counts.

Usage::

    from jaxskip import rigid_stone, paper_stone, water_params, SimConfig
    from benchmarks.numpy_baseline import stone_to_numpy, water_to_numpy, simulate_numpy
    out = simulate_numpy(throws, stone_to_numpy(rigid_stone(paper_stone(), density=2650.0)),
                         water_to_numpy(water_params()), SimConfig())

where ``throws`` is a dict of equal-length 1-D arrays ``speed`` [m/s],
``tilt``, ``attack``, ``heading`` [rad], ``spin`` [rad/s], ``height`` [m].
"""

from __future__ import annotations

import dataclasses

import numpy as np

# Outcome and phase codes: the same values as jaxskip.simulate.
RUNNING, SANK, STOPPED, FLIPPED, TIME_LIMIT, STEP_LIMIT, DIVERGED = 0, 1, 2, 3, 4, 5, 6
OUTCOMES = ("running", "sank", "stopped", "flipped", "time_limit", "step_limit", "diverged")
DIVERGED_SPEED = 1000.0  # m/s: jaxskip.simulate.DIVERGED_SPEED
AIR, WET, LEAVING = 0, 1, 2
# Free-rotation substeps and the axisymmetry tolerance of a jump's rotation cap: as jaxskip.simulate.
FREE_ROTATION_SUBSTEPS, ASYMMETRY_TOLERANCE, LONGEST_CAP = 2, 1e-6, 1e3

THROW_FIELDS = ("speed", "tilt", "attack", "spin", "height", "heading")


# ---------------------------------------------------------------------------
# inputs
# ---------------------------------------------------------------------------


@dataclasses.dataclass(frozen=True)
class NpStone:
    """A :class:`jaxskip.body.RigidStone` as float64 NumPy arrays (body frame = principal frame)."""

    triangles: np.ndarray  # (F, 3, 3) vertices relative to the centre of mass [m]
    normals: np.ndarray  # (F, 3) outward unit normals
    areas: np.ndarray  # (F,) [m^2]
    mass: float  # [kg]
    inertia: np.ndarray  # (3, 3) diagonal [kg m^2]
    inv_inertia: np.ndarray  # (3, 3) [1/(kg m^2)]
    radius: float  # bounding radius about the centre of mass [m]


@dataclasses.dataclass(frozen=True)
class NpWater:
    """Water constants as Python floats."""

    c_lift: float
    c_friction: float
    rho_water: float
    gravity: float


def stone_to_numpy(stone) -> NpStone:
    """Convert a :class:`jaxskip.body.RigidStone` (any float dtype) to float64 NumPy arrays."""
    f = lambda a: np.asarray(a, dtype=np.float64)
    return NpStone(
        triangles=f(stone.triangles), normals=f(stone.normals), areas=f(stone.areas),
        mass=float(stone.mass), inertia=f(stone.inertia), inv_inertia=f(stone.inv_inertia),
        radius=float(stone.radius),
    )


def water_to_numpy(water) -> NpWater:
    """Convert :class:`jaxskip.forces.WaterParams` to Python floats."""
    return NpWater(float(water.c_lift), float(water.c_friction), float(water.rho_water), float(water.gravity))


def _check_config(config) -> None:
    """Refuse configurations this baseline does not implement."""
    f = config.force
    wanted = {"integrator": "euler", "attitude": "free", "flight": "jump"}
    for name, value in wanted.items():
        if getattr(config, name) != value:
            raise NotImplementedError(f"numpy baseline: only {name}={value!r} is implemented")
    if f.law != "bocquet" or f.sharpness is not None:
        raise NotImplementedError("numpy baseline: only law='bocquet' with exact clipping is implemented")
    if f.faces not in ("leading", "all") or f.velocity not in ("local", "body"):
        raise NotImplementedError(f"numpy baseline: faces={f.faces!r}, velocity={f.velocity!r} not implemented")


# ---------------------------------------------------------------------------
# small linear algebra on batches (3-term sums written out, in index order)
# ---------------------------------------------------------------------------


def _rotate(R, v):
    """``R @ v`` for per-throw ``R`` (B, 3, 3) and body-frame vectors ``v`` (..., 3) shared by all throws.

    Returns (B, ..., 3); the sum over ``j`` runs 0, 1, 2 as in ``jaxskip.quaternion.rotate``.
    """
    Rb = R.reshape((R.shape[0],) + (1,) * (v.ndim - 1) + (3, 3))
    return Rb[..., 0] * v[..., None, 0] + Rb[..., 1] * v[..., None, 1] + Rb[..., 2] * v[..., None, 2]


def _rotate_inverse(R, v):
    """``R.T @ v`` for ``R`` (B, 3, 3) and ``v`` (B, 3) -> (B, 3)."""
    return R[:, 0, :] * v[:, 0, None] + R[:, 1, :] * v[:, 1, None] + R[:, 2, :] * v[:, 2, None]


def _congruence(R, A):
    """``R @ A @ R.T`` for ``R`` (B, 3, 3) and a constant ``A`` (3, 3) -> (B, 3, 3)."""
    RA = R[:, :, 0, None] * A[None, 0, :] + R[:, :, 1, None] * A[None, 1, :] + R[:, :, 2, None] * A[None, 2, :]
    return (RA[:, :, None, 0] * R[:, None, :, 0] + RA[:, :, None, 1] * R[:, None, :, 1]
            + RA[:, :, None, 2] * R[:, None, :, 2])


def _matvec(M, v):
    """``M @ v`` for per-throw ``M`` (B, 3, 3) and ``v`` (B, 3) -> (B, 3)."""
    return M[:, :, 0] * v[:, 0, None] + M[:, :, 1] * v[:, 1, None] + M[:, :, 2] * v[:, 2, None]


def _sum3(x):
    """Sum over a last axis of length 3, in index order."""
    return x[..., 0] + x[..., 1] + x[..., 2]


# ---------------------------------------------------------------------------
# quaternions (w, x, y, z), body to world, batched (B, 4)
# ---------------------------------------------------------------------------


def quat_multiply(p, q):
    """Hamilton product of (B, 4) quaternions."""
    pw, px, py, pz = p[:, 0], p[:, 1], p[:, 2], p[:, 3]
    qw, qx, qy, qz = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    return np.stack([
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    ], axis=-1)


def quat_to_matrix(q):
    """Rotation matrices (B, 3, 3) of unit quaternions (B, 4)."""
    w, x, y, z = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    rows = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]
    return np.stack([np.stack(r, axis=-1) for r in rows], axis=-2)


def quat_exp_map(rotvec):
    """Quaternion (B, 4) of rotation vectors (B, 3): ``exp(φ/2)``, Taylor series near zero."""
    sq = _sum3(rotvec * rotvec)
    small = sq < 1e-16
    angle = np.sqrt(np.where(small, 1.0, sq))
    sinc = np.where(small, 0.5 - sq / 48.0, np.sin(0.5 * angle) / angle)
    cos = np.where(small, 1.0 - sq / 8.0, np.cos(0.5 * angle))
    return np.concatenate([cos[:, None], sinc[:, None] * rotvec], axis=-1)


def quat_normalize(q):
    """Unit quaternions (B, 4)."""
    return q / np.sqrt(q[:, 0] * q[:, 0] + q[:, 1] * q[:, 1] + q[:, 2] * q[:, 2] + q[:, 3] * q[:, 3])[:, None]


def free_rotation(q, L, stone: NpStone, h, substeps: int = FREE_ROTATION_SUBSTEPS):
    """Torque-free rotation over ``h`` (B,): exact symmetric-top flow, Strang-split asymmetry.

    Same splitting as :func:`jaxskip.simulate.free_rotation`: per substep a half
    step about body y (asymmetric term), the exact rotation about ``L`` and about
    body z, and another half step about body y.
    """
    inv = np.diagonal(stone.inv_inertia)
    c2 = inv[1] - inv[0]
    c3 = inv[2] - inv[0]
    k = h / substeps
    zero = np.zeros_like(k)

    def half_asym(q):
        s = _rotate_inverse(quat_to_matrix(q), L)[:, 1] * c2 * 0.5 * k
        return quat_multiply(q, quat_exp_map(np.stack([zero, s, zero], axis=-1)))

    for _ in range(substeps):
        q = half_asym(q)
        s = _rotate_inverse(quat_to_matrix(q), L)[:, 2] * c3 * k
        q = quat_multiply(quat_exp_map(L * (inv[0] * k)[:, None]),
                          quat_multiply(q, quat_exp_map(np.stack([zero, zero, s], axis=-1))))
        q = quat_normalize(half_asym(q))
    return q


# ---------------------------------------------------------------------------
# water force: exact clipping + Bocquet's per-face law
#
# The per-triangle work is done on a "structure of arrays": a vector field over
# the mesh is a list of three contiguous (B, F) arrays (x, y, z components), so
# every NumPy operation runs on contiguous memory without broadcasting a short
# trailing axis.
# ---------------------------------------------------------------------------


def _world_vertices(stone: NpStone, R, x):
    """World coordinates of the triangles' vertices: ``P[k][i]`` is (B, F), vertex k, coordinate i."""
    T = stone.triangles  # (F, 3, 3): face, vertex, coordinate
    P = []
    for k in range(3):
        t0, t1, t2 = T[None, :, k, 0], T[None, :, k, 1], T[None, :, k, 2]
        P.append([x[:, i, None] + (R[:, i, 0, None] * t0 + R[:, i, 1, None] * t1 + R[:, i, 2, None] * t2)
                  for i in range(3)])
    return P


def immersed_areas(P):
    """Immersed area fraction (B, F) and immersed centroid (3 x (B, F)) of triangles ``P`` (see above).

    Flat water at z = 0. The vertices are sorted by height (stably: equal
    heights keep their index order) and the triangle is cut by the water line:
    the whole triangle, the triangle minus the corner at its top vertex, or the
    corner at its bottom vertex. A corner's area fraction is the product of its
    two edge fractions.
    """
    zs = [P[0][2], P[1][2], P[2][2]]
    ps = [list(P[0]), list(P[1]), list(P[2])]
    # Bubble-sort network (0,1), (1,2), (0,1) of compare-and-swaps; equal heights never swap.
    for i, j in ((0, 1), (1, 2), (0, 1)):
        swap = zs[i] > zs[j]
        zs[i], zs[j] = np.where(swap, zs[j], zs[i]), np.where(swap, zs[i], zs[j])
        for d in range(3):
            ps[i][d], ps[j][d] = np.where(swap, ps[j][d], ps[i][d]), np.where(swap, ps[i][d], ps[j][d])
    a, b, c = zs
    pa, pb, pc = ps

    all_under = c <= 0.0
    one_above = (b <= 0.0) & (c > 0.0)
    two_above = (a < 0.0) & (b > 0.0)

    # Corner at the top vertex (one vertex above), removed from the whole triangle.
    t_a = c / np.where(one_above, c - a, 1.0)
    t_b = c / np.where(one_above, c - b, 1.0)
    alpha_c = np.where(one_above, t_a * t_b, 0.0)
    # Corner at the bottom vertex (two vertices above): the immersed part itself.
    s_b = -a / np.where(two_above, b - a, 1.0)
    s_c = -a / np.where(two_above, c - a, 1.0)
    alpha_a = np.where(two_above, s_b * s_c, 0.0)

    use_full = (all_under | one_above).astype(a.dtype)
    frac = use_full * 1.0 - alpha_c + alpha_a
    wet = frac > 1e-14
    safe_frac = np.where(wet, frac, 1.0)
    centroid = []
    for d in range(3):
        sum_c = pc[d] + (pc[d] + (pa[d] - pc[d]) * t_a) + (pc[d] + (pb[d] - pc[d]) * t_b)
        sum_a = pa[d] + (pa[d] + (pb[d] - pa[d]) * s_b) + (pa[d] + (pc[d] - pa[d]) * s_c)
        moment = use_full * ((pa[d] + pb[d] + pc[d]) / 3.0) - alpha_c * sum_c / 3.0 + alpha_a * sum_a / 3.0
        # A dry triangle gets its own centroid (its force is zero anyway).
        mean = (P[0][d] + P[1][d] + P[2][d]) / 3.0
        centroid.append(np.where(wet, moment / safe_frac, mean))
    return frac, centroid


def water_force(stone: NpStone, water: NpWater, model, x, R, v, omega):
    """Total water force (B, 3), torque about the centre of mass (B, 3) and wetted area (B,).

    ``model`` is the :class:`jaxskip.forces.ForceModel` (its ``faces`` and ``velocity`` are used).

    Also returns the vertex heights (B, F, 3), which the step reuses for the gap to the water.
    """
    P = _world_vertices(stone, R, x)
    nb = stone.normals
    N = [R[:, i, 0, None] * nb[None, :, 0] + R[:, i, 1, None] * nb[None, :, 1] + R[:, i, 2, None] * nb[None, :, 2]
         for i in range(3)]
    frac, cen = immersed_areas(P)
    area = frac * stone.areas
    r = [cen[i] - x[:, i, None] for i in range(3)]
    if model.velocity == "local":  # each triangle's own velocity v + ω × r
        w = [omega[:, i, None] for i in range(3)]
        V = [v[:, 0, None] + (w[1] * r[2] - w[2] * r[1]),
             v[:, 1, None] + (w[2] * r[0] - w[0] * r[2]),
             v[:, 2, None] + (w[0] * r[1] - w[1] * r[0])]
    else:  # "body": every triangle sees the centre-of-mass velocity
        V = [np.broadcast_to(v[:, i, None], area.shape) for i in range(3)]

    n_v = N[0] * V[0] + N[1] * V[1] + N[2] * V[2]
    v2 = V[0] * V[0] + V[1] * V[1] + V[2] * V[2]
    q = 0.5 * water.rho_water * area
    sign = np.where(n_v >= 0.0, 1.0, -1.0)
    lift = -water.c_lift * q * v2 * sign
    speed = np.where(v2 > 0.0, np.sqrt(np.where(v2 > 0.0, v2, 1.0)), 0.0)
    fric = -water.c_friction * q * speed
    f = [lift * N[i] + fric * (V[i] - n_v * N[i]) for i in range(3)]
    if model.faces == "leading":  # only faces moving into the water are loaded
        leading = n_v > 0.0
        f = [np.where(leading, fi, 0.0) for fi in f]

    force = np.stack([np.sum(fi, axis=1) for fi in f], axis=-1)
    torque = np.stack([np.sum(r[1] * f[2] - r[2] * f[1], axis=1),
                       np.sum(r[2] * f[0] - r[0] * f[2], axis=1),
                       np.sum(r[0] * f[1] - r[1] * f[0], axis=1)], axis=-1)
    z = np.stack([P[0][2], P[1][2], P[2][2]], axis=-1)
    return force, torque, np.sum(area, axis=1), z


# ---------------------------------------------------------------------------
# initial state, step, rollout
# ---------------------------------------------------------------------------


def _attitude(tilt, heading):
    """Quaternions (B, 4): tilt about y (leading edge up), then heading about z."""
    zero = np.zeros_like(tilt)
    half_t = 0.5 * -tilt
    q_tilt = np.stack([np.cos(half_t), zero * np.sin(half_t), np.sin(half_t), zero * np.sin(half_t)], axis=-1)
    half_h = 0.5 * heading
    q_head = np.stack([np.cos(half_h), zero, zero, np.sin(half_h)], axis=-1)
    return quat_multiply(q_head, q_tilt)


def initial_state(throws: dict, stone: NpStone) -> dict:
    """State at release, as :func:`jaxskip.simulate.initial_state`: arrays with a leading axis B."""
    t = {k: np.atleast_1d(np.asarray(throws[k], dtype=np.float64)) for k in THROW_FIELDS}
    B = max(v.shape[0] for v in t.values())
    t = {k: np.broadcast_to(v, (B,)) for k, v in t.items()}
    q = _attitude(t["tilt"], t["heading"])
    R = quat_to_matrix(q)
    lowest = np.min(_rotate(R, stone.triangles)[..., 2], axis=(1, 2))
    ca = np.cos(t["attack"])
    velocity = t["speed"][:, None] * np.stack(
        [ca * np.cos(t["heading"]), ca * np.sin(t["heading"]), -np.sin(t["attack"])], axis=-1)
    zero = np.zeros(B)
    position = np.stack([zero, zero, t["height"] - lowest], axis=-1)
    return {"position": position, "velocity": velocity, "orientation": q,
            "angular_velocity": t["spin"][:, None] * R[:, :, 2], "time": zero.copy()}


def _new_tracker(B: int) -> dict:
    i0 = np.zeros(B, dtype=np.int32)
    return {"alive": np.ones(B, dtype=bool), "outcome": i0.copy(), "phase": i0.copy(), "bounces": i0.copy(),
            "contacts": i0.copy(), "contact_steps": i0.copy(), "alive_steps": i0.copy()}


def step(state: dict, tr: dict, stone: NpStone, water: NpWater, config) -> tuple[dict, dict]:
    """One step for the whole batch: bookkeeping at the start state, then the Euler update."""
    x, v, q, w, t = (state[k] for k in ("position", "velocity", "orientation", "angular_velocity", "time"))
    g = water.gravity
    gvec = np.array([0.0 * g, 0.0 * g, -g])

    R = quat_to_matrix(q)
    L = _matvec(_congruence(R, stone.inertia), w)
    omega = _matvec(_congruence(R, stone.inv_inertia), L)  # from L, as the JAX derivative does
    F, tau, wet_area, z = water_force(stone, water, config.force, x, R, v, omega)
    a0 = F / stone.mass + gvec

    gap = np.min(z, axis=(1, 2))
    top = np.max(z, axis=(1, 2))

    # Conservative-advancement step length (flight="jump").
    spin = np.sqrt(_sum3(w * w) + 1e-30)
    b = v[:, 2] - spin * stone.radius
    dry = (gap > 0.0) & (wet_area <= 0.0)
    arg = np.where(dry, b * b + 2.0 * g * gap, 1.0)
    t_star = np.where(dry, (b + np.sqrt(arg)) / g, 0.0)
    dt = np.clip(t_star, config.dt, config.max_flight_step)
    # A jump's free-rotation substeps turn the body-frame L by at most 90 deg (jaxskip.simulate.rotation_cap).
    inv = np.diagonal(stone.inv_inertia)
    c2, c3 = inv[1] - inv[0], inv[2] - inv[0]
    rate = np.abs(_sum3(L * R[:, :, 2]) * c3)
    turn = FREE_ROTATION_SUBSTEPS * (0.5 * np.pi)  # a quarter turn per substep [rad]
    capped = (abs(c2) > ASYMMETRY_TOLERANCE * abs(c3)) & (rate > turn / LONGEST_CAP)
    cap = np.where(capped, turn / np.where(capped, rate, 1.0), np.inf)
    dt = np.maximum(np.minimum(dt, cap), config.dt)
    dt = np.minimum(dt, np.maximum(config.duration - t, 0.0))  # no step passes the duration (as jaxskip's)

    # Contact bookkeeping at the start of the step.
    alive0 = tr["alive"]
    phase0 = tr["phase"]
    wet = wet_area > 0.0
    begin = alive0 & wet & (phase0 == AIR)
    leave = alive0 & ~wet & (phase0 == WET)
    rewet = alive0 & wet & (phase0 == LEAVING)
    bounce = alive0 & ~wet & (phase0 == LEAVING) & (gap > config.bounce_clearance)
    phase = np.where(begin | rewet, WET, np.where(leave, LEAVING, np.where(bounce, AIR, phase0)))

    speed = np.sqrt(_sum3(v * v) + 1e-30)
    finite = np.all(np.isfinite(x), axis=-1) & np.all(np.isfinite(w), axis=-1)
    diverged = ~(finite & np.isfinite(top) & (speed <= DIVERGED_SPEED))
    outcome = np.where(diverged, DIVERGED,
                       np.where(top < 0.0, SANK,
                                np.where(R[:, 2, 2] < 0.0, FLIPPED,
                                         np.where(wet & (speed < config.stop_speed), STOPPED,
                                                  np.where(t >= config.duration, TIME_LIMIT, RUNNING)))))
    outcome = np.where(alive0, outcome, tr["outcome"])
    alive = alive0 & (outcome == RUNNING)
    tr1 = {"alive": alive, "outcome": outcome.astype(np.int32), "phase": phase.astype(np.int32),
           "bounces": tr["bounces"] + bounce, "contacts": tr["contacts"] + begin,
           "contact_steps": tr["contact_steps"] + (alive & wet), "alive_steps": tr["alive_steps"] + alive}

    # Semi-implicit Euler, gravity exact; angular-momentum kick, then free rotation.
    dt3 = dt[:, None]
    a_water = a0 - gvec
    v1 = v + a0 * dt3
    x1 = x + v * dt3 + (a_water + 0.5 * gvec) * dt3 * dt3
    L1 = L + tau * dt3
    q1 = free_rotation(q, L1, stone, dt)
    w1 = _matvec(_congruence(quat_to_matrix(q1), stone.inv_inertia), L1)

    keep = alive[:, None]
    state1 = {"position": np.where(keep, x1, x), "velocity": np.where(keep, v1, v),
              "orientation": np.where(keep, q1, q), "angular_velocity": np.where(keep, w1, w),
              "time": np.where(alive, t + dt, t)}
    return state1, tr1


def simulate_numpy(throws: dict, stone: NpStone, water: NpWater, config, *, steps: int | None = None,
                   early_exit: bool = False, snapshots=()) -> dict:
    """Simulate a batch of throws on flat water with NumPy (float64).

    Parameters
    ----------
    throws : dict of 1-D arrays (or scalars, broadcast) ``speed`` [m/s], ``tilt``,
        ``attack``, ``heading`` [rad], ``spin`` [rad/s], ``height`` [m], in SI as
        in :class:`jaxskip.Throw`.
    stone, water : from :func:`stone_to_numpy`, :func:`water_to_numpy`.
    config : :class:`jaxskip.SimConfig` (default model only; see the module docstring).
    steps : steps to run (default ``config.max_steps``, as the JAX scan).
    early_exit : stop as soon as every throw is out of play (the JAX scan never does).
    snapshots : step counts after which to keep a copy of the state (for comparisons).

    Returns
    -------
    dict with ``bounces``, ``contacts``, ``outcome`` (int codes, :data:`OUTCOMES`),
    ``outcome_name``, ``position``, ``velocity``, ``orientation``,
    ``angular_velocity``, ``time`` (final state, per throw), ``alive_steps`` (steps
    each throw advanced), ``contact_steps``, ``steps_run`` (steps executed for the
    batch), ``early_exit`` (whether the loop stopped before ``steps``) and
    ``snapshots`` ({step count: state dict}).
    """
    _check_config(config)
    n = config.max_steps if steps is None else int(steps)
    state = initial_state(throws, stone)
    tr = _new_tracker(state["time"].shape[0])
    done, stopped_early, snaps, wanted = 0, False, {}, set(snapshots)
    with np.errstate(invalid="ignore", divide="ignore"):
        while done < n:
            state, tr = step(state, tr, stone, water, config)
            done += 1
            if done in wanted:
                snaps[done] = {k: v.copy() for k, v in state.items()}
            if early_exit and not tr["alive"].any():
                stopped_early = done < n
                break
    outcome = np.where(tr["alive"], STEP_LIMIT, tr["outcome"]).astype(np.int32)
    return dict(
        bounces=tr["bounces"], contacts=tr["contacts"], outcome=outcome,
        outcome_name=[OUTCOMES[i] for i in outcome], alive_steps=tr["alive_steps"],
        contact_steps=tr["contact_steps"], steps_run=done, early_exit=stopped_early, snapshots=snaps, **state,
    )
