"""Mipmapped textures without paying for glGenerateMipmap's first call.

Mesa's llvmpipe compiles a blit shader the first time a process generates mipmaps, a noticeable part
of the screenshot command's start and of the window's. moderngl can only allocate mip levels through
`build_mipmaps` (`Texture.write(level=n)` refuses a level it did not allocate), so for a power-of-two
image the levels are made here with numpy and uploaded with `glTexImage2D` through ctypes, then
wrapped with `ctx.external_texture`. The GL entry points come from glvnd's `libOpenGL.so.0`, which
dispatches to whichever context is current on the thread, EGL or GLX. The levels are llvmpipe's own,
bit for bit (tests/test_mipmaps.py compares every level with `build_mipmaps`): each level averages
horizontal pairs, then vertical pairs, rounding halves up.

Anything else (a side that is not a power of two, no glvnd, a GL error) takes `build_mipmaps`.

A texture is sampled as its material says (model.sampling): moderngl sets filters, repeat and clamp;
mirrored repeat, which it does not name, is set through glTexParameteri, from glvnd or else from the
platform's GL library (opengl32 on Windows, the OpenGL framework on macOS).
"""

from __future__ import annotations

import ctypes
from dataclasses import dataclass
from functools import cache

import moderngl
import numpy as np

from marraztu.model.sampling import DEFAULT_SAMPLING, Filter, TextureSampling, Wrap
from marraztu.render.context import gl_library

GL_TEXTURE_2D = 0x0DE1
GL_TEXTURE_BINDING_2D = 0x8069
GL_UNPACK_ALIGNMENT = 0x0CF5
GL_RGB8 = 0x8051
GL_RGB = 0x1907
GL_UNSIGNED_BYTE = 0x1401
GL_TEXTURE_WRAP_S = 0x2802
GL_TEXTURE_WRAP_T = 0x2803
GL_MIRRORED_REPEAT = 0x8370
# A minified picture's filter within a level and between levels (None: level 0 alone), as GL names them.
_MINIFY = {(Filter.NEAREST, None): moderngl.NEAREST, (Filter.LINEAR, None): moderngl.LINEAR,
           (Filter.NEAREST, Filter.NEAREST): moderngl.NEAREST_MIPMAP_NEAREST,
           (Filter.LINEAR, Filter.NEAREST): moderngl.LINEAR_MIPMAP_NEAREST,
           (Filter.NEAREST, Filter.LINEAR): moderngl.NEAREST_MIPMAP_LINEAR,
           (Filter.LINEAR, Filter.LINEAR): moderngl.LINEAR_MIPMAP_LINEAR}
_MAGNIFY = {Filter.NEAREST: moderngl.NEAREST, Filter.LINEAR: moderngl.LINEAR}


def mip_levels(image: np.ndarray) -> list[np.ndarray]:
    """Level 0 (`image`, (H, W, C) uint8, both sides powers of two) down to 1x1, as llvmpipe's
    glGenerateMipmap makes them: its linear blit at each 2x2 block's centre is two 8-bit lerps at
    weight one half, horizontal first, each rounding up."""
    levels = [np.ascontiguousarray(image, dtype=np.uint8)]
    while levels[-1].shape[0] > 1 or levels[-1].shape[1] > 1:
        level = levels[-1].astype(np.uint16)
        if level.shape[1] > 1:
            level = (level[:, 0::2] + level[:, 1::2] + 1) >> 1
        if level.shape[0] > 1:
            level = (level[0::2] + level[1::2] + 1) >> 1
        levels.append(level.astype(np.uint8))
    return levels


def is_power_of_two(n: int) -> bool:
    return n > 0 and n & (n - 1) == 0


@cache
def _gl() -> ctypes.CDLL | None:
    try:
        return ctypes.CDLL("libOpenGL.so.0")
    except OSError:
        return None


@dataclass
class MipmappedTexture:
    """A (W, H) RGB texture with all its mip levels, sampled as its material says (`sample`). `texture`
    is the moderngl object to `use()`; `release()` frees the GL texture whichever way it was made."""

    texture: moderngl.Texture
    external_name: int | None = None  # the GL name when the levels came from numpy, ours to delete

    def use(self, location: int = 0) -> None:
        self.texture.use(location=location)

    def sample(self, sampling: TextureSampling) -> None:
        """Sampled as `sampling` says; a mirrored wrap repeats only where no GL library can be found."""
        self.texture.filter = (_MINIFY[sampling.minify, sampling.between_levels], _MAGNIFY[sampling.magnify])
        self.texture.repeat_x = sampling.wrap_u is not Wrap.CLAMP
        self.texture.repeat_y = sampling.wrap_v is not Wrap.CLAMP
        mirrored = [axis for axis, wrap in ((GL_TEXTURE_WRAP_S, sampling.wrap_u), (GL_TEXTURE_WRAP_T, sampling.wrap_v))
                    if wrap is Wrap.MIRROR]
        gl = _gl() or gl_library()
        if not mirrored or gl is None:
            return
        bound = ctypes.c_int(0)
        gl.glGetIntegerv(GL_TEXTURE_BINDING_2D, ctypes.byref(bound))
        gl.glBindTexture(GL_TEXTURE_2D, self.texture.glo)
        for axis in mirrored:
            gl.glTexParameteri(GL_TEXTURE_2D, axis, GL_MIRRORED_REPEAT)
        gl.glBindTexture(GL_TEXTURE_2D, bound.value)  # moderngl's bindings stay as it left them

    def release(self) -> None:
        self.texture.release()
        # moderngl does not delete what external_texture wrapped: the name is ours to delete.
        gl = _gl()
        if self.external_name is not None and gl is not None:
            gl.glDeleteTextures(1, ctypes.byref(ctypes.c_uint(self.external_name)))
            self.external_name = None


def create_mipmapped(ctx: moderngl.Context, pixels: np.ndarray,
                     sampling: TextureSampling = DEFAULT_SAMPLING) -> MipmappedTexture:
    """`pixels`: (H, W, 3) uint8, first row at v = 0 (GL's order), sampled as `sampling` says."""
    height, width = pixels.shape[:2]
    made = None
    if is_power_of_two(width) and is_power_of_two(height) and _gl() is not None:
        made = _upload_levels(ctx, mip_levels(pixels))
    if made is None:
        texture = ctx.texture((width, height), 3, np.ascontiguousarray(pixels).tobytes(), alignment=1)
        texture.build_mipmaps()
        made = MipmappedTexture(texture)
    made.sample(sampling)
    return made


def _upload_levels(ctx: moderngl.Context, levels: list[np.ndarray]) -> MipmappedTexture | None:
    gl = _gl()
    assert gl is not None
    ctx.error  # noqa: B018 - reading it clears any earlier error, so the check below is about ours
    name = ctypes.c_uint(0)
    gl.glGenTextures(1, ctypes.byref(name))
    bound = ctypes.c_int(0)
    gl.glGetIntegerv(GL_TEXTURE_BINDING_2D, ctypes.byref(bound))
    gl.glBindTexture(GL_TEXTURE_2D, name)
    gl.glPixelStorei(GL_UNPACK_ALIGNMENT, 1)
    for index, level in enumerate(levels):
        gl.glTexImage2D(GL_TEXTURE_2D, index, GL_RGB8, level.shape[1], level.shape[0], 0, GL_RGB,
                        GL_UNSIGNED_BYTE, level.ctypes.data_as(ctypes.c_void_p))
    gl.glBindTexture(GL_TEXTURE_2D, bound.value)  # moderngl's bindings stay as it left them
    if name.value == 0 or ctx.error != "GL_NO_ERROR":
        gl.glDeleteTextures(1, ctypes.byref(name))
        return None
    size = (levels[0].shape[1], levels[0].shape[0])
    return MipmappedTexture(ctx.external_texture(name.value, size, 3, 0, "f1"), name.value)
