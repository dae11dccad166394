"""On-screen text: the status line, messages, help, the file prompt and the panels of
marraztu.text.panels, on translucent backdrops.

The font is moderngl-window's Vera Mono atlas, scaled once to the pixel size it is drawn at and drawn
pixel for pixel: scaled while drawing, as moderngl-window's text writer does, its thin strokes
(the dot of an i, the stems of m, T and 1) fade into the background. Every length of the text is its
length at 800x800 times layout.screen_scale, rounded to whole pixels, so that a projector's or a HiDPI
screen's framebuffer gets text as large, to the eye, as an 800 pixel window's.
"""

from __future__ import annotations

import json
import re
import textwrap
from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import cache, lru_cache
from importlib.resources import files

import moderngl
import numpy as np
from PIL import Image

from marraztu.render.context import check_gl
from marraztu.render.gpu import load_program
from marraztu.render.layout import Extras, Label, labels_covered, scaled_px

# The lengths below are those of a window of up to 800x800; text_sizes scales them to larger ones.
LINE_HEIGHT_PX = 16.0
MARGIN_PX = 6.0
LABEL_PADDING_PX = 2.0  # each side of a vertex label's text, inside its backdrop
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


@dataclass(frozen=True)
class Lettering:
    """One size of the overlay's text, in pixels: a character's cell (width, height) and a line's height."""

    cell: tuple[int, int]
    line_height: float


@dataclass(frozen=True)
class TextSizes:
    """The overlay's lengths at one framebuffer size, in whole pixels."""

    lines: Lettering  # the status line, the help, the messages and the side-by-side titles
    panels: Lettering  # the probe, matrices and pipeline panels and the vertex labels
    margin: float
    label_padding: float

    def block_height(self, lines: int, lettering: Lettering) -> float:
        """A block of `lines` lines with a margin above and below them; nothing for no lines."""
        return 2 * self.margin + lettering.line_height * lines if lines else 0.0


def text_sizes(size: tuple[int, int]) -> TextSizes:
    """The lengths at 800x800 scaled to a framebuffer of `size` (layout.screen_scale), each rounded."""
    def cell(width_height: tuple[int, int]) -> tuple[int, int]:
        return scaled_px(width_height[0], size), scaled_px(width_height[1], size)

    def length(px: float) -> float:
        return float(scaled_px(px, size))

    return TextSizes(lines=Lettering(cell(CELL_PX), length(LINE_HEIGHT_PX)),
                     panels=Lettering(cell(PANEL_CELL_PX), length(PANEL_LINE_HEIGHT_PX)),
                     margin=length(MARGIN_PX), label_padding=length(LABEL_PADDING_PX))


@cache  # decoding the font's picture takes twice as long as scaling it: a window made larger scales it again
def _font_picture() -> tuple[Image.Image, dict]:
    """The font's characters stacked top down, as coverage, and its description (moderngl-window's)."""
    folder = files("moderngl_window").joinpath(FONT_FOLDER)
    with Image.open(folder.joinpath("textures/VeraMono.png")) as image:
        return image.getchannel("A"), json.loads(folder.joinpath("text/meta.json").read_text())


@lru_cache(maxsize=8)  # a window dragged larger meets a new cell every few dozen pixels: keep the latest
def glyph_atlas(cell: tuple[int, int]) -> tuple[np.ndarray, dict[int, int]]:
    """The font's characters at `cell` pixels, ATLAS_COLUMNS to a row of cells, as coverage (rows top
    first), and each character's cell by code point."""
    picture, meta = _font_picture()
    width, height = cell
    coverage = picture.resize((width, height * meta["characters"]), Image.Resampling.LANCZOS)
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
        self.fonts: dict[tuple[int, int], Font] = {}  # by cell: the two the last size drawn needs
        self._sized_for: tuple[int, int] | None = None  # the framebuffer size `sizes` and `fonts` are for
        self._fit_text_to((1, 1))  # the fonts of any window up to 800x800: a GPU that refuses them says so now
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

    def _fit_text_to(self, size: tuple[int, int]) -> None:
        """The text's sizes for a framebuffer of `size`: fonts are made at the first frame that needs
        them, and those no longer needed released; nothing to do while the size stays."""
        if tuple(size) == self._sized_for:
            return
        self._sized_for = (size[0], size[1])
        self.sizes = text_sizes(size)
        cells = {self.sizes.lines.cell, self.sizes.panels.cell}
        for cell in self.fonts.keys() - cells:
            self.fonts.pop(cell).texture.release()
        for cell in cells - self.fonts.keys():
            self.fonts[cell] = Font(self.ctx, cell)
            check_gl(self.ctx, "the overlay's font")

    def draw(self, top_lines: list[str], bottom_lines: list[str], size: tuple[int, int],
             extras: Extras | None = None) -> None:
        """Labels where they point; lines from the top-left corner down, and from the bottom-left
        corner up; then, below the top lines, the side-by-side titles and the right-hand panel, and
        above the bottom lines the bottom panel."""
        width, height = size
        self._fit_text_to(size)
        sizes, letters = self.sizes, self.sizes.lines
        top_lines, bottom_lines = self._fitted(top_lines, bottom_lines, size, extras)
        bottom_height = sizes.block_height(len(bottom_lines), letters)
        if extras is not None:
            extras = replace(extras, labels=spread_labels(extras.labels, self._label_width,
                                                          sizes.panels.line_height))
        self.ctx.disable(moderngl.DEPTH_TEST)
        self.ctx.enable(moderngl.BLEND)
        self.ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        self.backdrop["u_viewport"].value = (width, height)
        self.text["u_viewport"].value = (width, height)
        for label in extras.labels if extras is not None else []:  # part of the picture: text covers it
            self._label(label)
        if top_lines:
            self._backdrop(top_lines, height - sizes.block_height(len(top_lines), letters), height)
        if bottom_lines:
            self._backdrop(bottom_lines, 0.0, bottom_height)
        for row, line in enumerate(top_lines):
            self._line(line, sizes.margin, height - sizes.margin - letters.line_height * (row + 0.5), letters)
        for row, line in enumerate(reversed(bottom_lines)):
            self._line(line, sizes.margin, sizes.margin + letters.line_height * (row + 0.5), letters)
        if extras is not None:
            self._extras(extras, width, height - sizes.block_height(len(top_lines), letters), bottom_height)
        self.ctx.disable(moderngl.BLEND)

    def _fitted(self, top_lines: list[str], bottom_lines: list[str], size: tuple[int, int],
                extras: Extras | None) -> tuple[list[str], list[str]]:
        """The top and bottom lines wrapped and fitted, in order: the messages at the bottom keep up to
        half the height (a line, where the window holds one); the status line a line; each panel that
        is on a line; status and help what is left. Whatever does not fit says how much is left out;
        what has no room for a line, or a character, is not drawn."""
        width, height = size
        sizes, letters = self.sizes, self.sizes.lines
        fitting = int((width - 2 * sizes.margin) / letters.cell[0])
        columns = max(10, fitting)
        wrapped_bottom = [piece for line in bottom_lines for piece in wrap(line, columns)]
        bottom_room = max(height / 2, min(height, sizes.block_height(1, letters))) - 2 * sizes.margin
        # The last lines are kept: the file prompt and the latest message. The notes of what is left
        # out, and any line in a window under ten columns, are cut, not wrapped.
        bottom_lines = cut_lines(fit_lines(wrapped_bottom[::-1], bottom_room, letters.line_height,
                                           "a taller window shows them")[::-1], fitting)
        top_room = height - sizes.block_height(len(bottom_lines), letters) - 2 * sizes.margin
        top_room -= panels_first_lines(extras, top_room - letters.line_height, sizes)
        top_lines = cut_lines(fit_lines([piece for line in top_lines for piece in wrap(line, columns)], top_room,
                                        letters.line_height, "a taller window shows them"), fitting)
        return top_lines, bottom_lines

    def _extras(self, extras: Extras, width: int, below_top: float, above_bottom: float) -> None:
        sizes, panels = self.sizes, self.sizes.panels
        if extras.titles and below_top - above_bottom >= sizes.block_height(1, sizes.lines):
            self._titles(extras.titles, width, below_top)
            below_top -= sizes.block_height(1, sizes.lines)
        room_for_bottom = below_top - above_bottom
        panel_columns = int((width - 2 * sizes.margin) / panels.cell[0])
        if extras.right:
            # Fitted as the bottom panel is, leaving that panel two lines: it never ran off the window.
            kept_for_bottom = sizes.block_height(2, panels) if extras.bottom else 0.0
            right = cut_lines(fit_lines(extras.right, room_for_bottom - 2 * sizes.margin - kept_for_bottom,
                                        panels.line_height, "a taller window shows them"), panel_columns)
            if right:
                self._block(right, max(width - self._block_width(right, panels), 0.0), below_top, panels)
            # The bottom panel spans the width: it stops below the right-hand one, never over it.
            room_for_bottom -= sizes.block_height(len(right), panels)
        if extras.bottom:
            lines = cut_lines(fit_lines(extras.bottom, room_for_bottom - 2 * sizes.margin, panels.line_height,
                                        extras.bottom_overflow_hint), panel_columns)
            if lines:
                self._block(lines, 0.0, self._bottom_panel_top(extras, lines, above_bottom + room_for_bottom,
                                                               above_bottom), panels)

    def _titles(self, titles: list[str], width: int, top: float) -> None:
        """Each title centred over its view, and kept inside it: cut where the view is narrower."""
        lines = self.sizes.lines
        part = width / len(titles)
        columns = int((part - 2 * self.sizes.margin) / lines.cell[0])
        for index, title in enumerate(cut_lines(titles, columns)):
            if not title:
                continue
            title_width = self._block_width([title], lines)
            left = min(max((index + 0.5) * part - title_width / 2.0, index * part), (index + 1) * part - title_width)
            self._block([title], left, top, lines)

    def _bottom_panel_top(self, extras: Extras, lines: list[str], room_top: float, above_bottom: float) -> float:
        """Above the bottom lines; at the top of its room (under the top lines and the right-hand panel)
        where it covers less of the face it is about there (the probe's four corners fill half the
        picture). No top in between covers less: as the top moves, the height of the box it covers rises, then falls."""
        panels = self.sizes.panels
        height, right = self.sizes.block_height(len(lines), panels), self._block_width(lines, panels)
        low = above_bottom + height

        def covered(top: float) -> float:
            return labels_covered(extras.labels, self._label_width, panels.line_height, top - height, top, right)

        return room_top if covered(room_top) < covered(low) else low

    def _block(self, lines: list[str], left: float, top: float, lettering: Lettering) -> None:
        """Lines with their backdrop, the block's top-left corner at (left, top)."""
        margin = self.sizes.margin
        bottom = top - self.sizes.block_height(len(lines), lettering)
        right = left + self._block_width(lines, lettering)
        self.backdrop["u_colour"].value = PANEL_BACKDROP_RGBA
        self._rectangle(left, bottom, right, top)
        self.backdrop["u_colour"].value = BACKDROP_RGBA
        for row, line in enumerate(lines):
            self._line(line, left + margin, top - margin - lettering.line_height * (row + 0.5), lettering)

    def _block_width(self, lines: list[str], lettering: Lettering) -> float:
        """A block's width: its longest line with a margin each side."""
        return 2 * self.sizes.margin + lettering.cell[0] * len(max(lines, key=len))

    def _label_width(self, label: Label) -> float:
        return self.sizes.panels.cell[0] * len(label.text) + 2 * self.sizes.label_padding

    def _label(self, label: Label) -> None:
        """Centred on its point, on a tight backdrop."""
        panels = self.sizes.panels
        width = self._label_width(label)
        left, bottom = label.x - width / 2.0, label.y - panels.line_height / 2.0
        self._rectangle(left, bottom, left + width, bottom + panels.line_height)
        half_character = panels.cell[0] / 2.0
        self._line(label.text, left + self.sizes.label_padding + half_character,
                   bottom + panels.line_height / 2.0, panels)

    def _backdrop(self, lines: list[str], bottom: float, top: float) -> None:
        self._rectangle(0.0, bottom, self._block_width(lines, self.sizes.lines), top)

    def _rectangle(self, left: float, bottom: float, right: float, top: float) -> None:
        corners = np.array([left, bottom, right, bottom, left, top, right, top], dtype="f4")
        self.backdrop_corners.write(corners)
        self.backdrop_vao.render(moderngl.TRIANGLE_STRIP)

    def _line(self, text: str, x: float, y: float, lettering: Lettering) -> None:
        """(x, y) is the centre of the first character; characters land on whole pixels."""
        if not text:
            return
        font = self.fonts[lettering.cell]
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


def panels_first_lines(extras: Extras | None, room_px: float, sizes: TextSizes) -> float:
    """The height the panels that are on take with a line each, as far as they fit in `room_px` in the
    order _extras lays them out: the titles, then the right-hand panel with the two lines it leaves the
    bottom one, or else the bottom one alone."""
    if extras is None:
        return 0.0
    title = sizes.block_height(1, sizes.lines)
    titles = title if extras.titles and title <= room_px else 0.0
    room_px -= titles
    right = sizes.block_height(1, sizes.panels) if extras.right else 0.0
    bottom = sizes.block_height(2 if extras.right else 1, sizes.panels) if extras.bottom else 0.0
    lone_bottom = sizes.block_height(1, sizes.panels) if extras.bottom else 0.0
    return titles + next((need for need in (right + bottom, lone_bottom) if need <= room_px), 0.0)


def cut_lines(lines: list[str], columns: int) -> list[str]:
    """Each line, or as much of it as fits `columns` with CUT_MARK at its end to say it goes on; none
    where not one column fits."""
    if columns < 1:
        return []
    return [line if len(line) <= columns else line[:columns - 1] + CUT_MARK for line in lines]


def spread_labels(labels: list[Label], width_of: Callable[[Label], float], height: float) -> list[Label]:
    """The labels, each `height` tall, moved sideways off those before it that it would cover (a
    polygon's vertices a few pixels apart on the screen: "v3" and "v4" read "v43")."""
    placed: list[Label] = []
    for label in labels:
        for _ in range(len(placed)):
            covered = next((other for other in placed if _covers(other, label, width_of, height)), None)
            if covered is None:
                break
            side = 1.0 if label.x >= covered.x else -1.0
            label = replace(label, x=covered.x + side * (width_of(covered) + width_of(label)) / 2.0)
        placed.append(label)
    return placed


def _covers(one: Label, other: Label, width_of: Callable[[Label], float], height: float) -> bool:
    return (abs(one.y - other.y) < height
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
