"""Degenerate geometry renders without NaN pixels or GL errors, in every drawing mode.

Models come from inline OBJ text through the real reader (marraztu.loaders.obj.parse_obj) and are drawn by
the real renderer through the viewer's camera. Pixels are read from a float32 colour buffer, where a
NaN from the shaders stays a NaN instead of being clamped to a byte.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest

from marraztu.control.keymap import KeyPress
from marraztu.control.viewer import Viewer
from marraztu.loaders.obj import parse_obj
from marraztu.loaders.scenefile import DEFAULT_MATERIAL, load_builtin_scene
from marraztu.model.mesh import Mesh
from marraztu.model.scene import Scene, SceneObject
from marraztu.render.renderer import Renderer
from support import corpus
from support.scenes import BACKGROUND_FLOAT, NoFrontend, RenderingViewer

SIZE = (48, 48)
BACKGROUND = np.array(BACKGROUND_FLOAT)


def triangle_scaled(scale: float, offset: float = 0.0) -> bytes:
    corners = [(-scale, -scale, 0.0), (scale, -scale, 0.0), (0.0, scale, 0.0)]
    lines = [f"v {x + offset!r} {y + offset!r} {z!r}" for x, y, z in corners]
    return ("\n".join(lines) + "\nf 1 2 3\n").encode()


def box_scaled(scale: float) -> bytes:
    """A closed cube `scale` across: front and back faces both exist for culling to act on."""
    h = scale / 2
    points = [(-h, -h, -h), (h, -h, -h), (h, h, -h), (-h, h, -h), (-h, -h, h), (h, -h, h), (h, h, h), (-h, h, h)]
    faces = ["5 6 7 8", "2 1 4 3", "6 2 3 7", "1 5 8 4", "8 7 3 4", "1 2 6 5"]
    return ("\n".join(f"v {x!r} {y!r} {z!r}" for x, y, z in points) + "\n"
            + "\n".join(f"f {face}" for face in faces) + "\n").encode()


DEGENERATE_MODELS: dict[str, bytes] = {
    "zero_area_faces": b"v 0 0 0\nv 10 0 0\nv 20 0 0\nv 0 10 0\nf 1 2 3\nf 1 2 4\nf 3 2 1\n",
    "only_zero_area_faces": b"v -10 0 0\nv 0 0 0\nv 10 0 0\nf 1 2 3\nf 3 2 1\n",
    "coincident_vertices": b"v 5 5 5\nv 5 5 5\nv 5 5 5\nf 1 2 3\nf 1 1 1\n",
    "one_point_repeated": b"v 0 0 0\nf 1 1 1 1 1\n",
    "vertices_without_faces": b"v -20 -20 0\nv 20 -20 0\nv 0 20 0\nv 900 900 900\nv -900 0 0\nf 1 2 3\n",
    "zero_length_vertex_normal": b"v -20 -20 0\nv 20 -20 0\nv 0 20 0\nvn 0 0 0\nvn 0 0 1\n"
                                 b"f 1//1 2//1 3//2\n",
    "all_normals_zero": b"v -20 -20 0\nv 20 -20 0\nv 0 20 0\nvn 0 0 0\nf 1//1 2//1 3//1\n",
    "tiny_normal": b"v -20 -20 0\nv 20 -20 0\nv 0 20 0\nvn 0 0 1e-300\nf 1//1 2//1 3//1\n",
    "texcoords_far_outside": b"v -20 -20 0\nv 20 -20 0\nv 0 20 0\nvt -1e30 1e30\nvt 1e6 -7\n"
                             b"f 1/1 2/2 3/1\n",
    "bow_tie_polygon": b"v -20 -20 0\nv 20 20 0\nv 20 -20 0\nv -20 20 0\nf 1 2 3 4\n",
    "flat_line_polygon": b"v -20 0 0\nv -10 0 0\nv 0 0 0\nv 10 0 0\nv 20 0 0\nf 1 2 3 4 5\n",
    "micro_1e-6_across": box_scaled(1e-6),
    "mega_1e6_across": box_scaled(1e6),
    "far_from_origin_small": triangle_scaled(1.0, offset=1e7),
    "micro_1e-30_across": triangle_scaled(1e-30),
    "mega_1e30_across": triangle_scaled(1e30),
}

# Each is a key sequence pressed from the start state: every way the renderer draws a mesh.
MODES = {
    "filled_flat": "",
    "filled_gouraud_lit": "F 0 1 2 3",
    "lines": "l",
    "lines_culling": "l b",
    "normals_flat": "n",
    "normals_gouraud": "n F",
    "culling_lit": "b 0 1 2 3",
    "parallel": "p",
    "triangle_by_triangle": "o ENTER",
    "selected_only_lit_textured": "d 0 1 2 3 T",
    "look_through_the_object": "C",
    "analysis_camera_aimed": "c g",
    "lights_target_marker": "c c",
}


@pytest.fixture(scope="module")
def own_renderer(own_ctx) -> Iterator[Renderer]:
    """A renderer of this module's own, so the shared one keeps none of these odd meshes."""
    yield from corpus.own_renderer(own_ctx)


def viewer_with(mesh: Mesh, renderer: Renderer, with_builtin_scene: bool = False) -> Viewer:
    """The mesh as the selected object, seen from the built-in camera (and, optionally, with the
    built-in objects too, to see that the odd one spoils nothing else)."""
    scene = load_builtin_scene()
    if not with_builtin_scene:
        scene.objects.clear()
    scene.objects.append(SceneObject.placed(mesh.name, mesh, DEFAULT_MATERIAL, (0.0, 0.0, 0.0)))
    scene.selected_object = len(scene.objects) - 1
    return RenderingViewer(scene, renderer, NoFrontend())


def drawn_fraction(pixels: np.ndarray) -> float:
    return float((np.abs(pixels[..., :3] - BACKGROUND).sum(axis=2) > 0.02).mean())


@pytest.mark.parametrize("model", list(DEGENERATE_MODELS))
def test_degenerate_mesh_loads_with_finite_unit_normals(model: str) -> None:
    mesh = parse_obj(DEGENERATE_MODELS[model], f"{model}.obj")
    for normals in (mesh.face_normals, mesh.corner_normal):
        assert np.isfinite(normals).all()
        assert np.allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-3)
    assert np.isfinite(mesh.corner_uv).all()


@pytest.mark.parametrize("mode", list(MODES))
@pytest.mark.parametrize("model", list(DEGENERATE_MODELS))
def test_degenerate_mesh_renders_sane_pixels(model: str, mode: str, own_renderer: Renderer, own_ctx) -> None:
    mesh = parse_obj(DEGENERATE_MODELS[model], f"{model}.obj")
    viewer = viewer_with(mesh, own_renderer)
    viewer.press_sequence(MODES[mode])
    assert all(np.isfinite(obj.model).all() for obj in viewer.scene.objects + viewer.scene.cameras)
    corpus.assert_sane_pixels(corpus.render_float(own_ctx, own_renderer, viewer.scene, SIZE))


@pytest.mark.parametrize("model", ["zero_area_faces", "coincident_vertices", "mega_1e6_across"])
def test_degenerate_mesh_beside_the_builtin_scene_spoils_nothing(model: str, own_renderer: Renderer,
                                                                 own_ctx) -> None:
    """The other objects are drawn as they were without it (within a few pixels for the huge one,
    which hides part of the scene behind it)."""
    alone = load_builtin_scene()
    baseline = drawn_fraction(corpus.render_float(own_ctx, own_renderer, alone, SIZE))
    mesh = parse_obj(DEGENERATE_MODELS[model], f"{model}.obj")
    viewer = viewer_with(mesh, own_renderer, with_builtin_scene=True)
    pixels = corpus.render_float(own_ctx, own_renderer, viewer.scene, SIZE)
    corpus.assert_sane_pixels(pixels)
    assert drawn_fraction(pixels) >= baseline * 0.5


def test_mega_model_is_seen_when_the_camera_backs_away(own_renderer: Renderer, own_ctx) -> None:
    """A model 1e6 across is inside the far plane and shows when the camera stands back from it."""
    viewer = viewer_with(parse_obj(DEGENERATE_MODELS["mega_1e6_across"], "mega.obj"), own_renderer)
    camera = viewer.scene.camera
    camera.history[-1] = camera.model.copy()
    camera.history[-1][2, 3] = 3e6  # on +z, still looking toward -z
    pixels = corpus.render_float(own_ctx, own_renderer, viewer.scene, SIZE)
    corpus.assert_sane_pixels(pixels)
    assert 0.02 < drawn_fraction(pixels) < 0.98


def test_micro_model_is_seen_through_analysis_mode(own_renderer: Renderer, own_ctx) -> None:
    """Analysis mode aims at a 1e-6 model and `Z` comes closer; pixels stay sane all the way."""
    viewer = viewer_with(parse_obj(DEGENERATE_MODELS["micro_1e-6_across"], "micro.obj"), own_renderer)
    viewer.press_sequence("c g t" + " Z" * 40)
    for _ in range(3):
        corpus.assert_sane_pixels(corpus.render_float(own_ctx, own_renderer, viewer.scene, SIZE))
        viewer.press(KeyPress("p"))
    assert np.isfinite(viewer.scene.camera.model).all()


# Coordinates up to float32's largest finite value load; beyond it the loader refuses them.
@pytest.mark.parametrize("scale, refused", [(3e38, False), (1e39, True), (1e155, True), (1e300, True)])
def test_coordinates_at_or_beyond_float32_are_refused_or_harmless(scale: float, refused: bool,
                                                                  own_renderer: Renderer, own_ctx) -> None:
    """GL draws in float32. Past ~1e154 even float64 squares overflow: the bounding box diagonal, the
    far plane and the projection become inf/NaN and the WHOLE scene vanishes. Such a model must be
    refused (naming the line) or leave the other objects drawn as before."""
    from marraztu.errors import LoadError

    if refused:
        with pytest.raises(LoadError) as caught:
            parse_obj(triangle_scaled(scale), "huge.obj")
        assert caught.value.line == 1
        return
    mesh = parse_obj(triangle_scaled(scale), "huge.obj")
    baseline = drawn_fraction(corpus.render_float(own_ctx, own_renderer, load_builtin_scene(), SIZE))
    viewer = viewer_with(mesh, own_renderer, with_builtin_scene=True)
    with np.errstate(all="ignore"):
        pixels = corpus.render_float(own_ctx, own_renderer, viewer.scene, SIZE)
    corpus.assert_sane_pixels(pixels)
    assert drawn_fraction(pixels) >= baseline * 0.5, "the rest of the scene vanished"


def test_scene_of_degenerate_models_together(own_renderer: Renderer, own_ctx) -> None:
    """All of them in one scene, stepping through objects and faces in every mode."""
    scene: Scene = load_builtin_scene()
    for model, text in DEGENERATE_MODELS.items():
        mesh = parse_obj(text, f"{model}.obj")
        scene.objects.append(SceneObject.placed(model, mesh, DEFAULT_MATERIAL, (0.0, 0.0, 0.0)))
    viewer = RenderingViewer(scene, own_renderer, NoFrontend())
    for keys in MODES.values():
        for _ in range(len(scene.objects)):
            viewer.press_sequence(f"{keys} TAB ENTER")
            corpus.assert_sane_pixels(corpus.render_float(own_ctx, own_renderer, scene, (24, 24)))
