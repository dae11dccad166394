"""The model files around a loaded one: its neighbours in its folder (PageDown / PageUp) and whether it
changed on disk (--watch)."""

from __future__ import annotations

import bisect
import os
from collections.abc import Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

from marraztu.loaders.files import Stamp, file_stamp, same_file_key
from marraztu.loaders.registry import MODEL_READERS
from marraztu.model.scene import Scene, SceneObject
from marraztu.model.transforms import Vec3


def _sort_key(path: Path) -> tuple[str, str]:
    return path.name.lower(), path.name  # as a file browser lists them: case apart, then exact


def model_files(folder: Path) -> list[Path]:
    """The files of `folder` that some reader opens (by suffix), in name order."""
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return []
    files = []
    for entry in entries:
        try:
            if Path(entry.name).suffix.lower() in MODEL_READERS and entry.is_file():
                files.append(Path(entry.path))
        except OSError:  # vanished or unreadable while listing: not a neighbour
            continue
    return sorted(files, key=_sort_key)


def sibling_model(path: Path, step: int) -> Path | None:
    """The model file `step` places after `path` in its folder, wrapping round; None when it is alone.

    `path` itself may be gone (renamed, deleted): the neighbours are then found by its name."""
    files = [file for file in model_files(path.parent) if file.name != path.name]
    if not files:
        return None
    position = bisect.bisect_left([_sort_key(file) for file in files], _sort_key(path))
    index = position + step - 1 if step > 0 else position + step  # `path` sits between index-1 and index
    return files[index % len(files)]


def _stamp(path: Path) -> Stamp | None:
    """As the file stands now; None while it is gone (an editor replacing it) or empty (an editor that writes
    in place, not yet written): not a change until it is back."""
    stamp = file_stamp(path)
    return None if stamp is None or stamp.size == 0 else stamp


@dataclass
class FileWatcher:
    """Which of a few files (--watch's scene file, and the pictures it names) changed on disk since it was
    last seen; each change told once. One look stats each file: no thread, nothing done between looks."""

    path: Path  # the scene file; it is seen as it is when the watcher is made (before it is read)
    _seen: dict[Path, Stamp | None] = field(default_factory=dict)

    def __post_init__(self) -> None:
        self._seen = {self.path: _stamp(self.path)}

    def watch_also(self, others: Iterable[Path]) -> None:
        """The scene file and `others` from now on: a file watched before stays as last seen, a new one is
        seen as it is now."""
        watched = dict.fromkeys((self.path, *others))  # a picture a thousand objects name: stat once
        self._seen = {path: self._seen[path] if path in self._seen else _stamp(path) for path in watched}

    def watch_too(self, other: Path) -> None:
        """`other` as well as those watched now, seen as it is now where it is new."""
        self._seen.setdefault(other, _stamp(other))

    def changed(self) -> Path | None:
        """The first file that changed since the last look, where one did; all of them are seen anew."""
        stamps = {path: _stamp(path) for path in self._seen}
        changed = [path for path, stamp in stamps.items() if stamp is not None and stamp != self._seen[path]]
        self._seen.update((path, stamps[path]) for path in changed)
        return changed[0] if changed else None


@dataclass
class ModelWatcher:
    """Which elements' files changed on disk since they were last seen (--watch)."""

    _seen: dict[int, tuple[Path, Stamp]] = field(default_factory=dict)

    def changed(self, scene: Scene) -> list[SceneObject]:
        """Elements whose file differs from when it was first or last seen; each change told once."""
        changed = []
        elements = [element for element in scene.objects + scene.cameras if element.source is not None]
        stamps = {source: _stamp(source) for source in {element.source for element in elements}}  # one stat a file
        for element in elements:
            stamp = stamps[element.source]
            if stamp is None:
                continue
            seen = self._seen.get(element.uid)
            if seen is not None and seen[0] == element.source and seen[1] != stamp:
                changed.append(element)
            self._seen[element.uid] = (element.source, stamp)
        live = {element.uid for element in elements}
        self._seen = {uid: seen for uid, seen in self._seen.items() if uid in live}
        return changed

    def files_seen(self) -> dict[Path, Stamp]:
        """Each file as last seen (SeenFiles)."""
        return {source: stamp for source, stamp in self._seen.values()}

    def stand_as(self, elements: list[SceneObject], seen: dict[Path, Stamp]) -> None:
        """`elements` as if last seen when their files were as `seen` says (SeenFiles): a file that
        differs from that is told as changed at the next look."""
        for element in elements:
            if element.source in seen:
                self._seen[element.uid] = (element.source, seen[element.source])


class SeenFiles(NamedTuple):
    """The models' files as seen by the look that found their scene file changed, which is read again
    with them. A read that fails leaves its elements standing as the files were before that look, so that
    a change it found is told again; the elements a read places stand as after it, not as when they
    joined, so that a file saved while it was read is told."""
    before: dict[Path, Stamp]
    after: dict[Path, Stamp]


def read_together(elements: list[SceneObject]) -> list[tuple[SceneObject, ...]]:
    """`elements` by file (however spelled) and scale, in order: each group is read once and shares the
    mesh, as a scene file's entries of one model at one scale do."""
    keys = {source: same_file_key(source) for source in {element.source for element in elements}}
    groups: dict[tuple[Path, Vec3], list[SceneObject]] = {}
    for element in elements:
        # A scale set by hand may be a list: its numbers, which the read takes, are the key.
        groups.setdefault((keys[element.source], tuple(element.scale)), []).append(element)
    return [tuple(group) for group in groups.values()]
