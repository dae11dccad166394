"""On-screen text (status line, messages, help, the file prompt) with moderngl-window's TextWriter2D.

The text writer finds its font and program through moderngl-window's resource system, which needs
an "active" context; a bare EGL context is registered with `activate_context` for that.
"""

from __future__ import annotations

import textwrap

import moderngl
import moderngl_window
import numpy as np
from moderngl_window.text.bitmapped import TextWriter2D

from app.gpu import load_program

LINE_HEIGHT_PX = 16.0
MARGIN_PX = 6.0
TEXT_SIZE_PX = LINE_HEIGHT_PX * 0.9
BACKDROP_RGBA = (0.0, 0.0, 0.0, 0.6)
NO_BREAK = "\u00a0"


class Overlay:
    def __init__(self, ctx: moderngl.Context) -> None:
        try:
            moderngl_window.ctx()
        except ValueError:
            moderngl_window.activate_context(ctx=ctx)
        self.ctx = ctx
        self.writer = TextWriter2D()
        self.char_width_px = self.writer._meta.char_aspect_wh * TEXT_SIZE_PX  # no public getter
        self.backdrop = load_program(ctx, "backdrop")
        self.backdrop["u_colour"].value = BACKDROP_RGBA
        self.backdrop_corners = ctx.buffer(reserve=2 * 4 * 4)
        self.backdrop_vao = ctx.vertex_array(self.backdrop, [(self.backdrop_corners, "2f", "in_position")])

    def draw(self, top_lines: list[str], bottom_lines: list[str], size: tuple[int, int]) -> None:
        """Lines from the top-left corner down, and from the bottom-left corner up."""
        width, height = size
        columns = max(10, int((width - 2 * MARGIN_PX) / self.char_width_px))
        top_lines = [piece for line in top_lines for piece in wrap(line, columns)]
        bottom_lines = [piece for line in bottom_lines for piece in wrap(line, columns)]
        self.ctx.disable(moderngl.DEPTH_TEST)
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        self.backdrop["u_viewport"].value = (width, height)
        if top_lines:
            self._backdrop(top_lines, height - 2 * MARGIN_PX - LINE_HEIGHT_PX * len(top_lines), height)
        if bottom_lines:
            self._backdrop(bottom_lines, 0.0, 2 * MARGIN_PX + LINE_HEIGHT_PX * len(bottom_lines))
        for row, line in enumerate(top_lines):
            self._line(line, MARGIN_PX, height - MARGIN_PX - LINE_HEIGHT_PX * (row + 0.5))
        for row, line in enumerate(reversed(bottom_lines)):
            self._line(line, MARGIN_PX, MARGIN_PX + LINE_HEIGHT_PX * (row + 0.5))
        self.ctx.disable(moderngl.BLEND)

    def _backdrop(self, lines: list[str], bottom: float, top: float) -> None:
        right = 2 * MARGIN_PX + self.char_width_px * max(len(line) for line in lines)
        corners = np.array([0, bottom, right, bottom, 0, top, right, top], dtype="f4")
        self.backdrop_corners.write(corners)
        self.backdrop_vao.render(moderngl.TRIANGLE_STRIP)

    def _line(self, text: str, x: float, y: float) -> None:
        if not text:
            return
        self.writer.text = text
        self.writer.draw((x, y), size=TEXT_SIZE_PX)


def wrap(line: str, columns: int) -> list[str]:
    """Fits a line to the width, breaking the status line only at its " | " separators.

    Spaces inside a status field become no-break spaces for textwrap (which breaks only at ASCII
    whitespace), so a field is never split unless it alone is wider than the window.
    """
    if " | " in line:
        line = " | ".join(field.replace(" ", NO_BREAK) for field in line.split(" | "))
    pieces = textwrap.wrap(line, columns, subsequent_indent="  ", break_on_hyphens=False,
                           drop_whitespace=True) or [""]
    return [piece.replace(NO_BREAK, " ") for piece in pieces]
