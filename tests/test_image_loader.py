"""Texture images: our PPM reader (P6, P3), Pillow for the rest, and the built-in fallback."""

from __future__ import annotations

import io
import random
import re
import tracemalloc
import warnings
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from marraztu.errors import LoadError
from marraztu.loaders.images import (
    MAX_JPEG_SCANS,
    MAX_PIXELS,
    check_picture,
    check_picture_header,
    fallback_texture,
    load_image,
    load_texture_or_fallback,
    parse_ppm,
)
from marraztu.loaders.patterns import POSSESSIVE_GROUPS_HOLD
from support.corpus import git_lfs_pointer, jpeg_of_scans, png_bytes
from support.refusals import one_line_refusal

# 2 x 2: red, green / blue, white. Rows top first, as in the file.
PIXELS = np.array([[[255, 0, 0], [0, 255, 0]], [[0, 0, 255], [255, 255, 255]]], dtype=np.uint8)


def write(tmp_path: Path, name: str, data: bytes) -> Path:
    path = tmp_path / name
    path.write_bytes(data)
    return path


def p3_text(pixels: np.ndarray, maxval: int = 255) -> bytes:
    height, width, _ = pixels.shape
    body = " ".join(str(value) for value in pixels.ravel())
    return f"P3\n{width} {height}\n{maxval}\n{body}\n".encode()


# --- PPM ------------------------------------------------------------------------------------------------


def test_p6_rows_top_first(tmp_path: Path) -> None:
    image = load_image(write(tmp_path, "a.ppm", b"P6\n2 2\n255\n" + PIXELS.tobytes()))
    assert image.dtype == np.uint8 and image.shape == (2, 2, 3)
    np.testing.assert_array_equal(image, PIXELS)


def test_p3(tmp_path: Path) -> None:
    np.testing.assert_array_equal(load_image(write(tmp_path, "a.ppm", p3_text(PIXELS))), PIXELS)


def test_p3_with_small_maxval_is_scaled() -> None:
    image = parse_ppm(b"P3 1 1 15\n15 0 7\n", "a.ppm")
    np.testing.assert_array_equal(image, [[[255, 0, 119]]])  # 7 * 255 / 15 = 119


def test_p6_16_bit_big_endian_is_scaled() -> None:
    samples = np.array([65535, 0, 32768], dtype=">u2").tobytes()
    np.testing.assert_array_equal(parse_ppm(b"P6 1 1 65535\n" + samples, "a.ppm"), [[[255, 0, 128]]])


def test_p6_with_maxval_1000() -> None:
    samples = np.array([1000, 500, 0], dtype=">u2").tobytes()
    np.testing.assert_array_equal(parse_ppm(b"P6 1 1 1000\n" + samples, "a.ppm"), [[[255, 128, 0]]])


def test_header_comments_and_any_whitespace() -> None:
    header = b"P6# right after the magic\n\t2 # width\r\n#a whole line\n 2\n255# after maxval\n"
    np.testing.assert_array_equal(parse_ppm(header + PIXELS.tobytes(), "a.ppm"), PIXELS)


def test_p3_comments_in_the_pixel_data() -> None:
    text = b"P3\n1 1\n255\n# red\n255 0 # no green\n0\n"
    np.testing.assert_array_equal(parse_ppm(text, "a.ppm"), [[[255, 0, 0]]])


def test_extra_data_after_the_raster_is_ignored() -> None:
    np.testing.assert_array_equal(parse_ppm(b"P6 2 2 255\n" + PIXELS.tobytes() + b"junk", "a.ppm"), PIXELS)


def test_binary_raster_may_start_with_whitespace_bytes() -> None:
    pixel = bytes([10, 32, 35])  # '\n', ' ', '#' are pixel values here, not header
    np.testing.assert_array_equal(parse_ppm(b"P6 1 1 255\n" + pixel, "a.ppm"), [[[10, 32, 35]]])


PPM_ERRORS = [
    ("wrong magic", b"P7\n1 1\n255\n\0\0\0", "expected P6 or P3"),
    ("no width", b"P6\n", "no width"),
    ("no maxval", b"P6 1 1", "no maxval"),
    ("letters in header", b"P6 a 1 255\n\0\0\0", "not a whole number"),
    ("negative size", b"P6 -1 1 255\n\0\0\0", "not a whole number"),
    ("long word in header", b"P6 1 " + b"h" * 50 + b" 255\n\0\0\0",
     "height b'" + "h" * 40 + "'... (50 bytes) is not a whole number"),
    ("zero width", b"P6 0 1 255\n", "at least 1"),
    ("zero height", b"P3 1 0 255\n", "at least 1"),
    ("absurd size", b"P6 100000 100000 255\n\0\0\0", "too large"),
    ("absurd digits", b"P6 99999999999999999999 1 255\n", "too large"),
    ("maxval zero", b"P6 1 1 0\n\0\0\0", "maxval 0"),
    ("maxval too big", b"P6 1 1 70000\n\0\0\0", "maxval 70000"),
    ("no raster", b"P6 1 1 255", "no pixel data"),
    ("truncated p6", b"P6 2 2 255\n" + bytes(11), "12 bytes of pixel data expected, found 11"),
    ("truncated 16 bit", b"P6 1 1 65535\n" + bytes(5), "6 bytes"),
    ("truncated p3", b"P3 1 1 255\n1 2\n", "3 samples expected"),
    ("p3 above maxval", b"P3 1 1 15\n1 2 16\n", "exceeds maxval 15"),
    ("p6 above maxval", b"P6 1 1 100\n\x01\x65\x02", "exceeds maxval 100"),
    ("p3 not a number", b"P3 1 1 255\n1 x 2\n", "not part of a number"),
    ("p3 negative", b"P3 1 1 255\n1 -2 3\n", "not part of a number"),
    ("p3 huge value", b"P3 1 1 255\n1 99999999999999999999999 3\n", "exceeds maxval"),
]


@pytest.mark.parametrize(("data", "line"), [
    (b"P3\n2 1\n255\n1 2 3\n4 x 6\n", 5),
    (b"P3\r\n2 1\r\n255\r\n1 2 3\r\n4 -5 6\r\n", 5),  # the header's last CR and its LF end one line
    (b"P3\r2 1\r255\r1 2 3\r4 5 6z\r", 5),
    (b"P3 2 1 255\n# x is no word here\n1 2 3 # nor here\n\n4 5 6.\n", 5),
    (b"P3 1 1 255 x 2 3\n", 1),
])
def test_bad_p3_pixel_data_names_the_line_of_its_first_bad_word(data: bytes, line: int) -> None:
    with pytest.raises(LoadError, match="bad P3 pixel data") as caught:
        parse_ppm(data, "a.ppm")
    assert caught.value.line == line and str(caught.value).startswith(f"a.ppm:{line}: "), str(caught.value)


@pytest.mark.parametrize(("data", "line", "value"), [
    (b"P3\n2 1\n255\n1 2 3\n4 256 6\n", 5, 256),
    (b"P3\r\n2 1\r\n15\r\n1 2 3 # 99\r\n\r\n 4 5 16 17\r\n", 6, 16),  # the first, past a comment's number
    (b"P3\r2 1\r255\r1 2 3\r4 5 999\r", 5, 999),
    (b"P3 1 1 255 1 99999999999999999999999 3\n", 1, np.iinfo(np.int64).max),
])
def test_a_p3_sample_past_maxval_names_its_line(data: bytes, line: int, value: int) -> None:
    """It named no line, where P3's other bad pixel data did."""
    with pytest.raises(LoadError, match=f"a sample value \\({value}\\) exceeds maxval") as caught:
        parse_ppm(data, "a.ppm")
    assert caught.value.line == line and str(caught.value).startswith(f"a.ppm:{line}: "), str(caught.value)


@pytest.mark.parametrize("seed", range(6))
def test_a_p3_sample_past_maxval_is_found_across_the_pieces_it_is_looked_for_in(seed: int, monkeypatch) -> None:
    """The numbers are counted a few bytes at a time here: a number cut by a piece's end is one number."""
    from marraztu.loaders import images

    monkeypatch.setattr(images, "_NUMBER_PIECE_BYTES", 7)
    rng = random.Random(seed)
    lines, bad_line = [], 0
    for at in range(40):
        words = [str(rng.randrange(0, 1000 if at >= 20 else 100)) for _ in range(rng.randrange(1, 6))]
        if rng.random() < 0.2:
            words.append("# 999 " + str(rng.randrange(1000)))
        lines.append(" ".join(words))
        if not bad_line and any(int(word) > 99 for word in words if word.isdigit()):
            bad_line = at + 4  # after the three lines of the header
    width = sum(len(line.split("#")[0].split()) for line in lines) // 3
    data = f"P3\n{width} 1\n99\n".encode() + "\r\n".join(lines).encode()
    with pytest.raises(LoadError, match="exceeds maxval 99") as caught:
        parse_ppm(data, "a.ppm")
    assert caught.value.line == bad_line


@pytest.mark.parametrize(("data", "message"), [case[1:] for case in PPM_ERRORS], ids=[c[0] for c in PPM_ERRORS])
def test_bad_ppm_raises_load_error_naming_the_file(tmp_path: Path, data: bytes, message: str) -> None:
    path = write(tmp_path, "bad.ppm", data)
    with pytest.raises(LoadError) as caught:
        load_image(path)
    assert caught.value.path == str(path)
    assert message in caught.value.message


@pytest.mark.parametrize("data", [b"P6 8000 8000 255\n\0\0\0", b"P3 8000 8000 255\n1 2 3\n",
                                  b"P6 8000 8000 65535\n\0\0\0"], ids=["p6", "p3", "p6 16 bit"])
def test_a_huge_header_with_no_data_fails_fast_without_allocating(data: bytes) -> None:
    """("too large" headers are PPM_ERRORS' "absurd size".)"""
    tracemalloc.start()
    try:
        with pytest.raises(LoadError, match="truncated"):
            parse_ppm(data, "huge.ppm")
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < len(data) + (1 << 20), f"{peak} bytes traced for a {len(data)}-byte file"


def test_size_cap_is_the_documented_one() -> None:
    assert MAX_PIXELS == 64 * 1024 * 1024


# --- Pillow formats -------------------------------------------------------------------------------------


def test_png_round_trip(tmp_path: Path) -> None:
    path = tmp_path / "a.png"
    Image.fromarray(PIXELS).save(path)
    np.testing.assert_array_equal(load_image(path), PIXELS)


def test_jpeg_round_trip(tmp_path: Path) -> None:
    pixels = np.zeros((16, 16, 3), dtype=np.uint8)
    pixels[:8] = (200, 40, 40)  # top half red: the top row stays first
    path = tmp_path / "a.jpg"
    Image.fromarray(pixels).save(path, quality=95)
    image = load_image(path)
    assert image.shape == (16, 16, 3) and image.dtype == np.uint8
    # JPEG is lossy (and blurs colour at the edge): compare the halves.
    np.testing.assert_allclose(image[:6].reshape(-1, 3).mean(axis=0), (200, 40, 40), atol=8)
    np.testing.assert_allclose(image[10:].reshape(-1, 3).mean(axis=0), (0, 0, 0), atol=8)


@pytest.mark.parametrize("orientation", range(1, 9))
def test_a_jpeg_is_drawn_as_stored_whatever_its_exif_orientation(tmp_path: Path, orientation: int) -> None:
    """As Blender and game engines draw a texture, so that UVs made there fit (the README says so)."""
    exif = Image.Exif()
    exif[0x0112] = orientation
    stored = np.kron(PIXELS[:, :1], np.ones((16, 8, 1), dtype=np.uint8))  # 8 wide, 32 high: red over blue
    Image.fromarray(stored).save(tmp_path / "phone.jpg", quality=95, subsampling=0, exif=exif)
    image = load_image(tmp_path / "phone.jpg")
    assert image.shape == stored.shape and np.abs(image.astype(int) - stored).max() < 20


def test_a_jpeg_with_exif_a_comment_and_a_large_colour_profile_loads(tmp_path: Path) -> None:
    """A profile of 1 MB goes in 16 APP2 segments: a photo's header holds tens of segments."""
    exif = Image.Exif()
    exif[0x010F] = "camera"
    path = tmp_path / "photo.jpg"
    Image.new("RGB", (16, 8), (200, 30, 30)).save(path, "JPEG", exif=exif, icc_profile=bytes(1 << 20),
                                                   comment=b"made here", progressive=True)
    assert load_image(path).shape == (8, 16, 3)


@pytest.mark.parametrize(("stray", "segment"), [(b"", b"\xff\xef\x00\x02"), (b"\xff", b"\xff\xef\x00\x02"),
                                               (b"\x00", b"\xff\xef\x00\x02"), (b"\xff\x00", b"\xff\xef\x00\x02"),
                                               (b"", b"\xff\xef\x00\x00")])
def test_a_jpeg_header_of_a_million_segments_is_refused_before_pillow_keeps_them(tmp_path: Path, stray: bytes,
                                                                                segment: bytes) -> None:
    """Pillow kept every empty APP segment in a list, about 33 bytes for each byte of the file; a fill
    byte, a stray byte or an escaped 0xFF, which Pillow skips, must not end the walk before them, nor a
    segment whose length is less than its own two bytes, which Pillow reads as empty."""
    plain = tmp_path / "plain.jpg"
    Image.new("RGB", (8, 8), (200, 30, 30)).save(plain, "JPEG")
    data = plain.read_bytes()
    path = tmp_path / "many.jpg"
    path.write_bytes(data[:2] + b"\xff\xef\x00\x02" + stray + segment * 1_000_000 + data[2:])
    tracemalloc.start()
    try:
        with pytest.raises(LoadError, match="more than 4096 markers and stray bytes before the picture"):
            load_image(path)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 3 * path.stat().st_size, peak  # the file read once to walk it
    path.write_bytes(data[:2] + b"\xff\xef\x00\x02" + stray + segment * 4000 + data[2:])
    assert load_image(path).shape == (8, 8, 3)


def test_a_jpeg_cut_off_in_stray_bytes_is_pillows_to_refuse(tmp_path: Path) -> None:
    """Stray bytes up to the end are counted as far as they go, not as a run past the limit."""
    path = tmp_path / "cut.jpg"
    path.write_bytes(b"\xff\xd8\xff\xe0\x00\x04ab" + b"\x00" * 100)
    with pytest.raises(LoadError) as refused:
        load_image(path)
    assert refused.value.message == "a broken JPEG: Pillow cannot read its header"


@pytest.mark.parametrize("kind", [b"tEXt", b"iTXt", b"prVt"])
def test_a_png_of_a_million_text_or_private_chunks_is_refused_before_pillow_keeps_them(tmp_path: Path,
                                                                                     kind: bytes) -> None:
    """Pillow kept each text and private chunk: an iTXt flood took 31 bytes for each byte of the file."""
    import zlib

    plain = tmp_path / "plain.png"
    Image.new("RGB", (8, 8), (200, 30, 30)).save(plain, "PNG")
    data = plain.read_bytes()
    body = b"k%d\0" if kind == b"tEXt" else b"k%d\0\0\0\0\0" if kind == b"iTXt" else b"%d"

    def chunk(number: int) -> bytes:
        payload = body % number
        return len(payload).to_bytes(4, "big") + kind + payload + zlib.crc32(kind + payload).to_bytes(4, "big")

    header_end = 8 + 25  # the signature and IHDR
    path = tmp_path / "many.png"
    path.write_bytes(data[:header_end] + b"".join(chunk(number) for number in range(300_000)) + data[header_end:])
    with pytest.raises(LoadError, match="more than 4096 chunks besides its pixels"):
        load_image(path)
    path.write_bytes(data[:header_end] + b"".join(chunk(number) for number in range(100)) + data[header_end:])
    assert load_image(path).shape == (8, 8, 3)


def test_a_png_chunk_longer_than_the_file_is_refused_before_pillow_asks_for_it(tmp_path: Path) -> None:
    """Pillow read an IDAT's whole length at once: 4 GiB asked for by a 77-byte file (a MemoryError
    under a memory limit). A chunk cut short by the file's end, a checksum missing, is Pillow's still."""
    plain = tmp_path / "plain.png"
    Image.new("RGB", (5, 3), (200, 30, 30)).save(plain, "PNG")
    data = plain.read_bytes()
    idat = data.index(b"IDAT") - 4
    path = tmp_path / "long.png"
    path.write_bytes(data[:idat] + b"\xff\xff\xff\xff" + data[idat + 4:])
    with pytest.raises(LoadError) as refused:
        load_image(path)
    assert refused.value.message == (f"a broken PNG: its chunk at byte {idat} says it holds 4294967295 bytes, past "
                                     f"the file's end ({len(data)} bytes)")
    path.write_bytes(data[:-4])  # IEND's checksum left out
    assert load_image(path).shape == (3, 5, 3)


def test_a_jpeg_of_more_scans_than_encoders_write_is_refused_before_it_is_decoded(tmp_path: Path) -> None:
    """Each scan of a progressive JPEG is decoded over the whole picture: 2,006 scans of a few bytes each
    made 507 KB that took 95 s to load."""
    with pytest.raises(LoadError) as caught:
        load_image(write(tmp_path, "scans.jpg", jpeg_of_scans(MAX_JPEG_SCANS + 1)))
    assert caught.value.message == (f"more than {MAX_JPEG_SCANS} scans, each decoded over the whole picture: a "
                                    "progressive JPEG has about 10")
    assert load_image(write(tmp_path, "ten.jpg", jpeg_of_scans(10))).shape == (16, 16, 3)


def test_the_scans_are_counted_up_to_the_bound() -> None:
    check_picture_header("a.jpg", jpeg_of_scans(MAX_JPEG_SCANS))
    with pytest.raises(LoadError, match="scans"):
        check_picture_header("a.jpg", jpeg_of_scans(MAX_JPEG_SCANS + 1))


def test_a_picture_claiming_more_pixels_than_the_cap_is_refused_as_such_and_quietly(tmp_path: Path) -> None:
    """A PNG header claiming 13000 x 13000 pixels: refused by the cap, in the cap's words, before Pillow's
    own guard warns of it."""
    path = write(tmp_path, "big.png", png_bytes(2, 2, claimed=(13000, 13000)))
    with warnings.catch_warnings(record=True) as heard:
        warnings.simplefilter("always")
        with pytest.raises(LoadError) as caught:
            load_image(path)
    assert caught.value.message == f"image size 13000x13000 is too large (at most {MAX_PIXELS} pixels)"
    assert [str(item.message) for item in heard] == []


def test_pillows_own_openers_stand_again_once_pictures_are_opened(tmp_path: Path) -> None:
    """marraztu's checking openers stand in for Pillow's only while it opens pictures, however many
    threads do at once: a program that uses Pillow beside it gets Pillow's own after."""
    from concurrent.futures import ThreadPoolExecutor

    Image.preinit()
    own, opens = dict(Image.OPEN), Image.open  # every format's: each checks a picture's size while pictures are opened
    Image.new("RGB", (8, 8), (200, 30, 30)).save(tmp_path / "a.jpg", "JPEG")
    Image.new("RGB", (8, 8), (200, 30, 30)).save(tmp_path / "a.png", "PNG")
    with ThreadPoolExecutor(4) as pool:
        shapes = list(pool.map(lambda name: load_image(tmp_path / name).shape, ["a.jpg", "a.png"] * 20))
    assert shapes == [(8, 8, 3)] * 40
    assert {kind: Image.OPEN[kind] for kind in own} == own and Image.open is opens


@pytest.mark.parametrize(("data", "why"), [
    (b"\x89PNG\r\n\x1a\n" + b"\0" * 30, "a broken PNG: Pillow cannot read its header"),
    (b"\xff\xd8\xff" + b"\0" * 30, "a broken JPEG: Pillow cannot read its header"),
])
def test_a_picture_pillow_cannot_identify_is_named_without_pillows_object(tmp_path: Path, data: bytes,
                                                                          why: str) -> None:
    """Pillow says 'cannot identify image file <_io.BytesIO object at 0x...>' of what it was handed."""
    for check in (lambda: load_image(write(tmp_path, "broken.png", data)), lambda: check_picture("broken.png", data)):
        with pytest.raises(LoadError) as refused:
            check()
        assert refused.value.message == why


def test_a_png_of_many_pixel_chunks_loads(tmp_path: Path) -> None:
    """Pixels in many IDAT chunks are no header: an encoder may cut them small."""
    import zlib

    pixels = np.random.default_rng(1).integers(0, 256, size=(64, 64, 3), dtype=np.uint8)
    Image.fromarray(pixels).save(tmp_path / "one.png", "PNG")
    data = (tmp_path / "one.png").read_bytes()
    at, stream, rest = 8, b"", []
    while at < len(data):  # the compressed pixels gathered from the IDAT chunks, every other chunk kept
        length, kind = int.from_bytes(data[at:at + 4], "big"), data[at + 4:at + 8]
        if kind == b"IDAT":
            stream += data[at + 8:at + 8 + length]
        else:
            rest.append(data[at:at + 12 + length])
        at += 12 + length
    pieces = [stream[start:start + 2] for start in range(0, len(stream), 2)]
    idat = b"".join(len(piece).to_bytes(4, "big") + b"IDAT" + piece + zlib.crc32(b"IDAT" + piece).to_bytes(4, "big")
                    for piece in pieces)
    path = tmp_path / "chunked.png"
    path.write_bytes(data[:8] + b"".join(rest[:-1]) + idat + rest[-1])  # ... IDAT x many, IEND
    assert len(pieces) > 4096
    np.testing.assert_array_equal(load_image(path), pixels)


def test_rgba_grey_and_palette_become_rgb(tmp_path: Path) -> None:
    rgba = np.dstack([PIXELS, np.full((2, 2), 7, dtype=np.uint8)])
    Image.fromarray(rgba).save(tmp_path / "rgba.png")
    np.testing.assert_array_equal(load_image(tmp_path / "rgba.png"), PIXELS)
    Image.fromarray(np.array([[0, 128]], dtype=np.uint8)).save(tmp_path / "grey.png")
    np.testing.assert_array_equal(load_image(tmp_path / "grey.png"), [[[0, 0, 0], [128, 128, 128]]])
    Image.fromarray(PIXELS).convert("P").save(tmp_path / "palette.png")
    np.testing.assert_array_equal(load_image(tmp_path / "palette.png"), PIXELS)


def test_16_bit_grey_png_is_scaled_not_clipped(tmp_path: Path) -> None:
    Image.fromarray(np.array([[0, 32896, 65535]], dtype=np.uint16)).save(tmp_path / "deep.png")
    np.testing.assert_array_equal(load_image(tmp_path / "deep.png")[0, :, 0], [0, 128, 255])


def test_grey_pnm_is_refused_as_not_a_ppm(tmp_path: Path) -> None:
    with pytest.raises(LoadError, match="P6 or P3"):
        load_image(write(tmp_path, "grey.pgm", b"P5 2 1 255\n\x00\xff"))


# --- only PPM, PNG and JPEG, chosen by content ------------------------------------------------------
EPS_LOOP = b"%!PS-Adobe-3.0 EPSF-3.0\n%%BoundingBox: 0 0 10 10\n{ } loop\nshowpage\n"
EPS_WRITES = b"%!PS-Adobe-3.0 EPSF-3.0\n%%BoundingBox: 0 0 10 10\n(/tmp/pwned) (w) file closefile\nshowpage\n"


def other_format(kind: str) -> bytes:
    """A valid picture in a format marraztu does not read."""
    from io import BytesIO

    out = BytesIO()
    Image.fromarray(PIXELS).save(out, format=kind)
    return out.getvalue()


@pytest.mark.parametrize("content", [EPS_LOOP, EPS_WRITES], ids=["loops forever", "writes a file"])
@pytest.mark.parametrize("name", ["loop.png", "loop.jpg", "loop.ppm", "loop"])
def test_postscript_is_refused_by_its_content_and_never_runs_anything(tmp_path: Path, monkeypatch,
                                                                     content: bytes, name: str) -> None:
    import subprocess

    def no_child(*args, **kwargs):
        raise AssertionError("a texture must never start another program")

    monkeypatch.setattr(subprocess, "Popen", no_child)
    with pytest.raises(LoadError, match="PNG, JPEG or PPM|expected P6 or P3"):
        load_image(write(tmp_path, name, content))


@pytest.mark.parametrize("kind", ["GIF", "BMP", "TIFF", "WEBP", "ICO", "TGA"])
def test_other_pillow_formats_are_refused_whatever_their_name(tmp_path: Path, kind: str) -> None:
    for name in ("disguised.png", "disguised.jpg", f"honest.{kind.lower()}"):
        with pytest.raises(LoadError, match="PNG, JPEG or PPM") as caught:
            load_image(write(tmp_path, name, other_format(kind)))
        assert caught.value.path.endswith(name) and "\n" not in str(caught.value)


def test_png_and_jpeg_are_read_by_content_whatever_their_name(tmp_path: Path) -> None:
    Image.fromarray(PIXELS).save(tmp_path / "real.png")
    np.testing.assert_array_equal(load_image(write(tmp_path, "named.jpg", (tmp_path / "real.png").read_bytes())),
                                  PIXELS)
    ppm = b"P6\n2 2\n255\n" + PIXELS.tobytes()
    np.testing.assert_array_equal(load_image(write(tmp_path, "named.png", ppm)), PIXELS)


@pytest.mark.parametrize(("name", "data"), [
    ("garbage.png", b"\x89PNG\r\n\x1a\nnot really"),
    ("empty.jpg", b""),
    ("text.png", b"hello"),
])
def test_broken_images_raise_load_error(tmp_path: Path, name: str, data: bytes) -> None:
    path = write(tmp_path, name, data)
    with pytest.raises(LoadError) as caught:
        load_image(path)
    assert caught.value.path == str(path)


def test_truncated_png(tmp_path: Path) -> None:
    path = tmp_path / "cut.png"
    Image.fromarray(np.random.default_rng(1).integers(0, 255, (64, 64, 3), dtype=np.uint8)).save(path)
    path.write_bytes(path.read_bytes()[:200])
    with pytest.raises(LoadError):
        load_image(path)


# What a PNG or JPEG cut short or damaged is refused as, in our words: Pillow's ("broken data stream when
# reading image file", "image file is truncated (2 bytes not processed)", "Truncated File Read") are not shown.
OUR_BROKEN_PICTURE = re.compile(r"a broken (PNG|JPEG): (its image data is (cut short|damaged)|Pillow finds no image "
                                r"data in it|Pillow cannot read its header|its chunk at byte \d+ says it holds \d+ "
                                r"bytes, past the file's end \(\d+ bytes\))")


@pytest.mark.parametrize("kind", ["PNG", "JPEG"])
def test_a_picture_cut_short_or_damaged_is_refused_in_our_words(tmp_path: Path, kind: str) -> None:
    rng = random.Random(f"broken {kind}")
    stored = io.BytesIO()
    Image.fromarray(np.random.default_rng(3).integers(0, 255, (48, 64, 3), dtype=np.uint8)).save(stored, kind)
    data, said = stored.getvalue(), set()
    for attempt in range(120):
        broken = bytearray(data[:rng.randrange(8, len(data))] if attempt % 2 else data)
        for _ in range(0 if attempt % 2 else rng.randrange(1, 4)):
            broken[rng.randrange(8, len(broken))] ^= 1 << rng.randrange(8)
        path = write(tmp_path, f"broken.{kind.lower()}", bytes(broken))
        try:
            load_image(path)
        except LoadError as refused:
            assert refused.path == str(path) and OUR_BROKEN_PICTURE.fullmatch(refused.message), refused.message
            said.add(refused.message.split(": ", 1)[1])
    assert "its image data is damaged" in said and (kind == "PNG" or "its image data is cut short" in said)


def test_a_png_whose_pixels_end_early_is_refused_as_cut_short(tmp_path: Path) -> None:
    """Its chunks whole (half the pixels' zlib stream, then IEND): Pillow said "image file is truncated"."""
    import zlib

    pixels = np.random.default_rng(3).integers(0, 255, (48, 64, 3), dtype=np.uint8)
    stream = zlib.compress(b"".join(b"\0" + row.tobytes() for row in pixels))
    data = png_bytes(64, 48)
    idat = data.index(b"IDAT") - 4
    pixels_chunk = len(stream[:len(stream) // 2]).to_bytes(4, "big") + b"IDAT" + stream[:len(stream) // 2]
    pixels_chunk += zlib.crc32(pixels_chunk[4:]).to_bytes(4, "big")
    path = write(tmp_path, "half.png", data[:idat] + pixels_chunk + data[-12:])  # IEND
    assert one_line_refusal(lambda: load_image(path)).message == "a broken PNG: its image data is cut short"


def test_missing_file_directory_and_device(tmp_path: Path) -> None:
    with pytest.raises(LoadError, match="no such file"):
        load_image(tmp_path / "selfi.ppm")
    with pytest.raises(LoadError, match="directory"):
        load_image(tmp_path)
    if Path("/dev/zero").exists():
        with pytest.raises(LoadError, match="not a regular file"):
            load_image("/dev/zero")


# --- the fallback ---------------------------------------------------------------------------------------


def test_fallback_texture_is_a_checker_with_a_marked_top_left_corner() -> None:
    texture = fallback_texture()
    assert texture.dtype == np.uint8 and texture.ndim == 3 and texture.shape[2] == 3
    height, width, _ = texture.shape
    corners = [tuple(texture[0, 0]), tuple(texture[0, -1]), tuple(texture[-1, 0]), tuple(texture[-1, -1])]
    assert len(set(corners)) >= 3  # flips and mirrors show
    assert corners[0] not in corners[1:]
    assert len({tuple(pixel) for pixel in texture[height // 2]}) >= 2  # a checker, not a flat colour


def test_load_texture_or_fallback(tmp_path: Path) -> None:
    good = write(tmp_path, "good.ppm", b"P6 2 2 255\n" + PIXELS.tobytes())
    image, message = load_texture_or_fallback(good)
    np.testing.assert_array_equal(image, PIXELS)
    assert message is None
    image, message = load_texture_or_fallback(tmp_path / "selfi.ppm")
    np.testing.assert_array_equal(image, fallback_texture())
    assert message is not None and "selfi.ppm" in message and "\n" not in message
    image, message = load_texture_or_fallback(None)
    np.testing.assert_array_equal(image, fallback_texture())
    assert message is None


def test_a_p6_raster_is_read_where_it_lies() -> None:
    """The pixels are read from the file's bytes where they lie: the image is the one copy made."""
    from support.work import peak_traced_bytes

    side = 512
    raster = np.random.default_rng(4).integers(0, 256, side * side * 3, dtype=np.uint8).tobytes()
    data = b"P6\n%d %d\n255\n" % (side, side) + raster
    image, peak = peak_traced_bytes(lambda: parse_ppm(data, "a.ppm"))
    assert image.tobytes() == raster
    assert peak < len(raster) * 3 // 2, peak


@pytest.mark.parametrize("gap", [b" ", b"#\n"])
def test_whitespace_and_comments_in_a_header_cost_their_length(gap: bytes) -> None:
    """The header's gaps are skipped without regex state per byte (it held 115 bytes a byte)."""
    from support.work import peak_traced_bytes

    data = b"P6" + gap * 500_000 + b"1 1 255\n\x01\x02\x03"
    image, peak = peak_traced_bytes(lambda: parse_ppm(data, "a.ppm"))
    assert image.tolist() == [[[1, 2, 3]]]
    if POSSESSIVE_GROUPS_HOLD:  # 3.11.0 to 3.11.4 skip the gaps with an atomic group, which keeps state per gap
        assert peak < len(data), peak


@pytest.mark.parametrize("line_end", [b"\n", b"\r"])
def test_comments_in_a_p3_raster_cost_their_length_and_read_as_spaces(monkeypatch: pytest.MonkeyPatch,
                                                                      line_end: bytes) -> None:
    """Comments become spaces a piece of lines at a time: every piece boundary gives what one
    substitution over the whole raster gives, and a raster of short comments holds a few copies of
    itself at most (one substitution held 87 bytes a byte)."""
    import random
    import re

    from marraztu.loaders import images
    from support.work import peak_traced_bytes

    rng = random.Random(6)
    raster = b"".join(rng.choice([b"1", b" ", b"#", b"\n", b"\r", b"x"]) for _ in range(5000))
    monkeypatch.setattr(images, "_COMMENT_PIECE_BYTES", 7)
    assert images._without_comments(raster) == re.sub(rb"#[^\n\r]*", b" ", raster)
    monkeypatch.undo()
    data = b"P3 1 1 255\n1 2 3\n" + (b"#" + line_end) * 500_000
    image, peak = peak_traced_bytes(lambda: parse_ppm(data, "a.ppm"))
    assert image.tolist() == [[[1, 2, 3]]]
    assert peak < 4 * len(data), peak


@pytest.mark.parametrize("maxval", [254, 1000, 65535])
def test_samples_are_scaled_by_table_within_a_bounded_memory(maxval: int) -> None:
    """A maxval other than 255 scales every sample, rounded, as (v * 255 + maxval // 2) // maxval
    does, through a table and a piece at a time: no wide copies of the raster."""
    from support.work import peak_traced_bytes

    side = 512
    wide = maxval > 255
    rng = np.random.default_rng(5)
    values = rng.integers(0, maxval + 1, side * side * 3).astype(">u2" if wide else np.uint8)
    data = b"P6 %d %d %d\n" % (side, side, maxval) + values.tobytes()
    image, peak = peak_traced_bytes(lambda: parse_ppm(data, "a.ppm"))
    expected = (values.astype(np.uint32) * 255 + maxval // 2) // maxval
    assert np.array_equal(image.reshape(-1), expected)
    assert peak < 3 * side * side * 3, peak  # the image, and the table's pieces


def test_16_bit_grey_is_scaled_by_table_as_the_formula_rounds(tmp_path: Path) -> None:
    from support.work import peak_traced_bytes

    values = np.arange(1 << 16, dtype=np.uint16).reshape(256, 256)
    Image.fromarray(values).save(tmp_path / "deep.png")
    image, peak = peak_traced_bytes(lambda: load_image(tmp_path / "deep.png"))
    expected = np.clip(values * (255.0 / 65535.0), 0, 255).round().astype(np.uint8)
    assert np.array_equal(image[..., 0], expected) and np.array_equal(image[..., 2], expected)
    assert peak < 16 * values.size, peak  # the picture, its indices and the RGB image: not floats (24 B a pixel)


@pytest.mark.parametrize("mode", ["RGB", "L"])
def test_a_picture_becomes_rgb_a_band_at_a_time(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, mode: str) -> None:
    """No whole-picture conversion (Pillow's own memory, which tracemalloc does not see) and no
    whole-picture bytes object (tobytes() joins its pieces: twice the picture's size)."""
    from support.work import peak_traced_bytes

    rows, columns = np.indices((1024, 2048))
    pixels = np.dstack([rows % 256, columns % 256, (rows + columns) % 256]).astype(np.uint8)
    picture = Image.fromarray(pixels).convert(mode)
    picture.save(tmp_path / "big.png")  # small: the header check reads the whole file
    expected = np.asarray(picture.convert("RGB"))
    converted: list[tuple[int, int]] = []
    convert = Image.Image.convert
    monkeypatch.setattr(Image.Image, "convert",
                        lambda self, *a, **k: converted.append(self.size) or convert(self, *a, **k))
    image, peak = peak_traced_bytes(lambda: load_image(tmp_path / "big.png"))
    np.testing.assert_array_equal(image, expected)
    assert all(width * height <= 2048 * 256 for width, height in converted), converted
    assert peak < 1.5 * image.nbytes, peak / image.nbytes


@pytest.mark.parametrize("size", [(0, 5), (5, 0), (0, 0)])
def test_a_picture_of_no_pixels_becomes_an_empty_rgb_array(size: tuple[int, int]) -> None:
    """No file makes one (Pillow refuses them), but rgb_array also takes pictures handed to it."""
    from marraztu.loaders.images import rgb_array

    assert rgb_array(Image.new("RGB", size)).shape == (size[1], size[0], 3)


def test_a_palette_png_with_alpha_per_entry_loads_without_pillows_warning(tmp_path: Path) -> None:
    """Paint programs and optimisers write such a tRNS; alpha is dropped, as an RGBA picture's is."""
    Image.fromarray(PIXELS).convert("P").save(tmp_path / "palette.png", transparency=bytes([0, 128, 255, 255]))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        np.testing.assert_array_equal(load_image(tmp_path / "palette.png"), PIXELS)


@pytest.mark.parametrize("before_frame", [b"", b"\xff", b"\x00"])
@pytest.mark.parametrize("bits", [12, 16])
def test_a_jpeg_of_more_than_8_bits_is_refused_as_such(tmp_path: Path, bits: int, before_frame: bytes) -> None:
    """Not "broken", as Pillow's words had it: a 12-bit JPEG (medical and some camera pictures) or a
    16-bit lossless one is sound, and Pillow reads 8-bit ones only. Its frame comes after an EXIF block,
    and a fill byte or a stray one, which Pillow's reader skips."""
    path = tmp_path / "deep.jpg"
    Image.fromarray(PIXELS).save(path, exif=Image.Exif())
    data = bytearray(path.read_bytes())
    frame = data.index(b"\xff\xc0")
    data[frame + 4] = bits  # the frame's sample precision
    data[frame:frame] = before_frame
    path.write_bytes(data)
    with pytest.raises(LoadError, match=rf"deep\.jpg: a {bits}-bit JPEG: Pillow reads 8-bit ones only$"):
        load_image(path)


@pytest.mark.parametrize("name", ["wood.png", "wood.jpg", "wood.ppm", "wood"])
def test_a_git_lfs_pointer_in_a_pictures_place_is_said_so(tmp_path: Path, name: str) -> None:
    """A clone without `git lfs pull` holds a small text in the picture's place: it was 'not a PNG, JPEG
    or PPM picture (it starts with b'version ')', and a .ppm 'not a PPM image: starts with b've'."""
    path = write(tmp_path, name, git_lfs_pointer(52114))
    assert one_line_refusal(lambda: load_image(path)).message == (
        "a Git LFS pointer, not the picture: its 52114 bytes are fetched by `git lfs pull`")
