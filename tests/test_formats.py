"""STL, PLY, OFF and glTF/GLB: written here with trimesh's own exporters, read through the registry,
drawn like the same triangles written as OBJ, and refused in one line naming the file when broken."""

from __future__ import annotations

import gc
import json
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import trimesh
from PIL import Image

from marraztu.control.viewer import StartOptions, Viewer
from marraztu.errors import LoadError
from marraztu.frontends.screenshot import take_screenshot
from marraztu.loaders import exchange, stl
from marraztu.loaders.registry import MODEL_READERS, load_model
from marraztu.loaders.scenefile import empty_scene
from support import corpus
from support.refusals import one_line_refusal
from support.scenes import BACKGROUND, NoFrontend

SIZE = (120, 120)
# A square of two triangles facing the start camera, and a tilted one behind it: a model whose
# picture shows shading, depth and the two faces' order.
POSITIONS = np.array([[-60, -60, 0], [60, -60, 0], [60, 60, 0], [-60, 60, 0],
                      [-30, -30, -40], [40, -30, -10], [0, 50, -25]], dtype=np.float64)
FACES = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6]])
FORMATS = {  # file name -> how trimesh writes it
    "model.stl": lambda mesh: trimesh.exchange.stl.export_stl(mesh),
    "ascii.stl": lambda mesh: trimesh.exchange.stl.export_stl_ascii(mesh).encode(),
    "model.ply": lambda mesh: trimesh.exchange.ply.export_ply(mesh, encoding="binary"),
    "ascii.ply": lambda mesh: trimesh.exchange.ply.export_ply(mesh, encoding="ascii"),
    "model.off": lambda mesh: trimesh.exchange.off.export_off(mesh).encode(),
    "model.glb": lambda mesh: mesh.export(file_type="glb"),
}


def square_mesh() -> trimesh.Trimesh:
    return trimesh.Trimesh(vertices=POSITIONS, faces=FACES, process=False)


def write_obj(path: Path) -> Path:
    lines = [f"v {x:g} {y:g} {z:g}" for x, y, z in POSITIONS] + [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in FACES]
    path.write_text("\n".join(lines) + "\n")
    return path


@pytest.fixture
def written(tmp_path: Path) -> dict[str, Path]:
    files = {}
    for name, export in FORMATS.items():
        files[name] = tmp_path / name
        files[name].write_bytes(export(square_mesh()))
    return files


def picture(path: Path, out: Path, keys: str = "T 0 1") -> np.ndarray:
    shot = take_screenshot(StartOptions(empty=True, models=(path,)), out, SIZE, keys=keys)
    return np.asarray(Image.open(shot).convert("RGB")).astype(int)


def test_every_new_suffix_has_a_reader() -> None:
    assert {".stl", ".ply", ".off", ".gltf", ".glb"} <= set(MODEL_READERS)


@pytest.mark.parametrize("name", FORMATS)
def test_each_format_holds_the_same_model(written: dict[str, Path], name: str) -> None:
    mesh = load_model(written[name])
    assert (mesh.vertex_count, mesh.face_count) == (7, 3), "STL's repeated corners are shared again"
    assert np.allclose(np.sort(mesh.positions, axis=0), np.sort(POSITIONS, axis=0), atol=1e-5)


@pytest.mark.parametrize(("name", "subdivisions"), [("ascii.stl", 5), ("model.ply", 6), ("model.glb", 6)])
@pytest.mark.parametrize("broken", [False, True])
def test_a_large_models_trimesh_objects_are_freed_when_it_is_read(tmp_path: Path, name: str, subdivisions: int,
                                                                  broken: bool) -> None:
    """They refer to one another, so without a collection they, their tables and the file's bytes would
    wait for Python's cycle collector (switched off here, so that only the reader's own run counts),
    after a good file or a refused one (a NaN coordinate) alike."""
    sphere = trimesh.creation.icosphere(subdivisions=subdivisions)  # a file of 1 MB or more
    if broken:
        sphere.vertices[5, 0] = np.nan
    path = tmp_path / name
    path.write_bytes(FORMATS[name](sphere))
    assert path.stat().st_size >= exchange.COLLECT_AFTER_BYTES
    gc.collect()
    gc.disable()
    try:
        if broken:
            with pytest.raises(LoadError, match="not a finite number"):
                load_model(path)
        else:
            assert load_model(path).face_count == len(sphere.faces)
        assert not [item for item in corpus.tracked_objects() if isinstance(item, (trimesh.Trimesh, trimesh.Scene))
                    and item is not sphere]
    finally:
        gc.enable()


@pytest.mark.parametrize("moved_on", [False, True])
def test_the_collection_after_a_read_spares_the_old_generation_unless_it_must(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, moved_on: bool) -> None:
    """The young generations hold trimesh's objects, so only they are collected; where a collection
    during the read moved those objects to the oldest generation, a full collection frees them."""
    sphere = trimesh.creation.icosphere(subdivisions=6)
    path = tmp_path / "model.ply"
    path.write_bytes(FORMATS["model.ply"](sphere))
    if moved_on:  # as an automatic collection during the read would: its survivors go to the oldest generation
        watched = exchange._watched
        monkeypatch.setattr(exchange, "_watched", lambda loaded: (watched(loaded), gc.collect())[0])
    generations: list[int] = []

    def note(phase: str, info: dict[str, int]) -> None:
        if phase == "start":
            generations.append(info["generation"])

    gc.collect()
    gc.disable()
    gc.callbacks.append(note)
    try:
        assert load_model(path).face_count == len(sphere.faces)
        assert not [item for item in corpus.tracked_objects() if isinstance(item, (trimesh.Trimesh, trimesh.Scene))
                    and item is not sphere]
    finally:
        gc.callbacks.remove(note)
        gc.enable()
    # Moved on: the test's own full collection, the young ones', then a full one where it found them alive
    # (an incremental collector's may have freed them already).
    assert generations[:2] == [2, 1] if moved_on else generations == [1]


def test_a_gltf_whose_buffers_lie_beside_it_is_freed_by_its_faces(tmp_path: Path) -> None:
    """Its JSON is small, the buffer beside it large: the faces read say a collection is worth it."""
    sphere = trimesh.creation.icosphere(subdivisions=5)
    for name, data in sphere.export(file_type="gltf").items():
        (tmp_path / name).write_bytes(data)
    path = tmp_path / "model.gltf"
    assert path.stat().st_size < exchange.COLLECT_AFTER_BYTES
    gc.collect()
    gc.disable()
    try:
        assert load_model(path).face_count == len(sphere.faces) >= exchange.COLLECT_AFTER_FACES
        assert not [item for item in corpus.tracked_objects() if isinstance(item, (trimesh.Trimesh, trimesh.Scene))
                    and item is not sphere]
    finally:
        gc.enable()


@pytest.mark.parametrize("suffix", [".stl", ".ply", ".off", ".gltf", ".glb", ".obj"])
def test_a_name_the_system_cannot_take_is_one_load_error(suffix: str) -> None:
    with pytest.raises(LoadError, match="cannot read the file"):
        load_model(f"m\0{suffix}")


@pytest.mark.parametrize(("name", "why"), [("my models", "is a directory, not a file"), ("gone", "no such file"),
                                           ("gone.fbx", "no such file"),
                                           ("notes.txt", "not a model file marraztu reads (by its suffix")])
def test_a_folder_or_a_missing_file_is_said_before_its_suffix(tmp_path: Path, name: str, why: str) -> None:
    """A folder given as a model ('marraztu "my models"', or typed at `f`) was 'not a model file marraztu
    reads (by its suffix: ...)', as was a mistyped name without its suffix: the suffix was blamed."""
    (tmp_path / "my models").mkdir()
    (tmp_path / "notes.txt").write_text("not a model\n")
    with pytest.raises(LoadError) as caught:
        load_model(tmp_path / name)
    assert str(caught.value).startswith(f"{tmp_path / name}: {why}"), caught.value


@pytest.mark.parametrize("suffix", sorted(MODEL_READERS))
def test_a_git_lfs_pointer_in_a_models_place_is_said_so(tmp_path: Path, suffix: str) -> None:
    """A clone without `git lfs pull` holds a small text in each model's place: an STL was 'neither a
    binary STL ... nor an ASCII one', a PLY 'not a PLY file', an OBJ 'no faces'."""
    path = tmp_path / f"model{suffix}"
    path.write_bytes(corpus.git_lfs_pointer(734120))
    assert one_line_refusal(lambda: load_model(path)).message == (
        "a Git LFS pointer, not the model: its 734120 bytes are fetched by `git lfs pull`")


def test_a_model_that_only_begins_as_a_git_lfs_pointer_is_read_by_its_format(tmp_path: Path) -> None:
    """A pointer is under 1024 bytes: a longer file that begins with its words is its format's to refuse."""
    path = tmp_path / "model.obj"
    path.write_bytes(corpus.git_lfs_pointer(5) + b"\n" * 1024)
    assert one_line_refusal(lambda: load_model(path)).message == "no faces (no 'f' statements)"


def test_a_refused_files_bytes_and_tables_are_freed_with_its_error(tmp_path: Path) -> None:
    """The error's traceback would hold the readers' frames, and in them the file's bytes and trimesh's
    tables, for as long as the error is kept (the window keeps it in its load job, in a cycle)."""
    import tracemalloc

    sphere = trimesh.creation.icosphere(subdivisions=5)
    solid = trimesh.exchange.stl.export_stl_ascii(sphere)
    path = tmp_path / "cut.stl"
    path.write_text(solid + "\n" + solid[:solid.rindex("endsolid")])  # refused: its last solid is not closed
    gc.collect()
    gc.disable()
    tracemalloc.start()
    try:
        with pytest.raises(LoadError, match="not closed by 'endsolid'") as refused:
            load_model(path)
        kept = tracemalloc.get_traced_memory()[0]
        assert refused.value.__traceback__ is not None and kept < path.stat().st_size / 4
    finally:
        tracemalloc.stop()
        gc.enable()


def test_running_out_of_memory_is_one_load_error(tmp_path: Path, monkeypatch) -> None:
    def out_of_memory(data: bytes) -> np.ndarray:
        raise MemoryError

    monkeypatch.setattr(stl, "_binary_corners", out_of_memory)
    path = tmp_path / "model.stl"
    path.write_bytes(FORMATS["model.stl"](square_mesh()))
    with pytest.raises(LoadError, match="not enough memory to load this file"):
        load_model(path)


@pytest.mark.parametrize("name", FORMATS)
def test_each_format_is_drawn_as_the_same_triangles_written_as_obj(written: dict[str, Path], name: str,
                                                                   tmp_path: Path) -> None:
    expected = picture(write_obj(tmp_path / "same.obj"), tmp_path / "obj.png")
    drawn = picture(written[name], tmp_path / "drawn.png")
    centre, corner = drawn[SIZE[1] // 2, SIZE[0] // 2], drawn[2, 2]
    assert tuple(corner) == BACKGROUND and tuple(centre) != BACKGROUND  # the square covers the centre
    # Named pixels: the square's centre, a point of the tilted triangle above it, the background.
    for row, column in [(60, 60), (30, 60), (100, 20), (5, 5)]:
        assert np.abs(drawn[row, column] - expected[row, column]).max() <= 1, (name, row, column)
    assert (np.abs(drawn - expected).max(axis=2) > 1).mean() < 0.002


@pytest.mark.parametrize("encoding", ["ascii", "binary_little_endian"])
@pytest.mark.parametrize("keys", ["T 0 1 l", "T 0 1"])
def test_a_plys_quads_are_drawn_as_the_objs_of_the_same_faces(tmp_path: Path, encoding: str, keys: str) -> None:
    """A PLY's polygons are polygons, as an OBJ's: in lines, a quad shows no diagonal; filled, Flat
    lights it with one normal."""
    rng = np.random.default_rng(7)
    grid = [(x * 20.0 - 50, y * 20.0 - 50, float(rng.uniform(-8, 8))) for y in range(6) for x in range(6)]
    faces = []
    for y in range(5):
        for x in range(5):
            a = 6 * y + x
            faces += [[a, a + 1, a + 7, a + 6]] if (x + y) % 2 else [[a, a + 1, a + 7], [a, a + 7, a + 6]]
    obj = tmp_path / "grid.obj"
    obj.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in np.float32(grid).tolist())
                   + "".join("f " + " ".join(str(i + 1) for i in face) + "\n" for face in faces))
    mesh = trimesh.Trimesh(np.float32(grid), [face[:3] for face in faces], process=False)
    ply = tmp_path / "grid.ply"
    exported = trimesh.exchange.ply.export_ply(mesh, encoding="ascii" if encoding == "ascii" else "binary")
    head, body = exported.split(b"end_header\n", 1)
    ply.write_bytes(_ply_with_faces(head, body, len(grid), faces, encoding))
    assert load_model(ply).face_sizes.tolist() == [len(face) for face in faces]
    expected, drawn = picture(obj, tmp_path / "obj.png", keys), picture(ply, tmp_path / "ply.png", keys)
    assert (drawn != np.array(BACKGROUND)).any(axis=2).mean() > 0.02  # not blank
    assert np.array_equal(drawn, expected)
    if keys.endswith("l"):  # the quads' diagonals are what the triangles would add
        triangles = tmp_path / "triangles.obj"
        positions = "".join(line for line in obj.read_text().splitlines(keepends=True) if line.startswith("v "))
        triangles.write_text(positions + "".join(f"f {face[0] + 1} {face[k] + 1} {face[k + 1] + 1}\n"
                                                 for face in faces for k in range(1, len(face) - 1)))
        assert not np.array_equal(picture(triangles, tmp_path / "triangles.png", keys), drawn)


def _ply_with_faces(head: bytes, body: bytes, vertices: int, faces: list[list[int]], encoding: str) -> bytes:
    """trimesh's PLY of the vertices, its faces replaced by these (trimesh writes triangles alone)."""
    lines = head.decode().splitlines()
    at = next(number for number, line in enumerate(lines) if line.startswith("element face"))
    lines[at] = f"element face {len(faces)}"
    header = ("\n".join(lines) + "\nend_header\n").encode()
    if encoding == "ascii":
        rows = body.decode().splitlines()[:vertices]
        return header + ("\n".join(rows) + "\n" + "".join(
            f"{len(face)} {' '.join(map(str, face))}\n" for face in faces)).encode()
    vertex_bytes = vertices * 12
    return header + body[:vertex_bytes] + b"".join(
        np.array([len(face)], "u1").tobytes() + np.array(face, "<i4").tobytes() for face in faces)


def test_gltf_nodes_are_placed_by_their_transforms(tmp_path: Path) -> None:
    scene = trimesh.Scene()
    moved = trimesh.transformations.translation_matrix([30, 0, 0])
    scene.add_geometry(square_mesh(), node_name="moved", transform=moved)
    (tmp_path / "moved.glb").write_bytes(scene.export(file_type="glb"))
    mesh = load_model(tmp_path / "moved.glb")
    assert np.allclose(mesh.bounds[0], POSITIONS.min(axis=0) + [30, 0, 0], atol=1e-5)


def instanced_glb(placements: int) -> bytes:
    """One mesh of three triangles placed `placements` times by the node graph, stored once."""
    scene = trimesh.Scene()
    scene.add_geometry(square_mesh(), geom_name="square", node_name="n0")
    for node in range(1, placements):
        scene.graph.update(frame_to=f"n{node}", geometry="square",
                           matrix=trimesh.transformations.translation_matrix([200 * node, 0, 0]))
    return scene.export(file_type="glb")


def test_a_mesh_placed_many_times_is_refused_before_it_is_copied(tmp_path: Path,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    from marraztu.loaders import exchange

    (tmp_path / "many.glb").write_bytes(instanced_glb(40))
    assert load_model(tmp_path / "many.glb").face_count == 40 * len(FACES)  # placed, as drawn
    # The real limit is the largest binary STL's triangles; a smaller one keeps the test small.
    assert exchange.MAX_PLACED_TRIANGLES == ((1 << 30) - 84) // 50
    monkeypatch.setattr(exchange, "MAX_PLACED_TRIANGLES", 40 * len(FACES) - 1)
    copies = []
    monkeypatch.setattr(exchange, "_placed_positions", lambda *placed: copies.append(placed))
    with pytest.raises(LoadError) as caught:
        load_model(tmp_path / "many.glb")
    assert str(caught.value).startswith(str(tmp_path / "many.glb"))
    words = "places its meshes 40 times, 120 triangles and 280 vertices in all: more than the 119"
    assert words in caught.value.message
    assert copies == []


def test_a_mesh_of_many_vertices_placed_many_times_is_counted_by_the_vertices_it_is_handed(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Few triangles, many vertices: the vertices are what the memory holds, and each placement is handed
    only those its triangle uses (rewrite._used_vertices_made_own), 3 of the 100, so 15 in all are read,
    where the count took the whole accessor each placement and refused 500."""
    from marraztu.loaders import exchange

    sparse = trimesh.Trimesh(np.random.default_rng(5).normal(size=(100, 3)), [[0, 1, 2]], process=False)
    scene = trimesh.Scene()
    for node in range(5):
        scene.add_geometry(sparse, geom_name="sparse", node_name=f"n{node}",
                           transform=trimesh.transformations.translation_matrix([10 * node, 0, 0]))
    (tmp_path / "sparse.glb").write_bytes(scene.export(file_type="glb"))
    monkeypatch.setattr(exchange, "MAX_PLACED_TRIANGLES", 100)  # 5 triangles pass; 500 vertices are past 300
    assert len(load_model(tmp_path / "sparse.glb").positions) == 15
    monkeypatch.setattr(exchange, "MAX_PLACED_TRIANGLES", 4)  # 15 vertices are past 12
    with pytest.raises(LoadError, match="5 triangles and 15 vertices"):
        load_model(tmp_path / "sparse.glb")


def test_a_textured_mesh_placed_many_times_is_read_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A material's picture is read and hashed to find equal materials: once per picture, not per
    placement, which would cost placements x pixels."""
    from marraztu.loaders import exchange

    scene = trimesh.Scene()
    scene.add_geometry(textured_square((250, 0, 0), 0.0), geom_name="square", node_name="n0")
    for node in range(1, 50):
        scene.graph.update(frame_to=f"n{node}", geometry="square",
                           matrix=trimesh.transformations.translation_matrix([100 * node, 0, 0]))
    (tmp_path / "tiles.glb").write_bytes(scene.export(file_type="glb"))
    calls: list[str] = []
    for helper in ("picture_rgb", "_vertex_uvs"):
        real = getattr(exchange, helper)
        monkeypatch.setattr(exchange, helper, lambda *given, real=real, helper=helper: (calls.append(helper),
                                                                                        real(*given))[1])
    loaded = load_model(tmp_path / "tiles.glb")
    assert loaded.face_count == 100 and len(loaded.materials) == 1
    assert sorted(calls) == ["_vertex_uvs", "picture_rgb"]


def test_a_node_graph_with_a_cycle_is_one_load_error(tmp_path: Path) -> None:
    files = trimesh.Scene([square_mesh()]).export(file_type="gltf")
    document = json.loads(files["model.gltf"])
    first = len(document["nodes"])
    document["nodes"] += [{"name": "c", "children": [first + 1]}, {"name": "d", "children": [first], "mesh": 0}]
    document["scenes"][0]["nodes"].append(first)
    for name, content in files.items():
        (tmp_path / name).write_bytes(json.dumps(document).encode() if name == "model.gltf" else content)
    with pytest.raises(LoadError, match=rf"not a glTF file: node {first + 1} is its own ancestor"):
        load_model(tmp_path / "model.gltf")


def test_gltf_json_beside_its_buffer_and_its_base_colour(tmp_path: Path) -> None:
    mesh = square_mesh()
    mesh.visual = trimesh.visual.TextureVisuals(
        material=trimesh.visual.material.PBRMaterial(baseColorFactor=[255, 128, 0, 255]))
    for name, data in trimesh.Scene(mesh).export(file_type="gltf").items():
        (tmp_path / name).write_bytes(data)
    loaded = load_model(tmp_path / "model.gltf")
    assert loaded.face_count == 3
    assert np.allclose(loaded.file_material["kd"], (1.0, 128 / 255, 0.0), atol=1e-3)


@pytest.mark.parametrize("textured", [True, False])
def test_a_gltf_material_without_a_base_colour_factor_is_white(tmp_path: Path, textured: bool) -> None:
    """glTF's baseColorFactor defaults to white, and Blender leaves it out of a material whose colour
    is its texture: such a material was lit with the viewer's Kd of 0.7, not the file's 1."""
    picture = Image.new("RGB", (4, 4), (0, 250, 0)) if textured else None
    mesh = square_with(trimesh.visual.material.PBRMaterial(name="leaf", baseColorTexture=picture), uv=textured)
    files = trimesh.Scene(mesh).export(file_type="gltf")
    document = json.loads(files["model.gltf"])
    for material in document["materials"]:
        material.get("pbrMetallicRoughness", {}).pop("baseColorFactor", None)
    for name, content in files.items():
        (tmp_path / name).write_bytes(json.dumps(document).encode() if name == "model.gltf" else content)
    loaded = load_model(tmp_path / "model.gltf")
    kd = loaded.materials[0].values["kd"] if textured else loaded.file_material["kd"]
    assert kd == (1.0, 1.0, 1.0)


def coloured_mesh(colours: np.ndarray) -> trimesh.Trimesh:
    mesh = square_mesh()
    mesh.visual.vertex_colors = colours
    return mesh


TINT = np.array([200, 90, 30, 255])  # one colour for every vertex


@pytest.mark.parametrize("encoding", ["binary", "ascii"])
def test_ply_vertex_colours_tint_the_lit_colour(tmp_path: Path, encoding: str) -> None:
    path = tmp_path / "coloured.ply"
    path.write_bytes(trimesh.exchange.ply.export_ply(coloured_mesh(np.tile(TINT, (7, 1))), encoding=encoding))
    assert np.array_equal(load_model(path).vertex_colours, np.tile(TINT[:3], (7, 1)))
    plain = picture(write_obj(tmp_path / "same.obj"), tmp_path / "obj.png")
    tinted = picture(path, tmp_path / "tinted.png")
    model = np.any(plain != BACKGROUND, axis=2)
    # Analytic, to 1/255: each pixel of the model is the lit colour times the vertex colour.
    expected = np.rint(plain * (TINT[:3] / 255.0))
    assert model.mean() > 0.15
    assert np.abs(tinted[model] - expected[model]).max() <= 1
    assert np.array_equal(tinted[~model], plain[~model])


def test_vertex_colours_take_the_scene_pictures_place(tmp_path: Path) -> None:
    """A coloured scan without uvs wore the scene's test picture (an arrow, "TOP", "F") over its own
    colours, with the texture on: its colours are its surface, as a model's own texture is."""
    path = tmp_path / "coloured.ply"
    path.write_bytes(trimesh.exchange.ply.export_ply(coloured_mesh(np.tile(TINT, (7, 1)))))
    untextured = picture(write_obj(tmp_path / "same.obj"), tmp_path / "obj.png")
    textured_plain = picture(write_obj(tmp_path / "same.obj"), tmp_path / "obj_t.png", keys="0 1")
    tinted = picture(path, tmp_path / "tinted.png", keys="0 1")
    model = np.any(untextured != BACKGROUND, axis=2)
    assert (textured_plain[model] != untextured[model]).any()  # the scene's picture shows on a plain model
    expected = np.rint(untextured * (TINT[:3] / 255.0))
    assert np.abs(tinted[model] - expected[model]).max() <= 1


def test_the_probe_of_a_vertex_coloured_face_says_no_picture_multiplies_it(tmp_path: Path) -> None:
    from marraztu.model.probe import probe

    path = tmp_path / "coloured.ply"
    path.write_bytes(trimesh.exchange.ply.export_ply(coloured_mesh(np.tile(TINT, (7, 1)))))
    plain = write_obj(tmp_path / "same.obj")
    found = {}
    for model in (path, plain):
        viewer = Viewer(empty_scene(), NoFrontend())
        viewer.start(StartOptions(empty=True, models=(model,)), longest_texture_side=64)
        found[model.suffix] = probe(viewer.scene)
    assert viewer.scene.modes.texture and found[".obj"].textured and not found[".ply"].textured


def test_vertex_colours_are_flat_in_flat_and_blended_in_gouraud(tmp_path: Path) -> None:
    colours = np.tile([0, 255, 0, 255], (7, 1))
    colours[0] = [255, 0, 0, 255]  # the square's two polygons both start at vertex 0
    path = tmp_path / "corner.ply"
    path.write_bytes(trimesh.exchange.ply.export_ply(coloured_mesh(colours)))
    flat = picture(path, tmp_path / "flat.png")
    gouraud = picture(path, tmp_path / "gouraud.png", keys="T 0 1 F")
    plain_gouraud = picture(write_obj(tmp_path / "same.obj"), tmp_path / "plain.png", keys="T 0 1 F")
    # Flat: the whole square takes its first vertex's colour, red; the green channel is gone.
    square = flat[45:75, 45:75]
    assert square[..., 0].min() > 0 and square[..., 1].max() == 0
    # Gouraud: red at vertex 0's corner (bottom left) fading to green at the far corner (top right).
    near, far = gouraud[84, 35], gouraud[35, 84]  # the square's corners, framed
    assert near[0] > 10 * near[1] and far[1] > 10 * far[0]
    assert np.array_equal(gouraud[2, 2], plain_gouraud[2, 2])  # the background is untouched


def test_glb_vertex_colours_are_read(tmp_path: Path) -> None:
    path = tmp_path / "coloured.glb"
    path.write_bytes(coloured_mesh(np.tile(TINT, (7, 1))).export(file_type="glb"))
    assert np.array_equal(load_model(path).vertex_colours, np.tile(TINT[:3], (7, 1)))


def _cut(data: bytes) -> bytes:
    return data[: len(data) * 2 // 3]


def _nan(data: bytes) -> bytes:
    """The first coordinate of the first vertex (after STL's 'vertex', PLY's header, OFF's counts)."""
    text = data.decode()
    start = max(text.find("vertex "), text.find("end_header"), 0) if "facet" in text or "ply" in text[:3] else \
        text.index("\n", text.index("\n") + 1)
    found = re.compile(r"-?\d+\.\d+(e[-+]\d+)?").search(text, start)
    return (text[:found.start()] + "nan" + text[found.end():]).encode()


def _far_index(data: bytes) -> bytes:
    lines = data.decode().splitlines()
    lines[-1] = " ".join(lines[-1].split()[:-1] + ["99"])
    return ("\n".join(lines) + "\n").encode()


@pytest.mark.parametrize(("name", "damage", "line"), [
    ("ascii.stl", _cut, True), ("ascii.stl", _nan, True), ("model.stl", _cut, True),
    ("ascii.ply", _cut, True), ("ascii.ply", _nan, True), ("ascii.ply", _far_index, True),
    ("model.ply", _cut, False), ("model.off", _cut, True), ("model.off", _nan, True),
    ("model.off", _far_index, True), ("model.glb", _cut, False),
    ("model.glb", lambda data: b"glTF" + bytes(40), False), ("model.off", lambda data: b"", False),
    ("model.stl", lambda data: b"\x89PNG\r\n\x1a\n" + bytes(100), True),
])
def test_a_broken_file_is_one_load_error_naming_it(written: dict[str, Path], name: str, damage, line: bool) -> None:
    path = written[name]
    path.write_bytes(damage(path.read_bytes()))
    with pytest.raises(LoadError) as raised:
        load_model(path)
    assert raised.value.path == str(path) and "\n" not in str(raised.value)
    assert (raised.value.line is not None) == line, str(raised.value)


def test_a_readers_module_is_imported_only_when_a_file_of_its_kind_is_opened(tmp_path: Path) -> None:
    """A start on OBJ files (the built-in scene's) imports no other reader; an STL brings its own alone."""
    (tmp_path / "m.stl").write_bytes(FORMATS["model.stl"](square_mesh()))
    others = ["marraztu.loaders.stl", "marraztu.loaders.off", "marraztu.loaders.exchange", "marraztu.loaders.ply",
              "marraztu.loaders.gltf"]
    code = ("import sys; from marraztu.cli import main; from marraztu.loaders.registry import load_model; "
            f"main(['screenshot', '-o', {str(tmp_path / 'x.png')!r}, '--size', '32x32']); "
            f"print([name in sys.modules for name in {others!r}]); "
            f"load_model({str(tmp_path / 'm.stl')!r}); print([name in sys.modules for name in {others!r}])")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.splitlines()[-2:] == [str([False] * 5), str([True, False, False, False, False])]


def test_trimesh_is_imported_only_when_such_a_file_is_opened(tmp_path: Path) -> None:
    """Start-up, OBJ and STL loads stay as light as they were (the STL readers are ours); a PLY brings
    trimesh in."""
    model = write_obj(tmp_path / "m.obj")
    (tmp_path / "m.stl").write_bytes(FORMATS["model.stl"](square_mesh()))
    (tmp_path / "a.stl").write_bytes(FORMATS["ascii.stl"](square_mesh()))
    (tmp_path / "m.ply").write_bytes(FORMATS["model.ply"](square_mesh()))
    code = ("import sys; from marraztu.cli import main; from marraztu.loaders.registry import load_model; "
            f"main(['screenshot', '-o', {str(tmp_path / 'x.png')!r}, '--size', '32x32', {str(model)!r}]); "
            f"load_model({str(tmp_path / 'm.stl')!r}); load_model({str(tmp_path / 'a.stl')!r}); "
            "print('trimesh' in sys.modules); "
            f"load_model({str(tmp_path / 'm.ply')!r}); print('trimesh' in sys.modules)")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert result.stdout.split()[-2:] == ["False", "True"]


def test_a_glb_base_colour_texture_is_drawn_with_its_uvs(tmp_path: Path) -> None:
    """Its picture is the model's own material texture, as an OBJ's map_Kd: the square's left half
    red and its right half blue in the picture, texture on; one colour with T."""
    picture_rgb = np.zeros((8, 8, 3), np.uint8)
    picture_rgb[:, :4] = (250, 0, 0)
    picture_rgb[:, 4:] = (0, 0, 250)
    mesh = trimesh.Trimesh(vertices=POSITIONS[:4], faces=FACES[:2], process=False)
    mesh.visual = trimesh.visual.TextureVisuals(uv=[[0, 0], [1, 0], [1, 1], [0, 1]], image=Image.fromarray(picture_rgb))
    (tmp_path / "tex.glb").write_bytes(mesh.export(file_type="glb"))
    loaded = load_model(tmp_path / "tex.glb")
    assert loaded.materials[0].texture.shape == (8, 8, 3)
    drawn = picture(tmp_path / "tex.glb", tmp_path / "on.png", keys="0")
    left, right = drawn[60, 42], drawn[60, 78]  # the framed square spans about 36..84
    assert left[0] > left[2] + 30 and right[2] > right[0] + 30
    plain = picture(tmp_path / "tex.glb", tmp_path / "off.png", keys="0 T")
    assert np.abs(plain[60, 42] - plain[60, 78]).max() <= 2


def textured_square(colour: tuple[int, int, int], x: float) -> trimesh.Trimesh:
    square = trimesh.Trimesh(vertices=POSITIONS[:4] * 0.4 + [x, 0, 0], faces=FACES[:2], process=False)
    square.visual = trimesh.visual.TextureVisuals(uv=[[0, 0], [1, 0], [1, 1], [0, 1]],
                                                  image=Image.new("RGB", (4, 4), colour))
    return square


def test_each_mesh_of_a_glb_keeps_its_own_texture(tmp_path: Path) -> None:
    """Two meshes, a red picture and a green one: two materials, as an OBJ's two groups, each square
    drawn with its own (not the first mesh's picture over every mesh, nor one packed by trimesh)."""
    scene = trimesh.Scene([textured_square((250, 0, 0), -30.0), textured_square((0, 250, 0), 30.0)])
    (tmp_path / "two.glb").write_bytes(scene.export(file_type="glb"))
    loaded = load_model(tmp_path / "two.glb")
    assert sorted(material.texture[0, 0].tolist() for material in loaded.materials) == [[0, 250, 0], [250, 0, 0]]
    assert sorted(loaded.face_material.tolist()) == [0, 0, 1, 1] and loaded.warnings == ()
    assert loaded.face_material[0] == loaded.face_material[1] != loaded.face_material[2] == loaded.face_material[3]
    drawn = picture(tmp_path / "two.glb", tmp_path / "two.png", keys="0")
    left, right = drawn[60, 38], drawn[60, 82]
    assert left[0] > 40 and left[1] == left[2] == 0, left
    assert right[1] > 40 and right[0] == right[2] == 0, right


def glb_of(tmp_path: Path, name: str, *meshes: trimesh.Trimesh) -> Path:
    """Each mesh placed by a node of its own, in this order."""
    scene = trimesh.Scene()
    for number, mesh in enumerate(meshes):
        scene.add_geometry(mesh, node_name=f"n{number}", geom_name=f"g{number}",
                           transform=trimesh.transformations.translation_matrix([60.0 * number, 0, 0]))
    (tmp_path / name).write_bytes(scene.export(file_type="glb"))
    return tmp_path / name


def square_with(material: trimesh.visual.material.Material | None = None, uv: bool = False) -> trimesh.Trimesh:
    visual = trimesh.visual.TextureVisuals(uv=[[0, 0], [1, 0], [1, 1], [0, 1]] if uv else None, material=material)
    return trimesh.Trimesh(POSITIONS[:4] * 0.4, FACES[:2], process=False, visual=visual)


def test_a_mesh_without_a_colour_of_its_own_takes_the_viewers_not_the_first_meshs(tmp_path: Path) -> None:
    red = trimesh.visual.material.PBRMaterial(name="red", baseColorFactor=[255, 0, 0, 255])
    plain = trimesh.Trimesh(POSITIONS[:4] * 0.4, FACES[:2])
    loaded = load_model(glb_of(tmp_path, "mixed.glb", square_with(red), plain))
    assert loaded.file_material is None and [material.name for material in loaded.materials] == ["red"]
    assert sorted(loaded.face_material.tolist()) == [-1, -1, 0, 0]  # trimesh lists the nodes in its own order


def test_a_shared_material_keeps_its_texture_for_the_meshes_with_uvs(tmp_path: Path) -> None:
    """The first mesh using it has no uvs (no texture drawn there); the second has them."""
    shared = trimesh.visual.material.PBRMaterial(name="shared", baseColorFactor=[255, 255, 255, 255],
                                                 baseColorTexture=Image.new("RGB", (4, 4), (250, 0, 0)))
    loaded = load_model(glb_of(tmp_path, "shared.glb", square_with(shared), square_with(shared, uv=True)))
    textures = [material.texture for material in loaded.materials]
    assert len(textures) == 2 and sum(texture is None for texture in textures) == 1
    assert [texture[0, 0].tolist() for texture in textures if texture is not None] == [[250, 0, 0]]


def test_equal_materials_are_one_material_even_as_copies(tmp_path: Path) -> None:
    picture = Image.new("RGB", (4, 4), (0, 250, 0))
    meshes = [square_with(trimesh.visual.material.PBRMaterial(name="green", baseColorTexture=picture), uv=True)
              for _ in range(3)]
    loaded = load_model(glb_of(tmp_path, "copies.glb", *meshes))
    assert [material.name for material in loaded.materials] == ["green"] and set(loaded.face_material) == {0}


def test_many_materials_sharing_a_picture_hash_it_once(monkeypatch: pytest.MonkeyPatch) -> None:
    from marraztu.loaders import exchange

    picture = Image.new("RGB", (64, 64), (0, 250, 0))
    scene = trimesh.Scene([square_with(trimesh.visual.material.PBRMaterial(name=f"m{number}", baseColorTexture=picture),
                                       uv=True) for number in range(20)])
    hashed: list[object] = []
    real = exchange.picture_rgb  # each picture read, and its key hashed from what it reads, once
    monkeypatch.setattr(exchange, "picture_rgb", lambda given: (hashed.append(given), real(given))[1])
    materials = exchange.mesh_of_trimesh("tiles", scene).materials
    assert len(materials) == 20 and len(hashed) == 1  # named apart: twenty materials, one picture
    assert len({id(material.texture) for material in materials}) == 1  # one array: uploaded once


def test_gltf_vertex_colours_beside_a_material_tint(tmp_path: Path) -> None:
    """trimesh keeps a COLOR_0 that comes with a material as a vertex attribute, not as the visual."""
    mesh = square_with(trimesh.visual.material.PBRMaterial(name="white", baseColorFactor=[255, 255, 255, 255]), uv=True)
    mesh.visual.vertex_attributes["color"] = np.tile(np.array([0, 255, 0, 255], np.uint8), (4, 1))
    loaded = load_model(glb_of(tmp_path, "tinted.glb", mesh))
    assert np.array_equal(loaded.vertex_colours, np.tile([0, 255, 0], (4, 1)))


def test_a_transform_of_nan_is_one_load_error(tmp_path: Path) -> None:
    scene = trimesh.Scene()
    scene.add_geometry(square_mesh(), node_name="bad", transform=np.full((4, 4), np.nan))
    (tmp_path / "nan.glb").write_bytes(scene.export(file_type="glb"))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(LoadError, match="not a finite number"):
            load_model(tmp_path / "nan.glb")


def test_a_mirroring_node_keeps_its_mesh_facing_out(tmp_path: Path) -> None:
    """glTF turns the winding round under a transform of negative determinant: the mirrored square
    still faces the camera, so culling back faces leaves it drawn."""
    scene = trimesh.Scene()
    scene.add_geometry(square_mesh(), node_name="mirrored", transform=np.diag([-1.0, 1.0, 1.0, 1.0]))
    (tmp_path / "mirrored.glb").write_bytes(scene.export(file_type="glb"))
    loaded = load_model(tmp_path / "mirrored.glb")
    assert loaded.face_normals[0] @ [0.0, 0.0, 1.0] > 0.99
    culled = picture(tmp_path / "mirrored.glb", tmp_path / "culled.png", keys="T 0 1 b")
    assert (culled[45:75, 45:75] != BACKGROUND).any(axis=2).all()


def test_per_vertex_uvs_are_kept_per_position(tmp_path: Path) -> None:
    """A glTF's texture coordinates are one per vertex, as are its derived normals: the mesh stores
    them once per position, and every corner reads its vertex's own."""
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float64)
    mesh = trimesh.Trimesh(vertices=POSITIONS[:4], faces=FACES[:2], process=False)
    mesh.visual = trimesh.visual.TextureVisuals(uv=uv, image=Image.fromarray(np.zeros((4, 4, 3), np.uint8)))
    (tmp_path / "uv.glb").write_bytes(mesh.export(file_type="glb"))
    loaded = load_model(tmp_path / "uv.glb")
    assert loaded.attributes_per_position and loaded.uvs.shape == (loaded.vertex_count, 2)
    by_position = {tuple(np.round(p, 4)): tuple(t) for p, t in zip(POSITIONS[:4], uv)}
    for corner, vertex in enumerate(loaded.corner_vertex):  # glTF stores v upside down: trimesh flips it back
        assert tuple(loaded.corner_uv[corner]) == by_position[tuple(np.round(loaded.positions[vertex], 4))]


def test_an_ascii_stl_of_several_solids_is_one_model_of_them_all(tmp_path: Path) -> None:
    solids = [trimesh.exchange.stl.export_stl_ascii(trimesh.Trimesh(POSITIONS + [0, 0, shift], FACES, process=False))
              for shift in (0, 100)]
    path = tmp_path / "two.stl"
    path.write_text("\n".join(solids))
    mesh = load_model(path)
    assert (mesh.vertex_count, mesh.face_count) == (14, 6)


def test_an_ascii_stls_last_solid_without_its_endsolid_is_refused_not_dropped(tmp_path: Path) -> None:
    """trimesh reads the solids that end and drops the last one."""
    solid = trimesh.exchange.stl.export_stl_ascii(square_mesh())
    path = tmp_path / "cut.stl"
    path.write_text(solid + "\n" + solid[:solid.rindex("endsolid")])
    second = solid.count("\n") + 2
    with pytest.raises(LoadError, match=f"the solid begun on line {second} is not closed by 'endsolid'"):
        load_model(path)


def test_a_files_first_word_is_found_without_copying_the_file(tmp_path: Path) -> None:
    """Whether an STL is empty or starts with 'solid' is searched for, not found by strip() and
    lstrip(), which copied the whole file to look at its first word."""
    from support.work import peak_traced_bytes

    path = tmp_path / "blank.stl"
    path.write_bytes(b"not solid\n" + b"x\n" * (1 << 20))  # strip() copied all but the last newline
    error, peak = peak_traced_bytes(lambda: load_model(path))
    assert isinstance(error, LoadError) and "does not start with 'solid'" in error.message
    assert peak < 3 * path.stat().st_size // 2, peak  # the bytes read, once


@pytest.mark.parametrize("encoding", ["binary", "ascii"])
def test_a_ply_with_uvs_and_no_picture_has_no_texture(tmp_path: Path, encoding: str) -> None:
    """trimesh gives such uvs a 2x2 grey stand-in picture: it is no texture, so the scene's shows."""
    uvs = POSITIONS[:, :2] / 120.0 + 0.5
    mesh = trimesh.Trimesh(POSITIONS, FACES, process=False, visual=trimesh.visual.TextureVisuals(uv=uvs))
    path = tmp_path / "uv.ply"
    path.write_bytes(trimesh.exchange.ply.export_ply(mesh, encoding=encoding))
    loaded = load_model(path)
    assert loaded.materials == () and loaded.attributes_per_position
    assert np.allclose(loaded.uvs, uvs)


@pytest.mark.parametrize("encoding", ["ascii", "binary_little_endian"])
def test_a_plys_diffuse_colours_are_its_vertex_colours(tmp_path: Path, encoding: str) -> None:
    """Some writers name a vertex's colour diffuse_red/green/blue, which trimesh passed over: not drawn,
    and no note said so."""
    rows = [((0, 0, 0), (0, 255, 0)), ((1, 0, 0), (255, 0, 0)), ((0, 1, 0), (0, 0, 255))]
    header = (f"ply\nformat {encoding} 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "property uchar diffuse_red\nproperty uchar diffuse_green\nproperty uchar diffuse_blue\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n").encode()
    if encoding == "ascii":
        body = "".join(f"{x} {y} {z} {r} {g} {b}\n" for (x, y, z), (r, g, b) in rows).encode() + b"3 0 1 2\n"
    else:
        vertex = np.dtype([("p", "<f4", 3), ("c", "u1", 3)])
        body = np.array(rows, vertex).tobytes() + np.array([3], "u1").tobytes() + np.array([0, 1, 2], "<i4").tobytes()
    path = tmp_path / "diffuse.ply"
    path.write_bytes(header + body)
    assert load_model(path).vertex_colours.tolist() == [list(colour) for _, colour in rows]


@pytest.mark.parametrize(("channels", "notes"), [
    (["diffuse_red"], ("vertex colours not drawn: diffuse_red without diffuse_green and diffuse_blue",)),
    (["red", "blue"], ("vertex colours not drawn: red and blue without green",)),
    (["red", "diffuse_green", "diffuse_blue"], ("vertex colours not drawn: red without green and blue",
                                                "vertex colours not drawn: diffuse_green and diffuse_blue without "
                                                "diffuse_red")),
    (["alpha"], ()),
    (["red", "green", "blue", "diffuse_red"], ()),  # drawn: the first names trimesh reads
])
def test_a_plys_colour_of_only_some_channels_is_not_drawn_with_a_note(tmp_path: Path, channels: list[str],
                                                                       notes: tuple) -> None:
    """trimesh passes over a colour short of a channel without a word."""
    names = "".join(f"property uchar {channel}\n" for channel in channels)
    values = " 200" * len(channels)
    path = tmp_path / "partial.ply"
    path.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                    f"{names}element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                    f"0 0 0{values}\n1 0 0{values}\n0 1 0{values}\n3 0 1 2\n")
    loaded = load_model(path)
    assert loaded.warnings == notes and (loaded.vertex_colours is None) == ("green" not in channels)


@pytest.mark.parametrize("prefix", ["", "diffuse_"])
@pytest.mark.parametrize(("first", "colour", "notes"), [
    ("0.25", [64, 128, 128], ()), ("1e30", [255, 128, 128], ("1 vertex colour outside 0..1 held to it",)),
    ("-5", [0, 128, 128], ("1 vertex colour outside 0..1 held to it",)), ("nan", None, ()), ("-inf", None, ()),
])
def test_a_plys_float_colours_are_checked(tmp_path: Path, prefix: str, first: str, colour: list | None,
                                          notes: tuple) -> None:
    """trimesh made NaN 0 and 1e30 255 without a word: a NaN is refused as in every model, and a
    value outside 0..1 held to it with a note, as an OBJ's is."""
    names = "".join(f"property float {prefix}{channel}\n" for channel in ("red", "green", "blue"))
    path = tmp_path / "floats.ply"
    path.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                    f"{names}element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                    f"0 0 0 {first} 0.5 0.5\n1 0 0 0.5 0.5 0.5\n0 1 0 0.5 0.5 0.5\n3 0 1 2\n")
    if colour is None:
        refused = one_line_refusal(lambda: load_model(path))
        assert str(refused) == f"{path}: its vertex colours hold a NaN or an infinity"
        return
    loaded = load_model(path)
    assert loaded.vertex_colours[0].tolist() == colour and loaded.warnings == notes


@pytest.mark.parametrize("prefix", ["", "diffuse_"])
@pytest.mark.parametrize(("kind", "first", "colour", "notes"), [
    ("int", "300", [255, 20, 30], ("1 vertex colour outside 0..255 held to it",)),
    ("char", "-5", [0, 20, 30], ("1 vertex colour outside 0..255 held to it",)),
    ("ushort", "200", [200, 20, 30], ()),
])
def test_a_plys_whole_number_colours_past_a_byte_are_held_to_it(tmp_path: Path, prefix: str, kind: str, first: str,
                                                                 colour: list, notes: tuple) -> None:
    """trimesh wrapped an int's 300 to 44 and a char's -5 to 251 without a word."""
    names = "".join(f"property {kind} {prefix}{channel}\n" for channel in ("red", "green", "blue"))
    path = tmp_path / "whole.ply"
    path.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                    f"{names}element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                    f"0 0 0 {first} 20 30\n1 0 0 10 20 30\n0 1 0 10 20 30\n3 0 1 2\n")
    loaded = load_model(path)
    assert loaded.vertex_colours.tolist() == [colour, [10, 20, 30], [10, 20, 30]] and loaded.warnings == notes
