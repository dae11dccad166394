"""The mesh's two costliest loops, compiled by numba: the polygon normals and the vertex-normal sums.

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

from marraztu.model.jit import njit

# positions (V, 3), corners' positions, face starts, smallest length, first and end face, normals (F, 3), degenerate
_NORMALS = "void(float64[:, ::1], int32[::1], int32[::1], float64, int64, int64, float64[:, ::1], boolean[::1])"
# face normals (F, 3), corners' positions, face starts, first and end position, sums (V, 3)
_SUMS = "void(float64[:, ::1], int32[::1], int32[::1], int64, int64, float64[:, ::1])"


@njit(_NORMALS, nogil=True, cache=True)
def polygon_normals(positions: np.ndarray, corner_vertex: np.ndarray, face_start: np.ndarray, smallest: float,
                    first: int, end: int, normals: np.ndarray, degenerate: np.ndarray) -> None:
    """Unit normals of faces first..end: the sum of their fans' (p_i - p_0) x (p_(i+1) - p_0) in fan
    order, made unit; zero, and degenerate, where its length is not finite or at most `smallest`."""
    for face in range(first, end):
        low, high = face_start[face], face_start[face + 1]
        origin = corner_vertex[low]
        x0, y0, z0 = positions[origin, 0], positions[origin, 1], positions[origin, 2]
        sx = sy = sz = 0.0
        for corner in range(low + 1, high - 1):
            a, b = corner_vertex[corner], corner_vertex[corner + 1]
            ax, ay, az = positions[a, 0] - x0, positions[a, 1] - y0, positions[a, 2] - z0
            bx, by, bz = positions[b, 0] - x0, positions[b, 1] - y0, positions[b, 2] - z0
            cx, cy, cz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
            if corner == low + 1:  # set, not added to zero: 0.0 + -0.0 would lose the zero's sign
                sx, sy, sz = cx, cy, cz
            else:
                sx, sy, sz = sx + cx, sy + cy, sz + cz
        length = math.sqrt(sx * sx + sy * sy + sz * sz)
        flat = not length > smallest or math.isinf(length)  # NaN fails the comparison
        degenerate[face] = flat
        if flat:
            sx = sy = sz = 0.0
            length = 1.0
        normals[face, 0], normals[face, 1], normals[face, 2] = sx / length, sy / length, sz / length


@njit(_SUMS, nogil=True, cache=True)
def normal_sums(face_normals: np.ndarray, corner_vertex: np.ndarray, face_start: np.ndarray, first: int, end: int,
                sums: np.ndarray) -> None:
    """sums[v] += the normal of each face with a corner at v, for positions first..end, corner by
    corner in order. Each call reads every corner but writes only its own positions, so calls for
    other positions run at once."""
    for face in range(face_start.shape[0] - 1):
        for corner in range(face_start[face], face_start[face + 1]):
            position = corner_vertex[corner]
            if first <= position < end:
                for axis in range(3):
                    sums[position, axis] += face_normals[face, axis]
