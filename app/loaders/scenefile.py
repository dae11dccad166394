"""Scene files: which models to load, where to put them and what they are made of, in TOML.

    texture = "selfi.ppm"                 # optional, relative to the scene file; the built-in scene's otherwise;
                                          # false: none (its models' own pictures stay)

    [materials.golden]                    # named materials, used by name below
    ka = [0.8, 0.72, 0.0]                 # ka, kd, ks: three numbers in 0..1
    kd = [0.8, 0.6, 0.4]
    ks = [0.9, 0.8, 0.5]
    ns = 80                               # > 0
    rgb = [1, 1, 1]                       # optional base colour, default white

    [[cameras]]                           # none: the built-in scene's, framing the models
    model = "camera.obj"                  # relative to the scene file; a camera's is the built-in one if left out
    position = [0, 0, 150]                # a camera's is required: where it looks from
    material = "golden"                   # a name above, or an inline table of the same keys

    [[objects]]                           # any number
    name = "Rammer_255"                   # optional: default is the model file's stem
    model = "rammer.obj"
    position = [0, 0, 0]                  # optional: the origin, where a model loaded alone stands
    scale = 0.5                           # optional: > 0, or three numbers along x, y, z; a camera's sizes its body
    material = { ka = [0.8, 0.72, 0], kd = [0.8, 0.6, 0.4], ks = [0.9, 0.8, 0.5], ns = 80 }
    texture = "concrete.png"              # optional: its own picture, in place of its model's and the scene's;
                                          # false: none, drawn at its Kd (PLAIN_PICTURE)

    ambient = [200, 75, 255]              # optional: SPEC's Ia otherwise (0..255 units, >= 0)
    [lights.bulb]                         # optional, one per light: sun, bulb, object_spotlight, camera_spotlight
    on = true                             # optional: off otherwise, as SPEC starts
    intensity = [250, 50, 150]            # optional: SPEC's otherwise, as ambient
    position = [0, 200, 0]                # the bulb's; the sun takes direction, a spotlight aperture

`scale` sizes the model as it is read (Mesh.scaled), not in its model matrix: SPEC's keys build that
matrix of turns and moves, and the steps, the near plane and the grid follow the model's size.

An entry without ``material`` gets what a model loaded at run time gets (`material_for_loaded`).
Every problem, unknown keys included (a typo must not pass silently), is a LoadError naming the
scene file and, where it can be found, the line.
"""

from __future__ import annotations

import functools
import math
import re
import sys
import tomllib
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass, field
from itertools import chain, islice
from pathlib import Path
from typing import NoReturn

import numpy as np

from marraztu.errors import LoadError, ViewerError, shortened
from marraztu.loaders.files import (
    as_typed,
    escape_words,
    file_stamp,
    line_at,
    read_file,
    said_as_written,
    same_file_key,
    shown,
)
from marraztu.loaders.images import load_image
from marraztu.loaders.patterns import compiled
from marraztu.loaders.registry import MODEL_READERS, Stage, load_model, sized
from marraztu.model.geometry import CAMERAS_REACH, FLOAT32_MAX, MODELS_REACH
from marraztu.model.lights import (
    AMBIENT_INTENSITY,
    DIRECTIONAL,
    POINT,
    SPOT,
    SPOT_APERTURE_RANGE_DEG,
    Light,
    LightKind,
    default_lights,
)
from marraztu.model.mesh import PLAIN_PICTURE, Mesh, counted, with_picture_as_colour
from marraztu.model.scene import (
    DIRECTION,
    LIGHT_COLOUR,
    MATERIAL_COLOUR,
    MATERIAL_COLOUR_RANGE,
    Material,
    Scene,
    SceneObject,
    TripleKind,
    Vec3,
    kept_name,
    name_refusal,
    place_kind,
    placement_refusal,
)
from marraztu.resources import ASSET_DIR

BUILTIN_SCENE_FILE = "scene.toml"
TOP_LEVEL_KEYS = frozenset({"texture", "materials", "objects", "cameras", "ambient", "lights"})
ENTRY_KEYS = frozenset({"name", "model", "position", "rotation", "scale", "material", "texture"})
REQUIRED_OBJECT_KEYS = ("model",)  # an object's position is the origin, where a model loaded alone stands
ORIGIN: Vec3 = (0.0, 0.0, 0.0)
# A camera's model may be left out: the built-in camera's is drawn, which an installed copy's own
# scene files cannot otherwise name (it lies inside the package).
CAMERA_MODEL = "camera.obj"
BUILT_IN_CAMERA_MODEL = ASSET_DIR / CAMERA_MODEL  # a camera's body where its scene names none
MATERIAL_KEYS = frozenset({"ka", "kd", "ks", "ns", "rgb"})
REQUIRED_MATERIAL_KEYS = ("ka", "kd", "ks", "ns")
# tomllib holds up to 100 bytes for each byte of some texts ([t1] [t2]... tables): only a scene's size is
# parsed. A scene names files and numbers: a thousand objects take about 100 KB.
SCENE_FILE_LIMIT = 1 << 20
# Read, and scanned for the runs below (linear), up to this size: a key of a million parts is named at its line.
SCENE_READ_LIMIT = 16 << 20
# Dotted parts a key may have: the deepest a scene uses is 3 (materials.NAME.kd). Checked before
# tomllib, whose cost for a dotted key grows with the square of its parts.
MAX_KEY_PARTS = 16
WHITE: Vec3 = (1.0, 1.0, 1.0)
NAMES_LISTED = 10  # the known names a message lists for one it does not know
# SPEC 4's Ia, as the file's `ambient` is read.
SPEC_AMBIENT: Vec3 = tuple(map(float, AMBIENT_INTENSITY))  # type: ignore[assignment]
LIGHT_KEYS = frozenset({"on", "intensity"})  # every light's, past the one its kind takes (KIND_KEY)
# What else a light's table sets: the sun is a direction, the bulb a place, a spotlight rides on its owner
# and sets only its cone.
KIND_KEY: dict[LightKind, str] = {DIRECTIONAL: "direction", POINT: "position", SPOT: "aperture"}

# What a model loaded at run time is made of when its file says nothing: a light grey, mostly
# diffuse plastic. Grey shows the lights' and the texture's colours as they are; the ambient share is
# low because SPEC's ambient light (200, 75, 255) is strong and violet and would wash out the shading;
# a modest, broad highlight (ns 20) makes Flat and Gouraud differ visibly without looking wet.
DEFAULT_MATERIAL = Material(ka=(0.3, 0.3, 0.3), kd=(0.7, 0.7, 0.7), ks=(0.3, 0.3, 0.3), ns=20.0)
MIN_FILE_NS = 1.0  # MTL files often say "Ns 0", which would light every face with full specular

_TOML_POSITION = re.compile(r"\s*\(at line (\d+), column (\d+)\)$")
_AT_THE_END = "(at end of document)"  # tomllib's place of an error the file's end shows
_DECLARED_TWICE = re.compile(r"Cannot declare \(.*\) twice")  # tomllib writes the key as a tuple of its parts
# tomllib's words for a bare key set twice in an inline table: the first words where its values are arrays or tables.
_INLINE_KEY_TWICE = re.compile(r"Cannot mutate immutable namespace \('(?P<a>[A-Za-z0-9_-]+)',\)"
                               r"|Duplicate inline table key '(?P<b>[A-Za-z0-9_-]+)'")
# tomllib's words for slips of a key = value line, as its writer would see them.
_SYNTAX_REWORDED = {
    "Illegal character '\\n'": 'a string in "quotes" is not closed on its line',  # a one-line "string" only
    "Found invalid character '\\n'": "a string in 'quotes' is not closed on its line",  # a one-line 'string' only
    "Invalid value": "no value TOML reads",
    "Unclosed array": "Unclosed array (a comma missing between values?)",
    "Expected ']' at the end of a table declaration": "Expected ']' at the end of a table declaration (a name with "
                                                      "spaces is written with _: [lights.camera_spotlight])",
}
# What a bare word TOML does not read was meant as, where it is a yes or a no written as a person would.
_LOWER_CASE_HINT = " (TOML writes true and false in lower case)"
_YES_NO_HINT = " (TOML writes yes and no as true and false, in lower case)"
_BARE_WORD_HINTS = {"true": _LOWER_CASE_HINT, "false": _LOWER_CASE_HINT, "yes": _YES_NO_HINT, "no": _YES_NO_HINT}
_BARE_WORD = re.compile(r"[A-Za-z]*")
# An [[array]] of the scene written [with single brackets] for each of its entries.
_ENTRY_BRACKETS = {"objects": "each object is [[objects]], with double brackets",
                   "cameras": "each camera is [[cameras]], with double brackets"}
# tomllib's words for an escape in a "double-quoted" string that it cannot read: \U and \u start hex codes.
_ESCAPE_SLIPS = frozenset({"Invalid hex value", "Unescaped '\\' in a string",
                           "Escaped character is not a Unicode scalar value"})
_QUOTES_HINT = ' (text, a file name too, goes in "quotes")'
_LOOKS_LIKE_TEXT = re.compile(r"[^\W\d]|[./\\~]")  # a value starting so is a word or a path, not a number
TOO_LARGE = "is too large: the GPU's 32-bit numbers end at 3.4e38"

# A TOML key as written: bare, "basic" (with escapes) or 'literal'; dotted keys join them with dots.
# Possessive (nothing a key gives back could match what follows it): sre keeps no state per part, which
# for a line of millions of parts was gigabytes.
_KEY_PART = r"""(?:[A-Za-z0-9_-]++|"(?:[^"\\\n]|\\.)*+"|'[^'\n]*+')"""
_NEXT_PART = rf"[ \t]*+\.[ \t]*+{_KEY_PART}"
_DOTTED_KEY = rf"{_KEY_PART}(?:{_NEXT_PART})*+"
_LINE_START = compiled("|".join((rf"[ \t]*\[\[[ \t]*(?P<array>{_DOTTED_KEY})[ \t]*\]\]",
                                 rf"[ \t]*\[[ \t]*(?P<table>{_DOTTED_KEY})[ \t]*\]",
                                 rf"[ \t]*(?P<key>{_DOTTED_KEY})[ \t]*=")))
_KEY_PARTS = compiled(_KEY_PART)
# A dotted key of more than MAX_KEY_PARTS parts, from the start of its first: never a part's middle,
# nor an escaped quote, from which a string of them would be scanned again at every one.
_LONG_DOTTED_RUN = compiled(rf"(?<![A-Za-z0-9_\\-]){_KEY_PART}(?:{_NEXT_PART}){{{MAX_KEY_PARTS}}}")
# tomllib reads a number with patterns that hold over 100 bytes a digit (a backtracking repeat), so a
# run of (hex) digits longer than any number Python reads is refused at its line first, wherever it
# stands. Each run is tried once, from its start: never again from each of its digits.
MAX_DIGIT_RUN = 4300  # Python's default limit on the digits of an integer it reads
_LONG_DIGIT_RUN = compiled(rf"(?<![0-9A-Fa-f_])[0-9A-Fa-f](?:_?+[0-9A-Fa-f]){{{MAX_DIGIT_RUN},}}+")
_LONG_RUNS = (
    (_LONG_DOTTED_RUN, f"more than {MAX_KEY_PARTS} words joined by dots: a key of so many parts (a scene's deepest, "
                       "materials.NAME.kd, has 3)"),
    (_LONG_DIGIT_RUN, f"more than {MAX_DIGIT_RUN} digits or letters a to f in a row (in a number, a string or a "
                      "comment): no scene holds so many"),
)
# The first part of a table header, or of a key before any header (the top level's), that is none of
# TOP_LEVEL_KEYS as written bare; found before tomllib, which holds hundreds of bytes for each table.
_KNOWN_BARE = "|".join(sorted(TOP_LEVEL_KEYS))
_UNKNOWN_NAME = rf"(?!(?:{_KNOWN_BARE})[ \t]*+[.\]=])(?P<first>{_KEY_PART})(?:{_NEXT_PART})*+[ \t]*+"
_UNKNOWN_TABLE = compiled(rf"(?m:^)[ \t]*+\[\[?+[ \t]*+{_UNKNOWN_NAME}\]\]?+[ \t]*+(?=#|\r?(?m:$))")
_UNKNOWN_TOP_KEY = compiled(rf"(?m:^)[ \t]*+{_UNKNOWN_NAME}=")
_FIRST_HEADER = re.compile(r"(?m:^)[ \t]*+\[")
_MULTI_LINE_QUOTES = ('"""', "'''")  # a header-like line may be inside a multi-line string


@dataclass(frozen=True)
class SceneEntry:
    """One [[objects]] or [[cameras]] table, checked; the model is not loaded yet."""

    name: str
    model: str  # as written in the file, for messages
    model_path: Path
    position: Vec3
    rotation: Vec3  # degrees about the world x, then y, then z axis
    material: Material | None  # None: the loaded model's own, see material_for_loaded
    line: int | None
    what: str  # the entry, as messages name it: "objects[2]"
    scale: Vec3  # the model's size as read, along x, y and z (Mesh.scaled)
    scale_line: int | None
    texture: str | None = None  # its own picture, as written in the file (relative to it), for messages
    texture_line: int | None = None
    position_line: int | None = None
    camera: bool = False  # a camera's body and eye stand out to CAMERAS_REACH, where it frames models from
    plain: bool = False  # `texture = false`: it wears no picture, its model's own neither


@dataclass(frozen=True)
class SceneDescription:
    path: Path
    objects: tuple[SceneEntry, ...]
    cameras: tuple[SceneEntry, ...]
    texture_path: Path | None
    texture_line: int | None = None  # where `texture` is set, for the message of a texture that fails
    cameras_given: bool = True  # False: the file places none, and `cameras` are the built-in scene's
    # The file that sets `texture` where this one sets none: the built-in scene's (SPEC 3: selfi.ppm at start).
    texture_named_in: Path | None = None
    # SPEC 4's lights and Ia, with what the file's `ambient` and [lights.NAME] tables set.
    lights: tuple[Light, ...] = field(default_factory=lambda: tuple(default_lights()))
    ambient: Vec3 = SPEC_AMBIENT
    notes: tuple[str, ...] = ()  # values taken that look like slips, each 'FILE:LINE: what', told at load
    texture_plain: bool = False  # `texture = false`: objects without a picture of their own wear none


# --------------------------------------------------------------------------------------------------
# Public API
# --------------------------------------------------------------------------------------------------
def builtin_scene_path() -> Path:
    return ASSET_DIR / BUILTIN_SCENE_FILE


def load_scene(path: str | Path, stage: Stage | None = None, again: bool = False) -> Scene:
    """The scene a TOML file describes, every model loaded; LoadError naming the file otherwise. `stage`
    hears the loads' stages; `again`: read again for --watch (read_scene_description)."""
    description = read_scene_description(path, again)
    loader = _ModelLoader(description.path, stage)
    return Scene(objects=[loader.place(entry) for entry in description.objects],
                 cameras=[loader.place(entry) for entry in description.cameras],
                 lights=list(description.lights), ambient=np.array(description.ambient),
                 texture_path=_optional_str(description.texture_path), texture_named_at=_texture_named_at(description),
                 texture_plain=description.texture_plain, frame_at_start=not description.cameras_given,
                 notes=description.notes)


def load_builtin_scene() -> Scene:
    """SPEC 3's scene: the camera, x_wing, r_falke and Rammer_255 with their materials."""
    return load_scene(builtin_scene_path())


def empty_scene() -> Scene:
    """The built-in camera alone (``--empty``): somewhere to look from before loading anything."""
    description = read_scene_description(builtin_scene_path())
    loader = _ModelLoader(description.path)
    return Scene(objects=[], cameras=[loader.place(entry) for entry in description.cameras],
                 texture_path=_optional_str(description.texture_path), texture_named_at=_texture_named_at(description))


def _texture_named_at(description: SceneDescription) -> str | None:
    """'FILE:LINE: texture', where the scene file names its texture: the words before that texture's
    message, which is given when the viewer starts (SPEC 7: the checker, not a refusal)."""
    if description.texture_path is None:
        return None
    return str(LoadError(description.texture_named_in or description.path, "texture", description.texture_line))


def material_for_loaded(mesh: Mesh, own_picture: bool = False) -> Material:
    """A run-time model's material: its MTL's numbers where given, the neutral default elsewhere; with
    `own_picture` (a picture given for it, add_mesh's texture=), Kd 1 where its file gives none, as a
    file's own picture is drawn."""
    values = with_picture_as_colour(mesh.file_material or {}, own_picture)
    return _material_from(values, DEFAULT_MATERIAL, _clamped_colour(mesh.base_colour, WHITE))


def give_part_materials(obj: SceneObject, from_scene: bool) -> None:
    """One material per material of the file, as Mesh.materials lists them: its MTL numbers, each
    missing one taken from the object's own; all the object's own when the scene file gave it one."""
    own = obj.material
    obj.file_materials = tuple(_material_from(material.values, own, own.rgb) for material in obj.mesh.materials)
    obj.part_materials = tuple(own for _ in obj.mesh.materials) if from_scene else obj.file_materials


def _material_from(values: dict[str, object], fallback: Material, rgb: Vec3) -> Material:
    return Material(ka=_clamped_colour(values.get("ka"), fallback.ka),
                    kd=_clamped_colour(values.get("kd"), fallback.kd),
                    ks=_clamped_colour(values.get("ks"), fallback.ks),
                    ns=_file_shininess(values.get("ns"), fallback.ns), rgb=rgb)


def light_table_name(light: Light) -> str:
    """A light's table in a scene file, [lights.NAME]: its name as the status line and help say it."""
    return light.name.replace(" ", "_")


def read_scene_description(path: str | Path, again: bool = False) -> SceneDescription:
    """Parse and check a scene file without loading its models. `again` (--watch's read again): an empty
    file is one an editor that writes in place has emptied and not yet written, refused, not a scene of nothing."""
    reader = _SceneReader(Path(path), again)
    return reader.describe()


# --------------------------------------------------------------------------------------------------
# Reading and checking the TOML
# --------------------------------------------------------------------------------------------------
def _nowhere(key: str) -> int | None:
    """No key's line is known (entries written inline, or headers that do not match them)."""
    return None


def _or_header(key_line: Callable[[str], int | None], header: int | None) -> Callable[[str], int | None]:
    """The line that sets a key, else its table's header line."""
    return lambda key: key_line(key) or header


class _SceneReader:
    """Checks one scene file; every failure is a LoadError naming the file and, when known, the line."""

    def __init__(self, path: Path, again: bool = False) -> None:
        self.path = path
        self.again = again
        if path.suffix.lower() in MODEL_READERS:  # its TOML syntax error, at its line 3, would hide the slip
            self.fail("a model file, not a TOML scene file: add it as a model (Viewer.load, or MODEL on the "
                      "command line)")
        self.text = self._read_text()
        self._refuse_long_runs()
        self._refuse_unknown_top_level()
        if len(self.text) > SCENE_FILE_LIMIT:  # in characters, which tomllib reads one by one
            self.fail(f"file too large for a scene (more than {SCENE_FILE_LIMIT >> 20} MiB; a thousand objects take "
                      "about 100 KB)")
        self.document = self._parse()
        self.lines = _LineIndex.of(self.text)
        self.notes: list[str] = []

    def fail(self, message: str, line: int | None = None) -> NoReturn:
        raise LoadError(self.path, message, line)

    def _read_text(self) -> str:
        before = file_stamp(self.path) if self.again else None
        data = read_file(self.path, limit=SCENE_READ_LIMIT)
        if self.again and not data:
            self.fail("empty as it was read again (caught part way through a save?): the scene stays as it was")
        if self.again and (before is None or file_stamp(self.path) != before or len(data) != before.size):
            # an editor writing in place (or gone as the read began), caught mid-save: read whole at the next look
            self.fail("changed as it was read again (caught part way through a save?): the scene stays as it was")
        try:
            return data.decode("utf-8-sig")  # a byte order mark (Notepad writes one) is no TOML
        except UnicodeDecodeError as error:
            self.fail("not a TOML scene file (not UTF-8 text)", line_at(data, error.start))

    def _refuse_long_runs(self) -> None:
        """Any run longer than tomllib reads in proportion to it, wherever tomllib would read it (a key, a
        header, an inline table, a number); in a string or a comment too, where no scene has one."""
        for run, said in _LONG_RUNS:
            found = run.search(self.text)
            if found is not None:
                self.fail(said, _line_of(self.text, found.start()))

    def _refuse_unknown_top_level(self) -> None:
        """A table header, or a key before any header, whose first part is no top-level key, refused at
        its line before tomllib reads it; not looked for where a multi-line string may hold such a line."""
        if any(quotes in self.text for quotes in _MULTI_LINE_QUOTES):
            return
        header = _FIRST_HEADER.search(self.text)
        top_end = len(self.text) if header is None else header.start()
        names = chain(_UNKNOWN_TOP_KEY.finditer(self.text, 0, top_end), _UNKNOWN_TABLE.finditer(self.text, top_end))
        for found in names:
            name = _key_parts(found["first"])[0]  # quoted ("objects") or escaped names are known ones too
            if name not in TOP_LEVEL_KEYS:
                self.fail(_unknown_key("the scene", name, TOP_LEVEL_KEYS), _line_of(self.text, found.start()))

    def _parse(self) -> dict:
        try:
            return tomllib.loads(self.text)
        except tomllib.TOMLDecodeError as err:
            message = str(err)
            found = _TOML_POSITION.search(message)
            line = int(found.group(1)) if found else self._last_line() if message.endswith(_AT_THE_END) else None
            column = int(found.group(2)) if found else None
            self.fail(f"TOML syntax: {self._syntax_words(_TOML_POSITION.sub('', message), line, column)}", line)
        except RecursionError:  # tomllib recurses once per nesting level of arrays and inline tables
            self.fail("TOML nested too deeply to be a scene file")
        except ValueError as err:  # Python refuses to read decimal integers longer than its digit limit
            line = _overlong_integer_line(self.text)
            self.fail(f"an integer of thousands of digits {TOO_LARGE}" if line else f"TOML: {err}", line)

    def _syntax_words(self, said: str, line: int | None, column: int | None) -> str:
        """tomllib's words for a syntax error, with the key or [table] of its line; a few said as a person
        would ("Cannot declare ('materials', 'red') twice": [materials.red] is declared twice)."""
        if line is None or column is None:  # at the end: the last line, maybe not where the slip is
            return said
        text = self._line_text(line)
        written = _LINE_START.match(text)
        if written is None:
            return _SYNTAX_REWORDED.get(said, said)
        if written["table"] is not None and _DECLARED_TWICE.fullmatch(said):
            return _table_declared_twice(self.text, written["table"], line)
        if written["array"] is not None and said == "Cannot overwrite a value":
            return _array_over_a_table(self.text, written["array"], line)
        if written["key"] is None:
            return _SYNTAX_REWORDED.get(said, said)
        key = shortened(written["key"])
        if said in _ESCAPE_SLIPS:  # a Windows path in "double quotes": C:\Users reads \U as a character's code
            return f"{key}: {escape_words(_escape_before(text, column))}"
        if said == "Cannot overwrite a value" and len(_key_parts(written["key"])) == 1:  # else a part may be a value
            return f"{key} is set twice in one table"
        twice = _INLINE_KEY_TWICE.fullmatch(said)
        if twice and _written_twice(text[written.end():column], twice["a"] or twice["b"]):
            return f"{key}: {shortened(twice['a'] or twice['b'])} is set twice in one inline table"
        unquoted = said == "Invalid value" and _LOOKS_LIKE_TEXT.match(text, column - 1)
        word = _BARE_WORD.match(text, column - 1)[0].lower()
        hint = _BARE_WORD_HINTS.get(word, _QUOTES_HINT) if unquoted else ""
        return f"{key}: {_SYNTAX_REWORDED.get(said, said)}{hint}"

    def _last_line(self) -> int:
        """The last line that holds anything: where a file cut short ends (tomllib says only "at end of
        document")."""
        return _line_of(self.text, max(len(self.text.rstrip()) - 1, 0))

    def describe(self) -> SceneDescription:
        self.check_keys(self.document, TOP_LEVEL_KEYS, "the scene", None)
        materials = self.named_materials()
        objects = self.entries("objects", materials)
        cameras = self.entries("cameras", materials)
        given, texture, texture_line, named_in = bool(cameras), self.texture(), self.lines.first(("texture",)), None
        plain = texture is False
        if not given or texture is None:
            builtin = read_scene_description(builtin_scene_path())  # what the file leaves out, as --empty gives it
            cameras = cameras if given else builtin.cameras
            if texture is None:  # its models show the texture they show alone on the command line
                texture, texture_line, named_in = builtin.texture_path, builtin.texture_line, builtin.path
        ambient, lights = self.ambient(), self.lights()  # their notes in the file's order
        return SceneDescription(self.path, objects, cameras, None if plain else texture, texture_line, given, named_in,
                                lights, ambient, tuple(self.notes), plain)

    # --- top level -----------------------------------------------------------------------------
    def texture(self) -> Path | bool | None:
        """The picture the scene's `texture` names; False: `texture = false`, none; None: not set."""
        if "texture" not in self.document:
            return None
        line = self.lines.first(("texture",))
        name = self.picture_name(self.document["texture"], "texture", line)
        return False if name is False else (self.path.parent / name).absolute()

    def ambient(self) -> Vec3:
        if "ambient" not in self.document:
            return SPEC_AMBIENT
        return self.intensity(self.document["ambient"], "ambient", self.lines.first(("ambient",)))

    # --- lights --------------------------------------------------------------------------------
    def lights(self) -> tuple[Light, ...]:
        """SPEC 4's four lights, each with what its [lights.NAME] table sets."""
        lights = default_lights()
        tables = self.document.get("lights", {})
        names = {light_table_name(light): light for light in lights}
        if not isinstance(tables, dict):
            self.fail(f"lights must be tables, one per light: {_light_headers(names)}", self.lines.first(("lights",)))
        for name, table in tables.items():
            line = self.lines.first(("lights", name)) or self.lines.first(("lights",))  # inline: where lights opens
            if name not in names:
                self.fail(f"lights: unknown light {_quoted(name)} (lights: {', '.join(names)})", line)
            self.set_light(names[name], table, f"lights.{name}", line, self._light_key_line(name))
        return tuple(lights)

    def _light_key_line(self, name: str) -> Callable[[str], int | None]:
        return lambda key: self.lines.first(("lights", name, key))

    def set_light(self, light: Light, table: object, what: str, line: int | None,
                  key_line: Callable[[str], int | None]) -> None:
        """The light as its table sets it, each value held to the rule the scene set by hand is (Scene.check_values)."""
        own = KIND_KEY[light.kind]
        allowed = LIGHT_KEYS | {own}
        if not isinstance(table, dict):
            self.fail(f"{what} must be a table of {', '.join(sorted(allowed))}", line)
        at = _or_header(key_line, line)
        for key in [key for key in table if key not in allowed]:  # another light's key: say whose
            owners = [name for name, kind_key in _light_keys().items() if kind_key == key]
            if owners:
                whose = " and ".join(f"the {owner}'s" for owner in owners)
                self.fail(f"{_unknown_key(what, key, allowed)}: {key} is {whose}", at(key))
        self.check_keys(table, allowed, what, line, key_line=at)
        if "on" in table:
            light.on = self.flag(table["on"], f"{what}: on", at("on"))
        if "intensity" in table:
            light.intensity = np.array(self.intensity(table["intensity"], f"{what}: intensity", at("intensity")))
        if own == "direction" and own in table:
            light.direction = np.array(self.triple_of(DIRECTION, table[own], f"{what}: {own}", at(own)))
        if own == "position" and own in table:
            light.position = np.array(self.triple_of(place_kind(light), table[own], f"{what}: {own}", at(own)))
            light.placed_by_file = True
        if own == "aperture" and own in table:
            light.aperture_deg = self.aperture(table[own], f"{what}: {own}", at(own))

    def aperture(self, value: object, what: str, line: int | None) -> float:
        """Degrees from the axis to the cone's edge, within the range + and - keep it in."""
        degrees = self.number(value, what, line)
        low, high = SPOT_APERTURE_RANGE_DEG
        if not low <= degrees <= high:
            self.fail(f"{what} must be from {low:g} to {high:g} degrees (the axis to the cone's edge, as + and - "
                      f"keep it), not {degrees:g}", line)
        return degrees

    def named_materials(self) -> dict[str, Material]:
        tables = self.document.get("materials", {})
        if not isinstance(tables, dict):
            self.fail("materials must be tables: [materials.NAME]", self.lines.first(("materials",)))
        return {name: self.material(table, f"material {_quoted(name)}", self._material_line(name),
                                    self._material_key_line(name))
                for name, table in tables.items()}

    def _material_line(self, name: str) -> int | None:
        return self.lines.first(("materials", name)) or self.lines.first(("materials",))  # inline: where it opens

    def _material_key_line(self, name: str) -> Callable[[str], int | None]:
        return lambda key: self.lines.first(("materials", name, key))

    def entries(self, kind: str, materials: dict[str, Material]) -> tuple[SceneEntry, ...]:
        tables = self.document.get(kind, [])
        if not isinstance(tables, list):
            self.fail(f"{kind} must be an array of tables: [[{kind}]]", self.lines.first((kind,)))
        headers = self.lines.array_headers(kind, len(tables))
        return tuple(self.entry(table, f"{kind}[{index + 1}]", line, materials,
                                self.lines.of_entry(kind, index, len(tables)), camera=kind == "cameras")
                     for index, (table, line) in enumerate(zip(tables, headers)))

    # --- one object or camera ------------------------------------------------------------------
    def entry(self, table: object, what: str, line: int | None, materials: dict[str, Material],
              key_line: Callable[[str], int | None] = _nowhere, camera: bool = False) -> SceneEntry:
        if not isinstance(table, dict):
            self.fail(f"{what} must be a table", line)

        at = _or_header(key_line, line)
        self.check_keys(table, ENTRY_KEYS, what, line, required=() if camera else REQUIRED_OBJECT_KEYS, key_line=at)
        if camera and "position" not in table:  # at the origin it would stand inside the models it is to show
            self.fail(f"{what}: missing key 'position' (where the camera looks from; a file without [[cameras]] "
                      "has the built-in camera framing its models)", line)
        if "model" in table:
            model = self.file_name(table["model"], f"{what}: model", at("model"))
            path = self.path.parent / model
        else:  # a camera's: the built-in one
            model, path = CAMERA_MODEL, BUILT_IN_CAMERA_MODEL
        # A model "." has no stem: its own words name it, and loading it says what is wrong with it.
        name = self.text_value(table.get("name", kept_name(Path(model).stem or model)), f"{what}: name", at("name"))
        refusal = name_refusal(name) if "name" in table else None  # a model's stem is kept as a loaded file's is
        if refusal is not None:
            self.fail(f"{what}: {refusal}", at("name"))
        position = self.triple(table.get("position", list(ORIGIN)), f"{what}: position", at("position"))
        rotation = self.triple(table.get("rotation", [0, 0, 0]), f"{what}: rotation", at("rotation"))
        scale = self.scale(table.get("scale", 1), f"{what}: scale", at("scale"))
        material = self.entry_material(table.get("material"), what, at("material"), materials)
        texture = self.picture_name(table["texture"], f"{what}: texture", at("texture")) if "texture" in table else None
        return SceneEntry(name, model, path, position, rotation, material, at("model"), what, scale, at("scale"),
                          texture or None, at("texture"), at("position"), camera, plain=texture is False)

    def entry_material(self, value: object, what: str, line: int | None,
                       materials: dict[str, Material]) -> Material | None:
        if value is None:
            return None
        if isinstance(value, str):
            if value not in materials:
                self.fail(f"{what}: unknown material {_quoted(value)} (known: {_some_of(materials)})", line)
            return materials[value]
        return self.material(value, f"{what}: material", line)

    # --- materials -----------------------------------------------------------------------------
    def material(self, table: object, what: str, line: int | None,
                 key_line: Callable[[str], int | None] = _nowhere) -> Material:
        if not isinstance(table, dict):
            self.fail(f"{what} must be a material name or a table of ka, kd, ks, ns", line)

        at = _or_header(key_line, line)
        self.check_keys(table, MATERIAL_KEYS, what, line, required=REQUIRED_MATERIAL_KEYS, key_line=at)
        colours = {key: self.material_colour(table[key], f"{what}: {key}", at(key)) for key in ("ka", "kd", "ks")}
        ns = self.number(table["ns"], f"{what}: ns", at("ns"))
        if ns <= 0:
            self.fail(f"{what}: ns must be greater than 0, not {ns:g}", at("ns"))
        rgb = self.material_colour(table["rgb"], f"{what}: rgb", at("rgb")) if "rgb" in table else WHITE
        return Material(ka=colours["ka"], kd=colours["kd"], ks=colours["ks"], ns=ns, rgb=rgb)

    # --- values --------------------------------------------------------------------------------
    def check_keys(self, table: dict, allowed: frozenset[str], what: str, line: int | None,
                   required: tuple[str, ...] = (), key_line: Callable[[str], int | None] = _nowhere) -> None:
        unknown = [key for key in table if key not in allowed]  # in the file's order: tomllib keeps it
        if unknown:
            # TOML reads a key below a header as that table's: the scene's own, written last, lands there
            misplaced = (f": {unknown[0]} is the scene's, written before the first [table]"
                         if unknown[0] in TOP_LEVEL_KEYS and table is not self.document else "")
            self.fail(_unknown_key(what, unknown[0], allowed) + misplaced, key_line(unknown[0]) or line)
        missing = [key for key in required if key not in table]
        if missing:
            self.fail(f"{what}: missing key {missing[0]!r}", line)

    def text_value(self, value: object, what: str, line: int | None) -> str:
        if not isinstance(value, str) or not value.strip():
            self.fail(f"{what} must be a non-empty string in quotes", line)
        return value

    def file_name(self, value: object, what: str, line: int | None) -> str:
        """A model's or picture's name: text that names a file ("" is in quotes, yet names none)."""
        if isinstance(value, str) and not value.strip():
            self.fail(f"{what} must name a file (it is {'blank' if value else 'empty'})", line)
        return self.text_value(value, what, line)

    def picture_name(self, value: object, what: str, line: int | None) -> str | bool:
        """A `texture`'s value: a file's name, or False for none (`true` would name no picture)."""
        if value is False:
            return False
        if value is True:
            self.fail(f"{what} = true names no picture: name a file in quotes, or write false for none", line)
        if not isinstance(value, str):
            self.fail(f"{what} must be a file name in quotes, or false for no picture, not {_toml_type(value)}", line)
        return self.file_name(value, what, line)

    def _line_text(self, line: int | None) -> str:
        return "" if line is None else next(islice(_lines(self.text), line - 1, None), "")

    def number(self, value: object, what: str, line: int | None) -> float:
        # bool is an int in Python, but `true` is never a sensible coordinate
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.fail(f"{what} must be a number, not {_toml_type(value)}", line)
        if isinstance(value, float) and not math.isfinite(value):
            self.fail(f"{what} must be a finite number, not {value}", line)
        if abs(value) > FLOAT32_MAX:  # exact for integers of any size, which float() could overflow on
            self.fail(f"{what} {_named_number(value)} {TOO_LARGE}", line)
        return float(value)

    def scale(self, value: object, what: str, line: int | None) -> Vec3:
        """One number, the same along x, y and z, or three; each greater than 0."""
        if isinstance(value, list) and len(value) == 3:
            self.all_numbers(value, f"{what} must be one number or three, like 2 or [1, 2, 1]", line)
            x, y, z = (self.number(item, what, line) for item in value)
        elif isinstance(value, (int, float)) and not isinstance(value, bool):
            x = y = z = self.number(value, what, line)
        else:
            self.fail(f"{what} must be one number or three, like 2 or [1, 2, 1], not {_shape_words(value)}", line)
        if min(x, y, z) <= 0.0:
            self.fail(f"{what} must be greater than 0 (a size, not a mirror), not {min(x, y, z):g}", line)
        return (x, y, z)

    def triple(self, value: object, what: str, line: int | None) -> Vec3:
        if not isinstance(value, list) or len(value) != 3:
            self.fail(f"{what} must be three numbers, like [0, 0, 0], not {_shape_words(value)}", line)
        self.all_numbers(value, f"{what} must be three numbers, like [0, 0, 0]", line)
        x, y, z = (self.number(item, what, line) for item in value)
        return (x, y, z)

    def all_numbers(self, items: list[object], rule: str, line: int | None) -> None:
        """Which of three is not a number: `position must be a number` would misname a list of three."""
        for ordinal, item in zip(("first", "second", "third"), items):
            if isinstance(item, bool) or not isinstance(item, (int, float)):
                self.fail(f"{rule}: its {ordinal} is {_toml_type(item)}", line)

    def material_colour(self, value: object, what: str, line: int | None) -> Vec3:
        """Three numbers in the range Scene.check_by_hand holds a material's colours to."""
        colour = self.triple(value, what, line)
        hint = " (0..255 colours: divide by 255)" if _looks_like_bytes(colour) else ""
        return self.held_to(MATERIAL_COLOUR, colour, value, what, line, hint)

    def triple_of(self, kind: TripleKind, value: object, what: str, line: int | None) -> Vec3:
        """Three numbers of a kind, as Scene.check_by_hand holds the scene set by hand to it."""
        return self.held_to(kind, self.triple(value, what, line), value, what, line)

    def held_to(self, kind: TripleKind, triple: Vec3, value: object, what: str, line: int | None,
                hint: str = "") -> Vec3:
        """`triple` (read from `value`) within its kind's range, and long enough where its kind points some way."""
        numbers = np.array(triple)
        if not kind.holds(numbers):
            self.fail(f"{what} must be three numbers {kind.within}, not {_toml_list(value)}{hint}", line)
        if not kind.points_some_way(numbers[None]):
            self.fail(f"{what} must point some way (at least {kind.shortest:g} long), not {_toml_list(value)}", line)
        return triple

    def intensity(self, value: object, what: str, line: int | None) -> Vec3:
        """A light's or the ambient's, in 0..255 units; one written in 0..1 (not all 0, a deliberate off) is
        taken, as it is legal, with a note: its scene is nearly dark."""
        intensity = self.triple_of(LIGHT_COLOUR, value, what, line)
        if 0 < max(intensity) <= 1:
            self.notes.append(str(LoadError(self.path, f"{what} {_toml_list(value)} is in 0..255 units (so nearly "
                                            "dark): [255, 255, 255] is full white", line)))
        return intensity

    def flag(self, value: object, what: str, line: int | None) -> bool:
        if not isinstance(value, bool):
            self.fail(f"{what} must be true or false, not {_toml_type(value)}", line)
        return value


def _light_keys() -> dict[str, str]:
    """Each light's table name and the key its kind takes (KIND_KEY)."""
    return {light_table_name(light): KIND_KEY[light.kind] for light in default_lights()}


def _light_headers(names: dict[str, Light]) -> str:
    return ", ".join(f"[lights.{name}]" for name in names)


def _unknown_key(what: str, key: str, allowed: frozenset[str]) -> str:
    return f"{what}: unknown key {_quoted(key)} (allowed: {', '.join(sorted(allowed))})"


def _quoted(word: str) -> str:
    """A word of the file in quotes, as a message shows it: a long one cut."""
    return repr(shortened(word))


def _some_of(names: Iterable[str]) -> str:
    """The first few names in order, and how many more: a scene may name thousands."""
    ordered = sorted(names)
    more = f" and {len(ordered) - NAMES_LISTED:,} more" if len(ordered) > NAMES_LISTED else ""
    return ", ".join(shortened(name) for name in ordered[:NAMES_LISTED]) + more if ordered else "none"


def _looks_like_bytes(colour: Vec3) -> bool:
    """Whole numbers from 0 to 255, one above 1: a colour written as an image editor shows it."""
    return all(c.is_integer() and 0 <= c <= 255 for c in colour) and max(colour) > 1


def _toml_list(numbers: list[object]) -> str:
    """Numbers as TOML read them: [255, 0, 0], whole ones whole, not a tuple of floats (1e2 is 100.0)."""
    return f"[{', '.join(map(str, numbers))}]"


def _shape_words(value: object) -> str:
    """What a value that should be a list of three is: '2 numbers', 'a string'."""
    return counted(len(value), "number") if isinstance(value, list) else _toml_type(value)


def _toml_type(value: object) -> str:
    names = {bool: "true/false", str: "a string", list: "an array", dict: "a table", int: "one number",
             float: "one number"}
    return names.get(type(value), type(value).__name__)


def _named_number(value: float) -> str:
    """A number as a message shows it: never all the hundreds of digits of a huge integer."""
    return f"{value:g}" if isinstance(value, float) else f"(a {_decimal_digits(value)}-digit integer)"


def _decimal_digits(value: int) -> int:
    """Digits of a non-zero integer of any size; str() refuses integers past Python's digit limit."""
    size = abs(value)
    digits = int(math.log10(size)) + 1
    if size < 10 ** (digits - 1):  # log10 rounds near powers of ten
        return digits - 1
    return digits + 1 if size >= 10**digits else digits


def _overlong_integer_line(text: str) -> int | None:
    """The line of the first decimal integer longer than Python will read, or None when there is none."""
    limit = sys.get_int_max_str_digits()
    # whole runs of digits only (not inside words, hex numbers or fractions): each run is tried once
    # possessive: sre keeps no state per digit (a backtracking repeat kept over 100 bytes per digit)
    found = _integer_run_longer_than(limit).search(text) if limit else None
    return None if found is None else _line_of(text, found.start())


@functools.lru_cache(maxsize=2)
def _integer_run_longer_than(limit: int) -> re.Pattern[str]:
    return compiled(rf"(?<![0-9A-Za-z_.])[0-9](?:_?+[0-9]){{{limit},}}+(?![0-9A-Za-z_.])")


def _array_over_a_table(text: str, name: str, line: int) -> str:
    """tomllib's 'Cannot overwrite a value' at an [[array]] header: its name is a table or a value already."""
    first = _first_header_line(text, _key_parts(name), line)
    shown = shortened(name)
    if first is None:  # a key's value, or a table made by a dotted key or a longer header
        return f"[[{shown}]]: {shown} is already a table or a value"
    return f"[[{shown}]] after [{shown}] (line {first}): write [[{shown}]] for every entry"


def _table_declared_twice(text: str, name: str, line: int) -> str:
    """tomllib's 'Cannot declare (...) twice' at a [table] header: a header named it before, or a key set it
    (material.ka = ..., or material = { ... }), which tomllib says in the same words."""
    key, shown = _key_parts(name), shortened(name)
    first = _first_header_line(text, key, line)
    if first is not None:
        brackets = _ENTRY_BRACKETS.get(name)
        return f"[{shown}] is declared twice (first at line {first})" + (f": {brackets}" if brackets else "")
    set_at = _first_key_line(text, key, line)
    return f"[{shown}]: {shortened(key[-1])} is already set by a key" + (f" (line {set_at})" if set_at else "")


def _written_twice(inline: str, key: str) -> bool:
    """Whether the key is written bare twice in the inline tables of `inline` (as tomllib names only a
    dotted key's last part, a.ka's ka, that one is said in its words)."""
    return len(re.findall(rf"[{{,][ \t]*+{key}[ \t]*+=", inline)) >= 2


def _first_header_line(text: str, key: KeyPath, before: int) -> int | None:
    """The line of the first [table] or [[array]] header naming `key`, if one comes before line `before`."""
    for number, found in _line_starts(text, before):
        header = found["table"] or found["array"]
        if header is not None and _key_parts(header) == key:
            return number
    return None


def _first_key_line(text: str, key: KeyPath, before: int) -> int | None:
    """The line of the first key = value before line `before` that sets `key` or a key inside it, in
    the [[array]] entry the key is in, where it is in one (each entry's keys are its own)."""
    table: KeyPath = ()
    found = None
    for number, written in _line_starts(text, before):
        if written["key"] is None:
            table = _key_parts(written["array"] or written["table"])
            if written["array"] is not None and key[:len(table)] == table:
                found = None
        elif found is None and (table + _key_parts(written["key"]))[:len(key)] == key:
            found = number
    return found


def _escape_before(line: str, column: int) -> str | None:
    """The escape (a back slash and the letter after it) last begun before `column` of `line`, where tomllib
    stopped reading it."""
    at = line.rfind("\\", 0, column - 1)
    return line[at:at + 2] if at >= 0 else None


def _line_of(text: str, offset: int) -> int:
    """The line of the character at `offset`, as tomllib counts lines ("\n" ends one)."""
    return text.count("\n", 0, offset) + 1


# --------------------------------------------------------------------------------------------------
# Lines, for messages (tomllib reports lines only for syntax errors)
# --------------------------------------------------------------------------------------------------
KeyPath = tuple[str, ...]  # a dotted TOML key, part by part


def _lines(text: str) -> Iterator[str]:
    """The text's lines, one at a time (a list of them all would hold the text again, in pieces);
    tomllib counts "\n" alone as a line end."""
    start = 0
    while (end := text.find("\n", start)) >= 0:
        yield text[start:end]
        start = end + 1
    yield text[start:]


def _line_starts(text: str, before: int | None = None) -> Iterator[tuple[int, re.Match[str]]]:
    """Each line, before line `before` where given, that starts a [table], an [[array]] entry or a key
    (_LINE_START): its number, and that start."""
    for number, line in enumerate(islice(_lines(text), None if before is None else before - 1), 1):
        found = _LINE_START.match(line)
        if found is not None:
            yield number, found


@dataclass(frozen=True)
class _LineIndex:
    """Where each table, array-of-tables entry and key of a TOML text starts, found in one pass."""

    first_lines: dict[KeyPath, int]  # a table or key (and each of its parents): the line that first names it
    array_lines: dict[KeyPath, list[int]]  # [[NAME]] headers in order: one per entry of the array
    entry_lines: dict[tuple[KeyPath, int], dict[str, int]]  # an array entry's own keys: where each is set
    plain: bool = True  # no multi-line string, whose lines may look like keys, is in the text

    @classmethod
    def of(cls, text: str) -> _LineIndex:
        first_lines: dict[KeyPath, int] = {}
        array_lines: dict[KeyPath, list[int]] = {}
        entry_lines: dict[tuple[KeyPath, int], dict[str, int]] = {}
        section: KeyPath = ()
        entry: dict[str, int] | None = None  # the keys of the [[NAME]] entry being read
        for number, found in _line_starts(text):
            if found["key"] is not None:
                key = _key_parts(found["key"])
                _remember(first_lines, section, key, number)
                if entry is not None:
                    entry.setdefault(key[0], number)
                continue
            section, entry = _key_parts(found["array"] or found["table"]), None
            _remember(first_lines, (), section, number)
            if found["array"] is not None:
                array_lines.setdefault(section, []).append(number)
                entry = entry_lines.setdefault((section, len(array_lines[section]) - 1), {})
        return cls(first_lines, array_lines, entry_lines, not any(quotes in text for quotes in _MULTI_LINE_QUOTES))

    def first(self, key: KeyPath) -> int | None:
        return self.first_lines.get(key)

    def of_entry(self, name: str, index: int, count: int) -> Callable[[str], int | None]:
        """Where each key of entry `index` of the array `name` (of `count` entries) is set, when the
        headers match the entries one to one (see array_headers)."""
        lines = self.entry_lines.get(((name,), index), {})
        return lines.get if len(self.array_lines.get((name,), [])) == count else _nowhere

    def array_headers(self, name: str, count: int) -> list[int | None]:
        """The header line of each of the `count` entries; the line that opens them where they are written
        inline (name = [{ ... }]); None for all when the headers do not match them one to one (a header-like
        line inside a multi-line string)."""
        lines = self.array_lines.get((name,), [])
        if not lines and self.plain:
            return [self.first_lines.get((name,))] * count
        return list(lines) if len(lines) == count else [None] * count


def _remember(first_lines: dict[KeyPath, int], section: KeyPath, key: KeyPath, number: int) -> None:
    """The first line of `key` and of each dotted part of it, within `section` (remembered at its header)."""
    for end in range(1, len(key) + 1):
        first_lines.setdefault(section + key[:end], number)


@functools.lru_cache(maxsize=1024)  # the same few keys come back on line after line
def _key_parts(dotted: str) -> KeyPath:
    return tuple(_unquoted(part) for part in _KEY_PARTS.findall(dotted))


def _unquoted(part: str) -> str:
    if part[0] == "'":
        return part[1:-1]
    if part[0] != '"':
        return part
    if "\\" not in part:
        return part[1:-1]
    try:
        return tomllib.loads(f"k = {part}")["k"]
    except tomllib.TOMLDecodeError:  # a key-like line inside a multi-line literal string may hold any escape
        return part[1:-1]


# --------------------------------------------------------------------------------------------------
# Loading the models
# --------------------------------------------------------------------------------------------------
class _ModelLoader:
    """Loads each model file once per scene, wrapping its errors so they name the scene file too."""

    def __init__(self, scene_path: Path, stage: Stage | None = None) -> None:
        self.scene_path = scene_path
        self.stage = stage
        self.meshes: dict[Path, Mesh] = {}
        self.sized: dict[tuple[Path, Vec3], Mesh] = {}  # the entries of one model at one scale share its mesh
        self.keys: dict[str, Path] = {}  # each spelling resolved once: thousands of entries may name one model
        self.pictures: dict[Path, np.ndarray] = {}  # each object texture read once, however spelled

    def place(self, entry: SceneEntry) -> SceneObject:
        mesh = self.mesh(entry)
        material = entry.material if entry.material is not None else material_for_loaded(mesh)
        obj = SceneObject.placed(entry.name, mesh, material, entry.position, entry.rotation, source=entry.model_path)
        refusal = placement_refusal(obj.model, mesh, CAMERAS_REACH if entry.camera else MODELS_REACH)
        if refusal is not None:  # the programming interface's next call would refuse the scene, the GPU light it wrong
            raise LoadError(self.scene_path, f"{entry.what}: position {_triple_words(entry.position)}: {refusal}",
                            entry.position_line)
        obj.scale = entry.scale
        obj.picture = self.picture(entry)
        obj.picture_source = None if entry.texture is None else _picture_path(self.scene_path, entry.texture)
        obj.given_material = entry.material
        give_part_materials(obj, from_scene=entry.material is not None)
        return obj

    def picture(self, entry: SceneEntry) -> np.ndarray | None:
        """The entry's own texture, read once for every entry that names it; a LoadError at its line (the
        scene's own texture is SPEC 7's, with the checker: an object's is named as its model is)."""
        if entry.plain:
            return PLAIN_PICTURE
        if entry.texture is None:
            return None
        path = _picture_path(self.scene_path, entry.texture)
        key = same_file_key(path)  # a.png and ./a.png: one picture, as one model
        if key not in self.pictures:
            try:
                self.pictures[key] = load_image(path)
            except (ViewerError, OSError) as err:  # its message names the file, the written name within it
                said = said_as_written(err, path, entry.texture)
                raise LoadError(self.scene_path, f"{entry.what}: texture: {said}", entry.texture_line) from err
        return self.pictures[key]

    def mesh(self, entry: SceneEntry) -> Mesh:
        key = self.keys.get(entry.model)
        if key is None:
            key = self.keys[entry.model] = same_file_key(entry.model_path)  # x.obj and ./x.obj: one model
        if key not in self.meshes:
            try:
                self.meshes[key] = load_model(entry.model_path.absolute(), self.stage)
            except (ViewerError, OSError) as err:
                said = said_as_written(err, entry.model_path.absolute(), entry.model)
                raise LoadError(self.scene_path, f"model {shown(as_typed(entry.model))}: {said}", entry.line) from err
        if (key, entry.scale) not in self.sized:
            try:
                self.sized[key, entry.scale] = sized(self.meshes[key], entry.scale, entry.model_path)
            except LoadError as err:
                raise LoadError(self.scene_path, f"{entry.what}: scale {_scale_words(entry.scale)}: {err.message}",
                                entry.scale_line) from err
        return self.sized[key, entry.scale]


def _picture_path(scene_path: Path, texture: str) -> Path:
    """The file an entry's `texture` names: the one looked for, whatever the working folder."""
    return (scene_path.parent / texture).absolute()


def _scale_words(scale: Vec3) -> str:
    x, y, z = scale
    return f"{x:g}" if x == y == z else _triple_words(scale)


def _triple_words(triple: Vec3) -> str:
    return "[{:g}, {:g}, {:g}]".format(*triple)


def _optional_str(path: Path | None) -> str | None:
    return None if path is None else str(path)


def _clamped_colour(value: object, default: Vec3) -> Vec3:
    """A 3-tuple in 0..1 from a file's numbers; the default when the file gave none or nonsense."""
    try:
        numbers = tuple(float(c) for c in value)  # type: ignore[union-attr]
    except (TypeError, ValueError, OverflowError):
        return default
    if len(numbers) != 3 or not all(math.isfinite(c) for c in numbers):
        return default
    r, g, b = (min(max(c, MATERIAL_COLOUR_RANGE[0]), MATERIAL_COLOUR_RANGE[1]) for c in numbers)
    return (r, g, b)


def _file_shininess(value: object, default: float = DEFAULT_MATERIAL.ns) -> float:
    try:
        ns = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        return default
    if not math.isfinite(ns):
        return default
    return min(max(ns, MIN_FILE_NS), FLOAT32_MAX)  # a float32 past that is infinite, and pow(1, inf) NaN
