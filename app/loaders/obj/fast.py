"""The fast OBJ reader: the whole byte buffer at once with numpy, on several threads.

Lines are classified by their first bytes, the lines of each kind (v, vt, vn, f) are copied together
and parsed in cache-sized chunks, every check is an array operation, and digits are read eight at a
time (SWAR). Only rare statements (o, g, s, usemtl, mtllib, unknown ones, indented lines) cost
Python work per line. Anything it does not handle, valid or not, raises Unusual, and the line reader
takes over: so reporting errors costs this reader nothing.
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

from marraztu.loaders.obj.raw import CORNER_GAPS, MAX_DIGITS, ColourComment, RawObj, statement
from marraztu.model.geometry import FLOAT32_MAX


class Unusual(Exception):
    """The fast reader met something it does not handle; the line-by-line reader takes over."""


_SKIP, _V, _VT, _VN, _F = 0, 1, 2, 3, 4
_UNCLASSIFIED = 255
_KEYWORDS = {b"v": _V, b"vt": _VT, b"vn": _VN, b"f": _F}
_KEYWORD_LENGTH = {_V: 1, _VT: 2, _VN: 2, _F: 1}

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
_Chunk = TypeVar("_Chunk")  # a piece of work: a byte offset, a range of lines
_ChunkResult = TypeVar("_ChunkResult")
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


def read_fast(text: bytes) -> RawObj:
    buf = np.frombuffer(text, dtype=np.uint8)
    line_end = _newlines(buf)
    line_start = np.concatenate(([0], line_end[:-1] + 1))
    kinds, comments = _classify_lines(buf, line_start)
    indented, mtllib = _settle_irregular_lines(text, line_start, line_end, kinds, comments)
    colour = ColourComment()
    for line in sorted(comments):
        colour.offer(line + 1, text[int(line_start[line]):int(line_end[line])])
    lines = {kind: np.flatnonzero(kinds == kind) for kind in (_V, _VT, _VN, _F)}
    if lines[_F].size == 0:
        raise Unusual  # "no faces" is reported by the line reader, after any earlier error

    def of_kind(kind: int) -> _Lines:
        return _Lines(buf, line_start, line_end, lines[kind], _KEYWORD_LENGTH[kind], indented)

    positions = _float_table(of_kind(_V), fewest=3, most=7)
    texcoords = _float_table(of_kind(_VT), fewest=2, most=3)
    normals = _float_table(of_kind(_VN), fewest=3, most=3)
    totals = {_V: len(positions), _VT: len(texcoords), _VN: len(normals)}
    fields, face_start = _face_table(of_kind(_F))
    corner_lines = _Lazy(lambda: np.repeat(lines[_F], np.diff(face_start)))
    resolved = [None if raw is None else _resolve_indices(raw, kind, totals[kind], kinds, corner_lines)
                for raw, kind in zip(fields, (_V, _VT, _VN))]
    return RawObj(positions, texcoords, normals, resolved[0], resolved[1], resolved[2], face_start, mtllib,
                   colour.colour, colour.notes)


def _newlines(buf: np.ndarray) -> np.ndarray:
    """Offsets of every newline, found chunk by chunk on several threads: a mask of the whole file would be
    a temporary as large as the file, in fresh memory that costs more to touch than the scan itself."""
    pieces = _chunk_map(lambda low: np.flatnonzero(buf[low:low + _CHUNK_BYTES] == ord("\n")) + low,
                        range(0, buf.size, _CHUNK_BYTES))
    return np.concatenate(pieces) if pieces else np.zeros(0, np.int64)


class _Lazy:
    """A value computed on first use: line numbers of corners are needed only for relative indices."""

    def __init__(self, make: Callable[[], np.ndarray]) -> None:
        self.make, self.value = make, None

    def get(self) -> np.ndarray:
        if self.value is None:
            self.value = self.make()
        return self.value


def _classify_lines(buf: np.ndarray, line_start: np.ndarray) -> tuple[np.ndarray, list[int]]:
    """Kind of each line from its first three bytes (the rare others stay _UNCLASSIFIED), and the lines
    that start with '#'; in pieces of _CHUNK_LINES lines on several threads."""
    pieces = _chunk_map(lambda low: _classify_piece(buf, line_start[low:low + _CHUNK_LINES], low),
                        range(0, line_start.size, _CHUNK_LINES))
    if not pieces:
        return np.zeros(0, np.uint8), []
    return np.concatenate([kinds for kinds, _ in pieces]), np.concatenate([hashes for _, hashes in pieces]).tolist()


def _classify_piece(buf: np.ndarray, line_start: np.ndarray, first_line: int) -> tuple[np.ndarray, np.ndarray]:
    first = buf[line_start]
    second = buf[np.minimum(line_start + 1, buf.size - 1)]  # an empty last line has no second byte
    kinds = np.full(line_start.size, _UNCLASSIFIED, dtype=np.uint8)
    kinds[(first == ord("#")) | (first == ord("\n"))] = _SKIP
    one_letter = _IS_SPACE[second]
    kinds[(first == ord("v")) & one_letter] = _V
    kinds[(first == ord("f")) & one_letter] = _F
    two_letter = np.flatnonzero((first == ord("v")) & ((second == ord("t")) | (second == ord("n"))))
    two_letter = two_letter[_IS_SPACE[buf[line_start[two_letter] + 2]]]
    kinds[two_letter] = np.where(second[two_letter] == ord("t"), _VT, _VN)
    return kinds, np.flatnonzero(first == ord("#")) + first_line


def _settle_irregular_lines(text: bytes, line_start: np.ndarray, line_end: np.ndarray, kinds: np.ndarray,
                            comments: list[int]) -> tuple[dict[int, int], str | None]:
    """Per-line Python work for the rare lines: indented ones, and o/g/s/usemtl/mtllib/unknown.

    Returns the keyword offset of indented v/vt/vn/f lines, and the first mtllib; adds indented
    comment lines to `comments`.
    """
    indented: dict[int, int] = {}
    mtllib = None
    for line in np.flatnonzero(kinds == _UNCLASSIFIED).tolist():
        content = text[int(line_start[line]):int(line_end[line])]
        keyword, rest = statement(content)
        kinds[line] = _KEYWORDS.get(keyword, _SKIP)
        if kinds[line] != _SKIP:
            indented[line] = content.index(keyword)
        elif keyword == b"mtllib" and mtllib is None:
            mtllib = rest.decode("utf-8", errors="replace")
        elif not keyword and content.lstrip().startswith(b"#"):
            comments.append(line)
    return indented, mtllib


@dataclass
class _Lines:
    """The lines of one kind, where they are in the file's bytes, and how to cut them into pieces.

    Each piece of about _CHUNK_BYTES is copied into a blob of its own by the thread that parses it,
    right before parsing: the copy is still in the CPU cache when it is read, the threads share the
    copying, and no copy of the whole file's lines is ever made."""

    buf: np.ndarray
    line_start: np.ndarray
    line_end: np.ndarray
    lines: np.ndarray  # the line numbers, ascending
    keyword_length: int
    indented: dict[int, int]

    @property
    def count(self) -> int:
        return int(self.lines.size)

    def pieces(self) -> list[tuple[int, int]]:
        """[first, stop) ranges of `lines`, whole lines of about _CHUNK_BYTES each, in order."""
        if self.count == 0:
            return []
        ends = np.cumsum(self.line_end[self.lines] - self.line_start[self.lines] + 1)
        targets = np.arange(_CHUNK_BYTES, int(ends[-1]), _CHUNK_BYTES)
        cuts = np.concatenate(([0], np.searchsorted(ends, targets) + 1, [self.count]))
        # Already sorted, so drop repeats by hand: np.unique imports numpy.ma, which slows start-up.
        cuts = cuts[np.concatenate(([True], cuts[1:] != cuts[:-1]))]
        return list(zip(cuts[:-1].tolist(), cuts[1:].tolist()))

    def blob(self, first: int, stop: int) -> _Blob:
        return _Blob.gather(self.buf, self.line_start, self.line_end, self.lines[first:stop], self.keyword_length,
                            self.indented)


@dataclass
class _Blob:
    """Lines of one kind, copied together after _PAD separators, their keywords blanked."""

    data: np.ndarray  # uint8
    newlines: np.ndarray  # offset of each line's newline in data

    @classmethod
    def gather(cls, buf: np.ndarray, line_start: np.ndarray, line_end: np.ndarray, lines: np.ndarray,
               keyword_length: int, indented: dict[int, int]) -> _Blob:
        lengths = line_end[lines] - line_start[lines] + 1
        newlines = _PAD - 1 + np.cumsum(lengths)
        pieces = _line_runs(buf, line_start, line_end, lines)
        tail = 8 + (-(_PAD + int(lengths.sum()))) % 8  # whole uint64 words, one spare
        data = np.concatenate([_SPACES[:_PAD], *pieces, _SPACES[:tail]])
        keyword_at = newlines + 1 - lengths
        if indented and lines.size:
            moved = np.array(list(indented.items()), dtype=np.int64)  # (line, keyword offset) rows
            where = np.minimum(np.searchsorted(lines, moved[:, 0]), lines.size - 1)
            ours = lines[where] == moved[:, 0]
            keyword_at[where[ours]] += moved[ours, 1]
        for step in range(keyword_length):
            data[keyword_at + step] = ord(" ")
        return cls(data, newlines)

    def words(self) -> np.ndarray:
        """The data as aligned little-endian uint64 words (see _words_before)."""
        return self.data.view("<u8")


def _line_runs(buf: np.ndarray, line_start: np.ndarray, line_end: np.ndarray, lines: np.ndarray) -> list[np.ndarray]:
    """The bytes of the given lines as few pieces: consecutive lines are one slice."""
    if lines.size == 0:
        return []
    breaks = np.flatnonzero(np.diff(lines) != 1) + 1
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


def _float_table(source: _Lines, fewest: int, most: int) -> np.ndarray:
    """(lines, fewest) float64 from lines of fewest..most numbers each; extra numbers dropped."""
    if source.count == 0:
        return np.zeros((0, fewest))

    pieces = _chunk_map(lambda piece: _float_chunk(source.blob(*piece)), source.pieces())
    values = np.concatenate([values for values, _ in pieces])
    per_line = np.concatenate([counts for _, counts in pieces])
    if per_line.min() < fewest or per_line.max() > most or not np.all(np.abs(values) <= FLOAT32_MAX):
        raise Unusual  # NaN fails the comparison too
    if per_line.min() == per_line.max():
        table = values.reshape(source.count, -1)
        return table if table.shape[1] == fewest else table[:, :fewest].copy()
    first = np.cumsum(per_line) - per_line
    return values[first[:, None] + np.arange(fewest)]


def _float_chunk(blob: _Blob) -> tuple[np.ndarray, np.ndarray]:
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


def _face_table(source: _Lines) -> tuple[list[np.ndarray | None], np.ndarray]:
    """Per corner, the file's index minus one for v, vt, vn (None when absent; see _resolve_indices),
    and face_start."""
    shape = _corner_shape(source.blob(0, 1))
    gaps = CORNER_GAPS[shape]

    pieces = _chunk_map(lambda piece: _face_chunk(source.blob(*piece), gaps), source.pieces())
    per_line = np.concatenate([counts for _, counts in pieces])
    if per_line.min() < 3:
        raise Unusual
    chunk_columns: list[list[np.ndarray | None]] = [columns for columns, _ in pieces]  # type: ignore[misc]
    del pieces
    fields: list[np.ndarray | None] = [None, None, None]
    for column, field in enumerate(_CORNER_FIELDS[shape]):
        fields[field] = np.concatenate([columns[column] for columns in chunk_columns])
        for columns in chunk_columns:  # a field's pieces go once joined: the peak holds one field twice, not all
            columns[column] = None
    return fields, np.concatenate(([0], np.cumsum(per_line)))


def _corner_shape(blob: _Blob) -> tuple[bool, ...]:
    """Which of v/vt/vn the first corner has; every other corner must match it."""
    tokens = blob.data[_PAD:_PAD + 256].tobytes().split(None, 1)
    shape = tuple(bool(part) for part in tokens[0].split(b"/")) if tokens else ()
    if shape not in CORNER_GAPS:
        raise Unusual
    return shape


def _face_chunk(blob: _Blob, gaps: tuple[int, ...]) -> tuple[list[np.ndarray], np.ndarray]:
    """Each field's index minus one, as a contiguous column per field (made here, while the chunk is in
    the cache, not over the whole table later), and how many corners each line has."""
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
    if starts.size == 0:
        return [np.zeros(0, dtype=np.int64)] * width, per_line
    _check_corner_layout(blob.data, corner_starts, corner_ends, gaps)
    signed = _count(minus) > 0  # relative indices; a '-' inside a number fails the digit check
    negative = blob.data[starts] == ord("-") if signed else False
    lengths = ends - starts - negative
    if lengths.min() < 1 or lengths.max() > MAX_DIGITS:
        raise Unusual
    magnitude = _digits_value(blob.words(), ends, lengths, check=signed).view(np.int64)
    raw = (np.where(negative, -magnitude, magnitude) if signed else magnitude).reshape(-1, width)
    return [np.subtract(raw[:, column], 1) for column in range(width)], per_line


def _check_corner_layout(data: np.ndarray, starts: np.ndarray, ends: np.ndarray, gaps: tuple[int, ...]) -> None:
    """Every corner is exactly number(/number) with the first corner's slashes, between spaces."""
    ok = _IS_SPACE[data[starts[:, 0] - 1]] & _IS_SPACE[data[ends[:, -1]]]
    for column, gap in enumerate(gaps):
        ok &= starts[:, column + 1] - ends[:, column] == gap
        for step in range(gap):
            ok &= data[np.minimum(ends[:, column] + step, data.size - 1)] == ord("/")
    if not ok.all():
        raise Unusual


def _resolve_indices(shifted: np.ndarray, kind: int, total: int, kinds: np.ndarray, corner_lines: _Lazy
                     ) -> np.ndarray:
    """The file's indices minus one to 0-based ones: positive indices are already; -1 is the file's
    index 0 and below that are relative (negative) indices. Out of range is unusual."""
    resolved = shifted
    if resolved.min() < 0:  # index 0 or relative indices
        if np.any(shifted == -1):
            raise Unusual
        negative = shifted < 0
        defined_before = np.cumsum(kinds == kind)[corner_lines.get()]
        resolved = np.where(negative, defined_before + shifted + 1, shifted)
        if resolved.min() < 0:
            raise Unusual
    if resolved.max() >= total:
        raise Unusual
    return resolved
