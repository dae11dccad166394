"""The views of the scene in a framebuffer (one, or three side by side), how a world point lands on a
pixel and which world points a pixel shows. No GL: the renderer draws these views, the text layer
labels them, and a click finds its face in them (marraztu.model.picking).
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


def pixel_refusal(pixel: tuple[int, int], size: tuple[int, int]) -> str | None:
    """Why `pixel` (column, row from the top-left) is no pixel of a framebuffer of `size` (None: it is)."""
    column, row = pixel
    width, height = size
    if 0 <= column < width and 0 <= row < height:
        return None
    return f"{column},{row} lies outside the {width}x{height} picture (0,0 is its top-left pixel)"


def pixel_centre(pixel: tuple[int, int], size: tuple[int, int]) -> tuple[float, float]:
    """The centre of `pixel` (column, row from the top-left) in GL's window coordinates (origin at the
    bottom-left, pixel centres at .5), where the rasteriser samples it."""
    return pixel[0] + 0.5, size[1] - pixel[1] - 0.5


def view_at(scene: Scene, size: tuple[int, int], point: tuple[float, float]) -> View:
    """The view that holds a window point (`pixel_centre`'s): side by side, the third it falls in."""
    shown = views(scene, size)
    return next((view for view in shown if point[0] < view.viewport[0] + view.viewport[2]), shown[-1])


def pixel_segment(view_projection: np.ndarray, point: tuple[float, float],
                  viewport: tuple[int, int, int, int]) -> tuple[np.ndarray, np.ndarray]:
    """The world points a window point shows, from the near plane to the far one (NDC z = -1 and +1):
    `project`'s inverse, along the ray the rasteriser samples there."""
    x0, y0, width, height = viewport
    ndc_x, ndc_y = 2.0 * (point[0] - x0) / width - 1.0, 2.0 * (point[1] - y0) / height - 1.0
    ends = np.linalg.inv(view_projection) @ np.array([[ndc_x, ndc_x], [ndc_y, ndc_y], [-1.0, 1.0], [1.0, 1.0]])
    near, far = (ends[:3] / ends[3]).T
    return near, far
