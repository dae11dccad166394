"""The project's own models and texture, made by code: ``python -m marraztu.devtools.assetgen`` rewrites assets/.

Each model is a list of parts, and each part is a closed solid built by one of a few numpy
primitives (lathe, loft, box, wedge, cylinder, cone) and placed with a 4x4 matrix, so a model reads
as a description of its shape rather than as a table of numbers. Every primitive emits polygons whose
corners run counter-clockwise seen from outside (the right-hand-rule normal points out of the solid):
the viewer paints faces it sees from behind red, so a wrong winding would show at once.

Nothing here is random and every number is written rounded, so running the generator twice gives the
same bytes (tests/test_assets.py checks that the committed files are exactly what this code makes).
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import reduce
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

from marraztu.model.geometry import newell_normal, unit
from marraztu.model.transforms import rotation_about_axis
from marraztu.resources import ASSET_DIR

DECIMALS = 4  # enough for models tens of units across; fewer digits keep the files small and stable
MODEL_FILES = ("camera.obj", "x_wing.obj", "r_falke.obj", "rammer.obj")
TEXTURE_FILE = "selfi.ppm"
TEXTURE_SIZE = 256


# --------------------------------------------------------------------------------------------------
# Parts and placing them
# --------------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Part:
    """One closed solid: corners carry their own uv and normal, faces index corners (CCW outside)."""

    name: str
    positions: np.ndarray  # (N, 3)
    uvs: np.ndarray  # (N, 2) in [0, 1]
    normals: np.ndarray  # (N, 3) unit
    faces: tuple[tuple[int, ...], ...]

    def placed(self, matrix: np.ndarray, name: str | None = None) -> Part:
        """The part moved by an affine matrix; a mirroring matrix also flips the winding back."""
        linear = matrix[:3, :3]
        positions = self.positions @ linear.T + matrix[:3, 3]
        # Normals follow the inverse transpose so they stay perpendicular under non-uniform scaling.
        normals = self.normals @ np.linalg.inv(linear)
        normals = normals / np.linalg.norm(normals, axis=1, keepdims=True)
        faces = self.faces
        if np.linalg.det(linear) < 0:
            faces = tuple((face[0],) + tuple(reversed(face[1:])) for face in faces)
        return Part(name or self.name, positions, self.uvs, normals, faces)


def translate(x: float, y: float, z: float) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, 3] = (x, y, z)
    return matrix


def scale(x: float, y: float, z: float) -> np.ndarray:
    return np.diag([x, y, z, 1.0])


def rotate_x(degrees: float) -> np.ndarray:
    return rotation_about_axis(0, math.radians(degrees))


def rotate_y(degrees: float) -> np.ndarray:
    return rotation_about_axis(1, math.radians(degrees))


def rotate_z(degrees: float) -> np.ndarray:
    return rotation_about_axis(2, math.radians(degrees))


def compose(*matrices: np.ndarray) -> np.ndarray:
    """Product of the matrices: the rightmost one acts first, as in M @ p."""
    return reduce(np.matmul, matrices, np.eye(4))


MIRROR_X = scale(-1.0, 1.0, 1.0)
# Lathes turn about +z; these aim that axis elsewhere.
AXIS_Z_TO_Y = rotate_x(-90.0)
AXIS_Z_TO_MINUS_Z = rotate_y(180.0)
AXIS_Z_TO_X = rotate_y(90.0)


# --------------------------------------------------------------------------------------------------
# Primitives
# --------------------------------------------------------------------------------------------------
class _FlatFaces:
    """Collects flat-shaded polygons, each with its own corners so normals do not blend across edges."""

    def __init__(self) -> None:
        self.positions: list[np.ndarray] = []
        self.uvs: list[np.ndarray] = []
        self.normals: list[np.ndarray] = []
        self.faces: list[tuple[int, ...]] = []
        self.count = 0

    def add(self, points: np.ndarray, uvs: np.ndarray) -> None:
        normal = unit(newell_normal(points))
        indices = tuple(range(self.count, self.count + len(points)))
        self.positions.append(points)
        self.uvs.append(uvs)
        self.normals.append(np.repeat(normal[None, :], len(points), axis=0))
        self.count += len(points)
        if len(points) <= 4:
            self.faces.append(indices)
        else:  # caps of many sides become a fan of triangles (the caps are convex)
            self.faces.extend((indices[0], indices[k], indices[k + 1]) for k in range(1, len(indices) - 1))

    def part(self, name: str) -> Part:
        return Part(name, np.concatenate(self.positions), np.concatenate(self.uvs),
                    np.concatenate(self.normals), tuple(self.faces))


def _planar_uvs(points: np.ndarray) -> np.ndarray:
    """Map a flat polygon onto [0, 1]^2 along its first edge and the in-plane perpendicular."""
    normal = unit(newell_normal(points))
    across = unit(points[1] - points[0])
    up = np.cross(normal, across)
    coords = np.stack([(points - points[0]) @ across, (points - points[0]) @ up], axis=1)
    low, high = coords.min(axis=0), coords.max(axis=0)
    return (coords - low) / np.maximum(high - low, 1e-9)


def _perimeter_fractions(loop: np.ndarray) -> np.ndarray:
    """(K + 1,) running length around a closed loop, 0 at its first point and 1 back there."""
    steps = np.linalg.norm(np.roll(loop, -1, axis=0) - loop, axis=1)
    return np.concatenate([[0.0], np.cumsum(steps)]) / steps.sum()


def loft(name: str, sections: Sequence[Sequence[Sequence[float]]]) -> Part:
    """A flat-faced solid skinned over closed loops of equal size, capped at both ends.

    The loops may be given in either turning sense; they are put counter-clockwise about the
    direction the loft runs, which makes the side quads and both caps face outward.
    """
    loops = [np.asarray(section, dtype=np.float64) for section in sections]
    runs = loops[-1].mean(axis=0) - loops[0].mean(axis=0)
    if np.dot(newell_normal(loops[0]), runs) < 0:
        loops = [loop[::-1] for loop in loops]
    faces = _FlatFaces()
    around = _perimeter_fractions(loops[0])
    along = np.linspace(0.0, 1.0, len(loops))
    size = len(loops[0])
    for s in range(len(loops) - 1):
        for k in range(size):
            nxt = (k + 1) % size
            quad = np.stack([loops[s][k], loops[s][nxt], loops[s + 1][nxt], loops[s + 1][k]])
            uvs = np.array([[around[k], along[s]], [around[k + 1], along[s]],
                            [around[k + 1], along[s + 1]], [around[k], along[s + 1]]])
            faces.add(quad, uvs)
    end_cap, start_cap = loops[-1], loops[0][::-1]
    faces.add(end_cap, _planar_uvs(end_cap))
    faces.add(start_cap, _planar_uvs(start_cap))
    return faces.part(name)


def lathe(name: str, profile: Sequence[tuple[float, float]], segments: int = 24) -> Part:
    """A solid of revolution about +z from a (radius, z) profile that starts and ends on the axis.

    Normals are smooth around the axis and flat along each profile step, so cylinders look round
    while their rims stay crisp. The profile runs so that the solid lies on its left in (r, z):
    e.g. up a cylinder's side, from the bottom centre out, up, and back in to the top centre.
    """
    points = np.asarray(profile, dtype=np.float64)
    lengths = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    along = lengths / lengths[-1]
    angles = np.linspace(0.0, 2.0 * math.pi, segments + 1)
    positions, uvs, normals, faces = [], [], [], []
    for band in range(len(points) - 1):
        start = 2 * band * (segments + 1)  # each band has its own two rings of corners
        (r0, z0), (r1, z1) = points[band], points[band + 1]
        for radius, z, v in ((r0, z0, along[band]), (r1, z1, along[band + 1])):
            positions.append(_ring(radius, z, angles))
            uvs.append(np.stack([angles / (2.0 * math.pi), np.full_like(angles, v)], axis=1))
            normals.append(_band_normals(r1 - r0, z1 - z0, angles, on_axis=radius == 0.0))
        faces.extend(_band_faces(start, segments, r0 == 0.0, r1 == 0.0))
    return Part(name, np.concatenate(positions), np.concatenate(uvs), np.concatenate(normals),
                tuple(faces))


def _ring(radius: float, z: float, angles: np.ndarray) -> np.ndarray:
    return np.stack([radius * np.cos(angles), radius * np.sin(angles), np.full_like(angles, z)], axis=1)


def _band_normals(dr: float, dz: float, angles: np.ndarray, on_axis: bool) -> np.ndarray:
    """Outward normals of one profile step: (dz, -dr) in the (r, z) half-plane, turned around z."""
    if on_axis:  # the corner on the axis serves one triangle: aim it at that triangle's middle
        angles = angles + (angles[1] - angles[0]) / 2.0
    length = math.hypot(dr, dz)
    return np.stack([dz * np.cos(angles), dz * np.sin(angles), np.full_like(angles, -dr)], axis=1) / length


def _band_faces(start: int, segments: int, first_on_axis: bool, second_on_axis: bool
                ) -> list[tuple[int, ...]]:
    """Quads between two rings; a ring shrunk onto the axis turns them into triangles."""
    faces = []
    for j in range(segments):
        a0, a1 = start + j, start + j + 1
        b0, b1 = a0 + segments + 1, a1 + segments + 1
        if first_on_axis:
            faces.append((a0, b1, b0))
        elif second_on_axis:
            faces.append((a0, a1, b0))
        else:
            faces.append((a0, a1, b1, b0))
    return faces


def rect_loop(half_width: float, half_height: float, z: float, x: float = 0.0, y: float = 0.0
              ) -> np.ndarray:
    """A rectangle in the plane z = const, centred on (x, y)."""
    return np.array([[x - half_width, y - half_height, z], [x + half_width, y - half_height, z],
                     [x + half_width, y + half_height, z], [x - half_width, y + half_height, z]])


def chamfered_loop(half_width: float, half_height: float, z: float, y: float = 0.0,
                   chamfer: float = 0.35) -> np.ndarray:
    """An octagon: a rectangle with its corners cut by a fraction of its half sizes."""
    w, h = half_width, half_height
    cw, ch = w * (1.0 - chamfer), h * (1.0 - chamfer)
    corners = [(w, -ch), (w, ch), (cw, h), (-cw, h), (-w, ch), (-w, -ch), (-cw, -h), (cw, -h)]
    return np.array([[cx, y + cy, z] for cx, cy in corners])


def box(name: str, size: Sequence[float], centre: Sequence[float] = (0.0, 0.0, 0.0)) -> Part:
    sx, sy, sz = size
    cx, cy, cz = centre
    return loft(name, [rect_loop(sx / 2, sy / 2, cz - sz / 2, cx, cy),
                       rect_loop(sx / 2, sy / 2, cz + sz / 2, cx, cy)])


def wedge(name: str, width: float, height: float, length: float) -> Part:
    """A triangular prism: a base width wide at z = 0 narrowing to an edge at z = -length."""
    def triangle(y: float) -> list[tuple[float, float, float]]:
        return [(-width / 2, y, 0.0), (width / 2, y, 0.0), (0.0, y, -length)]
    return loft(name, [triangle(-height / 2), triangle(height / 2)])


def cylinder(name: str, radius: float, length: float, segments: int = 24) -> Part:
    """Along +z from z = 0 to z = length."""
    return lathe(name, [(0.0, 0.0), (radius, 0.0), (radius, length), (0.0, length)], segments)


def cone(name: str, radius: float, length: float, segments: int = 24) -> Part:
    """Base at z = 0, apex at z = length."""
    return lathe(name, [(0.0, 0.0), (radius, 0.0), (0.0, length)], segments)


def dome_profile(radius: float, base_height: float = 0.0, steps: int = 6) -> list[tuple[float, float]]:
    """A hemisphere on a short collar: from the base centre out, up the collar, over the top."""
    profile = [(0.0, 0.0), (radius, 0.0)]
    if base_height > 0:
        profile.append((radius, base_height))
    for k in range(1, steps + 1):
        angle = k * math.pi / 2 / steps
        r = 0.0 if k == steps else radius * math.cos(angle)  # exactly on the axis at the top
        profile.append((r, base_height + radius * math.sin(angle)))
    return profile


# --------------------------------------------------------------------------------------------------
# The four models
# --------------------------------------------------------------------------------------------------
def camera_model() -> list[Part]:
    """A single-lens reflex camera, lens toward -z, its origin inside the lens barrel.

    Parts overlap a little wherever they meet: two faces in one plane would flicker, and the one
    facing inward would show as a red back face.
    """
    # Lens: along +z in lathe space (0 inside the body, 5.2 at the front glass), then turned to -z.
    lens_profile = [(0.0, 0.0), (2.7, 0.0), (2.7, 1.5), (3.1, 1.5), (3.1, 3.1), (2.8, 3.1),
                    (2.8, 4.6), (3.3, 5.2), (2.5, 5.2), (2.3, 4.9), (0.0, 4.9)]
    lens = lathe("lens", lens_profile, 32).placed(compose(translate(0.0, 0.0, 2.0), AXIS_Z_TO_MINUS_Z))
    prism_section = [(-3.2, 3.3), (3.2, 3.3), (2.0, 6.2), (-2.0, 6.2)]
    prism = loft("prism", [[(x, y, z) for x, y in prism_section] for z in (2.2, 6.0)])
    return [
        box("body", (12.0, 7.0, 4.4), (0.0, 0.0, 3.9)),
        lens,
        prism,
        box("grip", (2.4, 6.4, 1.6), (4.6, -0.2, 1.3)),  # on the right of someone holding it
        cylinder("shutter", 0.7, 1.0, 16).placed(compose(translate(4.2, 3.3, 2.6), AXIS_Z_TO_Y)),
        cylinder("dial", 1.1, 0.8, 20).placed(compose(translate(-4.0, 3.3, 4.0), AXIS_Z_TO_Y)),
        box("eyepiece", (2.4, 1.8, 1.0), (0.0, 4.6, 6.3)),
    ]


def x_wing_model() -> list[Part]:
    """A starfighter: pointed fuselage along -z, four wings in an X, engines at the roots, guns at the tips."""
    fuselage = loft("fuselage", [
        chamfered_loop(4.0, 3.6, 26.0), chamfered_loop(4.4, 4.2, 14.0),
        chamfered_loop(4.2, 4.0, 2.0), chamfered_loop(3.4, 3.2, -10.0, y=-0.4),
        chamfered_loop(2.4, 2.2, -24.0, y=-1.0), chamfered_loop(1.4, 1.3, -38.0, y=-1.4),
        chamfered_loop(0.6, 0.6, -42.0, y=-1.5),
    ])
    canopy = loft("canopy", [rect_loop(2.0, 1.2, -12.0, y=2.4), rect_loop(2.6, 2.4, -6.0, y=3.6),
                             rect_loop(2.4, 2.4, 1.0, y=3.8), rect_loop(2.0, 1.6, 4.0, y=3.4)])
    astromech = lathe("astromech", dome_profile(1.8, 1.0), 20).placed(
        compose(translate(0.0, 3.6, 8.0), AXIS_Z_TO_Y))
    parts = [fuselage, canopy, astromech]
    for side, mirror in (("right", np.eye(4)), ("left", MIRROR_X)):
        for tilt, level in ((12.0, "upper"), (-12.0, "lower")):
            frame = compose(mirror, rotate_z(tilt))
            parts.extend(part.placed(frame, f"{side}_{level}_{part.name}") for part in _x_wing_wing(tilt > 0))
    return parts


def _x_wing_wing(upper: bool) -> list[Part]:
    """One wing along +x with its engine and cannon, flat in the xz plane before it is tilted."""
    def section(x: float, leading: float, trailing: float, thickness: float) -> list[list[float]]:
        return [[x, 0.0, leading], [x, -thickness, (leading + trailing) / 2],
                [x, 0.0, trailing], [x, thickness, (leading + trailing) / 2]]
    wing = loft("wing", [section(3.0, 4.0, 24.0, 0.9), section(29.5, 11.0, 21.0, 0.45)])
    side = 1.0 if upper else -1.0  # engines sit on the outer face of each wing, away from the others
    engine_profile = [(0.0, 1.5), (2.0, 1.5), (2.9, 3.0), (2.9, 22.0), (2.5, 24.0), (2.5, 26.0),
                      (1.8, 26.0), (0.0, 25.2)]
    engine = lathe("engine", engine_profile, 24).placed(translate(7.8, side * 3.2, 0.0))
    cannon_profile = [(0.0, 20.0), (1.3, 20.0), (1.3, 6.0), (0.9, 4.0), (0.5, 3.0), (0.5, -25.0),
                      (0.85, -26.0), (0.85, -29.0), (0.0, -29.6)]
    # Listed muzzle last for reading; a lathe wants z to grow along the side, so it is reversed.
    cannon = lathe("cannon", cannon_profile[::-1], 16).placed(translate(30.0, 0.0, 0.0))
    return [wing, engine, cannon]


def r_falke_model() -> list[Part]:
    """A saucer freighter: a thick disc, two mandibles forward (-z), the cockpit tube on the right."""
    disc_centre = translate(0.0, 0.0, 4.0)
    hull_profile = [(0.0, -4.6), (9.0, -4.6), (22.0, -3.8), (28.0, -2.4), (30.0, -0.6), (30.0, 0.6),
                    (28.0, 2.3), (20.0, 3.6), (12.0, 4.2), (11.0, 5.4), (7.0, 5.8), (0.0, 5.8)]
    hull = lathe("hull", hull_profile, 48).placed(compose(disc_centre, AXIS_Z_TO_Y))
    turret = lathe("turret", dome_profile(2.6, 0.6), 20).placed(compose(translate(0.0, 5.6, 4.0), AXIS_Z_TO_Y))
    parts = [hull, turret, *_falke_mandibles(), *_falke_cockpit(), *_falke_dish(),
             _falke_engine_band(disc_centre)]
    for side in (1.0, -1.0):
        parts.append(cylinder("docking_port", 2.2, 4.0, 16).placed(
            compose(translate(side * 27.0, 0.0, 6.0), scale(side, 1.0, 1.0), AXIS_Z_TO_X),
            "right_docking_port" if side > 0 else "left_docking_port"))
    return parts


def _falke_mandibles() -> list[Part]:
    """The two forward prongs, flat and slightly tapered, with a bevel along their outer top edge."""
    def section(inner: float, outer: float, z: float, low: float, high: float) -> list[list[float]]:
        bevel = (outer - inner) * 0.25
        return [[inner, low, z], [outer, low, z], [outer, high - 1.0, z], [outer - bevel, high, z],
                [inner, high, z]]
    right = loft("right_mandible", [section(3.4, 12.0, -14.0, -2.8, 2.4),
                                    section(3.6, 11.0, -34.0, -2.0, 1.8),
                                    section(4.0, 9.6, -40.0, -1.4, 1.2)])
    return [right, right.placed(MIRROR_X, "left_mandible")]


def _falke_cockpit() -> list[Part]:
    """An offset tube out of the starboard rim ending in a rounded cockpit."""
    tube_profile = [(0.0, 0.0), (2.4, 0.0), (2.4, 14.0), (2.7, 14.0), (2.7, 18.0)]
    tube_profile += [(2.7 * math.cos(a), 18.0 + 3.2 * math.sin(a))
                     for a in np.linspace(0.0, math.pi / 2, 6)[1:-1]] + [(0.0, 21.2)]
    tube = lathe("cockpit", tube_profile, 24).placed(compose(translate(24.5, 0.4, -2.0), AXIS_Z_TO_MINUS_Z))
    return [tube]


def _falke_dish() -> list[Part]:
    """The radar dish on the upper port side: a shallow cone on a short stalk, tilted forward."""
    stalk = cylinder("dish_stalk", 0.6, 3.2, 12).placed(compose(translate(-13.0, 3.5, -2.0), AXIS_Z_TO_Y))
    dish_profile = [(0.0, 0.0), (0.8, 0.0), (4.2, 1.4), (4.2, 1.8), (0.0, 0.9)]
    dish = lathe("dish", dish_profile, 24).placed(
        compose(translate(-13.0, 6.6, -2.0), rotate_x(-25.0), AXIS_Z_TO_Y))
    return [stalk, dish]


def _falke_engine_band(disc_centre: np.ndarray) -> Part:
    """The glowing engine strip along the rear rim: a curved bar lofted along an arc."""
    sections = []
    for degrees in np.linspace(-55.0, 55.0, 12):
        angle = math.radians(degrees)
        outward = np.array([math.sin(angle), 0.0, math.cos(angle)])  # 0 degrees = straight back (+z)
        inner, outer = 27.0, 30.6
        corners = [(inner, -1.2), (outer, -1.2), (outer, 1.2), (inner, 1.2)]
        sections.append([(outward * r + np.array([0.0, y, 0.0])).tolist() for r, y in corners])
    return loft("engine_band", sections).placed(disc_centre)


def rammer_model() -> list[Part]:
    """A blocky warship built to ram: armoured hull, a wedge ram forward (-z), pods and engines aft."""
    hull = loft("hull", [rect_loop(8.5, 4.6, 20.0), rect_loop(9.6, 5.2, 4.0),
                         rect_loop(9.0, 5.0, -10.0), rect_loop(7.6, 4.2, -15.0)])
    ram = loft("ram", [rect_loop(7.0, 3.8, -14.0), rect_loop(4.2, 2.4, -25.0),
                       rect_loop(0.8, 1.0, -33.0)])
    ram_blade = wedge("ram_blade", 3.0, 11.0, 10.0).placed(translate(0.0, 0.0, -24.0))
    tower = loft("bridge", [rect_loop(4.0, 2.6, 17.0, y=7.0), rect_loop(4.0, 2.6, 8.0, y=7.0),
                            rect_loop(3.2, 1.4, 4.0, y=5.8)])
    fin_side = [(9.2, 10.0), (9.2, 18.0), (14.0, 18.0)]  # (y, z): tall at the back
    fin = loft("fin", [[(x, y, z) for y, z in fin_side] for x in (-0.6, 0.6)])
    parts = [hull, ram, ram_blade, tower, fin,
             cylinder("main_engine", 3.6, 5.0, 24).placed(translate(0.0, 0.0, 19.0)),
             cylinder("main_nozzle", 2.6, 2.0, 24).placed(translate(0.0, 0.0, 23.5))]
    for side, name in ((1.0, "right"), (-1.0, "left")):
        parts.extend(part.placed(scale(side, 1.0, 1.0), f"{name}_{part.name}")
                     for part in _rammer_pod())
    return parts


def _rammer_pod() -> list[Part]:
    """A side engine pod on a strut, drawn on the +x side."""
    pod = loft("pod", [rect_loop(2.6, 2.6, 22.0, x=13.5), rect_loop(2.8, 2.8, 2.0, x=13.5),
                       rect_loop(1.6, 1.8, -6.0, x=13.5)])
    strut = box("strut", (4.4, 1.6, 10.0), (10.4, 0.0, 10.0))
    nozzle = lathe("nozzle", [(0.0, 0.0), (2.0, 0.0), (2.0, 1.5), (2.4, 3.5), (1.6, 3.5), (0.0, 2.6)],
                   20).placed(translate(13.5, 0.0, 21.5))
    armour = box("armour", (1.0, 6.0, 13.5), (9.9, 0.0, -2.25))
    return [pod, strut, nozzle, armour]


MODELS = {
    "camera.obj": ("camera", camera_model),
    "x_wing.obj": ("x_wing", x_wing_model),
    "r_falke.obj": ("r_falke", r_falke_model),
    "rammer.obj": ("rammer", rammer_model),
}


# --------------------------------------------------------------------------------------------------
# Checking and writing models
# --------------------------------------------------------------------------------------------------
def _rounded_keys(rows: np.ndarray) -> list[str]:
    """Rows as the text written to the file; also what decides that two corners share a vertex."""
    rounded = np.round(rows, DECIMALS) + 0.0  # + 0.0 turns -0.0 into 0.0
    return [" ".join(f"{value:.{DECIMALS}f}" for value in row) for row in rounded]


def closure_problems(part: Part) -> list[str]:
    """Why a part is not a closed solid with outward faces (empty when it is one)."""
    keys = _rounded_keys(part.positions)
    vertex_of_key: dict[str, int] = {}
    vertex = [vertex_of_key.setdefault(key, len(vertex_of_key)) for key in keys]
    edges: dict[tuple[int, int], int] = {}
    problems = []
    for face in part.faces:
        corners = [vertex[i] for i in face]
        if len(set(corners)) != len(corners):
            problems.append(f"{part.name}: degenerate face {face}")
        for a, b in zip(corners, corners[1:] + corners[:1]):
            edges[(a, b)] = edges.get((a, b), 0) + 1
    if any(count != 1 or edges.get((b, a)) != 1 for (a, b), count in edges.items()):
        problems.append(f"{part.name}: not closed, or faces wound inconsistently")
    if _signed_volume(part) <= 0:
        problems.append(f"{part.name}: faces point inward")
    return problems


def _signed_volume(part: Part) -> float:
    total = 0.0
    for face in part.faces:
        p = part.positions[list(face)]
        for k in range(1, len(face) - 1):
            total += float(np.dot(p[0], np.cross(p[k], p[k + 1]))) / 6.0
    return total


def obj_text(model_name: str, parts: Sequence[Part]) -> str:
    """The model as OBJ text: shared v/vt/vn tables, then one group of faces per part."""
    tables: dict[str, dict[str, int]] = {"v": {}, "vt": {}, "vn": {}}
    groups = []
    for part in parts:
        indices = [[table.setdefault(key, len(table) + 1) for key in _rounded_keys(rows)]
                   for table, rows in ((tables["v"], part.positions), (tables["vt"], part.uvs),
                                       (tables["vn"], part.normals))]
        faces = [" ".join(f"{indices[0][i]}/{indices[1][i]}/{indices[2][i]}" for i in face)
                 for face in part.faces]
        groups.append((part.name, faces))
    face_count = sum(len(faces) for _, faces in groups)
    lines = [f"# {model_name}: made by app/devtools/assetgen.py (make assets); do not edit.",
             f"# {len(tables['v'])} vertices, {face_count} faces in {len(parts)} parts;"
             " counter-clockwise faces seen from outside.",
             f"o {model_name}"]
    for statement, table in tables.items():
        lines.extend(f"{statement} {key}" for key in table)
    for name, faces in groups:
        lines.append(f"g {name}")
        lines.extend(f"f {face}" for face in faces)
    return "\n".join(lines) + "\n"


def build_model(file_name: str) -> tuple[str, list[Part]]:
    model_name, make = MODELS[file_name]
    parts = make()
    problems = [problem for part in parts for problem in closure_problems(part)]
    if problems:
        raise AssertionError(f"{file_name}: " + "; ".join(problems))
    return model_name, parts


# --------------------------------------------------------------------------------------------------
# The texture
# --------------------------------------------------------------------------------------------------
# 5 x 7 block letters, so the texture does not depend on which fonts a machine has.
GLYPHS = {
    "T": ["#####", "..#..", "..#..", "..#..", "..#..", "..#..", "..#.."],
    "O": [".###.", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."],
    "P": ["####.", "#...#", "#...#", "####.", "#....", "#....", "#...."],
    "F": ["#####", "#....", "#....", "####.", "#....", "#....", "#...."],
}


def _draw_text(draw: ImageDraw.ImageDraw, text: str, left: int, top: int, cell: int,
               colour: tuple[int, int, int]) -> None:
    for index, letter in enumerate(text):
        x0 = left + index * 6 * cell
        for row, bits in enumerate(GLYPHS[letter]):
            for column, bit in enumerate(bits):
                if bit == "#":
                    x, y = x0 + column * cell, top + row * cell
                    draw.rectangle([x, y, x + cell - 1, y + cell - 1], fill=colour)


def _gradient_background(size: int) -> Image.Image:
    """Red grows to the right, green toward the top, so every direction has its own colour."""
    ramp = np.linspace(0.0, 1.0, size)
    red = np.tile(ramp, (size, 1))
    green = np.tile(ramp[::-1, None], (1, size))
    blue = 0.55 + 0.35 * np.sin(np.pi * red) * np.sin(np.pi * green)
    pixels = np.stack([0.2 + 0.75 * red, 0.15 + 0.75 * green, blue], axis=2)
    grid = (np.arange(size) % 32) == 0  # a UV grid shows stretching on the models
    pixels[grid, :, :] *= 0.6
    pixels[:, grid, :] *= 0.6
    return Image.fromarray(np.round(pixels * 255).astype(np.uint8), "RGB")


def texture_image() -> Image.Image:
    """selfi.ppm: a picture whose top, bottom, left and right can never be confused."""
    image = _gradient_background(TEXTURE_SIZE)
    draw = ImageDraw.Draw(image)
    draw.rectangle([0, 0, 39, 39], fill=(255, 220, 0), outline=(0, 0, 0), width=3)  # top-left marker
    _draw_text(draw, "TOP", 81, 16, 6, (0, 0, 0))
    _draw_text(draw, "TOP", 78, 13, 6, (255, 255, 255))
    arrow = [(90, 70), (138, 128), (106, 128), (106, 224), (74, 224), (74, 128), (42, 128)]
    draw.polygon(arrow, fill=(255, 255, 255), outline=(0, 0, 0), width=3)
    _draw_text(draw, "F", 166, 120, 10, (150, 0, 40))
    return image


# --------------------------------------------------------------------------------------------------
# Examples with materials: a model with its own texture, a model of two materials
# --------------------------------------------------------------------------------------------------
EXAMPLE_DIR = "examples"
CRATE_TEXTURE_SIZE = 64
CRATE_QUADRANTS = ((230, 60, 40), (40, 180, 60), (40, 80, 220), (240, 220, 60))  # top-left, top-right, ...
EXAMPLE_MATERIALS = {  # material name -> (Ka, Kd, Ks, Ns, texture file or None)
    "wood": ((0.3, 0.3, 0.3), (0.9, 0.9, 0.9), (0.1, 0.1, 0.1), 10.0, "crate.ppm"),
    "red": ((0.2, 0.05, 0.05), (0.8, 0.1, 0.1), (0.5, 0.5, 0.5), 40.0, None),
    "blue": ((0.05, 0.05, 0.2), (0.1, 0.2, 0.8), (0.5, 0.5, 0.5), 40.0, None),
}
EXAMPLES = {  # file stem -> [(part, material)]
    "crate": [(box("crate", (40.0, 40.0, 40.0)), "wood")],
    "two_tone": [(box("left", (30.0, 40.0, 20.0), (-16.0, 0.0, 0.0)), "red"),
                 (box("right", (30.0, 40.0, 20.0), (16.0, 0.0, 0.0)), "blue")],
}


def example_obj_text(stem: str) -> str:
    """The example as OBJ text naming its MTL, each part's faces after its usemtl."""
    placed = EXAMPLES[stem]
    lines = obj_text(stem, [part for part, _ in placed]).splitlines()
    lines.insert(2, f"mtllib {stem}.mtl")
    for part, material in placed:
        lines.insert(lines.index(f"g {part.name}") + 1, f"usemtl {material}")
    return "\n".join(lines) + "\n"


def example_mtl_text(stem: str) -> str:
    lines = [f"# {stem}.mtl: made by app/devtools/assetgen.py (make assets); do not edit."]
    for material in dict.fromkeys(name for _, name in EXAMPLES[stem]):
        ka, kd, ks, ns, texture = EXAMPLE_MATERIALS[material]
        lines += [f"newmtl {material}", *(f"{key} {r:g} {g:g} {b:g}" for key, (r, g, b) in
                                          (("Ka", ka), ("Kd", kd), ("Ks", ks))), f"Ns {ns:g}"]
        lines += [f"map_Kd {texture}"] if texture else []
    return "\n".join(lines) + "\n"


def crate_texture() -> Image.Image:
    """Four coloured quadrants with dark seams: which corner of the texture lands where is plain."""
    half = CRATE_TEXTURE_SIZE // 2
    pixels = np.zeros((CRATE_TEXTURE_SIZE, CRATE_TEXTURE_SIZE, 3), np.uint8)
    for index, colour in enumerate(CRATE_QUADRANTS):
        row, column = divmod(index, 2)
        pixels[row * half:(row + 1) * half, column * half:(column + 1) * half] = colour
    pixels[half - 1:half + 1, :] = pixels[:, half - 1:half + 1] = 30
    return Image.fromarray(pixels)


def generate_examples(out_dir: Path) -> list[Path]:
    folder = out_dir / EXAMPLE_DIR
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for stem in EXAMPLES:
        for path, text in ((folder / f"{stem}.obj", example_obj_text(stem)), (folder / f"{stem}.mtl",
                                                                                 example_mtl_text(stem))):
            path.write_bytes(text.encode("ascii"))
            written.append(path)
    crate_texture().save(folder / "crate.ppm", format="PPM")
    return [*written, folder / "crate.ppm"]


# --------------------------------------------------------------------------------------------------
# Entry point
# --------------------------------------------------------------------------------------------------
def generate_assets(out_dir: Path) -> list[Path]:
    """Write the four models, the texture and the examples into out_dir; returns the files written."""
    out_dir.mkdir(parents=True, exist_ok=True)
    written = generate_examples(out_dir)
    for file_name in MODEL_FILES:
        model_name, parts = build_model(file_name)
        path = out_dir / file_name
        path.write_bytes(obj_text(model_name, parts).encode("ascii"))
        written.append(path)
    texture_path = out_dir / TEXTURE_FILE
    texture_image().save(texture_path, format="PPM")  # Pillow writes RGB as binary P6
    written.append(texture_path)
    return written


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m marraztu.devtools.assetgen", description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ASSET_DIR, help="folder to write (default: assets/)")
    args = parser.parse_args(argv)
    for path in generate_assets(args.out):
        print(path)


if __name__ == "__main__":
    main()
