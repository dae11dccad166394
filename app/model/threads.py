"""Work in pieces on several threads at once: numba's compiled code and numpy's gathers and arithmetic
run without the GIL, so pieces of one large table are worked on together."""

from __future__ import annotations

import os
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor, wait
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
    """[work(item) for item in items], on up to `threads` threads (THREADS unless given), every item
    done before it returns; the first exception, in the items' order, is raised. numpy's error state is
    per thread: `work` sets its own. Called from one of its own threads, it works in that thread."""
    threads = THREADS if threads is None else threads
    if len(items) < 2 or threads < 2 or threading.current_thread().name.startswith(_PREFIX):
        return [work(item) for item in items]
    if threads != THREADS:  # a count of its own (tests): a pool of its own
        with ThreadPoolExecutor(max_workers=min(threads, len(items)), thread_name_prefix=_PREFIX) as pool:
            return list(pool.map(work, items))
    futures = [_shared_pool().submit(work, item) for item in items]
    wait(futures)
    return [future.result() for future in futures]


_PREFIX = "marraztu-piece"
_pool: ThreadPoolExecutor | None = None
_pool_lock = threading.Lock()


def _shared_pool() -> ThreadPoolExecutor:
    """One pool for the process: on a 16-core host, starting 16 threads anew for each table took
    longer than some tables' work."""
    global _pool
    with _pool_lock:
        if _pool is None:
            _pool = ThreadPoolExecutor(max_workers=THREADS, thread_name_prefix=_PREFIX)
        return _pool


def _forget_pool() -> None:  # a forked child has none of its parent's threads
    global _pool
    _pool = None


if hasattr(os, "register_at_fork"):
    os.register_at_fork(after_in_child=_forget_pool)


# Rows per piece of a table worked on row by row: each piece's gathers and copies stay in the CPU's cache.
ROWS_PER_PIECE = 1 << 16


def pieces(count: int, size: int | None = None) -> list[slice]:
    """Rows 0..count in slices of `size` rows (ROWS_PER_PIECE unless given), the last shorter."""
    size = ROWS_PER_PIECE if size is None else size
    return [slice(low, min(low + size, count)) for low in range(0, count, size)]


def weighed_pieces(weights: np.ndarray, size: int) -> list[slice]:
    """Rows 0..len(weights), each weighing more than 0, in slices of about `size` in weight; a row that
    weighs more, a slice of its own: a slice's work stays bounded however the rows weigh."""
    ends = np.cumsum(weights)
    heavy = np.flatnonzero(weights > size)
    cuts = np.sort(np.concatenate([[0], np.searchsorted(ends, np.arange(size, ends[-1], size), side="right"),
                                   heavy, heavy + 1]))
    # Each cut once, kept as np.unique would but without it: its first call imports numpy.ma, 5 ms of a start.
    cuts = cuts[np.append(True, cuts[1:] != cuts[:-1]) & (cuts < weights.size)].tolist()
    return [slice(low, high) for low, high in zip(cuts, [*cuts[1:], weights.size])]


# Rows a thread takes at least from one_per_thread: a small table is done sooner than a thread is woken.
FEWEST_ROWS_PER_THREAD = 1 << 12
# The same for a pass that does next to nothing a row (a comparison, a maximum): waking a thread took
# longer than such a pass over 200,000 integers.
FEWEST_QUICK_ROWS_PER_THREAD = 1 << 18


def one_per_thread(count: int, quick: bool = False) -> list[slice]:
    """Rows 0..count in at most one slice per thread (THREADS when called), none under
    FEWEST_ROWS_PER_THREAD rows but the last (FEWEST_QUICK_ROWS_PER_THREAD for a `quick` pass over a
    table): for work whose every piece reads all of its input, where more pieces would read it more
    often, or a pass over a table."""
    fewest = FEWEST_QUICK_ROWS_PER_THREAD if quick else FEWEST_ROWS_PER_THREAD
    return pieces(count, max(fewest, -(-count // THREADS)))  # ceil(count / THREADS) rows, or more


def converted(table: np.ndarray, dtype: type) -> np.ndarray:
    """table.astype(dtype), C-ordered, converted in pieces of rows on threads."""
    out = np.empty(table.shape, dtype)

    def piece(rows: slice) -> None:
        out[rows] = table[rows]

    each(piece, pieces(table.shape[0]))
    return out


def arrays_equal(first: np.ndarray, second: np.ndarray) -> bool:
    """np.array_equal(first, second), a piece of rows a thread."""
    if first.shape != second.shape:
        return False
    return all(each(lambda rows: np.array_equal(first[rows], second[rows]),
                    one_per_thread(first.shape[0], quick=True)))


def largest(values: np.ndarray) -> int:
    """The largest of a non-empty array of integers, a piece of rows a thread (integers have no signed
    zero for the pieces to disagree on)."""
    return max(each(lambda rows: int(values[rows].max()), one_per_thread(values.shape[0], quick=True)))


def gathered(table: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """np.take(table, rows, axis=0) of rows in range, a piece of rows a thread."""
    out = np.empty((len(rows), *table.shape[1:]), table.dtype)

    def piece(some: slice) -> None:  # mode="clip" is the mode that writes into `out` unbuffered
        np.take(table, rows[some], axis=0, out=out[some], mode="clip")

    each(piece, pieces(len(rows)))
    return out
