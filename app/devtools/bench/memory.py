"""4. Memory: host and GPU bytes per triangle of a loaded mesh."""

from __future__ import annotations

import gc
import json
import os
import statistics
import subprocess
import sys
import time
import tracemalloc
from collections import Counter
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from marraztu.devtools.bench.frames import FrameBench
from marraztu.devtools.bench.inputs import LoadInput
from marraztu.devtools.bench.loading import gpu_ready_arrays
from marraztu.devtools.bench.report import MEGABYTE, markdown_table, number, progress
from marraztu.render.context import is_llvmpipe

if TYPE_CHECKING:
    from marraztu.render.gpu import ObjectGpu

MEMORY_HEADERS = ("file", "triangles", "Mesh B/tri", "GPU-ready arrays B/tri", "GPU when filled B/tri",
                  "GPU with lines and normals B/tri", "edges B/tri", "normals B/tri", "RSS growth, all drawn B/tri",
                  "of which llvmpipe's scene queue B/tri", "compiled reader MB, once", "compiled reader s, once")


# The textured materials of the large grid's copy measured beside it: a part per material, each gathered
# from runs all over the whole's tables (Mesh.part_mesh).
MATERIALS = 8


def memory_row(bench: FrameBench, item: LoadInput, queue_measured: bool = True) -> list[str]:
    triangles, per_triangle = held_per_triangle(bench, item.path)
    growth, reader_bytes, reader_seconds = median_rss_growth(item.path)
    queue = "—"  # a GPU has no such queue, and ignores the variable; or left unmeasured
    if queue_measured and is_llvmpipe(bench.ctx):
        unqueued, _, _ = median_rss_growth(item.path, {"LP_NUM_THREADS": "0"})  # each scene rasterized at once
        queue = number(growth - unqueued)
    return [item.label, str(triangles), *(number(value) for value in per_triangle), number(growth),
            queue, number(reader_bytes / MEGABYTE), number(reader_seconds)]


def held_per_triangle(bench: FrameBench, path: Path) -> tuple[int, list[float]]:
    """The triangles, and the host and GPU bytes per triangle of the first six columns after them."""
    from marraztu.loaders.obj import load_obj
    from marraztu.loaders.obj.fast import load_machine_code
    from marraztu.render.gpu import MeshGpus

    load_machine_code()  # the process's, once (reported apart): its Python objects are not the model's
    gc.collect()
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        mesh = load_obj(path)
        triangles = int(mesh.triangles_before_face()[-1])
        ready = sum(array.nbytes for part in mesh.drawn_parts()
                    for array in gpu_ready_arrays(mesh.part_mesh(part)).values())
        meshes = MeshGpus(bench.ctx)
        programs = bench.renderer.programs
        # Exactly what the renderer allocates for one object: a MeshGpu per material's part, or the whole.
        gpus = [meshes.object_gpu(mesh, programs, part) for part in mesh.drawn_parts()]
        try:
            surface = sum(_gpu_bytes(*gpus).values())  # all there is before lines or normals
            for gpu in gpus:
                shared = gpu.shared
                _ = shared.edges, shared.face_normals, shared.vertex_normals(0, shared.face_count)  # on first use
            sizes = _gpu_bytes(*gpus)
            gc.collect()
            host = tracemalloc.get_traced_memory()[0] - before  # the mesh, its parts, what the renderer keeps
            per_triangle = [value / triangles for value in (
                host, ready, surface, sum(sizes.values()), sizes["edges"] + sizes["edge rows"] + sizes["edge faces"],
                sizes["face normals"] + sizes["vertex normal rows"])]  # vertex normals read the surface's rows
        finally:
            for gpu in gpus:
                meshes.release(gpu)
    finally:
        tracemalloc.stop()
    return triangles, per_triangle


def _gpu_bytes(*gpus: ObjectGpu) -> Counter[str]:
    """The bytes of each kind of buffer the objects' parts hold so far, their lit buffers too."""
    sizes: Counter[str] = Counter()
    for gpu in gpus:
        sizes.update(gpu.shared.byte_sizes)
        sizes["lit"] += gpu.lit.size
    return sizes


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


def memory_section(bench: FrameBench, inputs: Sequence[LoadInput], several: LoadInput) -> list[str]:
    """`several`: the large grid of MATERIALS materials, after `inputs`; its llvmpipe queue is left unmeasured."""
    rows = []
    for item in [*inputs, several]:
        progress(f"memory: {item.path.name}")
        rows.append(memory_row(bench, item, queue_measured=item is not several))
    return [
        "## 4. Memory per triangle of a loaded mesh",
        "",
        "*Mesh*: the host memory Python allocated (tracemalloc's) and still held once the object's "
        "buffers of every kind are built, less before loading: the Mesh's tables, its materials' parts and "
        "what the renderer keeps of each (`triangles_before`), for the object's life. The last file is the "
        f"large v/vt/vn grid again, its rows taking {MATERIALS} textured materials in turn: each is drawn "
        "as a part of its own, gathered from the whole's tables. *GPU-ready arrays*: the surface's vertex "
        "and index arrays made before the first "
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
        "their memory for reuse (none of ours; measured on llvmpipe only, and not for the file of several "
        "materials: the queue is the driver's, and it would add six processes). "
        "*Compiled reader*: what importing numba and loading the OBJ reader's machine code from numba's "
        "cache adds to the same process before that, and how long that takes, once per process whatever "
        "the model (a process whose files are all under 8 MB never pays it: the line reader reads "
        "them).",
        "",
        *markdown_table(MEMORY_HEADERS, rows),
    ]
