"""The mesh's compiled loops (marraztu.model.compiled) give numpy's normals bit for bit, and take no
array type they were not compiled for."""

from __future__ import annotations

import importlib
import subprocess
import sys
import warnings

import numpy as np
import pytest

from marraztu.model import build, threads
from marraztu.model.build import derive_mesh
from marraztu.model.geometry import column_bounds
from marraztu.model.mesh import INDEX, Mesh

compiled = pytest.importorskip("marraztu.model.compiled", reason="numba is not installed here")
NAME = "marraztu.model.compiled"


def _mesh(shape: str, scale: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Random polygons over 5,000 positions, in pieces of several threads' worth, with a zero-area
    face; far away, one face whose fans' cross products overflow to infinity. `shape`: one size (a number),
    sizes 3 to 8 mixed, or triangles and one polygon of 20,000 corners."""
    rng = np.random.default_rng(len(shape))
    positions = rng.normal(size=(5000, 3)) * scale
    faces = 2 * threads.ROWS_PER_PIECE // 3 + 7
    if shape == "mixed":
        sizes = rng.integers(3, 9, faces)
        sizes[1] = 5
    elif shape == "huge":
        sizes = np.full(faces, 3)
        sizes[faces // 2] = 20_000
    else:
        sizes = np.full(faces, int(shape))
    face_start = np.concatenate(([0], np.cumsum(sizes))).astype(INDEX)
    corner_vertex = rng.integers(0, positions.shape[0] - 3, face_start[-1]).astype(INDEX)
    corner_vertex[:sizes[0]] = 0  # a zero-area face
    if scale > 1.0:  # face 1's first fan's x*y overflows to inf; its second's, where it has one, to -inf
        positions[-3:] = [[1e160, 0.0, 0.0], [0.0, 1e160, 0.0], [1e160, 1e160, 0.0]]
        corner_vertex[face_start[1]:face_start[2]] = ([0, 4997, 4998, 4999] + [4999] * sizes[1])[:sizes[1]]
    return positions, corner_vertex, face_start


def _derived(positions: np.ndarray, corner_vertex: np.ndarray, face_start: np.ndarray) -> Mesh:
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # no overflow or division warning from either way
        return derive_mesh("m", positions, corner_vertex, face_start, None, None, None, None, ())


def _float64_normals(positions: np.ndarray, corner_vertex: np.ndarray, face_start: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The face normals, degenerate faces and per-position sums before they are rounded to float32."""
    sizes = np.diff(face_start)
    faces, degenerate = build._face_normals(positions, corner_vertex, face_start, sizes, column_bounds(positions))
    return faces, degenerate, build._normal_sums(faces, corner_vertex, face_start, sizes, positions.shape[0])


@pytest.mark.parametrize("shape", ["3", "4", "5", str(build.MAX_COLUMN_SIZE), "mixed", "huge"])
@pytest.mark.parametrize("scale", [1.0, 1e37], ids=["near", "far"])
@pytest.mark.parametrize("thread_count", [1, 4])
@pytest.mark.parametrize("fan_block", [build._FAN_BLOCK, 1000], ids=["blocks", "small-blocks"])
def test_compiled_normals_equal_numpys_bit_for_bit(shape: str, scale: float, thread_count: int, fan_block: int,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    """In float64 (the order of the fans' and the per-position sums shows there), and in the mesh. Small
    blocks: numpy's polygons of many sizes in many blocks, the huge one a block of fans at a time, and
    the per-position sums a block of corners at a time, cutting polygons."""
    positions, corner_vertex, face_start = _mesh(shape, scale)
    monkeypatch.setattr(threads, "THREADS", thread_count)
    monkeypatch.setattr(threads, "FEWEST_ROWS_PER_THREAD", 1)
    monkeypatch.setattr(build, "_FAN_BLOCK", fan_block)
    monkeypatch.setattr(build, "_CORNER_BLOCK", fan_block + 1)  # a block's first and last polygons cut
    assert len(threads.one_per_thread(5000)) == thread_count  # the sums' position ranges
    with monkeypatch.context() as without:
        without.delitem(sys.modules, NAME)  # as in a process that has not imported it
        by_numpy = _float64_normals(positions, corner_vertex, face_start)
        mesh_by_numpy = _derived(positions, corner_vertex, face_start)
    calls: list[str] = []
    for loop in ("polygon_normals", "normal_sums"):
        monkeypatch.setattr(compiled, loop, _counted(getattr(compiled, loop), calls, loop))
    by_compiled = _float64_normals(positions, corner_vertex, face_start)
    mesh = _derived(positions, corner_vertex, face_start)
    assert {"polygon_normals", "normal_sums"} <= set(calls)
    for ours, numpys in zip(by_compiled, by_numpy):
        assert ours.tobytes() == numpys.tobytes()  # zeros' signs too
    assert by_compiled[1][0] and by_compiled[1][1] == (scale > 1.0)
    assert mesh.face_normals.tobytes() == mesh_by_numpy.face_normals.tobytes()
    assert mesh.normals.tobytes() == mesh_by_numpy.normals.tobytes()
    assert mesh.warnings == mesh_by_numpy.warnings


def _counted(loop, calls: list[str], name: str):  # noqa: ANN001, ANN202  # numba's dispatcher, wrapped
    def counting(*args: object) -> None:
        calls.append(name)
        loop(*args)
    return counting


@pytest.mark.parametrize("kind", ["float32 positions", "int64 corners", "Fortran-ordered positions",
                                  "read-only positions", "read-only corners"])
def test_arrays_of_other_types_go_to_numpy_and_compile_nothing(kind: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Another format's or the API's own array types are worked on by numpy, as without the loops,
    which keep their one machine code each."""
    importlib.import_module(NAME)
    positions, corner_vertex, face_start = _mesh("mixed", 1.0)
    if kind == "float32 positions":
        positions = positions.astype(np.float32)
    elif kind == "int64 corners":
        corner_vertex = corner_vertex.astype(np.int64)
    elif kind == "Fortran-ordered positions":
        positions = np.asfortranarray(positions)
    else:  # as np.frombuffer gives them
        (positions if kind == "read-only positions" else corner_vertex).flags.writeable = False
    given = _derived(positions, corner_vertex, face_start)
    with monkeypatch.context() as without:
        without.delitem(sys.modules, NAME)
        by_numpy = _derived(positions, corner_vertex, face_start)
    assert given.normals.tobytes() == by_numpy.normals.tobytes()
    assert [len(loop.signatures) for loop in (compiled.polygon_normals, compiled.normal_sums)] == [1, 1]


def test_the_compiled_reader_reads_where_the_loops_cannot_load() -> None:
    """The loops load with the OBJ reader's passes, but the reader does not depend on them."""
    code = ("import sys\nsys.modules['marraztu.model.compiled'] = None  # its import fails\n"
            "from marraztu.loaders.obj import fast\n"
            "raw = fast.read_fast(b'v 0 0 0\\nv 1 0 0\\nv 0 1 0\\nf 1 2 3\\n', 'one triangle')\n"
            "print(raw.face_start.size - 1, sys.modules['marraztu.model.compiled'])")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split() == ["1", "None"]
