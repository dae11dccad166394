"""Reference images of the built-in scene in the main modes, rendered through the screenshot path.

Tolerance, stated: a pixel "differs" when any channel is more than 8/255 away from the reference;
at most 0.5 % of the pixels may differ, and the mean absolute difference must stay under 1/255.
That absorbs rasterisation and rounding differences between Mesa versions or GPUs, but not a moved
object, a wrong colour or a lost texture. Regenerate after an intended change with
`UPDATE_REFERENCES=1 make test` and look at every image before committing it.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from marraztu.control.viewer import StartOptions
from marraztu.frontends.screenshot import take_screenshot
from support.scenes import BACKGROUND as BACKGROUND_BYTES

REFERENCE_DIR = Path(__file__).parent / "reference"
SIZE = (320, 320)
CHANNEL_TOLERANCE = 8
MAX_DIFFERING_FRACTION = 0.005
MAX_MEAN_DIFFERENCE = 1.0
BACKGROUND = np.array(BACKGROUND_BYTES)

# name -> keys replayed from the start state (SPEC 3)
MODES = {
    "start": "",
    "all_lights_flat": "0 1 2 3",
    "all_lights_gouraud": "0 1 2 3 F",
    "lines": "l",
    "parallel_sun": "0 p",
    "culling_normals_untextured": "T b n 0 F",
}


def render(name: str, tmp_path: Path) -> np.ndarray:
    out = take_screenshot(StartOptions(), tmp_path / f"{name}.png", SIZE, keys=MODES[name])
    return np.asarray(Image.open(out).convert("RGB"))


@pytest.mark.parametrize("name", MODES)
def test_reference_image(name: str, tmp_path: Path) -> None:
    image = render(name, tmp_path)
    drawn = (np.abs(image.astype(int) - BACKGROUND).sum(axis=2) > 24).mean()
    assert drawn > 0.02, f"{name}: almost nothing but background ({drawn:.1%})"
    reference_path = REFERENCE_DIR / f"{name}.png"
    if os.environ.get("UPDATE_REFERENCES") == "1":
        Image.fromarray(image).save(reference_path)
    if not reference_path.exists():
        pytest.fail(f"no reference image {reference_path}; make one with UPDATE_REFERENCES=1")
    reference = np.asarray(Image.open(reference_path).convert("RGB"))
    difference = np.abs(image.astype(int) - reference.astype(int))
    differing = (difference.max(axis=2) > CHANNEL_TOLERANCE).mean()
    assert differing <= MAX_DIFFERING_FRACTION, f"{name}: {differing:.2%} of the pixels differ"
    assert difference.mean() < MAX_MEAN_DIFFERENCE, f"{name}: mean difference {difference.mean():.2f}"


def test_modes_differ_from_each_other(tmp_path: Path) -> None:
    """Guards the references themselves: every mode must show something the start state does not."""
    start = render("start", tmp_path).astype(int)
    for name in MODES:
        if name != "start":
            assert (np.abs(render(name, tmp_path).astype(int) - start).max(axis=2) > 8).mean() > 0.001, name
