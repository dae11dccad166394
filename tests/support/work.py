"""Measuring work instead of time: how many lines the OBJ line reader read, and peak traced memory.

A busy machine makes seconds meaningless; a count of Python lines or traced bytes is the same on any.
"""

from __future__ import annotations

import gc
import sys
import tracemalloc
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from types import FrameType
from typing import Any, TypeVar

import numpy as np

from marraztu.errors import LoadError
from marraztu.loaders.obj import lines as line_reader
from marraztu.model import threads

Result = TypeVar("Result")


@dataclass
class LineCount:
    lines: int = 0


@contextmanager
def lines_read_by_python() -> Iterator[LineCount]:
    """Counts the lines the Python side reads inside the block: each goes through the line reader's
    `statement`, or, a plain row the compiled code left for its long numbers, into the fast reader's
    batches (fast.read_plain_batch)."""
    from marraztu.loaders.obj import fast  # imports numba: only where a test counts

    count = LineCount()
    original, original_batch = line_reader.statement, fast.read_plain_batch

    def counted(content: bytes) -> tuple[bytes, bytes]:
        count.lines += 1  # threads may race here; the GIL makes the loss at most a line or two
        return original(content)

    def counted_batch(*args: Any) -> np.ndarray:
        kept = original_batch(*args)
        count.lines += len(kept)
        return kept

    line_reader.statement = counted  # type: ignore[assignment]
    fast.read_plain_batch = counted_batch  # type: ignore[assignment]
    try:
        yield count
    finally:
        line_reader.statement = original  # type: ignore[assignment]
        fast.read_plain_batch = original_batch  # type: ignore[assignment]


def peak_traced_bytes(work: Callable[[], Result]) -> tuple[Result | LoadError, int]:
    """(work's result or the LoadError it raised, the peak of memory traced while it ran, beyond the start).

    numpy reports its arrays to tracemalloc, so this counts the readers' arrays as well as Python objects.
    The model's own pieces (marraztu.model.threads) are worked on in one thread meanwhile, so that the
    peak does not depend on whose temporaries happen to meet; the readers' threads are left as set."""
    gc.collect()
    saved_threads = threads.THREADS
    threads.THREADS = 1
    tracemalloc.start()
    try:
        baseline = tracemalloc.get_traced_memory()[0]
        try:
            outcome: Result | LoadError = work()
        except LoadError as error:  # the caller decides whether an error was the outcome wanted
            outcome = error
        peak = tracemalloc.get_traced_memory()[1] - baseline
    finally:
        tracemalloc.stop()
        threads.THREADS = saved_threads
    return outcome, peak


def python_lines_run(action: Callable[[], object], module: str) -> int:
    """How many lines of `module`'s source Python runs in `action`: work counted, not timed."""
    count = 0

    def tracer(frame: FrameType, event: str, arg: object) -> Callable | None:
        if frame.f_code.co_filename != module:
            return None
        return counting

    def counting(frame: FrameType, event: str, arg: object) -> Callable:
        nonlocal count
        count += event == "line"
        return counting

    _run_hooked(sys.settrace, sys.gettrace(), tracer, action)
    return count


def calls_made(action: Callable[[], object]) -> int:
    """How many Python and C functions `action` calls: work counted, not timed, so a busy machine cannot fail it."""
    count = 0

    def profile(frame: object, event: str, arg: object) -> None:
        nonlocal count
        if event in ("call", "c_call"):
            count += 1

    _run_hooked(sys.setprofile, sys.getprofile(), profile, action)
    return count


def _run_hooked(install: Callable[[Any], None], previous: Any, hook: Any, action: Callable[[], object]) -> None:
    """`action` run with the interpreter's trace or profile hook set to `hook`, `previous` put back after."""
    install(hook)
    try:
        action()
    finally:
        install(previous)
