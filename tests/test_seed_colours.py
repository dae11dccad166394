"""SPEC 4's check colours: the seed's own models, ambient light only, flat, texture off (Figure 1)."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from marraztu.control.viewer import StartOptions
from marraztu.frontends.screenshot import take_screenshot
from support.scenes import BACKGROUND
from support.seed import EXPECTED, SEED_ASSETS, SEED_SCENE


@pytest.fixture(scope="module")
def figure1(tmp_path_factory: pytest.TempPathFactory) -> np.ndarray:
    if not SEED_ASSETS.is_dir():
        pytest.skip(f"the seed's models are not here ({SEED_ASSETS}); they live in ../shared")
    folder = tmp_path_factory.mktemp("seed")
    scene = folder / "seed.toml"
    scene.write_text(SEED_SCENE.replace("{assets}", SEED_ASSETS.as_posix()))
    out = take_screenshot(StartOptions(scene_file=scene), folder / "figure1.png", (500, 500), keys="T")
    return np.asarray(Image.open(out).convert("RGB"))


def dominant_colour(pixels: np.ndarray) -> tuple[int, int, int]:
    """The most common non-background colour of a region: flat ambient paints each object one colour."""
    flat = pixels.reshape(-1, 3)
    flat = flat[np.any(flat != BACKGROUND, axis=1)]
    assert len(flat) > 20, "the object is not there"
    colours, counts = np.unique(flat, axis=0, return_counts=True)
    return tuple(int(c) for c in colours[counts.argmax()])


def test_background(figure1: np.ndarray) -> None:
    assert tuple(figure1[5, 5]) == BACKGROUND


@pytest.mark.parametrize("name, columns", [
    ("x_wing", slice(0, 200)), ("golden", slice(200, 300)), ("r_falke", slice(300, 500)),
])
def test_check_colour(figure1: np.ndarray, name: str, columns: slice) -> None:
    colour = dominant_colour(figure1[:, columns])
    assert np.abs(np.subtract(colour, EXPECTED[name])).max() == 0, (name, colour)
