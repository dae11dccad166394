"""The mesh's two costliest loops, compiled by numba: the polygon normals and the vertex-normal sums
of a mesh whose polygons all have one size.

marraztu.model.build uses them only where this module is imported already: the OBJ reader imports it
with its own compiled passes, on a thread while the file is read, because importing numba for one
mesh costs more than it saves. They give build's numpy code's results bit for bit: the same
operations in the same order, in one pass without the temporaries, and without the GIL, so that
pieces run on threads at once. The signatures are given, so importing this module loads the machine
code (from numba's cache) and no other array type is ever compiled.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# (positions (V, 3), polygons (F, k), smallest length, first and end polygon, normals (F, 3), degenerate (F,))
_NORMALS = "void(float64[:, ::1], int32[:, ::1], float64, int64, int64, float64[:, ::1], boolean[::1])"
# (face normals (F, 3), polygons (F, k), first and end position, sums (V, 3), one column's sums (end - first, 3))
_SUMS = "void(float64[:, ::1], int32[:, ::1], int64, int64, float64[:, ::1], float64[:, ::1])"


@njit(_NORMALS, nogil=True, cache=True)
def polygon_normals(positions: np.ndarray, polygons: np.ndarray, smallest: float, first: int, end: int,
                    normals: np.ndarray, degenerate: np.ndarray) -> None:
    """Unit normals of polygons first..end: the sum of their fans' (p_i - p_0) x (p_(i+1) - p_0) in fan
    order, made unit; zero, and degenerate, where its length is not finite or at most `smallest`."""
    for polygon in range(first, end):
        corners = polygons[polygon]
        origin = corners[0]
        x0, y0, z0 = positions[origin, 0], positions[origin, 1], positions[origin, 2]
        sx = sy = sz = 0.0
        for fan in range(1, corners.shape[0] - 1):
            a, b = corners[fan], corners[fan + 1]
            ax, ay, az = positions[a, 0] - x0, positions[a, 1] - y0, positions[a, 2] - z0
            bx, by, bz = positions[b, 0] - x0, positions[b, 1] - y0, positions[b, 2] - z0
            cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
            if fan == 1:  # set, not added to zero: 0.0 + -0.0 would lose the zero's sign
                sx, sy, sz = cx, cy, cz
            else:
                sx, sy, sz = sx + cx, sy + cy, sz + cz
        length = math.sqrt(sx * sx + sy * sy + sz * sz)
        flat = not length > smallest or math.isinf(length)  # NaN fails the comparison
        degenerate[polygon] = flat
        if flat:
            sx = sy = sz = 0.0
            length = 1.0
        normals[polygon, 0], normals[polygon, 1], normals[polygon, 2] = sx / length, sy / length, sz / length


@njit(_SUMS, nogil=True, cache=True)
def normal_sums(face_normals: np.ndarray, polygons: np.ndarray, first: int, end: int, sums: np.ndarray,
                column_sums: np.ndarray) -> None:
    """sums[v] for positions first..end (zero on entry): per corner column, the face normals of the
    faces whose corner there is v, added in face order; the columns' sums then added in column order.
    Each call reads every corner but writes only its own positions, so calls for other positions can
    run at once."""
    for column in range(polygons.shape[1]):
        column_sums[:] = 0.0
        for face in range(polygons.shape[0]):
            position = polygons[face, column]
            if first <= position < end:
                row = position - first
                for axis in range(3):
                    column_sums[row, axis] += face_normals[face, axis]
        for row in range(end - first):
            for axis in range(3):
                sums[first + row, axis] += column_sums[row, axis]
