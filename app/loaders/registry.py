"""Which reader opens a model file: one table from file suffix to reader."""

from __future__ import annotations

import gc
import importlib
import sys
from collections.abc import Callable
from pathlib import Path

from marraztu.errors import LoadError, error_words
from marraztu.loaders.files import COLLECT_AFTER_BYTES, refuse_git_lfs_pointer, regular_file_size, size_or_zero
from marraztu.model.build import scaled_mesh
from marraztu.model.geometry import cannot_light
from marraztu.model.mesh import Mesh
from marraztu.model.transforms import Vec3

UNSCALED: Vec3 = (1.0, 1.0, 1.0)
Stage = Callable[[str], None]  # hears what a long load is doing now, for the window's status
ModelReader = Callable[[Path, Stage | None], Mesh]

# Each reader's module and function: a module is imported when a file of its kind is first opened,
# so a start that reads OBJ files only (the built-in scene's) never imports the others.
# STL and PLY come in ASCII and binary: their readers tell the two apart by content.
MODEL_READERS: dict[str, tuple[str, str]] = {
    ".obj": ("marraztu.loaders.obj", "load_obj"),
    ".stl": ("marraztu.loaders.stl", "load_stl"),
    ".ply": ("marraztu.loaders.exchange", "load_ply"),
    ".off": ("marraztu.loaders.off", "load_off"),
    ".gltf": ("marraztu.loaders.exchange", "load_gltf"),
    ".glb": ("marraztu.loaders.exchange", "load_gltf"),
}


def reader_of(suffix: str) -> ModelReader | None:
    """The reader of files ending in `suffix` (lower case), None for a suffix no reader takes."""
    found = MODEL_READERS.get(suffix)
    if found is None:
        return None
    module, name = found
    reader: ModelReader = getattr(importlib.import_module(module), name)
    return reader


def load_model(path: str | Path, stage: Stage | None = None) -> Mesh:
    """The model in `path`, read by the reader of its suffix; LoadError naming the file otherwise."""
    path = Path(path)
    reader = reader_of(path.suffix.lower())
    if reader is None:
        regular_file_size(path, limit=sys.maxsize)  # a folder or a missing file is said so, not its suffix blamed
        known = ", ".join(MODEL_READERS)
        raise LoadError(path, f"not a model file marraztu reads (by its suffix: {known})")
    refuse_git_lfs_pointer(path, "model")  # before a format's reader blames its own first bytes
    try:
        return _drawable(reader(path, stage), path)
    except MemoryError:  # every reader's tables grow with the file
        failure = LoadError(path, "not enough memory to load this file")
    except LoadError as error:
        failure = error
    except Exception as error:  # a reader's bug: the person still reads one line naming the file
        failure = LoadError(path, f"could not read the model ({error_words(error)})")
    try:
        raise _freed(failure, path)
    finally:
        del failure  # else this frame, in the error's traceback, would hold the error: a cycle


def sized(mesh: Mesh, scale: Vec3, path: Path) -> Mesh:
    """The mesh at `scale` (scaled_mesh); LoadError naming `path` where a coordinate then lies too far
    to light."""
    return mesh if scale == UNSCALED else _drawable(scaled_mesh(mesh, scale), path)


def _drawable(mesh: Mesh, path: Path) -> Mesh:
    refusal = cannot_light(*mesh.bounds)
    if refusal is not None:
        raise LoadError(path, refusal)
    return mesh


def _freed(failure: LoadError, path: Path) -> LoadError:
    """The error without the traceback and context that hold the reader's frames, and in them the file's
    bytes and tables (trimesh's in cycles: collected here for a large file). It is told in one line."""
    failure.__traceback__ = failure.__context__ = None
    if size_or_zero(path) >= COLLECT_AFTER_BYTES:
        gc.collect()
    return failure
