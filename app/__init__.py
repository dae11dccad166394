"""marraztu: a 3D viewer for people who learn and teach computer graphics.

`marraztu.Viewer` draws the program's scenes offscreen, for notebooks and scripts
(marraztu.frontends.api).
"""

from typing import Any

_API_NAMES = ("Viewer", "ProbeReport", "ProbedVertex", "LightShare", "ViewerError", "LoadError", "KeyMapError")


def __getattr__(name: str) -> Any:
    if name == "__version__":  # importing importlib.metadata costs more start-up than the rest of this package
        return _installed_version()
    # Imported on first use: the command line and `--help` need none of GL's start-up.
    if name in _API_NAMES:
        from marraztu.frontends import api

        return getattr(api, name)
    raise AttributeError(f"module 'marraztu' has no attribute {name!r}")


__all__ = ["__version__", *_API_NAMES]


def __dir__() -> list[str]:
    """The lazily imported names too, so that a notebook's completion offers marraztu.Viewer."""
    return sorted({*globals(), *__all__})


def _installed_version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("marraztu")
    except PackageNotFoundError:  # run from a checkout that was never installed
        return "0+unknown"
