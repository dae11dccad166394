"""Overlay text: every line fits the window, nothing is lost, wrapping always ends, and the font is
legible at 100 %: thin strokes kept, look-alike glyphs told apart."""

from __future__ import annotations

import textwrap
from pathlib import Path

import moderngl
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from marraztu.render.overlay import fit_lines, wrap
from support import corpus


def test_status_line_breaks_only_between_fields() -> None:
    line = "target objects | translate local | gouraud | perspective | culling off | filled"
    pieces = wrap(line, 30)
    assert all(len(piece) <= 30 for piece in pieces)
    assert [piece.strip(" |") for piece in " | ".join(pieces).split(" | ")][:2] == [
        "target objects", "translate local"]


@settings(max_examples=200, derandomize=True, deadline=None)
@given(st.text(alphabet=st.sampled_from("ab /|_-."), max_size=300), st.integers(10, 80))
def test_wrap_fits_and_keeps_every_visible_character(line: str, columns: int) -> None:
    pieces = wrap(line, columns)
    assert all(len(piece) <= columns for piece in pieces)
    assert "".join(pieces).replace(" ", "") == line.replace(" ", "")


def textwrapped(line: str, columns: int) -> list[str]:
    """wrap as it was, every line through textwrap."""
    if " | " in line:
        line = " | ".join(field.replace(" ", "\u00a0") for field in line.split(" | "))
    pieces = textwrap.wrap(line, columns, subsequent_indent="  ", break_on_hyphens=False,
                           drop_whitespace=True) or [""]
    return [piece.replace("\u00a0", " ") for piece in pieces]


@settings(max_examples=400, derandomize=True, deadline=None)
@given(st.text(alphabet=st.sampled_from("ab |\u00a0\u2003\t\r\n\x0b\x0c-"), max_size=40), st.integers(10, 40))
def test_a_short_line_is_wrapped_as_textwrap_wraps_it(line: str, columns: int) -> None:
    assert wrap(line, columns) == textwrapped(line, columns)


def test_short_lines_are_not_handed_to_textwrap(monkeypatch) -> None:
    """The overlay wraps every line of the message each frame, to count what does not fit: a message of
    16,000 lines (a start with as many models) took 200 ms a frame, where the picture took 10."""
    wrapped = []
    monkeypatch.setattr(textwrap, "wrap", lambda *args, **kwargs: wrapped.append(args) or [])
    lines = [f"loaded m{n}.obj as a new object: 3 vertices, 1 face" for n in range(1000)]
    assert [piece for line in lines for piece in wrap(line, 98)] == lines
    assert wrapped == []
    wrap("x " * 60, 98)
    assert len(wrapped) == 1  # a long line is textwrap's


def test_fit_lines_keeps_what_fits_and_says_how_many_more() -> None:
    lines = [f"line {n}" for n in range(10)]
    assert fit_lines(lines, room_px=150.0, line_height=15.0) == lines  # exactly 10 fit
    cut = fit_lines(lines, room_px=100.0, line_height=15.0, hint="m hides the matrices panel")
    assert len(cut) == 6 and cut[:5] == lines[:5]
    assert cut[-1] == "... 5 more lines: m hides the matrices panel"
    assert fit_lines(lines, room_px=15.0, line_height=15.0) == ["... 10 more lines"]
    assert fit_lines(lines, room_px=14.0, line_height=15.0) == []  # no room for a line: none drawn


# --- legible at 100 % ----------------------------------------------------------------------------
@pytest.fixture(scope="module")
def overlay(own_ctx):
    from marraztu.render.overlay import Overlay

    corpus.make_current(own_ctx)
    made = Overlay(own_ctx)
    yield made
    corpus.make_current(own_ctx)
    made.release()


def drawn_text(ctx, overlay, text: str) -> np.ndarray:
    """`text` drawn by the overlay, white on black, as the coverage of each pixel (0..1), rows top first."""
    from marraztu.render.context import offscreen_framebuffer, read_pixels
    from marraztu.render.overlay import CELL_PX

    corpus.make_current(ctx)
    size = (CELL_PX[0] * (len(text) + 2), 2 * CELL_PX[1])
    with offscreen_framebuffer(ctx, size) as fbo:
        fbo.use()
        fbo.clear(0.0, 0.0, 0.0, 1.0)
        ctx.enable(moderngl.BLEND)
        ctx.blend_func = moderngl.SRC_ALPHA, moderngl.ONE_MINUS_SRC_ALPHA
        overlay.text["u_viewport"].value = size
        overlay._fit_text_to(size)
        overlay._line(text, CELL_PX[0] * 1.5, size[1] / 2, overlay.sizes.lines)
        ctx.disable(moderngl.BLEND)
        return read_pixels(fbo, size)[..., 0] / 255.0


@pytest.mark.parametrize("glyph", list("m n i T 1 + | l . , : ; ' \" - _ ( ) [ ] / \\ ! ?".split()) + ["i"])
def test_thin_glyphs_keep_a_solid_stroke(own_ctx, overlay, glyph: str) -> None:
    """Each glyph has pixels at least 60 % covered: a stroke, not a grey smudge that vanishes."""
    cover = drawn_text(own_ctx, overlay, glyph)
    assert cover.max() >= 0.6, f"{glyph!r}: strongest pixel {cover.max():.2f}"


def test_look_alike_glyphs_differ(own_ctx, overlay) -> None:
    pairs = [("m", "n"), ("i", "l"), ("l", "1"), ("1", "7"), ("O", "0"), ("+", "t"), ("|", "l"), (".", ",")]
    for first, second in pairs:
        a, b = drawn_text(own_ctx, overlay, first), drawn_text(own_ctx, overlay, second)
        assert np.abs(a - b).max() > 0.5, f"{first!r} and {second!r} look alike"


def test_the_dot_of_an_i_is_drawn_apart_from_its_stem(own_ctx, overlay) -> None:
    cover = drawn_text(own_ctx, overlay, "i")
    rows = cover.max(axis=1) > 0.3  # which rows hold ink, top first
    inked = np.flatnonzero(rows)
    assert inked.size and (~rows[inked[0]:inked[-1] + 1]).any(), "no gap between the dot and the stem"


@pytest.mark.parametrize("keys", ["m", "i ENTER m P s"])
def test_the_right_hand_panel_is_fitted_to_a_small_window(tmp_path, monkeypatch, keys: str) -> None:
    """The matrices panel ran off a 320x320 window's bottom, over the panel and the message below it."""
    from marraztu.control.viewer import StartOptions
    from marraztu.frontends.screenshot import take_screenshot
    from marraztu.render import overlay as overlay_module

    blocks: list[tuple[list[str], float, float, float]] = []
    real = overlay_module.Overlay._block

    def spied(self, lines, left, top, lettering):
        blocks.append((lines, left, top, top - self.sizes.block_height(len(lines), lettering)))
        return real(self, lines, left, top, lettering)

    monkeypatch.setattr(overlay_module.Overlay, "_block", spied)
    take_screenshot(StartOptions(), tmp_path / "shot.png", (320, 320), keys=keys, overlay=True)
    matrices = [block for block in blocks if block[0][0].startswith("MATRICES")]
    assert matrices and matrices[0][0][-1].endswith("a taller window shows them")
    others_below = [block for block in blocks if block[2] < matrices[0][3] + 1e-6 and block is not matrices[0]]
    assert all(block[3] >= 0.0 for block in blocks)
    assert matrices[0][3] >= max((block[2] for block in others_below), default=0.0) - 1e-6


def _blocks_and_labels(tmp_path, monkeypatch, keys: str, size: tuple[int, int] = (800, 800)):
    """The panels the overlay drew, as (lines, left, top, bottom), and the labels' points."""
    from marraztu.control.viewer import StartOptions
    from marraztu.frontends.screenshot import take_screenshot
    from marraztu.render import overlay as overlay_module

    blocks: list[tuple[list[str], float, float, float]] = []
    labels: list[tuple[float, float]] = []
    real_block, real_label = overlay_module.Overlay._block, overlay_module.Overlay._label

    def spied_block(self, lines, left, top, lettering):
        blocks.append((lines, left, top, top - self.sizes.block_height(len(lines), lettering)))
        return real_block(self, lines, left, top, lettering)

    def spied_label(self, label):
        labels.append((label.x, label.y))
        return real_label(self, label)

    monkeypatch.setattr(overlay_module.Overlay, "_block", spied_block)
    monkeypatch.setattr(overlay_module.Overlay, "_label", spied_label)
    take_screenshot(StartOptions(), tmp_path / "shot.png", size, keys=keys, overlay=True)
    return blocks, labels


@pytest.mark.parametrize("keys, at_top", [("F 0 i ENTER*40", True), ("F 0 i ENTER*40 P", True),
                                          ("F 0 i", False), ("F 0 i ENTER*40 m", False)])
def test_the_probe_panel_moves_up_rather_than_cover_the_face_it_is_about(tmp_path, monkeypatch, keys: str,
                                                                         at_top: bool) -> None:
    """Gouraud's four corners fill the lower half of an 800x800 picture: x_wing's face 41, and its v1-v4,
    were under the panel. Where the face lies under it and not under the top, the panel goes up; with
    the matrices panel up, the room under it is too short here, and it stays."""
    blocks, labels = _blocks_and_labels(tmp_path, monkeypatch, keys)
    panel = next(block for block in blocks if block[0][0].startswith(("PROBE", "PIPELINE")))
    _, left, top, bottom = panel
    assert labels
    covered = [(x, y) for x, y in labels if bottom <= y <= top]
    assert (top > 400) is at_top, (top, bottom, labels)
    if at_top:
        assert not covered, (top, bottom, covered)


def _drawn_lines(tmp_path, monkeypatch, keys: str, size: tuple[int, int], models: tuple = ()):
    """Every line of text the overlay drew, as (text, left, right, bottom, top) in pixels."""
    from marraztu.control.viewer import StartOptions
    from marraztu.frontends.screenshot import take_screenshot
    from marraztu.render import overlay as overlay_module

    drawn: list[tuple[str, float, float, float, float]] = []
    real = overlay_module.Overlay._line

    def spied(self, text, x, y, lettering):
        width, height = lettering.cell
        left, bottom = round(x - width / 2.0), round(y - height / 2.0)
        drawn.append((text, left, left + width * len(text), bottom, bottom + height))
        return real(self, text, x, y, lettering)

    monkeypatch.setattr(overlay_module.Overlay, "_line", spied)
    options = StartOptions(empty=True, models=models) if models else StartOptions()
    take_screenshot(options, tmp_path / "shot.png", size, keys=keys, overlay=True)
    return drawn


@pytest.mark.parametrize("size", [(300, 1000), (320, 240), (200, 150), (64, 64)])
@pytest.mark.parametrize("keys", ["i", "F 0 i ENTER*40 P", "m", "s i", "h"])
def test_no_text_runs_off_a_narrow_window_and_a_cut_line_says_so(tmp_path, monkeypatch, keys: str,
                                                                 size: tuple[int, int]) -> None:
    """The probe's, the pipeline's and the matrices' lines (about 110 columns), the side-by-side titles
    and the "... more lines" notes ran off a 300 pixel wide window's right edge, cut with no sign."""
    from marraztu.render.overlay import CUT_MARK

    drawn = _drawn_lines(tmp_path, monkeypatch, keys, size)
    off = [(text, right) for text, _, right, _, _ in drawn if right > size[0]]
    assert not off, off
    if ("i" in keys or "P" in keys) and size[0] >= 200:  # the probe and the pipeline are wider
        assert any(text.endswith(CUT_MARK) for text, *_ in drawn)


def test_a_name_s_control_characters_are_escaped_in_the_panels_as_in_the_status_line(tmp_path, monkeypatch) -> None:
    """A model file named with a tab: the status line said 'tab\\tin' and the probe's, the pipeline's and
    the matrices' panels drew the tab itself, a '?' glyph."""
    model = tmp_path / "tab\tin\x1bname.obj"
    model.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    for keys in ("i m", "P"):
        drawn = _drawn_lines(tmp_path, monkeypatch, keys, (1000, 800), models=(model,))
        named = [text for text, *_ in drawn if "name" in text]
        assert len(named) >= 2, named  # the status line and a panel's
        assert all(text.isprintable() and "tab\\tin\\x1bname" in text for text in named), named


def test_the_labels_of_nearby_vertices_do_not_cover_each_other(tmp_path, monkeypatch) -> None:
    """Face 41 of x_wing in Gouraud at 800x800: the labels v3 and v4 landed 7 pixels apart and read "v43"."""
    from marraztu.render.overlay import PANEL_LINE_HEIGHT_PX

    drawn = [line for line in _drawn_lines(tmp_path, monkeypatch, "F 0 i ENTER*40", (800, 800))
             if line[0] in ("v1", "v2", "v3", "v4") and line[4] - line[3] < PANEL_LINE_HEIGHT_PX]
    assert len(drawn) == 4
    for index, (_, left, right, bottom, top) in enumerate(drawn):
        for text, other_left, other_right, other_bottom, other_top in drawn[index + 1:]:
            apart = right <= other_left or other_right <= left or top <= other_bottom or other_top <= bottom
            assert apart, (drawn[index], text)


@pytest.mark.parametrize("size", [(200, 150), (320, 240)])
def test_side_by_side_titles_stay_in_their_third(tmp_path, monkeypatch, size: tuple[int, int]) -> None:
    """At 200x150 "Gouraud" and "Phong (per pixel)" were drawn over each other; at 320 the last ran off."""
    drawn = _drawn_lines(tmp_path, monkeypatch, "s", size)
    titles = [line for line in drawn if line[0].startswith(("Fl", "Go", "Ph"))]
    assert len(titles) == 3
    for third, (text, left, right, _, _) in enumerate(titles):
        assert third * size[0] / 3 <= left and right <= (third + 1) * size[0] / 3, (text, left, right)


@pytest.mark.parametrize("size", [(800, 1100), (1000, 1400)])
def test_with_the_matrices_panel_up_the_probe_panel_moves_up_under_it_where_there_is_room(
        tmp_path, monkeypatch, size: tuple[int, int]) -> None:
    """The top was the matrices panel's, so the probe panel stayed over its face even where the room
    under the matrices panel left the face clear (1000x1400 draws the text 1.25 times as large)."""
    blocks, labels = _blocks_and_labels(tmp_path, monkeypatch, "F 0 c t y*6 c c i ENTER*40 m", size)
    matrices = next(block for block in blocks if block[0][0].startswith("MATRICES"))
    _, _, top, bottom = next(block for block in blocks if block[0][0].startswith("PROBE"))
    assert top == matrices[3] and labels and not [(x, y) for x, y in labels if bottom <= y <= top]


def _backdrops(tmp_path, monkeypatch, keys: str, size: tuple[int, int]):
    """The backdrop of every block of text the overlay drew (the labels' aside: they are part of the
    picture), as (left, bottom, right, top) in pixels."""
    return _backdrops_and_label_boxes(tmp_path, monkeypatch, keys, size)[0]


def _backdrops_and_label_boxes(tmp_path, monkeypatch, keys: str, size: tuple[int, int], models: tuple = ()):
    """The backdrops of the blocks of text, and apart those of the labels, as (left, bottom, right, top)."""
    from marraztu.control.viewer import StartOptions
    from marraztu.frontends.screenshot import take_screenshot
    from marraztu.render import overlay as overlay_module

    backdrops: list[tuple[float, float, float, float]] = []
    label_boxes: list[tuple[float, float, float, float]] = []
    real_rectangle, real_label = overlay_module.Overlay._rectangle, overlay_module.Overlay._label
    in_label = []

    def spied_rectangle(self, left, bottom, right, top):
        (label_boxes if in_label else backdrops).append((left, bottom, right, top))
        return real_rectangle(self, left, bottom, right, top)

    def spied_label(self, label):
        in_label.append(label)
        try:
            return real_label(self, label)
        finally:
            in_label.pop()

    monkeypatch.setattr(overlay_module.Overlay, "_rectangle", spied_rectangle)
    monkeypatch.setattr(overlay_module.Overlay, "_label", spied_label)
    options = StartOptions(empty=True, models=models) if models else StartOptions()
    take_screenshot(options, tmp_path / "shot.png", size, keys=keys, overlay=True)
    return backdrops, label_boxes


def _plate(path: Path) -> Path:
    """A plate 20 wide and 60 tall facing the camera, in six rows of two triangles: a face a sixth of its
    height, whose probe panel in Gouraud is taller than half an 800x600 picture."""
    corners = [(x * 20.0 - 10.0, y * 10.0 - 30.0) for y in range(7) for x in range(2)]
    faces = [face for row in range(6) for face in ((2 * row + 1, 2 * row + 2, 2 * row + 4),
                                                    (2 * row + 1, 2 * row + 4, 2 * row + 3))]
    path.write_text("".join(f"v {x} {y} 0\n" for x, y in corners) + "".join(f"f {a} {b} {c}\n" for a, b, c in faces))
    return path


def _covered_height(box: tuple[float, float, float, float], bottom: float, top: float) -> float:
    return max(0.0, min(box[3], top) - max(box[1], bottom))


@pytest.mark.parametrize("click_y, at_top", [(400, True), (250, False)])
def test_where_both_places_cover_the_face_the_probe_panel_takes_the_one_that_covers_less(
        tmp_path, monkeypatch, click_y: int, at_top: bool) -> None:
    """Where the panel at the bottom and at the top of its room both covered the face, it stayed at the
    bottom: a face in the lower middle of 800x600 was hidden whole, labels, dots and outline, while the
    top left part of it clear. The face's box (its labels' and what they surround) decides."""
    size = (800, 600)
    backdrops, label_boxes = _backdrops_and_label_boxes(
        tmp_path, monkeypatch, f"T 0 1 F click=400,{click_y} i", size, models=(_plate(tmp_path / "plate.obj"),))
    status_bottom = next(bottom for _, bottom, _, top in backdrops if top == size[1])
    panel = next(box for box in backdrops if box[0] == 0.0 and box[3] <= status_bottom)
    height = panel[3] - panel[1]
    face = (min(box[0] for box in label_boxes), min(box[1] for box in label_boxes),
            max(box[2] for box in label_boxes), max(box[3] for box in label_boxes))
    assert len(label_boxes) == 3 and face[0] < panel[2], (label_boxes, panel)
    low, high = _covered_height(face, 0.0, height), _covered_height(face, status_bottom - height, status_bottom)
    assert low > 0.0 and high > 0.0, (face, panel)  # too tall for either place to miss the face
    covered = _covered_height(face, panel[1], panel[3])
    assert (panel[3] == status_bottom) is at_top, (panel, status_bottom)
    assert covered == min(low, high)
    if at_top:
        assert covered < low  # the bottom, where it stayed before, covers more


def _assert_blocks_apart_and_inside(backdrops: list[tuple[float, float, float, float]],
                                    size: tuple[int, int]) -> None:
    """No backdrop (left, bottom, right, top) leaves the window, and none covers another."""
    width, height = size
    assert all(0.0 <= left and 0.0 <= bottom and right <= width and top <= height
               for left, bottom, right, top in backdrops), backdrops
    for index, (left, bottom, right, top) in enumerate(backdrops):
        for other_left, other_bottom, other_right, other_top in backdrops[index + 1:]:
            apart = right <= other_left or other_right <= left or top <= other_bottom or other_top <= bottom
            assert apart, backdrops


@pytest.mark.parametrize("size", [(160, 120), (320, 60), (64, 64), (200, 40), (1, 1), (8, 300)])
@pytest.mark.parametrize("keys", ["i", "s i", "i m", "F 0 i ENTER*40 P m", "s i c c g"])
def test_in_a_small_window_no_block_of_text_covers_another_or_leaves_the_window(
        tmp_path, monkeypatch, keys: str, size: tuple[int, int]) -> None:
    """At 160x120 the probe panel was drawn over the status line's last lines, at 64x64 the titles and
    the matrices below the window's bottom and over the message: a panel with no room for a line kept one."""
    _assert_blocks_apart_and_inside(_backdrops(tmp_path, monkeypatch, keys, size), size)


@pytest.mark.parametrize("keys, first", [("i", "PROBE"), ("m", "MATRICES"), ("P", "PIPELINE")])
def test_a_panel_asked_for_keeps_a_line_before_the_status_line_s_last_ones(tmp_path, monkeypatch, keys: str,
                                                                          first: str) -> None:
    """At 160x120 the status line, wrapped to seven lines, took the window's height: the probe panel had
    no room. The panel keeps one line (its note of how many more a taller window shows) first."""
    drawn = [text for text, *_ in _drawn_lines(tmp_path, monkeypatch, keys, (160, 120))]
    assert any(text.startswith("... ") and "more lines" in text for text in drawn[:-1]), drawn
    assert drawn[-1].startswith(("... ", first)), drawn


def test_the_status_line_gives_way_only_to_panels_that_then_have_room(tmp_path, monkeypatch) -> None:
    """At 1200x100, side by side with the probe, the matrices and a message, the status line was cut to
    its note to keep room for the probe and the matrices, which still had none: the room went unused."""
    drawn = [text for text, *_ in _drawn_lines(tmp_path, monkeypatch, "s i m c c g", (1200, 100))]
    assert any(text.startswith("target lights") for text in drawn), drawn
    assert not any("more lines" in text for text in drawn), drawn


# --- text as large, to the eye, on a projector's framebuffer -------------------------------------
def _status_band(tmp_path, size: tuple[int, int]) -> np.ndarray:
    """The overlay over an empty scene (a plain background): the rows of the status line's first line,
    as the white text's coverage, rows top first."""
    from PIL import Image

    from marraztu.control.viewer import StartOptions
    from marraztu.frontends.screenshot import take_screenshot
    from marraztu.render.overlay import text_sizes

    shot = take_screenshot(StartOptions(empty=True), tmp_path / f"{size[0]}x{size[1]}.png", size, overlay=True)
    sizes = text_sizes(size)
    pixels = np.asarray(Image.open(shot).convert("RGB"))
    return pixels[:int(sizes.margin + sizes.lines.line_height), :, 0] / 255.0


def _ink_rows(band: np.ndarray) -> int:
    """How many rows, from the first to the last, hold a pixel of the text at least half covered."""
    inked = np.flatnonzero((band > 0.5).any(axis=1))
    return int(inked[-1] - inked[0] + 1)


@pytest.mark.parametrize("size, scale", [((1920, 1080), 1.35), ((1600, 1200), 1.5), ((3840, 2160), 2.7)])
def test_the_text_grows_with_the_framebuffer_s_shorter_side(tmp_path, size: tuple[int, int], scale: float) -> None:
    """At 1920x1080, on a projector, the status line was drawn 14 pixels high, as in an 800x600 window:
    unreadable from the back of a room. Its letters now stand `scale` times as high, and as solid."""
    small, large = _status_band(tmp_path, (800, 600)), _status_band(tmp_path, size)
    # Within a pixel, and half a pixel of the small text's rounding grown by the scale.
    assert abs(_ink_rows(large) - scale * _ink_rows(small)) <= 1.0 + scale / 2, (_ink_rows(small), _ink_rows(large))
    # Drawn pixel for pixel from an atlas made at that size, not stretched: as many solid pixels per
    # letter area, where a stretched small font would smear into grey.
    solid_share = [(band > 0.9).sum() / (band > 0.1).sum() for band in (small, large)]
    assert solid_share[1] >= 0.9 * solid_share[0], solid_share


@pytest.mark.parametrize("size", [(480, 300), (640, 480), (720, 680), (800, 800), (800, 900), (1200, 480),
                                  (801, 801)])
def test_up_to_800_pixels_on_the_shorter_side_the_text_is_drawn_as_at_800x600(tmp_path,
                                                                              size: tuple[int, int]) -> None:
    """The docs' pictures keep their pixels: the status line's first characters are the same pixels
    at every size whose shorter side is at most 800 (801 rounds to the same cells)."""
    columns = 30  # fit every size's first line, however it wraps
    width = 6 + 7 * columns
    expected = _status_band(tmp_path, (800, 600))[:, :width]
    assert np.array_equal(_status_band(tmp_path, size)[:, :width], expected)
    assert not np.array_equal(_status_band(tmp_path, (1920, 1080))[:expected.shape[0], :width], expected)


def test_text_sizes_are_those_at_800_pixels_times_the_scale_rounded() -> None:
    from marraztu.render.overlay import CELL_PX, LINE_HEIGHT_PX, MARGIN_PX, PANEL_CELL_PX, Lettering, text_sizes

    assert text_sizes((800, 600)) == text_sizes((16384, 800)) == text_sizes((1, 1))
    assert text_sizes((800, 600)).lines == Lettering(CELL_PX, LINE_HEIGHT_PX)
    assert text_sizes((800, 600)).panels.cell == PANEL_CELL_PX and text_sizes((800, 600)).margin == MARGIN_PX
    big = text_sizes((1920, 1080))  # 1.35 times
    assert big.lines == Lettering((9, 19), 22.0) and big.panels == Lettering((8, 18), 20.0)
    assert (big.margin, big.label_padding) == (8.0, 3.0)


@pytest.mark.parametrize("size", [(1920, 1080), (1600, 1200), (1000, 2400)])
@pytest.mark.parametrize("keys", ["h", "F 0 i ENTER*40 P m", "s i m", "F 0 c t y*6 c c i ENTER*40 m"])
def test_on_a_large_framebuffer_no_block_of_text_covers_another_or_leaves_it(
        tmp_path, monkeypatch, keys: str, size: tuple[int, int]) -> None:
    """Lines, backdrops and panels are fitted with the larger text's sizes: none runs off the window
    (1000x2400 draws at 1.25 times: the probe's lines are cut there) and none covers another."""
    _assert_blocks_apart_and_inside(_backdrops(tmp_path, monkeypatch, keys, size), size)
    drawn = _drawn_lines(tmp_path, monkeypatch, keys, size)
    assert not [(text, right) for text, _, right, _, _ in drawn if right > size[0]]


def test_on_a_large_framebuffer_the_vertex_labels_grow_and_keep_apart(tmp_path, monkeypatch) -> None:
    """The labels v1-v4 of x_wing's face 41 in Gouraud, at 1920x1080: in the panels' larger letters,
    and still clear of each other."""
    from marraztu.render.overlay import text_sizes

    cell = text_sizes((1920, 1080)).panels.cell
    drawn = [line for line in _drawn_lines(tmp_path, monkeypatch, "F 0 i ENTER*40", (1920, 1080))
             if line[0] in ("v1", "v2", "v3", "v4") and line[4] - line[3] == cell[1]]
    assert len(drawn) == 4
    for index, (_, left, right, bottom, top) in enumerate(drawn):
        assert right - left == 2 * cell[0]
        for text, other_left, other_right, other_bottom, other_top in drawn[index + 1:]:
            apart = right <= other_left or other_right <= left or top <= other_bottom or other_top <= bottom
            assert apart, (drawn[index], text)
