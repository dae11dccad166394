"""Property tests for what crosses into the program beside models: pictures of every format Pillow
writes, mutated and renamed (only PPM, PNG and JPEG load, by content, and nothing escapes but a
LoadError); screenshot output paths of every shape (written whole, or refused with one ViewerError);
polygons of every size (the same normal whichever path computes it); and scene-file numbers of every
size (a finite placement, or one LoadError); tables of repeated rows (equal positions merged as
np.unique merges them).

Derandomized: the same examples every run.
"""

from __future__ import annotations

import io
import subprocess
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from PIL import Image

from marraztu.errors import LoadError, ViewerError
from marraztu.frontends.screenshot import write_picture
from marraztu.loaders.images import image_format, load_image
from marraztu.model import geometry, threads
from marraztu.model.build import build_mesh
from marraztu.model.geometry import FLOAT32_MAX, merged_rows

FUZZ = settings(derandomize=True, database=None, deadline=None, max_examples=150,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
PILLOW_FORMATS = ["PNG", "JPEG", "PPM", "GIF", "BMP", "TIFF", "WEBP", "ICO", "TGA", "PCX", "EPS", "SGI"]
READ = {"PNG", "JPEG", "PPM"}
NAMES = ["t.png", "t.jpg", "t.jpeg", "t.ppm", "t.pnm", "t.gif", "t", "t.PNG", "t.eps"]


def picture_bytes(kind: str, size: tuple[int, int]) -> bytes:
    out = io.BytesIO()
    image = Image.new("RGB", size, (120, 30, 200))
    try:
        image.save(out, format=kind)
    except (OSError, KeyError, ValueError):  # this Pillow cannot write that format
        return b""
    return out.getvalue()


@FUZZ
@given(kind=st.sampled_from(PILLOW_FORMATS), name=st.sampled_from(NAMES),
       size=st.tuples(st.integers(1, 9), st.integers(1, 9)), cut=st.one_of(st.none(), st.integers(0, 64)),
       flips=st.lists(st.tuples(st.integers(0, 200), st.integers(0, 255)), max_size=3))
def test_pictures_of_every_format_load_only_as_ppm_png_or_jpeg(tmp_path: Path, monkeypatch, kind: str, name: str,
                                                              size: tuple[int, int], cut: int | None,
                                                              flips: list[tuple[int, int]]) -> None:
    def no_child(*args, **kwargs):
        raise AssertionError("a texture must never start another program")

    monkeypatch.setattr(subprocess, "Popen", no_child)
    data = bytearray(picture_bytes(kind, size))
    if cut is not None:
        del data[cut:]
    for at, value in flips:
        if at < len(data):
            data[at] = value
    path = tmp_path / name
    path.write_bytes(bytes(data))
    try:
        image = load_image(path)
    except LoadError as error:
        assert error.path == str(path) and "\n" not in str(error)
        return
    assert image_format(bytes(data[:8])) in READ, f"{kind} loaded"
    assert image.dtype == np.uint8 and image.ndim == 3 and image.shape[2] == 3


OUTPUT_NAMES = st.text(alphabet=st.sampled_from(list("ab.-_ /\\\n\x1b~") + ["é", "\u202e"]), min_size=0, max_size=12)
SUFFIXES = st.sampled_from(["", ".png", ".PNG", ".jpg", ".jpeg", ".gif", ".png.obj", ".obj", "/"])


@FUZZ
@given(stem=OUTPUT_NAMES, suffix=SUFFIXES, existing=st.sampled_from(["nothing", "file", "folder", "link"]))
def test_output_paths_are_written_whole_or_refused_in_one_line(tmp_path: Path, stem: str, suffix: str,
                                                               existing: str) -> None:
    folder = tmp_path / "out"
    folder.mkdir(exist_ok=True)
    out = folder / (stem + suffix)
    if out.parent != folder and not out.parent.is_relative_to(folder):
        return  # a name that climbs out of the folder: not this test's business
    try:
        if existing == "file" and out.parent.is_dir() and not out.exists():
            out.write_bytes(b"old")
        elif existing == "folder" and not out.exists():
            out.mkdir(parents=True, exist_ok=True)
        elif existing == "link" and not out.exists() and out.parent.is_dir():
            out.symlink_to(folder / "elsewhere")
    except OSError:
        return  # the name cannot even be made here
    pixels = np.full((3, 4, 3), 77, np.uint8)
    try:
        write_picture(pixels, out)
    except ViewerError as error:
        assert "\n" not in str(error).replace("\\n", "")
        return
    with Image.open(out) as written:
        assert written.size == (4, 3) and written.format in ("PNG", "JPEG")
    assert not [path for path in out.parent.iterdir() if path.name.endswith(".part")]


@settings(derandomize=True, database=None, deadline=None, max_examples=60)
@given(corners=st.integers(3, 400), copies=st.integers(1, 5), tilt=st.floats(-1.0, 1.0))
def test_polygons_of_every_size_get_the_same_normal(corners: int, copies: int, tilt: float) -> None:
    """One size for all (the column-by-column path up to its limit, the general one beyond) or mixed
    with a triangle (the general path): the normal of a flat polygon is its plane's."""
    angles = np.linspace(0.0, 2.0 * np.pi, corners, endpoint=False)
    ring = np.stack([np.cos(angles), np.sin(angles), tilt * np.cos(angles)], axis=1) * 5.0
    positions = np.concatenate([ring + [0.0, 0.0, 20.0 * copy] for copy in range(copies)])
    faces = [list(range(copy * corners, (copy + 1) * corners)) for copy in range(copies)]
    plane = np.array([-tilt, 0.0, 1.0]) / np.hypot(tilt, 1.0)
    alone = build_mesh("alone", positions, faces)
    mixed = build_mesh("mixed", np.concatenate([positions, [[0, 0, 0], [1, 0, 0], [0, 1, 0]]]),
                       faces + [[len(positions), len(positions) + 1, len(positions) + 2]])
    np.testing.assert_allclose(alone.face_normals, np.tile(plane, (copies, 1)), atol=1e-5)
    np.testing.assert_allclose(mixed.face_normals[:copies], alone.face_normals, atol=1e-6)


ROW_VALUES = st.sampled_from([0.0, -0.0, 1.0, -1.0, 0.1, 1e-300, 5e-324, 3.0e38, -1e308, 2.0**52 + 1])


# Keys that collide: none (each row's own), every row's, or rows sharing their first number's (so
# that some keys hold one row's copies and others several rows).
_ROW_KEYS = geometry._row_keys


def _keyed(hashes: Callable[[np.ndarray, np.uint64], np.ndarray]) -> Callable[[np.ndarray, np.uint64], np.ndarray]:
    """Keys as _row_keys makes them from these hashes of the rows: their low bits the row's index."""
    def keys(table: np.ndarray, index_bits: np.uint64) -> np.ndarray:
        return hashes(table, index_bits) >> index_bits << index_bits | np.arange(len(table), dtype=np.uint64)
    return keys


def _last_row_keyed_as_the_middle_one(table: np.ndarray, index_bits: np.uint64) -> np.ndarray:
    """The real keys, but the last row's (and its equals') made the middle row's: one collision, found
    far into the table, in a large one in a later piece. Equal rows keep equal keys."""
    keys = _ROW_KEYS(table, index_bits)
    if len(table):
        hashes = keys >> index_bits
        keys[hashes == hashes[-1]] = keys[len(table) // 2]
    return keys


COLLIDING_KEYS = {
    "none": None,
    "all": _keyed(lambda table, _: np.zeros(len(table), np.uint64)),
    "by first number": _keyed(lambda table, _: (table[:, 0] + 0.0).view(np.uint64) * np.uint64(0x9E3779B97F4A7C15)),
    "last row as the middle one": _keyed(_last_row_keyed_as_the_middle_one),
}


@FUZZ
@given(rows=st.lists(st.tuples(ROW_VALUES, ROW_VALUES, ROW_VALUES), min_size=0, max_size=60),
       colliding=st.sampled_from(sorted(COLLIDING_KEYS)))
def test_equal_rows_merge_as_np_unique_merges_them(rows: list[tuple[float, float, float]], colliding: str) -> None:
    """The same rows in the order first seen, whether each key is its row's or keys collide (those
    rows grouped exactly): -0.0 and 0.0 are one number, as np.unique has them."""
    table = np.array(rows, dtype=np.float64).reshape(-1, 3)
    with pytest.MonkeyPatch.context() as patch:
        if COLLIDING_KEYS[colliding] is not None:
            patch.setattr(geometry, "_row_keys", COLLIDING_KEYS[colliding])
        merged, first, inverse = merged_rows(table)
    expected = np.unique(table, axis=0) if len(table) else table
    assert len(merged) == len(expected) and len(inverse) == len(table)
    np.testing.assert_array_equal(merged[inverse], table)  # each row is its merged row (-0.0 == 0.0)
    np.testing.assert_array_equal(merged, table[first])
    assert (np.diff(first) > 0).all() and (first[inverse] <= np.arange(len(table))).all()  # first seen, first


@pytest.mark.parametrize("colliding", sorted(COLLIDING_KEYS))
def test_a_large_table_merges_as_np_unique_merges_it(colliding: str) -> None:
    """Enough rows that the key's low bits give way to 18 bits of index, and that the key and the
    check of the groups work in several pieces, on threads; seeded."""
    table = np.random.default_rng(7).integers(0, 40, (200_000, 3)).astype(np.float64) / 8.0
    with pytest.MonkeyPatch.context() as patch:
        if COLLIDING_KEYS[colliding] is not None:
            patch.setattr(geometry, "_row_keys", COLLIDING_KEYS[colliding])
        patch.setattr(threads, "THREADS", 4)
        merged, first, inverse = merged_rows(table)
    assert len(merged) == len(np.unique(table, axis=0))
    np.testing.assert_array_equal(merged[inverse], table)
    np.testing.assert_array_equal(merged, table[first])
    assert (np.diff(first) > 0).all() and (first[inverse] <= np.arange(len(table))).all()


CELLS = st.sampled_from([0.0, 0.5, -2.0, 1e30, 1e300, float("nan"), float("inf"), -float("inf")])


@FUZZ
@given(data=st.data(), triangles=st.integers(1, 4), per_vertex=st.sampled_from([None, True, False]))
def test_uvs_and_normals_of_every_shape_make_a_finite_mesh_or_one_value_error(data: st.DataObject, triangles: int,
                                                                               per_vertex: bool | None) -> None:
    """Tables of any row count, width and values, per vertex, per corner or either: a Mesh whose uvs are
    finite and whose normals are unit vectors, each given finite row kept, or a ValueError."""
    vertices = data.draw(st.integers(3, 3 * triangles))
    faces = np.array(data.draw(st.lists(st.lists(st.integers(0, vertices - 1), min_size=3, max_size=3),
                                        min_size=triangles, max_size=triangles)))
    positions = np.random.default_rng(triangles).normal(size=(vertices, 3))
    tables = {}
    for name, width in (("uvs", 2), ("normals", 3)):
        rows = data.draw(st.sampled_from([vertices, faces.size, 0, vertices + 1]))
        shape = (rows, data.draw(st.sampled_from([width, width, 1, 4])))
        cells = data.draw(st.lists(CELLS, min_size=shape[0] * shape[1], max_size=shape[0] * shape[1]))
        tables[name] = data.draw(st.sampled_from([None, np.array(cells).reshape(shape)]))
    try:
        mesh = build_mesh("fuzz", positions, faces, attributes_per_vertex=per_vertex, **tables)
    except ValueError:
        return
    assert np.isfinite(mesh.corner_uv).all() and np.isfinite(mesh.corner_normal).all()
    np.testing.assert_allclose(np.linalg.norm(mesh.corner_normal, axis=1), 1.0, rtol=1e-5)
    uvs = tables["uvs"]
    if uvs is not None:
        by_vertex = per_vertex if per_vertex is not None else len(uvs) == vertices
        given = uvs[faces.reshape(-1)] if by_vertex else uvs
        kept = np.isfinite(given).all(axis=1)
        expected = np.clip(given[kept], -FLOAT32_MAX, FLOAT32_MAX).astype(np.float32)
        np.testing.assert_array_equal(mesh.corner_uv[kept], expected)


@pytest.mark.parametrize("kind", sorted(READ))
def test_the_formats_read_are_known_by_their_first_bytes(kind: str) -> None:
    assert image_format(picture_bytes(kind, (2, 2))[:8]) == kind


TOML_NUMBERS = st.one_of(
    st.integers(-(10**60), 10**60).map(str),
    st.integers(300, 5000).map(lambda digits: "9" * digits),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["1e39", "-1e308", "3.4028235e38", "3.4028236e38", "nan", "+inf", "-inf", "0x7fffffff",
                     "1_000", "1e400", "-0.0", "5e-324"]),
)


@FUZZ
@given(position=st.lists(TOML_NUMBERS, min_size=3, max_size=3), rotation=st.lists(TOML_NUMBERS, min_size=3, max_size=3),
       ns=TOML_NUMBERS)
def test_scene_numbers_load_or_are_one_load_error(tmp_path: Path, position: list[str], rotation: list[str],
                                                  ns: str) -> None:
    from marraztu.loaders.scenefile import load_scene

    (tmp_path / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    text = (f'[materials.m]\nka = [0.1, 0.2, 0.3]\nkd = [0.4, 0.5, 0.6]\nks = [0.7, 0.8, 0.9]\nns = {ns}\n\n'
            f'[[cameras]]\nmodel = "tri.obj"\nposition = [0, 0, 150]\n\n'
            f'[[objects]]\nmodel = "tri.obj"\nposition = [{", ".join(position)}]\n'
            f'rotation = [{", ".join(rotation)}]\nmaterial = "m"\n')
    scene_file = tmp_path / "scene.toml"
    scene_file.write_text(text)
    try:
        scene = load_scene(scene_file)
    except LoadError as error:
        assert error.path == str(scene_file) and "\n" not in str(error)
        return
    model = scene.objects[0].model
    assert np.isfinite(model).all() and np.abs(model[:3, 3]).max() <= np.finfo(np.float32).max
