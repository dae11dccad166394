"""`marraztu screenshot`: the scene rendered offscreen (EGL, no display needed), keys replayed first.

Same viewer, key map and renderer as the window; only the framebuffer differs.
"""

from __future__ import annotations

import os
import sys
import tempfile
from collections.abc import Callable, Iterable, Iterator, Mapping
from pathlib import Path

import moderngl
import numpy as np
from PIL import Image

from marraztu.control.keymap import KeyPress, parse_key_sequence
from marraztu.control.viewer import StartOptions, Viewer, starting_scene
from marraztu.errors import ViewerError, escaped
from marraztu.model.scene import Scene
from marraztu.render.context import create_offscreen_context, offscreen_framebuffer, read_pixels
from marraztu.render.renderer import Renderer

# Pillow's format for each suffix a picture may be written as.
IMAGE_FORMATS = {".png": "PNG", ".jpg": "JPEG", ".jpeg": "JPEG"}


class OffscreenFrontend:
    """ESC ends the replay; the -o file is the screenshot. `quiet` (the API): notices stay in the
    scene's message instead of going to stderr."""

    def __init__(self, quiet: bool = False) -> None:
        self.quitting = False
        self.quiet = quiet

    def quit(self) -> None:
        self.quitting = True

    def replay(self, viewer: Viewer, presses: Iterable[KeyPress]) -> Iterator[KeyPress]:
        """Each press, given to `viewer` and then yielded, up to ESC, which ends the replay."""
        for press in presses:
            if self.quitting:
                return
            viewer.press(press)
            yield press

    def notice(self, text: str) -> None:
        if not self.quiet:
            print(escaped(text), file=sys.stderr)


def take_screenshot(options: StartOptions, out: Path, size: tuple[int, int], keys: str = "",
                    overlay: bool = False) -> Path:
    """Renders the starting scene after `keys` into the picture `out`; ViewerError on bad input."""
    presses = parse_key_sequence(keys)
    check_output(out, [*options.models, options.texture, options.scene_file, *(press.path for press in presses)])
    frontend = OffscreenFrontend()
    scene = starting_scene(options, frontend.notice)
    check_output(out, [scene.texture_path])
    ctx = create_offscreen_context()
    try:
        renderer = Renderer(ctx)
        viewer = Viewer(scene, frontend, strict=True, frame_size=lambda: size)
        viewer.start(options, renderer.max_texture_side)
        inputs = InputsGuard(out)
        inputs.check(viewer)
        for _ in frontend.replay(viewer, presses):
            inputs.check(viewer)  # a model loaded by a key brings its MTL and textures
        write_picture(render_pixels(ctx, renderer, viewer, size, overlay), out)
    finally:
        ctx.release()
    return out


def render_pixels(ctx: moderngl.Context, renderer: Renderer, viewer: Viewer, size: tuple[int, int],
                  overlay: bool) -> np.ndarray:
    """The viewer's scene drawn into a fresh framebuffer of `size`: (height, width, 3) uint8, top row first."""
    with offscreen_framebuffer(ctx, size) as fbo:
        render(ctx, renderer, viewer, fbo, size, overlay)
        return read_pixels(fbo, size)


def render(ctx: moderngl.Context, renderer: Renderer, viewer: Viewer, fbo: moderngl.Framebuffer,
           size: tuple[int, int], overlay: bool) -> None:
    renderer.render(viewer.scene, fbo, size)
    if overlay:
        # The overlay's text imports moderngl-window, which is slow to import: only when asked for.
        from marraztu.render.overlay import Overlay
        from marraztu.text import panels, status

        drawer = Overlay(ctx)
        try:
            drawer.draw(*status.overlay_lines(viewer), size, panels.extras(viewer.scene, size))
        finally:
            drawer.release()  # made per picture: an API loop must not leak its GL objects


def check_output(out: Path, inputs: Iterable[str | Path | None] = (),
                 formats: Mapping[str, str] = IMAGE_FORMATS, what: str = "a picture") -> None:
    """Refuses, in one line, a file that cannot be written where asked, or would replace an input."""
    if formats.get(out.suffix.lower()) is None:
        raise ViewerError(f"{out}: write {what} as {', '.join(formats)}")
    try:
        if out.is_dir():
            raise ViewerError(f"{out}: is a folder, not a file")
        if out.exists() and not out.is_symlink() and not out.is_file():
            raise ViewerError(f"{out}: is not a regular file (a pipe or a device?)")
        folder = next((above for above in out.parents if above.exists()), None)  # made when it is written
        if folder is not None and not folder.is_dir():
            raise ViewerError(f"{out}: {folder} is not a folder")
        if folder is not None:  # tried before anything is drawn: a large picture takes seconds
            handle, name = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".part", dir=folder)
            os.close(handle)
            os.unlink(name)
        if not out.exists():
            return
    except OSError as error:  # a name too long, a folder it may not look into or write in
        raise ViewerError(f"{out}: cannot write here ({error.strerror or error})") from None
    for given in inputs:
        if given is not None and _same_file(out, Path(given)):
            raise ViewerError(f"{out}: is an input of this {what.split()[-1]} ({given}); write it elsewhere")


def _same_file(out: Path, given: Path) -> bool:
    """Whether `given` is the file `out` names; an input that cannot be looked at is not (reading it
    will say why)."""
    try:
        return given.exists() and os.path.samefile(out, given)
    except OSError:
        return False


def files_read(scene: Scene) -> dict[Path, None]:
    """Every file the scene's elements were read from, in order: each model and the files read beside it
    (an OBJ's MTL and its textures, a glTF's buffers and pictures)."""
    return {path: None for element in (*scene.objects, *scene.cameras)
            for path in (element.source, *element.mesh.read_beside) if path is not None}


class InputsGuard:
    """Refuses `out` when it is a file the scene was read from; each file is looked at once, and the
    scene's files again only after a load (a key that loads nothing costs nothing here)."""

    def __init__(self, out: Path, formats: Mapping[str, str] = IMAGE_FORMATS, what: str = "a picture") -> None:
        self.out, self.formats, self.what = out, formats, what
        self.checked: set[Path] = set()  # found to be other files than `out` already
        self.loads_seen = -1  # the scene's load count when last looked at

    def check(self, viewer: Viewer) -> None:
        if viewer.scene.loads == self.loads_seen:
            return
        self.loads_seen = viewer.scene.loads
        new = [path for path in files_read(viewer.scene) if path not in self.checked]
        if new:
            check_output(self.out, new, self.formats, self.what)
            self.checked.update(new)


def write_picture(pixels: np.ndarray, out: Path) -> None:
    """The picture, in the format of its suffix (zlib level 1 for PNG: written once, and soon)."""
    check_output(out)
    image_format = IMAGE_FORMATS[out.suffix.lower()]
    options = {"compress_level": 1} if image_format == "PNG" else {"quality": 95}
    write_atomically(out, lambda temporary: picture_of(pixels).save(temporary, format=image_format, **options))


def picture_of(pixels: np.ndarray) -> Image.Image:
    """Pillow's picture of (H, W, 3) uint8. Rows read_pixels turned upside down in a view are put upright
    by Pillow's decoder, which fromarray would first copy whole (a large picture's size once more)."""
    stored = pixels[::-1]
    if pixels.ndim != 3 or not stored.flags.c_contiguous:
        return Image.fromarray(pixels)
    height, width = pixels.shape[:2]
    return Image.frombuffer("RGB", (width, height), stored, "raw", "RGB", 0, -1)


def write_atomically(out: Path, write: Callable[[Path], None]) -> None:
    """`write` fills a temporary file beside `out`, which is then renamed into place: the file is
    written whole or not at all, and an older one survives a failure."""
    folder = out.parent
    made = [above for above in (folder, *folder.parents) if not above.exists()]  # taken away again on failure
    try:
        folder.mkdir(parents=True, exist_ok=True)
        handle, name = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".part", dir=folder)
        os.close(handle)
    except OSError as error:
        _remove_folders(made)
        raise ViewerError(f"{out}: cannot write here ({error.strerror or error})") from None
    temporary = Path(name)
    try:
        write(temporary)
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(temporary, 0o666 & ~mask)  # mkstemp makes it private; a picture is not
        os.replace(temporary, out)
    except BaseException as error:  # a write that failed, or was interrupted: nothing of it is left
        temporary.unlink(missing_ok=True)
        _remove_folders(made)
        if isinstance(error, OSError):
            raise ViewerError(f"{out}: cannot write it ({error.strerror or error})") from None
        raise


def _remove_folders(made: list[Path]) -> None:
    """The folders a failed write made for its file, deepest first, where still empty."""
    for folder in made:
        try:
            folder.rmdir()
        except OSError:
            return
