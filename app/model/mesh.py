"""A loaded model: the seed's vertex and face tables as numpy arrays, no GL.

Faces are polygons of any size stored as one flat list of *corners* (CSR layout): polygon ``f`` owns
corners ``face_start[f]:face_start[f + 1]``. A corner carries the index of its position and its own
texture coordinate and vertex normal, because OBJ lets one position have different ``vt``/``vn`` on
different faces; where no position does, they are stored once per position instead. Triangles are a
fan from each polygon's first corner, the way the seed draws them, so the first corner of every
triangle is its polygon's first vertex: with the provoking vertex set to the first one, a ``flat``
varying gives exactly SPEC's "face normal at the polygon's first vertex".
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import numpy as np

from marraztu.model.geometry import column_bounds
from marraztu.model.sampling import DEFAULT_SAMPLING, TextureSampling

# Corner and face indices are 32-bit: half of numpy's default, and no file the viewer reads (1 GiB at
# most, two bytes a corner at least) holds 2**31 of anything. build.derive_mesh refuses more.
INDEX = np.int32
INDEX_LIMIT = int(np.iinfo(INDEX).max)  # counts of positions and corners stay below it
# The GPU's positions are 32-bit: a model this many times its size from the origin would be drawn with
# its corners on steps of up to 1/2048 of its size, and one farther away on coarser steps still. Past
# FAR_AWAY units every model is measured from its centre, whatever its size, so that the models of one
# far site (a terrain under a house) are all drawn the same way.
FAR_FROM_ORIGIN = 4096
FAR_AWAY = float(1 << 16)
# Each material is drawn as a part of its own (a draw and a lighting pass): a file of thousands of
# materials would cost thousands of draws a frame. Real models use tens.
MAX_MATERIALS = 256
WHOLE = -1  # the part index that stands for the whole mesh (Mesh.part_mesh)


def counted(number: int, noun: str, plural: str | None = None) -> str:
    """'1 face', '2 faces'."""
    return f"{number} {noun if number == 1 else plural or noun + 's'}"


def polygons_of_corners(face_start: np.ndarray, corners: int | np.ndarray) -> np.ndarray:
    """The polygon of each corner, where polygon p's corners start at face_start[p] (and the last ends
    at face_start[-1]); the corners are below face_start[-1], so they hold in its type."""
    # Corners in the table's own type: any other would have numpy convert the whole table at each call.
    return np.searchsorted(face_start, np.asarray(corners, face_start.dtype), side="right") - 1


def corners_of_polygons(first_corners: np.ndarray, sizes: np.ndarray, step: int = 1) -> np.ndarray:
    """Every corner of polygons that start at `first_corners` and hold `sizes` corners (`step` apart),
    one polygon after another: each polygon's first corner plus each corner's place in it. Any rows
    laid out so list their items this way: a PLY row's list items, their byte offsets too."""
    # signed: an unsigned count's cumsum is uint64, and uint64 less int64 is float64 in numpy
    first_corners, sizes = np.asarray(first_corners, np.int64), np.asarray(sizes, np.int64)
    before = np.cumsum(sizes) - sizes  # the corners listed before each polygon's
    places = np.arange(int(sizes.sum()), dtype=np.int64)
    if step != 1:
        before *= step
        places *= step
    return np.repeat(first_corners - before, sizes) + places


def fan_gather(values: np.ndarray, face_start: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
    """(3T,) `values`, one per corner, in the order of the fan triangles' corners, polygon by polygon:
    the seed's triangulation from each polygon's first corner; `face_start` runs from 0, as a mesh's
    does. Written straight into place (`out`, where given): where the polygons are all of one size,
    from slices of each polygon's row of values, with no table of corner indices; else from one index
    per fan."""
    sizes = np.diff(face_start)
    one_size = bool(sizes.size) and sizes.min() == sizes.max()
    if one_size and sizes[0] == 3 and out is None:  # the common case: the corners are the triangles already
        return values
    per_face = sizes - 2
    fans = np.empty(3 * int(per_face.sum()), values.dtype) if out is None else out
    if one_size:  # the same fan in each polygon
        polygons = values.reshape(-1, int(sizes[0]))
        in_place = fans.reshape(polygons.shape[0], -1, 3)
        in_place[:, :, 0] = polygons[:, :1]
        in_place[:, :, 1] = polygons[:, 1:-1]
        in_place[:, :, 2] = polygons[:, 2:]
        return fans
    rows = fans.reshape(-1, 3)
    rows[:, 0] = np.repeat(values[face_start[:-1]], per_face)
    # Fan j of polygon p starts at corner j + 2p: each polygon before it has two corners more than fans.
    second = np.repeat(np.arange(0, 2 * per_face.size, 2), per_face)
    second += np.arange(1, rows.shape[0] + 1)
    rows[:, 1] = values[second]
    second += 1
    rows[:, 2] = values[second]
    return fans


def polygon_corners_of_fans(fans: np.ndarray, sizes: np.ndarray) -> np.ndarray:
    """The corners of polygons of these sizes, one polygon after another, from their fans (T, 3) in
    fan_gather's order, which this undoes: a polygon's first fan holds its first three corners, and
    each fan after it the next corner, last."""
    first_fans = np.cumsum(sizes - 2) - (sizes - 2)
    kept = np.ones(fans.shape, bool)
    kept[:, :2] = False
    kept[first_fans, :2] = True
    return fans[kept]  # row by row: the corners in order


def fan_triangles(face_start: np.ndarray) -> np.ndarray:
    """(T, 3) corner indices of every polygon's fan from its first corner, polygon by polygon: the
    seed's triangulation, so each triangle's first corner is its polygon's first vertex."""
    return fan_gather(np.arange(int(face_start[-1]), dtype=np.int64), face_start).reshape(-1, 3)


PLAIN_PICTURE = np.full((1, 1, 3), 255, dtype=np.uint8)  # white, no picture: the lit colour times 1
PLAIN_PICTURE.flags.writeable = False  # shared by every element that wears no picture


def is_plain(picture: np.ndarray | None) -> bool:
    """Whether a picture multiplies nothing (None is drawn white too): told by its pixels, as a copy of
    PLAIN_PICTURE (copy.deepcopy of a scene) or a one-pixel white file multiplies nothing either."""
    return picture is None or (picture.shape[:2] == (1, 1) and bool((picture == 255).all()))
# The Kd of a material whose own picture is its colour and that gives no Kd (an MTL's map_Kd alone, a PLY's
# TextureFile, a trimesh's picture): Blender, three.js and glTF draw the picture unscaled.
PICTURE_AS_COLOUR = (1.0, 1.0, 1.0)


def with_picture_as_colour(values: dict[str, object], textured: bool) -> dict[str, object]:
    """A material's numbers, with Kd PICTURE_AS_COLOUR where it has a picture of its own and no Kd."""
    return {**values, "kd": PICTURE_AS_COLOUR} if textured and "kd" not in values else values


@dataclass(frozen=True, eq=False)
class MeshMaterial:
    """One material a model file defines (an MTL's newmtl): the numbers it gives, by key "ka", "kd",
    "ks" (3-tuples) and "ns", and its diffuse texture when it names one that could be read, with how
    that is sampled (a glTF's sampler)."""

    name: str
    values: dict[str, object] = field(default_factory=dict)
    texture: np.ndarray | None = None  # (H, W, 3) uint8, top row first
    texture_name: str | None = None
    sampling: TextureSampling = DEFAULT_SAMPLING


@dataclass(frozen=True, eq=False)
class MeshPart:
    """The faces of one material: `material` indexes Mesh.materials (-1: the object's own), and `faces`
    are their indices in the whole mesh, ascending (None where they are every face). The Mesh a part
    is drawn from is made from the whole's tables when asked (Mesh.part_mesh), not held beside them."""

    material: int
    faces: np.ndarray | None  # (F,) INDEX

    def face_range(self, start: int, stop: int) -> tuple[int, int]:
        """The part's own [start, stop) of the faces of the whole mesh's [start, stop) that it holds."""
        if self.faces is None:
            return start, stop
        low, high = np.searchsorted(self.faces, [start, stop]).tolist()
        return low, high

    def own_face(self, face: int) -> int | None:
        """The part's own index of the whole mesh's polygon `face`; None where the part lacks it."""
        if self.faces is None:
            return face
        local = int(np.searchsorted(self.faces, face))
        return local if local < self.faces.size and self.faces[local] == face else None


@dataclass(frozen=True, eq=False)
class Mesh:
    name: str
    positions: np.ndarray  # (V, 3) float64: the file's `v` table, in file order
    corner_vertex: np.ndarray  # (C,) INDEX: index into positions for each polygon corner
    # A row per corner, or per position where attributes_per_position: see attribute_rows.
    uvs: np.ndarray  # (C or V, 2) float32: texture coordinates (from vt, or the bounding box)
    normals: np.ndarray  # (C or V, 3) float32: unit vertex normals (vn, or averaged faces)
    face_start: np.ndarray  # (F + 1,) INDEX: CSR offsets of each polygon's corners
    face_normals: np.ndarray  # (F, 3) float32: unit normal per polygon (Newell's method)
    base_colour: tuple[float, float, float] | None = None  # the seed's `# colour r g b`, in 0..1
    # Ka/Kd/Ks/Ns read from the file's MTL when it exists: keys "ka", "kd", "ks" (3-tuples), "ns".
    file_material: dict[str, object] | None = None
    warnings: tuple[str, ...] = field(default=())  # non-fatal oddities worth telling the person
    # True when every corner of a position has the same normal and uv, stored once per position: then
    # no position needs a second vertex row (no seams), and the tables hold fewer rows than corners.
    attributes_per_position: bool = False
    # Which normals were averaged from the faces around them, the file giving none usable: all (True), none
    # (False), or some, as a (C or V,) bool per row of `normals`. A stretch averages these again.
    normals_averaged: bool | np.ndarray = False
    # The file's materials and, per polygon, which one it uses (-1: none, the object's own material).
    # Without `usemtl` both are empty and the whole mesh takes the object's material.
    materials: tuple[MeshMaterial, ...] = ()
    face_material: np.ndarray | None = None  # (F,) int32
    # A colour per position (PLY, glTF COLOR_0), drawn as a tint of the lit colour, like a texture.
    vertex_colours: np.ndarray | None = None  # (V, 3) uint8
    # The files looked for beside the model's own (an OBJ's MTL and its textures, a glTF's buffers and
    # pictures), read or not: the screenshot command must write over none of them.
    read_beside: tuple[Path, ...] = ()
    # A part's gpu_origin: its whole mesh's, so that the parts of one mesh are drawn alike (None: its own).
    whole_gpu_origin: np.ndarray | None = None

    def __repr__(self) -> str:
        """Its name and size, not its tables: a notebook showing a scene would print every row."""
        return f"<Mesh {self.name!r}: {self.summary()}>"

    def summary(self) -> str:
        """Its size as messages give it: '4 vertices, 1 face'."""
        return f"{counted(self.vertex_count, 'vertex', 'vertices')}, {counted(self.face_count, 'face')}"

    @property
    def vertex_count(self) -> int:
        return int(self.positions.shape[0])

    @property
    def face_count(self) -> int:
        return int(self.face_start.shape[0] - 1)

    @property
    def face_sizes(self) -> np.ndarray:
        return np.diff(self.face_start)

    def attribute_rows(self, corners: np.ndarray | int) -> np.ndarray | np.integer | int:
        """The rows of `uvs` and `normals` that hold these corners' values (one corner: one row)."""
        return self.corner_vertex[corners] if self.attributes_per_position else corners

    @property
    def corner_uv(self) -> np.ndarray:
        """(C, 2) float32: each corner's texture coordinate (gathered anew where stored per position)."""
        return self.uvs[self.corner_vertex] if self.attributes_per_position else self.uvs

    @property
    def corner_normal(self) -> np.ndarray:
        """(C, 3) float32: each corner's unit vertex normal (gathered anew where stored per position)."""
        return self.normals[self.corner_vertex] if self.attributes_per_position else self.normals

    # Cached: the renderer asks every frame (far plane, normal length) and a mesh never changes.
    # cached_property writes the instance __dict__ directly, so it works on a frozen dataclass.
    @cached_property
    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """The seed's `min` and `max` points of the vertex table."""
        low, high = column_bounds(self.positions)
        low.flags.writeable = high.flags.writeable = False  # cached, so shared by every caller
        return low, high

    @cached_property
    def gpu_origin(self) -> np.ndarray:
        """Where its GPU rows are measured from: the origin, or the centre of its box where that lies
        more than FAR_FROM_ORIGIN times its size or FAR_AWAY units away (the renderer adds it back to
        the model matrix in 64-bit numbers)."""
        if self.whole_gpu_origin is not None:
            return self.whole_gpu_origin
        low, high = self.bounds
        centre = (low + high) / 2
        near_enough = min(FAR_FROM_ORIGIN * self.size, FAR_AWAY) if self.size > 0 else FAR_AWAY
        if np.abs(centre).max() <= near_enough:
            return np.zeros(3)
        centre.flags.writeable = False  # cached, so shared by every caller
        return centre

    def gpu_positions(self, rows: slice | None = None) -> np.ndarray:
        """(V, 3) float64: the positions (these rows of them) less gpu_origin (the table itself where
        that is the origin)."""
        origin = self.gpu_origin
        table = self.positions if rows is None else self.positions[rows]
        return table - origin if origin.any() else table

    @cached_property
    def all_triangles(self) -> bool:
        return bool(self.face_count * 3 == self.face_start[-1])

    @cached_property
    def size(self) -> float:
        """Length of the bounding box diagonal: the scale for normals, markers and ortho sizing."""
        low, high = self.bounds
        return float(np.linalg.norm(high - low))

    @cached_property
    def parts(self) -> tuple[MeshPart, ...]:
        """The mesh cut by material, each part its faces in file order, so that each draws with its own
        material and texture; () for a mesh without the file's materials, and one part of every face
        where all have the same one."""
        if self.face_material is None:
            return ()
        first = int(self.face_material[0])
        if first == self.face_material.min() == self.face_material.max():  # the part is the whole, not a copy
            return (MeshPart(first, None),)
        order = np.argsort(self.face_material, kind="stable").astype(INDEX)
        bounds = np.flatnonzero(np.diff(self.face_material[order])) + 1
        return tuple(MeshPart(int(self.face_material[faces[0]]), faces) for faces in np.split(order, bounds))

    def drawn_parts(self) -> tuple[int, ...]:
        """What it is drawn as: each of its parts (indices into `parts`), or WHOLE where it has none."""
        return tuple(range(len(self.parts))) or (WHOLE,)

    def part_mesh(self, part: int) -> Mesh:
        """The Mesh part `part` (an index into `parts`, or WHOLE) is drawn from: this one where it holds
        every face, else made anew at each call from this one's tables, so that its copies live only
        while a renderer builds from them."""
        faces = None if part == WHOLE else self.parts[part].faces
        if faces is None:
            return self
        first, last = int(faces[0]), int(faces[-1])
        run = self._run_part(first, last + 1) if last - first + 1 == faces.size else None
        return self._gathered_part(faces) if run is None else run

    def _run_part(self, start: int, stop: int) -> Mesh | None:
        """The Mesh of faces [start, stop) as views of this one's tables, where their corners use every
        position of one run of them (a glTF primitive, an OBJ object of one material); else None."""
        first_corner, stop_corner = int(self.face_start[start]), int(self.face_start[stop])
        vertices = self.corner_vertex[first_corner:stop_corner]
        low, high = int(vertices.min()), int(vertices.max()) + 1
        corner_vertex = np.subtract(vertices, low, dtype=INDEX)
        used = np.zeros(high - low, bool)
        used[corner_vertex] = True
        if not used.all():
            return None
        rows = slice(low, high) if self.attributes_per_position else slice(first_corner, stop_corner)
        face_start = np.subtract(self.face_start[start:stop + 1], first_corner, dtype=INDEX)
        return Mesh(name=self.name, positions=self.positions[low:high], corner_vertex=corner_vertex,
                    uvs=self.uvs[rows], normals=self.normals[rows], face_start=face_start,
                    face_normals=self.face_normals[start:stop], base_colour=self.base_colour,
                    attributes_per_position=self.attributes_per_position,
                    vertex_colours=None if self.vertex_colours is None else self.vertex_colours[low:high],
                    whole_gpu_origin=self.gpu_origin)

    def _gathered_part(self, faces: np.ndarray) -> Mesh:
        sizes = self.face_sizes[faces]
        face_start = np.concatenate(([0], np.cumsum(sizes))).astype(INDEX)
        corners = corners_of_polygons(self.face_start[faces], sizes)
        # Only the positions the part uses: the GPU arrays hold a row per position, so parts sharing
        # the whole table would cost the table once per material.
        used, corner_vertex = np.unique(self.corner_vertex[corners], return_inverse=True)
        rows = used if self.attributes_per_position else corners
        return Mesh(name=self.name, positions=self.positions[used], corner_vertex=corner_vertex.astype(INDEX),
                    uvs=self.uvs[rows], normals=self.normals[rows],
                    face_start=face_start, face_normals=self.face_normals[faces], base_colour=self.base_colour,
                    attributes_per_position=self.attributes_per_position,
                    vertex_colours=None if self.vertex_colours is None else self.vertex_colours[used],
                    whole_gpu_origin=self.gpu_origin)

    def own_picture(self, part: int) -> np.ndarray | None:
        """The picture a part is drawn with in place of the scene's (None: the scene's): its material's
        texture, or, where it has none and the mesh has vertex colours, plain white, since those colours
        are the model's surface, as a texture of its own is (a scan under the scene's test picture)."""
        texture = self.materials[part].texture if 0 <= part < len(self.materials) else None
        if texture is None and self.vertex_colours is not None:
            return PLAIN_PICTURE
        return texture

    def own_sampling(self, part: int) -> TextureSampling:
        """How own_picture(part) is sampled: its material's way for its material's texture, else the default."""
        if 0 <= part < len(self.materials) and self.materials[part].texture is not None:
            return self.materials[part].sampling
        return DEFAULT_SAMPLING

    def triangle_corners(self) -> np.ndarray:
        """(T, 3) corner indices of the fan triangulation, polygon by polygon, in file order."""
        return fan_triangles(self.face_start)

    def triangles_before_face(self) -> np.ndarray:
        """(F + 1,) how many fan triangles come before each polygon (and in all, last)."""
        before = np.zeros(self.face_count + 1, INDEX)
        np.cumsum(self.face_sizes - 2, out=before[1:])
        return before

    def edge_neighbours(self, face: int) -> np.ndarray:
        """The other polygons with an edge of polygon `face` (its two positions, either way round), in
        order. Only polygons with a corner on one of its positions can share an edge: one pass over the
        corners finds them, and only their edges are compared."""
        start, stop = int(self.face_start[face]), int(self.face_start[face + 1])
        own = self.corner_vertex[start:stop]
        touching = np.unique(polygons_of_corners(self.face_start, np.flatnonzero(np.isin(self.corner_vertex, own))))
        firsts, sizes = self.face_start[touching], self.face_sizes[touching]
        corners = corners_of_polygons(firsts, sizes)
        following = corners + 1  # each corner's next one round its polygon, the last closing on the first
        ends = np.cumsum(sizes) - 1
        following[ends] = firsts
        keys = self._edge_keys(corners, following)
        shared = np.isin(keys, self._edge_keys(np.arange(start, stop), np.roll(np.arange(start, stop), -1)))
        faces = np.unique(np.repeat(touching, sizes)[shared])
        return faces[faces != face]

    def _edge_keys(self, corners: np.ndarray, following: np.ndarray) -> np.ndarray:
        """One number per edge from corner to following corner, the same whichever way round it runs."""
        ends = np.stack([self.corner_vertex[corners], self.corner_vertex[following]]).astype(np.int64)
        return ends.min(axis=0) * self.vertex_count + ends.max(axis=0)

    def edge_corners(self) -> np.ndarray:
        """(E, 2) INDEX corner pairs of every polygon's boundary, polygon by polygon (its first corner
        first): each corner and the next, the last closing on the first."""
        pairs = np.empty((int(self.face_start[-1]), 2), INDEX)
        pairs[:, 0] = np.arange(pairs.shape[0], dtype=INDEX)
        pairs[:, 1] = pairs[:, 0] + 1
        pairs[self.face_start[1:] - 1, 1] = self.face_start[:-1]
        return pairs
