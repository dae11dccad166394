"""STL's two encodings, read here: the triangles' corners, three rows a triangle.

Why not trimesh's readers: its binary one copies the file and keeps the copy alive through the
normals it reads, three times the file in all; its ASCII one splits the whole text on the word
'vertex' (a solid named 'vertex_paint' breaks it), stops without a word at a bad number, and takes
seconds a million triangles. The ASCII reader below reads the usual text whole facets at a time, and
the rest a line at a time, in blocks, saying which line is wrong.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

from marraztu.errors import LoadError, shortened
from marraztu.loaders.files import bom_length, line_at, read_model_bytes, text_lines
from marraztu.loaders.patterns import compiled
from marraztu.loaders.words import (
    WordBlocks,
    checked_coordinates,
    said_count,
    unheld_coordinate,
)
from marraztu.model.build import derive_mesh
from marraztu.model.geometry import holds_in_float32, merged_rows
from marraztu.model.mesh import INDEX, Mesh

HEADER_BYTES, TRIANGLE_BYTES = 84, 50  # binary: an 80-byte header and a count, then 50 bytes a triangle
# A binary triangle: its normal, its three corners, and two bytes of attributes (no standard meaning).
_TRIANGLE_LAYOUT = np.dtype([("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attributes", "<u2")])
# Searched, not stripped: strip() and lstrip() copy the whole file to look at its first word.
_ASCII_START = re.compile(rb"\s*solid(?![^\s])", re.IGNORECASE)
# VisCAM, SolidView and Magics keep a facet's colour in its attribute bytes; the renderer has no face colours.
ATTRIBUTES_NOTE = "the facets' attribute bytes (colours, as some writers use them) are not drawn"


def load_stl(path: Path, stage: Callable[[str], None] | None = None) -> Mesh:
    """Each triangle lists its own corners: equal ones are joined, so that Gouraud smooths across edges.
    Joined here, before the mesh is built, so that the corners' table is freed first."""
    data = read_model_bytes(path, stage)
    corners = stl_corners(path, data)
    notes = (ATTRIBUTES_NOTE,) if _is_binary(data) and _attributes_used(data) else ()
    del data  # freed before the corners are merged
    if not len(corners):
        raise LoadError(path, "no faces")
    if not holds_in_float32(corners):  # a binary file's; before merging, which takes finite numbers
        raise unheld_coordinate(path)
    positions, _, corner_vertex = merged_rows(corners)
    del corners
    try:
        return derive_mesh(path.stem, positions, corner_vertex.astype(INDEX, copy=False),
                           np.arange(0, len(corner_vertex) + 1, 3, dtype=INDEX), None, None, None, None, notes)
    except ValueError as error:  # more corners than 32-bit indices hold
        raise LoadError(path, str(error)) from None


def stl_corners(path: Path, data: bytes) -> np.ndarray:
    """(3T, 3) float64 corners, three a triangle. An ASCII file's numbers are checked as they are read;
    a binary file's are the caller's to check."""
    if _is_binary(data):
        return _binary_corners(data)
    if bom_length(data):  # Notepad's mark before the text: such a rare file costs one copy without it
        data = data[bom_length(data):]
    if not _ASCII_START.match(data):
        raise LoadError(path, "neither a binary STL (its size does not match its triangle count) nor an "
                              "ASCII one (it does not start with 'solid')", line=1)
    data = _without_end_padding(data)
    if b"\0" in data:
        raise LoadError(path, "binary data after 'solid': a binary STL whose size does not match its "
                              f"triangle count ({len(data)} bytes)?", line=line_at(data, data.find(b"\0")))
    blocks, resume_at = _usual_ascii_corners(data)
    if resume_at is not None:
        blocks.append(_ascii_corners(path, data, resume_at))
    return blocks[0] if len(blocks) == 1 else np.concatenate(blocks)


_END_PADDING = b"\0\x1a \t\r\n"  # NULs, or DOS's end-of-file byte, that some writers put after endsolid
_PADDING_PIECE_BYTES = 1 << 16  # looked at from the end a piece at a time: a copy of a piece only


def _without_end_padding(data: bytes) -> bytes:
    """The text without the padding after its last endsolid (copied only where there is a NUL or a DOS
    end-of-file byte in it)."""
    end = _padding_start(data)
    if data.find(b"\0", end) < 0 and data.find(b"\x1a", end) < 0:
        return data
    return b"".join((memoryview(data)[:end], b"\n"))  # one copy: a slice and a sum made two


def _padding_start(data: bytes) -> int:
    """Where the run of padding bytes that ends the text begins, found a piece at a time from the end
    by bytes' own loops in C (a Python step per byte took seconds a megabyte of padding)."""
    end = len(data)
    while end:
        low = max(0, end - _PADDING_PIECE_BYTES)
        piece = data[low:end]
        if piece.translate(None, _END_PADDING):  # something other than padding: the piece holds the run's start
            return low + len(piece.rstrip(_END_PADDING))
        end = low
    return 0


def _binary_triangles(data: bytes) -> np.ndarray:
    """A binary file's triangle records, in place (no copy)."""
    return np.frombuffer(data, _TRIANGLE_LAYOUT, offset=HEADER_BYTES)


def _binary_corners(data: bytes) -> np.ndarray:
    # Cast first: reshaping the strided view copies.
    return _binary_triangles(data)["corners"].astype(np.float64).reshape(-1, 3)


def _attributes_used(data: bytes) -> bool:
    return bool(_binary_triangles(data)["attributes"].any())


def _is_binary(data: bytes) -> bool:
    """By size, not by the first word: binary STL headers often begin with 'solid' too."""
    if len(data) < HEADER_BYTES:
        return False
    return len(data) == HEADER_BYTES + TRIANGLE_BYTES * int.from_bytes(data[80:84], "little")


# What each state of a solid takes next: the keyword and the state it leads to. A facet is
# `facet normal n n n`, `outer loop`, three `vertex x y z`, `endloop`, `endfacet`; what follows
# `facet` and `outer` is not read (the normals are derived from the corners).
_OUTSIDE, _IN_SOLID, _FACET, _LOOP, _SECOND, _THIRD, _LOOP_END, _FACET_END = range(8)
_NEXT: list[dict[str, int]] = [
    {"solid": _IN_SOLID},  # _OUTSIDE
    {"facet": _FACET, "endsolid": _OUTSIDE},  # _IN_SOLID
    {"outer": _LOOP},  # _FACET
    {"vertex": _SECOND},  # _LOOP
    {"vertex": _THIRD},  # _SECOND
    {"vertex": _LOOP_END},  # _THIRD
    {"endloop": _FACET_END},  # _LOOP_END
    {"endfacet": _IN_SOLID},  # _FACET_END
]
_EXPECTED = {
    _OUTSIDE: "'solid' or the end of the file", _IN_SOLID: "'facet' or 'endsolid'", _FACET: "'outer loop'",
    _LOOP: "'vertex'", _SECOND: "'vertex'", _THIRD: "'vertex'", _LOOP_END: "'endloop'", _FACET_END: "'endfacet'",
}


def _ascii_corners(path: Path, data: bytes, start: int = 0) -> np.ndarray:
    """One pass over the lines from `start` (0, or just after a facet), a state per line: every
    corner's three numbers, or the first bad line."""
    state, step = (_IN_SOLID if start else _OUTSIDE), _NEXT
    lines_before = line_at(data, start) - 1
    number = lines_before  # the last line read, which the errors at the end name
    solid_line = 0  # where the solid was opened: 0 before `start`, looked for only if it is not closed
    corners = WordBlocks(path, checked_coordinates)
    for number, line in enumerate(text_lines(data, start), start=lines_before + 1):
        words = line.split(None, 6)  # bounded: a line of millions of words is not made a list of them
        if not words:
            continue
        keyword = words[0]
        next_state = step[state].get(keyword)
        if next_state is None:  # in capitals, or not what comes next
            keyword = keyword.lower()
            next_state = step[state].get(keyword)
            if next_state is None:
                raise _after_words_read(corners, _unexpected(path, state, keyword, number))
        if keyword == "vertex":
            if len(words) != 4:
                raise _after_words_read(corners, LoadError(
                    path, f"a vertex line holds 3 numbers, this one {said_count(words[1:], 5)}", line=number))
            corners.add(words[1:], number)
        elif keyword == "solid":
            solid_line = number
        state = next_state
    if state == _IN_SOLID:
        solid_line = solid_line or _line_of_last_solid(data, start)
        raise _after_words_read(corners, LoadError(
            path, f"the solid begun on line {solid_line} is not closed by 'endsolid'", line=number))
    if state != _OUTSIDE:
        raise _after_words_read(corners, LoadError(path, "the file ends inside a facet", line=number))
    return corners.values().reshape(-1, 3)


def _after_words_read(corners: WordBlocks, error: LoadError) -> LoadError:
    """`error`, unless a word of the lines before its own is no coordinate: that line's error, since the
    words are made numbers a block at a time and the first bad line is the one named."""
    corners.values()
    return error


# The usual ASCII file, read whole facets at a time by one pattern: a facet's seven lines, each
# keyword in any case at the start of its line, the vertex lines' numbers taken as they are. Between
# facets there may only be blank lines, or one solid's end and the next one's start. A file holding
# anything else goes to the line reader above from its last facet read, and that reader names what
# is wrong; where this path reads a text, it gives what the line reader would.
# Possessive quantifiers, and a facet that begins at a line's start with no blank lines ahead of it,
# keep each try at a line start from scanning what the try before scanned: the cost stays linear.
_AFTER_KEYWORD = rb"(?:[ \t][^\r\n]*+)?+"  # what follows `facet`, `outer` and `solid` is not read
_NUMBER = rb"([-+0-9.eE]++)"
_VERTEX_LINE = rb"[ \t]*+(?i:vertex)[ \t]++" + rb"[ \t]++".join([_NUMBER] * 3) + rb"[ \t]*+\r?\n"
_FACET_TEXT = compiled(rb"(?m:^)[ \t]*+(?i:facet)" + _AFTER_KEYWORD + rb"\r?\n[ \t]*+(?i:outer)" + _AFTER_KEYWORD
                         + rb"\r?\n" + _VERTEX_LINE * 3
                         + rb"[ \t]*+(?i:endloop)[ \t]*+\r?\n[ \t]*+(?i:endfacet)[ \t]*+\r?\n")
_SPLIT_STRIDE = _FACET_TEXT.groups + 1  # re.split gives the text before each facet, then its nine numbers
_SOLID, _END_SOLID = rb"(?i:solid)" + _AFTER_KEYWORD + rb"\r?\n", rb"(?i:endsolid)" + _AFTER_KEYWORD
_SOLIDS_BETWEEN = rb"\s*+(?:" + _END_SOLID + rb"\r?\n\s*+" + _SOLID + rb"\s*+)*+"  # one closed, the next opened
_BEFORE_FIRST_FACET = compiled(rb"\s*+" + _SOLID + rb"\s*+")
_BETWEEN_FACETS = compiled(_SOLIDS_BETWEEN)
_AFTER_LAST_FACET = compiled(_SOLIDS_BETWEEN + _END_SOLID + rb"\s*+")
_ENDFACET_WORD = re.compile(rb"(?i:endfacet)")
_FACETS_PIECE = 1 << 20  # bytes read at once, ending after a facet: the piece's words stay a few megabytes


def _usual_ascii_corners(data: bytes) -> tuple[list[np.ndarray], int | None]:
    """The (N, 3) corners of the text's leading facets, a piece at a time while the text is the usual
    one, and the offset from which the line reader reads the rest: just after the last facet read (0
    where none was), or None where the whole text is usual."""
    blocks: list[np.ndarray] = []
    gap = b""  # the text after the last facet read
    for start, stop in _facet_pieces(data):
        resume_at = start - len(gap)
        parts = _FACET_TEXT.split(memoryview(data)[start:stop])
        gaps = parts[::_SPLIT_STRIDE]
        gaps[0] = gap + gaps[0]
        if len(gaps) == 1:  # no facet in the piece: the usual text only at its end, after the last one
            if stop < len(data):
                return blocks, resume_at
            gap = gaps[0]
            break
        # An empty gap needs no look: two facets in a row.
        if not ((_BETWEEN_FACETS if blocks else _BEFORE_FIRST_FACET).fullmatch(gaps[0])
                and all(_BETWEEN_FACETS.fullmatch(between) for between in gaps[1:-1] if between)):
            return blocks, resume_at
        gap = gaps[-1]
        del parts[::_SPLIT_STRIDE]
        try:
            corners = np.array(parts, dtype=np.float64).reshape(-1, 3)
        except ValueError:  # `1e`, `.`, `1-2`: the line reader names the word and its line
            return blocks, resume_at
        if not holds_in_float32(corners):
            return blocks, resume_at
        blocks.append(corners)
    return blocks, (None if blocks and _AFTER_LAST_FACET.fullmatch(gap) else len(data) - len(gap))


def _facet_pieces(data: bytes) -> Iterator[tuple[int, int]]:
    """(start, stop) of pieces of the text of about _FACETS_PIECE bytes, each ending after an endfacet line."""
    start = 0
    while start < len(data):
        end = _ENDFACET_WORD.search(data, start + _FACETS_PIECE)
        # Just past the line end after it; the text's end where there is none (find gives -1).
        stop = len(data) if end is None else data.find(b"\n", end.end()) + 1 or len(data)
        yield start, stop
        start = stop


_SOLID_KEYWORD = re.compile(rb"(?m:^)[ \t\v\f\r]*+((?i:solid))")  # at a line's start: a line begun by 'solid'


def _line_of_last_solid(data: bytes, before: int) -> int:
    """The line of the last solid opened before `before`, in text the usual path has read: only
    solid lines begin with 'solid' there."""
    last = None
    for last in _SOLID_KEYWORD.finditer(data, 0, before):
        pass
    assert last is not None, "the usual path reads facets in a solid only"
    return line_at(data, last.start(1))


def _unexpected(path: Path, state: int, keyword: str, line: int) -> LoadError:
    if keyword == "vertex" and state == _LOOP_END:
        return LoadError(path, "a facet of more than 3 vertices: STL facets are triangles", line=line)
    if keyword == "endloop" and state in (_LOOP, _SECOND, _THIRD):
        return LoadError(path, f"a facet of {state - _LOOP} vertices: STL facets are triangles", line=line)
    return LoadError(path, f"expected {_EXPECTED[state]}, found '{shortened(keyword)}'", line=line)
