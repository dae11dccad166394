"""A PLY file's header read here, and an ASCII body made the binary body it stands for, for trimesh.

Why not trimesh's ASCII reader: it holds one numpy array per line, many times the file's size, fails
on blank lines, casts 1.5 or 300 into an index or a byte without a word, and names no line. Here the
body becomes numbers in one call, each property is checked against its type where the file gives it,
and the rows are written as the little-endian binary body that trimesh reads without parsing, so
that what trimesh makes of it is what it makes of a binary file. trimesh's binary reader takes one
corner count for a whole face element, and splits quads into triangles in an order of its own: faces
of more than three corners are fanned into triangles first, in the file's order, and their sizes
kept, so that the loader makes the polygons again of trimesh's triangles
(marraztu.model.mesh.polygon_corners_of_fans). A binary body is read the same way
(vertices_and_faces) where trimesh's reader would refuse it (faces of mixed lengths), split it its
own way (every quad's first triangle, then every second one, from its third corner) or make of it
what the viewer cannot use (a path of an edge element).
"""

from __future__ import annotations

import functools
import re
import struct
from array import array
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, replace
from pathlib import Path
from typing import NamedTuple, Protocol

import numpy as np

from marraztu.errors import LoadError, shortened
from marraztu.loaders.files import line_at, line_end_from, text_lines
from marraztu.loaders.words import (
    DECIMAL_BYTES,
    MAX_COUNT_DIGITS,
    is_count,
    outruns,
    pieces_at_gaps,
    shortened_bytes,
    text_numbers,
    unheld_coordinate,
    words_and_line_ends,
)
from marraztu.model.geometry import FLOAT32_MAX, holds_in_float32
from marraztu.model.mesh import corners_of_polygons, counted, fan_gather

# The property types PLY names, as trimesh reads them (its float16 and 64-bit integers too).
PLY_TYPES = {"char": "i1", "uchar": "u1", "short": "i2", "ushort": "u2", "int": "i4", "uint": "u4",
             "float": "f4", "double": "f8", "int8": "i1", "uint8": "u1", "int16": "i2", "uint16": "u2",
             "int32": "i4", "uint32": "u4", "int64": "i8", "uint64": "u8", "float16": "f2", "float32": "f4",
             "float64": "f8"}
FORMATS = {"ascii": "ascii", "binary_little_endian": "<", "binary_big_endian": ">"}
FACE_LISTS = ("vertex_indices", "vertex_index")  # the names exporters give a face's corners
STRIPS = "tristrips"  # scanalyze's and VCG's element: one list of triangle strips, -1 between two
TEXCOORD_LIST = "texcoord"  # MeshLab's: u v for each corner of the face
# A model's header declares a few elements of a few properties each: past this many, it is no model's.
MAX_DECLARATIONS = 4096
# The header's lines that say nothing of the body ("": a blank line, or the first, 'ply').
_REMARKS = ("", "comment", "obj_info")
_NOT_FINITE = re.compile(rb"(?i)[+-]?(?:nan|inf|infinity)")  # numpy reads these too: refused later where wrong
_END_WORD = "end_header"
_NOT_A_PLY = "not a PLY file (no 'ply' ... 'end_header' header)"
_END_LINE = re.compile(rb"[\r\n][ \t]*+end_header[ \t]*+(?=[\r\n]|\Z)")  # a line end leads: re looks for it fast


class ForTrimesh(NamedTuple):
    """A binary PLY that trimesh's reader takes as it is, the sizes of the one face element's polygons
    where they were fanned into its triangles (None where trimesh's triangles are the file's), and what
    of the file it does not hold (notes)."""

    data: bytes
    face_sizes: np.ndarray | None = None
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class PlyProperty:
    name: str
    value_type: str  # PLY's name of the value's type (a list's items')
    count_type: str | None = None  # a list's count's; None for a single value

    def declaration(self) -> str:
        if self.count_type is None:
            return f"property {self.value_type} {self.name}"
        return f"property list {self.count_type} {self.value_type} {self.name}"


@dataclass(frozen=True)
class PlyElement:
    name: str
    count: int
    properties: tuple[PlyProperty, ...]


# An element's rows as trimesh's binary reader takes them: the element and each property's values.
_Table = tuple[PlyElement, list[np.ndarray]]


@dataclass(frozen=True)
class PlyHeader:
    encoding: str  # a FORMATS value
    elements: tuple[PlyElement, ...]
    picture: str | None  # what a 'TextureFile' names (MeshLab's comment), the last as trimesh reads it
    body_at: int  # the offset of the body's first byte
    # whether a comment holds the word end_header: trimesh ends the header at any line that does
    comment_ends_it_for_trimesh: bool = False

    def count(self, name: str) -> int:
        return sum(element.count for element in self.elements if element.name == name)

    def text(self, encoding: str, elements: tuple[PlyElement, ...]) -> bytes:
        """A header of the given encoding and elements that names this one's picture."""
        lines = ["ply", f"format {encoding} 1.0", *([f"comment TextureFile {self.picture}"] if self.picture else [])]
        for element in elements:
            lines.append(f"element {element.name} {element.count}")
            lines.extend(prop.declaration() for prop in element.properties)
        return ("\n".join([*lines, "end_header"]) + "\n").encode("utf-8")


def read_header(path: Path, data: bytes) -> PlyHeader:
    """The header's format, elements and properties, each line checked; a LoadError names the line."""
    end = _end_line(data)
    if not data.startswith(b"ply") or (end < 0 and _END_WORD.encode() not in data):
        raise LoadError(path, _NOT_A_PLY, line=1)
    encoding, picture, elements = None, None, []
    comment_ends_it = False
    properties: list[list[PlyProperty]] = []
    filled: set[str] = set()  # the names of the vertex and face elements of rows so far
    element_lines: list[int] = []
    number, declared = 1, 0
    # With the word but no line of it alone, the lines are read until the one holding it is refused.
    header_lines = text_lines(data[:end] if end >= 0 else data)
    for number, line in enumerate(header_lines, start=1):  # a line at a time: never a list of them
        words = line.split(None, 5)
        keyword = words[0] if words and number > 1 else ""
        if _END_WORD in line and _END_WORD in line.split():
            comment_ends_it = True
            _check_end_word_in_comment(path, keyword, line, number)
        if keyword == "format":
            encoding = _encoding(path, words, number, encoding)
        elif keyword in ("element", "property"):
            declared += 1
            if declared > MAX_DECLARATIONS:
                raise LoadError(path, f"more than {MAX_DECLARATIONS} elements and properties: no model's header",
                                line=number)
            if keyword == "element":
                elements.append(_element(path, words, number, filled))
                properties.append([])
                property_names: set[str] = set()
                element_lines.append(number)
            elif not elements:
                raise LoadError(path, "a property before any element", line=number)
            else:
                properties[-1].append(_property(path, words, number, elements[-1], property_names))
        elif "texturefile" in line.lower():  # on any other line, as trimesh reads it
            picture = _picture_named(line)
        elif keyword not in _REMARKS:  # trimesh passed over it: a header cut or run together
            if end < 0 and _END_WORD not in line:  # no line ended the header: a body, the word in a comment or past
                raise LoadError(path, _NOT_A_PLY, line=1)
            raise LoadError(path, f"'{shortened(keyword)}' begins no PLY header line: a line is a format, element, "
                                  "property, comment or obj_info", line=number)
    if end < 0:  # the word only in comments, and no body: no line ends the header
        raise LoadError(path, _NOT_A_PLY, line=1)
    if encoding is None:
        raise LoadError(path, "the header has no 'format' line", line=number + 1)
    checked, body_at = _checked_elements(path, elements, properties, element_lines), line_end_from(data, end)
    if encoding == "ascii":
        _check_ascii_rows_fit(path, checked, element_lines, len(data) - body_at)
    return PlyHeader(encoding, checked, picture, body_at, comment_ends_it)


def _encoding(path: Path, words: list[str], line: int, encoding_so_far: str | None) -> str:
    """The FORMATS value a 'format' line names, where it is the header's first."""
    if encoding_so_far is not None:  # trimesh read the last one, numpy the body as that
        raise LoadError(path, "a second 'format' line: a PLY's header has one", line=line)
    if len(words) != 3 or words[1] not in FORMATS:
        raise LoadError(path, "expected 'format ascii 1.0' or a binary_little_endian or binary_big_endian "
                              "format", line=line)
    return FORMATS[words[1]]


def _picture_named(line: str) -> str | None:
    """What a header line names after the word TextureFile, in any case, as trimesh reads it."""
    return line[line.lower().index("texturefile") + len("texturefile"):].strip() or None


def _checked_elements(path: Path, elements: list[PlyElement], properties: list[list[PlyProperty]],
                      element_lines: list[int]) -> tuple[PlyElement, ...]:
    """The elements given their properties, a vertex element of rows checked to have its coordinates and
    a face element of rows its list of corners."""
    elements = [replace(element, properties=tuple(props)) for element, props in zip(elements, properties)]
    for element, line in zip(elements, element_lines):
        if element.name == "vertex" and element.count:
            _check_coordinates(path, element, line)
        if element.name == "face" and element.count and _corner_list(element) is None:
            raise LoadError(path, "element face has no list of its corners (property list uchar int vertex_indices)",
                            line=line)
    return tuple(elements)


_LEAST_NUMBER_BYTES = 2  # an ASCII body's number: a byte and a blank after it (the last one's may be missing)


def _check_ascii_rows_fit(path: Path, elements: tuple[PlyElement, ...], element_lines: list[int], held: int) -> None:
    """An ASCII body's counts refused at their line where the `held` bytes after the header cannot hold
    that many rows, before the body is read: a row holds a number a property at least (a list's count,
    of no items). One row is let off, so that a row that is there, however wrong (a last one cut short),
    is left to be named at its line; the element named is the first whose rows the bytes cannot hold."""
    rows = [(element, line, len(element.properties)) for element, line in zip(elements, element_lines)
            if element.count and element.properties]
    least = sum(element.count * numbers for element, _, numbers in rows)
    if not rows or not outruns(least - max(numbers for _, _, numbers in rows), _LEAST_NUMBER_BYTES, held + 1):
        return
    so_far = 0
    for element, line, numbers in rows:
        so_far += element.count * numbers
        if outruns(so_far, _LEAST_NUMBER_BYTES, held + 1):
            raise LoadError(path, f"{_ended(path, element).message}: the {counted(held, 'byte')} after the header "
                                  f"hold {counted((held + 1) // _LEAST_NUMBER_BYTES, 'number')} at most", line=line)


def _end_line(data: bytes) -> int:
    """Where the header's last line starts: the first line of 'end_header' alone, blanks around it (the
    word in a comment, 'no end_header here', ends nothing); -1 where there is none. The file begins
    'ply', so that line follows a line end."""
    found = _END_LINE.search(data) if _END_WORD.encode() in data else None  # the word alone is found sooner
    return -1 if found is None else found.start() + 1


def _check_end_word_in_comment(path: Path, keyword: str, line: str, number: int) -> None:
    """The word end_header on a header line before its end: trimesh ends the header there, so it may
    stand only in a comment, which is left out of the header handed to trimesh."""
    if keyword in ("comment", "obj_info") and "texturefile" not in line.lower():
        return
    raise LoadError(path, "'end_header' on a line of other words: the header ends at a line of 'end_header' alone, "
                          "and before it only a comment (not a TextureFile's) may hold the word", line=number)


def _element(path: Path, words: list[str], line: int, filled: set[str]) -> PlyElement:
    """The element a line declares; `filled`, the names of those of rows before it, takes its own."""
    if len(words) != 3:
        raise LoadError(path, "expected 'element', a name and a count", line=line)
    if not is_count(words[2]):
        raise LoadError(path, _not_a_count(words[1], words[2]), line=line)
    # trimesh keeps one table of each name (an empty one, and elements other than these, are left out)
    if int(words[2]) and words[1] in _KEPT_ELEMENTS:
        if words[1] in filled:
            raise LoadError(path, f"a second element named {shortened(words[1])} with rows", line=line)
        filled.add(words[1])
    return PlyElement(words[1], int(words[2]), ())


def _not_a_count(element: str, word: str) -> str:
    if word.isascii() and word.isdecimal():  # past MAX_COUNT_DIGITS
        return (f"element {shortened(element)}: {shortened(word)} rows are more than a file holds (a count has at "
                f"most {MAX_COUNT_DIGITS} digits)")
    return f"element {shortened(element)}: '{shortened(word)}' is not a count"


def _property(path: Path, words: list[str], line: int, element: PlyElement, names: set[str]) -> PlyProperty:
    """The property a line declares; `names`, the element's so far, takes its name."""
    types = words[2:4] if words[1:2] == ["list"] else words[1:2]
    if len(words) != 3 + 2 * (words[1:2] == ["list"]):
        raise LoadError(path, "expected 'property', a type and a name, or 'property list', two types and a name",
                        line=line)
    if words[-1] in names:  # a row's fields are named: numpy refuses two of a name
        raise LoadError(path, f"element {shortened(element.name)}: a second property named {shortened(words[-1])}",
                        line=line)
    names.add(words[-1])
    if element.name == "vertex" and words[-1] in ("x", "y", "z") and len(types) == 2:  # numpy fails to promote it
        raise LoadError(path, f"vertex {words[-1]} is a list: a coordinate is one number", line=line)
    unknown = [kind for kind in types if kind not in PLY_TYPES]
    if unknown:
        raise LoadError(path, f"'{shortened(unknown[0])}' is not a PLY type", line=line)
    if len(types) == 2:
        if PLY_TYPES[types[0]][0] == "f":
            raise LoadError(path, f"a list's count must be of a whole-number type, not {types[0]}", line=line)
        return PlyProperty(words[4], types[1], types[0])
    return PlyProperty(words[2], types[0])


def _check_coordinates(path: Path, element: PlyElement, line: int) -> None:
    """A vertex element's x, y and z, which trimesh reads (or fails in numpy's words)."""
    names = {prop.name for prop in element.properties}
    missing = [name for name in "xyz" if name not in names]
    if missing:
        raise LoadError(path, f"element vertex has no property {missing[0]}: a vertex's coordinates are x, y and z",
                        line=line)


def _corner_list(element: PlyElement) -> str | None:
    """The name of a face element's list of corners as trimesh reads it: vertex_indices (or vertex_index),
    or the one property of an element of one list, whatever its name; None where there is none."""
    lists = [prop.name for prop in element.properties if prop.count_type is not None]
    named = [name for name in lists if name in FACE_LISTS]
    return named[0] if named else lists[0] if len(element.properties) == 1 and lists else None


# --- the ASCII body -------------------------------------------------------------------------------
def binary_of_ascii(path: Path, data: bytes, header: PlyHeader, most_triangles: int) -> ForTrimesh:
    """The binary little-endian PLY file that holds what `data`, an ASCII one, holds: every number
    checked against its property's type, every face's corners against the vertex count, and the
    triangles they fan into against `most_triangles`, before they are made."""
    body = _Body(path, data, header.body_at, _numbers(path, data, header.body_at))
    tables, at = [], 0
    sizes: list[np.ndarray] = []
    for element in header.elements:
        columns, uniform, at = _element_columns(body, element, at)
        for column in columns:
            _check_type(body, element, column)
            _check_coordinate(body, element, column)
        if not columns:  # no rows, or no properties: nothing of it for trimesh to read
            continue
        table, _, fanned = _table_for_trimesh(header, element, columns, uniform, body, most_triangles)
        tables.append(table)
        if fanned is not None:
            sizes.append(fanned)
    _check_rows_fill_the_body(body, at)
    tables, sizes, notes = _strips_made_faces(tables, sizes)
    return ForTrimesh(_written(header.text("binary_little_endian", tuple(element for element, _ in tables)), tables),
                      _face_sizes(header, sizes), notes)


def _table_for_trimesh(header: PlyHeader, element: PlyElement, columns: list[_Column], uniform: bool,
                       places: _Places, most_triangles: int) -> tuple[_Table, bool, np.ndarray | None]:
    """The element's rows as trimesh's binary reader takes them, whether they are the file's own, and
    the sizes of the faces fanned: faces of more than three corners fanned, triangle strips made faces;
    another element's lists left out where they vary (trimesh draws nothing of them). `places` makes
    the error of a bad index, as _face_corners says."""
    vertices = header.count("vertex")
    strips = _strip_triangles(element, columns, vertices, places)
    if strips is not None:
        return strips, False, None
    corners = _face_corners(element, columns, vertices, places)
    if corners is not None and (not uniform or corners.values.shape[1] > 3):
        assert corners.counts is not None
        check_triangles(places.path, int(corners.counts.sum()) - 2 * len(corners.counts), most_triangles)
        return _fanned(element, columns, corners), False, corners.counts
    if not uniform:
        return _without_lists(element, columns), False, None
    return (element, [column.values for column in columns]), True, None


def check_triangles(path: Path, triangles: int, most: int) -> None:
    """Refuses faces that make more triangles than the viewer draws from one model."""
    if triangles > most:
        raise LoadError(path, f"its faces make {triangles} triangles: more than the {most} the viewer draws "
                              "from one model")


def _face_sizes(header: PlyHeader, fanned: list[np.ndarray]) -> np.ndarray | None:
    """The fanned polygons' sizes, where the file's one face element of rows was fanned (trimesh reads
    one; an empty one is left out before it)."""
    faces = sum(element.name == "face" and element.count > 0 for element in header.elements)
    return fanned[0] if faces == 1 and len(fanned) == 1 else None


def _numbers(path: Path, data: bytes, body_at: int) -> np.ndarray:
    """Every number of the body, in order, as float64; a LoadError names the line of a word that is none."""
    body = data[body_at:]
    if not body or body.isspace():  # numpy reads a body of blanks alone as [-1]
        return np.empty(0)
    try:
        return text_numbers(body)
    except ValueError:
        del body
        raise _first_bad_word(path, data, body_at) from None


def _first_bad_word(path: Path, data: bytes, body_at: int) -> LoadError:
    """The error of the first word of the body that numpy would not read: numpy finds its piece, and
    only that piece's words are looked at one by one."""
    for start, stop in pieces_at_gaps(data, body_at):
        piece = data[start:stop]
        if piece.isspace():
            continue
        try:
            text_numbers(piece)
            continue
        except ValueError:
            pass
        for found in re.finditer(rb"\S++", piece):
            if not DECIMAL_BYTES.fullmatch(found[0]) and not _NOT_FINITE.fullmatch(found[0]):
                word = shortened_bytes(found[0], _as_text)
                return LoadError(path, f"'{word}' is not a number", line=line_at(data, start + found.start()))
    return LoadError(path, "its body could not be read as numbers")


def _as_text(word: bytes) -> str:
    return word.decode("utf-8", errors="replace")


def _ended(path: Path, element: PlyElement, line: int | None = None) -> LoadError:
    """The body ends before the rows of `element` its header counts (a binary body names no line)."""
    return LoadError(path, f"the header counts {counted(element.count, 'row')} of {shortened(element.name)}, the file "
                           "ends before them", line=line)


_LINE_PIECE_BYTES = 1 << 16
_WORD = re.compile(rb"\S++")  # a word of the body: bytes' \s is numpy's blanks


class _Places(Protocol):
    """Where a body's numbers lie: the error of a problem at a number's place, and a number as the file
    gives it."""

    path: Path

    def error(self, message: str, index: int) -> LoadError: ...

    def shown(self, value: float, index: int) -> str: ...


@dataclass(frozen=True)
class _BinaryPlaces:
    """A binary body's: its values are exact as read, and it has no line to name."""

    path: Path

    def error(self, message: str, index: int) -> LoadError:
        return LoadError(self.path, message)

    def shown(self, value: float, index: int) -> str:
        return _shown(value)


class _Body:
    """The body's numbers, the file, to name the line of one of them, and where the rows read so far
    start, to say where they stop beginning lines."""

    def __init__(self, path: Path, data: bytes, body_at: int, numbers: np.ndarray) -> None:
        self.path, self.data, self.body_at, self.numbers = path, data, body_at, numbers
        # Each element's row starts in [first, stop), by the element (those of no rows have none).
        self.row_starts: dict[str, Callable[[int, int], np.ndarray]] = {}

    def error(self, message: str, index: int) -> LoadError:
        """A LoadError at the line of the number at `index`; and where rows that began lines stopped
        doing so up to it, led by the line of the row before the first that does not, with the numbers
        that line holds and its row does: a row that holds a number too many or too few shifts every row
        after it, and the error shows only where one no longer makes sense."""
        line, shift = self._lines(index)
        if shift is None:
            return LoadError(self.path, message, line=line)
        culprit = line_at(self.data, shift.row_at)
        held = len(_WORD.findall(self.data, shift.row_at, line_end_from(self.data, shift.row_at)))
        return LoadError(self.path, f"line {culprit} holds {counted(held, 'number')} where {self._row_of(shift)}, "
                                    f"so the rows after it no longer begin lines (line {line}: {message})",
                         line=culprit)

    def _row_of(self, shift: _Shift) -> str:
        """What the row that began the shift holds, by its element: its counts read from it."""
        name = next(name for name, rows in self.row_starts.items() if rows(shift.row, shift.row + 1).size)
        return f"a {shortened(name)} row of these properties holds {shift.next_row - shift.row}"

    def shown(self, value: float, index: int) -> str:
        """The number at `index` as the file writes it, shortened: its value may not be (400 nines are
        read as inf, 24 digits as 1.2345678901234569e+23)."""
        passed = 0
        for start, words, _ in self._words_by_piece(pieces_at_gaps(self.data, self.body_at)):
            if index < passed + len(words):
                word = _WORD.match(self.data, start + int(words[index - passed]))
                return shortened(word[0].decode("ascii", "replace")) if word else _shown(value)
            passed += len(words)
        return _shown(value)

    def ended(self, element: PlyElement) -> LoadError:
        """_ended at the body's last line."""
        return _ended(self.path, element, line=line_at(self.data, max(len(self.data.rstrip()) - 1, 0)))

    def numbers_beginning_lines(self) -> np.ndarray:
        """Per number of the body, whether it is the first word of its line."""
        pieces = pieces_at_gaps(self.data, self.body_at, _LINE_PIECE_BYTES)  # a line end's 8 bytes a piece
        return np.concatenate([np.empty(0, bool), *(begins for _, _, begins in self._words_by_piece(pieces))])

    def _words_by_piece(self, pieces: Iterable[tuple[int, int]]) -> Iterator[tuple[int, np.ndarray, np.ndarray]]:
        """For each (start, stop) piece of the body, in order: its start, where each of its words starts
        within it, and whether each word begins its line."""
        after_line_end = True  # the body starts on a line of its own
        for start, stop in pieces:
            words, ends_before, ends = words_and_line_ends(
                np.frombuffer(self.data, np.uint8, count=stop - start, offset=start))
            # a line ended between the word before and this one
            yield start, words, np.diff(np.concatenate(([-1 if after_line_end else 0], ends_before))) > 0
            after_line_end = bool(ends > ends_before[-1]) if len(words) else (after_line_end or bool(ends))

    def _lines(self, index: int) -> tuple[int, _Shift | None]:
        """The line of the number at `index`, and the row before the first row up to it that does not
        begin its line, after two or more that do; counted a piece at a time, up to that number only."""
        passed, aligned, shift = 0, 0, None
        last_row, last_row_at = 0, self.body_at  # the last row start seen: its number, and its offset
        for start, words, begins_line in self._words_by_piece(pieces_at_gaps(self.data, self.body_at)):
            if shift is None and aligned >= 0:
                starts = np.concatenate([np.empty(0, np.int64), *(rows(passed, min(passed + len(words), index + 1))
                                                                   for rows in self.row_starts.values())])
                misplaced = np.flatnonzero(~begins_line[starts - passed])
                if misplaced.size:
                    first = int(misplaced[0])
                    if first:
                        last_row, last_row_at = int(starts[first - 1]), start + int(words[starts[first - 1] - passed])
                    shift = _Shift(last_row, last_row_at, int(starts[first])) if aligned + first >= 2 else None
                    aligned = -1  # a file whose rows never began lines packs them: no hint
                elif starts.size:
                    aligned += len(starts)
                    last_row, last_row_at = int(starts[-1]), start + int(words[starts[-1] - passed])
            if index < passed + len(words):
                return line_at(self.data, start + int(words[index - passed])), shift
            passed += len(words)
        return line_at(self.data, len(self.data)), shift


class _Shift(NamedTuple):
    """The last row that began its line before one that does not: its first number, that number's offset in
    the file, and the next row's first number."""

    row: int
    row_at: int
    next_row: int


def _check_rows_fill_the_body(body: _Body, at: int) -> None:
    """Rows the header's counts place wrong, which the counts alone cannot show: a number left over
    after the last row, or, in an element whose first rows began lines, a row that does not (a row
    of one number too many and a later one of one too few shift the rows between, and balance)."""
    if at < len(body.numbers):
        raise body.error(f"{counted(len(body.numbers) - at, 'number')} after the rows the header counts", at)
    begins: np.ndarray | None = None
    for name, rows in body.row_starts.items():
        starts = rows(0, len(body.numbers))
        if starts.size < 3:
            continue
        begins = body.numbers_beginning_lines() if begins is None else begins
        # Rows of a line each: the first two begin lines, and no other of their numbers does (a file
        # may spread its numbers over lines as it likes, or pack its rows into a few)
        one_a_line = (begins.size == len(body.numbers) and begins[starts[0]] and begins[starts[1]]
                      and not begins[starts[0] + 1:starts[1]].any() and not begins[starts[1] + 1:starts[2]].any())
        if one_a_line and not begins[starts].all():
            row = int(np.argmin(begins[starts]))
            raise body.error(f"{name} row {row + 1} does not begin its line, as the rows before it do",
                             int(starts[row]))  # led by the line of the row before it (_Body.error)


class _WalkedStarts:
    """The starts of the rows walked so far, for _Body's hint while the walk goes on."""

    def __init__(self, starts: np.ndarray) -> None:
        self.starts, self.known = starts, 0

    def __call__(self, first: int, stop: int) -> np.ndarray:
        done = self.starts[:self.known]  # ascending: rows are walked in order
        return done[np.searchsorted(done, first):np.searchsorted(done, stop)]  # not a mask of every row a piece


@dataclass(frozen=True)
class _Column:
    """One property's numbers: a value by row, or a list's items and each row's count."""

    prop: PlyProperty
    values: np.ndarray  # (rows,); a list's (rows, count) where every row has one count, else row after row
    index: Callable[[int], int]  # where the k-th of values (in row order) lies among the body's numbers
    counts: np.ndarray | None = None  # (rows,) a list's
    count_index: Callable[[int], int] | None = None  # where a row's count of a list lies


def _element_columns(body: _Body, element: PlyElement, at: int) -> tuple[list[_Column], bool, int]:
    """The element's columns from `at`, whether every row has the first row's counts, and where the
    next element starts. Such rows are views of one table; only where a count differs are the rows
    walked one by one."""
    if not element.count or not element.properties:
        return [], True, at
    first_counts, width = _walked_row(body, element, at)
    columns = _one_table_columns(body, element, at, first_counts, width)
    if columns is not None:
        return columns, True, at + width * element.count
    if not first_counts or at + element.count * len(element.properties) > len(body.numbers):
        raise body.ended(element)  # before anything is made by the count: each row holds a number a property
    columns, at = _walked_element(body, element, at, len(first_counts))
    return columns, False, at


def _one_table_columns(body: _Body, element: PlyElement, at: int, first_counts: list[int], width: int
                       ) -> list[_Column] | None:
    """The columns where every row has the first row's counts, and so its `width`: views of one table
    from `at`. None where the body ends before the table or some row's count differs."""
    end = at + width * element.count
    if end > len(body.numbers):
        return None
    table = body.numbers[at:end].reshape(element.count, width)
    counts = np.array(first_counts, np.int64)
    columns, count_offsets = _table_columns(element, table, at, counts)
    if not all((table[:, offset] == count).all() for offset, count in zip(count_offsets, counts)):
        return None
    body.row_starts[element.name] = lambda first, stop: np.arange(
        at + -(-max(first - at, 0) // width) * width, min(stop, end), width)
    return columns


def _walked_element(body: _Body, element: PlyElement, at: int, lists: int) -> tuple[list[_Column], int]:
    """The columns of rows of mixed counts from `at`, walked row by row (those _quick_rows cannot take
    one at a time), and where the next element starts."""
    starts, counts = np.empty(element.count, np.int64), np.empty((element.count, lists), np.int64)
    walked = _WalkedStarts(starts)
    body.row_starts[element.name] = walked
    quick, at = _quick_rows(body, element, at, starts, counts)
    walked.known = quick
    for row in range(quick, element.count):  # each row's length is known only once its counts are read
        starts[row], walked.known = at, row + 1
        counts[row], width = _walked_row(body, element, at)
        at += width
    return _walked_columns(body, element, starts, counts), at


def _quick_rows(body: _Body, element: PlyElement, at: int, starts: np.ndarray, counts: np.ndarray
                ) -> tuple[int, int]:
    """Rows of one list each (a face's corners), walked from `at` into `starts` and `counts` up to the
    first whose count is bad: how many rows, and where the next starts. _walked_row takes that one,
    and names what is wrong with it."""
    lists = [(number, prop.count_type) for number, prop in enumerate(element.properties) if prop.count_type]
    if len(lists) != 1:
        return 0, at
    # Every other property is one number, so the list's count lies `before` numbers into its row.
    (before, count_type), = lists
    stride, size = len(element.properties), len(body.numbers)  # stride: a row's numbers less its items
    numbers, walked, row = memoryview(body.numbers), array("q", [0]) * len(starts), 0
    try:
        for row in range(len(starts)):  # checked after: every row up to the first bad one is found right
            walked[row] = at
            at += stride + int(numbers[at + before])
        row = len(starts)
    except (IndexError, ValueError, OverflowError):  # past the numbers, NaN or infinite: a bad row
        pass
    found_starts = np.frombuffer(walked, np.int64, count=row)
    found = body.numbers[found_starts + before]
    good = (found >= 0) & (found <= _most(count_type)) & (found == np.trunc(found))
    good &= found_starts + stride + found <= size
    if not good.all():  # the rows after the first bad one were found by a wrong count: dropped
        row = int(np.argmin(good))
        at = int(found_starts[row])
    starts[:row], counts[:row, 0] = found_starts[:row], found[:row]
    return row, at


def _walked_row(body: _Body, element: PlyElement, at: int) -> tuple[list[int], int]:
    """The counts of the row at `at`, each checked, and how many numbers the row holds."""
    counts, position = [], at
    for prop in element.properties:
        if prop.count_type is not None:
            if position >= len(body.numbers):
                raise body.ended(element)
            count = float(body.numbers[position])
            if not (0 <= count <= _most(prop.count_type) and count == int(count)):
                raise body.error(f"{shortened(element.name)} {shortened(prop.name)}: {body.shown(count, position)} is "
                                 f"no {prop.count_type} count ({_range(prop.count_type, counts=True)})", position)
            counts.append(int(count))
            position += int(count)
        position += 1
    if position > len(body.numbers):
        raise body.ended(element)
    return counts, position - at


def _table_columns(element: PlyElement, table: np.ndarray, at: int, counts: np.ndarray
                   ) -> tuple[list[_Column], list[int]]:
    """Columns of rows that all have these counts, views of the table; and where in a row each list's
    count lies."""
    columns, count_offsets, offset, width = [], [], 0, table.shape[1]
    for prop in element.properties:
        if prop.count_type is None:
            columns.append(_Column(prop, table[:, offset], lambda k, o=offset: at + k * width + o))
            offset += 1
            continue
        count = int(counts[len(count_offsets)])
        count_offsets.append(offset)
        where = lambda k, o=offset + 1, c=max(count, 1): at + (k // c) * width + o + k % c  # noqa: E731
        columns.append(_Column(prop, table[:, offset + 1:offset + 1 + count], where,
                               np.full(len(table), count, np.int64), lambda row, o=offset: at + row * width + o))
        offset += 1 + count
    return columns, count_offsets


def _walked_columns(body: _Body, element: PlyElement, starts: np.ndarray, counts: np.ndarray) -> list[_Column]:
    """Columns of rows of mixed counts: each value, and each list's items one row after another, gathered."""
    columns, passed, lists = [], np.zeros(len(starts), np.int64), 0
    for index, prop in enumerate(element.properties):
        at = starts + index + passed  # a value, or a list's count
        if prop.count_type is None:
            columns.append(_Column(prop, body.numbers[at], lambda k, at=at: int(at[k])))
            continue
        count = counts[:, lists]
        items = corners_of_polygons(at + 1, count)  # each row's items, its list's first after its count
        columns.append(_Column(prop, body.numbers[items], lambda k, items=items: int(items[k]), count,
                               lambda row, at=at: int(at[row])))
        passed, lists = passed + count, lists + 1
    return columns


def _check_type(body: _Body, element: PlyElement, column: _Column) -> None:
    """Whole-number types hold whole numbers within their range; a float type, any number it can hold
    (NaN and infinities are refused later where a value cannot be one, as in every model)."""
    if not column.values.size:
        return
    held = _held(column.values, column.prop.value_type)
    if not held.all():
        first = int(np.argmin(held.ravel()))
        at = column.index(first)
        shown = body.shown(column.values.ravel()[first], at)
        raise body.error(f"{shortened(element.name)} {shortened(column.prop.name)}: {shown} is no "
                         f"{column.prop.value_type} ({_range(column.prop.value_type)})", at)


def _check_coordinate(body: _Body, element: PlyElement, column: _Column) -> None:
    """A vertex's x, y or z, of any type, within what the GPU holds (a double may hold 3.5e38): refused
    here, at its line, where the table trimesh makes of it names none."""
    if element.name != "vertex" or column.prop.name not in ("x", "y", "z") or holds_in_float32(column.values):
        return
    with np.errstate(invalid="ignore"):
        first = int(np.argmin(np.abs(column.values.ravel()) <= FLOAT32_MAX))  # NaN too is not
    raise body.error(unheld_coordinate(body.path).message, column.index(first))


def _held(values: np.ndarray, kind: str) -> np.ndarray:
    """Which values a PLY type holds: a float's finite range (NaN and infinities too), or whole numbers
    within an integer's. A 64-bit type's largest is float64's 2 ** bits, as an ASCII body's numbers are
    float64 (the few whole numbers past it that round there too cannot be told from it)."""
    code = PLY_TYPES[kind]
    if code[0] == "f":
        return ~(np.isfinite(values) & (np.abs(values) > np.finfo(code).max))
    limits = np.iinfo(code)
    return (values >= limits.min) & (values <= float(limits.max)) & (values == np.trunc(values))  # NaN: none


def _write_typed(target: np.ndarray, values: np.ndarray, kind: str) -> None:
    """Checked values (_held) into `target`, of PLY type `kind`: float64's 2 ** bits, a 64-bit type's
    largest as an ASCII body reads it, written as that largest (a cast would wrap it round)."""
    with np.errstate(invalid="ignore"):
        target[...] = values
    if values.dtype.kind == "f" and PLY_TYPES[kind] in ("i8", "u8"):
        target[values >= float(_most(kind))] = _most(kind)


def _range(kind: str, counts: bool = False) -> str:
    code = PLY_TYPES[kind]
    if code[0] == "f":
        return f"numbers up to {np.finfo(code).max:.3g}"
    return f"whole numbers from {0 if counts else np.iinfo(code).min} to {np.iinfo(code).max}"


@functools.cache
def _most(kind: str) -> int:
    return int(np.iinfo(PLY_TYPES[kind]).max)


def _shown(value: float | np.number) -> str:
    """A number as the file gives it: a whole one without a point (a binary body's integers exactly)."""
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    return str(int(value)) if abs(value) < 1e15 and value == int(value) else repr(float(value))


def _face_corners(element: PlyElement, columns: list[_Column], vertices: int,
                  places: _Places) -> _Column | None:
    """A face element's list of vertex indices, each face checked to have 3 or more corners, each index
    to name a vertex and MeshLab's texture coordinates to give two numbers a corner; None for another
    element. `places` makes the error of a problem at a number's place: an ASCII body's names its line
    (_Body.error), a binary one's its file."""
    name = _corner_list(element)
    corners = next((column for column in columns if column.prop.name == name and column.counts is not None), None)
    if element.name != "face" or corners is None or corners.counts is None or corners.count_index is None:
        return None
    short = corners.counts < 3
    if short.any():
        row = int(np.argmax(short))
        size = int(corners.counts[row])
        raise places.error(f"a face of {size} corner{'' if size == 1 else 's'}: 3 or more make one",
                           corners.count_index(row))
    _check_names_vertices(corners, vertices, places)
    for column in columns:
        if column.prop.name == TEXCOORD_LIST and column.counts is not None and column.count_index is not None:
            wrong = column.counts != 2 * corners.counts
            if wrong.any():
                row = int(np.argmax(wrong))
                raise places.error(f"face texcoord: {column.counts[row]} numbers for a face of {corners.counts[row]} "
                                   "corners (two a corner)", column.count_index(row))
    return corners


def _strip_triangles(element: PlyElement, columns: list[_Column], vertices: int,
                     places: _Places) -> _Table | None:
    """A file's triangle strips as a table of their triangles, still named STRIPS (_strips_made_faces
    makes them faces); None for another element. Each row is a strip, or several with -1 between them;
    each next index makes a triangle of the two before it, every second one turned so that all face the
    same way (as VCG reads them), and those that repeat a vertex, which only join two strips, are left out."""
    lists = [column for column in columns if column.counts is not None and column.prop.name in FACE_LISTS]
    if element.name != STRIPS or not lists:
        return None
    _check_names_vertices(lists[0], vertices, places, between_strips=True)
    indices = lists[0].values
    row_ends = np.cumsum(lists[0].counts)
    chain = np.insert(indices.ravel().astype(np.int64), row_ends, -1)  # a row's end ends its strip too
    at = np.arange(len(chain))
    strip_start = np.maximum.accumulate(np.where(chain == -1, at + 1, 0))
    a, b, c = chain[:-2], chain[1:-1], chain[2:]
    made = (a >= 0) & (b >= 0) & (c >= 0) & (a != b) & (b != c) & (a != c)
    turned = (at[:-2] - strip_start[:-2]) % 2 == 1
    triangles = np.stack([np.where(turned, b, a), np.where(turned, a, b), c], axis=1)[made]
    return PlyElement(STRIPS, len(triangles), (PlyProperty(FACE_LISTS[0], "int", "uchar"),)), [triangles]


def _strips_made_faces(tables: list[_Table], fanned: list[np.ndarray]
                       ) -> tuple[list[_Table], list[np.ndarray], tuple[str, ...]]:
    """The tables with the strips' triangles (_strip_triangles') made the face element trimesh reads,
    where the file has no faces; else appended to its faces, which keep their numbers, as triangles
    (`fanned`, a fanned face element's sizes, given theirs) whose other values are zeros (trimesh draws
    none of them: a face's colour is a note). Not where the faces give texture coordinates per corner,
    which no strip has: a note says they are not drawn. Also the notes."""
    names = [element.name for element, _ in tables]
    if STRIPS not in names:
        return tables, fanned, ()
    strips = tables.pop(names.index(STRIPS))
    names.remove(STRIPS)
    if "face" not in names:
        return [*tables, (replace(strips[0], name="face"), strips[1])], fanned, ()
    at = names.index("face")
    (faces, values), triangles = tables[at], strips[1][0]
    if any(prop.name == TEXCOORD_LIST and prop.count_type for prop in faces.properties):
        return tables, fanned, (f"{counted(len(triangles), 'triangle')} of its triangle strips not drawn: its faces "
                                "give texture coordinates per corner, which strips do not",)
    corners = _corner_list(faces)
    joined = [np.concatenate((value, triangles if prop.name == corners else
                              np.zeros((len(triangles), *value.shape[1:]), value.dtype)))
              for prop, value in zip(faces.properties, values)]
    # the strips' indices name any vertex, past the type of the faces' (a uchar's 255, say)
    props = tuple(replace(prop, value_type="int") if prop.name == corners else prop for prop in faces.properties)
    tables[at] = (PlyElement("face", faces.count + len(triangles), props), joined)
    sizes = [np.concatenate((fanned[0], np.full(len(triangles), 3, fanned[0].dtype)))] if fanned else fanned
    return tables, sizes, ()


def _check_names_vertices(column: _Column, vertices: int, places: _Places,
                          between_strips: bool = False) -> None:
    """Each index names a vertex: a whole number from 0 to vertices - 1 (an index list of a float type may
    hold 1.5 or NaN, which trimesh would cast without a word), or -1 `between_strips` where there are
    vertices. The first that does not, in file order, is refused at its place."""
    indices = column.values
    checked = np.where(indices == -1, 0, indices) if between_strips else indices  # -1 passes where 0 would
    named = (checked >= 0) & (checked < vertices)  # NaN: False
    if indices.dtype.kind == "f":
        named &= checked == np.trunc(checked)
    if not named.all():
        first = int(np.argmin(named.ravel()))
        value, at = indices.ravel()[first], column.index(first)
        raise places.error(_unnamed_vertex(value, places.shown(value, at), vertices), at)


def _unnamed_vertex(value: float | np.number, shown: str, vertices: int) -> str:
    if value == np.trunc(value):  # NaN is not
        return f"vertex index {shown} out of range (the file has {vertices} vertices)"
    return f"vertex index {shown} is not a whole number"


def _fanned(element: PlyElement, columns: list[_Column], corners: _Column) -> _Table:
    """The faces as triangles (0, i, i + 1) of each, fan_gather's, which trimesh's binary reader takes:
    each keeps its face's values, and MeshLab's texture coordinates their corners'. Other lists are
    left out. Each value is made its type before it is gathered, and the indices are 32-bit where they fit."""
    assert corners.counts is not None
    kind = np.int32 if corners.values.size < np.iinfo(np.int32).max // 2 else np.int64
    face_start = np.concatenate(([0], np.cumsum(corners.counts, dtype=kind))).astype(kind, copy=False)
    # The mesh's own fans, in the order polygon_corners_of_fans undoes to make the polygons again.
    fan = fan_gather(np.arange(int(face_start[-1]), dtype=kind), face_start).reshape(-1, 3)
    face = np.repeat(np.arange(len(corners.counts), dtype=kind), corners.counts - 2)
    kept, values = [], []
    for column in columns:
        typed = np.empty(column.values.shape, "<" + PLY_TYPES[column.prop.value_type])
        _write_typed(typed, column.values, column.prop.value_type)
        if column.counts is None:
            values.append(typed[face])
        elif column is corners:
            values.append(typed.ravel()[fan])
        elif column.prop.name == TEXCOORD_LIST:  # two numbers a corner (_face_corners)
            values.append(typed.ravel()[(2 * fan[:, :, None] + np.arange(2, dtype=kind)).reshape(len(face), 6)])
        else:
            continue
        kept.append(column.prop)
    return PlyElement(element.name, len(face), tuple(kept)), values


def _without_lists(element: PlyElement, columns: list[_Column]) -> _Table:
    """An element of lists of mixed lengths, which trimesh's binary reader cannot take, as its single
    values alone (trimesh draws nothing of such lists)."""
    kept = [column for column in columns if column.counts is None]
    return replace(element, properties=tuple(column.prop for column in kept)), [column.values for column in kept]


def _written(header: bytes, tables: list[_Table]) -> bytes:
    """The header and each element's rows in binary little-endian PLY's layout: each value, and each
    list's count before its items, written in place."""
    layouts = [_row_dtype(element, _list_counts(element, values), "<") for element, values in tables]
    out = bytearray(len(header) + sum(element.count * layout.itemsize for (element, _), layout in
                                      zip(tables, layouts)))
    out[:len(header)] = header
    offset = len(header)
    for (element, values), layout in zip(tables, layouts):
        rows = np.frombuffer(out, layout, count=element.count, offset=offset)
        for number, (prop, value) in enumerate(zip(element.properties, values)):
            if prop.count_type is not None:
                rows[f"count{number}"] = value.shape[1]
            _write_typed(rows[f"value{number}"], value, prop.value_type)
        offset += element.count * layout.itemsize
        del rows  # a view of `out`, which bytes() must not find exported
    return bytes(out)


def _list_counts(element: PlyElement, values: list[np.ndarray]) -> list[int]:
    """The one count of each list of a table whose rows all have the same counts: its values' width."""
    return [value.shape[1] for prop, value in zip(element.properties, values) if prop.count_type is not None]


# --- a binary body, for trimesh's reader --------------------------------------------------------------
# What the viewer draws: trimesh makes a path of an edge element (which needs scipy), and draws nothing
# of the others.
_KEPT_ELEMENTS = ("vertex", "face", STRIPS)


def vertices_and_faces(path: Path, data: bytes, header: PlyHeader, most_triangles: int) -> ForTrimesh:
    """A binary PLY as trimesh's binary reader takes it: its vertex and face elements alone, read where
    they lie in the body, little-endian; faces of more than three corners fanned into triangles as an
    ASCII body's are, as that reader takes one count for a whole element. The file itself where that
    changes nothing."""
    # trimesh ends a header's lines at \n alone, and the header at a comment's end_header: such a one is written again
    at, tables = header.body_at, []
    unchanged = header.encoding == "<" and b"\r" not in data[:header.body_at] and not header.comment_ends_it_for_trimesh
    sizes: list[np.ndarray] = []
    for element in header.elements:
        columns, uniform, at = _binary_columns(path, data, element, at, header.encoding)
        if element.name not in _KEPT_ELEMENTS or not columns:
            unchanged = False
            continue
        table, as_read, fanned = _table_for_trimesh(header, element, columns, uniform, _BinaryPlaces(path),
                                                    most_triangles)
        tables.append(table)
        if fanned is not None:
            sizes.append(fanned)
        unchanged = unchanged and as_read
    if at != len(data):
        raise LoadError(path, f"its body holds {len(data) - at} bytes more than the rows its header counts")
    if unchanged:
        return ForTrimesh(data)
    tables, sizes, notes = _strips_made_faces(tables, sizes)
    return ForTrimesh(_written(header.text("binary_little_endian", tuple(element for element, _ in tables)), tables),
                      _face_sizes(header, sizes), notes)


def _binary_columns(path: Path, data: bytes, element: PlyElement, at: int, order: str
                    ) -> tuple[list[_Column], bool, int]:
    """The element's columns from byte `at`, whether every row has the first row's list counts, and where
    the next element starts. Such rows are one table, read in place; only where a count differs are the
    rows walked one by one (a row's length is known once its counts are read)."""
    if not element.count or not element.properties:
        return [], True, at
    _, counts, _ = _walked_rows(path, data, element, at, order, rows=1)
    layout = _row_dtype(element, counts[0], order)
    end = at + element.count * layout.itemsize
    if end <= len(data):
        table = np.frombuffer(data, layout, count=element.count, offset=at)
        lists = [number for number, prop in enumerate(element.properties) if prop.count_type is not None]
        if all((table[f"count{number}"] == count).all() for number, count in zip(lists, counts[0])):
            return _binary_table_columns(element, table), True, end
    starts, counts, end = _walked_rows(path, data, element, at, order)
    return _gathered_columns(data, element, starts, counts, order), False, end


def _row_dtype(element: PlyElement, counts: np.ndarray | list[int], order: str) -> np.dtype:
    """A row of the element whose lists hold these counts, as a numpy record."""
    fields: list[tuple] = []
    given = iter(counts)
    for number, prop in enumerate(element.properties):
        if prop.count_type is None:
            fields.append((f"value{number}", order + PLY_TYPES[prop.value_type]))
            continue
        fields.append((f"count{number}", order + PLY_TYPES[prop.count_type]))
        fields.append((f"value{number}", order + PLY_TYPES[prop.value_type], (int(next(given)),)))
    return np.dtype(fields)


def _binary_table_columns(element: PlyElement, table: np.ndarray) -> list[_Column]:
    """Columns of rows that all hold the same counts: views of the table, a list's as (rows, count)."""
    columns = []
    for number, prop in enumerate(element.properties):
        values = table[f"value{number}"]
        counts = None if prop.count_type is None else np.full(len(table), values.shape[1], np.int64)
        columns.append(_Column(prop, values, _no_line, counts, None if counts is None else _no_line))
    return columns


def _walked_rows(path: Path, data: bytes, element: PlyElement, at: int, order: str, rows: int | None = None
                 ) -> tuple[np.ndarray, np.ndarray, int]:
    """Each row's start and its lists' counts, row by row (the first `rows` only, where given), and
    where the rows end. Each row holds its values and counts at least: the header's count is checked
    against what the body can hold before anything is made by it."""
    steps, tail = _row_steps(element, order)
    least = sum(skip + counter.size for skip, counter, _ in steps) + tail
    if outruns(element.count, least, len(data) - at):
        raise _ended(path, element)
    wanted = element.count if rows is None else rows
    quick_starts, quick_counts, at = _byte_counted_rows(data, at, wanted, steps, tail)
    starts, counts, end = array("q"), array("q"), len(data)
    walks = [(skip, counter.unpack_from, skip + counter.size, item) for skip, counter, item in steps]
    try:
        for _ in range(wanted - len(quick_starts)):
            starts.append(at)
            for skip, unpack, before_items, item in walks:
                (count,) = unpack(data, at + skip)
                at += before_items + count * item
                if count < 0 or at > end:  # (a count read past the end raises struct.error)
                    raise _bad_count(path, element, count)
                counts.append(count)
            at += tail
    except struct.error:  # the body ends before a count
        raise _ended(path, element) from None
    if at > end:
        raise _ended(path, element)
    if not starts:  # every row walked quickly: no copy
        return quick_starts, quick_counts, at
    return (np.concatenate((quick_starts, np.frombuffer(starts, np.int64))),
            np.concatenate((quick_counts, np.frombuffer(counts, np.int64).reshape(len(starts), len(steps)))), at)


def _byte_counted_rows(data: bytes, at: int, rows: int, steps: list[tuple[int, struct.Struct, int]], tail: int
                       ) -> tuple[np.ndarray, np.ndarray, int]:
    """Rows of one list whose count is an unsigned byte (a face's, as exporters write it), walked from
    `at` up to the first whose count lies past the data: their starts, their counts, and where the next
    row starts; none for other rows. The last row's items may run past the data: the caller's walk
    says where the body ends."""
    if len(steps) != 1 or not steps[0][1].format.endswith("B"):
        return np.zeros(0, np.int64), np.zeros((0, len(steps)), np.int64), at
    skip, _, item = steps[0]
    stride, starts, row = skip + 1 + tail, array("q", [0]) * rows, 0
    try:
        for row in range(rows):
            starts[row] = at
            at += stride + data[at + skip] * item  # indexing bytes gives the byte's value without a call
        row = rows
    except IndexError:  # the row at `at` has no count within the data
        pass
    walked = np.frombuffer(starts, np.int64, count=row)
    counts = np.frombuffer(data, np.uint8)[walked + skip].astype(np.int64)
    return walked, counts.reshape(row, 1), at


def _bad_count(path: Path, element: PlyElement, count: int) -> LoadError:
    if count < 0:
        return LoadError(path, f"{shortened(element.name)}: a list count of {count}, below 0")
    return _ended(path, element)


def _row_steps(element: PlyElement, order: str) -> tuple[list[tuple[int, struct.Struct, int]], int]:
    """How a row is walked: for each list, the bytes of values before its count, its count's format and
    the bytes of an item; and the bytes of values after the last list."""
    steps, before = [], 0
    for prop in element.properties:
        if prop.count_type is None:
            before += np.dtype(PLY_TYPES[prop.value_type]).itemsize
            continue
        counter = struct.Struct(order + _STRUCT_CODES[PLY_TYPES[prop.count_type]])
        steps.append((before, counter, np.dtype(PLY_TYPES[prop.value_type]).itemsize))
        before = 0
    return steps, before


# A list's count, of a whole-number type (read_header refuses others), as struct reads it.
_STRUCT_CODES = {"i1": "b", "u1": "B", "i2": "h", "u2": "H", "i4": "i", "u4": "I", "i8": "q", "u8": "Q"}


def _gathered_columns(data: bytes, element: PlyElement, starts: np.ndarray, counts: np.ndarray, order: str
                      ) -> list[_Column]:
    """Columns of rows of mixed counts, as the ASCII reader makes them: each value gathered from its
    row, and each list's items one row after another."""
    columns, at, lists = [], starts.copy(), 0  # `at`: where each row's next property lies
    for prop in element.properties:
        item = np.dtype(order + PLY_TYPES[prop.value_type])
        if prop.count_type is None:
            columns.append(_Column(prop, _gathered(data, at, item), _no_line))
            at += item.itemsize
            continue
        count, first = counts[:, lists], at + np.dtype(PLY_TYPES[prop.count_type]).itemsize
        items = corners_of_polygons(first, count, item.itemsize)  # each row's items' byte offsets
        columns.append(_Column(prop, _gathered(data, items, item), _no_line, count.copy(), _no_line))
        at, lists = first + count * item.itemsize, lists + 1
    return columns


def _gathered(data: bytes, offsets: np.ndarray, kind: np.dtype) -> np.ndarray:
    """The values of type `kind` at these byte offsets, which need not be a multiple of its size."""
    raw, out = np.frombuffer(data, np.uint8), np.empty(len(offsets), kind)
    out_bytes = out.view(np.uint8).reshape(len(offsets), kind.itemsize)
    for byte in range(kind.itemsize):
        out_bytes[:, byte] = raw[offsets + byte]
    return out


def _no_line(at: int) -> int:
    """A binary body's value has no line to name: the ASCII reader's way of finding one, unused."""
    return at
