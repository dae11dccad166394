"""What every text format's reader shares: a UTF-8 byte order mark (Notepad writes one) before the
first line is read past, as the OBJ reader reads past it, and the lines keep their numbers."""

from __future__ import annotations

from pathlib import Path

import pytest

from marraztu.errors import LoadError
from marraztu.loaders.files import BOM, bom_length
from marraztu.loaders.obj import load_obj
from marraztu.loaders.off import load_off
from marraztu.loaders.scenefile import read_scene_description
from marraztu.loaders.stl import load_stl

TRIANGLE_OFF = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
TRIANGLE_STL = ("solid part\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n"
                " endloop\nendfacet\nendsolid part\n")
MATERIALS = "newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n"
CAMERA = '[[cameras]]\nmodel = "m.obj"\nposition = [0, 0, 10]\n'


def written(folder: Path, name: str, text: str, bom: bool) -> Path:
    path = folder / name
    path.write_bytes((BOM if bom else b"") + text.encode())
    return path


def outcome(read: object) -> object:
    """What reading gives, as plain values: the positions and corners, or the error and its line."""
    try:
        mesh = read()  # type: ignore[operator]
    except LoadError as error:
        return error.message, error.line
    return mesh.positions.tolist(), mesh.corner_vertex.tolist()


def test_one_byte_order_mark_is_counted() -> None:
    assert [bom_length(text) for text in (b"", b"OFF", BOM, BOM + b"OFF", BOM + BOM)] == [0, 0, 3, 3, 3]


@pytest.mark.parametrize("load, name, text", [
    (load_off, "m.off", TRIANGLE_OFF),
    (load_off, "m.off", "OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 # a comment\n"),
    (load_off, "m.off", TRIANGLE_OFF.replace("3 0 1 2", "3 0 1 7")),  # refused at line 6 both ways
    (load_off, "m.off", "\n" + TRIANGLE_OFF.replace("0 1 0\n", "0 x 0\n")),
    (load_stl, "m.stl", TRIANGLE_STL),
    (load_stl, "m.stl", TRIANGLE_STL.replace("endsolid part\n", "")),  # its solid opened on line 1
    (load_stl, "m.stl", TRIANGLE_STL.replace("vertex 1 0 0", "vertex 1 0")),
    (load_stl, "m.stl", TRIANGLE_STL + "\0\0\x1a"),
])
def test_a_model_after_a_byte_order_mark_reads_as_without_it(tmp_path: Path, load, name: str, text: str) -> None:
    """Read past, it left '\\ufeffOFF' no OFF keyword and '\\ufeffsolid' no ASCII STL."""
    assert outcome(lambda: load(written(tmp_path, name, text, bom=True))) == \
        outcome(lambda: load(written(tmp_path, name, text, bom=False)))


def test_the_first_material_after_a_byte_order_mark_is_kept(tmp_path: Path) -> None:
    """'\\ufeffnewmtl' was no newmtl: the first material was lost without a note."""
    written(tmp_path, "m.mtl", MATERIALS, bom=True)
    model = written(tmp_path, "m.obj", "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n"
                                       "usemtl blue\nf 1 3 2\n", bom=False)
    mesh = load_obj(model)
    assert {material.name: material.values["kd"] for material in mesh.materials} == {
        "red": (1.0, 0.0, 0.0), "blue": (0.0, 0.0, 1.0)}


@pytest.mark.parametrize("text, expected", [
    (CAMERA, None),
    ('texture = "t.ppm"\n' + CAMERA, None),
    (CAMERA + "positon = [0, 0, 0]\n", ("cameras[1]: unknown key 'positon' (allowed: material, model, name, "
                                       "position, rotation, scale, texture)", 4)),
    (CAMERA + "model = 3\n", ("TOML syntax: model is set twice in one table", 4)),
])
def test_a_scene_after_a_byte_order_mark_reads_as_without_it(tmp_path: Path, text: str, expected: tuple | None) -> None:
    """tomllib reads no byte order mark: the first line was an 'Invalid statement'."""
    def read(bom: bool) -> object:
        try:
            return read_scene_description(written(tmp_path, "scene.toml", text, bom)).cameras[0].position
        except LoadError as error:
            return error.message, error.line

    (tmp_path / "m.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    assert read(bom=True) == read(bom=False) == (expected or (0.0, 0.0, 10.0))


@pytest.mark.parametrize("end", [b"\n", b"\r\n", b"\r", b"\n\r"])
def test_lines_are_read_a_piece_at_a_time_whatever_ends_them(monkeypatch, end: bytes) -> None:
    """A file whose lines end in a lone CR (classic Mac OS) was read as one piece, every line in one list
    beside the text copied twice: the pieces are now a few kilobytes for every line end, and the lines
    are the same as the whole text's."""
    from marraztu.loaders import files

    pieces: list[int] = []
    split = files._lines_of
    monkeypatch.setattr(files, "_lines_of", lambda piece: (pieces.append(len(piece)), split(piece))[1])
    rows = [f"v {number}.5 {number % 7}.25 0" for number in range(20_000)]
    data = end.join(row.encode() for row in rows) + end
    lines = list(files.text_lines(data))
    expected = split(data)
    assert lines == expected and len(pieces) > 10 and max(pieces) <= files._LINES_PIECE + 64


class _CountedBytes(bytes):
    """Bytes that count how far each find() looks: a line end looked for to the text's end for every piece
    makes a text of no \\n cost its length squared."""

    looked = 0

    def find(self, sub, start=None, end=None) -> int:  # type: ignore[override]
        start, end = 0 if start is None else start, len(self) if end is None else end
        found = super().find(sub, start, end)
        _CountedBytes.looked += max((end if found < 0 else found + 1) - start, 0)  # as far as it looked
        return found


@pytest.mark.parametrize("end", [b"\n", b"\r\n", b"\r", b"\n\r"])
def test_each_piece_looks_for_its_end_no_further_than_that_end(end: bytes) -> None:
    """A text whose lines end in a lone CR had every piece look for a \\n to the text's end: 16 MB of
    CR lines took five times as long as 8 MB. The text is looked through about once, whatever ends its lines."""
    from marraztu.loaders import files

    data = _CountedBytes(end.join(b"v 1.5 2.25 0" for _ in range(50_000)) + end)
    _CountedBytes.looked = 0
    lines = list(files.text_lines(data))
    assert lines == files._lines_of(bytes(data)) and _CountedBytes.looked <= 2 * len(data)
