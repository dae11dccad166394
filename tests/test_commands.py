"""Every key of SPEC 6 as scene state: no GL, tiny meshes built here."""

from __future__ import annotations

import numpy as np
import pytest

from marraztu.control import commands
from marraztu.control.keymap import KEYMAP, KeyPress, dispatch, parse_key_sequence
from marraztu.model import transforms
from marraztu.model.lights import SPOT_APERTURE_RANGE_DEG
from marraztu.model.mesh import Mesh
from marraztu.model.scene import (
    CameraMode,
    Fill,
    Frame,
    Material,
    Projection,
    Scene,
    SceneObject,
    Shading,
    Target,
)
from marraztu.model.transforms import TransformKind
from marraztu.text.status import help_lines, status_line
from support.scenes import RecordingHost

PLAIN = Material(ka=(0.2, 0.2, 0.2), kd=(0.5, 0.5, 0.5), ks=(0.1, 0.1, 0.1), ns=10.0)


def cube_mesh(name: str, half: float = 10.0) -> Mesh:
    """A cube of six quads, made directly from numpy tables."""
    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=np.float64)
    quads = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    normals = np.array([[-1, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1]], np.float32)
    corners = np.array(quads, dtype=np.int64).ravel()
    return Mesh(
        name=name,
        positions=signs * half,
        corner_vertex=corners,
        uvs=np.zeros((corners.size, 2), np.float32),
        normals=np.repeat(normals, 4, axis=0),
        face_start=np.arange(0, corners.size + 1, 4, dtype=np.int64),
        face_normals=normals,
    )


def make_scene(unit: float = 1.0) -> Scene:
    """Three 20-unit cubes 100 units apart, seen from 150 units: the seed's scale, in `unit`s."""
    objects = [SceneObject.placed(name, cube_mesh(name, 10.0 * unit), PLAIN, tuple(unit * np.array(position)))
               for name, position in (("left", (-100, 0, 0)), ("right", (100, 0, 0)), ("middle", (0, 0, 0)))]
    cameras = [SceneObject.placed("camera", cube_mesh("camera", 3.0 * unit), PLAIN, (0, 0, 150 * unit))]
    return Scene(objects=objects, cameras=cameras)


def press(scene: Scene, keys: str, host: RecordingHost | None = None) -> RecordingHost:
    host = host or RecordingHost()
    for key in parse_key_sequence(keys):
        dispatch(scene, key, host)
    return host


@pytest.fixture
def scene() -> Scene:
    return make_scene()


def tilted(scene: Scene) -> SceneObject:
    """The selected object given a rotation first, so local and global moves differ."""
    obj = scene.object
    obj.history = [transforms.rotation_about_axis(1, 0.7) @ transforms.rotation_about_axis(0, 0.3)]
    obj.history[0][:3, 3] = (-100.0, 5.0, 2.0)
    return obj


# --- transforms ------------------------------------------------------------------------------------
def test_rotations_are_right_handed_for_column_vectors() -> None:
    quarter = np.pi / 2
    x, y, z = np.eye(4)[:, 0], np.eye(4)[:, 1], np.eye(4)[:, 2]
    np.testing.assert_allclose(transforms.rotation_about_axis(0, quarter) @ y, z, atol=1e-12)
    np.testing.assert_allclose(transforms.rotation_about_axis(1, quarter) @ z, x, atol=1e-12)
    np.testing.assert_allclose(transforms.rotation_about_axis(2, quarter) @ x, y, atol=1e-12)


def test_a_rotation_about_no_axis_is_refused() -> None:
    with pytest.raises(ValueError, match="axis index 3"):
        transforms.rotation3(3, 0.1)


def test_perspective_is_glfrustum_of_a_symmetric_view() -> None:
    """The reference pages' glFrustum(l, r, b, t, n, f) with t = n tan(fovy / 2), r = t aspect."""
    fovy, aspect, near, far = 70.0, 1.6, 0.5, 300.0
    t = near * np.tan(np.radians(fovy) / 2)
    r, b, l = t * aspect, -t, -t * aspect  # noqa: E741 - the reference's own names
    frustum = np.array([[2 * near / (r - l), 0, (r + l) / (r - l), 0],
                        [0, 2 * near / (t - b), (t + b) / (t - b), 0],
                        [0, 0, -(far + near) / (far - near), -2 * far * near / (far - near)],
                        [0, 0, -1, 0]])
    np.testing.assert_allclose(transforms.perspective(fovy, aspect, near, far), frustum, rtol=1e-12, atol=1e-15)


def test_orthographic_is_glortho_centred_on_the_axis() -> None:
    """The reference pages' glOrtho(l, r, b, t, n, f) with l = -r and b = -t: near maps to -1, far to +1."""
    r, t, near, far = 40.0, 25.0, 5.0, 900.0
    l, b = -r, -t  # noqa: E741 - the reference's own names
    ortho = np.array([[2 / (r - l), 0, 0, -(r + l) / (r - l)],
                      [0, 2 / (t - b), 0, -(t + b) / (t - b)],
                      [0, 0, -2 / (far - near), -(far + near) / (far - near)],
                      [0, 0, 0, 1]])
    matrix = transforms.orthographic(r, t, near, far)
    np.testing.assert_allclose(matrix, ortho, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose((matrix @ [r, -t, -near, 1.0])[:3], [1.0, -1.0, -1.0], atol=1e-12)
    np.testing.assert_allclose((matrix @ [0.0, 0.0, -far, 1.0])[2], 1.0, atol=1e-12)


def test_translation_moves_points_along_one_axis() -> None:
    point = np.array([1.0, 2.0, 3.0, 1.0])
    np.testing.assert_array_equal(transforms.translation(1, 5.0) @ point, [1.0, 7.0, 3.0, 1.0])


def test_look_at_model_points_minus_z_at_the_target() -> None:
    eye, target = np.array([10.0, 20.0, 30.0]), np.array([-5.0, 0.0, 2.0])
    model = transforms.look_at_model(eye, target, np.array([0.0, 1.0, 0.0]))
    expected_forward = (target - eye) / np.linalg.norm(target - eye)
    np.testing.assert_allclose(-model[:3, 2], expected_forward, atol=1e-12)
    np.testing.assert_allclose(model[:3, :3].T @ model[:3, :3], np.eye(3), atol=1e-12)
    assert np.linalg.det(model[:3, :3]) == pytest.approx(1.0)
    np.testing.assert_array_equal(model[:3, 3], eye)


def test_look_at_model_copes_with_up_along_the_view_axis() -> None:
    model = transforms.look_at_model(np.zeros(3), np.array([0.0, -10.0, 0.0]), np.array([0.0, 1.0, 0.0]))
    np.testing.assert_allclose(-model[:3, 2], [0.0, -1.0, 0.0], atol=1e-12)
    assert transforms.look_at_model(np.ones(3), np.ones(3), np.array([0.0, 1.0, 0.0])) is None


# --- display keys ----------------------------------------------------------------------------------
TOGGLES = [
    ("l", lambda s: s.modes.fill, Fill.FILLED, Fill.LINES),
    ("o", lambda s: s.modes.triangle_only, False, True),
    ("d", lambda s: s.modes.draw_all, True, False),
    ("n", lambda s: s.modes.normals, False, True),
    ("b", lambda s: s.modes.culling, False, True),
    ("p", lambda s: s.modes.projection, Projection.PERSPECTIVE, Projection.PARALLEL),
    ("F", lambda s: s.modes.shading, Shading.FLAT, Shading.GOURAUD),
    ("T", lambda s: s.modes.texture, True, False),
    ("h", lambda s: s.modes.show_help, False, True),
    ("F1", lambda s: s.modes.show_help, False, True),
    ("C", lambda s: s.modes.view_from_object, False, True),
    ("0", lambda s: s.lights[0].on, False, True),
    ("1", lambda s: s.lights[1].on, False, True),
    ("2", lambda s: s.lights[2].on, False, True),
    ("3", lambda s: s.lights[3].on, False, True),
]


@pytest.mark.parametrize(("key", "read", "before", "after"), TOGGLES, ids=[t[0] for t in TOGGLES])
def test_display_key_toggles_and_toggles_back(scene: Scene, key, read, before, after) -> None:
    assert read(scene) == before
    press(scene, key)
    assert read(scene) == after
    press(scene, key)
    assert read(scene) == before


def test_parallel_projection_is_sized_from_the_current_view(scene: Scene) -> None:
    expected = scene.matching_parallel_half_height()
    press(scene, "p")
    assert scene.modes.parallel_half_height == pytest.approx(expected)
    assert scene.modes.parallel_half_height == pytest.approx(150.0 * np.tan(np.radians(45.0)))


def test_view_from_object_looks_through_the_selected_object(scene: Scene) -> None:
    press(scene, "C")
    assert scene.viewer is scene.object


def test_escape_quits_and_f12_takes_a_screenshot(scene: Scene) -> None:
    host = press(scene, "ESC F12")
    assert host.calls == [("quit",), ("save_screenshot",)]


# --- selection -------------------------------------------------------------------------------------
def test_c_cycles_objects_cameras_lights(scene: Scene) -> None:
    seen = []
    for _ in range(4):
        seen.append(scene.modes.target)
        press(scene, "c")
    assert seen == [Target.OBJECTS, Target.CAMERAS, Target.LIGHTS, Target.OBJECTS]


def test_tab_wraps_through_objects_and_resets_the_face(scene: Scene) -> None:
    scene.objects[1].selected_face = 4
    order = []
    for _ in range(4):
        press(scene, "TAB")
        order.append(scene.selected_object)
    assert order == [1, 2, 0, 1]
    assert scene.objects[1].selected_face == 0


def test_tab_wraps_through_cameras_and_lights(scene: Scene) -> None:
    scene.cameras.append(SceneObject.placed("second", cube_mesh("second"), PLAIN, (0, 0, -150)))
    press(scene, "c TAB")
    assert scene.selected_camera == 1
    press(scene, "TAB")
    assert scene.selected_camera == 0
    press(scene, "c TAB*5")
    assert scene.selected_light == 1
    assert scene.selected_object == 0  # other targets untouched


def test_enter_steps_through_faces_and_wraps(scene: Scene) -> None:
    press(scene, "ENTER*5")
    assert scene.object.selected_face == 5
    press(scene, "ENTER")
    assert scene.object.selected_face == 0


# --- moving objects --------------------------------------------------------------------------------
def test_local_rotation_is_model_times_step(scene: Scene) -> None:
    obj = tilted(scene)
    start = obj.model
    press(scene, "x")
    np.testing.assert_allclose(obj.model, start @ transforms.rotation_about_axis(0, 0.1), atol=1e-9)


def test_global_rotation_is_step_times_model(scene: Scene) -> None:
    obj = tilted(scene)
    start = obj.model
    press(scene, "g Y")
    np.testing.assert_allclose(obj.model, transforms.rotation_about_axis(1, -0.1) @ start, atol=1e-9)


@pytest.mark.parametrize("axis_key,axis,sign", [("x", 0, 1), ("y", 1, 1), ("z", 2, 1),
                                                ("X", 0, -1), ("Y", 1, -1), ("Z", 2, -1)])
def test_translation_local_and_global_differ_as_mt_and_tm(scene: Scene, axis_key, axis, sign) -> None:
    obj = tilted(scene)
    start = obj.model
    step = transforms.translation(axis, sign * commands.TRANSLATION_STEP)
    press(scene, f"t {axis_key}")
    local = obj.model
    np.testing.assert_allclose(local, start @ step, atol=1e-9)
    press(scene, f"u g {axis_key}")
    np.testing.assert_allclose(obj.model, step @ start, atol=1e-9)
    assert not np.allclose(local, obj.model)


def test_63_presses_of_x_turn_almost_a_full_circle(scene: Scene) -> None:
    obj = scene.object
    start = obj.model
    press(scene, "x*63")
    np.testing.assert_allclose(obj.model, start @ transforms.rotation_about_axis(0, 6.3), atol=1e-9)
    left_to_full_turn = 2 * np.pi - 6.3
    np.testing.assert_allclose(obj.model, start @ transforms.rotation_about_axis(0, -left_to_full_turn),
                               atol=1e-9)
    assert len(obj.history) == 64


MOVE_WORDS = ["x", "y", "z", "X", "Y", "Z"]
MODE_WORDS = ["r", "t", "g"]


def random_session(rng: np.random.Generator, length: int) -> str:
    words = rng.choice(MOVE_WORDS + MODE_WORDS, size=length, p=[0.13] * 6 + [0.22 / 3] * 3)
    return " ".join(words)


@pytest.mark.parametrize("seed", range(8))
@pytest.mark.parametrize("target_presses", ["", "c"], ids=["objects", "cameras"])
def test_undo_restores_the_initial_matrix_exactly(scene: Scene, seed: int, target_presses: str) -> None:
    press(scene, target_presses)
    element = scene.object if scene.modes.target is Target.OBJECTS else scene.camera
    initial = element.model.copy()
    press(scene, random_session(np.random.default_rng(seed), 120))
    moves = len(element.history) - 1
    assert moves > 0
    press(scene, f"u*{moves}")
    assert np.array_equal(element.model, initial)
    press(scene, "u")  # at the initial state: nothing happens
    assert np.array_equal(element.model, initial) and len(element.history) == 1
    assert scene.message == "nothing to undo"


def test_moves_of_one_object_leave_the_others_alone(scene: Scene) -> None:
    press(scene, "x t y TAB z")
    np.testing.assert_array_equal(scene.objects[2].model, np.eye(4))
    np.testing.assert_array_equal(scene.objects[1].model[:3, :3], np.eye(3))
    assert len(scene.objects[0].history) == 3 and len(scene.objects[1].history) == 2


# --- cameras ---------------------------------------------------------------------------------------
def test_flight_mode_moves_the_camera_in_its_own_frame(scene: Scene) -> None:
    camera = scene.camera
    press(scene, "c y")
    turned = camera.model
    press(scene, "t Z")
    np.testing.assert_allclose(camera.model, turned @ transforms.translation(2, -commands.TRANSLATION_STEP),
                               atol=1e-9)
    assert scene.modes.frame is Frame.LOCAL  # g for objects untouched by camera moves


def centre_off_view_axis(scene: Scene) -> float:
    """Distance of the selected object's centre from the camera's view ray."""
    camera, centre = scene.camera, scene.object.centre
    to_centre = centre - camera.origin
    along = float(np.dot(to_centre, camera.forward))
    assert along > 0, "the object is behind the camera"
    return float(np.linalg.norm(to_centre - along * camera.forward))


def test_entering_analysis_turns_the_camera_to_the_object_keeping_its_place(scene: Scene) -> None:
    camera = scene.camera
    position = camera.origin
    press(scene, "c g")
    assert scene.modes.camera_mode is CameraMode.ANALYSIS
    np.testing.assert_array_equal(camera.origin, position)
    assert centre_off_view_axis(scene) < 1e-9
    press(scene, "u")  # the turn is undoable
    assert len(camera.history) == 1


def test_entering_analysis_on_an_off_axis_object(scene: Scene) -> None:
    scene.selected_object = 0  # "left", at (-100, 0, 0)
    press(scene, "c g")
    assert centre_off_view_axis(scene) < 1e-9
    np.testing.assert_allclose(scene.camera.model[:3, 0] @ [0, 1, 0], 0.0, atol=1e-12)  # no roll


def test_an_object_selected_in_analysis_mode_is_turned_to_at_the_next_camera_press(scene: Scene) -> None:
    """Analysis mode orbits and approaches the selected object: one selected after the camera turned to
    another is off the view axis, so the next press turns the camera to it (undoable), the one after moves.
    Before, y orbited the new object while looking past it, and Z flew along the old axis into another
    model, saying it stopped by the new one."""
    scene.selected_object = 0  # "left"
    press(scene, "c g c c TAB c")  # analysis on "left", then "right" selected, cameras targeted again
    assert scene.object.name != "left" and centre_off_view_axis(scene) > 1.0
    turns = len(scene.camera.history)
    press(scene, "y")
    assert centre_off_view_axis(scene) < 1e-9 and len(scene.camera.history) == turns + 1
    assert scene.message == (f"analysis mode: turned to look at {scene.object.name}, the selected object (press "
                             "again to move)")
    press(scene, "y t Z*100")
    assert centre_off_view_axis(scene) < 1e-7 and scene.object.name in scene.message  # it stopped by this one


@pytest.mark.parametrize("seed", range(6))
def test_analysis_orbits_keep_the_object_on_the_view_axis(scene: Scene, seed: int) -> None:
    rng = np.random.default_rng(seed)
    scene.selected_object = int(rng.integers(0, 3))
    press(scene, "c g")
    distance = np.linalg.norm(scene.object.centre - scene.camera.origin)
    for word in rng.choice(MOVE_WORDS, size=200):
        press(scene, str(word))
        assert centre_off_view_axis(scene) < 1e-7
        assert np.linalg.norm(scene.object.centre - scene.camera.origin) == pytest.approx(distance)
    press(scene, "t z*3 Z")
    assert centre_off_view_axis(scene) < 1e-7
    assert np.linalg.norm(scene.object.centre - scene.camera.origin) == pytest.approx(distance + 10.0)


def test_reach_along_follows_the_objects_turn_and_scale() -> None:
    """A 20-unit cube stretched 2x along its own x, then turned 90 degrees about y (its x to world -z)."""
    cube = SceneObject.placed("cube", cube_mesh("cube", 10.0), PLAIN, (5, 6, 7))
    cube.push(cube.model @ transforms.rotation_about_axis(1, np.pi / 2) @ np.diag([2.0, 1.0, 1.0, 1.0]))
    assert cube.reach_along(np.array([1.0, 0.0, 0.0])) == pytest.approx(10.0)
    assert cube.reach_along(np.array([0.0, 0.0, -1.0])) == pytest.approx(20.0)
    assert cube.reach_along(np.array([0.0, 0.6, 0.8])) == pytest.approx(10.0 / 0.6)


def test_analysis_rotation_orbits_around_the_centre(scene: Scene) -> None:
    scene.selected_object = 2  # "middle", at the origin
    press(scene, "c g y*16")  # 1.6 rad around it, from (0, 0, 150)
    eye = scene.camera.origin
    np.testing.assert_allclose(eye, [150 * np.sin(1.6), 0.0, 150 * np.cos(1.6)], atol=1e-9)


def left_reach(x: float = 100.0) -> float:
    """The camera at (0, 0, 150) looks at "left" (-x, 0, 0): the line back to it leaves the 20-unit
    cube through its +z face, 10 / cos(its angle to z) from the centre."""
    return 10.0 * np.hypot(x, 150.0) / 150.0


def test_analysis_approach_stops_outside_the_objects_box(scene: Scene) -> None:
    press(scene, "c g t Z*100")
    distance = np.linalg.norm(scene.object.centre - scene.camera.origin)
    assert distance == pytest.approx(left_reach() + commands.ANALYSIS_GAP)
    assert "as close to left as allowed, 10 units outside its box" in scene.message
    assert centre_off_view_axis(scene) < 1e-9
    eye = transforms.point_in_frame(scene.object.model, scene.camera.origin) - np.mean(scene.object.mesh.bounds, axis=0)
    assert eye[2] == pytest.approx(10.0 + commands.ANALYSIS_GAP * 150.0 / np.hypot(100.0, 150.0))
    camera = scene.camera  # 3 units out, as framing puts a small model (the mouse's dolly goes there too)
    camera.push(transforms.apply_local(camera.model, transforms.translation(2, 3.0 - distance)))
    press(scene, "z")  # backing away from within the minimum was refused as coming closer
    assert np.linalg.norm(scene.object.centre - scene.camera.origin) == pytest.approx(8.0)


@pytest.mark.parametrize("unit", [1e-3, 1.0, 1e3])
def test_the_steps_follow_the_models_size_by_powers_of_ten(unit: float) -> None:
    """The seed's scene in millimetres or kilometres moves the same share of itself a press: SPEC 6's
    few units are 5 of the seed's, and analysis mode's closest approach follows too."""
    scene = make_scene(unit)
    start = scene.object.model
    press(scene, "t x")
    np.testing.assert_allclose(scene.object.model, start @ transforms.translation(0, 5.0 * unit), rtol=1e-12)
    press(scene, "c g Z*100")
    distance = np.linalg.norm(scene.object.centre - scene.camera.origin)
    assert distance == pytest.approx((left_reach(95.0) + commands.ANALYSIS_GAP) * unit)  # t x moved it 5


def test_a_small_part_among_large_models_moves_and_is_approached_on_its_own_scale() -> None:
    """A 2-unit part beside the 20-unit cubes: a press moves it 0.5 (5 was two and a half of its
    lengths), and analysis mode stops 1 outside its box; a flying camera still moves on the scene's scale."""
    scene = make_scene()
    scene.objects.append(SceneObject.placed("part", cube_mesh("part", 1.0), PLAIN, (0, 0, 100)))
    scene.selected_object = 3
    start = scene.object.model
    press(scene, "t x")
    np.testing.assert_allclose(scene.object.model, start @ transforms.translation(0, 0.5), rtol=1e-12)
    camera = scene.camera.model
    press(scene, "c Z")  # flight
    np.testing.assert_allclose(scene.camera.model, camera @ transforms.translation(2, -5.0), rtol=1e-12)
    press(scene, "g Z*1000")  # analysis: 1 outside the part's +z face, seen 0.5 off its axis from 45 out
    distance = np.linalg.norm(scene.object.centre - scene.camera.origin)
    assert distance == pytest.approx(np.hypot(0.5, 45.0) / 45.0 + commands.ANALYSIS_GAP / 10)


def test_analysis_sideways_translation_is_refused(scene: Scene) -> None:
    press(scene, "c g t")
    before = len(scene.camera.history)
    press(scene, "x")
    assert len(scene.camera.history) == before and "z only" in scene.message


def test_leaving_analysis_returns_to_flight(scene: Scene) -> None:
    press(scene, "c g g")
    assert scene.modes.camera_mode is CameraMode.FLIGHT


# --- lights ----------------------------------------------------------------------------------------
def test_sun_turns_about_world_axes_and_undo_restores_it(scene: Scene) -> None:
    sun = scene.lights[0]
    start = sun.direction.copy()
    press(scene, "c c x")
    np.testing.assert_allclose(sun.direction, transforms.rotation3(0, 0.1) @ start, atol=1e-12)
    press(scene, "Y*7 z u*9")
    assert np.array_equal(sun.direction, start)
    press(scene, "u")
    assert scene.message == "nothing to undo"


def test_spotlight_axis_turns_relative_to_its_owner(scene: Scene) -> None:
    press(scene, "c c TAB TAB y")
    spot = scene.light
    assert spot.name == "object spotlight"
    np.testing.assert_allclose(spot.axis_in_owner, transforms.rotation3(1, 0.1), atol=1e-12)
    np.testing.assert_allclose(scene.placed_light(spot).direction, [-np.sin(0.1), 0.0, -np.cos(0.1)], atol=1e-12)
    press(scene, "c")  # back to objects: turning the owner turns the spot with it
    press(scene, "y")
    np.testing.assert_allclose(scene.placed_light(spot).direction, [-np.sin(0.2), 0.0, -np.cos(0.2)], atol=1e-12)


def test_bulb_moves_along_world_axes_but_does_not_turn(scene: Scene) -> None:
    press(scene, "c c TAB t x y*2")
    bulb = scene.light
    np.testing.assert_allclose(bulb.position, [5.0, 210.0, 0.0])
    press(scene, "r x")
    assert "t instead" in scene.message and len(bulb.history) == 3
    press(scene, "u*3")
    assert np.array_equal(bulb.position, [0.0, 200.0, 0.0])


def test_a_light_with_a_direction_says_where_it_points(scene: Scene) -> None:
    """In the built-in scene `2` changed no pixel and said nothing: the object spotlight points down
    each ship's -z, at empty space. Switching on or turning the sun or a spotlight says where its
    light goes; the bulb, lighting every way, and switching off say nothing."""
    press(scene, "2")
    assert scene.message == "object spotlight on (left's): pointing (0.00, 0.00, -1.00), a 25.75 deg cone"
    press(scene, "0")
    assert scene.message == "sun on: its light comes from (0.14, 0.27, 0.95)"
    press(scene, "c c TAB TAB r y*16")
    assert scene.message == "object spotlight (left's): pointing (-1.00, 0.00, 0.03), a 25.75 deg cone"
    press(scene, "3")
    assert scene.message.startswith("camera spotlight on (camera's): pointing (0.00, 0.00, -1.00)")
    for keys in ("3", "1", "TAB*3 t x"):
        press(scene, keys)
        assert scene.message == "", keys


def test_sun_and_spots_refuse_translation(scene: Scene) -> None:
    press(scene, "c c t x")
    assert scene.message and not scene.lights[0].history
    press(scene, "TAB TAB x")
    assert scene.message and not scene.lights[2].history


@pytest.mark.parametrize("seed", range(4))
def test_light_undo_is_exact_after_random_moves(scene: Scene, seed: int) -> None:
    rng = np.random.default_rng(seed)
    press(scene, "c c")
    starts = [(light.position.copy(), light.direction.copy(), light.axis_in_owner.copy())
              for light in scene.lights]
    words = " ".join(rng.choice(MOVE_WORDS + ["r", "t", "TAB"], size=150))
    press(scene, words)
    for index, light in enumerate(scene.lights):
        scene.selected_light = index
        press(scene, f"u*{len(light.history) + 1}")
        for now, start in zip((light.position, light.direction, light.axis_in_owner), starts[index]):
            assert np.array_equal(now, start)


def test_plus_and_minus_change_the_spot_aperture_within_range(scene: Scene) -> None:
    press(scene, "c c TAB TAB")
    spot = scene.light
    press(scene, "+")
    assert spot.aperture_deg == pytest.approx(25.75 + commands.APERTURE_STEP_DEG)
    press(scene, "+*100")
    assert spot.aperture_deg == SPOT_APERTURE_RANGE_DEG[1]
    press(scene, "-*100")
    assert spot.aperture_deg == SPOT_APERTURE_RANGE_DEG[0]


def test_plus_on_a_light_that_is_not_a_spot_says_so(scene: Scene) -> None:
    press(scene, "c c +")
    assert scene.lights[0].aperture_deg == 180.0 and "spotlight" in scene.message


# --- files and deletion ----------------------------------------------------------------------------
def test_f_opens_the_prompt_but_not_for_lights(scene: Scene) -> None:
    host = press(scene, "f")
    assert host.calls == [("open_file_prompt",)]
    host = press(scene, "c c f")
    assert host.calls == [] and scene.message == "cannot load a file while lights are targeted"


def test_f_with_a_path_asks_the_host_to_load_it(scene: Scene) -> None:
    host = press(scene, 'f=model.obj f="with space.obj"')
    assert host.calls == [("load_model", "model.obj"), ("load_model", "with space.obj")]
    host = RecordingHost()
    press(scene, "c c")
    dispatch(scene, KeyPress("f", "x.obj"), host)
    assert host.calls == [] and "lights" in scene.message


def test_add_loaded_selects_the_new_object_or_camera(scene: Scene) -> None:
    new = SceneObject.placed("new", cube_mesh("new"), PLAIN, (0, 0, 0))
    new.selected_face = 3
    commands.add_loaded(scene, new, as_camera=False)
    assert scene.object is new and new.selected_face == 0
    press(scene, "c")
    assert commands.loads_as_camera(scene)
    eye = SceneObject.placed("eye", cube_mesh("eye"), PLAIN, (0, 0, 50))
    commands.add_loaded(scene, eye, as_camera=True)
    assert scene.camera is eye and len(scene.objects) == 4


def test_delete_removes_the_object(scene: Scene) -> None:
    scene.selected_object = 2
    last = scene.object
    host = press(scene, "DELETE")
    assert last not in scene.objects and scene.selected_object == 1
    assert host.calls == []  # the renderer drops a departed object's buffers at its next frame
    press(scene, "DELETE*2")
    assert scene.objects == [] and scene.object is None
    press(scene, "DELETE x ENTER TAB C")  # nothing left: messages, no errors
    assert scene.message


def test_delete_always_keeps_one_camera(scene: Scene) -> None:
    scene.cameras.append(SceneObject.placed("second", cube_mesh("second"), PLAIN, (0, 0, -150)))
    press(scene, "c TAB")
    host = press(scene, "DELETE")
    assert len(scene.cameras) == 1 and scene.selected_camera == 0 and host.calls == []
    host = press(scene, "DELETE")
    assert len(scene.cameras) == 1 and host.calls == [] and "last camera" in scene.message


def test_lights_cannot_be_deleted(scene: Scene) -> None:
    press(scene, "c c DELETE")
    assert len(scene.lights) == 4 and scene.message


# --- mouse -----------------------------------------------------------------------------------------
def test_drag_turns_like_the_y_and_x_keys(scene: Scene) -> None:
    keyed = make_scene()
    press(keyed, "y x")
    press(scene, "t")  # the r/t mode does not matter to a drag
    window = (720, 360)  # VTK's trackball: a drag across the whole window turns 200 degrees
    press_share = commands.ROTATION_STEP_RAD / np.radians(200.0)
    commands.drag(scene, press_share * window[0], press_share * window[1], window)
    np.testing.assert_allclose(scene.object.model, keyed.object.model, atol=1e-9)
    assert scene.modes.transform is TransformKind.TRANSLATE


@pytest.mark.parametrize("targeting", ["", "c", "c c"])
def test_one_drag_is_one_undo_step_whatever_it_turns(scene: Scene, targeting: str) -> None:
    """Each mouse event of a ctrl-drag pushed a step of its own (two, one an axis): 20 presses of u to
    undo a drag of ten events. A button or a key starts the next drag."""
    press(scene, targeting or "r")
    moved = {"": lambda: scene.object.model, "c": lambda: scene.camera.model,
             "c c": lambda: np.concatenate([scene.light.position, scene.light.direction])}[targeting]
    start = moved().copy()
    for _ in range(10):
        commands.drag(scene, 3.0, 2.0, (400, 300))
    after_first = moved().copy()
    commands.end_view_gesture(scene)  # the button let go and pressed again
    for _ in range(5):
        commands.drag(scene, 4.0, 0.0, (400, 300))
    assert not np.allclose(moved(), after_first)
    press(scene, "u")
    np.testing.assert_allclose(moved(), after_first, atol=1e-9)
    press(scene, "u")
    np.testing.assert_allclose(moved(), start, atol=1e-9)


# --- status and help -------------------------------------------------------------------------------
def test_status_line_reports_modes_lights_and_selection(scene: Scene) -> None:
    press(scene, "0 2 F g t ENTER*2")
    line = status_line(scene)
    for part in ("target objects", "translate global", "gouraud", "perspective", "culling off",
                 "filled", "texture on", "lights 0\u00b72\u00b7", "object left face 3/6", "camera camera",
                 "light sun"):
        assert part in line, part
    press(scene, "c g")
    assert "flight" not in status_line(scene) and "analysis" in status_line(scene)


def test_status_line_gives_a_step_and_a_parallel_size_on_a_scale_other_than_the_seeds() -> None:
    scene = make_scene(1e-3)  # the cubes in thousandths
    press(scene, "t p")
    line = status_line(scene)
    assert "translate 0.005 local" in line and "parallel 0.15" in line, line
    seed_scale = make_scene()
    press(seed_scale, "t")
    assert "translate local" in status_line(seed_scale)  # SPEC's 5: not said


def test_help_lists_every_key_with_its_state(scene: Scene) -> None:
    lines = help_lines(scene, KEYMAP)
    listed = [token for line in lines for token in line.split("  ")[0].split()]
    assert listed == [*KEYMAP, "f=PATH", "click"]
    culling = next(line for line in lines if line.startswith("b "))
    assert culling.endswith("[off]")
    press(scene, "b")
    assert next(line for line in help_lines(scene, KEYMAP) if line.startswith("b ")).endswith("[on]")


def test_the_help_fits_a_projectors_window(scene: Scene) -> None:
    """48 lines of help, with the status line, did not fit 768 pixels: keys the table lists together
    (x y z, X Y Z, the four lights, + and -, h and F1) now share a line, with every state said."""
    lines = help_lines(scene, KEYMAP)
    assert len(lines) <= 38
    lights = next(line for line in lines if line.startswith("0 1 2 3 "))
    assert lights.endswith("[sun off, bulb off, object spotlight off, camera spotlight off]")
    press(scene, "1")
    assert "bulb on" in next(line for line in help_lines(scene, KEYMAP) if line.startswith("0 1 2 3 "))
    assert any(line.startswith("x y z ") and "+x, +y, +z" in line for line in lines)


def test_the_help_says_how_far_a_press_of_x_y_z_goes_now() -> None:
    """0.1 rad (SPEC 6) and the translation step of what is targeted, on its scale: a student stood a model up
    with X*16 by trial, the step being only in the README and the matrices panel."""
    for scale, step in ((1.0, "5"), (1e-3, "0.005")):
        lines = help_lines(make_scene(scale), KEYMAP)
        assert next(line for line in lines if line.startswith("x y z ")).endswith(f"[0.1 rad or {step} units a press]")
        assert not next(line for line in lines if line.startswith("X Y Z ")).endswith("]")  # said once


def test_plus_and_minus_say_the_aperture_and_when_it_stops(scene: Scene) -> None:
    press(scene, "c c TAB TAB TAB +")
    assert scene.message == "camera spotlight: aperture 32.5 deg"
    press(scene, "+*30")
    assert scene.message == "camera spotlight: aperture 89 deg (its widest: 1 to 89 deg)"
    press(scene, "-*60")
    assert scene.message == "camera spotlight: aperture 1 deg (its narrowest: 1 to 89 deg)"


def test_delete_says_what_it_removed_and_what_is_selected(scene: Scene) -> None:
    names = [obj.name for obj in scene.objects]
    press(scene, "DELETE")
    assert scene.message == f"deleted {names[0]}; {names[1]} selected"
