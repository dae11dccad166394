"""Scene files: SPEC 3's built-in scene exactly, and every bad file refused with a LoadError naming it."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from marraztu.errors import LoadError
from marraztu.loaders.scenefile import (
    DEFAULT_MATERIAL,
    builtin_scene_path,
    empty_scene,
    load_builtin_scene,
    load_scene,
    material_for_loaded,
)
from marraztu.model.mesh import Mesh
from marraztu.model.scene import Material
from marraztu.model.transforms import euler_xyz
from marraztu.resources import ASSET_DIR

SPEC_MATERIALS = {
    "shiny_plastic": Material((0.0, 0.3, 1.0), (0.5922, 0.0166, 0.0), (0.5974, 0.2084, 0.2084), 100.2237),
    "greenish": Material((0.4, 0.8, 0.3), (0.3, 0.4, 0.6), (0.3, 0.1, 0.2), 60.0),
    "vibrant_green": Material((0.1, 1.0, 0.2), (0.8, 0.8, 0.8), (0.5, 0.5, 0.5), 225.0),
    "golden": Material((0.8, 0.72, 0.0), (0.8, 0.6, 0.4), (0.9, 0.8, 0.5), 80.0),
}

# A tetrahedron: the smallest model every scene below can point at.
TETRAHEDRON = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"

CAMERA = '[[cameras]]\nmodel = "m.obj"\nposition = [0, 0, 10]\n'
MATERIAL = '[materials.m]\nka = [0.1, 0.2, 0.3]\nkd = [0.4, 0.5, 0.6]\nks = [0.7, 0.8, 0.9]\nns = 10\n'


def write_scene(folder: Path, text: str) -> Path:
    (folder / "m.obj").write_text(TETRAHEDRON)
    path = folder / "scene.toml"
    path.write_text(text)
    return path


# --- the built-in scene --------------------------------------------------------------------------
def test_builtin_scene_is_spec_3() -> None:
    scene = load_builtin_scene()
    placed = {obj.name: (tuple(obj.origin), obj.material) for obj in scene.objects + scene.cameras}
    assert placed == {
        "camera": ((0.0, 0.0, 150.0), SPEC_MATERIALS["shiny_plastic"]),
        "x_wing": ((-100.0, 0.0, 0.0), SPEC_MATERIALS["greenish"]),
        "r_falke": ((100.0, 0.0, 0.0), SPEC_MATERIALS["vibrant_green"]),
        "Rammer_255": ((0.0, 0.0, 0.0), SPEC_MATERIALS["golden"]),
    }
    assert [obj.name for obj in scene.cameras] == ["camera"]
    assert [obj.name for obj in scene.objects] == ["x_wing", "r_falke", "Rammer_255"]
    assert np.array_equal(scene.camera.model[:3, :3], np.eye(3)), "the camera looks toward -z"
    top_toward_camera_nose_down = euler_xyz((90, 0, 180))
    assert all(np.array_equal(obj.model[:3, :3], top_toward_camera_nose_down) for obj in scene.objects)
    assert all(len(obj.history) == 1 for obj in scene.objects + scene.cameras)
    assert scene.texture_path == str(ASSET_DIR / "selfi.ppm")
    assert Path(scene.texture_path).is_file()


def test_builtin_scene_path_is_in_the_assets() -> None:
    assert builtin_scene_path() == ASSET_DIR / "scene.toml"
    assert builtin_scene_path().is_file()


def test_empty_scene_is_the_builtin_camera_alone() -> None:
    scene = empty_scene()
    assert scene.objects == []
    assert [camera.name for camera in scene.cameras] == ["camera"]
    assert tuple(scene.camera.origin) == (0.0, 0.0, 150.0)
    assert scene.camera.material == SPEC_MATERIALS["shiny_plastic"]


# --- good files ------------------------------------------------------------------------------------
def test_inline_material_default_name_and_paths_relative_to_the_scene(tmp_path: Path) -> None:
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "ship.obj").write_text(TETRAHEDRON)
    path = write_scene(tmp_path, 'texture = "pics/t.png"\n' + CAMERA + """
[[objects]]
model = "models/ship.obj"
position = [1, 2.5, -3]
material = { ka = [0, 0, 0], kd = [1, 1, 1], ks = [0.5, 0.5, 0.5], ns = 2.5, rgb = [1, 0, 0] }
""")
    scene = load_scene(path)
    ship = scene.objects[0]
    assert ship.name == "ship"
    assert tuple(ship.origin) == (1.0, 2.5, -3.0)
    assert ship.material == Material((0.0, 0.0, 0.0), (1.0, 1.0, 1.0), (0.5, 0.5, 0.5), 2.5, (1.0, 0.0, 0.0))
    # a missing texture is not the scene's problem: the viewer falls back to a built-in one
    assert scene.texture_path == str(tmp_path / "pics" / "t.png")


def test_named_material_explicit_name_and_no_texture(tmp_path: Path) -> None:
    path = write_scene(tmp_path, MATERIAL + CAMERA + """
[[objects]]
name = "first"
model = "m.obj"
position = [0, 0, 0]
material = "m"

[[objects]]
model = "m.obj"
position = [5, 0, 0]
""")
    scene = load_scene(path)
    assert [obj.name for obj in scene.objects] == ["first", "m"]
    assert scene.objects[0].material == Material((0.1, 0.2, 0.3), (0.4, 0.5, 0.6), (0.7, 0.8, 0.9), 10.0)
    assert scene.objects[1].material == DEFAULT_MATERIAL  # no material: a run-time model's default
    assert scene.texture_path is None


def test_absolute_model_path(tmp_path: Path) -> None:
    model = tmp_path / "elsewhere.obj"
    model.write_text(TETRAHEDRON)
    path = write_scene(tmp_path, f'[[cameras]]\nmodel = "{model}"\nposition = [0, 0, 0]\n')
    assert load_scene(path).camera.name == "elsewhere"


# --- bad files -------------------------------------------------------------------------------------
BAD_SCENES = {
    "toml syntax": ('[[cameras]]\nmodel = m.obj\n', "TOML syntax"),
    "duplicate table": (MATERIAL + "[materials.m]\nns = 1\n", "TOML syntax"),
    "empty file": ("", "no camera"),
    "objects but no camera": ('[[objects]]\nmodel = "m.obj"\nposition = [0, 0, 0]\n', "no camera"),
    "unknown top-level key": ('textures = "a.ppm"\n' + CAMERA, "unknown key 'textures'"),
    "unknown entry key": (CAMERA + "positon = [1, 2, 3]\n", "unknown key 'positon'"),
    "missing model": ("[[cameras]]\nposition = [0, 0, 0]\n", "missing key 'model'"),
    "missing position": ('[[cameras]]\nmodel = "m.obj"\n', "missing key 'position'"),
    "model not a string": ("[[cameras]]\nmodel = 3\nposition = [0, 0, 0]\n", "model must be"),
    "empty model": ('[[cameras]]\nmodel = ""\nposition = [0, 0, 0]\n', "model must be"),
    "name not a string": (CAMERA + "name = 7\n", "name must be"),
    "position too short": ('[[cameras]]\nmodel = "m.obj"\nposition = [0, 0]\n', "three numbers"),
    "position not numbers": ('[[cameras]]\nmodel = "m.obj"\nposition = ["a", 0, 0]\n', "a number"),
    "position a boolean": ('[[cameras]]\nmodel = "m.obj"\nposition = [true, 0, 0]\n', "a number"),
    "position not a list": ('[[cameras]]\nmodel = "m.obj"\nposition = 3\n', "three numbers"),
    "position nan": ('[[cameras]]\nmodel = "m.obj"\nposition = [nan, 0, 0]\n', "finite"),
    "position infinite": ('[[cameras]]\nmodel = "m.obj"\nposition = [0, -inf, 0]\n', "finite"),
    "unknown material": (CAMERA + 'material = "gold"\n', "unknown material 'gold'"),
    "material not a table": (CAMERA + "material = 3\n", "material name or a table"),
    "material missing ns": (CAMERA + "material = { ka = [0, 0, 0], kd = [0, 0, 0], ks = [0, 0, 0] }\n",
                            "missing key 'ns'"),
    "material unknown key": (MATERIAL + "kx = [0, 0, 0]\n" + CAMERA, "unknown key 'kx'"),
    "material colour above 1": (MATERIAL.replace("[0.1, 0.2, 0.3]", "[2, 0, 0]") + CAMERA, "between 0 and 1"),
    "material colour negative": (MATERIAL.replace("[0.4, 0.5, 0.6]", "[0, -0.1, 0]") + CAMERA, "between 0 and 1"),
    "material colour a string": (MATERIAL.replace("[0.7, 0.8, 0.9]", '"red"') + CAMERA, "three numbers"),
    "ns zero": (MATERIAL.replace("ns = 10", "ns = 0") + CAMERA, "greater than 0"),
    "ns negative": (MATERIAL.replace("ns = 10", "ns = -3") + CAMERA, "greater than 0"),
    "ns infinite": (MATERIAL.replace("ns = 10", "ns = inf") + CAMERA, "finite"),
    "rgb wrong size": (MATERIAL + "rgb = [1, 1]\n" + CAMERA, "three numbers"),
    "materials not tables": ("materials = 3\n" + CAMERA, "[materials.NAME]"),
    "cameras not an array": ('[cameras]\nmodel = "m.obj"\nposition = [0, 0, 0]\n', "[[cameras]]"),
    "texture not a string": ("texture = 5\n" + CAMERA, "texture must be"),
    "model file missing": ('[[cameras]]\nmodel = "missing.obj"\nposition = [0, 0, 0]\n', "model missing.obj"),
}


@pytest.mark.parametrize("text, expected", BAD_SCENES.values(), ids=BAD_SCENES.keys())
def test_bad_scene_raises_load_error_naming_the_file(tmp_path: Path, text: str, expected: str) -> None:
    path = write_scene(tmp_path, text)
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.path == str(path)
    assert expected in caught.value.message
    assert str(path) in str(caught.value)


def test_syntax_error_gives_tomls_line(tmp_path: Path) -> None:
    path = write_scene(tmp_path, CAMERA + "\n[[objects]]\nmodel = m.obj\n")
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line == 6
    assert "(at line" not in caught.value.message  # the line is in the prefix, not said twice


def test_entry_error_gives_its_tables_line(tmp_path: Path) -> None:
    path = write_scene(tmp_path, CAMERA + '\n[[objects]]\nmodel = "m.obj"\nposition = [0, 0, 0]\n'
                                          '\n[[objects]]\nmodel = "m.obj"\n')
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line == 9
    assert "objects[2]" in caught.value.message


def test_broken_model_names_the_model_and_its_line(tmp_path: Path) -> None:
    (tmp_path / "broken.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    path = write_scene(tmp_path, '[[cameras]]\nmodel = "broken.obj"\nposition = [0, 0, 0]\n')
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.path == str(path) and caught.value.line == 1
    assert caught.value.message.startswith("model broken.obj: ")
    assert "broken.obj:4" in caught.value.message


def test_binary_scene_file(tmp_path: Path) -> None:
    path = tmp_path / "scene.toml"
    path.write_bytes(bytes(range(256)))
    with pytest.raises(LoadError, match="not UTF-8") as caught:
        load_scene(path)
    assert caught.value.path == str(path)


@pytest.mark.parametrize("name, reason", [("does_not_exist.toml", "no such file"),
                                          (".", "is a directory")])
def test_unreadable_scene_file(tmp_path: Path, name: str, reason: str) -> None:
    path = tmp_path / name
    with pytest.raises(LoadError, match=reason) as caught:
        load_scene(path)
    assert caught.value.path == str(path)


# --- materials of models loaded at run time --------------------------------------------------------
def tiny_mesh(file_material: dict[str, object] | None = None,
              base_colour: tuple[float, float, float] | None = None) -> Mesh:
    return Mesh(name="t", positions=np.eye(3), corner_vertex=np.arange(3),
                corner_uv=np.zeros((3, 2), np.float32), corner_normal=np.tile([0, 0, 1], (3, 1)).astype(np.float32),
                face_start=np.array([0, 3]), face_normals=np.array([[0, 0, 1]], np.float32),
                base_colour=base_colour, file_material=file_material)


def test_loaded_model_without_material_gets_the_default() -> None:
    assert material_for_loaded(tiny_mesh()) == DEFAULT_MATERIAL
    assert DEFAULT_MATERIAL.rgb == (1.0, 1.0, 1.0)


def test_loaded_model_takes_its_files_material_and_colour() -> None:
    mesh = tiny_mesh({"kd": (0.9, 0.1, 0.1), "ns": 42.0}, base_colour=(0.2, 0.4, 0.6))
    material = material_for_loaded(mesh)
    assert material.kd == (0.9, 0.1, 0.1) and material.ns == 42.0
    assert material.ka == DEFAULT_MATERIAL.ka and material.ks == DEFAULT_MATERIAL.ks
    assert material.rgb == (0.2, 0.4, 0.6)


def test_loaded_models_odd_material_numbers_are_tamed() -> None:
    material = material_for_loaded(tiny_mesh({"ka": (2.0, -1.0, 0.5), "ns": 0.0, "ks": "junk"}))
    assert material.ka == (1.0, 0.0, 0.5)
    assert material.ns >= 1.0  # "Ns 0" would light every face with full specular
    assert material.ks == DEFAULT_MATERIAL.ks


def test_rotation_is_optional_and_checked(tmp_path: Path) -> None:
    model = tmp_path / "tri.obj"
    model.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    good = tmp_path / "good.toml"
    good.write_text('[[cameras]]\nmodel = "tri.obj"\nposition = [0, 0, 0]\nrotation = [0, 90, 0]\n')
    camera = load_scene(good).camera
    assert np.allclose(camera.forward, [-1.0, 0.0, 0.0])
    bad = tmp_path / "bad.toml"
    bad.write_text('[[cameras]]\nmodel = "tri.obj"\nposition = [0, 0, 0]\nrotation = [0, "x", 0]\n')
    with pytest.raises(LoadError, match="bad.toml"):
        load_scene(bad)
