"""Accessor reading, which the rewrites, morphs and skins build on: an accessor's items, dense or
sparse, from the GLB's binary chunk, a buffer's file or a data: URI; normalized integers made fractions;
and the buffer that holds what is made for trimesh.
"""

from __future__ import annotations

import base64
import binascii
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from marraztu.errors import LoadError
from marraztu.loaders.gltf.document import _binary_chunk, _is_data_uri
from marraztu.loaders.gltf.values import (
    _COMPONENT_DTYPES,
    _FAN,
    _SPARSE_INDEX_BYTES,
    _STRIP,
    _item_bytes,
    _read_accessors,
)

_CHECKED_ITEMS = 1 << 16  # an accessor's items looked at at once: their temporaries stay small


class _BufferBytes:
    """A checked glTF's buffers' bytes, each read once when first asked for, as trimesh reads them: a
    GLB's binary chunk, a data: URI's base64, or the file a URI names (`read_beside`)."""

    def __init__(self, path: Path, data: bytes, document: dict[str, Any], file_type: str,
                 read_beside: Callable[[str], bytes]) -> None:
        self.path, self.data, self.file_type, self.read_beside = path, data, file_type, read_beside
        self.document = document  # its buffers looked up when asked: a rewrite may add the list (_MadeBuffer)
        self.read: dict[int, bytes | memoryview] = {}

    def __call__(self, number: int) -> bytes | memoryview:
        if number not in self.read:
            buffer = self.document["buffers"][number]
            held = self._held(buffer.get("uri"), number)
            if len(held) < buffer["byteLength"]:
                raise LoadError(self.path, f"not a glTF file: buffer {number} holds {len(held)} bytes, where its "
                                           f"byteLength says {buffer['byteLength']}")
            self.read[number] = held
        return self.read[number]

    def made_here(self, made: _MadeBuffer) -> None:
        """Appends `made`'s buffer to the document, its bytes read from here, not decoded again from its data: URI."""
        made.append()
        self.read[made.number] = memoryview(made.made)

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


_UINT32_COMPONENTS = 5125


def _corners(path: Path, document: dict[str, Any], primitive: dict[str, Any], vertices: int,
             buffer: Callable[[int], bytes | memoryview]) -> np.ndarray:
    """A primitive's corners in order, uint32: its indices, or its vertices in theirs where it has none."""
    if "indices" not in primitive:
        return np.arange(vertices, dtype=np.uint32)
    return _values(path, document, primitive["indices"], buffer).ravel().astype(np.uint32)


def _fan_triangles(corners: np.ndarray) -> np.ndarray:
    """(corners - 2, 3) uint32, C-ordered: the first corner with each corner and the one after it."""
    triangles = np.empty((len(corners) - 2, 3), np.uint32)
    triangles[:, 0], triangles[:, 1], triangles[:, 2] = corners[0], corners[1:-1], corners[2:]
    return triangles


def _triangles(path: Path, document: dict[str, Any], primitive: dict[str, Any],
               buffer: Callable[[int], bytes | memoryview]) -> np.ndarray:
    """(triangles, 3) uint32, writable: the triangles of a checked primitive that draws faces, as trimesh makes
    them of triangles and strips (each other triangle of a strip turned round) and glTF of a fan."""
    mode = primitive.get("mode")
    corners = _corners(path, document, primitive, document["accessors"][primitive["attributes"]["POSITION"]]["count"],
                       buffer)
    if mode == _FAN:
        return _fan_triangles(corners)
    if mode == _STRIP:
        from trimesh.util import triangle_strips_to_faces  # trimesh's own rule, so the turned strip draws as it did

        return triangle_strips_to_faces([corners]).astype(np.uint32)
    return corners.reshape(-1, 3)


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

    def accessor(self, values: np.ndarray, like: dict[str, Any]) -> int:
        """The number of an accessor appended of `values`, an item a row, in a view of its own: as `like` (its
        componentType, type, normalized) but for where it lies, its sparse part and its bounds (all items')."""
        kept = {key: value for key, value in like.items() if key not in ("bufferView", "byteOffset", "sparse",
                                                                         "min", "max")}
        accessors = self.document.setdefault("accessors", [])
        accessors.append({**kept, "count": len(values), "bufferView": self.view(values)})
        return len(accessors) - 1

    def append(self) -> None:
        self.document["buffers"].append({"byteLength": len(self.made), "uri": "data:application/octet-stream;base64,"
                                         + base64.b64encode(self.made).decode()})


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
    return {index for mesh in document.get("meshes", []) for primitive in mesh["primitives"]
            for index in _read_accessors(primitive) if index is not None}


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
