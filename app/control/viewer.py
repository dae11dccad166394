"""What the window, the screenshot command and the API share: the scene, the key map, the `f` prompt
and the loading of files.

A `Viewer` is the key map's `Host`: commands that reach outside the scene (load a file, quit, save a
screenshot) land here, and the front end supplies what only it can do through `Frontend`. Drawing
is not here: every front end hands the viewer's scene to the one renderer.
"""

from __future__ import annotations

import functools
import threading
import time
import weakref
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple, Protocol

import numpy as np

from marraztu.control import commands, keymap, rereading
from marraztu.control.browse import FileWatcher, ModelWatcher, SeenFiles, read_together
from marraztu.errors import LoadError, ViewerError, escaped
from marraztu.loaders.images import fit_texture, load_image, load_texture_or_fallback
from marraztu.loaders.obj import READER_COMPILING
from marraztu.loaders.registry import UNSCALED, Stage, load_model, sized
from marraztu.loaders.scenefile import (
    empty_scene,
    give_part_materials,
    load_builtin_scene,
    load_scene,
    material_for_loaded,
)
from marraztu.model.framing import framed_scale
from marraztu.model.mesh import PLAIN_PICTURE, Mesh, counted
from marraztu.model.scene import WIDEST_ASPECT, Outlook, Scene, SceneObject, Sight, kept_name, placed_boxes
from marraztu.model.transforms import Vec3
from marraztu.model.viewports import narrowest_aspect


class Frontend(Protocol):
    """What only a window, or only the offscreen runner, can do."""

    def quit(self) -> None: ...

    def notice(self, text: str) -> None:
        """Tells what happened at start-up where the person started the program (stderr)."""
        ...


@dataclass
class StartOptions:
    """Where the starting scene comes from: SPEC 3's built-in one, a TOML file, or the camera alone."""

    scene_file: Path | None = None
    empty: bool = False
    texture: Path | None = None
    models: tuple[Path, ...] = ()
    watch: bool = False  # reload a model when its file changes on disk (the window's --watch)


def starting_scene(options: StartOptions, notice: Callable[[str], None] | None = None) -> Scene:
    """Raises LoadError when the scene file is bad: there is no earlier scene to fall back on. `notice`
    hears what a scene file's loads tell as the screenshot command's do (tell_compiling)."""
    if options.empty:
        return empty_scene()
    if options.scene_file is not None:
        return load_scene(options.scene_file, None if notice is None else functools.partial(tell_compiling, notice))
    return load_builtin_scene()


def scene_file_watcher(options: StartOptions) -> FileWatcher | None:
    """--watch's scene file as it is before the start reads it (Viewer.start): a save while its models load is
    then read once they have."""
    return FileWatcher(options.scene_file) if options.watch and options.scene_file is not None else None


def load_model_object(path: str | Path, scale: Vec3 = UNSCALED, stage: Stage | None = None) -> SceneObject:
    """A model file as a new scene element, placed at the origin like the seed's fresh objects; read at
    `scale` where it takes the place of an element a scene file sized. `stage` hears the load's stages."""
    return _placed(sized(load_model(path, stage), scale, Path(path)), Path(path), scale)


def _placed(mesh: Mesh, source: Path, scale: Vec3 = UNSCALED) -> SceneObject:
    material = material_for_loaded(mesh)
    obj = SceneObject.placed(kept_name(mesh.name), mesh, material, (0.0, 0.0, 0.0), source=source)
    obj.scale = scale
    give_part_materials(obj, from_scene=False)
    return obj


MAX_PROMPT_CHARACTERS = 4096  # Linux's PATH_MAX
UNSEEN_NAMES_SAID = 5  # a start message names this many models too small to see, then "..."
# PageDown keeps the camera, so that a view set up to compare models of one size stays; a file shown
# this many times smaller or larger than `.` would frame it is said, with that key.
SCALE_SAID_FROM_FRAMED = 10.0
# The message of a start that says nothing else: a first-time person learns the two keys that open the rest.
START_HINT = "h: help \u00b7 f: open a model"


@dataclass(eq=False)
class LoadJob:
    """One file being loaded on the worker thread; where it goes is decided when it is asked for."""

    path: Path
    as_camera: bool
    at_start: bool = False  # asked for on the command line: its outcome is told, not overwritten
    # PageDown / --watch: the elements it takes the place of, one file's at one scale, which share its mesh.
    replaces: tuple[SceneObject, ...] = ()
    # --watch's scene file read again whole (a Scene comes back), and its models' files as seen before.
    reads_scene: bool = False
    seen: SeenFiles = SeenFiles({}, {})
    # Its texture put in the Scene read, on the worker too (a large picture decodes for a visible while),
    # and what that said; None where the command line named the texture.
    read_texture: Callable[[Scene], list[str]] | None = None
    texture_notes: list[str] = field(default_factory=list)
    future: Future[SceneObject | Scene] = field(default_factory=Future)
    # Written by the worker, read by the window's status line. Stages, not a percentage: the parser
    # works on whole arrays, so a percentage would jump in a few steps rather than move smoothly.
    stage: str = "waiting"
    started: float = field(default_factory=time.monotonic)

    def set_stage(self, stage: str) -> None:
        self.stage = stage

    @property
    def label(self) -> str:
        seconds = time.monotonic() - self.started
        return f"loading {escaped(self.path.name)}: {self.stage} ({seconds:.0f} s)"


class BackgroundLoader:
    """Loads model files off the render thread, so the window keeps drawing and answering keys while
    a large file is read (numpy releases the GIL for most of a load). One worker: loads finish in the
    order asked. `prepare` (the renderer's) readies a mesh for its first frame."""

    def __init__(self, prepare: Callable[[Mesh], None] | None = None, wake: Callable[[], None] | None = None) -> None:
        self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="model-loader")
        self._jobs: list[LoadJob] = []
        self._lock = threading.Lock()
        self._prepare = prepare
        self._wake = wake  # called from the worker when a load ends: the window's loop answers it at once

    def start(self, path: Path, as_camera: bool, at_start: bool = False,
              replaces: tuple[SceneObject, ...] = ()) -> LoadJob:
        return self._submit(LoadJob(path, as_camera, at_start, replaces))

    def start_scene(self, path: Path, seen: SeenFiles,
                    read_texture: Callable[[Scene], list[str]] | None = None) -> LoadJob:
        """--watch: the scene file read again whole, its models and texture too, as at start."""
        return self._submit(LoadJob(path, as_camera=False, reads_scene=True, seen=seen, read_texture=read_texture))

    def _submit(self, job: LoadJob) -> LoadJob:
        with self._lock:
            self._jobs.append(job)
        job.future = self._pool.submit(self._load, job)
        if self._wake is not None:
            wake = self._wake
            job.future.add_done_callback(lambda _: wake())
        return job

    def _load(self, job: LoadJob) -> SceneObject | Scene:
        if job.reads_scene:
            return self._load_scene(job)
        scale = job.replaces[0].scale if job.replaces else UNSCALED  # read again at the size it was read
        mesh = sized(load_model(job.path, stage=job.set_stage), scale, job.path)
        if self._prepare is not None:
            job.set_stage("preparing vertex arrays")
            self._prepare(mesh)
        job.set_stage("joining the scene at the next frame")
        return _placed(mesh, job.path, scale)

    def _load_scene(self, job: LoadJob) -> Scene:
        scene = load_scene(job.path, job.set_stage, again=True)
        if job.read_texture is not None:
            job.set_stage("reading the texture")
            job.texture_notes = job.read_texture(scene)
        if self._prepare is not None:
            job.set_stage("preparing vertex arrays")
            for mesh in {id(element.mesh): element.mesh for element in scene.objects + scene.cameras}.values():
                self._prepare(mesh)
        job.set_stage("joining the scene at the next frame")
        return scene

    def pending(self) -> list[LoadJob]:
        with self._lock:
            return [job for job in self._jobs if not job.future.done()]

    def uncollected(self) -> list[LoadJob]:
        """Every job not yet taken by a frame, finished or not: to the person it is still loading
        until it is in the scene."""
        with self._lock:
            return list(self._jobs)

    def finished(self) -> list[LoadJob]:
        """The jobs done and waiting for a frame to take them."""
        with self._lock:
            return [job for job in self._jobs if job.future.done()]

    def take_finished(self) -> list[LoadJob]:
        with self._lock:
            # Each job asked once: a job finishing between two asks would be in neither list, and lost.
            finished = {id(job): job.future.done() for job in self._jobs}
            done = [job for job in self._jobs if finished[id(job)]]
            self._jobs = [job for job in self._jobs if not finished[id(job)]]
        return done

    def shutdown(self) -> None:
        self._pool.shutdown(wait=False, cancel_futures=True)


class _StartLoad(NamedTuple):
    """A start-up model that loaded, told with the rest of its batch (Viewer._tell_start_loads)."""
    obj: SceneObject
    path: Path
    joined: bool  # joined objects from elsewhere: where it stands is said


# What a load says of a model its lights leave black: SPEC starts with every light off, under an ambient light
# that a material of Ka 0 0 0 does not reflect.
DARK_HINT = ", black with every light off (its Ka is 0 0 0: 0 to 3 turn lights on)"
# What a load says of a model whose box holds the eye: the picture shows its inside, often back faces alone.
AROUND_HINT = ", around the camera (. frames it from outside)"


class _Before(NamedTuple):
    """The selected object as a key found it (its matrix and mesh, as they are never changed in place),
    and the view then."""
    obj: SceneObject
    model: np.ndarray
    mesh: Mesh
    outlook: Outlook
    pixels_high: int | None  # the filled views' height: None where lines are drawn, which are never too thin

    def sight(self) -> Sight:
        corners = placed_boxes(self.model[None], np.array([self.mesh.bounds], dtype=np.float64))
        return self.outlook.sights(corners, self.pixels_high)[0]


class _SaidUnseen(NamedTuple):
    """A message that says the object is out of view, and what it says without those words: what a mouse
    move that brings the object into view leaves up."""
    obj: weakref.ref[SceneObject]  # weak: a model deleted meanwhile is freed, not kept for its message
    said: str
    seen: str


class Viewer:
    def __init__(self, scene: Scene, frontend: Frontend, strict: bool = False,
                 background: BackgroundLoader | None = None,
                 frame_size: Callable[[], tuple[int, int]] | None = None) -> None:
        self.scene = scene
        # The framebuffer the front end draws now, width and height: a click finds its pixel there, and a
        # model loaded beside the scene is said to be outside its narrowest view. None: no picture is drawn.
        self.frame_size: Callable[[], tuple[int, int] | None] = frame_size or (lambda: None)
        self.frontend = frontend
        self.keys = keymap.KEYMAP
        # Strict (the screenshot command): a failed load is an error that ends the run, since a
        # picture without the asked-for model would be a lie. The window shows the message instead.
        self.strict = strict
        # With a background loader (the window), `f` and dropped files load on a worker thread and
        # join the scene in `collect_loads`, called once a frame; without one, loads are immediate.
        self.background = background
        self.prompt: str | None = None  # the `f` prompt's text while it is open
        self.watcher: ModelWatcher | None = None  # set by --watch
        self.scene_watcher: FileWatcher | None = None  # set by --watch with a scene file
        # Where the scene file's last read placed its elements, by uid: a read again takes their place.
        self._last_read = rereading.FileSaid({}, {})
        self._collecting: list[LoadJob] = []  # the worker's finished loads collect_loads is adding
        # What reads the scene file's texture into its Scene read again; None where the command line named
        # the texture, which outlasts a read again.
        self._scene_texture: Callable[[Scene], list[str]] | None = None
        self._starting = False
        self._start_models_alone = False  # the scene holds only the command line's models: framed together
        self._start_models_to_frame = False  # some of them joined since they were last framed
        # Told once the batch is in: where each stands then comes from one look at the scene, not one
        # per model (thousands of models on the command line).
        self._start_loads: list[_StartLoad | str] = []  # a failure as its message
        self._said_unseen: _SaidUnseen | None = None  # the last message that said an object is out of view
        self._said_by_mouse = ""  # what the last mouse event said of its own (a refusal): "" where nothing

    # --- start-up ------------------------------------------------------------------------------
    def start(self, options: StartOptions, longest_texture_side: int,
              scene_watcher: FileWatcher | None = None) -> None:
        """The texture (the one named, or the scene's) and the models of the command line. Every
        failure is told, on screen and to the front end, and none hides another. `scene_watcher`: the scene
        file as scene_file_watcher saw it before it was read; made here, seen as now, where none is given."""
        self._starting = True
        self._last_read = rereading.file_said(self.scene)
        self._scene_texture = (None if options.texture is not None
                               else functools.partial(read_texture, named=None, longest_side=longest_texture_side))
        # The command line's models are framed together where they are alone, or beside a scene
        # file's that places no camera (framed with them).
        self._start_models_alone = not self.scene.objects or self.scene.frame_at_start
        self._start_models_to_frame = self.scene.frame_at_start and bool(self.scene.objects)
        self.scene.message = ""
        try:
            for note in self.scene.notes:
                self.tell(note)
            self._start_texture(options.texture, longest_texture_side)
            for model in options.models:
                self.load_model(model)
            self._tell_start_loads()
            self._frame_start_models()
            # A model asked for is always told, once loaded (later, in the window): no hint before it.
            if not self.scene.message and not options.models:
                self.scene.message = START_HINT
            if options.watch:
                self.watcher = ModelWatcher()
                self.watcher.changed(self.scene)  # what the files are now: later changes are the news
            if options.watch and options.scene_file is not None:
                self.scene_watcher = scene_watcher or FileWatcher(options.scene_file)
                self.scene_watcher.watch_also(self._pictures_named(self.scene))
        finally:
            self._starting = False

    def _start_texture(self, named: Path | None, longest_side: int) -> None:
        """The texture named on the command line, else the scene's; one that cannot be read is told
        and stood in for, but where strict a named one ends the command."""
        if named is not None and self.strict:  # asked for by name: a bad one ends the command
            self.scene.texture, note = fit_texture(load_image(named), longest_side)
            notes = [note]
        else:
            notes = read_texture(self.scene, named, longest_side)
        for message in filter(None, notes):
            self.tell(message)

    def _at_start(self, at_start: bool | None) -> bool:
        """Whether a message belongs to start-up: as said, or (None) while the viewer is starting."""
        return self._starting if at_start is None else at_start

    def tell(self, text: str, at_start: bool | None = None, worth_a_notice: bool = True) -> None:
        """The message the person reads. At start-up messages add up instead of replacing each other,
        and the front end hears those worth a notice (failures, notes) too."""
        self._tell_each([(text, worth_a_notice)], at_start)

    def _tell_each(self, told: list[tuple[str, bool]], at_start: bool | None) -> None:
        """Messages, each with whether it is worth a notice, as `tell` tells them one by one; joined
        once, as a batch of thousands would be copied thousands of times."""
        if not told:
            return
        if not self._at_start(at_start):
            self.scene.message = told[-1][0]
            return
        lines = [text for text, _ in told]
        self.scene.message = "\n".join([self.scene.message, *lines] if self.scene.message else lines)
        for text, worth_a_notice in told:
            if worth_a_notice:
                self.frontend.notice(text)

    # --- keys ----------------------------------------------------------------------------------
    def press(self, key: keymap.KeyPress) -> None:
        """One key: typed into the `f` prompt while it is open (a drag or the wheel moves past it), otherwise the
        key map's command."""
        self._said_by_mouse = ""  # the message answers this key now: a mouse move takes back none of its words
        if self.prompt is not None and key.path is None and keymap.typed_into_prompt(key):
            self._prompt_key(key.token)
            return
        if self.strict and key.pixel is not None:  # a click off the picture is a mistake in the keys, as a bad key is
            refusal = keymap.mouse_refusal(key, self)
            if refusal is not None:
                raise ViewerError(refusal)
        before = self._seen_selected()
        keymap.dispatch(self.scene, key, self)
        lost = self._lost_since(before, said=self.scene.message)  # dispatch cleared it: the key's own words
        if lost and before is not None:
            said = self.scene.message
            self._say_unseen(before.obj, f"{said}; {lost}" if said else lost, seen=said)
        # A bare f too: the keys after it, read as typed into a prompt that never opened, would be pressed.
        if self.strict and key.token == "f" and self.scene.message == commands.LIGHTS_LOAD_REFUSAL:
            raise ViewerError(f"{key}: {commands.LIGHTS_LOAD_REFUSAL} (press c to target objects)")

    def press_sequence(self, text: str) -> None:
        for key in self.key_presses(text):
            self.press(key)

    def key_presses(self, text: str) -> list[keymap.KeyPress]:
        """Keys in the language of --keys, as pressed now: typed into a prompt an earlier sequence left open."""
        return keymap.parse_key_sequence(text, in_prompt=self.prompt is not None)

    def type_text(self, char: str) -> None:
        """A character from the window's text input: typed into the prompt, or pressed as a key."""
        if self.prompt is not None:
            self._type(char)
        elif not char.isspace():
            self.press(keymap.KeyPress(char))

    def _prompt_key(self, token: str) -> None:
        if token == "ESC":
            self.prompt = None
            self.scene.message = "loading cancelled"
        elif token == "ENTER":
            typed, self.prompt = self.prompt.strip(), None
            if typed:
                self.load_model(typed)
        elif token == "BACKSPACE":
            self.prompt = self.prompt[:-1]
        elif token in keymap.PROMPT_TEXT:
            self._type(keymap.PROMPT_TEXT[token])
        elif len(token) == 1:
            self._type(token)

    def _type(self, text: str) -> None:
        """Into the `f` prompt, up to MAX_PROMPT_CHARACTERS: a path is shorter, and a longer line would
        cost every key a copy of it and end as an error message pages long."""
        if len(self.prompt) + len(text) <= MAX_PROMPT_CHARACTERS:
            self.prompt += text

    # --- Host ----------------------------------------------------------------------------------
    def load_model(self, path: str | Path) -> bool:
        """SPEC 6 `f`: on success the new element is selected; on failure the scene is untouched."""
        as_camera = commands.loads_as_camera(self.scene)
        try:
            path = Path(path).expanduser()
        except RuntimeError:  # "~nosuchuser/..."
            return self._failed(LoadError(path, "no such user's home folder"))
        if self.background is not None:
            job = self.background.start(path, as_camera, at_start=self._starting)
            if not self._starting:
                self.tell(f"loading {escaped(job.path.name)}; the window stays usable meanwhile")
            return True
        try:
            obj = load_model_object(path, stage=self._waiting_on)
        except LoadError as error:
            return self._failed(error)
        self._add(obj, path, as_camera)
        return True

    def _waiting_on(self, stage: str) -> None:
        tell_compiling(self.frontend.notice, stage)

    def collect_loads(self) -> None:
        """Adds what the worker finished, in the order asked; a failure leaves only its message."""
        if self.background is None:
            return
        self._collecting = self.background.take_finished()
        try:
            for job in self._collecting:
                self._collect(job)
        finally:
            self._collecting = []  # taken: nothing of the batch held till the next frame
        if any(job.at_start for job in self.background.uncollected()):
            return  # the command line's models are told and framed as one batch, as start() does without a worker
        self._tell_start_loads()
        self._frame_start_models()

    def _collect(self, job: LoadJob) -> None:
        """One finished load into the scene, or its message."""
        error = job.future.exception()
        if error is not None and not isinstance(error, LoadError):  # a bug, not a bad file: said, not raised
            error = LoadError(job.path, f"could not be loaded ({type(error).__name__}: {error})")
        if job.reads_scene:
            self._scene_read(job.future.result() if error is None else error, job.path, job.seen,
                             job.texture_notes)
        elif error is None and job.replaces:
            self._replace_each(job.replaces, job.future.result())
        elif error is None:
            self._add(job.future.result(), job.path, job.as_camera, job.at_start)
        else:
            self._failed(error, job.at_start)

    def replace_model(self, element: SceneObject, path: Path) -> bool:
        """PageDown / PageUp and --watch: `path` in `element`'s place; a bad file leaves it as it was."""
        return self._replace_models((element,), path)

    def _replace_models(self, elements: tuple[SceneObject, ...], path: Path) -> bool:
        """`path`, read once at their scale, in the place of each of `elements` (read_together's group)."""
        if self.background is not None:
            self.background.start(path, elements[0] in self.scene.cameras, replaces=elements)
            self.tell(f"loading {escaped(path.name)} in place of {_names([element.name for element in elements])}")
            return True
        try:
            loaded = load_model_object(path, elements[0].scale, stage=self._waiting_on)
        except LoadError as error:
            return self._failed(error)
        self._replace_each(elements, loaded)
        return True

    def check_watched(self) -> None:
        """--watch: every element whose file changed on disk is read again, in its place; the elements of
        one file at one scale share the new mesh, as a scene file's do."""
        if self.watcher is None:
            return
        reading_scene = self.scene_watcher.changed() if self.scene_watcher is not None else None
        before = self.watcher.files_seen() if reading_scene else {}
        changed = self.watcher.changed(self.scene)
        if reading_scene or self._scene_read_pending():  # its models are read with it: not in what it replaces
            changed = [element for element in changed if element.uid not in self._last_read.placed]
        if reading_scene:
            self._read_scene_again(self.scene_watcher.path, SeenFiles(before, self.watcher.files_seen()), reading_scene)
        for elements in read_together(changed):
            self._replace_models(elements, elements[0].source)

    def _scene_read_pending(self) -> bool:
        return self.background is not None and any(job.reads_scene for job in self.background.uncollected())

    def _read_scene_again(self, path: Path, seen: SeenFiles, changed: Path) -> None:
        """--watch: the scene file read again whole, as at start, in the place of what it placed, where it or
        a picture it names (`changed`) changed."""
        texture_reader = self._scene_texture
        if self.background is not None:
            self.background.start_scene(path, seen, texture_reader)
            again = "it" if changed == path else escaped(path.name)
            self.tell(f"{escaped(changed.name)} changed: reading {again} again")
            return
        try:
            read: Scene | LoadError = load_scene(path, self._waiting_on, again=True)
        except LoadError as error:
            read = error
        notes = texture_reader(read) if texture_reader is not None and isinstance(read, Scene) else []
        self._scene_read(read, path, seen, notes)

    def _scene_read(self, read: Scene | LoadError, path: Path, seen: SeenFiles, notes: list[str]) -> None:
        """A scene file read again, in the place of what it placed; one that failed leaves the scene as it
        was, its message saying where, the models' changes its look found to be told again, and the file it
        failed on (a model or picture it names) watched until a read succeeds."""
        if isinstance(read, LoadError):
            elements = self.scene.objects + self.scene.cameras
            self.watcher.stand_as([element for element in elements if element.uid in self._last_read.placed],
                                  seen.before)
            if isinstance(read.__cause__, LoadError):  # the model or picture it names that failed: its save is news
                self.scene_watcher.watch_too(Path(read.__cause__.path))
            self._failed(read)
            return
        self._last_read, kept, lit_anew = rereading.take_scene_read(self.scene, read, self._last_read,
                                                                    self.narrowest_aspect())
        self._loads_follow(kept)
        kept_now = {element.uid for element in kept.values()}  # a set: a scene of thousands is looked up once each
        anew = [element for element in read.objects + read.cameras if element.uid not in kept_now]
        self.scene_watcher.watch_also(self._pictures_named(read))
        self.watcher.stand_as(read.objects + read.cameras, seen.after)
        if self._scene_texture is not None:  # read with the file; a texture named on the command line stays
            self.scene.texture = read.texture
        said = (f"read {escaped(path.name)} again: {counted(len(read.objects), 'object')}, "
                f"{counted(len(read.cameras), 'camera')}")
        if anew:
            said += f"; placed where the file now says, their undo afresh: {_names([element.name for element in anew])}"
        if lit_anew:
            said += f"; lights as the file now sets them: {', '.join(lit_anew)}"
        self.tell("; ".join([said, *read.notes, *notes]))

    def _loads_follow(self, kept: dict[int, SceneObject]) -> None:
        """A PageDown still loading for an element a scene file's read again kept (by its old uid) goes to the
        element that took its place, as its moves did."""
        for job in [*self._collecting, *self.background.uncollected()] if self.background is not None else []:
            job.replaces = tuple(kept.get(element.uid, element) for element in job.replaces)

    def _pictures_named(self, read: Scene) -> list[Path]:
        """The pictures a scene file's read named: its objects' and cameras' own, and its texture where no
        --texture stands in for it."""
        own = [element.picture_source for element in read.objects + read.cameras if element.picture_source]
        scenes = [Path(read.texture_path)] if read.texture_path and self._scene_texture else []
        return own + scenes

    def _replace_each(self, elements: tuple[SceneObject, ...], loaded: SceneObject) -> None:
        """`loaded` in the first element's place, and its mesh, with materials of their own, in the others';
        one message says them all (each saying its own, only the last one's showed)."""
        replaced: list[tuple[SceneObject, str]] = []  # with its name before
        refusals: list[str] = []
        lost: tuple[SceneObject, str] | None = None  # the selected element, where the view no longer shows it
        in_scene = {id(element) for element in self.scene.objects + self.scene.cameras}  # identity: eq=False
        for index, element in enumerate(elements):
            each = loaded if index == 0 else _placed(loaded.mesh, element.source, element.scale)
            refusal = self._replace_refusal(element, each, id(element) in in_scene)
            if refusal:
                refusals.append(refusal)
                continue
            selected = element is self.scene.object and self.scene.viewer is not element
            seen = selected and not self._unseen_as(element, by_scale=True)
            replaced.append((element, element.name))
            commands.replace_loaded(self.scene, element, each)
            where = self._unseen_as(element, by_scale=True) if seen else ""
            if where:
                lost = (element, _lost_notice(element, where))
        said = self._replaced_words(loaded, replaced)
        refused = _names(refusals, "; ")
        told = "; ".join(filter(None, [said, lost[1] if lost else "", refused]))
        self.tell(told)
        if replaced and self.scene.message == told:  # not joined to start-up's lines
            self._remember_unseen(lost[0] if lost else replaced[0][0], told, "; ".join(filter(None, [said, refused])))

    def _replace_refusal(self, element: SceneObject, loaded: SceneObject, in_scene: bool) -> str:
        """Why `loaded` cannot take the element's place (`in_scene`: whether it is still there); "" where it can."""
        if not in_scene:
            return f"{escaped(loaded.source.name)} was read, but {element.name} has left the scene meanwhile"
        refusal = self.scene.placement_refusal(element, element.model, loaded.mesh)
        # where it stands, the next call would refuse the scene
        return "" if refusal is None else f"{escaped(loaded.source.name)} cannot take {element.name}'s place: {refusal}"

    def _replaced_words(self, loaded: SceneObject, replaced: list[tuple[SceneObject, str]]) -> str:
        """A read's message of the elements it replaced: what all of them are said, as one element's is,
        after the mesh's summary; what only some are, after its notes, with their names. "" where none."""
        if not replaced:
            return ""
        elements = [element for element, _ in replaced]
        hints = {AROUND_HINT: self._around(elements), DARK_HINT: [self._dark(element) for element in elements]}
        named = {hint: [element.name for element, words in zip(elements, each) if words]
                 for hint, each in hints.items()}
        shared = "".join(hint for hint, names in named.items() if len(names) == len(elements))
        some = "".join(f"; {_names(names)}: {hint.removeprefix(', ')}" for hint, names in named.items()
                       if 0 < len(names) < len(elements))
        names = _names([name for _, name in replaced])
        return with_notes(f"{escaped(loaded.source.name)} in place of {names}: {loaded.mesh.summary()}{shared}",
                          loaded.mesh) + some

    def loading_lines(self) -> list[str]:
        return [job.label for job in self.background.uncollected()] if self.background else []

    def _failed(self, error: LoadError, at_start: bool | None = None) -> bool:
        if self.strict:
            self._tell_start_loads()  # the loads before it are told first
            self.scene.message = str(error)
            raise error
        if self._at_start(at_start):
            self._start_loads.append(str(error))
        else:
            self.tell(str(error), at_start)
        return False

    def _add(self, obj: SceneObject, path: Path, as_camera: bool, at_start: bool | None = None) -> None:
        # The command line's models are framed together while the scene holds only them, once the
        # ones that join together have (_frame_start_models): framing looks at every model.
        starting = self._at_start(at_start)
        together = starting and not as_camera and self._start_models_alone
        commands.add_loaded(self.scene, obj, as_camera=as_camera, aspect=self.narrowest_aspect())
        if as_camera:
            self._tell_each([_loaded_message(obj, Path(path), "camera", "")], at_start)
            return
        self._start_models_alone = together  # a model from elsewhere joins: no longer theirs alone
        self._start_models_to_frame = together
        if starting:
            self._start_loads.append(_StartLoad(obj, Path(path), joined=not together))
            return
        sight, inside = self._sights_and_insides([obj])[0]
        told = _loaded_message(obj, Path(path), "object", commands.sight_words(sight) + inside)
        self._tell_each([told], at_start)
        if self.scene.message == told[0]:  # not joined to start-up's lines
            self._remember_unseen(obj, told[0], _loaded_message(obj, Path(path), "object", inside)[0])

    def add_made(self, obj: SceneObject) -> None:
        """An object made in Python (the API's add_mesh) joins as a loaded model does: framed where it is
        the only one, in the narrowest view, and said with where the view shows it."""
        commands.add_loaded(self.scene, obj, as_camera=False, aspect=self.narrowest_aspect())
        sight, inside = self._sights_and_insides([obj])[0]
        said, seen = (with_notes(f"added {obj.name}: {obj.mesh.summary()}{where}", obj.mesh)
                      for where in (commands.sight_words(sight) + inside, inside))
        self._say_unseen(obj, said, seen)

    def _tell_start_loads(self) -> None:
        """The start-up loads' messages, in the order asked, once the batch has joined the scene."""
        loads = self._start_loads.copy()
        self._start_loads.clear()  # the same list: a refused press leaves the viewer as it found it
        started = [load for load in loads if isinstance(load, _StartLoad)]
        joined = iter(self._unseen([load.obj for load in started if load.joined]))
        # Framed together, so seen: only a box of another holding one is said.
        together = iter(self._inside([load.obj for load in started if not load.joined]))
        told = []
        for load in loads:
            if isinstance(load, str):
                told.append((load, True))
            else:
                told.append(_loaded_message(load.obj, load.path, "object", next(joined if load.joined else together)))
        self._tell_each(told, at_start=True)

    def _unseen(self, objects: list[SceneObject]) -> list[str]:
        """What each load's message says of an object the view does not show, whose box holds the eye, or
        that another's box holds (framed with `.`, it may still be hidden there); "" where none."""
        return [commands.sight_words(sight) + inside for sight, inside in self._sights_and_insides(objects)]

    def _sights_and_insides(self, objects: list[SceneObject]) -> list[tuple[Sight, str]]:
        """How the view shows each loaded object, and what its message says whichever way it does: that
        its box holds the eye, that another's box holds it, that it is drawn black."""
        sights = self.scene.sights(objects, self.narrowest_aspect(), commands.filled_pixels_high(self.scene, self))
        return [(sight, around + inside) for sight, around, inside in zip(sights, self._around(objects),
                                                                          self._inside(objects))]

    def _say_unseen(self, obj: SceneObject, said: str, seen: str) -> None:
        self.scene.message = said
        self._remember_unseen(obj, said, seen)

    def _remember_unseen(self, obj: SceneObject, said: str, seen: str) -> None:
        self._said_unseen = _SaidUnseen(weakref.ref(obj), said, seen)

    def _inside(self, objects: list[SceneObject]) -> list[str]:
        """What each load's message says of an object that another's box holds, and of one its lights
        leave black; "" where neither."""
        return [("" if holder is None else f", inside {_other(holder, obj)}'s bounding box, perhaps hidden by it "
                 "(d shows it alone)") + self._dark(obj) for obj, holder in zip(objects, self.scene.enclosers(objects))]

    def _around(self, objects: list[SceneObject]) -> list[str]:
        """What each load's message says of an object whose box holds the eye; "" where it does not."""
        return [AROUND_HINT if around else "" for around in self.scene.around_eye(objects)]

    def _dark(self, obj: SceneObject) -> str:
        """What a load's message says of an object the lights leave black; "" where they do not."""
        return DARK_HINT if self.scene.black_for_want_of_light(obj) else ""

    def _seen_selected(self) -> _Before | None:
        """The selected object as a key finds it, and the view then; no test made yet."""
        obj = self.scene.object
        if obj is None or self.scene.viewer is obj:
            return None
        return _Before(obj, obj.model, obj.mesh, self.scene.outlook(self.narrowest_aspect()),
                       commands.filled_pixels_high(self.scene, self))

    def move_by_mouse(self, move: Callable[[Scene], None]) -> None:
        """One event of a drag or the wheel; said, as a key's move is, where it takes the selected model
        out of view (the message then answers the mouse, not the last key). What an event says of its own
        (a move refused) is taken back by the next event that says nothing: that one was made."""
        before = self._seen_selected()
        kept, self.scene.message = self.scene.message, ""
        move(self.scene)
        said = self.scene.message
        if not said:  # the last event's own words, where still up, no longer hold
            self.scene.message = "" if kept == self._said_by_mouse else kept
        self._said_by_mouse = said
        lost = self._lost_since(before)
        if lost and before is not None:
            self._say_unseen(before.obj, lost, seen="")
        elif before is not None:
            self._withdraw_unseen_words(before.obj)

    def _withdraw_unseen_words(self, obj: SceneObject) -> None:
        """The words that the object is out of view, taken back where a mouse move brought it in again:
        the next key would, and meanwhile they mislead over the model in plain view. The rest stays."""
        said = self._said_unseen
        if said is None or said.obj() is not obj or self.scene.message != said.said:
            return
        if self.scene.object is obj and self.scene.viewer is not obj and not self._unseen_as(obj):
            self.scene.message, self._said_unseen = said.seen, None

    def _lost_since(self, before: _Before | None, said: str = "") -> str:
        """That the object a key or a mouse move found in view is out of it now, in a message's words; ""
        where not, or where `said`, what the key itself said, says it (a mouse move says nothing of its own):
        one box test, and a second (the view before) only where it is out (a file read in its place is told
        by _replace, which also sees the one before)."""
        if before is None:
            return ""
        obj = before.obj
        if self.scene.object is not obj or self.scene.viewer is obj or obj.mesh is not before.mesh:
            return ""
        where = self._unseen_as(obj)
        if not where or where in said:  # `.` framing a beam under a pixel thick says so itself
            return ""
        return _lost_notice(obj, where) if before.sight() is Sight.SEEN else ""

    def _unseen_as(self, obj: SceneObject, by_scale: bool = False) -> str:
        """How the view does not show the object, in a message's words: outside it or too small to see,
        and, `by_scale` (a pass over its vertices), much smaller or larger than framed; "" where none."""
        aspect = self.narrowest_aspect()
        sight = self.scene.sight(obj, aspect, commands.filled_pixels_high(self.scene, self))
        if sight is not Sight.SEEN or not by_scale:
            return "" if sight is Sight.SEEN else sight.value
        scale = framed_scale(self.scene, obj, aspect)
        if scale < 1.0 / SCALE_SAID_FROM_FRAMED:
            return "much smaller than the view"
        return "much larger than the view" if scale > SCALE_SAID_FROM_FRAMED else ""

    def _frame_start_models(self) -> None:
        """The command line's models that joined, framed together while the camera has not moved."""
        if self._start_models_to_frame and len(self.scene.camera.history) == 1:
            commands.frame_models(self.scene, self.narrowest_aspect())
            self._tell_unseen_start_models()
        self._start_models_to_frame = False

    def _tell_unseen_start_models(self) -> None:
        """Models framed together far apart may each span under a pixel, and a thin one be under a pixel
        across: the picture alone is empty."""
        sights = self.scene.sights(self.scene.objects, self.narrowest_aspect(),
                                   commands.filled_pixels_high(self.scene, self))
        unseen = [obj.name for obj, sight in zip(self.scene.objects, sights) if sight not in (Sight.SEEN, Sight.THIN)]
        thin = [obj.name for obj, sight in zip(self.scene.objects, sights) if sight is Sight.THIN]
        if unseen:
            self.tell(f"{_names(unseen)}: too small to see framed together (TAB selects one, . frames it)",
                      at_start=True)
        if thin:
            self.tell(f"{_names(thin)}: {Sight.THIN.value} ({commands.sight_hint(Sight.THIN)})", at_start=True)

    def quit(self) -> None:
        self.frontend.quit()

    def open_file_prompt(self) -> None:
        self.prompt = ""

    def narrowest_aspect(self) -> float:
        """Width over height of the narrowest view drawn now; a view WIDEST_ASPECT wide where none is."""
        size = self.frame_size()
        return WIDEST_ASPECT if size is None else narrowest_aspect(self.scene, size)

    def save_screenshot(self) -> None:
        save = getattr(self.frontend, "save_screenshot", None)  # only a window keeps pictures as it goes
        if save is None:
            self.scene.message = "F12 saves in the window; offscreen, the picture is the one -o or render() makes"
        else:
            save()

    def toggle_recording(self) -> None:
        record = getattr(self.frontend, "toggle_recording", None)  # only a window records as it goes
        if record is None:
            self.scene.message = "F9 records in the window; offscreen, `marraztu record` draws a frame per press"
        else:
            record()


def _loaded_message(obj: SceneObject, path: Path, kind: str, where: str) -> tuple[str, bool]:
    """A load's message, and whether it is worth a notice: notes, or a place the view does not show."""
    text = with_notes(f"loaded {escaped(path.name)} as a new {kind}: {obj.mesh.summary()}{where}", obj.mesh)
    return text, bool(obj.mesh.warnings) or bool(where)


def tell_compiling(notice: Callable[[str], None], stage: str) -> None:
    """A stage of a load waited on with no status line meanwhile (the screenshot command's): the one that
    takes seconds, numba compiling the OBJ reader once after install, is told as it begins."""
    if stage == READER_COMPILING:
        notice(stage)


def _other(holder: SceneObject, obj: SceneObject) -> str:
    """The holder's name as a message about `obj` says it: a file loaded twice gives two of one name."""
    return f"the other {holder.name}" if holder.name == obj.name else holder.name


def read_texture(scene: Scene, named: Path | None, longest_side: int) -> list[str]:
    """The texture named on the command line, else the scene's (none for its `texture = false`), in `scene`;
    what it says: a picture that cannot be read (stood in for by the checker), one made smaller to fit."""
    if named is None and scene.texture_plain:
        scene.texture = PLAIN_PICTURE
        return []
    texture_path = named or (Path(scene.texture_path) if scene.texture_path else None)
    image, message = load_texture_or_fallback(texture_path)
    if message and named is None and scene.texture_named_at:  # the scene file's entry named it
        message = f"{scene.texture_named_at}: {message}"
    scene.texture, note = fit_texture(image, longest_side)
    return [said for said in (message, note) if said]


def _names(names: list[str], separator: str = ", ") -> str:
    """Models' names (or what a message says of each) in a message: the first UNSEEN_NAMES_SAID, then "..."."""
    return separator.join(names[:UNSEEN_NAMES_SAID]) + (f"{separator}..." if len(names) > UNSEEN_NAMES_SAID else "")


def _lost_notice(obj: SceneObject, where: str) -> str:
    """What a key, a mouse move or a file read in its place says of the selected object the view no longer shows."""
    sight = Sight.THIN if where == Sight.THIN.value else Sight.OUTSIDE  # or much smaller or larger: `.` too
    return f"{obj.name} is now {where} ({commands.sight_hint(sight)})"


def with_notes(message: str, mesh: Mesh) -> str:
    """A load's message with its mesh's notes after it, in brackets."""
    return f"{message} ({'; '.join(mesh.warnings)})" if mesh.warnings else message
