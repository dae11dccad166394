"""SPEC 4's lighting worked by hand, apart from app/model/lighting.py: the probe's numbers and the
pixels of Flat, Gouraud and Phong, the term views, a light behind the face, a spotlight's edge,
parallel projection, a non-uniform scale and the camera's torch, all on one square facing the camera.

The square spans +-40 at z = 0 and the camera sits at (0, 0, 30) looking down -z: with the 90 deg
field of view it fills the 200x200 picture, every corner lies at the same depth, so Gouraud's
interpolation is linear in the window, and a pixel's point on the square is found by casting its ray.
"""

from __future__ import annotations

import numpy as np
import pytest

import marraztu
from marraztu.model.scene import Material

SIZE = 200
EYE = np.array([0.0, 0.0, 30.0])
CORNERS = np.array([[-40.0, -40.0, 0.0], [40.0, -40.0, 0.0], [40.0, 40.0, 0.0], [-40.0, 40.0, 0.0]])
FACE_NORMAL = np.array([0.0, 0.0, 1.0])
KA, KD, KS, NS = np.array([0.2, 0.3, 0.1]), np.array([0.6, 0.5, 0.4]), np.array([0.5, 0.4, 0.3]), 10.0
MATERIAL = Material(tuple(KA), tuple(KD), tuple(KS), NS)
# SPEC 4's numbers.
IA = np.array([200.0, 75.0, 255.0])
SUN, SUN_DIRECTION = np.array([200.0, 200.0, 200.0]), np.array([0.1, 0.2, 0.7])
BULB, BULB_POSITION = np.array([250.0, 50.0, 150.0]), np.array([0.0, 200.0, 0.0])
OBJECT_SPOT, OBJECT_APERTURE = np.array([75.0, 75.0, 75.0]), 25.75
CAMERA_SPOT, CAMERA_APERTURE = np.array([155.0, 120.0, 75.0]), 30.0


def unit(vector) -> np.ndarray:
    vector = np.asarray(vector, float)
    return vector / np.linalg.norm(vector)


def light_share(intensity, to_light, normal, to_eye, kd=KD, ks=KS, ns=NS) -> np.ndarray:
    """I_l (Kd max(N.L, 0) + Ks max(N.H, 0)^ns): SPEC 4 gates the highlight by N.H alone, not N.L."""
    halfway = unit(to_light + to_eye)
    return intensity * (kd * max(normal @ to_light, 0.0) + ks * max(normal @ halfway, 0.0) ** ns)


def in_cone(position, axis, aperture_deg, point) -> bool:
    cosine = unit(axis) @ unit(point - position)
    return bool(np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0))) < aperture_deg)


def on_square(column: int, row: int, camera: np.ndarray, width: int = SIZE) -> np.ndarray:
    """Where the ray through the pixel's centre (row 0 at the top) meets the plane z = 0."""
    x, y = (column + 0.5) / width * 2 - 1, 1 - (row + 0.5) / SIZE * 2
    direction = camera[:3, :3] @ np.array([x * width / SIZE, y, -1.0])  # tan(45 deg) = 1
    return camera[:3, 3] - camera[2, 3] / direction[2] * direction


def fan_weights(point: np.ndarray) -> dict[int, float]:
    """The point's barycentric weights in the fan triangle (0, 1, 2) or (0, 2, 3) that holds it."""
    s, t = (point[0] + 40) / 80, (point[1] + 40) / 80
    return {0: 1 - s, 1: s - t, 2: t} if s >= t else {0: 1 - t, 2: s, 3: t - s}


def viewer(width: int = SIZE, normals=None, model=None, corners=CORNERS) -> marraztu.Viewer:
    """The square on its own, the camera at EYE, texture off (the framing of add_mesh is undone)."""
    view = marraztu.Viewer(size=(width, SIZE), empty=True)
    view.add_mesh(corners, np.array([[0, 1, 2, 3]]), normals=normals, name="square")
    square = view.scene.objects[-1]
    square.material = MATERIAL
    if model is not None:
        square.history[-1] = model
    camera = np.eye(4)
    camera[:3, 3] = EYE
    view.scene.cameras[0].history[-1] = camera
    view.press("T")
    return view


def camera_of(view: marraztu.Viewer) -> np.ndarray:
    return view.scene.cameras[0].history[-1]


def pixel(picture, column: int, row: int) -> np.ndarray:
    return np.asarray(picture).astype(int)[row, column]


def assert_pixel(picture, column: int, row: int, expected) -> None:
    assert np.abs(pixel(picture, column, row) - np.minimum(expected, 255)).max() <= 1, (column, row)


def test_flat_sun_is_the_formula_at_the_first_corner_over_the_whole_face() -> None:
    with viewer() as view:
        view.press("0")
        first = view.probe().vertices[0]
        to_eye = unit(EYE - CORNERS[0])
        expected = KA * IA + light_share(SUN, unit(SUN_DIRECTION), FACE_NORMAL, to_eye)
        assert first.lights[0].n_dot_l == pytest.approx(0.7 / np.sqrt(0.54))
        assert first.lights[0].highlight == pytest.approx(0.07365, abs=1e-5)  # (N.H)^10, H toward (-40, -40)
        assert first.total == pytest.approx(tuple(expected))
        assert first.colour == (162, 124, 106)
        picture = view.render()
        for column, row in [(100, 100), (10, 190), (190, 10)]:  # both fan triangles
            assert_pixel(picture, column, row, expected)


def test_gouraud_interpolates_the_corners_colours() -> None:
    with viewer() as view:
        view.press("0 F")
        corners = [np.minimum(KA * IA + light_share(SUN, unit(SUN_DIRECTION), FACE_NORMAL,
                                                    unit(EYE - corner)), 255) for corner in CORNERS]
        assert [v.colour for v in view.probe().vertices] == [(162, 124, 106), (167, 128, 109),
                                                             (198, 153, 128), (177, 136, 115)]
        picture = view.render()
        for column, row in [(100, 100), (30, 170), (170, 30), (60, 140)]:
            weights = fan_weights(on_square(column, row, camera_of(view)))
            assert_pixel(picture, column, row, sum(w * corners[k] for k, w in weights.items()))


def test_side_by_side_specular_flat_gouraud_and_phong() -> None:
    """Corner normals tilted outward: Flat keeps the face normal, Gouraud blends the corners'
    highlights, Phong blends the normals and lights every pixel."""
    normals = np.array([unit([-0.3, -0.3, 1]), unit([0.3, -0.3, 1]), unit([0.3, 0.3, 1]), unit([-0.3, 0.3, 1])])
    with viewer(3 * SIZE, normals=normals) as view:
        view.press("0 s v v v")
        assert view.probe().view == "specular only"
        picture = view.render()

        def specular(point, normal):
            return light_share(SUN, unit(SUN_DIRECTION), normal, unit(EYE - point), kd=0.0)

        for column, row in [(100, 100), (40, 160), (160, 40), (150, 150)]:
            point = on_square(column, row, camera_of(view))
            weights = fan_weights(point).items()
            assert_pixel(picture, column, row, specular(CORNERS[0], FACE_NORMAL))
            assert_pixel(picture, SIZE + column, row, sum(w * specular(CORNERS[k], normals[k]) for k, w in weights))
            blended = unit(sum(w * normals[k] for k, w in weights))
            assert_pixel(picture, 2 * SIZE + column, row, specular(point, blended))
        assert_pixel(picture, 2 * SIZE + 100, 100, [88, 71, 53])  # a highlight Gouraud misses: 1 1 1 there
        assert_pixel(picture, SIZE + 100, 100, [1, 1, 1])


def test_a_light_behind_the_face_adds_no_diffuse_but_its_highlight_per_spec_4() -> None:
    """The bulb at (0, 200, 0) is behind the square moved to z = 10 (N.L = -0.041 at its first corner);
    SPEC 4's highlight is gated by max(N.H, 0) only, so with ns = 1 it shows."""
    corners = CORNERS + [0, 0, 10]
    with viewer(corners=corners) as view:
        view.scene.objects[-1].material = Material((0, 0, 0), tuple(KD), (1, 1, 1), 1.0)
        view.press("1")
        to_light, to_eye = unit(BULB_POSITION - corners[0]), unit(EYE - corners[0])
        assert FACE_NORMAL @ to_light < 0
        share = view.probe().vertices[0].lights[0]
        assert share.n_dot_l == 0 and share.diffuse == (0, 0, 0)
        assert share.highlight == pytest.approx(FACE_NORMAL @ unit(to_light + to_eye))  # 0.1561
        assert_pixel(view.render(), 100, 100, BULB * share.highlight)  # (39, 8, 23)


def test_the_object_spotlight_stops_at_its_aperture() -> None:
    """The square's origin 20 in front of it: the object's torch at (0, 0, 20) looks down -z and
    lights a disc of radius 20 tan(25.75 deg) = 9.65 on it; its light alone in the Phong third."""
    position = np.array([0.0, 0.0, 20.0])
    model = np.eye(4)
    model[:3, 3] = position
    with viewer(3 * SIZE, corners=CORNERS - position, model=model) as view:
        view.press("2 F")
        assert [share.reaches for v in view.probe().vertices for share in v.lights] == [False] * 4  # 70.5 deg out
        view.press("s v v v v v v")
        assert view.probe().view == "object spotlight alone"
        picture = view.render()
        for column in [100, 128, 131, 132, 135]:  # x = 9.45 lies at 25.29 deg, x = 9.75 at 25.99 deg
            point = on_square(column, 100, camera_of(view))
            lit = in_cone(position, [0, 0, -1], OBJECT_APERTURE, point)
            assert lit == (column <= 131)
            expected = light_share(OBJECT_SPOT, unit(position - point), FACE_NORMAL, unit(EYE - point)) * lit
            assert_pixel(picture, 2 * SIZE + column, 100, expected)


def test_parallel_projection_has_one_view_vector() -> None:
    """V is the camera's backward axis (0, 0, 1) at every point: one colour over the face."""
    with viewer() as view:
        view.press("0 F p")
        expected = KA * IA + light_share(SUN, unit(SUN_DIRECTION), FACE_NORMAL, FACE_NORMAL)
        for vertex in view.probe().vertices:
            assert vertex.n_dot_v == pytest.approx(1.0)
            assert vertex.total == pytest.approx(tuple(expected))  # (243.0, 188.7, 154.9)
        picture = view.render()
        for column, row in [(100, 100), (5, 5), (195, 195)]:
            assert_pixel(picture, column, row, expected)


def test_a_non_uniform_scale_turns_normals_by_the_inverse_transpose() -> None:
    """Corners on the model's plane x + z = 0 with normals (1, 0, 1)/sqrt 2, scaled by 3 along x
    then turned 0.4 rad about z: the world normal is inv(M)^T n, (0.291, 0.123, 0.949), not M n."""
    corners = np.array([[-10.0, -40.0, 10.0], [10.0, -40.0, -10.0], [10.0, 40.0, -10.0], [-10.0, 40.0, 10.0]])
    c, s = np.cos(0.4), np.sin(0.4)
    model = np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]) @ np.diag([3.0, 1, 1, 1])
    normals = np.tile(unit([1, 0, 1]), (4, 1))
    world_normal = unit(np.linalg.inv(model[:3, :3]).T @ normals[0])
    for given in (None, normals):  # the face's normal from its corners, and the normals given
        with viewer(3 * SIZE, normals=given, model=model, corners=corners) as view:
            view.press("0 F")
            for k, vertex in enumerate(view.probe().vertices):
                point = (model @ np.append(corners[k], 1))[:3]
                assert vertex.normal == pytest.approx(tuple(world_normal))
                expected = KA * IA + light_share(SUN, unit(SUN_DIRECTION), world_normal, unit(EYE - point))
                assert vertex.total == pytest.approx(tuple(expected))
            view.press("s")
            ray_point = on_square(100, 100, camera_of(view))  # the view axis: the square passes through the origin
            expected = KA * IA + light_share(SUN, unit(SUN_DIRECTION), world_normal, unit(EYE - ray_point))
            assert_pixel(view.render(), 2 * SIZE + 100, 100, expected)
            view.press("s v v v v v v v v v")
            assert_pixel(view.render(), 3 * SIZE // 2, 100, world_normal * 127.5 + 127.5)  # one view: its centre


def test_the_camera_spotlight_turns_with_the_camera() -> None:
    """Turned 0.3 rad about its own y, the camera's torch looks along (-0.296, 0, -0.955): the
    square's corners fall outside its 30 deg, and in the Phong third its disc follows the axis."""
    with viewer(3 * SIZE) as view:
        view.press("3 F c r y y y")
        camera = camera_of(view)
        axis = -camera[:3, 2]
        assert axis == pytest.approx([-np.sin(0.3), 0, -np.cos(0.3)])
        assert [share.reaches for v in view.probe().vertices for share in v.lights] == [False] * 4
        view.press("s v v v v v v v")
        assert view.probe().view == "camera spotlight alone"
        picture = view.render()
        lit = []
        for column in range(36, 200, 12):
            point = on_square(column, 100, camera)
            inside = in_cone(EYE, axis, CAMERA_APERTURE, point)
            lit.append(inside)
            expected = light_share(CAMERA_SPOT, unit(EYE - point), FACE_NORMAL, unit(EYE - point)) * inside
            assert_pixel(picture, 2 * SIZE + column, 100, expected)
        assert lit == [False] + [True] * 10 + [False] * 3  # the disc lies left of the view axis
