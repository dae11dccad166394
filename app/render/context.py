"""An offscreen OpenGL context: EGL where there is one (no display needed), otherwise the platform's
own standalone context (CGL on macOS, WGL on Windows, GLX with a display on Linux)."""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from functools import cache

import moderngl
import numpy as np

from marraztu.errors import ViewerError, first_line

GL_VERSION = 330

# The process that made the first context. The driver's display lives as long as the process, and a
# child forked from it has none of its threads: Mesa's first picture there waited for them for ever.
_gl_process: int | None = None


def create_offscreen_context() -> moderngl.Context:
    global _gl_process
    refuse_forked_gl()
    try:
        ctx = moderngl.create_standalone_context(require=GL_VERSION, backend="egl")
    except Exception as egl_error:  # glcontext raises plain Exception subclasses of its own
        try:
            ctx = moderngl.create_standalone_context(require=GL_VERSION)
        except Exception as error:
            raise ViewerError(f"cannot create an offscreen OpenGL {GL_VERSION // 100}.{GL_VERSION // 10 % 10} "
                              f"context: EGL said {first_line(egl_error)}; the platform's context said "
                              f"{first_line(error)}{_INSTALL_HINT}") from None  # both causes are in its words
    _gl_process = os.getpid() if _gl_process is None else _gl_process
    return ctx


def refuse_forked_gl() -> None:
    """A ViewerError in a process forked from one that had opened OpenGL, where any drawing would hang."""
    if _gl_process is not None and _gl_process != os.getpid():
        raise ViewerError("this process was forked from one that had opened OpenGL, which cannot draw in a "
                          "fork: start the processes that draw with multiprocessing's \"spawn\" or "
                          "\"forkserver\" method, or fork before the first Viewer")


# What a person on Linux is missing, most likely: Mesa's EGL and its drivers (llvmpipe among them).
_INSTALL_HINT = (" (Mesa's EGL draws without a display or a GPU: apt-get install libegl1 libgl1-mesa-dri on "
                 "Debian and Ubuntu)" if sys.platform.startswith("linux") else "")


def check_gl(ctx: moderngl.Context, what: str) -> None:
    """A ViewerError when GL reports an error after `what` (an upload, a framebuffer)."""
    error = ctx.error
    if error != "GL_NO_ERROR":
        raise ViewerError(f"the GPU refused {what} ({error})")


# What the staging buffer of an upload holds: the data passes through it a piece at a time.
STAGING_BYTES = 1 << 20
# Up to this size an upload is written directly: for thousands of tiny objects the staging's calls
# cost more than the small host copies they spare.
DIRECT_UPLOAD_BYTES = 1 << 16


def device_buffer(ctx: moderngl.Context, data: np.ndarray) -> moderngl.Buffer:
    """A buffer holding `data`, filled on the GPU by copies from a small staging buffer.

    NVIDIA's driver keeps a host copy of a buffer the CPU writes, as much resident memory again; of
    one a GPU copy fills it keeps none, and the upload is quicker there (slower on llvmpipe)."""
    raw = np.ascontiguousarray(data).reshape(-1).view(np.uint8)
    if raw.size <= DIRECT_UPLOAD_BYTES:
        return ctx.buffer(raw)  # moderngl refuses an empty one itself
    return _filled_on_gpu(ctx, raw.size, raw)


def zeroed_device_buffer(ctx: moderngl.Context, size: int) -> moderngl.Buffer:
    """A buffer of `size` zero bytes, filled as device_buffer fills one (moderngl's clear writes from
    the CPU)."""
    if size <= DIRECT_UPLOAD_BYTES:
        buffer = ctx.buffer(reserve=size)
        buffer.clear()
        return buffer
    return _filled_on_gpu(ctx, size, None)


def device_texture(ctx: moderngl.Context, shape: tuple[int, int], components: int, data: np.ndarray,
                   dtype: str) -> moderngl.Texture:
    """A texture of `data`, unpacked on the GPU from a buffer device_buffer filled (on NVIDIA's driver
    a texture the CPU writes gets a host copy too)."""
    if data.nbytes <= DIRECT_UPLOAD_BYTES:
        return ctx.texture(shape, components, np.ascontiguousarray(data), dtype=dtype)
    pixels = device_buffer(ctx, data)
    texture = None
    try:
        texture = ctx.texture(shape, components, dtype=dtype)
        texture.write(pixels)
    except Exception:
        if texture is not None:
            texture.release()
        raise
    finally:
        pixels.release()
    return texture


def _filled_on_gpu(ctx: moderngl.Context, size: int, source: np.ndarray | None) -> moderngl.Buffer:
    """A buffer of `size` bytes, `source` (uint8) or zeros, copied into place a staging buffer at a time."""
    buffer = ctx.buffer(reserve=size)
    staging = ctx.buffer(reserve=min(size, STAGING_BYTES))
    try:
        if source is None:
            staging.clear()
        for at in range(0, size, STAGING_BYTES):
            piece = min(STAGING_BYTES, size - at)
            if source is not None:
                staging.write(source[at:at + piece])
            ctx.copy_buffer(buffer, staging, size=piece, write_offset=at)
    except Exception:
        buffer.release()
        raise
    finally:
        staging.release()
    return buffer


@cache
def gl_flush() -> Callable[[], None]:
    """glFlush, which moderngl does not wrap, from the GL library glcontext loads (so that it reaches
    the context glcontext made; libglvnd's libraries all reach the current one). A no-op where that
    library cannot be found: it only lets the GPU start sooner."""
    try:
        library = gl_library()
        flush = library.glFlush if library is not None else None
    except AttributeError:
        flush = None
    if flush is None:
        return lambda: None
    flush.restype, flush.argtypes = None, []
    return flush


@cache
def gl_library() -> ctypes.CDLL | None:
    """The GL library glcontext loads, whose GL 1.1 entry points reach the current context on every
    platform; None where it cannot be found."""
    try:
        return _gl_library()
    except OSError:
        return None


def _gl_library() -> ctypes.CDLL | None:
    if sys.platform == "win32":
        return ctypes.WinDLL(os.environ.get("GLCONTEXT_WIN_LIBGL", "opengl32"))  # by name: the loaded one
    if sys.platform == "darwin":
        path = ctypes.util.find_library("OpenGL")
    else:
        path = os.environ.get("GLCONTEXT_LINUX_LIBGL") or ctypes.util.find_library("GL")
    return None if path is None else ctypes.CDLL(path)


# llvmpipe sorts every primitive of a flush into tiles before its threads draw any: drawn in pieces
# with a glFlush after each, the next piece is sorted while the threads draw the last.
SOFTWARE_PIECE_PRIMITIVES = 1 << 14
# llvmpipe keeps the memory of every scene it has queued, for reuse; the normals' segments, made by a
# geometry stage, queue far deeper than triangles do, so their draws wait for it every few pieces.
SOFTWARE_SEGMENT_PIECES_IN_FLIGHT = 4


def draw_piece_primitives(ctx: moderngl.Context) -> int | None:
    """How many primitives a draw call sends before a glFlush: pieces on llvmpipe; None (whole draws)
    on a GPU, where each flush costs a submission."""
    return SOFTWARE_PIECE_PRIMITIVES if is_llvmpipe(ctx) else None


# Compute programs came with OpenGL 4.3.
COMPUTE_GL_VERSION = 430


def lights_by_compute(ctx: moderngl.Context) -> bool:
    """Whether the lighting pass runs as a compute program: on llvmpipe, which runs a vertex stage on
    one thread and a compute program on all of them. GPUs keep transform feedback, as fast there."""
    return is_llvmpipe(ctx) and ctx.version_code >= COMPUTE_GL_VERSION


def is_llvmpipe(ctx: moderngl.Context) -> bool:
    """Whether this context is Mesa's llvmpipe, whose GPU memory is the process's own."""
    # At the start only: zink on lavapipe, a Vulkan driver, names llvmpipe later in its string.
    return str(ctx.info.get("GL_RENDERER", "")).startswith("llvmpipe")


def max_texture_side(ctx: moderngl.Context) -> int:
    """The longest texture side this GL takes."""
    return int(ctx.info["GL_MAX_TEXTURE_SIZE"])


def max_framebuffer_side(ctx: moderngl.Context) -> int:
    info = ctx.info
    viewport = info.get("GL_MAX_VIEWPORT_DIMS", (0, 0))
    return int(min(info.get("GL_MAX_RENDERBUFFER_SIZE", 0), *viewport))


@contextmanager
def offscreen_framebuffer(ctx: moderngl.Context, size: tuple[int, int]) -> Iterator[moderngl.Framebuffer]:
    """A colour and depth framebuffer of `size`, refused in one line when this GL cannot hold it, and
    released with its attachments afterwards (moderngl's Framebuffer.release leaves them alive)."""
    largest = max_framebuffer_side(ctx)
    if max(size) > largest:
        raise ViewerError(f"a picture of {size[0]}x{size[1]} is larger than this OpenGL can draw "
                          f"({largest}x{largest} at most)")
    ctx.error  # noqa: B018 - reading it clears an older error, so the check below is about this one
    bound = ctx.fbo  # bound again before the release: moderngl would later bind the deleted name
    try:
        fbo = ctx.simple_framebuffer(size, components=4)
    except (moderngl.Error, MemoryError) as error:
        raise ViewerError(f"cannot make a {size[0]}x{size[1]} picture ({error})") from None
    try:
        check_gl(ctx, f"a {size[0]}x{size[1]} picture")
        yield fbo
    finally:
        (bound if bound is not None else ctx.detect_framebuffer(0)).use()
        attachments = [*fbo.color_attachments, fbo.depth_attachment]
        fbo.release()
        for attachment in attachments:
            if attachment is not None:
                attachment.release()


def read_pixels(fbo: moderngl.Framebuffer, size: tuple[int, int]) -> np.ndarray:
    """(H, W, 3) uint8, top row first."""
    width, height = size
    try:
        pixels = np.frombuffer(fbo.read(components=3, alignment=1), np.uint8).reshape(height, width, 3)
        return np.flipud(pixels)
    except MemoryError:
        raise ViewerError(f"not enough memory to read a {width}x{height} picture") from None
