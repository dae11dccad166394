"""SPEC 4's lighting formula in numpy, written from the SPEC and not from the shader, so tests can
hold the GPU to it; the lighting probe shows its per-light terms.

Per colour channel, in the seed's 0..255 units:

    I = Ka * Ia + sum over lights that are on: I_l * (Kd * max(N.L, 0) + Ks * max(N.H, 0)^ns)

clamped to 255 and displayed as I / 255 (times the texture colour when texturing is on).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping

import numpy as np

from marraztu.model.geometry import unit
from marraztu.model.lights import Light, TermWeights, WorldLight, kind_named
from marraztu.model.scene import Material

MAX_INTENSITY = 255.0


@dataclass(frozen=True)
class LightTerm:
    """One light's share of I at a point: zero when the point is outside a spotlight's cone.
    The vectors and factors are kept so the lighting probe can show how the share came about."""

    name: str
    reaches: bool
    diffuse: np.ndarray  # (3,) I_l * Kd * max(N.L, 0)
    specular: np.ndarray  # (3,) I_l * Ks * max(N.H, 0)^ns
    to_light: np.ndarray = field(default_factory=lambda: np.zeros(3))  # L (zero outside a cone)
    halfway: np.ndarray = field(default_factory=lambda: np.zeros(3))  # H = normalise(L + V)
    n_dot_l: float = 0.0  # max(N.L, 0)
    highlight: float = 0.0  # max(N.H, 0)^ns

    @property
    def contribution(self) -> np.ndarray:
        return self.diffuse + self.specular

    def in_view(self, weights: TermWeights) -> np.ndarray:
        """Its share of I as a term view shows it."""
        return weights.diffuse * self.diffuse + weights.specular * self.specular


@dataclass(frozen=True)
class ShadingTerms:
    ambient: np.ndarray  # (3,) Ka * Ia
    lights: tuple[LightTerm, ...]

    @property
    def total(self) -> np.ndarray:
        """I before clamping."""
        return self.ambient + sum((t.diffuse + t.specular for t in self.lights), np.zeros(3))

    @property
    def clamped(self) -> np.ndarray:
        return np.minimum(self.total, MAX_INTENSITY)

    def in_view(self, weights: TermWeights, light_names: Iterable[str] | None = None) -> np.ndarray:
        """I before clamping as a term view shows it: the weighted terms of the named lights only
        (all of them for None)."""
        shown = None if light_names is None else set(light_names)
        total = weights.ambient * self.ambient
        for term in self.lights:
            if shown is None or term.name in shown:
                total = total + term.in_view(weights)
        return total


LightLike = WorldLight | Light | Mapping[str, Any]


def as_world_light(light: LightLike) -> WorldLight | None:
    """Accept a WorldLight, a dict with WorldLight's field names (plus optional `on`), or a scene
    Light without an owner (its own position and axis); None for a light that is off."""
    if isinstance(light, WorldLight):
        return light
    if isinstance(light, Light):
        return light.placed(None) if light.on else None
    if not light.get("on", True):
        return None
    kind = kind_named(light["kind"])
    return WorldLight(
        name=str(light.get("name", kind.name)),
        kind=kind,
        intensity=np.asarray(light["intensity"], float),
        position=np.asarray(light.get("position", (0.0, 0.0, 0.0)), float),
        direction=unit(light.get("direction", (0.0, 0.0, 1.0))),
        aperture_deg=float(light.get("aperture_deg", 180.0)),
    )


def shade_terms(point: Iterable[float], normal: Iterable[float], eye_or_view: Iterable[float],
                material: Material, lights: Iterable[LightLike], ambient: Iterable[float],
                parallel: bool) -> ShadingTerms:
    """Every term of I at `point`; `normal` need not be unit length, only non-zero.

    `eye_or_view` is the eye position in perspective (V = P -> eye) and V itself in parallel
    projection (the viewer's backward axis), as SPEC 4 says.
    """
    p = np.asarray(point, float)
    n = unit(normal)
    v = unit(eye_or_view) if parallel else unit(np.asarray(eye_or_view, float) - p)
    ambient_term = np.asarray(material.ka, float) * np.asarray(ambient, float)
    terms = []
    for light in lights:
        placed = as_world_light(light)
        if placed is not None:
            terms.append(_light_term(placed, p, n, v, material))
    return ShadingTerms(ambient_term, tuple(terms))


def _light_term(light: WorldLight, p: np.ndarray, n: np.ndarray, v: np.ndarray,
                material: Material) -> LightTerm:
    zero = np.zeros(3)
    if not light.reaches(p):
        return LightTerm(light.name, False, zero, zero)
    to_light = light.to_light(p)
    halfway = unit(to_light + v)
    n_dot_l = max(float(n @ to_light), 0.0)
    # At most 1, as for unit vectors: past it by rounding, a huge ns overflowed the power.
    n_dot_h = min(max(float(n @ halfway), 0.0), 1.0)
    # 0 ** ns is 0 for ns > 0; written out so that ns = 0 does not turn 0 ** 0 into a highlight.
    highlight = n_dot_h ** material.ns if n_dot_h > 0.0 else 0.0
    diffuse = light.intensity * np.asarray(material.kd, float) * n_dot_l
    specular = light.intensity * np.asarray(material.ks, float) * highlight
    return LightTerm(light.name, True, diffuse, specular, to_light, halfway, n_dot_l, highlight)


def shade(point: Iterable[float], normal: Iterable[float], eye_or_view: Iterable[float],
          material: Material, lights: Iterable[LightLike], ambient: Iterable[float],
          parallel: bool) -> np.ndarray:
    """I at the point, clamped: (3,) float in 0..255."""
    return shade_terms(point, normal, eye_or_view, material, lights, ambient, parallel).clamped


def lit_colour_bytes(point: Iterable[float], normal: Iterable[float], eye_or_view: Iterable[float],
                     material: Material, lights: Iterable[LightLike], ambient: Iterable[float],
                     parallel: bool, texture_rgb: Iterable[int] | None = None) -> np.ndarray:
    """The 8-bit pixel a framebuffer should hold: round(I/255 * texture * 255), texture in bytes."""
    intensity = shade(point, normal, eye_or_view, material, lights, ambient, parallel)
    return to_bytes(intensity, texture_rgb)


def to_bytes(intensity: np.ndarray, texture_rgb: Iterable[int] | None = None) -> np.ndarray:
    """Clamped 0..255 intensity (times an 8-bit texture colour) as the uint8 pixel GL would store."""
    # The shader's steps in its 32-bit floats, then round half to even, as llvmpipe stores a float
    # (and Direct3D's rule): SPEC 4's 76.5 is the 76 of its check colour, not 77.
    colour = np.minimum(np.asarray(intensity, np.float32), np.float32(MAX_INTENSITY)) / np.float32(MAX_INTENSITY)
    if texture_rgb is not None:
        colour = colour * (np.asarray(texture_rgb, np.float32) / np.float32(255.0))
    return np.rint(colour * np.float32(255.0)).astype(np.uint8)
