"""What the GPU cannot hold is said in one line, never drawn wrong in silence: a texture wider than
GL_MAX_TEXTURE_SIZE is scaled down with a note, a framebuffer beyond the context's limits is refused,
and a GL error after an upload is an error, not a black picture."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import moderngl
import numpy as np
import pytest
from PIL import Image

from marraztu.errors import ViewerError
from marraztu.render import context as gl_context
from marraztu.render.renderer import Renderer
from support import corpus

COLOUR = (200, 120, 60)


def run_app(*args: str, cwd: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "marraztu", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=180)


def test_a_texture_past_the_gpu_limit_is_scaled_down_with_a_note(tmp_path: Path, gl_ctx) -> None:
    limit = int(gl_ctx.info["GL_MAX_TEXTURE_SIZE"])
    Image.new("RGB", (limit + 1, 1), COLOUR).save(tmp_path / "wide.png")
    Image.new("RGB", (4, 1), COLOUR).save(tmp_path / "small.png")
    wide = run_app("screenshot", "-o", "wide_shot.png", "--size", "96x96", "--texture", "wide.png", cwd=tmp_path)
    assert wide.returncode == 0, wide.stderr
    assert f"scaled to {limit}x1" in wide.stderr and len(wide.stderr.strip().splitlines()) == 1
    small = run_app("screenshot", "-o", "small_shot.png", "--size", "96x96", "--texture", "small.png", cwd=tmp_path)
    assert small.returncode == 0, small.stderr
    # A uniform picture stays uniform when scaled: the objects look exactly as with a small texture.
    shot = np.asarray(Image.open(tmp_path / "wide_shot.png"))
    assert np.array_equal(shot, np.asarray(Image.open(tmp_path / "small_shot.png")))
    assert (np.abs(shot.astype(int) - [0, 0, 178]).sum(axis=2) > 30).mean() > 0.02, "nothing drawn"


def test_the_renderer_refuses_a_texture_it_cannot_hold(own_ctx) -> None:
    from marraztu.model.scene import SceneObject
    from support.scenes import PLAIN, quad_mesh, scene_with

    limit = int(own_ctx.info["GL_MAX_TEXTURE_SIZE"])
    scene = scene_with([SceneObject.placed("quad", quad_mesh(), PLAIN, (0, 0, 0))], texture=True)
    scene.texture = np.zeros((1, limit + 1, 3), np.uint8)
    corpus.make_current(own_ctx)
    renderer = Renderer(own_ctx)
    try:
        with gl_context.offscreen_framebuffer(own_ctx, (8, 8)) as fbo:
            with pytest.raises(ViewerError, match=f"larger than this OpenGL takes \\({limit}"):
                renderer.render(scene, fbo, (8, 8))
    finally:
        renderer.release()


def test_a_framebuffer_past_the_context_limit_is_refused_in_one_line(tmp_path: Path, own_ctx, monkeypatch) -> None:
    monkeypatch.setattr(gl_context, "max_framebuffer_side", lambda ctx: 64)
    corpus.make_current(own_ctx)
    with pytest.raises(ViewerError, match="65x10 is larger than this OpenGL can draw \\(64x64"):
        with gl_context.offscreen_framebuffer(own_ctx, (65, 10)):
            pass


def test_reading_a_picture_without_the_memory_for_it_is_one_line(own_ctx, monkeypatch) -> None:
    corpus.make_current(own_ctx)
    with gl_context.offscreen_framebuffer(own_ctx, (8, 8)) as fbo:
        def no_memory(*args, **kwargs):
            raise MemoryError

        monkeypatch.setattr(moderngl.Framebuffer, "read", no_memory)
        with pytest.raises(ViewerError, match="not enough memory to read a 8x8 picture"):
            gl_context.read_pixels(fbo, (8, 8))


def test_a_gl_error_is_reported_and_cleared(own_ctx) -> None:
    from marraztu.render.mipmaps import _gl

    gl = _gl()
    if gl is None:
        pytest.skip("no glvnd libOpenGL to make a GL error with")
    corpus.make_current(own_ctx)
    gl_context.check_gl(own_ctx, "nothing")  # no error: passes
    gl.glEnable(0xFFFF)  # not a capability: GL_INVALID_ENUM
    with pytest.raises(ViewerError, match="the GPU refused a test upload \\(GL_INVALID_ENUM\\)"):
        gl_context.check_gl(own_ctx, "a test upload")
    gl_context.check_gl(own_ctx, "nothing")  # reading the error cleared it


def test_offscreen_framebuffers_leave_nothing_behind(own_ctx) -> None:
    """moderngl's Framebuffer.release keeps the colour and depth buffers alive: F12 and the screenshot
    command lost both at every picture until they were released too."""
    corpus.make_current(own_ctx)
    with gl_context.offscreen_framebuffer(own_ctx, (32, 32)):  # binds the default framebuffer once
        pass
    before = corpus.live_gl_objects(own_ctx)
    with corpus.DroppedGlObjects(own_ctx) as dropped:
        for _ in range(5):
            with gl_context.offscreen_framebuffer(own_ctx, (32, 32)):
                pass
    assert dropped.leaked == 0 and corpus.live_gl_objects(own_ctx) == before


def test_edges_of_more_polygons_than_their_tables_hold_are_refused_in_one_line(own_ctx, monkeypatch) -> None:
    from marraztu.model.scene import Fill, SceneObject
    from marraztu.render import gpu
    from support.scenes import PLAIN, mesh_from_polygons, scene_with

    limit = int(own_ctx.info["GL_MAX_TEXTURE_SIZE"])
    monkeypatch.setattr(gpu, "EDGE_FACE_TEXTURE_SIDE", 1)  # one polygon a row: limit + 1 rows is one too many
    strip = [(float(i // 2), float(i % 2), 0.0) for i in range(limit + 3)]
    mesh = mesh_from_polygons("strip", strip, [(i, i + 1, i + 2) for i in range(limit + 1)])
    scene = scene_with([SceneObject.placed("strip", mesh, PLAIN, (0, 0, 0))])
    scene.modes.fill = Fill.LINES
    corpus.make_current(own_ctx)
    renderer = Renderer(own_ctx)
    try:
        with gl_context.offscreen_framebuffer(own_ctx, (8, 8)) as fbo:
            refusal = f"more polygons \\({limit + 1}\\) than this OpenGL can draw the edges of"
            with pytest.raises(ViewerError, match=refusal):
                renderer.render(scene, fbo, (8, 8))
    finally:
        renderer.release()


def test_a_file_texture_the_gpu_refuses_is_released(own_ctx, monkeypatch) -> None:
    """A GL error after a material's picture is uploaded raises, and the texture it made is let go: it
    was kept by nothing and freed by no one."""
    from marraztu.model.mesh import MeshMaterial
    from marraztu.model.scene import SceneObject
    from marraztu.render import renderer as renderer_module
    from support.scenes import PLAIN, quad_mesh, scene_with

    picture = np.full((4, 4, 3), 200, np.uint8)
    mesh = quad_mesh()
    mesh = type(mesh)(**{**vars(mesh), "materials": (MeshMaterial("painted", {}, picture, "map_Kd"),),
                         "face_material": np.zeros(mesh.face_count, np.int32)})
    scene = scene_with([SceneObject.placed("quad", mesh, PLAIN, (0, 0, 0))], texture=True)
    corpus.make_current(own_ctx)
    renderer = Renderer(own_ctx)
    released: list[object] = []
    original = renderer_module.MipmappedTexture.release
    monkeypatch.setattr(renderer_module.MipmappedTexture, "release",
                        lambda self: (released.append(self), original(self))[1])

    def refused(ctx, what: str) -> None:
        if what.startswith("a texture of 4x4"):
            raise ViewerError(f"the GPU refused {what} (GL_OUT_OF_MEMORY)")

    monkeypatch.setattr(renderer_module, "check_gl", refused)
    try:
        with gl_context.offscreen_framebuffer(own_ctx, (8, 8)) as fbo:
            with pytest.raises(ViewerError, match="refused a texture of 4x4"):
                renderer.render(scene, fbo, (8, 8))
        assert len(released) == 1 and not renderer._file_textures
    finally:
        renderer.release()


@pytest.mark.parametrize(("gl", "glsl"), [("3.3", "330"), ("4.1", "410")])  # the least asked for; macOS's most
def test_a_context_of_an_older_gl_draws_the_same_picture(tmp_path: Path, gl_ctx, gl: str, glsl: str) -> None:
    """Mesa can offer an older GL than it has: under GL 3.3, or macOS's 4.1, no compute lighting pass and no
    shader past that version's GLSL may be needed. Every view the equation shows, against the same keys drawn
    with the GL this machine has."""
    if "Mesa" not in gl_ctx.info["GL_VERSION"]:
        pytest.skip("only Mesa takes MESA_GL_VERSION_OVERRIDE")
    keys = "c t Z*8 c c r T 0 1 2 3 F l n i TAB TAB ENTER*3 P m"
    pictures = {}
    for name, env in (("now", {}), ("older", {"MESA_GL_VERSION_OVERRIDE": gl, "MESA_GLSL_VERSION_OVERRIDE": glsl})):
        out = tmp_path / f"{name}.png"
        done = subprocess.run([sys.executable, "-m", "marraztu", "screenshot", "-o", str(out), "--size", "480x300",
                               "--keys", keys, "--overlay"], capture_output=True, text=True, timeout=180,
                              env={**os.environ, **env})
        assert done.returncode == 0, done.stderr
        pictures[name] = np.asarray(Image.open(out).convert("RGB")).astype(int)
    assert (np.abs(pictures["now"] - pictures["older"]).max(axis=2) > 1).sum() == 0
    assert (np.abs(pictures["now"] - [0, 0, 178]).sum(axis=2) > 30).mean() > 0.05, "almost blank"
