"""The fast OBJ reader: the whole byte buffer at once with numpy, on several threads.

Lines are classified by their first bytes, the lines of each kind (v, vt, vn, f) are copied together
and parsed in cache-sized pieces, every check is an array operation, and digits are read eight at a
time (SWAR). Only rare statements (o, g, s, usemtl, mtllib, unknown ones, indented lines) cost
Python work per line. A piece holding anything it does not handle, valid or not, is read again line
by line by the line reader (lines.py), which gives that piece's tables or its first error: so an odd
or broken line costs one piece of Python work, not the whole file's, and every message is the line
reader's. The first error in the file's order wins.
"""

from __future__ import annotations

import itertools
import os
import threading
import warnings
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import TypeVar

import numpy as np

from marraztu.errors import LoadError
from marraztu.loaders.obj.lines import LineReader, check_forward_indices, no_faces_error
from marraztu.loaders.obj.raw import CORNER_GAPS, MAX_DIGITS, ColourComment, RawObj, material_name, statement
from marraztu.model.geometry import FLOAT32_MAX


class Unusual(Exception):
    """A piece holds something the fast reader does not handle; the line reader reads that piece."""


_SKIP, _V, _VT, _VN, _F = 0, 1, 2, 3, 4
_UNCLASSIFIED = 255
_KEYWORDS = {b"v": _V, b"vt": _VT, b"vn": _VN, b"f": _F}
_KEYWORD_LENGTH = {_V: 1, _VT: 2, _VN: 2, _F: 1}
_TABLE_KINDS = (_V, _VT, _VN)

_IS_SPACE = np.zeros(256, dtype=bool)
_IS_SPACE[list(b" \t\n\r\x0b\x0c")] = True


# Up to MAX_DIGITS significant digits the integer mantissa and the power of ten are exact doubles,
# so one division gives the correctly rounded value, the same as Python's float() (Clinger's fast path).
_POW10_U64 = np.array([10**k for k in range(MAX_DIGITS + 1)], dtype=np.uint64)
_POW10_FLOAT = np.array([float(10**k) for k in range(MAX_DIGITS + 1)])

# Every blob starts with _PAD separators, so the 8-byte words ending at any number (two for 16
# digits) lie inside it. Pieces of _CHUNK_BYTES keep numpy's temporaries in the CPU cache, unlike
# whole-file arrays, while each numpy call runs long enough for two threads to share the work
# without waiting on each other for the GIL.
_PAD = 16
_SPACES = np.full(_PAD, ord(" "), dtype=np.uint8)
_CHUNK_BYTES = 1 << 20
_CHUNK_LINES = 1 << 16  # lines classified per piece: about as many bytes of kinds and masks
# Seven numbers never need this much: a longer v, vt or vn line goes to the line reader, whose
# bounded split costs a few copies of it, not numpy's masks and token offsets many times its size.
_LONGEST_TABLE_LINE = 4096
_Chunk = TypeVar("_Chunk")  # a piece of work: a byte offset, a range of lines
_ChunkResult = TypeVar("_ChunkResult")
_Parsed = TypeVar("_Parsed")
# The chunks are independent and numpy releases the GIL inside each operation, so several threads
# parse at once. (Processes would not share the GIL at all, but each would import numpy and need the text.)
_PARSE_THREADS = max(1, min(4, os.cpu_count() or 1))


def _chunk_map(work: Callable[[_Chunk], _ChunkResult], chunks: Iterable[_Chunk]) -> list[_ChunkResult]:
    """[work(chunk) for chunk in chunks], on up to _PARSE_THREADS threads, this one among them.

    The first exception is raised here once every thread has stopped; the others stop taking chunks.
    """
    todo = list(chunks)
    threads = min(_PARSE_THREADS, len(todo))
    if threads < 2:
        return [work(chunk) for chunk in todo]
    results: list[_ChunkResult | None] = [None] * len(todo)
    failures: list[BaseException] = []
    taken = itertools.count()  # next() on it is atomic under the GIL: each chunk is taken once

    def take_chunks() -> None:
        while not failures:
            index = next(taken)
            if index >= len(todo):
                return
            try:
                results[index] = work(todo[index])
            except BaseException as error:  # re-raised by the caller's thread below
                failures.append(error)

    helpers = [threading.Thread(target=take_chunks, name="obj-parse", daemon=True) for _ in range(threads - 1)]
    for helper in helpers:
        helper.start()
    take_chunks()
    for helper in helpers:
        helper.join()
    if failures:
        raise failures[0]
    return results  # type: ignore[return-value]  # every slot was filled: no failure


@dataclass
class _LineTable:
    """Where each line that is not empty lies in the text, and its line number (empty lines are left
    out: a file of blank lines must not cost two offsets per byte)."""

    start: np.ndarray  # int64 offsets
    end: np.ndarray  # offset of each line's newline
    number: np.ndarray | None  # 1-based line numbers; None when no line is empty: then each is its index + 1

    def number_of(self, lines: np.ndarray) -> np.ndarray:
        return lines + 1 if self.number is None else self.number[lines]

    def number_of_line(self, line: int) -> int:
        return line + 1 if self.number is None else int(self.number[line])


@dataclass
class _File:
    """What every piece of work reads: the text, its lines, and which lines hold which kind."""

    source: str
    text: bytes
    buf: np.ndarray
    lines: _LineTable
    of_kind: dict[int, np.ndarray]  # indices into `lines`, ascending, per kind
    indented: dict[int, int]  # keyword offset of indented v, vt, vn, f lines, by line index
    errors: list[LoadError]  # the first of each piece that has one, in no particular order

    def content(self, line: int) -> bytes:
        return self.text[int(self.lines.start[line]):int(self.lines.end[line])]

    def defined_before(self, lines: np.ndarray) -> list[np.ndarray]:
        """How many v, vt and vn lines come before each of the given lines."""
        return [np.searchsorted(self.of_kind[kind], lines) for kind in _TABLE_KINDS]


@dataclass
class _Faces:
    """One piece's faces: 0-based v, vt, vn per corner (None: no corner has one; -1: this one has none;
    positive ones may point past the end, checked once all are read), and corners per face."""

    columns: list[np.ndarray | None]
    per_line: np.ndarray

    @property
    def corners(self) -> int:
        return int(self.per_line.sum())


def read_fast(text: bytes, source: str) -> RawObj:
    """The file's tables, or the LoadError the line reader gives for its first bad line."""
    buf = np.frombuffer(text, dtype=np.uint8)
    lines = _line_table(buf)
    kinds, comments = _classify_lines(buf, lines.start)
    irregular = _settle_irregular_lines(text, lines, kinds)
    comments = np.sort(np.concatenate((comments, np.array(irregular.comments, dtype=np.int64))))
    colour = _colour_comment(text, lines, comments)
    of_kind = {kind: np.flatnonzero(kinds == kind) for kind in (*_TABLE_KINDS, _F)}
    del kinds, comments
    file = _File(source, text, buf, lines, of_kind, irregular.indented, [])
    positions = _float_table(file, _V, fewest=3, most=7)
    texcoords = _float_table(file, _VT, fewest=2, most=3)
    normals = _float_table(file, _VN, fewest=3, most=3)
    columns, face_start = _face_table(file)
    if file.errors:  # the earliest in the file is the one the line reader would give
        raise min(file.errors, key=lambda error: error.line or 0)
    if of_kind[_F].size == 0:
        raise no_faces_error(source, irregular.any_statement or any(of_kind[kind].size for kind in _TABLE_KINDS))
    face_lines = lines.number_of(of_kind[_F])
    check_forward_indices(source, columns, [len(positions), len(texcoords), len(normals)],
                          lambda corner: int(face_lines[np.searchsorted(face_start, corner, "right") - 1]))
    assert columns[0] is not None  # every corner has a vertex
    # A usemtl covers the faces from the first face line after it: as many face lines as come before.
    first_faces = np.searchsorted(of_kind[_F], [line for line, _ in irregular.usemtl]).tolist()
    runs = [(face, name) for face, (_, name) in zip(first_faces, irregular.usemtl)]
    return RawObj(positions, texcoords, normals, columns[0], columns[1], columns[2], face_start,
                  irregular.mtllib, colour.colour, colour.notes, runs)


def _line_table(buf: np.ndarray) -> _LineTable:
    """Every line that is not empty, found chunk by chunk on several threads: a mask of the whole file
    would be a temporary as large as the file, in fresh memory that costs more to touch than the scan."""
    pieces = _chunk_map(lambda low: _lines_in(buf, low), range(0, buf.size, _CHUNK_BYTES))
    if not pieces:
        return _LineTable(np.zeros(0, np.int64), np.zeros(0, np.int64), None)
    first_numbers = []
    last_newline, lines_before = -1, 0
    for piece in pieces:
        if piece.start.size and piece.start[0] < 0:  # the chunk's first line began in an earlier chunk
            piece.start[0] = last_newline + 1
        first_numbers.append(lines_before + 1)
        last_newline = piece.last_newline if piece.newlines else last_newline
        lines_before += piece.newlines
    starts = np.concatenate([piece.start for piece in pieces])
    ends = np.concatenate([piece.end for piece in pieces])
    if all(piece.kept is None for piece in pieces):
        return _LineTable(starts, ends, None)
    numbers = [(np.arange(piece.end.size) if piece.kept is None else piece.kept) + first
               for piece, first in zip(pieces, first_numbers)]
    return _LineTable(starts, ends, np.concatenate(numbers))


@dataclass
class _ChunkLines:
    """The lines ending in one chunk of bytes that are not empty."""

    start: np.ndarray  # -1 for a first line begun in an earlier chunk
    end: np.ndarray
    kept: np.ndarray | None  # index of each among all the chunk's lines; None: every line
    newlines: int  # how many lines end in the chunk, empty ones included
    last_newline: int


def _lines_in(buf: np.ndarray, low: int) -> _ChunkLines:
    newlines = np.flatnonzero(buf[low:low + _CHUNK_BYTES] == ord("\n"))
    newlines += low
    starts = np.empty_like(newlines)
    if newlines.size == 0:
        return _ChunkLines(starts, newlines, None, 0, -1)
    starts[0] = -1
    np.add(newlines[:-1], 1, out=starts[1:])
    if newlines[0] == low and (low == 0 or buf[low - 1] == ord("\n")):  # the first line is empty
        starts[0] = low
    kept = np.flatnonzero(newlines != starts)
    if kept.size == newlines.size:
        return _ChunkLines(starts, newlines, None, int(newlines.size), int(newlines[-1]))
    return _ChunkLines(starts[kept], newlines[kept], kept, int(newlines.size), int(newlines[-1]))


def _classify_lines(buf: np.ndarray, line_start: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Kind of each line from its first three bytes (the rare others stay _UNCLASSIFIED), and the lines
    that start with '#'; in pieces of _CHUNK_LINES lines on several threads."""
    pieces = _chunk_map(lambda low: _classify_piece(buf, line_start[low:low + _CHUNK_LINES], low),
                        range(0, line_start.size, _CHUNK_LINES))
    if not pieces:
        return np.zeros(0, np.uint8), np.zeros(0, np.int64)
    return np.concatenate([kinds for kinds, _ in pieces]), np.concatenate([hashes for _, hashes in pieces])


def _classify_piece(buf: np.ndarray, line_start: np.ndarray, first_line: int) -> tuple[np.ndarray, np.ndarray]:
    first = buf[line_start]
    second = buf[line_start + 1]  # every line here holds at least one byte and its newline
    kinds = np.full(line_start.size, _UNCLASSIFIED, dtype=np.uint8)
    kinds[(first == ord("#")) | (_IS_SPACE[first] & (second == ord("\n")))] = _SKIP  # the CR of a CRLF blank line
    one_letter = _IS_SPACE[second]
    kinds[(first == ord("v")) & one_letter] = _V
    kinds[(first == ord("f")) & one_letter] = _F
    two_letter = np.flatnonzero((first == ord("v")) & ((second == ord("t")) | (second == ord("n"))))
    two_letter = two_letter[_IS_SPACE[buf[line_start[two_letter] + 2]]]
    kinds[two_letter] = np.where(second[two_letter] == ord("t"), _VT, _VN)
    return kinds, np.flatnonzero(first == ord("#")) + first_line


@dataclass
class _Irregular:
    """What the rare lines hold (see _settle_irregular_lines)."""

    indented: dict[int, int]  # keyword offset of indented v, vt, vn and f lines, by line index
    mtllib: str | None  # the first one
    any_statement: bool
    comments: list[int]  # indented comment lines
    usemtl: list[tuple[int, str]]  # (line index, material name) of every usemtl line


def _settle_irregular_lines(text: bytes, lines: _LineTable, kinds: np.ndarray) -> _Irregular:
    """Per-line Python work for the rare lines: indented ones, and o/g/s/usemtl/mtllib/unknown.
    Their kinds are set in `kinds`."""
    irregular = _Irregular({}, None, False, [], [])
    for line in np.flatnonzero(kinds == _UNCLASSIFIED).tolist():
        content = text[int(lines.start[line]):int(lines.end[line])]
        keyword, rest = statement(content)
        irregular.any_statement = irregular.any_statement or bool(keyword)
        kinds[line] = _KEYWORDS.get(keyword, _SKIP)
        if kinds[line] != _SKIP:
            irregular.indented[line] = content.index(keyword)
        elif keyword == b"mtllib" and irregular.mtllib is None:
            irregular.mtllib = rest.decode("utf-8", errors="replace")
        elif keyword == b"usemtl":
            irregular.usemtl.append((line, material_name(rest)))
        elif not keyword and content.lstrip().startswith(b"#"):
            irregular.comments.append(line)
    return irregular


def _colour_comment(text: bytes, lines: _LineTable, comments: np.ndarray) -> ColourComment:
    """The comment lines offered in order, a block at a time: a list of every one would cost far more."""
    colour = ColourComment()
    for block in range(0, comments.size, _CHUNK_LINES):
        for line in comments[block:block + _CHUNK_LINES].tolist():
            colour.offer(lines.number_of_line(line), text[int(lines.start[line]):int(lines.end[line])])
        if colour.colour is not None:
            break  # the first well-formed one counts
    return colour


@dataclass
class _Lines:
    """The lines of one kind, where they are in the file's bytes, and how to cut them into pieces.

    Each piece of about _CHUNK_BYTES is copied into a blob of its own by the thread that parses it,
    right before parsing: the copy is still in the CPU cache when it is read, the threads share the
    copying, and no copy of the whole file's lines is ever made."""

    file: _File
    kind: int
    lines: np.ndarray  # indices into file.lines, ascending

    @classmethod
    def of(cls, file: _File, kind: int) -> _Lines:
        return cls(file, kind, file.of_kind[kind])

    @property
    def count(self) -> int:
        return int(self.lines.size)

    def lengths(self, first: int = 0, stop: int | None = None) -> np.ndarray:
        """Bytes of each line, its newline included."""
        lines = self.lines[first:stop]
        return self.file.lines.end[lines] - self.file.lines.start[lines] + 1

    def pieces(self) -> list[tuple[int, int]]:
        """[first, stop) ranges of `lines`, whole lines of about _CHUNK_BYTES each, in order."""
        if self.count == 0:
            return []
        ends = np.cumsum(self.lengths())
        targets = np.arange(_CHUNK_BYTES, int(ends[-1]), _CHUNK_BYTES)
        cuts = np.concatenate(([0], np.searchsorted(ends, targets) + 1, [self.count]))
        # Already sorted, so drop repeats by hand: np.unique imports numpy.ma, which slows start-up.
        cuts = cuts[np.concatenate(([True], cuts[1:] != cuts[:-1]))]
        return list(zip(cuts[:-1].tolist(), cuts[1:].tolist()))

    def blob(self, first: int, stop: int) -> _Blob:
        return _Blob.gather(self.file, self.lines[first:stop], _KEYWORD_LENGTH[self.kind])

    def read_by_lines(self, first: int, stop: int, defined: Callable[[int], list[int]] | None = None
                      ) -> LineReader | None:
        """The piece's lines through the line reader: what it read, or None after adding its first error
        to file.errors.

        `defined(i)` gives the counts of v, vt and vn before the piece's i-th line, for relative indices."""
        # One piece, not the file: an odd line costs a piece of Python work, and the words stay the line reader's.
        reader = LineReader(self.file.source)
        for position, line in enumerate(self.lines[first:stop].tolist()):
            if defined is not None:
                reader.defined = defined(position)
            try:
                reader.read_line(self.file.lines.number_of_line(line), self.file.content(line))
            except LoadError as error:
                self.file.errors.append(error)  # list.append is atomic: pieces run on several threads
                return None
        return reader


@dataclass
class _Blob:
    """Lines of one kind, copied together after _PAD separators, their keywords blanked."""

    data: np.ndarray  # uint8
    newlines: np.ndarray  # offset of each line's newline in data

    @classmethod
    def gather(cls, file: _File, lines: np.ndarray, keyword_length: int) -> _Blob:
        line_start, line_end = file.lines.start, file.lines.end
        lengths = line_end[lines] - line_start[lines] + 1
        newlines = _PAD - 1 + np.cumsum(lengths)
        pieces = _line_runs(file.buf, line_start, line_end, lines)
        tail = 8 + (-(_PAD + int(lengths.sum()))) % 8  # whole uint64 words, one spare
        data = np.concatenate([_SPACES[:_PAD], *pieces, _SPACES[:tail]])
        keyword_at = newlines + 1 - lengths
        if file.indented and lines.size:
            moved = np.array(list(file.indented.items()), dtype=np.int64)  # (line, keyword offset) rows
            where = np.minimum(np.searchsorted(lines, moved[:, 0]), lines.size - 1)
            ours = lines[where] == moved[:, 0]
            keyword_at[where[ours]] += moved[ours, 1]
        for step in range(keyword_length):
            data[keyword_at + step] = ord(" ")
        return cls(data, newlines)

    def words(self) -> np.ndarray:
        """The data as aligned little-endian uint64 words (see _words_before)."""
        return self.data.view("<u8")

    def blank_comments(self) -> bool:
        """Overwrites each line's comment, '#' to its end, with spaces; False when there is none."""
        hashes = np.flatnonzero(self.data == ord("#"))
        if hashes.size == 0:
            return False
        line_ends = self.newlines[np.searchsorted(self.newlines, hashes)]
        first_of_line = np.concatenate(([True], line_ends[1:] != line_ends[:-1]))
        starts, lengths = hashes[first_of_line], line_ends[first_of_line] - hashes[first_of_line]
        self.data[np.repeat(starts - np.cumsum(lengths) + lengths, lengths) + np.arange(int(lengths.sum()))] = ord(" ")
        return True


def _parse_blob(parse: Callable[[_Blob], _Parsed], blob: _Blob) -> _Parsed:
    """parse(blob); when that fails and the lines hold trailing comments, parse(blob) without them."""
    try:
        return parse(blob)
    except Unusual:
        if not blob.blank_comments():
            raise
    return parse(blob)


def _line_runs(buf: np.ndarray, line_start: np.ndarray, line_end: np.ndarray, lines: np.ndarray) -> list[np.ndarray]:
    """The bytes of the given lines as few pieces: lines that follow each other in the text are one slice."""
    if lines.size == 0:
        return []
    breaks = np.flatnonzero(line_start[lines[1:]] != line_end[lines[:-1]] + 1) + 1
    low = line_start[lines[np.concatenate(([0], breaks))]]
    high = line_end[lines[np.concatenate((breaks - 1, [lines.size - 1]))]] + 1
    if low.size <= 4096:  # the usual case: big blocks of v, vt, vn and f lines
        return [buf[a:b] for a, b in zip(low.tolist(), high.tolist())]
    lengths = high - low
    offsets = np.repeat(low - (np.cumsum(lengths) - lengths), lengths)
    return [buf[offsets + np.arange(int(lengths.sum()))]]


# Byte tests by arithmetic on whole chunks: a lookup table or bincount costs numpy far more.
def _is_digit(chunk: np.ndarray) -> np.ndarray:
    return (chunk - np.uint8(ord("0"))) < np.uint8(10)  # uint8 wraps below '0'


def _is_space(chunk: np.ndarray) -> np.ndarray:
    return (chunk == np.uint8(ord(" "))) | ((chunk - np.uint8(ord("\t"))) < np.uint8(5))  # \t \n \v \f \r


def _count(mask: np.ndarray) -> int:
    return int(np.count_nonzero(mask))


def _runs(mask: np.ndarray, offset: int) -> tuple[np.ndarray, np.ndarray]:
    """Start and end (exclusive) offsets of every run of True, plus offset.

    A chunk begins with a line's (blanked) keyword or indentation and ends with a newline, so it
    never begins or ends inside a run and the edges pair up.
    """
    edges = np.flatnonzero(mask[1:] != mask[:-1]) + (offset + 1)
    return edges[0::2], edges[1::2]


def _per_line(token_starts: np.ndarray, newlines: np.ndarray, chunk_start: int) -> np.ndarray:
    """How many tokens each line holds, for tokens and lines of one chunk."""
    width, extra = divmod(token_starts.size, max(newlines.size, 1))
    if width and not extra:  # the usual case, every line alike: check that instead of counting
        line_starts = np.concatenate(([chunk_start], newlines[:-1]))
        if np.all(token_starts[::width] > line_starts) and np.all(token_starts[width - 1::width] < newlines):
            return np.full(newlines.size, width)
    return np.diff(np.searchsorted(token_starts, newlines), prepend=0)


# --- number tables (v, vt, vn) --------------------------------------------------------------------


def _float_table(file: _File, kind: int, fewest: int, most: int) -> np.ndarray:
    """(lines, fewest) float64 from lines of fewest..most numbers each, extra numbers dropped; a piece
    with an error adds it to file.errors and no rows."""
    source = _Lines.of(file, kind)
    if source.count == 0:
        return np.zeros((0, fewest))
    pieces = _chunk_map(lambda piece: _float_piece(source, *piece, fewest, most), source.pieces())
    return pieces[0] if len(pieces) == 1 else np.concatenate(pieces)


def _float_piece(source: _Lines, first: int, stop: int, fewest: int, most: int) -> np.ndarray:
    try:
        if source.lengths(first, stop).max() > _LONGEST_TABLE_LINE:
            raise Unusual
        values, per_line = _parse_blob(lambda blob: _float_chunk(blob, fewest, most), source.blob(first, stop))
    except Unusual:
        reader = source.read_by_lines(first, stop)
        if reader is None:
            return np.zeros((0, fewest))
        return np.frombuffer(reader.tables[_TABLE_KINDS.index(source.kind)], dtype=np.float64).reshape(-1, fewest)
    if per_line.min() == per_line.max():
        table = values.reshape(per_line.size, -1)
        return table if table.shape[1] == fewest else table[:, :fewest].copy()
    first_value = np.cumsum(per_line) - per_line
    return values[first_value[:, None] + np.arange(fewest)]


def _float_chunk(blob: _Blob, fewest: int, most: int) -> tuple[np.ndarray, np.ndarray]:
    """The numbers of the blob's lines in order, and how many each line has (fewest..most)."""
    values, per_line = _float_numbers(blob)
    if per_line.min() < fewest or per_line.max() > most or not np.all(np.abs(values) <= FLOAT32_MAX):
        raise Unusual  # NaN fails the comparison too
    return values, per_line


def _float_numbers(blob: _Blob) -> tuple[np.ndarray, np.ndarray]:
    """The numbers of the blob's lines in order, and how many each line has."""
    low, high = _PAD, int(blob.newlines[-1]) + 1
    chunk = blob.data[low:high]
    in_token = ~_is_space(chunk)
    dot = chunk == np.uint8(ord("."))
    exotic = (chunk == np.uint8(ord("+"))) | ((chunk | np.uint8(0x20)) == np.uint8(ord("e")))  # + e E
    minus_count = _count(chunk == np.uint8(ord("-")))
    plain = _count(_is_digit(chunk)) + _count(dot) + minus_count
    has_exotic = _count(exotic)
    if plain + has_exotic != _count(in_token):
        raise Unusual  # some other character
    starts, ends = _runs(in_token, low)
    per_line = _per_line(starts, blob.newlines, low)
    if starts.size == 0:
        return np.zeros(0), per_line
    if has_exotic:
        return _strtod(chunk, starts.size), per_line
    values = _plain_decimals(blob.data, blob.words(), starts, ends, np.flatnonzero(dot) + low, minus_count)
    return (_strtod(chunk, starts.size) if values is None else values), per_line


def _strtod(chunk: np.ndarray, expected: int) -> np.ndarray:
    """numpy's C parser for exponents, '+' and long numbers; anything it cannot read is unusual."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            values = np.fromstring(chunk.tobytes(), sep=" ")
        except ValueError:
            raise Unusual from None
    if values.size != expected:
        raise Unusual
    return values


def _plain_decimals(data: np.ndarray, words: np.ndarray, starts: np.ndarray, ends: np.ndarray,
                    dots: np.ndarray, minus_count: int) -> np.ndarray | None:
    """Numbers like -12.5, .5, 7. or 3 read with integer arithmetic; None when too long for that.

    A stray '-' or second '.' lands inside a digit run, where the digit check rejects it; when the
    counts show there is none, the check is skipped.
    """
    negative = data[starts] == ord("-")
    one_dot_each = dots.size == starts.size and np.all(dots > starts) and np.all(dots < ends)
    check = not one_dot_each or minus_count != _count(negative)
    if one_dot_each:
        integer_end = dots  # the usual case
    else:
        integer_end = ends.copy()
        integer_end[np.searchsorted(starts, dots, side="right") - 1] = dots
    fraction_length = np.maximum(ends - integer_end - 1, 0)
    integer_length = integer_end - starts - negative
    digits = integer_length + fraction_length
    if digits.min() < 1:
        raise Unusual  # '-', '.', '-.'
    if digits.max() > MAX_DIGITS:
        return None
    scale = _table_lookup(_POW10_U64, fraction_length)
    mantissa = (_digits_value(words, integer_end, integer_length, check) * scale
                + _digits_value(words, ends, fraction_length, check))
    values = mantissa / _table_lookup(_POW10_FLOAT, fraction_length)
    np.negative(values, out=values, where=negative)
    return values


# SWAR ("SIMD within a register") parsing of up to 8 ASCII digits held in one uint64: the method of
# simdjson's parse_eight_digits_unrolled, run on whole arrays.
_U64 = np.uint64
_KEEP = np.array([~((1 << (8 * (8 - n))) - 1) & (2**64 - 1) for n in range(9)], dtype=np.uint64)
_ZEROS = _U64(0x3030303030303030)
_FILL = ~_KEEP & _ZEROS
_ABOVE_NINE = _U64(0x4646464646464646)
_HIGH_BITS = _U64(0x8080808080808080)
_BYTE_PAIRS = _U64(0x000000FF000000FF)
_MUL_1 = _U64(100 + (1000000 << 32))
_MUL_2 = _U64(1 + (10000 << 32))


def _digits_value(words: np.ndarray, ends: np.ndarray, lengths: np.ndarray, check: bool) -> np.ndarray:
    """uint64 value of the `lengths` (0..16) digits ending before each offset in `ends`.

    With `check`, a byte that is not a digit raises Unusual.
    """
    low = np.minimum(lengths, 8)
    value = _eight_digits(words, ends, low, check)
    high = lengths - low
    if high.any():
        value += _eight_digits(words, ends - 8, high, check) * _U64(10**8)
    return value


def _table_lookup(table: np.ndarray, index: np.ndarray) -> np.ndarray | np.generic:
    """table[index], as one scalar when every index is the same (numbers of one format)."""
    low = index.min()
    return table[low] if low == index.max() else table[index]


def _words_before(words: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """The 8 bytes before each offset as a uint64, from the two aligned words they straddle."""
    start = ends - 8
    shift = (start.view(np.uint64) & _U64(7)) << _U64(3)  # offsets are never negative
    index = start >> 3
    return (words[index] >> shift) | (words[index + 1] << (_U64(64) - shift))  # numpy: x << 64 == 0


def _eight_digits(words: np.ndarray, ends: np.ndarray, lengths: np.ndarray, check: bool) -> np.ndarray:
    word = _words_before(words, ends)  # the number's bytes are the high ones, its first digit the lowest
    word &= _table_lookup(_KEEP, lengths)
    word |= _table_lookup(_FILL, lengths)  # left-pad with '0' digits
    if check and np.any(((word + _ABOVE_NINE) | (word - _ZEROS)) & _HIGH_BITS):
        raise Unusual  # a byte that is not a digit (bytes are ASCII here, so no carries)
    word -= _ZEROS
    word = word * _U64(10) + (word >> _U64(8))
    return ((word & _BYTE_PAIRS) * _MUL_1 + ((word >> _U64(16)) & _BYTE_PAIRS) * _MUL_2) >> _U64(32)


# --- faces ----------------------------------------------------------------------------------------

# Which field (v, vt, vn) each number of a corner is, by the corner's format.
_CORNER_FIELDS = {(True,): (0,), (True, True): (0, 1), (True, False, True): (0, 2), (True, True, True): (0, 1, 2)}


def _face_table(file: _File) -> tuple[list[np.ndarray | None], np.ndarray]:
    """Per corner, the 0-based v, vt, vn (see _Faces) and face_start; a piece with an error adds it to
    file.errors and no faces."""
    source = _Lines.of(file, _F)
    faces = _chunk_map(lambda piece: _face_piece(source, *piece), source.pieces())
    per_line = np.concatenate([piece.per_line for piece in faces]) if faces else np.zeros(0, np.int64)
    fields: list[np.ndarray | None] = [None, None, None]
    for field in range(3):
        if all(piece.columns[field] is None for piece in faces):
            continue
        fields[field] = np.concatenate([np.full(piece.corners, -1) if piece.columns[field] is None
                                        else piece.columns[field] for piece in faces])
        for piece in faces:  # a field's pieces go once joined: the peak holds one field twice, not all
            piece.columns[field] = None
    return fields, np.concatenate(([0], np.cumsum(per_line)))


def _face_piece(source: _Lines, first: int, stop: int) -> _Faces:
    try:
        return _parse_blob(lambda blob: _face_chunk(blob, source, first, stop), source.blob(first, stop))
    except Unusual:
        defined = source.file.defined_before(source.lines[first:stop])
        reader = source.read_by_lines(first, stop, lambda line: [int(counts[line]) for counts in defined])
        if reader is None:
            return _Faces([None, None, None], np.zeros(0, dtype=np.int64))
        columns = [np.frombuffer(column, dtype=np.int64) for column in reader.corners]
        return _Faces([column if np.any(column >= 0) else None for column in columns],
                      np.frombuffer(reader.face_sizes, dtype=np.int64))


def _corner_shape(blob: _Blob) -> tuple[bool, ...]:
    """Which of v/vt/vn the first corner has; every other corner must match it."""
    tokens = blob.data[_PAD:_PAD + 256].tobytes().split(None, 1)
    shape = tuple(bool(part) for part in tokens[0].split(b"/")) if tokens else ()
    if shape not in CORNER_GAPS:
        raise Unusual
    return shape


def _face_chunk(blob: _Blob, source: _Lines, first: int, stop: int) -> _Faces:
    """Each field's 0-based indices, as a contiguous column per field (made here, while the chunk is in
    the cache, not over the whole table later), and how many corners each line has."""
    shape = _corner_shape(blob)
    gaps = CORNER_GAPS[shape]
    low, high = _PAD, int(blob.newlines[-1]) + 1
    chunk = blob.data[low:high]
    minus = chunk == np.uint8(ord("-"))
    in_number = _is_digit(chunk) | minus
    slashes = _count(chunk == np.uint8(ord("/")))
    if _count(in_number) + slashes + _count(_is_space(chunk)) != chunk.size:
        raise Unusual  # some other character
    starts, ends = _runs(in_number, low)
    width = len(gaps) + 1
    if starts.size % width or slashes != sum(gaps) * (starts.size // width):
        raise Unusual
    corner_starts, corner_ends = starts.reshape(-1, width), ends.reshape(-1, width)
    per_line = _per_line(corner_starts[:, 0], blob.newlines, low)
    if per_line.min() < 3:
        raise Unusual
    _check_corner_layout(blob.data, corner_starts, corner_ends, gaps)
    signed = _count(minus) > 0  # relative indices; a '-' inside a number fails the digit check
    negative = blob.data[starts] == ord("-") if signed else False
    lengths = ends - starts - negative
    if lengths.min() < 1 or lengths.max() > MAX_DIGITS:
        raise Unusual
    magnitude = _digits_value(blob.words(), ends, lengths, check=signed).view(np.int64)
    if magnitude.min() == 0:
        raise Unusual  # index 0
    columns: list[np.ndarray | None] = [None, None, None]
    if signed:
        raw = np.where(negative, -magnitude, magnitude).reshape(-1, width)
        defined = _Lazy(lambda: source.file.defined_before(np.repeat(source.lines[first:stop], per_line)))
        for column, field in enumerate(_CORNER_FIELDS[shape]):
            columns[field] = _resolve_indices(raw[:, column], defined, field)
    else:
        raw = magnitude.reshape(-1, width)
        for column, field in enumerate(_CORNER_FIELDS[shape]):
            columns[field] = np.subtract(raw[:, column], 1)
    return _Faces(columns, per_line)


def _check_corner_layout(data: np.ndarray, starts: np.ndarray, ends: np.ndarray, gaps: tuple[int, ...]) -> None:
    """Every corner is exactly number(/number) with the first corner's slashes, between spaces."""
    ok = _IS_SPACE[data[starts[:, 0] - 1]] & _IS_SPACE[data[ends[:, -1]]]
    for column, gap in enumerate(gaps):
        ok &= starts[:, column + 1] - ends[:, column] == gap
        for step in range(gap):
            ok &= data[np.minimum(ends[:, column] + step, data.size - 1)] == ord("/")
    if not ok.all():
        raise Unusual


class _Lazy:
    """A value computed on first use: the counts before each corner are needed only for relative indices."""

    def __init__(self, make: Callable[[], list[np.ndarray]]) -> None:
        self.make, self.value = make, None

    def get(self) -> list[np.ndarray]:
        if self.value is None:
            self.value = self.make()
        return self.value


def _resolve_indices(raw: np.ndarray, defined_before: _Lazy, field: int) -> np.ndarray:
    """The file's indices (never 0) of one field to 0-based ones: positive ones less one, negative ones
    counted back from the definitions before their line. One reaching before the first is unusual."""
    if raw.min() > 0:
        return raw - 1
    resolved = np.where(raw < 0, defined_before.get()[field] + raw, raw - 1)
    if resolved.min() < 0:
        raise Unusual
    return resolved
