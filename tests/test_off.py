"""The OFF reader: polygons kept as the file gives them, COFF's colours, ModelNet's run-on header, and
every problem refused at its line; the same positions and triangles as trimesh reads where it reads
the file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from marraztu.errors import LoadError
from marraztu.loaders import off, words
from marraztu.loaders.off import load_off
from marraztu.loaders.registry import load_model
from support.refusals import one_line_refusal, written
from support.work import peak_traced_bytes

SQUARE = ["0 0 0", "1 0 0", "1 1 0", "0 1 0"]


def off_text(vertices: list[str] = SQUARE, faces: tuple[str, ...] = ("3 0 1 2", "3 0 2 3"),
             header: str | None = None) -> str:
    header = header if header is not None else f"OFF\n{len(vertices)} {len(faces)} 0\n"
    return header + "".join(f"{row}\n" for row in vertices) + "".join(f"{row}\n" for row in faces)


def read(tmp_path: Path, text: str, name: str = "m.off"):
    return load_off(written(tmp_path, text, name))


def refusal(tmp_path: Path, text: str) -> LoadError:
    return one_line_refusal(lambda: read(tmp_path, text))


@pytest.mark.parametrize("seed", range(3))
def test_positions_and_triangles_are_those_trimesh_reads_from_its_own_export(tmp_path: Path, seed: int) -> None:
    rng = np.random.default_rng(seed)
    mesh = trimesh.Trimesh(rng.normal(size=(30, 3)) * 100, rng.integers(0, 30, (50, 3)), process=False)
    loaded = read(tmp_path, trimesh.exchange.off.export_off(mesh))
    assert np.allclose(loaded.positions, mesh.vertices, rtol=0, atol=1e-7)  # trimesh writes 8 decimals
    assert np.array_equal(loaded.corner_vertex.reshape(-1, 3), mesh.faces)


def test_polygons_stay_polygons_and_comments_and_blank_lines_are_read_past(tmp_path: Path) -> None:
    text = "# made by hand\nOFF\n\n5 2 0 # counts\n" + "".join(f"{row} # a vertex\n" for row in SQUARE) + \
        "2 0.5 0\n4 0 1 2 3\n\n3 2 4 3 255 0 0\n"
    mesh = read(tmp_path, text)
    assert mesh.face_sizes.tolist() == [4, 3] and mesh.corner_vertex.tolist() == [0, 1, 2, 3, 2, 4, 3]


@pytest.mark.parametrize("header", ["OFF 4 2 0\n", "OFF4 2 0\n", "off\n4 2\n"])
def test_the_counts_may_follow_the_keyword_on_its_line(tmp_path: Path, header: str) -> None:
    """ModelNet's files often run the vertex count on after OFF."""
    assert read(tmp_path, off_text(header=header)).face_count == 2


@pytest.mark.parametrize(("rows", "expected"), [
    (["0 0 0 255 0 0", "1 0 0 0 255 0", "1 1 0 0 0 255", "0 1 0 255 255 255"], [255, 0, 0]),
    (["0 0 0 1 0 0 1", "1 0 0 0 1 0 1", "1 1 0 0 0 1 1", "0 1 0 1 1 1 1"], [255, 0, 0]),
    (["0 0 0 0.5 0 0 1", "1 0 0 0 1 0 1", "1 1 0 0 0 1 1", "0 1 0 1 1 1 1"], [128, 0, 0]),
])
def test_coff_colours_tint_the_vertices(tmp_path: Path, rows: list[str], expected: list[int]) -> None:
    mesh = read(tmp_path, off_text(rows, header="COFF\n4 2 0\n"))
    assert mesh.vertex_colours is not None and mesh.vertex_colours[0].tolist() == expected


def test_a_noff_rows_normal_and_an_stoff_rows_coordinates_are_read_past(tmp_path: Path) -> None:
    normals = [f"{row} 0 0 1" for row in SQUARE]
    assert read(tmp_path, off_text(normals, header="NOFF\n4 2 0\n")).face_count == 2
    both = [f"{row} 0 0 1 255 0 0 0.5 0.5" for row in SQUARE]
    mesh = read(tmp_path, off_text(both, header="STCNOFF\n4 2 0\n"))
    assert mesh.vertex_colours is not None and mesh.vertex_colours[0].tolist() == [255, 0, 0]


@pytest.mark.parametrize("faces", [("3 0 1 2 255 0 0", "3 0 2 3"), ("3 0 2 3", "4 0 1 2 3 7"),
                                   ("3 0 1 2 0.5 0.25 1.0 0.75", "3 0 2 3")])
def test_a_faces_colour_is_read_past_with_a_note(tmp_path: Path, faces: tuple[str, ...]) -> None:
    mesh = read(tmp_path, off_text(faces=faces))
    assert mesh.face_count == 2 and mesh.vertex_colours is None
    assert mesh.warnings == ("colours given per face are not drawn, only those per vertex",)
    assert read(tmp_path, off_text()).warnings == ()


@pytest.mark.parametrize(("faces", "word"), [(("3 0 1 2", "3 0 2 3 255 0 x"), "x"), (("3 0 1 2", "3 0 2 3 red"), "red"),
                                             (("3 0 1 2", "3 0 2 3 1_0 0 0"), "1_0")])
def test_a_faces_colour_that_is_no_number_is_refused_at_its_line(tmp_path: Path, faces: tuple[str, ...],
                                                                  word: str) -> None:
    refused = refusal(tmp_path, off_text(faces=faces))
    assert (refused.message, refused.line) == (f"'{word}' is not a number", 8)


@pytest.mark.parametrize(("text", "line", "word"), [
    (off_text(faces=("3 0 1 2", "3 0 2 3 nan 0 0")), 8, "nan"),
    (off_text(faces=("3 0 1 2 0.5 0.5 0.5", "3 0 2 3 0.5 inf 0.5 1")), 8, "inf"),
    (off_text(faces=("3 0 1 2 1e400 0 0", "3 0 2 3")), 7, "1e400"),
    (off_text([f"{row} 1 0 0" for row in SQUARE[:3]] + ["0 1 0 NaN 0 0"], header="COFF\n4 2 0\n"), 6, "NaN"),
    (off_text([f"{row} 1 0 0 1" for row in SQUARE[:3]] + ["0 1 0 0.5 0.5 0.5 -inf"], header="COFF\n4 2 0\n"), 6,
     "-inf"),
])
def test_a_colour_that_is_not_finite_is_refused_at_its_line(tmp_path: Path, text: str, line: int, word: str,
                                                            monkeypatch: pytest.MonkeyPatch) -> None:
    """A face's NaN passed unread, and a vertex colour's was called a coordinate: both are numbers of
    the file's that are not finite, refused alike (whichever reader reads the body)."""
    refused = refusal(tmp_path, text)
    assert (refused.message, refused.line) == (f"'{word}' is not a finite number", line)
    assert outcome(tmp_path, text, monkeypatch) == (refused.message, line)


@pytest.mark.parametrize(("text", "line", "message"), [
    (off_text(faces=("4 0 1 2", "3 0 2 3")), 7, "a face of 4 corners, this line holds 3 numbers after its count"),
    (off_text(faces=("3 0 1 2 5 6", "3 0 2 3")), 7, "a face of 3 corners, this line holds 5 numbers after its count"),
    (off_text(faces=("2 0 1", "3 0 2 3")), 7, "a face's corner count must be a whole number of 3 or more, not '2'"),
    (off_text(faces=("x 0 1 2", "3 0 2 3")), 7, "a face's corner count must be a whole number of 3 or more, not 'x'"),
    (off_text(faces=("3 0 1 x", "3 0 2 3")), 7, "'x' is not a whole number"),
    (off_text(faces=("3 0 1 2.5", "3 0 2 3")), 7, "'2.5' is not a whole number"),
    (off_text(faces=("3 0 1 2", "3 0 2 1_0")), 8, "'1_0' is not a whole number"),
    (off_text(faces=("3 0 1 9", "3 0 2 3")), 7, "vertex index 9 out of range (the file has 4 vertices)"),
    (off_text(faces=("3 0 1 -1", "3 0 2 3")), 7, "vertex index -1 out of range (the file has 4 vertices)"),
    (off_text(faces=("3 0 1 99999999999999999999", "3 0 2 3")), 7,
     "vertex index 99999999999999999999 out of range (the file has 4 vertices)"),
    (off_text(["0 0", *SQUARE[1:]]), 3, "a vertex row holds 3 numbers here, this one 2"),
    (off_text(["0 0 0 x", *SQUARE[1:]]), 3, "a vertex row holds 3 numbers here, this one 4"),
    (off_text(["0 0 y", *SQUARE[1:]]), 3, "'y' is not a number"),
    # a megabyte of digits ending badly: read once, not once for every split of the digits
    (off_text(["0 0 " + "1" * (1 << 20) + "x", *SQUARE[1:]]), 3,
     f"'{'1' * 40}... (1048577 characters)' is not a number"),
    # a long word is shown shortened, and how long it is said: 400 digits are not shown as 40
    (off_text(faces=("3 0 1 " + "9" * 400, "3 0 2 3")), 7,
     f"vertex index {'9' * 40}... (400 digits) out of range (the file has 4 vertices)"),
    (off_text(faces=("9" * 400 + " 0 1 2", "3 0 2 3")), 7,
     f"a face's corner count must be a whole number of 3 or more, not '{'9' * 40}... (400 digits)'"),
    (off_text(faces=("3 0 1 2 " + "1" * 400 + "e400 0 0", "3 0 2 3")), 7,
     f"'{'1' * 40}... (404 characters)' is not a finite number"),
    (off_text() + "9" * 400 + "\n", 9, f"'{'9' * 40}... (400 digits)' after the 2 faces the header counts"),
    (off_text(header="N" * 60 + "OFF\n4 2 0\n"), 1,
     f"{'N' * 40}... (63 characters): only OFF, COFF, NOFF, STOFF and their blends are read (no 4 or n dimensions)"),
    (off_text([*SQUARE[:3], "0 1 nan"]), 6, "a vertex coordinate is not a finite number the GPU can hold"),
    (off_text([*SQUARE[:3], "0 1 1e39"]), 6, "a vertex coordinate is not a finite number the GPU can hold"),
    (off_text(header="OFF\n4 3 0\n"), 8, "the header counts 3 faces, the file ends before them"),
    (off_text(header="OFF\n4 1 0\n", faces=()), 6, "the header counts 1 face, the file ends before them"),
    ("OFF\n3 1 0\n", 2,
     "the header counts 3 vertices and 1 face, the file ends before them: the 0 bytes after the counts hold 0 rows "
     "at most"),
    ("OFF\n3 1 0\n \t\n\n", 2,  # a body of no words
     "the header counts 3 vertices and 1 face, the file ends before them: the 4 bytes after the counts hold 2 rows "
     "at most"),
    (off_text(header="OFF\n5 2 0\n"), 7, "a vertex row holds 3 numbers here, this one 4"),
    (off_text(header="OFF\n4 0 0\n"), 2, "the header declares no faces: nothing to draw"),
    (off_text() + "5 6 7\n", 9, "'5' after the 2 faces the header counts"),
    (off_text(header="OFF\n4 1 0\n"), 8, "'3' after the 1 face the header counts"),
    (off_text() + "# the end\n\n \t\n junk # more\n", 12, "'junk' after the 2 faces the header counts"),
    (off_text(header="OFF\nfour 2 0\n"), 2, "expected the vertex, face and edge counts"),
    (off_text(header="OFF\n4 \u00b2 0\n"), 2, "expected the vertex, face and edge counts"),  # '²'.isdigit()
    (off_text(faces=("\u0663 0 1 2", "3 0 2 3")), 7,
     "a face's corner count must be a whole number of 3 or more, not '\u0663'"),  # an Arabic-Indic 3
    (off_text(faces=("3 0 x 2", "3 0 1 99999999999999999999")), 7, "'x' is not a whole number"),  # the first
    (off_text(header="PLY\n4 2 0\n"), 1, "not an OFF file (it does not start with 'OFF')"),
    (off_text(header="4OFF\n4 2 0\n"), 1,
     "4OFF: only OFF, COFF, NOFF, STOFF and their blends are read (no 4 or n dimensions)"),
    (off_text(["0 0 0 255 0", *SQUARE[1:]], header="COFF\n4 2 0\n"), 3,
     "a vertex row holds 6 or 7 numbers here, this one 5"),
    (off_text([f"{row} 255 0 0" for row in SQUARE[:3]] + ["0 1 0 255 0 0 255"], header="COFF\n4 2 0\n"), 6,
     "a vertex row holds 6 numbers here, as the first one does; this one 7"),
])
def test_a_broken_off_is_refused_at_its_line(tmp_path: Path, text: str, line: int, message: str) -> None:
    refused = refusal(tmp_path, text)
    assert (refused.message, refused.line) == (message, line)


@pytest.mark.parametrize(("header", "line"), [("OFF\n4 100000000000 0\n", 2), ("OFF\n4 " + "9" * 5000 + " 0\n", 2),
                                              ("OFF" + "9" * 5000 + " 2 0\n", 1), ("OFF\n" + "9" * 20 + " 2 0\n", 2)])
def test_a_header_claiming_more_than_the_file_holds_is_refused_without_reserving_it(tmp_path: Path, header: str,
                                                                                      line: int) -> None:
    refused = refusal(tmp_path, off_text(header=header))
    assert refused.line == line and ("file ends before them" in refused.message
                                     or refused.message == "expected the vertex, face and edge counts")


@pytest.mark.parametrize(("header", "line", "counts"), [
    ("OFF\n3000000000 2 0\n", 2, "3000000000 vertices and 2 faces"),
    ("OFF3000000000 2 0\n", 1, "3000000000 vertices and 2 faces"),  # ModelNet's run-on count
    ("# made by hand\nOFF\n\n4 999999999999 0 # counts\n", 4, "4 vertices and 999999999999 faces"),
])
def test_counts_of_more_rows_than_the_file_holds_are_refused_at_the_header(tmp_path: Path, header: str, line: int,
                                                                           counts: str) -> None:
    """Three billion vertices in a file of six rows were read as rows until one broke: a face row was
    refused as a vertex row of 4 numbers, at line 7, blaming the row for the header's count. The counts
    are refused at their line from the file's size alone (a row is a line of a word at least), before
    anything is made by them."""
    path = written(tmp_path, off_text(header=header), "m.off")
    refused, peak = peak_traced_bytes(lambda: off.read_off(path, path.read_bytes()))
    rows = len(off_text(header=""))  # the bytes after the counts: 4 vertex rows and 2 face rows
    assert isinstance(refused, LoadError), refused
    assert (refused.message, refused.line) == (f"the header counts {counts}, the file ends before them: the {rows} "
                                               f"bytes after the counts hold {(rows + 1) // 2} rows at most", line)
    assert peak < 1 << 20


def test_a_form_feed_in_a_comment_ends_no_line(tmp_path: Path) -> None:
    """str.splitlines() ends lines at form feeds and separators too: a comment's would become a row."""
    mesh = read(tmp_path, off_text(header="OFF # written by \x0c a tool\n4 2 0\n"))
    assert mesh.face_count == 2
    refused = refusal(tmp_path, "# a\x0cb\n" + off_text(faces=("3 0 1 9", "3 0 2 3")))
    assert refused.line == 8


def test_leading_zeros_make_no_index_too_long(tmp_path: Path) -> None:
    mesh = read(tmp_path, off_text(faces=("3 0 1 " + "0" * 30 + "2", "3 0 2 3")))
    assert mesh.corner_vertex[:3].tolist() == [0, 1, 2]


def test_a_colour_past_255_is_refused_at_its_line(tmp_path: Path) -> None:
    rows = [f"{row} 300 0 0" for row in SQUARE]
    assert "nor the file's colours within 0..255" in refusal(tmp_path, off_text(rows, header="COFF\n4 2 0\n")).message
    rows = [f"{row} {255 if at != 2 else -1} 0 0" for at, row in enumerate(SQUARE)]
    refused = refusal(tmp_path, off_text(rows, header="COFF\n# a note\n4 2 0\n"))
    assert (refused.line, refused.message) == (6, "a vertex colour is not within 0..1, nor the file's colours within "
                                                  "0..255")


def test_the_first_bad_index_is_named_among_many(tmp_path: Path) -> None:
    """Indices are made numbers many faces at a time: the line is found again within the block."""
    faces = ("3 0 1 2",) * 40_000 + ("4 0 1 2 3",) * 30_000 + ("3 0 1 7",)
    refused = refusal(tmp_path, off_text(faces=faces))
    assert refused.line == 2 + 4 + 70_001 and refused.message.startswith("vertex index 7 out of range")


def test_reading_holds_blocks_of_words_not_a_list_of_every_line(tmp_path: Path) -> None:
    rows = [f"{x} 0.123456 1.5" for x in range(100_000)]
    faces = tuple(f"3 {a} {a + 1} {a + 2}" for a in range(100_000 - 2))
    path = tmp_path / "big.off"
    path.write_text(off_text(rows, faces))
    mesh, peak = peak_traced_bytes(lambda: load_off(path))
    mesh_bytes = sum(value.nbytes for value in vars(mesh).values() if isinstance(value, np.ndarray))
    assert mesh.face_count == 100_000 - 2
    # The bytes, the mesh and the arrays it is derived through, and one block of words (a list of every
    # line's words would be 30 MB more).
    assert peak < path.stat().st_size + 5 * mesh_bytes // 2 + (8 << 20), (peak, mesh_bytes)


@pytest.mark.parametrize("where", ["header", "vertex", "face"])
def test_a_line_of_a_million_words_is_never_a_list_of_them(tmp_path: Path, where: str) -> None:
    """A header line is split into its keyword and counts, a vertex row into at most 12 numbers, a face
    row into its count, corners and colour: a header with a million words after its counts was held
    31 bytes a byte as a list of them."""
    many = " 7" * 1_000_000
    text = {"header": off_text(header=f"OFF 4 2 0{many}\n"), "vertex": off_text([*SQUARE[:3], f"0 1 0{many}"]),
            "face": off_text(faces=("3 0 1 2", f"3 0 2 3{many}"))}[where]
    path = tmp_path / "long.off"
    path.write_text(text)
    outcome, peak = peak_traced_bytes(lambda: load_off(path))
    if where == "header":
        assert outcome.face_count == 2
    elif where == "vertex":
        assert (outcome.line, outcome.message) == (6, "a vertex row holds 3 numbers here, this one more than 12")
    else:
        assert (outcome.line, outcome.message) == (8, "a face of 3 corners, this line holds more than 7 numbers "
                                                      "after its count")
    assert peak < 5 * len(text), peak


def test_an_off_file_loads_through_the_registry_without_trimesh(tmp_path: Path) -> None:
    path = tmp_path / "square.off"
    path.write_text(off_text(faces=("4 0 1 2 3",)))
    mesh = load_model(path)
    assert (mesh.vertex_count, mesh.face_count, mesh.face_sizes.tolist()) == (4, 1, [4])


@pytest.mark.parametrize("word", ["\u0663", "\uff13", "\u00b3"])
def test_digits_of_other_scripts_are_no_number(tmp_path: Path, word: str) -> None:
    """float() and int() read '٣' (and numpy with them) as 3: a model file's numbers are ASCII."""
    refused = refusal(tmp_path, off_text([*SQUARE[:3], f"0 {word} 0"]))
    assert (refused.message, refused.line) == (f"'{word}' is not a number", 6)
    refused = refusal(tmp_path, off_text(faces=(f"3 0 1 {word}", "3 0 2 3")))
    assert (refused.message, refused.line) == (f"'{word}' is not a whole number", 7)


# --- the body read at once ---------------------------------------------------------------------------
def outcome(tmp_path: Path, text: str | bytes, monkeypatch: pytest.MonkeyPatch | None = None) -> tuple:
    """What reading gives, as plain values: its tables, or its error and line; by the line reader alone
    where `monkeypatch` is given."""
    path = tmp_path / "m.off"
    path.write_bytes(text.encode() if isinstance(text, str) else text)
    with pytest.MonkeyPatch.context() as patch:
        if monkeypatch is not None:
            patch.setattr(off, "_body_at_once", lambda *args: None)
        try:
            tables = off.read_off(path, path.read_bytes())
        except LoadError as error:
            return error.message, error.line
    colours = None if tables.colours is None else tables.colours.tolist()
    return (tables.positions.tolist(), tables.corner_vertex.tolist(), tables.face_start.tolist(), colours,
            tables.face_colours)


PLAIN_BODIES = [
    off_text(),
    off_text(faces=("4 0 1 2 3", "3 0 2 3")),
    off_text(header="OFF 4 2 0\n\n") + "\r\n",
    off_text(header="COFF\n4 2 0\n", vertices=[f"{row} 255 0 0 1" for row in SQUARE]),
    off_text(header="NOFF\n4 2 0\n", vertices=[f"{row} 0 0 1" for row in SQUARE]),
    "OFF\r\n4 1 0\r\n" + "".join(f"  {row}\t\r\n\r\n" for row in SQUARE) + "4 0 1 2 3" + " 0" * 0,
    off_text(vertices=[f"{i} {i * i % 7} 1e-3" for i in range(80)], faces=("70 " + " ".join(map(str, range(70))),)),
    # comments: on lines of their own, after a row's words, touching a word, ending at a lone \r
    "OFF\n4 2 0\n# the vertices\n" + "".join(f"{row} # a corner\n" for row in SQUARE) + "#\n3 0 1 2#x\r3 0 2 3\n",
    off_text(faces=("3 0 1 2 # \x0c a form feed ends no line 7 7", "3 0 2 3 #")),
    # faces with a colour: a colour map's index, RGB or RGBA, in bytes or fractions, on some rows only
    off_text(faces=("3 0 1 2 255 0 0", "3 0 2 3")),
    off_text(faces=("3 0 1 2 0.5 0.25 1.0 0.75", "4 0 1 2 3 7", "3 0 2 3 1e-1 .5 1")),
    off_text(vertices=[f"{i} {i * i % 7} 1e-3" for i in range(80)],
             faces=("70 " + " ".join(map(str, range(70))) + " 0.2 0.4 0.6", "3 0 1 2 12 34 56 78")),
]


@pytest.mark.parametrize("text", PLAIN_BODIES)
def test_a_plain_body_is_read_at_once_as_the_line_reader_reads_it(tmp_path: Path, text: str,
                                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    by_lines = outcome(tmp_path, text, monkeypatch)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(off, "_vertex_rows", lambda *args: pytest.fail("the line reader read a plain body"))
        assert outcome(tmp_path, text) == by_lines


@pytest.mark.parametrize("text", [
    off_text(faces=("3 0 1 2 # a comment", "3 0 2 3")),
    off_text(faces=("3 0 1 2 255 0", "3 0 2 3")),  # a colour of two words
    off_text(faces=("3 0 1 2 red", "3 0 2 3")),  # a colour that is no number: refused
    off_text(faces=("3 0 1 2.0 0.5 0.5 0.5", "3 0 2 3")),  # a fraction among the corners
    off_text(faces=("3 0 1 2", "2 0 1 3")),  # a count of 2 and a word more, as if a colour
    off_text(faces=("3 0 1 2 0.5 0.5 0.5", "3 0 2 3 1 2 3 4 5")),  # a colour of five words
    off_text(faces=("3 0 1 2 0.5 0.5 nan", "3 0 2 3")),
    off_text(faces=("3 0 1 2 0.5\x1c0.5 0.5", "3 0 2 3")),
    off_text(vertices=["0 0 0"], faces=("2147483648" + " 0" * 64,)),  # a count past int32 on a long row
    # more digits than Python's int() reads, leading zeros all the same: the index 2
    off_text(faces=("3 0 1 " + "0" * 4300 + "2 0.5 0.5 0.5", "3 0 2 3")),
    off_text(faces=("3 0 1 " + "0" * 4300 + "2 9 9 9", "3 0 2 3")),
    off_text(faces=("3 0 1 " + "0" * 4300 + "2", "3 0 2 3")),
    off_text(faces=("+3 0 1 2", "3 0 2 3")),
    off_text(faces=("3.0 0 1 2", "3 0 2 3")),
    off_text(faces=("3 0 1 2.0", "3 0 2 3")),
    off_text(faces=("3 0 -1 2", "3 0 2 3")),
    off_text(faces=("0000000000003 0 1 2", "3 0 2 3")),  # 13 digits: no count
    off_text(faces=("000000000003 0 1 0000000000002", "3 0 2 3")),  # 12 digits, and leading zeros: both read
    off_text(faces=("3 0 1 99999999999999999999", "3 0 2 3")),
    off_text(faces=("70 " + " ".join(["1"] * 71), "3 0 2 3")),  # a long row one word too long
    off_text(vertices=[*SQUARE[:3], "0 1 1e400"]),
    off_text(vertices=[*SQUARE[:3], "0 1 nan"]),
    off_text(vertices=[*SQUARE[:3], "0 1\x1c0"]),  # a separator str.split() splits at and numpy does not
    off_text(vertices=[*SQUARE[:3], "0 1 0\x00"]),
    off_text(faces=("3 0 1 2", "3 0 2 3", "junk after the faces")),
    off_text(faces=("3 0 1", "2 3 0 2 3")),  # the right numbers, on the wrong lines
    off_text(faces=("3 0 1 4", "3 0 2 3")),
])
def test_what_needs_the_line_reader_is_read_by_it(tmp_path: Path, text: str, monkeypatch: pytest.MonkeyPatch) -> None:
    assert outcome(tmp_path, text) == outcome(tmp_path, text, monkeypatch)


@pytest.mark.parametrize("seed", range(3))
def test_seeded_bodies_read_the_same_at_once_and_by_lines(tmp_path: Path, seed: int,
                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """Small pieces, so that rows and words are cut where a large file's are, and (seeds 1 and 2) small
    blocks of face words, so that rows of 5 or 66 words are read as a polygon of many corners is."""
    monkeypatch.setattr(words, "_WORDS_PIECE_BYTES", 16)
    monkeypatch.setattr(off, "_FACE_BLOCK_WORDS", [1 << 16, 4, 8][seed])
    monkeypatch.setattr(off, "_ROW_PIECE_BYTES", [1 << 18, 1, 16][seed])
    rng = np.random.default_rng(seed)
    for _ in range(60):
        vertices = int(rng.integers(1, 9))
        rows = [" ".join(f"{value:.{rng.integers(0, 5)}f}" for value in rng.normal(size=3)) for _ in range(vertices)]
        faces = []
        for _ in range(rng.integers(1, 6)):
            size = int(rng.choice([3, 4, 5, 66]))
            corners = [str(corner) for corner in rng.integers(0, vertices + (rng.random() < 0.05), size)]
            colour = [[], ["7"], [str(byte) for byte in rng.integers(0, 256, 3)],
                      [f"{part:.2f}" for part in rng.random(4)], ["0"] * int(rng.choice([2, 5]))][rng.integers(0, 5)]
            faces.append(" ".join([str(size), *corners, *colour]))
        text = off_text(rows, tuple(faces)).replace("\n", str(rng.choice(["\n", "\r\n", " \n\n", "\t\r"])))
        assert outcome(tmp_path, text) == outcome(tmp_path, text, monkeypatch)


@pytest.mark.parametrize("comment", ["", "# a comment\n"])
@pytest.mark.parametrize("last", ["3 0 1 4", "2 0 1", "3 0 1 2 red", "3 0 1 2\njunk after the faces", None])
def test_a_file_bad_at_its_end_is_read_by_lines_from_its_last_block_only(tmp_path: Path, last: str | None,
                                                                         comment: str,
                                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """An index out of range, a count of 2 or a colour of words in the last face row, words after the
    faces, or a file that ends before its last row: the line reader read the whole file again, four
    times a good file's time at 200,000 triangles. It reads on from the first block of rows not read at
    once, and names the same problem at the same line as reading the whole file by lines."""
    monkeypatch.setattr(off, "_FACE_BLOCK_WORDS", 64)  # blocks of 16 triangle rows
    faces = ["3 0 1 2"] * 999 + ([] if last is None else [last])
    text = off_text(faces=tuple(faces), header=f"OFF\n4 1000 0\n{comment}")
    by_lines = outcome(tmp_path, text, monkeypatch)
    assert isinstance(by_lines[0], str)  # refused
    lines_read = []
    line_reader = off._Rows.next
    monkeypatch.setattr(off._Rows, "next", lambda rows, *most: lines_read.append(rows) or line_reader(rows, *most))
    assert outcome(tmp_path, text) == by_lines
    assert len(lines_read) <= 2 + 16 + 2  # the header's, a block's rows, the last and one after


@pytest.mark.parametrize(("faces", "after"), [(2, "3 0 1 4\r"), (3, "3 0 2 3\r"), (1, "junk\r")])
def test_a_comment_between_a_lone_cr_and_a_newline_keeps_the_lines_after_it_numbered(
        tmp_path: Path, faces: int, after: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """An index out of range, a file that ends too soon, words after the faces: each at line 9. Taken
    out, the comment made "\\r# c\\n" one line end, and the line reader reading on named line 8."""
    text = f"OFF\r4 {faces} 0\r" + "\r".join(SQUARE) + "\r3 0 1 2\r# c\n" + after
    by_lines = outcome(tmp_path, text, monkeypatch)
    assert by_lines[1] == 9
    assert outcome(tmp_path, text) == by_lines


@pytest.mark.parametrize("seed", range(3))
def test_seeded_bodies_cut_short_or_run_on_read_the_same_at_once_and_by_lines(tmp_path: Path, seed: int,
                                                                           monkeypatch: pytest.MonkeyPatch) -> None:
    """Files that end before the header's rows, or hold rows after them, read on by lines from where
    the rows read at once end: the same tables or the same refusal as by lines alone."""
    monkeypatch.setattr(off, "_FACE_BLOCK_WORDS", [1 << 16, 4, 8][seed])
    rng = np.random.default_rng(seed)
    for _ in range(40):
        vertices = int(rng.integers(1, 6))
        rows = [" ".join(f"{value:.2f}" for value in rng.normal(size=3)) for _ in range(vertices)]
        faces = [" ".join(map(str, [3, *rng.integers(0, vertices + (rng.random() < 0.1), 3)]))
                 for _ in range(rng.integers(1, 8))]
        said = len(faces) + int(rng.integers(-2, 3))  # the header's count: too few, right or too many
        text = off_text(rows, tuple(faces), header=f"OFF\n{vertices} {max(said, 1)} 0\n")
        text = text[:-1] if rng.random() < 0.5 else text  # a last row with no line end, or with one
        text = text.replace("\n", str(rng.choice(["\n", "\r\n", " \n\n", "\t\r"])))
        assert outcome(tmp_path, text) == outcome(tmp_path, text, monkeypatch)


def test_a_file_of_triangles_costs_a_few_times_its_size(tmp_path: Path) -> None:
    """Read at once: the numbers and a few per line, where a list of every block's words cost fifteen
    times the file."""
    faces = 300_000
    path = tmp_path / "triangles.off"
    path.write_text("OFF\n11 %d 0\n" % faces + "".join(f"{i} {i * i % 7} 0\n" for i in range(11))
                    + "3 10 1 2\n" * faces)
    tables, peak = peak_traced_bytes(lambda: off.read_off(path, path.read_bytes()))
    assert tables.face_start.size == faces + 1
    assert peak < 8 * path.stat().st_size, (peak, path.stat().st_size)


def test_a_colour_of_one_huge_fraction_costs_a_few_times_its_size(tmp_path: Path) -> None:
    """Its face's words are found digits only or not a few bytes per byte at most, though one word is
    most of the text (an array of a word number per byte made it 24 times the file)."""
    path = tmp_path / "fraction.off"
    path.write_bytes(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 0." + b"1" * (8 << 20) + b" 0 0\n")
    tables, peak = peak_traced_bytes(lambda: off.read_off(path, path.read_bytes()))
    assert tables.corner_vertex.tolist() == [0, 1, 2]
    assert peak < 7 * path.stat().st_size, (peak, path.stat().st_size)


def test_a_body_of_comments_costs_a_few_times_its_size(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Taken out a piece at a time in numpy: a regular expression's substitution held an object per
    comment, 86 times the text for a comment on every line; read at once, not by the line reader."""
    monkeypatch.setattr(off, "_vertex_rows", lambda *args: pytest.fail("the line reader read the body"))
    path = tmp_path / "comments.off"
    path.write_bytes(off_text().replace("3 0 1 2", "#\n" * (4 << 20) + "3 0 1 2#\r").encode())
    tables, peak = peak_traced_bytes(lambda: off.read_off(path, path.read_bytes()))
    assert tables.corner_vertex.tolist() == [0, 1, 2, 0, 2, 3]
    assert peak < 4 * path.stat().st_size, (peak, path.stat().st_size)


def test_one_face_row_of_a_million_corners_is_made_numbers_a_piece_at_a_time(tmp_path: Path) -> None:
    corners = 1_000_000
    path = tmp_path / "polygon.off"
    path.write_bytes(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n%d " % corners + b" ".join([b"2", b"0", b"1"] * (corners // 3))
                     + b" 0\n")
    tables, peak = peak_traced_bytes(lambda: off.read_off(path, path.read_bytes()))
    assert tables.corner_vertex.size == corners
    # The text, the corners (4 bytes for each 2-byte word) and a few pieces' numbers, not all of them at once.
    assert peak < path.stat().st_size + tables.corner_vertex.nbytes + (6 << 20), (peak, path.stat().st_size)


@pytest.mark.parametrize("after", ["", "\n\n", "# written by hand\n", " \t\r\n# a\n\n#b"])
def test_blank_lines_and_comments_after_the_faces_are_read_past(tmp_path: Path, after: str,
                                                                monkeypatch: pytest.MonkeyPatch) -> None:
    by_lines = outcome(tmp_path, off_text() + after, monkeypatch)
    assert outcome(tmp_path, off_text() + after) == by_lines == outcome(tmp_path, off_text())


def test_lines_after_the_faces_are_refused_at_the_first_without_reading_on(tmp_path: Path) -> None:
    """The line reader stops at the first line of words after the header's faces; so does the count of
    each line's words."""
    path = tmp_path / "trailing.off"
    path.write_bytes(off_text().encode() + b"1\n" * 5_000_000)
    refused, peak = peak_traced_bytes(lambda: one_line_refusal(lambda: off.read_off(path, path.read_bytes())))
    assert (refused.message, refused.line) == ("'1' after the 2 faces the header counts", 9)
    assert peak < 2 * path.stat().st_size, (peak, path.stat().st_size)  # the text, and a piece's words counted


def test_a_long_face_row_followed_by_blank_lines_is_read_at_once(tmp_path: Path,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    """Its last pieces of text hold blanks only, which numpy alone would read as a number."""
    monkeypatch.setattr(off, "_ROW_PIECE_BYTES", 16)
    monkeypatch.setattr(off, "_FACE_BLOCK_WORDS", 8)
    text = off_text(faces=("3 0 1 2", "40 " + " ".join(["0", "1", "2", "3"] * 10) + "\n" * 100, "3 0 2 3"))
    by_lines = outcome(tmp_path, text, monkeypatch)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(off, "_vertex_rows", lambda *args: pytest.fail("the line reader read a plain body"))
        assert outcome(tmp_path, text) == by_lines


def test_one_long_comment_line_costs_a_few_times_its_size(tmp_path: Path) -> None:
    """Comments are taken out a piece of a fixed size at a time: cut only at line ends, the one long
    line was one piece, with an 8-byte number for each of its '#'s (25 times the file)."""
    path = tmp_path / "comment.off"
    path.write_bytes(b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 " + b"#" * (4 << 20) + b"\n")
    tables, peak = peak_traced_bytes(lambda: off.read_off(path, path.read_bytes()))
    assert tables.corner_vertex.tolist() == [0, 1, 2]
    assert peak < 4 * path.stat().st_size, (peak, path.stat().st_size)


@pytest.mark.parametrize("piece", [1, 2, 3, 7])
def test_comments_cut_anywhere_by_the_pieces_read_as_the_line_reader_reads_them(
        tmp_path: Path, piece: int, monkeypatch: pytest.MonkeyPatch) -> None:
    """A piece may begin inside a comment, on its '#', on the \\n of a \\r\\n or just after a comment's end."""
    rng = np.random.default_rng(piece)
    for _ in range(40):
        notes = [rng.choice(["", "#", " # a note", "#\t##x", "# 3 0 1 2"]) for _ in range(len(SQUARE) + 2)]
        ends = [str(rng.choice(["\n", "\r\n", "\r", " \n"])) for _ in notes]
        rows = [*SQUARE, "3 0 1 2", "3 0 2 3"]
        text = "OFF\n4 2 0\n" + "".join(f"{row}{note}{end}" for row, note, end in zip(rows, notes, ends))
        by_lines = outcome(tmp_path, text, monkeypatch)
        with pytest.MonkeyPatch.context() as patch:
            patch.setattr(off, "_UNCOMMENT_PIECE_BYTES", piece)
            patch.setattr(off, "_vertex_rows", lambda *args: pytest.fail("the line reader read a plain body"))
            assert outcome(tmp_path, text) == by_lines


def test_a_binary_off_is_named_as_such(tmp_path: Path) -> None:
    refused = refusal(tmp_path, "OFF BINARY\n" + "\n".join(SQUARE))
    assert (refused.message, refused.line) == ("a binary OFF file: only text OFF is read", 1)
