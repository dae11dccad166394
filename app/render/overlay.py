"""On-screen text: the status line, messages, help, the file prompt and the panels of
marraztu.text.panels, on translucent backdrops.

The font is moderngl-window's Vera Mono atlas, scaled once to the pixel size it is drawn at and drawn
pixel for pixel: scaled while drawing, as moderngl-window's text writer does, its thin strokes
(the dot of an i, the stems of m, T and 1) fade into the background.
"""

from __future__ import annotations

import json
import re
import textwrap
from collections.abc import Callable
from dataclasses import replace
from functools import cache
from importlib.resources import files

import moderngl
import numpy as np
from PIL import Image

from marraztu.render.context import check_gl
from marraztu.render.gpu import load_program
from marraztu.render.layout import Extras, Label, holds_a_label

LINE_HEIGHT_PX = 16.0
MARGIN_PX = 6.0
# A character's cell, width and height in pixels: Vera Mono's proportions at 14 pixels, and at 13 for
# the panels, whose lines of about 110 characters must fit an 800 pixel window.
CELL_PX = (7, 14)
PANEL_CELL_PX = (6, 13)
ATLAS_COLUMNS = 16
FONT_FOLDER = "text/bitmapped/bitmapped"  # inside the moderngl_window package
TEXT_RGBA = (1.0, 1.0, 1.0, 1.0)
# The probe and matrices panels: a little smaller, so that a probe of three vertices and four
# lights still leaves room for the picture in an 800 pixel window.
PANEL_LINE_HEIGHT_PX = 15.0
PANEL_BACKDROP_RGBA = (0.0, 0.0, 0.0, 0.88)  # darker: the panels are read for long, over anything
BACKDROP_RGBA = (0.0, 0.0, 0.0, 0.6)
NO_BREAK = "\u00a0"
CUT_MARK = "\u00bb"  # ends a line cut at the window's edge: the font has no ellipsis
# What textwrap turns into spaces (tabs into several): a short line of none, ending in no blank, is kept whole.
_WRAPPED_WHITESPACE = re.compile("[\t\n\x0b\x0c\r]")


@cache
def glyph_atlas(cell: tuple[int, int]) -> tuple[np.ndarray, dict[int, int]]:
    """The font's characters at `cell` pixels, ATLAS_COLUMNS to a row of cells, as coverage (rows top
    first), and each character's cell by code point."""
    folder = files("moderngl_window").joinpath(FONT_FOLDER)
    meta = json.loads(folder.joinpath("text/meta.json").read_text())
    width, height = cell
    with Image.open(folder.joinpath("textures/VeraMono.png")) as image:  # characters stacked top down
        coverage = image.getchannel("A").resize((width, height * meta["characters"]), Image.Resampling.LANCZOS)
    cells = np.asarray(coverage).reshape(meta["characters"], height, width)
    rows = -(-len(cells) // ATLAS_COLUMNS)
    grid = np.zeros((rows * ATLAS_COLUMNS, height, width), np.uint8)
    grid[:len(cells)] = cells
    atlas = grid.reshape(rows, ATLAS_COLUMNS, height, width).transpose(0, 2, 1, 3)
    code_points = [code for span in meta["character_ranges"] for code in range(span["min"], span["max"] + 1)]
    return atlas.reshape(rows * height, ATLAS_COLUMNS * width), {code: index for index, code
                                                                 in enumerate(code_points)}


class Font:
    """One size of the font: its atlas on the GPU and where each character is in it."""

    def __init__(self, ctx: moderngl.Context, cell: tuple[int, int]) -> None:
        atlas, self.cell_of = glyph_atlas(cell)
        self.cell = cell
        self.unknown = self.cell_of[ord("?")]
        self.atlas_cells = (ATLAS_COLUMNS, atlas.shape[0] // cell[1])
        self.texture = ctx.texture((atlas.shape[1], atlas.shape[0]), 1, np.ascontiguousarray(np.flipud(atlas)),
                                   alignment=1)
        self.texture.filter = (moderngl.NEAREST, moderngl.NEAREST)  # one texel to one pixel

    def cells(self, text: str) -> list[int]:
        return [self.cell_of.get(ord(char), self.unknown) for char in text]


class Overlay:
    def __init__(self, ctx: moderngl.Context) -> None:
        self.ctx = ctx
        self.fonts = {LINE_HEIGHT_PX: Font(ctx, CELL_PX), PANEL_LINE_HEIGHT_PX: Font(ctx, PANEL_CELL_PX)}
        self.char_width_px = float(CELL_PX[0])
        self.text = load_program(ctx, "text")
        self.text["u_atlas"].value = 1
        self.text["u_colour"].value = TEXT_RGBA
        self.glyphs = ctx.buffer(reserve=1024 * 12)
        self.glyph_vao = ctx.vertex_array(self.text, [(self.glyphs, "2f 1f/i", "in_origin", "in_glyph")])
        check_gl(ctx, "the overlay's font")
        self.backdrop = load_program(ctx, "backdrop")
        self.backdrop["u_colour"].value = BACKDROP_RGBA
        self.backdrop_corners = ctx.buffer(reserve=2 * 4 * 4)
        self.backdrop_vao = ctx.vertex_array(self.backdrop, [(self.backdrop_corners, "2f", "in_position")])

    def release(self) -> None:
        for resource in (self.glyph_vao, self.glyphs, self.text, self.backdrop_vao, self.backdrop_corners,
                         self.backdrop, *(font.texture for font in self.fonts.values())):
            resource.release()

    def draw(self, top_lines: list[str], bottom_lines: list[str], size: tuple[int, int],
             extras: Extras | None = None) -> None:
        """Labels where they point; lines from the top-left corner down, and from the bottom-left
        corner up; then, below the top lines, the side-by-side titles and the right-hand panel, and
        above the bottom lines the bottom panel."""
        width, height = size
        top_lines, bottom_lines = self._fitted(top_lines, bottom_lines, size, extras)
        bottom_height = block_height(len(bottom_lines), LINE_HEIGHT_PX)
        if extras is not None:
            extras = replace(extras, labels=spread_labels(extras.labels, self._label_width))
        self.ctx.disable(moderngl.DEPTH_TEST)
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        self.backdrop["u_viewport"].value = (width, height)
        self.text["u_viewport"].value = (width, height)
        for label in extras.labels if extras is not None else []:  # part of the picture: text covers it
            self._label(label)
        if top_lines:
            self._backdrop(top_lines, height - block_height(len(top_lines), LINE_HEIGHT_PX), height)
        if bottom_lines:
            self._backdrop(bottom_lines, 0.0, bottom_height)
        for row, line in enumerate(top_lines):
            self._line(line, MARGIN_PX, height - MARGIN_PX - LINE_HEIGHT_PX * (row + 0.5))
        for row, line in enumerate(reversed(bottom_lines)):
            self._line(line, MARGIN_PX, MARGIN_PX + LINE_HEIGHT_PX * (row + 0.5))
        if extras is not None:
            self._extras(extras, width, height - block_height(len(top_lines), LINE_HEIGHT_PX), bottom_height)
        self.ctx.disable(moderngl.BLEND)

    def _fitted(self, top_lines: list[str], bottom_lines: list[str], size: tuple[int, int],
                extras: Extras | None) -> tuple[list[str], list[str]]:
        """The top and bottom lines wrapped and fitted, in order: the messages at the bottom keep up to
        half the height (a line, where the window holds one); the status line a line; each panel that
        is on a line; status and help what is left. Whatever does not fit says how much is left out;
        what has no room for a line, or a character, is not drawn."""
        width, height = size
        fitting = int((width - 2 * MARGIN_PX) / self.char_width_px)
        columns = max(10, fitting)
        wrapped_bottom = [piece for line in bottom_lines for piece in wrap(line, columns)]
        bottom_room = max(height / 2, min(height, block_height(1, LINE_HEIGHT_PX))) - 2 * MARGIN_PX
        # The last lines are kept: the file prompt and the latest message. The notes of what is left
        # out, and any line in a window under ten columns, are cut, not wrapped.
        bottom_lines = cut_lines(fit_lines(wrapped_bottom[::-1], bottom_room, LINE_HEIGHT_PX,
                                           "a taller window shows them")[::-1], fitting)
        top_room = height - block_height(len(bottom_lines), LINE_HEIGHT_PX) - 2 * MARGIN_PX
        top_room -= panels_first_lines(extras, top_room - LINE_HEIGHT_PX)
        top_lines = cut_lines(fit_lines([piece for line in top_lines for piece in wrap(line, columns)], top_room,
                                        LINE_HEIGHT_PX, "a taller window shows them"), fitting)
        return top_lines, bottom_lines

    def _extras(self, extras: Extras, width: int, below_top: float, above_bottom: float) -> None:
        if extras.titles and below_top - above_bottom >= block_height(1, LINE_HEIGHT_PX):
            self._titles(extras.titles, width, below_top)
            below_top -= block_height(1, LINE_HEIGHT_PX)
        room_for_bottom = below_top - above_bottom
        panel_columns = int((width - 2 * MARGIN_PX) / PANEL_CELL_PX[0])
        if extras.right:
            # Fitted as the bottom panel is, leaving that panel two lines: it never ran off the window.
            kept_for_bottom = block_height(2, PANEL_LINE_HEIGHT_PX) if extras.bottom else 0.0
            right = cut_lines(fit_lines(extras.right, room_for_bottom - 2 * MARGIN_PX - kept_for_bottom,
                                        PANEL_LINE_HEIGHT_PX, "a taller window shows them"), panel_columns)
            if right:
                self._block(right, max(width - self._block_width(right), 0.0), below_top)
            # The bottom panel spans the width: it stops below the right-hand one, never over it.
            room_for_bottom -= block_height(len(right), PANEL_LINE_HEIGHT_PX)
        if extras.bottom:
            lines = cut_lines(fit_lines(extras.bottom, room_for_bottom - 2 * MARGIN_PX, PANEL_LINE_HEIGHT_PX,
                                        extras.bottom_overflow_hint), panel_columns)
            if lines:
                self._block(lines, 0.0, self._bottom_panel_top(extras, lines, above_bottom + room_for_bottom,
                                                               above_bottom))

    def _titles(self, titles: list[str], width: int, top: float) -> None:
        """Each title centred over its view, and kept inside it: cut where the view is narrower."""
        part = width / len(titles)
        columns = int((part - 2 * MARGIN_PX) / CELL_PX[0])
        for index, title in enumerate(cut_lines(titles, columns)):
            if not title:
                continue
            title_width = self._block_width([title], LINE_HEIGHT_PX)
            left = min(max((index + 0.5) * part - title_width / 2.0, index * part), (index + 1) * part - title_width)
            self._block([title], left, top, LINE_HEIGHT_PX)

    def _bottom_panel_top(self, extras: Extras, lines: list[str], room_top: float, above_bottom: float) -> float:
        """Above the bottom lines; at the top of its room (under the top lines and the right-hand panel)
        where the face it is about lies under it there and not here (the probe's four corners fill half
        the picture)."""
        height, right = block_height(len(lines), PANEL_LINE_HEIGHT_PX), self._block_width(lines)
        low = above_bottom + height
        if not holds_a_label(extras.labels, above_bottom, low, right):
            return low
        return room_top if not holds_a_label(extras.labels, room_top - height, room_top, right) else low

    def _block(self, lines: list[str], left: float, top: float,
               line_height: float = PANEL_LINE_HEIGHT_PX) -> None:
        """Lines with their backdrop, the block's top-left corner at (left, top)."""
        bottom, right = top - block_height(len(lines), line_height), left + self._block_width(lines, line_height)
        self.backdrop["u_colour"].value = PANEL_BACKDROP_RGBA
        self._rectangle(left, bottom, right, top)
        self.backdrop["u_colour"].value = BACKDROP_RGBA
        for row, line in enumerate(lines):
            self._line(line, left + MARGIN_PX, top - MARGIN_PX - line_height * (row + 0.5),
                       line_height)

    def _block_width(self, lines: list[str], line_height: float = PANEL_LINE_HEIGHT_PX) -> float:
        """A block's width: its longest line with a margin each side."""
        return 2 * MARGIN_PX + self._text_width(max(lines, key=len), line_height)

    def _label_width(self, label: Label) -> float:
        return self._text_width(label.text) + 4.0

    def _label(self, label: Label) -> None:
        """Centred on its point, on a tight backdrop."""
        width = self._label_width(label)
        left, bottom = label.x - width / 2.0, label.y - PANEL_LINE_HEIGHT_PX / 2.0
        self._rectangle(left, bottom, left + width, bottom + PANEL_LINE_HEIGHT_PX)
        half_character = self._text_width(" ") / 2.0
        self._line(label.text, left + 2.0 + half_character, bottom + PANEL_LINE_HEIGHT_PX / 2.0,
                   PANEL_LINE_HEIGHT_PX)

    def _text_width(self, text: str, line_height: float = PANEL_LINE_HEIGHT_PX) -> float:
        return self.fonts[line_height].cell[0] * len(text)

    def _backdrop(self, lines: list[str], bottom: float, top: float) -> None:
        self._rectangle(0.0, bottom, self._block_width(lines, LINE_HEIGHT_PX), top)

    def _rectangle(self, left: float, bottom: float, right: float, top: float) -> None:
        corners = np.array([left, bottom, right, bottom, left, top, right, top], dtype="f4")
        self.backdrop_corners.write(corners)
        self.backdrop_vao.render(moderngl.TRIANGLE_STRIP)

    def _line(self, text: str, x: float, y: float, line_height: float = LINE_HEIGHT_PX) -> None:
        """(x, y) is the centre of the first character; characters land on whole pixels."""
        if not text:
            return
        font = self.fonts[line_height]
        width, height = font.cell
        left, bottom = round(x - width / 2.0), round(y - height / 2.0)
        glyphs = np.empty((len(text), 3), "f4")
        glyphs[:, 0] = left + width * np.arange(len(text))
        glyphs[:, 1] = bottom
        glyphs[:, 2] = font.cells(text)
        data = glyphs.tobytes()
        if len(data) > self.glyphs.size:
            self.glyphs.orphan(len(data))
        self.glyphs.write(data)
        self.text["u_cell"].value = font.cell
        self.text["u_atlas_cells"].value = font.atlas_cells
        font.texture.use(location=1)
        self.glyph_vao.render(moderngl.TRIANGLE_STRIP, vertices=4, instances=len(text))


def fit_lines(lines: list[str], room_px: float, line_height: float, hint: str = "") -> list[str]:
    """The first lines that fit in `room_px`, the last of them replaced by a note of how many more
    there are (and how to make room) when they do not all fit; none where not one line fits."""
    fitting = max(int(room_px // line_height), 0)
    if len(lines) <= fitting:
        return lines
    if not fitting:
        return []
    shown = fitting - 1
    note = f"... {len(lines) - shown} more lines{': ' + hint if hint else ''}"
    return lines[:shown] + [note]


def panels_first_lines(extras: Extras | None, room_px: float) -> float:
    """The height the panels that are on take with a line each, as far as they fit in `room_px` in the
    order _extras lays them out: the titles, then the right-hand panel with the two lines it leaves the
    bottom one, or else the bottom one alone."""
    if extras is None:
        return 0.0
    titles = block_height(1, LINE_HEIGHT_PX) if extras.titles and block_height(1, LINE_HEIGHT_PX) <= room_px else 0.0
    room_px -= titles
    right = block_height(1, PANEL_LINE_HEIGHT_PX) if extras.right else 0.0
    bottom = block_height(2 if extras.right else 1, PANEL_LINE_HEIGHT_PX) if extras.bottom else 0.0
    lone_bottom = block_height(1, PANEL_LINE_HEIGHT_PX) if extras.bottom else 0.0
    return titles + next((need for need in (right + bottom, lone_bottom) if need <= room_px), 0.0)


def block_height(lines: int, line_height: float) -> float:
    """A block of `lines` lines with a margin above and below them; nothing for no lines."""
    return 2 * MARGIN_PX + line_height * lines if lines else 0.0


def cut_lines(lines: list[str], columns: int) -> list[str]:
    """Each line, or as much of it as fits `columns` with CUT_MARK at its end to say it goes on; none
    where not one column fits."""
    if columns < 1:
        return []
    return [line if len(line) <= columns else line[:columns - 1] + CUT_MARK for line in lines]


def spread_labels(labels: list[Label], width_of: Callable[[Label], float]) -> list[Label]:
    """The labels, each moved sideways off those before it that it would cover (a polygon's vertices
    a few pixels apart on the screen: "v3" and "v4" read "v43")."""
    placed: list[Label] = []
    for label in labels:
        for _ in range(len(placed)):
            covered = next((other for other in placed if _covers(other, label, width_of)), None)
            if covered is None:
                break
            side = 1.0 if label.x >= covered.x else -1.0
            label = replace(label, x=covered.x + side * (width_of(covered) + width_of(label)) / 2.0)
        placed.append(label)
    return placed


def _covers(one: Label, other: Label, width_of: Callable[[Label], float]) -> bool:
    return (abs(one.y - other.y) < PANEL_LINE_HEIGHT_PX
            and abs(one.x - other.x) < (width_of(one) + width_of(other)) / 2.0)


def wrap(line: str, columns: int) -> list[str]:
    """Fits a line to the width, breaking the status line only at its " | " separators.

    Spaces inside a status field become no-break spaces for textwrap (which breaks only at ASCII
    whitespace), so a field is never split unless it alone is wider than the window.
    """
    if " | " in line:
        line = " | ".join(field.replace(" ", NO_BREAK) for field in line.split(" | "))
    if len(line) <= columns and not _WRAPPED_WHITESPACE.search(line) and not line[-1:].isspace():
        return [line.replace(NO_BREAK, " ")]  # textwrap's answer, without its work
    pieces = textwrap.wrap(line, columns, subsequent_indent="  ", break_on_hyphens=False,
                           drop_whitespace=True) or [""]
    return [piece.replace(NO_BREAK, " ") for piece in pieces]
