"""The MTL file beside an OBJ: the numbers of its first material. Every problem is a note, not an error."""

from __future__ import annotations

from pathlib import Path

from marraztu.errors import LoadError
from marraztu.loaders.files import read_file
from marraztu.loaders.obj.raw import finite_floats

# A material library is a few lines per material: one this large is not one.
MAX_MTL_BYTES = 16 << 20
# 'mtllib a.mtl b.mtl' names several files; a line of a million names must not cost a million lookups.
_MOST_NAMES = 16
_SHOWN_NAME_CHARACTERS = 80


def first_material(base_dir: Path, name: str, notes: list[str]) -> dict[str, object] | None:
    """Ka/Kd/Ks/Ns of the first material in the MTL file next to the OBJ; problems become notes."""
    shown = _shown(name)
    mtl = _library_path(base_dir, name)
    if mtl is None:
        notes.append(f"material library '{shown}' not found next to the model; using the scene's material")
        return None
    try:
        text = read_file(mtl, limit=MAX_MTL_BYTES).decode("utf-8", errors="replace")
    except LoadError as error:
        notes.append(f"material library '{shown}' could not be read ({error.message}); using the scene's material")
        return None
    material = _parse_first_material(text, shown, notes)
    return material or None


def _library_path(base_dir: Path, name: str) -> Path | None:
    """The first of the names that exists and is no folder: 'mtllib a b.mtl' is one file with a space, or two."""
    for candidate in [name] + name.split(None, _MOST_NAMES)[:_MOST_NAMES]:
        path = base_dir / candidate
        try:
            if path.exists() and not path.is_dir():
                return path
        except (OSError, ValueError):  # a name too long for the file system, or with a NUL: not there
            continue
    return None


def _shown(name: str) -> str:
    return name if len(name) <= _SHOWN_NAME_CHARACTERS else name[:_SHOWN_NAME_CHARACTERS - 3] + "..."


def _parse_first_material(text: str, name: str, notes: list[str]) -> dict[str, object]:
    material: dict[str, object] = {}
    malformed: list[str] = []  # keys of the lines ignored, for one note however many there are
    inside = False
    for line in text.splitlines():
        tokens = line.split("#", 1)[0].split()
        if not tokens:
            continue
        key = tokens[0].lower()
        if key == "newmtl":
            if inside:
                break
            inside = True
        elif inside and key in ("ka", "kd", "ks", "ns") and not _material_value(material, key, tokens[1:]):
            malformed.append(key.capitalize())
    if not inside:
        notes.append(f"material library '{name}' defines no material; using the scene's material")
    if len(malformed) == 1:
        notes.append(f"material library '{name}': ignored a malformed {malformed[0]} line")
    elif malformed:
        notes.append(f"material library '{name}': ignored {len(malformed)} malformed lines (the first a "
                     f"{malformed[0]} line)")
    return material


def _material_value(material: dict[str, object], key: str, tokens: list[str]) -> bool:
    """Sets `key` from the numbers; False when they are not a valid value for it."""
    values = finite_floats(tokens)
    if key == "ns" and values is not None and len(values) == 1:
        material["ns"] = values[0]
    elif key != "ns" and values is not None and len(values) in (1, 3):
        material[key] = tuple(values * 3 if len(values) == 1 else values)  # one number: a grey
    else:
        return False
    return True
