"""Property tests: mutated and randomly assembled OBJ and PPM files either load into something the
renderer can trust or fail with a LoadError; nothing else ever escapes the loaders.

Derandomized (the same examples every run) and bounded, so the file takes seconds, not minutes.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from marraztu.errors import LoadError
from marraztu.loaders.images import MAX_PIXELS, parse_ppm
from marraztu.loaders.obj import parse_obj
from marraztu.model.mesh import Mesh
from marraztu.render.gpu import (
    EDGE_FACE_TEXTURE_SIDE,
    edge_face_shape,
    edge_faces,
    edge_pairs,
    edge_rows,
    face_normal_feet,
    surface_arrays,
)
from support import corpus

FUZZ = settings(derandomize=True, database=None, deadline=None, max_examples=600,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

# Tokens that break readers: overflowing, zero and negative indices, non-numbers, separators.
OBJ_TOKENS = [b"0", b"1", b"2", b"3", b"-1", b"-3", b"-4", b"7", b"99999999999999999999", b"2147483648",
              b"nan", b"inf", b"-inf", b"1e309", b"1e-320", b"3.5e38", b"1e300", b"-0", b".", b"-", b"+1",
              b"1.5", b"1e5", b"1/1", b"1//1", b"1/1/1", b"/", b"//", b"1/", b"#", b"\\", b"\x00", b"\xff",
              b"\xc3\xa9", b"\t", b"\r", b"v", b"vt", b"vn", b"f", b"o", b"g", b"s", b"mtllib", b"usemtl"]
OBJ_KEYWORDS = [b"v", b"vt", b"vn", b"f", b"o", b"g", b"s", b"#", b"mtllib", b"usemtl", b"t", b"c", b"", b"F",
                b"vp", b"l", b"p"]
PPM_TOKENS = [b"P6", b"P3", b"0", b"1", b"2", b"3", b"255", b"256", b"65535", b"65536", b"-1", b"#", b"# c\n",
              b"99999999999999999999", b"100000", b"\n", b" ", b"\r", b"\t", b"\x00", b"\xff", b"1.5", b"x"]


# --------------------------------------------------------------------------------------------------
# Byte- and line-level mutations of a valid file
# --------------------------------------------------------------------------------------------------
def _position(draw, data: bytearray) -> int:
    return draw(st.integers(0, len(data)))


def _flip(draw, data: bytearray, tokens: list[bytes]) -> None:
    if data:
        data[min(_position(draw, data), len(data) - 1)] = draw(st.integers(0, 255))


def _insert_bytes(draw, data: bytearray, tokens: list[bytes]) -> None:
    at = _position(draw, data)
    data[at:at] = draw(st.binary(min_size=1, max_size=6))


def _insert_token(draw, data: bytearray, tokens: list[bytes]) -> None:
    at = _position(draw, data)
    data[at:at] = draw(st.sampled_from([b" ", b""])) + draw(st.sampled_from(tokens))


def _delete_span(draw, data: bytearray, tokens: list[bytes]) -> None:
    at = _position(draw, data)
    del data[at:at + draw(st.integers(1, 12))]


def _truncate(draw, data: bytearray, tokens: list[bytes]) -> None:
    del data[_position(draw, data):]


def _replace_word(draw, data: bytearray, tokens: list[bytes]) -> None:
    """A whole number or keyword swapped for a troublesome token: keeps the line's shape."""
    words = [(start, start + len(word)) for start, word in _words(bytes(data))]
    if words:
        start, end = draw(st.sampled_from(words))
        data[start:end] = draw(st.sampled_from(tokens))


def _words(data: bytes) -> list[tuple[int, bytes]]:
    out, at = [], 0
    for word in data.split(b" "):
        for part in word.split(b"\n"):
            if part:
                out.append((data.index(part, at), part))
                at = out[-1][0] + len(part)
    return out


def _line_edit(draw, data: bytearray, tokens: list[bytes]) -> None:
    """Duplicate, delete or swap whole lines, as an editor (or a bad merge) would."""
    lines = bytes(data).split(b"\n")
    i, j = draw(st.integers(0, len(lines) - 1)), draw(st.integers(0, len(lines) - 1))
    edit = draw(st.sampled_from(["duplicate", "delete", "swap"]))
    if edit == "duplicate":
        lines.insert(j, lines[i])
    elif edit == "delete" and len(lines) > 1:
        del lines[i]
    else:
        lines[i], lines[j] = lines[j], lines[i]
    data[:] = b"\n".join(lines)


MUTATIONS = [_flip, _insert_bytes, _insert_token, _delete_span, _truncate, _replace_word, _line_edit]


@st.composite
def mutated(draw, seeds: list[bytes], tokens: list[bytes]) -> bytes:
    data = bytearray(draw(st.sampled_from(seeds)))
    for _ in range(draw(st.integers(1, 4))):
        draw(st.sampled_from(MUTATIONS))(draw, data, tokens)
    return bytes(data)


# --------------------------------------------------------------------------------------------------
# Files assembled from a small grammar: valid-looking structure, hostile details
# --------------------------------------------------------------------------------------------------
# Mostly small indices that exist, so that many drawn files load and the mesh checks have work.
_small_numbers = st.one_of(st.integers(1, 4).map(lambda n: str(n).encode()),
                           st.integers(-5, 9).map(lambda n: str(n).encode()),
                           st.floats(allow_nan=True, allow_infinity=True).map(lambda x: repr(x).encode()),
                           st.sampled_from(OBJ_TOKENS))
_corner = st.tuples(_small_numbers, st.sampled_from([b"", b"/", b"//"]), _small_numbers).map(
    lambda parts: parts[0] + (parts[1] + parts[2] if parts[1] else b""))


@st.composite
def obj_line(draw) -> bytes:
    keyword = draw(st.sampled_from(OBJ_KEYWORDS))
    item = _corner if keyword == b"f" else _small_numbers
    items = draw(st.lists(item, min_size=0, max_size=6))
    return b" ".join([keyword, *items])


@st.composite
def assembled_obj(draw) -> bytes:
    """Mostly well-formed vertices, then faces and oddities drawn from the grammar."""
    vertices = draw(st.lists(st.tuples(*[st.integers(-50, 50)] * 3), min_size=0, max_size=6))
    vertices += [(-1, -1, 0), (1, -1, 0), (0, 1, 0), (0, 0, 1)][:draw(st.integers(0, 4))]
    lines = [b"v %d %d %d" % v for v in vertices]
    lines += draw(st.lists(obj_line(), min_size=1, max_size=12))
    if draw(st.booleans()):
        lines.append(b"f 1 2 3")
    ending = draw(st.sampled_from([b"\n", b"\r\n", b""]))
    return ending.join(draw(st.permutations(lines))) + ending


# --------------------------------------------------------------------------------------------------
# The properties
# --------------------------------------------------------------------------------------------------
def _unit(vectors: np.ndarray) -> bool:
    return bool(np.isfinite(vectors).all() and np.allclose(np.linalg.norm(vectors, axis=1), 1.0, atol=1e-3))


def check_mesh(mesh: Mesh) -> None:
    """What the renderer relies on from any mesh the loader lets through."""
    assert mesh.vertex_count >= 1 and mesh.face_count >= 1, "a loaded mesh has at least one polygon"
    assert np.isfinite(mesh.positions).all(), "coordinates are finite"
    with np.errstate(over="ignore"):
        assert np.isfinite(mesh.positions.astype(np.float32)).all(), "coordinates fit GL's float32"
    assert mesh.face_start[0] == 0 and mesh.face_start[-1] == mesh.corner_vertex.size
    assert (mesh.face_sizes >= 3).all(), "every polygon has at least 3 corners"
    assert mesh.corner_vertex.min() >= 0 and mesh.corner_vertex.max() < mesh.vertex_count, "indices in range"
    assert _unit(mesh.face_normals), "face normals are finite unit vectors"
    assert _unit(mesh.corner_normal), "vertex normals are finite unit vectors"
    assert mesh.corner_uv.shape == (mesh.corner_vertex.size, 2) and np.isfinite(mesh.corner_uv).all()
    assert mesh.triangle_corners().shape[0] == int((mesh.face_sizes - 2).sum())
    surface = surface_arrays(mesh)
    shape = edge_face_shape(mesh.face_count, EDGE_FACE_TEXTURE_SIDE)
    width = shape[0]
    edges = edge_rows(mesh, width)
    for table in (surface.vertices, face_normal_feet(mesh), edges["position"], *edge_faces(mesh, shape)):
        assert np.isfinite(table).all(), "everything sent to the GPU is finite"
    faces = edges["face_texel"].astype(np.int64) @ [1, width]
    assert (faces == np.repeat(np.arange(mesh.face_count), mesh.face_sizes)).all(), "each corner names its polygon"
    rows = surface.vertices.shape[0]
    for indices, rows in ((surface.indices, rows), (surface.shared_indices, rows),
                          (edge_pairs(mesh), mesh.corner_vertex.shape[0])):
        assert indices.max() < rows, "every index names a vertex row"


def parse_obj_or_load_error(data: bytes) -> Mesh | None:
    try:
        return parse_obj(data, "fuzz.obj")
    except LoadError as error:
        assert error.path == "fuzz.obj" and str(error).startswith("fuzz.obj")
        line_ends = data.count(b"\n") + data.count(b"\r")  # a lone CR ends a line too
        assert error.line is None or 1 <= error.line <= line_ends + 1
        return None


OBJ_SEEDS = [corpus.VALID_OBJ, corpus.TRIANGLE + b"f 1 2 3\n",
             b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 1\nf -4/-2 -3/-1 -2/-1 -1/-2\n"]


@FUZZ
@given(mutated(OBJ_SEEDS, OBJ_TOKENS))
def test_mutated_obj_loads_sanely_or_raises_load_error(data: bytes) -> None:
    mesh = parse_obj_or_load_error(data)
    if mesh is not None:
        check_mesh(mesh)


@FUZZ
@given(assembled_obj())
def test_assembled_obj_loads_sanely_or_raises_load_error(data: bytes) -> None:
    mesh = parse_obj_or_load_error(data)
    if mesh is not None:
        check_mesh(mesh)


# --------------------------------------------------------------------------------------------------
# Line endings and encodings: the same model as other editors and systems write it
# --------------------------------------------------------------------------------------------------
_NO_BREAK_SPACE = "\u00a0".encode()
_ENDINGS = [b"\n", b"\r\n", b"\r"]
_BACKSLASH_COMMENTS = [b"# exported from C:\\models\\", b"#\\", b"  # path: D:\\ships\\ \\", b"# \\ \t"]


@st.composite
def respelled(draw, seeds: list[bytes]) -> tuple[bytes, bytes]:
    """(seed, the seed written another way with the same meaning): CR, CRLF or mixed line ends, a byte
    order mark, no-break spaces between words, comments ending in a backslash, continued statements."""
    seed = draw(st.sampled_from(seeds))
    lines: list[bytes] = []
    for line in seed.rstrip(b"\n").split(b"\n"):
        if draw(st.integers(0, 5)) == 0:
            lines.append(draw(st.sampled_from(_BACKSLASH_COMMENTS)))
        words = line.split(b" ")
        if not line.startswith(b"#") and len(words) > 2 and draw(st.integers(0, 4)) == 0:
            cut = draw(st.integers(1, len(words) - 1))  # continued: the rest on the next physical line
            lines += [b" ".join(words[:cut]) + b" \\", b" " + b" ".join(words[cut:])]
            continue
        gaps = [draw(st.sampled_from([b" ", b" ", _NO_BREAK_SPACE, b" " + _NO_BREAK_SPACE])) for _ in words[1:]]
        lines.append(words[0] + b"".join(gap + word for gap, word in zip(gaps, words[1:])))
    spelled = b"".join(line + draw(st.sampled_from(_ENDINGS)) for line in lines)
    return seed, (b"\xef\xbb\xbf" if draw(st.booleans()) else b"") + spelled


def assert_same_mesh(a: Mesh, b: Mesh) -> None:
    for name in ("positions", "corner_vertex", "face_start", "corner_uv", "corner_normal"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)


@FUZZ
@given(respelled(OBJ_SEEDS))
def test_line_ends_and_encodings_do_not_change_the_model(pair: tuple[bytes, bytes]) -> None:
    seed, spelled = pair
    assert_same_mesh(parse_obj(spelled, "fuzz.obj"), parse_obj(seed, "fuzz.obj"))


@st.composite
def mutated_respelling(draw) -> bytes:
    _, spelled = draw(respelled(OBJ_SEEDS))
    data = bytearray(spelled)
    for _ in range(draw(st.integers(1, 3))):
        draw(st.sampled_from(MUTATIONS))(draw, data, OBJ_TOKENS + [_NO_BREAK_SPACE, b"\\\r", b"\\\n", b"#\\\n"])
    return bytes(data)


@FUZZ
@given(mutated_respelling())
def test_mutated_respelled_obj_loads_sanely_or_raises_load_error(data: bytes) -> None:
    mesh = parse_obj_or_load_error(data)
    if mesh is not None:
        check_mesh(mesh)


def test_the_seeds_themselves_load() -> None:
    """Mutations start from valid files; a seed that failed would make the tests above vacuous."""
    for seed in OBJ_SEEDS:
        check_mesh(parse_obj(seed, "seed.obj"))
    for seed in PPM_SEEDS:
        check_image(parse_ppm(seed, "seed.ppm"), seed)


# --------------------------------------------------------------------------------------------------
# PPM
# --------------------------------------------------------------------------------------------------
PPM_SEEDS = [corpus.VALID_P6, corpus.VALID_P3, corpus.ppm_p6(2, 2, maxval=65535),
             b"P6\n# comment\n2 1 # size\n15\n\x01\x02\x03\x0f\x00\x07"]


_small_size = st.integers(1, 4).map(lambda n: str(n).encode())
_odd_number = st.one_of(st.integers(0, 300).map(lambda n: str(n).encode()), st.sampled_from(PPM_TOKENS))
_maxval = st.sampled_from([b"1", b"15", b"255", b"255", b"256", b"65535"])
# Repeating a branch in one_of makes it likelier: most headers are sane, so many files load.
_width_or_height = st.one_of(_small_size, _small_size, _small_size, _odd_number)
_maxval_token = st.one_of(_maxval, _maxval, _maxval, _odd_number)
_header_gap = st.sampled_from([b" ", b"\n", b" # a comment\n", b"\n#c\n", b"\t", b"\r\n", b" "])


@st.composite
def assembled_ppm(draw) -> bytes:
    """A header of drawn numbers and comments, then a raster about the size the header asks for."""
    magic = draw(st.sampled_from([b"P6", b"P3"] * 4 + [b"P5"]))
    width, height, maxval = draw(_width_or_height), draw(_width_or_height), draw(_maxval_token)
    gaps = [draw(_header_gap) for _ in range(3)]
    header = magic + gaps[0] + width + gaps[1] + height + gaps[2] + maxval + draw(st.sampled_from([b"\n", b" "]))
    wanted = _claimed_samples(width, height)
    top = int(maxval) if maxval.isdigit() and len(maxval) < 6 else 255
    if magic == b"P3":
        sample = st.one_of(st.integers(0, top), st.integers(0, top), st.integers(0, 70000))
        samples = draw(st.lists(sample, min_size=max(0, wanted - 1), max_size=wanted + 1))
        raster = b" ".join(str(value).encode() for value in samples)
    else:
        size = wanted * (2 if top > 255 else 1)
        raster = draw(st.binary(min_size=max(0, size - 2), max_size=size + 2))
    return header + raster


def _claimed_samples(width: bytes, height: bytes) -> int:
    """Samples the header asks for, capped: a big claim gets a short raster, as in the corpus."""
    if width.isdigit() and height.isdigit() and len(width) < 4 and len(height) < 4:
        return min(int(width) * int(height) * 3, 64)
    return 3


def check_image(image: np.ndarray, data: bytes) -> None:
    assert image.ndim == 3 and image.shape[2] == 3 and image.dtype == np.uint8
    height, width = image.shape[:2]
    assert height >= 1 and width >= 1 and height * width <= MAX_PIXELS
    assert height * width * 3 <= len(data), "no more pixels than the file has bytes for"


def parse_ppm_or_load_error(data: bytes) -> np.ndarray | None:
    try:
        return parse_ppm(data, "fuzz.ppm")
    except LoadError as error:
        assert error.path == "fuzz.ppm"
        return None


@FUZZ
@given(mutated(PPM_SEEDS, PPM_TOKENS))
def test_mutated_ppm_loads_sanely_or_raises_load_error(data: bytes) -> None:
    image = parse_ppm_or_load_error(data)
    if image is not None:
        check_image(image, data)


@FUZZ
@given(assembled_ppm())
def test_assembled_ppm_loads_sanely_or_raises_load_error(data: bytes) -> None:
    image = parse_ppm_or_load_error(data)
    if image is not None:
        check_image(image, data)


# --------------------------------------------------------------------------------------------------
# The formats read through trimesh: mutations of files its own exporters wrote
# --------------------------------------------------------------------------------------------------
def _exported_seeds() -> dict[str, list[bytes]]:
    import trimesh

    mesh = trimesh.Trimesh(vertices=[[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0.5]], faces=[[0, 1, 2], [0, 2, 3]],
                           process=False)
    return {".stl": [trimesh.exchange.stl.export_stl(mesh), trimesh.exchange.stl.export_stl_ascii(mesh).encode()],
            ".ply": [trimesh.exchange.ply.export_ply(mesh, encoding="binary"),
                     trimesh.exchange.ply.export_ply(mesh, encoding="ascii")],
            ".off": [trimesh.exchange.off.export_off(mesh).encode()],
            ".glb": [mesh.export(file_type="glb")]}


EXPORTED = _exported_seeds()
FORMAT_TOKENS = [b"nan", b"inf", b"-1", b"99", b"99999999999", b"0", b"3", b"\x00", b"\xff" * 4, b"solid", b"facet",
                 b"endfacet", b"vertex", b"element face 9", b"end_header", b"OFF", b"glTF", b"{", b"\n", b" "]
FORMAT_FUZZ = settings(FUZZ, max_examples=120)


def load_file_or_load_error(data: bytes, suffix: str) -> Mesh | None:
    import tempfile
    from pathlib import Path

    from marraztu.loaders.registry import load_model

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / f"fuzz{suffix}"
        path.write_bytes(data)
        try:
            return load_model(path)
        except LoadError as error:
            assert error.path == str(path) and "\n" not in str(error)
            return None


@pytest.mark.parametrize("suffix", sorted(EXPORTED))
def test_mutated_exchange_files_load_sanely_or_raise_load_error(suffix: str) -> None:
    @FORMAT_FUZZ
    @given(mutated(EXPORTED[suffix], FORMAT_TOKENS))
    def property_holds(data: bytes) -> None:
        mesh = load_file_or_load_error(data, suffix)
        if mesh is not None:
            check_mesh(mesh)

    property_holds()
