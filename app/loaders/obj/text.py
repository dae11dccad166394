"""What an OBJ text must be before either reader reads it, and the checks that make it so.

`ended` is cheap and comes first (`read_text` reads a file as it makes it): both readers need the
last line to end with a newline. `checked` costs a few passes over the bytes; the fast reader's
first pass notes whether a text needs it at all.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

import numpy as np

from marraztu.errors import LoadError
from marraztu.loaders.files import (
    BOM,
    UTF16_BOMS,
    bom_length,
    errors_as_load_errors,
    line_at,
    read_model_bytes,
    refuse_blank,
    regular_file_size,
)
from marraztu.loaders.obj.raw import comment_at

_BACKSLASH_AT_LINE_END = re.compile(rb"\\[^\S\n]*\n")
_NO_BREAK_SPACE = "\u00a0".encode()
_NEWLINE = ord("\n")


def read_text(path: str | Path, stage: Callable[[str], None] | None,
              opened: Callable[[int], None] = lambda size: None) -> np.ndarray:
    """A file's text as `ended` makes it, in a uint8 array: numpy backs a large array with huge pages,
    which a large file is read into more quickly than into bytes, and the newline a last line lacks
    goes in room kept for it instead of a copy. `stage` hears "reading", then "parsing"; `opened`
    hears the file's size once it is open, before it is read."""
    if stage is not None:
        stage("reading")
    size = regular_file_size(path)
    room = np.empty(size + 2, np.uint8)  # the room for a newline, and a byte more to notice a file that grew
    with errors_as_load_errors(path), open(path, "rb", buffering=0) as stream:
        opened(size)
        got = _read_into(stream, memoryview(room))
    if got > size:  # it grew after stat: read as bytes, which follow it up to the size limit
        data = read_model_bytes(path, None)
        room, got = np.empty(len(data) + 1, np.uint8), len(data)
        room[:got] = np.frombuffer(data, np.uint8)
        del data
    refuse_blank(path, memoryview(room)[:got])
    if room[got - 1] != _NEWLINE:
        room[got] = _NEWLINE
        got += 1
    if stage is not None:
        stage("parsing")
    return room[bom_length(room[:min(got, len(BOM))].tobytes()):got]


def _read_into(stream: BinaryIO, room: memoryview) -> int:
    got = 0
    while got < len(room):
        count = stream.readinto(room[got:])
        if not count:
            break
        got += count
    return got


def as_bytes(text: bytes | np.ndarray) -> bytes:
    """The text checks' bytes methods need bytes: a copy of an array's."""
    return text if isinstance(text, bytes) else text.tobytes()


def ended(data: bytes) -> bytes:
    """The text without a UTF-8 byte order mark, its last line ended by a newline (a copy only where
    either is needed)."""
    start = bom_length(data[:len(BOM)])
    if start or not data.endswith(b"\n"):  # both edits in one copy
        data = b"".join((memoryview(data)[start:], b"" if data.endswith(b"\n") else b"\n"))
    return data


def checked(text: bytes, source: str) -> bytes:
    """Reject binary data; make a lone CR (old Mac files) end a line; read what editors write as ASCII.

    A no-break space becomes two spaces. Tabs, the CR of CRLF and the other ASCII whitespace stay:
    both readers treat them as spaces. The same object comes back where nothing changed.
    """
    if b"\r" in text and text.count(b"\r") != text.count(b"\r\n"):
        text = text.replace(b"\r\n", b"\n").replace(b"\r", b"\n")  # no regex: it would hold a piece per line
    nul = text.find(b"\0")
    if nul >= 0 and text.startswith(UTF16_BOMS):
        raise LoadError(source, "UTF-16 text, not an OBJ text file: save it as UTF-8", line=1)
    if nul >= 0:
        raise LoadError(source, "binary data (a NUL byte), not an OBJ text file", line=line_at(text, nul))
    if not text.isascii():  # comments and names may be UTF-8 or Windows-1252: both are read
        text = text.replace(_NO_BREAK_SPACE, b"  ")
    return text


def has_continuations(text: bytes) -> bool:
    """A backslash ending a line continues it, unless the line holds a comment (C:\\models\\ in one): a
    '#' at its start or after a blank (raw.comment_at), as both readers read comments."""
    if b"\\" not in text:
        return False
    for match in _BACKSLASH_AT_LINE_END.finditer(text):
        line_start = text.rfind(b"\n", 0, match.start()) + 1
        if comment_at(text, line_start, match.start()) < 0:
            return True
    return False
