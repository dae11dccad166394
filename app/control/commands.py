"""What every key of SPEC 6 does to the scene, as plain functions `(scene, host) -> None`.

Only scene state changes here. Whatever needs the world outside the scene (quit, a file prompt,
loading a file, a screenshot) goes through the `Host`: the viewer. A refused action never raises:
it leaves the scene as it was and says why in `scene.message`.

Every move pushes a new matrix (or, for lights, a snapshot of the old state) and never edits one in
place, so `u` gives back the earlier state bit for bit.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Callable
from enum import Enum
from pathlib import Path
from typing import Protocol, TypeVar

import numpy as np

from marraztu.control.browse import sibling_model
from marraztu.errors import escaped
from marraztu.loaders.registry import load_model, sized
from marraztu.loaders.scenefile import BUILT_IN_CAMERA_MODEL, give_part_materials
from marraztu.model import framing, picking, transforms, viewports
from marraztu.model.build import scaled_mesh
from marraztu.model.geometry import CAMERA_REACH, DRAWABLE_SIZE
from marraztu.model.lights import SPOT_APERTURE_RANGE_DEG, TERM_VIEWS, Light, Owner, default_lights
from marraztu.model.mesh import Mesh, counted
from marraztu.model.scene import (
    INSIDE_FRACTION,
    SWITCHED_SHADINGS,
    CameraMode,
    Fill,
    Frame,
    Modes,
    Projection,
    Scene,
    SceneObject,
    Sight,
    Target,
    array_refusal,
    model_refusal,
    perspective_half_height,
    place_kind,
    size_unit,
    world_box,
)
from marraztu.model.transforms import TransformKind, Vec3, step_matrix

ROTATION_STEP_RAD = 0.1  # the seed author's step
TRANSLATION_STEP = 5.0  # world units, for models of the seed's size (see translation_unit)
APERTURE_STEP_DEG = 2.5
# Analysis mode stops the camera this far outside the orbited object's box (no entering it), for an
# object of the seed's models' size.
ANALYSIS_GAP = 10.0
# Mouse drag, as VTK's trackball (vtkInteractorStyleTrackballCamera::Rotate, 20 degrees times its
# MotionFactor 10): a drag across the whole window, either way, turns this far.
DRAG_RADIANS_PER_WINDOW = math.radians(200.0)
DOLLY_PER_NOTCH = 0.9  # each wheel notch toward the object leaves this share of the distance
# Of the object's size: nearer, a notch out no longer moved a far model's camera; ten near planes
# inside its box (INSIDE_FRACTION), so that what the camera looks at is not cut away there.
DOLLY_CLOSEST = 10.0 * INSIDE_FRACTION
# Of the object's size: farther, it spans a ten-thousandth of the view, a speck, and notches on would
# take the camera past what a 32-bit matrix holds.
DOLLY_FARTHEST = 1e4

TARGET_CYCLE = (Target.OBJECTS, Target.CAMERAS, Target.LIGHTS)


class Host(Protocol):
    """The world outside the scene, as the window or the screenshot command provides it."""

    def quit(self) -> None: ...

    def open_file_prompt(self) -> None: ...

    def narrowest_aspect(self) -> float:
        """Width over height of the narrowest view drawn now (a third of the window, side by side)."""
        ...

    def frame_size(self) -> tuple[int, int] | None:
        """The framebuffer's width and height in pixels, where a picture is drawn (None: none is)."""
        ...

    def load_model(self, path: str) -> bool | None:
        """Loads a model file; on success calls `add_loaded`, on failure sets scene.message."""
        ...

    def replace_model(self, element: SceneObject, path: Path) -> bool | None:
        """Reads `path` into `element`'s place (`replace_loaded`); on failure the scene is kept."""
        ...

    def save_screenshot(self) -> None: ...

    def toggle_recording(self) -> None:
        """F9: starts recording the pictures, or stops and saves them (the window only)."""
        ...


CommandFunction = Callable[[Scene, Host], None]


_Item = TypeVar("_Item")


def _next_in(cycle: tuple[_Item, ...], current: _Item) -> _Item:
    """The item after `current` in `cycle`, wrapping (ValueError where it is none of them)."""
    return cycle[(cycle.index(current) + 1) % len(cycle)]


# --- display switches ------------------------------------------------------------------------------
def toggle_fill(scene: Scene, host: Host) -> None:
    scene.modes.fill = Fill.LINES if scene.modes.fill is Fill.FILLED else Fill.FILLED


def toggle(switch: str) -> CommandFunction:
    """The command of a key that flips one on/off switch of the modes (`n`, `b`, `T`, `h`...)."""
    if not isinstance(getattr(Modes(), switch, None), bool):
        raise ValueError(f"{switch!r} is not an on/off mode")

    def flip(scene: Scene, host: Host) -> None:
        setattr(scene.modes, switch, not getattr(scene.modes, switch))

    return flip


def toggle_projection(scene: Scene, host: Host) -> None:
    if scene.modes.projection is Projection.PERSPECTIVE:
        # Sized at the switch, from the current view, so the scene stays about where it was (SPEC 5).
        scene.modes.parallel_half_height = scene.matching_parallel_half_height()
        scene.modes.projection = Projection.PARALLEL
    else:
        scene.modes.projection = Projection.PERSPECTIVE


def toggle_shading(scene: Scene, host: Host) -> None:
    shading = scene.modes.shading  # Phong, set by hand, is none of the two: F goes to the first
    scene.modes.shading = _next_in(SWITCHED_SHADINGS, shading) if shading in SWITCHED_SHADINGS else SWITCHED_SHADINGS[0]


# --- seeing the equation ---------------------------------------------------------------------------
def cycle_term_view(scene: Scene, host: Host) -> None:
    """`v`: the next term view (everything, ambient, diffuse, specular, each light alone, depth,
    normals), wrapping."""
    scene.modes.term_view = _next_in(TERM_VIEWS, scene.modes.term_view)


def toggle_probe(scene: Scene, host: Host) -> None:
    """`i`: the lighting probe of the selected face (Enter steps to the next face)."""
    if not scene.modes.probe and scene.object is None:
        scene.message = "no object to probe"
        return
    scene.modes.probe = not scene.modes.probe


def toggle_view_from_object(scene: Scene, host: Host) -> None:
    if not scene.modes.view_from_object and scene.object is None:
        scene.message = "no object to look through"
        return
    scene.modes.view_from_object = not scene.modes.view_from_object


def light_by_key(scene: Scene, key: str) -> Light | None:
    return next((light for light in scene.lights if light.key == key), None)


def light_switch(key: str) -> CommandFunction:
    """The command of key `0`..`3`: that light on/off."""

    def switch(scene: Scene, host: Host) -> None:
        light = light_by_key(scene, key)
        if light is None:
            scene.message = f"no light on key {key}"
            return
        light.on = not light.on
        if light.on:
            say_aim(scene, light, f"{light.name} on")

    return switch


def say_aim(scene: Scene, light: Light, said: str) -> None:
    """Where a light that sends its light one way points now, after `said`, as the message."""
    aim = light.kind.aim(scene.placed_light(light))
    if aim:
        owner = scene.light_owner(light)
        whose = "" if owner is None else f" ({owner.name}'s)"
        scene.message = f"{said}{whose}: {aim}"


# --- modes of moving ---------------------------------------------------------------------------------
def use_rotation(scene: Scene, host: Host) -> None:
    scene.modes.transform = TransformKind.ROTATE


def use_translation(scene: Scene, host: Host) -> None:
    scene.modes.transform = TransformKind.TRANSLATE


def toggle_frame_or_camera_mode(scene: Scene, host: Host) -> None:
    """`g`: local/global for objects, flight/analysis for cameras."""
    target = scene.modes.target
    if target is Target.OBJECTS:
        scene.modes.frame = Frame.GLOBAL if scene.modes.frame is Frame.LOCAL else Frame.LOCAL
    elif target is Target.CAMERAS:
        if scene.modes.camera_mode is CameraMode.ANALYSIS:
            scene.modes.camera_mode = CameraMode.FLIGHT
        elif aim_camera_at_object(scene):
            scene.modes.camera_mode = CameraMode.ANALYSIS
        else:  # the turn to the object refused: analysis mode would orbit what the camera does not look at
            scene.message += " (flight mode stays)"
    else:
        scene.message = "g switches local/global for objects and flight/analysis for cameras"


def aim_camera_at_object(scene: Scene) -> bool:
    """Entering analysis mode: the camera keeps its place and turns to the selected object's centre.
    Pushed like any move, so `u` turns it back. False, saying why, where the turn would take the camera
    past its reach (moved_to); with no object, or from its centre, there is nothing to turn to."""
    obj = scene.object
    if obj is None:
        scene.message = "analysis mode: no object to look at"
        return True
    camera = scene.camera
    # Keep the camera's own up as far as possible, so entering analysis does not roll the view.
    aimed = transforms.look_at_model(camera.origin, obj.centre, camera.model[:3, 1])
    if aimed is None:
        scene.message = f"analysis mode: the camera sits at the centre of {obj.name}"
        return True
    return moved_to(scene, camera, aimed)


# --- moving ----------------------------------------------------------------------------------------
def translation_unit(scene: Scene) -> float:
    """SPEC 6's "a few units" on the scale of what moves (size_unit): the selected object's, where it
    moves or analysis mode approaches it; the scene's, where a flying camera or a light moves."""
    obj = scene.object
    target = scene.modes.target
    if obj is not None and (target is Target.OBJECTS or (target is Target.CAMERAS and
                                                         scene.modes.camera_mode is CameraMode.ANALYSIS)):
        return size_unit(obj.mesh.size)
    return scene.unit()


def translation_step(scene: Scene) -> float:
    """How far one press of t's x/y/z moves what is targeted now."""
    return TRANSLATION_STEP * translation_unit(scene)


def key_amount(scene: Scene, kind: TransformKind, sign: int) -> float:
    """How far one press of x/y/z (sign +1) or X/Y/Z (sign -1) goes."""
    return sign * (ROTATION_STEP_RAD if kind is TransformKind.ROTATE else translation_step(scene))


def move_object(scene: Scene, kind: TransformKind, axis_index: int, amount: float) -> np.ndarray | None:
    """Where one press moves the selected object to (None: nowhere, said)."""
    obj = scene.object
    if obj is None:
        scene.message = "no object to move"
        return None
    step = step_matrix(kind, axis_index, amount)
    if scene.modes.frame is Frame.LOCAL:
        return transforms.apply_local(obj.model, step)
    return transforms.apply_global(obj.model, step)


def move_camera(scene: Scene, kind: TransformKind, axis_index: int, amount: float) -> np.ndarray | None:
    """Where one press moves the selected camera to (None: nowhere, said)."""
    camera = scene.camera
    if scene.modes.camera_mode is CameraMode.FLIGHT:
        return transforms.apply_local(camera.model, step_matrix(kind, axis_index, amount))
    obj = scene.object
    if obj is not None and not _looks_at(camera.model, obj.centre):  # selected, or moved, since the camera turned
        said = scene.message
        if aim_camera_at_object(scene):  # it orbits and approaches what it looks at
            scene.message = f"analysis mode: turned to look at {obj.name}, the selected object (press again to move)"
            return None
        scene.message = said  # that turn would leave the camera's reach: it moves as before, not said refused
    if kind is TransformKind.ROTATE:
        return orbit_camera(scene, axis_index, amount)
    return approach_object(scene, axis_index, amount)


_AIMED = 1e-6  # how far off the view axis, over its distance, an object's centre may be and be looked at


def _looks_at(camera_model: np.ndarray, point: np.ndarray) -> bool:
    """Whether `point` lies on the camera's view axis, in front of it (or at the camera: nothing to turn to)."""
    x, y, z = transforms.point_in_frame(camera_model, point)
    return bool(math.hypot(x, y) <= _AIMED * max(abs(z), 1e-300) and z <= 0.0)


def orbit_camera(scene: Scene, axis_index: int, angle: float) -> np.ndarray | None:
    """Analysis mode: turn about the camera's own axis, through the selected object's centre."""
    obj = scene.object
    if obj is None:
        scene.message = "analysis mode: no object to orbit"
        return None
    return transforms.orbit(scene.camera.model, obj.centre, axis_index, angle)


def approach_object(scene: Scene, axis_index: int, distance: float) -> np.ndarray | None:
    """Analysis mode: t moves along the view axis only (z: back away, Z: come closer); moving sideways
    would lose the object from the view axis, so x and y are refused."""
    if axis_index != 2:
        scene.message = "analysis mode: t moves along z only (z backs away, Z comes closer)"
        return None
    obj = scene.object
    if obj is None:
        scene.message = "analysis mode: no object to approach"
        return None
    camera = scene.camera
    depth = -transforms.point_in_frame(camera.model, obj.centre)[2]
    gap = ANALYSIS_GAP * size_unit(obj.mesh.size)
    closest = obj.reach_along(-camera.forward) + gap  # outside the object's box, not on or in it
    if distance < 0.0 and depth + distance < closest:  # backing away is never refused
        distance = min(0.0, closest - depth)  # stop at the minimum, never push back
        if distance == 0.0:
            scene.message = f"analysis mode: as close to {obj.name} as allowed, {gap:g} units outside its box"
            return None
    return transforms.apply_local(camera.model, transforms.translation(2, distance))


def move_light(scene: Scene, kind: TransformKind, axis_index: int, amount: float) -> bool:
    """As the selected light's kind allows (marraztu.model.lights); anything else is refused with a
    message. Whether it moved."""
    refusal = scene.light.move(kind, axis_index, amount)
    if refusal:
        scene.message = refusal
        return False
    say_aim(scene, scene.light, scene.light.name)
    return True


def moved_to(scene: Scene, element: SceneObject, model: np.ndarray) -> bool:
    """`element` moved to `model`, a step `u` takes back; False, saying why, where that would take it
    past its reach (Scene.move_refusal), which the next call of the programming interface refuses."""
    if _refused_move(scene, element, model):
        return False
    element.push(model)
    return True


def _refused_move(scene: Scene, element: SceneObject, model: np.ndarray) -> bool:
    """Whether moving `element` to `model` would take it past its reach (Scene.move_refusal), the message
    then saying why: a key's move and the view's stop alike."""
    refusal = scene.move_refusal(element, model)
    if refusal:
        scene.message = refusal
    return bool(refusal)


def _moved_target(scene: Scene) -> Light | SceneObject | None:
    """What x/y/z, a ctrl-drag and `u` act on now: the selected light, object or camera (None: objects
    targeted, and none loaded)."""
    return scene.light if scene.modes.target is Target.LIGHTS else scene.targeted_element


_ELEMENT_MOVERS = {Target.OBJECTS: move_object, Target.CAMERAS: move_camera}


def move_target(scene: Scene, kind: TransformKind, axis_index: int, amount: float) -> None:
    """One move of the current target: `amount` is radians for rotations, world units otherwise. Every
    key's move of an object or a camera is made here, where one past its reach stops."""
    target = _moved_target(scene)
    if isinstance(target, Light):
        moved = move_light(scene, kind, axis_index, amount)
    else:
        model = _ELEMENT_MOVERS[scene.modes.target](scene, kind, axis_index, amount)
        moved = target is not None and model is not None and moved_to(scene, target, model)
    if moved:  # a refused move leaves `u` to the view
        scene.view_moves.clear()  # from now on `u` undoes this move, the target's own


# --- the view: framing, reset, and the mouse's orbit, pan and dolly ----------------------------------
def move_view(scene: Scene, matrix: np.ndarray, gesture: str | None = None,
              half_height: float | None = None) -> bool:
    """The selected camera moved to `matrix`, and the parallel view's half height set where given,
    undoable with `u` whatever is targeted. The events of one mouse gesture (`gesture` names it) amend
    one history entry instead of pushing one each. False, with a message, while looking through the
    object (the camera is not what we see through, and moving it would show nothing), and where it
    would take the camera past its reach (Scene.move_refusal), as a key's move would."""
    if scene.modes.view_from_object:
        scene.message = "looking through the object: C looks through the camera again, which the view moves"
        return False
    camera = scene.camera
    if _refused_move(scene, camera, matrix):
        return False
    if _continues_gesture(scene, camera, gesture):
        camera.amend_view_move(matrix)
    else:
        parallel = scene.modes.projection is Projection.PARALLEL
        scene.view_moves.append(camera)
        camera.push_view_move(matrix, scene.modes.parallel_half_height if parallel else None)
        scene.view_gesture = gesture
    if half_height is not None:
        scene.modes.parallel_half_height = half_height
    return True


def _continues_gesture(scene: Scene, camera: SceneObject, gesture: str | None) -> bool:
    """Whether an event of `gesture` goes on with the one whose move of this camera is the last view
    move: it amends that move's history entry, and `u` takes the whole gesture back."""
    return (gesture is not None and scene.view_gesture == gesture and bool(scene.view_moves)
            and scene.view_moves[-1] is camera and camera.made_by_view_move())


def end_view_gesture(scene: Scene) -> None:
    """A button pressed or released, or a key: the next mouse move is a new undo step."""
    scene.view_gesture = None


def frame_selected(scene: Scene, host: Host) -> None:
    """`.`: the camera steps back along its view until the selected object fills two thirds of it,
    turned first where that view sees it edge or end on (a plate, a beam: a line or nothing)."""
    obj = scene.object
    if obj is None:
        scene.message = "no object to frame"
        return
    aspect = host.narrowest_aspect()
    short = _frame(scene, [obj], aspect)
    if short is not None:
        sight = scene.sight(obj, aspect, filled_pixels_high(scene, host))
        scene.message = f"framed {obj.name}{short}" + (sight_words(sight) if sight is Sight.THIN else "")


def frame_everything(scene: Scene, host: Host) -> None:
    """`>`: as `.`, for everything the picture shows: models added one by one leave the view on the
    first, and a viewer's usual "frame all" shows them together."""
    shown = scene.shown_elements()
    if not shown:
        scene.message = "nothing to frame"
        return
    short = _frame(scene, shown, host.narrowest_aspect())
    if short is not None:
        camera_ids = {id(camera) for camera in scene.cameras}
        cameras = sum(id(element) in camera_ids for element in shown)  # a body of another camera
        counts = [counted(n, kind) for n, kind in ((len(shown) - cameras, "object"), (cameras, "camera")) if n]
        scene.message = f"framed everything shown ({' and '.join(counts)}){short}"


def _frame(scene: Scene, shown: list[SceneObject], aspect: float) -> str | None:
    """`.` and `>`'s move: the view frames `shown` in a view `aspect` wide, turned first where it sees
    their box edge or end on; what the message adds where CAMERA_REACH stopped the camera short ("" where
    it did not), or None where move_view refuses it, saying why."""
    turned = framing.revealing(scene.camera.model, shown)
    matrix, half_height, short = framing.frame_objects(scene, turned, shown, aspect, scene.camera.mesh)
    if not move_view(scene, matrix, half_height=half_height):
        return None
    if not short or scene.modes.projection is Projection.PARALLEL:  # there the view's height frames them
        return ""
    return f", from as far back as a camera may stand ({CAMERA_REACH:.0e} from the origin)"


def filled_pixels_high(scene: Scene, host: Host) -> int | None:
    """The views' height in pixels where they are drawn filled; None where no picture is drawn, or lines
    are, which light pixels however thin the model."""
    size = host.frame_size()
    return None if size is None or scene.modes.fill is not Fill.FILLED else int(size[1])


def sight_words(sight: Sight) -> str:
    """What a message says of where the view shows an object, and the key that shows it: nothing where it does."""
    return "" if sight is Sight.SEEN else f", {sight.value} ({sight_hint(sight)})"


def sight_hint(sight: Sight) -> str:
    """The key that shows an object the view does not: lines light pixels however thin the model."""
    return "l draws its edges" if sight is Sight.THIN else ". frames it"


def reset_view(scene: Scene, host: Host) -> None:
    """HOME: the selected camera back where the scene started it, and a parallel view sized as `p`
    sizes it there (u takes both back again)."""
    if not move_view(scene, scene.camera.history[0].copy()):
        return
    _size_parallel_view(scene)
    scene.message = "view reset to the start"


def _size_parallel_view(scene: Scene) -> None:
    """In parallel projection, its half height as `p` sizes it for the view now (SPEC 5)."""
    if scene.modes.projection is Projection.PARALLEL:
        scene.modes.parallel_half_height = scene.matching_parallel_half_height()


def _view_centre(scene: Scene) -> np.ndarray:
    """What the mouse turns the view about: the selected object, or the whole scene."""
    return scene.object.centre if scene.object is not None else framing.bounding_sphere(scene.objects)[0]


def _view_size(scene: Scene) -> float:
    """The diagonal of the world box of what the mouse turns the view about; a unit sphere's, as framing
    takes it, where that has none (no object, one point): the wheel's bounds are shares of it."""
    low, high = world_box([scene.object] if scene.object is not None else scene.objects)
    return 2.0 * framing.framed_radius(float(np.linalg.norm(high - low)) / 2.0)


def drag_angles(dx_pixels: float, dy_pixels: float, window_px: tuple[int, int]) -> tuple[float, float]:
    """A drag's turns in radians, sideways and vertical: each a share of DRAG_RADIANS_PER_WINDOW, the
    share of the window's width (height) that the drag crossed."""
    width, height = max(window_px[0], 1), max(window_px[1], 1)
    return dx_pixels * DRAG_RADIANS_PER_WINDOW / width, dy_pixels * DRAG_RADIANS_PER_WINDOW / height


def orbit_view(scene: Scene, dx_pixels: float, dy_pixels: float, window_px: tuple[int, int]) -> None:
    """Left drag: the camera turns round the selected object, as analysis mode's r x/y keys do."""
    sideways, vertical = drag_angles(dx_pixels, dy_pixels, window_px)
    model, centre = scene.camera.model, _view_centre(scene)
    model = transforms.orbit(model, centre, 1, -sideways)
    model = transforms.orbit(model, centre, 0, -vertical)
    move_view(scene, model, "orbit")


def pan_view(scene: Scene, dx_pixels: float, dy_pixels: float, view_height_px: int) -> None:
    """Right or shift drag: the camera slides in its own plane so that the point under the cursor at
    the selected object's depth follows the cursor, or, with it behind the eye, at the depth `p` keeps."""
    depth = scene.depth_of(_view_centre(scene))
    if scene.modes.projection is Projection.PARALLEL:
        half_height = scene.modes.parallel_half_height
    elif depth > scene.near_plane():
        half_height = perspective_half_height(depth)
    else:
        half_height = scene.matching_parallel_half_height()
    units_per_pixel = 2.0 * half_height / max(view_height_px, 1)
    step = transforms.translation_by(np.array([-dx_pixels * units_per_pixel, dy_pixels * units_per_pixel, 0.0]))
    move_view(scene, transforms.apply_local(scene.camera.model, step), "pan")


def dolly_view(scene: Scene, steps: float) -> None:
    """The wheel: toward the selected object (steps > 0) or away, a fraction of the way each notch, so
    the camera never passes through it, and no nearer than DOLLY_CLOSEST of its size. In parallel
    projection, where the distance changes nothing but what the near plane cuts, the view's size
    shrinks instead (as far) and the camera stays."""
    factor = DOLLY_PER_NOTCH ** steps
    size = _view_size(scene)
    bounds = (DOLLY_CLOSEST * size, DOLLY_FARTHEST * size)
    model = scene.camera.model.copy()
    if scene.modes.projection is Projection.PARALLEL:
        half_height = _dollied(scene.modes.parallel_half_height, factor, bounds)
        move_view(scene, model, "dolly", half_height=half_height)
        return
    centre = _view_centre(scene)
    offset = model[:3, 3] - centre
    distance = float(np.linalg.norm(offset))
    backward = offset / distance if distance > 0.0 else model[:3, 2] / np.linalg.norm(model[:3, 2])
    model[:3, 3] = centre + backward * _dollied(distance, factor, bounds)
    move_view(scene, model, "dolly")


def _dollied(length: float, factor: float, bounds: tuple[float, float]) -> float:
    """A distance or a view's size scaled by the wheel, kept within (closest, farthest): never in under
    the one nor out past the other (one already past it stays), so that notches the other way always
    move it."""
    closest, farthest = bounds
    if factor > 1.0:
        return min(max(length * factor, closest), max(length, farthest))
    return max(length * factor, min(length, closest))


def axis_press(axis_index: int, sign: int) -> CommandFunction:
    """The command of one of x y z X Y Z."""

    def press(scene: Scene, host: Host) -> None:
        kind = scene.modes.transform
        move_target(scene, kind, axis_index, key_amount(scene, kind, sign))

    return press


def undo(scene: Scene, host: Host) -> None:
    """`u`: a view move just made first (framing, reset, the mouse), else the target's last move."""
    scene.view_gesture = None
    if _undo_view_move(scene):
        return
    target = _moved_target(scene)
    if isinstance(target, Light):
        undone = target.undo()
    else:
        undone = target is not None and _undo_element(scene, target)
    if not undone:
        scene.message = "nothing to undo"


def _undo_element(scene: Scene, element: SceneObject) -> bool:
    """The element's last move undone, or dropped where `u` cannot take it back (_dropped_unreachable_step);
    where a view move made it, with the parallel view's size before (a move made in perspective: sized as
    `p` sizes it for the view it gives back). False where none is left."""
    if _dropped_unreachable_step(scene, element):
        return True
    made_by_view_move = element.made_by_view_move()
    if not element.undo():
        return False
    if made_by_view_move:
        _, half_height = element.view_sizes.pop()
        if half_height is not None:
            scene.modes.parallel_half_height = half_height
        else:
            _size_parallel_view(scene)
    return True


def _dropped_unreachable_step(scene: Scene, element: SceneObject) -> bool:
    """Where `u` cannot take `element` back to where it stood before (as it is now, a larger file read in
    its place or a camera's body fitted larger since, it would reach past its reach there): that place
    comes off its history, it stays, and the message says why; so the next `u` goes on with the moves
    before, never stuck on this one. False where it can go back (or undo says what is wrong)."""
    earlier = element.history[-2] if len(element.history) > 1 else None
    if earlier is None or model_refusal(earlier) or array_refusal(earlier):
        return False
    why = scene.why_move_stops(element, earlier)
    if why:
        element.drop_step_under_top()  # at the top, as the press's restorer keeps it
        scene.message = f"u cannot take {element.name} back to where it stood before ({why}): that step is dropped"
    return bool(why)


def undoable_view_moves(scene: Scene) -> int:
    """How many view moves `u` takes back before the target's: as _undo_view_move passes over those of a
    camera since deleted, or past what its history holds."""
    pending: dict[int, int] = {}
    for camera in scene.view_moves:
        pending[id(camera)] = pending.get(id(camera), 0) + 1
    return sum(min(pending.get(id(camera), 0), len(camera.history) - 1) for camera in scene.cameras)


def _undo_view_move(scene: Scene) -> bool:
    """The latest view move undone, with the parallel view's size before it; False where none is left
    (a move of a camera since deleted, or of one with nothing left to undo, is passed over). A step
    pushed over it on that camera (`obj.model = M`, `g`'s turn) is taken back first, the view move left
    for the next `u`: its entry goes only with a view move's step (its view_sizes entry)."""
    while scene.view_moves:
        moved = scene.view_moves[-1]
        if moved not in scene.cameras:
            scene.view_moves.pop()
            continue
        view_steps = len(moved.view_sizes)
        undone = _undo_element(scene, moved)
        if not undone or len(moved.view_sizes) < view_steps:
            scene.view_moves.pop()
        if undone:
            return True
    return False


def change_aperture(delta_deg: float) -> CommandFunction:
    """`+` / `-`: widen / narrow the selected spotlight's cone."""

    def change(scene: Scene, host: Host) -> None:
        light = scene.light
        if scene.modes.target is not Target.LIGHTS or not light.kind.has_cone:
            scene.message = "+ and - change a spotlight's aperture: target lights (c), pick a spot (TAB)"
            return
        low, high = SPOT_APERTURE_RANGE_DEG
        wanted = light.aperture_deg + delta_deg
        light.aperture_deg = float(np.clip(wanted, low, high))
        scene.message = f"{light.name}: aperture {light.aperture_deg:g} deg"
        if wanted != light.aperture_deg:
            scene.message += f" (its {'widest' if wanted > high else 'narrowest'}: {low:g} to {high:g} deg)"

    return change


# --- mouse -----------------------------------------------------------------------------------------
def drag(scene: Scene, dx_pixels: float, dy_pixels: float, window_px: tuple[int, int]) -> None:
    """Ctrl-drag turns the current target as y (sideways drag) and x (vertical drag) do, whatever
    r/t says, as far as a plain drag turns the view. Window y grows downward: dragging right or down
    swings an object's near side right or down; a camera in analysis mode orbits as its y and x keys
    orbit it, so the picture turns the other way. The events of one drag make one undo step, as the
    view's gestures do."""
    # A key or a button ends the gesture (end_view_gesture): the selection cannot change within one.
    target = _moved_target(scene)
    if scene.view_gesture != "drag":
        scene.drag_depth = 0 if target is None else len(target.history)
    sideways, vertical = drag_angles(dx_pixels, dy_pixels, window_px)
    if dx_pixels:
        move_target(scene, TransformKind.ROTATE, 1, sideways)
    if dy_pixels:
        move_target(scene, TransformKind.ROTATE, 0, vertical)
    if target is not None:
        target.fold_history(scene.drag_depth)
        scene.view_gesture = "drag"


class DragMove(Enum):
    """What a drag moves: the window's left, right (or shift) and ctrl drags, and --keys' drag words."""

    ORBIT = "orbit"
    PAN = "pan"
    TURN_TARGET = "turn the target"


def _pan_by_drag(scene: Scene, dx_pixels: float, dy_pixels: float, window_px: tuple[int, int]) -> None:
    pan_view(scene, dx_pixels, dy_pixels, window_px[1])


_DRAG_MOVES: dict[DragMove, Callable[[Scene, float, float, tuple[int, int]], None]] = {
    DragMove.ORBIT: orbit_view, DragMove.PAN: _pan_by_drag, DragMove.TURN_TARGET: drag}


def drag_by(scene: Scene, move: DragMove, dx_pixels: float, dy_pixels: float, window_px: tuple[int, int]) -> None:
    """One motion of a drag, `window_px` the picture's width and height its pixels are counted in: the
    window's drags and --keys' come here alike, so both move the same for the same pixels."""
    _DRAG_MOVES[move](scene, dx_pixels, dy_pixels, window_px)


# --- selection -------------------------------------------------------------------------------------
def cycle_target(scene: Scene, host: Host) -> None:
    scene.modes.target = _next_in(TARGET_CYCLE, scene.modes.target)


def select_next(scene: Scene, host: Host) -> None:
    """TAB: the next element of the current target, wrapping; a new object starts at face 0."""
    target = scene.modes.target
    if target is Target.LIGHTS:
        scene.selected_light = (scene.selected_light + 1) % len(scene.lights)
    elif target is Target.CAMERAS:
        scene.selected_camera = (scene.selected_camera + 1) % len(scene.cameras)
        scene.camera.selected_face = 0
    elif scene.objects:
        select_face(scene, (scene.selected_object + 1) % len(scene.objects), 0)
    else:
        scene.message = "no objects to select"


def select_face(scene: Scene, index: int, face: int) -> None:
    """Object `index` of the scene and its polygon `face` selected: what the probe and the pipeline explain."""
    scene.selected_object = index
    scene.objects[index].selected_face = face


def next_face(scene: Scene, host: Host) -> None:
    """ENTER: the next polygon of the selected object, wrapping."""
    obj = scene.object
    if obj is None or obj.mesh.face_count == 0:
        scene.message = "no object to step through"
        return
    select_face(scene, scene.selected_object, (obj.selected_face + 1) % obj.mesh.face_count)


def select_at(scene: Scene, host: Host, pixel: tuple[int, int]) -> None:
    """A click (`click=X,Y` in --keys): the object and the face drawn at that pixel (column, row from the
    top-left) selected, whatever is targeted (the probe explains the selected object's face); the
    background, a camera's body, or any click while looking through the object (C) changes nothing."""
    refusal = click_refusal(host, pixel)
    if refusal is not None:
        scene.message = refusal
        return
    eye = scene.object
    if eye is not None and scene.viewer is eye:  # the selected object is the eye: another selected, the view jumps
        scene.message = f"looking through {eye.name}: a click would look through what it selects (C: the camera again)"
        return
    hit = picking.pick(scene, host.frame_size(), pixel)
    where = f"at {pixel[0]},{pixel[1]}"
    if hit is None:
        scene.message = f"nothing drawn {where} (the background): the selection stays"
    elif hit.element not in scene.objects:  # identity (eq=False): a camera's body
        scene.message = f"camera {hit.element.name} is drawn {where}: a click selects objects, c then TAB cameras"
    else:
        select_face(scene, scene.objects.index(hit.element), hit.face)
        scene.message = _picked_message(scene, hit.element, hit.face)


def click_refusal(host: Host, pixel: tuple[int, int]) -> str | None:
    """Why a click on `pixel` cannot be made (None: it can): no picture, or not one of its pixels."""
    size = host.frame_size()
    if size is None:
        return "no picture to click in"
    outside = viewports.pixel_refusal(pixel, size)
    return None if outside is None else f"click={outside}"


def _picked_message(scene: Scene, obj: SceneObject, face: int) -> str:
    """'Rammer_255 face 812 of 3,604', and how to see why it has its colour, or that the panel shows it."""
    said = f"{obj.name} face {face + 1:,} of {obj.mesh.face_count:,}"
    if scene.modes.pipeline:  # it takes the probe's place
        said += " (the pipeline follows it)"
    elif scene.modes.probe:
        said += " (the probe follows it)"
    else:
        said += " (i: its probe, P: its pipeline)"
    if scene.modes.target is not Target.OBJECTS:
        said += f"; {scene.modes.target.value} stay targeted"
    return said


# --- files, deletion and the world outside ---------------------------------------------------------
LIGHTS_LOAD_REFUSAL = "cannot load a file while lights are targeted"


def request_file(scene: Scene, host: Host) -> None:
    """`f`: the host asks for a file name (in the window) and loads it."""
    if not _refuses_loading(scene):
        host.open_file_prompt()


def load_file(scene: Scene, host: Host, path: str) -> None:
    """An `f=PATH` press: as `f` with the name already given."""
    if not _refuses_loading(scene):
        host.load_model(path)


def _refuses_loading(scene: Scene) -> bool:
    """Whether `f` is refused now, saying why: a file becomes an object or a camera, never a light."""
    if scene.modes.target is Target.LIGHTS:
        scene.message = LIGHTS_LOAD_REFUSAL
        return True
    return False


def loads_as_camera(scene: Scene) -> bool:
    """A file loaded while cameras are targeted becomes a camera (SPEC 6 `f`)."""
    return scene.modes.target is Target.CAMERAS


def add_loaded(scene: Scene, obj: SceneObject, as_camera: bool, aspect: float = 1.0) -> None:
    """The host's half of `f`: the loaded element joins its list, selected, at face 0. A new camera
    stands where it sees the scene, looking the way the current one does; a lone model is framed
    (the host frames the models of the command line together, frame_models)."""
    obj.selected_face = 0
    scene.loads += 1
    end_view_gesture(scene)  # it is selected: a drag going on turns it as a gesture of its own
    if as_camera:
        looking, others = scene.camera.model, scene.objects + scene.cameras
        scene.cameras.append(obj)
        scene.selected_camera = len(scene.cameras) - 1
        if scene.objects:  # the cameras too: it stands clear of their bodies, which it sees
            obj.history = [_new_camera_place(scene, obj, looking, [others, scene.objects], aspect)]
        return
    lone = not scene.objects
    scene.objects.append(obj)
    scene.selected_object = len(scene.objects) - 1
    if lone:
        frame_models(scene, aspect)


def _new_camera_place(scene: Scene, camera: SceneObject, looking: np.ndarray, framings: list[list[SceneObject]],
                      aspect: float) -> np.ndarray:
    """Where a camera joining the scene stands, looking as `looking` does: framing the first of
    `framings` from which its body is within its reach. Framing stops a camera at CAMERA_REACH, so the
    first is passed over only where its body cannot stand there either; the last is taken as it is."""
    for shown in framings:
        matrix = framing.frame_objects(scene, looking, shown, aspect, camera.mesh)[0]
        if scene.placement_refusal(camera, matrix) is None:
            break
    return matrix


def frame_models(scene: Scene, aspect: float = 1.0) -> None:
    """The models fill two thirds of a view `aspect` wide, whatever their units. A camera not yet moved
    takes that as its start (HOME comes back to it); otherwise it is a move `u` takes back."""
    fit_to_models(scene)
    camera = scene.camera
    if len(camera.history) == 1:
        camera.history[0] = framing.revealing(camera.model, scene.objects)  # the start may turn
        camera.history[0], scene.modes.parallel_half_height, _ = framing.frame_objects(
            scene, camera.model, scene.objects, aspect, camera.mesh)
    else:
        matrix, half_height, _ = framing.frame_objects(scene, camera.model, scene.objects, aspect, camera.mesh)
        move_view(scene, matrix, half_height=half_height)


def fit_to_models(scene: Scene) -> None:
    """The built-in camera's body and the lights' places on the models' scale (Scene.unit), as the
    near plane and the steps are: a scene in millimetres is lit and seen as the same in metres (the
    bulb 200 m up, not 200 mm up inside the model, and a camera's body not 18 m long round a mug).
    A light the person has placed (with the keys, or from Python) stays where they put it."""
    unit = scene.unit()
    if unit == scene.fitted_unit:
        return
    for light in scene.lights:
        if stands_where_fitted(light, scene.fitted_unit):
            light.position = fitted_light_place(light, unit)
    scene.fitted_unit = unit
    fit_camera_bodies(scene.cameras, unit)


def fit_camera_bodies(cameras: list[SceneObject], unit: float) -> None:
    """The built-in camera's body of each of `cameras` on a scale of `unit` (Scene.fitted_unit, where
    --watch reads the cameras of a scene file again)."""
    for camera in cameras:
        if camera.source == BUILT_IN_CAMERA_MODEL:
            camera.mesh = _fitted_body(camera, unit)


def fitted_light_place(light: Light, unit: float) -> np.ndarray:
    """Where fitting puts a built-in light on a scale of `unit`: its place at start times the unit,
    brought in toward the origin to where its kind may stand (the bulb's 200 units past 5e18, say)."""
    place = _BUILT_IN_PLACES[light.key] * unit
    farthest, reach = float(np.abs(place).max()), place_kind(light).most
    return place * (reach / farthest) if farthest > reach else place


_BUILT_IN_PLACES = {light.key: light.position for light in default_lights()}


def _fitted_body(camera: SceneObject, unit: float) -> Mesh:
    """The built-in camera's body, as a scene file sized it, on a scale of `unit`: never under
    DRAWABLE_SIZE, nor past CAMERA_REACH where the camera stands (one far off, or sized 1000 times, round
    the largest models), which the next call would refuse: it is drawn and checked as any model is. Read
    again, not scaled from the last fitting's, so that no rounding piles up."""
    body = _built_in_body(camera.scale)
    low, high = body.bounds
    # The least power of ten that keeps it DRAWABLE_SIZE long, a billionth of a decade over: clear of rounding.
    least = 10.0 ** math.ceil(math.log10(DRAWABLE_SIZE / float(np.max(high - low))) + 1e-9)
    factor = max(min(unit, framing.body_scale_within_reach(camera.model, body)), least)
    return scaled_mesh(body, (factor, factor, factor))


@functools.lru_cache(maxsize=4)
def _built_in_body(scale: Vec3) -> Mesh:
    """The built-in camera's body as read at a scene file's `scale`, once."""
    return sized(load_model(BUILT_IN_CAMERA_MODEL), scale, BUILT_IN_CAMERA_MODEL)


def stands_where_fitted(light: Light, fitted_unit: float) -> bool:
    """Whether a light stands where the last fitting, to `fitted_unit`, put it: an owned one rides at
    its owner's origin, and a moved one is the person's (or the scene file's, where it wrote its place)."""
    return (light.owner is Owner.NONE and not light.history and not light.placed_by_file
            and light.key in _BUILT_IN_PLACES
            and np.allclose(light.position, fitted_light_place(light, fitted_unit), rtol=1e-9, atol=0.0))


def replace_loaded(scene: Scene, element: SceneObject, loaded: SceneObject) -> None:
    """The host's half of PageDown / --watch: the element keeps its place, history and uid (so its
    undo and GPU slot stay), and takes the new file's mesh, name and material (the scene file's
    material, where it gave one, stays, as its scale and texture do; its own file read again, --watch's,
    leaves its name, which a scene file or a person may have given)."""
    if loaded.source != element.source:
        element.name = loaded.name
    element.mesh, element.material = loaded.mesh, loaded.material
    scene.loads += 1
    element.part_materials, element.file_materials = loaded.part_materials, loaded.file_materials
    if element.given_material is not None:
        element.material = element.given_material
        give_part_materials(element, from_scene=True)
    # PageDown goes on from the shown file once the last file it asked for is the one shown (an earlier
    # load, or --watch's, finishing after a later PageDown leaves that one where the next step starts).
    if element.browsed == loaded.source:
        element.browsed = None
    element.source, element.selected_face = loaded.source, 0


def step_file(step: int) -> CommandFunction:
    """PageDown / PageUp: the next or previous model file in the targeted element's folder, in its place."""

    def step_through_folder(scene: Scene, host: Host) -> None:
        element = scene.targeted_element
        if element is None:
            scene.message = ("no object or camera to replace (c: target objects or cameras)"
                             if scene.modes.target is Target.LIGHTS else "no object to replace")
            return
        if element.source is None:
            scene.message = f"{element.name} was not read from a file"
            return
        # From the file last asked for, which may not have loaded: a bad file is stepped past, not retried.
        sibling = sibling_model(element.browsed or element.source, step)
        if sibling is None:
            scene.message = f"no other model file beside {escaped(element.source.name)}"
            return
        element.browsed = sibling
        host.replace_model(element, sibling)

    return step_through_folder


def delete_selected(scene: Scene, host: Host) -> None:
    """DELETE: the selected object (or camera) leaves the scene; the last camera always stays."""
    target = scene.modes.target
    if target is Target.LIGHTS:
        scene.message = "lights cannot be deleted (switch them off with their keys)"
    elif target is Target.CAMERAS:
        _delete_camera(scene)
    else:
        _delete_object(scene)


def _delete_camera(scene: Scene) -> None:
    if len(scene.cameras) == 1:
        scene.message = "the last camera cannot be deleted"
        return
    removed = scene.cameras.pop(scene.selected_camera)
    scene.selected_camera = min(scene.selected_camera, len(scene.cameras) - 1)
    scene.message = f"deleted the camera {removed.name}; looking through {scene.camera.name}"


def _delete_object(scene: Scene) -> None:
    if not scene.objects:
        scene.message = "no object to delete"
        return
    removed = scene.objects.pop(scene.selected_object)
    scene.selected_object = max(0, min(scene.selected_object, len(scene.objects) - 1))
    if not scene.objects:
        scene.modes.view_from_object = False
    left = f"{scene.object.name} selected" if scene.object is not None else "no objects left"
    scene.message = f"deleted {removed.name}; {left}"


def quit_viewer(scene: Scene, host: Host) -> None:
    host.quit()


def save_screenshot(scene: Scene, host: Host) -> None:
    host.save_screenshot()


def toggle_recording(scene: Scene, host: Host) -> None:
    host.toggle_recording()
