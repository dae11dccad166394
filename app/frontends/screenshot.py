"""`marraztu screenshot`: the scene rendered offscreen (EGL, no display needed), keys replayed first.

Same viewer, key map and renderer as the window; only the framebuffer differs.
"""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

import moderngl
import numpy as np
from PIL import Image

from marraztu.control.keymap import parse_key_sequence
from marraztu.control.viewer import StartOptions, Viewer, starting_scene
from marraztu.errors import ViewerError
from marraztu.loaders.images import load_image
from marraztu.render.context import create_offscreen_context
from marraztu.render.renderer import Renderer

# Pillow's format for each suffix a picture may be written as.
IMAGE_FORMATS = {".png": "PNG", ".jpg": "JPEG", ".jpeg": "JPEG"}


class OffscreenFrontend:
    """ESC ends the replay; the -o file is the screenshot."""

    def __init__(self) -> None:
        self.quitting = False

    def quit(self) -> None:
        self.quitting = True

    def save_screenshot(self) -> None:
        pass


def take_screenshot(options: StartOptions, out: Path, size: tuple[int, int], keys: str = "",
                    overlay: bool = False) -> Path:
    """Renders the starting scene after `keys` into the picture `out`; ViewerError on bad input."""
    presses = parse_key_sequence(keys)
    check_output(out)
    scene = starting_scene(options)
    ctx = create_offscreen_context()
    try:
        viewer = Viewer(scene, OffscreenFrontend(), strict=True)
        if options.texture is not None:
            # Asked for by name: a bad one ends the command with its LoadError, no fallback.
            scene.texture = load_image(options.texture)
        else:
            message = viewer.use_texture(Path(scene.texture_path) if scene.texture_path else None)
            if message:
                print(message, file=sys.stderr)
        for model in options.models:
            viewer.load_model(model)
        for press in presses:
            if viewer.frontend.quitting:
                break
            viewer.press(press)
        fbo = ctx.simple_framebuffer(size, components=4)
        try:
            render(ctx, viewer, fbo, size, overlay)
            write_picture(read_pixels(fbo, size), out)
        finally:
            release_framebuffer(fbo)
    finally:
        ctx.release()
    return out


def render(ctx: moderngl.Context, viewer: Viewer, fbo: moderngl.Framebuffer, size: tuple[int, int],
           overlay: bool) -> None:
    Renderer(ctx).render(viewer.scene, fbo, size)
    if overlay:
        # The overlay's text imports moderngl-window: a tenth of a second, only when asked for.
        from marraztu.render.overlay import Overlay
        from marraztu.text import panels, status

        Overlay(ctx).draw(*status.overlay_lines(viewer), size, panels.extras(viewer.scene, size))


def read_pixels(fbo: moderngl.Framebuffer, size: tuple[int, int]) -> np.ndarray:
    """(H, W, 3) uint8, top row first."""
    width, height = size
    pixels = np.frombuffer(fbo.read(components=3, alignment=1), np.uint8).reshape(height, width, 3)
    return np.flipud(pixels)


def release_framebuffer(fbo: moderngl.Framebuffer) -> None:
    """moderngl's Framebuffer.release leaves its attachments alive: release them too."""
    attachments = [*fbo.color_attachments, fbo.depth_attachment]
    fbo.release()
    for attachment in attachments:
        if attachment is not None:
            attachment.release()


def check_output(out: Path) -> None:
    """Refuses, in one line, a picture that cannot be written where asked."""
    if IMAGE_FORMATS.get(out.suffix.lower()) is None:
        raise ViewerError(f"{out}: write a picture as {', '.join(IMAGE_FORMATS)}")
    if out.is_dir():
        raise ViewerError(f"{out}: is a folder, not a picture file")


def write_picture(pixels: np.ndarray, out: Path) -> None:
    """The picture, in the format of its suffix, written whole or not at all: into a temporary file
    beside it, then renamed into place."""
    check_output(out)
    folder = out.parent
    try:
        folder.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(prefix=f".{out.name}.", suffix=".part", dir=folder)
    except OSError as error:
        raise ViewerError(f"{out}: cannot write here ({error.strerror or error})") from None
    try:
        with os.fdopen(handle, "wb") as stream:
            # zlib level 1: a screenshot is written once, and soon.
            options = {"compress_level": 1} if IMAGE_FORMATS[out.suffix.lower()] == "PNG" else {"quality": 95}
            Image.fromarray(pixels).save(stream, format=IMAGE_FORMATS[out.suffix.lower()], **options)
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(temporary, 0o666 & ~mask)  # mkstemp makes it private; a picture is not
        os.replace(temporary, out)
    except OSError as error:
        Path(temporary).unlink(missing_ok=True)
        raise ViewerError(f"{out}: cannot write the picture ({error.strerror or error})") from None
