"""The scene: objects, cameras, lights, selection, modes and transform histories. Plain numpy, no GL.

Matrices follow the column-vector convention of the seed and of SPEC (p' = M @ p, local transform
M = M @ T, global transform M = T @ M), stored as numpy (4, 4) float64 arrays. OpenGL wants them
column-major, which is ``M.T`` in numpy's row-major memory; the renderer does that conversion.
"""

from __future__ import annotations

import functools
import itertools
import math
import typing
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path

import numpy as np

from marraztu.errors import SHOWN_WHOLE, escaped, shortened
from marraztu.model.geometry import (
    CAMERAS_REACH,
    DRAWABLE_SIZE,
    FLOAT32_MAX,
    LIGHT_REACH,
    MODELS_REACH,
    Reach,
    all_lightable,
    lighting_refusal,
)
from marraztu.model.holders import first_holders
from marraztu.model.lights import (
    AMBIENT_INTENSITY,
    LIGHT_KINDS,
    SPOT_APERTURE_RANGE_DEG,
    Light,
    LightKind,
    Owner,
    TermView,
    WorldLight,
    default_lights,
)
from marraztu.model.mesh import Mesh
from marraztu.model.sampling import DEFAULT_SAMPLING, TextureSampling
from marraztu.model.transforms import (
    TransformKind,
    Vec3,
    orthographic,
    perspective,
    placement,
    transform_point,
    transform_points,
)

# SPEC 5: perspective is the seed's frustum l=-5 r=5 b=-5 t=5 n=5, i.e. a 90 degree vertical field.
PERSPECTIVE_FOVY_DEG = 90.0
# SPEC 5's near plane, and the least far plane, in a scene of the seed's models' size: a power of ten
# more or less for a scene of larger or smaller models (size_unit).
NEAR_PLANE, FAR_PLANE_LEAST = 5.0, 1000.0
# The seed's models are about +-45 units: a scene of models a power of ten larger or smaller is seen
# and moved as the seed's are, on a scale a power of ten larger or smaller (millimetres as metres).
SEED_MODEL_SIZE = 100.0
# The near plane keeps clear of what is shown and in view: within this share of the eye's distance to
# the nearest box (its normals included while drawn), measured along a view's widest direction...
NEAR_MARGIN = 0.5
WIDEST_ASPECT = 3.0  # ...in a view up to this wide (the window's shape is the front end's)...
# ...and where the eye is inside a box, or nearly, within this share of that box's least side that is
# not flat: a sheet 1e6 wide and 1 thick has its faces half a unit from an eye inside it, not 1,400.
INSIDE_FRACTION = 1e-3
# The guides (key `a`): an empty scene's grid is of the start camera's scale (it stands 150 away)...
GUIDES_MIN_EXTENT = 100.0
# ...and the grid lies within this many extents of the objects' box centre (its half width is three
# quarters of one, rounded up to a step, and the ground under them up to one down)...
GUIDES_REACH = 2.0
# ...and each world axis reaches half of one from the origin, or leaves the objects' box by half of
# one on its side, so that it stands out of a model around the origin, seen from close by.
WORLD_AXES_PAST_BOX = 0.5
# SPEC 5: the normals' length, a fixed share of the object's bounding-box diagonal (key `n`).
NORMAL_LENGTH_FRACTION = 0.05
# How far the selected object's depth may pull parallel projection's size from the rest of the scene's.
PARALLEL_DEPTH_RANGE = 1.5
# A box spanning less of the view's width and height than this is too small to see: under a pixel
# in a view 1000 pixels high (a model in millimetres loaded beside ships in metres).
SEEN_SHARE_LEAST = 1e-3
# A box whose outline is narrower than this across, in pixels, may light no pixel centre when filled (a
# 1000:1 beam framed whole in a window 300 pixels high is 0.2 of one thick).
THINNEST_PIXELS = 1.0
# A view reaching deeper than this many near planes into what it shows is drawn in depth slices, the
# farthest first, each this deep (over its near plane) and its own depth buffer: a 24-bit buffer's step
# at a slice's back is then under 1% of the depth there, where a molecule framed among ships left the
# ships past the buffer's last step (1 - near / depth rounds to 1, the cleared depth: not drawn).
DEPTH_SLICE_REACH = 1e5
DEPTH_SLICES_MOST = 8  # the farthest takes the rest: each slice draws the whole scene again
DEPTH_SLICE_OVERLAP = 1.01  # a slice reaches this far into the next one: no crack where they meet
MATERIAL_COLOURS = ("ka", "kd", "ks", "rgb")  # a material's colours, each 3 finite numbers in MATERIAL_COLOUR_RANGE
# SPEC 4's Ka, Kd and Ks are the share of each light a material gives back, and its rgb a colour of
# the same kind: none gives back more than it gets, or less than none. MTL's and glTF's colours hold to it too.
MATERIAL_COLOUR_RANGE = (0.0, 1.0)


class Target(Enum):
    OBJECTS = "objects"
    CAMERAS = "cameras"
    LIGHTS = "lights"


class Fill(Enum):
    FILLED = "filled"
    LINES = "lines"


class Shading(Enum):
    """How lighting spreads over a polygon, from the key to the shader (surface.glsl builds a lit
    program and a depth view's for each member, by its name). `F` switches Flat and Gouraud; Phong is
    the third model of the side-by-side view."""

    FLAT = "flat"
    GOURAUD = "gouraud"
    PHONG = "phong"

    @property
    def lights_vertices(self) -> bool:
        """Lit at vertices, in a lighting pass of its own (Phong lights pixels as it draws)."""
        return self is not Shading.PHONG


SWITCHED_SHADINGS = (Shading.FLAT, Shading.GOURAUD)  # what `F` switches between (SPEC 6)


class Projection(Enum):
    PERSPECTIVE = "perspective"
    PARALLEL = "parallel"


class Frame(Enum):
    LOCAL = "local"  # objects: M = M @ T, the object's own frame
    GLOBAL = "global"  # objects: M = T @ M, the world frame


class CameraMode(Enum):
    FLIGHT = "flight"
    ANALYSIS = "analysis"


@dataclass(frozen=True)
class Material:
    ka: Vec3
    kd: Vec3
    ks: Vec3
    ns: float
    rgb: Vec3 = (1.0, 1.0, 1.0)  # the seed's base colour (`# colour r g b`); kept, not drawn


_uids = itertools.count(1)


def model_refusal(model: object) -> str | None:
    """Why a model matrix cannot be drawn (None: it can): an affine 4x4 of finite numbers with an inverse."""
    matrix = _numbers(model)
    if matrix is None:
        return "must be a 4x4 of numbers"
    if matrix.shape != (4, 4):
        return f"must be 4x4, not {matrix.shape}"
    if not np.isfinite(matrix).all():
        return "must hold finite numbers"
    if not np.array_equal(matrix[3], [0.0, 0.0, 0.0, 1.0]):  # the lighting and the probe take M p as a point
        return f"must end in the row 0 0 0 1 (an affine transform), not {' '.join(f'{x:g}' for x in matrix[3])}"
    try:
        with np.errstate(all="ignore"):
            inverse = np.linalg.inv(matrix)
    except np.linalg.LinAlgError:
        inverse = None
    if inverse is None or not np.isfinite(inverse).all():
        return "has no inverse (a scale of 0?): the view and the normals need one"
    return None


def array_refusal(model: object) -> str | None:
    """Why a matrix put on a history by hand, which model_refusal passes, cannot be made current (None:
    it can): the renderer slices it as a numpy array, and a list or np.matrix slices otherwise."""
    if type(model) is np.ndarray:
        return None
    return f"must be a numpy array (obj.model = M makes one of any 4x4), not {type(model).__name__}"


def triple_refusal(value: object, names: str) -> str | None:
    """Why a colour or a point cannot be drawn (None: it can): it must be 3 finite numbers."""
    numbers = _numbers(value)
    if numbers is None or numbers.shape != (3,):
        return f"must be 3 numbers ({names}), not {_shown(value)}"
    if not np.isfinite(numbers).all():
        return "must be 3 finite numbers"
    return None


@dataclass(frozen=True)
class TripleKind:
    """What a colour, a place or a direction set by hand must be, past 3 finite numbers: the range of
    each of them, the GPU's or its meaning's (a scene file's material colours are held to it too)."""

    names: str  # its numbers' names, in a refusal
    most: float  # how far from 0 each may reach
    within: str  # `least` and `most` in a refusal's words: "must be 3 numbers {within}"
    shortest: float = 0.0  # a direction: how long, at least, to point some way
    least: float = -math.inf  # the lowest each may be: a colour's 0

    def holds(self, rows: np.ndarray) -> bool:
        """Whether every number of these finite (..., 3) rows is at least `least` and at most `most` from 0."""
        return bool((rows >= self.least).all() and (np.abs(rows) <= self.most).all())

    def points_some_way(self, rows: np.ndarray) -> bool:
        """Whether each of these finite (N, 3) rows is at least `shortest` long."""
        return bool((_squared_lengths(rows) >= self.shortest**2).all())


MATERIAL_COLOUR = TripleKind("R, G, B", MATERIAL_COLOUR_RANGE[1],
                             f"between {MATERIAL_COLOUR_RANGE[0]:g} and {MATERIAL_COLOUR_RANGE[1]:g}",
                             least=MATERIAL_COLOUR_RANGE[0])
# A light's intensity and the ambient Ia, in the seed's 0..255 units: brighter than 255 is only brighter
# (SPEC 4 clamps the sum), darker than none is nonsense.
LIGHT_COLOUR = TripleKind("R, G, B", FLOAT32_MAX, "from 0 to 3.4e38, where the GPU's 32-bit floats end", least=0.0)
# The sun's place: where its marker is drawn.
MARKED = TripleKind("x, y, z", FLOAT32_MAX, "within 32-bit floats (3.4e38), where the GPU reads them")
PLACE = TripleKind("x, y, z", LIGHT_REACH, f"within ±{LIGHT_REACH:.0e}: past it the GPU's 32-bit "
                   "numbers cannot light from there")
# unit() leaves (0, 0, 0), or a direction whose square rounds to 0, as it is (the sun then lights no face,
# and a highlight faces the eye); 1e-150 squared is still a normal float64, which it makes 1 long.
DIRECTION = TripleKind("x, y, z", FLOAT32_MAX, "within 32-bit floats (3.4e38)", shortest=1e-150)


def place_kind(light: Light) -> TripleKind:
    """What a light's position must be: the sun's marks where its marker is drawn, the others' are lit from."""
    return MARKED if light.kind is LightKind.DIRECTIONAL else PLACE


def reach_refusal(value: object, kind: TripleKind) -> str | None:
    """Why 3 finite numbers (triple_refusal passes them) of this kind cannot be drawn (None: they can)."""
    numbers: np.ndarray = _numbers(value)  # type: ignore[assignment]
    if not kind.holds(numbers):
        return f"must be 3 numbers {kind.within}, not {_shown(value)}"
    if not kind.points_some_way(numbers[None]):
        return f"must point some way: at least {kind.shortest:g} long, not {_shown(value)}"
    return None


def _all_within_reach(rows: np.ndarray, kinds: list[TripleKind], rest: TripleKind) -> bool:
    """Whether reach_refusal finds nothing in these (N, 3) finite rows, the first of these kinds and the
    rest of the kind `rest`, which points any way, in one pass over those."""
    own = rows[:len(kinds)]
    return all(kind.holds(row) and kind.points_some_way(row[None]) for kind, row in zip(kinds, own)) \
        and rest.holds(rows[len(kinds):])


def _squared_lengths(rows: np.ndarray) -> np.ndarray:
    """(N,): the squared length of each of (N, 3) rows, as unit() takes it."""
    return np.einsum("ij,ij->i", rows, rows)


def _shown(value: object) -> str:
    """A value in an error's one line: its repr, its line breaks made spaces, cut short."""
    if isinstance(value, np.bool_):  # numpy 1 shows np.True_ as True: "must be True or False, not True"
        return f"np.{bool(value)}_"
    return shortened(" ".join(repr(value).split()))


def _shown_name(name: str) -> str:
    """A name refused, in its error: its repr cut short, without the repr's length (the refusal says the name's)."""
    return repr(name) if len(name) <= SHOWN_WHOLE else f"{name[:SHOWN_WHOLE]!r}..."


def _picture_size(picture: object) -> str:
    """A picture's width x height, or its kind where it is none (set by hand, refused at the next call)."""
    if picture_refusal(picture) is None:
        return f"{picture.shape[1]}x{picture.shape[0]}"  # type: ignore[attr-defined]
    return type(picture).__name__


def _materials_refusal(element: SceneObject) -> str | None:
    """Why an element's material or part materials, set by hand, are not Materials (None: they are)."""
    if not isinstance(element.material, Material):
        return f"material must be a Material (dataclasses.replace(obj.material, kd=...)), not " \
               f"{type(element.material).__name__}"
    if element.given_material is not None and not isinstance(element.given_material, Material):
        return f"given_material must be None or a Material, not {type(element.given_material).__name__}"
    parts = element.part_materials
    if isinstance(parts, (tuple, list)):
        given = next((f"a {type(parts).__name__} holding a {type(part).__name__}" for part in parts
                      if not isinstance(part, Material)), None)
    else:
        given = type(parts).__name__
    if given is None:
        return None
    return f"part_materials must be a tuple of Materials, one per material of its file " \
           f"({len(element.mesh.materials)}), not {given}"


def picture_refusal(picture: object) -> str | None:
    """Why a picture set by hand cannot be drawn (None: it can, or there is none): the renderer takes
    (H, W, 3) bytes, top row first, as every reader gives them."""
    if picture is None:
        return None
    if not isinstance(picture, np.ndarray):
        given = type(picture).__name__
    elif picture.dtype == np.uint8 and picture.ndim == 3 and picture.shape[2] == 3 and picture.size:
        return None
    else:
        given = f"{picture.dtype} of shape {picture.shape}"
    return f"must be an (H, W, 3) array of bytes, top row first (add_mesh's texture= reads others), not {given}"


def _stacked(values: list[object], shape: tuple[int, ...]) -> np.ndarray | None:
    """(N, *shape) float64 of values each of `shape`; None where one is not (model_refusal says why)."""
    stack = _numbers(values) if values else np.zeros((0, *shape))
    return stack if stack is not None and stack.shape == (len(values), *shape) else None


def _numbers(value: object) -> np.ndarray | None:
    """`value` as float64 where it holds real numbers; None where it does not: text, which numpy and
    float() read as numbers ('90'), and complex numbers, whose imaginary part numpy drops."""
    try:
        given = np.asarray(value)
        return None if given.dtype.kind in "USVc" else given.astype(np.float64, copy=False)
    except (TypeError, ValueError, OverflowError):
        return None


def _finite_number(value: object) -> bool:
    number = _numbers(value)
    return number is not None and number.ndim == 0 and bool(np.isfinite(number))


def _number_within(value: object, low: float, high: float) -> bool:
    """A finite number from `low` to `high`; True and False are none, though Python counts them 1 and 0."""
    return not isinstance(value, (bool, np.bool_)) and _finite_number(value) and low <= float(value) <= high  # type: ignore[arg-type]


def _view_size_refusal(entry: object) -> str | None:
    """Why an entry of a camera's view_sizes set by hand cannot be given back (None: it can)."""
    if not (isinstance(entry, tuple) and len(entry) == 2):
        return f"must be a pair (its model matrix, the half height before or None), not {_shown(entry)}"
    if entry[1] is not None and not _number_within(entry[1], *HALF_HEIGHT_RANGE):
        return f"must hold None or a half height, a finite number from {HALF_HEIGHT_RANGE[0]:g} to " \
               f"{HALF_HEIGHT_RANGE[1]:g}, not {_shown(entry[1])}"
    return None


def light_refusal(light: Light) -> str | None:
    """Why a light's switch or aperture, set by hand, cannot be drawn (None: they can): `on` is True or
    False, not a truthy word; a spotlight's aperture is within the range + and - keep it in, as a scene
    file's is; another light's is no cone, but the probe tests the angle to it and the shader that angle's
    cosine, which agree only from 0 to 180 degrees."""
    if not isinstance(light.on, (bool, np.bool_)):
        return f"the {light.name}'s on must be True or False, not {_shown(light.on)}"
    aperture = light.aperture_deg
    low, high = SPOT_APERTURE_RANGE_DEG if light.kind.has_cone else (0.0, 180.0)
    if not _number_within(aperture, low, high):
        return (f"the {light.name}'s aperture_deg must be a number of degrees from {low:g} to {high:g}, not "
                f"{_shown(aperture)}")
    return None


def _is_index(value: object) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


# The longest name an object or camera may be given: a file's name may be as long (255 on Linux, macOS
# and Windows), and the status line and messages show it whole.
NAME_LIMIT = 255


def name_refusal(name: str) -> str | None:
    """Why a name given an object, camera or light cannot be shown (None: it can): longer than a file's,
    or holding a line break or another character no font draws, where the status line, the panels and
    the messages show it within one line of theirs."""
    if len(name) > NAME_LIMIT:
        return f"name is {len(name)} characters long: at most {NAME_LIMIT}"
    if not name.isprintable():
        odd = next(char for char in name if not char.isprintable())
        return f"name must be one line of printable characters: it holds {escaped(odd)}"
    return None


def kept_name(name: str) -> str:
    """A name a file gives (its own name, where nothing names the model), as name_refusal takes it: its
    control characters escaped, as the status line shows them, and cut to NAME_LIMIT."""
    return escaped(name)[:NAME_LIMIT]


def _element_refusal(element: object, what: str) -> str | None:
    """Why an object or camera put in the scene by hand is not one the program can use (None: it is):
    the parts every call reads before its values are checked."""
    if not isinstance(element, SceneObject):
        return f"the scene's {what} must hold SceneObjects, not {_shown(element)}"
    if not isinstance(element.name, str):
        return f"the scene's {what}' names must be str, not {_shown(element.name)}"
    if (refusal := name_refusal(element.name)) is not None:  # the panels lay a name out glyph by glyph
        return f"{_shown_name(element.name)}: {refusal}"
    if not isinstance(element.mesh, Mesh):
        return f"{element.name}'s mesh must be a Mesh, not {_shown(element.mesh)}"
    if not isinstance(element.history, list) or not element.history:
        return f"{element.name}'s history must be a list of model matrices, the current last, not " \
               f"{_shown(element.history)}"
    if not isinstance(element.view_sizes, list):
        return f"{element.name}'s view_sizes must be a list, not {_shown(element.view_sizes)}"
    top = element.history[-1]
    if type(top) is not np.ndarray and model_refusal(top) is None:  # the walk says what else is wrong
        return f"{element.name}'s model matrix {array_refusal(top)}"
    if not _is_index(element.selected_face):
        return f"{element.name}'s selected_face must be a whole number, not {_shown(element.selected_face)}"
    return None


def _shared_uid_refusal(objects: list[SceneObject], cameras: list[SceneObject]) -> str | None:
    """Why the scene's elements cannot be told apart (None: they can): the renderer keeps each one's GPU
    buffers by its uid, a whole number (a list raised 'unhashable'), and drew one with buffers another
    of its uid had released."""
    elements = [*objects, *cameras]
    uids = [element.uid for element in elements]
    if set(map(type, uids)) - {int}:  # one pass where all are Python's, as the program makes them
        odd = next((index for index, uid in enumerate(uids) if not _is_index(uid)), None)
        if odd is not None:
            return f"{elements[odd].name}'s uid must be a whole number, not {_shown(uids[odd])}"
    if len(set(uids)) == len(uids):
        return None
    first_of: dict[int, int] = {}
    second = next(index for index, uid in enumerate(uids) if first_of.setdefault(uid, index) != index)
    first = first_of[uids[second]]

    def place(index: int) -> str:
        shown = f"objects[{index}]" if index < len(objects) else f"cameras[{index - len(objects)}]"
        return f"{shown} ({elements[index].name})"
    if elements[first] is elements[second]:  # no copy: the words of copies would mislead
        return f"the scene's {place(first)} and {place(second)} are one element listed twice: list it once (the " \
               f"renderer keeps each element's GPU buffers by its uid, {uids[second]})"
    return f"the scene's {place(first)} and {place(second)} have the same uid {uids[second]}: the renderer keeps " \
           f"each element's GPU buffers by it (copy.copy and dataclasses.replace keep the original's; " \
           f"SceneObject(...) makes one of its own)"


def _light_parts_refusal(light: object) -> str | None:
    """Why a light put in the scene by hand is not one the program can place (None: it is): the parts
    every call reads before its values are checked."""
    if not isinstance(light, Light):
        return f"the scene's lights must hold Lights, not {_shown(light)}"
    if not isinstance(light.name, str) or not isinstance(light.key, str):
        return f"a light's name and key must be str, not {_shown(light.name)} and {_shown(light.key)}"
    if (refusal := name_refusal(light.name)) is not None:  # the panels and messages name it
        return f"{_shown_name(light.name)}: {refusal}"
    if not isinstance(light.kind, LightKind):
        kinds = ", ".join(map(repr, LIGHT_KINDS))
        return f"the {light.name}'s kind must be a LightKind ({kinds}; from {LightKind.__module__}), not " \
               f"{_shown(light.kind)}"
    if not isinstance(light.owner, Owner):
        members = ", ".join(f"Owner.{owner.name}" for owner in Owner)
        return f"the {light.name}'s owner must be an Owner ({members}; from {Owner.__module__}), not " \
               f"{_shown(light.owner)}"
    if not isinstance(light.history, list):
        return f"the {light.name}'s history must be a list, not {_shown(light.history)}"
    axis = _stacked([light.axis_in_owner], (3, 3))
    if axis is None or not np.isfinite(axis).all() or not _is_rotation(axis[0]):
        return f"the {light.name}'s axis_in_owner must be a 3x3 rotation of finite numbers (columns 1 long, at " \
               f"right angles, no mirror), not {_shown(light.axis_in_owner)}"
    return None


@dataclass(frozen=True)
class _Gathered:
    """What Scene._all_drawable stacks of the objects and cameras, read in one pass over them."""

    models: list[object]
    boxes: list[object]  # each mesh's bounds
    pictures: list[object]  # those set, not None
    materials: list[Material]  # each once: their own and their parts'

    @classmethod
    def of(cls, elements: Iterable[SceneObject]) -> _Gathered | None:
        """None where a material or the part materials are not plainly Materials in a tuple or a list
        (_materials_refusal, in the walk, says which)."""
        models, boxes, pictures, materials = [], [], [], {}
        for element in elements:
            models.append(element.model)
            boxes.append(element.mesh.bounds)
            if element.picture is not None:
                pictures.append(element.picture)
            parts = element.part_materials
            if type(parts) not in (tuple, list):
                return None
            materials[id(element.material)] = element.material  # _materials_of's, inline: no call an element
            if element.given_material is not None:
                materials[id(element.given_material)] = element.given_material
            for part in parts:
                materials[id(part)] = part
        if not all(map(isinstance, materials.values(), itertools.repeat(Material))):
            return None
        return cls(models, boxes, pictures, list(materials.values()))


# A rotation typed to 4 decimals (0.7071) is one: only the direction it turns the owner's -z to is read.
ROTATION_TOLERANCE = 1e-3


def _is_rotation(matrix: np.ndarray) -> bool:
    """Whether a 3x3 of finite numbers turns without scaling or mirroring: a spotlight's axis_in_owner,
    which a singular one (zeros) left pointing nowhere, lighting nothing or all round it."""
    with np.errstate(all="ignore"):  # 1e300 squared: not a rotation, and no warning
        square = matrix.T @ matrix
    return bool(np.allclose(square, np.eye(3), rtol=0.0, atol=ROTATION_TOLERANCE) and np.linalg.det(matrix) > 0.0)


@dataclass(eq=False)
class SceneObject:
    """An object or a camera: a mesh, a material and a history of model matrices (top = current).
    Setting `material` gives it to every part too; `part_materials` set after it tell parts apart."""

    name: str
    mesh: Mesh
    material: Material
    history: list[np.ndarray]
    selected_face: int = 0
    uid: int = field(default_factory=lambda: next(_uids))  # stable key for GPU resources
    source: Path | None = None  # the model file it was read from: PageDown's folder, --watch's file
    browsed: Path | None = None  # the file PageDown / PageUp last asked for: the next step goes on past it
    part_materials: tuple[Material, ...] = ()  # one per Mesh.materials: what each part is drawn with
    file_materials: tuple[Material, ...] = ()  # what the file gave each part: a part drawn with another is not its
    # The scene file's `scale` its mesh was read at (Mesh.scaled): a file read again in its place is too.
    scale: Vec3 = (1.0, 1.0, 1.0)
    # A scene file's `texture` for this object, (H, W, 3) uint8: drawn in place of its file's and the scene's.
    picture: np.ndarray | None = None
    picture_source: Path | None = None  # the file `picture` was read from: --watch's, which reads the scene again
    # A scene file's `material` for this object: it stays, as `picture` does, when its file is read again.
    given_material: Material | None = None
    # A camera's: the parallel view's half height before each view move whose matrix is still on its
    # history, latest last, with that matrix (None: made in perspective). `u` gives the size back as it
    # takes the matrix off, as the view's move or, after a key move, as the camera's own.
    view_sizes: list[tuple[np.ndarray, float | None]] = field(default_factory=list, repr=False)

    @classmethod
    def placed(cls, name: str, mesh: Mesh, material: Material, position: Vec3,
               rotation_deg: Vec3 = (0.0, 0.0, 0.0), source: Path | None = None) -> SceneObject:
        """Initial placement: turned about the world x, then y, then z axis, then moved."""
        return cls(name=name, mesh=mesh, material=material, history=[placement(position, rotation_deg)],
                   source=source)

    def __setattr__(self, name: str, value: object) -> None:
        """Setting `material` gives it to every part too, as a scene file's material does: the whole
        object is then drawn, probed and shown with it. Set `part_materials` after it to tell parts apart."""
        super().__setattr__(name, value)
        if name == "material":
            super().__setattr__("part_materials", tuple(value for _ in self.mesh.materials))

    def __repr__(self) -> str:
        """What it is and where, not its tables: the history grows a matrix with every move."""
        own_picture = "" if self.picture is None else f", picture={_picture_size(self.picture)}"
        return (f"SceneObject(name={self.name!r}, mesh={self.mesh!r}, material={self.material!r}, "
                f"{self._placement_shown()}, selected_face={self.selected_face}, source={self.source!r}{own_picture})")

    def _placement_shown(self) -> str:
        """Its matrix and how many moves led there, in its repr; what its history or matrix is instead,
        set by hand (refused at the next call), shortened: a repr never raises, nor prints a table."""
        history = self.history
        if not isinstance(history, list) or not history:
            return f"history={_shown(history)}"
        matrix = _numbers(history[-1])
        model = repr(np.round(matrix, 6).tolist()) if matrix is not None and matrix.shape == (4, 4) else \
            _shown(history[-1])
        return f"model={model}, moves={len(history) - 1}"

    @property
    def model(self) -> np.ndarray:
        return self.history[-1]

    @model.setter
    def model(self, matrix: object) -> None:
        """A move set by hand (the programming interface): an undo step, as a key's is, refused here
        where it could not be drawn."""
        refusal = model_refusal(matrix)
        if refusal is not None:
            raise ValueError(f"{self.name}'s model matrix {refusal}")
        self.push(matrix)

    def picture_of(self, part: int) -> np.ndarray | None:
        """The picture the file's material `part` (-1: the whole) is drawn with; None: the scene's."""
        return self.picture if self.picture is not None else self.mesh.own_picture(part)

    def sampling_of(self, part: int) -> TextureSampling:
        """How picture_of(part) is sampled: the file's way for its own picture, the default for another."""
        return DEFAULT_SAMPLING if self.picture is not None else self.mesh.own_sampling(part)

    def material_of(self, index: int) -> Material:
        """The material of the file's material `index` (Mesh.materials); -1: the object's own."""
        return self.part_materials[index] if 0 <= index < len(self.part_materials) else self.material

    def material_name_of_face(self, face: int) -> str | None:
        """The file's name for the material polygon `face` is drawn with: None where the file names
        none, or the part is drawn with another (a scene file's, or one set by hand)."""
        index = -1 if self.mesh.face_material is None else int(self.mesh.face_material[face])
        if not 0 <= index < len(self.file_materials) or self.material_of(index) is not self.file_materials[index]:
            return None
        return self.mesh.materials[index].name

    def face_material(self, face: int) -> Material:
        return self.material_of(-1 if self.mesh.face_material is None else int(self.mesh.face_material[face]))

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
        return transform_point(self.model, (low + high) / 2.0)

    def reach_along(self, direction: np.ndarray) -> float:
        """How far from its centre a line along the world `direction` (a unit vector) leaves its box."""
        step = np.linalg.solve(self.model[:3, :3], direction)  # a world unit along it, in the box's frame
        low, high = self.mesh.bounds
        moving = np.abs(step) > 0.0
        return float(np.min((high - low)[moving] / 2.0 / np.abs(step[moving]), initial=np.inf))

    def push(self, model: np.ndarray) -> None:
        self.history.append(np.asarray(model, dtype=np.float64))

    def undo(self) -> bool:
        """The previous model matrix made current again. The keys push only matrices that can be drawn;
        one pushed by hand (the programming interface's scene) under the current one is refused here,
        ValueError, before it becomes current: the calls after could not undo past it."""
        if len(self.history) <= 1:
            return False
        refusal = model_refusal(self.history[-2]) or array_refusal(self.history[-2])
        if refusal is not None:
            raise ValueError(f"{self.name}'s history[-2], which u undoes to, {refusal}")
        self.history.pop()
        return True

    def fold_history(self, depth: int) -> None:
        """The moves pushed since the history was `depth` deep become one undo step (a mouse gesture)."""
        del self.history[depth:-1]

    def push_view_move(self, model: np.ndarray, half_height_before: float | None) -> None:
        """A view move (framing, reset, the mouse) of this camera: a move `u` takes back with the parallel
        view's size before it."""
        self.push(model)
        self.view_sizes.append((self.history[-1], half_height_before))

    def amend_view_move(self, model: np.ndarray) -> None:
        """The last view move's matrix replaced by the next event of its gesture; its size before kept."""
        self.history[-1] = np.asarray(model, dtype=np.float64)
        self.view_sizes[-1] = (self.history[-1], self.view_sizes[-1][1])

    def made_by_view_move(self) -> bool:
        """Whether the current matrix is the one a view move put on the history. An entry set by hand that
        `u` could not give back is refused here, ValueError, as undo refuses a history[-2]."""
        if not self.view_sizes:
            return False
        refusal = _view_size_refusal(self.view_sizes[-1])
        if refusal is not None:
            raise ValueError(f"{self.name}'s view_sizes[-1], which u gives back, {refusal}")
        return self.view_sizes[-1][0] is self.history[-1]

    def drop_step_under_top(self) -> None:
        """history[-2] taken off, the current matrix kept: `u` then takes the two steps back as one, so
        where a view move pushed the dropped matrix, the size before it is the one that step gives back."""
        dropped = self.history.pop(-2)
        tail = self.view_sizes[-2:]  # the entries of history[-2:] are the last two at most, in its order
        before = [size for matrix, size in tail if matrix is dropped]
        if before:
            below = [entry for entry in tail if entry[0] is not dropped and entry[0] is not self.history[-1]]
            self.view_sizes[-2:] = [*below, (self.history[-1], before[0])]


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
    pipeline: bool = False  # `P`: the selected face through every space, model to window
    side_by_side: bool = False  # `s`: Flat | Gouraud | Phong in three viewports
    guides: bool = False  # `a`: the grid and the axes
    # Parallel projection's half height in world units, fixed when `p` switches to parallel.
    parallel_half_height: float = 150.0


_MODE_KINDS: dict[str, type] = typing.get_type_hints(Modes)  # the kind each switch holds
# A parallel view's half height set by hand: P holds its inverse in float32, which ends at 3.4e38.
HALF_HEIGHT_RANGE = (1e-30, 1e30)
# A material's Ns set by hand: above 0, as a scene file's (a negative one turns every highlight inside
# out), and within float32, where the shader raises to it.
NS_RANGE = (math.ulp(0.0), FLOAT32_MAX)


def _modes_refusal(modes: Modes) -> str | None:
    """Why a switch set by hand cannot be drawn (None: none): each holds the kind its key sets."""
    for name, kind in _MODE_KINDS.items():
        value = getattr(modes, name)
        if kind is bool:
            if not isinstance(value, bool):  # numpy's True too: moderngl packs only Python's into a uniform
                return f"modes.{name} must be True or False, not {_shown(value)}"
        elif kind is float:
            if not _number_within(value, *HALF_HEIGHT_RANGE):
                return f"modes.{name} must be a finite number from {HALF_HEIGHT_RANGE[0]:g} to " \
                       f"{HALF_HEIGHT_RANGE[1]:g}, not {_shown(value)}"
        elif not isinstance(value, kind):
            members = [f"{kind.__name__}.{member}" for member in _named_members(kind)]
            return f"modes.{name} must be a {kind.__name__} ({', '.join(members)}; from {kind.__module__}), " \
                   f"not {_shown(value)}"
    return None


def _named_members(kind: type) -> list[str]:
    """An enum's members, or a class's own instances kept as its attributes (TermView.EVERYTHING)."""
    if issubclass(kind, Enum):
        return [member.name for member in kind]
    return [name for name, value in vars(kind).items() if isinstance(value, kind)]


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
    texture_named_at: str | None = None  # 'FILE:LINE: texture', the scene file's entry that names texture_path
    texture_plain: bool = False  # the scene file's `texture = false`: no picture (PLAIN_PICTURE), no checker
    # (H, W, 3) uint8, top row first, what filled faces show; None: white. Its file names it in a repr.
    texture: np.ndarray | None = field(default=None, repr=False)
    message: str = ""  # the last thing the person should read (errors, where a file was saved)
    # The cameras the view moves (framing, reset, the mouse) moved since the target last moved, latest
    # last: `u` undoes those first, whatever is targeted (each camera's view_sizes holds the parallel
    # view's size to give back). And the mouse gesture still going on, whose events make one undo step in all.
    view_moves: list[SceneObject] = field(default_factory=list)
    view_gesture: str | None = None
    # How deep the dragged element's history was when the ctrl-drag going on began: its events fold into
    # one undo step.
    drag_depth: int = 0
    # Elements that joined or were read again so far: who watches the files read looks when it moves.
    loads: int = 0
    # The scale (unit) the built-in camera's body and the lights' places were last fitted to.
    fitted_unit: float = 1.0
    # A scene file that places no camera: its models are framed at start, as a model given alone is.
    frame_at_start: bool = False
    notes: tuple[str, ...] = ()  # what its scene file's read noted (a value that looks like a slip), told at load

    def __post_init__(self) -> None:
        if not self.cameras:
            raise ValueError("a scene needs at least one camera")

    # --- going back ----------------------------------------------------------------------------
    def restorer(self, presses: int) -> Callable[[], None]:
        """What puts the scene back in place as it is now, after up to `presses` keys (the programming
        interface's press refused half way): the fields of the scene, its modes, elements and lights, and
        its lists, but for where PageDown has got to where an element shows its file as before
        (_browsing_put_back). Arrays and meshes are kept, not copied: keys replace them, never change one
        in place. A key changes a history, and a camera's view sizes, only at its top (a push, an undo, a
        view step redone or dropped), so of each the last presses + 1 are kept: the cost grows with the
        keys and the elements, not the histories."""
        elements = (*self.objects, *self.cameras, *self.lights)
        fields = [(part, dict(vars(part))) for part in (self, self.modes, *elements)]
        lists = [(items, list(items)) for items in (self.objects, self.cameras, self.lights, self.view_moves)]
        stacks = [*(element.history for element in elements),
                  *(element.view_sizes for element in (*self.objects, *self.cameras))]
        tops = [(stack, len(stack), stack[max(0, len(stack) - presses - 1):]) for stack in stacks]

        def restore() -> None:
            for part, kept in fields:
                # past SceneObject's setattr: its part materials are kept as they were
                vars(part).update(_browsing_put_back(vars(part), kept))
            for items, contents in lists:
                items[:] = contents
            for stack, depth, top in tops:
                stack[depth - len(top):] = top
        return restore

    # --- selection -----------------------------------------------------------------------------
    def settle_selection(self) -> None:
        """Selections kept within lists changed by hand (the programming interface's scene): a negative
        one counts from the end, as Python's indices do; the last element where the selected one is gone.
        ValueError where a selection is no whole number, or no camera or light is left to select."""
        if not self.cameras or not self.lights:
            raise ValueError(f"the scene needs a camera and a light (it has {len(self.cameras)} and "
                             f"{len(self.lights)}): the keys and panels act on the selected ones")
        for attribute, elements in (("selected_object", self.objects), ("selected_camera", self.cameras),
                                    ("selected_light", self.lights)):
            index = getattr(self, attribute)
            if not _is_index(index):
                raise ValueError(f"the scene's {attribute} must be a whole number, not {_shown(index)}")
            index = int(index) + (len(elements) if index < 0 else 0)
            setattr(self, attribute, max(0, min(index, len(elements) - 1)))

    def check_by_hand(self) -> None:
        """What every call of the programming interface checks first, as the scene may have been changed
        by hand since the last: the kinds of its parts, then its selections, then its values."""
        self.check_kinds()
        self.settle_selection()
        self.check_values()

    def check_kinds(self) -> None:
        """ValueError where a part of the scene replaced by hand is not of the kind the program made
        there (a list of objects, cameras and lights, a Mesh, a Light's kind, the Modes...): every
        other check reads those parts. One isinstance a part: no pass over any table."""
        refusal = self._kind_refusal()
        if refusal is not None:
            raise ValueError(refusal)

    def _kind_refusal(self) -> str | None:
        for what, items in (("objects", self.objects), ("cameras", self.cameras), ("lights", self.lights)):
            if not isinstance(items, list):
                return f"the scene's {what} must be a list, not {type(items).__name__}"
        if not isinstance(self.message, str):
            return f"the scene's message must be str, not {_shown(self.message)}"
        if not isinstance(self.modes, Modes):
            return f"the scene's modes must be a Modes (from {Modes.__module__}), not {_shown(self.modes)}"
        for what, items in (("objects", self.objects), ("cameras", self.cameras)):
            refusal = next(filter(None, map(_element_refusal, items, itertools.repeat(what))), None)
            if refusal is not None:
                return refusal
        refusal = _shared_uid_refusal(self.objects, self.cameras)
        return refusal or next(filter(None, map(_light_parts_refusal, self.lights)), None)

    def check_values(self) -> None:
        """ValueError, naming the first, where a value changed by hand (the programming interface's
        scene) cannot be drawn: a model matrix not affine or without an inverse, a light's or a
        material's colour, place or direction that is not 3 finite numbers within its kind's range
        (TripleKind), a spotlight's aperture past 1..89 degrees (another's past 0..180), a mode not of
        the kind its key sets."""
        if self._all_drawable():  # every call of the interface asks: the walk below costs far more per element
            return
        refusal = next(self._refusals(), None)
        if refusal is not None:
            raise ValueError(refusal)

    def _all_drawable(self) -> bool:
        """Whether _refusals finds nothing, in a few passes over stacked arrays (False may also mean
        that some value could not be stacked: the walk then decides)."""
        if _modes_refusal(self.modes) is not None:
            return False
        gathered = _Gathered.of((*self.objects, *self.cameras))
        if gathered is None:
            return False
        if any(map(picture_refusal, (self.texture, *gathered.pictures))):  # None where it can be drawn
            return False
        materials = gathered.materials
        shininess = _stacked([material.ns for material in materials], ())
        if shininess is None or not ((shininess >= NS_RANGE[0]) & (shininess <= NS_RANGE[1])).all():
            return False
        if any(light_refusal(light) is not None for light in self.lights):
            return False
        own = self._own_triples()
        triples = [value for _, value, _ in own]
        triples += [getattr(material, key) for material in materials for key in MATERIAL_COLOURS]
        models, rows = _stacked(gathered.models, (4, 4)), _stacked(triples, (3,))
        if models is None or rows is None or not np.isfinite(rows).all() or not np.isfinite(models).all():
            return False
        if not _all_within_reach(rows, [kind for _, _, kind in own], MATERIAL_COLOUR):
            return False
        if not (models[:, 3] == [0.0, 0.0, 0.0, 1.0]).all():
            return False
        try:
            with np.errstate(all="ignore"):
                if not np.isfinite(np.linalg.inv(models)).all():
                    return False
        except np.linalg.LinAlgError:  # one of them is singular: the walk names it
            return False
        bounds = _stacked(gathered.boxes, (2, 3))
        if bounds is None:
            return False
        kinds, counts = zip(*self._reach_counts())
        most = np.repeat([reach.most for reach in kinds], counts)
        return all_lightable(*placed_reach_and_size(models, bounds), most)

    def _own_triples(self) -> list[tuple[str, object, TripleKind]]:
        """The scene's colours, places and directions that must be 3 finite numbers, outside its elements:
        what each is, its value, and its kind."""
        triples: list[tuple[str, object, TripleKind]] = [("the scene's ambient", self.ambient, LIGHT_COLOUR)]
        for light in self.lights:
            triples += [(f"the {light.name}'s intensity", light.intensity, LIGHT_COLOUR),
                        (f"the {light.name}'s position", light.position, place_kind(light)),
                        (f"the {light.name}'s direction", light.direction, DIRECTION)]
        return triples

    def _refusals(self) -> Iterator[str]:
        """Each value that cannot be drawn, in words: the walk that _all_drawable's stacked passes
        shortcut, both reading the values from _own_triples, _materials_of and MATERIAL_COLOURS."""
        refusal = _modes_refusal(self.modes)
        if refusal is not None:
            yield f"the scene's {refusal}"
        refusal = picture_refusal(self.texture)
        if refusal is not None:
            yield f"the scene's texture {refusal}"
        yield from (refusal for refusal in map(light_refusal, self.lights) if refusal is not None)
        triples = self._own_triples()
        for element, reach in zip((*self.objects, *self.cameras), self._reaches()):
            refusal = model_refusal(element.model)
            if refusal is not None:
                yield f"{element.name}'s model matrix {refusal}"
            else:  # where its matrix puts it: moved or scaled by hand past what the GPU lights
                refusal = placement_refusal(element.model, element.mesh, reach)
                if refusal is not None:
                    yield f"{element.name} as its model matrix places it: {refusal}"
            refusal = picture_refusal(element.picture)
            if refusal is not None:
                yield f"{element.name}'s picture {refusal}"
            refusal = _materials_refusal(element)
            if refusal is not None:
                yield f"{element.name}'s {refusal}"
                continue
            for material in _materials_of(element):
                triples += [(f"{element.name}'s material {key}", getattr(material, key), MATERIAL_COLOUR)
                            for key in MATERIAL_COLOURS]
                if not _number_within(material.ns, *NS_RANGE):
                    yield f"{element.name}'s material ns must be a number greater than 0 and within 32-bit " \
                          f"floats (3.4e38), not {_shown(material.ns)}"
        for what, value, kind in triples:
            refusal = triple_refusal(value, kind.names) or reach_refusal(value, kind)
            if refusal is not None:
                yield f"{what} {refusal}"

    def _reaches(self) -> list[Reach]:
        """(objects + cameras): reach_of of each element, in the scene's order, without a scan per element."""
        return [reach for reach, count in self._reach_counts() for _ in range(count)]

    def _reach_counts(self) -> list[tuple[Reach, int]]:
        """reach_of of the objects, then of the cameras, each with how many there are: the scene's order."""
        return [(MODELS_REACH, len(self.objects)), (CAMERAS_REACH, len(self.cameras))]

    def reach_of(self, element: SceneObject) -> Reach:
        """How far from the origin, along an axis, an element may reach, and the words that say so: a
        camera's eye and body stand farther off than a model may, where the program frames the models from."""
        return CAMERAS_REACH if element in self.cameras else MODELS_REACH  # identity: eq=False

    def placement_refusal(self, element: SceneObject, model: np.ndarray, mesh: Mesh | None = None) -> str | None:
        """Why `element` placed by `model` (an affine matrix with an inverse), and given `mesh` where one is
        given, cannot be lit; None if it can."""
        return placement_refusal(model, element.mesh if mesh is None else mesh, self.reach_of(element))

    def move_refusal(self, element: SceneObject, model: np.ndarray) -> str:
        """Why a move cannot take `element` to `model`, in a message's words ("" where it can): why_move_stops."""
        why = self.why_move_stops(element, model)
        return f"{element.name} stops here: {why}" if why else ""

    def why_move_stops(self, element: SceneObject, model: np.ndarray) -> str:
        """Why a move cannot take `element` to `model` ("" where it can): past its reach, or under
        DRAWABLE_SIZE (a turn in its own frame of a matrix scaled unevenly by hand), where the next call of
        the programming interface would refuse the scene. A move that takes it no farther off and makes
        it no smaller is always made."""
        farthest, size = placed_reach_and_size(np.stack([element.model, model]), np.array([element.mesh.bounds] * 2))
        reach = self.reach_of(element)
        if farthest[1] > max(farthest[0], reach.most):
            return f"past {reach.most:.0e} from the origin the GPU's 32-bit numbers cannot {reach.cannot} it"
        if 0.0 < size[1] < min(size[0], DRAWABLE_SIZE):
            return f"under {DRAWABLE_SIZE:.0e} across the GPU's 32-bit numbers cannot light it"
        return ""

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
        """The selected object or camera, whichever x/y/z and u act on; None when they act on a
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

    def unit(self) -> float:
        """The scene's scale against the seed's (size_unit of its largest model)."""
        return size_unit(max((obj.mesh.size for obj in self.objects), default=0.0))

    def far_plane(self, near: float | None = None) -> float:
        """Beyond the whole scene, from wherever the eye is. In parallel projection, whose depth buffer
        steps evenly from near to far, twice the depth of the farthest shown point, and never nearer
        than the near plane (`near`, where the caller has it): neither the floor nor the lights far
        off (a molecule, or a model 5,000 km from the lights at the origin, would have its back faces
        show through its front)."""
        if self.modes.projection is Projection.PARALLEL:  # in view or not: a zoom never moves it
            deepest = float(self._shown_boxes(everywhere=True).backs.max(initial=0.0))
            if self.modes.guides:
                low, high, extent = self.guides_extent()
                deepest = max(deepest, self.depth_of((low + high) / 2.0) + GUIDES_REACH * extent,
                              self.depth_of(np.zeros(3)) + float(world_axes_lengths(high, extent).max()))
            return 2.0 * max(deepest, self.near_plane() if near is None else near)
        eye = self.eye_position()
        elements = self.objects + self.cameras
        centres = _placed_centres(elements)
        reach = list(np.linalg.norm(centres - eye, axis=1) + [element.mesh.size for element in elements])
        reach += [np.linalg.norm(light.position - eye) for light in self.lights]
        return max(FAR_PLANE_LEAST * self.unit(), 2.0 * max(reach, default=0.0))

    def guides_extent(self) -> tuple[np.ndarray, np.ndarray, float]:
        """The objects' world box, and the guides' scale: the box's size, never under GUIDES_MIN_EXTENT
        on the scene's scale (a model a millimetre across, or one 5,000 km from the origin, gets a grid
        of its own size)."""
        low, high = world_box(self.objects)
        return low, high, max(float(np.max(high - low)), GUIDES_MIN_EXTENT * self.unit())

    def shown_elements(self) -> list[SceneObject]:
        """What the picture draws: the selected object alone (SPEC 5's `o` and `d`) or every object
        and camera; never the viewer, which we look from inside."""
        if self.modes.triangle_only or not self.modes.draw_all:
            shown = [self.object] if self.object is not None else []
        else:
            shown = self.objects + self.cameras
        viewer = self.viewer
        return [element for element in shown if element is not viewer and element.mesh.face_count > 0]

    def drawn_faces(self) -> list[tuple[SceneObject, int, int]]:
        """SPEC 5's `o` and `d` as (element, first face, face past the last) of what the picture draws:
        the shown elements whole, or the selected one's faces up to the selected face, or that face alone."""
        shown = self.shown_elements()
        if not self.modes.triangle_only:
            return [(element, 0, element.mesh.face_count) for element in shown]
        if not shown:
            return []
        selected = shown[0]  # the selected object alone
        face = selected.selected_face % selected.mesh.face_count
        return [(selected, 0 if self.modes.draw_all else face, face + 1)]

    def near_plane(self, aspect: float = WIDEST_ASPECT) -> float:
        """SPEC 5's 5 units on the scene's scale, brought in to keep clear of what is shown and in a
        view `aspect` wide, or WIDEST_ASPECT if narrower (see NEAR_MARGIN and INSIDE_FRACTION)."""
        return self._near_of(self._boxes_near(aspect))

    def _boxes_near(self, aspect: float) -> InView:
        """The boxes the near plane keeps clear of, in a view `aspect` wide: a light at the eye asks nothing."""
        return self._shown_boxes(max(aspect, WIDEST_ASPECT), marker=False)

    def _near_of(self, boxes: InView) -> float:
        clear = np.maximum(NEAR_MARGIN * boxes.distances, INSIDE_FRACTION * boxes.least_sides)
        return min(NEAR_PLANE * self.unit(), float(clear.min(initial=np.inf)))

    def _shown_boxes(self, aspect: float = WIDEST_ASPECT, marker: bool = True, everywhere: bool = False) -> InView:
        """The boxes of what is shown that meet a view `aspect` wide (all of them, `everywhere`), the
        normals drawn out of them included, and the selected light's marker while lights are targeted
        (`marker`)."""
        models, bounds = self._shown_placements(marker)
        outlook = self.outlook(aspect)
        view = outlook.view @ models
        in_eye = np.einsum("nij,nkj->nki", view[:, :3, :3], _box_corners(bounds)) + view[:, None, :3, 3]
        depth = -in_eye[..., 2]
        beyond = outlook.beyond(in_eye)
        seen = np.ones_like(beyond) if everywhere else ~beyond
        distances = self._least_depths(models, bounds, depth, aspect)
        return InView(distances[seen], depth.max(axis=1, initial=-np.inf)[seen], _least_sides(bounds)[seen])

    def outlook(self, aspect: float) -> Outlook:
        """The view now, `aspect` wide, as the box tests see it."""
        parallel = self.modes.projection is Projection.PARALLEL
        return Outlook(self.viewer.model, self.modes.parallel_half_height if parallel else None, aspect)

    def _shown_placements(self, marker: bool) -> tuple[np.ndarray, np.ndarray]:
        """(N, 4, 4) model matrices and (N, 2, 3) boxes of what is shown, each box grown by
        the normals drawn out of it, and a box of no size round the selected light's marker while
        lights are targeted (`marker`)."""
        shown = self.shown_elements()
        models, bounds = _placements(shown)
        sizes = np.array([element.mesh.size for element in shown], dtype=np.float64)
        pad = NORMAL_LENGTH_FRACTION * sizes if self.modes.normals else np.zeros(len(shown))
        bounds = bounds + np.stack([-pad, pad], axis=1)[:, :, None]
        if marker and self.modes.target is Target.LIGHTS:
            at_marker = np.eye(4)
            at_marker[:3, 3] = self.placed_light(self.light).position
            models = np.concatenate([models, at_marker[None]])
            bounds = np.concatenate([bounds, np.zeros((1, 2, 3))])
        return models, bounds

    def _least_depths(self, models: np.ndarray, bounds: np.ndarray, depth: np.ndarray, aspect: float
                      ) -> np.ndarray:
        """(N,): how deep, at least, each box's nearest point in a view `aspect` wide lies, from its
        (N, 8) corners' depths: in parallel projection its nearest corner's depth (0 with the eye past
        it); in perspective the eye's distance to the box, in the box's frame, of which a point that
        far toward the view's corner (aspect : 1 : 1) is 1 / sqrt(aspect^2 + 2) deep."""
        if self.modes.projection is Projection.PARALLEL:
            return np.maximum(depth.min(axis=1, initial=np.inf), 0.0)
        eye = self._eye_in_frames(models)
        outside = eye - np.clip(eye, bounds[:, 0], bounds[:, 1])
        return np.linalg.norm(outside, axis=1) / np.sqrt(aspect**2 + 2.0)

    def _eye_in_frames(self, models: np.ndarray) -> np.ndarray:
        """(N, 3): the eye in the frames of (N, 4, 4) model matrices, where each mesh's box is a box."""
        return np.einsum("nij,j->ni", np.linalg.inv(models), np.append(self.eye_position(), 1.0))[:, :3]

    def lens(self, aspect: float) -> Lens:
        """What P is built from now, in a view `aspect` wide: the near and far planes follow what is shown."""
        return self._lens_from(aspect, self.near_plane(aspect))

    def _lens_from(self, aspect: float, near: float) -> Lens:
        parallel = self.modes.projection is Projection.PARALLEL
        return Lens(aspect, near, self.far_plane(near), self.modes.parallel_half_height if parallel else None)

    def depth_slices(self, aspect: float) -> list[Lens]:
        """The lens (Scene.lens) cut in depth, farthest first, where what is shown and in view reaches
        deeper than DEPTH_SLICE_REACH near planes; the lens whole elsewhere (every ordinary view). The
        first's far plane and the last's near plane are the lens's."""
        boxes = self._boxes_near(aspect)  # one look at the boxes for the near plane and the depth
        lens = self._lens_from(aspect, self._near_of(boxes))
        deepest = min(lens.far, float(boxes.backs.max(initial=0.0)))
        cuts = [lens.near]
        while 0.0 < cuts[-1] * DEPTH_SLICE_REACH < deepest and len(cuts) < DEPTH_SLICES_MOST:  # 0: no depth to cut
            cuts.append(cuts[-1] * DEPTH_SLICE_REACH)
        if len(cuts) == 1:
            return [lens]
        fars = [cut * DEPTH_SLICE_OVERLAP for cut in cuts[1:]] + [lens.far]
        return [Lens(aspect, near, far, lens.half_height) for near, far in zip(cuts, fars)][::-1]

    def projection_matrix(self, aspect: float) -> np.ndarray:
        return self.lens(aspect).matrix()

    def matching_parallel_half_height(self) -> float:
        """Half height that keeps the scene about where perspective showed it (SPEC 5): the selected
        object's depth, kept within PARALLEL_DEPTH_RANGE of the others' in front of the camera, or
        theirs when it is not in front itself; never less than the near plane."""
        selected = self.object
        near = self.near_plane()
        viewer = self.viewer
        placed = [obj for obj in self.objects if obj is not viewer]
        depths = (_placed_centres(placed) - viewer.origin) @ viewer.forward  # each one's depth_of, at once
        mine = np.array([obj is selected for obj in placed], dtype=bool)
        others = depths[~mine & (depths > near)]
        scene_depth = float(np.median(others)) if others.size else None
        own = float(depths[mine][0]) if mine.any() else None
        if own is not None and own > near:
            depth = own if scene_depth is None else float(np.clip(own, scene_depth / PARALLEL_DEPTH_RANGE,
                                                                  scene_depth * PARALLEL_DEPTH_RANGE))
        else:
            depth = scene_depth if scene_depth is not None else near
        return perspective_half_height(max(depth, near))

    def sight(self, element: SceneObject, aspect: float, pixels_high: int | None = None) -> Sight:
        return self.sights([element], aspect, pixels_high)[0]

    def sights(self, elements: list[SceneObject], aspect: float, pixels_high: int | None = None) -> list[Sight]:
        """How each element's box stands in a view `aspect` wide and `pixels_high` high (a load may land
        outside it, or so far off or so small that it is not seen, or so thin that it lights no pixel),
        from its eight corners alone: no pass over the scene."""
        return self.outlook(aspect).sights(world_boxes(elements), pixels_high)

    def enclosers(self, elements: list[SceneObject]) -> list[SceneObject | None]:
        """For each element, the first other shown element whose world box holds its whole (a model in
        metres loaded at the origin, inside Rammer_255), which may hide it; None where there is none."""
        shown = self.shown_elements()
        if not shown:
            return [None] * len(elements)
        shown_low, shown_high = placed_bounds(*_placements(shown))
        low, high = placed_bounds(*_placements(elements))
        position = {id(element): index for index, element in enumerate(shown)}
        itself = np.fromiter((position.get(id(element), -1) for element in elements), np.int64, len(elements))
        return [None if index < 0 else shown[index]
                for index in first_holders(shown_low, shown_high, low, high, itself).tolist()]

    def around_eye(self, elements: list[SceneObject]) -> list[bool]:
        """Whether each element's box holds the eye (a room or a ground sheet loaded round the camera,
        which then shows its inside), tested in its own frame; never the viewer, which we look from inside."""
        models, bounds = _placements(elements)
        eye = self._eye_in_frames(models)
        holds = ((bounds[:, 0] <= eye) & (eye <= bounds[:, 1])).all(axis=1)
        viewer = self.viewer
        return [bool(held) and element is not viewer for element, held in zip(elements, holds.tolist())]

    def black_for_want_of_light(self, obj: SceneObject) -> bool:
        """Whether the object is drawn black as the lights stand: every one off, and no ambient colour in
        any material it is drawn with (Ka 0 0 0, as SketchUp and Maya write one)."""
        return not any(light.on for light in self.lights) and not any(any(m.ka) for m in _materials_of(obj))

    def depth_of(self, point: np.ndarray) -> float:
        """How far in front of the eye a world point is, along the view axis (negative: behind)."""
        return float(np.dot(point - self.eye_position(), self.viewer.forward))

    # --- the probe's face ------------------------------------------------------------------------
    def probed_corners(self) -> list[int]:
        """Corners of the selected face that the lighting probe lights, and the picture marks: all of
        them in Gouraud, the first in Flat."""
        obj = self.object
        if obj is None or obj.mesh.face_count == 0:
            return []
        face = obj.selected_face % obj.mesh.face_count
        start, stop = int(obj.mesh.face_start[face]), int(obj.mesh.face_start[face + 1])
        return list(range(start, stop if self.modes.shading is Shading.GOURAUD else start + 1))

    def probed_points(self, most: int | None = None) -> np.ndarray:
        """(N, 3) world positions of the first `most` probed corners (all where not given), in
        probed_corners' order."""
        corners = self.probed_corners()[:most]
        if not corners:
            return np.zeros((0, 3))
        obj = self.object
        return transform_points(obj.model, obj.mesh.positions[obj.mesh.corner_vertex[corners]])

    # --- lights in the world -------------------------------------------------------------------
    def light_owner(self, light: Light) -> SceneObject | None:
        if light.owner is Owner.SELECTED_OBJECT:
            return self.object
        if light.owner is Owner.SELECTED_CAMERA:
            return self.camera
        return None

    def placed_light(self, light: Light) -> WorldLight:
        owner = self.light_owner(light)
        return light.placed(None if owner is None else owner.model)

    def world_lights(self, only_on: bool = True) -> list[WorldLight]:
        """The scene's lights in the world, as the renderer and the probe use them."""
        return [self.placed_light(light) for light in self.lights if light.on or not only_on]

    def term_view_name(self) -> str:
        """What the lit colour shows (v), with the light's own name for the "one light alone" views."""
        view = self.modes.term_view
        index = view.light_index
        if index is None:
            return view.name
        if index >= len(self.lights):
            return f"light {index} alone (no such light)"
        light = self.lights[index]
        return f"{light.name} alone" + ("" if light.on else f" (off: {light.key} turns it on)")

    def lights_in_view(self) -> list[WorldLight]:
        """The lights that are on and that the term view shows: one of them for "light k alone"."""
        index = self.modes.term_view.light_index
        if index is None:
            return self.world_lights()
        if index >= len(self.lights) or not self.lights[index].on:
            return []
        return [self.placed_light(self.lights[index])]


@dataclass(frozen=True)
class InView:
    """Scene._shown_boxes: for each box, (N,) arrays."""

    distances: np.ndarray  # how deep, at least, its nearest point in view lies
    backs: np.ndarray  # the depth of its farthest corner
    least_sides: np.ndarray  # its least side that is not flat (0 for a point, and the light's marker)


@dataclass(frozen=True)
class Lens:
    """The numbers P is built from (Scene.lens): perspective is PERSPECTIVE_FOVY_DEG high, parallel
    `half_height` either side of the view's middle."""

    aspect: float  # the view's width over its height
    near: float  # the near plane's distance from the eye
    far: float
    half_height: float | None  # None in perspective

    @property
    def projection(self) -> Projection:
        return Projection.PERSPECTIVE if self.half_height is None else Projection.PARALLEL

    def matrix(self) -> np.ndarray:
        if self.half_height is None:
            return perspective(PERSPECTIVE_FOVY_DEG, self.aspect, self.near, self.far)
        # SPEC 5: n, as in perspective
        return orthographic(self.half_height * self.aspect, self.half_height, self.near, self.far)


@dataclass(eq=False)
class Outlook:
    """A view as the box tests see it: where the eye stands and how far the view reaches. A key's
    notice keeps the one before the key (Scene.outlook), with no test made until it is needed."""

    eye: np.ndarray  # the viewer's model matrix (pushed anew on each move, never changed in place)
    parallel_half_height: float | None  # None in perspective, 90 degrees high
    aspect: float

    @functools.cached_property
    def view(self) -> np.ndarray:
        return np.linalg.inv(self.eye)

    def sights(self, corners: np.ndarray, pixels_high: int | None = None) -> list[Sight]:
        """How each box of these (N, 8, 3) world corners stands in the view, `pixels_high` high (None:
        no picture, so none is too thin)."""
        in_eye = corners @ self.view[:3, :3].T + self.view[:3, 3]
        beyond, small = self.beyond(in_eye), self._spans(in_eye) < SEEN_SHARE_LEAST
        thin = np.zeros(len(in_eye), dtype=bool)
        if pixels_high is not None:  # under a pixel every way is a speck, too small; one way, thin
            least, most = self._outline_widths(in_eye) * (pixels_high / 2.0)  # the view is 2 high
            small, thin = small | (most < THINNEST_PIXELS), least < THINNEST_PIXELS
        return [Sight.OUTSIDE if out else Sight.TOO_SMALL if too_small else Sight.THIN if too_thin else Sight.SEEN
                for out, too_small, too_thin in zip(beyond.tolist(), small.tolist(), thin.tolist())]

    def beyond(self, in_eye: np.ndarray) -> np.ndarray:
        """(N,): whether each box of these (N, 8, 3) corners in the eye's frame lies wholly behind the
        eye or beyond one side of the view. The near and far planes keep clear of what is shown, so
        they leave nothing more out."""
        across, depth = in_eye[..., :2], -in_eye[..., 2]
        reach = self._reaches(depth)
        sides = np.concatenate([across > reach, across < -reach], axis=2)  # (N, 8, 4): beyond each side
        return (depth <= 0.0).all(axis=1) | sides.all(axis=1).any(axis=1)

    def _spans(self, in_eye: np.ndarray) -> np.ndarray:
        """(N,): how many views each box of these (N, 8, 3) eye-frame corners spans, across or up,
        whichever is more; in perspective, infinity where it reaches behind the eye."""
        depth = -in_eye[..., 2]
        reach = self._reaches(np.where(depth > 0.0, depth, 1.0))  # behind the eye: infinity below
        spans = np.ptp(in_eye[..., :2] / reach, axis=1).max(axis=1, initial=0.0) / 2.0  # the view is 2 across
        if self.parallel_half_height is not None:
            return spans
        return np.where((depth > 0.0).all(axis=1), spans, np.inf)

    def _outline_widths(self, in_eye: np.ndarray) -> np.ndarray:
        """(2, N): how wide each box of these (N, 8, 3) eye-frame corners looks across its narrowest and
        its widest, in half the view's height; infinity where it reaches behind the eye in perspective.
        An outline's least width lies across one of its sides, and its sides join pairs of corners."""
        depth = -in_eye[..., 2]
        scale = self._reaches(np.where(depth > 0.0, depth, 1.0))[..., 1:]  # up: the view is 2 high
        flat = in_eye[..., :2] / scale
        first, second = _CORNER_PAIRS
        along = flat[:, second] - flat[:, first]  # (N, 28, 2)
        length = np.linalg.norm(along, axis=2)
        across = np.stack([-along[..., 1], along[..., 0]], axis=2) / np.where(length > 0.0, length, 1.0)[..., None]
        widths = np.ptp(np.einsum("npk,nck->npc", across, flat), axis=2)
        both = np.stack([np.where(length > 0.0, widths, np.inf).min(axis=1, initial=np.inf),
                         length.max(axis=1, initial=0.0)])
        if self.parallel_half_height is not None:
            return both
        return np.where((depth > 0.0).all(axis=1), both, np.inf)

    def _reaches(self, depth: np.ndarray) -> np.ndarray:
        """(..., 2): how far the view reaches across and up, in the eye's frame, at these depths."""
        widths = np.array([self.aspect, 1.0])
        if self.parallel_half_height is not None:  # the view a box
            return np.broadcast_to(self.parallel_half_height * widths, (*depth.shape, 2))
        return depth[..., None] * widths  # tan 45 = 1


class Sight(Enum):
    """How a box stands in the view (Scene.sight), in the words a load's message says it with."""

    SEEN = "seen"
    OUTSIDE = "outside the view"  # wholly behind the eye or beyond one side of it
    TOO_SMALL = "too small to see from here"  # wholly in front of the eye, under SEEN_SHARE_LEAST of it
    THIN = "thinner than a pixel from here"  # its outline under THINNEST_PIXELS across: maybe no pixel lit


_BOX_CORNER_PICKS = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)])  # low 0, high 1
_CORNER_PAIRS = np.array(list(itertools.combinations(range(8), 2))).T  # (2, 28): every two of a box's corners


def perspective_half_height(depth: float) -> float:
    """Half the height perspective's view spans at this depth in front of the eye."""
    return depth * float(np.tan(np.radians(PERSPECTIVE_FOVY_DEG) / 2.0))


def world_axes_lengths(high: np.ndarray, extent: float) -> np.ndarray:
    """How far the world's x, y and z axes reach from the origin, for objects whose box ends at `high`:
    half an extent past that end (past the origin where the box ends short of it), and no further than
    one and a half extents, since a box reaching further is not around the origin."""
    return np.maximum(extent / 2.0, np.clip(high, 0.0, extent) + WORLD_AXES_PAST_BOX * extent)


def size_unit(size: float) -> float:
    """1 for a model about the seed's models' size, else the power of ten that brings it there, so that
    its scale's numbers stay round."""
    if not size > 0.0 or not math.isfinite(size):
        return 1.0
    return 10.0 ** float(np.clip(round(math.log10(size / SEED_MODEL_SIZE)), -300, 300))


def _placements(elements: list[SceneObject]) -> tuple[np.ndarray, np.ndarray]:
    """(N, 4, 4) model matrices and (N, 2, 3) mesh boxes (low, high) of the elements."""
    if not elements:
        return np.zeros((0, 4, 4)), np.zeros((0, 2, 3))
    return (np.array([element.model for element in elements]),
            np.array([element.mesh.bounds for element in elements], dtype=np.float64))


def _box_corners(bounds: np.ndarray) -> np.ndarray:
    """(N, 8, 3): the corners of (N, 2, 3) boxes."""
    return bounds[:, _BOX_CORNER_PICKS, np.arange(3)]


def world_boxes(elements: list[SceneObject]) -> np.ndarray:
    """(N, 8, 3): each element's mesh's bounding box's corners, placed in the world, in one pass."""
    return placed_boxes(*_placements(elements))


def placed_boxes(models: np.ndarray, bounds: np.ndarray) -> np.ndarray:
    """(N, 8, 3): the corners of (N, 2, 3) boxes placed by (N, 4, 4) model matrices, each summed x + y,
    then + z, then + the move, whatever N (np.einsum's order changed with N: a box alone differed from
    the same box among others in its last bit)."""
    x, y, z = np.moveaxis(np.stack(_turned_sides(models, bounds), axis=1), 3, 0)  # each (N, 2, 3): low, high
    corners = (x[:, :, None, None] + y[:, None, :, None]) + z[:, None, None, :]
    return corners.reshape(-1, 8, 3) + models[:, None, :3, 3]  # _BOX_CORNER_PICKS' order


def placed_bounds(models: np.ndarray, bounds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(N, 3) lows and highs of placed_boxes' corners, the same numbers without the corners: rounding a
    sum never reverses an order, so the least corner is the sum of the least sides, as placed_boxes sums
    (where a turned side is not finite, both are not, maybe not alike: inf - inf is nan in a corner)."""
    lows, highs = _turned_sides(models, bounds)
    least, most = np.minimum(lows, highs), np.maximum(lows, highs)
    low, high = (((sides[..., 0] + sides[..., 1]) + sides[..., 2]) + models[:, :3, 3] for sides in (least, most))
    return low, high


def _browsing_put_back(now: dict[str, object], kept: dict[str, object]) -> dict[str, object]:
    """An element's fields as Scene.restorer keeps them, but where it shows the file it showed: there where
    PageDown has got to stays, so the next press steps past a file that did not load. Where a file read in
    its place goes back, that goes back with it: the next step starts beside the file shown."""
    if "browsed" not in kept or now.get("source") != kept.get("source"):
        return kept
    return {name: value for name, value in kept.items() if name != "browsed"}


def placement_refusal(model: np.ndarray, mesh: Mesh, reach: Reach) -> str | None:
    """Why a mesh placed by `model` (an affine matrix with an inverse), of the kind that may reach `reach`
    (MODELS_REACH, CAMERAS_REACH), cannot be drawn; None if it can."""
    farthest, size = placed_reach_and_size(model[None], np.array(mesh.bounds)[None])
    return lighting_refusal(float(farthest[0]), float(size[0]), reach, "move it nearer the origin, or scale it down")


def placed_reach_and_size(models: np.ndarray, bounds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(N,) each, of (N, 2, 3) boxes placed by (N, 4, 4) model matrices: how far from the origin each
    reaches along an axis, its origin with it (where it is looked through from and its spotlight
    stands), and its longest side as placed, turned or not (a turn brings no two points nearer)."""
    with np.errstate(over="ignore", invalid="ignore"):  # a matrix of 1e300s set by hand: not finite, refused
        low, high = placed_bounds(models, bounds)
        farthest = np.maximum(np.maximum(-low, high).max(axis=1), np.abs(models[:, :3, 3]).max(axis=1))
        stretch = np.linalg.norm(models[:, :3, :3], axis=1)
        stretch[np.abs(stretch - 1.0) < 1e-9] = 1.0  # a turn's columns are 1 long but for rounding
        sides = stretch * (bounds[:, 1] - bounds[:, 0])
    return farthest, sides.max(axis=1)


def _turned_sides(models: np.ndarray, bounds: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(N, 3, 3) each: R_ij times the box's low, and its high, along j, for (N, 4, 4) model matrices R."""
    turn = models[:, :3, :3]
    return turn * bounds[:, :1], turn * bounds[:, 1:]


def _materials_of(element: SceneObject) -> tuple[Material, ...]:
    """The materials an element is drawn with: its own, and its parts'."""
    return (element.material, *element.part_materials)


def _least_sides(bounds: np.ndarray) -> np.ndarray:
    """(N,): each of (N, 2, 3) boxes' least side that is not flat; 0 where all are (a point)."""
    sides = bounds[:, 1] - bounds[:, 0]
    least = np.where(sides > 0.0, sides, np.inf).min(axis=1, initial=np.inf)
    return np.where(np.isfinite(least), least, 0.0)


def world_box(objects: Iterable[SceneObject]) -> tuple[np.ndarray, np.ndarray]:
    """The world bounding box of the objects' mesh boxes (the origin alone when there are none)."""
    points = world_boxes(list(objects)).reshape(-1, 3)
    if not points.size:
        return np.zeros(3), np.zeros(3)
    return points.min(axis=0), points.max(axis=0)


def _placed_centres(elements: list[SceneObject]) -> np.ndarray:
    """(N, 3): each element's box centre in the world (SceneObject.centre, in one pass)."""
    models, bounds = _placements(elements)
    return np.einsum("nij,nj->ni", models[:, :3, :3], bounds.mean(axis=1)) + models[:, :3, 3]
