"""3. Start: process start to the screenshot's PNG, beside a process that only opens an EGL context."""

from __future__ import annotations

import compileall
import statistics
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import marraztu
from marraztu.devtools.bench.config import BenchConfig
from marraztu.devtools.bench.inputs import SEED, cells_for_triangles, grid_triangles, wavy_surface, write_obj
from marraztu.devtools.bench.report import markdown_table, number, progress, ratio
from marraztu.loaders.obj import COMPILED_READER_BYTES

START_HEADERS = ("process", "to PNG written s", "PNG ÷ bare EGL", "to exit s", "exit ÷ bare EGL", "runs")


BARE_EGL_CODE = "import numpy, moderngl; moderngl.create_standalone_context(backend='egl').release()"
# The screenshot command with the compiled OBJ reader's bound lowered to nothing: the model goes to it.
BY_COMPILED_READER_CODE = ("import sys; import marraztu.loaders.obj as obj; obj.COMPILED_READER_BYTES = 0; "
                           "from marraztu.cli import main; sys.exit(main())")
BOUND_MODEL = "bound.obj"


@dataclass(frozen=True)
class StartCommand:
    label: str
    argv: tuple[str, ...]  # `{png}` stands for the output file, `{model}` for bound_model's
    writes_png: bool


BARE_EGL = StartCommand("bare: import numpy, moderngl; open an EGL context", ("-c", BARE_EGL_CODE), False)
BY_COMPILED_READER = StartCommand("the same grid through the compiled reader (its bound lowered in that process: numba "
                                  "imported and its code loaded while the file is read)",
                                  ("-c", BY_COMPILED_READER_CODE, "screenshot", "-o", "{png}", "--empty", "{model}"),
                                  True)
START_COMMANDS = (
    StartCommand("`python -m marraztu screenshot -o X.png` (built-in scene, 800x800)",
                 ("-m", "marraztu", "screenshot", "-o", "{png}"), True),
    StartCommand("the same with `--empty` and a grid of `v` and `f` lines just under the size from which the compiled "
                 "OBJ reader is loaded: read by lines",
                 ("-m", "marraztu", "screenshot", "-o", "{png}", "--empty", "{model}"), True),
    BY_COMPILED_READER,
    BARE_EGL,
    StartCommand("python -c pass", ("-c", "pass"), False),
)


def bound_model(directory: Path) -> Path:
    """A grid of `v` and `f` lines only, the line reader's slowest text per byte, just under
    COMPILED_READER_BYTES."""
    path = directory / BOUND_MODEL
    cells = cells_for_triangles(COMPILED_READER_BYTES // 38)  # such a file's bytes per triangle, about
    write_obj(path, wavy_surface(cells, SEED), grid_triangles(cells), uv_and_normals=False)
    assert 0.9 * COMPILED_READER_BYTES < path.stat().st_size < COMPILED_READER_BYTES, path.stat().st_size
    return path


def time_start(command: StartCommand, png: Path, model: Path) -> tuple[float | None, float]:
    """Seconds from spawning to the PNG's last write (its mtime, as coarse as the file system's clock)
    and to the exit."""
    png.unlink(missing_ok=True)
    argv = [sys.executable, *(part.replace("{png}", str(png)).replace("{model}", str(model)) for part in command.argv)]
    wall_start_ns = time.time_ns()
    start = time.perf_counter()
    done = subprocess.run(argv, capture_output=True, text=True)
    exit_s = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(argv)} failed:\n{done.stderr.strip()}")
    png_s = (png.stat().st_mtime_ns - wall_start_ns) / 1e9 if command.writes_png else None
    return png_s, exit_s


def start_section(config: BenchConfig, directory: Path) -> list[str]:
    png = directory / "start.png"
    # The bare process imports numpy and moderngl from the byte code pip compiled when it installed
    # them; ours is an editable install, which compiles nothing, and where PYTHONDONTWRITEBYTECODE is
    # set no run ever writes it. Compiling first, as a regular install would, keeps the comparison
    # about starting rather than about compiling our modules.
    compileall.compile_dir(str(Path(marraztu.__file__).parent), quiet=1)
    model = bound_model(directory)
    time_start(BY_COMPILED_READER, png, model)  # numba's cache filled: the rounds load its code, never compile it
    runs: dict[str, list[tuple[float | None, float]]] = {c.label: [] for c in START_COMMANDS}
    for run in range(config.start_runs):  # rounds, so every command sees the same background load
        for command in START_COMMANDS:
            progress(f"start: {command.label} (run {run + 1})")
            runs[command.label].append(time_start(command, png, model))
    bare_exit = statistics.median(exit_s for _, exit_s in runs[BARE_EGL.label])
    rows = []
    for command in START_COMMANDS:
        png_times = [png_s for png_s, _ in runs[command.label] if png_s is not None]
        exit_s = statistics.median(exit_s for _, exit_s in runs[command.label])
        png_s = statistics.median(png_times) if png_times else None
        rows.append([command.label, number(png_s), ratio(png_s, bare_exit),
                     number(exit_s), ratio(exit_s, bare_exit), str(config.start_runs)])
    return [
        "## 3. Start: process start to the first PNG",
        "",
        f"Median of {config.start_runs} run(s), interleaved. *to PNG written* is the PNG's mtime minus "
        "the spawn time, compared with the bare process's exit (it has no PNG); "
        "*to exit* adds the interpreter's tear-down.",
        "",
        *markdown_table(START_HEADERS, rows),
    ]
