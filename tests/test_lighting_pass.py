"""The lighting pass: Flat and Gouraud light their vertices in a transform-feedback pass whose result
is kept until a uniform it reads changes (app/gpu.py ObjectGpu.light). A stale colour would be a
wrong picture that no single-frame test can see, so here a renderer that drew the scene before a key
must draw, after it, exactly the picture of a renderer that never drew it (its buffers dropped, so
everything is lit afresh); and a frame where nothing lighting reads has changed runs no pass.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from marraztu.control.viewer import StartOptions
from marraztu.loaders.scenefile import load_builtin_scene
from marraztu.model.lights import TERM_VIEWS, TermView
from marraztu.model.scene import Scene
from marraztu.render.renderer import Renderer
from support import corpus
from support.scenes import BACKGROUND as BACKGROUND_BYTES
from support.scenes import NoFrontend, RenderingViewer

SIZE = (96, 72)
BACKGROUND = np.array(BACKGROUND_BYTES)
CLOSE = "c t Z*14 c c r"  # the camera 70 units nearer, objects targeted again, rotating

# (keys, does the next frame need a lighting pass). Each step starts from the frame of the one before.
STEPS = [
    ("", False),
    ("T", False),  # texture: the drawing pass's, not lighting's
    ("b", False),  # culling: the drawing pass's
    ("0", True),  # the sun off
    ("x", True),  # the selected object turns
    ("TAB", True),  # another object selected: the object spotlight goes with it
    ("y*3", True),
    ("u", True),  # undo
    ("F", True),  # Gouraud: its own pass, never run yet
    ("F", True),  # back to Flat: Flat's rows were lit for inputs Gouraud's frames have not changed...
    ("v", True),  # term view: ambient only
    (f"v*{len(TERM_VIEWS) - 1}", True),  # ... round to everything again
    ("p", True),  # parallel projection: one V for the whole scene
    ("p", True),
    ("c t Z", True),  # the camera moves: V and the camera's spotlight
    ("3", True),  # the camera's spotlight off
    ("r x", False),  # the camera turns in place: perspective's V comes from its position alone
    ("p", True),
    ("x", True),  # parallel projection's V is the camera's direction
    ("t Z", False),  # and its position goes unread
    ("p", True),
    ("3", True),
    ("c", False),  # lights targeted: their marker is drawn, nothing lit changes
    ("TAB TAB", False),  # the object spotlight selected
    ("+", True),  # its cone widens
    ("r x", True),  # and turns
    ("c", False),  # objects targeted again
    ("C", True),  # looking through the selected object
    ("C", True),
    ("b", False),  # culling off again, so that single faces show whichever way they look
    ("o ENTER", False),  # one face: its row was lit with the whole object's
    ("ENTER*3", True),  # another face, whose row the one-face frame before did not light
    ("x", True),  # the object turns: only the drawn face's row is lit
    ("o", True),  # every face again: the other rows are stale
    ("F o ENTER", True),  # Gouraud's one face lights every shared row it might read
    ("o F", True),
    ("s", True),  # side by side: Gouraud's pass (Flat's rows are current), Phong lights pixels
    ("s", False),
    ("i", False),  # the probe's outline and panel
    ("l", False),  # lines: no surface, no pass
    ("l", True),  # filled again: lit afresh, as the lines frame before lit nothing
    (f"v*{TERM_VIEWS.index(TermView.DEPTH)}", True),  # the depth view: Flat's rows carry N.V, for back faces
    ("F", False),  # Gouraud's depth view reads no lit row
    ("F", True),  # Flat's again: its rows were dropped, and Gouraud's fresh frame lit none
    (f"v*{len(TERM_VIEWS) - TERM_VIEWS.index(TermView.DEPTH)}", True),  # lit again
    ("F", True),  # Gouraud: its rows were lit before the views went round
    ("3", True),  # the camera's spotlight off
    ("c t Z", True),  # the camera moves: Gouraud's specular term reads V
    ("v", True),  # ambient only: Gouraud reads no V...
    ("Z", False),  # ... so a camera that moves lights nothing again
    ("v", True),  # diffuse only
    ("Z", False),
    ("v", True),  # specular only: V is read again, from where the camera is now
    ("Z", True),
    (f"v*{TERM_VIEWS.index(TermView.NORMALS) - TERM_VIEWS.index(TermView.SPECULAR)}", True),  # the normals view
    ("Z", False),
    ("v", True),  # everything again
    ("1 2", True),  # the last lights on switched off (the sun and the camera's spotlight are)
    ("Z", False),
    ("F", True),  # Flat: its rows carry N.V, for back faces, whatever is lit
    ("Z", True),
    ("1 2 3", True),
    ("c c", False),  # objects targeted again
]


@pytest.fixture(scope="module")
def lit_viewer(own_ctx):
    """The built-in scene with every light on, the camera close, in a renderer of its own (the pass
    counts and kept rows must be this test's alone)."""
    for renderer in corpus.own_renderer(own_ctx):
        scene = load_builtin_scene()
        viewer = RenderingViewer(scene, renderer, NoFrontend(), strict=True)
        viewer.start(StartOptions(), longest_texture_side=renderer.max_texture_side)
        viewer.press_sequence(f"{CLOSE} 0 1 2 3")
        yield viewer


def draw(ctx, renderer: Renderer, scene: Scene) -> np.ndarray:
    pixels = corpus.render_float(ctx, renderer, scene, SIZE)
    return np.round(pixels[..., :3] * 255).astype(np.uint8)


def forget_lighting(renderer: Renderer, scene: Scene) -> None:
    """Drops every object's GPU buffers, lit rows included: the next frame builds and lights afresh."""
    for obj in scene.objects + scene.cameras:
        renderer.release_object(obj)


def test_a_kept_lighting_pass_draws_what_a_fresh_one_does(own_ctx, lit_viewer) -> None:
    viewer, renderer, scene = lit_viewer, lit_viewer.renderer, lit_viewer.scene
    draw(own_ctx, renderer, scene)
    blank = []
    for keys, relights in STEPS:
        viewer.press_sequence(keys)
        before = renderer.lighting_passes
        kept = draw(own_ctx, renderer, scene)
        ran = renderer.lighting_passes - before
        assert (ran > 0) == relights, f"after {keys!r}: {ran} lighting passes"
        still = renderer.lighting_passes
        assert np.array_equal(draw(own_ctx, renderer, scene), kept), f"after {keys!r}: a second frame differs"
        assert renderer.lighting_passes == still, f"after {keys!r}: a still frame lit something"
        forget_lighting(renderer, scene)
        fresh = draw(own_ctx, renderer, scene)
        differs = np.abs(kept.astype(int) - fresh).max(axis=2) > 0
        assert not differs.any(), f"after {keys!r}: {int(differs.sum())} pixels differ from a fresh frame"
        if not (fresh != BACKGROUND).any():
            blank.append(keys)
    assert blank == ["C"], "only the view out of the x-wing's nose shows nothing but sky"


def test_a_changed_material_relights(own_ctx, lit_viewer) -> None:
    """Materials change only through scene files, never by a key; the pass must notice anyway."""
    renderer, scene = lit_viewer.renderer, lit_viewer.scene
    draw(own_ctx, renderer, scene)
    obj = scene.objects[scene.selected_object]
    obj.material = replace(obj.material, kd=tuple(1.0 - c for c in obj.material.kd))
    before = renderer.lighting_passes
    kept = draw(own_ctx, renderer, scene)
    assert renderer.lighting_passes > before
    forget_lighting(renderer, scene)
    assert np.array_equal(draw(own_ctx, renderer, scene), kept)


def test_without_specular_colours_gouraud_lights_nothing_again_for_a_camera_move(own_ctx, lit_viewer,
                                                                                 monkeypatch) -> None:
    """With every Ks zero, Gouraud's colours do not read V: a camera that moves lights nothing again,
    and its frame is a fresh renderer's. Flat's rows carry N.V, so Flat lights them again."""
    viewer, renderer, scene = lit_viewer, lit_viewer.renderer, lit_viewer.scene
    for obj in scene.objects + scene.cameras:  # put back after the test, whatever it finds
        monkeypatch.setattr(obj, "material", replace(obj.material, ks=(0.0, 0.0, 0.0)))
        monkeypatch.setattr(obj, "part_materials",
                            tuple(replace(material, ks=(0.0, 0.0, 0.0)) for material in obj.part_materials))
    for keys, relights in [("F", True), ("3 c t", True), ("Z", False), ("p", True), ("Z", False), ("p", True),
                           ("F", True), ("Z", True), ("3 c c", True)]:
        viewer.press_sequence(keys)
        before = renderer.lighting_passes
        kept = draw(own_ctx, renderer, scene)
        assert (renderer.lighting_passes > before) == relights, f"after {keys!r}"
        forget_lighting(renderer, scene)
        assert np.array_equal(draw(own_ctx, renderer, scene), kept), f"after {keys!r}"
