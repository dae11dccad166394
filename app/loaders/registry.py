"""Which reader opens a model file: one table from file suffix to reader."""

from __future__ import annotations

import gc
from collections.abc import Callable
from pathlib import Path

from marraztu.errors import LoadError
from marraztu.loaders.exchange import COLLECT_AFTER_BYTES, load_gltf, load_ply
from marraztu.loaders.files import size_or_zero
from marraztu.loaders.obj import load_obj
from marraztu.loaders.off import load_off
from marraztu.loaders.stl import load_stl
from marraztu.model.mesh import Mesh

Stage = Callable[[str], None]  # hears what a long load is doing now, for the window's status
ModelReader = Callable[[Path, Stage | None], Mesh]

# STL and PLY come in ASCII and binary: their readers tell the two apart by content.
MODEL_READERS: dict[str, ModelReader] = {
    ".obj": load_obj,
    ".stl": load_stl,
    ".ply": load_ply,
    ".off": load_off,
    ".gltf": load_gltf,
    ".glb": load_gltf,
}


def load_model(path: str | Path, stage: Stage | None = None) -> Mesh:
    """The model in `path`, read by the reader of its suffix; LoadError naming the file otherwise."""
    path = Path(path)
    reader = MODEL_READERS.get(path.suffix.lower())
    if reader is None:
        known = ", ".join(MODEL_READERS)
        raise LoadError(path, f"not a model file marraztu reads (by its suffix: {known})")
    try:
        return reader(path, stage)
    except MemoryError:  # every reader's tables grow with the file
        failure = LoadError(path, "not enough memory to load this file")
    except LoadError as error:
        failure = error
    try:
        raise _freed(failure, path)
    finally:
        del failure  # else this frame, in the error's traceback, would hold the error: a cycle


def _freed(failure: LoadError, path: Path) -> LoadError:
    """The error without the traceback and context that hold the reader's frames, and in them the file's
    bytes and tables (trimesh's in cycles: collected here for a large file). It is told in one line."""
    failure.__traceback__ = failure.__context__ = None
    if size_or_zero(path) >= COLLECT_AFTER_BYTES:
        gc.collect()
    return failure
