"""1. Loading: a model file to GPU-ready arrays, each (loader, file) in fresh processes, beside peers."""

from __future__ import annotations

import importlib.util
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from marraztu.devtools.bench.config import BenchConfig
from marraztu.devtools.bench.inputs import LoadInput
from marraztu.devtools.bench.report import MEGABYTE, markdown_table, number, progress, ratio

if TYPE_CHECKING:
    from marraztu.model.mesh import Mesh

LOAD_HEADERS = ("file", "triangles", "MB", "loader", "seconds", "of which surface arrays s", "MB/s",
                "peak RSS MB", "warm peak RSS MB", "warm peak ÷ file", "time ÷ ours", "RSS ÷ ours")
# Peers that read OBJ only; trimesh reads every format.
OBJ_ONLY_LOADERS = ("tinyobjloader", "rapidobj")


@dataclass(frozen=True)
class LoadTiming:
    triangles: int
    seconds: float
    surface_seconds: float | None = None


LoadFunction = Callable[[Path], LoadTiming]


def _ours(path: Path) -> LoadFunction:
    if path.suffix == ".obj":  # the other formats' readers never import numba, nor the mesh's compiled loops
        import marraztu.loaders.obj.fast  # noqa: F401  # numba: an import, as the other loaders' are
    from marraztu.loaders.registry import load_model

    def load(path: Path) -> LoadTiming:
        start = time.perf_counter()
        mesh = load_model(path)
        parsed = time.perf_counter()
        gpu_ready_arrays(mesh)
        done = time.perf_counter()
        return LoadTiming(int(mesh.triangles_before_face()[-1]), done - start, done - parsed)
    return load


def gpu_ready_arrays(mesh: Mesh) -> dict[str, np.ndarray]:
    """What a new model costs before its first frame: the surface array `MeshGpu` uploads.

    Edges and normal segments are built only when lines or normals are first drawn (marraztu.render.gpu).
    """
    from marraztu.render.gpu import surface_arrays

    return surface_arrays(mesh).arrays


def _trimesh(_path: Path) -> LoadFunction:
    import trimesh

    def load(path: Path) -> LoadTiming:
        start = time.perf_counter()
        loaded = trimesh.load(str(path), process=False)
        done = time.perf_counter()
        geometries = loaded.geometry.values() if hasattr(loaded, "geometry") else [loaded]
        return LoadTiming(sum(len(g.faces) for g in geometries), done - start)
    return load


def _tinyobjloader(_path: Path) -> LoadFunction:
    import tinyobjloader

    def load(path: Path) -> LoadTiming:
        start = time.perf_counter()
        reader = tinyobjloader.ObjReader()
        if not reader.ParseFromFile(str(path), tinyobjloader.ObjReaderConfig()):
            raise RuntimeError(f"tinyobjloader could not read {path}: {reader.Error()}")
        attrib = reader.GetAttrib()
        # numpy copies of the tables and indices: what a viewer would go on to use.
        attrib.numpy_vertices(), attrib.numpy_normals(), attrib.numpy_texcoords()
        shapes = reader.GetShapes()
        triangles = 0
        for shape in shapes:
            shape.mesh.numpy_indices()
            triangles += len(shape.mesh.numpy_num_face_vertices())
        done = time.perf_counter()
        return LoadTiming(triangles, done - start)
    return load


# Each imports what it needs for reading this file, before the peak-memory baseline.
_LOADER_FACTORIES: dict[str, Callable[[Path], LoadFunction]] = {
    "ours": _ours, "trimesh": _trimesh, "tinyobjloader": _tinyobjloader}


def peak_rss_bytes() -> int:
    """This process's peak resident memory.

    On Linux ru_maxrss is not usable here: execve keeps the larger of the old and new peaks, and the
    old one is the bench process's (fork copies its memory map), which hides a small loader's peak.
    VmHWM is the peak of the current memory map only, which starts at exec.
    """
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return peak if sys.platform == "darwin" else peak * 1024  # Linux reports KiB, macOS bytes


def reset_peak_rss() -> bool:
    """Sets this process's peak RSS to its present RSS (Linux's clear_refs); False where it cannot."""
    try:
        Path("/proc/self/clear_refs").write_text("5")
    except OSError:
        return False
    return True


def load_worker(argv: Sequence[str]) -> int:
    """The child: import the loader, note the peak RSS, load `repeats` times, print JSON. With a
    fourth argument, a one-triangle model: read it first (ours through the compiled reader, as any
    large file before would have), then measure from there."""
    loader, path, repeats = argv[0], Path(argv[1]), int(argv[2])
    load = _LOADER_FACTORIES[loader](path)
    peak_known = True
    if argv[3:]:
        if loader == "ours" and argv[3].endswith(".obj"):
            from marraztu.loaders.obj.fast import load_machine_code

            load_machine_code()  # a file this small would go to the line reader
        else:
            load(Path(argv[3]))
        peak_known = reset_peak_rss()
    pause_s = float(argv[4]) if argv[4:] else 0.0
    baseline = peak_rss_bytes()
    timings = []
    for done in range(repeats):
        if done == 1:
            time.sleep(pause_s)  # as a person looks at one model before opening the next
        timings.append(load(path))
    print(json.dumps({"triangles": timings[0].triangles,
                      "seconds": [t.seconds for t in timings],
                      "surface_seconds": [t.surface_seconds for t in timings],
                      "peak_rss_bytes": peak_rss_bytes() - baseline if peak_known else None}))
    return 0


_WORKER_CODE = ("import sys; from marraztu.devtools.bench.loading import load_worker; "
                "sys.exit(load_worker(sys.argv[1:]))")

# rapidobj's bindings exist for Python 3.12 and later only, so it runs in another interpreter, which
# need not have marraztu: its worker stands alone, measuring as load_worker does.
RAPIDOBJ_PYTHON_VARIABLE = "MARRAZTU_BENCH_RAPIDOBJ_PYTHON"
_RAPIDOBJ_CODE = """
import json, sys, time
from pathlib import Path
import rapidobj
def peak():
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) * 1024
    return 0
path, repeats, peak_known = sys.argv[1], int(sys.argv[2]), True
if sys.argv[3:]:  # a one-triangle model to read first, as load_worker's warm-up
    rapidobj.parse_obj(sys.argv[3])
    try:
        Path("/proc/self/clear_refs").write_text("5")
    except OSError:
        peak_known = False
pause_s = float(sys.argv[4]) if sys.argv[4:] else 0.0
baseline, seconds, triangles = peak(), [], 0
for done in range(repeats):
    if done == 1:
        time.sleep(pause_s)
    start = time.perf_counter()
    result = rapidobj.parse_obj(path)  # triangulated; numpy tables of positions, uvs and indices
    if not result.ok:
        raise SystemExit(f"rapidobj could not read {path}: {result.error_message}")
    triangles = len(result.faces)
    result.vertices, result.texcoords, result.wedge_texcoord_indices
    seconds.append(time.perf_counter() - start)
print(json.dumps({"triangles": triangles, "seconds": seconds, "surface_seconds": [None] * repeats,
                  "peak_rss_bytes": peak() - baseline if peak_known else None}))
"""


@cache
def rapidobj_python() -> str | None:
    """An interpreter that can import rapidobj: $MARRAZTU_BENCH_RAPIDOBJ_PYTHON, this one, or a
    python3.13/3.12 on PATH; None when there is none."""
    candidates = [os.environ.get(RAPIDOBJ_PYTHON_VARIABLE), sys.executable,
                  shutil.which("python3.13"), shutil.which("python3.12")]
    for python in filter(None, candidates):
        try:
            found = subprocess.run([python, "-c", "import rapidobj"], capture_output=True, timeout=60)
        except (OSError, subprocess.TimeoutExpired):
            continue
        if found.returncode == 0:
            return python
    return None


def _worker_command(loader: str, path: Path, repeats: int, warm_up: Path | None = None,
                    pause_s: float | None = None) -> list[str]:
    assert pause_s is None or warm_up is not None, "the pause's argument follows the warm-up's"
    arguments = [str(path), str(repeats), *([str(warm_up)] if warm_up else []),
                 *([str(pause_s)] if pause_s is not None else [])]
    if loader == "rapidobj":
        python = rapidobj_python()
        assert python is not None, "available_loaders keeps rapidobj only where an interpreter has it"
        return [python, "-c", _RAPIDOBJ_CODE, *arguments]
    return [sys.executable, "-c", _WORKER_CODE, loader, *arguments]


def _run_worker(loader: str, path: Path, repeats: int, warm_up: Path | None = None, pause_s: float | None = None,
                environment: dict[str, str] | None = None) -> dict:
    done = subprocess.run(_worker_command(loader, path, repeats, warm_up, pause_s), capture_output=True, text=True,
                          env=None if environment is None else {**os.environ, **environment})
    if done.returncode != 0:
        raise RuntimeError(f"{loader} on {path.name} failed:\n{done.stderr.strip()}")
    return json.loads(done.stdout.strip().splitlines()[-1])


@dataclass
class LoadResult:
    """Every load of one loader and file, over all its processes."""

    triangles: int = 0
    seconds: list[float] = field(default_factory=list)
    surface_seconds: list[float] = field(default_factory=list)
    peak_rss_bytes: list[int] = field(default_factory=list)  # one per process
    first_seconds: list[float] = field(default_factory=list)  # each process's first load
    warm_peak_rss_bytes: list[int] = field(default_factory=list)  # one per warm process

    def add_process(self, loader: str, path: Path, repeats: int) -> None:
        report = _run_worker(loader, path, repeats)
        self.triangles = report["triangles"]
        self.seconds += report["seconds"]
        self.first_seconds.append(report["seconds"][0])
        self.surface_seconds += [s for s in report["surface_seconds"] if s is not None]
        self.peak_rss_bytes.append(report["peak_rss_bytes"])

    def add_warm_process(self, loader: str, item: LoadInput) -> None:
        """One load in a process that has read a one-triangle model of the same format first: the peak a
        file itself costs."""
        peak = _run_worker(loader, item.path, 1, warm_up=item.warm_up)["peak_rss_bytes"]
        if peak is not None:
            self.warm_peak_rss_bytes.append(peak)

    @property
    def median_warm_peak_rss_bytes(self) -> float | None:
        return statistics.median(self.warm_peak_rss_bytes) if self.warm_peak_rss_bytes else None

    @property
    def median_seconds(self) -> float:
        return statistics.median(self.seconds)

    @property
    def median_surface_seconds(self) -> float | None:
        return statistics.median(self.surface_seconds) if self.surface_seconds else None

    @property
    def median_peak_rss_bytes(self) -> float:
        return statistics.median(self.peak_rss_bytes)


def available_loaders(wanted: Sequence[str]) -> tuple[list[str], list[str]]:
    """The wanted loaders that can be imported, and notes for those that cannot."""
    present, notes = [], []
    for name in wanted:
        if name == "rapidobj":
            if rapidobj_python() is not None:
                present.append(name)
            else:
                notes.append(f"rapidobj is left out: its bindings need Python 3.12 or later, and no interpreter "
                             f"here imports it (set {RAPIDOBJ_PYTHON_VARIABLE} to one that does).")
        elif name == "ours" or importlib.util.find_spec(name) is not None:
            present.append(name)
        else:
            notes.append(f"{name} is not installed, so its rows are left out "
                         f"(`pip install 'marraztu[bench]'`, or `'.[bench]'` in a checkout, adds tinyobjloader).")
    return present, notes


def loading_section(config: BenchConfig, inputs: Sequence[LoadInput]) -> list[str]:
    loaders, notes = available_loaders(config.loaders)
    rows: list[list[str]] = []
    firsts: list[str] = []
    for item in inputs:
        obj = item.path.suffix == ".obj"
        results = {loader: LoadResult() for loader in loaders if obj or loader not in OBJ_ONLY_LOADERS}
        for round_number in range(config.rounds):  # in turn, so that all see the machine alike
            for loader, result in results.items():
                progress(f"loading {item.path.name} with {loader} ({round_number + 1}/{config.rounds})")
                result.add_process(loader, item.path, config.repeats)
                result.add_warm_process(loader, item)
        rows += [_load_row(item, loader, result, results.get("ours")) for loader, result in results.items()]
        if "ours" in results and obj:
            firsts.append(f"{item.label}: {number(statistics.median(results['ours'].first_seconds))} s")
    lines = [
        "## 1. Loading: a model file to GPU-ready arrays",
        "",
        f"Median of {config.rounds * config.repeats} load(s): {config.rounds} fresh process(es) per loader and "
        f"file, the loaders taking turns, {config.repeats} load(s) in each; peak RSS is the median over those "
        "processes of the process's peak minus its peak after imports. *Warm peak*: the same in one more "
        "process per round, which first reads a one-triangle model (ours through its compiled reader, as "
        "any earlier large file would have; the reader's own memory is in section 4), so that only what "
        "the file itself costs is left; *÷ file*: that over the file's size. *ours* = `load_model` (the OBJ "
        "reader; for the other formats, whose files trimesh's exporters wrote from the v f only grid, our "
        "STL and OFF readers, or trimesh and our checks for PLY and GLB, in processes without numba, as "
        "in a window that has opened no large OBJ file: their normals by numpy, the OBJ files' by the "
        "compiled loops that load with the OBJ reader) + the surface vertex and index arrays `MeshGpu` "
        "uploads for the first frame (marraztu.render.gpu; edges and normal segments "
        "are built later, when lines or normals are first drawn); trimesh = `trimesh.load(process=False)`; "
        "tinyobjloader = parse (triangulated) + numpy copies of its tables; rapidobj = `parse_obj` "
        "(multi-threaded C++, triangulated; numpy tables of positions, uvs and indices, no normals), in a "
        "Python 3.12+ interpreter of its own. Ratios > 1: ours is faster or smaller.",
        "",
        *markdown_table(LOAD_HEADERS, rows),
        "",
        "*ours*, the first load in each process (median over the processes), which also loads the compiled "
        "reader's machine code from numba's cache (numba itself is imported before the baseline, as the "
        "other loaders are): " + "; ".join(firsts) + ".",
    ]
    return lines + [""] + [f"Note: {note}" for note in notes]


def _load_row(item: LoadInput, loader: str, result: LoadResult, ours: LoadResult | None) -> list[str]:
    mb = item.megabytes
    seconds = result.median_seconds
    warm = None if result.median_warm_peak_rss_bytes is None else result.median_warm_peak_rss_bytes / MEGABYTE
    return [item.label, str(result.triangles), number(mb), loader, number(seconds),
            number(result.median_surface_seconds), number(mb / seconds),
            number(result.median_peak_rss_bytes / MEGABYTE), number(warm), number(None if warm is None else warm / mb),
            ratio(seconds, ours.median_seconds if ours else None),
            ratio(result.median_peak_rss_bytes, ours.median_peak_rss_bytes if ours else None)]


PAUSE_HEADERS = ("file", "loader", "first s", "after a pause s", "right after s", "after a pause ÷ right after",
                 "after a pause: time ÷ ours")
# numpy asks for huge pages for arrays of 4 MB and more unless this says 0.
_SMALL_PAGES = {"NUMPY_MADVISE_HUGEPAGE": "0"}
# A virtio balloon with this feature hands the guest's free memory back to its host (Linux reports
# free blocks of 2 MB and more, two seconds after they are freed); the host makes it up again on use.
_BALLOON_REPORTING_BIT = 5


@dataclass(frozen=True)
class _PausedLoader:
    label: str
    loader: str
    environment: dict[str, str] | None = None


def pause_section(config: BenchConfig, item: LoadInput) -> list[str]:
    """Loads after a pause, as a person makes them: in a fresh process, after the one-triangle warm-up,
    a first load, `config.load_pause_s` seconds idle, the load measured, then one more at once, as the
    loading section's repeats are made."""
    if "ours" not in config.loaders:
        return []
    loaders = [_PausedLoader("ours", "ours"), _PausedLoader("ours, numpy's huge pages off", "ours", _SMALL_PAGES)]
    if "rapidobj" in config.loaders and rapidobj_python() is not None:
        loaders.append(_PausedLoader("rapidobj", "rapidobj"))
    seconds: dict[str, tuple[list[float], ...]] = {run.label: ([], [], []) for run in loaders}
    for round_number in range(config.rounds):
        for run in loaders:
            progress(f"loading {item.path.name} after a pause with {run.label} ({round_number + 1}/{config.rounds})")
            report = _run_worker(run.loader, item.path, 3, item.warm_up, config.load_pause_s, run.environment)
            for kept, measured in zip(seconds[run.label], report["seconds"]):
                kept.append(measured)
    ours = statistics.median(seconds["ours"][1])
    rows = []
    for label, loads in seconds.items():
        first, after_pause, at_once = (statistics.median(each_load) for each_load in loads)
        rows.append([item.label, label, number(first), number(after_pause), number(at_once),
                     ratio(after_pause, at_once), ratio(after_pause, ours)])
    return [
        "### Loading after a pause",
        "",
        f"Median over {config.rounds} fresh process(es) per loader, taking turns: the process reads the "
        f"one-triangle model, loads the file (*first*), waits {config.load_pause_s:g} s, loads it again "
        "(*after a pause*, as a person opens a second model after looking at the first), then once more at "
        "once (*right after*, as the repeats above). *numpy's huge pages off*: ours with "
        "`NUMPY_MADVISE_HUGEPAGE=0`, so that its arrays are made of 4 KB pages. Free memory handed back to "
        f"a virtual machine's host: {free_page_reporting()}.",
        "",
        *markdown_table(PAUSE_HEADERS, rows),
    ]


def free_page_reporting() -> str:
    """Whether this machine's virtio balloon reports free memory to its host, in words."""
    features = sorted(Path("/sys/bus/virtio/drivers/virtio_balloon").glob("virtio*/features"))
    if not features:
        return "no virtio balloon here"
    try:
        bits = features[0].read_text().strip()
    except OSError:
        return "unknown (the virtio balloon's features cannot be read)"
    reporting = len(bits) > _BALLOON_REPORTING_BIT and bits[_BALLOON_REPORTING_BIT] == "1"
    return ("yes: the virtio balloon reports free memory (Linux's free page reporting)" if reporting
            else "no: the virtio balloon does not report free memory")
