"""The STL reader: an ASCII file read line by line, strictly, naming the line that is wrong, or whole
facets at a time where it is the usual text, with the same corners; the same corners as trimesh reads
from what its exporters write; the binary one told apart by its size."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from marraztu.errors import LoadError
from marraztu.loaders import stl
from marraztu.loaders.registry import load_model
from marraztu.loaders.stl import stl_corners
from support.refusals import one_line_refusal
from support.work import peak_traced_bytes, python_lines_run

PATH = Path("m.stl")


def facet(corners: list[str], normal: str = "0 0 1", indent: str = "  ") -> str:
    lines = [f"facet normal {normal}", f"{indent}outer loop"]
    lines += [f"{indent * 2}vertex {corner}" for corner in corners]
    return "\n".join(lines + [f"{indent}endloop", "endfacet", ""])


TRIANGLE = ["0 0 0", "1 0 0", "0 1 0"]


def solid(*facets: str, name: str = "part") -> str:
    return f"solid {name}\n" + "".join(facets) + f"endsolid {name}\n"


def read(text: str | bytes) -> np.ndarray:
    return stl_corners(PATH, text.encode() if isinstance(text, str) else text)


def refusal(text: str | bytes) -> LoadError:
    return one_line_refusal(lambda: read(text))


@pytest.mark.parametrize("seed", range(4))
def test_the_corners_are_those_trimesh_reads_from_its_own_export(seed: int) -> None:
    rng = np.random.default_rng(seed)
    mesh = trimesh.Trimesh(rng.normal(size=(40, 3)) * 10.0 ** rng.integers(-3, 4), rng.integers(0, 40, (60, 3)),
                           process=False)
    text = trimesh.exchange.stl.export_stl_ascii(mesh)
    assert np.array_equal(read(text), mesh.vertices[mesh.faces].reshape(-1, 3))


def test_a_solid_named_with_a_keyword_is_read() -> None:
    """trimesh splits the text on the word 'vertex', the solid's name included."""
    corners = read(solid(facet(TRIANGLE), name="vertex_paint normal 1 2"))
    assert np.array_equal(corners, [[0, 0, 0], [1, 0, 0], [0, 1, 0]])


def test_keywords_in_any_case_blank_lines_tabs_and_crlf_are_read() -> None:
    text = "SOLID x\r\n\r\n FACET NORMAL 0 0 1\r\n\tOUTER LOOP\r\n" + "\tVERTEX 1e1 -2.5 +.5\r\n" * 3 + \
        " ENDLOOP\r\n EndFacet\r\n\r\nENDSOLID\r\n"
    assert np.array_equal(read(text), [[10, -2.5, 0.5]] * 3)


def test_several_solids_are_one_list_of_corners_and_the_normal_is_not_read() -> None:
    text = solid(facet(TRIANGLE)) + "\n" + solid(facet(["5 5 5", "6 5 5", "5 6 5"], normal="nan -nan 0"))
    assert read(text).shape == (6, 3)


def test_a_solid_without_facets_gives_no_corners() -> None:
    assert read("solid empty\nendsolid empty\n").shape == (0, 3)


@pytest.mark.parametrize(("text", "line", "message"), [
    (solid(facet(TRIANGLE)).replace("endsolid part\n", ""), 8, "the solid begun on line 1 is not closed by 'endsolid'"),
    (solid(facet(TRIANGLE)) + solid(facet(TRIANGLE))[:-len("endsolid part\n")], 17,
     "the solid begun on line 10 is not closed by 'endsolid'"),
    (solid(facet(TRIANGLE))[:40], 3, "the file ends inside a facet"),
    # A bad number before the line of another error is the first bad line, though words are read in blocks.
    (solid(facet(["0 0 0", "1 0 0", "x 0 0"])).split("\n  endloop")[0], 6, "'x' is not a number"),
    (solid(facet(["0 0 0", "1 0 0", "x 0 0"])).split("\n  endloop")[0] + "\n", 6, "'x' is not a number"),
    (solid(facet(["0 0 0", "1 0 x1", "0 1 0"])).replace("endsolid part\n", ""), 5, "'x1' is not a number"),
    (solid(facet(["0 0 0", "1 0 x1", "0 1 0"])).replace("endfacet", "endloop"), 5, "'x1' is not a number"),
    (solid(facet(["x 0 0", "1 0", "0 1 0"])), 4, "'x' is not a number"),
    (solid(facet(["0 0 0", "1 0 0", "0 1 nan"] + TRIANGLE)), 6,
     "a vertex coordinate is not a finite number the GPU can hold"),
    (solid(facet(TRIANGLE + ["0 0 1"])), 7, "a facet of more than 3 vertices: STL facets are triangles"),
    (solid(facet(TRIANGLE[:2])), 6, "a facet of 2 vertices: STL facets are triangles"),
    (solid(facet(["0 0 0", "1 0 x1", "0 1 0"])), 5, "'x1' is not a number"),
    (solid(facet(["0 0 0", "1 0 1_0", "0 1 0"])), 5, "'1_0' is not a number"),
    (solid(facet(["0 0 0", "1 0 0x10", "0 1 0"])), 5, "'0x10' is not a number"),
    (solid(facet(["0 0 0", "1 0 " + "1" * (1 << 20) + "e", "0 1 0"])), 5,
     f"'{'1' * 40}... (1048577 characters)' is not a number"),
    (solid(facet(TRIANGLE)).replace("vertex 1", "v" + "x" * 100 + " 1"), 5,
     f"expected 'vertex', found 'v{'x' * 39}... (101 characters)'"),
    (solid(facet(["0 0 0", "1 0 0", "0 1 nan"])), 6, "a vertex coordinate is not a finite number the GPU can hold"),
    (solid(facet(["0 0 0", "1e400 0 0", "0 1 0"])), 5, "a vertex coordinate is not a finite number the GPU can hold"),
    (solid(facet(["0 0 0", "1e39 0 0", "0 1 0"])), 5, "a vertex coordinate is not a finite number the GPU can hold"),
    (solid(facet(["0 0 0", "1 0", "0 1 0"])), 5, "a vertex line holds 3 numbers, this one 2"),
    (solid(facet(["0 0 0", "1 0 0 1", "0 1 0"])), 5, "a vertex line holds 3 numbers, this one 4"),
    (solid(facet(["0 0 0", "1 0 0 1 2  ", "0 1 0"])), 5, "a vertex line holds 3 numbers, this one 5"),
    (solid(facet(["0 0 0", "1 0 0 1 2 3 4", "0 1 0"])), 5, "a vertex line holds 3 numbers, this one more than 5"),
    (solid(facet(TRIANGLE)).replace("vertex 1", "vertx 1"), 5, "expected 'vertex', found 'vertx'"),
    (solid(facet(TRIANGLE)).replace("outer loop", "vertex 0 0 0"), 3, "expected 'outer loop', found 'vertex'"),
    (solid(facet(TRIANGLE)).replace("endfacet", "endloop"), 8, "expected 'endfacet', found 'endloop'"),
    (solid(facet(TRIANGLE)) + "garbage\n", 10, "expected 'solid' or the end of the file, found 'garbage'"),
    (solid(facet(TRIANGLE)).replace("endsolid part", "solid other"), 9,
     "expected 'facet' or 'endsolid', found 'solid'"),
])
def test_a_broken_ascii_stl_is_refused_at_its_line(text: str, line: int, message: str) -> None:
    refused = refusal(text)
    assert (refused.message, refused.line) == (message, line)


def test_the_first_bad_number_is_named_among_many() -> None:
    """Numbers are made floats many corners at a time: the line is found again within the block."""
    good = facet(TRIANGLE) * 20_000
    text = solid(good + facet(["0 0 0", "1 0 0", "0 1 bad"]))
    refused = refusal(text)
    assert (refused.message, refused.line) == ("'bad' is not a number", 1 + 20_000 * 7 + 5)


@pytest.mark.parametrize("padding", [b"\x1a", b"\0" * 300, b"\r\n\x1a\0\0\n"])
def test_padding_after_the_last_endsolid_is_read_past(padding: bytes) -> None:
    """DOS's end-of-file byte, or NULs, that some writers put at the end."""
    assert read(solid(facet(TRIANGLE)).encode() + padding).shape == (3, 3)





@pytest.mark.parametrize("padding", [b" " * (1 << 20) + b"\0", b"\0" * (1 << 20), b"\r\n\x1a\t" * (1 << 18)])
def test_a_megabyte_of_padding_is_read_past_in_a_few_steps(padding: bytes) -> None:
    """It is looked at a piece at a time by bytes' own loops: a Python step per byte took 1.2 s for
    8 MB of blanks and a NUL (150 s at the size limit)."""
    text = solid(facet(TRIANGLE)).encode() + padding
    steps = python_lines_run(lambda: stl._without_end_padding(text), stl.__file__)
    assert stl._without_end_padding(text) == solid(facet(TRIANGLE)).encode()[:-1] + b"\n"
    assert steps < 4 * len(padding) // stl._PADDING_PIECE_BYTES + 32, steps


@pytest.mark.parametrize("piece", [1, 2, 3, 5])
def test_padding_cut_anywhere_by_the_pieces_is_the_same_run(piece: int, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(stl, "_PADDING_PIECE_BYTES", piece)
    rng = np.random.default_rng(piece)
    for _ in range(200):
        tail = bytes(rng.choice(list(b"\0\x1a \t\r\nx"), int(rng.integers(0, 12))))
        data = b"solid" + tail
        end = len(data)
        while end and data[end - 1] in b"\0\x1a \t\r\n":
            end -= 1
        assert stl._padding_start(data) == end, data


def test_a_form_feed_ends_no_line() -> None:
    text = solid(facet(TRIANGLE)).replace("outer loop", "outer loop \x0c") + solid(facet(["0 0 0", "1 0 0", "x 1 0"]))
    assert refusal(text).line == 9 + 6  # the third vertex of the second solid's facet


def test_binary_data_after_solid_is_named() -> None:
    """A binary STL whose header begins with 'solid' and whose size does not match its count."""
    data = b"solid exported by some tool" + bytes(53) + (5).to_bytes(4, "little") + bytes(50 * 4)
    refused = refusal(data)
    assert refused.message.startswith("binary data after 'solid'") and refused.line == 1


def test_a_binary_stl_beginning_with_solid_is_read_as_binary() -> None:
    mesh = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], process=False)
    data = bytearray(trimesh.exchange.stl.export_stl(mesh))
    data[:5] = b"solid"
    assert np.array_equal(read(bytes(data)), mesh.vertices)


def binary_stl(attributes: list[int]) -> bytes:
    """Triangles along x, each with the given two attribute bytes (VisCAM and Magics keep colours there)."""
    data = bytearray(80) + len(attributes).to_bytes(4, "little")
    for index, attribute in enumerate(attributes):
        corners = np.array([[index, 0, 0], [index + 1, 0, 0], [index, 1, 0]], dtype="<f4")
        data += np.array([0, 0, 1], dtype="<f4").tobytes() + corners.tobytes() + attribute.to_bytes(2, "little")
    return bytes(data)


@pytest.mark.parametrize("attributes, said", [([0, 0, 0], False), ([0, 0x801F, 0], True), ([0x7C00] * 3, True)])
def test_facet_colours_in_the_attribute_bytes_are_said_not_drawn(tmp_path: Path, attributes: list[int],
                                                                 said: bool) -> None:
    """The bytes have no standard meaning, but every writer that fills them puts a colour there."""
    path = tmp_path / "painted.stl"
    path.write_bytes(binary_stl(attributes))
    mesh = load_model(path)
    assert mesh.face_count == 3
    assert (stl.ATTRIBUTES_NOTE in mesh.warnings) is said


@pytest.mark.parametrize("value", [np.inf, np.nan])
def test_a_binary_corner_that_is_no_finite_number_is_refused(tmp_path: Path, value: float) -> None:
    """A binary STL's corners are float32, held by the GPU: only infinity and NaN are refused."""
    data = bytearray(binary_stl([0]))
    data[96:100] = np.float32(value).tobytes()  # the first corner's x
    path = tmp_path / "unheld.stl"
    path.write_bytes(bytes(data))
    refused = one_line_refusal(lambda: load_model(path))
    assert refused.message == "a vertex coordinate is not a finite number the GPU can hold" and refused.line is None


@pytest.mark.parametrize("start", [b"", b"solidworks part\n", b"not solid\n"])
def test_a_file_that_does_not_start_with_solid_is_neither_kind(start: bytes) -> None:
    assert "does not start with 'solid'" in refusal(start + b"facet normal 0 0 1\n").message


def test_reading_holds_a_block_of_words_not_a_list_of_every_line() -> None:
    """Lines are split a piece at a time and numbers made floats a block at a time: beyond the corners
    read, the reader holds a few megabytes whatever the file's size."""
    text = solid(facet(["0.123456 1.234567 2.345678"] * 3) * 100_000).encode()
    corners, peak = peak_traced_bytes(lambda: read(text))
    assert corners.shape == (300_000, 3)
    assert peak < 2 * corners.nbytes + (8 << 20), peak


def test_a_solid_of_blank_lines_is_no_faces(tmp_path: Path) -> None:
    path = tmp_path / "blank.stl"
    path.write_bytes(b"solid x\n" + b" \n" * 100_000 + b"endsolid x\n")
    with pytest.raises(LoadError, match="no faces"):
        load_model(path)


def test_an_ascii_stl_with_a_keyword_in_its_name_loads_as_a_model(tmp_path: Path) -> None:
    path = tmp_path / "named.stl"
    path.write_text(solid(facet(TRIANGLE), facet(["1 0 0", "1 1 0", "0 1 0"]), name="vertex_paint"))
    mesh = load_model(path)
    assert (mesh.vertex_count, mesh.face_count) == (4, 2)


def test_a_line_of_many_words_is_never_a_list_of_them() -> None:
    """A line is split into at most six words, what any STL line needs: a solid's name of a million
    words held 26 bytes a byte as a list of them."""
    text = solid(facet(TRIANGLE), name="a " * 500_000).encode()
    corners, peak = peak_traced_bytes(lambda: read(text))
    np.testing.assert_array_equal(corners, [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    assert peak < 4 * len(text), peak


def test_the_usual_text_is_read_whole_facets_at_a_time() -> None:
    """trimesh's export, and keywords in capitals with CRLF, indents and blank lines: no call per line."""
    mesh = trimesh.Trimesh(np.random.default_rng(0).normal(size=(40, 3)), np.arange(60).reshape(-1, 3) % 40,
                           process=False)
    for text in (trimesh.exchange.stl.export_stl_ascii(mesh),
                 solid(facet(TRIANGLE, indent="\t"), "\n\n", facet(TRIANGLE)).upper().replace("\n", "\r\n")):
        blocks, rest = stl._usual_ascii_corners(text.encode())
        assert rest is None and np.array_equal(np.concatenate(blocks), read(text))


def _variant(rng: np.random.Generator) -> bytes:
    """An ASCII STL like a person's: a style of its own (keywords' case, line ends, indents), and in
    most files each part now and then written otherwise or wrongly."""
    oddness = float(rng.choice([0.0, 0.1, 1.0]))
    case = str(rng.choice(["lower", "upper", "title"]))
    newline, indent = str(rng.choice(["\n", "\r\n"])), str(rng.choice(["", "  ", "\t"]))

    def pick(*choices: str, odd: float = 0.1) -> str:
        return choices[0] if rng.random() >= odd * oddness else str(rng.choice(choices[1:]))

    def keyword(word: str) -> str:
        return pick(getattr(word, case)(), word.upper(), word[:-1], word + "x", "", odd=0.08)

    def blank() -> str:
        return pick(" ", "\t", "  ", "\v", "\f", "\xa0", "", odd=0.05)

    def end() -> str:
        return pick(newline, "\n", "\r\n", "\r", " \n", "\n\n", "\n \n", "\n\f\n", odd=0.05)

    def number() -> str:
        good = f"{rng.normal() * 10.0 ** rng.integers(-5, 6):.{rng.integers(0, 18)}{rng.choice(list('efg'))}}"
        return pick(good, str(rng.integers(-9, 10)), "-0", "+.5", "5.", "1e", ".", "1-2", "1_0", "nan", "inf",
                    "1e400", "1e39", "0x1", "1.5E+3", "\u0663", "", "1 2", odd=0.04)

    def line(words: list[str]) -> str:
        return pick(indent, "", "  ", "\t", odd=0.3) + blank().join(words) + end()

    def one_facet() -> str:
        text = line([keyword("facet"), pick("normal 0 0 1", "normal", "x", "", "facet", odd=0.2)])
        text += line([keyword("outer"), pick("loop", "", "vertex", odd=0.1)])
        for _ in range(int(pick("3", "2", "4", odd=0.03))):
            text += line([keyword("vertex"), number(), number(), number()])
        return text + line([keyword("endloop")]) + line([keyword("endfacet"), pick("", "x", odd=0.05)])

    def one_solid() -> str:
        name = pick("part", "", "facet", "endfacet", "vertex 1 2 3", "solid", "a\fb", odd=0.2)
        facets = "".join(one_facet() for _ in range(int(rng.integers(0, 6))))
        return line([keyword("solid"), name]) + facets + line([keyword("endsolid"), name])

    return "".join(one_solid() for _ in range(int(rng.integers(1, 4)))).encode("utf-8")


def _outcome(data: bytes) -> np.ndarray | str:
    try:
        return read(data)
    except LoadError as error:
        return str(error)


@pytest.mark.parametrize("piece", [1 << 20, 1, 200])
def test_the_reader_gives_what_the_line_reader_alone_gives(piece: int, monkeypatch: pytest.MonkeyPatch) -> None:
    """Seeded variants, in pieces of any size: the corners, bit for bit, or the same error on the same
    line, whether the whole-facet path read all of the text, part of it, or none."""
    monkeypatch.setattr(stl, "_FACETS_PIECE", piece)
    rng = np.random.default_rng(piece)
    wholly = partly = 0
    for _ in range(600):
        data = _variant(rng)
        rest = stl._usual_ascii_corners(data)[1]
        wholly, partly = wholly + (rest is None), partly + (rest is not None and rest > 0)
        outcome = _outcome(data)
        with monkeypatch.context() as lines_alone:
            lines_alone.setattr(stl, "_usual_ascii_corners", lambda text: ([], 0))
            expected = _outcome(data)
        if isinstance(expected, str):
            assert outcome == expected, data
        else:
            assert isinstance(outcome, np.ndarray) and np.array_equal(outcome.view(np.int64), expected.view(np.int64))
    assert wholly > 100 and partly > 20  # the variants reach both paths, and the hand-over between them


@pytest.mark.parametrize(("text", "rest"), [
    ("solid a\nendsolid a\n", 0),  # no facet: the line reader's, which finds no faces
    ("  \nENDSOLID \n", 0),  # no solid
    ("solid facet\n" + facet(TRIANGLE).split("\n", 1)[1] + "endsolid\n", 0),  # `facet` is the solid's name
    ("solid a\nendsolid a\nsolid b\n" + facet(TRIANGLE) + "endsolid b\n", 0),  # an empty solid first
    (solid(facet(TRIANGLE)).replace("\n", "\r"), 0),  # lines ended by CR alone
    (solid(facet(TRIANGLE), facet(["0 0 0", "1 0 0", "0 1 1e39"])), 0),  # past float32, in the first piece
    (solid(facet(TRIANGLE), facet(TRIANGLE)) + "garbage\n", len(solid(facet(TRIANGLE), facet(TRIANGLE)))
     - len("endsolid part\n")),  # after the last facet
    (solid(facet(TRIANGLE)) + "\n\n", None),  # all of it
])
def test_the_line_reader_reads_on_from_where_the_usual_path_stops(text: str, rest: int | None) -> None:
    assert stl._usual_ascii_corners(text.encode())[1] == rest


def test_an_error_after_many_usual_facets_is_named_by_the_line_reader_reading_on_from_the_last_good_piece(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """The pieces before the bad one are not read again; the lines named are the file's."""
    monkeypatch.setattr(stl, "_FACETS_PIECE", 1000)
    text = "solid a\n" + facet(TRIANGLE) * 20 + "endsolid a\n\n" + solid(facet(TRIANGLE) * 500)

    def line_of(text: str, part: str) -> int:
        return text[:text.index(part)].count("\n") + 1

    cut = text[:-len("endsolid part\n")]
    assert stl._usual_ascii_corners(cut.encode())[1] == len(cut)  # all but the missing endsolid
    refused = refusal(cut)
    assert (refused.message, refused.line) == (
        f"the solid begun on line {line_of(cut, 'solid part')} is not closed by 'endsolid'", cut.count("\n"))
    bad = text.replace("0 1 0", "0 1 x", 401).replace("0 1 x", "0 1 0", 400)
    assert 1000 < stl._usual_ascii_corners(bad.encode())[1] < len(bad) - 1000
    refused = refusal(bad)
    assert (refused.message, refused.line) == ("'x' is not a number", line_of(bad, "0 1 x"))
