"""The indexed surface (app/gpu.py surface_arrays) draws exactly the de-indexed corners: every fan
triangle corner gets its own position, vertex normal and uv, except that each triangle's first index
in Flat is its polygon's own row, whose normal is the face normal (what Flat and the back-face test
read)."""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import replace

import numpy as np
import pytest

from marraztu.loaders.obj import load_obj, parse_obj
from marraztu.model import threads
from marraztu.model.build import build_mesh
from marraztu.model.mesh import (
    INDEX,
    Mesh,
    corners_of_polygons,
    fan_gather,
    polygon_corners_of_fans,
    polygons_of_corners,
)
from marraztu.render.gpu import _seams, edge_pairs, surface_arrays, used_shared_rows
from support.seed import SEED_ASSETS, SEED_MODELS


def corner_table(mesh: Mesh) -> np.ndarray:
    """(3T, 8) float32 position, vertex normal, uv per fan-triangle corner, straight from the mesh."""
    corners = mesh.triangle_corners().reshape(-1)
    return np.hstack([mesh.positions[mesh.corner_vertex[corners]], mesh.corner_normal[corners],
                      mesh.corner_uv[corners]]).astype(np.float32)


# A quad and a pentagon sharing an edge, with a uv seam (vertex 2 has two vt) and vn on some corners.
SEAMED = b"""v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 2 0 0.5
v 2 1 0.5
v 1.5 1.5 0.2
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vt 0.5 0.5
f 1/1 2/2 3/3 4/4
f 2/2 5/1 6/4 7/5 3/5
"""


def check_same_corners(mesh: Mesh) -> np.ndarray:
    arrays = surface_arrays(mesh)
    assert arrays.indices.dtype == np.uint32 and arrays.indices.max() < arrays.vertices.shape[0]
    drawn = arrays.vertices[arrays.indices]
    expected = corner_table(mesh)
    first = np.zeros(drawn.shape[0], bool)
    first[0::3] = True
    not_normal = [0, 1, 2, 6, 7]
    assert np.array_equal(drawn[:, not_normal], expected[:, not_normal])
    assert np.array_equal(drawn[~first, 3:6], expected[~first, 3:6])
    faces = np.repeat(np.arange(mesh.face_count), mesh.face_sizes - 2)  # each fan triangle's polygon
    assert np.array_equal(drawn[first, 3:6], mesh.face_normals[faces])  # first corner: the face normal
    # Gouraud and Phong's indices: the same corners, from the shared rows only.
    assert arrays.shared_indices.dtype == np.uint32
    shared = arrays.vertices[arrays.shared_indices]
    assert np.array_equal(shared, expected)
    assert arrays.shared_indices.max() < arrays.vertices.shape[0] - mesh.face_count, "no polygon row"
    # Whole-mesh vertex normals: each row the shared indices read, once.
    rows = used_shared_rows(mesh, arrays.vertices.shape[0] - mesh.face_count)
    assert np.array_equal(rows, np.unique(arrays.shared_indices))
    return arrays.vertices


def test_a_position_no_face_uses_gets_no_normal() -> None:
    mesh = parse_obj(b"v 0 0 0\nv 1 0 0\nv 9 9 9\nv 0 1 0\nf 1 2 4\n", "unused.obj")
    check_same_corners(mesh)
    assert used_shared_rows(mesh, mesh.vertex_count).tolist() == [0, 1, 3]


def test_polygons_with_a_uv_seam_draw_their_own_corners() -> None:
    mesh = parse_obj(SEAMED, "seamed.obj")
    vertices = check_same_corners(mesh)
    # 7 positions + 1 seam corner (vertex 3 with vt 5 in the pentagon) + 2 polygons' own rows
    assert vertices.shape[0] == 7 + 1 + 2


def test_a_smooth_grid_shares_its_vertices() -> None:
    rng = np.random.default_rng(5)
    cells = 20
    xs, ys = np.meshgrid(np.arange(cells + 1.0), np.arange(cells + 1.0))
    zs = rng.normal(scale=0.2, size=xs.shape)
    lines = [f"v {x} {y} {z}" for x, y, z in zip(xs.ravel(), ys.ravel(), zs.ravel())]
    row = cells + 1
    for j in range(cells):
        for i in range(cells):
            a = j * row + i + 1
            lines += [f"f {a} {a + 1} {a + row + 1}", f"f {a} {a + row + 1} {a + row}"]
    mesh = parse_obj(("\n".join(lines) + "\n").encode(), "grid.obj")
    assert mesh.attributes_per_position
    vertices = check_same_corners(mesh)
    assert vertices.shape[0] == mesh.vertex_count + mesh.face_count  # no seams: uv and normals per vertex


def _random_obj(seams: bool) -> bytes:
    """Triangles and quads over shared positions; with seams, each corner names a vt and vn of its own."""
    rng = np.random.default_rng(37)
    lines = [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in rng.normal(size=(40, 3))]
    corner = 0
    for size in rng.integers(3, 5, 60):
        picked = rng.choice(40, int(size), replace=False) + 1
        if seams:
            lines += [f"vt {u:.4f} {v:.4f}" for u, v in rng.random((size, 2))]
            lines += [f"vn {x:.4f} {y:.4f} {z:.4f}" for x, y, z in rng.normal(size=(size, 3))]
            lines.append("f " + " ".join(f"{p}/{corner + k + 1}/{corner + k + 1}" for k, p in enumerate(picked)))
            corner += int(size)
        else:
            lines.append("f " + " ".join(str(p) for p in picked))
    return ("\n".join(lines) + "\n").encode()


@pytest.mark.parametrize("seams", [False, True], ids=["per position", "seams"])
def test_surface_rows_made_in_small_pieces_are_the_same(seams: bool, monkeypatch: pytest.MonkeyPatch) -> None:
    """Pieces of 3 rows cut through the positions' rows, the seams', the polygons' own and their fans'
    indices: the arrays are those made in one piece, and draw the same corners."""
    mesh = parse_obj(_random_obj(seams), "random.obj")
    whole = surface_arrays(mesh)
    monkeypatch.setattr(threads, "ROWS_PER_PIECE", 3)
    pieced = surface_arrays(mesh)
    assert (whole.shared_rows > mesh.vertex_count) == seams
    for name, array in whole.arrays.items():
        assert np.array_equal(array.view(np.uint8), pieced.arrays[name].view(np.uint8)), name
    check_same_corners(mesh)


@pytest.mark.parametrize("size", [4, 5, 7])
def test_polygons_all_of_one_size_fan_from_their_first_corner(size: int) -> None:
    """Their fans are gathered within each polygon's row of corners (no table of triangle corners)."""
    angles = np.linspace(0.0, 2.0 * np.pi, size, endpoint=False)
    ring = [f"v {np.cos(a)} {np.sin(a)} {0.1 * k}" for k, a in enumerate(angles)]
    lifted = [f"v {np.cos(a)} {np.sin(a)} {1.0 + 0.1 * k}" for k, a in enumerate(angles)]
    faces = [" ".join(str(k + 1) for k in range(size)), " ".join(str(size + k + 1) for k in reversed(range(size)))]
    mesh = parse_obj(("\n".join(ring + lifted + [f"f {face}" for face in faces]) + "\n").encode(), "rings.obj")
    assert not mesh.all_triangles and set(mesh.face_sizes.tolist()) == {size}
    check_same_corners(mesh)


@pytest.mark.parametrize("sizes", [[3, 3], [4, 4, 4], [5], [3, 4, 9, 3], [1000, 3]])
def test_fans_gathered_into_place_are_the_fans_gathered(sizes: list[int]) -> None:
    """fan_gather's `out` takes what it would give: the surface indices write each block's fans there."""
    face_start = np.concatenate(([0], np.cumsum(sizes)))
    values = np.random.default_rng(len(sizes)).integers(0, 1 << 31, face_start[-1]).astype(np.uint32)
    given = fan_gather(values, face_start)
    out = np.full(given.shape, 7, np.uint32)
    assert fan_gather(values, face_start, out=out) is out and np.array_equal(out, given)
    assert np.array_equal(given.reshape(-1, 3)[:, 0], np.repeat(values[face_start[:-1]], np.array(sizes) - 2))


@pytest.mark.parametrize("sizes", [[3, 3], [4, 4, 4], [5], [3, 4, 9, 3], [1000, 3]])
def test_polygons_are_made_again_of_their_fans(sizes: list[int]) -> None:
    """polygon_corners_of_fans undoes fan_gather (a PLY's polygons, made again of trimesh's triangles),
    and build_mesh takes the corners with their sizes as it takes the polygons listed."""
    face_start = np.concatenate(([0], np.cumsum(sizes)))
    corners = np.random.default_rng(len(sizes)).integers(0, 1200, face_start[-1])
    fans = fan_gather(corners, face_start).reshape(-1, 3)
    assert np.array_equal(polygon_corners_of_fans(fans, np.array(sizes)), corners)
    positions = np.random.default_rng(1).normal(size=(1200, 3))
    listed = build_mesh("m", positions, [corners[start:stop] for start, stop in zip(face_start, face_start[1:])])
    sized = build_mesh("m", positions, corners, face_sizes=np.array(sizes))
    for name in ("corner_vertex", "face_start", "face_normals", "normals", "uvs"):
        assert np.array_equal(getattr(sized, name), getattr(listed, name)), name
    with pytest.raises(ValueError, match="hold"):
        build_mesh("m", positions, corners[:-1], face_sizes=np.array(sizes))


@pytest.mark.parametrize(("sizes", "corners", "said"), [
    ([3.5], [0, 1, 2], "face sizes must be whole numbers"),
    ([float("nan")], [0, 1, 2], "face sizes must be whole numbers"),
    ([2], [0, 1], "face 0 has 2 vertices: a face needs at least 3"),
    ([2 ** 62] * 3 + [2 ** 62 + 3], [0, 1, 2], "fewer than"),  # a sum that would wrap
    ([3, 4], [[0, 1, 2], [0, 1, 2, 3]], "one flat array"),
    ([3, 3], [0, 1, 2, 0, 1, 2**70], r"^face 1 refers to vertex 1180591620717411303424, but there are 5 \(0-based\)$"),
    ([3, 3], [0, 1, 2, 0, 1, 7], r"^face 1 refers to vertex 7, but there are 5 \(0-based\)$"),
])
def test_faces_with_sizes_are_checked_where_they_enter(sizes: list[float], corners: list, said: str) -> None:
    with pytest.raises(ValueError, match=said):
        build_mesh("m", np.zeros((5, 3)), corners, face_sizes=sizes)


def test_each_corner_is_found_in_its_polygon() -> None:
    """One corner (a Python int) or many (int64, as np.flatnonzero gives them), on the mesh's own index type."""
    sizes = [3, 4, 9, 3, 1000, 3]
    face_start = np.concatenate(([0], np.cumsum(sizes))).astype(INDEX)
    owner = np.repeat(np.arange(len(sizes)), sizes)
    corners = np.arange(face_start[-1], dtype=np.int64)
    assert np.array_equal(polygons_of_corners(face_start, corners), owner)
    assert [int(polygons_of_corners(face_start, corner)) for corner in (0, 2, 3, 16, 1018, 1021)] == [0, 0, 1, 3, 4, 5]


@pytest.mark.parametrize("dtype", [np.uint8, np.uint32, np.int32, np.int64])
def test_the_corners_of_chosen_polygons_are_listed_whatever_the_counts_type(dtype: type) -> None:
    """A PLY's list counts may come as uchar: the corners are indices (or byte offsets), never floats."""
    first, sizes = np.array([5, 0, 9], dtype), np.array([3, 4, 2], dtype)
    corners = corners_of_polygons(first, sizes)
    assert corners.dtype.kind == "i" and corners.tolist() == [5, 6, 7, 0, 1, 2, 3, 9, 10]
    assert corners_of_polygons(first, sizes, 4).tolist() == [5, 9, 13, 0, 4, 8, 12, 9, 13]


def assert_no_seams(mesh: Mesh) -> None:
    """What lets surface_arrays skip the seam search when the mesh says it has per-position attributes."""
    representative = np.zeros(mesh.vertex_count, np.int64)
    representative[mesh.corner_vertex] = np.arange(mesh.corner_vertex.size)
    assert _seams(mesh, representative[mesh.corner_vertex]).size == 0


@pytest.mark.parametrize("name", [name for name, _, _ in SEED_MODELS])
def test_per_position_attributes_are_claimed_only_where_there_are_no_seams(name: str) -> None:
    path = SEED_ASSETS / name
    if not path.exists():
        pytest.skip(f"{path} is not here (the seed's models live in ../shared)")
    mesh = load_obj(path)
    if mesh.attributes_per_position:  # cam and kupula; r_falke and x_wing have positions that only
        # zero-area faces touch, whose corners take their own faces' normals (see the test below)
        assert_no_seams(mesh)
    check_same_corners(mesh)


Row = Callable[[int], int] | None  # a corner's 1-based vt or vn row from its position's 1-based row


def grid_obj(cells: int, vt: Row, vn: Row, seed: int = 5) -> bytes:
    """A bumpy grid of triangles, each corner's vt and vn rows given by `vt` and `vn` (None: none)."""
    rng = np.random.default_rng(seed)
    side = cells + 1
    xs, ys = np.meshgrid(np.arange(side, dtype=float), np.arange(side, dtype=float))
    zs = rng.normal(scale=0.2, size=xs.shape)
    lines = [f"v {x} {y} {z}" for x, y, z in zip(xs.ravel(), ys.ravel(), zs.ravel())]
    lines += [f"vt {u:.4f} {v:.4f}" for u, v in rng.random((side * side + 3, 2))] if vt else []
    lines += [f"vn {x:.4f} {y:.4f} {z:.4f}" for x, y, z in rng.normal(size=(side * side + 3, 3))] if vn else []

    def corner(p: int) -> str:
        return "/".join([str(p), str(vt(p)) if vt else "", str(vn(p)) if vn else ""]).rstrip("/")

    for j in range(cells):
        for i in range(cells):
            a = j * side + i + 1
            for triangle in ((a, a + 1, a + side + 1), (a, a + side + 1, a + side)):
                lines.append("f " + " ".join(corner(p) for p in triangle))
    return ("\n".join(lines) + "\n").encode()


def same_row(p: int) -> int:
    return p


def shifted_row(p: int) -> int:
    return p + 2


@pytest.mark.parametrize("vt, vn", [(same_row, same_row), (same_row, None), (None, same_row),
                                    (shifted_row, same_row), (same_row, shifted_row)])
def test_a_file_whose_corners_name_their_positions_rows_stores_them_per_position(vt: Row, vn: Row) -> None:
    """`f 1/1/1 2/2/2 3/3/3`, or any vt and vn that follow the position: a row per position, a sixth
    of the corners', and the same corners as the file gives them."""
    mesh = parse_obj(grid_obj(12, vt, vn), "grid.obj")
    assert mesh.attributes_per_position
    assert mesh.uvs.shape == (mesh.vertex_count, 2) and mesh.normals.shape == (mesh.vertex_count, 3)
    check_same_corners(mesh)
    assert_no_seams(mesh)


def test_per_position_and_per_corner_storage_give_the_same_corners() -> None:
    """One extra face whose first corner names another vt makes the file per corner: every corner the
    two files share has the same uv and normal either way."""
    text = grid_obj(10, same_row, same_row)
    per_position = parse_obj(text, "grid.obj")
    per_corner = parse_obj(text + b"f 1/2/1 2/2/2 13/13/13\n", "seam.obj")
    assert per_position.attributes_per_position and not per_corner.attributes_per_position
    assert per_corner.normals.shape == (per_corner.corner_vertex.size, 3)
    shared = per_position.corner_vertex.size
    assert np.array_equal(per_corner.corner_uv[:shared], per_position.corner_uv)
    assert np.array_equal(per_corner.corner_normal[:shared], per_position.corner_normal)
    check_same_corners(per_corner)


def test_the_material_parts_of_a_per_position_mesh_keep_their_corners() -> None:
    mesh = parse_obj(grid_obj(6, same_row, same_row), "grid.obj")
    split = replace(mesh, face_material=(np.arange(mesh.face_count) % 3 == 0).astype(np.int32))
    for index, part in enumerate(split.parts):
        drawn = split.part_mesh(index)
        assert drawn.attributes_per_position and drawn.normals.shape == (drawn.vertex_count, 3)
        corners = (split.face_start[part.faces][:, None] + np.arange(3)).reshape(-1)
        assert np.array_equal(drawn.corner_uv, mesh.corner_uv[corners])
        assert np.array_equal(drawn.corner_normal, mesh.corner_normal[corners])
        check_same_corners(drawn)


def test_build_mesh_takes_per_vertex_tables_as_the_same_corners() -> None:
    """attributes_per_vertex: a row per position, stored per position; a NaN row is derived, as a
    NaN corner row is."""
    rng = np.random.default_rng(7)
    positions = rng.normal(size=(6, 3))
    faces = np.array([[0, 1, 2], [0, 2, 3], [3, 4, 5], [1, 5, 4]])
    uvs, normals = rng.random((6, 2)), rng.normal(size=(6, 3))
    uvs[4] = np.nan
    corners = faces.reshape(-1)
    per_corner = build_mesh("a", positions, faces, uvs=uvs[corners], normals=normals[corners])
    per_vertex = build_mesh("a", positions, faces, uvs=uvs, normals=normals, attributes_per_vertex=True)
    by_rows = build_mesh("a", positions, faces, uvs=uvs, normals=normals)  # 6 rows, 12 corners: per vertex
    for mesh in (per_vertex, by_rows):
        assert mesh.attributes_per_position and mesh.uvs.shape == (6, 2)
        assert np.array_equal(mesh.corner_uv, per_corner.corner_uv)
        assert np.array_equal(mesh.corner_normal, per_corner.corner_normal)
    with pytest.raises(ValueError, match=r"one row per vertex, shape \(6, 2\)"):
        build_mesh("a", positions, faces, uvs=uvs[:5])
    with pytest.raises(ValueError, match=r"per vertex need shape \(6, 2\)"):
        build_mesh("a", positions, faces, uvs=uvs[corners], attributes_per_vertex=True)


def test_a_zero_length_vn_is_derived_per_position_too() -> None:
    """Position 1's corners all name a zero-length vn: it gets the normal derived from its faces."""
    text = re.sub(rb"^vn .*$", b"vn 0 0 0", grid_obj(6, None, same_row), count=1, flags=re.MULTILINE)
    mesh = parse_obj(text, "zero.obj")
    assert mesh.attributes_per_position
    check_same_corners(mesh)
    assert np.allclose(np.linalg.norm(mesh.normals, axis=1), 1.0, atol=1e-6)
    derived = parse_obj(grid_obj(6, None, None), "derived.obj")
    assert np.array_equal(mesh.normals[0], derived.normals[0])
    assert not np.allclose(mesh.normals[1], derived.normals[1])  # the file's own


def test_unused_positions_of_a_per_position_mesh_get_unit_normals() -> None:
    mesh = parse_obj(b"v 0 0 0\nv 1 0 0\nv 9 9 9\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
                     b"f 1/1/1 2/2/1 4/3/1\n", "unused.obj")
    assert mesh.attributes_per_position
    assert np.allclose(np.linalg.norm(mesh.normals, axis=1), 1.0) and np.isfinite(mesh.uvs).all()
    check_same_corners(mesh)


def test_a_position_with_no_face_of_any_area_is_not_per_position() -> None:
    """Its corners take their own faces' normals (the loader's last resort), which may differ."""
    mesh = parse_obj(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 5 5 5\nf 1 2 3\nf 4 4 4\nf 1 4 4\n", "lonely.obj")
    assert not mesh.attributes_per_position
    check_same_corners(mesh)


def test_edge_pairs_are_each_polygons_boundary_in_order() -> None:
    """Every corner and the next one of its polygon, the last closing on the first, polygon by polygon:
    written out corner by corner here, against the array version, on polygons of random sizes."""
    rng = np.random.default_rng(5)
    sizes = rng.integers(3, 9, size=200)
    faces = [list(range(start, start + size)) for start, size in zip(np.cumsum(sizes) - sizes, sizes)]
    mesh = build_mesh("polygons", rng.random((int(sizes.sum()), 3)), faces)
    expected = [(face[at], face[(at + 1) % len(face)]) for face in faces for at in range(len(face))]
    assert edge_pairs(mesh).reshape(-1, 2).tolist() == [list(pair) for pair in expected]
    assert edge_pairs(mesh).dtype == np.uint32
