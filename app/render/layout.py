"""Where things go in a framebuffer: its size, a pixel's size in the world, and the text panels the
overlay draws (the views of the scene are the model's: marraztu.model.viewports). No GL: the text
layer uses it too.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from marraztu.errors import shortened
from marraztu.model.viewports import View

MAX_SIDE = 16384  # pixels: no framebuffer side beyond what GL implementations promise
SCREEN_SIDE_PX = 800  # the shorter framebuffer side up to which the overlay's text and the markers keep their size


def parse_size(text: str) -> tuple[int, int]:
    """'800x600' -> (800, 600); ValueError saying what is wrong."""
    try:
        width, height = (int(part) for part in text.lower().split("x"))
    except ValueError:
        raise ValueError(f"size must look like 800x600, not {shortened(text)!r}") from None
    return checked_size(width, height)


def checked_size(width: int, height: int) -> tuple[int, int]:
    """(width, height), each 1..MAX_SIDE; ValueError otherwise."""
    if not (1 <= width <= MAX_SIDE and 1 <= height <= MAX_SIDE):
        shown = f" {width}x{height}" if max(abs(width), abs(height)) < 10**9 else ""  # not a page of digits
        raise ValueError(f"size{shown} is out of range 1..{MAX_SIDE}")
    return width, height


def screen_scale(size: tuple[int, int]) -> float:
    """How much larger than at 800x800 what is drawn in pixels (the overlay's text, the light's and the probe's
    dots) is drawn: the framebuffer's shorter side over SCREEN_SIDE_PX, never under 1 (a smaller window wraps
    and cuts its text instead)."""
    return max(1.0, min(size) / SCREEN_SIDE_PX)


def scaled_px(length: float, size: tuple[int, int]) -> int:
    """A length of the overlay's text at 800x800, at the framebuffer `size`: whole pixels, the nearest."""
    return int(length * screen_scale(size) + 0.5)


def pixel_per_w(projection: np.ndarray, view: View) -> float:
    """A pixel's height in the world at clip w = 1 (w is the depth in perspective, 1 in parallel):
    projection[1][1] maps a world height at w = 1 to half the view's height."""
    return 2.0 / (float(projection[1, 1]) * view.viewport[3])


@dataclass(frozen=True)
class Label:
    """A short text centred on a pixel position (origin bottom-left, like GL's window coordinates)."""

    text: str
    x: float
    y: float


@dataclass(frozen=True)
class Extras:
    """What the overlay draws besides its top and bottom lines."""

    bottom: list[str] = field(default_factory=list)  # a panel above the bottom lines (the probe)
    right: list[str] = field(default_factory=list)  # a panel at the top right (the matrices)
    titles: list[str] = field(default_factory=list)  # one title per side-by-side viewport
    labels: list[Label] = field(default_factory=list)
    bottom_overflow_hint: str = ""  # said after the bottom panel's last line when it is cut short


def labels_covered(labels: list[Label], width_of: Callable[[Label], float], height: float,
                   bottom: float, top: float, right: float) -> float:
    """The area, in square pixels, of the box around the labels (each `height` tall) that the band from
    the left edge to `right`, between `bottom` and `top`, covers: a probed face lies inside that box, as
    each label sits beyond its vertex, away from the face."""
    if not labels:
        return 0.0
    box_left = min(label.x - width_of(label) / 2.0 for label in labels)
    box_right = max(label.x + width_of(label) / 2.0 for label in labels)
    box_bottom = min(label.y for label in labels) - height / 2.0
    box_top = max(label.y for label in labels) + height / 2.0
    across = min(box_right, right) - max(box_left, 0.0)
    up = min(box_top, top) - max(box_bottom, bottom)
    return max(across, 0.0) * max(up, 0.0)
