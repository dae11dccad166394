"""The Python interface: the same viewer, key map and renderer as the screenshot command, so the same
pixels for the same keys; models from files, arrays and trimesh; the probe as numbers; the context
closed by `with`, `close` or garbage collection; bad input refused where it enters."""

from __future__ import annotations

import collections
import copy
import dataclasses
import gc
import pickle
import re
import subprocess
import sys
import threading
from collections.abc import Callable
from io import BytesIO
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest
import trimesh
from PIL import Image

import marraztu
from marraztu.control.viewer import START_HINT, StartOptions
from marraztu.errors import KeyMapError, LoadError, ViewerError
from marraztu.frontends import api
from marraztu.frontends.screenshot import take_screenshot
from marraztu.model.geometry import FLOAT32_MAX
from marraztu.model.probe import probe as scene_probe
from marraztu.model.scene import LIGHT_REACH, NAME_LIMIT
from marraztu.resources import ASSET_DIR

SIZE = (160, 120)
TRIANGLE = np.array([[-60.0, -60.0, 20.0], [60.0, -60.0, 20.0], [0.0, 60.0, 20.0]])


def screenshot(tmp_path: Path, keys: str, overlay: bool = False, **options: object) -> np.ndarray:
    out = take_screenshot(StartOptions(**options), tmp_path / "shot.png", SIZE, keys=keys, overlay=overlay)
    return np.asarray(Image.open(out).convert("RGB"))


@pytest.fixture
def viewer():
    with marraztu.Viewer(size=SIZE) as v:
        yield v


@pytest.mark.parametrize("keys", ["", "0 1 F x*5", "c t Z*8 c c l b", "TAB TAB ENTER*3 i v v s", "x ESC x*20",
                                  "f ESC x*3"])
def test_the_api_draws_the_screenshot_commands_pixels(viewer, tmp_path: Path, keys: str) -> None:
    picture = np.asarray(viewer.press(keys).render())
    assert np.array_equal(picture, screenshot(tmp_path, keys))
    assert (np.abs(picture.astype(int) - [0, 0, 178]).sum(axis=2) > 30).mean() > 0.01, "not blank"


def test_the_overlay_is_the_screenshot_commands_overlay(viewer, tmp_path: Path) -> None:
    picture = np.asarray(viewer.press("0 1 i").render(overlay=True))
    assert np.array_equal(picture, screenshot(tmp_path, "0 1 i", overlay=True))
    assert not np.array_equal(picture, np.asarray(viewer.render()))


def test_the_start_hint_is_the_api_message_and_the_screenshot_commands_overlay(viewer, tmp_path: Path) -> None:
    assert viewer.message == START_HINT
    picture = np.asarray(viewer.render(overlay=True))
    assert np.array_equal(picture, screenshot(tmp_path, "", overlay=True))
    assert not np.array_equal(picture, np.asarray(viewer.press("l l").render(overlay=True)))


def test_a_notebook_shows_the_picture(viewer) -> None:
    shown = np.asarray(Image.open(BytesIO(viewer._repr_png_())).convert("RGB"))
    assert np.array_equal(shown, np.asarray(viewer.render()))


def test_each_picture_hands_back_the_memory_its_drawing_freed(viewer, monkeypatch) -> None:
    """A notebook keeps the process between pictures, as the window does between keys."""
    from marraztu.frontends import api

    handed_back: list[bool] = []
    monkeypatch.setattr(api, "return_freed_memory", lambda: handed_back.append(True))
    viewer.render()
    viewer.press("l").render(overlay=True)
    assert len(handed_back) == 2


def test_closing_hands_back_the_memory_its_context_held(monkeypatch) -> None:
    """A context on llvmpipe holds ~9 MB: 100 viewers open then closed left the process at 914 MB, not
    the 125 MB it held, until some viewer drew again."""
    from marraztu.frontends import api

    first, second = marraztu.Viewer(size=SIZE, empty=True), marraztu.Viewer(size=SIZE, empty=True)
    handed_back: list[bool] = []
    monkeypatch.setattr(api, "return_freed_memory", lambda: handed_back.append(True))
    first.close()
    second.close()  # whether its context is kept for the next viewer or released
    assert len(handed_back) == 2


def test_threads_sharing_a_viewer_take_turns(viewer, tmp_path: Path) -> None:
    """Its GL context can be current in one thread only: two renders at once failed with "cannot
    create renderbuffer"; they now take turns, each picture whole."""
    expected = screenshot(tmp_path, "x")
    viewer.press("x")
    pictures: list[np.ndarray] = []
    failures: list[Exception] = []

    def draw() -> None:
        for _ in range(4):
            try:
                pictures.append(np.asarray(viewer.render()))
            except Exception as error:  # noqa: BLE001 - collected, to fail in the test's own thread
                failures.append(error)

    threads = [threading.Thread(target=draw) for _ in range(3)]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join()
    assert failures == [] and len(pictures) == 12
    assert all(np.array_equal(picture, expected) for picture in pictures)


@pytest.mark.parametrize("read", ["status", "message"])
def test_the_top_and_bottom_lines_are_read_in_turn(viewer, monkeypatch: pytest.MonkeyPatch, read: str) -> None:
    """status checked the scene and read it while another thread's press could be half done; it and
    message now take their turn as every call does: no other thread can take it while they read."""
    taken_meanwhile: list[bool] = []

    def another_thread_takes_the_turn() -> None:
        def take() -> None:
            taken = viewer._turn.acquire(blocking=False)
            taken_meanwhile.append(taken)
            if taken:
                viewer._turn.release()
        thread = threading.Thread(target=take)
        thread.start()
        thread.join()

    real_check = viewer._check_scene if read == "status" else None
    if read == "status":
        monkeypatch.setattr(viewer, "_check_scene", lambda: (another_thread_takes_the_turn(), real_check())[1])
    else:
        viewer.press("f")  # the prompt open: message writes its line
        monkeypatch.setattr(api, "prompt_line", lambda prompt: (another_thread_takes_the_turn(), "prompt")[1])
    getattr(viewer, read)
    assert taken_meanwhile == [False]


def test_render_at_another_size(viewer) -> None:
    assert viewer.render(size=(64, 48)).size == (64, 48)


def test_load_draws_a_file_like_the_command_line(tmp_path: Path) -> None:
    model = tmp_path / "tri.obj"
    model.write_text("".join(f"v {x:g} {y:g} {z:g}\n" for x, y, z in TRIANGLE) + "f 1 2 3\n")
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        assert "loaded tri.obj" in v.load(model).message
        picture = np.asarray(v.press("0 1").render())
    assert np.array_equal(picture, screenshot(tmp_path, "0 1", empty=True, models=(model,)))


def test_arrays_draw_like_the_same_triangle_from_a_file(tmp_path: Path) -> None:
    model = tmp_path / "tri.obj"
    model.write_text("".join(f"v {x:g} {y:g} {z:g}\n" for x, y, z in TRIANGLE) + "f 1 2 3\n")
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        from_arrays = np.asarray(v.add_mesh(TRIANGLE, [[0, 1, 2]], name="tri").press("0 1").render())
    assert np.array_equal(from_arrays, screenshot(tmp_path, "0 1", empty=True, models=(model,)))


def test_a_trimesh_with_its_vertex_colours() -> None:
    mesh = trimesh.Trimesh(TRIANGLE, [[0, 1, 2]], process=False)
    mesh.visual.vertex_colors = np.tile([255, 0, 0, 255], (3, 1))
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(mesh).press("T 0 1")
        assert np.array_equal(v.scene.object.mesh.vertex_colours, np.tile([255, 0, 0], (3, 1)))
        centre = np.asarray(v.render())[SIZE[1] // 2, SIZE[0] // 2]
    assert centre[0] > 0 and centre[1] == 0 and centre[2] == 0  # lit, times pure red


def test_a_trimesh_with_its_texture_draws_like_the_same_model_from_a_file(tmp_path: Path) -> None:
    """Its uvs and its material's picture, as an OBJ with vt and map_Kd gives them: the picture at full
    strength where no colour is given (it took the viewer's Kd 0.7, an MTL's map_Kd alone Kd 1)."""
    picture = Image.new("RGB", (2, 2))
    picture.putdata([(255, 0, 0), (0, 255, 0), (0, 0, 255), (255, 255, 0)])
    picture.save(tmp_path / "four.ppm")
    square = [[-60.0, -60.0, 20.0], [60.0, -60.0, 20.0], [60.0, 60.0, 20.0], [-60.0, 60.0, 20.0]]
    uvs = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    (tmp_path / "square.mtl").write_text("newmtl square\nmap_Kd four.ppm\n")  # no Kd: the picture is the colour
    (tmp_path / "square.obj").write_text("mtllib square.mtl\nusemtl square\n"
                                         + "".join(f"v {x:g} {y:g} {z:g}\n" for x, y, z in square)
                                         + "".join(f"vt {u:g} {v:g}\n" for u, v in uvs)
                                         + "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
    mesh = trimesh.Trimesh(square, [[0, 1, 2], [0, 2, 3]], process=False,
                           visual=trimesh.visual.TextureVisuals(uv=uvs, image=picture))
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        from_trimesh = np.asarray(v.add_mesh(mesh, name="square").press("0 1").render())
        assert v.scene.object.mesh.attributes_per_position
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        from_file = np.asarray(v.load(tmp_path / "square.obj").press("0 1").render())
    assert np.array_equal(from_trimesh, from_file)
    centre = SIZE[1] // 2
    left, right = from_file[centre - 20, SIZE[0] // 2 - 20], from_file[centre + 20, SIZE[0] // 2 + 20]
    # red; yellow, by margins: at Kd 1 the red pixel is (142, 74, 56), under the ratio of 2 Kd 0.7 gave
    assert left[0] > max(left[1:]) + 50 and min(right[:2]) > right[2] + 50


FOUR = np.array([[[255, 0, 0], [0, 255, 0]], [[0, 0, 255], [255, 255, 0]]], dtype=np.uint8)  # top row first
SQUARE = np.array([[-60.0, -60.0, 20.0], [60.0, -60.0, 20.0], [60.0, 60.0, 20.0], [-60.0, 60.0, 20.0]])
SQUARE_UVS = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


def _textured_square(texture: object) -> np.ndarray:
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(SQUARE, [[0, 1, 2], [0, 2, 3]], uvs=SQUARE_UVS, texture=texture, name="square")
        return np.asarray(v.press("0 1").render())


@pytest.mark.parametrize("kind", ["bytes", "floats", "RGBA", "a PIL image", "a file"])
def test_add_mesh_takes_a_texture_made_in_numpy_and_draws_it_as_a_files_own(tmp_path: Path, kind: str) -> None:
    """A picture made in code could only reach a mesh through trimesh's TextureVisuals: add_mesh's
    texture= takes one as colours are taken (bytes, or floats in 0..1), a PIL image, or a file."""
    Image.fromarray(FOUR).save(tmp_path / "four.png")
    texture = {"bytes": FOUR, "floats": FOUR / 255.0, "RGBA": np.dstack([FOUR, np.full((2, 2), 9, np.uint8)]),
               "a PIL image": Image.fromarray(FOUR).convert("P"), "a file": tmp_path / "four.png"}[kind]
    visual = trimesh.visual.TextureVisuals(uv=SQUARE_UVS, image=Image.fromarray(FOUR))
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(trimesh.Trimesh(SQUARE, [[0, 1, 2], [0, 2, 3]], process=False, visual=visual), name="square")
        from_trimesh = np.asarray(v.press("0 1").render())
    np.testing.assert_array_equal(_textured_square(texture), from_trimesh)


@pytest.mark.parametrize(("positions", "faces", "words"), [
    (SQUARE.T, [[0, 1, 2], [0, 2, 3]], "not (3, 4): for 4 positions, give positions.T"),
    (SQUARE, np.array([[0, 1, 2], [0, 2, 3]]).T, "3 faces of 2 corners, and a face needs at least 3: for 2 faces "
                                                 "of 3, give faces.T"),
    (SQUARE, np.array([[0, 1, 2, 3]]).T, "4 faces of 1 corner, and a face needs at least 3: for 1 face of 4"),
])
def test_arrays_given_transposed_are_refused_saying_so(positions: np.ndarray, faces: object, words: str) -> None:
    """(3, V) positions and (3, F) faces of one or two triangles were refused as 'not (3, 4)' and 'face 0
    has 2 vertices', which did not say that the arrays were only turned."""
    with marraztu.Viewer(size=SIZE, empty=True) as v, pytest.raises(ValueError, match=re.escape(words)):
        v.add_mesh(positions, faces)


def test_faces_given_transposed_are_said_to_be_perhaps_so() -> None:
    """An icosphere's (80, 3) faces given as (3, 80) drew 3 polygons of 80 corners; the message said
    '3 faces' and '1 zero-area face', not why."""
    sphere = trimesh.creation.icosphere(1, radius=50.0)
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(sphere.vertices, sphere.faces.T, name="ball")
        assert v.message.endswith("(3 polygons of 80 corners: for 80 polygons of 3, give faces.T)"), v.message
        v.add_mesh(sphere.vertices, sphere.faces, name="ball")
        assert v.message.startswith("added ball: 42 vertices, 80 faces") and "faces.T" not in v.message
        hexagons = np.arange(18).reshape(3, 6)  # three real polygons of six corners: no hint
        v.add_mesh(np.c_[np.cos(np.arange(18)), np.sin(np.arange(18)), np.arange(18) // 6], hexagons, name="rings")
        assert v.message.startswith("added rings: 18 vertices, 3 faces") and "faces.T" not in v.message


@pytest.mark.parametrize("stray", ["a", None])
def test_faces_of_three_rows_that_are_not_numbers_are_refused_as_any_faces_are(stray: object) -> None:
    """75b8a32's hint sorted each row of faces not yet checked: a stray word or None in (3, 5) objects
    raised TypeError "'<' not supported between instances of 'str' and 'int'"."""
    faces = np.array([[0, 1, 2, 3, stray], [0, 1, 2, 3, 4], [0, 1, 2, 3, 4]], dtype=object)
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        with pytest.raises(ValueError, match=r"^face indices must be whole numbers"):
            v.add_mesh(np.eye(5, 3), faces)


def test_a_name_longer_than_a_files_is_refused_not_cut() -> None:
    """add_mesh cut a name at 200 characters without a word, where a scene file kept it whole."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(TRIANGLE, [[0, 1, 2]], name="n" * NAME_LIMIT)
        assert v.scene.object.name == "n" * NAME_LIMIT
        with pytest.raises(ValueError, match=f"^name is 100000 characters long: at most {NAME_LIMIT}$"):
            v.add_mesh(TRIANGLE, [[0, 1, 2]], name="n" * 100_000)


def test_the_status_line_says_what_a_mode_key_changed() -> None:
    """After F, b or c g, v.message was empty and only render(overlay=True) showed the switch."""
    with marraztu.Viewer(size=SIZE) as v:
        assert v.status.startswith("target objects | rotate local | flat | ") and "culling off" in v.status
        v.press("F b c g")
        assert v.message == "" and v.status.startswith("target cameras | rotate analysis | gouraud | ")
        assert "culling on" in v.status


def test_the_probe_says_whether_a_texture_multiplies_the_pixel() -> None:
    """A student compared the probe's colour with the pixel's and found them apart, with nothing in the
    report saying the built-in picture multiplied it."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(SQUARE, [[0, 1, 2], [0, 2, 3]])
        assert v.probe().textured and not v.press("T").probe().textured
        v.add_mesh(SQUARE, [[0, 1, 2], [0, 2, 3]], colours=np.full((4, 3), 200))  # its colours are its surface
        assert not v.press("T").probe().textured


@pytest.mark.parametrize("texture", [Image.new("L", (4, 4)), np.zeros((4, 4), np.uint8)], ids=["Pillow", "array"])
def test_a_texture_of_more_pixels_than_a_files_is_refused_as_a_pillow_image_too(monkeypatch: pytest.MonkeyPatch,
                                                                               texture: object) -> None:
    """An array past MAX_PIXELS was refused and the same picture as a Pillow image drawn: 3c26c74 read
    Pillow's through rgb_array, which counts no pixels (8193x8192 of mode L was kept, 200 MB)."""
    from marraztu.loaders import images

    monkeypatch.setattr(images, "MAX_PIXELS", 15)
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        with pytest.raises(ValueError, match=r"at most 15 pixels"):
            v.add_mesh(SQUARE, [[0, 1, 2, 3]], uvs=SQUARE_UVS, texture=texture)
        assert not v.scene.objects


def test_a_pillow_texture_is_read_as_a_file_of_its_mode_is() -> None:
    """A 16-bit grey image (Image.fromarray of uint16) went through Pillow's convert, which clips: 30000
    of 65535 was drawn white. It is scaled as a 16-bit PNG's grey is, as a trimesh material's picture
    and the same picture saved as a file are."""
    grey16 = Image.fromarray(np.full((2, 2), 30000, np.uint16))
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(SQUARE, [[0, 1, 2, 3]], uvs=SQUARE_UVS, texture=grey16)
        assert v.scene.object.picture[0, 0].tolist() == [117, 117, 117]
        # 32-bit integers made in code have no range a file says: their numbers, as an array's (100 was black)
        v.add_mesh(SQUARE, [[0, 1, 2, 3]], uvs=SQUARE_UVS, texture=Image.fromarray(np.full((2, 2), 100, np.int32)))
        assert v.scene.object.picture[0, 0].tolist() == [100, 100, 100]
        with pytest.raises(ValueError, match="^integer texture pixels must lie in 0..255$"):
            v.add_mesh(SQUARE, [[0, 1, 2, 3]], uvs=SQUARE_UVS, texture=Image.fromarray(np.full((2, 2), -5, np.int32)))


@pytest.mark.parametrize("texture, words", [
    (np.zeros((2, 2, 2), np.uint8), r"an \(H, W\) grey or \(H, W, 3 or 4\) picture, not shape \(2, 2, 2\)"),
    (np.zeros((0, 4, 3), np.uint8), r"not shape \(0, 4, 3\)"),
    (np.full((2, 2, 3), 256), "integer texture pixels must lie in 0..255"),
    (np.full((2, 2, 3), 1.5), "float texture pixels must be finite and lie in 0..1"),
    # a picture of 0..255 made in float64 was refused without a word on what to give instead
    (np.full((2, 2, 3), 200.0), r"^float texture pixels must be finite and lie in 0\.\.1; for 0\.\.255, give bytes "
                                r"\(\.astype\(np\.uint8\)\) or divide by 255$"),
    (np.full((2, 2, 3), np.nan), "float texture pixels must be finite"),
    (np.array([["a"]]), "texture pixels must be numbers"),
    (np.broadcast_to(np.uint8(7), (10**5, 10**5, 3)), r"^image size 100000x100000 is too large \(at most 67108864 "),
    (Image.new("La", (2, 2)), "^a picture in Pillow's mode La cannot be drawn: give it in RGB$"),
    (np.full((2, 2), 30000, np.uint16), "^integer texture pixels must lie in 0..255$"),
])
def test_a_texture_that_cannot_be_drawn_is_refused_by_add_mesh_in_one_line(texture: object, words: str) -> None:
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        with pytest.raises(ValueError, match=words):
            v.add_mesh(SQUARE, [[0, 1, 2], [0, 2, 3]], uvs=SQUARE_UVS, texture=texture)
        with pytest.raises(LoadError, match="^no such file.png: "):  # a file's picture: as v.load says it
            v.add_mesh(SQUARE, [[0, 1, 2], [0, 2, 3]], uvs=SQUARE_UVS, texture="no such file.png")
        assert v.scene.objects == []


def test_a_trimesh_scene_draws_like_its_glb_file(tmp_path: Path) -> None:
    """Its meshes placed by their nodes, each with its own picture, as the file reader places them."""
    corners = np.array([[-25.0, -25.0, 20.0], [25.0, -25.0, 20.0], [25.0, 25.0, 20.0], [-25.0, 25.0, 20.0]])
    scene = trimesh.Scene()
    for colour, x in (((250, 0, 0), -30.0), ((0, 0, 250), 30.0)):
        picture = Image.new("RGB", (4, 4), colour)
        visual = trimesh.visual.TextureVisuals(uv=[[0, 0], [1, 0], [1, 1], [0, 1]], image=picture)
        scene.add_geometry(trimesh.Trimesh(corners, [[0, 1, 2], [0, 2, 3]], process=False, visual=visual),
                           transform=trimesh.transformations.translation_matrix([x, 0, 0]))
    (tmp_path / "scene.glb").write_bytes(scene.export(file_type="glb"))
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        from_scene = np.asarray(v.add_mesh(trimesh.load(tmp_path / "scene.glb"), name="scene").press("0 1").render())
        assert len(v.scene.object.mesh.materials) == 2
        with pytest.raises(ValueError, match="no triangle mesh"):
            v.add_mesh(trimesh.Scene())
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        from_file = np.asarray(v.load(tmp_path / "scene.glb").press("0 1").render())
    assert np.array_equal(from_scene, from_file)
    left, right = from_file[SIZE[1] // 2, SIZE[0] // 2 - 30], from_file[SIZE[1] // 2, SIZE[0] // 2 + 30]
    assert left[0] > 2 * left[2] and right[2] > 2 * right[0], (left, right)


def test_a_trimeshs_picture_is_its_texture_whatever_its_kind() -> None:
    """A Pillow picture or an array, in a PBR or a plain material; 16-bit grey scaled as a PNG's is;
    trimesh's 2x2 stand-in for uvs without a picture is no texture."""
    square = [[-60.0, -60.0, 20.0], [60.0, -60.0, 20.0], [60.0, 60.0, 20.0], [-60.0, 60.0, 20.0]]
    uvs = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]
    red = np.tile(np.array([255, 0, 0], np.uint8), (4, 4, 1))
    grey16 = Image.fromarray(np.full((4, 4), 30000, np.uint16))
    visuals = {
        "array in a PBR material": trimesh.visual.TextureVisuals(
            uv=uvs, material=trimesh.visual.material.PBRMaterial(baseColorTexture=red)),
        "array as the image": trimesh.visual.TextureVisuals(uv=uvs, image=red),
        "16-bit grey": trimesh.visual.TextureVisuals(uv=uvs, image=grey16),
        "no picture": trimesh.visual.TextureVisuals(uv=uvs),
    }
    textures = {}
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        for name, visual in visuals.items():
            v.add_mesh(trimesh.Trimesh(square, [[0, 1, 2], [0, 2, 3]], process=False, visual=visual))
            materials = v.scene.object.mesh.materials
            textures[name] = materials[0].texture[0, 0].tolist() if materials else None
    assert textures == {"array in a PBR material": [255, 0, 0], "array as the image": [255, 0, 0],
                        "16-bit grey": [117, 117, 117], "no picture": None}


@pytest.mark.parametrize("picture", [np.full((4, 4, 3), 0.5, np.float32), np.full((4, 4), 0.5),
                                     Image.fromarray(np.full((4, 4), 0.5, np.float32))],
                         ids=["float32 RGB", "float64 grey", "Pillow's mode F"])
def test_a_trimeshs_picture_of_floats_is_read_as_add_mesh_reads_one(viewer, picture: object) -> None:
    """A texture of 0..1 floats, as numpy makes them: an RGB array's note blamed Pillow ('Pillow cannot
    decode it'), and a grey one (or a Pillow picture of mode F made from it) was drawn black without a
    word, read as 16-bit grey is. Floats in 0..1 are drawn, as add_mesh's texture= draws them; others
    are a note in the same words as its refusal."""
    def textured(image: object) -> trimesh.Trimesh:
        return trimesh.Trimesh([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0]], [[0, 1, 2]], process=False,
                               visual=trimesh.visual.TextureVisuals(uv=[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]],
                                                                    image=image))

    viewer.add_mesh(textured(picture))
    assert viewer.scene.object.mesh.materials[0].texture[0, 0].tolist() == [128, 128, 128]
    viewer.add_mesh(textured(np.asarray(picture) * 3.0))
    assert viewer.scene.object.mesh.materials == ()
    assert "(float texture pixels must be finite and lie in 0..1; for 0..255, give bytes" in viewer.message


def test_a_trimesh_face_past_its_own_vertices_is_refused_not_joined_to_the_next_mesh(viewer) -> None:
    scene = trimesh.Scene([trimesh.Trimesh(TRIANGLE, [[0, 1, 5]], process=False, validate=False),
                           trimesh.Trimesh(TRIANGLE + 100.0, [[0, 1, 2]], process=False)])
    with pytest.raises(ValueError, match="face 0 refers to vertex 5, but its mesh has 3"):
        viewer.add_mesh(scene)
    with pytest.raises(ValueError, match="face 0 refers to vertex -1, but its mesh has 3"):
        viewer.add_mesh(trimesh.Trimesh(TRIANGLE, [[0, 1, -1]], process=False, validate=False))


def test_a_textured_trimesh_material_takes_the_models_name(viewer) -> None:
    """trimesh names its materials material_0, material_1...: the name given is shown instead."""
    visual = trimesh.visual.TextureVisuals(uv=[[0, 0], [1, 0], [0, 1]], image=Image.new("RGB", (4, 4), (9, 9, 9)))
    viewer.add_mesh(trimesh.Trimesh(TRIANGLE, [[0, 1, 2]], process=False, visual=visual), name="mine")
    assert [material.name for material in viewer.scene.object.mesh.materials] == ["mine"]


@pytest.mark.parametrize("file_name", ["globe.glb", "part.stl"])
def test_a_trimesh_read_from_a_file_takes_the_files_name(viewer, tmp_path: Path, file_name: str) -> None:
    """README's add_mesh(trimesh.load("models/globe.glb")) named the object, and its material, "mesh";
    trimesh keeps where it read a geometry (since 4.6.0, its .source). A name given still wins, and a
    trimesh made in Python keeps "mesh"."""
    visual = trimesh.visual.TextureVisuals(uv=[[0, 0], [1, 0], [0, 1]], image=Image.new("RGB", (4, 4), (9, 9, 9)))
    trimesh.Trimesh(TRIANGLE, [[0, 1, 2]], process=False, visual=visual).export(tmp_path / file_name)
    read = trimesh.load(tmp_path / file_name)
    viewer.add_mesh(read)
    stem, textured = Path(file_name).stem, file_name.endswith(".glb")  # an STL keeps no texture
    assert viewer.scene.object.name == stem
    assert [material.name for material in viewer.scene.object.mesh.materials] == [stem] * textured
    assert viewer.add_mesh(read, name="mine").scene.object.name == "mine"
    assert viewer.add_mesh(trimesh.Trimesh(TRIANGLE, [[0, 1, 2]], process=False)).scene.object.name == "mesh"
    assert viewer.add_mesh(TRIANGLE, [[0, 1, 2]]).scene.object.name == "mesh"


def test_any_object_with_vertices_and_faces_is_taken_as_a_trimesh_is(viewer) -> None:
    viewer.add_mesh(SimpleNamespace(vertices=TRIANGLE, faces=np.array([[0, 1, 2]])), name="plain")
    assert viewer.scene.object.mesh.face_count == 1


def test_uvs_and_normals_rows_that_are_not_finite_are_derived_as_nan_rows_are(viewer) -> None:
    faces = [[0, 1, 2]]
    meshes = []
    for bad in (np.nan, np.inf):
        uvs, normals = np.full((3, 2), 0.25), np.tile([0.0, 0.0, 1.0], (3, 1))
        uvs[1, 0] = normals[2, 1] = bad
        meshes.append(viewer.add_mesh(TRIANGLE, faces, uvs=uvs, normals=normals).scene.object.mesh)
    assert np.array_equal(meshes[0].uvs, meshes[1].uvs) and np.array_equal(meshes[0].normals, meshes[1].normals)
    assert np.isfinite(meshes[1].uvs).all()
    for ragged_or_complex in ([[0, 0], [1], [0, 1]], np.zeros((3, 2), complex)):
        with pytest.raises(ValueError, match="rows of 2 real numbers"):
            viewer.add_mesh(TRIANGLE, faces, uvs=ragged_or_complex)


def test_per_vertex_normals_and_uvs_draw_like_the_same_per_corner_ones() -> None:
    sphere = trimesh.creation.icosphere(subdivisions=2, radius=60.0)
    corners = sphere.faces.reshape(-1)
    rng = np.random.default_rng(3)
    normals, uvs = rng.normal(size=(len(sphere.vertices), 3)), rng.random((len(sphere.vertices), 2))
    pictures, stored_per_position = [], []
    for given in ((normals, uvs), (normals[corners], uvs[corners])):
        with marraztu.Viewer(size=SIZE, empty=True) as v:
            v.add_mesh(sphere.vertices, sphere.faces, normals=given[0], uvs=given[1]).press("0 1")
            pictures.append(np.asarray(v.render()))
            stored_per_position.append(v.scene.object.mesh.attributes_per_position)
    assert stored_per_position == [True, False]  # rows per vertex stay so: a sixth of the rows per corner
    assert np.array_equal(*pictures)
    assert (np.abs(pictures[0].astype(int) - [0, 0, 178]).sum(axis=2) > 30).mean() > 0.1, "not blank"


def test_rows_that_fit_vertices_and_corners_alike_must_say_which(viewer) -> None:
    soup = np.concatenate([TRIANGLE, TRIANGLE + 1.0])
    faces, normals = [[0, 1, 2], [5, 4, 3]], np.tile([0.0, 0.0, 1.0], (6, 1))
    with pytest.raises(ValueError, match="attributes_per_vertex"):
        viewer.add_mesh(soup, faces, normals=normals)
    viewer.add_mesh(soup, faces, normals=normals, attributes_per_vertex=False)
    viewer.add_mesh(soup, [[0, 1, 2], [3, 4, 5]], normals=normals)  # every vertex once, in order: the same
    with pytest.raises(ValueError, match="own uvs"):
        viewer.add_mesh(trimesh.Trimesh(TRIANGLE, [[0, 1, 2]], process=False), normals=normals[:3])


@pytest.mark.parametrize(("positions", "faces", "words"), [
    (np.full((3, 3), np.nan), [[0, 1, 2]], "finite"),
    (TRIANGLE * 1e39, [[0, 1, 2]], "float32"),
    (TRIANGLE * 1e20, [[0, 1, 2]], "cannot light"),
    (TRIANGLE * 1e-25, [[0, 1, 2]], "under 1e-18 the GPU's 32-bit numbers cannot light"),
    (TRIANGLE[:, :2], [[0, 1, 2]], "shape"),
    (TRIANGLE, [[0, 1, 2], [0, 1, 3]], r"face 1 refers to vertex 3, but there are 3 \(0-based\)"),
    # Past int64, named as given: a uint64 2**63 was "vertex -9223372036854775808", the others 2**62; and
    # with their face, which "1180591620717411303424 is no vertex index or face size" left out.
    (TRIANGLE, np.array([[0, 1, 2**63]], np.uint64), r"^face 0 refers to vertex 9223372036854775808, but there "
                                                     r"are 3 \(0-based\)$"),
    (TRIANGLE, [[0, 1, 2**63]], "^face 0 refers to vertex 9223372036854775808, "),  # no numpy warning on the terminal
    (TRIANGLE, [[0, 1, 2.0**70]], "^face 0 refers to vertex 1180591620717411303424, "),
    (TRIANGLE, [[0, 1, 2], [0, 1, 2**70]], "^face 1 refers to vertex 1180591620717411303424, "),
    (TRIANGLE, np.array([[0, 1, 2], [0, -2**70, 1]], object), "^face 1 refers to vertex -1180591620717411303424, "),
    (TRIANGLE, [[0, 1, 2], [0, 1, 2, 2**70]], "^face 1 refers to vertex 1180591620717411303424, "),
    (TRIANGLE, [[0, 1, 2**40]], "^face 0 refers to vertex 1099511627776, but there are 3"),
    (TRIANGLE, [[0, 1]], "at least 3"),
    (TRIANGLE, [[0, 1, 2], [0, 1], [1, 2]], "^face 1 has 2 vertices: a face needs at least 3$"),
    (TRIANGLE, [[0, 1, 2], [0]], "^face 1 has 1 vertex: a face needs at least 3$"),
    (TRIANGLE, "abc", "^faces must be rows of vertex indices, .*, not text$"),  # said "face 0 has 1 vertices"
    (TRIANGLE, b"abc", "not text$"),
    (TRIANGLE, np.empty((0, 3), int), "^a mesh needs at least one face$"),  # not "faces of at least 3 vertices"
    (TRIANGLE, [], "^a mesh needs at least one face$"),
    (TRIANGLE, np.array([[0, 1, 1.5]]), "whole numbers"),
    (TRIANGLE, [[0, 1, "2"]], "whole numbers"),
    (TRIANGLE + 1j, [[0, 1, 2]], "real numbers"),  # numpy would drop the imaginary part
    (TRIANGLE.astype(str), [[0, 1, 2]], "real numbers"),  # and read "60.0" as a number
    (np.array([["60.0", 0, 0], [0, 60, 0], [0, 0, 60]], dtype=object), [[0, 1, 2]], "real numbers"),
])
def test_bad_arrays_are_refused_where_they_enter(viewer, positions, faces, words: str) -> None:
    with pytest.raises(ValueError, match=words):
        viewer.add_mesh(positions, faces)


def test_masked_values_are_refused_not_drawn(viewer) -> None:
    """A masked array's hidden values were read as any others: the masked corner at 77 was drawn there."""
    shown = np.ma.masked_array(TRIANGLE, mask=np.eye(3, dtype=bool))
    for given in ("positions", "normals", "uvs", "colours", "faces"):
        arrays = {"positions": TRIANGLE, "faces": [[0, 1, 2]], given: shown[:, :2] if given == "uvs" else shown}
        if given == "faces":
            arrays["faces"] = np.ma.masked_array([[0, 1, 2]], mask=[[0, 0, 1]])
        with pytest.raises(ValueError, match=f"^{given} has masked values, which would be drawn as any others"):
            viewer.add_mesh(**arrays)
    assert viewer.add_mesh(np.ma.masked_array(TRIANGLE), [[0, 1, 2]]).scene.objects[-1].mesh.face_count == 1


def test_uvs_and_normals_past_32_bit_floats_are_refused_as_a_files_are(viewer) -> None:
    for given in ("uvs", "normals"):
        huge = np.full((3, 2 if given == "uvs" else 3), 1e300)
        with pytest.raises(ValueError, match=f"{given} must lie within 32-bit floats"):
            viewer.add_mesh(TRIANGLE, [[0, 1, 2]], **{given: huge})


def test_per_corner_values_of_the_wrong_shape_say_what_is_expected(viewer) -> None:
    with pytest.raises(ValueError, match=r"shape \(3, 2\)"):
        viewer.add_mesh(TRIANGLE, [[0, 1, 2]], uvs=np.zeros((3, 3)))
    with pytest.raises(ValueError, match="rows of RGB"):
        viewer.add_mesh(TRIANGLE, [[0, 1, 2]], colours=np.zeros((2, 3)))


@pytest.mark.parametrize("given", ["arrays", "trimesh"])
def test_the_scene_keeps_its_own_copy_of_the_positions(viewer, given: str) -> None:
    """Changing the caller's table afterwards does not move the model behind the renderer's back."""
    if given == "arrays":
        positions = TRIANGLE.copy()
        viewer.add_mesh(positions, [[0, 1, 2]])
    else:
        model = trimesh.Trimesh(TRIANGLE.copy(), [[0, 1, 2]], process=False)
        viewer.add_mesh(model)
        positions = model.vertices
    positions[:] = 0.0
    assert np.array_equal(viewer.scene.object.mesh.positions, TRIANGLE)


def test_numbers_held_as_objects_are_numbers(viewer) -> None:
    """As pandas gives them: floats in an object array."""
    viewer.add_mesh(TRIANGLE.astype(object), [[0, 1, 2]], uvs=np.zeros((3, 2)).astype(object))
    assert np.array_equal(viewer.scene.object.mesh.positions, TRIANGLE)


def test_a_name_cannot_move_the_cursor(viewer) -> None:
    viewer.add_mesh(TRIANGLE, [[0, 1, 2]], name="evil\x1b[2Jname\n")
    assert "\x1b" not in viewer.scene.object.name and "\n" not in viewer.scene.object.name


def test_a_name_as_long_as_a_files_with_its_control_characters_escaped_is_refused_at_once(viewer) -> None:
    """255 control characters were kept escaped, 1020 characters long, which the next call refused."""
    before = len(viewer.scene.objects)
    with pytest.raises(ValueError, match=rf"^name is 1020 characters long: at most {NAME_LIMIT} \(its control "):
        viewer.add_mesh(TRIANGLE, [[0, 1, 2]], name="\x01" * 255)
    assert len(viewer.scene.objects) == before and np.asarray(viewer.render()).any()


def test_a_model_files_name_is_kept_as_the_status_line_shows_it(viewer, tmp_path: Path) -> None:
    """A file named 'x<line break>y.obj' was kept as the name 'x', 'y' of two lines: the overlay drew '.'s
    message, 'framed x' and 'y', on two lines."""
    model = tmp_path / "x\ny.obj"
    model.write_bytes((ASSET_DIR / "examples" / "two_tone.obj").read_bytes())
    viewer.load(model)
    assert viewer.message.startswith("loaded x\\ny.obj as a new object: ")  # its message was two lines too
    assert viewer.scene.object.name == "x\\ny" and viewer.press(".").message == "framed x\\ny"
    assert np.asarray(viewer.render(overlay=True)).any()


@pytest.mark.parametrize("name", [b"abc", 5, object(), ["a"]])
def test_a_name_that_is_no_text_is_refused(viewer, name: object) -> None:
    """str() was taken of any name: b"abc" became "b'abc'", an object() "<object object at 0x7f...>", and
    one whose __str__ raised raised its own error. A scene file's name is text too."""
    before = len(viewer.scene.objects)
    with pytest.raises(TypeError, match=f"^name is a str, not {type(name).__name__}$"):
        viewer.add_mesh(TRIANGLE, [[0, 1, 2]], name=name)
    assert len(viewer.scene.objects) == before


@pytest.mark.parametrize("name", ["", "   "])
def test_a_blank_name_is_refused(viewer, name: str) -> None:
    """"" was taken as the object's name ("added : 3 vertices"); a scene file refuses it."""
    with pytest.raises(ValueError, match="^name is empty: give one with words in it, or None for the default$"):
        viewer.add_mesh(TRIANGLE, [[0, 1, 2]], name=name)


def test_bad_files_and_keys_raise_the_programs_errors(viewer, tmp_path: Path) -> None:
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    with pytest.raises(LoadError, match="bad.obj"):
        viewer.load(bad)
    with pytest.raises(KeyMapError):
        viewer.press("nosuchkey")
    with pytest.raises(ValueError, match="out of range"):
        marraztu.Viewer(size=(0, 10))


def test_the_probe_as_plain_numbers(viewer) -> None:
    viewer.press("0 1 F i")
    report = viewer.probe()
    found = scene_probe(viewer.scene)
    assert report is not None and found is not None
    assert dataclasses.asdict(report)["object"] == found.obj.name  # plain data all the way down
    assert (report.face, report.shading, len(report.vertices)) == (found.face, "gouraud", len(found.vertices))
    for mine, theirs in zip(report.vertices, found.vertices):
        assert mine.total == pytest.approx(tuple(theirs.shown))
        assert mine.colour == tuple(int(c) for c in (found.displayed(theirs)
                                                     if found.displayed(theirs) is not None else theirs.lit_bytes))
        assert len(mine.lights) == len(theirs.terms.lights)


def test_the_probe_gives_each_lights_l_and_h_as_the_equation_uses_them(viewer) -> None:
    """N.L and N.H come with the L and H they were taken with, so that a lesson can redo the sum."""
    viewer.press("0 1 2 3 F i")
    report = viewer.probe()
    assert report is not None
    eye = viewer.scene.eye_position()
    for vertex in report.vertices:
        normal, position = np.array(vertex.normal), np.array(vertex.world_position)
        to_eye = (eye - position) / np.linalg.norm(eye - position)
        for share in (share for share in vertex.lights if share.reaches):
            to_light, halfway = np.array(share.to_light), np.array(share.halfway)
            assert np.linalg.norm(to_light) == pytest.approx(1.0)
            assert share.n_dot_l == pytest.approx(max(float(normal @ to_light), 0.0))
            assert halfway == pytest.approx((to_light + to_eye) / np.linalg.norm(to_light + to_eye))


def test_a_lights_kind_is_found_where_its_repr_names_it(viewer) -> None:
    """A notebook prints LightKind.SPOT, as an Enum's member: that name did not exist, and a lesson that
    compared kind.name with 'SPOT' took the wrong branch without a word."""
    from marraztu.model.lights import LightKind

    kinds = {light.kind for light in viewer.scene.lights}
    assert len(kinds) == 3
    for kind in kinds:
        assert getattr(LightKind, repr(kind).removeprefix("LightKind.")) is kind
        assert kind.name == repr(kind).removeprefix("LightKind.").lower()


def test_frame_everything_shows_every_mesh_added_one_by_one() -> None:
    """Meshes added one at a time left the view on the first; `>` frames them all, as `.` frames one."""
    cube = trimesh.creation.box(extents=(10, 10, 10))
    with marraztu.Viewer(size=(200, 150), empty=True) as v:
        assert v.press(">").message == "nothing to frame"
        for offset, colour in (((0, 0, 0), (255, 0, 0)), ((60, 0, 0), (0, 255, 0)), ((-150, 40, -90), (255, 255, 255))):
            v.add_mesh(cube.vertices + offset, cube.faces, colours=np.tile(colour, (len(cube.vertices), 1)))

        def seen(picture: np.ndarray) -> set[tuple[bool, ...]]:  # the channels each model's pixels light
            return {tuple(pixel) for pixel in (picture > 0).reshape(-1, 3)} - {(False, False, True)}  # the sky

        red, green, white = (True, False, False), (False, True, False), (True, True, True)
        assert green not in seen(np.asarray(v.render()))  # framed by the first load, the second beside it
        picture = np.asarray(v.press(">").render())
        assert v.message == "framed everything shown (3 objects)"
        assert seen(picture) == {red, green, white}
        edges = np.concatenate([picture[0], picture[-1], picture[:, 0], picture[:, -1]])
        assert (edges == picture[0, 0]).all()  # none cut by the view's sides
        assert green not in seen(np.asarray(v.press("u").render()))  # u takes it back, as any view move


def test_frame_everything_counts_a_cameras_body_as_a_camera() -> None:
    with marraztu.Viewer(size=(120, 90)) as v:
        assert v.press(">").message == "framed everything shown (3 objects)"
        v.press("c").load(ASSET_DIR / "camera.obj").press("TAB")  # the new camera's body is drawn, seen from the first
        assert v.press(">").message == "framed everything shown (3 objects and 1 camera)"


def test_no_face_no_probe() -> None:
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        assert v.probe() is None


def test_esc_ends_a_sequence_and_the_next_one_is_pressed(viewer) -> None:
    viewer.press("x ESC x*20")
    once = np.asarray(viewer.render())
    viewer.press("x")
    assert not np.array_equal(np.asarray(viewer.render()), once)


def test_the_package_names_its_errors() -> None:
    assert (marraztu.ViewerError, marraztu.LoadError, marraztu.KeyMapError) == (ViewerError, LoadError, KeyMapError)
    assert all(hasattr(marraztu, name) for name in marraztu.__all__)


def test_the_repr_says_what_the_viewer_holds_without_drawing(monkeypatch: pytest.MonkeyPatch) -> None:
    """It was object.__repr__'s '<marraztu.frontends.api.Viewer object at 0x...>'."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        monkeypatch.setattr(v, "render", None)  # drawing would fail
        assert repr(v) == "<marraztu.Viewer 160x120, 0 objects, 1 camera, 4 lights, open>"
        v.add_mesh(TRIANGLE, [[0, 1, 2]])
    assert repr(v) == "<marraztu.Viewer 160x120, 1 object, 1 camera, 4 lights, closed>"


def test_the_scene_shows_what_it_holds_not_its_tables() -> None:
    """A notebook cell ending in `v.scene` printed 17 KB: every mesh's position, uv, normal and index
    tables, and the texture's pixels. A mesh says its name and size; the scene names its texture's file."""
    with marraztu.Viewer(size=SIZE) as v:
        obj = v.scene.objects[0]
        assert repr(obj.mesh) == f"<Mesh {obj.mesh.name!r}: {obj.mesh.summary()}>"
        shown = repr(v.scene)
        assert f"mesh=<Mesh {obj.mesh.name!r}: " in shown and "positions=array" not in shown
        assert "texture=array" not in shown and f"texture_path={v.scene.texture_path!r}" in shown
        still = repr(obj)
        v.press("x*50")  # each move is one more matrix in its history: the repr grew 300 bytes a key
        assert len(repr(obj)) < len(still) + 60 and "moves=50" in repr(obj) and "history" not in repr(obj)
        obj.picture = np.zeros((512, 512, 3), np.uint8)
        assert len(repr(obj)) < 1000, repr(obj)
        obj.history.append("abc")  # refused at the next call, but shown
        assert "model='abc'" in repr(obj)
        obj.history.append(np.zeros((1000, 1000)))  # the walk says it is no 4x4; the repr shows no million numbers
        assert len(repr(obj)) < 1000, repr(obj)


@pytest.mark.parametrize("history, shown", [([], "history=[]"), (None, "history=None"),
                                            ((np.eye(4),), "history=(array(")])
def test_the_repr_of_an_element_whose_history_was_emptied_by_hand_says_so(history: object, shown: str) -> None:
    """repr(obj), as a notebook shows a cell's last value, raised IndexError from the model property."""
    with marraztu.Viewer(size=SIZE) as v:
        for element in (v.scene.objects[0], v.scene.camera):
            element.history = history
            assert re.search(rf"^SceneObject\(name='{element.name}', .*, {re.escape(shown)}.*, selected_face=0, ",
                             repr(element))
        assert shown in repr(v.scene)
        v.scene.objects = None
        assert repr(v) == "<marraztu.Viewer 160x120, objects: NoneType, 1 camera, 4 lights, open>"


def test_close_releases_and_garbage_collection_too() -> None:
    v = marraztu.Viewer(size=SIZE)
    v.close()
    for call in (v.render, v.probe, lambda: v.press("x"), lambda: v.load("no-such.obj"),
                 lambda: v.add_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])):
        with pytest.raises(ViewerError, match="closed"):
            call()
    assert v._repr_png_() is None, "a notebook shows a closed viewer's text, not a traceback"
    assert v.scene.objects and v.size == SIZE, "what it held can still be read"
    closer = marraztu.Viewer(size=SIZE)._closer
    gc.collect()
    assert not closer.alive, "a viewer no one holds has closed its context"


@pytest.mark.parametrize("copied", [copy.copy, copy.deepcopy, pickle.dumps])
def test_a_viewer_is_not_copied(viewer, copied: Callable[[object], object]) -> None:
    """copy.copy shared the GL context, so closing the copy closed the original; deepcopy and pickle
    said "cannot pickle '_thread.RLock' object". The scene is what copies."""
    with pytest.raises(TypeError, match=r"^a Viewer holds a GL context: it is not copied or pickled; "):
        copied(viewer)
    assert viewer.render().size == SIZE
    assert copy.deepcopy(viewer.scene).objects[0].name == viewer.scene.objects[0].name


def test_a_viewer_collected_while_another_draws_leaves_it_drawing(monkeypatch: pytest.MonkeyPatch) -> None:
    """Garbage collection may run inside another viewer's GL calls: releasing a context there broke them
    ('cannot create vertex array' at the 29th of a loop of viewers held in cycles)."""
    from marraztu.frontends import screenshot as screenshot_module

    kept = marraztu.Viewer(size=SIZE)
    alone = np.asarray(kept.render())
    for _ in range(40):
        cycle = marraztu.Viewer(size=SIZE, empty=True)
        cycle.me = cycle  # only the cyclic collector frees it, whenever it runs
        cycle.render()
    drawn = screenshot_module.render
    monkeypatch.setattr(screenshot_module, "render",
                        lambda *args, **options: (gc.collect(), drawn(*args, **options))[1])
    assert np.array_equal(np.asarray(kept.render()), alone)
    kept.close()


def test_each_viewer_draws_in_its_own_context() -> None:
    """A notebook cell run again makes a second Viewer while the first is alive: each draws its own
    picture, and closing one leaves the other drawing."""
    first = marraztu.Viewer(size=SIZE)
    alone = np.asarray(first.render())
    second = marraztu.Viewer(size=SIZE)
    empty = marraztu.Viewer(size=SIZE, empty=True)
    assert np.array_equal(np.asarray(second.render()), alone)
    assert not np.array_equal(np.asarray(empty.render()), alone)
    assert np.array_equal(np.asarray(first.render()), alone)
    assert np.array_equal(np.asarray(first.render(overlay=True)), np.asarray(second.render(overlay=True)))
    second.close()
    empty.close()
    assert np.array_equal(np.asarray(first.render()), alone)
    first.close()


def test_viewers_made_one_after_another_keep_the_process_the_same_size() -> None:
    """moderngl frees nothing of a context it releases: each Viewer kept ~900 Python blocks (~60 KB, with
    Mesa's share) for good. A closed viewer's context now serves the next one."""
    def one_picture() -> None:
        with marraztu.Viewer(size=(16, 12)) as v:
            v.render()

    one_picture()
    gc.collect()
    before = sys.getallocatedblocks()
    for _ in range(20):
        one_picture()
    gc.collect()
    assert (sys.getallocatedblocks() - before) / 20 < 100


def _release_spare_contexts() -> None:
    """No context kept from the tests before: the next viewers' are counted from none."""
    from marraztu.frontends import api

    while api._spare_contexts:
        api._spare_contexts.pop().release()


def test_a_context_handed_on_draws_what_a_new_one_draws() -> None:
    """The next viewer draws in a closed one's context: whatever state that one left, the same pixels."""
    from marraztu.frontends import api

    _release_spare_contexts()
    with marraztu.Viewer(size=SIZE) as first:
        first.press("l b n F T 0 1 p")
        first.render(overlay=True)
    handed_on = marraztu.Viewer(size=SIZE)
    new = marraztu.Viewer(size=SIZE)  # the kept context is taken: this one is made
    for keys in ("", "0 1 F x*5"):
        assert np.array_equal(np.asarray(handed_on.press(keys).render()), np.asarray(new.press(keys).render()))
    handed_on.close()
    new.close()
    assert len(api._spare_contexts) == 2, "each context closed kept, up to the few a script keeps open at once"


def test_viewers_opened_together_figure_after_figure_make_no_new_context(monkeypatch: pytest.MonkeyPatch) -> None:
    """Two viewers per figure (a comparison), closed after it: only one context was kept, so the second
    was made and released each time, and moderngl never frees all of a released one (57 KB a figure)."""
    from marraztu.frontends import api

    _release_spare_contexts()
    made: list[object] = []
    real = api.create_offscreen_context
    monkeypatch.setattr(api, "create_offscreen_context", lambda: made.append(real()) or made[-1])
    for _ in range(api.MAX_SPARE_CONTEXTS + 2):  # figures
        opened = [marraztu.Viewer(size=SIZE, empty=True) for _ in range(api.MAX_SPARE_CONTEXTS)]
        for viewer in opened:
            viewer.close()
    assert len(made) <= api.MAX_SPARE_CONTEXTS and len(api._spare_contexts) == api.MAX_SPARE_CONTEXTS
    many = [marraztu.Viewer(size=SIZE, empty=True) for _ in range(api.MAX_SPARE_CONTEXTS + 2)]
    for viewer in many:
        viewer.close()
    assert len(api._spare_contexts) == api.MAX_SPARE_CONTEXTS, "no more kept than that, however many closed"


@pytest.mark.parametrize("size", [(float("inf"), 5), (True, True), (1.9, 2.7), "12", ("5", "5"), (10**5000, 5),
                                  (5,), (5, 5, 5), None, b"\x05\x05", {3: 0, 4: 0}, (0, 10),
                                  (-(10**30), 10)])
def test_a_size_is_two_whole_numbers_in_range(size: object) -> None:
    with pytest.raises(ValueError, match="size") as caught:
        marraztu.Viewer(size=size)  # type: ignore[arg-type]
    assert len(str(caught.value)) < 200


def test_a_size_of_numpy_integers_is_a_size(viewer) -> None:
    assert viewer.render(size=(np.int64(20), np.int32(10))).size == (20, 10)


@pytest.mark.parametrize("keys", [b"x", ["x"], None, 5])
def test_keys_are_text(viewer, keys: object) -> None:
    with pytest.raises(TypeError, match="str"):
        viewer.press(keys)  # type: ignore[arg-type]


def test_a_number_past_a_doubles_range_is_refused(viewer) -> None:
    with pytest.raises(ValueError, match="real numbers"):
        viewer.add_mesh([[10**400, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])


def test_too_many_rows_are_refused_before_any_pass_over_them(viewer, monkeypatch) -> None:
    """A broadcast view makes any count of rows without memory: they are counted first."""
    from marraztu.frontends import api
    from marraztu.model import build

    monkeypatch.setattr(api, "INDEX_LIMIT", 1000)
    monkeypatch.setattr(build, "INDEX_LIMIT", 1000)
    monkeypatch.setattr(api, "holds_in_float32", lambda table: pytest.fail("looked at every row"))
    with pytest.raises(ValueError, match="fewer than 1000 positions"):
        viewer.add_mesh(np.broadcast_to(np.zeros(3), (5000, 3)), [[0, 1, 2]])
    monkeypatch.undo()
    monkeypatch.setattr(build, "INDEX_LIMIT", 1000)
    monkeypatch.setattr(build, "whole_numbers", lambda values: pytest.fail("copied every corner"))
    with pytest.raises(ValueError, match="fewer than 1000"):
        viewer.add_mesh(TRIANGLE, np.broadcast_to(np.arange(3), (5000, 3)))


def test_arguments_that_contradict_or_only_look_right_are_refused() -> None:
    with pytest.raises(ValueError, match="give one"):
        marraztu.Viewer(size=SIZE, scene="nowhere.toml", empty=True)
    with pytest.raises(ValueError, match="empty is True or False"):
        marraztu.Viewer(size=SIZE, empty="yes")  # type: ignore[arg-type]
    with marraztu.Viewer(size=SIZE, empty=np.True_) as v:
        for overlay in ("yes", 1, None, ""):  # render(overlay="no") drew the overlay
            with pytest.raises(ValueError, match=f"^overlay is True or False, not {overlay!r}$"):
                v.render(overlay=overlay)  # type: ignore[arg-type]
        v.render(overlay=np.False_)
        with pytest.raises(ValueError, match="attributes_per_vertex is True, False or None"):
            v.add_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]], attributes_per_vertex="no")  # type: ignore
        for faces, said in ([[0, 1, 2, 3]], "rows of 3 real numbers"), ([0, 1, 2], "rows of 3"), \
                           ([[0, 1, 2.5]], "whole numbers"), ([[0, 1], [2]], "not a table of numbers"):
            with pytest.raises(ValueError, match=said):  # taken as a trimesh's: checked as its arrays are
                v.add_mesh(SimpleNamespace(vertices=np.eye(4, 3), faces=faces))
        assert v.scene.objects == []


def test_add_mesh_says_its_notes_as_a_load_does() -> None:
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [2, 0, 0]], [[0, 1, 2], [0, 1, 3]])
        assert v.message.startswith("added mesh: 4 vertices, 2 faces (") and "zero-area" in v.message


def test_faces_and_colours_in_other_shapes_are_read_or_refused_in_words(viewer) -> None:
    square = [[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]]
    for faces in (np.array([0, 1, 2]), np.array([[[0, 1, 2]]]), 5):
        with pytest.raises(ValueError, match=r"faces must be rows of vertex indices, \(F, k\), or a list of polygons"):
            viewer.add_mesh(square, faces)
    viewer.add_mesh(square, np.array([[0, 1, 2], [0, 2, 3]], dtype=object),  # as pandas gives them
                    colours=np.array([[255, 0, 0]] * 4, dtype=object))
    assert viewer.scene.object.mesh.face_count == 2 and (viewer.scene.object.mesh.vertex_colours == [255, 0, 0]).all()
    with pytest.raises(ValueError, match="vertex colours must be 4 rows of RGB or RGBA"):
        viewer.add_mesh(square, [[0, 1, 2]], colours=[[1, 0], [0, 0, 0], [1, 1, 1], [0, 0, 0]])
    with pytest.raises(ValueError, match=r"^float vertex colours .* 0\.\.1; for 0\.\.255, give bytes .* by 255$"):
        viewer.add_mesh(square, [[0, 1, 2]], colours=np.full((4, 3), 200.0))


def test_a_scene_changed_by_hand_keeps_its_selection_in_range() -> None:
    """The scene is the caller's to change: an object removed by hand left the selection past the list's
    end, and every later call raised an IndexError."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(TRIANGLE, [[0, 1, 2]], name="one").add_mesh(TRIANGLE, [[0, 1, 2]], name="two")
        v.scene.objects.pop()
        assert v.probe().object == "one" and np.asarray(v.render()).any()
        v.scene.objects.clear()
        assert v.probe() is None and v.press("x").scene.object is None
        v.scene.lights.clear()
        with pytest.raises(ValueError, match="needs a camera and a light"):
            v.render(overlay=True)


def test_a_negative_selection_counts_from_the_end_as_pythons_indices_do() -> None:
    """selected_object = -1 selected the first object, where a Python user means the last."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        for name in ("one", "two", "three"):
            v.add_mesh(TRIANGLE, [[0, 1, 2]], name=name)
        v.scene.selected_object, v.scene.selected_light = -1, -2
        assert v.probe().object == "three"
        assert v.scene.selected_light == len(v.scene.lights) - 2
        v.scene.selected_object = -99  # past the start: the first, as one past the end is the last
        assert v.probe().object == "one"


@pytest.mark.parametrize("attribute, value", [("selected_object", 1.5), ("selected_camera", "0"),
                                              ("selected_light", True), ("selected_object", None)])
def test_a_selection_that_is_no_whole_number_is_refused_in_one_line(attribute: str, value: object) -> None:
    with marraztu.Viewer(size=SIZE) as v:
        setattr(v.scene, attribute, value)
        with pytest.raises(ValueError, match=rf"^the scene's {attribute} must be a whole number, not "):
            v.render()


BAD_MODELS = [
    (np.diag([1.0, 0.0, 1.0, 1.0]), "has no inverse"),  # a squash onto a plane, as a lab might try
    (np.eye(3), r"4x4, not \(3, 3\)"),
    (np.full((4, 4), np.nan), "finite"),
    ("abc", "4x4 of numbers"),
    (np.eye(4).astype(str), "4x4 of numbers"),  # numpy reads text as numbers: einsum's 'invalid data type'
    (np.array([[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0.002, 0, 1]]),  # drew, lit as if affine
     "must end in the row 0 0 0 1 \\(an affine transform\\), not 0 0.002 0 1"),
]
# Taken by obj.model = M, which makes an array of them, but not put on a history by hand: the renderer
# slices the matrix (a list raised 'list indices must be integers', an np.matrix 'could not broadcast').
ON_A_HISTORY_BY_HAND = BAD_MODELS + [
    (np.eye(4).tolist(), "must be a numpy array \\(obj.model = M makes one of any 4x4\\), not list"),
    (np.eye(4).view(np.matrix), "must be a numpy array .*, not matrix"),  # made without its warning
]


@pytest.mark.parametrize("model, words", ON_A_HISTORY_BY_HAND)
def test_a_model_matrix_set_by_hand_that_cannot_be_drawn_is_refused_in_one_line(model, words: str) -> None:
    """The renderer inverts every model matrix (the near plane, the normals): a singular one pushed by
    hand raised numpy's LinAlgError from deep in the renderer, a 3x3 one a ValueError about sequences."""
    with marraztu.Viewer(size=SIZE) as v:
        v.scene.objects[0].history.append(model)
        for call in (v.render, lambda: v.press("x"), v.probe):
            with pytest.raises(ValueError, match=f"^{v.scene.objects[0].name}'s model matrix .*{words}"):
                call()
        v.scene.objects[0].history.pop()
        v.scene.cameras[0].history.append(model)
        with pytest.raises(ValueError, match=f"^{v.scene.cameras[0].name}'s model matrix"):
            v.render()
        v.scene.cameras[0].history.pop()
        assert np.asarray(v.render()).any()


def test_a_model_matrix_set_by_hand_is_a_move_that_u_undoes() -> None:
    """obj.model = M raised 'property has no setter' (only history.append, hinted at in a docstring,
    placed an object); it is a move, as a key's is: drawn as the key's own matrix is, and undone by u."""
    with marraztu.Viewer(size=SIZE) as v:
        start, obj = np.asarray(v.render()), v.scene.objects[0]
        keyed = np.asarray(v.press("t x").render())
        moved = obj.model
        v.press("u")
        obj.model = moved.tolist()  # any 4x4 of numbers
        assert obj.model.dtype == np.float64 and len(obj.history) == 2
        np.testing.assert_array_equal(np.asarray(v.render()), keyed)
        np.testing.assert_array_equal(np.asarray(v.press("u").render()), start)
        for bad, words in BAD_MODELS:  # refused as it is set, the object's matrix as it was
            with pytest.raises(ValueError, match=f"^{obj.name}'s model matrix .*{words}"):
                obj.model = bad
        assert len(obj.history) == 1


@pytest.mark.parametrize("scale", [(10.0, 10.0, 10.0), (1.0, 1.0, 30.0), (0.01, 0.01, 0.01)])
def test_dot_frames_a_model_scaled_by_its_matrix_as_one_made_that_size(scale: tuple[float, float, float]) -> None:
    """The framing sphere's radius was measured in the mesh's own units: a cube scaled 10 times by a
    matrix set by hand was framed from 1.56 units, inside it, as 'framed box'."""
    cube = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)])
    faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    eyes = []
    for by_matrix in (True, False):
        with marraztu.Viewer(size=SIZE, empty=True) as v:
            v.add_mesh(cube if by_matrix else cube * scale, faces, name="box")
            box = v.scene.objects[-1]
            if by_matrix:
                box.model = np.diag([*scale, 1.0])
            v.press(".")
            assert v.scene.around_eye([box]) == [False]
            eyes.append(v.scene.eye_position())
    np.testing.assert_allclose(eyes[0], eyes[1])


def moved_along_z(distance: float) -> np.ndarray:
    matrix = np.eye(4)
    matrix[2, 3] = distance
    return matrix


@pytest.mark.parametrize("which, matrix, words", [
    ("objects", np.diag([1e17, 1e17, 1e17, 1.0]), "a coordinate reaches .*: past 1e\\+18"),
    ("objects", np.diag([1e-30, 1e-30, 1e-30, 1.0]), "the model is .* across: under 1e-18"),
    ("cameras", moved_along_z(1e31), "a coordinate reaches 1e\\+31"),
    # in three digits this read 'reaches 5e+18: past 5e+18', as if 5e18 itself were refused (it is drawn)
    ("cameras", moved_along_z(5.0000001e18), "a coordinate reaches 5\\.0000001e\\+18: past 5e\\+18"),
])
def test_an_element_placed_by_hand_past_what_the_gpu_lights_is_refused(which: str, matrix: np.ndarray,
                                                                       words: str) -> None:
    """A file past 1e18 or under 1e-18 across is refused, but a matrix set by hand could scale or move
    one there: a camera at 1e31 then made p's half height 1.5e31, which the next call refused, and numpy
    printed 'overflow encountered in cast' for each picture."""
    with marraztu.Viewer(size=SIZE) as v:
        element = getattr(v.scene, which)[0]
        element.model = matrix
        with pytest.raises(ValueError, match=f"^{element.name} as its model matrix places it: {words}"):
            v.render()
        element.history.pop()
        assert np.asarray(v.render()).any()


def test_a_scene_that_can_be_drawn_is_checked_in_stacked_arrays_not_element_by_element(monkeypatch) -> None:
    """Every call checks the whole scene (it may have been changed by hand): element by element, a press
    of TAB on a scene of 4,000 objects took 190 ms, 47 µs an object, where the screenshot command's
    took none. The walk that names the first bad value runs only where there is one."""
    from marraztu.model import scene as scene_module

    walked = {"models": 0, "triples": 0}
    model_refusal, triple_refusal = scene_module.model_refusal, scene_module.triple_refusal

    def counting_model_refusal(model: object) -> str | None:
        walked["models"] += 1
        return model_refusal(model)

    def counting_triple_refusal(value: object, names: str) -> str | None:
        walked["triples"] += 1
        return triple_refusal(value, names)

    monkeypatch.setattr(scene_module, "model_refusal", counting_model_refusal)
    monkeypatch.setattr(scene_module, "triple_refusal", counting_triple_refusal)
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        for index in range(50):
            v.add_mesh(TRIANGLE + [index, 0, 0], [[0, 1, 2]], name=f"t{index}")
        v.press("TAB x c y").probe()
        assert np.asarray(v.render()).any()
        assert walked == {"models": 0, "triples": 0}
        v.scene.objects[7].history.append(np.diag([1.0, 0.0, 1.0, 1.0]))
        with pytest.raises(ValueError, match="^t7's model matrix has no inverse"):
            v.press("TAB")
        assert walked["models"] == 8  # the walk stops at the first refusal


def test_the_check_of_a_scene_that_can_be_drawn_makes_four_calls_an_element(tmp_path: Path) -> None:
    """Each call's check of the whole scene gathers every element's values in one pass for the stacked
    arrays, where it made a pass, or a generator, for the materials, the pictures, the models...: a
    loop of add_mesh calls checks the scene on each. Textured, many-material and shared-material
    elements among them, and never the walk's calls."""
    (tmp_path / "two.mtl").write_text("newmtl red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\n")
    (tmp_path / "two.obj").write_text("mtllib two.mtl\nv 0 0 0\nv 9 0 0\nv 0 9 0\nv 9 9 0\n"
                                      "usemtl red\nf 1 2 3\nusemtl blue\nf 2 4 3\n")
    calls = []
    for count in (20, 40):
        made: collections.Counter[str] = collections.Counter()
        with marraztu.Viewer(size=SIZE, empty=True) as v:
            for index in range(count):
                if index % 3 == 0:
                    v.add_mesh(SQUARE + [index, 0.0, 0.0], [[0, 1, 2, 3]], uvs=SQUARE_UVS, texture=FOUR)
                elif index % 3 == 1:
                    v.load(tmp_path / "two.obj")
                else:  # drawn with the first one's material, the same object
                    v.add_mesh(TRIANGLE + [index, 0.0, 0.0], [[0, 1, 2]]).scene.object.material = \
                        v.scene.objects[0].material
            assert sum(len(obj.part_materials) == 2 for obj in v.scene.objects) == len(range(1, count, 3))
            profile = sys.getprofile()
            sys.setprofile(lambda frame, event, _: made.update([frame.f_code.co_name]) if event == "call" else None)
            try:
                v.scene.check_by_hand()
            finally:
                sys.setprofile(profile)
        assert not {"_refusals", "model_refusal", "triple_refusal"} & set(made)
        calls.append(sum(made.values()) - made["picture_refusal"])
    assert (calls[1] - calls[0]) / 20 <= 4


@pytest.mark.parametrize("model, words", ON_A_HISTORY_BY_HAND)
def test_a_matrix_down_the_undo_history_that_cannot_be_drawn_is_refused_before_u_makes_it_current(
        model, words: str) -> None:
    """Only the current matrix is checked at each call: a singular one pushed under a good one was made
    current by `u` (a 3x3 one raised matmul's error from x), and from then on every call, press("u")
    too, was refused. `u` refuses it, leaving the good one current."""
    with marraztu.Viewer(size=SIZE) as v:
        obj = v.scene.objects[0]
        obj.history += [model, np.eye(4)]
        with pytest.raises(ValueError, match=rf"^{obj.name}'s history\[-2\], which u undoes to, .*{words}"):
            v.press("u x")
        assert obj.history[-1] is not model and np.asarray(v.render()).any()
        del obj.history[-2]
        assert np.asarray(v.press("u x").render()).any()


@pytest.mark.parametrize("entry_of, words", [
    (lambda matrix: 1, r"must be a pair \(its model matrix, the half height before or None\), not 1$"),
    (lambda matrix: "on top", r"must be a pair .*, not 'on top'$"),
    (lambda matrix: (matrix, "big"), r"must hold None or a half height, a finite number from 1e-30 to 1e\+30, "
                                     r"not 'big'$"),
    (lambda matrix: (matrix, -5.0), r"must hold None or a half height, .* not -5\.0$"),
])
def test_a_view_size_set_by_hand_that_u_cannot_give_back_is_refused_before_u_gives_it(entry_of, words: str) -> None:
    """A view_sizes entry set by hand was read as `u` gave it back: 1 raised "'int' object is not
    subscriptable", a text numpy's ufunc error, and -5.0 became the view's size, which the next call
    refused in the words of modes.parallel_half_height. `u` refuses it, the press undone."""
    with marraztu.Viewer(size=SIZE) as v:
        v.press("p .")
        camera, size = v.scene.camera, v.scene.modes.parallel_half_height
        matrix = camera.history[-1]
        camera.view_sizes[-1] = entry_of(matrix)
        with pytest.raises(ValueError, match=rf"^camera's view_sizes\[-1\], which u gives back, {words}"):
            v.press("u")
        assert camera.history[-1] is matrix and v.scene.modes.parallel_half_height == size


@pytest.mark.parametrize("change, words", [
    (lambda s: setattr(s.lights[1], "intensity", 200), r"the bulb's intensity must be 3 numbers \(R, G, B\)"),
    (lambda s: setattr(s.lights[1], "intensity", "white"), "the bulb's intensity must be 3 numbers"),
    (lambda s: setattr(s.lights[1], "position", [1.0, 2.0]), r"the bulb's position must be 3 numbers \(x, y, z\)"),
    (lambda s: setattr(s.lights[1], "position", [np.nan, 0, 0]), "the bulb's position must be 3 finite numbers"),
    (lambda s: setattr(s.lights[0], "direction", [0, 1]), "the sun's direction must be 3 numbers"),
    # a spotlight's is held to the range + and - keep it in, as a scene file's (120 was drawn, and - jumped to 89)
    (lambda s: setattr(s.lights[3], "aperture_deg", -30.0),
     r"the camera spotlight's aperture_deg must be a number of degrees from 1 to 89, not -30\.0$"),
    (lambda s: setattr(s.lights[2], "aperture_deg", 120.0), "the object spotlight's aperture_deg must be .*, not 120"),
    # the probe tests the angle, the shader its cosine: past 0..180 they disagree (-30 lit a pixel the probe left dark)
    (lambda s: setattr(s.lights[0], "aperture_deg", -30.0),
     r"the sun's aperture_deg must be a number of degrees from 0 to 180, not -30\.0$"),
    (lambda s: setattr(s.lights[2], "aperture_deg", 400), "the object spotlight's aperture_deg must be .*, not 400$"),
    (lambda s: setattr(s.lights[3], "aperture_deg", float("nan")), "the camera spotlight's aperture_deg must be "),
    (lambda s: setattr(s.lights[3], "aperture_deg", "wide"), "the camera spotlight's aperture_deg must be .*'wide'$"),
    # text that float() and numpy read as numbers ('90') passed, then raised "Unknown format code 'g'" or a
    # UFuncTypeError from the messages, the probe or the renderer
    (lambda s: setattr(s.lights[2], "aperture_deg", "90"), "the object spotlight's aperture_deg must be .*'90'$"),
    (lambda s: setattr(s.lights[1], "position", ("1", "2", "3")), r"the bulb's position must be 3 numbers \(x, y, z\)"),
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, kd=("1", "0", "0"))),
     "'s material kd must be 3 numbers"),
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, ns="5")),
     "'s material ns must be a number greater than 0 .*, not '5'$"),
    # "yes" drew the light on as a truthy word would; "off" too
    (lambda s: setattr(s.lights[1], "on", "off"), r"^the bulb's on must be True or False, not 'off'$"),
    (lambda s: setattr(s, "ambient", 50), "the scene's ambient must be 3 numbers"),
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, kd=(1, 0))),
     "'s material kd must be 3 numbers"),
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, ks="red")),
     "'s material ks must be 3 numbers"),
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, ns=float("nan"))),
     "'s material ns must be a number greater than 0 and within 32-bit floats"),
    # a negative Ns drew every face's highlight inside out; one past float32 overflowed in the shader
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, ns=-5)),
     "'s material ns must be a number greater than 0 .*, not -5$"),
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, ns=1e300)),
     "'s material ns must be a number greater than 0 .*, not 1e\\+300$"),
    # numpy drops the imaginary part with a warning: the colour drawn is not the one given
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, kd=np.array([1j, 0, 0]))),
     "'s material kd must be 3 numbers"),
    (lambda s: setattr(s, "message", 5), r"^the scene's message must be str, not 5$"),
    # AttributeError: 'dict' object has no attribute 'ka', and TypeError: Value after * must be an iterable:
    (lambda s: setattr(s.objects[0], "material", {"kd": (1, 0, 0)}), r"'s material must be a Material \(.*not dict$"),
    (lambda s: setattr(s.objects[0], "material", None), "'s material must be a Material .*not NoneType$"),
    # PageDown and --watch give it back through the part materials: a dict raised AttributeError there
    (lambda s: setattr(s.objects[0], "given_material", {"kd": (1, 0, 0)}),
     "'s given_material must be None or a Material, not dict$"),
    (lambda s: setattr(s.objects[0], "part_materials", s.objects[0].material),
     r"'s part_materials must be a tuple of Materials, one per material of its file \(\d+\), not Material$"),
    (lambda s: setattr(s.objects[0], "part_materials", ({"kd": 1},)),
     r"'s part_materials must be .*\(\d+\), not a tuple holding a dict$"),
    # finite in float64, past float32 where the GPU reads them: a bulb at 1e20 lit nothing on the GPU while
    # the probe lit the face, one at 1e300 made the far plane infinite (nothing drawn); an intensity of
    # 1e39 drew another picture than 3e38 with the same probe
    (lambda s: setattr(s.lights[1], "position", np.array([0.0, 1e300, 0.0])),
     r"^the bulb's position must be 3 numbers within ±5e\+18: past it the GPU's 32-bit numbers "
     r"cannot light from there, "
     r"not array\(\[0\.e\+000, 1\.e\+300, 0\.e\+000\]\)$"),
    (lambda s: setattr(s.lights[1], "position", [0.0, 0.0, -1e20]),
     r"^the bulb's position must be 3 numbers within ±5e\+18"),
    (lambda s: setattr(s.lights[0], "position", [0.0, 0.0, 1e39]),  # only its marker is drawn there
     r"^the sun's position must be 3 numbers within 32-bit floats"),
    (lambda s: setattr(s.lights[1], "intensity", np.array([1e300, 0.0, 0.0])),
     r"^the bulb's intensity must be 3 numbers from 0 to 3\.4e38, where the GPU's 32-bit floats end, not "),
    (lambda s: setattr(s.lights[0], "intensity", [1e39, 1, 1]),
     r"^the sun's intensity must be 3 numbers from 0 to 3\.4e38"),
    (lambda s: setattr(s, "ambient", (0, -1e39, 0)), r"^the scene's ambient must be 3 numbers from 0 to 3\.4e38"),
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, kd=(1e39, 0, 0))),
     r"'s material kd must be 3 numbers between 0 and 1, not \(1e\+39, 0, 0\)$"),
    # a light gives no less than none: the bulb's -100 took light from every face it reached, the
    # scene's ambient -1 from every face; a scene file has no lights to compare with
    (lambda s: setattr(s.lights[1], "intensity", (-100, 0, 0)),
     r"^the bulb's intensity must be 3 numbers from 0 to 3\.4e38, where the GPU's 32-bit floats end, "
     r"not \(-100, 0, 0\)$"),
    (lambda s: setattr(s, "ambient", np.array([0.0, -1.0, 0.0])), r"^the scene's ambient must be 3 numbers from 0 to "),
    # a material's colours are shares of each light (SPEC 4), as a scene file, MTL and glTF hold them:
    # kd 2 drew a face brighter than its light, and passed here where the scene file refused it
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, kd=(2, 0, 0))),
     r"'s material kd must be 3 numbers between 0 and 1, not \(2, 0, 0\)$"),
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, ka=(-1, 0, 0))),
     r"'s material ka must be 3 numbers between 0 and 1, not \(-1, 0, 0\)$"),
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, ks=(0, 0, 1.001))),
     r"'s material ks must be 3 numbers between 0 and 1, not \(0, 0, 1\.001\)$"),
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, rgb=(0, 5, 0))),
     r"'s material rgb must be 3 numbers between 0 and 1, not \(0, 5, 0\)$"),
    (lambda s: setattr(s.objects[0], "material", dataclasses.replace(s.objects[0].material, rgb=(0, 1))),
     r"'s material rgb must be 3 numbers \(R, G, B\), not \(0, 1\)$"),
    (lambda s: setattr(s.lights[0], "direction", [1e300, 1e300, 0.0]),
     r"^the sun's direction must be 3 numbers within 32-bit"),
    # the sun then lit no face and put a highlight where the eye looks from (H = normalize(0 + V))
    (lambda s: setattr(s.lights[0], "direction", np.zeros(3)),
     r"^the sun's direction must point some way: at least 1e-150 long, not array\(\[0\., 0\., 0\.\]\)$"),
    (lambda s: setattr(s.lights[0], "direction", (1e-200, 0, 0)),  # its square rounds to 0
     r"^the sun's direction must point some way"),
    (lambda s: setattr(s.lights[2], "direction", [0, 0, 0]), r"^the object spotlight's direction must point some way"),
])
def test_lights_and_materials_set_by_hand_that_cannot_be_drawn_are_refused_in_one_line(change, words: str) -> None:
    """A light's intensity set to 200, or a kd of two numbers, raised numpy's broadcasting errors or
    moderngl's 'pack expected 3 items for packing (got 2)' from deep in the renderer."""
    with marraztu.Viewer(size=SIZE) as v:
        v.press("0 1 2 3")
        change(v.scene)
        for call in (v.render, lambda: v.press("x"), v.probe):
            with pytest.raises(ValueError, match=words):
                call()


def test_lights_fitted_to_the_largest_models_that_are_drawn_are_taken() -> None:
    """A light's place was refused past 1e18, as a model's coordinate is: a cube 3e17 wide, drawn, had the
    bulb fitted to 2e18 and the sun to 4e18 (200 and 400 of the scene's unit, 1e16), and its next call
    refused the scene the program had made."""
    half = 1.5e17
    cube = np.array([[x, y, z] for x in (-half, half) for y in (-half, half) for z in (-half, half)])
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(cube, [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]])
        assert v.scene.lights[0].position[0] == 4e18 and v.scene.lights[1].position[1] == 2e18
        assert np.asarray(v.press("0 1").render()).any()


def test_the_bulb_moved_by_keys_stops_where_the_gpu_can_still_light_from() -> None:
    """t y*70 took the bulb of a scene 3e17 wide to 5.5e18, past LIGHT_REACH: every call after, u too,
    refused the scene the keys had made."""
    half = 1.5e17
    cube = np.array([[x, y, z] for x in (-half, half) for y in (-half, half) for z in (-half, half)])
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(cube, [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]])
        bulb = v.scene.lights[1]
        v.press("1 c c TAB t y*70")
        assert v.scene.light is bulb and LIGHT_REACH - 5e16 < bulb.position[1] <= LIGHT_REACH, bulb.position
        assert v.message == f"the bulb stops here: past {LIGHT_REACH:.0e} from the origin the GPU's 32-bit numbers " \
                            "cannot light from it"
        assert np.asarray(v.render()).any()
        v.press("Y u")  # back toward the origin, and back again
        assert bulb.position[1] <= LIGHT_REACH


def test_lights_and_materials_at_the_edge_of_what_the_gpu_reads_are_drawn_without_the_walk(monkeypatch) -> None:
    """The stacked check and the walk draw the same line: what the one passes, the other is not asked."""
    from marraztu.model import scene as scene_module

    walked: list[object] = []
    monkeypatch.setattr(scene_module, "reach_refusal", lambda value, kind: walked.append(value))
    with marraztu.Viewer(size=SIZE) as v:
        v.press("0 1")
        v.scene.lights[1].position, v.scene.lights[1].intensity = (0.0, 0.0, -LIGHT_REACH), [FLOAT32_MAX] * 3
        v.scene.lights[0].position = (FLOAT32_MAX, 0.0, 0.0)
        v.scene.lights[0].direction = np.array([0.0, -1e-150, 0.0])
        v.scene.lights[0].intensity = np.zeros(3)
        v.scene.objects[0].material = dataclasses.replace(v.scene.objects[0].material, ks=(1.0, 0, 0), ka=(0, 0, 0),
                                                          rgb=(0.0, 1.0, 0.0))
        v.scene.ambient = (0.0, 0, FLOAT32_MAX)
        assert np.asarray(v.render()).any() and v.probe() is not None
        assert walked == []


@pytest.mark.parametrize("name, value, words", [
    ("shading", "gouraud", r"modes\.shading must be a Shading \(Shading\.FLAT, Shading\.GOURAUD, Shading\.PHONG"),
    ("projection", "parallel", r"modes\.projection must be a Projection \(Projection\.PERSPECTIVE, "),
    ("culling", "on", r"modes\.culling must be True or False, not 'on'$"),
    ("texture", None, r"modes\.texture must be True or False, not None$"),
    ("normals", np.True_, r"modes\.normals must be True or False, not np\.True_$"),
    ("term_view", "ambient", r"modes\.term_view must be a TermView \(TermView\.EVERYTHING, .*not 'ambient'$"),
    ("parallel_half_height", 0.0, r"modes\.parallel_half_height must be a finite number from 1e-30 to 1e\+30, "
                                  r"not 0\.0$"),
    ("parallel_half_height", float("nan"), r"modes\.parallel_half_height must be a finite number from "),
    ("parallel_half_height", 1e-300, r"modes\.parallel_half_height must be .*, not 1e-300$"),
    ("parallel_half_height", 3e38, r"modes\.parallel_half_height must be .*, not 3e\+38$"),
    ("parallel_half_height", "150", r"modes\.parallel_half_height must be .*, not '150'$"),
])
def test_modes_set_by_hand_that_cannot_be_drawn_are_refused_in_one_line(name: str, value: object, words: str) -> None:
    """`scene.modes.shading = "gouraud"`, as the repr's <Shading.FLAT: 'flat'> invites, raised 'str'
    object has no attribute 'name' from the renderer, culling = "on" struct's 'required argument is not
    an integer', and and a half height of 0 a ZeroDivisionError."""
    with marraztu.Viewer(size=SIZE) as v:
        setattr(v.scene.modes, name, value)
        for call in (v.render, lambda: v.press("x"), v.probe):
            with pytest.raises(ValueError, match=f"^the scene's {words}"):
                call()
        setattr(v.scene.modes, name, getattr(type(v.scene.modes)(), name))
        assert np.asarray(v.render()).any()


@pytest.mark.parametrize("change, words", [
    (lambda s: setattr(s.objects[0], "picture", Image.new("RGB", (4, 4))), "'s picture must be .*, not Image$"),
    (lambda s: setattr(s.objects[0], "picture", [[1, 2, 3]]), "'s picture must be .*, not list$"),
    (lambda s: setattr(s.objects[0], "picture", np.zeros((4, 4, 3))), "'s picture must be .*, not float64 of shape"),
    (lambda s: setattr(s.objects[0], "picture", np.zeros(5, np.uint8)),
     r"'s picture must be .*, not uint8 of shape \(5,\)$"),
    (lambda s: setattr(s, "texture", np.zeros((4, 4, 4), np.uint8)), r"^the scene's texture must be .*\(4, 4, 4\)$"),
])
def test_pictures_set_by_hand_that_cannot_be_drawn_are_refused_in_one_line(change, words: str) -> None:
    """obj.picture = Image.open(...), as add_mesh's texture= invites, raised 'Image' object has no attribute
    'shape' from the renderer, and from repr(obj) too; a float picture was drawn black without a word."""
    with marraztu.Viewer(size=SIZE) as v:
        change(v.scene)
        assert "picture=" in repr(v.scene.objects[0]) or v.scene.objects[0].picture is None
        for call in (v.render, lambda: v.press("x"), v.probe):
            with pytest.raises(ValueError, match=words):
                call()
        v.scene.objects[0].picture, v.scene.texture = None, None
        assert np.asarray(v.render()).any()


def test_the_status_of_a_mode_set_by_hand_that_cannot_be_drawn_is_refused_as_a_render_is() -> None:
    """v.status raised 'str' object has no attribute 'value' where render said what was wrong."""
    with marraztu.Viewer(size=SIZE) as v:
        v.scene.modes.shading = "gouraud"
        with pytest.raises(ValueError, match=r"^the scene's modes\.shading must be a Shading"):
            v.status  # noqa: B018 - the property is the call


def test_modes_set_by_hand_draw_as_their_keys_do() -> None:
    from marraztu.model.scene import Projection, Shading

    with marraztu.Viewer(size=SIZE) as by_key, marraztu.Viewer(size=SIZE) as by_hand:
        by_key.press("0 1 F p b")
        by_hand.press("0 1").scene.modes.shading = Shading.GOURAUD
        by_hand.scene.modes.projection, by_hand.scene.modes.culling = Projection.PARALLEL, True
        by_hand.scene.modes.parallel_half_height = by_key.scene.modes.parallel_half_height
        assert np.array_equal(np.asarray(by_key.render()), np.asarray(by_hand.render()))


def test_a_material_set_by_hand_mends_part_materials_that_are_no_tuple() -> None:
    """Setting `material` gives it to every part: with part_materials set to one Material it raised
    'Material' object is not iterable, so the mistake could not be mended that way."""
    with marraztu.Viewer(size=SIZE) as v:
        obj = v.scene.objects[0]
        material, obj.part_materials = obj.material, obj.material
        obj.material = material
        assert obj.part_materials == tuple(material for _ in obj.mesh.materials) and np.asarray(v.render()).any()


def test_lights_and_materials_set_by_hand_in_lists_are_drawn() -> None:
    with marraztu.Viewer(size=SIZE) as v:
        v.press("0 1")
        v.scene.lights[1].intensity, v.scene.lights[1].position = [255, 255, 255], (10, 20, 30)
        v.scene.objects[0].material = dataclasses.replace(v.scene.objects[0].material, kd=[1, 0, 0], ns=5)
        v.scene.ambient = [10, 10, 10]
        assert np.asarray(v.render()).any() and v.probe() is not None


def test_a_material_set_by_hand_on_a_model_of_several_draws_its_every_part(tmp_path: Path) -> None:
    """two_tone's red and blue parts were drawn with the MTL's materials whatever `material` was set to:
    now it replaces them, as a scene file's material does, in the picture and the probe alike."""
    for name in ("two_tone.obj", "two_tone.mtl"):
        (tmp_path / name).write_bytes((ASSET_DIR / "examples" / name).read_bytes())
    entry = '[[objects]]\nmodel = "two_tone.obj"\nposition = [0, 0, 0]\n'
    green = "material = { ka = [0, 1, 0], kd = [0, 0.5, 0], ks = [0, 0, 0], ns = 1 }\n"
    (tmp_path / "own.toml").write_text(entry)
    (tmp_path / "given.toml").write_text(entry + green)
    with marraztu.Viewer(size=SIZE, scene=tmp_path / "given.toml") as given, \
            marraztu.Viewer(size=SIZE, scene=tmp_path / "own.toml") as v:
        before = np.asarray(v.press("T").render())
        obj = v.scene.objects[0]
        obj.material = given.scene.objects[0].material
        assert obj.part_materials == (obj.material, obj.material)
        after = np.asarray(v.render())
        assert not np.array_equal(after, before)
        assert np.array_equal(after, np.asarray(given.press("T").render()))
        for face in (0, 6):  # one face of each part
            obj.selected_face = face
            assert v.probe().vertices[0].ambient == (0.0, 75.0, 0.0)  # Ka x Ia: Ia is (200, 75, 255)
            assert v.probe().material is None  # not the MTL's 'red' or 'blue': not what is drawn
        blue = dataclasses.replace(obj.material, ka=(0, 0, 1))
        obj.part_materials = (obj.material, blue)  # set after it, a part's own
        assert v.probe().vertices[0].ambient == (0.0, 0.0, 255.0)


def test_a_path_that_is_not_a_path_is_refused_naming_the_argument(viewer) -> None:
    """load(3) and Viewer(scene=3) raised pathlib's 'expected str, bytes or os.PathLike object, not int',
    from eight calls down, naming no argument."""
    with pytest.raises(TypeError, match=r"^path is a file name \(str or Path\), not int$"):
        viewer.load(3)
    with pytest.raises(TypeError, match=r"^path is a file name \(str or Path\), not NoneType$"):
        viewer.load(None)
    for argument in ("scene", "texture"):
        with pytest.raises(TypeError, match=rf"^{argument} is a file name \(str or Path\), not list$"):
            marraztu.Viewer(size=SIZE, **{argument: ["model.obj"]})


def test_viewers_open_at_exit_are_released_whenever_the_first_finalizer_was_made(tmp_path: Path) -> None:
    """weakref.finalize's exit hook is registered by the process's first finalizer (numba's, say): the
    API's own hook releases what is open or queued whichever runs first."""
    script = ("import sys, tempfile\nif sys.argv[1] == 'early':\n    held = tempfile.TemporaryDirectory()\n"
              "import marraztu.frontends.api as api\nreal = api._release\n"
              "api._release = lambda *both: (print('released', flush=True), real(*both))\n"
              "viewer = api.Viewer((16, 12))\nviewer.render()\n")
    for order in ("early", "late"):
        result = subprocess.run([sys.executable, "-c", script, order], capture_output=True, text=True, timeout=120)
        assert result.returncode == 0 and result.stdout.split() == ["released"], (order, result.stderr)


_FORKED_CHILD = """
import os, signal, marraztu
with marraztu.Viewer((16, 12)) as closed:
    closed.render()
held = marraztu.Viewer((16, 12))
held.render()
child = os.fork()
if child == 0:
    signal.alarm(10)  # each call below hung for good in the child, where Mesa's drawing threads are not
    for call in (lambda: marraztu.Viewer((16, 12)).render(), held.render, lambda: held.press("x")):
        try:
            call()
            print("drew", flush=True)  # os._exit flushes nothing, and a pipe's output is buffered
        except marraztu.ViewerError as error:
            print(str(error).replace(os.linesep, "|"), flush=True)
    os._exit(0)
os.waitpid(child, 0)
print("parent", held.render().size)
"""


def test_a_process_forked_after_a_viewer_was_made_is_refused_in_one_line_not_hung() -> None:
    """multiprocessing's default on Linux forks: the child inherits the parent's GL display without its
    drawing threads, and its first picture waited for them for ever."""
    result = subprocess.run([sys.executable, "-c", _FORKED_CHILD], capture_output=True, text=True, timeout=120)
    lines = result.stdout.splitlines()
    assert result.returncode == 0 and len(lines) == 4, (result.stdout, result.stderr)
    assert all("forked" in line and "spawn" in line for line in lines[:3]), lines
    assert lines[3] == "parent (16, 12)", "the parent goes on drawing"


def test_the_probe_report_says_its_view_and_the_vertex_colour_that_tints_it() -> None:
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.add_mesh(TRIANGLE, [[0, 1, 2]], colours=[[255, 0, 0], [0, 255, 0], [0, 0, 255]])
        report = v.press("F").probe()
        assert report.view == "everything"
        assert [vertex.vertex_colour for vertex in report.vertices] == [(255, 0, 0), (0, 255, 0), (0, 0, 255)][
            :len(report.vertices)]
        assert v.press("v").probe().view != "everything"
        v.add_mesh(TRIANGLE, [[0, 1, 2]], name="plain")
        assert v.probe().vertices[0].vertex_colour is None


def test_dir_offers_the_lazily_imported_names() -> None:
    """A notebook's tab completion asks dir(): marraztu.Viewer was missing from it."""
    assert {"Viewer", "ViewerError", "LoadError", "ProbeReport"} <= set(dir(marraztu))


@pytest.mark.parametrize("keys, error", [
    ("F 0 l x u u u u", ValueError),  # the fourth u would undo to the singular matrix
    ("F x x u u u u u", ValueError),  # the history's top, pushed and popped below, as it was
    ("F HOME x u u u u", ValueError),  # the view moves, cleared by x's move, as they were
    ("F 0 x f=missing.obj", LoadError),
    ("F 0 x f={model} x f=missing.obj", LoadError),  # a model loaded before the refusal leaves again
    ("F 0 x c c f={model}", ViewerError),  # no file is loaded while lights are targeted
    ("F 0 x qq", KeyMapError),  # as before: no key is pressed before every name is known
])
def test_a_press_refused_half_way_leaves_the_viewer_as_it_was(keys: str, error: type) -> None:
    """The keys before a refused one stayed pressed: press("F 0 u") with u refused raised, yet left
    Gouraud shading and the sun on, so the same cell run again after the mistake was mended turned them
    off. A press is all or nothing, as a bad key's name always made it: the scene is as it was."""
    with marraztu.Viewer(size=SIZE) as v:
        obj = v.scene.objects[0]
        obj.history[:0] = [np.eye(4), np.zeros((4, 4)), np.eye(4), np.eye(4)]  # a singular matrix 3 down
        v.press(". .")  # view moves, which u undoes first
        history, objects, modes = list(obj.history), list(v.scene.objects), dataclasses.replace(v.scene.modes)
        cameras, view_moves = list(v.scene.camera.history), list(v.scene.view_moves)
        before = v.render(overlay=True)
        with pytest.raises(error):
            v.press(keys.format(model=ASSET_DIR / "examples" / "two_tone.obj"))
        assert [id(m) for m in obj.history] == [id(m) for m in history] and v.scene.objects == objects
        assert v.scene.modes == modes and v.scene.view_moves == view_moves and len(view_moves) == 2
        assert [id(m) for m in v.scene.camera.history] == [id(m) for m in cameras]
        assert np.array_equal(np.asarray(v.render(overlay=True)), np.asarray(before))


def test_the_message_says_the_file_prompt_is_open() -> None:
    """press("f") opens the prompt, and the presses after it were typed into it with no word: x did
    nothing, and `message` said ''. The window shows the prompt under its message; so does `message`."""
    with marraztu.Viewer(size=SIZE) as v:
        assert v.press("f x x").message == "model file to load (Enter loads, ESC cancels): xx_"
        assert v.press("ESC").message == "loading cancelled"


def test_a_prompt_left_open_by_one_press_is_typed_into_by_the_next() -> None:
    """press("f m o") left the prompt open, as `message` showed, but press("d e l") was refused with
    "unknown key 'e'", and SPACE and BACKSPACE too: the next call's words were read as keys."""
    with marraztu.Viewer(size=SIZE) as v:
        v.press("f m o")
        assert v.press("d e SPACE x BACKSPACE BACKSPACE l").message.endswith(": model_")
        assert v.press("ESC").message == "loading cancelled"


def test_a_mesh_added_from_python_says_where_it_stands_as_a_load_does() -> None:
    """add_mesh joined the scene past the viewer: a sphere at the origin of the built-in scene, inside
    Rammer_255, said only how many vertices it has, where `load` of the same says it may be hidden."""
    with marraztu.Viewer(size=SIZE) as v:
        v.add_mesh(trimesh.creation.icosphere())
        assert v.message.endswith("inside Rammer_255's bounding box, perhaps hidden by it (d shows it alone)")


@pytest.mark.parametrize("change, words", [
    (lambda s: s.objects.append("teapot"), r"^the scene's objects must hold SceneObjects, not 'teapot'$"),
    (lambda s: setattr(s, "objects", tuple(s.objects)), r"^the scene's objects must be a list, not tuple$"),
    (lambda s: setattr(s, "modes", None), r"^the scene's modes must be a Modes \(from .*, not None$"),
    (lambda s: setattr(s.objects[0], "mesh", None), r"'s mesh must be a Mesh, not None$"),
    (lambda s: setattr(s.objects[0], "name", 42), r"^the scene's objects' names must be str, not 42$"),
    (lambda s: setattr(s.objects[0], "name", "a" * (NAME_LIMIT + 1)), rf"name is {NAME_LIMIT + 1} characters long"),
    # the overlay drew a message naming it on two lines ('framed a', 'b'); a refusal naming it was two lines
    (lambda s: setattr(s.objects[0], "name", "a\nb"), r"^'a\\nb': name must be one line of printable characters"),
    (lambda s: setattr(s.cameras[0], "name", "\x1b[2J"), r"^'\\x1b\[2J': name must be one line of printable "),
    (lambda s: setattr(s.lights[1], "name", "bu\tlb"), r"^'bu\\tlb': name must be one line of printable characters"),
    (lambda s: setattr(s.objects[0], "name", "no\xa0break"), r"one line of printable characters: it holds \\xa0$"),
    # the repr's count, quotes and all, beside the name's: '(1000002 characters): name is 1000000 characters long'
    (lambda s: setattr(s.lights[1], "name", "b" * 10**6), r"^'b{40}'\.\.\.: name is 1000000 characters long"),
    (lambda s: s.objects[0].history.clear(), r"'s history must be a list of model matrices, .*not \[\]$"),
    (lambda s: setattr(s.cameras[0], "view_sizes", None), r"^camera's view_sizes must be a list, not None$"),
    (lambda s: setattr(s.objects[0], "selected_face", 1.5), r"'s selected_face must be a whole number, not 1\.5$"),
    (lambda s: setattr(s.objects[0], "uid", [1]), r"'s uid must be a whole number, not \[1\]$"),  # unhashable
    (lambda s: setattr(s.objects[0], "uid", s.cameras[0].uid),
     r"^the scene's objects\[0\] \(x_wing\) and cameras\[0\] \(camera\) have the same uid \d+: "),
    (lambda s: s.objects.append(s.objects[0]),  # not a copy: no word of copies
     r"^the scene's objects\[0\] \(x_wing\) and objects\[\d+\] \(x_wing\) are one element listed twice: list it "
     r"once \(the renderer keeps each element's GPU buffers by its uid, \d+\)$"),
    (lambda s: s.cameras.append(s.objects[0]),
     r"^the scene's objects\[0\] \(x_wing\) and cameras\[1\] \(x_wing\) are one element listed twice"),
    (lambda s: s.lights.append("sun"), r"^the scene's lights must hold Lights, not 'sun'$"),
    (lambda s: setattr(s.lights[1], "kind", "point"), r"^the bulb's kind must be a LightKind \(LightKind\."),
    (lambda s: setattr(s.lights[2], "owner", None), r"'s owner must be an Owner \(Owner\.NONE, .*not None$"),
    (lambda s: setattr(s.lights[2], "axis_in_owner", np.eye(2)), r"'s axis_in_owner must be a 3x3 rotation"),
    # the spotlight then pointed nowhere: it lit nothing (a 30 degree cone) or all round it (past 90), and r
    # could not turn it back; one of 1e-200 pointed 1e-200 long, which unit() could not make 1 long
    (lambda s: setattr(s.lights[3], "axis_in_owner", np.zeros((3, 3))),
     r"^the camera spotlight's axis_in_owner must be a 3x3 rotation of finite numbers \(.*\), not array\(\[\[0\., "),
    *[(lambda s, axis=axis: setattr(s.lights[2], "axis_in_owner", axis), r"'s axis_in_owner must be a 3x3 rotation")
      for axis in (np.diag([1.0, 1.0, 0.0]), np.eye(3) * 1e-200, np.eye(3) * 1e300, np.diag([1.0, 1.0, -1.0]))],
    (lambda s: setattr(s.lights[1], "key", None), r"^a light's name and key must be str, not 'bulb' and None$"),
])
def test_parts_of_the_scene_replaced_by_what_they_are_not_are_refused_in_one_line(change, words: str) -> None:
    """A light's kind set to "point", a mesh or the modes to None, a str among the objects raised
    AttributeError from deep in the renderer; selected_face 1.5 drew; an empty history an IndexError; a
    name of 10 MB took minutes to lay out in the panels (4 s a megabyte)."""
    with marraztu.Viewer(size=SIZE) as v:
        v.press("0 1 2 3")
        change(v.scene)
        for call in (v.render, lambda: v.press("x"), v.probe, lambda: v.status):
            with pytest.raises(ValueError, match=words):
                call()


def test_two_elements_of_one_uid_are_refused_in_one_line() -> None:
    """A copy given the original's uid (copy.copy and dataclasses.replace keep it) raised KeyError:
    'surface' from the GPU's surface_content: the renderer keeps each element's buffers by its uid, and
    made the copy's over the original's, releasing those while the original still waited to be drawn."""
    with marraztu.Viewer(size=SIZE) as v:
        v.add_mesh(TRIANGLE, [[0, 1, 2]], name="tri")
        copy = dataclasses.replace(v.scene.objects[-1], mesh=v.scene.objects[0].mesh, name="wing")
        own_uid, v.scene.objects[0].uid = v.scene.objects[0].uid, v.scene.objects[-1].uid
        said = (r"^the scene's objects\[0\] \(x_wing\) and objects\[\d+\] \(tri\) have the same uid \d+: the renderer "
                r"keeps each element's GPU buffers by it \(.*\)$")
        for call in (v.render, lambda: v.press("x"), v.probe, lambda: v.status):
            with pytest.raises(ValueError, match=said):
                call()
        v.scene.objects[0].uid = own_uid
        v.scene.objects.append(copy)
        with pytest.raises(ValueError, match=r"\(tri\) and objects\[\d+\] \(wing\) have the same uid"):
            v.render()
        v.scene.objects.pop()
        assert np.asarray(v.render()).any()


def test_a_spotlights_axis_turned_by_r_or_typed_to_four_decimals_is_a_rotation() -> None:
    with marraztu.Viewer(size=SIZE) as v:
        v.press("3 c c TAB TAB TAB r x*100 y*77")
        assert v.scene.light.name == "camera spotlight" and np.asarray(v.render()).any()
        v.scene.light.axis_in_owner = np.array([[0.7071, -0.7071, 0], [0.7071, 0.7071, 0], [0, 0, 1]])
        assert np.asarray(v.render()).any()


@pytest.mark.parametrize("emptied", ["cameras", "lights"])
def test_the_status_of_a_scene_without_a_camera_or_light_is_refused_as_a_render_is(emptied: str) -> None:
    """v.status raised IndexError where render said what was wrong."""
    with marraztu.Viewer(size=SIZE) as v:
        getattr(v.scene, emptied).clear()
        with pytest.raises(ValueError, match=r"^the scene needs a camera and a light"):
            v.status  # noqa: B018 - the property is the call


UNIT_CUBE = (np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)]),
             [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]])


def _cubes_added(v: marraztu.Viewer, first: int, count: int) -> None:
    """`count` unit cubes in a row, every third one a small one inside the cube before it."""
    positions, faces = UNIT_CUBE
    for index in range(first, first + count):
        place = [3.0 * (index - index % 3 // 2), 0.0, 0.0]
        v.add_mesh(positions * (0.25 if index % 3 == 2 else 1.0) + place + (0.5 if index % 3 == 2 else 0.0), faces,
                   name=f"cube {index}")


@pytest.mark.parametrize("before", [10, 60])
def test_a_loop_of_add_mesh_checks_the_scene_once_not_at_each_call(monkeypatch: pytest.MonkeyPatch,
                                                                   before: int) -> None:
    """Each add_mesh checked every element of the scene (Scene.check_by_hand): N calls cost N squared. No
    hand can change a scene no one was handed, and add_mesh checks what it adds where it enters: the
    check is made again once `scene` is read, or another call came between."""
    from marraztu.model import scene as scene_module

    checked = collections.Counter()
    refusal_of = scene_module._element_refusal

    def counting(element: object, what: str) -> str | None:
        checked["elements"] += 1
        return refusal_of(element, what)

    monkeypatch.setattr(scene_module, "_element_refusal", counting)
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        _cubes_added(v, 0, before)
        checked.clear()
        _cubes_added(v, before, 10)
        assert checked["elements"] == 0, checked
        v.press("x")  # a key's changes are not looked into: the next call checks
        _cubes_added(v, before + 10, 1)
        assert checked["elements"] == before + 10 + 1, checked  # the objects and the camera
        assert len(v.scene.objects) == before + 11
        checked.clear()
        _cubes_added(v, before + 11, 2)  # handed out: each call checks
        assert checked["elements"] == (before + 12) + (before + 13), checked
