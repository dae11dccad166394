"""Work in pieces on several threads at once: numba's compiled code and numpy's gathers and arithmetic
run without the GIL, so pieces of one large table are worked on together."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from typing import TypeVar

import numpy as np

_Item = TypeVar("_Item")
_Result = TypeVar("_Result")


def usable_cores() -> int:
    """The cores this process may run on: a container's or taskset's share where the system tells."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


# The OBJ reader's passes were measured still getting quicker from 8 to 16 threads on 16 cores.
THREADS = max(1, min(16, usable_cores()))


def each(work: Callable[[_Item], _Result], items: Sequence[_Item], threads: int | None = None) -> list[_Result]:
    """[work(item) for item in items], on up to `threads` threads (THREADS unless given); the first
    exception is raised. numpy's error state is per thread: `work` sets its own."""
    threads = THREADS if threads is None else threads
    if len(items) < 2 or threads < 2:
        return [work(item) for item in items]
    with ThreadPoolExecutor(max_workers=min(threads, len(items)), thread_name_prefix="marraztu-piece") as pool:
        return list(pool.map(work, items))


def pieces(count: int, size: int) -> list[slice]:
    """Rows 0..count in slices of `size` rows, the last shorter."""
    return [slice(low, min(low + size, count)) for low in range(0, count, size)]


def converted(table: np.ndarray, dtype: type) -> np.ndarray:
    """table.astype(dtype), C-ordered, converted in pieces of rows on threads."""
    out = np.empty(table.shape, dtype)

    def piece(rows: slice) -> None:
        out[rows] = table[rows]

    each(piece, pieces(table.shape[0], 1 << 16))
    return out
