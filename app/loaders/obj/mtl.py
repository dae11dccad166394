"""The MTL file beside an OBJ: every material's numbers and diffuse texture. Every problem is a note, not an
error: the model still loads, with the colours that could be read."""

from __future__ import annotations

import re
from collections.abc import Collection, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from marraztu.errors import LoadError
from marraztu.loaders.files import (
    GIT_LFS_POINTER_BYTES,
    UTF16_BOMS,
    Listings,
    bom_length,
    git_lfs_pointer_words,
    is_there,
    listings_kept,
    names_in_any_case,
    read_file,
    same_file_key,
    shown,
    spellings,
    text_lines,
)
from marraztu.loaders.images import load_image, unread_textures_note
from marraztu.loaders.obj.raw import (
    MAX_LIBRARY_LINES,
    MAX_MATERIAL_NAME,
    finite_floats,
    name_before_comment,
    name_of_words,
    text_without_comment,
)
from marraztu.model.mesh import MeshMaterial, counted, with_picture_as_colour
from marraztu.model.scene import MATERIAL_COLOUR_RANGE

# A material library is a few lines per material: one this large is not one.
MAX_MTL_BYTES = 16 << 20
# 'mtllib a.mtl b.mtl' names several files; a line of a million names must not cost a million lookups.
_MOST_NAMES = 16
# Words split off an MTL line: more than any statement read here needs (a map_Kd's options and a name
# of spaces, newmtl's MAX_MATERIAL_NAME characters), so that a line of a million is never a list of them.
_MOST_WORDS = MAX_MATERIAL_NAME + 1
ROUGHNESS_RANGE = (0.0, 1.0)  # a Pr line's, as Blender's Roughness holds it


def read_libraries(base_dir: Path, lines: Sequence[str], notes: list[str], wanted: Collection[str],
                   tried: list[Path]) -> Libraries:
    """The materials of the MTL files next to the OBJ that the model can use, in file order: the first
    (the whole model's where no usemtl says) and the first of each name in `wanted` (the usemtl
    names), their pictures not yet read (Libraries.with_pictures); problems become notes. `lines`
    are the mtllib lines' names, each one file or several; `tried` hears every MTL opened or looked
    for."""
    materials: list[UnreadMaterial] = []
    read: set[Path] = set()
    finder = _Finder()
    if len(lines) > MAX_LIBRARY_LINES:
        notes.append(f"more than {MAX_LIBRARY_LINES} material libraries named: those after "
                     f"'{shown(lines[MAX_LIBRARY_LINES - 1])}' are not read")
    missing: list[str] = []
    for line in lines[:MAX_LIBRARY_LINES]:
        for mtl in _library_paths(base_dir, line, missing, finder):
            key = same_file_key(mtl)
            if key not in read:
                read.add(key)
                materials += _read_library(mtl, notes, wanted, tried, keep_first=not materials)
    notes.extend(_missing_note(missing, none_read=not read))
    first_of_name: dict[str, UnreadMaterial] = {}
    for material in materials:
        first_of_name.setdefault(material.name, material)
    return Libraries(list(first_of_name.values()), _TextureCache(finder))


@dataclass(frozen=True, eq=False)
class UnreadMaterial:
    """A material an MTL defines, its picture not read yet: a model may use more than it draws."""

    name: str
    block: _Block
    folder: Path  # its MTL's, where its picture's name is looked for


@dataclass
class Libraries:
    """The materials of an OBJ's MTL files that the model can use, and the cache of their pictures:
    one for every library, so that a picture two of them name is read once."""

    materials: list[UnreadMaterial]
    textures: _TextureCache

    def with_pictures(self, drawn: Sequence[UnreadMaterial], notes: list[str], tried: list[Path]
                      ) -> list[MeshMaterial]:
        """The `drawn` materials, each with its picture read, once; called once: `notes` hears the
        pictures that could not be read, `tried` every picture opened or looked for."""
        materials = [self._with_picture(material) for material in drawn]
        notes.extend(self.textures.notes())
        tried.extend(self.textures.read_already)
        return materials

    def shows_picture(self, material: UnreadMaterial) -> bool:
        """Whether the material's picture is there to draw: read now, once, as with_pictures reads it."""
        return self.textures.read(material.block.texture, material.folder)[0] is not None

    def _with_picture(self, material: UnreadMaterial) -> MeshMaterial:
        block = material.block
        picture, picture_name = self.textures.read(block.texture, material.folder)
        return MeshMaterial(block.name, _as_meant(block, picture is not None), picture, picture_name)


def _read_library(mtl: Path, notes: list[str], wanted: Collection[str], tried: list[Path],
                  keep_first: bool) -> list[UnreadMaterial]:
    tried.append(mtl)
    name = shown(mtl.name)
    try:
        text = read_file(mtl, limit=MAX_MTL_BYTES)  # its lines are decoded one by one, as an OBJ's names
    except LoadError as error:
        notes.append(f"material library '{name}' could not be read ({error.message}); using the scene's material")
        return []
    return _parse_library(text, name, mtl.parent, notes, wanted, keep_first)


def _library_paths(base_dir: Path, name: str, missing: list[str], finder: _Finder) -> list[Path]:
    """The files an mtllib line names: the whole line where it is one file's name ('a b.mtl' with its
    space), else each of its names that is a file ('mtllib a.mtl b.mtl'), each found as a texture is;
    the names not found go to `missing` (the whole line where none is)."""
    whole = finder.find(name, base_dir, by_last_part=False)  # 'a/x.mtl b/y.mtl' ends in a file's name too
    if whole is not None:
        return [whole]
    words = name.split(None, _MOST_NAMES)[:_MOST_NAMES]
    there = [finder.find(word, base_dir) for word in words]
    found = [path for path in there if path is not None]
    missing.extend([word for word, path in zip(words, there) if path is None] if found else [name])
    return found


def _missing_note(missing: list[str], none_read: bool) -> list[str]:
    """One note for the libraries not found, however many lines name them; the scene's material stands
    in only where no library was read."""
    if not missing:
        return []
    stand_in = "; using the scene's material" if none_read else ""
    if len(missing) == 1:
        return [f"material library '{shown(missing[0])}' not found next to the model{stand_in}"]
    return [f"{len(missing)} material libraries not found next to the model (the first '{shown(missing[0])}')"
            f"{stand_in}"]


@dataclass
class _Block:
    """One newmtl as read so far: its name, numbers and texture file."""

    name: str
    values: dict[str, object] = field(default_factory=dict)
    texture: str | None = None
    roughness: float | None = None  # a Pr line's, in 0..1
    outside: dict[str, tuple[int, float]] = field(default_factory=dict)  # a colour past 0..1: its line, a value


@dataclass
class _Library:
    """What one MTL's lines held: the materials the model can use, and what was left out of them."""

    kept: dict[str, _Block] = field(default_factory=dict)  # the materials the model can use, by name, in file order
    defines_any: bool = False  # a newmtl line was read
    before_first: int = 0  # lines of values before the first newmtl, which belong to no material
    malformed: int = 0  # one note however many lines are ignored, naming the first
    first_malformed: str = ""
    ignored: set[str] = field(default_factory=set)
    by_blender: bool = False  # its first line is a Blender exporter's: its Ka is a metallic value

    def malformed_line(self, statement: str, number: int) -> None:
        self.malformed += 1
        self.first_malformed = self.first_malformed or f"{statement} line, on line {number}"


def _parse_library(text: bytes, name: str, folder: Path, notes: list[str], wanted: Collection[str],
                   keep_first: bool = True) -> list[UnreadMaterial]:
    library = _library_contents(text, wanted, keep_first)
    notes.extend(_library_notes(name, text, library))
    return [UnreadMaterial(block.name, block, folder) for block in library.kept.values()]


def _as_meant(block: _Block, textured: bool) -> dict[str, object]:
    """A material's numbers, with what its writer meant by the lines it left out: Kd 1 1 1 where a map_Kd's
    picture gives its colour (Blender writes no Kd beside one, and draws the picture unscaled), and Ns from a Pr
    where no Ns line gives it (Blender 4's "PBR extensions" write roughness in its place). A picture that
    could not be read gives no colour: the scene's stands in, under the viewer's Kd."""
    values = with_picture_as_colour(block.values, textured)
    if block.roughness is not None and "ns" not in values:
        values = {**values, "ns": _blender_shininess(block.roughness)}
    return values


def _blender_shininess(roughness: float) -> float:
    """The Ns Blender's OBJ exporter writes for a roughness, and its importer reads back as it."""
    return (1.0 - roughness) ** 2 * 1000.0


# The first line of an MTL that Blender's exporters wrote (2.8's "# Blender MTL File: 'None'", 3.1's and later
# "# Blender 4.2.1 LTS MTL File: 'None'"): they write a material's metallic as Ka, and Blender's importer
# reads it back so. Blender has no ambient colour.
_BLENDER_HEADER = re.compile(r"#\s*Blender\b[^:]*\bMTL File\b")

# A surface's relief as a picture: Blender writes its normal map as map_Bump -bm 1.0. SPEC 4 lights the
# model's own normals.
_RELIEF_MAPS = frozenset({"map_bump", "bump", "norm"})


def _library_contents(text: bytes, wanted: Collection[str], keep_first: bool) -> _Library:
    library = _Library()
    block: _Block | None = None  # the material being read; dropped at the next newmtl unless kept
    # Past a byte order mark, which would make the first newmtl no keyword.
    for number, line in enumerate(text_lines(text, bom_length(text)), start=1):
        tokens = text_without_comment(line).split(None, _MOST_WORDS)
        if not tokens:
            library.by_blender |= number == 1 and _BLENDER_HEADER.match(line) is not None
            continue
        key = tokens[0].lower()
        if key == "newmtl":
            block = _Block(name_of_words(line.lstrip()[len(tokens[0]):]))  # as usemtl's, '#' and all
            library.defines_any = True
            named = block.name in wanted or name_before_comment(block.name) in wanted
            if (keep_first and not library.kept) or (named and block.name not in library.kept):  # the first wins
                library.kept[block.name] = block
        elif block is None:
            library.before_first += 1
        elif key == "ka" and library.by_blender:
            library.ignored.add("Ka (Blender's metallic value, not an ambient colour)")
        elif key in ("ka", "kd", "ks", "ns") and not _material_value(block.values, key, tokens[1:]):
            library.malformed_line(key.capitalize(), number)
        elif key in ("ka", "kd", "ks"):  # a colour, just set
            _note_outside(block, key, number, block.values[key], MATERIAL_COLOUR_RANGE)  # type: ignore[arg-type]
        elif key == "pr":
            roughness = finite_floats(tokens[1:])
            if roughness is None or len(roughness) != 1:
                library.malformed_line("Pr", number)
            else:
                block.roughness = min(max(roughness[0], ROUGHNESS_RANGE[0]), ROUGHNESS_RANGE[1])
                _note_outside(block, key, number, roughness, ROUGHNESS_RANGE)
        elif key == "map_kd":
            texture = _texture_file(tokens[1:])
            if texture is None:
                library.malformed_line("map_Kd", number)
            else:
                block.texture, options = texture
                library.ignored.update(options)
        elif key in ("d", "tr") and _see_through(key, tokens[1:]):
            library.ignored.add("transparency (d, Tr)")
        elif key == "ke" and _glows(tokens[1:]):
            library.ignored.add("emission (Ke)")
        elif key in _RELIEF_MAPS:
            library.ignored.add("normal and bump maps (map_Bump, bump, norm)")
    return library


def _library_notes(name: str, text: bytes, library: _Library) -> list[str]:
    notes: list[str] = []
    pointer = None if library.defines_any else git_lfs_pointer_words(text[:GIT_LFS_POINTER_BYTES], "library")
    if not library.defines_any and text.startswith(UTF16_BOMS):  # as an OBJ's
        notes.append(f"material library '{name}' is UTF-16 text: save it as UTF-8; using the scene's material")
    elif pointer is not None:  # a note, not a refusal, as any library that gives no material
        notes.append(f"material library '{name}' is {pointer}; using the scene's material")
    elif not library.defines_any:
        notes.append(f"material library '{name}' defines no material; using the scene's material")
    elif library.before_first:
        before_first = library.before_first
        notes.append(f"material library '{name}': {counted(before_first, 'line')} before the first newmtl, "
                     f"which belong{'s' if before_first == 1 else ''} to no material, ignored")
    if library.malformed == 1:
        notes.append(f"material library '{name}': ignored a malformed {library.first_malformed}")
    elif library.malformed:
        notes.append(f"material library '{name}': ignored {library.malformed} malformed lines (the first a "
                     f"{library.first_malformed})")
    if library.ignored:
        notes.append(f"material library '{name}': {', '.join(sorted(library.ignored))} ignored")
    notes.extend(_outside_note(name, library.kept.values()))
    notes.extend(_unlit_picture_note(name, library.kept.values()))
    return notes


def _unlit_picture_note(name: str, blocks: Iterable[_Block]) -> list[str]:
    """The note of kept materials whose map_Kd sits under Kd 0 0 0, which Maya writes for a colour a
    picture gives: the picture gets no diffuse light, and the model is drawn black."""
    unlit = [block.name for block in blocks if block.texture is not None and block.values.get("kd") == (0.0, 0.0, 0.0)]
    if not unlit:
        return []
    first = f"material '{shown(unlit[0])}'"
    if len(unlit) == 1:
        which, picture = f"{first} has", "its picture gets"
    else:
        which, picture = f"{len(unlit)} materials (the first, {first}) have", "their pictures get"
    return [f"material library '{name}': {which} Kd 0 0 0 and a map_Kd, so {picture} no diffuse light "
            "(Maya writes so: Kd 1 1 1 shows the picture)"]


def _note_outside(block: _Block, key: str, line: int, values: Iterable[float], held_to: tuple[float, float]) -> None:
    """Remembers where the `values` of `key` just set (a colour, or Pr) hold one outside `held_to`,
    which drawing holds them to."""
    low, high = held_to
    outside = [value for value in values if not low <= value <= high]
    if outside:
        block.outside[key] = (line, outside[0])
    else:
        block.outside.pop(key, None)  # a later line of the key replaces the earlier one


def _outside_note(name: str, blocks: Iterable[_Block]) -> list[str]:
    """The note of the kept materials' colours and Pr outside MTL's 0..1: Kd 255 128 0, written in
    0..255, is drawn yellow, not orange."""
    found = sorted((line, key, value) for block in blocks for key, (line, value) in block.outside.items())
    if not found:
        return []
    line, key, value = found[0]
    first = f"{key.capitalize()} on line {line} holds {value:g}"
    if len(found) == 1:
        return [f"material library '{name}': {first}, outside MTL's 0..1: held to it"]
    return [f"material library '{name}': {len(found)} values outside MTL's 0..1 held to it (the first, {first})"]


# map_Kd's options: how many values each takes (-o, -s and -t one to three), and whether they are numbers.
_TEXTURE_OPTIONS = {"-blendu": (1, False), "-blendv": (1, False), "-bm": (1, True), "-boost": (1, True),
                    "-cc": (1, False), "-clamp": (1, False), "-imfchan": (1, False), "-mm": (2, True),
                    "-texres": (1, True), "-type": (1, False), "-o": (3, True), "-s": (3, True), "-t": (3, True)}


# What each option is where a line leaves it out (the MTL specification): written so, it changes nothing.
_TEXTURE_OPTION_DEFAULTS: dict[str, tuple[float, ...] | tuple[str, ...]] = {
    "-o": (0.0, 0.0, 0.0), "-s": (1.0, 1.0, 1.0), "-t": (0.0, 0.0, 0.0), "-mm": (0.0, 1.0), "-bm": (1.0,),
    "-blendu": ("on",), "-blendv": ("on",), "-clamp": ("off",), "-cc": ("off",)}


def _texture_file(tokens: list[str]) -> tuple[str, set[str]] | None:
    """The file a map_Kd line names (the rest of the line after its options: names may hold spaces; its
    last word, as an option's values never take it, even one spelled as an option), and the options it
    gives, which marraztu does not apply; None where it names none, or an option's number is none by the
    rule of Kd's numbers (finite_floats)."""
    options: set[str] = set()
    at = 0
    while at < len(tokens) - 1 and tokens[at].lower() in _TEXTURE_OPTIONS:
        option = tokens[at].lower()
        most, numbers = _TEXTURE_OPTIONS[option]
        start = at = at + 1
        while at - start < most and at < len(tokens) - 1 and (most < 3 or _meant_as_number(tokens[at])):
            at += 1
        values = finite_floats(tokens[start:at]) if numbers else tuple(token.lower() for token in tokens[start:at])
        if values is None:
            return None
        if tuple(values) != _TEXTURE_OPTION_DEFAULTS.get(option, ())[:len(values)] or not values:
            options.add(f"texture option {option}")
    name = " ".join(tokens[at:])
    return (name, options) if name else None


def _meant_as_number(token: str) -> bool:
    """Where -o, -s and -t's numbers end, and the name begins: at a word float() does not read. It reads
    more than the rule (1_0, nan, an Arabic-Indic 1), so such a word is the option's, and refused by it."""
    try:
        float(token)
    except ValueError:
        return False
    return True


class _Finder:
    """The file a name in an OBJ or MTL means. Exporters write Windows paths (back slashes, a drive:
    C:\\Users\\...\\t.png, from the machine the model was made on), quote names, and differ in case from
    the file: what is not found as written is looked for by its last part beside the file that
    names it, and then in any case, each folder listed once however many names are looked for."""

    def __init__(self) -> None:
        self.listings: Listings = {}  # by the folder resolved: 'a/..' and '.' are one
        self.resolved: dict[Path, Path] = {}  # a folder as named -> resolved: resolved once, not once a name

    def find(self, name: str, folder: Path, by_last_part: bool = True) -> Path | None:
        candidates = [folder / spelling for spelling in spellings(name)[:None if by_last_part else 1]]
        found = next((path for path in candidates if is_there(path)), None)
        return found or next((path for path in map(self._in_any_case, candidates) if path is not None), None)

    def _in_any_case(self, path: Path) -> Path | None:
        if path.parent not in self.resolved:
            self.resolved[path.parent] = same_file_key(path.parent)
        folder = self.resolved[path.parent]
        if folder not in self.listings:
            self.listings[folder] = names_in_any_case(path.parent)
        names = self.listings[folder].get(path.name.lower())
        return None if names is None else path.parent / names[0]


class _TextureCache:
    """Each texture file read once, however many materials name it; the ones that cannot be read
    make one note."""

    def __init__(self, finder: _Finder) -> None:
        self.read_already: dict[Path, tuple[np.ndarray | None, str | None]] = {}
        self.found: dict[tuple[str, Path], Path] = {}  # a name looked for once, for every material
        self.failures: list[tuple[str, str]] = []  # (name, why)
        self.finder = finder

    def read(self, name: str | None, folder: Path) -> tuple[np.ndarray | None, str | None]:
        """The picture a map_Kd line of an MTL in `folder` names."""
        if name is None:
            return None, None
        key = self.found.get((name, folder))
        if key is None:
            path = self.finder.find(name, folder) or folder / spellings(name)[0]  # not there: reading it says so
            key = self.found[name, folder] = same_file_key(path)  # t.png and ./t.png are one file, read once
            if key not in self.read_already:
                self.read_already[key] = self._read(path, name)
        return self.read_already[key]

    def _read(self, path: Path, name: str) -> tuple[np.ndarray | None, str | None]:
        try:
            with listings_kept(self.finder.listings):  # a missing picture's hint: its folder is listed already
                return load_image(path), name
        except LoadError as error:
            self.failures.append((name, error.message))
            return None, None

    def notes(self) -> list[str]:
        return unread_textures_note(self.failures)


def _see_through(key: str, tokens: list[str]) -> bool:
    """Whether a d or Tr line asks for transparency (d below 1, Tr above 0): an opaque one changes nothing."""
    values = finite_floats(tokens[-1:])  # "d -halo 0.5" puts its option first
    if not values:
        return True  # unreadable: said to be ignored
    return values[0] < 1.0 if key == "d" else values[0] > 0.0


def _glows(tokens: list[str]) -> bool:
    """Whether a Ke line asks for emission, which SPEC 4's lighting has no term for: Blender writes Ke 0 0 0
    for every material that does not glow."""
    values = finite_floats(tokens)
    return not values or any(value != 0.0 for value in values)  # unreadable: said to be ignored


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
