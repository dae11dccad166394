"""`marraztu bench`: how fast the viewer loads, draws and starts, beside the bare minimum and its peers.

Every figure is measured in the same run as the figure it is compared with, on inputs generated
here (seeded, written to a temporary folder), and printed as Markdown tables. One module per
section: loading.py, frames.py (with the CPU per frame), start.py, memory.py, shapes.py, window.py. Progress goes to
stderr, the tables to stdout. Nothing heavy is imported at module level: the loading workers import
these modules, and their memory baseline should hold only what their loader needs.
"""

from __future__ import annotations

import sys
import tempfile
import time
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path

from marraztu.devtools.bench.config import config_from_args
from marraztu.devtools.bench.frames import FrameBench, cpu_section, frames_section
from marraztu.devtools.bench.inputs import generate_format_inputs, generate_load_inputs, generate_materials_input
from marraztu.devtools.bench.loading import loading_section, pause_section
from marraztu.devtools.bench.memory import MATERIALS, memory_section
from marraztu.devtools.bench.report import emit, load_average, machine_lines
from marraztu.devtools.bench.shapes import shapes_section
from marraztu.devtools.bench.start import start_section
from marraztu.devtools.bench.window import window_section


def _open_gl(required: bool) -> FrameBench | None:
    """The GL context; without one, only the sections that need none run (the header says so)."""
    from marraztu.errors import ViewerError

    try:
        return FrameBench.open()
    except ViewerError:
        if required:
            raise
        return None


@contextmanager
def _work_directory(chosen: Path | None) -> Iterator[Path]:
    if chosen is not None:
        try:
            chosen.mkdir(parents=True, exist_ok=True)
        except OSError as error:
            raise SystemExit(f"error: --workdir {chosen}: {error.strerror or error}") from None
        yield chosen
        return
    with tempfile.TemporaryDirectory(prefix="marraztu-bench-") as temporary:
        yield Path(temporary)


def main(argv: Sequence[str]) -> int:
    config = config_from_args(argv)
    started = time.perf_counter()
    needs_gl = any(section in config.sections for section in ("frames", "cpu", "memory"))
    bench = _open_gl(required=needs_gl)
    try:
        emit(["# marraztu bench", "", *machine_lines(bench.ctx if bench else None, config)])
        with _work_directory(config.workdir) as directory:
            inputs = []
            if any(section in config.sections for section in ("load", "memory", "window")):
                inputs = generate_load_inputs(directory, *config.load_sizes)
            if "load" in config.sections:
                emit(loading_section(config, inputs + generate_format_inputs(directory, *config.load_sizes)))
                emit(pause_section(config, inputs[1]))
            if bench is not None and "frames" in config.sections:
                emit(frames_section(bench, config))
            if bench is not None and "cpu" in config.sections:
                emit(cpu_section(bench, config))
            if "start" in config.sections:
                emit(start_section(config, directory))
            if bench is not None and "memory" in config.sections:
                several = generate_materials_input(directory, config.load_sizes[1], MATERIALS)
                emit(memory_section(bench, inputs, several))
            if "shapes" in config.sections:
                emit(shapes_section(config, directory))
            if "window" in config.sections:
                emit(window_section(config, inputs))
    finally:
        if bench is not None:
            bench.release()
    emit([f"Bench took {time.perf_counter() - started:.0f} s; load average at the end: {load_average()}."])
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
