"""The grid and axes (`a`): the world's axes at the origin, a ground grid at the bottom of the scene,
and in local mode the selected object's own axes; drawn where they project, hidden behind models."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from marraztu.control.keymap import parse_key_sequence
from marraztu.control.viewer import StartOptions, Viewer
from marraztu.frontends.screenshot import take_screenshot
from marraztu.loaders.scenefile import empty_scene, load_builtin_scene
from marraztu.model.guides import AXIS_COLOURS, GRID_COLOUR, OWN_AXIS_LIGHTNESS, nice_step, scene_guides
from marraztu.model.scene import GUIDES_MIN_EXTENT
from marraztu.model.viewports import View, project, view_projection
from support.scenes import BACKGROUND, NoFrontend

SIZE = (200, 200)


def guide_lines(scene) -> np.ndarray:
    guides = scene_guides(scene)
    return np.concatenate([guides.axes, guides.grid])


def segments(lines: np.ndarray) -> np.ndarray:
    """(S, 2, 6): each segment's two rows."""
    return lines.reshape(-1, 2, 6)


def axes_among(lines: np.ndarray, colour: np.ndarray) -> np.ndarray:
    """(A, 2, 3) the segments of exactly this colour."""
    pairs = segments(lines)
    return pairs[np.all(np.isclose(pairs[:, 0, 3:], colour, atol=1e-6), axis=1)][:, :, :3]


@pytest.mark.parametrize(("span", "step"), [(100.0, 5.0), (300.0, 20.0), (1e-3, 5e-5), (7e4, 5000.0), (20.0, 1.0)])
def test_the_grid_step_is_a_round_number_giving_about_twenty_cells(span: float, step: float) -> None:
    assert nice_step(span) == pytest.approx(step)


def test_the_world_axes_start_at_the_origin_in_red_green_and_blue() -> None:
    lines = guide_lines(load_builtin_scene())
    for axis in range(3):
        (start, end), = axes_among(lines, AXIS_COLOURS[axis])
        assert np.allclose(start, 0.0) and end[axis] > 0 and np.allclose(np.delete(end, axis), 0.0)


def test_the_grid_lies_flat_at_the_bottom_of_the_scene() -> None:
    scene = load_builtin_scene()
    grid = axes_among(guide_lines(scene), np.float32(GRID_COLOUR))
    lowest = min(float((obj.mesh.positions @ obj.model[:3, :3].T + obj.model[:3, 3])[:, 1].min())
                 for obj in scene.objects)
    assert len(grid) >= 20 and np.allclose(grid[:, :, 1], lowest, atol=1e-4)


@pytest.mark.parametrize("keys", ["a p", "a c t Z*28 p", "a c t Z*28 r y*8 X*3 p", "a c t z*200 p"])
def test_parallel_projections_far_plane_is_beyond_every_guide(keys: str) -> None:
    """Its far plane is twice the depth of what is shown, not 1,000 units: the guides count too."""
    viewer = Viewer(load_builtin_scene(), NoFrontend())
    viewer.start(StartOptions(), longest_texture_side=64)
    for key in parse_key_sequence(keys):
        viewer.press(key)
    scene = viewer.scene
    depths = [scene.depth_of(point) for point in guide_lines(scene)[:, :3]]
    assert max(depths) < scene.far_plane()


@pytest.mark.parametrize("size,centre", [(1e-3, (0.0, 0.0, 0.0)), (50.0, (4e6, 3e6, -2e6))],
                         ids=["a millimetre in metres", "a site 5,000 km out"])
def test_a_small_or_far_model_gets_a_grid_of_its_own_size_under_it(
        tmp_path: Path, size: float, centre: tuple[float, float, float]) -> None:
    """The grid's cells followed the distance from the origin and a 100-unit least: a millimetre cube
    sat inside one 5-unit cell, a site's model on cells of 250 km 3,000 km above their plane."""
    corners = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)] * np.array([size / 2] * 3) + centre
    path = tmp_path / "cube.obj"
    path.write_text("".join(f"v {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in corners)
                    + "f 1 2 4 3\nf 5 7 8 6\nf 1 5 6 2\nf 3 4 8 7\nf 1 3 7 5\nf 2 6 8 4\n")
    viewer = Viewer(empty_scene(), NoFrontend())
    viewer.start(StartOptions(empty=True, models=(path,)), longest_texture_side=64)
    grid = axes_among(guide_lines(viewer.scene), np.float32(GRID_COLOUR))
    cells = (grid[:, :, 0].max() - grid[:, :, 0].min()) / nice_step(size)
    assert 20 <= cells <= 60 and np.allclose(grid[:, :, 1], centre[1] - size / 2)


def test_an_empty_scene_still_has_a_grid_of_sensible_size() -> None:
    grid = axes_among(guide_lines(empty_scene()), np.float32(GRID_COLOUR))
    assert grid[:, :, 0].max() - grid[:, :, 0].min() >= GUIDES_MIN_EXTENT


def test_local_mode_adds_the_selected_objects_own_axes_along_its_matrix() -> None:
    scene = load_builtin_scene()
    obj = scene.object
    own = [axes_among(guide_lines(scene), AXIS_COLOURS[axis] * OWN_AXIS_LIGHTNESS + (1 - OWN_AXIS_LIGHTNESS))
           for axis in range(3)]
    for axis, ((start, end),) in enumerate(own):
        along = (end - start) / np.linalg.norm(end - start)
        assert np.allclose(start, obj.origin, atol=1e-4)
        assert np.allclose(along, obj.model[:3, axis] / np.linalg.norm(obj.model[:3, axis]), atol=1e-5)
    scene.modes.frame = scene.modes.frame.__class__("global")
    assert len(segments(guide_lines(scene))) == len(segments(guide_lines(load_builtin_scene()))) - 3


# --- pixels --------------------------------------------------------------------------------------
def picture(tmp_path: Path, keys: str, models: tuple[Path, ...] = ()) -> np.ndarray:
    out = take_screenshot(StartOptions(empty=True, models=models), tmp_path / "shot.png", SIZE, keys=keys)
    return np.asarray(Image.open(out).convert("RGB")).astype(int)


def pixel_of(keys: str, point: tuple[float, float, float], models: tuple[Path, ...] = ()) -> tuple[int, int]:
    """Row and column where `point` lands in the picture of `keys`, computed apart from the renderer."""
    viewer = Viewer(empty_scene(), NoFrontend())
    viewer.start(StartOptions(empty=True, models=models), longest_texture_side=64)
    for key in parse_key_sequence(keys):
        viewer.press(key)
    x, y = project(view_projection(viewer.scene, View((0, 0, *SIZE), viewer.scene.modes.shading)), np.array(point),
                   (0, 0, *SIZE))
    return SIZE[1] - 1 - int(y), int(x)  # picture rows run top down


def test_the_axes_are_drawn_in_their_colours_where_they_project(tmp_path: Path) -> None:
    keys = "a c t y*4 x*4 c c"  # the camera moved up and right, so that the z axis shows too
    shown, hidden = picture(tmp_path, keys), picture(tmp_path, keys.replace("a ", "", 1))
    for axis in range(3):
        point = [0.0, 0.0, 0.0]
        point[axis] = 25.0  # on the axis, half way along it
        row, column = pixel_of(keys, tuple(point))
        near = shown[row - 1:row + 2, column - 1:column + 2].reshape(-1, 3)
        expected = np.round(AXIS_COLOURS[axis] * 255).astype(int)
        assert (np.abs(near - expected).max(axis=1) <= 1).any(), (axis, near)
        assert (hidden[row - 1:row + 2, column - 1:column + 2] == BACKGROUND).all()


def test_a_model_in_front_hides_the_axis_behind_it(tmp_path: Path) -> None:
    wall = tmp_path / "wall.obj"
    wall.write_text("v -100 -100 40\nv 100 -100 40\nv 100 100 40\nv -100 100 40\nf 1 2 3 4\n")
    everything = picture(tmp_path, "a T", (wall,))
    pixels = everything[70:130, 70:130]  # inside the wall's outline (framed, it spans about 60..140)
    red = np.round(AXIS_COLOURS[0] * 255).astype(int)
    grid = np.round(np.float32(GRID_COLOUR) * 255).astype(int)
    assert not (np.abs(pixels - red).max(axis=2) <= 1).any()  # the x axis, at z = 0, is behind the wall
    assert not (np.abs(pixels - grid).max(axis=2) <= 1).any()
    assert (pixels != BACKGROUND).any(axis=2).all()  # the wall itself is there
    assert (np.abs(everything[185:] - grid).max(axis=2) <= 1).any()  # the grid, below the wall


def test_the_ground_grid_is_drawn_in_its_colour(tmp_path: Path) -> None:
    pixels = picture(tmp_path, "a")
    grid = np.round(np.float32(GRID_COLOUR) * 255).astype(int)
    on_grid = (np.abs(pixels - grid).max(axis=2) <= 1)
    assert on_grid[SIZE[1] // 2:].sum() > 100 and not on_grid[: SIZE[1] // 2 - 2].any()  # below the horizon only


def ground_plane(tmp_path: Path, half: float = 20.0, cells: int = 8) -> Path:
    """A square of quads lying in y = 0: the ground grid's own plane."""
    path = tmp_path / "ground.obj"
    ticks = np.linspace(-half, half, cells + 1)
    lines = [f"v {x} 0 {z}" for x in ticks for z in ticks]
    for i in range(cells):
        for j in range(cells):
            a = i * (cells + 1) + j + 1
            lines.append(f"f {a} {a + 1} {a + cells + 2} {a + cells + 1}")
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.mark.parametrize("camera", ["", " c t Y*3", " c t Y*5", " c t Y*6", " p"])
def test_a_model_lying_on_the_ground_hides_the_grid_and_axes_in_its_plane(tmp_path: Path, camera: str) -> None:
    # Lines and triangles in one plane get depths up to half a pixel apart: the grid and the x and z
    # axes once showed through such a model as dots, most where the camera looks along the ground.
    plane = (ground_plane(tmp_path),)
    keys = "a" + camera
    shown, hidden = picture(tmp_path, keys, plane), picture(tmp_path, keys.replace("a", "", 1).strip(), plane)
    y_axis = np.round(AXIS_COLOURS[1] * 255).astype(int)  # rising from the origin, in front of the model
    for x in (-15.0, -10.0, -6.0, -3.0, 0.0, 3.0, 6.0, 10.0, 15.0):
        for z in (-15.0, -10.0, -6.0, -3.0, 0.0, 3.0, 6.0, 10.0, 15.0):
            row, column = pixel_of(keys, (x, 0.0, z), plane)
            near, bare = shown[row - 1:row + 2, column - 1:column + 2], hidden[row - 1:row + 2, column - 1:column + 2]
            on_model = (bare != BACKGROUND).any(axis=2)  # seen edge on, the model is a few pixels thin
            kept = (near == bare).all(axis=2) | (near == y_axis).all(axis=2)
            assert kept[on_model].all(), (x, z, near, bare)
            assert (bare[1, 1] != BACKGROUND).any()  # the model is there
    assert (shown != hidden).any()  # the guides are drawn beside it


def test_every_axis_stands_out_from_the_background() -> None:
    """Pure blue z on the seed's blue background (0, 0, 178) differed by 77 levels in one channel."""
    for colour in AXIS_COLOURS:
        assert np.abs(np.round(colour * 255) - BACKGROUND).max() >= 128, colour


@pytest.mark.parametrize("keys", ["a", "a g"], ids=["local", "global"])
def test_the_world_axes_stand_out_of_a_model_around_the_origin(tmp_path: Path, keys: str) -> None:
    """They were half the guides' extent long: inside a 1-unit cube centred on the origin, hidden, and
    in local mode covered by the cube's own (paler) axes, which reach half its diagonal."""
    corners = [(x, y, z) for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
    path = tmp_path / "cube.obj"
    path.write_text("".join(f"v {x} {y} {z}\n" for x, y, z in corners)
                    + "f 1 2 4 3\nf 5 7 8 6\nf 1 5 6 2\nf 3 4 8 7\nf 1 3 7 5\nf 2 6 8 4\n")
    pixels = picture(tmp_path, keys, (path,))
    for axis in (0, 1):  # x and y: across the view (z points at the camera)
        expected = np.round(AXIS_COLOURS[axis] * 255).astype(int)
        assert (np.abs(pixels - expected).max(axis=2) <= 1).sum() >= 5, axis
