"""`python -m app bench`: how fast the viewer loads, draws and starts, beside the bare minimum.

Every figure is measured in the same run as the figure it is compared with, on inputs generated
here (seeded, written to a temporary folder), and printed as Markdown tables that can be pasted into
the README. Sections:

1. Loading: OBJ file -> GPU-ready vertex arrays (load_obj + app/gpu.py's surface arrays), beside
   trimesh and tinyobjloader. Each (loader, file) runs in a fresh process, so its peak RSS is its own.
2. Frames: GPU-complete frame time of the renderer, still (nothing changed since the frame before,
   so no lighting pass runs) and moving (the camera turns every frame, so every vertex is lit
   again), beside a pass-through program drawing the same vertex data; and the Python CPU time the
   renderer spends per frame on the built-in scene.
3. Start: process start to the screenshot PNG, beside a process that only opens an EGL context.
4. Memory: host and GPU bytes per triangle of a loaded mesh.

Progress goes to stderr, the tables to stdout. Nothing heavy is imported at module level: the loading
workers import this module, and their RSS baseline should hold only what their loader needs.
"""

from __future__ import annotations

import argparse
import compileall
import importlib.util
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from app import PROJECT_ROOT

if TYPE_CHECKING:
    import moderngl

    from app.mesh import Mesh
    from app.renderer import Renderer
    from app.scene import Scene, SceneObject

SEED = 20240611
MEGABYTE = 1 << 20
SECTIONS = ("load", "frames", "cpu", "start", "memory")
LOADERS = ("ours", "trimesh", "tinyobjloader")
MISSING = "—"

# Column headers, shared with tests/test_bench.py so it can find each table.
MACHINE_HEADING = "## Machine"
LOAD_HEADERS = ("file", "triangles", "MB", "loader", "seconds", "of which surface arrays s", "MB/s",
                "peak RSS MB", "time ÷ ours", "RSS ÷ ours")
FRAME_HEADERS = ("scene", "triangles", "size", "mode", "still ms", "moving ms", "bare ms", "still ÷ bare",
                 "moving ÷ bare", "frames")
CPU_HEADERS = ("mode", "program process ms", "program thread ms", "program without draw calls ms",
               "bare process ms", "bare thread ms")
START_HEADERS = ("process", "to PNG written s", "PNG ÷ bare EGL", "to exit s", "exit ÷ bare EGL", "runs")
MEMORY_HEADERS = ("file", "triangles", "Mesh B/tri", "GPU-ready arrays B/tri", "GPU when filled B/tri",
                  "GPU with lines and normals B/tri", "edges B/tri", "normals B/tri")


# --------------------------------------------------------------------------------------------------
# Configuration
# --------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class BenchConfig:
    load_sizes: tuple[int, int]  # triangles of the small v/vt/vn file, and of every large file
    frame_sizes: tuple[int, ...]  # triangles of the generated meshes drawn (besides the built-in scene)
    resolutions: tuple[tuple[int, int], ...]
    frames: int  # measured frames per case, at most
    warmup: int
    frame_budget_s: float  # a case stops early (after MIN_FRAMES) once it has taken this long
    repeats: int  # loads per (loader, file) process
    rounds: int  # processes per (loader, file), the loaders taking turns; the median of all loads is reported
    start_runs: int
    cpu_frames: int
    sections: tuple[str, ...]
    loaders: tuple[str, ...]
    workdir: Path | None = None


DEFAULT_CONFIG = BenchConfig(
    load_sizes=(100_000, 1_000_000), frame_sizes=(100_000, 1_000_000, 5_000_000),
    resolutions=((1280, 720), (1920, 1080)), frames=10, warmup=1, frame_budget_s=5.0, repeats=3, rounds=3,
    start_runs=3, cpu_frames=100, sections=SECTIONS, loaders=LOADERS)
QUICK_CONFIG = replace(
    DEFAULT_CONFIG, load_sizes=(10_000, 50_000), frame_sizes=(20_000,), resolutions=((1280, 720),),
    frames=5, warmup=1, frame_budget_s=1.0, repeats=1, rounds=1, start_runs=1, cpu_frames=30)


def parse_count(text: str) -> int:
    """'100k', '1M', '5m', '2500' -> triangles."""
    multipliers = {"k": 1_000, "m": 1_000_000}
    text = text.strip().lower()
    scale = multipliers.get(text[-1:], 1)
    try:
        value = float(text[:-1] if scale != 1 else text) * scale
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a size: {text!r} (e.g. 100k, 1m, 2500)") from None
    if value < 2:
        raise argparse.ArgumentTypeError(f"size {text!r} is too small: at least 2 triangles")
    return int(value)


def parse_counts(text: str) -> tuple[int, ...]:
    return tuple(parse_count(part) for part in text.split(",") if part.strip())


def parse_resolutions(text: str) -> tuple[tuple[int, int], ...]:
    from app.cli import parse_size

    return tuple(parse_size(part) for part in text.split(",") if part.strip())


def parse_choices(allowed: Sequence[str]) -> Callable[[str], tuple[str, ...]]:
    def parse(text: str) -> tuple[str, ...]:
        chosen = tuple(part.strip() for part in text.split(",") if part.strip())
        unknown = [name for name in chosen if name not in allowed]
        if unknown:
            raise argparse.ArgumentTypeError(f"unknown {', '.join(unknown)}; choose from {', '.join(allowed)}")
        return chosen
    return parse


def bench_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="marraztu bench",
        description="Measure loading, frames, start-up and memory on generated inputs; print Markdown.")
    parser.add_argument("--quick", action="store_true", help="small sizes, one resolution: seconds")
    parser.add_argument("--sizes", type=parse_counts, metavar="LIST",
                        help="triangles of the drawn meshes, e.g. 100k,1m,5m (the default)")
    parser.add_argument("--skip-5m", action="store_true", help="leave out drawn meshes of 5M triangles and more")
    parser.add_argument("--load-sizes", type=parse_counts, metavar="SMALL,LARGE",
                        help="triangles of the small and the large OBJ files (default 100k,1m)")
    parser.add_argument("--resolutions", type=parse_resolutions, metavar="LIST",
                        help="framebuffer sizes, e.g. 1280x720,1920x1080 (the default)")
    parser.add_argument("--frames", type=int, metavar="N", help="measured frames per case (default 10)")
    parser.add_argument("--warmup", type=int, metavar="N", help="frames drawn before measuring (default 1)")
    parser.add_argument("--frame-budget", type=float, metavar="S", dest="frame_budget_s",
                        help="seconds after which a case stops at 3 frames (default 5)")
    parser.add_argument("--repeats", type=int, metavar="N", help="loads per process (default 3)")
    parser.add_argument("--rounds", type=int, metavar="N",
                        help="processes per loader and file, the loaders taking turns (default 3)")
    parser.add_argument("--start-runs", type=int, metavar="N", help="runs of each start command (default 3)")
    parser.add_argument("--cpu-frames", type=int, metavar="N", help="frames timed for CPU per frame (default 100)")
    parser.add_argument("--sections", type=parse_choices(SECTIONS), metavar="LIST",
                        help=f"which sections to run (default all: {','.join(SECTIONS)})")
    parser.add_argument("--loaders", type=parse_choices(LOADERS), metavar="LIST",
                        help=f"loaders compared (default all: {','.join(LOADERS)})")
    parser.add_argument("--workdir", type=Path, metavar="DIR",
                        help="write the generated files here and keep them (default: a temporary folder)")
    return parser


def config_from_args(argv: Sequence[str]) -> BenchConfig:
    parser = bench_parser()
    args = parser.parse_args(list(argv))
    config = QUICK_CONFIG if args.quick else DEFAULT_CONFIG
    overrides = {name: value for name, value in vars(args).items()
                 if name not in ("quick", "skip_5m") and value is not None}
    if "load_sizes" in overrides and len(overrides["load_sizes"]) != 2:
        parser.error("--load-sizes takes two sizes: SMALL,LARGE")
    config = replace(config, **{("frame_sizes" if name == "sizes" else name): value
                                for name, value in overrides.items()})
    if args.skip_5m:
        config = replace(config, frame_sizes=tuple(n for n in config.frame_sizes if n < 5_000_000))
    if min(config.frames, config.repeats, config.rounds, config.start_runs, config.cpu_frames) < 1 \
            or config.warmup < 1:
        parser.error("--frames, --warmup, --repeats, --rounds, --start-runs and --cpu-frames must be at least 1")
    return config


# --------------------------------------------------------------------------------------------------
# Generated inputs: a wavy height field, seeded, as arrays and as OBJ files
# --------------------------------------------------------------------------------------------------
GRID_EXTENT = 270.0  # world units: 90% of the built-in camera's view height at the origin


@dataclass(frozen=True)
class Surface:
    positions: np.ndarray  # (V, 3) float64
    uvs: np.ndarray  # (V, 2) float64
    normals: np.ndarray  # (V, 3) float64, unit
    cells: int  # the grid has cells x cells quads


def wavy_surface(cells: int, seed: int) -> Surface:
    """A square grid in the xy plane facing +z (the built-in camera), its z a seeded wave with noise.

    The noise keeps every coordinate's digits varied, as in a scanned or sculpted model.
    """
    rng = np.random.default_rng(seed)
    steps = np.linspace(0.0, 1.0, cells + 1)
    u, v = np.meshgrid(steps, steps)
    phase = rng.uniform(0.0, 2.0 * np.pi, size=2)
    frequency = 6.0 * np.pi
    amplitude = 0.04 * GRID_EXTENT
    height = amplitude * np.sin(frequency * u + phase[0]) * np.cos(frequency * v + phase[1])
    jitter = rng.normal(scale=GRID_EXTENT / cells * 0.05, size=(cells + 1, cells + 1, 3))
    x, y = (u - 0.5) * GRID_EXTENT, (v - 0.5) * GRID_EXTENT
    positions = np.stack([x, y, height], axis=-1) + jitter
    # Normals of the wave without the noise: close enough for shading, and cheap.
    slope = amplitude * frequency / GRID_EXTENT
    dz_dx = slope * np.cos(frequency * u + phase[0]) * np.cos(frequency * v + phase[1])
    dz_dy = -slope * np.sin(frequency * u + phase[0]) * np.sin(frequency * v + phase[1])
    normals = np.stack([-dz_dx, -dz_dy, np.ones_like(dz_dx)], axis=-1)
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    return Surface(positions.reshape(-1, 3), np.stack([u, v], axis=-1).reshape(-1, 2),
                   normals.reshape(-1, 3), cells)


def grid_quads(cells: int) -> np.ndarray:
    """(cells², 4) 0-based corners, counter-clockwise seen from +z."""
    row, col = np.meshgrid(np.arange(cells), np.arange(cells), indexing="ij")
    first = (row * (cells + 1) + col).reshape(-1)
    return np.stack([first, first + 1, first + cells + 2, first + cells + 1], axis=1)


def grid_triangles(cells: int) -> np.ndarray:
    """(2 cells², 3): each quad split along its diagonal from the first corner."""
    quads = grid_quads(cells)
    return np.stack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]], axis=1).reshape(-1, 3)


def cells_for_triangles(triangles: int) -> int:
    return max(1, round((triangles / 2) ** 0.5))


def cells_for_quads(quads: int) -> int:
    return max(1, round(quads ** 0.5))


_WRITE_CHUNK = 1 << 16  # lines formatted per call: bounds the temporary tuple's memory


def _format_rows(template: str, table: np.ndarray) -> Iterator[str]:
    """One `%`-formatted line per row: C-level formatting, far faster than np.savetxt."""
    for start in range(0, len(table), _WRITE_CHUNK):
        chunk = table[start:start + _WRITE_CHUNK]
        yield (template * len(chunk)) % tuple(chunk.ravel().tolist())


def write_obj(path: Path, surface: Surface, faces: np.ndarray, uv_and_normals: bool) -> None:
    """Blender-like formatting: 6 decimals for v and vt, 4 for vn; corners v/vt/vn or bare v."""
    corners = faces.shape[1]
    with path.open("w", encoding="ascii") as out:
        out.write(f"# generated by app.bench (seeded): {len(faces)} faces of {corners} corners\n")
        out.write("o bench\n")
        out.writelines(_format_rows("v %.6f %.6f %.6f\n", surface.positions))
        if uv_and_normals:
            out.writelines(_format_rows("vt %.6f %.6f\n", surface.uvs))
            out.writelines(_format_rows("vn %.4f %.4f %.4f\n", surface.normals))
            corner = "%d/%d/%d"
            indices = np.repeat(faces + 1, 3, axis=1)
        else:
            corner = "%d"
            indices = faces + 1
        out.writelines(_format_rows("f " + " ".join([corner] * corners) + "\n", indices))


@dataclass(frozen=True)
class LoadInput:
    label: str
    path: Path
    triangles: int  # after fan triangulation

    @property
    def megabytes(self) -> float:
        return self.path.stat().st_size / MEGABYTE


def generate_load_inputs(directory: Path, small: int, large: int) -> list[LoadInput]:
    """The four files of section 1: small and large v/vt/vn triangles, large quads, large v/f only."""
    specs = [  # label, triangles or quads wanted, quads?, vt/vn?
        (f"{_count_label(small)} tri v/vt/vn", small, False, True),
        (f"{_count_label(large)} tri v/vt/vn", large, False, True),
        (f"{_count_label(large)} quads v/vt/vn", large, True, True),
        (f"{_count_label(large)} tri v f only", large, False, False),
    ]
    inputs = []
    for number, (label, count, quads, uv_and_normals) in enumerate(specs):
        cells = cells_for_quads(count) if quads else cells_for_triangles(count)
        faces = grid_quads(cells) if quads else grid_triangles(cells)
        path = directory / f"bench_{number}_{label.replace(' ', '_').replace('/', '')}.obj"
        _progress(f"writing {path.name}")
        write_obj(path, wavy_surface(cells, SEED + number), faces, uv_and_normals)
        inputs.append(LoadInput(label, path, len(faces) * (faces.shape[1] - 2)))
    return inputs


def generated_mesh(triangles: int, seed: int = SEED) -> Mesh:
    """A drawn mesh straight from arrays: the same Mesh the loader makes, without writing a file."""
    from app.loaders.obj import build_mesh

    cells = cells_for_triangles(triangles)
    surface = wavy_surface(cells, seed)
    faces = grid_triangles(cells)
    corner_vertex = faces.reshape(-1)
    return build_mesh(f"grid {_count_label(triangles)}", surface.positions, faces,
                      uvs=surface.uvs[corner_vertex], normals=surface.normals[corner_vertex])


# --------------------------------------------------------------------------------------------------
# 1. Loading, one fresh process per (loader, file)
# --------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class LoadTiming:
    triangles: int
    seconds: float
    surface_seconds: float | None = None


LoadFunction = Callable[[Path], LoadTiming]


def _ours() -> LoadFunction:
    from app.loaders.obj import load_obj

    def load(path: Path) -> LoadTiming:
        start = time.perf_counter()
        mesh = load_obj(path)
        parsed = time.perf_counter()
        gpu_ready_arrays(mesh)
        done = time.perf_counter()
        return LoadTiming(int(mesh.triangles_before_face()[-1]), done - start, done - parsed)
    return load


def gpu_ready_arrays(mesh: Mesh) -> dict[str, np.ndarray]:
    """What a new object costs before its first frame: the surface array `ObjectGpu` uploads.

    Edges and normal segments are built only when lines or normals are first drawn (app/gpu.py).
    """
    from dataclasses import fields

    from app.gpu import surface_arrays

    surface = surface_arrays(mesh)
    return {array.name: getattr(surface, array.name) for array in fields(surface)}


def _trimesh() -> LoadFunction:
    import trimesh

    def load(path: Path) -> LoadTiming:
        start = time.perf_counter()
        loaded = trimesh.load(str(path), process=False)
        done = time.perf_counter()
        geometries = loaded.geometry.values() if hasattr(loaded, "geometry") else [loaded]
        return LoadTiming(sum(len(g.faces) for g in geometries), done - start)
    return load


def _tinyobjloader() -> LoadFunction:
    import tinyobjloader

    def load(path: Path) -> LoadTiming:
        start = time.perf_counter()
        reader = tinyobjloader.ObjReader()
        if not reader.ParseFromFile(str(path), tinyobjloader.ObjReaderConfig()):
            raise RuntimeError(f"tinyobjloader could not read {path}: {reader.Error()}")
        attrib = reader.GetAttrib()
        # numpy copies of the tables and indices: what a viewer would go on to use.
        attrib.numpy_vertices(), attrib.numpy_normals(), attrib.numpy_texcoords()
        shapes = reader.GetShapes()
        triangles = 0
        for shape in shapes:
            shape.mesh.numpy_indices()
            triangles += len(shape.mesh.numpy_num_face_vertices())
        done = time.perf_counter()
        return LoadTiming(triangles, done - start)
    return load


_LOADER_FACTORIES: dict[str, Callable[[], LoadFunction]] = {
    "ours": _ours, "trimesh": _trimesh, "tinyobjloader": _tinyobjloader}


def _peak_rss_bytes() -> int:
    """This process's peak resident memory.

    On Linux ru_maxrss is not usable here: execve keeps the larger of the old and new peaks, and the
    old one is the bench process's (fork copies its memory map), which hides a small loader's peak.
    VmHWM is the peak of the current memory map only, which starts at exec.
    """
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak if sys.platform == "darwin" else peak * 1024  # Linux reports KiB, macOS bytes


def load_worker(argv: Sequence[str]) -> int:
    """The child: import the loader, note the peak RSS, load `repeats` times, print JSON."""
    loader, path, repeats = argv[0], Path(argv[1]), int(argv[2])
    load = _LOADER_FACTORIES[loader]()
    baseline = _peak_rss_bytes()
    timings = [load(path) for _ in range(repeats)]
    print(json.dumps({"triangles": timings[0].triangles,
                      "seconds": [t.seconds for t in timings],
                      "surface_seconds": [t.surface_seconds for t in timings],
                      "peak_rss_bytes": _peak_rss_bytes() - baseline}))
    return 0


_WORKER_CODE = "import sys; from app.bench import load_worker; sys.exit(load_worker(sys.argv[1:]))"


@dataclass
class LoadResult:
    """Every load of one loader and file, over all its processes."""

    triangles: int = 0
    seconds: list[float] = field(default_factory=list)
    surface_seconds: list[float] = field(default_factory=list)
    peak_rss_bytes: list[int] = field(default_factory=list)  # one per process

    def add_process(self, loader: str, path: Path, repeats: int) -> None:
        done = subprocess.run([sys.executable, "-c", _WORKER_CODE, loader, str(path), str(repeats)],
                              cwd=PROJECT_ROOT, capture_output=True, text=True)
        if done.returncode != 0:
            raise RuntimeError(f"{loader} on {path.name} failed:\n{done.stderr.strip()}")
        report = json.loads(done.stdout.strip().splitlines()[-1])
        self.triangles = report["triangles"]
        self.seconds += report["seconds"]
        self.surface_seconds += [s for s in report["surface_seconds"] if s is not None]
        self.peak_rss_bytes.append(report["peak_rss_bytes"])

    @property
    def median_seconds(self) -> float:
        return statistics.median(self.seconds)

    @property
    def median_surface_seconds(self) -> float | None:
        return statistics.median(self.surface_seconds) if self.surface_seconds else None

    @property
    def median_peak_rss_bytes(self) -> float:
        return statistics.median(self.peak_rss_bytes)


def available_loaders(wanted: Sequence[str]) -> tuple[list[str], list[str]]:
    """The wanted loaders that can be imported, and notes for those that cannot."""
    present, notes = [], []
    for name in wanted:
        if name == "ours" or importlib.util.find_spec(name) is not None:
            present.append(name)
        else:
            notes.append(f"{name} is not installed, so its rows are left out "
                         f"(`pip install '.[bench]'` adds tinyobjloader).")
    return present, notes


def loading_section(config: BenchConfig, inputs: Sequence[LoadInput]) -> list[str]:
    loaders, notes = available_loaders(config.loaders)
    rows = []
    for item in inputs:
        results = {loader: LoadResult() for loader in loaders}
        for round_number in range(config.rounds):  # in turn, so that all see the machine alike
            for loader in loaders:
                _progress(f"loading {item.path.name} with {loader} ({round_number + 1}/{config.rounds})")
                results[loader].add_process(loader, item.path, config.repeats)
        rows += [_load_row(item, loader, result, results.get("ours")) for loader, result in results.items()]
    lines = [
        "## 1. Loading: OBJ file to GPU-ready arrays",
        "",
        f"Median of {config.rounds * config.repeats} load(s): {config.rounds} fresh process(es) per loader and "
        f"file, the loaders taking turns, {config.repeats} load(s) in each; peak RSS is the median over those "
        "processes of the process's peak minus its peak after imports. *ours* = `load_obj` + the surface "
        "vertex and index "
        "arrays `ObjectGpu` uploads for the first frame (app/gpu.py; edges and normal segments "
        "are built later, when lines or normals are first drawn); trimesh = `trimesh.load(process=False)`; "
        "tinyobjloader = parse (triangulated) + numpy copies of its tables. Ratios > 1: ours is faster "
        "or smaller.",
        "",
        *markdown_table(LOAD_HEADERS, rows),
    ]
    return lines + [""] + [f"Note: {note}" for note in notes]


def _load_row(item: LoadInput, loader: str, result: LoadResult, ours: LoadResult | None) -> list[str]:
    mb = item.megabytes
    seconds = result.median_seconds
    return [item.label, str(result.triangles), _number(mb), loader, _number(seconds),
            _number(result.median_surface_seconds), _number(mb / seconds),
            _number(result.median_peak_rss_bytes / MEGABYTE),
            _ratio(seconds, ours.median_seconds if ours else None),
            _ratio(result.median_peak_rss_bytes, ours.median_peak_rss_bytes if ours else None)]


# --------------------------------------------------------------------------------------------------
# 2. Frames: the renderer beside a pass-through program on the same vertex data
# --------------------------------------------------------------------------------------------------
BARE_VERTEX_SHADER = """#version 330
uniform mat4 u_mvp;
in vec3 in_position;
void main() { gl_Position = u_mvp * vec4(in_position, 1.0); }
"""
BARE_FRAGMENT_SHADER = """#version 330
out vec4 f_colour;
void main() { f_colour = vec4(1.0); }
"""
# The renderer's interleaved layouts (app/gpu.py) read for the position only: same buffer, same stride.
BARE_SURFACE_FORMAT = "3f 32x"  # skips vertex normal, face normal, uv
BARE_EDGE_FORMAT = "3f 24x"  # skips face normal, polygon's first vertex
MODES = ("flat", "gouraud", "lines")
MIN_FRAMES = 3  # a median of fewer says little


def set_mode(scene: Scene, mode: str) -> None:
    from app.scene import Fill, Shading

    scene.modes.fill = Fill.LINES if mode == "lines" else Fill.FILLED
    scene.modes.shading = Shading.GOURAUD if mode == "gouraud" else Shading.FLAT


def drawn_objects(scene: Scene) -> list[SceneObject]:
    """What the renderer draws with the start modes: every object and camera but the viewer."""
    return [obj for obj in scene.objects + scene.cameras if obj is not scene.viewer and obj.mesh.face_count]


def scene_triangles(scene: Scene) -> int:
    return sum(int(obj.mesh.triangles_before_face()[-1]) for obj in drawn_objects(scene))


class BareDraw:
    """A pass-through program drawing the renderer's vertex arrays: the floor under a frame's cost.

    Same framebuffer, clear, depth test, primitives, index buffers (Flat's, or the shared one of
    Gouraud) and vertex count as the renderer; no lighting, no texture, one pass of edges.
    """

    def __init__(self, ctx: moderngl.Context, scene: Scene) -> None:
        import moderngl

        from app.gpu import edge_vertices, surface_arrays
        from app.renderer import CLEAR_COLOUR

        self.gl = moderngl  # imported here, not per frame, so the bare CPU figures stay bare
        self.clear_colour = CLEAR_COLOUR
        self.ctx = ctx
        self.scene = scene
        self.program = ctx.program(vertex_shader=BARE_VERTEX_SHADER, fragment_shader=BARE_FRAGMENT_SHADER)
        self.buffers: list[moderngl.Buffer] = []
        self.objects: list[tuple[SceneObject, dict[str, moderngl.VertexArray]]] = []
        for obj in drawn_objects(scene):
            arrays = surface_arrays(obj.mesh)
            surface = ctx.buffer(arrays.vertices)
            indices, shared = ctx.buffer(arrays.indices), ctx.buffer(arrays.shared_indices)
            edges = ctx.buffer(edge_vertices(obj.mesh).tobytes())
            self.buffers += [surface, indices, shared, edges]
            position = [(surface, BARE_SURFACE_FORMAT, "in_position")]
            self.objects.append((obj, {
                "flat": ctx.vertex_array(self.program, position, index_buffer=indices, index_element_size=4),
                "gouraud": ctx.vertex_array(self.program, position, index_buffer=shared, index_element_size=4),
                "lines": ctx.vertex_array(self.program, [(edges, BARE_EDGE_FORMAT, "in_position")])}))

    def render(self, fbo: moderngl.Framebuffer, size: tuple[int, int], mode: str) -> None:
        gl = self.gl
        width, height = size
        fbo.use()
        fbo.viewport = (0, 0, width, height)
        fbo.clear(*self.clear_colour, 1.0, depth=1.0)
        filled = mode != "lines"
        if filled:
            self.ctx.enable(gl.DEPTH_TEST)
        else:
            self.ctx.disable(gl.DEPTH_TEST)
        view_projection = self.scene.projection_matrix(width / height) @ self.scene.view_matrix()
        for obj, arrays in self.objects:
            mvp = view_projection @ obj.model
            self.program["u_mvp"].write(np.ascontiguousarray(mvp.T, dtype="f4").tobytes())
            arrays[mode].render(gl.TRIANGLES if filled else gl.LINES)
        self.ctx.disable(gl.DEPTH_TEST)

    def release(self) -> None:
        for _, arrays in self.objects:
            for vao in arrays.values():
                vao.release()
        for buffer in self.buffers:
            buffer.release()
        self.program.release()


@dataclass
class FrameTimes:
    moving: list[float] = field(default_factory=list)
    still: list[float] = field(default_factory=list)
    bare: list[float] = field(default_factory=list)


# The camera turns this far, to and fro, before each moving frame: every lit colour changes (V and
# the camera's spotlight move), the picture hardly.
NUDGE_RADIANS = 1e-3


def nudge_camera(scene: Scene, step: int) -> None:
    """Turns the viewing camera about its own y axis, one way on even steps and back on odd ones."""
    from app.transforms import apply_local, rotation_about_axis

    turn = rotation_about_axis(1, NUDGE_RADIANS if step % 2 == 0 else -NUDGE_RADIANS)
    scene.camera.history[-1] = apply_local(scene.camera.model, turn)  # in place: no undo step per frame


def paired_frame_times(ctx: moderngl.Context, scene: Scene, program_frame: Callable[[], None],
                       bare_frame: Callable[[], None], config: BenchConfig) -> FrameTimes:
    """A moving frame (the camera nudged first), a still one (nothing changed since), a bare one, in
    turn, so all three see the same load from other processes.

    The first warm-up frame also builds the renderer's buffers for the object and compiles shader
    variants, which is why it is never measured.
    """
    for _ in range(config.warmup):
        for frame in (program_frame, bare_frame):
            frame()
            ctx.finish()
    times = FrameTimes()
    started = time.perf_counter()
    while len(times.still) < config.frames:
        if len(times.still) >= MIN_FRAMES and time.perf_counter() - started > config.frame_budget_s:
            break
        nudge_camera(scene, len(times.moving))
        for frame, record in ((program_frame, times.moving), (program_frame, times.still),
                              (bare_frame, times.bare)):
            start = time.perf_counter()
            frame()
            ctx.finish()
            record.append(time.perf_counter() - start)
    return times


@dataclass
class FrameBench:
    """The GL pieces shared by sections 2 and 4: one context, one renderer, the scene's texture."""

    ctx: moderngl.Context
    renderer: Renderer

    @classmethod
    def open(cls) -> FrameBench:
        from app.renderer import Renderer
        from app.screenshot import create_context

        ctx = create_context()
        return cls(ctx, Renderer(ctx))

    def use_scene_texture(self, scene: Scene) -> None:
        from app.loaders.image import load_texture_or_fallback

        image, _ = load_texture_or_fallback(scene.texture_path)
        self.renderer.set_texture(image)

    def release(self) -> None:
        self.renderer.release()
        self.ctx.release()


def bench_scene(mesh: Mesh | None) -> Scene:
    """The built-in scene (its camera, lights, texture), its objects replaced by `mesh` if given;
    all four lights on."""
    from app.scene import SceneObject
    from app.scenefile import DEFAULT_MATERIAL, load_builtin_scene

    scene = load_builtin_scene()
    if mesh is not None:
        scene.objects = [SceneObject.placed(mesh.name, mesh, DEFAULT_MATERIAL, (0.0, 0.0, 0.0))]
        scene.selected_object = 0
    for light in scene.lights:
        light.on = True
    return scene


@contextmanager
def scene_and_bare(bench: FrameBench, scene: Scene) -> Iterator[BareDraw]:
    """`scene` ready to draw with its texture, and the bare program on the same vertex data; both
    programs' buffers released afterwards."""
    bench.use_scene_texture(scene)
    bare = BareDraw(bench.ctx, scene)
    try:
        yield bare
    finally:
        bare.release()
        for obj in drawn_objects(scene):
            bench.renderer.release_object(obj)


@contextmanager
def framebuffer(bench: FrameBench, size: tuple[int, int]) -> Iterator[moderngl.Framebuffer]:
    fbo = bench.ctx.simple_framebuffer(size, components=4)
    try:
        yield fbo
    finally:
        fbo.release()


def frame_cases(bench: FrameBench, scene: Scene, label: str, config: BenchConfig) -> list[list[str]]:
    rows = []
    with scene_and_bare(bench, scene) as bare:
        for size in config.resolutions:
            with framebuffer(bench, size) as fbo:
                for mode in MODES:
                    _progress(f"frames: {label} {size[0]}x{size[1]} {mode}")
                    set_mode(scene, mode)
                    times = paired_frame_times(bench.ctx, scene, lambda: bench.renderer.render(scene, fbo, size),
                                               lambda: bare.render(fbo, size, mode), config)
                    rows.append(_frame_row(label, scene_triangles(scene), size, mode, times))
    return rows


def _frame_row(label: str, triangles: int, size: tuple[int, int], mode: str, times: FrameTimes) -> list[str]:
    still, moving, bare = (statistics.median(frames) * 1000 for frames in (times.still, times.moving, times.bare))
    return [label, str(triangles), f"{size[0]}x{size[1]}", mode, _number(still), _number(moving), _number(bare),
            _ratio(still, bare), _ratio(moving, bare), str(len(times.still))]


def frames_section(bench: FrameBench, config: BenchConfig) -> list[str]:
    rows = frame_cases(bench, bench_scene(None), "built-in", config)
    for triangles in config.frame_sizes:
        _progress(f"building the {_count_label(triangles)}-triangle mesh")
        rows += frame_cases(bench, bench_scene(generated_mesh(triangles)), f"grid {_count_label(triangles)}",
                            config)
    sizes = ", ".join(_count_label(n) for n in config.frame_sizes) or "none"
    resolutions = ", ".join(f"{w}x{h}" for w, h in config.resolutions)
    return [
        "## 2. Frames: GPU-complete frame time",
        "",
        f"Meshes: the built-in scene and generated grids of {sizes} triangles; sizes {resolutions}; "
        "all four lights on, texture on. Each frame is `render` + `ctx.finish()`; median of up to "
        f"{config.frames} frames after {config.warmup} warm-up frame(s) (a case stops at {MIN_FRAMES} frames after "
        f"{config.frame_budget_s:g} s). *moving*: the camera turns {NUDGE_RADIANS:g} rad before the frame, so "
        "every vertex is lit again; *still*: the next frame, nothing changed, so the lighting pass is "
        "skipped. *bare* = a pass-through program drawing the same vertex buffers (same layout, depth "
        "test and primitive count; lines drawn once) in the same process, frames alternating with the "
        "program's; the ratios are what the program adds.",
        "",
        *markdown_table(FRAME_HEADERS, rows),
    ]


def cpu_section(bench: FrameBench, config: BenchConfig) -> list[str]:
    """Python CPU per frame on the built-in scene: render() without finish, GPU work waited out
    between frames so none of it lands in the next measurement."""
    scene = bench_scene(None)
    size = config.resolutions[0]
    rows = []
    with scene_and_bare(bench, scene) as bare, framebuffer(bench, size) as fbo:
        for mode in MODES:
            _progress(f"CPU per frame: built-in {mode}")
            set_mode(scene, mode)
            program = _cpu_per_frame(bench.ctx, lambda: bench.renderer.render(scene, fbo, size), config)
            with _draw_calls_skipped():
                python_only = _cpu_per_frame(bench.ctx, lambda: bench.renderer.render(scene, fbo, size), config)
            bare_cpu = _cpu_per_frame(bench.ctx, lambda: bare.render(fbo, size, mode), config)
            rows.append([mode, *(_number(ms) for ms in (*program, python_only[1], *bare_cpu))])
    return [
        "### Python CPU per frame, built-in scene",
        "",
        f"Median over {config.cpu_frames} frames at {size[0]}x{size[1]} of `time.process_time()` (all "
        "threads) and `time.thread_time()` (the calling thread) around `render` alone, without "
        "`finish`. llvmpipe runs vertex shading in the calling thread, so both include some driver "
        "work; the bare columns are that floor. *without draw calls*: thread time with "
        "`VertexArray.render` made a no-op, i.e. the renderer's own Python work.",
        "",
        *markdown_table(CPU_HEADERS, rows),
    ]


@contextmanager
def _draw_calls_skipped() -> Iterator[None]:
    """Every VertexArray.render does nothing: what is left of a frame is Python and uniform uploads."""
    import moderngl

    original = moderngl.VertexArray.render
    moderngl.VertexArray.render = lambda self, *args, **kwargs: None  # type: ignore[method-assign]
    try:
        yield
    finally:
        moderngl.VertexArray.render = original  # type: ignore[method-assign]


def _cpu_per_frame(ctx: moderngl.Context, frame: Callable[[], None], config: BenchConfig) -> tuple[float, float]:
    for _ in range(config.warmup):
        frame()
        ctx.finish()
    process, thread = [], []
    for _ in range(config.cpu_frames):
        process_start, thread_start = time.process_time(), time.thread_time()
        frame()
        thread.append(time.thread_time() - thread_start)
        process.append(time.process_time() - process_start)
        ctx.finish()
    return statistics.median(process) * 1000, statistics.median(thread) * 1000


# --------------------------------------------------------------------------------------------------
# 3. Start: process start to the first PNG
# --------------------------------------------------------------------------------------------------
BARE_EGL_CODE = "import numpy, moderngl; moderngl.create_standalone_context(backend='egl').release()"


@dataclass(frozen=True)
class StartCommand:
    label: str
    argv: tuple[str, ...]  # `{png}` stands for the output file
    writes_png: bool


START_COMMANDS = (
    StartCommand("`python -m app screenshot -o X.png` (built-in scene, 800x800)",
                 ("-m", "app", "screenshot", "-o", "{png}"), True),
    StartCommand("bare: import numpy, moderngl; open an EGL context", ("-c", BARE_EGL_CODE), False),
    StartCommand("python -c pass", ("-c", "pass"), False),
)


def time_start(command: StartCommand, png: Path) -> tuple[float | None, float]:
    """Seconds from spawning to the PNG's last write (its mtime, ~4 ms granular) and to the exit."""
    png.unlink(missing_ok=True)
    argv = [sys.executable, *(part.replace("{png}", str(png)) for part in command.argv)]
    wall_start_ns = time.time_ns()
    start = time.perf_counter()
    done = subprocess.run(argv, cwd=PROJECT_ROOT, capture_output=True, text=True)
    exit_s = time.perf_counter() - start
    if done.returncode != 0:
        raise RuntimeError(f"{' '.join(argv)} failed:\n{done.stderr.strip()}")
    png_s = (png.stat().st_mtime_ns - wall_start_ns) / 1e9 if command.writes_png else None
    return png_s, exit_s


def start_section(config: BenchConfig, directory: Path) -> list[str]:
    png = directory / "start.png"
    # The bare process imports numpy and moderngl from the byte code pip compiled when it installed
    # them; ours is an editable install, which compiles nothing, and where PYTHONDONTWRITEBYTECODE is
    # set (this machine) no run ever writes it. Compiling first, as a regular install would, keeps
    # the comparison about starting rather than about compiling our modules.
    compileall.compile_dir(str(Path(__file__).parent), quiet=1)
    runs: dict[str, list[tuple[float | None, float]]] = {c.label: [] for c in START_COMMANDS}
    for run in range(config.start_runs):  # rounds, so every command sees the same background load
        for command in START_COMMANDS:
            _progress(f"start: {command.label} (run {run + 1})")
            runs[command.label].append(time_start(command, png))
    bare_exit = statistics.median(exit_s for _, exit_s in runs[START_COMMANDS[1].label])
    rows = []
    for command in START_COMMANDS:
        png_times = [png_s for png_s, _ in runs[command.label] if png_s is not None]
        exit_s = statistics.median(exit_s for _, exit_s in runs[command.label])
        png_s = statistics.median(png_times) if png_times else None
        rows.append([command.label, _number(png_s), _ratio(png_s, bare_exit),
                     _number(exit_s), _ratio(exit_s, bare_exit), str(config.start_runs)])
    return [
        "## 3. Start: process start to the first PNG",
        "",
        f"Median of {config.start_runs} run(s), interleaved. *to PNG written* is the PNG's mtime minus "
        "the spawn time, the issue's measure, compared with the bare process's exit (it has no PNG); "
        "*to exit* adds the interpreter's tear-down.",
        "",
        *markdown_table(START_HEADERS, rows),
    ]


# --------------------------------------------------------------------------------------------------
# 4. Memory per triangle
# --------------------------------------------------------------------------------------------------
MESH_ARRAYS = ("positions", "corner_vertex", "corner_uv", "corner_normal", "face_start", "face_normals")


def mesh_bytes(mesh: Mesh) -> int:
    return sum(getattr(mesh, name).nbytes for name in MESH_ARRAYS)


def memory_row(bench: FrameBench, item: LoadInput) -> list[str]:
    from app.gpu import ObjectGpu
    from app.loaders.obj import load_obj

    mesh = load_obj(item.path)
    triangles = int(mesh.triangles_before_face()[-1])
    ready = sum(array.nbytes for array in gpu_ready_arrays(mesh).values())
    renderer = bench.renderer
    gpu = ObjectGpu(bench.ctx, mesh, renderer.programs)  # exactly what the renderer allocates per object
    try:
        surface = sum(buffer.size for buffer in gpu.buffers.values())  # all there is before lines or normals
        _ = gpu.edges, gpu.face_normals, gpu.vertex_normals  # built on first use: force them here
        sizes = {name: buffer.size for name, buffer in gpu.buffers.items()}
        host = mesh_bytes(mesh) + gpu.triangles_before.nbytes
        per_triangle = [value / triangles for value in (
            host, ready, surface, sum(sizes.values()), sizes["edges"],
            sizes["face normals"] + sizes["vertex normals"])]
    finally:
        gpu.release()
    return [item.label, str(triangles), *(_number(value) for value in per_triangle)]


def memory_section(bench: FrameBench, inputs: Sequence[LoadInput]) -> list[str]:
    rows = []
    for item in inputs:
        _progress(f"memory: {item.path.name}")
        rows.append(memory_row(bench, item))
    return [
        "## 4. Memory per triangle of a loaded mesh",
        "",
        "*Mesh*: the Mesh's arrays plus the renderer's kept `triangles_before` (host, for the object's "
        "life). *GPU-ready arrays*: the surface's vertex and index arrays made before the first "
        "frame (host, while uploading). *GPU when filled*: the surface's buffers, all an object holds until lines or "
        "normals are drawn; *with lines and normals*: every buffer it can hold (surface, edges, face "
        "and vertex normal segments). On llvmpipe GPU buffers live in host memory too.",
        "",
        *markdown_table(MEMORY_HEADERS, rows),
    ]


# --------------------------------------------------------------------------------------------------
# Machine, formatting, main
# --------------------------------------------------------------------------------------------------
def machine_lines(ctx: moderngl.Context | None, config: BenchConfig) -> list[str]:
    import moderngl

    cores = os.cpu_count()
    usable = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else cores
    memory_gb = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 1e9 if hasattr(os, "sysconf") else 0
    info = ctx.info if ctx is not None else {}
    lines = [
        MACHINE_HEADING,
        "",
        f"- CPU: {_cpu_model()}, {cores} cores ({usable} usable), {memory_gb:.0f} GB memory",
        f"- GL_RENDERER: {info.get('GL_RENDERER', 'no context')}; GL_VERSION: {info.get('GL_VERSION', '-')}",
        f"- Python {platform.python_version()}, numpy {np.__version__}, moderngl {moderngl.__version__}",
        f"- load average at start: {_load_average()} (other processes share the cores: expect noise)",
        f"- sections: {', '.join(config.sections)}; OBJ files of {_count_label(config.load_sizes[0])} and "
        f"{_count_label(config.load_sizes[1])} triangles; drawn grids: "
        f"{', '.join(_count_label(n) for n in config.frame_sizes) or 'none'}; sizes: "
        f"{', '.join(f'{w}x{h}' for w, h in config.resolutions)}",
    ]
    return lines


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def _load_average() -> str:
    try:
        return " ".join(f"{value:.2f}" for value in os.getloadavg())
    except OSError:
        return "unknown"


def markdown_table(headers: Sequence[str], rows: Sequence[Sequence[str]]) -> list[str]:
    lines = ["| " + " | ".join(headers) + " |", "|" + "|".join("---" for _ in headers) + "|"]
    return lines + ["| " + " | ".join(row) + " |" for row in rows]


def _number(value: float | None) -> str:
    """Three significant figures, never in exponent form (the README reads better)."""
    if value is None:
        return MISSING
    magnitude = abs(value)
    if magnitude >= 100:
        return f"{value:.0f}"
    if magnitude >= 10:
        return f"{value:.1f}"
    if magnitude >= 1:
        return f"{value:.2f}"
    return f"{value:.3g}"


def _ratio(value: float | None, reference: float | None) -> str:
    if value is None or not reference:
        return MISSING
    return f"{value / reference:.2f}"


def _count_label(count: int) -> str:
    if count >= 1_000_000 and count % 100_000 == 0:
        return f"{count / 1_000_000:g}M"
    if count >= 1_000 and count % 100 == 0:
        return f"{count / 1_000:g}k"
    return str(count)


def _progress(message: str) -> None:
    print(f"[bench] {message}", file=sys.stderr, flush=True)


def _emit(lines: Sequence[str]) -> None:
    print("\n".join(lines) + "\n", flush=True)


def _open_gl(required: bool) -> FrameBench | None:
    """The GL context; without one, only the sections that need none run (the header says so)."""
    from app.errors import ViewerError

    try:
        return FrameBench.open()
    except ViewerError:
        if required:
            raise
        return None


@contextmanager
def _work_directory(chosen: Path | None) -> Iterator[Path]:
    if chosen is not None:
        chosen.mkdir(parents=True, exist_ok=True)
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
        _emit(["# marraztu bench", "", *machine_lines(bench.ctx if bench else None, config)])
        with _work_directory(config.workdir) as directory:
            inputs = []
            if "load" in config.sections or "memory" in config.sections:
                inputs = generate_load_inputs(directory, *config.load_sizes)
            if "load" in config.sections:
                _emit(loading_section(config, inputs))
            if bench is not None and "frames" in config.sections:
                _emit(frames_section(bench, config))
            if bench is not None and "cpu" in config.sections:
                _emit(cpu_section(bench, config))
            if "start" in config.sections:
                _emit(start_section(config, directory))
            if bench is not None and "memory" in config.sections:
                _emit(memory_section(bench, inputs))
    finally:
        if bench is not None:
            bench.release()
    _emit([f"Bench took {time.perf_counter() - started:.0f} s; load average at the end: {_load_average()}."])
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
