"""numba's njit, its machine code cached in the person's cache folder, not in the installed package:
pip knows nothing of files numba writes there, and `pip uninstall` left them, a folder that still
imported as an empty package. NUMBA_CACHE_DIR, where set, is the person's own choice."""

from __future__ import annotations

import os
from pathlib import Path

from numba import config, njit

__all__ = ["njit"]


def _cache_folder() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "marraztu" / "numba"


if not config.CACHE_DIR:  # a folder numba cannot make or write falls back to its own places
    config.CACHE_DIR = str(_cache_folder())
