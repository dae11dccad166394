"""marraztu: a 3D viewer for people who learn and teach computer graphics.

`marraztu.Viewer` draws the program's scenes offscreen, for notebooks and scripts
(marraztu.frontends.api).
"""

from importlib.metadata import PackageNotFoundError, version
from typing import Any

try:
    __version__ = version("marraztu")
except PackageNotFoundError:  # run from a checkout that was never installed
    __version__ = "0+unknown"

_API_NAMES = ("Viewer", "ProbeReport", "ProbedVertex", "LightShare", "LoadError")


def __getattr__(name: str) -> Any:
    # Imported on first use: the command line and `--help` need none of GL's start-up.
    if name in _API_NAMES:
        from marraztu.frontends import api

        return getattr(api, name)
    raise AttributeError(f"module 'marraztu' has no attribute {name!r}")


__all__ = ["__version__", *_API_NAMES]
