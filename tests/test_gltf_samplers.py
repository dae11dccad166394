"""A glTF's base colour texture drawn as its sampler says (wraps per axis, nearest or linear filters),
where trimesh keeps no sampler; and a specular-glossiness material's diffuse colour drawn as its base
colour, where trimesh's metallic-roughness conversion made it pale. Each file is a square built here,
facing the camera, its picture a 2x2 of red, green / blue, white."""

from __future__ import annotations

import base64
import io
import json
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from PIL import Image

from marraztu.control.viewer import StartOptions
from marraztu.frontends.screenshot import take_screenshot
from marraztu.loaders.gltf import rewrite
from marraztu.loaders.registry import load_model
from marraztu.model.sampling import DEFAULT_SAMPLING, Filter, TextureSampling, Wrap
from marraztu.render import mipmaps
from support.refusals import one_line_refusal

SIZE = (120, 120)
CHECKER = np.array([[[255, 0, 0], [0, 255, 0]], [[0, 0, 255], [255, 255, 255]]], np.uint8)  # top row first
# Each texel by the channels it leaves lit (any lighting scales them, none adds one): red, green, blue, white.
TEXELS = {(True, False, False): (0, 0), (False, True, False): (0, 1), (False, False, True): (1, 0),
          (True, True, True): (1, 1)}
CLAMP, MIRRORED, REPEAT, NEAREST = 33071, 33648, 10497, 9728


def png_uri(pixels: np.ndarray) -> str:
    out = io.BytesIO()
    Image.fromarray(pixels).save(out, format="PNG")
    return "data:image/png;base64," + base64.b64encode(out.getvalue()).decode()


def square(path: Path, materials: list[dict[str, Any]], textures: list[dict[str, Any]],
           samplers: tuple[dict[str, Any], ...] | list[dict[str, Any]] = (), uv_range: tuple[float, float] = (0.0, 1.0),
           pixels: np.ndarray = CHECKER) -> Path:
    """A .gltf of a square facing the camera (one primitive a material, side by side), its texture
    coordinates over `uv_range` on both axes, the picture upright (glTF's v = 0 is its top row)."""
    low, high = uv_range
    positions, uvs, indices = [], [], []
    width = 120 / len(materials)
    for number in range(len(materials)):
        left = -60 + number * width
        positions.append(np.array([[left, -60, 0], [left + width, -60, 0], [left + width, 60, 0], [left, 60, 0]]))
        uvs.append(np.array([[low, high], [high, high], [high, low], [low, low]]))
        indices.append(np.array([0, 1, 2, 0, 2, 3]) + 4 * number)
    tables = [np.concatenate(positions).astype(np.float32), np.concatenate(uvs).astype(np.float32),
              np.concatenate(indices).astype(np.uint16)]
    blob, views = b"", []
    for table in tables:
        views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": table.nbytes})
        blob += table.tobytes() + b"\0" * (-table.nbytes % 4)
    count = 4 * len(materials)
    accessors = [{"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3",
                  "min": [-60, -60, 0], "max": [60, 60, 0]},
                 {"bufferView": 1, "componentType": 5126, "count": count, "type": "VEC2"}]
    primitives = []
    for number in range(len(materials)):
        views.append({"buffer": 0, "byteOffset": views[2]["byteOffset"] + 12 * number, "byteLength": 12})
        accessors.append({"bufferView": len(views) - 1, "componentType": 5123, "count": 6, "type": "SCALAR"})
        primitives.append({"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": len(accessors) - 1,
                           "material": number})
    document = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                "meshes": [{"primitives": primitives}], "accessors": accessors, "bufferViews": views,
                "buffers": [{"byteLength": len(blob),
                             "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
                "images": [{"uri": png_uri(pixels)}], "textures": textures, "materials": materials}
    if samplers:
        document["samplers"] = list(samplers)
    path.write_text(json.dumps(document))
    return path


def checker_square(path: Path, sampler: dict[str, Any] | None, uv_range: tuple[float, float] = (0.0, 1.0)) -> Path:
    texture = {"source": 0} if sampler is None else {"source": 0, "sampler": 0}
    return square(path, [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}], [texture],
                  [] if sampler is None else [sampler], uv_range)


def shot(tmp_path: Path, model: Path, keys: str = "") -> np.ndarray:
    out = take_screenshot(StartOptions(empty=True, models=(model,)), tmp_path / f"{model.stem}.png", SIZE, keys=keys)
    return np.asarray(Image.open(out).convert("RGB")).astype(int)


def square_pixels(picture: np.ndarray) -> np.ndarray:
    """The square's pixels, top row first, less a pixel at each edge: where it differs from the background."""
    background = picture[0, 0]
    rows, columns = np.nonzero((picture != background).any(axis=2))
    return picture[rows.min() + 1:rows.max(), columns.min() + 1:columns.max()]


def texel_at(pixels: np.ndarray, u: float, v: float, uv_range: tuple[float, float]) -> tuple[int, int]:
    """The texel (row, column) drawn where the square's coordinates are (u, v) (v = 0 at its top)."""
    low, high = uv_range
    row = round((v - low) / (high - low) * (pixels.shape[0] - 1))
    column = round((u - low) / (high - low) * (pixels.shape[1] - 1))
    return TEXELS[tuple(bool(channel) for channel in pixels[row, column] > 8)]


def wrapped(mode: int, coordinate: float) -> float:
    """glTF's wraps, as its specification defines them."""
    if mode == CLAMP:
        return min(max(coordinate, 0.0), 0.999)
    if mode == MIRRORED:
        inside = coordinate % 2
        return inside if inside < 1 else 2 - inside
    return coordinate % 1


# --- samplers ----------------------------------------------------------------------------------------
def test_a_nearest_magnified_picture_shows_its_texels_alone(tmp_path: Path) -> None:
    nearest = square_pixels(shot(tmp_path, checker_square(tmp_path / "nearest.gltf", {"magFilter": NEAREST})))
    blended = square_pixels(shot(tmp_path, checker_square(tmp_path / "linear.gltf", None)))
    colours = {tuple(pixel) for pixel in nearest.reshape(-1, 3)}
    assert len(colours) == 4  # one colour a texel, lit alike over the flat square
    half_row, half_column = nearest.shape[0] // 2, nearest.shape[1] // 2
    for row in range(2):
        for column in range(2):
            quarter = nearest[row * half_row:(row + 1) * half_row, column * half_column:(column + 1) * half_column]
            assert (quarter == quarter[0, 0]).all()
            assert TEXELS[tuple(bool(channel) for channel in quarter[0, 0] > 8)] == (row, column)
    assert len({tuple(pixel) for pixel in blended.reshape(-1, 3)}) > 50  # without a sampler: blended, as before


def assert_wraps_as_gltf_says(tmp_path: Path, wrap_s: int, wrap_t: int) -> None:
    """A square whose coordinates run -1..2 read at 25 points, each the texel glTF's wraps give there."""
    uv_range = (-1.0, 2.0)
    path = checker_square(tmp_path / "wrapped.gltf", {"magFilter": NEAREST, "wrapS": wrap_s, "wrapT": wrap_t},
                          uv_range)
    pixels = square_pixels(shot(tmp_path, path))
    for u in (-0.75, -0.25, 0.25, 1.25, 1.75):
        for v in (-0.75, -0.25, 0.25, 1.25, 1.75):
            expected = (int(wrapped(wrap_t, v) * 2), int(wrapped(wrap_s, u) * 2))
            assert texel_at(pixels, u, v, uv_range) == expected, (u, v)


@pytest.mark.parametrize(("wrap_s", "wrap_t"), [(CLAMP, CLAMP), (MIRRORED, MIRRORED), (REPEAT, REPEAT),
                                                (CLAMP, MIRRORED), (MIRRORED, REPEAT), (REPEAT, CLAMP)])
def test_coordinates_outside_0_to_1_read_the_picture_as_each_axis_wrap_says(tmp_path: Path, wrap_s: int,
                                                                             wrap_t: int) -> None:
    assert_wraps_as_gltf_says(tmp_path, wrap_s, wrap_t)


def test_a_mirrored_wrap_holds_without_glvnd(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Where libOpenGL.so.0 is missing (macOS, Windows), the platform's GL library sets the mirror."""
    monkeypatch.setattr(mipmaps, "_gl", lambda: None)
    assert_wraps_as_gltf_says(tmp_path, MIRRORED, MIRRORED)


def test_one_picture_sampled_two_ways_by_two_materials_is_drawn_both_ways(tmp_path: Path) -> None:
    """The renderer makes a texture of a picture a sampling: the first material's would have served both."""
    materials = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": number}}} for number in range(2)]
    path = square(tmp_path / "two.gltf", materials, [{"source": 0, "sampler": 0}, {"source": 0, "sampler": 1}],
                  [{"magFilter": NEAREST}, {}])
    loaded = load_model(path)
    assert [material.sampling for material in loaded.materials] == [
        TextureSampling(magnify=Filter.NEAREST), DEFAULT_SAMPLING]
    assert loaded.materials[0].texture is loaded.materials[1].texture  # one picture, read once
    pixels = square_pixels(shot(tmp_path, path))
    half = pixels.shape[1] // 2
    assert len({tuple(pixel) for pixel in pixels[:, :half - 1].reshape(-1, 3)}) == 4
    assert len({tuple(pixel) for pixel in pixels[:, half + 1:].reshape(-1, 3)}) > 20


@pytest.mark.parametrize(("sampler", "sampling"), [
    ({}, DEFAULT_SAMPLING),
    ({"wrapS": CLAMP, "wrapT": MIRRORED}, TextureSampling(wrap_u=Wrap.CLAMP, wrap_v=Wrap.MIRROR)),
    ({"magFilter": NEAREST, "minFilter": 9984},  # Blender's "Closest"
     TextureSampling(magnify=Filter.NEAREST, minify=Filter.NEAREST, between_levels=Filter.NEAREST)),
    ({"minFilter": 9728}, TextureSampling(minify=Filter.NEAREST, between_levels=None)),
    ({"minFilter": 9729}, TextureSampling(between_levels=None)),
    ({"minFilter": 9985}, TextureSampling(between_levels=Filter.NEAREST)),
    ({"minFilter": 9986}, TextureSampling(minify=Filter.NEAREST)),
    ({"magFilter": 9729, "minFilter": 9987, "wrapS": REPEAT, "wrapT": REPEAT}, DEFAULT_SAMPLING),
])
def test_a_samplers_values_become_the_materials_sampling(tmp_path: Path, sampler: dict[str, Any],
                                                         sampling: TextureSampling) -> None:
    loaded = load_model(checker_square(tmp_path / "square.gltf", sampler))
    assert loaded.materials[0].sampling == sampling
    assert loaded.materials[0].name == "square" and loaded.warnings == ()  # the model's, not the number trimesh read


def test_a_numbered_materials_own_name_is_kept(tmp_path: Path) -> None:
    materials = [{"name": "pixels", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}},
                 {"name": "marraztu glTF material 0", "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}}}]
    loaded = load_model(square(tmp_path / "named.gltf", materials, [{"source": 0, "sampler": 0}, {"source": 0}],
                               [{"magFilter": NEAREST}]))
    assert [(material.name, material.sampling) for material in loaded.materials] == [
        ("pixels", TextureSampling(magnify=Filter.NEAREST)), ("marraztu glTF material 0", DEFAULT_SAMPLING)]


def test_a_sampler_of_a_picture_not_drawn_changes_nothing(tmp_path: Path) -> None:
    """A normal map's sampler: the base colour texture is sampled as before."""
    material = {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}, "normalTexture": {"index": 1}}
    loaded = load_model(square(tmp_path / "normal.gltf", [material], [{"source": 0}, {"source": 0, "sampler": 0}],
                               [{"magFilter": NEAREST, "wrapS": CLAMP}]))
    assert loaded.materials[0].sampling == DEFAULT_SAMPLING


def test_a_sampling_is_checked_where_it_is_made() -> None:
    with pytest.raises(ValueError, match="wrap_u must be a Wrap"):
        TextureSampling(wrap_u="clamp")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="magnify must be a Filter"):
        TextureSampling(magnify=None)  # type: ignore[arg-type]


# --- specular-glossiness -----------------------------------------------------------------------------
@pytest.mark.parametrize("extension", [
    {"diffuseFactor": [0.8, 0.2, 0.2, 1.0]},  # specularFactor left out: 1, trimesh's white
    {"diffuseFactor": [0.8, 0.2, 0.2, 1.0], "specularFactor": [0.2, 0.2, 0.2], "glossinessFactor": 0.5},
])
def test_a_specular_glossiness_diffuse_colour_is_drawn_as_a_base_colour_is(tmp_path: Path,
                                                                           extension: dict[str, Any]) -> None:
    glossy = {"pbrMetallicRoughness": {"baseColorFactor": [0, 1, 0, 1]},  # the extension's colour wins
              "extensions": {"KHR_materials_pbrSpecularGlossiness": extension}}
    plain = {"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.2, 0.2, 1.0]}}
    glossy_path = square(tmp_path / "glossy.gltf", [glossy], [{"source": 0}])
    plain_path = square(tmp_path / "plain.gltf", [plain], [{"source": 0}])
    assert load_model(glossy_path).file_material == {"kd": (0.8, 0.2, 0.2)}
    assert (shot(tmp_path, glossy_path, keys="T 0") == shot(tmp_path, plain_path, keys="T 0")).all()


def test_a_specular_glossiness_diffuse_texture_is_drawn_as_its_picture_with_its_sampler(tmp_path: Path) -> None:
    pixels = np.array([[[200, 40, 40], [40, 200, 40]], [[40, 40, 200], [120, 120, 120]]], np.uint8)
    glossy = {"extensions": {"KHR_materials_pbrSpecularGlossiness": {
        "diffuseTexture": {"index": 0}, "specularFactor": [0.5, 0.5, 0.5],
        "specularGlossinessTexture": {"index": 0}}}}
    plain = {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}
    textures, samplers = [{"source": 0, "sampler": 0}], [{"magFilter": NEAREST}]
    glossy_path = square(tmp_path / "glossy.gltf", [glossy], textures, samplers, pixels=pixels)
    plain_path = square(tmp_path / "plain.gltf", [plain], textures, samplers, pixels=pixels)
    loaded = load_model(glossy_path)
    assert (loaded.materials[0].texture == pixels).all()
    assert loaded.materials[0].sampling == TextureSampling(magnify=Filter.NEAREST)
    assert (shot(tmp_path, glossy_path, keys="0") == shot(tmp_path, plain_path, keys="0")).all()


def test_a_specular_glossiness_diffuse_factor_is_checked_as_a_base_colour(tmp_path: Path) -> None:
    glossy = {"extensions": {"KHR_materials_pbrSpecularGlossiness": {"diffuseFactor": [0.8, "red", 0.2, 1.0]}}}
    path = square(tmp_path / "bad.gltf", [glossy], [{"source": 0}])
    with pytest.raises(Exception, match="material 0's diffuseFactor is not a list of numbers"):
        load_model(path)


def test_a_specular_glossiness_diffuse_factor_outside_0_to_1_is_a_note(tmp_path: Path) -> None:
    glossy = {"extensions": {"KHR_materials_pbrSpecularGlossiness": {"diffuseFactor": [1.5, 0.2, 0.2, 1.0]}}}
    loaded = load_model(square(tmp_path / "bright.gltf", [glossy], [{"source": 0}]))
    assert loaded.warnings == ("material 0's diffuseFactor holds 1.5: glTF's colours are 0..1, held to it",)


# --- texture coordinate sets -------------------------------------------------------------------------
BLUE_TEXEL_MIDDLE = (0.25, 0.75)  # glTF's v = 0 is the picture's top row: the lower left texel, blue


def with_second_set(path: Path, uv: tuple[float, float]) -> Path:
    """The square's file with a TEXCOORD_1 on every primitive: each vertex at `uv`, in a buffer of its own."""
    document = json.loads(path.read_text())
    count = document["accessors"][0]["count"]
    table = np.tile(np.array(uv, np.float32), (count, 1))
    document["buffers"].append({"byteLength": table.nbytes,
                                "uri": "data:application/octet-stream;base64," + base64.b64encode(table).decode()})
    document["bufferViews"].append({"buffer": 1, "byteLength": table.nbytes})
    document["accessors"].append({"bufferView": len(document["bufferViews"]) - 1, "componentType": 5126,
                                  "count": count, "type": "VEC2"})
    for primitive in document["meshes"][0]["primitives"]:
        primitive["attributes"]["TEXCOORD_1"] = len(document["accessors"]) - 1
    path.write_text(json.dumps(document))
    return path


@pytest.mark.parametrize("specular_glossiness", [False, True])
def test_a_base_colour_texture_is_laid_on_by_the_set_its_tex_coord_names(tmp_path: Path,
                                                                         specular_glossiness: bool) -> None:
    """Khronos's MultiUVTest: a material whose base colour texture reads TEXCOORD_1 was laid on by
    TEXCOORD_0, with a note. The left half reads TEXCOORD_1 (every vertex on the blue texel), the right
    half TEXCOORD_0 (the whole picture), of the same primitives' attributes."""
    def material(texture_set: int) -> dict[str, Any]:
        texture = {"index": 0, "texCoord": texture_set}
        if specular_glossiness:
            return {"extensions": {"KHR_materials_pbrSpecularGlossiness": {"diffuseTexture": texture}}}
        return {"pbrMetallicRoughness": {"baseColorTexture": texture}}

    path = with_second_set(square(tmp_path / "sets.gltf", [material(1), material(0)], [{"source": 0, "sampler": 0}],
                                  [{"magFilter": NEAREST}]), BLUE_TEXEL_MIDDLE)
    pixels = square_pixels(shot(tmp_path, path))
    half = pixels.shape[1] // 2
    left = {TEXELS[tuple(bool(channel) for channel in pixel > 8)] for pixel in pixels[:, :half - 1].reshape(-1, 3)}
    right = {TEXELS[tuple(bool(channel) for channel in pixel > 8)] for pixel in pixels[:, half + 1:].reshape(-1, 3)}
    assert left == {(1, 0)}  # blue alone
    assert right == {(0, 0), (0, 1), (1, 0), (1, 1)}
    assert load_model(path).warnings == ()


# --- KHR_texture_transform ---------------------------------------------------------------------------
def transformed(transform: dict[str, Any], texture_set: int | None = None) -> dict[str, Any]:
    """A material whose base colour texture (texture 0) has this KHR_texture_transform."""
    texture: dict[str, Any] = {"index": 0, "extensions": {"KHR_texture_transform": transform}}
    if texture_set is not None:
        texture["texCoord"] = texture_set
    return {"pbrMetallicRoughness": {"baseColorTexture": texture}}


def moved(uvs: np.ndarray, transform: dict[str, Any]) -> np.ndarray:
    """glTF (u, v)s through a transform as T * R * S, R turning the UVs as Khronos's TextureTransformTest
    and glTF's viewers do (the extension's GLSL listing, read column-major, turns them the other way:
    KhronosGroup/glTF issue 1563)."""
    (offset_u, offset_v), rotation = transform.get("offset", [0, 0]), transform.get("rotation", 0)
    scale_u, scale_v = transform.get("scale", [1, 1])
    cos, sin = np.cos(rotation), np.sin(rotation)
    translation = np.array([[1, 0, offset_u], [0, 1, offset_v], [0, 0, 1]])
    turn = np.array([[cos, sin, 0], [-sin, cos, 0], [0, 0, 1]])
    scale = np.diag([scale_u, scale_v, 1])
    return (np.column_stack([uvs, np.ones(len(uvs))]) @ (translation @ turn @ scale).T)[:, :2]


def as_drawn(uvs: np.ndarray) -> np.ndarray:
    """glTF (u, v)s as a Mesh holds them: v up, as an OBJ's (glTF's v = 0 is the picture's top row)."""
    return np.column_stack([uvs[:, 0], 1 - uvs[:, 1]])


SQUARE_UVS = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], float)  # square()'s corners, in its order
ATLAS_TILE = {"offset": [0.5, -0.25], "rotation": 0.3, "scale": [2.0, 0.5]}


def test_a_base_colour_textures_transform_moves_the_coordinates_read_back(tmp_path: Path) -> None:
    """trimesh applies no KHR_texture_transform: an atlas's tile was drawn as the whole picture, with a
    note. Its offset, rotation and scale are applied to the uvs the mesh holds."""
    path = square(tmp_path / "tile.gltf", [transformed(ATLAS_TILE)], [{"source": 0}])
    loaded = load_model(path)
    assert np.allclose(loaded.uvs, as_drawn(moved(SQUARE_UVS, ATLAS_TILE)), atol=1e-6)
    assert loaded.warnings == ()


def test_coordinates_shared_by_primitives_are_moved_once_for_each_transform(tmp_path: Path,
                                                                           monkeypatch: pytest.MonkeyPatch) -> None:
    """Four primitives read one accessor of uvs (square()'s), two by one transform, one by another, one by
    none: each is drawn by its own material's, the file's values unchanged, each transform applied once."""
    other = {"rotation": -1.0, "scale": [1, 3]}
    path = square(tmp_path / "shared.gltf", [transformed(ATLAS_TILE), {"pbrMetallicRoughness": {"baseColorTexture": {
        "index": 0}}}, transformed(other), transformed(ATLAS_TILE)], [{"source": 0}])
    passes: list[int] = []
    moving = rewrite._moved_uvs
    monkeypatch.setattr(rewrite, "_moved_uvs", lambda uvs, affine: passes.append(len(uvs)) or moving(uvs, affine))
    loaded = load_model(path)
    rows = np.split(loaded.uvs, 4)  # each primitive reads all 16 vertices, and is given the 4 it draws
    for read, transform in zip(rows, (ATLAS_TILE, None, other, ATLAS_TILE), strict=True):
        assert np.allclose(read, as_drawn(SQUARE_UVS if transform is None else moved(SQUARE_UVS, transform)), atol=1e-6)
    assert passes == [16, 16]


def quarters(pixels: np.ndarray) -> list[tuple[int, int]]:
    """The texel drawn at the middle of each quarter of the square, top left, top right, bottom left, right."""
    return [texel_at(pixels, u, v, (0.0, 1.0)) for v in (0.25, 0.75) for u in (0.25, 0.75)]


def test_a_turned_texture_is_drawn_turned_as_the_extension_says(tmp_path: Path) -> None:
    """The extension's example: offset (0, 1), a quarter turn. The square at (u, v) reads the picture at
    (v, 1 - u): its top left quarter the picture's lower left (blue), and so round."""
    transform = {"offset": [0, 1], "rotation": np.pi / 2}
    path = square(tmp_path / "turned.gltf", [transformed(transform)], [{"source": 0, "sampler": 0}],
                  [{"magFilter": NEAREST}])
    middles = moved(np.array([[u, v] for v in (0.25, 0.75) for u in (0.25, 0.75)]), transform)
    assert np.allclose(middles, [[0.25, 0.75], [0.25, 0.25], [0.75, 0.75], [0.75, 0.25]])  # the sign checked
    assert quarters(square_pixels(shot(tmp_path, path))) == [(1, 0), (0, 0), (1, 1), (0, 1)]


def test_a_transforms_tex_coord_overrides_the_textures(tmp_path: Path) -> None:
    """KHR_texture_transform's texCoord names the set the texture reads in place of the textureInfo's."""
    path = with_second_set(square(tmp_path / "override.gltf", [transformed({"texCoord": 1}, texture_set=0)],
                                  [{"source": 0, "sampler": 0}], [{"magFilter": NEAREST}]), BLUE_TEXEL_MIDDLE)
    assert set(quarters(square_pixels(shot(tmp_path, path)))) == {(1, 0)}  # blue alone


def test_a_texture_whose_transform_names_its_set_does_not_ask_for_the_set_its_own_tex_coord_names(
        tmp_path: Path) -> None:
    """A primitive of TEXCOORD_1 alone, whose base colour texture says texCoord 0 and its transform 1, was
    refused for want of TEXCOORD_0, which nothing would read."""
    path = square(tmp_path / "only_second.gltf", [transformed({"texCoord": 1}, texture_set=0)], [{"source": 0}])
    document = json.loads(path.read_text())
    attributes = document["meshes"][0]["primitives"][0]["attributes"]
    attributes["TEXCOORD_1"] = attributes.pop("TEXCOORD_0")
    path.write_text(json.dumps(document))
    loaded = load_model(path)
    assert np.allclose(loaded.uvs, as_drawn(SQUARE_UVS), atol=1e-6)
    assert loaded.warnings == ()


@pytest.mark.parametrize(("extensions", "words"), [
    ([{"KHR_texture_transform": {"scale": [2, 2]}}], "material 0's baseColorTexture's extensions are not an object"),
    ({"KHR_texture_transform": [1]}, "material 0's baseColorTexture's KHR_texture_transform is not an object"),
    ({"KHR_texture_transform": {"offset": [1]}},
     "material 0's baseColorTexture's KHR_texture_transform's offset is not 2 finite numbers"),
    ({"KHR_texture_transform": {"scale": [1, "2"]}},
     "material 0's baseColorTexture's KHR_texture_transform's scale is not 2 finite numbers"),
    ({"KHR_texture_transform": {"scale": [1, float("inf")]}},
     "material 0's baseColorTexture's KHR_texture_transform's scale is not 2 finite numbers"),
    ({"KHR_texture_transform": {"rotation": float("nan")}},
     "material 0's baseColorTexture's KHR_texture_transform's rotation is not a finite number"),
    ({"KHR_texture_transform": {"texCoord": -1}},
     "material 0's baseColorTexture's KHR_texture_transform's texCoord is not a whole number of 0 or more"),
    ({"KHR_texture_transform": {"texCoord": 2}},
     "mesh 0's primitive 0 has no TEXCOORD_2, which material 0's baseColorTexture's KHR_texture_transform reads "
     "(its texCoord)"),
])
def test_a_transform_not_shaped_as_the_extensions_is_refused(tmp_path: Path, extensions: dict[str, Any],
                                                             words: str) -> None:
    """trimesh passed over them; applied, a NaN rotation would make every coordinate NaN."""
    material = {"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": extensions}}}
    path = square(tmp_path / "bad.gltf", [material], [{"source": 0}])
    assert str(one_line_refusal(lambda: load_model(path))) == f"{path}: not a glTF file: {words}"


@pytest.mark.parametrize("normalized", [False, True])
def test_quantized_coordinates_are_moved_as_the_numbers_they_stand_for(tmp_path: Path, normalized: bool) -> None:
    """gltfpack stores texture coordinates as unsigned shorts (KHR_mesh_quantization) and gives the
    transform that scales them back: unnormalized, the integers are moved; normalized, their fractions."""
    path = square(tmp_path / "quantized.gltf", [transformed({"offset": [0.25, 0], "scale": [1 / 1023, 1 / 1023]})],
                  [{"source": 0}])
    document = json.loads(path.read_text())
    shorts = (SQUARE_UVS * 1023).astype(np.uint16)
    document["buffers"].append({"byteLength": shorts.nbytes,
                                "uri": "data:application/octet-stream;base64," + base64.b64encode(shorts).decode()})
    document["bufferViews"].append({"buffer": 1, "byteLength": shorts.nbytes})
    document["accessors"][1].update(bufferView=len(document["bufferViews"]) - 1, componentType=5123,
                                    normalized=normalized)
    document["extensionsUsed"] = document["extensionsRequired"] = ["KHR_mesh_quantization"]
    path.write_text(json.dumps(document))
    stored = shorts / 65535 if normalized else shorts  # the numbers they stand for, as glTF defines them
    assert np.allclose(load_model(path).uvs, as_drawn(stored / 1023 + [0.25, 0]), atol=1e-6)


@pytest.mark.parametrize(("transform", "vertex"), [
    ({"offset": [1e308, 1e308]}, 0),
    ({"scale": [1e39, 1]}, 1),  # u = 0 stays 0: the first vertex moved past is square()'s second
    ({"scale": [1.7e308, 1.7e308], "rotation": 0.7853981633974483}, 0),  # past float64's too
])
def test_a_transform_that_takes_coordinates_past_float32_is_refused_naming_it(tmp_path: Path, transform: dict[str, Any],
                                                                            vertex: int) -> None:
    """Finite values that move finite coordinates past float32's range: numpy's overflow warnings were printed
    and the file was refused as if it held a coordinate that is not a finite number."""
    path = square(tmp_path / "far.gltf", [transformed(transform)], [{"source": 0}])
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # numpy's RuntimeWarning, printed past the one line
        refused = one_line_refusal(lambda: load_model(path))
    assert str(refused) == (f"{path}: mesh 0's primitive 0: material 0's baseColorTexture's KHR_texture_transform "
                            f"moves vertex {vertex} of its TEXCOORD_0 (accessor 1) past 3.4e38, where the GPU's 32-bit "
                            "numbers end")
