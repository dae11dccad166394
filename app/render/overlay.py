"""On-screen text (status line, messages, help, the file prompt, the panels of marraztu.text.panels) with
moderngl-window's TextWriter2D.

The text writer finds its font and program through moderngl-window's resource system, which needs
an "active" context; a bare EGL context is registered with `activate_context` for that.
"""

from __future__ import annotations

import textwrap

import moderngl
import moderngl_window
import numpy as np
from moderngl_window.text.bitmapped import TextWriter2D

from marraztu.render.gpu import load_program
from marraztu.render.layout import Extras, Label

LINE_HEIGHT_PX = 16.0
MARGIN_PX = 6.0
TEXT_SIZE_PX = LINE_HEIGHT_PX * 0.9
# The probe and matrices panels: a little smaller, so that a probe of three vertices and four
# lights still leaves room for the picture in an 800 pixel window.
PANEL_LINE_HEIGHT_PX = 15.0
PANEL_BACKDROP_RGBA = (0.0, 0.0, 0.0, 0.88)  # darker: the panels are read for long, over anything
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

    def draw(self, top_lines: list[str], bottom_lines: list[str], size: tuple[int, int],
             extras: Extras | None = None) -> None:
        """Labels where they point; lines from the top-left corner down, and from the bottom-left
        corner up; then, below the top lines, the side-by-side titles and the right-hand panel, and
        above the bottom lines the bottom panel."""
        width, height = size
        columns = max(10, int((width - 2 * MARGIN_PX) / self.char_width_px))
        # Messages at the bottom keep up to half the height; status and help get what is left, and
        # whatever does not fit says how much is left out rather than running off the window.
        wrapped_bottom = [piece for line in bottom_lines for piece in wrap(line, columns)]
        # The last lines are kept: the file prompt and the latest message.
        bottom_lines = fit_lines(wrapped_bottom[::-1], height / 2 - 2 * MARGIN_PX, LINE_HEIGHT_PX,
                                 "a taller window shows them")[::-1]
        bottom_height = 2 * MARGIN_PX + LINE_HEIGHT_PX * len(bottom_lines) if bottom_lines else 0.0
        top_lines = fit_lines([piece for line in top_lines for piece in wrap(line, columns)],
                              height - bottom_height - 2 * MARGIN_PX, LINE_HEIGHT_PX, "a taller window shows them")
        self.ctx.disable(moderngl.DEPTH_TEST)
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        self.backdrop["u_viewport"].value = (width, height)
        for label in extras.labels if extras is not None else []:  # part of the picture: text covers it
            self._label(label)
        if top_lines:
            self._backdrop(top_lines, height - 2 * MARGIN_PX - LINE_HEIGHT_PX * len(top_lines), height)
        if bottom_lines:
            self._backdrop(bottom_lines, 0.0, 2 * MARGIN_PX + LINE_HEIGHT_PX * len(bottom_lines))
        for row, line in enumerate(top_lines):
            self._line(line, MARGIN_PX, height - MARGIN_PX - LINE_HEIGHT_PX * (row + 0.5))
        for row, line in enumerate(reversed(bottom_lines)):
            self._line(line, MARGIN_PX, MARGIN_PX + LINE_HEIGHT_PX * (row + 0.5))
        if extras is not None:
            below_top = height - (2 * MARGIN_PX + LINE_HEIGHT_PX * len(top_lines) if top_lines else 0.0)
            above_bottom = 2 * MARGIN_PX + LINE_HEIGHT_PX * len(bottom_lines) if bottom_lines else 0.0
            self._extras(extras, width, below_top, above_bottom)
        self.ctx.disable(moderngl.BLEND)

    def _extras(self, extras: Extras, width: int, below_top: float, above_bottom: float) -> None:
        if extras.titles:
            part = width / len(extras.titles)
            for index, title in enumerate(extras.titles):
                left = (index + 0.5) * part - self._text_width(title, LINE_HEIGHT_PX) / 2.0 - MARGIN_PX
                self._block([title], left, below_top, LINE_HEIGHT_PX)
            below_top -= 2 * MARGIN_PX + LINE_HEIGHT_PX
        room_for_bottom = below_top - above_bottom
        if extras.right:
            panel_width = self._text_width(max(extras.right, key=len)) + 2 * MARGIN_PX
            self._block(extras.right, max(width - panel_width, 0.0), below_top)
            # The bottom panel spans the width: it stops below the right-hand one, never over it.
            room_for_bottom -= 2 * MARGIN_PX + PANEL_LINE_HEIGHT_PX * len(extras.right)
        if extras.bottom:
            lines = fit_lines(extras.bottom, room_for_bottom - 2 * MARGIN_PX, PANEL_LINE_HEIGHT_PX,
                              extras.bottom_overflow_hint)
            self._block(lines, 0.0, above_bottom + 2 * MARGIN_PX + PANEL_LINE_HEIGHT_PX * len(lines))

    def _block(self, lines: list[str], left: float, top: float,
               line_height: float = PANEL_LINE_HEIGHT_PX) -> None:
        """Lines with their backdrop, the block's top-left corner at (left, top)."""
        bottom = top - 2 * MARGIN_PX - line_height * len(lines)
        right = left + 2 * MARGIN_PX + self._text_width(max(lines, key=len), line_height)
        self.backdrop["u_colour"].value = PANEL_BACKDROP_RGBA
        self._rectangle(left, bottom, right, top)
        self.backdrop["u_colour"].value = BACKDROP_RGBA
        for row, line in enumerate(lines):
            self._line(line, left + MARGIN_PX, top - MARGIN_PX - line_height * (row + 0.5),
                       line_height)

    def _label(self, label: Label) -> None:
        """Centred on its point, on a tight backdrop."""
        width = self._text_width(label.text) + 4.0
        left, bottom = label.x - width / 2.0, label.y - PANEL_LINE_HEIGHT_PX / 2.0
        self._rectangle(left, bottom, left + width, bottom + PANEL_LINE_HEIGHT_PX)
        half_character = self._text_width(" ") / 2.0
        self._line(label.text, left + 2.0 + half_character, bottom + PANEL_LINE_HEIGHT_PX / 2.0,
                   PANEL_LINE_HEIGHT_PX)

    def _text_width(self, text: str, line_height: float = PANEL_LINE_HEIGHT_PX) -> float:
        return self.char_width_px * line_height / LINE_HEIGHT_PX * len(text)

    def _backdrop(self, lines: list[str], bottom: float, top: float) -> None:
        right = 2 * MARGIN_PX + self.char_width_px * max(len(line) for line in lines)
        self._rectangle(0.0, bottom, right, top)

    def _rectangle(self, left: float, bottom: float, right: float, top: float) -> None:
        corners = np.array([left, bottom, right, bottom, left, top, right, top], dtype="f4")
        self.backdrop_corners.write(corners)
        self.backdrop_vao.render(moderngl.TRIANGLE_STRIP)

    def _line(self, text: str, x: float, y: float, line_height: float = LINE_HEIGHT_PX) -> None:
        """(x, y) is the centre of the first character: that is how the writer places text."""
        if not text:
            return
        self.writer.text = text
        size = TEXT_SIZE_PX * line_height / LINE_HEIGHT_PX
        self.writer.draw((x, y), size=size)


def fit_lines(lines: list[str], room_px: float, line_height: float, hint: str = "") -> list[str]:
    """The first lines that fit in `room_px`, the last of them replaced by a note of how many more
    there are (and how to make room) when they do not all fit."""
    fitting = max(int(room_px // line_height), 1)
    if len(lines) <= fitting:
        return lines
    shown = max(fitting - 1, 0)
    note = f"... {len(lines) - shown} more lines{': ' + hint if hint else ''}"
    return lines[:shown] + [note]


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
