r"""Immersed area of a triangle below the water surface: the kernel for one triangle.

Exact clipping (Do, Lee & Ryu, Fig. 3)
--------------------------------------
Let the heights of the vertices above the local water surface be
:math:`\zeta_k = z_k - h_k` (negative = under water). The height is linear
over the triangle, so the immersed part is the triangle cut by the line
:math:`\zeta = 0`. With the heights sorted, :math:`a \le b \le c`, the
paper's three cases are:

* all under (:math:`c \le 0`): the whole triangle, fraction 1;
* one vertex above (:math:`b \le 0 < c`): the triangle minus the corner at
  the top vertex, whose area fraction is :math:`c^2 / ((c-a)(c-b))`;
* two vertices above (:math:`a < 0 \le b`): the corner at the lowest vertex,
  fraction :math:`a^2 / ((b-a)(c-a))`;

and no vertex under gives 0. Each corner is a triangle similar in
barycentric terms, so its area fraction is the product of its two edge
fractions (the paper subtracts triangle areas found by Heron's formula; the
result is the same). The immersed centroid follows from the same sub-triangles.
The code does not sort: :func:`clip_weights` finds the lone vertex (the one on
its side of the line) from the signs and writes every integral as weights on
the three vertices, so a triangle costs a few scalar operations and the
vertices enter once, linearly.
The area fraction is :math:`C^1` in the heights except for a horizontal
triangle, where it jumps from 0 to 1.

Heights within :func:`surface_tolerance` of the water (about a thousand rounding errors of a height near
the surface) count as on it, neither under nor above: a face that lies flat on the water (a disk's face at
tilt 0, landed exactly on the surface by a flight jump) has heights that differ by rounding alone, and
cutting it there split it by rounding noise, with edge fractions whose derivatives reached 1e16-1e20 (a
review, 2026-12-07). A vertex that close to the water adds at most a sliver of that size squared.

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


def surface_tolerance(dtype) -> float:
    """Heights [m] within which a vertex counts as on the water: 1024 rounding units of a 1 mm height
    (``1e-3 * 1024 * eps``: 2.3e-16 m in float64, 1.2e-7 m in float32), far below any step's motion (a
    0.25 ms step at 1 m/s moves 0.25 mm) and above the rounding of a stone's vertex heights near the
    surface (~1e-18 m in float64 for a 5 cm stone)."""
    return 1e-3 * 1024 * float(jnp.finfo(dtype).eps)


def _on_surface_as_zero(zeta):
    """``zeta`` with the heights within :func:`surface_tolerance` of 0 set to 0 (their derivative then 0).
    Per element."""
    return jnp.where(jnp.abs(zeta) < surface_tolerance(zeta.dtype), jnp.zeros_like(zeta), zeta)


def clip_weights(zeta):
    r"""Integrals over the part of a triangle with :math:`\zeta < 0`, as weights on its vertices.

    The immersed part is the whole triangle, a corner at the one vertex on its side of the
    water line, or the triangle minus the corner at the one vertex above. Call that lone
    vertex :math:`k` and the edge fractions to the cut :math:`t_i = \zeta_k/(\zeta_k-\zeta_i)`
    (:math:`i \ne k`; set :math:`t_k = 0`, :math:`S = \sum_i t_i`). The corner is the
    triangle :math:`p_k,\ p_k + t_i (p_i - p_k)`, so with :math:`\alpha = \prod_{i\ne k} t_i`
    its area fraction, :math:`e_i = [i = k]` and :math:`d = -\zeta` the depth,

    .. math::
        \frac1A\int_{\rm corner} p\,dA &= \tfrac{\alpha}{3}\sum_i \big(t_i + e_i(3-S)\big)\,p_i, \\
        \frac1A\int_{\rm corner} d\,dA &= \tfrac{\alpha}{3}\,d_k, \qquad
        \frac1A\int_{\rm corner} p\,d\,dA = \tfrac{\alpha d_k}{12}\sum_i \big(t_i + e_i(4-S)\big)\,p_i,

    (the sub-triangle rules :math:`\int p = A\bar q`, :math:`\int q\,d = \tfrac{A}{12}(\sum_j q_j d_j + \sum_j q_j \sum_j d_j)`)
    and the whole triangle has weights :math:`\tfrac13` and :math:`(d_i + \sum_j d_j)/12`.
    Everything is a function of the three heights only: no vertex is sorted or selected, and
    the vertices enter once, linearly, in :func:`clip_integrals`.

    Parameters
    ----------
    zeta : (3,) vertex heights above the cutting level [m] (negative = below).

    Returns
    -------
    fraction : () immersed area / triangle area.
    moment_w : (3,) weights :math:`w_i` with :math:`\frac1A\int_{\zeta<0} p\,dA = \sum_i w_i p_i`.
    depth : () :math:`\frac1A\int_{\zeta<0} (-\zeta)\,dA` [m].
    depth_w : (3,) weights [m] with :math:`\frac1A\int_{\zeta<0} p\,(-\zeta)\,dA = \sum_i w_i p_i`.

    Every division is guarded by a double ``where``, so gradients are finite everywhere; heights within
    :func:`surface_tolerance` of 0 count as 0, so no edge fraction divides by rounding noise.
    """
    zeta = _on_surface_as_zero(zeta)
    under = zeta < 0.0
    n_under = jnp.sum(under.astype(jnp.int32))
    corner_under = n_under == 1          # the immersed part is the corner at the one vertex under
    corner_above = n_under == 2          # the triangle minus the corner at the one vertex above
    lone = jnp.where(corner_under, under, corner_above & ~under)        # e_i
    active = corner_under | corner_above
    z_k = jnp.sum(jnp.where(lone, zeta, 0.0))
    # i != k lies on the other side of the line, so z_k - z_i is nonzero (|z_k - z_i| >= |z_k|).
    other = active & ~lone
    t = jnp.where(other, _quotient(z_k, jnp.where(other, z_k - zeta, 1.0)), 0.0)
    s = jnp.sum(t)
    e = lone.astype(zeta.dtype)
    alpha = jnp.where(active, jnp.prod(t + e), 0.0)
    d_k = -z_k
    corner = (
        alpha,
        alpha / 3.0 * (t + e * (3.0 - s)),
        alpha * d_k / 3.0,
        alpha * d_k / 12.0 * (t + e * (4.0 - s)),
    )
    d = -zeta
    full = (1.0, jnp.full(3, 1.0 / 3.0, zeta.dtype), jnp.sum(d) / 3.0, (d + jnp.sum(d)) / 12.0)
    base = (n_under >= 2).astype(zeta.dtype)
    sign = jnp.where(corner_under, 1.0, jnp.where(corner_above, -1.0, 0.0))
    return tuple(base * f + sign * c for f, c in zip(full, corner))


@jax.custom_jvp
def _quotient(a, b):
    """a / b, with the derivative written as (da - (a/b) db) / b: JAX's rule for a division forms a/b², whose
    square underflows for heights below ~1e-19 m in float32 (~1e-154 m in float64) and made the edge
    fractions' gradients infinite (and the centroid's NaN) at a barely wetted corner. Per element."""
    return a / b


@_quotient.defjvp
def _quotient_jvp(primals, tangents):
    (a, b), (da, db) = primals, tangents
    r = a / b
    return r, (da - r * db) / b


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

    From :func:`clip_weights`; gradients are finite everywhere.
    """
    frac, w, depth, dw = clip_weights(zeta)
    return frac, jnp.sum(w[:, None] * p, axis=0), depth, jnp.sum(dw[:, None] * p, axis=0)


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
    frac, moment = immersed_moment_from_heights(p, zeta, sharpness)
    wet = frac > 1e-14
    centroid = jnp.where(wet, moment / jnp.where(wet, frac, 1.0), jnp.mean(p, axis=0))
    return frac, centroid


def immersed_moment_from_heights(p, zeta, sharpness=None):
    r"""Immersed area fraction and first moment of one triangle, without the centroid's division.

    ``p`` (3, 3) vertices [m] in any frame, ``zeta`` (3,) their heights above the water [m],
    ``sharpness`` as in :func:`immersed_area`. Returns ``fraction`` () (immersed area / area)
    and ``moment`` (3,) :math:`\frac1A\int_{\rm immersed} p\,dA` [m], so that the centroid is
    ``moment / fraction``. A force proportional to the immersed area, :math:`f = S\,g`, has the
    torque :math:`G \times f = A\,(\text{moment} \times g)`: no division, and no guard.
    """
    if sharpness is None:
        frac, moment, _, _ = clip_integrals(p, zeta)
        return frac, moment
    half = 0.5 / sharpness
    _, _, d_hi, m_hi = clip_integrals(p, zeta - half)
    _, _, d_lo, m_lo = clip_integrals(p, zeta + half)
    return (d_hi - d_lo) * sharpness, (m_hi - m_lo) * sharpness


def wet_pieces(zeta):
    r"""The part of a triangle with :math:`\zeta < 0` as two triangles in barycentric coordinates.

    ``zeta`` (3,): vertex heights above the cutting level [m]. Returns ``(B1, B2)``, each (3, 3): row
    :math:`r` of :math:`B` holds the barycentric weights of the piece's vertex :math:`r` on the triangle's
    vertices, so the piece is ``B @ p`` and a linear function with vertex values :math:`f` takes the values
    ``B @ f`` at its corners, and its area is :math:`|\det B|` of the triangle's. The whole triangle is
    :math:`B_1 = I`; a corner at the lone vertex :math:`k` under water is
    :math:`(e_k,\ e_k + t_i(e_i - e_k),\ e_k + t_j(e_j - e_k))`; the triangle less the corner at the lone
    vertex above is the quadrilateral :math:`e_i, e_j, c_j, c_i` cut into two (:math:`c` those corner
    points); an unused piece is zero (no area). Edge fractions as in :func:`clip_weights`, guarded, and heights
    within :func:`surface_tolerance` of 0 count as 0.
    """
    zeta = _on_surface_as_zero(zeta)
    under = zeta < 0.0
    n_under = jnp.sum(under.astype(jnp.int32))
    corner_under = n_under == 1
    corner_above = n_under == 2
    lone = jnp.where(corner_under, under, corner_above & ~under)
    active = corner_under | corner_above
    z_k = jnp.sum(jnp.where(lone, zeta, 0.0))
    other = active & ~lone
    t = jnp.where(other, _quotient(z_k, jnp.where(other, z_k - zeta, 1.0)), 0.0)
    e = lone.astype(zeta.dtype)
    e_i, e_j = jnp.roll(e, 1), jnp.roll(e, 2)          # the two other vertices, in the triangle's order
    t_i, t_j = jnp.sum(t * e_i), jnp.sum(t * e_j)
    c_i, c_j = e + t_i * (e_i - e), e + t_j * (e_j - e)
    zero = jnp.zeros((3, 3), zeta.dtype)
    corner = jnp.stack([e, c_i, c_j])
    b1 = jnp.where(corner_under, corner, jnp.where(corner_above, jnp.stack([e_i, e_j, c_j]),
                                                   jnp.where(n_under == 3, jnp.eye(3, dtype=zeta.dtype), zero)))
    b2 = jnp.where(corner_above, jnp.stack([e_i, c_j, c_i]), zero)
    return b1, b2


def gated_moment_from_heights(p, zeta, gate):
    r"""Area fraction and first moment of the part of one triangle with :math:`\zeta < 0` and :math:`g > 0`.

    ``p`` (3, 3) vertices [m] in any frame, ``zeta`` (3,) their heights above the water [m] (negative:
    under), ``gate`` (3,) the values at the vertices of a second function :math:`g` linear over the
    triangle (a velocity's normal part, say). Returns ``fraction`` () (that part's area / the triangle's)
    and ``moment`` (3,) :math:`\frac1A\int p\,dA` over it [m], as
    :func:`immersed_moment_from_heights` (exact clipping) does for :math:`\zeta < 0` alone: the wet part
    (:func:`wet_pieces`) cut again by :math:`g = 0` with :func:`clip_integrals`. The answer depends on the
    region only, not on how a surface is cut into triangles.

    >>> import jax.numpy as jnp
    >>> tri = jnp.array([[0., 0., -1.], [1., 0., -1.], [0., 1., -1.]])      # all under water
    >>> f, m = gated_moment_from_heights(tri, tri[:, 2], jnp.array([-1., 1., -1.]))   # g > 0 near vertex 1
    >>> round(float(f), 6)    # the corner at vertex 1, cut halfway along both its edges: 1/4
    0.25
    """
    fraction, moment = 0.0, 0.0
    for b in wet_pieces(zeta):
        piece, g = b @ p, b @ gate
        share = jnp.abs(jnp.dot(b[0], jnp.cross(b[1], b[2])))   # the piece's area / the triangle's
        f, m, _, _ = clip_integrals(piece, -g)
        fraction, moment = fraction + share * f, moment + share * m
    return fraction, moment


def immersed_moments_from_heights(p, zeta, sharpness=None):
    """:func:`immersed_moment_from_heights` over a mesh: ``p`` (F, 3, 3), ``zeta`` (F, 3) -> (F,), (F, 3)."""
    return jax.vmap(lambda pi, zi: immersed_moment_from_heights(pi, zi, sharpness))(p, zeta)


def immersed_areas_from_heights(p, zeta, sharpness=None):
    """:func:`immersed_area_from_heights` over a mesh: ``p`` (F, 3, 3), ``zeta`` (F, 3) -> (F,), (F, 3)."""
    return jax.vmap(lambda pi, zi: immersed_area_from_heights(pi, zi, sharpness))(p, zeta)


def immersed_areas(p, surface, sharpness=None):
    """:func:`immersed_area` over a mesh: ``p`` (F, 3, 3), ``surface`` (F, 3) -> (F,), (F, 3)."""
    return jax.vmap(lambda pi, si: immersed_area(pi, si, sharpness))(p, surface)
