"""Reading a file a person named: regular files only, of a bounded size, every failure a LoadError.

Shared by the OBJ, image and scene readers so that none of them can be handed /dev/zero or a named
pipe (which Path.read_bytes() would read forever or block on).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path
from typing import BinaryIO

from app.errors import LoadError

MAX_FILE_BYTES = 1 << 30


def regular_file_size(path: str | Path) -> int:
    """The size of a regular file, or a LoadError naming it (without a line).

    Directories, devices (/dev/zero never ends) and named pipes (opening one blocks until someone
    writes) are refused from their metadata, before anything is opened.
    """
    try:
        info = os.stat(path)
    except FileNotFoundError:
        raise LoadError(path, "no such file") from None
    except PermissionError:
        raise LoadError(path, "permission denied") from None
    except (OSError, ValueError) as error:
        raise LoadError(path, f"cannot read the file ({getattr(error, 'strerror', None) or error})") from None
    if stat.S_ISDIR(info.st_mode):
        raise LoadError(path, "is a directory, not a file")
    if not stat.S_ISREG(info.st_mode):
        raise LoadError(path, "not a regular file (a device or a named pipe?)")
    return info.st_size


def read_file(path: str | Path, limit: int = MAX_FILE_BYTES) -> bytes:
    """All bytes of a regular file of at most `limit` bytes, or a LoadError naming it."""
    size = regular_file_size(path)
    if size > limit:
        raise LoadError(path, f"file too large (more than {limit >> 20} MiB)")
    try:
        with open(path, "rb") as stream:
            data = _read_up_to(stream, size, limit)
    except PermissionError:
        raise LoadError(path, "permission denied") from None
    except MemoryError:
        raise LoadError(path, "file too large to load") from None
    except OSError as error:
        raise LoadError(path, f"cannot read the file ({error.strerror or error})") from None
    if len(data) > limit:
        raise LoadError(path, f"file too large (more than {limit >> 20} MiB)")
    return data


def _read_up_to(stream: BinaryIO, expected: int, limit: int) -> bytes:
    """The stream's bytes, at most limit + 1 of them.

    read(n) reserves n bytes at once, so ask for the size stat gave (and one more, to notice a file
    that grew meanwhile), never for the limit.
    """
    pieces = [stream.read(expected + 1)]
    total = len(pieces[0])
    while total > expected and total <= limit:
        piece = stream.read(min(1 << 24, limit + 1 - total))
        if not piece:
            break
        pieces.append(piece)
        total += len(piece)
    return b"".join(pieces) if len(pieces) > 1 else pieces[0]
