"""SPEC 4's check colours: the seed's own models, ambient light only, flat, texture off (Figure 1)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from app.screenshot import take_screenshot
from app.viewer import StartOptions

SEED_ASSETS = Path(__file__).resolve().parents[2] / "shared" / "seed-assets"

SEED_SCENE = """
[materials.shiny_plastic]
ka = [0.0, 0.3, 1.0]
kd = [0.5922, 0.0166, 0.0]
ks = [0.5974, 0.2084, 0.2084]
ns = 100.2237

[materials.greenish]
ka = [0.4, 0.8, 0.3]
kd = [0.3, 0.4, 0.6]
ks = [0.3, 0.1, 0.2]
ns = 60.0

[materials.vibrant_green]
ka = [0.1, 1.0, 0.2]
kd = [0.8, 0.8, 0.8]
ks = [0.5, 0.5, 0.5]
ns = 225.0

[materials.golden]
ka = [0.8, 0.72, 0.0]
kd = [0.8, 0.6, 0.4]
ks = [0.9, 0.8, 0.5]
ns = 80.0

[[cameras]]
model = "{assets}/cam.obj"
position = [0, 0, 150]
material = "shiny_plastic"

[[objects]]
name = "x_wing"
model = "{assets}/x_wing.obj"
position = [-100, 0, 0]
material = "greenish"

[[objects]]
name = "r_falke"
model = "{assets}/r_falke.obj"
position = [100, 0, 0]
material = "vibrant_green"

[[objects]]
name = "Rammer_255"
model = "{assets}/rammer_225.obj"
position = [0, 0, 0]
material = "golden"
"""

EXPECTED = {"x_wing": (80, 60, 76), "r_falke": (20, 75, 51), "golden": (160, 54, 0)}
BACKGROUND = (0, 0, 178)


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
    assert np.abs(np.subtract(colour, EXPECTED[name])).max() <= 1, (name, colour)
