"""The window hands back the memory the C library keeps after frames have freed their arrays: where
that library is glibc (tests/test_window_xvfb.py checks when the window asks)."""

from __future__ import annotations

import platform

from marraztu.frontends.heap import return_freed_memory


def test_freed_memory_goes_back_where_the_c_library_is_glibc() -> None:
    expected = platform.system() == "Linux" and platform.libc_ver()[0] == "glibc"
    assert return_freed_memory() is expected
