"""What the JSON names, checked before trimesh reads it (GltfReferences: indices, byte ranges, types
and numbers), and the checks of its structure: one parent to each node, geometry trimesh can read, and
the extensions it requires.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

from marraztu.errors import LoadError, escaped, shortened
from marraztu.loaders.files import MAX_FILE_BYTES
from marraztu.loaders.gltf.accessors import _data_uri_payload, _read_by_primitives, data_uri_bytes
from marraztu.loaders.gltf.counts import _roots
from marraztu.loaders.gltf.document import _is_data_uri
from marraztu.loaders.gltf.values import (
    _BASE_COLOUR_TEXTURES,
    _COMPONENT_BYTES,
    _FAN,
    _FLOAT_COMPONENTS,
    _POINTS,
    _READ_EXTENSIONS,
    _SKIN_SETS,
    _SPARSE_INDEX_BYTES,
    _TEXTURE_TRANSFORM,
    _TRIANGLES,
    _TYPE_COMPONENTS,
    _base_colour,
    _base_colour_texture,
    _diffuse_values,
    _draco_decoder,
    _is_drawn,
    _is_finite,
    _is_number,
    _is_undrawn_extension,
    _is_whole,
    _item_bytes,
    _listed,
    _nested,
    _numbers_of,
    _texture_infos,
    made_limit,
    past_made_limit,
)
from marraztu.model.mesh import counted

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
            said = f"{what}'s {shortened(escaped(str(name)))}"
            accessor = self.named(index, "accessors", said)
            if not str(name).startswith(_SKIN_SETS):  # read only where a skin moves the primitive: skinned_primitives
                self.attribute_types(said, str(name), index, accessor)
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
        each JOINTS_n with its WEIGHTS_n, of the types glTF allows, as glTF requires: what a joint moves is read
        from them (trimesh reads none: a primitive no skin moves has them read past). Each mesh is looked at
        once, for the first node that skins it."""
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
                    said = f"mesh {node['mesh']}'s primitive {primitive_number}'s {shortened(escaped(name))}"
                    self.attribute_types(said, name, attributes[name], self.document["accessors"][attributes[name]])

    def attribute_types(self, said: str, name: str, index: int, accessor: dict[str, Any]) -> None:
        """An attribute's accessor type, and its component type where it is read here, as glTF allows them;
        `said` names the attribute."""
        semantic = name.split("_", 1)[0]
        types = _ATTRIBUTE_TYPES.get(semantic, (accessor.get("type"),))
        if accessor.get("type") not in types:  # trimesh said an IndexError, or misread them
            self.refuse(f"{said} is accessor {index}, of type {accessor['type']}: glTF's are {' or '.join(types)}")
        if semantic in _COMPONENT_TYPES:  # an attribute not read here is not asked
            self.components(f"{said} is", _COMPONENT_TYPES[semantic], index, accessor)

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
    attributes (normalized ones made floats for trimesh: _fractions_made_floats), the base colour texture's
    transform (_texture_transforms_applied; other textures are not drawn), a specular-glossiness material's
    diffuse colour (its base colour), the default materials of variants (what glTF draws where none is
    chosen), emission's strength and unlit materials (notes of their own: _emission_notes, _unlit_notes), and
    the lights and shading the viewer's lighting has no term for (_is_undrawn_extension, noted)."""
    return name in _READ_EXTENSIONS or _is_undrawn_extension(name)

