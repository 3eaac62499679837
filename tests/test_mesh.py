"""Tests for jaxskip.mesh and jaxskip.stones (numpy only, fast)."""

import math
import os
import re

import numpy as np
import pytest

from jaxskip.mesh import (
    MeshError,
    TriMesh,
    mass_properties,
    read_obj,
    validate_mesh,
    write_obj,
)
from jaxskip.stones import (
    ALUMINIUM_DENSITY,
    BUILTIN_STONES,
    STONE_DENSITY,
    clanet_disk,
    disk,
    ellipsoid_pebble,
    irregular_pebble,
    load_stone,
    paper_stone,
)


def box(a, b, c):
    """Axis-aligned box of sides a, b, c [m] centred at the origin: 8 vertices, 12 triangles."""
    # vertex k = 4 x + 2 y + z with x, y, z in {0, 1}
    bits = np.array([[k >> 2 & 1, k >> 1 & 1, k & 1] for k in range(8)], dtype=float)
    vertices = (bits - 0.5) * [a, b, c]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    faces = [f for p, q, r, s in quads for f in ((p, q, r), (p, r, s))]
    return TriMesh(vertices, faces, "box")


def rotation(axis, angle):
    """Rotation matrix about ``axis`` by ``angle`` [rad] (Rodrigues' formula)."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * kx + (1 - math.cos(angle)) * kx @ kx


def assert_rel(actual, expected, rtol=1e-9):
    """Compare with a tolerance relative to the largest entry of ``expected``."""
    expected = np.asarray(expected, float)
    np.testing.assert_allclose(actual, expected, rtol=0, atol=rtol * np.abs(expected).max())


# ---------------------------------------------------------------------------
# mass properties
# ---------------------------------------------------------------------------

A, B, C, RHO = 0.07, 0.05, 0.011, 2650.0
BOX_MASS = RHO * A * B * C
BOX_INERTIA = BOX_MASS / 12 * np.diag([B**2 + C**2, A**2 + C**2, A**2 + B**2])


def test_box_mass_properties():
    mesh = box(A, B, C)
    validate_mesh(mesh.vertices, mesh.faces)
    assert mesh.n_triangles == 12
    props = mass_properties(mesh, density=RHO)
    assert props.volume == pytest.approx(A * B * C, rel=1e-12)
    assert props.mass == pytest.approx(BOX_MASS, rel=1e-12)
    np.testing.assert_allclose(props.center_of_mass, 0.0, atol=1e-15)
    assert_rel(props.inertia, BOX_INERTIA)
    assert mesh.areas.sum() == pytest.approx(2 * (A * B + B * C + A * C), rel=1e-12)
    np.testing.assert_allclose(np.linalg.norm(mesh.normals, axis=1), 1.0, rtol=1e-12)


def test_box_translated_and_rotated():
    rot = rotation([1.0, -2.0, 0.5], 0.7)
    offset = np.array([3.0, -1.5, 20.0])
    mesh = box(A, B, C).rotated(rot).translated(offset)
    validate_mesh(mesh.vertices, mesh.faces)
    props = mass_properties(mesh, density=RHO)
    assert props.volume == pytest.approx(A * B * C, rel=1e-9)
    np.testing.assert_allclose(props.center_of_mass, offset, rtol=0, atol=1e-9 * A)
    assert_rel(props.inertia, rot @ BOX_INERTIA @ rot.T)


@pytest.mark.parametrize("n", [3, 7, 256])
def test_disk_matches_polygonal_prism_and_cylinder(n):
    radius, thickness, rho = 0.04, 0.008, 2700.0
    props = mass_properties(disk(radius, thickness, n), density=rho)
    alpha = 2 * np.pi / n
    area = 0.5 * n * radius**2 * np.sin(alpha)
    polar = n * radius**4 * np.sin(alpha) * (2 + np.cos(alpha)) / 12  # int (x^2 + y^2) dA
    mass = rho * area * thickness
    izz = rho * thickness * polar
    ixx = 0.5 * izz + mass * thickness**2 / 12
    assert props.volume == pytest.approx(area * thickness, rel=1e-9)
    assert_rel(props.inertia, np.diag([ixx, ixx, izz]))
    np.testing.assert_allclose(props.center_of_mass, 0.0, atol=1e-15)
    if n >= 256:  # cylinder limit: relative error ~ alpha^2 / 6
        cyl_mass = rho * np.pi * radius**2 * thickness
        tol = alpha**2
        assert props.mass == pytest.approx(cyl_mass, rel=tol)
        assert float(props.inertia[2, 2]) == pytest.approx(cyl_mass * radius**2 / 2, rel=tol)
        assert float(props.inertia[0, 0]) == pytest.approx(cyl_mass * (3 * radius**2 + thickness**2) / 12, rel=tol)


def test_mass_and_density_agree():
    mesh = clanet_disk()
    by_density = mass_properties(mesh, density=ALUMINIUM_DENSITY)
    by_mass = mass_properties(mesh, mass=by_density.mass)
    assert by_mass.mass == pytest.approx(by_density.mass, rel=1e-14)
    np.testing.assert_allclose(by_mass.inertia, by_density.inertia, rtol=1e-12, atol=0)


@pytest.mark.parametrize("kwargs", [{}, {"density": 1.0, "mass": 1.0}, {"density": -1.0},
                                    {"mass": 0.0}, {"density": float("nan")}])
def test_mass_properties_argument_errors(kwargs):
    with pytest.raises(MeshError, match="density|mass"):
        mass_properties(box(1, 1, 1), **kwargs)


# ---------------------------------------------------------------------------
# built-in stones
# ---------------------------------------------------------------------------


def test_paper_stone_has_38_triangles():
    mesh = paper_stone()
    assert mesh.name == "paper"
    assert mesh.n_triangles == 38 and len(mesh.vertices) == 21
    validate_mesh(mesh.vertices, mesh.faces)
    assert np.ptp(mesh.vertices[:, 2]) == pytest.approx(0.012, rel=1e-12)


@pytest.mark.parametrize("name", sorted(BUILTIN_STONES))
def test_builtin_stones(name):
    mesh, density = load_stone(name)
    assert density == (ALUMINIUM_DENSITY if name == "clanet" else STONE_DENSITY)
    assert mesh.name == name   # (messages name the mesh: the Clanet disk's said "disk")
    validate_mesh(mesh.vertices, mesh.faces, name=name)
    props = mass_properties(mesh, density=density)
    assert props.volume > 0
    np.testing.assert_allclose(props.center_of_mass, 0.0, atol=1e-12)
    extent = np.ptp(mesh.vertices, axis=0)
    assert np.argmin(extent) == 2
    assert np.argmax(np.diag(props.inertia)) == 2  # thin axis = largest moment


def test_irregular_pebble_is_deterministic_per_seed():
    a, b, c = irregular_pebble(seed=3), irregular_pebble(seed=3), irregular_pebble(seed=4)
    np.testing.assert_array_equal(a.vertices, b.vertices)
    assert not np.allclose(a.vertices, c.vertices)
    # a NumPy integer roughness is a number like any other (refused as "must lie in [0, 1), got np.int64(0)")
    np.testing.assert_array_equal(irregular_pebble(seed=3, roughness=np.int64(0)).vertices,
                                  irregular_pebble(seed=3, roughness=0.0).vertices)


@pytest.mark.parametrize("call", [lambda: disk(0.04, 0.008, segments=2),
                                  lambda: disk(-0.04, 0.008),
                                  lambda: paper_stone(thickness=float("inf")),
                                  lambda: irregular_pebble(roughness=1.0)])
def test_stone_parameter_errors(call):
    with pytest.raises(MeshError, match="segments|radius|thickness|roughness"):
        call()


# ---------------------------------------------------------------------------
# validation
# ---------------------------------------------------------------------------


def broken_box(kind):
    mesh = box(1.0, 2.0, 3.0)
    v, f = mesh.vertices.copy(), mesh.faces.copy()
    if kind == "open":
        f = f[1:]
    elif kind == "flipped":
        f[0] = f[0, ::-1]
    elif kind == "inside-out":
        f = f[:, ::-1]
    elif kind == "degenerate":
        v[1] = v[0]
    elif kind == "repeated":
        f[0, 1] = f[0, 0]
    elif kind == "range":
        f[3, 2] = 8
    elif kind == "nan":
        v[5, 1] = np.nan
    return v, f


@pytest.mark.parametrize("kind, message", [
    ("open", "not closed"),
    ("flipped", "orientation"),
    ("inside-out", "inward"),
    ("degenerate", "degenerate"),
    ("repeated", "repeats a vertex"),
    ("range", "out of range"),
    ("nan", "not finite"),
])
def test_validate_mesh_errors(kind, message):
    v, f = broken_box(kind)
    with pytest.raises(MeshError, match=message):
        validate_mesh(v, f, name="box")


def test_a_closed_sheet_is_said_to_enclose_no_volume_not_to_face_inwards():
    """(2026-12-07, a review) A closed two-sided square (zero thickness) was told its faces point inward and to
    reverse them, which changes nothing; a box is still told so when it is inside out."""
    v = np.array([[0.0, 0.0, 0.0], [0.05, 0.0, 0.0], [0.05, 0.05, 0.0], [0.0, 0.05, 0.0]])
    f = np.array([[0, 1, 2], [0, 2, 3], [1, 0, 3], [1, 3, 2]])   # front and back, each its own diagonal
    for faces in (f, f[:, ::-1]):
        with pytest.raises(MeshError, match="encloses no volume") as err:
            validate_mesh(v, faces, name="sheet")
        assert "inward" not in str(err.value)
    with pytest.raises(MeshError, match="inward"):
        validate_mesh(*broken_box("inside-out"), name="box")


def test_validate_mesh_shape_errors():
    with pytest.raises(MeshError, match=r"shape \(V, 3\)"):
        validate_mesh(np.zeros((4, 2)), np.zeros((4, 3), int))
    with pytest.raises(MeshError, match="integer"):
        validate_mesh(np.zeros((4, 3)), np.zeros((4, 3)))


def test_trimesh_refuses_face_indices_outside_its_vertices():
    """A 1-based or negative face index is refused by the constructor, with the face and the valid
    range, before mass_properties (an IndexError, or with -1 a silently wrong mass: 0.1161 kg for the
    paper stone's 0.1207) or write_obj (an OBJ that read_obj then refuses) see it."""
    stone = paper_stone()
    with pytest.raises(MeshError, match=r"paper: face 33 has vertex index 21, outside \[0, 20\].*1-based"):
        TriMesh(stone.vertices, stone.faces + 1, name="paper")
    faces = stone.faces.copy()
    faces[2, 1] = -1
    with pytest.raises(MeshError, match=r"face 2 has vertex index -1, outside \[0, 20\]"):
        TriMesh(stone.vertices, faces)
    TriMesh(stone.vertices, stone.faces)  # the valid mesh still builds


def test_trimesh_is_read_only_and_rejects_reflections():
    mesh = box(1, 1, 1)
    with pytest.raises(ValueError):
        mesh.vertices[0, 0] = 5.0
    with pytest.raises(MeshError, match="rotation"):
        mesh.rotated(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(MeshError, match="factor"):
        mesh.scaled(-2.0)


# ---------------------------------------------------------------------------
# OBJ files
# ---------------------------------------------------------------------------


def test_obj_round_trip_is_exact(tmp_path):
    mesh = irregular_pebble(seed=7).rotated(rotation([1, 1, 0], 0.3))
    path = tmp_path / "stone.obj"
    write_obj(path, mesh)
    back = read_obj(path)
    assert back.name == "stone"
    np.testing.assert_array_equal(back.vertices, mesh.vertices)
    np.testing.assert_array_equal(back.faces, mesh.faces)


TETRA_OBJ = """\
# a unit tetrahedron, written in several face styles
mtllib stone.mtl
o tetra
v 0 0 0
v 1 0 0 1.0
v 0 1 0
v 0 0 1
vt 0 0
vn 0 0 1
g group
s off
usemtl rock

f 1/1/1 3/1/1 2/1/1
f 1//1 2//1 4//1
f -4 -1 -2   # negative indices count back from the last vertex
f 2/1 3/1 4/1
"""


def test_read_obj_face_styles(tmp_path):
    path = tmp_path / "tetra.obj"
    path.write_text(TETRA_OBJ)
    mesh = read_obj(path, name="t")
    assert mesh.name == "t"
    np.testing.assert_array_equal(mesh.faces, [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    assert mass_properties(mesh, density=1.0).volume == pytest.approx(1 / 6, rel=1e-15)


def test_read_obj_triangulates_quads(tmp_path):
    mesh = box(1.0, 2.0, 3.0)
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in mesh.vertices.tolist()]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    lines += ["f " + " ".join(str(k + 1) for k in q) for q in quads]
    path = tmp_path / "box.obj"
    path.write_text("\n".join(lines))
    back = read_obj(path)
    assert back.n_triangles == 12
    np.testing.assert_array_equal(back.faces, mesh.faces)


def _l_prism_obj(start: int) -> str:
    """An L-shaped prism (4 x 4 x 0.6 cm) with its two 6-sided faces listed from corner ``start``."""
    corners = np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]], float) * 0.02
    lines = [f"v {x!r} {y!r} 0.006" for x, y in corners.tolist()] + [f"v {x!r} {y!r} 0.0" for x, y in corners.tolist()]
    lines.append("f " + " ".join(str((start + k) % 6 + 1) for k in range(6)))
    lines.append("f " + " ".join(str((start - k) % 6 + 7) for k in range(6)))
    lines += [f"f {i + 1} {i + 7} {(i + 1) % 6 + 7} {(i + 1) % 6 + 1}" for i in range(6)]
    return "\n".join(lines) + "\n"


def test_read_obj_refuses_a_polygon_that_fans_into_folded_triangles(tmp_path):
    """(session 33) An L-shaped face listed from a corner that does not see every edge fanned into
    overlapping triangles, one facing into the stone; the mesh stayed closed with the right volume, so it
    passed validation, and the stone loaded a third more bottom area than it has (4 bounces instead of 10).
    Listed from its reflex corner the same face fans correctly and is read."""
    good = tmp_path / "good.obj"
    good.write_text(_l_prism_obj(3))
    mesh = read_obj(good)
    up = mesh.normals[:, 2] > 0.5
    assert mesh.areas[up].sum() == pytest.approx(3 * 0.02 ** 2, rel=1e-12)    # the L's area, 3 unit squares
    assert mass_properties(mesh, density=1.0).volume == pytest.approx(3 * 0.02 ** 2 * 0.006, rel=1e-12)
    # (2026-12-07) listed from another corner, the face is fanned from the first corner that sees every edge
    other = tmp_path / "other.obj"
    other.write_text(_l_prism_obj(1))
    again = read_obj(other)
    assert again.areas[again.normals[:, 2] > 0.5].sum() == pytest.approx(3 * 0.02 ** 2, rel=1e-12)
    assert mass_properties(again, density=1.0).volume == pytest.approx(3 * 0.02 ** 2 * 0.006, rel=1e-12)
    # a U-shaped face: no corner sees every edge, so no fan triangulates it
    u = np.array([[0, 0], [3, 0], [3, 2], [2, 2], [2, 1], [1, 1], [1, 2], [0, 2]], float) * 0.01
    lines = [f"v {x!r} {y!r} 0.006" for x, y in u.tolist()] + [f"v {x!r} {y!r} 0.0" for x, y in u.tolist()]
    lines.append("f " + " ".join(str(k + 1) for k in range(8)))
    lines.append("f " + " ".join(str((-k) % 8 + 9) for k in range(8)))
    lines += [f"f {i + 1} {i + 9} {(i + 1) % 8 + 9} {(i + 1) % 8 + 1}" for i in range(8)]
    bad = tmp_path / "bad.obj"
    bad.write_text("\n".join(lines) + "\n")
    with pytest.raises(MeshError, match=r"bad.obj, line 17: the 8-sided face is not convex \(no corner sees every edge\)"):
        read_obj(bad)


def test_read_obj_fans_a_convex_face_from_a_corner_off_its_straight_edges(tmp_path):
    """(2026-12-07, a review) a convex pentagon listed from a corner next to a midpoint of one of its edges,
    f 5 9 6 7 8 (9 halfway between 5 and 6, as a modeller leaves a split edge), was refused as 'not convex': its
    first fan triangle (5, 9, 6) has no area. It is fanned from its next corner now: the box has its volume."""
    a, b, c = 0.04, 0.03, 0.01
    v = [(0, 0, 0), (a, 0, 0), (a, b, 0), (0, b, 0), (0, 0, c), (a, 0, c), (a, b, c), (0, b, c), (a / 2, 0, c)]
    faces = ["1 4 3 2", "5 9 6 7 8", "1 2 6 9 5", "3 4 8 7", "1 5 8 4", "2 3 7 6"]
    path = tmp_path / "split.obj"
    path.write_text("\n".join([f"v {x!r} {y!r} {z!r}" for x, y, z in v] + [f"f {f}" for f in faces]) + "\n")
    back = read_obj(path)
    assert mass_properties(back, density=1.0).volume == pytest.approx(a * b * c, rel=1e-12)
    assert back.areas.min() > 0.0 and back.n_triangles == 2 + 3 + 3 + 2 + 2 + 2


def test_read_obj_takes_vertex_colours(tmp_path):
    """(session 32) ``v x y z r g b``, as MeshLab and photogrammetry tools write a scanned object, was
    refused ("a vertex needs 3 coordinates"): the colour is ignored, the mesh is the same."""
    mesh = box(0.05, 0.04, 0.01)
    lines = [f"v {x!r} {y!r} {z!r} 0.5 0.25 1" for x, y, z in mesh.vertices.tolist()]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in mesh.faces.tolist()]
    path = tmp_path / "scan.obj"
    path.write_text("\n".join(lines))
    back = read_obj(path)
    np.testing.assert_array_equal(back.vertices, mesh.vertices)
    np.testing.assert_array_equal(back.faces, mesh.faces)


@pytest.mark.parametrize("bad_line", ["v 1 2", "v 1 2 x", "v 1 2 3 4 5", "v 1 2 3 0.5 x 1", "f 1 2", "f 1 2 9", "f 0 1 2",
                                      "f a/1 2 3", "l 1 2", "import os",
                                      # (session 33: each read as a plain number before)
                                      "f 1/x/1 2 3", "f 1/2/3/4 2 3", "f 1/ 2 3", "f 1// 2 3", "v 0.0_1 0 0",
                                      "v \uff10 0 0", "v 0 \u0661 0"])
def test_read_obj_malformed_lines(tmp_path, bad_line):
    lines = TETRA_OBJ.splitlines()
    lines.insert(5, bad_line)  # becomes line 6
    path = tmp_path / "bad.obj"
    path.write_text("\n".join(lines))
    with pytest.raises(MeshError, match="bad.obj, line 6"):
        read_obj(path)


def test_read_obj_invalid_mesh(tmp_path):
    path = tmp_path / "flipped.obj"
    path.write_text(TETRA_OBJ.replace("f 2/1 3/1 4/1", "f 2 4 3"))
    with pytest.raises(MeshError, match="flipped.obj.*orientation"):
        read_obj(path)


def test_read_obj_names_triangles_by_line_and_vertices_by_obj_number(tmp_path):
    """A file's faults point at the OBJ line of the triangle and at 1-based OBJ vertex numbers, not at
    0-based indices of the triangulated arrays (which a user cannot find in the file)."""
    cases = [
        ("f 2 2 3", r"the triangle of line 17 repeats a vertex index \[2, 2, 3\]"),
        ("f 2 4 3", r"edge \(2, 4\) of the triangles of lines \[15, 17\] runs in the same direction"),
        ("f 2 3 4\nf 2 3 4", r"edge \(2, 3\) of the triangles of lines \[14, 17, 18\] is shared by more"),
    ]
    for last, message in cases:
        path = tmp_path / "bad.obj"
        path.write_text(TETRA_OBJ.replace("f 2/1 3/1 4/1", last))
        with pytest.raises(MeshError, match=message):
            read_obj(path)
    # the arrays themselves are still named by 0-based index
    good = tmp_path / "good.obj"
    good.write_text(TETRA_OBJ)
    mesh = read_obj(good)
    faces = mesh.faces.copy()
    faces[3] = [1, 1, 2]
    with pytest.raises(MeshError, match=r"triangle 3 repeats a vertex index \[1, 1, 2\]"):
        validate_mesh(mesh.vertices, faces)


def test_load_stone_errors_and_obj(tmp_path):
    with pytest.raises(MeshError, match="clanet.*ellipsoid.*paper.*pebble.*obj"):
        load_stone("granite")
    with pytest.raises(MeshError, match="missing.obj"):
        load_stone(tmp_path / "missing.obj")
    path = tmp_path / "rock.obj"
    write_obj(path, box(0.04, 0.03, 0.01).translated([1.0, 2.0, 3.0]))
    mesh, density = load_stone(str(path))
    assert density == STONE_DENSITY
    np.testing.assert_allclose(mass_properties(mesh, density=1.0).center_of_mass, 0, atol=1e-15)


# ---------------------------------------------------------------------------
# session 23: a review of meshes, OBJ files and bad input
# ---------------------------------------------------------------------------


@pytest.mark.parametrize("second", ["inside-out", "outward", "nested"])
def test_a_mesh_of_several_parts_is_refused(second):
    """A second closed part could face inwards (the total volume stayed positive, the inertia had
    negative moments and the stone simulated), or sit nested inside the first (its volume counted
    twice): a stone is one closed surface."""
    stone = box(0.07, 0.05, 0.011)
    extra = box(0.01, 0.01, 0.004)
    if second == "nested":
        pass  # inside the first box, outward: the volume would count twice
    else:
        extra = extra.translated([0.2, 0.0, 0.0])
    faces = extra.faces[:, ::-1] if second == "inside-out" else extra.faces
    v = np.vstack([stone.vertices, extra.vertices])
    f = np.vstack([stone.faces, faces + len(stone.vertices)])
    with pytest.raises(MeshError, match="2 separate closed parts.*one closed surface"):
        validate_mesh(v, f, name="two")
    if second == "inside-out":  # its total volume is positive, but an inertia moment is not
        with pytest.raises(MeshError, match="principal moments .* run validate_mesh"):
            mass_properties(TriMesh(v, f), density=1.0)


def test_vertices_no_triangle_uses_are_refused_and_dropped_from_obj_files(tmp_path):
    """A stray vertex entered the degenerate-triangle threshold and the stone's size (a 5 cm stone
    with one at 0.5 m got a 0.48 m radius): ``validate_mesh`` refuses it, ``read_obj`` drops it."""
    b = box(0.04, 0.03, 0.01)
    with pytest.raises(MeshError, match="1 of its 9 vertices .* belong to no triangle"):
        validate_mesh(np.vstack([b.vertices, [[0.5, 0.0, 0.0]]]), b.faces)
    path = tmp_path / "stray.obj"
    write_obj(path, TriMesh(np.vstack([[[0.5, 0.0, 0.0]], b.vertices]), b.faces + 1, "stray"))
    read = read_obj(path)
    np.testing.assert_array_equal(read.vertices, b.vertices)
    np.testing.assert_array_equal(read.faces, b.faces)


def test_obj_lines_end_at_newlines_only_and_messages_stay_short(tmp_path):
    b = box(0.04, 0.03, 0.01)
    path = tmp_path / "b.obj"
    write_obj(path, b)
    text = path.read_text()
    path.write_text("# a comment\u2028f 1 2 3 with a line separator\n" + text)
    assert read_obj(path).n_triangles == 12  # the separator does not start a statement
    path.write_text(text + "v 0 0 " + "x" * 100000 + "\n")
    with pytest.raises(MeshError) as err:
        read_obj(path)
    assert "line 22" in str(err.value) and len(str(err.value)) < 300


def test_read_obj_refuses_what_is_not_a_regular_file_and_oversized_meshes(tmp_path, monkeypatch):
    import jaxskip.mesh as mesh_module

    with pytest.raises(MeshError, match="not a regular file"):
        read_obj("/dev/zero")  # read without end before
    if hasattr(os, "mkfifo"):   # a named pipe: opening it waited for a writer, without end (2026-12-06)
        os.mkfifo(tmp_path / "pipe.obj")
        with pytest.raises(MeshError, match="not a regular file"):
            read_obj(tmp_path / "pipe.obj")
    with pytest.raises(MeshError, match="file name"):
        read_obj(None)
    path = tmp_path / "b.obj"
    write_obj(path, box(0.04, 0.03, 0.01))
    monkeypatch.setattr(mesh_module, "MAX_OBJ_TRIANGLES", 11)
    with pytest.raises(MeshError, match="more than 11 triangles"):
        read_obj(path)
    monkeypatch.setattr(mesh_module, "MAX_OBJ_VERTICES", 7)
    with pytest.raises(MeshError, match="line 9: more than 7 vertices"):
        read_obj(path)


@pytest.mark.parametrize("call, message", [
    (lambda: paper_stone(radius="0.05"), r"radius must be a real number in \[1e-06, 100\] m, got '0.05'"),
    (lambda: disk(True, True), r"radius must be a real number in \[1e-06, 100\] m, got True"),
    (lambda: paper_stone(radius=10**400), "radius must be finite .* beyond the floating-point range"),
    # (2026-12-06) sizes beyond floating point's reach were "degenerate" triangles, advice no one could act on
    (lambda: paper_stone(1e-120, 1e-120), r"radius must be in \[1e-06, 100\] m, got 1e-120"),
    (lambda: disk(1.0, 1e-14), r"thickness must be in \[1e-06, 100\] m, got 1e-14"),
    (lambda: ellipsoid_pebble((1e-160,) * 3), r"semi_axes\[0\] must be in \[1e-06, 100\] m"),
    (lambda: paper_stone(1e200, 1e200), r"radius must be in \[1e-06, 100\] m, got 1e\+200"),
    (lambda: mass_properties(box(0.04, 0.03, 0.01), mass=1e308), "must be finite and > 0"),
    (lambda: mass_properties(box(0.04, 0.03, 0.01), density=1e-320), "must be finite and > 0"),
    (lambda: box(0.04, 0.03, 0.01).translated("abc"), "offset must be real numbers"),
    (lambda: TriMesh(np.zeros((4, 3)), [[0, 1, 2], [1, 2]]), "faces must be an array of shape"),
    (lambda: TriMesh(np.zeros((4, 3)), [[0, 1, 2]], name=None), "name must be a str"),
    (lambda: load_stone(None), "stone must be a built-in name"),
])
def test_mesh_inputs_are_refused_by_name(call, message):
    with pytest.raises(MeshError, match=message):
        call()


def test_mesh_review_2026_12_07(tmp_path):
    """(2026-12-07, a review) a cube exported face by face (each face its own four corners, as from STL) was
    refused as 'a hole ... add the missing triangles': it is named as unwelded now. mass_properties of a mesh
    with a NaN, or a thousandfold too large for floating point, said 'signed volume is nan <= 0; ... outward
    normals' (and NumPy warned); it says what is wrong. write_obj into a missing folder raised a raw
    FileNotFoundError and write_obj(123, mesh) a TypeError; both are MeshErrors naming the path. A mass at
    the top of the density range (25 000 kg/m^3) was refused by rounding, with a message whose range held it."""
    import warnings

    from jaxskip import rigid_stone
    from jaxskip.mesh import TriMesh, validate_mesh, write_obj

    cube = box(0.04, 0.04, 0.04)
    v, f = np.asarray(cube.vertices), np.asarray(cube.faces)
    unwelded = TriMesh(v[f].reshape(-1, 3), np.arange(3 * len(f)).reshape(-1, 3), name="stl cube")
    with pytest.raises(MeshError, match=r"belongs to only one triangle.*But 28 of its 36 vertices repeat another's "
                                        r"position.*merge \(weld\) the equal vertices"):
        validate_mesh(unwelded.vertices, unwelded.faces, name=unwelded.name)
    with warnings.catch_warnings():
        warnings.simplefilter("error")      # (no NumPy overflow warning either)
        for bad in (TriMesh(v * np.nan, f, name="nan"), TriMesh(v * 1e160, f, name="huge")):
            with pytest.raises(MeshError, match=r"its volume is not a finite number"):
                mass_properties(bad, density=1.0)
    with pytest.raises(MeshError, match=r"path: the folder .*nowhere' of .* does not exist"):
        write_obj(tmp_path / "nowhere" / "c.obj", cube)
    with pytest.raises(MeshError, match=r"path must be a file name"):
        write_obj(123, cube)
    top = 25000.0 * float(mass_properties(cube, density=1.0).volume) * (1 + 1e-12)   # the top, and a rounding over
    assert float(rigid_stone(cube, mass=top).mass) == pytest.approx(top, rel=1e-12)


def test_read_obj_takes_latin1_comments_and_continued_lines(tmp_path):
    """(2026-12-07, a review) one Latin-1 byte in a comment ('# Stein größe', as Windows exporters write) refused
    the whole file as not UTF-8; a face continued on the next line with a backslash, as the OBJ format allows,
    was refused as a bad face entry '\\\\'. Both read now, as the same box; a UTF-16 file is still refused."""
    a, b, c = 0.04, 0.03, 0.01
    v = [(0, 0, 0), (a, 0, 0), (a, b, 0), (0, b, 0), (0, 0, c), (a, 0, c), (a, b, c), (0, b, c)]
    faces = ["1 4 3 2", "5 6 7 8", "1 2 6 5", "3 4 8 7", "1 5 8 4", "2 3 7 6"]
    plain = "\n".join([f"v {x!r} {y!r} {z!r}" for x, y, z in v] + [f"f {f}" for f in faces]) + "\n"
    ref = read_obj(_write(tmp_path / "plain.obj", plain.encode()))
    latin = ("# Stein größe\n" + plain).encode("latin-1")
    continued = plain.replace("f 1 2 6 5\n", "f 1 2 \\\n  6 5\n").replace("f 5 6 7 8\n", "f 5 6 7 8 # top \\\n")
    for name, data in (("latin.obj", latin), ("continued.obj", continued.encode())):
        mesh = read_obj(_write(tmp_path / name, data))
        np.testing.assert_array_equal(mesh.vertices, ref.vertices)
        np.testing.assert_array_equal(mesh.faces, ref.faces)
    # (2026-12-07, a review: these read "'utf-8' codec can't decode byte 0xff in position 0", Python's words)
    import gzip

    for name, data, kind in (("wide.obj", plain.encode("utf-16"), "UTF-16 text.*save it as UTF-8"),
                             ("packed.obj", gzip.compress(plain.encode()), "a gzip archive.*decompress it"),
                             ("bytes.obj", bytes(range(256)), "binary data")):
        with pytest.raises(MeshError, match=f"cannot read OBJ file .* is not a text OBJ file \\(it looks like {kind}"):
            read_obj(_write(tmp_path / name, data))


def _write(path, data: bytes):
    path.write_bytes(data)
    return path


def test_a_stone_out_of_size_is_named_by_its_size_before_its_mass():
    """(2026-12-07, a review) a 0.05 mm stone given a mass was sent to a mass range ('mass must be in [4.56e-12,
    1.13e-09] kg') that then failed on its size; the size is checked first now."""
    from jaxskip import ParameterError, paper_stone, rigid_stone

    tiny = paper_stone().scaled(1e-3)
    for kw in ({"mass": 0.1}, {"mass": 1e-10}, {"density": 2650.0}):
        with pytest.raises(ParameterError, match=r"size \(bounding radius\) must be in \[1 mm, 1 m\]"):
            rigid_stone(tiny, **kw)


@pytest.mark.parametrize("far", [1e10, 1e30, 1e200])
def test_a_mesh_in_other_units_is_named_by_its_span_not_as_degenerate(far, recwarn):
    """(stop 47, a review) A tetrahedron with one vertex at 1e30 m was refused as "the triangle of line 5 is
    degenerate (area 2.5e+28 m^2)", and at 1e200 NumPy's overflow warnings came first: a mesh spanning over
    1 km (MAX_MESH_SPAN) is named by its span, silently."""
    v = np.array([[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [0.0, 0.01, 0.0], [0.0, 0.0, 0.01]])
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    validate_mesh(v, f)
    v[1, 0] = far
    with pytest.raises(MeshError, match=re.escape(f"spans {far:.3g} m along an axis, more than 1000 m: coordinates are "
                                                  "in metres")):
        validate_mesh(v, f)
    assert not [w for w in recwarn if issubclass(w.category, RuntimeWarning)]


def test_write_obj_with_its_arguments_swapped_says_so(tmp_path):
    """(stop 47, a review) write_obj(mesh, path) put the mesh's whole repr, ~250 lines of arrays, in its message."""
    with pytest.raises(MeshError, match=r"^path must be a file name \(str or os.PathLike\), got a TriMesh: the arguments "
                                        r"are write_obj\(path, mesh\)$"):
        write_obj(disk(0.04, 0.01), str(tmp_path / "x.obj"))


def test_an_empty_mesh_is_named_as_such_by_rigid_stone():
    """(stop 47, a review of the session's diff) With the stone's size checked before the mesh, an empty mesh met
    NumPy's raw "zero-size array to reduction operation maximum" instead of the mesh check's message."""
    from jaxskip import rigid_stone

    with pytest.raises(MeshError, match="a closed mesh needs at least 4 triangles, got 0"):
        rigid_stone(TriMesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=int)), density=2650.0)
