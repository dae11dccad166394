"""The window's own reading of pyglet's X11 drag messages (window.py) is taken on only where pyglet
keeps the drag as that reading expects; another pyglet keeps its own handler, not a broken one."""

from __future__ import annotations

from types import SimpleNamespace

import pytest

xlib = pytest.importorskip("pyglet.libs.x11.xlib")

from marraztu.frontends.window import ViewerWindow  # noqa: E402


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
