"""marraztu: a 3D viewer for people who learn and teach computer graphics."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("marraztu")
except PackageNotFoundError:  # run from a checkout that was never installed
    __version__ = "0+unknown"
