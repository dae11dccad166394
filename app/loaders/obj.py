"""Wavefront OBJ reader: one file becomes one Mesh, quickly and strictly.

Why our own reader and not trimesh's: trimesh silently reads tab-separated lines as nothing, accepts
index 0, drops a truncated last face and accepts NaN. A viewer for students must instead say what is
wrong and on which line.

Two readers produce the same raw tables:

* the fast reader works on the byte buffer with numpy: lines are classified by their first bytes,
  the lines of each kind (v, vt, vn, f) are copied together and parsed in cache-sized chunks, with
  every check an array operation and digits read eight at a time (SWAR). Only rare statements
  (o, g, s, usemtl, mtllib, unknown ones, indented lines) cost Python work per line.
* the line-by-line reader is the authority on meaning. It runs only when the fast reader meets
  anything it does not handle, valid or not (mixed corner formats across faces, trailing comments,
  line continuations, any error). It returns the same tables, or raises the LoadError naming the
  first offending line; so error reporting costs the fast reader nothing.

Normals and texture coordinates are then derived by the same code as ``build_mesh``'s.
"""

from __future__ import annotations

import itertools
import os
import re
import threading
import warnings
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

import numpy as np

from app.errors import LoadError
from app.loaders.files import read_file
from app.mesh import Mesh, column_bounds, fan_triangles

# --------------------------------------------------------------------------------------------------
# Public API
# --------------------------------------------------------------------------------------------------


def load_obj(path: str | Path, stage: Callable[[str], None] | None = None) -> Mesh:
    """Read an OBJ file into a Mesh; every problem becomes a LoadError naming the file.

    `stage` hears "reading" and then "parsing" (the window's loader thread shows them)."""
    if stage is not None:
        stage("reading")
    data = read_file(path)
    if stage is not None:
        stage("parsing")
    return parse_obj(data, str(path), base_dir=Path(path).parent)


def parse_obj(data: bytes, source: str, base_dir: str | Path | None = None) -> Mesh:
    """Parse OBJ bytes; ``source`` names the file in messages and gives the mesh its name (the stem).

    ``base_dir`` is where ``mtllib`` files are looked for; without it the MTL is not read.
    """
    try:
        return _parse(data, source, None if base_dir is None else Path(base_dir))
    except LoadError:
        raise
    except MemoryError:
        raise LoadError(source, "not enough memory to load this file") from None
    except Exception as error:  # the contract: bad input never escapes as anything but LoadError
        raise LoadError(source, f"could not read the model ({type(error).__name__}: {error})") from None


def build_mesh(
    name: str,
    positions: np.ndarray | Sequence[Sequence[float]],
    faces: Sequence[Sequence[int]] | np.ndarray,
    uvs: np.ndarray | Sequence[Sequence[float]] | None = None,
    normals: np.ndarray | Sequence[Sequence[float]] | None = None,
    base_colour: tuple[float, float, float] | None = None,
    file_material: dict[str, object] | None = None,
    warnings: Sequence[str] = (),
) -> Mesh:
    """A Mesh from plain tables, with normals and texture coordinates derived as the loader does.

    ``faces`` holds 0-based vertex indices, one sequence per polygon (3 or more). ``uvs`` and
    ``normals`` are per corner, in the order the faces list their corners; a NaN row means "derive
    this one". Raises ValueError for impossible input (this is a programming interface).
    """
    points = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    corner_vertex, face_start = _faces_to_csr(faces)
    if corner_vertex.size and (corner_vertex.min() < 0 or corner_vertex.max() >= len(points)):
        raise ValueError("a face refers to a vertex that does not exist")
    corners = corner_vertex.size
    given_uv = None if uvs is None else _per_corner_table(uvs, corners, 2)
    given_normals = None if normals is None else _per_corner_table(normals, corners, 3)
    return _derive_mesh(name, points, corner_vertex, face_start, given_uv, given_normals,
                        base_colour, file_material, tuple(warnings))


# About ten million triangles; deriving a mesh needs several times the file's size in memory.
def _per_corner_table(values: np.ndarray | Sequence[Sequence[float]], corners: int, width: int
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Per-corner values as a (table, index) pair; rows with NaN get index -1 (derived instead)."""
    table = np.asarray(values, dtype=np.float64).reshape(corners, width)
    return table, np.where(np.isnan(table).any(axis=1), -1, np.arange(corners))


# --------------------------------------------------------------------------------------------------
# Reading and the two readers' shared result
# --------------------------------------------------------------------------------------------------

# Zero-area faces get a fallback normal; "zero" is relative to the model's size.
_DEGENERATE_AREA = 1e-12
_FALLBACK_NORMAL = np.array([0.0, 0.0, 1.0])
# The renderer works in float32: a number beyond this would become infinite there.
_FLOAT32_MAX = float(np.finfo(np.float32).max)


@dataclass
class _RawObj:
    """The file's tables as read, before anything is derived. Corner indices are 0-based."""

    positions: np.ndarray  # (V, 3) float64
    texcoords: np.ndarray  # (T, 2) float64
    normals: np.ndarray  # (N, 3) float64
    corner_vertex: np.ndarray  # (C,) int64
    corner_texcoord: np.ndarray | None  # (C,) int64, -1 where a corner has no vt; None: no corner has
    corner_normal: np.ndarray | None  # (C,) int64, likewise for vn
    face_start: np.ndarray  # (F + 1,) int64
    mtllib: str | None
    colour: tuple[float, float, float] | None  # the seed reader's "# colour r g b", in 0..1
    notes: list[str]


def _parse(data: bytes, source: str, base_dir: Path | None) -> Mesh:
    text = _normalized_text(data, source)
    raw = _read_tables(text, source)
    notes = list(raw.notes)
    material = None
    if raw.mtllib is not None and base_dir is not None:
        material = _first_material(base_dir, raw.mtllib, notes)
    uv = None if raw.corner_texcoord is None else (raw.texcoords, raw.corner_texcoord)
    normals = None if raw.corner_normal is None else (raw.normals, raw.corner_normal)
    return _derive_mesh(Path(source).stem, raw.positions, raw.corner_vertex, raw.face_start,
                        uv, normals, raw.colour, material, tuple(notes))


def _read_tables(text: bytes, source: str) -> _RawObj:
    if not _needs_line_reader(text):
        try:
            return _read_fast(text)
        except _Unusual:
            pass
        except MemoryError:
            raise
        except Exception:  # a fast-reader bug must not cost the person their model: read it slowly
            pass
    return _read_by_lines(text, source)


def _needs_line_reader(text: bytes) -> bool:
    """Line continuations (a backslash ending a line) change line numbering: the slow reader's job."""
    return b"\\" in text and re.search(rb"\\[^\S\n]*\n", text) is not None


def _normalized_text(data: bytes, source: str) -> bytes:
    """Reject binary data and make sure the last line ends with a newline.

    Tabs, CR (of CRLF) and the other ASCII whitespace stay: both readers treat them as spaces.
    """
    nul = data.find(b"\0")
    if nul >= 0:
        raise LoadError(source, "binary data (a NUL byte), not an OBJ text file", line=_line_of(data, nul))
    if not data.isascii():
        try:
            data.decode("utf-8")
        except UnicodeDecodeError as error:
            raise LoadError(source, "binary data (not UTF-8 text), not an OBJ text file",
                            line=_line_of(data, error.start)) from None
    return data if data.endswith(b"\n") else data + b"\n"


def _line_of(data: bytes, offset: int) -> int:
    return data.count(b"\n", 0, offset) + 1


# --------------------------------------------------------------------------------------------------
# The fast reader
# --------------------------------------------------------------------------------------------------


class _Unusual(Exception):
    """The fast reader met something it does not handle; the line-by-line reader takes over."""


_SKIP, _V, _VT, _VN, _F = 0, 1, 2, 3, 4
_UNCLASSIFIED = 255
_KEYWORDS = {b"v": _V, b"vt": _VT, b"vn": _VN, b"f": _F}
_KEYWORD_LENGTH = {_V: 1, _VT: 2, _VN: 2, _F: 1}

_IS_SPACE = np.zeros(256, dtype=bool)
_IS_SPACE[list(b" \t\n\r\x0b\x0c")] = True


# Up to 15 significant digits the integer mantissa and the power of ten are exact doubles, so one
# division gives the correctly rounded value, the same as Python's float() (Clinger's fast path).
_MAX_FAST_DIGITS = 15
_POW10_U64 = np.array([10**k for k in range(_MAX_FAST_DIGITS + 1)], dtype=np.uint64)
_POW10_FLOAT = np.array([float(10**k) for k in range(_MAX_FAST_DIGITS + 1)])

# Every blob starts with _PAD separators, so the 8-byte words ending at any number (two for 16
# digits) lie inside it. Pieces of a megabyte keep numpy's temporaries in the CPU cache (several
# times faster than whole-file arrays) while each numpy call runs long enough for two threads to
# share the work without waiting on each other for the GIL.
_PAD = 16
_SPACES = np.full(_PAD, ord(" "), dtype=np.uint8)
_CHUNK_BYTES = 1 << 20
_CHUNK_LINES = 1 << 16  # lines classified per piece: about as many bytes of kinds and masks
_Chunk = TypeVar("_Chunk")  # a piece of work: a byte offset, a range of lines
_ChunkResult = TypeVar("_ChunkResult")
# The chunks are independent and numpy releases the GIL inside each operation, so every core parses
# some. (Processes would not share the GIL at all, but each would import numpy and need the text.)
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


def _read_fast(text: bytes) -> _RawObj:
    buf = np.frombuffer(text, dtype=np.uint8)
    line_end = _newlines(buf)
    line_start = np.concatenate(([0], line_end[:-1] + 1))
    kinds, comments = _classify_lines(buf, line_start)
    indented, mtllib = _settle_irregular_lines(text, line_start, line_end, kinds, comments)
    colour = _ColourComment()
    for line in sorted(comments):
        colour.offer(line + 1, text[int(line_start[line]):int(line_end[line])])
    lines = {kind: np.flatnonzero(kinds == kind) for kind in (_V, _VT, _VN, _F)}
    if lines[_F].size == 0:
        raise _Unusual  # "no faces" is reported by the line reader, after any earlier error

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
    return _RawObj(positions, texcoords, normals, resolved[0], resolved[1], resolved[2], face_start, mtllib,
                   colour.colour, colour.notes)


def _newlines(buf: np.ndarray) -> np.ndarray:
    """Offsets of every newline, found chunk by chunk on every core: a mask of the whole file would be
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
    that start with '#'; in pieces of _CHUNK_LINES lines on every core."""
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
        keyword, rest = _statement(content)
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
        # Already sorted, so drop repeats by hand: np.unique imports numpy.ma (10-50 ms at start-up).
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


# Byte tests by arithmetic on whole chunks: a lookup table or bincount costs numpy ten times more.
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
    if per_line.min() < fewest or per_line.max() > most or not np.all(np.abs(values) <= _FLOAT32_MAX):
        raise _Unusual  # NaN fails the comparison too
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
        raise _Unusual  # some other character
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
            raise _Unusual from None
    if values.size != expected:
        raise _Unusual
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
        raise _Unusual  # '-', '.', '-.'
    if digits.max() > _MAX_FAST_DIGITS:
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

    With `check`, a byte that is not a digit raises _Unusual.
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
        raise _Unusual  # a byte that is not a digit (bytes are ASCII here, so no carries)
    word -= _ZEROS
    word = word * _U64(10) + (word >> _U64(8))
    return ((word & _BYTE_PAIRS) * _MUL_1 + ((word >> _U64(16)) & _BYTE_PAIRS) * _MUL_2) >> _U64(32)


# --- faces ----------------------------------------------------------------------------------------

# Corner formats by which of v/vt/vn they hold: the slashes between consecutive numbers, and which
# field each number is.
_CORNER_GAPS = {(True,): (), (True, True): (1,), (True, False, True): (2,), (True, True, True): (1, 1)}
_CORNER_FIELDS = {(True,): (0,), (True, True): (0, 1), (True, False, True): (0, 2), (True, True, True): (0, 1, 2)}


def _face_table(source: _Lines) -> tuple[list[np.ndarray | None], np.ndarray]:
    """Per corner, the file's index minus one for v, vt, vn (None when absent; see _resolve_indices),
    and face_start."""
    shape = _corner_shape(source.blob(0, 1))
    gaps = _CORNER_GAPS[shape]

    pieces = _chunk_map(lambda piece: _face_chunk(source.blob(*piece), gaps), source.pieces())
    per_line = np.concatenate([counts for _, counts in pieces])
    if per_line.min() < 3:
        raise _Unusual
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
    if shape not in _CORNER_GAPS:
        raise _Unusual
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
        raise _Unusual  # some other character
    starts, ends = _runs(in_number, low)
    width = len(gaps) + 1
    if starts.size % width or slashes != sum(gaps) * (starts.size // width):
        raise _Unusual
    corner_starts, corner_ends = starts.reshape(-1, width), ends.reshape(-1, width)
    per_line = _per_line(corner_starts[:, 0], blob.newlines, low)
    if starts.size == 0:
        return [np.zeros(0, dtype=np.int64)] * width, per_line
    _check_corner_layout(blob.data, corner_starts, corner_ends, gaps)
    signed = _count(minus) > 0  # relative indices; a '-' inside a number fails the digit check
    negative = blob.data[starts] == ord("-") if signed else False
    lengths = ends - starts - negative
    if lengths.min() < 1 or lengths.max() > _MAX_FAST_DIGITS:
        raise _Unusual
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
        raise _Unusual


def _resolve_indices(shifted: np.ndarray, kind: int, total: int, kinds: np.ndarray, corner_lines: _Lazy
                     ) -> np.ndarray:
    """The file's indices minus one to 0-based ones: positive indices are already; -1 is the file's
    index 0 and below that are relative (negative) indices. Out of range is unusual."""
    resolved = shifted
    if resolved.min() < 0:  # index 0 or relative indices
        if np.any(shifted == -1):
            raise _Unusual
        negative = shifted < 0
        defined_before = np.cumsum(kinds == kind)[corner_lines.get()]
        resolved = np.where(negative, defined_before + shifted + 1, shifted)
        if resolved.min() < 0:
            raise _Unusual
    if resolved.max() >= total:
        raise _Unusual
    return resolved


# --------------------------------------------------------------------------------------------------
# The line-by-line reader: the authority on meaning and on error messages
# --------------------------------------------------------------------------------------------------

_FLOAT = re.compile(rb"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?\Z")
_INTEGER = re.compile(rb"-?[0-9]+\Z")
_TABLES = {b"v": ("vertex position (v)", 3, 7), b"vt": ("texture coordinate (vt)", 2, 3),
           b"vn": ("normal (vn)", 3, 3)}
_FIELDS = (b"v", b"vt", b"vn")
_FIELD_NAMES = ("vertex", "texture coordinate (vt)", "normal (vn)")


def _float_or_none(token: bytes) -> float | None:
    return float(token) if _FLOAT.match(token) else None


def _is_non_finite(token: bytes) -> bool:
    """nan, inf, infinity (any case and sign): worth a clearer message than "not a number"."""
    return token.lstrip(b"+-").lower() in (b"nan", b"inf", b"infinity")


class _LineReader:
    """Reads statement by statement, remembering enough to name the line of any later problem."""

    def __init__(self, source: str) -> None:
        self.source = source
        self.tables: dict[bytes, list[list[float]]] = {field: [] for field in _FIELDS}
        self.corners: list[list[int]] = [[], [], []]  # 0-based v, vt, vn per corner; -1: none
        self.face_sizes: list[int] = []
        self.face_lines: list[int] = []
        self.mtllib: str | None = None
        self.colour = _ColourComment()
        self.statements = 0

    def fail(self, line: int, message: str) -> LoadError:
        return LoadError(self.source, message, line=line)

    def read(self, text: bytes) -> _RawObj:
        for number, content in _logical_lines(text):
            keyword, rest = _statement(content)
            if not keyword and content.lstrip().startswith(b"#"):
                self.colour.offer(number, content)
            if keyword:
                self.statements += 1
                self.statement(number, keyword, rest)
        if not self.face_sizes:
            what = "empty file: no faces" if self.statements == 0 else "no faces (no 'f' statements)"
            raise LoadError(self.source, what)
        corners = [np.array(field, dtype=np.int64) for field in self.corners]
        self.check_forward_indices(corners)
        return self.result(corners)

    def statement(self, number: int, keyword: bytes, rest: bytes) -> None:
        if keyword in _TABLES:
            name, fewest, most = _TABLES[keyword]
            values = self.numbers(number, rest.split(), name, fewest, most)
            self.tables[keyword].append(values[:fewest])
        elif keyword == b"f":
            self.face(number, rest.split())
        elif keyword == b"mtllib" and self.mtllib is None:
            self.mtllib = rest.decode("utf-8", errors="replace")

    def numbers(self, number: int, tokens: list[bytes], name: str, fewest: int, most: int) -> list[float]:
        if not fewest <= len(tokens) <= most:
            expected = str(fewest) if fewest == most else f"{fewest} to {most}"
            raise self.fail(number, f"a {name} needs {expected} numbers, found {len(tokens)}")
        values = []
        for token in tokens:
            value = _float_or_none(token)
            if value is None or not np.isfinite(value):
                kind = "finite number" if value is not None or _is_non_finite(token) else "number"
                raise self.fail(number, f"{_quoted(token)} is not a {kind}")
            if abs(value) > _FLOAT32_MAX:
                raise self.fail(number, f"{_quoted(token)} is too large: the GPU's 32-bit numbers end at 3.4e38")
            values.append(value)
        return values

    def face(self, number: int, tokens: list[bytes]) -> None:
        if len(tokens) < 3:
            raise self.fail(number, f"a face needs at least 3 vertices, found {len(tokens)}")
        corners = [self.corner(number, token) for token in tokens]
        if len({tuple(index is None for index in corner) for corner in corners}) > 1:
            raise self.fail(number, f"mixed corner formats in one face: {_quoted(b' '.join(tokens))}")
        for corner, token in zip(corners, tokens):
            self.add_corner(number, corner, token)
        self.face_sizes.append(len(tokens))
        self.face_lines.append(number)

    def corner(self, number: int, token: bytes) -> list[int | None]:
        parts = token.split(b"/")
        if tuple(bool(part) for part in parts) not in _CORNER_GAPS:
            raise self.fail(number, f"bad face corner {_quoted(token)} (expected v, v/vt, v//vn or v/vt/vn)")
        for field, part in enumerate(parts):
            if part and not _INTEGER.match(part):
                raise self.fail(number, f"bad face corner {_quoted(token)}: {_quoted(part)} is not an index")
            if len(part.lstrip(b"-")) > _MAX_FAST_DIGITS:  # no file holds 10**15 of anything
                raise self.fail(number, f"{_FIELD_NAMES[field]} index {_quoted(part)} out of range")
        indices = [int(part) if part else None for part in (parts + [b"", b""])[:3]]
        if 0 in indices:
            raise self.fail(number, f"index 0 in face corner {_quoted(token)}: OBJ indices start at 1")
        return indices

    def add_corner(self, number: int, corner: list[int | None], token: bytes) -> None:
        for field, raw in enumerate(corner):
            if raw is None:
                self.corners[field].append(-1)
            elif raw > 0:
                self.corners[field].append(raw - 1)  # may point forward: checked at the end
            else:
                defined = len(self.tables[_FIELDS[field]])
                if defined + raw < 0:
                    raise self.fail(number, f"relative {_FIELD_NAMES[field]} index {raw} in {_quoted(token)} "
                                            f"reaches before the first one ({defined} defined so far)")
                self.corners[field].append(defined + raw)

    def check_forward_indices(self, corners: list[np.ndarray]) -> None:
        """Positive indices may point forward, so they are checked once the whole file is read."""
        face_of_corner = np.repeat(np.arange(len(self.face_sizes)), self.face_sizes)
        for field, resolved in enumerate(corners):
            total = len(self.tables[_FIELDS[field]])
            bad = np.flatnonzero(resolved >= total)
            if bad.size:
                line = self.face_lines[face_of_corner[bad[0]]]
                raise self.fail(line, f"{_FIELD_NAMES[field]} index {resolved[bad[0]] + 1} out of range: "
                                      f"the file has {total}")

    def result(self, corners: list[np.ndarray]) -> _RawObj:
        def table(field: bytes, width: int) -> np.ndarray:
            return np.array(self.tables[field], dtype=np.float64).reshape(-1, width)

        def optional(field: int) -> np.ndarray | None:
            return corners[field] if np.any(corners[field] >= 0) else None

        face_start = np.concatenate(([0], np.cumsum(self.face_sizes))).astype(np.int64)
        return _RawObj(table(b"v", 3), table(b"vt", 2), table(b"vn", 3), corners[0], optional(1), optional(2),
                       face_start, self.mtllib, self.colour.colour, self.colour.notes)


def _read_by_lines(text: bytes, source: str) -> _RawObj:
    return _LineReader(source).read(text)


def _logical_lines(text: bytes) -> Iterator[tuple[int, bytes]]:
    """(first line number, content) with backslash-continued lines joined."""
    pending, first = b"", 0
    for number, line in enumerate(text.split(b"\n"), start=1):
        stripped = line.rstrip()
        if stripped.endswith(b"\\"):
            first = first if pending else number
            pending += stripped[:-1] + b" "
            continue
        if pending:
            yield first, pending + line
            pending = b""
        else:
            yield number, line
    if pending:
        yield first, pending


def _statement(content: bytes) -> tuple[bytes, bytes]:
    """(keyword, rest of the line without comment, stripped); keyword b'' for blank and comment lines.

    Only ASCII whitespace separates (bytes.split), as in the fast reader.
    """
    parts = content.split(b"#", 1)[0].split(None, 1)
    if not parts:
        return b"", b""
    return parts[0], parts[1].strip() if len(parts) > 1 else b""


def _quoted(token: bytes) -> str:
    text = token.decode("utf-8", errors="replace")
    return repr(text if len(text) <= 40 else text[:37] + "...")


# --------------------------------------------------------------------------------------------------
# Comments and materials around the geometry
# --------------------------------------------------------------------------------------------------

_COLOUR_COMMENT = re.compile(rb"\s*#\s*colou?r\s+(\S+)\s+(\S+)\s+(\S+)\s*\Z")


class _ColourComment:
    """The seed reader's ``# colour r g b`` (0..255) as a 0..1 colour: the first well-formed one counts."""

    def __init__(self) -> None:
        self.colour: tuple[float, float, float] | None = None
        self.notes: list[str] = []

    def offer(self, line_number: int, comment: bytes) -> None:
        if self.colour is not None or b"colo" not in comment:
            return
        match = _COLOUR_COMMENT.match(comment)
        if match is None:
            return
        values = _finite_floats(match.groups())
        if values is None:
            self.notes.append(f"ignored a malformed '# colour' comment on line {line_number}")
        else:
            red, green, blue = (min(max(value / 255.0, 0.0), 1.0) for value in values)
            self.colour = (red, green, blue)


def _finite_floats(tokens: Sequence[bytes | str]) -> list[float] | None:
    try:
        values = [float(token) for token in tokens]
    except ValueError:
        return None
    return values if all(np.isfinite(values)) else None


def _first_material(base_dir: Path, name: str, notes: list[str]) -> dict[str, object] | None:
    """Ka/Kd/Ks/Ns of the first material in the MTL file next to the OBJ; problems become notes."""
    candidates = [name] + name.split()  # 'mtllib a b.mtl' is one file with a space, or two files
    mtl = next((base_dir / candidate for candidate in candidates if (base_dir / candidate).is_file()), None)
    if mtl is None:
        notes.append(f"material library '{name}' not found next to the model; using the scene's material")
        return None
    try:
        text = mtl.read_bytes()[:16 << 20].decode("utf-8", errors="replace")
    except (OSError, MemoryError) as error:
        notes.append(f"material library '{name}' could not be read ({error}); using the scene's material")
        return None
    material = _parse_first_material(text, name, notes)
    return material or None


def _parse_first_material(text: str, name: str, notes: list[str]) -> dict[str, object]:
    material: dict[str, object] = {}
    inside = False
    for line in text.splitlines():
        tokens = line.split("#", 1)[0].split()
        if not tokens:
            continue
        key = tokens[0].lower()
        if key == "newmtl":
            if inside:
                break
            inside = True
        elif inside and key in ("ka", "kd", "ks", "ns"):
            _material_value(material, key, tokens[1:], name, notes)
    if not inside:
        notes.append(f"material library '{name}' defines no material; using the scene's material")
    return material


def _material_value(material: dict[str, object], key: str, tokens: list[str], name: str, notes: list[str]) -> None:
    values = _finite_floats(tokens)
    if key == "ns" and values is not None and len(values) == 1:
        material["ns"] = values[0]
    elif key != "ns" and values is not None and len(values) in (1, 3):
        material[key] = tuple(values * 3 if len(values) == 1 else values)  # one number: a grey
    else:
        notes.append(f"material library '{name}': ignored a malformed {key.capitalize()} line")


# --------------------------------------------------------------------------------------------------
# Derived data, shared by the loader and build_mesh
# --------------------------------------------------------------------------------------------------


def _faces_to_csr(faces: Sequence[Sequence[int]] | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    if isinstance(faces, np.ndarray) and faces.ndim == 2:
        sizes = np.full(faces.shape[0], faces.shape[1], dtype=np.int64)
        corners = faces.astype(np.int64).ravel()
    else:
        lists = [list(face) for face in faces]
        sizes = np.array([len(face) for face in lists], dtype=np.int64)
        corners = np.array([index for face in lists for index in face], dtype=np.int64)
    if sizes.size == 0 or sizes.min() < 3:
        raise ValueError("a mesh needs faces of at least 3 vertices")
    return corners, np.concatenate(([0], np.cumsum(sizes))).astype(np.int64)


_CornerSource = tuple[np.ndarray, np.ndarray]  # (table, per-corner row index; -1: none)


def _derive_mesh(name: str, positions: np.ndarray, corner_vertex: np.ndarray, face_start: np.ndarray,
                 uv: _CornerSource | None, normals: _CornerSource | None,
                 base_colour: tuple[float, float, float] | None, file_material: dict[str, object] | None,
                 notes: tuple[str, ...]) -> Mesh:
    """The Mesh, with every normal and texture coordinate the file lacks derived. Never NaN."""
    sizes = np.diff(face_start)
    bounds = column_bounds(positions)
    face_normals, degenerate = _face_normals(positions, corner_vertex, face_start, sizes, bounds)
    corner_normal, missing = _usable_normals(normals, corner_vertex.size)
    if missing.any():
        missing = _fill_vertex_normals(corner_normal, missing, positions.shape[0], corner_vertex, sizes,
                                       face_normals)
    if degenerate.any():
        _fill_degenerate(face_normals, degenerate, corner_normal, face_start, sizes)
        notes += (f"{int(degenerate.sum())} zero-area faces (given a fallback normal)",)
    per_position = uv is None and normals is None and not missing.any()
    if missing.any():
        corners = np.flatnonzero(missing)  # no usable face touches their position: take their face's
        corner_normal[corners] = face_normals[np.searchsorted(face_start, corners, side="right") - 1]
    return Mesh(
        name=name,
        positions=np.ascontiguousarray(positions, dtype=np.float64),
        corner_vertex=np.ascontiguousarray(corner_vertex, dtype=np.int64),
        corner_uv=_corner_uv(uv, positions, corner_vertex, bounds),
        corner_normal=corner_normal,
        face_start=np.ascontiguousarray(face_start, dtype=np.int64),
        face_normals=face_normals.astype(np.float32),
        base_colour=base_colour,
        file_material=file_material,
        warnings=notes,
        attributes_per_position=per_position,
    )


def _corner_uv(uv: _CornerSource | None, positions: np.ndarray, corner_vertex: np.ndarray,
               bounds: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """The file's vt per corner, and the bounding-box projection where a corner has none."""
    if uv is None:
        return _bounding_box_uv(positions, corner_vertex, bounds)
    table, index = uv
    # np.take on rows: three times faster than fancy indexing for gathers of small rows (build_mesh)
    corner_uv = np.take(np.clip(table, -_FLOAT32_MAX, _FLOAT32_MAX).astype(np.float32), index, axis=0)
    without = np.flatnonzero(index < 0)
    if without.size:
        corner_uv[without] = _bounding_box_uv(positions, corner_vertex[without], bounds)
    return corner_uv


def _face_normals(positions: np.ndarray, corner_vertex: np.ndarray, face_start: np.ndarray,
                  sizes: np.ndarray, bounds: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """Unit polygon normals by Newell's method, and which faces have (almost) no area (left zero).

    Newell's sum of p_i x p_(i+1) is unchanged by moving the origin to the first vertex, where it
    becomes the sum of the fan triangles' cross products: cheaper, and exact far from the origin.
    The work is done on one contiguous array per axis: gathers from and arithmetic on (N,) arrays
    run at memory speed, where the columns of an (N, 3) array are strided (twice as slow in all).
    """
    if sizes.min() == sizes.max():  # polygons of one size (triangles, quads): fans column by column
        corners = corner_vertex.reshape(-1, int(sizes[0])).T
        sums = _cross_from_first(positions, corners[[0, 1, 2]])
        for second in range(2, int(sizes[0]) - 1):  # in fan order, as reduceat below adds them
            sums += _cross_from_first(positions, corners[[0, second, second + 1]])
    else:
        fans = corner_vertex[fan_triangles(face_start)].T
        firsts = np.concatenate(([0], np.cumsum(sizes - 2)[:-1]))
        sums = np.add.reduceat(_cross_from_first(positions, fans), firsts, axis=1)
    with np.errstate(all="ignore"):
        x, y, z = sums
        length = np.sqrt(x * x + y * y + z * z)
        degenerate = ~np.isfinite(length) | (length <= _DEGENERATE_AREA * _size_squared(bounds))
        sums /= np.where(degenerate, 1.0, length)
    sums[:, degenerate] = 0.0
    return sums.T, degenerate


_CROSS_CHUNK = 1 << 14  # triangles per piece: a dozen temporaries of this many numbers stay in cache


def _cross_from_first(positions: np.ndarray, fans: np.ndarray) -> np.ndarray:
    """(3, T): (p1 - p0) x (p2 - p0) for the triangles `fans`, (3, T) position indices.

    In pieces, so that the gathered coordinates and products are cache-sized temporaries instead of a
    dozen arrays as long as the mesh in fresh memory (a million triangles: 150 MB)."""
    x, y, z = np.ascontiguousarray(positions.T)
    out = np.empty((3, fans.shape[1]), positions.dtype)
    with np.errstate(all="ignore"):
        for low in range(0, fans.shape[1], _CROSS_CHUNK):
            first, second, third = fans[:, low:low + _CROSS_CHUNK]
            x0, y0, z0 = x[first], y[first], z[first]
            ax, ay, az = x[second] - x0, y[second] - y0, z[second] - z0
            bx, by, bz = x[third] - x0, y[third] - y0, z[third] - z0
            high = low + first.shape[0]
            np.subtract(ay * bz, az * by, out=out[0, low:high])
            np.subtract(az * bx, ax * bz, out=out[1, low:high])
            np.subtract(ax * by, ay * bx, out=out[2, low:high])
    return out


def _size_squared(bounds: tuple[np.ndarray, np.ndarray]) -> float:
    low, high = bounds
    with np.errstate(all="ignore"):
        size = float(np.sum((high - low) ** 2))
    return size if np.isfinite(size) else 0.0


def _usable_normals(normals: _CornerSource | None, corners: int) -> tuple[np.ndarray, np.ndarray]:
    """(C, 3) float32 unit normals from the file's vn, and which corners lack a usable one.

    Normalized once per vn row, not per corner; a zero-length vn is not usable.
    """
    if normals is None:
        return np.zeros((corners, 3), dtype=np.float32), np.ones(corners, dtype=bool)
    table, index = normals
    unit, ok = _normalized(table)
    corner_normal = np.take(unit.astype(np.float32), index, axis=0)
    if ok.all() and index.min() >= 0:  # the usual case: nothing to derive
        return corner_normal, np.zeros(corners, dtype=bool)
    missing = (index < 0) | ~ok[index]
    corner_normal[missing] = 0.0
    return corner_normal, missing


def _fill_vertex_normals(corner_normal: np.ndarray, missing: np.ndarray, vertex_count: int,
                         corner_vertex: np.ndarray, sizes: np.ndarray, face_normals: np.ndarray) -> np.ndarray:
    """Vertex normals for the missing corners: the normalized sum of the unit normals of the faces
    around the position (zero-area faces, still zero here, do not count). Returns the corners
    still missing one: their position touches no face with an area."""
    sums = _normal_sums(face_normals, corner_vertex, sizes, vertex_count)
    vertex_normals, vertex_ok = _normalized(sums)
    vertex_normals = vertex_normals.astype(corner_normal.dtype)  # a fancy assignment that also
    # converts is several times slower than one gather of the right type
    if missing.all():  # no `vn` in the file, the usual case: one gather straight into place
        np.take(vertex_normals, corner_vertex, axis=0, out=corner_normal)
        return ~vertex_ok[corner_vertex]
    corners = np.flatnonzero(missing)
    corner_normal[corners] = vertex_normals[corner_vertex[corners]]
    still = np.zeros_like(missing)
    still[corners] = ~vertex_ok[corner_vertex[corners]]
    return still


def _normal_sums(face_normals: np.ndarray, corner_vertex: np.ndarray, sizes: np.ndarray, vertex_count: int
                 ) -> np.ndarray:
    """(V, 3): per position, the sum of the normals of the faces that use it.

    One axis at a time on contiguous arrays; for polygons of one size, one bincount per corner column
    instead of repeating every face normal per corner (36 instead of 59 ms for a million triangles).
    """
    axes = [np.ascontiguousarray(face_normals[:, axis]) for axis in range(3)]
    if sizes.min() == sizes.max():
        columns = [np.ascontiguousarray(column) for column in corner_vertex.reshape(-1, int(sizes[0])).T]
        return np.stack([sum(np.bincount(column, weights=axis, minlength=vertex_count) for column in columns)
                         for axis in axes], axis=1)
    return np.stack([np.bincount(corner_vertex, weights=np.repeat(axis, sizes), minlength=vertex_count)
                     for axis in axes], axis=1)


def _fill_degenerate(face_normals: np.ndarray, degenerate: np.ndarray, corner_normal: np.ndarray,
                     face_start: np.ndarray, sizes: np.ndarray) -> None:
    """A zero-area face takes the average of its corners' normals, or +z when that is zero too."""
    faces = np.flatnonzero(degenerate)
    corners = np.repeat(face_start[faces], sizes[faces]) + _ranks(sizes[faces])
    sums = np.add.reduceat(corner_normal[corners], np.concatenate(([0], np.cumsum(sizes[faces])[:-1])), axis=0)
    averaged, ok = _normalized(sums)
    averaged[~ok] = _FALLBACK_NORMAL
    face_normals[faces] = averaged


def _ranks(sizes: np.ndarray) -> np.ndarray:
    """0, 1, .. size-1 for each size, concatenated."""
    return np.arange(int(sizes.sum())) - np.repeat(np.cumsum(sizes) - sizes, sizes)


def _normalized(vectors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors and which rows could be normalized; the others are left zero."""
    with np.errstate(all="ignore"):
        length = np.sqrt(np.einsum("ij,ij->i", vectors, vectors))
        ok = np.isfinite(length) & (length > 1e-300)
        unit = vectors / np.where(ok, length, 1.0)[:, None]
    unit[~ok] = 0.0
    return unit, ok


def _bounding_box_uv(positions: np.ndarray, corner_vertex: np.ndarray,
                     bounds: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """Planar projection onto the bounding box's two largest extents, each mapped to 0..1.

    The two axes keep x-y-z order, so a model lying in the xy plane gets u along x and v along y.
    """
    low, high = bounds
    with np.errstate(all="ignore"):
        extent = high - low
        extent = np.where(np.isfinite(extent), extent, 0.0)
        axes = np.sort(np.argsort(-extent, kind="stable")[:2])
        # Per position, then gathered: a position has one box coordinate, and corners are ~6x more.
        uv = (positions[:, axes] - low[axes]) / np.where(extent[axes] > 0, extent[axes], 1.0)
    uv[:, extent[axes] <= 0] = 0.0
    uv = np.where(np.isfinite(uv), uv, 0.0).astype(np.float32)
    return np.take(uv, corner_vertex, axis=0)
