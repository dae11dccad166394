"""The errors a person sees: each names the file and, for a parse error, the line."""

from __future__ import annotations

import os
import sys
from pathlib import Path


def escaped(text: str) -> str:
    """The text with control characters written as escapes (\\n, \\x1b, \\u202e): a file name must not
    move the cursor, set a terminal's title or start a line of its own."""
    if text.isprintable():
        return text
    return "".join(char if char.isprintable() or char == " " else repr(char)[1:-1] for char in text)


SHOWN_WHOLE = 40  # a word a message quotes (from a file, the command line, the API) is shown whole up to this long


def shortened(word: str, most: int = SHOWN_WHOLE) -> str:
    """A word as a message shows it: where longer than `most` characters, its first ones and how long it is
    ("..." in ASCII: the window's font has no other)."""
    if len(word) <= most:
        return word
    digits = word.lstrip("+-")
    length = f"{len(digits)} digits" if digits.isascii() and digits.isdecimal() else f"{len(word)} characters"
    return f"{word[:most]}... ({length})"


def say(text: str) -> bool:
    """What a command made, as a line on standard output; False where its reader has gone (`marraztu ...
    | head`: it has what it wanted), a full output a ViewerError: never a traceback."""
    try:
        print(text, flush=True)
    except BrokenPipeError:
        _forget_standard_output()
        return False
    except OSError as error:
        _forget_standard_output()
        raise ViewerError(f"cannot write to standard output ({error.strerror or error})") from None
    return True


def first_line(error: BaseException) -> str:
    """A library's error in a line of ours: the first line of its words, or its kind where it has none."""
    return (str(error).strip().splitlines() or [type(error).__name__])[0]


def error_words(error: BaseException, most: int = 160) -> str:
    """An error no check foresaw, in a line of ours: its kind, and the first line of its words, cut."""
    words = str(error).strip().splitlines()
    return f"{type(error).__name__}: {words[0][:most]}" if words else type(error).__name__


def _forget_standard_output() -> None:
    """What is left in the buffer goes nowhere: Python's own flush at exit would fail again, a second
    message and exit status 120 where standard output is buffered (a file or a pipe, as a person's is)."""
    os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())


class ViewerError(Exception):
    """Anything the person must be told about in one line; never a programming error."""

    def __str__(self) -> str:
        return escaped(super().__str__())


class LoadError(ViewerError):
    """A file could not be read: missing, unreadable, malformed, or describing impossible data."""

    def __init__(self, path: str | Path, message: str, line: int | None = None) -> None:
        self.path = str(path)
        self.line = line
        self.message = message
        super().__init__(str(self))

    def __str__(self) -> str:
        where = _cut_middle(self.path) if self.line is None else f"{_cut_middle(self.path)}:{self.line}"
        return escaped(f"{where}: {self.message}")


# A path a message shows whole; a longer one (a name a hostile file gives) is cut, its start and end kept.
_LONGEST_SHOWN_PATH = 1024


def _cut_middle(path: str) -> str:
    """The path as a message shows it: a long one cut in the middle, its folder and name kept."""
    if len(path) <= _LONGEST_SHOWN_PATH:
        return path
    half = _LONGEST_SHOWN_PATH // 2 - 2
    return f"{path[:half]}...{path[-half:]}"


class KeyMapError(ViewerError):
    """The key table or a key sequence given on the command line is wrong."""
