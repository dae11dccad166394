"""4x4 matrices for the moving keys, in the column-vector convention of app.scene (p' = M @ p).

pyrr's `matrix33.create_from_{x,y,z}_rotation` already are right-handed rotations for column vectors
(tests/test_commands.py pins that), so we use them. Its translation and axis-angle builders are laid
out for row vectors (the transpose of ours), so translation is written here instead: it is one line.
"""

from __future__ import annotations

import numpy as np
import pyrr

_ROTATION_BUILDERS = (
    pyrr.matrix33.create_from_x_rotation,
    pyrr.matrix33.create_from_y_rotation,
    pyrr.matrix33.create_from_z_rotation,
)


def rotation3(axis_index: int, angle: float) -> np.ndarray:
    """3x3 right-handed rotation by `angle` radians about the x, y or z axis (0, 1, 2)."""
    return np.asarray(_ROTATION_BUILDERS[axis_index](float(angle)), dtype=np.float64)


def rotation_about_axis(axis_index: int, angle: float) -> np.ndarray:
    """4x4 right-handed rotation about a coordinate axis: positive angles turn y toward z, z toward x,
    x toward y."""
    matrix = np.eye(4)
    matrix[:3, :3] = rotation3(axis_index, angle)
    return matrix


def translation_by(offset: np.ndarray) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, 3] = offset
    return matrix


def translation(axis_index: int, distance: float) -> np.ndarray:
    """4x4 translation by `distance` along the x, y or z axis (0, 1, 2)."""
    offset = np.zeros(3)
    offset[axis_index] = distance
    return translation_by(offset)


def apply_local(model: np.ndarray, step: np.ndarray) -> np.ndarray:
    """The step in the element's own frame (SPEC: M = M.T). Always a new array: histories stay exact."""
    return model @ step


def apply_global(model: np.ndarray, step: np.ndarray) -> np.ndarray:
    """The step in the world frame (SPEC: M = T.M)."""
    return step @ model


def _unit(vector: np.ndarray) -> np.ndarray | None:
    length = float(np.linalg.norm(vector))
    return None if length < 1e-12 else vector / length


def look_at_model(eye: np.ndarray, target: np.ndarray, up: np.ndarray) -> np.ndarray | None:
    """A rigid model matrix at `eye` whose -z axis points at `target`, its y axis as close to `up` as
    possible. The inverse of gluLookAt's view matrix. None when eye and target coincide."""
    backward = _unit(np.asarray(eye, dtype=np.float64) - np.asarray(target, dtype=np.float64))
    if backward is None:
        return None
    right = _unit(np.cross(up, backward))
    if right is None:  # up is along the view axis: any perpendicular up will do
        fallback_up = np.array([1.0, 0.0, 0.0]) if abs(backward[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        right = _unit(np.cross(fallback_up, backward))
    model = np.eye(4)
    model[:3, 0] = right
    model[:3, 1] = np.cross(backward, right)
    model[:3, 2] = backward
    model[:3, 3] = eye
    return model


def point_in_frame(model: np.ndarray, world_point: np.ndarray) -> np.ndarray:
    """Coordinates of a world point in the frame of `model` (the inverse transform)."""
    return (np.linalg.inv(model) @ np.append(world_point, 1.0))[:3]


def orbit(model: np.ndarray, pivot_world: np.ndarray, axis_index: int, angle: float) -> np.ndarray:
    """Turns the frame about its own axis `axis_index`, but through `pivot_world` instead of its
    origin: the pivot keeps its coordinates in the frame, so a camera looking at it still does."""
    pivot_local = point_in_frame(model, pivot_world)
    about_pivot = translation_by(pivot_local) @ rotation_about_axis(axis_index, angle) \
        @ translation_by(-pivot_local)
    return model @ about_pivot
