"""Small geometric helpers, one copy each: unit vectors, polygon normals, bounds."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

# The GPU draws in float32: a coordinate beyond this would be infinite there.
FLOAT32_MAX = float(np.finfo(np.float32).max)


def unit(vector: Iterable[float]) -> np.ndarray:
    """The vector scaled to length 1; a zero vector stays zero."""
    v = np.asarray(vector, float)
    length = float(np.linalg.norm(v))
    return v / length if length > 0.0 else v


def unit_or_none(vector: Iterable[float], shortest: float = 1e-12) -> np.ndarray | None:
    """The vector scaled to length 1, or None when it is too short to have a direction."""
    v = np.asarray(vector, float)
    length = float(np.linalg.norm(v))
    return None if length < shortest else v / length


def unit_rows(vectors: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each row scaled to length 1, and which rows could be; the others are left zero."""
    with np.errstate(all="ignore"):
        length = np.sqrt(np.einsum("ij,ij->i", vectors, vectors))
        ok = np.isfinite(length) & (length > 1e-300)
        scaled = vectors / np.where(ok, length, 1.0)[:, None]
    scaled[~ok] = 0.0
    return scaled, ok


def newell_normal(points: np.ndarray) -> np.ndarray:
    """A polygon's normal, not normalised, by Newell's method: right even for a slightly bent polygon."""
    following = np.roll(points, -1, axis=0)
    return np.cross(points, following).sum(axis=0)


def column_bounds(table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(low, high): each column's minimum and maximum of an (N, k) table, N > 0."""
    # Column by column: reducing a C-ordered table over axis 0 runs its inner loop across short rows.
    low = np.array([table[:, column].min() for column in range(table.shape[1])])
    high = np.array([table[:, column].max() for column in range(table.shape[1])])
    return low, high
