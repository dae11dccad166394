"""The last two term views of `v`: the depth buffer as grey and the world normal as a colour, checked
against numpy to 1/255; the views before them keep their order and weights."""

from __future__ import annotations

import numpy as np
import pytest

import marraztu
from marraztu.model.lights import TERM_VIEWS, Show, TermView, TermWeights
from marraztu.model.transforms import transform_point

SIZE = (120, 90)
# A square facing +z, its centre on the axis the framed camera looks along.
SQUARE = np.array([[-10.0, -10.0, 0.0], [10.0, -10.0, 0.0], [10.0, 10.0, 0.0], [-10.0, 10.0, 0.0]])
TO_DEPTH = " ".join(["v"] * TERM_VIEWS.index(TermView.DEPTH))
TO_NORMALS = " ".join(["v"] * TERM_VIEWS.index(TermView.NORMALS))


def centre(picture) -> np.ndarray:
    return np.asarray(picture).astype(int)[SIZE[1] // 2, SIZE[0] // 2]


def test_the_lit_views_keep_their_places() -> None:
    assert [view.shows for view in TERM_VIEWS[:-2]] == [Show.LIT] * (len(TERM_VIEWS) - 2)
    assert TERM_VIEWS[:4] == (TermView.EVERYTHING, TermView.AMBIENT, TermView.DIFFUSE, TermView.SPECULAR)
    assert TERM_VIEWS[1].weights == TermWeights(1.0, 0.0, 0.0)
    assert TERM_VIEWS[-2:] == (TermView.DEPTH, TermView.NORMALS)


@pytest.mark.parametrize("keys", ["", "F", "s"])
def test_normals_view_paints_the_world_normal(keys: str) -> None:
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(SQUARE, [[0, 1, 2, 3]]).press(f"{keys} {TO_NORMALS}")
        assert v.message == "" and v.scene.modes.term_view is TermView.NORMALS
        assert np.abs(centre(v.render()) - np.rint((np.array([0.0, 0.0, 1.0]) * 0.5 + 0.5) * 255)).max() <= 1
        # Turned about y: the world normal turns with the object, and so does the colour.
        v.press("y*3")
        normal = v.scene.object.model[:3, :3] @ np.array([0.0, 0.0, 1.0])
        expected = np.rint((normal * 0.5 + 0.5) * 255)
        assert np.abs(centre(v.render()) - expected).max() <= 1, (normal, expected)


def test_gouraud_normals_vary_over_a_sphere_and_flat_ones_do_not() -> None:
    import trimesh

    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(trimesh.creation.icosphere(subdivisions=3, radius=10.0)).press(f"F {TO_NORMALS}")
        row = np.asarray(v.render()).astype(int)[SIZE[1] // 2]
        covered = np.flatnonzero(np.abs(row - [0, 0, 178]).sum(axis=1) > 30)
        left, right = row[covered[2]], row[covered[-3]]
        assert left[0] < 100 < 160 < right[0], "x of the normal grows from the left edge to the right"
        gouraud_colours = len(np.unique(row[covered], axis=0))
        flat_colours = len(np.unique(np.asarray(v.press("F").render()).astype(int)[SIZE[1] // 2][covered], axis=0))
        assert gouraud_colours > 2 * flat_colours


@pytest.mark.parametrize("parallel", [False, True])
def test_depth_view_paints_the_depth_buffer(parallel: bool) -> None:
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(SQUARE, [[0, 1, 2, 3]]).press(f"{'p' if parallel else ''} {TO_DEPTH}")
        scene = v.scene
        world = transform_point(scene.object.model, np.zeros(3))  # the square's centre, under the pixel
        clip = scene.projection_matrix(SIZE[0] / SIZE[1]) @ scene.view_matrix() @ np.append(world, 1.0)
        depth = (clip[2] / clip[3] + 1.0) / 2.0  # NDC z to the default depth range 0..1
        grey = centre(v.render())
        assert grey[0] == grey[1] == grey[2]
        assert abs(grey[0] - depth * 255) <= 1, (grey, depth * 255)


def test_depth_view_nearer_is_darker() -> None:
    near = SQUARE + [0, 0, 30]
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(np.vstack([SQUARE * 3, near]), [[0, 1, 2, 3], [4, 5, 6, 7]]).press(f"p {TO_DEPTH}")
        picture = np.asarray(v.render()).astype(int)
    nearer, farther = picture[SIZE[1] // 2, SIZE[0] // 2], picture[SIZE[1] // 2, SIZE[0] // 2 + 13]
    assert nearer[0] == nearer[2] and farther[0] == farther[2], "both grey"
    assert nearer[0] < farther[0], "the nearer square is darker than the far one around it"


def test_the_probe_says_what_the_pixels_show() -> None:
    from marraztu.text.panels import extras

    with marraztu.Viewer(size=(800, 800)) as v:
        v.press(f"i {TO_DEPTH}")
        assert "showing depth (v), not the colour below" in "\n".join(extras(v.scene, (800, 800)).bottom)
