"""Numbers read from a text file's words many at a time, each checked, the first bad one named by its line.

numpy turns a list of words into numbers in one call, where float() or int() would be a call a word;
only where that fails, or a value is out of range, are the words looked at one by one, to find the
first bad one and its line.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

import numpy as np

from marraztu.errors import LoadError
from marraztu.model.geometry import FLOAT32_MAX, holds_in_float32

LineOf = Callable[[int], int]  # the line of the word at this index
# A header's count longer than this is no count of anything a 1 GiB file holds (and int() refuses
# thousands of digits with a ValueError).
MAX_COUNT_DIGITS = 12

_DECIMAL = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
_WHOLE = re.compile(r"[-+]?\d+")


def checked_coordinates(path: Path, words: list[str], line_of: LineOf) -> np.ndarray:
    """float64 coordinates, each a decimal number within float32's range (the GPU's)."""
    values = _converted(path, words, line_of, np.float64, _DECIMAL)
    if not holds_in_float32(values):
        held = np.abs(values) <= FLOAT32_MAX  # NaN too is not
        raise LoadError(path, "a vertex coordinate is not a finite number the GPU can hold",
                        line=line_of(int(np.argmin(held))))
    return values


def checked_indices(path: Path, words: list[str], line_of: LineOf, vertices: int) -> np.ndarray:
    """int64 vertex indices, each a whole number from 0 to vertices - 1."""
    if any(len(word) > 18 for word in words):  # numpy raises OverflowError past int64's 18 digits
        words = [_trimmed(word) for word in words]
        at = next((at for at, word in enumerate(words) if len(word.lstrip("+-")) > 18 and _WHOLE.fullmatch(word)),
                  None)
        if at is not None:
            raise LoadError(path, f"vertex index {words[at][:40]} out of range (the file has {vertices} vertices)",
                            line=line_of(at))
    values = _converted(path, words, line_of, np.int64, _WHOLE)
    outside = (values < 0) | (values >= vertices)
    if outside.any():
        at = int(np.argmax(outside))
        raise LoadError(path, f"vertex index {values[at]} out of range (the file has {vertices} vertices)",
                        line=line_of(at))
    return values


def _trimmed(word: str) -> str:
    """A whole number's word without its leading zeros ('-0000000000000000000002' is '-2'); others as they are."""
    if not _WHOLE.fullmatch(word):
        return word
    digits = word.lstrip("+-")
    return word[:len(word) - len(digits)] + (digits.lstrip("0") or "0")


def _converted(path: Path, words: list[str], line_of: LineOf, kind: type, syntax: re.Pattern[str]) -> np.ndarray:
    try:
        values = np.array(words, dtype=kind)
    except ValueError:
        values = None
    if values is None or "_" in "".join(words):  # float() and int() read 1_000 too
        at = next((at for at, word in enumerate(words) if not syntax.fullmatch(word)), 0)
        wanted = "a number" if kind is np.float64 else "a whole number"
        raise LoadError(path, f"'{words[at][:40]}' is not {wanted}", line=line_of(at))
    return values
