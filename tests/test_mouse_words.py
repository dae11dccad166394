"""The mouse's words in --keys (drag=, rdrag=, ctrl+drag=, wheel=) move what the window's drags and wheel
move, through the same control-layer function with the same numbers: the matrices must be equal, and
`u` takes each word back as one step, as it takes back a drag or a run of notches in the window."""

from __future__ import annotations

import re

import numpy as np
import pytest

from marraztu.control import commands
from marraztu.control.keymap import (
    CLICK_TRAVEL_PX,
    MAX_SEQUENCE_PRESSES,
    MAX_WHEEL_NOTCHES,
    KeyPress,
    parse_key_sequence,
)
from marraztu.control.viewer import Viewer
from marraztu.errors import KeyMapError, ViewerError
from marraztu.model.scene import SceneObject
from support.scenes import PLAIN, NoFrontend, box_mesh, scene_with

SIZE = (160, 120)


def viewer(strict: bool = True) -> Viewer:
    box = SceneObject.placed("box", box_mesh(20.0), PLAIN, (5.0, -3.0, 0.0), (10.0, 20.0, 0.0))
    return Viewer(scene_with([box]), NoFrontend(), strict=strict, frame_size=lambda: SIZE)


def test_the_words_parse_and_name_themselves() -> None:
    words = "drag=10,20,70,50*2 rdrag=1,1,2,2 ctrl+drag=0,0,9,0 wheel=-3 click=4,5"
    presses = parse_key_sequence(words)
    assert [str(press) for press in presses] == ["drag=10,20,70,50", "drag=10,20,70,50", "rdrag=1,1,2,2",
                                                  "ctrl+drag=0,0,9,0", "wheel=-3", "click=4,5"]
    assert [press.pixel for press in presses] == [(10, 20), (10, 20), (1, 1), (0, 0), None, (4, 5)]


@pytest.mark.parametrize("word, says", [
    ("drag=1,2", "a drag is drag=X1,Y1,X2,Y2, whole pixels from the top-left"),
    ("drag=1,2,3,-4", "a drag is drag=X1,Y1,X2,Y2"),
    ("rdrag=a,b,c,d", "a rdrag is rdrag=X1,Y1,X2,Y2"),
    ("ctrl+drag=", "a ctrl+drag is ctrl+drag=X1,Y1,X2,Y2"),
    ("wheel=1.5", "a wheel is wheel=N, notches, negative toward the person"),
    ("wheel=0", f"1 to {MAX_WHEEL_NOTCHES} notches"),
    (f"wheel=-{MAX_WHEEL_NOTCHES + 1}", f"1 to {MAX_WHEEL_NOTCHES} notches"),
    (f"drag=10,10,{10 + CLICK_TRAVEL_PX},{10 - CLICK_TRAVEL_PX}", "which the window takes as a click"),
    (f"ctrl+drag=10,10,10,{10 + CLICK_TRAVEL_PX}", "which the window takes as a click"),
])
def test_a_malformed_word_is_refused_with_its_form_in_one_line(word: str, says: str) -> None:
    with pytest.raises(KeyMapError, match=re.escape(says)) as refused:
        parse_key_sequence(f"x {word} y")
    assert "\n" not in str(refused.value) and word in str(refused.value)


@pytest.mark.parametrize("word, move", [("drag", commands.DragMove.ORBIT), ("rdrag", commands.DragMove.PAN),
                                        ("ctrl+drag", commands.DragMove.TURN_TARGET)])
def test_a_drag_word_moves_as_the_window_s_drag_of_the_same_pixels(word: str, move: commands.DragMove) -> None:
    by_word, by_window = viewer(), viewer()
    start = by_word.scene.camera.model.copy(), by_word.scene.object.model.copy()
    by_word.press_sequence(f"{word}=10,20,70,50")
    by_window.move_by_mouse(lambda scene: commands.drag_by(scene, move, 60, 30, SIZE))
    for scene in (by_word.scene, by_window.scene):
        moved = scene.object if move is commands.DragMove.TURN_TARGET else scene.camera
        assert not np.allclose(moved.model, start[moved is scene.object])
    assert np.array_equal(by_word.scene.camera.model, by_window.scene.camera.model)
    assert np.array_equal(by_word.scene.object.model, by_window.scene.object.model)
    by_word.press_sequence("u")
    assert np.array_equal(by_word.scene.camera.model, start[0]) and np.array_equal(by_word.scene.object.model, start[1])


@pytest.mark.parametrize("notches", [3, -2])
def test_the_wheel_word_dollies_as_the_window_s_notches_and_u_takes_the_run_back(notches: int) -> None:
    by_word, by_window = viewer(), viewer()
    start = by_word.scene.camera.model.copy()
    by_word.press_sequence(f"wheel={notches}")
    for _ in range(abs(notches)):  # the window: an event a notch
        by_window.move_by_mouse(lambda scene: commands.dolly_view(scene, np.sign(notches)))
    assert not np.allclose(by_word.scene.camera.model, start)
    assert np.array_equal(by_word.scene.camera.model, by_window.scene.camera.model)
    by_word.press_sequence("u")
    assert np.array_equal(by_word.scene.camera.model, start)


def test_each_word_is_an_undo_step_of_its_own() -> None:
    moved = viewer()
    moved.press_sequence("drag=10,20,70,50")
    once = moved.scene.camera.model.copy()
    moved.press_sequence("drag=10,20,70,50 u")
    assert np.array_equal(moved.scene.camera.model, once)


def test_a_drag_pressed_off_the_picture_is_refused() -> None:
    with pytest.raises(ViewerError, match=r"drag=160,0,170,0: its press at 160,0 lies outside the 160x120 picture"):
        viewer().press_sequence("drag=160,0,170,0")
    loose = viewer(strict=False)
    start = loose.scene.camera.model.copy()
    loose.press(KeyPress("rdrag", numbers=(0, 120, 10, 130)))
    assert loose.scene.message.startswith("rdrag=0,120,10,130: its press at 0,120 lies outside")
    assert np.array_equal(loose.scene.camera.model, start)
    unsized = Viewer(scene_with([]), NoFrontend())
    unsized.press_sequence("drag=1,1,20,20")
    assert unsized.scene.message == "no picture to drag in"
    ended = viewer()
    ended.press_sequence("drag=10,10,150,10")  # the end may leave the picture, as a drag may leave the window
    assert not np.array_equal(ended.scene.camera.model, start)


@pytest.mark.parametrize("word", ["drag=10,20,70,50", "rdrag=10,20,70,50", "wheel=2"])
def test_a_drag_or_the_wheel_in_the_file_prompt_moves_the_view_as_in_the_window(word: str) -> None:
    """The window's drags and wheel move the view while the `f` prompt is open (only a click is typed into
    it, where it does nothing); the words were swallowed by the prompt, silently."""
    in_prompt, alone = viewer(), viewer()
    in_prompt.press_sequence(f"f {word}")
    alone.press_sequence(word)
    assert in_prompt.prompt == "" and np.array_equal(in_prompt.scene.camera.model, alone.scene.camera.model)
    clicked = viewer()
    clicked.press_sequence("f click=80,60")
    assert clicked.prompt == "" and clicked.scene.message == ""


def test_a_wheel_word_s_notches_count_toward_the_sequence_s_presses() -> None:
    """wheel=100*20000, 15 characters, was 2 million notches run one by one (about 100 seconds) within a
    limit of a million presses meant to bound a sequence's work: each notch counts as a press."""
    assert len(parse_key_sequence(f"wheel=-100*{MAX_SEQUENCE_PRESSES // 100}")) == MAX_SEQUENCE_PRESSES // 100
    for words in (f"wheel=100*{MAX_SEQUENCE_PRESSES // 100} x", f"x wheel=20*{MAX_SEQUENCE_PRESSES // 20}"):
        with pytest.raises(KeyMapError, match=f"more than {MAX_SEQUENCE_PRESSES} presses"):
            parse_key_sequence(words)
