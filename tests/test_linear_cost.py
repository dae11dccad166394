"""Cost in proportion to the input, for inputs shaped to break it: counted as work done (rows gathered,
bins allocated), never as seconds, so the counts hold on any machine however busy."""

from __future__ import annotations

import numpy as np
import pytest

from marraztu.model import build
from marraztu.model.build import build_mesh
from marraztu.model.geometry import column_bounds
from support.work import peak_traced_bytes


def polygon(corners: int) -> tuple[np.ndarray, list[list[int]]]:
    """One flat polygon of `corners` corners on a circle."""
    angles = np.linspace(0.0, 2.0 * np.pi, corners, endpoint=False)
    positions = np.stack([np.cos(angles), np.sin(angles), np.zeros(corners)], axis=1) * 10.0
    return positions, [list(range(corners))]


@pytest.fixture
def work(monkeypatch) -> dict[str, int]:
    """Counts the rows the face normals gather and the corners the vertex-normal sums add."""
    counted = {"rows": 0, "bins": 0}
    fan_sums = build._fan_sums
    sums_at = build._sums_at

    def counting_fan_sums(positions: np.ndarray, polygons: np.ndarray, axes: np.ndarray | None = None) -> np.ndarray:
        # The positions are copied where the caller has not, and each polygon's fans gathered.
        counted["rows"] += (positions.shape[0] if axes is None else 0) + polygons.shape[0] * (polygons.shape[1] - 2)
        return fan_sums(positions, polygons, axes)

    def counting_sums_at(out: np.ndarray, rows: np.ndarray, values: np.ndarray) -> None:
        counted["bins"] += len(rows)
        sums_at(out, rows, values)

    monkeypatch.setattr(build, "_fan_sums", counting_fan_sums)
    monkeypatch.setattr(build, "_sums_at", counting_sums_at)
    return counted


@pytest.mark.parametrize("corners", [100, 3_000])
def test_one_huge_polygon_costs_in_proportion_to_its_corners(work: dict[str, int], corners: int) -> None:
    positions, faces = polygon(corners)
    mesh = build_mesh("polygon", positions, faces)
    np.testing.assert_allclose(mesh.face_normals[0], [0.0, 0.0, 1.0], atol=1e-6)
    assert work["rows"] <= 4 * 2 * corners, work  # positions once and the fan's triangles once
    assert work["bins"] <= 4 * corners, work  # one pass per axis, not one per corner column


def test_small_polygons_of_one_size_keep_their_column_by_column_path(work: dict[str, int]) -> None:
    grid = np.array([[x, y, 0.0] for x in range(11) for y in range(11)])
    quads = [[x * 11 + y, (x + 1) * 11 + y, (x + 1) * 11 + y + 1, x * 11 + y + 1] for x in range(10) for y in range(10)]
    build_mesh("quads", grid, quads)
    assert work["rows"] <= 2 * (len(grid) + 2 * len(quads)) + 2 * len(grid), work


def test_a_huge_polygon_among_small_ones_is_summed_a_block_of_fans_at_a_time() -> None:
    """Alone in its block whatever follows it: with a triangle after it, its fans were gathered whole
    (60 bytes a corner). It goes round a circle of a thousand positions a thousand times."""
    corners = 1_000_000
    positions, _ = polygon(1000)
    sizes = np.array([3, corners, 3])
    face_start = np.concatenate(([0], np.cumsum(sizes))).astype(np.int32)
    corner_vertex = np.concatenate(([0, 1, 2], np.arange(corners) % 1000, [2, 3, 4])).astype(np.int32)
    normals, peak = peak_traced_bytes(lambda: build._face_normals(positions, corner_vertex, face_start, sizes,
                                                                 column_bounds(positions)))
    np.testing.assert_allclose(normals[0][1], [0.0, 0.0, 1.0], atol=1e-6)
    # A block's fans, their sums and running sums, and the pieces its threads gather at once.
    assert peak < 32 * build._FAN_BLOCK * 8, peak


def test_the_check_of_a_refused_scene_of_many_objects_and_cameras_compares_each_element_a_few_times(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """Scene.check_values' walk, which names what it refuses, asked of each element whether it is a camera
    (its reach) by a pass over the cameras: objects times cameras comparisons."""
    from marraztu.control.viewer import empty_scene
    from marraztu.model.scene import Scene, SceneObject

    camera = empty_scene().cameras[0]
    count = 200
    objects = [SceneObject.placed(f"o{index}", camera.mesh, camera.material, (0.0, 0.0, 0.0)) for index in range(count)]
    cameras = [SceneObject.placed(f"c{index}", camera.mesh, camera.material, (0.0, 0.0, 150.0))
               for index in range(count)]
    scene = Scene(objects=objects, cameras=cameras)
    scene.ambient = np.array([np.nan, 0.0, 0.0])  # refused after every element is walked
    compared = {"elements": 0}

    def counting_eq(self: SceneObject, other: object) -> bool:
        compared["elements"] += 1
        return self is other

    monkeypatch.setattr(SceneObject, "__eq__", counting_eq)
    with pytest.raises(ValueError, match="ambient"):
        scene.check_values()
    assert compared["elements"] <= 4 * 2 * count, compared


def test_the_stacked_check_of_a_scene_reads_each_kind_of_elements_reach_once(monkeypatch: pytest.MonkeyPatch) -> None:
    """Scene._all_drawable read each element's reach (a Python map over one Reach an element, into
    np.fromiter) where one np.repeat of the objects' and the cameras' does."""
    import dataclasses

    from marraztu.control.viewer import empty_scene
    from marraztu.model import scene as scene_module
    from marraztu.model.scene import SceneObject

    scene = empty_scene()
    camera = scene.cameras[0]
    scene.objects = [SceneObject.placed(f"o{index}", camera.mesh, camera.material, (0.0, 0.0, 0.0))
                     for index in range(300)]
    read = {"reaches": 0}

    @dataclasses.dataclass(frozen=True)
    class CountedReach(scene_module.Reach):
        def __getattribute__(self, name: str) -> object:
            if name == "most":
                read["reaches"] += 1
            return super().__getattribute__(name)

    for name in ("MODELS_REACH", "CAMERAS_REACH"):
        monkeypatch.setattr(scene_module, name, CountedReach(**dataclasses.asdict(getattr(scene_module, name))))
    scene.check_values()
    assert read["reaches"] <= 2, read
