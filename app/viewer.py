"""What the window and the screenshot command share: the scene, the key map and the renderer.

A `Viewer` is the key map's `Host`: commands that reach outside the scene (load a file, quit,
screenshot, free GPU buffers) land here, and the front end (window or offscreen) supplies the parts
that differ through `Frontend`.
"""

from __future__ import annotations

import threading
import time
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Protocol

from app import commands, keymap, status
from app.errors import LoadError
from app.loaders.image import load_texture_or_fallback
from app.gpu import prepare_surface
from app.loaders.obj import load_obj
from app.mesh import Mesh
from app.renderer import Renderer
from app.scene import Scene, SceneObject
from app.scenefile import empty_scene, load_builtin_scene, load_scene, material_for_loaded


class Frontend(Protocol):
    """The parts of a host that only a window, or only the offscreen runner, can do."""

    def quit(self) -> None: ...
    def open_file_prompt(self) -> None: ...
    def save_screenshot(self) -> None: ...


@dataclass
class StartOptions:
    """Where the starting scene comes from: SPEC 3's built-in one, a TOML file, or the camera alone."""

    scene_file: Path | None = None
    empty: bool = False
    texture: Path | None = None
    models: tuple[Path, ...] = ()


def starting_scene(options: StartOptions) -> Scene:
    """Raises LoadError when the scene file is bad: there is no earlier scene to fall back on."""
    if options.empty:
        return empty_scene()
    if options.scene_file is not None:
        return load_scene(options.scene_file)
    return load_builtin_scene()


def load_model_object(path: str | Path) -> SceneObject:
    """An OBJ file as a new scene element, placed at the origin like the seed's fresh objects."""
    return _placed(load_obj(path))


def _placed(mesh: Mesh) -> SceneObject:
    return SceneObject.placed(mesh.name, mesh, material_for_loaded(mesh), (0.0, 0.0, 0.0))


@dataclass(eq=False)
class LoadJob:
    """One file being loaded on the worker thread; where it goes is decided when it is asked for."""

    path: Path
    as_camera: bool
    future: Future = field(default_factory=Future)
    # Written by the worker, read by the window's status line. The stages, not a percentage: the
    # parser works on whole arrays, so a percentage would be three numbers pretending to be smooth.
    stage: str = "waiting"
    started: float = field(default_factory=time.monotonic)

    def set_stage(self, stage: str) -> None:
        self.stage = stage

    @property
    def label(self) -> str:
        seconds = time.monotonic() - self.started
        return f"loading {self.path.name}: {self.stage} ({seconds:.0f} s)"


class BackgroundLoader:
    """Loads OBJ files off the render thread so the window keeps drawing and answering keys while a
    multi-million-triangle file is read. numpy releases the GIL for its heavy work, which is most of
    a load, so the render thread keeps its frames. One worker: loads finish in the order asked."""

    def __init__(self) -> None:
        self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="obj-loader")
        self._jobs: list[LoadJob] = []
        self._lock = threading.Lock()

    def start(self, path: Path, as_camera: bool) -> LoadJob:
        job = LoadJob(path, as_camera)
        with self._lock:
            self._jobs.append(job)
        job.future = self._pool.submit(self._load, job)
        return job

    @staticmethod
    def _load(job: LoadJob) -> SceneObject:
        mesh = load_obj(job.path, stage=job.set_stage)
        job.set_stage("preparing vertex arrays")
        prepare_surface(mesh)  # so the frame that adds it only uploads
        job.set_stage("joining the scene at the next frame")
        return _placed(mesh)

    def pending(self) -> list[LoadJob]:
        with self._lock:
            return [job for job in self._jobs if not job.future.done()]

    def uncollected(self) -> list[LoadJob]:
        """Every job not yet taken by a frame, finished or not: to the person it is still loading
        until it is in the scene."""
        with self._lock:
            return list(self._jobs)

    def take_finished(self) -> list[LoadJob]:
        with self._lock:
            done = [job for job in self._jobs if job.future.done()]
            self._jobs = [job for job in self._jobs if not job.future.done()]
        return done

    def shutdown(self) -> None:
        self._pool.shutdown(wait=False, cancel_futures=True)


class Viewer:
    def __init__(self, scene: Scene, renderer: Renderer, frontend: Frontend,
                 strict: bool = False, background: BackgroundLoader | None = None) -> None:
        self.scene = scene
        self.renderer = renderer
        self.frontend = frontend
        self.keys = keymap.KEYMAP
        # Strict (the screenshot command): a failed load is an error that ends the run, since a
        # picture without the asked-for model would be a lie. The window shows the message instead.
        self.strict = strict
        # With a background loader (the window), `f` and dropped files load on a worker thread and
        # join the scene in `collect_loads`, called once a frame; without one, loads are immediate.
        self.background = background

    # --- start-up ------------------------------------------------------------------------------
    def use_texture(self, path: Path | None) -> str | None:
        """Loads the texture, or the built-in fallback; returns the message to show, if any."""
        image, message = load_texture_or_fallback(path)
        self.renderer.set_texture(image)
        if message:
            self.scene.message = message
        return message

    # --- keys ----------------------------------------------------------------------------------
    def press(self, key: keymap.KeyPress) -> None:
        keymap.dispatch(self.scene, key, self)

    def press_sequence(self, text: str) -> None:
        for key in keymap.parse_key_sequence(text):
            self.press(key)

    # --- what the overlay shows ----------------------------------------------------------------
    def overlay_lines(self, prompt: str | None = None) -> tuple[list[str], list[str]]:
        """(top lines, bottom lines): status and help at the top, message and `f` prompt below."""
        top = [status.status_line(self.scene)]
        if self.scene.modes.show_help:
            top += status.help_lines(self.scene, self.keys)
        bottom = [self.scene.message] if self.scene.message else []
        bottom += self.loading_lines()
        if prompt is not None:
            bottom.append(f"OBJ file to load (Enter loads, ESC cancels): {prompt}_")
        return top, bottom

    # --- Host ----------------------------------------------------------------------------------
    def load_model(self, path: str | Path) -> bool:
        """SPEC 6 `f`: on success the new element is selected; on failure the scene is untouched."""
        as_camera = commands.loads_as_camera(self.scene)
        if self.background is not None:
            job = self.background.start(Path(path), as_camera)
            self.scene.message = f"loading {job.path.name}; the window stays usable meanwhile"
            return True
        try:
            obj = load_model_object(path)
        except LoadError as error:
            return self._failed(error)
        self._add(obj, Path(path), as_camera)
        return True

    def collect_loads(self) -> None:
        """Adds what the worker finished, in the order asked; a failure leaves only its message."""
        if self.background is None:
            return
        for job in self.background.take_finished():
            error = job.future.exception()
            if error is None:
                self._add(job.future.result(), job.path, job.as_camera)
            elif isinstance(error, LoadError):
                self._failed(error)
            else:  # a bug, not a bad file: say so instead of dying in the render loop
                self._failed(LoadError(job.path, f"could not be loaded ({type(error).__name__}: {error})"))

    def loading_lines(self) -> list[str]:
        return [job.label for job in self.background.uncollected()] if self.background else []

    def _failed(self, error: LoadError) -> bool:
        self.scene.message = str(error)
        if self.strict:
            raise error
        return False

    def _add(self, obj: SceneObject, path: Path, as_camera: bool) -> None:
        commands.add_loaded(self.scene, obj, as_camera=as_camera)
        kind = "camera" if as_camera else "object"
        self.scene.message = f"loaded {Path(path).name} as a new {kind}: " \
                             f"{obj.mesh.vertex_count} vertices, {obj.mesh.face_count} faces"
        if obj.mesh.warnings:
            self.scene.message += " (" + "; ".join(obj.mesh.warnings) + ")"

    def released(self, obj: SceneObject) -> None:
        self.renderer.release_object(obj)

    def quit(self) -> None:
        self.frontend.quit()

    def open_file_prompt(self) -> None:
        self.frontend.open_file_prompt()

    def save_screenshot(self) -> None:
        self.frontend.save_screenshot()
