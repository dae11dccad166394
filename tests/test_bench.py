"""`python -m marraztu bench` at miniature sizes: every table is there, whole, and holds positive figures.

No timing is asserted: the figures depend on the machine and on whatever else runs on it.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from marraztu.devtools import bench
from marraztu.devtools.bench.config import LOADERS, config_from_args, parse_counts
from marraztu.devtools.bench.frames import CPU_HEADERS, FRAME_HEADERS, MODES
from marraztu.devtools.bench.inputs import (
    FORMATS,
    cells_for_triangles,
    generate_format_inputs,
    generate_load_inputs,
    generate_materials_input,
)
from marraztu.devtools.bench.loading import LOAD_HEADERS, OBJ_ONLY_LOADERS, PAUSE_HEADERS, available_loaders
from marraztu.devtools.bench.memory import MATERIALS, MEMORY_HEADERS
from marraztu.devtools.bench.report import MACHINE_HEADING, MISSING, ratio
from marraztu.devtools.bench.shapes import SHAPE_HEADERS, SHAPES
from marraztu.devtools.bench.start import START_COMMANDS, START_HEADERS
from marraztu.devtools.bench.window import WINDOW_HEADERS
from marraztu.loaders.registry import load_model
from marraztu.render.context import COMPUTE_GL_VERSION
from support import corpus
from support.processes import buffered_environment

TINY_ARGS = ["--load-sizes", "200,400", "--sizes", "300", "--resolutions", "48x32", "--frames", "2",
             "--warmup", "1", "--repeats", "1", "--rounds", "1", "--start-runs", "1", "--cpu-frames", "2",
             "--objects", "20", "--shape-megabytes", "1", "--idle-seconds", "0.5", "--load-pause", "0.1"]


def markdown_tables(text: str) -> dict[tuple[str, ...], list[list[str]]]:
    """Each table's rows, keyed by its header cells."""
    tables: dict[tuple[str, ...], list[list[str]]] = {}
    header: tuple[str, ...] | None = None
    for line in text.splitlines():
        if not line.startswith("|"):
            header = None
            continue
        cells = [cell.strip() for cell in line.strip().strip("|").split("|")]
        if header is None:
            header = tuple(cells)
            tables[header] = []
        elif not all(set(cell) <= {"-"} for cell in cells):
            tables[header].append(cells)
    return tables


def numbers_in(rows: list[list[str]], headers: tuple[str, ...], column: str) -> list[float]:
    at = headers.index(column)
    return [float(row[at]) for row in rows if row[at] != MISSING]


@pytest.fixture(scope="module")
def report(tmp_path_factory: pytest.TempPathFactory, gl_ctx) -> str:
    """(gl_ctx: skips where there is no EGL.) The bench makes and releases contexts of its own."""
    from contextlib import redirect_stdout
    from io import StringIO

    out = StringIO()
    with redirect_stdout(out), corpus.kept_gl_context():
        assert bench.main([*TINY_ARGS, "--workdir", str(tmp_path_factory.mktemp("bench"))]) == 0
    return out.getvalue()


def test_every_section_prints_one_whole_table(report: str) -> None:
    assert MACHINE_HEADING in report and "GL_RENDERER: " in report
    tables = markdown_tables(report)
    loaders = available_loaders(LOADERS)[0]
    other_format_loaders = [loader for loader in loaders if loader not in OBJ_ONLY_LOADERS]
    expected = {LOAD_HEADERS: 4 * len(loaders) + len(FORMATS) * len(other_format_loaders),
                PAUSE_HEADERS: 2 + ("rapidobj" in loaders),  # ours with and without numpy's huge pages
                FRAME_HEADERS: 2 * len(MODES),  # the built-in scene and the 300-triangle grid
                CPU_HEADERS: 2 * len(MODES),  # the built-in scene and 20 objects of one mesh
                START_HEADERS: len(START_COMMANDS),
                MEMORY_HEADERS: 5,  # the four files of section 1, and the large grid of several materials
                SHAPE_HEADERS: len(SHAPES)}
    if "Skipped: no Xvfb" not in report:
        expected[WINDOW_HEADERS] = 6  # idle twice, a key for the model and the camera, a load in the scene and shown
    assert set(tables) == set(expected)
    for headers, row_count in expected.items():
        rows = tables[headers]
        assert len(rows) == row_count, headers
        assert all(len(row) == len(headers) for row in rows), headers


def test_figures_are_positive_numbers(report: str) -> None:
    tables = markdown_tables(report)
    measured = {
        LOAD_HEADERS: ["triangles", "MB", "seconds", "MB/s", "time ÷ ours"],
        PAUSE_HEADERS: ["first s", "after a pause s", "right after s", "after a pause ÷ right after",
                        "after a pause: time ÷ ours"],
        FRAME_HEADERS: ["triangles", "still ms", "moving ms", "bare ms", "bare moving ms", "still ÷ bare",
                        "moving ÷ bare", "moving ÷ bare moving", "frames"],
        CPU_HEADERS: ["program process ms", "program without draw calls ms", "bare process ms"],
        START_HEADERS: ["to exit s", "exit ÷ bare EGL", "runs"],
        MEMORY_HEADERS: ["triangles", "Mesh B/tri", "GPU-ready arrays B/tri", "GPU when filled B/tri",
                               "GPU with lines and normals B/tri"],
        SHAPE_HEADERS: ["MB", "seconds", "s per MB", "time ÷ plain"],
    }
    for headers, columns in measured.items():
        for column in columns:
            values = numbers_in(tables[headers], headers, column)
            assert values and all(np.isfinite(v) and v > 0 for v in values), (column, values)
    # A tiny file may fit in memory the process already had: its extra peak may be zero, never less.
    rss = numbers_in(tables[LOAD_HEADERS], LOAD_HEADERS, "peak RSS MB")
    assert rss and min(rss) >= 0
    screenshot_png = numbers_in(tables[START_HEADERS], START_HEADERS, "to PNG written s")
    assert len(screenshot_png) == sum(command.writes_png for command in START_COMMANDS) and min(screenshot_png) > 0


def test_the_memory_section_measures_the_large_grid_of_several_materials_beside_the_plain_one(report: str) -> None:
    """A part's Mesh held beside the whole for the model's life doubled a grid of interleaved materials'
    tables: its row sits beside the plain grid's, from the same file's rows and texture coordinates."""
    rows = {row[0]: row for row in markdown_tables(report)[MEMORY_HEADERS]}
    several, plain = rows[f"400 tri v/vt/vn, {MATERIALS} textured materials"], rows["400 tri v/vt/vn"]
    triangles, mesh = MEMORY_HEADERS.index("triangles"), MEMORY_HEADERS.index("Mesh B/tri")
    assert several[triangles] == plain[triangles]
    assert float(several[mesh]) > 0 and float(plain[mesh]) > 0


def test_the_grid_of_several_materials_takes_each_in_turn_by_row(tmp_path: Path) -> None:
    item = generate_materials_input(tmp_path, 400, MATERIALS)
    mesh = load_model(item.path)
    assert mesh.face_count == item.triangles and len(mesh.parts) == MATERIALS
    assert all(material.texture is not None for material in mesh.materials)
    assert np.count_nonzero(np.diff(mesh.face_material)) == cells_for_triangles(400) - 1  # a run per row


def test_the_generated_files_are_the_sizes_asked_for(tmp_path: Path) -> None:
    inputs = generate_load_inputs(tmp_path, 200, 400)
    assert [item.triangles for item in inputs] == [200, 392, 800, 392]  # 10x10 cells, 14x14, 20x20 quads
    first = inputs[0].path.read_text().splitlines()
    assert any(line.startswith("f ") and line.count("/") == 6 for line in first)
    assert not any(line.count("/") for line in inputs[3].path.read_text().splitlines() if line.startswith("f "))


def test_the_other_formats_hold_the_large_grid_and_are_read_by_ours_and_trimesh(report: str,
                                                                              tmp_path: Path) -> None:
    inputs = generate_format_inputs(tmp_path, 200, 400)
    assert [item.path.suffix for item in inputs] == [".stl", ".ply", ".glb", ".stl", ".ply", ".off"]
    assert [item.triangles for item in inputs] == [392, 392, 392, 200, 200, 200]
    assert all(load_model(item.path).face_count == item.triangles for item in inputs)
    assert inputs[3].path.read_bytes().startswith(b"solid") and inputs[3].warm_up.read_bytes().startswith(b"solid")
    assert b"format ascii" in inputs[4].path.read_bytes()[:40] and b"format ascii" in inputs[4].warm_up.read_bytes()
    assert all(load_model(item.warm_up).face_count == 1 for item in inputs)
    rows = markdown_tables(report)[LOAD_HEADERS]
    for item in inputs:
        loaders = [row[LOAD_HEADERS.index("loader")] for row in rows if row[0] == item.label]
        assert loaders == [loader for loader in available_loaders(LOADERS)[0] if loader not in OBJ_ONLY_LOADERS]


def test_sizes_and_shortcuts_parse() -> None:
    assert parse_counts("100k,1m,5M,2500") == (100_000, 1_000_000, 5_000_000, 2500)
    config = config_from_args(["--skip-5m"])
    assert config.frame_sizes == (100_000, 1_000_000)
    assert config_from_args(["--quick", "--frames", "7"]).frames == 7
    assert config_from_args(["--load-pause", "0"]).load_pause_s == 0


@pytest.mark.parametrize("option, value", [("--load-pause", "-1"), ("--load-pause", "inf"), ("--load-pause", "nan"),
                                           ("--idle-seconds", "0"), ("--idle-seconds", "inf"),
                                           ("--frame-budget", "nan"), ("--frame-budget", "0"), ("--objects", "0"),
                                           ("--sizes", "inf"),
                                           ("--sizes", "1e12"), ("--sizes", "nan"), ("--load-sizes", "1,1e400")])
def test_pauses_and_sizes_must_be_finite_and_bounded(option: str, value: str) -> None:
    with pytest.raises(SystemExit):
        config_from_args([option, value])


@pytest.mark.parametrize("mode", MODES)
def test_the_bare_draw_covers_the_pixels_the_renderer_does(gl_ctx, mode: str) -> None:
    """The floor under a frame's cost draws the same geometry: same vertices, read through the
    renderer's own layouts, so exactly the same pixels differ from the background."""
    from marraztu.devtools.bench.frames import BareDraw, bench_scene, set_mode
    from marraztu.render.renderer import Renderer

    size = (160, 120)
    scene = bench_scene(None)
    set_mode(scene, mode)
    renderer = Renderer(gl_ctx)
    bare = BareDraw(gl_ctx, scene, renderer.compute_lighting)
    covered = []
    try:
        for draw in (lambda fbo: renderer.render(scene, fbo, size), lambda fbo: bare.render(fbo, size, mode)):
            fbo = gl_ctx.simple_framebuffer(size, components=4)
            draw(fbo)
            pixels = np.frombuffer(fbo.read(components=3), np.uint8).reshape(size[1], size[0], 3)
            covered.append(np.any(pixels != pixels[0, 0], axis=2))  # the corner is background
            fbo.release()
    finally:
        bare.release()
        renderer.release()
    assert covered[0].sum() > 100, "not blank"
    assert np.array_equal(covered[0], covered[1])


@pytest.mark.parametrize("mode", ["flat", "gouraud"])
def test_the_inputs_floor_shows_the_lit_rows_times_the_texture_over_the_same_pixels(gl_ctx, mode: str) -> None:
    """The floor under a still frame reads the lit rows and the texture and shows their product:
    with every lit row one colour and the renderer's white texture of a scene without a picture,
    every pixel the renderer covers is that colour, and no other pixel changes."""
    from marraztu.devtools.bench.frames import BareDraw, bench_scene, set_mode
    from marraztu.render.renderer import Renderer

    size = (160, 120)
    scene = bench_scene(None)
    set_mode(scene, mode)
    scene.modes.culling = True  # the renderer draws back faces red; the floor draws them as front ones
    renderer = Renderer(gl_ctx)
    bare = BareDraw(gl_ctx, scene, renderer.compute_lighting)
    colour = np.array([0.5, 0.25, 1.0, 1.0], np.float32)
    pictures = []
    try:
        for draw in (lambda fbo: renderer.render(scene, fbo, size),
                     lambda fbo: bare.render(fbo, size, mode, texture=renderer.texture)):
            for lighting in bare.lighting:
                lighting.lit.write(np.tile(colour, lighting.lit.size // 16))
            fbo = gl_ctx.simple_framebuffer(size, components=4)
            draw(fbo)
            pictures.append(np.frombuffer(fbo.read(components=3), np.uint8).reshape(size[1], size[0], 3))
            fbo.release()
    finally:
        bare.release()
        renderer.release()
    drawn, floor = pictures
    covered = np.any(drawn != drawn[0, 0], axis=2)  # the corner is background
    assert covered.sum() > 100, "not blank"
    assert np.array_equal(floor[~covered], drawn[~covered])
    assert np.abs(floor[covered].astype(int) - np.round(colour[:3] * 255)).max() <= 1


@pytest.mark.parametrize("compute", [False, True])
@pytest.mark.parametrize("mode", ["flat", "gouraud"])
def test_the_bare_moving_frame_captures_the_rows_the_lighting_pass_lights(gl_ctx, mode: str, compute: bool) -> None:
    """The floor under a moving frame does the lighting pass's traffic: it reads the rows the
    renderer's pass lights (Flat: the polygons' own; Gouraud: the shared ones) and writes 16 bytes
    for each, at the same place, and no others; by transform feedback or compute, as the renderer."""
    from marraztu.devtools.bench.frames import BareDraw, bench_scene, drawn_objects, set_mode
    from marraztu.model.scene import Shading
    from marraztu.render.gpu import surface_arrays
    from marraztu.render.renderer import Renderer

    size = (32, 32)
    scene = bench_scene(None)
    set_mode(scene, mode)
    if compute and gl_ctx.version_code < COMPUTE_GL_VERSION:
        pytest.skip("no compute programs before OpenGL 4.3")
    renderer = Renderer(gl_ctx, compute_lighting=compute)
    bare = BareDraw(gl_ctx, scene, compute)
    fbo = gl_ctx.simple_framebuffer(size, components=4)
    try:
        renderer.render(scene, fbo, size)
        lit_by_renderer = [renderer._gpu_for(obj)._lit[Shading(mode)] for obj in drawn_objects(scene)]
        for lighting in bare.lighting:
            lighting.lit.write(np.full(lighting.lit.size // 4, -7.0, np.float32))  # not a value the pass writes
        gl_ctx.detect_framebuffer(0).use()  # none bound, as in a fresh context: the floor binds its own
        gl_ctx.error  # noqa: B018 - reading it clears an older error
        bare.render(fbo, size, mode, moving=True)
        assert gl_ctx.error == "GL_NO_ERROR"
        for (obj, _, _), lighting, lit_rows in zip(bare.objects, bare.lighting, lit_by_renderer, strict=True):
            first, stop = lighting.rows[mode]
            assert (first, stop) == (lit_rows.first, lit_rows.stop)
            vertices = surface_arrays(obj.mesh).vertices
            lit = np.frombuffer(lighting.lit.read(), np.float32).reshape(-1, 4)
            assert np.array_equal(lit[first:stop, :3], vertices[first:stop, :3])
            assert np.all(lit[first:stop, 3] == 1.0)
            assert np.all(lit[:first] == -7.0) and np.all(lit[stop:] == -7.0)
    finally:
        fbo.release()
        bare.release()
        renderer.release()


def test_a_ratio_below_a_hundredth_keeps_its_figures() -> None:
    """A C parser beside ours on a 200-triangle file is some hundred times quicker: never 0.00."""
    assert [ratio(*pair) for pair in [(1.0, 3.0), (0.000141, 0.0366), (5e-6, 1.0), (1.0, None)]] == [
        "0.33", "0.00385", "5e-06", MISSING]


def test_a_reader_that_leaves_ends_the_bench_and_a_full_output_is_one_line(tmp_path: Path) -> None:
    """`marraztu bench | head`: the bench stops at its next table, with no traceback; /dev/full is one line."""
    shapes_only = [sys.executable, "-m", "marraztu", "bench", *TINY_ARGS, "--sections", "shapes",
                   "--workdir", str(tmp_path)]
    reader, writer = os.pipe()
    os.close(reader)
    try:
        gone = subprocess.run(shapes_only, stdout=writer, stderr=subprocess.PIPE, text=True, timeout=300,
                              env=buffered_environment())
    finally:
        os.close(writer)
    assert gone.returncode == 0 and gone.stderr == "", gone.stderr
    with open("/dev/full", "w") as full:
        filled = subprocess.run(shapes_only, stdout=full, stderr=subprocess.PIPE, text=True, timeout=300,
                                env=buffered_environment())
    assert filled.returncode == 1 and filled.stderr == (
        "error: cannot write to standard output (No space left on device)\n"), filled.stderr
