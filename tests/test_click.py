"""A left click (the window's, or `click=X,Y` in --keys) selects the object and the face drawn at that
pixel: the ray through the pixel's centre, in the view it falls in, met with what the picture draws.
The pictures are the judges: in Flat every face is one colour, the probe's, so each picked face's probe
colour must be the pixel's, and the background must be where nothing is picked."""

from __future__ import annotations

import warnings
from collections.abc import Callable
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from marraztu.control import commands
from marraztu.control.keymap import CLICK_TOKEN, KeyPress, click, parse_key_sequence
from marraztu.control.viewer import Viewer
from marraztu.errors import KeyMapError, ViewerError
from marraztu.model.build import build_mesh
from marraztu.model.geometry import segment_meets_box
from marraztu.model.picking import pick
from marraztu.model.probe import probe
from marraztu.model.scene import Material, Projection, Scene, SceneObject, Shading, Target
from marraztu.model.viewports import views
from support.scenes import BACKGROUND, PLAIN, NoFrontend, box_mesh, mesh_from_polygons, quad_mesh, scene_with

SIZE = (121, 91)
STEP_PX = 3  # the pixels checked: every third column and row
RED = Material(ka=(0.3, 0.1, 0.1), kd=(0.8, 0.2, 0.1), ks=(0.5, 0.5, 0.5), ns=30.0)


def lit(scene: Scene) -> Scene:
    """The sun and the bulb on: faces of one object differ in colour. Not the object spotlight, which
    moves with the selection that the checks change."""
    for light in scene.lights[:2]:
        light.on = True
    return scene


def two_boxes(projection: Projection = Projection.PERSPECTIVE) -> Scene:
    """Two turned cubes, the nearer hiding part of the farther."""
    near = SceneObject.placed("near", box_mesh(25.0), PLAIN, (-15.0, -5.0, 20.0), (25.0, 35.0, 0.0))
    far = SceneObject.placed("far", box_mesh(30.0), RED, (30.0, 15.0, -30.0), (-20.0, 50.0, 10.0))
    scene = lit(scene_with([near, far]))
    scene.modes.projection = projection
    if projection is Projection.PARALLEL:
        scene.modes.parallel_half_height = scene.matching_parallel_half_height()
    return scene


def back_over_front() -> Scene:
    """A square facing away from the camera (a back face), in front of a larger one facing it."""
    front = SceneObject.placed("front", quad_mesh(50.0), PLAIN, (0.0, 0.0, 0.0))
    back = SceneObject.placed("back", quad_mesh(20.0, facing_camera=False), RED, (0.0, 0.0, 30.0))
    return lit(scene_with([front, back]))


class Host:
    """The key map's host for a picture of SIZE."""

    def frame_size(self) -> tuple[int, int]:
        return SIZE


def colour_of(scene: Scene, obj: SceneObject, face: int) -> np.ndarray:
    """The colour the picture gives the face in Flat: the probe's, or red for a back face."""
    kept = scene.selected_object, obj.selected_face
    commands.select_face(scene, scene.objects.index(obj), face)
    found = probe(scene)
    scene.selected_object, obj.selected_face = kept
    return found.displayed(found.vertices[0])


def inner_pixels(picture: np.ndarray, columns: range) -> list[tuple[int, int]]:
    """The checked pixels whose 3x3 neighbours have their colour: none on an edge, where the
    rasteriser's rule for pixels shared by two triangles decides. `picture` may hold a colour, or a
    class, per pixel."""
    found = []
    for row in range(1, picture.shape[0] - 1, STEP_PX):
        for column in columns[::STEP_PX]:
            around = picture[row - 1:row + 2, column - 1:column + 2].reshape(9, -1)
            if (around == around[0]).all():
                found.append((column, row))
    return found


def check_picks(offscreen: Callable[..., np.ndarray], scene: Scene, columns: range | None = None,
                colours: bool = True) -> set[tuple[str, int]]:
    """Each checked pixel: the background where nothing is picked, else (`colours`) the picked face's
    colour. The faces picked, by object name."""
    picture = offscreen(scene, SIZE)
    picked = set()
    # Gouraud and Phong shade across a face: there only the background and the rest are told apart
    classes = picture if colours else (picture == BACKGROUND).all(axis=2)
    pixels = inner_pixels(classes, columns or range(1, SIZE[0] - 1))
    assert len(pixels) > 100
    for column, row in pixels:
        hit = pick(scene, SIZE, (column, row))
        shown = picture[row, column]
        if hit is None:
            assert tuple(shown) == BACKGROUND, (column, row)
            continue
        assert tuple(shown) != BACKGROUND, (column, row, hit.element.name, hit.face)
        if colours:
            assert tuple(shown) == tuple(colour_of(scene, hit.element, hit.face)), (column, row, hit.face)
        picked.add((hit.element.name, hit.face))
    return picked


@pytest.mark.parametrize("projection", list(Projection), ids=lambda p: p.value)
def test_each_pixel_picks_the_face_drawn_there(offscreen, projection: Projection) -> None:
    picked = check_picks(offscreen, two_boxes(projection))
    assert {name for name, _ in picked} == {"near", "far"}
    assert len(picked) >= 5  # three faces of the near cube, and of the far one what it leaves seen


def test_culling_on_picks_the_front_face_behind_a_back_face(offscreen) -> None:
    scene = back_over_front()
    centre = (SIZE[0] // 2, SIZE[1] // 2)
    assert pick(scene, SIZE, centre).element.name == "back"  # drawn red
    assert ("back", 0) in check_picks(offscreen, scene)
    scene.modes.culling = True
    assert pick(scene, SIZE, centre).element.name == "front"  # the back face is culled
    assert {name for name, _ in check_picks(offscreen, scene)} == {"front"}


def test_only_the_faces_drawn_with_o_and_d_are_picked(offscreen) -> None:
    scene = two_boxes()
    scene.objects[0].selected_face = 3
    scene.modes.triangle_only = True  # o: the near cube's faces up to the selected one
    picked = check_picks(offscreen, scene)
    assert picked and all(name == "near" and face <= 3 for name, face in picked)
    scene.modes.draw_all = False  # d: the selected face alone
    assert check_picks(offscreen, scene) == {("near", 3)}
    scene.modes.triangle_only = False  # the near cube alone, whole
    assert {name for name, _ in check_picks(offscreen, scene)} == {"near"}


def test_side_by_side_a_click_is_in_the_third_it_falls_in(offscreen) -> None:
    """Each third is the whole scene at its own aspect: the far cube, off to the right, is met at other
    pixels than in the whole window. In the Flat third the colours are the probe's too."""
    scene = two_boxes()
    scene.modes.side_by_side = True
    for view in views(scene, SIZE):
        x0, _, width, _ = view.viewport
        inside = range(x0 + 3, x0 + width - 3)  # clear of the lines between the thirds
        picked = check_picks(offscreen, scene, inside, colours=view.shading is Shading.FLAT)
        assert {name for name, _ in picked} == {"near", "far"}, view.title


def test_a_click_meets_the_triangles_of_the_objects_its_ray_reaches_alone(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each click met every triangle of every drawn object, 2 ms a click on the built-in scene whatever
    it hit, and `click=1,1*100000` a few times over took an hour. A ray that misses an object's box
    meets none of its triangles."""
    from marraztu.model import picking

    met: list[str] = []
    real = picking._met_in
    monkeypatch.setattr(picking, "_met_in", lambda element, *rest: met.append(element.name) or real(element, *rest))
    scene = two_boxes()
    assert pick(scene, SIZE, (0, 0)) is None and met == []  # the corner: the background
    hit = pick(scene, SIZE, (SIZE[0] // 2 - 10, SIZE[1] // 2))
    assert hit is not None and hit.element.name == "near" and met == ["near"]


@pytest.mark.parametrize("origin, direction, met", [
    ((0, 5, 0), (0, -10, 0), True),  # down onto a floor, a box 0 high
    ((0, 5, 0), (0, -4, 0), False),  # stops short of it
    ((0, 0.5, 0), (0, 1, 0), False),  # starts above it, going up
    ((0.5, 0, 0.5), (0, 0, 0), True),  # a point on it
    ((3, 5, 0), (0, -10, 0), False),  # beside it
    ((3, 0, 0), (-10, 0, 0), True),  # along it, edge on
    ((-5, 1e-12, 0), (10, 0, 0), True),  # along it, a hair above: within the billionth of its size
])
def test_a_segment_meets_a_box_as_a_ray_meets_what_it_holds(origin, direction, met: bool) -> None:
    low, high = np.array([-1.0, 0.0, -1.0]), np.array([1.0, 0.0, 1.0])
    assert segment_meets_box(np.array(origin, float), np.array(direction, float), low, high) is met


def test_a_click_selects_the_object_and_face_and_says_so() -> None:
    scene = two_boxes()
    scene.selected_object = 1
    centre = (SIZE[0] // 2 - 10, SIZE[1] // 2)
    hit = pick(scene, SIZE, centre)
    assert hit is not None and hit.element is scene.objects[0]
    commands.select_at(scene, Host(), centre)
    assert scene.selected_object == 0 and scene.object.selected_face == hit.face
    assert scene.message == f"near face {hit.face + 1} of 6 (i: its probe, P: its pipeline)"
    scene.modes.probe = True
    commands.select_at(scene, Host(), centre)
    assert scene.message.endswith("(the probe follows it)")


def test_thousands_of_faces_are_counted_with_commas_and_a_targeted_light_stays_targeted() -> None:
    cells = 50
    u, v = np.meshgrid(np.linspace(-40, 40, cells + 1), np.linspace(-40, 40, cells + 1), indexing="ij")
    first = (np.arange(cells)[:, None] * (cells + 1) + np.arange(cells)[None, :]).reshape(-1)
    quads = np.stack([first, first + cells + 1, first + cells + 2, first + 1], axis=1)
    grid = build_mesh("grid", np.stack([u.ravel(), v.ravel(), np.zeros(u.size)], axis=1), quads)
    scene = scene_with([SceneObject.placed("grid", grid, PLAIN, (0.0, 0.0, 0.0))])
    scene.modes.target = Target.LIGHTS
    commands.select_at(scene, Host(), (SIZE[0] // 2, SIZE[1] // 2))
    face = scene.object.selected_face
    assert face > 0 and scene.modes.target is Target.LIGHTS
    assert scene.message == f"grid face {face + 1:,} of 2,500 (i: its probe, P: its pipeline); lights stay targeted"


def test_a_click_on_the_background_or_a_camera_changes_nothing() -> None:
    scene = two_boxes()
    other = SceneObject.placed("spare camera", quad_mesh(10.0), PLAIN, (0.0, 0.0, 100.0))
    scene.cameras.append(other)  # drawn in front of the cubes, at the window's centre
    scene.selected_object, scene.objects[1].selected_face = 1, 4
    commands.select_at(scene, Host(), (0, 0))
    assert scene.message == "nothing drawn at 0,0 (the background): the selection stays"
    commands.select_at(scene, Host(), (SIZE[0] // 2, SIZE[1] // 2))
    assert scene.message.startswith("camera spare camera is drawn at")
    assert (scene.selected_object, scene.objects[1].selected_face, scene.selected_camera) == (1, 4, 0)


def test_a_click_across_a_zero_area_face_warns_of_nothing() -> None:
    """A sliver's corners on one line (a file's degenerate face, kept with a fallback normal) met the ray
    with a determinant of 0: u + v was inf - inf, and numpy printed "RuntimeWarning: invalid value
    encountered in add" on every such click."""
    corners = [(-50, 0, 0), (0, 0, 0), (50, 0, 0), (-50, -50, 0), (50, -50, 0), (0, 50, 0)]
    scene = scene_with([SceneObject.placed("sliver", mesh_from_polygons("sliver", corners, [[0, 1, 2], [3, 4, 5]]),
                                           PLAIN, (0.0, 0.0, 0.0))])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        hits = [pick(scene, SIZE, (SIZE[0] // 2, row)) for row in range(SIZE[1] // 2 - 2, SIZE[1] // 2 + 3)]
    assert [hit.face for hit in hits] == [1] * 5


def test_looking_through_an_object_a_click_does_not_jump_to_the_object_it_meets() -> None:
    """With C, the view is the selected object's: a click that selected the box it met put the eye inside
    that box, so the picture changed whole and the face the panels explained was no longer under the pointer."""
    eye = SceneObject.placed("eye", box_mesh(5.0), PLAIN, (0.0, 0.0, 0.0))
    scene = scene_with([eye, SceneObject.placed("ahead", box_mesh(20.0), PLAIN, (0.0, 0.0, -100.0))])
    scene.modes.view_from_object = True
    assert pick(scene, SIZE, (SIZE[0] // 2, SIZE[1] // 2)) is not None
    commands.select_at(scene, Host(), (SIZE[0] // 2, SIZE[1] // 2))
    assert scene.object is eye and scene.viewer is eye
    assert scene.message == "looking through eye: a click would look through what it selects (C: the camera again)"


def test_click_in_a_key_sequence() -> None:
    assert parse_key_sequence("click=400,300 i click=0,0*2") == [click(400, 300), KeyPress("i"), click(0, 0),
                                                                 click(0, 0)]
    assert str(click(400, 300)) == "click=400,300" and click(1, 2).token == CLICK_TOKEN
    for bad in ("click=", "click=1", "click=-1,2", "click=a,b", "click=1,2,3", "click=1.5,2"):
        with pytest.raises(KeyMapError, match="click=X,Y"):
            parse_key_sequence(bad)


def test_the_viewer_clicks_in_its_frame_and_refuses_a_pixel_outside_it_where_strict() -> None:
    centre = (SIZE[0] // 2, SIZE[1] // 2)
    viewer = Viewer(two_boxes(), NoFrontend(), strict=True, frame_size=lambda: SIZE)
    viewer.press_sequence(f"click={centre[0] - 10},{centre[1]} i")
    assert viewer.scene.object.name == "near" and viewer.scene.modes.probe
    with pytest.raises(ViewerError, match=r"click=121,0 lies outside the 121x91 picture"):
        viewer.press_sequence("click=121,0")
    loose = Viewer(two_boxes(), NoFrontend(), frame_size=lambda: SIZE)
    loose.press_sequence("click=5,91")
    assert loose.scene.message.startswith("click=5,91 lies outside")
    unsized = Viewer(two_boxes(), NoFrontend())  # a front end that draws no picture
    unsized.press_sequence("click=1,1")
    assert unsized.scene.message == "no picture to click in"


# --- the window: a click is a left press and release that hardly moved ------------------------------
class _Wnd:
    size, buffer_size = (400, 300), (800, 600)  # a HiDPI screen: two pixels a point


def _window() -> SimpleNamespace:
    pytest.importorskip("pyglet.libs.x11.xlib")  # the window module needs pyglet, as test_window_drag_guard's
    from marraztu.frontends.window import ViewerWindow

    pressed: list[KeyPress] = []
    window = SimpleNamespace(viewer=SimpleNamespace(press=pressed.append, scene=scene_with([])), wnd=_Wnd(),
                             click_travel=None, needs_frame=False, scene_changed=False, last_failure="",
                             pressed=pressed)
    window.scene = window.viewer.scene
    window.viewer.move_by_mouse = lambda move: move(window.scene)
    window._framebuffer_pixel = lambda x, y: ViewerWindow._framebuffer_pixel(window, x, y)
    window.press = lambda x, y, button=1: ViewerWindow.on_mouse_press_event(window, x, y, button)
    window.release = lambda x, y, button=1: ViewerWindow.on_mouse_release_event(window, x, y, button)
    window.travel = lambda dx, dy: ViewerWindow.on_mouse_drag_event(window, 0, 0, dx, dy)  # moderngl-window's drag
    window.wnd.mouse_states = SimpleNamespace(right=False, middle=False)  # the left button alone
    window.wnd.modifiers = SimpleNamespace(ctrl=False, shift=False)
    window.held_motion = (0, 0)
    window.drag = window.travel
    return window


def test_a_left_press_and_release_in_place_clicks_the_pixel_under_the_pointer() -> None:
    """moderngl-window gives y as height - pyglet's y, 1 on the top row; the framebuffer has two pixels a point."""
    window = _window()
    window.press(100, 51)
    window.travel(1, -1)  # a hand's shake
    window.release(101, 50)
    assert window.pressed == [click(202, 98)] and window.scene_changed
    window.press(0, 1)
    window.release(0, 1)
    assert window.pressed[-1] == click(0, 0)


@pytest.mark.parametrize("moves", [[(2, 0), (0, 2)], [(5, 0), (-5, 0)]], ids=["a short drag", "there and back"])
def test_a_drag_is_no_click(moves: list[tuple[int, int]]) -> None:
    window = _window()
    window.press(100, 51)
    for dx, dy in moves:
        window.travel(dx, dy)
    window.release(100, 51)
    assert window.pressed == []


def test_a_hands_shake_does_not_turn_the_view_before_its_click() -> None:
    window = _window()
    start = window.scene.camera.model.copy()
    window.press(100, 51)
    window.drag(1, -1)
    window.drag(-1, 0)
    window.release(100, 51)
    assert window.pressed == [click(200, 100)]
    np.testing.assert_array_equal(window.scene.camera.model, start)


def test_a_drag_turns_the_view_as_far_as_the_pointer_went_once_it_is_no_click() -> None:
    """The motion held while it could still be a click is not lost: 2 + 2 + 2 pixels turn as 6 do."""
    window, reference = _window(), scene_with([])
    window.press(100, 51)
    for _ in range(3):
        window.drag(2, 0)
    window.release(106, 51)
    commands.orbit_view(reference, 6, 0, _Wnd.size)
    assert window.pressed == []
    np.testing.assert_allclose(window.scene.camera.model, reference.camera.model, atol=1e-12)


def test_the_other_buttons_do_not_click() -> None:
    window = _window()
    for button in (2, 3):
        window.press(100, 51, button)
        window.release(100, 51, button)
    window.release(100, 51)  # a left release with no left press (pressed outside the window)
    assert window.pressed == []


# --- F9: a recording is written on a thread of its own, the window drawing on meanwhile -------------
def test_f9_starts_the_save_and_says_so_without_waiting_for_the_gif(tmp_path: Path) -> None:
    """The GIF was written on the window's thread: 46 frames at 1024x768 held it still for a second, and
    a recording of random pictures for half a minute. F9 now hands the frames over and returns."""
    pytest.importorskip("pyglet.libs.x11.xlib")
    from marraztu.frontends.window import ViewerWindow

    started: list[tuple[int, Path]] = []
    saves = SimpleNamespace(save=lambda frames, path, fps: started.append((len(frames), path)))
    window = SimpleNamespace(scene=scene_with([]), recording=[np.zeros((2, 2, 3), np.uint8)] * 3, saves=saves)
    ViewerWindow.toggle_recording(window)  # F9 again
    assert window.scene.message == "saving the recording of 3 frames..." and window.recording is None
    assert [count for count, _ in started] == [3] and started[0][1].suffix == ".gif"


def test_a_finished_save_is_said_on_the_window_and_asks_for_a_frame() -> None:
    pytest.importorskip("pyglet.libs.x11.xlib")
    from marraztu.frontends.window import ViewerWindow

    finished = [["recording saved to /x.gif: 3 frames"], []]
    window = SimpleNamespace(scene=scene_with([]), saves=SimpleNamespace(finished=lambda: finished.pop(0)),
                             needs_frame=False, scene_changed=False, last_failure="")
    ViewerWindow._say_finished_saves(window)
    assert window.scene.message == "recording saved to /x.gif: 3 frames" and window.needs_frame
    assert not window.scene_changed  # only the text over the picture changed
    window.needs_frame = False
    ViewerWindow._say_finished_saves(window)
    assert not window.needs_frame  # nothing finished: no frame


@pytest.mark.parametrize(("shades", "said"), [
    ((0, 0, 0), "3 frames, all the same picture: nothing in view changed"),  # a redraw or the mouse drew one too
    ((0, 0, 90), "3 frames, held as 2 pictures: a GIF shows a frame the same as the one before by showing that one "
                 "longer"),
    ((0, 90, 180), "3 frames"),
])
def test_a_saved_recording_says_what_the_record_command_says_of_its_frames(tmp_path: Path, shades: tuple[int, ...],
                                                                           said: str) -> None:
    """F9 said 'recording of 3 frames saved to' where `marraztu record` says the frames are all one picture
    (a key drew the same picture again), or that a GIF holds fewer; then 'the keys changed nothing in view',
    where the window's frames come from its redraws and the mouse too."""
    from marraztu.frontends import record

    saves = record.BackgroundSaves(wake=lambda: None)
    saves.save([np.full((4, 4, 3), shade, np.uint8) for shade in shades], tmp_path / "a.gif", 10)
    assert saves.close() == [f"recording saved to {tmp_path / 'a.gif'}: {said}"]


def test_saves_run_on_their_own_thread_and_are_said_when_done(tmp_path: Path,
                                                              monkeypatch: pytest.MonkeyPatch) -> None:
    import threading

    from marraztu.frontends import record

    release, woken = threading.Event(), threading.Event()
    writers: list[str] = []

    def slow_write(frames: list[np.ndarray], path: Path, fps: float) -> record.Written:
        writers.append(threading.current_thread().name)
        assert release.wait(30)
        if path.name == "bad.gif":
            raise ViewerError("cannot write bad.gif: no room")
        return record.Written(len(frames), 0, "GIF")

    monkeypatch.setattr(record, "write_animation", slow_write)
    saves = record.BackgroundSaves(wake=woken.set)
    try:
        saves.save([np.zeros((2, 2, 3), np.uint8)] * 3, tmp_path / "good.gif", 10)
        saves.save([np.zeros((2, 2, 3), np.uint8)] * 2, tmp_path / "bad.gif", 10)
        assert saves.finished() == [] and not woken.is_set()  # both wait on the writer; save() did not
    finally:
        release.set()  # a failure above leaves no writer waiting into the next tests and the exit
    assert woken.wait(30)
    assert saves.close() == [f"recording saved to {tmp_path / 'good.gif'}: 3 frames",
                             "recording not saved: cannot write bad.gif: no room"]
    assert len(writers) == 2 and threading.current_thread().name not in writers
    assert saves.finished() == []  # each said once


def test_frames_still_being_saved_count_toward_the_next_recordings_memory(tmp_path: Path,
                                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """The cap held one recording; with the GIF written meanwhile, F9 again could gather another 2 GiB
    while the last one's frames were still held, and so on without end."""
    import threading

    from marraztu.frontends import record

    release = threading.Event()
    monkeypatch.setattr(record, "write_animation", lambda frames, path, fps: release.wait(30))
    saves = record.BackgroundSaves(wake=lambda: None)
    saves.save([np.zeros((2, 2, 3), np.uint8)] * 3, tmp_path / "a.gif", 10)
    assert saves.held_bytes() == 36  # its frames, until written
    release.set()
    saves.close()
    assert saves.held_bytes() == 0


def test_a_recording_stops_where_the_saves_still_writing_leave_no_room(monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("pyglet.libs.x11.xlib")
    from marraztu.frontends import window as window_module
    from marraztu.frontends.record import MAX_RECORDING_BYTES

    monkeypatch.setattr(window_module, "read_pixels", lambda fbo, size: np.zeros((2, 2, 3), np.uint8))
    started: list[int] = []
    saves = SimpleNamespace(held_bytes=lambda: MAX_RECORDING_BYTES - 20,  # a long recording still being written
                            save=lambda frames, path, fps: started.append(len(frames)))
    window = SimpleNamespace(scene=scene_with([]), recording=[np.zeros((2, 2, 3), np.uint8)], recording_bytes=12,
                             saves=saves, wnd=SimpleNamespace(fbo=None))
    window.toggle_recording = lambda: window_module.ViewerWindow.toggle_recording(window)
    window_module.ViewerWindow._record_frame(window, (2, 2))
    assert window.recording is None and started == [2]
    assert window.scene.message.endswith("(stopped: the frames filled the memory a recording may take)")


def test_a_save_that_fails_unforeseen_is_one_line_and_the_next_is_still_said(tmp_path: Path,
                                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """A MemoryError in the writer was raised again by close() after the window had gone: a traceback,
    and the saves after it never said."""
    from marraztu.frontends import record

    def write(frames: list[np.ndarray], path: Path, fps: float) -> record.Written:
        if path.name == "big.gif":
            raise MemoryError()
        return record.Written(len(frames), 0, "GIF")

    monkeypatch.setattr(record, "write_animation", write)
    saves = record.BackgroundSaves(wake=lambda: None)
    saves.save([np.zeros((2, 2, 3), np.uint8)] * 2, tmp_path / "big.gif", 10)
    saves.save([np.zeros((2, 2, 3), np.uint8)] * 3, tmp_path / "small.gif", 10)
    assert saves.close() == ["recording not saved: MemoryError",
                             f"recording saved to {tmp_path / 'small.gif'}: 3 frames"]


def test_ctrl_c_in_the_window_still_finishes_and_says_the_recording(monkeypatch: pytest.MonkeyPatch) -> None:
    """Ctrl-C or kill ended the loop past the close of the saves: the process waited for the GIF in
    Python's exit hook and never said where it went."""
    pytest.importorskip("pyglet.libs.x11.xlib")
    from marraztu.frontends import window as window_module
    from marraztu.frontends.window import ViewerWindow

    monkeypatch.setattr(window_module, "Timer", lambda: SimpleNamespace(start=lambda: None))
    said: list[str] = []

    def interrupted() -> None:
        raise KeyboardInterrupt

    window = SimpleNamespace(wnd=SimpleNamespace(is_closing=False), _check_watched_files=interrupted,
                             saves=SimpleNamespace(close=lambda: ["recording saved to /x.gif: 3 frames"]),
                             notice=said.append)
    window._draw_until_closed = lambda: ViewerWindow._draw_until_closed(window)
    with pytest.raises(KeyboardInterrupt):
        ViewerWindow.run(window)
    assert said == ["recording saved to /x.gif: 3 frames"]
