"""Wavefront OBJ reader: one file becomes one Mesh, quickly and strictly.

Why our own reader and not trimesh's: trimesh silently reads tab-separated lines as nothing, accepts
index 0, drops a truncated last face and accepts NaN. A viewer for students must instead say what is
wrong and on which line.

Two readers produce the same raw tables (raw.py): the fast one (fast.py, compiled by numba) reads
files of a few megabytes or more, and any file once it is loaded; the line-by-line one (lines.py) is
the authority on meaning. It reads a process's first small files (but for those of many lines it
reads one at a time), files that continue lines with a backslash, and every line the fast one does
not read itself, valid or not, so it alone words the errors. The MTL beside the file gives the
material (mtl.py). Normals and texture coordinates the file lacks are derived by
marraztu.model.build, as for every other format.
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from marraztu.errors import LoadError, shortened
from marraztu.loaders.obj.lines import LONGEST_BATCHED_LINE, ReadsSlowly, read_by_lines
from marraztu.loaders.obj.mtl import Libraries, UnreadMaterial, read_libraries
from marraztu.loaders.obj.raw import MaterialRuns, RawObj, name_before_comment
from marraztu.loaders.obj.text import as_bytes, checked, ended, has_continuations, read_text
from marraztu.model.build import colour_bytes, colour_fractions, derive_mesh
from marraztu.model.mesh import MAX_MATERIALS, Mesh, MeshMaterial, counted


def load_obj(path: str | Path, stage: Callable[[str], None] | None = None) -> Mesh:
    """Read an OBJ file into a Mesh; every problem becomes a LoadError naming the file.

    `stage` hears "reading" and then "parsing" (the window's loader thread shows them)."""
    # The bytes are passed on, never kept here: they are freed once the tables are read, before
    # the normals and coordinates are derived.
    source = str(path)
    return _guarded(source, lambda: _mesh(_tables(_read_while_reader_loads(path, stage), source), source,
                                          Path(path).parent))


def parse_obj(data: bytes, source: str, base_dir: str | Path | None = None) -> Mesh:
    """Parse OBJ bytes; ``source`` names the file in messages and gives the mesh its name (the stem).

    ``base_dir`` is where ``mtllib`` files are looked for; without it the MTL is not read.
    """
    return _guarded(source, lambda: _mesh(_tables(ended(data), source), source,
                                          None if base_dir is None else Path(base_dir)))


def _guarded(source: str, read: Callable[[], Mesh]) -> Mesh:
    try:
        return read()
    except LoadError:
        raise
    except MemoryError:
        raise LoadError(source, "not enough memory to load this file") from None
    except Exception as error:  # the contract: bad input never escapes as anything but LoadError
        raise LoadError(source, f"could not read the model ({type(error).__name__}: {error})") from None


def _mesh(raw: RawObj, source: str, base_dir: Path | None) -> Mesh:
    notes = list(raw.notes)
    tried: list[Path] = []
    libraries = _library(raw, base_dir, notes, tried)
    faces = _FaceMaterials.of(raw.material_runs, libraries, raw.face_start.size - 1)
    first, drawn = _with_pictures(libraries, faces, notes, tried)
    uv = None if raw.corner_texcoord is None else (raw.texcoords, raw.corner_texcoord)
    normals = None if raw.corner_normal is None else (raw.normals, raw.corner_normal)
    colours, colour_notes = _drawn_vertex_colours(raw.vertex_colours)
    mesh = derive_mesh(Path(source).stem, raw.positions, raw.corner_vertex, raw.face_start,
                       uv, normals, raw.colour, first, tuple(notes + colour_notes))
    mesh = replace(mesh, vertex_colours=colours, read_beside=tuple(tried))
    if faces.face_material is None:  # every face the object's own: a missing library is noted already
        return mesh
    return replace(mesh, materials=tuple(drawn), face_material=faces.face_material,
                   warnings=mesh.warnings + faces.notes())


def _with_pictures(libraries: Libraries | None, faces: _FaceMaterials, notes: list[str], tried: list[Path]
                   ) -> tuple[dict[str, object] | None, list[MeshMaterial]]:
    """The whole model's numbers (its first material's, where no usemtl says) and the materials the faces
    draw, their pictures read: past MAX_MATERIALS, none of those not drawn is."""
    if libraries is None or not libraries.materials:
        return None, []
    first, *drawn = libraries.with_pictures([libraries.materials[0], *faces.drawn], notes, tried)
    return first.values or None, drawn


def _library(raw: RawObj, base_dir: Path | None, notes: list[str], tried: list[Path]) -> Libraries | None:
    """The materials of the MTL files the mtllib lines name that the model uses (mtl.read_libraries);
    without a base_dir none is read, and usemtl lines with no mtllib line make a note."""
    runs = raw.material_runs
    used_names = [runs.names[number] for number in runs.used_numbers()] if runs else []
    if raw.mtllib and base_dir is not None:
        wanted = {*used_names, *map(name_before_comment, used_names)}  # "usemtl wood # oak" may mean "wood"
        return read_libraries(base_dir, raw.mtllib, notes, wanted, tried)
    if used_names and not raw.mtllib:
        notes.append(f"usemtl names materials ({_names_shown(used_names)}) but no mtllib line names their library; "
                     "using the scene's material")
    return None


def _names_shown(names: list[str]) -> str:
    return ", ".join(f"'{shortened(name)}'" for name in names[:3]) + (" ..." if len(names) > 3 else "")


def _drawn_vertex_colours(table: np.ndarray | None) -> tuple[np.ndarray | None, list[str]]:
    """The colours v lines give as the renderer's bytes, and what to say of them: 0..1 as MeshLab
    writes them, or 0..255 where they are whole numbers above 1 (as COFF's); a position whose v line
    gives none is white. A value outside the range (a float colour past 1) is held to it, with a note."""
    if table is None:
        return None, []
    given = ~np.isnan(table[:, 0])
    scaled = colour_fractions(table[given])
    held = np.clip(scaled, 0.0, 1.0)
    drawn = colour_bytes(held, int(given.sum()))
    colours = np.full((table.shape[0], 3), 255, np.uint8)
    colours[given] = drawn
    notes = [] if given.all() else [f"{counted(int((~given).sum()), 'position')} without a colour drawn white"]
    outside = int((held != scaled).any(axis=1).sum())
    if outside:
        notes.append(f"{counted(outside, 'vertex colour')} outside 0..1 (or 0..255) held to it")
    return colours, notes


@dataclass
class _FaceMaterials:
    """The materials the faces use, each once, and per face its index among them (-1: the object's own,
    where no usemtl gives one and the library's first shows no picture); the names the library lacks;
    how many materials past MAX_MATERIALS."""

    drawn: list[UnreadMaterial] = field(default_factory=list)
    face_material: np.ndarray | None = None  # None: every face the object's own
    unknown: list[str] = field(default_factory=list)  # in file order
    beyond: int = 0

    @staticmethod
    def of(runs: MaterialRuns, libraries: Libraries | None, faces: int) -> _FaceMaterials:
        """Each face's usemtl material; a face no usemtl gives one (none before it, a name the library
        lacks, one past MAX_MATERIALS) takes the object's own, the library's first material's numbers,
        and is drawn as a part of that material where its picture is read, so that it shows it."""
        if not libraries or not libraries.materials:
            return _FaceMaterials()
        first = libraries.materials[0]
        shown = libraries.shows_picture(first)  # one that cannot be read draws as the object's own: no part for it
        if not runs and not shown:  # its numbers are the object's own: one part would cost a copy
            return _FaceMaterials()
        found = _FaceMaterials()
        used: dict[int, int] = {}  # a material's id -> its index among those drawn
        found.face_material = np.full(faces, -1, np.int32)
        if runs:
            found._fill_runs(runs, libraries, used)
        unset = found.face_material < 0
        if shown and unset.any():  # past MAX_MATERIALS too: in place of the -1 part
            found.face_material[unset] = found._index(first, used)
        return found

    def _fill_runs(self, runs: MaterialRuns, libraries: Libraries, used: dict[int, int]) -> None:
        """Each usemtl run's faces get its material's index; -1 where the library lacks the name or
        it is past MAX_MATERIALS."""
        by_name = {material.name: material for material in reversed(libraries.materials)}  # the first of a name wins
        for material in libraries.materials:  # "newmtl wood # oak" is found as "wood" too, where no "wood" is
            by_name.setdefault(name_before_comment(material.name), material)
        index_of_number = np.full(len(runs.names), -1, np.int32)
        for number in runs.used_numbers().tolist():  # each name once, in the order of its first run
            name = runs.names[number]
            material = by_name.get(name) or by_name.get(name_before_comment(name))  # "usemtl wood # oak": wood
            if material is None:
                self.unknown.append(name)
            elif id(material) not in used and len(used) >= MAX_MATERIALS:
                self.beyond += 1
            else:
                index_of_number[number] = self._index(material, used)
        starts = np.frombuffer(runs.starts, np.int64)
        lengths = np.diff(np.append(starts, self.face_material.size))
        self.face_material[int(starts[0]):] = np.repeat(
            index_of_number[np.frombuffer(runs.name_numbers, np.int64)], lengths)

    def _index(self, material: UnreadMaterial, used: dict[int, int]) -> int:
        """The material's index among those drawn, drawn from now on where it was not."""
        if id(material) not in used:
            used[id(material)] = len(self.drawn)
            self.drawn.append(material)
        return used[id(material)]

    def notes(self) -> tuple[str, ...]:
        """Notes for the names the library lacks and the materials past MAX_MATERIALS."""
        notes: list[str] = []
        if self.unknown:
            notes.append(f"usemtl names materials the library lacks ({_names_shown(self.unknown)}); their faces "
                         "take the library's first material")
        if self.beyond:
            notes.append(f"{MAX_MATERIALS + self.beyond} materials used; the faces of all but the first "
                         f"{MAX_MATERIALS} take the library's first material")
        return tuple(notes)


# The compiled reader's first use in a process imports numba and loads its machine code: below this
# size the line reader is done sooner, and holds the GIL no longer than that import would.
# Once loaded, the compiled reader is the quicker one whatever the size.
COMPILED_READER_BYTES = 8 << 20
# Except a file with this many bytes in lines the line reader reads a word at a time (faces longer
# than its batches take, CAD's n-gons), where it is at its slowest.
COMPILED_READER_LONG_LINE_BYTES = 512 << 10


# Lines the line reader reads one at a time (blank lines, comments, statements, relative faces: not plain
# rows and faces, which it reads a batch at a time) cost it many times a batched line each; past this
# many a first file goes to the compiled reader, which reads it again from its start.
LINE_READER_SINGLE_LINES = 1 << 14


def _prefers_compiled_reader(text: bytes | np.ndarray) -> bool:
    if len(text) >= COMPILED_READER_BYTES or _compiled_reader_loaded():
        return True
    if len(text) < COMPILED_READER_LONG_LINE_BYTES:
        return False
    ends = np.flatnonzero(np.frombuffer(text, np.uint8) == ord("\n"))
    lengths = np.diff(ends, prepend=-1)
    return int(lengths[lengths > LONGEST_BATCHED_LINE].sum()) >= COMPILED_READER_LONG_LINE_BYTES


def _tables(text: bytes | np.ndarray, source: str) -> RawObj:
    """The raw tables of an ended text (marraztu.loaders.obj.text). One function, so that where the
    text is copied or edited the original, which only this frame holds, goes before the reading."""
    if not _prefers_compiled_reader(text):
        try:
            return _read_by_lines(text, source, LINE_READER_SINGLE_LINES)
        except ReadsSlowly:
            pass
    try:
        from marraztu.loaders.obj import fast  # numba, imported for the files that repay it
        counted = fast.count_text(text)
        if counted.to_look_at:  # a NUL, a CR, a backslash or a no-break space: the text checks decide
            text = as_bytes(text)
            edited = checked(text, source)
            if edited is not text:
                text, counted = edited, fast.count_text(edited)
            del edited
            if has_continuations(text):  # a continuation joins lines: only the line reader follows them
                return read_by_lines(text, source)
        return fast.read_fast(text, source, counted)
    except (LoadError, MemoryError):
        raise
    except Exception:  # no numba here, or a fast-reader bug: the person still gets their model, slowly
        return _read_by_lines(text, source)


_LOADING_THREAD = "marraztu compiled reader"
# The stage of a load that waits for numba to compile the reader (seconds, once: then it is cached).
READER_COMPILING = "compiling the fast OBJ reader, once after install"


@dataclass
class _ReaderLoad:
    """What the loading thread found out: whether numba compiles the reader (its cache lacks it)."""

    known: threading.Event = field(default_factory=threading.Event)
    compiles: bool = False


def _read_while_reader_loads(path: str | Path, stage: Callable[[str], None] | None) -> np.ndarray:
    """read_text; for a file the compiled reader will read, with its machine code loaded meanwhile on
    another thread: the read waits on the disk and on the kernel's fresh pages, the loading on a CPU.
    `stage` hears READER_COMPILING, once, where the read is done and numba is still compiling."""
    if _compiled_reader_loaded():
        return read_text(path, stage)
    load = _ReaderLoad()
    loading = threading.Thread(target=_load_compiled_reader, args=(load,), name=_LOADING_THREAD, daemon=True)

    def start_loading(size: int) -> None:  # once the file is open: a file that cannot be read waits for nothing
        if size >= COMPILED_READER_BYTES:
            loading.start()

    try:
        return read_text(path, stage, start_loading)
    finally:
        if loading.ident is not None:  # started
            load.known.wait()  # numba's import, the thread's first step
            compiling = load.compiles and stage is not None and loading.is_alive()
            if compiling:
                stage(READER_COMPILING)
            loading.join()
            if compiling:
                stage("parsing")


def _load_compiled_reader(load: _ReaderLoad) -> None:
    try:
        from marraztu.loaders.obj import scan  # numba; the passes compile on first use, not here
        load.compiles = scan.machine_code_cached() is False
        load.known.set()
        from marraztu.loaders.obj import fast  # its import compiles the mesh's loops where not cached
        fast.load_machine_code()
    except Exception:  # no numba here: _tables meets the same failure and reads by lines
        return
    finally:
        load.known.set()


def _read_by_lines(text: bytes | np.ndarray, source: str, most_single_lines: int = sys.maxsize) -> RawObj:
    return read_by_lines(checked(as_bytes(text), source), source, most_single_lines)


def _compiled_reader_loaded() -> bool:
    fast = sys.modules.get("marraztu.loaders.obj.fast")  # never imported here: that would import numba
    # Another thread may be importing it still: the module is listed before its functions are defined.
    loaded = getattr(fast, "machine_code_loaded", None)
    return loaded is not None and loaded()
