"""The window: a moderngl-window `WindowConfig` (pyglet) that owns the viewer and turns events into
key presses. It holds no rendering logic: the renderer draws the scene, the overlay draws text.
"""

from __future__ import annotations

import logging
from datetime import datetime
from pathlib import Path
from time import perf_counter, sleep
from typing import Any

import moderngl_window as mglw

from app import commands, panels
from app.cli import add_scene_arguments, start_options
from app.keymap import KeyPress
from app.overlay import Overlay
from app.renderer import Renderer
from app.screenshot import write_png
from app.viewer import BackgroundLoader, Viewer, starting_scene

SCREENSHOT_DIR = Path("screenshots")
# While a model loads on the worker thread, frames are paced to at most this rate: keys are still
# answered within a frame, and the cores that llvmpipe would spend redrawing an unchanged picture as
# fast as it can (no display paces it under Xvfb, nor where vsync is off) go to the loader instead.
LOADING_FRAMES_PER_SECOND = 30


class ViewerWindow(mglw.WindowConfig):
    title = "marraztu"
    gl_version = (3, 3)
    window_size = (800, 800)
    aspect_ratio = None  # the projection follows the window's shape instead of letterboxing it
    resizable = True
    clear_color = None  # the renderer clears
    samples = 0  # the same pixels as the offscreen screenshot command
    log_level = logging.WARNING

    @classmethod
    def add_arguments(cls, parser: Any) -> None:
        add_scene_arguments(parser)

    def __init__(self, **kwargs: Any) -> None:
        super().__init__(**kwargs)
        self.wnd.exit_key = None  # ESC belongs to the key map: it also cancels the file prompt
        options = start_options(self.argv)
        self.viewer = Viewer(starting_scene(options), Renderer(self.ctx), self,
                             background=BackgroundLoader())
        self.viewer.use_texture(options.texture or _as_path(self.viewer.scene.texture_path))
        for model in options.models:
            self.viewer.load_model(model)
        self.overlay = Overlay(self.ctx)
        self.prompt: str | None = None  # the `f` prompt's text while it is open
        self.named_keys = self._named_keys()
        self.last_frame_start = perf_counter()

    def _named_keys(self) -> dict[Any, str]:
        keys = self.wnd.keys
        names = {keys.TAB: "TAB", keys.ENTER: "ENTER", keys.ESCAPE: "ESC", keys.DELETE: "DELETE",
                 keys.F1: "F1", keys.F12: "F12", keys.BACKSPACE: "BACKSPACE"}
        try:  # moderngl-window maps ENTER to pyglet's keypad Enter; the main Enter is RETURN
            from pyglet.window import key as pyglet_key

            names[pyglet_key.RETURN] = "ENTER"
        except ImportError:
            pass
        return names

    @property
    def scene(self):
        return self.viewer.scene

    # --- drawing -------------------------------------------------------------------------------
    def on_render(self, time: float, frame_time: float) -> None:
        self._pace_while_loading()
        self.viewer.collect_loads()
        size = self.wnd.buffer_size
        self.wnd.fbo.use()
        self.viewer.renderer.render(self.scene, self.wnd.fbo, size)
        self.overlay.draw(*self.viewer.overlay_lines(self.prompt), size, panels.extras(self.scene, size))

    def _pace_while_loading(self) -> None:
        if self.viewer.background is not None and self.viewer.background.pending():
            wait = self.last_frame_start + 1.0 / LOADING_FRAMES_PER_SECOND - perf_counter()
            if wait > 0:
                sleep(wait)
        self.last_frame_start = perf_counter()

    # --- keys ----------------------------------------------------------------------------------
    def on_unicode_char_entered(self, char: str) -> None:
        """Letters come from text input so that `F` is shift+f on any keyboard layout (SPEC 6)."""
        if not char.isprintable():
            return
        if self.prompt is not None:
            self.prompt += char
        elif not char.isspace():
            self.viewer.press(KeyPress(char))

    def on_key_event(self, key: Any, action: Any, modifiers: Any) -> None:
        if action != self.wnd.keys.ACTION_PRESS:
            return
        name = self.named_keys.get(key)
        if name is None:
            return
        if self.prompt is not None:
            self._prompt_key(name)
        elif name != "BACKSPACE":
            self.viewer.press(KeyPress(name))

    def _prompt_key(self, name: str) -> None:
        if name == "ESC":
            self.prompt = None
            self.scene.message = "loading cancelled"
        elif name == "ENTER":
            path, self.prompt = self.prompt.strip(), None
            if path:
                self.viewer.load_model(Path(path).expanduser())
        elif name == "BACKSPACE":
            self.prompt = self.prompt[:-1]

    # --- mouse and files ----------------------------------------------------------------------
    def on_mouse_drag_event(self, x: int, y: int, dx: int, dy: int) -> None:
        commands.drag(self.scene, dx, dy)

    def on_mouse_scroll_event(self, x_offset: float, y_offset: float) -> None:
        commands.wheel(self.scene, y_offset)

    def on_files_dropped_event(self, x: int, y: int, paths: list[str | Path]) -> None:
        for path in paths:
            self.viewer.load_model(path)

    # --- Frontend ------------------------------------------------------------------------------
    def quit(self) -> None:
        if self.viewer.background is not None:
            self.viewer.background.shutdown()
        self.wnd.close()

    def open_file_prompt(self) -> None:
        self.prompt = ""

    def save_screenshot(self) -> None:
        """F12: the scene as the screenshot command would draw it (no overlay), at the window's size."""
        size = self.wnd.buffer_size
        fbo = self.ctx.simple_framebuffer(size, components=4)
        try:
            fbo.use()
            self.viewer.renderer.render(self.scene, fbo, size)
            SCREENSHOT_DIR.mkdir(exist_ok=True)
            path = (SCREENSHOT_DIR / f"marraztu-{datetime.now():%Y%m%d-%H%M%S-%f}.png").resolve()
            write_png(fbo, size, path)
            self.scene.message = f"screenshot saved to {path}"
        finally:
            fbo.release()
            self.wnd.fbo.use()


def _as_path(value: str | None) -> Path | None:
    return Path(value) if value else None


def run(argv: list[str]) -> int:
    mglw.run_window_config(ViewerWindow, args=argv)
    return 0
