"""PLY: the header read here, an ASCII body made the binary one it stands for (marraztu.loaders.ply), and
the model trimesh makes of it, checked against trimesh's own reading and at the line of a problem."""

from __future__ import annotations

import random
import struct
from pathlib import Path

import numpy as np
import pytest
import trimesh

from marraztu.errors import LoadError
from marraztu.loaders import ply
from marraztu.loaders.ply import binary_of_ascii, read_header, vertices_and_faces
from marraztu.loaders.registry import load_model
from support.refusals import one_line_refusal, written
from support.work import peak_traced_bytes

GRID = [f"{x} {y} {(x * y) % 3 * 0.1:.1f}" for y in range(3) for x in range(3)]  # 3 x 3 vertices
ANY_TRIANGLES = 1 << 62  # no limit on what the faces make, for the readers called alone


def ply_text(faces: list[str], vertices: list[str] = GRID, face_properties: str = "property list uchar int "
             "vertex_indices\n", vertex_properties: str = "property float x\nproperty float y\nproperty float z\n",
             remarks: str = "") -> str:
    return (f"ply\nformat ascii 1.0\n{remarks}element vertex {len(vertices)}\n{vertex_properties}"
            f"element face {len(faces)}\n{face_properties}end_header\n" + "\n".join(vertices + faces) + "\n")


def load(tmp_path: Path, text: str, name: str = "m.ply"):
    return load_model(written(tmp_path, text, name))


def refusal(tmp_path: Path, text: str) -> LoadError:
    return one_line_refusal(lambda: load(tmp_path, text))


@pytest.mark.parametrize("seed", range(3))
def test_an_exported_ascii_ply_gives_what_trimesh_reads_of_it(tmp_path: Path, seed: int) -> None:
    rng = np.random.default_rng(seed)
    mesh = trimesh.creation.icosphere(subdivisions=2)
    mesh.vertices += rng.normal(size=mesh.vertices.shape) * 0.01
    mesh.visual.vertex_colors = rng.integers(0, 256, size=(len(mesh.vertices), 4), dtype=np.uint8)
    path = tmp_path / "a.ply"
    path.write_bytes(trimesh.exchange.ply.export_ply(mesh, encoding="ascii"))
    ours, theirs = load_model(path), trimesh.load(path, process=False)
    np.testing.assert_array_equal(ours.positions, theirs.vertices)
    np.testing.assert_array_equal(ours.corner_vertex.reshape(-1, 3), theirs.faces)
    np.testing.assert_array_equal(ours.vertex_colours, theirs.visual.vertex_colors[:, :3])


def test_blank_lines_and_rows_split_over_lines_read_as_the_numbers_they_hold(tmp_path: Path) -> None:
    """PLY's body is numbers in order: trimesh's reader, a line at a time, could read neither."""
    text = ply_text(["3 0 1 4", "3 0 4 3"])
    plain = load(tmp_path, text, "plain.ply")
    header, body = text.split("end_header\n")
    rows = body.splitlines()
    spread = "\n\n".join(" ".join(rows[:4]).split()) + "\n\n\n" + " ".join(rows[4:8]) + "\n"
    spread += "\n".join(rows[8:]) + "\n\n"
    loose = load(tmp_path, header + "end_header\n" + spread, "loose.ply")
    np.testing.assert_array_equal(loose.positions, plain.positions)
    np.testing.assert_array_equal(loose.corner_vertex, plain.corner_vertex)


def test_rows_of_a_line_each_that_shift_are_refused_though_the_counts_balance(tmp_path: Path) -> None:
    """A row of a number too many and a later one of a number too few moved every vertex between
    them, without a word: the count of numbers came out right."""
    vertices = list(GRID)
    vertices[2] += " 7"
    vertices[5] = vertices[5].rsplit(" ", 1)[0]
    assert str(refusal(tmp_path, ply_text(["3 0 1 4", "3 0 4 3"], vertices))).endswith(
        "m.ply:12: line 12 holds 4 numbers where a vertex row of these properties holds 3, so the rows after it no "
        "longer begin lines (line 12: vertex row 4 does not begin its line, as the rows before it do)")
    said = str(refusal(tmp_path, ply_text(["3 0 1 4 3 1", "3 1 4 2"])))  # face 2 read as (1, 3, 1)
    assert said.endswith("m.ply:19: line 19 holds 6 numbers where a face row of these properties holds 4, so the "
                         "rows after it no longer begin lines (line 20: 2 numbers after the rows the header "
                         "counts)"), said
    packed = ply_text(["3 0 1 4 3 0 4 3"]).replace("element face 1", "element face 2")
    assert load(tmp_path, packed).face_count == 2  # rows never one a line: PLY's body is numbers in order


def test_polygons_are_kept_as_the_file_gives_them(tmp_path: Path) -> None:
    """trimesh makes triangles of every face: they are fanned here first, in the file's order, and made
    polygons again of trimesh's triangles, as an OBJ or OFF file's polygons are kept."""
    faces = [[0, 1, 4, 3], [1, 2, 5], [3, 4, 7, 6, 3], [4, 5, 8, 7]]
    mesh = load(tmp_path, ply_text([f"{len(face)} {' '.join(map(str, face))}" for face in faces]))
    obj = load(tmp_path, "".join(f"v {row}\n" for row in GRID) + "".join(
        "f " + " ".join(str(index + 1) for index in face) + "\n" for face in faces), "m.obj")
    assert mesh.corner_vertex.tolist() == [index for face in faces for index in face]
    assert mesh.face_start.tolist() == [0, 4, 7, 12, 16]
    for name in ("corner_vertex", "face_start"):
        np.testing.assert_array_equal(getattr(mesh, name), getattr(obj, name), err_msg=name)
    for name in ("positions", "face_normals", "corner_normal", "corner_uv"):  # a PLY's floats are 32-bit
        np.testing.assert_allclose(getattr(mesh, name), getattr(obj, name), atol=1e-6, err_msg=name)


def test_uniform_quads_are_kept_too(tmp_path: Path) -> None:
    """A file of quads alone, which trimesh's reader would make triangles of in an order of its own."""
    faces = [[0, 1, 4, 3], [1, 2, 5, 4], [3, 4, 7, 6], [4, 5, 8, 7]]
    for name, data in written_both_ways(faces).items():
        (tmp_path / name).write_bytes(data)
        mesh = load_model(tmp_path / name)
        assert mesh.corner_vertex.tolist() == [index for face in faces for index in face], name
        assert mesh.face_start.tolist() == [0, 4, 8, 12, 16], name


@pytest.mark.parametrize(("index", "said"), [("1.5", "1.5 is not a whole number"), ("nan", "nan is not a whole number"),
                                             ("12.0", "12 out of range (the file has 9 vertices)")])
@pytest.mark.parametrize("encoding", ["ascii", "binary_little_endian"])
def test_an_index_list_of_floats_names_vertices_by_whole_numbers(tmp_path: Path, index: str, said: str,
                                                                 encoding: str) -> None:
    """A face list may be declared of floats: 1.5 or NaN names no vertex (trimesh cast them without a
    word, NaN to -2**63)."""
    faces = [[0, 1, 4, 3], [1, 2, 5, float(index)]]
    text = ply_text([" ".join(f"{value:g}" for value in [len(face), *face]) for face in faces],
                    face_properties="property list uchar float vertex_indices\n")
    if encoding == "ascii":
        data = text.encode()
    else:
        header = text[:text.index("end_header\n") + 11].replace("format ascii", "format binary_little_endian")
        data = header.encode() + np.array(GRID_NUMBERS, "<f4").tobytes() + b"".join(
            struct.pack("<B4f", 4, *face) for face in faces)
    (tmp_path / "m.ply").write_bytes(data)
    refused = one_line_refusal(lambda: load_model(tmp_path / "m.ply"))
    assert refused.message == f"vertex index {said}"
    assert refused.line == (20 if encoding == "ascii" else None)


def test_an_empty_second_face_element_leaves_the_polygons_kept(tmp_path: Path) -> None:
    """trimesh reads one face element: an empty one beside it is left out before trimesh sees it."""
    text = ply_text(["4 0 1 4 3", "5 1 2 5 8 4"]).replace(
        "end_header", "element face 0\nproperty list uchar int vertex_indices\nend_header")
    assert load(tmp_path, text).face_sizes.tolist() == [4, 5]


def test_a_face_elements_one_list_of_another_name_is_its_corners(tmp_path: Path) -> None:
    """trimesh reads the one list of a face element as its corners, whatever its name: its polygons were
    not fanned (mixed corners were no faces at all) and its corners not checked."""
    foo = "property list uchar int foo\n"
    assert load(tmp_path, ply_text(["4 0 1 4 3", "3 1 2 5"], face_properties=foo)).face_sizes.tolist() == [4, 3]
    refused = refusal(tmp_path, ply_text(["3 0 1 4", "2 1 2"], face_properties=foo))
    assert (refused.line, refused.message) == (20, "a face of 2 corners: 3 or more make one")


def written_both_ways(faces: list[list[int]]) -> dict[str, bytes]:
    """The grid with these faces as an ASCII PLY and a binary one."""
    text = ply_text([f"{len(face)} {' '.join(map(str, face))}" for face in faces])
    header = text[:text.index("end_header\n") + 11].replace("format ascii", "format binary_little_endian")
    binary = header.encode() + np.array(GRID_NUMBERS, "<f4").tobytes() + b"".join(
        struct.pack(f"<B{len(face)}i", len(face), *face) for face in faces)
    return {"ascii.ply": text.encode(), "binary.ply": binary}


def written_as_strips(strips: list[list[int]], encoding: str) -> bytes:
    """The grid with these rows of a tristrips element (scanalyze's and VCG's), in place of faces."""
    rows = [f"{len(strip)} {' '.join(map(str, strip))}" for strip in strips]
    text = ply_text(rows).replace("element face", "element tristrips")
    if encoding == "ascii":
        return text.encode()
    header = text[:text.index("end_header\n") + 11].replace("format ascii", "format binary_little_endian")
    return header.encode() + np.array(GRID_NUMBERS, "<f4").tobytes() + b"".join(
        struct.pack(f"<B{len(strip)}i", len(strip), *strip) for strip in strips)


@pytest.mark.parametrize("encoding", ["ascii", "binary_little_endian"])
def test_triangle_strips_are_drawn_as_their_triangles(tmp_path: Path, encoding: str) -> None:
    """Each index after a strip's second makes a triangle of the two before it, every second one turned
    so that all face +z as the grid's quads
    do; -1 and a row's end start a new strip, and the
    triangles that repeat a vertex (a join between strips) are none."""
    strips = [[3, 0, 4, 1, 5, 2, 2, 6, 6, 3, 7, 4, 8, 5], [0, 1, -1, 3, 4, 6]]
    (tmp_path / "m.ply").write_bytes(written_as_strips(strips, encoding))
    mesh = load_model(tmp_path / "m.ply")
    assert mesh.corner_vertex.reshape(-1, 3).tolist() == [
        [3, 0, 4], [4, 0, 1], [4, 1, 5], [5, 1, 2], [6, 3, 7], [7, 3, 4], [7, 4, 8], [8, 4, 5], [3, 4, 6]]
    assert (mesh.face_normals[:, 2] > 0.9).all()  # the grid rises a little in z


@pytest.mark.parametrize(("encoding", "line"), [("ascii", 20), ("binary_little_endian", None)])
def test_a_strip_index_that_names_no_vertex_is_refused_at_its_line(tmp_path: Path, encoding: str,
                                                                   line: int | None) -> None:
    (tmp_path / "m.ply").write_bytes(written_as_strips([[0, 1, 3], [4, -2, 5]], encoding))
    refused = one_line_refusal(lambda: load_model(tmp_path / "m.ply"))
    assert (refused.line, refused.message) == (line, "vertex index -2 out of range (the file has 9 vertices)")


def faces_and_strips(faces: list[str], strips: list[list[int]], encoding: str, face_properties: str = "property "
                     "list uchar int vertex_indices\n", strips_first: bool = False) -> bytes:
    """The grid with these face rows (as ply_text's) and a tristrips element of these rows after them
    (before them in the header and body where `strips_first`)."""
    strip_rows = [f"{len(strip)} {' '.join(map(str, strip))}" for strip in strips]
    strip_header = f"element tristrips {len(strips)}\nproperty list uchar int vertex_indices\n"
    text = ply_text(faces, face_properties=face_properties)
    head, body = text.split("end_header\n")
    if strips_first:
        head = head.replace("element face", strip_header + "element face")
    else:
        head += strip_header
    rows = body.splitlines()
    rows = rows[:len(GRID)] + (strip_rows + rows[len(GRID):] if strips_first else rows[len(GRID):] + strip_rows)
    if encoding == "ascii":
        return (head + "end_header\n" + "\n".join(rows) + "\n").encode()
    binary = b"".join(struct.pack(f"<B{len(row.split()) - 1}i", *map(int, row.split())) for row in rows[len(GRID):])
    return (head.replace("format ascii", "format binary_little_endian") + "end_header\n").encode() + np.array(
        GRID_NUMBERS, "<f4").tobytes() + binary


@pytest.mark.parametrize("strips_first", [False, True])
@pytest.mark.parametrize("encoding", ["ascii", "binary_little_endian"])
def test_strips_beside_faces_are_drawn_after_them(tmp_path: Path, encoding: str, strips_first: bool) -> None:
    """A file of faces and strips: its faces, which keep their numbers, then the strips' triangles (the
    strips were left out, without a word)."""
    data = faces_and_strips(["4 0 1 4 3", "3 1 2 5"], [[7, 4, 8, 5], [6, 3, 7, 4]], encoding,
                            strips_first=strips_first)
    (tmp_path / "m.ply").write_bytes(data)
    mesh = load_model(tmp_path / "m.ply")
    assert mesh.face_sizes.tolist() == [4, 3, 3, 3, 3, 3]
    assert mesh.corner_vertex.tolist() == [0, 1, 4, 3, 1, 2, 5, 7, 4, 8, 8, 4, 5, 6, 3, 7, 7, 3, 4]
    assert (mesh.face_normals[:, 2] > 0.9).all() and not mesh.warnings


@pytest.mark.parametrize("encoding", ["ascii", "binary_little_endian"])
def test_strips_beside_triangles_name_vertices_past_the_faces_index_type(tmp_path: Path, encoding: str) -> None:
    """Faces of uchar indices beside strips that name vertex 299: the appended triangles' indices
    are not cut to a byte. Each strip index is checked as where the file has no faces."""
    vertices = [f"{i % 20} {i // 20} 0" for i in range(300)]
    faces = "property list uchar uchar vertex_indices\n"
    text = ply_text(["3 0 1 20"], vertices=vertices, face_properties=faces).replace(
        "end_header", "element tristrips 1\nproperty list uchar int vertex_indices\nend_header") + "3 278 279 298\n"
    if encoding != "ascii":
        head = text[:text.index("end_header\n") + 11].replace("format ascii", "format binary_little_endian")
        numbers = np.array([row.split() for row in vertices], float)
        text = head.encode() + numbers.astype("<f4").tobytes() + bytes([3, 0, 1, 20]) + struct.pack(
            "<B3i", 3, 278, 279, 298)
    (tmp_path / "m.ply").write_bytes(text.encode() if isinstance(text, str) else text)
    assert load_model(tmp_path / "m.ply").corner_vertex.tolist() == [0, 1, 20, 278, 279, 298]
    (tmp_path / "bad.ply").write_bytes(faces_and_strips(["3 0 1 4"], [[0, 1, 9]], encoding))
    refused = one_line_refusal(lambda: load_model(tmp_path / "bad.ply"))
    assert refused.message == "vertex index 9 out of range (the file has 9 vertices)"


def test_strips_beside_coloured_faces_keep_the_colours_rows(tmp_path: Path) -> None:
    """A face's own values (its colour) stay its own: the strips' triangles come after every face."""
    properties = ("property list uchar int vertex_indices\nproperty uchar red\nproperty uchar green\n"
                  "property uchar blue\n")
    data = faces_and_strips(["4 0 1 4 3 255 0 0", "3 1 2 5 0 255 0"], [[7, 4, 8, 5]], "ascii", properties)
    (tmp_path / "m.ply").write_bytes(data)
    mesh = load_model(tmp_path / "m.ply")
    assert mesh.face_sizes.tolist() == [4, 3, 3, 3]
    assert mesh.corner_vertex.tolist() == [0, 1, 4, 3, 1, 2, 5, 7, 4, 8, 8, 4, 5]
    assert any("per face" in note for note in mesh.warnings)


def test_strips_beside_faces_of_corner_texture_coordinates_are_a_note(tmp_path: Path) -> None:
    """Faces with MeshLab's texture coordinates per corner: a strip has none to give its triangles, so
    they are not drawn, and a note says so; the faces keep theirs."""
    properties = "property list uchar int vertex_indices\nproperty list uchar float texcoord\n"
    data = faces_and_strips(["3 0 1 4 6 0 0 0.5 0 0.5 0.5"], [[4, 7, 5, 8]], "ascii", properties)
    (tmp_path / "m.ply").write_bytes(data)
    mesh = load_model(tmp_path / "m.ply")
    np.testing.assert_allclose(mesh.positions[mesh.corner_vertex], [[0, 0, 0], [1, 0, 0], [1, 1, 0.1]], atol=1e-6)
    assert mesh.corner_uv.tolist() == [[0, 0], [0.5, 0], [0.5, 0.5]]
    assert mesh.warnings == ("2 triangles of its triangle strips not drawn: its faces give texture coordinates per "
                             "corner, which strips do not",)


def test_mixed_faces_keep_their_corners_texture_coordinates(tmp_path: Path) -> None:
    """MeshLab writes a face's u v per corner in a second list: each polygon's corners keep theirs, as
    an OBJ's vt per corner gives them."""
    uv = {0: (0.0, 0.0), 1: (0.5, 0.0), 4: (0.5, 0.5), 3: (0.0, 0.5), 2: (1.0, 0.0), 5: (1.0, 0.5)}
    faces = [[0, 1, 4, 3], [1, 2, 5]]
    rows = [f"{len(f)} {' '.join(map(str, f))} {2 * len(f)} {' '.join(f'{c:g}' for v in f for c in uv[v])}"
            for f in faces]
    properties = "property list uchar int vertex_indices\nproperty list uchar float texcoord\n"
    mesh = load(tmp_path, ply_text(rows, face_properties=properties))
    assert mesh.face_sizes.tolist() == [4, 3]
    assert mesh.corner_uv.tolist() == [list(uv[v]) for face in faces for v in face]
    np.testing.assert_allclose(mesh.positions[mesh.corner_vertex],
                               np.array([GRID[v].split() for face in faces for v in face], float), atol=1e-6)


@pytest.mark.parametrize(("faces", "line", "message"), [
    (["3 0 1 4", "3 0 x 3"], 20, "'x' is not a number"),
    (["3 0 1 4", "3 0 1.5 3"], 20, "face vertex_indices: 1.5 is no int (whole numbers from -2147483648 to 2147483647)"),
    (["3 0 1 4", "3 0 9 3"], 20, "vertex index 9 out of range (the file has 9 vertices)"),
    (["3 0 1 4", "3 0 -1 3"], 20, "vertex index -1 out of range (the file has 9 vertices)"),
    (["3 0 1 4", "2 0 1"], 20, "a face of 2 corners: 3 or more make one"),
    (["3 0 1 4", "300 0 1"], 20, "face vertex_indices: 300 is no uchar count (whole numbers from 0 to 255)"),
    (["3 0 1 4", "3 0 1"], 20, "the header counts 2 rows of face, the file ends before them"),
    (["3 0 1 4"], 19, "the header counts 2 rows of face, the file ends before them"),
])
def test_a_bad_body_is_refused_at_its_line(tmp_path: Path, faces: list[str], line: int, message: str) -> None:
    text = ply_text(faces)
    if len(faces) == 1:
        text = text.replace("element face 1", "element face 2")
    refused = refusal(tmp_path, text)
    assert (refused.line, refused.message) == (line, message)


NINES = "9" * 400  # float64 reads it as inf
SHOWN_NINES = "9" * 40 + "... (400 digits)"


@pytest.mark.parametrize(("faces", "vertex_properties", "vertices", "message"), [
    ([f"3 0 1 {NINES}"], None, None, f"face vertex_indices: {SHOWN_NINES} is no int (whole numbers from -2147483648 to "
                                     "2147483647)"),
    ([f"3 0 1 -{NINES}"], None, None, f"face vertex_indices: -{SHOWN_NINES[:39]}... (400 digits) is no int (whole "
                                      "numbers from -2147483648 to 2147483647)"),
    ([f"{NINES} 0 1 2"], None, None, f"face vertex_indices: {SHOWN_NINES} is no uchar count (whole numbers from 0 to "
                                     "255)"),
    (["3 0 1 123456789012345678901234"], None, None, "face vertex_indices: 123456789012345678901234 is no int "
                                                     "(whole numbers from -2147483648 to 2147483647)"),
    (["3 0 1 " + "1234567890" * 5], None, None, "face vertex_indices: " + "1234567890" * 4 + "... (50 digits) is no "
                                                "int (whole numbers from -2147483648 to 2147483647)"),
    (["3 0 1 2"], "property float x\nproperty float y\nproperty float z\nproperty uchar red\n",
     [f"{row} {NINES if at == 8 else 0}" for at, row in enumerate(GRID)],
     f"vertex red: {SHOWN_NINES} is no uchar (whole numbers from 0 to 255)"),
])
def test_a_huge_number_is_shown_as_written_not_as_inf(tmp_path: Path, faces: list[str], vertex_properties: str | None,
                                                      vertices: list[str] | None, message: str) -> None:
    """float64 reads 400 nines as inf, and 24 digits as 1.2345678901234569e+23: the message said those."""
    text = ply_text(faces, vertices=vertices or GRID, **({"vertex_properties": vertex_properties}
                                                          if vertex_properties else {}))
    refused = refusal(tmp_path, text)
    assert (refused.line, refused.message) == (19, message)  # the face's line, or the last vertex's


LONG_NAME = "n" * 50
SHOWN_NAME = "n" * 40 + "... (50 characters)"
GRID_ROWS = [f"{row} 0" for row in GRID]


@pytest.mark.parametrize(("vertex_property", "vertices", "more", "line", "message"), [
    (f"property uchar {LONG_NAME}", [*GRID_ROWS[:8], f"{GRID[8]} 300"], "", 19,
     f"vertex {SHOWN_NAME}: 300 is no uchar (whole numbers from 0 to 255)"),
    (f"property list uchar int {LONG_NAME}", [*GRID_ROWS[:8], f"{GRID[8]} 300"], "", 19,
     f"vertex {SHOWN_NAME}: 300 is no uchar count (whole numbers from 0 to 255)"),
    ("", GRID, f"element {LONG_NAME} 2\nproperty float a\n", 22,
     f"the header counts 2 rows of {SHOWN_NAME}, the file ends before them"),
])
def test_a_long_element_or_property_name_is_shown_shortened(tmp_path: Path, vertex_property: str,
                                                           vertices: list[str], more: str, line: int,
                                                           message: str) -> None:
    """A body's message named its element and property whole, however long."""
    properties = "property float x\nproperty float y\nproperty float z\n" + (vertex_property and vertex_property + "\n")
    text = ply_text(["3 0 1 2"], vertices=vertices, vertex_properties=properties)
    text = text.replace("end_header\n", more + "end_header\n") + ("1\n" if more else "")
    refused = refusal(tmp_path, text)
    assert (refused.line, refused.message) == (line, message)


def test_a_long_element_name_is_shown_shortened_in_a_binary_body(tmp_path: Path) -> None:
    header = ply_text(["3 0 1 2"]).split("end_header")[0].replace("ascii", "binary_little_endian")
    header += f"element {LONG_NAME} 1\nproperty list char int a\nend_header\n"
    rows = b"".join(struct.pack("<3f", *map(float, row.split())) for row in GRID)
    (tmp_path / "b.ply").write_bytes(header.encode() + rows + struct.pack("<B3ib", 3, 0, 1, 2, -1))
    refused = one_line_refusal(lambda: load_model(tmp_path / "b.ply"))
    assert refused.message == f"{SHOWN_NAME}: a list count of -1, below 0"


@pytest.mark.parametrize("list_type", ["float", "int"])
def test_a_huge_index_of_a_binary_or_float_list_is_shown_as_its_value(tmp_path: Path, list_type: str) -> None:
    """A float list's 400 nines are shown as written; a binary body's values are exact as read."""
    properties = f"property list uchar {list_type} vertex_indices\n"
    text = ply_text([f"3 0 1 {NINES}"], face_properties=properties)
    refused = refusal(tmp_path, text)
    if list_type == "float":
        assert refused.message == f"vertex index {SHOWN_NINES} out of range (the file has 9 vertices)"
    header = ply_text(["3 0 1 4"], face_properties=properties).split("end_header")[0]
    header = header.replace("ascii", "binary_little_endian")
    rows = b"".join(struct.pack("<3f", *map(float, row.split())) for row in GRID)
    corners = struct.pack("<B3f", 3, 0, 1, 1e30) if list_type == "float" else struct.pack("<B3i", 3, 0, 1, 2**31 - 1)
    (tmp_path / "b.ply").write_bytes((header + "end_header\n").encode() + rows + corners)
    binary = one_line_refusal(lambda: load_model(tmp_path / "b.ply"))
    shown = "1.0000000150474662e+30" if list_type == "float" else "2147483647"
    assert binary.message == f"vertex index {shown} out of range (the file has 9 vertices)"


@pytest.mark.parametrize(("count", "message"), [
    (NINES, f"element vertex: {SHOWN_NINES} rows are more than a file holds (a count has at most 12 digits)"),
    ("1234567890123", "element vertex: 1234567890123 rows are more than a file holds (a count has at most 12 digits)"),
    ("x" * 50, f"element vertex: '{'x' * 40}... (50 characters)' is not a count"),
    ("-3", "element vertex: '-3' is not a count"),
])
def test_a_header_count_past_any_file_is_shown_shortened(tmp_path: Path, count: str, message: str) -> None:
    refused = refusal(tmp_path, ply_text(["3 0 1 4"]).replace("element vertex 9", f"element vertex {count}"))
    assert (refused.line, refused.message) == (3, message)


def test_a_body_short_of_its_one_row_says_one_row(tmp_path: Path) -> None:
    text = ply_text(["3 0 1 4"])
    refused = refusal(tmp_path, text[:text.rindex("3 0 1 4")])
    assert (refused.line, refused.message) == (18, "the header counts 1 row of face, the file ends before them")


def test_a_coordinate_past_a_floats_range_is_refused_at_its_line(tmp_path: Path) -> None:
    refused = refusal(tmp_path, ply_text(["3 0 1 4"], vertices=[*GRID[:4], "1 1 -1e39", *GRID[5:]]))
    assert (refused.line, refused.message) == (14, "vertex z: -1e39 is no float (numbers up to 3.4e+38)")


@pytest.mark.parametrize("value", ["3.5e38", "-1e300", "nan"])
def test_a_double_coordinate_the_gpu_cannot_hold_is_refused_at_its_line(tmp_path: Path, value: str) -> None:
    """A double holds 3.5e38, a float does not: the line was named for NaN alone, and the NaN of a
    normal's line before it was named instead of the coordinate's."""
    doubles = "".join(f"property double {name}\n" for name in ("x", "y", "z", "nx"))
    vertices = [f"{row} {'nan' if at == 2 else 0}" for at, row in enumerate(GRID)]
    vertices[4] = f"1 1 {value} 0"
    refused = refusal(tmp_path, ply_text(["3 0 1 4"], vertices=vertices, vertex_properties=doubles))
    assert (refused.line, refused.message) == (15, "a vertex coordinate is not a finite number the GPU can hold")


@pytest.mark.parametrize("claim", ["element face 99999999999\nproperty list uchar int vertex_indices\n",
                                   "element face 2\nproperty list uchar int vertex_indices\nelement nothing "
                                   "99999999999\n"])
def test_a_claimed_count_reserves_nothing(tmp_path: Path, claim: str) -> None:
    text = ply_text(["3 0 1 4", "4 0 1 4 3"]).replace("element face 2\nproperty list uchar int vertex_indices\n",
                                                       claim)
    path = tmp_path / "m.ply"
    path.write_text(text)
    load(tmp_path, ply_text(["3 0 1 4"]), "warm.ply")  # trimesh imported, as by any PLY opened before
    outcome, peak = peak_traced_bytes(lambda: load_model(path))
    if "nothing" in claim:
        assert outcome.face_count == 2
    else:
        assert (outcome.line, outcome.message) == (7, "the header counts 99999999999 rows of face, the file ends "
                                                      "before them: the 90 bytes after the header hold 45 numbers "
                                                      "at most")
    assert peak < 1 << 20, peak


BODY_BYTES = len(ply_text(["3 0 1 4"]).split("end_header\n")[1])


@pytest.mark.parametrize(("old", "new", "line", "counted"), [
    ("element vertex 9", "element vertex 999999999", 3, "999999999 rows of vertex"),
    ("element face 1", "element face 99999999999", 7, "99999999999 rows of face"),
    # a row of a list of no items and a number: two numbers at least
    ("end_header", "element edge 40\nproperty list uchar int a\nproperty int b\nend_header", 9, "40 rows of edge"),
])
def test_counts_of_more_rows_than_an_ascii_body_holds_are_refused_at_the_header(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, old: str, new: str, line: int, counted: str) -> None:
    """A count past what the body's bytes hold was refused only once the whole body was read as numbers,
    at its last line: now at the count's line, from the file's size alone (a number a property a row,
    each a byte and a blank), before the body is read."""
    monkeypatch.setattr(ply, "text_numbers", lambda *_: pytest.fail("the body was read"))
    refused = refusal(tmp_path, ply_text(["3 0 1 4"]).replace(old, new))
    assert (refused.line, refused.message) == (line, f"the header counts {counted}, the file ends before them: the "
                                                     f"{BODY_BYTES} bytes after the header hold {BODY_BYTES // 2} "
                                                     "numbers at most")


@pytest.mark.parametrize(("rows", "refused_at_the_header"), [(6, False), (7, True)])
def test_the_header_lets_off_one_row_of_the_least_numbers(rows: int, refused_at_the_header: bool) -> None:
    """Rows of one number (a list of no items), a byte and a line end each: five rows' bytes hold a count
    of six, all but its last row, which a file cut short holds in part (the body names it at its line);
    not a count of seven."""
    data = f"ply\nformat ascii 1.0\nelement e {rows}\nproperty list uchar int a\nend_header\n".encode() + b"0\n" * 5
    if refused_at_the_header:
        refused = one_line_refusal(lambda: read_header(Path("e.ply"), data))
        assert (refused.line, refused.message) == (3, "the header counts 7 rows of e, the file ends before them: "
                                                      "the 10 bytes after the header hold 5 numbers at most")
    else:
        assert read_header(Path("e.ply"), data).elements[0].count == rows


def test_a_colour_past_its_type_is_refused_at_its_line(tmp_path: Path) -> None:
    colours = [f"{row} 10 20 {300 if number == 5 else 30}" for number, row in enumerate(GRID)]
    properties = "property float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar " \
                 "green\nproperty uchar blue\n"
    refused = refusal(tmp_path, ply_text(["3 0 1 4"], vertices=colours, vertex_properties=properties))
    assert (refused.line, refused.message) == (18, "vertex blue: 300 is no uchar (whole numbers from 0 to 255)")


def test_a_header_of_many_lines_is_never_a_list_of_them(tmp_path: Path) -> None:
    elements = "".join(f"element e{number} 3\n" for number in range(5000))  # of names of their own
    header = ("ply\nformat ascii 1.0\n" + "comment many\n" * 200_000 + elements + "end_header\n").encode()
    refused, peak = peak_traced_bytes(lambda: read_header(Path("m.ply"), header))
    assert (refused.line, refused.message) == (200_000 + 2 + 4097, "more than 4096 elements and properties: no "
                                                                   "model's header")
    assert peak < 1.5 * len(header), peak  # the header's bytes once more, cut from the body


def test_rows_that_stop_beginning_lines_are_named_with_the_error(tmp_path: Path) -> None:
    """A vertex row short of a number shifts every row after it: the error shows where one no longer
    makes sense, and says where the rows stopped beginning lines."""
    vertices = [*GRID[:4], "1 1", *GRID[5:]]
    refused = refusal(tmp_path, ply_text(["3 0 1 4", "3 0 4 3"], vertices=vertices))
    assert (refused.line, refused.message) == (14, "line 14 holds 2 numbers where a vertex row of these properties "
                                                   "holds 3, so the rows after it no longer begin lines (line 19: a "
                                                   "face of 0 corners: 3 or more make one)")
    vertices = [*GRID[:4], "1 1 0 1", *GRID[5:]]
    refused = refusal(tmp_path, ply_text(["3 0 1 4", "3 0 4 3"], vertices=vertices))
    assert refused.line == 14 and refused.message.startswith(
        "line 14 holds 4 numbers where a vertex row of these properties holds 3, so the rows after it no longer "
        "begin lines (line "), refused.message


def test_a_row_of_more_numbers_than_its_counts_leads_the_error_with_its_line(tmp_path: Path) -> None:
    """trimesh's fuze_ascii.ply: each face row holds 6 numbers more than its properties (21 where its counts
    make 15). The error led with the next line and a texcoord count, the line at fault said in brackets."""
    properties = ("property list uchar int vertex_indices\nproperty list uchar float texcoord\nproperty uchar red\n"
                  "property uchar green\nproperty uchar blue\nproperty uchar alpha\n")
    faces = [f"3 {corners} 6 {uvs} 9 1 1 1 1 1 1 1 1 1" for corners, uvs in [
        ("0 5 1", "0.629012 0.417026 0.599829 0.426753 0.629012 0.442966"),
        ("0 6 5", "0.629012 0.417026 0.596587 0.404056 0.599829 0.426753"),
        ("2 0 3", "0.661437 0.404056 0.629012 0.417026 0.654952 0.429996")]]  # its first three, as it writes them
    refused = refusal(tmp_path, ply_text(faces, face_properties=properties))
    assert (refused.line, refused.message) == (24, "line 24 holds 21 numbers where a face row of these properties "
                                                   "holds 15, so the rows after it no longer begin lines (line 25: "
                                                   "face texcoord: 0.599829 is no uchar count (whole numbers from 0 "
                                                   "to 255))")


def test_an_error_in_the_first_row_is_named_too(tmp_path: Path) -> None:
    properties = "property float x\nproperty float y\nproperty float z\nproperty list uchar int n\n"
    refused = refusal(tmp_path, ply_text(["3 0 1 4"], vertices=[f"{row} 1.5" for row in GRID],
                                         vertex_properties=properties))
    assert (refused.line, refused.message) == (11, "vertex n: 1.5 is no uchar count (whole numbers from 0 to 255)")


def test_an_error_in_a_file_that_packs_its_rows_says_nothing_of_lines(tmp_path: Path) -> None:
    text = ply_text(["3 0 1 4", "3 0 9 3"])
    header, body = text.split("end_header\n")
    refused = refusal(tmp_path, header + "end_header\n" + " ".join(body.split()) + "\n")
    assert refused.message == "vertex index 9 out of range (the file has 9 vertices)" and refused.line == 10


@pytest.mark.parametrize("word", ["--inf", "+-nan", "1e", "0x10"])
def test_a_word_numpy_would_not_read_is_named_at_its_line(tmp_path: Path, word: str) -> None:
    refused = refusal(tmp_path, ply_text(["3 0 1 4"], vertices=[*GRID[:6], f"0 {word} 0", *GRID[7:]]))
    assert (refused.line, refused.message) == (16, f"'{word}' is not a number")


def test_a_long_word_numpy_would_not_read_is_shown_shortened(tmp_path: Path) -> None:
    refused = refusal(tmp_path, ply_text(["3 0 1 4"], vertices=[*GRID[:6], f"0 {'1x' * 30} 0", *GRID[7:]]))
    assert (refused.line, refused.message) == (16, f"'{'1x' * 20}... (60 bytes)' is not a number")


@pytest.mark.parametrize(("kind", "index"), [("uint64", 2**64 - 1), ("uint64", 2**64), ("int64", 2**63 - 1)])
def test_an_index_at_a_64_bit_types_edge_is_out_of_range(tmp_path: Path, kind: str, index: int) -> None:
    """float64 rounds a 64-bit type's largest value up to 2 ** bits: it was refused as no uint64."""
    refused = refusal(tmp_path, ply_text([f"3 0 1 {index}"], face_properties=f"property list uchar {kind} "
                                                                              "vertex_indices\n"))
    assert (refused.line, refused.message) == (19, f"vertex index {index} out of range (the file has 9 vertices)")


def test_a_64_bit_value_at_its_types_edge_is_read_as_its_float_value(tmp_path: Path) -> None:
    """Past it, a value is still refused: 2 ** 64 + 10 ** 6 is float64's next number after 2 ** 64."""
    extra = "property uint64 id\nproperty int64 low\nproperty int64 high\n"
    vertices = [f"{row} {2**64 - 1} {-2**63} {2**63 - 1}" for row in GRID]
    text = ply_text(["3 0 1 4"], vertices, vertex_properties="property float x\nproperty float y\nproperty float z\n"
                    + extra)
    data = text.encode()
    binary = binary_of_ascii(Path("m.ply"), data, read_header(Path("m.ply"), data), ANY_TRIANGLES).data
    rows = np.frombuffer(binary, "<3f4,<u8,<i8,<i8", count=9, offset=read_header(Path("m.ply"), binary).body_at)
    assert rows["f1"].tolist() == [2**64 - 1] * 9 and rows["f2"].tolist() == [-2**63] * 9
    assert rows["f3"].tolist() == [2**63 - 1] * 9
    assert load(tmp_path, text).face_count == 1
    refused = refusal(tmp_path, text.replace(str(2**64 - 1), str(2**64 + 10**6), 1))
    assert (refused.line, refused.message) == (13, "vertex id: 18446744073710551616 is no uint64 (whole numbers "
                                                   "from 0 to 18446744073709551615)")


@pytest.mark.parametrize(("faces", "line", "said"), [
    (["3 0 1 4 4 0 0 1 0"], 20, "4 numbers for a face of 3 corners"),
    (["3 0 1 4 6 0 0 1 0 1 1", "4 0 1 4 3 6 0 0 1 0 1 1"], 21, "6 numbers for a face of 4 corners")])
def test_texture_coordinates_of_the_wrong_length_are_refused_at_their_line(tmp_path: Path, faces: list[str],
                                                                           line: int, said: str) -> None:
    """Whether the faces are fanned or not: trimesh refused the one and dropped the other's silently."""
    properties = "property list uchar int vertex_indices\nproperty list uchar float texcoord\n"
    refused = refusal(tmp_path, ply_text(faces, face_properties=properties))
    assert (refused.line, refused.message) == (line, f"face texcoord: {said} (two a corner)")


def test_elements_trimesh_draws_nothing_of_are_left_to_it_or_out(tmp_path: Path) -> None:
    """A zero-row edge element (trimesh makes a path of any edge element, which needs scipy) is left out,
    and a vertex element's lists of mixed lengths too, its colours kept."""
    colours = [f"{row} {1 + number % 2} {' '.join(['7'] * (1 + number % 2))} 10 20 30" for number, row in
               enumerate(GRID)]
    properties = ("property float x\nproperty float y\nproperty float z\nproperty list uchar int neighbours\n"
                  "property uchar red\nproperty uchar green\nproperty uchar blue\n")
    text = ply_text(["3 0 1 4"], vertices=colours, vertex_properties=properties)
    text = text.replace("end_header", "element edge 0\nproperty int vertex1\nproperty int vertex2\nend_header")
    mesh = load(tmp_path, text)
    assert mesh.face_count == 1 and mesh.vertex_colours.tolist() == [[10, 20, 30]] * 9


@pytest.mark.parametrize("line_end", ["\r", "\r\n"])
def test_other_line_ends_read_as_newlines(tmp_path: Path, line_end: str) -> None:
    text = ply_text(["3 0 1 4", "3 0 4 3"], remarks="obj_info TextureFile q.png\n").replace("\n", line_end)
    header = read_header(Path("m.ply"), text.encode())
    assert header.picture == "q.png" and header.count("vertex") == 9
    assert load(tmp_path, text).face_count == 2


def test_a_byte_order_mark_before_the_header_is_read_past(tmp_path: Path) -> None:
    """Notepad's mark before 'ply' was refused as no PLY header, as STL's, OFF's and OBJ's are read past."""
    for name, data in written_both_ways([[0, 1, 4], [0, 4, 3]]).items():
        (tmp_path / name).write_bytes(b"\xef\xbb\xbf" + data)
        assert load_model(tmp_path / name).face_count == 2
    refused = refusal(tmp_path, "\ufeff" + ply_text(["3 0 1 9"]))
    assert (refused.line, refused.message) == (19, "vertex index 9 out of range (the file has 9 vertices)")


@pytest.mark.parametrize("line_end", [b"\r", b"\r\n"])
def test_a_binary_bodys_header_of_other_line_ends_is_read(tmp_path: Path, line_end: bytes) -> None:
    """trimesh ends a header's lines at \\n alone: one of lone \\r said "IndexError: list index out of range"."""
    data = written_both_ways([[0, 1, 4], [0, 4, 3]])["binary.ply"]
    body_at = data.index(b"end_header\n") + 11
    path = tmp_path / "m.ply"
    path.write_bytes(data[:body_at].replace(b"\n", line_end) + data[body_at:])
    assert load_model(path).face_count == 2


def test_one_polygon_of_many_corners_fans_in_proportion(tmp_path: Path) -> None:
    """Fanned with 32-bit indices, each value made its type before it is gathered: at most a few times
    the binary rows written (a triangle of 16 bytes for each corner of two in the text)."""
    corners = 300_000
    data = ply_text([f"{corners} " + " ".join(["0 1 4"] * (corners // 3))],
                    face_properties="property list int int vertex_indices\n").encode()
    binary, peak = peak_traced_bytes(lambda: binary_of_ascii(Path("m.ply"), data, read_header(Path("m.ply"), data),
                                                             ANY_TRIANGLES).data)
    assert len(binary) - binary.index(b"end_header\n") - 11 == 9 * 12 + (corners - 2) * 16  # int count, 3 ints
    assert peak < 3.5 * len(binary), peak


@pytest.mark.parametrize(("header", "line", "message"), [
    ("ply\nformat ascii 1.0\nproperty float x\nend_header\n", 3, "a property before any element"),
    ("ply\nformat ascii 1.0\nelement vertex 3\nproperty real x\nend_header\n", 4, "'real' is not a PLY type"),
    ("ply\nformat ascii 1.0\nelement vertex 3\nproperty " + "r" * 41 + " x\nend_header\n", 4,
     f"'{'r' * 40}... (41 characters)' is not a PLY type"),
    ("ply\nformat ascii 1.0\nelement face 1\nproperty list float int vertex_indices\nend_header\n", 4,
     "a list's count must be of a whole-number type, not float"),
    ("ply\nformat ascii 2.0 x\nelement face 1\nend_header\n", 2,
     "expected 'format ascii 1.0' or a binary_little_endian or binary_big_endian format"),
    ("ply\nelement face 1\nend_header\n", 3, "the header has no 'format' line"),
    # the second was read, the first passed over
    ("ply\nformat binary_little_endian 1.0\nformat ascii 1.0\nelement face 1\nend_header\n", 3,
     "a second 'format' line: a PLY's header has one"),
    # passed over: a header cut or run together
    ("ply\nformat ascii 1.0\n1 2 3 4\nelement face 1\nend_header\n", 3,
     "'1' begins no PLY header line: a line is a format, element, property, comment or obj_info"),
    ("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nvertex 3\nend_header\n", 5,
     "'vertex' begins no PLY header line: a line is a format, element, property, comment or obj_info"),
    ("ply\nformat ascii 1.0\n" + "9" * 400 + "\nelement face 1\nend_header\n", 3,
     f"'{'9' * 40}... (400 digits)' begins no PLY header line: a line is a format, element, property, comment "
     "or obj_info"),
    ("ply\nformat ascii 1.0\nelement face\nend_header\n", 3, "expected 'element', a name and a count"),
    ("ply\nformat ascii 1.0\nelement " + "e" * 50 + " x\nend_header\n", 3,
     f"element {'e' * 40}... (50 characters): 'x' is not a count"),
    # trimesh said "PLY is unexpected length!" for both
    ("ply\nformat ascii 1.0\nelement face 2\nelement vertex 0\nelement face 0\nelement face 1\nend_header\n", 6,
     "a second element named face with rows"),
    ("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float x\nend_header\n", 6,
     "element vertex: a second property named x"),
    ("ply\nformat ascii 1.0\nelement " + "e" * 50 + " 1\nproperty float " + "p" * 50 + "\nproperty float " + "p" * 50
     + "\nend_header\n", 5,
     f"element {'e' * 40}... (50 characters): a second property named {'p' * 40}... (50 characters)"),
    # numpy said "no field of name z" and "The DType <class 'numpy.dtypes.VoidDType'> could not be promoted"
    ("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nelement face 1\nend_header\n", 3,
     "element vertex has no property z: a vertex's coordinates are x, y and z"),
    ("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty list uchar float y\nend_header\n", 5,
     "vertex y is a list: a coordinate is one number"),
    # trimesh said "UnboundLocalError: cannot access local variable 'name'"
    ("ply\nformat ascii 1.0\nelement face 1\nproperty int a\nproperty list uchar int b\nend_header\n", 3,
     "element face has no list of its corners (property list uchar int vertex_indices)"),
])
def test_a_bad_header_is_refused_at_its_line(tmp_path: Path, header: str, line: int, message: str) -> None:
    refused = refusal(tmp_path, header + "3 0 1 2\n")
    assert (refused.line, refused.message) == (line, message)


@pytest.mark.parametrize("comment", [b"comment no end_header here\n", b"obj_info end_header\r\n",
                                     b"comment xend_header\ncomment end_headers\n"])
def test_end_header_ends_the_header_only_as_a_line_alone(tmp_path: Path, comment: bytes) -> None:
    """The word in a comment ended the header there ("the header declares no faces"), and trimesh ends
    it at any line holding the word: a binary file's header is written again for it without comments."""
    for name, data in written_both_ways([[0, 1, 4], [0, 4, 3]]).items():
        data = data.replace(b"1.0\n", b"1.0\n" + comment, 1)
        header = read_header(Path(name), data)
        assert header.count("face") == 2 and data[:header.body_at].endswith(b"\nend_header\n")
        if header.encoding == "<":
            for_trimesh = trimesh.util.wrap_as_stream(vertices_and_faces(Path(name), data, header,
                                                                         ANY_TRIANGLES).data)
            assert len(trimesh.load(for_trimesh, file_type="ply", process=False).faces) == 2
        (tmp_path / name).write_bytes(data)
        assert load_model(tmp_path / name).face_count == 2


@pytest.mark.parametrize("line", ["end_header x", "x end_header", "comment TextureFile end_header .png"])
def test_end_header_on_a_line_of_other_words_before_the_end_is_refused(tmp_path: Path, line: str) -> None:
    refused = refusal(tmp_path, ply_text(["3 0 1 4"], remarks=line + "\n"))
    assert (refused.line, refused.message) == (3, "'end_header' on a line of other words: the header ends at a line "
                                                  "of 'end_header' alone, and before it only a comment (not a "
                                                  "TextureFile's) may hold the word")


@pytest.mark.parametrize("joined", ["end_header ", " end_header\n"])
def test_a_header_whose_only_end_header_shares_a_line_is_refused_at_that_line(tmp_path: Path, joined: str) -> None:
    """No line of 'end_header' alone: the word run together with the body's first row, or with the last
    property line, is named at its line, not as a file that is no PLY."""
    header, body = ply_text(["3 0 1 4"]).split("end_header\n")
    text = header.rstrip("\n") + joined + body if joined.startswith(" ") else header + joined + body
    refused = refusal(tmp_path, text)
    assert (refused.line, refused.message) == (text.count("\n", 0, text.index("end_header")) + 1,
                                               "'end_header' on a line of other words: the header ends at a line "
                                               "of 'end_header' alone, and before it only a comment (not a "
                                               "TextureFile's) may hold the word")


@pytest.mark.parametrize("remarks", ["", "comment end_header comes later\n"])
def test_a_header_that_never_ends_is_no_ply_whether_a_comment_holds_the_word_or_not(tmp_path: Path,
                                                                                    remarks: str) -> None:
    """No line ends the header: with the word in a comment, the body's first row was refused as a header
    line ("'0' begins no PLY header line", line 10), where the same file without the comment is no PLY."""
    text = ply_text(["3 0 1 4"], remarks=remarks).replace("end_header\n", "")
    refused = refusal(tmp_path, text)
    assert (refused.line, refused.message) == (1, "not a PLY file (no 'ply' ... 'end_header' header)")


def test_the_picture_and_unknown_elements_are_kept_for_trimesh(tmp_path: Path) -> None:
    text = ply_text(["3 0 1 4"], remarks="comment TextureFile p.png\ncomment TextureFile q.png\nobj_info by hand\n")
    text = text.replace("end_header", "element material 1\nproperty float shine\nend_header") + "0.5\n"
    data = text.encode()
    binary = binary_of_ascii(Path("m.ply"), data, read_header(Path("m.ply"), data), ANY_TRIANGLES).data
    header = read_header(Path("m.ply"), binary)
    assert header.encoding == "<" and header.picture == "q.png"
    assert [(element.name, element.count) for element in header.elements] == [("vertex", 9), ("face", 1),
                                                                              ("material", 1)]
    assert binary[header.body_at:] == np.array(GRID_NUMBERS, "<f4").tobytes() + b"\x03" + \
        np.array([0, 1, 4], "<i4").tobytes() + np.array([0.5], "<f4").tobytes()


GRID_NUMBERS = [float(number) for row in GRID for number in row.split()]


def test_blank_lines_cost_no_more_than_their_bytes(tmp_path: Path) -> None:
    """trimesh's reader held a numpy array per line: 170 bytes a byte of blank lines."""
    text = ply_text(["3 0 1 4\n" * 20 + "\n" * 1_000_000]).replace("element face 1\n", "element face 20\n")
    path = tmp_path / "m.ply"
    path.write_text(text)
    mesh, peak = peak_traced_bytes(lambda: load_model(path))
    assert mesh.face_count == 20
    assert peak < 3 * len(text), peak  # the file's bytes, and its body once more while numpy reads it


def test_short_face_rows_cost_their_numbers(tmp_path: Path) -> None:
    """Rows of '3 0 1 4' took 60 bytes a byte through trimesh's reader (52 in it alone). Made binary, they
    take 8 bytes for each number of two, and the binary rows; the model built of them, about 11 more."""
    data = ply_text(["3 0 1 4"] * 200_000).encode()
    binary, peak = peak_traced_bytes(lambda: binary_of_ascii(Path("m.ply"), data, read_header(Path("m.ply"), data),
                                                             ANY_TRIANGLES).data)
    assert len(binary) - binary.index(b"end_header\n") - 11 == 9 * 12 + 200_000 * 13  # the rows, bytes as typed
    assert peak < 10 * len(data), peak
    (tmp_path / "m.ply").write_bytes(data)
    mesh, peak = peak_traced_bytes(lambda: load_model(tmp_path / "m.ply"))
    assert mesh.face_count == 200_000 and peak < 25 * len(data), peak


# --- rows of one list, walked quickly ------------------------------------------------------------
def mixed_faces_ply(rng: random.Random, encoding: str) -> bytes:
    """Triangles and quads under one header, maybe a value before or after each face's list, and
    maybe one thing wrong: a count that is no count, a row cut or lengthened, rows packed on one line."""
    before, after = rng.random() < 0.3, rng.random() < 0.3
    count_type = "uchar" if encoding != "ascii" else rng.choice(["uchar", "int", "ushort"])
    faces = [[rng.randrange(9) for _ in range(rng.choice([3, 4]))] for _ in range(rng.randint(1, 60))]
    rows = [[*([("uchar", 1)] if before else []), (count_type, len(face)), *(("int", index) for index in face),
             *([("float", 0.5)] if after else [])] for face in faces]
    wrong = rng.random()
    if wrong < 0.6:
        row = rng.choice(rows)
        at = int(before)
        row[at] = (row[at][0], rng.choice([-1, 2, 0, 2.5, 256, 65536, float("nan"), 5]))
    header = ["ply", f"format {encoding} 1.0", "element vertex 9", "property float x", "property float y",
              "property float z", f"element face {len(faces)}", *(["property uchar flag"] if before else []),
              f"property list {count_type} int vertex_indices", *(["property float quality"] if after else []),
              "end_header"]
    head = ("\n".join(header) + "\n").encode()
    if encoding == "ascii":
        lines = [" ".join(f"{value:g}" for _, value in row) for row in rows]
        body = "\n".join(GRID) + "\n" + (" " if rng.random() < 0.1 else "\n").join(lines) + "\n"
        data = head + body.encode()
    else:
        codes = {"uchar": "B", "int": "i", "float": "f"}
        vertices = np.array(GRID_NUMBERS, "<f4").tobytes()
        data = head + vertices + b"".join(struct.pack("<" + codes[kind], int(value) if kind != "float" else value)
                                          if not (kind == "uchar" and not 0 <= value <= 255 or value != value)
                                          else b"\xff" for row in rows for kind, value in row)
    if 0.6 <= wrong < 0.8:
        return data[:rng.randrange(len(head), len(data) + 1)]
    return data + b" 3 1 2 0\n" if wrong >= 0.9 else data


def as_read(data: bytes) -> tuple[bytes, list[int] | None] | tuple[int | None, str]:
    """What the PLY reader makes of a file for trimesh and the sizes of the polygons it fanned, or its
    error's line and message."""
    path = Path("m.ply")
    try:
        header = read_header(path, data)
        sizes = None
        if header.encoding == "ascii":
            data, sizes, _ = binary_of_ascii(path, data, header, ANY_TRIANGLES)
            header = read_header(path, data)
        data, binary_sizes, _ = vertices_and_faces(path, data, header, ANY_TRIANGLES)
        fanned = binary_sizes if sizes is None else sizes
        return data, None if fanned is None else fanned.tolist()
    except LoadError as refused:
        return refused.line, refused.message


@pytest.mark.parametrize("encoding", ["ascii", "binary_little_endian"])
def test_rows_of_one_list_walked_quickly_read_as_the_checked_walk_reads_them(
        monkeypatch: pytest.MonkeyPatch, encoding: str) -> None:
    """A face element's rows are walked without a check per value while their counts are good, and the
    first that is not is left to the walk that checks each: the same tables, or the same error at the
    same line, as that walk gives alone."""
    rng = random.Random(encoding)
    files = [mixed_faces_ply(rng, encoding) for _ in range(300)]
    quick = [as_read(data) for data in files]
    monkeypatch.setattr(ply, "_quick_rows", lambda body, element, at, starts, counts: (0, at))
    monkeypatch.setattr(ply, "_byte_counted_rows", lambda data, at, rows, steps, tail: (
        np.zeros(0, np.int64), np.zeros((0, len(steps)), np.int64), at))
    checked = [as_read(data) for data in files]
    assert quick == checked
    assert sum(isinstance(outcome, tuple) for outcome in quick) > 50  # errors of every kind among them


@pytest.mark.parametrize("encoding", ["ascii", "binary"])
def test_faces_that_fan_into_too_many_triangles_are_refused_before_trimesh_builds_them(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, encoding: str) -> None:
    """A 92 MB binary PLY of 52-corner faces fans into 22M triangles: trimesh built them all, 1.2 GB, and
    the refusal after it spoke of a scene placing 'its meshes 1 times'. The fanned count is known first."""
    from marraztu.loaders import exchange

    data = ply_text(["8 0 1 2 5 8 7 6 3"] * 5).encode()  # 6 triangles each: 30
    if encoding == "binary":  # as a binary file holds them: polygons, not fanned
        data = struct.pack("<B8i", 8, 0, 1, 2, 5, 8, 7, 6, 3) * 5
        data = (b"ply\nformat binary_little_endian 1.0\nelement vertex 9\nproperty float x\nproperty float y\n"
                b"property float z\nelement face 5\nproperty list uchar int vertex_indices\nend_header\n"
                + np.array([[x, y, 0.0] for y in range(3) for x in range(3)], "<f4").tobytes() + data)
    (tmp_path / "m.ply").write_bytes(data)
    monkeypatch.setattr(exchange, "MAX_PLACED_TRIANGLES", 29)
    built: list[bytes] = []
    monkeypatch.setattr(exchange, "_trimesh_load", lambda *args, **kwargs: built.append(args[1]))
    refused = one_line_refusal(lambda: load_model(tmp_path / "m.ply"))
    assert built == []
    assert refused.message == "its faces make 30 triangles: more than the 29 the viewer draws from one model"
