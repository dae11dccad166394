"""Reading a file a person named: regular files only, of a bounded size, every failure a LoadError.

Shared by the OBJ, image and scene readers so that none of them can be handed /dev/zero or a named
pipe (which Path.read_bytes() would read forever or block on); and their text's lines, a piece at
a time.
"""

from __future__ import annotations

import os
import re
import stat
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path
from typing import BinaryIO, Callable, Iterator, NamedTuple

from marraztu.errors import LoadError

MAX_FILE_BYTES = 1 << 30
# From this size of file on, what a read left in reference cycles (trimesh's objects, a refused read's
# frames) is collected once it is done (marraztu.loaders.exchange, marraztu.loaders.registry).
COLLECT_AFTER_BYTES = 1 << 20


class Stamp(NamedTuple):
    """When a file was last written, and its size: what tells that it changed."""

    modified_ns: int
    size: int


def file_stamp(path: str | Path) -> Stamp | None:
    """The file's Stamp; None where it is not there (or cannot be looked at)."""
    try:
        status = os.stat(path)
    except (OSError, ValueError):  # ValueError: a NUL in its name
        return None
    return Stamp(status.st_mtime_ns, status.st_size)


class MissingFile(LoadError):
    """No file at `path`. Its hint looks at `written`, the name as the person wrote it, where the reader
    of that name gives it again (as_written); else at the whole path. `other_case`: the one file of its
    folder named so but for case ("" for none), where already looked for (its folder is listed once)."""

    def __init__(self, path: str | Path, written: str | None = None, other_case: str | None = None) -> None:
        self.other_case = _named_in_other_case(path) if other_case is None else other_case
        hint = _windows_path_hint(str(path)) if written is None else _windows_name_hint(written)
        super().__init__(path, f"no such file{_other_case_hint(self.other_case, written)}{hint}")

    def as_written(self, written: str) -> MissingFile:
        return MissingFile(self.path, written, self.other_case)


def _named_in_other_case(path: str | Path) -> str:
    """The one file in the folder of `path` named as it is but for case (sphere.obj, Sphere.obj written): a
    file copied from Windows or macOS, which read names in any case; "" where none or several are."""
    folder, name = os.path.split(os.fspath(path))
    found = names_in_any_case(folder).get(name.lower(), ())
    return found[0] if len(found) == 1 else ""


def _other_case_hint(found: str, written: str | None) -> str:
    """' (did you mean models/sphere.obj?)': the name as written, its last part as the folder holds it."""
    if not found:
        return ""
    folders, slash, _ = (written or "").rpartition("/")
    return f" (did you mean {folders}{slash}{found}?)"


def names_in_any_case(folder: str | Path) -> dict[str, tuple[str, ...]]:
    """The files in `folder`, each spelling of a name by that name in lower case; nothing where it cannot be
    listed. Within listings_kept, listed once for the load however many names are looked for in it."""
    folder = os.fspath(folder) or os.curdir
    kept = _KEPT.get()
    try:
        if kept is None:
            return _listing(folder)
        key = same_file_key(Path(folder))  # 'a/..' and '.' are one listing
        if key not in kept:
            kept[key] = _listing(folder)
        return kept[key]
    except (OSError, ValueError):  # no such folder, or a NUL in its name
        return {}


Listings = dict[Path, dict[str, tuple[str, ...]]]  # a folder resolved (same_file_key) -> names_in_any_case's
# One load's listings, given up with it: a cache between loads would be stale where a folder changed within
# its modification time's tick (a coarse clock, FAT's 2 seconds) or another took its name.
_KEPT: ContextVar[Listings | None] = ContextVar("listings_kept", default=None)


@contextmanager
def listings_kept(listings: Listings) -> Iterator[None]:
    """Within it, names_in_any_case (the MTL reader's any-case lookup and a missing file's hint) lists each
    folder once, into `listings`: a model naming thousands of missing pictures costs one listing, not one each."""
    token = _KEPT.set(listings)
    try:
        yield
    finally:
        _KEPT.reset(token)


def _listing(folder: str) -> dict[str, tuple[str, ...]]:
    names: dict[str, list[str]] = {}
    with os.scandir(folder) as entries:
        for entry in entries:
            if entry.is_file():
                names.setdefault(entry.name.lower(), []).append(entry.name)
    return {lower: tuple(spellings) for lower, spellings in names.items()}  # a tuple grown each time: n squared


def said_as_written(error: BaseException, path: Path, written: str) -> BaseException:
    """The error, its hint given by `written` where it says that `path`, the file named so, is missing
    (not a file that one names): a folder above it, which no one typed, may hold a back slash."""
    return error.as_written(written) if isinstance(error, MissingFile) and error.path == str(path) else error


@contextmanager
def errors_as_load_errors(path: str | Path) -> Iterator[None]:
    """Turns what the operating system says about `path` into a LoadError naming it."""
    try:
        yield
    except FileNotFoundError:
        raise MissingFile(path) from None
    except PermissionError:
        raise LoadError(path, "permission denied") from None
    except MemoryError:
        raise LoadError(path, "file too large to load") from None
    except (OSError, ValueError) as error:  # ValueError: a path with a NUL byte in it
        raise LoadError(path, f"cannot read the file ({getattr(error, 'strerror', None) or error})") from None


# A drive, as a Windows path begins: C:\ or C:/ (after the folder a scene or a model is read from).
_WINDOWS_DRIVE = re.compile(r"(?:^|[/\\])([A-Za-z]:)[/\\]")
# A drive, as a name a person wrote begins.
_WRITTEN_DRIVE = re.compile(r"([A-Za-z]:)[/\\]")


def _windows_path_hint(path: str) -> str:
    """Why a path holding a back slash, or beginning with a drive (a command line's, as typed), is not
    found where "\\" is no folder separator and C: no drive (every system but Windows): it is a Windows
    path, as a scene or a model written there gives it. Its drive may follow the folder read from. A control
    character in it is an escape a scene's "double quotes" made of a back slash (a scene's own texture)."""
    back_slashes = "\\" in path
    drive = _WINDOWS_DRIVE.search(path) if back_slashes else _WRITTEN_DRIVE.match(path)
    return _hint(back_slashes, drive, _CONTROL_CHARACTER.search(path))


def _windows_name_hint(written: str) -> str:
    """_windows_path_hint of a name as written: a drive, where it has one, begins it."""
    return _hint("\\" in written, _WRITTEN_DRIVE.match(written), _CONTROL_CHARACTER.search(written))


def _hint(back_slashes: bool, drive: re.Match[str] | None, control: re.Match[str] | None) -> str:
    windows = os.sep == "\\"  # where back slashes and drives are read as written
    slashes = [_escape_made(control[0])] if control else [_USE_SLASHES] if back_slashes and not windows else []
    words = slashes + ([f"{drive[1]} is a Windows drive"] if drive and not windows else [])
    return f" ({'; '.join(words)})" if words else ""


_USE_SLASHES = "use / between folders"
_OR_SINGLE_QUOTES = "(or, on Windows, 'single quotes')"  # which keep back slashes, folder separators only there
# What TOML's escapes in a "double-quoted" string make of a Windows path's folders (models\floor.obj: \f).
_ESCAPES_MADE = {"\b": ("\\b", "a backspace"), "\t": ("\\t", "a tab"), "\n": ("\\n", "a line end"),
                 "\f": ("\\f", "a form feed"), "\r": ("\\r", "a carriage return")}
_AS_TYPED = str.maketrans({made: escape for made, (escape, _) in _ESCAPES_MADE.items()})
_CONTROL_CHARACTER = re.compile(r"[\x00-\x1f\x7f]")


def escape_words(escape: str | None = None) -> str:
    """Why a Windows path in a TOML "double-quoted" string is not the path written (C:\\Users: \\U), and what
    to write instead; `escape` names the escape, where known."""
    here = f" ({escape} here)" if escape else ""
    return f'a back slash inside "double quotes" starts an escape{here}; {_USE_SLASHES} {_OR_SINGLE_QUOTES}'


def _escape_made(control: str) -> str:
    """The words for a control character in a file's name, which no one means: the escape that makes it first,
    where one does (models\\floor.obj's \\f)."""
    escape, made = _ESCAPES_MADE.get(control, (None, None))
    if escape is None:
        return f"it holds a control character, {escape_words()}"
    return f"{escape} made {made}: {escape_words()}"


def as_typed(name: str) -> str:
    """A name as a person typed it in "double quotes": its escaped control characters as the escapes (\\f)."""
    return name.translate(_AS_TYPED)


# Linux's PATH_MAX: no longer path names a file it opens.
_LONGEST_PATH = 4096


def same_file_key(path: Path) -> Path:
    """One key for every spelling of a file (./x, a/../x, a link to it), so a cache reads it once. A path
    longer than any the system opens is known by its text ('..' taken away), since resolving it looks at
    each of its parts with the text copied anew, its length squared."""
    absolute = path.absolute()
    if len(str(absolute)) > _LONGEST_PATH:
        return Path(os.path.normpath(absolute))
    try:
        return path.resolve()
    except (OSError, RuntimeError, ValueError):  # a link loop, a NUL: the reading says what is wrong
        return absolute


_SHOWN_NAME_CHARACTERS = 80


def shown(name: str) -> str:
    """A name a file gives (a library, a texture, a URI) as a message shows it: a long one cut."""
    return name if len(name) <= _SHOWN_NAME_CHARACTERS else name[:_SHOWN_NAME_CHARACTERS - 3] + "..."


def is_there(path: Path) -> bool:
    """Something other than a folder is at `path`: reading a device or a pipe then says what it is."""
    try:
        return path.exists() and not path.is_dir()
    except (OSError, ValueError):  # a name too long for the file system, or with a NUL: not there
        return False


_PROJECT_FOLDERS = 3  # deep enough for the folders exporters keep pictures in (3ds Max's sceneassets/images/)


def spellings(name: str) -> tuple[str, ...]:
    """Where a file a model names beside it is looked for: as written (a Windows exporter's back
    slashes as slashes, quotes and blanks around it dropped), then by its last part alone, as the
    model's own folder would hold it, then with the folders before that part, one to three, as a copied
    project holds it (a whole path into Maya's sourceimages/), never above a '..' or a drive."""
    written = name.strip().strip('"').replace("\\", "/")
    parts = written.split("/")
    drive = max((at for at, part in enumerate(parts) if part[1:2] == ":"), default=-1)  # as Windows reads 'C:'
    if drive >= 0:  # past the last drive: 'a/C:../t' on Windows is C:'s '..'
        parts = [parts[drive][2:], *parts[drive + 1:]]
    cut = max((at + 1 for at, part in enumerate(parts) if part == ".."), default=0)
    inside = [part for part in parts[cut:] if part not in ("", ".")]
    tails = ["/".join(inside[-count:]) for count in range(1, min(len(inside), _PROJECT_FOLDERS + 1) + 1)]
    return tuple(dict.fromkeys([written, parts[-1], *tails]))


def line_at(data: bytes, offset: int) -> int:
    """The line number of the byte at `offset`, lines ending as text_lines ends them (\n, \r\n, a lone \r)."""
    return data.count(b"\n", 0, offset) + data.count(b"\r", 0, offset) - data.count(b"\r\n", 0, offset) + 1


def line_end_from(data: bytes, at: int) -> int:
    """The offset just past the end of the line the byte at `at` lies on; the file's end on a last line
    without a line end."""
    end = _LINE_END.search(data, at)
    return len(data) if end is None else end.end()


def line_end_after(data: bytes, line: int) -> int:
    """The offset just past the end of line number `line` (1-based, lines ending as text_lines ends them);
    the file's end where that line is its last and has no line end."""
    at, ended = 0, 0
    for ended, end in zip(range(1, line + 1), _LINE_END.finditer(data)):
        at = end.end()
    return at if ended == line else len(data)


_LINE_END = re.compile(rb"\r\n|\n|\r")


BOM = b"\xef\xbb\xbf"  # UTF-8's byte order mark, which Notepad and some exporters put before a text
UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")  # Notepad's "Unicode", PowerShell's Out-File: no text a reader reads


def bom_length(data: bytes) -> int:
    """How many of a text's first bytes are one UTF-8 byte order mark, which every text reader skips."""
    return len(BOM) if data.startswith(BOM) else 0


def decoded(text: bytes) -> str:
    """A name or a text file's words: UTF-8, or else Windows-1252, which Windows exporters write."""
    try:
        return text.decode("utf-8")
    except UnicodeDecodeError:
        return text.decode("cp1252", errors="replace")  # five of its bytes are no character


_LINES_PIECE = 1 << 12  # a piece and the list of its lines stay a few kilobytes


def text_lines(data: bytes, start: int = 0) -> Iterator[str]:
    """The text's lines from `start` (a line's first byte) as editors count them (a line ends at \n,
    \r\n or a lone \r, never at the form feeds and separators str.splitlines() also ends lines at), a
    piece at a time: a list of every line would hold the text again, in pieces. Each is UTF-8, or else
    Windows-1252 (see decoded). Each piece ends just after a line end, so its lines are the text's."""
    while start < len(data):
        stop = line_end_from(data, start + _LINES_PIECE)  # found by a search that stops at the first end
        yield from _lines_of(data[start:stop])
        start = stop


def _lines_of(piece: bytes) -> list[str]:
    if b"\r" in piece:
        piece = piece.replace(b"\r\n", b"\n").replace(b"\r", b"\n")
    try:
        lines = piece.decode("utf-8").split("\n")
    except UnicodeDecodeError:  # a line of another encoding: each line decoded on its own
        lines = [decoded(line) for line in piece.split(b"\n")]
    return lines[:-1] if not lines[-1] else lines  # the piece ends with its newline


def regular_file_size(path: str | Path, limit: int = MAX_FILE_BYTES) -> int:
    """The size of a regular file of at most `limit` bytes, or a LoadError naming it (no line).

    Directories, devices (/dev/zero never ends) and named pipes (opening one blocks until someone
    writes) are refused from their metadata, before anything is opened.
    """
    with errors_as_load_errors(path):
        info = os.stat(path)
    if stat.S_ISDIR(info.st_mode):
        raise LoadError(path, "is a directory, not a file")
    if not stat.S_ISREG(info.st_mode):
        raise LoadError(path, "not a regular file (a device or a named pipe?)")
    if info.st_size > limit:
        raise LoadError(path, f"file too large (more than {limit >> 20} MiB)")
    return info.st_size


def size_or_zero(path: str | Path) -> int:
    """The file's size in bytes; 0 where it cannot be known (gone, a NUL in its name)."""
    try:
        return os.stat(path).st_size
    except (OSError, ValueError):
        return 0


# What a clone without `git lfs pull` holds in a model's or picture's place: git-lfs's pointer, a text
# under this many bytes of its version line first and a size line (of the file it stands for) among its keys.
GIT_LFS_POINTER_BYTES = 1024
_GIT_LFS_POINTER = re.compile(rb"version https://git-lfs\.github\.com/spec/v1\r?\n(?:[^\n]*\n)*?size ([0-9]+)\r?\n")


def git_lfs_pointer_words(head: bytes, what: str) -> str | None:
    """Why a file whose first GIT_LFS_POINTER_BYTES are `head` is no `what` (model, picture) where it is a
    Git LFS pointer; None where it is not one."""
    pointer = _GIT_LFS_POINTER.match(head) if len(head) < GIT_LFS_POINTER_BYTES else None
    if pointer is None:
        return None
    return f"a Git LFS pointer, not the {what}: its {pointer[1].decode()} bytes are fetched by `git lfs pull`"


def refuse_git_lfs_pointer(path: str | Path, what: str) -> None:
    """A LoadError where the file at `path` is a Git LFS pointer (git_lfs_pointer_words). Only a regular file
    as small as one is opened; one that cannot be read is left to its reader, which says why."""
    try:
        info = os.stat(path)
        if not stat.S_ISREG(info.st_mode) or info.st_size >= GIT_LFS_POINTER_BYTES:
            return
        with open(path, "rb") as stream:
            head = stream.read(GIT_LFS_POINTER_BYTES)
    except (OSError, ValueError):  # ValueError: a NUL in the name
        return
    words = git_lfs_pointer_words(head, what)
    if words is not None:
        raise LoadError(path, words)


def read_head(path: str | Path, count: int) -> bytes:
    """The first `count` bytes of a regular file (fewer if it is shorter): enough to tell its kind."""
    regular_file_size(path)
    with errors_as_load_errors(path), open(path, "rb") as stream:
        return stream.read(count)


def read_file(path: str | Path, limit: int = MAX_FILE_BYTES) -> bytes:
    """All bytes of a regular file of at most `limit` bytes, or a LoadError naming it."""
    size = regular_file_size(path, limit)
    with errors_as_load_errors(path), open(path, "rb") as stream:
        data = _read_up_to(stream, size, limit)
    if len(data) > limit:  # it grew after stat
        raise LoadError(path, f"file too large (more than {limit >> 20} MiB)")
    return data


_ANYTHING = re.compile(rb"\S")  # searched, not stripped: strip() copies the whole file to look at its first word


def read_model_bytes(path: str | Path, stage: Callable[[str], None] | None) -> bytes:
    """A model file's bytes, refused where they are blank; `stage` hears "reading" and then "parsing"
    (the window shows them)."""
    if stage is not None:
        stage("reading")
    data = read_file(path)
    refuse_blank(path, data)
    if stage is not None:
        stage("parsing")
    return data


def refuse_blank(path: str | Path, data: bytes | memoryview) -> None:
    """A LoadError for a model file of whitespace alone."""
    if not _ANYTHING.search(data):
        raise LoadError(path, "empty file: no faces")


def _read_up_to(stream: BinaryIO, expected: int, limit: int) -> bytes:
    """The stream's bytes, at most limit + 1 of them.

    read(n) reserves n bytes at once, so ask for the size stat gave (and one more, to notice a file
    that grew meanwhile), never for the limit.
    """
    pieces = [stream.read(expected + 1)]
    total = len(pieces[0])
    while total > expected and total <= limit:
        piece = stream.read(min(1 << 24, limit + 1 - total))
        if not piece:
            break
        pieces.append(piece)
        total += len(piece)
    return b"".join(pieces) if len(pieces) > 1 else pieces[0]
