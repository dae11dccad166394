"""How a material's picture is read between and beyond its texels (glTF's sampler), no GL: the wrap
of each texture coordinate outside 0..1, and the filter of a magnified and of a minified picture."""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum


class Wrap(Enum):
    """What a texture coordinate outside 0..1 reads."""

    REPEAT = "repeat"  # the picture again, tiled
    CLAMP = "clamp"  # the texel at the picture's edge
    MIRROR = "mirror"  # the picture again, every other copy mirrored


class Filter(Enum):
    """How a point between texels (or between mip levels) is read."""

    NEAREST = "nearest"  # the nearest one: pixel art stays sharp
    LINEAR = "linear"  # the nearest ones blended


@dataclass(frozen=True)
class TextureSampling:
    """A picture's wraps along u and v and its filters; the defaults are how every picture is drawn
    where the file says nothing (an OBJ's, the scene's): repeated, blended within and between mip levels."""

    wrap_u: Wrap = Wrap.REPEAT
    wrap_v: Wrap = Wrap.REPEAT
    magnify: Filter = Filter.LINEAR
    minify: Filter = Filter.LINEAR  # within a mip level
    between_levels: Filter | None = Filter.LINEAR  # None: the picture itself only, no mip level read

    def __post_init__(self) -> None:
        for name in ("wrap_u", "wrap_v"):
            if not isinstance(getattr(self, name), Wrap):
                raise ValueError(f"a texture sampling's {name} must be a Wrap, not {getattr(self, name)!r}")
        for name in ("magnify", "minify", "between_levels"):
            value = getattr(self, name)
            if not isinstance(value, Filter) and not (name == "between_levels" and value is None):
                raise ValueError(f"a texture sampling's {name} must be a Filter, not {value!r}")

    @property
    def is_default(self) -> bool:
        return self == DEFAULT_SAMPLING


DEFAULT_SAMPLING = TextureSampling()
