"""The line-by-line OBJ reader: the authority on meaning and on error messages.

It runs when the fast reader meets anything it does not handle, and returns the same tables or
raises the LoadError that names the first offending line.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

import numpy as np

from marraztu.errors import LoadError
from marraztu.loaders.obj.raw import CORNER_GAPS, MAX_DIGITS, ColourComment, RawObj, statement
from marraztu.model.geometry import FLOAT32_MAX

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
        self.colour = ColourComment()
        self.statements = 0

    def fail(self, line: int, message: str) -> LoadError:
        return LoadError(self.source, message, line=line)

    def read(self, text: bytes) -> RawObj:
        for number, content in _logical_lines(text):
            keyword, rest = statement(content)
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
            if abs(value) > FLOAT32_MAX:
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
        if tuple(bool(part) for part in parts) not in CORNER_GAPS:
            raise self.fail(number, f"bad face corner {_quoted(token)} (expected v, v/vt, v//vn or v/vt/vn)")
        for field, part in enumerate(parts):
            if part and not _INTEGER.match(part):
                raise self.fail(number, f"bad face corner {_quoted(token)}: {_quoted(part)} is not an index")
            if len(part.lstrip(b"-")) > MAX_DIGITS:  # no file holds 10**15 of anything
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

    def result(self, corners: list[np.ndarray]) -> RawObj:
        def table(field: bytes, width: int) -> np.ndarray:
            return np.array(self.tables[field], dtype=np.float64).reshape(-1, width)

        def optional(field: int) -> np.ndarray | None:
            return corners[field] if np.any(corners[field] >= 0) else None

        face_start = np.concatenate(([0], np.cumsum(self.face_sizes))).astype(np.int64)
        return RawObj(table(b"v", 3), table(b"vt", 2), table(b"vn", 3), corners[0], optional(1), optional(2),
                       face_start, self.mtllib, self.colour.colour, self.colour.notes)


def read_by_lines(text: bytes, source: str) -> RawObj:
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


def _quoted(token: bytes) -> str:
    text = token.decode("utf-8", errors="replace")
    return repr(text if len(text) <= 40 else text[:37] + "...")
