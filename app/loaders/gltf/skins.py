"""Skins: the meshes their joints place, at rest, counted against the limit on what is made, and their
skinned positions made for trimesh, which draws a skinned mesh where its node places it.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from marraztu.errors import LoadError
from marraztu.loaders.gltf.accessors import (
    _CHECKED_ITEMS,
    _UINT32_COMPONENTS,
    _MadeBuffer,
    _triangles,
    _values,
    _values_in_blocks,
)
from marraztu.loaders.gltf.counts import _draws_faces, _placed_node_numbers, _primitive_size
from marraztu.loaders.gltf.morphs import _BASE_SHAPE, _MORPHED_ITEM_BYTES, MorphedShapes
from marraztu.loaders.gltf.values import (
    _FLOAT_COMPONENTS,
    _SKIN_SETS,
    _TRIANGLES,
    _draco_attributes,
    _draco_decoder,
    _is_drawn,
    _mesh_copy,
    _mesh_named,
    made_limit,
    past_made_limit,
)
from marraztu.model.mesh import counted

# What a skin makes and reads besides its vertices: a joint's matrix and its node's placement (4x4 float64s).
_JOINT_BYTES = 2 * 16 * 8
_TURNED_TRIANGLE_BYTES = 3 * 4  # a triangle whose winding is turned round: its corners made uint32s


_AFFINE_ROW, _AFFINE_TOLERANCE = np.array([0.0, 0.0, 0.0, 1.0]), 1e-6  # an inverse bind matrix's last row


@dataclass(frozen=True)
class SkinnedPlacements:
    """The placed nodes whose skins place their meshes (glTF applies no transform of a skinned mesh's own
    node), each with the file's number of the mesh it skins (a shape's copy is numbered past the file's:
    _mesh_per_shape), and the notes of the meshes left placed by their nodes, what their skins would make
    being past the limit."""

    nodes: tuple[tuple[int, int], ...] = ()
    notes: tuple[str, ...] = ()


def skinned_placements(document: dict[str, Any], held: int, shapes: MorphedShapes) -> SkinnedPlacements:
    """The placed nodes of a checked glTF that skin their meshes, from its JSON. What the skins read and make,
    with what `shapes` does, may come to no more than made_limit(held) bytes: a mesh is skinned once for each
    skin and shape it is placed in, however many nodes place it so; one past the limit, or whose Draco stream
    trimesh decodes, is placed by its nodes, with a note. Each mesh is looked at once."""
    nodes, meshes = document.get("nodes", []), document.get("meshes", [])
    shape_of = {node: weights for by_weights in shapes.by_mesh.values() for weights, placing in by_weights.items()
                for node in placing}
    budget, made = made_limit(held) - shapes.made, 0
    applied: dict[tuple[Any, ...], bool] = {}  # (mesh, its shape, skin) -> whether it is skinned
    costs: dict[int, tuple[int, int | None]] = {}  # mesh -> (what skinning it makes, its Draco primitive)
    skins_counted: set[int] = set()
    skinned, unapplied = [], []
    for number in sorted(set(_placed_node_numbers(document))):
        node = nodes[number]
        if "skin" not in node or "mesh" not in node:
            continue
        key = (node["mesh"], shape_of.get(number, _BASE_SHAPE), node["skin"])
        if key not in applied:
            mesh = meshes[node["mesh"]]
            if node["mesh"] not in costs:
                costs[node["mesh"]] = (len(json.dumps(_mesh_copy(mesh))) + _skinning_bytes(document["accessors"], mesh),
                                       _draco_skinned(mesh))
            mesh_bytes, compressed = costs[node["mesh"]]
            joints = 0 if node["skin"] in skins_counted else len(document["skins"][node["skin"]]["joints"])
            work = mesh_bytes + _JOINT_BYTES * joints
            applied[key] = compressed is None and made + work <= budget
            if applied[key]:
                made += work
                skins_counted.add(node["skin"])
            elif compressed is not None:
                unapplied.append(f"{_mesh_named(node['mesh'], mesh)}'s primitive {compressed} is Draco-compressed: "
                                 "trimesh decodes it over what its skin makes")
            else:
                unapplied.append(f"{_mesh_named(node['mesh'], mesh)}'s skinning by skin {node['skin']} would bring "
                                 f"what is made to {past_made_limit(held)}")
        if applied[key]:
            skinned.append((number, node["mesh"]))
    return SkinnedPlacements(tuple(skinned), _unskinned_notes(unapplied))


def _draco_skinned(mesh: dict[str, Any]) -> int | None:
    """The first drawn primitive whose Draco stream holds what a skin reads (POSITION, JOINTS_n, WEIGHTS_n),
    where trimesh decodes it: it writes them, after the skin is applied, into the accessors they name."""
    if not _draco_decoder():
        return None
    return next((number for number, primitive in enumerate(mesh["primitives"]) if _is_drawn(primitive)
                 and any(name == "POSITION" or name.startswith(_SKIN_SETS) for name in _draco_attributes(primitive))),
                None)


def _skinning_bytes(accessors: list[dict[str, Any]], mesh: dict[str, Any]) -> int:
    """What skinning a mesh reads and writes, in _MORPHED_ITEM_BYTES a vertex: for each drawn primitive its
    POSITION, its skinned positions, and each JOINTS_n and WEIGHTS_n set; and its triangles, should its joints
    mirror them (_Skinning.faces_turned)."""
    total = 0
    for primitive in filter(_is_drawn, mesh["primitives"]):
        sets = len(_skin_sets(primitive["attributes"]))
        total += _MORPHED_ITEM_BYTES * accessors[primitive["attributes"]["POSITION"]]["count"] * (2 + 2 * sets)
        total += _TURNED_TRIANGLE_BYTES * (_primitive_size(accessors, primitive) or (0, 0))[0]
    return total


def _skin_sets(attributes: dict[str, Any]) -> list[str]:
    """The n of each JOINTS_n (each with its WEIGHTS_n: GltfReferences.skinned_primitives)."""
    return sorted(name[len(_SKIN_SETS[0]):] for name in attributes if name.startswith(_SKIN_SETS[0]))


def _unskinned_notes(reasons: list[str]) -> tuple[str, ...]:
    """One note of the skinned meshes placed by their nodes (a reason each), the first named."""
    if not reasons:
        return ()
    if len(reasons) == 1:
        return (f"{reasons[0]}: placed by its node, not its skin",)
    return (f"{len(reasons)} skinned meshes placed by their nodes, not their skins (the first, {reasons[0]})",)


def _skins_applied(path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview],
                   skins: SkinnedPlacements, notes: list[str]) -> bool:
    """Places each mesh that the nodes of `skins` skin as glTF does at the nodes' rest transforms (animations
    are not read): each vertex where its joints take it, the sum of w_i * world(joint_i) *
    inverseBindMatrix_i * position over its JOINTS_n and WEIGHTS_n, in a buffer appended as a data: URI; the
    mesh taken off its node (whose children it still places) onto a root node of its own, which places it
    where it is. trimesh applies no skin, and places a skinned mesh by its node. A mesh is skinned once for
    each skin and shape (its morph targets applied first: _shapes_made), however many nodes place it so, into
    a copy where nodes draw it otherwise too. A note is added to `notes` of the vertices weighted by no joint
    (_unweighted_note). False where there is none."""
    if not skins.nodes:
        return False
    nodes = document["nodes"]
    skinned_nodes = {number for number, _ in skins.nodes}
    unskinned = {nodes[number]["mesh"] for number in _placed_node_numbers(document)
                 if "mesh" in nodes[number] and number not in skinned_nodes}
    skinning = _Skinning(path, document, buffer, unskinned)
    roots = document["scenes"][document.get("scene", 0)]["nodes"]
    for number, file_mesh in skins.nodes:
        node = nodes[number]
        mesh = skinning.mesh(node["mesh"], node["skin"], file_mesh)
        del node["mesh"], node["skin"]
        nodes.append({"mesh": mesh})
        roots.append(len(nodes) - 1)
    skinning.made.append()
    notes.extend(_unweighted_note(list(skinning.unweighted.values())))
    return True


def _unweighted_note(found: list[tuple[int, int, str]]) -> tuple[str, ...]:
    """One note of the vertices whose weights are all 0 (Blender's exporter writes them for a vertex in no
    vertex group), from each skinned set's (count, first vertex, what it is), the first named."""
    count = sum(unweighted for unweighted, _, _ in found)
    if not count:
        return ()
    _, vertex, what = next(item for item in found if item[0])
    placed = ("is placed by its first joint, as three.js places it" if count == 1
              else "are placed by their first joint, as three.js places them")
    first = "" if count == 1 else "the first, "
    return (f"{counted(count, 'vertex', 'vertices')} weighted by no joint {placed} ({first}vertex {vertex} of "
            f"{what})",)


class _Skinning:
    """The skinned copies of a checked glTF's meshes, each made once, and what they are made of: the positions
    skinned, the skins' joints' matrices and the nodes' places. `unskinned`: the meshes nodes draw unskinned
    too, which keep their place."""

    def __init__(self, path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview],
                 unskinned: set[int]) -> None:
        self.path, self.document, self.buffer, self.unskinned = path, document, buffer, unskinned
        self.made = _MadeBuffer(document)
        self.sources: dict[int, dict[str, Any]] = {}  # each mesh as the file gives it, before its place is taken
        self.meshes: dict[tuple[int, int], int] = {}  # (mesh, skin) -> its skinned copy
        self.positions: dict[tuple[Any, ...], int] = {}  # (POSITION, its sets, skin) -> the accessor skinned
        self.mirrored: dict[int, np.ndarray] = {}  # an accessor skinned -> its vertices mirrored, where some are
        self.turned: dict[tuple[Any, ...], int | None] = {}  # (indices, mode, accessor skinned) -> turned triangles
        self.matrices: dict[int, np.ndarray] = {}  # skin -> its joints' matrices
        self.places = _WorldTransforms(document)
        # each skinned primitive's JOINTS_n and WEIGHTS_n -> its vertices weighted by no joint: (count, first, what)
        self.unweighted: dict[tuple[tuple[int, int], ...], tuple[int, int, str]] = {}

    def mesh(self, number: int, skin: int, file_mesh: int) -> int:
        """Mesh `number` skinned by `skin`, made once: in the mesh's place where no node draws it otherwise.
        `file_mesh`: the number the file gives it, which its refusals name."""
        if (number, skin) in self.meshes:
            return self.meshes[number, skin]
        meshes = self.document["meshes"]
        in_place = number not in self.unskinned and number not in self.sources
        source = self.sources.setdefault(number, meshes[number])
        mesh = _mesh_copy(source)
        if in_place:
            meshes[number] = mesh
        else:
            meshes.append(mesh)
        self.meshes[number, skin] = number if in_place else len(meshes) - 1
        named = _mesh_named(file_mesh, source)
        for primitive_number, (primitive, original) in enumerate(zip(mesh["primitives"], source["primitives"])):
            attributes = primitive["attributes"]
            for name in [name for name in attributes if name.startswith(_SKIN_SETS)]:
                del attributes[name]  # read here, not by trimesh
            if _is_drawn(original):
                attributes["POSITION"] = self.position(original, skin, f"{named}'s primitive {primitive_number}")
                self.faces_turned(primitive, original)
        return self.meshes[number, skin]

    def position(self, primitive: dict[str, Any], skin: int, what: str) -> int:
        """The accessor of a primitive's positions skinned by `skin`, made once for its POSITION and sets."""
        attributes = primitive["attributes"]
        sets = _skin_sets(attributes)
        weights = tuple((attributes[f"JOINTS_{n}"], attributes[f"WEIGHTS_{n}"]) for n in sets)
        key = (attributes["POSITION"], weights, skin)
        if key not in self.positions:
            if skin not in self.matrices:
                self.matrices[skin] = _joint_matrices(self.path, self.document, skin, self.buffer, self.places)
            placed, mirrored, unweighted = _skinned_positions(self.path, self.document, attributes, sets,
                                                              self.matrices[skin], self.buffer,
                                                              f"{what}, skinned by skin {skin}")
            self.unweighted.setdefault(weights, (*unweighted, what))  # its vertices counted once, however skinned
            self.positions[key] = self.made.accessor(placed, {"componentType": _FLOAT_COMPONENTS, "type": "VEC3"})
            if mirrored.any():
                self.mirrored[self.positions[key]] = mirrored
        return self.positions[key]

    def faces_turned(self, primitive: dict[str, Any], source: dict[str, Any]) -> None:
        """Turns round each triangle of a skinned primitive (`source`, as the file gives it) where two or three of
        its corners are placed by a blend of their joints' matrices that mirrors (of negative determinant), as
        glTF turns round the triangles of a mirroring node: the primitive made one of triangles, of the same
        corners in the same order, once for its indices and skinned positions. A Draco primitive's indices are
        its stream's, which trimesh decodes: left as they are."""
        mirrored = self.mirrored.get(primitive["attributes"]["POSITION"])
        if mirrored is None or _draco_attributes(source) or not _draws_faces(self.document["accessors"], source):
            return
        key = (source.get("indices"), source.get("mode", _TRIANGLES), primitive["attributes"]["POSITION"])
        if key not in self.turned:
            triangles = _triangles(self.path, self.document, source, self.buffer)
            turned = mirrored[triangles].sum(axis=1) >= 2
            triangles[turned] = triangles[turned, ::-1]
            self.turned[key] = self.made.accessor(triangles.reshape(-1), {
                "componentType": _UINT32_COMPONENTS, "type": "SCALAR"}) if turned.any() else None
        if self.turned[key] is not None:
            primitive["mode"], primitive["indices"] = _TRIANGLES, self.turned[key]


def _joint_matrices(path: Path, document: dict[str, Any], number: int, buffer: Callable[[int], bytes | memoryview],
                    places: Callable[[int], np.ndarray]) -> np.ndarray:
    """(joints, 3, 4) float64: skin `number`'s world(joint) * inverseBindMatrix, each joint's, their last row
    (0 0 0 1) left out. Inverse bind matrices of a value not finite, or not affine, are refused."""
    skin = document["skins"][number]
    joints = skin["joints"]
    if "inverseBindMatrices" not in skin:  # glTF's default: the identity each
        inverses = np.broadcast_to(np.eye(4), (len(joints), 4, 4))
    else:
        index = skin["inverseBindMatrices"]
        values = _values(path, document, index, buffer)[:len(joints)].astype(np.float64)
        inverses = values.reshape(-1, 4, 4).transpose(0, 2, 1)  # glTF's matrices are stored by column
        said = f"skin {number}'s inverseBindMatrices (accessor {index})"
        unheld = ~np.isfinite(values).all(axis=1)
        if unheld.any():
            raise LoadError(path, f"{said}: matrix {np.argmax(unheld)} holds a value that is not a finite number")
        projective = np.abs(inverses[:, 3] - _AFFINE_ROW).max(axis=1) > _AFFINE_TOLERANCE
        if projective.any():
            at = int(np.argmax(projective))
            row = " ".join(f"{value:g}" for value in inverses[at, 3])
            raise LoadError(path, f"{said}: matrix {at}'s last row is {row}, where glTF's are 0 0 0 1")
    with np.errstate(all="ignore"):  # past float's range: the positions made of it are refused
        return (np.stack([places(joint) for joint in joints]) @ inverses)[:, :3]


def _skinned_positions(path: Path, document: dict[str, Any], attributes: dict[str, Any], sets: list[str],
                       matrices: np.ndarray, buffer: Callable[[int], bytes | memoryview], what: str
                       ) -> tuple[np.ndarray, np.ndarray, tuple[int, int]]:
    """(vertices, 3) float32: each vertex's POSITION through its joints' `matrices`, weighed by its weights,
    which are made to add up to 1 (as three.js's glTF reader does: quantized weights add up to nearly 1); which
    vertices that blend of matrices mirrors ((vertices,) bool); and how many vertices are weighted by no joint,
    with the first (-1: none). Such a vertex takes weight 1 on
    its JOINTS_0's first joint, as three.js's normalizeSkinWeights gives it (a set's values: _checked_weights,
    _checked_joints). A block of vertices at a time, its sets widened (intp joints, float64 weights) for that
    block alone: whole, they held several times the file's."""
    count = document["accessors"][attributes["POSITION"]]["count"]
    positions = _values_in_blocks(path, document, attributes["POSITION"], buffer)
    read = [(n, _values_in_blocks(path, document, attributes[f"JOINTS_{n}"], buffer),
             _values_in_blocks(path, document, attributes[f"WEIGHTS_{n}"], buffer)) for n in sets]
    placed, mirrored = np.empty((count, 3), np.float32), np.empty(count, bool)
    unweighted, first = 0, -1
    for low in range(0, count, _CHECKED_ITEMS):
        block = slice(low, low + _CHECKED_ITEMS)
        widened = {n: (joints(block).astype(np.intp), _checked_weights(path, n, weights(block), what, low))
                   for n, joints, weights in read}
        total = sum(weights.sum(axis=1) for _, weights in widened.values())
        if (none := total == 0).any():
            _first_joint_weighted(path, *widened["0"], none, len(matrices), what, low)
            total[none] = 1
            first = first if unweighted else low + int(np.argmax(none))
            unweighted += int(none.sum())
        weighed = [_checked_joints(path, n, joints, weights, len(matrices), what, low)
                   for n, (joints, weights) in widened.items()]
        with np.errstate(all="ignore"):  # past float's range: refused below
            placed[block] = _weighed_sum(positions(block).astype(np.float64), weighed, matrices) / total[:, None]
            mirrored[block] = _mirroring(weighed, matrices)
    unheld = ~np.isfinite(placed).all(axis=1)
    if unheld.any():
        raise LoadError(path, f"{what}: vertex {np.argmax(unheld)} is placed by its joints at a coordinate that is not "
                              "a finite number (their transforms take it past float's range)")
    return placed, mirrored, (unweighted, first)


def _first_joint_weighted(path: Path, joints: np.ndarray, weights: np.ndarray, none: np.ndarray, joint_count: int,
                          what: str, low: int) -> None:
    """Weight 1 on the first joint of JOINTS_0 (a block from vertex `low`) of each vertex weighted by no joint
    (`none`), refused where it names none of the skin's `joint_count`: nothing says what would place it."""
    if (outside := none & (joints[:, 0] >= joint_count)).any():
        vertex = int(np.argmax(outside))
        raise LoadError(path, f"{what}: vertex {low + vertex} is weighted by no joint, and the first joint of its "
                              f"JOINTS_0, which would place it, is joint {joints[vertex, 0]}, of the skin's "
                              f"{joint_count}")
    weights[none, 0] = 1


def _weighed_sum(positions: np.ndarray, weighed: list[tuple[np.ndarray, np.ndarray]], matrices: np.ndarray
                 ) -> np.ndarray:
    """(vertices, 3) float64: the sum of each vertex's weights times its joints' matrices times it."""
    moved = np.zeros((len(positions), 3))
    for joints, weights in weighed:
        for column in range(joints.shape[1]):
            gathered = matrices[joints[:, column]]
            moved += weights[:, column, None] * (np.einsum("vij,vj->vi", gathered[:, :, :3], positions)
                                                 + gathered[:, :, 3])
    return moved


def _mirroring(weighed: list[tuple[np.ndarray, np.ndarray]], matrices: np.ndarray) -> np.ndarray:
    """(vertices,) bool: whether the sum of each vertex's weights times its joints' matrices mirrors it, its
    determinant below 0 (their sum, not made to add up to 1: a scale by more than 0 keeps the sign)."""
    blended = np.zeros((len(weighed[0][0]), 3, 3))
    for joints, weights in weighed:
        for column in range(joints.shape[1]):
            blended += weights[:, column, None, None] * matrices[joints[:, column], :, :3]
    return np.linalg.det(blended) < 0


def _checked_weights(path: Path, n: str, weights: np.ndarray, what: str, low: int) -> np.ndarray:
    """A block of a primitive's WEIGHTS_n, (vertices, 4) float64, from vertex `low`, checked: each weight finite
    and 0 or more."""
    weights = weights.astype(np.float64)
    if (unheld := ~np.isfinite(weights).all(axis=1)).any():
        vertex = int(np.argmax(unheld))
        raise LoadError(path, f"{what}: vertex {low + vertex}'s WEIGHTS_{n} holds "
                              f"{weights[vertex][~np.isfinite(weights[vertex])][0]}, not a finite number")
    if (below := (weights < 0).any(axis=1)).any():
        vertex = int(np.argmax(below))
        raise LoadError(path, f"{what}: vertex {low + vertex}'s WEIGHTS_{n} holds {weights[vertex].min():g}, where "
                              "glTF's weights are 0 or more")
    return weights


def _checked_joints(path: Path, n: str, joints: np.ndarray, weights: np.ndarray, joint_count: int, what: str,
                    low: int) -> tuple[np.ndarray, np.ndarray]:
    """A block of a primitive's JOINTS_n, (vertices, 4) intp, with its checked WEIGHTS_n, from vertex `low`:
    each joint of a weight above 0 one of the skin's `joint_count`; a joint of weight 0 moves nothing, and is
    made joint 0, which any skin has."""
    outside = (joints >= joint_count) & (weights > 0)
    if (vertices_outside := outside.any(axis=1)).any():
        vertex = int(np.argmax(vertices_outside))
        raise LoadError(path, f"{what}: vertex {low + vertex}'s JOINTS_{n} names joint "
                              f"{joints[vertex][outside[vertex]][0]}, of the skin's {joint_count}, at a weight above 0")
    joints[weights == 0] = 0
    return joints, weights


class _WorldTransforms:
    """Each node's 4x4 place in the scene, as trimesh places its nodes (its parent's times its own
    transform), each node's made once, however many ask for it."""

    def __init__(self, document: dict[str, Any]) -> None:
        self.nodes = document.get("nodes", [])
        self.parent = {child: number for number, node in enumerate(self.nodes) for child in node.get("children", [])}
        self.made: dict[int, np.ndarray] = {}

    def __call__(self, number: int) -> np.ndarray:
        above: list[int] = []  # the node and its ancestors not made yet, the nearest first
        node: int | None = number
        while node is not None and node not in self.made:
            above.append(node)
            node = self.parent.get(node)
        place = np.eye(4) if node is None else self.made[node]
        with np.errstate(all="ignore"):  # past float's range: the positions made of it are refused
            for below in reversed(above):
                place = self.made[below] = place @ _node_transform(self.nodes[below])
        return self.made[number]


def _node_transform(node: dict[str, Any]) -> np.ndarray:
    """A node's 4x4 transform from its parent's, as trimesh makes it: its matrix times T * R * S."""
    from trimesh import transformations  # its quaternion made a matrix as trimesh makes it: normalized

    transform = np.array(node["matrix"], np.float64).reshape(4, 4).T if "matrix" in node else np.eye(4)
    if "translation" in node:
        transform = transform @ transformations.translation_matrix(node["translation"])
    if "rotation" in node:
        x, y, z, w = node["rotation"]  # trimesh's quaternions are w x y z
        transform = transform @ transformations.quaternion_matrix([w, x, y, z])
    if "scale" in node:
        transform = transform @ np.diag([*node["scale"], 1.0])
    return transform
