"""4. Memory: host and GPU bytes per triangle of a loaded mesh."""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from marraztu.devtools.bench.frames import FrameBench
from marraztu.devtools.bench.inputs import LoadInput
from marraztu.devtools.bench.loading import gpu_ready_arrays
from marraztu.devtools.bench.report import markdown_table, number, progress

if TYPE_CHECKING:
    from marraztu.model.mesh import Mesh

MEMORY_HEADERS = ("file", "triangles", "Mesh B/tri", "GPU-ready arrays B/tri", "GPU when filled B/tri",
                  "GPU with lines and normals B/tri", "edges B/tri", "normals B/tri")


MESH_ARRAYS = ("positions", "corner_vertex", "corner_uv", "corner_normal", "face_start", "face_normals")


def mesh_bytes(mesh: Mesh) -> int:
    return sum(getattr(mesh, name).nbytes for name in MESH_ARRAYS)


def memory_row(bench: FrameBench, item: LoadInput) -> list[str]:
    from marraztu.loaders.obj import load_obj
    from marraztu.render.gpu import ObjectGpu

    mesh = load_obj(item.path)
    triangles = int(mesh.triangles_before_face()[-1])
    ready = sum(array.nbytes for array in gpu_ready_arrays(mesh).values())
    renderer = bench.renderer
    gpu = ObjectGpu(bench.ctx, mesh, renderer.programs)  # exactly what the renderer allocates per object
    try:
        surface = sum(buffer.size for buffer in gpu.buffers.values())  # all there is before lines or normals
        _ = gpu.edges, gpu.face_normals, gpu.vertex_normals  # built on first use: force them here
        sizes = {name: buffer.size for name, buffer in gpu.buffers.items()}
        host = mesh_bytes(mesh) + gpu.triangles_before.nbytes
        per_triangle = [value / triangles for value in (
            host, ready, surface, sum(sizes.values()), sizes["edges"],
            sizes["face normals"] + sizes["vertex normals"])]
    finally:
        gpu.release()
    return [item.label, str(triangles), *(number(value) for value in per_triangle)]


def memory_section(bench: FrameBench, inputs: Sequence[LoadInput]) -> list[str]:
    rows = []
    for item in inputs:
        progress(f"memory: {item.path.name}")
        rows.append(memory_row(bench, item))
    return [
        "## 4. Memory per triangle of a loaded mesh",
        "",
        "*Mesh*: the Mesh's arrays plus the renderer's kept `triangles_before` (host, for the object's "
        "life). *GPU-ready arrays*: the surface's vertex and index arrays made before the first "
        "frame (host, while uploading). *GPU when filled*: the surface's buffers, all an object holds until lines or "
        "normals are drawn; *with lines and normals*: every buffer it can hold (surface, edges, face "
        "and vertex normal segments). On llvmpipe GPU buffers live in host memory too.",
        "",
        *markdown_table(MEMORY_HEADERS, rows),
    ]
