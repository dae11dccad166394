"""Framing: where a camera stands to see some objects whole, whatever their units.

The camera keeps the direction it looks in and moves along it until the objects' bounding sphere
fills FILL of the view's narrower side (its height in a wide view): in perspective the sphere's
angular size, in parallel projection its share of the half height or half width. Only a view that
would see them edge or end on turns first (revealing): the start's, and `.`'s.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from marraztu.model import transforms
from marraztu.model.geometry import CAMERA_REACH
from marraztu.model.mesh import Mesh
from marraztu.model.scene import PERSPECTIVE_FOVY_DEG, Projection, Scene, SceneObject, placed_bounds, world_box

FILL = 2.0 / 3.0  # of the view's narrower side: the model whole, with a margin round it
# A view whose box shows less than this share of its largest side's area (a ground plane edge
# on, a beam end on) turns to look from above, right and in front, as a drawing's oblique view does.
THIN_VIEW_SHARE = 0.1
# In the camera's frame: from above, right and in front; from above, left and in front where a plane
# holds both the view and the first (no plane holds all three).
OBLIQUE_VIEWS = (np.array([1.0, 1.0, 1.0]), np.array([-1.0, 1.0, 1.0]))


def bounding_sphere(objects: Iterable[SceneObject]) -> tuple[np.ndarray, float]:
    """A sphere round every vertex: centred on the objects' world box, as wide as its farthest vertex
    (for a round model much tighter than the box's own sphere)."""
    objects = list(objects)
    low, high = world_box(objects)
    centre = (low + high) / 2.0
    radius = 0.0
    for obj in objects:
        # In the object's own frame, no placed copy of the table: a world offset A d is |A d|^2 = d . (A^T A) d
        # long, its model matrix's scale (by hand, in Python) included.
        local_centre = np.linalg.solve(obj.model, np.append(centre, 1.0))[:3]
        offsets = obj.mesh.positions - local_centre
        linear = obj.model[:3, :3]
        squares = np.einsum("ij,ij->i", offsets @ (linear.T @ linear), offsets)
        radius = max(radius, float(np.sqrt(squares.max(initial=0.0))))
    return centre, radius


def framing_distance(radius: float, aspect: float = 1.0) -> float:
    """How far from the sphere's centre its angular size is FILL of the field of view, vertical or, in a
    view narrower than high, horizontal."""
    half_fov = math.radians(PERSPECTIVE_FOVY_DEG) / 2.0
    # The sphere's tangents span FILL of the narrower side: tan(half width) = aspect tan(half height).
    return radius / math.sin(math.atan(FILL * _narrowness(aspect) * math.tan(half_fov)))


def framed_radius(radius: float) -> float:
    """The radius framed: a model's own, however small its units (a molecule in metres is 1e-10), and
    a unit's for a model of one point."""
    return radius if radius > 0.0 else 1.0


def framed(camera_model: np.ndarray, centre: np.ndarray, radius: float, aspect: float,
           body: Mesh) -> tuple[np.ndarray, bool]:
    """The camera's matrix moved, not turned, so that it looks at `centre` from far enough back, in a
    view `aspect` wide, or from as far as its eye and `body` stay within CAMERA_REACH; and whether
    that stopped it short."""
    backward = camera_model[:3, 2] / np.linalg.norm(camera_model[:3, 2])  # the camera looks along -z
    moved = np.array(camera_model, dtype=np.float64)
    moved[:3, 3] = 0.0
    wanted = framing_distance(framed_radius(radius), aspect)
    within = _distance_within_reach(moved, body, centre, backward)
    moved[:3, 3] = centre + backward * min(wanted, within)
    return moved, within < wanted


def _distance_within_reach(turned: np.ndarray, body: Mesh, centre: np.ndarray, backward: np.ndarray) -> float:
    """How far back from `centre` along `backward` a camera turned so (its matrix at the origin) keeps
    its eye and its body within CAMERA_REACH along every axis (0 where none is)."""
    low, high = _placed_body(turned, body)
    low, high = np.minimum(low, 0.0), np.maximum(high, 0.0)  # the eye, at the origin, with its body
    return _growth_within_reach(centre + low, centre + high, backward, backward)


def body_scale_within_reach(camera_model: np.ndarray, body: Mesh) -> float:
    """How many times larger `body` may be made (about the camera's eye, as scaled_mesh scales it) where
    a camera placed by `camera_model` stands, with its body still within CAMERA_REACH along every axis."""
    turned = np.array(camera_model, dtype=np.float64)
    turned[:3, 3] = 0.0
    low, high = _placed_body(turned, body)
    eye = camera_model[:3, 3]
    return _growth_within_reach(eye, eye, low, high)


def _placed_body(model: np.ndarray, body: Mesh) -> tuple[np.ndarray, np.ndarray]:
    """(3,) each: the low and high corners of the box of `body` placed by `model`."""
    low, high = placed_bounds(model[None], np.array(body.bounds)[None])
    return low[0], high[0]


def _growth_within_reach(low: np.ndarray, high: np.ndarray, low_growth: np.ndarray, high_growth: np.ndarray) -> float:
    """The largest t >= 0 for which the box from low + t low_growth to high + t high_growth stays within
    CAMERA_REACH along every axis (0 where none does, inf where every t does): one closed form for a
    camera backing away (framing) and a body growing round its eye (fitting)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        limits = np.minimum(np.where(high_growth > 0.0, (CAMERA_REACH - high) / high_growth, np.inf),
                            np.where(low_growth < 0.0, (-CAMERA_REACH - low) / low_growth, np.inf))
    return max(float(limits.min()) * (1.0 - 1e-9), 0.0)  # a billionth short: what rounding may add back


def frame_objects(scene: Scene, camera_model: np.ndarray, objects: list[SceneObject], aspect: float,
                  body: Mesh) -> tuple[np.ndarray, float, bool]:
    """The matrix of a camera of this `body` framing `objects` in a view `aspect` wide, the parallel
    view's half height that frames them (the current one in perspective), and whether CAMERA_REACH
    stopped the camera short of where it would frame them."""
    centre, radius = bounding_sphere(objects)
    parallel = scene.modes.projection is Projection.PARALLEL
    half_height = _framed_half_height(radius, aspect) if parallel else scene.modes.parallel_half_height
    matrix, short = framed(camera_model, centre, radius, aspect, body)
    return matrix, half_height, short


def framed_scale(scene: Scene, obj: SceneObject, aspect: float = 1.0) -> float:
    """How many times larger than `.` would frame it a view `aspect` wide shows the object now: the
    framing's distance over the eye's from its sphere's centre (in parallel projection, the framing's
    view size over the view's)."""
    centre, radius = bounding_sphere([obj])
    if scene.modes.projection is Projection.PARALLEL:
        return _framed_half_height(radius, aspect) / scene.modes.parallel_half_height
    distance = float(np.linalg.norm(centre - scene.eye_position()))
    return framing_distance(framed_radius(radius), aspect) / distance if distance > 0.0 else math.inf


def _framed_half_height(radius: float, aspect: float) -> float:
    """The parallel view's half height in which a sphere of `radius` fills FILL of a view `aspect` wide."""
    return framed_radius(radius) / _narrowness(aspect) / FILL


def _narrowness(aspect: float) -> float:
    """How much of the view's height its width spans, where less: a view narrower than high (a third
    of the window, side by side) frames by its width."""
    return min(aspect, 1.0)


def _box_faces(objects: list[SceneObject]) -> np.ndarray:
    """(3, 3): the area vectors of the box's faces across its three axes: a lone object's own box as
    placed (turned, a plate stays a plate), else the objects' world box."""
    if len(objects) == 1:
        axes = objects[0].model[:3, :3] * np.ptp(objects[0].mesh.bounds, axis=0)  # its edges, columns
    else:
        low, high = world_box(objects)
        axes = np.diag(high - low)
    return np.cross(axes[:, [1, 2, 0]].T, axes[:, [2, 0, 1]].T)


def revealing(camera_model: np.ndarray, objects: list[SceneObject]) -> np.ndarray:
    """The camera turned, where it stands, to look at the objects from above, right and in front (or
    left, where that too sees it so) where its own direction sees their box nearly edge or end on;
    else as it is."""
    faces = _box_faces(objects)
    least = THIN_VIEW_SHARE * float(np.linalg.norm(faces, axis=1).max())

    def shows(direction: np.ndarray) -> bool:  # the box's outline along it: one face of each pair
        return float(np.abs(faces @ direction).sum()) >= least * float(np.linalg.norm(direction))

    if not least > 0.0 or shows(camera_model[:3, 2]):
        return camera_model
    centre = np.mean(world_box(objects), axis=0)
    for oblique in (camera_model[:3, :3] @ view for view in OBLIQUE_VIEWS):
        if shows(oblique):
            turned = transforms.look_at_model(centre + oblique, centre, camera_model[:3, 1])
            return camera_model if turned is None else turned
    return camera_model
