"""--watch's scene file read again, in the place of what its last read placed: what you edited in the
file takes effect, what you did not stays (the moves, undo and PageDown choice of an element whose entry
places it as before; a light's values the save did not change)."""

from __future__ import annotations

from pathlib import Path
from typing import NamedTuple

import numpy as np

from marraztu.control.commands import (
    end_view_gesture,
    fit_camera_bodies,
    fitted_light_place,
    frame_models,
    replace_loaded,
    stands_where_fitted,
)
from marraztu.model.lights import Light
from marraztu.model.scene import Scene, SceneObject


class FilePlacement(NamedTuple):
    """Which entry of a scene file placed an element, and how: what --watch's read again matches and compares."""

    # A camera or an object, its name, and which of that name in the file: an element is matched by name, so
    # that entries added, removed or reordered around it leave its match (unnamed ones go by their model's).
    entry: tuple[bool, str, int]
    model: Path | None
    scale: tuple[float, ...]
    matrix: tuple[float, ...]  # its position and rotation, as the file placed it


def file_placements(read: Scene) -> dict[int, FilePlacement]:
    """By uid, where a scene file just read placed each of its objects and cameras (before any move or framing)."""
    seen: dict[tuple[bool, str], int] = {}
    placements = {}
    for is_camera, element in [(False, obj) for obj in read.objects] + [(True, camera) for camera in read.cameras]:
        which = seen[is_camera, element.name] = seen.get((is_camera, element.name), -1) + 1
        placements[element.uid] = FilePlacement((is_camera, element.name, which), element.source,
                                                tuple(element.scale), tuple(element.history[0].ravel()))
    return placements


def replace_scene_read(scene: Scene, read: Scene, placed: dict[int, FilePlacement], now: dict[int, FilePlacement],
                       aspect: float = 1.0) -> dict[int, SceneObject]:
    """The host's half of --watch's scene file read again: `read`'s objects and cameras (placed as `now`
    says) in the place of the elements its last read placed (`placed`, by uid), and ahead of those that
    joined from elsewhere (the command line, `f`), which stay as they were. An element whose entry places it
    as the last read did keeps where the person moved it, its undo and the model PageDown chose (returned:
    the read element that took each such one's place, by the uid it had); the others stand where the file
    says, their undo afresh. The modes stay (the lights: take_edited_lights); each selection follows its
    entry, else stays at its index. A file that places no camera has its models framed, as at start, where
    that camera is the one viewing and has not been moved."""
    end_view_gesture(scene)
    successors = _successors(scene, placed, read, now)
    selected_object = _index_after_reading(scene.objects, scene.selected_object, read.objects, placed, successors)
    selected_camera = _index_after_reading(scene.cameras, scene.selected_camera, read.cameras, placed, successors)
    before = {element.uid: element for element in scene.objects + scene.cameras if element.uid in placed}
    scene.objects[:] = [*read.objects, *(obj for obj in scene.objects if obj.uid not in placed)]
    scene.cameras[:] = [*read.cameras, *(camera for camera in scene.cameras if camera.uid not in placed)]
    scene.selected_object, scene.selected_camera = selected_object, selected_camera
    kept = {uid: element for uid, element in successors.items()
            if placed[uid] == now[element.uid] and _may_stay(scene, before[uid], element)}
    for uid, element in kept.items():
        _keep_what_the_person_did(scene, before[uid], element)
    scene.view_moves[:] = [kept.get(camera.uid, camera) for camera in scene.view_moves
                           if camera.uid not in placed or camera.uid in kept]
    scene.texture_path, scene.texture_named_at = read.texture_path, read.texture_named_at
    scene.texture_plain = read.texture_plain
    scene.frame_at_start = read.frame_at_start
    scene.loads += 1
    if scene.fitted_unit != 1.0:  # read on the seed's scale, as at start; the lights stand on the fitted one
        fit_camera_bodies(read.cameras, scene.fitted_unit)
    if (read.frame_at_start and scene.objects and any(camera is scene.camera for camera in read.cameras)
            and len(scene.camera.history) == 1):
        frame_models(scene, aspect)
    return kept


LightSettings = dict[str, object]  # a light's values a scene file sets, by the Light field each is
FILE_LIGHT_FIELDS = ("on", "intensity", "direction", "position", "aperture_deg")


def file_lights(read: Scene) -> dict[str, LightSettings]:
    """What a scene file just read set each light to, by its key, and the ambient Ia ("ambient"): what
    --watch's read again compares, before any fitting to the models' units moves a light."""
    settings: dict[str, LightSettings] = {light.key: {name: _comparable(getattr(light, name))
                                                      for name in FILE_LIGHT_FIELDS} for light in read.lights}
    for light in read.lights:  # a place the file wrote and SPEC's, the same numbers, fit otherwise
        settings[light.key]["position"] = (settings[light.key]["position"], light.placed_by_file)
    settings["ambient"] = {"ambient": _comparable(read.ambient)}
    return settings


def _comparable(value: object) -> object:
    return tuple(value) if isinstance(value, np.ndarray) else value


def take_edited_lights(scene: Scene, read: Scene, before: dict[str, LightSettings],
                       now: dict[str, LightSettings]) -> list[str]:
    """The ambient, and each value of a light (on, intensity, direction, position, aperture) that the file
    changed since its last read, as the file now sets it; what the file did not change stays as the keys
    left it. Returns the names of those changed."""
    taken = []
    if before["ambient"] != now["ambient"]:
        scene.ambient = read.ambient.copy()
        taken.append("ambient")
    for light, as_read in zip(scene.lights, read.lights):
        edited = [name for name in FILE_LIGHT_FIELDS if before[light.key][name] != now[light.key][name]]
        if edited:
            _take_light(light, as_read, edited, scene.fitted_unit)
            taken.append(light.name)
    return taken


class FileSaid(NamedTuple):
    """What a scene file's read placed and lit, before any move or fitting: what its next read is compared with."""

    placed: dict[int, FilePlacement]
    lights: dict[str, LightSettings]


def file_said(read: Scene) -> FileSaid:
    return FileSaid(file_placements(read), file_lights(read))


def take_scene_read(scene: Scene, read: Scene, last: FileSaid, aspect: float) -> tuple[FileSaid, dict[int, SceneObject],
                                                                                      list[str]]:
    """`read` in the place of what the `last` read placed (replace_scene_read), with the lights' values it
    changed (take_edited_lights): what it said, the elements kept as the person moved them, and the lights set."""
    now = file_said(read)  # before framing moves its camera
    kept = replace_scene_read(scene, read, last.placed, now.placed, aspect)
    return now, kept, take_edited_lights(scene, read, last.lights, now.lights)


def _take_light(light: Light, as_read: Light, edited: list[str], fitted_unit: float) -> None:
    """`light`'s `edited` values as a scene file read again sets them; a new place or direction starts its
    moves afresh (their undo would put back the old one), a place at SPEC's on the models' units, as at start."""
    for name in edited:
        value = getattr(as_read, name)
        setattr(light, name, value.copy() if isinstance(value, np.ndarray) else value)
    if "position" in edited:
        light.placed_by_file = as_read.placed_by_file
        if stands_where_fitted(as_read, 1.0):
            light.position = fitted_light_place(as_read, fitted_unit)
    if "position" in edited or "direction" in edited:
        light.history = []


def _successors(scene: Scene, placed: dict[int, FilePlacement], read: Scene,
                now: dict[int, FilePlacement]) -> dict[int, SceneObject]:
    """By uid, each element still in the scene that the last read placed, and the element read for its entry."""
    read_for = {now[element.uid].entry: element for element in read.objects + read.cameras}
    return {element.uid: read_for[placed[element.uid].entry] for element in scene.objects + scene.cameras
            if element.uid in placed and placed[element.uid].entry in read_for}


def _may_stay(scene: Scene, before: SceneObject, read: SceneObject) -> bool:
    """Whether `read` can stand where the person moved `before`: not where the model read again cannot."""
    return before.source != read.source or scene.placement_refusal(read, before.model) is None


def _keep_what_the_person_did(scene: Scene, before: SceneObject, read: SceneObject) -> None:
    """`read` where the person moved `before`, with its undo and the model PageDown chose for it (its entry's
    model unchanged: what the person did not edit stays)."""
    read.history, read.view_sizes = before.history, before.view_sizes
    if before.source != read.source:
        replace_loaded(scene, read, before)
    read.browsed = before.browsed
    read.selected_face = before.selected_face if before.selected_face < read.mesh.face_count else 0


def _index_after_reading(elements: list[SceneObject], selected: int, read: list[SceneObject],
                         placed: dict[int, FilePlacement], successors: dict[int, SceneObject]) -> int:
    """Where the selected element's successor stands once `read` took the place of those the last read placed:
    the one read for its entry; else the one read at its index among them (the last one read where the file
    places fewer); or, where it joined from elsewhere, itself."""
    if not elements:
        return 0
    chosen = elements[selected]
    if chosen.uid in successors:
        return next(index for index, element in enumerate(read) if element is successors[chosen.uid])
    if chosen.uid not in placed:
        return len(read) + sum(1 for element in elements[:selected] if element.uid not in placed)
    index = sum(1 for element in elements[:selected] if element.uid in placed)
    return max(0, min(index, len(read) - 1))
