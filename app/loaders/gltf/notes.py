"""What trimesh draws otherwise than the file says, in notes: the primitives it does not draw, colours
outside 0 to 1, emission, normal maps, unlit materials, texture transforms and material variants.
"""

from __future__ import annotations

from typing import Any

from marraztu.loaders.gltf.counts import _placed_meshes
from marraztu.loaders.gltf.values import (
    _LINE_LOOP,
    _LINE_STRIP,
    _LINES,
    _MATERIALS_VARIANTS,
    _POINTS,
    _TEXTURE_TRANSFORM,
    _TRIANGLES,
    _base_colour,
    _is_number,
    _is_undrawn_extension,
    _is_whole,
    _listed,
    _nested,
    _uv_transform,
    _uvs_decoded_by_trimesh,
)
from marraztu.model.mesh import counted
from marraztu.model.scene import MATERIAL_COLOUR_RANGE


def unfaithful_notes(document: dict[str, Any], undrawn: list[str]) -> list[str]:
    """What of a checked glTF is drawn otherwise than it says, which trimesh passes over without a word:
    primitives it reads no faces of (`undrawn`, its undrawn_primitive_notes, which the placement check has
    read already), base colours outside 0..1 it holds to it, and base colour textures' transforms of the
    Draco-compressed coordinates it decodes over those moved; and emission and normal maps, which SPEC 4's
    lighting has no term for, unlit materials, which it lights, the lights and shading the file requires
    that it has no term for either, and material variants, which it does not offer. (Weights that cannot shape
    a mesh: MorphedShapes.notes.)"""
    return [*undrawn, *_outside_colour_notes(document), *_texture_transform_notes(document),
            *_emission_notes(document), *_normal_map_notes(document), *_unlit_notes(document),
            *_undrawn_extension_notes(document), *_variant_notes(document)]


# The modes of primitive no face is made of, by what a note calls them.
_UNDRAWN_MODES = {_POINTS: "points", _LINES: "lines", _LINE_LOOP: "line loops", _LINE_STRIP: "line strips"}


def sceneless_words(document: dict[str, Any]) -> list[str]:
    """Why a file of no scene places nothing: glTF reads its meshes as a library, as trimesh does."""
    return [] if document.get("scenes") else ["the file lists no scene, and glTF places no mesh outside one"]


def undrawn_primitive_notes(document: dict[str, Any]) -> list[str]:
    """The placed meshes' primitives of points and lines (Blender's loose edges)."""
    meshes = document.get("meshes", [])
    modes = [mode for index in _placed_meshes(document) for primitive in meshes[index]["primitives"]
             if _is_whole(mode := primitive.get("mode", _TRIANGLES)) and mode in _UNDRAWN_MODES]
    if not modes:
        return []
    kinds = [_UNDRAWN_MODES[mode] for mode in sorted(set(modes))]
    kinds_said = ", ".join(kinds[:-1]) + " and " + kinds[-1] if len(kinds) > 1 else kinds[0]
    return [f"{counted(len(modes), 'primitive')} of {kinds_said} {'is' if len(modes) == 1 else 'are'} not drawn"]


def _outside_colour_notes(document: dict[str, Any]) -> list[str]:
    """A material's base colour factor outside glTF's 0..1, which trimesh holds to it."""
    outside = [(number, key, value) for number, material in enumerate(document.get("materials", []))
               for where, key, _ in [_base_colour(material)] for value in _listed(where.get(key))
               if _is_number(value) and not MATERIAL_COLOUR_RANGE[0] <= value <= MATERIAL_COLOUR_RANGE[1]]
    if not outside:
        return []
    (number, key, value), materials = outside[0], len({number for number, _, _ in outside})
    if materials == 1:
        return [f"material {number}'s {key} holds {value:g}: glTF's colours are 0..1, held to it"]
    return [f"{materials} materials' {key} hold values outside glTF's 0..1 (the first, material {number}'s, "
            f"{value:g}), held to it"]


def _emission_notes(document: dict[str, Any]) -> list[str]:
    """Materials that glow (an emissiveFactor not black, a KHR_materials_emissive_strength not 0), as Blender
    writes a lamp's: drawn lit as any other."""
    glowing = [number for number, material in enumerate(document.get("materials", [])) if _glows(material)]
    return _materials_note(glowing, "emission (emissiveFactor) is not drawn")


def _glows(material: dict[str, Any]) -> bool:
    strength = _nested(material, ("extensions", "KHR_materials_emissive_strength")).get("emissiveStrength", 1)
    factor = _listed(material.get("emissiveFactor"))
    return any(_is_number(value) and value > 0 for value in factor) and not (_is_number(strength) and strength <= 0)


def _normal_map_notes(document: dict[str, Any]) -> list[str]:
    """Materials with a normalTexture, as Blender writes a normal map: drawn with the mesh's own normals."""
    mapped = [number for number, material in enumerate(document.get("materials", []))
              if isinstance(material.get("normalTexture"), dict)]
    return _materials_note(mapped, "normal map (normalTexture) is not drawn",
                           "normal maps (normalTexture) are not drawn")


def _unlit_notes(document: dict[str, Any]) -> list[str]:
    """Materials of KHR_materials_unlit (their base colour, not lit): drawn lit by SPEC 4's Phong."""
    unlit = [number for number, material in enumerate(document.get("materials", []))
             if "KHR_materials_unlit" in _nested(material, ("extensions",))]
    return _materials_note(unlit, "unlit shading (KHR_materials_unlit) is not applied: drawn lit")


def _materials_note(numbers: list[int], said_of_one: str, said_of_many: str | None = None) -> list[str]:
    """One note for the materials `numbers` however many, naming the first (`said_of_many`: where it is
    said otherwise of several)."""
    if not numbers:
        return []
    if len(numbers) == 1:
        return [f"material {numbers[0]}'s {said_of_one}"]
    return [f"{len(numbers)} materials' {said_of_many or said_of_one} (the first, material {numbers[0]}'s)"]


def _texture_transform_notes(document: dict[str, Any]) -> list[str]:
    """Base colour textures whose KHR_texture_transform moves the coordinates of a drawn primitive's Draco
    stream, where trimesh decodes it: it writes them, unmoved, over the set that would be moved."""
    materials = document.get("materials", [])
    unmoved = sorted({primitive["material"] for mesh in document.get("meshes", []) for primitive in mesh["primitives"]
                      if "material" in primitive and _uv_transform(materials[primitive["material"]]) is not None
                      and _uvs_decoded_by_trimesh(primitive, materials[primitive["material"]])})
    return _materials_note(unmoved, f"baseColorTexture's {_TEXTURE_TRANSFORM} is not applied to Draco-compressed "
                           "texture coordinates")


def _undrawn_extension_notes(document: dict[str, Any]) -> list[str]:
    """The required extensions of _is_undrawn_extension (a file's own lights, PBR shading), which the viewer's
    four lights and Phong shading of the base colour stand in for."""
    required = set(_listed(document.get("extensionsRequired")))  # checked: names (check_geometry_readable)
    undrawn = sorted(name for name in required if _is_undrawn_extension(name))
    if not undrawn:
        return []
    names = ", ".join(undrawn[:-1]) + " and " + undrawn[-1] if len(undrawn) > 1 else undrawn[0]
    return [f"{names}, which the file requires, {'is' if len(undrawn) == 1 else 'are'} not drawn: the viewer's "
            "own lights and Phong shading stand in"]


def _variant_notes(document: dict[str, Any]) -> list[str]:
    """The file's material variants (KHR_materials_variants, as a product's colours are written), which the
    viewer does not offer: each primitive is drawn with its own material, what glTF draws where none is chosen."""
    variants = _listed(_nested(document, ("extensions", _MATERIALS_VARIANTS)).get("variants"))
    if not variants:
        return []
    return [f"{counted(len(variants), 'material variant')} ({_MATERIALS_VARIANTS}) "
            f"{'is' if len(variants) == 1 else 'are'} not offered: each mesh is drawn with its default material"]
