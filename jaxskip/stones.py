"""Built-in stone meshes and a loader for stones given by name or OBJ file.

Every built-in stone obeys one convention: the mesh frame has its origin at the
stone's centre of mass (uniform density) and the stone's thinnest axis along
z, i.e. the stone lies flat in the x-y plane.  Meshes are closed, outward
oriented and pass :func:`jaxskip.mesh.validate_mesh`.  Lengths are in metres.

All shapes are built from horizontal vertex rings stacked from top to bottom,
closed by a single vertex at the top and at the bottom (see :func:`_ring_mesh`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import numbers
import os
from pathlib import Path

import numpy as np

from ._checks import ParameterError, check_range
from .mesh import MeshError, TriMesh, mass_properties, read_obj, validate_mesh

__all__ = [
    "STONE_DENSITY",
    "ALUMINIUM_DENSITY",
    "BUILTIN_STONES",
    "paper_stone",
    "disk",
    "clanet_disk",
    "ellipsoid_pebble",
    "irregular_pebble",
    "load_stone",
]

#: Density of a typical skipping stone (quartz, granite) [kg/m^3].
STONE_DENSITY = 2650.0

#: Density of aluminium [kg/m^3] (the disks of Clanet, Hersen & Bocquet 2004).
ALUMINIUM_DENSITY = 2700.0


# ---------------------------------------------------------------------------
# helpers
# ---------------------------------------------------------------------------


#: Most triangles a built-in parametric stone may have (``disk``'s 4 ``segments``, a pebble's
#: 2 (``n_lat`` - 1) ``n_lon``): 2^17. A stone's every triangle is clipped every step, so far fewer serve any
#: throw (``notebooks/speed_vs_accuracy.py``: the disk converges by 512); 10^6 segments took 29 s to build.
MAX_TRIANGLES = 2 ** 17


#: Lengths [m] a built-in stone's size may have (radius, thickness, semi-axes): 1 µm to 100 m. Beyond them a
#: mesh's triangles underflow to zero area or overflow (a 1e-120 m paper stone was refused as "degenerate");
#: :func:`jaxskip.rigid_stone` then takes stones of 1 mm to 1 m (:data:`jaxskip.body.RADIUS_RANGE`).
SIZE_RANGE = (1e-6, 100.0)


def _size(value, name: str) -> float:
    """``value`` [m] as a float in :data:`SIZE_RANGE`, or MeshError naming ``name`` and the range."""
    try:
        return check_range(name, value, SIZE_RANGE[0], SIZE_RANGE[1], unit="m")
    except ParameterError as err:
        raise MeshError(str(err)) from None


def _count(value, name: str, minimum: int, maximum: int) -> int:
    """Return ``value`` as an int, or raise MeshError unless it is an integer in [minimum, maximum]."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not minimum <= value <= maximum:
        raise MeshError(f"{name} must be an integer in [{minimum}, {maximum}], got {value!r}")
    return int(value)


def _ring_angles(n: int, offset: float = 0.0) -> np.ndarray:
    """Equally spaced angles ``offset + 2 pi k / n``, k = 0..n-1, shape (n,) [rad]."""
    return offset + 2.0 * np.pi * np.arange(n) / n


def _strip(upper: np.ndarray, upper_angles: np.ndarray,
           lower: np.ndarray, lower_angles: np.ndarray) -> list[tuple[int, int, int]]:
    """Triangulate the band between two closed vertex rings ("zipper").

    Both rings run counter-clockwise seen from +z (increasing azimuth) and
    start at about the same azimuth; ``upper`` lies above ``lower``.  Walking
    round the band, the ring whose next edge has the smaller mid-azimuth
    advances (a rule that respects mirror symmetries of the rings), giving
    ``len(upper) + len(lower)`` triangles whose right-hand normals point away
    from the z axis.

    Parameters
    ----------
    upper, lower : ndarray of int, shapes (m,), (n,)
        Vertex indices of the rings.
    upper_angles, lower_angles : ndarray, shapes (m,), (n,)
        Increasing azimuths of the ring vertices, spanning less than 2 pi [rad].
    """
    m, n = len(upper), len(lower)
    a = np.append(upper_angles, upper_angles[0] + 2.0 * np.pi)
    b = np.append(lower_angles, lower_angles[0] + 2.0 * np.pi)
    faces = []
    i = j = 0
    while i < m or j < n:
        if i == m or (j < n and b[j] + b[j + 1] <= a[i] + a[i + 1]):
            faces.append((upper[i % m], lower[j], lower[(j + 1) % n]))
            j += 1
        else:
            faces.append((upper[i], lower[j % n], upper[(i + 1) % m]))
            i += 1
    return faces


def _ring_mesh(top, rings, bottom, name: str) -> TriMesh:
    """Closed mesh from a top vertex, horizontal rings (top to bottom) and a bottom vertex.

    Parameters
    ----------
    top, bottom : array_like, shape (3,)
        Pole vertices [m], above and below all rings.
    rings : list of (points, angles)
        ``points`` (n_k, 3) [m] ordered by increasing azimuth ``angles``
        (n_k,) [rad], n_k >= 3.

    Returns
    -------
    TriMesh
        Validated, outward oriented mesh with ``2 + sum n_k`` vertices and
        ``2 * sum n_k`` triangles, recentred so its centre of mass (uniform
        density) is the origin.
    """
    points = [np.asarray(top, float)[None]] + [np.asarray(p, float) for p, _ in rings]
    points.append(np.asarray(bottom, float)[None])
    vertices = np.concatenate(points)

    starts = np.cumsum([1] + [len(p) for p, _ in rings])
    index = [np.arange(s, s + len(p)) for s, (p, _) in zip(starts, rings)]
    angles = [np.asarray(a, float) for _, a in rings]
    first, last, bottom_index = index[0], index[-1], len(vertices) - 1

    faces = [(0, first[k], first[(k + 1) % len(first)]) for k in range(len(first))]
    for k in range(len(rings) - 1):
        faces += _strip(index[k], angles[k], index[k + 1], angles[k + 1])
    faces += [(bottom_index, last[(k + 1) % len(last)], last[k]) for k in range(len(last))]

    validate_mesh(vertices, faces, name=name)
    return _centred(TriMesh(vertices, faces, name))


def _centred(mesh: TriMesh) -> TriMesh:
    """Return ``mesh`` translated so its centre of mass (uniform density) is the origin."""
    return mesh.translated(-mass_properties(mesh, density=1.0).center_of_mass)


# ---------------------------------------------------------------------------
# built-in stones
# ---------------------------------------------------------------------------


def paper_stone(radius: float = 0.05, thickness: float = 0.012) -> TriMesh:
    """Flat rounded pebble of exactly 38 triangles, after Fig. 2 of Do, Lee & Ryu.

    A low-poly reconstruction of the stone of J.-Y. Do, N.-K. Lee & K.-W. Ryu,
    "Real-time Simulation of Stone Skipping" (Fig. 2): 21 vertices, 38
    triangles (Euler: F = 2 V - 4 for a closed genus-0 triangle mesh).
    From top to bottom: a centre vertex at ``z = +thickness/2``; a ring of 5
    vertices at radius ``0.6 * radius``; a rim of 9 vertices at ``radius``,
    ``z = 0``; a ring of 5; a centre vertex at ``z = -thickness/2``.  The ring
    heights follow the elliptical profile
    ``(rho / radius)**2 + (z / (thickness / 2))**2 = 1``, a lens with a rounded
    rim.  The mesh is mirror symmetric in y and z; it is then shifted along x
    to put its volume centroid at the origin (by about 0.2 % of ``radius``,
    since odd rings are not symmetric in x).

    Parameters
    ----------
    radius : float
        Rim radius [m], in [1e-6, 100] (:data:`SIZE_RANGE`).
    thickness : float
        Full thickness [m], in [1e-6, 100] (smaller than ``2 * radius`` for a flat stone).

    Returns
    -------
    TriMesh
        Mesh named "paper", V = 21 vertices (21, 3) [m], F = 38 faces (38, 3).
    """
    radius = _size(radius, "radius")
    half = 0.5 * _size(thickness, "thickness")
    inner = 0.6
    z_inner = half * math.sqrt(1.0 - inner**2)

    def ring(n: int, rho: float, z: float, offset: float = 0.0):
        phi = _ring_angles(n, offset)
        return np.stack([rho * np.cos(phi), rho * np.sin(phi), np.full(n, z)], axis=1), phi

    # The pentagons point to -x and the 9-gon to +x, which keeps the shape balanced.
    rings = [ring(5, inner * radius, z_inner, np.pi / 5), ring(9, radius, 0.0),
             ring(5, inner * radius, -z_inner, np.pi / 5)]
    return _ring_mesh((0.0, 0.0, half), rings, (0.0, 0.0, -half), "paper")


def disk(radius: float, thickness: float, segments: int = 32) -> TriMesh:
    """Flat cylinder (a regular prism) centred at the origin, axis along z.

    Flat faces at ``z = +-thickness/2``, each a fan around a centre vertex;
    rim polygon with ``segments`` vertices on the circle of ``radius``.
    Volume ``V = (n/2) R^2 sin(2 pi/n) t`` (n = segments), which tends to
    ``pi R^2 t``.

    Parameters
    ----------
    radius : float
        Circumradius of the rim polygon [m], in [1e-6, 100].
    thickness : float
        Height of the cylinder [m], in [1e-6, 100].
    segments : int
        Number of rim vertices, in [3, 32768] (4 n triangles, at most :data:`MAX_TRIANGLES`).

    Returns
    -------
    TriMesh
        Mesh named "disk" with 2 n + 2 vertices and 4 n triangles.
    """
    radius = _size(radius, "radius")
    half = 0.5 * _size(thickness, "thickness")
    n = _count(segments, "segments", 3, MAX_TRIANGLES // 4)
    phi = _ring_angles(n)
    rim = np.stack([radius * np.cos(phi), radius * np.sin(phi), np.zeros(n)], axis=1)
    rings = [(rim + (0.0, 0.0, half), phi), (rim - (0.0, 0.0, half), phi)]
    return _ring_mesh((0.0, 0.0, half), rings, (0.0, 0.0, -half), "disk")


def clanet_disk(segments: int = 32) -> TriMesh:
    """Aluminium disk of Clanet, Hersen & Bocquet, Nature 427:29 (2004).

    Radius 0.025 m (5 cm diameter), thickness 0.00275 m; use
    ``ALUMINIUM_DENSITY``.  See :func:`disk` for ``segments`` and the result, named ``"clanet"`` (as
    messages name it: a warning about the Clanet disk named "disk").
    """
    return dataclasses.replace(disk(0.025, 0.00275, segments), name="clanet")


def ellipsoid_pebble(semi_axes=(0.03, 0.025, 0.008), n_lat: int = 8, n_lon: int = 16) -> TriMesh:
    """Flattened ellipsoid ``(x/a)^2 + (y/b)^2 + (z/c)^2 = 1`` as a UV sphere.

    Parameters
    ----------
    semi_axes : sequence of 3 floats
        Semi-axes ``(a, b, c)`` [m], each in [1e-6, 100]; ``c`` the smallest for a flat stone.
    n_lat : int
        Number of latitude bands, >= 2 (``n_lat - 1`` rings between the poles).
    n_lon : int
        Vertices per ring, >= 3; the ``2 (n_lat - 1) n_lon`` triangles at most :data:`MAX_TRIANGLES` (131072).

    Returns
    -------
    TriMesh
        Mesh named "ellipsoid", ``2 + (n_lat - 1) n_lon`` vertices,
        ``2 (n_lat - 1) n_lon`` triangles, centred on its centre of mass.
    """
    return _uv_pebble(semi_axes, n_lat, n_lon, lambda theta, phi: np.zeros_like(theta), "ellipsoid")


def irregular_pebble(seed: int = 0, radius: float = 0.04, thickness: float = 0.012,
                     n_lat: int = 8, n_lon: int = 16, roughness: float = 0.15) -> TriMesh:
    """Random, deterministic, star-shaped pebble: a perturbed flattened ellipsoid.

    The ellipsoid with semi-axes ``(radius, radius, thickness/2)`` is scaled
    radially by ``1 + roughness * f(theta, phi)``, with polar angle theta and
    azimuth phi, and the smooth random field

    ``f = [sum_{m=1}^{3} sin^m(theta) (a_m cos(m phi) + b_m sin(m phi))
    + sum_{k=1}^{2} c_k cos(k theta)] / (sum |a_m| + |b_m| + |c_k|)``,

    so ``|f| <= 1``.  The terms are smooth on the whole sphere (they are
    polynomials in the unit direction vector), the coefficients come from
    ``numpy.random.default_rng(seed)``, and ``roughness < 1`` keeps the radial
    factor positive, so the surface stays star-shaped, closed and outward.
    The mesh is recentred on its centre of mass.

    Parameters
    ----------
    seed : int
        Random seed, an integer >= 0; the same seed always gives the same pebble.
    radius : float
        Unperturbed equatorial semi-axis [m], in [1e-6, 100].
    thickness : float
        Unperturbed full thickness [m], in [1e-6, 100].
    n_lat, n_lon : int
        Latitude bands (>= 2) and vertices per ring (>= 3), as in
        :func:`ellipsoid_pebble` (at most :data:`MAX_TRIANGLES` triangles).
    roughness : float
        Relative amplitude of the perturbation, in [0, 1).

    Returns
    -------
    TriMesh
        Mesh named "pebble".
    """
    try:   # (a NumPy integer was refused as "must lie in [0, 1), got np.int64(0)")
        roughness = check_range("roughness", roughness, 0.0, 1.0, high_open=True)
    except ParameterError as err:
        raise MeshError(str(err)) from None
    if isinstance(seed, (bool, np.bool_)) or not isinstance(seed, numbers.Integral) or seed < 0:
        raise MeshError(f"seed must be an integer >= 0, got {seed!r}")
    radius = _size(radius, "radius")
    half = 0.5 * _size(thickness, "thickness")
    rng = np.random.default_rng(int(seed))
    ab = rng.normal(size=(3, 2))
    ck = rng.normal(size=2)
    norm = np.abs(ab).sum() + np.abs(ck).sum()

    def field(theta, phi):
        f = sum(np.sin(theta) ** m * (a * np.cos(m * phi) + b * np.sin(m * phi))
                for m, (a, b) in enumerate(ab, start=1))
        f = f + sum(c * np.cos(k * theta) for k, c in enumerate(ck, start=1))
        return roughness * f / norm

    return _uv_pebble((radius, radius, half), n_lat, n_lon, field, "pebble")


def _uv_pebble(semi_axes, n_lat, n_lon, perturbation, name: str) -> TriMesh:
    """UV-sphere ellipsoid scaled radially by ``1 + perturbation(theta, phi)``.

    ``theta`` is the polar angle from +z, ``phi`` the azimuth [rad]; the
    perturbation takes and returns arrays of equal shape and must be > -1.
    """
    try:
        axes = tuple(semi_axes)
    except TypeError:
        axes = ()
    if len(axes) != 3:
        raise MeshError(f"semi_axes must be 3 positive lengths [m], got {semi_axes!r}")
    axes = np.array([_size(x, f"semi_axes[{i}]") for i, x in enumerate(axes)])
    n_lat = _count(n_lat, "n_lat", 2, MAX_TRIANGLES // 6 + 1)
    n_lon = _count(n_lon, "n_lon", 3, MAX_TRIANGLES // 2)
    if 2 * (n_lat - 1) * n_lon > MAX_TRIANGLES:
        raise MeshError(f"n_lat = {n_lat} and n_lon = {n_lon} make 2 (n_lat - 1) n_lon = {2 * (n_lat - 1) * n_lon} "
                        f"triangles; at most {MAX_TRIANGLES} (MAX_TRIANGLES)")

    def surface(theta, phi):
        theta, phi = np.broadcast_arrays(np.asarray(theta, float), np.asarray(phi, float))
        direction = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi),
                              np.cos(theta)], axis=-1)
        return direction * axes * (1.0 + perturbation(theta, phi))[..., None]

    phi = _ring_angles(n_lon)
    rings = [(surface(np.pi * k / n_lat, phi), phi) for k in range(1, n_lat)]
    return _ring_mesh(surface(0.0, 0.0), rings, surface(np.pi, 0.0), name)


# ---------------------------------------------------------------------------
# registry and loader
# ---------------------------------------------------------------------------

#: Built-in stones: name -> (zero-argument mesh factory, default density [kg/m^3]). Sizes are the factories'
#: defaults; the masses [kg], rounded, are at the default density (from the meshes' exact volumes):
#:
#: * ``"paper"``: :func:`paper_stone`, rim radius 0.05 m, thickness 0.012 m, 38 triangles; 2650 kg/m^3, ~0.121 kg.
#: * ``"disk"``: :func:`disk` of radius 0.04 m and thickness 0.008 m (32 segments); 2650 kg/m^3, ~0.106 kg.
#: * ``"clanet"``: :func:`clanet_disk`, radius 0.025 m, thickness 0.00275 m; aluminium, 2700 kg/m^3, ~0.0145 kg.
#: * ``"ellipsoid"``: :func:`ellipsoid_pebble`, semi-axes (0.03, 0.025, 0.008) m; 2650 kg/m^3, ~0.0624 kg.
#: * ``"pebble"``: :func:`irregular_pebble` (seed 0), radius 0.04 m, thickness 0.012 m before its
#:   roughness (radii scaled by up to ±15 %); 2650 kg/m^3, ~0.097 kg.
BUILTIN_STONES = {
    "paper": (paper_stone, STONE_DENSITY),
    "disk": (functools.partial(disk, 0.04, 0.008), STONE_DENSITY),
    "clanet": (clanet_disk, ALUMINIUM_DENSITY),
    "ellipsoid": (ellipsoid_pebble, STONE_DENSITY),
    "pebble": (irregular_pebble, STONE_DENSITY),
}


def source_mesh(name_or_path: str | os.PathLike) -> TriMesh:
    """The mesh a stone is made from in its own frame: a built-in's (as :func:`load_stone` gives it), or an
    ``.obj`` file's as written, not moved to its centre of mass. Give it to :func:`jaxskip.export.mesh_frame` and
    :func:`jaxskip.export.write_trajectory` to drive your own file's mesh (its frame, vertex order and UVs).
    Raises :class:`MeshError` as :func:`load_stone` does."""
    mesh, _ = load_stone(name_or_path)
    if isinstance(name_or_path, str) and name_or_path in BUILTIN_STONES:
        return mesh
    return read_obj(Path(name_or_path))


def load_stone(name_or_path: str | os.PathLike) -> tuple[TriMesh, float]:
    """Return a stone mesh and its default density.

    Parameters
    ----------
    name_or_path : str or os.PathLike
        A key of ``BUILTIN_STONES`` ("paper", "disk", "clanet", "ellipsoid",
        "pebble"), or the path of an ``.obj`` file (coordinates in metres).

    Returns
    -------
    mesh : TriMesh
        The stone with its centre of mass at the origin (a file's mesh moved
        there; :func:`source_mesh` keeps the file's own frame).  Its orientation
        does not matter: :func:`jaxskip.rigid_stone` turns every stone to its
        principal axes, the axis of largest inertia (a flat stone's thin axis)
        along z and that of smallest inertia (an elongated stone's long axis)
        along x, the throw's heading, whichever way the file had it.
    density : float
        Default density [kg/m^3]: the built-in's own, or ``STONE_DENSITY`` for
        a file.

    Raises
    ------
    MeshError
        For an unknown name, a missing file or an invalid mesh file.
    """
    if not isinstance(name_or_path, (str, os.PathLike)):
        raise MeshError(f"stone must be a built-in name ({', '.join(sorted(BUILTIN_STONES))}) or the path of an "
                        f".obj file, got {name_or_path!r}")
    if isinstance(name_or_path, str) and name_or_path in BUILTIN_STONES:
        factory, density = BUILTIN_STONES[name_or_path]
        return factory(), density
    path = Path(name_or_path)
    if path.suffix.lower() != ".obj":
        if path.is_file():   # (it was "unknown", as if the file were not there)
            raise MeshError(f"stone file {str(name_or_path)!r} exists but is not an .obj file: jaxskip reads "
                            "Wavefront OBJ meshes only, named *.obj (rename it if it is one)")
        raise MeshError(f"stone {str(name_or_path)!r} is unknown; valid names are "
                        f"{', '.join(sorted(BUILTIN_STONES))}, or give a path to an .obj file")
    if not path.is_file():
        raise MeshError(f"stone file {str(path)!r} " + ("is not a regular file" if path.exists() else "does not exist"))
    return _centred(read_obj(path)), STONE_DENSITY
