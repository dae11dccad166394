"""The lighting probe (key `i`): SPEC 4's formula worked through for the selected face, in numpy.

For every vertex the renderer lights (all of the polygon's corners in Gouraud, the first one in
Flat) it keeps the positions and normals in world and camera space, N.V, every light's L, H, N.L,
(N.H)^ns and cone test, the per-light contributions, their sum, the clamp and the final 0..255
colour: the numbers a learner needs to see why a pixel has its colour. Built on
marraztu.model.lighting, which is written from SPEC and not from the shader, so the probe also
checks the renderer (tests compare its colours with the pixels). No GL here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from marraztu.model.geometry import unit, unit_rows
from marraztu.model.lighting import ShadingTerms, shade_terms, to_bytes
from marraztu.model.lights import TermView, TermWeights, WorldLight
from marraztu.model.mesh import is_plain, polygons_of_corners
from marraztu.model.scene import Projection, Scene, SceneObject, Shading
from marraztu.model.transforms import normal_matrix, transform_point, transform_points

BACK_FACE_RGB = np.array([255, 0, 0], np.uint8)  # SPEC 5: back faces are drawn red without culling


@dataclass(frozen=True)
class VertexProbe:
    """One lit vertex: where it is, which normal lights it, and every term of I there."""

    corner: int  # index into the mesh's corner table
    vertex: int  # index into the file's `v` table (0-based)
    world_position: np.ndarray  # (3,)
    camera_position: np.ndarray  # (3,) in the viewer's frame: the camera looks along its -z
    world_normal: np.ndarray  # (3,) unit: the vertex normal (Gouraud) or the face normal (Flat)
    camera_normal: np.ndarray  # (3,) unit
    n_dot_v: float  # with the normal above and V at this vertex
    terms: ShadingTerms  # every light that is on, whatever the term view
    lights: tuple[WorldLight, ...]  # the lights of terms.lights, in the same order
    shown: np.ndarray  # (3,) I before clamping, in the current term view

    @property
    def clamped(self) -> np.ndarray:
        return np.minimum(self.shown, 255.0)

    @property
    def lit_bytes(self) -> np.ndarray:
        """The 0..255 colour the lit formula gives here (texture off), back face or not."""
        return to_bytes(self.clamped)


@dataclass(frozen=True)
class Probe:
    obj: SceneObject
    face: int
    face_count: int
    shading: Shading
    facing: float  # face normal . V at the polygon's first vertex: SPEC 5's back-face test
    face_normal: np.ndarray  # (3,) unit, in the world
    culling: bool
    textured: bool  # a picture multiplies the pixel: it is the colour here times the texel (T turns it off)
    view: TermView
    view_name: str  # Scene.term_view_name: "sun alone", not "light 0 alone"
    weights: TermWeights
    shown_lights: frozenset[str]  # the lights the term view keeps: every one on, or one alone
    vertices: tuple[VertexProbe, ...]  # the first `most` that probe() was asked for, or all
    lit_count: int  # the vertices lit for this face: all its corners in Gouraud, the first in Flat

    @property
    def back_face(self) -> bool:
        return self.facing <= 0.0

    def displayed(self, vertex: VertexProbe) -> np.ndarray | None:
        """The pixel at that vertex as the renderer draws it (texture off): the lit colour, red for
        a back face, or None where culling hides the face."""
        if not self.back_face:
            return vertex.lit_bytes
        return None if self.culling else BACK_FACE_RGB.copy()


@dataclass(frozen=True)
class ProbedFace:
    """The selected object's selected face and how it faces the eye: where the probe, the pipeline
    panel and the picture's outline of that face start, without lighting anything."""

    obj: SceneObject
    face: int
    facing: float  # face normal . V at the polygon's first vertex: SPEC 5's back-face test
    face_normal: np.ndarray  # (3,) unit, in the world


def probed_face(scene: Scene) -> ProbedFace | None:
    """The face the probe explains; None when there is none."""
    obj = scene.object
    if obj is None or obj.mesh.face_count == 0:
        return None
    face = obj.selected_face % obj.mesh.face_count
    return ProbedFace(obj, face, float(facings(scene, obj, np.array([face]))[0]),
                      _world_normal(obj.model, obj.mesh.face_normals[face]))


def probe(scene: Scene, most: int | None = None) -> Probe | None:
    """The probe of the selected object's selected face, its first `most` lit vertices worked out (a
    panel shows a few of a polygon of thousands); None when there is no face to probe."""
    found = probed_face(scene)
    if found is None:
        return None
    obj, face, face_normal = found.obj, found.face, found.face_normal
    gouraud = scene.modes.shading is Shading.GOURAUD
    corners = scene.probed_corners()
    lit = _VertexLighting(scene)
    vertices = tuple(lit.probe(obj, corner, None if gouraud else face_normal) for corner in corners[:most])
    return Probe(obj=obj, face=face, face_count=obj.mesh.face_count, shading=scene.modes.shading,
                 facing=found.facing, face_normal=face_normal, culling=scene.modes.culling,
                 textured=_textured(scene, obj, face),
                 view=scene.modes.term_view, view_name=scene.term_view_name(), weights=lit.weights,
                 shown_lights=frozenset(lit.shown_names), vertices=vertices, lit_count=len(corners))


def _textured(scene: Scene, obj: SceneObject, face: int) -> bool:
    """Whether a picture multiplies the face's pixels: the texture is on and the face's part is not
    drawn plain (its vertex colours take the picture's place, or a scene file's `texture = false`)."""
    part = -1 if obj.mesh.face_material is None else int(obj.mesh.face_material[face])
    picture = obj.picture_of(part)
    return scene.modes.texture and not is_plain(scene.texture if picture is None else picture)


def facings(scene: Scene, obj: SceneObject, faces: np.ndarray) -> np.ndarray:
    """Face normal . V of each of the object's polygons `faces`, V taken at each one's first vertex: SPEC
    5's back-face test, as the shaders make it."""
    mesh = obj.mesh
    normals, _ = unit_rows(mesh.face_normals[faces] @ normal_matrix(obj.model).T)
    firsts = transform_points(obj.model, mesh.positions[mesh.corner_vertex[mesh.face_start[faces]]])
    return np.einsum("ij,ij->i", normals, _toward_eyes(scene, firsts))


class _VertexLighting:
    """What every probed vertex of one frame shares: the lights, the term view, the viewer."""

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self.view = scene.view_matrix()
        self.parallel = scene.modes.projection is Projection.PARALLEL
        self.eye_or_view = scene.eye_backward() if self.parallel else scene.eye_position()
        self.lights = tuple(scene.world_lights())
        self.shown_names = {light.name for light in scene.lights_in_view()}
        self.weights = scene.modes.term_view.weights

    def probe(self, obj: SceneObject, corner: int, face_normal: np.ndarray | None) -> VertexProbe:
        mesh = obj.mesh
        vertex = int(mesh.corner_vertex[corner])
        position = transform_point(obj.model, mesh.positions[vertex])
        normal = (face_normal if face_normal is not None
                  else _world_normal(obj.model, mesh.normals[mesh.attribute_rows(corner)]))
        face = int(polygons_of_corners(mesh.face_start, corner))
        terms = shade_terms(position, normal, self.eye_or_view, obj.face_material(face), self.lights,
                            self.scene.ambient, self.parallel)
        return VertexProbe(
            corner=corner, vertex=vertex, world_position=position,
            camera_position=transform_point(self.view, position), world_normal=normal,
            camera_normal=_world_normal(self.view, normal),
            n_dot_v=float(normal @ _toward_eyes(self.scene, position[None])[0]),
            terms=terms, lights=self.lights, shown=terms.in_view(self.weights, self.shown_names))


def _toward_eyes(scene: Scene, points: np.ndarray) -> np.ndarray:
    """SPEC 4's V at each of these (N, 3) world points: toward the eye in perspective, the viewer's
    backward axis in parallel."""
    if scene.modes.projection is Projection.PARALLEL:
        return np.broadcast_to(unit(scene.eye_backward()), points.shape)
    return unit_rows(scene.eye_position() - points)[0]


def _world_normal(matrix: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Normals go through the inverse transpose, as in the shader, so scaling keeps them perpendicular."""
    return unit(normal_matrix(matrix) @ np.asarray(normal, float))
