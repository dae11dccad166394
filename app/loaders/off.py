"""OFF (Object File Format, Geomview's and the Princeton shape benchmark's), read here: its vertices,
its polygons as the file gives them, and COFF's vertex colours.

Why not trimesh's reader: it takes a face line with fewer indices than its count as a smaller face,
reads past words after a vertex's numbers, names no line for a bad number or index, fails with a
TypeError on some polygons and drops COFF's colours. This one reads the body's numbers in one numpy
call where its lines are plain (comments taken out, a face's count and corners only digits, whatever
its colour), and otherwise a line at a time (from the first block of face rows that is not plain, where
the vertex rows are), making the numbers arrays a block of lines at a time; that reader names the line
of the first problem.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from marraztu.errors import LoadError, shortened
from marraztu.loaders.files import bom_length, line_at, line_end_after, line_end_from, read_model_bytes, text_lines
from marraztu.loaders.words import (
    BLANKS,
    MAX_COUNT_DIGITS,
    WHITESPACE,
    LineOf,
    WordBlocks,
    checked_coordinates,
    checked_indices,
    checked_numbers,
    is_count,
    line_end_places,
    line_words,
    outruns,
    pieces_at_gaps,
    said_count,
    text_numbers,
    word_starts,
)
from marraztu.model.build import FACE_COLOURS_NOTE, colour_bytes, colour_fractions, derive_mesh
from marraztu.model.geometry import holds_in_float32
from marraztu.model.mesh import INDEX, INDEX_LIMIT, Mesh, counted
from marraztu.model.threads import weighed_pieces

# A comment runs from '#' to its line's end (\n, \r\n or a lone \r, as text_lines ends lines).
_LINE_END_BYTES = (ord("\r"), ord("\n"))
_UNCOMMENT_PIECE_BYTES = 1 << 18  # a piece's tables of its '#'s and line ends stay a few megabytes
# A polygon's colour may follow its indices: none, an index into a colour map, RGB or RGBA. Not drawn.
_FACE_COLOUR_WORDS = (0, 1, 3, 4)


def load_off(path: Path, stage: Callable[[str], None] | None = None) -> Mesh:
    """An OFF file's Mesh: its polygons as they are (as an OBJ's), tinted by COFF's vertex colours."""
    tables = read_off(path, read_model_bytes(path, stage))  # the bytes are freed on return
    notes = (FACE_COLOURS_NOTE,) if tables.face_colours else ()
    try:
        mesh = derive_mesh(path.stem, tables.positions, tables.corner_vertex, tables.face_start, None, None, None,
                           None, notes)
    except ValueError as error:  # more corners than 32-bit indices hold
        raise LoadError(path, str(error)) from None
    return mesh if tables.colours is None else replace(mesh, vertex_colours=_colour_bytes(tables.colours))


def _colour_bytes(colours: np.ndarray) -> np.ndarray:
    """COFF's colours as bytes: read_off has checked them (_check_colours)."""
    return colour_bytes(colour_fractions(colours), len(colours))


@dataclass(frozen=True)
class OffTables:
    positions: np.ndarray  # (V, 3) float64
    corner_vertex: np.ndarray  # (C,) whole numbers
    face_start: np.ndarray  # (F + 1,) int64
    colours: np.ndarray | None  # (V, 3 or 4) float64, COFF's, as the file writes them (0..255 or 0..1)
    face_colours: bool  # whether a face row gives a colour (checked to be numbers, not drawn)


Row = tuple[int, list[str]]  # a line's number and its words before any '#'
# A header line needs its keyword and three counts, a vertex row at most 12 numbers (STCNOFF with an
# RGBA colour): split further, a line of a million words would be held as a list of them.
_HEADER_WORDS = 4
_MOST_VERTEX_WORDS = 12


class _Rows:
    """The lines that hold words, one at a time, from `start` (a line's first byte, after line number
    `line`; None: the text's start), remembering the last one's number (to name where a file ends too soon)."""

    def __init__(self, data: bytes, start: int | None = None, line: int = 0) -> None:
        self.rows = _lines_with_words(data, bom_length(data) if start is None else start, line + 1)
        self.line = max(line, 1)

    def next(self, most_words: int = -1) -> Row | None:
        """The next line's number and its words, the last of `most_words` (unless -1) holding the rest."""
        row = next(self.rows, None)
        if row is None:
            return None
        self.line = row[0]
        return row[0], row[1].split(None, most_words)


def read_off(path: Path, data: bytes) -> OffTables:
    rows = _Rows(data)
    layout, vertices, faces = _header(path, rows)
    body_at = line_end_after(data, rows.line)
    _check_counts_fit(path, vertices, faces, len(data) - body_at, rows.line)
    text, start, lines_before = data, body_at, 0
    if data.find(b"#", body_at) >= 0:  # the body without its comments, each line kept
        text, start, lines_before = _without_comments(data, body_at), 0, rows.line
    at_once = _body_at_once(text, start, layout, vertices, faces)
    if at_once is None:
        positions, colours = _vertex_rows(path, rows, vertices, layout)
        corner_vertex, face_start, face_colours = _face_rows(path, rows, faces, vertices)
        _check_nothing_after(path, rows, faces)
        tables = OffTables(positions, corner_vertex, face_start, colours, face_colours)
    else:
        tables, read_on = at_once
        if read_on is not None:  # the line reader reads on from the first face row not read at once
            start, line = read_on
            tables = _faces_read_on(path, _Rows(text, start, lines_before + line), tables, faces, vertices)
    if tables.colours is not None:
        _check_colours(path, data, tables.colours)
    return tables


def _faces_read_on(path: Path, rows: _Rows, read: OffTables, faces: int, vertices: int) -> OffTables:
    """The tables read at once, and the face rows after them read by the line reader, which names the
    first problem in them or after them, as it would reading the whole file."""
    done = read.face_start.size - 1
    corner_vertex, face_start, coloured = _face_rows(path, rows, faces - done, vertices, faces)
    _check_nothing_after(path, rows, faces)
    return replace(read, corner_vertex=np.concatenate((read.corner_vertex, corner_vertex)),
                   face_start=np.concatenate((read.face_start, face_start[1:] + read.face_start[-1])),
                   face_colours=read.face_colours or coloured)


def _check_colours(path: Path, data: bytes, colours: np.ndarray) -> None:
    """COFF writes colours as 0..255 or as 0..1, the file's values say which (build.colour_fractions): a
    colour within neither is refused at its line."""
    scaled = colour_fractions(colours[:, :3])
    with np.errstate(invalid="ignore"):
        outside = ~((scaled >= 0.0) & (scaled <= 1.0)).all(axis=1)
    if not outside.any():
        return
    rows = _Rows(data)
    _header(path, rows)
    for _ in range(int(np.argmax(outside)) + 1):  # that vertex's row: an error's cost, once
        rows.next(0)
    raise LoadError(path, "a vertex colour is not within 0..1, nor the file's colours within 0..255", line=rows.line)


def _without_comments(data: bytes, start: int) -> bytes:
    """The text from `start` with its comments taken out, each leaving a blank (one taken out whole from
    between a lone \\r and a \\n made them one line end), their line ends kept; a piece of a fixed size
    at a time, in numpy, carrying whether a piece begins inside a comment: a few bytes of temporaries
    per byte of a piece, however many comments and however long a line (a piece cut only at line ends
    was a whole line, and a long comment line cost 25 times itself)."""
    kept = []
    inside = False  # whether the text before the piece ends inside a comment
    for low in range(start, len(data), _UNCOMMENT_PIECE_BYTES):
        piece = np.frombuffer(data, np.uint8, count=min(_UNCOMMENT_PIECE_BYTES, len(data) - low), offset=low)
        text, inside = _piece_without_comments(piece, inside)
        kept.append(text)
    return b"".join(kept)


def _piece_without_comments(piece: np.ndarray, inside: bool) -> tuple[bytes, bool]:
    """A piece of text, its comments taken out, each leaving a blank where its '#' was (one runs on from
    the piece before where `inside`), and whether it ends inside one."""
    spans = _comment_spans(piece, inside)
    if spans is None:
        return piece.tobytes(), False
    starts, stops = spans
    taken = _in_spans(starts, stops, piece.size)
    taken[starts] = piece[starts] != ord("#")  # not one carried in from the piece before: its '#' left a blank
    kept = piece[~taken]
    kept[kept == ord("#")] = ord(" ")  # the '#' that begins each comment: every other lies within one
    return kept.tobytes(), bool(stops[-1] == piece.size)


def _comment_spans(piece: np.ndarray, inside: bool) -> tuple[np.ndarray, np.ndarray] | None:
    """(starts, stops) of the piece's comments, each from its line's first '#' (the piece's start, for
    one carried in) to its line end or the piece's end; None where there is none. Its own function: the
    table of every '#' is freed on return."""
    hashes = np.flatnonzero(piece == ord("#"))
    if inside and piece[0] not in _LINE_END_BYTES:  # as if a '#' began the piece (one there is its line's second)
        hashes = np.concatenate(([0], hashes))
    if not hashes.size:
        return None
    ends = np.append(line_end_places(piece), piece.size)
    stops = ends[np.searchsorted(ends, hashes)]  # each '#''s line end
    del ends  # a number per line: with a comment on every line, as large as the two tables made below
    first = np.concatenate(([True], stops[1:] != stops[:-1]))  # a line's first '#' starts its comment
    return hashes[first], stops[first]


def _in_spans(starts: np.ndarray, stops: np.ndarray, size: int) -> np.ndarray:
    """Which of `size` places lie in a span [start, stop), the spans in order and apart (no span's
    stop is another's start): +1 where each begins, -1 where it ends, summed."""
    steps = np.zeros(size + 1, np.int8)
    steps[starts] = 1
    steps[stops] = -1
    return np.cumsum(steps[:size], dtype=np.int8).view(bool)  # each sum 0 or 1


# Where the line reader reads on from: a line's first byte, and the number of the line before it.
ReadOn = tuple[int, int]


def _body_at_once(data: bytes, body_at: int, layout: _Layout, vertices: int, faces: int
                  ) -> tuple[OffTables, ReadOn | None] | None:
    """The tables, from the body's numbers read by numpy (the vertex rows' in one call, the faces' a block
    of rows at a time), where each row is one the line reader takes without a word and nothing in it
    needs that reader's care: a face's count and corners only digits (comments are taken out before);
    and where the line reader reads on, None where every row was read so and nothing follows them.
    Where a face row is not plain (or the file ends before the faces, or words follow them), the tables
    hold the rows before it, and the line reader reads on from it and names any problem. None where the
    vertex rows are not all plain: the line reader reads the whole file. The rows' shapes are checked
    from their word counts first, so a line of a million words is never made numbers here."""
    rows = vertices + faces
    counts, firsts = line_words(data, body_at, rows + 1)  # a line after the faces: words past them
    present = min(counts.size, rows)  # the rows the file holds, up to the header's count
    if present < vertices or not present:
        return None
    width = int(counts[0]) if vertices else 3
    face_words, face_firsts = counts[vertices:present], firsts[vertices:present]
    faces_at = int(firsts[vertices]) if present > vertices else line_end_from(data, int(firsts[present - 1]))
    if (width not in layout.row_sizes() or (counts[:vertices] != width).any()
            or _long_counts(data, face_firsts) or not _counts_fit(data, face_firsts, face_words)):
        return None
    table = _numbers_of(data[body_at:faces_at], vertices * width, np.float64)
    if table is None or not holds_in_float32(table):
        return None
    end = int(firsts[present]) if counts.size > present else len(data)  # the faces' text: up to a line after them
    corner_vertex, face_start, face_colours = _face_rows_at_once(data, face_firsts, end, face_words, vertices)
    positions, colours = _vertex_table(table.reshape(vertices, width), layout)
    tables = OffTables(positions, corner_vertex, face_start, colours, face_colours)
    read = vertices + face_start.size - 1
    if read == rows and counts.size == rows:
        return tables, None
    if not read:  # no vertices, and no face row read: from the body's first line
        return tables, (body_at, line_at(data, body_at) - 1)
    last = int(firsts[read - 1])  # the last row read: from the line after it (it may end the file)
    return tables, (line_end_from(data, last), line_at(data, last))


_FACE_BLOCK_WORDS = 1 << 16  # the faces' words made numbers at once: half a megabyte of them
_ROW_PIECE_BYTES = 1 << 18  # a longer row's text made numbers at once


def _face_rows_at_once(data: bytes, firsts: np.ndarray, end: int, words: np.ndarray, vertices: int
                       ) -> tuple[np.ndarray, np.ndarray, bool]:
    """The corners and face_start of the face rows that begin at `firsts`, each of its count, that many
    corners and perhaps a colour (`words` in all), and whether any gives a colour; made numbers a block
    of rows at a time (a row of more words than a block, a piece of it at a time), into the corners'
    final table. Only the blocks before the first that holds another row (a count of less than 3, a
    colour of another number of words, an index out of range): the line reader reads on from it."""
    short = np.flatnonzero(words < 4)
    if short.size:  # a row of no count and three corners: those before it are read at once
        end, words, firsts = int(firsts[short[0]]), words[:short[0]], firsts[:short[0]]
    corners = np.empty(int(words.sum()) - words.size, INDEX)  # room for every word after a count
    face_start = np.zeros(words.size + 1, np.int64)  # each row's count, then summed in place
    written = 0
    limit = min(vertices, INDEX_LIMIT)
    for block in weighed_pieces(words, _FACE_BLOCK_WORDS) if words.size else ():
        low, high = block.start, block.stop
        text_end = int(firsts[high]) if high < words.size else end
        if words[low] > _FACE_BLOCK_WORDS:  # alone in its block
            counts = _long_row(data, int(firsts[low]), text_end, int(words[low]), corners[written:], limit)
        else:
            counts = _rows(data[firsts[low]:text_end], words[low:high], corners[written:], limit)
        if counts is None:
            face_start = face_start[:low + 1]
            break
        face_start[low + 1:high + 1] = counts
        written += int(counts.sum())
    np.cumsum(face_start, out=face_start)
    coloured = written != int(words[:face_start.size - 1].sum()) - (face_start.size - 1)  # a colour's words
    return (corners if written == corners.size else corners[:written].copy()), face_start, coloured


def _rows(text: bytes, words: np.ndarray, corners: np.ndarray, limit: int) -> np.ndarray | None:
    """Face rows of these word counts: their corners into the start of `corners`, and their counts;
    None where they are other rows."""
    total = int(words.sum())
    count_at = np.cumsum(words) - words
    digits = None  # whether each word is digits only, where some are not
    numbers = _numbers_of(text, total, np.int64)
    if numbers is None:  # a colour of fractions, say: then the counts and corners must be digits only
        digits = _digits_only_words(text, total)
        numbers = None if digits is None or not digits[count_at].all() else _numbers_of(text, total, np.float64)
        if numbers is None or not np.isfinite(numbers).all():  # a colour's NaN: the line reader names it
            return None
    counts = numbers[count_at].astype(np.int64)
    colour_words = words - 1 - counts
    if (counts < 3).any() or not np.isin(colour_words, _FACE_COLOUR_WORDS).all():
        return None
    if colour_words.any() or digits is not None:
        corner = _corner_words(count_at, counts, total)
        if digits is not None and not digits[corner].all():
            return None
        read = numbers[corner]
    else:  # the usual rows: every word after a count a corner
        numbers[count_at] = -1
        read = numbers[numbers >= 0]
    if read.max() >= limit:  # checked before it is made 32-bit
        return None
    corners[:read.size] = read
    return counts


def _corner_words(count_at: np.ndarray, counts: np.ndarray, total: int) -> np.ndarray:
    """Which of the rows' `total` words are corners: the `counts` words after each row's count, which
    is word `count_at` (a colour's words follow them)."""
    return _in_spans(count_at + 1, count_at + 1 + counts, total)  # apart: the next row's count is between


def _digits_only_words(text: bytes, total: int) -> np.ndarray | None:
    """Whether each word of the text is digits only; None where it does not hold `total` words. A few
    bytes of temporaries per byte: one word may be most of the text."""
    text_bytes = np.frombuffer(text, np.uint8)
    blank = WHITESPACE[text_bytes]
    starts = word_starts(blank)
    if starts.size != total:
        return None
    other = ~(blank | _DIGIT[text_bytes])  # a byte that is neither: a sign, a point, a letter
    return ~np.logical_or.reduceat(other, starts)  # each word with the blanks after it


def _long_row(data: bytes, start: int, end: int, words: int, corners: np.ndarray, limit: int) -> np.ndarray | None:
    """One face row of `words` words, its corners into the start of `corners`, made numbers a piece of
    its text at a time, and its count; None where it is another row. What follows its corners is its
    colour."""
    count, at, seen = -1, 0, 0  # the row's count, once read; corners written; numbers read
    for low, high in pieces_at_gaps(data, start, _ROW_PIECE_BYTES, end):
        numbers = _numbers_of(data[low:high], None, np.int64)
        if numbers is None:
            return None
        seen += numbers.size
        if count < 0:
            count, numbers = int(numbers[0]), numbers[1:]
            if count < 3 or words - 1 - count not in _FACE_COLOUR_WORDS:
                return None
        numbers = numbers[:count - at]
        if numbers.size and numbers.max() >= limit:
            return None
        corners[at:at + numbers.size] = numbers
        at += numbers.size
    return np.array([count]) if at == count and seen == words else None


def _numbers_of(text: bytes, expected: int | None, kind: type) -> np.ndarray | None:
    """The text's numbers, where its words are `expected` numbers (None: any number of them); None
    otherwise. Whole numbers only where it holds only digits and blanks: a sign, a decimal point or an
    exponent is read otherwise by the line reader ('3.0' is no count), or refused."""
    if kind is np.int64 and text.translate(None, _DIGITS_AND_BLANKS):
        return None
    if text.isspace():  # numpy reads blanks alone as one number
        return np.empty(0, kind) if expected in (None, 0) else None
    try:
        numbers = text_numbers(text, kind)
    except ValueError:
        return None
    return numbers if expected is None or numbers.size == expected else None  # some numpy stops at a NUL


_DIGITS = b"0123456789"
_DIGITS_AND_BLANKS = _DIGITS + BLANKS
_DIGIT = np.zeros(256, bool)
_DIGIT[list(_DIGITS)] = True
# A face row this long has its count read alone before any row is made numbers.
_LONG_ROW_WORDS = 64


def _long_counts(data: bytes, firsts: np.ndarray) -> bool:
    """Whether a face row's first word may be longer than a count is (leading zeros make it one numpy
    reads): its bytes looked at one place further at a time, for the rows whose word is that long yet."""
    text, rows = np.frombuffer(data, np.uint8), firsts
    for offset in range(1, MAX_COUNT_DIGITS + 1):
        rows = rows[~WHITESPACE[text[np.minimum(rows + offset, len(data) - 1)]]]
    return rows.size > 0


def _counts_fit(data: bytes, firsts: np.ndarray, words: np.ndarray) -> bool:
    """Whether each long face row's count (its first word) leaves words for that many corners and
    perhaps a colour."""
    for row in np.flatnonzero(words > _LONG_ROW_WORDS).tolist():
        first = int(firsts[row])
        count = data[first:first + MAX_COUNT_DIGITS].split(None, 1)[0]
        if not count.isdigit() or int(words[row]) - 1 - int(count) not in _FACE_COLOUR_WORDS:
            return False
    return True


def _lines_with_words(data: bytes, start: int, first_line: int) -> Iterator[tuple[int, str]]:
    """(line number, what comes before any #) of each line from `start` that holds a word, read a piece
    at a time; the first is line `first_line`."""
    for number, line in enumerate(text_lines(data, start), start=first_line):
        content = line.split("#", 1)[0] if "#" in line else line
        if content and not content.isspace():
            yield number, content


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
    first = rows.next(_HEADER_WORDS)
    if first is None:
        raise LoadError(path, "empty file: no faces")
    number, words = first
    keyword = _KEYWORD.fullmatch(words[0].upper())
    if keyword is None:
        said = "not an OFF file (it does not start with 'OFF')"
        if words[0].upper().endswith("OFF"):
            said = (f"{shortened(words[0])}: only OFF, COFF, NOFF, STOFF and their blends are read (no 4 "
                    "or n dimensions)")
        raise LoadError(path, said, line=number)
    if len(words) > 1 and words[1].upper() == "BINARY":
        raise LoadError(path, "a binary OFF file: only text OFF is read", line=number)
    counts = ([keyword[4]] if keyword[4] else []) + words[1:]
    if not counts:
        number, counts = rows.next(_HEADER_WORDS - 1) or (number, [])
    if len(counts) < 2 or not all(is_count(word) for word in counts[:2]):
        raise LoadError(path, "expected the vertex, face and edge counts", line=number)
    vertices, faces = int(counts[0]), int(counts[1])
    if faces == 0:
        raise LoadError(path, "the header declares no faces: nothing to draw", line=number)
    return _Layout(normal=bool(keyword[3]), coloured=bool(keyword[2]), texture=bool(keyword[1])), vertices, faces


_LEAST_ROW_BYTES = 2  # a row is a line of words: a word and a line end at least (the last row's may be missing)


def _check_counts_fit(path: Path, vertices: int, faces: int, held: int, line: int) -> None:
    """The header's counts refused at their line where the `held` bytes after it cannot hold that many
    rows, before anything is made by them; a row that is there, however wrong, is left to be named."""
    if outruns(vertices + faces, _LEAST_ROW_BYTES, held + 1):
        raise LoadError(path, f"the header counts {counted(vertices, 'vertex', 'vertices')} and "
                              f"{counted(faces, 'face')}, the file ends before them: the {counted(held, 'byte')} "
                              f"after the counts hold {counted((held + 1) // _LEAST_ROW_BYTES, 'row')} at most",
                        line=line)


def _taken(path: Path, rows: _Rows, count: int, what: tuple[str, str], most_words: int = -1,
           header_count: int | None = None) -> Iterator[Row]:
    """The next `count` rows of the header's `header_count` (None: `count`), or a LoadError where the
    file ends before them; `what`: a row's noun, and its plural."""
    for _ in range(count):
        row = rows.next(most_words)
        if row is None:
            said = counted(count if header_count is None else header_count, *what)
            raise LoadError(path, f"the header counts {said}, the file ends before them", line=rows.line)
        yield row


def _vertex_rows(path: Path, rows: _Rows, count: int, layout: _Layout
                 ) -> tuple[np.ndarray, np.ndarray | None]:
    """Each vertex row's x y z, and COFF's colour; the row holds what the keyword says, all numbers."""
    sizes = layout.row_sizes()
    positions = WordBlocks(path, checked_coordinates)
    extras = WordBlocks(path, checked_numbers)  # all checked to be finite numbers; the colour's kept
    width = 0
    for number, words in _taken(path, rows, count, ("vertex", "vertices"), _MOST_VERTEX_WORDS):
        if len(words) not in sizes:
            wanted = " or ".join(map(str, sizes))
            raise LoadError(path, f"a vertex row holds {wanted} numbers here, this one "
                                  f"{said_count(words, _MOST_VERTEX_WORDS)}", line=number)
        if width and len(words) != width:
            raise LoadError(path, f"a vertex row holds {width} numbers here, as the first one does; this one "
                                  f"{len(words)}", line=number)
        width = len(words)
        positions.add(words[:3], number)
        if width > 3:
            extras.add(words[3:], number)
    extra = extras.values()
    if not count:
        return np.zeros((0, 3)), None
    return _vertex_table(np.concatenate([positions.values().reshape(count, 3), extra.reshape(count, -1)], axis=1),
                         layout)


def _check_nothing_after(path: Path, rows: _Rows, faces: int) -> None:
    """Only blanks and comments may follow the faces: a word there is refused at its line, as PLY's
    numbers after its last row are (the header's counts, or the file, are not what they say)."""
    after = rows.next(1)
    if after is not None:
        raise LoadError(path, f"'{shortened(after[1][0])}' after the {counted(faces, 'face')} the header "
                              "counts", line=after[0])


def _vertex_table(table: np.ndarray, layout: _Layout) -> tuple[np.ndarray, np.ndarray | None]:
    """The positions and COFF's colours (3 or 4 numbers) of a table of the vertex rows' numbers."""
    positions = np.ascontiguousarray(table[:, :3])
    if not layout.coloured or not table.shape[0]:
        return positions, None
    colour_at = 3 + 3 * layout.normal  # after x y z and the normal
    return positions, table[:, colour_at:colour_at + table.shape[1] - layout.row_sizes()[0] + 3]


def _face_rows(path: Path, rows: _Rows, count: int, vertices: int, header_count: int | None = None
               ) -> tuple[np.ndarray, np.ndarray, bool]:
    """Each face row's corner count n, its n vertex indices and perhaps a colour (checked to be numbers,
    not drawn), and whether any row gives one: `count` rows of the `header_count` (where others were read
    before them). Held a block at a time as the rows come: never by the header's count, which a short
    file may exaggerate."""
    corners = WordBlocks(path, lambda path, words, line_of: checked_indices(path, words, line_of, vertices))
    colours = WordBlocks(path, _checked_not_kept)
    coloured = False
    most = max(_FACE_COLOUR_WORDS)
    for number, (first, *rest) in _taken(path, rows, count, ("face", "faces"), 1, header_count):
        size = int(first) if is_count(first) else -1
        if size < 3:
            raise LoadError(path, "a face's corner count must be a whole number of 3 or more, not "
                                  f"'{shortened(first)}'", line=number)
        words = rest[0].split(None, size + most) if rest else []  # its corners and a colour: never more words
        if len(words) - size not in _FACE_COLOUR_WORDS:
            raise LoadError(path, f"a face of {size} corners, this line holds {said_count(words, size + most)} "
                                  "numbers after its count", line=number)
        corners.add(words[:size], number)
        if len(words) > size:
            colours.add(words[size:], number)
            coloured = True
    corner_vertex = corners.values()
    colours.values()  # the last block's words checked
    return corner_vertex, np.concatenate(([0], np.cumsum(corners.row_sizes()))), coloured


def _checked_not_kept(path: Path, words: list[str], line_of: LineOf) -> np.ndarray:
    """A block of face colours' words checked to be numbers, as the corners are, and none kept (an
    empty array): the renderer draws no colour given per face."""
    return checked_numbers(path, words, line_of)[:0]
