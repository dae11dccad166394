"""The STL reader: an ASCII file read line by line, strictly, naming the line that is wrong; the same
corners as trimesh reads from what its exporters write; the binary one told apart by its size."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import trimesh

from marraztu.errors import LoadError
from marraztu.loaders.registry import load_model
from marraztu.loaders.stl import stl_corners
from support.refusals import one_line_refusal
from support.work import peak_traced_bytes

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
    (solid(facet(TRIANGLE + ["0 0 1"])), 7, "a facet of more than 3 vertices: STL facets are triangles"),
    (solid(facet(TRIANGLE[:2])), 6, "a facet of 2 vertices: STL facets are triangles"),
    (solid(facet(["0 0 0", "1 0 x1", "0 1 0"])), 5, "'x1' is not a number"),
    (solid(facet(["0 0 0", "1 0 1_0", "0 1 0"])), 5, "'1_0' is not a number"),
    (solid(facet(["0 0 0", "1 0 0x10", "0 1 0"])), 5, "'0x10' is not a number"),
    (solid(facet(["0 0 0", "1 0 " + "1" * (1 << 20) + "e", "0 1 0"])), 5, f"'{'1' * 40}' is not a number"),
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
