"""The screenshot and record commands never write over a file read to make their picture: the models,
and what loading them read beside them (an OBJ's MTL and its textures, a glTF's buffers and pictures),
however the model came in. And they are strict about the scene file's texture, as about --texture."""

from __future__ import annotations

import json
import struct
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from marraztu.cli import main
from marraztu.control.viewer import StartOptions, Viewer
from marraztu.loaders.images import fallback_texture
from marraztu.loaders.scenefile import load_scene
from support.scenes import Notices

TRIANGLE = "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0.5 1\n"
MATERIAL = "newmtl m\nKd 0.8 0.8 0.8\nmap_Kd q.png\n"


def write_textured_model(folder: Path, library: str = "b4.mtl") -> Path:
    """b4.obj, whose MTL (`library`) names the texture q.png: the exploratory tester's case."""
    (folder / "b4.obj").write_text(f"mtllib {library}\n{TRIANGLE}usemtl m\nf 1/1 2/2 3/3\n")
    (folder / library).write_text(MATERIAL)
    Image.new("RGB", (4, 4), (200, 30, 30)).save(folder / "q.png")
    return folder / "b4.obj"


def write_scene(folder: Path, texture: str | None = None, model: str = "b4.obj") -> Path:
    """s.toml in `folder`: a camera, an object of `model`, and `texture` where given."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "camera.obj").write_text(TRIANGLE + "f 1 2 3\n")
    lines = [] if texture is None else [f'texture = "{texture}"']
    lines += ["[[cameras]]", 'model = "camera.obj"', "position = [0, 0, 5]",
              "[[objects]]", f'model = "{model}"', "position = [0, 0, 0]"]
    (folder / "s.toml").write_text("\n".join(lines) + "\n")
    return folder / "s.toml"


def run(capsys: pytest.CaptureFixture[str], *arguments: str) -> tuple[int, str]:
    """The command's exit status and what it printed on stderr."""
    status = main([*arguments, "--size", "32x32"])
    return status, capsys.readouterr().err.strip()


def assert_refused_as_input(status: int, error: str, out: Path, what: str = "picture") -> None:
    assert status == 1
    assert error.startswith(f"error: {out}: is an input of this {what} (") and "\n" not in error, error
    assert error.endswith("; write it elsewhere"), error


# --- files read beside a model -------------------------------------------------------------------
@pytest.mark.parametrize("how", ["command line", "key", "typed", "scene file"])
def test_the_texture_an_mtl_names_is_never_overwritten(tmp_path: Path, capsys, monkeypatch, how: str) -> None:
    model = write_textured_model(tmp_path)
    texture = (tmp_path / "q.png").read_bytes()
    monkeypatch.chdir(tmp_path)  # -o q.png as the tester typed it: a relative name
    ways = {"command line": ["--empty", str(model)], "key": ["--empty", "--keys", f"f={model}"],
            "typed": ["--empty", "--keys", "f b 4 . o b j ENTER"],
            "scene file": ["--scene", str(write_scene(tmp_path))]}
    status, error = run(capsys, "screenshot", "-o", "q.png", *ways[how])
    assert_refused_as_input(status, error, Path("q.png"))
    assert (tmp_path / "q.png").read_bytes() == texture
    assert not list(tmp_path.glob(".q.png.*")), "no temporary file is left behind"


def test_a_model_loaded_then_deleted_still_keeps_its_texture(tmp_path: Path, capsys) -> None:
    model = write_textured_model(tmp_path)
    texture = (tmp_path / "q.png").read_bytes()
    status, error = run(capsys, "screenshot", "-o", str(tmp_path / "q.png"), "--empty", "--keys",
                        f"f={model} DELETE")
    assert_refused_as_input(status, error, tmp_path / "q.png")
    assert (tmp_path / "q.png").read_bytes() == texture


def test_a_texture_that_cannot_be_read_is_an_input_all_the_same(tmp_path: Path, capsys) -> None:
    model = write_textured_model(tmp_path)
    (tmp_path / "q.png").write_bytes(b"GIF89a: the person's file, whatever its name says")
    status, error = run(capsys, "screenshot", "-o", str(tmp_path / "q.png"), "--empty", str(model))
    note, error = error.splitlines()
    assert "texture 'q.png' could not be read" in note  # the load's note comes first
    assert_refused_as_input(status, error, tmp_path / "q.png")
    assert (tmp_path / "q.png").read_bytes().startswith(b"GIF89a")


def test_the_mtl_itself_is_never_overwritten(tmp_path: Path, capsys) -> None:
    model = write_textured_model(tmp_path)
    status, error = run(capsys, "screenshot", "-o", str(tmp_path / "b4.mtl"), "--empty", str(model))
    assert status == 1 and "write a picture as .png" in error
    (tmp_path / "lib.png").write_text(MATERIAL)  # an MTL by any other name
    model.write_text(f"mtllib lib.png\n{TRIANGLE}usemtl m\nf 1/1 2/2 3/3\n")
    status, error = run(capsys, "screenshot", "-o", str(tmp_path / "lib.png"), "--empty", str(model))
    assert_refused_as_input(status, error, tmp_path / "lib.png")
    assert (tmp_path / "lib.png").read_text() == MATERIAL and (tmp_path / "b4.mtl").read_text() == MATERIAL


def test_record_keeps_off_them_too(tmp_path: Path, capsys) -> None:
    model = write_textured_model(tmp_path)
    texture = (tmp_path / "q.png").read_bytes()
    status, error = run(capsys, "record", "-o", str(tmp_path / "q.png"), "--empty", "--keys", f"y f={model} y")
    assert_refused_as_input(status, error, tmp_path / "q.png", "animation")
    assert (tmp_path / "q.png").read_bytes() == texture
    assert not list(tmp_path.glob(".q.png.*")), "no temporary file is left behind"


def test_a_gltf_keeps_its_picture_and_buffer(tmp_path: Path, capsys) -> None:
    write_gltf(tmp_path)
    kept = {name: (tmp_path / name).read_bytes() for name in ("tex.png", "data.png")}
    for name in kept:
        status, error = run(capsys, "screenshot", "-o", str(tmp_path / name), "--empty", str(tmp_path / "t.gltf"))
        assert_refused_as_input(status, error, tmp_path / name)
    assert {name: (tmp_path / name).read_bytes() for name in kept} == kept


def test_an_output_beside_the_inputs_is_written(tmp_path: Path, capsys) -> None:
    model = write_textured_model(tmp_path)
    texture = (tmp_path / "q.png").read_bytes()
    status, error = run(capsys, "screenshot", "-o", str(tmp_path / "shot.png"), "--empty", "--keys", f"f={model}")
    assert status == 0, error
    assert (tmp_path / "shot.png").exists() and (tmp_path / "q.png").read_bytes() == texture


def write_gltf(folder: Path) -> None:
    """t.gltf: one textured triangle whose buffer (data.png, named so it could be an output) and
    picture (tex.png) lie beside it."""
    positions = np.array([[-1, -1, 0], [1, -1, 0], [0, 1, 0]], np.float32)
    uvs = np.array([[0, 0], [1, 0], [0.5, 1]], np.float32)
    data = positions.tobytes() + uvs.tobytes() + struct.pack("<3H", 0, 1, 2)
    (folder / "data.png").write_bytes(data)
    Image.new("RGB", (4, 4), (30, 200, 30)).save(folder / "tex.png")
    views = [(0, 36, 34962), (36, 24, 34962), (60, 6, 34963)]
    document = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "buffers": [{"uri": "data.png", "byteLength": len(data)}],
        "bufferViews": [{"buffer": 0, "byteOffset": at, "byteLength": size, "target": target}
                        for at, size, target in views],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
             "min": [-1, -1, 0], "max": [1, 1, 0]},
            {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
            {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"},
        ],
        "images": [{"uri": "tex.png"}], "textures": [{"source": 0}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
    }
    (folder / "t.gltf").write_text(json.dumps(document))


# --- the scene file's texture --------------------------------------------------------------------
def write_gif(path: Path) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    Image.new("RGB", (4, 4), (10, 10, 200)).save(path, format="GIF")


@pytest.mark.parametrize("command", ["screenshot", "record"])
@pytest.mark.parametrize("texture, words", [("../bad/t.gif", "not a PNG, JPEG or PPM picture"),
                                            ("nothere.ppm", "no such file"), ("../bad", "is a directory")])
def test_a_bad_scene_texture_is_a_message_and_the_checker(tmp_path: Path, capsys, command: str, texture: str,
                                                          words: str) -> None:
    """SPEC 7: a missing or broken texture at start is a message and the fallback, not an exit (a texture
    named with --texture is the person's own choice, and ends the command)."""
    write_gif(tmp_path / "bad" / "t.gif")
    scene = write_scene(tmp_path / "scenes", texture, model="camera.obj")
    out = tmp_path / ("shot.png" if command == "screenshot" else "turn.gif")
    status, error = run(capsys, command, "-o", str(out), "--scene", str(scene), "--keys", "y")
    assert status == 0 and out.exists()
    assert "\n" not in error and Path(texture).name in error and words in error and "checker" in error, error
    assert error.startswith(f"{scene}:1: texture: "), error  # the scene file's entry that named it


def test_a_named_texture_takes_the_place_of_a_bad_scene_texture(tmp_path: Path, capsys) -> None:
    write_gif(tmp_path / "bad" / "t.gif")
    scene = write_scene(tmp_path / "scenes", "../bad/t.gif", model="camera.obj")
    Image.new("RGB", (4, 4), (200, 200, 30)).save(tmp_path / "good.png")
    status, error = run(capsys, "screenshot", "-o", str(tmp_path / "shot.png"), "--scene", str(scene),
                        "--texture", str(tmp_path / "good.png"))
    assert status == 0 and error == ""
    assert (tmp_path / "shot.png").exists()


def test_the_window_goes_on_with_the_checker(tmp_path: Path) -> None:
    write_gif(tmp_path / "bad" / "t.gif")
    scene_file = write_scene(tmp_path / "scenes", "../bad/t.gif", model="camera.obj")
    front = Notices()
    viewer = Viewer(load_scene(scene_file), front)
    viewer.start(StartOptions(scene_file=scene_file), longest_texture_side=4096)
    assert len(front.told) == 1 and "t.gif" in front.told[0] and "checker" in front.told[0]
    assert (viewer.scene.texture == fallback_texture()).all()


def test_a_name_too_long_for_the_system_is_one_line(tmp_path: Path, capsys) -> None:
    assert main(["screenshot", "-o", str(tmp_path / ("a" * 300 + ".png")), "--size", "8x8", "--empty"]) == 1
    error = capsys.readouterr().err.strip()
    assert error.startswith("error:") and "\n" not in error and "cannot write here" in error, error


def test_an_input_named_past_the_systems_limit_is_its_loads_error(tmp_path: Path, capsys) -> None:
    out = tmp_path / "k.png"
    Image.new("RGB", (4, 4)).save(out)  # it exists: the inputs are compared with it
    assert main(["screenshot", "-o", str(out), "--size", "8x8", "--empty", "--keys",
                 f"f={tmp_path / ('a' * 300 + '.obj')}"]) == 1
    error = capsys.readouterr().err.strip()
    assert error.startswith("error:") and "\n" not in error and "Traceback" not in error, error


def test_keys_that_load_nothing_do_not_look_at_the_files_again(tmp_path: Path, monkeypatch) -> None:
    """Each press is followed by a look at the files read, which costs every element: only after a load."""
    from marraztu.frontends import screenshot

    for name in ("t.obj", "u.obj"):  # PageDown goes from t to u
        (tmp_path / name).write_text(TRIANGLE + "f 1 2 3\n")
    looks: list[int] = []
    original = screenshot.files_read
    monkeypatch.setattr(screenshot, "files_read", lambda scene: looks.append(1) or original(scene))
    keys = " ".join([f"f={tmp_path / 't.obj'}"] * 3 + ["x*500", "PAGEDOWN"])
    assert main(["screenshot", "-o", str(tmp_path / "s.png"), "--size", "8x8", "--empty", "--keys", keys]) == 0
    assert len(looks) == 1 + 3 + 1  # the start, each load, the PageDown that read the file again
