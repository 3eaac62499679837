"""Closed triangle meshes of rigid stones: validation, mass properties, OBJ I/O.

Everything here is plain numpy (float64) and runs once, before a simulation;
the differentiable part of jaxskip only consumes the resulting arrays.

Conventions
-----------
* SI units throughout: metres [m], kilograms [kg], densities [kg/m^3],
  moments of inertia [kg m^2].
* A mesh is a closed, orientable (watertight) surface.  Each triangle lists its
  vertex indices counter-clockwise as seen from *outside*, so the right-hand
  normal ``(v1 - v0) x (v2 - v0)`` points outward and the signed volume is
  positive.
"""

from __future__ import annotations

import dataclasses
import math
import re
import os
import stat
from pathlib import Path

import numpy as np

from ._docs import document_fields
from ._files import check_file_path, writing
from ._checks import ParameterError, check_positive

__all__ = [
    "MeshError",
    "TriMesh",
    "MassProperties",
    "validate_mesh",
    "mass_properties",
    "read_obj",
    "write_obj",
]

#: Largest OBJ file :func:`read_obj` agrees to read [bytes].
MAX_OBJ_BYTES = 50 * 1024 * 1024

#: Most vertices and most triangles (after fan triangulation) :func:`read_obj` agrees to read, and the
#: longest line [characters]: a stone of a million triangles would be far too slow to simulate, and the
#: caps keep a hostile file's parse to a few hundred MB of memory.
MAX_OBJ_VERTICES = 1_000_000
MAX_OBJ_TRIANGLES = 2_000_000
MAX_OBJ_LINE = 1 << 20

#: Largest extent [m] of a mesh along any axis: a thousand times a stone's largest size (1 m in radius). A
#: larger mesh is in other units, and its arithmetic could overflow.
MAX_MESH_SPAN = 1000.0

#: A triangle counts as degenerate when its area is at most this fraction of
#: the squared bounding-box diagonal of the mesh.
DEGENERATE_AREA_FRACTION = 1e-12


class MeshError(ParameterError):
    """A mesh, a mesh file or a mesh-related parameter is invalid (a :class:`jaxskip.ParameterError`,
    so one ``except jaxskip.ParameterError`` catches every refused input)."""


# ---------------------------------------------------------------------------
# small helpers
# ---------------------------------------------------------------------------


def _positive_scalar(value, name: str) -> float:
    """Return ``value`` as a float, or raise MeshError unless it is a finite real number > 0 (strings and
    bools refused, as by :func:`jaxskip._checks.check_positive`)."""
    try:
        return check_positive(name, value)
    except ParameterError as err:
        raise MeshError(str(err)) from None


def _float_array(value, name: str) -> np.ndarray:
    """``value`` as a float64 array, or MeshError naming ``name`` (strings, ragged lists, ...)."""
    try:
        if isinstance(value, (str, bytes)):
            raise TypeError
        return np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise MeshError(f"{name} must be real numbers, got {value!r}") from None


def _as_vertices(vertices, name: str) -> np.ndarray:
    """Convert to a float64 (V, 3) array, raising MeshError on wrong dtype/shape."""
    try:
        arr = np.asarray(vertices)
    except ValueError:  # ragged nesting
        raise MeshError(f"{name}: vertices must be an array of shape (V, 3), got a ragged "
                        "sequence") from None
    if arr.dtype.kind not in "fiu":
        raise MeshError(f"{name}: vertices must be real numbers, got dtype {arr.dtype}")
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise MeshError(f"{name}: vertices must have shape (V, 3), got {arr.shape}")
    return arr.astype(np.float64)


def _as_faces(faces, name: str) -> np.ndarray:
    """Convert to an int64 (F, 3) array, raising MeshError on wrong dtype/shape."""
    try:
        arr = np.asarray(faces)
    except ValueError:  # ragged nesting
        raise MeshError(f"{name}: faces must be an array of shape (F, 3), got a ragged "
                        "sequence") from None
    if arr.size and arr.dtype.kind not in "iu":
        raise MeshError(f"{name}: faces must be integer vertex indices, got dtype {arr.dtype}")
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise MeshError(f"{name}: faces must have shape (F, 3), got {arr.shape}")
    return arr.astype(np.int64)


def _check_indices(faces: np.ndarray, n_vertices: int, name: str) -> None:
    """Raise MeshError unless every index of ``faces`` (F, 3) is in ``[0, n_vertices)``."""
    bad = (faces < 0) | (faces >= n_vertices)
    if bad.any():
        f, k = map(int, np.argwhere(bad)[0])
        one_based = " (1-based indices? OBJ files count from 1, TriMesh from 0)" if (
            faces.min() >= 1 and faces.max() == n_vertices) else ""
        raise MeshError(f"{name}: face {f} has vertex index {int(faces[f, k])}, outside [0, {n_vertices - 1}] "
                        f"(the mesh has {n_vertices} vertices){one_based}")


def _readonly(arr: np.ndarray) -> np.ndarray:
    arr = np.array(arr)  # private copy, so the caller cannot mutate it behind our back
    arr.setflags(write=False)
    return arr


def _triangle_cross(vertices: np.ndarray, faces: np.ndarray) -> np.ndarray:
    """Right-hand cross products ``(v1 - v0) x (v2 - v0)``, shape (F, 3) [m^2]."""
    tri = vertices[faces]
    return np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])


def _signed_volume(vertices: np.ndarray, faces: np.ndarray) -> float:
    """Enclosed volume by the divergence theorem [m^3].

    ``V = (1/6) sum_f (a_f - p) . ((b_f - p) x (c_f - p))`` for any reference
    point ``p`` (here the vertex mean, to limit cancellation).
    """
    rel = vertices - vertices.mean(axis=0)
    tri = rel[faces]
    return float(np.einsum("ij,ij->", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])) / 6.0)


# ---------------------------------------------------------------------------
# TriMesh
# ---------------------------------------------------------------------------


@document_fields
@dataclasses.dataclass(frozen=True, eq=False)
class TriMesh:
    """An immutable triangle mesh of a closed surface.

    The arrays are stored as read-only copies.  The constructor only checks
    shapes, dtypes and that every face index is a vertex (in ``[0, V)``: a
    1-based or negative index is refused, not wrapped); call :func:`validate_mesh`
    to check that the surface is closed, manifold and outward oriented.  Meshes
    compare by identity.
    """

    vertices: np.ndarray
    """Vertex positions, shape (V, 3), float64 [m]."""

    faces: np.ndarray
    """Vertex indices of each triangle, shape (F, 3), int64, counter-clockwise
    as seen from outside (right-hand normals point outward)."""

    name: str = "mesh"
    """Human-readable name used in error messages."""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str):
            raise MeshError(f"name must be a str, got {self.name!r}")
        object.__setattr__(self, "vertices", _readonly(_as_vertices(self.vertices, self.name)))
        object.__setattr__(self, "faces", _readonly(_as_faces(self.faces, self.name)))
        _check_indices(self.faces, len(self.vertices), self.name)

    @property
    def n_triangles(self) -> int:
        """Number of triangles F."""
        return int(self.faces.shape[0])

    @property
    def triangles(self) -> np.ndarray:
        """Vertex coordinates of every triangle, shape (F, 3, 3) [m]."""
        return self.vertices[self.faces]

    @property
    def normals(self) -> np.ndarray:
        """Unit outward normals ``n = (v1 - v0) x (v2 - v0) / |...|``, shape (F, 3)."""
        cross = _triangle_cross(self.vertices, self.faces)
        return cross / np.linalg.norm(cross, axis=1, keepdims=True)

    @property
    def areas(self) -> np.ndarray:
        """Triangle areas ``|(v1 - v0) x (v2 - v0)| / 2``, shape (F,) [m^2]."""
        return 0.5 * np.linalg.norm(_triangle_cross(self.vertices, self.faces), axis=1)

    def translated(self, offset) -> "TriMesh":
        """Return the mesh moved by ``offset``, shape (3,) [m]."""
        offset = _float_array(offset, 'offset')
        if offset.shape != (3,) or not np.all(np.isfinite(offset)):
            raise MeshError(f"offset must be 3 finite numbers [m], got {offset!r}")
        return TriMesh(self.vertices + offset, self.faces, self.name)

    def scaled(self, factor) -> "TriMesh":
        """Return the mesh scaled about the origin.

        Parameters
        ----------
        factor : float or array_like, shape (3,)
            Positive finite scale factor(s), dimensionless; a (3,) array scales
            x, y, z separately.  Positive factors keep the outward orientation.
        """
        f = _float_array(factor, 'factor')
        if f.shape not in ((), (3,)) or not np.all(np.isfinite(f)) or not np.all(f > 0):
            raise MeshError(f"factor must be a positive finite number or 3 of them, got {factor!r}")
        return TriMesh(self.vertices * f, self.faces, self.name)

    def rotated(self, rotation) -> "TriMesh":
        """Return the mesh rotated about the origin: ``v' = R v``.

        Parameters
        ----------
        rotation : array_like, shape (3, 3)
            Proper rotation matrix R (``R R^T = 1``, ``det R = +1``, to 1e-9);
            reflections are refused since they would turn the mesh inside out.
        """
        r = _float_array(rotation, 'rotation')
        if (
            r.shape != (3, 3)
            or not np.allclose(r @ r.T, np.eye(3), rtol=0.0, atol=1e-9)
            or not np.linalg.det(r) > 0
        ):
            raise MeshError("rotation must be a 3x3 proper rotation matrix (R R^T = I, det R = +1)")
        return TriMesh(self.vertices @ r.T, self.faces, self.name)


# ---------------------------------------------------------------------------
# validation
# ---------------------------------------------------------------------------


class _Numbering:
    """How error messages name triangles and vertices: from 0 in array order (default), or, for a mesh
    read from an OBJ file, by the file's ``f`` line each triangle came from and the file's 1-based vertex
    numbers (``lines`` (F,) and ``numbers`` (V,) ints)."""

    def __init__(self, lines=None, numbers=None):
        self.lines, self.numbers = lines, numbers

    def tri(self, i) -> str:
        return f"triangle {int(i)}" if self.lines is None else f"the triangle of line {int(self.lines[int(i)])}"

    def tris(self, idx) -> str:
        idx = [int(i) for i in idx]
        if self.lines is None:
            return f"triangles {idx}"
        return f"the triangles of lines {[int(self.lines[i]) for i in idx]}"

    def vert(self, i) -> str:
        return f"vertex {int(i)}" if self.numbers is None else f"vertex {int(self.numbers[int(i)])}"

    def verts(self, idx) -> list:
        return [int(i) if self.numbers is None else int(self.numbers[int(i)]) for i in idx]


def validate_mesh(vertices, faces, *, name: str = "mesh", _numbering: _Numbering | None = None) -> None:
    """Check that ``(vertices, faces)`` is a closed, outward-oriented triangle mesh.

    Parameters
    ----------
    vertices : array_like, shape (V, 3)
        Vertex positions [m], finite real numbers.
    faces : array_like, shape (F, 3)
        Integer vertex indices in ``[0, V)``.
    name : str
        Name used in error messages (e.g. a file name).

    Raises
    ------
    MeshError
        On the first problem found, in this order: shapes/dtypes; fewer than
        4 triangles (a closed mesh needs at least 4); non-finite vertices;
        indices out of range; triangles with a repeated index; vertices that
        no triangle uses (they would enter the stone's size); degenerate
        triangles (area ``<= 1e-12 * d**2`` with ``d`` the bounding-box
        diagonal); edges not shared by exactly two triangles (holes or
        non-manifold edges); inconsistent orientation (a directed edge used
        twice); more than one connected part (a stone is one closed
        surface: a second part could be inside out, or nested inside the
        first, and its volume would count wrongly); non-positive signed
        volume (inside-out mesh).

    Notes
    -----
    A closed, consistently oriented surface uses each directed edge ``(a, b)``
    exactly once and its reverse ``(b, a)`` exactly once.  The signed volume
    follows from the divergence theorem,
    ``V = (1/6) sum_f v0 . (v1 x v2)``, and is positive iff the normals point
    outward.

    Not checked: self-intersection. A surface folded through itself (the paper stone's top pole pushed
    through its bottom) passes, with a volume that counts the fold negatively (1.27e-5 against 4.55e-5 m^3)
    and faces in the fold whose normals point into the stone, so its mass and its water forces are wrong.
    Meshes made by the constructors of :mod:`jaxskip.stones` never fold; check a mesh from elsewhere in a
    mesh tool.
    """
    v = _as_vertices(vertices, name)
    f = _as_faces(faces, name)
    n_v, n_f = len(v), len(f)
    at = _Numbering() if _numbering is None else _numbering
    if n_f < 4:
        raise MeshError(f"{name}: a closed mesh needs at least 4 triangles, got {n_f}")

    bad = np.flatnonzero(~np.all(np.isfinite(v), axis=1))
    if bad.size:
        raise MeshError(f"{name}: {at.vert(bad[0])} is not finite ({v[bad[0]].tolist()}); "
                        "all coordinates must be finite numbers")

    bad = np.flatnonzero(np.any((f < 0) | (f >= n_v), axis=1))
    if bad.size:
        raise MeshError(f"{name}: triangle {bad[0]} has vertex index out of range "
                        f"{f[bad[0]].tolist()}; indices must lie in [0, {n_v - 1}]")

    bad = np.flatnonzero((f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 2] == f[:, 0]))
    if bad.size:
        raise MeshError(f"{name}: {at.tri(bad[0])} repeats a vertex index {at.verts(f[bad[0]])}; "
                        "remove this degenerate triangle")

    unused = np.setdiff1d(np.arange(n_v), f)
    if unused.size:
        raise MeshError(f"{name}: {unused.size} of its {n_v} vertices (the first: {at.vert(unused[0])}) belong to "
                        "no triangle; remove them (they would count towards the stone's size)")

    # (a vertex at 1e30 m was called a degenerate triangle, "area 2.5e+28 m^2", and at 1e200 NumPy's overflow
    # warnings came first; a review) A stone is at most 1 m in radius: a mesh 1 km across is in other units.
    span = np.ptp(v, axis=0)
    if not np.all(span <= MAX_MESH_SPAN):
        raise MeshError(f"{name}: spans {float(np.max(span)):.3g} m along an axis, more than {MAX_MESH_SPAN:g} m: "
                        "coordinates are in metres and a stone is at most 1 m in radius (convert a mesh in other "
                        "units)")
    diag2 = float(np.sum(span ** 2))
    areas = 0.5 * np.linalg.norm(_triangle_cross(v, f), axis=1)
    bad = np.flatnonzero(areas <= DEGENERATE_AREA_FRACTION * diag2)
    if bad.size:
        raise MeshError(f"{name}: {at.tri(bad[0])} {at.verts(f[bad[0]])} is degenerate "
                        f"(area {areas[bad[0]]:.3g} m^2); remove it or fix its vertices")

    try:
        _check_edges(f, n_v, name, at)
    except MeshError as exc:
        # A mesh exported face by face (as from STL) repeats each corner per face: its triangles share no vertex,
        # so every edge reads as a hole. Say so, rather than 'add the missing triangles'.
        _, first, count = np.unique(v, axis=0, return_index=True, return_counts=True)
        if np.any(count > 1):
            again = np.flatnonzero(~np.isin(np.arange(n_v), first))
            twin = first[np.flatnonzero(np.all(v[first] == v[again[0]], axis=1))[0]]
            raise MeshError(f"{exc}. But {again.size} of its {n_v} vertices repeat another's position (the first: "
                            f"{at.vert(again[0])} at {v[again[0]].tolist()}, as {at.vert(twin)}): the triangles do "
                            "not share their corners, as in a mesh exported face by face (STL); merge (weld) the "
                            "equal vertices, e.g. Blender's Merge by Distance") from None
        raise

    parts = _parts(f, n_v)
    if parts.max() > 0:
        n_parts = int(parts.max()) + 1
        volumes = [_signed_volume(v, f[parts == k]) for k in range(min(n_parts, 5))]  # the ones shown
        raise MeshError(f"{name}: the mesh has {n_parts} separate closed parts (signed volumes "
                        f"{', '.join(f'{x:.3g}' for x in volumes[:5])}{', ...' if n_parts > 5 else ''} m^3; "
                        f"{at.tris(np.flatnonzero(parts == 1)[:5])}... form the second); a stone "
                        "must be one closed surface: remove the extra parts")

    volume = _signed_volume(v, f)
    if not np.isfinite(volume):   # (a NaN volume was read as "<= 0, so the faces point inward")
        raise MeshError(f"{name}: its volume overflows the floating-point range (vertex coordinates up to "
                        f"{float(np.max(np.abs(v))):.3g}); vertices are read in metres")
    # A closed surface that encloses nothing (a two-sided sheet, or a stone so far out that its coordinates round
    # it flat) has a signed volume of rounding size: that is no volume, not inward faces (reversing changes nothing)
    # (rounding: the coordinates relative to their mean carry eps * max|v| each, over a stone L across)
    extent, far = np.ptp(v, axis=0), float(np.max(np.abs(v)))
    size = float(np.max(extent))
    if abs(volume) <= size ** 2 * (1e-9 * size + 1e3 * np.finfo(np.float64).eps * far):
        raise MeshError(f"{name}: the mesh encloses no volume (signed volume {volume:.3g} m^3; its extents are "
                        f"{', '.join(f'{e:.3g}' for e in extent)} m): a stone must be a solid with a thickness, not a "
                        "flat or two-sided sheet" + (f" (or its coordinates, up to {far:.3g} m, are too large for its "
                                                     "size)" if far > 1e6 * size else ""))
    if not volume > 0.0:
        raise MeshError(f"{name}: signed volume is {volume:.6g} m^3 <= 0, so the faces point "
                        "inward; reverse the vertex order of every triangle")


def _edges(faces: np.ndarray, n_vertices: int):
    """The directed edges (f0, f1), (f1, f2), (f2, f0) of every triangle, (3F,) heads and tails in
    triangle order, and each edge's direction-free key ``min * V + max``."""
    heads = faces.reshape(-1)
    tails = np.roll(faces, -1, axis=1).reshape(-1)
    return heads, tails, np.minimum(heads, tails) * n_vertices + np.maximum(heads, tails)


def _check_edges(faces: np.ndarray, n_vertices: int, name: str, at: _Numbering) -> None:
    """Raise MeshError unless every directed edge occurs once, together with its reverse."""
    heads, tails, undirected = _edges(faces, n_vertices)
    edge_triangle = np.repeat(np.arange(len(faces)), 3)

    def describe(edge_keys: np.ndarray, key: int) -> str:
        a, b = divmod(int(key), n_vertices)
        a, b = at.verts((a, b))
        return f"edge ({a}, {b}) of {at.tris(edge_triangle[edge_keys == key])}"

    keys, counts = np.unique(undirected, return_counts=True)
    if np.any(counts == 1):
        raise MeshError(f"{name}: {describe(undirected, keys[counts == 1][0])} belongs to only "
                        "one triangle: the mesh has a hole (it is not closed); add the missing "
                        "triangles")
    if np.any(counts > 2):
        raise MeshError(f"{name}: {describe(undirected, keys[counts > 2][0])} is shared by more "
                        "than two triangles: the mesh is not manifold; split it into separate "
                        "closed meshes")

    directed = heads * n_vertices + tails
    keys, counts = np.unique(directed, return_counts=True)
    if np.any(counts > 1):
        raise MeshError(f"{name}: {describe(directed, keys[counts > 1][0])} runs in the same "
                        "direction in both: inconsistent orientation; flip one of them so all "
                        "triangles are counter-clockwise seen from outside")


def _parts(faces: np.ndarray, n_vertices: int) -> np.ndarray:
    """Connected part of every triangle, (F,) ints numbered 0, 1, ... in order of first
    appearance; triangles sharing an edge are in the same part (label propagation with pointer
    jumping over the edge-adjacency pairs; for a closed manifold mesh every edge has two)."""
    keys = _edges(faces, n_vertices)[2]
    order = np.argsort(keys, kind="stable")
    tri = np.repeat(np.arange(len(faces)), 3)[order]
    same = keys[order][1:] == keys[order][:-1]
    a, b = tri[:-1][same], tri[1:][same]
    label = np.arange(len(faces))
    while True:
        low = np.minimum(label[a], label[b])
        new = label.copy()
        np.minimum.at(new, a, low)
        np.minimum.at(new, b, low)
        new = new[new]
        if np.array_equal(new, label):
            break
        label = new
    return np.unique(label, return_inverse=True)[1].reshape(-1)


# ---------------------------------------------------------------------------
# mass properties
# ---------------------------------------------------------------------------


@document_fields
@dataclasses.dataclass(frozen=True, eq=False)
class MassProperties:
    """Rigid-body mass properties of a uniform solid."""

    mass: float
    """Total mass m [kg]."""

    volume: float
    """Enclosed volume [m^3]."""

    center_of_mass: np.ndarray
    """Centre of mass in the mesh frame, shape (3,) [m]."""

    inertia: np.ndarray
    """Inertia tensor about the centre of mass, axes of the mesh frame,
    shape (3, 3), symmetric positive definite [kg m^2]."""

    def __post_init__(self) -> None:
        for field in ("center_of_mass", "inertia"):
            object.__setattr__(self, field, _readonly(np.asarray(getattr(self, field), float)))


def mass_properties(mesh: TriMesh, *, density: float | None = None,
                    mass: float | None = None) -> MassProperties:
    """Exact mass properties of a uniform solid bounded by a closed mesh.

    Parameters
    ----------
    mesh : TriMesh
        Closed, outward-oriented mesh (see :func:`validate_mesh`), vertices [m].
    density : float, optional
        Uniform density rho [kg/m^3], finite and > 0.
    mass : float, optional
        Total mass [kg], finite and > 0; then ``rho = mass / volume``.  Give
        exactly one of ``density`` and ``mass``.  Either is checked only for
        being finite and > 0 (no upper bound here); otherwise :class:`MeshError`.

    Returns
    -------
    MassProperties
        Mass [kg], volume [m^3], centre of mass (3,) [m] and inertia tensor
        (3, 3) about the centre of mass [kg m^2].

    Notes
    -----
    The solid is split into signed tetrahedra ``(p, a, b, c)``, one per
    triangle, with apex ``p`` at the vertex mean (any apex is exact; a central
    one limits cancellation).  With ``a, b, c`` relative to ``p``,
    ``d = a . (b x c)`` and ``s = a + b + c``:

    * volume        ``V = sum d / 6``
    * first moment  ``S = sum d s / 24``  (so the centroid is ``p + S / V``)
    * second moment ``C = int x x^T dV = sum d (a a^T + b b^T + c c^T + s s^T) / 120``

    (the closed form of the tetrahedron covariance; F. Tonon, J. Math. Stat.
    1(1):8-11, 2004; J. Blow & A. Binstock, "How to find the inertia tensor
    (or other mass properties) of a 3D solid body represented by a triangle
    mesh", 2004).  The parallel-axis theorem moves ``C`` to the centroid ``c``:
    ``C_c = C - V c c^T``, and the inertia tensor is
    ``I = rho (tr(C_c) 1 - C_c)``.  The result is exact up to rounding for any
    closed mesh.
    """
    _check_mesh_type(mesh)
    if (density is None) == (mass is None):
        raise MeshError("give exactly one of density [kg/m^3] or mass [kg]")
    if density is not None:
        density = _positive_scalar(density, "density [kg/m^3]")
    else:
        mass = _positive_scalar(mass, "mass [kg]")
    with np.errstate(over="ignore", invalid="ignore"):   # (a non-finite volume is named below)
        origin = mesh.vertices.mean(axis=0)
        tri = mesh.triangles - origin
        a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
        d = np.einsum("ij,ij->i", a, np.cross(b, c))
        volume = float(d.sum() / 6.0)
    s = a + b + c

    if not math.isfinite(volume):   # (a NaN read as '<= 0; the mesh must be closed with outward normals')
        raise MeshError(f"{mesh.name}: its volume is not a finite number ({volume}): a vertex coordinate is not "
                        "finite, or the mesh is far too large for floating point (it is read in metres); run "
                        "validate_mesh")
    if not volume > 0.0:
        raise MeshError(f"{mesh.name}: signed volume is {volume:.6g} m^3 <= 0; the mesh must be "
                        "closed with outward normals (run validate_mesh)")
    centroid = (d @ s) / 24.0 / volume
    second = (np.einsum("i,ij,ik->jk", d, a, a) + np.einsum("i,ij,ik->jk", d, b, b)
              + np.einsum("i,ij,ik->jk", d, c, c) + np.einsum("i,ij,ik->jk", d, s, s)) / 120.0
    second_c = second - volume * np.outer(centroid, centroid)

    rho = density if density is not None else mass / volume
    with np.errstate(over="ignore", under="ignore", invalid="ignore"):  # refused below, with the figures
        inertia = rho * (np.trace(second_c) * np.eye(3) - second_c)
    inertia = 0.5 * (inertia + inertia.T)
    moments = np.linalg.eigvalsh(inertia) if np.all(np.isfinite(inertia)) else None
    mass_ok = math.isfinite(rho * volume) and rho * volume > 0.0
    if not (mass_ok and moments is not None and np.all(moments > 0.0)):
        given = f"density {density!r} kg/m^3" if density is not None else f"mass {mass!r} kg"
        raise MeshError(f"{mesh.name}: {given} gives mass {rho * volume!r} kg and principal moments "
                        f"{'not finite' if moments is None else moments.tolist()} kg m^2; they must be finite and > 0 ("
                        + ("is the mesh one closed, outward surface? run validate_mesh)" if mass_ok and moments is not None
                           else "a density or mass beyond any physical range?)"))
    return MassProperties(mass=rho * volume, volume=volume,
                          center_of_mass=origin + centroid, inertia=inertia)


# ---------------------------------------------------------------------------
# OBJ input/output
# ---------------------------------------------------------------------------

_IGNORED_OBJ_KEYWORDS = frozenset({"vn", "vt", "o", "g", "s", "usemtl", "mtllib"})
_OBJ_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|[+-]?(?:nan|inf|infinity)",
                         re.ASCII | re.IGNORECASE)
# A face entry: i, i/t, i/t/n or i//n (ASCII digits; "1/x/1", "1/" or "1/2/3/4" are malformed).
_OBJ_FACE_ENTRY = re.compile(r"([+-]?[0-9]+)(?:/-?[0-9]+(?:/-?[0-9]+)?|//-?[0-9]+)?", re.ASCII)


def _obj_vertex(fields: list[str]) -> list[float]:
    """Parse the fields of ``v x y z [w]`` or ``v x y z r g b`` (a colour per vertex, as MeshLab and
    photogrammetry tools write scanned objects; the colour is ignored) into ``[x, y, z]``; ValueError if
    malformed."""
    if len(fields) not in (3, 4, 6):
        raise ValueError("a vertex needs 3 coordinates (and optionally w, or a colour r g b)")
    # Plain ASCII decimals only: float() also reads "0.0_1" as 0.01 and full-width or Arabic-Indic digits.
    if not all(_OBJ_NUMBER.fullmatch(t) for t in fields):
        raise ValueError("vertex coordinates must be numbers (plain ASCII decimals, such as -1.5e-3)")
    xyz = [float(t) for t in fields]
    if not all(math.isfinite(x) for x in xyz):
        raise ValueError("vertex coordinates must be finite")
    return xyz[:3]


def _joined_lines(lines: list[str]):
    """``(number, line)`` for each logical line of an OBJ file: a line whose text before any ``#`` ends in a
    backslash is joined with the next (numbered as its first physical line)."""
    number, pending = 0, None
    for k, line in enumerate(lines, start=1):
        if pending is not None:
            line = pending + " " + line
        else:
            number = k
        code = line.split("#", 1)[0].rstrip()
        if code.endswith("\\") and k < len(lines):
            pending = code[:-1]
            continue
        pending = None
        yield number, line


def _fan_corner(vertices: list[list[float]], idx: list[int]) -> list[int]:
    """Polygon ``idx`` listed from its first corner whose fan ``(0, k, k+1)`` triangulates it (``idx`` itself
    when its own first corner does); ValueError when none does. Every fan triangle must turn the same way
    as the polygon (its Newell normal). A polygon that is not convex as seen from its first vertex (an
    L-shaped face listed from its reflex corner) fans into overlapping triangles, one facing into the stone,
    which the mesh's edge and volume checks cannot see; a convex one listed from a corner on a straight edge
    (the midpoint of two others) fans into a triangle of no area, so another corner is taken."""
    p = np.asarray([vertices[k] for k in idx], dtype=np.float64)
    newell = np.cross(p, np.roll(p, -1, axis=0)).sum(axis=0)
    for start in range(len(idx)):
        q = np.roll(p, -start, axis=0)
        fan = np.cross(q[1:-1] - q[0], q[2:] - q[0])
        if np.all(fan @ newell > 1e-12 * np.linalg.norm(fan, axis=1) * np.linalg.norm(newell)):
            return idx[start:] + idx[:start]
    raise ValueError(f"the {len(idx)}-sided face is not convex (no corner sees every edge), so it cannot be "
                     "fan-triangulated (its triangles would overlap and fold inwards); triangulate it in the "
                     "exporting program (e.g. Blender's Triangulate modifier)")


def _obj_face(fields: list[str], n_vertices: int) -> list[int]:
    """Parse the fields of ``f ...`` into 0-based vertex indices; ValueError if malformed.

    Each field is ``i``, ``i/t``, ``i/t/n`` or ``i//n``; only ``i`` is used.
    Index ``i > 0`` means vertex ``i - 1``; ``i < 0`` means ``n_vertices + i``
    (counting back from the last vertex defined so far).
    """
    if len(fields) < 3:
        raise ValueError("a face needs at least 3 vertices")
    indices = []
    for field in fields:
        entry = _OBJ_FACE_ENTRY.fullmatch(field)
        if entry is None:
            raise ValueError(f"bad face entry {field[:20]!r} (expected i, i/t, i/t/n or i//n, integers)")
        i = int(entry.group(1))
        k = i - 1 if i > 0 else n_vertices + i
        if i == 0 or not 0 <= k < n_vertices:
            raise ValueError(f"vertex index {i} does not refer to one of the {n_vertices} "
                             "vertices defined so far")
        indices.append(k)
    return indices


def read_obj(path: str | os.PathLike, *, name: str | None = None) -> TriMesh:
    """Read a closed triangle mesh from a Wavefront OBJ file.

    Only geometry is read: ``v x y z [w]`` (``w`` is ignored) and
    ``f i j k ...`` lines whose entries may be ``i``, ``i/t``, ``i/t/n`` or
    ``i//n``; indices are 1-based, negative ones count back from the last
    vertex defined so far.  Polygons with more than 3 vertices are
    fan-triangulated ``(0, k, k+1)`` from their first corner that sees every edge (a corner on a straight
    edge, or the reflex corner of an L, gives way to the next that works); a polygon no corner of which sees
    every edge (a U: the fan would fold) is refused.  Numbers are plain ASCII.  Lines starting with ``vn vt o g s
    usemtl mtllib``, comments (``#``) and blank lines are ignored; anything
    else is an error.  Nothing is ever evaluated.

    Parameters
    ----------
    path : str or os.PathLike
        A regular file; at most 50 MiB (:data:`MAX_OBJ_BYTES`), :data:`MAX_OBJ_VERTICES` vertices,
        :data:`MAX_OBJ_TRIANGLES` triangles and :data:`MAX_OBJ_LINE` characters a line.  Coordinates
        are taken as metres; vertices that no face uses are dropped (the faces renumbered).
    name : str, optional
        Mesh name; defaults to the file name without extension.

    Returns
    -------
    TriMesh
        The mesh, checked with :func:`validate_mesh`.

    Raises
    ------
    MeshError
        If the file is missing, too large, not text (bytes beyond ASCII are read as UTF-8, or else as
        Latin-1: they can only stand in comments and names, which are not parsed), has a malformed
        line (the message gives file and line number) or is not a valid mesh.
    """
    if not isinstance(path, (str, os.PathLike)):
        raise MeshError(f"path must be a file name (str or os.PathLike), got {path!r}")
    if name is not None and not isinstance(name, str):
        raise MeshError(f"name must be a str, got {name!r}")
    path = Path(path)
    fname = path.name
    try:
        # (before opening: opening a named pipe for reading waits for a writer, without end)
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise MeshError(f"cannot read OBJ file {str(path)!r}: not a regular file")
        with open(path, "rb") as fh:
            st = os.fstat(fh.fileno())
            if not stat.S_ISREG(st.st_mode):  # a device or a pipe would be read without end
                raise MeshError(f"cannot read OBJ file {str(path)!r}: not a regular file")
            if st.st_size > MAX_OBJ_BYTES:
                raise MeshError(f"OBJ file {str(path)!r} is {st.st_size} bytes; at most {MAX_OBJ_BYTES} "
                                "(50 MiB) are accepted")
            data = fh.read(MAX_OBJ_BYTES + 1)  # the file may have grown since fstat
        if len(data) > MAX_OBJ_BYTES:
            raise MeshError(f"OBJ file {str(path)!r} is over {MAX_OBJ_BYTES} bytes (50 MiB); no more are accepted")
        try:
            text = data.decode("utf-8-sig")
        except UnicodeDecodeError:
            # Geometry is ASCII: a comment or a material name in Windows-1252 or Latin-1 (as Windows exporters
            # write "größe") refused the whole file. Those bytes are read as Latin-1 and never parsed; a file with
            # NUL bytes (UTF-16, or not text) is still refused.
            if b"\x00" in data:
                kind, advice = (("UTF-16 text", ": save it as UTF-8") if data[:2] in (b"\xff\xfe", b"\xfe\xff") else
                                ("a gzip archive", ": decompress it first") if data[:2] == b"\x1f\x8b" else
                                ("a PNG image", "") if data[:4] == b"\x89PNG" else ("binary data", ""))
                raise MeshError(f"cannot read OBJ file {str(path)!r}: it is not a text OBJ file (it looks like {kind}); "
                                f"jaxskip reads Wavefront OBJ as plain text, UTF-8 or Latin-1{advice}") from None
            text = data.decode("latin-1")
    except (OSError, UnicodeDecodeError) as err:
        raise MeshError(f"cannot read OBJ file {str(path)!r}: {err}") from None
    del data

    def shown(line: str) -> str:
        line = line.strip()
        return repr(line if len(line) <= 80 else line[:77] + "...")

    vertices: list[list[float]] = []
    faces: list[tuple[int, int, int]] = []
    face_lines: list[int] = []   # the line each triangle came from, for the messages of validate_mesh
    # Lines end at "\n" only (str.splitlines would also split at U+2028, form feeds, ... inside a comment); a
    # backslash ending a line (outside a comment) continues it on the next, as the OBJ format allows.
    for lineno, line in _joined_lines(text.replace("\r\n", "\n").replace("\r", "\n").split("\n")):
        if len(line) > MAX_OBJ_LINE:
            raise MeshError(f"{fname}, line {lineno}: {len(line)} characters; at most {MAX_OBJ_LINE} a line")
        tokens = line.split("#", 1)[0].split()
        try:
            if not tokens or tokens[0] in _IGNORED_OBJ_KEYWORDS:
                continue
            if tokens[0] == "v":
                vertices.append(_obj_vertex(tokens[1:]))
                if len(vertices) > MAX_OBJ_VERTICES:
                    raise ValueError(f"more than {MAX_OBJ_VERTICES} vertices")
            elif tokens[0] == "f":
                idx = _obj_face(tokens[1:], len(vertices))
                if len(faces) + len(idx) - 2 > MAX_OBJ_TRIANGLES:
                    raise ValueError(f"more than {MAX_OBJ_TRIANGLES} triangles")
                if len(idx) > 3 and len(set(idx)) == len(idx):   # (a repeated vertex: a degenerate triangle, below)
                    idx = _fan_corner(vertices, idx)
                faces.extend((idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1))
                face_lines.extend([lineno] * (len(idx) - 2))
            else:
                raise ValueError(f"unsupported statement {tokens[0][:20]!r}")
        except ValueError as err:
            raise MeshError(f"{fname}, line {lineno}: {err}: {shown(line)}") from None

    v = np.array(vertices, dtype=np.float64).reshape(-1, 3)
    f = np.array(faces, dtype=np.int64).reshape(-1, 3)
    numbers = np.arange(1, len(v) + 1)   # the file's vertex numbers (OBJ counts from 1)
    if f.size:  # vertices no face uses are not part of the surface: drop them
        used = np.unique(f)
        if used.size < len(v) and used.max() < len(v) and used.min() >= 0:
            v, f, numbers = v[used], np.searchsorted(used, f), numbers[used]
    # (messages name the file's lines and vertex numbers: "triangle 12 [0, 0, 1]" was line 21's "f 1 1 2")
    validate_mesh(v, f, name=fname, _numbering=_Numbering(np.array(face_lines, dtype=np.int64), numbers))
    return TriMesh(v, f, name if name is not None else path.stem)


def _check_mesh_type(mesh) -> None:
    """``mesh`` must be a :class:`TriMesh` (a name such as ``"paper"`` met an AttributeError inside)."""
    if not isinstance(mesh, TriMesh):
        raise MeshError(f"mesh must be a jaxskip.TriMesh (e.g. jaxskip.paper_stone(), jaxskip.read_obj(path)), "
                        f"got {type(mesh).__name__}")


def write_obj(path: str | os.PathLike, mesh: TriMesh) -> None:
    """Write a mesh as a Wavefront OBJ file (``v`` and ``f`` lines only).

    Coordinates [m] are written with ``repr`` (shortest exact decimal), so
    ``read_obj(write_obj(...))`` reproduces the vertices and faces of a valid mesh (:func:`validate_mesh`:
    every vertex used by a triangle) bit for bit; a vertex no triangle uses is written but not read back.

    Parameters
    ----------
    path : str or os.PathLike
        Destination file (overwritten), in a folder that exists.
    mesh : TriMesh
        Mesh to write; faces become 1-based indices.
    """
    if not isinstance(path, (str, os.PathLike)):   # (a bare TypeError from Path(123) before)
        if isinstance(path, TriMesh):   # (its whole repr, ~250 lines of arrays, was the message; a review)
            raise MeshError("path must be a file name (str or os.PathLike), got a TriMesh: the arguments are "
                            "write_obj(path, mesh)")
        raise MeshError(f"path must be a file name (str or os.PathLike), got {path!r:.80}")
    text = obj_text(mesh)
    try:
        check_file_path("path", path)   # (a missing folder was a raw FileNotFoundError)
    except ParameterError as exc:
        raise MeshError(str(exc)) from None   # (MeshError is a ParameterError, as read_obj raises)
    with writing(path):
        Path(path).write_text(text, encoding="utf-8")


def obj_text(mesh: TriMesh) -> str:
    """The text :func:`write_obj` writes for ``mesh``: a comment line (the mesh's name and size), ``v`` lines
    [m] and 1-based ``f`` lines."""
    _check_mesh_type(mesh)
    title = " ".join(mesh.name.split())  # keep the comment on one line
    lines = [f"# {title}: {len(mesh.vertices)} vertices, {mesh.n_triangles} triangles, metres"]
    lines += [f"v {float(x)!r} {float(y)!r} {float(z)!r}" for x, y, z in mesh.vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in mesh.faces.tolist()]
    return "\n".join(lines) + "\n"
