"""Shared fixtures: a headless EGL context, one renderer, and small meshes built straight from numpy."""

from __future__ import annotations

from typing import Callable, Iterator, Sequence

import corpus
import moderngl
import numpy as np
import pytest

from app.mesh import Mesh
from app.scene import Material, Scene, SceneObject

OffscreenRender = Callable[..., np.ndarray]
BACKGROUND = (0, 0, 178)  # SPEC 3: (0, 0, 0.7) in bytes


@pytest.fixture(scope="session")
def gl_ctx() -> Iterator[moderngl.Context]:
    try:
        ctx = moderngl.create_standalone_context(backend="egl")
    except Exception as error:  # no EGL, no driver: GL tests cannot run here, the others still do
        pytest.skip(f"no headless EGL OpenGL context: {error}")
    yield ctx
    ctx.release()


@pytest.fixture(scope="module")
def own_ctx():
    """A module's own EGL context, for tests that count its GL objects or must not share state;
    see corpus.own_gl_context for why not the session's."""
    yield from corpus.own_gl_context()


@pytest.fixture(scope="session")
def renderer(gl_ctx: moderngl.Context):
    from app.renderer import Renderer

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


# --- meshes built by hand ------------------------------------------------------------------------
def mesh_from_polygons(name: str, positions: Sequence[Sequence[float]],
                       polygons: Sequence[Sequence[int]],
                       uvs: Sequence[Sequence[float]] | None = None) -> Mesh:
    """A Mesh with Newell face normals and, per corner, the average normal of the faces at its vertex."""
    points = np.asarray(positions, float)
    corner_vertex = np.concatenate([np.asarray(p, np.int64) for p in polygons])
    face_start = np.concatenate([[0], np.cumsum([len(p) for p in polygons])]).astype(np.int64)
    face_normals = np.array([_newell(points[list(p)]) for p in polygons])
    vertex_sum = np.zeros_like(points)
    for polygon, normal in zip(polygons, face_normals):
        vertex_sum[list(polygon)] += normal
    vertex_normals = vertex_sum / np.linalg.norm(vertex_sum, axis=1, keepdims=True)
    corner_uv = (np.asarray(uvs, float)[corner_vertex] if uvs is not None
                 else np.zeros((corner_vertex.size, 2)))
    return Mesh(name=name, positions=points, corner_vertex=corner_vertex,
                corner_uv=corner_uv.astype(np.float32),
                corner_normal=vertex_normals[corner_vertex].astype(np.float32),
                face_start=face_start, face_normals=face_normals.astype(np.float32))


def _newell(points: np.ndarray) -> np.ndarray:
    following = np.roll(points, -1, axis=0)
    normal = np.array([
        np.sum((points[:, 1] - following[:, 1]) * (points[:, 2] + following[:, 2])),
        np.sum((points[:, 2] - following[:, 2]) * (points[:, 0] + following[:, 0])),
        np.sum((points[:, 0] - following[:, 0]) * (points[:, 1] + following[:, 1])),
    ])
    return normal / np.linalg.norm(normal)


def quad_mesh(half: float = 50.0, facing_camera: bool = True) -> Mesh:
    """A square in z = 0 centred on the origin, uv (0, 0) at its bottom-left; counter-clockwise seen
    from +z (normal +z) or, with facing_camera False, the other way round (normal -z)."""
    positions = [(-half, -half, 0), (half, -half, 0), (half, half, 0), (-half, half, 0)]
    uvs = [(0, 0), (1, 0), (1, 1), (0, 1)]
    polygon = [0, 1, 2, 3] if facing_camera else [0, 3, 2, 1]
    return mesh_from_polygons("quad", positions, [polygon], uvs)


def box_mesh(half: float = 30.0) -> Mesh:
    """A closed cube, outward normals, counter-clockwise seen from outside."""
    h = half
    positions = [(-h, -h, -h), (h, -h, -h), (h, h, -h), (-h, h, -h),
                 (-h, -h, h), (h, -h, h), (h, h, h), (-h, h, h)]
    faces = [[4, 5, 6, 7], [1, 0, 3, 2], [5, 1, 2, 6], [0, 4, 7, 3], [7, 6, 2, 3], [0, 1, 5, 4]]
    return mesh_from_polygons("box", positions, faces)


PLAIN = Material(ka=(0.2, 0.3, 0.4), kd=(0.6, 0.5, 0.4), ks=(0.5, 0.4, 0.3), ns=20.0)


def scene_with(objects: list[SceneObject], camera_at: tuple[float, float, float] = (0, 0, 150),
               texture: bool = False) -> Scene:
    """The objects, seen from a camera on +z looking toward -z; all lights off, texture off."""
    camera = SceneObject.placed("camera", quad_mesh(2.0), PLAIN, camera_at)
    scene = Scene(objects=objects, cameras=[camera])
    scene.modes.texture = texture
    return scene


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
