"""Scene files: SPEC 3's built-in scene exactly, and every bad file refused with a LoadError naming it."""

from __future__ import annotations

import copy
import dataclasses
import os
import re
import subprocess
import sys
import tomllib
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from marraztu.errors import LoadError
from marraztu.loaders.patterns import POSSESSIVE_GROUPS_HOLD
from marraztu.loaders.registry import load_model as load_model_as_read
from marraztu.loaders.scenefile import (
    DEFAULT_MATERIAL,
    builtin_scene_path,
    empty_scene,
    load_builtin_scene,
    load_scene,
    material_for_loaded,
    read_scene_description,
)
from marraztu.model.build import build_mesh, scaled_mesh
from marraztu.model.geometry import FLOAT32_MAX
from marraztu.model.lights import AMBIENT_INTENSITY, SPOT_APERTURE_RANGE_DEG, Light, default_lights
from marraztu.model.mesh import Mesh
from marraztu.model.scene import NAME_LIMIT, Material, Scene
from marraztu.model.transforms import euler_xyz
from marraztu.resources import ASSET_DIR
from support.work import calls_made

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


# --- lights --------------------------------------------------------------------------------------
def light_state(light: Light) -> tuple[object, ...]:
    return (light.name, light.on, tuple(light.intensity), tuple(light.position), tuple(light.direction),
            light.aperture_deg, light.owner)


def test_a_scene_file_without_lights_starts_with_specs_all_off() -> None:
    for scene in (load_builtin_scene(), empty_scene()):
        assert [light_state(light) for light in scene.lights] == [light_state(light) for light in default_lights()]
        assert not any(light.on for light in scene.lights)
        assert np.array_equal(scene.ambient, AMBIENT_INTENSITY)


LESSON_LIGHTS = """ambient = [20, 30, 40.5]
[lights.sun]
on = true
intensity = [100, 0, 300]
direction = [0, 1, 0]
[lights.bulb]
on = true
position = [10, -20, 30]
[lights.camera_spotlight]
aperture = 12.5
"""


def test_a_scene_file_sets_the_lights_it_names_and_leaves_the_others_as_spec_starts_them(tmp_path: Path) -> None:
    """A lesson on a point light started with every light off at SPEC's numbers: the student had to
    press 1 and move the bulb."""
    scene = load_scene(write_scene(tmp_path, LESSON_LIGHTS + CAMERA))
    sun, bulb, object_spot, camera_spot = scene.lights
    spec_sun, spec_bulb, spec_object_spot, spec_camera_spot = default_lights()
    assert np.array_equal(scene.ambient, [20, 30, 40.5])
    assert sun.on and np.array_equal(sun.intensity, [100, 0, 300]) and np.array_equal(sun.direction, [0, 1, 0])
    assert np.array_equal(sun.position, spec_sun.position)  # only where its marker is drawn
    assert bulb.on and np.array_equal(bulb.position, [10, -20, 30])
    assert np.array_equal(bulb.intensity, spec_bulb.intensity)
    assert light_state(object_spot) == light_state(spec_object_spot)
    assert not camera_spot.on and camera_spot.aperture_deg == 12.5
    assert light_state(camera_spot)[:-2] == light_state(spec_camera_spot)[:-2]
    assert all(light.history == [] for light in scene.lights)  # `u` has nothing to take back
    scene.check_by_hand()  # and the programming interface's next call draws them


def test_a_scene_files_lights_are_its_own_each_time_it_is_read(tmp_path: Path) -> None:
    path = write_scene(tmp_path, LESSON_LIGHTS + CAMERA)
    first, second = load_scene(path), load_scene(path)
    first.lights[1].position[0] = 99.0
    assert second.lights[1].position[0] == 10.0 and not set(map(id, first.lights)) & set(map(id, second.lights))


def test_lights_written_inline_or_dotted_are_read_too(tmp_path: Path) -> None:
    scene = load_scene(write_scene(tmp_path, 'lights = { bulb = { on = true }, sun.direction = [1, 0, 0] }\n' + CAMERA))
    assert scene.lights[1].on and np.array_equal(scene.lights[0].direction, [1, 0, 0])
    dotted = load_scene(write_scene(tmp_path, 'lights.object_spotlight.on = true\n' + CAMERA))
    assert [light.on for light in dotted.lights] == [False, False, True, False]


# Each a scene, the message's words and the line it names.
BAD_LIGHTS = {
    "unknown light": (CAMERA + "[lights.lamp]\non = true\n", "lights: unknown light 'lamp' (lights: sun, bulb, "
                      "object_spotlight, camera_spotlight)", 4),
    "the name as the status line says it": (CAMERA + '[lights."object spotlight"]\n',
                                             "lights: unknown light 'object spotlight'", 4),
    "unknown key": (CAMERA + "[lights.bulb]\non = true\ncolour = [1, 1, 1]\n",
                    "lights.bulb: unknown key 'colour' (allowed: intensity, on, position)$", 6),
    "two unknown keys: the first in the file": (CAMERA + "[lights.bulb]\nwatts = 60\ncolour = [1, 1, 1]\n",
                                                "lights.bulb: unknown key 'watts'", 5),
    "the sun placed": (CAMERA + "[lights.sun]\nposition = [0, 0, 0]\n",
                       "lights.sun: unknown key 'position' (allowed: direction, intensity, on): position is the "
                       "bulb's$", 5),
    "the bulb aimed": (CAMERA + "[lights.bulb]\n\ndirection = [0, 0, 1]\n",
                       "lights.bulb: unknown key 'direction' (allowed: intensity, on, position): direction is the "
                       "sun's$", 6),
    "a spotlight placed": (CAMERA + "[lights.camera_spotlight]\nposition = [0, 0, 0]\n",
                           "lights.camera_spotlight: unknown key 'position' (allowed: aperture, intensity, on): "
                           "position is the bulb's", 5),
    "the sun's aperture": (CAMERA + "[lights.sun]\naperture = 20\n",
                           "aperture is the object_spotlight's and the camera_spotlight's", 5),
    "on a number": (CAMERA + "[lights.bulb]\non = 1\n", "lights.bulb: on must be true or false, not one number", 5),
    "on a word": (CAMERA + '[lights.bulb]\non = "yes"\n', "lights.bulb: on must be true or false, not a string", 5),
    "intensity negative": (CAMERA + "[lights.sun]\nintensity = [200, -1, 0]\n",
                           "lights.sun: intensity must be three numbers from 0 to 3.4e38, where the GPU's 32-bit "
                           "floats end, not [200, -1, 0]", 5),
    "intensity of two": (CAMERA + "[lights.sun]\nintensity = [200, 200]\n",
                         "lights.sun: intensity must be three numbers, like [0, 0, 0], not 2 numbers", 5),
    "intensity past float32": (CAMERA + "[lights.sun]\nintensity = [1e39, 0, 0]\n", "is too large", 5),
    "direction zero": (CAMERA + "[lights.sun]\non = true\ndirection = [0, 0, 0]\n",
                       "lights.sun: direction must point some way (at least 1e-150 long), not [0, 0, 0]", 6),
    "direction nan": (CAMERA + "[lights.sun]\ndirection = [nan, 0, 1]\n", "direction must be a finite number", 5),
    "position past the light's reach": (CAMERA + "[lights.bulb]\nposition = [0, 6e18, 0]\n",
                                        "lights.bulb: position must be three numbers within ±5e+18", 5),
    "position a string": (CAMERA + '[lights.bulb]\nposition = "up"\n', "not a string", 5),
    "aperture too wide": (CAMERA + "[lights.object_spotlight]\naperture = 90\n",
                          "lights.object_spotlight: aperture must be from 1 to 89 degrees (the axis to the cone's "
                          "edge, as + and - keep it), not 90", 5),
    "aperture too narrow": (CAMERA + "[lights.camera_spotlight]\naperture = 0.5\n", "not 0.5", 5),
    "aperture three numbers": (CAMERA + "[lights.camera_spotlight]\naperture = [1, 2, 3]\n",
                               "aperture must be a number, not an array", 5),
    "ambient negative": ("ambient = [200, 75, -255]\n" + CAMERA,
                         "ambient must be three numbers from 0 to 3.4e38, where the GPU's 32-bit floats end, "
                         "not [200, 75, -255]", 1),
    "ambient one number": ("ambient = 200\n" + CAMERA, "ambient must be three numbers, like [0, 0, 0], not one "
                           "number", 1),
    "lights a value": ("lights = true\n" + CAMERA, "lights must be tables, one per light: [lights.sun], "
                       "[lights.bulb], [lights.object_spotlight], [lights.camera_spotlight]", 1),
    "lights an array of tables": (CAMERA + "[[lights]]\non = true\n", "lights must be tables", 4),
    "a light a value": (CAMERA + "[lights]\nbulb = true\n", "lights.bulb must be a table of intensity, on, "
                        "position", 5),
    "inside an inline table: the line that opens it": (
        "\nlights = { bulb = { on = 'yes' } }\n" + CAMERA, "lights.bulb: on must be true or false", 2),
    "inside a light's inline table": (CAMERA + "[lights]\n\nbulb = { on = 'yes' }\n", "on must be true", 6),
    # TOML reads a key after a header as the table's: the scene's ambient, written last, was only "unknown"
    "the ambient after a light's table": (CAMERA + "[lights.sun]\non = true\nambient = [1, 1, 1]\n",
                                          "lights.sun: unknown key 'ambient' (allowed: direction, intensity, on): "
                                          "ambient is the scene's, written before the first [table]$", 6),
    "the texture after a material's table": (
        CAMERA + '[materials.red]\nka = [0, 0, 0]\nkd = [1, 0, 0]\nks = [0, 0, 0]\nns = 1\ntexture = "a.png"\n',
        "material 'red': unknown key 'texture' (allowed: ka, kd, ks, ns, rgb): texture is the scene's, written "
        "before the first [table]$", 9),
}


@pytest.mark.parametrize("text, expected, line", BAD_LIGHTS.values(), ids=BAD_LIGHTS.keys())
def test_a_bad_light_is_refused_at_its_line(tmp_path: Path, text: str, expected: str, line: int) -> None:
    path = write_scene(tmp_path, text)
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert expected in caught.value.message + "$"
    assert (caught.value.path, caught.value.line) == (str(path), line)


# Each a value tried as a light's intensity, the bulb's place, the sun's direction and the ambient.
LIGHT_VALUES_TRIED = {
    "inside": "[0.5, 250, 0]",
    "zero": "[0, 0, 0]",
    "just below 0": "[0, -1e-9, 0]",
    "past the bulb's reach": "[0, 0, 5.000001e18]",
    "huge": "[3e38, 0, 0]",
}


def _refusal(path: Path) -> str:
    """What loading the scene file at `path` is refused with, whole (the file and line first)."""
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    return str(caught.value)


def _refused_from_the_file_and_by_hand(tmp_path: Path, text: str,
                                      set_by_hand: Callable[[Scene], None]) -> tuple[str | None, str | None]:
    """What a scene file of `text` is refused with, and what the same value set by hand on a scene is."""
    try:
        load_scene(write_scene(tmp_path, text))
        file_refused = None
    except LoadError as error:
        file_refused = error.message
    scene = load_scene(write_scene(tmp_path, CAMERA))
    set_by_hand(scene)
    try:
        scene.check_by_hand()
        return file_refused, None
    except ValueError as error:
        return file_refused, str(error)


@pytest.mark.parametrize("where", ["ambient", "intensity", "position", "direction"])
@pytest.mark.parametrize("toml", LIGHT_VALUES_TRIED.values(), ids=LIGHT_VALUES_TRIED.keys())
def test_a_scene_file_and_the_scene_set_by_hand_refuse_the_same_light_values(tmp_path: Path, where: str,
                                                                            toml: str) -> None:
    """One rule, the model's (Scene.check_by_hand, the programming interface's next call), for both."""
    light = {"intensity": "bulb", "position": "bulb", "direction": "sun"}.get(where)
    text = f"ambient = {toml}\n" + CAMERA if light is None else CAMERA + f"[lights.{light}]\n{where} = {toml}\n"
    value = np.array(tomllib.loads(f"v = {toml}")["v"], float)

    def set_by_hand(scene: Scene) -> None:
        if light is None:
            scene.ambient = value
        else:
            setattr(next(each for each in scene.lights if each.name == light), where, value)

    file_refused, hand_refused = _refused_from_the_file_and_by_hand(tmp_path, text, set_by_hand)
    assert (file_refused is None) == (hand_refused is None), (file_refused, hand_refused)
    assert file_refused is None or file_refused.startswith("ambient" if light is None else f"lights.{light}: {where}")


@pytest.mark.parametrize("degrees", ["0", "0.5", "1", "45", "89", "89.5", "120", "180"])
def test_a_scene_file_and_the_scene_set_by_hand_refuse_the_same_apertures(tmp_path: Path, degrees: str) -> None:
    """A spotlight's aperture is held to the range + and - keep it in, from Python too: 120 set by hand was
    drawn, and the next - jumped it to 89."""
    text = CAMERA + f"[lights.object_spotlight]\naperture = {degrees}\n"
    file_refused, hand_refused = _refused_from_the_file_and_by_hand(
        tmp_path, text, lambda scene: setattr(scene.lights[2], "aperture_deg", float(degrees)))
    assert (file_refused is None) == (hand_refused is None), (file_refused, hand_refused)
    assert (hand_refused is None) == (SPOT_APERTURE_RANGE_DEG[0] <= float(degrees) <= SPOT_APERTURE_RANGE_DEG[1])


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
    # a missing texture is not the scene's problem: the viewer falls back to a built-in one, and its
    # message names the scene file's entry
    assert scene.texture_path == str(tmp_path / "pics" / "t.png")
    assert scene.texture_named_at == f"{path}:1: texture"


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


def test_a_scene_without_texture_shows_the_built_in_one_as_a_model_alone_does(tmp_path: Path) -> None:
    """SPEC's texture at start is selfi.ppm: a model given alone showed it, and the same model in a scene
    file that names no texture showed the built-in checker instead."""
    scene = load_scene(write_scene(tmp_path, CAMERA + '[[objects]]\nmodel = "m.obj"\n'))
    assert scene.texture_path == empty_scene().texture_path == load_builtin_scene().texture_path
    assert scene.texture_path == str(ASSET_DIR / "selfi.ppm")
    # should it fail to read, its message names the line that names it, as --empty's does
    assert scene.texture_named_at == empty_scene().texture_named_at == f"{builtin_scene_path()}:7: texture"


def test_a_name_longer_than_a_files_is_refused_at_its_line(tmp_path: Path) -> None:
    """A name of 100,000 characters was kept whole, and the status panel showed 863 lines of it."""
    longest = "n" * NAME_LIMIT
    scene = load_scene(write_scene(tmp_path, CAMERA + f'[[objects]]\nmodel = "m.obj"\nname = "{longest}"\n'))
    assert scene.objects[0].name == longest
    path = write_scene(tmp_path, CAMERA + f'[[objects]]\nmodel = "m.obj"\nname = "{"n" * 100_000}"\n')
    with pytest.raises(LoadError, match=f"^{path}:6: objects\\[1\\]: name is 100000 characters long: "
                                        f"at most {NAME_LIMIT}$"):
        load_scene(path)



@pytest.mark.parametrize("entry,line,refused", [
    ('[[objects]]\nmodel = "m.obj"\nposition = [2e18, 0, 0]\n', 6, "a coordinate reaches 2e+18: past 1e+18"),
    ('[[objects]]\nmodel = "m.obj"\nposition = [0, 0, 9.5e17]\nrotation = [0, 45, 0]\n', 6, None),
    ('[[objects]]\nmodel = "m.obj"\nposition = [0, 9.5e17, 0]\nscale = 1e17\n', 6,
     "a coordinate reaches 1.05e+18: past 1e+18"),
    ('[[cameras]]\nposition = [0, 0, 6e18]\n', 5, "a coordinate reaches 6e+18: past 5e+18"),
    ('[[cameras]]\nposition = [0, 0, 4e18]\n', 5, None),
], ids=["an object past 1e18", "an object within", "its origin within, a corner past", "a camera past 5e18",
        "a camera within"])
def test_a_position_past_an_elements_reach_is_refused_at_its_line(tmp_path: Path, entry: str, line: int,
                                                                   refused: str | None) -> None:
    """An object placed at 2e18 (its model 1 across) loaded, and the programming interface's next call
    refused the scene it had made ('objects[1] as its model matrix places it: ...'); the window drew it
    with numbers the GPU cannot light."""
    path = write_scene(tmp_path, CAMERA + entry)
    if refused is None:
        load_scene(path)
        return
    with pytest.raises(LoadError, match=rf"^{path}:{line}: (objects|cameras)\[\d\]: position .*: {re.escape(refused)}"):
        load_scene(path)

def test_a_name_that_is_not_one_printable_line_is_refused_at_its_line_and_a_files_is_kept_escaped(
        tmp_path: Path) -> None:
    """TOML's "a\\nb" was kept as a name of two lines: every message naming it (framed a...) was shown as
    two. A model's file name, which the scene keeps as its name where it gives none, is kept as the
    status line shows it, as a model loaded alone is."""
    path = write_scene(tmp_path, CAMERA + '[[objects]]\nmodel = "m.obj"\nname = "a\\nb"\n')
    with pytest.raises(LoadError, match=f"^{path}:6: objects\\[1\\]: name must be one line of printable "):
        load_scene(path)
    (tmp_path / "x\ty.obj").write_text(TETRAHEDRON)
    scene = load_scene(write_scene(tmp_path, CAMERA + '[[objects]]\nmodel = "x\\ty.obj"\n'))
    assert scene.objects[0].name == "x\\ty"


def test_one_model_spelled_three_ways_is_loaded_once(tmp_path: Path, monkeypatch) -> None:
    """m.obj, ./m.obj and d/../m.obj are one file: a scene naming it thrice reads it once."""
    import marraztu.loaders.scenefile as scenefile

    loaded: list[Path] = []

    def counting_load(path: Path, stage: object = None) -> Mesh:
        loaded.append(path)
        return load_model_as_is(path)

    load_model_as_is = scenefile.load_model
    monkeypatch.setattr(scenefile, "load_model", counting_load)
    (tmp_path / "d").mkdir()
    entries = "".join(f'[[objects]]\nmodel = "{name}"\nposition = [0, 0, 0]\n'
                      for name in ("m.obj", "./m.obj", "d/../m.obj"))
    scene = load_scene(write_scene(tmp_path, CAMERA + entries))
    assert len(loaded) == 1
    assert len({id(obj.mesh) for obj in scene.objects}) == 1


def test_an_object_without_position_stands_where_a_model_loaded_alone_does(tmp_path: Path) -> None:
    """position was required: a teacher's first scene of one model needed [0, 0, 0] written out."""
    from marraztu.control.viewer import load_model_object

    scene = load_scene(write_scene(tmp_path, CAMERA + '[[objects]]\nmodel = "m.obj"\n'))
    assert np.array_equal(scene.objects[0].model, load_model_object(tmp_path / "m.obj").model)
    assert tuple(scene.objects[0].origin) == (0.0, 0.0, 0.0)


def test_scale_sizes_the_model_as_read_and_leaves_its_model_matrix_rigid(tmp_path: Path) -> None:
    """A model in millimetres beside one in metres could not be sized: there was no scale."""
    scene = load_scene(write_scene(tmp_path, CAMERA + '[[objects]]\nmodel = "m.obj"\nscale = 0.5\n'
                                                      '[[objects]]\nmodel = "m.obj"\nposition = [5, 0, 0]\n'
                                                      'rotation = [0, 90, 0]\nscale = [1, 2, 4]\n'))
    plain = load_model_as_read(tmp_path / "m.obj")
    half, stretched = scene.objects
    assert np.array_equal(half.mesh.positions, plain.positions * 0.5) and half.mesh.size == plain.size * 0.5
    assert np.array_equal(half.mesh.normals, plain.normals), "a uniform scale turns no normal"
    assert np.array_equal(stretched.mesh.positions, plain.positions * [1.0, 2.0, 4.0])
    assert (half.scale, stretched.scale) == ((0.5, 0.5, 0.5), (1.0, 2.0, 4.0))
    assert np.array_equal(stretched.model[:3, :3], euler_xyz((0, 90, 0))), "the model matrix holds no scale"
    assert np.array_equal(half.model, np.eye(4))
    # Each face normal is the stretched face's own: the inverse transpose's, as Newell's method finds it.
    for face in range(stretched.mesh.face_count):
        corners = stretched.mesh.corner_vertex[stretched.mesh.face_start[face]:stretched.mesh.face_start[face + 1]]
        points = stretched.mesh.positions[corners]
        newell = np.cross(points, np.roll(points, -1, axis=0)).sum(axis=0)
        assert np.allclose(stretched.mesh.face_normals[face], newell / np.linalg.norm(newell), atol=1e-6)
    assert np.allclose(np.linalg.norm(stretched.mesh.normals, axis=1), 1.0, atol=1e-6)


@pytest.mark.parametrize("corners", ["v", "v//vn", "v/vt"])
def test_an_uneven_scale_gives_the_normals_of_the_file_written_already_scaled(tmp_path: Path, corners: str) -> None:
    """Normals the file lacks are each vertex's average of its faces': at scale [1, 3, 0.5] they were
    the unscaled averages turned, and v1's probe read (0.098, -0.009, 0.995) where the same model written
    scaled reads (0.105, -0.008, 0.994). A file's own normals are turned, as a matrix turns them."""
    points = np.array([[0, 0, 0], [40, -30, -30], [40, 30, -30], [-5, 3, -1], [-4, -4, -2]], float)
    faces = "f 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 2\n"
    with_normals = corners == "v//vn"
    normals = {"v": "", "v//vn": "vn 0.1 0.2 1\nvn 1 0 0\nvn 0 1 0.5\nvn -1 0 1\nvn 0 0 1\n",
               "v/vt": "vt 0 0\nvt 1 0\nvt 0 1\n"}[corners]  # texture corners with seams: rows per corner
    if corners != "v":
        faces = "".join(f"f {a}{corners[1:].replace('vn', str(a)).replace('vt', str(1 + (a + face) % 3))}"
                        f" {b}{corners[1:].replace('vn', str(b)).replace('vt', str(1 + (b + face) % 3))}"
                        f" {c}{corners[1:].replace('vn', str(c)).replace('vt', str(1 + (c + face) % 3))}\n"
                        for face, (a, b, c) in enumerate(((1, 2, 3), (1, 3, 4), (1, 4, 5), (1, 5, 2))))

    def model(name: str, stretch: list[float]) -> None:
        (tmp_path / name).write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in (points * stretch).tolist())
                                     + normals + faces)

    model("fan.obj", [1, 1, 1])
    model("scaled.obj", [1, 3, 0.5])
    scene = load_scene(write_scene(tmp_path, CAMERA + '[[objects]]\nmodel = "fan.obj"\nscale = [1, 3, 0.5]\n'))
    stretched, written = scene.objects[0].mesh, load_model_as_read(tmp_path / "scaled.obj")
    assert np.allclose(stretched.positions, written.positions)
    assert np.allclose(stretched.face_normals, written.face_normals, atol=1e-6)
    if with_normals:  # the file's own, turned by the inverse transpose and made unit again
        turned = np.array([[0.1, 0.2, 1], [1, 0, 0], [0, 1, 0.5], [-1, 0, 1], [0, 0, 1]]) / [1, 3, 0.5]
        turned /= np.linalg.norm(turned, axis=1, keepdims=True)
        assert np.allclose(stretched.normals, turned[stretched.corner_vertex] if len(stretched.normals) > 5
                           else turned, atol=1e-6)
    else:
        assert stretched.attributes_per_position is written.attributes_per_position is (corners == "v")
        assert np.allclose(stretched.normals, written.normals, atol=1e-6)
        assert np.array_equal(stretched.uvs, load_model_as_read(tmp_path / "fan.obj").uvs)


FAN = np.array([[0, 0, 0], [40, -30, -30], [40, 30, -30], [-5, 3, -1], [-4, -4, -2]], float)
FAN_FACES = [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 1]]


def test_an_uneven_scale_averages_again_the_normals_a_file_gives_for_some_faces_only(tmp_path: Path) -> None:
    """A file whose first face has vn and whose others have none: under a stretch its other normals were
    turned with the file's, not averaged again from the turned faces, up to 0.0104 off the same model
    written stretched; the file's own stay turned."""
    own = np.array([[0.1, 0.2, 1], [1, 0, 0], [0, 1, 0.5]])
    stretch = [1, 3, 0.5]

    def model(name: str, scale: list[float]) -> Path:
        (tmp_path / name).write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in (FAN * scale).tolist())
                                     + "".join(f"vn {x} {y} {z}\n" for x, y, z in own)
                                     + "f 1//1 2//2 3//3\nf 1 3 4\nf 1 4 5\nf 1 5 2\n")
        return tmp_path / name

    model("fan.obj", [1, 1, 1])
    scene = load_scene(write_scene(tmp_path, CAMERA + '[[objects]]\nmodel = "fan.obj"\nscale = [1, 3, 0.5]\n'))
    stretched, written = scene.objects[0].mesh, load_model_as_read(model("scaled.obj", stretch))
    turned = own / stretch
    turned /= np.linalg.norm(turned, axis=1, keepdims=True)
    expected = written.corner_normal.copy()
    expected[:3] = turned  # the first face's corners: the file's own, turned
    assert np.allclose(stretched.corner_normal, expected, atol=1e-6)
    assert np.allclose(stretched.face_normals, written.face_normals, atol=1e-6)


@pytest.mark.parametrize("per_vertex", [True, False])
def test_an_uneven_scale_averages_again_the_normals_given_as_nan(per_vertex: bool) -> None:
    """add_mesh's NaN rows are derived: under a stretch they are averaged again, as for the same mesh
    given stretched, and the rows given are turned."""
    given = np.array([[0.1, 0.2, 1], [np.nan] * 3, [0, 1, 0.5], [np.nan] * 3, [0, 0, 1]])
    if not per_vertex:  # a row per corner, the first face's alone given
        given = np.array([given[vertex] if face == 0 else [np.nan] * 3 for face, corners in enumerate(FAN_FACES)
                          for vertex in corners])
    stretch = (1.0, 3.0, 0.5)
    scaled = scaled_mesh(build_mesh("fan", FAN, FAN_FACES, normals=given, attributes_per_vertex=per_vertex),
                         stretch)
    written = build_mesh("fan", FAN * stretch, FAN_FACES, normals=given / stretch, attributes_per_vertex=per_vertex)
    assert scaled.attributes_per_position is written.attributes_per_position is per_vertex
    assert np.allclose(scaled.corner_normal, written.corner_normal, atol=1e-6)
    assert np.allclose(scaled.face_normals, written.face_normals, atol=1e-6)
    again = scaled_mesh(scaled, (2.0, 1.0, 1.0))  # which rows were averaged goes with the stretched mesh
    assert np.allclose(again.corner_normal, build_mesh("fan", FAN * stretch * [2, 1, 1], FAN_FACES,
                                                       normals=given / stretch / [2, 1, 1],
                                                       attributes_per_vertex=per_vertex).corner_normal, atol=1e-6)


def test_an_uneven_scale_that_leaves_faces_without_area_says_so(tmp_path: Path) -> None:
    """At [1e-6, 1, 1e6] a box's faces across z have no area beside its size: they take the fallback
    normal, as in the box written stretched, whose load note says so; the stretched box's said nothing."""
    corners = "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"
    box = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1]], float)
    stretch = [1e-6, 1, 1e6]
    for name, scale in (("box.obj", [1, 1, 1]), ("scaled.obj", stretch)):
        (tmp_path / name).write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in (box * scale).tolist())
                                     + corners)
    scene = load_scene(write_scene(tmp_path, CAMERA + '[[objects]]\nmodel = "box.obj"\nscale = [1e-6, 1, 1e6]\n'))
    stretched, written = scene.objects[0].mesh, load_model_as_read(tmp_path / "scaled.obj")
    assert written.warnings == ("2 zero-area faces (given a fallback normal)",)
    assert stretched.warnings == written.warnings
    assert np.array_equal(stretched.face_normals, written.face_normals)
    assert scaled_mesh(written, (1e6, 1, 1e-6)).warnings == ()  # stretched back: the note goes with the faces


def test_entries_of_one_model_at_one_scale_share_its_mesh(tmp_path: Path, monkeypatch) -> None:
    import marraztu.loaders.scenefile as scenefile

    loaded: list[Path] = []
    monkeypatch.setattr(scenefile, "load_model", lambda path, _=None: loaded.append(path) or load_model_as_read(path))
    entries = "".join(f'[[objects]]\nmodel = "m.obj"\nscale = {scale}\n' for scale in ("2", "[2, 2, 2]", "3", "1"))
    scene = load_scene(write_scene(tmp_path, CAMERA + entries))
    assert len(loaded) == 1
    meshes = [obj.mesh for obj in scene.objects]
    assert meshes[0] is meshes[1] and len({id(mesh) for mesh in meshes}) == 3


def test_a_scale_past_the_gpus_reach_is_refused_at_its_line(tmp_path: Path) -> None:
    path = write_scene(tmp_path, CAMERA + '[[objects]]\nmodel = "m.obj"\nscale = 1e20\n')
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line == 6
    assert caught.value.message.startswith("objects[1]: scale 1e+20: a coordinate reaches 1e+20: past 1e+18"), \
        caught.value.message


@pytest.mark.parametrize("scale", ["1e-300", "[1e-25, 1e-25, 1e-25]"])
def test_a_scale_too_small_to_light_is_refused_at_its_line(tmp_path: Path, scale: str) -> None:
    """scale = 1e-300 was accepted: the model was drawn flat red or not at all, framing it printed numpy's
    overflow warning, and a click still picked its faces."""
    path = write_scene(tmp_path, CAMERA + f'[[objects]]\nmodel = "m.obj"\nscale = {scale}\n')
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line == 6
    assert caught.value.message.startswith("objects[1]: scale 1e-"), caught.value.message
    assert "under 1e-18 the GPU's 32-bit numbers cannot light the model (scale it up)" in caught.value.message


def test_a_cameras_scale_sizes_its_body_not_its_view(tmp_path: Path) -> None:
    scene = load_scene(write_scene(tmp_path, CAMERA + "scale = 3\n"))
    camera = scene.camera
    assert np.array_equal(camera.mesh.positions, load_model_as_read(tmp_path / "m.obj").positions * 3)
    assert np.array_equal(camera.model[:3, :3], np.eye(3)) and tuple(camera.origin) == (0.0, 0.0, 10.0)


def test_a_model_read_again_in_its_place_keeps_its_scale(tmp_path: Path) -> None:
    """--watch and PageDown read a file again in an element's place: a sized model came back at its
    file's size, a thousand times too large."""
    from marraztu.control.viewer import BackgroundLoader, Viewer
    from support.scenes import NoFrontend

    viewer = Viewer(load_scene(write_scene(tmp_path, CAMERA + '[[objects]]\nmodel = "m.obj"\nscale = 0.001\n')),
                    NoFrontend())
    element = viewer.scene.objects[0]
    assert viewer.replace_model(element, tmp_path / "m.obj")
    assert np.array_equal(element.mesh.positions, load_model_as_read(tmp_path / "m.obj").positions * 0.001)
    assert element.scale == (0.001, 0.001, 0.001)
    background = BackgroundLoader()  # the window's: read on a worker thread
    try:
        loaded = background.start(tmp_path / "m.obj", as_camera=False, replaces=(element,)).future.result(timeout=60)
    finally:
        background.shutdown()
    assert np.array_equal(loaded.mesh.positions, element.mesh.positions) and loaded.scale == element.scale


def test_absolute_model_path(tmp_path: Path) -> None:
    model = tmp_path / "elsewhere.obj"
    model.write_text(TETRAHEDRON)
    path = write_scene(tmp_path, f'[[cameras]]\nmodel = "{model}"\nposition = [0, 0, 0]\n')
    assert load_scene(path).camera.name == "elsewhere"


# --- bad files -------------------------------------------------------------------------------------
BAD_SCENES = {
    "toml syntax": ('[[cameras]]\nmodel = m.obj\n',
                    'TOML syntax: model: no value TOML reads (text, a file name too, goes in "quotes")'),
    "no value, not text": (CAMERA + "rotation = (0, 0, 0)\n", "TOML syntax: rotation: no value TOML reads$"),
    "string not closed": ('[[cameras]]\nmodel = "m.obj\nposition = [0, 0, 0]\n',
                          'TOML syntax: model: a string in "quotes" is not closed on its line'),
    "literal string not closed": ("[[cameras]]\nmodel = 'm.obj\nposition = [0, 0, 0]\nname = 'c'\n",
                                  "TOML syntax: model: a string in 'quotes' is not closed on its line"),
    "literal string not closed, at the end": ("[[cameras]]\nmodel = 'm.obj\nposition = [0, 0, 0]\n",
                                              "TOML syntax: Expected \"'\" (at end of document)"),  # no line to name
    "key set twice": (CAMERA + "position = [0, 0, 1]\nname = 'c'\n", "TOML syntax: position is set twice in one table"),
    "dotted key over a value": (CAMERA + "name = 'c'\nmodel.kind = 1\n", "TOML syntax: model.kind: Cannot overwrite"),
    # tomllib (3.11 to 3.13) said "material: Cannot mutate immutable namespace ('ka',)" where the values are arrays.
    "key set twice in an inline table": (CAMERA + "material = { ka = [0, 0, 0], ka = [1, 1, 1] }\n",
                                         "TOML syntax: material: ka is set twice in one inline table$"),
    "number set twice in an inline table": (CAMERA + "material = { ns = 1, ns = 2 }\n",
                                            "TOML syntax: material: ns is set twice in one inline table$"),
    "duplicate table": (MATERIAL + "[materials.m]\nns = 1\n",
                        "TOML syntax: [materials.m] is declared twice (first at line 1)"),
    "table after an array of them": (CAMERA + '[cameras]\nmodel = "m.obj"\n',
                                     "TOML syntax: [cameras] is declared twice (first at line 1)"),
    # tomllib says "Cannot declare ... twice" where a key made the table; no header declared it before.
    "table after a dotted key": (CAMERA + "material.ka = [1, 1, 1]\n[cameras.material]\nkd = [1, 1, 1]\n",
                                 "TOML syntax: [cameras.material]: material is already set by a key (line 4)$"),
    "table after an inline one, in a second entry": (
        CAMERA + "material.ka = [1, 1, 1]\n" + CAMERA + "material = { ka = [1, 1, 1] }\n[cameras.material]\n",
        "TOML syntax: [cameras.material]: material is already set by a key (line 8)$"),
    "an array of them after a table": ('[objects]\nmodel = "m.obj"\n' + CAMERA + '[[objects]]\nmodel = "m.obj"\n',
                                       "TOML syntax: [[objects]] after [objects] (line 1): write [[objects]] "
                                       "for every entry$"),
    "an array of them after a value": ("objects = 1\n" + CAMERA + "[[objects]]\nmodel = 'm.obj'\n",
                                       "TOML syntax: [[objects]]: objects is already a table or a value$"),
    "unknown top-level key": ('textures = "a.ppm"\n' + CAMERA, "unknown key 'textures'"),
    "unknown entry key": (CAMERA + "positon = [1, 2, 3]\n", "unknown key 'positon'"),
    "missing model": ("[[objects]]\nposition = [0, 0, 0]\n", "missing key 'model'"),
    "missing position": ('[[cameras]]\nmodel = "m.obj"\n', "missing key 'position' (where the camera looks from"),
    "scale zero": (CAMERA + "[[objects]]\nmodel = \"m.obj\"\nscale = 0\n", "objects[1]: scale must be greater than 0"),
    "scale negative": (CAMERA + "[[objects]]\nmodel = \"m.obj\"\nscale = [1, -2, 1]\n",
                       "objects[1]: scale must be greater than 0 (a size, not a mirror), not -2"),
    "scale two numbers": (CAMERA + "[[objects]]\nmodel = \"m.obj\"\nscale = [1, 2]\n",
                          "objects[1]: scale must be one number or three, like 2 or [1, 2, 1], not 2 numbers"),
    "scale a string": (CAMERA + "[[objects]]\nmodel = \"m.obj\"\nscale = \"2\"\n", "not a string"),
    "scale a boolean": (CAMERA + "scale = true\n", "cameras[1]: scale must be one number or three"),
    "scale nan": (CAMERA + "[[objects]]\nmodel = \"m.obj\"\nscale = nan\n", "scale must be a finite number"),
    "scale infinite": (CAMERA + "[[objects]]\nmodel = \"m.obj\"\nscale = [1, inf, 1]\n", "finite"),
    "scale past float32": (CAMERA + "[[objects]]\nmodel = \"m.obj\"\nscale = 1e39\n", "is too large"),
    "model not a string": ("[[cameras]]\nmodel = 3\nposition = [0, 0, 0]\n", "model must be"),
    "empty model": ('[[cameras]]\nmodel = ""\nposition = [0, 0, 0]\n', "model must name a file (it is empty)$"),
    "name not a string": (CAMERA + "name = 7\n", "name must be"),
    "position too short": ('[[cameras]]\nmodel = "m.obj"\nposition = [0, 0]\n',
                           "cameras[1]: position must be three numbers, like [0, 0, 0], not 2 numbers"),
    "rotation of one number": (CAMERA + "rotation = [90]\n",
                               "rotation must be three numbers, like [0, 0, 0], not 1 number$"),
    "rotation a string": (CAMERA + 'rotation = "90 0 0"\n',
                          "rotation must be three numbers, like [0, 0, 0], not a string"),
    "position not numbers": ('[[cameras]]\nmodel = "m.obj"\nposition = [0, "1", 0]\n',
                             "cameras[1]: position must be three numbers, like [0, 0, 0]: its second is a string"),
    "position a boolean": ('[[cameras]]\nmodel = "m.obj"\nposition = [true, 0, 0]\n', "its first is true/false"),
    "scale of a string among three": (CAMERA + "[[objects]]\nmodel = \"m.obj\"\nscale = [1, 1, \"2\"]\n",
                                      "objects[1]: scale must be one number or three, like 2 or [1, 2, 1]: "
                                      "its third is a string"),
    "position not a list": ('[[cameras]]\nmodel = "m.obj"\nposition = 3\n',
                            "three numbers, like [0, 0, 0], not one number"),
    "position nan": ('[[cameras]]\nmodel = "m.obj"\nposition = [nan, 0, 0]\n', "finite"),
    "position infinite": ('[[cameras]]\nmodel = "m.obj"\nposition = [0, -inf, 0]\n', "finite"),
    "unknown material": (CAMERA + 'material = "gold"\n', "unknown material 'gold'"),
    "material not a table": (CAMERA + "material = 3\n", "material name or a table"),
    "material missing ns": (CAMERA + "material = { ka = [0, 0, 0], kd = [0, 0, 0], ks = [0, 0, 0] }\n",
                            "missing key 'ns'"),
    "material unknown key": (MATERIAL + "kx = [0, 0, 0]\n" + CAMERA, "unknown key 'kx'"),
    "material colour above 1": (MATERIAL.replace("[0.1, 0.2, 0.3]", "[2, 0, 0]") + CAMERA, "between 0 and 1"),
    "material colour negative": (MATERIAL.replace("[0.4, 0.5, 0.6]", "[0, -0.1, 0]") + CAMERA, "between 0 and 1"),
    "material colour as given": (MATERIAL.replace("[0.4, 0.5, 0.6]", "[2, 0, 0.5]") + CAMERA,
                                 "material 'm': kd must be three numbers between 0 and 1, not [2, 0, 0.5]"),
    "material colour 0..255": (CAMERA + "material = { ka = [0, 0, 0], kd = [255, 0, 0], ks = [0, 0, 0], ns = 10 }\n",
                               "cameras[1]: material: kd must be three numbers between 0 and 1, not [255, 0, 0] "
                               "(0..255 colours: divide by 255)"),
    "material colour past 255": (MATERIAL.replace("[0.4, 0.5, 0.6]", "[256, 0, 0]") + CAMERA,
                                 "kd must be three numbers between 0 and 1, not [256, 0, 0]$"),
    "material colour 0..255 with a fraction": (MATERIAL.replace("[0.4, 0.5, 0.6]", "[255, 0.5, 0]") + CAMERA,
                                               "not [255, 0.5, 0]$"),
    "material colour 0..255 as floats": (MATERIAL.replace("[0.1, 0.2, 0.3]", "[128.0, 64, 0]") + CAMERA,
                                         "ka must be three numbers between 0 and 1, not [128.0, 64, 0] (0..255 "),
    "material colour a string": (MATERIAL.replace("[0.7, 0.8, 0.9]", '"red"') + CAMERA, "three numbers"),
    "ns zero": (MATERIAL.replace("ns = 10", "ns = 0") + CAMERA, "greater than 0"),
    "ns negative": (MATERIAL.replace("ns = 10", "ns = -3") + CAMERA, "greater than 0"),
    "ns infinite": (MATERIAL.replace("ns = 10", "ns = inf") + CAMERA, "finite"),
    "rgb wrong size": (MATERIAL + "rgb = [1, 1]\n" + CAMERA, "three numbers"),
    "materials not tables": ("materials = 3\n" + CAMERA, "[materials.NAME]"),
    "cameras not an array": ('[cameras]\nmodel = "m.obj"\nposition = [0, 0, 0]\n', "[[cameras]]"),
    "texture not a string": ("texture = 5\n" + CAMERA, "texture must be"),
    "model file missing": ('[[cameras]]\nmodel = "missing.obj"\nposition = [0, 0, 0]\n', "model missing.obj"),
    "key of 16 parts": (CAMERA + ".".join("abcdefghijklmnop") + " = 1\n", "unknown key 'a'"),
    "key of 17 parts": (CAMERA + ".".join("abcdefghijklmnopq") + " = 1\n", "more than 16 words joined by dots"),
    "17 words joined by dots in a comment": (CAMERA + "# " + ".".join("abcdefghijklmnopq") + "\n",
                                             "more than 16 words joined by dots"),
}


def test_a_camera_may_leave_out_its_model_and_a_scene_its_cameras(tmp_path: Path) -> None:
    """An installed copy's own scene files cannot name the built-in camera model, which lies inside the
    package: every scene needed a camera OBJ of its own beside it."""
    (tmp_path / "m.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    path = tmp_path / "scene.toml"
    path.write_text('[[cameras]]\nposition = [0, 0, 40]\n[[objects]]\nmodel = "m.obj"\nposition = [0, 0, 0]\n')
    scene = load_scene(path)
    builtin = load_builtin_scene()
    assert len(scene.cameras) == 1 and scene.cameras[0].name == "camera"
    assert scene.cameras[0].mesh.face_count == builtin.cameras[0].mesh.face_count
    assert np.allclose(scene.cameras[0].model[:3, 3], [0, 0, 40])
    path.write_text('[[objects]]\nmodel = "m.obj"\nposition = [0, 0, 0]\n')  # none: the built-in scene's
    alone = load_scene(path)
    assert [camera.name for camera in alone.cameras] == [camera.name for camera in builtin.cameras]
    assert np.allclose(alone.cameras[0].model, builtin.cameras[0].model)


@pytest.mark.parametrize("text, expected", BAD_SCENES.values(), ids=BAD_SCENES.keys())
def test_bad_scene_raises_load_error_naming_the_file(tmp_path: Path, text: str, expected: str) -> None:
    path = write_scene(tmp_path, text)
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.path == str(path)
    assert expected in caught.value.message + "$"  # a "$" at its end: nothing (no hint) follows
    assert str(path) in str(caught.value)


# Each a TOML array and the tuple the programming interface is handed: inside, on and past 0..1's ends.
MATERIAL_COLOURS_TRIED = {
    "inside": ("[0.5, 0.25, 0]", (0.5, 0.25, 0.0)),
    "the ends": ("[0, 1, -0.0]", (0.0, 1.0, -0.0)),
    "just above 1": ("[0, 0, 1.000001]", (0.0, 0.0, 1.000001)),
    "2": ("[2, 0, 0]", (2.0, 0.0, 0.0)),
    "just below 0": ("[0, -1e-9, 0]", (0.0, -1e-9, 0.0)),
    "-1": ("[-1, 0, 0]", (-1.0, 0.0, 0.0)),
    "past float32": ("[0, 1e39, 0]", (0.0, 1e39, 0.0)),
}


@pytest.mark.parametrize("key", ["ka", "kd", "ks", "rgb"])
@pytest.mark.parametrize("toml, given", MATERIAL_COLOURS_TRIED.values(), ids=MATERIAL_COLOURS_TRIED.keys())
def test_a_scene_file_and_the_scene_set_by_hand_refuse_the_same_material_colours(
        tmp_path: Path, key: str, toml: str, given: tuple[float, float, float]) -> None:
    """The scene file refused kd [2, 0, 0] and [-1, 0, 0] where Scene.check_by_hand (the programming
    interface's next call) drew them: one rule, the model's, for both."""
    table = {"ka": "[0, 0, 0]", "kd": "[0, 0, 0]", "ks": "[0, 0, 0]", "ns": "1", key: toml}
    path = write_scene(tmp_path, CAMERA + f"material = {{ {', '.join(f'{k} = {v}' for k, v in table.items())} }}\n")
    try:
        load_scene(path)
        file_refused = None
    except LoadError as error:
        file_refused = error.message
    scene = load_scene(write_scene(tmp_path, CAMERA))
    camera = scene.cameras[0]
    camera.material = dataclasses.replace(camera.material, **{key: given})
    camera.part_materials = tuple(camera.material for _ in camera.part_materials)
    try:
        scene.check_by_hand()
        hand_refused = None
    except ValueError as error:
        hand_refused = str(error)
    assert (file_refused is None) == (hand_refused is None), (file_refused, hand_refused)
    if file_refused is not None and "too large" not in file_refused:  # the file's own words for past float32
        as_read = ", ".join(map(str, tomllib.loads(f"v = {toml}")["v"]))  # -1e-9 is shown as Python writes it
        assert f"{key} must be three numbers between 0 and 1, not [{as_read}]" in file_refused
        assert hand_refused.startswith(f"{camera.name}'s material {key} must be 3 numbers between 0 and 1, not ")


def test_a_part_material_set_by_hand_is_held_to_the_same_colours(tmp_path: Path) -> None:
    """A part's material (one per material of the model's file) is drawn as the object's own is."""
    for name in ("two_tone.obj", "two_tone.mtl"):
        (tmp_path / name).write_bytes((ASSET_DIR / "examples" / name).read_bytes())
    scene = load_scene(write_scene(tmp_path, CAMERA + '[[objects]]\nmodel = "two_tone.obj"\n'))
    obj = scene.objects[0]
    obj.part_materials = (obj.part_materials[0], dataclasses.replace(obj.part_materials[1], kd=(0, 0, 2)))
    with pytest.raises(ValueError, match=r"^two_tone's material kd must be 3 numbers between 0 and 1, not \(0, 0, 2\)"):
        scene.check_by_hand()


def test_a_string_of_escaped_quotes_is_looked_at_once(tmp_path: Path) -> None:
    """The search for over-long dotted keys starts no key at an escaped quote: from each, it would scan
    the rest of the string again (a name of 500,000 escaped quotes would have taken about half an hour)."""
    path = write_scene(tmp_path, CAMERA + 'name = "' + '\\"' * 500_000 + '"\n')
    with pytest.raises(LoadError, match=r":4: cameras\[1\]: name is 500000 characters long"):  # read to its end
        load_scene(path)


def test_an_overlong_integer_is_found_without_state_per_digit(tmp_path: Path) -> None:
    """The search for the integer Python refuses skips a comment of thousands of digits in its length (a
    backtracking repeat held over 100 bytes a digit)."""
    from support.work import peak_traced_bytes

    text = ("# " + "1" * 4000 + "x\n") * 250 + CAMERA.replace("[0, 0, 10]", f"[{'9' * 4300}, 0, 0]")
    path = write_scene(tmp_path, text)
    previous = sys.get_int_max_str_digits()
    sys.set_int_max_str_digits(1000)  # a Python that reads fewer digits than the scene reader lets through
    try:
        error, peak = peak_traced_bytes(lambda: load_scene(path))
    finally:
        sys.set_int_max_str_digits(previous)
    assert isinstance(error, LoadError) and (error.line, "thousands of digits" in error.message) == (253, True)
    assert peak < 8 * len(text), peak


@pytest.mark.parametrize("number", ["1" * 1_000_000, "1." + "1" * 1_000_000, "1e" + "1" * 1_000_000,
                                    "0x" + "a" * 1_000_000, "1_" * 500_000 + "1"])
def test_a_number_of_a_million_digits_is_refused_before_toml_reads_it(tmp_path: Path, number: str) -> None:
    """tomllib held about 130 bytes a digit of a number while it read it (a backtracking repeat)."""
    from support.work import peak_traced_bytes

    path = write_scene(tmp_path, CAMERA + f"fov = {number}\n")
    error, peak = peak_traced_bytes(lambda: load_scene(path))
    assert isinstance(error, LoadError) and error.line == 4
    assert error.message == ("more than 4300 digits or letters a to f in a row (in a number, a string or a comment): "
                             "no scene holds so many")
    if POSSESSIVE_GROUPS_HOLD:  # 3.11.0 to 3.11.4 match the digits with an atomic group, which keeps state per digit
        assert peak < 3 * len(number), peak


def test_a_string_of_a_million_letters_a_is_refused_as_hexadecimal_digits(tmp_path: Path) -> None:
    """tomllib's hexadecimal numbers take a to f as digits, so a run of them is refused as a run of digits
    is: it was called 'more than 4300 digits in a row', which a string of letters is not, to read."""
    path = write_scene(tmp_path, CAMERA + f'name = "{"a" * 1_000_000}"\n')
    with pytest.raises(LoadError) as refused:
        load_scene(path)
    assert refused.value.line == 4 and refused.value.message.startswith("more than 4300 digits or letters a to f in")


@pytest.mark.parametrize("suffix", ["", ".obj"])
def test_a_model_name_of_half_a_million_letters_is_cut_in_its_message(tmp_path: Path, suffix: str) -> None:
    """The refusal named it twice, as written and as the path looked at: one line of a million characters."""
    name = "n" * 500_000 + suffix
    (tmp_path / "s.toml").write_text(f'[[objects]]\nmodel = "{name}"\nposition = [0, 0, 0]\n')
    with pytest.raises(LoadError) as raised:
        load_scene(tmp_path / "s.toml")
    shown = str(raised.value)
    assert len(shown) < 2_500 and shown.startswith(f"{tmp_path / 's.toml'}:2: model nnn")
    assert f"{tmp_path}/nnn" in shown and "nnn..." in shown


def test_thousands_of_entries_of_one_model_resolve_its_path_once(tmp_path: Path, monkeypatch) -> None:
    """Resolving a path asks the file system about every folder in it: a third of the reading of a scene
    of 160,000 objects, when it was done for each."""
    from marraztu.loaders import scenefile

    resolved: list[Path] = []
    monkeypatch.setattr(scenefile, "same_file_key", lambda path: resolved.append(path) or path.resolve())
    entry = '[[objects]]\nmodel = "m.obj"\nposition = [1, 2, 3]\n'
    scene = load_scene(write_scene(tmp_path, CAMERA + entry * 2000 + entry.replace("m.obj", "./m.obj")))
    assert len(scene.objects) == 2001 and len({id(obj.mesh) for obj in scene.objects}) == 1
    assert len(resolved) == 2  # m.obj (the camera and the objects) and ./m.obj


def test_syntax_error_gives_tomls_line(tmp_path: Path) -> None:
    path = write_scene(tmp_path, CAMERA + "\n[[objects]]\nmodel = m.obj\n")
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line == 6
    assert "(at line" not in caught.value.message  # the line is in the prefix, not said twice


@pytest.mark.parametrize("end", ["", "\n", "\n\n  \n", "\r\n"])
@pytest.mark.parametrize("cut", ["position = [1,2", 'position = "1', "position = { x = 1", "position = "])
def test_a_syntax_error_at_the_end_gives_the_last_line(tmp_path: Path, cut: str, end: str) -> None:
    """tomllib says "Unclosed array (at end of document)", with no line to put in the file:line prefix."""
    path = write_scene(tmp_path, '[[objects]]\nmodel = "m.obj"\n' + cut + end)
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line == 3 and caught.value.message.startswith("TOML syntax: ")


def test_entry_error_gives_its_tables_line(tmp_path: Path) -> None:
    path = write_scene(tmp_path, CAMERA + '\n[[objects]]\nmodel = "m.obj"\nposition = [0, 0, 0]\n'
                                          '\n[[objects]]\nposition = [0, 0, 0]\n')
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line == 9
    assert "objects[2]" in caught.value.message



def test_error_in_the_last_of_many_entries_names_its_own_line(tmp_path: Path) -> None:
    text = many_entries("objects", 60) + '\n[[objects]]\nmodel = "m.obj"\nposition = [0, 0]\n'
    path = write_scene(tmp_path, text)
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line == text.count("\n") and "objects[61]" in caught.value.message


LINE_ENDS = {
    "windows line ends": ("\r\n", ""),
    # str.splitlines() would end lines at these too; TOML (and tomllib's own line numbers) do not
    "unicode separators in a comment": ("\n", "# one\u2028two\x85three\u2029four\n"),
}


@pytest.mark.parametrize("end, comment", LINE_ENDS.values(), ids=LINE_ENDS.keys())
def test_lines_are_counted_as_toml_counts_them(tmp_path: Path, end: str, comment: str) -> None:
    text = comment + CAMERA + '\n[[objects]]\nmodel = "m.obj"\nposition = [0, "x", 0]\n'
    path = write_scene(tmp_path, text.replace("\n", end))
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line == (8 if comment else 7)


BAD_NS = "ka = [0, 0, 0]\nkd = [0, 0, 0]\nks = [0, 0, 0]\nns = 0\n"
# Names written in each way TOML allows, after the camera (lines 1 to 4); the line the error must name.
QUOTED_AND_DOTTED = {
    "quoted material name": ('[materials."two words"]\n' + BAD_NS, 9),
    "escaped material name": ('[materials."a\\u0020b"]\n' + BAD_NS, 9),
    "spaces around the dot": ("[ materials . m ]\n" + BAD_NS, 9),
    "inline in a [materials] table": ("[materials]\nok = { ka = [0, 0, 0], kd = [0, 0, 0], ks = [0, 0, 0], ns = 1 }\n"
                                      + "bad = { ka = [0, 0, 0], kd = [0, 0, 0], ks = [0, 0, 0], ns = 0 }\n", 7),
    "dotted keys in a [materials] table": ("[materials]\n" + BAD_NS.replace("k", "m.k").replace("ns", "m.ns"), 9),
    "quoted array header": ('[["cameras"]]\nmodel = "m.obj"\nposition = [0, 0, 1]\n'
                            + '\n[[ cameras ]]\nmodel = "m.obj"\nposition = [0, 0]\n', 11),
}


@pytest.mark.parametrize("text, line", QUOTED_AND_DOTTED.values(), ids=QUOTED_AND_DOTTED.keys())
def test_quoted_and_dotted_names_still_find_their_line(tmp_path: Path, text: str, line: int) -> None:
    path = write_scene(tmp_path, CAMERA + "\n" + text)
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line == line


def test_header_inside_a_multi_line_string_gives_no_line_rather_than_a_wrong_one(tmp_path: Path) -> None:
    path = write_scene(tmp_path, CAMERA + '\n[[objects]]\ntexture = """\n[[objects]]\n"""\nmodel = "m.obj"\n'
                                          'position = [0, 0, 0]\n\n[[objects]]\nposition = [0, 0, 0]\n')
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line is None and "objects[2]: missing key 'model'" in caught.value.message


def test_broken_model_names_the_model_and_its_line(tmp_path: Path) -> None:
    (tmp_path / "broken.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    path = write_scene(tmp_path, '[[cameras]]\nmodel = "broken.obj"\nposition = [0, 0, 0]\n')
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.path == str(path) and caught.value.line == 2  # its model key's
    assert caught.value.message.startswith("model broken.obj: ")
    assert "broken.obj:4" in caught.value.message


@pytest.mark.parametrize("model", [".", "models/"])
def test_a_model_without_a_file_name_is_blamed_not_its_name(tmp_path: Path, model: str) -> None:
    """Its name came from the model's stem, empty here: the error blamed a name the file never gave."""
    (tmp_path / "models").mkdir()
    path = write_scene(tmp_path, f'[[cameras]]\nmodel = "{model}"\nposition = [0, 0, 0]\n')
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line == 2 and caught.value.message.startswith(f"model {model}: ")


def test_binary_scene_file(tmp_path: Path) -> None:
    path = tmp_path / "scene.toml"
    path.write_bytes(bytes(range(256)))
    with pytest.raises(LoadError, match="not UTF-8") as caught:
        load_scene(path)
    assert caught.value.path == str(path)
    path.write_bytes("# a scene\n\n# caf\xe9, in Latin-1\n[[objects]]\n".encode("latin-1"))
    with pytest.raises(LoadError, match="not UTF-8") as caught:
        load_scene(path)
    assert caught.value.line == 3


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
                uvs=np.zeros((3, 2), np.float32), normals=np.tile([0, 0, 1], (3, 1)).astype(np.float32),
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


def test_a_files_shininess_past_float32_is_float32s_largest() -> None:
    """The GPU's ns is a float32: 1e300 would be infinite there, and pow(1, inf) NaN."""
    assert material_for_loaded(tiny_mesh({"ns": 1e300})).ns == FLOAT32_MAX
    assert material_for_loaded(tiny_mesh({"ns": 1e9})).ns == 1e9


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


# --- cost grows with the file, not with its square -------------------------------------------------
def many_entries(kind: str, count: int) -> str:
    """A scene of `count` objects, cameras or named materials, each table on lines of its own."""
    if kind == "materials":
        tables = "".join(MATERIAL.replace("[materials.m]", f"[materials.m{i}]") + "\n" for i in range(count))
        return tables + CAMERA + 'material = "m0"\n'
    entries = "".join(f'\n[[{kind}]]\nname = "e{i}"\nmodel = "m.obj"\nposition = [{i}, 0, 0]\n'
                      "rotation = [0, 90, 0]\nmaterial = { ka = [0, 0, 0], kd = [1, 1, 1], ks = [1, 1, 1], ns = 2 }\n"
                      for i in range(count))
    return (CAMERA if kind == "objects" else "") + entries


@pytest.mark.parametrize("kind", ["objects", "cameras", "materials"])
def test_reading_four_times_the_entries_costs_about_four_times_the_work(tmp_path: Path, kind: str) -> None:
    def work(count: int) -> int:
        path = write_scene(tmp_path, many_entries(kind, count))
        return calls_made(lambda: read_scene_description(path))

    small, large = work(100), work(400)
    assert large <= 4.4 * small, f"{kind}: {small} calls for 100 entries, {large} for 400"


# --- what tomllib reads at a hundred bytes a byte, refused before it reads it ------------------------
ALLOWED_TOP = "(allowed: ambient, cameras, lights, materials, objects, texture)"


def unparsed(monkeypatch: pytest.MonkeyPatch) -> None:
    """Fails a test where tomllib reads the scene: what it is handed costs up to 100 bytes a byte."""
    import tomllib

    monkeypatch.setattr(tomllib, "loads", lambda *args, **kwargs: pytest.fail("tomllib read the scene"))


@pytest.mark.parametrize("text, line, name", [
    (CAMERA + "".join(f"[t{i}]\n" for i in range(20_000)), 4, "t0"),
    (CAMERA + "".join(f"[[t{i}]] # a comment\n" for i in range(20_000)), 4, "t0"),
    ("".join(f"t{i} = {{ a = 1 }}\n" for i in range(20_000)) + CAMERA, 1, "t0"),
    ('texture = "t.ppm"\n  "x".y = 1\n' + CAMERA, 2, "x"),
    (CAMERA + "[ 'lamps' . a ]\n", 4, "lamps"),
])
def test_an_unknown_top_level_name_is_refused_at_its_line_before_toml_reads_the_file(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, text: str, line: int, name: str) -> None:
    """tomllib held about 100 bytes for each byte of a file of [t1] [t2]... tables (a megabyte: 111 MB and
    2 s) before the scene's keys were checked, and the unknown one was named without its line."""
    from support.work import peak_traced_bytes

    path = write_scene(tmp_path, text)
    unparsed(monkeypatch)
    error, peak = peak_traced_bytes(lambda: read_scene_description(path))
    assert isinstance(error, LoadError)
    assert (error.message, error.line) == (f"the scene: unknown key {name!r} {ALLOWED_TOP}", line)
    assert peak < 4 * len(text) + (64 << 10), peak  # the text, and a few objects


KNOWN_NAMES_WRITTEN_OTHERWISE = (
    '"texture" = "t.ppm"\nmaterials.q = { ka = [0, 0, 0], kd = [0, 0, 0], ks = [0, 0, 0], ns = 1 }\n'
    '[ materials . m ]\nka = [0, 0, 0]\nkd = [0, 0, 0]\nks = [0, 0, 0]\nns = 1\n'
    '[["cam\\u0065ras"]]\nmodel = "m.obj"\nposition = [0, 0, 1]\n[[ \'objects\' ]] # one\n'
    'model = "m.obj"\nposition = [1, 0, 0]\nname = "o"\n[objects.material]\nka = [0, 0, 0]\nkd = [0, 0, 0]\n'
    "ks = [0, 0, 0]\nns = 2\n")


@pytest.mark.parametrize("texture, text", [  # a name is one line: the texture's file name holds the header
    ("t.ppm", KNOWN_NAMES_WRITTEN_OTHERWISE),
    ("[lamps]\n", KNOWN_NAMES_WRITTEN_OTHERWISE.replace('"t.ppm"', '"""\n[lamps]\n"""')),
    ("[lamps]\n", KNOWN_NAMES_WRITTEN_OTHERWISE.replace('"t.ppm"', "\'\'\'\n[lamps]\n\'\'\'")),
])
def test_top_level_names_quoted_split_or_in_a_multi_line_string_are_read_as_before(tmp_path: Path, texture: str,
                                                                                    text: str) -> None:
    """Quoted, escaped, dotted or spaced, they are the known ones; a header-like line in a multi-line
    string is no header, so the look for unknown names is not made where the text holds one."""
    description = read_scene_description(write_scene(tmp_path, text))
    assert [entry.name for entry in description.objects] == ["o"] and description.texture_path.name == texture
    assert description.objects[0].material.ns == 2 and description.cameras[0].position == (0.0, 0.0, 1.0)


def test_a_scene_larger_than_a_scene_is_refused_before_toml_reads_it(tmp_path: Path,
                                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    """Known names cost tomllib as much ([materials.mN] tables: 47 bytes a byte): only 1 MiB is parsed."""
    from marraztu.loaders.scenefile import SCENE_FILE_LIMIT
    from support.work import peak_traced_bytes

    text = CAMERA + "".join(f"[materials.m{i}]\n" for i in range(SCENE_FILE_LIMIT // 16))
    path = write_scene(tmp_path, text)
    unparsed(monkeypatch)
    error, peak = peak_traced_bytes(lambda: read_scene_description(path))
    assert isinstance(error, LoadError) and error.line is None
    assert error.message == "file too large for a scene (more than 1 MiB; a thousand objects take about 100 KB)"
    assert peak < 4 * len(text), peak


def test_a_scene_of_a_thousand_objects_is_far_within_the_limit(tmp_path: Path) -> None:
    from marraztu.loaders.scenefile import SCENE_FILE_LIMIT

    text = many_entries("objects", 1000)
    assert len(text) < SCENE_FILE_LIMIT // 4
    assert len(read_scene_description(write_scene(tmp_path, text)).objects) == 1000


# --- numbers past what the GPU's float32 can hold ----------------------------------------------------
TOO_LARGE = "is too large: the GPU's 32-bit numbers end at 3.4e38"
# Where a number goes, with {n} for it, and the line an error there must name: the line of its key.
NUMBER_PLACES = {
    "object position": (CAMERA + '\n[[objects]]\nmodel = "m.obj"\nposition = [{n}, 0, 0]\n', 7),
    "camera position": ('[[cameras]]\nmodel = "m.obj"\nposition = [0, 0, {n}]\n', 3),
    "camera rotation": ('[[cameras]]\nmodel = "m.obj"\nposition = [0, 0, 0]\nrotation = [0, {n}, 0]\n', 4),
    "named material ns": (CAMERA + "\n" + MATERIAL.replace("ns = 10", "ns = {n}"), 9),
    "named material colour": (MATERIAL.replace("[0.1, 0.2, 0.3]", "[0, {n}, 0]") + CAMERA, 2),
    "inline material ns": (CAMERA + "material = { ka = [0, 0, 0], kd = [0, 0, 0], ks = [0, 0, 0], ns = {n} }\n", 4),
}
TOO_LARGE_NUMBERS = {"400-digit integer": "9" * 400, "40-digit integer": "1" + "0" * 39,
                     "1e39": "1e39", "-1e308": "-1e308", "just past float32": "3.5e38"}


@pytest.mark.parametrize("template, line", NUMBER_PLACES.values(), ids=NUMBER_PLACES.keys())
@pytest.mark.parametrize("number", TOO_LARGE_NUMBERS.values(), ids=TOO_LARGE_NUMBERS.keys())
def test_number_past_float32_is_refused_naming_file_and_line(tmp_path: Path, template: str, line: int,
                                                             number: str) -> None:
    path = write_scene(tmp_path, template.replace("{n}", number))
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert (caught.value.path, caught.value.line) == (str(path), line)
    assert caught.value.message.endswith(TOO_LARGE), caught.value.message
    assert len(str(caught.value)) < 200 and "\n" not in str(caught.value)  # never all 400 digits


# A position past its element's reach is refused too (test_a_position_past_an_elements_reach_is_refused_at_its_line).
UNBOUNDED_PLACES = {place: template for place, (template, _) in NUMBER_PLACES.items()
                    if "colour" not in place and "position" not in place}


@pytest.mark.parametrize("template", UNBOUNDED_PLACES.values(), ids=UNBOUNDED_PLACES.keys())
@pytest.mark.parametrize("number", ["1e38", "3.4e38", "340282346638528859811704183484516925440"])
def test_number_within_float32_is_accepted(tmp_path: Path, template: str, number: str) -> None:
    scene = load_scene(write_scene(tmp_path, template.replace("{n}", number)))
    assert scene.camera is not None


def test_integer_too_long_for_python_to_read_names_its_line(tmp_path: Path) -> None:
    """Python refuses to turn thousands of decimal digits into an integer: still a LoadError, not a ValueError
    (refused before the TOML reader reads it; with a Python that reads fewer digits, after)."""
    path = write_scene(tmp_path, CAMERA + '\n[[objects]]\nmodel = "m.obj"\nposition = [1, ' + "9" * 4301 + ", 0]\n")
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert (caught.value.path, caught.value.line) == (str(path), 7)
    assert caught.value.message.startswith("more than 4300 digits or letters") and len(str(caught.value)) < 200
    previous = sys.get_int_max_str_digits()
    sys.set_int_max_str_digits(1000)
    try:
        with pytest.raises(LoadError) as caught:
            load_scene(write_scene(tmp_path, CAMERA.replace("10]", "9" * 4300 + "]")))
    finally:
        sys.set_int_max_str_digits(previous)
    assert caught.value.line == 3 and caught.value.message.endswith(TOO_LARGE)


def test_huge_numbers_in_a_models_own_material_fall_back_to_the_default() -> None:
    material = material_for_loaded(tiny_mesh({"kd": (10**400, 0, 0), "ns": -(10**400)}))
    assert material.kd == DEFAULT_MATERIAL.kd and material.ns == DEFAULT_MATERIAL.ns


def test_screenshot_refuses_a_huge_number_in_one_line(tmp_path: Path) -> None:
    """Through a real `python -m marraztu`: exit 1, one line on stderr naming file and line, no traceback."""
    path = write_scene(tmp_path, NUMBER_PLACES["object position"][0].replace("{n}", "9" * 400))
    out = tmp_path / "out.png"
    argv = [sys.executable, "-m", "marraztu", "screenshot", "-o", str(out), "--scene", str(path)]
    done = subprocess.run(argv, check=False, capture_output=True, text=True, timeout=120,
                          env={**os.environ, "PYTHONIOENCODING": "utf-8"})
    lines = done.stderr.splitlines()
    assert done.returncode == 1 and len(lines) == 1, done.stderr
    assert f"{path}:7: " in lines[0] and lines[0].endswith(TOO_LARGE)
    assert not out.exists()


def test_the_line_index_of_a_long_scene_holds_no_list_of_its_lines() -> None:
    from marraztu.loaders import scenefile
    from support.work import peak_traced_bytes

    text = '[[objects]]\nmodel = "m.obj"\nnote = """\n' + "ab\n" * 300_000 + '"""\n'
    index, peak = peak_traced_bytes(lambda: scenefile._LineIndex.of(text))
    assert index.array_lines[("objects",)] == [1]
    assert peak < len(text) // 8, peak


def _two_quads(tmp_path: Path, texture_line: str) -> Path:
    (tmp_path / "quad.obj").write_text("v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n")
    from PIL import Image

    Image.new("RGB", (2, 2), (255, 0, 0)).save(tmp_path / "red.png")
    left = f'[[objects]]\nname = "left"\nmodel = "quad.obj"\nposition = [-1.5, 0, 0]\n{texture_line}'
    right = '[[objects]]\nname = "right"\nmodel = "quad.obj"\nposition = [1.5, 0, 0]\n'
    return write_scene(tmp_path, '[[cameras]]\nposition = [0, 0, 6]\n' + left + right)


def test_an_objects_own_texture_is_drawn_in_place_of_the_scenes(tmp_path: Path) -> None:
    """A floor and a wall could only wear the scene's test picture: a scene file gave no object a
    picture of its own, as an MTL's map_Kd gives one."""
    from PIL import Image

    from marraztu.control.viewer import StartOptions
    from marraztu.frontends.screenshot import take_screenshot

    path = _two_quads(tmp_path, 'texture = "red.png"\n')
    scene = load_scene(path)
    left, right = scene.objects
    assert left.picture_of(-1) is not None and (left.picture_of(-1) == (255, 0, 0)).all()
    assert right.picture_of(-1) is None  # the scene's
    shot = take_screenshot(StartOptions(scene_file=path), tmp_path / "shot.png", (120, 60), keys="0 1")
    pixels = np.asarray(Image.open(shot).convert("RGB")).astype(int)
    left_pixels, right_pixels = pixels[27:33, 49:55].reshape(-1, 3), pixels[27:33, 64:70].reshape(-1, 3)
    assert (left_pixels[:, 0] > 0).all() and (left_pixels[:, 1:] == 0).all()
    assert (right_pixels[:, 1:] > 0).any()


def test_an_objects_texture_stays_when_its_file_is_read_again_in_its_place(tmp_path: Path) -> None:
    from marraztu.control.viewer import Viewer
    from support.scenes import NoFrontend

    viewer = Viewer(load_scene(_two_quads(tmp_path, 'texture = "red.png"\n')), NoFrontend())
    left = viewer.scene.objects[0]
    picture = left.picture
    assert viewer.replace_model(left, tmp_path / "m.obj")  # PageDown's and --watch's way
    assert left.picture is picture and left.picture_of(-1) is picture


def test_an_objects_texture_that_cannot_be_read_is_refused_at_its_line(tmp_path: Path,
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    """Named once, as the file looked for: 'texture models/nope.png: models/nope.png' said the name twice, and
    from a scene given by a relative path, neither said where it was looked for."""
    _two_quads(tmp_path, 'texture = "pictures/missing.png"\n')
    monkeypatch.chdir(tmp_path)
    with pytest.raises(LoadError) as caught:
        load_scene("scene.toml")
    looked_for = tmp_path / "pictures" / "missing.png"
    assert str(caught.value) == f"scene.toml:7: objects[1]: texture: {looked_for}: no such file"


def _shot(path: Path, tmp_path: Path, keys: str = "0 1", texture: Path | None = None) -> np.ndarray:
    """The scene file's picture with the sun and the bulb on (their highlights are what a plain model shows)."""
    from PIL import Image

    from marraztu.control.viewer import StartOptions
    from marraztu.frontends.screenshot import take_screenshot

    shot = take_screenshot(StartOptions(scene_file=path, texture=texture), tmp_path / "shot.png", (120, 60), keys=keys)
    return np.asarray(Image.open(shot).convert("RGB")).astype(int)


def _white_png(tmp_path: Path) -> None:
    from PIL import Image

    Image.new("RGB", (1, 1), (255, 255, 255)).save(tmp_path / "white.png")


def _quad_with_its_own_picture(tmp_path: Path) -> str:
    """An entry whose model's MTL gives it a green picture: its own, as a map_Kd is."""
    from PIL import Image

    Image.new("RGB", (2, 2), (0, 255, 0)).save(tmp_path / "green.png")
    (tmp_path / "own.mtl").write_text("newmtl g\nKd 1 1 1\nmap_Kd green.png\n")
    (tmp_path / "own.obj").write_text("mtllib own.mtl\nusemtl g\nv -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n")
    return '[[objects]]\nname = "own"\nmodel = "own.obj"\nposition = [1.5, 0, 0]\n'


LEFT, RIGHT = (slice(27, 33), slice(49, 55)), (slice(27, 33), slice(64, 70))  # inside each quad of _two_quads


def test_an_objects_texture_false_is_drawn_as_a_white_picture_named_there_is(tmp_path: Path) -> None:
    """A lesson on highlights wants its models plain: `texture = false` was refused ('must be a non-empty
    string in quotes'), and the README's way was a white picture made by hand."""
    from marraztu.model.mesh import PLAIN_PICTURE

    _white_png(tmp_path)
    plain = _two_quads(tmp_path, "texture = false\n")
    left, right = load_scene(plain).objects
    assert left.picture is PLAIN_PICTURE and left.picture_source is None and right.picture is None
    pixels = _shot(plain, tmp_path)
    _two_quads(tmp_path, 'texture = "white.png"\n')
    assert np.array_equal(pixels, _shot(plain, tmp_path))  # the same pixels, highlights included
    left_pixels, right_pixels = pixels[LEFT].reshape(-1, 3), pixels[RIGHT].reshape(-1, 3)
    assert (left_pixels != pixels[0, 0]).any(axis=1).all()  # drawn, not the background
    assert len(np.unique(right_pixels, axis=0)) > 1 and len(np.unique(left_pixels, axis=0)) == 1  # selfi vs plain


def test_an_objects_texture_false_takes_its_models_own_picture_away_too(tmp_path: Path) -> None:
    from marraztu.model.mesh import PLAIN_PICTURE

    entry = _quad_with_its_own_picture(tmp_path)
    obj = load_scene(write_scene(tmp_path, CAMERA + entry + "texture = false\n")).objects[0]
    assert obj.picture_of(0) is PLAIN_PICTURE and obj.picture_of(-1) is PLAIN_PICTURE


def test_a_scenes_texture_false_shows_no_picture_and_keeps_a_models_own(tmp_path: Path) -> None:
    """The scene's objects without a picture of their own wear none (no checker, no message); the model
    whose MTL gives one keeps it, as a scene's texture only ever stood in for the scene's picture."""
    from marraztu.control.viewer import StartOptions, Viewer
    from marraztu.model.mesh import PLAIN_PICTURE
    from support.scenes import NoFrontend

    _white_png(tmp_path)
    right = '[[objects]]\nname = "right"\nmodel = "quad.obj"\nposition = [1.5, 0, 0]\n'
    quads = _two_quads(tmp_path, "").read_text().replace(right, _quad_with_its_own_picture(tmp_path))
    path = write_scene(tmp_path, "texture = false\n" + quads)
    scene = load_scene(path)
    assert scene.texture_plain and scene.texture_path is None and scene.texture_named_at is None
    viewer = Viewer(scene, NoFrontend())
    viewer.start(StartOptions(scene_file=path), longest_texture_side=4096)
    assert scene.texture is PLAIN_PICTURE and "checker" not in scene.message
    pixels = _shot(path, tmp_path)
    assert np.array_equal(pixels[LEFT], _shot(path, tmp_path, keys="0 1 T")[LEFT])  # T: nothing to take away
    own = pixels[RIGHT].reshape(-1, 3)
    assert (own[:, 1] > 0).all() and (own[:, [0, 2]] == 0).all()  # its green picture
    path.write_text('texture = "white.png"\n' + quads)
    assert np.array_equal(pixels, _shot(path, tmp_path))


@pytest.mark.parametrize("where", ["scene", "object"])
def test_the_probe_of_a_face_that_wears_no_picture_says_none_multiplies_it(tmp_path: Path, where: str) -> None:
    from marraztu.control.viewer import StartOptions, Viewer
    from marraztu.model.probe import probe
    from support.scenes import NoFrontend

    path = _two_quads(tmp_path, "texture = false\n" if where == "object" else "")
    if where == "scene":
        path.write_text("texture = false\n" + path.read_text())
    viewer = Viewer(load_scene(path), NoFrontend())
    viewer.start(StartOptions(scene_file=path), longest_texture_side=64)
    found = probe(viewer.scene)
    assert viewer.scene.modes.texture and found is not None and not found.textured
    copied = copy.deepcopy(viewer.scene)  # as the programming interface's refusal to copy a viewer suggests
    assert not probe(copied).textured  # the shared white copied too: its pixels, not its identity, say so


def test_the_command_lines_texture_stands_in_for_a_scenes_texture_false(tmp_path: Path) -> None:
    from marraztu.control.viewer import StartOptions, Viewer
    from support.scenes import NoFrontend

    path = _two_quads(tmp_path, "")
    path.write_text("texture = false\n" + path.read_text())
    viewer = Viewer(load_scene(path), NoFrontend())
    viewer.start(StartOptions(scene_file=path, texture=tmp_path / "red.png"), longest_texture_side=4096)
    assert (viewer.scene.texture == (255, 0, 0)).all()


@pytest.mark.parametrize("text, said", [
    ("texture = true\n" + CAMERA, ":1: texture = true names no picture: name a file in quotes, or write false for "
                                   "none"),
    (CAMERA + "texture = true\n", ":4: cameras[1]: texture = true names no picture: name a file in quotes, or write "
                                   "false for none"),
    ("texture = 5\n" + CAMERA, ":1: texture must be a file name in quotes, or false for no picture, not one number"),
    ('[[objects]]\nmodel = "m.obj"\ntexture = [1]\n', ":3: objects[1]: texture must be a file name in quotes, or "
                                                      "false for no picture, not an array"),
], ids=["scene's true", "an entry's true", "scene's number", "an entry's array"])
def test_a_texture_neither_a_name_nor_false_is_refused_at_its_line(tmp_path: Path, text: str, said: str) -> None:
    path = write_scene(tmp_path, text)
    assert _refusal(path) == f"{path}{said}"


@pytest.mark.parametrize("suffix", [".obj", ".STL", ".glb"])
def test_a_model_file_given_as_the_scene_says_so(tmp_path: Path, suffix: str) -> None:
    """Viewer(scene="x.obj") or --scene x.obj, where the model was meant: not a TOML syntax error at its line 3."""
    path = tmp_path / f"model{suffix}"
    path.write_text(TETRAHEDRON)
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert caught.value.line is None
    assert caught.value.message.startswith("a model file, not a TOML scene file")


def test_an_objects_material_stays_when_its_file_is_read_again_in_its_place(tmp_path: Path) -> None:
    """--watch read a scene's red sphere again as the viewer's grey: the scene file's material was
    dropped for the file's, where its scale and texture stayed."""
    from marraztu.control.viewer import Viewer
    from support.scenes import NoFrontend

    material = 'material = { ka = [0.1, 0, 0], kd = [0.9, 0, 0], ks = [0, 0, 0], ns = 10 }\n'
    viewer = Viewer(load_scene(_two_quads(tmp_path, material)), NoFrontend())
    left, right = viewer.scene.objects
    given, plain, parts = left.material, right.material, left.part_materials
    assert given.kd == (0.9, 0.0, 0.0)
    for element in (left, right):
        assert viewer.replace_model(element, element.source)  # --watch's way: the same file again
    assert left.material == given and left.part_materials == parts
    assert right.material == plain  # no material in the scene: its file's, as before


def test_an_objects_name_stays_when_its_own_file_is_read_again(tmp_path: Path) -> None:
    """--watch renamed a scene's "left" to its file's "quad" when quad.obj was saved, where its material,
    scale and texture stayed; another file in its place (PageDown's) still takes that file's name."""
    from marraztu.control.viewer import Viewer
    from support.scenes import NoFrontend

    viewer = Viewer(load_scene(_two_quads(tmp_path, "")), NoFrontend())
    left, right = viewer.scene.objects
    assert viewer.replace_model(left, left.source)  # --watch's way: the same file again
    (tmp_path / "tri.obj").write_text(TETRAHEDRON)
    assert viewer.replace_model(right, tmp_path / "tri.obj")
    assert [left.name, right.name] == ["left", "tri"]


WINDOWS_PATHS = {
    "model, basic string": ('model = "sub\\\\m.obj"\n', "", ":2: model sub\\m.obj: ", " (use / between folders)"),
    "model, literal string": ("model = 'sub\\m.obj'\n", "", ":2: model sub\\m.obj: ", " (use / between folders)"),
    "model with a drive": ("model = 'C:\\Users\\t\\m.obj'\n", "", ":2: model C:\\Users\\t\\m.obj: ",
                           " (use / between folders; C: is a Windows drive)"),
    "model with a drive, slashes": ("model = 'C:/Users/t/m.obj'\n", "", ":2: model C:/Users/t/m.obj: ",
                                    " (C: is a Windows drive)"),
    "texture": ('model = "sub/m.obj"\n', "texture = 'sub\\red.png'\n", ":3: objects[1]: texture: ",
                " (use / between folders)"),
    "model missing, no back slash": ('model = "sub/n.obj"\n', "", ":2: model sub/n.obj: ", ""),
}


@pytest.mark.skipif(os.sep == "\\", reason="a back slash is a folder separator on Windows")
@pytest.mark.parametrize("model, texture, where, hint", WINDOWS_PATHS.values(), ids=WINDOWS_PATHS.keys())
def test_a_windows_path_not_found_says_to_use_slashes(tmp_path: Path, model: str, texture: str, where: str,
                                                      hint: str) -> None:
    """A teacher's models\\ico.obj, written on Windows, was only 'no such file', the back slash unseen in it."""
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "m.obj").write_text(TETRAHEDRON)
    path = write_scene(tmp_path, "[[objects]]\n" + model + texture)
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert str(caught.value).startswith(f"{path}{where}")
    assert str(caught.value).endswith(f": no such file{hint}")


@pytest.mark.skipif(os.sep == "\\", reason="a back slash is a folder separator on Windows")
@pytest.mark.parametrize("model, texture, where", [
    ('model = "gone.obj"\n', "", ":2: model gone.obj: "),
    ('model = "m.obj"\n', 'texture = "gone.png"\n', ":3: objects[1]: texture: "),
], ids=["model", "texture"])
def test_a_missing_file_in_a_folder_whose_name_holds_a_back_slash_gets_no_windows_hint(
        tmp_path: Path, model: str, texture: str, where: str) -> None:
    """The hint looked at the whole path, the scene's folder in it: a Linux folder named a\\b gave
    'gone.obj: no such file (use / between folders)', where the name written has no back slash."""
    folder = tmp_path / "a\\b"
    folder.mkdir()
    path = write_scene(folder, "[[objects]]\n" + model + texture)
    with pytest.raises(LoadError) as caught:
        load_scene(path)
    assert str(caught.value).startswith(f"{path}{where}") and str(caught.value).endswith(": no such file")


@pytest.mark.skipif(os.sep == "\\", reason="a drive and a back slash are Windows's")
@pytest.mark.parametrize("typed, hint", [("C:/Users/m.obj", " (C: is a Windows drive)"),
                                         ("sub\\m.obj", " (use / between folders)"),
                                         ("C:\\Users\\m.obj", " (use / between folders; C: is a Windows drive)"),
                                         ("sub/m.obj", "")])
def test_a_missing_path_as_typed_says_what_of_it_is_windows(typed: str, hint: str) -> None:
    """As the command line gives it: C:/Users/m.obj, a drive with forward slashes, got no hint."""
    with pytest.raises(LoadError) as caught:
        load_model_as_read(Path(typed))
    assert str(caught.value) == f"{typed}: no such file{hint}"


@pytest.mark.skipif(os.sep == "\\", reason="a back slash is a folder separator on Windows")
def test_a_file_whose_name_holds_a_back_slash_is_read(tmp_path: Path) -> None:
    (tmp_path / "sub\\m.obj").write_text(TETRAHEDRON)
    scene = load_scene(write_scene(tmp_path, "[[objects]]\nmodel = 'sub\\m.obj'\n"))
    assert scene.objects[0].name == "sub\\m"


@pytest.mark.parametrize("text, said", [
    ('texture = ""\n' + CAMERA, ':1: texture must name a file (it is empty)'),
    ("texture = '  '\n" + CAMERA, ':1: texture must name a file (it is blank)'),
    (CAMERA + 'texture = ""\n', ':4: cameras[1]: texture must name a file (it is empty)'),
    ('[[objects]]\nmodel = ""\n', ':2: objects[1]: model must name a file (it is empty)'),
], ids=["scene's texture", "blank", "an entry's texture", "model"])
def test_an_empty_file_name_is_said_to_name_no_file(tmp_path: Path, text: str, said: str) -> None:
    """texture = "" said 'texture must be a file name in quotes', though it is in quotes."""
    path = write_scene(tmp_path, text)
    assert _refusal(path) == f"{path}{said}"



ESCAPES = ('a back slash inside "double quotes" starts an escape{}; use / between folders (or, on Windows, '
           "'single quotes')")
MADE = " ({} made {}: " + ESCAPES.format("") + ")"
ESCAPED_PATHS = {  # the scene, where the message is, and what it says after that; {} the scene's folder
    "\\f": ('[[objects]]\nmodel = "models\\floor.obj"\n',
            ":2: model models\\floor.obj: {}/models\\x0cloor.obj: no such file" + MADE.format("\\f", "a form feed")),
    "\\n": ('[[objects]]\nmodel = "models\\new_ball.obj"\n',
            ":2: model models\\new_ball.obj: {}/models\\new_ball.obj: no such file" + MADE.format("\\n", "a line end")),
    "\\b": ('[[objects]]\nmodel = "models\\ball.obj"\n',
            ":2: model models\\ball.obj: {}/models\\x08all.obj: no such file" + MADE.format("\\b", "a backspace")),
    "\\r": ('[[objects]]\nmodel = "models\\rock.obj"\n',
            ":2: model models\\rock.obj: {}/models\\rock.obj: no such file" + MADE.format("\\r", "a carriage return")),
    "\\U": ('[[objects]]\nmodel = "C:\\Users\\teacher\\floor.obj"\n',
            ":2: TOML syntax: model: " + ESCAPES.format(" (\\U here)")),
    "\\w": ('[[objects]]\nmodel = "models\\wood_floor.obj"\n',
            ":2: TOML syntax: model: " + ESCAPES.format(" (\\w here)")),
    "\\u, no character": ('[[objects]]\nmodel = "a\\udead.obj"\n',
                          ":2: TOML syntax: model: " + ESCAPES.format(" (\\u here)")),
    "an entry's texture": (CAMERA + 'texture = "pics\\floor.png"\n',
                           ":4: cameras[1]: texture: {}/pics\\x0cloor.png: no such file"
                           + MADE.format("\\f", "a form feed")),
    "a control character by its code": ('[[objects]]\nmodel = "a\\u0001b.obj"\n',
                                        ":2: model a\\x01b.obj: {}/a\\x01b.obj: no such file (it holds a control "
                                        "character, " + ESCAPES.format("") + ")"),
}


@pytest.mark.skipif(os.sep == "\\", reason="the paths expected are joined with /")
@pytest.mark.parametrize("text, said", ESCAPED_PATHS.values(), ids=ESCAPED_PATHS.keys())
def test_a_windows_path_in_double_quotes_says_its_back_slashes_start_escapes(tmp_path: Path, text: str,
                                                                              said: str) -> None:
    """model = "models\\floor.obj" said 'model models\\x0cloor.obj: .../models\\x0cloor.obj: no such file' (\\f a
    form feed), "models\\new_ball.obj" the same without a hint, "C:\\Users..." 'Invalid hex value' and
    "models\\wood_floor.obj" "Unescaped '\\' in a string"."""
    path = write_scene(tmp_path, text)
    assert _refusal(path) == f"{path}{said.format(tmp_path)}"


@pytest.mark.skipif(os.sep == "\\", reason="the path expected is joined with /")
def test_the_scenes_own_texture_in_double_quotes_says_its_back_slashes_start_escapes(tmp_path: Path) -> None:
    """texture = "pics\\tex.png" (a tab in it) said at start '...: no such file (using the built-in checker
    texture)', with no word of the escape."""
    from marraztu.control.viewer import read_texture

    path = write_scene(tmp_path, 'texture = "pics\\tex.png"\n' + CAMERA)
    said = read_texture(load_scene(path), None, 1024)
    assert said == [f"{path}:1: texture: {tmp_path}/pics\\tex.png: no such file" + MADE.format("\\t", "a tab")
                    + " (using the built-in checker texture)"]


SYNTAX_SLIPS = {
    "a comma missing": (CAMERA + "rotation = [0, 80 60]\n",
                        ":4: TOML syntax: rotation: Unclosed array (a comma missing between values?)"),
    "a comma missing, a line on": (CAMERA + "rotation = [0,\n80 60]\n",
                                   ":5: TOML syntax: Unclosed array (a comma missing between values?)"),
    "[objects]": ('[objects]\nmodel = "m.obj"\n' + CAMERA + '[objects]\nmodel = "m.obj"\n',
                  ":6: TOML syntax: [objects] is declared twice (first at line 1): each object is [[objects]], with "
                  "double brackets"),
    "[cameras]": (CAMERA + "[cameras]\nposition = [0, 0, 1]\n",
                  ":4: TOML syntax: [cameras] is declared twice (first at line 1): each camera is [[cameras]], with "
                  "double brackets"),
    "True": (CAMERA + "[lights.bulb]\non = True\n",
             ":5: TOML syntax: on: no value TOML reads (TOML writes true and false in lower case)"),
    "FALSE": (CAMERA + "[lights.bulb]\non = FALSE\n",
              ":5: TOML syntax: on: no value TOML reads (TOML writes true and false in lower case)"),
    "Yes": (CAMERA + "[lights.bulb]\non = Yes\n",
            ":5: TOML syntax: on: no value TOML reads (TOML writes yes and no as true and false, in lower case)"),
    "a word, as before": (CAMERA + "[lights.bulb]\non = maybe\n",
                          ':5: TOML syntax: on: no value TOML reads (text, a file name too, goes in "quotes")'),
    "a name with a space": (CAMERA + "[lights.camera spotlight]\non = true\n",
                            ":4: TOML syntax: Expected ']' at the end of a table declaration (a name with spaces is "
                            "written with _: [lights.camera_spotlight])"),
}


@pytest.mark.parametrize("text, said", SYNTAX_SLIPS.values(), ids=SYNTAX_SLIPS.keys())
def test_a_slip_tomllib_names_in_its_words_says_what_was_meant(tmp_path: Path, text: str, said: str) -> None:
    """A teacher's [0, 80 60], [objects] written twice, on = True and [lights.camera spotlight] got only
    tomllib's words: Unclosed array, declared twice, no value TOML reads (text goes in "quotes"), Expected ']'."""
    path = write_scene(tmp_path, text)
    assert _refusal(path) == f"{path}{said}"


@pytest.mark.parametrize("entry, said", [
    ('model = "M.obj"\n', ":2: model M.obj: {}/M.obj: no such file (did you mean m.obj?)"),
    ('model = "m.obj"\ntexture = "Red.PNG"\n',
     ":3: objects[1]: texture: {}/Red.PNG: no such file (did you mean red.png?)"),
    ('model = "sub\\\\M.obj"\n', ":2: model sub\\M.obj: {}/sub\\M.obj: no such file (use / between folders)"),
    ('model = "sub/M.obj"\n', ":2: model sub/M.obj: {}/sub/M.obj: no such file (did you mean sub/m.obj?)"),
], ids=["model", "texture", "a Windows path", "in a folder: named as written"])
@pytest.mark.skipif(os.sep == "\\", reason="Windows reads names in any case")
def test_a_file_named_in_another_case_says_which_was_meant(tmp_path: Path, entry: str, said: str) -> None:
    """model = "Sphere.obj" beside sphere.obj said only 'no such file'."""
    (tmp_path / "red.png").write_bytes(b"")
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "m.obj").write_bytes(b"")  # only named: the model not found is sub/M.obj
    path = write_scene(tmp_path, "[[objects]]\n" + entry)
    assert _refusal(path) == f"{path}{said.format(tmp_path)}"


@pytest.mark.skipif(os.sep == "\\", reason="Windows reads names in any case")
def test_a_name_two_files_match_but_for_case_gets_no_guess(tmp_path: Path) -> None:
    (tmp_path / "Ball.obj").write_text(TETRAHEDRON)
    (tmp_path / "BALL.obj").write_text(TETRAHEDRON)
    (tmp_path / "ball.OBJ").mkdir()  # a folder is no model
    with pytest.raises(LoadError) as caught:
        load_model_as_read(tmp_path / "ball.obj")
    assert str(caught.value) == f"{tmp_path}/ball.obj: no such file"
    (tmp_path / "BALL.obj").unlink()
    with pytest.raises(LoadError) as caught:
        load_model_as_read(tmp_path / "ball.obj")  # as the command line and `f` name it
    assert str(caught.value) == f"{tmp_path}/ball.obj: no such file (did you mean Ball.obj?)"


@pytest.mark.skipif(os.sep == "\\", reason="Windows reads names in any case")
def test_a_missing_file_lists_its_folder_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Cost: one listing of the folder, only where the file is missing (a scene's model named as written again)."""
    listed = []
    real_scandir = os.scandir
    monkeypatch.setattr(os, "scandir", lambda folder: listed.append(folder) or real_scandir(folder))
    load_scene(write_scene(tmp_path, '[[objects]]\nmodel = "m.obj"\n'))
    assert listed == []
    with pytest.raises(LoadError, match=r"\(did you mean m\.obj\?\)$"):
        load_scene(write_scene(tmp_path, '[[objects]]\nmodel = "M.obj"\n'))
    assert listed == [str(tmp_path)]


DARK = "is in 0..255 units (so nearly dark): [255, 255, 255] is full white"
DIM_LIGHTS = ("ambient = [1.0, 1.0, 1.0]\n" + CAMERA + "[lights.bulb]\non = true\nintensity = [1.0, 1.0, 1.0]\n"
              "[lights.sun]\nintensity = [0, 0, 0]\n[lights.camera_spotlight]\nintensity = [1, 2, 0]\n"
              "[lights.object_spotlight]\nintensity = [0, 0.5, 0]\n")


def test_an_intensity_written_in_0_to_1_is_taken_with_a_note(tmp_path: Path) -> None:
    """intensity = [1.0, 1.0, 1.0] was taken silently, and the scene nearly black; [0, 0, 0] is a deliberate off."""
    import marraztu

    path = write_scene(tmp_path, DIM_LIGHTS)
    scene = load_scene(path)
    notes = (f"{path}:1: ambient [1.0, 1.0, 1.0] {DARK}", f"{path}:7: lights.bulb: intensity [1.0, 1.0, 1.0] {DARK}",
             f"{path}:13: lights.object_spotlight: intensity [0, 0.5, 0] {DARK}")
    assert scene.notes == notes
    assert list(scene.ambient) == [1, 1, 1] and list(scene.lights[1].intensity) == [1, 1, 1]
    with marraztu.Viewer(size=(64, 48), scene=path) as viewer:  # told at start, as the window and screenshot tell it
        assert all(note in viewer.message for note in notes), viewer.message


LONG_WORD = "x" * 3000
LONG_WORDS = {  # a word of the file each message quotes: shown whole, the message was 3,000 to 9,000 characters
    "unknown top key": (f"{LONG_WORD} = 1\n", 1, "the scene: unknown key 'xxx"),
    "unknown entry key": (f'[[objects]]\nmodel = "m.obj"\n{LONG_WORD} = 1\n', 3, "objects[1]: unknown key 'xxx"),
    "unknown material": (f'[[objects]]\nmodel = "m.obj"\nmaterial = "{LONG_WORD}"\n', 3,
                         "objects[1]: unknown material 'xxx"),
    "unknown light": (f"[lights.{LONG_WORD}]\non = true\n", 1, "lights: unknown light 'xxx"),
    "material's name": (f"[materials.{LONG_WORD}]\nka = 1\n", 1, "material 'xxx"),
    "escape in a key's value": (f'[[objects]]\n{LONG_WORD} = "C:\\Users"\n', 2, "TOML syntax: xxx"),
    "table declared twice": (f"[materials.{LONG_WORD}]\n[materials.{LONG_WORD}]\n", 2, "TOML syntax: [materials.xxx"),
    "array over a table": (f"[materials.{LONG_WORD}]\n[[materials.{LONG_WORD}]]\n", 2,
                           "TOML syntax: [[materials.xxx"),
    "inline key twice": (f'[[objects]]\nmodel = "m.obj"\nmaterial = {{ {LONG_WORD} = 1, {LONG_WORD} = 2 }}\n', 3,
                         "TOML syntax: material: xxx"),
}


@pytest.mark.parametrize("text, line, said", LONG_WORDS.values(), ids=LONG_WORDS.keys())
def test_a_long_word_of_the_file_is_cut_in_its_message(tmp_path: Path, text: str, line: int, said: str) -> None:
    with pytest.raises(LoadError) as refused:
        read_scene_description(write_scene(tmp_path, text))
    assert refused.value.line == line and refused.value.message.startswith(said)
    assert len(refused.value.message) < 300 and re.search(r"\.\.\. \(30[01]0 characters\)", refused.value.message)


def test_an_unknown_material_lists_a_few_of_the_known_ones(tmp_path: Path) -> None:
    """Every name was listed whole: a scene of ten thousand materials said ten thousand names in one line."""
    materials = "".join(MATERIAL.replace("materials.m", f"materials.m{index}") for index in range(10_000))
    with pytest.raises(LoadError) as refused:
        read_scene_description(write_scene(tmp_path, materials + '[[objects]]\nmodel = "m.obj"\nmaterial = "n"\n'))
    assert refused.value.message.startswith("objects[1]: unknown material 'n' (known: m0, m1, m10, ")
    assert len(refused.value.message) < 300 and refused.value.message.endswith(" and 9,990 more)")


INLINE_ENTRIES = {  # entries written inline had no line, where lights written inline have the one that opens them
    "an object's model": ('\nobjects = [{ model = "" }]\n', "objects[1]: model must name a file", 2),
    "a camera's position": ('cameras = [\n  { position = [0, 0] },\n]\n', "cameras[1]: position must be three", 1),
    "a model not found": ('"objects" = [{ model = "m.obj" }, { model = "n.obj" }]\n', "model n.obj: ", 1),
}


@pytest.mark.parametrize("text, said, line", INLINE_ENTRIES.values(), ids=INLINE_ENTRIES.keys())
def test_entries_written_inline_are_refused_at_the_line_that_opens_them(tmp_path: Path, text: str, said: str,
                                                                         line: int) -> None:
    with pytest.raises(LoadError) as refused:
        load_scene(write_scene(tmp_path, text))
    assert refused.value.message.startswith(said) and refused.value.line == line


def test_materials_written_inline_are_refused_at_the_line_that_opens_them(tmp_path: Path) -> None:
    """materials = { red = { ... } } was refused with no line, where lights written so have the line."""
    text = '\nmaterials = { red = { ka = [1, 0, 0], kd = [1, 0, 0], ks = [1, 1, 1], on = true } }\n'
    with pytest.raises(LoadError) as refused:
        read_scene_description(write_scene(tmp_path, text))
    assert refused.value.message.startswith("material 'red': unknown key 'on'") and refused.value.line == 2
