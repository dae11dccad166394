"""A press is all or nothing: every key of the key map, after a few prefixes that change what it acts
on, pressed before a refused load leaves everything one can see as it was, down to the bit: the scene
walked whole (histories, materials, lights, modes, selections, message), the viewer's own state, the
renderer's caches, the probe and the pictures with and without the overlay."""

from __future__ import annotations

import dataclasses
import enum
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import marraztu
from marraztu.control.keymap import KEYMAP
from marraztu.errors import LoadError, ViewerError
from marraztu.resources import ASSET_DIR

SIZE = (64, 64)
# What the keys act on: objects, cameras (flight, then analysis), lights (the bulb, moved by t), the
# file prompt (keys typed into it), one face alone, a term view, parallel projection through the object,
# a scene whose view moves are cleared (x), taken (HOME) or undone (u) just before, a model loaded as an
# object or a camera, and no object left.
PREFIXES = ("", "c", "c g", "c c", "c c TAB t", "f", "o", "v v", "p C", "HOME", "t x", "u u", "f={model}",
            "c f={model}", "DELETE DELETE")
# Lights on, histories of the camera, the bulb and the object deeper than a press reaches, a view move
# for u to take first, the probe and the matrices panel showing a face that is not the first.
SETUP = "0 1 2 3 c x*9 c TAB t x*9 r c x*12 ENTER i m ."


def _walk(value: Any, seen: set[int]) -> Any:
    """Everything reachable from `value`, as comparable values: the identity of each mutable part (a
    caller may hold it), its contents, and each shared part once."""
    if value is None or isinstance(value, (bool, int, float, str, bytes, Path, enum.Enum)):
        return repr(value)
    if isinstance(value, np.ndarray):
        return ("array", id(value), value.dtype.str, value.shape, value.tobytes())
    if id(value) in seen:
        return ("again", id(value))
    seen.add(id(value))
    if isinstance(value, (list, tuple)):
        return (type(value).__name__, id(value), [_walk(item, seen) for item in value])
    if isinstance(value, dict):
        return ("dict", id(value), [(_walk(k, seen), _walk(v, seen)) for k, v in value.items()])
    if isinstance(value, (set, frozenset)):  # the viewer's uids of what the scene file placed
        return (type(value).__name__, id(value), sorted(repr(_walk(item, seen)) for item in value))
    if callable(value) and not dataclasses.is_dataclass(value):
        return ("callable", id(value))
    if dataclasses.is_dataclass(value):  # its fields, not what cached_property keeps beside them
        parts = {f.name: getattr(value, f.name) for f in dataclasses.fields(value)}
    else:
        parts = vars(value)
    return (type(value).__name__, id(value), {name: _walk(part, seen) for name, part in parts.items()})


def observed(v: marraztu.Viewer) -> tuple[Any, ...]:
    """What the viewer shows and holds: the pictures drawn first, so the renderer's caches are what
    they are after drawing."""
    plain, overlaid = np.asarray(v.render()), np.asarray(v.render(overlay=True))
    keys = v._viewer
    viewer_state = [(name, _walk(part, set())) for name, part in vars(keys).items() if name not in ("scene", "keys")]
    caches = sorted((key, id(gpu.mesh)) for key, gpu in v._renderer._objects.items())
    return (plain.tobytes(), overlaid.tobytes(), repr(v.probe()), v.message, caches,
            sorted(v._renderer._file_textures), _walk(v.scene, set()), viewer_state)


def differences(before: tuple[Any, ...], after: tuple[Any, ...]) -> list[str]:
    names = ("picture", "picture with overlay", "probe", "message", "renderer's meshes",
             "renderer's textures", "scene", "viewer")
    return [name for name, old, new in zip(names, before, after) if old != new]


@pytest.fixture(scope="module")
def models(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The project's two examples in a folder of their own: PageDown steps between them."""
    folder = tmp_path_factory.mktemp("models")
    for name in ("crate.obj", "crate.mtl", "crate.ppm", "two_tone.obj", "two_tone.mtl"):
        shutil.copy(ASSET_DIR / "examples" / name, folder / name)
    return folder


@pytest.fixture(scope="module")
def viewer(models: Path) -> Iterator[marraztu.Viewer]:
    """Two objects, one with its MTL's texture, the other with two materials."""
    with marraztu.Viewer(size=SIZE, empty=True) as v:
        v.load(models / "crate.obj").load(models / "two_tone.obj").press(SETUP)
        assert len(v.scene.objects) == 2 and v.scene.objects[0].mesh.materials[0].texture is not None
        yield v


def _sequences(prefix: str, missing: Path) -> Iterator[str]:
    for key in KEYMAP:
        if key == "ESC" and prefix != "f":  # ends the sequence (as --keys): the load after it is not pressed
            continue
        yield f"{prefix} {key} f={missing}"
        if key != "ESC":  # the second ESC would leave the prompt the first closed, and end the sequence
            yield f"{prefix} {key} {key} f={missing}"


@pytest.mark.parametrize("prefix", PREFIXES)
def test_every_key_before_a_refused_load_is_taken_back(viewer: marraztu.Viewer, models: Path, tmp_path: Path,
                                                       prefix: str) -> None:
    before = observed(viewer)
    failures = []
    for keys in _sequences(prefix.format(model=models / "two_tone.obj"), tmp_path / "missing.obj"):
        with pytest.raises((LoadError, ViewerError)):  # ViewerError: no file loads while lights are targeted
            viewer.press(keys)
        changed = differences(before, observed(viewer))
        if changed:
            failures.append(f"{keys.split(' f=')[0]!r}: {', '.join(changed)}")
            before = observed(viewer)  # the next sequence is measured from where this one left it
    assert not failures, "\n".join(failures)
