"""Shared fixtures: a headless EGL context, one renderer, and small meshes built straight from numpy."""

from __future__ import annotations

from typing import Callable, Iterator

import moderngl
import numpy as np
import pytest

from marraztu.model.mesh import Mesh
from marraztu.model.scene import Scene
from support import corpus
from support.scenes import box_mesh, mesh_from_polygons, quad_mesh, scene_with

OffscreenRender = Callable[..., np.ndarray]


@pytest.fixture(scope="session")
def gl_ctx() -> Iterator[moderngl.Context]:
    from marraztu.errors import ViewerError
    from marraztu.render.context import create_offscreen_context

    try:
        ctx = create_offscreen_context()
    except ViewerError as error:  # no OpenGL here: GL tests cannot run, the others still do
        pytest.skip(str(error))
    yield ctx
    ctx.release()


@pytest.fixture(scope="module")
def own_ctx():
    """A module's own EGL context, for tests that count its GL objects or must not share state;
    see corpus.own_gl_context for why not the session's."""
    yield from corpus.own_gl_context()


@pytest.fixture(scope="session")
def renderer(gl_ctx: moderngl.Context):
    from marraztu.render.renderer import Renderer

    corpus.make_current(gl_ctx)  # see `render` below
    shared = Renderer(gl_ctx)
    yield shared
    corpus.make_current(gl_ctx)
    shared.release()


@pytest.fixture(scope="session")
def offscreen(gl_ctx: moderngl.Context, renderer) -> Iterator[OffscreenRender]:
    """render(scene, size=(63, 63)) -> (H, W, 3) uint8, rows top first.

    Odd sizes put a pixel centre exactly on the view axis, where tests read their colours.
    """
    framebuffers: dict[tuple[int, int], moderngl.Framebuffer] = {}

    def render(scene: Scene, size: tuple[int, int] = (63, 63)) -> np.ndarray:
        # moderngl draws into whatever context is current and never switches back by itself; the
        # in-process screenshot tests make and release contexts of their own, so claim ours each time.
        corpus.make_current(gl_ctx)
        fbo = framebuffers.get(size)
        if fbo is None:
            fbo = gl_ctx.simple_framebuffer(size, components=4)
            framebuffers[size] = fbo
        renderer.render(scene, fbo, size)
        assert gl_ctx.error == "GL_NO_ERROR"
        width, height = size
        raw = fbo.read(components=3, alignment=1)
        return np.flipud(np.frombuffer(raw, np.uint8).reshape(height, width, 3))

    yield render
    for fbo in framebuffers.values():
        fbo.release()


@pytest.fixture
def make_quad() -> Callable[..., Mesh]:
    return quad_mesh


@pytest.fixture
def make_box() -> Callable[..., Mesh]:
    return box_mesh


@pytest.fixture
def make_scene() -> Callable[..., Scene]:
    return scene_with


@pytest.fixture
def build_mesh() -> Callable[..., Mesh]:
    return mesh_from_polygons
