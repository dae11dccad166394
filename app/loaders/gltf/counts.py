"""What the scene places, counted before trimesh builds a node for each placement: the nodes placed
from the scene's roots, and the faces, vertices and points of the primitives their meshes draw.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from marraztu.loaders.gltf.values import (
    _FAN,
    _FAN_LEAST_CORNERS,
    _LINES,
    _POINTS,
    _READ_MODES,
    _TRIANGLES,
    _draco_attributes,
    _is_whole,
    _read_accessors,
)


class _Unshaped(Exception):
    """A glTF's JSON that is not shaped as glTF's where it is counted: trimesh says how."""


def gltf_counts(document: dict[str, Any] | None) -> tuple[int, int, int] | None:
    """(placements, triangles, vertices) the scene trimesh reads places, from the counts its JSON
    declares: its nodes walked from the scene's roots as trimesh walks them (an edge from a parent to a
    child once; a node's mesh placed once a primitive where it has several), each node's children once.
    None where the JSON is not shaped as glTF's."""
    if document is None:
        return None
    try:
        sizes = _mesh_sizes(document)
        placements, triangles, vertices = 0, 0, 0
        for node in _placed_nodes(document):
            read, faces, points = sizes[node["mesh"]] if "mesh" in node else (0, 0, 0)
            placements, triangles, vertices = placements + read, triangles + faces, vertices + points
    except (_Unshaped, LookupError, TypeError, AttributeError):
        return None
    return placements, triangles, vertices


def _placed_nodes(document: dict[str, Any]) -> Iterator[dict[str, Any]]:
    nodes = document.get("nodes", [])
    return (nodes[number] for number in _placed_node_numbers(document))


def _placed_node_numbers(document: dict[str, Any]) -> Iterator[int]:
    """Each node of the scene each time trimesh places it: walked from the scene's roots, an edge from a
    parent to a child once (a root listed twice is placed once), each node's children queued once."""
    nodes = document.get("nodes", [])
    edges = [("root", root) for root in _roots(document)]
    consumed, opened = set(), set()
    while edges:
        edge = edges.pop()
        if edge in consumed:
            continue
        consumed.add(edge)
        child = nodes[edge[1]]
        if edge[1] not in opened:  # trimesh queues them again for each parent: all consumed by then
            opened.add(edge[1])
            edges.extend((edge[1], index) for index in child.get("children", []))
        yield edge[1]


def _roots(document: dict[str, Any]) -> list[Any]:
    """The root nodes of the scene trimesh reads: the one `scene` names, else the first."""
    if "scenes" not in document:
        return []
    return list(document["scenes"][document.get("scene", 0)].get("nodes", []))


def _mesh_sizes(document: dict[str, Any]) -> list[tuple[int, int, int]]:
    """Per mesh, (primitives, triangles, vertices) of the primitives trimesh reads, added up once: a node
    placing it adds them, however many primitives it has."""
    return [(len(read), sum(faces for faces, _ in read), sum(points for _, points in read))
            for read in _primitive_sizes(document)]


def _primitive_sizes(document: dict[str, Any]) -> list[list[tuple[int, int]]]:
    """Per mesh, (triangles, vertices) of each primitive trimesh reads, from its accessors' counts
    (the vertices of a primitive of no triangles are not drawn, so not counted)."""
    accessors, decoded = document.get("accessors", []), _decoded_accessors(document)
    return [[size for primitive in mesh["primitives"]
             if (size := _primitive_size(accessors, primitive, decoded)) is not None]
            for mesh in document.get("meshes", [])]


def _primitive_size(accessors: list[Any], primitive: dict[str, Any], decoded: set[Any] | frozenset[Any] = frozenset()
                    ) -> tuple[int, int] | None:
    """(triangles, vertices) of a primitive trimesh reads (its vertices counted only where it has triangles),
    None where it skips it. An indexed one is handed no more vertices than its corners (but where it reads
    accessors of `decoded`, Draco's): where it has more, those its indices use (rewrite._used_vertices_made_own)."""
    mode = primitive.get("mode", _TRIANGLES)
    if mode not in (*_READ_MODES, _FAN):
        return None
    points = _count(accessors[primitive["attributes"]["POSITION"]])
    corners = _count(accessors[primitive["indices"]]) if "indices" in primitive else points
    if mode == _FAN and corners < _FAN_LEAST_CORNERS:
        return None  # not made triangles (_drawn_fans): trimesh skips it
    faces = 0 if mode in (_POINTS, _LINES) else corners // 3 if mode == _TRIANGLES else max(corners - 2, 0)
    if "indices" in primitive and decoded.isdisjoint(_read_accessors(primitive)):
        points = min(points, 3 * faces if mode == _FAN else corners)  # a fan's corners are made its triangles'
    return faces, points if faces else 0


def _decoded_accessors(document: dict[str, Any]) -> set[Any]:
    """The accessors the Draco primitives read, whose items their decoder makes: no primitive reading one
    is handed its own vertices."""
    return {index for mesh in document.get("meshes", []) for primitive in mesh["primitives"]
            if _draco_attributes(primitive) for index in _read_accessors(primitive)}


def _draws_faces(accessors: list[Any], primitive: dict[str, Any]) -> bool:
    """Whether trimesh makes triangles of a checked primitive (whose vertices the placements count)."""
    size = _primitive_size(accessors, primitive)
    return size is not None and size[0] > 0


def _count(accessor: Any) -> int:
    count = accessor["count"]
    if not _is_whole(count) or count < 0:
        raise _Unshaped
    return count


def _placed_meshes(document: dict[str, Any]) -> set[int]:
    """The meshes of the nodes under the scene's roots, as trimesh walks them."""
    return {node["mesh"] for node in _placed_nodes(document) if "mesh" in node}
