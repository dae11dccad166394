"""glTF's JSON (a .gltf, or a GLB's chunk of it) read and checked before trimesh reads the file: what it
names, its byte ranges and the placements of its scene; the notes of what trimesh draws otherwise than
it says; the JSON made again where trimesh is to read it otherwise. Ours because trimesh reads the JSON
without these checks, and fails in words of its own internals, or draws what the file does not say.
"""

from __future__ import annotations

import base64
import binascii
import importlib.util
import json
import math
import re
import sys
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from marraztu.errors import LoadError, escaped, shortened
from marraztu.loaders.files import MAX_FILE_BYTES
from marraztu.model.mesh import counted
from marraztu.model.sampling import DEFAULT_SAMPLING, Filter, TextureSampling, Wrap

# A GLB holds its JSON and, after it, its binary buffer; chunks of other kinds are to be read past. Past
# this many after the JSON, a file is refused unread.
MAX_GLB_CHUNKS = 16


# --- a .gltf's JSON, and a GLB's chunks ----------------------------------------------------------
def gltf_document(path: Path, data: bytes, in_glb: bool = False) -> dict[str, Any]:
    """A .gltf's JSON (or a GLB's chunk of it: `in_glb`, whose lines are no lines of the file), checked
    to be glTF 2's: trimesh, given text that is not JSON, looks for a file named model.gltf and says
    that is missing."""
    try:
        document = json.loads(data)  # from bytes: UTF-8, -16 or -32, as the glTF's JSON may be
    except json.JSONDecodeError as error:
        if in_glb:
            raise LoadError(path, f"not a glTF file: its JSON is not valid: {error.msg} (line {error.lineno}, "
                                  f"column {error.colno} of its JSON chunk)") from None
        raise LoadError(path, f"not a glTF file: its JSON is not valid: {error.msg} (column {error.colno})",
                        line=error.lineno) from None
    except UnicodeDecodeError:
        raise LoadError(path, "not a glTF file: its JSON is not UTF-8 text") from None
    except RecursionError:
        raise LoadError(path, "not a glTF file: its JSON nests too deeply to read") from None
    except ValueError:  # an integer of thousands of digits, which Python will not read
        raise LoadError(path, "not a glTF file: its JSON holds a number too long to read") from None
    if not isinstance(document, dict):
        raise LoadError(path, "not a glTF file: its JSON is not an object of glTF's keys", line=None if in_glb else 1)
    _check_version(path, document)
    return document


def _check_version(path: Path, document: dict[str, Any]) -> None:
    """The asset's version, which glTF requires, as trimesh reads it: a string whose part before its first
    dot is a whole number (it says "'int' object has no attribute 'get'", or "invalid literal for int()"),
    of 2: a glTF 1 file is refused as one, its version a number too, as collada2gltf wrote some; trimesh
    read a file without one as glTF 2, and one of 3 as if it were."""
    asset = document.get("asset")
    if asset is not None and not isinstance(asset, dict):
        raise LoadError(path, "not a glTF file: its asset is not an object")
    version = (asset or {}).get("version")
    if version is None:
        raise LoadError(path, "not a glTF file: its asset gives no version (glTF 2's is \"2.0\")")
    if _is_number(version) and 0 <= version < 2:  # glTF 1's, as a number: a string in every glTF 2
        version = str(version)
    major = version.split(".", 1)[0] if isinstance(version, str) else ""
    if not (major.isascii() and major.isdecimal()):  # glTF's are ASCII digits; Python reads others too
        raise LoadError(path, f"not a glTF file: its asset's version {shortened(escaped(repr(version)))} is not a "
                              "version such as \"2.0\"")
    if major.lstrip("0") != str(_GLTF_MAJOR):  # not int(): Python refuses one of thousands of digits
        raise LoadError(path, f"a file of glTF version {shortened(escaped(version))}: only glTF 2 is read")
    _check_min_version(path, asset)


_GLTF_MAJOR = 2  # the glTF read here: 2.0 and its minor versions


def _check_min_version(path: Path, asset: dict[str, Any]) -> None:
    """The asset's minVersion, where it gives one: glTF's form, "major.minor", and no later than 2.0, the
    version read here (glTF: a reader refuses an asset whose minVersion it does not support; trimesh
    reads past it)."""
    if "minVersion" not in asset:
        return
    least = asset["minVersion"]
    if not (isinstance(least, str) and re.fullmatch(r"[0-9]+\.[0-9]+", least)):
        raise LoadError(path, f"not a glTF file: its asset's minVersion {shortened(escaped(repr(least)))} is not a "
                              "version such as \"2.0\"")
    major, minor = (part.lstrip("0") for part in least.split("."))
    if (len(major), major) > (1, str(_GLTF_MAJOR)) or major == str(_GLTF_MAJOR) and minor:  # past 2.0, as digits
        raise LoadError(path, f"a file that needs glTF {shortened(least)} or later (its asset's minVersion): only "
                              "glTF 2.0 is read")


def glb_document(path: Path, data: bytes) -> dict[str, Any]:
    """A GLB's JSON chunk, its frame checked: trimesh, given lying lengths, fails in words of its own
    internals (a missing text-encoding module, a chunk "not expected length")."""
    def word(at: int) -> int:
        return int.from_bytes(data[at:at + 4], "little")

    if len(data) < 20 or data[:4] != b"glTF":
        raise LoadError(path, "not a GLB file: it does not begin with glTF's 12-byte header and a chunk")
    if word(4) == 1:  # glTF 1.0's binary form (KHR_binary_glTF), as old Blender and collada2gltf wrote it
        raise LoadError(path, "a GLB of glTF version 1.0: only glTF 2 is read")
    if word(4) != _GLTF_MAJOR:
        raise LoadError(path, f"not a GLB file: its header gives version {word(4)}, where glTF 2's GLB gives 2")
    if word(8) > len(data):
        raise LoadError(path, f"cut short: its header gives {word(8)} bytes, the file holds {len(data)}")
    if data[16:20] != b"JSON":
        raise LoadError(path, "not a GLB file: its first chunk is not its JSON")
    if 20 + word(12) > word(8):
        raise LoadError(path, f"not a GLB file: its JSON chunk of {word(12)} bytes runs past the file's "
                              f"{word(8)}")
    document = gltf_document(path, data[20:20 + word(12)], in_glb=True)
    buffers = document.get("buffers")
    first = buffers[0] if isinstance(buffers, list) and buffers and isinstance(buffers[0], dict) else {}
    declared = first.get("byteLength")
    held = len(_binary_chunk(data))
    if "uri" not in first and _is_whole(declared) and declared > held:  # the buffer the binary chunk holds
        raise LoadError(path, f"cut short: its buffer is {declared} bytes, its binary chunk holds {held}")
    if first and "uri" not in first and not _holds_binary_chunk(data):
        raise LoadError(path, "not a GLB file: its buffer 0 has no uri, and no binary chunk follows its JSON")
    _check_glb_chunks(path, data, _after_json(data), word(8))
    return document


def _after_json(data: bytes) -> int:
    """Where a GLB's chunk after its JSON begins: where the JSON chunk ends, as trimesh reads it, not at the
    next multiple of four (glTF's writers pad the JSON; trimesh's own once did not, and reads its files so)."""
    return 20 + int.from_bytes(data[12:16], "little")


def _holds_binary_chunk(data: bytes) -> bool:
    """Whether a binary chunk follows a GLB's JSON within the length its header gives (trimesh reads no
    further): trimesh gives a buffer of no uri the next chunk's bytes, and where none is left reads no
    buffer after it (those made for it appended, say: an IndexError)."""
    at = _after_json(data)
    return data[at + 4:at + 8] == b"BIN\0" and at + 8 <= int.from_bytes(data[8:12], "little")


def _binary_chunk(data: bytes) -> memoryview:
    """A GLB's binary chunk, the one after its JSON, as much of it as the file holds; empty where none is."""
    at = _after_json(data)
    if not _holds_binary_chunk(data):
        return memoryview(b"")
    return memoryview(data)[at + 8:at + 8 + int.from_bytes(data[at:at + 4], "little")]


def _check_glb_chunks(path: Path, data: bytes, at: int, end: int) -> None:
    """The chunks after the JSON, as trimesh reads them (each where the one before ends, up to `end`, the
    length the header gives): each within it, and few (trimesh reads each in a Python loop: a million
    empty ones, 8 MB, took 3 s)."""
    for _ in range(MAX_GLB_CHUNKS):
        if at + 8 > end:
            return
        size = int.from_bytes(data[at:at + 4], "little")
        if at + 8 + size > end:  # trimesh said "chunk was not expected length!"
            raise LoadError(path, f"not a GLB file: its chunk at byte {at}, of {size} bytes, runs past the {end} "
                                  "its header gives")
        at += 8 + size
    if at + 8 <= end:
        raise LoadError(path, f"not a GLB file: more than {MAX_GLB_CHUNKS} chunks after its JSON (glTF writes one, "
                              "its binary buffer)")


def declared_part(data: bytes) -> bytes:
    """A GLB's bytes up to the length its header gives (checked not to pass the file's): trimesh read on
    past it, the bytes after as chunks."""
    declared = int.from_bytes(data[8:12], "little")
    return data if len(data) == declared else data[:declared]


# --- what it names beside it ---------------------------------------------------------------------
def gltf_pictures(document: dict[str, Any]) -> frozenset[str]:
    """The URIs of a .gltf's pictures (not its buffers', which may be named anything), as trimesh asks for them."""
    return frozenset(_uris(document.get("images"))) - frozenset(_uris(document.get("buffers")))


def buffer_bytes(document: dict[str, Any]) -> dict[str, int]:
    """The byteLength of each buffer a glTF names by a file URI, by the URI as trimesh asks for it."""
    buffers = document.get("buffers")
    return {as_trimesh_asks(item["uri"]): item["byteLength"] for item in buffers if isinstance(item, dict)
            and isinstance(item.get("uri"), str) and not _is_data_uri(item["uri"])
            and _is_whole(item.get("byteLength"))} if isinstance(buffers, list) else {}


def _uris(items: object) -> Iterator[str]:
    """The file URIs a glTF list of images or buffers gives (a data: URI holds its bytes itself), as
    trimesh asks for them."""
    for item in items if isinstance(items, list) else ():
        uri = item.get("uri") if isinstance(item, dict) else None
        if isinstance(uri, str) and not _is_data_uri(uri):
            yield as_trimesh_asks(uri)


def _is_data_uri(uri: str) -> bool:
    """A URI that holds its bytes itself (RFC 2397): of the scheme data, in any case."""
    return uri[:5].lower() == "data:"


def as_trimesh_asks(uri: str) -> str:
    """A file URI as trimesh is to ask the resolver for it: trimesh decodes what follows "base64," in any
    URI as the bytes themselves, so there its comma is percent-encoded, which names the same file."""
    return uri.replace("base64,", "base64%2C")


# --- what it names, checked ----------------------------------------------------------------------
# An accessor's component types as numpy reads them, and their bytes; and the components of its types.
_COMPONENT_DTYPES = {5120: "<i1", 5121: "<u1", 5122: "<i2", 5123: "<u2", 5125: "<u4", 5126: "<f4"}
_COMPONENT_BYTES = {kind: np.dtype(dtype).itemsize for kind, dtype in _COMPONENT_DTYPES.items()}
_TYPE_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 9, "MAT4": 16}
_SPARSE_INDEX_BYTES = {5121: 1, 5123: 2, 5125: 4}  # a sparse accessor's indices: unsigned integers
# The byteStride glTF allows a vertex attribute's view: a multiple of 4, from 4 to 252.
_ATTRIBUTE_ALIGNMENT, _LEAST_STRIDE, _MOST_STRIDE = 4, 4, 252
_NODE_TRANSFORMS = {"translation": 3, "rotation": 4, "scale": 3, "matrix": 16}
# A material's numbers as trimesh reads them (its words otherwise: "cannot reshape array of size 1 into
# shape (3,)", "Colors not of appropriate shape!"): how many, or None for one number.
_MATERIAL_NUMBERS = {"baseColorFactor": 4, "emissiveFactor": 3, "metallicFactor": None, "roughnessFactor": None,
                     "alphaCutoff": None, "diffuseFactor": 4}
_ALPHA_MODES = ("OPAQUE", "MASK", "BLEND")
_LEAST_EMISSION = -1e-5  # trimesh refuses an emissiveFactor below it ("all factors must be greater than 0.0")
# The accessor types of the attributes read here (POSITION, TEXCOORD_n, COLOR_n, and a skin's JOINTS_n and
# WEIGHTS_n) and of NORMAL, by the name before "_".
_ATTRIBUTE_TYPES = {"POSITION": ("VEC3",), "NORMAL": ("VEC3",), "TEXCOORD": ("VEC2",), "COLOR": ("VEC3", "VEC4"),
                    "JOINTS": ("VEC4",), "WEIGHTS": ("VEC4",)}
# The component types glTF allows of the attributes read here and of NORMAL (by the name before "_"), and of
# indices, each with whether it may be normalized (glTF's own, and KHR_mesh_quantization's for positions, normals
# and texture coordinates), and in words: trimesh read integers of any other kind as they were, without a word.
_ComponentTypes = tuple[dict[int, tuple[bool, ...]], str]
_FLOAT, _SMALL_INTEGERS = {5126: (False,)}, {kind: (False, True) for kind in (5120, 5121, 5122, 5123)}
_COMPONENT_TYPES: dict[str, _ComponentTypes] = {
    "POSITION": ({**_FLOAT, **_SMALL_INTEGERS},
                 "5126 (float), or 5120, 5121, 5122 or 5123, normalized or not (KHR_mesh_quantization)"),
    "NORMAL": ({**_FLOAT, 5120: (True,), 5122: (True,)},
               "5126 (float), or 5120 or 5122 normalized (KHR_mesh_quantization)"),
    "TEXCOORD": ({**_FLOAT, **_SMALL_INTEGERS}, "5126 (float), 5121 or 5123 normalized, or 5120, 5121, 5122 or 5123, "
                                                "normalized or not (KHR_mesh_quantization)"),
    "COLOR": ({**_FLOAT, 5121: (True,), 5123: (True,)}, "5126 (float), or 5121 or 5123 normalized"),
    "JOINTS": ({5121: (False,), 5123: (False,)}, "5121 or 5123, not normalized"),
    "WEIGHTS": ({**_FLOAT, 5121: (True,), 5123: (True,)}, "5126 (float), or 5121 or 5123 normalized"),
}
_INDEX_COMPONENT_TYPES: _ComponentTypes = ({5121: (False,), 5123: (False,), 5125: (False,)},
                                           "5121, 5123 or 5125, not normalized")
_TARGET_POSITION_TYPES: _ComponentTypes = ({**_FLOAT, 5120: (False, True), 5122: (False, True)},
                                           "5126 (float), or 5120 or 5122, normalized or not (KHR_mesh_quantization)")
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
# The arrays of objects trimesh reads item by item (with .get or [key]), and the samplers and skins, which it
# passes over (the skins are applied here: _skins_applied), by the name of their items.
_READ_ARRAYS = {"scenes": "scene", "nodes": "node", "meshes": "mesh", "materials": "material", "textures": "texture",
                "images": "image", "accessors": "accessor", "bufferViews": "buffer view", "buffers": "buffer",
                "samplers": "sampler", "skins": "skin"}
# A sampler's values glTF allows (OpenGL's enums): its filters', and its wraps' (CLAMP_TO_EDGE, MIRRORED_REPEAT,
# REPEAT).
_SAMPLER_VALUES = {"magFilter": (9728, 9729), "minFilter": (9728, 9729, 9984, 9985, 9986, 9987),
                   "wrapS": (33071, 33648, 10497), "wrapT": (33071, 33648, 10497)}


class GltfReferences:
    """What a glTF's JSON names checked to exist, and its byte ranges to fit, before trimesh reads it:
    trimesh says an IndexError, an AssertionError or a failed reshape. The arrays it reads must be
    lists of objects, and a primitive's attributes an object with POSITION (trimesh says an
    AttributeError, a TypeError or a KeyError); values it reads that are not shaped as glTF's (a
    count that is not a number) are refused where they are known to fail it."""

    def __init__(self, path: Path, document: dict[str, Any], held: int) -> None:
        """`held`: the bytes of the file and of the buffers it names beside it."""
        self.path, self.document = path, document
        self.copied = {"buffer view": 0, "accessor": 0}  # the bytes trimesh copies of each, in all
        self.held, self.made_limit = held, made_limit(held)
        self.skinned_meshes: set[int] = set()  # each looked at once, however many nodes skin it

    def check(self) -> None:
        for key in _READ_ARRAYS:
            self.objects(key)
            for number, item in self.each(key):  # trimesh says "object of type 'int' has no len()"
                if not isinstance(item.get("name", ""), str):
                    self.refuse(f"{_READ_ARRAYS[key]} {number}'s name is not a string")
                self.extensions(item, f"{_READ_ARRAYS[key]} {number}")
        if self.document.get("scenes") == []:  # the walk of the scene reads the first, as trimesh does
            self.refuse("its scenes are an empty list: glTF lists one scene or more where it lists any")
        if "scene" in self.document:
            self.named(self.document["scene"], "scenes", "its scene")
        for number, scene in self.each("scenes"):
            for node in self.listed(scene, "nodes", f"scene {number}"):
                self.named(node, "nodes", f"scene {number}")
        for number, node in self.each("nodes"):
            self.node(number, node)
        for number, image in self.each("images"):
            if "bufferView" in image:
                self.named(image["bufferView"], "bufferViews", f"image {number}")
            if "uri" in image and not isinstance(image["uri"], str):  # trimesh passed over it without a word
                self.refuse(f"image {number}'s uri is not a string")
            if _is_data_uri(image.get("uri", "")):  # its form: trimesh decodes it (bytes of no picture are a note)
                _data_uri_payload(self.path, image["uri"], f"image {number}")
        for number, texture in self.each("textures"):  # trimesh drops a picture named out of range without a word
            if "source" in texture:
                self.named(texture["source"], "images", f"texture {number}")
            if "sampler" in texture:
                self.named(texture["sampler"], "samplers", f"texture {number}")
        for number, sampler in self.each("samplers"):
            self.sampler(number, sampler)
        for number, buffer in self.each("buffers"):  # before the views that count on their lengths
            self.byte_count(buffer, "byteLength", f"buffer {number}", required=True)
            self.buffer_uri(number, buffer)
        for number, view in self.each("bufferViews"):  # before the accessors that count on their lengths
            self.view(number, view)
        for number, accessor in self.each("accessors"):  # before the primitives that count their items
            self.accessor(number, accessor)
        for what, total in self.copied.items():  # each view and accessor a copy: many of one buffer are many times it
            if total > MAX_FILE_BYTES:
                self.refuse(f"its {what}s add up to {total} bytes: more than the {MAX_FILE_BYTES} a model's file may "
                            "hold")
        if self.copied["buffer view"] > self.made_limit:
            self.refuse(f"its buffer views add up to {self.copied['buffer view']} bytes: {self.past_made_limit()}")
        for number, mesh in self.each("meshes"):
            self.mesh(number, mesh)
        for number, skin in self.each("skins"):  # after the nodes its joints name, and the accessors
            self.skin(number, skin)
        for number, node in self.each("nodes"):  # after the meshes' primitives are checked
            self.skinned_primitives(number, node)
        self.made_accessors()  # once the primitives are checked to name accessors
        for number, material in self.each("materials"):
            self.material(number, material)

    def buffer_uri(self, number: int, buffer: dict[str, Any]) -> None:
        """A buffer's uri, a string; left out only by a GLB's buffer (trimesh says "KeyError: 'uri'")."""
        if "uri" in buffer and not isinstance(buffer["uri"], str):
            self.refuse(f"buffer {number}'s uri is not a string")
        if "uri" not in buffer and self.path.suffix.lower() == ".gltf":
            self.refuse(f"buffer {number} has no uri: a .gltf's buffers are files beside it or data: URIs")
        if "uri" not in buffer and number:  # trimesh gives it the chunk after the binary one, or none
            self.refuse(f"buffer {number} has no uri: only a GLB's first buffer, its binary chunk, may leave it out")
        uri = buffer.get("uri", "")
        if _is_data_uri(uri):  # trimesh decodes it; one short of its byteLength, it asserted
            held = len(data_uri_bytes(self.path, uri, number))
            if held < buffer["byteLength"]:
                self.refuse(f"buffer {number} holds {held} bytes, where its byteLength says "
                            f"{buffer['byteLength']}")

    def made_accessors(self) -> None:
        """The accessors' items trimesh copies (those of a view) or that are written before it reads them
        (those a primitive reads), added up in the accessors' order: the one that passes the limit is named."""
        read, total = _read_by_primitives(self.document), 0
        for number, accessor in self.each("accessors"):
            if "bufferView" in accessor or number in read:  # an unread one of zeros: pages nothing writes
                total += accessor["count"] * _item_bytes(accessor)
                if total > self.made_limit:
                    self.refuse(f"accessor {number}'s {accessor['count']} items bring what its accessors make to "
                                f"{total} bytes: {self.past_made_limit()}")

    def past_made_limit(self) -> str:
        return past_made_limit(self.held)

    def material(self, number: int, material: dict[str, Any]) -> None:
        """Its values as trimesh reads them: pbrMetallicRoughness's merged into the material's, each list
        made numbers (it says "could not convert string to float" or a TypeError)."""
        values = material.get("pbrMetallicRoughness", {})
        if not isinstance(values, dict):
            self.refuse(f"material {number}'s pbrMetallicRoughness is not an object")
        for key, value in (*material.items(), *values.items(), *_diffuse_values(material)):
            if key in _BASE_COLOUR_TEXTURES and not isinstance(value, dict):  # trimesh took it as the picture
                self.refuse(f"material {number}'s {key} is not an object (a texture's index, and its texCoord)")
            if isinstance(value, list) and not all(map(_is_number, value)):
                self.refuse(f"material {number}'s {shortened(escaped(str(key)))} is not a list of numbers")
            if key in _MATERIAL_NUMBERS and not _numbers_of(value, _MATERIAL_NUMBERS[key]):
                size = _MATERIAL_NUMBERS[key]
                self.refuse(f"material {number}'s {key} is not {'a number' if size is None else f'{size} numbers'}")
            if key in _MATERIAL_NUMBERS and (unheld := [part for part in _listed(value) or [value]
                                                        if not _is_finite(part)]):
                self.refuse(f"material {number}'s {key} holds {shortened(str(unheld[0]))}: not a finite "
                            "number")
            if key == "emissiveFactor" and (below := [part for part in value if part < _LEAST_EMISSION]):
                self.refuse(f"material {number}'s emissiveFactor holds {below[0]:g}: glTF's colours are 0..1")
        for key, texture in _texture_infos(material):  # trimesh drops one that names no texture
            self.named(texture["index"], "textures", f"material {number}'s {shortened(escaped(key))}")
            texture_set = texture.get("texCoord", 0)
            if not _is_whole(texture_set) or texture_set < 0:
                self.refuse(f"material {number}'s {shortened(escaped(key))}'s texCoord is not a whole number of 0 "
                            "or more")

        self.texture_transform(number, material)
        mode = material.get("alphaMode", "OPAQUE")
        if not (isinstance(mode, str) and mode.upper() in _ALPHA_MODES):  # trimesh upper-cases it
            self.refuse(f"material {number}'s alphaMode {shortened(escaped(repr(mode)))} is not one of glTF's (OPAQUE, "
                        "MASK, BLEND)")

    def texture_transform(self, number: int, material: dict[str, Any]) -> None:
        """Its base colour texture's KHR_texture_transform, which is applied (_texture_transforms_applied):
        an object of glTF's values, each left out or finite. Other textures' are not read."""
        texture = _base_colour_texture(material)
        if "index" not in texture:
            return
        _, _, key = _base_colour(material)
        self.extensions(texture, f"material {number}'s {key}")  # else its transform would be passed over
        transform = _nested(texture, ("extensions",)).get(_TEXTURE_TRANSFORM, {})
        said = f"material {number}'s {key}'s {_TEXTURE_TRANSFORM}"
        if not isinstance(transform, dict):
            self.refuse(f"{said} is not an object")
        for name in ("offset", "scale"):
            values = transform.get(name, [0, 0])
            if not (_numbers_of(values, 2) and all(map(_is_finite, values))):
                self.refuse(f"{said}'s {name} is not 2 finite numbers")
        if not (_is_number(rotation := transform.get("rotation", 0)) and _is_finite(rotation)):
            self.refuse(f"{said}'s rotation is not a finite number")
        texture_set = transform.get("texCoord", 0)
        if not _is_whole(texture_set) or texture_set < 0:
            self.refuse(f"{said}'s texCoord is not a whole number of 0 or more")

    def mesh(self, number: int, mesh: dict[str, Any]) -> None:
        if mesh.get("primitives", []) == []:  # glTF holds one or more; trimesh drops a node of none, and its children
            self.refuse(f"mesh {number} has no primitives")
        for primitive_number, primitive in enumerate(self.listed(mesh, "primitives", f"mesh {number}")):
            if not isinstance(primitive, dict):
                self.refuse(f"mesh {number}'s primitive {primitive_number} is not an object")
            self.extensions(primitive, f"mesh {number}'s primitive {primitive_number}")
            self.primitive(f"mesh {number}'s primitive {primitive_number}", primitive)

    def node(self, number: int, node: dict[str, Any]) -> None:
        for child in self.listed(node, "children", f"node {number}"):
            self.named(child, "nodes", f"node {number}")
        if "mesh" in node:
            self.named(node["mesh"], "meshes", f"node {number}")
        if "camera" in node:  # a broken reference, though the camera is taken out before trimesh reads it
            self.named(node["camera"], "cameras", f"node {number}")
        if "skin" in node:
            self.named(node["skin"], "skins", f"node {number}")
        for key, size in _NODE_TRANSFORMS.items():
            if key not in node:  # glTF's default, not made to be checked again for each of thousands of nodes
                continue
            values = node[key]
            if not (isinstance(values, list) and len(values) == size and all(_is_number(value) for value in values)):
                self.refuse(f"node {number}'s {key} is not {size} numbers")
            if unheld := [value for value in values if not _is_finite(value)]:  # trimesh took NaN's matrix for none
                self.refuse(f"node {number}'s {key} holds {shortened(str(unheld[0]))}: not a finite number")

    def primitive(self, what: str, primitive: dict[str, Any]) -> None:
        attributes = primitive.get("attributes")
        if not isinstance(attributes, dict):
            self.refuse(f"{what} has no attributes" if attributes is None else f"{what}'s attributes are not an object")
        if "POSITION" not in attributes:  # trimesh reads every primitive's positions (a KeyError)
            self.refuse(f"{what} has no POSITION attribute")
        mode = primitive.get("mode", _TRIANGLES)
        if not (_is_whole(mode) and _POINTS <= mode <= _FAN):  # trimesh skipped the primitive without a word
            self.refuse(f"{what}'s mode {shortened(escaped(repr(mode)))} is not one of glTF's (0 to 6)")
        for name, index in attributes.items():
            said, semantic = f"{what}'s {shortened(escaped(str(name)))}", str(name).split("_", 1)[0]
            accessor = self.named(index, "accessors", said)
            types = _ATTRIBUTE_TYPES.get(semantic, (accessor.get("type"),))
            if accessor.get("type") not in types:  # trimesh said an IndexError, or misread them
                self.refuse(f"{said} is accessor {index}, of type {accessor['type']}: glTF's are {' or '.join(types)}")
            if semantic in _COMPONENT_TYPES:  # an attribute not read here is not asked
                self.components(f"{said} is", _COMPONENT_TYPES[semantic], index, accessor)
            self.attribute_stride(said, index, accessor)
        if "material" in primitive:
            material = self.named(primitive["material"], "materials", f"{what}'s material")
            self.texture_sets(what, primitive["material"], material, attributes)
        if "indices" in primitive:
            accessor = self.named(primitive["indices"], "accessors", f"{what}'s indices")
            if accessor.get("type") != "SCALAR":  # trimesh read a VEC3's items as three indices each
                self.refuse(f"{what}'s indices are accessor {primitive['indices']}, of type {accessor.get('type')}: "
                            "glTF's are SCALAR")
            self.components(f"{what}'s indices are", _INDEX_COMPONENT_TYPES, primitive["indices"], accessor)
        for index in [attributes["POSITION"], *([primitive["indices"]] if "indices" in primitive else [])]:
            if self.document["accessors"][index]["count"] == 0:  # read, one failed; exporters leave ones none reads
                self.refuse(f"{what} reads accessor {index}, of no items: glTF's accessors hold one item or more")
        for number, target in enumerate(self.listed(primitive, "targets", what)):
            self.morph_target(f"{what}'s morph target {number}", target, attributes["POSITION"])
        if primitive.get("mode", _TRIANGLES) == _TRIANGLES:  # three corners each, or trimesh fails to reshape them
            corners = "indices" if "indices" in primitive else "vertices and no indices"
            count = self.document["accessors"][primitive.get("indices", attributes["POSITION"])].get("count")
            if _is_whole(count) and count % 3:
                self.refuse(f"{what} has {count} {corners}: its triangles take three each")
        self.counts_alike(what, attributes)

    def morph_target(self, what: str, target: object, position: int) -> None:
        """A morph target's attributes, each naming an accessor of an item per vertex; its POSITION and NORMAL
        VEC3s, its POSITION of a component type glTF allows (trimesh reads none: the weights' shapes do)."""
        if not isinstance(target, dict):
            self.refuse(f"{what} is not an object")
        vertices = self.document["accessors"][position]["count"]
        for name, index in target.items():
            said = f"{what}'s {shortened(escaped(str(name)))}"
            accessor = self.named(index, "accessors", said)
            if name in ("POSITION", "NORMAL") and accessor["type"] != "VEC3":
                self.refuse(f"{said} is accessor {index}, of type {accessor['type']}: glTF's are VEC3")
            if name == "POSITION":
                self.components(f"{said} is", _TARGET_POSITION_TYPES, index, accessor)
            self.attribute_stride(said, index, accessor)
            if accessor["count"] != vertices:
                self.refuse(f"{said} has {accessor['count']} items, the primitive's POSITION {vertices}: a morph "
                            "target holds one item per vertex")

    def skin(self, number: int, skin: dict[str, Any]) -> None:
        """Its joints, one node or more, and its inverseBindMatrices, where it gives them: MAT4s of floats, one a
        joint at least, as glTF's are (its values: _joint_matrices)."""
        joints = self.listed(skin, "joints", f"skin {number}")
        if not joints:
            self.refuse(f"skin {number} has no joints: glTF's skins list one or more")
        for joint in joints:
            self.named(joint, "nodes", f"skin {number}'s joints")
        if "skeleton" in skin:
            self.named(skin["skeleton"], "nodes", f"skin {number}'s skeleton")
        if "inverseBindMatrices" not in skin:
            return
        index = skin["inverseBindMatrices"]
        accessor = self.named(index, "accessors", f"skin {number}'s inverseBindMatrices")
        if accessor["type"] != "MAT4" or accessor["componentType"] != _FLOAT_COMPONENTS:
            self.refuse(f"skin {number}'s inverseBindMatrices are accessor {index}, of type {accessor['type']} and "
                        f"componentType {accessor['componentType']}: glTF's are MAT4 of 5126 (float)")
        if accessor["count"] < len(joints):
            self.refuse(f"skin {number}'s inverseBindMatrices are accessor {index}, of {accessor['count']} items, for "
                        f"its {counted(len(joints), 'joint')}: glTF's have one a joint")

    def skinned_primitives(self, number: int, node: dict[str, Any]) -> None:
        """The primitives a node's skin moves (those it draws faces of), each with JOINTS_0 and WEIGHTS_0, and
        each JOINTS_n with its WEIGHTS_n, as glTF requires: what a joint moves is read from them. Each mesh is
        looked at once, for the first node that skins it."""
        if "skin" not in node or "mesh" not in node or node["mesh"] in self.skinned_meshes:
            return
        self.skinned_meshes.add(node["mesh"])
        for primitive_number, primitive in enumerate(self.document["meshes"][node["mesh"]]["primitives"]):
            if not _is_drawn(primitive):
                continue
            attributes = primitive["attributes"]
            sets = {name.split("_", 1)[1] for name in attributes if name.startswith(_SKIN_SETS)}
            for part in sorted({"0", *sets}):
                for name in (f"JOINTS_{part}", f"WEIGHTS_{part}"):
                    if name not in attributes:
                        self.refuse(f"node {number} skins mesh {node['mesh']} by skin {node['skin']}, whose primitive "
                                    f"{primitive_number} has no {shortened(escaped(name))}: glTF's skinned primitives "
                                    "have JOINTS_0 and WEIGHTS_0, and each JOINTS_n with its WEIGHTS_n")

    def attribute_stride(self, said: str, index: int, accessor: dict[str, Any]) -> None:
        """A vertex attribute's view's byteStride, where it has one: a multiple of 4 from 4 to 252, as glTF
        requires of a vertex attribute's (a view no attribute reads is not asked)."""
        if "bufferView" not in accessor:
            return
        stride = self.document["bufferViews"][accessor["bufferView"]].get("byteStride")
        if stride is not None and not (stride % _ATTRIBUTE_ALIGNMENT == 0 and _LEAST_STRIDE <= stride <= _MOST_STRIDE):
            self.refuse(f"{said} is accessor {index}, in buffer view {accessor['bufferView']} of byteStride {stride}: "
                        f"glTF's vertex attributes' strides are multiples of {_ATTRIBUTE_ALIGNMENT} from "
                        f"{_LEAST_STRIDE} to {_MOST_STRIDE}")

    def components(self, what: str, rule: _ComponentTypes, index: int, accessor: dict[str, Any]) -> None:
        """An attribute's or the indices' component type, and whether it is normalized, as glTF allows
        them (`rule`); `what` names it, "... is" or "... are"."""
        allowed, said = rule
        component, normalized = accessor["componentType"], accessor.get("normalized") is True
        if normalized in allowed.get(component, ()):
            return
        flag = "" if component not in allowed else ", normalized" if normalized else ", not normalized"
        self.refuse(f"{what} accessor {index}, of componentType {component}{flag}: glTF's are {said}")

    def texture_sets(self, what: str, number: int, material: dict[str, Any], attributes: dict[str, Any]) -> None:
        """The TEXCOORD_n each texture of its material names by its texCoord, which the primitive must have
        (trimesh reads TEXCOORD_0 whatever it says). One left out, 0, is not asked for: a primitive without
        uvs shows the scene's texture in place of its own picture, with a note. The base colour texture's
        KHR_texture_transform's texCoord, where it gives one, is the set asked for in place of its own."""
        base_colour = _base_colour_texture(material)
        for key, texture in _texture_infos(material):
            said, texture_set = shortened(escaped(key)), texture.get("texCoord")
            transform = _nested(texture, ("extensions", _TEXTURE_TRANSFORM)) if texture is base_colour else {}
            if "texCoord" in transform:
                said, texture_set = f"{said}'s {_TEXTURE_TRANSFORM}", transform["texCoord"]
            if _is_whole(texture_set) and texture_set >= 0 and f"TEXCOORD_{texture_set}" not in attributes:
                self.refuse(f"{what} has no TEXCOORD_{texture_set}, which material {number}'s {said} reads "
                            "(its texCoord)")

    def extensions(self, item: dict[str, Any], what: str) -> None:
        """Its extensions an object: trimesh said an AttributeError (a material's, a primitive's), or drew a
        texture's picture as none, without a word."""
        if not isinstance(item.get("extensions", {}), dict):
            self.refuse(f"{what}'s extensions are not an object")

    def sampler(self, number: int, sampler: dict[str, Any]) -> None:
        """Its filters and wraps, each left out or one of glTF's enums: trimesh passes over them without a word."""
        for key, allowed in _SAMPLER_VALUES.items():
            value = sampler.get(key, allowed[0])
            if not (_is_whole(value) and value in allowed):
                self.refuse(f"sampler {number}'s {key} {shortened(escaped(repr(value)))} is not one of glTF's "
                            f"({', '.join(map(str, allowed))})")

    def counts_alike(self, what: str, attributes: dict[str, Any]) -> None:
        """One item of each attribute per vertex, as glTF requires: trimesh drew 4 uvs over 5 positions
        shifted, without a word."""
        accessors = self.document["accessors"]
        vertices = accessors[attributes["POSITION"]]["count"]
        for name, index in attributes.items():
            if accessors[index]["count"] != vertices:
                self.refuse(f"{what}'s {shortened(escaped(str(name)))} has {accessors[index]['count']} items, its "
                            f"POSITION {vertices}: a primitive's attributes hold one item per vertex each")

    def accessor(self, number: int, accessor: dict[str, Any]) -> None:
        count = accessor.get("count")
        if not _is_whole(count) or count < 0:
            self.refuse(f"accessor {number}'s count is not a whole number")
        component, kind = accessor.get("componentType"), accessor.get("type")
        if not (_is_whole(component) and component in _COMPONENT_BYTES):  # trimesh says a KeyError
            self.refuse(self.unknown(f"accessor {number}", "componentType", component))
        if not (isinstance(kind, str) and kind in _TYPE_COMPONENTS):
            self.refuse(self.unknown(f"accessor {number}", "type", kind))
        if not isinstance(normalized := accessor.get("normalized", False), bool):  # read as false without a word
            self.refuse(f"accessor {number}'s normalized {shortened(escaped(repr(normalized)))} is not true or false")
        offset = self.byte_count(accessor, "byteOffset", f"accessor {number}")
        size = _item_bytes(accessor)
        self.copied["accessor"] += count * size
        if "sparse" in accessor:
            self.sparse(f"accessor {number}'s sparse", accessor["sparse"], count, size)
        if "bufferView" not in accessor:  # all zeros, or sparse, which trimesh makes of its count, read or not
            if count * size > MAX_FILE_BYTES:
                self.refuse(f"accessor {number} is {count} items of zeros, {count * size} bytes: more than the "
                            f"{MAX_FILE_BYTES} a model's file may hold")
            return
        view = self.named(accessor["bufferView"], "bufferViews", f"accessor {number}")
        length, stride = view.get("byteLength"), view.get("byteStride") or size
        if count == 0 and "byteStride" in view:  # trimesh reads every accessor, a strided one as -stride+size bytes
            self.refuse(f"accessor {number}'s count is 0, in buffer view {accessor['bufferView']} of byteStride "
                        f"{stride}: glTF's accessors hold one item or more")
        if _is_whole(stride) and stride < size:  # its items would overlap, each read over the next
            self.refuse(f"accessor {number}'s items are {size} bytes, more than the byteStride {stride} of buffer "
                        f"view {accessor['bufferView']}")
        if count and all(map(_is_whole, (length, stride))) and offset + (count - 1) * stride + size > length:
            self.refuse(f"accessor {number}'s {count} items run past the {length} bytes of buffer view "
                        f"{accessor['bufferView']}")  # its last item's last byte

    def sparse(self, what: str, sparse: object, count: int, size: int) -> None:
        """An accessor's sparse values, shaped as glTF's: a count of 1 up to the accessor's, and its
        indices (of unsigned integers) and values, each that many items within its buffer view."""
        if not isinstance(sparse, dict):
            self.refuse(f"{what} is not an object")
        changed = sparse.get("count")
        if not _is_whole(changed) or not 1 <= changed <= count:
            self.refuse(f"{what}'s count is not a whole number from 1 to the accessor's {count}")
        for key in ("indices", "values"):
            part, named = sparse.get(key), f"{what} {key}"
            if not isinstance(part, dict):
                self.refuse(f"{what} has no {key}" if part is None else f"{named} are not an object")
            kind = part.get("componentType")
            if key == "indices" and not (_is_whole(kind) and kind in _SPARSE_INDEX_BYTES):
                self.refuse(f"{named}' componentType {shortened(escaped(repr(kind)))} is not one of an index's "
                            "(5121, 5123, 5125)")
            view = self.named(part.get("bufferView"), "bufferViews", named)
            if "byteStride" in view:  # which would be read packed
                self.refuse(f"{named}' buffer view {part['bufferView']} has a byteStride: glTF's sparse indices and "
                            "values are packed")
            offset = self.byte_count(part, "byteOffset", named)
            length = view.get("byteLength")
            item = _SPARSE_INDEX_BYTES[kind] if key == "indices" else size
            if _is_whole(length) and offset + changed * item > length:
                self.refuse(f"{named}, {changed} items, run past the {length} bytes of buffer view "
                            f"{part['bufferView']}")

    def view(self, number: int, view: dict[str, Any]) -> None:
        buffer = self.named(view.get("buffer"), "buffers", f"buffer view {number}")
        offset = self.byte_count(view, "byteOffset", f"buffer view {number}")
        length = self.byte_count(view, "byteLength", f"buffer view {number}", required=True)
        self.copied["buffer view"] += length
        if "byteStride" in view and self.byte_count(view, "byteStride", f"buffer view {number}") == 0:
            self.refuse(f"buffer view {number}'s byteStride is 0")  # trimesh asserts it is positive
        size = buffer.get("byteLength")
        if _is_whole(size) and offset + length > size:
            self.refuse(f"buffer view {number} runs past the {size} bytes of buffer {view['buffer']}")

    @staticmethod
    def unknown(what: str, key: str, value: object) -> str:
        if value is None:
            return f"{what} has no {key}"
        return f"{what}'s {key} {shortened(escaped(repr(value)))} is not one of glTF's"

    def byte_count(self, item: dict[str, Any], key: str, what: str, required: bool = False) -> int:
        """item[key], a number of bytes (0 where it may be left out), which must be a whole number of 0 or
        more: trimesh reads a negative one as counting from the end, and asserts, or fails to reshape."""
        if required and key not in item:
            self.refuse(f"{what} has no {key}")
        value = item.get(key, 0)
        if not _is_whole(value) or value < 0:
            self.refuse(f"{what}'s {key} is not a whole number of 0 or more")
        return value

    def named(self, index: object, key: str, by: str) -> dict[str, Any]:
        """The item document[key][index] that `by` names, which must be there."""
        items = self.document.get(key)
        size = len(items) if isinstance(items, list) else 0
        if not _is_whole(index) or not 0 <= index < size:  # type: ignore[operator]
            kind = {"bufferViews": "buffer view", "meshes": "mesh"}.get(key, key[:-1])
            self.refuse(f"{by} names {kind} {shortened(escaped(repr(index)))}, of {size}")
        item = items[index]  # type: ignore[index]
        return item if isinstance(item, dict) else {}

    def each(self, key: str) -> Iterator[tuple[int, dict[str, Any]]]:
        items = self.document.get(key)
        for number, item in enumerate(items if isinstance(items, list) else ()):
            if isinstance(item, dict):
                yield number, item

    def objects(self, key: str) -> None:
        """document[key], where there, must be a list of objects."""
        items = self.document.get(key, [])
        if not isinstance(items, list):
            self.refuse(f"its {key} are not a list")
        for number, item in enumerate(items):
            if not isinstance(item, dict):
                self.refuse(f"{_READ_ARRAYS[key]} {number} is not an object")

    def listed(self, item: dict[str, Any], key: str, what: str) -> list[Any]:
        """item[key], where there, which must be a list."""
        values = item.get(key, [])
        if not isinstance(values, list):
            self.refuse(f"{what}'s {key} are not a list")
        return values

    def refuse(self, words: str) -> None:
        raise LoadError(self.path, f"not a glTF file: {words}")


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


def check_one_parent_each(path: Path, document: dict[str, Any]) -> None:
    """glTF's nodes form trees: a node that is the child of two (trimesh's reader takes time in the square
    of such sharing), its own ancestor, or a root of the scene drawn that it places again under another, is
    refused before trimesh reads the file. Its nodes, scenes and their lists checked by GltfReferences:
    objects, and lists of node indices."""
    parent: dict[int, int] = {}
    for number, node in enumerate(document.get("nodes", [])):
        for child in node.get("children", []):
            if child in parent:
                raise LoadError(path, f"not a glTF file: node {child} is the child of two nodes (glTF's nodes form "
                                      "trees)")
            parent[child] = number
    _check_no_loop(path, parent)
    _check_roots_placed_once(path, document, parent)


def _check_roots_placed_once(path: Path, document: dict[str, Any], parent: dict[int, int]) -> None:
    """The drawn scene's roots, none under another (the walk counted it twice, trimesh placed it once, by
    the root alone). A root whose parent the scene does not place is let through: UniGLTF's exports (Kenney's
    kits) list a child of an unplaced "tmpParent" as their root, and trimesh and the walk place it once."""
    nodes, roots = document.get("nodes", []), set(_roots(document))
    below = [child for root in roots for child in nodes[root].get("children", [])]
    while below:  # each node once: the nodes form trees, and the walk stops at the first root met again
        node = below.pop()
        if node in roots:
            raise LoadError(path, f"not a glTF file: node {node} is a root of scene {document.get('scene', 0)} and "
                                  f"the child of node {parent[node]}, which it places too (glTF's nodes form trees)")
        below.extend(nodes[node].get("children", []))


def _check_no_loop(path: Path, parent: dict[int, int]) -> None:
    """A loop of children (trimesh said only "Iteration limit exceeded", or that no node placed a mesh), found
    in one walk up from each node, none walked twice."""
    cleared: set[int] = set()
    for start in parent:
        walked: set[int] = set()
        node: int | None = start
        while node is not None and node not in cleared:
            if node in walked:
                raise LoadError(path, f"not a glTF file: node {node} is its own ancestor (its children lead back "
                                      "to it; glTF's nodes form trees)")
            walked.add(node)
            node = parent.get(node)
        cleared |= walked


# Geometry trimesh cannot decode here: it reads such a file as placeholder zeros, or fails inside.
_UNREAD_COMPRESSION = {
    "KHR_draco_mesh_compression": "Draco-compressed",
    "EXT_meshopt_compression": "meshopt-compressed",
}


def check_geometry_readable(path: Path, document: dict[str, Any]) -> None:
    """Refuses compressed geometry, which glTF's writers list as required, and extensions it requires
    that are not read here."""
    required = document.get("extensionsRequired", [])
    if not (isinstance(required, list) and all(isinstance(name, str) for name in required)):
        raise LoadError(path, "not a glTF file: its extensionsRequired are not a list of extension names")
    for name in required:
        if name in _UNREAD_COMPRESSION and not (name == "KHR_draco_mesh_compression" and _draco_decoder()):
            raise LoadError(path, f"its geometry is {_UNREAD_COMPRESSION[name]} ({name}), which is not read here: "
                                  "export it uncompressed")
        if not _required_extension_read(name):  # glTF: a reader must refuse what it cannot honour
            raise LoadError(path, f"it requires the glTF extension {shortened(escaped(name))}, which is not "
                                  "read here")


def _required_extension_read(name: object) -> bool:
    """Extensions a file may require and still be drawn as it means: Draco with its decoder, quantized
    attributes (normalized ones made floats for trimesh: _accessors_made_plain), the base colour texture's
    transform (_texture_transforms_applied; other textures are not drawn), and materials'
    extensions, which change only what the viewer's Phong lighting does not draw (it takes the base
    colour); KHR_materials_unlit, which it does, is drawn lit with a note (_unlit_notes)."""
    return (name in ("KHR_draco_mesh_compression", "KHR_mesh_quantization", _TEXTURE_TRANSFORM)
            or isinstance(name, str) and name.startswith("KHR_materials_"))


def _draco_decoder() -> bool:
    """trimesh decodes Draco where DracoPy is installed (not a dependency: it is built for few platforms)."""
    return importlib.util.find_spec("DracoPy") is not None


# --- what the scene places, counted --------------------------------------------------------------
class _Unshaped(Exception):
    """A glTF's JSON that is not shaped as glTF's where it is counted: trimesh says how."""


def gltf_counts(document: dict[str, Any] | None) -> tuple[int, int, int] | None:
    """(placements, triangles, vertices) the scene trimesh reads places, from the counts its JSON
    declares: its nodes walked from the scene's roots as trimesh walks them (an edge from a parent to a
    child once; a node's mesh placed once a primitive where it has several), each node's children once.
    None where the JSON is not shaped as glTF's."""
    if document is None:
        return None
    try:
        sizes = _mesh_sizes(document)
        placements, triangles, vertices = 0, 0, 0
        for node in _placed_nodes(document):
            read, faces, points = sizes[node["mesh"]] if "mesh" in node else (0, 0, 0)
            placements, triangles, vertices = placements + read, triangles + faces, vertices + points
    except (_Unshaped, LookupError, TypeError, AttributeError):
        return None
    return placements, triangles, vertices


def _placed_nodes(document: dict[str, Any]) -> Iterator[dict[str, Any]]:
    nodes = document.get("nodes", [])
    return (nodes[number] for number in _placed_node_numbers(document))


def _placed_node_numbers(document: dict[str, Any]) -> Iterator[int]:
    """Each node of the scene each time trimesh places it: walked from the scene's roots, an edge from a
    parent to a child once (a root listed twice is placed once), each node's children queued once."""
    nodes = document.get("nodes", [])
    edges = [("root", root) for root in _roots(document)]
    consumed, opened = set(), set()
    while edges:
        edge = edges.pop()
        if edge in consumed:
            continue
        consumed.add(edge)
        child = nodes[edge[1]]
        if edge[1] not in opened:  # trimesh queues them again for each parent: all consumed by then
            opened.add(edge[1])
            edges.extend((edge[1], index) for index in child.get("children", []))
        yield edge[1]


def _roots(document: dict[str, Any]) -> list[Any]:
    """The root nodes of the scene trimesh reads: the one `scene` names, else the first."""
    if "scenes" not in document:
        return []
    return list(document["scenes"][document.get("scene", 0)].get("nodes", []))


# glTF's modes of primitive: trimesh reads points and lines (placed, not drawn), triangles and strips;
# it skips line loops, line strips and fans (fans are made triangles for it: _fans_made_triangles).
_POINTS, _LINES, _LINE_LOOP, _LINE_STRIP, _TRIANGLES, _STRIP, _FAN = 0, 1, 2, 3, 4, 5, 6
_READ_MODES = (_POINTS, _LINES, _TRIANGLES, _STRIP)  # trimesh makes something of these, and skips the rest
_FAN_LEAST_CORNERS = 3  # a fan of fewer draws nothing, in glTF too: left a fan, which trimesh skips


def _mesh_sizes(document: dict[str, Any]) -> list[tuple[int, int, int]]:
    """Per mesh, (primitives, triangles, vertices) of the primitives trimesh reads, added up once: a node
    placing it adds them, however many primitives it has."""
    return [(len(read), sum(faces for faces, _ in read), sum(points for _, points in read))
            for read in _primitive_sizes(document)]


def _primitive_sizes(document: dict[str, Any]) -> list[list[tuple[int, int]]]:
    """Per mesh, (triangles, vertices) of each primitive trimesh reads, from its accessors' counts
    (the vertices of a primitive of no triangles are not drawn, so not counted)."""
    accessors = document.get("accessors", [])
    return [[size for primitive in mesh["primitives"] if (size := _primitive_size(accessors, primitive)) is not None]
            for mesh in document.get("meshes", [])]


def _primitive_size(accessors: list[Any], primitive: dict[str, Any]) -> tuple[int, int] | None:
    """(triangles, vertices) of a primitive trimesh reads (its vertices counted only where it has triangles),
    None where it skips it."""
    mode = primitive.get("mode", _TRIANGLES)
    if mode not in (*_READ_MODES, _FAN):
        return None
    points = _count(accessors[primitive["attributes"]["POSITION"]])
    corners = _count(accessors[primitive["indices"]]) if "indices" in primitive else points
    if mode == _FAN and corners < _FAN_LEAST_CORNERS:
        return None  # not made triangles (_drawn_fans): trimesh skips it
    faces = 0 if mode in (_POINTS, _LINES) else corners // 3 if mode == _TRIANGLES else max(corners - 2, 0)
    return faces, points if faces else 0


def _draws_faces(accessors: list[Any], primitive: dict[str, Any]) -> bool:
    """Whether trimesh makes triangles of a checked primitive (whose vertices the placements count)."""
    size = _primitive_size(accessors, primitive)
    return size is not None and size[0] > 0


def _count(accessor: Any) -> int:
    count = accessor["count"]
    if not _is_whole(count) or count < 0:
        raise _Unshaped
    return count


# --- what trimesh draws otherwise than it says ---------------------------------------------------
def unfaithful_notes(document: dict[str, Any], undrawn: list[str]) -> list[str]:
    """What of a checked glTF is drawn otherwise than it says, which trimesh passes over without a word:
    primitives it reads no faces of (`undrawn`, its undrawn_primitive_notes, which the placement check has
    read already), base colours outside 0..1 it holds to it, and base colour textures' transforms of the
    Draco-compressed coordinates it decodes over those moved; and emission and normal maps, which SPEC 4's
    lighting has no term for, and unlit materials, which it lights. (Weights that cannot shape a mesh:
    MorphedShapes.notes.)"""
    return [*undrawn, *_outside_colour_notes(document), *_texture_transform_notes(document),
            *_emission_notes(document), *_normal_map_notes(document), *_unlit_notes(document)]


# The modes of primitive no face is made of, by what a note calls them.
_UNDRAWN_MODES = {_POINTS: "points", _LINES: "lines", _LINE_LOOP: "line loops", _LINE_STRIP: "line strips"}


def sceneless_words(document: dict[str, Any]) -> list[str]:
    """Why a file of no scene places nothing: glTF reads its meshes as a library, as trimesh does."""
    return [] if document.get("scenes") else ["the file lists no scene, and glTF places no mesh outside one"]


def undrawn_primitive_notes(document: dict[str, Any]) -> list[str]:
    """The placed meshes' primitives of points and lines (Blender's loose edges)."""
    meshes = document.get("meshes", [])
    modes = [mode for index in _placed_meshes(document) for primitive in meshes[index]["primitives"]
             if _is_whole(mode := primitive.get("mode", _TRIANGLES)) and mode in _UNDRAWN_MODES]
    if not modes:
        return []
    kinds = [_UNDRAWN_MODES[mode] for mode in sorted(set(modes))]
    kinds_said = ", ".join(kinds[:-1]) + " and " + kinds[-1] if len(kinds) > 1 else kinds[0]
    return [f"{counted(len(modes), 'primitive')} of {kinds_said} {'is' if len(modes) == 1 else 'are'} not drawn"]


def _outside_colour_notes(document: dict[str, Any]) -> list[str]:
    """A material's base colour factor outside glTF's 0..1, which trimesh holds to it."""
    outside = [(number, key, value) for number, material in enumerate(document.get("materials", []))
               for where, key, _ in [_base_colour(material)] for value in _listed(where.get(key))
               if _is_number(value) and not 0 <= value <= 1]
    if not outside:
        return []
    (number, key, value), materials = outside[0], len({number for number, _, _ in outside})
    if materials == 1:
        return [f"material {number}'s {key} holds {value:g}: glTF's colours are 0..1, held to it"]
    return [f"{materials} materials' {key} hold values outside glTF's 0..1 (the first, material {number}'s, "
            f"{value:g}), held to it"]


def _emission_notes(document: dict[str, Any]) -> list[str]:
    """Materials that glow (an emissiveFactor not black, a KHR_materials_emissive_strength not 0), as Blender
    writes a lamp's: drawn lit as any other."""
    glowing = [number for number, material in enumerate(document.get("materials", [])) if _glows(material)]
    return _materials_note(glowing, "emission (emissiveFactor) is not drawn", "emission (emissiveFactor) is not drawn")


def _glows(material: dict[str, Any]) -> bool:
    strength = _nested(material, ("extensions", "KHR_materials_emissive_strength")).get("emissiveStrength", 1)
    factor = _listed(material.get("emissiveFactor"))
    return any(_is_number(value) and value > 0 for value in factor) and not (_is_number(strength) and strength <= 0)


def _normal_map_notes(document: dict[str, Any]) -> list[str]:
    """Materials with a normalTexture, as Blender writes a normal map: drawn with the mesh's own normals."""
    mapped = [number for number, material in enumerate(document.get("materials", []))
              if isinstance(material.get("normalTexture"), dict)]
    return _materials_note(mapped, "normal map (normalTexture) is not drawn",
                           "normal maps (normalTexture) are not drawn")


def _unlit_notes(document: dict[str, Any]) -> list[str]:
    """Materials of KHR_materials_unlit (their base colour, not lit): drawn lit by SPEC 4's Phong."""
    unlit = [number for number, material in enumerate(document.get("materials", []))
             if "KHR_materials_unlit" in _nested(material, ("extensions",))]
    note = "unlit shading (KHR_materials_unlit) is not applied: drawn lit"
    return _materials_note(unlit, note, note)


def _materials_note(numbers: list[int], said_of_one: str, said_of_many: str) -> list[str]:
    """One note for the materials `numbers` however many, naming the first."""
    if not numbers:
        return []
    if len(numbers) == 1:
        return [f"material {numbers[0]}'s {said_of_one}"]
    return [f"{len(numbers)} materials' {said_of_many} (the first, material {numbers[0]}'s)"]


def _texture_transform_notes(document: dict[str, Any]) -> list[str]:
    """Base colour textures whose KHR_texture_transform moves the coordinates of a drawn primitive's Draco
    stream, where trimesh decodes it: it writes them, unmoved, over the set that would be moved."""
    materials = document.get("materials", [])
    unmoved = sorted({primitive["material"] for mesh in document.get("meshes", []) for primitive in mesh["primitives"]
                      if "material" in primitive and _uv_transform(materials[primitive["material"]]) is not None
                      and _uvs_decoded_by_trimesh(primitive, materials[primitive["material"]])})
    return _materials_note(unmoved, f"baseColorTexture's {_TEXTURE_TRANSFORM} is not applied to Draco-compressed "
                           "texture coordinates", f"baseColorTexture's {_TEXTURE_TRANSFORM} is not applied to "
                           "Draco-compressed texture coordinates")


def _listed(value: object) -> list[Any]:
    return value if isinstance(value, list) else []


def _base_colour_texture(material: dict[str, Any]) -> dict[str, Any]:
    """A material's base colour texture's textureInfo (empty where it has none)."""
    where, _, key = _base_colour(material)
    return _nested(where, (key,))


# --- morph targets: the shapes the weights give -------------------------------------------------
_BASE_SHAPE: tuple[float, ...] = ()  # the weights of a placement drawn in its mesh's base shape
_MORPHED_ITEM_BYTES = 12  # a vertex of a shape (float32 VEC3): what a shape's reads and writes are counted in


@dataclass(frozen=True)
class MorphedShapes:
    """Each placed mesh with morph targets that its weights shape (a node's, else its mesh's): the nodes
    that place it, by the weights they shape it with (_BASE_SHAPE: its base shape); and the notes of
    weights that cannot be applied, whose placements are drawn in the base shape; what the shapes read and
    write (_shaping_bytes), which the skins' share the limit with."""

    by_mesh: dict[int, dict[tuple[float, ...], list[int]]]
    notes: tuple[str, ...] = ()
    made: int = 0


def morphed_shapes(document: dict[str, Any], held: int) -> MorphedShapes:
    """The shapes of a checked glTF's placed meshes, from its JSON. What they read and write may come to no
    more than made_limit(held) bytes, `held` the file's and its buffers' bytes: a mesh past it is drawn in
    its base shape, with a note (each shape reads its targets again: many nodes of weights of their own
    would read a large mesh's many times). Each mesh's primitives and own weights are read once, however
    many nodes place it."""
    meshes, nodes = document.get("meshes", []), document.get("nodes", [])
    by_mesh: dict[int, dict[tuple[float, ...], list[int]]] = {}
    unapplied: dict[int, str] = {}  # each mesh's first reason
    targets: dict[int, _Targets] = {}
    by_mesh_weights: dict[int, list[int]] = {}  # the nodes each mesh's own weights shape it for
    for number in sorted(set(_placed_node_numbers(document))):
        mesh_number = nodes[number].get("mesh")
        if mesh_number is not None and mesh_number not in targets:
            targets[mesh_number] = _targets_of(meshes[mesh_number])
        if mesh_number is None or not targets[mesh_number].counts[-1]:  # no primitive has targets
            continue
        own = "weights" in nodes[number]
        if not own and mesh_number in by_mesh_weights:
            by_mesh_weights[mesh_number].append(number)
            continue
        weights = _shaping_weights(number, nodes[number], mesh_number, meshes[mesh_number], targets[mesh_number])
        if isinstance(weights, str):
            unapplied.setdefault(mesh_number, weights)
            weights = _BASE_SHAPE
        placing = by_mesh.setdefault(mesh_number, {}).setdefault(weights, [])
        placing.append(number)
        if not own:
            by_mesh_weights[mesh_number] = placing
    made = 0
    for mesh_number, shapes in list(by_mesh.items()):
        work = _shaping_bytes(document, meshes[mesh_number], shapes, made_limit(held) - made)
        if work and made + work <= made_limit(held):
            made += work
            continue
        del by_mesh[mesh_number]  # its base shape alone: nothing to make
        if work:
            unapplied.setdefault(mesh_number, f"{_mesh_named(mesh_number, meshes[mesh_number])}'s shapes by its "
                                              f"weights would bring what shapes make to {past_made_limit(held)}")
    return MorphedShapes(by_mesh, _unshaped_notes(list(unapplied.values())), made)


@dataclass(frozen=True)
class _Targets:
    """A mesh's primitives' counts of morph targets (sorted, each once), and the primitives whose Draco
    stream holds POSITION."""

    counts: tuple[int, ...]
    compressed: tuple[int, ...]


def _targets_of(mesh: dict[str, Any]) -> _Targets:
    primitives = mesh["primitives"]
    return _Targets(tuple(sorted({len(primitive.get("targets", [])) for primitive in primitives})),
                    tuple(number for number, primitive in enumerate(primitives)
                          if "POSITION" in _draco_attributes(primitive)))


def _shaping_weights(number: int, node: dict[str, Any], mesh_number: int, mesh: dict[str, Any],
                     targets: _Targets) -> tuple[float, ...] | str:
    """The weights node `number` shapes its mesh with, glTF's default pose (its own, else its mesh's;
    _BASE_SHAPE where they are zeros or none), or why they cannot be applied."""
    own = "weights" in node
    weights = node["weights"] if own else mesh.get("weights", [])
    named = _mesh_named(mesh_number, mesh)
    whose, targets_of = (f"node {number}'s weights", f"{named}'s") if own else (f"{named}'s weights", "its")
    if not (isinstance(weights, list) and all(map(_is_number, weights))):
        return f"{whose} are not a list of numbers"
    if unheld := [weight for weight in weights if not _is_finite(weight)]:
        return f"{whose} hold {shortened(str(unheld[0]))}, not a finite number"
    if not any(weights):
        return _BASE_SHAPE
    if len(targets.counts) > 1:
        return (f"{named}'s primitives have {' and '.join(map(str, targets.counts))} morph targets (glTF's have as "
                "many each)")
    if len(weights) != targets.counts[0]:
        return (f"{whose} are {counted(len(weights), 'number')}, for {targets_of} "
                f"{counted(targets.counts[0], 'morph target')}")
    if targets.compressed and _draco_decoder():  # it writes what it decodes into the accessor POSITION points at
        return (f"{named}'s primitive {targets.compressed[0]} is Draco-compressed: trimesh decodes its positions over "
                "the shape")
    return tuple(float(weight) for weight in weights)


def _shaping_bytes(document: dict[str, Any], mesh: dict[str, Any], shapes: dict[tuple[float, ...], list[int]],
                   budget: int) -> int:
    """What a mesh's shapes read and write, counted until it passes `budget`: for each shape other than the
    base, the JSON of its copy of the mesh, and for each drawn primitive its POSITION, the targets'
    accessors that move it and the shape made, in _MORPHED_ITEM_BYTES a vertex, and as many again a target
    its weights are looked up against (many nodes' weights on many primitives' targets: looked up all)."""
    accessors, total = document["accessors"], 0
    copy_bytes = len(json.dumps(_mesh_copy(mesh))) if any(shapes) else 0
    for weights in filter(None, shapes):
        total += copy_bytes
        for primitive in filter(_is_drawn, mesh["primitives"]):
            targets = primitive["targets"]
            vertices = accessors[primitive["attributes"]["POSITION"]]["count"]
            moving = len(_moving_weights(accessors, weights, targets))
            total += _MORPHED_ITEM_BYTES * (vertices * (2 + moving) + len(targets))
            if total > budget:
                return total
    return total


def _is_drawn(primitive: dict[str, Any]) -> bool:
    return primitive.get("mode", _TRIANGLES) in _DRAWN_MODES


def _moving_weights(accessors: list[dict[str, Any]], weights: tuple[float, ...],
                    targets: list[dict[str, Any]]) -> dict[int, float]:
    """The accessors of the targets' POSITIONs that move the vertices, each with its weights added up (a
    file may name one in several targets): one of zeros (no view, no sparse values) moves none."""
    moving: dict[int, float] = {}
    for weight, target in zip(weights, targets):
        position = target.get("POSITION")
        if weight and position is not None and ("bufferView" in accessors[position] or "sparse" in accessors[position]):
            moving[position] = moving.get(position, 0.0) + weight
    return {position: weight for position, weight in moving.items() if weight}


def _unshaped_notes(reasons: list[str]) -> tuple[str, ...]:
    """One note of the meshes whose weights cannot be applied (a reason each), naming the first."""
    if not reasons:
        return ()
    if len(reasons) == 1:
        return (f"{reasons[0]}: drawn in the base shape",)
    return (f"{counted(len(reasons), 'mesh', 'meshes')} with morph targets drawn in the base shape: their weights "
            f"cannot be applied (the first, {reasons[0]})",)


# --- the JSON made again for trimesh -------------------------------------------------------------
def as_trimesh_reads(path: Path, data: bytes, document: dict[str, Any], file_type: str,
                     read_beside: Callable[[str], bytes], number_materials: bool = False,
                     shapes: MorphedShapes | None = None, skins: SkinnedPlacements | None = None) -> bytes:
    """The file, its JSON made again (a GLB's JSON chunk too) where trimesh is to read it otherwise: its
    file URIs that hold "base64," spelled apart, its materials named by number where their samplers matter,
    the meshes no node places emptied, each primitive's TEXCOORD_0 the set its base colour texture reads, the
    meshes its weights shape given their shapes' positions, the skinned meshes placed by their joints (each
    moved onto a node of its own), the accessors its primitives read made plain
    (sparse ones dense, normalized positions and texture coordinates floats), the texture coordinates its
    base colour textures' KHR_texture_transform moves made moved, its nodes' cameras taken out, each
    primitive of a mesh of several made a mesh of its own on a node of its own, its WEBP textures' fallbacks
    chosen, its specular-glossiness materials' diffuse colours made their base colours and the pictures no
    material draws emptied, its triangle fans made triangles, the meshes it
    makes nothing of taken off their nodes, and an empty list of buffer views where it lists none.
    The document is checked already (GltfReferences), and the values its drawn primitives read are
    checked here (_check_drawn_values); `read_beside` reads a buffer's file; `number_materials`: where
    sampled_materials found a sampling to keep; `shapes`: its morphed_shapes (None: none made); `skins`: its
    skinned_placements (None: none skinned)."""
    respelled = _file_uris_respelled(document)  # first: a buffer read here is then named as trimesh asks for it
    views_listed = _buffer_views_listed(document)  # before the rewrites that add a view
    numbered = number_materials and _materials_numbered(document)
    unplaced_emptied = _unplaced_meshes_emptied(document)  # before their accessors are checked and made plain
    uv_sets_chosen = _uv_sets_chosen(document)
    buffers = _BufferBytes(path, data, document, file_type, read_beside)
    _check_drawn_values(path, document, buffers)
    shaped = shapes is not None and _shapes_made(path, document, buffers, shapes)  # before: its POSITIONs are plain
    skinned = skins is not None and _skins_applied(path, document, buffers, skins)  # after: glTF skins the shape
    made_plain = _accessors_made_plain(path, document, buffers)
    transforms_applied = _texture_transforms_applied(path, document, buffers)  # after: it reads plain coordinates
    fans_made_triangles = _fans_made_triangles(path, document, buffers)  # after: it reads plain indices
    nothing_taken_off = _meshes_of_nothing_taken_off(document)  # after: a fan of triangles is something
    cameras_taken_out = _node_cameras_taken_out(document)
    primitives_apart = _primitives_put_apart(document)  # last: the meshes and the nodes that place them are final
    fallbacks_chosen = _fallbacks_chosen(document)
    diffuse_made_base = _diffuse_made_base_colour(document)
    undrawn_emptied = _undrawn_pictures_emptied(document)
    if not (respelled or numbered or unplaced_emptied or uv_sets_chosen or shaped or skinned or made_plain
            or transforms_applied
            or fans_made_triangles or nothing_taken_off or cameras_taken_out or primitives_apart or views_listed
            or fallbacks_chosen
            or diffuse_made_base or undrawn_emptied):
        return data
    text = json.dumps(document).encode()
    if file_type == "gltf":
        return text
    text += b" " * (-len(text) % 4)  # chunks are aligned to four bytes, a JSON chunk padded with spaces
    rest = data[_after_json(data):int.from_bytes(data[8:12], "little")]  # the chunks after the JSON
    return (b"glTF" + (2).to_bytes(4, "little") + (20 + len(text) + len(rest)).to_bytes(4, "little")
            + len(text).to_bytes(4, "little") + b"JSON" + text + rest)


def _file_uris_respelled(document: dict[str, Any]) -> bool:
    """Spells each buffer's and picture's file URI as trimesh is to ask for it (as_trimesh_asks): it read
    "x-base64,y.bin" as the bytes that "y.bin" decodes to. False where none is spelled otherwise."""
    respelled = False
    for item in (*document.get("buffers", []), *document.get("images", [])):
        uri = item.get("uri")
        if isinstance(uri, str) and not _is_data_uri(uri) and as_trimesh_asks(uri) != uri:
            item["uri"], respelled = as_trimesh_asks(uri), True
    return respelled


def _unplaced_meshes_emptied(document: dict[str, Any]) -> bool:
    """Empties each mesh no node of the scene places: trimesh builds every mesh listed, each primitive a
    copy of what it reads (200 primitives of one 300k-vertex accessor, 3.6 MB: 1.9 GB), drawn or not.
    False where there is none."""
    meshes, placed = document.get("meshes", []), _placed_meshes(document)
    unplaced = [index for index, mesh in enumerate(meshes) if mesh["primitives"] and index not in placed]
    for index in unplaced:
        meshes[index]["primitives"] = []
    return bool(unplaced)


def _uv_sets_chosen(document: dict[str, Any]) -> bool:
    """Points each primitive's TEXCOORD_0 at the set its material's base colour texture reads (its texCoord,
    checked to be one the primitive has: GltfReferences.texture_sets): trimesh lays the picture on by
    TEXCOORD_0 whatever texCoord says, and the base colour texture is the one picture drawn. A Draco
    stream's first set is left undecoded: trimesh's decoder writes each attribute into the accessor its
    name points at, the first set over the one chosen. False where none reads another set."""
    materials, chosen = document.get("materials", []), False
    for mesh in document.get("meshes", []):
        for primitive in mesh["primitives"]:
            texture_set = _drawn_uv_set(materials[primitive["material"]]) if "material" in primitive else 0
            if texture_set:
                attributes = primitive["attributes"]
                attributes["TEXCOORD_0"], chosen = attributes[f"TEXCOORD_{texture_set}"], True
                _draco_attributes(primitive).pop("TEXCOORD_0", None)
    return chosen


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


def _texture_transforms_applied(path: Path, document: dict[str, Any],
                                buffer: Callable[[int], bytes | memoryview]) -> bool:
    """Points each primitive that draws faces at its TEXCOORD_0 (the set its base colour texture reads:
    _uv_sets_chosen) moved by that texture's KHR_texture_transform, in a buffer appended as a data: URI:
    trimesh applies none. Each accessor is moved once for each transform that moves it, into an accessor
    of its own (primitives may share it, moved otherwise or not at all); one vertex made for each one a
    primitive draws at most, so no more than the placements counted make. False where none is moved."""
    accessors, materials = document.get("accessors", []), document.get("materials", [])
    made, moved = _MadeBuffer(document), {}
    for mesh_number, mesh in enumerate(document.get("meshes", [])):
        for primitive_number, primitive in enumerate(mesh["primitives"]):
            material = materials[primitive["material"]] if "material" in primitive else {}
            affine = _uv_transform(material)
            uvs = primitive["attributes"].get("TEXCOORD_0")
            if affine is None or uvs is None or not _draws_faces(accessors, primitive) \
                    or _uvs_decoded_by_trimesh(primitive, material):
                continue
            if (uvs, affine) not in moved:
                source = _uv_values(path, document, uvs, buffer)
                values = _moved_uvs(source, affine)
                if (vertex := _first_moved_past_float32(source, values)) is not None:
                    what = f"{_mesh_named(mesh_number, mesh)}'s primitive {primitive_number}"
                    raise LoadError(path, f"{what}: material {primitive['material']}'s {_base_colour(material)[2]}'s "
                                          f"{_TEXTURE_TRANSFORM} moves vertex {vertex} of its TEXCOORD_"
                                          f"{_drawn_uv_set(material)} (accessor {uvs}) past 3.4e38, where the GPU's "
                                          "32-bit numbers end")
                accessors.append({"bufferView": made.view(values), "componentType": _FLOAT_COMPONENTS,
                                  "count": len(values), "type": "VEC2"})
                moved[uvs, affine] = len(accessors) - 1
            primitive["attributes"]["TEXCOORD_0"] = moved[uvs, affine]
    if moved:
        made.append()
    return bool(moved)


def _uv_values(path: Path, document: dict[str, Any], number: int, buffer: Callable[[int], bytes | memoryview]
               ) -> np.ndarray:
    """Accessor `number`'s texture coordinates, (count, 2) float64: floats, or the integers KHR_mesh_quantization
    stores unnormalized (normalized ones are made floats first: _accessors_made_plain)."""
    items = _items(path, document, number, buffer)
    return np.ascontiguousarray(items).view(_COMPONENT_DTYPES[document["accessors"][number]["componentType"]]
                                            ).astype(np.float64)


def _moved_uvs(uvs: np.ndarray, affine: tuple[float, ...]) -> np.ndarray:
    """(count, 2) float32: `uvs` through the affine map (a, b, c, d, e, f) of _uv_transform."""
    a, b, c, d, e, f = affine
    with np.errstate(all="ignore"):  # past float32's range: refused (_first_moved_past_float32)
        return (uvs @ np.array([[a, c], [b, d]]) + np.array([e, f])).astype(np.float32)


def _first_moved_past_float32(source: np.ndarray, moved: np.ndarray) -> int | None:
    """The first vertex whose finite coordinates a transform moved past float32's range (its values are
    checked finite, but large ones take them past it); None where none is. The file's own that are not
    finite are left to the check of every mesh's texture coordinates, which names them so."""
    unheld = np.isfinite(source).all(axis=1) & ~np.isfinite(moved).all(axis=1)
    return int(np.argmax(unheld)) if unheld.any() else None


def _placed_meshes(document: dict[str, Any]) -> set[int]:
    """The meshes of the nodes under the scene's roots, as trimesh walks them."""
    return {node["mesh"] for node in _placed_nodes(document) if "mesh" in node}


_DRAWN_MODES = (_TRIANGLES, _STRIP, _FAN)  # trimesh makes faces of the first two; fans are made triangles
_FLOAT_COMPONENTS = 5126
_CHECKED_ITEMS = 1 << 16  # an accessor's items looked at at once: their temporaries stay small


def _check_drawn_values(path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview]) -> None:
    """The values the placed meshes' drawn primitives read, refused naming the mesh and the primitive:
    a position that is not a finite number, an index past the primitive's vertices. trimesh reads them
    as they are, into meshes of its own names, where they were refused naming neither. Each accessor is
    looked at once (for each vertex count, its indices), however many primitives read it."""
    accessors, positions_seen, indices_seen = document.get("accessors", []), set(), set()
    for number, mesh in enumerate(document.get("meshes", [])):
        for primitive_number, primitive in enumerate(mesh["primitives"]):
            if primitive.get("mode", _TRIANGLES) not in _DRAWN_MODES:
                continue
            what = f"{_mesh_named(number, mesh)}'s primitive {primitive_number}"
            position = primitive["attributes"]["POSITION"]
            vertices = accessors[position]["count"]
            if accessors[position]["componentType"] == _FLOAT_COMPONENTS and position not in positions_seen:
                _check_finite_positions(path, document, position, what, buffer)  # integers are finite
            if "indices" in primitive and (primitive["indices"], vertices) not in indices_seen:
                _check_indices(path, document, primitive["indices"], vertices, what, buffer)
            positions_seen.add(position)
            indices_seen.add((primitive.get("indices"), vertices))


def _check_finite_positions(path: Path, document: dict[str, Any], number: int, what: str,
                            buffer: Callable[[int], bytes | memoryview]) -> None:
    """Float positions (accessor `number`) refused at the first that is not a finite number."""
    vertex = _first_item(_items(path, document, number, buffer), "<f4", lambda values: ~np.isfinite(values).all(axis=1))
    if vertex is not None:
        raise LoadError(path, f"{what}: a vertex coordinate is not a finite number (vertex {vertex} of its POSITION, "
                              f"accessor {number})")


def _check_indices(path: Path, document: dict[str, Any], number: int, vertices: int, what: str,
                   buffer: Callable[[int], bytes | memoryview]) -> None:
    """Indices (accessor `number`) refused at the first that names no one of the `vertices`."""
    items = _items(path, document, number, buffer)
    kind = f"<u{items.shape[1]}"
    item = _first_item(items, kind, lambda values: values[:, 0] >= vertices)
    if item is not None:
        vertex = int(np.ascontiguousarray(items[item:item + 1]).view(kind)[0, 0])
        raise LoadError(path, f"{what}: index {item} of its indices (accessor {number}) refers to vertex {vertex}, "
                              f"but the primitive has {counted(vertices, 'vertex', 'vertices')}")


def _first_item(items: np.ndarray, kind: str, wrong: Callable[[np.ndarray], np.ndarray]) -> int | None:
    """The first of an accessor's items (count, bytes of an item) that, read as numbers of `kind`, is
    `wrong`; None where none is. A block of items at a time, each made contiguous (a view may be strided)."""
    for low in range(0, len(items), _CHECKED_ITEMS):
        found = wrong(np.ascontiguousarray(items[low:low + _CHECKED_ITEMS]).view(kind))
        if found.any():
            return low + int(np.argmax(found))
    return None


def _mesh_named(number: int, mesh: dict[str, Any]) -> str:
    """'mesh 2', and its name where it has one: 'mesh 2 ('wing')'."""
    name = mesh.get("name")
    return f"mesh {number} ('{shortened(escaped(name))}')" if name else f"mesh {number}"


class _BufferBytes:
    """A checked glTF's buffers' bytes, each read once when first asked for, as trimesh reads them: a
    GLB's binary chunk, a data: URI's base64, or the file a URI names (`read_beside`)."""

    def __init__(self, path: Path, data: bytes, document: dict[str, Any], file_type: str,
                 read_beside: Callable[[str], bytes]) -> None:
        self.path, self.data, self.file_type, self.read_beside = path, data, file_type, read_beside
        self.buffers: list[dict[str, Any]] = document.get("buffers", [])
        self.read: dict[int, bytes | memoryview] = {}

    def __call__(self, number: int) -> bytes | memoryview:
        if number not in self.read:
            held = self._held(self.buffers[number].get("uri"), number)
            if len(held) < self.buffers[number]["byteLength"]:
                raise LoadError(self.path, f"not a glTF file: buffer {number} holds {len(held)} bytes, where its "
                                           f"byteLength says {self.buffers[number]['byteLength']}")
            self.read[number] = held
        return self.read[number]

    def _held(self, uri: object, number: int) -> bytes | memoryview:
        if not isinstance(uri, str):  # a GLB's own buffer
            return _binary_chunk(self.data) if self.file_type == "glb" and number == 0 else b""
        if not _is_data_uri(uri):
            return self.read_beside(uri)
        return data_uri_bytes(self.path, uri, number)


def data_uri_bytes(path: Path, uri: str, number: int) -> bytes:
    """Buffer `number`'s bytes, in its uri after "base64,", decoded as trimesh decodes them."""
    try:
        return base64.b64decode(_data_uri_payload(path, uri, f"buffer {number}"))
    except (binascii.Error, ValueError):
        raise LoadError(path, f"not a glTF file: buffer {number}'s data: URI is not base64") from None


def _data_uri_payload(path: Path, uri: str, what: str) -> str:
    """What a URI holds after "base64,", where trimesh decodes it; a data: URI must be glTF's, base64
    (data:[<media type>];base64,<data>): trimesh read another as the name of a file."""
    header, comma, _ = uri.partition(",")
    if _is_data_uri(uri) and not (comma and header.endswith(";base64")):
        raise LoadError(path, f"not a glTF file: {what}'s data: URI does not say ';base64,' before its data (glTF's "
                              "data: URIs are base64)")
    return uri[uri.index("base64,") + 7:]


def _accessors_made_plain(path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview]) -> bool:
    """Makes the accessors the primitives read ones trimesh reads as glTF means them, in a buffer
    appended as a data: URI: a sparse one dense (its base, its view's items or zeros, with the listed
    items replaced), and positions or texture coordinates stored as normalized integers (as
    KHR_mesh_quantization writes them) floats. trimesh reads no sparse values, and reads normalized
    integers as the integers (255 where 1 was meant). False where there is none."""
    accessors, read = document.get("accessors", []), _read_by_primitives(document)
    fractions = _normalized_read(document)
    plain = sorted({index for index in read if "sparse" in accessors[index]} | fractions)
    if not plain:
        return False
    made = _MadeBuffer(document)
    for index in plain:
        items, accessor = _items(path, document, index, buffer), accessors[index]
        if index in fractions:
            items, accessor = _as_fractions(items, accessor)
        kept = {key: value for key, value in accessor.items() if key not in ("sparse", "byteOffset")}
        accessors[index] = {**kept, "bufferView": made.view(items)}
    made.append()
    return True


def _shapes_made(path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview],
                 shapes: MorphedShapes) -> bool:
    """Gives each mesh its weights shape the positions of its shape (glTF's default pose), in a buffer
    appended as a data: URI: trimesh reads no morph target. Each shape but the base is drawn by a copy of
    the mesh (_mesh_per_shape). Primitives of the same POSITION and targets shaped alike share one
    accessor. False where no mesh is shaped."""
    if not shapes.by_mesh:
        return False
    meshes, accessors, made = document.get("meshes", []), document.get("accessors", []), _MadeBuffer(document)
    made_for: dict[tuple[Any, ...], int] = {}  # (POSITION, its targets, weights) -> the accessor of the shape
    for mesh_number, by_weights in shapes.by_mesh.items():
        unshaped = meshes[mesh_number]
        named = _mesh_named(mesh_number, unshaped)
        for mesh, weights in _mesh_per_shape(document, mesh_number, by_weights):
            for number, (primitive, source) in enumerate(zip(mesh["primitives"], unshaped["primitives"])):
                if not weights or not _is_drawn(source):
                    continue
                key = (source["attributes"]["POSITION"], tuple(target.get("POSITION") for target in
                                                               source["targets"]), weights)
                if key not in made_for:
                    shape = _shape(path, document, source, weights, buffer, f"{named}'s primitive {number}")
                    accessors.append({"bufferView": made.view(shape), "componentType": _FLOAT_COMPONENTS,
                                      "count": len(shape), "type": "VEC3"})
                    made_for[key] = len(accessors) - 1
                primitive["attributes"]["POSITION"] = made_for[key]
    made.append()
    return True


def _mesh_per_shape(document: dict[str, Any], mesh_number: int, by_weights: dict[tuple[float, ...], list[int]]
                    ) -> list[tuple[dict[str, Any], tuple[float, ...]]]:
    """Mesh `mesh_number` as it is for its base shape, and a copy of it for each other shape, each with its
    weights: the first shape's in its place, the others' appended, each node placing them re-pointed at its
    own."""
    meshes, nodes = document["meshes"], document["nodes"]
    unshaped = meshes[mesh_number]
    ordered = sorted(by_weights.items(), key=lambda shape: bool(shape[0]))  # _BASE_SHAPE first
    placed = []
    for number, (weights, placing) in enumerate(ordered):
        mesh = _mesh_copy(unshaped) if weights else unshaped
        if number == 0:
            meshes[mesh_number] = mesh
        else:
            meshes.append(mesh)
            for node in placing:
                nodes[node]["mesh"] = len(meshes) - 1
        placed.append((mesh, weights))
    return placed


def _mesh_copy(mesh: dict[str, Any]) -> dict[str, Any]:
    """A mesh for a shape of its own: its primitives, and their attributes, its own to change, without the
    targets and weights the shape applies (written again in each copy, they would be many times the file's)."""
    return {**{key: value for key, value in mesh.items() if key != "weights"},
            "primitives": [{**{key: value for key, value in primitive.items() if key != "targets"},
                            "attributes": dict(primitive["attributes"])} for primitive in mesh["primitives"]]}


def _shape(path: Path, document: dict[str, Any], primitive: dict[str, Any], weights: tuple[float, ...],
           buffer: Callable[[int], bytes | memoryview], what: str) -> np.ndarray:
    """(vertices, 3) float32: a primitive's POSITION and each morph target's times its weight; a coordinate
    that is not a finite number is refused. Targets' NORMALs are not read, as no NORMAL is: the viewer
    derives normals from the shape's faces."""
    with np.errstate(all="ignore"):  # NaN, or past float32's range: refused below
        shape = _values(path, document, primitive["attributes"]["POSITION"], buffer).astype(np.float64)
        for position, weight in _moving_weights(document["accessors"], weights, primitive["targets"]).items():
            shape += weight * _values(path, document, position, buffer)
        made = shape.astype(np.float32)
    unheld = ~np.isfinite(made).all(axis=1)
    if unheld.any():
        raise LoadError(path, f"{what}: vertex {np.argmax(unheld)} of its shape by its weights is not a finite number "
                              "(a morph target's POSITION holds one, or a weight takes it past float's range)")
    return made


def _values(path: Path, document: dict[str, Any], number: int, buffer: Callable[[int], bytes | memoryview]
            ) -> np.ndarray:
    """Accessor `number`'s values, (count, components), as glTF means them: normalized integers as fractions."""
    return _item_values(_items(path, document, number, buffer), document["accessors"][number])


def _values_in_blocks(path: Path, document: dict[str, Any], number: int, buffer: Callable[[int], bytes | memoryview]
                      ) -> Callable[[slice], np.ndarray]:
    """Accessor `number`'s values (as _values makes them) of a block of its items, its items read once."""
    items, accessor = _items(path, document, number, buffer), document["accessors"][number]
    return lambda block: _item_values(items[block], accessor)


def _item_values(items: np.ndarray, accessor: dict[str, Any]) -> np.ndarray:
    """An accessor's items' values, (items, components), as glTF means them: normalized integers as fractions."""
    if accessor.get("normalized") is True and accessor["componentType"] in _NORMALIZED:
        return _as_fractions(items, accessor)[0]
    return np.ascontiguousarray(items).view(_COMPONENT_DTYPES[accessor["componentType"]])


# --- skins: the meshes their joints place, at rest ------------------------------------------------
# What a skin makes and reads besides its vertices: a joint's matrix and its node's placement (4x4 float64s).
_JOINT_BYTES = 2 * 16 * 8
_SKIN_SETS = ("JOINTS_", "WEIGHTS_")  # a skinned primitive's attributes: each JOINTS_n with its WEIGHTS_n
_AFFINE_ROW, _AFFINE_TOLERANCE = np.array([0.0, 0.0, 0.0, 1.0]), 1e-6  # an inverse bind matrix's last row


@dataclass(frozen=True)
class SkinnedPlacements:
    """The placed nodes whose skins place their meshes (glTF applies no transform of a skinned mesh's own
    node), each with the file's number of the mesh it skins (a shape's copy is numbered past the file's:
    _mesh_per_shape), and the notes of the meshes left placed by their nodes, what their skins would make
    being past the limit."""

    nodes: tuple[tuple[int, int], ...] = ()
    notes: tuple[str, ...] = ()


def skinned_placements(document: dict[str, Any], held: int, shapes: MorphedShapes) -> SkinnedPlacements:
    """The placed nodes of a checked glTF that skin their meshes, from its JSON. What the skins read and make,
    with what `shapes` does, may come to no more than made_limit(held) bytes: a mesh is skinned once for each
    skin and shape it is placed in, however many nodes place it so; one past the limit, or whose Draco stream
    trimesh decodes, is placed by its nodes, with a note. Each mesh is looked at once."""
    nodes, meshes = document.get("nodes", []), document.get("meshes", [])
    shape_of = {node: weights for by_weights in shapes.by_mesh.values() for weights, placing in by_weights.items()
                for node in placing}
    budget, made = made_limit(held) - shapes.made, 0
    applied: dict[tuple[Any, ...], bool] = {}  # (mesh, its shape, skin) -> whether it is skinned
    costs: dict[int, tuple[int, int | None]] = {}  # mesh -> (what skinning it makes, its Draco primitive)
    skins_counted: set[int] = set()
    skinned, unapplied = [], []
    for number in sorted(set(_placed_node_numbers(document))):
        node = nodes[number]
        if "skin" not in node or "mesh" not in node:
            continue
        key = (node["mesh"], shape_of.get(number, _BASE_SHAPE), node["skin"])
        if key not in applied:
            mesh = meshes[node["mesh"]]
            if node["mesh"] not in costs:
                costs[node["mesh"]] = (len(json.dumps(_mesh_copy(mesh))) + _skinning_bytes(document["accessors"], mesh),
                                       _draco_skinned(mesh))
            mesh_bytes, compressed = costs[node["mesh"]]
            joints = 0 if node["skin"] in skins_counted else len(document["skins"][node["skin"]]["joints"])
            work = mesh_bytes + _JOINT_BYTES * joints
            applied[key] = compressed is None and made + work <= budget
            if applied[key]:
                made += work
                skins_counted.add(node["skin"])
            elif compressed is not None:
                unapplied.append(f"{_mesh_named(node['mesh'], mesh)}'s primitive {compressed} is Draco-compressed: "
                                 "trimesh decodes it over what its skin makes")
            else:
                unapplied.append(f"{_mesh_named(node['mesh'], mesh)}'s skinning by skin {node['skin']} would bring "
                                 f"what is made to {past_made_limit(held)}")
        if applied[key]:
            skinned.append((number, node["mesh"]))
    return SkinnedPlacements(tuple(skinned), _unskinned_notes(unapplied))


def _draco_skinned(mesh: dict[str, Any]) -> int | None:
    """The first drawn primitive whose Draco stream holds what a skin reads (POSITION, JOINTS_n, WEIGHTS_n),
    where trimesh decodes it: it writes them, after the skin is applied, into the accessors they name."""
    if not _draco_decoder():
        return None
    return next((number for number, primitive in enumerate(mesh["primitives"]) if _is_drawn(primitive)
                 and any(name == "POSITION" or name.startswith(_SKIN_SETS) for name in _draco_attributes(primitive))),
                None)


def _skinning_bytes(accessors: list[dict[str, Any]], mesh: dict[str, Any]) -> int:
    """What skinning a mesh reads and writes, in _MORPHED_ITEM_BYTES a vertex: for each drawn primitive its
    POSITION, its skinned positions, and each JOINTS_n and WEIGHTS_n set."""
    total = 0
    for primitive in filter(_is_drawn, mesh["primitives"]):
        sets = len(_skin_sets(primitive["attributes"]))
        total += _MORPHED_ITEM_BYTES * accessors[primitive["attributes"]["POSITION"]]["count"] * (2 + 2 * sets)
    return total


def _skin_sets(attributes: dict[str, Any]) -> list[str]:
    """The n of each JOINTS_n (each with its WEIGHTS_n: GltfReferences.skinned_primitives)."""
    return sorted(name[len(_SKIN_SETS[0]):] for name in attributes if name.startswith(_SKIN_SETS[0]))


def _unskinned_notes(reasons: list[str]) -> tuple[str, ...]:
    """One note of the skinned meshes placed by their nodes (a reason each), the first named."""
    if not reasons:
        return ()
    if len(reasons) == 1:
        return (f"{reasons[0]}: placed by its node, not its skin",)
    return (f"{len(reasons)} skinned meshes placed by their nodes, not their skins (the first, {reasons[0]})",)


def _skins_applied(path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview],
                   skins: SkinnedPlacements) -> bool:
    """Places each mesh that the nodes of `skins` skin as glTF does at the nodes' rest transforms (animations
    are not read): each vertex where its joints take it, the sum of w_i * world(joint_i) *
    inverseBindMatrix_i * position over its JOINTS_n and WEIGHTS_n, in a buffer appended as a data: URI; the
    mesh taken off its node (whose children it still places) onto a root node of its own, which places it
    where it is. trimesh applies no skin, and places a skinned mesh by its node. A mesh is skinned once for
    each skin and shape (its morph targets applied first: _shapes_made), however many nodes place it so, into
    a copy where nodes draw it otherwise too. False where there is none."""
    if not skins.nodes:
        return False
    nodes = document["nodes"]
    skinned_nodes = {number for number, _ in skins.nodes}
    unskinned = {nodes[number]["mesh"] for number in _placed_node_numbers(document)
                 if "mesh" in nodes[number] and number not in skinned_nodes}
    skinning = _Skinning(path, document, buffer, unskinned)
    roots = document["scenes"][document.get("scene", 0)]["nodes"]
    for number, file_mesh in skins.nodes:
        node = nodes[number]
        mesh = skinning.mesh(node["mesh"], node["skin"], file_mesh)
        del node["mesh"], node["skin"]
        nodes.append({"mesh": mesh})
        roots.append(len(nodes) - 1)
    skinning.made.append()
    return True


class _Skinning:
    """The skinned copies of a checked glTF's meshes, each made once, and what they are made of: the positions
    skinned, the skins' joints' matrices and the nodes' places. `unskinned`: the meshes nodes draw unskinned
    too, which keep their place."""

    def __init__(self, path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview],
                 unskinned: set[int]) -> None:
        self.path, self.document, self.buffer, self.unskinned = path, document, buffer, unskinned
        self.made = _MadeBuffer(document)
        self.sources: dict[int, dict[str, Any]] = {}  # each mesh as the file gives it, before its place is taken
        self.meshes: dict[tuple[int, int], int] = {}  # (mesh, skin) -> its skinned copy
        self.positions: dict[tuple[Any, ...], int] = {}  # (POSITION, its sets, skin) -> the accessor skinned
        self.matrices: dict[int, np.ndarray] = {}  # skin -> its joints' matrices
        self.places = _WorldTransforms(document)

    def mesh(self, number: int, skin: int, file_mesh: int) -> int:
        """Mesh `number` skinned by `skin`, made once: in the mesh's place where no node draws it otherwise.
        `file_mesh`: the number the file gives it, which its refusals name."""
        if (number, skin) in self.meshes:
            return self.meshes[number, skin]
        meshes = self.document["meshes"]
        in_place = number not in self.unskinned and number not in self.sources
        source = self.sources.setdefault(number, meshes[number])
        mesh = _mesh_copy(source)
        if in_place:
            meshes[number] = mesh
        else:
            meshes.append(mesh)
        self.meshes[number, skin] = number if in_place else len(meshes) - 1
        named = _mesh_named(file_mesh, source)
        for primitive_number, (primitive, original) in enumerate(zip(mesh["primitives"], source["primitives"])):
            attributes = primitive["attributes"]
            for name in [name for name in attributes if name.startswith(_SKIN_SETS)]:
                del attributes[name]  # read here, not by trimesh
            if _is_drawn(original):
                attributes["POSITION"] = self.position(original, skin, f"{named}'s primitive {primitive_number}")
        return self.meshes[number, skin]

    def position(self, primitive: dict[str, Any], skin: int, what: str) -> int:
        """The accessor of a primitive's positions skinned by `skin`, made once for its POSITION and sets."""
        attributes = primitive["attributes"]
        sets = _skin_sets(attributes)
        key = (attributes["POSITION"], tuple((attributes[f"JOINTS_{n}"], attributes[f"WEIGHTS_{n}"]) for n in sets),
               skin)
        if key not in self.positions:
            if skin not in self.matrices:
                self.matrices[skin] = _joint_matrices(self.path, self.document, skin, self.buffer, self.places)
            placed = _skinned_positions(self.path, self.document, attributes, sets, self.matrices[skin], self.buffer,
                                        f"{what}, skinned by skin {skin}")
            accessors = self.document["accessors"]
            accessors.append({"bufferView": self.made.view(placed), "componentType": _FLOAT_COMPONENTS,
                              "count": len(placed), "type": "VEC3"})
            self.positions[key] = len(accessors) - 1
        return self.positions[key]


def _joint_matrices(path: Path, document: dict[str, Any], number: int, buffer: Callable[[int], bytes | memoryview],
                    places: Callable[[int], np.ndarray]) -> np.ndarray:
    """(joints, 3, 4) float64: skin `number`'s world(joint) * inverseBindMatrix, each joint's, their last row
    (0 0 0 1) left out. Inverse bind matrices of a value not finite, or not affine, are refused."""
    skin = document["skins"][number]
    joints = skin["joints"]
    if "inverseBindMatrices" not in skin:  # glTF's default: the identity each
        inverses = np.broadcast_to(np.eye(4), (len(joints), 4, 4))
    else:
        index = skin["inverseBindMatrices"]
        values = _values(path, document, index, buffer)[:len(joints)].astype(np.float64)
        inverses = values.reshape(-1, 4, 4).transpose(0, 2, 1)  # glTF's matrices are stored by column
        said = f"skin {number}'s inverseBindMatrices (accessor {index})"
        unheld = ~np.isfinite(values).all(axis=1)
        if unheld.any():
            raise LoadError(path, f"{said}: matrix {np.argmax(unheld)} holds a value that is not a finite number")
        projective = np.abs(inverses[:, 3] - _AFFINE_ROW).max(axis=1) > _AFFINE_TOLERANCE
        if projective.any():
            at = int(np.argmax(projective))
            row = " ".join(f"{value:g}" for value in inverses[at, 3])
            raise LoadError(path, f"{said}: matrix {at}'s last row is {row}, where glTF's are 0 0 0 1")
    with np.errstate(all="ignore"):  # past float's range: the positions made of it are refused
        return (np.stack([places(joint) for joint in joints]) @ inverses)[:, :3]


def _skinned_positions(path: Path, document: dict[str, Any], attributes: dict[str, Any], sets: list[str],
                       matrices: np.ndarray, buffer: Callable[[int], bytes | memoryview], what: str) -> np.ndarray:
    """(vertices, 3) float32: each vertex's POSITION through its joints' `matrices`, weighed by its weights,
    which are made to add up to 1 (as three.js's glTF reader does: quantized weights add up to nearly 1).
    Weights adding up to 0 are refused (and a set's values: _checked_set). A block of vertices at a time,
    its sets widened (intp joints, float64 weights) for that block alone: whole, they held several times the file's."""
    count = document["accessors"][attributes["POSITION"]]["count"]
    positions = _values_in_blocks(path, document, attributes["POSITION"], buffer)
    read = [(n, _values_in_blocks(path, document, attributes[f"JOINTS_{n}"], buffer),
             _values_in_blocks(path, document, attributes[f"WEIGHTS_{n}"], buffer)) for n in sets]
    placed = np.empty((count, 3), np.float32)
    for low in range(0, count, _CHECKED_ITEMS):
        block = slice(low, low + _CHECKED_ITEMS)
        weighed = [_checked_set(path, n, joints(block), weights(block), len(matrices), what, low)
                   for n, joints, weights in read]
        total = sum(weights.sum(axis=1) for _, weights in weighed)
        if (none := total <= 0).any():
            raise LoadError(path, f"{what}: vertex {low + int(np.argmax(none))}'s weights add up to 0, where glTF's "
                                  "add up to 1")
        with np.errstate(all="ignore"):  # past float's range: refused below
            placed[block] = _weighed_sum(positions(block).astype(np.float64), weighed, matrices) / total[:, None]
    unheld = ~np.isfinite(placed).all(axis=1)
    if unheld.any():
        raise LoadError(path, f"{what}: vertex {np.argmax(unheld)} is placed by its joints at a coordinate that is not "
                              "a finite number (their transforms take it past float's range)")
    return placed


def _weighed_sum(positions: np.ndarray, weighed: list[tuple[np.ndarray, np.ndarray]], matrices: np.ndarray
                 ) -> np.ndarray:
    """(vertices, 3) float64: the sum of each vertex's weights times its joints' matrices times it."""
    moved = np.zeros((len(positions), 3))
    for joints, weights in weighed:
        for column in range(joints.shape[1]):
            gathered = matrices[joints[:, column]]
            moved += weights[:, column, None] * (np.einsum("vij,vj->vi", gathered[:, :, :3], positions)
                                                 + gathered[:, :, 3])
    return moved


def _checked_set(path: Path, n: str, joints: np.ndarray, weights: np.ndarray, joint_count: int, what: str,
                 low: int) -> tuple[np.ndarray, np.ndarray]:
    """A block of a primitive's JOINTS_n, (vertices, 4) intp, and WEIGHTS_n, (vertices, 4) float64, from vertex
    `low`, checked: each joint one of the skin's `joint_count`, each weight finite and 0 or more."""
    joints, weights = joints.astype(np.intp), weights.astype(np.float64)
    if (outside := (joints >= joint_count).any(axis=1)).any():
        vertex = int(np.argmax(outside))
        raise LoadError(path, f"{what}: vertex {low + vertex}'s JOINTS_{n} names joint "
                              f"{joints[vertex][joints[vertex] >= joint_count][0]}, of the skin's {joint_count}")
    if (unheld := ~np.isfinite(weights).all(axis=1)).any():
        vertex = int(np.argmax(unheld))
        raise LoadError(path, f"{what}: vertex {low + vertex}'s WEIGHTS_{n} holds "
                              f"{weights[vertex][~np.isfinite(weights[vertex])][0]}, not a finite number")
    if (below := (weights < 0).any(axis=1)).any():
        vertex = int(np.argmax(below))
        raise LoadError(path, f"{what}: vertex {low + vertex}'s WEIGHTS_{n} holds {weights[vertex].min():g}, where "
                              "glTF's weights are 0 or more")
    return joints, weights


class _WorldTransforms:
    """Each node's 4x4 place in the scene, as trimesh places its nodes (its parent's times its own
    transform), each node's made once, however many ask for it."""

    def __init__(self, document: dict[str, Any]) -> None:
        self.nodes = document.get("nodes", [])
        self.parent = {child: number for number, node in enumerate(self.nodes) for child in node.get("children", [])}
        self.made: dict[int, np.ndarray] = {}

    def __call__(self, number: int) -> np.ndarray:
        above: list[int] = []  # the node and its ancestors not made yet, the nearest first
        node: int | None = number
        while node is not None and node not in self.made:
            above.append(node)
            node = self.parent.get(node)
        place = np.eye(4) if node is None else self.made[node]
        with np.errstate(all="ignore"):  # past float's range: the positions made of it are refused
            for below in reversed(above):
                place = self.made[below] = place @ _node_transform(self.nodes[below])
        return self.made[number]


def _node_transform(node: dict[str, Any]) -> np.ndarray:
    """A node's 4x4 transform from its parent's, as trimesh makes it: its matrix times T * R * S."""
    from trimesh import transformations  # its quaternion made a matrix as trimesh makes it: normalized

    transform = np.array(node["matrix"], np.float64).reshape(4, 4).T if "matrix" in node else np.eye(4)
    if "translation" in node:
        transform = transform @ transformations.translation_matrix(node["translation"])
    if "rotation" in node:
        x, y, z, w = node["rotation"]  # trimesh's quaternions are w x y z
        transform = transform @ transformations.quaternion_matrix([w, x, y, z])
    if "scale" in node:
        transform = transform @ np.diag([*node["scale"], 1.0])
    return transform


_UINT32_COMPONENTS = 5125


def _fans_made_triangles(path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview]) -> bool:
    """Makes each triangle fan (glTF's mode 6) of three corners or more a primitive of its triangles, as
    glTF draws it (the first corner with each next two), their indices in a buffer appended as a data:
    URI: trimesh skips fans. Fans of the same indices over as many vertices share one accessor. The
    indices are checked already (_check_drawn_values). False where there is none."""
    accessors, made = document.get("accessors", []), _MadeBuffer(document)
    made_for: dict[tuple[Any, int], int] = {}  # (indices, vertices) -> the accessor of their triangles
    for primitive, vertices in _drawn_fans(document):
        fanned = (primitive.get("indices"), vertices)
        if fanned not in made_for:
            triangles = _fan_triangles(_fan_corners(path, document, primitive, vertices, buffer))
            accessors.append({"bufferView": made.view(triangles), "componentType": _UINT32_COMPONENTS,
                              "count": triangles.size, "type": "SCALAR"})
            made_for[fanned] = len(accessors) - 1
        primitive["mode"], primitive["indices"] = _TRIANGLES, made_for[fanned]
    if not made_for:
        return False
    made.append()
    return True


class _MadeBuffer:
    """Values made for trimesh (plain accessors, shapes, fans' triangles), a buffer view each, appended to
    the document as one buffer of a data: URI. A file may list no buffer, each of its accessors zeros
    (read without a view), and have them made all the same."""

    def __init__(self, document: dict[str, Any]) -> None:
        self.document, self.made = document, bytearray()
        self.number = len(document.setdefault("buffers", []))  # of the buffer `append` adds

    def view(self, values: np.ndarray) -> int:
        """A buffer view of `values`' bytes (not a copy of them made first), at a multiple of four bytes
        as glTF's are; its number."""
        views = self.document.setdefault("bufferViews", [])
        views.append({"buffer": self.number, "byteOffset": len(self.made), "byteLength": values.nbytes})
        self.made += memoryview(np.ascontiguousarray(values)).cast("B")
        self.made += b"\0" * (-values.nbytes % 4)
        return len(views) - 1

    def append(self) -> None:
        self.document["buffers"].append({"byteLength": len(self.made), "uri": "data:application/octet-stream;base64,"
                                         + base64.b64encode(self.made).decode()})


def _drawn_fans(document: dict[str, Any]) -> Iterator[tuple[dict[str, Any], int]]:
    """Each primitive of a triangle fan of three corners or more (fewer draw nothing, in glTF too), with
    its vertices' count."""
    accessors = document.get("accessors", [])
    for mesh in document.get("meshes", []):
        for primitive in mesh["primitives"]:
            vertices = accessors[primitive["attributes"]["POSITION"]]["count"]
            corners = accessors[primitive["indices"]]["count"] if "indices" in primitive else vertices
            if primitive.get("mode", _TRIANGLES) == _FAN and corners >= _FAN_LEAST_CORNERS:
                yield primitive, vertices


def _fan_corners(path: Path, document: dict[str, Any], primitive: dict[str, Any], vertices: int,
                 buffer: Callable[[int], bytes | memoryview]) -> np.ndarray:
    """A fan's corners in order, uint32: its indices, or its vertices in theirs where it has none."""
    if "indices" not in primitive:
        return np.arange(vertices, dtype=np.uint32)
    items = _items(path, document, primitive["indices"], buffer)
    return np.ascontiguousarray(items).view(f"<u{items.shape[1]}").ravel().astype(np.uint32)


def _fan_triangles(corners: np.ndarray) -> np.ndarray:
    """(corners - 2, 3) uint32, C-ordered: the first corner with each corner and the one after it."""
    triangles = np.empty((len(corners) - 2, 3), np.uint32)
    triangles[:, 0], triangles[:, 1], triangles[:, 2] = corners[0], corners[1:-1], corners[2:]
    return triangles


# glTF's normalized integers: each component type's dtype and the value that stands for 1.
_NORMALIZED = {kind: (_COMPONENT_DTYPES[kind], one) for kind, one in ((5120, 127), (5121, 255), (5122, 32767),
                                                                       (5123, 65535))}
_NORMALIZED_SHORTS = 5123


def _normalized_read(document: dict[str, Any]) -> set[int]:
    """The accessors the primitives read as positions or texture coordinates that hold normalized
    integers, and colours of normalized shorts, which trimesh casts to bytes where the mesh has no
    material (normals keep their direction, and are made unit length anyway; colours of bytes are
    the bytes drawn)."""
    accessors, found = document.get("accessors", []), set()
    for mesh in document.get("meshes", []):
        for primitive in mesh["primitives"]:
            for name, index in primitive["attributes"].items():
                accessor, name = accessors[index], str(name)
                if accessor.get("normalized") is not True or accessor["componentType"] not in _NORMALIZED:
                    continue
                if (name == "POSITION" or name.startswith("TEXCOORD_")
                        or name.startswith("COLOR_") and accessor["componentType"] == _NORMALIZED_SHORTS):
                    found.add(index)
    return found


def _as_fractions(items: np.ndarray, accessor: dict[str, Any]) -> tuple[np.ndarray, dict[str, Any]]:
    """(count, components) float32 of normalized integer items, as glTF defines them (c / the value that
    stands for 1, and no less than -1: a signed type has one value more below 0), and the accessor of
    them: float, its bounds (the integers') left out."""
    dtype, one = _NORMALIZED[accessor["componentType"]]
    values = np.ascontiguousarray(items).view(dtype).reshape(len(items), -1)
    fractions = np.maximum(values / np.float32(one), np.float32(-1.0)).astype(np.float32)
    described = {key: value for key, value in accessor.items() if key not in ("normalized", "min", "max")}
    return fractions, {**described, "componentType": 5126}


def _items(path: Path, document: dict[str, Any], number: int, buffer: Callable[[int], bytes | memoryview]
           ) -> np.ndarray:
    """Accessor `number`'s items, (count, bytes of an item): a sparse one's made dense, else its view's
    items, or zeros where it has no view."""
    if "sparse" in document["accessors"][number]:
        return _dense_items(path, document, number, buffer)
    return _base_items(document, number, buffer)


def _base_items(document: dict[str, Any], number: int, buffer: Callable[[int], bytes | memoryview]) -> np.ndarray:
    """Accessor `number`'s items before any sparse ones, (count, bytes of an item): its view's, or
    zeros where it has no view (glTF's meaning)."""
    accessor = document["accessors"][number]
    count, size = accessor["count"], _item_bytes(accessor)
    if "bufferView" not in accessor:
        return np.zeros((count, size), np.uint8)
    return _view_items(document, accessor["bufferView"], accessor.get("byteOffset", 0), count, size, buffer)


def _read_by_primitives(document: dict[str, Any]) -> set[int]:
    """The accessors the primitives read: their attributes' and indices (each checked to name one)."""
    read: set[int] = set()
    for mesh in document.get("meshes", []):
        for primitive in mesh["primitives"]:
            read.update(primitive["attributes"].values())
            if "indices" in primitive:
                read.add(primitive["indices"])
    return read


def _dense_items(path: Path, document: dict[str, Any], number: int, buffer: Callable[[int], bytes | memoryview]
                 ) -> np.ndarray:
    """Sparse accessor `number`'s items, (count, bytes of an item): its base with the listed ones
    replaced; an index that names no item, or indices that do not strictly increase, are refused."""
    accessor = document["accessors"][number]
    count, size = accessor["count"], _item_bytes(accessor)
    base = _base_items(document, number, buffer)
    items = base if base.flags.writeable else base.copy()  # a view of the buffer is read-only
    sparse = accessor["sparse"]
    changed, index_bytes = sparse["count"], _SPARSE_INDEX_BYTES[sparse["indices"]["componentType"]]
    where = _view_items(document, sparse["indices"]["bufferView"], sparse["indices"].get("byteOffset", 0), changed,
                        index_bytes, buffer, packed=True).view(f"<u{index_bytes}").ravel()
    outside = where >= count
    if outside.any():
        raise LoadError(path, f"not a glTF file: accessor {number}'s sparse indices name item "
                              f"{where[np.argmax(outside)]}, of {count}")
    unordered = np.diff(where.astype(np.int64)) <= 0  # of an index named twice, the last value would win
    if unordered.any():
        at = np.argmax(unordered) + 1
        raise LoadError(path, f"not a glTF file: accessor {number}'s sparse indices do not strictly increase: item "
                              f"{where[at]} follows {where[at - 1]}")
    items[where] = _view_items(document, sparse["values"]["bufferView"], sparse["values"].get("byteOffset", 0),
                               changed, size, buffer, packed=True)
    return items


def _view_items(document: dict[str, Any], view_number: int, offset: int, count: int, size: int,
                buffer: Callable[[int], bytes | memoryview], packed: bool = False) -> np.ndarray:
    """(count, size) bytes from `offset` into buffer view `view_number`, an item each `size` bytes apart
    where `packed` (a sparse accessor's parts), else its byteStride's; a view of the buffer. GltfReferences
    has checked that they lie within the view, and the view within its buffer's byteLength (_BufferBytes,
    that the buffer holds it)."""
    view = document["bufferViews"][view_number]
    stride = size if packed else view.get("byteStride") or size
    held = np.frombuffer(buffer(view["buffer"]), np.uint8, offset=view.get("byteOffset", 0) + offset,
                         count=(count - 1) * stride + size)
    return np.lib.stride_tricks.as_strided(held, (count, size), (stride, 1), writeable=False)


def _meshes_of_nothing_taken_off(document: dict[str, Any]) -> bool:
    """Takes each mesh trimesh makes nothing of (line loops, line strips, fans of under three corners
    alone) off the nodes that place it: trimesh leaves such a node out, and the children under it with
    it ("No path from world"). Its primitives are a note already. False where no node places one."""
    meshes = document.get("meshes", [])
    empty = {index for index, mesh in enumerate(meshes) if mesh["primitives"]
             and all(primitive.get("mode", _TRIANGLES) not in _READ_MODES for primitive in mesh["primitives"])}
    nodes = [node for node in document.get("nodes", []) if node.get("mesh") in empty]
    for node in nodes:
        del node["mesh"]
    return bool(nodes)


def _primitives_put_apart(document: dict[str, Any]) -> bool:
    """Makes each primitive of a mesh of several a mesh of its own (the first keeps the mesh's place), and
    each node that places such a mesh the parent of a node per primitive, of no transform, that places its
    mesh: trimesh names the frame of each primitive of a mesh of several by a short random id, and of two
    frames named alike keeps one, the other primitive's faces lost, a different one each load. trimesh
    names these nodes by their numbers, and reaches their primitives in the file's order, as it did the
    mesh's. False where no mesh has several."""
    meshes, nodes = document.get("meshes", []), document.get("nodes", [])
    apart: dict[int, list[int]] = {}  # a mesh of several primitives -> the meshes of one that hold them, in order
    for node in nodes[:]:  # the nodes made here place meshes of one primitive
        number = node.get("mesh")
        if number is not None and number not in apart and len(meshes[number]["primitives"]) > 1:
            apart[number] = _meshes_of_one_primitive(meshes, number)
        if number not in apart:
            continue
        first = len(nodes)
        nodes.extend({"mesh": mesh} for mesh in apart[number])
        del node["mesh"]
        # trimesh walks a node's children last first: its primitives, first before, are listed last, reversed
        node["children"] = [*node.get("children", []), *reversed(range(first, len(nodes)))]
    return bool(apart)


def _meshes_of_one_primitive(meshes: list[dict[str, Any]], number: int) -> list[int]:
    """The meshes, each of one of mesh `number`'s primitives in order, with its name and extras: the first
    in its place, the others appended."""
    mesh = meshes[number]
    others = [{**mesh, "primitives": [primitive]} for primitive in mesh["primitives"][1:]]
    mesh["primitives"] = mesh["primitives"][:1]
    meshes.extend(others)
    return [number, *range(len(meshes) - len(others), len(meshes))]


def _buffer_views_listed(document: dict[str, Any]) -> bool:
    """Lists no buffer views where the file lists none: trimesh then reads no accessor at all (an
    UnboundLocalError), where glTF's accessors without one are zeros. False where it lists some."""
    if "bufferViews" in document:
        return False
    document["bufferViews"] = []
    return True


def _node_cameras_taken_out(document: dict[str, Any]) -> bool:
    """Takes out the nodes' cameras: trimesh leaves out a node with a camera, its mesh and the children
    under it too, and the viewer reads no camera of a model. False where there is none."""
    nodes = [node for node in document.get("nodes", []) if "camera" in node]
    for node in nodes:
        del node["camera"]
    return bool(nodes)


_WEBP = "EXT_texture_webp"


def _fallbacks_chosen(document: dict[str, Any]) -> bool:
    """Takes out EXT_texture_webp where a texture gives a fallback `source` too, as a viewer that draws
    no WEBP does (trimesh took the WEBP, not drawn). False where no texture has both."""
    both = [texture for texture in document.get("textures", [])
            if "source" in texture and _WEBP in _nested(texture, ("extensions",))]
    for texture in both:
        del texture["extensions"][_WEBP]
    return bool(both)


# glTF's sampler values (OpenGL's enums) as a TextureSampling's; left out, the default's.
_WRAPS = {33071: Wrap.CLAMP, 33648: Wrap.MIRROR, 10497: Wrap.REPEAT}
_MAGNIFY = {9728: Filter.NEAREST, 9729: Filter.LINEAR}
_MINIFY = {9728: (Filter.NEAREST, None), 9729: (Filter.LINEAR, None), 9984: (Filter.NEAREST, Filter.NEAREST),
           9985: (Filter.LINEAR, Filter.NEAREST), 9986: (Filter.NEAREST, Filter.LINEAR),
           9987: (Filter.LINEAR, Filter.LINEAR)}
# trimesh keeps no sampler, but keeps a material's name: where samplers matter, the JSON it reads names
# each material by its number, and the reader finds the material's own name and sampling by it.
_NUMBERED = "marraztu glTF material "


def sampled_materials(document: dict[str, Any]) -> tuple[tuple[str, TextureSampling], ...]:
    """Each material's name ("" for none) and its base colour texture's sampling (its sampler's), where any
    is not the default; () where none is. The document is checked already (GltfReferences)."""
    materials, textures = document.get("materials", []), document.get("textures", [])
    by_sampler = [_sampling(sampler) for sampler in document.get("samplers", [])]  # each made once, however shared
    samplings = [_sampling_of(_base_colour_texture(material), textures, by_sampler) for material in materials]
    if all(sampling.is_default for sampling in samplings):
        return ()
    return tuple((material.get("name", ""), sampling) for material, sampling in zip(materials, samplings))


def numbered_material(name: object) -> int | None:
    """The number of a material trimesh read from JSON made again by _materials_numbered; None for another."""
    number = name[len(_NUMBERED):] if isinstance(name, str) and name.startswith(_NUMBERED) else ""
    return int(number) if number.isdecimal() else None


def _sampling_of(texture_info: dict[str, Any], textures: list[dict[str, Any]],
                 by_sampler: list[TextureSampling]) -> TextureSampling:
    """A textureInfo's sampling: its texture's sampler's, made by _sampling (the default where it names none)."""
    index = texture_info.get("index")
    if not _is_whole(index) or "sampler" not in textures[index]:
        return DEFAULT_SAMPLING
    return by_sampler[textures[index]["sampler"]]


def _sampling(sampler: dict[str, Any]) -> TextureSampling:
    minify, between_levels = _MINIFY.get(sampler.get("minFilter"), (Filter.LINEAR, Filter.LINEAR))
    return TextureSampling(wrap_u=_WRAPS[sampler.get("wrapS", 10497)], wrap_v=_WRAPS[sampler.get("wrapT", 10497)],
                           magnify=_MAGNIFY.get(sampler.get("magFilter"), Filter.LINEAR), minify=minify,
                           between_levels=between_levels)


def _materials_numbered(document: dict[str, Any]) -> bool:
    """Names each material by its number (numbered_material), every one, so that no name of the file's is
    taken for a number. False where there is none."""
    materials = document.get("materials", [])
    for number, material in enumerate(materials):
        material["name"] = f"{_NUMBERED}{number}"
    return bool(materials)


def _diffuse_made_base_colour(document: dict[str, Any]) -> bool:
    """Makes each specular-glossiness material's diffuseFactor and diffuseTexture its baseColorFactor and
    baseColorTexture, and takes the extension out: trimesh turned them into metallic-roughness values,
    whose base colour is no diffuse colour (pale: a specularFactor of 1, the default, made it white), and
    the viewer's Phong lighting reads the diffuse colour as Kd. False where there is none."""
    found = [material for material in document.get("materials", []) if _specular_glossiness(material) is not None]
    for material in found:
        extension = material["extensions"].pop(_SPECULAR_GLOSSINESS)
        values = material.setdefault("pbrMetallicRoughness", {})
        for diffuse, base in _DIFFUSE_KEYS.items():
            values.pop(base, None)  # the extension's, given or not (its default is glTF's), is the colour
            if diffuse in extension:
                values[base] = extension[diffuse]
    return bool(found)


def _undrawn_pictures_emptied(document: dict[str, Any]) -> bool:
    """Empties each picture no material's colour is made of (each material's base colour texture, as
    trimesh reads it), which trimesh then neither reads nor decodes: a normal map that cannot be read is
    no note that the scene's texture is shown. False where there is none."""
    textures, images = document.get("textures", []), document.get("images", [])
    drawn = {source for material in document.get("materials", [])
             if _is_whole(index := _base_colour_texture(material).get("index")) and 0 <= index < len(textures)
             for source in _texture_sources(textures[index])}
    undrawn = [index for index, image in enumerate(images) if image and index not in drawn]
    for index in undrawn:
        images[index] = {}  # trimesh passes over a picture of neither a URI nor a view
    return bool(undrawn)


def _nested(item: dict[str, Any], keys: tuple[str, ...]) -> dict[str, Any]:
    for key in keys:
        inner = item.get(key)
        item = inner if isinstance(inner, dict) else {}
    return item


def _texture_sources(texture: dict[str, Any]) -> set[int | None]:
    """The pictures trimesh may take for a texture: its `source`, or an extension's (EXT_texture_webp's)."""
    extensions = _nested(texture, ("extensions",)).values()
    return {texture.get("source"), *(_extension_source(extension) for extension in extensions)}


def _extension_source(extension: object) -> int | None:
    source = extension.get("source") if isinstance(extension, dict) else None
    return source if _is_whole(source) else None

