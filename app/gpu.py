"""GPU side of a mesh: the shader loader and the per-object vertex buffers the renderer draws from.

The vertex arrays are built here with numpy, de-indexed to one vertex per triangle corner (or per
line end), because each corner needs attributes that belong to its polygon (the face normal, the
polygon's first vertex) and GL has no per-primitive attributes. Everything is built once per object
and kept until the object leaves the scene; drawing a subset of faces is a `first`/`vertices` range.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import moderngl
import numpy as np

from app import SHADER_DIR
from app.mesh import Mesh

# Attribute layouts, one per program; the names are the shaders' `in_` attributes.
SURFACE_LAYOUT = ("3f 3f 3f 2f", "in_position", "in_normal", "in_face_normal", "in_uv")
EDGE_LAYOUT = ("3f 3f 3f", "in_position", "in_face_normal", "in_face_point")
NORMAL_LAYOUT = ("3f 3f 1f", "in_position", "in_direction", "in_along")


def load_program(ctx: moderngl.Context, name: str, shader_dir: Path = SHADER_DIR) -> moderngl.Program:
    """Compile `shaders/<name>.glsl`, a single file split by `#if defined VERTEX_SHADER` blocks.

    Same convention as moderngl-window's single-file programs, but moderngl-window's loader wants its
    own window context registered; the screenshot command and the tests run on a bare standalone EGL
    context, so we insert the defines ourselves: after the `#version` line, which must stay first.
    """
    source = (shader_dir / f"{name}.glsl").read_text(encoding="utf-8")
    return ctx.program(
        vertex_shader=_with_define(source, "VERTEX_SHADER"),
        fragment_shader=_with_define(source, "FRAGMENT_SHADER"),
    )


def _with_define(source: str, define: str) -> str:
    version, newline, rest = source.partition("\n")
    if not version.lstrip().startswith("#version"):
        raise ValueError("a shader file must start with its #version line")
    return f"{version}{newline}#define {define}\n{rest}"


# --- numpy: the de-indexed vertex arrays -------------------------------------------------------
def _face_of_corner(mesh: Mesh) -> np.ndarray:
    return np.repeat(np.arange(mesh.face_count), mesh.face_sizes)


def surface_vertices(mesh: Mesh) -> np.ndarray:
    """(3T, 11) float32: position, vertex normal, face normal, uv for every fan-triangle corner.

    The first corner of each fan triangle is its polygon's first vertex, so with the provoking vertex
    set to the first one a `flat` varying carries the value computed at the polygon's first vertex.
    """
    corners = mesh.triangle_corners().reshape(-1)
    faces = np.repeat(mesh.triangle_face(), 3)
    return np.hstack([
        mesh.positions[mesh.corner_vertex[corners]],
        mesh.corner_normal[corners],
        mesh.face_normals[faces],
        mesh.corner_uv[corners],
    ]).astype("f4")


def edge_vertices(mesh: Mesh) -> np.ndarray:
    """(2E, 9) float32: position, face normal, and the polygon's first vertex for every edge end.

    An edge's first end is not its polygon's first vertex, so the back-face test (made at that
    vertex, SPEC 4) gets the point as an attribute instead of relying on the provoking vertex.
    """
    corners = mesh.edge_corners().reshape(-1)
    faces = _face_of_corner(mesh)[corners]
    first_corner = mesh.face_start[:-1][faces]
    return np.hstack([
        mesh.positions[mesh.corner_vertex[corners]],
        mesh.face_normals[faces],
        mesh.positions[mesh.corner_vertex[first_corner]],
    ]).astype("f4")


def face_normal_segments(mesh: Mesh) -> np.ndarray:
    """(2F, 7) float32: each face's normal as a segment from the polygon's centroid."""
    corner_positions = mesh.positions[mesh.corner_vertex]
    centroids = np.add.reduceat(corner_positions, mesh.face_start[:-1], axis=0)
    centroids /= mesh.face_sizes[:, None]
    return _segments(centroids, mesh.face_normals)


def vertex_normal_segments(mesh: Mesh) -> np.ndarray:
    """(2C, 7) float32: every corner's vertex normal as a segment from its vertex (Gouraud's normals)."""
    return _segments(mesh.positions[mesh.corner_vertex], mesh.corner_normal)


def _segments(feet: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Two vertices per segment, both with the foot and direction; `in_along` 0 at the foot, 1 at the tip.

    The shader puts the tip at foot + normalize(world normal) * length, so a segment keeps its
    length in world units whatever the model matrix does to normals.
    """
    count = feet.shape[0]
    per_end = np.hstack([np.repeat(feet, 2, axis=0), np.repeat(directions, 2, axis=0)])
    along = np.tile([0.0, 1.0], count)[:, None]
    return np.hstack([per_end, along]).astype("f4")


# --- GL buffers for one object -----------------------------------------------------------------
@dataclass(frozen=True)
class VertexRange:
    first: int
    vertices: int


@dataclass
class ObjectGpu:
    """The buffers and vertex arrays of one scene object, built once from its mesh."""

    mesh: Mesh  # the mesh these buffers were built from: a replaced mesh means rebuilding
    surface: moderngl.VertexArray
    edges: moderngl.VertexArray
    face_normals: moderngl.VertexArray
    vertex_normals: moderngl.VertexArray
    buffers: tuple[moderngl.Buffer, ...]
    triangles_before: np.ndarray  # mesh.triangles_before_face(), kept so drawing allocates nothing

    @classmethod
    def build(cls, ctx: moderngl.Context, mesh: Mesh, surface_program: moderngl.Program,
              edge_program: moderngl.Program, normal_program: moderngl.Program) -> ObjectGpu:
        buffers = [ctx.buffer(data.tobytes()) for data in (
            surface_vertices(mesh), edge_vertices(mesh),
            face_normal_segments(mesh), vertex_normal_segments(mesh))]
        surface, edges, face_normals, vertex_normals = buffers
        return cls(
            mesh=mesh,
            surface=ctx.vertex_array(surface_program, [(surface, *SURFACE_LAYOUT)]),
            edges=ctx.vertex_array(edge_program, [(edges, *EDGE_LAYOUT)]),
            face_normals=ctx.vertex_array(normal_program, [(face_normals, *NORMAL_LAYOUT)]),
            vertex_normals=ctx.vertex_array(normal_program, [(vertex_normals, *NORMAL_LAYOUT)]),
            buffers=tuple(buffers),
            triangles_before=mesh.triangles_before_face(),
        )

    def release(self) -> None:
        for vao in (self.surface, self.edges, self.face_normals, self.vertex_normals):
            vao.release()
        for buffer in self.buffers:
            buffer.release()

    # Vertex ranges of the faces [start, stop): every array above is laid out polygon by polygon.
    def surface_range(self, start: int, stop: int) -> VertexRange:
        before = self.triangles_before
        return VertexRange(3 * int(before[start]), 3 * int(before[stop] - before[start]))

    def edge_range(self, start: int, stop: int) -> VertexRange:
        return self._corner_range(start, stop)

    def face_normal_range(self, start: int, stop: int) -> VertexRange:
        return VertexRange(2 * start, 2 * (stop - start))

    def vertex_normal_range(self, start: int, stop: int) -> VertexRange:
        return self._corner_range(start, stop)

    def _corner_range(self, start: int, stop: int) -> VertexRange:
        offsets = self.mesh.face_start
        return VertexRange(2 * int(offsets[start]), 2 * int(offsets[stop] - offsets[start]))
