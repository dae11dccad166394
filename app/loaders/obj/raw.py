"""What the OBJ reader's two halves share: the tables they produce and the pieces of a line both read."""

from __future__ import annotations

import re
from array import array
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from marraztu.loaders.files import decoded
from marraztu.loaders.words import DECIMAL, DECIMAL_BYTES

# Corner formats by which of v/vt/vn they hold: the slashes between consecutive numbers.
CORNER_GAPS = {(True,): (), (True, True): (1,), (True, False, True): (2,), (True, True, True): (1, 1),
               # Wings3D writes a corner of no vt and no vn as 'v//', and old assimp one of no vn as 'v/vt/'
               (True, False, False): (), (True, True, False): (1,)}
# No file holds 10**15 of anything, and up to 15 digits an index or mantissa is an exact double.
MAX_DIGITS = 15
# The columns of the v, vt and vn tables (RawObj's positions, texcoords and normals).
TABLE_WIDTHS = (3, 2, 3)


@dataclass
class RawObj:
    """The file's tables as read, before anything is derived. Corner indices are 0-based."""

    positions: np.ndarray  # (V, 3) float64
    texcoords: np.ndarray  # (T, 2) float64
    normals: np.ndarray  # (N, 3) float64
    corner_vertex: np.ndarray  # (C,) model.mesh.INDEX
    corner_texcoord: np.ndarray | None  # (C,) INDEX, -1 where a corner has no vt; None: no corner has
    corner_normal: np.ndarray | None  # (C,) INDEX, likewise for vn
    face_start: np.ndarray  # (F + 1,) INDEX
    mtllib: tuple[str, ...]  # each distinct mtllib line's names, at most MAX_LIBRARY_LINES + 1 of them
    colour: tuple[float, float, float] | None  # the seed reader's "# colour r g b", in 0..1
    notes: list[str]
    material_runs: MaterialRuns = field(default_factory=lambda: MaterialRuns())
    # (V, 3) float64: the colour each `v x y z r g b` line gives (NaN where its line gives none); None:
    # no v line gives one.
    vertex_colours: np.ndarray | None = None


COLOUR_COMMENT = re.compile(rb"\s*#\s*colou?r\s+(\S+)\s+(\S+)\s+(\S+)\s*\Z")


class ColourComment:
    """The seed reader's ``# colour r g b`` (0..255) as a 0..1 colour: the first well-formed one counts.

    Malformed ones before it become one note, however many there are: the overlay shows every note."""

    def __init__(self) -> None:
        self.colour: tuple[float, float, float] | None = None
        self.malformed = 0
        self.first_malformed_line = 0

    def offer(self, line_number: int, comment: bytes) -> None:
        if self.colour is not None or b"colo" not in comment:
            return
        match = COLOUR_COMMENT.match(comment)
        if match is None:
            return
        values = finite_floats(match.groups())
        if values is None:
            self.malformed += 1
            self.first_malformed_line = self.first_malformed_line or line_number
        else:
            red, green, blue = (min(max(value / 255.0, 0.0), 1.0) for value in values)
            self.colour = (red, green, blue)

    @property
    def notes(self) -> list[str]:
        if self.malformed == 0:
            return []
        if self.malformed == 1:
            return [f"ignored a malformed '# colour' comment on line {self.first_malformed_line}"]
        first = self.first_malformed_line
        return [f"ignored {self.malformed} malformed '# colour' comments (the first on line {first})"]


_POLYPAINT_LINE = re.compile(rb"\s*#MRGB[ \t\v\f\r]+([0-9A-Fa-f]+)\s*\Z")
_POLYPAINT_ENTRY_DIGITS = 8  # MMRRGGBB: ZBrush's mask byte, then the colour


class Polypaint:
    """ZBrush's vertex colours: `#MRGB` comment lines of MMRRGGBB entries, one per position in file
    order. A malformed line would shift every colour after it, so one makes the whole paint a note."""

    def __init__(self) -> None:
        self.payloads: list[bytes] = []
        self.first_malformed_line = 0

    def offer(self, line_number: int, comment: bytes) -> None:
        if b"#MRGB" not in comment[:16] or self.first_malformed_line:
            return
        match = _POLYPAINT_LINE.match(comment)
        if match is None or len(match.group(1)) % _POLYPAINT_ENTRY_DIGITS:
            if comment.lstrip().startswith(b"#MRGB"):
                self.first_malformed_line = line_number
            return
        self.payloads.append(match.group(1))

    def with_colours(self, table: np.ndarray | None, positions: int) -> tuple[np.ndarray | None, list[str]]:
        """RawObj.vertex_colours with the paint put in where no v line gives colours, and its notes."""
        if self.first_malformed_line:
            return table, [f"ignored the ZBrush polypaint (#MRGB): line {self.first_malformed_line} is malformed"]
        if not self.payloads:
            return table, []
        if table is not None:
            return table, ["the v lines' colours are drawn, not the ZBrush polypaint (#MRGB)"]
        entries = np.frombuffer(bytes.fromhex(b"".join(self.payloads).decode("ascii")), np.uint8).reshape(-1, 4)
        table = np.full((positions, 3), np.nan)
        painted = min(positions, len(entries))
        table[:painted] = entries[:painted, 1:] / 255.0  # 0..1 already: colour_fractions never reads them as 0..255
        extra = len(entries) - painted
        return table, [f"{extra} ZBrush polypaint (#MRGB) colours past the last position ignored"] if extra else []


def finite_floats(tokens: Sequence[bytes | str]) -> list[float] | None:
    """The tokens' values where each is a finite decimal number in ASCII digits; None otherwise."""
    # float() reads '١' (an Arabic-Indic 1) and 1_0 (10) too, which v lines refuse as no number
    if not all((DECIMAL_BYTES if isinstance(token, bytes) else DECIMAL).fullmatch(token)  # type: ignore[arg-type]
               for token in tokens):
        return None
    values = [float(token) for token in tokens]
    return values if all(np.isfinite(values)) else None


# A comment starts at a '#' that begins the line or follows a blank: inside a word it is the word's
# (old Windows programs wrote NaN as -1.#IND, which cut there read as -1).
_COMMENT_SYNTAX = r"(?<![^ \t\n\r\x0b\x0c])#"
_COMMENT, _TEXT_COMMENT = re.compile(_COMMENT_SYNTAX.encode()), re.compile(_COMMENT_SYNTAX)  # in bytes, in text


def comment_at(text: bytes, start: int = 0, stop: int | None = None) -> int:
    """Where the first comment of text[start:stop] starts (by the rule above); -1 where there is none."""
    found = _COMMENT.search(text, start, len(text) if stop is None else stop)
    return -1 if found is None else found.start()


def without_comment(content: bytes) -> bytes:
    at = comment_at(content)
    return content if at < 0 else content[:at]


def text_without_comment(line: str) -> str:
    """An MTL line without its comment, by the rule of an OBJ line's."""
    found = _TEXT_COMMENT.search(line)
    return line if found is None else line[:found.start()]


def statement(content: bytes) -> tuple[bytes, bytes]:
    """(keyword, rest of the line without comment, stripped); keyword b'' for blank and comment lines.

    Only ASCII whitespace separates (bytes.split), as in the fast reader.
    """
    parts = without_comment(content).split(None, 1)
    if not parts:
        return b"", b""
    if parts[0] == b"usemtl":  # a name, '#' and all: 3ds Max names materials "Material #25"
        return parts[0], content.lstrip()[len(parts[0]):].strip()
    return parts[0], parts[1].strip() if len(parts) > 1 else b""


class MaterialRuns:
    """The file's `usemtl` runs, in file order: the first face of each and its material's number in
    `names`; the faces up to the next run use it. Two arrays, not a tuple per run: a file may change
    material before every face."""

    def __init__(self) -> None:
        self.starts, self.name_numbers = array("q"), array("q")
        self.names: list[str] = []
        self._numbers: dict[str, int] = {}

    def __len__(self) -> int:
        return len(self.starts)

    def as_pairs(self) -> list[tuple[int, str]]:
        return [(start, self.names[number]) for start, number in zip(self.starts, self.name_numbers)]

    def used_numbers(self) -> np.ndarray:
        """The numbers of the names the runs use, in the order of their first run. Not np.unique, whose
        first call imports numpy.ma."""
        numbers = np.frombuffer(self.name_numbers, np.int64)
        first_run = np.full(len(self.names), numbers.size)
        np.minimum.at(first_run, numbers, np.arange(numbers.size))
        used = np.flatnonzero(first_run < numbers.size)
        return used[np.argsort(first_run[used])]

    def number(self, name: str) -> int:
        """The name's number in `names`, given it now where it has none."""
        number = self._numbers.setdefault(name, len(self.names))
        if number == len(self.names):
            self.names.append(name)
        return number

    def add(self, faces_before: int, name: str) -> None:
        """A usemtl: its faces start at `faces_before`. One that another follows before any face takes
        no face, so the later replaces it: a file of usemtl lines holds one run, not one per line; one
        naming the material the faces before use goes on with their run."""
        if self.starts and self.starts[-1] == faces_before:
            self.starts.pop()
            self.name_numbers.pop()
        number = self.number(name)
        if not self.name_numbers or self.name_numbers[-1] != number:
            self.starts.append(faces_before)
            self.name_numbers.append(number)

    def extend(self, starts: np.ndarray, numbers: np.ndarray) -> None:
        """Many usemtl lines, in file order (their first faces and name numbers), as `add` would take
        them one by one: of those at one face (and the last run so far, where it starts there) the last
        counts; then one naming the material of the one before goes on with its run."""
        starts, numbers = np.asarray(starts, np.int64), np.asarray(numbers, np.int64)
        if self.starts:
            starts = np.concatenate(([self.starts.pop()], starts))
            numbers = np.concatenate(([self.name_numbers.pop()], numbers))
        last_at_its_face = np.append(starts[1:] != starts[:-1], True)
        starts, numbers = starts[last_at_its_face], numbers[last_at_its_face]
        before = self.name_numbers[-1] if self.name_numbers else -1
        new_run = numbers != np.concatenate(([before], numbers[:-1]))
        self.starts.frombytes(starts[new_run].tobytes())
        self.name_numbers.frombytes(numbers[new_run].tobytes())


# `v x y z r g b` (MeshLab): a colour after the position, drawn as PLY's and COFF's are.
COLOURED_V_NUMBERS = 6
# The v forms: x y z; x y z w; x y z r g b. A line of 5 or 7 numbers (3 to 7 are read) fits none: it is
# read as the form before it, with a note, as the readers have always read it.
V_FORMS = (3, 4, COLOURED_V_NUMBERS)


class UnformedVLines:
    """The v lines of 5 or 7 numbers, each read as the form before it, its last number ignored: one
    note for them all, naming the first (the readers of pieces give theirs in any order)."""

    def __init__(self) -> None:
        self.count = 0
        self.first_line = 0

    def add(self, line_number: int, count: int = 1) -> None:
        """`count` such lines, the first of them on line `line_number`."""
        if count:
            self.count += count
            self.first_line = min(self.first_line or line_number, line_number)

    @property
    def notes(self) -> list[str]:
        if self.count == 0:
            return []
        forms = "v reads x y z, x y z w or x y z r g b"
        if self.count == 1:
            return [f"ignored the last number of a v line of 5 or 7 numbers on line {self.first_line} ({forms})"]
        return [f"ignored the last number of {self.count} v lines of 5 or 7 numbers (the first on line "
                f"{self.first_line}; {forms})"]
# Said where a file has l or p statements beside its faces: drawn nowhere, not lost without a word.
UNDRAWN_ELEMENTS = "its l and p statements (lines and points) are not drawn"


def reading_notes(unformed: UnformedVLines, colour: ColourComment, paint_notes: list[str], elements: bool
                  ) -> list[str]:
    """RawObj.notes, in the one order both readers give them: v lines of no v form, '# colour'
    comments, the polypaint, l and p statements."""
    return [*unformed.notes, *colour.notes, *paint_notes, *([UNDRAWN_ELEMENTS] if elements else [])]
MAX_LIBRARY_LINES = 16  # mtllib lines read: a file of a million must not cost a million lookups
MAX_MATERIAL_NAME = 200  # characters of a usemtl name kept: enough for any real one, bounded for a hostile one


def put_colours(table: np.ndarray, rows: Sequence[int], values: Sequence[float]) -> np.ndarray:
    """RawObj.vertex_colours: `table` with the colours some v lines give put in (their position rows,
    and three numbers each)."""
    table[np.asarray(rows, dtype=np.int64)] = np.asarray(values, dtype=np.float64).reshape(-1, 3)
    return table


def with_library(libraries: tuple[bytes, ...], rest: bytes) -> tuple[bytes, ...]:
    """The mtllib lines' names so far, as the file's bytes, and this line's where its bytes are new (as
    the compiled reader tells them apart): one more than MAX_LIBRARY_LINES at most, so that the
    reader can say some were left unread. Files joined into one repeat one mtllib line per object."""
    return libraries + (rest,) if len(libraries) <= MAX_LIBRARY_LINES and rest not in libraries else libraries


def library_names(libraries: tuple[bytes, ...]) -> tuple[str, ...]:
    return tuple(decoded(name) for name in libraries)


def usemtl_name(line: bytes) -> str:
    """The name a whole usemtl line gives."""
    return material_name(statement(line)[1])


def material_name(rest: bytes) -> str:
    """The name a usemtl line gives (the whole rest of the line: names may hold spaces)."""
    return name_of_words(decoded(rest))


def name_before_comment(name: str) -> str:
    """A material's name read the other way, a '#' after a blank starting a comment ("wood # oak" is
    "wood"): looked for where the whole name is not found."""
    return name_of_words(text_without_comment(name))


def name_of_words(text: str) -> str:
    """A material's name, as usemtl and newmtl give it: the words of the rest of the line, one blank
    between each, '#' and all; at most MAX_MATERIAL_NAME characters (so never more words than that)."""
    return " ".join(text.split(None, MAX_MATERIAL_NAME)[:MAX_MATERIAL_NAME])[:MAX_MATERIAL_NAME]
