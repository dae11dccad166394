"""PLY and glTF/GLB through trimesh, and STL's corners (read in stl.py) made a mesh, checked the way
the OBJ reader checks its own.

trimesh reads these formats well but forgives too much for a viewer that must say what is wrong: it
reads an ASCII PLY cut short as fewer faces, and takes NaN coordinates and face indices past the
vertex table. So the header's counts, the tables' values and the indices are checked here, and every
trimesh exception becomes one LoadError naming the file (and the line, for text formats, where it
can be known). trimesh is imported only when such a file is opened.

What a file names beside it (a glTF's buffers and pictures, a PLY's TextureFile) is read by marraztu
for trimesh, in the file's folder only; a picture that cannot be read is a note, as an MTL's is, and
trimesh's log, which would print its tracebacks on the person's terminal, is kept quiet.
"""

from __future__ import annotations

import functools
import gc
import io
import json
import logging
import re
import threading
import weakref
from collections.abc import Callable, Collection, Iterator
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, TypeVar
from urllib.parse import unquote

import numpy as np
from PIL import Image

from marraztu.errors import LoadError
from marraztu.loaders.files import (
    COLLECT_AFTER_BYTES,
    MAX_FILE_BYTES,
    is_there,
    line_at,
    read_file,
    read_model_bytes,
    same_file_key,
    shown,
    size_or_zero,
    spellings,
)
from marraztu.loaders.images import (
    FORMATS_BY_MAGIC,
    check_picture_header,
    image_format,
    pictures_checked,
    rgb_array,
    unread_textures_note,
)
from marraztu.loaders.ply import binary_of_ascii, read_header
from marraztu.loaders.stl import HEADER_BYTES, TRIANGLE_BYTES
from marraztu.loaders.words import unheld_coordinate
from marraztu.model.build import build_mesh, by_largest, colour_bytes
from marraztu.model.geometry import holds_in_float32
from marraztu.model.mesh import MAX_MATERIALS, Mesh, MeshMaterial

Stage = Callable[[str], None]
# A glTF node places a mesh, so a small file can place one mesh a million times. No scene may place
# more triangles than the largest binary STL the viewer reads lists one by one.
MAX_PLACED_TRIANGLES = (MAX_FILE_BYTES - HEADER_BYTES) // TRIANGLE_BYTES
_NOT_FINITE = re.compile(rb"(?i)(?<![a-z])(?:[-+]?nan|[-+]?inf(?:inity)?)(?![a-z])")


# --- the readers of the registry -----------------------------------------------------------------
# trimesh's objects refer to one another (a mesh, its visuals, their caches), so its tables, and the
# file's bytes it keeps, wait for Python's cycle collector, which may not run for minutes. From
# COLLECT_AFTER_BYTES of file on (or this many faces read: a .gltf's buffers lie beside it), what
# reads through trimesh runs it once done: a collection takes some ms, which a scene file of
# thousands of small models would pay thousands of times. (After a refused file, the registry runs it.)
COLLECT_AFTER_FACES = 20_000
_Read = TypeVar("_Read")
# Per thread, what the read under way loaded through trimesh, weakly: what its collection must free.
_reading = threading.local()


def _frees_what_trimesh_held(read: Callable[..., _Read]) -> Callable[..., _Read]:
    """`read(path, ...)`, which reads through trimesh, then the collection that frees trimesh's objects."""
    @functools.wraps(read)
    def reading(path: Path, *args: Any, **options: Any) -> _Read:
        outer = getattr(_reading, "loaded", None)  # a read within a read (none does so yet) keeps its own list
        _reading.loaded = []
        try:
            result = read(path, *args, **options)  # its frame, the last plain reference to trimesh's scene, is gone
        finally:
            loaded, _reading.loaded = _reading.loaded, outer
        if getattr(result, "face_count", 0) >= COLLECT_AFTER_FACES or size_or_zero(path) >= COLLECT_AFTER_BYTES:
            _collect(loaded)
        return result
    return reading


def _collect(loaded: list[weakref.ref[Any]]) -> None:
    """Frees trimesh's scenes and meshes: the young generations hold them unless a collection during the
    read moved them on, and collecting those alone skips the whole heap (a notebook's may be large)."""
    gc.collect(1)
    if any(alive() is not None for alive in loaded):
        gc.collect()


def _watched(loaded: Any) -> Any:
    """trimesh's scene, its meshes noted as the read's to free."""
    watched = getattr(_reading, "loaded", None)
    if watched is not None:
        watched.extend(weakref.ref(item) for item in (loaded, *loaded.geometry.values()))
    return loaded


@_frees_what_trimesh_held
def load_ply(path: Path, stage: Stage | None = None) -> Mesh:
    data = read_model_bytes(path, stage)
    header = read_header(path, data)
    if header.count("face") == 0:
        raise LoadError(path, "the header declares no faces (a point cloud?): nothing to draw")
    text = data if header.encoding == "ascii" else None  # kept for a text body only, to name the line of a bad number
    if text is not None:
        data = binary_of_ascii(path, text, header)
    beside = _FilesBeside(path.parent, is_picture=lambda name: True)  # a PLY names its TextureFile only
    scene = _trimesh_load(path, data, "ply", beside)
    del data
    held = sum(_ply_vertices_read(geometry) for geometry in scene.geometry.values())
    if held != header.count("vertex"):
        raise LoadError(path, f"the header promises {header.count('vertex')} vertices, the file holds {held}")
    return _finish(path, scene, data=text, beside=beside)


@_frees_what_trimesh_held
def load_gltf(path: Path, stage: Stage | None = None) -> Mesh:
    """glTF (JSON beside its buffers) or GLB: every mesh with its node's transform, as one model."""
    data, file_type = read_model_bytes(path, stage), path.suffix.lower().lstrip(".")
    pictures = _gltf_pictures(path, data) if file_type == "gltf" else frozenset()  # a GLB's JSON is trimesh's to read
    beside = _FilesBeside(path.parent, is_picture=pictures.__contains__, uri=True)
    return _finish(path, _trimesh_load(path, data, file_type, beside), data=None, beside=beside)


# --- reading and checking ------------------------------------------------------------------------
def _trimesh_load(path: Path, data: bytes, file_type: str, beside: _FilesBeside | None = None) -> Any:
    """The file as a trimesh.Scene, each mesh as trimesh read it: trimesh reads every file as a scene,
    and joining one into a single mesh (force="mesh") copies and hashes every table. `beside` reads
    the files it names."""
    trimesh = _quiet_trimesh()
    try:
        with pictures_checked() as refused:  # the pictures trimesh has Pillow open, a glTF's own included
            loaded = _watched(trimesh.load(io.BytesIO(data), file_type=file_type, process=False, force="scene",
                                           resolver=beside))
        if beside is not None:
            beside.held_failures.extend(refused)
        return loaded
    except MemoryError:
        raise LoadError(path, "not enough memory to load this file") from None
    except LoadError as error:  # from `beside`: a file it names that trimesh cannot do without (a buffer)
        raise LoadError(path, f"'{error.path}', which it names, could not be read ({error.message})") from None
    except Exception as error:  # trimesh raises ValueError, KeyError, IndexError, struct.error, ... for bad files
        words = str(error).strip().splitlines()
        detail = f"{type(error).__name__}: {words[0][:160]}" if words else type(error).__name__
        raise LoadError(path, f"not a readable {file_type.upper()} file ({detail})") from None


@functools.cache
def _quiet_trimesh() -> Any:
    """trimesh, imported here, not at the top (only these formats need it, and it costs start-up time),
    its log kept off the terminal: with no handler configured, Python's last resort prints trimesh's
    warnings, tracebacks included, for what it drops (a picture it cannot read), which notes tell."""
    import trimesh

    log = logging.getLogger("trimesh")
    log.addHandler(logging.NullHandler())
    log.propagate = False
    return trimesh


class _FilesBeside:
    """The files a model names beside it (a glTF's buffers and pictures, a PLY's TextureFile), read for
    trimesh as its own resolver reads them: the name, then its last part, in the model's folder and
    never outside it. A glTF names them by URI, percent-encoded ('my%20buf.bin' is 'my buf.bin'). Read
    by read_file (no device, pipe or huge file); a picture only when its first bytes are PNG, JPEG or
    PPM, as every texture. trimesh drops a picture it cannot have; `failures` keeps why, for a note."""

    def __init__(self, folder: Path, is_picture: Callable[[str], bool], uri: bool = False) -> None:
        self.folder = folder
        self.is_picture = is_picture
        self.uri = uri
        self.tried: list[Path] = []  # every path looked at, read or not: no output may replace one
        self.failures: dict[str, str] = {}  # the name shown -> why it was not read
        self.held_failures: list[str] = []  # why a picture the file holds itself was not read

    def get(self, name: str) -> bytes:
        named = shown((unquote(name) if self.uri else name).strip())
        try:
            data = read_file(self._path(name, named))
            if self.is_picture(name) and image_format(data[:8]) is None:
                raise LoadError(named, f"not a PNG, JPEG or PPM picture (it starts with {data[:8]!r})")
            if self.is_picture(name):
                check_picture_header(named, data)
        except LoadError as error:
            self.failures.setdefault(named, error.message)
            raise LoadError(named, error.message) from None  # named as the file names it
        return data

    __getitem__ = get  # trimesh's glTF reader asks resolver[name]

    def _path(self, name: str, named: str) -> Path:
        # The name decoded; then as written, for a writer that left a '%' of the file's name unencoded.
        written = dict.fromkeys([unquote(name), name] if self.uri else [name])
        # From the folder, a leading slash too, as trimesh's own resolver does.
        candidates = [self.folder / candidate.lstrip("/") for text in written for candidate in spellings(text)]
        self.tried.extend(candidates)
        folder = same_file_key(self.folder)
        inside = [path for path in candidates if same_file_key(path).is_relative_to(folder)]  # links followed
        found = next((path for path in inside if is_there(path)), None)
        if found is None and candidates[0] not in inside:
            raise LoadError(named, "it lies outside the model's folder")
        if found is None and _looks_absolute(next(iter(written))):
            raise LoadError(named, "no such file in the model's folder (only that folder is read, not a whole path)")
        return found or candidates[0]  # not there: reading it says so

    def notes(self) -> list[str]:
        """One note of the pictures not read, as for an MTL's textures."""
        held = [f"a picture the file holds could not be read ({why}); the scene's texture is shown in its place"
                for why in self.held_failures[:1]]
        return unread_textures_note(list(self.failures.items())) + held


def _looks_absolute(name: str) -> bool:
    return name.startswith(("/", "\\")) or re.match(r"[A-Za-z]:[\\/]", name) is not None


def _gltf_pictures(path: Path, data: bytes) -> frozenset[str]:
    """The URIs of a .gltf's pictures (not its buffers', which may be named anything), its JSON checked
    first: trimesh, given text that is not JSON, looks for a file named model.gltf and says that is missing."""
    try:
        document = json.loads(data)  # from bytes: UTF-8, -16 or -32, as the glTF's JSON may be
    except json.JSONDecodeError as error:
        raise LoadError(path, f"not valid JSON: {error.msg} (column {error.colno})", line=error.lineno) from None
    except UnicodeDecodeError:
        raise LoadError(path, "not a glTF file: its JSON is not UTF-8 text") from None
    except RecursionError:
        raise LoadError(path, "not a glTF file: its JSON nests too deeply to read") from None
    except ValueError:  # an integer of thousands of digits, which Python will not read
        raise LoadError(path, "not a glTF file: its JSON holds a number too long to read") from None
    if not isinstance(document, dict):
        raise LoadError(path, "not a glTF file: its JSON is not an object of glTF's keys", line=1)
    return frozenset(_uris(document.get("images"))) - frozenset(_uris(document.get("buffers")))


def _uris(items: object) -> Iterator[str]:
    """The file URIs a glTF list of images or buffers gives (a data: URI holds its bytes itself)."""
    for item in items if isinstance(items, list) else ():
        uri = item.get("uri") if isinstance(item, dict) else None
        if isinstance(uri, str) and not uri.startswith("data:"):
            yield uri


def _ply_vertices_read(mesh: Any) -> int:
    """The vertices trimesh read from a PLY's vertex table: before it splits those whose faces give them
    several texture coordinates (MeshLab's texcoord lists), which would count as more."""
    table = getattr(mesh, "metadata", {}).get("_ply_raw", {}).get("vertex", {}).get("data")
    if isinstance(table, np.ndarray):
        return len(table)
    if isinstance(table, dict) and table:
        return len(next(iter(table.values())))
    return len(mesh.vertices)


def _line_of_first_non_finite(data: bytes) -> int | None:
    found = _NOT_FINITE.search(data)
    return None if found is None else line_at(data, found.start())


def _finish(path: Path, loaded: Any, data: bytes | None, beside: _FilesBeside | None = None) -> Mesh:
    """A file's Mesh; `data`, for a text format, lets a bad number be found by line; `beside` read what
    the file names beside it, and says what it could not read."""
    mesh = _mesh_of(path, path.stem, loaded, data, picture_formats=_PICTURE_FORMATS)
    if beside is None or not (beside.tried or beside.failures or beside.held_failures):
        return mesh
    return replace(mesh, warnings=(*beside.notes(), *mesh.warnings), read_beside=tuple(dict.fromkeys(beside.tried)))


# The pictures a file's material may show: those every texture may be (a glTF may embed any picture
# Pillow reads, and Pillow hands some, PostScript, to other programs). MPO: a camera's JPEG, as Pillow names it.
_PICTURE_FORMATS = frozenset({*FORMATS_BY_MAGIC.values(), "MPO"})


def mesh_of_trimesh(name: str, loaded: Any) -> Mesh:
    """A trimesh.Trimesh, or a trimesh.Scene's meshes each placed by its node, as a Mesh: for the
    programming interface, so what is wrong is a ValueError."""
    try:
        return _mesh_of(name, name, loaded, data=None, own_copy=True)
    except LoadError as error:
        raise ValueError(error.message) from None


@dataclass(frozen=True, eq=False)
class _Geometry:
    """One trimesh mesh's checked tables, read once however many nodes place it."""

    mesh: Any
    positions: np.ndarray
    faces: np.ndarray
    uvs: np.ndarray | None  # per vertex, NaN rows to derive
    colours: np.ndarray | None  # per vertex, RGB bytes


# A mesh and the transform of a node that places it (None: where it is).
Part = tuple[_Geometry, np.ndarray | None]


def _mesh_of(source: str | Path, name: str, loaded: Any, data: bytes | None, own_copy: bool = False,
             picture_formats: Collection[str] | None = None) -> Mesh:
    """One Mesh of every placed mesh, each keeping its uvs, vertex colours and material (base colour
    and texture), as an OBJ's groups keep theirs. Placed here, not by trimesh's to_geometry(), which
    packs every mesh's picture into one (recoloured) atlas and keeps one material. `own_copy`: the
    caller keeps `loaded` (the programming interface), so a mesh left where it is is copied too.
    `picture_formats`: the formats of picture Pillow opened that a material may show (None: any)."""
    parts = _placed_parts(source, loaded)
    sizes = [len(geometry.positions) for geometry, _ in parts]
    with np.errstate(all="ignore"):  # a transform of NaN or huge numbers: refused by _check_tables
        placed = [_placed_positions(geometry.positions, transform) for geometry, transform in parts]
        positions = placed[0] if len(placed) == 1 else np.concatenate(placed)
        if own_copy and positions is parts[0][0].positions:  # the caller's own table, unmoved
            positions = positions.copy()
        mirrored = _mirroring([transform for _, transform in parts])
    faces = _placed_faces([geometry.faces for geometry, _ in parts], mirrored, sizes)
    _check_tables(source, positions, faces, data)
    uvs = _joined([geometry.uvs for geometry, _ in parts], sizes, np.nan)  # NaN: derived
    colours = _joined([geometry.colours for geometry, _ in parts], sizes, 255)  # white: untinted
    materials, part_material, notes = _part_materials(name, parts, picture_formats)
    if any(getattr(getattr(geometry.mesh, "visual", None), "kind", None) == "face" for geometry, _ in parts):
        notes.append("colours given per face are not drawn (vertex colours are)")
    # One mesh's base colour is the model's; of several, each keeps its own, and one without takes the
    # viewer's rather than another mesh's.
    own = _material_of(parts[0][0].mesh) if len(parts) == 1 else None
    mesh = build_mesh(name=name, positions=positions, faces=faces, uvs=uvs, file_material=own, warnings=notes,
                      vertex_colours=colours, attributes_per_vertex=True)
    if not materials:
        return mesh
    part_faces = [len(geometry.faces) for geometry, _ in parts]
    return replace(mesh, materials=materials, face_material=np.repeat(np.array(part_material, np.int32), part_faces))


def _placed_parts(source: str | Path, loaded: Any) -> list[Part]:
    """A scene's meshes with the transforms of the nodes that place them (a mesh placed twice is two
    parts), counted before any is read; a mesh alone, where it is."""
    if not hasattr(loaded, "geometry"):
        return [(_geometry(source, loaded), None)]
    meshes = {name: geometry for name, geometry in loaded.geometry.items()
              if hasattr(geometry, "faces") and len(geometry.faces)}  # a mesh of no faces draws nothing
    if not meshes:
        raise LoadError(source, "the scene holds no triangle mesh: nothing to draw")
    try:
        placements = [loaded.graph[node] for node in loaded.graph.nodes_geometry]
    except Exception as error:  # a broken node graph (a cycle, say): trimesh's own words
        raise LoadError(source, f"cannot place the scene's meshes ({type(error).__name__}: {error})") from None
    placements = [(transform, name) for transform, name in placements if name in meshes]
    if not placements:
        raise LoadError(source, "no node of the scene places a triangle mesh: nothing to draw")
    _check_placed_size(source, [meshes[name] for _, name in placements])
    read = {name: _geometry(source, meshes[name]) for name in dict.fromkeys(name for _, name in placements)}
    return [(read[name], _moving(transform)) for transform, name in placements]


def _moving(transform: Any) -> np.ndarray | None:
    """A node's transform; None where it leaves its mesh where it is (a file of one mesh, usually)."""
    transform = np.asarray(transform, dtype=np.float64)
    return None if np.array_equal(transform, _IDENTITY) else transform


_IDENTITY = np.eye(4)


def _mirroring(transforms: list[np.ndarray | None]) -> np.ndarray:
    """Which transforms mirror: their determinants in one call, as a scene may have thousands."""
    mirrors = np.zeros(len(transforms), bool)
    moving = [at for at, transform in enumerate(transforms) if transform is not None]
    if moving:
        mirrors[moving] = np.linalg.det(np.stack([transforms[at][:3, :3] for at in moving])) < 0
    return mirrors


def _geometry(source: str | Path, mesh: Any) -> _Geometry:
    positions = np.asarray(mesh.vertices, dtype=np.float64).reshape(-1, 3)
    faces = np.asarray(mesh.faces, dtype=np.int64).reshape(-1, 3)
    if faces.size and (faces.min() < 0 or faces.max() >= len(positions)):  # checked before meshes are joined
        bad = int(faces.min()) if faces.min() < 0 else int(faces.max())
        raise LoadError(source, f"a face refers to vertex {bad}, but its mesh has {len(positions)}")
    return _Geometry(mesh, positions, faces, _vertex_uvs(mesh), _vertex_colours(mesh))


def _placed_faces(faces: list[np.ndarray], mirrored: np.ndarray, sizes: list[int]) -> np.ndarray:
    """The parts' faces as one table of indices into the joined positions. A mirroring transform turns
    the winding round: glTF asks for it to be turned back. One part left as it is: its own table."""
    if len(faces) == 1 and not mirrored[0]:
        return faces[0]
    return np.concatenate([(table[:, ::-1] if mirrors else table) + offset
                           for table, mirrors, offset in zip(faces, mirrored, np.cumsum([0, *sizes[:-1]]))])


def _placed_positions(positions: np.ndarray, transform: np.ndarray | None) -> np.ndarray:
    return positions if transform is None else positions @ transform[:3, :3].T + transform[:3, 3]


def _joined(tables: list[np.ndarray | None], sizes: list[int], fill: float) -> np.ndarray | None:
    """The parts' per-vertex tables as one, `fill` for a part without; None when no part has one."""
    given = [table for table in tables if table is not None]
    if not given:
        return None
    width, dtype = given[0].shape[1], given[0].dtype
    return np.concatenate([np.full((size, width), fill, dtype) if table is None else table
                           for table, size in zip(tables, sizes)])


def _part_materials(name: str, parts: list[Part], picture_formats: Collection[str] | None = None
                    ) -> tuple[tuple[MeshMaterial, ...], list[int], list[str]]:
    """The materials of the parts, each once, and per part its index among them (-1: no base colour
    or texture of its own, or past MAX_MATERIALS), and the notes. None at all for one untextured part:
    its base colour is the model's."""
    by_geometry: dict[int, int] = {}  # each mesh's material is found once, however often it is placed
    # Each picture read and hashed once, however many materials share it, as one array (the renderer
    # uploads it once), with its key: the shape and a hash of the RGB bytes drawn.
    textures: dict[int, tuple[np.ndarray | None, tuple[object, ...] | None]] = {}
    by_content: dict[tuple[object, ...], int] = {}
    materials: list[MeshMaterial] = []
    beyond = 0
    undrawn: list[str] = []  # why each picture that cannot be drawn is not
    for geometry, _ in parts:
        if id(geometry) in by_geometry:
            continue
        material = getattr(getattr(geometry.mesh, "visual", None), "material", None)
        values = _material_of(geometry.mesh)
        # A picture counts only where uvs address it; equal materials are one, copies included.
        picture = _picture(material) if geometry.uvs is not None else None
        if id(picture) not in textures:
            texture = None if picture is None else _drawn_picture(picture, picture_formats, undrawn)
            textures[id(picture)] = texture, None if texture is None else (texture.shape, hash(texture.tobytes()))
        texture, texture_key = textures[id(picture)]
        key = (_material_name(material), values and tuple(values.items()), texture_key)
        if key not in by_content:
            if texture is None and values is None:
                by_content[key] = -1
            elif len(materials) >= MAX_MATERIALS:
                by_content[key], beyond = -1, beyond + 1
            else:
                by_content[key] = len(materials)
                materials.append(MeshMaterial(key[0], values or {}, texture,
                                              None if texture is None else "base colour texture"))
        by_geometry[id(geometry)] = by_content[key]
    part_material = [by_geometry[id(geometry)] for geometry, _ in parts]
    notes = _undrawn_notes(undrawn)
    if len(parts) == 1 and materials and materials[0].texture is None:
        return (), part_material, notes
    materials = [replace(material, name=material.name or (name if len(materials) == 1 else f"{name} {number}"))
                 for number, material in enumerate(materials, start=1)]
    if beyond:
        notes.append(f"{MAX_MATERIALS + beyond} materials used; the meshes of all but the first {MAX_MATERIALS} "
                     "take the viewer's material")
    return tuple(materials), part_material, notes


def _drawn_picture(picture: Any, formats: Collection[str] | None, undrawn: list[str]) -> np.ndarray | None:
    """The picture's RGB bytes; None, and why in `undrawn`, for one of a format textures may not be or
    one Pillow cannot decode (a cut PNG: Pillow opens it, reading its first bytes only)."""
    found = getattr(picture, "format", None)  # Pillow's name for what it opened; None for a picture made in code
    if formats is not None and found is not None and found not in formats:
        undrawn.append(f"a {found} picture, not a PNG, JPEG or PPM one")
        return None
    texture = _texture(picture)
    if texture is None:
        undrawn.append("Pillow cannot decode it")
    return texture


def _undrawn_notes(undrawn: list[str]) -> list[str]:
    if not undrawn:
        return []
    if len(undrawn) == 1:
        return [f"a material's picture is not drawn ({undrawn[0]}); the scene's texture is shown in its place"]
    return [f"{len(undrawn)} materials' pictures are not drawn (the first: {undrawn[0]}); the scene's texture is "
            "shown in their place"]


_AUTOMATIC_NAME = re.compile(r"(?:material_?\d*)?")


def _material_name(material: Any) -> str:
    """The file's name for a material; empty for none, and for the ones trimesh makes up (material_0)."""
    name = str(getattr(material, "name", None) or "")
    return "" if _AUTOMATIC_NAME.fullmatch(name) else name


def _picture(material: Any) -> Any:
    """The material's picture as trimesh holds it: glTF's base colour texture, or trimesh's own image
    (an OBJ's map_Kd, a texture given to it), but not its stand-in for none."""
    picture = getattr(material, "baseColorTexture", None)
    if picture is None and not _stand_in_material(material):
        picture = getattr(material, "image", None)
    return picture


def _texture(picture: Any) -> np.ndarray | None:
    try:
        return rgb_array(picture if isinstance(picture, Image.Image) else Image.fromarray(np.asarray(picture)))
    except Exception:  # a picture Pillow cannot convert: the colours alone, as for a missing map_Kd
        return None


def _stand_in_material(material: Any) -> bool:
    """trimesh gives uvs without a picture a material whose image is 2x2 pixels of one colour
    (trimesh.visual.material.empty_material): no texture, not a grey one."""
    image = getattr(material, "image", None)
    if not isinstance(image, Image.Image) or image.size != (2, 2):
        return False
    pixels = np.asarray(image).reshape(4, -1)
    return bool((pixels == pixels[0]).all())


def _check_tables(path: str | Path, positions: np.ndarray, faces: np.ndarray, data: bytes | None) -> None:
    """Faces, and positions the GPU can hold (each mesh's indices are checked as it is read)."""
    if len(faces) == 0:
        raise LoadError(path, "no faces")
    if not holds_in_float32(positions):
        line = _line_of_first_non_finite(data) if data is not None else None
        raise unheld_coordinate(path, line)


def _check_placed_size(path: str | Path, placed: list[Any]) -> None:
    """Counted from the node graph before any mesh is copied into place: triangles, and vertices too
    (a mesh of many vertices and one face, placed many times, would otherwise pass)."""
    triangles = sum(len(mesh.faces) for mesh in placed)
    vertices = sum(len(mesh.vertices) for mesh in placed)
    if triangles > MAX_PLACED_TRIANGLES or vertices > 3 * MAX_PLACED_TRIANGLES:
        raise LoadError(path, f"the scene places its meshes {len(placed)} times, {triangles} triangles and "
                              f"{vertices} vertices in all: more than the {MAX_PLACED_TRIANGLES} triangles (and three "
                              "vertices each) the viewer draws from one model")


def _vertex_uvs(mesh: Any) -> np.ndarray | None:
    """The texture coordinates, one row per vertex (build_mesh derives the rows that are not finite,
    as for an OBJ corner without vt)."""
    uv = getattr(getattr(mesh, "visual", None), "uv", None)
    if uv is None or len(uv) != len(mesh.vertices):
        return None
    table = np.asarray(uv, dtype=np.float64)
    return table if table.ndim == 2 and table.shape[1] == 2 else None


def _material_of(mesh: Any) -> dict[str, object] | None:
    """The base colour of a glTF material as Kd: the quantity the lighting equation reads."""
    material = getattr(getattr(mesh, "visual", None), "material", None)
    colour = getattr(material, "baseColorFactor", None)
    if colour is None:
        return None
    rgb = np.asarray(colour, dtype=np.float64).reshape(-1)[:3]
    rgb = by_largest(rgb)  # trimesh keeps glTF colours as bytes
    return {"kd": tuple(float(c) for c in rgb)} if np.isfinite(rgb).all() else None


def _vertex_colours(mesh: Any) -> np.ndarray | None:
    """The file's colour per vertex (PLY's red/green/blue, glTF's COLOR_0) as RGB bytes, if any."""
    visual = getattr(mesh, "visual", None)
    if getattr(visual, "kind", None) == "vertex":
        colours = np.asarray(visual.vertex_colors)
    else:  # glTF's COLOR_0 beside a material: trimesh keeps it as the file gives it, a vertex attribute
        attributes = getattr(visual, "vertex_attributes", None)
        if attributes is None or "color" not in attributes:
            return None
        colours = np.asarray(attributes["color"])
        if colours.dtype == np.uint16:  # glTF's normalized shorts
            colours = (colours >> 8).astype(np.uint8)
    try:
        return colour_bytes(colours, len(mesh.vertices))
    except ValueError:  # not one RGB or RGBA row per vertex of bytes or 0..1: not trusted, not drawn
        return None
