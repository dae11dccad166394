"""The grid and axes (key `a`): the world's axes at the origin, a ground grid under the scene, and in
local mode the selected object's own axes, as coloured line segments in world space.

They show what `g` changes: in local mode an object moves along its own (light) axes, in global
mode along the world's (strong) ones. As in f3d, the grid lies in the ground plane (y up, the start
camera's up) at the bottom of the scene, so that the start camera sees it from above.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from marraztu.model.scene import Frame, Scene, Target, world_axes_lengths

# x red, y green, z blue, as in every graphics tool; z a sky blue, as Blender's, since pure blue on the
# seed's blue background (0, 0, 0.7) hardly shows.
AXIS_COLOURS = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.25, 0.6, 1.0]], dtype=np.float32)
OWN_AXIS_LIGHTNESS = 0.55  # an object's own axes: the same hues, paler, told from the world's
GRID_COLOUR = (0.55, 0.55, 0.6)
GRID_CELLS = 20  # about this many cells across the scene: fine enough to read distances


def nice_step(span: float, cells: int = GRID_CELLS) -> float:
    """A round grid step (1, 2 or 5 times a power of ten) giving about `cells` cells over `span`."""
    raw = max(span, 1e-30) / cells
    power = 10.0 ** math.floor(math.log10(raw))
    return next(power * m for m in (1.0, 2.0, 5.0, 10.0) if power * m >= raw)


@dataclass(frozen=True)
class Guides:
    """(N, 6) float64 rows: x y z r g b, two rows a segment, in world space."""

    axes: np.ndarray  # the world's, then the selected object's own in local mode
    grid: np.ndarray


def scene_guides(scene: Scene) -> Guides:
    low, high, extent = scene.guides_extent()
    axes = [_axes(np.eye(4), world_axes_lengths(high, extent), 1.0)]
    obj = scene.object
    if obj is not None and scene.modes.frame is Frame.LOCAL and scene.modes.target is Target.OBJECTS:
        axes.append(_axes(obj.model, np.full(3, max(obj.mesh.size / 2.0, extent / 20.0)), OWN_AXIS_LIGHTNESS))
    return Guides(np.concatenate(axes), _grid(low, high, extent))  # 64-bit: the renderer rounds them


def _grid(low: np.ndarray, high: np.ndarray, extent: float) -> np.ndarray:
    """Lines along x and z at the bottom of the scene, on round numbers, covering it with a margin:
    on the ground (y = 0) where the scene stands on it or floats less than an extent above, else
    under the scene itself (a site's model thousands of kilometres up its map's axis)."""
    step = nice_step(extent)
    floor_y = float(low[1]) if low[1] > extent else min(float(low[1]), 0.0)
    centre = (low + high) / 2.0
    half = math.ceil(extent * 0.75 / step) * step
    x_from, z_from = (round(centre[axis] / step) * step - half for axis in (0, 2))
    ticks = np.arange(int(round(2 * half / step)) + 1) * step
    rows = []
    for tick in ticks:
        rows += [[x_from + tick, floor_y, z_from], [x_from + tick, floor_y, z_from + 2 * half],
                 [x_from, floor_y, z_from + tick], [x_from + 2 * half, floor_y, z_from + tick]]
    positions = np.array(rows)
    return np.hstack([positions, np.tile(GRID_COLOUR, (len(positions), 1))])


def _axes(model: np.ndarray, lengths: np.ndarray, lightness: float) -> np.ndarray:
    """Three segments from `model`'s origin along its own x, y and z axes, `lengths` long in the world."""
    origin = model[:3, 3]
    rows = []
    for axis in range(3):
        direction = model[:3, axis] / np.linalg.norm(model[:3, axis])
        colour = AXIS_COLOURS[axis] * lightness + (1.0 - lightness)  # paler toward white
        rows += [[*origin, *colour], [*(origin + direction * lengths[axis]), *colour]]
    return np.array(rows)
