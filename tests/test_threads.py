"""Work in pieces on threads (marraztu.model.threads): the same results, in order, as one thread gives."""

from __future__ import annotations

import threading
import time
import warnings

import numpy as np
import pytest

from marraztu.model import threads
from marraztu.model.build import _CROSS_CHUNK, build_mesh, derive_mesh


def test_each_keeps_the_order_and_raises_the_first_error() -> None:
    assert threads.each(lambda item: item * item, range(50), threads=4) == [item * item for item in range(50)]

    def fails_at_seven(item: int) -> int:
        if item >= 7:
            raise ValueError(f"item {item}")
        return item

    with pytest.raises(ValueError, match="item 7"):
        threads.each(fails_at_seven, range(20), threads=4)


def test_each_on_the_shared_pool_finishes_every_item_before_it_raises() -> None:
    finished: list[int] = []

    def slow_unless_first(item: int) -> int:
        if item == 0:
            raise ValueError("item 0")
        time.sleep(0.01)  # the others still run when the first has failed
        finished.append(item)
        return item

    with pytest.raises(ValueError, match="item 0"):
        threads.each(slow_unless_first, range(6), threads=threads.THREADS if threads.THREADS > 1 else None)
    assert sorted(finished) == ([1, 2, 3, 4, 5] if threads.THREADS > 1 else [])


def test_each_within_each_works_in_its_own_thread(monkeypatch: pytest.MonkeyPatch) -> None:
    """A piece that works in pieces again does so in its own thread: the pool cannot run out of
    threads that wait for it."""
    monkeypatch.setattr(threads, "THREADS", 2)
    monkeypatch.setattr(threads, "_pool", None)
    inner = threads.each(lambda outer: threads.each(lambda item: (outer, item, threading.current_thread().name),
                                                    range(3)), range(4))
    for outer, rows in enumerate(inner):
        assert [row[:2] for row in rows] == [(outer, 0), (outer, 1), (outer, 2)]
        assert len({name for _, _, name in rows}) == 1
    assert threads._pool is not None
    threads._pool.shutdown()


def _mesh_of_several_pieces(sizes: np.ndarray, far: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(14)
    positions = rng.normal(size=(5000, 3)) * (1e37 if far else 1.0)  # far: as far as float32 holds
    corner_vertex = rng.integers(0, positions.shape[0], int(sizes.sum()))
    corner_vertex[:3] = 0  # a zero-area face
    face_start = np.concatenate(([0], np.cumsum(sizes)))
    return positions, corner_vertex, face_start


@pytest.mark.parametrize("mixed", [False, True], ids=["triangles", "mixed sizes"])
@pytest.mark.parametrize("far", [False, True], ids=["near", "far"])
def test_face_normals_on_threads_equal_one_threads_bit_for_bit(mixed: bool, far: bool,
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    """A mesh of several pieces, with a zero-area face: the normals are the one-thread ones exactly,
    and no thread warns."""
    faces = 3 * _CROSS_CHUNK + 17
    sizes = np.random.default_rng(1).integers(3, 7, faces) if mixed else np.full(faces, 3)
    positions, corner_vertex, face_start = _mesh_of_several_pieces(sizes, far)
    results = []
    for count in (1, 4):
        monkeypatch.setattr(threads, "THREADS", count)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            mesh = derive_mesh("m", positions, corner_vertex, face_start, None, None, None, None, ())
        results.append(mesh)
    one, several = results
    assert np.array_equal(one.face_normals, several.face_normals)
    assert np.array_equal(one.normals, several.normals)
    assert np.isfinite(several.face_normals).all()


def test_unit_rows_in_pieces_equal_one_piece_in_either_type(monkeypatch: pytest.MonkeyPatch) -> None:
    """Rows of every kind (long, tiny, zero, NaN, infinite) across pieces of 3 rows on 4 threads: the
    same numbers as in one piece, and as float32 the float64 ones rounded."""
    from marraztu.model.geometry import unit_rows

    vectors = np.random.default_rng(3).normal(size=(40, 3)) * np.logspace(-200, 200, 40)[:, None]
    vectors[[4, 11, 23]] = [[0.0, 0.0, 0.0], [np.nan, 1.0, 0.0], [np.inf, 0.0, 0.0]]
    whole, whole_ok = unit_rows(vectors)
    monkeypatch.setattr(threads, "ROWS_PER_PIECE", 3)
    monkeypatch.setattr(threads, "THREADS", 4)
    for dtype in (np.float64, np.float32):
        pieced, ok = unit_rows(vectors, dtype)
        assert pieced.dtype == dtype and np.array_equal(ok, whole_ok)
        assert pieced.tobytes() == whole.astype(dtype).tobytes()
    assert not whole_ok[[4, 11, 23]].any() and not whole[[4, 11, 23]].any()


@pytest.mark.parametrize("seed", range(6))
def test_zeros_of_both_signs_give_the_same_mesh_in_pieces_as_in_one(seed: int, monkeypatch: pytest.MonkeyPatch) -> None:
    """Positions whose columns hold 0.0 and -0.0 in any order: the bounds, and the bounding-box uvs
    whose sign bits follow them, are those of one piece on one thread, bit for bit."""
    rng = np.random.default_rng(seed)
    positions = np.abs(rng.normal(size=(9000, 3)))  # each column's least is a zero, of either sign
    zeros = rng.random(positions.shape) < 0.3
    positions[zeros] = np.where(rng.random(int(zeros.sum())) < 0.5, 0.0, -0.0)
    faces = np.arange(9000).reshape(-1, 3)
    meshes = []
    for count, rows in ((1, 1 << 16), (4, 7)):
        monkeypatch.setattr(threads, "THREADS", count)
        monkeypatch.setattr(threads, "ROWS_PER_PIECE", rows)
        monkeypatch.setattr(threads, "FEWEST_ROWS_PER_THREAD", rows)
        meshes.append(build_mesh("zeros", positions, faces))
    one, several = meshes
    for low_or_high, other in zip(one.bounds, several.bounds):
        assert low_or_high.tobytes() == other.tobytes()
    assert one.uvs.tobytes() == several.uvs.tobytes() and one.normals.tobytes() == several.normals.tobytes()


def test_arrays_equal_in_pieces_is_array_equal(monkeypatch: pytest.MonkeyPatch) -> None:
    """A piece of rows a thread on 4 threads: a difference in any piece, or in the shape, is seen."""
    monkeypatch.setattr(threads, "THREADS", 4)
    monkeypatch.setattr(threads, "FEWEST_QUICK_ROWS_PER_THREAD", 1)
    table = np.arange(30, dtype=np.int32).reshape(10, 3)
    assert threads.arrays_equal(table, table.copy()) and threads.arrays_equal(table[:0], table[:0])
    for row in (0, 5, 9):
        other = table.copy()
        other[row, 2] += 1
        assert not threads.arrays_equal(table, other)
    assert not threads.arrays_equal(table, table[:9])
    assert not threads.arrays_equal(table.reshape(-1), table.reshape(15, 2))


def test_largest_in_pieces_is_the_largest(monkeypatch: pytest.MonkeyPatch) -> None:
    """A piece of rows a thread on 4 threads, the largest in any piece, negatives only, one value."""
    monkeypatch.setattr(threads, "THREADS", 4)
    monkeypatch.setattr(threads, "FEWEST_QUICK_ROWS_PER_THREAD", 1)
    values = np.random.default_rng(8).integers(-1000, 1000, 41).astype(np.int32)
    for at in (0, 20, 40):
        tall = values.copy()
        tall[at] = 5000
        assert threads.largest(tall) == 5000
    assert threads.largest(-np.abs(values) - 1) == int((-np.abs(values) - 1).max())
    assert threads.largest(np.array([-7])) == -7


@pytest.mark.parametrize("seed", range(5))
def test_weighed_pieces_cover_the_rows_in_order_each_bounded_or_one_heavy_row(seed: int) -> None:
    rng = np.random.default_rng(seed)
    weights = rng.integers(1, 40, 500)
    weights[rng.integers(0, 500, 6)] = 300  # heavier than a piece
    slices = threads.weighed_pieces(weights, 100)
    assert [rows.start for rows in slices] == [0, *[rows.stop for rows in slices[:-1]]]
    assert slices[-1].stop == weights.size
    for rows in slices:
        heavy = weights[rows] > 100
        assert (rows.stop - rows.start == 1) if heavy.any() else weights[rows].sum() <= 100 + 40
