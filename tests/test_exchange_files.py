"""The files a glTF or PLY names beside it, read for trimesh by marraztu: a glTF's percent-encoded URIs,
a MeshLab PLY's TextureFile, a picture that cannot be read (a note, as an MTL's), a .gltf that is not
JSON (one line with its line number), and trimesh's log kept off the terminal."""

from __future__ import annotations

import base64
import io
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh
from PIL import Image

from marraztu.control.viewer import StartOptions
from marraztu.errors import LoadError
from marraztu.frontends.screenshot import take_screenshot
from marraztu.loaders.registry import load_model
from support.corpus import git_lfs_pointer
from support.refusals import one_line_refusal

SIZE = (120, 120)
SQUARE = np.array([[-60, -60, 0], [60, -60, 0], [60, 60, 0], [-60, 60, 0]], dtype=np.float64)
FACES = np.array([[0, 1, 2], [0, 2, 3]])
UVS = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=np.float64)
RED, BLUE = (250, 0, 0), (0, 0, 250)


def top_red_bottom_blue() -> Image.Image:
    """8x8, the top half red, the bottom half blue: a picture drawn upside down shows it."""
    pixels = np.zeros((8, 8, 3), np.uint8)
    pixels[:4], pixels[4:] = RED, BLUE
    return Image.fromarray(pixels)


def png_bytes(image: Image.Image, format: str = "PNG") -> bytes:
    out = io.BytesIO()
    image.save(out, format=format)
    return out.getvalue()


def picture(path: Path, out: Path) -> np.ndarray:
    shot = take_screenshot(StartOptions(empty=True, models=(path,)), out, SIZE, keys="0")
    return np.asarray(Image.open(shot).convert("RGB")).astype(int)


# --- glTF --------------------------------------------------------------------------------------------
def write_gltf(folder: Path, buffer_file: str = "square.bin", buffer_uri: str | None = None,
               image_uri: str | None = "square.png", image_file: str | None = "square.png",
               text: str | None = None) -> Path:
    """square.gltf, as trimesh exports a textured square, its buffers joined into `buffer_file` (named
    `buffer_uri` in the JSON) and its picture moved out to `image_file` (named `image_uri`)."""
    mesh = trimesh.Trimesh(vertices=SQUARE, faces=FACES, process=False)
    mesh.visual = trimesh.visual.TextureVisuals(uv=UVS, image=top_red_bottom_blue())
    files = trimesh.Scene(mesh).export(file_type="gltf")
    document = json.loads(files["model.gltf"])
    joined, starts = b"", []
    for buffer in document["buffers"]:  # one buffer, as Blender writes it
        starts.append(len(joined))
        joined += files[buffer["uri"]] + b"\0" * (-len(files[buffer["uri"]]) % 4)
    for view in document["bufferViews"]:
        view["byteOffset"] = starts[view["buffer"]] + view.get("byteOffset", 0)
        view["buffer"] = 0
    document["buffers"] = [{"uri": buffer_uri or buffer_file, "byteLength": len(joined)}]
    (folder / buffer_file).write_bytes(joined)
    if image_uri is not None:
        document["images"] = [{"uri": image_uri}]
    if image_file is not None:
        (folder / image_file).write_bytes(png_bytes(top_red_bottom_blue()))
    (folder / "square.gltf").write_text(json.dumps(document) if text is None else text)
    return folder / "square.gltf"


def hostile_jpeg(segments: int) -> bytes:
    """The top-red, bottom-blue picture as a JPEG whose header holds `segments` empty APP15 segments more."""
    data = png_bytes(top_red_bottom_blue(), "JPEG")
    return data[:2] + b"\xff\xef\x00\x02" * segments + data[2:]


def with_held_jpeg(folder: Path, where: str, segments: int) -> Path:
    return with_held_picture(folder, where, hostile_jpeg(segments))


def with_held_picture(folder: Path, where: str, picture: bytes) -> Path:
    """write_gltf's square, its picture (a JPEG's bytes) held in the glTF itself: a data: URI, a view of
    the GLB's binary chunk, or a view of the buffer it names beside it."""
    path = write_gltf(folder, image_uri=None, image_file=None)
    document = json.loads(path.read_text())
    joined = (folder / "square.bin").read_bytes()
    if where == "data URI":
        document["images"] = [{"uri": "data:image/jpeg;base64," + base64.b64encode(picture).decode()}]
        path.write_text(json.dumps(document))
        return path
    document["bufferViews"].append({"buffer": 0, "byteOffset": len(joined), "byteLength": len(picture)})
    document["images"] = [{"bufferView": len(document["bufferViews"]) - 1, "mimeType": "image/jpeg"}]
    joined += picture + b"\0" * (-len(picture) % 4)
    document["buffers"][0]["byteLength"] = len(joined)
    if where == "beside":
        (folder / "square.bin").write_bytes(joined)
        path.write_text(json.dumps(document))
        return path
    del document["buffers"][0]["uri"]
    text = json.dumps(document).encode()
    text += b" " * (-len(text) % 4)
    glb = folder / "square.glb"
    chunks = len(text).to_bytes(4, "little") + b"JSON" + text + len(joined).to_bytes(4, "little") + b"BIN\0" + joined
    glb.write_bytes(b"glTF" + (2).to_bytes(4, "little") + (12 + len(chunks)).to_bytes(4, "little") + chunks)
    return glb


@pytest.mark.parametrize("where", ["data URI", "GLB", "beside"])
def test_a_jpeg_a_gltf_holds_is_checked_as_a_texture_is(tmp_path: Path, where: str) -> None:
    """Pillow kept every empty APP segment of a JPEG's header in a list, 33 bytes a byte; the pictures a
    glTF holds itself reached it through trimesh unchecked. Pillow's opener checks them now, wherever
    trimesh finds them, and trimesh drops the picture: a note says so."""
    loaded = load_model(with_held_jpeg(tmp_path, where, 100))
    texture = loaded.materials[0].texture
    assert texture[0, 0, 0] > 200 and texture[-1, 0, 2] > 200  # red above blue
    refused = load_model(with_held_jpeg(tmp_path, where, 1_000_000))
    assert refused.face_count == 2 and all(material.texture is None for material in refused.materials)
    assert refused.warnings == ("a picture the file holds could not be read (more than 4096 markers and stray bytes "
                                "before the picture: no JPEG's header holds so many); the scene's texture is shown "
                                "in its place",)


@pytest.mark.parametrize("where", ["data URI", "GLB", "beside"])
@pytest.mark.parametrize(("picture", "why"), [
    (b"garbage!" * 8, "not a PNG, JPEG or PPM picture (it starts with b'garbage!')"),
    (b"\x89PNG\r\n\x1a\n" + b"\0" * 30, "a broken PNG: Pillow cannot read its header"),
])
def test_a_picture_the_gltf_holds_that_pillow_cannot_open_is_a_note(tmp_path: Path, where: str, picture: bytes,
                                                                    why: str) -> None:
    """trimesh dropped it without a word, and the square was drawn untextured; Pillow's own words named
    its object ('<_io.BytesIO object at 0x...>')."""
    loaded = load_model(with_held_picture(tmp_path, where, picture))
    assert loaded.face_count == 2 and all(material.texture is None for material in loaded.materials)
    assert loaded.warnings == (f"a picture the file holds could not be read ({why}); the scene's texture is shown "
                               "in its place",)


def test_a_broken_png_beside_a_gltf_is_named_without_pillows_object(tmp_path: Path) -> None:
    (tmp_path / "broken.png").write_bytes(b"\x89PNG\r\n\x1a\n" + b"\0" * 30)
    loaded = load_model(write_gltf(tmp_path, image_uri="broken.png", image_file=None))
    assert loaded.warnings == ("texture 'broken.png' could not be read (a broken PNG: Pillow cannot read its header); "
                               "the scene's texture is shown in its place",)


def test_a_git_lfs_pointer_beside_a_gltf_is_named_as_one(tmp_path: Path) -> None:
    """trimesh hands Pillow a glTF's pictures: a pointer in a picture's place was 'not a PNG, JPEG or PPM
    picture (it starts with b'version ')'."""
    (tmp_path / "pointer.png").write_bytes(git_lfs_pointer(2048))
    loaded = load_model(write_gltf(tmp_path, image_uri="pointer.png", image_file=None))
    assert loaded.warnings == ("texture 'pointer.png' could not be read (a Git LFS pointer, not the picture: its "
                               "2048 bytes are fetched by `git lfs pull`); the scene's texture is shown in its place",)


@pytest.mark.parametrize("corners", [3, 30])
def test_a_git_lfs_pointer_in_a_gltfs_buffer_is_named_as_one(tmp_path: Path, corners: int) -> None:
    """A pointer in the .bin's place was read as the buffer: one as long as its byteLength drew its text as
    coordinates ('a coordinate reaches 1.92e+31: ... scale it down'), a shorter one 'holds 131 bytes'."""
    positions = np.zeros((corners, 3), np.float32)
    positions[1::3, 0] = positions[2::3, 1] = 1.0
    document = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
                "accessors": [{"bufferView": 0, "componentType": 5126, "count": corners, "type": "VEC3",
                               "min": [0, 0, 0], "max": [1, 1, 0]}],
                "bufferViews": [{"buffer": 0, "byteLength": positions.nbytes}],
                "buffers": [{"uri": "m.bin", "byteLength": positions.nbytes}]}
    (tmp_path / "m.gltf").write_text(json.dumps(document))
    (tmp_path / "m.bin").write_bytes(git_lfs_pointer(positions.nbytes))
    with pytest.raises(LoadError) as raised:
        load_model(tmp_path / "m.gltf")
    assert raised.value.message == (f"'m.bin', which it names, could not be read (a Git LFS pointer, not the buffer: "
                                    f"its {positions.nbytes} bytes are fetched by `git lfs pull`)")


@pytest.mark.parametrize("fallback", [True, False])
def test_a_webp_textures_fallback_is_drawn(tmp_path: Path, fallback: bool) -> None:
    """EXT_texture_webp names a WEBP, `source` a PNG for a viewer that draws no WEBP: trimesh took the
    WEBP, which was refused with a note, and the PNG was never drawn. Without a fallback, the note stays."""
    path = write_gltf(tmp_path)
    document = json.loads(path.read_text())
    (tmp_path / "square.webp").write_bytes(png_bytes(top_red_bottom_blue(), "WEBP"))
    document["images"].append({"uri": "square.webp"})
    document["textures"] = [{**({"source": 0} if fallback else {}), "extensions": {"EXT_texture_webp": {"source": 1}}}]
    document["extensionsUsed"] = ["EXT_texture_webp"]
    path.write_text(json.dumps(document))
    loaded = load_model(path)
    if fallback:
        assert loaded.warnings == () and loaded.materials[0].texture[0, 0, 0] > 200
        assert tmp_path / "square.webp" not in loaded.read_beside  # not read at all
    else:
        assert loaded.warnings[0].startswith("texture 'square.webp' could not be read (not a PNG, JPEG or PPM")


@pytest.mark.parametrize("map_name", ["normalTexture", "occlusionTexture", "emissiveTexture"])
def test_a_picture_no_material_draws_is_not_read(tmp_path: Path, map_name: str) -> None:
    """A normal, occlusion or emissive map is not drawn: one that could not be read was a note that
    the scene's texture is shown in its place, though the base colour's picture was drawn."""
    path = write_gltf(tmp_path)
    document = json.loads(path.read_text())
    document["images"].append({"uri": "missing.png"})
    document["textures"].append({"source": 1})
    document["materials"][0][map_name] = {"index": len(document["textures"]) - 1}
    path.write_text(json.dumps(document))
    loaded = load_model(path)
    said = ("material 0's normal map (normalTexture) is not drawn",) if map_name == "normalTexture" else ()
    assert loaded.warnings == said and loaded.materials[0].texture[0, 0, 0] > 200
    assert tmp_path / "missing.png" not in loaded.read_beside


def test_a_gltf_draws_its_picture_named_by_a_plain_uri(tmp_path: Path) -> None:
    loaded = load_model(write_gltf(tmp_path))
    assert loaded.warnings == () and loaded.materials[0].texture.shape == (8, 8, 3)
    assert {tmp_path / "square.bin", tmp_path / "square.png"} <= set(loaded.read_beside)


@pytest.mark.parametrize(("buffer_uri", "image_uri"), [
    ("my%20buf.bin", "my%20tex.png"),  # as the glTF specification and Blender write a space
    ("my buf.bin", "my tex.png"),  # as some writers do, though a URI may hold no space
    ("my%20buf.bin", "./my%20tex.png"),
])
def test_a_gltfs_percent_encoded_uris_name_its_files(tmp_path: Path, buffer_uri: str, image_uri: str) -> None:
    path = write_gltf(tmp_path, buffer_file="my buf.bin", buffer_uri=buffer_uri, image_uri=image_uri,
                      image_file="my tex.png")
    loaded = load_model(path)
    assert loaded.face_count == 2 and loaded.warnings == ()
    texture = loaded.materials[0].texture
    assert texture[0, 0].tolist() == list(RED) and texture[-1, 0].tolist() == list(BLUE)
    assert tmp_path / "my buf.bin" in loaded.read_beside and tmp_path / "my tex.png" in loaded.read_beside


def test_a_uri_whose_percent_is_the_files_own_is_read_as_written(tmp_path: Path) -> None:
    """A writer that did not encode a '%' in the name: not found decoded, the name as written is."""
    loaded = load_model(write_gltf(tmp_path, image_uri="tex%20100.png", image_file="tex%20100.png"))
    assert loaded.warnings == () and loaded.materials[0].texture is not None


@pytest.mark.parametrize(("buffer_file", "image_file"), [
    ("x-base64,y.bin", "square.png"), ("square.bin", "p-base64,q.png"), ("model-base64,part.bin", "base64,AAAA.png")])
def test_a_uri_holding_base64_that_is_no_data_uri_names_a_file(tmp_path: Path, buffer_file: str, image_file: str
                                                             ) -> None:
    """trimesh decodes what follows 'base64,' in any URI: such a buffer was refused (its name's tail decoded
    as a few bytes), such a picture dropped. Only a data: URI holds its bytes."""
    loaded = load_model(write_gltf(tmp_path, buffer_file=buffer_file, image_uri=image_file, image_file=image_file))
    assert loaded.face_count == 2 and loaded.warnings == ()
    texture = loaded.materials[0].texture
    assert texture[0, 0].tolist() == list(RED) and texture[-1, 0].tolist() == list(BLUE)
    assert {tmp_path / buffer_file, tmp_path / image_file} <= set(loaded.read_beside)


def test_a_file_uri_holding_base64_is_checked_as_the_file_it_names(tmp_path: Path) -> None:
    """Read as a file, it is checked as one: missing, short of its byteLength, or not a picture."""
    path = write_gltf(tmp_path, buffer_file="elsewhere.bin", buffer_uri="x-base64,AAAA")
    assert one_line_refusal(lambda: load_model(path)).message == (
        "'x-base64,AAAA', which it names, could not be read (no such file)")
    (tmp_path / "x-base64,AAAA").write_bytes((tmp_path / "elsewhere.bin").read_bytes()[:-4])
    assert one_line_refusal(lambda: load_model(path)).message.startswith(
        "'x-base64,AAAA', which it names, could not be read (it holds ")
    (tmp_path / "p-base64,q.png").write_text("not a picture")
    loaded = load_model(write_gltf(tmp_path, image_uri="p-base64,q.png", image_file=None))
    assert loaded.materials == () and len(loaded.warnings) == 1
    assert loaded.warnings[0].startswith("texture 'p-base64,q.png' could not be read (not a PNG, JPEG or PPM picture")


def test_a_buffer_named_by_a_whole_path_is_looked_for_in_the_folder_and_says_so(tmp_path: Path) -> None:
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "square.bin").write_bytes(b"")
    path = write_gltf(tmp_path / "elsewhere", buffer_file="other.bin", buffer_uri=str(elsewhere / "gone.bin"))
    with pytest.raises(LoadError, match="only that folder is read, not a whole path"):
        load_model(path)


def test_a_missing_buffer_is_one_load_error_naming_it_decoded(tmp_path: Path) -> None:
    path = write_gltf(tmp_path, buffer_file="elsewhere.bin", buffer_uri="my%20buf.bin")
    with pytest.raises(LoadError) as caught:
        load_model(path)
    assert str(caught.value) == f"{path}: 'my buf.bin', which it names, could not be read (no such file)"


@pytest.mark.parametrize(("image_uri", "why"), [
    ("missing.png", "no such file"),
    ("my%20missing.png", "no such file"),
    ("../outside.png", "it lies outside the model's folder"),
    ("sub", "is a directory, not a file"),
    ("notes.png", "not a PNG, JPEG or PPM picture"),
])
def test_a_picture_that_cannot_be_read_is_a_note(tmp_path: Path, image_uri: str, why: str) -> None:
    """As an MTL's missing texture: the model loads, the note names the picture and says why."""
    folder = tmp_path / "model"
    folder.mkdir()
    (folder / "sub").mkdir()
    (folder / "notes.png").write_text("not a picture")
    (tmp_path / "outside.png").write_bytes(png_bytes(top_red_bottom_blue()))
    loaded = load_model(write_gltf(folder, image_uri=image_uri, image_file=None))
    assert loaded.face_count == 2 and loaded.materials == ()
    shown = image_uri.replace("%20", " ")
    assert len(loaded.warnings) == 1 and loaded.warnings[0].startswith(f"texture '{shown}' could not be read ({why}")
    assert loaded.warnings[0].endswith("the scene's texture is shown in its place")


def test_a_picture_linked_from_outside_the_folder_is_not_read(tmp_path: Path) -> None:
    (tmp_path / "secret.png").write_bytes(png_bytes(top_red_bottom_blue()))
    (tmp_path / "model").mkdir()
    (tmp_path / "model" / "link.png").symlink_to(tmp_path / "secret.png")
    loaded = load_model(write_gltf(tmp_path / "model", image_uri="link.png", image_file=None))
    assert loaded.materials == () and "it lies outside the model's folder" in loaded.warnings[0]


def test_a_uri_longer_than_any_path_is_known_outside_by_its_text(tmp_path: Path) -> None:
    """A path too long to be resolved part by part (its length squared) is judged by its text: its '..'
    parts still take it out of the model's folder."""
    (tmp_path / "outside.png").write_bytes(png_bytes(top_red_bottom_blue()))
    (tmp_path / "model").mkdir()
    uri = "d/" * 3_000 + "../" * 3_001 + "outside.png"
    loaded = load_model(write_gltf(tmp_path / "model", image_uri=uri, image_file=None))
    assert loaded.materials == () and "it lies outside the model's folder" in loaded.warnings[0]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes are POSIX's")
def test_a_picture_that_is_a_named_pipe_is_a_note_not_a_wait(tmp_path: Path) -> None:
    os.mkfifo(tmp_path / "pipe.png")
    loaded = load_model(write_gltf(tmp_path, image_uri="pipe.png", image_file=None))
    assert "not a regular file" in loaded.warnings[0]


def test_an_embedded_picture_of_another_format_is_a_note_not_drawn(tmp_path: Path) -> None:
    """Textures are PNG, JPEG and PPM, by content, however the file brings them (Pillow would open
    any, and hands some to other programs)."""
    gif = png_bytes(top_red_bottom_blue(), format="GIF")
    loaded = load_model(write_gltf(tmp_path, image_uri="data:image/gif;base64," + base64.b64encode(gif).decode(),
                                   image_file=None))
    assert loaded.materials == () and loaded.warnings == (
        "a material's picture is not drawn (a GIF picture, not a PNG, JPEG or PPM one); the scene's texture is "
        "shown in its place",)


@pytest.mark.parametrize(("text", "line", "words"), [
    ("{ not json", 1, "not a glTF file: its JSON is not valid: Expecting property name enclosed in double quotes "
                      "(column 3)"),
    ('{\n  "asset": {"version": "2.0"},\n  "buffers": [,]\n}', 3,
     "not a glTF file: its JSON is not valid: Expecting value (column 15)"),
    ("", None, "empty file: no faces"),
    ("[1, 2]", 1, "not a glTF file: its JSON is not an object of glTF's keys"),
    ("[" * 100_000, None, "not a glTF file: its JSON nests too deeply to read"),
    ('{"asset": {"version": ' + "9" * 5000 + "}}", None, "not a glTF file: its JSON holds a number too long to read"),
])
def test_a_gltf_that_is_not_json_says_so_at_its_line(tmp_path: Path, text: str, line: int | None, words: str) -> None:
    path = write_gltf(tmp_path, text=text)
    with pytest.raises(LoadError) as caught:
        load_model(path)
    assert (caught.value.line, caught.value.message) == (line, words)
    assert "\n" not in str(caught.value)


def test_a_gltf_that_is_not_utf8_is_one_load_error(tmp_path: Path) -> None:
    (tmp_path / "latin.gltf").write_bytes(b'{"asset": {"version": "2.0", "generator": "\xe9"}}')
    with pytest.raises(LoadError, match="not a glTF file: its JSON is not UTF-8 text"):
        load_model(tmp_path / "latin.gltf")


# --- PLY ---------------------------------------------------------------------------------------------
def test_a_plys_face_colours_are_said_not_to_be_drawn(tmp_path: Path) -> None:
    # Written here: trimesh's exporter leaves face colours out before 5.2.
    corners = "".join(f"{x} {y} {z}\n" for x, y, z in SQUARE)
    (tmp_path / "faces.ply").write_text(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 2\nproperty list uchar int vertex_indices\nproperty uchar red\nproperty uchar green\n"
        "property uchar blue\nproperty uchar alpha\nend_header\n"
        + corners + "3 0 1 2 255 0 0 255\n3 0 2 3 0 0 255 255\n")
    loaded = load_model(tmp_path / "faces.ply")
    assert loaded.vertex_colours is None
    assert loaded.warnings == ("colours given per face are not drawn, only those per vertex",)


def test_a_ply_count_of_thousands_of_digits_is_one_load_error(tmp_path: Path) -> None:
    (tmp_path / "m.ply").write_text("ply\nformat ascii 1.0\nelement vertex " + "9" * 5000 + "\nend_header\n")
    with pytest.raises(LoadError, match="rows are more than a file holds"):
        load_model(tmp_path / "m.ply")

def write_meshlab_ply(path: Path, texture: str = "q.png", per_face: bool = False) -> Path:
    """An ASCII PLY as MeshLab writes a textured one: `comment TextureFile`, and texture coordinates
    per vertex (s t) or per face corner (a texcoord list)."""
    header = ["ply", "format ascii 1.0", "comment VCGLIB generated", f"comment TextureFile {texture}",
              "element vertex 4", "property float x", "property float y", "property float z"]
    header += [] if per_face else ["property float s", "property float t"]
    header += ["element face 2", "property list uchar int vertex_indices"]
    header += ["property list uchar float texcoord"] if per_face else []
    rows = [" ".join(f"{value:g}" for value in (*position, *([] if per_face else uv)))
            for position, uv in zip(SQUARE, UVS)]
    for face in FACES:
        corners = " ".join(f"{value:g}" for corner in face for value in UVS[corner])
        rows.append(f"3 {' '.join(map(str, face))}" + (f" 6 {corners}" if per_face else ""))
    path.write_text("\n".join([*header, "end_header", *rows]) + "\n")
    return path


def write_textured_obj(folder: Path) -> Path:
    """The same square and picture as an OBJ and its MTL: how a texture is drawn."""
    lines = ["mtllib square.mtl", *(f"v {x:g} {y:g} {z:g}" for x, y, z in SQUARE),
             *(f"vt {u:g} {v:g}" for u, v in UVS), "usemtl pic",
             *(f"f {a + 1}/{a + 1} {b + 1}/{b + 1} {c + 1}/{c + 1}" for a, b, c in FACES)]
    (folder / "square.obj").write_text("\n".join(lines) + "\n")
    (folder / "square.mtl").write_text("newmtl pic\nmap_Kd q.png\n")  # no Kd: the picture is the colour, as a PLY's
    return folder / "square.obj"


@pytest.mark.parametrize("per_face", [False, True], ids=["s t per vertex", "texcoord per face"])
def test_a_meshlab_plys_texture_is_drawn_as_an_objs(tmp_path: Path, per_face: bool) -> None:
    top_red_bottom_blue().save(tmp_path / "q.png")
    path = write_meshlab_ply(tmp_path / "square.ply", per_face=per_face)
    loaded = load_model(path)
    assert loaded.face_count == 2 and loaded.warnings == () and tmp_path / "q.png" in loaded.read_beside
    assert loaded.materials[0].texture.shape == (8, 8, 3)
    drawn = picture(path, tmp_path / "ply.png")
    assert drawn[40, 60, 0] > drawn[40, 60, 2] + 30 and drawn[80, 60, 2] > drawn[80, 60, 0] + 30  # red above blue
    assert np.abs(drawn - picture(write_textured_obj(tmp_path), tmp_path / "obj.png")).max() <= 2


@pytest.mark.parametrize(("texture", "why"), [("nothere.png", "no such file"),
                                              ("../q.png", "it lies outside the model's folder")])
def test_a_plys_texture_that_cannot_be_read_is_a_note(tmp_path: Path, texture: str, why: str) -> None:
    top_red_bottom_blue().save(tmp_path / "q.png")
    (tmp_path / "model").mkdir()
    loaded = load_model(write_meshlab_ply(tmp_path / "model" / "square.ply", texture=texture))
    assert loaded.face_count == 2 and loaded.materials == ()
    assert loaded.warnings == (f"texture '{texture}' could not be read ({why}); the scene's texture is shown in "
                               "its place",)


def test_a_plys_jpeg_of_a_million_header_segments_is_a_note(tmp_path: Path) -> None:
    """The pictures a file names are checked as textures are, before Pillow keeps every segment."""
    top_red_bottom_blue().save(tmp_path / "plain.jpg")
    data = (tmp_path / "plain.jpg").read_bytes()
    (tmp_path / "q.jpg").write_bytes(data[:2] + b"\xff\xef\x00\x02" * 1_000_000 + data[2:])
    loaded = load_model(write_meshlab_ply(tmp_path / "square.ply", texture="q.jpg"))
    assert loaded.face_count == 2 and loaded.materials == ()
    assert loaded.warnings == ("texture 'q.jpg' could not be read (more than 4096 markers and stray bytes before the "
                               "picture: no "
                               "JPEG's header holds so many); the scene's texture is shown in its place",)


def test_a_plys_windows_texture_path_is_looked_for_beside_it(tmp_path: Path) -> None:
    top_red_bottom_blue().save(tmp_path / "q.png")
    loaded = load_model(write_meshlab_ply(tmp_path / "square.ply", texture="C:\\Users\\me\\Desktop\\q.png"))
    assert loaded.warnings == () and loaded.materials[0].texture.shape == (8, 8, 3)


def test_trimesh_prints_nothing_on_the_terminal(tmp_path: Path) -> None:
    """trimesh logs a traceback where it cannot read a PLY's picture; with no handler configured,
    Python's last resort would print it. A fresh process: the log is quieted once, at trimesh's import."""
    ply = write_meshlab_ply(tmp_path / "square.ply", texture="nothere.png")
    gltf = write_gltf(tmp_path, image_uri="missing.png", image_file=None)
    code = ("from marraztu.loaders.registry import load_model; "
            f"print(load_model({str(ply)!r}).warnings); print(load_model({str(gltf)!r}).warnings)")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0 and result.stderr == "", result.stderr
    assert "'nothere.png' could not be read" in result.stdout and "'missing.png' could not be read" in result.stdout


def test_the_programming_interface_draws_any_picture_pillow_opened() -> None:
    """A trimesh built in code is the caller's: its picture, whatever Pillow opened, is drawn."""
    from marraztu.loaders.exchange import mesh_of_trimesh

    gif = Image.open(io.BytesIO(png_bytes(top_red_bottom_blue(), format="GIF")))
    mesh = trimesh.Trimesh(SQUARE, FACES, process=False, visual=trimesh.visual.TextureVisuals(uv=UVS, image=gif))
    loaded = mesh_of_trimesh("gif", mesh)
    assert loaded.warnings == () and loaded.materials[0].texture[0, 0].tolist() == list(RED)
