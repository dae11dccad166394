"""`python -m app screenshot`: the scene rendered offscreen through EGL, keys replayed first.

Same key map, same renderer as the window; only the framebuffer differs. No display is needed.
"""

from __future__ import annotations

import sys
from pathlib import Path

import moderngl
import numpy as np
from PIL import Image

from app.errors import ViewerError
from app.keymap import parse_key_sequence
from app.loaders.image import load_image
from app.renderer import Renderer
from app.viewer import StartOptions, Viewer, starting_scene


class OffscreenFrontend:
    """ESC ends the replay; the window-only actions become messages."""

    def __init__(self) -> None:
        self.quitting = False

    def quit(self) -> None:
        self.quitting = True

    def open_file_prompt(self) -> None:
        raise ViewerError("`f` opens a prompt in the window; in --keys use f=PATH")

    def save_screenshot(self) -> None:
        pass  # the -o file is the screenshot


def create_context() -> moderngl.Context:
    try:
        return moderngl.create_standalone_context(backend="egl")
    except Exception as error:  # glcontext raises plain Exception subclasses of its own
        raise ViewerError(f"cannot create an offscreen OpenGL context through EGL: {error}") from error


def take_screenshot(options: StartOptions, out: Path, size: tuple[int, int], keys: str = "",
                    overlay: bool = False) -> Path:
    """Renders the starting scene after `keys` into the PNG `out`; raises ViewerError on bad input."""
    scene = starting_scene(options)
    ctx = create_context()
    try:
        return _render(ctx, scene, options, out, size, keys, overlay)
    finally:
        ctx.release()


def _render(ctx: moderngl.Context, scene, options: StartOptions, out: Path, size: tuple[int, int],
            keys: str, overlay: bool) -> Path:
    frontend = OffscreenFrontend()
    viewer = Viewer(scene, Renderer(ctx), frontend, strict=True)
    if options.texture is not None:
        # Asked for by name: a bad one ends the command with its LoadError, no fallback.
        viewer.renderer.set_texture(load_image(options.texture))
    else:
        message = viewer.use_texture(Path(scene.texture_path) if scene.texture_path else None)
        if message:
            print(message, file=sys.stderr)
    for model in options.models:
        viewer.load_model(model)
    for key in parse_key_sequence(keys):
        if frontend.quitting:
            break
        viewer.press(key)
    fbo = ctx.simple_framebuffer(size, components=4)
    fbo.use()
    viewer.renderer.render(scene, fbo, size)
    if overlay:
        from app import panels
        from app.overlay import Overlay  # moderngl-window's text: 0.1 s of imports, only when asked

        Overlay(ctx).draw(*viewer.overlay_lines(), size, panels.extras(scene, size))
    out.parent.mkdir(parents=True, exist_ok=True)
    write_png(fbo, size, out)
    return out


def write_png(fbo: moderngl.Framebuffer, size: tuple[int, int], out: Path) -> None:
    """The framebuffer as an RGB PNG, top row first: the screenshot command's file and the window's
    F12 file, written the same way.

    moderngl_window.screenshot.create does the same, but importing moderngl-window (for this one
    call) costs the command about 0.1 s of its 0.3 s start; Pillow is already loaded for textures.
    """
    width, height = size
    pixels = np.frombuffer(fbo.read(components=3, alignment=1), np.uint8).reshape(height, width, 3)
    # Level 1 of zlib's 9: a third of the default's time (9 ms against 27 at 800x800) for files a
    # third larger; a screenshot is written once, and soon.
    Image.fromarray(np.flipud(pixels)).save(out, format="PNG", compress_level=1)
