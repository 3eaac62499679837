"""The stone as a rigid body: mesh geometry in its body frame plus mass properties.

A :class:`RigidStone` is a pytree of arrays, so stones with the same number of
triangles share one compiled simulator and can be batched.
"""

from __future__ import annotations

import dataclasses
import math

import jax
import numpy as np

from ._docs import document_fields
from ._arrays import float_array
from ._checks import ParameterError, check_range, check_real
from .mesh import TriMesh, mass_properties, validate_mesh


@document_fields
@jax.tree_util.register_dataclass
@dataclasses.dataclass(frozen=True)
class RigidStone:
    """A rigid stone: body-frame geometry (origin at the centre of mass) and mass properties.

    Its fields are independent pytree leaves, some derived from others by :func:`rigid_stone`
    (``inv_inertia`` from ``inertia``; ``normals``, ``areas``, ``radius`` from ``triangles``;
    ``inertia`` from the mass and the mesh). A gradient with respect to a field is therefore a
    *partial* derivative with the other fields held: ``grad.inertia`` alone is not d/d(inertia) of a
    consistent stone (which also moves ``inv_inertia``: measured on one throw, +35.8 against -2.7 with
    both), and ``grad.mass`` keeps the inertia (a weighted stone). For the derivative along a
    consistent change, combine the fields' gradients by the chain rule, e.g. for a scaled inertia
    ``I -> kI``: ``sum(g.inertia * I) - sum(g.inv_inertia * inv_I)``.
    """

    triangles: jax.Array
    """(F, 3, 3) triangle vertices in the body frame, relative to the centre of mass [m]."""
    normals: jax.Array
    """(F, 3) outward unit normals in the body frame [-]."""
    areas: jax.Array
    """(F,) triangle areas [m^2]."""
    mass: jax.Array
    """() total mass [kg]."""
    inertia: jax.Array
    """(3, 3) inertia tensor about the centre of mass, body (principal) frame: diagonal [kg m^2]."""
    inv_inertia: jax.Array
    """(3, 3) inverse of ``inertia`` [1/(kg m^2)]."""
    radius: jax.Array
    """() largest distance of a vertex from the centre of mass [m] (bounds the stone)."""
    thickness: jax.Array
    """() extent of the stone along its body z axis (its face normal) [m]: the triangles' extent, for
    reports and plots (the simulation does not use it; :meth:`check` refuses any other value)."""

    @property
    def n_triangles(self) -> int:
        """Number of triangles F of the mesh (``triangles`` is (F, 3, 3))."""
        return self.triangles.shape[-3]

    def check(self) -> "RigidStone":
        """Raise :class:`jaxskip.ParameterError` unless this is a usable single stone; return it.

        :func:`rigid_stone` builds valid stones; this guards one built or changed by hand
        (``dataclasses.replace(stone, mass=...)``), which the simulator would otherwise run into
        NaN distances or a "sank" with a negative mass. Checked on concrete values (a traced stone
        passes through): the shapes above with one F; every number finite; ``mass`` > 0 with the
        density it implies through the mesh's volume in :data:`DENSITY_RANGE`; ``areas`` > 0;
        unit ``normals``; ``inertia`` diagonal (the principal frame) and positive definite with
        ``inv_inertia`` its inverse; ``radius`` in :data:`RADIUS_RANGE` and at least the vertices' reach;
        ``thickness`` the triangles' extent along body z.
        (The mass distribution may differ from the mesh's uniform one: a weighted stone is allowed.)
        """
        leaves = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        if any(isinstance(v, jax.core.Tracer) for v in leaves.values()):
            return self
        for k, v in leaves.items():  # not strings, bools, None or complex numbers (float64 would read "0.12")
            kind = np.asarray(v).dtype.kind
            if kind not in "fiu":
                raise ParameterError(f"stone.{k} must hold real numbers, got {type(v).__name__} of dtype "
                                     f"{np.asarray(v).dtype} ({v!r:.60})")
        a = {k: np.asarray(v, dtype=np.float64) for k, v in leaves.items()}
        tri = a["triangles"].shape
        if len(tri) != 3 or tri[1:] != (3, 3) or tri[0] < 1:
            raise ParameterError(f"stone.triangles must have shape (F, 3, 3) with F >= 1 (one stone, not a batch), "
                                 f"got {tri}")
        n = tri[0]
        shapes = {"normals": (n, 3), "areas": (n,), "mass": (), "inertia": (3, 3),
                  "inv_inertia": (3, 3), "radius": (), "thickness": ()}
        for k, want in shapes.items():
            if a[k].shape != want:
                raise ParameterError(f"stone.{k} must have shape {want} (F = {n} triangles; one stone, "
                                     f"not a batch), got {a[k].shape}")
        for k, v in a.items():
            if not np.all(np.isfinite(v)):
                raise ParameterError(f"stone.{k} must be finite, got {float(v[~np.isfinite(v)].flat[0])!r}")
        m = float(a["mass"])
        if m <= 0.0:
            raise ParameterError(f"stone.mass must be > 0 kg, got {m!r}")
        if np.any(a["areas"] <= 0.0):
            raise ParameterError(f"stone.areas must be > 0 m^2 (no degenerate triangle), got {a['areas'].min()!r}")
        if np.max(np.abs(np.linalg.norm(a["normals"], axis=1) - 1.0)) > 1e-4:
            raise ParameterError("stone.normals must be unit vectors")
        # Divergence theorem: V = sum_i A_i (n_i . c_i) / 3 over the closed mesh.
        volume = float(np.sum(a["areas"] * np.sum(a["normals"] * a["triangles"].mean(axis=1), axis=1)) / 3.0)
        lo, hi = DENSITY_RANGE
        # (within 1e-6 relative: this volume, summed again from the stored and possibly float32 triangles, differs
        # from rigid_stone's in the last digits, and the Clanet disk at exactly 100 kg/m^3 was refused here)
        if not volume > 0.0 or not lo * (1.0 - DENSITY_SLACK) <= m / volume <= hi * (1.0 + DENSITY_SLACK):
            density = m / volume if volume > 0.0 else float("nan")
            raise ParameterError(f"stone.mass must give a density in [{lo:g}, {hi:g}] kg/m^3 (cork to osmium) over "
                                 f"the mesh's {volume * 1e6:.3g} cm^3, got {m!r} kg ({density:.3g} kg/m^3)")
        inertia = a["inertia"]
        scale = float(np.max(np.abs(inertia)))
        if not scale > 0.0 or np.max(np.abs(inertia - inertia.T)) > 1e-6 * scale or \
                np.min(np.linalg.eigvalsh(0.5 * (inertia + inertia.T))) <= 0.0:
            raise ParameterError("stone.inertia must be a symmetric positive definite (3, 3) tensor [kg m^2]")
        if np.max(np.abs(inertia - np.diag(np.diag(inertia)))) > 1e-9 * scale:
            raise ParameterError("stone.inertia must be diagonal: the body frame is the stone's principal frame "
                                 "(the simulator reads only the principal moments; jaxskip.rigid_stone rotates "
                                 "the mesh into that frame)")
        if np.max(np.abs(a["inv_inertia"] @ inertia - np.eye(3))) > 1e-4:
            raise ParameterError("stone.inv_inertia must be the inverse of stone.inertia")
        r = float(a["radius"])
        reach = float(np.max(np.linalg.norm(a["triangles"], axis=-1)))
        if not RADIUS_RANGE[0] <= r <= RADIUS_RANGE[1] or r < reach * (1.0 - 1e-5):
            raise ParameterError(f"stone.radius must be in [{RADIUS_RANGE[0] * 1e3:g} mm, {RADIUS_RANGE[1]:g} m] and "
                                 f"at least the vertices' reach {reach:.4g} m, got {r!r}")
        z = a["triangles"][..., 2]
        extent = float(np.max(z) - np.min(z))
        if abs(float(a["thickness"]) - extent) > 1e-5 * max(extent, 1e-12) + 1e-9:
            raise ParameterError(f"stone.thickness must be the triangles' extent along body z, {extent:.6g} m, got "
                                 f"{float(a['thickness'])!r}")
        return self


def _size_message(name: str, shown: str) -> str:
    return (f"stone {name!r}: its size (bounding radius) must be in [{RADIUS_RANGE[0] * 1e3:g} mm, "
            f"{RADIUS_RANGE[1]:g} m], got {shown} m; vertices are read in metres (an OBJ in millimetres needs "
            "scaling by 0.001)")


def body_frame(mesh: TriMesh) -> tuple[np.ndarray, np.ndarray]:
    """Where :func:`rigid_stone` puts the body frame in ``mesh``'s own frame: the centre of mass ``c`` (3,) [m]
    of the uniform solid, and ``axes`` (3, 3), the principal axes as columns (:func:`principal_axes`), so
    that a point ``p`` of the mesh is at ``axes.T @ (p - c)`` in the body frame and, at a trajectory frame with
    position ``x`` and quaternion ``q``, at ``x + R(q) axes.T (p - c)`` in the world: how to drive the mesh
    you made (with its own vertex order, UVs and materials) by :func:`jaxskip.export.frames`. A uniform
    density's frame, which is the stone's for any density or mass given to :func:`rigid_stone`.

    >>> from jaxskip.stones import clanet_disk
    >>> c, axes = body_frame(clanet_disk().translated([0.1, 0.0, 0.0]))
    >>> bool(np.allclose(c, [0.1, 0.0, 0.0], atol=1e-12)), bool(np.allclose(axes, np.eye(3), atol=1e-12))
    (True, True)
    """
    props = mass_properties(mesh, density=1.0)
    return np.asarray(props.center_of_mass, dtype=np.float64), principal_axes(np.asarray(props.inertia, np.float64))


def principal_axes(inertia: np.ndarray) -> np.ndarray:
    """Rotation (3, 3) whose columns are the principal axes, moments ascending, det +1.

    The third axis (largest moment) keeps the sign of the mesh's own z axis,
    so a stone modelled lying in the x-y plane keeps its top face up.

    Equal moments (a disk's two in-plane ones, to within ``1e-9`` of the largest) leave the axes in
    their plane undetermined: LAPACK returns a pair set by rounding noise, which moved with the mesh's
    position and would move with the LAPACK build. Such a pair (or triple) is replaced by the mesh's own
    axes projected into their plane, taken in the order z, y, x for the larger moments first, so a
    disk lying in the x-y plane keeps the mesh's x and y axes and its result does not depend on where
    the mesh sits.
    """
    moments, axes = np.linalg.eigh(inertia)
    tol = 1e-9 * max(float(np.max(np.abs(moments))), np.finfo(float).tiny)
    start = 0
    while start < 3:
        end = start + 1
        while end < 3 and moments[end] - moments[start] <= tol:
            end += 1
        if end - start > 1:                     # a cluster of equal moments: [start, end)
            plane = axes[:, start:end].copy()
            chosen = []
            for i in range(end - 1, start - 1, -1):   # larger moments first
                candidates = []
                for e in np.eye(3)[::-1]:             # the mesh's z, y, x axes
                    v = plane @ (plane.T @ e)
                    for c in chosen:
                        v = v - c * (c @ v)
                    candidates.append(v)
                norms = np.round([np.linalg.norm(v) for v in candidates], 9)
                v = candidates[int(np.argmax(norms))]
                chosen.append(v / np.linalg.norm(v))
                axes[:, i] = chosen[-1]
        start = end
    if axes[2, 2] < 0.0:
        axes[:, 2] = -axes[:, 2]
    if np.linalg.det(axes) < 0.0:
        axes[:, 0] = -axes[:, 0]
    return axes


#: Densities [kg/m^3] a stone may have, from cork (~120) to osmium (~22600). Outside it the
#: simulator still runs but its answers mean nothing: the paper stone given 0.01 g (density 0.2)
#: is flung about by its first contact and flips 0.01 s after release in the default throw.
DENSITY_RANGE = (100.0, 25000.0)

#: Density [kg/m^3] below which a stone floats in fresh water, which the force laws cannot show (they have no
#: buoyancy): :func:`rigid_stone` warns (:class:`jaxskip.AccuracyWarning`); a stone of 150 kg/m^3 dropped flat at
#: 0.3 m/s was reported "sank".
FLOATS_BELOW = 1000.0

#: Sizes [m] a stone may have: its bounding radius (largest distance of a vertex from the centre of
#: mass), from a 1 mm grain to a 1 m slab. The force laws are for skipping stones; outside this a mesh
#: is most likely in other units (an OBJ written in millimetres makes the paper stone a 50 m, 10^8 kg
#: boulder that still "skips" 53 times).
RADIUS_RANGE = (1e-3, 1.0)


def _round_inside(low: float, high: float, digits: int = 3) -> tuple[float, float]:
    """``(low, high)`` rounded to ``digits`` significant digits inwards (low up, high down): every value
    of the printed interval is valid."""
    def at(x, up):
        e = 10.0 ** (math.floor(math.log10(abs(x))) - digits + 1)
        return (math.ceil if up else math.floor)(x / e * (1 - 1e-12 if up else 1 + 1e-12)) * e

    return at(low, True), at(high, False)


#: Relative slack of :meth:`RigidStone.check`'s density test: the volume it sums again from the stone's stored
#: triangles (float32 unless x64 is on) differs from :func:`rigid_stone`'s float64 one by rounding.
DENSITY_SLACK = 1e-6


def rigid_stone(mesh: TriMesh, *, density: float | None = None, mass: float | None = None) -> RigidStone:
    """Make a :class:`RigidStone` from a closed mesh.

    The body frame is the principal frame: origin at the centre of mass, axes
    along the principal axes of inertia with the largest moment on z. For a
    flat stone that axis is the face normal, the axis that ``tilt`` tips; the
    principal frame lets the free flight rotate exactly (see ``simulate``).

    Parameters
    ----------
    mesh : a closed, outward-oriented :class:`jaxskip.mesh.TriMesh` [m], of bounding radius within
        :data:`RADIUS_RANGE` (1 mm - 1 m).
    density : uniform density [kg/m^3], within :data:`DENSITY_RANGE` (100-25000); or
    mass : total mass [kg] (exactly one of the two), such that the mesh's density lies in that range.

    Examples
    --------
    >>> from jaxskip.stones import clanet_disk
    >>> s = rigid_stone(clanet_disk(), density=2700.0)
    >>> round(float(s.mass) * 1e3, 1)  # grams
    14.5
    """
    if not isinstance(mesh, TriMesh):
        raise ParameterError(f"mesh must be a jaxskip.mesh.TriMesh (e.g. paper_stone(), or load_stone(name)[0] for a "
                             f"built-in name or an .obj path), got {type(mesh).__name__}")
    if (density is None) == (mass is None):
        raise ParameterError("give exactly one of density [kg/m^3] or mass [kg]")
    lo, hi = DENSITY_RANGE
    if density is not None:
        check_range("density", density, lo, hi, unit="kg/m^3 (cork to osmium)")
    if mass is not None:
        mass = check_real("mass", mass, valid="> 0 kg")   # (a mass <= 0 gets this stone's range, below)
    # The bounding radius about the centre of mass lies between half the vertices' largest span and the span:
    # a stone a thousandfold out of range is named as such here, before its mass or inertia can overflow (an
    # OBJ scaled by 1e100 was refused as "a density or mass beyond any physical range?"), and before the mesh's
    # checks (which name a mesh over 1 km across by its span alone); nearer the range, by its exact radius below.
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    # (an empty mesh is named by validate_mesh, below: np.ptp of no vertices raised a raw ValueError; a review)
    span = float(np.max(np.ptp(vertices, axis=0))) if vertices.size and np.all(np.isfinite(vertices)) else None
    if span is not None and not (1e-3 * RADIUS_RANGE[0] <= span and 0.5 * span <= 1e3 * RADIUS_RANGE[1]):
        raise ParameterError(_size_message(mesh.name, f"about {0.5 * span:.3g} to {span:.3g}"))
    validate_mesh(mesh.vertices, mesh.faces, name=mesh.name)  # closed, outward, no degenerate triangle
    # the exact size before the mass: an out-of-range stone was first sent to a mass range that then failed on
    # its size (a 0.05 mm mesh: "--mass must be in [4.56e-12, 1.13e-09] kg", then "its size ... must be in [1 mm,
    # 1 m]"; a review). The bounding radius about the centre of mass, which no density moves.
    unit = mass_properties(mesh, density=1.0)
    radius = float(np.max(np.linalg.norm(np.asarray(mesh.vertices, dtype=np.float64)
                                         - np.asarray(unit.center_of_mass), axis=1)))
    if not RADIUS_RANGE[0] <= radius <= RADIUS_RANGE[1]:
        shown = f"{radius:.4g}"
        if RADIUS_RANGE[0] <= float(shown) <= RADIUS_RANGE[1]:  # ("got 1 m" for 1.0000125 m read as a contradiction)
            shown = f"{radius:.12g}"
        raise ParameterError(_size_message(mesh.name, shown))
    if mass is not None:
        volume = float(unit.volume)
        # (with DENSITY_SLACK: a mass at the range's top, 0.15 kg for 6 cm^3, gave 25000.000000000004 kg/m^3 by
        # rounding and was refused, printing [.., 0.15] kg, while density=25000 gave the same stone)
        if not lo * (1 - DENSITY_SLACK) <= float(mass) / volume <= hi * (1 + DENSITY_SLACK):
            low, high = _round_inside(lo * volume, hi * volume)
            raise ParameterError(
                f"mass must be in [{low:.3g}, {high:.3g}] kg for this stone "
                f"({volume * 1e6:.3g} cm^3: densities {lo:g}-{hi:g} kg/m^3, cork to osmium), got {float(mass)!r} "
                f"(density {float(mass) / volume:.3g} kg/m^3)")
    props = mass_properties(mesh, density=density, mass=mass)
    if float(props.mass) < FLOATS_BELOW * float(props.volume):
        import warnings

        from .simulate import AccuracyWarning   # (here: simulate imports this module)
        # (worded without a leading "stone": the CLI turned it into "--stone 'clanet' is lighter", blaming the stone
        # where --density or --mass made it light; a review)
        warnings.warn(f"the {mesh.name!r} stone at this mass or density is lighter than water "
                      f"({float(props.mass) / float(props.volume):.4g} "
                      f"kg/m^3 < {FLOATS_BELOW:g}): the force laws have no buoyancy (the water pushes by its dynamic "
                      "pressure alone), so where a real stone would float this one sinks once it is slow",
                      AccuracyWarning, stacklevel=2)
    axes = principal_axes(np.asarray(props.inertia, dtype=np.float64))   # (body_frame's, for any density)
    v = (np.asarray(mesh.vertices, dtype=np.float64) - np.asarray(props.center_of_mass)) @ axes
    radius = float(np.max(np.linalg.norm(v, axis=1)))
    tri = v[np.asarray(mesh.faces)]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    area2 = np.linalg.norm(cross, axis=1)
    inertia = axes.T @ np.asarray(props.inertia, dtype=np.float64) @ axes
    inertia = np.diag(np.diag(inertia))  # principal frame: off-diagonals are rounding
    f = float_array  # no compile per field on a first call (jnp.asarray would lift each one)
    return RigidStone(
        triangles=f(tri),
        normals=f(cross / area2[:, None]),
        areas=f(0.5 * area2),
        mass=f(float(props.mass)),
        inertia=f(inertia),
        inv_inertia=f(np.linalg.inv(inertia)),
        radius=f(radius),
        thickness=f(float(np.ptp(v[:, 2]))),
    )
