"""glTF's JSON (a .gltf, or a GLB's chunk of it) read and checked before trimesh reads the file: what it
names, its byte ranges and the placements of its scene; the notes of what trimesh draws otherwise than
it says; the JSON made again where trimesh is to read it otherwise. Ours because trimesh reads the JSON
without these checks, and fails in words of its own internals, or draws what the file does not say.

Its modules, each importing only those before it: values, document, counts, accessors, checks, notes,
morphs, skins, samplings, rewrite.
"""

from __future__ import annotations

from marraztu.loaders.gltf.checks import GltfReferences, check_geometry_readable, check_one_parent_each
from marraztu.loaders.gltf.counts import gltf_counts
from marraztu.loaders.gltf.document import buffer_bytes, declared_part, glb_document, gltf_document, gltf_pictures
from marraztu.loaders.gltf.morphs import MorphedShapes, morphed_shapes
from marraztu.loaders.gltf.notes import sceneless_words, undrawn_primitive_notes, unfaithful_notes
from marraztu.loaders.gltf.rewrite import as_trimesh_reads
from marraztu.loaders.gltf.samplings import numbered_material, sampled_materials
from marraztu.loaders.gltf.skins import SkinnedPlacements, skinned_placements

__all__ = [
    "GltfReferences", "MorphedShapes", "SkinnedPlacements", "as_trimesh_reads", "buffer_bytes",
    "check_geometry_readable", "check_one_parent_each", "declared_part", "glb_document", "gltf_counts",
    "gltf_document", "gltf_pictures", "morphed_shapes", "numbered_material", "sampled_materials",
    "sceneless_words", "skinned_placements", "undrawn_primitive_notes", "unfaithful_notes",
]
