"""An offscreen OpenGL context: EGL where there is one (no display needed), otherwise the platform's
own standalone context (CGL on macOS, WGL on Windows, GLX with a display on Linux)."""

from __future__ import annotations

import moderngl

from marraztu.errors import ViewerError

GL_VERSION = 330


def create_offscreen_context() -> moderngl.Context:
    try:
        return moderngl.create_standalone_context(require=GL_VERSION, backend="egl")
    except Exception as egl_error:  # glcontext raises plain Exception subclasses of its own
        try:
            return moderngl.create_standalone_context(require=GL_VERSION)
        except Exception as error:
            raise ViewerError(f"cannot create an offscreen OpenGL {GL_VERSION // 100}.{GL_VERSION // 10 % 10} "
                              f"context: EGL said {_first_line(egl_error)}; the platform's context said "
                              f"{_first_line(error)}") from error


def _first_line(error: Exception) -> str:
    return (str(error).strip().splitlines() or [type(error).__name__])[0]
