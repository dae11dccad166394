"""Where things go in a framebuffer: the views of the scene (one, or three side by side), how a world
point lands on a pixel, and the text panels the overlay draws. No GL: the text layer uses it too.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from marraztu.errors import shortened
from marraztu.model.scene import Scene, Shading

MAX_SIDE = 16384  # pixels: no framebuffer side beyond what GL implementations promise


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


@dataclass(frozen=True)
class View:
    """One picture of the scene: a viewport of the framebuffer and how it spreads the lighting."""

    viewport: tuple[int, int, int, int]  # x, y, width, height in pixels, origin bottom-left
    shading: Shading
    title: str = ""

    @property
    def aspect(self) -> float:
        return self.viewport[2] / self.viewport[3]


SIDE_BY_SIDE = ((Shading.FLAT, "Flat"), (Shading.GOURAUD, "Gouraud"), (Shading.PHONG, "Phong (per pixel)"))


def views(scene: Scene, size: tuple[int, int]) -> list[View]:
    """The whole framebuffer in the scene's shading, or (side by side) three thirds of it, each with
    its own aspect ratio so that nothing is squeezed: one camera, three lighting models."""
    width, height = max(int(size[0]), 1), max(int(size[1]), 1)
    if not scene.modes.side_by_side:
        return [View((0, 0, width, height), scene.modes.shading)]
    edges = [round(k * width / len(SIDE_BY_SIDE)) for k in range(len(SIDE_BY_SIDE) + 1)]
    return [View((edges[k], 0, max(edges[k + 1] - edges[k], 1), height), shading, title)
            for k, (shading, title) in enumerate(SIDE_BY_SIDE)]


def narrowest_aspect(scene: Scene, size: tuple[int, int]) -> float:
    """Width over height of the narrowest view of the framebuffer (a third of it, side by side)."""
    return min(view.aspect for view in views(scene, size))


def view_projection(scene: Scene, view: View) -> np.ndarray:
    return scene.projection_matrix(view.aspect) @ scene.view_matrix()


def pixel_per_w(projection: np.ndarray, view: View) -> float:
    """A pixel's height in the world at clip w = 1 (w is the depth in perspective, 1 in parallel):
    projection[1][1] maps a world height at w = 1 to half the view's height."""
    return 2.0 / (float(projection[1, 1]) * view.viewport[3])


def project(view_projection: np.ndarray, point: np.ndarray,
            viewport: tuple[int, int, int, int]) -> tuple[float, float] | None:
    """Window position of a world point in pixels, origin at the framebuffer's bottom-left, as GL
    maps it (pixel centres at .5); None behind the eye."""
    clip = view_projection @ np.append(np.asarray(point, float), 1.0)
    if clip[3] <= 1e-9:
        return None
    x0, y0, width, height = viewport
    ndc = clip[:3] / clip[3]
    return x0 + (ndc[0] + 1.0) / 2.0 * width, y0 + (ndc[1] + 1.0) / 2.0 * height


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
