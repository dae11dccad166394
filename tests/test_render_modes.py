"""What each drawing mode puts on screen (SPEC 5): lines, `o`/`d` face selection, normals, culling,
cameras, the light marker; and that GPU buffers live as long as their object, not a frame."""

from __future__ import annotations

import numpy as np
import pytest

from marraztu.model.scene import Fill, Material, Projection, Scene, SceneObject, Shading, Target
from marraztu.render import gpu
from support.scenes import BACKGROUND as BACKGROUND_BYTES

BACKGROUND = np.array(BACKGROUND_BYTES)
WHITE = np.array([255, 255, 255])
GREEN = np.array([0, 255, 0])
RED = np.array([255, 0, 0])
YELLOW = np.array([255, 255, 0])
MATERIAL = Material(ka=(0.2, 0.3, 0.4), kd=(0.6, 0.5, 0.4), ks=(0.5, 0.4, 0.3), ns=20.0)


def count(pixels: np.ndarray, colour: np.ndarray) -> int:
    return int((pixels == colour).all(axis=2).sum())


def is_background(pixel: np.ndarray) -> bool:
    return bool((pixel == BACKGROUND).all())


def pixel_of(point: tuple[float, float, float], size: int, half_view: float = 150.0) -> tuple[int, int]:
    """Row and column of a point in the z = 0 plane seen from (0, 0, 150) with a 90 deg field."""
    scale = size / (2.0 * half_view)
    return int(size / 2 - point[1] * scale), int(size / 2 + point[0] * scale)


def rotation_x(degrees: float) -> np.ndarray:
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    m = np.eye(4)
    m[1:3, 1:3] = [[c, -s], [s, c]]
    return m


def rotation_y(degrees: float) -> np.ndarray:
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    m = np.eye(4)
    m[0, 0], m[0, 2], m[2, 0], m[2, 2] = c, s, -s, c
    return m


# --- lines mode --------------------------------------------------------------------------------
def test_lines_mode_draws_edges_only_selected_green(offscreen, make_quad, make_scene) -> None:
    left = SceneObject.placed("left", make_quad(30.0), MATERIAL, (-60, 0, 0))
    right = SceneObject.placed("right", make_quad(30.0), MATERIAL, (60, 0, 0))
    scene = make_scene([left, right])
    scene.modes.fill = Fill.LINES
    pixels = offscreen(scene, (127, 127))
    assert count(pixels[:, :63], GREEN) > 50 and count(pixels[:, :63], WHITE) == 0
    assert count(pixels[:, 64:], WHITE) > 50 and count(pixels[:, 64:], GREEN) == 0
    for centre in ((-60, 0, 0), (60, 0, 0)):  # no fill inside the squares
        assert is_background(pixels[pixel_of(centre, 127)])
    assert set(map(tuple, pixels.reshape(-1, 3))) <= {tuple(BACKGROUND), tuple(GREEN), tuple(WHITE)}


def test_lines_mode_draws_polygon_edges_not_fan_diagonals(offscreen, make_quad, make_scene) -> None:
    scene = make_scene([SceneObject.placed("quad", make_quad(60.0), MATERIAL, (0, 0, 0))])
    scene.modes.fill = Fill.LINES
    pixels = offscreen(scene, (127, 127))
    # The fan diagonal of a square runs through its centre and the quarter points.
    for point in ((0, 0, 0), (30, 30, 0), (-30, -30, 0)):
        assert is_background(pixels[pixel_of(point, 127)])
    assert count(pixels, GREEN) > 4 * 40


# --- `o` and `d` ---------------------------------------------------------------------------------
FACE_CENTRES = [(-50, -7, 0), (-20, 0, 0), (20, 0, 0), (60, 0, 0)]


@pytest.fixture
def strip_scene(build_mesh, make_quad, make_scene) -> Scene:
    """Four faces in a row, left to right: a triangle, a square, a pentagon, a square (so the fan
    triangle ranges of each face differ), plus a second object below them."""
    positions = [(-80, -20, 0), (-40, -20, 0), (-40, 20, 0),  # 0 triangle
                 (-40, -20, 0), (0, -20, 0), (0, 20, 0), (-40, 20, 0),  # 1 square
                 (0, -20, 0), (40, -20, 0), (40, 20, 0), (20, 20, 0), (0, 20, 0),  # 2 pentagon
                 (40, -20, 0), (80, -20, 0), (80, 20, 0), (40, 20, 0)]  # 3 square
    faces = [[0, 1, 2], [3, 4, 5, 6], [7, 8, 9, 10, 11], [12, 13, 14, 15]]
    strip = SceneObject.placed("strip", build_mesh("strip", positions, faces), MATERIAL, (0, 0, 0))
    other = SceneObject.placed("other", make_quad(15.0), MATERIAL, (0, -80, 0))
    return make_scene([strip, other])


def drawn_faces(pixels: np.ndarray) -> list[bool]:
    return [not is_background(pixels[pixel_of(c, 127)]) for c in FACE_CENTRES]


def test_everything_drawn_by_default(offscreen, strip_scene: Scene) -> None:
    pixels = offscreen(strip_scene, (127, 127))
    assert drawn_faces(pixels) == [True] * 4
    assert not is_background(pixels[pixel_of((0, -80, 0), 127)])


def test_d_draws_only_the_selected_object(offscreen, strip_scene: Scene) -> None:
    strip_scene.modes.draw_all = False
    pixels = offscreen(strip_scene, (127, 127))
    assert drawn_faces(pixels) == [True] * 4
    assert is_background(pixels[pixel_of((0, -80, 0), 127)])


def test_o_draws_only_the_selected_face(offscreen, strip_scene: Scene) -> None:
    strip_scene.modes.triangle_only, strip_scene.modes.draw_all = True, False
    strip_scene.objects[0].selected_face = 2
    pixels = offscreen(strip_scene, (127, 127))
    assert drawn_faces(pixels) == [False, False, True, False]
    assert is_background(pixels[pixel_of((0, -80, 0), 127)])


@pytest.mark.parametrize("fill", list(Fill), ids=lambda f: f.value)
def test_o_with_all_builds_the_object_up_face_by_face(offscreen, strip_scene: Scene,
                                                      fill: Fill) -> None:
    strip_scene.modes.triangle_only, strip_scene.modes.draw_all = True, True
    strip_scene.modes.fill = fill
    probe = FACE_CENTRES if fill is Fill.FILLED else [(-40, 0, 0), (0, 0, 0), (40, 0, 0), (80, 0, 0)]
    for selected in range(4):
        strip_scene.objects[0].selected_face = selected
        pixels = offscreen(strip_scene, (127, 127))
        # Lines mode probes each face's right edge, which no face to its left has.
        seen = [not is_background(pixels[pixel_of(p, 127)]) for p in probe]
        assert seen == [k <= selected for k in range(4)]
        assert is_background(pixels[pixel_of((0, -80, 0), 127)])


# --- normals -----------------------------------------------------------------------------------
@pytest.fixture
def tilted_scene(make_quad, make_scene) -> Scene:
    """A square tipped back 60 deg about x, close to the camera, so its normals show as segments."""
    quad = SceneObject(name="tilted", mesh=make_quad(20.0), material=MATERIAL,
                       history=[rotation_x(-60.0)])
    return make_scene([quad], camera_at=(0, 0, 40))


NORMALS_SIZE = (191, 191)  # normals are 5% of the square's diagonal: give them a few pixels
NORMALS_MIDDLE = 95


def test_normals_appear_only_when_on(offscreen, tilted_scene: Scene) -> None:
    assert count(offscreen(tilted_scene, NORMALS_SIZE), YELLOW) == 0
    tilted_scene.modes.normals = True
    assert count(offscreen(tilted_scene, NORMALS_SIZE), YELLOW) >= 4


def test_flat_normal_from_the_centroid_gouraud_normals_from_the_vertices(offscreen,
                                                                          tilted_scene) -> None:
    tilted_scene.modes.normals = True
    flat = (offscreen(tilted_scene, NORMALS_SIZE) == YELLOW).all(axis=2)
    tilted_scene.modes.shading = Shading.GOURAUD
    gouraud = (offscreen(tilted_scene, NORMALS_SIZE) == YELLOW).all(axis=2)
    flat_rows, flat_cols = np.nonzero(flat)
    # The face normal starts at the centre (on the view axis) and leans up, toward +y.
    assert np.abs(flat_cols - NORMALS_MIDDLE).max() <= 1
    assert flat_rows.min() < NORMALS_MIDDLE - 2 and flat_rows.max() <= NORMALS_MIDDLE
    # The vertex normals sit at the four corners: left and right of the centre, none at it.
    gouraud_cols = np.nonzero(gouraud)[1]
    assert (gouraud_cols < NORMALS_MIDDLE - 20).any() and (gouraud_cols > NORMALS_MIDDLE + 20).any()
    assert not gouraud[:, NORMALS_MIDDLE - 5:NORMALS_MIDDLE + 6].any()


def test_each_face_normal_is_its_own_faces(offscreen, build_mesh, make_scene) -> None:
    """A sheet folded along a vertical ridge toward the camera: each slope's face normal (read from its
    polygon's own surface row) leans out sideways as long as it comes forward, 7 pixels across here,
    where the ridge's vertex normal, pointing at the camera, would draw a segment of 2."""
    positions = [(-10, -10, -10), (0, -10, 0), (0, 10, 0), (-10, 10, -10), (10, -10, -10), (10, 10, -10)]
    fold = build_mesh("fold", positions, [(0, 1, 2, 3), (1, 4, 5, 2)])
    scene = make_scene([SceneObject.placed("fold", fold, MATERIAL, (0, 0, 0))], camera_at=(0, 0, 15))
    scene.modes.normals = True
    yellow = (offscreen(scene, NORMALS_SIZE) == YELLOW).all(axis=2)
    left, right = (np.nonzero(half)[1] for half in (yellow[:, :NORMALS_MIDDLE], yellow[:, NORMALS_MIDDLE + 1:]))
    assert left.size and right.size
    assert left.max() - left.min() >= 5 and right.max() - right.min() >= 5, (left, right)
    assert abs((NORMALS_MIDDLE - 1 - left.max()) - right.min()) <= 1  # mirror images


def test_normals_in_lines_mode(offscreen, tilted_scene: Scene) -> None:
    tilted_scene.modes.normals, tilted_scene.modes.fill = True, Fill.LINES
    assert count(offscreen(tilted_scene, NORMALS_SIZE), YELLOW) >= 4


# --- back faces on a closed box ----------------------------------------------------------------
@pytest.fixture
def box_scene(make_box, make_scene) -> Scene:
    box = SceneObject(name="box", mesh=make_box(30.0), material=MATERIAL,
                      history=[rotation_x(30.0) @ rotation_y(40.0)])
    return make_scene([box])


@pytest.mark.parametrize("projection", list(Projection), ids=lambda p: p.value)
def test_closed_box_filled_culling_changes_nothing(offscreen, box_scene: Scene,
                                                   projection: Projection) -> None:
    box_scene.modes.projection = projection
    box_scene.lights[0].on = True
    shown = offscreen(box_scene, (127, 127))
    box_scene.modes.culling = True
    culled = offscreen(box_scene, (127, 127))
    assert count(shown, RED) == 0
    assert (shown == culled).all()
    assert count(shown, BACKGROUND) < 127 * 127 - 500


@pytest.mark.parametrize("projection", list(Projection), ids=lambda p: p.value)
def test_closed_box_lines_back_edges_red_or_culled(offscreen, box_scene: Scene,
                                                   projection: Projection) -> None:
    box_scene.modes.fill, box_scene.modes.projection = Fill.LINES, projection
    shown = offscreen(box_scene, (127, 127))
    box_scene.modes.culling = True
    culled = offscreen(box_scene, (127, 127))
    assert count(shown, RED) > 20 and count(shown, GREEN) > 100
    assert count(culled, RED) == 0 and count(culled, GREEN) == count(shown, GREEN)


def test_edges_find_their_polygons_in_tables_of_several_rows(offscreen, make_box, make_scene, monkeypatch) -> None:
    # Each corner names its polygon's texel in the tables of face points and normals; a table one
    # texel wide puts every polygon on a row of its own, and the picture must not change.
    def lines_of_a_box() -> np.ndarray:
        box = SceneObject(name="box", mesh=make_box(30.0), material=MATERIAL,
                          history=[rotation_x(30.0) @ rotation_y(40.0)])  # a new object: its edges built anew
        scene = make_scene([box])
        scene.modes.fill = Fill.LINES
        return offscreen(scene, (127, 127))

    one_row = lines_of_a_box()
    monkeypatch.setattr(gpu, "EDGE_FACE_TEXTURE_SIDE", 1)
    assert (lines_of_a_box() == one_row).all()
    assert count(one_row, RED) > 20 and count(one_row, GREEN) > 100


def test_inside_a_closed_box_every_face_is_a_back_face(offscreen, box_scene: Scene) -> None:
    box_scene.cameras[0].history = [np.eye(4)]  # the eye at the box's centre
    inside = offscreen(box_scene, (63, 63))
    assert (inside == RED).all()
    box_scene.modes.culling = True
    assert (offscreen(box_scene, (63, 63)) == BACKGROUND).all()


# --- cameras, the light marker, the aspect ratio -------------------------------------------------
def test_other_cameras_are_drawn_the_viewer_is_not(offscreen, build_mesh, make_quad,
                                                   make_scene) -> None:
    # A camera body 50 units in front of its own origin: it would fill the view if it were drawn.
    body = build_mesh("body", [(-20, -20, -50), (20, -20, -50), (20, 20, -50), (-20, 20, -50)],
                      [[0, 1, 2, 3]])
    scene = make_scene([SceneObject.placed("far", make_quad(5.0), MATERIAL, (0, 0, -400))])
    scene.cameras = [SceneObject.placed("viewer", body, MATERIAL, (0, 0, 150)),
                     SceneObject.placed("other", body, MATERIAL, (0, 0, 100))]
    pixels = offscreen(scene, (63, 63))
    # "other" is 100 in front of the viewer: its body (at z = 50) covers the centre, 40 px wide.
    assert not is_background(pixels[31, 31])
    scene.selected_camera = 1  # now looking through "other": its body must not hide the view
    pixels = offscreen(scene, (63, 63))
    assert is_background(pixels[31, 20]) and not is_background(pixels[31, 31])  # only "far" is seen


def test_selected_light_marker(offscreen, make_quad, make_scene) -> None:
    scene = make_scene([SceneObject.placed("quad", make_quad(20.0), MATERIAL, (0, 0, 0))])
    bulb = scene.lights[1]
    bulb.position = np.array([60.0, 60.0, 0.0])
    scene.selected_light = 1
    row, col = pixel_of((60, 60, 0), 127)
    assert is_background(offscreen(scene, (127, 127))[row, col])  # only when the target is lights
    scene.modes.target = Target.LIGHTS
    bulb.on = True
    marker = offscreen(scene, (127, 127))[row, col].astype(int)
    assert np.abs(marker - np.array([250, 50, 150])).max() <= 1


@pytest.mark.parametrize(("side", "dot"), [(127, 9), (800, 9), (1600, 18)])
def test_the_light_marker_grows_with_the_framebuffer_as_the_text_does(offscreen, make_quad, make_scene, side: int,
                                                                      dot: int) -> None:
    """9 pixels across up to 800 on the shorter side, then as the overlay's text grows (layout.screen_scale):
    a projector's or a HiDPI screen's dot as large to the eye as an 800 pixel window's."""
    scene = make_scene([SceneObject.placed("quad", make_quad(20.0), MATERIAL, (0, 0, 0))])
    scene.lights[1].position, scene.lights[1].on = np.array([60.0, 60.0, 0.0]), True
    scene.selected_light, scene.modes.target = 1, Target.LIGHTS
    lit = (np.abs(offscreen(scene, (side, side)).astype(int) - [250, 50, 150]).max(axis=2) <= 1)
    rows, cols = np.nonzero(lit)
    assert rows.max() - rows.min() + 1 == dot and cols.max() - cols.min() + 1 == dot


def test_aspect_ratio_keeps_squares_square(offscreen, make_quad, make_scene) -> None:
    scene = make_scene([SceneObject.placed("quad", make_quad(50.0), MATERIAL, (0, 0, 0))])
    for projection in Projection:
        scene.modes.projection = projection
        drawn = (offscreen(scene, (191, 95)) != BACKGROUND).any(axis=2)
        rows, cols = np.nonzero(drawn)
        height, width = rows.max() - rows.min() + 1, cols.max() - cols.min() + 1
        assert abs(int(height) - int(width)) <= 1 and height > 20


# --- GPU resources ---------------------------------------------------------------------------------
def test_buffers_built_once_and_dropped_with_their_object(offscreen, renderer, make_quad,
                                                          make_scene) -> None:
    first = SceneObject.placed("first", make_quad(20.0), MATERIAL, (-40, 0, 0))
    second = SceneObject.placed("second", make_quad(20.0), MATERIAL, (40, 0, 0))
    scene = make_scene([first, second])
    offscreen(scene, (63, 63))
    def held(obj: SceneObject) -> bool:
        return any(uid == obj.uid for uid, _ in renderer._objects)

    built = dict(renderer._objects)
    assert held(first) and held(second)
    offscreen(scene, (63, 63))
    assert all(renderer._objects[key] is gpu for key, gpu in built.items())  # reused, not rebuilt per frame
    scene.objects.remove(second)
    offscreen(scene, (63, 63))
    assert not held(second)
    renderer.release_object(first)
    assert not held(first)
    offscreen(scene, (63, 63))  # and comes back when drawn again
    assert held(first)
