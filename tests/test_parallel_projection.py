"""`p` keeps the scene about where perspective showed it (SPEC 5), wherever the selected object is:
behind the camera, at the near plane, or far away, the other objects stay within half and twice
their perspective size, and the picture is never one object's colour from edge to edge."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from marraztu.control.keymap import dispatch, parse_key_sequence
from marraztu.control.viewer import StartOptions
from marraztu.frontends.screenshot import take_screenshot
from marraztu.loaders.scenefile import load_builtin_scene
from marraztu.model.scene import Projection, Scene, SceneObject
from marraztu.model.viewports import View, project, view_projection
from support.scenes import BACKGROUND, RecordingHost

VIEW = View((0, 0, 400, 400), shading=None)  # type: ignore[arg-type]  # only the viewport matters here


def press(scene: Scene, keys: str) -> None:
    host = RecordingHost()
    for key in parse_key_sequence(keys):
        dispatch(scene, key, host)


def screen_height(scene: Scene, obj: SceneObject) -> float:
    """How tall the object's bounding box looks, in pixels."""
    low, high = obj.mesh.bounds
    corners = np.array([[x, y, z] for x in (low[0], high[0]) for y in (low[1], high[1]) for z in (low[2], high[2])])
    matrix = view_projection(scene, VIEW)
    points = [project(matrix, (obj.model @ np.append(corner, 1.0))[:3], VIEW.viewport) for corner in corners]
    ys = [point[1] for point in points if point is not None]
    return max(ys) - min(ys)


# The golden ship (selected after TAB TAB) moved along world z: behind the camera, at the near plane, far.
@pytest.mark.parametrize("moves", ["g t z*40", "g t z*29", "g t Z*400", "g t Z*2000", ""],
                         ids=["behind the camera", "at the near plane", "far behind the others",
                              "very far", "where it starts"])
def test_the_others_keep_about_their_size(moves: str) -> None:
    scene = load_builtin_scene()
    press(scene, f"TAB TAB {moves}")
    selected = scene.object
    others = [obj for obj in scene.objects if obj is not selected]
    before = [screen_height(scene, obj) for obj in others]
    press(scene, "p")
    assert scene.modes.projection is Projection.PARALLEL
    after = [screen_height(scene, obj) for obj in others]
    for height_before, height_after in zip(before, after):
        assert 0.5 <= height_after / height_before <= 2.0, (moves, before, after)


def test_where_it_starts_the_selected_object_keeps_its_size_exactly() -> None:
    scene = load_builtin_scene()
    press(scene, "TAB TAB")
    before = screen_height(scene, scene.object)
    press(scene, "p")
    assert screen_height(scene, scene.object) == pytest.approx(before, rel=0.1)  # a box's depth


def test_an_object_moved_behind_the_camera_does_not_fill_the_picture(tmp_path) -> None:
    out = take_screenshot(StartOptions(), tmp_path / "behind.png", (120, 120), keys="T TAB TAB g t z*40 p")
    pixels = np.asarray(Image.open(out)).astype(int)
    background = (np.abs(pixels - BACKGROUND).sum(axis=2) == 0).mean()
    assert background > 0.5, f"only {background:.0%} of the picture is background"


@pytest.mark.parametrize("projection", ["", "p"], ids=["perspective", "parallel"])
def test_what_is_behind_the_near_plane_is_cut_in_either_projection(tmp_path, projection: str) -> None:
    """SPEC 5's near plane (n = 5) is glOrtho's as gluPerspective's: a camera flown past every ship
    sees none of them (parallel's depth range once reached as far behind the eye as in front)."""
    out = take_screenshot(StartOptions(), tmp_path / "past.png", (120, 90), keys=f"{projection} c t Z*40")
    assert (np.asarray(Image.open(out)).astype(int) == BACKGROUND).all()
    scene = load_builtin_scene()
    press(scene, projection)
    clip = scene.projection_matrix(4 / 3) @ np.array([0.0, 0.0, -scene.near_plane(), 1.0])
    assert clip[2] / clip[3] == pytest.approx(-1.0)  # the near plane is where depth starts


def spelled_out_half_height(scene: Scene) -> float:
    """matching_parallel_half_height written object by object, as its docstring says it."""
    near, selected = scene.near_plane(), scene.object
    placed = [obj for obj in scene.objects if obj is not scene.viewer]
    others = [scene.depth_of(obj.centre) for obj in placed if obj is not selected]
    scene_depth = float(np.median([depth for depth in others if depth > near]))
    own = scene.depth_of(selected.centre) if selected in placed else None
    depth = float(np.clip(own, scene_depth / 1.5, scene_depth * 1.5)) if own is not None and own > near \
        else scene_depth
    return max(depth, near)  # tan(45 degrees) = 1


@pytest.mark.parametrize("keys", ["TAB", "TAB g t Z*30", "TAB C"], ids=["starting", "moved far", "looked through"])
def test_p_takes_the_objects_depths_at_once_not_object_by_object(monkeypatch, keys: str) -> None:
    """Each object's centre went through its own matrix product in Python, 12 µs an object: `p` took
    100 ms on a scene file of 8,000 objects, each press, twice what the same press's frame did."""
    scene = load_builtin_scene()
    for step in range(1, 40):  # the ships again, further off each time
        for obj in scene.objects[:3]:
            model = obj.model.copy()
            model[2, 3] -= 40.0 * step
            scene.objects.append(SceneObject(f"{obj.name}{step}", obj.mesh, obj.material, [model]))
    press(scene, keys)
    expected = spelled_out_half_height(scene)
    centres = {"taken": 0}
    centre = SceneObject.centre

    def counted_centre(obj: SceneObject) -> np.ndarray:
        centres["taken"] += 1
        return centre.fget(obj)

    monkeypatch.setattr(SceneObject, "centre", property(counted_centre))
    press(scene, "p")
    assert scene.modes.parallel_half_height == pytest.approx(expected, rel=1e-12)
    assert centres["taken"] == 0
