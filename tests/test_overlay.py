"""Overlay text layout: every line fits the window, nothing is lost, and wrapping always ends."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from marraztu.render.overlay import fit_lines, wrap


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


def test_fit_lines_keeps_what_fits_and_says_how_many_more() -> None:
    lines = [f"line {n}" for n in range(10)]
    assert fit_lines(lines, room_px=150.0, line_height=15.0) == lines  # exactly 10 fit
    cut = fit_lines(lines, room_px=100.0, line_height=15.0, hint="m hides the matrices panel")
    assert len(cut) == 6 and cut[:5] == lines[:5]
    assert cut[-1] == "... 5 more lines: m hides the matrices panel"
    assert fit_lines(lines, room_px=0.0, line_height=15.0) == ["... 10 more lines"]
