"""4. Memory: host and GPU bytes per triangle of a loaded mesh."""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import time
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from marraztu.devtools.bench.frames import FrameBench
from marraztu.devtools.bench.inputs import LoadInput
from marraztu.devtools.bench.loading import gpu_ready_arrays
from marraztu.devtools.bench.report import MEGABYTE, markdown_table, number, progress
from marraztu.render.context import is_llvmpipe

if TYPE_CHECKING:
    from marraztu.model.mesh import Mesh

MEMORY_HEADERS = ("file", "triangles", "Mesh B/tri", "GPU-ready arrays B/tri", "GPU when filled B/tri",
                  "GPU with lines and normals B/tri", "edges B/tri", "normals B/tri", "RSS growth, all drawn B/tri",
                  "of which llvmpipe's scene queue B/tri", "compiled reader MB, once", "compiled reader s, once")


MESH_ARRAYS = ("positions", "corner_vertex", "uvs", "normals", "face_start", "face_normals")


def mesh_bytes(mesh: Mesh) -> int:
    return sum(getattr(mesh, name).nbytes for name in MESH_ARRAYS)


def memory_row(bench: FrameBench, item: LoadInput) -> list[str]:
    from marraztu.loaders.obj import load_obj
    from marraztu.render.gpu import MeshGpus

    mesh = load_obj(item.path)
    triangles = int(mesh.triangles_before_face()[-1])
    ready = sum(array.nbytes for array in gpu_ready_arrays(mesh).values())
    meshes = MeshGpus(bench.ctx)
    gpu = meshes.object_gpu(mesh, bench.renderer.programs)  # exactly what the renderer allocates for one object
    shared = gpu.shared
    try:
        surface = sum(shared.byte_sizes.values()) + gpu.lit.size  # all there is before lines or normals
        _ = shared.edges, shared.face_normals, shared.vertex_normals(0, mesh.face_count)  # built on first use
        sizes = shared.byte_sizes
        sizes["lit"] = gpu.lit.size
        host = mesh_bytes(mesh) + shared.triangles_before.nbytes
        per_triangle = [value / triangles for value in (
            host, ready, surface, sum(sizes.values()), sizes["edges"] + sizes["edge rows"] + sizes["edge faces"],
            sizes["face normals"] + sizes["vertex normal rows"])]  # vertex normals read the surface's rows
    finally:
        meshes.release(gpu)
    growth, reader_bytes, reader_seconds = median_rss_growth(item.path)
    queue = "—"  # a GPU has no such queue, and ignores the variable
    if is_llvmpipe(bench.ctx):
        unqueued, _, _ = median_rss_growth(item.path, {"LP_NUM_THREADS": "0"})  # each scene rasterized at once
        queue = number(growth - unqueued)
    return [item.label, str(triangles), *(number(value) for value in per_triangle), number(growth),
            queue, number(reader_bytes / MEGABYTE), number(reader_seconds)]


def resident_bytes() -> int:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024
    return 0


def rss_worker(argv: Sequence[str]) -> int:
    """The child: RSS after the model is loaded and drawn filled (Flat, Gouraud), in lines and with
    both kinds of normals, less RSS before loading, with the context and renderer already made."""
    from marraztu.devtools.bench.frames import FrameBench, bench_scene, set_mode
    from marraztu.frontends.heap import return_freed_memory
    from marraztu.loaders.obj import load_obj

    bench = FrameBench.open()
    size = (640, 480)
    fbo = bench.ctx.simple_framebuffer(size, components=4)
    bench.renderer.render(bench_scene(None), fbo, size)  # programs compiled, driver warmed
    start, started = resident_bytes(), time.perf_counter()
    from marraztu.loaders.obj.fast import load_machine_code  # numba, imported here: its memory is measured
    load_machine_code()  # once per process, whatever the model: reported apart from the growth
    before, warmed = resident_bytes(), time.perf_counter()
    mesh = load_obj(Path(argv[0]))
    scene = bench_scene(mesh)
    for mode in ("flat", "gouraud", "lines"):
        set_mode(scene, mode)
        for normals in (False, True):
            scene.modes.normals = normals
            bench.renderer.render(scene, fbo, size)
            bench.ctx.finish()
            return_freed_memory()  # as the window does once it is still after a key's frame
    print(json.dumps({"triangles": int(mesh.triangles_before_face()[-1]), "growth": resident_bytes() - before,
                      "compiled_reader": before - start, "compiled_reader_seconds": warmed - started}))
    return 0


_RSS_WORKER = ("import sys; from marraztu.devtools.bench.memory import rss_worker; "
               "sys.exit(rss_worker(sys.argv[1:]))")


RSS_RUNS = 3  # llvmpipe's queue of binned scenes grows with how far its threads fall behind: it varies


def median_rss_growth(path: Path, environment: Mapping[str, str] | None = None) -> tuple[float, int, float]:
    growth, reader_bytes, reader_seconds = zip(*(rss_growth(path, environment) for _ in range(RSS_RUNS)))
    return statistics.median(growth), int(statistics.median(reader_bytes)), statistics.median(reader_seconds)


def rss_growth(path: Path, environment: Mapping[str, str] | None = None) -> tuple[float, int, float]:
    """Bytes per triangle, and the compiled reader's bytes and seconds (once per process), in a fresh
    process, so that nothing this one holds (or freed) blurs the figures; `environment` adds to this
    one's."""
    done = subprocess.run([sys.executable, "-c", _RSS_WORKER, str(path)], capture_output=True, text=True,
                          env={**os.environ, **(environment or {})})
    if done.returncode != 0:
        raise RuntimeError(f"the memory worker failed on {path.name}:\n{done.stderr.strip()}")
    report = json.loads(done.stdout.strip().splitlines()[-1])
    return report["growth"] / report["triangles"], report["compiled_reader"], report["compiled_reader_seconds"]


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
        "frame (host, while uploading). *GPU when filled*: the surface's buffers, all an object holds until "
        "lines or normals are drawn; *with lines and normals*: every buffer and texture it can hold (surface, "
        "edges and their polygon textures, face and vertex normal segments). On llvmpipe GPU buffers live in "
        "host memory too. *RSS growth, all "
        "drawn*: a fresh process's resident memory after loading the file and drawing it in Flat, "
        "Gouraud and lines, each with normals, each frame followed by the hand-back of freed memory the "
        "window makes once it is still, less before loading (context and programs made), median of "
        f"{RSS_RUNS} processes: "
        "everything the object costs the machine, host and (on llvmpipe) GPU. *Of which llvmpipe's "
        "scene queue*: that growth less the same with `LP_NUM_THREADS=0`, where llvmpipe rasterizes each "
        "scene as soon as it is binned instead of queueing binned scenes for its threads and keeping "
        "their memory for reuse (none of ours; measured on llvmpipe only). "
        "*Compiled reader*: what importing numba and loading the OBJ reader's machine code from numba's "
        "cache adds to the same process before that, and how long that takes, once per process whatever "
        "the model (a process whose files are all under 8 MB never pays it: the line reader reads "
        "them).",
        "",
        *markdown_table(MEMORY_HEADERS, rows),
    ]
