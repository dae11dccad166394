"""Every 4x4 and 3x3 matrix the viewer builds, in the column-vector convention (p' = M @ p).

Ours rather than a library's: the README's Decisions say why.
"""

from __future__ import annotations

from enum import Enum

import numpy as np

from marraztu.model.geometry import unit_or_none

Vec3 = tuple[float, float, float]


class TransformKind(Enum):
    """What x/y/z do (keys r and t)."""

    ROTATE = "rotate"
    TRANSLATE = "translate"


def rotation3(axis_index: int, angle: float) -> np.ndarray:
    """3x3 right-handed rotation by `angle` radians about the x, y or z axis (0, 1, 2)."""
    if axis_index not in (0, 1, 2):
        raise ValueError(f"axis index {axis_index}: 0 (x), 1 (y) or 2 (z)")
    cos, sin = np.cos(float(angle)), np.sin(float(angle))
    # The next axis turns toward the one after it (y to z, z to x, x to y); the axis itself stays.
    turned, toward = (axis_index + 1) % 3, (axis_index + 2) % 3
    matrix = np.eye(3)
    matrix[turned, turned], matrix[turned, toward] = cos, -sin
    matrix[toward, turned], matrix[toward, toward] = sin, cos
    return matrix


def rotation_about_axis(axis_index: int, angle: float) -> np.ndarray:
    """4x4 right-handed rotation about a coordinate axis: positive angles turn y toward z, z toward x,
    x toward y."""
    matrix = np.eye(4)
    matrix[:3, :3] = rotation3(axis_index, angle)
    return matrix


def euler_xyz(degrees: Vec3) -> np.ndarray:
    """3x3 Rz @ Ry @ Rx: turned about the world x axis first, then y, then z."""
    ax, ay, az = np.radians(degrees)
    return rotation3(2, az) @ rotation3(1, ay) @ rotation3(0, ax)


def translation_by(offset: np.ndarray) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, 3] = offset
    return matrix


def translation(axis_index: int, distance: float) -> np.ndarray:
    """4x4 translation by `distance` along the x, y or z axis (0, 1, 2)."""
    offset = np.zeros(3)
    offset[axis_index] = distance
    return translation_by(offset)


def step_matrix(kind: TransformKind, axis_index: int, amount: float) -> np.ndarray:
    """One press of x/y/z: `amount` radians about the axis, or world units along it."""
    if kind is TransformKind.ROTATE:
        return rotation_about_axis(axis_index, amount)
    return translation(axis_index, amount)


def placement(position: Vec3, rotation_deg: Vec3 = (0.0, 0.0, 0.0)) -> np.ndarray:
    """A model matrix: turned about the world x, then y, then z axis, then moved to `position`."""
    model = np.eye(4)
    model[:3, :3] = euler_xyz(rotation_deg)
    model[:3, 3] = position
    return model


def apply_local(model: np.ndarray, step: np.ndarray) -> np.ndarray:
    """The step in the element's own frame (SPEC's M = M.T, i.e. M @ T). Always a new array: histories stay exact."""
    return model @ step


def apply_global(model: np.ndarray, step: np.ndarray) -> np.ndarray:
    """The step in the world frame (SPEC's M = T.M, i.e. T @ M)."""
    return step @ model


def perspective(fovy_deg: float, aspect: float, near: float, far: float) -> np.ndarray:
    """gluPerspective: glFrustum whose near plane spans +-top vertically and +-top * aspect across."""
    top = near * np.tan(fovy_deg * np.pi / 360.0)  # tan(fovy / 2), fovy in degrees
    right = top * aspect
    depth = far - near
    return np.array([
        [near / right, 0.0, 0.0, 0.0],
        [0.0, near / top, 0.0, 0.0],
        [0.0, 0.0, -(far + near) / depth, -2.0 * far * near / depth],  # near -> -1, far -> +1 after the divide
        [0.0, 0.0, -1.0, 0.0],  # w = -z: the divide by the distance in front of the eye
    ])


def orthographic(half_w: float, half_h: float, near: float, far: float) -> np.ndarray:
    """glOrtho, centred on the view axis."""
    depth = far - near
    return np.array([
        [1.0 / half_w, 0.0, 0.0, 0.0],
        [0.0, 1.0 / half_h, 0.0, 0.0],
        [0.0, 0.0, -2.0 / depth, -(far + near) / depth],  # the eye looks down -z: near -> -1, far -> +1
        [0.0, 0.0, 0.0, 1.0],
    ])


def normal_matrix(model: np.ndarray) -> np.ndarray:
    """The inverse transpose of the model's 3x3: it keeps normals perpendicular to a scaled surface."""
    return np.linalg.inv(model[:3, :3]).T


def transform_point(matrix: np.ndarray, point: np.ndarray) -> np.ndarray:
    """A point through a 4x4 affine matrix."""
    return (matrix @ np.append(np.asarray(point, float), 1.0))[:3]


def transform_points(matrix: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(N, 3) points through a 4x4 affine matrix, at once: p' = M3 p + t for each."""
    return np.asarray(points, float) @ matrix[:3, :3].T + matrix[:3, 3]


def point_in_frame(model: np.ndarray, world_point: np.ndarray) -> np.ndarray:
    """Coordinates of a world point in the frame of `model` (the inverse transform)."""
    return transform_point(np.linalg.inv(model), world_point)


def look_at_model(eye: np.ndarray, target: np.ndarray, up: np.ndarray) -> np.ndarray | None:
    """A rigid model matrix at `eye` whose -z axis points at `target`, its y axis as close to `up` as
    possible. The inverse of gluLookAt's view matrix. None when eye and target coincide."""
    backward = unit_or_none(np.asarray(eye, dtype=np.float64) - np.asarray(target, dtype=np.float64))
    if backward is None:
        return None
    right = unit_or_none(np.cross(up, backward))
    if right is None:  # up is along the view axis: any perpendicular up will do
        fallback_up = np.array([1.0, 0.0, 0.0]) if abs(backward[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        right = unit_or_none(np.cross(fallback_up, backward))
    model = np.eye(4)
    model[:3, 0] = right
    model[:3, 1] = np.cross(backward, right)
    model[:3, 2] = backward
    model[:3, 3] = eye
    return model


def orbit(model: np.ndarray, pivot_world: np.ndarray, axis_index: int, angle: float) -> np.ndarray:
    """Turns the frame about its own axis `axis_index`, but through `pivot_world` instead of its
    origin: the pivot keeps its coordinates in the frame, so a camera looking at it still does."""
    pivot_local = point_in_frame(model, pivot_world)
    about_pivot = translation_by(pivot_local) @ rotation_about_axis(axis_index, angle) \
        @ translation_by(-pivot_local)
    return model @ about_pivot
