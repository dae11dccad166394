"""Whether DracoPy is installed, as the glTF reader sees it: each of its modules that asks, told alike."""

from __future__ import annotations

import importlib
import pkgutil

import pytest

from marraztu.loaders import gltf
from marraztu.loaders.gltf import values


def draco_decoder(monkeypatch: pytest.MonkeyPatch, decoded: bool) -> None:
    """Makes values._draco_decoder answer `decoded` in every module of the reader that imported it: a
    patch of one module's name would not reach its siblings' copies."""
    asked = values._draco_decoder
    for found in pkgutil.iter_modules(gltf.__path__):
        module = importlib.import_module(f"{gltf.__name__}.{found.name}")
        if getattr(module, "_draco_decoder", None) is asked:
            monkeypatch.setattr(module, "_draco_decoder", lambda: decoded)
