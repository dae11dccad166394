"""Numbers read from a text file's words many at a time, each checked, the first bad one named by its line.

numpy turns a list of words into numbers in one call, where float() or int() would be a call a word;
only where that fails, or a value is out of range, are the words looked at one by one, to find the
first bad one and its line.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np

from marraztu.errors import SHOWN_WHOLE, LoadError, shortened
from marraztu.loaders.patterns import compiled
from marraztu.model.geometry import FLOAT32_MAX, holds_in_float32

LineOf = Callable[[int], int]  # the line of the word at this index
# A header's count longer than this is no count of anything a 1 GiB file holds (and int() refuses
# thousands of digits with a ValueError).
MAX_COUNT_DIGITS = 12
# A decimal number as float() reads it, but in ASCII digits only (float() also takes '٣' for 3).
# Possessive: "[0-9]+\.?[0-9]*" could split a run of digits two ways, so a long run that ends badly
# was tried at every split (a 20,000-digit word took 8 s); no part of a number gives back digits.
DECIMAL_SYNTAX = r"[+-]?+(?:[0-9]++(?:\.[0-9]*+)?+|\.[0-9]++)(?:[eE][+-]?+[0-9]++)?+"
ROWS_AT_ONCE = 1 << 15  # rows whose words are made numbers in one call

DECIMAL = compiled(DECIMAL_SYNTAX)  # fullmatch: one decimal number in ASCII digits
DECIMAL_BYTES = compiled(DECIMAL_SYNTAX.encode())
# What bytes.split() and numpy's fromstring part numbers at.
BLANKS = b" \t\n\r\x0b\x0c"  # what numpy's and bytes.split()'s words are parted by
WHITESPACE = np.zeros(256, bool)
WHITESPACE[list(BLANKS)] = True
_PIECE_BYTES = 1 << 20  # a text looked at word by word a piece at a time: its temporaries stay small
_WHOLE = re.compile(r"[+-]?[0-9]+")
_COUNT = re.compile(r"[0-9]+")


class WordBlocks:
    """Rows of words gathered as a file is read, and made numbers a block of rows at a time by
    `convert` (checked_coordinates, say), which names a bad word's line: never a list of every word."""

    def __init__(self, path: Path, convert: Callable[[Path, list[str], LineOf], np.ndarray]) -> None:
        self.path, self.convert = path, convert
        self.blocks: list[np.ndarray] = []
        self.size_blocks: list[np.ndarray] = []
        self.words: list[str] = []
        self.lines: list[int] = []
        self.sizes: list[int] = []

    def add(self, words: list[str], line: int) -> None:
        self.words += words
        self.lines.append(line)
        self.sizes.append(len(words))
        if len(self.lines) == ROWS_AT_ONCE:
            self._convert()

    def values(self) -> np.ndarray:
        """Every row's numbers, one after the other."""
        self._convert()
        return np.concatenate(self.blocks)

    def row_sizes(self) -> np.ndarray:
        """How many numbers each row gave (after values())."""
        return np.concatenate(self.size_blocks)

    def _convert(self) -> None:
        ends = np.cumsum(self.sizes, dtype=np.int64)
        lines = self.lines
        self.blocks.append(self.convert(self.path, self.words,
                                        lambda at: lines[int(np.searchsorted(ends, at, side="right"))]))
        self.size_blocks.append(np.array(self.sizes, np.int64))
        self.words, self.lines, self.sizes = [], [], []


def checked_coordinates(path: Path, words: list[str], line_of: LineOf) -> np.ndarray:
    """float64 coordinates, each a decimal number within float32's range (the GPU's)."""
    values = _converted(path, words, line_of, np.float64, DECIMAL)
    if not holds_in_float32(values):
        held = np.abs(values) <= FLOAT32_MAX  # NaN too is not
        raise unheld_coordinate(path, line_of(int(np.argmin(held))))
    return values


def checked_numbers(path: Path, words: list[str], line_of: LineOf) -> np.ndarray:
    """float64 numbers, each a finite decimal number (numpy reads 'nan', 'inf' and 1e400 too: refused)."""
    values = _converted(path, words, line_of, np.float64, DECIMAL)
    finite = np.isfinite(values)
    if not finite.all():
        at = int(np.argmin(finite))
        raise LoadError(path, f"'{shortened(words[at])}' is not a finite number", line=line_of(at))
    return values


def unheld_coordinate(path: str | Path, line: int | None = None) -> LoadError:
    """The error of a model whose coordinates the GPU cannot hold (not finite, or past float32's range)."""
    return LoadError(path, "a vertex coordinate is not a finite number the GPU can hold", line=line)


def checked_indices(path: Path, words: list[str], line_of: LineOf, vertices: int) -> np.ndarray:
    """int64 vertex indices, each a whole number from 0 to vertices - 1."""
    out_of_range = f"vertex index {{}} out of range (the file has {vertices} vertices)"
    values = _converted(path, words, line_of, np.int64, _WHOLE, out_of_range)
    outside = (values < 0) | (values >= vertices)
    if outside.any():
        at = int(np.argmax(outside))
        raise LoadError(path, out_of_range.format(values[at]), line=line_of(at))
    return values


def said_count(words: list[str], most: int) -> str:
    """How many words a line held, from its split into at most `most` + 1: exactly, up to `most`."""
    return str(len(words)) if len(words) <= most else f"more than {most}"


def shortened_bytes(word: bytes, shown: Callable[[bytes], str] = repr, most: int = SHOWN_WHOLE) -> str:
    """A word of bytes as a message shows it, made text by `shown`; where longer than `most` bytes, its first
    ones and how many bytes it is: only those are made text, never a long word whole (repr writes 4 a byte)."""
    if len(word) <= most:
        return shown(word)
    return f"{shown(word[:most])}... ({len(word)} bytes)"


def outruns(rows: int, least: int, held: int) -> bool:
    """Whether `rows` rows of at least `least` bytes each need more than the `held` bytes a file has for
    them: a header's counts checked before anything is made by them (billions of rows counted in a file
    of a few lines)."""
    return rows * least > held


def is_count(word: str) -> bool:
    """A header's count: ASCII digits ('٣'.isdigit() too is true), no more than MAX_COUNT_DIGITS."""
    return len(word) <= MAX_COUNT_DIGITS and _COUNT.fullmatch(word) is not None


def _converted(path: Path, words: list[str], line_of: LineOf, kind: type, syntax: re.Pattern[str],
               out_of_range: str = "{} out of range") -> np.ndarray:
    """The words as `kind`, or the LoadError of the first, in file order, that is not one: not of
    `syntax`, or (int64) a whole number past it (numpy's OverflowError), worded by `out_of_range`."""
    try:
        values = np.array(words, dtype=kind)
    except (ValueError, OverflowError):  # or int()'s cap of 4,300 digits, leading zeros too
        values = _wholes_without_leading_zeros(words) if kind is np.int64 else None
    joined = "".join(words)
    if values is not None and "_" not in joined and joined.isascii():  # float() and int() read 1_000 and '٣' too
        return values
    whole = kind is np.int64
    at, word = next(((at, word) for at, word in enumerate(words)
                     if not syntax.fullmatch(word) or (whole and _past_int64(word))), (0, words[0]))
    if syntax.fullmatch(word):
        raise LoadError(path, out_of_range.format(shortened(word)), line=line_of(at))
    wanted = "a number" if kind is np.float64 else "a whole number"
    raise LoadError(path, f"'{shortened(word)}' is not {wanted}", line=line_of(at))


def _wholes_without_leading_zeros(words: list[str]) -> np.ndarray | None:
    """The words as int64 where each is a whole number within its range, however many zeros lead it;
    None otherwise."""
    if not all(_WHOLE.fullmatch(word) and not _past_int64(word) for word in words):
        return None
    return np.array([_without_leading_zeros(word) for word in words], dtype=np.int64)


def _without_leading_zeros(word: str) -> str:
    digits = word.lstrip("+-")
    return word[:len(word) - len(digits)] + (digits.lstrip("0") or "0")


def _past_int64(word: str) -> bool:
    """A whole number of more than 18 significant digits ('-0000000000000000000002' is not one)."""
    return _WHOLE.fullmatch(word) is not None and len(word.lstrip("+-").lstrip("0")) > 18


def text_numbers(text: bytes, kind: type = np.float64) -> np.ndarray:
    """Every number of a text of numbers, in order, as `kind`, in one numpy call; ValueError where a
    word is none (numpy before 2.3 warned, and stopped there). Some numpy versions stop at a NUL byte
    without a word: callers count the words too. As int64, a number past its range is read as its
    largest."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", DeprecationWarning)
        try:
            return np.fromstring(text, dtype=kind, sep=" ")
        except DeprecationWarning:
            raise ValueError("not a number") from None


def pieces_at_gaps(data: bytes, start: int, piece_bytes: int = _PIECE_BYTES, end: int | None = None
                   ) -> Iterator[tuple[int, int]]:
    """(start, stop) of pieces of about `piece_bytes` from `start` to `end` (the text's end unless given),
    each ending at a blank."""
    end = len(data) if end is None else end
    while start < end:
        gap = _GAP.search(data, start + piece_bytes, end)
        stop = end if gap is None else gap.end()
        yield start, stop
        start = stop


_GAP = re.compile(rb"\s")


def word_starts(blank: np.ndarray) -> np.ndarray:
    """Where each word begins in a text whose blank bytes are `blank` (WHITESPACE of its bytes)."""
    return np.flatnonzero(~blank & np.concatenate(([True], blank[:-1])))


def line_end_places(piece: np.ndarray) -> np.ndarray:
    """Where a piece of text (uint8) holds a line end, \\n or \\r (a CRLF's two count apart)."""
    return np.flatnonzero((piece == ord("\n")) | (piece == ord("\r")))


def words_and_line_ends(piece: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """Where each word of a piece of text (uint8) begins, how many line ends (\\n or \\r) come before
    it, and how many the piece holds: a few numbers per word and line end, never one per byte."""
    words = word_starts(WHITESPACE[piece])
    line_ends = line_end_places(piece)
    return words, np.searchsorted(line_ends, words), line_ends.size


def line_words(data: bytes, start: int, most: int) -> tuple[np.ndarray, np.ndarray]:
    """For each line from `start` on that holds a word, up to `most` of them: how many it holds, and
    where its first begins. A line ends at \\n or \\r (\\r\\n leaves an empty line between, which
    holds none). Worked out a piece at a time, a few numbers per word and line: never one per byte."""
    counts: list[np.ndarray] = []
    firsts: list[np.ndarray] = []
    offset_type = np.int32 if len(data) < 1 << 30 else np.int64  # an offset plus a little stays an int32
    lines_before, last_line, found = 0, -1, 0  # lines ended before the piece; the line of the last word seen
    for low, high in pieces_at_gaps(data, start, _WORDS_PIECE_BYTES):  # no word spans two pieces
        words, ends_before, ends = words_and_line_ends(np.frombuffer(data, np.uint8, count=high - low, offset=low))
        line_of_word = ends_before + lines_before
        lines_before += ends
        new_line = np.flatnonzero(np.diff(line_of_word, prepend=last_line) != 0)
        going_on = int(new_line[0]) if new_line.size else words.size  # words on the last piece's last line
        if going_on:
            next(run for run in reversed(counts) if run.size)[-1] += going_on
        if new_line.size:
            counts.append(np.diff(np.append(new_line, words.size)).astype(np.int32))
            firsts.append((words[new_line] + low).astype(offset_type))
            last_line = int(line_of_word[-1])
            found += new_line.size
            if found > most:  # the lines after the last wanted one's end are not looked at
                break
    if not counts:
        return np.zeros(0, np.int32), np.zeros(0, offset_type)
    return np.concatenate(counts)[:most], np.concatenate(firsts)[:most]


_WORDS_PIECE_BYTES = 1 << 18  # line_words's pieces: a few megabytes of temporaries at most
