"""The lighting pass as a compute program (llvmpipe: every thread lights rows, where a vertex stage
uses one) writes the very bytes the transform-feedback pass writes, window by window, and so draws
the same pixels. It lights large passes only; GPUs and GL before 4.3 keep transform feedback."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import moderngl
import numpy as np
import pytest

from marraztu.loaders.scenefile import DEFAULT_MATERIAL, load_builtin_scene
from marraztu.model.build import build_mesh
from marraztu.model.scene import Scene, SceneObject, Shading
from marraztu.render import gpu as gpu_module
from marraztu.render import renderer as renderer_module
from marraztu.render.context import COMPUTE_GL_VERSION, lights_by_compute
from marraztu.render.gpu import (
    COLOUR_ROW_BYTES,
    COMPUTE_LIGHTING_MIN_ROWS,
    LIGHTING_GROUP_ROWS,
    LIT_ROW_BYTES,
    SURFACE_ROW_BYTES,
    ObjectGpu,
    lighting_window_rows,
)
from marraztu.render.renderer import Renderer
from support import corpus
from support.scenes import BACKGROUND, builtin_pictures_with

SMALL_WINDOW = 64  # rows a dispatch: the built-in scene's objects take many windows, from unaligned rows


class FakeContext:
    def __init__(self, renderer: str, version_code: int) -> None:
        self.info = {"GL_RENDERER": renderer}
        self.version_code = version_code


def test_compute_lighting_on_llvmpipe_with_gl_4_3_only(gl_ctx: moderngl.Context) -> None:
    assert lights_by_compute(FakeContext("llvmpipe (LLVM 15.0.6, 256 bits)", 450))  # type: ignore[arg-type]
    for renderer, version in (("llvmpipe (LLVM 15.0.6, 256 bits)", 330), ("NVIDIA H100 80GB HBM3/PCIe/SSE2", 460),
                              ("zink (llvmpipe (LLVM 15.0.6, 256 bits))", 460)):
        assert not lights_by_compute(FakeContext(renderer, version))  # type: ignore[arg-type]
    expected = gl_ctx.info["GL_RENDERER"].startswith("llvmpipe") and gl_ctx.version_code >= 430
    assert lights_by_compute(gl_ctx) == expected


def test_a_window_is_aligned_and_fits_the_limits(gl_ctx: moderngl.Context) -> None:
    if gl_ctx.version_code < COMPUTE_GL_VERSION:
        pytest.skip("no compute programs before OpenGL 4.3")
    rows = lighting_window_rows(gl_ctx)
    assert all(rows * size % 256 == 0 for size in (SURFACE_ROW_BYTES, COLOUR_ROW_BYTES, LIT_ROW_BYTES))
    assert rows * SURFACE_ROW_BYTES <= gl_ctx.info["GL_MAX_SHADER_STORAGE_BLOCK_SIZE"]
    assert -(-rows // LIGHTING_GROUP_ROWS) <= gl_ctx.info["GL_MAX_COMPUTE_WORK_GROUP_COUNT"][0]


def skip_unless_llvmpipe_computes(ctx: moderngl.Context) -> None:
    """Only llvmpipe lights by compute; its compute and vertex stages read colour bytes alike."""
    if not lights_by_compute(ctx):
        pytest.skip("the compute lighting pass is llvmpipe's (with OpenGL 4.3)")


@pytest.fixture(scope="module")
def both_renderers(own_ctx):
    skip_unless_llvmpipe_computes(own_ctx)
    corpus.make_current(own_ctx)
    renderers = (Renderer(own_ctx, compute_lighting=True), Renderer(own_ctx, compute_lighting=False))
    yield renderers
    corpus.make_current(own_ctx)
    for renderer in renderers:
        renderer.release()


def coloured_scene(side: int = 40) -> Scene:
    """The built-in scene's lights and camera around a bumpy grid of side x side vertices, with seeded
    vertex colours."""
    rng = np.random.default_rng(7)
    x, y = np.meshgrid(np.linspace(-150, 150, side), np.linspace(-150, 150, side))
    positions = np.column_stack([x.ravel(), y.ravel(), rng.uniform(-8, 8, side * side)])
    corner = (np.arange(side - 1)[:, None] * side + np.arange(side - 1)[None, :]).ravel()
    quads = np.column_stack([corner, corner + 1, corner + side + 1, corner + side])
    colours = rng.integers(0, 256, (side * side, 4))
    mesh = build_mesh("grid", positions, quads, vertex_colours=colours)
    scene = load_builtin_scene()
    scene.objects = [SceneObject.placed("grid", mesh, DEFAULT_MATERIAL, (0.0, 0.0, 0.0))]
    scene.selected_object = 0
    for light in scene.lights:
        light.on = True
    return scene


@pytest.mark.parametrize("shading", [Shading.FLAT, Shading.GOURAUD])
@pytest.mark.parametrize("window", [None, SMALL_WINDOW])
def test_compute_pass_writes_the_bytes_of_transform_feedback(own_ctx, both_renderers, monkeypatch, shading,
                                                             window) -> None:
    """Every lit row, vertex colours included (read as the unpacked bytes the vertex fetch reads)."""
    compute, feedback = both_renderers
    monkeypatch.setattr(gpu_module, "COMPUTE_LIGHTING_MIN_ROWS", 0)
    if window is not None:
        small = replace(compute.programs.compute_lighting, window_rows=window)
        monkeypatch.setattr(compute, "programs", replace(compute.programs, compute_lighting=small))
    scene = coloured_scene()
    scene.modes.shading = shading
    pictures, lit = [], []
    for renderer in (compute, feedback):
        pixels = corpus.render_float(own_ctx, renderer, scene, (96, 72))
        pictures.append(pixels)
        gpu = renderer._gpu_for(scene.objects[0])
        assert gpu.shared.vertex_coloured
        lit.append(gpu.lit.read())
        renderer.release_object(scene.objects[0])
    assert (np.round(pictures[0][..., :3] * 255) != np.array(BACKGROUND)).any(axis=2).mean() > 0.2, "not blank"
    assert lit[0] == lit[1]
    assert np.array_equal(pictures[0], pictures[1])


@pytest.mark.parametrize("keys", ["", "F", "v*3", "v*7", "b r x*5", "o ENTER*3", "F o ENTER*5", "p F", "s"])
def test_compute_and_transform_feedback_draw_the_same_pictures(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                               keys: str, gl_ctx: moderngl.Context) -> None:
    """The built-in scene through the screenshot command, the compute pass in windows of 64 rows."""
    skip_unless_llvmpipe_computes(gl_ctx)
    monkeypatch.setattr(renderer_module, "lighting_window_rows", lambda ctx: SMALL_WINDOW)
    monkeypatch.setattr(gpu_module, "COMPUTE_LIGHTING_MIN_ROWS", 0)
    by_compute, by_feedback = builtin_pictures_with(monkeypatch, renderer_module, "lights_by_compute", (True, False),
                                                    tmp_path, keys)
    assert (by_compute != np.array(BACKGROUND, np.uint8)).any(axis=2).sum() > 20, "not blank: one face at least"
    assert np.array_equal(by_compute, by_feedback)


def test_only_large_passes_are_lit_by_compute(own_ctx, both_renderers, monkeypatch) -> None:
    """Below COMPUTE_LIGHTING_MIN_ROWS rows waking llvmpipe's threads costs more than it saves."""
    compute, _ = both_renderers
    by_compute: list[tuple[int, int]] = []
    light_by_compute = ObjectGpu._light_by_compute

    def noted(gpu: ObjectGpu, compute, shading: Shading, first: int, stop: int) -> None:
        by_compute.append((first, stop))
        light_by_compute(gpu, compute, shading, first, stop)

    monkeypatch.setattr(ObjectGpu, "_light_by_compute", noted)
    for side, expected in ((40, []), (100, [(10000, 19801)])):  # Flat: the 9801 polygons' own rows
        scene = coloured_scene(side)
        by_compute.clear()
        corpus.render_float(own_ctx, compute, scene, (32, 32))
        compute.release_object(scene.objects[0])
        assert 39 * 39 < COMPUTE_LIGHTING_MIN_ROWS <= 99 * 99
        assert by_compute == expected
