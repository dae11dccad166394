"""Malformed inputs, made by code (nothing downloaded), and the measuring tools the tests use on them.

Every case is a `Case`: a file name, its bytes (or how to make a path that is not a plain file), and
the line a message must name where there is one. `write_case` puts it on disk. The lists:

* `bad_obj_cases`, `good_obj_cases`: Wavefront OBJ files that must fail / must load;
* `bad_image_cases`, `good_image_cases`: PPM (and a few PNG) textures;
* `bad_scene_cases`: TOML scene files (with the models they point at).

Random bytes come from seeded generators, so every run tries exactly the same files.
"""

from __future__ import annotations

import gc
import io
import os
import random
import struct
import weakref
import zlib
from collections import Counter
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import numpy as np
from PIL import Image

Kind = Literal["obj", "image", "scene"]
# How the path is made: a plain file with `content`, or one of the things that are not one.
Setup = Literal["file", "missing", "directory", "unreadable", "dangling_link", "link_loop"]

MEGABYTE = 1 << 20
SEED = 20240611


@dataclass(frozen=True)
class Case:
    id: str
    kind: Kind
    filename: str
    content: bytes = b""
    line: int | None = None  # the line a message must name (None: no line, or none to check)
    setup: Setup = "file"
    # Files written next to the case (a scene's models); (name, bytes) pairs.
    companions: tuple[tuple[str, bytes], ...] = field(default=())

    def __repr__(self) -> str:  # pytest shows ids; the bytes may be megabytes long
        return f"Case({self.kind}:{self.id})"


def write_case(case: Case, folder: Path) -> Path:
    """Makes the case's path under `folder` (its own sub-folder, so names never clash)."""
    home = folder / f"{case.kind}-{case.id}"
    home.mkdir(parents=True, exist_ok=True)
    for name, data in case.companions:
        (home / name).write_bytes(data)
    path = home / case.filename
    if case.setup == "file":
        path.write_bytes(case.content)
    elif case.setup == "directory":
        path.mkdir(exist_ok=True)
    elif case.setup == "unreadable":
        path.write_bytes(case.content)
        path.chmod(0)
    elif case.setup == "dangling_link":
        path.symlink_to(home / "nothing-here")
    elif case.setup == "link_loop":
        path.symlink_to(path)
    return path


def running_as_root() -> bool:
    """chmod 000 stops no one who runs as root: such cases are skipped, not passed."""
    return hasattr(os, "geteuid") and os.geteuid() == 0


# --------------------------------------------------------------------------------------------------
# OBJ
# --------------------------------------------------------------------------------------------------
TRIANGLE = b"v -40 -40 0\nv 40 -40 0\nv 0 40 0\n"  # three vertices, lines 1-3; the face goes on line 4
VALID_OBJ = (
    b"# a small valid model: the seed of the mutation tests\n"
    b"o square\n"
    b"v -30 -30 0\nv 30 -30 0\nv 30 30 0\nv -30 30 0\nv 0 0 25\n"
    b"vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
    b"vn 0 0 1\nvn 0 0 -1\n"
    b"g body\ns 1\n"
    b"f 1/1/1 2/2/1 3/3/1 4/4/1\n"
    b"f 1/1/2 2/2/2 5/5/2\n"
    b"f -4/-4/-1 -3/-3/-1 -1/-1/-1\n"
    b"f 3//1 4//1 5//1\n"
    b"f 4 1 5\n"
)

# Index text that cannot be a real index: 20 digits overflow int64, 5000 exceed Python's int() limit.
ABSURD_INDEX = b"99999999999999999999"
DIGITS_5000 = b"9" * 5000
MILLION = 1_000_000


def _noise(size: int, seed: int, forbid_nul: bool = False) -> bytes:
    rng = random.Random(seed)
    data = bytearray(rng.getrandbits(8) for _ in range(size))
    if forbid_nul:
        data = bytearray(byte or 1 for byte in data)
    return bytes(data)


def _face_line(face: bytes) -> bytes:
    return TRIANGLE + face + b"\n"


def _obj(case_id: str, content: bytes, line: int | None, filename: str = "") -> Case:
    return Case(case_id, "obj", filename or f"{case_id}.obj", content, line)


def bad_obj_cases() -> list[Case]:
    """OBJ files that must be refused, each with the line the message must name (None: no line)."""
    return [
        # nothing to draw
        _obj("empty", b"", None),
        _obj("blank_lines", b"\n\n   \n\t\n\r\n", None),
        _obj("comments_only", b"# a comment\n# another one\n", None),
        _obj("vertices_only", TRIANGLE, None),
        _obj("groups_only", b"o thing\ng part\ns off\nusemtl x\n", None),
        # not text
        _obj("binary_noise", _noise(4096, SEED), None),
        _obj("binary_noise_no_nul", _noise(4096, SEED + 1, forbid_nul=True), None),
        _obj("utf16_text", (TRIANGLE + b"f 1 2 3\n").decode().encode("utf-16"), None),
        _obj("png_named_obj", png_bytes(2, 2), None),
        _obj("nul_in_valid_text", TRIANGLE + b"f 1 2\x003\n", 4),
        # cut off
        _obj("truncated_mid_vertex", b"v -40 -40 0\nv 40 -40 0\nv 0 40", 3),
        _obj("truncated_mid_face", TRIANGLE + b"f 1 2", 4),
        _obj("truncated_mid_number", TRIANGLE + b"f 1 2 3\nv 1e", 5),
        _obj("truncated_mid_corner", b"vt 0 0\n" + TRIANGLE + b"f 1/1 2/1 3/", 5),
        # indices
        _obj("index_zero", _face_line(b"f 0 1 2"), 4),
        _obj("index_past_end", _face_line(b"f 1 2 4"), 4),
        _obj("index_far_past_end", _face_line(b"f 1 2 2147483648"), 4),
        _obj("index_absurd", _face_line(b"f 1 2 " + ABSURD_INDEX), 4),
        _obj("index_absurd_negative", _face_line(b"f 1 2 -" + ABSURD_INDEX), 4),
        _obj("index_5000_digits", _face_line(b"f 1 2 " + DIGITS_5000), 4),
        _obj("index_absurd_texcoord", b"vt 0 0\n" + TRIANGLE + b"f 1/1 2/1 3/" + ABSURD_INDEX + b"\n", 5),
        _obj("negative_past_start", _face_line(b"f -1 -2 -4"), 4),
        _obj("negative_before_any_vertex", b"f -1 -2 -3\n" + TRIANGLE, 1),
        _obj("face_before_its_vertices", b"v 0 0 0\nf 1 2 3\nv 1 0 0\n", 2),
        _obj("texcoord_past_end", b"vt 0 0\n" + TRIANGLE + b"f 1/1 2/1 3/2\n", 5),
        _obj("normal_past_end", b"vn 0 0 1\n" + TRIANGLE + b"f 1//1 2//1 3//2\n", 5),
        _obj("texcoord_zero", b"vt 0 0\n" + TRIANGLE + b"f 1/0 2/1 3/1\n", 5),
        _obj("faces_without_vertices", b"f 1 2 3\n", 1),
        # faces too small or malformed
        _obj("face_of_one_vertex", _face_line(b"f 1"), 4),
        _obj("face_of_two_vertices", _face_line(b"f 1 2"), 4),
        _obj("face_of_no_vertex", _face_line(b"f"), 4),
        _obj("face_of_text", _face_line(b"f a b c"), 4),
        _obj("face_of_fractions", _face_line(b"f 1.0 2 3"), 4),
        _obj("face_mixed_formats", b"vt 0 0\n" + TRIANGLE + b"f 1/1 2 3\n", 5),
        _obj("face_four_slashes", _face_line(b"f 1/1/1/1 2/1/1/1 3/1/1/1"), 4),
        _obj("face_only_slashes", _face_line(b"f / // ///"), 4),
        # numbers that are not numbers
        _obj("nan_coordinate", b"v nan 0 0\n" + TRIANGLE + b"f 2 3 4\n", 1),
        _obj("inf_coordinate", b"v 0 inf 0\n" + TRIANGLE + b"f 2 3 4\n", 1),
        _obj("minus_inf_coordinate", b"v 0 0 -infinity\n" + TRIANGLE + b"f 2 3 4\n", 1),
        _obj("overflow_to_inf", b"v 1e999 0 0\n" + TRIANGLE + b"f 2 3 4\n", 1),
        _obj("words_for_numbers", b"v one two three\n" + TRIANGLE + b"f 2 3 4\n", 1),
        _obj("decimal_comma", b"v 1,5 0 0\n" + TRIANGLE + b"f 2 3 4\n", 1),
        _obj("hex_float", b"v 0x1p3 0 0\n" + TRIANGLE + b"f 2 3 4\n", 1),
        _obj("two_numbers", b"v 1 2\n" + TRIANGLE + b"f 2 3 4\n", 1),
        _obj("nan_texcoord", b"vt nan 0\n" + TRIANGLE + b"f 1 2 3\n", 1),
        _obj("inf_normal", b"vn 0 0 inf\n" + TRIANGLE + b"f 1 2 3\n", 1),
        # large: each must fail (or load) in a moment, without memory in proportion to the claim
        _obj("million_corners_one_bad", TRIANGLE + b"f " + b"1 2 3 " * (MILLION // 3) + b"9\n", 4),
        _obj("million_faces_one_line", TRIANGLE + b"f 1 2 3" + b" f 1 2 3" * MILLION + b"\n", 4),
        _obj("megabyte_line_of_text", b"v " + b"x" * MEGABYTE + b"\n" + TRIANGLE + b"f 2 3 4\n", 1),
        _obj("megabyte_number", b"v " + b"1" * MEGABYTE + b" 0 0\n" + TRIANGLE + b"f 2 3 4\n", 1),
        # a long run of digits that ends badly: a number's syntax must not try every split of it
        _obj("megabyte_number_ending_badly", b"v " + b"1" * MEGABYTE + b"x 0 0\n" + TRIANGLE + b"f 2 3 4\n", 1),
        _obj("megabyte_texcoord_ending_badly", TRIANGLE + b"vt 0 " + b"1" * MEGABYTE + b"e\nf 1 2 3\n", 4),
        _obj("megabyte_of_numbers", b"v" + b" 1" * (MEGABYTE // 2) + b"\n" + TRIANGLE + b"f 2 3 4\n", 1),
        # paths that are not a readable file
        Case("missing", "obj", "missing.obj", setup="missing"),
        Case("directory", "obj", "folder.obj", setup="directory"),
        Case("unreadable", "obj", "locked.obj", TRIANGLE + b"f 1 2 3\n", setup="unreadable"),
        Case("dangling_link", "obj", "dangling.obj", setup="dangling_link"),
        Case("link_loop", "obj", "loop.obj", setup="link_loop"),
        _obj("bad_in_odd_name", _face_line(b"f 1 2 9"), 4, filename="bad model ñ 模型.obj"),
    ]


def good_obj_cases() -> list[Case]:
    """Odd but valid: must load."""
    return [
        _obj("spaces_and_non_ascii_name", TRIANGLE + b"f 1 2 3\n", None, filename="my model ñandú 模型.obj"),
        _obj("crlf_tabs_and_comments",
             b"# c\r\nv\t-1 -1 0\r\nv 1 -1 0 # trailing\r\nv 0 1 0\r\n\r\nf 1 2 3\r\n", None),
        _obj("no_final_newline", TRIANGLE + b"f 1 2 3", None),
        _obj("unknown_statements", b"t 1 2\nc 3\nmtllib missing.mtl\nusemtl red\n" + TRIANGLE + b"f 1 2 3\n",
             None),
        _obj("million_corner_polygon", TRIANGLE + b"f " + b"1 2 3 " * (MILLION // 3) + b"\n", None),
        _obj("megabyte_comment", b"#" + b"c" * MEGABYTE + b"\n" + TRIANGLE + b"f 1 2 3\n", None),
        _obj("valid_seed", VALID_OBJ, None),
    ]


# --------------------------------------------------------------------------------------------------
# Images
# --------------------------------------------------------------------------------------------------
def ppm_p6(width: int, height: int, maxval: int = 255, header_extra: bytes = b"") -> bytes:
    """A valid binary PPM whose pixels count up, so every pixel differs from its neighbours."""
    wide = maxval > 255
    count = width * height * 3
    samples = [(index * 37) % (maxval + 1) for index in range(count)]
    raster = struct.pack(f">{count}H", *samples) if wide else bytes(samples)
    return b"P6\n" + header_extra + f"{width} {height}\n{maxval}\n".encode() + raster


def ppm_p3(width: int, height: int, maxval: int = 255) -> bytes:
    count = width * height * 3
    samples = " ".join(str((index * 37) % (maxval + 1)) for index in range(count))
    return f"P3\n{width} {height}\n{maxval}\n{samples}\n".encode()


VALID_P6 = ppm_p6(4, 3)
VALID_P3 = ppm_p3(3, 2)


def git_lfs_pointer(size: int) -> bytes:
    """What a clone without `git lfs pull` holds in place of a file of `size` bytes (git-lfs's spec v1)."""
    return (b"version https://git-lfs.github.com/spec/v1\noid sha256:" + b"4d7a2146" * 8
            + f"\nsize {size}\n".encode())


def png_bytes(width: int, height: int, claimed: tuple[int, int] | None = None) -> bytes:
    """A PNG made by hand (zlib + CRCs); `claimed` puts another size in the header than the data has."""
    def chunk(kind: bytes, body: bytes) -> bytes:
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))

    header_w, header_h = claimed or (width, height)
    ihdr = struct.pack(">IIBBBBB", header_w, header_h, 8, 2, 0, 0, 0)  # 8-bit RGB
    rows = b"".join(b"\0" + bytes([200, 40, 40]) * width for _ in range(height))
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b"")


def jpeg_of_scans(scans: int) -> bytes:
    """A 16 x 16 progressive JPEG (Pillow writes 10 scans), its last scan repeated until it holds `scans`."""
    out = io.BytesIO()
    Image.fromarray(np.random.default_rng(4).integers(0, 255, (16, 16, 3), dtype=np.uint8)).save(
        out, "JPEG", progressive=True)
    data = out.getvalue()
    last = data.rindex(b"\xff\xda")
    return data[:-2] + data[last:-2] * (scans - data.count(b"\xff\xda")) + data[-2:]


def _image(case_id: str, content: bytes, filename: str = "") -> Case:
    return Case(case_id, "image", filename or f"{case_id}.ppm", content)


def bad_image_cases() -> list[Case]:
    return [
        _image("empty", b""),
        _image("magic_only", b"P6"),
        _image("wrong_magic_p5", b"P5\n2 2\n255\n" + b"\x80" * 4),
        _image("wrong_magic_p7", b"P7\nWIDTH 1\nHEIGHT 1\nDEPTH 3\nMAXVAL 255\nENDHDR\n\0\0\0"),
        _image("wrong_magic_lowercase", b"p6\n1 1\n255\n\0\0\0"),
        _image("wrong_magic_text", b"hello, this is not an image\n"),
        _image("binary_noise", _noise(2048, SEED + 2)),
        _image("zero_width", b"P6\n0 2\n255\n"),
        _image("zero_size", b"P6\n0 0\n255\n"),
        _image("zero_height_p3", b"P3\n2 0\n255\n"),
        _image("absurd_size", b"P6\n100000 100000\n255\n\xff\x00\x00"),  # 10^10 pixels claimed
        _image("absurd_size_p3", b"P3\n100000 100000\n255\n255 0 0\n"),
        _image("absurd_size_20_digits", b"P6\n99999999999999999999 1\n255\n\0\0\0"),
        _image("largest_allowed_claim_p6", b"P6\n8192 8192\n255\n\xff\x00\x00"),
        _image("largest_allowed_claim_p3", b"P3\n8192 8192\n255\n255 0 0\n"),
        _image("negative_width", b"P6\n-2 2\n255\n" + b"\0" * 12),
        _image("fractional_width", b"P6\n2.5 2\n255\n" + b"\0" * 12),
        _image("words_for_size", b"P6\nwide 2\n255\n" + b"\0" * 12),
        _image("truncated_header", b"P6\n2 2"),
        _image("truncated_after_maxval", b"P6\n2 2\n255"),
        _image("truncated_p6_data", b"P6\n2 2\n255\n" + b"\x10" * 6),
        _image("truncated_p6_16bit", b"P6\n1 1\n65535\n\0\0\0"),
        _image("truncated_p3_data", b"P3\n2 2\n255\n1 2 3 4 5 6\n"),
        _image("maxval_zero", b"P6\n1 1\n0\n\0\0\0"),
        _image("maxval_65536", b"P6\n1 1\n65536\n" + b"\0" * 6),
        _image("maxval_absurd", b"P6\n1 1\n99999999999999999999\n" + b"\0" * 6),
        _image("p3_sample_over_maxval", b"P3\n1 1\n15\n16 0 0\n"),
        _image("p3_sample_absurd", b"P3\n1 1\n255\n99999999999999999999999 0 0\n"),
        _image("p3_negative_sample", b"P3\n1 1\n255\n-1 0 0\n"),
        _image("p3_word_sample", b"P3\n1 1\n255\nred 0 0\n"),
        _image("p3_fraction_sample", b"P3\n1 1\n255\n0.5 0 0\n"),
        _image("png_noise", b"\x89PNG\r\n\x1a\n" + _noise(512, SEED + 3), filename="noise.png"),
        _image("png_truncated", png_bytes(8, 8)[:40], filename="cut.png"),
        _image("png_absurd_size", png_bytes(1, 1, claimed=(100000, 100000)), filename="absurd.png"),
        Case("missing", "image", "missing.ppm", setup="missing"),
        Case("directory", "image", "folder.ppm", setup="directory"),
        Case("unreadable", "image", "locked.ppm", VALID_P6, setup="unreadable"),
        Case("dangling_link", "image", "dangling.ppm", setup="dangling_link"),
        _image("bad_in_odd_name", b"P6\n2 2\n255\n\0", filename="bild ñ 画像.ppm"),
    ]


def good_image_cases() -> list[tuple[Case, tuple[int, int]]]:
    """Valid images and their (height, width)."""
    odd_comments = (b"P6# right after the magic\n# a line of its own\n4# glued to the width\n"
                    b"  # between width and height\n3\n#before maxval\n255\n")
    raster_like_a_header = b"#\n# \n255\n" + bytes(range(36 - 9))  # '#' and newlines in binary data
    return [
        (_image("p6", VALID_P6), (3, 4)),
        (_image("p3", VALID_P3), (2, 3)),
        (_image("p6_comments_in_odd_places", odd_comments + VALID_P6[-36:]), (3, 4)),
        (_image("p6_raster_looks_like_header", b"P6\n4 3\n255\n" + raster_like_a_header), (3, 4)),
        (_image("p3_comments_between_samples",
                b"P3\n# size\n2 1 # w h\n255\n255 0 0 # red\n# a whole line\n0 0 255# blue\n"), (1, 2)),
        (_image("p3_crlf", b"P3\r\n1 1\r\n255\r\n1 2 3\r\n"), (1, 1)),
        (_image("p3_maxval_1", b"P3\n2 1\n1\n1 0 1 0 1 0\n"), (1, 2)),
        (_image("p6_16_bit", ppm_p6(2, 2, maxval=65535)), (2, 2)),
        (_image("p3_maxval_65535", ppm_p3(2, 1, maxval=65535)), (1, 2)),
        (_image("p6_trailing_bytes", VALID_P6 + b"extra"), (3, 4)),
        (_image("png", png_bytes(3, 2), filename="small.png"), (2, 3)),
        (_image("spaces_and_non_ascii_name", VALID_P6, filename="my picture ñ 画像.ppm"), (3, 4)),
    ]


# --------------------------------------------------------------------------------------------------
# Scene files
# --------------------------------------------------------------------------------------------------
GOOD_MODEL = ("tri.obj", TRIANGLE + b"f 1 2 3\n")
BAD_MODEL = ("bad.obj", _face_line(b"f 1 2 7"))
CAMERA_TABLE = '[[cameras]]\nmodel = "tri.obj"\nposition = [0, 0, 150]\n'
MATERIAL_TABLE = "[materials.m]\nka = [0.1, 0.2, 0.3]\nkd = [0.4, 0.5, 0.6]\nks = [0.7, 0.8, 0.9]\nns = 10\n"


def _scene(case_id: str, text: str | bytes, line: int | None = None) -> Case:
    content = text.encode() if isinstance(text, str) else text
    return Case(case_id, "scene", f"{case_id}.toml", content, line, companions=(GOOD_MODEL, BAD_MODEL))


def _object_table(body: str) -> str:
    return CAMERA_TABLE + "[[objects]]\n" + body  # the [[objects]] header is on line 4


def bad_scene_cases() -> list[Case]:
    return [
        # (a scene of no cameras takes the built-in scene's, and one of nothing is --empty's)
        _scene("syntax_error", CAMERA_TABLE + "[[objects]\nmodel = 1\n", 4),
        _scene("unclosed_string", 'texture = "selfi.ppm\n' + CAMERA_TABLE, 1),
        _scene("binary_noise", _noise(1024, SEED + 4)),
        _scene("not_utf8", b"# caf\xe9\n" + CAMERA_TABLE.encode(), 1),
        _scene("deeply_nested_array", CAMERA_TABLE + "texture = " + "[" * 5000 + "]" * 5000 + "\n"),
        _scene("deeply_nested_table", CAMERA_TABLE + "texture = " + "{a=" * 3000 + "1" + "}" * 3000 + "\n"),
        # dotted keys of many parts: tomllib's cost grows with the square of a key's parts
        _scene("key_of_a_million_parts", "a" + ".a" * MILLION + " = 1\n" + CAMERA_TABLE, 1),
        _scene("quoted_key_of_a_million_parts", CAMERA_TABLE + '"a"' + '."a"' * MILLION + " = 1\n", 4),
        _scene("table_of_a_million_parts", CAMERA_TABLE + "[" + "a." * MILLION + "a]\n", 4),
        _scene("key_of_seventeen_parts", CAMERA_TABLE + ".".join("abcdefghijklmnopq") + " = 1\n", 4),
        _scene("inline_key_of_a_million_parts", CAMERA_TABLE + "x = { " + "a." * MILLION + "a = 1 }\n", 4),
        _scene("key_of_a_million_parts_without_a_value", CAMERA_TABLE + "a" + ".a" * MILLION + "\n", 4),
        _scene("unknown_top_level_key", "lights = 4\n" + CAMERA_TABLE),
        _scene("missing_model", _object_table("position = [0, 0, 0]\n"), 4),  # a camera's is the built-in one
        _scene("missing_position", '[[cameras]]\nmodel = "tri.obj"\n', 1),
        _scene("misspelt_key", _object_table('model = "tri.obj"\npositon = [0, 0, 0]\n'), 6),
        _scene("position_is_text", _object_table('model = "tri.obj"\nposition = "middle"\n'), 6),
        _scene("position_two_numbers", _object_table('model = "tri.obj"\nposition = [1, 2]\n'), 6),
        _scene("position_nan", _object_table('model = "tri.obj"\nposition = [nan, 0, 0]\n'), 6),
        _scene("position_inf", _object_table('model = "tri.obj"\nposition = [0, -inf, 0]\n'), 6),
        _scene("position_booleans", _object_table('model = "tri.obj"\nposition = [true, 0, 0]\n'), 6),
        _scene("position_400_digit_integer", _object_table(f'model = "tri.obj"\nposition = [{"9" * 400}, 0, 0]\n'), 6),
        _scene("position_past_float32", _object_table('model = "tri.obj"\nposition = [0, 1e39, 0]\n'), 6),
        _scene("position_past_int_digit_limit",  # Python itself refuses to read this integer
               _object_table(f'model = "tri.obj"\nposition = [{"9" * 5000}, 0, 0]\n'), 6),
        _scene("rotation_far_past_float32", CAMERA_TABLE + "rotation = [0, -1e308, 0]\n", 4),
        _scene("material_ns_past_float32", MATERIAL_TABLE.replace("ns = 10", "ns = 1e39") + CAMERA_TABLE, 5),
        _scene("model_is_number", _object_table("model = 5\nposition = [0, 0, 0]\n"), 5),
        _scene("model_is_empty", _object_table('model = ""\nposition = [0, 0, 0]\n'), 5),
        _scene("objects_not_tables", 'objects = "x_wing"\n' + CAMERA_TABLE, 1),
        _scene("texture_is_number", "texture = 5\n" + CAMERA_TABLE, 1),
        _scene("unknown_material", _object_table('model = "tri.obj"\nposition = [0, 0, 0]\nmaterial = "gold"\n'),
               7),
        _scene("materials_not_tables", "materials = 5\n" + CAMERA_TABLE, 1),
        _scene("material_missing_ns", "[materials.m]\nka = [0.1, 0.2, 0.3]\nkd = [0.4, 0.5, 0.6]\n"
                                      "ks = [0.7, 0.8, 0.9]\n" + CAMERA_TABLE, 1),
        _scene("material_ns_text", MATERIAL_TABLE.replace("ns = 10", 'ns = "shiny"') + CAMERA_TABLE, 5),
        _scene("material_ns_negative", MATERIAL_TABLE.replace("ns = 10", "ns = -3") + CAMERA_TABLE, 5),
        _scene("material_colour_out_of_range", MATERIAL_TABLE.replace("ka = [0.1", "ka = [2.5") + CAMERA_TABLE,
               2),
        _scene("inline_material_wrong_type", _object_table('model = "tri.obj"\nposition = [0, 0, 0]\n'
                                                           "material = [1, 2, 3]\n"), 7),
        _scene("model_missing_file", _object_table('model = "nowhere.obj"\nposition = [0, 0, 0]\n'), 5),
        _scene("model_fails_to_load", _object_table('model = "bad.obj"\nposition = [0, 0, 0]\n'), 5),
        _scene("model_is_a_folder", _object_table('model = ".."\nposition = [0, 0, 0]\n'), 5),
        _scene("camera_model_fails", '[[cameras]]\nmodel = "bad.obj"\nposition = [0, 0, 150]\n', 2),
        Case("missing", "scene", "missing.toml", setup="missing"),
        Case("directory", "scene", "folder.toml", setup="directory"),
        Case("unreadable", "scene", "locked.toml", CAMERA_TABLE.encode(), setup="unreadable",
             companions=(GOOD_MODEL,)),
    ]


def scene_with_bad_texture() -> Case:
    """A good scene whose texture is broken: a message and the fallback, not an exit (SPEC 7)."""
    texture = ("broken.ppm", b"P6\n2 2\n255\n\0")
    return Case("bad_texture", "scene", "scene.toml", ('texture = "broken.ppm"\n' + CAMERA_TABLE).encode(),
                companions=(GOOD_MODEL, texture))


# --------------------------------------------------------------------------------------------------
# Measuring: memory and GL objects
# --------------------------------------------------------------------------------------------------
def current_rss_bytes() -> int:
    """Resident memory now (not the peak): what a leak makes grow. Linux /proc; 0 elsewhere."""
    try:
        resident_pages = int(Path("/proc/self/statm").read_text().split()[1])
    except (OSError, IndexError, ValueError):
        return 0
    return resident_pages * os.sysconf("SC_PAGE_SIZE")


def _gl_object_types() -> tuple[type, ...]:
    import moderngl

    names = ("Buffer", "VertexArray", "Texture", "Texture3D", "TextureArray", "TextureCube", "Program",
             "Framebuffer", "Renderbuffer", "Sampler", "Query", "ComputeShader", "Scope")
    return tuple(getattr(moderngl, name) for name in names if hasattr(moderngl, name))


def tracked_objects() -> list[object]:
    """What the garbage collector tracks, less weakref proxies: isinstance() on one whose object is gone
    raises ReferenceError (numba leaves such proxies behind a dispatcher that was dropped)."""
    proxies = (weakref.ProxyType, weakref.CallableProxyType)
    return [obj for obj in gc.get_objects() if type(obj) not in proxies]


def live_gl_objects(ctx: object) -> Counter[str]:
    """moderngl objects of `ctx` that Python still holds and nobody released, by type.

    moderngl 5.13 keeps no registry of live objects (`ctx.objects` only collects dropped ones in
    "context_gc" mode, see `DroppedGlObjects`), so the garbage collector's view is the census.
    """
    import moderngl

    gc.collect()
    types = _gl_object_types()
    return Counter(type(obj).__name__ for obj in tracked_objects()
                   if isinstance(obj, types) and getattr(obj, "ctx", None) is ctx
                   and not isinstance(obj.mglo, moderngl.InvalidObject))


class DroppedGlObjects:
    """Counts GL objects that Python dropped without releasing them (a GL leak moderngl hides).

    In "context_gc" mode moderngl appends each collected wrapper's handle to `ctx.objects`, released
    or not; the ones still valid were leaked. On exit they are released and the mode restored.
    """

    def __init__(self, ctx) -> None:
        self.ctx = ctx
        self.leaked = 0

    def __enter__(self) -> DroppedGlObjects:
        self._mode = self.ctx.gc_mode
        self.ctx.objects.clear()
        self.ctx.gc_mode = "context_gc"
        return self

    def count(self) -> int:
        import moderngl

        gc.collect()
        return sum(not isinstance(handle, moderngl.InvalidObject) for handle in self.ctx.objects)

    def __exit__(self, *exc: object) -> None:
        import moderngl

        self.leaked = self.count()
        for handle in self.ctx.objects:
            if not isinstance(handle, moderngl.InvalidObject):
                handle.release()
        self.ctx.objects.clear()
        self.ctx.gc_mode = self._mode


# --------------------------------------------------------------------------------------------------
# Rendering with a float colour buffer
# --------------------------------------------------------------------------------------------------
_float_targets: dict[tuple[int, tuple[int, int]], object] = {}


def _egl_library():
    """libEGL through ctypes, for what moderngl does not offer: asking which context is current."""
    import ctypes
    import ctypes.util

    try:
        egl = ctypes.CDLL(ctypes.util.find_library("EGL") or "libEGL.so.1")
    except OSError:
        return None
    egl.eglGetCurrentDisplay.restype = ctypes.c_void_p
    egl.eglGetCurrentContext.restype = ctypes.c_void_p
    egl.eglGetCurrentSurface.restype = ctypes.c_void_p
    egl.eglGetCurrentSurface.argtypes = [ctypes.c_int]
    egl.eglMakeCurrent.argtypes = [ctypes.c_void_p] * 4
    egl.eglMakeCurrent.restype = ctypes.c_uint
    return egl


_EGL_DRAW, _EGL_READ = 0x3059, 0x305A


@contextmanager
def kept_gl_context() -> Iterator[None]:
    """Whatever GL context is current before the block is current again after it.

    Creating a moderngl context makes it current and releasing it restores nothing, so a test that
    makes one of its own (or runs the screenshot command in-process) would leave every later user
    of another context drawing into a destroyed one. See `make_current`.
    """
    egl = _egl_library()
    saved = None
    if egl is not None:
        saved = (egl.eglGetCurrentDisplay(), egl.eglGetCurrentSurface(_EGL_DRAW),
                 egl.eglGetCurrentSurface(_EGL_READ), egl.eglGetCurrentContext())
    try:
        yield
    finally:
        if saved is not None and saved[3]:
            egl.eglMakeCurrent(*saved)


def own_gl_context() -> Iterator:
    """A module's own EGL context (for a module-scoped fixture), leaving the current one as it was.

    The session's `gl_ctx` is not used: created early, it would be at the mercy of every later test
    that makes a context of its own, and moderngl never switches back to it.
    """
    import moderngl
    import pytest

    with kept_gl_context():
        try:
            ctx = moderngl.create_standalone_context(backend="egl")
        except Exception as error:  # no EGL, no driver: the GL tests cannot run here
            pytest.skip(f"no headless EGL OpenGL context: {error}")
        try:
            yield ctx
        finally:
            for key in [key for key in _float_targets if key[0] == id(ctx)]:
                del _float_targets[key]
            ctx.release()


def own_renderer(ctx) -> Iterator:
    """A Renderer of a module's own on `ctx` (for a fixture), released on the context that made it."""
    from marraztu.render.renderer import Renderer

    make_current(ctx)
    renderer = Renderer(ctx)
    yield renderer
    make_current(ctx)  # the release must reach the context that made these objects
    renderer.release()


def make_current(ctx) -> None:
    """Makes `ctx` this thread's current GL context, and leaves it so.

    moderngl sends every call to whatever context is current and never switches by itself. A test
    that makes and releases a context of its own (the in-process screenshot command does) leaves a
    destroyed one current: the session's context then draws nowhere, reads garbage and reports
    GL_INVALID_OPERATION. Entering without leaving keeps it current for whatever runs next too.
    """
    ctx.__enter__()


def render_float(ctx, renderer, scene, size: tuple[int, int] = (64, 64)):
    """Renders `scene` into a float32 colour buffer and returns (H, W, 4) float32, rows bottom first.

    A byte buffer clamps and hides a NaN (it reads as 0 or 255); a float buffer keeps it, so a shader
    fed garbage shows as garbage. The GL error flag is checked right after the frame.
    """
    import numpy as np

    make_current(ctx)
    key = (id(ctx), size)
    fbo = _float_targets.get(key)
    if fbo is None:
        fbo = ctx.framebuffer(color_attachments=[ctx.texture(size, 4, dtype="f4")],
                              depth_attachment=ctx.depth_renderbuffer(size))
        _float_targets[key] = fbo
    pending = ctx.error
    assert pending == "GL_NO_ERROR", f"{pending} was pending before the frame"
    renderer.render(scene, fbo, size)
    error = ctx.error
    assert error == "GL_NO_ERROR", error
    width, height = size
    return np.frombuffer(fbo.read(components=4, dtype="f4"), dtype="f4").reshape(height, width, 4)


def assert_sane_pixels(pixels) -> None:
    """Every channel a finite number in 0..1: what lit colour x texture, lines and markers give."""
    import numpy as np

    finite = np.isfinite(pixels)
    assert finite.all(), f"{int((~finite).sum())} NaN/inf channel values"
    assert pixels.min() >= -1e-4 and pixels.max() <= 1 + 1e-4, (float(pixels.min()), float(pixels.max()))


class NoFrontend:
    """A viewer frontend that does nothing: for tests that drive a Viewer without a window."""

    def quit(self) -> None: ...
    def open_file_prompt(self) -> None: ...
    def save_screenshot(self) -> None: ...
