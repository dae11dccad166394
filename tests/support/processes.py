"""A command run as a person runs it, not as this machine's environment would."""

from __future__ import annotations

import os


def buffered_environment() -> dict[str, str]:
    """The environment without PYTHONUNBUFFERED, which a CI machine may set: Python then buffers standard
    output to a file or a pipe, and its own flush at exit meets a full or closed output again."""
    return {name: value for name, value in os.environ.items() if name != "PYTHONUNBUFFERED"}
