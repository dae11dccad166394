"""The OBJ loader: every good and bad case of SPEC 7, the derived normals and uv, the seed models."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from types import ModuleType
from typing import NamedTuple

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from marraztu.errors import LoadError
from marraztu.loaders import obj as obj_module
from marraztu.loaders.files import read_file
from marraztu.loaders.obj import fast as fast_reader
from marraztu.loaders.obj import lines as lines_module
from marraztu.loaders.obj import load_obj, parse_obj, scan
from marraztu.loaders.obj import text as obj_text
from marraztu.loaders.obj.lines import read_by_lines
from marraztu.loaders.obj.raw import TABLE_WIDTHS, RawObj
from marraztu.model.build import build_mesh
from marraztu.model.mesh import Mesh
from support.seed import SEED_MODELS, seed_model
from support.work import lines_read_by_python

QUAD = b"v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nf 1 2 3 4\n"


def parse(text: bytes | str, source: str = "model.obj") -> Mesh:
    return parse_obj(text.encode() if isinstance(text, str) else text, source)


def assert_finite(mesh: Mesh) -> None:
    for array in (mesh.positions, mesh.corner_uv, mesh.corner_normal, mesh.face_normals):
        assert np.isfinite(array).all()


def assert_mesh_dtypes(mesh: Mesh) -> None:
    assert mesh.positions.dtype == np.float64
    assert mesh.corner_vertex.dtype == np.int32
    assert mesh.corner_uv.dtype == np.float32
    assert mesh.corner_normal.dtype == np.float32
    assert mesh.face_start.dtype == np.int32
    assert mesh.face_normals.dtype == np.float32


# --- good input ------------------------------------------------------------------------------------


@pytest.mark.parametrize("reader", [read_by_lines, fast_reader.read_fast])
def test_corners_of_empty_last_parts_are_read_as_written_without_them(reader) -> None:
    """Wings3D writes a corner of no vt and no vn as 'v//', old assimp one of no vn as 'v/vt/': both were
    refused as bad face corners, which Blender's and trimesh's readers take."""
    tables = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
    raw = reader(tables + b"f 1// 2// 3// 4//\nf 1/1/ 2/2/ 3/3/\n", "wings.obj")
    plain = reader(tables + b"f 1 2 3 4\nf 1/1 2/2 3/3\n", "plain.obj")
    assert raw.face_start.tolist() == plain.face_start.tolist() == [0, 4, 7]
    assert raw.corner_vertex.tolist() == plain.corner_vertex.tolist()
    assert raw.corner_texcoord.tolist() == plain.corner_texcoord.tolist() == [-1, -1, -1, -1, 0, 1, 2]


def test_quad_keeps_one_polygon_with_normals_and_bounding_box_uv() -> None:
    mesh = parse(QUAD)
    assert (mesh.vertex_count, mesh.face_count) == (4, 1)
    assert mesh.face_start.tolist() == [0, 4]
    assert mesh.corner_vertex.tolist() == [0, 1, 2, 3]
    np.testing.assert_allclose(mesh.face_normals, [[0, 0, 1]])
    np.testing.assert_allclose(mesh.corner_normal, [[0, 0, 1]] * 4)
    # The two largest extents are x (2) and y (1), each mapped to 0..1.
    np.testing.assert_allclose(mesh.corner_uv, [[0, 0], [1, 0], [1, 1], [0, 1]])
    assert mesh.name == "model"
    assert mesh.warnings == ()
    assert_mesh_dtypes(mesh)


def test_clockwise_quad_faces_the_other_way() -> None:
    mesh = parse(QUAD.replace(b"f 1 2 3 4", b"f 4 3 2 1"))
    np.testing.assert_allclose(mesh.face_normals, [[0, 0, -1]])


@pytest.mark.parametrize(("text", "uv"), [
    ("v 0 0 0\nv 2 0 0\nv 2 5 0\nf 1 2 3\n", [[0, 0], [1, 0], [1, 1]]),  # facing z: u along x, v up y
    ("v 0 0 0\nv 0 5 0\nv 0 5 2\nf 1 2 3\n", [[1, 0], [1, 1], [0, 1]]),  # a wall facing x: u along -z, v up y
    ("v 0 0 0\nv 2 0 0\nv 2 0 5\nf 1 2 3\n", [[0, 1], [1, 1], [1, 0]]),  # a floor: u along x, v along -z
])
def test_bounding_box_uv_reads_upright_from_the_flattest_sides_positive_end(text: str, uv: list[list[int]]) -> None:
    """A floor's v ran along +z, toward the start camera: from above its picture read mirrored."""
    mesh = parse(text)
    np.testing.assert_array_equal(mesh.corner_uv, np.array(uv, np.float32))
    assert not np.signbit(mesh.corner_uv).any()



@pytest.mark.parametrize("z_extent", ["2", "2.000001", "1.999999"])
def test_a_cube_a_float_rounding_off_square_takes_the_texture_facing_the_start_camera(z_extent: str) -> None:
    """A cube written in float32 (trimesh's cube.glb: 2 x 2 x 2.000001) was taken for a floor, its
    picture projected from above, so the face toward the start camera showed streaks of its edge rows."""
    corners = [(x, y, z) for x in ("0", "2") for y in ("0", "2") for z in ("0", z_extent)]
    mesh = parse("".join(f"v {x} {y} {z}\n" for x, y, z in corners) + "f 2 6 8 4\nf 1 2 4 3\n")
    np.testing.assert_array_equal(mesh.corner_uv[:4], np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32))

def test_pentagon_is_kept_whole_and_fans_from_its_first_corner() -> None:
    mesh = parse("v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\nf 1 2 3 4 5\nf 1 2 3\n")
    assert mesh.face_start.tolist() == [0, 5, 8]
    assert mesh.triangle_corners().tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 4], [5, 6, 7]]
    np.testing.assert_allclose(mesh.face_normals, [[0, 0, 1], [0, 0, 1]], atol=1e-7)


def test_polygons_all_of_one_size_fan_the_same_way() -> None:
    """Quads-only and pentagons-only meshes take the loader's and Mesh's one-size shortcuts."""
    pentagon = "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\n"
    mesh = parse(pentagon + "f 1 2 3 4 5\nf 5 4 3 2 1\n")
    assert mesh.triangle_corners().tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 4], [5, 6, 7], [5, 7, 8], [5, 8, 9]]
    np.testing.assert_allclose(mesh.face_normals, [[0, 0, 1], [0, 0, -1]], atol=1e-7)


@pytest.mark.parametrize("corners", ["1 2 3", "1/1 2/2 3/3", "1//1 2//2 3//3", "1/1/1 2/2/2 3/3/3"])
def test_every_corner_format(corners: str) -> None:
    text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.5\nvt 0.75 0.5\nvt 0.5 1\nvn 0 0 2\nvn 0 0 1\nvn 0 0 1\n"
    mesh = parse(text + f"f {corners}\n")
    assert mesh.corner_vertex.tolist() == [0, 1, 2]
    if "/" in corners and not corners.startswith("1//"):
        np.testing.assert_allclose(mesh.corner_uv, [[0.25, 0.5], [0.75, 0.5], [0.5, 1]])
    else:
        np.testing.assert_allclose(mesh.corner_uv, [[0, 0], [1, 0], [0, 1]])
    np.testing.assert_allclose(mesh.corner_normal, [[0, 0, 1]] * 3)  # vn 0 0 2 is normalized


def test_file_normals_win_over_derived_ones_and_zero_length_ones_do_not() -> None:
    text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 1 0 0\nvn 0 0 0\nf 1//1 2//2 3//1\n"
    mesh = parse(text)
    np.testing.assert_allclose(mesh.corner_normal, [[1, 0, 0], [0, 0, 1], [1, 0, 0]])


def test_vertex_normals_average_the_faces_around_a_position() -> None:
    # Two triangles folded along the y axis at a right angle: the shared edge gets the average.
    text = "v 0 0 0\nv 0 1 0\nv 1 0 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n"
    mesh = parse(text)
    np.testing.assert_allclose(mesh.face_normals, [[0, 0, 1], [1, 0, 0]], atol=1e-7)
    shared = np.array([1, 0, 1]) / np.sqrt(2)  # vertices 1 and 2 lie on the fold
    np.testing.assert_allclose(mesh.corner_normal[[0, 2, 3, 4]], [shared] * 4, atol=1e-6)
    np.testing.assert_allclose(mesh.corner_normal[1], [0, 0, 1], atol=1e-7)
    np.testing.assert_allclose(mesh.corner_normal[5], [1, 0, 0], atol=1e-7)


def test_negative_indices_count_back_from_the_last_definition() -> None:
    text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\nv 6 5 5\nv 5 6 5\nf -3 -2 -1\nf 1 -2 -1\n"
    mesh = parse(text)
    assert mesh.corner_vertex.tolist() == [0, 1, 2, 3, 4, 5, 0, 4, 5]


def test_negative_texture_and_normal_indices() -> None:
    text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf -3/-3/-1 -2/-2/-1 -1/-1/-1\n"
    mesh = parse(text)
    np.testing.assert_allclose(mesh.corner_uv, [[0, 0], [1, 0], [0, 1]])


def test_groups_smoothing_materials_comments_and_unknown_statements_are_one_object() -> None:
    text = (
        "# a comment\nmtllib missing.mtl\no first\ng part\ns 1\nusemtl red\n\n"
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\no second\ns off\n"
        "t 0 0 0  1 1 1\nc 100 0 255\nvp 0.5\ncstype bezier\nf 2 4 3\n"
    )
    mesh = parse(text)
    assert mesh.face_count == 2
    assert mesh.warnings == ()  # parse_obj without base_dir does not look for the MTL


def test_crlf_tabs_and_indentation_are_whitespace() -> None:
    text = b"v\t0 0 0\r\n  v 1\t0 0\r\n\tv 0 1 0 \r\n\r\n   \r\nf 1\t2 3\r\n"
    mesh = parse(text)
    assert (mesh.vertex_count, mesh.face_count) == (3, 1)
    np.testing.assert_allclose(mesh.positions[1], [1, 0, 0])


def test_last_line_without_newline() -> None:
    assert parse(QUAD.rstrip(b"\n")).face_count == 1


@pytest.mark.parametrize(("written", "read"), [
    (QUAD, QUAD), (QUAD[:-1], QUAD), (b"\xef\xbb\xbf" + QUAD, QUAD), (b"\xef\xbb\xbf" + QUAD[:-1], QUAD),
    (b"\xef\xbb\xbf", b"\n"), (b"x", b"x\n")])
def test_a_file_is_read_as_its_text_ended(tmp_path: Path, written: bytes, read: bytes) -> None:
    """What read_text gives is what ended gives the bytes: no byte order mark, a last newline."""
    path = tmp_path / "m.obj"
    path.write_bytes(written)
    assert obj_text.read_text(path, None).tobytes() == obj_text.ended(written) == read


def test_a_file_that_grows_after_its_size_is_known_is_read_whole(tmp_path: Path,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    """Read into room for the size stat gave, and a byte more: a file that grew since is read again."""
    path = tmp_path / "m.obj"
    path.write_bytes(QUAD * 100)
    monkeypatch.setattr(obj_text, "regular_file_size", lambda path: len(QUAD))
    assert obj_text.read_text(path, None).tobytes() == QUAD * 100
    assert load_obj(path).face_count == 100


def test_a_blank_file_is_refused_as_empty(tmp_path: Path) -> None:
    path = tmp_path / "m.obj"
    path.write_bytes(b" \n\t\r\n")
    with pytest.raises(LoadError, match="empty file: no faces"):
        obj_text.read_text(path, None)


@pytest.mark.parametrize("long_line", ["first", "middle", "last", "only"])
def test_the_text_is_cut_into_whole_lines_whatever_their_lengths(long_line: str) -> None:
    """A line longer than a piece (one huge polygon) must not cut a piece short, repeat one, or send
    the search for the next cut past the text's end."""
    short = b"v 1 2 3\n" * (fast_reader.MIN_PIECE_BYTES // 4)
    long = b"f" + b" 1" * (3 * fast_reader.MIN_PIECE_BYTES) + b"\n"
    text = {"first": long + short, "middle": short + long + short, "last": short + long, "only": long}[long_line]
    buf = np.frombuffer(text, np.uint8)
    pieces = fast_reader._pieces(buf, 16)
    assert pieces[0][0] == 0 and pieces[-1][1] == len(text)
    assert all(low < high and text[high - 1:high] == b"\n" for low, high in pieces)
    assert all(earlier[1] == later[0] for earlier, later in zip(pieces, pieces[1:]))


def test_vertex_extras_w_and_colours_are_ignored_and_vt_may_have_w() -> None:
    text = "v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0 1 0.2 0.3 0.4\nvt 0.5 0.5 0\nf 1/1 2/1 3/1\n"
    mesh = parse(text)
    np.testing.assert_allclose(mesh.positions, [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    np.testing.assert_allclose(mesh.corner_uv, [[0.5, 0.5]] * 3)


def test_number_syntaxes() -> None:
    text = "v -1.5e2 +2 .5\nv 1. -0 3E-1\nv 0.000001 1234567890.12345 -7\nf 1 2 3\n"
    mesh = parse(text)
    np.testing.assert_array_equal(mesh.positions, [[-150, 2, 0.5], [1, 0, 0.3], [1e-6, 1234567890.12345, -7]])


def test_trailing_comments_line_continuations_and_forward_references() -> None:
    text = "f 1 2 \\\n 3 # a face before its vertices\nv 0 0 0 # origin\nv 1 0 0\nv 0 1 0\n"
    mesh = parse(text)
    assert mesh.corner_vertex.tolist() == [0, 1, 2]


def test_a_statement_continued_over_many_lines_costs_its_length() -> None:
    """Continued lines are joined in one growing buffer, not kept as an object each until the end."""
    from support.work import peak_traced_bytes

    text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\no a \\\n" + b"\\\n" * 500_000 + b"x\n"
    raw, peak = peak_traced_bytes(lambda: read_by_lines(text, "continued.obj"))
    assert raw.corner_vertex.tolist() == [0, 1, 2]
    assert peak < 4 * len(text), peak  # a list of its lines held 94 times the text


def test_a_last_line_continued_without_a_newline_is_read_as_with_one() -> None:
    """The loader always ends a text with a newline; a caller of the line reader may not."""
    with pytest.raises(LoadError) as refused:
        read_by_lines(b"v 1 2 \\", "x.obj")
    assert (refused.value.line, refused.value.message) == (1, "a vertex position (v) needs 3 to 7 numbers, found 2")


def test_faces_may_mix_formats_across_faces() -> None:
    text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0.5 0.5\nf 1 2 3\nf 2/1 4/1 3/1\n"
    mesh = parse(text)
    np.testing.assert_allclose(mesh.corner_uv[:3], [[0, 0], [1, 0], [0, 1]])
    np.testing.assert_allclose(mesh.corner_uv[3:], [[0.5, 0.5]] * 3)


def test_unreferenced_vertices_are_fine() -> None:
    mesh = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 9 9 9\nf 1 2 3\n")
    assert mesh.vertex_count == 4
    assert_finite(mesh)


def test_zero_area_faces_get_a_fallback_normal_and_a_warning() -> None:
    text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 3 3 3\n"
    mesh = parse(text)
    assert mesh.warnings == ("2 zero-area faces (given a fallback normal)",)
    assert_finite(mesh)
    np.testing.assert_allclose(np.linalg.norm(mesh.face_normals, axis=1), 1, atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(mesh.corner_normal, axis=1), 1, atol=1e-6)
    np.testing.assert_allclose(mesh.face_normals[1], [0, 0, 1], atol=1e-6)  # its vertices' normals


def test_a_mesh_of_only_degenerate_faces_has_no_nan() -> None:
    mesh = parse("v 1 1 1\nv 1 1 1\nv 1 1 1\nf 1 2 3\n")
    assert_finite(mesh)
    np.testing.assert_allclose(mesh.face_normals, [[0, 0, 1]])


def test_huge_coordinates_give_no_nan() -> None:
    mesh = parse("v -3e38 0 0\nv 3e38 0 0\nv 0 3e38 0\nvt 3e38 -3e38\nf 1/1 2/1 3/1\n")
    assert_finite(mesh)
    assert mesh.warnings == ()


def test_colour_comment_sets_the_base_colour() -> None:
    mesh = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n# colour 255 0 51\n")
    assert mesh.base_colour == pytest.approx((1.0, 0.0, 0.2))


@pytest.mark.parametrize("comment", ["# colour red green blue", "# colour 1_0 0 0"])  # float() reads 1_0 as 10
def test_malformed_colour_comment_is_a_warning(comment: str) -> None:
    mesh = parse(f"{comment}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    assert mesh.base_colour is None
    assert mesh.warnings == ("ignored a malformed '# colour' comment on line 1",)


def test_mtl_next_to_the_file_seeds_the_material(tmp_path: Path) -> None:
    (tmp_path / "paint.mtl").write_text("# c\nnewmtl gold\nKa 0.1 0.2 0.3\nKd 0.5\nNs 80\nnewmtl other\nKs 1 1 1\n")
    path = tmp_path / "ship.obj"
    path.write_bytes(b"mtllib paint.mtl\n" + QUAD)
    mesh = load_obj(path)
    assert mesh.file_material == {"ka": (0.1, 0.2, 0.3), "kd": (0.5, 0.5, 0.5), "ns": 80.0}
    assert mesh.warnings == ()
    assert mesh.name == "ship"


def test_mtl_name_with_a_space(tmp_path: Path) -> None:
    (tmp_path / "Rammer 225.mtl").write_text("newmtl a\nKs 0.9 0.8 0.5\n")
    path = tmp_path / "rammer.obj"
    path.write_bytes(b"mtllib Rammer 225.mtl\n" + QUAD)
    assert load_obj(path).file_material == {"ks": (0.9, 0.8, 0.5)}


def test_missing_or_broken_mtl_is_a_warning(tmp_path: Path) -> None:
    path = tmp_path / "a.obj"
    path.write_bytes(b"mtllib nowhere.mtl\n" + QUAD)
    mesh = load_obj(path)
    assert mesh.file_material is None
    assert len(mesh.warnings) == 1 and "nowhere.mtl" in mesh.warnings[0]
    (tmp_path / "broken.mtl").write_bytes(b"\xff\xfe garbage\nKd x y z\n")
    path.write_bytes(b"mtllib broken.mtl\n" + QUAD)
    mesh = load_obj(path)
    assert mesh.file_material is None and "broken.mtl" in mesh.warnings[0]
    (tmp_path / "bad.mtl").write_text("newmtl a\nKd 1 nan 2\nNs 5\n")
    path.write_bytes(b"mtllib bad.mtl\n" + QUAD)
    mesh = load_obj(path)
    assert mesh.file_material == {"ns": 5.0}
    assert "Kd" in mesh.warnings[0]


# --- bad input: a LoadError naming the file and the line ---------------------------------------------

V3 = "v 0 0 0\nv 1 0 0\nv 0 1 0\n"

BAD_CASES = [
    ("empty file", "", None, "no faces"),
    ("whitespace only", " \n\n# nothing\n", None, "no faces"),
    ("no faces", V3, None, "no faces"),
    ("nul byte", V3 + "f 1 2\x00 3\n", 4, "binary"),
    ("two numbers", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", 2, "needs 3 to 7 numbers, found 2"),
    ("bare v", "v\n" + V3 + "f 1 2 3\n", 1, "found 0"),
    ("eight numbers", "v 1 2 3 4 5 6 7 8\n" + V3 + "f 1 2 3\n", 1, "found 8"),
    ("not a number", V3 + "v 1 x 3\nf 1 2 3\n", 4, "'x' is not a number"),
    ("two dots", V3 + "v 1 2.3.4 3\nf 1 2 3\n", 4, "'2.3.4' is not a number"),
    ("minus inside", V3 + "v 1 2-3 3\nf 1 2 3\n", 4, "'2-3' is not a number"),
    ("truncated exponent", V3 + "v 1 2 3e\nf 1 2 3\n", 4, "'3e' is not a number"),
    ("comma decimal", V3 + "v 1 2,5 3\nf 1 2 3\n", 4, "'2,5' is not a number"),
    ("nan", V3 + "v 1 nan 3\nf 1 2 3\n", 4, "'nan' is not a finite number"),
    ("inf", V3 + "vn inf 0 0\nf 1 2 3\n", 4, "not a finite number"),
    ("overflow", V3 + "v 1 1e999 3\nf 1 2 3\n", 4, "'1e999' is not a finite number"),
    ("beyond float32", V3 + "v 1 3.5e38 3\nf 1 2 3\n", 4, "'3.5e38' is too large"),
    ("beyond float32 vt", V3 + "vt 1e300 0\nf 1 2 3\n", 4, "'1e300' is too large"),
    ("vt no number", V3 + "vt\nf 1 2 3\n", 4, "texture coordinate (vt) needs 1 to 3 numbers, found 0"),
    ("vn two numbers", V3 + "vn 0 1\nf 1 2 3\n", 4, "normal (vn) needs 3 numbers, found 2"),
    ("truncated face", V3 + "f 1 2 3\nf 1 2", 5, "at least 3 vertices, found 2"),
    ("face of one", V3 + "f 1\nf 1 2 3\n", 4, "found 1"),
    ("index zero", V3 + "f 0 1 2\n", 4, "index 0"),
    ("index zero vt", V3 + "vt 0 0\nf 1/0 2/1 3/1\n", 5, "index 0"),
    ("out of range", V3 + "f 1 2 3\nf 1 2 4\n", 5, "vertex index 4 out of range: the file has 3"),
    ("negative past start", V3 + "f -1 -2 -4\n", 4, "reaches before the first one"),
    ("negative before later vertices", "v 0 0 0\nf -1 -2 -3\n" + V3, 2, "reaches before"),
    ("relative errors in corner order", V3 + "vt 0 0\nf 1/-2 -9/1 2/1\n", 5, "(vt) index -2 in '1/-2'"),
    ("vt missing", V3 + "f 1/1 2/1 3/1\n", 4, "texture coordinate (vt) index 1 out of range: the file has 0"),
    ("vn missing", V3 + "vn 0 0 1\nf 1//1 2//2 3//1\n", 5, "normal (vn) index 2 out of range"),
    ("mixed formats", V3 + "vt 0 0\nf 1/1 2 3/1\n", 5, "mixed corner formats"),
    ("trailing slash", V3 + "f 1/ 2/ 3/\n", 4, "bad face corner '1/'"),
    ("four parts", V3 + "f 1/1/1/1 2 3\n", 4, "bad face corner"),
    ("empty vertex", V3 + "vt 0 0\nf /1 /1 /1\n", 5, "bad face corner"),
    ("letters in a corner", V3 + "f 1 2 3x\n", 4, "'3x' is not an index"),
    ("double minus", V3 + "f --1 2 3\n", 4, "is not an index"),
    ("plus sign", V3 + "f +1 2 3\n", 4, "is not an index"),
    ("float index", V3 + "f 1.0 2 3\n", 4, "is not an index"),
    ("absurd index", V3 + "f 1 2 99999999999999999999\n", 4, "vertex index '99999999999999999999' out of range"),
    # Past a 32-bit index: 2**32 + 1 must not wrap round to vertex 1.
    ("index past 32 bits", V3 + "f 1 2 4294967297\n", 4,
     "vertex index '4294967297' out of range: more than a model holds (2147483647)"),
    ("vt past 32 bits", V3 + "vt 0 0\nf 1/1 2/1 3/2147483648\n", 5,
     "texture coordinate (vt) index '2147483648' out of range"),
    ("absurd negative", V3 + "f 1 2 -99999999999999999999\n", 4, "out of range"),
    ("5000 digits", V3 + "f 1 2 " + "9" * 5000 + "\n", 4, "out of range"),
    ("absurd vt", "vt 0 0\n" + V3 + "f 1/1 2/1 3/99999999999999999999\n", 5, "texture coordinate (vt) index"),
    # a long word is shown shortened, and how long it is said: 400 digits are not shown as 37 and '...'
    ("400 digits", V3 + "f 1 2 " + "9" * 400 + "\n", 4,
     f"vertex index '{'9' * 40}... (400 digits)' out of range: more than a model holds"),
    ("a long number", V3 + "v 1 " + "9" * 400 + " 3\nf 1 2 3\n", 4, f"'{'9' * 40}... (400 digits)' is not a finite"),
    ("a long word", V3 + "v 1 " + "x" * 100 + " 3\nf 1 2 3\n", 4, f"'{'x' * 40}... (100 characters)' is not a number"),
    ("a long corner", V3 + "f 1 2 3/" + "x" * 100 + "\n", 4,
     f"bad face corner '3/{'x' * 38}... (102 characters)': '{'x' * 40}... (100 characters)' is not an index"),
]


@pytest.mark.parametrize(("text", "line", "message"), [case[1:] for case in BAD_CASES],
                         ids=[case[0] for case in BAD_CASES])
def test_bad_input_names_the_file_and_line(text: str, line: int | None, message: str) -> None:
    with pytest.raises(LoadError) as caught:
        parse(text, source="dir/broken.obj")
    error = caught.value
    assert error.path == "dir/broken.obj"
    assert error.line == line
    assert message in error.message
    assert str(error).startswith("dir/broken.obj:" if line is None else f"dir/broken.obj:{line}:")


def test_line_numbers_count_physical_lines_across_crlf_comments_and_continuations() -> None:
    text = b"# one\r\nv 0 0 0\r\nv 1 0 \\\r\n 0\r\n\r\nv 0 1 0\r\n\tf 1 2 9\r\n"
    with pytest.raises(LoadError) as caught:
        parse(text)
    assert caught.value.line == 7


def test_windows_1252_comments_and_names_are_read(tmp_path: Path) -> None:
    """Windows exporters write their comments and names in Windows-1252: a usemtl name matches its newmtl."""
    (tmp_path / "w.mtl").write_bytes(b"# Erstellt am 01.M\xe4rz\nnewmtl Gr\xfcn\nKd 0 1 0\nnewmtl other\nKd 1 0 0\n")
    path = tmp_path / "w.obj"
    path.write_bytes(b"# File Created: 01.M\xe4rz.2020\nmtllib w.mtl\ng W\xfcrfel\nusemtl Gr\xfcn\n" + QUAD)
    mesh = load_obj(path)
    assert mesh.face_count == 1 and [material.name for material in mesh.materials] == ["Gr\u00fcn"]
    assert mesh.materials[0].values["kd"] == (0.0, 1.0, 0.0) and not mesh.warnings


@pytest.mark.parametrize("read", [read_by_lines, fast_reader.read_fast], ids=["line reader", "fast reader"])
@pytest.mark.parametrize(("line", "said"), [
    ("v 0 1 -1.#IND", "4: '-1.#IND' is not a finite number"), ("vn 0 0 1.#QNAN", "4: '1.#QNAN' is not a finite number"),
    ("vt 0.5 1.#INF00", "4: '1.#INF00' is not a finite number"), ("v 0 1 2#c", "4: '2#c' is not a number"),
    ("f 1 2 3#c", "4: bad face corner '3#c': '3#c' is not an index"),
])
def test_a_hash_inside_a_word_is_the_words_not_a_comment(read, line: str, said: str) -> None:
    """Old Windows programs wrote NaN as -1.#IND: cut at its '#', it was read as -1, without a word."""
    with pytest.raises(LoadError) as refused:
        read(f"{V3}{line}\nf 1 2 3\n".encode(), "w.obj")
    assert str(refused.value) == f"w.obj:{said}"
    kept = read(f"{V3}vn 0 0 1 # a comment\n\t# and one more\nf 1//1 2//1 3//1 #\n".encode(), "w.obj")
    assert kept.normals.tolist() == [[0, 0, 1]] and kept.face_start.tolist() == [0, 3]


@pytest.mark.parametrize("read", [read_by_lines, fast_reader.read_fast], ids=["line reader", "fast reader"])
def test_l_and_p_statements_beside_faces_are_said_to_be_undrawn(read) -> None:
    lines = read(f"{V3}l 1 2\np 3\nl 2 3\nf 1 2 3\n".encode(), "guides.obj")
    assert lines.notes == ["its l and p statements (lines and points) are not drawn"]
    assert read(f"{V3}lod 1\nf 1 2 3\n".encode(), "lod.obj").notes == []


@pytest.mark.parametrize("read", [read_by_lines, fast_reader.read_fast], ids=["line reader", "fast reader"])
def test_a_vt_of_one_number_has_v_0_as_the_format_says(read) -> None:
    """Wavefront's `vt u [v [w]]`: v and w default to 0 (one number was refused)."""
    text = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5\nvt 0.25 0.75\nvt 0.125 # u alone\nf 1/1 2/2 3/3\n"
    assert read(text, "u.obj").texcoords.tolist() == [[0.5, 0.0], [0.25, 0.75], [0.125, 0.0]]


@pytest.mark.parametrize("read", [read_by_lines, fast_reader.read_fast], ids=["line reader", "fast reader"])
def test_vertex_colours_after_the_position_are_read(read) -> None:
    """MeshLab writes `v x y z r g b`: the position and the colour are read; x y z w is no colour."""
    text = b"v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 0.5\nf 1 2 3\n"
    raw = read(text, "coloured.obj")
    assert raw.notes == []
    assert raw.positions.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]]
    assert raw.vertex_colours.tolist() == [[1, 0, 0], [0, 1, 0], [0, 0, 0.5]]
    assert read(b"v 0 0 0 1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "w.obj").vertex_colours is None


FORMS = "v reads x y z, x y z w or x y z r g b"


@pytest.mark.parametrize("read", [read_by_lines, fast_reader.read_fast], ids=["line reader", "fast reader"])
def test_a_v_line_of_5_or_7_numbers_is_read_as_the_form_before_it_with_a_note(read) -> None:
    """x y z w and x y z r g b are the forms past x y z: 5 numbers read as the first, 7 as the second,
    the last number ignored; one note counts them and names the first."""
    five = read(b"v 1 2 3 4 5\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "five.obj")
    assert five.notes == [f"ignored the last number of a v line of 5 or 7 numbers on line 1 ({FORMS})"]
    assert five.positions[0].tolist() == [1, 2, 3] and five.vertex_colours is None
    seven = read(b"v 0 0 0\n# x\nv 1 0 0 0.5 0.5 0.5 9\nv 0 1 0 1 2\nf 1 2 3\n", "seven.obj")
    assert seven.notes == [f"ignored the last number of 2 v lines of 5 or 7 numbers (the first on line 3; {FORMS})"]
    assert seven.vertex_colours[1].tolist() == [0.5, 0.5, 0.5]
    assert read(b"v 0 0 0 1\nv 1 0 0 1 0 0\nv 0 1 0\nf 1 2 3\n", "forms.obj").notes == []


@pytest.mark.parametrize("chunk", [8, 24, 64])
def test_v_lines_of_no_form_are_counted_across_pieces_and_lines_left_to_the_line_reader(chunk: int) -> None:
    """Each piece counts its own, and the line reader the lines left to it for their long numbers:
    the note sums them and names the file's first, whichever piece read it."""
    lines = [b"v 0 0 0"] * 20 + [b"v 0 0 0.1234567890123456789 1 2", b"v 1 2 3 4 5"] * 3
    text = b"\n".join([*lines, b"v 1 0 0 0.5 0.5 0.5 1", b"f 1 2 3"]) + b"\n"
    with small_chunks(chunk):
        both = read_both(text)
    assert_agree(both)
    said = f"ignored the last number of 7 v lines of 5 or 7 numbers (the first on line 21; {FORMS})"
    assert both.fast.notes == [said]


@pytest.mark.parametrize("read", [read_by_lines, fast_reader.read_fast], ids=["line reader", "fast reader"])
def test_zbrush_polypaint_gives_the_positions_colours_in_file_order(read) -> None:
    """ZBrush writes `#MRGB` lines of MMRRGGBB entries (a mask byte, then the colour), one per
    position, 64 to a line, each after its positions."""
    text = b"v 0 0 0\nv 1 0 0\n#MRGB 00ff0000ffFF8000\nv 0 1 0\n  #MRGB  ff0000ff \nf 1 2 3\n"
    raw = read(text, "painted.obj")
    assert raw.notes == []
    assert (raw.vertex_colours * 255).round().tolist() == [[255, 0, 0], [255, 128, 0], [0, 0, 255]]


@pytest.mark.parametrize("read", [read_by_lines, fast_reader.read_fast], ids=["line reader", "fast reader"])
@pytest.mark.parametrize(("paint", "colours", "note"), [
    (b"#MRGB ffff0000ff00ff00\n#MRGB ff0000f\n", None,
     "ignored the ZBrush polypaint (#MRGB): line 5 is malformed"),  # one entry short of a digit
    (b"#MRGB ffff0000ff00ff00\n#MRGB ff0000fg\n", None, "ignored the ZBrush polypaint (#MRGB): line 5 is malformed"),
    (b"#MRGBffff0000\n", None, "ignored the ZBrush polypaint (#MRGB): line 4 is malformed"),
    (b"#MRGB ffff0000ff00ff00ff0000ffff111111\n", [[255, 0, 0], [0, 255, 0], [0, 0, 255]],
     "1 ZBrush polypaint (#MRGB) colours past the last position ignored"),
    (b"#MRGB ffff0000\n", [[255, 0, 0], [None] * 3, [None] * 3], None),  # the rest are drawn white
])
def test_zbrush_polypaint_that_does_not_fit_is_said(read, paint: bytes, colours: list | None, note: str | None) -> None:
    raw = read(V3.encode() + paint + b"f 1 2 3\n", "painted.obj")
    assert raw.notes == ([note] if note else [])
    if colours is None:
        assert raw.vertex_colours is None
    else:
        got = np.where(np.isnan(raw.vertex_colours), -1, raw.vertex_colours * 255).round()
        assert got.tolist() == [[-1 if value is None else value for value in row] for row in colours]


def test_v_line_colours_win_over_zbrush_polypaint(tmp_path: Path) -> None:
    path = tmp_path / "both.obj"
    path.write_bytes(b"v 0 0 0 0 1 0\nv 1 0 0 0 1 0\nv 0 1 0 0 1 0\n#MRGB ffff0000ffff0000ffff0000\nf 1 2 3\n")
    mesh = load_obj(path)
    assert mesh.vertex_colours.tolist() == [[0, 255, 0]] * 3
    assert list(mesh.warnings) == ["the v lines' colours are drawn, not the ZBrush polypaint (#MRGB)"]


def test_a_large_files_polypaint_comes_through_the_compiled_reader(tmp_path: Path) -> None:
    """Every byte value of every channel comes back exactly, 64 entries a line, past
    COMPILED_READER_BYTES (so read by the compiled reader, in several pieces)."""
    rows = obj_module.COMPILED_READER_BYTES // 20
    colours = np.random.default_rng(7).integers(0, 256, size=(rows, 3))
    lines = []
    for block in range(0, rows, 64):
        lines += [f"v {i} {i % 5} 0" for i in range(block, min(rows, block + 64))]
        lines.append("#MRGB " + "".join(f"ff{r:02x}{g:02x}{b:02x}" for r, g, b in colours[block:block + 64].tolist()))
    lines += [f"f {i + 1} {i + 2} {i + 3}" for i in range(0, rows - 2, 3)]
    path = tmp_path / "painted.obj"
    path.write_text("\n".join(lines) + "\n")
    assert path.stat().st_size > obj_module.COMPILED_READER_BYTES
    mesh = load_obj(path)
    assert not [note for note in mesh.warnings if "MRGB" in note] and np.array_equal(mesh.vertex_colours, colours)


@pytest.mark.parametrize(("lines", "colours", "notes"), [
    (b"v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 0.5\n", [[255, 0, 0], [0, 255, 0], [0, 0, 128]], []),
    (b"v 0 0 0 255 0 0\nv 1 0 0 0 255 0\nv 0 1 0 0 0 128\n", [[255, 0, 0], [0, 255, 0], [0, 0, 128]], []),
    (b"v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0 1\n", [[255, 0, 0], [255, 255, 255], [255, 255, 255]],
     ["2 positions without a colour drawn white"]),
    (b"v 0 0 0 1 0 0\nv 1 0 0 0 -1 0\nv 0 1 0 0 0 1\n", [[255, 0, 0], [0, 0, 0], [0, 0, 255]],
     ["1 vertex colour outside 0..1 (or 0..255) held to it"]),
    (b"v 0 0 0 300 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\n", [[255, 0, 0], [0, 1, 0], [0, 0, 1]],
     ["1 vertex colour outside 0..1 (or 0..255) held to it"]),
    # A float colour a little past 1 (Blender's, made sRGB) is no 0..255 one: the others stay as they are.
    (b"v 0 0 0 1.0001 0.5 0.5\nv 1 0 0 0.5 0.5 0.5\nv 0 1 0 -0.0001 0.2 0.1\n",
     [[255, 128, 128], [128, 128, 128], [0, 51, 26]], ["2 vertex colours outside 0..1 (or 0..255) held to it"]),
    (b"v 0 0 0 127.5 0 0\nv 1 0 0 0 255 0\nv 0 1 0 0 0 64\n", [[128, 0, 0], [0, 255, 0], [0, 0, 64]], []),
])
def test_vertex_colours_are_drawn_as_0_to_1_or_0_to_255(tmp_path: Path, lines: bytes, colours: list | None,
                                                        notes: list[str]) -> None:
    path = tmp_path / "coloured.obj"
    path.write_bytes(lines + b"f 1 2 3\n")
    mesh = load_obj(path)
    assert (mesh.vertex_colours is None) == (colours is None)
    if colours is not None:
        assert mesh.vertex_colours.tolist() == colours
    assert list(mesh.warnings) == notes


def test_a_large_files_vertex_colours_come_through_the_compiled_reader(tmp_path: Path) -> None:
    """Past COMPILED_READER_BYTES the third, compiled pass reads them; a line it leaves to the line
    reader (a number it does not read: 17 digits) still gives its colour."""
    rows = obj_module.COMPILED_READER_BYTES // 40
    rng = np.random.default_rng(5)
    colours = rng.integers(0, 256, size=(rows, 3))
    lines = [f"v {i} {i % 7} 0 {r} {g} {b}" for i, (r, g, b) in enumerate(colours.tolist())]
    lines[1234] = "v 1234.0000000000000001 6 0 1 2 3"  # the line reader's: the compiled reader reads 15 digits
    colours[1234] = (1, 2, 3)
    faces = [f"f {i + 1} {i + 2} {i + 3}" for i in range(rows - 2)]
    path = tmp_path / "large.obj"
    path.write_text("\n".join(lines + faces) + "\n")
    assert path.stat().st_size > obj_module.COMPILED_READER_BYTES
    with lines_read_by_python() as counted:
        mesh = load_obj(path)
    assert counted.lines == 1
    assert mesh.vertex_colours.tolist() == colours.tolist()


def test_a_stray_byte_in_a_number_is_that_lines_error() -> None:
    with pytest.raises(LoadError) as caught:
        parse(b"v 0 0 0\nv 1 0 0\nv 0 1\xff 0\nf 1 2 3\n")
    assert caught.value.line == 3


def test_utf8_comments_and_names_are_fine() -> None:
    assert parse("# Ã±andÃº modelo\no ontzia_Ã±\n".encode() + QUAD).face_count == 1


def test_missing_file_and_directory(tmp_path: Path) -> None:
    with pytest.raises(LoadError, match="no such file") as caught:
        load_obj(tmp_path / "nothing.obj")
    assert caught.value.line is None
    with pytest.raises(LoadError, match="directory"):
        load_obj(tmp_path)


def test_devices_pipes_and_huge_files_are_refused_without_reading(tmp_path: Path) -> None:
    if Path("/dev/zero").exists():
        with pytest.raises(LoadError, match="not a regular file"):
            load_obj("/dev/zero")  # would never end
    if hasattr(os, "mkfifo"):
        pipe = tmp_path / "pipe.obj"
        os.mkfifo(pipe)
        outcome: list[object] = []
        reader = threading.Thread(target=lambda: outcome.append(_error_of(load_obj, pipe)), daemon=True)
        reader.start()
        reader.join(timeout=5)  # opening a pipe would block until someone writes
        assert outcome and "not a regular file" in str(outcome[0])
    path = tmp_path / "big.obj"
    path.write_bytes(QUAD)
    with pytest.raises(LoadError, match="too large"):
        read_file(path, limit=10)


def _error_of(loader: Callable[[Path], object], path: Path) -> object:
    try:
        return loader(path)
    except LoadError as error:
        return error


@pytest.mark.skipif(os.name != "posix" or os.geteuid() == 0, reason="root reads every file")
def test_unreadable_file(tmp_path: Path) -> None:
    path = tmp_path / "secret.obj"
    path.write_bytes(QUAD)
    path.chmod(0)
    with pytest.raises(LoadError, match="permission"):
        load_obj(path)


# --- the two readers agree -------------------------------------------------------------------------


class Both(NamedTuple):
    fast: RawObj | LoadError | None  # None: the file continues lines, which only the line reader reads
    slow: RawObj | LoadError
    fast_lines: int  # lines the fast reader handed to the line reader


def read_both(text: bytes) -> Both:
    """What the fast reader gives (its tables or its error), what the line reader alone gives, and how
    many lines the fast reader had the line reader read."""
    normalized = obj_text.checked(obj_text.ended(text), "x.obj")
    fast: RawObj | LoadError | None = None
    with lines_read_by_python() as counted:
        if not obj_text.has_continuations(normalized):
            fast = outcome(lambda: fast_reader.read_fast(normalized, "x.obj"))
    return Both(fast, outcome(lambda: read_by_lines(normalized, "x.obj")), counted.lines)


def outcome(read: Callable[[], RawObj]) -> RawObj | LoadError:
    try:
        return read()
    except LoadError as error:
        return error


def assert_agree(both: Both) -> None:
    """The fast reader gives the line reader's tables, or its very error: message and line."""
    if both.fast is None:
        return
    if isinstance(both.slow, LoadError):
        assert isinstance(both.fast, LoadError), f"fast reader accepted what the line reader rejects: {both.slow}"
        assert (both.fast.message, both.fast.line) == (both.slow.message, both.slow.line)
    else:
        assert not isinstance(both.fast, LoadError), f"fast reader rejected what the line reader accepts: {both.fast}"
        assert_same_tables(both.fast, both.slow)


def assert_same_tables(fast: object, slow: object) -> None:
    for name in ("positions", "texcoords", "normals", "corner_vertex", "corner_texcoord", "corner_normal",
                 "face_start"):
        a, b = getattr(fast, name), getattr(slow, name)
        assert (a is None) == (b is None), name
        if a is not None:
            assert a.shape == b.shape and np.array_equal(a, b), name
    for name in ("mtllib", "colour", "notes"):
        assert getattr(fast, name) == getattr(slow, name), name
    colours = [getattr(tables, "vertex_colours") for tables in (fast, slow)]
    assert (colours[0] is None) == (colours[1] is None)
    if colours[0] is not None:
        assert np.array_equal(colours[0], colours[1], equal_nan=True)


NUMBER = st.one_of(
    st.integers(-10**6, 10**6).map(str),
    st.floats(-1e6, 1e6, allow_nan=False).map(lambda x: f"{x:.6f}"),
    st.floats(-1e6, 1e6, allow_nan=False).map(repr),
    st.sampled_from(["-0", ".5", "5.", "-.5", "1e3", "+2", "1E-2", "0.1234567890123456789", "007"]),
    # either side of the plain numbers' border (lines.py), read without a check
    st.sampled_from(["9" * 29 + ".5e9", "9" * 30, "1e+09", "1e+10", "2E+00000009", "1e-400", "-0.5e-09"]),
)
SPACE = st.sampled_from([" ", " ", " ", "  ", "\t", " \t"])
END = st.sampled_from(["\n", "\n", "\n", "\r\n", " \n", "\n\n", "\n# note\n", " # trailing\n", "\r", "#\\\n"])
EXTRAS = ["o thing", "s 1", "g a b", "# colour 10 20 30", "#colour 1 2", "usemtl x", "vp 1", "# c",
          "mtllib a b.mtl", "  # indented comment", "cstype bezier", "# exported from C:\\models\\", "\r", " ",
          "#MRGB ffff0000ff00ff00", " #MRGB ff0000ff", "#MRGB ff00ff", "#MRGBff000000", "#MRGB ff0000ff # c"]
BROKEN_LINES = ["v 1 2", "v 1 nan 3", "v 1 2 3x", "v 1.2.3 0 0", "vt 1", "vn 0 1", "f 1 2", "f 0 1 2",
                "f 1 2 99", "f -99 1 2", "f 1/1 2 3", "f 1// 2// 3//", "f 1/2/3/4 1 2", "f a b c", "v 1 - 2",
                "v 1 2 3 # trailing", "f 1 2 \\\n 3"]


def table_lines(draw: st.DrawFn, keyword: str, count: int, widths: list[int]) -> list[str]:
    return [keyword + "".join(draw(SPACE) + draw(NUMBER) for _ in range(draw(st.sampled_from(widths))))
            for _ in range(count)]


@st.composite
def obj_texts(draw: st.DrawFn) -> bytes:
    """Valid OBJ text in many spellings, a third of it with one broken or unusual line."""
    counts = {"v": draw(st.integers(3, 8)), "vt": draw(st.integers(0, 4)), "vn": draw(st.integers(0, 4))}
    lines = table_lines(draw, "v", counts["v"], [3, 3, 3, 4, 5, 6, 7])
    lines += table_lines(draw, "vt", counts["vt"], [2, 2, 3]) + table_lines(draw, "vn", counts["vn"], [3])
    shapes = ["{v}"] + ["{v}/{t}"] * bool(counts["vt"]) + ["{v}//{n}"] * bool(counts["vn"])
    shapes += ["{v}/{t}/{n}"] * bool(counts["vt"] and counts["vn"])
    file_shape = draw(st.sampled_from(shapes))

    def index(table: str) -> int:
        size = max(counts[table], 1)
        return draw(st.one_of(st.integers(1, size), st.integers(-size, -1)))

    for _ in range(draw(st.integers(1, 4))):
        shape = draw(st.sampled_from([file_shape] * 6 + shapes))  # now and then formats differ by face
        corners = [shape.format(v=index("v"), t=index("vt"), n=index("vn"))
                   for _ in range(draw(st.sampled_from([3, 3, 4, 5, 6])))]
        lines.append(draw(st.sampled_from(["f", "f", "\tf"])) + "".join(draw(SPACE) + c for c in corners))
    for extra in draw(st.lists(st.sampled_from(EXTRAS), max_size=3)):
        lines.insert(draw(st.integers(0, len(lines))), extra)
    if draw(st.integers(0, 2)) == 0:
        lines.insert(draw(st.integers(0, len(lines))), draw(st.sampled_from(BROKEN_LINES)))
    return "".join(line + draw(END) for line in lines).encode()


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(obj_texts())
def test_the_fast_reader_agrees_with_the_line_reader(text: bytes) -> None:
    assert_agree(read_both(text))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(obj_texts())
def test_the_line_reader_reads_alike_in_batches_of_any_size(text: bytes) -> None:
    """A whole file's plain lines are kept and read a batch at a time: however many lines or bytes a
    batch holds, the tables, or the error and its line, are the same."""
    text = obj_text.checked(obj_text.ended(text), "x.obj")
    outcomes = []
    for lines, size in ((lines_module._BATCHED_LINES, lines_module._BATCHED_BYTES), (1, 1 << 20), (2, 1 << 20),
                        (1 << 12, 16)):
        with pytest.MonkeyPatch.context() as patch:
            patch.setattr(lines_module, "_BATCHED_LINES", lines)
            patch.setattr(lines_module, "_BATCHED_BYTES", size)
            outcomes.append(outcome(lambda: read_by_lines(text, "x.obj")))
    first = outcomes[0]
    for other in outcomes[1:]:
        if isinstance(first, LoadError):
            assert isinstance(other, LoadError) and (other.message, other.line) == (first.message, first.line)
        else:
            assert_same_tables(other, first)


def test_an_error_after_batches_of_plain_lines_names_its_own_line() -> None:
    plain = b"v 1 2 3\nvt 0.5 0.5\nvn 0 0 1\nf 1/1/1 1/1/1 1/1/1\n" * (lines_module._BATCHED_LINES + 5)
    error = outcome(lambda: read_by_lines(plain + b"v 1 2 3e39\nf 1 2\n", "x.obj"))
    assert isinstance(error, LoadError) and error.line == plain.count(b"\n") + 1 and "too large" in error.message


# Bytes the text checks judge (a NUL, a CR, a backslash, a no-break space), and others beside them.
LOOKED_AT = st.sampled_from(["\0", "\r", "\r\n", "\\", "\\\n", "\u00a0", "\u00e9", "\u00a9", "\xa0", "\t"])


def with_inserted(text: bytes, insertions: list[tuple[int, str]]) -> bytes:
    for where, inserted in insertions:
        at = where % (len(text) + 1)
        text = text[:at] + inserted.encode() + text[at:]
    return text


# Every kind of line pass one reads, with blanks and a comment.
EVERY_LINE = b"v 1 2 3\n vt 0.5 1\nvn 0 0 1 # n\n\tf 1/1/1 2/1/1 3/1/1\ng part\n# colour 1 2 3\n\nusemtl a\n"


def test_the_compiled_passes_refuse_a_text_that_does_not_end_a_line() -> None:
    """They stop at newlines: given a text without its last one (a test inserting a byte after it
    did), they read past its end, and one run in many crashed."""
    with pytest.raises(ValueError, match="ended text"):
        fast_reader.count_text(b"v 1 2 3\nf 1 1 1")
    with pytest.raises(ValueError, match="ended text"):
        fast_reader.count_text(b"")


@pytest.mark.parametrize("inserted", ["\0", "\r", "\\", "\u00a0"])
def test_pass_one_notes_a_byte_the_text_checks_judge_wherever_it_is(inserted: str) -> None:
    """The compiled path runs the text checks only where pass one says so, so it must say so for
    each of their bytes at each byte offset of every kind of line."""
    assert not fast_reader.count_text(EVERY_LINE).to_look_at
    for at in range(len(EVERY_LINE)):
        assert fast_reader.count_text(EVERY_LINE[:at] + inserted.encode() + EVERY_LINE[at:]).to_look_at, at


def test_the_word_scan_for_those_bytes_sees_each_at_any_alignment_and_bounds() -> None:
    """It reads aligned eight-byte words between bytewise ends: each byte it looks for, or one next to
    them in value, at every place of a short text at every alignment, with every low and high bound."""
    plain = np.frombuffer(b"v 0.5 1/2 # \x7f\x80\xc3\n" * 2, np.uint8)
    for byte in (0x00, 0x0D, 0x5C, 0xC2, 0x01, 0x0C, 0x5D, 0xC1, 0xFF):
        for alignment in range(8):
            room = np.zeros(len(plain) + 16, np.uint8)
            text = room[alignment:alignment + len(plain)]
            for at in range(len(plain)):
                text[:] = plain
                text[at] = byte
                read_only = fast_reader._read_only_bytes(text)  # as the reader passes it: one machine code
                for low in range(0, at + 1, 5):
                    for high in range(at, len(text) + 1, 3):
                        looked_at = byte in (0x00, 0x0D, 0x5C, 0xC2) and low <= at < high
                        assert scan.holds_bytes_to_look_at(read_only, low, high) == looked_at, (byte, at, low, high)


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(obj_texts(), st.lists(st.tuples(st.integers(0, 10**6), LOOKED_AT), max_size=3))
def test_the_compiled_path_gives_what_the_checked_line_reader_gives(text: bytes,
                                                                    insertions: list[tuple[int, str]]) -> None:
    """A NUL, a lone CR, a continuation or a no-break space anywhere: the tables, or the very error."""
    text = with_inserted(text, insertions)
    fast_reader.read_fast(QUAD, "warm.obj")  # the compiled reader loaded: small texts take its path
    compiled = outcome(lambda: obj_module._tables(obj_text.ended(text), "x.obj"))  # as the loader hands it on
    by_lines = outcome(lambda: read_by_lines(obj_text.checked(obj_text.ended(text), "x.obj"), "x.obj"))
    if isinstance(by_lines, LoadError) or isinstance(compiled, LoadError):
        assert isinstance(compiled, LoadError) and isinstance(by_lines, LoadError), (compiled, by_lines)
        assert (compiled.message, compiled.line) == (by_lines.message, by_lines.line)
    else:
        assert_same_tables(compiled, by_lines)


@pytest.mark.parametrize("edit", ["none", "CRLF", "a lone CR", "a NUL", "a no-break space", "a continuation",
                                  "a backslash in a comment"])
def test_a_large_text_is_checked_only_where_pass_one_says(edit: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Over the compiled reader's size: the checks run for the texts that hold what they judge, and
    the outcome is the line reader's on the checked text."""
    rows = obj_module.COMPILED_READER_BYTES // 12
    plain = b"".join(b"v %d 0 %d\n" % (row, row % 7) for row in range(1, rows + 1)) + b"f 1 2 3\nf -1 -2 -3\n"
    text = {"none": plain, "CRLF": plain.replace(b"\n", b"\r\n"), "a lone CR": plain.replace(b"\n", b"\r", 5),
            "a NUL": plain[:-12] + b"\0" + plain[-12:], "a no-break space": plain.replace(b"v ", "v\u00a0".encode(), 3),
            "a continuation": plain + b"f 1 \\\n 2 3\n",
            "a backslash in a comment": b"# C:\\models\\\n" + plain}[edit]
    assert len(text) > obj_module.COMPILED_READER_BYTES
    checks: list[bytes] = []
    real_checked = obj_module.checked
    monkeypatch.setattr(obj_module, "checked", lambda text, source: checks.append(text) or real_checked(text, source))
    compiled = outcome(lambda: obj_module._tables(text, "x.obj"))
    by_lines = outcome(lambda: read_by_lines(real_checked(text, "x.obj"), "x.obj"))
    assert len(checks) == (edit != "none")
    if edit == "a NUL":
        assert isinstance(compiled, LoadError) and isinstance(by_lines, LoadError)
        assert (compiled.message, compiled.line) == (by_lines.message, by_lines.line) == (
            "binary data (a NUL byte), not an OBJ text file", rows + 1)
    else:
        assert_same_tables(compiled, by_lines)
        assert compiled.corner_vertex.size == 6 + 3 * (edit == "a continuation")


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(obj_texts())
def test_parse_obj_returns_a_finite_mesh_or_raises_load_error(text: bytes) -> None:
    try:
        mesh = parse(text)
    except LoadError as error:
        assert error.path == "model.obj"
        return
    assert_finite(mesh)
    assert_mesh_dtypes(mesh)
    assert mesh.corner_vertex.max() < mesh.vertex_count


@settings(max_examples=200, deadline=None)
@given(st.binary(max_size=200))
def test_random_bytes_never_raise_anything_but_load_error(data: bytes) -> None:
    try:
        parse(data)
    except LoadError:
        pass


@contextmanager
def small_chunks(chunk_bytes: int = 64, threads: int = 8) -> Iterator[None]:
    """The fast reader's pieces made tiny and its threads several, so that small texts are cut into
    several pieces parsed at once, as megabyte files are."""
    saved = fast_reader.MIN_PIECE_BYTES, fast_reader.PARSE_THREADS
    fast_reader.MIN_PIECE_BYTES, fast_reader.PARSE_THREADS = chunk_bytes, threads
    try:
        yield
    finally:
        fast_reader.MIN_PIECE_BYTES, fast_reader.PARSE_THREADS = saved


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(obj_texts(), st.sampled_from([8, 24, 64]))
def test_the_fast_reader_agrees_with_the_line_reader_across_chunks_and_threads(text: bytes, chunk: int) -> None:
    with small_chunks(chunk):
        assert_agree(read_both(text))


def big_generated_text() -> bytes:
    rng = np.random.default_rng(7)
    side = 40
    points = rng.normal(size=(side * side, 3))
    def row(keyword: str, values, digits: int) -> str:
        return keyword + "".join(f" {value:.{digits}f}" for value in values)

    def face(indices) -> str:
        return "f " + " ".join(f"{i}/{i}/{i}" for i in indices)

    lines = [row("v", point, 6) for point in points]
    lines += [row("vt", uv, 4) for uv in rng.random((side * side, 2))]
    lines += [row("vn", point, 5) for point in points]
    for grid_row in range(side - 1):
        for col in range(side - 1):
            a = grid_row * side + col + 1
            lines.append(face((a, a + 1, a + side + 1)))
            lines.append(face(index - side * side - 1 for index in (a, a + side + 1, a + side)))  # -1: the last
    return ("\n".join(lines) + "\n").encode()


def test_big_generated_file_takes_the_fast_path_and_matches_the_line_reader() -> None:
    text = big_generated_text()
    both = read_both(text)
    assert both.fast_lines == 0
    assert_agree(both)
    with small_chunks(1000):
        chunked = read_both(text)
    assert chunked.fast_lines == 0
    assert_agree(chunked)


@pytest.mark.parametrize("where", [0.02, 0.5, 0.98])
def test_a_bad_line_in_any_chunk_is_found_with_its_line(where: float) -> None:
    """Each thread checks its own chunks: a fault in a late one must still reach the line reader."""
    lines = big_generated_text().split(b"\n")
    faces = [number for number, line in enumerate(lines) if line.startswith(b"f ")]
    bad = faces[int(where * (len(faces) - 1))]
    lines[bad] = lines[bad].replace(b"/", b"/x", 1)
    with small_chunks(1000), pytest.raises(LoadError) as error:
        parse(b"\n".join(lines))
    assert error.value.line == bad + 1


# --- build_mesh -------------------------------------------------------------------------------------


def test_build_mesh_derives_like_the_loader() -> None:
    built = build_mesh("quad", [[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]])
    loaded = parse(QUAD)
    for name in ("positions", "corner_vertex", "corner_uv", "corner_normal", "face_start", "face_normals"):
        np.testing.assert_array_equal(getattr(built, name), getattr(loaded, name))
    assert built.name == "quad"


def test_build_mesh_takes_per_corner_uv_and_normals_with_nan_meaning_derive() -> None:
    mesh = build_mesh("t", np.eye(3), np.array([[0, 1, 2]]),
                      uvs=[[0.1, 0.2], [np.nan, np.nan], [0.3, 0.4]],
                      normals=[[0, 0, 5], [np.nan, 0, 0], [1, 0, 0]],
                      base_colour=(1.0, 0.5, 0.0), warnings=["made in code"])
    np.testing.assert_allclose(mesh.corner_uv[[0, 2]], [[0.1, 0.2], [0.3, 0.4]])
    assert np.isfinite(mesh.corner_uv).all()
    np.testing.assert_allclose(mesh.corner_normal[0], [0, 0, 1])
    np.testing.assert_allclose(mesh.corner_normal[1], np.ones(3) / np.sqrt(3), rtol=1e-6)
    assert mesh.base_colour == (1.0, 0.5, 0.0) and mesh.warnings == ("made in code",)


@pytest.mark.parametrize("faces", [[[0, 1]], [], [[0, 1, 7]], [[0, -1, 2]]])
def test_build_mesh_rejects_impossible_faces(faces: list[list[int]]) -> None:
    with pytest.raises(ValueError):
        build_mesh("bad", np.eye(3), faces)


def test_build_mesh_refuses_more_than_32_bit_indices_hold(monkeypatch: pytest.MonkeyPatch) -> None:
    from marraztu.model import build

    built = build_mesh("quad", np.eye(4, 3), [[0, 1, 2, 3]])
    assert built.corner_vertex.dtype == built.face_start.dtype == np.int32
    monkeypatch.setattr(build, "INDEX_LIMIT", 4)  # 2**31 - 1 corners would not fit in this test
    with pytest.raises(ValueError, match="fewer than 4 positions and corners"):
        build_mesh("quad", np.eye(4, 3), [[0, 1, 2, 3]])


# --- the seed's models ------------------------------------------------------------------------------


@pytest.mark.parametrize(("name", "vertices", "faces"), SEED_MODELS)
def test_seed_models_load_with_their_counts(name: str, vertices: int, faces: int) -> None:
    mesh = load_obj(seed_model(name))
    assert (mesh.vertex_count, mesh.face_count) == (vertices, faces)
    assert_finite(mesh)
    assert_mesh_dtypes(mesh)
    np.testing.assert_allclose(np.linalg.norm(mesh.corner_normal, axis=1), 1, atol=1e-5)


@pytest.mark.parametrize("name", [name for name, _, _ in SEED_MODELS])
def test_seed_models_take_the_fast_path(name: str) -> None:
    both = read_both(seed_model(name).read_bytes())
    assert both.fast_lines == 0, name
    assert_agree(both)


def test_rammer_has_quads_texture_coordinates_and_normals() -> None:
    mesh = load_obj(seed_model("rammer_225.obj"))
    assert set(np.unique(mesh.face_sizes).tolist()) == {3, 4}
    assert "Rammer 225.mtl" in mesh.warnings[0]  # the seed ships no MTL
    assert mesh.corner_uv.min() >= 0 and mesh.corner_uv.max() <= 1
    raw = read_both(seed_model("rammer_225.obj").read_bytes()).fast  # the file's own vt and vn, not derived
    assert isinstance(raw, RawObj)
    assert (raw.corner_texcoord >= 0).all() and (raw.corner_normal >= 0).all()


def test_cam_has_its_colour_comment() -> None:
    mesh = load_obj(seed_model("cam.obj"))
    assert mesh.base_colour == pytest.approx((100 / 255, 0.0, 1.0))


# --- the compiled reader's own reading of numbers and indices -----------------------------------------

# (token, whether the compiled reader reads it itself): what it leaves goes to the line reader.
NUMBER_TOKENS = [
    ("1e22", True), ("1e23", False), ("1.5e-21", True), ("1.5e-22", False), ("1e-23", False), ("123456789012345", True),
    ("1234567890123456", False), ("0.000000000000001", True), ("0000000000000000001.5", True),
    ("1.e5", True), ("-0", True), ("+.5", True), ("5.", True), (".5", True), ("-.5e+2", True),
    ("1e-400", False), ("3.4028234663852886e38", False), ("3.4e38", False), ("3.5e38", False), ("-2.5e21", True),
    ("1e99999999999", False), ("0.1234567890123456789", False), ("0.30000000000000004", False),
    ("1e", False), ("e5", False), ("1e+", False), ("--1", False), ("+-1", False), ("1.2.3", False),
    ("0x10", False), ("nan", False), ("-inf", False), ("1_0", False), (".", False), ("-", False),
    ("1,5", False), ("1#5", False), ("1/2", False),
]


@pytest.mark.parametrize("token, compiled", NUMBER_TOKENS)
def test_a_number_reads_as_float_reads_it_or_goes_to_the_line_reader(token: str, compiled: bool) -> None:
    text = f"v {token} 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n".encode()
    both = read_both(text)
    assert_agree(both)
    assert both.fast_lines == (0 if compiled else 1), token
    if isinstance(both.fast, RawObj):  # -0 stays -0: the GPU would see the sign
        assert np.signbit(both.fast.positions[0, 0]) == np.signbit(both.slow.positions[0, 0])


LONG_NUMBER = st.one_of(st.floats(-1e30, 1e30, allow_nan=False).map(repr), st.floats(allow_nan=False).map(repr),
                        st.sampled_from(["1e23", "1e-23", "0.1234567890123456789", "-0.0", "1e0", "9" * 29 + "e9",
                                         "9" * 30, "1e+10", "nan", "1x", "+.5e-400"]))


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(["", " ", "\t", "\x0b ", "\r"]), st.sampled_from(["v", "vt", "vn", "f", "V"]),
       st.sampled_from([" ", "\t", "\x0c", ""]), st.lists(st.one_of(LONG_NUMBER, NUMBER), min_size=2, max_size=3),
       st.sampled_from(["", " ", "\r", " # c", "#"]))
def test_a_deferred_line_read_whole_reads_as_the_line_reader_reads_it(start: str, keyword: str, space: str,
                                                                     numbers: list[str], end: str) -> None:
    """A deferred line the fast reader takes as a plain row (lines.PLAIN_ROW_RUNS, the line with its
    newline) gives the line reader's values, and no error."""
    content = (start + keyword + space + " ".join(numbers) + end).encode()
    for kind, pattern in enumerate(lines_module.PLAIN_ROW_RUNS):
        if pattern.match(content + b"\n").end() == 0:
            continue
        reader = lines_module.LineReader("x.obj")
        reader.read_line(1, content)
        table = np.zeros((1, TABLE_WIDTHS[kind]))
        assert fast_reader.read_plain_batch(np.frombuffer(content + b"\n", np.uint8), kind,
                                            record_of_line(kind, len(content)), table).tolist() == [0]
        assert np.array_equal(np.frombuffer(reader.tables[kind], np.float64), table[0])
        assert np.array_equal(np.signbit(np.frombuffer(reader.tables[kind], np.float64)), np.signbit(table[0]))


def record_of_line(kind: int, length: int) -> np.ndarray:
    """The compiled pass's record of a line of `length` bytes at the text's start, of table `kind`, row 0."""
    record = np.zeros((1, scan.RECORD_COLUMNS), np.int64)
    record[0, scan.R_KEYWORD], record[0, scan.R_END] = kind, length
    return record


# Lines whose numbers run on into the next line's if a newline were taken for a blank between numbers.
NUMBERS = st.lists(st.one_of(LONG_NUMBER, NUMBER), min_size=1, max_size=4).map(" ".join)
RUN_ON_LINES = st.lists(st.one_of(
    st.tuples(st.sampled_from(["v", "vt", "vn", " v", "v\t"]), NUMBERS).map(" ".join), NUMBERS,
    st.sampled_from(["", "# a comment", "\t", "f 1 1 1", "vt", "v 0.5 0.25 1 # c"])), min_size=1, max_size=12)


@settings(max_examples=300, deadline=None)
@given(RUN_ON_LINES)
def test_deferred_rows_are_read_line_by_line_whatever_follows_them(lines: list[str]) -> None:
    """A run of plain rows read at once ends at each line's newline: a row short of numbers is the line
    reader's error even when the next line holds numbers alone."""
    assert_agree(read_both(("\n".join(lines) + "\nf 1 1 1\n").encode()))


def test_a_row_short_of_numbers_is_not_finished_by_the_next_line() -> None:
    both = read_both(b"v 0.10000000000000001 2\n3\nf 1 1 1\n")
    assert_agree(both)
    assert isinstance(both.fast, LoadError) and both.fast.line == 1


@pytest.mark.parametrize("at_once", [1, 3, 1 << 12])
def test_rows_left_for_their_long_numbers_are_read_in_batches_into_their_rows(at_once: int,
                                                                             monkeypatch: pytest.MonkeyPatch) -> None:
    """The compiled code leaves numbers of more than 15 digits to Python; the plain rows among those
    lines are read a batch at a time into the rows they fill, the others one at a time, all as the line
    reader reads them."""
    monkeypatch.setattr(fast_reader, "_PLAIN_ROWS_AT_ONCE", at_once)
    rng = np.random.default_rng(47)
    lines = []
    for row in range(300):
        x, y, z = (rng.normal(size=3) * 100).tolist()
        lines.append(rng.choice([f"v {x!r} {y!r} {z!r}", f"v {x:.3f} {y:.3f} {z:.3f}", f"v {x!r} {y} {z} 0.5 0.25 1",
                                 f"  v\t{x!r} {y!r} {z!r}  ", f"v {x!r} {y!r} {z!r} # a comment", f"vt {x!r} {y!r}",
                                 f"vn {x!r} {y!r} {z!r}", f"vt {x!r} {y!r} 0"]))
    lines += [f"f {row + 1} {row + 2} {row + 3}" for row in range(100)]
    both = read_both(("\n".join(lines) + "\n").encode())
    assert_agree(both)
    assert isinstance(both.fast, RawObj) and both.fast_lines > 150


@settings(max_examples=300, deadline=None)
@given(st.floats(-3e38, 3e38, allow_nan=False),
       st.sampled_from(["{!r}", "{:.17g}", "{:.6f}", "{:.9g}", "{:.6e}", "{:.15e}", "{:.3E}", "{:.0f}"]))
def test_numbers_in_every_spelling_read_as_float_reads_them(value: float, spelling: str) -> None:
    token = spelling.format(value)
    raw = fast_reader.read_fast(f"v {token} {token} 0\nf 1 1 1\n".encode(), "x.obj")
    expected = float(token)
    assert raw.positions[0, 0] == expected and np.signbit(raw.positions[0, 0]) == np.signbit(expected), token


@pytest.mark.parametrize("corner", ["-1", "01", "1//", "1/2/", "+1", "1/-1/1", "999999999999999", "1234567890123456",
                                    "1/", "/1", "1//1/", "-4", "0", "1/0", "-0", "1 1/1", "2147483647", "2147483648",
                                    "4294967297", "1/4294967297/1", "-2147483648"])
def test_a_face_corner_reads_as_the_line_reader_reads_it(corner: str) -> None:
    text = f"v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf {corner} 2 3\nf 1/1/1 2/1/1 3/1/1\n".encode()
    assert_agree(read_both(text))


COLOUR_COMMENTS = ["# colour 255 0 51", "#colour 1 2 3", " \t# \tcolor 1 2 3 ", "# colour 1 2", "# colour 1 2 3 4",
                   "# colour red 0 0", "# colour 1 2 3#", "# colour 1 2 #3", "# colour 1_0 2 3", "# colour 1e400 0 0",
                   "# colour inf 0 0", "# colour nan 1 2", "# colour .5 5. -0", "# colour 1e3 +2 1E-2",
                   "# colour 0.1234567890123456789 1 1", "# Colour 1 2 3", "# colourful 1 2 3", "# colouur 1 2 3",
                   "# colo r 1 2 3", "# colour\t1\x0b2\x0c3", "# the colour 1 2 3", "# colour", "#", "# c"]


@pytest.mark.parametrize("first", COLOUR_COMMENTS)
@pytest.mark.parametrize("second", ["# colour 10 20 30", "# colour x y z"])
def test_a_colour_comment_reads_as_the_line_reader_reads_it(first: str, second: str) -> None:
    """The compiled code records only comments of the colour's shape, and none after one that sets the
    colour; the colour and the notes about malformed ones must come out as the line reader's."""
    text = f"{first}\nv 0 0 0\nv 1 0 0\n{second}\n{first}\nv 0 1 0\nf 1 2 3\n".encode()
    both = read_both(text)
    assert_agree(both)
    assert both.fast_lines == 0


def test_random_colour_comments_read_as_the_line_reader_reads_them() -> None:
    rng = np.random.default_rng(11)
    words = ["#", "# ", "colour", "color", "colou", " ", "\t", "1", "2.5", "-3", "x", "1e9", "e", ".", "#", "255", "u"]
    for _ in range(3000):
        comments = ["".join(rng.choice(words, size=int(rng.integers(1, 9)))) for _ in range(3)]
        text = ("\n".join(f"#{comment}" for comment in comments) + "\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").encode()
        assert_agree(read_both(text))


def test_a_process_reading_only_small_files_never_imports_numba() -> None:
    """The built-in scene's models are read by the line reader: the screenshot and the window's start
    never pay numba's start-up, nor numpy.ma's (np.unique's first call imports it: 6 ms)."""
    # numpy before 2.0 imports numpy.ma with itself: only an import that the read adds counts.
    code = ("import sys, numpy; numpys_own = 'numpy.ma' in sys.modules; "
            "from marraztu.loaders.scenefile import load_builtin_scene; load_builtin_scene(); "
            "print('numba' in sys.modules, 'numpy.ma' in sys.modules and not numpys_own)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "False False"


def test_files_and_bytes_share_one_machine_code_of_each_compiled_pass(tmp_path: Path) -> None:
    """numba compiles and loads machine code per array type: a file read into an array and bytes
    given to parse_obj must take the same, or a process holds (and a fresh install compiles) two."""
    path = tmp_path / "big.obj"
    path.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\n" + b"f 1 2 3\n" * (obj_module.COMPILED_READER_BYTES // 8))
    code = ("import sys; from marraztu.loaders.obj import load_obj, parse_obj, scan; "
            f"load_obj({str(path)!r}); parse_obj(b'v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nf 1 2 3\\n' * 2, 'b.obj'); "
            "print([len(f.signatures) for f in (scan.count_piece, scan.read_piece, scan.line_end)])")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[1, 1, 1]"


# In a fresh process: loads the file at argv[1]; prints its faces, whether the compiled reader was
# loaded on the loading thread, whether that thread was alive as the bytes were read, and whether
# the compiled reader is loaded in the end.
_FIRST_LARGE_FILE = """
import sys, threading
import marraztu.loaders.obj as obj, marraztu.loaders.obj.text as text
alive, read_into, ran_on, load = [], text._read_into, [], obj._load_compiled_reader
def spy_read(*args):
    alive.append(obj._LOADING_THREAD in [thread.name for thread in threading.enumerate()])
    return read_into(*args)
def spy_load(*args):
    ran_on.append(threading.current_thread().name)
    load(*args)
text._read_into, obj._load_compiled_reader = spy_read, spy_load
mesh = obj.load_obj(sys.argv[1])
print(mesh.face_count, ran_on == [obj._LOADING_THREAD], alive[0], obj._compiled_reader_loaded())
"""


def _first_large_file(path: Path, numba: bool) -> list[str]:
    prelude = "" if numba else "import sys; sys.modules['numba'] = None\n"  # numba cannot be imported
    done = subprocess.run([sys.executable, "-c", prelude + _FIRST_LARGE_FILE, str(path)],
                          capture_output=True, text=True, check=True)
    assert done.stderr == ""  # the loading thread's failure too is quiet
    return done.stdout.split()


@pytest.mark.parametrize("numba", [True, False])
def test_a_first_large_file_is_read_while_the_compiled_reader_loads(tmp_path: Path, numba: bool) -> None:
    """numba's import and the passes' machine code load on another thread while the file is read;
    without numba (the thread's import fails at once) the file is read by lines all the same."""
    path = tmp_path / "big.obj"
    faces = obj_module.COMPILED_READER_BYTES // 8
    path.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\n" + b"f 1 2 3\n" * faces)
    count, on_the_thread, alive_while_read, loaded = _first_large_file(path, numba)
    assert (count, on_the_thread, loaded) == (str(faces), "True", str(numba))
    if numba:  # it takes a tenth of a second or more: still at work when the read begins
        assert alive_while_read == "True"


def test_a_file_read_while_another_thread_imports_the_compiled_reader(tmp_path: Path,
                                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    """While a first large file's loading thread imported fast.py, a file loaded on another thread (two
    viewers in two threads) found the module in sys.modules with none of its functions yet: "could not
    read the model (AttributeError: partially initialized module ...)". An import under way is no
    loaded reader."""
    monkeypatch.setitem(sys.modules, "marraztu.loaders.obj.fast", ModuleType("marraztu.loaders.obj.fast"))
    path = tmp_path / "small.obj"
    path.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    assert load_obj(path).face_count == 1


def _compiling_for_as_long_as_it_takes(monkeypatch: pytest.MonkeyPatch, cached: bool) -> threading.Event:
    """The first large file's loading thread, as after an install (`cached` False: numba's cache lacks the
    passes) where compiling lasts until the load has said so (the returned event), or 10 s at most."""
    said = threading.Event()
    monkeypatch.setattr(obj_module, "_compiled_reader_loaded", lambda: False)
    monkeypatch.setattr(scan, "machine_code_cached", lambda: cached)
    monkeypatch.setattr(fast_reader, "load_machine_code", lambda: cached or said.wait(timeout=10))
    return said


@pytest.mark.parametrize("cached", [False, True])
def test_a_first_large_file_says_numba_compiles_the_reader_once_where_it_does(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, cached: bool) -> None:
    """The first large file after installing waited seconds for numba's compiling while the window's
    status line said "parsing" and the screenshot command said nothing."""
    path = tmp_path / "big.obj"
    path.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\n" + b"f 1 2 3\n" * (obj_module.COMPILED_READER_BYTES // 8))
    said = _compiling_for_as_long_as_it_takes(monkeypatch, cached)
    stages: list[str] = []

    def stage(words: str) -> None:
        stages.append(words)
        if words == obj_module.READER_COMPILING:
            said.set()

    load_obj(path, stage)
    expected = ["reading", "parsing"] if cached else ["reading", "parsing", obj_module.READER_COMPILING, "parsing"]
    assert stages == expected


def test_the_screenshot_command_tells_numba_compiles_the_reader(tmp_path: Path, monkeypatch) -> None:
    from marraztu.control.viewer import StartOptions, Viewer
    from marraztu.loaders.scenefile import empty_scene
    from support.scenes import Notices

    path = tmp_path / "big.obj"
    path.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\n" + b"f 1 2 3\n" * (obj_module.COMPILED_READER_BYTES // 8))
    said = _compiling_for_as_long_as_it_takes(monkeypatch, cached=False)
    front = Notices(heard=lambda text: said.set() if text == obj_module.READER_COMPILING else None)
    Viewer(empty_scene(), front, strict=True).start(StartOptions(empty=True, models=(path,)), longest_texture_side=256)
    assert front.told == [obj_module.READER_COMPILING]


def test_the_screenshot_command_tells_it_for_a_scene_files_model(tmp_path: Path, monkeypatch, capsys) -> None:
    """A scene file's large OBJ (--scene) was read with no stage heard: numba compiled for seconds in silence."""
    from marraztu.control.viewer import StartOptions
    from marraztu.frontends.screenshot import take_screenshot

    path = tmp_path / "big.obj"
    path.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\n" + b"f 1 2 3\n" * (obj_module.COMPILED_READER_BYTES // 8))
    (tmp_path / "scene.toml").write_text('[[objects]]\nmodel = "big.obj"\n')
    said = _compiling_for_as_long_as_it_takes(monkeypatch, cached=False)
    monkeypatch.setattr(sys, "stderr", _SaysWhenTold(sys.stderr, obj_module.READER_COMPILING, said))
    take_screenshot(StartOptions(scene_file=tmp_path / "scene.toml"), tmp_path / "shot.png", (16, 16))
    assert said.is_set()


class _SaysWhenTold:
    """stderr, setting `said` once `words` are written to it."""

    def __init__(self, stream, words: str, said: threading.Event) -> None:
        self.stream, self.words, self.said = stream, words, said

    def write(self, text: str) -> int:
        if self.words in text:
            self.said.set()
        return self.stream.write(text)

    def flush(self) -> None:
        self.stream.flush()


def test_numba_is_asked_whether_its_cache_holds_a_functions_machine_code(tmp_path: Path, monkeypatch) -> None:
    from marraztu.model import jit

    monkeypatch.setattr(jit, "_cache_folder", lambda: tmp_path)
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    monkeypatch.setattr(jit.config, "CACHE_DIR", "")

    def twice(x: int) -> int:
        return 2 * x

    compiled = jit.njit(cache=True)(twice)
    assert jit.has_cached_code(compiled) is False
    assert compiled(21) == 42  # compiled, and cached
    assert jit.has_cached_code(compiled) is True
    assert jit.has_cached_code(jit.njit(cache=True)(twice)) is True  # as a fresh process finds it
    assert jit.has_cached_code(twice) is None, "not numba's: it cannot be asked"
    assert scan.machine_code_cached() in (True, False)


def test_a_large_file_that_cannot_be_opened_waits_for_no_compiled_reader(tmp_path: Path) -> None:
    path = tmp_path / "big.obj"
    path.write_bytes(b"v 0 0 0\n" * (obj_module.COMPILED_READER_BYTES // 8 + 1))
    code = ("import sys, marraztu.loaders.obj as obj, marraztu.loaders.obj.text as text\n"
            "def refuse(*args, **kwargs):\n    raise PermissionError(13, 'Permission denied')\n"
            "text.open = refuse  # as for a file this user may not read\n"
            "try:\n    obj.load_obj(sys.argv[1])\nexcept obj.LoadError as error:\n    print(error)\n"
            "print('numba' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code, str(path)], capture_output=True, text=True, check=True)
    assert done.stdout.splitlines() == [f"{path}: permission denied", "False"]


def test_once_the_compiled_reader_is_loaded_it_reads_small_files_too(monkeypatch: pytest.MonkeyPatch) -> None:
    read: list[str] = []

    def spy(text: bytes, source: str, counted: fast_reader.Counted | None = None) -> RawObj:
        read.append(source)
        return read_by_lines(text, source)

    fast_reader.read_fast(QUAD, "warm.obj")  # as a large file would have, first
    assert fast_reader.machine_code_loaded()
    monkeypatch.setattr(fast_reader, "read_fast", spy)
    parse(QUAD, "small.obj")
    assert read == ["small.obj"]


def test_utf16_text_is_named_as_such(tmp_path: Path) -> None:
    """Notepad's "Unicode" and PowerShell's Out-File write UTF-16, which was refused as binary data."""
    path = tmp_path / "notepad.obj"
    path.write_bytes("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n".encode("utf-16"))
    with pytest.raises(LoadError) as refused:
        load_obj(path)
    assert (refused.value.message, refused.value.line) == ("UTF-16 text, not an OBJ text file: save it as UTF-8", 1)


def test_a_hash_inside_a_word_does_not_stop_a_line_continuing() -> None:
    text = f"{V3}usemtl Wood#2 \\\n oak\nf 1 2 3\nusemtl W # c \\\nf 1 2 3\n".encode()
    fast_reader.read_fast(QUAD, "warm.obj")
    assert obj_module._tables(text, "x.obj").material_runs.names == ["Wood#2 oak", "W # c \\"]
    assert read_by_lines(obj_module.checked(text, "x.obj"), "x.obj").material_runs.names == ["Wood#2 oak", "W # c \\"]


@pytest.mark.parametrize("line", [b"\n", b"# a comment\n", b"f -3 -2 -1\n", b"g part\n"])
def test_a_small_file_of_lines_read_one_at_a_time_goes_on_in_the_compiled_reader(monkeypatch, line: bytes) -> None:
    """The line reader reads these one at a time, 2 to 40 microseconds each: a 7.9 MB file of blank
    lines or comments took 7.7 s to load in a fresh process, one of relative faces (7.5 MB) 10 s; past
    LINE_READER_SINGLE_LINES of them the compiled reader reads the file (1.2, 1.0 and 1.9 s)."""
    monkeypatch.setattr(obj_module, "_compiled_reader_loaded", lambda: False)
    monkeypatch.setattr(obj_module, "LINE_READER_SINGLE_LINES", 100)
    fast_reader.read_fast(QUAD, "warm.obj")  # numba's machine code, loaded before the lines are counted
    text = V3.encode() + line * 1000 + b"f 1 2 3\n"
    with lines_read_by_python() as counted:
        raw = obj_module._tables(text, "x.obj")
    assert counted.lines <= 102
    assert_same_tables(raw, read_by_lines(text, "x.obj"))


def test_long_face_lines_go_to_the_compiled_reader_however_small_the_file(monkeypatch) -> None:
    """The line reader reads a face longer than its batches a word at a time: a 6 MB file of
    100-corner faces (CAD's n-gons) took 9 s through it, under a second through the compiled one."""
    monkeypatch.setattr(obj_module, "_compiled_reader_loaded", lambda: False)
    corners = " ".join(["1 2 3 4"] * 50)  # 400 bytes a line
    long_faces = (f"f {corners}\n" * (obj_module.COMPILED_READER_LONG_LINE_BYTES // len(corners) + 1)).encode()
    short_faces = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n" + b"f 1 2 3 4\n" * (len(long_faces) // 10)
    assert obj_module._prefers_compiled_reader(long_faces)
    assert not obj_module._prefers_compiled_reader(short_faces)
    assert not obj_module._prefers_compiled_reader(long_faces[:len(long_faces) // 2])
