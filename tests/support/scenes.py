"""Scenes and meshes built by hand for the render tests, and the colours every picture is checked against."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from PIL import Image

from marraztu.control.viewer import StartOptions, Viewer
from marraztu.frontends.screenshot import take_screenshot
from marraztu.model.build import build_mesh
from marraztu.model.mesh import Mesh
from marraztu.model.scene import Material, Scene, SceneObject
from marraztu.render.renderer import Renderer

BACKGROUND = (0, 0, 178)  # SPEC 3: the clear colour (0, 0, 0.7) in bytes
BACKGROUND_FLOAT = (0.0, 0.0, 0.7)


def collect_when_loaded(viewer: Viewer, seconds: float = 600.0) -> None:  # only against a hang
    """The window's worker's loads, collected once none is pending, as the window collects them."""
    deadline = time.monotonic() + seconds
    while viewer.background.pending() and time.monotonic() < deadline:
        time.sleep(0.01)
    viewer.collect_loads()


def mesh_from_polygons(name: str, positions: Sequence[Sequence[float]],
                       polygons: Sequence[Sequence[int]],
                       uvs: Sequence[Sequence[float]] | None = None) -> Mesh:
    """A Mesh as the loader would make it, with per-vertex texture coordinates (zeros without)."""
    corner_vertex = [index for polygon in polygons for index in polygon]
    per_vertex = np.zeros((len(positions), 2)) if uvs is None else np.asarray(uvs, float)
    return build_mesh(name, positions, polygons, uvs=per_vertex[corner_vertex], attributes_per_vertex=False)


def quad_mesh(half: float = 50.0, facing_camera: bool = True) -> Mesh:
    """A square in z = 0 centred on the origin, uv (0, 0) at its bottom-left; counter-clockwise seen
    from +z (normal +z) or, with facing_camera False, the other way round (normal -z)."""
    positions = [(-half, -half, 0), (half, -half, 0), (half, half, 0), (-half, half, 0)]
    uvs = [(0, 0), (1, 0), (1, 1), (0, 1)]
    polygon = [0, 1, 2, 3] if facing_camera else [0, 3, 2, 1]
    return mesh_from_polygons("quad", positions, [polygon], uvs)


def box_mesh(half: float = 30.0) -> Mesh:
    """A closed cube, outward normals, counter-clockwise seen from outside."""
    h = half
    positions = [(-h, -h, -h), (h, -h, -h), (h, h, -h), (-h, h, -h),
                 (-h, -h, h), (h, -h, h), (h, h, h), (-h, h, h)]
    faces = [[4, 5, 6, 7], [1, 0, 3, 2], [5, 1, 2, 6], [0, 4, 7, 3], [7, 6, 2, 3], [0, 1, 5, 4]]
    return mesh_from_polygons("box", positions, faces)


PLAIN = Material(ka=(0.2, 0.3, 0.4), kd=(0.6, 0.5, 0.4), ks=(0.5, 0.4, 0.3), ns=20.0)


def scene_with(objects: list[SceneObject], camera_at: tuple[float, float, float] = (0, 0, 150),
               texture: bool = False) -> Scene:
    """The objects, seen from a camera on +z looking toward -z; all lights off, texture off."""
    camera = SceneObject.placed("camera", quad_mesh(2.0), PLAIN, camera_at)
    scene = Scene(objects=objects, cameras=[camera])
    scene.modes.texture = texture
    return scene


class RecordingHost:
    """The key map's host for tests without a window: records every call as (name, *arguments)."""

    def __init__(self) -> None:
        self.calls: list[tuple[object, ...]] = []

    def quit(self) -> None:
        self.calls.append(("quit",))

    def open_file_prompt(self) -> None:
        self.calls.append(("open_file_prompt",))

    def narrowest_aspect(self) -> float:
        return 1.0  # a square view, as the scenes' tests draw

    def frame_size(self) -> tuple[int, int] | None:
        return None  # no picture: a click is refused

    def load_model(self, path: str) -> bool | None:
        self.calls.append(("load_model", path))
        return None

    def replace_model(self, element: SceneObject, path: Path) -> bool | None:
        self.calls.append(("replace_model", element.name, path))
        return None

    def save_screenshot(self) -> None:
        self.calls.append(("save_screenshot",))

    def toggle_recording(self) -> None:
        self.calls.append(("toggle_recording",))


class NoFrontend:
    """A viewer's front end that does nothing: for tests that drive a Viewer without a window."""

    def quit(self) -> None: ...
    def save_screenshot(self) -> None: ...
    def notice(self, text: str) -> None: ...


class Notices(NoFrontend):
    """A front end that keeps what the viewer tells it (`told`), and hands each to `heard` as it comes."""

    def __init__(self, heard: Callable[[str], None] | None = None) -> None:
        self.told: list[str] = []
        self.heard = heard

    def notice(self, text: str) -> None:
        self.told.append(text)
        if self.heard is not None:
            self.heard(text)


class RenderingViewer(Viewer):
    """A viewer and the renderer that draws it, held together as a front end holds them."""

    def __init__(self, scene: Scene, renderer: Renderer, frontend, **options) -> None:
        super().__init__(scene, frontend, **options)
        self.renderer = renderer


def builtin_pictures_with(monkeypatch: pytest.MonkeyPatch, target: Any, name: str, values: Sequence[Any],
                          folder: Path, keys: str) -> list[np.ndarray]:
    """The built-in scene at 160x160 after `keys`, through the screenshot command, once with the function
    `target.name` answering each of `values` (whatever it is asked)."""
    pictures = []
    for value in values:
        monkeypatch.setattr(target, name, lambda *args, value=value: value)
        out = take_screenshot(StartOptions(), folder / f"{name}-{value}.png", (160, 160), keys=keys)
        pictures.append(np.asarray(Image.open(out).convert("RGB")))
    return pictures
