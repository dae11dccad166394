"""The OBJ reader against inputs shaped to cost it: a bad file's error costs about what a good file of
its size costs, and every input costs in proportion to its size. Also what people's editors write:
byte order marks, old Mac line ends, Windows paths in comments, no-break spaces, odd material files.

Work is measured, never seconds: lines the Python line reader reads, and peak memory traced.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest

import marraztu.loaders.obj as obj_module
from marraztu.errors import LoadError
from marraztu.loaders.obj import fast as fast_reader
from marraztu.loaders.obj import load_obj, parse_obj
from marraztu.loaders.obj.lines import read_by_lines
from marraztu.model.mesh import Mesh
from support.work import lines_read_by_python, peak_traced_bytes

PIECE_BYTES = 1 << 16
QUAD = b"v 0 0 0\nv 2 0 0\nv 2 1 0\nv 0 1 0\nf 1 2 3 4\n"


@pytest.fixture(scope="module", autouse=True)
def small_chunks() -> Iterator[None]:
    """Small pieces and many threads: a file of a few megabytes is then cut as a large file is. Small
    files here take the compiled reader too."""
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(obj_module, "COMPILED_READER_BYTES", 0)
        patch.setattr(fast_reader, "MIN_PIECE_BYTES", PIECE_BYTES)
        patch.setattr(fast_reader, "PARSE_THREADS", 8)
        yield


def exporter_text(side: int = 120) -> bytes:
    """A grid of v/vt/vn triangles written as exporters write them: a few megabytes."""
    rng = np.random.default_rng(3)
    count = side * side
    lines = [f"v {a:.6f} {b:.6f} {c:.6f}" for a, b, c in rng.normal(size=(count, 3))]
    lines += [f"vt {a:.6f} {b:.6f}" for a, b in rng.random((count, 2))]
    lines += [f"vn {a:.4f} {b:.4f} {c:.4f}" for a, b, c in rng.normal(size=(count, 3))]
    for row in range(side - 1):
        for column in range(side - 1):
            a = row * side + column + 1
            for triangle in ((a, a + 1, a + side + 1), (a, a + side + 1, a + side)):
                lines.append("f " + " ".join(f"{i}/{i}/{i}" for i in triangle))
    return ("\n".join(lines) + "\n").encode()


TEXT = exporter_text()
TEXT_LINES = TEXT.count(b"\n")


def load_counting(data: bytes) -> tuple[Mesh | LoadError, int, int]:
    """(the mesh or the error, lines the line reader read, peak bytes traced)."""
    with lines_read_by_python() as counted:
        outcome, peak = peak_traced_bytes(lambda: parse_obj(data, "hostile.obj"))
    return outcome, counted.lines, peak


def error_of(outcome: Mesh | LoadError) -> LoadError:
    assert isinstance(outcome, LoadError), outcome
    return outcome


@pytest.fixture(scope="module")
def plain_peak(small_chunks: None) -> int:
    """Peak memory of loading TEXT, the good file every bad one is weighed against."""
    outcome, lines, peak = load_counting(TEXT)
    assert isinstance(outcome, Mesh) and lines == 0
    return peak


# --- errors cost what a good file costs ------------------------------------------------------------


def test_a_good_exporter_file_takes_the_fast_path_end_to_end() -> None:
    outcome, lines, _ = load_counting(TEXT)
    assert isinstance(outcome, Mesh) and outcome.face_count == 2 * 119 * 119
    assert lines == 0
    assert len(TEXT) > 8 * PIECE_BYTES  # cut into as many pieces as there are threads


def test_a_cut_last_line_costs_one_line_not_the_file(plain_peak: int) -> None:
    outcome, lines, peak = load_counting(TEXT + b"f 1/1/1 2/1")
    error = error_of(outcome)
    assert (error.line, error.message) == (TEXT_LINES + 1, "a face needs at least 3 vertices, found 2")
    assert lines == 1
    assert peak <= 2 * plain_peak


def test_a_file_without_its_last_newline_is_not_held_twice(tmp_path: Path) -> None:
    """The readers want a newline after the last line; adding one copies the file, and the bytes read
    from disk must go once the copy is made, not stay alongside it while the tables are read."""
    ended, unended = tmp_path / "ended.obj", tmp_path / "unended.obj"
    ended.write_bytes(TEXT)
    unended.write_bytes(TEXT[:-1])
    load_obj(ended)  # the compiled reader's code loaded before anything is weighed
    (mesh, ended_peak), (same, unended_peak) = (peak_traced_bytes(lambda: load_obj(path)) for path in (ended, unended))
    assert isinstance(same, Mesh) and isinstance(mesh, Mesh) and same.face_count == mesh.face_count
    assert unended_peak < ended_peak + len(TEXT) // 4, (ended_peak, unended_peak, len(TEXT))


@pytest.mark.parametrize("edit", ["a byte order mark", "a no-break space", "an emoji"])
def test_a_text_edit_costs_one_copy_not_several(tmp_path: Path, edit: str) -> None:
    """The file as read and one edited copy, as for a file that lacks only its last newline: a BOM
    is stripped in the copy that adds the newline, and text that is not ASCII is never decoded whole
    (which takes up to four bytes a byte)."""
    edited_text = {"a byte order mark": b"\xef\xbb\xbf" + TEXT[:-1],
                   "a no-break space": TEXT.replace(b"v ", "v\u00a0".encode(), 1),  # the replacing is the copy
                   "an emoji": "# \U0001F600\n".encode() + TEXT[:-1]}[edit]
    plain, edited = tmp_path / "plain.obj", tmp_path / "edited.obj"
    plain.write_bytes(TEXT[:-1])
    edited.write_bytes(edited_text)
    load_obj(plain)  # the compiled reader's code loaded before anything is weighed
    (mesh, plain_peak), (same, edited_peak) = (peak_traced_bytes(lambda: load_obj(path)) for path in (plain, edited))
    assert isinstance(same, Mesh) and isinstance(mesh, Mesh) and same.face_count == mesh.face_count
    assert edited_peak < plain_peak + len(TEXT) // 4, (plain_peak, edited_peak, len(TEXT))


@pytest.mark.parametrize("statement", [b"g\n", b"o part\n", b"s 1\n", b"usemtl a\n", b"usemtl a\nusemtl b\n",
                                       b"mtllib a.mtl\n"])
def test_statements_that_take_no_face_cost_no_memory(plain_peak: int, statement: bytes) -> None:
    """g, o and s are only counted, a usemtl no face follows is replaced by the next, and mtllib lines
    past the first 16 are not read: a file of them holds nothing per line (each was an 80-byte record,
    and a run per usemtl)."""
    outcome, lines, peak = load_counting(TEXT + statement * (len(TEXT) // len(statement)))
    assert isinstance(outcome, Mesh) and outcome.face_count == 2 * 119 * 119
    assert lines == 0
    assert peak < plain_peak + len(TEXT) // 8, (plain_peak, peak)


def test_records_are_never_copied_to_make_room(monkeypatch: pytest.MonkeyPatch) -> None:
    """A piece's records grow by chunks, each kept as it is, and the deferred lines among them are read
    as each chunk comes and then dropped: the largest chunk is the most held at once, where doubling
    one table held three times them while it was copied. One piece, so the count is exact."""
    monkeypatch.setattr(fast_reader, "MIN_PIECE_BYTES", 1 << 30)
    parse_obj(QUAD, "warm.obj")  # the compiled reader's code loaded (or compiled) before anything is weighed
    deferred = 16 * 2**12 + 1  # one record past a doubling: the worst case for a table that doubles
    outcome, lines, peak = load_counting(QUAD + b"v 1e-30 0 0\n" * deferred)  # an exponent the line reader reads
    assert isinstance(outcome, Mesh) and lines == deferred
    same, _, read_peak = load_counting(QUAD + b"v 1e-3 0 0\n" * deferred)  # the compiled pass reads these
    record_bytes = fast_reader.scan.RECORD_COLUMNS * 4  # int32: a text under 2 GiB
    assert peak - read_peak < deferred * record_bytes, (peak, read_peak, deferred * record_bytes)


def test_a_file_of_bad_lines_holds_the_records_before_the_first() -> None:
    """Each piece's deferred lines are read as its records come, so a bad one ends the piece: a file of
    millions of faces without corners holds a few chunks of records, not 40 bytes for each 2-byte
    line (20 times the file). What is left is the face table pass one counted, 4 bytes a face."""
    data = QUAD + b"f\n" * (len(TEXT) // 2)
    outcome, lines, peak = load_counting(data)
    assert error_of(outcome).line == 6
    assert peak < 3 * len(data), (peak, len(data))


def test_a_usemtl_before_every_face_is_one_run(plain_peak: int) -> None:
    """A usemtl naming the material the faces before it use is not recorded (the compiled pass compares
    it with the piece's last one) and goes on with their run (raw.MaterialRuns)."""
    faces = TEXT[TEXT.index(b"\nf ") + 1:]
    data = TEXT[:len(TEXT) - len(faces)] + faces.replace(b"\nf ", b"\nusemtl a\nf ")
    outcome, lines, peak = load_counting(data)
    assert isinstance(outcome, Mesh) and outcome.face_count == 2 * 119 * 119 and lines == 0
    assert peak < plain_peak + len(TEXT) // 8, (plain_peak, peak)
    assert fast_reader.read_fast(data, "runs.obj").material_runs.as_pairs() == [(1, "a")]


@pytest.mark.parametrize("comment", [b"# colour 255 0 0\n", b"# the colour is red\n", b"#color\n"])
def test_colour_comments_after_the_one_that_counts_cost_no_memory(plain_peak: int, comment: bytes,
                                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    """The first "# colour r g b" whose numbers the compiled code reads sets the colour, so none after
    it is recorded (one in each piece of the text at most); comments of another shape never are (each
    was an 80-byte record, made by the compiled code, where tracemalloc does not see it)."""
    settled: list[int] = []
    settle = fast_reader._Records.settle
    monkeypatch.setattr(fast_reader._Records, "settle",
                        lambda self, records, *rest: (settled.append(len(records)), settle(self, records, *rest))[1])
    outcome, lines, peak = load_counting(TEXT + comment * (len(TEXT) // len(comment)))
    assert sum(settled) <= fast_reader.PARSE_THREADS * fast_reader.PIECES_PER_THREAD * 4, settled
    assert isinstance(outcome, Mesh) and outcome.warnings == ()
    assert outcome.base_colour == ((1.0, 0.0, 0.0) if comment.startswith(b"# colour") else None)
    assert lines == 0
    assert peak < plain_peak + len(TEXT) // 8, (plain_peak, peak)


def test_blank_lines_say_no_faces_without_reading_a_line(plain_peak: int) -> None:
    outcome, lines, peak = load_counting(b"\n" * len(TEXT))
    assert error_of(outcome).message == "empty file: no faces"
    assert lines == 0
    assert peak <= 2 * plain_peak


def test_vertices_only_say_no_faces_without_reading_a_line() -> None:
    vertices = TEXT[:TEXT.index(b"\nf ") + 1]
    outcome, lines, _ = load_counting(vertices)
    assert error_of(outcome).message == "no faces (no 'f' statements)"
    assert lines == 0



@pytest.mark.parametrize("elements", [b"l 1 2 3 4 1\n", b"p 1 2 3 4\n"], ids=["a wireframe", "points"])
def test_a_wireframe_or_point_cloud_says_its_lines_and_points_are_not_drawn(elements: bytes) -> None:
    """A file of l lines alone said 'no faces (no 'f' statements)', as if it held nothing to show."""
    data = QUAD[:QUAD.index(b"f ")] + elements
    said = "no faces (no 'f' statements), and its l and p statements (lines and points) are not drawn"
    assert error_of(load_counting(data)[0]).message == said  # the compiled reader
    with pytest.raises(LoadError) as line_reader:
        read_by_lines(data, "w.obj")
    assert line_reader.value.message == said

def test_one_huge_vertex_line_is_counted_not_split() -> None:
    data = QUAD + b"v" + b" 1.5" * (len(TEXT) // 4) + b"\n"
    outcome, lines, peak = load_counting(data)
    error = error_of(outcome)
    assert error.line == 6
    assert error.message == "a vertex position (v) needs 3 to 7 numbers, found more than 8"
    assert lines <= 6
    assert peak <= 5 * len(data)  # a few copies of the line, not millions of tokens


def test_a_bad_line_in_the_middle_costs_one_line(plain_peak: int) -> None:
    lines_of_text = TEXT.split(b"\n")
    middle = len(lines_of_text) // 2
    lines_of_text[middle] = b"v 1 2"
    outcome, lines, peak = load_counting(b"\n".join(lines_of_text))
    error = error_of(outcome)
    assert (error.line, error.message) == (middle + 1, "a vertex position (v) needs 3 to 7 numbers, found 2")
    assert lines == 1
    assert peak <= 2 * plain_peak


def test_odd_but_valid_lines_cost_nothing_and_give_the_same_model() -> None:
    """A trailing comment, an exponent and a face of another corner format, late in the file; a number
    of 17 digits costs its line."""
    lines_of_text = TEXT.split(b"\n")
    at = len(lines_of_text) - 10
    lines_of_text[at] = lines_of_text[at] + b"  # the last faces"
    lines_of_text.insert(at, b"f 1 2 3")
    lines_of_text.insert(5, b"v 1e0 2E+0 -3.5e-1")
    lines_of_text.insert(6, b"v 0.12345678901234567 1 1")
    outcome, lines, _ = load_counting(b"\n".join(lines_of_text))
    assert isinstance(outcome, Mesh)
    assert lines == 1
    reference = parse_obj(TEXT, "hostile.obj")
    assert outcome.face_count == reference.face_count + 1
    np.testing.assert_array_equal(outcome.positions[5:7], [[1, 2, -0.35], [0.12345678901234567, 1, 1]])


def test_the_first_error_in_the_file_wins_whatever_kind_is_read_first() -> None:
    """Vertices are parsed before faces, but a bad face before a bad vertex is the one reported."""
    faces_at = TEXT.index(b"\nf ") + 1
    first_face_line = TEXT.count(b"\n", 0, faces_at) + 1
    bad_face = TEXT[:faces_at] + b"f 1 2\n" + TEXT[faces_at:] + b"v 1 2\n"
    error = error_of(load_counting(bad_face)[0])
    assert (error.line, error.message) == (first_face_line, "a face needs at least 3 vertices, found 2")
    bad_vertex_first = b"v 1 x 3\n" + TEXT + b"f 1 2\n"
    assert error_of(load_counting(bad_vertex_first)[0]).line == 1


def test_an_index_past_the_end_is_reported_after_errors_of_single_lines() -> None:
    """As the line reader does: a positive index may point forward, so it is checked at the end."""
    data = QUAD + b"f 1 2 99999999\n" + TEXT + b"v 1 2\n"
    error = error_of(load_counting(data)[0])
    assert (error.line, error.message) == (7 + TEXT_LINES, "a vertex position (v) needs 3 to 7 numbers, found 2")
    error = error_of(load_counting(QUAD + b"f 1 2 99999999\n" + TEXT)[0])
    assert error.line == 6 and error.message.startswith("vertex index 99999999 out of range")


def test_a_relative_index_reaching_before_the_first_names_its_line() -> None:
    data = TEXT + b"f -1 -2 -99999999\n"
    outcome, lines, _ = load_counting(data)
    error = error_of(outcome)
    assert error.line == TEXT_LINES + 1 and "reaches before the first one" in error.message
    assert lines == 1


def test_many_malformed_colour_comments_are_one_note() -> None:
    data = b"# colour red green blue\n" * 1000 + QUAD
    mesh = parse_obj(data, "colours.obj")
    assert mesh.warnings == ("ignored 1000 malformed '# colour' comments (the first on line 1)",)


# --- what people's editors write ------------------------------------------------------------------


def test_a_byte_order_mark_is_not_part_of_the_first_statement() -> None:
    mesh = parse_obj(b"\xef\xbb\xbf" + QUAD, "bom.obj")
    assert mesh.vertex_count == 4
    with pytest.raises(LoadError) as caught:
        parse_obj(b"\xef\xbb\xbfv 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n", "bom.obj")
    assert caught.value.line == 3


def test_cr_only_line_ends_are_line_ends() -> None:
    mesh = parse_obj(QUAD.replace(b"\n", b"\r"), "mac.obj")
    assert (mesh.vertex_count, mesh.face_count) == (4, 1)
    with pytest.raises(LoadError) as caught:
        parse_obj(b"v 0 0 0\rv 1 0 0\r\rv 0 1\r\nf 1 2 3\r", "mac.obj")
    assert caught.value.line == 4


def test_a_comment_ending_in_a_backslash_does_not_swallow_the_next_line() -> None:
    data = b"# exported from C:\\models\\\n" + QUAD
    with lines_read_by_python() as counted:
        mesh = parse_obj(data, "windows.obj")
    assert mesh.vertex_count == 4
    assert counted.lines == 0  # the comment alone does not send the file to the line reader
    assert parse_obj(b"v 0 0 0 # C:\\\n" + QUAD, "windows.obj").vertex_count == 5


def test_a_continued_statement_does_not_swallow_a_comment_line() -> None:
    mesh = parse_obj(b"v 0 0 0 \\\n# colour 255 0 0\n" + QUAD, "continued.obj")
    assert mesh.base_colour == (1.0, 0.0, 0.0)
    assert mesh.vertex_count == 5
    mesh = parse_obj(b"v 0 0 \\\n 0 # origin\n" + QUAD, "continued.obj")
    assert mesh.vertex_count == 5


def test_a_no_break_space_separates_like_a_space() -> None:
    nbsp = "\u00a0".encode()
    mesh = parse_obj(QUAD.replace(b" ", nbsp), "nbsp.obj")
    assert (mesh.vertex_count, mesh.face_count) == (4, 1)
    np.testing.assert_array_equal(mesh.positions[1], [2, 0, 0])


def test_a_material_library_name_too_long_for_the_file_system_is_a_note(tmp_path: Path) -> None:
    path = tmp_path / "long.obj"
    path.write_bytes(b"mtllib " + b"m" * 300 + b".mtl\n" + QUAD)
    mesh = load_obj(path)
    assert mesh.face_count == 1
    assert len(mesh.warnings) == 1 and "not found" in mesh.warnings[0]
    assert len(mesh.warnings[0]) < 200


def test_a_huge_material_library_is_a_note_and_is_not_read(tmp_path: Path) -> None:
    huge = tmp_path / "huge.mtl"
    with huge.open("wb") as stream:
        stream.truncate(2 << 30)  # sparse: costs no disk
    path = tmp_path / "model.obj"
    path.write_bytes(b"mtllib huge.mtl\n" + QUAD)
    mesh, peak = peak_traced_bytes(lambda: load_obj(path))
    assert isinstance(mesh, Mesh) and mesh.file_material is None
    assert len(mesh.warnings) == 1 and "too large" in mesh.warnings[0]
    assert peak < 1 << 24  # refused from its size, never read


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no named pipes here")
def test_a_material_library_that_is_a_pipe_is_a_note(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "pipe.mtl")
    path = tmp_path / "model.obj"
    path.write_bytes(b"mtllib pipe.mtl\n" + QUAD)
    outcome: list[Mesh] = []
    reader = threading.Thread(target=lambda: outcome.append(load_obj(path)), daemon=True)
    reader.start()
    reader.join(timeout=30)  # opening a pipe would block until someone writes
    assert outcome, "reading the material library blocked on a pipe"
    assert len(outcome[0].warnings) == 1 and "not a regular file" in outcome[0].warnings[0]


def test_many_malformed_material_lines_are_one_note(tmp_path: Path) -> None:
    (tmp_path / "bad.mtl").write_text("newmtl a\n" + "Kd x y z\n" * 1000 + "Ks 1 nan 1\nNs 5\n")
    path = tmp_path / "model.obj"
    path.write_bytes(b"mtllib bad.mtl\n" + QUAD)
    mesh = load_obj(path)
    assert mesh.file_material == {"ns": 5.0}
    assert mesh.warnings == ("material library 'bad.mtl': ignored 1001 malformed lines (the first a Kd line, on "
                             "line 2)",)


def test_a_material_line_of_a_million_numbers_is_never_a_list_of_them(tmp_path: Path) -> None:
    """An MTL line is split into a bounded number of words: a Kd line of a million numbers was held 44
    bytes a byte as a list of them and their floats."""
    (tmp_path / "long.mtl").write_text("newmtl a\nKd" + " 10" * 1_000_000 + "\nKs 0.5\nnewmtl " + "b " * 500 + "\n")
    path = tmp_path / "model.obj"
    path.write_bytes(b"mtllib long.mtl\n" + QUAD)
    mesh, peak = peak_traced_bytes(lambda: load_obj(path))
    assert mesh.file_material == {"ks": (0.5, 0.5, 0.5)}
    assert mesh.warnings == ("material library 'long.mtl': ignored a malformed Kd line, on line 2",)
    assert peak < 8 * (tmp_path / "long.mtl").stat().st_size, peak  # the text's bytes, piece, line and rest


def test_the_folder_of_textures_not_found_is_resolved_once_not_once_a_name(tmp_path: Path,
                                                                           monkeypatch: pytest.MonkeyPatch) -> None:
    """Each map_Kd name not found as written is looked for in any case in its folder's listing: the
    folder was resolved again for each name (a walk of its path, lstat by lstat), a third of the load of
    an MTL of thousands of missing pictures."""
    from marraztu.loaders.obj import mtl

    count = 200
    (tmp_path / "many.mtl").write_text("".join(f"newmtl m{at}\nmap_Kd missing{at}.png\n" for at in range(count)))
    vertices = "".join(f"v {at} {at % 2} 0\n" for at in range(count + 2))
    faces = "".join(f"usemtl m{at}\nf {at + 1} {at + 2} {at + 3}\n" for at in range(count))
    path = tmp_path / "model.obj"
    path.write_text(f"mtllib many.mtl\n{vertices}{faces}")
    resolved: list[Path] = []
    same_file_key = mtl.same_file_key
    monkeypatch.setattr(mtl, "same_file_key", lambda named: (resolved.append(named), same_file_key(named))[1])
    mesh = load_obj(path)
    assert f"{count} textures could not be read (the first, 'missing0.png': no such file)" in mesh.warnings[0]
    folders = [named for named in resolved if named == tmp_path]
    assert len(folders) <= 2, len(folders)
