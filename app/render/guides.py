"""Draws the grid and axes that marraztu.model.guides lays out: a few hundred segments, written to
one buffer again whenever they change."""

from __future__ import annotations

import moderngl
import numpy as np

from marraztu.model.guides import Guides
from marraztu.render.gpu import load_program

ROW_BYTES = 7 * 4  # x y z r g b level, float32
LEVEL_TOLERANCE = 1e-6  # of a segment's length: a rise this small still lies in a horizontal plane


class GuidesDrawer:
    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self.program = load_program(ctx, "guides")
        self.buffer: moderngl.Buffer | None = None
        self.vao: moderngl.VertexArray | None = None
        self._rows = 0
        self._held: bytes = b""  # what the buffer holds: unchanged guides upload nothing

    def draw(self, guides: Guides, fbo: moderngl.Framebuffer, origin: np.ndarray) -> None:
        """The grid first, hidden by models but hiding nothing (no depth writes), so that the axes on
        it show even where it is seen edge on; then the axes, through the depth test. Positions are
        measured from `origin`, the renderer's frame origin; the renderer sets the program's uniforms."""
        rows = np.concatenate([guides.grid, guides.axes])
        rows[:, :3] -= origin  # x y z first, r g b after
        data = np.ascontiguousarray(np.hstack([rows, _levels(rows)]), dtype="f4").tobytes()
        if data != self._held:
            self._upload(data)
        grid_rows = len(guides.grid)
        fbo.depth_mask = False
        self.vao.render(moderngl.LINES, vertices=grid_rows)
        fbo.depth_mask = True
        self.vao.render(moderngl.LINES, vertices=self._rows - grid_rows, first=grid_rows)

    def _upload(self, data: bytes) -> None:
        if self.buffer is None or self.buffer.size < len(data):
            self.release()
            self.buffer = self.ctx.buffer(reserve=max(len(data), ROW_BYTES))
            self.vao = self.ctx.vertex_array(
                self.program, [(self.buffer, "3f 3f 1f", "in_position", "in_colour", "in_level")])
        self.buffer.write(data)
        self._rows, self._held = len(data) // ROW_BYTES, data

    def release(self) -> None:
        for resource in (self.vao, self.buffer):
            if resource is not None:
                resource.release()
        self.vao = self.buffer = None
        self._held = b""

    def release_program(self) -> None:
        self.release()
        self.program.release()


def _levels(rows: np.ndarray) -> np.ndarray:
    """(N, 1): 1 on both rows of a horizontal segment (the grid, the x and z axes), whose likeliest
    companion is a model lying in its plane, else 0 (guides.glsl pushes the first further)."""
    starts, ends = rows[0::2, :3], rows[1::2, :3]
    rise = np.abs(ends[:, 1] - starts[:, 1])
    level = rise <= LEVEL_TOLERANCE * np.linalg.norm(ends - starts, axis=1)
    return np.repeat(level, 2).astype(np.float64)[:, None]
