"""Text of the pipeline panel (key `P`): the selected face's corners from model space to the window,
the matrices that carry them, the perspective divide written out, and what clipping and culling
decide. Plain strings; the overlay draws them in the bottom panel."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from marraztu.model.pipeline import CornerStages, FacePipeline, face_pipeline
from marraztu.model.scene import PERSPECTIVE_FOVY_DEG, Lens, Projection, Scene
from marraztu.text.numbers import aligned_columns, fixed, matrix_entries, position_decimals, significant

MAX_CORNERS = 4  # more would not fit an 800 pixel window; the panel says how many are left
INDENT = "       "
ENTRY_WIDTH = 7  # characters of a matrix entry, at least
BLOCK_WIDTH = 32  # characters: a matrix of such entries and its title


def pipeline_lines(scene: Scene, viewport: tuple[int, int, int, int]) -> list[str]:
    """The panel: empty unless the pipeline view is on."""
    if not scene.modes.pipeline:
        return []
    found = face_pipeline(scene, viewport, MAX_CORNERS)
    if found is None:
        return ["PIPELINE: no face to follow (select an object with TAB)"]
    lines = _header(found, probe_hidden=scene.modes.probe)
    for number, corner in enumerate(found.corners, start=1):
        lines += _corner_lines(found, number, corner)
    hidden = found.corner_count - MAX_CORNERS
    if hidden > 0:
        lines.append(f"(and {hidden} more corners of this polygon, carried the same way)")
    lines.append(_culling_line(found))
    return lines


def _header(found: FacePipeline, probe_hidden: bool) -> list[str]:
    width, height = found.viewport[2], found.viewport[3]
    note = "   (the probe, i, waits behind this panel)" if probe_hidden else ""
    lines = [f"PIPELINE {found.obj.name} face {found.face + 1}/{found.face_count} (Enter: next)   "
             f"{width}x{height}, {lens_shape(found.lens)}{note}",
             "world = M model   eye = V world   clip = P eye   ndc = clip.xyz / w   window = viewport(ndc), y up from "
             "the bottom, as GL counts it"]
    blocks = [[f"M: model of {found.obj.name}", *_matrix_rows(found.model_matrix, 2)],
              ["V: view", *_matrix_rows(found.view_matrix, 2)],
              [f"P: {lens_numbers(found.lens)}", *_matrix_rows(found.projection_matrix, 3)]]
    return lines + _side_by_side(blocks)


def lens_shape(lens: Lens) -> str:
    """How P's view is shaped, in the words the pipeline and matrices panels share."""
    if lens.half_height is None:
        return f"{lens.projection.value} {PERSPECTIVE_FOVY_DEG:g} deg high"
    return f"{lens.projection.value}, half height {significant(lens.half_height)}"


def lens_numbers(lens: Lens) -> str:
    """P's other numbers: the near and far planes follow what is shown, so a camera's move changes P."""
    return f"aspect {lens.aspect:.2f}, near plane {significant(lens.near)}, far plane {significant(lens.far)}"


def _corner_lines(found: FacePipeline, number: int, corner: CornerStages) -> list[str]:
    decimals = position_decimals(found.obj.mesh.size, 1)
    clip = 3 if found.lens.projection is Projection.PARALLEL else decimals  # parallel's clip is its ndc (w = 1)
    lines = [f"v{number} #{corner.vertex + 1:<4} model {_vector(corner.model, decimals)} -> world "
             f"{_vector(corner.world, decimals)} -> eye {_vector(corner.eye, decimals)}",
             f"{INDENT}clip {_vector(corner.clip[:3], clip)} w {corner.clip[3]:.{clip + 1}f}"]
    if corner.ndc is None or corner.window is None:
        lines[-1] += "  w <= 0: behind the eye, no divide"
    else:
        lines[-1] += (f"  / w -> ndc {_vector(corner.ndc, 3)} -> window x {corner.window[0]:.1f} "
                      f"y {corner.window[1]:.1f} depth {corner.window[2]:.4f}")
    lines += [INDENT + line for line in _clip_verdict(found, corner)]
    return lines


def _clip_verdict(found: FacePipeline, corner: CornerStages) -> list[str]:
    if not corner.outside:
        return ["inside the clip volume (-w <= x, y, z <= w): kept whole"]
    lines = ["outside the clip volume, beyond the planes: " + ", ".join(corner.outside) + " (the polygon is cut there)"]
    if "near" in corner.outside:
        behind = "; w <= 0: behind the eye too" if corner.behind_eye else ""
        eye_z = f"{corner.eye[2]:.{position_decimals(found.obj.mesh.size, 2)}f}"
        lines.append(f"near plane: eye z {eye_z} > -{found.lens.near:g}, nearer than it, so clip z < -w{behind}")
    return lines


def _culling_line(found: FacePipeline) -> str:
    verdict = "a front face, drawn"
    if found.back_face:
        verdict = "a back face, culled (b)" if found.culled else "a back face, drawn red (b culls it)"
    return f"culling: face normal . V at v1 {found.facing:.3f} {'<= 0' if found.back_face else '> 0'}: {verdict}"


def _matrix_rows(matrix: np.ndarray, decimals: int) -> list[str]:
    return aligned_columns(matrix_entries(matrix, decimals), ENTRY_WIDTH)


def _side_by_side(blocks: list[list[str]]) -> list[str]:
    """Blocks of lines set beside each other, each as wide as its widest line and at least
    BLOCK_WIDTH: a wide entry moves the blocks after it on every line, and its title with them."""
    widths = [max(BLOCK_WIDTH, 1 + max(len(line) for line in block)) for block in blocks]
    return ["".join(f"{block[k]:<{width}}" for block, width in zip(blocks, widths)).rstrip()
            for k in range(len(blocks[0]))]


def _vector(values: Sequence[float] | np.ndarray, decimals: int = 1) -> str:
    return "(" + " ".join(fixed(value, decimals) for value in values) + ")"
