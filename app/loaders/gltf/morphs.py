"""Morph targets: the shapes the weights of each placement give, counted against the limit on what is
made, and each shape's mesh made for trimesh, which draws a mesh in its base shape only.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from marraztu.errors import LoadError, shortened
from marraztu.loaders.gltf.accessors import _MadeBuffer, _values
from marraztu.loaders.gltf.counts import _placed_node_numbers
from marraztu.loaders.gltf.values import (
    _FLOAT_COMPONENTS,
    _draco_attributes,
    _draco_decoder,
    _is_drawn,
    _is_finite,
    _is_number,
    _mesh_copy,
    _mesh_named,
    made_limit,
    past_made_limit,
)
from marraztu.model.mesh import counted

_BASE_SHAPE: tuple[float, ...] = ()  # the weights of a placement drawn in its mesh's base shape
_MORPHED_ITEM_BYTES = 12  # a vertex of a shape (float32 VEC3): what a shape's reads and writes are counted in


@dataclass(frozen=True)
class MorphedShapes:
    """Each placed mesh with morph targets that its weights shape (a node's, else its mesh's): the nodes
    that place it, by the weights they shape it with (_BASE_SHAPE: its base shape); and the notes of
    weights that cannot be applied, whose placements are drawn in the base shape; what the shapes read and
    write (_shaping_bytes), which the skins' share the limit with."""

    by_mesh: dict[int, dict[tuple[float, ...], list[int]]]
    notes: tuple[str, ...] = ()
    made: int = 0


def morphed_shapes(document: dict[str, Any], held: int) -> MorphedShapes:
    """The shapes of a checked glTF's placed meshes, from its JSON. What they read and write may come to no
    more than made_limit(held) bytes, `held` the file's and its buffers' bytes: a mesh past it is drawn in
    its base shape, with a note (each shape reads its targets again: many nodes of weights of their own
    would read a large mesh's many times). Each mesh's primitives and own weights are read once, however
    many nodes place it."""
    meshes, nodes = document.get("meshes", []), document.get("nodes", [])
    by_mesh: dict[int, dict[tuple[float, ...], list[int]]] = {}
    unapplied: dict[int, str] = {}  # each mesh's first reason
    targets: dict[int, _Targets] = {}
    by_mesh_weights: dict[int, list[int]] = {}  # the nodes each mesh's own weights shape it for
    for number in sorted(set(_placed_node_numbers(document))):
        mesh_number = nodes[number].get("mesh")
        if mesh_number is not None and mesh_number not in targets:
            targets[mesh_number] = _targets_of(meshes[mesh_number])
        if mesh_number is None or not targets[mesh_number].counts[-1]:  # no primitive has targets
            continue
        own = "weights" in nodes[number]
        if not own and mesh_number in by_mesh_weights:
            by_mesh_weights[mesh_number].append(number)
            continue
        weights = _shaping_weights(number, nodes[number], mesh_number, meshes[mesh_number], targets[mesh_number])
        if isinstance(weights, str):
            unapplied.setdefault(mesh_number, weights)
            weights = _BASE_SHAPE
        placing = by_mesh.setdefault(mesh_number, {}).setdefault(weights, [])
        placing.append(number)
        if not own:
            by_mesh_weights[mesh_number] = placing
    made = 0
    for mesh_number, shapes in list(by_mesh.items()):
        work = _shaping_bytes(document, meshes[mesh_number], shapes, made_limit(held) - made)
        if work and made + work <= made_limit(held):
            made += work
            continue
        del by_mesh[mesh_number]  # its base shape alone: nothing to make
        if work:
            unapplied.setdefault(mesh_number, f"{_mesh_named(mesh_number, meshes[mesh_number])}'s shapes by its "
                                              f"weights would bring what shapes make to {past_made_limit(held)}")
    return MorphedShapes(by_mesh, _unshaped_notes(list(unapplied.values())), made)


@dataclass(frozen=True)
class _Targets:
    """A mesh's primitives' counts of morph targets (sorted, each once), and the primitives whose Draco
    stream holds POSITION."""

    counts: tuple[int, ...]
    compressed: tuple[int, ...]


def _targets_of(mesh: dict[str, Any]) -> _Targets:
    primitives = mesh["primitives"]
    return _Targets(tuple(sorted({len(primitive.get("targets", [])) for primitive in primitives})),
                    tuple(number for number, primitive in enumerate(primitives)
                          if "POSITION" in _draco_attributes(primitive)))


def _shaping_weights(number: int, node: dict[str, Any], mesh_number: int, mesh: dict[str, Any],
                     targets: _Targets) -> tuple[float, ...] | str:
    """The weights node `number` shapes its mesh with, glTF's default pose (its own, else its mesh's;
    _BASE_SHAPE where they are zeros or none), or why they cannot be applied."""
    own = "weights" in node
    weights = node["weights"] if own else mesh.get("weights", [])
    named = _mesh_named(mesh_number, mesh)
    whose, targets_of = (f"node {number}'s weights", f"{named}'s") if own else (f"{named}'s weights", "its")
    if not (isinstance(weights, list) and all(map(_is_number, weights))):
        return f"{whose} are not a list of numbers"
    if unheld := [weight for weight in weights if not _is_finite(weight)]:
        return f"{whose} hold {shortened(str(unheld[0]))}, not a finite number"
    if not any(weights):
        return _BASE_SHAPE
    if len(targets.counts) > 1:
        return (f"{named}'s primitives have {' and '.join(map(str, targets.counts))} morph targets (glTF's have as "
                "many each)")
    if len(weights) != targets.counts[0]:
        return (f"{whose} are {counted(len(weights), 'number')}, for {targets_of} "
                f"{counted(targets.counts[0], 'morph target')}")
    if targets.compressed and _draco_decoder():  # it writes what it decodes into the accessor POSITION points at
        return (f"{named}'s primitive {targets.compressed[0]} is Draco-compressed: trimesh decodes its positions over "
                "the shape")
    return tuple(float(weight) for weight in weights)


def _shaping_bytes(document: dict[str, Any], mesh: dict[str, Any], shapes: dict[tuple[float, ...], list[int]],
                   budget: int) -> int:
    """What a mesh's shapes read and write, counted until it passes `budget`: for each shape other than the
    base, the JSON of its copy of the mesh, and for each drawn primitive its POSITION, the targets'
    accessors that move it and the shape made, in _MORPHED_ITEM_BYTES a vertex, and as many again a target
    its weights are looked up against (many nodes' weights on many primitives' targets: looked up all)."""
    accessors, total = document["accessors"], 0
    copy_bytes = len(json.dumps(_mesh_copy(mesh))) if any(shapes) else 0
    for weights in filter(None, shapes):
        total += copy_bytes
        for primitive in filter(_is_drawn, mesh["primitives"]):
            targets = primitive["targets"]
            vertices = accessors[primitive["attributes"]["POSITION"]]["count"]
            moving = len(_moving_weights(accessors, weights, targets))
            total += _MORPHED_ITEM_BYTES * (vertices * (2 + moving) + len(targets))
            if total > budget:
                return total
    return total


def _moving_weights(accessors: list[dict[str, Any]], weights: tuple[float, ...],
                    targets: list[dict[str, Any]]) -> dict[int, float]:
    """The accessors of the targets' POSITIONs that move the vertices, each with its weights added up (a
    file may name one in several targets): one of zeros (no view, no sparse values) moves none."""
    moving: dict[int, float] = {}
    for weight, target in zip(weights, targets):
        position = target.get("POSITION")
        if weight and position is not None and ("bufferView" in accessors[position] or "sparse" in accessors[position]):
            moving[position] = moving.get(position, 0.0) + weight
    return {position: weight for position, weight in moving.items() if weight}


def _unshaped_notes(reasons: list[str]) -> tuple[str, ...]:
    """One note of the meshes whose weights cannot be applied (a reason each), naming the first."""
    if not reasons:
        return ()
    if len(reasons) == 1:
        return (f"{reasons[0]}: drawn in the base shape",)
    return (f"{counted(len(reasons), 'mesh', 'meshes')} with morph targets drawn in the base shape: their weights "
            f"cannot be applied (the first, {reasons[0]})",)


def _shapes_made(path: Path, document: dict[str, Any], buffer: Callable[[int], bytes | memoryview],
                 shapes: MorphedShapes) -> bool:
    """Gives each mesh its weights shape the positions of its shape (glTF's default pose), in a buffer
    appended as a data: URI: trimesh reads no morph target. Each shape but the base is drawn by a copy of
    the mesh (_mesh_per_shape). Primitives of the same POSITION and targets shaped alike share one
    accessor. False where no mesh is shaped."""
    if not shapes.by_mesh:
        return False
    meshes, made = document.get("meshes", []), _MadeBuffer(document)
    made_for: dict[tuple[Any, ...], int] = {}  # (POSITION, its targets, weights) -> the accessor of the shape
    for mesh_number, by_weights in shapes.by_mesh.items():
        unshaped = meshes[mesh_number]
        named = _mesh_named(mesh_number, unshaped)
        for mesh, weights in _mesh_per_shape(document, mesh_number, by_weights):
            for number, (primitive, source) in enumerate(zip(mesh["primitives"], unshaped["primitives"])):
                if not weights or not _is_drawn(source):
                    continue
                key = (source["attributes"]["POSITION"], tuple(target.get("POSITION") for target in
                                                               source["targets"]), weights)
                if key not in made_for:
                    shape = _shape(path, document, source, weights, buffer, f"{named}'s primitive {number}")
                    made_for[key] = made.accessor(shape, {"componentType": _FLOAT_COMPONENTS, "type": "VEC3"})
                primitive["attributes"]["POSITION"] = made_for[key]
    made.append()
    return True


def _mesh_per_shape(document: dict[str, Any], mesh_number: int, by_weights: dict[tuple[float, ...], list[int]]
                    ) -> list[tuple[dict[str, Any], tuple[float, ...]]]:
    """Mesh `mesh_number` as it is for its base shape, and a copy of it for each other shape, each with its
    weights: the first shape's in its place, the others' appended, each node placing them re-pointed at its
    own."""
    meshes, nodes = document["meshes"], document["nodes"]
    unshaped = meshes[mesh_number]
    ordered = sorted(by_weights.items(), key=lambda shape: bool(shape[0]))  # _BASE_SHAPE first
    placed = []
    for number, (weights, placing) in enumerate(ordered):
        mesh = _mesh_copy(unshaped) if weights else unshaped
        if number == 0:
            meshes[mesh_number] = mesh
        else:
            meshes.append(mesh)
            for node in placing:
                nodes[node]["mesh"] = len(meshes) - 1
        placed.append((mesh, weights))
    return placed


def _shape(path: Path, document: dict[str, Any], primitive: dict[str, Any], weights: tuple[float, ...],
           buffer: Callable[[int], bytes | memoryview], what: str) -> np.ndarray:
    """(vertices, 3) float32: a primitive's POSITION and each morph target's times its weight; a coordinate
    that is not a finite number is refused. Targets' NORMALs are not read, as no NORMAL is: the viewer
    derives normals from the shape's faces."""
    with np.errstate(all="ignore"):  # NaN, or past float32's range: refused below
        shape = _values(path, document, primitive["attributes"]["POSITION"], buffer).astype(np.float64)
        for position, weight in _moving_weights(document["accessors"], weights, primitive["targets"]).items():
            shape += weight * _values(path, document, position, buffer)
        made = shape.astype(np.float32)
    unheld = ~np.isfinite(made).all(axis=1)
    if unheld.any():
        raise LoadError(path, f"{what}: vertex {np.argmax(unheld)} of its shape by its weights is not a finite number "
                              "(a morph target's POSITION holds one, or a weight takes it past float's range)")
    return made
