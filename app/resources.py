"""Where the program's own files are: its GLSL programs and the built-in scene's models and texture.

Found through importlib.resources, so an editable install, a wheel and pipx find them the same way.
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path


def _folder(package: str) -> Path:
    folder = files(package)
    # Scene files name their models relative to themselves, so the assets must be real files.
    if not isinstance(folder, Path):
        raise RuntimeError(f"{package} is installed inside an archive; install marraztu unpacked")
    return folder


ASSET_DIR = _folder("marraztu.assets")
SHADER_DIR = _folder("marraztu.shaders")


def shader_source(name: str) -> str:
    """The text of shaders/<name>.glsl."""
    return (SHADER_DIR / f"{name}.glsl").read_text(encoding="utf-8")
