"""The error a person sees of a reader's refusal: a LoadError, in one line."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from marraztu.errors import LoadError


def one_line_refusal(read: Callable[[], object]) -> LoadError:
    """The LoadError `read` raises, checked to be one line."""
    with pytest.raises(LoadError) as refused:
        read()
    assert "\n" not in str(refused.value)
    return refused.value


def written(folder: Path, text: str, name: str) -> Path:
    """A file `name` in `folder` holding `text` in UTF-8, for a reader to read."""
    path = folder / name
    path.write_text(text, encoding="utf-8")
    return path
