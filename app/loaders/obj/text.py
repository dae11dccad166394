"""What an OBJ text must be before either reader reads it, and the checks that make it so.

`ended` is cheap and comes first: both readers need the last line to end with a newline. `checked`
costs a few passes over the bytes; the fast reader's first pass notes whether a text needs it at all.
"""

from __future__ import annotations

import re

from marraztu.errors import LoadError
from marraztu.loaders.files import line_at

_BACKSLASH_AT_LINE_END = re.compile(rb"\\[^\S\n]*\n")
_BOM = b"\xef\xbb\xbf"
_NO_BREAK_SPACE = "\u00a0".encode()


def ended(data: bytes) -> bytes:
    """The text without a UTF-8 byte order mark, its last line ended by a newline (a copy only where
    either is needed)."""
    start = len(_BOM) if data.startswith(_BOM) else 0
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
    if nul >= 0:
        raise LoadError(source, "binary data (a NUL byte), not an OBJ text file", line=line_at(text, nul))
    if not text.isascii():  # comments and names may be UTF-8 or Windows-1252: both are read
        text = text.replace(_NO_BREAK_SPACE, b"  ")
    return text


def has_continuations(text: bytes) -> bool:
    """A backslash ending a line continues it, unless the line holds a comment (C:\\models\\ in one)."""
    if b"\\" not in text:
        return False
    for match in _BACKSLASH_AT_LINE_END.finditer(text):
        line_start = text.rfind(b"\n", 0, match.start()) + 1
        if text.find(b"#", line_start, match.start()) < 0:
            return True
    return False
