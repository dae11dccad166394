"""SPEC 4's lights: each kind of light described once, the scene's four lights, and the term views.

A kind says where its light comes from at a point (L), whether it reaches the point, and which
x/y/z moves it takes. shaders/surface.glsl is the only other place that knows the kinds: it gets
their codes and the number of lights from `shader_defines`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum
from typing import ClassVar

import numpy as np

from marraztu.model.geometry import LIGHT_REACH, unit
from marraztu.model.transforms import TransformKind, rotation3

AMBIENT_INTENSITY = np.array([200.0, 75.0, 255.0])  # SPEC 4's Ia
FORWARD = np.array([0.0, 0.0, -1.0])  # an owner's forward axis in its own frame: where it looks
SPOT_APERTURE_RANGE_DEG = (1.0, 89.0)


@dataclass(frozen=True)
class WorldLight:
    """A light placed in the world: a spotlight's owner already resolved to a position and an axis."""

    name: str
    kind: LightKind
    intensity: np.ndarray  # (3,) in the seed's 0..255 units
    position: np.ndarray  # (3,) world; the sun's is only for drawing it
    direction: np.ndarray  # (3,) unit; directional: toward the light; spot: the cone's axis
    aperture_deg: float = 180.0

    def to_light(self, point: np.ndarray) -> np.ndarray:
        return self.kind.to_light(self, point)

    def reaches(self, point: np.ndarray) -> bool:
        return self.kind.reaches(self, point)


class LightKind:
    """What differs between kinds of light. One instance per kind: DIRECTIONAL, POINT, SPOT."""

    name: ClassVar[str]
    shader_code: ClassVar[int]  # surface.glsl's LIGHT_<NAME>
    has_cone: ClassVar[bool] = False
    moved_by: ClassVar[TransformKind]  # what x/y/z do to it; the other kind of move is refused
    refusal: ClassVar[str]  # why the other move is refused; {name} is the light's name
    DIRECTIONAL: ClassVar[LightKind]  # the kinds, where their repr names them, as an Enum's members are
    POINT: ClassVar[LightKind]
    SPOT: ClassVar[LightKind]

    def to_light(self, light: WorldLight, point: np.ndarray) -> np.ndarray:
        """L: the unit vector from the point toward the light."""
        return unit(light.position - point)

    def reaches(self, light: WorldLight, point: np.ndarray) -> bool:
        return True

    def world_direction(self, light: Light, owner_rotation: np.ndarray) -> np.ndarray:
        """WorldLight.direction for this light; `owner_rotation` is its owner's 3x3 (identity: none)."""
        return np.zeros(3)

    def move(self, light: Light, axis_index: int, amount: float) -> None:
        """One press of x/y/z with `moved_by`: radians about, or units along, the axis."""
        raise NotImplementedError

    def move_refusal(self, light: Light, axis_index: int, amount: float) -> str:
        """Why that press cannot move it ("" where it can)."""
        return ""

    def aim(self, light: WorldLight) -> str:
        """Where its light goes, in words, for a kind that sends it one way ("" for one that shines
        every way): a spotlight pointing at empty space lights no pixel."""
        return ""

    def __repr__(self) -> str:
        return f"LightKind.{self.name.upper()}"


class Directional(LightKind):
    """The sun: parallel rays from a direction; r turns that direction about the world axes."""

    name = "directional"
    shader_code = 0
    moved_by = TransformKind.ROTATE
    refusal = "the {name} is a direction: turn it with r instead"

    def to_light(self, light: WorldLight, point: np.ndarray) -> np.ndarray:
        return light.direction

    def world_direction(self, light: Light, owner_rotation: np.ndarray) -> np.ndarray:
        return unit(light.direction)

    def move(self, light: Light, axis_index: int, amount: float) -> None:
        light.direction = rotation3(axis_index, amount) @ light.direction

    def aim(self, light: WorldLight) -> str:
        return f"its light comes from {_unit_vector(light.direction)}"


class Point(LightKind):
    """The bulb: shines every way from a point; t moves it along the world axes."""

    name = "point"
    shader_code = 1
    moved_by = TransformKind.TRANSLATE
    refusal = "the {name} shines every way: move it with t instead"

    def move(self, light: Light, axis_index: int, amount: float) -> None:
        offset = np.zeros(3)
        offset[axis_index] = amount
        light.position = light.position + offset

    def move_refusal(self, light: Light, axis_index: int, amount: float) -> str:
        """Past LIGHT_REACH, where the next call of the programming interface would refuse the scene;
        a step back toward the origin is always taken."""
        along = float(light.position[axis_index])
        if abs(along + amount) <= max(abs(along), LIGHT_REACH):
            return ""
        return f"the {light.name} stops here: past {LIGHT_REACH:.0e} from the origin the GPU's 32-bit numbers " \
               "cannot light from it"


class Spot(LightKind):
    """A spotlight: a point light that lights only inside a cone about its owner's forward axis; r turns
    the axis about the owner's own axes."""

    name = "spot"
    shader_code = 2
    has_cone = True
    moved_by = TransformKind.ROTATE
    refusal = "the {name} sits on its owner: move the owner, or turn the light with r"

    def reaches(self, light: WorldLight, point: np.ndarray) -> bool:
        return cone_angle_deg(light, point) < light.aperture_deg

    def world_direction(self, light: Light, owner_rotation: np.ndarray) -> np.ndarray:
        return unit(owner_rotation @ (light.axis_in_owner @ FORWARD))

    def move(self, light: Light, axis_index: int, amount: float) -> None:
        light.axis_in_owner = rotation3(axis_index, amount) @ light.axis_in_owner

    def aim(self, light: WorldLight) -> str:
        return f"pointing {_unit_vector(light.direction)}, a {light.aperture_deg:g} deg cone"


DIRECTIONAL, POINT, SPOT = Directional(), Point(), Spot()
LightKind.DIRECTIONAL, LightKind.POINT, LightKind.SPOT = DIRECTIONAL, POINT, SPOT
LIGHT_KINDS: tuple[LightKind, ...] = (DIRECTIONAL, POINT, SPOT)


def kind_named(kind: LightKind | str) -> LightKind:
    """A kind, or a kind's name ("directional", "point", "spot")."""
    if isinstance(kind, LightKind):
        return kind
    found = next((known for known in LIGHT_KINDS if known.name == kind), None)
    if found is None:
        raise ValueError(f"no light kind {kind!r}; kinds: {', '.join(known.name for known in LIGHT_KINDS)}")
    return found


def _unit_vector(vector: np.ndarray) -> str:
    """A unit vector to two decimals, without a "-0.00"."""
    return "(" + ", ".join(f"{value:.2f}" for value in np.round(vector, 2) + 0.0) + ")"


def cone_angle_deg(light: WorldLight, point: np.ndarray) -> float:
    """Angle between a spotlight's axis and the ray from the light to the point; 180 at the light."""
    ray = np.asarray(point, float) - light.position
    length = float(np.linalg.norm(ray))
    if length == 0.0:
        return 180.0
    return float(np.degrees(np.arccos(np.clip(light.direction @ ray / length, -1.0, 1.0))))


class Owner(Enum):
    """Whose origin and forward axis a light follows."""

    NONE = "none"
    SELECTED_OBJECT = "selected object"
    SELECTED_CAMERA = "selected camera"


LightState = tuple[np.ndarray, np.ndarray, np.ndarray]  # position, direction, axis_in_owner


@dataclass(eq=False)
class Light:
    name: str
    key: str  # the key that switches it on and off
    kind: LightKind
    intensity: np.ndarray  # (3,) in the seed's 0..255 units
    on: bool = False
    position: np.ndarray = field(default_factory=lambda: np.zeros(3))  # world; owned lights: the owner's
    direction: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))  # sun: toward it
    aperture_deg: float = 180.0  # spotlights: half-angle of the cone
    owner: Owner = Owner.NONE
    # Spotlights: rotation of the axis relative to the owner's frame; identity = the owner's -z.
    axis_in_owner: np.ndarray = field(default_factory=lambda: np.eye(3))
    # Earlier states, for `u`: each move pushes a copy of the state before it. Empty: the initial one.
    history: list[LightState] = field(default_factory=list)
    # Its position as a scene file wrote it, in the scene's units: fitting to the models' units leaves it there.
    placed_by_file: bool = False

    def placed(self, owner_model: np.ndarray | None) -> WorldLight:
        """The light in the world; `owner_model` is its owner's model matrix (None: it has none)."""
        position = self.position if owner_model is None else owner_model[:3, 3].copy()
        rotation = np.eye(3) if owner_model is None else owner_model[:3, :3]
        return WorldLight(self.name, self.kind, np.asarray(self.intensity, float),
                          np.asarray(position, float), self.kind.world_direction(self, rotation),
                          self.aperture_deg)

    def move(self, kind: TransformKind, axis_index: int, amount: float) -> str:
        """One press of x/y/z; returns why it was refused ("" when it moved)."""
        if kind is not self.kind.moved_by:
            return self.kind.refusal.format(name=self.name)
        refusal = self.kind.move_refusal(self, axis_index, amount)
        if refusal:
            return refusal
        self.history.append((self.position.copy(), self.direction.copy(), self.axis_in_owner.copy()))
        self.kind.move(self, axis_index, amount)
        return ""

    def undo(self) -> bool:
        if not self.history:
            return False
        self.position, self.direction, self.axis_in_owner = self.history.pop()
        return True

    def fold_history(self, depth: int) -> None:
        """The moves since the history was `depth` deep become one undo step: back to where they began."""
        del self.history[depth + 1:]


def default_lights() -> list[Light]:
    """SPEC 4: the sun, the bulb, the object spotlight and the camera spotlight, all off."""
    return [
        Light("sun", "0", DIRECTIONAL, np.array([200.0, 200.0, 200.0]),
              position=np.array([400.0, 400.0, 400.0]), direction=np.array([0.1, 0.2, 0.7])),
        Light("bulb", "1", POINT, np.array([250.0, 50.0, 150.0]), position=np.array([0.0, 200.0, 0.0])),
        Light("object spotlight", "2", SPOT, np.array([75.0, 75.0, 75.0]),
              aperture_deg=25.75, owner=Owner.SELECTED_OBJECT),
        Light("camera spotlight", "3", SPOT, np.array([155.0, 120.0, 75.0]),
              aperture_deg=30.0, owner=Owner.SELECTED_CAMERA),
    ]


LIGHT_KEYS = tuple(light.key for light in default_lights())
MAX_LIGHTS = len(LIGHT_KEYS)  # what the shader has room for


def shader_defines() -> dict[str, str]:
    """What surface.glsl knows of the lights and the term views: each light kind's code, how many
    lights there may be, and the code of each thing a term view can paint."""
    defines = {f"LIGHT_{kind.name.upper()}": str(kind.shader_code) for kind in LIGHT_KINDS}
    shows = {f"SHOW_{show.name}": str(show.value) for show in Show}
    return {**defines, **shows, "MAX_LIGHTS": str(MAX_LIGHTS)}


# --- term views (key `v`) ----------------------------------------------------------------------
@dataclass(frozen=True)
class TermWeights:
    """Which terms of SPEC 4's sum a term view keeps: 1 keeps a term, 0 drops it."""

    ambient: float = 1.0
    diffuse: float = 1.0
    specular: float = 1.0

    def as_tuple(self) -> tuple[float, float, float]:
        return (self.ambient, self.diffuse, self.specular)


class Show(Enum):
    """What a term view paints: the lit colour, or one of the quantities the pipeline works with.
    The values are the shader's codes (SHOW_LIT, ...)."""

    LIT = 0
    DEPTH = 1  # the depth buffer's value as grey: black at the near plane, white at the far one
    NORMALS = 2  # N in world space as a colour, N * 0.5 + 0.5


@dataclass(frozen=True)
class TermView:
    """What the lit colour shows: SPEC 4's sum, one of its terms, or one light's share. Each view is
    clamped on its own, so the views add up to the whole wherever nothing saturates. The last views
    paint the depth or the normal instead of a colour."""

    name: str
    weights: TermWeights
    light_index: int | None = None  # "one light alone": which of the scene's lights
    shows: Show = Show.LIT

    EVERYTHING: ClassVar[TermView]
    AMBIENT: ClassVar[TermView]
    DIFFUSE: ClassVar[TermView]
    SPECULAR: ClassVar[TermView]
    DEPTH: ClassVar[TermView]
    NORMALS: ClassVar[TermView]

    @classmethod
    def alone(cls, light_index: int) -> TermView:
        """One light's diffuse and specular share, without the ambient."""
        return cls(f"light {light_index} alone", TermWeights(0.0, 1.0, 1.0), light_index)


TermView.EVERYTHING = TermView("everything", TermWeights())
TermView.AMBIENT = TermView("ambient only", TermWeights(1.0, 0.0, 0.0))
TermView.DIFFUSE = TermView("diffuse only", TermWeights(0.0, 1.0, 0.0))
TermView.SPECULAR = TermView("specular only", TermWeights(0.0, 0.0, 1.0))
TermView.DEPTH = TermView("depth", TermWeights(), shows=Show.DEPTH)
TermView.NORMALS = TermView("normals (world)", TermWeights(), shows=Show.NORMALS)
# `v` cycles through these: the sum, each term, each light alone, then depth and normals.
TERM_VIEWS = (TermView.EVERYTHING, TermView.AMBIENT, TermView.DIFFUSE, TermView.SPECULAR,
              *(TermView.alone(index) for index in range(MAX_LIGHTS)), TermView.DEPTH, TermView.NORMALS)
