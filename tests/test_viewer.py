"""The viewer, without GL: the `f` prompt driven by keys, start-up messages that add up instead of
hiding each other, and the strict screenshot's refusals."""

from __future__ import annotations

from pathlib import Path

import pytest

from marraztu.control.keymap import KeyPress, parse_key_sequence
from marraztu.control.viewer import START_HINT, BackgroundLoader, StartOptions, Viewer
from marraztu.errors import ViewerError
from marraztu.loaders.images import fallback_texture
from marraztu.loaders.scenefile import empty_scene, load_builtin_scene
from marraztu.model.scene import Projection
from support import corpus
from support.scenes import Notices

GOOD = corpus.TRIANGLE + b"f 1 2 3\n"


def press(viewer: Viewer, keys: str) -> None:
    for key in parse_key_sequence(keys):
        viewer.press(key)


def test_keys_type_into_the_file_prompt_and_enter_loads(tmp_path: Path, monkeypatch) -> None:
    (tmp_path / "a b.obj").write_bytes(GOOD)
    monkeypatch.chdir(tmp_path)
    viewer = Viewer(empty_scene(), Notices())
    press(viewer, "f a SPACE b . o b j x BACKSPACE")
    assert viewer.prompt == "a b.obj"
    press(viewer, "ENTER")
    assert viewer.prompt is None and [obj.name for obj in viewer.scene.objects] == ["a b"]
    press(viewer, "f q ESC")
    assert viewer.prompt is None and viewer.scene.message == "loading cancelled"


def test_a_home_folder_of_no_one_is_a_message_not_a_crash() -> None:
    viewer = Viewer(empty_scene(), Notices())
    press(viewer, "f ~ n o s u c h u s e r / m . o b j ENTER")
    assert "no such user" in viewer.scene.message and viewer.scene.objects == []


def test_every_start_up_failure_is_told_and_none_hides_another(tmp_path: Path) -> None:
    (tmp_path / "broken.obj").write_bytes(corpus.TRIANGLE + b"f 1 2 9\n")
    (tmp_path / "good.obj").write_bytes(GOOD)
    (tmp_path / "bad.ppm").write_bytes(b"P6\n4 4\n255\n\x00")
    front = Notices()
    viewer = Viewer(load_builtin_scene(), front)
    viewer.start(StartOptions(texture=tmp_path / "bad.ppm",
                              models=(tmp_path / "broken.obj", tmp_path / "good.obj")), longest_texture_side=4096)
    lines = viewer.scene.message.splitlines()
    assert len(lines) == 3 and front.told == lines[:2], "a plain success is shown, not noticed"
    assert "bad.ppm" in lines[0] and "checker" in lines[0]
    assert "broken.obj:4" in lines[1] and "loaded good.obj" in lines[2]
    assert (viewer.scene.texture == fallback_texture()).all()
    press(viewer, "l")
    assert viewer.scene.message == "", "the first key press starts afresh"


@pytest.mark.parametrize("scene", [empty_scene, load_builtin_scene])
def test_a_start_that_says_nothing_else_says_how_to_begin(scene) -> None:
    """A first-time person saw a blank window (--empty) or a status line with no word of help."""
    viewer = Viewer(scene(), Notices())
    viewer.start(StartOptions(), longest_texture_side=4096)
    assert viewer.scene.message == START_HINT == "h: help \u00b7 f: open a model"
    press(viewer, "l")
    assert START_HINT not in viewer.scene.message, "a press clears it, as any message"


@pytest.mark.parametrize("worker", [False, True])
def test_a_start_that_says_something_says_no_hint(tmp_path: Path, worker: bool) -> None:
    """The window (a worker) and the screenshot command end their start with the same words."""
    (tmp_path / "good.obj").write_bytes(GOOD)
    (tmp_path / "bad.ppm").write_bytes(b"P6\n4 4\n255\n\x00")
    loader = BackgroundLoader() if worker else None
    viewer = Viewer(empty_scene(), Notices(), background=loader)
    try:
        viewer.start(StartOptions(models=(tmp_path / "good.obj",)), longest_texture_side=4096)
        assert START_HINT not in viewer.scene.message, "told once its model lands"
        for job in loader.uncollected() if loader else []:
            job.future.result(timeout=60)
        viewer.collect_loads()
    finally:
        if loader:
            loader.shutdown()
    assert viewer.scene.message.startswith("loaded good.obj") and START_HINT not in viewer.scene.message
    textured = Viewer(empty_scene(), Notices())
    textured.start(StartOptions(texture=tmp_path / "bad.ppm"), longest_texture_side=4096)
    assert "bad.ppm" in textured.scene.message and START_HINT not in textured.scene.message


def test_start_up_loads_on_the_worker_are_told_when_they_land(tmp_path: Path) -> None:
    (tmp_path / "broken.obj").write_bytes(corpus.TRIANGLE + b"f 1 2 9\n")
    (tmp_path / "good.obj").write_bytes(GOOD)
    front = Notices()
    loader = BackgroundLoader()
    viewer = Viewer(empty_scene(), front, background=loader)
    try:
        viewer.start(StartOptions(models=(tmp_path / "broken.obj", tmp_path / "good.obj")), longest_texture_side=4096)
        assert front.told == [], "nothing is told before the loads land"
        for job in loader.uncollected():
            job.future.exception(timeout=60)  # waits for it, failed or not
        viewer.collect_loads()
    finally:
        loader.shutdown()
    assert len(front.told) == 1 and "broken.obj:4" in front.told[0]
    assert viewer.scene.message.splitlines()[0] == front.told[0]
    assert "loaded good.obj" in viewer.scene.message.splitlines()[1]


def test_the_strict_viewer_refuses_a_load_while_lights_are_targeted(tmp_path: Path) -> None:
    (tmp_path / "good.obj").write_bytes(GOOD)
    viewer = Viewer(empty_scene(), Notices(), strict=True)
    press(viewer, "c c")
    with pytest.raises(ViewerError, match="lights are targeted"):
        viewer.press(KeyPress("f", str(tmp_path / "good.obj")))
    forgiving = Viewer(empty_scene(), Notices())
    press(forgiving, "c c")
    forgiving.press(KeyPress("f", str(tmp_path / "good.obj")))
    assert "lights are targeted" in forgiving.scene.message


def test_the_strict_viewer_refuses_a_bare_f_while_lights_are_targeted() -> None:
    """`c c f e SPACE p ENTER`: the keys after f were read as typed into the file prompt, which never
    opened, so they were pressed as keys (p switched the projection) and the command wrote its picture."""
    viewer = Viewer(empty_scene(), Notices(), strict=True)
    with pytest.raises(ViewerError, match="^f: cannot load a file while lights are targeted"):
        viewer.press_sequence("c c f e SPACE p ENTER")
    assert viewer.scene.modes.projection is Projection.PERSPECTIVE
    forgiving = Viewer(empty_scene(), Notices())
    forgiving.press_sequence("c c f")
    assert forgiving.scene.message == "cannot load a file while lights are targeted" and forgiving.prompt is None


def test_the_command_lines_models_are_framed_once_together(tmp_path: Path, monkeypatch) -> None:
    """Framing looks at every model: once for all of them, not once as each joins."""
    from marraztu.control import commands

    (tmp_path / "t.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    (tmp_path / "far.obj").write_text("v 50 0 0\nv 51 0 0\nv 50 1 0\nf 1 2 3\n")
    framed: list[int] = []
    original = commands.frame_models
    monkeypatch.setattr(commands, "frame_models",
                        lambda scene, *rest: framed.append(len(scene.objects)) or original(scene, *rest))
    models = (tmp_path / "t.obj",) * 40 + (tmp_path / "far.obj",)
    viewer = Viewer(empty_scene(), Notices(), strict=True)
    viewer.start(StartOptions(empty=True, models=models), 4096)
    assert framed == [1, 41]  # the first into the empty scene, then all of them
    alone = Viewer(empty_scene(), Notices(), strict=True)
    alone.start(StartOptions(empty=True, models=models[-2:]), 4096)
    assert (viewer.scene.camera.model == alone.scene.camera.model).all()  # as if framed as each joined


def test_a_sequence_types_into_a_prompt_an_earlier_one_left_open() -> None:
    """press_sequence("f m o") left the prompt open, and press_sequence("d e l") was refused, "unknown key
    'e'": its words were read as keys, as the programming interface's press read them before 43e613b."""
    viewer = Viewer(empty_scene(), Notices(), strict=False)
    viewer.press_sequence("f m o")
    viewer.press_sequence("d e SPACE l")
    assert viewer.prompt == "mode l"


def test_the_file_prompt_holds_a_path_at_most() -> None:
    """Typing on past PATH_MAX is dropped: each key would copy the line, and its error would fill pages."""
    from marraztu.control.viewer import MAX_PROMPT_CHARACTERS

    viewer = Viewer(empty_scene(), Notices(), strict=False)
    press(viewer, f"f a*{MAX_PROMPT_CHARACTERS + 500}")
    assert viewer.prompt == "a" * MAX_PROMPT_CHARACTERS
    viewer.type_text("b")
    assert viewer.prompt == "a" * MAX_PROMPT_CHARACTERS
