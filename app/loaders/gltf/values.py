"""The value predicates, tables and look-ups the package's other modules share: glTF's component and
type tables, its modes of primitive, a material's base colour, uv set and texture transform, a mesh's
name and copy, the accessors a primitive reads, Draco's attributes, and the limit on what is made. It
imports none of its siblings.
"""

from __future__ import annotations

import importlib.util
import math
import sys
from collections.abc import Iterator
from typing import Any

import numpy as np

from marraztu.errors import escaped, shortened

# An accessor's component types as numpy reads them, and their bytes; and the components of its types.
_COMPONENT_DTYPES = {5120: "<i1", 5121: "<u1", 5122: "<i2", 5123: "<u2", 5125: "<u4", 5126: "<f4"}
_COMPONENT_BYTES = {kind: np.dtype(dtype).itemsize for kind, dtype in _COMPONENT_DTYPES.items()}
_TYPE_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
_SPARSE_INDEX_BYTES = {5121: 1, 5123: 2, 5125: 4}  # a sparse accessor's indices: unsigned integers


# What trimesh copies (each buffer view, each accessor's items from its view) and what is written before
# it builds the meshes (the zeros, or sparse items, of an accessor a primitive reads) adds up, in a file
# as glTF's writers make it, to at most the bytes the file and its buffers hold: past twice those and
# this many more, a file is refused unread (a POSITION of 3M zeros from 400 bytes took 376 MB).
MADE_FLOOR_BYTES = 1 << 20


def made_limit(held: int) -> int:
    """The bytes a glTF whose file and buffers hold `held` may make: twice them, and MADE_FLOOR_BYTES more."""
    return 2 * held + MADE_FLOOR_BYTES


def past_made_limit(held: int) -> str:
    return (f"more than the {made_limit(held)} a file and buffers of {held} bytes may make (twice them, and "
            f"{MADE_FLOOR_BYTES} more)")


def _texture_infos(material: dict[str, Any]) -> Iterator[tuple[str, dict[str, Any]]]:
    """A material's textures (its own, its pbrMetallicRoughness's and a specular-glossiness diffuseTexture),
    each with its key: what trimesh reads as one, an object with an index."""
    values = material.get("pbrMetallicRoughness", {})
    for key, value in (*material.items(), *(values.items() if isinstance(values, dict) else ()),
                       *_diffuse_values(material)):
        if isinstance(value, dict) and "index" in value:
            yield str(key), value


# A material of the specular-glossiness workflow: its diffuse colour is what the lighting's Kd is.
_SPECULAR_GLOSSINESS = "KHR_materials_pbrSpecularGlossiness"
_DIFFUSE_KEYS = {"diffuseFactor": "baseColorFactor", "diffuseTexture": "baseColorTexture"}
# The keys of a base colour texture, which trimesh takes as the picture where it is not an object.
_BASE_COLOUR_TEXTURES = ("baseColorTexture", "diffuseTexture")


def _specular_glossiness(material: dict[str, Any]) -> dict[str, Any] | None:
    extension = _nested(material, ("extensions",)).get(_SPECULAR_GLOSSINESS)
    return extension if isinstance(extension, dict) else None


def _diffuse_values(material: dict[str, Any]) -> list[tuple[str, Any]]:
    """A specular-glossiness material's diffuseFactor and diffuseTexture, those it gives."""
    extension = _specular_glossiness(material) or {}
    return [(key, extension[key]) for key in _DIFFUSE_KEYS if key in extension]


def _base_colour(material: dict[str, Any]) -> tuple[dict[str, Any], str, str]:
    """Where a material's base colour lies, and its factor's and texture's keys there: a specular-glossiness
    material's diffuseFactor and diffuseTexture (which a glTF viewer that reads the extension takes over the
    metallic-roughness ones), else its pbrMetallicRoughness's baseColorFactor and baseColorTexture."""
    extension = _specular_glossiness(material)
    if extension is not None:
        return extension, "diffuseFactor", "diffuseTexture"
    return _nested(material, ("pbrMetallicRoughness",)), "baseColorFactor", "baseColorTexture"


def _item_bytes(accessor: dict[str, Any]) -> int:
    """The bytes of a checked accessor's item."""
    return _COMPONENT_BYTES[accessor["componentType"]] * _TYPE_COMPONENTS[accessor["type"]]


def _numbers_of(value: object, size: int | None) -> bool:
    """One number (size None), or a list of `size` (a baseColorFactor of 3, as trimesh reads it, too)."""
    if size is None:
        return _is_number(value)
    sizes = (size, 3) if size == 4 else (size,)
    return isinstance(value, list) and len(value) in sizes and all(map(_is_number, value))


def _is_whole(value: object) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def _is_finite(number: float) -> bool:
    """A number that is one as a float: not NaN, not infinite, no whole number past float's range."""
    return math.isfinite(number) if isinstance(number, float) else abs(number) <= sys.float_info.max


def _is_number(value: object) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _draco_decoder() -> bool:
    """trimesh decodes Draco where DracoPy is installed (not a dependency: it is built for few platforms)."""
    return importlib.util.find_spec("DracoPy") is not None


# glTF's modes of primitive: trimesh reads points and lines (placed, not drawn), triangles and strips;
# it skips line loops, line strips and fans (fans are made triangles for it: _fans_made_triangles).
_POINTS, _LINES, _LINE_LOOP, _LINE_STRIP, _TRIANGLES, _STRIP, _FAN = 0, 1, 2, 3, 4, 5, 6
_READ_MODES = (_POINTS, _LINES, _TRIANGLES, _STRIP)  # trimesh makes something of these, and skips the rest
_FAN_LEAST_CORNERS = 3  # a fan of fewer draws nothing, in glTF too: left a fan, which trimesh skips


def _listed(value: object) -> list[Any]:
    return value if isinstance(value, list) else []


def _base_colour_texture(material: dict[str, Any]) -> dict[str, Any]:
    """A material's base colour texture's textureInfo (empty where it has none)."""
    where, _, key = _base_colour(material)
    return _nested(where, (key,))


def _is_drawn(primitive: dict[str, Any]) -> bool:
    return primitive.get("mode", _TRIANGLES) in _DRAWN_MODES


def _read_accessors(primitive: dict[str, Any]) -> list[Any]:
    """The accessors a primitive reads: its attributes' and its indices (None where it has none)."""
    return [*primitive["attributes"].values(), primitive.get("indices")]


def _draco_attributes(primitive: dict[str, Any]) -> dict[str, Any]:
    """The attributes a primitive's Draco stream holds (name: its id in the stream); empty where none."""
    return _nested(primitive, ("extensions", "KHR_draco_mesh_compression", "attributes"))


def _drawn_uv_set(material: dict[str, Any]) -> int:
    """The texCoord of a material's base colour texture, where it has one (an index), else 0: its
    KHR_texture_transform's where that gives one, which overrides the textureInfo's."""
    texture = _base_colour_texture(material)
    if "index" not in texture:
        return 0
    return _nested(texture, ("extensions", _TEXTURE_TRANSFORM)).get("texCoord", texture.get("texCoord", 0))


_TEXTURE_TRANSFORM = "KHR_texture_transform"

_MATERIALS_VARIANTS = "KHR_materials_variants"  # its default materials drawn, its variants a note
# Extensions a file may require that are read as it means them (checks._required_extension_read).
_READ_EXTENSIONS = ("KHR_draco_mesh_compression", "KHR_mesh_quantization", _TEXTURE_TRANSFORM,
                    _SPECULAR_GLOSSINESS, _MATERIALS_VARIANTS,
                    "KHR_materials_emissive_strength", "KHR_materials_unlit")


def _is_undrawn_extension(name: object) -> bool:
    """Whether a required extension adds what SPEC 4's lighting (its four lights, Phong from the base colour)
    has no term for: a file's own lights, or a material's shading past the base colour, which glTF's
    material extensions add without changing the geometry; left out with a note."""
    return name == "KHR_lights_punctual" or (isinstance(name, str) and name.startswith("KHR_materials_")
                                             and name not in _READ_EXTENSIONS)


def _uv_transform(material: dict[str, Any]) -> tuple[float, ...] | None:
    """A checked material's base colour texture's KHR_texture_transform as the affine map of texture
    coordinates it gives, (a, b, c, d, e, f): u' = a u + b v + e, v' = c u + d v + f; None where it leaves
    them as they are. Its offset, rotation and scale as T * R * S, R the rotation glTF's viewers and
    Khronos's TextureTransformTest apply: the extension's GLSL listing turns the other way (glTF issue
    1563), and would move its example's quadrant off the picture."""
    texture = _base_colour_texture(material)
    transform = _nested(texture, ("extensions", _TEXTURE_TRANSFORM)) if "index" in texture else {}
    (offset_u, offset_v), rotation = transform.get("offset", [0, 0]), transform.get("rotation", 0)
    (scale_u, scale_v) = transform.get("scale", [1, 1])
    cos, sin = math.cos(rotation), math.sin(rotation)
    affine = (cos * scale_u, sin * scale_v, -sin * scale_u, cos * scale_v, float(offset_u), float(offset_v))
    return None if affine == _UNMOVED else affine


_UNMOVED = (1.0, 0.0, -0.0, 1.0, 0.0, 0.0)  # the affine map of a transform of no offset, rotation or scale


def _uvs_decoded_by_trimesh(primitive: dict[str, Any], material: dict[str, Any]) -> bool:
    """Whether the texture coordinates the primitive's base colour texture reads are in its Draco stream,
    which trimesh decodes where it can, and writes into the accessor the set names, after any made here."""
    return f"TEXCOORD_{_drawn_uv_set(material)}" in _draco_attributes(primitive) and _draco_decoder()


_DRAWN_MODES = (_TRIANGLES, _STRIP, _FAN)  # trimesh makes faces of the first two; fans are made triangles
_FLOAT_COMPONENTS = 5126


def _mesh_named(number: int, mesh: dict[str, Any]) -> str:
    """'mesh 2', and its name where it has one: 'mesh 2 ('wing')'."""
    name = mesh.get("name")
    return f"mesh {number} ('{shortened(escaped(name))}')" if name else f"mesh {number}"


def _mesh_copy(mesh: dict[str, Any]) -> dict[str, Any]:
    """A mesh for a shape of its own: its primitives, and their attributes, its own to change, without the
    targets and weights the shape applies (written again in each copy, they would be many times the file's)."""
    return {**{key: value for key, value in mesh.items() if key != "weights"},
            "primitives": [{**{key: value for key, value in primitive.items() if key != "targets"},
                            "attributes": dict(primitive["attributes"])} for primitive in mesh["primitives"]]}


_SKIN_SETS = ("JOINTS_", "WEIGHTS_")  # a skinned primitive's attributes: each JOINTS_n with its WEIGHTS_n


def _nested(item: dict[str, Any], keys: tuple[str, ...]) -> dict[str, Any]:
    for key in keys:
        inner = item.get(key)
        item = inner if isinstance(inner, dict) else {}
    return item
