"""The views of the scene in a framebuffer (one, or three side by side) and how a world point lands on
a pixel. No GL: the renderer draws these views and the text layer labels them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from marraztu.model.scene import Scene, Shading


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

