"""A glTF's skins, applied at the nodes' rest transforms: each skinned vertex placed by its joints, the
skinned mesh's own node not applied (glTF's rule), morph targets first; what a skin reads refused where
it is not glTF's, in one line naming the skin or the mesh."""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from PIL import Image

from marraztu.control.viewer import StartOptions
from marraztu.frontends.screenshot import take_screenshot
from marraztu.loaders import gltf
from marraztu.loaders.gltf import skins, values
from marraztu.loaders.registry import load_model
from support.draco import draco_decoder
from support.gltf import glb
from support.refusals import one_line_refusal

# A strip two high: its bottom corners follow joint 0, its top right joint 1, its top left both by half.
STRIP = np.array([[0, 0, 0], [1, 0, 0], [1, 2, 0], [0, 2, 0]], np.float32)
CORNERS = np.array([0, 1, 2, 0, 2, 3], np.uint16)
JOINTS = np.array([[0, 0, 0, 0], [0, 0, 0, 0], [1, 0, 0, 0], [0, 1, 0, 0]], np.uint8)
WEIGHTS = np.array([[1, 0, 0, 0], [1, 0, 0, 0], [1, 0, 0, 0], [0.5, 0.5, 0, 0]], np.float32)
# Joint 1 bound at (0, 1, 0): its inverse bind matrix takes it back to the origin (stored by column).
BIND = np.stack([np.eye(4), np.array([[1, 0, 0, 0], [0, 1, 0, -1], [0, 0, 1, 0], [0, 0, 0, 1]])]).astype(np.float32)
QUARTER_TURN = [0.0, 0.0, math.sin(math.pi / 4), math.cos(math.pi / 4)]  # about z
# Joint 1 turned a quarter about z at its place, (0, 1, 0): the top right corner (1, 2) goes to (-1, 2);
# the top left, (0, 2), to (-1, 1) by joint 1 and stays by joint 0: half of each.
BENT = np.array([[0, 0, 0], [1, 0, 0], [-1, 2, 0], [-0.5, 1.5, 0]])
_COMPONENTS = {np.dtype(kind): number for kind, number in ((np.float32, 5126), (np.uint32, 5125), (np.uint16, 5123),
                                                         (np.uint8, 5121))}
_TYPES = {1: "SCALAR", 3: "VEC3", 4: "VEC4", 16: "MAT4"}


class Parts:
    """Accessors of arrays, each in a view of its own in one binary buffer."""

    def __init__(self) -> None:
        self.binary, self.views, self.accessors = b"", [], []  # type: ignore[var-annotated]

    def add(self, values: np.ndarray, normalized: bool = False) -> int:
        rows = values.reshape(len(values), -1)
        self.views.append({"buffer": 0, "byteOffset": len(self.binary), "byteLength": values.nbytes})
        self.binary += values.tobytes() + b"\0" * (-values.nbytes % 4)
        self.accessors.append({"bufferView": len(self.views) - 1, "componentType": _COMPONENTS[values.dtype],
                               "count": len(values), "type": _TYPES[rows.shape[1]],
                               **({"normalized": True} if normalized else {})})
        return len(self.accessors) - 1


def skinned_document(joints: np.ndarray = JOINTS, weights: np.ndarray = WEIGHTS, bind: np.ndarray = BIND,
                     turn: list[float] = QUARTER_TURN, nodes: list[dict[str, Any]] | None = None,
                     roots: list[int] | None = None) -> tuple[dict[str, Any], bytes]:
    """The strip skinned by skin 0 (joints nodes 1 and 2, 2 under 1 at (0, 1, 0) turned by `turn`), its mesh
    placed by node 0, which moves and scales it (glTF applies no transform of a skinned mesh's node), or by
    `nodes` appended, the scene's roots `roots` (else 0 and 1)."""
    parts = Parts()
    attributes = {"POSITION": parts.add(STRIP), "JOINTS_0": parts.add(joints),
                  "WEIGHTS_0": parts.add(weights, normalized=weights.dtype != np.float32)}
    indices = parts.add(CORNERS)
    skin: dict[str, Any] = {"joints": [1, 2], "inverseBindMatrices": parts.add(bind.transpose(0, 2, 1).copy())}
    document = {
        "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": roots if roots is not None else [0, 1]}],
        "nodes": [{"mesh": 0, "skin": 0, "translation": [5, 0, 0], "scale": [3, 3, 3]},
                  {"children": [2]}, {"translation": [0, 1, 0], "rotation": turn}, *(nodes or [])],
        "meshes": [{"primitives": [{"attributes": attributes, "indices": indices}]}],
        "skins": [skin], "accessors": parts.accessors, "bufferViews": parts.views,
        "buffers": [{"byteLength": len(parts.binary)}],
    }
    return document, parts.binary


def written(folder: Path, document: dict[str, Any], binary: bytes, name: str = "skinned.glb") -> Path:
    path = folder / name
    path.write_bytes(glb(document, binary))
    return path


def placed(positions: np.ndarray) -> list[tuple[float, ...]]:
    return sorted(tuple(round(float(value), 5) for value in row) for row in positions)


# --- placed as glTF places them ------------------------------------------------------------------
def test_a_skinned_strip_is_placed_by_its_joints_not_its_node(tmp_path: Path) -> None:
    """glTF: each vertex the sum of w_i * world(joint_i) * inverseBindMatrix_i * position, the skinned
    mesh's node not applied. trimesh applies no skin: the strip was drawn straight, moved by (5, 0, 0) and
    scaled 3 times by its node."""
    loaded = load_model(written(tmp_path, *skinned_document()))
    np.testing.assert_allclose(loaded.positions, BENT, atol=1e-6)
    assert loaded.warnings == ()


def test_at_the_bind_pose_a_skinned_mesh_is_where_its_inverse_bind_matrices_put_it(tmp_path: Path) -> None:
    """Joints where the inverse bind matrices bound them: each vertex as its POSITION gives it (Khronos's
    SimpleSkin at rest), whatever the mesh's node does; bound elsewhere, moved by as much (assimp's and
    bevy's copies of SimpleSkin bind it half a unit left: it was drawn from x 0 to 1, glTF's -0.5 to 0.5)."""
    at_rest = load_model(written(tmp_path, *skinned_document(turn=[0, 0, 0, 1])))
    np.testing.assert_allclose(at_rest.positions, STRIP, atol=1e-6)
    left = BIND.copy()
    left[:, 0, 3] = 0.5
    moved = load_model(written(tmp_path, *skinned_document(bind=left, turn=[0, 0, 0, 1]), name="left.glb"))
    np.testing.assert_allclose(moved.positions, STRIP + (0.5, 0, 0), atol=1e-6)
    document, binary = skinned_document(turn=[0, 0, 0, 1])
    del document["skins"][0]["inverseBindMatrices"]  # glTF's default: the identity each, joint 1 (0, 1, 0) off
    unbound = load_model(written(tmp_path, document, binary, name="unbound.glb"))
    np.testing.assert_allclose(unbound.positions, STRIP + [[0, 0, 0], [0, 0, 0], [0, 1, 0], [0, 0.5, 0]], atol=1e-6)


def test_weights_of_a_second_set_and_normalized_bytes_weigh_alike(tmp_path: Path) -> None:
    """JOINTS_1 and WEIGHTS_1 add their joints; weights of normalized bytes (255: 1) that add up to nearly 1
    are made to add up to 1, as three.js's reader makes them."""
    document, binary = skinned_document(weights=np.round(WEIGHTS * 255).astype(np.uint8))
    loaded = load_model(written(tmp_path, document, binary))
    np.testing.assert_allclose(loaded.positions, BENT, atol=1e-6)
    parts = Parts()
    parts.binary, parts.views, parts.accessors = binary, document["bufferViews"], document["accessors"]
    halves = WEIGHTS.copy()
    halves[3] = (0.5, 0, 0, 0)
    attributes = document["meshes"][0]["primitives"][0]["attributes"]
    attributes["WEIGHTS_0"] = parts.add(halves)
    attributes["JOINTS_1"] = parts.add(np.array([[0, 0, 0, 0]] * 3 + [[1, 0, 0, 0]], np.uint8))
    attributes["WEIGHTS_1"] = parts.add(np.array([[0, 0, 0, 0]] * 3 + [[0.5, 0, 0, 0]], np.float32))
    document["buffers"][0]["byteLength"] = len(parts.binary)
    two_sets = load_model(written(tmp_path, document, parts.binary, "two_sets.glb"))
    np.testing.assert_allclose(two_sets.positions, BENT, atol=1e-6)


def test_joints_are_placed_by_their_parents_and_a_skinned_nodes_children_by_it(tmp_path: Path) -> None:
    """A joint's world transform is its ancestors' times its own: the skeleton under a node that moves it by
    (0, 0, 2) moves the strip with it. The skinned mesh's node still places its children (a mesh of its own)."""
    document, binary = skinned_document(nodes=[{"children": [1], "translation": [0, 0, 2]}, {"mesh": 1}], roots=[0, 3])
    document["nodes"][0]["children"] = [4]
    document["meshes"].append({"primitives": [{"attributes": {"POSITION": 0}, "indices": 3}]})
    loaded = load_model(written(tmp_path, document, binary))
    child = STRIP * 3 + (5, 0, 0)  # placed by node 0: moved and scaled
    assert placed(loaded.positions) == placed(np.concatenate([BENT + (0, 0, 2), child]))


def test_a_mesh_placed_skinned_and_unskinned_is_drawn_both_ways_and_skinned_once(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Three nodes skin the mesh by skin 0 (each drawn where the joints place it: glTF draws it there three
    times), one places it unskinned by its own transform; the skinned positions are made once."""
    made: list[str] = []
    skinned = skins._skinned_positions

    def counted(*args: Any) -> np.ndarray:
        made.append(args[-1])
        return skinned(*args)

    monkeypatch.setattr(skins, "_skinned_positions", counted)
    extra = [{"mesh": 0, "skin": 0}, {"mesh": 0, "skin": 0, "translation": [9, 9, 9]},
             {"mesh": 0, "translation": [7, 0, 0]}]
    loaded = load_model(written(tmp_path, *skinned_document(nodes=extra, roots=[0, 1, 3, 4, 5])))
    assert placed(loaded.positions) == placed(np.concatenate([BENT, BENT, BENT, STRIP + (7, 0, 0)]))
    assert made == ["mesh 0's primitive 0, skinned by skin 0"] and loaded.warnings == ()


def test_a_mesh_skinned_by_two_skins_is_drawn_by_each(tmp_path: Path) -> None:
    """Skin 1 binds joint 1 of its own (node 3, turned the other way) where skin 0 binds node 2."""
    document, binary = skinned_document(nodes=[{"translation": [0, 1, 0], "rotation": [0, 0, -QUARTER_TURN[2],
                                                                                      QUARTER_TURN[3]]},
                                               {"mesh": 0, "skin": 1}], roots=[0, 1, 4])
    document["nodes"][1]["children"] = [2, 3]
    document["skins"].append({**document["skins"][0], "joints": [1, 3]})
    loaded = load_model(written(tmp_path, document, binary))
    turned_right = np.array([[0, 0, 0], [1, 0, 0], [1, 0, 0], [0.5, 1.5, 0]])  # (1, 2) about (0, 1) to (1, 0)
    assert placed(loaded.positions) == placed(np.concatenate([BENT, turned_right]))


def test_morph_targets_shape_the_mesh_before_its_skin_places_it(tmp_path: Path) -> None:
    """glTF morphs first, then skins: a target lifting every vertex by 3 along z, at weight 1, lifts the bent
    strip by 3 (joint 1 turns about z, which keeps z)."""
    document, binary = skinned_document()
    parts = Parts()
    parts.binary, parts.views, parts.accessors = binary, document["bufferViews"], document["accessors"]
    primitive = document["meshes"][0]["primitives"][0]
    primitive["targets"] = [{"POSITION": parts.add(np.full((4, 3), [0, 0, 3], np.float32))}]
    document["meshes"][0]["weights"] = [1.0]
    document["buffers"][0]["byteLength"] = len(parts.binary)
    loaded = load_model(written(tmp_path, document, parts.binary))
    np.testing.assert_allclose(loaded.positions, BENT + (0, 0, 3), atol=1e-6)
    assert loaded.warnings == ()


def test_a_sparse_position_skinned_is_made_dense_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The strip's POSITION, its top right corner moved by a sparse item, was made dense to be checked, then again
    to be skinned."""
    from marraztu.loaders.gltf import accessors

    unmoved = STRIP.copy()
    unmoved[2] = 0  # the base: the top right corner at the origin, moved back by the sparse item
    document, binary = skinned_document()
    parts = Parts()
    parts.binary, parts.views, parts.accessors = binary, document["bufferViews"], document["accessors"]
    where, value = (parts.accessors[parts.add(part)]["bufferView"] for part in (np.array([2], np.uint16), STRIP[2:3]))
    document["accessors"][0]["sparse"] = {"count": 1, "indices": {"bufferView": where, "componentType": 5123},
                                          "values": {"bufferView": value}}
    document["buffers"][0]["byteLength"] = len(parts.binary)
    binary = unmoved.tobytes() + parts.binary[unmoved.nbytes:]  # accessor 0's view is the first
    made: list[int] = []
    dense = accessors._dense_items
    monkeypatch.setattr(accessors, "_dense_items", lambda *args: (made.append(args[2]), dense(*args))[1])
    loaded = load_model(written(tmp_path, document, binary))
    np.testing.assert_allclose(loaded.positions, BENT, atol=1e-6)
    assert made == [0]


def test_a_gltf_of_no_skin_is_handed_to_trimesh_as_it_is(tmp_path: Path) -> None:
    document, binary = skinned_document()
    del document["nodes"][0]["skin"], document["skins"]
    path = written(tmp_path, document, binary)
    data = path.read_bytes()
    read = gltf.glb_document(path, data)
    shapes = gltf.morphed_shapes(read, held=len(data))
    skins = gltf.skinned_placements(read, len(data), shapes)
    assert skins == gltf.SkinnedPlacements()
    assert gltf.as_trimesh_reads(path, data, read, "glb", read_beside=bytes, shapes=shapes, skins=skins) is data


def test_skins_past_the_bytes_a_file_may_make_are_a_note_placed_by_their_node(tmp_path: Path) -> None:
    """Each joint is a matrix made: a skin of thousands of joints over a few vertices would make many times
    the file's bytes. Its mesh is placed by its node, with a note."""
    document, binary = skinned_document(turn=[0, 0, 0, 1])
    joints = 20_000
    document["nodes"] += [{}] * joints
    document["skins"][0]["joints"] = [1, 2, *range(3, 3 + joints)]
    del document["skins"][0]["inverseBindMatrices"]
    loaded = load_model(written(tmp_path, document, binary))
    np.testing.assert_allclose(loaded.positions, STRIP * 3 + (5, 0, 0), atol=1e-6)
    (note,) = loaded.warnings
    assert note.startswith("mesh 0's skinning by skin 0 would bring what is made to more than the ")
    assert note.endswith(": placed by its node, not its skin")


def test_a_skinned_mesh_whose_draco_stream_trimesh_decodes_is_a_note_placed_by_its_node(
        monkeypatch: pytest.MonkeyPatch) -> None:
    """trimesh writes what it decodes into the accessors the stream's attributes name, over the skinned
    positions (and reads no JOINTS_0 or WEIGHTS_0 it decodes): the mesh stays placed by its node."""
    draco_decoder(monkeypatch, True)
    document, _ = skinned_document()
    primitive = document["meshes"][0]["primitives"][0]
    primitive["extensions"] = {"KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"WEIGHTS_0": 2}}}
    skins = gltf.skinned_placements(document, 1000, gltf.MorphedShapes({}))
    assert skins == gltf.SkinnedPlacements((), ("mesh 0's primitive 0 is Draco-compressed: trimesh decodes it over "
                                                "what its skin makes: placed by its node, not its skin",))


def test_a_bent_skin_draws_as_the_strip_written_bent(tmp_path: Path) -> None:
    """The picture of the skinned strip is the picture of a plain strip at the bent positions."""
    bent, plain = written(tmp_path, *skinned_document()), Parts()
    document = {"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                "meshes": [{"primitives": [{"attributes": {"POSITION": plain.add(BENT.astype(np.float32))},
                                            "indices": plain.add(CORNERS)}]}]}
    document.update(accessors=plain.accessors, bufferViews=plain.views, buffers=[{"byteLength": len(plain.binary)}])
    pictures = [np.asarray(Image.open(take_screenshot(StartOptions(empty=True, models=(path,)),
                                                      tmp_path / f"{path.stem}.png", (80, 80), keys="0"))).astype(int)
                for path in (bent, written(tmp_path, document, plain.binary, "plain.glb"))]
    assert np.abs(pictures[0] - pictures[1]).max() <= 2
    assert (np.abs(pictures[0] - pictures[0][2, 2]).max(axis=2) > 40).sum() > 200  # the strip, not the background


# --- turned outward where its joints mirror it -------------------------------------------------------
SQUARE = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)  # facing +z, wound anticlockwise
# Each mode's corners of the square, wound to face +z: its triangles as glTF (and trimesh) make them.
SQUARE_CORNERS = {"triangles": (4, [0, 1, 2, 0, 2, 3]), "strip": (5, [0, 1, 3, 2]), "fan": (6, [0, 1, 2, 3]),
                  "unindexed": (4, None)}
MIRROR_X, MIRROR_Z = [-1.0, 1.0, 1.0], [1.0, 1.0, -1.0]  # a joint's scale: the second keeps the square in place
X_MIRRORED = np.array(MIRROR_X, np.float32)


def mirrored_square(mirror: list[float], on_mirror: list[int], mode: str = "triangles"
                    ) -> tuple[dict[str, Any], bytes]:
    """The green square skinned by joint 0 (node 1, unmoved) and joint 1 (node 2, scaled by `mirror`), its
    vertices `on_mirror` wholly on joint 1, the others on joint 0."""
    parts, (number, corners) = Parts(), SQUARE_CORNERS[mode]
    vertices = SQUARE if corners is not None else SQUARE[[0, 1, 2, 0, 2, 3]]
    joints = np.zeros((len(vertices), 4), np.uint8)
    joints[on_mirror, 0] = 1
    primitive: dict[str, Any] = {"mode": number, "material": 0, "attributes": {
        "POSITION": parts.add(vertices), "JOINTS_0": parts.add(joints),
        "WEIGHTS_0": parts.add(np.tile(np.array([1, 0, 0, 0], np.float32), (len(vertices), 1)))}}
    if corners is not None:
        primitive["indices"] = parts.add(np.array(corners, np.uint16))
    document = {
        "asset": {"version": "2.0"}, "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [{"mesh": 0, "skin": 0}, {}, {"scale": mirror}], "skins": [{"joints": [1, 2]}],
        "meshes": [{"primitives": [primitive]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.8, 0.1, 1]}}],
        "accessors": parts.accessors, "bufferViews": parts.views, "buffers": [{"byteLength": len(parts.binary)}],
    }
    return document, parts.binary


@pytest.mark.parametrize("mode", list(SQUARE_CORNERS))
def test_a_square_its_joint_mirrors_keeps_facing_out(tmp_path: Path, mode: str) -> None:
    """glTF turns round the triangles a mirroring transform places: the square mirrored left to right by its
    joint kept its winding, so it faced away (-z), its inside shown, whatever the mode of its triangles."""
    loaded = load_model(written(tmp_path, *mirrored_square(MIRROR_X, [0, 1, 2, 3], mode)))
    assert loaded.face_count == 2
    np.testing.assert_allclose(loaded.face_normals, [[0, 0, 1]] * 2, atol=1e-6)
    assert placed(loaded.positions) == placed((SQUARE if mode != "unindexed" else SQUARE[[0, 1, 2, 0, 2, 3]])
                                              * X_MIRRORED)


@pytest.mark.parametrize(("on_mirror", "facing"), [([], [1, 1]), ([0, 1, 2, 3], [-1, -1]), ([0, 1], [-1, 1]),
                                                   ([3], [1, 1]), ([0, 2], [-1, -1])])
def test_a_triangle_is_turned_where_most_of_its_corners_are_mirrored(tmp_path: Path, on_mirror: list[int],
                                                                     facing: list[int]) -> None:
    """Joint 1 mirrors z, which leaves the square where it is: a triangle two or three of whose corners it
    places is turned round, to face -z, as the mirrored square faces; one of one such corner, or none, is not."""
    loaded = load_model(written(tmp_path, *mirrored_square(MIRROR_Z, on_mirror)))
    np.testing.assert_allclose(loaded.positions, SQUARE, atol=1e-6)
    np.testing.assert_allclose(loaded.face_normals[:, 2], facing, atol=1e-6)


def test_a_square_its_joint_mirrors_shows_its_colour_with_culling_on(tmp_path: Path) -> None:
    """Drawn from its front with back faces culled (b), untextured and lit by the bulb alone (T 0 1), the mirrored
    square shows its green, as the same square written mirrored, its triangles turned, does; its inside faced the
    camera, and it was culled to the background."""
    plain = Parts()
    document = {"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
                "meshes": [{"primitives": [{"attributes": {"POSITION": plain.add(SQUARE * X_MIRRORED)}, "material": 0,
                                            "indices": plain.add(np.array([2, 1, 0, 3, 2, 0], np.uint16))}]}],
                "materials": mirrored_square(MIRROR_X, [])[0]["materials"]}
    document.update(accessors=plain.accessors, bufferViews=plain.views, buffers=[{"byteLength": len(plain.binary)}])
    files = (written(tmp_path, *mirrored_square(MIRROR_X, [0, 1, 2, 3]), "mirrored.glb"),
             written(tmp_path, document, plain.binary, "plain.glb"))
    pictures = [np.asarray(Image.open(take_screenshot(StartOptions(empty=True, models=(path,)),
                                                      tmp_path / f"{path.stem}.png", (80, 80), keys="T 0 1 b")))
                .astype(int) for path in files]
    middle = pictures[0][40, 40]
    assert middle[1] > middle[0] + 40 and middle[1] > middle[2] + 40, middle  # green, not the background
    assert np.abs(pictures[0] - pictures[1]).max() <= 2


# --- refused where it enters -----------------------------------------------------------------------
def edited(edit: Callable[[dict[str, Any]], None], **arrays: Any) -> Callable[[Path], Path]:
    def write(folder: Path) -> Path:
        document, binary = skinned_document(**arrays)
        edit(document)
        return written(folder, document, binary)
    return write


def _as_it_is(document: dict[str, Any]) -> None:
    pass


def _set(where: Callable[[dict[str, Any]], dict[str, Any]], key: str, value: object) -> Callable[[dict[str, Any]],
                                                                                                  None]:
    return lambda document: where(document).__setitem__(key, value)


def _skin(document: dict[str, Any]) -> dict[str, Any]:
    return document["skins"][0]


def _attributes(document: dict[str, Any]) -> dict[str, Any]:
    return document["meshes"][0]["primitives"][0]["attributes"]


_PROJECTIVE = BIND.copy()
_PROJECTIVE[1, 3, 0] = 0.5
_NAN_BIND = BIND.copy()
_NAN_BIND[1, 2, 2] = np.nan
_PAST = JOINTS.copy()
_PAST[3, 1] = 2
_NAN_WEIGHTS, _NEGATIVE, _NONE = WEIGHTS.copy(), WEIGHTS.copy(), WEIGHTS.copy()
_NAN_WEIGHTS[2, 3], _NEGATIVE[1] = np.inf, (1.5, -0.5, 0, 0)
_NONE[3] = 0
_NONE_PAST = JOINTS.copy()
_NONE_PAST[3, 0] = 2
_WHAT = "mesh 0's primitive 0, skinned by skin 0"


@pytest.mark.parametrize(("write", "words"), [
    (edited(_set(lambda d: d["nodes"][0], "skin", 3)), "not a glTF file: node 0 names skin 3, of 1"),
    (edited(_set(_skin, "joints", [1, 7])), "not a glTF file: skin 0's joints names node 7, of 3"),
    (edited(_set(_skin, "joints", [])), "not a glTF file: skin 0 has no joints: glTF's skins list one or more"),
    (edited(_set(_skin, "joints", 1)), "not a glTF file: skin 0's joints are not a list"),
    (edited(_set(_skin, "skeleton", 5)), "not a glTF file: skin 0's skeleton names node 5, of 3"),
    (edited(_set(_skin, "inverseBindMatrices", 0)),
     "not a glTF file: skin 0's inverseBindMatrices are accessor 0, of type VEC3 and componentType 5126: glTF's are "
     "MAT4 of 5126 (float)"),
    (edited(_set(_skin, "joints", [1, 2, 1])),
     "not a glTF file: skin 0's inverseBindMatrices are accessor 4, of 2 items, for its 3 joints: glTF's have one a "
     "joint"),
    (edited(lambda d: _attributes(d).pop("WEIGHTS_0")),
     "not a glTF file: node 0 skins mesh 0 by skin 0, whose primitive 0 has no WEIGHTS_0: glTF's skinned primitives "
     "have JOINTS_0 and WEIGHTS_0, and each JOINTS_n with its WEIGHTS_n"),
    (edited(lambda d: _attributes(d).__setitem__("JOINTS_1", 1)),
     "not a glTF file: node 0 skins mesh 0 by skin 0, whose primitive 0 has no WEIGHTS_1: glTF's skinned primitives "
     "have JOINTS_0 and WEIGHTS_0, and each JOINTS_n with its WEIGHTS_n"),
    (edited(_as_it_is, joints=JOINTS.astype(np.float32)),
     "not a glTF file: mesh 0's primitive 0's JOINTS_0 is accessor 1, of componentType 5126: glTF's are 5121 or "
     "5123, not normalized"),
    (edited(lambda d: d["accessors"][2].__setitem__("componentType", 5125)),
     "not a glTF file: mesh 0's primitive 0's WEIGHTS_0 is accessor 2, of componentType 5125: glTF's are 5126 "
     "(float), or 5121 or 5123 normalized"),
    (edited(lambda d: d["accessors"][2].__setitem__("type", "VEC3")),
     "not a glTF file: mesh 0's primitive 0's WEIGHTS_0 is accessor 2, of type VEC3: glTF's are VEC4"),
    (edited(_as_it_is, bind=_NAN_BIND),
     "skin 0's inverseBindMatrices (accessor 4): matrix 1 holds a value that is not a finite number"),
    (edited(_as_it_is, bind=_PROJECTIVE),
     "skin 0's inverseBindMatrices (accessor 4): matrix 1's last row is 0.5 0 0 1, where glTF's are 0 0 0 1"),
    (edited(_as_it_is, joints=_PAST),
     f"{_WHAT}: vertex 3's JOINTS_0 names joint 2, of the skin's 2, at a weight above 0"),
    (edited(_as_it_is, weights=_NAN_WEIGHTS), f"{_WHAT}: vertex 2's WEIGHTS_0 holds inf, not a finite number"),
    (edited(_as_it_is, weights=_NEGATIVE),
     f"{_WHAT}: vertex 1's WEIGHTS_0 holds -0.5, where glTF's weights are 0 or more"),
    (edited(_as_it_is, joints=_NONE_PAST, weights=_NONE),
     f"{_WHAT}: vertex 3 is weighted by no joint, and the first joint of its JOINTS_0, which would place it, is "
     "joint 2, of the skin's 2"),
])
def test_a_skin_not_shaped_as_gltfs_is_refused_in_one_line(tmp_path: Path, write: Callable[[Path], Path],
                                                          words: str) -> None:
    """trimesh reads no skin, so any passed; a skin that places a mesh is read now, and checked."""
    assert one_line_refusal(lambda: load_model(write(tmp_path))).message == words


@pytest.mark.parametrize("edit", [lambda d: d["accessors"][1].__setitem__("componentType", 5120),
                                  lambda d: d["accessors"][2].__setitem__("componentType", 5125),
                                  lambda d: d["accessors"][2].__setitem__("type", "VEC3")],
                         ids=["signed-byte joints", "uint weights", "VEC3 weights"])
def test_skin_sets_of_types_gltf_forbids_on_a_primitive_no_skin_moves_are_read_past(
        tmp_path: Path, edit: Callable[[dict[str, Any]], None]) -> None:
    """JOINTS_0 and WEIGHTS_0 are read only where a skin moves the primitive; trimesh reads none. Of a type
    glTF forbids on a mesh no node skins, they were refused."""
    document, binary = skinned_document()
    del document["nodes"][0]["skin"]
    edit(document)
    loaded = load_model(written(tmp_path, document, binary))
    np.testing.assert_allclose(loaded.positions, STRIP * 3 + (5, 0, 0), atol=1e-6)
    assert loaded.warnings == ()


def test_vertices_weighted_by_no_joint_are_placed_by_their_first_joint_with_a_note(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Blender's exporter writes weights of 0 for a vertex in no vertex group; three.js's normalizeSkinWeights
    gives such a vertex weight 1 on its first joint slot. They were refused ("weights add up to 0"). Vertex 1's
    first joint is joint 0, which keeps it; vertex 3's joint 1, which turns it about (0, 1) to (-1, 1); counted
    over blocks of two vertices, once for the file."""
    monkeypatch.setattr(skins, "_CHECKED_ITEMS", 2)
    joints, weights = JOINTS.copy(), WEIGHTS.copy()
    joints[3], weights[1], weights[3] = (1, 0, 0, 0), 0, 0
    loaded = load_model(written(tmp_path, *skinned_document(joints=joints, weights=weights)))
    np.testing.assert_allclose(loaded.positions, [[0, 0, 0], [1, 0, 0], [-1, 2, 0], [-1, 1, 0]], atol=1e-6)
    assert loaded.warnings == ("2 vertices weighted by no joint are placed by their first joint, as three.js places "
                               "them (the first, vertex 1 of mesh 0's primitive 0)",)


def test_a_vertex_weighted_by_no_joint_is_noted_once_however_many_skins_place_it(tmp_path: Path) -> None:
    """Skin 1 places the mesh too (its joint 1, node 3, not turned): vertex 3 is placed by joint 0 by each."""
    weights = WEIGHTS.copy()
    weights[3] = 0
    document, binary = skinned_document(weights=weights, nodes=[{"translation": [0, 1, 0]}, {"mesh": 0, "skin": 1}],
                                        roots=[0, 1, 4])
    document["nodes"][1]["children"] = [2, 3]
    document["skins"].append({**document["skins"][0], "joints": [1, 3]})
    loaded = load_model(written(tmp_path, document, binary))
    assert placed(loaded.positions) == placed(np.concatenate([BENT[:3], STRIP[3:], STRIP]))
    assert loaded.warnings == ("1 vertex weighted by no joint is placed by its first joint, as three.js places it "
                               "(vertex 3 of mesh 0's primitive 0)",)


def test_a_joint_past_the_skins_at_weight_0_is_read_past(tmp_path: Path) -> None:
    """A joint of weight 0 moves nothing (three.js's shader multiplies its matrix by 0); one past the skin's
    joints was refused, and is read past. Vertex 0's second slot names joint 255, vertex 3's third joint 2."""
    joints = JOINTS.copy()
    joints[0, 1], joints[3, 2] = 255, 2
    loaded = load_model(written(tmp_path, *skinned_document(joints=joints)))
    np.testing.assert_allclose(loaded.positions, BENT, atol=1e-6)
    assert loaded.warnings == ()


def test_a_joint_that_takes_a_vertex_past_floats_range_is_refused(tmp_path: Path) -> None:
    """Joints scaled 1e30 each: vertex 2, which joint 1 (under joint 0) places, by 1e60."""
    document, binary = skinned_document()
    document["nodes"][1]["scale"] = [1e30, 1e30, 1e30]
    document["nodes"][2]["scale"] = [1e30, 1e30, 1e30]
    path = written(tmp_path, document, binary)
    assert one_line_refusal(lambda: load_model(path)).message == (
        f"{_WHAT}: vertex 2 is placed by its joints at a coordinate that is not a finite number (their transforms "
        "take it past float's range)")


class _CountedModes(tuple):  # type: ignore[type-arg]
    """glTF's drawn modes, counting each time a primitive's mode is looked up in them."""

    looked_up = 0

    def __contains__(self, mode: object) -> bool:
        self.looked_up += 1
        return super().__contains__(mode)


def test_a_mesh_skinned_by_many_nodes_has_its_primitives_checked_once(tmp_path: Path,
                                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    """Each node that skins a mesh had each of the mesh's primitives checked for its JOINTS_n and WEIGHTS_n:
    nodes times primitives, from a small file."""
    many = 300
    document, binary = skinned_document(nodes=[{"mesh": 0, "skin": 0}] * many + [{"mesh": 1}], roots=[3 + many])
    document["meshes"][0]["primitives"] *= many
    document["meshes"].append({"primitives": [{"attributes": {"POSITION": 0}, "indices": 3}]})
    modes = _CountedModes(values._DRAWN_MODES)
    monkeypatch.setattr(values, "_DRAWN_MODES", modes)
    assert load_model(written(tmp_path, document, binary)).face_count == 2
    assert modes.looked_up < 10 * many, modes.looked_up


def test_a_skinned_shape_of_a_mesh_is_named_as_the_files_mesh(tmp_path: Path) -> None:
    """A shape other than the base is drawn by a copy of the mesh, numbered past the file's meshes: a skin's
    refusal of that copy named "mesh 1" in a file of one mesh."""
    weights = WEIGHTS.copy()
    weights[2, 3] = np.nan
    document, binary = skinned_document(weights=weights, nodes=[{"mesh": 0}], roots=[0, 1, 3])
    parts = Parts()
    parts.binary, parts.views, parts.accessors = binary, document["bufferViews"], document["accessors"]
    document["meshes"][0]["primitives"][0]["targets"] = [{"POSITION": parts.add(np.full((4, 3), 3, np.float32))}]
    document["nodes"][0]["weights"] = [1.0]  # node 3 draws the base shape, in the mesh's place
    document["buffers"][0]["byteLength"] = len(parts.binary)
    path = written(tmp_path, document, parts.binary)
    refusal = one_line_refusal(lambda: load_model(path)).message
    assert refusal == f"{_WHAT}: vertex 2's WEIGHTS_0 holds nan, not a finite number"


def test_skinning_holds_a_block_of_its_vertices_widened_not_all(tmp_path: Path,
                                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    """Each JOINTS_n and WEIGHTS_n was made intp and float64 whole before any vertex was placed, three times
    the file's bytes, the peak of the whole load. A block at a time, skinning holds the positions it makes
    (float32 VEC3s) and a block's temporaries."""
    import tracemalloc

    vertices, sets = 39_999, 2
    rng = np.random.default_rng(5)
    parts = Parts()
    attributes = {"POSITION": parts.add(rng.random((vertices, 3), dtype=np.float32))}
    for n in range(sets):
        attributes[f"JOINTS_{n}"] = parts.add(rng.integers(0, 2, (vertices, 4)).astype(np.uint8))
        attributes[f"WEIGHTS_{n}"] = parts.add(rng.integers(1, 60, (vertices, 4)).astype(np.uint8), normalized=True)
    document, binary = skinned_document()
    parts.add(BIND.transpose(0, 2, 1).copy())
    document.update(accessors=parts.accessors, bufferViews=parts.views, buffers=[{"byteLength": len(parts.binary)}])
    document["skins"][0]["inverseBindMatrices"] = len(parts.accessors) - 1
    document["meshes"][0]["primitives"][0] = {"attributes": attributes}
    path = written(tmp_path, document, parts.binary)
    skinned, growth = skins._skinned_positions, []

    def measured(*args: Any) -> np.ndarray:
        tracemalloc.start()
        try:
            placed = skinned(*args)
            growth.append(tracemalloc.get_traced_memory()[1])
        finally:
            tracemalloc.stop()
        return placed

    monkeypatch.setattr(skins, "_skinned_positions", measured)
    monkeypatch.setattr(skins, "_CHECKED_ITEMS", 1024)  # a block's temporaries small beside the vertices'
    assert load_model(path).warnings == ()
    # Widened whole, the two sets alone took 128 bytes a vertex: room left for numpy's temporaries to change.
    assert growth[0] < 4 * 12 * vertices, growth
