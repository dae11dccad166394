"""The line-by-line OBJ reader: the authority on meaning and on error messages.

It reads whole files: a process's first small files, and files that continue lines with a
backslash. Their plain lines it keeps and reads in batches (_PlainLines), a run of them in one match
where no line continues, the others one at a time.
Otherwise the fast reader hands it just the lines of a piece it does not handle, one at a time
(LineReader.read_line), and it words the errors that need the whole file (no faces, indices past
the end) with the functions below. Either way a LoadError names the first offending line.
"""

from __future__ import annotations

import io
import math
import re
import sys
from array import array
from collections.abc import Callable, Iterator, Sequence
from typing import NamedTuple

import numpy as np

from marraztu.errors import SHOWN_WHOLE, LoadError, shortened
from marraztu.loaders.files import decoded
from marraztu.loaders.obj.raw import (
    COLOURED_V_NUMBERS,
    CORNER_GAPS,
    MAX_DIGITS,
    TABLE_WIDTHS,
    UNDRAWN_ELEMENTS,
    V_FORMS,
    ColourComment,
    MaterialRuns,
    Polypaint,
    RawObj,
    UnformedVLines,
    comment_at,
    library_names,
    material_name,
    put_colours,
    reading_notes,
    statement,
    with_library,
)
from marraztu.loaders.obj.text import has_continuations
from marraztu.loaders.patterns import compiled
from marraztu.loaders.words import BLANKS, DECIMAL_BYTES
from marraztu.model.geometry import FLOAT32_MAX
from marraztu.model.mesh import INDEX, INDEX_LIMIT, polygons_of_corners
from marraztu.model.threads import largest

_INTEGER = re.compile(rb"-?[0-9]+\Z")
_TOKEN = re.compile(rb"\S+")
class _Table(NamedTuple):
    """What a v, vt or vn line fills: its table (RawObj's positions, texcoords, normals), its name in
    messages, and how many numbers it holds."""

    field: int
    name: str
    fewest: int
    most: int


_TABLES = {b"v": _Table(0, "vertex position (v)", 3, 7), b"vt": _Table(1, "texture coordinate (vt)", 1, 3),
           b"vn": _Table(2, "normal (vn)", 3, 3)}
_FIELDS = (b"v", b"vt", b"vn")
_FIELD_NAMES = ("vertex", "texture coordinate (vt)", "normal (vn)")
# Plain lines, read in one match each: most lines. Their numbers and indices need no check: a plain
# number is finite and within float32 by its syntax alone (at most 29 digits before the point; a
# negative exponent, or one digit after any zeros), and a plain index is below INDEX_LIMIT (at most
# 9 digits).
# Anything else is read number by number, or corner by corner, and its errors are worded there.
_PLAIN_NUMBER = rb"[+-]?+(?:[0-9]{1,29}+(?:\.[0-9]*+)?+|\.[0-9]++)(?:[eE](?:-[0-9]++|\+?+0*[0-9]))?+"
_PLAIN_INDEX = rb"[1-9][0-9]{0,8}"
_SPACE = b"[%s]" % re.escape(BLANKS.replace(b"\n", b""))  # a blank within a line


def _plain_numbers(fewest: int, most: int | None = None) -> bytes:
    """The syntax of `fewest` to `most` (or just `fewest`) plain numbers parted by blanks within a line."""
    return rb"%s(?:%s+%s){%d,%d}" % (_PLAIN_NUMBER, _SPACE, _PLAIN_NUMBER, fewest - 1,
                                     (fewest if most is None else most) - 1)


def _plain_run(keyword: bytes, items: bytes) -> re.Pattern[bytes]:
    """Whole lines, each with its newline, of `keyword` and `items` parted and surrounded by blanks
    within the line and no comment: a run of them read in one match."""
    return compiled(rb"(?:%s*+%s%s++%s%s*+\n)*+" % (_SPACE, keyword, _SPACE, items, _SPACE))


# A v, vt or vn line of plain numbers; a whole file's reading batches those of just the table's width,
# and reads runs of such lines in one match.
_PLAIN_ROWS = {keyword: compiled(_plain_numbers(table.fewest, table.most)) for keyword, table in _TABLES.items()}
_BATCHED_ROWS = {keyword: compiled(_plain_numbers(width)) for keyword, width in zip(_FIELDS, TABLE_WIDTHS)}
PLAIN_ROW_RUNS = [_plain_run(keyword, _plain_numbers(width)) for keyword, width in zip(_FIELDS, TABLE_WIDTHS)]
_ROW_RUN_FIELDS = {b"vt": 1, b"vn": 2}  # by a line's first two bytes; v's, any other after a v


class _FaceForm(NamedTuple):
    """One of the four corner formats: a short face of plain indices in it, the fields its corners
    give, and runs of plain triangles and quads in it (corners a face, the run's pattern)."""

    face: re.Pattern[bytes]
    fields: tuple[int, ...]
    runs: tuple[tuple[int, re.Pattern[bytes]], ...]


def _face_form(corner: bytes, fields: tuple[int, ...]) -> _FaceForm:
    return _FaceForm(compiled(rb"%s(?:%s+%s){2,}" % (corner, _SPACE, corner)), fields,
                     tuple((corners, _plain_run(b"f", rb"%s(?:%s++%s){%d}" % (corner, _SPACE, corner, corners - 1)))
                           for corners in (3, 4)))


LONGEST_BATCHED_LINE = 256
_FACE_FORMS = [_face_form(corner, fields) for corner, fields in (
    (_PLAIN_INDEX, (0,)), (rb"%s/%s" % (_PLAIN_INDEX, _PLAIN_INDEX), (0, 1)),
    (rb"%s//%s" % (_PLAIN_INDEX, _PLAIN_INDEX), (0, 2)),
    (rb"%s/%s/%s" % (_PLAIN_INDEX, _PLAIN_INDEX, _PLAIN_INDEX), (0, 1, 2)))]
_BATCHED_KEYWORDS = frozenset((*_FIELDS, b"f"))


def _beyond_index(part: bytes) -> bool:
    """An index no file the viewer reads can hold (model.mesh.INDEX); its digits are counted first, so
    that a million of them are never made into a number."""
    digits = part.lstrip(b"-")
    return len(digits) > MAX_DIGITS or (bool(digits) and int(digits) > INDEX_LIMIT)


def _float_or_none(token: bytes) -> float | None:
    return float(token) if DECIMAL_BYTES.fullmatch(token) else None


_WINDOWS_NON_FINITE = re.compile(rb"[+-]?[0-9]\.#(?:IND|QNAN|SNAN|INF)[0-9]*", re.IGNORECASE)


def _is_non_finite(token: bytes) -> bool:
    """nan, inf, infinity (any case and sign), and old Windows programs' -1.#IND, 1.#QNAN, 1.#INF00:
    worth a clearer message than "not a number"."""
    return token.lstrip(b"+-").lower() in (b"nan", b"inf", b"infinity") or bool(_WINDOWS_NON_FINITE.fullmatch(token))


class ReadsSlowly(Exception):
    """A whole file held more lines to read one at a time than the reader was given leave to read."""


class LineReader:
    """Reads statement by statement, remembering enough to name the line of any later problem.

    `defined` counts the v, vt and vn lines before the line being read: relative indices count back
    from there. Reading a whole file keeps it up to date; the fast reader sets it before each line."""

    def __init__(self, source: str, most_single_lines: int = sys.maxsize) -> None:
        self.source = source
        self.most_single_lines = most_single_lines  # a whole file's, read one at a time (see ReadsSlowly)
        self.tables = [array("d") for _ in _FIELDS]  # flat rows, TABLE_WIDTHS numbers each
        self.defined = [0, 0, 0]
        # The file's v, vt and vn index per corner, relative ones made absolute: 1-based, 0 for none,
        # so that most faces' digits go in as read (corner_columns makes them 0-based, -1 for none).
        self.corners = [array("q") for _ in _FIELDS]
        self.face_sizes = array("q")
        self.face_lines = array("q")
        self.mtllib: tuple[bytes, ...] = ()
        self.coloured_rows = array("q")  # the position rows whose v line gives a colour after x y z
        self.colour_values = array("d")  # and its three numbers each
        self.unformed = UnformedVLines()
        self.material_runs = MaterialRuns()
        self.colour = ColourComment()
        self.polypaint = Polypaint()
        self.statements = 0
        self.elements = False  # an l or p statement was read

    def fail(self, line: int, message: str) -> LoadError:
        return LoadError(self.source, message, line=line)

    def read(self, text: bytes) -> RawObj:
        batch = _PlainLines(self)
        if text.endswith(b"\n") and not has_continuations(text):
            self.read_runs(text, batch)
        else:
            for number, content in _logical_lines(text):
                self.read_kept(number, content, batch)
        batch.flush()
        if not self.face_sizes:
            raise no_faces_error(self.source, self.statements > 0, self.elements)
        corners = self.corner_columns()
        face_lines = np.frombuffer(self.face_lines, dtype=np.int64)
        face_start = np.concatenate(([0], np.cumsum(np.frombuffer(self.face_sizes, dtype=np.int64)))).astype(INDEX)
        columns = checked_columns(self.source, corners, self.defined,
                                  lambda corner: int(face_lines[polygons_of_corners(face_start, corner)]))
        return self.result(columns, face_start)

    def read_runs(self, text: bytes, batch: _PlainLines) -> None:
        """Runs of plain lines in one match each (most of a file), the other lines one at a time. After
        a line that starts no run, runs are tried again 2, 4, 8... lines on, _RUN_TRIES_APART at most:
        a file of other lines pays for a try that far apart."""
        lines = io.BytesIO(text)  # its line iterator: the lines between runs one at a time
        at, number, next_try, apart, single = 0, 0, 1, 1, 0
        for content in lines:
            number += 1
            if number >= next_try:
                end, taken = batch.take_run(text, at, number)
                if taken:
                    lines.seek(end)
                    at, number, next_try, apart = end, number + taken - 1, number + taken, 1
                    continue
                apart = min(2 * apart, _RUN_TRIES_APART)
                next_try = number + apart
            at += len(content)
            if not self.read_kept(number, content, batch):
                single += 1
                if single > self.most_single_lines:
                    raise ReadsSlowly

    def read_kept(self, number: int, content: bytes, batch: _PlainLines) -> bool:
        """One line: kept in the batch if plain, else read now; whether it was kept."""
        keyword, rest = statement(content)
        if keyword in _BATCHED_KEYWORDS:
            if batch.keep(number, keyword, rest):
                return True
            batch.flush()  # first: the tables' rows and the corners stay in file order
        self.read_statement(number, content, keyword, rest)
        return False

    def corner_columns(self) -> list[np.ndarray]:
        """The corners' v, vt and vn columns: 0-based, -1 for none."""
        return [(np.frombuffer(field, dtype=np.int64) - 1).astype(INDEX) for field in self.corners]

    def read_line(self, number: int, content: bytes) -> None:
        """One physical (or continued) line: the statement it holds, or the comment it is."""
        self.read_statement(number, content, *statement(content))

    def read_statement(self, number: int, content: bytes, keyword: bytes, rest: bytes) -> None:
        if keyword:
            self.statements += 1
            self.statement(number, keyword, rest)
        elif content.lstrip().startswith(b"#"):
            self.colour.offer(number, content)
            self.polypaint.offer(number, content)

    def statement(self, number: int, keyword: bytes, rest: bytes) -> None:
        if keyword in _TABLES:
            field = _TABLES[keyword].field
            values = self.numbers(number, keyword, rest)
            row = values[:TABLE_WIDTHS[field]]
            self.tables[field].extend(row + [0.0] * (TABLE_WIDTHS[field] - len(row)))  # `vt u`: v is 0
            if field == 0 and len(values) >= COLOURED_V_NUMBERS:
                self.coloured_rows.append(self.defined[0])
                self.colour_values.extend(values[3:COLOURED_V_NUMBERS])
            if field == 0 and len(values) not in V_FORMS:
                self.unformed.add(number)
            self.defined[field] += 1
        elif keyword == b"f":
            self.face(number, rest)
        elif keyword == b"mtllib":
            self.mtllib = with_library(self.mtllib, rest)
        elif keyword == b"usemtl":
            self.material_runs.add(len(self.face_sizes), material_name(rest))
        elif keyword in (b"l", b"p"):
            self.elements = True

    def numbers(self, number: int, keyword: bytes, rest: bytes) -> list[float]:
        if _PLAIN_ROWS[keyword].fullmatch(rest):
            return [float(token) for token in rest.split()]
        _, name, fewest, most = _TABLES[keyword]
        tokens = rest.split(None, most + 1)  # bounded: a line of millions of numbers is not split into them
        if not fewest <= len(tokens) <= most:
            expected = str(fewest) if fewest == most else f"{fewest} to {most}"
            found = f"more than {most + 1}" if len(tokens) > most + 1 else str(len(tokens))
            raise self.fail(number, f"a {name} needs {expected} numbers, found {found}")
        values = []
        for token in tokens:
            value = _float_or_none(token)
            if value is None or not math.isfinite(value):
                kind = "finite number" if value is not None or _is_non_finite(token) else "number"
                raise self.fail(number, f"{_quoted(token)} is not a {kind}")
            if abs(value) > FLOAT32_MAX:
                raise self.fail(number, f"{_quoted(token)} is too large: the GPU's 32-bit numbers end at 3.4e38")
            values.append(value)
        return values

    def face(self, number: int, rest: bytes) -> None:
        """Corner by corner, never a list of them: one face may hold millions. (A whole file's plain faces
        are read in batches, _PlainLines; the compiled reader reads them itself.)"""
        count = len(rest.split(None, 3))
        if count < 3:
            raise self.fail(number, f"a face needs at least 3 vertices, found {count}")
        first = len(self.corners[0])
        shapes = set()
        for match in _TOKEN.finditer(rest):
            corner = self.corner(number, match.group())
            shapes.add(tuple(index == 0 for index in corner))
            for field, index in enumerate(corner):
                self.corners[field].append(index)  # relative ones are resolved below
        if len(shapes) > 1:
            raise self.fail(number, f"mixed corner formats in one face: {_quoted_start(_first_tokens(rest))}")
        self.resolve(number, rest, first)
        self.end_face(number, len(self.corners[0]) - first)

    def end_face(self, number: int, size: int) -> None:
        self.face_sizes.append(size)
        self.face_lines.append(number)

    def resolve(self, number: int, rest: bytes, first: int) -> None:
        """The face's relative corners from `first` on made absolute, corner by corner; positive ones
        may point forward. A relative one reaching before the first is an error."""
        for at in range(first, len(self.corners[0])):
            for field, column in enumerate(self.corners):
                raw = column[at]
                if raw < 0:
                    if self.defined[field] + raw < 0:
                        raise self.relative_error(number, field, raw, rest, at - first)
                    column[at] = self.defined[field] + raw + 1

    def relative_error(self, number: int, field: int, raw: int, rest: bytes, corner: int) -> LoadError:
        token = next(match.group() for position, match in enumerate(_TOKEN.finditer(rest)) if position == corner)
        return self.fail(number, f"relative {_FIELD_NAMES[field]} index {raw} in {_quoted(token)} "
                                 f"reaches before the first one ({self.defined[field]} defined so far)")

    def corner(self, number: int, token: bytes) -> list[int]:
        """The file's v, vt and vn indices of one corner, 0 where it has none."""
        parts = token.split(b"/")
        if tuple(bool(part) for part in parts) not in CORNER_GAPS:
            expected = "v, v/vt, v//vn, v/vt/vn, v// or v/vt/"
            raise self.fail(number, f"bad face corner {_quoted(token)} (expected {expected})")
        for field, part in enumerate(parts):
            if part and not _INTEGER.match(part):
                raise self.fail(number, f"bad face corner {_quoted(token)}: {_quoted(part)} is not an index")
            if _beyond_index(part):
                raise self.fail(number, f"{_FIELD_NAMES[field]} index {_quoted(part)} out of range: more than a "
                                        f"model holds ({INDEX_LIMIT})")
        indices = [int(part) if part else None for part in (parts + [b"", b""])[:3]]
        if 0 in indices:
            raise self.fail(number, f"index 0 in face corner {_quoted(token)}: OBJ indices start at 1")
        return [index or 0 for index in indices]

    def result(self, columns: list[np.ndarray | None], face_start: np.ndarray) -> RawObj:
        tables = [np.frombuffer(table, dtype=np.float64).reshape(-1, width)
                  for table, width in zip(self.tables, TABLE_WIDTHS)]
        colours, paint_notes = self.polypaint.with_colours(
            put_colours(np.full((len(tables[0]), 3), np.nan), self.coloured_rows, self.colour_values)
            if self.coloured_rows else None, len(tables[0]))
        return RawObj(tables[0], tables[1], tables[2], *columns,
                      face_start, library_names(self.mtllib), self.colour.colour,
                      reading_notes(self.unformed, self.colour, paint_notes, self.elements),
                      self.material_runs, colours)


# A batch is read once it holds this many lines or bytes, whichever comes first: a line's bytes object
# costs more than its numbers, and a batch's joined copy as much as its lines. A run is read a
# batch's bytes at a time.
_BATCHED_LINES = 1 << 12
_BATCHED_BYTES = 1 << 20
_RUN_TRIES_APART = 64


class _PlainLines:
    """A whole file's plain v, vt and vn rows of just their table's width, and its short plain faces,
    kept as bytes (a run of such lines as one) until the next other line of those kinds, the file's
    end or a full batch: then their numbers are made in one call, not a float() or int() each."""

    def __init__(self, reader: LineReader) -> None:
        self.reader = reader
        self.rows: list[list[bytes]] = [[] for _ in _FIELDS]
        self.faces: list[bytes] = []
        self.face_form = _FACE_FORMS[-1]  # the kept faces' form: a file keeps to one, so it is tried first
        self.lines = self.bytes = 0

    def take_run(self, text: bytes, at: int, number: int) -> tuple[int, int]:
        """Keeps the run of plain rows of a table's width, or of plain triangles or quads in the kept
        faces' form, that starts at `at` (line `number`), a batch's bytes of it at most: where it ends
        and its lines; (at, 0) where none starts there."""
        reader, stop, first = self.reader, at + _BATCHED_BYTES, text[at:at + 2]
        if first[:1] == b"v":
            field = _ROW_RUN_FIELDS.get(first, 0)
            end = PLAIN_ROW_RUNS[field].match(text, at, stop).end()
            lines = text.count(b"\n", at, end)
            if not lines:
                return at, 0
            self.rows[field].append(text[at:end])
            reader.defined[field] += lines
        elif first[:1] == b"f":
            for corners, run in self.face_form.runs:
                end = run.match(text, at, stop).end()
                if end > at:
                    break
            else:
                return at, 0
            lines = text.count(b"\n", at, end)
            self.faces.append(text[at:end])
            reader.face_sizes.extend(array("q", [corners]) * lines)
            reader.face_lines.extend(range(number, number + lines))
        else:
            return at, 0
        self.counted(lines, end - at)
        return end, lines

    def keep(self, number: int, keyword: bytes, rest: bytes) -> bool:
        """Whether the line is plain, and kept; if so, the reader counts it as LineReader.statement would."""
        reader = self.reader
        if keyword == b"f":
            if len(rest) > LONGEST_BATCHED_LINE or not self.keep_face(rest):
                return False
            reader.end_face(number, len(rest.split()))
        else:
            if not _BATCHED_ROWS[keyword].fullmatch(rest):
                return False
            field = _TABLES[keyword].field
            self.rows[field].append(rest)
            reader.defined[field] += 1
        self.counted(1, len(rest))
        return True

    def keep_face(self, rest: bytes) -> bool:
        if not self.face_form.face.fullmatch(rest):
            form = next((form for form in _FACE_FORMS if form.face.fullmatch(rest)), None)
            if form is None:
                return False
            self.flush_faces()  # the kept faces, in their own form
            self.face_form = form
        self.faces.append(rest)
        return True

    def counted(self, lines: int, size: int) -> None:
        self.reader.statements += lines
        self.lines += lines
        self.bytes += size
        if self.lines >= _BATCHED_LINES or self.bytes >= _BATCHED_BYTES:
            self.flush()

    def flush(self) -> None:
        for table, rows in zip(self.reader.tables, self.rows):
            if rows:
                table.frombytes(read_plain_numbers(rows, np.float64).tobytes())
                rows.clear()
        self.flush_faces()
        self.lines = self.bytes = 0

    def flush_faces(self) -> None:
        if not self.faces:
            return
        fields = self.face_form.fields
        corners = read_plain_numbers(self.faces, np.int64).reshape(-1, len(fields))
        for field, column in enumerate(self.reader.corners):
            column.frombytes(corners[:, fields.index(field)].tobytes() if field in fields
                             else bytes(corners.itemsize * len(corners)))
        self.faces.clear()


# What parts the numbers of plain lines and runs: blanks, newlines, a face's slashes and the keywords'
# letters, none of which a plain number holds.
_NUMBERS_ONLY = bytes.maketrans(b"/vtnf", b"     ")


def read_plain_numbers(lines: Sequence[bytes], dtype: type) -> np.ndarray:
    """The numbers of plain lines or runs of them. numpy reads each as float() and int() do: its
    decimal numbers go through the same PyOS_string_to_double, and indices have 9 digits."""
    return np.fromstring(b" ".join(lines).translate(_NUMBERS_ONLY), dtype=dtype, sep=" ")


def read_by_lines(text: bytes, source: str, most_single_lines: int = sys.maxsize) -> RawObj:
    """The file's tables; ReadsSlowly past `most_single_lines` lines read one at a time, unless lines continue."""
    return LineReader(source, most_single_lines).read(text)


def no_faces_error(source: str, has_statements: bool, elements: bool) -> LoadError:
    """No face read: an empty file, or one of other statements, which for a wireframe or a point cloud
    (l and p, `elements`) say what it holds that is not drawn."""
    if not has_statements:
        return LoadError(source, "empty file: no faces")
    return LoadError(source, "no faces (no 'f' statements)" + (f", and {UNDRAWN_ELEMENTS}" if elements else ""))


def checked_columns(source: str, corners: Sequence[np.ndarray], totals: Sequence[int],
                    line_of_corner: Callable[[int], int]) -> list[np.ndarray | None]:
    """The corners' v, vt and vn columns (0-based, -1 for none), each index checked against its table
    once the whole file is read, since positive indices may point forward; a vt or vn column that
    names no row, None."""
    kept: list[np.ndarray | None] = []
    for field, column in enumerate(corners):
        top = largest(column) if column.size else -1
        if top >= totals[field]:
            first_bad = int(np.argmax(column >= totals[field]))
            raise LoadError(source, f"{_FIELD_NAMES[field]} index {column[first_bad] + 1} out of range: "
                                    f"the file has {totals[field]}", line=line_of_corner(first_bad))
        kept.append(column if field == 0 or top >= 0 else None)
    return kept


def _logical_lines(text: bytes) -> Iterator[tuple[int, bytes]]:
    """(first line number, content) with backslash-continued lines joined.

    A backslash continues only a statement: not a line with a comment, and a comment line is never
    joined to the statement before it."""
    pending = bytearray()  # grows in place: bytes' += copies at every line, a list holds an object a line
    first = 0
    for number, line in enumerate(_physical_lines(text), start=1):
        if pending and line.lstrip().startswith(b"#"):
            yield first, bytes(pending)
            pending.clear()
        stripped = line.rstrip()
        if stripped.endswith(b"\\") and comment_at(line) < 0:
            first = first if pending else number
            pending += stripped[:-1]
            pending += b" "
            continue
        if pending:
            pending += line
            yield first, bytes(pending)
            pending.clear()
        else:
            yield number, line
    if pending:
        yield first, bytes(pending)


def _physical_lines(text: bytes) -> Iterator[bytes]:
    """The lines one at a time: a list of them all would cost many times the file."""
    start = 0
    while start <= len(text):
        end = text.find(b"\n", start)
        end = len(text) if end < 0 else end
        yield text[start:end]
        start = end + 1


def _first_tokens(rest: bytes) -> bytes:
    """The face's corners joined by single spaces, only as far as _quoted_start shows them."""
    return b" ".join(rest.split(None, SHOWN_WHOLE + 1)[:SHOWN_WHOLE + 1])


def _quoted(token: bytes) -> str:
    """A word of the file, quoted, shortened where long (its length said)."""
    return repr(shortened(decoded(token)))


def _quoted_start(tokens: bytes) -> str:
    """The start of a line's words, quoted, cut where long: not all of them are joined, to count."""
    text = decoded(tokens)
    return repr(text if len(text) <= SHOWN_WHOLE else text[:SHOWN_WHOLE - 3] + "...")
