"""Textures get their mip levels from numpy instead of glGenerateMipmap (app/mipmaps.py): the levels
must be the ones llvmpipe would have made, so that pictures do not change, and the GL texture must
go when it is released."""

from __future__ import annotations

import moderngl
import numpy as np
import pytest

from marraztu.render import mipmaps
from marraztu.render.mipmaps import create_mipmapped, mip_levels
from support import corpus

SIZES = [(256, 256), (64, 16), (16, 64), (1, 8), (8, 1), (1, 1)]


@pytest.fixture
def ctx(gl_ctx: moderngl.Context) -> moderngl.Context:
    corpus.make_current(gl_ctx)
    return gl_ctx


@pytest.fixture
def llvmpipe_ctx(ctx: moderngl.Context) -> moderngl.Context:
    if "llvmpipe" not in ctx.info["GL_RENDERER"]:
        pytest.skip("mip levels are the driver's choice; these are llvmpipe's")
    return ctx


@pytest.fixture
def glvnd() -> None:
    if mipmaps._gl() is None:
        pytest.skip("no glvnd libOpenGL here: textures take build_mipmaps")


def generated_texture(ctx: moderngl.Context, image: np.ndarray) -> moderngl.Texture:
    """What moderngl alone makes: the image, its levels from glGenerateMipmap, sampled trilinearly."""
    height, width = image.shape[:2]
    texture = ctx.texture((width, height), 3, image.tobytes(), alignment=1)
    texture.build_mipmaps()
    texture.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    return texture


def generated_levels(ctx: moderngl.Context, image: np.ndarray) -> list[np.ndarray]:
    height, width = image.shape[:2]
    texture = generated_texture(ctx, image)
    levels = []
    for level in range(max(width, height).bit_length()):
        w, h = max(1, width >> level), max(1, height >> level)
        levels.append(np.frombuffer(texture.read(level=level, alignment=1), np.uint8).reshape(h, w, 3))
    texture.release()
    return levels


@pytest.mark.parametrize("width,height", SIZES)
def test_the_levels_are_llvmpipes_bit_for_bit(llvmpipe_ctx: moderngl.Context, width: int, height: int) -> None:
    image = np.random.default_rng(width * 1000 + height).integers(0, 256, (height, width, 3), np.uint8)
    ours = mip_levels(image)
    theirs = generated_levels(llvmpipe_ctx, image)
    assert [level.shape for level in ours] == [level.shape for level in theirs]
    for index, (mine, generated) in enumerate(zip(ours, theirs)):
        assert np.array_equal(mine, generated), f"level {index} of {width}x{height}"


def test_a_level_rounds_halves_up_horizontal_pairs_first() -> None:
    # (1 + 2 + 1) >> 1 = 2 across, then (2 + 3 + 1) >> 1 = 3 down: not (1 + 2 + 3 + 4) / 4 = 2.5 -> 2.
    image = np.array([[[1] * 3, [2] * 3], [[3] * 3, [4] * 3]], np.uint8)
    assert mip_levels(image)[1].tolist() == [[[3, 3, 3]]]


def draw_minified(ctx: moderngl.Context, *textures) -> list[np.ndarray]:
    """Each 256-texel texture on a 37x37 quad: sampling reads levels 2 and 3."""
    program = ctx.program(
        vertex_shader="#version 330\nin vec2 in_position; out vec2 v_uv;"
                      "void main() { v_uv = in_position * 0.5 + 0.5; gl_Position = vec4(in_position, 0, 1); }",
        fragment_shader="#version 330\nuniform sampler2D u_texture; in vec2 v_uv; out vec4 f_colour;"
                        "void main() { f_colour = texture(u_texture, v_uv); }")
    quad = ctx.buffer(np.array([-1, -1, 1, -1, -1, 1, 1, 1], np.float32).tobytes())
    vao = ctx.vertex_array(program, [(quad, "2f", "in_position")])
    fbo = ctx.simple_framebuffer((37, 37), components=4)
    # A scope puts the earlier framebuffer binding back on exit: releasing a still-bound framebuffer
    # leaves moderngl binding a deleted name next time, an error the next test would find.
    scope = ctx.scope(framebuffer=fbo)
    pictures = []
    with scope:
        for texture in textures:
            fbo.clear()
            texture.use(location=0)
            vao.render(moderngl.TRIANGLE_STRIP)
            pictures.append(np.frombuffer(fbo.read(components=3), np.uint8).reshape(37, 37, 3).copy())
    for resource in (scope, vao, quad, program, fbo):
        resource.release()
    return pictures


def test_a_minified_texture_samples_as_with_generated_mipmaps(llvmpipe_ctx: moderngl.Context, glvnd) -> None:
    image = np.random.default_rng(7).integers(0, 256, (256, 256, 3), np.uint8)
    ours = create_mipmapped(llvmpipe_ctx, image)
    generated = generated_texture(llvmpipe_ctx, image)
    try:
        assert ours.external_name is not None, "a power-of-two image takes the numpy path"
        drawn, reference = draw_minified(llvmpipe_ctx, ours, generated)
        assert drawn.std() > 1.0, "not a blank picture"
        assert np.array_equal(drawn, reference)
        assert llvmpipe_ctx.error == "GL_NO_ERROR"
    finally:
        ours.release()
        generated.release()


def test_other_sizes_take_build_mipmaps(ctx: moderngl.Context) -> None:
    image = np.random.default_rng(3).integers(0, 256, (37, 100, 3), np.uint8)
    texture = create_mipmapped(ctx, image)
    assert texture.external_name is None
    assert texture.texture.filter == (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    texture.release()


def test_release_deletes_the_gl_texture(ctx: moderngl.Context, glvnd) -> None:
    texture = create_mipmapped(ctx, np.zeros((4, 4, 3), np.uint8))
    name = texture.external_name
    assert name is not None, "with glvnd, a power-of-two image takes the numpy path"
    gl = mipmaps._gl()
    assert gl.glIsTexture(name)
    texture.release()
    assert not gl.glIsTexture(name)
    assert ctx.error == "GL_NO_ERROR"
