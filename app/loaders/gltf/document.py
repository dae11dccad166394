"""A .gltf's JSON, and a GLB's chunks, read and checked to be glTF 2's; and what the JSON names beside
it: its buffers' and pictures' URIs, spelled as trimesh asks for them, and its buffers' byte lengths.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from marraztu.errors import LoadError, escaped, shortened
from marraztu.loaders.gltf.values import _is_number, _is_whole

# A GLB holds its JSON and, after it, its binary buffer; chunks of other kinds are to be read past. Past
# this many after the JSON, a file is refused unread.
MAX_GLB_CHUNKS = 16


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
    _refuse_numbered_version(path, "version", version)
    major = version.split(".", 1)[0] if isinstance(version, str) else ""
    if not (major.isascii() and major.isdecimal()):  # glTF's are ASCII digits; Python reads others too
        raise LoadError(path, f"not a glTF file: its asset's version {shortened(escaped(repr(version)))} is not a "
                              "version such as \"2.0\"")
    if major.lstrip("0") != str(_GLTF_MAJOR):  # not int(): Python refuses one of thousands of digits
        raise LoadError(path, f"a file of glTF version {shortened(escaped(version))}: only glTF 2 is read")
    _check_min_version(path, asset)


_GLTF_MAJOR = 2  # the glTF read here: 2.0 and its minor versions


def _refuse_numbered_version(path: Path, key: str, value: object) -> None:
    """A version written as a JSON number, 2.0: glTF's is text, and "2.0 is not a version such as \"2.0\""
    would puzzle whoever reads it."""
    if _is_number(value):
        raise LoadError(path, f"not a glTF file: its asset's {key} is the number {shortened(escaped(repr(value)))}, "
                              "where glTF's is text, \"2.0\"")


def _check_min_version(path: Path, asset: dict[str, Any]) -> None:
    """The asset's minVersion, where it gives one: glTF's form, "major.minor", or "major" read as "major.0"
    as its version is (_check_version), and no later than 2.0, the version read here (glTF: a reader refuses
    an asset whose minVersion it does not support; trimesh reads past it)."""
    if "minVersion" not in asset:
        return
    least = asset["minVersion"]
    _refuse_numbered_version(path, "minVersion", least)
    if not (isinstance(least, str) and re.fullmatch(r"[0-9]+(\.[0-9]+)?", least)):
        raise LoadError(path, f"not a glTF file: its asset's minVersion {shortened(escaped(repr(least)))} is not a "
                              "version such as \"2.0\"")
    major, _, minor = (part.lstrip("0") for part in least.partition("."))
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
