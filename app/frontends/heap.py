"""Gives back to the system the memory the C library keeps after the arrays of a load or an upload
are freed.

glibc keeps freed blocks of up to a few tens of megabytes for reuse instead of returning them, so
after a large model is loaded and drawn the process stays larger than what it holds.
`malloc_trim` returns them, quickly enough to run each time the window goes still. Where the C
library is not glibc, nothing is done.
"""

from __future__ import annotations

import ctypes
import sys
from collections.abc import Callable
from functools import cache


@cache
def _malloc_trim() -> Callable[[int], int] | None:
    if not sys.platform.startswith("linux"):
        return None
    try:
        return ctypes.CDLL("libc.so.6").malloc_trim
    except (OSError, AttributeError):  # another C library (musl): no such function
        return None


def return_freed_memory() -> bool:
    """Whether there was a C library to ask."""
    trim = _malloc_trim()
    if trim is None:
        return False
    trim(0)
    return True
