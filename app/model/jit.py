"""numba's njit, its machine code cached in the person's cache folder, not in the installed package:
pip knows nothing of files numba writes there, and `pip uninstall` left them, a folder that still
imported as an empty package. NUMBA_CACHE_DIR, where set, is the person's own choice."""

from __future__ import annotations

import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numba
from numba import config


def njit(*args: Any, **options: Any) -> Callable[[Callable[..., Any]], Any]:
    """numba.njit, whose cache (numba picks its folder as it decorates) is ours for our functions
    only: a notebook's own cached functions stay where numba puts them."""
    decorate = numba.njit(*args, **options)

    def cached_in_ours(function: Callable[..., Any]) -> Any:
        given = config.CACHE_DIR
        config.CACHE_DIR = given or str(_cache_folder())  # a folder numba cannot make: it falls back
        try:
            return decorate(function)
        finally:
            config.CACHE_DIR = given

    return cached_in_ours


def has_cached_code(function: Any) -> bool | None:
    """Whether numba's cache holds machine code this process can load for an njit(cache=True) function:
    numba's own lookup (an index for this source and numba version, an entry for this CPU and bytecode).
    None where its cache cannot be asked."""
    try:  # numba has no public question for it: its Cache's own index and key
        cache, codegen = function._cache, function.targetctx.codegen()
        return any(cache._index_key(key[0], codegen) == key for key in cache._cache_file._load_index())
    except Exception:
        return None


def _cache_folder() -> Path:
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "marraztu" / "numba"
