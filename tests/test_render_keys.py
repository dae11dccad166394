"""Keys replayed through the screenshot path change the picture as SPEC 6 says."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from marraztu.control.viewer import StartOptions
from marraztu.frontends.screenshot import take_screenshot
from support.scenes import BACKGROUND as BACKGROUND_BYTES

SIZE = (160, 160)
BACKGROUND = np.array(BACKGROUND_BYTES)


@pytest.fixture
def shoot(tmp_path: Path):
    count = iter(range(1000))

    def render(keys: str) -> np.ndarray:
        out = take_screenshot(StartOptions(), tmp_path / f"{next(count)}.png", SIZE, keys=keys)
        return np.asarray(Image.open(out).convert("RGB")).astype(int)

    return render


def changed_fraction(a: np.ndarray, b: np.ndarray) -> float:
    return float((np.abs(a - b).max(axis=2) > 4).mean())


# (moves, how many of them `u` must undo): entering analysis mode (`c g`) is itself an undoable move.
@pytest.mark.parametrize("moves, undos", [
    ("x*5", 5), ("t y*3 X*2", 5), ("g z*4", 4), ("c g x*3 t z*2", 6), ("c c x*4", 4),
])
def test_undo_restores_the_picture_pixel_for_pixel(shoot, moves: str, undos: int) -> None:
    start = shoot("0 1")
    moved = shoot(f"0 1 {moves}")
    assert changed_fraction(start, moved) > 0.001, "the moves must show"
    assert np.array_equal(start, shoot(f"0 1 {moves} u*{undos}"))


def test_looking_through_the_object(shoot) -> None:
    from_camera = shoot("T")
    from_object = shoot("T C")
    assert changed_fraction(from_camera, from_object) > 0.01
    assert np.array_equal(shoot("T C C"), from_camera), "C again goes back to the camera"


def test_widening_the_camera_spotlight_lights_more(shoot) -> None:
    """The camera spotlight (30 degrees) reaches the middle of the scene; widened by 7.5 degrees it
    also reaches r_falke's far side (SPEC 6 `+` with the lights target, TAB to the spotlight)."""
    narrow = shoot("T 3")
    wide = shoot("T 3 c c TAB TAB TAB +*3")
    assert changed_fraction(narrow, wide) > 0.002
    assert np.abs(wide - BACKGROUND).sum() > np.abs(narrow - BACKGROUND).sum()
    assert np.array_equal(shoot("T 3 c c TAB TAB TAB +*3 -*3"), narrow)
