"""The window: a moderngl-window pyglet window whose events become the viewer's key presses. It holds
no drawing logic: the renderer draws the scene, the overlay draws the text."""

from __future__ import annotations

import functools
import logging
import os
import signal
import socket
import sys
import threading
from collections.abc import Callable, Iterator
from contextlib import ExitStack, contextmanager
from datetime import datetime
from enum import Enum
from pathlib import Path
from time import perf_counter
from typing import Any
from urllib.parse import unquote_to_bytes, urlsplit

import moderngl_window as mglw
import numpy as np
from moderngl_window.timers.clock import Timer

from marraztu.control import commands
from marraztu.control.keymap import CLICK_TRAVEL_PX, KeyPress, click
from marraztu.control.viewer import BackgroundLoader, StartOptions, Viewer, scene_file_watcher, starting_scene
from marraztu.errors import LoadError, ViewerError, escaped, first_line
from marraztu.frontends.heap import return_freed_memory
from marraztu.frontends.record import MAX_RECORDING_BYTES, BackgroundSaves
from marraztu.frontends.screenshot import write_picture
from marraztu.model.mesh import counted
from marraztu.render.context import offscreen_framebuffer, read_pixels
from marraztu.render.gpu import prepare_surface
from marraztu.render.overlay import Overlay
from marraztu.render.renderer import Renderer
from marraztu.text import panels, status

TITLE = "marraztu"
SCREENSHOT_DIR = Path("screenshots")
RECORDING_DIR = Path("recordings")
RECORDING_FPS = 10  # a frame per change, not per tick: a slow, readable pace for slides
WATCH_INTERVAL_S = 0.5  # --watch looks at the models' files this often: soon enough after a save
# A frame is drawn only when something changed; between frames the loop sleeps in the window
# system's event wait, waking at least this often for what no event announces (a load finishing).
IDLE_WAKE_S = 0.1
LEFT_BUTTON = 1  # moderngl-window's number of the left button


class Unchanged(Enum):
    """What a handler returns when its event left the scene as it was; None: it may have changed it."""

    NOTHING = "nothing"  # no new picture at all (a key released)
    SCENE = "scene"  # only the text over the scene changed: the frame copies the held picture


# Named keys whose repeats, while held down, come as text (here) or as a text motion (repeated_motions),
# not as presses.
_REPEATED_TEXT = {"\r": "ENTER", "\t": "TAB"}


# pyglet 2.1's X11 window's state of a drag, which an XdndEnter sets and its later messages read.
_PYGLET_DRAG_STATE = ("_xdnd_source", "_xdnd_version", "_xdnd_format")


def uri_list_lines(text: str) -> list[str]:
    """An X11 drop's text/uri-list (RFC 2483: lines end CRLF) as its lines, which dropped_files reads."""
    return [line.removesuffix("\r") for line in text.split("\n")]


def dropped_files(entries: list[str | Path]) -> tuple[list[str | Path], list[str]]:
    """The local paths among a drop's entries, and the URIs of what is not on this computer. An entry is
    a line of an X11 text/uri-list, or a path that another system gives."""
    local_hosts = ("", "localhost", socket.gethostname().lower())  # RFC 8089: a file URI's own host
    paths: list[str | Path] = []
    remote: list[str] = []
    for entry in entries:
        if isinstance(entry, str) and (not entry or entry.startswith("#")):
            continue  # a blank line, or a comment
        try:
            uri = urlsplit(str(entry))
        except ValueError:  # "http://[": no address, and no path either
            remote.append(str(entry))
            continue
        if isinstance(entry, Path) or len(uri.scheme) < 2:  # a path as given (a drive letter is no scheme)
            paths.append(entry)
        elif uri.scheme.lower() == "file" and uri.netloc.lower() in local_hosts:
            paths.append(os.fsdecode(unquote_to_bytes(uri.path)))  # %FF is a name's byte, not UTF-8
        else:
            remote.append(entry)
    return paths, remote


def guarded(handler: Callable[..., Unchanged | None], after_failure: Unchanged | None = None
            ) -> Callable[..., None]:
    """A window event must never end the session: a failure becomes one line on screen and on stderr
    (once, however often it comes again in a row), and the window goes on. An event asks for a frame,
    which draws the scene again, unless the handler says what it left unchanged; after a failure,
    unless `after_failure` says so (a failed drawing must not ask for itself again, in a loop)."""

    @functools.wraps(handler)
    def run(window: ViewerWindow, *args: Any) -> None:
        unchanged = None
        try:
            unchanged = handler(window, *args)
        except Exception as error:  # what no check foresaw: said, not fatal
            line = escaped(f"{handler.__name__.removeprefix('on_')} failed: {type(error).__name__}: {error}")
            window.scene.message = line
            if line != window.last_failure:
                print(line, file=sys.stderr)
            window.last_failure, unchanged = line, after_failure
        if unchanged is not Unchanged.NOTHING:
            window.needs_frame = True
        if unchanged is None:
            window.scene_changed = True

    return run


class HeldPicture:
    """The scene's last picture, kept offscreen: a frame that changes only the text over it (the
    loading line moving on, a dropped file's message, the `f` prompt's typing) copies it instead of
    drawing a large scene again, which would take the loader's cores or keep a key waiting."""

    def __init__(self, ctx: Any) -> None:
        self.ctx = ctx
        self.size: tuple[int, int] | None = None
        self.holds_picture = False
        self._framebuffer: ExitStack | None = None
        self._fbo: Any = None

    def framebuffer(self, size: tuple[int, int]) -> Any:
        if self._fbo is None or self.size != tuple(size):
            self.release()
            self._framebuffer = ExitStack()
            self._fbo = self._framebuffer.enter_context(offscreen_framebuffer(self.ctx, tuple(size)))
            self.size = tuple(size)
        return self._fbo

    def release(self) -> None:
        if self._framebuffer is not None:
            self._framebuffer.close()
        self._framebuffer = self._fbo = self.size = None
        self.holds_picture = False


class ViewerWindow:
    """One window on one viewer: pyglet's events in, the renderer's frames out."""

    def __init__(self, options: StartOptions, size: tuple[int, int]) -> None:
        logging.getLogger("moderngl_window").setLevel(logging.WARNING)
        with _signals_end_the_process():  # pyglet's import makes its hidden window, then ours is made
            window_class = mglw.get_local_window_cls("pyglet")
            # samples=0: the same pixels as the offscreen screenshot command; no aspect ratio: the
            # projection follows the window's shape instead of letterboxing it.
            self.wnd = window_class(title=TITLE, size=size, resizable=True, gl_version=(3, 3), aspect_ratio=None,
                                    vsync=True, samples=0)
        self.wnd.swap_buffers()  # some platforms report the true buffer size only after one swap
        self.wnd.set_default_viewport()
        self.ctx = self.wnd.ctx
        self.wnd.exit_key = None  # ESC belongs to the key map: it also cancels the file prompt
        self.last_failure = ""  # the last failure said on stderr: a repeat is not said again
        self.text_of_press: str | None = None  # a named key just pressed, whose own text or motion comes next
        self.renderer = Renderer(self.ctx)
        loader = BackgroundLoader(prepare_surface, wake=_wake_event_loop)
        scene_watcher = scene_file_watcher(options)  # before the read: a save while its models load is news
        self.viewer = Viewer(starting_scene(options, self.notice), self, background=loader,
                             frame_size=lambda: self.wnd.buffer_size)
        self.viewer.start(options, self.renderer.max_texture_side, scene_watcher)
        self.overlay = Overlay(self.ctx)
        self.named_keys, self.repeated_motions = self._named_keys()
        self.last_watch_check = perf_counter()
        self.needs_frame = True
        self.drawn_since_still = False  # frames since the window was last still: it then returns what they freed
        self.scene_changed = True  # by an event since the last frame (guarded)
        self.drawn_loading_lines: list[str] = []  # the loading lines of the last frame
        self.held_scene = HeldPicture(self.ctx)
        self.recording: list[np.ndarray] | None = None  # F9: the pictures drawn since it was pressed
        self.recording_bytes = 0  # theirs, counted as they come: not summed again with every frame
        self.saves = BackgroundSaves(wake=_wake_event_loop)  # F9 again: the recording written meanwhile
        self.click_travel: int | None = None  # how far the pointer went since a left press (None: no left press)
        self.held_motion: tuple[int, int] = (0, 0)  # a left drag's motion while it may still be a click
        self._connect_events()
        self._close_when_destroyed()
        self._take_drag_messages()

    def _connect_events(self) -> None:
        wnd = self.wnd
        wnd.render_func = self.on_render
        wnd.key_event_func = self.on_key_event
        wnd.unicode_char_entered_func = self.on_unicode_char_entered
        wnd.mouse_drag_event_func = self.on_mouse_drag_event
        wnd.mouse_scroll_event_func = self.on_mouse_scroll_event
        wnd.mouse_press_event_func = self.on_mouse_press_event
        wnd.mouse_release_event_func = self.on_mouse_release_event
        wnd.files_dropped_event_func = self.on_files_dropped_event
        wnd.resize_func = self.on_resize
        pyglet_window = getattr(wnd, "_window", None)
        if pyglet_window is not None:  # uncovered after being hidden: the window system lost the picture
            pyglet_window.push_handlers(on_expose=self.on_expose, on_text_motion=self.on_text_motion)

    def _close_when_destroyed(self) -> None:
        """Without a window manager, `xdotool windowclose` destroys the X window outright and no close
        event comes: pyglet would go on drawing into nothing. Its DestroyNotify ends the loop instead."""
        handlers = getattr(getattr(self.wnd, "_window", None), "_event_handlers", None)
        try:
            from pyglet.libs.x11 import xlib
        except ImportError:  # not X11: the window system sends a close event
            return
        if isinstance(handlers, dict):
            handlers[xlib.DestroyNotify] = lambda event: self.wnd.close()

    def _take_drag_messages(self) -> None:
        """X11's drag and drop comes as client messages that pyglet (2.1) reads, and one it did not
        foresee raised out of its event loop, ending the program: an XdndEnter listing its types itself
        (as a source of at most three types does), read as a pointer, or an XdndPosition before any
        XdndEnter. The window reads the first kind itself, and guards pyglet's reading of the others; and
        it reads the dropped list of files itself (dropped_files), guarding pyglet's decoding of it."""
        pyglet_window = getattr(self.wnd, "_window", None)
        handlers = getattr(pyglet_window, "_event_handlers", None)
        try:
            from pyglet.libs.x11 import xlib
        except ImportError:  # not X11
            return
        atoms = getattr(pyglet_window, "_xdnd_atoms", None)
        # only where this pyglet keeps the drag as on_client_message reads and writes it: another leaves pyglet's own
        if (isinstance(handlers, dict) and xlib.ClientMessage in handlers and isinstance(atoms, dict)
                and {"XdndEnter", "text/uri-list"} <= atoms.keys()
                and all(hasattr(pyglet_window, name) for name in _PYGLET_DRAG_STATE)):
            self.pyglet_client_message = handlers[xlib.ClientMessage]
            handlers[xlib.ClientMessage] = self.on_client_message
        if (isinstance(handlers, dict) and xlib.SelectionNotify in handlers
                and hasattr(pyglet_window, "parse_filenames")):
            # pyglet read a URI list's comment as the path "" and a web address as a local path
            pyglet_window.parse_filenames = uri_list_lines
            self.pyglet_selection_notify = handlers[xlib.SelectionNotify]
            handlers[xlib.SelectionNotify] = self.on_selection_notify

    def _named_keys(self) -> tuple[dict[Any, str], dict[int, str]]:
        """The key map's names of the window's keys, and of the text motions that repeat them."""
        keys = self.wnd.keys
        names = {keys.TAB: "TAB", keys.ENTER: "ENTER", keys.ESCAPE: "ESC", keys.DELETE: "DELETE",
                 keys.F1: "F1", keys.F9: "F9", keys.F12: "F12", keys.BACKSPACE: "BACKSPACE",
                 keys.PAGE_DOWN: "PAGEDOWN", keys.PAGE_UP: "PAGEUP", keys.HOME: "HOME"}
        from pyglet.window import key as pyglet_key

        # The keypad's keys do what the main ones do (its Enter confirms the file prompt).
        names.update({pyglet_key.RETURN: "ENTER", pyglet_key.NUM_ENTER: "ENTER", pyglet_key.NUM_TAB: "TAB",
                      pyglet_key.NUM_DELETE: "DELETE", pyglet_key.NUM_HOME: "HOME",
                      pyglet_key.NUM_PAGE_DOWN: "PAGEDOWN", pyglet_key.NUM_PAGE_UP: "PAGEUP"})
        motions = {pyglet_key.MOTION_BACKSPACE: "BACKSPACE", pyglet_key.MOTION_DELETE: "DELETE",
                   pyglet_key.MOTION_NEXT_PAGE: "PAGEDOWN", pyglet_key.MOTION_PREVIOUS_PAGE: "PAGEUP"}
        return names, motions

    @property
    def scene(self):
        return self.viewer.scene

    def run(self) -> None:
        try:
            self._draw_until_closed()
        finally:  # after ESC, Ctrl-C or kill: a GIF that F9 asked for is finished, and said where it went
            for message in self.saves.close():
                self.notice(message)

    def _draw_until_closed(self) -> None:
        timer = Timer()
        timer.start()
        while not self.wnd.is_closing:
            self._check_watched_files()
            self._say_finished_saves()
            if not (self.needs_frame or self._loading_changed()):
                # Still now: what those frames freed goes back to the system. Not while a file loads:
                # the loader would take the same memory back, page by page, and wait for the trim's lock.
                if self.drawn_since_still and not self.drawn_loading_lines:
                    return_freed_memory()
                    self.drawn_since_still = False
                self._wait_for_events(IDLE_WAKE_S)
                continue
            self.drawn_since_still = True
            now, delta = timer.next_frame()
            self.wnd.use()
            self.wnd.render(now, delta)
            if not self.wnd.is_closing:
                self.wnd.swap_buffers()  # also dispatches the events that came meanwhile
        self.held_scene.release()
        if self.viewer.background is not None:
            self.viewer.background.shutdown()
        self.wnd.destroy()

    # --- drawing -------------------------------------------------------------------------------
    @functools.partial(guarded, after_failure=Unchanged.NOTHING)
    def on_render(self, time: float, frame_time: float) -> Unchanged:
        # No event that changed the scene and no finished load: only the text over it changed.
        scene_unchanged = not self.scene_changed and not self.viewer.background.finished()
        self.scene_changed = self.needs_frame = False
        self.viewer.collect_loads()
        self.drawn_loading_lines = self.viewer.loading_lines()
        size = self.wnd.buffer_size
        held = self.held_scene.framebuffer(size)  # a new size starts with no picture
        if not (scene_unchanged and self.held_scene.holds_picture):
            self.renderer.render(self.scene, held, size)
            self.held_scene.holds_picture = True
        self.ctx.copy_framebuffer(self.wnd.fbo, held)
        self.wnd.fbo.use()
        if self.recording is not None and not scene_unchanged:
            self._record_frame(size)
        self.overlay.draw(*status.overlay_lines(self.viewer), size, panels.extras(self.scene, size))
        return Unchanged.NOTHING  # drawing asks for no other picture

    def _record_frame(self, size: tuple[int, int]) -> None:
        """The scene's picture, before the overlay: the frames `marraztu record` would draw."""
        assert self.recording is not None
        self.recording.append(read_pixels(self.wnd.fbo, size))
        self.recording_bytes += self.recording[-1].nbytes
        if self.recording_bytes + self.saves.held_bytes() > MAX_RECORDING_BYTES:
            self.toggle_recording()
            self.scene.message += " (stopped: the frames filled the memory a recording may take)"

    def _loading_changed(self) -> bool:
        """A load finished, or its status line moved on (it counts seconds): worth a frame."""
        background = self.viewer.background
        if background is None or not (background.uncollected() or self.drawn_loading_lines):
            return False
        return bool(background.finished()) or self.viewer.loading_lines() != self.drawn_loading_lines

    def _wait_for_events(self, timeout: float) -> None:
        """Sleeps in the window system's own wait until an event comes or `timeout` passes, then
        dispatches what came: no frames, and no CPU, while nothing happens."""
        import pyglet.app

        pyglet.app.platform_event_loop.step(timeout)
        window = self.wnd._window
        window.dispatch_pending_events()  # what the wait queued: it may be ESC, closing the window
        if not self.wnd.is_closing:
            window.dispatch_events()

    def _check_watched_files(self) -> None:
        if perf_counter() - self.last_watch_check >= WATCH_INTERVAL_S:  # a stat per file, not per frame
            self.last_watch_check = perf_counter()
            self.viewer.check_watched()

    @guarded
    def on_resize(self, width: int, height: int) -> None:
        """A new size needs a new frame; guarded asks for it."""

    @guarded
    def on_expose(self) -> Unchanged:
        """The window system lost the window's picture; the scene's held one is still good."""
        return Unchanged.SCENE

    # --- keys ----------------------------------------------------------------------------------
    @guarded
    def on_unicode_char_entered(self, char: str) -> Unchanged | None:
        """Letters come from text input so that `F` is shift+f on any keyboard layout (SPEC 6); Enter's
        and Tab's text, held down, are their repeats."""
        if char in _REPEATED_TEXT:
            return self._repeated(_REPEATED_TEXT[char])
        typed_into_prompt = self.viewer.prompt is not None
        if char.isprintable():
            self.viewer.type_text(char)
        return Unchanged.SCENE if typed_into_prompt else None

    @guarded
    def on_text_motion(self, motion: int) -> Unchanged | None:
        """BackSpace, Delete, PageDown and PageUp held down: pyglet sends their repeats as motions."""
        name = self.repeated_motions.get(motion)
        return Unchanged.NOTHING if name is None else self._repeated(name)

    def _repeated(self, name: str) -> Unchanged | None:
        """A named key's text or motion: the one its own press brings is that press; any other is the
        key held down, repeating (pyglet sends no press for a repeat)."""
        if self.text_of_press == name:
            self.text_of_press = None
            return Unchanged.NOTHING
        return self._named_press(name)

    @guarded
    def on_key_event(self, key: Any, action: Any, modifiers: Any) -> Unchanged | None:
        """Named keys (letters come as text); a release, a modifier or BACKSPACE outside the prompt
        does nothing."""
        name = self.named_keys.get(key)
        if action != self.wnd.keys.ACTION_PRESS or name is None:
            return Unchanged.NOTHING
        self.text_of_press = name  # the text or motion that comes with this press is not a repeat
        return self._named_press(name)

    def _named_press(self, name: str) -> Unchanged | None:
        in_prompt = self.viewer.prompt is not None
        if name == "BACKSPACE" and not in_prompt:
            return Unchanged.NOTHING
        self.viewer.press(KeyPress(name))
        # The prompt takes every key while open, and what Enter asks for loads in the background.
        return Unchanged.SCENE if in_prompt else None

    # --- mouse and files ----------------------------------------------------------------------
    @guarded
    def on_mouse_drag_event(self, x: int, y: int, dx: int, dy: int) -> Unchanged | None:
        """As f3d and MeshLab: left orbits, right (or shift-left) pans; ctrl-drag turns the target. A left
        drag moves nothing until it is no click, then moves as far as the pointer went since the press."""
        if self.click_travel is not None:  # the pointer's path since a left press, there and back both counted
            self.click_travel += max(abs(dx), abs(dy))
            dx, dy = dx + self.held_motion[0], dy + self.held_motion[1]
            if self.click_travel <= CLICK_TRAVEL_PX:  # a hand's shake must not turn the view it clicks in
                self.held_motion = (dx, dy)
                return Unchanged.NOTHING
            self.held_motion = (0, 0)
        buttons, held, size = self.wnd.mouse_states, self.wnd.modifiers, self.wnd.size
        if held.ctrl:
            move = commands.DragMove.TURN_TARGET
        elif buttons.right or buttons.middle or held.shift:
            move = commands.DragMove.PAN
        else:
            move = commands.DragMove.ORBIT
        self.viewer.move_by_mouse(lambda scene: commands.drag_by(scene, move, dx, dy, size))
        return None

    @guarded
    def on_mouse_scroll_event(self, x_offset: float, y_offset: float) -> None:
        self.viewer.move_by_mouse(lambda scene: commands.dolly_view(scene, y_offset))

    @guarded
    def on_mouse_press_event(self, x: int, y: int, button: int) -> Unchanged:
        """A press ends a gesture: the next drag is an undo step of its own (the matrices panel counts them). A
        left one may begin a click."""
        commands.end_view_gesture(self.scene)
        self.click_travel = 0 if button == LEFT_BUTTON else None
        self.held_motion = (0, 0)
        return Unchanged.SCENE

    @guarded
    def on_mouse_release_event(self, x: int, y: int, button: int) -> Unchanged | None:
        """A release ends a gesture too; the left button's, the pointer moved CLICK_TRAVEL_PX or less in all
        since the press (there and back counts both ways), is a click: the object and the face drawn at
        that pixel are selected."""
        commands.end_view_gesture(self.scene)
        clicked = button == LEFT_BUTTON and self.click_travel is not None and self.click_travel <= CLICK_TRAVEL_PX
        self.click_travel = None
        if not clicked:
            return Unchanged.SCENE
        self.viewer.press(click(*self._framebuffer_pixel(x, y)))
        return None

    def _framebuffer_pixel(self, x: float, y: float) -> tuple[int, int]:
        """The framebuffer's pixel (column, row from the top-left) under moderngl-window's mouse point: it
        gives pyglet's y (0 on the bottom row) as height - y, so the top row is 1; and on a HiDPI screen
        the framebuffer has more pixels than the window has points."""
        (width, height), (buffer_width, buffer_height) = self.wnd.size, self.wnd.buffer_size
        column = int(x * buffer_width / max(width, 1))
        row = int((y - 1) * buffer_height / max(height, 1))
        return min(max(column, 0), buffer_width - 1), min(max(row, 0), buffer_height - 1)

    @guarded
    def on_files_dropped_event(self, x: int, y: int, entries: list[str | Path]) -> Unchanged:
        paths, remote = dropped_files(entries)
        for path in paths:
            self.viewer.load_model(path)
        if remote:  # said after the loads' 'loading' lines, which would replace it
            more = f" ({counted(len(remote) - 1, 'other')} not opened either)" if len(remote) > 1 else ""
            self.viewer.tell(f"{LoadError(remote[0], 'only files on this computer can be opened')}{more}")
        return Unchanged.SCENE  # the models load in the background and join the scene at a later frame

    @functools.partial(guarded, after_failure=Unchanged.SCENE)
    def on_client_message(self, event: Any) -> Unchanged:
        """A drag's messages and the window manager's (close, sync): no new picture by themselves."""
        pyglet_window, message = self.wnd._window, event.xclient
        atoms = pyglet_window._xdnd_atoms
        if message.message_type == atoms["XdndEnter"] and not message.data.l[1] & 1:  # bit 0: more types
            pyglet_window._xdnd_source, pyglet_window._xdnd_version = message.data.l[0], message.data.l[1] >> 24
            offered = list(message.data.l[2:5])
            pyglet_window._xdnd_format = atoms["text/uri-list"] if atoms["text/uri-list"] in offered else None
        else:
            self.pyglet_client_message(event)
        return Unchanged.NOTHING

    @functools.partial(guarded, after_failure=Unchanged.SCENE)
    def on_selection_notify(self, event: Any) -> Unchanged:
        """A drop's list of files: pyglet decodes it as UTF-8, and other bytes raised out of its event loop."""
        try:
            self.pyglet_selection_notify(event)
        except UnicodeDecodeError as error:
            self.viewer.tell(f"dropped files not opened: their list is not UTF-8 text (byte {error.start})")
            return Unchanged.SCENE
        return Unchanged.NOTHING  # a drop asks for its own frame

    # --- Frontend ------------------------------------------------------------------------------
    def quit(self) -> None:
        self.wnd.close()

    def notice(self, text: str) -> None:
        print(escaped(text), file=sys.stderr)

    def toggle_recording(self) -> None:
        """F9: from now on every new picture is a frame; F9 again writes them as a GIF."""
        if self.recording is None:
            self.recording, self.recording_bytes = [], 0
            self.scene.message = "recording: every new picture is a frame; F9 again saves them"
            return
        frames, self.recording = self.recording, None
        if len(frames) <= 1:  # the picture F9 found, and none after it
            self.scene.message = "recording stopped: no picture changed, nothing saved"
            return
        path = (RECORDING_DIR / f"marraztu-{datetime.now():%Y%m%d-%H%M%S-%f}.gif").absolute()
        self.saves.save(frames, path, RECORDING_FPS)
        self.scene.message = f"saving the recording of {counted(len(frames), 'frame')}..."

    @guarded
    def _say_finished_saves(self) -> Unchanged:
        finished = self.saves.finished()
        if finished:
            self.scene.message = finished[-1]
        return Unchanged.SCENE if finished else Unchanged.NOTHING

    def save_screenshot(self) -> None:
        """F12: the scene as the screenshot command draws it (no overlay), at the window's size."""
        size = self.wnd.buffer_size
        path = (SCREENSHOT_DIR / f"marraztu-{datetime.now():%Y%m%d-%H%M%S-%f}.png").absolute()
        try:
            with offscreen_framebuffer(self.ctx, size) as fbo:
                self.renderer.render(self.scene, fbo, size)
                write_picture(read_pixels(fbo, size), path)
            self.scene.message = f"screenshot saved to {path}"
        except ViewerError as error:
            self.scene.message = f"screenshot not saved: {error}"
        finally:
            self.wnd.fbo.use()


@contextmanager
def _signals_end_the_process() -> Iterator[None]:
    """Ctrl-C and `kill` end the process outright while pyglet makes the window: it waits in C for the
    window to be mapped, for ever on some displays (a 16-bit Xvfb), and Python's handlers run only
    between bytecodes. Nothing is being written then, and the shell reports the same 130 and 143."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    handled = [number for number in (signal.SIGINT, signal.SIGTERM) if signal.getsignal(number) is not None]
    before = {number: signal.signal(number, signal.SIG_DFL) for number in handled}  # one set in C is left alone
    try:
        yield
    finally:
        for number, handler in before.items():
            signal.signal(number, handler)


def _wake_event_loop() -> None:
    """Ends the loop's wait for events now (safe from any thread): a finished load is drawn at once."""
    import pyglet.app

    pyglet.app.platform_event_loop.notify()


def run_window(options: StartOptions, size: tuple[int, int]) -> int:
    open_window(options, size).run()
    return 0


def open_window(options: StartOptions, size: tuple[int, int]) -> ViewerWindow:
    """The window, or a ViewerError in one line when the display or its OpenGL cannot give one."""
    try:
        return ViewerWindow(options, size)
    except ViewerError:
        raise
    except Exception as error:  # pyglet and the GL driver raise their own kinds, at import time too
        raise ViewerError(f"{_why_no_window(error)}; without a display, `marraztu screenshot -o shot.png` draws "
                          "offscreen") from None


def _why_no_window(error: Exception) -> str:
    """pyglet's words, but where Xlib found no X server to connect to: its 'Cannot connect to "None"'
    names the default it was given, not the display tried."""
    display = os.environ.get("DISPLAY")
    xlib_display = sys.modules.get("pyglet.display.xlib")  # loaded where the failure came from it
    cannot_connect = (xlib_display is not None and isinstance(error, xlib_display.NoSuchDisplayException)
                      and str(error).startswith("Cannot connect"))
    if cannot_connect and display:
        return f"cannot open a window on {display}: no X server there accepts a connection"
    if cannot_connect:  # pyglet 2.1 has no Wayland windows
        return "cannot open a window: it needs an X server, and DISPLAY is not set (XWayland sets it under Wayland)"
    where = display or os.environ.get("WAYLAND_DISPLAY") or "the default display"
    return f"cannot open a window on {where} ({first_line(error)})"
