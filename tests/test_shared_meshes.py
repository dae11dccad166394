"""Objects that place one mesh (a scene file's model placed again and again) share its GPU buffers:
each holds only its own lit rows. The pictures are those of objects each with a copy of the mesh, and
the mesh's buffers go with the last object that draws it. A frame works out again only the matrices
of objects that moved."""

from __future__ import annotations

import gc
from pathlib import Path

import moderngl
import numpy as np
import pytest

from marraztu.loaders.registry import load_model
from marraztu.loaders.scenefile import load_builtin_scene
from marraztu.model.mesh import Mesh
from marraztu.model.scene import Fill, Material, Scene, SceneObject, Shading, TermView
from marraztu.render import renderer as renderer_module
from marraztu.render.gpu import LIT_ROW_BYTES, surface_arrays
from marraztu.render.renderer import Renderer
from marraztu.resources import ASSET_DIR
from support import corpus

RAMMER = ASSET_DIR / "rammer.obj"
SIZE = (160, 120)
COPIES = 5
MATERIALS = [Material(ka=(0.1 * k, 0.2, 0.3), kd=(0.5, 0.1 * k, 0.4), ks=(0.6, 0.5, 0.1 * k), ns=10.0 + 20 * k)
             for k in range(COPIES)]


@pytest.fixture(scope="module")
def own_renderer(own_ctx):
    yield from corpus.own_renderer(own_ctx)


def placed_scene(meshes: list[Mesh]) -> Scene:
    """The built-in scene's camera and lights (all on) over the meshes in a row, each turned and
    coloured its own way, so that no two are lit alike."""
    scene = load_builtin_scene()
    scene.objects = [SceneObject.placed(f"rammer {k}", mesh, MATERIALS[k], (-70.0 + 35 * k, 8.0 * k - 16.0, 40.0),
                                        (30.0 * k, 50.0 * k, 0.0)) for k, mesh in enumerate(meshes)]
    scene.selected_object = 0
    for light in scene.lights:
        light.on = True
    return scene


def buffer_census(ctx: moderngl.Context) -> tuple[int, int]:
    """How many GL buffers of `ctx` are alive (as corpus.live_gl_objects counts them), and their bytes."""
    gc.collect()
    buffers = [obj for obj in corpus.tracked_objects() if isinstance(obj, moderngl.Buffer) and obj.ctx is ctx
               and not isinstance(obj.mglo, moderngl.InvalidObject)]
    return len(buffers), sum(buffer.size for buffer in buffers)


def every_mode(ctx, renderer: Renderer, scene: Scene) -> list[np.ndarray]:
    """The scene's pictures in Flat, Gouraud and Phong, with normals, in lines, and in the depth view:
    everything an object and its mesh can build is built."""
    pictures = []
    for shading in Shading:
        scene.modes.shading = shading
        for normals in (False, True):
            scene.modes.normals = normals
            pictures.append(corpus.render_float(ctx, renderer, scene, SIZE))
    scene.modes.fill = Fill.LINES
    pictures.append(corpus.render_float(ctx, renderer, scene, SIZE))
    scene.modes.fill, scene.modes.term_view = Fill.FILLED, TermView.DEPTH
    pictures.append(corpus.render_float(ctx, renderer, scene, SIZE))
    scene.modes.term_view, scene.modes.normals, scene.modes.shading = TermView.EVERYTHING, False, Shading.FLAT
    return pictures


def test_objects_of_one_mesh_draw_what_objects_of_copies_draw(own_ctx, own_renderer) -> None:
    shared = placed_scene([load_model(RAMMER)] * COPIES)
    copies = placed_scene([load_model(RAMMER) for _ in range(COPIES)])
    for scene in (shared, copies):
        scene.texture = np.full((4, 4, 3), 200, np.uint8)
    pictures = [every_mode(own_ctx, own_renderer, scene) for scene in (shared, copies)]
    for scene in (shared, copies):
        for obj in scene.objects:
            own_renderer.release_object(obj)
    first = pictures[0][0]
    assert (np.abs(first[..., :3] - first[0, 0, :3]).max(axis=2) > 0.01).mean() > 0.04, "not blank"
    for one, other in zip(*pictures):
        assert np.array_equal(one, other)


def test_another_object_of_a_mesh_adds_only_its_lit_buffer(own_ctx, own_renderer) -> None:
    """A mesh's surface, edges and normals are built once for all its objects; each object adds one
    buffer, of a lit row per surface row."""
    corpus.make_current(own_ctx)
    mesh = load_model(RAMMER)
    empty = placed_scene([])
    corpus.render_float(own_ctx, own_renderer, empty, SIZE)
    before = buffer_census(own_ctx)
    held = []
    for count in (1, COPIES):
        scene = placed_scene([mesh] * count)
        every_mode(own_ctx, own_renderer, scene)
        held.append(buffer_census(own_ctx))
        for obj in scene.objects:
            own_renderer.release_object(obj)
    assert buffer_census(own_ctx) == before
    (one_buffers, one_bytes), (many_buffers, many_bytes) = held
    lit = surface_arrays(mesh).vertices.shape[0] * LIT_ROW_BYTES
    assert many_buffers - one_buffers == COPIES - 1
    assert many_bytes - one_bytes == (COPIES - 1) * lit
    assert one_bytes - before[1] > 3 * lit  # the shared buffers are the larger part


def test_a_mesh_s_buffers_go_with_its_last_object(own_ctx, own_renderer) -> None:
    corpus.make_current(own_ctx)
    mesh, other = load_model(RAMMER), load_model(RAMMER)
    scene = placed_scene([mesh] * 3)
    with corpus.DroppedGlObjects(own_ctx) as dropped:
        corpus.render_float(own_ctx, own_renderer, scene, SIZE)
        assert [shared.mesh for shared in own_renderer._meshes.held] == [mesh]
        scene.objects.pop()
        corpus.render_float(own_ctx, own_renderer, scene, SIZE)
        assert [shared.users for shared in own_renderer._meshes.held] == [2]
        scene.objects[0].mesh = other  # loading another model into an object
        corpus.render_float(own_ctx, own_renderer, scene, SIZE)
        assert sorted(shared.users for shared in own_renderer._meshes.held) == [1, 1]
        scene.objects.pop()
        corpus.render_float(own_ctx, own_renderer, scene, SIZE)
        assert [shared.mesh for shared in own_renderer._meshes.held] == [other]
        own_renderer.release_object(scene.objects[0])
        assert own_renderer._meshes.held == []
    assert dropped.leaked == 0


def test_a_frame_works_out_only_the_matrices_of_objects_that_moved(own_ctx, own_renderer, monkeypatch) -> None:
    inverted = []
    normal_matrix = renderer_module.normal_matrix
    monkeypatch.setattr(renderer_module, "normal_matrix", lambda model: inverted.append(1) or normal_matrix(model))
    scene = placed_scene([load_model(RAMMER)] * COPIES)
    corpus.render_float(own_ctx, own_renderer, scene, SIZE)
    assert len(inverted) == COPIES
    corpus.render_float(own_ctx, own_renderer, scene, SIZE)
    assert len(inverted) == COPIES  # a still frame: none
    moved = scene.objects[2]
    moved.history.append(moved.model @ np.diag([1.0, 2.0, 1.0, 1.0]))
    moved_picture = corpus.render_float(own_ctx, own_renderer, scene, SIZE)
    assert len(inverted) == COPIES + 1
    for obj in scene.objects:
        own_renderer.release_object(obj)
    assert np.array_equal(moved_picture, corpus.render_float(own_ctx, own_renderer, scene, SIZE))  # as if new


def test_a_watched_file_placed_many_times_keeps_one_set_of_buffers(own_ctx, own_renderer, tmp_path: Path) -> None:
    """--watch read a changed file once for each object a scene file placed from it: three objects of one
    model held one set of its buffers at start, and three after the file was saved."""
    import os

    from marraztu.control.viewer import StartOptions, Viewer
    from marraztu.loaders.scenefile import load_scene
    from support.scenes import NoFrontend

    model = tmp_path / "m.obj"
    model.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    path = tmp_path / "scene.toml"
    path.write_text('[[cameras]]\nposition = [0, 0, 10]\n'
                    + "".join(f'[[objects]]\nmodel = "m.obj"\nposition = [{x}, 0, 0]\n' for x in (-2, 0, 2)))
    viewer = Viewer(load_scene(path), NoFrontend())
    viewer.start(StartOptions(scene_file=path, watch=True), longest_texture_side=64)
    corpus.render_float(own_ctx, own_renderer, viewer.scene, SIZE)
    assert [shared.users for shared in own_renderer._meshes.held] == [3]
    before = model.stat().st_mtime_ns
    model.write_text("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
    os.utime(model, ns=(before + 2_000_000_000, before + 2_000_000_000))  # a new time on a coarse file system
    viewer.check_watched()
    corpus.render_float(own_ctx, own_renderer, viewer.scene, SIZE)
    try:
        assert [shared.users for shared in own_renderer._meshes.held] == [3]
        assert own_renderer._meshes.held[0].mesh.vertex_count == 4
    finally:
        for obj in viewer.scene.objects:
            own_renderer.release_object(obj)
