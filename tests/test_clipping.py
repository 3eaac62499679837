"""Immersed area by clipping: exact cases, the disk-segment formula, smooth convergence."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from jaxskip.clipping import immersed_area, immersed_areas


def polygon_clip_area(p):
    """Independent reference: Sutherland-Hodgman clip of a 3-D triangle to z <= 0, area and centroid."""
    out = []
    n = len(p)
    for i in range(n):
        a, b = p[i], p[(i + 1) % n]
        if a[2] <= 0:
            out.append(a)
        if (a[2] <= 0) != (b[2] <= 0):
            t = a[2] / (a[2] - b[2])
            out.append(a + t * (b - a))
    if len(out) < 3:
        return 0.0, None
    out = np.array(out)
    area_vec = np.zeros(3)
    moment = np.zeros(3)
    for i in range(1, len(out) - 1):
        c = np.cross(out[i] - out[0], out[i + 1] - out[0]) / 2
        area_vec += c
        moment += np.linalg.norm(c) * (out[0] + out[i] + out[i + 1]) / 3
    area = np.linalg.norm(area_vec)
    return area, moment / area


def tri_area(p):
    return 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0]))


@pytest.mark.parametrize("n_under", [0, 1, 2, 3])
def test_clip_cases_match_polygon_clipping(n_under):
    rng = np.random.default_rng(n_under)
    for _ in range(50):
        p = rng.normal(size=(3, 3))
        z = np.abs(rng.normal(size=3)) + 0.01
        z[:n_under] *= -1
        p[:, 2] = z[rng.permutation(3)]
        frac, centroid = immersed_area(jnp.asarray(p), jnp.zeros(3))
        ref_area, ref_centroid = polygon_clip_area(p)
        assert abs(float(frac) * tri_area(p) - ref_area) < 1e-12
        if ref_centroid is not None:
            np.testing.assert_allclose(np.asarray(centroid), ref_centroid, atol=1e-12)


def test_clip_against_a_non_flat_surface():
    """Heights are measured from the local surface under each vertex."""
    p = jnp.array([[0.0, 0.0, 0.3], [1.0, 0.0, 0.3], [0.0, 1.0, 0.3]])
    frac, _ = immersed_area(p, jnp.array([0.5, 0.5, 0.5]))
    assert float(frac) == 1.0
    frac, _ = immersed_area(p, jnp.array([0.0, 0.0, 0.0]))
    assert float(frac) == 0.0


def disk_segment_area(R, s):
    u = 1 - s / R
    return R**2 * (np.arccos(u) - u * np.sqrt(1 - u**2))


def dipped_disk_area(R, s, n=512):
    """Immersed area of a vertical n-gon disk of radius R dipped to depth s, by our clipping."""
    ang = 2 * np.pi * np.arange(n) / n
    rim = np.stack([R * np.cos(ang), np.zeros(n), R * np.sin(ang) + R - s], axis=1)
    centre = np.array([0.0, 0.0, R - s])
    tris = np.stack([np.broadcast_to(centre, rim.shape), rim, np.roll(rim, -1, axis=0)], axis=1)
    frac, _ = immersed_areas(jnp.asarray(tris), jnp.zeros((n, 3)))
    areas = 0.5 * np.linalg.norm(np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]), axis=1)
    return float(np.sum(np.asarray(frac) * areas))


@pytest.mark.parametrize("s_over_r", [0.2, 0.5, 1.0, 1.5, 2.0])
def test_refined_disk_matches_segment_formula(s_over_r):
    """A vertical 512-gon disk dipped to depth s: within 0.5 % of the circular-segment area."""
    R = 0.05
    assert abs(dipped_disk_area(R, s_over_r * R) / disk_segment_area(R, s_over_r * R) - 1) < 5e-3


@pytest.mark.parametrize("s_over_r", [0.01, 0.02, 0.04])
def test_shallow_immersion_follows_the_three_halves_law(s_over_r):
    """For s << R the wetted area grows like (4 sqrt(2)/3) R^(1/2) s^(3/2) (physics.md §2)."""
    R = 0.05
    s = s_over_r * R
    law = 4 * np.sqrt(2) / 3 * R**0.5 * s**1.5
    assert abs(dipped_disk_area(R, s, n=2048) / law - 1) < 0.02


def test_smooth_area_converges_to_exact():
    rng = np.random.default_rng(7)
    p = jnp.asarray(rng.normal(size=(200, 3, 3)) * 0.05)
    h = jnp.zeros((200, 3))
    exact, _ = immersed_areas(p, h)
    errors = []
    for kappa in [1e2, 1e3, 1e4, 1e5]:
        smooth, _ = immersed_areas(p, h, kappa)
        errors.append(float(jnp.max(jnp.abs(smooth - exact))))
    # O(1/kappa): each decade of sharpness cuts the worst error by about ten.
    assert all(b < 0.2 * a for a, b in zip(errors, errors[1:])), errors


def test_smooth_area_is_continuous_for_a_horizontal_triangle():
    """Exact clipping jumps 0 -> 1 for a horizontal face; the smooth ramp does not."""
    def frac(z, kappa):
        p = jnp.array([[0.0, 0.0, z], [1.0, 0.0, z], [0.0, 1.0, z]])
        return immersed_area(p, jnp.zeros(3), kappa)[0]

    assert float(frac(-1e-9, None)) == 1.0 and float(frac(1e-9, None)) == 0.0
    assert abs(float(frac(0.0, 100.0)) - 0.5) < 1e-12
    g = jax.grad(frac)(0.0, 100.0)
    assert np.isfinite(float(g)) and abs(float(g) + 100.0) < 1e-9


def test_area_gradient_finite_at_zero_immersion():
    """A vertex exactly on the surface, and a triangle exactly at the surface: finite gradients."""
    def f(z0):
        p = jnp.array([[0.0, 0.0, z0], [1.0, 0.0, 0.5], [0.0, 1.0, 0.7]])
        frac, c = immersed_area(p, jnp.zeros(3))
        return frac + jnp.sum(c)

    for z0 in [0.0, -0.0, 1e-300]:
        assert np.isfinite(float(jax.grad(f)(z0)))
    flat = lambda z: immersed_area(jnp.array([[0.0, 0.0, z], [1.0, 0.0, z], [0.0, 1.0, z]]), jnp.zeros(3))[0]
    assert np.isfinite(float(jax.grad(flat)(0.0)))


@pytest.mark.parametrize("dtype, eps, tiny", [(jnp.float32, 1e-5, 1e-20), (jnp.float64, 1e-14, 1e-160)])
def test_a_barely_wetted_triangles_gradients_are_its_scaled_gradients(dtype, eps, tiny):
    """(2026-12-06, a review) Every clipped integral per unit area is homogeneous in the heights: the fraction of
    degree 0, the centroid's weights too. So d/dzeta at eps * zeta is 1/eps times that at zeta, down to heights of
    the surface tolerance (2026-12-07: 1.2e-7 m in float32, 2.3e-16 m in float64; heights below it are rounding
    noise of a face lying on the water, and count as on it: fraction 0, derivative 0). JAX's division rule squared
    the tiny heights, underflowed, and gave +-inf for the fraction (the centroid: NaN) at 1e-20 in float32 and
    1e-160 in float64: finite everywhere now."""
    from jaxskip.clipping import clip_weights, surface_tolerance

    for zeta in ([-1.0, 1.0, 1.0], [-1.0, -2.0, 0.5], [1.0, -2.0, 3.0]):
        zeta = jnp.asarray(zeta, dtype)
        assert float(jnp.min(jnp.abs(zeta * eps))) > surface_tolerance(dtype)
        for output in (lambda w: w[0], lambda w: w[1]):
            unit = jax.jacfwd(lambda z: output(clip_weights(z)))(zeta)
            small = jax.jacfwd(lambda z: output(clip_weights(z)))(zeta * eps)
            reverse = jax.jacrev(lambda z: output(clip_weights(z)))(zeta * eps)
            for jac in (small, reverse):
                assert np.all(np.isfinite(np.asarray(jac, np.float64)))
                np.testing.assert_allclose(np.asarray(jac, np.float64) * eps, np.asarray(unit, np.float64), rtol=1e-5)
            for jac in (jax.jacfwd, jax.jacrev):
                assert np.all(np.asarray(jac(lambda z: output(clip_weights(z)))(zeta * tiny)) == 0.0)
        assert float(clip_weights(zeta * tiny)[0]) == 0.0


@pytest.mark.parametrize("law,velocity,sharpness", [("bocquet", "body", None), ("seed", "local", None),
                                                    ("bocquet", "local", 400.0), ("seed", "body", None),
                                                    ("bocquet", "body", 400.0)])
def test_body_frame_force_equals_the_world_frame_sum(paper, water, law, velocity, sharpness):
    """The simulator clips and loads each triangle in the body frame (constant vertices, one
    rotated velocity); the law is rotation-invariant, so this must equal clipping the world-frame
    triangles and summing the world-frame forces, on flat and on rippled water. With
    ``velocity="body"`` the sums come from first moments (``forces.body_water_load``: no
    per-triangle centroid), so this also checks that algebra for both laws and both clips."""
    from jaxskip import quaternion as quat
    from jaxskip.forces import ForceModel, flat_surface, total_force, triangle_force, water_force, world_triangles

    model = ForceModel(law=law, velocity=velocity, sharpness=sharpness)
    rippled = lambda x, y: 0.002 * jnp.sin(40.0 * x) * jnp.cos(25.0 * y)  # noqa: E731
    rng = np.random.default_rng(4)
    wet = []
    for surface in (flat_surface, rippled):
        for _ in range(4):
            q = quat.normalize(jnp.asarray(rng.normal(size=4)))
            R = quat.to_matrix(q)
            x = jnp.asarray([rng.uniform(-0.1, 0.1), rng.uniform(-0.1, 0.1), rng.uniform(-0.01, 0.01)])
            v, w = jnp.asarray(rng.normal(size=3) * 4.0), jnp.asarray(rng.normal(size=3) * 60.0)
            tri, normals = world_triangles(paper, x, R)
            frac, centroid = immersed_areas(tri, surface(tri[..., 0], tri[..., 1]), sharpness)
            area = frac * paper.areas
            r = centroid - x[None, :]
            vel = v[None, :] + (jnp.cross(w[None, :], r) if velocity == "local" else 0.0 * r)
            forces = jax.vmap(lambda n, s, u: triangle_force(model, water, n, s, u))(normals, area, vel)
            expected = total_force(forces, centroid, area, x)
            got = water_force(model, water, paper, x, R, v, w, surface)
            wet.append(float(expected[2]) / float(jnp.sum(paper.areas)))
            for e, g in zip(expected, got):
                np.testing.assert_allclose(np.asarray(g), np.asarray(e), rtol=1e-10, atol=1e-12 * (1 + float(jnp.max(jnp.abs(e)))))
    assert sum(0.0 < f < 0.9 for f in wet) >= 6, wet   # partly immersed poses: every clip case occurs


def test_gated_moment_is_the_wet_part_cut_again():
    """gated_moment_from_heights (the passive law's loaded part of a wet triangle, 2026-12-07): the area and first
    moment of {zeta < 0} and {g > 0} against a polygon clip of the triangle by both lines, over random triangles;
    the wet part when g > 0 all over, nothing when g < 0; the same region found with the two cuts swapped (another
    decomposition: agreement to rounding); gradients finite and equal to central differences."""
    from _polygons import area_and_moment, clip_polygon

    from jaxskip.clipping import gated_moment_from_heights, immersed_moment_from_heights

    rng = np.random.default_rng(11)
    for _ in range(300):
        p = rng.normal(size=(3, 3))
        zeta, g = rng.normal(size=3), rng.normal(size=3)
        f, m = (np.asarray(a) for a in gated_moment_from_heights(jnp.asarray(p), jnp.asarray(zeta), jnp.asarray(g)))
        # the two linear functions carried as extra coordinates of the vertices: clipping keeps them linear
        tri_area = 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0]))
        pts = [np.concatenate([p[k], [zeta[k], g[k]]]) for k in range(3)]
        piece = clip_polygon(clip_polygon(pts, lambda x: x[3]), lambda x: -x[4])
        area, moment = area_and_moment(piece)
        assert abs(f * tri_area - area) <= 1e-12 * (1 + tri_area), (f * tri_area, area)
        np.testing.assert_allclose(m * tri_area, moment, atol=1e-12)
        f2, m2 = gated_moment_from_heights(jnp.asarray(p), jnp.asarray(-g), jnp.asarray(-zeta))
        assert abs(float(f2) - f) <= 1e-14 and np.abs(np.asarray(m2) - m).max() <= 1e-14
    p, zeta = jnp.asarray(rng.normal(size=(3, 3))), jnp.array([-0.3, 0.2, -0.1])
    wet = immersed_moment_from_heights(p, zeta)
    for got, want in zip(gated_moment_from_heights(p, zeta, jnp.array([1.0, 2.0, 0.5])), wet):
        np.testing.assert_allclose(np.asarray(got), np.asarray(want), atol=1e-15)
    for got in gated_moment_from_heights(p, zeta, jnp.array([-1.0, -2.0, -0.5])):
        np.testing.assert_array_equal(np.asarray(got), 0.0)
    x = jnp.array([-0.3, 0.2, -0.1, 0.4, -0.2, 0.15])   # (g = 0.1 puts the cut through a wet corner: a kink)
    func = lambda x: gated_moment_from_heights(p, x[:3], x[3:])[0] + jnp.sum(gated_moment_from_heights(p, x[:3], x[3:])[1])
    grad = np.asarray(jax.grad(func)(x))
    h = 1e-6
    fd = np.array([(func(x.at[i].add(h)) - func(x.at[i].add(-h))) / (2 * h) for i in range(6)])
    assert np.all(np.isfinite(grad)) and np.abs(grad).max() > 0
    np.testing.assert_allclose(grad, fd, rtol=1e-6, atol=1e-8)
