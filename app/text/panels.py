"""Text of the "see the equation" panels: the lighting probe (key `i`), the matrices (key `m`), the
pipeline (key `P`, marraztu.text.pipeline), and
the short labels the overlay puts in the picture (the probed vertices, the side-by-side titles).
Plain strings from the scene, no GL; the overlay draws them.

The lines are laid out for a fixed-width font and kept under ~100 columns, which fits an 800 pixel
wide window without wrapping.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from marraztu.control.commands import ROTATION_STEP_RAD, translation_step, undoable_view_moves
from marraztu.errors import escaped
from marraztu.model.lighting import LightTerm
from marraztu.model.lights import DIRECTIONAL, Show, TermView, WorldLight, cone_angle_deg
from marraztu.model.mesh import counted
from marraztu.model.probe import Probe, VertexProbe, probe
from marraztu.model.scene import CameraMode, Frame, Scene, Shading, Target
from marraztu.model.viewports import project, view_projection, views
from marraztu.render.layout import Extras, Label, scaled_px
from marraztu.text.numbers import aligned_columns, fixed, matrix_entries, position_decimals
from marraztu.text.pipeline import lens_numbers, lens_shape, pipeline_lines

MAX_PROBED_VERTICES = 4  # more would not fit an 800 pixel window; the panel says how many are left
CONE_DECIMALS = 4  # enough to tell 25.7499 from 25.75; the GPU's 32-bit cone test decides closer ones
MATRIX_DECIMALS = 3
MATRIX_COLUMN = 10
# The probe's table: indent, then light name, L, H, N.L, (N.H)^ns, cone, what the light adds.
INDENT = 8
COLUMNS = (("light", 18), ("L", 20), ("H", 20), ("N.L", 7), ("(N.H)^ns", 9), ("cone", 14),
           ("adds (r g b)", 0))


LABEL_DISTANCE_PX = 14.0  # from the vertex to the middle of its label, at 800x800 (layout.scaled_px)


def extras(scene: Scene, size: tuple[int, int]) -> Extras:
    """The panels that are on; with the help overlay up they make way for it."""
    if scene.modes.show_help:
        return Extras()
    right = matrix_lines(scene, size) if scene.modes.matrices else []
    titles = [view.title for view in views(scene, size)] if scene.modes.side_by_side else []
    hint = "m hides the matrices panel" if right else "a taller window shows them"
    bottom = pipeline_lines(scene, views(scene, size)[0].viewport) or probe_lines(scene)
    # Names as the status line shows them: a file's tab or escape character is no glyph of the font.
    bottom, right = [escaped(line) for line in bottom], [escaped(line) for line in right]
    return Extras(bottom=bottom, right=right, titles=titles,
                  labels=vertex_labels(scene, size), bottom_overflow_hint=hint)


# --- the probe ---------------------------------------------------------------------------------
def probe_lines(scene: Scene) -> list[str]:
    """The probe panel: empty unless the probe is on."""
    if not scene.modes.probe:
        return []
    found = probe(scene, MAX_PROBED_VERTICES)
    if found is None:
        return ["PROBE: no face to probe (select an object with TAB)"]
    lines = _probe_header(found)
    for number, vertex in enumerate(found.vertices, start=1):
        lines += _vertex_lines(found, number, vertex)
    hidden = found.lit_count - MAX_PROBED_VERTICES
    if hidden > 0:
        lines.append(f"(and {hidden} more vertices of this polygon, lit the same way)")
    return lines


def _probe_header(found: Probe) -> list[str]:
    obj = found.obj
    material, named = obj.face_material(found.face), obj.material_name_of_face(found.face)
    if found.shading is Shading.FLAT:
        how = "flat: lit once, at v1 with the face normal; the whole face takes v1's colour"
    else:
        how = f"gouraud: lit at each of its {found.lit_count} vertices, colours interpolated"
    face = "a back face, drawn red" if found.back_face else "a front face"
    if found.back_face and found.culling:
        face = "a back face, culled (b)"
    notes = "" if found.view == TermView.EVERYTHING else f"; showing {found.view_name} (v)"
    if found.view.shows is not Show.LIT:
        notes += ", not the colour below"
    notes += "; texture on: pixel = colour x texel (T)" if found.textured else ""
    notes += "; pixel = colour x vertex colour (the file's)" if obj.mesh.vertex_colours is not None else ""
    return [
        f"PROBE {obj.name} face {found.face + 1}/{found.face_count} (Enter: next)   {how}",
        f"face normal . V at v1 {_signed(found.facing, 3)}: {face}{notes}",
        f"Ka {_triple(material.ka, 2)}  Kd {_triple(material.kd, 2)}  Ks {_triple(material.ks, 2)}"
        f"  ns {material.ns:g}" + (f"  (material {named})" if named else ""),
        " " * INDENT + _row(*(name for name, _ in COLUMNS)),
    ]


def _row(*cells: str) -> str:
    return "".join(f"{cell:<{width}}" if width else cell for cell, (_, width) in zip(cells, COLUMNS))


def _vertex_lines(found: Probe, number: int, vertex: VertexProbe) -> list[str]:
    normal = "face normal" if found.shading is Shading.FLAT else "vertex normal"
    head = f"v{number} #{vertex.vertex + 1} "  # the blank stays where the number fills the indent
    pad = " " * INDENT
    decimals = position_decimals(found.obj.mesh.size, 1)
    lines = [
        f"{head:<{INDENT}}world  P {_triple(vertex.world_position, decimals)}  N {_triple(vertex.world_normal, 2)}"
        f" ({normal})  N.V {_signed(vertex.n_dot_v, 2)}",
        f"{pad}camera P {_triple(vertex.camera_position, decimals)}  N {_triple(vertex.camera_normal, 2)}",
        pad + _row("ambient Ka*Ia", "", "", "", "", "", _kept(found.weights.ambient * vertex.terms.ambient,
                                                             bool(found.weights.ambient))),
    ]
    for light, term in zip(vertex.lights, vertex.terms.lights):
        lines.append(pad + _light_row(found, light, term, vertex))
    lines.append(pad + _result(found, vertex))
    return lines


def _light_row(found: Probe, light: WorldLight, term: LightTerm, vertex: VertexProbe) -> str:
    """A light's row: what it adds in the term view shown, so that the rows add up to its sum."""
    cone = ""
    if light.kind.has_cone:
        cone = _cone_words(cone_angle_deg(light, vertex.world_position), light.aperture_deg, term.reaches)
    weights = found.weights
    kept = light.name in found.shown_lights and bool(weights.diffuse or weights.specular)
    adds = _kept(term.in_view(weights), kept)
    if not term.reaches:
        return _row(light.name, "outside the cone", "", "", "", cone, adds)
    return _row(light.name, _triple(term.to_light, 2), _triple(term.halfway, 2), f"{term.n_dot_l:.3f}",
                f"{term.highlight:.4f}", cone, adds)


def _cone_words(angle: float, aperture: float, inside: bool) -> str:
    """The angle to the aperture, with as many decimals as the comparison needs to read true: 29.97
    degrees is "29.97<30", not "30.0<30"."""
    decimals = next((places for places in range(1, CONE_DECIMALS) if (round(angle, places) < aperture) == inside),
                    CONE_DECIMALS)
    return f"{angle:.{decimals}f}{'<' if inside else '>='}{aperture:g}"


def _kept(adds: np.ndarray, kept: bool) -> str:
    """A row's share of the sum, or that the term view leaves it out."""
    return _channels(adds) if kept else "(not in this view)"


def _result(found: Probe, vertex: VertexProbe) -> str:
    lit_view = found.view == TermView.EVERYTHING or found.view.shows is not Show.LIT
    view = "sum" if lit_view else f"sum of {found.view_name}"
    displayed = found.displayed(vertex)
    final = f"colour {_bytes(vertex.lit_bytes)}"
    if displayed is None:
        final += ", culled"
    elif found.back_face:
        final += ", drawn red"  # short: the line must fit 800 pixels, and the header says why
    return f"{view} {_channels(vertex.shown)} -> clamped {_channels(vertex.clamped)} -> {final}"


# --- the matrices ------------------------------------------------------------------------------
def matrix_lines(scene: Scene, size: tuple[int, int]) -> list[str]:
    """Model of the selected element, view, projection (column vectors: p' = M p), the frame and
    the undo depth of what x/y/z move now."""
    lens = scene.lens(views(scene, size)[0].aspect)
    lines = ["MATRICES (column vectors: p' = M p)"]
    lines += _model_lines(scene)
    lines.append(f"view: inverse of {scene.viewer.name}'s model")
    lines += _matrix_rows(scene.view_matrix())
    lines += [f"projection: {lens_shape(lens)}", lens_numbers(lens)]
    lines += _matrix_rows(lens.matrix())
    lines += _frame_lines(scene)
    return lines


def _model_lines(scene: Scene) -> list[str]:
    if scene.modes.target is Target.LIGHTS:
        return _light_model_lines(scene)
    element = scene.targeted_element
    if element is None:
        return ["model: no object selected"]
    kind = "object" if scene.modes.target is Target.OBJECTS else "camera"
    return [f"model of {kind} {element.name}"] + _matrix_rows(element.model)


def _light_model_lines(scene: Scene) -> list[str]:
    light = scene.light
    owner = scene.light_owner(light)
    if owner is not None:
        return ([f"{light.name}: rides on {owner.name}; its model", *_matrix_rows(owner.model),
                 f"axis {_triple(scene.placed_light(light).direction, 3)}"])
    if light.kind is DIRECTIONAL:
        return [f"{light.name}: a direction, no matrix", f"toward it {_triple(light.direction, 3)}"]
    return [f"{light.name}: a point, no matrix", f"at {_triple(light.position, 1)}"]


def _frame_lines(scene: Scene) -> list[str]:
    modes = scene.modes
    local = "local: M = M T" if modes.frame is Frame.LOCAL else "global: M = T M"
    camera = ("flight: moves in its own frame" if modes.camera_mode is CameraMode.FLIGHT
              else "analysis: orbits the object")
    press = f"a press of x y z: {ROTATION_STEP_RAD:g} rad or {translation_step(scene):g} units"
    return [f"objects {local}", f"cameras {camera}", f"undo depth of the {_target_name(scene)}: "
            f"{_undo_depth(scene)} ({_view_moves_first(scene)})", press]


def _view_moves_first(scene: Scene) -> str:
    """`u`, and the view's moves it takes back before the target's (the mouse, `.`, HOME)."""
    moves = undoable_view_moves(scene)
    return f"u: {counted(moves, 'view move')} first" if moves else "u"


def _target_name(scene: Scene) -> str:
    if scene.modes.target is Target.LIGHTS:
        return scene.light.name
    element = scene.targeted_element
    return "object" if element is None else element.name


def _undo_depth(scene: Scene) -> int:
    """Moves `u` can take back: a light's history holds only earlier states, an element's also its
    current model."""
    if scene.modes.target is Target.LIGHTS:
        return len(scene.light.history)
    element = scene.targeted_element
    return 0 if element is None else len(element.history) - 1


def _matrix_rows(matrix: np.ndarray) -> list[str]:
    entries = [[_signed_entry(entry) for entry in row] for row in matrix_entries(matrix, MATRIX_DECIMALS)]
    return ["  " + line for line in aligned_columns(entries, MATRIX_COLUMN)]


# --- labels in the picture ---------------------------------------------------------------------
def vertex_labels(scene: Scene, size: tuple[int, int]) -> list[Label]:
    """"v1", "v2", ... beside the probed vertices, in every viewport, so the panel's rows can be
    matched to the picture. Each label sits outside the face, away from its centre, so that the
    labels of nearby vertices do not cover each other or the face."""
    obj = scene.object
    if not scene.modes.probe or obj is None or obj is scene.viewer:
        return []
    points = scene.probed_points(MAX_PROBED_VERTICES)  # no lighting needed: the panel does that
    labels = []
    distance = scaled_px(LABEL_DISTANCE_PX, size)
    for view in views(scene, size):
        matrix = view_projection(scene, view)
        at = [project(matrix, point, view.viewport) for point in points]
        if any(point is None for point in at):
            continue
        screen = np.array(at)
        middle = screen.mean(axis=0)
        for number, point in enumerate(screen, start=1):
            if _inside(tuple(point), view.viewport):
                centre = _label_centre(point, middle, distance)
                labels.append(Label(f"v{number}", float(centre[0]), float(centre[1])))
    return labels


def _label_centre(point: np.ndarray, middle: np.ndarray, distance: float) -> np.ndarray:
    """`distance` pixels from a vertex on the screen, straight away from the face's `middle` (along the
    diagonal where the two meet)."""
    away = point - middle
    length = float(np.linalg.norm(away))
    away = away / length if length > 1e-6 else np.array([1.0, 1.0]) / np.sqrt(2.0)
    return point + distance * away


def _inside(point: tuple[float, float], viewport: tuple[int, int, int, int]) -> bool:
    x0, y0, width, height = viewport
    return x0 <= point[0] < x0 + width and y0 <= point[1] < y0 + height


# --- numbers -----------------------------------------------------------------------------------
def _triple(values: Iterable[float], decimals: int) -> str:
    """Positive numbers get a space, not a "+": at overlay sizes the font's + and - look alike."""
    return "(" + " ".join(_signed(v, decimals) for v in values) + ")"


def _signed(value: float, decimals: int) -> str:
    return _signed_entry(fixed(float(value), decimals))


def _signed_entry(entry: str) -> str:
    """A space before an entry without a minus, where a "+" would be (see _triple)."""
    return entry if entry.startswith("-") else " " + entry


def _channels(values: Sequence[float]) -> str:
    return "(" + " ".join(f"{float(v):6.1f}" for v in values) + ")"


def _bytes(values: Sequence[int]) -> str:
    return "(" + ", ".join(str(int(v)) for v in values) + ")"
