"""OFF (Object File Format, Geomview's and the Princeton shape benchmark's), read here: its vertices,
its polygons as the file gives them, and COFF's vertex colours.

Why not trimesh's reader: it takes a face line with fewer indices than its count as a smaller face,
reads past words after a vertex's numbers, names no line for a bad number or index, fails with a
TypeError on some polygons and drops COFF's colours. This one reads a line at a time, makes the
numbers arrays a block of lines at a time, and names the line of the first problem.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from marraztu.errors import LoadError
from marraztu.loaders.files import read_model_bytes, text_lines
from marraztu.loaders.words import MAX_COUNT_DIGITS, checked_coordinates, checked_indices
from marraztu.model.build import derive_mesh
from marraztu.model.mesh import Mesh

_ROWS_AT_ONCE = 1 << 15  # rows whose words are made numbers in one call
# A polygon's colour may follow its indices: none, an index into a colour map, RGB or RGBA. Not read.
_FACE_COLOUR_WORDS = (0, 1, 3, 4)


def load_off(path: Path, stage: Callable[[str], None] | None = None) -> Mesh:
    """An OFF file's Mesh: its polygons as they are (as an OBJ's), tinted by COFF's vertex colours."""
    tables = read_off(path, read_model_bytes(path, stage))  # the bytes are freed on return
    try:
        mesh = derive_mesh(path.stem, tables.positions, tables.corner_vertex, tables.face_start, None, None, None,
                           None, ())
    except ValueError as error:  # more corners than 32-bit indices hold
        raise LoadError(path, str(error)) from None
    return mesh if tables.colours is None else replace(mesh, vertex_colours=_colour_bytes(path, tables.colours))


def _colour_bytes(path: Path, colours: np.ndarray) -> np.ndarray:
    """COFF writes colours as 0..255 or as 0..1: the file's largest value says which."""
    rgb = colours[:, :3] * (1.0 if colours.max(initial=0.0) > 1.0 else 255.0)
    if rgb.min(initial=0.0) < 0.0 or rgb.max(initial=0.0) > 255.0:
        raise LoadError(path, "a vertex colour is not within 0..255 (or 0..1)")
    return np.rint(rgb).astype(np.uint8)


@dataclass(frozen=True)
class OffTables:
    positions: np.ndarray  # (V, 3) float64
    corner_vertex: np.ndarray  # (C,) int64
    face_start: np.ndarray  # (F + 1,) int64
    colours: np.ndarray | None  # (V, 3 or 4) float64, COFF's, as the file writes them (0..255 or 0..1)


Row = tuple[int, list[str]]  # a line's number and its words before any '#'


class _Rows:
    """The lines that hold words, one at a time, remembering the last one's number (to name where a
    file ends too soon)."""

    def __init__(self, data: bytes) -> None:
        self.rows = _rows_with_words(data)
        self.line = 1

    def next(self) -> Row | None:
        row = next(self.rows, None)
        if row is not None:
            self.line = row[0]
        return row


def read_off(path: Path, data: bytes) -> OffTables:
    rows = _Rows(data)
    layout, vertices, faces = _header(path, rows)
    positions, colours = _vertex_rows(path, rows, vertices, layout)
    corner_vertex, face_start = _face_rows(path, rows, faces, vertices)
    return OffTables(positions, corner_vertex, face_start, colours)


def _rows_with_words(data: bytes) -> Iterator[Row]:
    """(line number, words before any #) of each line that has some, read a piece at a time."""
    for number, line in enumerate(text_lines(data), start=1):
        words = (line.split("#", 1)[0] if "#" in line else line).split()
        if words:
            yield number, words


# The keyword: [ST][C][N]OFF says the vertex rows also hold texture coordinates, a colour, a normal.
# ModelNet's files often run the vertex count on after it ("OFF1234 5678 0").
_KEYWORD = re.compile(r"(ST)?(C)?(N)?OFF(\d*)")


@dataclass(frozen=True)
class _Layout:
    """What a vertex row holds after its x y z: its normal (N), its colour (C: 3 or 4 numbers) and its
    texture coordinates (ST), in that order. Only the colour is read: the rest is derived."""

    normal: bool
    coloured: bool
    texture: bool

    def row_sizes(self) -> tuple[int, ...]:
        plain = 3 + 3 * self.normal + 2 * self.texture
        return (plain + 3, plain + 4) if self.coloured else (plain,)


def _header(path: Path, rows: _Rows) -> tuple[_Layout, int, int]:
    """The layout its keyword gives, and the vertex and face counts, on the keyword's line or the next."""
    first = rows.next()
    if first is None:
        raise LoadError(path, "empty file: no faces")
    number, words = first
    keyword = _KEYWORD.fullmatch(words[0].upper())
    if keyword is None:
        said = "not an OFF file (it does not start with 'OFF')"
        if words[0].upper().endswith("OFF"):
            said = f"{words[0][:40]}: only OFF, COFF, NOFF, STOFF and their blends are read (no 4 or n dimensions)"
        raise LoadError(path, said, line=number)
    counts = ([keyword[4]] if keyword[4] else []) + words[1:]
    if not counts:
        number, counts = rows.next() or (number, [])
    if len(counts) < 2 or not all(word.isdigit() and len(word) <= MAX_COUNT_DIGITS for word in counts[:2]):
        raise LoadError(path, "expected the vertex, face and edge counts", line=number)
    vertices, faces = int(counts[0]), int(counts[1])
    if faces == 0:
        raise LoadError(path, "the header declares no faces: nothing to draw", line=number)
    return _Layout(normal=bool(keyword[3]), coloured=bool(keyword[2]), texture=bool(keyword[1])), vertices, faces


def _taken(path: Path, rows: _Rows, count: int, what: str) -> Iterator[Row]:
    """The next `count` rows, or a LoadError where the file ends before them."""
    for _ in range(count):
        row = rows.next()
        if row is None:
            raise LoadError(path, f"the header counts {count} {what}, the file ends before them", line=rows.line)
        yield row


def _vertex_rows(path: Path, rows: _Rows, count: int, layout: _Layout
                 ) -> tuple[np.ndarray, np.ndarray | None]:
    """Each vertex row's x y z, and COFF's colour; the row holds what the keyword says, all numbers."""
    sizes = layout.row_sizes()
    colour_at = 3 + 3 * layout.normal
    blocks: list[np.ndarray] = []
    colour_blocks: list[np.ndarray] = []
    words_read: list[str] = []
    extra_words: list[str] = []  # checked to be numbers; the colour's kept
    lines: list[int] = []
    width = 0
    for number, words in _taken(path, rows, count, "vertices"):
        if len(words) not in sizes:
            wanted = " or ".join(map(str, sizes))
            raise LoadError(path, f"a vertex row holds {wanted} numbers here, this one {len(words)}", line=number)
        if width and len(words) != width:
            raise LoadError(path, f"a vertex row holds {width} numbers here, as the first one does; this one "
                                  f"{len(words)}", line=number)
        width = len(words)
        words_read += words[:3]
        extra_words += words[3:]
        lines.append(number)
        if len(lines) == _ROWS_AT_ONCE:
            _flush(path, blocks, words_read, colour_blocks, extra_words, lines)
            words_read, extra_words, lines = [], [], []
    _flush(path, blocks, words_read, colour_blocks, extra_words, lines)
    positions = np.concatenate(blocks).reshape(-1, 3)
    if not layout.coloured or not count:
        return positions, None
    extras = np.concatenate(colour_blocks).reshape(count, width - 3)
    return positions, extras[:, colour_at - 3:colour_at - 3 + width - sizes[0] + 3]


def _flush(path: Path, blocks: list[np.ndarray], words: list[str], extra_blocks: list[np.ndarray],
           extra_words: list[str], lines: list[int]) -> None:
    blocks.append(checked_coordinates(path, words, lambda at: lines[at // 3]))
    if extra_words:
        per_row = len(extra_words) // len(lines)
        extra_blocks.append(checked_coordinates(path, extra_words, lambda at: lines[at // per_row]))


def _face_rows(path: Path, rows: _Rows, count: int, vertices: int) -> tuple[np.ndarray, np.ndarray]:
    """Each face row's corner count n, its n vertex indices and perhaps a colour (not read). Held a
    block at a time as the rows come: never by the header's count, which a short file may exaggerate."""
    blocks: list[np.ndarray] = []
    size_blocks: list[np.ndarray] = []
    sizes: list[int] = []
    index_words: list[str] = []
    face_lines: list[int] = []
    for number, words in _taken(path, rows, count, "faces"):
        corners = int(words[0]) if words[0].isdigit() and len(words[0]) < 10 else -1
        if corners < 3:
            raise LoadError(path, f"a face's corner count must be a whole number of 3 or more, not '{words[0][:40]}'",
                            line=number)
        if len(words) - 1 - corners not in _FACE_COLOUR_WORDS:
            raise LoadError(path, f"a face of {corners} corners, this line holds {len(words) - 1} numbers after "
                                  "its count", line=number)
        sizes.append(corners)
        index_words += words[1:1 + corners]
        face_lines.append(number)
        if len(face_lines) == _ROWS_AT_ONCE:
            size_blocks.append(np.array(sizes, np.int64))
            blocks.append(_indices(path, index_words, face_lines, size_blocks[-1], vertices))
            sizes, index_words, face_lines = [], [], []
    size_blocks.append(np.array(sizes, np.int64))
    blocks.append(_indices(path, index_words, face_lines, size_blocks[-1], vertices))
    return np.concatenate(blocks), np.concatenate(([0], np.cumsum(np.concatenate(size_blocks))))


def _indices(path: Path, words: list[str], lines: list[int], sizes: np.ndarray, vertices: int) -> np.ndarray:
    ends = np.cumsum(sizes)
    return checked_indices(path, words, lambda at: lines[int(np.searchsorted(ends, at, side="right"))], vertices)
