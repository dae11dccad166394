"""Texture images: PPM (P6, P3) by our own code, PNG and JPEG through Pillow; nothing else.

The format comes from the file's first bytes, never its name, and Pillow is asked for that one format
only: it recognises many others by content, some of which it hands to other programs (EPS to
Ghostscript), and a texture must never run anything.

Why our own PPM reader when Pillow reads PPM: the seed's texture format deserves strict errors that
say what is wrong (a truncated raster, a value above maxval, a bad header token), and a header must
not make us allocate what it merely claims: the raster's length is checked against the header
before any array is made, and sizes are capped.

Images come back as (H, W, 3) uint8 with the top row first, as stored in the file; the renderer flips
them for OpenGL so that v = 0 is the bottom row.
"""

from __future__ import annotations

import contextlib
import io
import re
import threading
import warnings
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import BinaryIO, NamedTuple

import numpy as np
from PIL import Image

from marraztu.errors import LoadError, escaped
from marraztu.loaders.files import GIT_LFS_POINTER_BYTES, git_lfs_pointer_words, line_at, read_file, read_head, shown
from marraztu.loaders.patterns import compiled
from marraztu.loaders.words import shortened_bytes
from marraztu.model.build import picture_bytes

# No texture a student uses comes near this; a header claiming more is broken or hostile.
MAX_PIXELS = 64 * 1024 * 1024
# A photo's header holds tens of markers (JFIF, EXIF, an ICC profile in 64 KB pieces, its tables), an
# editor's PNG tens of chunks besides its pixels. Pillow keeps every segment and text or private chunk
# it reads, in lists and dicts, some 33 bytes for each byte of a header of empty ones: a picture that
# holds more than this many is refused before Pillow reads it.
MAX_HEADER_PARTS = 4096
# A progressive JPEG is drawn in scans, each decoded over the whole picture: encoders write about 10, so a
# file of thousands (a few bytes each) would cost thousands of decodings. More than this is refused.
MAX_JPEG_SCANS = 100
_PPM_MAGICS = (b"P6", b"P3")
# The formats read, by their first bytes.
FORMATS_BY_MAGIC = {b"P6": "PPM", b"P3": "PPM", b"\x89PNG\r\n\x1a\n": "PNG", b"\xff\xd8\xff": "JPEG"}
_MAGIC_LENGTH = max(len(magic) for magic in FORMATS_BY_MAGIC)
# Skips whitespace and comments; possessive, so that sre keeps no state per byte skipped.
_HEADER_TOKEN = compiled(rb"(?:\s|#[^\n\r]*+[\n\r])*+([^\s#]++)")


def load_image(path: str | Path) -> np.ndarray:
    """(H, W, 3) uint8, top row first. Raises LoadError naming the file for any problem."""
    file = Path(path)
    head = read_head(file, GIT_LFS_POINTER_BYTES)  # refuses directories, devices, pipes and huge files first
    kind = image_format(head)
    try:
        if kind == "PPM":
            return parse_ppm(read_file(file), str(path))
        if kind is None:
            raise _not_a_picture(file, head)
        return _load_with_pillow(file, kind)
    except LoadError:
        raise
    except MemoryError:
        raise LoadError(file, "not enough memory to load this image") from None


def _not_a_picture(file: Path, head: bytes) -> LoadError:
    """Why a file of no format read is refused: a Git LFS pointer, a netpbm file not P6 or P3, or neither."""
    if git_lfs_pointer_words(head, "picture") is None and (file.suffix.lower() in (".ppm", ".pnm")
                                                           or _looks_like_pnm(head)):
        return _not_ppm(file, head[:2])
    return LoadError(file, not_a_picture(head))


def not_a_picture(head: bytes) -> str:
    """Why a file whose first GIT_LFS_POINTER_BYTES (or all, where fewer) are `head`, of no format read, is no
    picture."""
    return git_lfs_pointer_words(head, "picture") or f"not a PNG, JPEG or PPM picture (it starts with {head[:8]!r})"


def _looks_like_pnm(head: bytes) -> bool:
    """P1 to P7: the netpbm family, of which only P6 and P3 (colour) are read."""
    return head[:1] == b"P" and head[1:2].isdigit()


def image_format(head: bytes) -> str | None:
    """"PPM", "PNG" or "JPEG" from a file's first bytes; None for anything else."""
    return next((kind for magic, kind in FORMATS_BY_MAGIC.items() if head.startswith(magic)), None)


def fit_texture(image: np.ndarray, longest_side: int) -> tuple[np.ndarray, str | None]:
    """The image scaled down, keeping its shape, when a side is longer than the GPU takes; and a note
    saying so."""
    height, width = image.shape[:2]
    if max(height, width) <= longest_side:
        return image, None
    scale = longest_side / max(height, width)
    size = (max(1, round(width * scale)), max(1, round(height * scale)))
    smaller = np.asarray(Image.fromarray(image).resize(size, Image.Resampling.LANCZOS), dtype=np.uint8)
    return smaller, (f"texture {width}x{height} scaled to {size[0]}x{size[1]}: this GPU takes "
                     f"{longest_side} pixels a side at most")


def fallback_texture() -> np.ndarray:
    """A 64x64 light checker whose top-left cell is red, so a flipped or mirrored mapping shows."""
    cells = (np.indices((8, 8)).sum(axis=0) % 2).astype(bool)
    image = np.where(cells[..., None], np.uint8(255), np.uint8(170)).repeat(3, axis=2)
    image = image.repeat(8, axis=0).repeat(8, axis=1)
    image[:8, :8] = (220, 30, 30)  # the orientation mark: top-left in the file
    image[:8, -8:] = (30, 160, 30)  # top-right: tells a left-right mirror from an upside-down flip
    return np.ascontiguousarray(image)


def load_texture_or_fallback(path: str | Path | None) -> tuple[np.ndarray, str | None]:
    """The image, or the built-in checker and a one-line message naming the file."""
    if path is None:
        return fallback_texture(), None
    try:
        return load_image(path), None
    except LoadError as error:
        return fallback_texture(), f"{error} (using the built-in checker texture)"


# --------------------------------------------------------------------------------------------------
# PPM
# --------------------------------------------------------------------------------------------------


def parse_ppm(data: bytes, source: str) -> np.ndarray:
    """A P6 or P3 image from bytes; ``source`` names the file in messages."""
    magic = data[:2]
    if magic not in _PPM_MAGICS:
        raise _not_ppm(source, magic)
    width, height, maxval, raster_at = _ppm_header(data, source)
    if magic == b"P6":
        samples = _binary_samples(memoryview(data)[raster_at:], width * height * 3, maxval, source)  # no copy
        if samples.size and int(samples.max()) > maxval:
            raise LoadError(source, f"a sample value ({int(samples.max())}) exceeds maxval {maxval}")
    else:
        samples = _ascii_samples(data, raster_at, width * height * 3, maxval, source)
    return _to_8_bit(samples, maxval).reshape(height, width, 3)


def _not_ppm(source: str | Path, magic: bytes) -> LoadError:
    return LoadError(source, f"not a PPM image: starts with {magic!r}, expected P6 or P3")


def _ppm_header(data: bytes, source: str) -> tuple[int, int, int, int]:
    """(width, height, maxval, offset of the raster): three numbers after the magic, then one whitespace."""
    numbers, at = [], 2
    for name in ("width", "height", "maxval"):
        match = _HEADER_TOKEN.match(data, at)
        if match is None:
            raise LoadError(source, f"truncated PPM header: no {name}")
        token = match.group(1)
        if not token.isdigit():
            raise LoadError(source, f"bad PPM header: {name} {shortened_bytes(token)} is not a whole number")
        numbers.append(int(token[:12]) if len(token) <= 12 else 10**12)  # beyond any cap anyway
        at = match.end()
    width, height, maxval = numbers
    _check_header(width, height, maxval, source)
    # One whitespace byte ends the header; a comment may sit right after maxval, before it.
    at = _skip_comment(data, at)
    if at >= len(data) or data[at:at + 1] not in (b" ", b"\t", b"\n", b"\r", b"\x0b", b"\x0c"):
        raise LoadError(source, "truncated PPM: no pixel data after the header")
    return width, height, maxval, at + 1


def _skip_comment(data: bytes, at: int) -> int:
    if data[at:at + 1] != b"#":
        return at
    newline = min((pos for pos in (data.find(b"\n", at), data.find(b"\r", at)) if pos >= 0), default=len(data))
    return newline


def _check_header(width: int, height: int, maxval: int, source: str) -> None:
    if width < 1 or height < 1:
        raise LoadError(source, f"bad PPM size {width}x{height}: both must be at least 1")
    refusal = picture_size_refusal(width, height, "PPM")
    if refusal is not None:
        raise LoadError(source, refusal)
    if not 1 <= maxval <= 65535:
        raise LoadError(source, f"bad PPM maxval {maxval}: must be 1 to 65535")


def _binary_samples(raster: bytes | memoryview, count: int, maxval: int, source: str) -> np.ndarray:
    width = 1 if maxval < 256 else 2  # 16-bit samples are big-endian
    needed = count * width
    if len(raster) < needed:
        raise LoadError(source, f"truncated PPM: {needed} bytes of pixel data expected, found {len(raster)}")
    return np.frombuffer(raster, dtype=np.uint8 if width == 1 else ">u2", count=count)


_COMMENT = re.compile(rb"#[^\n\r]*+")
_LINE_END = re.compile(rb"[\n\r]")
_COMMENT_PIECE_BYTES = 1 << 12


def _without_comments(raster: bytes) -> bytes:
    """Each comment (# to its line's end) a space, a piece of whole lines at a time: re.sub holds two
    objects a comment until it joins them, which for a raster of short comments was 87 bytes a byte."""
    cleaned, start = [], 0
    while start < len(raster):
        line_end = _LINE_END.search(raster, start + _COMMENT_PIECE_BYTES)  # no comment spans one
        end = len(raster) if line_end is None else line_end.end()
        cleaned.append(_COMMENT.sub(b" ", raster[start:end]))
        start = end
    return b"".join(cleaned)


# Digits, whitespace and comments: what a P3 raster holds up to its first byte that is none of them.
_GOOD_P3_TEXT = compiled(rb"(?:[0-9 \t\n\r\x0b\x0c]++|#[^\n\r]*+)*+")


def _ascii_samples(data: bytes, raster_at: int, count: int, maxval: int, source: str) -> np.ndarray:
    raster = data[raster_at:]
    if b"#" in raster:
        raster = _without_comments(raster)
    stray = raster.translate(None, b"0123456789 \t\n\r\x0b\x0c")
    if stray:  # found in the raster without its comments; its line, in the file with them
        at = _GOOD_P3_TEXT.match(data, raster_at).end()  # type: ignore[union-attr]  # it matches empty text: never None
        raise LoadError(source, f"bad P3 pixel data: {stray[:1]!r} is not part of a number", line=line_at(data, at))
    # Every sample takes at least two bytes (a digit and a separator): a short raster fails here,
    # before the parser builds anything the size of what the header claims.
    if len(raster) < 2 * count - 1 or not raster.strip():  # (numpy reads blank text as [-1])
        raise LoadError(source, f"truncated PPM: {count} samples expected, the data is too short")
    samples = np.fromstring(raster, dtype=np.int64, sep=" ")  # only digits and whitespace remain
    if samples.size < count:
        raise LoadError(source, f"truncated PPM: {count} samples expected, found {samples.size}")
    samples = samples[:count]
    above = samples > maxval  # numbers too long for int64 saturate, so this still finds them
    if above.any():
        first = int(np.argmax(above))
        raise LoadError(source, f"a sample value ({int(samples[first])}) exceeds maxval {maxval}",
                        line=_raster_line(data, raster_at, raster, _number_start(raster, first)))
    return samples


def _raster_line(data: bytes, raster_at: int, raster: bytes, offset: int) -> int:
    """The file's line of the raster's byte at `offset`: a comment made a blank held no line end, so the
    raster without its comments has the file's lines."""
    # The header's last byte a CR and the raster's first an LF: one line end, which each count would count.
    split_line_end = data[raster_at - 1:raster_at] == b"\r" and raster[:1] == b"\n"
    return line_at(data, raster_at) + line_at(raster, offset) - 1 - split_line_end


_NUMBER_PIECE_BYTES = 1 << 20


def _number_start(raster: bytes, index: int) -> int:
    """Where number `index` starts in a raster of digits and whitespace alone, counted a piece at a time:
    a table of every number's start would cost more than the samples."""
    before, after_digit = 0, False  # numbers started in the pieces before; whether they end in a digit
    for at in range(0, len(raster), _NUMBER_PIECE_BYTES):
        piece = np.frombuffer(raster, np.uint8, min(_NUMBER_PIECE_BYTES, len(raster) - at), at)
        digit = piece - ord("0") < 10  # uint8 wraps: a byte below '0' is large
        starts = np.flatnonzero(digit & ~np.concatenate(([after_digit], digit[:-1])))
        if before + starts.size > index:
            return at + int(starts[index - before])
        before, after_digit = before + starts.size, bool(digit[-1])
    raise ValueError(f"no number {index} in the raster")  # never: the samples were read from it


def _to_8_bit(samples: np.ndarray, maxval: int) -> np.ndarray:
    if maxval == 255:
        return samples.astype(np.uint8)
    return _through_table(samples, _scale_table(maxval + 1, maxval))


def _scale_table(size: int, top: int) -> np.ndarray:
    """Every sample value 0..size-1 scaled to 0..255, rounded (so `top` maps to 255)."""
    return ((np.arange(size, dtype=np.uint32) * 255 + top // 2) // top).astype(np.uint8)


_TABLE_PIECE = 1 << 20


def _through_table(samples: np.ndarray, table: np.ndarray) -> np.ndarray:
    """table[samples] as uint8, a piece at a time: indexing converts the indices to 8-byte integers."""
    out = np.empty(samples.shape, np.uint8)
    flat_in, flat_out = samples.reshape(-1), out.reshape(-1)
    for at in range(0, flat_in.size, _TABLE_PIECE):
        flat_out[at:at + _TABLE_PIECE] = table[flat_in[at:at + _TABLE_PIECE]]
    return out


# --------------------------------------------------------------------------------------------------
# Files and Pillow
# --------------------------------------------------------------------------------------------------


def check_picture_header(source: str | Path, data: bytes | memoryview) -> None:
    """Refuses a JPEG or PNG whose header Pillow would keep at many times its size, and a JPEG of more
    scans than any encoder writes."""
    kind = image_format(bytes(data[:_MAGIC_LENGTH]))
    header = _jpeg_header(data) if kind == "JPEG" else _JpegHeader(0, None)
    if header.steps > MAX_HEADER_PARTS:
        raise LoadError(source, f"more than {MAX_HEADER_PARTS} markers and stray bytes before the picture: no "
                                "JPEG's header holds so many")
    if header.precision not in (None, 8):
        raise LoadError(source, f"a {header.precision}-bit JPEG: Pillow reads 8-bit ones only")
    if kind == "JPEG" and _jpeg_scans(data) > MAX_JPEG_SCANS:
        raise LoadError(source, f"more than {MAX_JPEG_SCANS} scans, each decoded over the whole picture: a "
                                "progressive JPEG has about 10")
    if kind == "PNG":
        _check_png_chunks(source, data)


def check_picture(source: str | Path, data: bytes) -> None:
    """Refuses, from its header alone, a PPM, PNG or JPEG that check_picture_header refuses, one of more
    than MAX_PIXELS pixels, or one Pillow cannot open: for a picture read for another reader (trimesh)."""
    kind = image_format(data[:_MAGIC_LENGTH])
    if kind == "PPM":
        _ppm_header(data, str(source))  # checks the size
    elif kind is not None:
        with _opened(source, io.BytesIO(data), kind):
            pass


def check_picture_size(source: str | Path, width: int, height: int) -> None:
    """Refuses a picture of more than MAX_PIXELS pixels (before it is decoded)."""
    refusal = picture_size_refusal(width, height)
    if refusal is not None:
        raise LoadError(source, refusal)


def picture_size_refusal(width: int, height: int, kind: str = "image") -> str | None:
    """Why a picture of this size is not decoded (more than MAX_PIXELS pixels); None when it may be."""
    if width * height > MAX_PIXELS:
        return f"{kind} size {width}x{height} is too large (at most {MAX_PIXELS} pixels)"
    return None


def _jpeg_scans(data: bytes | memoryview) -> int:
    """The start-of-scan markers: an 0xFF in a scan's coded data is followed by 0x00, so each is a marker
    (or lies in a segment's bytes, a thumbnail's own scan say: counted too, as few are)."""
    return (data if isinstance(data, bytes) else bytes(data)).count(b"\xff\xda")


# Start-of-frame markers: baseline, extended, progressive, lossless, in their Huffman and arithmetic kinds.
_JPEG_FRAMES = frozenset(range(0xC0, 0xD0)) - {0xC4, 0xC8, 0xCC}


class _JpegHeader(NamedTuple):
    steps: int  # the markers and stray bytes Pillow reads before the scan (up to one past the limit)
    precision: int | None  # the frame header's bits a sample (Pillow takes all but 8 for no JPEG); None: none read


def _jpeg_header(data: bytes | memoryview) -> _JpegHeader:
    """The header walked as Pillow's reader walks it: it skips bytes that are not 0xFF, fill bytes and
    escaped 0xFF one at a time, and stops at a frame header of other than 8 bits a sample."""
    from PIL.JpegImagePlugin import MARKER

    view, at, steps, precision = memoryview(data), 2, 0, None  # the first 0xFF after the start-of-image marker
    while at + 1 < len(view) and steps <= MAX_HEADER_PARTS:
        if view[at] != 0xFF:  # junk: to the next 0xFF, a step a byte
            window = bytes(view[at:at + MAX_HEADER_PARTS + 1])
            found = window.find(b"\xff")
            steps, at = steps + (found if found >= 0 else len(window)), at + (found if found >= 0 else len(window))
            continue
        marker, steps = (view[at] << 8) | view[at + 1], steps + 1
        if marker in MARKER and MARKER[marker][2] is not None:  # a segment: its length follows
            if marker == 0xFFDA or at + 4 > len(view):  # the scan: Pillow's header ends
                break
            if view[at + 1] in _JPEG_FRAMES and precision is None and at + 4 < len(view):
                precision = view[at + 4]
                if precision != 8:  # Pillow refuses the file here
                    break
            at += 2 + max((view[at + 2] << 8) | view[at + 3], 2)  # Pillow reads no less than the length's own
        elif marker in MARKER or marker == 0xFF00:  # a marker alone, or an escaped 0xFF
            at += 2
        elif marker == 0xFFFF:  # a fill byte
            at += 1
        else:  # Pillow says "no marker found"
            break
    return _JpegHeader(steps, precision)


def _check_png_chunks(source: str | Path, data: bytes | memoryview) -> None:
    """The chunks walked by their lengths, up to the end: more than MAX_HEADER_PARTS besides the pixels'
    (IDAT, fdAT), or a length past the file's end, is refused before Pillow, which asks for the whole
    of an IDAT's at once (4 GiB for a length of 0xFFFFFFFF in a 77-byte file)."""
    view, at, chunks = memoryview(data), 8, 0
    while at + 8 <= len(view):
        kind, length = bytes(view[at + 4:at + 8]), int.from_bytes(view[at:at + 4], "big")
        if at + 8 + length > len(view):  # its data; a missing checksum is Pillow's to judge
            raise LoadError(source, f"a broken PNG: its chunk at byte {at} says it holds {length} bytes, past the "
                                    f"file's end ({len(view)} bytes)")
        chunks += kind not in (b"IDAT", b"fdAT")
        if chunks > MAX_HEADER_PARTS:
            raise LoadError(source, f"more than {MAX_HEADER_PARTS} chunks besides its pixels: no PNG holds so many")
        if kind == b"IEND":
            break
        at += 12 + length


class _HeaderRefused(SyntaxError):
    """A picture refused by check_picture_header or check_picture_size inside Pillow: SyntaxError, so that
    Pillow goes on as it does for a file not of that format, and its message noted where
    pictures_checked() asked."""


_checked = threading.local()  # .refusals: the messages of the innermost pictures_checked() of this thread
_installed: dict[str, tuple[Callable, Callable | None]] = {}  # Pillow's own openers while ours stand in
_installed_open: list[Callable] = []  # Pillow's own Image.open while ours stands in
_installed_by = [0]  # how many pictures_checked() blocks are open, in all threads
_install_lock = threading.Lock()


@contextlib.contextmanager
def pictures_checked() -> Iterator[list[str]]:
    """While the block runs, Pillow's openers of the common formats (JPEG, PNG, PPM, BMP, GIF) check a
    picture's header first (check_picture_header) and its size once read (check_picture_size), before
    Pillow's own guard warns, wherever Pillow is asked to open one: by marraztu, or by trimesh for the
    pictures a glTF holds. What they refused is listed, and a picture Pillow cannot open at all
    (trimesh drops a picture it cannot open, in no words)."""
    refusals: list[str] = []
    outer, _checked.refusals = getattr(_checked, "refusals", None), refusals
    with _install_lock:
        if not _installed_by[0]:
            Image.preinit()
            for kind, (factory, accept) in list(Image.OPEN.items()):
                _installed[kind] = (factory, accept)
                Image.OPEN[kind] = (_checking(factory), accept)
            _installed_open.append(Image.open)
            Image.open = _noting_failures(Image.open)
        _installed_by[0] += 1
    try:
        yield refusals
    finally:
        with _install_lock:
            _installed_by[0] -= 1
            if not _installed_by[0]:
                Image.OPEN.update(_installed)
                _installed.clear()
                Image.open = _installed_open.pop()
        _checked.refusals = outer


def _checking(factory: Callable) -> Callable:
    def open_checked(fp: BinaryIO, filename: str | bytes | None = None) -> Image.Image:
        start = fp.tell()
        data = fp.read()
        fp.seek(start)
        try:
            check_picture_header("picture", data)
        except LoadError as error:
            raise _refused(error) from None
        finally:
            del data
        image = factory(fp, filename)
        try:
            check_picture_size("picture", *image.size)
        except LoadError as error:
            raise _refused(error) from None
        return image
    return open_checked


def _noting_failures(open_: Callable) -> Callable:
    """Pillow's Image.open, a picture it cannot open listed, as a refusal, with why."""
    def open_noted(fp: BinaryIO | str | Path, *args: object, **options: object) -> Image.Image:
        try:
            return open_(fp, *args, **options)
        except Exception as error:
            if getattr(_checked, "refusals", None) is not None:
                _checked.refusals.append(unreadable(error, _head_of(fp)))
            raise
    return open_noted


def _head_of(stream: object) -> bytes:
    """The first bytes of a stream Pillow was handed and left open, enough to tell a Git LFS pointer; none of
    a file name."""
    try:
        at = stream.tell()  # type: ignore[attr-defined]
        stream.seek(0)  # type: ignore[attr-defined]
        head = stream.read(GIT_LFS_POINTER_BYTES)  # type: ignore[attr-defined]
        stream.seek(at)  # type: ignore[attr-defined]
    except (AttributeError, OSError, ValueError):
        return b""
    return head if isinstance(head, bytes) else b""


# Pillow's words for a picture whose file ends too soon (in its header, or its image data), and the end of
# its words for a decoder's failure ("broken data stream when reading image file").
_PILLOW_CUT_SHORT = ("image file is truncated", "Truncated File Read")
_PILLOW_DECODER_FAILED = (" when reading image file",)
_PILLOW_NO_DATA = "cannot load this image"


def unreadable(error: Exception, head: bytes) -> str:
    """Why Pillow could not open or decode a picture of these first bytes, in our words where its own
    speak of its workings (its object's repr, a decoder's status, bytes not processed); else its own."""
    kind = image_format(head)
    if isinstance(error, Image.UnidentifiedImageError):
        if kind is None:
            return not_a_picture(head)
        return f"a broken {kind}: Pillow cannot read its header"
    ours = None if kind is None else _broken_data(error)
    return f"a broken {kind}: {ours}" if ours else f"not a readable image ({type(error).__name__}: {error})"


def _broken_data(error: Exception) -> str | None:
    """What is wrong with a known picture's data, in our words, where Pillow's say it; else None."""
    said = str(error)
    if isinstance(error, OSError) and said.startswith(_PILLOW_CUT_SHORT):
        return "its image data is cut short"
    if isinstance(error, SyntaxError) or (isinstance(error, OSError) and said.endswith(_PILLOW_DECODER_FAILED)
                                          and "memory" not in said):  # SyntaxError: a PNG chunk read as it decodes
        return "its image data is damaged"
    if isinstance(error, OSError) and said == _PILLOW_NO_DATA:
        return "Pillow finds no image data in it"
    return None


def _refused(error: LoadError) -> _HeaderRefused:
    """The refusal Pillow takes for "not this format", its message listed where pictures_checked() asks."""
    if getattr(_checked, "refusals", None) is not None:
        _checked.refusals.append(error.message)
    return _HeaderRefused(error.message)


def _load_with_pillow(file: Path, kind: str) -> np.ndarray:
    with file.open("rb") as stream, _opened(file, stream, kind) as image:  # a stream: its head for a message
        image.load()
        return rgb_array(image)


@contextlib.contextmanager
def _opened(source: str | Path, file: BinaryIO, kind: str) -> Iterator[Image.Image]:
    """The picture as Pillow opens it, of `kind` only, its header and size checked and its pixels not yet
    decoded; what goes wrong, then or while the block decodes it, a LoadError naming `source`."""
    try:
        with warnings.catch_warnings(), pictures_checked() as refusals:
            warnings.simplefilter("error", Image.DecompressionBombWarning)
            try:
                image = Image.open(file, formats=[kind])
            except Image.UnidentifiedImageError as error:  # refused by a check, or not identified: listed
                raise LoadError(source, refusals[0] if refusals else unreadable(error, _head_of(file))) from None
            with image:
                check_picture_size(source, *image.size)
                yield image
    except LoadError:
        raise
    except (Image.DecompressionBombError, Image.DecompressionBombWarning):
        raise LoadError(source, "image is too large (Pillow's decompression-bomb guard)") from None
    except Exception as error:  # Pillow raises OSError, ValueError, SyntaxError, EOFError, ... for bad files
        raise LoadError(source, unreadable(error, _head_of(file))) from None


def picture_rgb(picture: object) -> np.ndarray:
    """(H, W, 3) uint8 of a picture handed over in code (the API's texture, a trimesh material's): a
    Pillow image read as a file of its mode is (16-bit grey scaled), an array, or an image of floats or
    32-bit integers made in code, checked as colours are (bytes, or floats in 0..1). ValueError saying
    why it cannot be drawn."""
    refusal = picture_size_refusal(*picture_size(picture))
    if refusal is not None:  # before it is decoded or copied: a broadcast view may be endless
        raise ValueError(refusal)
    if not isinstance(picture, Image.Image):
        return picture_bytes(picture)
    if picture.mode in ("F", "I") and picture.format is None:  # numbers made in code: no file says their range
        return picture_bytes(np.asarray(picture))
    try:
        return rgb_array(picture)
    except ValueError:  # a mode Pillow converts to nothing else (La)
        raise ValueError(f"a picture in Pillow's mode {picture.mode} cannot be drawn: give it in RGB") from None


def picture_size(picture: object) -> tuple[int, int]:
    """(width, height) of a Pillow image, or of an array's first two axes; (0, 0) where it has none (its
    check says what is wrong)."""
    if isinstance(picture, Image.Image):
        return picture.size
    try:
        shape = np.shape(picture)  # an array's own, no copy
    except ValueError:  # ragged rows
        return 0, 0
    return (int(shape[1]), int(shape[0])) if len(shape) >= 2 else (0, 0)


def rgb_array(image: Image.Image) -> np.ndarray:
    """RGB uint8; wide grey modes are scaled, not clipped as Pillow's convert('RGB') would."""
    if image.mode.startswith("I") or image.mode == "F":
        values = np.asarray(image)
        if values.dtype.kind == "u" and values.dtype.itemsize == 2:  # 16-bit grey: by table, 1 byte a pixel
            grey = _through_table(values, _scale_table(1 << 16, 65535))  # no value lies halfway: same rounding
        else:
            scaled = np.nan_to_num(values.astype(np.float64)) * (255.0 / 65535.0)
            grey = np.clip(scaled, 0.0, 255.0).round().astype(np.uint8)
        return np.ascontiguousarray(np.repeat(grey[..., None], 3, axis=2))
    return _rgb_in_bands(image)


_BAND_BYTES = 1 << 20


def _rgb_in_bands(image: Image.Image) -> np.ndarray:
    """RGB uint8, a band of rows at a time: converting the whole picture, then numpy's tobytes(), made
    a 4-byte-a-pixel copy and two 3-byte ones, each the picture's size."""
    width, height = image.size
    out = np.empty((height, width, 3), np.uint8)
    rows = max(1, _BAND_BYTES // (4 * max(width, 1)))  # a picture 0 wide has rows, and no bytes in them
    for top in range(0, height, rows):
        band = image.crop((0, top, width, min(top + rows, height)))
        band.info.pop("transparency", None)  # dropped as alpha is; Pillow warns on stderr for a palette's
        out[top:top + rows] = np.asarray(band if band.mode == "RGB" else band.convert("RGB"), dtype=np.uint8)
    return out


def unread_textures_note(failures: Sequence[tuple[str, str]]) -> list[str]:
    """One note of the textures a model names that could not be read, (name, why) each: their faces
    show the scene's texture."""
    if not failures:
        return []
    (name, why), more = failures[0], len(failures) - 1
    if not more:
        said = f"texture '{shown(name)}' could not be read ({why}); the scene's texture is shown in its place"
    else:
        said = (f"{more + 1} textures could not be read (the first, '{shown(name)}': {why}); the scene's texture "
                "is shown in their place")
    return [escaped(said)]
