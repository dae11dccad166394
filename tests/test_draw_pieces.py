"""Draw calls in pieces with a glFlush between them (llvmpipe: binning overlaps rasterizing, in less
memory) give exactly the pixels whole draws give, and GPUs keep whole draws."""

from __future__ import annotations

from pathlib import Path

import moderngl
import numpy as np
import pytest
from PIL import Image

from marraztu.control.viewer import StartOptions
from marraztu.frontends.screenshot import take_screenshot
from marraztu.render import renderer as renderer_module
from marraztu.render.context import SOFTWARE_PIECE_PRIMITIVES, draw_piece_primitives, gl_flush
from marraztu.render.gpu import VertexRange
from marraztu.render.renderer import Draw
from support.scenes import BACKGROUND


class RecordingArray:
    def __init__(self) -> None:
        self.calls: list[tuple[int, int, int]] = []

    def render(self, mode: int, vertices: int, first: int) -> None:
        self.calls.append((mode, first, vertices))


@pytest.fixture
def flushes(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    counted: list[int] = []
    monkeypatch.setattr(renderer_module, "gl_flush", lambda: lambda: counted.append(1))
    return counted


@pytest.mark.parametrize("mode, per_primitive", [(moderngl.TRIANGLES, 3), (moderngl.LINES, 2), (moderngl.POINTS, 1)])
def test_pieces_cover_the_range_once_in_order_with_a_flush_between(flushes: list[int], mode: int,
                                                                   per_primitive: int) -> None:
    array = RecordingArray()
    Draw(4)(array, mode, VertexRange(first=3 * per_primitive, vertices=10 * per_primitive))  # type: ignore[arg-type]
    piece = 4 * per_primitive
    assert array.calls == [(mode, 3 * per_primitive, piece), (mode, 7 * per_primitive, piece),
                           (mode, 11 * per_primitive, 2 * per_primitive)]
    assert len(flushes) == 2


def test_whole_draws_and_empty_ranges(flushes: list[int]) -> None:
    array = RecordingArray()
    Draw(None)(array, moderngl.TRIANGLES, VertexRange(first=6, vertices=3_000_000))  # type: ignore[arg-type]
    Draw(None)(array, moderngl.TRIANGLES, VertexRange(first=6, vertices=0))  # type: ignore[arg-type]
    Draw(4)(array, moderngl.LINES, VertexRange(first=2, vertices=0))  # type: ignore[arg-type]
    assert array.calls == [(moderngl.TRIANGLES, 6, 3_000_000)] and not flushes


def test_pieces_on_llvmpipe_only(gl_ctx: moderngl.Context) -> None:
    class GpuContext:
        info = {"GL_RENDERER": "NVIDIA H100 80GB HBM3/PCIe/SSE2"}

    assert draw_piece_primitives(GpuContext()) is None  # type: ignore[arg-type]
    software = "llvmpipe" in gl_ctx.info["GL_RENDERER"]
    assert draw_piece_primitives(gl_ctx) == (SOFTWARE_PIECE_PRIMITIVES if software else None)
    gl_flush()()  # found and callable with the context current
    assert gl_ctx.error == "GL_NO_ERROR"


@pytest.mark.parametrize("keys", ["", "F", "s", "l", "F n", "n", "l b n", "i ENTER*5", "v*3"])
def test_draws_in_pieces_give_the_pixels_of_whole_draws(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                        keys: str) -> None:
    """The built-in scene's thousands of triangles, edges and normals in pieces of 7 primitives."""
    pictures = []
    for piece in (None, 7):
        monkeypatch.setattr(renderer_module, "draw_piece_primitives", lambda ctx, piece=piece: piece)
        out = take_screenshot(StartOptions(), tmp_path / f"{piece}.png", (160, 160), keys=keys)
        pictures.append(np.asarray(Image.open(out).convert("RGB")))
    whole, pieced = pictures
    assert (whole != np.array(BACKGROUND, np.uint8)).any(axis=2).mean() > 0.02, "not blank"
    assert np.array_equal(whole, pieced)
