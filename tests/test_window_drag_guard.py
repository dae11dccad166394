"""The window's own reading of pyglet's X11 drag messages (window.py) is taken on only where pyglet
keeps the drag as that reading expects; another pyglet keeps its own handler, not a broken one. A drop's
text/uri-list is read by the window too: its comments, its remote addresses, its percent-encoded bytes."""

from __future__ import annotations

import os
import socket
from pathlib import Path
from types import SimpleNamespace

import pytest

xlib = pytest.importorskip("pyglet.libs.x11.xlib")

from marraztu.frontends.window import ViewerWindow, dropped_files, uri_list_lines  # noqa: E402


def _window_of(pyglet_window: object) -> SimpleNamespace:
    return SimpleNamespace(wnd=SimpleNamespace(_window=pyglet_window), on_client_message="the window's")


def _pyglet_window(**drag_state: object) -> SimpleNamespace:
    handlers = {xlib.ClientMessage: "pyglet's own"}
    atoms = {"XdndEnter": 1, "XdndPosition": 2, "XdndDrop": 3, "text/uri-list": 4}
    return SimpleNamespace(_event_handlers=handlers, _xdnd_atoms=atoms, **drag_state)


def test_client_messages_are_taken_where_pyglet_keeps_the_drag_as_read() -> None:
    pyglet_window = _pyglet_window(_xdnd_source=None, _xdnd_version=None, _xdnd_format=None)
    window = _window_of(pyglet_window)
    ViewerWindow._take_drag_messages(window)  # type: ignore[arg-type]
    assert window.pyglet_client_message == "pyglet's own"
    assert pyglet_window._event_handlers[xlib.ClientMessage] == "the window's"


@pytest.mark.parametrize("drag_state", [{}, {"_xdnd_source": None, "_xdnd_version": None}])
def test_another_pyglets_drag_keeps_its_own_handler(drag_state: dict[str, object]) -> None:
    pyglet_window = _pyglet_window(**drag_state)
    ViewerWindow._take_drag_messages(_window_of(pyglet_window))  # type: ignore[arg-type]
    assert pyglet_window._event_handlers[xlib.ClientMessage] == "pyglet's own"


def test_atoms_named_otherwise_keep_pyglets_handler() -> None:
    pyglet_window = _pyglet_window(_xdnd_source=None, _xdnd_version=None, _xdnd_format=None)
    pyglet_window._xdnd_atoms = {"XdndPosition": 2}
    ViewerWindow._take_drag_messages(_window_of(pyglet_window))  # type: ignore[arg-type]
    assert pyglet_window._event_handlers[xlib.ClientMessage] == "pyglet's own"


def test_a_uri_lists_comments_and_blank_lines_are_no_files() -> None:
    """pyglet read a comment line (RFC 2483) as the path "", which then loaded the current folder."""
    text = "# dragged from a file manager\r\nfile:///tmp/a.obj\r\n\r\n"
    assert dropped_files(uri_list_lines(text)) == (["/tmp/a.obj"], [])


def test_several_files_dropped_at_once_keep_their_order_and_spelling() -> None:
    host = socket.gethostname()
    text = (f"file:///tmp/with%20space%C3%B1.obj\r\nfile://localhost/tmp/b.stl\r\nfile://{host}/tmp/c.ply\n"
            "file:///tmp/%FF.obj")
    assert dropped_files(uri_list_lines(text)) == (
        ["/tmp/with spaceñ.obj", "/tmp/b.stl", "/tmp/c.ply", os.fsdecode(b"/tmp/\xff.obj")], [])


@pytest.mark.parametrize("uri", ["https://example.com/model.obj", "http://[broken/m.obj",
                                 "file://another-computer/tmp/a.obj", "ftp://example.com/a.obj"])
def test_what_is_not_on_this_computer_is_no_local_path(uri: str) -> None:
    """pyglet read https://example.com/model.obj as the local path /model.obj."""
    assert dropped_files(uri_list_lines(f"{uri}\r\nfile:///tmp/a.obj\r\n")) == (["/tmp/a.obj"], [uri])


def test_paths_other_systems_give_are_taken_as_given() -> None:
    entries: list[str | Path] = [r"C:\models\a%20b.obj", "/Users/me/a%20b.obj", Path("/tmp/x.obj")]
    assert dropped_files(entries) == (entries, [])


def test_a_remote_drop_is_said_in_one_line_and_local_files_still_load() -> None:
    loaded: list[str | Path] = []
    viewer = SimpleNamespace(load_model=loaded.append, tell=lambda text: setattr(viewer, "told", text))
    window = SimpleNamespace(viewer=viewer, needs_frame=False, scene_changed=False, last_failure="")
    entries = uri_list_lines("https://example.com/a.obj\r\nfile:///tmp/b.obj\r\nhttps://example.com/c.obj\r\n")
    ViewerWindow.on_files_dropped_event(window, 0, 0, entries)  # type: ignore[arg-type]
    assert loaded == ["/tmp/b.obj"]
    assert viewer.told == ("https://example.com/a.obj: only files on this computer can be opened "
                           "(1 other not opened either)")


def test_a_list_that_is_not_utf8_is_said_not_raised() -> None:
    """pyglet decodes the dropped list as UTF-8: another byte raised out of its event loop."""
    def pyglets_own(event: object) -> None:
        b"file:///tmp/\xff.obj".decode()

    viewer = SimpleNamespace(tell=lambda text: setattr(viewer, "told", text))
    window = SimpleNamespace(viewer=viewer, pyglet_selection_notify=pyglets_own, needs_frame=False,
                             scene_changed=False, last_failure="")
    ViewerWindow.on_selection_notify(window, object())  # type: ignore[arg-type]
    assert viewer.told == "dropped files not opened: their list is not UTF-8 text (byte 12)"
    assert window.needs_frame


def test_pyglets_reading_of_a_drop_is_replaced_where_it_has_one() -> None:
    pyglet_window = _pyglet_window(_xdnd_source=None, _xdnd_version=None, _xdnd_format=None,
                                   parse_filenames="pyglet's parsing")
    pyglet_window._event_handlers[xlib.SelectionNotify] = "pyglet's selection"
    window = _window_of(pyglet_window)
    window.on_selection_notify = "the window's selection"
    ViewerWindow._take_drag_messages(window)  # type: ignore[arg-type]
    assert pyglet_window.parse_filenames is uri_list_lines
    assert window.pyglet_selection_notify == "pyglet's selection"
    assert pyglet_window._event_handlers[xlib.SelectionNotify] == "the window's selection"
