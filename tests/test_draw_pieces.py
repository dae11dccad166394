"""Draw calls in pieces with a glFlush between them (llvmpipe: binning overlaps rasterizing, in less
memory) give exactly the pixels whole draws give, and GPUs keep whole draws."""

from __future__ import annotations

from pathlib import Path

import moderngl
import numpy as np
import pytest

from marraztu.render import renderer as renderer_module
from marraztu.render.context import SOFTWARE_PIECE_PRIMITIVES, draw_piece_primitives, gl_flush
from marraztu.render.gpu import VertexRange
from marraztu.render.renderer import Draw, pieced_draws
from support.scenes import BACKGROUND, builtin_pictures_with


class RecordingArray:
    """A vertex array that notes its draws, and its context's waits, as ("finish",) in the same list."""

    def __init__(self) -> None:
        self.calls: list[tuple] = []
        self.ctx = self

    def render(self, mode: int, vertices: int, first: int) -> None:
        self.calls.append((mode, first, vertices))

    def finish(self) -> None:
        self.calls.append(("finish",))

    def flush(self) -> None:
        self.calls.append(("flush",))


@pytest.mark.parametrize("mode, per_primitive", [(moderngl.TRIANGLES, 3), (moderngl.LINES, 2), (moderngl.POINTS, 1)])
def test_pieces_cover_the_range_once_in_order_with_a_flush_between(mode: int, per_primitive: int) -> None:
    array = RecordingArray()
    Draw(4, array.flush)(array, mode, VertexRange(first=3 * per_primitive, vertices=10 * per_primitive))  # type: ignore[arg-type]
    piece = 4 * per_primitive
    assert array.calls == [(mode, 3 * per_primitive, piece), ("flush",), (mode, 7 * per_primitive, piece),
                           ("flush",), (mode, 11 * per_primitive, 2 * per_primitive)]


def test_pieces_in_flight_are_bounded_by_a_wait() -> None:
    array = RecordingArray()
    Draw(1, array.flush, pieces_in_flight=2)(array, moderngl.POINTS, VertexRange(first=0, vertices=5))  # type: ignore[arg-type]
    waits = [call[0] for call in array.calls if isinstance(call[0], str)]
    assert waits == ["flush", "finish", "flush", "finish"]
    assert [call[1:] for call in array.calls if not isinstance(call[0], str)] == [(k, 1) for k in range(5)]


def test_whole_draws_and_empty_ranges() -> None:
    array = RecordingArray()
    Draw()(array, moderngl.TRIANGLES, VertexRange(first=6, vertices=3_000_000))  # type: ignore[arg-type]
    Draw()(array, moderngl.TRIANGLES, VertexRange(first=6, vertices=0))  # type: ignore[arg-type]
    Draw(4, array.flush)(array, moderngl.LINES, VertexRange(first=2, vertices=0))  # type: ignore[arg-type]
    assert array.calls == [(moderngl.TRIANGLES, 6, 3_000_000)]


def test_pieces_on_llvmpipe_only(gl_ctx: moderngl.Context) -> None:
    class GpuContext:
        def __init__(self, renderer: str) -> None:
            self.info = {"GL_RENDERER": renderer}

    for gpu in ("NVIDIA H100 80GB HBM3/PCIe/SSE2", "zink (llvmpipe (LLVM 15.0.6, 256 bits))"):
        assert draw_piece_primitives(GpuContext(gpu)) is None  # type: ignore[arg-type]
        assert pieced_draws(GpuContext(gpu)) == (Draw(), Draw())  # type: ignore[arg-type]
    software = gl_ctx.info["GL_RENDERER"].startswith("llvmpipe")
    assert draw_piece_primitives(gl_ctx) == (SOFTWARE_PIECE_PRIMITIVES if software else None)
    if software:  # glcontext's GL library was found: the pieces are flushed, not just cut
        assert getattr(gl_flush(), "__name__", "") == "glFlush"
    gl_flush()()  # callable with the context current
    assert gl_ctx.error == "GL_NO_ERROR"


@pytest.mark.parametrize("keys", ["", "F", "s", "l", "F n", "n", "l b n", "i ENTER*5", "v*3"])
def test_draws_in_pieces_give_the_pixels_of_whole_draws(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                        keys: str) -> None:
    """The built-in scene's thousands of triangles, edges and normals in pieces of 7 primitives."""
    whole, pieced = builtin_pictures_with(monkeypatch, renderer_module, "draw_piece_primitives", (None, 7),
                                          tmp_path, keys)
    assert (whole != np.array(BACKGROUND, np.uint8)).any(axis=2).mean() > 0.02, "not blank"
    assert np.array_equal(whole, pieced)
