"""The water-force laws against their formulas (physics.md §2-3), written out here in NumPy.

Every expected value below is computed independently of :mod:`jaxskip.forces`: the seed law's
lift direction from the cross products of physics.md, ``u = (±n × V̂) × V̂``, the angle from
``arcsin |n·V̂|``, Bocquet's tangential velocity as ``n × (V × n)``, immersed areas from the
analytic corner of a triangle cut parallel to its base, and for a whole mesh from a
Sutherland-Hodgman clip. Single triangles are wrapped in a one-face :class:`RigidStone` built
from world-frame geometry, so the tests also cover the body/world frame changes.
"""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from _polygons import area_and_moment, clip_polygon
from jaxskip import ForceModel, ParameterError, RigidStone, WaterParams
from jaxskip.forces import body_triangle_forces, flat_surface, triangle_force, triangle_forces, water_force

CL, CF, RHO = 0.7, 0.25, 998.0  # distinct, non-default values so a swapped coefficient shows

def params(cl=CL, cf=CF, rho=RHO):
    f = lambda x: jnp.asarray(x, jnp.float64)
    return WaterParams(c_lift=f(cl), c_friction=f(cf), rho_water=f(rho), gravity=f(9.81))


def rotation(axis, angle):
    """Rodrigues' rotation matrix (NumPy), body to world."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * K + (1 - np.cos(angle)) * K @ K


R_GENERIC = rotation([0.3, -0.5, 0.8], 0.9)
POS_GENERIC = np.array([0.7, -0.4, 0.0])


def one_triangle_stone(world_tri, outward, position, R):
    """A one-face stone whose triangle sits at ``world_tri`` (3, 3) for the pose (position, R)."""
    body = (np.asarray(world_tri) - position[None, :]) @ R  # rows: R^T (p - x)
    e = np.cross(world_tri[1] - world_tri[0], world_tri[2] - world_tri[0])
    n = e / np.linalg.norm(e)
    n = n if np.dot(n, outward) > 0 else -n
    f = lambda x: jnp.asarray(x, jnp.float64)
    return RigidStone(triangles=f(body[None]), normals=f((R.T @ n)[None]), areas=f([0.5 * np.linalg.norm(e)]),
                      mass=f(1.0), inertia=f(np.eye(3)), inv_inertia=f(np.eye(3)), radius=f(1.0),
                      thickness=f(0.01)), n


# A triangle with its apex P0 below the water and its opposite edge level at height +H: the
# immersed part is the corner at P0, similar with linear ratio t = d / (d + H), area t^2 A and
# centroid P0 + t (P1 + P2 - 2 P0) / 3.
D, H = 0.006, 0.004
PARTIAL = np.array([[0.01, -0.02, -D], [0.05, 0.03, H], [-0.03, 0.04, H]])
T_CUT = D / (D + H)
FULL = PARTIAL - np.array([0.0, 0.0, 0.05])  # the same triangle, wholly under water
OUTWARD = np.array([0.2, 0.1, -1.0])  # the face looks down-ish (a stone's underside)


def tri_area(p):
    return 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0]))


def immersed(tri):
    """(area, centroid) of FULL or PARTIAL, from the analytic formulas above."""
    if tri is FULL:
        return tri_area(tri), tri.mean(axis=0)
    p0, p1, p2 = tri
    return T_CUT**2 * tri_area(tri), p0 + T_CUT * (p1 + p2 - 2 * p0) / 3


def seed_formula(n, V, S, normalize=True, cl=CL, cf=CF, rho=RHO):
    """Eqs. (1)-(2) of physics.md, term by term."""
    speed = np.linalg.norm(V)
    Vh = V / speed
    nv = np.dot(n, Vh)
    drag = -0.5 * cf * rho * S * speed**2 * abs(nv) * Vh
    u = np.cross(np.cross(n, Vh), Vh) if nv > 0 else np.cross(np.cross(-n, Vh), Vh)
    cos_theta = np.cos(np.arcsin(abs(nv)))  # theta: angle between the face and V
    if normalize:  # the magnitude the paper states: |F_L| = 1/2 C_l rho |V|^2 S cos(theta)
        u = u / np.linalg.norm(u)
    lift = 0.5 * cl * rho * S * abs(cos_theta) * speed**2 * u
    return drag, lift


def bocquet_formula(n, V, S, cl=CL, cf=CF, rho=RHO):
    """Lift 1/2 C_l rho |V|^2 S along the inward normal, friction 1/2 C_f rho |V||V_t| S against V_t."""
    speed = np.linalg.norm(V)
    v_t = np.cross(n, np.cross(V, n))
    lift = -0.5 * cl * rho * speed**2 * S * n
    friction = -0.5 * cf * rho * speed * np.linalg.norm(v_t) * S * v_t / np.linalg.norm(v_t)
    return lift, friction


def passive_formula(n, v, w, S, cl=CL, cf=CF, rho=RHO):
    """velocity="passive": Bocquet's pressure from the centre of mass's v, the face's own w deciding the
    lift's side (-sgn(n.w) n); the friction is Bocquet's at v (it acts at the centre of mass: no moment);
    the gate (n.w > 0 for leading faces) is the caller's. Returns (lift, friction)."""
    lift, friction = bocquet_formula(n, v, S, cl, cf, rho)
    return (lift if np.dot(n, w) >= 0 else -lift), friction


def loaded(model, tri, V, omega=np.zeros(3), pos=POS_GENERIC, R=R_GENERIC):
    """The library's world-frame force, immersed centroid and area for one triangle at a pose."""
    world = tri + pos[None, :]
    stone, n = one_triangle_stone(world, OUTWARD, pos, R)
    f = lambda x: jnp.asarray(x, jnp.float64)
    F, c, S = triangle_forces(model, params(), stone, f(pos), f(R), f(V), f(omega), flat_surface)
    return np.asarray(F)[0], np.asarray(c)[0] - pos, float(S[0]), n


def assert_vec(actual, expected, rtol=1e-12):
    err = np.linalg.norm(np.asarray(actual) - expected)
    assert err <= rtol * np.linalg.norm(expected), (actual, expected, err / np.linalg.norm(expected))


V_LEAD = np.array([3.0, 0.5, -1.2])  # the underside moves into the water: n . V > 0


# --------------------------------------------------------------------------- a. seed law
@pytest.mark.parametrize("tri", ["full", "partial"])
@pytest.mark.parametrize("normalize", [True, False])
def test_seed_law_matches_eqs_1_and_2(tri, normalize):
    """Drag -1/2 C_f rho S |V|^2 |n.V^| V^ and lift 1/2 C_l rho S |cos th| |V|^2 u, with |F_L| ∝ cos th
    (normalize_lift=True, û) or cos^2 th (False, eq. 2 as printed) - for a fully immersed triangle
    (S = its area) and one cut by the water (S = t^2 A), at a generic pose."""
    tri = FULL if tri == "full" else PARTIAL
    model = ForceModel(law="seed", normalize_lift=normalize)
    F, centroid, S, n = loaded(model, tri, V_LEAD)
    S_ref, c_ref = immersed(tri)
    assert abs(S - S_ref) <= 1e-12 * S_ref
    assert_vec(centroid, c_ref)
    assert np.dot(n, V_LEAD) > 0
    drag, lift = seed_formula(n, V_LEAD, S_ref, normalize)
    assert_vec(F, drag + lift)
    # The lift is perpendicular to V and pushes against the face's motion into the water, and its
    # magnitude is the stated one: 1/2 C_l rho S |V|^2 cos th (normalised) or cos^2 th (printed).
    speed, sin_t = np.linalg.norm(V_LEAD), abs(np.dot(n, V_LEAD)) / np.linalg.norm(V_LEAD)
    cos_t = np.sqrt(1 - sin_t**2)
    lift_lib = F - drag
    assert abs(np.dot(lift_lib, V_LEAD)) <= 1e-12 * np.linalg.norm(lift_lib) * speed
    assert np.dot(lift_lib, -n) > 0
    expected = 0.5 * CL * RHO * S_ref * speed**2 * (cos_t if normalize else cos_t**2)
    assert abs(np.linalg.norm(lift_lib) - expected) <= 1e-12 * expected


def test_seed_law_by_hand():
    """A face n = -z sliding at V = (2, 0, -1): |V|^2 = 5, |n.V| = 1, cos th = 2/sqrt(5), û = (1, 0, 2)/sqrt(5).
    Drag -1/2 C_f rho S |n.V| V; lift 1/2 C_l rho S |V|^2 cos th û (normalize_lift=True)."""
    n, V, S = np.array([0.0, 0.0, -1.0]), np.array([2.0, 0.0, -1.0]), 0.01
    F = np.asarray(triangle_force(ForceModel(law="seed"), params(), jnp.asarray(n), jnp.asarray(S), jnp.asarray(V)))
    drag = -0.5 * CF * RHO * S * 1.0 * V
    lift = 0.5 * CL * RHO * S * 5.0 * (2 / np.sqrt(5)) * np.array([1.0, 0.0, 2.0]) / np.sqrt(5)
    assert_vec(F, drag + lift)


def test_seed_printed_lift_is_cos_theta_times_the_stated_one():
    """normalize_lift=False (eq. 2 as printed, ∝ cos^2 th) is the True lift (∝ cos th) times |cos th|;
    the drag is the same."""
    n, V, S = np.array([0.0, 0.0, -1.0]), np.array([2.0, 0.0, -1.0]), 0.01
    f = lambda model: np.asarray(triangle_force(model, params(), jnp.asarray(n), jnp.asarray(S), jnp.asarray(V)))
    drag = -0.5 * CF * RHO * S * 1.0 * V
    a = f(ForceModel(law="seed", normalize_lift=True)) - drag
    b = f(ForceModel(law="seed", normalize_lift=False)) - drag
    assert_vec(b, (2 / np.sqrt(5)) * a)


# --------------------------------------------------------------------------- b. Bocquet's law
@pytest.mark.parametrize("tri", ["full", "partial"])
def test_bocquet_law_matches_lift_and_friction(tri):
    """Lift 1/2 C_l rho |V|^2 S along the inward normal -n; friction 1/2 C_f rho |V| |V_t| S against V_t."""
    tri = FULL if tri == "full" else PARTIAL
    F, _, S, n = loaded(ForceModel(law="bocquet"), tri, V_LEAD)
    S_ref, _ = immersed(tri)
    lift, friction = bocquet_formula(n, V_LEAD, S_ref)
    assert_vec(F, lift + friction)
    # The split: the normal part is the lift alone, the in-plane part the friction alone.
    assert_vec(np.dot(F, n) * n, lift)
    assert_vec(F - np.dot(F, n) * n, friction)


@pytest.mark.parametrize("theta_deg", [10.0, 20.0, 45.0])
def test_bocquet_law_on_a_tilted_plate_in_horizontal_motion(theta_deg):
    """physics.md §3's setting: the underside of a plate tilted by th (leading edge up) moving at V_x.
    By hand: n = (sin th, 0, -cos th), n.V = V sin th, |V_t| = V cos th, so
    F_z = 1/2 rho V^2 S (C_l cos th - C_f sin th cos th), F_x = -1/2 rho V^2 S (C_l sin th + C_f cos^2 th):
    Bocquet's C = C_l cos th - C_f sin th and C~ = C_l sin th + C_f cos th with the friction
    scaled by |V_t|/|V| = cos th (equal in his grazing limit)."""
    th = np.radians(theta_deg)
    n = np.array([np.sin(th), 0.0, -np.cos(th)])
    V, S = 6.0, 3e-3
    F = np.asarray(triangle_force(ForceModel(law="bocquet"), params(), jnp.asarray(n), jnp.asarray(S),
                                  jnp.asarray([V, 0.0, 0.0])))
    q = 0.5 * RHO * V**2 * S
    expected = np.array([-q * (CL * np.sin(th) + CF * np.cos(th) ** 2), 0.0,
                         q * (CL * np.cos(th) - CF * np.sin(th) * np.cos(th))])
    assert_vec(F, expected)


# --------------------------------------------------------------------------- c. which faces
@pytest.mark.parametrize("law", ["seed", "bocquet"])
@pytest.mark.parametrize("tri", ["full", "partial"])
def test_trailing_face_is_unloaded_only_with_leading_faces(law, tri):
    """A face moving away from the water (n.V < 0) carries no force under faces="leading" and the
    law's force under faces="all": for the seed law u = (-n × V^) × V^ (physics.md); for Bocquet's
    law the code flips the lift with sgn(n.V), so it opposes the normal flow (along +n here)."""
    tri = FULL if tri == "full" else PARTIAL
    V = -V_LEAD  # the underside moves up, out of the water: n . V < 0
    F_lead, _, _, n = loaded(ForceModel(law=law, faces="leading"), tri, V)
    assert np.dot(n, V) < 0
    assert np.all(F_lead == 0.0)
    F_all, _, _, _ = loaded(ForceModel(law=law, faces="all", normalize_lift=True), tri, V)
    S_ref, _ = immersed(tri)
    if law == "seed":
        drag, lift = seed_formula(n, V, S_ref)
        assert_vec(F_all, drag + lift)
        assert np.dot(F_all - drag, n) > 0  # against the face's motion out of the water
    else:
        lift, friction = bocquet_formula(n, V, S_ref)
        assert_vec(F_all, -lift + friction)  # lift along +n: against the normal flow
    # The same face moving into the water is loaded identically under both choices.
    F1, _, _, _ = loaded(ForceModel(law=law, faces="leading"), tri, -V)
    F2, _, _, _ = loaded(ForceModel(law=law, faces="all"), tri, -V)
    assert np.any(F1 != 0.0) and np.array_equal(F1, F2)


@pytest.mark.parametrize("law", ["seed", "bocquet"])
def test_face_parallel_to_the_flow_is_not_leading(law):
    """The criterion is strict, n.V > 0: a face sliding in its own plane (n.V = 0 exactly) is unloaded."""
    n = jnp.array([0.0, 0.0, -1.0])
    V = jnp.array([3.0, 1.0, 0.0])
    F = triangle_force(ForceModel(law=law, faces="leading"), params(), n, jnp.asarray(0.01), V)
    assert np.all(np.asarray(F) == 0.0)
    F = triangle_force(ForceModel(law=law, faces="all"), params(), n, jnp.asarray(0.01), V)
    assert np.linalg.norm(np.asarray(F)) > 0


@pytest.mark.parametrize("law", ["seed", "bocquet"])
def test_leading_faces_of_a_whole_stone(paper, law):
    """On the half-immersed mesh, faces="leading" loads exactly the immersed faces with n.V > 0, each as "all" does."""
    R, pos = R_GENERIC, np.array([0.0, 0.0, 0.0])
    V, w = np.array([4.0, -1.0, -1.5]), np.zeros(3)
    f = lambda x: jnp.asarray(x, jnp.float64)
    out = {faces: triangle_forces(ForceModel(law=law, faces=faces), params(), paper, f(pos), f(R), f(V), f(w),
                                  flat_surface) for faces in ("leading", "all")}
    Fl, Fa, S = np.asarray(out["leading"][0]), np.asarray(out["all"][0]), np.asarray(out["all"][2])
    nv = (np.asarray(paper.normals) @ R.T) @ V
    lead = nv > 0
    wet = S > 0
    assert np.any(lead & wet) and np.any(~lead & wet)  # both kinds are immersed
    assert np.all(Fl[~lead] == 0.0)
    np.testing.assert_array_equal(Fl[lead], Fa[lead])
    assert np.all(np.linalg.norm(Fa[~lead & wet], axis=1) > 0)


# --------------------------------------------------------------------------- d. velocity
@pytest.mark.parametrize("law", ["seed", "bocquet"])
@pytest.mark.parametrize("tri", ["full", "partial"])
def test_local_velocity_adds_omega_cross_r_at_the_immersed_centroid(law, tri):
    """velocity="local": V = v + ω × r, r the immersed centroid relative to the centre of mass
    (world frame, any pose); velocity="body": V = v."""
    tri = FULL if tri == "full" else PARTIAL
    omega = np.array([-20.0, 35.0, 120.0])  # rad/s
    S_ref, r = immersed(tri)
    v_local = V_LEAD + np.cross(omega, r)
    formula = (lambda n, V: sum(seed_formula(n, V, S_ref))) if law == "seed" else \
        (lambda n, V: sum(bocquet_formula(n, V, S_ref)))
    F_loc, c, _, n = loaded(ForceModel(law=law, velocity="local", faces="all"), tri, V_LEAD, omega)
    assert_vec(c, r)
    assert np.linalg.norm(v_local - V_LEAD) > 0.1 * np.linalg.norm(V_LEAD)  # the spin matters here
    assert_vec(F_loc, formula(n, v_local))
    F_body, _, _, _ = loaded(ForceModel(law=law, velocity="body", faces="all"), tri, V_LEAD, omega)
    assert_vec(F_body, formula(n, V_LEAD))
    F_still, _, _, _ = loaded(ForceModel(law=law, velocity="body", faces="all"), tri, V_LEAD)
    np.testing.assert_array_equal(F_body, F_still)  # ω does not enter the body law at all


@pytest.mark.parametrize("tri", ["full", "partial"])
@pytest.mark.parametrize("faces", ["leading", "all"])
def test_passive_velocity_takes_the_pressure_from_v_and_the_loading_from_v_plus_omega_cross_r(tri, faces):
    """velocity="passive" against its formula: the lift on the part of the wet face whose own velocity
    w = v + ω × r moves into the water (n.w > 0; the rest unloaded with leading faces, its lift reversed with all
    faces), found here by clipping the wet polygon at n.w = 0; for a spin that turns the face away from the
    water at its centroid (n.w = -1.5 < 0 < n.v there, but not all over it), a third of it, and none; without
    rotation it is the body law to rounding (bit for bit until 2026-12-07, when a face was gated whole)."""
    tri = FULL if tri == "full" else PARTIAL
    S_ref, r = immersed(tri)
    n = one_triangle_stone(tri + POS_GENERIC, OUTWARD, POS_GENERIC, R_GENERIC)[1]
    # a spin with n.(ω × r) = ω.(r × n) = -(n.v + 1.5) turns the face away from the water (n.w = -1.5 < 0 < n.v),
    # plus a part along r, which does not move the centroid
    rn = np.cross(r, n)
    flip = -(np.dot(n, V_LEAD) + 1.5) * rn / np.dot(rn, rn) + 40.0 * r / np.linalg.norm(r)
    assert np.dot(n, V_LEAD) > 0 > np.dot(n, V_LEAD + np.cross(flip, r))
    split = 0
    for omega in (flip, 0.3 * flip, np.zeros(3)):
        F, c, S, _ = loaded(ForceModel(velocity="passive", faces=faces), tri, V_LEAD, omega)
        assert_vec(c, r)
        (s_in, _), (s_out, _) = passive_split(tri, n, lambda x: np.dot(n, V_LEAD + np.cross(omega, x)))
        assert abs(s_in + s_out - S_ref) <= 1e-14 * (1 + S_ref) and abs(S - S_ref) <= 1e-14
        split += 0.0 < s_in < S_ref
        lift_in, friction_in = passive_formula(n, V_LEAD, n, s_in)
        lift_out, _ = passive_formula(n, V_LEAD, -n, s_out)
        _, friction_all = passive_formula(n, V_LEAD, n, S_ref)
        expected = lift_in + friction_in if faces == "leading" else lift_in + lift_out + friction_all
        assert_vec(F, expected)
    assert split >= 1
    F_body, _, _, _ = loaded(ForceModel(velocity="body", faces=faces), tri, V_LEAD, omega)
    np.testing.assert_allclose(F, F_body, rtol=1e-15, atol=0)  # (omega = 0 last; summed otherwise: to rounding)


def test_passive_water_does_no_positive_work_on_any_face():
    """The power of the passive law on a face moving at w_i, L_i . w_i of its lift (at the face) plus
    f_i . v of its friction (at the centre of mass), is never positive, for random normals, centre-of-mass
    velocities v and face velocities w (the body law's F_i . w_i often is, and the friction's f_i . w_i,
    were it acting at the face, is positive on 26 % / 51 % of these draws with leading / all faces); a seed law with velocity="passive" is refused, naming the
    parameter."""
    from jaxskip.forces import _passive_parts

    rng = np.random.default_rng(7)
    n = rng.normal(size=(4000, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    v, w = rng.normal(size=(2, 4000, 3)) * np.array([[[4.0, 1.0, 1.0]]])
    f = lambda x: jnp.asarray(x, jnp.float64)
    for faces in ("leading", "all"):
        model = ForceModel(velocity="passive", faces=faces)
        lift, friction = (np.asarray(a) for a in jax.vmap(
            lambda n, v, w: _passive_parts(model, params(), n, f(1e-3), v, w))(f(n), f(v), f(w)))
        F = jax.vmap(lambda n, v, w: triangle_force(model, params(), n, f(1e-3), v, w))(f(n), f(v), f(w))
        np.testing.assert_array_equal(np.asarray(F), lift + friction)
        power = np.sum(lift * w, axis=1) + np.sum(friction * v, axis=1)
        assert power.max() <= 0.0, (faces, power.max())
        assert np.sum(friction * w, axis=1).max() > 1.0  # at the face the friction would do positive work
        model = ForceModel(velocity="body", faces=faces)
        F = jax.vmap(lambda n, v, w: triangle_force(model, params(), n, f(1e-3), v, w))(f(n), f(v), f(w))
        assert np.sum(np.asarray(F) * w, axis=1).max() > 1.0, faces
    with pytest.raises(ParameterError, match="velocity='passive'.*law='bocquet'"):
        ForceModel(law="seed", velocity="passive")


# --------------------------------------------------------------------------- e. totals over a mesh
def polygon_area(points, fallback):
    """(area, centroid) of a planar polygon (``fallback`` as the centroid when it has none)."""
    area, moment = area_and_moment(points) if len(points) >= 3 else (0.0, None)
    return (area, moment / area) if area > 0 else (0.0, fallback)


def polygon_clip(p):
    """Sutherland-Hodgman clip of a world triangle to z <= 0: (area, centroid)."""
    return polygon_area(clip_polygon(list(p), lambda x: x[2]), p.mean(axis=0))


def passive_split(p, n, gate):
    """The wet part of world triangle ``p`` split by the sign of ``gate(point)`` (its own velocity's normal part
    n.w, linear over the face): ((area, centroid) where gate > 0, (area, centroid) where gate <= 0)."""
    wet = clip_polygon(list(p), lambda x: x[2])
    return (polygon_area(clip_polygon(wet, lambda x: -gate(x)), p.mean(axis=0)),
            polygon_area(clip_polygon(wet, gate), p.mean(axis=0)))


MESH_CASES = [(law, faces, vel, norm) for law in ("seed", "bocquet") for faces in ("leading", "all")
              for vel in ("body", "local") + (("passive",) if law == "bocquet" else ())
              for norm in ((True, False) if law == "seed" else (True,))]


MESH_POSE = dict(R=rotation([1.0, 0.4, -0.2], 0.35), pos=np.array([0.3, 0.1, 0.002]),
                 v=np.array([5.0, 0.7, -1.1]), w=np.array([2.0, -3.0, 110.0]))


def mesh_loads(paper, model, R, pos, v, w):
    f = lambda x: jnp.asarray(x, jnp.float64)
    args = (model, params(), paper, f(pos), f(R), f(v), f(w), flat_surface)
    return [np.asarray(a) for a in water_force(*args)], [np.asarray(a) for a in triangle_forces(*args)]


@pytest.mark.parametrize("law,faces,velocity,normalize", MESH_CASES)
def test_total_force_and_torque_are_the_sums_over_triangles(paper, law, faces, velocity, normalize):
    """water_force (the simulator's kernel; with velocity="body" a path that never forms per-triangle
    forces) equals the sum of triangle_forces' F_i and of (c_i - x) × F_i about the centre of mass x, to 1e-10
    (velocity="passive": the force; its friction acts at x, and the next test sums its torque)."""
    model = ForceModel(law=law, faces=faces, velocity=velocity, normalize_lift=normalize)
    (F, tau, wet), (Fi, ci, Si) = mesh_loads(paper, model, **MESH_POSE)
    pos = MESH_POSE["pos"]
    assert np.sum(Si > 0) >= 5 and np.sum(Si == 0) >= 5  # a partly immersed stone
    assert np.sum(np.linalg.norm(Fi, axis=1) > 0) >= 5
    assert_vec(F, Fi.sum(axis=0), 1e-10)
    if velocity != "passive":  # (its friction acts at the centre of mass: the next test checks its torque)
        assert_vec(tau, np.cross(ci - pos, Fi).sum(axis=0), 1e-10)
    assert abs(float(wet) - Si.sum()) <= 1e-12 * Si.sum()


@pytest.mark.parametrize("law,faces,velocity,normalize", MESH_CASES)
def test_mesh_forces_match_the_law_triangle_by_triangle(paper, law, faces, velocity, normalize):
    """Each triangle's immersed area and centroid (own polygon clip of the world triangle) and force
    (own law at v, or v + ω × r for "local"; for "passive" on the part of the wet face whose own points move
    into the water, clipped once more), and their totals against water_force."""
    model = ForceModel(law=law, faces=faces, velocity=velocity, normalize_lift=normalize)
    (F, tau, _), (Fi, ci, Si) = mesh_loads(paper, model, **MESH_POSE)
    R, pos, v, w = (MESH_POSE[k] for k in ("R", "pos", "v", "w"))
    world = pos + np.asarray(paper.triangles) @ R.T
    normals = np.asarray(paper.normals) @ R.T
    scale = np.max(np.linalg.norm(Fi, axis=1))
    F_own, tau_own, split = np.zeros(3), np.zeros(3), 0
    for k in range(paper.n_triangles):
        S, c = polygon_clip(world[k])
        assert abs(Si[k] - S) <= 1e-14
        if S == 0.0:
            assert np.all(Fi[k] == 0.0)
            continue
        np.testing.assert_allclose(ci[k], c, atol=1e-12)
        V = v + np.cross(w, c - pos) if velocity != "body" else v
        at_centroid = None  # the part of the force that acts at the centroid (None: all of it)
        if velocity == "passive":
            # the lift on the part of the wet face moving into the water (n.w > 0, w its own velocity), the
            # other part unloaded ("leading") or pushed the other way ("all"); the friction at x, on the loaded
            # part ("leading") or all the wet face ("all")
            (s_in, c_in), (s_out, c_out) = passive_split(world[k], normals[k],
                                                         lambda x: np.dot(normals[k], v + np.cross(w, x - pos)))
            assert abs(s_in + s_out - S) <= 1e-14
            split += 0.0 < s_in < S
            lift_in, friction_in = passive_formula(normals[k], v, normals[k], s_in)
            lift_out, _ = passive_formula(normals[k], v, -normals[k], s_out)
            _, friction_all = passive_formula(normals[k], v, normals[k], S)
            if faces == "leading":
                expected = lift_in + friction_in
                tau_own += np.cross(c_in - pos, lift_in)
            else:
                expected = lift_in + lift_out + friction_all
                tau_own += np.cross(c_in - pos, lift_in) + np.cross(c_out - pos, lift_out)
            assert np.linalg.norm(Fi[k] - expected) <= 1e-12 * scale, k
            F_own += expected
            continue
        if faces == "leading" and np.dot(normals[k], V) <= 0:
            expected = np.zeros(3)
        elif law == "seed":
            expected = sum(seed_formula(normals[k], V, S, normalize))
        else:
            lift, friction = bocquet_formula(normals[k], V, S)
            expected = (lift if np.dot(normals[k], V) >= 0 else -lift) + friction  # see the trailing-face test
        assert np.linalg.norm(Fi[k] - expected) <= 1e-12 * scale, k
        F_own += expected
        tau_own += np.cross(c - pos, expected if at_centroid is None else at_centroid)
    assert_vec(F, F_own, 1e-10)
    assert_vec(tau, tau_own, 1e-10)
    assert velocity != "passive" or split >= 2, split   # wet faces that are loaded in part


# --------------------------------------------------------------------------- f. scaling
@pytest.mark.parametrize("law,normalize,velocity", [(law, norm, vel) for law, norm in
                                                    [("seed", True), ("seed", False), ("bocquet", True)]
                                                    for vel in ("body", "local", "passive")
                                                    if law == "bocquet" or vel != "passive"])
def test_force_scales_as_speed_squared_and_linearly_in_coefficients(paper, law, normalize, velocity):
    """F(λV, λω) = λ² F(V, ω); F is linear in C_l and C_f jointly (F(C_l, C_f) = C_l F(1, 0) + C_f F(0, 1))
    and proportional to ρ; the same for the torque."""
    model = ForceModel(law=law, velocity=velocity, normalize_lift=normalize)
    R, pos = rotation([0.2, 1.0, 0.1], -0.3), np.array([0.0, 0.0, -0.001])
    v, w = np.array([5.0, 0.7, -1.1]), np.array([2.0, -3.0, 110.0])
    f = lambda x: jnp.asarray(x, jnp.float64)
    load = jax.jit(lambda p, v, w: water_force(model, p, paper, f(pos), f(R), v, w, flat_surface)[:2])

    def total(v=v, w=w, **kw):
        return np.concatenate([np.asarray(a) for a in load(params(**kw), f(v), f(w))])

    base = total()
    assert np.linalg.norm(base[:3]) > 0
    lam = 2.75
    assert_vec(total(v=lam * v, w=lam * w), lam**2 * base)
    assert_vec(total(rho=3.5 * RHO), 3.5 * base)
    lift_only, friction_only = total(cl=1.0, cf=0.0), total(cl=0.0, cf=1.0)
    assert np.linalg.norm(lift_only) > 0 and np.linalg.norm(friction_only) > 0
    assert_vec(CL * lift_only + CF * friction_only, base)
    assert_vec(total(cl=2 * CL), base + CL * lift_only)


def test_body_frame_kernel_is_rotation_invariant(paper):
    """body_triangle_forces in body axes, turned by R, are triangle_forces' world forces."""
    model = ForceModel(law="seed", velocity="local", faces="all")
    R, pos = R_GENERIC, np.array([0.1, 0.0, 0.0])
    v, w = np.array([5.0, 0.7, -1.1]), np.array([2.0, -3.0, 110.0])
    f = lambda x: jnp.asarray(x, jnp.float64)
    Fb, cb, Sb = (np.asarray(a) for a in body_triangle_forces(model, params(), paper, f(pos), f(R), f(v), f(w),
                                                              flat_surface))
    Fw, cw, Sw = (np.asarray(a) for a in triangle_forces(model, params(), paper, f(pos), f(R), f(v), f(w),
                                                         flat_surface))
    np.testing.assert_allclose(Fb @ R.T, Fw, rtol=0, atol=1e-12 * np.abs(Fw).max())
    np.testing.assert_allclose(cb @ R.T + pos, cw, rtol=0, atol=1e-14)
    np.testing.assert_array_equal(Sb, Sw)


def test_passive_gate_ignores_rounding_of_a_face_sliding_along_the_water():
    """(stop 48, a review) A flat face sliding along the water (normal speed n.w = 0) got the rounding of its
    vertices' n.w, ~1e-15 m/s of either sign, as its gate, and the cut by g = 0 divided that noise by noise: the
    Clanet disk lying flat at 8 m/s had d(force)/d(velocity) 10.9 with v_z = -1e-14 m/s and -0.049 with 0 or
    +1e-14. Normal speeds within rounding of 0 are 0 now: the force and its gradient do not see 1e-14 m/s."""
    from jaxskip import clanet_disk, quaternion as quat, rigid_stone, water_params
    from jaxskip.forces import body_water_load
    from jaxskip.throw import attitude

    disk = rigid_stone(clanet_disk(), density=2650.0)
    model, water = ForceModel(velocity="passive"), water_params()
    R = quat.to_matrix(attitude(jnp.array(0.0), jnp.array(0.0)))
    position = jnp.array([0.0, 0.0, float(disk.thickness) / 2 - 1e-4])   # the bottom face 0.1 mm under

    def load(v):
        f, tau, _ = body_water_load(model, water, disk, position, R, v, jnp.zeros(3), flat_surface)
        return jnp.sum(f) + jnp.sum(tau)

    grad = jax.jit(jax.value_and_grad(load))
    runs = [grad(jnp.array([8.0, 0.0, vz])) for vz in (0.0, -1e-14, 1e-14)]
    for value, g in runs[1:]:
        np.testing.assert_allclose(float(value), float(runs[0][0]), rtol=1e-12)
        np.testing.assert_allclose(np.asarray(g), np.asarray(runs[0][1]), rtol=1e-9, atol=1e-12)
    # a real normal speed still decides: 1 mm/s into the water loads the face, 1 mm/s out of it does not
    into, out = (float(load(jnp.array([8.0, 0.0, vz]))) for vz in (-1e-3, 1e-3))
    assert abs(into - out) > 1.0
    # and in float32 too, down to 0.1 mm/s (the first band, 1024 rounding units, took 1 mm/s at 8 m/s for 0: the
    # stop-48 diff review)
    f32 = lambda tree: jax.tree_util.tree_map(lambda a: jnp.asarray(a, jnp.float32), tree)  # noqa: E731
    disk32, water32, R32, position32 = f32(disk), f32(water), f32(R), f32(position)

    def load32(v):
        f, tau, _ = body_water_load(model, water32, disk32, position32, R32, v, jnp.zeros(3, jnp.float32),
                                    flat_surface)
        return f[2]

    slow = [float(load32(jnp.array([8.0, 0.0, vz], jnp.float32))) for vz in (-1e-4, -1e-3, 1e-4)]
    assert slow[0] == pytest.approx(slow[1], rel=1e-5) and slow[0] > 1.0 and abs(slow[2]) < 1e-3, slow
