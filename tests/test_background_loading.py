"""The window's loads run on a worker thread and join the scene between frames, in order."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from marraztu.control.viewer import BackgroundLoader, StartOptions, Viewer
from marraztu.loaders.scenefile import empty_scene
from marraztu.model.mesh import WHOLE
from support.scenes import NoFrontend, collect_when_loaded


def test_loads_join_the_scene_between_frames(tmp_path: Path) -> None:
    good = tmp_path / "good.obj"
    good.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nf 1 2 9\n")
    viewer = Viewer(empty_scene(), NoFrontend(), background=BackgroundLoader())
    viewer.load_model(good)
    assert viewer.scene.objects == [], "nothing joins until the frame collects it"
    collect_when_loaded(viewer)
    assert [obj.name for obj in viewer.scene.objects] == ["good"]
    assert "loaded good.obj" in viewer.scene.message

    before = [obj.model.copy() for obj in viewer.scene.objects]
    viewer.load_model(bad)
    collect_when_loaded(viewer)
    assert [obj.name for obj in viewer.scene.objects] == ["good"]
    assert all((a == b.model).all() for a, b in zip(before, viewer.scene.objects))
    assert "bad.obj:3" in viewer.scene.message
    viewer.background.shutdown()


def test_every_ended_load_wakes_the_window_after_it_can_be_collected(tmp_path: Path) -> None:
    """The window sleeps in the window system's wait between events: a load that ends must end that
    wait, or the model joins only at the next timeout."""
    good = tmp_path / "good.obj"
    good.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    woken: list[int] = []
    loader = BackgroundLoader(wake=lambda: woken.append(len(loader.finished())))
    viewer = Viewer(empty_scene(), NoFrontend(), background=loader)
    viewer.load_model(good)
    viewer.load_model(bad)
    collect_when_loaded(viewer)
    deadline = time.monotonic() + 60  # a future's callbacks run just after it reads as done
    while len(woken) < 2 and time.monotonic() < deadline:
        time.sleep(0.01)
    assert len(woken) == 2, "one wake per load, good or bad"
    assert woken[0] >= 1, "the first wake came when its load could be collected (the second was still loading)"
    assert [obj.name for obj in viewer.scene.objects] == ["good"] and "bad.obj" in viewer.scene.message
    viewer.background.shutdown()


def test_a_camera_load_stays_a_camera_even_if_the_target_changes_meanwhile(tmp_path: Path) -> None:
    good = tmp_path / "cam.obj"
    good.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    viewer = Viewer(empty_scene(), NoFrontend(), background=BackgroundLoader())
    viewer.press_sequence("c")  # target cameras
    viewer.load_model(good)
    viewer.press_sequence("c")  # target lights before the load lands
    collect_when_loaded(viewer)
    assert [cam.name for cam in viewer.scene.cameras][-1] == "cam"
    assert viewer.scene.cameras[viewer.scene.selected_camera].name == "cam"
    viewer.background.shutdown()


def test_the_worker_prepares_the_surface_and_the_first_frame_only_uploads_it(tmp_path: Path, renderer,
                                                                                offscreen) -> None:
    from marraztu.render import gpu

    good = tmp_path / "quad.obj"
    good.write_text("v -40 -40 0\nv 40 -40 0\nv 40 40 0\nv -40 40 0\nf 1 2 3 4\n")
    viewer = Viewer(empty_scene(), NoFrontend(), background=BackgroundLoader(gpu.prepare_surface))
    viewer.load_model(good)
    assert any("quad.obj" in line for line in viewer.loading_lines())
    collect_when_loaded(viewer)
    mesh = viewer.scene.objects[0].mesh
    prepared = gpu._prepared_surfaces.get(mesh, {}).get(WHOLE)
    expected = gpu.surface_arrays(mesh)
    assert prepared is not None and np.array_equal(prepared.triangles_before, mesh.triangles_before_face())
    prepared = prepared.surface
    assert np.array_equal(prepared.vertices, expected.vertices)
    assert np.array_equal(prepared.indices, expected.indices)
    assert np.array_equal(prepared.shared_indices, expected.shared_indices)

    viewer.press_sequence("T")  # texture off: the pure lit colour, ambient only (SPEC 3's start)
    pixels = offscreen(viewer.scene)
    assert mesh not in gpu._prepared_surfaces, "the first frame takes the prepared array"
    centre = pixels[pixels.shape[0] // 2, pixels.shape[1] // 2].astype(float)
    ambient_only = np.asarray(viewer.scene.objects[0].material.ka) * viewer.scene.ambient  # SPEC 4, 0..255
    assert np.abs(centre - ambient_only).max() <= 1.0, (centre, ambient_only)
    viewer.background.shutdown()


def test_a_model_of_two_materials_has_its_parts_prepared_and_nothing_left_after_its_first_frame(
        tmp_path: Path, offscreen) -> None:
    """The worker prepared the whole mesh's surface, which the renderer never draws where the mesh has
    parts (one per material, each drawn from its own arrays): kept for the object's life, a second set."""
    from marraztu.render import gpu

    (tmp_path / "m.mtl").write_text("newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n")
    model = tmp_path / "two.obj"
    model.write_text("mtllib m.mtl\nv -40 -40 0\nv 40 -40 0\nv 40 40 0\nv -40 40 0\n"
                     "usemtl red\nf 1 2 3\nusemtl blue\nf 1 3 4\n")
    viewer = Viewer(empty_scene(), NoFrontend(), background=BackgroundLoader(gpu.prepare_surface))
    viewer.load_model(model)
    collect_when_loaded(viewer)
    mesh = viewer.scene.objects[0].mesh
    assert len(mesh.parts) == 2 and sorted(gpu._prepared_surfaces[mesh]) == [0, 1]
    offscreen(viewer.scene)
    assert mesh not in gpu._prepared_surfaces
    viewer.background.shutdown()


def test_the_command_lines_models_are_told_together_however_their_loads_land(tmp_path: Path) -> None:
    """`marraztu --empty duck.glb teapot.obj` said of the duck, inside the teapot, only 'loaded duck.glb',
    where the screenshot command says it lies in the teapot's box: the window told the first load as
    soon as a frame collected it, before the teapot it lies in had joined."""
    small, big = tmp_path / "small.obj", tmp_path / "big.obj"
    small.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    big.write_text("v -5 -5 -5\nv 5 -5 -5\nv 0 5 5\nf 1 2 3\n")
    loader = BackgroundLoader()
    viewer = Viewer(empty_scene(), NoFrontend(), background=loader)
    viewer.start(StartOptions(empty=True, models=(small, big)), longest_texture_side=64)
    jobs = loader.uncollected()
    for job in jobs:  # a frame after each load lands, as the window's loop may draw one
        job.future.result(timeout=600)
        viewer.collect_loads()
    assert [obj.name for obj in viewer.scene.objects] == ["small", "big"]
    assert "loaded small.obj as a new object" in viewer.scene.message
    assert "inside big's bounding box" in viewer.scene.message, viewer.scene.message
    loader.shutdown()
