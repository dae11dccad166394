"""The scene: objects, cameras, lights, selection, modes and transform histories. Plain numpy, no GL.

Matrices follow the column-vector convention of the seed and of SPEC (p' = M @ p, local transform
M = M @ T, global transform M = T @ M), stored as numpy (4, 4) float64 arrays. OpenGL wants them
column-major, which is ``M.T`` in numpy's row-major memory; the renderer does that conversion.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass, field
from enum import Enum

import numpy as np
import pyrr

from app.mesh import Mesh

Vec3 = tuple[float, float, float]

# SPEC 5: perspective is the seed's frustum l=-5 r=5 b=-5 t=5 n=5, i.e. a 90 degree vertical field.
PERSPECTIVE_FOVY_DEG = 90.0
NEAR_PLANE = 5.0
SPOT_APERTURE_RANGE_DEG = (1.0, 89.0)


class Target(Enum):
    OBJECTS = "objects"
    CAMERAS = "cameras"
    LIGHTS = "lights"


class Fill(Enum):
    FILLED = "filled"
    LINES = "lines"


class Shading(Enum):
    FLAT = "flat"
    GOURAUD = "gouraud"


class Projection(Enum):
    PERSPECTIVE = "perspective"
    PARALLEL = "parallel"


class TransformKind(Enum):
    ROTATE = "rotate"
    TRANSLATE = "translate"


class Frame(Enum):
    LOCAL = "local"  # objects: M = M @ T, the object's own frame
    GLOBAL = "global"  # objects: M = T @ M, the world frame


class CameraMode(Enum):
    FLIGHT = "flight"
    ANALYSIS = "analysis"


class TermView(Enum):
    """What the lit colour shows (key `v`): SPEC 4's sum, one of its terms, or one light's share.
    Each view is clamped on its own, so the views add up to the whole wherever nothing saturates."""

    EVERYTHING = "everything"
    AMBIENT = "ambient only"
    DIFFUSE = "diffuse only"
    SPECULAR = "specular only"
    LIGHT_0 = "light 0 alone"
    LIGHT_1 = "light 1 alone"
    LIGHT_2 = "light 2 alone"
    LIGHT_3 = "light 3 alone"

    @property
    def light_index(self) -> int | None:
        """Which of the scene's four lights a "one light alone" view shows; None for the others."""
        if self.name.startswith("LIGHT_"):
            return int(self.name.removeprefix("LIGHT_"))
        return None


class LightKind(Enum):
    DIRECTIONAL = "directional"
    POINT = "point"
    SPOT = "spot"


class Owner(Enum):
    """Whose origin and forward axis a spotlight follows."""

    NONE = "none"
    SELECTED_OBJECT = "selected object"
    SELECTED_CAMERA = "selected camera"


@dataclass(frozen=True)
class Material:
    ka: Vec3
    kd: Vec3
    ks: Vec3
    ns: float
    rgb: Vec3 = (1.0, 1.0, 1.0)  # the seed's base colour; shown in lines mode of nothing else


_uids = itertools.count(1)


@dataclass(eq=False)
class SceneObject:
    """An object or a camera: a mesh, a material and a history of model matrices (top = current)."""

    name: str
    mesh: Mesh
    material: Material
    history: list[np.ndarray]
    selected_face: int = 0
    uid: int = field(default_factory=lambda: next(_uids))  # stable key for GPU resources

    @classmethod
    def placed(cls, name: str, mesh: Mesh, material: Material, position: Vec3,
               rotation_deg: Vec3 = (0.0, 0.0, 0.0)) -> SceneObject:
        """Initial placement: turned about the world x, then y, then z axis, then moved."""
        model = np.eye(4)
        model[:3, :3] = euler_xyz(rotation_deg)
        model[:3, 3] = position
        return cls(name=name, mesh=mesh, material=material, history=[model])

    @property
    def model(self) -> np.ndarray:
        return self.history[-1]

    @property
    def origin(self) -> np.ndarray:
        return self.model[:3, 3].copy()

    @property
    def forward(self) -> np.ndarray:
        """World direction of the object's -z axis: where a camera (or `C`) looks."""
        axis = -self.model[:3, 2]
        return axis / np.linalg.norm(axis)

    @property
    def centre(self) -> np.ndarray:
        """World position of the mesh's bounding-box centre: what analysis mode orbits."""
        low, high = self.mesh.bounds
        return (self.model @ np.append((low + high) / 2.0, 1.0))[:3]

    def push(self, model: np.ndarray) -> None:
        self.history.append(np.asarray(model, dtype=np.float64))

    def undo(self) -> bool:
        if len(self.history) <= 1:
            return False
        self.history.pop()
        return True


@dataclass(eq=False)
class Light:
    name: str
    key: str  # the key that switches it on and off
    kind: LightKind
    intensity: np.ndarray  # (3,) in the seed's 0..255 units
    on: bool = False
    position: np.ndarray = field(default_factory=lambda: np.zeros(3))  # world; spots: from the owner
    direction: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))  # sun: toward it
    aperture_deg: float = 180.0  # spotlights: half-angle of the cone
    owner: Owner = Owner.NONE
    # Spotlights: rotation of the axis relative to the owner's frame; identity = the owner's -z.
    axis_in_owner: np.ndarray = field(default_factory=lambda: np.eye(3))
    # Undo stack of the light's earlier states (position, direction, axis_in_owner): each move pushes
    # a copy of the state before it, `u` pops one back. Empty = the initial state.
    history: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = field(default_factory=list)


def default_lights() -> list[Light]:
    """SPEC 4: the sun, the bulb, the object spotlight and the camera spotlight, all off."""
    return [
        Light("sun", "0", LightKind.DIRECTIONAL, np.array([200.0, 200.0, 200.0]),
              position=np.array([400.0, 400.0, 400.0]), direction=np.array([0.1, 0.2, 0.7])),
        Light("bulb", "1", LightKind.POINT, np.array([250.0, 50.0, 150.0]),
              position=np.array([0.0, 200.0, 0.0])),
        Light("object spotlight", "2", LightKind.SPOT, np.array([75.0, 75.0, 75.0]),
              aperture_deg=25.75, owner=Owner.SELECTED_OBJECT),
        Light("camera spotlight", "3", LightKind.SPOT, np.array([155.0, 120.0, 75.0]),
              aperture_deg=30.0, owner=Owner.SELECTED_CAMERA),
    ]


AMBIENT_INTENSITY = np.array([200.0, 75.0, 255.0])


@dataclass
class Modes:
    """Every switch of SPEC 3's start state and SPEC 6's keys."""

    target: Target = Target.OBJECTS
    fill: Fill = Fill.FILLED
    triangle_only: bool = False  # `o`
    draw_all: bool = True  # `d`
    shading: Shading = Shading.FLAT
    projection: Projection = Projection.PERSPECTIVE
    normals: bool = False
    culling: bool = False
    texture: bool = True
    transform: TransformKind = TransformKind.ROTATE
    frame: Frame = Frame.LOCAL
    camera_mode: CameraMode = CameraMode.FLIGHT
    view_from_object: bool = False  # `C`
    show_help: bool = False  # `h` / F1: the help overlay listing every key
    term_view: TermView = TermView.EVERYTHING  # `v`
    probe: bool = False  # `i`: the lighting probe of the selected face
    matrices: bool = False  # `m`: the matrices panel
    side_by_side: bool = False  # `s`: Flat | Gouraud | Phong in three viewports
    # Parallel projection's half height in world units, fixed when `p` switches to parallel.
    parallel_half_height: float = 150.0


@dataclass(eq=False)
class Scene:
    objects: list[SceneObject]
    cameras: list[SceneObject]
    lights: list[Light] = field(default_factory=default_lights)
    ambient: np.ndarray = field(default_factory=lambda: AMBIENT_INTENSITY.copy())
    modes: Modes = field(default_factory=Modes)
    selected_object: int = 0
    selected_camera: int = 0
    selected_light: int = 0
    texture_path: str | None = None
    message: str = ""  # the last thing the person should read (errors, where a file was saved)

    def __post_init__(self) -> None:
        if not self.cameras:
            raise ValueError("a scene needs at least one camera")

    # --- selection -----------------------------------------------------------------------------
    @property
    def object(self) -> SceneObject | None:
        return self.objects[self.selected_object] if self.objects else None

    @property
    def camera(self) -> SceneObject:
        return self.cameras[self.selected_camera]

    @property
    def light(self) -> Light:
        return self.lights[self.selected_light]

    @property
    def targeted_element(self) -> SceneObject | None:
        """The selected object or camera, whichever x/y/z and u act on now; None when they act on a
        light (or on objects, with none loaded)."""
        if self.modes.target is Target.OBJECTS:
            return self.object
        return self.camera if self.modes.target is Target.CAMERAS else None

    # --- viewing -------------------------------------------------------------------------------
    @property
    def viewer(self) -> SceneObject:
        """What we look through: the selected camera, or the selected object after `C`."""
        if self.modes.view_from_object and self.object is not None:
            return self.object
        return self.camera

    def view_matrix(self) -> np.ndarray:
        return np.linalg.inv(self.viewer.model)

    def eye_position(self) -> np.ndarray:
        return self.viewer.origin

    def eye_backward(self) -> np.ndarray:
        """SPEC 4: V for parallel projection, the viewer's backward (+z) axis in the world."""
        return -self.viewer.forward

    def far_plane(self) -> float:
        """Beyond the whole scene, from wherever the eye is."""
        eye = self.eye_position()
        reach = [np.linalg.norm(o.centre - eye) + o.mesh.size for o in self.objects + self.cameras]
        reach += [np.linalg.norm(light.position - eye) for light in self.lights]
        return max(1000.0, 2.0 * max(reach, default=0.0))

    def projection_matrix(self, aspect: float) -> np.ndarray:
        far = self.far_plane()
        if self.modes.projection is Projection.PERSPECTIVE:
            return perspective(PERSPECTIVE_FOVY_DEG, aspect, NEAR_PLANE, far)
        half_h = self.modes.parallel_half_height
        return orthographic(half_h * aspect, half_h, -far, far)

    def matching_parallel_half_height(self) -> float:
        """Half height that keeps the selected object (or the origin) as large as in perspective."""
        target = self.object.centre if self.object is not None else np.zeros(3)
        depth = float(np.dot(target - self.eye_position(), self.viewer.forward))
        half_fov = np.radians(PERSPECTIVE_FOVY_DEG) / 2.0
        return max(depth, NEAR_PLANE) * float(np.tan(half_fov))

    # --- lights in the world -------------------------------------------------------------------
    def light_owner(self, light: Light) -> SceneObject | None:
        if light.owner is Owner.SELECTED_OBJECT:
            return self.object
        if light.owner is Owner.SELECTED_CAMERA:
            return self.camera
        return None

    def light_position(self, light: Light) -> np.ndarray:
        owner = self.light_owner(light)
        return owner.origin if owner is not None else light.position

    def spot_axis(self, light: Light) -> np.ndarray:
        """World direction a spotlight points: its owner's -z, turned by the light's own rotation."""
        owner = self.light_owner(light)
        rotation = owner.model[:3, :3] if owner is not None else np.eye(3)
        axis = rotation @ (light.axis_in_owner @ np.array([0.0, 0.0, -1.0]))
        return axis / np.linalg.norm(axis)


def euler_xyz(degrees: Vec3) -> np.ndarray:
    """Rz @ Ry @ Rx: turn about world x first. pyrr's matrix33 rotations are right for column vectors."""
    ax, ay, az = np.radians(degrees)
    return (pyrr.matrix33.create_from_z_rotation(az) @ pyrr.matrix33.create_from_y_rotation(ay)
            @ pyrr.matrix33.create_from_x_rotation(ax))


def perspective(fovy_deg: float, aspect: float, near: float, far: float) -> np.ndarray:
    """glFrustum for a symmetric field of view; pyrr builds it for row vectors, hence the transpose."""
    return pyrr.matrix44.create_perspective_projection(fovy_deg, aspect, near, far, dtype=np.float64).T


def orthographic(half_w: float, half_h: float, near: float, far: float) -> np.ndarray:
    """glOrtho, centred on the view axis; transposed from pyrr's row-vector layout as above."""
    return pyrr.matrix44.create_orthogonal_projection(
        -half_w, half_w, -half_h, half_h, near, far, dtype=np.float64).T
