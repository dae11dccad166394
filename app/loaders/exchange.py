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

A PLY's body is first made the binary body trimesh reads (ply.py); a glTF's JSON is first checked, its
placements counted before trimesh builds a node for each, and made again where trimesh is to read it
otherwise (the gltf package).
"""

from __future__ import annotations

import functools
import gc
import io
import logging
import re
import threading
import warnings
import weakref
from collections.abc import Callable, Collection, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, TypeVar
from urllib.parse import unquote

import numpy as np
from PIL import Image

from marraztu.errors import LoadError, error_words
from marraztu.loaders.files import (
    COLLECT_AFTER_BYTES,
    GIT_LFS_POINTER_BYTES,
    MAX_FILE_BYTES,
    bom_length,
    git_lfs_pointer_words,
    is_there,
    line_at,
    read_file,
    read_model_bytes,
    same_file_key,
    shown,
    size_or_zero,
    spellings,
)
from marraztu.loaders.gltf import (
    GltfReferences,
    as_trimesh_reads,
    buffer_bytes,
    check_geometry_readable,
    check_one_parent_each,
    declared_part,
    glb_document,
    gltf_counts,
    gltf_document,
    gltf_pictures,
    morphed_shapes,
    numbered_material,
    sampled_materials,
    sceneless_words,
    skinned_placements,
    undrawn_primitive_notes,
    unfaithful_notes,
)
from marraztu.loaders.images import (
    FORMATS_BY_MAGIC,
    check_picture,
    image_format,
    not_a_picture,
    picture_rgb,
    picture_size,
    picture_size_refusal,
    pictures_checked,
    unread_textures_note,
)
from marraztu.loaders.ply import STRIPS, binary_of_ascii, check_triangles, read_header, vertices_and_faces
from marraztu.loaders.stl import HEADER_BYTES, TRIANGLE_BYTES
from marraztu.loaders.words import unheld_coordinate
from marraztu.model.build import FACE_COLOURS_NOTE, build_mesh, checked_vertex_rows, colour_bytes, colour_fractions
from marraztu.model.geometry import holds_in_float32
from marraztu.model.mesh import (
    MAX_MATERIALS,
    Mesh,
    MeshMaterial,
    counted,
    polygon_corners_of_fans,
    with_picture_as_colour,
)
from marraztu.model.sampling import DEFAULT_SAMPLING, TextureSampling

Stage = Callable[[str], None]
# A glTF node places a mesh, so a small file can place one mesh a million times. No scene may place
# more triangles than the largest binary STL the viewer reads lists one by one.
MAX_PLACED_TRIANGLES = (MAX_FILE_BYTES - HEADER_BYTES) // TRIANGLE_BYTES
# Each (node, primitive) placed costs trimesh a node of its graph and this reader a part, some 2 KB and
# 40 us, whatever its triangles: 400 nodes placing a mesh of 400 primitives are 160,000 placements from
# 23 KB. Real scenes place hundreds to thousands of meshes: past this many, a file is refused unread.
MAX_PLACEMENTS = 1 << 16
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
    """trimesh's scene, its meshes noted as the read's to free (each caller reads under
    _frees_what_trimesh_held, which keeps the list)."""
    _reading.loaded.extend(weakref.ref(item) for item in (loaded, *loaded.geometry.values()))
    return loaded


@_frees_what_trimesh_held
def load_ply(path: Path, stage: Stage | None = None) -> Mesh:
    data = read_model_bytes(path, stage)
    if bom := bom_length(data):  # Notepad's mark before the header: such a rare file costs one copy without it
        data = data[bom:]
    header = read_header(path, data)
    if header.count("face") == 0 and header.count(STRIPS) == 0:
        raise LoadError(path, "the header declares no faces (a point cloud?): nothing to draw")
    text = data if header.encoding == "ascii" else None  # kept for a text body only, to name the line of a bad number
    face_sizes, notes = None, ()
    if text is not None:
        data, face_sizes, notes = binary_of_ascii(path, text, header, MAX_PLACED_TRIANGLES)
        header = read_header(path, data)
    data, binary_face_sizes, binary_notes = vertices_and_faces(path, data, header, MAX_PLACED_TRIANGLES)
    if text is None:  # (an ASCII body's polygons are fanned already: the binary one holds triangles)
        face_sizes, notes = binary_face_sizes, binary_notes
    # Fanned faces were counted before they were made; these are all the triangles trimesh would build.
    check_triangles(path, read_header(path, data).count("face"), MAX_PLACED_TRIANGLES)
    beside = _FilesBeside(path.parent, is_picture=lambda name: True)  # a PLY names its TextureFile only
    scene = _trimesh_load(path, data, "ply", beside)
    del data
    held = sum(_ply_vertices_read(geometry) for geometry in scene.geometry.values())
    if held != header.count("vertex"):
        raise LoadError(path, f"the header promises {header.count('vertex')} vertices, the file holds {held}")
    return _finish(path, scene, data=text, beside=beside, face_sizes=face_sizes, notes=list(notes))


@_frees_what_trimesh_held
def load_gltf(path: Path, stage: Stage | None = None) -> Mesh:
    """glTF (JSON beside its buffers) or GLB: every mesh with its node's transform, as one model."""
    data, file_type = read_model_bytes(path, stage), path.suffix.lower().lstrip(".")
    document = gltf_document(path, data) if file_type == "gltf" else glb_document(path, data)
    pictures = gltf_pictures(document) if file_type == "gltf" else frozenset()  # a GLB holds its own
    check_geometry_readable(path, document)  # first: compressed accessors are bytes a decoder makes, not zeros
    least_bytes = buffer_bytes(document)
    held = len(data) + sum(least_bytes.values())
    GltfReferences(path, document, held=held).check()
    check_one_parent_each(path, document)
    counts, undrawn = gltf_counts(document), undrawn_primitive_notes(document)
    if counts is not None:  # before trimesh builds a node and a mesh per placement
        _check_placed_counts(path, *counts, undrawn=sceneless_words(document) + undrawn)
    shapes, sampled = morphed_shapes(document, held), sampled_materials(document)
    skins = skinned_placements(document, held, shapes)
    notes = [*shapes.notes, *skins.notes, *unfaithful_notes(document, undrawn)]
    beside = _FilesBeside(path.parent, is_picture=pictures.__contains__, uri=True, least_bytes=least_bytes)
    data = as_trimesh_reads(path, data if file_type == "gltf" else declared_part(data), document, file_type,
                            functools.partial(_read_named, path, beside), number_materials=bool(sampled),
                            shapes=shapes, skins=skins, notes=notes)
    del document
    return _finish(path, _trimesh_load(path, data, file_type, beside), data=None, beside=beside, notes=notes,
                   sampled=sampled)


# --- reading and checking ------------------------------------------------------------------------
def _trimesh_load(path: Path, data: bytes, file_type: str, beside: _FilesBeside) -> Any:
    """The file as a trimesh.Scene, each mesh as trimesh read it: trimesh reads every file as a scene,
    and joining one into a single mesh (force="mesh") copies and hashes every table. `beside` reads
    the files it names."""
    trimesh = _quiet_trimesh()
    try:
        # The pictures trimesh has Pillow open (a glTF's own too) checked; numpy's and Pillow's warnings of
        # what trimesh does with NaN or huge values kept off the terminal: the checks after it say what is wrong.
        with pictures_checked() as refused, np.errstate(all="ignore"), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            loaded = _watched(trimesh.load(io.BytesIO(data), file_type=file_type, process=False, force="scene",
                                           resolver=beside))
        beside.held_failures.extend(refused)
        beside.read.clear()  # trimesh has made its tables of them
        return loaded
    except MemoryError:
        raise LoadError(path, "not enough memory to load this file") from None
    except LoadError as error:  # from `beside`: a file it names that trimesh cannot do without (a buffer)
        raise _unread_named_file(path, error) from None
    except Exception as error:  # trimesh raises ValueError, KeyError, IndexError, struct.error, ... for bad files
        raise LoadError(path, f"not a readable {file_type.upper()} file ({error_words(error)})") from None


def _unread_named_file(path: Path, error: LoadError) -> LoadError:
    """The model's error of a file it names that cannot be read, and that it cannot do without."""
    return LoadError(path, f"'{error.path}', which it names, could not be read ({error.message})")


def _read_named(path: Path, beside: _FilesBeside, name: str) -> bytes:
    """A file the model at `path` names, read by `beside` before trimesh reads the model (a glTF's
    buffer, to apply a sparse accessor's values)."""
    try:
        return beside.get(name)
    except LoadError as error:
        raise _unread_named_file(path, error) from None


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
    by read_file (no device, pipe or huge file), none that is a Git LFS pointer; a picture only when its
    first bytes are PNG, JPEG or PPM, as every texture. trimesh drops a picture it cannot have; `failures`
    keeps why, for a note."""

    def __init__(self, folder: Path, is_picture: Callable[[str], bool], uri: bool = False,
                 least_bytes: dict[str, int] | None = None) -> None:
        self.folder = folder
        self.folder_key: Path | None = None  # the folder resolved, once: not again for each of thousands of names
        self.least_bytes = least_bytes or {}  # a glTF buffer's byteLength, by its URI
        self.is_picture = is_picture
        self.uri = uri
        self.tried: list[Path] = []  # every path looked at, read or not: no output may replace one
        self.failures: dict[str, str] = {}  # the name shown -> why it was not read
        self.held_failures: list[str] = []  # why a picture the file holds itself was not read
        self.read: dict[Path, bytes] = {}  # each file once, however many names give it: trimesh keeps each answer

    def get(self, name: str) -> bytes:
        named = shown((unquote(name) if self.uri else name).strip())
        try:
            data = self._read(self._path(name, named))
            what = "picture" if self.is_picture(name) else "buffer"
            pointer = git_lfs_pointer_words(data[:GIT_LFS_POINTER_BYTES], what)
            if pointer is not None:  # else read as the buffer: its text drawn as coordinates, or 'holds 128 bytes'
                raise LoadError(named, pointer)
            if len(data) < self.least_bytes.get(name, 0):  # trimesh's reader asserts, in no words
                raise LoadError(named, f"it holds {len(data)} bytes, where the model says {self.least_bytes[name]}")
            if self.is_picture(name) and image_format(data[:8]) is None:
                raise LoadError(named, not_a_picture(data[:GIT_LFS_POINTER_BYTES]))
            if self.is_picture(name):
                check_picture(named, data)  # its header and size, before trimesh has Pillow decode it
        except LoadError as error:
            self.failures.setdefault(named, error.message)
            raise LoadError(named, error.message) from None  # named as the file names it
        return data

    __getitem__ = get  # trimesh's glTF reader asks resolver[name]

    def _read(self, path: Path) -> bytes:
        key = same_file_key(path)
        if key not in self.read:
            self.read[key] = read_file(path)
        return self.read[key]

    def _path(self, name: str, named: str) -> Path:
        # The name decoded; then as written, for a writer that left a '%' of the file's name unencoded.
        written = dict.fromkeys([unquote(name), name] if self.uri else [name])
        # From the folder, a leading slash too, as trimesh's own resolver does.
        candidates = [self.folder / candidate.lstrip("/") for text in written for candidate in spellings(text)]
        self.tried.extend(candidates)
        folder = self.folder_key = self.folder_key or same_file_key(self.folder)
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


def _ply_vertex_table(mesh: Any) -> dict[str, np.ndarray]:
    """A PLY's vertex table as trimesh read it, before it splits vertices for MeshLab's per-corner
    texture coordinates: each property's values, one a row; empty for another file."""
    table = getattr(mesh, "metadata", {}).get("_ply_raw", {}).get("vertex", {}).get("data")
    if isinstance(table, np.ndarray) and table.dtype.names:
        table = {name: table[name] for name in table.dtype.names}
    if not isinstance(table, dict):
        return {}
    return {name: np.asarray(values).reshape(len(values), -1)[:, 0] for name, values in table.items()}


def _ply_vertices_read(mesh: Any) -> int:
    """The vertices trimesh read from a PLY's vertex table: before it splits those whose faces give them
    several texture coordinates (MeshLab's texcoord lists), which would count as more."""
    columns = _ply_vertex_table(mesh)
    return len(next(iter(columns.values()))) if columns else len(mesh.vertices)


def _line_of_first_non_finite(data: bytes) -> int | None:
    found = _NOT_FINITE.search(data)
    return None if found is None else line_at(data, found.start())


def _finish(path: Path, loaded: Any, data: bytes | None, beside: _FilesBeside | None = None,
            face_sizes: np.ndarray | None = None, notes: list[str] | None = None, sampled: Sampled = ()) -> Mesh:
    """A file's Mesh; `data`, for a text format, lets a bad number be found by line; `beside` read what
    the file names beside it, and says what it could not read; `face_sizes`, the polygons a PLY's
    triangles were fanned from; `notes`, what was found of the file before trimesh read it; `sampled`, a
    glTF's materials by number (gltf.sampled_materials)."""
    mesh = _mesh_of(path, path.stem, loaded, data, picture_formats=_PICTURE_FORMATS, finite_uvs=True,
                    face_sizes=face_sizes, sampled=sampled)
    if notes:
        mesh = replace(mesh, warnings=(*notes, *mesh.warnings))
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
    notes: tuple[str, ...] = ()  # what its tables say of themselves (PLY's float colours held to 0..1)


# A mesh and the transform of a node that places it (None: where it is).
Part = tuple[_Geometry, np.ndarray | None]
# A glTF's materials by number, each its name and its picture's sampling, where trimesh read them numbered.
Sampled = tuple[tuple[str, TextureSampling], ...]


def _mesh_of(source: str | Path, name: str, loaded: Any, data: bytes | None, own_copy: bool = False,
             picture_formats: Collection[str] | None = None, finite_uvs: bool = False,
             face_sizes: np.ndarray | None = None, sampled: Sampled = ()) -> Mesh:
    """One Mesh of every placed mesh, each keeping its uvs, vertex colours and material (base colour
    and texture), as an OBJ's groups keep theirs. Placed here, not by trimesh's to_geometry(), which
    packs every mesh's picture into one (recoloured) atlas and keeps one material. `own_copy`: the
    caller keeps `loaded` (the programming interface), so a mesh left where it is is copied too.
    `picture_formats`: the formats of picture Pillow opened that a material may show (None: any).
    `finite_uvs`: a texture coordinate that is not a finite number is refused, as an OBJ's is (the
    programming interface derives it, as build_mesh does). `face_sizes`: the polygons whose fans the
    one mesh's triangles are, made polygons again. `sampled`: a glTF's materials by number."""
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
    if finite_uvs:
        _check_uvs(source, parts, data)
    uvs = _joined([geometry.uvs for geometry, _ in parts], sizes, np.nan)  # NaN: derived
    colours = _joined([geometry.colours for geometry, _ in parts], sizes, 255)  # white: untinted
    materials, part_material, notes = _part_materials(name, parts, picture_formats, sampled)
    notes += dict.fromkeys(note for geometry, _ in parts for note in geometry.notes)
    if any(getattr(getattr(geometry.mesh, "visual", None), "kind", None) == "face" for geometry, _ in parts):
        notes.append(FACE_COLOURS_NOTE)
    # One mesh's base colour is the model's; of several, each keeps its own, and one without takes the
    # viewer's rather than another mesh's.
    own = _material_of(parts[0][0].mesh) if len(parts) == 1 else None
    if face_sizes is not None and (len(parts) != 1 or len(faces) != int((face_sizes - 2).sum())):
        face_sizes = None  # a guard, never met: trimesh keeps a PLY's triangles, in order; else drawn as they are
    polygons = faces if face_sizes is None else polygon_corners_of_fans(faces, face_sizes)
    mesh = build_mesh(name=name, positions=positions, faces=polygons, uvs=uvs, file_material=own, warnings=notes,
                      vertex_colours=colours, attributes_per_vertex=True, face_sizes=face_sizes)
    if not materials:
        return mesh
    part_faces = [len(geometry.faces) for geometry, _ in parts] if face_sizes is None else [len(face_sizes)]
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
    graph = loaded.graph
    placed = [(node, graph.transforms.node_data[node].get("geometry")) for node in graph.nodes_geometry]
    placed = [(node, name) for node, name in placed if name in meshes]
    if not placed:
        raise LoadError(source, "no node of the scene places a triangle mesh: nothing to draw")
    _check_placed_size(source, [meshes[name] for _, name in placed])
    try:
        transforms = _moving(_world_transforms(graph, [node for node, _ in placed]))
    except Exception as error:  # a broken node graph (loops are refused before): trimesh's own words
        raise LoadError(source, f"cannot place the scene's meshes ({type(error).__name__}: {error})") from None
    read = {name: _geometry(source, meshes[name]) for name in dict.fromkeys(name for _, name in placed)}
    return [(read[name], transform) for (_, name), transform in zip(placed, transforms)]


def _world_transforms(graph: Any, nodes: list[Any]) -> list[np.ndarray]:
    """Each node's transform from the scene's base frame, as trimesh's graph[node] makes it (an edge from
    the base as it is; else the product down the path of the matrices that are not the identity; a
    nearly rigid one repaired), from one walk down the forest: graph[node] multiplies the chain above
    each node anew, numpy ordering its product in the cube of its length (7.5 s for one mesh 400 deep)."""
    with np.errstate(all="ignore"):  # NaN or huge matrices: refused once placed, by _check_tables
        products = _walked_products(graph.transforms, graph.base_frame)
        found = [_from_base(graph, products, node) for node in nodes]
        return _repaired(found, getattr(graph, "repair_rigid", None))


def _from_base(graph: Any, products: dict[Any, np.ndarray | None], node: Any) -> np.ndarray:
    """One node's transform from the base, before any repair, as trimesh's graph.get makes it."""
    base, edges = graph.base_frame, graph.transforms.edge_data
    if node == base:
        return _IDENTITY
    if (base, node) in edges:  # trimesh takes an edge from the base as it is
        return edges[(base, node)]["matrix"]
    if node in products:
        product = products[node]
        return _IDENTITY if product is None else product
    return graph[node][0]  # not below the base: trimesh's own path, or its error


def _walked_products(forest: Any, base: Any) -> dict[Any, np.ndarray | None]:
    """Every node below `base` with the product of the matrices on its path from it that are not the
    identity (None: none is), each node's from its parent's, once."""
    children: dict[Any, list[Any]] = {}
    for child, parent in forest.parents.items():
        children.setdefault(parent, []).append(child)
    products: dict[Any, np.ndarray | None] = {base: None}
    waiting = [base]
    while waiting:
        parent = waiting.pop()
        for child in children.get(parent, ()):
            if child not in products:  # a forest's node has one parent: a cycle through the base stops here
                products[child] = _then(products[parent], forest.edge_data.get((parent, child), {}).get("matrix"))
                waiting.append(child)
    return products


def _then(above: np.ndarray | None, matrix: Any) -> np.ndarray | None:
    """The product of the path down to a node from its parent's: trimesh leaves out what is within 1e-8
    of the identity (NaN too)."""
    if matrix is None or not np.abs(np.asarray(matrix, dtype=np.float64) - _IDENTITY).max() > 1e-8:
        return above
    return matrix if above is None else above @ matrix


def _repaired(matrices: list[np.ndarray], most: float | None) -> list[np.ndarray]:
    """The matrices with trimesh's repair of one that is rigid but for rounding (what graph[node] does),
    found for all at once: a scene may place thousands."""
    if most is None or not matrices:
        return matrices
    from trimesh.transformations import fix_rigid

    turns = np.stack([np.asarray(matrix, dtype=np.float64) for matrix in matrices])[:, :3, :3]
    with np.errstate(all="ignore"):
        off = np.abs(turns @ turns.transpose(0, 2, 1) - np.eye(3)).max(axis=(1, 2))
    mended = set(np.flatnonzero((off > 1e-13) & (off < most)).tolist())
    return [fix_rigid(matrix, max_deviance=most) if at in mended else matrix for at, matrix in enumerate(matrices)]


def _moving(transforms: list[np.ndarray]) -> list[np.ndarray | None]:
    """The nodes' transforms; None for one that leaves its mesh where it is (a file of one mesh, usually)."""
    stacked = np.stack([np.asarray(transform, dtype=np.float64) for transform in transforms])
    still = (stacked == _IDENTITY).all(axis=(1, 2))
    return [None if unmoved else transform for transform, unmoved in zip(stacked, still)]


_IDENTITY = np.eye(4)


def _mirroring(transforms: list[np.ndarray | None]) -> np.ndarray:
    """Which transforms mirror: their determinants in one call, as a scene may have thousands."""
    mirrors = np.zeros(len(transforms), bool)
    moving = [at for at, transform in enumerate(transforms) if transform is not None]
    if moving:
        mirrors[moving] = np.linalg.det(np.stack([transforms[at][:3, :3] for at in moving])) < 0
    return mirrors


def _geometry(source: str | Path, mesh: Any) -> _Geometry:
    positions = _rows_of_three(source, mesh.vertices, "vertices").astype(np.float64, copy=False)
    faces = _rows_of_three(source, mesh.faces, "faces")
    def refusal(value: int, corner: int) -> str:
        return f"face {corner // 3} refers to vertex {value}, but its mesh has {len(positions)}"

    try:  # a mesh given in code may hold anything; trimesh's files hold int64. Before meshes are joined
        faces = checked_vertex_rows(faces, len(positions), refusal, "its faces must be whole numbers")
    except ValueError as error:
        raise LoadError(source, str(error)) from None
    return _Geometry(mesh, positions, faces, _vertex_uvs(mesh), _vertex_colours(mesh), _ply_colour_notes(source, mesh))


def _rows_of_three(source: str | Path, values: Any, what: str) -> np.ndarray:
    """A trimesh-like mesh's vertices or faces, (N, 3) real numbers (faces as triangles, as trimesh's)."""
    try:
        table = np.asarray(values)
    except (ValueError, TypeError):  # ragged rows
        raise LoadError(source, f"its {what} are not a table of numbers") from None
    if table.size == 0:
        return table.reshape(0, 3).astype(np.float64)
    if table.ndim != 2 or table.shape[1] != 3 or table.dtype.kind not in "iubf":
        raise LoadError(source, f"its {what} must be rows of 3 real numbers, not {table.dtype} of shape {table.shape}")
    return table


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


def _part_materials(name: str, parts: list[Part], picture_formats: Collection[str] | None = None,
                    sampled: Sampled = ()) -> tuple[tuple[MeshMaterial, ...], list[int], list[str]]:
    """The materials of the parts, each once, and per part its index among them (-1: no base colour
    or texture of its own, or past MAX_MATERIALS), and the notes. None at all for one untextured part:
    its base colour is the model's. `sampled`: a glTF's materials by number, where trimesh read them so."""
    by_geometry: dict[int, int] = {}  # each mesh's material is found once, however often it is placed
    # Each picture read and hashed once, however many materials share it, as one array (the renderer
    # uploads it once), with its key: the shape and a hash of the RGB bytes drawn.
    textures: dict[int, tuple[np.ndarray | None, tuple[object, ...] | None]] = {}
    by_content: dict[tuple[object, ...], int] = {}
    materials: list[MeshMaterial] = []
    beyond = 0
    undrawn: list[str] = []  # why each picture that cannot be drawn is not
    unaddressed: set[int] = set()  # the materials whose picture a mesh without uvs left out, each told once
    for geometry, _ in parts:
        if id(geometry) in by_geometry:
            continue
        material = getattr(getattr(geometry.mesh, "visual", None), "material", None)
        values = _material_of(geometry.mesh)
        # A picture counts only where uvs address it; equal materials are one, copies included.
        picture = _addressed_picture(material, geometry, unaddressed, undrawn)
        if id(picture) not in textures:
            texture = None if picture is None else _drawn_picture(picture, picture_formats, undrawn)
            textures[id(picture)] = texture, None if texture is None else (texture.shape, hash(texture.tobytes()))
        texture, texture_key = textures[id(picture)]
        values = with_picture_as_colour(values or {}, texture is not None) or None
        own_name, sampling = _name_and_sampling(material, sampled)
        sampling = DEFAULT_SAMPLING if texture is None else sampling
        key = (own_name, values and tuple(values.items()), texture_key, sampling)
        if key not in by_content:
            if texture is None and values is None:
                by_content[key] = -1
            elif len(materials) >= MAX_MATERIALS:
                by_content[key], beyond = -1, beyond + 1
            else:
                by_content[key] = len(materials)
                materials.append(MeshMaterial(own_name, values or {}, texture,
                                              None if texture is None else "base colour texture", sampling))
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


def _addressed_picture(material: Any, geometry: _Geometry, unaddressed: set[int], undrawn: list[str]) -> Any:
    """The material's picture where the mesh's uvs address it; None for a mesh without uvs, and why in
    `undrawn`, once a material (a glTF primitive with TEXCOORD_1 alone: trimesh reads TEXCOORD_0)."""
    picture = _picture(material)
    if picture is None or geometry.uvs is not None:
        return picture
    if id(material) not in unaddressed:
        unaddressed.add(id(material))
        undrawn.append("its mesh has no texture coordinates")
    return None


def _drawn_picture(picture: Any, formats: Collection[str] | None, undrawn: list[str]) -> np.ndarray | None:
    """The picture's RGB bytes; None, and why in `undrawn`, for one of a format textures may not be or
    one Pillow cannot decode (a cut PNG: Pillow opens it, reading its first bytes only)."""
    found = getattr(picture, "format", None)  # Pillow's name for what it opened; None for a picture made in code
    if formats is not None and found is not None and found not in formats:
        undrawn.append(f"a {found} picture, not a PNG, JPEG or PPM one")
        return None
    refusal = picture_size_refusal(*picture_size(picture))
    if refusal is not None:  # before it is decoded
        undrawn.append(refusal)
        return None
    try:
        return picture_rgb(picture)
    except ValueError as error:  # a picture made in code that cannot be drawn: why, in its words
        undrawn.append(str(error))
    except Exception:  # a file Pillow opened from its first bytes and cannot decode
        undrawn.append("Pillow cannot decode it")
    return None


def _undrawn_notes(undrawn: list[str]) -> list[str]:
    if not undrawn:
        return []
    if len(undrawn) == 1:
        return [f"a material's picture is not drawn ({undrawn[0]}); the scene's texture is shown in its place"]
    return [f"{len(undrawn)} materials' pictures are not drawn (the first: {undrawn[0]}); the scene's texture is "
            "shown in their place"]


_AUTOMATIC_NAME = re.compile(r"(?:material_?\d*)?")


def _name_and_sampling(material: Any, sampled: Sampled) -> tuple[str, TextureSampling]:
    """The file's name for a material (empty for none, and for the ones trimesh makes up: material_0)
    and how its picture is sampled: a numbered glTF material's own, else the default."""
    name = str(getattr(material, "name", None) or "")
    number = numbered_material(name) if sampled else None
    name, sampling = (name, DEFAULT_SAMPLING) if number is None else sampled[number]
    return "" if _AUTOMATIC_NAME.fullmatch(name) else name, sampling


def _picture(material: Any) -> Any:
    """The material's picture as trimesh holds it: glTF's base colour texture, or trimesh's own image
    (an OBJ's map_Kd, a texture given to it), but not its stand-in for none."""
    picture = getattr(material, "baseColorTexture", None)
    if picture is None and not _stand_in_material(material):
        picture = getattr(material, "image", None)
    return picture


def _stand_in_material(material: Any) -> bool:
    """trimesh gives uvs without a picture a material whose image is 2x2 pixels of one colour
    (trimesh.visual.material.empty_material): no texture, not a grey one. It is made in code, so
    Pillow names no format; a file's own 2x2 picture of one colour is drawn."""
    image = getattr(material, "image", None)
    if not isinstance(image, Image.Image) or image.size != (2, 2) or image.format is not None:
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


def _check_uvs(path: str | Path, parts: list[Part], data: bytes | None) -> None:
    """A file's texture coordinates, each mesh's once: NaN or infinite ones are the file's error (trimesh
    reads them as they are), not coordinates to derive."""
    tables = {id(geometry): geometry.uvs for geometry, _ in parts if geometry.uvs is not None}
    if not all(np.isfinite(table).all() for table in tables.values()):
        line = _line_of_first_non_finite(data) if data is not None else None
        raise LoadError(path, "a texture coordinate is not a finite number", line=line)
    if not all(holds_in_float32(table) for table in tables.values()):  # a PLY's doubles: as an OBJ's vt
        raise LoadError(path, "a texture coordinate is too large: the GPU's 32-bit numbers end at 3.4e38")


def _check_placed_size(path: str | Path, placed: list[Any]) -> None:
    """Counted from the node graph before any mesh is copied into place: triangles, and vertices too
    (a mesh of many vertices and one face, placed many times, would otherwise pass)."""
    triangles = sum(len(mesh.faces) for mesh in placed)
    vertices = sum(len(mesh.vertices) for mesh in placed)
    _check_placed_counts(path, len(placed), triangles, vertices)


def _check_placed_counts(path: str | Path, placements: int, triangles: int, vertices: int,
                         undrawn: Sequence[str] = ()) -> None:
    """Refuses a scene of more placements, or of more triangles or vertices placed, than a model may hold,
    and one that places no triangle (a glTF's meshes no node places are not handed to trimesh), saying
    which of its primitives are `undrawn` (points, lines)."""
    if triangles == 0:
        why = f" ({'; '.join(undrawn)})" if undrawn else ""
        raise LoadError(path, f"no node of the scene places a triangle mesh: nothing to draw{why}")
    if triangles > MAX_PLACED_TRIANGLES or vertices > 3 * MAX_PLACED_TRIANGLES:
        raise LoadError(path, f"the scene places its meshes {placements} times, {triangles} triangles and "
                              f"{vertices} vertices in all: more than the {MAX_PLACED_TRIANGLES} triangles (and three "
                              "vertices each) the viewer draws from one model")
    if placements > MAX_PLACEMENTS:
        raise LoadError(path, f"the scene places its meshes {placements} times (nodes times primitives): more than "
                              f"the {MAX_PLACEMENTS} placements the viewer reads from one model")


def _vertex_uvs(mesh: Any) -> np.ndarray | None:
    """The texture coordinates, one row per vertex (build_mesh derives the rows that are not finite,
    as for an OBJ corner without vt)."""
    uv = getattr(getattr(mesh, "visual", None), "uv", None)
    if uv is None or len(uv) != len(mesh.vertices):
        return None
    table = np.asarray(uv, dtype=np.float64)
    return table if table.ndim == 2 and table.shape[1] == 2 else None


GLTF_BASE_COLOUR = (1.0, 1.0, 1.0)  # a glTF material's baseColorFactor where it gives none


def _material_of(mesh: Any) -> dict[str, object] | None:
    """The base colour of a glTF material as Kd: the quantity the lighting equation reads."""
    material = getattr(getattr(mesh, "visual", None), "material", None)
    if not hasattr(material, "baseColorFactor"):  # no glTF material (none, or trimesh's of an OBJ)
        return None
    colour = material.baseColorFactor
    if colour is None:  # glTF's default, which Blender leaves out
        return {"kd": GLTF_BASE_COLOUR}
    rgb = np.asarray(colour, dtype=np.float64).reshape(-1)[:3]
    rgb = colour_fractions(rgb)  # trimesh keeps glTF colours as bytes
    return {"kd": tuple(float(c) for c in rgb)} if np.isfinite(rgb).all() else None


# A PLY vertex's colour: trimesh reads the first names; some writers use the second, which it passes over.
_DIFFUSE_COLOURS = ("diffuse_red", "diffuse_green", "diffuse_blue")
_PLY_COLOURS = (("red", "green", "blue"), _DIFFUSE_COLOURS)


def _ply_colour_notes(source: str | Path, mesh: Any) -> tuple[str, ...]:
    """A PLY's colours, which trimesh makes bytes without a word (NaN as 0, 1e30 as 255, an int's 300 as
    44): a NaN or an infinity is refused, as in every model; values outside 0..1 (floats) or 0..255
    (whole numbers) are held to it, with a note, as an OBJ's are."""
    table = _ply_vertex_table(mesh)
    names, colours = _ply_colour_columns(table)
    if colours is None:
        return _partial_colour_notes(table)
    if colours.dtype.kind == "f" and not np.isfinite(colours).all():
        raise LoadError(source, "its vertex colours hold a NaN or an infinity")
    most = 1.0 if colours.dtype.kind == "f" else 255
    outside = int(((colours < 0) | (colours > most)).any(axis=1).sum())
    return (f"{counted(outside, 'vertex colour')} outside 0..{most:g} held to it",) if outside else ()


def _ply_colours(mesh: Any) -> np.ndarray | None:
    """A PLY's vertex colours where trimesh's are not the file's, held as _ply_colour_notes says: the
    diffuse_ names it passes over, and whole numbers other than bytes, which it wraps; else None."""
    names, colours = _ply_colour_columns(_ply_vertex_table(mesh))
    if colours is None:
        return None
    if colours.dtype.kind == "f":
        return np.clip(colours, 0.0, 1.0) if names == _DIFFUSE_COLOURS else None
    if colours.dtype != np.uint8:
        return np.clip(colours, 0, 255).astype(np.uint8)
    return colours if names == _DIFFUSE_COLOURS else None


def _ply_colour_columns(table: dict[str, np.ndarray]) -> tuple[tuple[str, ...], np.ndarray | None]:
    """The first of _PLY_COLOURS' names the vertex table has all of, and their (V, 3) columns; None
    where it has no whole colour."""
    names = next((names for names in _PLY_COLOURS if table.keys() >= set(names)), ())
    return names, np.column_stack([table[name] for name in names]) if names else None


def _partial_colour_notes(table: dict[str, np.ndarray]) -> tuple[str, ...]:
    """A PLY's vertex colour of only some of its names (diffuse_red alone, say), not drawn: a note, where
    trimesh passes over it without a word."""
    partial = [(present, [name for name in names if name not in table]) for names in _PLY_COLOURS
               if (present := [name for name in names if name in table])]
    return tuple(f"vertex colours not drawn: {' and '.join(present)} without {' and '.join(missing)}"
                 for present, missing in partial)


def _vertex_colours(mesh: Any) -> np.ndarray | None:
    """The file's colour per vertex (PLY's red/green/blue, glTF's COLOR_0) as RGB bytes, if any."""
    visual = getattr(mesh, "visual", None)
    if (ply_colours := _ply_colours(mesh)) is not None:
        colours = ply_colours
    elif getattr(visual, "kind", None) == "vertex":
        colours = np.asarray(visual.vertex_colors)
    else:  # glTF's COLOR_0 beside a material: trimesh keeps it as the file gives it, a vertex attribute
        attributes = getattr(visual, "vertex_attributes", None)
        if attributes is None or "color" not in attributes:
            return None
        colours = np.asarray(attributes["color"])  # normalized shorts made fractions (gltf._normalized_read)
    try:
        return colour_bytes(colours, len(mesh.vertices))
    except ValueError:  # not one RGB or RGBA row per vertex of bytes or 0..1: not trusted, not drawn
        return None
