"""--watch reads a changed scene file again whole, as at start, in the place of what it placed: its objects,
cameras, materials and texture. The modes, the lights and the selections stay, and so do the moves and undo
of each element whose placement in the file is as it was; the others stand where the file says. A scene
file that fails to read leaves the scene as it was and says where."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from marraztu.control.browse import ModelWatcher
from marraztu.control.keymap import parse_key_sequence
from marraztu.control.viewer import BackgroundLoader, StartOptions, Viewer, scene_file_watcher
from marraztu.loaders.scenefile import load_scene
from marraztu.model.scene import Projection, Shading, Target
from support.scenes import NoFrontend, collect_when_loaded

SQUARE = b"v -20 -20 0\nv 20 -20 0\nv 20 20 0\nv -20 20 0\nf 1 2 3 4\n"
TRIANGLE = b"v -10 -10 0\nv 10 -10 0\nv 0 10 0\nf 1 2 3\n"
CAMERA = '[[cameras]]\nposition = [0, 0, 80]\n'


def square_at(x: float, kd: str = "[0.2, 0.4, 0.6]") -> str:
    return (f'[[objects]]\nmodel = "square.obj"\nposition = [{x}, 0, 0]\n'
            f'material = {{ ka = [0, 0, 0], kd = {kd}, ks = [0, 0, 0], ns = 10 }}\n')


def rewrite(path: Path, content: str) -> None:
    """New content with a new modification time, even on a file system with coarse timestamps."""
    before = path.stat().st_mtime_ns
    path.write_text(content)
    os.utime(path, ns=(before + 2_000_000_000, before + 2_000_000_000))


def press(viewer: Viewer, keys: str) -> None:
    for key in parse_key_sequence(keys):
        viewer.press(key)


def watched(tmp_path: Path, content: str, background: BackgroundLoader | None = None,
            models: tuple[Path, ...] = ()) -> Viewer:
    (tmp_path / "square.obj").write_bytes(SQUARE)
    (tmp_path / "triangle.obj").write_bytes(TRIANGLE)
    path = tmp_path / "lesson.toml"
    path.write_text(content)
    options = StartOptions(scene_file=path, models=models, watch=True)
    seen = scene_file_watcher(options)  # as the window does: before the read
    viewer = Viewer(load_scene(path), NoFrontend(), background=background)
    viewer.start(options, longest_texture_side=4096, scene_watcher=seen)
    return viewer


def test_a_changed_kd_and_position_are_read_again_and_a_new_object_joins(tmp_path: Path) -> None:
    viewer = watched(tmp_path, CAMERA + square_at(0))
    viewer.check_watched()
    before = viewer.scene.objects[0]
    assert viewer.scene.objects == [before]  # nothing changed: nothing read
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(5, kd="[0.9, 0.1, 0.1]")
            + '[[objects]]\nmodel = "triangle.obj"\n')
    viewer.check_watched()
    square, triangle = viewer.scene.objects
    assert square is not before and square.material.kd == (0.9, 0.1, 0.1)
    assert np.array_equal(square.model[:3, 3], [5, 0, 0]) and triangle.mesh.vertex_count == 3
    assert viewer.scene.message == ("read lesson.toml again: 2 objects, 1 camera; placed where the file now says, "
                                    "their undo afresh: square, triangle")
    viewer.check_watched()
    assert viewer.scene.objects[0] is square  # one change, one read


def test_a_bad_edit_leaves_the_scene_as_it_was_and_says_where_then_the_next_save_is_read(tmp_path: Path) -> None:
    viewer = watched(tmp_path, CAMERA + square_at(0))
    objects, cameras = list(viewer.scene.objects), list(viewer.scene.cameras)
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(0) + 'position = [1, 2]\n')  # half written, or a slip
    viewer.check_watched()
    assert viewer.scene.objects == objects and viewer.scene.cameras == cameras
    message = viewer.scene.message
    assert message.startswith(f"{tmp_path / 'lesson.toml'}:") and "\n" not in message
    assert "position" in message
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(0) + '[[objects]]\nmodel = "nope.obj"\n')
    viewer.check_watched()
    assert viewer.scene.objects == objects and f"{tmp_path / 'lesson.toml'}:8: model" in viewer.scene.message
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(3))
    viewer.check_watched()
    assert np.array_equal(viewer.scene.object.model[:3, 3], [3, 0, 0])


def test_the_modes_lights_selections_and_moves_stay_where_only_a_material_changed(tmp_path: Path) -> None:
    viewer = watched(tmp_path, CAMERA * 2 + square_at(0) + square_at(30), models=(tmp_path / "triangle.obj",))
    scene = viewer.scene
    kept = scene.object  # the command line's triangle, selected as it joined: not the scene file's
    press(viewer, "t x F p b 1 2")  # the triangle moved; Gouraud, parallel, culling, two lights
    press(viewer, "c TAB c c TAB TAB x x")  # the second camera; then the second square, moved twice
    light_switches = [light.on for light in scene.lights]
    assert scene.objects[2] is kept and len(kept.history) == 2
    assert scene.object is scene.objects[1] and len(scene.object.history) == 3
    rewrite(tmp_path / "lesson.toml", CAMERA * 2 + square_at(0, kd="[1, 1, 1]") + square_at(30))
    viewer.check_watched()
    assert scene.modes.shading is Shading.GOURAUD and scene.modes.projection is Projection.PARALLEL
    assert scene.modes.culling and scene.modes.target is Target.OBJECTS
    assert [light.on for light in scene.lights] == light_switches and sum(light_switches) == 2
    assert scene.selected_camera == 1 and scene.selected_object == 1
    assert len(scene.object.history) == 3 and scene.object.model[0, 3] != 30  # its placement is as it was
    assert scene.objects[2] is kept and len(kept.history) == 2  # joined from elsewhere: stays as it was
    assert scene.objects[0].material.kd == (1.0, 1.0, 1.0)
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(0))  # fewer: the last of each it places
    viewer.check_watched()
    assert scene.selected_camera == 0 and scene.selected_object == 0 and scene.objects[1] is kept


def test_the_files_lights_are_the_scenes_at_start_and_an_edited_one_is_taken_when_it_is_read_again(
        tmp_path: Path) -> None:
    """A lesson's lights start as the file sets them; read again, the ambient and each light whose settings
    the save changed are set as it says now, the others stay as the person switched and moved them."""
    lights = "ambient = [10, 20, 30]\n[lights.bulb]\non = true\nposition = [0, 50, 0]\n"
    viewer = watched(tmp_path, lights + CAMERA + square_at(0))
    scene = viewer.scene
    bulb = scene.lights[1]
    assert bulb.on and np.array_equal(bulb.position, [0, 50, 0]) and np.array_equal(scene.ambient, [10, 20, 30])
    press(viewer, "c c TAB t x 3")  # the bulb, moved along x; the camera spotlight on
    moved = bulb.position.copy()
    assert moved[0] > 0 and scene.lights[3].on
    rewrite(tmp_path / "lesson.toml", lights + CAMERA + square_at(0, kd="[1, 1, 1]"))  # a material alone
    viewer.check_watched()
    assert scene.message == "read lesson.toml again: 1 object, 1 camera"
    assert bulb.on and np.array_equal(bulb.position, moved) and len(bulb.history) == 1
    assert [light.on for light in scene.lights] == [False, True, False, True]
    rewrite(tmp_path / "lesson.toml", "ambient = [9, 9, 9]\n[lights.bulb]\non = true\nposition = [0, 9, 0]\n"
            "[lights.sun]\non = true\n" + CAMERA + square_at(0, kd="[1, 1, 1]"))
    viewer.check_watched()
    assert scene.message == ("read lesson.toml again: 1 object, 1 camera; lights as the file now sets them: ambient, "
                             "sun, bulb")
    assert scene.lights[1] is bulb and np.array_equal(bulb.position, [0, 9, 0]) and bulb.history == []
    assert [light.on for light in scene.lights] == [True, True, False, True]  # the spotlight: as the key left it
    assert np.array_equal(scene.ambient, [9, 9, 9])
    rewrite(tmp_path / "lesson.toml", "ambient = [9, 9, 9]\n[lights.sun]\non = true\n" + CAMERA + square_at(0))
    viewer.check_watched()  # the bulb's table taken out: SPEC's, off at its place
    assert scene.message == "read lesson.toml again: 1 object, 1 camera; lights as the file now sets them: bulb"
    assert not bulb.on and np.array_equal(bulb.position, [0, 200, 0])


def test_only_the_values_a_save_changed_are_taken_so_a_light_switched_off_by_key_stays_off(tmp_path: Path) -> None:
    """A teacher switches the bulb off with 1, then edits only its intensity: the new intensity is taken,
    the switch and the place the keys gave it stay."""
    bulb_at = "[lights.bulb]\non = true\nposition = [0, 50, 0]\nintensity = [{0}, {0}, {0}]\n"
    viewer = watched(tmp_path, bulb_at.format(250) + CAMERA + square_at(0))
    bulb = viewer.scene.lights[1]
    press(viewer, "1 c c TAB t x")  # off, then moved
    moved = bulb.position.copy()
    rewrite(tmp_path / "lesson.toml", bulb_at.format(100) + CAMERA + square_at(0))
    viewer.check_watched()
    assert viewer.scene.message.endswith("lights as the file now sets them: bulb")
    assert not bulb.on and np.array_equal(bulb.intensity, [100, 100, 100])
    assert np.array_equal(bulb.position, moved) and len(bulb.history) == 1  # its move, and its undo


def test_a_bulb_the_file_places_stands_as_written_even_at_specs_place(tmp_path: Path) -> None:
    """Fitting to the models' units moves only a bulb the file leaves unplaced: one written at (0, 200, 0)
    stays there, as one written at (0, 199, 0) does, at start and read again."""
    tiny = '[[objects]]\nmodel = "square.obj"\nscale = 0.001\n'
    viewer = watched(tmp_path, "[lights.bulb]\nposition = [0, 200, 0]\n" + tiny)
    bulb = viewer.scene.lights[1]
    assert viewer.scene.fitted_unit != 1.0 and np.array_equal(bulb.position, [0, 200, 0])
    rewrite(tmp_path / "lesson.toml", "[lights.bulb]\non = true\nposition = [0, 200, 0]\n" + tiny)
    viewer.check_watched()
    assert bulb.on and np.array_equal(bulb.position, [0, 200, 0])


def test_an_edited_bulb_at_specs_place_is_fitted_to_the_models_units_as_at_start(tmp_path: Path) -> None:
    tiny = '[[objects]]\nmodel = "square.obj"\nscale = 0.001\n'
    viewer = watched(tmp_path, "[lights.bulb]\non = false\n" + tiny)
    bulb = viewer.scene.lights[1]
    at_start = bulb.position.copy()
    assert at_start[1] < 200  # fitted with the models, as the built-in bulb is
    rewrite(tmp_path / "lesson.toml", "[lights.bulb]\non = true\n" + tiny)
    viewer.check_watched()
    assert bulb.on and np.array_equal(bulb.position, at_start)


def test_a_file_that_places_no_camera_is_framed_again(tmp_path: Path) -> None:
    viewer = watched(tmp_path, square_at(0))
    start = viewer.scene.camera.model
    rewrite(tmp_path / "lesson.toml", square_at(0) + square_at(200))
    viewer.check_watched()
    assert viewer.scene.camera.model[2, 3] > start[2, 3]  # further back: both squares framed
    assert len(viewer.scene.camera.history) == 1  # the start HOME comes back to, as at start


def test_on_the_windows_worker_the_scene_is_read_off_the_render_thread(tmp_path: Path) -> None:
    viewer = watched(tmp_path, CAMERA + square_at(0), BackgroundLoader())
    try:
        before = viewer.scene.object
        rewrite(tmp_path / "lesson.toml", CAMERA + square_at(7))
        viewer.check_watched()
        assert viewer.scene.message == "lesson.toml changed: reading it again"
        assert viewer.loading_lines()[0].startswith("loading lesson.toml: ")
        collect_when_loaded(viewer)
        assert viewer.scene.object is not before and np.array_equal(viewer.scene.object.model[:3, 3], [7, 0, 0])
        assert viewer.scene.message.startswith("read lesson.toml again: 1 object, 1 camera")
        rewrite(tmp_path / "lesson.toml", "[[objects]]\n")
        viewer.check_watched()
        collect_when_loaded(viewer)
        assert viewer.scene.object.model[0, 3] == 7 and "lesson.toml:1: " in viewer.scene.message
    finally:
        viewer.background.shutdown()


def test_a_pagedown_pressed_while_the_scene_file_is_read_again_goes_to_the_element_kept(tmp_path: Path) -> None:
    """The read again keeps the square (its entry did not change) in a new element: PageDown's load, asked
    for the element before, goes to that one, not lost as having left the scene."""
    viewer = watched(tmp_path, CAMERA + square_at(0), BackgroundLoader())
    try:
        press(viewer, "t x")
        rewrite(tmp_path / "lesson.toml", CAMERA + square_at(0, kd="[0.9, 0.1, 0.1]"))
        viewer.check_watched()  # the read again starts on the worker
        press(viewer, "PAGEDOWN")  # the next model in the folder, for the square that is still there
        collect_when_loaded(viewer)
        square = viewer.scene.object
        assert square.source.name == "triangle.obj" and square.mesh.vertex_count == 3
        assert square.material.kd == (0.9, 0.1, 0.1) and len(square.history) == 2  # the file's Kd, its moves
        assert "left the scene" not in viewer.scene.message and square.browsed is None
    finally:
        viewer.background.shutdown()


def test_a_model_changed_with_its_scene_file_is_read_with_it_once(tmp_path: Path, monkeypatch) -> None:
    from marraztu.loaders import scenefile

    read: list[Path] = []
    load_model = scenefile.load_model
    monkeypatch.setattr(scenefile, "load_model", lambda path, stage=None: read.append(path) or load_model(path))
    viewer = watched(tmp_path, CAMERA + square_at(0))
    read.clear()
    rewrite(tmp_path / "square.obj", TRIANGLE.decode())
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(1))
    viewer.check_watched()
    assert [path.name for path in read] == ["square.obj", "camera.obj"]
    assert viewer.scene.object.mesh.vertex_count == 3 and viewer.scene.message.startswith("read lesson.toml again")


def test_a_model_changed_with_a_bad_scene_file_is_read_again_in_its_place(tmp_path: Path) -> None:
    """The look that found both changed left the model to the scene file's read: that read failing,
    the model is read again at the next look, in its element's place."""
    viewer = watched(tmp_path, CAMERA + square_at(0))
    square = viewer.scene.object
    rewrite(tmp_path / "square.obj", TRIANGLE.decode())
    rewrite(tmp_path / "lesson.toml", CAMERA + "[[objects]]\n")
    viewer.check_watched()
    assert viewer.scene.object is square and square.mesh.vertex_count == 4 and "lesson.toml:3:" in viewer.scene.message
    viewer.check_watched()
    assert viewer.scene.object is square and square.mesh.vertex_count == 3
    assert viewer.scene.message.startswith("square.obj in place of square")


def test_a_model_saved_while_its_scene_file_was_read_is_read_again() -> None:
    """The elements a scene file's read placed stand as their files were seen when that read began, not
    when they joined: a model saved meanwhile may not be in what was read."""
    from marraztu.control.browse import Stamp
    from marraztu.model.mesh import Mesh
    from marraztu.model.scene import Material, Scene, SceneObject

    path = Path(__file__)
    made = [SceneObject.placed("a", Mesh.__new__(Mesh), Material((0, 0, 0), (0, 0, 0), (0, 0, 0), 1.0), (0, 0, 0),
                               source=path) for _ in range(2)]
    watcher = ModelWatcher()
    assert watcher.changed(Scene(objects=[], cameras=made[:1])) == []
    watcher.stand_as(made[1:], {path: Stamp(0, 0)})  # seen so as the read began; it is newer now
    assert watcher.changed(Scene(objects=[], cameras=made[1:])) == made[1:]


@pytest.mark.parametrize("kd", ["[0.2, 0.2, 0.2]", "[1, 0, 0]"])
def test_a_changed_kd_changes_the_picture(tmp_path: Path, offscreen, kd: str) -> None:
    viewer = watched(tmp_path, CAMERA + square_at(0))
    press(viewer, "0")  # a light on: Kd shows
    before = offscreen(viewer.scene)[31, 31]
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(0, kd=kd))
    viewer.check_watched()
    after = offscreen(viewer.scene)[31, 31]
    assert viewer.scene.lights[0].on and tuple(after) != tuple(before)
    if kd == "[1, 0, 0]":
        assert after[0] > before[0] and after[1] < before[1] and after[2] < before[2]
    else:  # red as it was: 0.2 before too
        assert abs(int(after[0]) - int(before[0])) <= 1 and after[1] < before[1] and after[2] < before[2]


def test_on_the_windows_worker_the_texture_is_read_off_the_render_thread_too(tmp_path: Path, monkeypatch) -> None:
    """A large picture takes a visible while to decode: the window would stop on each save."""
    import threading

    from PIL import Image

    from marraztu.control import viewer as viewer_module

    Image.new("RGB", (4, 4), (255, 0, 0)).save(tmp_path / "red.png")
    Image.new("RGB", (4, 4), (0, 255, 0)).save(tmp_path / "green.png")
    threads: list[str] = []
    read_picture = viewer_module.load_texture_or_fallback
    monkeypatch.setattr(viewer_module, "load_texture_or_fallback",
                        lambda path: threads.append(threading.current_thread().name) or read_picture(path))
    viewer = watched(tmp_path, 'texture = "red.png"\n' + CAMERA + square_at(0), BackgroundLoader())
    try:
        threads.clear()
        rewrite(tmp_path / "lesson.toml", 'texture = "green.png"\n' + CAMERA + square_at(0))
        viewer.check_watched()
        collect_when_loaded(viewer)
        assert tuple(viewer.scene.texture[0, 0]) == (0, 255, 0) and viewer.scene.texture_path.endswith("green.png")
        assert threads and all(name.startswith("model-loader") for name in threads)
        assert viewer.scene.message == "read lesson.toml again: 1 object, 1 camera"
    finally:
        viewer.background.shutdown()


def test_a_scene_file_caught_empty_while_an_editor_writes_it_is_not_read(tmp_path: Path) -> None:
    """An editor that writes in place empties the file first: a look between read it as a scene of no
    objects, and the selection fell to the first and stayed there after the whole save was read."""
    viewer = watched(tmp_path, CAMERA + square_at(0) + square_at(50))
    press(viewer, "TAB")
    path = tmp_path / "lesson.toml"
    rewrite(path, "")
    viewer.check_watched()
    assert len(viewer.scene.objects) == 2 and viewer.scene.selected_object == 1
    rewrite(path, CAMERA + square_at(0) + square_at(60))
    viewer.check_watched()
    assert len(viewer.scene.objects) == 2 and viewer.scene.selected_object == 1
    assert viewer.scene.objects[1].model[0, 3] == 60


def test_a_scene_file_caught_part_way_through_a_save_is_not_read(tmp_path: Path, monkeypatch) -> None:
    """An editor that writes in place, caught after the first entry: valid TOML of fewer entries, read as the
    scene, so that the second square left and came back with its moves lost. A file that changes while it is
    read is refused; the whole save is read at the next look."""
    from marraztu.loaders import scenefile

    viewer = watched(tmp_path, CAMERA + square_at(0) + square_at(50))
    press(viewer, "TAB t x")  # the second square moved
    moved = viewer.scene.object.model.copy()
    path, whole = tmp_path / "lesson.toml", CAMERA + square_at(0, kd="[0.9, 0.1, 0.1]") + square_at(50)
    read_file = scenefile.read_file

    def caught_part_way(at: Path, limit: int) -> bytes:
        data = read_file(at, limit=limit)
        rewrite(path, whole)  # the rest of the save, as the read ends
        return data

    rewrite(path, CAMERA + square_at(0, kd="[0.9, 0.1, 0.1]"))  # the first entry written: seen changed
    monkeypatch.setattr(scenefile, "read_file", caught_part_way)
    viewer.check_watched()
    assert len(viewer.scene.objects) == 2 and viewer.scene.objects[0].material.kd == (0.2, 0.4, 0.6)
    assert "changed as it was read again" in viewer.scene.message
    monkeypatch.setattr(scenefile, "read_file", read_file)
    viewer.check_watched()  # the whole save, seen changed again
    assert viewer.scene.objects[0].material.kd == (0.9, 0.1, 0.1)
    assert np.array_equal(viewer.scene.objects[1].model, moved)


def test_what_the_person_moved_stays_where_a_save_changed_only_a_material(tmp_path: Path) -> None:
    """A teacher flies the camera and moves a model, then saves a new Kd: the view and the model stay."""
    viewer = watched(tmp_path, CAMERA + square_at(0))
    press(viewer, "t x x c x c c")  # the square moved twice, the camera once
    square, camera = viewer.scene.object, viewer.scene.camera
    moved, looked_from = square.model.copy(), camera.model.copy()
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(0, kd="[0.9, 0.1, 0.1]"))
    viewer.check_watched()
    assert viewer.scene.object.material.kd == (0.9, 0.1, 0.1)
    assert np.array_equal(viewer.scene.object.model, moved) and len(viewer.scene.object.history) == 3
    assert np.array_equal(viewer.scene.camera.model, looked_from) and len(viewer.scene.camera.history) == 2
    assert viewer.scene.message == "read lesson.toml again: 1 object, 1 camera"
    press(viewer, "u")
    assert np.array_equal(viewer.scene.object.model, square.history[1])  # its undo came with it


def test_the_model_pagedown_chose_stays_where_the_entry_did_not_change(tmp_path: Path) -> None:
    """What the person did not edit stays: PageDown's model too, with the file's new material; an edited entry
    stands as the file says."""
    viewer = watched(tmp_path, CAMERA + square_at(0))
    press(viewer, "t x PAGEDOWN")
    chosen = viewer.scene.object
    assert chosen.name == "triangle" and chosen.mesh.vertex_count == 3
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(0, kd="[0.9, 0.1, 0.1]"))
    viewer.check_watched()
    kept = viewer.scene.object
    assert kept is not chosen and kept.name == "triangle" and kept.source == tmp_path / "triangle.obj"
    assert kept.mesh is chosen.mesh and kept.material.kd == (0.9, 0.1, 0.1) and len(kept.history) == 2
    assert viewer.scene.message == "read lesson.toml again: 1 object, 1 camera"
    press(viewer, "PAGEDOWN")  # on past the triangle, as before the read
    assert viewer.scene.object.source == tmp_path / "square.obj"
    press(viewer, "PAGEDOWN")
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(4))
    viewer.check_watched()
    assert viewer.scene.object.name == "square" and viewer.scene.object.mesh.vertex_count == 4


def test_an_element_whose_placement_changed_takes_the_files_and_the_others_stay(tmp_path: Path) -> None:
    viewer = watched(tmp_path, CAMERA + square_at(0) + square_at(30))
    press(viewer, "t x TAB x c x")  # both squares and the camera moved
    first, looked_from = viewer.scene.objects[0].model.copy(), viewer.scene.camera.model.copy()
    rewrite(tmp_path / "lesson.toml", '[[cameras]]\nposition = [0, 0, 90]\n' + square_at(0) + square_at(40))
    viewer.check_watched()
    kept, placed = viewer.scene.objects
    assert np.array_equal(kept.model, first) and len(kept.history) == 2
    assert np.array_equal(placed.model[:3, 3], [40, 0, 0]) and placed.history == [placed.model]
    assert not np.array_equal(viewer.scene.camera.model, looked_from) and viewer.scene.camera.model[2, 3] == 90
    assert viewer.scene.message == ("read lesson.toml again: 2 objects, 1 camera; placed where the file now says, "
                                    "their undo afresh: square, camera")


def test_elements_are_matched_by_name_so_one_added_before_them_moves_none(tmp_path: Path) -> None:
    named = '[[objects]]\nname = "left"\nmodel = "square.obj"\nposition = [-30, 0, 0]\n'
    viewer = watched(tmp_path, CAMERA + named + square_at(30))
    press(viewer, "t x TAB x")
    left, square = (obj.model.copy() for obj in viewer.scene.objects)
    rewrite(tmp_path / "lesson.toml", CAMERA + '[[objects]]\nmodel = "triangle.obj"\n' + square_at(30) + named)
    viewer.check_watched()
    triangle, after_square, after_left = viewer.scene.objects
    assert np.array_equal(after_square.model, square) and np.array_equal(after_left.model, left)
    assert triangle.history == [triangle.model] and viewer.scene.object is after_square  # the selection follows it
    assert viewer.scene.message.endswith("placed where the file now says, their undo afresh: triangle")


def test_a_file_without_cameras_frames_again_only_a_camera_not_moved(tmp_path: Path) -> None:
    viewer = watched(tmp_path, square_at(0))
    press(viewer, "c x")
    looked_from = viewer.scene.camera.model.copy()
    rewrite(tmp_path / "lesson.toml", square_at(0) + square_at(200))
    viewer.check_watched()
    assert np.array_equal(viewer.scene.camera.model, looked_from)


def _picture(path: Path, colour: tuple[int, int, int]) -> None:
    from PIL import Image

    before = path.stat().st_mtime_ns if path.exists() else None
    Image.new("RGB", (4, 4), colour).save(path)
    if before is not None:  # a new modification time, even on a file system with coarse timestamps
        os.utime(path, ns=(before + 2_000_000_000, before + 2_000_000_000))


def test_a_picture_the_file_names_is_watched_too(tmp_path: Path) -> None:
    _picture(tmp_path / "concrete.png", (255, 0, 0))
    _picture(tmp_path / "wall.png", (0, 0, 255))
    viewer = watched(tmp_path, 'texture = "wall.png"\n' + CAMERA + square_at(0) + 'texture = "concrete.png"\n')
    press(viewer, "t x")
    moved = viewer.scene.object.model.copy()
    viewer.check_watched()
    assert tuple(viewer.scene.object.picture[0, 0]) == (255, 0, 0)  # nothing changed: nothing read
    _picture(tmp_path / "concrete.png", (0, 255, 0))
    viewer.check_watched()
    assert tuple(viewer.scene.object.picture[0, 0]) == (0, 255, 0) and np.array_equal(viewer.scene.object.model, moved)
    assert viewer.scene.message.startswith("read lesson.toml again")
    _picture(tmp_path / "wall.png", (255, 255, 0))
    viewer.check_watched()
    assert tuple(viewer.scene.texture[0, 0]) == (255, 255, 0)


def test_a_picture_changed_is_read_on_the_windows_worker_and_said(tmp_path: Path) -> None:
    _picture(tmp_path / "concrete.png", (255, 0, 0))
    viewer = watched(tmp_path, CAMERA + square_at(0) + 'texture = "concrete.png"\n', BackgroundLoader())
    try:
        _picture(tmp_path / "concrete.png", (0, 255, 0))
        viewer.check_watched()
        assert viewer.scene.message == "concrete.png changed: reading lesson.toml again"
        collect_when_loaded(viewer)
        assert tuple(viewer.scene.object.picture[0, 0]) == (0, 255, 0)
    finally:
        viewer.background.shutdown()



def test_texture_false_read_again_takes_the_pictures_away_and_names_none_to_watch(tmp_path: Path) -> None:
    """A lesson edited to `texture = false` (the scene's and an object's): read again, as at start."""
    from marraztu.model.mesh import PLAIN_PICTURE

    _picture(tmp_path / "concrete.png", (255, 0, 0))
    _picture(tmp_path / "wall.png", (0, 0, 255))
    viewer = watched(tmp_path, 'texture = "wall.png"\n' + CAMERA + square_at(0) + 'texture = "concrete.png"\n')
    rewrite(tmp_path / "lesson.toml", "texture = false\n" + CAMERA + square_at(0) + "texture = false\n")
    viewer.check_watched()
    assert viewer.scene.texture is PLAIN_PICTURE and viewer.scene.object.picture is PLAIN_PICTURE
    assert viewer.scene.texture_plain and viewer.scene.message.startswith("read lesson.toml again")
    square = viewer.scene.object
    _picture(tmp_path / "concrete.png", (0, 255, 0))
    _picture(tmp_path / "wall.png", (255, 255, 0))
    viewer.check_watched()
    assert viewer.scene.object is square and viewer.scene.texture is PLAIN_PICTURE  # named no more: not read
    rewrite(tmp_path / "lesson.toml", 'texture = "wall.png"\n' + CAMERA + square_at(0))
    viewer.check_watched()
    assert tuple(viewer.scene.texture[0, 0]) == (255, 255, 0) and not viewer.scene.texture_plain


def test_the_scenes_texture_is_not_watched_where_the_command_line_names_one(tmp_path: Path) -> None:
    _picture(tmp_path / "wall.png", (0, 0, 255))
    _picture(tmp_path / "given.png", (255, 0, 0))
    path = tmp_path / "lesson.toml"
    (tmp_path / "square.obj").write_bytes(SQUARE)
    path.write_text('texture = "wall.png"\n' + CAMERA + square_at(0))
    options = StartOptions(scene_file=path, texture=tmp_path / "given.png", watch=True)
    viewer = Viewer(load_scene(path), NoFrontend())
    viewer.start(options, longest_texture_side=4096, scene_watcher=scene_file_watcher(options))
    square = viewer.scene.object
    _picture(tmp_path / "wall.png", (255, 255, 0))
    viewer.check_watched()
    assert viewer.scene.object is square and tuple(viewer.scene.texture[0, 0]) == (255, 0, 0)
    rewrite(path, 'texture = "wall.png"\n' + CAMERA + square_at(5))
    viewer.check_watched()
    assert viewer.scene.object is not square and tuple(viewer.scene.texture[0, 0]) == (255, 0, 0)

def test_a_picture_a_thousand_objects_name_is_stat_once_a_look_and_once_as_it_joins(tmp_path: Path,
                                                                                    monkeypatch) -> None:
    from marraztu.control import browse

    _picture(tmp_path / "concrete.png", (255, 0, 0))
    stats: list[Path] = []
    stamp = browse._stamp
    monkeypatch.setattr(browse, "_stamp", lambda path: stats.append(path) or stamp(path))
    viewer = watched(tmp_path, CAMERA + (square_at(0) + 'texture = "concrete.png"\n') * 1000)
    assert stats.count(tmp_path / "concrete.png") == 1
    viewer.check_watched()
    assert stats.count(tmp_path / "concrete.png") == 2

@pytest.mark.parametrize("named", ["picture", "model", "half-written model"])
def test_a_file_a_failed_read_named_is_watched_until_it_comes(tmp_path: Path, named: str) -> None:
    """A teacher names a picture or a model, then makes it: its save reads the scene file again, as a save of
    the scene file would."""
    viewer = watched(tmp_path, CAMERA + square_at(0))
    if named == "half-written model":
        (tmp_path / "new.obj").write_text("v 1 2\n")
    entry = 'texture = "new.png"\n' if named == "picture" else '[[objects]]\nmodel = "new.obj"\n'
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(0) + entry)
    viewer.check_watched()
    assert viewer.scene.message.startswith(f"{tmp_path / 'lesson.toml'}:") and len(viewer.scene.objects) == 1
    if named == "picture":
        _picture(tmp_path / "new.png", (0, 255, 0))
    elif named == "model":
        (tmp_path / "new.obj").write_bytes(TRIANGLE)
    else:
        rewrite(tmp_path / "new.obj", TRIANGLE.decode())
    viewer.check_watched()
    assert viewer.scene.message.startswith("read lesson.toml again")
    if named == "picture":
        assert tuple(viewer.scene.object.picture[0, 0]) == (0, 255, 0)
    else:
        assert [obj.name for obj in viewer.scene.objects] == ["square", "new"]

def test_a_save_made_while_the_starts_models_load_is_read_once_they_have(tmp_path: Path, monkeypatch) -> None:
    from marraztu.loaders import scenefile

    path = tmp_path / "lesson.toml"
    load_model = scenefile.load_model

    def saved_meanwhile(model: Path, stage=None):
        if path.read_text() != CAMERA + square_at(9):
            rewrite(path, CAMERA + square_at(9))
        return load_model(model)

    monkeypatch.setattr(scenefile, "load_model", saved_meanwhile)
    viewer = watched(tmp_path, CAMERA + square_at(0))
    assert viewer.scene.object.model[0, 3] == 0  # read as it was when the read began
    monkeypatch.setattr(scenefile, "load_model", load_model)
    viewer.check_watched()
    assert viewer.scene.object.model[0, 3] == 9


def test_a_scene_file_read_again_tells_its_load_notes(tmp_path: Path) -> None:
    """An intensity written in 0..1 is noted at each read, as at start: the read again's message says it too."""
    viewer = watched(tmp_path, CAMERA + square_at(0))
    rewrite(tmp_path / "lesson.toml", "ambient = [1, 1, 1]\n" + CAMERA + square_at(0))
    viewer.check_watched()
    assert viewer.scene.message == ("read lesson.toml again: 1 object, 1 camera; lights as the file now sets them: "
                                    f"ambient; {tmp_path / 'lesson.toml'}:1: ambient [1, 1, 1] is in 0..255 units "
                                    "(so nearly dark): [255, 255, 255] is full white")


@pytest.mark.parametrize("on_the_worker", [False, True])
def test_a_scene_file_an_editor_empties_as_it_is_read_again_leaves_the_scene_as_it_was(
        tmp_path: Path, monkeypatch, on_the_worker: bool) -> None:
    """The look saw the save whole; the read after it, later on the window's worker, caught the next save
    part way (emptied, not yet written): read as a scene of no objects, it dropped every move and undo."""
    from marraztu.control import viewer as viewer_module

    viewer = watched(tmp_path, CAMERA + square_at(0) + square_at(30), BackgroundLoader() if on_the_worker else None)
    try:
        press(viewer, "t x TAB")
        path = tmp_path / "lesson.toml"
        saved = CAMERA + square_at(0) + square_at(30, kd="[1, 1, 1]")
        read_whole = viewer_module.load_scene

        def caught_emptied(scene_file: Path, stage=None, again: bool = False):
            rewrite(scene_file, "")  # an editor that writes in place, between truncating and writing
            try:
                return read_whole(scene_file, stage, again)
            finally:
                rewrite(scene_file, saved)

        monkeypatch.setattr(viewer_module, "load_scene", caught_emptied)
        rewrite(path, saved)
        viewer.check_watched()
        if on_the_worker:
            collect_when_loaded(viewer)
        first = viewer.scene.objects[0]
        assert len(viewer.scene.objects) == 2 and first.model[0, 3] == 5 and len(first.history) == 2
        assert viewer.scene.selected_object == 1 and "\n" not in viewer.scene.message
        assert viewer.scene.message.startswith(f"{path}: empty")
        monkeypatch.setattr(viewer_module, "load_scene", read_whole)
        viewer.check_watched()  # the save, whole now: read
        if on_the_worker:
            collect_when_loaded(viewer)
        first, second = viewer.scene.objects
        assert first.model[0, 3] == 5 and len(first.history) == 2 and second.material.kd == (1.0, 1.0, 1.0)
        assert viewer.scene.selected_object == 1
        assert viewer.scene.message == "read lesson.toml again: 2 objects, 1 camera"
    finally:
        if on_the_worker:
            viewer.background.shutdown()


def test_a_scene_file_gone_as_its_read_begins_and_ends_is_not_read(tmp_path: Path, monkeypatch) -> None:
    """An editor that deletes the file and writes it anew, its stamp looked at while it was gone, before
    the read and after: refused as a save under way (it raised AttributeError), read at the next look."""
    from marraztu.loaders import scenefile

    viewer = watched(tmp_path, CAMERA + square_at(0))
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(0, kd="[0.9, 0.1, 0.1]"))
    monkeypatch.setattr(scenefile, "file_stamp", lambda path: None)
    viewer.check_watched()
    assert viewer.scene.objects[0].material.kd == (0.2, 0.4, 0.6)
    assert "changed as it was read again" in viewer.scene.message
    monkeypatch.undo()
    rewrite(tmp_path / "lesson.toml", CAMERA + square_at(0, kd="[0.9, 0.1, 0.1]") + "\n")
    viewer.check_watched()
    assert viewer.scene.objects[0].material.kd == (0.9, 0.1, 0.1)
