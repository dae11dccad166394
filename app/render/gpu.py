"""GPU side of a mesh: the shader loader and the vertex buffers the renderer draws from.

The vertex arrays are built here with numpy. GL has no per-primitive attributes, so what belongs to
a polygon (its face normal, its first vertex) rides on vertices: the surface is indexed, with one
extra vertex per polygon for its first corner (see SurfaceArrays). Vertex normals are the surface's
own rows drawn as points (each used row once, or a range of faces' corners through its indices),
face normals one point per polygon (its centroid, its direction read from the polygon's own surface
row), and a geometry stage draws each as a segment. Edges are one row per polygon corner: its
position and its polygon's texel in two float textures holding each polygon's first vertex and
face normal, drawn as indexed lines (a geometry stage over the surface's rows would spare those
rows, but makes llvmpipe's lines frames a third slower; the polygon's point and normal copied into
every row made three attributes a vertex, whose fetch doubled NVIDIA's frames of millions of edges).

Everything is built once per mesh (edges and normals on first use), shared by the objects that place
it, and kept until the last of them leaves the scene (MeshGpus); drawing a subset of faces is a
`first`/`vertices` range. Each object has a lit buffer of its own: a colour per vertex row, written by
the lighting pass from its placement and kept until what lighting reads changes (ObjectGpu.light).
"""

from __future__ import annotations

import math
import re
import threading
import weakref
from dataclasses import dataclass
from typing import Hashable, Mapping, NamedTuple, Sequence

import moderngl
import numpy as np

from marraztu.errors import ViewerError
from marraztu.model.mesh import INDEX, WHOLE, Mesh, fan_gather
from marraztu.model.scene import Shading
from marraztu.model.threads import each, pieces
from marraztu.render.context import (
    COMPUTE_GL_VERSION,
    check_gl,
    device_buffer,
    device_texture,
    max_texture_side,
    zeroed_device_buffer,
)
from marraztu.resources import shader_source

# Files of GLSL functions, not programs, that programs include: one place for what several use.
SHADER_INCLUDES = ("ray_depth",)
# Attribute layouts, one per program; the names are the shaders' `in_` attributes.
SURFACE_LAYOUT = ("3f 3f 2f", "in_position", "in_normal", "in_uv")
COLOUR_LAYOUT = ("4f1", "in_colour")  # a model's own vertex colours, bytes read as 0..1, one per surface row
LIT_LAYOUT = ("4f", "in_lit")  # the lighting pass's output: colour and N.V, one row per surface row
EDGE_LAYOUT = ("3f 2u2", "in_position", "in_face_texel")
EDGE_ROW = np.dtype([("position", np.float32, 3), ("face_texel", np.uint16, 2)])
OUTLINE_LAYOUT = ("3f 4x", "in_position")  # the probe's outline reads an edge row's position alone
# The edges program's polygon tables (edge_faces) by sampler and texture unit: 0 and 1 are the
# model's picture and the text atlas.
EDGE_FACE_UNITS = {"u_face_points": 2, "u_face_normals": 3}
EDGE_FACE_TEXTURE_SIDE = 1 << 15  # the polygon tables' widest: an edge row's texel coordinates are 16-bit
# The normals program reads a vertex row's position and vertex normal as a foot and a direction.
VERTEX_NORMAL_LAYOUT = ("3f 3f 2f", "in_position", "in_direction", "in_uv")
# A face normal's foot; its direction is read from the polygon's own surface row (ObjectGpu.face_normals).
FACE_NORMAL_LAYOUT = ("3f", "in_position")


class SurfaceWay(NamedTuple):
    """Which surface program draws: a shading, and whether it paints the depth view instead of the
    lit picture (surface.glsl builds one program for each)."""

    shading: Shading
    depth_view: bool = False

    @property
    def defines(self) -> dict[str, str]:
        return {"SHADING": self.shading.name, **({"DEPTH_VIEW": "1"} if self.depth_view else {})}


LIT_SURFACE_WAYS = tuple(SurfaceWay(shading) for shading in Shading)
SURFACE_WAYS = (*LIT_SURFACE_WAYS, *(SurfaceWay(shading, depth_view=True) for shading in Shading))


def load_program(ctx: moderngl.Context, name: str, defines: Mapping[str, str] | None = None,
                 varyings: Sequence[str] = ()) -> moderngl.Program:
    """Compile `shaders/<name>.glsl`, a single file split by `#if defined VERTEX_SHADER` blocks
    (and GEOMETRY_SHADER where it has one), with `defines` (e.g. surface.glsl's SHADING) for every
    stage. With `varyings`, a transform-feedback program instead: the vertex stage alone, capturing
    those outputs.
    """
    # moderngl-window reads single-file programs the same way, but its loader wants a window context
    # registered; the screenshot command runs on a bare offscreen one, so the defines go in here.
    _register_includes(ctx)
    source = shader_source(name)
    extra = _defines(defines)
    vertex_shader = _with_define(source, "VERTEX_SHADER", extra)
    if varyings:
        return ctx.program(vertex_shader=vertex_shader, varyings=list(varyings))
    geometry_shader = _with_define(source, "GEOMETRY_SHADER", extra) if "defined GEOMETRY_SHADER" in source else None
    return ctx.program(vertex_shader=vertex_shader, geometry_shader=geometry_shader,
                       fragment_shader=_with_define(source, "FRAGMENT_SHADER", extra))


def load_compute_program(ctx: moderngl.Context, name: str, defines: Mapping[str, str] | None = None
                         ) -> moderngl.ComputeShader:
    """Compile the `#if defined COMPUTE_SHADER` block of `shaders/<name>.glsl`, with `defines`."""
    _register_includes(ctx)
    return compute_program(ctx, shader_source(name), {"COMPUTE_SHADER": "1", **(defines or {})})


def _register_includes(ctx: moderngl.Context) -> None:
    """moderngl pastes shaders/<name>.glsl where a program says `#include "name"`, for each of
    SHADER_INCLUDES."""
    for name in SHADER_INCLUDES:
        if name not in ctx.includes:
            ctx.includes[name] = shader_source(name)


def compute_program(ctx: moderngl.Context, source: str, defines: Mapping[str, str]) -> moderngl.ComputeShader:
    """Compile `source` as a compute program after `defines`, in GLSL 4.30, the first version with
    them (replacing a #version line of its own, which the file's other programs keep)."""
    first_line, _, rest = source.partition("\n")
    body = rest if first_line.lstrip().startswith("#version") else source
    return ctx.compute_shader(f"#version {COMPUTE_GL_VERSION} core\n{_defines(defines)}{body}")


def _defines(defines: Mapping[str, str] | None) -> str:
    return "".join(f"#define {key} {value}\n" for key, value in (defines or {}).items())


def _with_define(source: str, define: str, extra: str = "") -> str:
    version, newline, rest = source.partition("\n")
    if not version.lstrip().startswith("#version"):
        raise ValueError("a shader file must start with its #version line")
    return f"{version}{newline}#define {define}\n{extra}{rest}"


# --- numpy: the vertex arrays ----------------------------------------------------------------
# Each array is allocated once at its final size and filled column block by column block: an
# hstack of float64 pieces then astype would make several whole-size copies.
@dataclass(frozen=True)
class SurfaceArrays:
    """The surface as indexed triangles: `vertices` rows of SURFACE_LAYOUT, and two index arrays of
    three per fan triangle, polygon by polygon (so a range of faces is a range of indices).

    Rows, in order: one per position, taking the vertex normal and uv of one of its corners; one per
    corner whose normal or uv differs from that (seams); one per polygon for its first corner, whose
    normal is the polygon's face normal: the normal each row is lit with.

    `indices` (Flat) start every triangle at its polygon's own row, so with the provoking vertex set
    to the first one, `flat` varyings come from the polygon's first vertex lit with its face normal
    (SPEC 4's Flat); the other corners are shared between polygons, so each is lit once for all the
    triangles around it. `shared_indices` (Gouraud, Phong) use the shared rows only: those modes need
    nothing of a polygon's own, so each corner is lit once, not once more as its polygon's first.
    """

    vertices: np.ndarray  # (N, 8) float32
    indices: np.ndarray  # (3T,) uint32
    shared_indices: np.ndarray  # (3T,) uint32
    shared_rows: int  # the rows before the polygons' own
    colours: np.ndarray | None = None  # (N, 4) uint8: each row's position's colour, when the mesh has them

    @property
    def arrays(self) -> dict[str, np.ndarray]:
        """What is uploaded, by the name of the ObjectGpu buffer it goes to: the vertices, both index
        arrays, and the colours where there are some."""
        arrays = {"surface": self.vertices, "surface indices": self.indices,
                  "shared surface indices": self.shared_indices, "colours": self.colours}
        return {name: array for name, array in arrays.items() if array is not None}


def surface_arrays(mesh: Mesh) -> SurfaceArrays:
    # Rows, then indices, each in a function of its own: the rows' temporaries are freed before the
    # index arrays are made, which lowers a load's peak.
    vertices, colours, seams, shared_rows = _surface_rows(mesh)
    indices, shared_indices = _surface_indices(mesh, seams, shared_rows)
    return SurfaceArrays(vertices, indices, shared_indices, shared_rows, colours)


def _surface_rows(mesh: Mesh) -> tuple[np.ndarray, np.ndarray | None, np.ndarray, int]:
    """SurfaceArrays' vertices and colours, the seam corners that have rows of their own, and how many
    rows are shared. Each block of columns is written straight into its rows: a gather only where a
    row takes another row's values, so no temporary is as long as the table."""
    corner_vertex = mesh.corner_vertex
    positions = mesh.vertex_count
    own = None  # per position, the row of uvs and normals it takes; None: its own row
    seams = np.zeros(0, np.int64)
    if not mesh.attributes_per_position:  # compared with any one corner of the position
        own = np.zeros(positions, np.int64)
        own[corner_vertex] = np.arange(corner_vertex.shape[0])
        seams = _seams(mesh, own[corner_vertex])
    shared_rows = positions + seams.shape[0]
    firsts = mesh.face_start[:-1]  # each polygon's own row copies its first corner's
    vertices = np.empty((shared_rows + firsts.shape[0], 8), np.float32)

    def position_rows(rows: slice) -> None:  # a position's own row is the position (unused ones are never indexed)
        vertices[rows, 0:3] = mesh.gpu_positions(rows)
        vertices[rows, 3:6] = _own_rows(mesh.normals, own, rows)
        vertices[rows, 6:8] = _own_rows(mesh.uvs, own, rows)

    # Each later row starts as a copy of its corner's position's row, gathered whole (np.take gathers rows
    # faster than fancy indexing, and whole rows faster than a few columns of them); then what differs.
    # mode="clip" (the indices are the mesh's, in range) is the mode that writes into `out` unbuffered.
    def seam_rows(seam: slice) -> None:  # seams exist only where attributes are per corner
        rows, corners = _after(positions, seam), seams[seam]
        np.take(vertices[:positions], corner_vertex[corners], axis=0, out=vertices[rows], mode="clip")
        vertices[rows, 3:6] = np.take(mesh.normals, corners, axis=0)
        vertices[rows, 6:8] = np.take(mesh.uvs, corners, axis=0)

    def polygon_rows(polygon: slice) -> None:
        rows, corners = _after(shared_rows, polygon), firsts[polygon]
        np.take(vertices[:positions], corner_vertex[corners], axis=0, out=vertices[rows], mode="clip")
        if own is not None:  # attributes per corner: the uv is the first corner's own
            vertices[rows, 6:8] = np.take(mesh.uvs, corners, axis=0)
        vertices[rows, 3:6] = mesh.face_normals[polygon]  # Flat lights a polygon at its own row only

    each(position_rows, pieces(positions))
    each(seam_rows, pieces(seams.shape[0]))  # these two after the positions' rows, which they copy
    each(polygon_rows, pieces(firsts.shape[0]))
    colours = None
    if mesh.vertex_colours is not None:  # 4 bytes a row keeps every row aligned for the GPU
        colours = np.full((vertices.shape[0], 4), 255, np.uint8)
        colours[:positions, :3] = mesh.vertex_colours
        colours[positions:, :3] = np.take(mesh.vertex_colours, corner_vertex[np.concatenate([seams, firsts])], axis=0)
    return vertices, colours, seams, shared_rows


def _after(first_row: int, rows: slice) -> slice:
    """These rows of a block that starts at `first_row`, as rows of the whole table."""
    return slice(first_row + rows.start, first_row + rows.stop)


def _own_rows(table: np.ndarray, own: np.ndarray | None, rows: slice) -> np.ndarray:
    """These positions' rows of a per-row table (uvs, normals): the table's own where rows are positions."""
    return table[rows] if own is None else np.take(table, own[rows], axis=0)


def _surface_indices(mesh: Mesh, seams: np.ndarray, shared_rows: int) -> tuple[np.ndarray, np.ndarray]:
    """SurfaceArrays' indices (Flat) and shared_indices (Gouraud, Phong), written a block of polygons
    at a time on threads: a polygon's fans go after the fans of the polygons before it."""
    face_start, vertex_count, all_triangles = mesh.face_start, mesh.vertex_count, mesh.all_triangles
    triangles = int(face_start[-1]) - 2 * mesh.face_count  # a polygon of n corners has n - 2 fans
    shared_indices = np.empty(3 * triangles, np.uint32)
    indices = np.empty(3 * triangles, np.uint32)

    def polygons(block: slice) -> None:
        first, stop = int(face_start[block.start]), int(face_start[block.stop])
        # Fans before polygon p, as Mesh.triangles_before_face counts them: two fewer than corners a polygon.
        fan_rows = slice(3 * (first - 2 * block.start), 3 * (stop - 2 * block.stop))
        row_of_corner = shared_indices[fan_rows] if all_triangles else np.empty(stop - first, np.uint32)
        row_of_corner[:] = mesh.corner_vertex[first:stop]
        # Seam k, a corner with a row of its own, is row vertex_count + k; seams are in corner order.
        low, high = np.searchsorted(seams, [first, stop]).tolist()
        row_of_corner[seams[low:high] - first] = np.arange(vertex_count + low, vertex_count + high, dtype=np.uint32)
        if not all_triangles:
            fan_gather(row_of_corner, face_start[block.start:block.stop + 1] - first, out=shared_indices[fan_rows])
        indices[fan_rows] = shared_indices[fan_rows]
        own_rows = np.arange(shared_rows + block.start, shared_rows + block.stop, dtype=np.uint32)
        if not all_triangles:  # each polygon's own row begins each of its fans
            own_rows = np.repeat(own_rows, np.diff(face_start[block.start:block.stop + 1]) - 2)
        indices[fan_rows.start:fan_rows.stop:3] = own_rows

    each(polygons, pieces(mesh.face_count))
    return indices, shared_indices


_SEAM_CHUNK = 1 << 15  # corners compared per piece: their gathered rows stay in the CPU cache


def _seams(mesh: Mesh, representative_corner: np.ndarray) -> np.ndarray:
    """Corners whose normal or uv differs from their position's representative corner, in bits
    (so -0.0 and 0.0, or two NaNs, are told apart as the GPU would see them). On uint32 views, the
    representative rows gathered whole with np.take, piece by piece: faster than gathering column by
    column over the whole mesh, or than comparing 20-byte numpy voids."""
    tables = [np.ascontiguousarray(table, dtype=np.float32).view(np.uint32)
              for table in (mesh.corner_normal, mesh.corner_uv)]
    pieces = []
    for low in range(0, representative_corner.shape[0], _SEAM_CHUNK):
        rows = representative_corner[low:low + _SEAM_CHUNK]
        differs = np.zeros(rows.shape[0], bool)
        for bits in tables:
            unequal = bits[low:low + _SEAM_CHUNK] != np.take(bits, rows, axis=0)
            for column in range(bits.shape[1]):
                differs |= unequal[:, column]
        pieces.append(np.flatnonzero(differs) + low)
    return np.concatenate(pieces) if pieces else np.zeros(0, np.int64)


def edge_rows(mesh: Mesh, width: int) -> np.ndarray:
    """(C,) EDGE_ROW: every polygon corner's position and the texel of its polygon in edge_faces's
    textures of `width` texels a row.

    The back-face test (made at the polygon's first vertex, SPEC 4) needs the polygon at both ends
    of each edge, and an edge's first end is not its polygon's first vertex, so the polygon is looked
    up rather than taken from the provoking vertex. One row per corner, not per edge end:
    edge_pairs index them, two per edge.
    """
    faces = np.arange(mesh.face_count, dtype=INDEX)
    texels = np.empty((mesh.face_count, 2), np.uint16)
    texels[:, 0], texels[:, 1] = faces % width, faces // width
    out = np.empty(mesh.corner_vertex.shape[0], EDGE_ROW)
    out["position"] = np.take(mesh.gpu_positions().astype(np.float32), mesh.corner_vertex, axis=0)
    out["face_texel"] = np.repeat(texels, mesh.face_sizes, axis=0)
    return out


def edge_faces(mesh: Mesh, shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """(height, width, 3) float32 twice, of edge_face_shape's `shape`: each polygon's first vertex
    and its face normal, polygon f at texel (f % width, f // width), the rest of the last row zeros."""
    width, height = shape
    points, normals = (np.zeros((height * width, 3), np.float32) for _ in range(2))
    points[:mesh.face_count] = np.take(mesh.gpu_positions(), mesh.corner_vertex[mesh.face_start[:-1]], axis=0)
    normals[:mesh.face_count] = mesh.face_normals
    return points.reshape(height, width, 3), normals.reshape(height, width, 3)


def edge_face_shape(faces: int, max_side: int) -> tuple[int, int]:
    """(width, height) of edge_faces's textures: one row where the polygons fit in one, else rows as
    wide as GL takes."""
    width = max(1, min(faces, max_side, EDGE_FACE_TEXTURE_SIDE))
    return width, max(1, -(-faces // width))


def edge_pairs(mesh: Mesh) -> np.ndarray:
    """(2E,) uint32: each polygon's boundary as pairs of edge_rows, polygon by polygon."""
    return mesh.edge_corners().reshape(-1).view(np.uint32)  # corner numbers: never negative


def used_shared_rows(mesh: Mesh, shared_rows: int) -> np.ndarray:
    """(R,) uint32: the surface's shared rows that some corner reads (SurfaceArrays): the rows of the
    positions faces use, then every seam row. Each vertex normal is drawn once from these."""
    used = np.zeros(mesh.vertex_count, bool)
    used[mesh.corner_vertex] = True
    seam_rows = np.arange(mesh.vertex_count, shared_rows)
    return np.concatenate([np.flatnonzero(used), seam_rows]).astype(np.uint32)


def face_normal_feet(mesh: Mesh) -> np.ndarray:
    """(F, 3) float32: each polygon's centroid, the foot of its face normal."""
    corner_positions = np.take(mesh.gpu_positions(), mesh.corner_vertex, axis=0)
    centroids = np.add.reduceat(corner_positions, mesh.face_start[:-1], axis=0)
    centroids /= mesh.face_sizes[:, None]
    return centroids.astype(np.float32)


@dataclass(frozen=True)
class DrawnArrays:
    """What a MeshGpu is built from, made from the Mesh it draws (a material's part is made for this
    and dropped after: Mesh.part_mesh): the surface's arrays, the fans before each of its polygons
    (Mesh.triangles_before_face), which turn ranges of faces into ranges of rows, and its size."""

    surface: SurfaceArrays
    triangles_before: np.ndarray
    size: float


def drawn_arrays(drawn: Mesh) -> DrawnArrays:
    return DrawnArrays(surface_arrays(drawn), drawn.triangles_before_face(), drawn.size)


# Arrays made ahead of time, off the render thread (the window's loader thread), waiting for their
# object's first frame, by mesh and part. Weak keys: a mesh dropped before it is drawn takes them with it.
_prepared_surfaces: weakref.WeakKeyDictionary[Mesh, dict[int, DrawnArrays]] = weakref.WeakKeyDictionary()
_prepared_lock = threading.Lock()


def prepare_surface(mesh: Mesh) -> None:
    """Builds the arrays of what the mesh is drawn as now (each material's part, or the mesh), so that
    its first frame only uploads them."""
    for part in mesh.drawn_parts():
        data = drawn_arrays(mesh.part_mesh(part))
        with _prepared_lock:
            _prepared_surfaces.setdefault(mesh, {})[part] = data


def _take_prepared_surface(mesh: Mesh, part: int) -> DrawnArrays | None:
    with _prepared_lock:
        held = _prepared_surfaces.get(mesh)
        taken = None if held is None else held.pop(part, None)
        if held == {}:
            del _prepared_surfaces[mesh]
        return taken


_ATTRIBUTE_FORMAT = re.compile(r"(\d*)([fiux])(\d?)")
_DEFAULT_COMPONENT_BYTES = {"f": 4, "i": 4, "u": 4, "x": 1}


def attribute_bytes(fmt: str) -> int:
    """The bytes of one attribute of a moderngl buffer format ("3f", "2u2", "4f1", "12x"): moderngl
    parses these only in its C code."""
    match = _ATTRIBUTE_FORMAT.fullmatch(fmt)
    if match is None:
        raise ValueError(f"not an attribute format: {fmt!r}")
    count, kind, size = match.groups()
    return int(count or 1) * (int(size) if size else _DEFAULT_COMPONENT_BYTES[kind])


def row_bytes(layout: tuple[str, ...]) -> int:
    """The bytes of one row of a layout (its attributes interleaved)."""
    return sum(attribute_bytes(fmt) for fmt in layout[0].split())


def attribute_offset(layout: tuple[str, ...], name: str) -> int:
    """Where attribute `name` starts in a row of `layout`, in bytes."""
    formats, names = layout[0].split(), layout[1:]
    return sum(attribute_bytes(fmt) for fmt in formats[:names.index(name)])


COLOUR_ROW_BYTES = row_bytes(COLOUR_LAYOUT)
LIT_ROW_BYTES = row_bytes(LIT_LAYOUT)
SURFACE_ROW_BYTES = row_bytes(SURFACE_LAYOUT)
# The compute lighting pass (surface.glsl's COMPUTE_SHADER block): rows per work group, and where the
# rows it reads and writes are.
LIGHTING_GROUP_ROWS = 64
LIGHTING_BINDINGS = ("surface", "colours", "lit")  # storage buffer binding points 0, 1, 2
LIGHTING_DEFINES = {
    "LIGHTING_GROUP_ROWS": str(LIGHTING_GROUP_ROWS),
    **{f"{name.upper()}_BINDING": str(binding) for binding, name in enumerate(LIGHTING_BINDINGS)},
    "SURFACE_ROW_FLOATS": str(SURFACE_ROW_BYTES // 4),
    "POSITION_AT": str(attribute_offset(SURFACE_LAYOUT, "in_position") // 4),
    "NORMAL_AT": str(attribute_offset(SURFACE_LAYOUT, "in_normal") // 4),
}
# Below this many rows transform feedback lights quicker: llvmpipe wakes its threads for each dispatch
# (about 0.1 ms), in which it lights some 4,000 rows by transform feedback.
COMPUTE_LIGHTING_MIN_ROWS = 1 << 13
# A window starts at a multiple of this many rows: then its offset into each buffer is a multiple of
# 256 bytes, the most GL 4.3 lets SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT be.
_WINDOW_ALIGN_ROWS = math.lcm(*(256 // math.gcd(256, size) for size in
                                (SURFACE_ROW_BYTES, COLOUR_ROW_BYTES, LIT_ROW_BYTES)))


def lighting_window_rows(ctx: moderngl.Context) -> int:
    """The most rows one dispatch of the compute lighting pass binds: within the largest storage
    block GL takes and the most work groups of one dispatch, a whole number of aligned runs."""
    info = ctx.info
    rows = min(int(info["GL_MAX_SHADER_STORAGE_BLOCK_SIZE"]) // SURFACE_ROW_BYTES,
               int(info["GL_MAX_COMPUTE_WORK_GROUP_COUNT"][0]) * LIGHTING_GROUP_ROWS)
    return max(rows - rows % _WINDOW_ALIGN_ROWS, _WINDOW_ALIGN_ROWS)


# After a compute pass: draws read the lit rows as vertices, transform feedback and compute passes
# write them again, and tests read them back.
_AFTER_COMPUTE_LIGHTING = (moderngl.VERTEX_ATTRIB_ARRAY_BARRIER_BIT | moderngl.TRANSFORM_FEEDBACK_BARRIER_BIT
                           | moderngl.SHADER_STORAGE_BARRIER_BIT | moderngl.BUFFER_UPDATE_BARRIER_BIT)


@dataclass(frozen=True)
class ComputeLighting:
    """The lighting passes as compute programs, which llvmpipe runs on all its threads, and the most
    rows one of their dispatches binds (lighting_window_rows)."""

    programs: Mapping[Shading, moderngl.ComputeShader]
    window_rows: int

    @staticmethod
    def takes(first: int, stop: int) -> bool:
        """Whether the rows [first, stop) are worth a compute pass (COMPUTE_LIGHTING_MIN_ROWS)."""
        return stop - first >= COMPUTE_LIGHTING_MIN_ROWS

    def run(self, ctx: moderngl.Context, shading: Shading, surface: moderngl.Buffer,
            colours: moderngl.Buffer | None, lit: moderngl.Buffer, first: int, stop: int) -> None:
        """Lights the rows [first, stop) of the surface, colour and lit buffers (LIGHTING_BINDINGS), of
        which a window of rows is bound at a time."""
        program = self.programs[shading]
        buffers = (surface, surface if colours is None else colours, lit)  # without colours, a binding left unread
        bound = list(zip(buffers, (SURFACE_ROW_BYTES, COLOUR_ROW_BYTES, LIT_ROW_BYTES), strict=True))
        for base in range(first - first % _WINDOW_ALIGN_ROWS, stop, self.window_rows):
            rows = min(self.window_rows, stop - base)
            for binding, (buffer, size) in enumerate(bound):
                buffer.bind_to_storage_buffer(binding, offset=base * size, size=rows * size)
            program["u_first_row"].value = max(first - base, 0)
            program["u_stop_row"].value = rows
            program.run(-(-rows // LIGHTING_GROUP_ROWS))
        ctx.memory_barrier(_AFTER_COMPUTE_LIGHTING)


def layout_for(program: moderngl.Program, layout: tuple[str, ...]) -> tuple[str, ...]:
    """`layout` with the attributes `program` does not read (its compiler dropped them) skipped."""
    formats, names = layout[0].split(), layout[1:]
    kept_formats, kept_names = [], []
    for fmt, name in zip(formats, names):
        if name in program:
            kept_formats.append(fmt)
            kept_names.append(name)
        else:
            kept_formats.append(f"{attribute_bytes(fmt)}x")
    return (" ".join(kept_formats), *kept_names)


# --- GL buffers for one object -----------------------------------------------------------------
@dataclass(frozen=True)
class VertexRange:
    first: int
    vertices: int


@dataclass(frozen=True)
class Programs:
    """The programs an object's vertex arrays are bound to: one surface program per SurfaceWay, the
    lighting pass of the shadings that light vertices, edges, normals; and where compute programs light
    large passes quicker (lights_by_compute), the lighting passes as compute programs too."""

    surfaces: dict[SurfaceWay, moderngl.Program]  # the depth view's added by the renderer when first drawn
    lightings: Mapping[Shading, moderngl.Program]
    edges: moderngl.Program
    normals: moderngl.Program
    outline: moderngl.Program  # the probe's: the edges' rows and pairs, one colour (outline.glsl)
    compute_lighting: ComputeLighting | None = None  # llvmpipe's, for passes of COMPUTE_LIGHTING_MIN_ROWS or more

    def lighting_passes(self, shading: Shading) -> list[moderngl.Program | moderngl.ComputeShader]:
        """The lighting passes of `shading`: by transform feedback, and by compute where there is one."""
        compute = [] if self.compute_lighting is None else [self.compute_lighting.programs[shading]]
        return [self.lightings[shading], *compute]


@dataclass(frozen=True)
class LitRows:
    """Rows of the lit buffer written by one lighting pass, and the uniform values it ran with."""

    inputs: Hashable
    first: int
    stop: int

    def cover(self, inputs: Hashable, first: int, stop: int) -> bool:
        return self.first <= first and stop <= self.stop and self.inputs == inputs


def lit_row_range(shading: Shading, shared_rows: int, start: int, stop: int) -> tuple[int, int]:
    """The rows [first, stop) the lighting pass of `shading` lights for the faces [start, stop) of a
    mesh whose polygons' own rows follow its `shared_rows` (SurfaceArrays).

    Flat reads the polygons' own rows, one contiguous run per range of faces; Gouraud reads shared
    rows from anywhere in the mesh, so it lights all of them.
    """
    if shading is Shading.FLAT:
        return shared_rows + start, shared_rows + stop
    return 0, shared_rows


class MeshGpu:
    """The buffers and vertex arrays of one mesh, or of one material's part of it (Mesh.parts), that no
    object's placement changes, shared by every object drawing it (a scene file may place one model a
    thousand times): the surface's vertex, index and colour buffers, the lighting passes' vertex arrays
    (which write into each object's own lit buffer), and the edges and normal segments.

    The surface is built with the first object; edges and normal segments only when lines or normals
    are first drawn (most models are never seen that way, and those arrays are bigger than the
    surface's), then kept while an object uses the mesh (MeshGpus). Each is built from the part's
    Mesh made anew (Mesh.part_mesh) and dropped: on the CPU only the whole mesh's tables are held.
    """

    # surface: a vertex and two index buffers, a vertex array per transform-feedback lighting pass (2;
    # a compute pass has none); edges: a row and an index buffer, a vertex array and two textures of
    # polygons; face normals: a buffer and a vertex array; vertex normals: a buffer of used rows and its
    # vertex array, and a vertex array over the surface indices for a range of faces. Vertex colours
    # add one buffer.
    GL_OBJECTS = 15

    def __init__(self, ctx: moderngl.Context, mesh: Mesh, programs: Programs, part: int = WHOLE) -> None:
        self.ctx = ctx
        self.mesh = mesh  # the mesh these buffers were built from: a replaced mesh means rebuilding
        self.part = part  # which of its parts (Mesh.part_mesh)
        self.programs = programs
        self.users = 0  # the ObjectGpus drawing from these buffers (MeshGpus releases them with the last)
        # By name: a buffer and the vertex array drawing it (either may be None: vertex normals own no
        # buffer, the edges' rows are drawn through the edges' index buffer's vertex array).
        self._built: dict[str, tuple[moderngl.Buffer | None, moderngl.VertexArray | None]] = {}
        self._edge_faces: dict[str, moderngl.Texture] = {}  # by EDGE_FACE_UNITS's sampler names, with the edges
        self.offset = bool(mesh.gpu_origin.any())  # whether its rows are measured from elsewhere than the origin
        drawn = _take_prepared_surface(mesh, part) or drawn_arrays(mesh.part_mesh(part))
        self.triangles_before = drawn.triangles_before  # kept so drawing allocates nothing
        self.size = drawn.size
        arrays = drawn.surface
        self.rows = arrays.vertices.shape[0]
        self.shared_rows = arrays.shared_rows
        self.buffers: dict[str, moderngl.Buffer] = {}  # by SurfaceArrays.arrays' names
        self._lightings: dict[Shading, moderngl.VertexArray] = {}
        ctx.error  # noqa: B018 - reading it clears an older error, so the check below is about these uploads
        try:
            for name, data in arrays.arrays.items():
                self.buffers[name] = device_buffer(ctx, data)
            check_gl(ctx, f"the vertex buffers of {mesh.name}")
        except Exception:
            self.release()
            raise

    @property
    def face_count(self) -> int:
        return int(self.triangles_before.shape[0] - 1)

    def _drawn_mesh(self) -> Mesh:
        """The Mesh these buffers draw, made anew (Mesh.part_mesh) for the arrays built on first use."""
        return self.mesh.part_mesh(self.part)

    @property
    def vertex_coloured(self) -> bool:
        return "colours" in self.buffers

    def surface_content(self, program: moderngl.Program, lit: moderngl.Buffer | None = None) -> list[tuple]:
        """The surface's vertex buffers `program` reads: the rows, the lit buffer `lit` where it reads
        lit rows (Phong lights per pixel and reads none), the colours where the mesh has them."""
        content = [(self.buffers["surface"], *layout_for(program, SURFACE_LAYOUT))]
        if lit is not None and LIT_LAYOUT[1] in program:
            content.append((lit, *LIT_LAYOUT))
        if "colours" in self.buffers and COLOUR_LAYOUT[1] in program:
            content.append((self.buffers["colours"], *COLOUR_LAYOUT))
        return content

    def lighting(self, shading: Shading) -> moderngl.VertexArray:
        """Every surface row once, no indices, bound to the transform-feedback lighting pass of
        `shading`: the pass writes into the lit buffer it is given."""
        vao = self._lightings.get(shading)
        if vao is None:
            program = self.programs.lightings[shading]
            vao = self._lightings[shading] = self.ctx.vertex_array(program, self.surface_content(program))
        return vao

    @property
    def edges(self) -> moderngl.VertexArray:
        """Drawn as indexed LINES: edge_pairs into edge_rows, with the polygon textures bound
        (use_edge_faces)."""
        built = self._built.get("edges")
        if built is None:
            max_side = max_texture_side(self.ctx)
            shape = edge_face_shape(self.face_count, max_side)
            if shape[1] > max_side:  # refused before any table is made
                raise ViewerError(f"{self.mesh.name} has more polygons ({self.face_count}) than this "
                                  "OpenGL can draw the edges of")
            drawn = self._drawn_mesh()
            textures = self._face_textures(drawn, shape)
            rows = None
            try:
                rows = device_buffer(self.ctx, edge_rows(drawn, shape[0]))
                content = [(rows, *EDGE_LAYOUT)]
                built = self._build("edges", edge_pairs(drawn), self.programs.edges, content, indexed=True)
            except Exception:
                for resource in (rows, *textures.values()):
                    if resource is not None:
                        resource.release()
                raise
            self._built["edge rows"] = (rows, None)
            self._edge_faces = textures
        return built[1]

    @property
    def outline(self) -> moderngl.VertexArray:
        """The edges' rows and pairs bound to the outline program, drawn as indexed LINES like `edges`."""
        built = self._built.get("outline")
        if built is None:
            self.edges  # noqa: B018 - builds the rows and pairs both draw
            rows, pairs = self._built["edge rows"][0], self._built["edges"][0]
            vao = self.ctx.vertex_array(self.programs.outline, [(rows, *OUTLINE_LAYOUT)], index_buffer=pairs,
                                        index_element_size=4)
            built = self._built["outline"] = (None, vao)
        return built[1]

    def use_edge_faces(self) -> None:
        """Binds the polygon textures the edges program reads (after `edges` has built them)."""
        for sampler, texture in self._edge_faces.items():
            texture.use(location=EDGE_FACE_UNITS[sampler])

    def _face_textures(self, drawn: Mesh, shape: tuple[int, int]) -> dict[str, moderngl.Texture]:
        textures: dict[str, moderngl.Texture] = {}
        self.ctx.error  # noqa: B018 - as in __init__: the check below is about these uploads only
        try:
            for sampler, table in zip(EDGE_FACE_UNITS, edge_faces(drawn, shape)):
                textures[sampler] = texture = device_texture(self.ctx, shape, 3, table, "f4")
                texture.filter = (moderngl.NEAREST, moderngl.NEAREST)  # no mipmaps: else GL holds it incomplete
            check_gl(self.ctx, f"the polygons of {self.mesh.name}")
        except Exception:
            for texture in textures.values():
                texture.release()
            raise
        return textures

    @property
    def face_normals(self) -> moderngl.VertexArray:
        """Drawn as POINTS, one per polygon: its foot from a buffer of feet, its direction from the
        polygon's own surface row, which holds its face normal already (SurfaceArrays)."""
        built = self._built.get("face normals")
        if built is None:
            built = self._build("face normals", face_normal_feet(self._drawn_mesh()), self.programs.normals,
                                FACE_NORMAL_LAYOUT)
            polygon_normals = self.shared_rows * SURFACE_ROW_BYTES + attribute_offset(SURFACE_LAYOUT, "in_normal")
            built[1].bind(self.programs.normals["in_direction"].location, "f", self.buffers["surface"],
                          "3f", offset=polygon_normals, stride=SURFACE_ROW_BYTES)
        return built[1]

    def vertex_normals(self, start: int, stop: int) -> tuple[moderngl.VertexArray, VertexRange]:
        """Drawn as POINTS, reading the surface's rows (no new vertex buffer): the whole mesh draws each
        row it uses once; a range of faces (one face, or up to the probed one) each of its triangles'
        corners, through the shared surface indices."""
        if start == 0 and stop == self.face_count:  # a row is shared by ~6 triangles: 6x fewer segments
            rows, vao = self._built.get("vertex normal rows") or self._build(
                "vertex normal rows", used_shared_rows(self._drawn_mesh(), self.shared_rows), self.programs.normals,
                self._normal_content(), indexed=True)
            return vao, VertexRange(0, rows.size // 4 if rows is not None else 0)  # uint32 indices
        built = self._built.get("vertex normals")
        if built is None:
            vao = self.ctx.vertex_array(self.programs.normals, self._normal_content(),
                                        index_buffer=self.buffers["shared surface indices"], index_element_size=4)
            built = self._built["vertex normals"] = (None, vao)
        return built[1], self.surface_range(start, stop)

    @property
    def byte_sizes(self) -> dict[str, int]:
        """The bytes of each buffer built so far by name ("surface" and "surface indices", "edges", ...),
        and of the edges' polygon textures ("edge faces")."""
        built = {name: buffer for name, (buffer, _) in self._built.items() if buffer is not None}
        sizes = {name: buffer.size for name, buffer in {**self.buffers, **built}.items()}
        if self._edge_faces:
            sizes["edge faces"] = sum(texture.width * texture.height * texture.components
                                      * np.dtype(texture.dtype).itemsize for texture in self._edge_faces.values())
        return sizes

    def _normal_content(self) -> list[tuple]:
        return [(self.buffers["surface"], *layout_for(self.programs.normals, VERTEX_NORMAL_LAYOUT))]

    def _build(self, name: str, data: np.ndarray, program: moderngl.Program, layout: tuple[str, ...] | list[tuple],
               indexed: bool = False) -> tuple[moderngl.Buffer | None, moderngl.VertexArray]:
        """Uploads `data`, as the vertex array's own vertices (`layout`) or, `indexed`, as indices into
        the vertex buffers `layout` lists."""
        self.ctx.error  # noqa: B018 - as in __init__: the check below is about this upload only
        buffer = device_buffer(self.ctx, data)
        try:
            check_gl(self.ctx, f"the {name} of {self.mesh.name}")
            if indexed:
                vao = self.ctx.vertex_array(program, layout, index_buffer=buffer, index_element_size=4)
            else:
                vao = self.ctx.vertex_array(program, [(buffer, *layout)])
        except Exception:
            buffer.release()
            raise
        self._built[name] = (buffer, vao)
        return buffer, vao

    def release(self) -> None:
        for vao in self._lightings.values():
            vao.release()
        for buffer in self.buffers.values():
            buffer.release()
        for buffer, vao in self._built.values():
            for resource in (vao, buffer):
                if resource is not None:
                    resource.release()
        for texture in self._edge_faces.values():
            texture.release()
        self._edge_faces.clear()
        self._lightings.clear()
        self.buffers.clear()
        self._built.clear()

    # Vertex ranges of the faces [start, stop): every array above is laid out polygon by polygon
    # (the surface's are ranges of its indices).
    def surface_range(self, start: int, stop: int) -> VertexRange:
        before = self.triangles_before
        return VertexRange(3 * int(before[start]), 3 * int(before[stop] - before[start]))

    def edge_range(self, start: int, stop: int) -> VertexRange:
        # An edge per corner, two indices each; a polygon has two corners more than fans.
        first, past = int(self.triangles_before[start]) + 2 * start, int(self.triangles_before[stop]) + 2 * stop
        return VertexRange(2 * first, 2 * (past - first))

    def face_normal_range(self, start: int, stop: int) -> VertexRange:
        return VertexRange(start, stop - start)


class ObjectGpu:
    """What one scene object holds of its own beside its mesh's shared buffers (`shared`): a lit
    buffer, a colour per surface row written by the lighting pass from the object's placement, material
    and the lights, kept until what lighting reads changes (light); and the surface's vertex arrays that
    read it.
    """

    # The lit buffer, and a vertex array per surface program (3 lit, 3 of the depth view).
    GL_OBJECTS = 7
    # Which index buffer each surface program draws with (see SurfaceArrays).
    INDICES = {Shading.FLAT: "surface indices", Shading.GOURAUD: "shared surface indices",
               Shading.PHONG: "shared surface indices"}

    def __init__(self, shared: MeshGpu) -> None:
        self.shared = shared
        ctx = shared.ctx
        ctx.error  # noqa: B018 - reading it clears an older error, so the check below is about this buffer
        # Zeros, not undefined memory: rows no pass has lit yet are read (never shown) by draws.
        self.lit = zeroed_device_buffer(ctx, shared.rows * LIT_ROW_BYTES)
        try:
            check_gl(ctx, f"the lit rows of {shared.mesh.name}")
        except Exception:
            self.lit.release()
            raise
        self._surfaces: dict[SurfaceWay, moderngl.VertexArray] = {}
        self._lit: dict[Shading, LitRows] = {}
        # (the model and frame origin's bytes, u_model's, u_normal_matrix's) as last drawn: Renderer._set_model
        self.placement: tuple[bytes, bytes, bytes] | None = None
        shared.users += 1

    @property
    def mesh(self) -> Mesh:
        return self.shared.mesh

    def surface(self, way: SurfaceWay) -> moderngl.VertexArray:
        """The surface bound to the program of `way`, indexed, reading this object's lit rows where the
        program does; each is made the first time that way is drawn."""
        vao = self._surfaces.get(way)
        if vao is None:
            shared = self.shared
            program = shared.programs.surfaces[way]
            vao = self._surfaces[way] = shared.ctx.vertex_array(
                program, shared.surface_content(program, self.lit),
                index_buffer=shared.buffers[self.INDICES[way.shading]], index_element_size=4)
        return vao

    def light(self, shading: Shading, inputs: Hashable, start: int, stop: int) -> bool:
        """Lights the rows the faces [start, stop) take their colour from, with the lighting pass of
        `shading` (Flat or Gouraud) whose uniforms are already set; `inputs` are those
        uniforms' values. Rows already lit with the same inputs are not lit again: a still frame
        runs no pass. Returns whether the pass ran.

        Which rows those are: lit_row_range.
        """
        first, stop_row = lit_row_range(shading, self.shared.shared_rows, start, stop)
        done = self._lit.get(shading)
        if stop_row <= first or (done is not None and done.cover(inputs, first, stop_row)):
            return False
        compute = self.shared.programs.compute_lighting
        if compute is not None and compute.takes(first, stop_row):
            self._light_by_compute(compute, shading, first, stop_row)
        else:
            self.shared.lighting(shading).transform(self.lit, moderngl.POINTS, vertices=stop_row - first,
                                                    first=first, buffer_offset=first * LIT_ROW_BYTES)
        self._lit[shading] = LitRows(inputs, first, stop_row)
        return True

    def _light_by_compute(self, compute: ComputeLighting, shading: Shading, first: int, stop: int) -> None:
        buffers = self.shared.buffers
        compute.run(self.shared.ctx, shading, buffers["surface"], buffers.get("colours"), self.lit, first, stop)

    def release(self) -> None:
        """Releases what is the object's own; its mesh's buffers are MeshGpus's to release."""
        for vao in self._surfaces.values():
            vao.release()
        self._surfaces.clear()
        self._lit.clear()
        self.lit.release()
        self.shared.users -= 1


class MeshGpus:
    """Each mesh's MeshGpu while an object draws it: built for its first ObjectGpu, released with its last."""

    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        # By the id of its mesh, which it holds (so the id is not reused), and its part.
        self._held: dict[tuple[int, int], MeshGpu] = {}

    def object_gpu(self, mesh: Mesh, programs: Programs, part: int = WHOLE) -> ObjectGpu:
        """A new object's lit buffer and vertex arrays, over its mesh's (its part's) shared buffers."""
        shared = self._held.get((id(mesh), part))
        if shared is None:
            shared = self._held[id(mesh), part] = MeshGpu(self.ctx, mesh, programs, part)
        try:
            return ObjectGpu(shared)
        except Exception:
            self._drop_unused(shared)
            raise

    def release(self, gpu: ObjectGpu) -> None:
        """Releases the object's own buffers, and its mesh's with the last object drawing it."""
        gpu.release()
        self._drop_unused(gpu.shared)

    def _drop_unused(self, shared: MeshGpu) -> None:
        if shared.users == 0:
            del self._held[id(shared.mesh), shared.part]
            shared.release()

    @property
    def held(self) -> list[MeshGpu]:
        return list(self._held.values())
