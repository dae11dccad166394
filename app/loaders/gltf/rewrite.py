"""The JSON made again for trimesh (as_trimesh_reads), and its small rewrites where trimesh would read
the file otherwise than it says: URIs, uv sets, texture transforms, plain accessors, fans, cameras,
primitives put apart, fallbacks, diffuse colours and undrawn pictures; and the checks of the values the
drawn primitives read.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np

from marraztu.errors import LoadError
from marraztu.loaders.gltf.accessors import (
    _CHECKED_ITEMS,
    _UINT32_COMPONENTS,
    _as_fractions,
    _BufferBytes,
    _corners,
    _fan_triangles,
    _items,
    _MadeBuffer,
    _normalized_read,
    _read_by_primitives,
    _values,
)
from marraztu.loaders.gltf.counts import _decoded_accessors, _draws_faces, _placed_meshes
from marraztu.loaders.gltf.document import _after_json, _is_data_uri, as_trimesh_asks
from marraztu.loaders.gltf.morphs import MorphedShapes, _shapes_made
from marraztu.loaders.gltf.samplings import _materials_numbered
from marraztu.loaders.gltf.skins import SkinnedPlacements, _skins_applied
from marraztu.loaders.gltf.values import (
    _DIFFUSE_KEYS,
    _FAN,
    _FLOAT_COMPONENTS,
    _READ_MODES,
    _SPECULAR_GLOSSINESS,
    _STRIP,
    _TEXTURE_TRANSFORM,
    _TRIANGLES,
    _base_colour,
    _base_colour_texture,
    _draco_attributes,
    _drawn_uv_set,
    _is_drawn,
    _is_whole,
    _mesh_named,
    _nested,
    _read_accessors,
    _specular_glossiness,
    _uv_transform,
    _uvs_decoded_by_trimesh,
)
from marraztu.model.mesh import counted


def as_trimesh_reads(path: Path, data: bytes, document: dict[str, Any], file_type: str,
                     read_beside: Callable[[str], bytes], number_materials: bool = False,
                     shapes: MorphedShapes | None = None, skins: SkinnedPlacements | None = None,
                     notes: list[str] | None = None) -> bytes:
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
    skinned_placements (None: none skinned); `notes`: where the notes of what the values read say are added."""
    rewritten = [
        _file_uris_respelled(document),  # first: a buffer read here is then named as trimesh asks for it
        _buffer_views_listed(document),  # before the rewrites that add a view
        number_materials and _materials_numbered(document),
        _unplaced_meshes_emptied(document),  # before their accessors are checked and made plain
        _uv_sets_chosen(document),
    ]
    buffers = _BufferBytes(path, data, document, file_type, read_beside)
    rewritten.append(_sparse_made_dense(path, document, buffers))  # before all that read them: made dense once
    _check_drawn_values(path, document, buffers)
    rewritten += [  # in this order, each where the one before leaves the document
        shapes is not None and _shapes_made(path, document, buffers, shapes),  # before: its POSITIONs are plain
        skins is not None and _skins_applied(path, document, buffers, skins,  # after: glTF skins the shape
                                             [] if notes is None else notes),
        _fractions_made_floats(path, document, buffers),
        _texture_transforms_applied(path, document, buffers),  # after: it reads plain coordinates
        _fans_made_triangles(path, document, buffers),  # after: it reads plain indices
        _meshes_of_nothing_taken_off(document),  # after: a fan of triangles is something
        _node_cameras_taken_out(document),
        _primitives_put_apart(document),  # last of the meshes' and nodes' rewrites: they are final after it
        _used_vertices_made_own(path, document, buffers),  # after: the indices and attributes are final
        _fallbacks_chosen(document),
        _diffuse_made_base_colour(document),
        _undrawn_pictures_emptied(document),
    ]
    if not any(rewritten):
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
                source = _values(path, document, uvs, buffer).astype(np.float64)  # plain or quantized: made plain first
                values = _moved_uvs(source, affine)
                if (vertex := _first_moved_past_float32(source, values)) is not None:
                    what = f"{_mesh_named(mesh_number, mesh)}'s primitive {primitive_number}"
                    raise LoadError(path, f"{what}: material {primitive['material']}'s {_base_colour(material)[2]}'s "
                                          f"{_TEXTURE_TRANSFORM} moves vertex {vertex} of its TEXCOORD_"
                                          f"{_drawn_uv_set(material)} (accessor {uvs}) past 3.4e38, where the GPU's "
                                          "32-bit numbers end")
                moved[uvs, affine] = made.accessor(values, {"componentType": _FLOAT_COMPONENTS, "type": "VEC2"})
            primitive["attributes"]["TEXCOORD_0"] = moved[uvs, affine]
    if moved:
        made.append()
    return bool(moved)


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


def _check_drawn_values(path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview]) -> None:
    """The values the placed meshes' drawn primitives read, refused naming the mesh and the primitive:
    a position that is not a finite number, an index past the primitive's vertices. trimesh reads them
    as they are, into meshes of its own names, where they were refused naming neither. Each accessor is
    looked at once (for each vertex count, its indices), however many primitives read it."""
    accessors, positions_seen, indices_seen = document.get("accessors", []), set(), set()
    for number, mesh in enumerate(document.get("meshes", [])):
        for primitive_number, primitive in enumerate(mesh["primitives"]):
            if not _is_drawn(primitive):
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


def _sparse_made_dense(path: Path, document: dict[str, Any], buffers: _BufferBytes) -> bool:
    """Makes each sparse accessor the primitives read dense (its base, its view's items or zeros, with the
    listed items replaced), in a buffer appended as a data: URI whose bytes `buffers` keeps: trimesh reads no
    sparse values. Once, before the checks, shapes and skins read them (each made its own dense copy). False
    where there is none."""
    accessors = document.get("accessors", [])
    sparse = sorted(index for index in _read_by_primitives(document) if "sparse" in accessors[index])
    if not sparse:
        return False
    made = _MadeBuffer(document)
    for index in sparse:
        kept = {key: value for key, value in accessors[index].items() if key not in ("sparse", "byteOffset")}
        accessors[index] = {**kept, "bufferView": made.view(_items(path, document, index, buffers))}
    buffers.made_here(made)
    return True


def _fractions_made_floats(path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview]) -> bool:
    """Makes the positions, texture coordinates (and colours of shorts: _normalized_read) the primitives read
    that are stored as normalized integers (as KHR_mesh_quantization writes them) floats, in a buffer appended
    as a data: URI: trimesh reads normalized integers as the integers (255 where 1 was meant). False where
    there is none."""
    accessors, fractions = document.get("accessors", []), sorted(_normalized_read(document))
    if not fractions:
        return False
    made = _MadeBuffer(document)
    for index in fractions:
        items, accessor = _as_fractions(_items(path, document, index, buffer), accessors[index])
        kept = {key: value for key, value in accessor.items() if key != "byteOffset"}
        accessors[index] = {**kept, "bufferView": made.view(items)}
    made.append()
    return True


def _fans_made_triangles(path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview]) -> bool:
    """Makes each triangle fan (glTF's mode 6) of three corners or more a primitive of its triangles, as
    glTF draws it (the first corner with each next two), their indices in a buffer appended as a data:
    URI: trimesh skips fans. Fans of the same indices over as many vertices share one accessor. The
    indices are checked already (_check_drawn_values). False where there is none."""
    made = _MadeBuffer(document)
    made_for: dict[tuple[Any, int], int] = {}  # (indices, vertices) -> the accessor of their triangles
    for primitive, vertices in _drawn_fans(document):
        fanned = (primitive.get("indices"), vertices)
        if fanned not in made_for:
            triangles = _fan_triangles(_corners(path, document, primitive, vertices, buffer))
            made_for[fanned] = made.accessor(triangles.reshape(-1), {"componentType": _UINT32_COMPONENTS,
                                                                     "type": "SCALAR"})
        primitive["mode"], primitive["indices"] = _TRIANGLES, made_for[fanned]
    if not made_for:
        return False
    made.append()
    return True


def _drawn_fans(document: dict[str, Any]) -> Iterator[tuple[dict[str, Any], int]]:
    """Each primitive of a triangle fan of three corners or more (fewer draw nothing, in glTF too), with
    its vertices' count."""
    accessors = document.get("accessors", [])
    for mesh in document.get("meshes", []):
        for primitive in mesh["primitives"]:
            if primitive.get("mode", _TRIANGLES) == _FAN and _draws_faces(accessors, primitive):
                yield primitive, accessors[primitive["attributes"]["POSITION"]]["count"]


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


_TRIMESH_ATTRIBUTES = ("POSITION", "NORMAL", "TEXCOORD_0", "COLOR_0")  # and custom ones, named "_..."


def _used_vertices_made_own(path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview]
                            ) -> bool:
    """Gives each indexed primitive of triangles or strips whose attributes another primitive reads too,
    or that has more vertices than indices, accessors of only the vertices its indices use (in the order
    of their numbers), its indices renumbered to them (each face's corners in their order, the faces in
    theirs), in a buffer appended as a data: URI: trimesh copies a primitive's whole attributes, a
    shared accessor once for each primitive. Primitives of the same indices and attributes share what
    is made. False where there is none."""
    accessors, shared = document.get("accessors", []), _read_by_several(document)
    made, made_for = _MadeBuffer(document), {}
    for primitive in _compactable_primitives(document):
        attributes = {name: index for name, index in primitive["attributes"].items()
                      if name in _TRIMESH_ATTRIBUTES or str(name).startswith("_")}
        if not (shared & set(attributes.values())
                or accessors[attributes["POSITION"]]["count"] > accessors[primitive["indices"]]["count"]):
            continue
        key = (primitive["indices"], tuple(sorted(attributes.items())))
        if key not in made_for:
            made_for[key] = _own_vertices(path, document, primitive["indices"], attributes, made, buffer)
        if made_for[key] is not None:
            primitive["indices"], own = made_for[key]
            primitive["attributes"] = {**primitive["attributes"], **own}
    if not any(made_for.values()):
        return False
    made.append()
    return True


def _read_by_several(document: dict[str, Any]) -> set[int]:
    """The accessors that the attributes of more than one primitive read."""
    seen: set[int] = set()
    several: set[int] = set()
    for mesh in document.get("meshes", []):
        for primitive in mesh["primitives"]:
            for index in set(primitive["attributes"].values()):
                (several if index in seen else seen).add(index)
    return several


def _compactable_primitives(document: dict[str, Any]) -> Iterator[dict[str, Any]]:
    """The indexed primitives trimesh makes faces of by their indices (triangles, strips), other than
    Draco's, whose accessors its decoder fills (and the primitives that read those)."""
    decoded = _decoded_accessors(document)
    for mesh in document.get("meshes", []):
        for primitive in mesh["primitives"]:
            if (primitive.get("mode", _TRIANGLES) in (_TRIANGLES, _STRIP) and "indices" in primitive
                    and decoded.isdisjoint(_read_accessors(primitive))):
                yield primitive


def _own_vertices(path: Path, document: dict[str, Any], indices: int, attributes: dict[str, int],
                  made: _MadeBuffer, buffer: Callable[[int], bytes | memoryview]) -> tuple[int, dict[str, int]] | None:
    """(the accessor of the renumbered indices, the accessor of each attribute's used items), appended;
    None where the indices use every vertex, or none."""
    accessors = document["accessors"]
    used, renumbered = np.unique(_values(path, document, indices, buffer).ravel(), return_inverse=True)
    if not 0 < len(used) < accessors[attributes["POSITION"]]["count"]:
        return None
    own = {name: made.accessor(_items(path, document, index, buffer)[used], accessors[index])
           for name, index in attributes.items()}
    return made.accessor(renumbered.astype(np.uint32), {"componentType": _UINT32_COMPONENTS, "type": "SCALAR"}), own


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


def _texture_sources(texture: dict[str, Any]) -> set[int | None]:
    """The pictures trimesh may take for a texture: its `source`, or an extension's (EXT_texture_webp's)."""
    extensions = _nested(texture, ("extensions",)).values()
    return {texture.get("source"), *(_extension_source(extension) for extension in extensions)}


def _extension_source(extension: object) -> int | None:
    source = extension.get("source") if isinstance(extension, dict) else None
    return source if _is_whole(source) else None
