"""The status line, the help overlay's text (SPEC 8), and the lines the overlay shows: plain strings
from the viewer, no GL."""

from __future__ import annotations

import itertools
from collections.abc import Mapping

from marraztu.control.commands import TRANSLATION_STEP, translation_step
from marraztu.control.keymap import Command
from marraztu.control.viewer import Viewer
from marraztu.errors import escaped
from marraztu.model.lights import Show
from marraztu.model.scene import Projection, Scene, SceneObject, Target
from marraztu.model.transforms import TransformKind

SEPARATOR = " | "
LIGHT_OFF_MARK = "\u00b7"  # a middle dot: "lights 0·2·" reads as sun and object spot on


def lights_summary(scene: Scene) -> str:
    return "lights " + "".join(light.key if light.on else LIGHT_OFF_MARK for light in scene.lights)


def moving_mode(scene: Scene) -> str:
    """What x/y/z do now: the transform kind (with its step where it is not SPEC's, on a scale other
    than the seed's) and, for the target, its frame or camera mode."""
    modes = scene.modes
    kind = modes.transform.value
    step = translation_step(scene)
    if modes.transform is TransformKind.TRANSLATE and step != TRANSLATION_STEP:
        kind += f" {step:g}"
    if modes.target is Target.OBJECTS:
        return f"{kind} {modes.frame.value}"
    if modes.target is Target.CAMERAS:
        return f"{kind} {modes.camera_mode.value}"
    return kind


def selection_summary(scene: Scene) -> list[str]:
    obj = scene.object
    parts = ["no object" if obj is None else
             f"object {obj.name} face {obj.selected_face + 1}/{obj.mesh.face_count}" + _material_of_face(obj)]
    parts.append(f"camera {scene.camera.name}")
    parts.append(f"light {scene.light.name}")
    return parts


def display_summary(scene: Scene) -> list[str]:
    modes = scene.modes
    projection = modes.projection.value
    if modes.projection is Projection.PARALLEL:
        projection += f" {modes.parallel_half_height:.3g}"  # three digits, whatever the units
    shading = "flat/gouraud/phong side by side" if modes.side_by_side else modes.shading.value
    return [
        shading,
        f"{'lit' if modes.term_view.shows is Show.LIT else 'shows'}: {scene.term_view_name()}",
        projection,
        "culling on" if modes.culling else "culling off",
        modes.fill.value,
        "texture on" if modes.texture else "texture off",
        lights_summary(scene),
    ]


def status_line(scene: Scene) -> str:
    """One line: target, moving mode, display switches, lights, selection."""
    parts = [f"target {scene.modes.target.value}", moving_mode(scene)]
    parts += display_summary(scene)
    if scene.modes.view_from_object:
        parts.append("viewing from the object")
    parts += selection_summary(scene)
    return SEPARATOR.join(parts)


def help_lines(scene: Scene, keymap: Mapping[str, Command]) -> list[str]:
    """Every key with what it does and, for switches, where it stands now; keys the table lists
    together (x y z, the lights, h and F1) share a line, so that the help fits a projector's window."""
    width = max(len(token) for token in keymap)
    lines = []
    for together, group in itertools.groupby(keymap.values(), key=lambda command: command.together or command.token):
        commands = list(group)
        tokens = " ".join(command.token for command in commands)
        words = commands[0].description if len(commands) == 1 else together
        states = list(dict.fromkeys(command.state(scene) for command in commands if command.state is not None))
        state = ", ".join(state for state in states if state)
        line = f"{tokens:<{width}}  {words}"
        lines.append(f"{line}  [{state}]" if state else line)
    lines.append(f"{'f=PATH':<{width}}  (in --keys) load PATH")
    lines.append(f"{'click':<{width}}  select the object and face drawn there (click=X,Y in --keys)")
    return lines


def overlay_lines(viewer: Viewer) -> tuple[list[str], list[str]]:
    """(top lines, bottom lines): status and help at the top; the message, the loads under way and
    the `f` prompt at the bottom."""
    scene = viewer.scene
    top = [status_line(scene)]
    if scene.modes.show_help:
        top += help_lines(scene, viewer.keys)
    bottom = scene.message.splitlines()
    bottom += viewer.loading_lines()
    if viewer.prompt is not None:
        bottom.append(prompt_line(viewer.prompt))
    return [escaped(line) for line in top], [escaped(line) for line in bottom]


def prompt_line(typed: str) -> str:
    return f"model file to load (Enter loads, ESC cancels): {typed}_"


def _material_of_face(obj: SceneObject) -> str:
    """' (material NAME)' where the file names the selected face's material."""
    if obj.mesh.face_count == 0:
        return ""
    named = obj.material_name_of_face(obj.selected_face % obj.mesh.face_count)
    return f" (material {named})" if named else ""
