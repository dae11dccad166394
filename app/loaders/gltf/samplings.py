"""The samplings of the materials' base colour textures (their samplers' wraps and filters), which
trimesh keeps none of, and the names by number that let the reader find each material's own.
"""

from __future__ import annotations

from typing import Any

from marraztu.loaders.gltf.values import _base_colour_texture, _is_whole
from marraztu.model.sampling import DEFAULT_SAMPLING, Filter, TextureSampling, Wrap

# glTF's sampler values (OpenGL's enums) as a TextureSampling's; left out, the default's.
_WRAPS = {33071: Wrap.CLAMP, 33648: Wrap.MIRROR, 10497: Wrap.REPEAT}
_MAGNIFY = {9728: Filter.NEAREST, 9729: Filter.LINEAR}
_MINIFY = {9728: (Filter.NEAREST, None), 9729: (Filter.LINEAR, None), 9984: (Filter.NEAREST, Filter.NEAREST),
           9985: (Filter.LINEAR, Filter.NEAREST), 9986: (Filter.NEAREST, Filter.LINEAR),
           9987: (Filter.LINEAR, Filter.LINEAR)}
# trimesh keeps no sampler, but keeps a material's name: where samplers matter, the JSON it reads names
# each material by its number, and the reader finds the material's own name and sampling by it.
_NUMBERED = "marraztu glTF material "


def sampled_materials(document: dict[str, Any]) -> tuple[tuple[str, TextureSampling], ...]:
    """Each material's name ("" for none) and its base colour texture's sampling (its sampler's), where any
    is not the default; () where none is. The document is checked already (GltfReferences)."""
    materials, textures = document.get("materials", []), document.get("textures", [])
    by_sampler = [_sampling(sampler) for sampler in document.get("samplers", [])]  # each made once, however shared
    samplings = [_sampling_of(_base_colour_texture(material), textures, by_sampler) for material in materials]
    if all(sampling.is_default for sampling in samplings):
        return ()
    return tuple((material.get("name", ""), sampling) for material, sampling in zip(materials, samplings))


def numbered_material(name: object) -> int | None:
    """The number of a material trimesh read from JSON made again by _materials_numbered; None for another."""
    number = name[len(_NUMBERED):] if isinstance(name, str) and name.startswith(_NUMBERED) else ""
    return int(number) if number.isdecimal() else None


def _sampling_of(texture_info: dict[str, Any], textures: list[dict[str, Any]],
                 by_sampler: list[TextureSampling]) -> TextureSampling:
    """A textureInfo's sampling: its texture's sampler's, made by _sampling (the default where it names none)."""
    index = texture_info.get("index")
    if not _is_whole(index) or "sampler" not in textures[index]:
        return DEFAULT_SAMPLING
    return by_sampler[textures[index]["sampler"]]


def _sampling(sampler: dict[str, Any]) -> TextureSampling:
    minify, between_levels = _MINIFY.get(sampler.get("minFilter"), (Filter.LINEAR, Filter.LINEAR))
    return TextureSampling(wrap_u=_WRAPS[sampler.get("wrapS", 10497)], wrap_v=_WRAPS[sampler.get("wrapT", 10497)],
                           magnify=_MAGNIFY.get(sampler.get("magFilter"), Filter.LINEAR), minify=minify,
                           between_levels=between_levels)


def _materials_numbered(document: dict[str, Any]) -> bool:
    """Names each material by its number (numbered_material), every one, so that no name of the file's is
    taken for a number. False where there is none."""
    materials = document.get("materials", [])
    for number, material in enumerate(materials):
        material["name"] = f"{_NUMBERED}{number}"
    return bool(materials)
