"""The pipeline view (`P`): its numbers equal an independent numpy computation (glFrustum written
out here, the camera's inverse, the divide and the viewport by hand); a corner nearer than the near
plane is said to be clipped; a back face is said to be culled with `b` on; the panel is drawn."""

from __future__ import annotations

import re

import numpy as np
import pytest

import marraztu
from marraztu.model import pipeline
from marraztu.model.pipeline import face_pipeline
from marraztu.model.scene import SceneObject
from marraztu.text.panels import matrix_lines
from marraztu.text.pipeline import pipeline_lines
from support.scenes import PLAIN

SIZE = (800, 800)
NUMBER = r"-?\d+\.\d+"


def gl_frustum(fovy_deg: float, aspect: float, near: float, far: float) -> np.ndarray:
    """The perspective matrix of the OpenGL red book, from its definition, not from the program."""
    f = 1.0 / np.tan(np.radians(fovy_deg) / 2.0)
    return np.array([[f / aspect, 0, 0, 0], [0, f, 0, 0],
                     [0, 0, (far + near) / (near - far), 2 * far * near / (near - far)], [0, 0, -1, 0]])


def numbers_after(word: str, line: str) -> list[float]:
    found = re.search(rf"{word} \(([^)]*)\)", line)
    assert found, (word, line)
    return [float(value) for value in found.group(1).split()]


def test_every_stage_equals_numpy() -> None:
    with marraztu.Viewer(size=SIZE) as v:
        v.press("x*3 ENTER*40 P")
        scene = v.scene
        viewport = (0, 0, *SIZE)
        found = face_pipeline(scene, viewport)
        lines = pipeline_lines(scene, viewport)
    obj, mesh = found.obj, found.obj.mesh
    projection = gl_frustum(90.0, 1.0, scene.near_plane(), scene.far_plane())
    assert np.allclose(found.projection_matrix, projection)
    view = np.linalg.inv(scene.camera.model)
    first = int(mesh.face_start[found.face])
    for k, corner in enumerate(found.corners):
        p = np.append(mesh.positions[mesh.corner_vertex[first + k]], 1.0)
        clip = projection @ view @ obj.model @ p
        ndc = clip[:3] / clip[3]
        window = [(ndc[0] + 1) * SIZE[0] / 2, (ndc[1] + 1) * SIZE[1] / 2, (ndc[2] + 1) / 2]
        assert np.allclose(corner.clip, clip) and np.allclose(corner.ndc, ndc) and np.allclose(corner.window, window)
        # What the panel prints is what numpy gives, to its decimals.
        row = next(i for i, line in enumerate(lines) if line.startswith(f"v{k + 1} "))
        assert np.allclose(numbers_after("world", lines[row]), (obj.model @ p)[:3], atol=0.051)
        assert np.allclose(numbers_after("eye", lines[row]), (view @ obj.model @ p)[:3], atol=0.051)
        assert np.allclose(numbers_after("clip", lines[row + 1]), clip[:3], atol=0.051)
        assert float(re.search(rf"w ({NUMBER})", lines[row + 1]).group(1)) == pytest.approx(clip[3], abs=0.006)
        assert np.allclose(numbers_after("ndc", lines[row + 1]), ndc, atol=0.0006)
        window_printed = re.search(rf"window x ({NUMBER}) y ({NUMBER}) depth ({NUMBER})", lines[row + 1])
        assert np.allclose([float(g) for g in window_printed.groups()], window, atol=[0.051, 0.051, 0.00006])
    # GL's window y grows upward, a picture's rows downward: the panel says which it prints.
    assert any("y up from the bottom" in line for line in lines[:2])


def test_a_corner_nearer_than_the_near_plane_is_clipped_and_says_why() -> None:
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        # The square moved 10 units toward the camera (0.5 a press: it is 14 units across) and tilted:
        # one edge between the near plane and the eye.
        v.add_mesh([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], [[0, 1, 2, 3]]).press("t z*20 r x*5 P")
        found = face_pipeline(v.scene, (0, 0, *SIZE))
        lines = "\n".join(pipeline_lines(v.scene, (0, 0, *SIZE)))
        near = v.scene.near_plane()
    clipped = [corner for corner in found.corners if -near < corner.eye[2] < 0.0]
    kept = [corner for corner in found.corners if corner.eye[2] < -near]
    assert len(clipped) == 2 and len(kept) == 2, [corner.eye for corner in found.corners]
    for corner in clipped:
        assert "near" in corner.outside and corner.clip[2] < -corner.clip[3] and corner.clip[3] > 0
    assert all("near" not in corner.outside for corner in kept)
    assert "near plane: eye z" in lines and "so clip z < -w" in lines


@pytest.mark.parametrize("half", [0.004, 4e-7])
def test_a_small_models_positions_keep_their_digits(half: float) -> None:
    """A square a centimetre or a micron across, framed: its positions read as numbers, not zeros."""
    corners = [[-half, -half, 0], [half, -half, 0], [half, half, 0], [-half, half, 0]]
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(corners, [[0, 1, 2, 3]]).press("P")
        lines = pipeline_lines(v.scene, (0, 0, *SIZE))
        eye = face_pipeline(v.scene, (0, 0, *SIZE)).corners[0].eye
    first = next(line for line in lines if line.startswith("v1 "))
    assert np.allclose(numbers_after("model", first), corners[0], rtol=0, atol=half / 100)
    assert np.allclose(numbers_after("eye", first), eye, rtol=0, atol=half / 100)


@pytest.mark.parametrize("half,keys", [(0.001, "P"), (5e4, "p P"), (10.0, "p P")])
def test_the_printed_matrices_give_the_numbers_printed_under_them(half: float, keys: str) -> None:
    """Fixed decimals printed a model in millimetres' view as 0.00 and a parallel projection of
    kilometres as zeros; in parallel projection clip is ndc (w = 1), and was printed with one decimal."""
    cube = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float) * half
    quads = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(cube, quads).press(keys)
        found = face_pipeline(v.scene, (0, 0, *SIZE))
        lines = pipeline_lines(v.scene, (0, 0, *SIZE))
    printed = np.array([[float(word) for word in line.split()] for line in lines[3:7]])
    true = np.hstack([found.model_matrix, found.view_matrix, found.projection_matrix])
    assert np.array_equal(printed != 0.0, true != 0.0)  # nothing but zeros reads as zero
    assert np.allclose(printed, true, rtol=0.06, atol=0.006)
    first = next(line for line in lines if line.startswith("       clip"))
    if "p" in keys.split():
        assert numbers_after("clip", first) == numbers_after("ndc", first)


def test_behind_the_eye_there_is_no_divide() -> None:
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh([[-5, -5, 0], [5, -5, 0], [0, 5, 0]], [[0, 1, 2]]).press("t z*30 P")  # past the eye
        found = face_pipeline(v.scene, (0, 0, *SIZE))
        assert all(corner.behind_eye and corner.ndc is None for corner in found.corners)
        assert "w <= 0: behind the eye, no divide" in "\n".join(pipeline_lines(v.scene, (0, 0, *SIZE)))


def test_the_culling_verdict_follows_b() -> None:
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh([[-5, -5, 0], [0, 5, 0], [5, -5, 0]], [[0, 1, 2]]).press("P")  # clockwise: a back face
        assert "a back face, drawn red (b culls it)" in pipeline_lines(v.scene, (0, 0, *SIZE))[-1]
        assert "a back face, culled (b)" in pipeline_lines(v.press("b").scene, (0, 0, *SIZE))[-1]
        assert face_pipeline(v.scene, (0, 0, *SIZE)).culled


def test_the_panel_is_drawn_and_replaces_the_probes() -> None:
    with marraztu.Viewer(size=SIZE) as v:
        plain = np.asarray(v.press("i").render(overlay=True)).astype(int)
        with_pipeline = np.asarray(v.press("P").render(overlay=True)).astype(int)
        assert "waits behind this panel" in pipeline_lines(v.scene, (0, 0, *SIZE))[0]
    bottom = slice(SIZE[1] // 2, SIZE[1])
    changed = (np.abs(with_pipeline[bottom] - plain[bottom]).max(axis=2) > 0).mean()
    assert changed > 0.05, "the bottom panel shows other text"
    assert len(np.unique(with_pipeline[bottom].reshape(-1, 3), axis=0)) > 20, "not blank"


def panels_of_a_model_1e12_away(keys: str) -> tuple[list[str], list[str]]:
    """The pipeline and matrices panels' lines, a triangle and its camera moved 1e12 along x, y and z."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh([[-1, -1, 0], [1, -1, 0], [0, 1, 0]], [[0, 1, 2]]).press(keys)
        for element in (v.scene.objects[0], v.scene.camera):
            element.push(element.model + np.pad(np.full((3, 1), 1e12), ((0, 1), (3, 0))))
        return pipeline_lines(v.scene, (0, 0, *SIZE)), matrix_lines(v.scene, SIZE)


def test_a_model_far_from_the_origin_keeps_the_matrices_bottom_row() -> None:
    """A translation of 1e12 made the 1 under it a billionth of its column, read as rounding: the
    model and view matrices' bottom rows were printed 0 0 0 0."""
    lines, panel = panels_of_a_model_1e12_away("t x m P")
    printed = [[float(word) for word in line.split()] for line in lines[3:7]]
    assert printed[3][:8] == [0.0, 0.0, 0.0, 1.0] * 2 and printed[0][3] > 1e12
    rows = [[float(word) for word in line.split()] for line in panel if re.fullmatch(r"[\s\d.e+-]+", line)]
    assert rows[3] == rows[7] == [0.0, 0.0, 0.0, 1.0], panel


def test_a_wide_entry_widens_its_own_column() -> None:
    """A translation of 1e12 pushed the rest of its row along: the rows below no longer stood under
    it, and the V and P titles stood over other matrices' columns."""
    lines, panel = panels_of_a_model_1e12_away("m P")
    rows = lines[3:7]
    ends = {tuple(match.end() for match in re.finditer(NUMBER, row)) for row in rows}
    assert len(ends) == 1, rows  # every entry ends where the one above it does
    v_at, p_at = lines[2].index("V: view"), lines[2].index("P: aspect")
    for row in rows:  # each title over its own matrix's four entries
        assert [len(re.findall(NUMBER, part)) for part in (row[:v_at], row[v_at:p_at], row[p_at:])] == [4, 4, 4], row
    model_rows = panel[panel.index("model of object mesh") + 1:][:4]
    assert len({len(row) for row in model_rows}) == 1, model_rows  # right-aligned columns: rows as long


def p_built_from(line: str) -> tuple[float, ...]:
    """Aspect, near and far as a panel prints them under or beside P's title."""
    found = re.fullmatch(r"(?:P: )?aspect (\S+), near plane (\S+), far plane (\S+)", line.strip())
    assert found, line
    return tuple(float(value) for value in found.groups())


def printed_p(panel: list[str], title: str) -> np.ndarray:
    at = panel.index(title)
    return np.array([[float(word) for word in row.split()] for row in panel[at + 2:at + 6]])


@pytest.mark.parametrize("keys", ["m", "m p"])
def test_the_matrices_panel_says_what_p_is_built_from(keys: str) -> None:
    """P changed when only the camera moved, and the panel said nothing of why: its near and far
    planes follow what is shown. The line under P's title gives them, the renderer's own, and P is
    built from them (glFrustum or glOrtho written out here)."""
    size = (800, 600)
    with marraztu.Viewer(size=size) as v:
        panels = []
        for move in ("", "c t Z*14"):
            scene = v.press(move or keys).scene
            panels.append(matrix_lines(scene, size))
            perspective = "p" not in keys.split()
            title = "projection: perspective 90 deg high" if perspective else \
                f"projection: parallel, half height {scene.modes.parallel_half_height:.3g}"
            aspect, near, far = p_built_from(panels[-1][panels[-1].index(title) + 1])
            assert aspect == pytest.approx(size[0] / size[1], abs=0.005)
            renderers_near = scene.near_plane(size[0] / size[1])  # what projection_matrix, the renderer's, uses
            assert (near, far) == pytest.approx((renderers_near, scene.far_plane(renderers_near)), rel=0.005)
            half = scene.modes.parallel_half_height
            built = gl_frustum(90.0, aspect, near, far) if perspective else np.array(
                [[1 / (half * aspect), 0, 0, 0], [0, 1 / half, 0, 0],
                 [0, 0, -2 / (far - near), -(far + near) / (far - near)], [0, 0, 0, 1]])
            assert np.allclose(printed_p(panels[-1], title), built, rtol=0.01, atol=0.002)
    before, after = (panel[panel.index(title) + 1:][:5] for panel in panels)
    if perspective:
        assert before[1:] != after[1:], "the camera's move changes P here"
    assert before[0] != after[0], "and the numbers P is built from change with it"


def test_both_panels_say_what_p_is_built_from_in_the_same_words() -> None:
    with marraztu.Viewer(size=SIZE) as v:
        v.press("c t Z*14 c c r TAB TAB m P")
        pipeline, panel = pipeline_lines(v.scene, (0, 0, *SIZE)), matrix_lines(v.scene, SIZE)
    built_from = panel[panel.index("projection: perspective 90 deg high") + 1]
    assert pipeline[2][pipeline[2].index("P: "):] == f"P: {built_from}"
    assert ", perspective 90 deg high" in pipeline[0]


def test_a_polygon_of_thousands_of_corners_is_carried_as_far_as_the_panel_shows(build_mesh, make_scene,
                                                                                monkeypatch) -> None:
    """Every corner of a million-corner polygon was carried through every space in Python, seconds and
    a gigabyte a picture, for a panel that shows four."""
    corners = 5000
    turn = np.linspace(0.0, 2.0 * np.pi, corners, endpoint=False)
    disc = build_mesh("disc", np.c_[np.cos(turn), np.sin(turn), np.zeros(corners)] * 50.0, [list(range(corners))])
    scene = make_scene([SceneObject.placed("disc", disc, PLAIN, (0.0, 0.0, 0.0))])
    scene.modes.pipeline = True
    viewport = (0, 0, *SIZE)
    whole = face_pipeline(scene, viewport)
    carried = []
    stages = pipeline._stages
    monkeypatch.setattr(pipeline, "_stages", lambda vertex, *rest: carried.append(vertex) or stages(vertex, *rest))
    lines = pipeline_lines(scene, viewport)
    assert carried == [0, 1, 2, 3]
    assert whole.corner_count == corners == len(whole.corners)
    assert lines[-2] == f"(and {corners - 4} more corners of this polygon, carried the same way)"
    shown = face_pipeline(scene, viewport, 4)
    assert shown.corner_count == corners and [corner.vertex for corner in shown.corners] == [0, 1, 2, 3]
    np.testing.assert_array_equal(shown.corners[3].clip, whole.corners[3].clip)
