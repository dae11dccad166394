"""The GPU's pixels against SPEC 4's formula (app/lighting.py), one light at a time.

A square faces the camera (spun about its normal and tilted a little, so the model and normal
matrices matter), texture off. The framebuffer is odd-sized so the centre pixel samples exactly the
square's centre, which is the midpoint of the diagonal shared by its two fan triangles:
- Flat: the whole polygon has the colour computed at its first vertex with the face normal;
- Gouraud: the centre is the average of the colours at the diagonal's ends, vertices 0 and 2
  (perspective-correct interpolation at a 3D midpoint is the plain average of the ends).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest

from marraztu.loaders.scenefile import load_scene
from marraztu.model.build import build_mesh
from marraztu.model.geometry import FLOAT32_MAX, unit
from marraztu.model.lighting import lit_colour_bytes, shade, shade_terms, to_bytes
from marraztu.model.lights import DIRECTIONAL, Owner, WorldLight
from marraztu.model.scene import SWITCHED_SHADINGS, Fill, Material, Projection, Scene, SceneObject, Shading
from support.scenes import BACKGROUND as BACKGROUND_BYTES

SIZE = (63, 63)
CENTRE = (31, 31)  # row, column: the pixel whose centre is the view axis
BACKGROUND = np.array(BACKGROUND_BYTES)
RED = np.array([255, 0, 0])
CAMERA = np.array([0.0, 0.0, 150.0])
MATERIAL = Material(ka=(0.2, 0.3, 0.4), kd=(0.6, 0.5, 0.4), ks=(0.5, 0.4, 0.3), ns=20.0)
QUAD_HALF = 50.0


def rotation_z(degrees: float) -> np.ndarray:
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    m = np.eye(4)
    m[:2, :2] = [[c, -s], [s, c]]
    return m


def rotation_y(degrees: float) -> np.ndarray:
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    m = np.eye(4)
    m[0, 0], m[0, 2], m[2, 0], m[2, 2] = c, s, -s, c
    return m


def translation(x: float, y: float, z: float) -> np.ndarray:
    m = np.eye(4)
    m[:3, 3] = (x, y, z)
    return m


# The square's centre stays on the view axis; its corners and normal move off the simple values.
QUAD_MODEL = translation(0.0, 0.0, -20.0) @ rotation_y(25.0) @ rotation_z(30.0)


def world(point: tuple[float, float, float], model: np.ndarray = QUAD_MODEL) -> np.ndarray:
    return (model @ np.append(point, 1.0))[:3]


def world_normal(normal: tuple[float, float, float], model: np.ndarray = QUAD_MODEL) -> np.ndarray:
    n = np.linalg.inv(model[:3, :3]).T @ np.asarray(normal, float)
    return n / np.linalg.norm(n)


def axis_turned_to(direction: np.ndarray) -> np.ndarray:
    """A rotation taking the owner's -z onto `direction` (for a spotlight's axis_in_owner)."""
    forward = direction / np.linalg.norm(direction)
    back = -forward
    side = np.cross([0.0, 1.0, 0.0], back)
    side /= np.linalg.norm(side)
    up = np.cross(back, side)
    return np.column_stack([side, up, back])


@pytest.fixture
def quad_scene(make_quad: Callable[..., Any], make_scene: Callable[..., Scene]) -> Scene:
    quad = SceneObject(name="quad", mesh=make_quad(QUAD_HALF), material=MATERIAL,
                       history=[QUAD_MODEL.copy()])
    return make_scene([quad])


# --- each light alone: scene set-up and the same light written out for lighting.py -----------
def light_sun(scene: Scene) -> list[dict[str, Any]]:
    scene.lights[0].on = True
    return [dict(kind="directional", intensity=(200, 200, 200), direction=(0.1, 0.2, 0.7))]


def light_bulb(scene: Scene) -> list[dict[str, Any]]:
    # Near and off-axis, so L differs a lot between the corners (Flat must use the first one).
    scene.lights[1].on = True
    scene.lights[1].position = np.array([40.0, 30.0, 60.0])
    return [dict(kind="point", intensity=(250, 50, 150), position=(40, 30, 60))]


def light_camera_spot_inside(scene: Scene) -> list[dict[str, Any]]:
    scene.lights[3].on = True  # at the camera, along its -z; the corners are ~23 deg off the axis
    return [dict(kind="spot", intensity=(155, 120, 75), position=CAMERA, direction=(0, 0, -1),
                 aperture_deg=30.0)]


def light_camera_spot_outside(scene: Scene) -> list[dict[str, Any]]:
    scene.lights[3].on = True
    scene.lights[3].aperture_deg = 10.0
    return [dict(kind="spot", intensity=(155, 120, 75), position=CAMERA, direction=(0, 0, -1),
                 aperture_deg=10.0)]


def light_free_spot(scene: Scene) -> list[dict[str, Any]]:
    """A spot with no owner, aimed at the square's first vertex: vertex 0 inside its 20 deg cone,
    vertex 2 far outside, so Flat is lit all over and Gouraud half lit at the centre."""
    spot = scene.lights[2]
    position = np.array([60.0, -20.0, 80.0])
    axis = world((-QUAD_HALF, -QUAD_HALF, 0.0)) - position
    spot.on, spot.owner, spot.position, spot.aperture_deg = True, Owner.NONE, position, 20.0
    spot.axis_in_owner = axis_turned_to(axis)
    return [dict(kind="spot", intensity=(75, 75, 75), position=position, direction=axis,
                 aperture_deg=20.0)]


LIGHTS = [light_sun, light_bulb, light_camera_spot_inside, light_camera_spot_outside,
          light_free_spot]


def expected_centre(scene: Scene, lights: list[dict[str, Any]],
                    material: Material = MATERIAL) -> np.ndarray:
    parallel = scene.modes.projection is Projection.PARALLEL
    eye_or_view = np.array([0.0, 0.0, 1.0]) if parallel else CAMERA
    first, opposite = world((-QUAD_HALF, -QUAD_HALF, 0.0)), world((QUAD_HALF, QUAD_HALF, 0.0))
    normal = world_normal((0.0, 0.0, 1.0))

    def at(point: np.ndarray) -> np.ndarray:
        return shade(point, normal, eye_or_view, material, lights, scene.ambient, parallel)

    if scene.modes.shading is Shading.FLAT:
        return to_bytes(at(first))
    return to_bytes((at(first) + at(opposite)) / 2.0)


def assert_close(actual: np.ndarray, expected: np.ndarray) -> None:
    difference = np.abs(actual.astype(int) - expected.astype(int))
    assert difference.max() <= 1, f"rendered {actual}, formula {expected}"


@pytest.mark.parametrize("projection", list(Projection), ids=lambda p: p.value)
@pytest.mark.parametrize("shading", SWITCHED_SHADINGS, ids=lambda s: s.value)
@pytest.mark.parametrize("add_light", LIGHTS, ids=lambda f: f.__name__.removeprefix("light_"))
def test_each_light_alone_matches_the_formula(offscreen, quad_scene: Scene, add_light,
                                              shading: Shading, projection: Projection) -> None:
    lights = add_light(quad_scene)
    quad_scene.modes.shading = shading
    quad_scene.modes.projection = projection
    pixels = offscreen(quad_scene, SIZE)
    assert_close(pixels[CENTRE], expected_centre(quad_scene, lights))


# A lesson's scene: the square, turned, and only the bulb on, where the file puts it.
BULB_LESSON = """[lights.bulb]
on = true
position = [40, 30, 60]

[[cameras]]
position = [0, 0, 150]

[[objects]]
model = "square.obj"
position = [0, 0, -20]
rotation = [0, 25, 0]
material = { ka = [0.2, 0.3, 0.4], kd = [0.6, 0.5, 0.4], ks = [0.5, 0.4, 0.3], ns = 20 }
"""
SQUARE_OBJ = f"v {-QUAD_HALF} {-QUAD_HALF} 0\nv {QUAD_HALF} {-QUAD_HALF} 0\nv {QUAD_HALF} {QUAD_HALF} 0\n" \
             f"v {-QUAD_HALF} {QUAD_HALF} 0\nf 1 2 3 4\n"


@pytest.mark.parametrize("shading", SWITCHED_SHADINGS, ids=lambda s: s.value)
def test_a_scene_files_bulb_lights_the_square_as_the_formula(offscreen, tmp_path: Path, shading: Shading) -> None:
    """Every lesson started with the lights off at SPEC's numbers; the file's bulb, at its place and
    with SPEC's intensity and Ia, lights the square's centre as SPEC 4 says."""
    (tmp_path / "square.obj").write_text(SQUARE_OBJ)
    (tmp_path / "lesson.toml").write_text(BULB_LESSON)
    scene = load_scene(tmp_path / "lesson.toml")
    scene.modes.shading = shading
    assert [light.on for light in scene.lights] == [False, True, False, False]
    model = scene.objects[0].model
    first, opposite = (world((-QUAD_HALF, -QUAD_HALF, 0.0), model), world((QUAD_HALF, QUAD_HALF, 0.0), model))
    normal = world_normal((0.0, 0.0, 1.0), model)
    bulb = [dict(kind="point", intensity=(250, 50, 150), position=(40, 30, 60))]

    def at(point: np.ndarray, lights: list[dict[str, Any]]) -> np.ndarray:
        return shade(point, normal, CAMERA, MATERIAL, lights, (200, 75, 255), False)

    ends = (first,) if shading is Shading.FLAT else (first, opposite)
    expected = to_bytes(sum(at(point, bulb) for point in ends) / len(ends))
    assert np.abs(expected.astype(int) - to_bytes(at(first, [])).astype(int)).max() > 5  # the bulb adds light
    assert_close(offscreen(scene, SIZE)[CENTRE], expected)


@pytest.mark.parametrize("add_light", [light_sun, light_bulb, light_camera_spot_inside],
                         ids=lambda f: f.__name__.removeprefix("light_"))
def test_lit_cases_really_add_light(quad_scene: Scene, add_light) -> None:
    """Guards the test above against agreeing on 'ambient only' by accident."""
    lights = add_light(quad_scene)
    assert np.abs(expected_centre(quad_scene, lights).astype(int)
                  - expected_centre(quad_scene, []).astype(int)).max() > 5


def test_flat_uses_the_first_vertex_not_the_centre(quad_scene: Scene) -> None:
    lights = light_bulb(quad_scene)
    at_centre = shade(world((0.0, 0.0, 0.0)), world_normal((0, 0, 1)), CAMERA, MATERIAL, lights,
                      quad_scene.ambient, False)
    assert np.abs(to_bytes(at_centre).astype(int)
                  - expected_centre(quad_scene, lights).astype(int)).max() > 5


def test_flat_polygon_is_one_colour(offscreen, quad_scene: Scene) -> None:
    light_bulb(quad_scene)
    pixels = offscreen(quad_scene, SIZE)
    inside = pixels[26:37, 26:37].reshape(-1, 3)
    assert (inside == inside[0]).all()


def test_ambient_only(offscreen, quad_scene: Scene) -> None:
    pixels = offscreen(quad_scene, SIZE)
    expected = to_bytes(np.asarray(MATERIAL.ka) * quad_scene.ambient)
    assert_close(pixels[CENTRE], expected)
    assert_close(pixels[0, 0], BACKGROUND)


@pytest.mark.parametrize("shading", SWITCHED_SHADINGS, ids=lambda s: s.value)
def test_clamped_to_255(offscreen, quad_scene: Scene, shading: Shading) -> None:
    bright = Material(ka=(2.0, 1.0, 0.2), kd=(0.9, 0.9, 0.1), ks=(0.5, 0.5, 0.0), ns=10.0)
    quad_scene.objects[0].material = bright
    quad_scene.modes.shading = shading
    lights = light_sun(quad_scene)
    pixels = offscreen(quad_scene, SIZE)
    expected = expected_centre(quad_scene, lights, bright)
    assert expected[0] == 255 and expected[2] < 255  # one channel clamped, another not
    assert_close(pixels[CENTRE], expected)


@pytest.mark.parametrize("shading", SWITCHED_SHADINGS, ids=lambda s: s.value)
def test_clamped_before_the_texture_multiplies(offscreen, renderer, quad_scene: Scene,
                                               shading: Shading) -> None:
    """The framebuffer clamps too, so clamping only shows where something follows it: I = 400 on a
    grey texel is 255 * 0.5, not 400 * 0.5."""
    texel = (128, 128, 128)
    bright = Material(ka=(2.0, 2.0, 2.0), kd=(0, 0, 0), ks=(0, 0, 0), ns=1.0)
    quad_scene.objects[0].material = bright
    quad_scene.ambient = np.array([200.0, 200.0, 200.0])
    quad_scene.modes.shading, quad_scene.modes.texture = shading, True
    quad_scene.texture = np.array([[texel]], np.uint8)
    pixels = offscreen(quad_scene, SIZE)
    expected = lit_colour_bytes(world((0, 0, 0)), (0, 0, 1), CAMERA, bright, [],
                                (200, 200, 200), False, texture_rgb=texel)
    assert tuple(expected) == (128, 128, 128)
    assert_close(pixels[CENTRE], expected)


@pytest.mark.parametrize("ns", [1e9, FLOAT32_MAX], ids=["1e9", "float32-max"])
def test_a_huge_shininess_lights_every_vertex_as_the_formula(offscreen, make_scene, ns: float) -> None:
    """Vertex normals a float32 rounding or two from H, Gouraud: N.H rounds past 1 at many of them on
    the GPU, where pow of a huge ns was infinite and Ks's 0 green times it NaN (G read 99-255 on
    llvmpipe). The green is Kd's alone, and the red at most I * Ks."""
    side = 33
    xs = np.linspace(-60.0, 60.0, side)
    grid_x, grid_y = np.meshgrid(xs, xs)
    positions = np.stack([grid_x.ravel(), grid_y.ravel(), np.zeros(side * side)], axis=1)
    faces = [[row * side + col, row * side + col + 1, (row + 1) * side + col + 1, (row + 1) * side + col]
             for row in range(side - 1) for col in range(side - 1)]
    sun_to_light, view = unit(np.array([0.1, 0.2, 0.7])), np.array([0.0, 0.0, 1.0])
    halfway = unit(sun_to_light + view)
    normals = halfway + np.random.default_rng(14).normal(0.0, 3e-8, (side * side, 3))
    mesh = build_mesh("grid", positions, faces, normals=normals, attributes_per_vertex=True)
    partly_shiny = Material(ka=(0.0, 0.0, 0.0), kd=(0.0, 0.5, 0.0), ks=(1.0, 0.0, 0.0), ns=ns)
    scene = make_scene([SceneObject.placed("grid", mesh, partly_shiny, (0.0, 0.0, 0.0))])
    scene.lights[0].on = True
    scene.modes.shading, scene.modes.projection = Shading.GOURAUD, Projection.PARALLEL
    pixels = offscreen(scene, (127, 127))
    drawn = pixels[(pixels != BACKGROUND).any(axis=2)]
    assert len(drawn) > 1000
    green = to_bytes(200.0 * 0.5 * np.array([float(halfway @ sun_to_light)] * 3))[1]
    assert np.abs(drawn[:, 1].astype(int) - int(green)).max() <= 1, np.unique(drawn[:, 1])
    assert drawn[:, 0].max() <= 201 and (drawn[:, 2] == 0).all()


@pytest.fixture
def back_scene(make_quad, make_scene) -> Scene:
    """The square wound the other way: its normal points away from the camera."""
    quad = SceneObject.placed("away", make_quad(QUAD_HALF, facing_camera=False), MATERIAL, (0, 0, 0))
    return make_scene([quad])


@pytest.mark.parametrize("projection", list(Projection), ids=lambda p: p.value)
@pytest.mark.parametrize("shading", SWITCHED_SHADINGS, ids=lambda s: s.value)
def test_back_face_is_red(offscreen, back_scene: Scene, shading: Shading,
                          projection: Projection) -> None:
    back_scene.modes.shading, back_scene.modes.projection = shading, projection
    light_sun(back_scene)
    assert (offscreen(back_scene, SIZE)[CENTRE] == RED).all()


def test_back_face_culled(offscreen, back_scene: Scene) -> None:
    back_scene.modes.culling = True
    pixels = offscreen(back_scene, SIZE)
    assert (pixels == BACKGROUND).all()


def test_back_face_edges_red_or_culled_in_lines_mode(offscreen, back_scene: Scene) -> None:
    back_scene.modes.fill = Fill.LINES
    pixels = offscreen(back_scene, SIZE)
    non_background = pixels[(pixels != BACKGROUND).any(axis=2)]
    assert len(non_background) > 0 and (non_background == RED).all()
    back_scene.modes.culling = True
    assert (offscreen(back_scene, SIZE) == BACKGROUND).all()


def test_parallel_projection_tests_back_faces_with_one_view_vector(offscreen, make_quad,
                                                                   make_scene) -> None:
    """A square turned 100 deg about y, left of the axis: the eye sees its front (N.(eye - P) > 0)
    but the camera's backward axis does not (N.z < 0), so it is red only in parallel projection."""
    model = translation(-40.0, 0.0, 0.0) @ rotation_y(100.0)
    quad = SceneObject(name="edge-on", mesh=make_quad(30.0), material=MATERIAL, history=[model])
    scene = make_scene([quad])
    scene.modes.parallel_half_height = 60.0
    perspective = offscreen(scene, (127, 127))
    scene.modes.projection = Projection.PARALLEL
    parallel = offscreen(scene, (127, 127))
    drawn = (perspective != BACKGROUND).any(axis=2)
    assert drawn.sum() > 20 and not (perspective[drawn] == RED).all(axis=1).any()
    assert (parallel == RED).all(axis=2).sum() > 20


@pytest.mark.parametrize("projection", list(Projection), ids=lambda p: p.value)
def test_gouraud_finds_the_back_faces_flat_finds(offscreen, make_box, build_mesh, make_scene,
                                                 projection: Projection) -> None:
    """Flat tests N.V at the polygon's own row; Gouraud draws from shared rows and asks the
    rasteriser's winding (surface.glsl). An open box turned at seeded random poses shows inside
    and outside faces, quads and triangles: the red pixels must be the same ones."""
    cube = make_box(30.0)
    polygons = [cube.corner_vertex[a:b].tolist() for a, b in zip(cube.face_start[:-1], cube.face_start[1:])]
    lid, top = polygons[0], polygons[4]  # +z, toward the camera; +y, split into two triangles
    faces = [face for face in polygons if face not in (lid, top)] + [top[:3], [top[0], *top[2:]]]
    box = SceneObject(name="open box", mesh=build_mesh("open box", cube.positions, faces), material=MATERIAL,
                      history=[np.eye(4)])
    scene = make_scene([box])
    scene.modes.projection, scene.modes.parallel_half_height = projection, 60.0
    rng = np.random.default_rng(11)
    reds = 0
    for _ in range(12):
        angles = rng.uniform(0.0, 360.0, 3)
        box.history = [rotation_y(angles[0]) @ rotation_z(angles[1]) @ rotation_y(angles[2])]
        scene.modes.shading = Shading.FLAT
        flat = (offscreen(scene, (95, 95)) == RED).all(axis=2)
        scene.modes.shading = Shading.GOURAUD
        gouraud = (offscreen(scene, (95, 95)) == RED).all(axis=2)
        assert np.array_equal(flat, gouraud), angles
        reds += int(flat.sum())
    assert reds > 1000, "the poses must show inside faces"


def test_texture_is_neither_flipped_nor_mirrored(offscreen, renderer, make_quad, make_scene) -> None:
    """uv (0, 0) at the square's bottom-left; the picture's top-left quadrant must land top-left."""
    picture = np.zeros((16, 16, 3), np.uint8)
    picture[:8, :8] = (255, 0, 0)  # top-left, first rows of the array
    picture[:8, 8:] = (0, 255, 0)  # top-right
    picture[8:, :8] = (0, 0, 255)  # bottom-left
    picture[8:, 8:] = (255, 255, 255)  # bottom-right
    white = Material(ka=(1.0, 1.0, 1.0), kd=(0, 0, 0), ks=(0, 0, 0), ns=1.0)
    scene = make_scene([SceneObject.placed("picture", make_quad(QUAD_HALF), white, (0, 0, 0))],
                       texture=True)
    scene.ambient = np.array([255.0, 255.0, 255.0])
    scene.texture = picture
    pixels = offscreen(scene, SIZE)
    # The square spans the middle third: rows and columns 21..41; sample inside each quadrant.
    assert (pixels[26, 26] == (255, 0, 0)).all()
    assert (pixels[26, 36] == (0, 255, 0)).all()
    assert (pixels[36, 26] == (0, 0, 255)).all()
    assert (pixels[36, 36] == (255, 255, 255)).all()


@pytest.mark.parametrize(("positions", "turn"), [
    ([(-1, 0, 1), (1, 0, 1), (1, 0, -1), (-1, 0, -1)], (90.0, 0.0, 0.0)),  # a floor, seen from above
    ([(1, -1, 1), (1, -1, -1), (1, 1, -1), (1, 1, 1)], (0.0, -90.0, 0.0)),  # a wall facing +x, from +x
], ids=["floor", "wall"])
def test_a_model_without_uvs_shows_its_picture_upright(offscreen, renderer, make_scene, positions, turn) -> None:
    """The bounding-box texture, seen from the flat side's positive end with the start camera's up:
    a floor's v ran along +z, so from above its picture read upside down; a wall's u ran up y."""
    picture = np.zeros((16, 16, 3), np.uint8)
    picture[:8, :8], picture[:8, 8:], picture[8:, :8], picture[8:, 8:] = RED, (0, 255, 0), (0, 0, 255), (255, 255, 255)
    mesh = build_mesh("flat", np.array(positions, float) * QUAD_HALF, [[0, 1, 2, 3]])
    white = Material(ka=(1.0, 1.0, 1.0), kd=(0, 0, 0), ks=(0, 0, 0), ns=1.0)
    scene = make_scene([SceneObject.placed("flat", mesh, white, (0, 0, 0), turn)], texture=True)
    scene.ambient = np.array([255.0, 255.0, 255.0])
    scene.texture = picture
    pixels = offscreen(scene, SIZE)
    assert [pixels[row, column].tolist() for row in (26, 36) for column in (26, 36)] == [
        list(RED), [0, 255, 0], [0, 0, 255], [255, 255, 255]]


def test_texture_multiplies_the_lit_colour(offscreen, renderer, quad_scene: Scene) -> None:
    texel = (200, 100, 50)
    quad_scene.modes.texture = True
    quad_scene.texture = np.array([[texel]], np.uint8)
    pixels = offscreen(quad_scene, SIZE)
    expected = lit_colour_bytes(world((0, 0, 0)), (0, 0, 1), CAMERA, MATERIAL, [],
                                quad_scene.ambient, False, texture_rgb=texel)
    assert_close(pixels[CENTRE], expected)


def test_not_blank(offscreen, quad_scene: Scene) -> None:
    light_sun(quad_scene)
    pixels = offscreen(quad_scene, SIZE)
    drawn = (pixels != BACKGROUND).any(axis=2)
    assert 0.05 < drawn.mean() < 0.5
    assert (pixels[~drawn] == BACKGROUND).all()


# --- lighting.py on its own (no GL) ----------------------------------------------------------------
def test_formula_terms_add_up() -> None:
    sun = WorldLight("sun", DIRECTIONAL, np.array([200.0, 200, 200]), np.zeros(3),
                     np.array([0.0, 0.0, 1.0]))
    terms = shade_terms((0, 0, 0), (0, 0, 1), (0, 0, 1), MATERIAL, [sun], (200, 75, 255), True)
    # N = L = V = H: diffuse I*Kd, specular I*Ks, whatever ns is.
    np.testing.assert_allclose(terms.ambient, np.multiply(MATERIAL.ka, (200, 75, 255)))
    np.testing.assert_allclose(terms.lights[0].diffuse, 200 * np.asarray(MATERIAL.kd))
    np.testing.assert_allclose(terms.lights[0].specular, 200 * np.asarray(MATERIAL.ks))
    np.testing.assert_allclose(terms.clamped, np.minimum(terms.total, 255))


def test_formula_spot_cone_and_off_lights() -> None:
    spot = dict(kind="spot", intensity=(100, 100, 100), position=(0, 0, 10), direction=(0, 0, -1),
                aperture_deg=45.0)
    inside = shade_terms((9, 0, 0), (0, 0, 1), (0, 0, 1), MATERIAL, [spot], (0, 0, 0), True)
    outside = shade_terms((11, 0, 0), (0, 0, 1), (0, 0, 1), MATERIAL, [spot], (0, 0, 0), True)
    off = shade_terms((0, 0, 0), (0, 0, 1), (0, 0, 1), MATERIAL, [{**spot, "on": False}],
                      (0, 0, 0), True)
    assert inside.lights[0].reaches and inside.total.min() > 0
    assert not outside.lights[0].reaches and (outside.total == 0).all()
    assert off.lights == ()


def test_formula_seed_check_colour() -> None:
    """SPEC 4's Figure 1: the golden object, ambient only, is (160, 54, 0)."""
    golden = Material(ka=(0.8, 0.72, 0.0), kd=(0.8, 0.6, 0.4), ks=(0.9, 0.8, 0.5), ns=80.0)
    colour = lit_colour_bytes((0, 0, 0), (0, 0, 1), (0, 0, 150), golden, [], (200, 75, 255), False)
    assert tuple(colour) == (160, 54, 0)
