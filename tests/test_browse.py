"""PageDown / PageUp step through the model files of the selected element's folder, each in its place,
and --watch reads a model again when its file changes. A bad file keeps the scene as it was."""

from __future__ import annotations

import dataclasses
import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import marraztu
from marraztu.control.browse import ModelWatcher, model_files, sibling_model
from marraztu.control.keymap import parse_key_sequence
from marraztu.control.viewer import DARK_HINT, BackgroundLoader, StartOptions, Viewer
from marraztu.errors import LoadError
from marraztu.frontends.screenshot import take_screenshot
from marraztu.loaders.scenefile import empty_scene, load_builtin_scene
from support import corpus
from support.scenes import BACKGROUND, NoFrontend, collect_when_loaded

TRIANGLE = corpus.TRIANGLE + b"f 1 2 3\n"
# A square, 4 vertices and 1 face, to tell it from the triangle by its counts.
SQUARE = b"v -20 -20 0\nv 20 -20 0\nv 20 20 0\nv -20 20 0\nf 1 2 3 4\n"
SIZE = (96, 96)


def press(viewer: Viewer, keys: str) -> None:
    for key in parse_key_sequence(keys):
        viewer.press(key)


def folder_of(tmp_path: Path, **files: bytes) -> Path:
    for name, content in files.items():
        (tmp_path / name.replace("_", ".")).write_bytes(content)
    return tmp_path


def viewer_on(path: Path, watch: bool = False) -> Viewer:
    viewer = Viewer(empty_scene(), NoFrontend())
    viewer.start(StartOptions(empty=True, models=(path,), watch=watch), longest_texture_side=64)
    return viewer


# --- the folder ----------------------------------------------------------------------------------
def test_model_files_are_the_readable_suffixes_in_name_order(tmp_path: Path) -> None:
    folder_of(tmp_path, b_obj=TRIANGLE, A_OBJ=TRIANGLE, c_txt=b"", d_png=b"")
    (tmp_path / "e.obj").mkdir()  # a folder with a model's name is no model
    assert [path.name for path in model_files(tmp_path)] == ["A.OBJ", "b.obj"]


def test_sibling_wraps_both_ways_and_is_none_for_a_lone_file(tmp_path: Path) -> None:
    folder_of(tmp_path, a_obj=TRIANGLE, b_obj=TRIANGLE, c_obj=TRIANGLE)
    a, b, c = (tmp_path / name for name in ("a.obj", "b.obj", "c.obj"))
    assert [sibling_model(a, +1), sibling_model(c, +1), sibling_model(a, -1), sibling_model(b, -1)] == [b, a, c, a]
    lone = tmp_path / "lone"
    lone.mkdir()
    (lone / "only.obj").write_bytes(TRIANGLE)
    assert sibling_model(lone / "only.obj", +1) is None


def test_a_file_gone_from_its_folder_still_has_neighbours_by_its_name(tmp_path: Path) -> None:
    folder_of(tmp_path, a_obj=TRIANGLE, c_obj=TRIANGLE)
    assert sibling_model(tmp_path / "b.obj", +1) == tmp_path / "c.obj"
    assert sibling_model(tmp_path / "b.obj", -1) == tmp_path / "a.obj"


# --- PageDown / PageUp ---------------------------------------------------------------------------
def test_pagedown_replaces_the_selected_object_in_place_keeping_its_moves(tmp_path: Path) -> None:
    folder_of(tmp_path, a_obj=TRIANGLE, b_obj=SQUARE)
    viewer = viewer_on(tmp_path / "a.obj")
    press(viewer, "t x x")
    moved = viewer.scene.object.model.copy()
    press(viewer, "PAGEDOWN")
    obj = viewer.scene.object
    assert (obj.name, obj.mesh.vertex_count, obj.source) == ("b", 4, tmp_path / "b.obj")
    assert len(viewer.scene.objects) == 1 and np.array_equal(obj.model, moved)
    assert viewer.scene.message.startswith("b.obj in place of a: 4 vertices, 1 face")
    press(viewer, "PGUP u")  # the alias, then the moves are still there to undo
    assert obj.name == "a" and len(obj.history) == 2


def test_a_bad_next_file_keeps_the_scene_and_says_which_line(tmp_path: Path) -> None:
    folder_of(tmp_path, a_obj=TRIANGLE, b_obj=corpus.TRIANGLE + b"f 1 2 9\n")
    viewer = viewer_on(tmp_path / "a.obj")
    before = viewer.scene.object.mesh
    press(viewer, "PAGEDOWN")
    assert viewer.scene.object.mesh is before and viewer.scene.object.name == "a"
    assert "b.obj" in viewer.scene.message and "b.obj:4:" in viewer.scene.message


def test_pagedown_steps_past_a_bad_file_and_pageup_comes_back(tmp_path: Path) -> None:
    """A file that would not load is where the next step starts from, not a wall PageDown keeps hitting."""
    folder_of(tmp_path, a_obj=TRIANGLE, b_obj=corpus.TRIANGLE + b"f 1 2 9\n", c_obj=SQUARE)
    viewer = viewer_on(tmp_path / "a.obj")
    press(viewer, "PAGEDOWN")
    assert viewer.scene.object.name == "a" and "b.obj:4:" in viewer.scene.message
    press(viewer, "PAGEDOWN")
    assert viewer.scene.object.name == "c" and viewer.scene.object.mesh.face_count == 1
    press(viewer, "PAGEUP")
    assert viewer.scene.object.name == "c" and "b.obj:4:" in viewer.scene.message
    press(viewer, "PAGEUP")
    assert viewer.scene.object.name == "a"


def test_the_programming_interfaces_pagedown_steps_past_a_bad_file_too(tmp_path: Path) -> None:
    """Its press raised for the bad file and put everything back, where PageDown had got to as well:
    every later PageDown read the same bad file again, and the files past it could not be reached."""
    folder_of(tmp_path, a_obj=TRIANGLE, b_obj=corpus.TRIANGLE + b"f 1 2 9\n", c_obj=SQUARE)
    with marraztu.Viewer(size=SIZE, empty=True) as viewer:
        viewer.load(tmp_path / "a.obj")
        with pytest.raises(LoadError, match="b.obj:4:"):
            viewer.press("PAGEDOWN")
        assert viewer.scene.object.name == "a"
        viewer.press("PAGEDOWN")
        assert viewer.scene.object.name == "c" and viewer.scene.object.mesh.face_count == 1


@pytest.mark.parametrize(("step", "after"), [("PAGEDOWN", "b"), ("PAGEUP", "d")])
def test_a_press_put_back_past_a_good_file_steps_on_from_the_file_it_shows(tmp_path: Path, step: str,
                                                                          after: str) -> None:
    """press("PAGEDOWN PAGEDOWN") read b, then refused c, and put a back but kept c as where PageDown had
    got to: from a, PageDown read d (b passed over, never shown) and PageUp read b, the next file."""
    folder_of(tmp_path, a_obj=TRIANGLE, b_obj=SQUARE, c_obj=corpus.TRIANGLE + b"f 1 2 9\n", d_obj=SQUARE)
    with marraztu.Viewer(size=SIZE, empty=True) as viewer:
        viewer.load(tmp_path / "a.obj")
        with pytest.raises(LoadError, match="c.obj:4:"):
            viewer.press("PAGEDOWN PAGEDOWN")
        assert viewer.scene.object.name == "a"
        viewer.press(step)
        assert viewer.scene.object.name == after


def test_an_earlier_load_finishing_late_leaves_the_next_step_where_the_last_press_put_it(tmp_path: Path) -> None:
    """In the window loads finish later: b asked, then c; b arrives, c fails; the next press goes past c."""
    from marraztu.control.commands import replace_loaded
    from marraztu.control.viewer import load_model_object

    folder_of(tmp_path, a_obj=TRIANGLE, b_obj=SQUARE, c_obj=b"v 1 2\n", d_obj=TRIANGLE)
    viewer = viewer_on(tmp_path / "a.obj")
    element = viewer.scene.object
    element.browsed = tmp_path / "c.obj"  # the second press, whose load will fail
    replace_loaded(viewer.scene, element, load_model_object(tmp_path / "b.obj"))  # the first press's load, arriving now
    assert element.source == tmp_path / "b.obj" and element.browsed == tmp_path / "c.obj"
    press(viewer, "PAGEDOWN")
    assert viewer.scene.object.name == "d" and element.browsed is None


def test_the_strict_screenshot_refuses_a_bad_next_file(tmp_path: Path) -> None:
    folder_of(tmp_path, a_obj=TRIANGLE, b_obj=b"v 1 2\n")
    viewer = Viewer(empty_scene(), NoFrontend(), strict=True)
    viewer.start(StartOptions(empty=True, models=(tmp_path / "a.obj",)), longest_texture_side=64)
    with pytest.raises(LoadError, match="b.obj"):
        press(viewer, "PAGEDOWN")


@pytest.mark.parametrize(("keys", "said"), [
    ("PAGEDOWN", "no other model file beside a.obj"),
    ("c c PAGEDOWN", "no object or camera to replace (c: target objects or cameras)"),
])
def test_pagedown_with_nowhere_to_go_says_why(tmp_path: Path, keys: str, said: str) -> None:
    folder_of(tmp_path, a_obj=TRIANGLE)
    viewer = viewer_on(tmp_path / "a.obj")
    press(viewer, keys)
    assert viewer.scene.message == said and viewer.scene.object.name == "a"


def test_the_built_in_scene_steps_through_its_own_folder() -> None:
    viewer = Viewer(load_builtin_scene(), NoFrontend())
    first = viewer.scene.object
    was = first.source
    press(viewer, "PAGEDOWN")
    assert was is not None and viewer.scene.object is first
    assert first.source == sibling_model(was, +1) and first.source.parent == was.parent


def test_pagedown_draws_the_next_file_as_if_it_had_been_opened(tmp_path: Path) -> None:
    # The same bounding box, so that the lone model's framing is the same for both.
    folder_of(tmp_path, a_obj=b"v -20 -20 0\nv 20 -20 0\nv 20 20 0\nf 1 2 3\n", b_obj=SQUARE)
    stepped = take_screenshot(StartOptions(empty=True, models=(tmp_path / "a.obj",)), tmp_path / "stepped.png",
                              SIZE, keys="PAGEDOWN")
    opened = take_screenshot(StartOptions(empty=True, models=(tmp_path / "b.obj",)), tmp_path / "opened.png", SIZE)
    pixels = np.asarray(Image.open(stepped).convert("RGB"))
    assert np.array_equal(pixels, np.asarray(Image.open(opened).convert("RGB")))
    assert tuple(pixels[0, 0]) == BACKGROUND and (pixels != BACKGROUND).any(axis=2).sum() > 100  # not blank


def octahedron(size: float, centre: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> bytes:
    """A model of radius `size` round `centre`, its six tips on the axes through it."""
    tips = [(size, 0, 0), (-size, 0, 0), (0, size, 0), (0, -size, 0), (0, 0, size), (0, 0, -size)]
    faces = [(1, 3, 5), (3, 2, 5), (2, 4, 5), (4, 1, 5), (3, 1, 6), (2, 3, 6), (4, 2, 6), (1, 4, 6)]
    return ("".join(f"v {x + centre[0]:g} {y + centre[1]:g} {z + centre[2]:g}\n" for x, y, z in tips)
            + "".join(f"f {a} {b} {c}\n" for a, b, c in faces)).encode()


# PageDown keeps the camera (a view set up to compare same-size models stays); a file that this view
# does not show as it showed the one before is said, with the key that frames it.
@pytest.mark.parametrize(("next_file", "said"), [
    (octahedron(10.0, (3000.0, 0.0, 0.0)), "b is now outside the view (. frames it)"),
    (octahedron(0.001), "b is now too small to see from here (. frames it)"),
    (octahedron(0.1), "b is now much smaller than the view (. frames it)"),
    (octahedron(1000.0), "b is now much larger than the view (. frames it)"),
    (octahedron(20.0), None),
    (octahedron(5.0, (8.0, 0.0, 0.0)), None),
], ids=["far off", "a speck", "100 times smaller", "100 times larger", "twice as large", "half as large, aside"])
@pytest.mark.parametrize("projection", ["", "p"], ids=["perspective", "parallel"])
def test_pagedown_keeps_the_camera_and_says_when_the_next_file_is_not_seen_as_the_last(
        tmp_path: Path, next_file: bytes, said: str | None, projection: str) -> None:
    folder_of(tmp_path, a_obj=octahedron(10.0), b_obj=next_file)
    viewer = viewer_on(tmp_path / "a.obj")
    press(viewer, projection)
    camera = viewer.scene.camera.model.copy()
    press(viewer, "PAGEDOWN")
    first, *rest = viewer.scene.message.split("; ")
    assert first.startswith("b.obj in place of a: 6 vertices, 8 faces") and rest == ([said] if said else [])
    assert np.array_equal(viewer.scene.camera.model, camera)
    press(viewer, ".")
    assert viewer.scene.message == "framed b"
    press(viewer, "PAGEUP")  # back to a, in b's framing: said where b was
    assert ("; a is now" in viewer.scene.message) == (said is not None)


def test_pagedown_to_a_file_around_the_camera_says_so(tmp_path: Path) -> None:
    """The next file 1000 across round a view framed on one 10 across showed its inside with no word of why."""
    folder_of(tmp_path, a_obj=octahedron(10.0), b_obj=octahedron(1000.0))
    viewer = viewer_on(tmp_path / "a.obj")
    press(viewer, "PAGEDOWN")
    assert viewer.scene.message.split("; ")[0] == ("b.obj in place of a: 6 vertices, 8 faces, around the camera "
                                                   "(. frames it from outside)")
    press(viewer, "PAGEUP")
    assert "around the camera" not in viewer.scene.message


def test_a_file_loaded_in_the_background_is_said_out_of_view_when_it_joins(tmp_path: Path) -> None:
    """In the window PageDown's file joins a frame or more later: the notice comes with it."""
    folder_of(tmp_path, a_obj=octahedron(10.0), b_obj=octahedron(10.0, (3000.0, 0.0, 0.0)))
    viewer = Viewer(empty_scene(), NoFrontend(), background=BackgroundLoader())
    viewer.start(StartOptions(empty=True), longest_texture_side=64)
    viewer.load_model(tmp_path / "a.obj")
    collect_when_loaded(viewer)
    press(viewer, "PAGEDOWN")
    assert viewer.scene.message == "loading b.obj in place of a"
    collect_when_loaded(viewer)
    assert viewer.scene.message.endswith("; b is now outside the view (. frames it)")
    viewer.background.shutdown()


# --- --watch -------------------------------------------------------------------------------------
def rewrite(path: Path, content: bytes) -> None:
    """New content with a new modification time, even on a file system with coarse timestamps."""
    before = path.stat().st_mtime_ns
    path.write_bytes(content)
    os.utime(path, ns=(before + 2_000_000_000, before + 2_000_000_000))


def test_watch_reads_a_changed_file_again_and_keeps_the_scene_while_it_is_bad(tmp_path: Path) -> None:
    model = tmp_path / "a.obj"
    model.write_bytes(TRIANGLE)
    viewer = viewer_on(model, watch=True)
    obj = viewer.scene.object
    viewer.check_watched()
    assert obj.mesh.vertex_count == 3  # nothing changed: nothing read

    rewrite(model, b"v 1 2\n")  # half written
    viewer.check_watched()
    assert obj.mesh.vertex_count == 3 and "a.obj" in viewer.scene.message and "a.obj:1:" in viewer.scene.message

    rewrite(model, SQUARE)
    viewer.check_watched()
    assert viewer.scene.object is obj and obj.mesh.vertex_count == 4
    viewer.check_watched()
    assert "in place of" in viewer.scene.message  # one change, one reload


def test_without_watch_nothing_is_read_again(tmp_path: Path) -> None:
    model = tmp_path / "a.obj"
    model.write_bytes(TRIANGLE)
    viewer = viewer_on(model)
    rewrite(model, SQUARE)
    viewer.check_watched()
    assert viewer.scene.object.mesh.vertex_count == 3


def test_the_watcher_forgets_elements_that_left_and_tells_each_change_once(tmp_path: Path) -> None:
    model = tmp_path / "a.obj"
    model.write_bytes(TRIANGLE)
    viewer = viewer_on(model)
    watcher = ModelWatcher()
    assert watcher.changed(viewer.scene) == []
    rewrite(model, SQUARE)
    assert watcher.changed(viewer.scene) == [viewer.scene.object]
    assert watcher.changed(viewer.scene) == []
    viewer.scene.objects.clear()
    assert watcher.changed(viewer.scene) == [] and set(watcher._seen) == {viewer.scene.camera.uid}


def test_the_watcher_looks_at_a_file_many_elements_share_once(tmp_path: Path, monkeypatch) -> None:
    """--watch stat'ed the file of every element, twice a second: a scene file of 8,000 objects of one
    model took 8,000 stats and 28 ms each time, 6% of a core with the window left alone."""
    from marraztu.control import browse

    model = folder_of(tmp_path, a_obj=TRIANGLE, b_obj=SQUARE)
    viewer = viewer_on(model / "a.obj")
    for name in ("a.obj", "b.obj") * 20:
        viewer.load_model(model / name)
    stamped: list[Path] = []
    stamp = browse._stamp
    monkeypatch.setattr(browse, "_stamp", lambda path: stamped.append(path) or stamp(path))
    watcher = ModelWatcher()
    assert watcher.changed(viewer.scene) == []
    assert len(stamped) == 3 and set(stamped) == {model / "a.obj", model / "b.obj", viewer.scene.camera.source}
    rewrite(model / "b.obj", TRIANGLE)
    assert watcher.changed(viewer.scene) == [obj for obj in viewer.scene.objects if obj.source.name == "b.obj"]


def watched_scene_file(tmp_path: Path, background: BackgroundLoader | None) -> Viewer:
    """A scene file that places a.obj three times, twice at one scale (spelled two ways) and once at
    another, the first with a picture of its own, watched."""
    from marraztu.loaders.scenefile import load_scene

    folder_of(tmp_path, a_obj=TRIANGLE, c_obj=TRIANGLE)
    Image.new("RGB", (2, 2), (255, 0, 0)).save(tmp_path / "red.png")
    entries = ['model = "a.obj"\ntexture = "red.png"\n', 'model = "./a.obj"\nposition = [2, 0, 0]\n',
               'model = "a.obj"\nposition = [4, 0, 0]\nscale = 2\n']
    path = tmp_path / "scene.toml"
    path.write_text('[[cameras]]\nmodel = "c.obj"\nposition = [0, 0, 30]\n'
                    + "".join(f"[[objects]]\n{entry}" for entry in entries))
    viewer = Viewer(load_scene(path), NoFrontend(), background=background)
    viewer.start(StartOptions(scene_file=path, watch=True), longest_texture_side=64)
    return viewer


@pytest.mark.parametrize("in_background", [False, True], ids=["at once", "on the window's worker"])
def test_watch_reads_a_file_a_scene_places_many_times_once_and_its_objects_share_the_new_mesh(
        tmp_path: Path, monkeypatch, in_background: bool) -> None:
    """A scene file's objects of one model at one scale share its mesh (and its GPU buffers); a change on
    disk read the file again once for each object, giving each a copy of its own."""
    from marraztu.control import viewer as viewer_module

    read: list[Path] = []
    load_model = viewer_module.load_model
    monkeypatch.setattr(viewer_module, "load_model", lambda path, stage=None: read.append(path) or load_model(path))
    viewer = watched_scene_file(tmp_path, BackgroundLoader() if in_background else None)
    try:
        first, second, third = viewer.scene.objects
        picture = first.picture
        assert first.mesh is second.mesh and third.mesh is not first.mesh
        rewrite(tmp_path / "a.obj", SQUARE)
        viewer.check_watched()
        if in_background:
            collect_when_loaded(viewer)
    finally:
        if in_background:
            viewer.background.shutdown()
    assert len(read) == 2  # once for each scale
    assert first.mesh.vertex_count == 4 and first.mesh is second.mesh and third.mesh is not first.mesh
    assert np.array_equal(third.mesh.positions, first.mesh.positions * 2)
    assert first.picture is picture and second.picture is None  # each keeps its own texture
    assert [obj.source.name for obj in viewer.scene.objects] == ["a.obj"] * 3
    assert viewer.scene.camera.mesh.vertex_count == 3  # its own file did not change


def test_watch_replacing_the_many_objects_of_one_file_compares_each_element_a_few_times(
        tmp_path: Path, monkeypatch) -> None:
    """_replace_each asked of each element of a group whether it had left the scene by a pass over the
    objects and the cameras: elements times objects comparisons, where one set of them does."""
    from marraztu.loaders.scenefile import load_scene
    from marraztu.model.scene import SceneObject

    folder_of(tmp_path, a_obj=TRIANGLE, c_obj=TRIANGLE)
    count = 200
    path = tmp_path / "scene.toml"
    path.write_text('[[cameras]]\nmodel = "c.obj"\nposition = [0, 0, 30]\n'
                    + "".join(f'[[objects]]\nmodel = "a.obj"\nposition = [{index}, 0, 0]\n' for index in range(count)))
    viewer = Viewer(load_scene(path), NoFrontend())
    viewer.start(StartOptions(scene_file=path, watch=True), longest_texture_side=64)
    compared = {"elements": 0}

    def counting_eq(self: SceneObject, other: object) -> bool:
        compared["elements"] += 1
        return self is other

    monkeypatch.setattr(SceneObject, "__eq__", counting_eq)
    rewrite(tmp_path / "a.obj", SQUARE)
    viewer.check_watched()
    assert all(obj.mesh.vertex_count == 4 for obj in viewer.scene.objects)
    assert compared["elements"] <= 4 * count, compared


def test_watch_groups_elements_whose_scale_was_set_by_hand_as_a_list(tmp_path: Path) -> None:
    """read_together keyed its groups by the scale itself: one set by hand as a list (obj.scale = [1, 1, 1])
    raised "unhashable type: 'list'" at the next change on disk, where the file was read again before."""
    viewer = watched_scene_file(tmp_path, None)
    first, second, third = viewer.scene.objects
    first.scale = [1.0, 1.0, 1.0]
    rewrite(tmp_path / "a.obj", SQUARE)
    viewer.check_watched()
    assert first.mesh.vertex_count == 4 and first.mesh is second.mesh and third.mesh is not first.mesh


def test_watch_says_one_message_for_the_objects_of_one_file_with_what_only_some_of_them_are(tmp_path: Path) -> None:
    """Each element of a group read again set its own message and only the last showed: that the middle
    object is drawn black with every light off, and the others' names, were lost."""
    from marraztu.loaders.scenefile import load_scene

    folder_of(tmp_path, a_obj=TRIANGLE, c_obj=TRIANGLE)
    material = "kd = [0.5, 0.5, 0.5], ks = [0, 0, 0], ns = 10"
    entries = [f'name = "{name}"\nposition = [{x}, 0, 0]\nmaterial = {{ ka = [{ka}], {material} }}\n'
               for name, x, ka in (("a", 0, "0.2, 0.2, 0.2"), ("b", 2, "0, 0, 0"), ("c", 4, "0.2, 0.2, 0.2"))]
    path = tmp_path / "scene.toml"
    path.write_text('[[cameras]]\nmodel = "c.obj"\nposition = [0, 0, 30]\n'
                    + "".join(f'[[objects]]\nmodel = "a.obj"\n{entry}' for entry in entries))
    viewer = Viewer(load_scene(path), NoFrontend())
    viewer.start(StartOptions(scene_file=path, watch=True), longest_texture_side=64)
    rewrite(tmp_path / "a.obj", SQUARE + b"f 1 1 2\n")
    viewer.check_watched()
    assert viewer.scene.message == ("a.obj in place of a, b, c: 4 vertices, 2 faces (1 zero-area face (given a "
                                    "fallback normal)); b: black with every light off (its Ka is 0 0 0: 0 to 3 "
                                    "turn lights on)")
    for obj in viewer.scene.objects:  # a scene file's material stays through a read again
        obj.given_material = dataclasses.replace(obj.given_material, ka=(0.0, 0.0, 0.0))
    rewrite(tmp_path / "a.obj", SQUARE)
    viewer.check_watched()  # all three alike: said once, as one object's message says it
    assert viewer.scene.message == "a.obj in place of a, b, c: 4 vertices, 1 face" + DARK_HINT
