r"""Immersed area of a triangle below the water surface: the kernel for one triangle.

Exact clipping (Do, Lee & Ryu, Fig. 3)
--------------------------------------
Let the heights of the vertices above the local water surface be
:math:`\zeta_k = z_k - h_k` (negative = under water). The height is linear
over the triangle, so the immersed part is the triangle cut by the line
:math:`\zeta = 0`. Sorting the heights :math:`a \le b \le c` gives the
paper's three cases:

* all under (:math:`c \le 0`): the whole triangle, fraction 1;
* one vertex above (:math:`b \le 0 < c`): the triangle minus the corner at
  the top vertex, whose area fraction is :math:`c^2 / ((c-a)(c-b))`;
* two vertices above (:math:`a < 0 \le b`): the corner at the lowest vertex,
  fraction :math:`a^2 / ((b-a)(c-a))`;

and no vertex under gives 0. Each corner is a triangle similar in
barycentric terms, so its area fraction is the product of its two edge
fractions (the paper subtracts triangle areas found by Heron's formula; the
result is the same). The immersed centroid follows from the same sub-triangles.
The area fraction is :math:`C^1` in the heights except for a horizontal
triangle, where it jumps from 0 to 1.

Smooth clipping
---------------
With a ramp of width :math:`w = 1/\kappa` (``sharpness`` :math:`\kappa`, 1/m),
the wet weight of a point at height :math:`\zeta` is
:math:`s(\zeta) = \mathrm{clip}(\tfrac12 - \zeta/w, 0, 1)
= [(w/2-\zeta)_+ - (-w/2-\zeta)_+]/w`. Because :math:`\zeta` is linear over the
triangle, :math:`\int (\ell - \zeta)_+\,dA` is an exact integral over the
triangle clipped at level :math:`\ell`, so

.. math:: S_\kappa = \frac{1}{w}\Big[\int_{\zeta<w/2} (w/2-\zeta)\,dA
          - \int_{\zeta<-w/2} (-w/2-\zeta)\,dA\Big]

exactly, with no quadrature. :math:`S_\kappa` is continuous even for a
horizontal triangle, and :math:`|S_\kappa - S| \le A` only within
:math:`|\zeta| < w/2`, so it converges to the exact area as
:math:`\kappa \to \infty` (error :math:`O(1/\kappa)`).

All functions act on a single triangle; ``vmap`` them over the mesh.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp


def _sorted_vertices(z, p):
    """The heights ``z`` (3,) sorted ascending, ties by index, and the vertices ``p`` (3, 3) in
    the same order: ``(a, b, c), (pa, pb, pc)``.

    Built from comparisons and selects only (no sort op, no permutation matrix): each vertex's
    rank counts the vertices below it, and each sorted slot picks the vertex of that rank.
    """
    z0, z1, z2 = z[0], z[1], z[2]
    # rank_i = #{j : z_j < z_i, or z_j == z_i and j < i}: distinct, so the ranks are a permutation.
    r0 = (z1 < z0).astype(jnp.int32) + (z2 < z0).astype(jnp.int32)
    r1 = (z0 <= z1).astype(jnp.int32) + (z2 < z1).astype(jnp.int32)

    def pick(k, v0, v1, v2):
        return jnp.where(r0 == k, v0, jnp.where(r1 == k, v1, v2))

    heights = tuple(pick(k, z0, z1, z2) for k in range(3))
    vertices = tuple(pick(k, p[0], p[1], p[2]) for k in range(3))
    return heights, vertices


def _tri_integrals(alpha, q, d):
    """Integrals over a sub-triangle, divided by the full triangle's area.

    ``alpha``: sub-triangle area / full area; ``q`` (3, 3): its vertices [m];
    ``d`` (3,): a linear function at its vertices (the depth below a level) [m].
    Returns ``(∫1, ∫p, ∫d, ∫p d) / A`` with shapes ``(), (3,), (), (3,)``.
    """
    sq = jnp.sum(q, axis=0)
    sd = jnp.sum(d)
    i_pd = alpha * (jnp.sum(q * d[:, None], axis=0) + sq * sd) / 12.0
    return alpha, alpha * sq / 3.0, alpha * sd / 3.0, i_pd


def clip_integrals(p, zeta):
    r"""Integrals over the part of a triangle with :math:`\zeta < 0`, per unit triangle area.

    Parameters
    ----------
    p : (3, 3) vertex positions [m].
    zeta : (3,) vertex heights above the cutting level [m] (negative = below).

    Returns
    -------
    fraction : () immersed area / triangle area.
    moment : (3,) :math:`\frac1A\int_{\zeta<0} p\,dA` [m].
    depth : () :math:`\frac1A\int_{\zeta<0} (-\zeta)\,dA` [m].
    depth_moment : (3,) :math:`\frac1A\int_{\zeta<0} p\,(-\zeta)\,dA` [m^2].

    Gradients are finite everywhere: every division is guarded by a double
    ``where`` so that the branch not taken never divides by zero.
    """
    (a, b, c), (pa, pb, pc) = _sorted_vertices(zeta, p)

    all_under = c <= 0.0
    one_above = (b <= 0.0) & (c > 0.0)
    two_above = (a < 0.0) & (b > 0.0)

    full = _tri_integrals(1.0, jnp.stack([pa, pb, pc]), -jnp.stack([a, b, c]))

    # Corner at the top vertex c (one vertex above): c - a >= c > 0 and c - b >= c > 0.
    ca = jnp.where(one_above, c - a, 1.0)
    cb = jnp.where(one_above, c - b, 1.0)
    t_a, t_b = c / ca, c / cb
    corner_c = _tri_integrals(
        jnp.where(one_above, t_a * t_b, 0.0),
        jnp.stack([pc, pc + (pa - pc) * t_a, pc + (pb - pc) * t_b]),
        jnp.stack([-c, 0.0 * c, 0.0 * c]),
    )
    # Corner at the bottom vertex a (two vertices above): b - a > -a > 0 and c - a > 0.
    ba = jnp.where(two_above, b - a, 1.0)
    ca2 = jnp.where(two_above, c - a, 1.0)
    s_b, s_c = -a / ba, -a / ca2
    corner_a = _tri_integrals(
        jnp.where(two_above, s_b * s_c, 0.0),
        jnp.stack([pa, pa + (pb - pa) * s_b, pa + (pc - pa) * s_c]),
        jnp.stack([-a, 0.0 * a, 0.0 * a]),
    )
    use_full = (all_under | one_above).astype(p.dtype)
    # Corner weights are zero outside their case, so the three terms simply add up.
    return tuple(use_full * f - cc + cq for f, cc, cq in zip(full, corner_c, corner_a))


def immersed_area(p, surface, sharpness=None):
    r"""Immersed area and its centroid for one triangle.

    Parameters
    ----------
    p : (3, 3) vertex positions in the world frame [m].
    surface : (3,) water-surface height below each vertex [m] (zeros for flat water).
    sharpness : None for exact clipping, or :math:`\kappa > 0` [1/m] for the
        smooth ramp of width :math:`1/\kappa` (static Python float).

    Returns
    -------
    fraction : () immersed area divided by the triangle's area (0..1).
    centroid : (3,) centroid of the immersed part [m]; the triangle's centroid
        when nothing is immersed (its force is then zero anyway).

    Examples
    --------
    >>> import jax.numpy as jnp
    >>> tri = jnp.array([[0., 0., -1.], [1., 0., 1.], [0., 1., 1.]])
    >>> f, g = immersed_area(tri, jnp.zeros(3))
    >>> round(float(f), 6)   # corner at the low vertex: (1/2) * (1/2)
    0.25
    """
    return immersed_area_from_heights(p, p[:, 2] - surface, sharpness)


def immersed_area_from_heights(p, zeta, sharpness=None):
    r"""As :func:`immersed_area`, from the vertices' heights above the water ``zeta`` (3,) [m].

    ``p`` (3, 3) may be in any frame (the body frame, say): the clipping depends on
    the heights only, and the centroid comes out in the frame of ``p``.
    """
    if sharpness is None:
        frac, moment, _, _ = clip_integrals(p, zeta)
    else:
        half = 0.5 / sharpness
        _, _, d_hi, m_hi = clip_integrals(p, zeta - half)
        _, _, d_lo, m_lo = clip_integrals(p, zeta + half)
        frac = (d_hi - d_lo) * sharpness
        moment = (m_hi - m_lo) * sharpness
    wet = frac > 1e-14
    centroid = jnp.where(wet, moment / jnp.where(wet, frac, 1.0), jnp.mean(p, axis=0))
    return frac, centroid


def immersed_areas_from_heights(p, zeta, sharpness=None):
    """:func:`immersed_area_from_heights` over a mesh: ``p`` (F, 3, 3), ``zeta`` (F, 3) -> (F,), (F, 3)."""
    return jax.vmap(lambda pi, zi: immersed_area_from_heights(pi, zi, sharpness))(p, zeta)


def immersed_areas(p, surface, sharpness=None):
    """:func:`immersed_area` over a mesh: ``p`` (F, 3, 3), ``surface`` (F, 3) -> (F,), (F, 3)."""
    return jax.vmap(lambda pi, si: immersed_area(pi, si, sharpness))(p, surface)
