"""The program never makes a scene that its own next call refuses: models at the bounds a file may
reach (1e18 from the origin, 1e-18 across), framed, fitted and moved by the keys, stay within what
every call of the programming interface checks (Scene.check_by_hand)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import marraztu
from marraztu.control import commands
from marraztu.control.keymap import parse_key_sequence
from marraztu.control.viewer import StartOptions, Viewer
from marraztu.errors import LoadError
from marraztu.loaders.scenefile import empty_scene
from marraztu.model.geometry import CAMERA_REACH, DRAWABLE_COORDINATE, DRAWABLE_SIZE, LIGHT_REACH
from marraztu.model.scene import CameraMode, SceneObject
from support.scenes import PLAIN, NoFrontend, mesh_from_polygons

SIZE = (64, 48)
CUBE_FACES = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]


def cube(half: float, centre: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> np.ndarray:
    return np.array([[x, y, z] for x in (-half, half) for y in (-half, half) for z in (-half, half)]) + centre


def _write_obj(path: Path, half: float, centre: tuple[float, float, float]) -> Path:
    lines = [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in cube(half, centre)]
    lines += ["f " + " ".join(str(index + 1) for index in face) for face in CUBE_FACES]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_a_model_framed_near_the_bound_leaves_the_camera_where_it_can_be_drawn_from() -> None:
    """A cube 3e17 from the origin was framed from 1.005e18, and every call after refused 'camera as its
    model matrix places it: ... past 1e+18 ... (scale it down)', blaming the camera for the model's size."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(cube(3e17), CUBE_FACES)
        v.press("u")
        assert np.asarray(v.render()).any()
        assert np.abs(v.scene.camera.origin).max() < CAMERA_REACH


def test_framing_stops_the_camera_where_it_can_still_be_drawn_from_and_says_so() -> None:
    """Side by side, in a window twice as high as wide, a view a sixth as wide as high frames a cube
    1.4e18 wide from 1.1e19: the camera stops at CAMERA_REACH, its body with it, nearer than framing
    would stand."""
    with marraztu.Viewer(size=(48, 96), empty=True) as v:
        v.add_mesh(cube(7e17), CUBE_FACES)
        v.press("s .")
        assert v.message == f"framed mesh, from as far back as a camera may stand ({CAMERA_REACH:.0e} from the origin)"
        camera = v.scene.camera
        assert CAMERA_REACH * 0.99 < float(np.abs(np.array(camera.mesh.bounds) + camera.origin).max()) <= CAMERA_REACH
        v.press("s .")
        assert v.message == "framed mesh"
        v.press("s p .")  # the parallel view's height frames it, wherever the camera stops
        assert v.message == "framed mesh" and v.scene.camera.origin[2] < CAMERA_REACH


def test_a_model_as_small_as_a_file_may_be_leaves_the_camera_body_as_large_as_one_may_be() -> None:
    """A cube 1e-18 across shrank the built-in camera's body to 1.2e-19, which the next call refused
    ('(scale it up)')."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        start = np.array(v.scene.camera.mesh.bounds)
        v.add_mesh(cube(5e-19), CUBE_FACES)
        low, high = v.scene.camera.mesh.bounds
        assert np.max(high - low) >= DRAWABLE_SIZE
        v.press("u DELETE")
        v.add_mesh(cube(50.0), CUBE_FACES)  # the seed's scale again: the body as it started
        assert np.array_equal(v.scene.camera.mesh.bounds, start)


def test_the_bulb_fitted_to_the_largest_model_stands_where_it_can_light_from() -> None:
    """Fitted to a model 3.5e18 across (the unit 1e17), the bulb stood at 200 units, 2e19, past LIGHT_REACH."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(cube(DRAWABLE_COORDINATE), CUBE_FACES)
        assert np.abs(v.scene.lights[1].position).max() <= LIGHT_REACH
        v.press("1")
        assert np.asarray(v.render()).any()


def test_a_model_moved_by_keys_stops_at_the_bound() -> None:
    """t x*20 took a cube 3e17 wide (the step 5e16) past 1e18, and every call after, u too, refused it."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(cube(3e17), CUBE_FACES)
        box = v.scene.objects[0]
        v.press("t x*20")
        assert DRAWABLE_COORDINATE - 5e16 < box.origin[0] + 3e17 <= DRAWABLE_COORDINATE
        assert v.message == f"mesh stops here: past {DRAWABLE_COORDINATE:.0e} from the origin the GPU's 32-bit " \
                            "numbers cannot light it"
        v.press("X u u")


def test_a_file_read_in_a_models_place_past_the_bound_there_is_refused_and_so_is_undoing_there(
        tmp_path: Path) -> None:
    """PageDown read a file 2e18 wide in the place of one moved a step off the origin, and `u` took one
    read at the origin back a step: either way past 1e18, which every call after refused."""
    small, large = (_write_obj(tmp_path / f"{name}.obj", half, (0.0, 0.0, 0.0)) for name, half in (("a", 5e16),
                                                                                                    ("b", 1e18)))
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.load(small)
        box = v.scene.objects[0]
        v.press("t x PAGEDOWN")
        assert box.source == small
        assert v.message.startswith("b.obj cannot take a's place: a coordinate reaches 1.005e+18: past 1e+18")
        v.press("u")
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.load(small)
        box = v.scene.objects[0]
        v.press("t x X PAGEDOWN")
        assert box.source == large and v.message.startswith("b.obj in place of a")
        kept = [matrix.copy() for matrix in box.history]
        with pytest.raises(LoadError):  # a press refused half way puts the dropped step back
            v.press(f"u f={tmp_path / 'missing.obj'}")
        assert len(box.history) == len(kept) and all(map(np.array_equal, box.history, kept))
        v.press("u")
        assert v.message == f"u cannot take b back to where it stood before (past {DRAWABLE_COORDINATE:.0e} from " \
                            "the origin the GPU's 32-bit numbers cannot light it): that step is dropped"
        assert np.array_equal(box.origin, [0.0, 0.0, 0.0])
        v.press("u")  # not stuck: the move before it, to the origin from the origin
        assert v.message == "" and np.array_equal(box.origin, [0.0, 0.0, 0.0])
        v.press("u")
        assert v.message == "nothing to undo"


def test_the_mouse_stops_the_camera_at_its_reach_as_the_keys_do() -> None:
    """The window's wheel backed the camera of a model 6e17 wide out to 1e4 times its size: past
    CAMERA_REACH, where the GPU's numbers overflow. The view's moves stop there as a key's move does."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(cube(3e17), CUBE_FACES)
        camera = v.scene.camera
        depth = len(camera.history)
        commands.dolly_view(v.scene, -50.0)
        assert len(camera.history) == depth
        assert v.message == f"camera stops here: past {CAMERA_REACH:.0e} from the origin the GPU's 32-bit numbers " \
                            "cannot see from it"
        commands.pan_view(v.scene, 0.0, 1e9, SIZE[1])
        assert len(camera.history) == depth
        v.press("u")


CAMERA_PAST = f"past {CAMERA_REACH:.0e} from the origin the GPU's 32-bit numbers cannot see from it"
CAMERA_STOPS = f"camera stops here: {CAMERA_PAST}"


def _window_viewer(half: float) -> Viewer:
    """The viewer a window drives (the mouse's events go through it), round a cube `half` wide."""
    viewer = Viewer(empty_scene(), NoFrontend())
    viewer.start(StartOptions(empty=True), longest_texture_side=64)
    viewer.add_made(_cube_object(half))
    return viewer


def _cube_object(half: float) -> SceneObject:
    return SceneObject.placed("mesh", mesh_from_polygons("mesh", cube(half), CUBE_FACES), PLAIN, (0.0, 0.0, 0.0))


def test_a_wheel_notch_back_in_from_the_reach_takes_back_the_words_that_the_camera_stopped() -> None:
    """Wheel notches out stopped the camera at its reach and said so; a notch back in moved it, and the
    words that it had stopped stayed up until the next key."""
    viewer = _window_viewer(3e17)
    viewer.scene.message = "loaded mesh"
    for _ in range(40):
        viewer.move_by_mouse(lambda scene: commands.dolly_view(scene, -1.0))
    assert viewer.scene.message == CAMERA_STOPS
    place = viewer.scene.camera.origin
    viewer.move_by_mouse(lambda scene: commands.dolly_view(scene, 1.0))
    assert viewer.scene.camera.origin[2] < place[2] and viewer.scene.message == ""
    viewer.move_by_mouse(lambda scene: commands.dolly_view(scene, -50.0))  # refused again: said again
    assert viewer.scene.message == CAMERA_STOPS


def test_a_keys_refusal_in_the_words_of_the_mouses_last_stays_up_after_a_mouse_move() -> None:
    """The wheel stopped the camera at its reach; `z` (cameras targeted, translating) stopped it too, in
    the same words; a pan, made, took the key's words back, as if they were the wheel's."""
    viewer = _window_viewer(3e17)
    for _ in range(40):
        viewer.move_by_mouse(lambda scene: commands.dolly_view(scene, -1.0))
    assert viewer.scene.message == CAMERA_STOPS
    for key in parse_key_sequence("c t"):
        viewer.press(key)
    for _ in range(60):  # out a step at a time, up to the reach
        viewer.press(parse_key_sequence("z")[0])
        if viewer.scene.message:
            break
    assert viewer.scene.message == CAMERA_STOPS
    viewer.move_by_mouse(lambda scene: commands.pan_view(scene, 1.0, 0.0, 48))
    assert viewer.scene.message == CAMERA_STOPS


@pytest.mark.parametrize("placed_by", ["hand", "scene file"])
def test_a_camera_placed_past_its_reach_is_refused_in_a_cameras_words(tmp_path: Path, placed_by: str) -> None:
    """A camera at 6e18, by hand or in a scene file, was refused as 'past 5e+18 the GPU's 32-bit numbers
    cannot light the model', a model's words for a camera's reach."""
    words = "a coordinate reaches 6e+18: past 5e+18 the GPU's 32-bit numbers cannot see from the camera " \
            "(move it nearer the origin, or scale it down)"
    if placed_by == "hand":
        with marraztu.Viewer(size=SIZE) as v:
            v.scene.camera.model = np.array([[1.0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 6e18], [0, 0, 0, 1]])
            with pytest.raises(ValueError) as refused:
                v.render()
        assert str(refused.value) == f"camera as its model matrix places it: {words}"
        return
    scene = tmp_path / "scene.toml"
    scene.write_text("[[cameras]]\nposition = [0, 0, 6e18]\n")
    with pytest.raises(marraztu.ViewerError) as refused:
        marraztu.Viewer(size=SIZE, scene=scene)
    assert str(refused.value).endswith(f"cameras[1]: position [0, 0, 6e+18]: {words}")


def test_u_drops_a_view_move_it_can_no_longer_take_the_camera_back_to() -> None:
    """The wheel backed the camera out near its reach, then in; a model 2e18 wide, loaded alone, grew the
    camera's body; where the camera had stood its body would reach past 5e18: `u` refused to go back
    there, every press, and no move before it could be undone ("stuck"). Now that step is dropped."""
    viewer = _window_viewer(3e17)
    scene = viewer.scene
    start = scene.camera.model
    for out_or_in in (-1.0, 1.0):  # two gestures: out near the reach, then back in a little
        for _ in range(40 if out_or_in < 0 else 10):
            viewer.move_by_mouse(lambda moved: commands.dolly_view(moved, out_or_in))
        commands.end_view_gesture(scene)
    came_in = scene.camera.model
    for key in parse_key_sequence("DELETE"):
        viewer.press(key)
    viewer.add_made(_cube_object(DRAWABLE_COORDINATE))  # framed: a view move, the body fitted to it
    viewer.press(parse_key_sequence("u")[0])
    assert np.array_equal(scene.camera.model, came_in) and scene.message == ""
    viewer.press(parse_key_sequence("u")[0])  # out where the body, larger now, cannot stand
    assert np.array_equal(scene.camera.model, came_in)
    assert scene.message == f"u cannot take camera back to where it stood before ({CAMERA_PAST}): that step is dropped"
    scene.check_by_hand()
    viewer.press(parse_key_sequence("u")[0])
    assert np.array_equal(scene.camera.model, start) and scene.message == ""
    viewer.press(parse_key_sequence("u")[0])
    assert scene.message == "nothing to undo"


def test_a_step_dropped_under_a_view_move_leaves_that_view_move_and_the_one_below_to_undo() -> None:
    """HOME, the camera set far out by hand, HOME again; a model 2e18 wide, framed alone, grew the
    camera's body. `u` dropped the far step, under the second HOME's, and that used up a view move of the
    list: the second HOME's was undone for the first's, and the first's stayed on the camera."""
    viewer = _window_viewer(3e17)
    scene, camera = viewer.scene, viewer.scene.camera
    start = camera.model.copy()
    viewer.press(parse_key_sequence("HOME")[0])
    for _ in range(40):
        viewer.move_by_mouse(lambda moved: commands.dolly_view(moved, -1.0))
    commands.end_view_gesture(scene)
    far = camera.model.copy()
    viewer.press(parse_key_sequence("u")[0])
    camera.model = far  # by hand: not a view move
    for key in parse_key_sequence("HOME DELETE"):
        viewer.press(key)
    viewer.add_made(_cube_object(DRAWABLE_COORDINATE))
    for _ in range(2):  # the framing, then the far step dropped
        viewer.press(parse_key_sequence("u")[0])
    assert scene.message.startswith("u cannot take camera back to where it stood before")
    for _ in range(2):  # the second HOME's, then the first's
        assert camera.made_by_view_move()
        viewer.press(parse_key_sequence("u")[0])
        assert scene.message == "" and np.array_equal(camera.model, start)
    assert len(camera.history) == 1
    viewer.press(parse_key_sequence("u")[0])
    assert scene.message == "nothing to undo"


def test_u_gives_a_dropped_view_moves_size_to_the_step_that_takes_its_place() -> None:
    """The wheel backed the camera out near its reach (in perspective), `p`, a wheel zoom there, HOME; a
    model 2e18 wide, framed alone, grew the camera's body. `u` dropped the two far steps, and the zoom's
    size before went with the zoom's matrix, so the `u` from HOME's step to the start gave back HOME's
    size before (the far zoom's, 3.3e18) in place of the start's (9.4e17, where `p` sized it)."""
    viewer = _window_viewer(3e17)
    scene = viewer.scene

    def wheel(notches: int, direction: float) -> None:
        for _ in range(notches):
            viewer.move_by_mouse(lambda moved: commands.dolly_view(moved, direction))
        commands.end_view_gesture(scene)

    wheel(40, -1.0)
    viewer.press(parse_key_sequence("p")[0])
    wheel(3, 1.0)
    viewer.press(parse_key_sequence("HOME")[0])
    start_size = scene.modes.parallel_half_height
    for key in parse_key_sequence("DELETE"):
        viewer.press(key)
    viewer.add_made(_cube_object(DRAWABLE_COORDINATE))
    for _ in range(3):  # the framing, then the zoom's far place and the far place, dropped
        viewer.press(parse_key_sequence("u")[0])
    assert scene.message.startswith("u cannot take camera back to where it stood before")
    viewer.press(parse_key_sequence("u")[0])
    assert scene.message == "" and len(scene.camera.history) == 1
    assert scene.modes.parallel_half_height == start_size


@pytest.mark.parametrize("top_by_view_move", [True, False])
def test_a_dropped_step_hands_its_size_before_to_the_current_matrix(top_by_view_move: bool) -> None:
    """A view move's matrix dropped under the current one (a key's move or a view move): `u` then takes
    both steps back at once, to the size before the dropped one."""
    camera = _cube_object(1.0)
    start, dropped, top = (np.eye(4) + index for index in range(3))
    camera.history = [start]
    camera.push_view_move(dropped, 10.0)
    if top_by_view_move:
        camera.push_view_move(top, 20.0)
    else:
        camera.push(top)
    camera.drop_step_under_top()
    assert [matrix is top for matrix in camera.history] == [False, True]
    assert camera.made_by_view_move() and [size for _, size in camera.view_sizes] == [10.0]


def test_g_refused_at_the_reach_leaves_the_camera_flying() -> None:
    """A camera whose body stood just within its reach: `g` turned it toward the selected object, which
    would take the body past the reach; the turn was refused, and analysis mode was entered all the same,
    the camera not looking at what it orbits."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(cube(3e17), CUBE_FACES)
        camera = v.scene.camera
        camera.model = np.array([[1.0, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, CAMERA_REACH - camera.mesh.bounds[1][2]],
                                 [0, 0, 0, 1]])
        v.add_mesh(cube(1e17, (9e17, 0.0, 0.0)), CUBE_FACES)
        v.press("c g")
        assert v.message == f"camera stops here: past {CAMERA_REACH:.0e} from the origin the GPU's 32-bit numbers " \
                            "cannot see from it (flight mode stays)"
        assert v.scene.modes.camera_mode is CameraMode.FLIGHT
        v.press("t Z g")  # a step in toward the origin: the turn is made there
        assert v.scene.modes.camera_mode is CameraMode.ANALYSIS


class _CountedScans(list):  # type: ignore[type-arg]
    """A list that counts how often `in` scans it."""

    scans = 0

    def __contains__(self, item: object) -> bool:
        self.scans += 1
        return super().__contains__(item)


def test_a_refused_key_move_asks_once_whether_the_element_is_a_camera() -> None:
    """Scene.move_refusal scanned the camera list twice for each refused move: once for the reach, once for
    the words."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(cube(3e17), CUBE_FACES)
        scene = v.scene
        far = np.array(scene.objects[0].model)
        far[0, 3] = DRAWABLE_COORDINATE
        scene.cameras = cameras = _CountedScans(scene.cameras)
        assert scene.move_refusal(scene.objects[0], far).startswith("mesh stops here")
        assert cameras.scans == 1



def test_a_turn_in_its_own_frame_stops_where_an_unevenly_scaled_model_would_be_too_small() -> None:
    """A rod 2e-18 long, its matrix squashed 1000 times along y by hand (accepted), turned about its own z
    by r z*16: its length came to lie along the squashed axis, 5.8e-20 across, refused by every call after."""
    rod = np.array([[x, y, z] for x in (-1e-18, 1e-18) for y in (-1e-21, 1e-21) for z in (-1e-21, 1e-21)])
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(rod, CUBE_FACES)
        obj = v.scene.objects[0]
        obj.model = obj.model @ np.diag([1.0, 1e-3, 1.0, 1.0])
        v.press("r z*16")
        assert v.message == f"mesh stops here: under {DRAWABLE_SIZE:.0e} across the GPU's 32-bit numbers cannot " \
                            "light it"
        v.press("u")
        v.scene.check_by_hand()



@pytest.mark.parametrize("second_camera", ["", "[[cameras]]\nposition = [0, 0, 4.9999e18]\n"], ids=["one", "far"])
@pytest.mark.parametrize("scale", [1, 1000])
def test_fitting_grows_no_camera_body_past_where_its_camera_stands(tmp_path: Path, scale: int,
                                                                   second_camera: str) -> None:
    """Fitted to the largest model (the unit 1e17), a second built-in camera at 4.9999e18 grew a body 1.2e18
    long round it, reaching 5.68e18, and one a scene file scaled 1000 times, 1.2e21: every call after
    refused the scene. A body grows only as far as its camera's reach, where it stands."""
    scene = tmp_path / "scene.toml"
    scene.write_text(f"[[cameras]]\nposition = [0, 0, 150]\nscale = {scale}\n\n{second_camera}\n"
                     f"[[objects]]\nmodel = \"{_write_obj(tmp_path / 'a.obj', 50.0, (0.0, 0.0, 0.0))}\"\n")
    with marraztu.Viewer(size=SIZE, scene=scene) as v:
        v.press("DELETE")
        v.add_mesh(cube(DRAWABLE_COORDINATE), CUBE_FACES)
        v.scene.check_by_hand()
        assert np.asarray(v.render()).any()


# The models at the bounds a file may reach: (half its side, its centre).
EXTREMES = {"as far as a file may reach": (DRAWABLE_COORDINATE, (0.0, 0.0, 0.0)),
            "3e17 from the origin": (3e17, (0.0, 0.0, 0.0)),
            "as small as a file may be": (DRAWABLE_SIZE / 2.0, (0.0, 0.0, 0.0)),
            "twice that size": (DRAWABLE_SIZE, (0.0, 0.0, 0.0)),
            "far from the origin": (5e16, (9e17, -9e17, 9e17))}
# Moves, turns, framing, the view's reset, targets and selections, modes that change what framing sees
# (side by side, parallel, looking through the object), undo, deletion, and files read in place and as cameras.
KEYS = ("t", "r", "g", "x", "y", "z", "X", "Y", "Z", "x*30", "Y*30", "z*30", "Z*30", ".", ">", "HOME", "c",
        "TAB", "u", "u*5", "C", "p", "s", "d", "0", "1", "2", "3", "DELETE", "PAGEDOWN", "PAGEUP")


@pytest.mark.parametrize("through", ["add_mesh", "load"])
@pytest.mark.parametrize("extreme", list(EXTREMES))
def test_keys_never_make_a_scene_the_next_call_refuses(tmp_path: Path, extreme: str, through: str) -> None:
    """The property: from a model at a bound, whatever keys are pressed, every call after accepts the
    scene they made (Scene.check_by_hand), and the picture is drawn."""
    files = [_write_obj(tmp_path / f"m{index}.obj", *bounds) for index, bounds in enumerate(EXTREMES.values())]
    half, centre = EXTREMES[extreme]
    keys = [*KEYS, *(f"f={path}" for path in files)]
    random = np.random.default_rng([list(EXTREMES).index(extreme), int(through == "load")])
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        if through == "load":
            v.load(files[list(EXTREMES).index(extreme)])
        else:
            v.add_mesh(cube(half, centre), CUBE_FACES)
        pressed = []
        for key in random.choice(keys, size=300):
            pressed.append(str(key))
            try:
                v.press(str(key))
            except marraztu.ViewerError:  # a key refused where it is pressed (f=PATH with lights targeted)
                pass
            try:
                v.scene.check_by_hand()
            except ValueError as refusal:
                pytest.fail(f"after {' '.join(pressed)}: {refusal}")
        assert np.asarray(v.render()).shape == (SIZE[1], SIZE[0], 3)
