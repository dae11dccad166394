"""What an object's buffers and textures hold is exactly the bytes given, however many staging
pieces they pass through on the way (render.context's device uploads), and the staging buffers are
gone afterwards."""

from __future__ import annotations

import moderngl
import numpy as np
import pytest

from marraztu.render import context as gl_context
from marraztu.render.gpu import EDGE_ROW
from support import corpus

STAGING = 64  # bytes: every test below passes through several pieces, the last one short


@pytest.fixture
def small_staging(monkeypatch) -> None:
    monkeypatch.setattr(gl_context, "STAGING_BYTES", STAGING)
    monkeypatch.setattr(gl_context, "DIRECT_UPLOAD_BYTES", 0)  # every upload below is staged


@pytest.mark.parametrize("size", [1, STAGING - 1, STAGING, STAGING + 1, 10 * STAGING + 13])
def test_a_buffer_holds_the_bytes_given_across_staging_pieces(own_ctx, small_staging, size: int) -> None:
    corpus.make_current(own_ctx)
    data = np.random.default_rng(size).integers(0, 256, size, dtype=np.uint8)
    buffer = gl_context.device_buffer(own_ctx, data)
    try:
        assert buffer.size == size and buffer.read() == data.tobytes()
    finally:
        buffer.release()


def test_rows_of_any_layout_and_strided_arrays_are_uploaded_as_their_c_order_bytes(own_ctx, small_staging) -> None:
    corpus.make_current(own_ctx)
    rows = np.zeros(37, EDGE_ROW)
    rows["position"] = np.arange(37 * 3, dtype=np.float32).reshape(37, 3)
    rows["face_texel"] = np.arange(37 * 2, dtype=np.uint16).reshape(37, 2)
    columns = np.arange(60, dtype=np.float32).reshape(3, 20).T  # a transposed view: not contiguous
    for data in (rows, columns):
        buffer = gl_context.device_buffer(own_ctx, data)
        try:
            assert buffer.read() == np.ascontiguousarray(data).tobytes()
        finally:
            buffer.release()


def test_a_zeroed_buffer_is_zeros_to_its_last_byte(own_ctx, small_staging) -> None:
    corpus.make_current(own_ctx)
    buffer = gl_context.zeroed_device_buffer(own_ctx, 5 * STAGING + 7)
    try:
        assert buffer.size == 5 * STAGING + 7 and not any(buffer.read())
    finally:
        buffer.release()


def test_a_texture_holds_the_texels_given(own_ctx, small_staging) -> None:
    corpus.make_current(own_ctx)
    table = np.random.default_rng(3).random((5, 7, 3), dtype=np.float32)  # 7 wide, 5 high: rows of 84 bytes
    texture = gl_context.device_texture(own_ctx, (7, 5), 3, table, "f4")
    try:
        assert np.array_equal(np.frombuffer(texture.read(), np.float32).reshape(5, 7, 3), table)
    finally:
        texture.release()


def test_uploads_leave_no_staging_buffer_behind(own_ctx, small_staging) -> None:
    corpus.make_current(own_ctx)
    data = np.arange(1000, dtype=np.uint8)
    before = corpus.live_gl_objects(own_ctx)
    with corpus.DroppedGlObjects(own_ctx) as dropped:
        made = [gl_context.device_buffer(own_ctx, data), gl_context.zeroed_device_buffer(own_ctx, 300),
                gl_context.device_texture(own_ctx, (10, 10), 1, data[:100], "f1")]
        for resource in made:
            resource.release()
    assert dropped.leaked == 0 and corpus.live_gl_objects(own_ctx) == before


def test_an_empty_buffer_is_refused_as_moderngl_refuses_it(own_ctx, small_staging) -> None:
    corpus.make_current(own_ctx)
    with pytest.raises(moderngl.Error, match="empty"):
        gl_context.device_buffer(own_ctx, np.zeros(0, np.float32))




def test_a_texture_that_cannot_be_made_or_written_leaves_nothing_behind(own_ctx, small_staging, monkeypatch) -> None:
    corpus.make_current(own_ctx)
    data = np.zeros(8 * 8 * 3, np.float32)
    before = corpus.live_gl_objects(own_ctx)
    with corpus.DroppedGlObjects(own_ctx) as dropped:
        with pytest.raises(moderngl.Error):
            gl_context.device_texture(own_ctx, (8, 8), 5, data, "f4")  # no texture of 5 components

        def refused(self, *args, **kwargs):
            raise moderngl.Error("refused")
        monkeypatch.setattr(moderngl.Texture, "write", refused)
        with pytest.raises(moderngl.Error, match="refused"):
            gl_context.device_texture(own_ctx, (8, 8), 3, data, "f4")
    assert dropped.leaked == 0 and corpus.live_gl_objects(own_ctx) == before


@pytest.mark.parametrize("shape", [(1, 1), (256, 256)])  # one byte, and DIRECT_UPLOAD_BYTES
def test_small_uploads_are_written_directly_and_hold_the_same(own_ctx, shape: tuple[int, int]) -> None:
    corpus.make_current(own_ctx)
    size = shape[0] * shape[1]
    data = np.random.default_rng(size).integers(0, 256, size, dtype=np.uint8)
    made = [gl_context.device_buffer(own_ctx, data), gl_context.zeroed_device_buffer(own_ctx, size),
            gl_context.device_texture(own_ctx, shape, 1, data, "f1")]
    try:
        assert [resource.read() for resource in made] == [data.tobytes(), bytes(size), data.tobytes()]
    finally:
        for resource in made:
            resource.release()
