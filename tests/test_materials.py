"""MTL materials whole: each `usemtl` group lit with its own Ka, Kd, Ks and Ns, a `map_Kd` texture read
beside its MTL and drawn on its faces only, notes for what is missing, the scene file's material
over the file's, and the probe and status line naming the selected face's material."""

from __future__ import annotations

import gc
import os
import shutil
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from marraztu.control.viewer import StartOptions, Viewer
from marraztu.devtools import assetgen
from marraztu.frontends.screenshot import take_screenshot
from marraztu.loaders.obj import fast, load_obj, parse_obj
from marraztu.loaders.obj.fast import read_fast
from marraztu.loaders.obj.lines import read_by_lines
from marraztu.loaders.obj.raw import MaterialRuns
from marraztu.loaders.registry import load_model
from marraztu.loaders.scenefile import DEFAULT_MATERIAL, empty_scene, load_scene
from marraztu.model.lights import AMBIENT_INTENSITY
from marraztu.model.mesh import Mesh
from marraztu.model.scene import SceneObject
from marraztu.render.renderer import DrawItem, part_of_face, split_by_material
from marraztu.resources import ASSET_DIR
from marraztu.text.panels import probe_lines
from marraztu.text.status import status_line
from support import corpus
from support.corpus import git_lfs_pointer
from support.scenes import NoFrontend

EXAMPLES = ASSET_DIR / assetgen.EXAMPLE_DIR
SIZE = (160, 160)
TRIANGLES = "v 0 0 0\nv 1 0 0\nv 0 1 0\n" + "f 1 2 3\n"


def ambient_bytes(material: str) -> np.ndarray:
    """What a face of `material` shows at the start (ambient light only, texture off): Ka * Ia."""
    return np.round(np.array(assetgen.EXAMPLE_MATERIALS[material][0]) * AMBIENT_INTENSITY).astype(int)


def picture(tmp_path: Path, model: Path, keys: str = "", name: str = "shot.png", **options) -> np.ndarray:
    out = take_screenshot(StartOptions(empty=True, models=(model,), **options), tmp_path / name, SIZE, keys=keys)
    return np.asarray(Image.open(out).convert("RGB")).astype(int)


# --- reading ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("text", [
    "usemtl a\n" + TRIANGLES + "usemtl b\nf 1 2 3\nf 1 2 3\n  usemtl c d\nf 1 2 3\nusemtl a\n",
    TRIANGLES + "usemtl b\n" + "f 1 2 3\nusemtl a\n" * 500,
    "g x\r\nusemtl a # a comment\r\n" + TRIANGLES.replace("\n", "\r\n"),
    "usemtl a\nusemtl b\n" + TRIANGLES + "usemtl c\ng y\nusemtl d\nf 1 2 3\nusemtl e\n",  # runs that take no face
    TRIANGLES + "usemtl a\nf 1 2 3\n" * 300 + "usemtl  a\nf 1 2 3\nusemtl b\nusemtl a\nf 1 2 3\n",  # one run
    TRIANGLES + "usemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\n" * 300,  # a run per face
    TRIANGLES + "".join(f"usemtl m{k % 100}\nf 1 2 3\ng\nusemtl m{k % 7}\n" for k in range(400)),  # past 64 names
    TRIANGLES + "".join(f"usemtl{' ' * (1 + k % 3)}m{k % 90}\nf 1 2 3\n" for k in range(900)),  # one name, other bytes
])
def test_both_readers_find_the_same_material_runs(text: str) -> None:
    data = text.encode()
    runs = read_fast(data, "m.obj").material_runs.as_pairs()
    assert runs == read_by_lines(data, "m.obj").material_runs.as_pairs()
    assert all(before[1] != after[1] for before, after in zip(runs, runs[1:]))  # a name goes on with its run


def test_usemtl_lines_past_those_kept_by_their_bytes_are_read_alike(monkeypatch: pytest.MonkeyPatch) -> None:
    """Past the piece's numbered usemtl lines, and past the lines the reader keeps by their bytes."""
    monkeypatch.setattr(fast, "_USEMTL_LINES_KEPT", 3)
    data = (TRIANGLES + "".join(f"usemtl{' ' * (1 + k % 3)}m{k % 90}\nf 1 2 3\n" for k in range(900))).encode()
    assert read_fast(data, "m.obj").material_runs.as_pairs() == read_by_lines(data, "m.obj").material_runs.as_pairs()


@pytest.mark.parametrize("seed", range(4))
def test_many_runs_at_once_are_those_one_at_a_time(seed: int) -> None:
    """MaterialRuns.extend, as the fast reader settles a chunk's usemtl lines, and add, one by one."""
    rng = np.random.default_rng(seed)
    one_by_one, at_once = MaterialRuns(), MaterialRuns()
    face = 0
    for _ in range(20):  # chunks, each going on from the runs the chunks before made
        count = int(rng.integers(1, 30))
        faces = face + np.cumsum(rng.integers(0, 3, count))  # several usemtl lines at one face, too
        numbers = rng.integers(0, 4, count)
        names = [at_once.number(f"m{number}") for number in numbers]
        for start, number in zip(faces.tolist(), numbers.tolist()):
            one_by_one.add(start, f"m{number}")
        at_once.extend(faces, np.array(names))
        face = int(faces[-1])
        assert at_once.as_pairs() == one_by_one.as_pairs()


def test_a_usemtl_naming_the_material_in_use_goes_on_with_its_run() -> None:
    data = (TRIANGLES + "usemtl a\nf 1 2 3\nusemtl a\nf 1 2 3\nusemtl b\nusemtl a\nf 1 2 3\n"
            "usemtl b\nf 1 2 3\n").encode()
    for read in (read_fast, read_by_lines):
        assert read(data, "m.obj").material_runs.as_pairs() == [(1, "a"), (4, "b")]


def test_each_usemtl_group_gets_its_own_material(tmp_path: Path) -> None:
    (tmp_path / "m.mtl").write_text("newmtl a\nKd 1 0 0\nnewmtl b\nKd 0 0 1\nNs 50\n")
    data = ("mtllib m.mtl\n" + TRIANGLES + "usemtl b\nf 1 2 3\nusemtl a\nf 1 2 3\nf 1 2 3\n").encode()
    mesh = parse_obj(data, str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert [material.name for material in mesh.materials] == ["b", "a"]
    assert mesh.face_material.tolist() == [-1, 0, 1, 1]  # the first face comes before any usemtl
    assert mesh.materials[0].values == {"kd": (0.0, 0.0, 1.0), "ns": 50.0}


@pytest.mark.parametrize("faces", ["f 1/1 2/2 3/3\n", "f 1/1 2/2 3/3\nusemtl other\nf 4 5 6\n",
                                   "usemtl gone\nf 1/1 2/2 3/3\n"])
def test_faces_no_usemtl_gives_a_material_show_the_first_materials_picture_too(tmp_path: Path, faces: str) -> None:
    """They took the library's first material's numbers (the model's) but not its map_Kd: the scene's
    picture showed under the first material's Kd 1 1 1 (no usemtl at all, before the first, a name the
    library lacks)."""
    Image.new("RGB", (4, 4), (0, 255, 0)).save(tmp_path / "green.png")
    (tmp_path / "m.mtl").write_text("newmtl first\nKa 1 1 1\nmap_Kd green.png\nnewmtl other\nKd 0 0 1\n")
    model = tmp_path / "m.obj"
    corner = "v 0.9 0.9 0\nv 1 0.9 0\nv 0.9 1 0\n"  # another material's face, in the box, off the first
    model.write_text("mtllib m.mtl\nv -1 -1 0\nv 1 -1 0\nv 0 1 0\n" + corner + "vt 0 0\nvt 1 0\nvt 0 1\n" + faces)
    mesh = load_obj(model)
    first = next(at for at, material in enumerate(mesh.materials) if material.name == "first")
    assert mesh.face_material[0] == first and mesh.materials[first].texture is not None
    assert mesh.file_material["ka"] == (1.0, 1.0, 1.0)  # the model's numbers are still the first's
    shown = picture(tmp_path, model, keys="1")  # the sun on, the file's picture on
    centre = shown[SIZE[1] * 2 // 3, SIZE[0] // 2]
    assert centre[1] > 0 and centre[0] == centre[2] == 0, centre


def test_a_first_material_of_no_picture_makes_no_part_without_usemtl(tmp_path: Path) -> None:
    """Its numbers are the object's own: the whole mesh is drawn as one, not copied into a part."""
    (tmp_path / "m.mtl").write_text("newmtl first\nKd 1 0 0\n")
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES).encode(), str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert mesh.file_material == {"kd": (1.0, 0.0, 0.0)} and mesh.face_material is None and mesh.parts == ()


@pytest.mark.parametrize("uses", ["", "usemtl other\nf 1 2 3\n"])
def test_a_first_material_whose_picture_cannot_be_read_makes_no_part_of_the_faces_no_usemtl_gives(
        tmp_path: Path, uses: str) -> None:
    """They were copied into a part of it that drew what the object's own does (the scene's picture under
    its numbers) and held the mesh twice; the probe named 'first' for them where a first of no picture is
    named for none. The picture's note stays."""
    (tmp_path / "m.mtl").write_text("newmtl first\nKs 1 0 0\nmap_Kd gone.png\nnewmtl other\nKd 0 0 1\n")
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + uses).encode(), str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert mesh.file_material == {"ks": (1.0, 0.0, 0.0)}
    assert [material.name for material in mesh.materials] == (["other"] if uses else [])
    assert mesh.face_material is None if not uses else list(mesh.face_material) == [-1, 0]
    assert any("'gone.png' could not be read" in note for note in mesh.warnings), mesh.warnings


def test_a_file_switching_material_every_face_stays_two_parts(tmp_path: Path) -> None:
    (tmp_path / "m.mtl").write_text("newmtl a\nKd 1 0 0\nnewmtl b\nKd 0 0 1\n")
    data = ("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n" + "usemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\n" * 5000).encode()
    mesh = parse_obj(data, str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert mesh.face_count == 10_000 and [part.faces.size for part in mesh.parts] == [5000, 5000]
    assert mesh.parts[1].faces[:3].tolist() == [1, 3, 5]


def grid_obj(folder: Path, uses: Callable[[int], str]) -> Path:
    """m.obj in `folder`: a 6x6 grid of v/vt/vn triangles, a wave in z, `uses(face)` before each face,
    and its MTL: materials 'wood' and 'wood2' alike, each with the same picture."""
    folder.mkdir(exist_ok=True)
    Image.fromarray(np.random.default_rng(5).integers(0, 256, (8, 8, 3), dtype=np.uint8)).save(folder / "wood.png")
    (folder / "m.mtl").write_text("".join(f"newmtl {name}\nKd 0.8 0.6 0.4\nKs 0.5 0.5 0.5\nNs 20\nmap_Kd wood.png\n"
                                          for name in ("wood", "wood2")))
    cells = 6
    steps = np.linspace(0.0, 1.0, cells + 1)
    u, v = (grid.reshape(-1) for grid in np.meshgrid(steps, steps))
    z = 0.1 * np.sin(6 * u) * np.cos(5 * v)
    normals = np.stack([-0.6 * np.cos(6 * u) * np.cos(5 * v), 0.5 * np.sin(6 * u) * np.sin(5 * v), np.ones_like(u)], 1)
    lines = ["mtllib m.mtl"]
    lines += [f"v {x:.4f} {y:.4f} {h:.4f}" for x, y, h in zip(u - 0.5, v - 0.5, z)]
    lines += [f"vt {a:.4f} {b:.4f}" for a, b in zip(u, v)]
    lines += [f"vn {a:.4f} {b:.4f} {c:.4f}" for a, b, c in normals]
    firsts = (np.arange(cells)[:, None] * (cells + 1) + np.arange(cells)).reshape(-1) + 1
    triangles = np.stack([firsts, firsts + 1, firsts + cells + 2, firsts, firsts + cells + 2, firsts + cells + 1], 1)
    for face, corners in enumerate(triangles.reshape(-1, 3)):
        lines.append(uses(face) + "f " + " ".join(f"{c}/{c}/{c}" for c in corners))
    (folder / "m.obj").write_text("\n".join(lines) + "\n")
    return folder / "m.obj"


def one_textured_glb(tmp_path: Path) -> Path:
    import trimesh

    picture = Image.fromarray(np.random.default_rng(5).integers(0, 256, (8, 8, 3), dtype=np.uint8))
    square = trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]], process=False,
                             visual=trimesh.visual.TextureVisuals(uv=[[0, 0], [1, 0], [1, 1], [0, 1]], image=picture))
    square.export(tmp_path / "m.glb")
    return tmp_path / "m.glb"


@pytest.mark.parametrize("model", [
    lambda tmp_path: grid_obj(tmp_path, lambda face: "usemtl wood\n" if face == 0 else ""),
    lambda tmp_path: grid_obj(tmp_path, lambda face: ""),  # no usemtl: the first material's picture
    one_textured_glb,
], ids=["usemtl", "no usemtl", "glb"])
def test_a_model_of_one_textured_material_is_drawn_from_its_own_tables(tmp_path: Path, model) -> None:
    """Its faces, all of one material, were copied into a part of that material: the model was held
    twice, and on llvmpipe its GPU rows too."""
    mesh = load_model(model(tmp_path))
    assert [part.material for part in mesh.parts] == [0] and mesh.materials[0].texture is not None
    assert mesh.parts[0].faces is None  # "every face": no list of them either
    obj = SceneObject.placed("m", mesh, DEFAULT_MATERIAL, (0.0, 0.0, 0.0))
    drawn = split_by_material(DrawItem(obj, 0, mesh.face_count))
    assert [(item.part, item.start, item.stop) for item in drawn] == [(0, 0, mesh.face_count)]
    assert mesh.part_mesh(drawn[0].part) is mesh
    assert part_of_face(obj, mesh.face_count - 1) == (0, mesh.face_count - 1)


@pytest.mark.parametrize("keys", ["", "F", "s", "l", "n", "F n", "s n", "i", "o i", "v", "v v", "v*3", "v*8", "b",
                                  "x*15", "x*15 b", "x*15 l", "T", "s T", "l T", "s i"])
def test_one_material_on_every_face_draws_what_its_faces_drawn_as_two_parts_do(
        tmp_path: Path, offscreen, keys: str) -> None:
    """The whole mesh drawn as its one part gives the pixels the faces copied into parts of two like
    materials give, in every shading, mode and view; the status line and the probe read the same."""
    pictures, texts = [], []
    for folder, uses in (("one", lambda face: "usemtl wood\n" if face == 0 else ""),
                         ("two", lambda face: f"usemtl wood{'2' if face % 2 else ''}\n")):
        viewer = Viewer(empty_scene(), NoFrontend())
        viewer.start(StartOptions(empty=True, models=(grid_obj(tmp_path / folder, uses),)), longest_texture_side=64)
        viewer.press_sequence(f"1 3 {keys}")
        pictures.append(offscreen(viewer.scene, (95, 95)))
        texts.append((status_line(viewer.scene), probe_lines(viewer.scene)))
    assert len(viewer.scene.objects[0].mesh.parts) == 2 and np.array_equal(*pictures)
    assert texts[0] == texts[1]


def test_a_material_whose_faces_and_positions_are_runs_of_their_own_is_a_view_of_the_whole() -> None:
    """Two_tone's materials each use one run of faces and every position of one run (as a glTF's
    primitives do): each part was copied out of the whole; now its tables are slices of it, holding
    the values the copy held."""
    mesh = load_model(EXAMPLES / "two_tone.obj")
    assert len(mesh.parts) == 2 and not mesh.attributes_per_position  # uvs and normals per corner
    for index, part in enumerate(mesh.parts):
        drawn = mesh.part_mesh(index)
        for table in ("positions", "uvs", "normals", "face_normals"):
            assert np.shares_memory(getattr(drawn, table), getattr(mesh, table)), table
        copied = mesh._gathered_part(part.faces)
        for table in ("positions", "corner_vertex", "uvs", "normals", "face_start", "face_normals"):
            ours, theirs = getattr(drawn, table), getattr(copied, table)
            assert ours.dtype == theirs.dtype and np.array_equal(ours, theirs), table


def test_a_part_is_a_view_where_its_run_uses_every_position_of_its_range_and_else_a_copy(tmp_path: Path) -> None:
    """The grid's halves share a row of positions and are views each; faces alternating are copied."""
    halves = load_model(grid_obj(tmp_path / "halves", lambda face: f"usemtl wood{'2' if face >= 36 else ''}\n"))
    assert all(np.shares_memory(halves.part_mesh(part).positions, halves.positions) for part in halves.drawn_parts())
    alternating = load_model(grid_obj(tmp_path / "alternating", lambda face: f"usemtl wood{'2' if face % 2 else ''}\n"))
    assert not any(np.shares_memory(alternating.part_mesh(part).positions, alternating.positions)
                   for part in alternating.drawn_parts())


def test_a_model_of_interleaved_materials_is_held_once_on_the_cpu_while_drawn(tmp_path: Path, offscreen,
                                                                               renderer) -> None:
    """Each material's part was a Mesh of copies of its faces' rows (positions, uvs, normals, face
    normals, corners), held beside the whole for the model's life and by the renderer while it drew the
    part: a model of interleaved materials held its tables about twice. Now a part's Mesh is made to
    build its buffers (surface, edges, normals) and dropped."""
    model = grid_obj(tmp_path / "interleaved", lambda face: f"usemtl wood{'2' if face % 2 else ''}\n")
    viewer = Viewer(empty_scene(), NoFrontend())
    viewer.start(StartOptions(empty=True, models=(model,)), longest_texture_side=64)
    obj = viewer.scene.objects[0]
    for keys in ("", "n", "s", "l", "i"):  # the surface, normals of both kinds, edges, the probe's outline
        viewer.press_sequence(keys)
        offscreen(viewer.scene)
    assert sorted(part for uid, part in renderer._objects if uid == obj.uid) == [0, 1]
    gc.collect()
    held = [item for item in corpus.tracked_objects() if isinstance(item, Mesh) and item.name == obj.mesh.name]
    assert held == [obj.mesh]


def test_one_texture_spelled_three_ways_is_read_once(tmp_path: Path, monkeypatch) -> None:
    """t.ppm, ./t.ppm and d/../t.ppm are one picture: three materials naming it read it once."""
    from marraztu.loaders.obj import mtl

    read: list[Path] = []

    def counting_load(path: Path) -> np.ndarray:
        read.append(path)
        return load_image_as_is(path)

    load_image_as_is = mtl.load_image
    monkeypatch.setattr(mtl, "load_image", counting_load)
    (tmp_path / "d").mkdir()
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / "t.ppm")
    (tmp_path / "m.mtl").write_text("".join(f"newmtl {material}\nmap_Kd {name}\n" for material, name in
                                            (("a", "t.ppm"), ("b", "./t.ppm"), ("c", "d/../t.ppm"))))
    faces = "".join(f"usemtl {material}\nf 1 2 3\n" for material in "abc")
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + faces).encode(), str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert len(read) == 1
    textures = [material.texture for material in mesh.materials]
    assert len(textures) == 3 and all(texture is textures[0] for texture in textures)


def test_only_the_materials_the_model_can_use_are_kept_and_their_textures_read(tmp_path: Path, monkeypatch) -> None:
    """The first material (the model's where no usemtl says) and the first of each usemtl name: a
    library of thousands costs what those few cost, and an unused material's texture is never read."""
    from marraztu.loaders.obj import mtl
    from support.work import peak_traced_bytes

    read: list[Path] = []
    load_image_as_is = mtl.load_image
    monkeypatch.setattr(mtl, "load_image", lambda path: read.append(path) or load_image_as_is(path))
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / "t.ppm")
    unused = "".join(f"newmtl unused{i}\nKd 1 0 0\nmap_Kd t{i}.ppm\n" for i in range(20_000))
    (tmp_path / "m.mtl").write_text("newmtl first\nKd 0 1 0\n" + unused + "newmtl b\nKd 0 0 1\nmap_Kd t.ppm\n"
                                    "newmtl b\nKd 1 1 1\n")
    text = ("mtllib m.mtl\n" + TRIANGLES + "usemtl b\nf 1 2 3\nusemtl gone\nf 1 2 3\n").encode()
    mesh, peak = peak_traced_bytes(lambda: parse_obj(text, str(tmp_path / "m.obj"), base_dir=tmp_path))
    assert [material.name for material in mesh.materials] == ["b"]
    assert mesh.materials[0].values["kd"] == (0.0, 0.0, 1.0)  # the first of a name wins
    assert read == [tmp_path / "t.ppm"]
    assert peak < 2 * (tmp_path / "m.mtl").stat().st_size + 64 * 64 * 3 * 8, peak


def test_textures_that_cannot_be_read_are_one_note(tmp_path: Path) -> None:
    """It counts the pictures looked for: those of the MAX_MATERIALS materials drawn, not the 500 used."""
    (tmp_path / "m.mtl").write_text("".join(f"newmtl m{i}\nmap_Kd gone{i}.png\n" for i in range(500)))
    uses = "".join(f"usemtl m{i}\nf 1 2 3\n" for i in range(500))
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + uses).encode(), str(tmp_path / "m.obj"), base_dir=tmp_path)
    texture_notes = [note for note in mesh.warnings if "could not be read" in note]
    assert texture_notes == ["256 textures could not be read (the first, 'gone0.png': no such file); the scene's "
                             "texture is shown in their place"]


def test_the_texture_is_read_beside_the_mtl_and_its_options_noted(tmp_path: Path) -> None:
    (tmp_path / "lib").mkdir()
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / "lib" / "my wood.ppm")
    (tmp_path / "lib" / "m.mtl").write_text("newmtl w\nmap_Kd -s 2 2 1 -clamp on -o 0.5 my wood.ppm\nd 0.5\n")
    mesh = parse_obj(("mtllib lib/m.mtl\n" + TRIANGLES + "usemtl w\nf 1 2 3\n").encode(),
                     str(tmp_path / "m.obj"), base_dir=tmp_path)
    material = mesh.materials[0]
    assert material.texture_name == "my wood.ppm" and material.texture.shape == (64, 64, 3)
    assert any("texture option -clamp, texture option -o, texture option -s, transparency (d, Tr) ignored"
               in note for note in mesh.warnings), mesh.warnings


@pytest.mark.parametrize("statements", ["mtllib a.mtl b.mtl\n", "mtllib a.mtl\nmtllib b.mtl\n",
                                        "mtllib a.mtl gone.mtl b.mtl\n"])
def test_every_library_named_is_read_and_the_first_of_a_name_wins(tmp_path: Path, statements: str) -> None:
    (tmp_path / "a.mtl").write_text("newmtl red\nKd 1 0 0\nnewmtl shared\nKd 0 0 0\n")
    (tmp_path / "b.mtl").write_text("newmtl blue\nKd 0 0 1\nnewmtl shared\nKd 1 1 1\n")
    uses = "usemtl blue\nf 1 2 3\nusemtl shared\nf 1 2 3\n"
    mesh = parse_obj((statements + TRIANGLES + uses).encode(), str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert {material.name: material.values["kd"] for material in mesh.materials} == {
        "blue": (0.0, 0.0, 1.0), "shared": (0.0, 0.0, 0.0)}
    assert mesh.file_material == {"kd": (1.0, 0.0, 0.0)}  # the first library's first material: the model's
    missing = [note for note in mesh.warnings if "not found" in note]
    assert missing == (["material library 'gone.mtl' not found next to the model"] if "gone" in statements else [])


@pytest.mark.parametrize(("statements", "said"), [
    ("mtllib a.mtl\n" + "".join(f"mtllib gone{at}.mtl\n" for at in range(3)),
     "3 material libraries not found next to the model (the first 'gone0.mtl')"),
    ("".join(f"mtllib gone{at}.mtl\n" for at in range(3)),
     "3 material libraries not found next to the model (the first 'gone0.mtl'); using the scene's material"),
])
def test_libraries_not_found_are_one_note(tmp_path: Path, statements: str, said: str) -> None:
    """A note a line made the load message a list of them; and one said 'using the scene's material'
    where another library's materials were used."""
    (tmp_path / "a.mtl").write_text("newmtl red\nKd 1 0 0\n")
    mesh = parse_obj((statements + TRIANGLES + "usemtl red\nf 1 2 3\n").encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    assert [note for note in mesh.warnings if "not found" in note] == [said]


def test_a_windows_1252_byte_in_an_mtl_leaves_its_utf8_names_alone(tmp_path: Path) -> None:
    """Each line is decoded on its own, as an OBJ's are: a comment in one encoding, names in the other."""
    (tmp_path / "m.mtl").write_bytes(b"# Erstellt am 01.M\xe4rz\n" + "newmtl Matériau\nKd 0 1 0\n".encode())
    uses = "usemtl Matériau\nf 1 2 3\n"
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + uses).encode(), str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert [material.name for material in mesh.materials] == ["Matériau"] and not mesh.warnings


@pytest.mark.parametrize("written", ["C:\\Users\\artist\\maps\\wood.ppm", "maps\\wood.ppm", '"wood.ppm"', "WOOD.PPM",
                                     "/nowhere/maps/wood.ppm"])
def test_a_texture_named_as_other_machines_write_it_is_found_beside_the_mtl(tmp_path: Path, written: str) -> None:
    """A Windows path from the machine the model was made on, a quoted name, another case: by its last
    part beside the MTL (or in the folder it names), in any case."""
    (tmp_path / "maps").mkdir()
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / ("maps" if written.startswith("maps") else ".") / "wood.ppm")
    (tmp_path / "m.mtl").write_text(f"newmtl w\nmap_Kd {written}\n")
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + "usemtl w\nf 1 2 3\n").encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    assert mesh.materials[0].texture is not None and not mesh.warnings, mesh.warnings


@pytest.mark.parametrize(("written", "folder"), [
    ("C:/Users/student/Documents/maya/projects/default/sourceimages/wood.ppm", "sourceimages"),
    ("C:\\Users\\Estudiante\\Documents\\3ds Max 2019\\sceneassets\\images\\wood.ppm", "sceneassets/images"),
    ("/home/artist/work/../proj/textures/WOOD.PPM", "textures"),
])
def test_a_whole_path_whose_picture_came_in_its_project_folder_is_found_there(
        tmp_path: Path, written: str, folder: str) -> None:
    """Maya writes map_Kd as the whole path to its project's sourceimages/, 3ds Max to sceneassets/images/;
    a student copies the project, so the picture lies in those folders beside the MTL, not beside it."""
    (tmp_path / folder).mkdir(parents=True)
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / folder / "wood.ppm")
    (tmp_path / "m.mtl").write_text(f"newmtl w\nKd 1 1 1\nmap_Kd {written}\n")
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + "usemtl w\nf 1 2 3\n").encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    assert mesh.materials[0].texture is not None and not mesh.warnings, mesh.warnings


@pytest.mark.parametrize("written", ["q/C:..\\wood.ppm", "maps\\D:tex\\wood.ppm", "a/c:/../wood.ppm",
                                     "x/C:\\Users\\..\\..\\wood.ppm", "p/Z:wood.ppm"])
def test_the_folders_kept_before_a_last_part_hold_no_drive(written: str) -> None:
    """'C:..' or 'D:tex' within a path is a drive on Windows: kept before the last part, 'C:../wood.ppm'
    joined to the MTL's folder C:/m is C:/wood.ppm, above it, and 'D:tex/wood.ppm' is on another drive."""
    from pathlib import PureWindowsPath

    from marraztu.loaders.files import spellings

    folder = PureWindowsPath("C:/m")
    for spelling in spellings(written)[1:]:
        joined = folder / spelling
        assert joined.parts[:2] == folder.parts and ".." not in joined.parts, spelling  # on its drive, under m


@pytest.mark.skipif(os.name == "nt", reason="a Windows file name holds no ':'")
def test_a_colon_within_a_last_part_is_no_drive(tmp_path: Path) -> None:
    """A Linux exporter's whole path to 'shot 10:00.ppm' is found by that last part beside the MTL, not as
    '00.ppm': only a part whose second character is ':' (C:, as Windows reads one) starts a drive."""
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / "shot 10:00.ppm")
    (tmp_path / "m.mtl").write_text("newmtl w\nKd 1 1 1\nmap_Kd /home/artist/proj/tex/shot 10:00.ppm\n")
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + "usemtl w\nf 1 2 3\n").encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    assert mesh.materials[0].texture is not None and not mesh.warnings, mesh.warnings


@pytest.mark.parametrize(("lines", "noted"), [("d 1\nTr 0.0\n", False), ("d 0.5\n", True), ("Tr 0.25\n", True),
                                              ("d -halo 0.5\n", True), ("d\n", True)])
def test_only_transparency_asked_for_is_said_to_be_ignored(tmp_path: Path, lines: str, noted: bool) -> None:
    (tmp_path / "m.mtl").write_text("newmtl w\nKd 1 0 0\n" + lines)
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + "usemtl w\nf 1 2 3\n").encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    assert any("transparency (d, Tr) ignored" in note for note in mesh.warnings) == noted, mesh.warnings


@pytest.mark.parametrize(("lines", "kd"), [("map_Kd wood.ppm\n", (1.0, 1.0, 1.0)),
                                          ("Kd 0.5 0.25 0.5\nmap_Kd wood.ppm\n", (0.5, 0.25, 0.5)),
                                          ("map_Kd wood.ppm\nKd 0 0 0\n", (0.0, 0.0, 0.0)),
                                          ("Ks 0.5 0.5 0.5\n", None), ("map_Kd gone.ppm\n", None)])
def test_a_picture_without_a_kd_is_the_diffuse_colour_itself(tmp_path: Path, lines: str, kd: tuple | None) -> None:
    """Blender's exporter writes no Kd beside a map_Kd, the picture being the colour, and shows it
    unscaled: it took the viewer's Kd 0.7, drawing the picture's diffuse light 30% darker. A picture that
    cannot be read gives no colour: the scene's, standing in, is drawn under the viewer's Kd."""
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / "wood.ppm")
    (tmp_path / "m.mtl").write_text("newmtl w\nNs 250.000000\nKa 1.000000 1.000000 1.000000\n" + lines)
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + "usemtl w\nf 1 2 3\n").encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    assert mesh.materials[0].values.get("kd") == kd


# A material as Blender 4's OBJ exporter writes it with "PBR extensions" on: Pr, Pm and no Ns or Ka.
BLENDER_PBR = ("newmtl Material\nKd 0.800000 0.800000 0.800000\nKs 0.500000 0.500000 0.500000\n"
               "Ke 0.000000 0.000000 0.000000\nNi 1.500000\nd 1.000000\nillum 2\n{pr}Pm 0.000000\nPs 0.000000\n"
               "Pc 0.000000\nPcr 0.030000\naniso 0.000000\nanisor 0.000000\n{ns}")


@pytest.mark.parametrize(("pr", "ns", "expected"), [("Pr 0.500000\n", "", 250.0), ("Pr 0.200000\n", "", 640.0),
                                                   ("Pr 1.000000\n", "", 0.0), ("Pr 0.2\n", "Ns 30\n", 30.0),
                                                   ("Pr 1.5\n", "", 0.0), ("", "", None)])
def test_blenders_roughness_gives_the_shininess_where_no_ns_does(tmp_path: Path, pr: str, ns: str,
                                                                 expected: float | None) -> None:
    """Blender 4's PBR export writes Pr and no Ns: the viewer's Ns 20 stood in for every material. Ns is
    Blender's own (1 - roughness)^2 * 1000, which its exporter writes without PBR and its importer inverts."""
    (tmp_path / "m.mtl").write_text(BLENDER_PBR.format(pr=pr, ns=ns))
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + "usemtl Material\nf 1 2 3\n").encode(),
                     str(tmp_path / "m.obj"), base_dir=tmp_path)
    held = ("material library 'm.mtl': Pr on line 8 holds 1.5, outside MTL's 0..1: held to it",)
    assert mesh.materials[0].values.get("ns") == pytest.approx(expected)
    assert mesh.warnings == (held if "1.5" in pr else ()), mesh.warnings


@pytest.mark.parametrize("header", ["# Blender MTL File: 'None'\n# Material Count: 1\n\n",
                                    "# Blender 4.2.1 LTS MTL File: 'None'\n# www.blender.org\n\n"])
@pytest.mark.parametrize("ka", ["1.000000 1.000000 1.000000", "0.800000 0.800000 0.800000"])
def test_blenders_ka_is_its_metallic_not_an_ambient_colour(tmp_path: Path, header: str, ka: str) -> None:
    """Blender's OBJ exporters write the metallic value as Ka (1 1 1 for every material that is not
    metal) and its importer reads it back so: taken as the ambient colour, every Blender model was lit by
    the whole of SPEC's violet Ia, where the viewer's Ka is 0.3. Another tool's Ka stays its own."""
    material = f"newmtl Material\nNs 250.000000\nKa {ka}\nKd 0.800000 0.100000 0.100000\nillum 2\n"
    (tmp_path / "blender.mtl").write_text(header + material)
    (tmp_path / "other.mtl").write_text("# 3ds Max Wavefront OBJ Exporter v0.97b\n" + material)
    read = {name: parse_obj((f"mtllib {name}.mtl\n" + TRIANGLES + "usemtl Material\nf 1 2 3\n").encode(),
                            str(tmp_path / f"{name}.obj"), base_dir=tmp_path) for name in ("blender", "other")}
    assert "ka" not in read["blender"].materials[0].values
    assert read["blender"].warnings == ("material library 'blender.mtl': Ka (Blender's metallic value, not an "
                                        "ambient colour) ignored",)
    assert read["other"].materials[0].values["ka"] == tuple(float(value) for value in ka.split())
    assert read["other"].warnings == ()


def test_a_malformed_roughness_is_a_malformed_line(tmp_path: Path) -> None:
    (tmp_path / "m.mtl").write_text(BLENDER_PBR.format(pr="Pr rough\n", ns=""))
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + "usemtl Material\nf 1 2 3\n").encode(),
                     str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert "ns" not in mesh.materials[0].values
    assert mesh.warnings == ("material library 'm.mtl': ignored a malformed Pr line, on line 8",)


@pytest.mark.parametrize("lines", ["map_Bump -bm 1.000000 normal.png\n", "bump bumps.png\n", "norm n.png\n",
                                   "map_bump n.png\nnorm n.png\n"])
def test_a_normal_map_is_said_to_be_ignored(tmp_path: Path, lines: str) -> None:
    """Blender writes a normal map as map_Bump -bm 1.0: it was read past without a word, where a map_Kd's
    options and a glTF's normalTexture are said."""
    (tmp_path / "m.mtl").write_text("newmtl w\nKd 1 0 0\n" + lines)
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + "usemtl w\nf 1 2 3\n").encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    assert mesh.warnings == ("material library 'm.mtl': normal and bump maps (map_Bump, bump, norm) ignored",)


@pytest.mark.parametrize(("lines", "noted"), [("Ke 0.000000 0.000000 0.000000\n", False), ("Ke 1.0 0.4 0.0\n", True),
                                              ("Ke 0.5\n", True), ("Ke glow\n", True)])
def test_only_emission_asked_for_is_said_to_be_ignored(tmp_path: Path, lines: str, noted: bool) -> None:
    """Blender writes Ke for every material, 0 0 0 where nothing glows: a glowing one is drawn unlit,
    which the load message says, as the lighting equation has no emission."""
    (tmp_path / "m.mtl").write_text("newmtl w\nKd 1 0 0\n" + lines)
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + "usemtl w\nf 1 2 3\n").encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    assert any("emission (Ke) ignored" in note for note in mesh.warnings) == noted, mesh.warnings


def _listings_counted(monkeypatch) -> list[object]:
    """The folders listed from now on (files.names_in_any_case's os.scandir), in order."""
    from marraztu.loaders import files as files_module

    listed: list[object] = []
    real_scandir = os.scandir
    monkeypatch.setattr(files_module.os, "scandir", lambda folder: listed.append(folder) or real_scandir(folder))
    return listed


def test_names_looked_for_in_any_case_list_each_folder_once(tmp_path: Path, monkeypatch) -> None:
    """A library of many missing textures in a folder of many files costs one listing, not one each."""


    for at in range(300):
        (tmp_path / f"other{at}.png").write_bytes(b"")
    listed = _listings_counted(monkeypatch)
    (tmp_path / "m.mtl").write_text("".join(f"newmtl m{at}\nmap_Kd gone{at}.png\n" for at in range(300)))
    uses = "".join(f"usemtl m{at}\nf 1 2 3\n" for at in range(300))
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + uses).encode(), str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert len(listed) == 1 and any("256 textures could not be read" in note for note in mesh.warnings)  # those drawn


def test_a_folder_spelled_many_ways_is_listed_once(tmp_path: Path, monkeypatch) -> None:
    """'a/../T0.PNG', 'a/../a/../T1.PNG'... each spell the MTL's folder anew: it was listed once for each
    spelling, each listing holding every file's path under that spelling, so 1,000 such names beside
    50,000 files filled the memory. One listing for the folder, however it is spelled."""


    (tmp_path / "a").mkdir()
    for at in range(200):
        (tmp_path / f"t{at}.png").write_bytes(b"P6 1 1 255\n\xff\x00\x00")  # a PPM: pictures are known by their bytes
    listed = _listings_counted(monkeypatch)
    (tmp_path / "m.mtl").write_text("".join(f"newmtl m{at}\nmap_Kd {'a/../' * (at + 1)}T{at}.PNG\n"
                                            for at in range(200)))
    uses = "".join(f"usemtl m{at}\nf 1 2 3\n" for at in range(200))
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + uses).encode(), str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert len({Path(folder).resolve() for folder in listed}) == len(listed) <= 3  # the folder, a/, a/../a
    assert all(material.texture is not None for material in mesh.materials) and not mesh.warnings, mesh.warnings


def test_a_name_longer_than_any_path_is_not_resolved_part_by_part(tmp_path: Path, monkeypatch) -> None:
    """Path.resolve() looks at each part of a path, its text copied anew for each: a map_Kd of 200,000
    parts ('d/d/...', 400 KB) took 8 s, its length squared, and an MTL may be 16 MB. A path longer than
    any the system opens is known by its text; it is still said not to be read."""
    import os

    looked: list[object] = []
    real_lstat = os.lstat
    monkeypatch.setattr(os, "lstat", lambda path, **kw: looked.append(path) or real_lstat(path, **kw))
    (tmp_path / "m.mtl").write_text("newmtl w\nmap_Kd " + "d/" * 20_000 + "t.png\n")
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + "usemtl w\nf 1 2 3\n").encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    assert len(looked) < 100 and mesh.materials[0].texture is None
    assert any("could not be read (cannot read the file (File name too long))" in note for note in mesh.warnings), \
        mesh.warnings


@pytest.mark.parametrize(("mtl", "usemtl", "said"), [
    ("newmtl w\nKd 1 0 0\nmap_Kd gone.png\n", "w", "texture 'gone.png' could not be read (no such file)"),
    ("newmtl w\nKd 1 0 0\n", "nobody", "usemtl names materials the library lacks ('nobody')"),
    ("newmtl w\nKd 1 0 0\n", "n" * 100, f"usemtl names materials the library lacks ('{'n' * 40}... (100 characters)')"),
])
def test_what_is_missing_is_a_note_and_the_colours_are_used(tmp_path: Path, mtl: str, usemtl: str,
                                                             said: str) -> None:
    (tmp_path / "m.mtl").write_text(mtl)
    (tmp_path / "m.obj").write_text(f"mtllib m.mtl\n{TRIANGLES}usemtl {usemtl}\nf 1 2 3\n")
    mesh = load_model(tmp_path / "m.obj")
    assert any(said in note for note in mesh.warnings), mesh.warnings
    assert mesh.face_count == 2


@pytest.mark.parametrize(("mtl", "obj", "said"), [
    ("newmtl w\nKd 1 0 0\n".encode("utf-16"), "mtllib m.mtl\n",
     "material library 'm.mtl' is UTF-16 text: save it as UTF-8; using the scene's material"),
    (b"# exported\nKd 1 0 0\nKs 1 1 1\nnewmtl w\nKd 1 0 0\n", "mtllib m.mtl\n",
     "material library 'm.mtl': 2 lines before the first newmtl, which belong to no material, ignored"),
    (b"Kd 1 0 0\nnewmtl w\nKd 1 0 0\n", "mtllib m.mtl\n",
     "material library 'm.mtl': 1 line before the first newmtl, which belongs to no material, ignored"),
    (b"", "", "usemtl names materials ('w') but no mtllib line names their library; using the scene's material"),
    (git_lfs_pointer(2048), "mtllib m.mtl\n", "material library 'm.mtl' is a Git LFS pointer, not the library: "
     "its 2048 bytes are fetched by `git lfs pull`; using the scene's material"),
])
def test_what_is_read_of_no_material_is_a_note(tmp_path: Path, mtl: bytes, obj: str, said: str) -> None:
    """A UTF-16 library, and a Git LFS pointer in one's place, said it 'defines no material'; the lines before
    the first newmtl, and a usemtl with no library, were passed over without a word."""
    (tmp_path / "m.mtl").write_bytes(mtl)
    (tmp_path / "m.obj").write_text(f"{obj}{TRIANGLES}usemtl w\nf 1 2 3\n")
    assert load_model(tmp_path / "m.obj").warnings == (said,)


@pytest.mark.parametrize(("mtl", "said"), [
    ("newmtl w\nKd 255 128 0\n", "material library 'm.mtl': Kd on line 2 holds 255, outside MTL's 0..1: held to it"),
    ("newmtl w\nKa 0 0 0\nKd 0.5 -0.5 2\nKs 3\n",
     "material library 'm.mtl': 2 values outside MTL's 0..1 held to it (the first, Kd on line 3 holds -0.5)"),
    ("newmtl w\nPr 2\n", "material library 'm.mtl': Pr on line 2 holds 2, outside MTL's 0..1: held to it"),
    ("newmtl w\nPr -1\nPr 0.5\n", None),  # a later line of the key replaces the earlier one
])
def test_a_colour_outside_0_to_1_is_held_to_it_with_a_note(tmp_path: Path, mtl: str, said: str | None) -> None:
    """Blender's roughness (Pr) too: 'Pr 2' was drawn as 1 without a word."""
    (tmp_path / "m.mtl").write_text(mtl + "newmtl unused\nKd 9 9 9\n")  # a material no face uses says nothing
    (tmp_path / "m.obj").write_text(f"mtllib m.mtl\n{TRIANGLES}usemtl w\nf 1 2 3\n")
    mesh = load_model(tmp_path / "m.obj")
    assert [note for note in mesh.warnings if "0..1" in note] == ([said] if said else [])


@pytest.mark.parametrize(("kd", "texture", "noted"), [("Kd 0.00 0.00 0.00\n", "map_Kd wood.ppm\n", True),
                                                      ("Kd 0.5 0.5 0.5\n", "map_Kd wood.ppm\n", False),
                                                      ("Kd 0 0 0\n", "", False), ("", "map_Kd wood.ppm\n", False)])
def test_a_black_diffuse_colour_under_a_picture_is_a_note(tmp_path: Path, kd: str, texture: str, noted: bool) -> None:
    """Maya writes Kd 0 0 0 for a colour a picture gives: its model was drawn black without a word."""
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / "wood.ppm")
    (tmp_path / "m.mtl").write_text(f"newmtl lambert2SG\nillum 4\n{kd}Ka 0.00 0.00 0.00\nTf 1.00 1.00 1.00\n{texture}")
    (tmp_path / "m.obj").write_text(f"mtllib m.mtl\n{TRIANGLES}usemtl lambert2SG\nf 1 2 3\n")
    mesh = load_model(tmp_path / "m.obj")
    assert mesh.warnings == (("material library 'm.mtl': material 'lambert2SG' has Kd 0 0 0 and a map_Kd, so its "
                              "picture gets no diffuse light (Maya writes so: Kd 1 1 1 shows the picture)",)
                             if noted else ())


@pytest.mark.parametrize("number", ["\u0661", "1_0", "0x1"])  # float() reads the first two, as 1 and 10
def test_a_colour_of_no_ascii_decimal_number_is_a_malformed_line(tmp_path: Path, number: str) -> None:
    (tmp_path / "m.mtl").write_text(f"newmtl w\nKd {number} 0 0\n", encoding="utf-8")
    (tmp_path / "m.obj").write_text(f"mtllib m.mtl\n{TRIANGLES}usemtl w\nf 1 2 3\n")
    mesh = load_model(tmp_path / "m.obj")
    assert mesh.warnings == ("material library 'm.mtl': ignored a malformed Kd line, on line 2",)
    assert mesh.materials[0].values == {}


@pytest.mark.parametrize("options", ["-s 1_0 1 1", "-s 1 nan 1", "-o inf", "-t 1 1 \u0661", "-s 1e400",
                                     "-bm NaN", "-boost 1_5", "-mm 0 inf", "-texres 1_024", "-bm x"])
def test_a_texture_option_of_no_ascii_decimal_number_is_a_malformed_line(tmp_path: Path, options: str) -> None:
    """Its numbers follow Kd's rule: float() read 1_0, nan, inf and '\u0661' (an Arabic-Indic 1), and -bm,
    -boost, -mm and -texres took any word, as numbers of an option that is not applied, without a word."""
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / "t.ppm")
    (tmp_path / "m.mtl").write_text(f"newmtl w\nKd 1 0 0\nmap_Kd {options} t.ppm\n", encoding="utf-8")
    (tmp_path / "m.obj").write_text(f"mtllib m.mtl\n{TRIANGLES}usemtl w\nf 1 2 3\n")
    mesh = load_model(tmp_path / "m.obj")
    assert mesh.warnings == ("material library 'm.mtl': ignored a malformed map_Kd line, on line 3",)
    assert mesh.materials[0].texture is None and mesh.materials[0].values == {"kd": (1.0, 0.0, 0.0)}


@pytest.mark.parametrize("options", ["-s 1 1 1", "-s 1", "-o 0 0 0", "-t 0 0", "-mm 0 1", "-bm 1", "-blendu on",
                                     "-blendv ON -clamp off -cc off", "-s 1.0 1 1 -o 0 0 0"])
def test_texture_options_written_as_their_defaults_are_not_said_to_be_ignored(tmp_path: Path, options: str) -> None:
    """Exporters write '-s 1 1 1 -o 0 0 0', which changes nothing, and the load said 'texture option -o,
    texture option -s ignored' as if the picture were drawn otherwise than the file says."""
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / "t.ppm")
    (tmp_path / "m.mtl").write_text(f"newmtl w\nmap_Kd {options} t.ppm\n")
    (tmp_path / "m.obj").write_text(f"mtllib m.mtl\n{TRIANGLES}usemtl w\nf 1 2 3\n")
    mesh = load_model(tmp_path / "m.obj")
    assert mesh.materials[0].texture_name == "t.ppm" and mesh.warnings == (), mesh.warnings


@pytest.mark.parametrize(("options", "name"), [("-s 1 1 2", "t.ppm"), ("-s 2", "t.ppm"), ("-o -0.5 +.5 1e-1", "t.ppm"),
                                               ("-mm 0 1 -bm 2 -texres 256 -clamp on", "t.ppm"),
                                               ("-s 2", "two words.ppm")])
def test_texture_options_of_numbers_read_past_to_the_name(tmp_path: Path, options: str, name: str) -> None:
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / name)
    (tmp_path / "m.mtl").write_text(f"newmtl w\nmap_Kd {options} {name}\n")
    (tmp_path / "m.obj").write_text(f"mtllib m.mtl\n{TRIANGLES}usemtl w\nf 1 2 3\n")
    mesh = load_model(tmp_path / "m.obj")
    assert mesh.materials[0].texture_name == name and mesh.materials[0].texture is not None
    assert len(mesh.warnings) == 1 and mesh.warnings[0].endswith(" ignored") and "texture option" in mesh.warnings[0]


@pytest.mark.parametrize(("options", "name"), [("-o", "-o"), ("-s 2 -o", "-o"), ("-clamp on -blendu", "-blendu")])
def test_a_map_kd_line_s_last_word_is_its_name_never_an_option(tmp_path: Path, options: str, name: str) -> None:
    """The last word is the picture's name, as an option's values never take it: 'map_Kd -o' named a
    file '-o' and read an option of no values and no picture, drawn without one and without a word."""
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / name)
    (tmp_path / "m.mtl").write_text(f"newmtl w\nmap_Kd {options}\n")
    (tmp_path / "m.obj").write_text(f"mtllib m.mtl\n{TRIANGLES}usemtl w\nf 1 2 3\n")
    mesh = load_model(tmp_path / "m.obj")
    assert mesh.materials[0].texture_name == name and mesh.materials[0].texture is not None


def test_a_map_kd_line_that_names_no_picture_is_a_malformed_line(tmp_path: Path) -> None:
    """A map_Kd of no words was read as no picture without a word."""
    (tmp_path / "m.mtl").write_text("newmtl w\nKd 1 0 0\nmap_Kd  # the picture\n")
    (tmp_path / "m.obj").write_text(f"mtllib m.mtl\n{TRIANGLES}usemtl w\nf 1 2 3\n")
    mesh = load_model(tmp_path / "m.obj")
    assert mesh.warnings == ("material library 'm.mtl': ignored a malformed map_Kd line, on line 3",)
    assert mesh.materials[0].values == {"kd": (1.0, 0.0, 0.0)}


def test_a_colour_set_again_within_0_to_1_says_nothing(tmp_path: Path) -> None:
    (tmp_path / "m.mtl").write_text("newmtl w\nKd 2 2 2\nKd 1 1 1\n")
    (tmp_path / "m.obj").write_text(f"mtllib m.mtl\n{TRIANGLES}usemtl w\nf 1 2 3\n")
    assert load_model(tmp_path / "m.obj").warnings == ()


# --- drawing ---------------------------------------------------------------------------------------
def centre_of(pixels: np.ndarray, left: bool) -> np.ndarray:
    """The front face of the left or right box of two_tone, at the start's framed view."""
    return pixels[SIZE[1] // 2, SIZE[0] // 2 + (-20 if left else 20)]


def test_each_material_lights_its_own_faces(tmp_path: Path) -> None:
    pixels = picture(tmp_path, EXAMPLES / "two_tone.obj", "T")
    assert np.abs(centre_of(pixels, left=True) - ambient_bytes("red")).max() <= 1
    assert np.abs(centre_of(pixels, left=False) - ambient_bytes("blue")).max() <= 1


def test_a_scene_files_material_overrides_the_files(tmp_path: Path) -> None:
    for name in ("two_tone.obj", "two_tone.mtl"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    (tmp_path / "scene.toml").write_text(
        '[[cameras]]\nmodel = "two_tone.obj"\nposition = [0, 0, 120]\n'
        '[[objects]]\nmodel = "two_tone.obj"\nposition = [0, 0, 0]\n'
        'material = { ka = [1, 1, 1], kd = [0, 0, 0], ks = [0, 0, 0], ns = 1 }\n')
    out = take_screenshot(StartOptions(scene_file=tmp_path / "scene.toml"), tmp_path / "s.png", SIZE, keys="T")
    pixels = np.asarray(Image.open(out).convert("RGB")).astype(int)
    for left in (True, False):
        assert np.abs(centre_of(pixels, left) - np.round(AMBIENT_INTENSITY)).max() <= 1


def test_a_texture_of_the_mtl_is_drawn_as_the_same_picture_given_as_the_scenes(tmp_path: Path) -> None:
    """The crate's own map_Kd, beside the same picture given with --texture and an MTL without map_Kd."""
    own = picture(tmp_path, EXAMPLES / "crate.obj", name="own.png")
    plain = tmp_path / "plain"
    plain.mkdir()
    shutil.copy(EXAMPLES / "crate.obj", plain / "crate.obj")
    (plain / "crate.mtl").write_text((EXAMPLES / "crate.mtl").read_text().replace("map_Kd crate.ppm\n", ""))
    given = picture(tmp_path, plain / "crate.obj", name="given.png", texture=EXAMPLES / "crate.ppm")
    assert np.array_equal(own, given)
    colours = {tuple(pixel) for pixel in own.reshape(-1, 3)}
    assert len(colours) > 4  # the four quadrants and the seams, not one flat colour


def test_t_switches_the_materials_texture_off_and_on(tmp_path: Path) -> None:
    textured = picture(tmp_path, EXAMPLES / "crate.obj", name="on.png")
    plain = picture(tmp_path, EXAMPLES / "crate.obj", "T", name="off.png")
    centre = plain[SIZE[1] // 2 + 10, SIZE[0] // 2 + 10]
    assert np.abs(centre - ambient_bytes("wood")).max() <= 1
    assert not np.array_equal(textured, plain)
    assert np.array_equal(picture(tmp_path, EXAMPLES / "crate.obj", "T T", name="again.png"), textured)


# --- naming ----------------------------------------------------------------------------------------
def test_the_status_line_and_the_probe_name_the_selected_faces_material() -> None:
    viewer = Viewer(empty_scene(), NoFrontend())
    viewer.start(StartOptions(empty=True, models=(EXAMPLES / "two_tone.obj",)), longest_texture_side=64)
    assert "(material red)" in status_line(viewer.scene)
    viewer.press_sequence("ENTER*6 i")  # the right box's first face
    assert "(material blue)" in status_line(viewer.scene)
    panel = "\n".join(probe_lines(viewer.scene))
    assert "(material blue)" in panel and "Kd (" in panel and "0.20" in panel.split("Kd (")[1][:20]


def test_a_face_drawn_with_another_material_than_its_files_is_not_named_by_the_file(tmp_path: Path) -> None:
    """The probe and the status line named two_tone's faces 'red' and 'blue' after a material given
    by a scene file or set by hand had replaced the MTL's: they showed green numbers as red."""
    for name in ("two_tone.obj", "two_tone.mtl"):
        shutil.copy(EXAMPLES / name, tmp_path / name)
    green = "material = { ka = [0, 1, 0], kd = [0, 0.5, 0], ks = [0, 0, 0], ns = 1 }\n"
    (tmp_path / "given.toml").write_text('[[objects]]\nmodel = "two_tone.obj"\nposition = [0, 0, 0]\n' + green)
    given = Viewer(load_scene(tmp_path / "given.toml"), NoFrontend())
    viewer = Viewer(empty_scene(), NoFrontend())
    viewer.start(StartOptions(empty=True, models=(tmp_path / "two_tone.obj",)), longest_texture_side=64)
    obj = viewer.scene.objects[0]
    files_red, files_blue = obj.part_materials
    obj.material = given.scene.objects[0].material
    viewer.press_sequence("i")
    given.press_sequence("i")
    for scene in (given.scene, viewer.scene):
        for face in (0, 6):  # one face of each part
            scene.objects[0].selected_face = face
            panel = "\n".join(probe_lines(scene))
            assert "PROBE" in panel and "(material" not in status_line(scene) + panel
    obj.part_materials = (obj.material, files_blue)  # the right box drawn with its file's again
    assert "(material blue)" in status_line(viewer.scene) and "(material blue)" in "".join(probe_lines(viewer.scene))
    obj.selected_face = 0
    assert "(material" not in status_line(viewer.scene)


def test_a_file_of_a_thousand_materials_costs_in_proportion_to_its_faces(tmp_path: Path) -> None:
    """Each part holds only the positions it uses, and past MAX_MATERIALS the faces take the model's
    first material, with a note: neither the GPU rows nor the draws a frame grow as materials x size."""
    from marraztu.loaders.obj import MAX_MATERIALS

    count = 1000
    (tmp_path / "m.mtl").write_text("".join(f"newmtl m{k}\nKd {k / count:g} 0 0\n" for k in range(count)))
    faces = "".join(f"v {k} 0 0\nv {k + 1} 0 0\nv {k} 1 0\nusemtl m{k}\nf -3 -2 -1\n" for k in range(count))
    (tmp_path / "m.obj").write_text("mtllib m.mtl\n" + faces)
    mesh = load_model(tmp_path / "m.obj")
    assert len(mesh.parts) == MAX_MATERIALS + 1  # the first 256, and the rest together
    assert sum(mesh.part_mesh(part).vertex_count for part in mesh.drawn_parts()) == 3 * count
    assert any(f"{count} materials used" in note for note in mesh.warnings), mesh.warnings


def test_a_picture_two_libraries_name_is_read_once_and_noted_once(tmp_path: Path, monkeypatch) -> None:
    """One texture cache for all of a model's MTL libraries: the same picture, or the same missing one."""
    from marraztu.loaders.obj import mtl

    reads: list[Path] = []
    real = mtl.load_image
    monkeypatch.setattr(mtl, "load_image", lambda path: reads.append(Path(path)) or real(path))
    (tmp_path / "a.mtl").write_text("newmtl a\nKd 1 0 0\nmap_Kd gone.png\n")
    (tmp_path / "b.mtl").write_text("newmtl b\nKd 0 1 0\nmap_Kd gone.png\n")
    path = tmp_path / "two.obj"
    path.write_text("mtllib a.mtl b.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\nusemtl b\nf 1 2 3\n")
    mesh = load_obj(path)
    assert [material.name for material in mesh.materials] == ["a", "b"]
    assert len(reads) == 1
    assert sum("gone.png" in note for note in mesh.warnings) == 1


@pytest.mark.parametrize("reader", [read_by_lines, read_fast])
def test_material_names_are_read_alike_on_both_sides_with_their_hashes(tmp_path: Path, reader) -> None:
    """3ds Max names materials "Material #25" (a '#' is no comment in a name), and a name's blanks are
    one blank on both sides: a name with two was looked for as written and not found."""
    (tmp_path / "m.mtl").write_text("newmtl Material #1\nKd 1 0 0\nnewmtl Material #2\nKd 0 1 0\n"
                                    "newmtl Wood  Dark\nKd 0 0 1\n")
    uses = "usemtl Material #2\nf 1 2 3\nusemtl Wood  Dark \nf 1 2 3\n"
    raw = reader(("mtllib m.mtl\n" + TRIANGLES + uses).encode(), "m.obj")
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + uses).encode(), str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert raw.material_runs.names == ["Material #2", "Wood Dark"]
    assert {material.name: material.values["kd"] for material in mesh.materials} == {
        "Material #2": (0.0, 1.0, 0.0), "Wood Dark": (0.0, 0.0, 1.0)}
    assert not mesh.warnings, mesh.warnings


@pytest.mark.parametrize("reader", [read_by_lines, read_fast])
def test_a_library_named_again_is_no_new_one_and_those_past_the_bound_are_said(reader) -> None:
    """Files joined into one repeat their mtllib line per object: a repeat took one of the 16 places."""
    repeated = "mtllib a.mtl\n" * 20 + "mtllib  b.mtl  # the last\n" + TRIANGLES
    assert reader(repeated.encode(), "m.obj").mtllib == ("a.mtl", "b.mtl")
    many = "".join(f"mtllib l{at}.mtl\n" for at in range(40)) + TRIANGLES
    assert reader(many.encode(), "m.obj").mtllib == tuple(f"l{at}.mtl" for at in range(17))


@pytest.mark.parametrize("written", ["M.MTL", ".\\m.mtl", "C:\\Users\\artist\\m.mtl", '"m.mtl"'])
def test_a_library_named_as_other_machines_write_it_is_found(tmp_path: Path, written: str) -> None:
    (tmp_path / "m.mtl").write_text("newmtl w\nKd 0 1 0\n")
    mesh = parse_obj((f"mtllib {written}\n" + TRIANGLES + "usemtl w\nf 1 2 3\n").encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    assert [material.name for material in mesh.materials] == ["w"] and not mesh.warnings, mesh.warnings


def test_libraries_past_the_bound_are_a_note(tmp_path: Path) -> None:
    for at in range(20):
        (tmp_path / f"l{at}.mtl").write_text(f"newmtl m{at}\nKd 0 1 0\n")
    statements = "".join(f"mtllib l{at}.mtl\n" for at in range(20))
    mesh = parse_obj((statements + TRIANGLES + "usemtl m3\nf 1 2 3\n").encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    assert "more than 16 material libraries named: those after 'l15.mtl' are not read" in mesh.warnings
    assert [material.name for material in mesh.materials] == ["m3"]


def test_an_mtl_names_a_texture_with_a_hash_in_it(tmp_path: Path) -> None:
    """A '#' inside a word is the word's, as in an OBJ: 'wood#2.ppm' was cut to 'wood'."""
    shutil.copy(EXAMPLES / "crate.ppm", tmp_path / "wood#2.ppm")
    (tmp_path / "m.mtl").write_text("newmtl w # the wood\nKd 1 1 1 # white\nmap_Kd wood#2.ppm # its picture\n")
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + "usemtl w\nf 1 2 3\n").encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    (material,) = mesh.materials  # named "w # the wood", found by its name before the comment
    assert material.texture is not None and material.texture_name == "wood#2.ppm" and not mesh.warnings


def test_an_mtllib_line_of_paths_reads_each_and_a_usemtl_comment_is_no_name(tmp_path: Path) -> None:
    """'mtllib ./a.mtl ./b.mtl' ends in a file's name too: looked up whole by its last part, it read b
    alone; 'usemtl blue # the sky' names blue."""
    (tmp_path / "a.mtl").write_text("newmtl red\nKd 1 0 0\n")
    (tmp_path / "b.mtl").write_text("newmtl blue\nKd 0 0 1\n")
    uses = "usemtl red\nf 1 2 3\nusemtl blue # the sky\nf 1 2 3\nusemtl blue\nf 1 2 3\n"
    mesh = parse_obj(("mtllib ./a.mtl ./b.mtl\n" + TRIANGLES + uses).encode(), str(tmp_path / "m.obj"),
                     base_dir=tmp_path)
    assert [material.name for material in mesh.materials] == ["red", "blue"] and not mesh.warnings
    assert mesh.face_material.tolist() == [-1, 0, 1, 1]


@pytest.mark.parametrize("reader", [read_by_lines, read_fast])
def test_libraries_are_told_apart_by_their_bytes_in_both_readers(reader) -> None:
    """Two spellings of one name (Windows-1252's \\xe9 and UTF-8's é) are two lines to both readers."""
    lines = b"".join(b"mtllib \xe9%d.mtl\nmtllib \xc3\xa9%d.mtl\n" % (at, at) for at in range(8)) + b"mtllib last.mtl\n"
    assert reader(lines + TRIANGLES.encode(), "m.obj").mtllib[-1] == "last.mtl"


def test_past_max_materials_the_pictures_of_the_materials_not_drawn_are_not_read(tmp_path: Path, monkeypatch) -> None:
    """An OBJ of 1,000 materials, each with a picture of its own, decoded all 1,000 (2.3 s, 200 MB) though
    the faces of those past MAX_MATERIALS take the model's first material: only the drawn ones' are read."""
    from marraztu.loaders.obj import MAX_MATERIALS, mtl

    count = MAX_MATERIALS + 44
    reads: list[str] = []
    real = mtl.load_image
    monkeypatch.setattr(mtl, "load_image", lambda path: reads.append(Path(path).name) or real(path))
    for at in range(count):
        (tmp_path / f"t{at}.ppm").write_bytes(b"P6 1 1 255\n" + bytes((at % 256, 0, 0)))
    (tmp_path / "m.mtl").write_text("".join(f"newmtl m{at}\nmap_Kd t{at}.ppm\n" for at in range(count)))
    uses = "".join(f"usemtl m{at}\nf 1 2 3\n" for at in range(count))
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + uses).encode(), str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert sorted(reads) == sorted(f"t{at}.ppm" for at in range(MAX_MATERIALS))
    assert [material.name for material in mesh.materials] == [f"m{at}" for at in range(MAX_MATERIALS)]
    assert all(material.texture is not None for material in mesh.materials)
    assert any(f"{count} materials used" in note for note in mesh.warnings), mesh.warnings


def test_missing_pictures_in_two_folders_list_each_once(tmp_path: Path, monkeypatch) -> None:
    """Missing pictures named in turn in two folders: the hint's listing, held for the last folder only, was
    made again at each turn (258 listings for 300 names; 8.8 s beside 50,000 files a folder). One each."""


    for folder in ("a", "b"):
        (tmp_path / folder).mkdir()
        for at in range(300):
            (tmp_path / folder / f"other{at}.png").write_bytes(b"")
    listed = _listings_counted(monkeypatch)
    (tmp_path / "m.mtl").write_text("".join(f"newmtl m{at}\nmap_Kd {'ab'[at % 2]}/gone{at}.png\n" for at in range(300)))
    uses = "".join(f"usemtl m{at}\nf 1 2 3\n" for at in range(300))
    mesh = parse_obj(("mtllib m.mtl\n" + TRIANGLES + uses).encode(), str(tmp_path / "m.obj"), base_dir=tmp_path)
    assert len(listed) <= 3 and any("256 textures could not be read" in note for note in mesh.warnings)


def test_the_case_hint_lists_the_folder_it_is_in(tmp_path: Path, monkeypatch) -> None:
    """Two folders of one modification time (as an archive unpacks them), each read as '.': the second was
    given the first's listing, its hint naming a file of the other folder."""
    import os

    from marraztu.loaders.files import MissingFile

    for folder, picture in (("a", "Wood.png"), ("b", "Stone.png")):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / picture).write_bytes(b"")
        os.utime(tmp_path / folder, ns=(10**18, 10**18))
    monkeypatch.chdir(tmp_path / "a")
    assert "did you mean Wood.png?" in MissingFile("wood.png").message
    monkeypatch.chdir(tmp_path / "b")
    assert "did you mean" not in MissingFile("wood.png").message
    assert "did you mean Stone.png?" in MissingFile("stone.png").message
