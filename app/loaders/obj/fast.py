"""The fast OBJ reader: compiled passes over the bytes (scan.py), on several threads.

The text is cut into pieces at line ends. Pass one counts each piece's rows, faces and corners,
and a word scan says whether the text needs the text checks (text.py), which most files (pure
ASCII, LF line ends) do not; the tables are then made at their final sizes, and pass two writes
every piece into them at its own offsets. What the compiled code does not read itself comes back
as records, in file order: the line reader (lines.py) reads each listed v, vt, vn or f line in its
piece's thread as the records come, giving its values or its error, so every message is the line
reader's and a bad line ends its piece (the plain rows among them, left for their long numbers, hold
no error: they are read here a batch at a time); other statements and colour comments are read here,
in file order, once every piece is read.
"""

from __future__ import annotations

import bisect
from array import array
from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from marraztu.loaders.obj import raw, scan
from marraztu.loaders.obj.lines import PLAIN_ROW_RUNS, LineReader, checked_columns, no_faces_error, read_plain_numbers
from marraztu.model.mesh import INDEX, polygons_of_corners
from marraztu.model.threads import THREADS, each

try:  # the mesh's compiled loops: their machine code loads with the reader's
    from marraztu.model import compiled  # noqa: F401
except Exception:  # they cannot load here: numpy derives the normals, and this reader still reads
    pass

# Pieces of at least this many bytes: below it a thread costs more than it saves.
MIN_PIECE_BYTES = 1 << 20
# numba's code runs without the GIL, so threads parse pieces at once.
PARSE_THREADS = THREADS
# More pieces than threads: a thread whose pieces went quickly takes the next, so a piece of costly
# lines (faces, long numbers) does not keep the others waiting.
PIECES_PER_THREAD = 4


_ONE_TRIANGLE = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"


def load_machine_code() -> None:
    """Has numba load the passes' machine code (from its cache, or compiled), as a first file would."""
    read_fast(_ONE_TRIANGLE, "one triangle")
    scan.line_end(_read_only_bytes(_ONE_TRIANGLE), 0)  # _pieces's, for texts of two pieces or more


def machine_code_loaded() -> bool:
    """Whether this process has its compiled code yet (numba loads it, from its cache, on first use)."""
    return all(function.signatures for function in (scan.count_piece, scan.holds_bytes_to_look_at, scan.read_piece))


@dataclass(frozen=True)
class Counted:
    """Pass one's outcome: the pieces of the text, their counts, and whether a byte in them is one
    only the text checks judge (scan.holds_bytes_to_look_at)."""

    pieces: list[tuple[int, int]]
    counts: np.ndarray  # (pieces, scan.COUNT_COLUMNS)
    to_look_at: bool


def count_text(text: bytes | np.ndarray) -> Counted:
    """Pass one, over the whole text. `text` ends with a newline (marraztu.loaders.obj.text.ended)."""
    buf = _read_only_bytes(text)
    if not buf.size or buf[-1] != ord("\n"):  # the passes stop at newlines: past the text's end, a crash
        raise ValueError("the compiled passes read an ended text (marraztu.loaders.obj.text.ended)")
    pieces = _pieces(buf, PARSE_THREADS * PIECES_PER_THREAD)
    counts = np.zeros((len(pieces), scan.COUNT_COLUMNS), np.int64)

    def count(at: int) -> bool:  # the piece's counts into its row; whether it holds a byte to look at
        scan.count_piece(buf, *pieces[at], counts[at])
        return scan.holds_bytes_to_look_at(buf, *pieces[at])

    return Counted(pieces, counts, any(each(count, list(range(len(pieces))), PARSE_THREADS)))


def read_fast(text: bytes | np.ndarray, source: str, counted: Counted | None = None) -> raw.RawObj:
    """The file's tables, or the LoadError the line reader gives for its first bad line.

    `text` ends with a newline and has passed the text checks where `counted` (its pass one, made
    here when not given) says it needs them (marraztu.loaders.obj.text)."""
    buf = _read_only_bytes(text)
    if counted is None:
        counted = count_text(text)
    pieces, counts = counted.pieces, counted.counts
    before = np.cumsum(counts, axis=0) - counts  # each piece's offsets into the tables
    total = counts.sum(axis=0)
    tables = [np.empty((int(total[kind]), width)) for kind, width in zip((scan.V, scan.VT, scan.VN), raw.TABLE_WIDTHS)]
    columns = [np.empty(int(total[scan.CORNERS]), INDEX) for _ in range(3)]
    face_start = np.zeros(int(total[scan.F]) + 1, INDEX)
    # The first bad line, in the pieces' order, is raised here: each piece stops at its own.
    read = each(lambda at: _read_piece(buf, pieces[at], before[at], _DeferredLines(source, buf, tables, columns),
                                       face_start),
                list(range(len(pieces))), PARSE_THREADS)
    outcome = _settled(buf, read)
    if total[scan.F] == 0:
        raise no_faces_error(source, outcome.statements > 0 or bool(total[[scan.V, scan.VT, scan.VN]].any()),
                            outcome.elements)
    totals = [len(table) for table in tables]
    kept = checked_columns(source, columns, totals, lambda corner: scan.line_of_face(
        buf, int(polygons_of_corners(face_start, corner))))
    colours = _v_line_colours(buf, pieces, before, len(tables[0]), outcome) if outcome.coloured else None
    colours, paint_notes = outcome.polypaint.with_colours(colours, len(tables[0]))
    notes = raw.reading_notes(outcome.unformed, outcome.colour, paint_notes, outcome.elements)
    return raw.RawObj(*tables, *kept, face_start, raw.library_names(outcome.mtllib), outcome.colour.colour, notes,
                      outcome.material_runs, colours)


def _settled(buf: np.ndarray, read: list[tuple[list[np.ndarray], _DeferredLines, np.ndarray]]) -> _Records:
    """Every piece's records settled in file order, once each piece's deferred lines are read."""
    outcome = _Records(buf)
    for chunks, deferred, names in read:
        outcome.take_piece(deferred)
        numbers = outcome.name_numbers(names)
        for chunk in chunks:
            outcome.settle(chunk, numbers)
    return outcome


def _v_line_colours(buf: np.ndarray, pieces: list[tuple[int, int]], before: np.ndarray, positions: int,
                    outcome: _Records) -> np.ndarray:
    """RawObj.vertex_colours of a file whose v lines give colours: a third pass, which the files
    without them skip, and the colours of the v lines the line reader read."""
    colours = np.full((positions, 3), np.nan)
    each(lambda at: scan.read_vertex_colours(buf, *pieces[at], before[at][scan.V], colours, np.empty((1, 7))),
         list(range(len(pieces))), PARSE_THREADS)
    return raw.put_colours(colours, outcome.colour_rows, outcome.colour_values)


def _read_piece(buf: np.ndarray, piece: tuple[int, int], before: np.ndarray, deferred: _DeferredLines,
                face_start: np.ndarray) -> tuple[list[np.ndarray], _DeferredLines, np.ndarray]:
    """Pass two over a piece; its records, in file order, in chunks of doubling size: a full chunk is
    kept as it is and the next one given, so that no record is copied to make room. The line reader
    reads each chunk's deferred lines as it comes, so a bad one ends the piece: a file of millions
    of bad lines holds a few records, not one per line. Also the bytes of its distinct usemtl lines."""
    state = np.zeros(scan.STATE_COLUMNS, np.int64)
    state[:scan.COUNT_COLUMNS] = before
    state[scan.LINES] += 1  # line numbers start at 1
    state[scan.S_AT] = piece[0]
    state[scan.S_LAST_NAME] = -1  # no usemtl line yet
    chunks = []
    rows = 16
    # A record's numbers (byte offsets, a line's number, counts) all stay below the text's length.
    record_type = np.int32 if buf.shape[0] <= np.iinfo(np.int32).max else np.int64
    names = np.zeros((scan.NAMES_PER_PIECE, 2), np.int64)
    libraries_named = np.zeros((raw.MAX_LIBRARY_LINES + 1, 2), np.int64)  # as many as raw.with_library keeps
    while True:
        records = np.empty((rows, scan.RECORD_COLUMNS), record_type)
        state[scan.S_USED] = 0
        scan.read_piece(buf, piece[1], state, records, names, libraries_named, *deferred.tables, *deferred.columns,
                        face_start)
        chunks.append(deferred.read(records[:state[scan.S_USED]], face_start))
        if state[scan.S_AT] >= piece[1]:
            deferred.unformed.add(int(state[scan.S_FIRST_UNFORMED]), int(state[scan.S_UNFORMED]))
            return chunks, deferred, names[:state[scan.S_NAMES]]
        rows *= 2


def _read_only_bytes(text: bytes | np.ndarray) -> np.ndarray:
    """The text as the compiled passes take it: read-only, as bytes give it, whatever it came as, so
    that numba has one machine code to load (it compiles each array type apart)."""
    buf = np.frombuffer(text, dtype=np.uint8)
    buf.flags.writeable = False
    return buf


def _pieces(buf: np.ndarray, count: int) -> list[tuple[int, int]]:
    """[low, high) byte ranges of whole lines, about equal: at most `count`, of MIN_PIECE_BYTES or more."""
    size = buf.shape[0]
    count = max(1, min(count, size // MIN_PIECE_BYTES))
    cuts = [0]
    for piece in range(1, count):
        if cuts[-1] == size:  # a long last line reached past the cuts still to make
            break
        cuts.append(scan.line_end(buf, max(piece * size // count, cuts[-1])) + 1)
    if cuts[-1] < size:
        cuts.append(size)
    return list(zip(cuts[:-1], cuts[1:]))


_SETTLED_AT_ONCE = 4096


def _python_rows(records: np.ndarray) -> Iterator[list[int]]:
    """Each record as a list of Python ints, made a few thousand records at a time: ten ints a record,
    never for every record at once."""
    for first in range(0, records.shape[0], _SETTLED_AT_ONCE):
        yield from records[first:first + _SETTLED_AT_ONCE].tolist()


class _DeferredLines:
    """Reads the v, vt, vn and f lines a piece's compiled pass left to the line reader, into the
    whole file's tables at the rows its records give: their values, or their LoadError."""

    def __init__(self, source: str, buf: np.ndarray, tables: list[np.ndarray], columns: list[np.ndarray]) -> None:
        self.source, self.buf, self.tables, self.columns = source, buf, tables, columns
        self.coloured = False  # some v line the line reader read gives a colour after its position
        # The colours of those v lines: their rows, and three numbers each.
        self.colour_rows, self.colour_values = array("q"), array("d")
        self.unformed = raw.UnformedVLines()  # the piece's: the lines the line reader read, then pass two's

    def read(self, records: np.ndarray, face_start: np.ndarray) -> np.ndarray:
        """Reads the deferred lines among `records`; the others, left for _Records to settle."""
        deferred = records[:, scan.R_KIND] == scan.DEFERRED
        if not deferred.any():
            return records
        left = records[deferred]
        # The plain rows hold no error, so the other lines still meet the line reader in file order.
        for record in _python_rows(left[~self.read_plain_rows(left)]):
            self.read_line(record, self.buf[record[scan.R_START]:record[scan.R_END]].tobytes(), face_start)
        return records[~deferred]

    def read_plain_rows(self, records: np.ndarray) -> np.ndarray:
        """Reads the records' v, vt and vn lines that are plain rows of their table's width into their
        rows, a batch at a time; which records they were."""
        read = np.zeros(len(records), bool)
        lengths = records[:, scan.R_END] - records[:, scan.R_START]
        for kind in (scan.V, scan.VT, scan.VN):
            lines = np.flatnonzero((records[:, scan.R_KEYWORD] == kind) & (lengths <= _PLAIN_ROW_BYTES))
            for first in range(0, len(lines), _PLAIN_ROWS_AT_ONCE):
                batch = lines[first:first + _PLAIN_ROWS_AT_ONCE]
                read[batch[read_plain_batch(self.buf, kind, records[batch], self.tables[kind])]] = True
        return read

    def read_line(self, record: list[int], content: bytes, face_start: np.ndarray) -> None:
        reader = LineReader(self.source)
        reader.defined = [record[scan.R_V], record[scan.R_VT], record[scan.R_VN]]
        reader.read_line(record[scan.R_LINE], content)
        if reader.coloured_rows:
            self.colour_rows.extend(reader.coloured_rows)
            self.colour_values.extend(reader.colour_values)
            self.coloured = True
        self.unformed.add(reader.unformed.first_line, reader.unformed.count)
        kind = record[scan.R_KEYWORD]
        if kind == scan.F:
            # Its slots end where pass two ended the face; they start where the record says, not where
            # face_start does: another piece, on another thread, writes the face's first entry.
            corner, corners = record[scan.R_CORNER], len(reader.corners[0])
            if corner + corners != face_start[record[scan.R_FACE] + 1]:
                raise RuntimeError("the line reader read other corners than pass one counted")
            for column, values in zip(self.columns, reader.corner_columns()):
                column[corner:corner + corners] = values
        else:
            self.tables[kind][record[scan.R_V + kind]] = reader.tables[kind]


# The deferred lines that are plain rows of their table's width (lines.PLAIN_ROW_RUNS) hold no error (a
# plain number is finite and within float32 by its syntax); the compiled code leaves them for their
# long numbers (more than 15 digits, as Python's repr writes them).
_PLAIN_ROWS_AT_ONCE = 1 << 12
_PLAIN_ROW_BYTES = 1 << 10  # longer lines go to the line reader: a batch's copy stays a few megabytes


def read_plain_batch(buf: np.ndarray, kind: int, records: np.ndarray, table: np.ndarray) -> np.ndarray:
    """Writes the plain rows among the lines of `records`, all of table `kind` (scan.V, VT or VN), into
    `table` at their rows, their numbers made in one call: a line reader for each would cost several
    times their numbers. Which of the records they were, as indices."""
    starts, ends = records[:, scan.R_START], records[:, scan.R_END] + 1  # each line with its newline
    # One slice per run of adjacent lines: a file whose numbers are all long has few, and long ones.
    gaps = np.flatnonzero(starts[1:] != ends[:-1]) + 1
    text = memoryview(buf)
    lines = b"".join([text[start:end] for start, end in zip(starts[np.r_[0, gaps]].tolist(),
                                                             ends[np.r_[gaps - 1, len(ends) - 1]].tolist())])
    line_ends = np.cumsum(ends - starts).tolist()
    runs, read = [], np.zeros(len(line_ends), bool)
    first, at = 0, 0
    while first < len(line_ends):  # a run of plain rows, then a line that is not one
        stop = PLAIN_ROW_RUNS[kind].match(lines, at).end()
        past = bisect.bisect_right(line_ends, stop, first)
        if past > first:
            runs.append(lines[at:stop])
            read[first:past] = True
        first = past + 1
        at = line_ends[past] if past < len(line_ends) else stop
    kept = np.flatnonzero(read)
    if runs:
        table[records[kept, scan.R_V + kind]] = read_plain_numbers(runs, np.float64).reshape(len(kept), -1)
    return kept


# The usemtl lines whose numbers _Records keeps by their bytes: a model's few materials, not a file of
# millions of names, each of which MaterialRuns keeps once already, nor lines longer than a name is kept.
_USEMTL_LINES_KEPT = 1 << 12
_USEMTL_LINE_BYTES_KEPT = 256


class _Records:
    """Settles the statements and comments of pass two in file order (every deferred line is read)."""

    def __init__(self, buf: np.ndarray) -> None:
        self.text = memoryview(buf)  # whose slices are quicker to make than an array's
        self.mtllib: tuple[bytes, ...] = ()
        self.material_runs = raw.MaterialRuns()
        self._by_line: dict[bytes, int] = {}  # a usemtl line's material number, by the line's bytes
        self.colour = raw.ColourComment()
        self.polypaint = raw.Polypaint()
        self.statements = 0
        self.elements = False  # an l or p statement was read
        self.coloured = False  # some v line gives a colour after its position
        self.colour_rows, self.colour_values = array("q"), array("d")
        self.unformed = raw.UnformedVLines()

    def take_piece(self, deferred: _DeferredLines) -> None:
        """What a piece's v lines give beside its records: colours the line reader read, and the
        lines of no v form."""
        self.unformed.add(deferred.unformed.first_line, deferred.unformed.count)
        self.coloured |= deferred.coloured
        self.colour_rows.extend(deferred.colour_rows)
        self.colour_values.extend(deferred.colour_values)

    def name_numbers(self, names: np.ndarray) -> np.ndarray:
        """The material numbers of a piece's distinct usemtl lines (their bytes' bounds)."""
        return np.array([self._line_number(start, end) for start, end in names.tolist()], np.int64)

    def _line_number(self, start: int, end: int) -> int:
        """The material number of the usemtl line text[start:end], looked up by its bytes."""
        line = self.text[start:end].tobytes()
        number = self._by_line.get(line)
        if number is None:
            number = self.material_runs.number(raw.usemtl_name(line))
            if len(self._by_line) < _USEMTL_LINES_KEPT and len(line) <= _USEMTL_LINE_BYTES_KEPT:
                self._by_line[line] = number
        return number

    def settle(self, records: np.ndarray, name_numbers: np.ndarray) -> None:
        """A chunk's records; `name_numbers`: the material of each of its piece's distinct usemtl lines."""
        usemtl = (records[:, scan.R_KIND] == scan.STATEMENT) & (records[:, scan.R_KEYWORD] == scan.USEMTL_KEYWORD)
        if usemtl.any():  # their runs at once; lines past the piece's numbered ones are numbered here
            lines = records[usemtl]
            places = lines[:, scan.R_NAME]
            numbered = places >= 0
            numbers = np.empty(places.size, np.int64)
            numbers[numbered] = name_numbers[places[numbered]]
            others = lines[~numbered]
            starts, ends = others[:, scan.R_START].tolist(), others[:, scan.R_END].tolist()
            numbers[~numbered] = [self._line_number(start, end) for start, end in zip(starts, ends)]
            self.material_runs.extend(lines[:, scan.R_FACE], numbers)
            self.statements += places.size
            records = records[~usemtl]
        for record in _python_rows(records):
            content = self.text[record[scan.R_START]:record[scan.R_END]].tobytes()
            if record[scan.R_KIND] == scan.STATEMENT:  # usemtl's were settled above
                self.statements += 1
                if record[scan.R_KEYWORD] == scan.MTLLIB_KEYWORD:
                    self.mtllib = raw.with_library(self.mtllib, raw.statement(content)[1])
                self.elements |= record[scan.R_KEYWORD] == scan.ELEMENTS_KEYWORD
            elif record[scan.R_KIND] == scan.VERTEX_COLOURS:
                self.coloured = True
            else:
                self.colour.offer(record[scan.R_LINE], content)
                self.polypaint.offer(record[scan.R_LINE], content)
