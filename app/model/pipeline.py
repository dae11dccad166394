"""The pipeline view (key `P`): the selected face's corners carried through every space the vertex
stage and the rasteriser use, in numpy, with the verdicts GL makes on the way.

model --M--> world --V--> eye --P--> clip --divide by w--> NDC --viewport--> window
No GL: the text layer prints these numbers and the tests recompute them independently.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from marraztu.model.probe import probed_face
from marraztu.model.scene import Lens, Scene, SceneObject

# GL's clip volume: -w <= x, y, z <= w. Each plane by the coordinate it bounds and its side.
CLIP_PLANES = (("left", 0, -1), ("right", 0, +1), ("bottom", 1, -1), ("top", 1, +1), ("near", 2, -1),
               ("far", 2, +1))


@dataclass(frozen=True)
class CornerStages:
    """One corner of the face in every space; `ndc` and `window` are None behind the eye (w <= 0)."""

    vertex: int  # 0-based row of the file's vertex table
    model: np.ndarray  # (3,)
    world: np.ndarray  # (3,) M·model
    eye: np.ndarray  # (3,) V·world: the camera looks along its -z
    clip: np.ndarray  # (4,) P·eye, homogeneous
    ndc: np.ndarray | None  # (3,) clip.xyz / clip.w, inside [-1, 1] when visible
    window: np.ndarray | None  # (3,) pixels from the bottom-left, and depth in 0..1
    outside: tuple[str, ...]  # the clip planes this corner is beyond, by name

    @property
    def behind_eye(self) -> bool:
        return bool(self.clip[3] <= 0.0)


@dataclass(frozen=True)
class FacePipeline:
    obj: SceneObject
    face: int  # 0-based
    face_count: int
    model_matrix: np.ndarray  # (4, 4) M
    view_matrix: np.ndarray  # (4, 4) V
    projection_matrix: np.ndarray  # (4, 4) P
    lens: Lens  # what P is built from
    viewport: tuple[int, int, int, int]  # x, y, width, height in pixels
    corners: tuple[CornerStages, ...]  # the first `most` that face_pipeline() was asked for, or all
    corner_count: int  # the face's corners
    facing: float  # face normal . V at the polygon's first vertex (SPEC 4's back-face test)
    culling: bool

    @property
    def back_face(self) -> bool:
        return self.facing <= 0.0

    @property
    def culled(self) -> bool:
        return self.back_face and self.culling


def face_pipeline(scene: Scene, viewport: tuple[int, int, int, int], most: int | None = None) -> FacePipeline | None:
    """The selected object's selected face (the probe's face) drawn into `viewport`, its first `most`
    corners carried (a panel shows a few of a polygon of thousands); None without one."""
    found = probed_face(scene)  # the back-face verdict, made as the probe makes it
    if found is None:
        return None
    obj, mesh = found.obj, found.obj.mesh
    model, view = obj.model, scene.view_matrix()
    aspect = viewport[2] / viewport[3]
    lens = scene.lens(aspect)
    projection = lens.matrix()
    start, stop = int(mesh.face_start[found.face]), int(mesh.face_start[found.face + 1])
    carried = range(start, stop)[:most]
    corners = tuple(_stages(int(mesh.corner_vertex[corner]), mesh.positions[mesh.corner_vertex[corner]], model,
                            view, projection, viewport) for corner in carried)
    return FacePipeline(obj=obj, face=found.face, face_count=mesh.face_count, model_matrix=model,
                        view_matrix=view, projection_matrix=projection, lens=lens, viewport=viewport,
                        corners=corners, corner_count=stop - start, facing=found.facing, culling=scene.modes.culling)


def _stages(vertex: int, point: np.ndarray, model: np.ndarray, view: np.ndarray, projection: np.ndarray,
            viewport: tuple[int, int, int, int]) -> CornerStages:
    model_point = np.asarray(point, float)
    world = model @ np.append(model_point, 1.0)
    eye = view @ world
    clip = projection @ eye
    ndc = window = None
    if clip[3] > 0.0:
        ndc = clip[:3] / clip[3]
        x0, y0, width, height = viewport
        # glViewport and the default glDepthRange(0, 1): each NDC axis from [-1, 1] onto its range.
        window = np.array([x0 + (ndc[0] + 1.0) / 2.0 * width, y0 + (ndc[1] + 1.0) / 2.0 * height,
                           (ndc[2] + 1.0) / 2.0])
    outside = tuple(name for name, axis, side in CLIP_PLANES if side * clip[axis] > clip[3])
    return CornerStages(vertex=vertex, model=model_point, world=world[:3], eye=eye[:3], clip=clip, ndc=ndc,
                        window=window, outside=outside)
