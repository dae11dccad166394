"""Which object and face a pixel shows (a click): the ray through the pixel's centre, in the view it
falls in, met with the fan triangles of what the picture draws, in numpy. No GL read-back: the same
matrices as the renderer, and SPEC 5's back-face test as the probe makes it, decide.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from marraztu.model.geometry import segment_meets_box
from marraztu.model.mesh import fan_triangles
from marraztu.model.probe import facings
from marraztu.model.scene import Scene, SceneObject
from marraztu.model.viewports import pixel_centre, pixel_segment, view_at, view_projection

# Polygon corners met with the ray at once: the arrays of a block stay a few tens of MB, whatever the model.
PICK_BLOCK_CORNERS = 1 << 18


@dataclass(frozen=True)
class Hit:
    """What a pixel shows: an element's polygon, and how far along the pixel's segment (0 at the near
    plane, 1 at the far one)."""

    element: SceneObject
    face: int
    depth: float


def pick(scene: Scene, size: tuple[int, int], pixel: tuple[int, int]) -> Hit | None:
    """The nearest drawn polygon at `pixel` (column, row from the top-left) of a framebuffer of `size`,
    beyond the near plane and before the far one; with culling on (`b`) never a back face. None: the
    background."""
    point = pixel_centre(pixel, size)
    view = view_at(scene, size, point)
    near, far = pixel_segment(view_projection(scene, view), point, view.viewport)
    nearest: Hit | None = None
    for element, start, stop in scene.drawn_faces():
        hit = _nearest_on(scene, element, start, stop, near, far - near)
        if hit is not None and (nearest is None or hit.depth < nearest.depth):
            nearest = hit
    return nearest


def _nearest_on(scene: Scene, element: SceneObject, start: int, stop: int, origin: np.ndarray,
                direction: np.ndarray) -> Hit | None:
    """The nearest of the element's polygons start..stop that the segment origin + t direction (t in
    0..1, in the world) meets, met in the mesh's own frame: an affine map keeps t."""
    inverse = np.linalg.inv(element.model)
    local_origin = inverse[:3, :3] @ origin + inverse[:3, 3]
    local_direction = inverse[:3, :3] @ direction
    if not segment_meets_box(local_origin, local_direction, *element.mesh.bounds):  # then no triangle of it
        return None
    faces_met, depths = [], []
    for first, last in _blocks(element.mesh.face_start, start, stop):
        faces, t = _met_in(element, first, last, local_origin, local_direction)
        faces_met.append(faces)
        depths.append(t)
    faces, t = np.concatenate(faces_met), np.concatenate(depths)
    if scene.modes.culling and faces.size:  # culled back faces are not drawn, so not seen
        front = facings(scene, element, faces) > 0.0
        faces, t = faces[front], t[front]
    if not faces.size:
        return None
    nearest = int(np.argmin(t))
    return Hit(element, int(faces[nearest]), float(t[nearest]))


def _blocks(face_start: np.ndarray, start: int, stop: int) -> Iterator[tuple[int, int]]:
    """Polygons start..stop in runs of about PICK_BLOCK_CORNERS corners (one polygon at least)."""
    first = start
    while first < stop:
        limit = int(face_start[first]) + PICK_BLOCK_CORNERS
        last = int(np.searchsorted(face_start, limit, side="right")) - 1  # the polygons ending within it
        last = min(max(last, first + 1), stop)
        yield first, last
        first = last


def _met_in(element: SceneObject, first: int, last: int, origin: np.ndarray, direction: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray]:
    """(faces, t) of the fan triangles of polygons first..last that origin + t direction meets for t in
    0..1 (Moller-Trumbore, every triangle at once)."""
    mesh = element.mesh
    starts = mesh.face_start[first:last + 1]
    corners = fan_triangles(starts - starts[0]) + starts[0]
    triangle_faces = np.repeat(np.arange(first, last), np.diff(starts) - 2)
    a, b, c = (mesh.positions[mesh.corner_vertex[corners[:, k]]] for k in range(3))
    edge1, edge2 = b - a, c - a
    across = np.cross(direction, edge2)
    determinant = np.einsum("ij,ij->i", edge1, across)
    to_origin = origin - a
    up = np.cross(to_origin, edge1)
    with np.errstate(divide="ignore", invalid="ignore"):  # a triangle edge on to the ray, or a sliver: det 0, not met
        u = np.einsum("ij,ij->i", to_origin, across) / determinant
        v = (up @ direction) / determinant
        t = np.einsum("ij,ij->i", edge2, up) / determinant
        met = (u >= 0.0) & (v >= 0.0) & (u + v <= 1.0) & (t >= 0.0) & (t <= 1.0)
    return triangle_faces[met], t[met]
