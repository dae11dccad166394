"""The lighting probe's outline (key `i`) in filled mode: solid where the picture shows the probed face,
dashed (its dots hollow) where the model hides it; in lines mode solid over everything."""

from __future__ import annotations

import numpy as np
import pytest

from marraztu.model.mesh import Mesh
from marraztu.model.probe import probe
from marraztu.model.scene import Fill, Projection, Scene, SceneObject
from marraztu.model.viewports import project, view_projection, views
from marraztu.render.layout import scaled_px
from marraztu.render.renderer import PROBE_COLOUR, PROBE_MARKER_PX
from support.scenes import PLAIN, box_mesh, mesh_from_polygons, scene_with

SIZE = (201, 201)
CYAN = np.array(PROBE_COLOUR) * 255
TURN = (25.0, 35.0, 0.0)  # the cube shows faces 0, 3 and 4; its corner 1 (+x, -y, -z) is hidden
FAR_FACE = 1  # faces 1, 2 and 5 meet at the hidden corner, and face 1 starts there
ENDS_PX = 6  # the dots at an edge's ends


def probed_scene(mesh: Mesh, face: int, projection: Projection) -> Scene:
    obj = SceneObject.placed("model", mesh, PLAIN, (0.0, 0.0, 0.0), TURN)
    obj.selected_face = face
    scene = scene_with([obj])
    scene.modes.probe, scene.modes.projection = True, projection
    return scene


def outline_mask(offscreen, scene: Scene) -> np.ndarray:
    return (offscreen(scene, SIZE) == CYAN).all(axis=2)


def window_corners(scene: Scene, face: int, size: tuple[int, int] = SIZE) -> list[np.ndarray]:
    obj = scene.objects[0]
    mesh, matrix = obj.mesh, view_projection(scene, views(scene, size)[0])
    corners = mesh.corner_vertex[mesh.face_start[face]:mesh.face_start[face + 1]]
    world = mesh.positions[corners] @ obj.model[:3, :3].T + obj.model[:3, 3]
    return [np.array(project(matrix, point, (0, 0, *size))) for point in world]


def along_edge(mask: np.ndarray, start: np.ndarray, end: np.ndarray) -> list[bool]:
    """Each half pixel along the edge, its dots' ends left out: whether the outline has a pixel there,
    a pixel either side of the line at most (a line's pixel centres lie within half a pixel of it)."""
    length = float(np.linalg.norm(end - start))
    direction = (end - start) / length
    across = np.array([0.0, 1.0]) if abs(direction[0]) > abs(direction[1]) else np.array([1.0, 0.0])
    found = []
    for distance in np.arange(ENDS_PX, length - ENDS_PX, 0.5):
        point = start + direction * distance
        near = [point + across * offset for offset in (-1.0, 0.0, 1.0)]
        found.append(any(mask[SIZE[1] - 1 - int(y), int(x)] for x, y in near))
    return found


def edges_of(scene: Scene, face: int) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """(first corner's index in the face, start, end) in window pixels, for each edge of the face."""
    corners = window_corners(scene, face)
    return [(i, corners[i], corners[(i + 1) % len(corners)]) for i in range(len(corners))]


def test_the_polygons_across_a_faces_edges_are_its_neighbours() -> None:
    cube = box_mesh(30.0)
    assert cube.edge_neighbours(0).tolist() == [2, 3, 4, 5] and cube.edge_neighbours(1).tolist() == [2, 3, 4, 5]
    strip = mesh_from_polygons("strip", [(x, y, 0.0) for x in range(4) for y in (0, 1)],
                               [[0, 2, 3, 1], [2, 4, 5, 3], [4, 6, 7, 5]])
    assert [strip.edge_neighbours(face).tolist() for face in range(3)] == [[1], [0, 2], [1]]


def gaps(found: list[bool]) -> int:
    return sum(1 for before, now in zip(found, found[1:]) if before and not now)


@pytest.mark.parametrize("projection", list(Projection), ids=lambda p: p.value)
def test_a_face_on_the_far_side_is_dashed_where_the_model_hides_it(offscreen, projection: Projection) -> None:
    """Its two edges from the hidden corner lie behind the model's front: dashed, not drawn as a front
    face's; its two others are on the model's outline, seen: solid. The dot on the hidden corner is
    hollow."""
    scene = probed_scene(box_mesh(30.0), FAR_FACE, projection)
    assert probe(scene).back_face
    mask = outline_mask(offscreen, scene)
    for first, start, end in edges_of(scene, FAR_FACE):
        found = along_edge(mask, start, end)
        if 0 in (first, (first + 1) % 4):  # from the hidden corner
            assert gaps(found) >= 3 and 0.3 < np.mean(found) < 0.8, (first, found)
        else:
            assert all(found), (first, found)
    corner = window_corners(scene, FAR_FACE)[0]
    row, column = SIZE[1] - 1 - int(corner[1]), int(corner[0])
    dot = mask[row - 3:row + 4, column - 3:column + 4]
    assert dot.sum() > 20 and dot[2:5, 2:5].sum() <= 6, dot.astype(int)  # the edges cross its hole


@pytest.mark.parametrize(("side", "border"), [(201, 2), (1601, 4)])
def test_a_hidden_corners_dot_keeps_its_border_in_proportion_as_it_grows(offscreen, side: int, border: int) -> None:
    """The hollow dot's border grows with the dot (layout.screen_scale), as the text does: 2 pixels of 7 up to
    800 pixels on the shorter side, 4 of 14 at 1600 (not a thin ring of 2)."""
    scene = probed_scene(box_mesh(30.0), FAR_FACE, Projection.PERSPECTIVE)
    dot = scaled_px(PROBE_MARKER_PX, (side, side))
    corner = window_corners(scene, FAR_FACE, (side, side))[0]
    mask = (offscreen(scene, (side, side)) == CYAN).all(axis=2)
    row, column = side - 1 - int(corner[1]), int(corner[0])
    around = mask[row - dot:row + dot + 1, column - dot:column + dot + 1]
    solid_rows = [line for line in around if longest_run(line) >= dot]  # the border's top and bottom
    assert len(solid_rows) == 2 * border, around.astype(int)


def longest_run(line: np.ndarray) -> int:
    longest = run = 0
    for filled in line:
        run = run + 1 if filled else 0
        longest = max(longest, run)
    return longest


def uv_sphere(radius: float, rings: int, segments: int) -> Mesh:
    """A closed sphere of triangles at the poles and quads between, outward normals."""
    turns = 2.0 * np.pi * np.arange(segments) / segments
    heights = np.pi * np.arange(1, rings) / rings
    positions = [(0.0, radius, 0.0)] + [
        (radius * np.sin(h) * np.cos(t), radius * np.cos(h), -radius * np.sin(h) * np.sin(t))
        for h in heights for t in turns] + [(0.0, -radius, 0.0)]

    def at(ring: int, segment: int) -> int:
        return 1 + ring * segments + segment % segments

    polygons = [[0, at(0, s), at(0, s + 1)] for s in range(segments)]
    polygons += [[at(r, s), at(r + 1, s), at(r + 1, s + 1), at(r, s + 1)]
                 for r in range(rings - 2) for s in range(segments)]
    polygons += [[at(rings - 2, s), len(positions) - 1, at(rings - 2, s + 1)] for s in range(segments)]
    return mesh_from_polygons("sphere", positions, polygons)


@pytest.mark.parametrize("projection", list(Projection), ids=lambda p: p.value)
@pytest.mark.parametrize("mesh", [box_mesh(30.0), uv_sphere(45.0, 6, 8)], ids=["cube", "sphere"])
def test_a_front_face_of_a_convex_model_is_outlined_solid_all_round(offscreen, mesh: Mesh,
                                                                    projection: Projection) -> None:
    """Nothing hides a front face of a convex model: filled mode draws every outline pixel (and dot)
    that lines mode draws over everything, though the outline lies on the face and its neighbours,
    at their depth, at every slope the faces show (the sphere's from face on to edge on)."""
    front = 0
    for face in range(mesh.face_count):
        scene = probed_scene(mesh, face, projection)
        if probe(scene).back_face:
            continue
        front += 1
        filled = outline_mask(offscreen, scene)
        scene.modes.fill = Fill.LINES
        lines = outline_mask(offscreen, scene)
        assert lines.sum() > 20 and not (lines & ~filled).any(), face
    assert front >= 3
